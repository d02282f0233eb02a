"""Levenberg-Marquardt against L-BFGS on the fits axojax users run (one run each).

1. The paper's fig. 7d-h global fit: seven filaments, 10 elements, five conditions
   p = 300, 150, 200, 400, 800 with the stated 51, 17, 22, 66, 245 Hz (2 % sigma);
   free ks, kl, cl, gamma shared; the same starts for both solvers (the caption's stated
   set, then a Sobol design of the bounds).
2. The bundled human sperm beat (``ax.datasets.human_sperm()``, where the data are
   installed): free p, ks, cl on the seven-filament model at the data's length, its
   frequency and in-plane psi_1 shape as targets.

Prints per solver: iterations per start, wall time (compilation included, then per
start), the best loss and, for fig. 7, the worst relative frequency error of the best
start. Timings are for comparison on one machine, not assertions.

    python benchmarks/bench_fit.py [--starts 8] [--only fig7|data]
"""

import argparse
import time

import numpy as np

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax.fitting import Target
from axojax.inverse import LBFGS, Condition, LevenbergMarquardt, Problem, least_squares

FIG7 = {300: 51.0, 150: 17.0, 200: 22.0, 400: 66.0, 800: 245.0}


def compare(problem: Problem, starts: int, label: str, check=None) -> None:
    print(f"\n== {label}: {len(problem.names)} unknowns, {problem.n_residuals} residuals, {starts} starts")
    print(f"{'solver':>8s}  {'wall s':>8s}  {'iterations per start':>28s}  {'best loss':>11s}  note")
    rows = []
    for solver in (LevenbergMarquardt(), LBFGS(max_steps=200)):
        t = time.perf_counter()
        result = least_squares(problem, solver, starts=starts)
        wall = time.perf_counter() - t
        note = check(result) if check else ""
        rows.append((solver.name, wall, result))
        print(f"{solver.name:>8s}  {wall:8.1f}  {str(result.iterations):>28s}  {result.loss:11.4g}  {note}")
    (a, wa, ra), (b, wb, rb) = rows
    print(f"wall-time ratio {b}/{a}: {wb / wa:.2f}; iterations {b}/{a}: {sum(rb.iterations) / max(sum(ra.iterations), 1):.2f}; "
          f"best loss {ra.loss:.4g} ({a}) vs {rb.loss:.4g} ({b})")


def fig7(starts: int) -> None:
    model = ax.models.seven(n_elements=10)
    conds = [Condition({"p": float(p)}, [Target("frequency_hz", f, 0.02 * f)], label=f"p{p}") for p, f in FIG7.items()]
    problem = Problem(model, conds, ["ks", "kl", "cl", "gamma"], params=ax.Params())

    def check(result):
        errs = [abs(c["achieved"]["frequency_hz"] / FIG7[round(c["params"]["p"])] - 1) for c in result.conditions]
        vals = ", ".join(f"{k} {v:.3g}" for k, v in result.params.items())
        return f"max |f/f_paper - 1| {max(errs):.3f}; {vals}"

    compare(problem, starts, "fig. 7d-h global fit", check)


def human_sperm(starts: int) -> None:
    datasets = getattr(ax, "datasets", None)
    if datasets is None or not hasattr(datasets, "human_sperm"):
        print("\n== human sperm: skipped (ax.datasets.human_sperm() is not in this checkout)")
        return
    beat = datasets.human_sperm()
    targets, shape = beat.targets()
    units = ax.Units(length_um=float(beat.length_um))
    problem = Problem(ax.models.seven(n_elements=10), [Condition(targets=targets, shape=shape, label="sperm")], ["p", "ks", "cl"], params=ax.Params(), units=units)
    compare(problem, starts, f"human sperm ({beat.length_um:.3g} um, {beat.frequency_hz:.3g} Hz)", lambda r: f"chi2/dof {r.chi2_per_dof:.3g}; at bound {r.at_bound}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument("--only", choices=("fig7", "data"), default=None, help="run one of the two comparisons")
    args = ap.parse_args()
    np.set_printoptions(precision=3)
    if args.only != "data":
        fig7(args.starts)
    if args.only != "fig7":
        human_sperm(args.starts)


if __name__ == "__main__":
    main()
