"""Wall time of 20 beat periods of the seven-filament, 10-element model (280 unknowns).

Runs ``ax.simulate`` at p = 1.04 p_c with the default cubic stiffening, starting near the
limit cycle, and prints compile time (first call minus second) and run time per period,
measured in one run.

    python benchmarks/bench_simulate.py [--periods 20] [--elements 10]
"""

import argparse
import os
import time

import axojax as ax  # first: it sets the XLA flags before jax starts

import jax


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--periods", type=float, default=20)
    ap.add_argument("--elements", type=int, default=10)
    args = ap.parse_args()
    model = ax.models.seven(n_elements=args.elements)
    crit = ax.critical_force(model, ax.Params())
    params = ax.Params(p=1.04 * float(crit.p))
    t_end = args.periods / float(ax.dominant_mode(model, params).frequency_hz())
    times, sims = [], []
    for _ in range(2):
        t = time.perf_counter()
        sims.append(ax.simulate(model, params, t_end, perturbation_um=3.0))
        times.append(time.perf_counter() - t)
    sim = sims[-1]
    steps = sim.meta["solver"]["steps"]
    print(f"device: {jax.devices()[0].device_kind}, {os.cpu_count()} cores; seven model, {args.elements} elements ({model.n_dof} dof)")
    print(f"p = 1.04 p_c = {float(params.p):.2f}, cubic {sim.meta['cubic']:g}, t_end {t_end:.3f} s ({args.periods:g} linear periods), state {sim.state}")
    if sim.limit_cycle:
        print(f"limit cycle {sim.limit_cycle['frequency_hz']:.3f} Hz, tip amplitude {sim.limit_cycle['tip_amplitude_um']:.3f} um")
    print(f"first call (compile + run): {times[0]:8.2f} s")
    print(f"second call (run only):     {times[1]:8.2f} s   {times[1] / args.periods:.3f} s per period, {steps} accepted steps, {times[1] / steps * 1e3:.2f} ms per step")


if __name__ == "__main__":
    main()
