"""Convergence diagnostics of MCMC draws: R-hat and effective sample size.

Thin, shape-documented wrappers around :mod:`blackjax.diagnostics`, which implements the
rank-normalised split-chain diagnostics of Vehtari, Gelman, Simpson, Carpenter and
Buerkner (2021, "Rank-normalization, folding, and localization: an improved R-hat",
Bayesian Analysis 16, 667), the convention of Stan and ArviZ:

- :func:`rhat`: the larger of the bulk (rank-normalised) and tail (folded) split-R-hat;
- :func:`ess_bulk`: effective sample size of the rank-normalised split chains (the
  precision of means and medians);
- :func:`ess_tail`: the smaller ESS of the 5 % and 95 % quantile indicators (the
  precision of a 90 % interval's ends).

All take draws shaped ``(chains, draws)`` or ``(chains, draws, k)`` and return one
value per trailing component (``()`` or ``(k,)``), as numpy arrays. Both diagnostics are
invariant under monotone maps of a parameter (they use ranks), so they are the same in
the fitted coordinate (log) and in the parameter values.
"""

from __future__ import annotations

from collections.abc import Sequence

import jax
import numpy as np
from blackjax import diagnostics as _bd
from jaxtyping import Float

# Thresholds of Vehtari et al. (2021), section 4: R-hat below 1.01, and a bulk and tail
# ESS of at least 100 per chain (400 for the usual four chains) before the R-hat and the
# interval ends are trusted.
RHAT_MAX = 1.01
ESS_MIN_PER_CHAIN = 100


def _check(draws) -> np.ndarray:
    x = np.asarray(draws, dtype=float)
    if x.ndim < 2:
        raise ValueError(f"draws must be shaped (chains, draws[, k]), got shape {x.shape}")
    if x.shape[1] < 4:
        raise ValueError(f"draws: need at least 4 draws per chain, got {x.shape[1]}")
    return x


# Compiled (once per shape): run op by op, blackjax's rank normalisation and
# autocorrelation dispatch hundreds of small operations (seconds per call).
_rhat = jax.jit(_bd.rhat)
_ess_bulk = jax.jit(_bd.ess_bulk)
_ess_tail = jax.jit(_bd.ess_tail)


@jax.jit
def _all(x):
    return _bd.rhat(x), _bd.ess_bulk(x), _bd.ess_tail(x)


def rhat(draws: Float[np.ndarray, "chains draws *k"]) -> Float[np.ndarray, "*k"]:
    """Rank-normalised split R-hat (max of bulk and folded-tail): 1 at convergence."""
    x = _check(draws)
    return np.asarray(_rhat(x)).reshape(x.shape[2:])  # blackjax squeezes a k of 1 away


def ess_bulk(draws: Float[np.ndarray, "chains draws *k"]) -> Float[np.ndarray, "*k"]:
    """Bulk effective sample size (rank-normalised split chains), total over chains."""
    x = _check(draws)
    return np.asarray(_ess_bulk(x)).reshape(x.shape[2:])


def ess_tail(draws: Float[np.ndarray, "chains draws *k"]) -> Float[np.ndarray, "*k"]:
    """Tail effective sample size (the 5 % and 95 % quantile indicators), total over chains."""
    x = _check(draws)
    return np.asarray(_ess_tail(x)).reshape(x.shape[2:])


def summary(draws: Float[np.ndarray, "chains draws k"]) -> dict[str, Float[np.ndarray, " k"]]:
    """Per-component summaries of ``(chains, draws, k)`` draws, pooled over chains:
    ``mean``, ``sd`` (ddof 1), ``q05``, ``q50``, ``q95``, ``rhat``, ``ess_bulk``, ``ess_tail``."""
    x = _check(draws)
    if x.ndim != 3:
        raise ValueError(f"draws must be shaped (chains, draws, k), got shape {x.shape}")
    flat = x.reshape(-1, x.shape[-1])
    q05, q50, q95 = np.quantile(flat, [0.05, 0.5, 0.95], axis=0)
    r, eb, et = (np.asarray(v).reshape(x.shape[2:]) for v in _all(x))
    return {
        "mean": flat.mean(axis=0),
        "sd": flat.std(axis=0, ddof=1),
        "q05": q05,
        "q50": q50,
        "q95": q95,
        "rhat": r,
        "ess_bulk": eb,
        "ess_tail": et,
    }


def sampler_notes(
    names: Sequence[str], summary_: dict[str, np.ndarray], chains: int, draws: int, divergences: int
) -> list[str]:
    """What makes a posterior's draws untrustworthy, one line each (empty: nothing):
    R-hat above :data:`RHAT_MAX`, bulk or tail ESS below :data:`ESS_MIN_PER_CHAIN` per
    chain (each parameter's lower one, named: "p tail 373"), divergent transitions (of
    ``draws``, all chains)."""
    notes = []
    rhat = summary_["rhat"]
    bad = [f"{n} {rhat[i]:.3f}" for i, n in enumerate(names) if not rhat[i] <= RHAT_MAX]
    if bad:
        notes.append(
            f"R-hat above {RHAT_MAX}: {', '.join(bad)} (chains disagree; run longer or look for several modes)"
        )
    floor = ESS_MIN_PER_CHAIN * chains
    bulk, tail = summary_["ess_bulk"], summary_["ess_tail"]
    ess = np.minimum(bulk, tail)  # the lower of the two, named: the table prints both
    low = [
        f"{n} {'tail' if tail[i] < bulk[i] else 'bulk'} {ess[i]:.0f}"
        for i, n in enumerate(names)
        if not ess[i] >= floor
    ]
    if low:
        notes.append(
            f"effective sample size below {floor} ({ESS_MIN_PER_CHAIN} per chain): {', '.join(low)} (run more draws)"
        )
    if divergences:
        notes.append(
            f"{divergences} divergent transitions of {draws} (try "
            "NUTS(target_acceptance_rate=0.95), or check the bounds)"
        )
    return notes
