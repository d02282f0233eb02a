"""Where the dominant eigenmode switches (a cliff of the likelihood): :func:`find_switches`
locates the switch lines among the points a sampler evaluated.

A switch is a discontinuity of the residuals: across it another eigenmode is the
dominant one and the predicted frequency (or wavelength) jumps. Candidates are pairs of
near neighbours (in coordinates whitened by the posterior's covariance), one of them
within :data:`REACH` of the best log density (the other may be beyond the cliff), whose
residuals differ by more than :data:`JUMP` (in sigmas). Each candidate segment is bisected
:data:`LEVELS` times, keeping the half whose ends differ most (residuals on a log scale,
so that a failed prediction's erratic residuals count as one side): a discontinuity keeps
its jump while the segment shrinks 2^LEVELS-fold, a smooth but steep change loses it
(halved at every level). Confirmed points are grouped into lines (single linkage within
:data:`LINE_GAP` whitened units); each line is reported with the range of every
parameter along it, its points, and the jump.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import scipy.sparse.csgraph
from jaxtyping import Array, Float

REACH = 25.0
"""Only points whose log density is within this of the best are searched."""
JUMP = 5.0
"""A jump of the residuals (largest component, in sigmas) that a switch must keep."""
LEVELS = 12
"""Bisection levels per candidate (the segment shrinks 4096-fold)."""
MAX_CANDIDATES = 48
"""Candidate segments bisected, the steepest first."""
NEIGHBOURS = 8
"""Nearest neighbours of each point paired with it."""
MAX_POINTS = 6000
"""Points searched (the highest log densities): those within :data:`REACH` of the best
and, as their neighbours, the rest."""
KEPT = 1.0
"""A switch keeps at least this jump of the log-scaled residuals (``sign(r) log(1 + |r|)``)
over the final segment (4096 times shorter than the first): a smooth change keeps about
1/4096 of its jump."""
LINE_GAP = 2.0
"""Confirmed switch points closer than this (whitened units) are one line."""


def _g(r):
    """Residuals on a log scale, sign kept: a failed prediction's erratic 1e5-sigma
    residuals are close to each other there and far from a beat's few sigma."""
    return jnp.sign(r) * jnp.log1p(jnp.abs(r))


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
            left = jnp.max(jnp.abs(_g(rm) - _g(ra))) >= jnp.max(
                jnp.abs(_g(rm) - _g(rb))
            )  # jump in (a, m)
            return (
                jnp.where(left, a, m),
                jnp.where(left, m, b),
                jnp.where(left, ra, rm),
                jnp.where(left, rm, rb),
            )

        return jax.lax.fori_loop(0, LEVELS, level, (a, b, ra, rb))

    return jax.vmap(one)(a, b)


def _candidates(w: np.ndarray, r: np.ndarray, near: np.ndarray) -> list[tuple[int, int, float]]:
    """Pairs (i, j, jump) of a point i within reach (``near``: their indices) and one of
    its :data:`NEIGHBOURS` nearest among all points (the far side of a cliff is often
    out of reach), whose residuals jump by over :data:`JUMP`; steepest (jump over
    distance) first, at most :data:`MAX_CANDIDATES`."""
    pairs = {}
    for start in range(0, len(near), 500):
        rows = near[start : start + 500]
        d2 = np.sum((w[rows, None, :] - w[None, :, :]) ** 2, axis=-1)
        d2[np.arange(len(rows)), rows] = np.inf
        nearest = np.argsort(d2, axis=1)[:, :NEIGHBOURS]
        for row, js in enumerate(nearest):
            i = int(rows[row])
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
    """Line index of each confirmed point (single linkage within :data:`LINE_GAP`; lines
    numbered in order of their first point)."""
    near = np.linalg.norm(points_w[:, None] - points_w[None], axis=-1) < LINE_GAP
    label = scipy.sparse.csgraph.connected_components(near, directed=False)[1]
    _, first, inverse = np.unique(label, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse].astype(int)


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
    order = np.nonzero(finite)[0]
    order = order[np.argsort(-ll[order])][:MAX_POINTS]  # the best points, any log density
    z, r, ll = z[order], r[order], ll[order]
    near = np.nonzero(ll >= ll[0] - REACH)[0]
    w = np.linalg.solve(chol, (z - centre).T).T
    cands = _candidates(w, r, near)
    if not cands:
        return [], 0
    a = jnp.asarray(z[[c[0] for c in cands]])
    b = jnp.asarray(z[[c[1] for c in cands]])
    a_end, b_end, ra, rb = (np.asarray(x) for x in call(_bisect, None, target, a, b))
    evaluations = len(cands) * (LEVELS + 2)
    final = np.max(np.abs(ra - rb), axis=1)
    kept = np.max(np.abs(np.asarray(_g(ra)) - np.asarray(_g(rb))), axis=1)
    confirmed = [i for i in range(len(cands)) if final[i] >= JUMP and kept[i] >= KEPT]
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
