"""Cost of a whole-beat fit's value and gradient through a regulated orbit against the
orbit alone (issue 47's acceptance: "at most 3x the cost of the orbit alone").

The row of tests/orbits/test_orbit_motors_gradient.py: two-filament sliding control (chi'' < 0)
on a clamped base, 10 % past its Hopf point (chi scaled by 1.1), motor kinetics
(tau_m = 5 ms), saturating motors (40 pN/um), cubic links 10, harmonic balance with the
solver a fit uses (``HarmonicBalance(floquet=0)``), started from the Hopf normal form
every call, and again warm-started from a fit's previous iterate (``WarmStart``: the orbit
at chi'' 1 % larger), where Newton takes fewer steps and the gradient's fixed cost (one
more factorisation and a transposed solve) weighs more. The loss is that test's: the
squared relative misfits of the orbit's frequency and dynamic amplitude against 170 Hz and
0.12 rad, differentiated in (tau_m, f_sat, chi', chi'', kappa) by reverse mode (the
implicit function theorem's transposed solve).

Three compiled functions of the same parameters, each called ``--repeats`` times after a
first (compiling) call, their median wall times printed in one run on one machine:

- the orbit alone: ``solver.solve`` returning the :class:`LimitCycle` (coefficients,
  frequency, tip amplitude);
- the loss's value: the orbit plus its measures;
- ``jax.value_and_grad`` of the loss;

and the ratio value-and-gradient / orbit alone, for each start.

    python benchmarks/bench_orbit_gradient.py [--elements 8] [--harmonics 10] [--repeats 9]
"""

import argparse
import os
import statistics
import time

import jax
import jax.numpy as jnp
import numpy as np
import scipy.linalg as sl

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax.orbits import HarmonicBalance, Motors, WarmStart, cycle_measures

TARGET_HZ = 170.0
TARGET_RAD = 0.12


def sliding_row(model, past: float = 0.1) -> ax.Params:
    """Sliding control at the Hopf point nearest chi = -1.3e5 - 1.8e5 i (a0 = 0.2 / 12,
    omega0 = 1000: tests/regulation/test_motor_kinetics.py's row), chi then scaled by 1 + ``past``.
    The Hopf point: i omega0 an eigenvalue of the pencil, A linear in chi (scipy)."""
    params = ax.Params(p=0.0, a0=0.2 / 12, omega0=1000.0)
    s0 = ax.assemble(model, params)
    s1 = ax.assemble(model, params.replace(chi_re=1.0))
    k0 = np.asarray(s0.A) + 1j * 1000.0 * np.asarray(s0.C)
    g = sl.eig(k0, -(np.asarray(s1.A) - np.asarray(s0.A)), right=False)
    g = g[np.isfinite(g)]
    chi = (1.0 + past) * g[np.argmin(np.abs(g - (-1.3e5 - 1.8e5j)))]
    return params.replace(chi_re=float(chi.real), chi_im=float(chi.imag))


def median_time(fn, x, repeats: int) -> tuple[float, float]:
    """(first call's seconds, with compilation; median of ``repeats`` further calls)."""
    t = time.perf_counter()
    jax.block_until_ready(fn(x))
    first = time.perf_counter() - t
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn(x))
        times.append(time.perf_counter() - t)
    return first, statistics.median(times)


def gradient_times(elements: int = 8, harmonics: int = 10, repeats: int = 9) -> dict:
    """Median seconds of the orbit alone, the loss and its value and gradient."""
    units = ax.Units()
    model = ax.models.two(n_elements=elements)
    params = sliding_row(model)
    solver = HarmonicBalance(harmonics=harmonics, floquet=0)
    x0 = jnp.asarray(
        [
            5e-3 / units.tau_s,
            float(units.p_from_pn_per_um(40.0)),
            float(params.chi_re),
            float(params.chi_im),
            10.0,
        ]
    )

    def orbit(x, start=None):
        tau_m, f_sat, chi_re, chi_im, kappa = x
        return WarmStart(solver).solve(
            model,
            params.replace(chi_re=chi_re, chi_im=chi_im),
            kappa,
            start,
            Motors(tau_m=tau_m, f_sat=f_sat),
        )

    def loss(x, start=None):
        m = cycle_measures(orbit(x, start), None, units)
        return ((m.frequency_hz - TARGET_HZ) / TARGET_HZ) ** 2 + (
            (m.dynamic_amplitude_rad - TARGET_RAD) / TARGET_RAD
        ) ** 2

    orbit_jit = jax.jit(orbit)
    # a fit's previous iterate: the orbit at chi'' 1 % larger
    start = orbit_jit(x0.at[3].multiply(1.01))
    out = {}
    for start_name, s in (("cold", None), ("warm", start)):
        for name, fn in (
            ("orbit", orbit_jit),
            ("loss", jax.jit(loss)),
            ("value_and_grad", jax.jit(jax.value_and_grad(loss))),
        ):
            first, median = median_time(lambda x: fn(x, s), x0, repeats)
            out[f"{start_name}_{name}_first_s"], out[f"{start_name}_{name}_s"] = first, median
        cycle = orbit_jit(x0, s)
        assert bool(cycle.converged), "the benchmark's orbit did not converge"
        out[f"{start_name}_newton_steps"] = int(cycle.steps)
        out[f"{start_name}_ratio"] = (
            out[f"{start_name}_value_and_grad_s"] / out[f"{start_name}_orbit_s"]
        )
    out["n_unknowns"] = 2 * model.n_unknowns
    out["frequency_hz"] = float(cycle.frequency_hz(units))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", type=int, default=8)
    ap.add_argument("--harmonics", type=int, default=10)
    ap.add_argument("--repeats", type=int, default=9)
    args = ap.parse_args()
    r = gradient_times(args.elements, args.harmonics, args.repeats)
    print(
        f"regulated orbit, two filaments, {args.elements} elements ({r['n_unknowns']} unknowns "
        f"with motor kinetics), {args.harmonics} harmonics, {r['frequency_hz']:.2f} Hz; medians "
        f"of {args.repeats} compiled calls ({jax.devices()[0].platform}, load average "
        f"{os.getloadavg()[0]:.1f}):"
    )
    for start, how in (
        ("cold", "from the Hopf normal form"),
        ("warm", "from a fit's previous iterate (WarmStart, the orbit at chi'' 1 % larger)"),
    ):
        print(f" {how}, {r[f'{start}_newton_steps']} Newton steps:")
        for name, label in (
            ("orbit", "orbit alone"),
            ("loss", "loss value (orbit + measures)"),
            ("value_and_grad", "value_and_grad (5 parameters)"),
        ):
            print(
                f"  {label:31s} {r[f'{start}_{name}_s']:.3f} s   "
                f"(first call, with compilation: {r[f'{start}_{name}_first_s']:.1f} s)"
            )
        print(f"  value_and_grad / orbit alone: {r[f'{start}_ratio']:.2f} (issue 47 asks for <= 3)")


if __name__ == "__main__":
    main()
