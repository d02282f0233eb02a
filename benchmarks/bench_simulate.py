"""Wall time of 20 beat periods of the seven-filament model, beside scipy's Radau.

At p = 1.04 p_c (its own mesh's Hopf point), from a 0.3 um bend, each ``ax.simulate``
call timed twice in one process: the first call includes compilation, the second is the
run alone.

1. the 10-element model (280 unknowns) without stiffening (``cubic = 0``): the linear beat;
2. the nonlinear beat with the default cubic stiffening on ``--nl-elements`` elements
   (default 10), to its limit cycle, whose frequency is printed beside the linear
   prediction (the Hopf frequency of the same mesh); then the same ODE, from the same
   state, over the same time, with the same tolerances (rtol 1e-6, atol 1e-9 L) by
   ``scipy.integrate.solve_ivp(method="Radau")`` with the exact Jacobian
   ``-C^{-1} (A + d f_nl/dq)`` (numpy, formed by the same rank-one sum), and the ratio of
   the two times. The end states are compared as a check that both solved the same
   problem.

3. the same limit cycle computed directly by ``ax.limit_cycle`` (``bench_orbit.py``).

    python benchmarks/bench_simulate.py [--periods 20] [--nl-elements 10] [--no-scipy] [--no-orbit]

The machine is shared in development: the load average is printed with the times.
"""

import argparse
import os
import sys
import time

import jax
import numpy as np
import scipy.integrate

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax.assembly import assemble
from axojax.dynamics.nonlinear import cubic_links
from axojax.dynamics.simulate import tip_deflection
from axojax.waveform.shapes import centreline


def setup(elements: int, periods: float):
    model = ax.models.seven(n_elements=elements)
    crit = ax.critical_force(model, ax.Params())
    params = ax.Params(p=1.04 * float(crit.p))
    t_end = periods / float(ax.dominant_mode(model, params).frequency_hz())
    return model, params, crit, t_end


def run(elements: int, cubic: float, periods: float) -> tuple:
    model, params, crit, t_end = setup(elements, periods)
    times = []
    for _ in range(2):
        t = time.perf_counter()
        sim = ax.simulate(model, params, t_end, cubic=cubic, perturbation_um=0.3)
        times.append(time.perf_counter() - t)
    solver = sim.meta["solver"]
    f_hopf = float(crit.frequency_hz())
    lc = ""
    if sim.limit_cycle:
        f_lc = sim.limit_cycle["frequency_hz"]
        lc = (
            f", limit cycle {f_lc:.2f} Hz ({100 * (f_lc / f_hopf - 1):+.1f} % from the Hopf "
            f"frequency {f_hopf:.2f} Hz), "
            f"tip amplitude {sim.limit_cycle['tip_amplitude_um']:.2f} um"
        )
    print(
        f"{elements} elements ({model.n_dof} dof), cubic {cubic:g}, {periods:g} periods "
        f"({t_end:.3f} s): state {sim.state}{lc}"
    )
    print(
        f"  axojax: first call (compile + run) {times[0]:7.2f} s; second call (run) "
        f"{times[1]:7.2f} s = {times[1] / periods:.3f} s per period; "
        f"{solver['steps']} accepted + {solver['rejected']} rejected steps "
        f"({times[1] / max(solver['steps'] + solver['rejected'], 1) * 1e3:.2f} ms each); "
        f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores"
    )
    return model, params, t_end, sim, times


def scipy_radau(model, params, cubic: float, t_end_s: float, perturbation_um: float = 0.3):
    """The same ODE by scipy's Radau with the exact Jacobian (numpy); (seconds, solution)."""
    units = ax.Units()
    s = assemble(model, params)
    C, A, b = (np.asarray(x) for x in (s.C, s.A, s.b))
    C_inv = np.linalg.inv(C)
    CA, Cb = C_inv @ A, C_inv @ b
    links = cubic_links(model, params, cubic)
    B, phi, weight = (np.asarray(x) for x in (links.B, links.phi, links.weight))
    nfd, m, n = model.n_fd, phi.shape[1], model.n_dof

    def f_nl(q):
        da = B @ (q.reshape(nfd, m) @ phi.T)
        return (B.T @ (weight * da**3) @ phi).ravel()

    def tangent(q):
        da = B @ (q.reshape(nfd, m) @ phi.T)
        Me = np.einsum("qr,eq,qs->ers", phi, 3.0 * weight * da**2, phi)
        return np.einsum("ei,ej,ers->irjs", B, B, Me).reshape(n, n)

    q0 = (perturbation_um / units.length_um) * tip_deflection(model)
    t = time.perf_counter()
    sol = scipy.integrate.solve_ivp(
        lambda _, q: Cb - CA @ q - C_inv @ f_nl(q),
        (0.0, t_end_s / units.tau_s),
        q0,
        method="Radau",
        jac=lambda _, q: -(CA + C_inv @ tangent(q)),
        rtol=1e-6,
        atol=1e-9,
    )
    return time.perf_counter() - t, sol


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--periods", type=float, default=20)
    ap.add_argument("--nl-elements", type=int, default=10)
    ap.add_argument("--no-scipy", action="store_true", help="skip the scipy Radau comparison")
    ap.add_argument(
        "--no-orbit", action="store_true", help="skip the direct limit-cycle computation"
    )
    args = ap.parse_args()
    print(f"device: {jax.devices()[0].device_kind}, {os.cpu_count()} cores, jax {jax.__version__}")
    run(10, 0.0, args.periods)
    cubic = ax.dynamics.DEFAULT_CUBIC
    model, params, t_end, sim, times = run(args.nl_elements, cubic, args.periods)
    if not args.no_scipy:
        seconds, sol = scipy_radau(model, params, cubic, t_end)
        tip_scipy = centreline(model, sol.y[:, -1], np.array([1.0]))[:, 0] * ax.Units().length_um
        print(
            f"  scipy Radau, exact Jacobian: {seconds:7.2f} s ({sol.message.rstrip('.')}; "
            f"{sol.t.size - 1} steps, {sol.njev} Jacobians, "
            f"{sol.nlu} LU factorisations); load average {os.getloadavg()[0]:.1f}"
        )
        print(
            f"  ratio scipy / axojax: {seconds / times[1]:.2f} (run), {seconds / times[0]:.2f} (with compilation); "
            f"tip at the end: axojax {np.round(sim.tip_um[-1], 5)} um, scipy {np.round(tip_scipy, 5)} um"
        )
    if not args.no_orbit:
        # The same limit cycle computed directly (benchmarks/bench_orbit.py), beside the
        # simulation that reaches it.
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from bench_orbit import orbit_times

        r = orbit_times(args.nl_elements, cubic=cubic)
        print(
            "one orbit directly (ax.limit_cycle, harmonic balance, Floquet multipliers "
            f"included): {r['after_compilation_s']:.2f} s "
            f"({r['with_compilation_s']:.1f} s with compilation), {r['newton_steps']} Newton "
            f"steps, {r['frequency_hz']:.3f} Hz "
            f"(simulation: {(sim.limit_cycle or {}).get('frequency_hz', float('nan')):.3f} "
            f"Hz), tip amplitude {r['tip_amplitude_um']:.3f} um; load average "
            f"{os.getloadavg()[0]:.1f}"
        )


if __name__ == "__main__":
    main()
