"""Levenberg-Marquardt against L-BFGS on the fits axojax users run (one run each).

1. The paper's fig. 7d-h global fit: seven filaments, 10 elements, five conditions
   p = 300, 150, 200, 400, 800 with the stated 51, 17, 22, 66, 245 Hz (2 % sigma);
   free ks, kl, cl, gamma shared; the same starts for both solvers (the caption's stated
   set, then a Sobol design of the bounds).
2. The bundled human sperm beat (``ax.datasets.human_sperm()``, where the data are
   installed): free p, ks, cl on the seven-filament model at the data's length, its
   frequency and in-plane psi_1 shape as targets.

3. Warm against cold starts of a limit-cycle waveform fit (issue 20): the orbit of the
   inferred fig. 12 parameters (seven filaments, 10 elements, 5:1 moment imbalance,
   harmonic balance with ``--harmonics``) observed as psi_0, psi_1 on 13 points and its
   frequency; free p, a0, cl from 3 % off. The default Levenberg-Marquardt starts each
   evaluation's orbit from the last accepted iterate's
   (``LevenbergMarquardt(warm_start=True)``); the cold one from the Hopf normal form.
   Prints, for each, LM steps, orbits solved, Newton steps per orbit (counted by a
   recording orbit solver), the wall time of the compiled fit and the compilation, the
   fitted values, then the warm/cold ratios measured in this one run.

Prints per solver: iterations per start, wall time (compilation included, then per
start), the best loss and, for fig. 7, the worst relative frequency error of the best
start. Timings are for comparison on one machine, not assertions.

    python benchmarks/bench_fit.py [--starts 8] [--only fig7|data|cycle] [--harmonics 4]
"""

import argparse
import time

import jax
import jax.numpy as jnp
import numpy as np

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax import paper
from axojax.fitting import ShapeTarget, Target
from axojax.inverse import LBFGS, Condition, LevenbergMarquardt, Problem, least_squares
from axojax.orbits.measures import cycle_measures

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


NEWTON_STEPS: list[int] = []


class CountingSolver(ax.orbits.HarmonicBalance):
    """HarmonicBalance recording the Newton steps of every orbit it solves."""

    def solve(self, model, params, kappa, start=None):
        cycle = super().solve(model, params, kappa, start)
        jax.debug.callback(lambda k: NEWTON_STEPS.append(int(k)), cycle.steps)
        return cycle


def cycle_fit(harmonics: int) -> None:
    inf = paper.INFERRED["fig12"]
    model, truth = inf.build()
    solver = CountingSolver(harmonics=harmonics, floquet=0, rtol=1e-10)
    s_um = np.linspace(0.0, 12.0, 13)
    m = cycle_measures(ax.limit_cycle(model, truth, inf.cubic, solver=solver), s_um)
    shape = ShapeTarget(s_um, np.asarray(m.psi1), 0.01, psi0=np.asarray(m.psi0), source="limit_cycle")
    freq = Target("frequency_hz", float(m.frequency_hz), 0.1, source="limit_cycle")
    free = ("p", "a0", "cl")
    start = truth.replace(**{k: 1.03 * float(getattr(truth, k)) for k in free})
    problem = Problem(model, [Condition(targets=[freq], shape=shape)], free, params=start, cubic=inf.cubic, orbit_solver=solver, shape_floor=0.0)
    z0 = problem.to_z(jnp.asarray(problem.u0))
    print(f"\n== limit-cycle waveform fit, fig. 12 orbit (seven filaments, {model.n_dof} dof, {harmonics} harmonics): free {', '.join(free)} from 3 % off")
    print(f"{'start':>6s}  {'LM steps':>8s}  {'orbits':>6s}  {'Newton/orbit':>12s}  {'fit s':>6s}  {'compile s':>9s}  fitted")
    rows = {}
    for label, lm in (("cold", LevenbergMarquardt(warm_start=False)), ("warm", LevenbergMarquardt())):
        run = lm.compile(problem)
        t = time.perf_counter()
        jax.block_until_ready(run(z0))
        first = time.perf_counter() - t
        NEWTON_STEPS.clear()
        t = time.perf_counter()
        z, loss, steps, _ = jax.block_until_ready(run(z0))
        wall = time.perf_counter() - t
        counts = list(NEWTON_STEPS)
        fitted = problem.values(np.asarray(problem.to_u(z)))
        rows[label] = (np.mean(counts), wall, fitted)
        vals = ", ".join(f"{k} {v / float(getattr(truth, k)) - 1:+.1e}" for k, v in fitted.items())
        print(f"{label:>6s}  {int(steps):8d}  {len(counts):6d}  {np.mean(counts):12.2f}  {wall:6.1f}  {first - wall:9.1f}  relative to the truth: {vals}")
    (nc, wc, fc), (nw, ww, fw) = rows["cold"], rows["warm"]
    agree = max(abs(fw[k] / fc[k] - 1) for k in fc)
    print(f"warm/cold: Newton steps per orbit {nw / nc:.2f}, fit wall time {ww / wc:.2f}; fitted values agree to {agree:.1e}")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument("--only", choices=("fig7", "data", "cycle"), default=None, help="run one of the three comparisons")
    ap.add_argument("--harmonics", type=int, default=4, help="harmonics of the limit-cycle fit")
    args = ap.parse_args()
    np.set_printoptions(precision=3)
    if args.only in (None, "fig7"):
        fig7(args.starts)
    if args.only in (None, "data"):
        human_sperm(args.starts)
    if args.only in (None, "cycle"):
        cycle_fit(args.harmonics)


if __name__ == "__main__":
    main()
