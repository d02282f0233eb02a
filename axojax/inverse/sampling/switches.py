"""Where the dominant eigenmode switches (a cliff of the likelihood): :func:`find_switches`
locates the switch lines among the points a sampler evaluated.

A switch is a discontinuity of the residuals: across it another eigenmode is the
dominant one and the predicted frequency (or wavelength) jumps. Candidates are pairs of
near neighbours (in coordinates whitened by the posterior's covariance) among the
evaluated points within :data:`REACH` of the best log density, whose residuals differ by
more than :data:`JUMP` (in sigmas). Each candidate segment is bisected
:data:`LEVELS` times, keeping the half whose ends differ most: a discontinuity keeps its
jump while the segment shrinks 2^LEVELS-fold, a smooth but steep change loses it (halved
at every level). Confirmed points are grouped into lines (single linkage within
:data:`LINE_GAP` whitened units); each line is reported with the range of every
parameter along it, its points, and the jump.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

REACH = 25.0
"""Only points whose log density is within this of the best are searched."""
JUMP = 5.0
"""A jump of the residuals (largest component, in sigmas) that a switch must keep."""
LEVELS = 12
"""Bisection levels per candidate (the segment shrinks 4096-fold)."""
MAX_CANDIDATES = 32
"""Candidate segments bisected, the steepest first."""
NEIGHBOURS = 3
"""Nearest neighbours of each point paired with it."""
MAX_POINTS = 3000
"""Points searched (the highest log densities)."""
LINE_GAP = 2.0
"""Confirmed switch points closer than this (whitened units) are one line."""


def _bisect(_, target, a: Float[Array, "c k"], b: Float[Array, "c k"]):
    """Bisect each segment (a_i, b_i) in z :data:`LEVELS` times towards its largest jump
    of the residuals; the final ends and their residuals."""
    problem = target.problem

    def r(z):
        return problem.residuals(problem.to_u(z))

    def one(a, b):
        ra, rb = r(a), r(b)

        def level(_, carry):
            a, b, ra, rb = carry
            m = 0.5 * (a + b)
            rm = r(m)
            left = jnp.max(jnp.abs(rm - ra)) >= jnp.max(jnp.abs(rm - rb))  # the jump is in (a, m)
            return (
                jnp.where(left, a, m),
                jnp.where(left, m, b),
                jnp.where(left, ra, rm),
                jnp.where(left, rm, rb),
            )

        return jax.lax.fori_loop(0, LEVELS, level, (a, b, ra, rb))

    return jax.vmap(one)(a, b)


def _candidates(w: np.ndarray, r: np.ndarray) -> list[tuple[int, int, float]]:
    """Pairs (i, j, jump) of near neighbours whose residuals jump by over :data:`JUMP`,
    steepest (jump over distance) first, at most :data:`MAX_CANDIDATES`."""
    n = len(w)
    pairs = {}
    for start in range(0, n, 500):
        d2 = np.sum((w[start : start + 500, None, :] - w[None, :, :]) ** 2, axis=-1)
        d2[np.arange(d2.shape[0]), start + np.arange(d2.shape[0])] = np.inf
        near = np.argsort(d2, axis=1)[:, :NEIGHBOURS]
        for row, js in enumerate(near):
            i = start + row
            for j in js:
                key = (min(i, int(j)), max(i, int(j)))
                if key in pairs:
                    continue
                jump = float(np.max(np.abs(r[i] - r[j])))
                if np.isfinite(jump) and jump > JUMP:
                    pairs[key] = (jump, jump / max(np.sqrt(d2[row, j]), 1e-300))
    ranked = sorted(pairs.items(), key=lambda kv: -kv[1][1])[:MAX_CANDIDATES]
    return [(i, j, v[0]) for (i, j), v in ranked]


def _lines(points_w: np.ndarray) -> np.ndarray:
    """Line index of each confirmed point (single linkage within :data:`LINE_GAP`)."""
    n = len(points_w)
    label = -np.ones(n, dtype=int)
    count = 0
    for i in range(n):
        if label[i] >= 0:
            continue
        label[i] = count
        stack = [i]
        while stack:
            j = stack.pop()
            near = np.nonzero(
                (label < 0) & (np.linalg.norm(points_w - points_w[j], axis=1) < LINE_GAP)
            )[0]
            label[near] = count
            stack.extend(near.tolist())
        count += 1
    return label


def find_switches(problem, target, seen, centre, chol, values_of, call) -> tuple[list[dict], int]:
    """The switch lines among the evaluated points ``seen`` = (z (n, k), residuals (n, m),
    log density (n,)), whitened by ``centre`` (k,) and ``chol`` (k, k) in z; ``values_of``
    maps z to {name: value}; ``call`` runs compiled pieces (the sampler's clock).

    Returns (lines, evaluations): per line ``points`` (the switch points as parameter
    values), ``range`` ({name: [min, max]} over them) and ``jump`` (the largest residual
    jump across it, in sigmas); and the residual evaluations spent bisecting."""
    z, r, ll = seen
    finite = np.isfinite(ll)
    if not np.any(finite):
        return [], 0
    keep = np.nonzero(finite & (ll >= np.max(ll[finite]) - REACH))[0]
    keep = keep[np.argsort(-ll[keep])][:MAX_POINTS]
    w = np.linalg.solve(chol, (z[keep] - centre).T).T
    cands = _candidates(w, r[keep])
    if not cands:
        return [], 0
    a = jnp.asarray(z[keep][[c[0] for c in cands]])
    b = jnp.asarray(z[keep][[c[1] for c in cands]])
    a_end, b_end, ra, rb = (np.asarray(x) for x in call(_bisect, None, target, a, b))
    evaluations = len(cands) * (LEVELS + 2)
    final = np.max(np.abs(ra - rb), axis=1)
    confirmed = [i for i, c in enumerate(cands) if final[i] >= max(JUMP, 0.5 * c[2])]
    if not confirmed:
        return [], evaluations
    mid = 0.5 * (a_end[confirmed] + b_end[confirmed])
    labels = _lines(np.linalg.solve(chol, (mid - centre).T).T)
    lines = []
    for line in range(int(labels.max()) + 1):
        at = np.nonzero(labels == line)[0]
        pts = [values_of(mid[i]) for i in at]
        names = list(pts[0])
        lines.append(
            {
                "points": pts,
                "range": {n: [min(p[n] for p in pts), max(p[n] for p in pts)] for n in names},
                "jump": float(np.max(final[np.asarray(confirmed)[at]])),
            }
        )
    return lines, evaluations


def switch_text(lines: list[dict]) -> str:
    """One clause naming the switch lines (empty when none)."""
    if not lines:
        return ""
    parts = []
    for line in lines:
        where = ", ".join(
            f"{n} {lo:.4g}" if np.isclose(lo, hi, rtol=1e-3) else f"{n} {lo:.4g}-{hi:.4g}"
            for n, (lo, hi) in line["range"].items()
        )
        parts.append(f"{where} (residuals jump by {line['jump']:.3g} sigma)")
    return "the dominant eigenmode switches at " + "; ".join(parts)
