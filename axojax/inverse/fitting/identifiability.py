"""What a fit determines: one verdict per fitted value, from one rule, and the words of
the fit's message.

The rule, in the fitted coordinate u (log for positive parameters, linear for gamma),
with the covariance ``cov`` (k, k) of u from the Gauss-Newton matrix:

1. ``"at_bound"``: within 1 % of its bound range of a bound (the box, not the data,
   stopped it);
2. ``"determined"``: its standard error ``sqrt(cov_ii)`` is at most its limit (1 for a
   log parameter: a factor e; 5 % of the bound range for a linear one);
3. ``"combination"``: not determined itself, but strongly correlated (``|corr| >=
   0.95``) with another value that is neither determined nor at a bound, and their
   best-determined combination (the smaller principal standard error of the 2 x 2 block
   of ``cov``) is within the smaller of their limits: only the combination is known;
4. ``"undetermined"``: anything else.

A value has exactly one verdict, so a message never calls a value determined and, in
the same breath, part of a combination that alone is determined. A strong correlation
between determined values is said as a correlation, no more. An uncertainty wider than
the whole bound range (in u) is said as ``unbounded``, not as a number like "a factor
1e+304".
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

IDENTIFIABLE_MAX_LOG_SE = 1.0
IDENTIFIABLE_MAX_LINEAR_FRACTION = 0.05
STRONG_CORRELATION = 0.95
VERDICTS = ("at_bound", "determined", "combination", "undetermined")


def limits(log: np.ndarray, span: np.ndarray) -> np.ndarray:
    """(k,) the largest standard error in u of a determined value (rule 2)."""
    return np.where(log, IDENTIFIABLE_MAX_LOG_SE, IDENTIFIABLE_MAX_LINEAR_FRACTION * span)


def verdicts(
    names: Sequence[str],
    cov: np.ndarray,
    log: np.ndarray,
    span: np.ndarray,
    at_bound: Sequence[str] = (),
) -> tuple[dict[str, str], list[tuple[str, str, float]]]:
    """The verdict of every value (module docstring) and the pairs behind the
    ``"combination"`` verdicts: (name, name, correlation).

    Args:
        names: the k fitted values.
        cov: (k, k) covariance in u (non-finite entries: no information).
        log: (k,) whether u is the log of the value.
        span: (k,) upper - lower bound in u.
        at_bound: names within 1 % of a bound.
    """
    k = len(names)
    cov = np.asarray(cov, dtype=float)
    se = np.sqrt(np.abs(np.diag(cov)))
    lim = limits(np.asarray(log, dtype=bool), np.asarray(span, dtype=float))
    out = {}
    for i, n in enumerate(names):
        if n in at_bound:
            out[n] = "at_bound"
        elif np.isfinite(se[i]) and se[i] <= lim[i]:
            out[n] = "determined"
        else:
            out[n] = "undetermined"
    pairs = []
    for i in range(k):
        for j in range(i + 1, k):
            if out[names[i]] != "undetermined" and out[names[i]] != "combination":
                continue
            if out[names[j]] not in ("undetermined", "combination"):
                continue
            c = _correlation(cov, se, i, j)
            block = cov[np.ix_([i, j], [i, j])]
            if not (np.isfinite(c) and abs(c) >= STRONG_CORRELATION and np.all(np.isfinite(block))):
                continue
            best = math.sqrt(max(float(np.linalg.eigvalsh(0.5 * (block + block.T))[0]), 0.0))
            if best <= min(lim[i], lim[j]):
                out[names[i]] = out[names[j]] = "combination"
                pairs.append((names[i], names[j], c))
    return out, pairs


def _correlation(cov: np.ndarray, se: np.ndarray, i: int, j: int) -> float:
    with np.errstate(invalid="ignore", divide="ignore"):
        c = cov[i, j] / (se[i] * se[j])
    return float(c) if np.isfinite(c) else math.nan


def uncertainty(se_u: float, log: bool, span: float) -> str:
    """An undetermined value's uncertainty in words: ``no information`` (not finite),
    ``unbounded`` (a standard error wider than the whole bound range in u: the data do
    not bound it inside the box), else the factor (log) or the +- and share of the range
    (linear)."""
    if not math.isfinite(se_u):
        return "no information"
    if se_u >= span:
        return "unbounded: the data do not bound it within its range"
    if log:
        return f"uncertain by a factor {math.exp(se_u):.3g}"
    return f"+- {se_u:.3g}, {se_u / span:.0%} of its range"


def strong_pairs(
    names: Sequence[str], cov: np.ndarray, verdict: dict[str, str]
) -> list[tuple[str, str, float]]:
    """Strongly correlated pairs of values not already joined by a ``"combination"``
    verdict (a correlation, said as one)."""
    cov = np.asarray(cov, dtype=float)
    se = np.sqrt(np.abs(np.diag(cov)))
    out = []
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            if verdict[names[i]] == verdict[names[j]] == "combination":
                continue
            c = _correlation(cov, se, i, j)
            if np.isfinite(c) and abs(c) >= STRONG_CORRELATION:
                out.append((names[i], names[j], c))
    return out


LOSS_TIE = 1e-3
"""Starts whose final losses differ by less than this share of the best (or of 1) reached
the same optimum (:func:`start_notes`)."""


NEAR_LOSS = 3.0
"""A start that stopped within this of the best loss (a posterior density within a factor
e^3 of the best's at its peak) is noted (:func:`start_notes`)."""


def start_notes(starts, loss: float) -> list[str]:
    """Notes on the other starts' final losses: when only one of several reached the best
    (the landscape has other optima, and a better one may lie beyond the starts: the
    human sperm's p, ks, where 4 of 32 starts reach the best loss), and when one stopped
    within :data:`NEAR_LOSS` of it (a second optimum, or a slow stretch of the same
    ridge, holding posterior mass that chains started at the best may not visit: the
    synthetic p-ks target's second mode)."""
    finals = np.array([f for _, f in starts], dtype=float)
    if finals.size < 2 or not math.isfinite(loss):
        return []
    tie = LOSS_TIE * max(abs(loss), 1.0)
    others = np.unique(np.round(finals[np.isfinite(finals) & (finals > loss + tie)], 4))
    notes = []
    if np.count_nonzero(finals <= loss + tie) == 1 and others.size:
        notes.append(
            f"only 1 of {finals.size} starts reached this loss ({loss:.4g}; the others stopped at "
            + ", ".join(f"{x:.4g}" for x in others[:4])
            + (", ..." if others.size > 4 else "")
            + "): other optima exist, and more starts (--starts) may find a better one"
        )
    near = others[others <= loss + NEAR_LOSS]
    if near.size:
        notes.append(
            f"a start stopped at loss {near[0]:.4g}, within {NEAR_LOSS:g} of this one's "
            f"({loss:.4g}): a second optimum or a slow stretch of the same ridge; a posterior "
            "started here may not visit it"
        )
    return notes


def distinct_optima(ends, limit: int = 8) -> list[dict]:
    """The distinct points the starts stopped at, best first: ``ends`` is
    :attr:`FitResult.optima` (values by name, final loss); two ends are one optimum when
    their losses tie (:data:`LOSS_TIE`) and every value agrees to 1e-3 (relative, or
    absolute for a value near 0). At most ``limit``, as ``{"params": ..., "loss": ...}``."""
    out: list[dict] = []
    for values, loss in sorted(ends, key=lambda e: e[1] if math.isfinite(e[1]) else math.inf):
        if not math.isfinite(loss):
            continue
        tie = LOSS_TIE * max(abs(loss), 1.0)
        same = any(
            abs(o["loss"] - loss) <= tie
            and all(
                math.isclose(values[n], o["params"][n], rel_tol=1e-3, abs_tol=1e-9) for n in values
            )
            for o in out
        )
        if not same:
            out.append({"params": dict(values), "loss": float(loss)})
        if len(out) >= limit:
            break
    return out
