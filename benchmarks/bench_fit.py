"""Levenberg-Marquardt against L-BFGS on the fits axojax users run (one run each).

1. The paper's fig. 7d-h global fit: seven filaments, 10 elements, five conditions
   p = 300, 150, 200, 400, 800 with the stated 51, 17, 22, 66, 245 Hz (2 % sigma);
   free ks, kl, cl, gamma shared; the same starts for both solvers (the caption's stated
   set, then a Sobol design of the bounds).
2. The bundled human sperm beat (``ax.datasets.human_sperm()``, where the data are
   installed): free p, ks, cl on the seven-filament model at the data's length, its
   frequency and in-plane psi_1 shape as targets.

3. Warm against cold starts of limit-cycle waveform fits (issue 20): the default
   Levenberg-Marquardt starts each evaluation's orbit from the last accepted iterate's
   (``LevenbergMarquardt(warm_start=True)``), the cold one from the Hopf normal form.
   (a) The two-filament fit of tests/inverse/test_whole_beat_targets.py (noise-free); (b) the
   orbit of the inferred fig. 12 parameters (seven filaments, 10 elements, 5:1 moment
   imbalance, ``--harmonics``) observed as psi_0, psi_1 on 13 points and its
   frequency, free p, a0, cl from 3 % off. Prints, for each, LM steps, orbits solved,
   Newton steps per orbit (counted by a recording orbit solver), the median wall time
   of the compiled fit (cold and warm run alternately) and the compilation, the fitted
   values, then the warm/cold ratios measured in this one run. Near the Hopf point the
   normal form is itself a start a few Newton steps away (4 at rtol 1e-10 for fig. 12),
   so the warm start saves least there.

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
from axojax.beats import ShapeTarget, Target
from axojax.inverse import LBFGS, Condition, LevenbergMarquardt, Problem, least_squares
from axojax.orbits.measures import cycle_measures

FIG7 = {300: 51.0, 150: 17.0, 200: 22.0, 400: 66.0, 800: 245.0}


def compare(problem: Problem, starts: int, label: str, check=None) -> None:
    print(
        f"\n== {label}: {len(problem.names)} unknowns, {problem.n_residuals} residuals, {starts} starts"
    )
    print(
        f"{'solver':>8s}  {'wall s':>8s}  {'iterations per start':>28s}  {'best loss':>11s}  note"
    )
    rows = []
    for solver in (LevenbergMarquardt(), LBFGS(max_steps=200)):
        t = time.perf_counter()
        result = least_squares(problem, solver, starts=starts)
        wall = time.perf_counter() - t
        note = check(result) if check else ""
        rows.append((solver.name, wall, result))
        print(
            f"{solver.name:>8s}  {wall:8.1f}  {str(result.iterations):>28s}  {result.loss:11.4g}  {note}"
        )
    (a, wa, ra), (b, wb, rb) = rows
    print(
        f"wall-time ratio {b}/{a}: {wb / wa:.2f}; iterations {b}/{a}: "
        f"{sum(rb.iterations) / max(sum(ra.iterations), 1):.2f}; "
        f"best loss {ra.loss:.4g} ({a}) vs {rb.loss:.4g} ({b})"
    )


def fig7(starts: int) -> None:
    model = ax.models.seven(n_elements=10)
    conds = [
        Condition({"p": float(p)}, [Target("frequency_hz", f, 0.02 * f)], label=f"p{p}")
        for p, f in FIG7.items()
    ]
    problem = Problem(model, conds, ["ks", "kl", "cl", "gamma"], params=ax.Params())

    def check(result):
        errs = [
            abs(c["achieved"]["frequency_hz"] / FIG7[round(c["params"]["p"])] - 1)
            for c in result.conditions
        ]
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
    problem = Problem(
        ax.models.seven(n_elements=10),
        [Condition(targets=targets, shape=shape, label="sperm")],
        ["p", "ks", "cl"],
        params=ax.Params(),
        units=units,
    )
    compare(
        problem,
        starts,
        f"human sperm ({beat.length_um:.3g} um, {beat.frequency_hz:.3g} Hz)",
        lambda r: f"chi2/dof {r.chi2_per_dof:.3g}; at bound {r.at_bound}",
    )


NEWTON_STEPS: list[int] = []


def counting_solver(**options) -> ax.orbits.Recording:
    """HarmonicBalance(**options) recording the Newton steps of every orbit it solves."""
    return ax.orbits.Recording(
        ax.orbits.HarmonicBalance(**options), lambda k: NEWTON_STEPS.append(int(k))
    )


def _warm_cold(problem: Problem, truth: ax.Params, label: str, repeats: int = 3) -> None:
    """Cold and warm Levenberg-Marquardt on ``problem`` from its start: compiled once,
    then run ``repeats`` times alternately (the median wall time; the Newton steps of
    the first run)."""
    z0 = problem.to_z(jnp.asarray(problem.u0))
    print(f"\n== {label}")
    print(
        f"{'start':>6s}  {'LM steps':>8s}  {'orbits':>6s}  {'Newton/orbit':>12s}  "
        f"{'fit s':>6s}  {'compile s':>9s}  fitted, relative to the truth"
    )
    runs, first = {}, {}
    for name, lm in (
        ("cold", LevenbergMarquardt(warm_start=False)),
        ("warm", LevenbergMarquardt()),
    ):
        runs[name] = lm.compile(problem)
        t = time.perf_counter()
        jax.block_until_ready(runs[name](z0))
        first[name] = time.perf_counter() - t
    walls, rows = {k: [] for k in runs}, {}
    for rep in range(repeats):
        for name, run in runs.items():
            NEWTON_STEPS.clear()
            t = time.perf_counter()
            out = jax.block_until_ready(run(z0))
            walls[name].append(time.perf_counter() - t)
            if rep == 0:
                rows[name] = (out, list(NEWTON_STEPS))
    for name, ((z, loss, steps, _, _), counts) in rows.items():
        wall = float(np.median(walls[name]))
        fitted = problem.values(np.asarray(problem.to_u(z)))
        vals = ", ".join(f"{k} {v / float(getattr(truth, k)) - 1:+.1e}" for k, v in fitted.items())
        print(
            f"{name:>6s}  {int(steps):8d}  {len(counts):6d}  {np.mean(counts):12.2f}  "
            f"{wall:6.2f}  {first[name] - wall:9.1f}  {vals}"
        )
        rows[name] = (np.mean(counts), wall, fitted)
    (nc, wc, fc), (nw, ww, fw) = rows["cold"], rows["warm"]
    agree = max(abs(fw[k] / fc[k] - 1) for k in fc)
    print(
        f"warm/cold: Newton steps per orbit {nw / nc:.2f}, fit wall time {ww / wc:.2f} (median "
        f"of {repeats}); fitted values agree to {agree:.1e}"
    )


def cycle_fit(harmonics: int) -> None:
    # 1. Two filaments, 4 elements (the fit of tests/inverse/test_whole_beat_targets.py, noise-free).
    model = ax.models.two(n_elements=4)
    base = ax.Params(p=160.0)
    truth = base.replace(p=1.06 * float(ax.critical_force(model, base).p), a0=0.3 / 12)
    solver = counting_solver(harmonics=4, floquet=0, rtol=1e-11)
    s_um = np.linspace(0.0, 12.0, 21)
    m = cycle_measures(ax.limit_cycle(model, truth, 6.0, solver=solver), s_um)
    shape = ShapeTarget(
        s_um, np.asarray(m.psi1), 0.002, psi0=np.asarray(m.psi0), source="limit_cycle"
    )
    freq = Target("frequency_hz", float(m.frequency_hz), 0.01, source="limit_cycle")
    start = truth.replace(p=float(truth.p) * 1.01, a0=float(truth.a0) * 1.15)
    problem = Problem(
        model,
        [Condition(targets=[freq], shape=shape)],
        ["p", "a0"],
        params=start,
        cubic=6.0,
        orbit_solver=solver,
        shape_floor=0.0,
    )
    _warm_cold(
        problem,
        truth,
        "limit-cycle waveform fit, two filaments (4 elements, 4 harmonics, 1.06 p_c): free p, a0 from 1 %, 15 % off",
    )
    # 2. The inferred fig. 12 orbit: seven filaments, close to its Hopf point.
    inf = paper.INFERRED["fig12"]
    model, truth = inf.build()
    solver = counting_solver(harmonics=harmonics, floquet=0, rtol=1e-10)
    s_um = np.linspace(0.0, 12.0, 13)
    m = cycle_measures(ax.limit_cycle(model, truth, inf.cubic, solver=solver), s_um)
    shape = ShapeTarget(
        s_um, np.asarray(m.psi1), 0.01, psi0=np.asarray(m.psi0), source="limit_cycle"
    )
    freq = Target("frequency_hz", float(m.frequency_hz), 0.1, source="limit_cycle")
    free = ("p", "a0", "cl")
    start = truth.replace(**{k: 1.03 * float(getattr(truth, k)) for k in free})
    problem = Problem(
        model,
        [Condition(targets=[freq], shape=shape)],
        free,
        params=start,
        cubic=inf.cubic,
        orbit_solver=solver,
        shape_floor=0.0,
    )
    _warm_cold(
        problem,
        truth,
        f"limit-cycle waveform fit, fig. 12 orbit (seven filaments, {model.n_dof} dof, "
        f"{harmonics} harmonics): free p, a0, cl from 3 % off",
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument(
        "--only",
        choices=("fig7", "data", "cycle"),
        default=None,
        help="run one of the three comparisons",
    )
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
