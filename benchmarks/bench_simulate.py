"""Wall time of 20 beat periods of the seven-filament model.

Two runs at p = 1.04 p_c (its own mesh's Hopf point), each one call, compilation included
and reported separately (a second, identical call):

1. the 10-element model (280 unknowns) without stiffening (``cubic = 0``): the linear beat;
2. the nonlinear beat with the default cubic stiffening on ``--nl-elements`` elements
   (default 10), from a 0.3 um bend to its limit cycle, whose frequency is printed beside
   the linear prediction (the Hopf frequency of the same mesh).

    python benchmarks/bench_simulate.py [--periods 20] [--nl-elements 10]
"""

import argparse
import os
import time

import axojax as ax  # first: it sets the XLA flags before jax starts

import jax


def run(elements: int, cubic: float, periods: float) -> None:
    model = ax.models.seven(n_elements=elements)
    crit = ax.critical_force(model, ax.Params())
    params = ax.Params(p=1.04 * float(crit.p))
    t_end = periods / float(ax.dominant_mode(model, params).frequency_hz())
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
        lc = (f", limit cycle {f_lc:.2f} Hz ({100 * (f_lc / f_hopf - 1):+.1f} % from the Hopf frequency {f_hopf:.2f} Hz), "
              f"tip amplitude {sim.limit_cycle['tip_amplitude_um']:.2f} um")
    print(f"{elements} elements ({model.n_dof} dof), cubic {cubic:g}, {periods:g} periods ({t_end:.3f} s): state {sim.state}{lc}")
    print(f"  first call (compile + run) {times[0]:8.2f} s; second call (run) {times[1]:8.2f} s = {times[1] / periods:.2f} s per period; "
          f"{solver['steps']} accepted steps ({times[1] / max(solver['steps'], 1) * 1e3:.1f} ms each), solver ok: {solver['ok']}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--periods", type=float, default=20)
    ap.add_argument("--nl-elements", type=int, default=10)
    args = ap.parse_args()
    print(f"device: {jax.devices()[0].device_kind}, {os.cpu_count()} cores, jax {jax.__version__}")
    run(10, 0.0, args.periods)
    run(args.nl_elements, ax.dynamics.DEFAULT_CUBIC, args.periods)


if __name__ == "__main__":
    main()
