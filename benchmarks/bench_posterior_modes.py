"""Posteriors with several modes and cliffs (issue 48): ``axojax.inverse.ModeMixture``
(default) or adaptive tempered SMC (``--sampler smc``) against a grid quadrature of the
same 2-parameter posterior (``--grid 0``: no quadrature).

The case: the seven-filament model (``ax.models.seven``), truth p 300, ks 1e5,
kl = ks / 1000, cl 0.005; targets its dominant mode's frequency (sigma 2 %) and
wavelength (sigma 5 %), both computed here from the truth with the current code; free p
and ks with the default bounds and the default prior (uniform in log p, log ks).

Quadrature: the log density -1/2 |residuals|^2 (uniform prior in u = (log p, log ks))
on a coarse n x n grid of the whole prior box, vmapped; its modes are the connected
regions within ``DROP`` of the maximum (scipy.ndimage.label), joined by boxes around
the least-squares fit's distinct optima (``FitResult.optima``, 16 starts) so that a mode
narrower than a coarse cell is not lost; each region is integrated again on a fine n x n
grid of its box. The draws are assigned to the region whose fine grid holds them above
the threshold. Printed: each mode's mass by quadrature and by the draws, R-hat, bulk ESS,
every log-density evaluation and evaluations per effective draw, wall time, the 90 %
intervals and whether they hold the truth; for ModeMixture also its modes and the
switch lines it met. One run, no assertions (timings are the machine's):
``python benchmarks/bench_posterior_modes.py --elements 10 --grid 0``.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import scipy.ndimage
import scipy.special

import axojax as ax
from axojax.beats import Target
from axojax.inverse import SMC, ModeMixture, build_problem, least_squares, posterior

TRUTH = {"p": 300.0, "ks": 1e5, "cl": 0.005}
KL_RATIO = 1000.0
DROP = 25.0
"""A mode is a connected region of the grid within this of the maximum log density."""


def case(elements: int, truth_values: dict):
    """The problem of issue 48's case on ``elements`` elements (the truth ``truth_values``:
    p, ks and optionally cl; the others axojax's defaults) and its targets (Hz, um)."""
    model = ax.models.seven(n_elements=elements)
    truth = ax.Params().with_values(truth_values, KL_RATIO)
    mode = ax.dominant_mode(model, truth)
    f, lam = float(mode.frequency_hz()), float(mode.wavelength_um())
    targets = [Target("frequency_hz", f, 0.02 * f), Target("wavelength_um", lam, 0.05 * lam)]
    start = truth.replace(p=250.0, ks=3e5)
    problem = build_problem(model, start, targets, ["p", "ks"], kl_ratio=KL_RATIO)
    return problem, (f, lam)


def log_density_grid(problem, lp, lk):
    """-1/2 |residuals|^2 on the grid lp x lk of u (uniform prior), (len(lp), len(lk))."""
    P, K = np.meshgrid(lp, lk, indexing="ij")
    u = jnp.asarray(np.stack([P.ravel(), K.ravel()], 1))
    r = jax.jit(lambda u: jax.lax.map(problem.residuals, u, batch_size=256))(u)
    logp = -0.5 * np.sum(np.asarray(r) ** 2, axis=1).reshape(P.shape)
    return np.where(np.isfinite(logp), logp, -np.inf)


def quadrature(problem, n: int, optima):
    """The modes: per region, its fine grid (lp, lk, logp), the log of its mass (the sum of
    exp(logp) times the cell area) and its best point; masses normalised over the regions."""
    lo, hi = np.asarray(problem.lower), np.asarray(problem.upper)
    lp, lk = np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n)
    coarse = log_density_grid(problem, lp, lk)
    top = max(np.max(coarse), *(logp for _, logp in optima))
    labels, count = scipy.ndimage.label(coarse > top - DROP)
    cell = np.array([lp[1] - lp[0], lk[1] - lk[0]])
    boxes = []
    for c in range(1, count + 1):
        i, j = np.nonzero(labels == c)
        boxes.append(
            (
                np.array([lp[i.min()], lk[j.min()]]) - 2 * cell,
                np.array([lp[i.max()], lk[j.max()]]) + 2 * cell,
            )
        )
    for u, _ in optima:  # a narrow mode between the coarse points
        if not any(np.all((a <= u) & (u <= b)) for a, b in boxes):
            boxes.append((u - 2 * cell, u + 2 * cell))
    modes = []
    for a, b in boxes:
        a, b = np.maximum(a, lo), np.minimum(b, hi)
        fp, fk = np.linspace(a[0], b[0], n), np.linspace(a[1], b[1], n)
        logp = log_density_grid(problem, fp, fk)
        area = (fp[1] - fp[0]) * (fk[1] - fk[0])
        i, j = np.unravel_index(np.argmax(logp), logp.shape)
        modes.append(
            {
                "grid": (fp, fk, logp),
                "log_mass": scipy.special.logsumexp(logp) + math.log(area),
                "best": (math.exp(fp[i]), math.exp(fk[j]), float(logp[i, j])),
            }
        )
    total = scipy.special.logsumexp([m["log_mass"] for m in modes])
    for m in modes:
        m["mass"] = math.exp(m["log_mass"] - total)
    return modes


def assign(modes, u, top: float) -> np.ndarray:
    """Each draw's mode (index), or -1 where none of the fine grids holds it above the
    threshold."""
    out = np.full(len(u), -1)
    for index, m in enumerate(modes):
        fp, fk, logp = m["grid"]
        inside = (u[:, 0] >= fp[0]) & (u[:, 0] <= fp[-1]) & (u[:, 1] >= fk[0]) & (u[:, 1] <= fk[-1])
        i = np.clip(np.rint((u[:, 0] - fp[0]) / (fp[1] - fp[0])).astype(int), 0, len(fp) - 1)
        j = np.clip(np.rint((u[:, 1] - fk[0]) / (fk[1] - fk[0])).astype(int), 0, len(fk) - 1)
        hit = inside & (logp[i, j] > top - DROP - 10) & (out < 0)
        out[hit] = index
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--elements", type=int, default=10, help="elements of the model (10)")
    parser.add_argument("--sampler", choices=("modes", "smc"), default="modes")
    parser.add_argument(
        "--particles", type=int, default=None, help="particles (per run, or per stage)"
    )
    parser.add_argument(
        "--draws", type=int, default=1000, help="ModeMixture: draws per chain (1000)"
    )
    parser.add_argument("--runs", type=int, default=4, help="independent SMC runs, or chains")
    parser.add_argument("--mutation-steps", type=int, default=8)
    parser.add_argument("--grid", type=int, default=160, help="points per side of each grid")
    parser.add_argument("--starts", type=int, default=16, help="least-squares starts")
    parser.add_argument("--ks", type=float, default=TRUTH["ks"], help="the truth's ks (1e5)")
    parser.add_argument(
        "--cl", type=float, default=TRUTH["cl"], help="the truth's cl (0.005; <= 0: the default)"
    )
    args = parser.parse_args()
    truth = {"p": TRUTH["p"], "ks": args.ks, **({"cl": args.cl} if args.cl > 0 else {})}

    problem, (f, lam) = case(args.elements, truth)
    print(f"truth {truth}")
    print(
        f"case: seven-filament, {args.elements} elements; targets {f:.4f} Hz (2 %), {lam:.4f} um (5 %)"
    )
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = least_squares(problem, starts=args.starts)
    ends = [np.log([v["p"], v["ks"]]) for v, loss in fit.optima if math.isfinite(loss)]
    optima = [(u, -0.5 * float(jnp.sum(problem.residuals(jnp.asarray(u)) ** 2))) for u in ends]
    distinct = {(round(u[0], 2), round(u[1], 1)): logp for u, logp in optima}
    print(f"fit: {time.perf_counter() - t0:.1f} s; distinct optima: log density -1/2 |r|^2")
    for key, logp in sorted(distinct.items(), key=lambda x: -x[1]):
        print(f"  p {math.exp(key[0]):9.4g}  ks {math.exp(key[1]):9.4g}  {logp:.3g}")

    modes, top = [], 0.0
    if args.grid > 0:
        t0 = time.perf_counter()
        modes = quadrature(problem, args.grid, optima)
        top = max(m["best"][2] for m in modes)
        print(f"quadrature: {len(modes)} region(s), {time.perf_counter() - t0:.1f} s")

    t0 = time.perf_counter()
    if args.sampler == "smc":
        sampler = SMC(particles=args.particles or 1000, mutation_steps=args.mutation_steps)
        kwargs = {}
    else:
        sampler = ModeMixture() if args.particles is None else ModeMixture(particles=args.particles)
        kwargs = {"draws": args.draws, "init": fit}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        post = posterior(problem, chains=args.runs, seed=0, sampler=sampler, **kwargs)
    wall = time.perf_counter() - t0
    for w in caught:
        print(f"  warning: {w.message}")
    if modes:
        u = post.u.reshape(-1, 2)
        where = assign(modes, u, top)
        print(
            "modes: p, ks at the best grid point, log density there; mass by quadrature / by the draws (per chain)"
        )
        for index, m in enumerate(modes):
            p, ks, best = m["best"]
            runs = [np.mean(assign(modes, post.u[r], top) == index) for r in range(post.chains)]
            print(
                f"  {index}: p {p:9.4g} ks {ks:9.4g} logp {best:8.3f}  mass {m['mass']:.4f} / "
                f"{np.mean(where == index):.4f} ({', '.join(f'{x:.3f}' for x in runs)})"
            )
        print(f"  outside every region: {np.mean(where < 0):.4f} of the draws")
    ess = min(post.ess.values())
    if args.sampler == "smc":
        print(
            f"SMC: {post.chains} runs x {post.draws} particles, {args.mutation_steps} mutation steps, "
            f"stages {post.tempering_stages}, acceptance {post.acceptance:.3f}, log evidence "
            f"{', '.join(f'{x:.3f}' for x in post.log_evidence)}"
        )
    else:
        print(
            f"ModeMixture: {post.chains} chains x {post.draws} draws, {post.tempering_stages[0]} stages of "
            f"{sampler.particles} points, acceptance {post.acceptance:.3f}; adaptation "
            f"{post.seconds_warmup:.1f} s, chains {post.seconds_sampling:.1f} s"
        )
        for m in post.modes:
            print(
                f"  mode {m['centre']}: mass {m['mass']:.4f} (importance {m['mass_importance']:.4f})"
            )
        for line in post.switches:
            print(
                f"  switch line {line['range']}: jump {line['jump']:.3g} sigma, {len(line['points'])} points"
            )
    print(
        f"  R-hat p {post.rhat['p']:.4f} ks {post.rhat['ks']:.4f}; ESS p {post.ess['p']:.0f} "
        f"ks {post.ess['ks']:.0f} (tail {min(post.ess_tail.values()):.0f}); evaluations {post.gradients} "
        f"({post.gradients / ess:.1f} per effective draw); wall {wall:.1f} s + fit (compile "
        f"{post.seconds_compile:.1f} s, {1e3 * post.seconds_per_gradient:.2f} ms per evaluation)"
    )
    for name, value in (("p", truth["p"]), ("ks", truth["ks"])):
        inside = post.q05[name] <= value <= post.q95[name]
        print(
            f"  {name}: 5/50/95 % {post.q05[name]:.4g} / {post.q50[name]:.4g} / "
            f"{post.q95[name]:.4g}; truth {value:g} inside: {inside}"
        )


if __name__ == "__main__":
    main()
