"""What every sampler of :mod:`axojax.inverse.sampling` makes of its draws (public, so that
a sampler of one's own, an :class:`~axojax.inverse.sampling.AbstractSampler`, can make
them the same way): draws in z as draws in u (:func:`to_u`, a compiled piece) and as
parameter values (:func:`value_draws`, by :func:`problem_values`), their per-parameter statistics
(:func:`statistics`), and the :class:`~axojax.inverse.Posterior` of a sampler without
gradients (:func:`gradient_free_posterior`)."""

from __future__ import annotations

import math
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np

from ...results import RESULTS, message
from ._densities import LogDensity
from ._posterior_result import Posterior
from .programs import Clock


def to_u(_, target, z):
    """Draws z (chains, draws, k) -> u (chains, draws, k): a piece for :meth:`Clock.call`
    (``clock.call(to_u, None, target, z)``)."""
    return jax.vmap(jax.vmap(target.problem.to_u))(z)


def _values_batch(_, target, u):
    return jax.vmap(target.problem.values)(u)


def problem_values(problem, u: np.ndarray, call) -> dict[str, np.ndarray]:
    """``problem.values`` of every row of u (n, k): vmapped where it is traceable (by
    ``call``, a :meth:`Clock.call`), else one call per draw (a ``values`` written in numpy
    for concrete u)."""
    try:
        return {
            n: np.asarray(v, dtype=float)
            for n, v in call(_values_batch, None, LogDensity(problem), jnp.asarray(u)).items()
        }
    except TypeError:  # jax's concretisation errors: values() needs concrete u
        rows = [problem.values(x) for x in u]
        return {n: np.array([float(r[n]) for r in rows]) for n in rows[0]}


def value_draws(problem, names, u, call):
    """The draws u (chains, draws, k) as parameter values: their names (the free
    parameters first, then what else ``problem.values`` reports), the values (chains,
    draws, n) and per free parameter whether u is the log of its value."""
    chains, draws, k = u.shape
    by_name = problem_values(problem, u.reshape(-1, k), call)
    value_names = tuple(names) + tuple(n for n in by_name if n not in names)
    cols = [
        np.asarray(by_name[n], dtype=float).reshape(chains, draws) if n in by_name else u[..., i]
        for i, n in enumerate(value_names)
    ]
    values = np.stack(cols, axis=-1)
    log_coordinate = {
        n: bool(
            np.all(values[..., i] > 0)
            and np.allclose(np.log(values[..., i]), u[..., i], rtol=1e-9, atol=1e-9)
        )
        for i, n in enumerate(names)
    }
    return value_names, values, log_coordinate


def statistics(names, summ, flat_u) -> dict[str, dict[str, float]]:
    """Per parameter, by name: mean, sd, 5/50/95 % quantiles, R-hat and bulk/tail ESS of
    its values (``summ``: :func:`.diagnostics.summary`), and the mean and sd of its
    draws in u (``flat_u``: (chains * draws, k)), as :class:`Posterior` names them."""

    def per(key):
        return {n: float(summ[key][i]) for i, n in enumerate(names)}

    return {
        "mean": per("mean"),
        "sd": per("sd"),
        "q05": per("q05"),
        "q50": per("q50"),
        "q95": per("q95"),
        "mean_u": {n: float(v) for n, v in zip(names, flat_u.mean(axis=0))},
        "sd_u": {n: float(v) for n, v in zip(names, flat_u.std(axis=0, ddof=1))},
        "rhat": per("rhat"),
        "ess": per("ess_bulk"),
        "ess_tail": per("ess_tail"),
    }


def gradient_free_posterior(
    *,
    names,
    u,
    draws_info: tuple,
    bounds: tuple,
    summ,
    notes: list[str],
    evaluations: int,
    clock: Clock,
    t_start: float,
    **fields,
):
    """The :class:`~axojax.inverse.Posterior` of a sampler without gradients (:class:`SMC`,
    :class:`ModeMixture`, or one's own, its ``run`` calling this): its notes warned (one
    line each, for the caller of :func:`posterior`, which called ``run``) and folded into
    ``message`` and ``result``; no divergences, step sizes or start. ``draws_info`` =
    (value_names, values, log_coordinate, log_density); ``bounds`` = (lower, upper);
    ``fields``: the sampler's own (``acceptance``, ``warmup``, ``seconds_warmup``,
    ``seconds_sampling``, ``sampler``, ...)."""
    for note in notes:
        warnings.warn(note, stacklevel=4)
    chains, draws, k = u.shape
    value_names, values, log_coordinate, log_density = draws_info
    total = time.perf_counter() - t_start
    ess_min = float(np.min(summ["ess_bulk"]))
    result = RESULTS.successful if not notes else RESULTS.chains_not_converged
    return Posterior(
        names=names,
        u=u,
        value_names=value_names,
        values=values,
        log_density=log_density,
        divergent=np.zeros(u.shape[:2], dtype=bool),
        lower=bounds[0],
        upper=bounds[1],
        log_coordinate=log_coordinate,
        **statistics(names, summ, u.reshape(-1, k)),
        divergences=0,
        step_size=np.full(chains, math.nan),
        gradients=int(evaluations),
        seconds=total,
        seconds_compile=clock.seconds,
        seconds_start=0.0,
        seconds_per_gradient=(total - clock.seconds) / max(evaluations, 1),
        seconds_per_ess=total / ess_min if ess_min > 0 else math.inf,
        start_u=np.full(k, math.nan),
        message="; ".join(notes) or message(result),
        result=result,
        gradients_per_draw=evaluations / (chains * draws),
        **fields,
    )
