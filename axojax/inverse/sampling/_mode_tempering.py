"""Stage 1 of :class:`~._mode_mixture.ModeMixture` (its module docstring): tempered
adaptive importance sampling from the prior box to the posterior, a Student-t mixture
(:mod:`._mixture`) fitted to the weighted points at every stage, the fit's optima seeded
(:func:`temper`); and the pieces the chains share with it: the log density's tempered
part at points (:func:`evaluate`, compiled) and systematic resampling
(:func:`systematic`)."""

from __future__ import annotations

import math

import blackjax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import scipy.special
from jaxtyping import Array, Float, PRNGKeyArray

from ..._progress import progress as progress_bar
from ._densities import log_reference
from ._laplace import centre, covariance, fitted_u
from ._mixture import TMixture, fit_mixture, mixture_of, split_to

EVALUATION_BATCH = 128
"""Points evaluated together (vmapped) at a time: bounds the memory of a stage."""
BRIDGE_FLOOR = 1000.0
"""The tempering's bridge floors the log likelihood this far below its best (:func:`_bridge`)."""
SEED_SHARE = 0.05
"""Share of the proposal given to the seeded optima's components (together)."""


def evaluate(_, target, z: Float[Array, "n k"]):
    """At each point z: the log density's tempered part (log likelihood and the prior's
    departure from uniform; failed evaluations -inf), log|du/dz| and the residuals."""
    problem = target.problem

    def one(zi):
        u = problem.to_u(zi)
        r = problem.residuals(u)
        log_ref = log_reference(problem)(zi)
        ll = -0.5 * jnp.sum(r**2) + target.log_prior(u)
        ll = jnp.where(jnp.isfinite(ll), ll, -jnp.inf)
        return ll, log_ref, r

    return jax.lax.map(one, z, batch_size=EVALUATION_BATCH)


def _draw(n_draws: int, target, mix: TMixture, key: PRNGKeyArray):
    """``n_draws`` draws from the mixture (keys split from ``key``) and their log proposal
    density."""
    problem = target.problem
    keys = jax.random.split(key, n_draws)
    z = jax.vmap(lambda k: mix.sample(k, problem.to_z))(keys)
    log_q = jax.vmap(lambda zi: mix.log_prob(zi, log_reference(problem)(zi)))(z)
    return z, log_q


def _ess(log_w: np.ndarray) -> float:
    """Effective sample size of importance weights given as logs (-inf: weight 0; none
    finite: 0), by blackjax's ``smc.ess``."""
    ess = float(blackjax.smc.ess.ess(jnp.asarray(log_w)))
    return ess if math.isfinite(ess) else 0.0


def _bridge(ll: np.ndarray) -> np.ndarray:
    """The log likelihood the tempering bridges with: floored at :data:`BRIDGE_FLOOR`
    below its best, failed evaluations (-inf) kept. Points far below the best (a failed
    prediction's penalty, 1e10 sigma away) would otherwise force stages of beta ~ 1e-10;
    at beta = 1 the floor changes no weight that is not already below exp(-1000)."""
    finite = np.isfinite(ll)
    if not np.any(finite):
        return ll
    return np.where(finite, np.maximum(ll, np.max(ll[finite]) - BRIDGE_FLOOR), -np.inf)


def _next_beta(beta: float, ll: np.ndarray, log_base: np.ndarray, share: float) -> float:
    """The largest beta' in [beta, 1] whose weights ``log_base + beta' ll`` keep ``share``
    of the ESS the weights have at ``beta`` (the conditional criterion of adaptive SMC:
    every stage moves, however good or poor the last proposal; bisection)."""
    floor = share * _ess(log_base + beta * ll)
    if _ess(log_base + ll) >= floor:
        return 1.0
    lo, hi = beta, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _ess(log_base + mid * ll) >= floor:
            lo = mid
        else:
            hi = mid
    return lo


def _recycled(history: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Every stage's points with log weights for the posterior: each stage's (z, log w)
    normalised within the stage and scaled by its effective sample size (the usual
    combination of independent importance samples: a stage drawn at a small beta adds
    the tails with little weight, the last ones the bulk)."""
    zs, logs = [], []
    for z, log_w in history:
        ess = _ess(log_w)
        if ess <= 0.0:
            continue
        zs.append(z)
        logs.append(log_w - scipy.special.logsumexp(log_w) + np.log(ess))
    return np.concatenate(zs), np.concatenate(logs)


def systematic(key: PRNGKeyArray, log_w: np.ndarray, n: int) -> np.ndarray:
    """n indices resampled systematically (blackjax) from weights given as logs."""
    w = jnp.asarray(scipy.special.softmax(log_w))
    return np.asarray(blackjax.smc.resampling.systematic(key, w, n))


def _initial_components(key, z: np.ndarray, log_w: np.ndarray, count: int):
    """``count`` components at points resampled by weight, each with the weighted
    covariance of all points shrunk by count^(2/k): a start that spans the weighted cloud."""
    k = z.shape[1]
    idx = np.unique(systematic(key, log_w, count))
    w = scipy.special.softmax(log_w)
    m = w @ z
    cov = ((z - m) * w[:, None]).T @ (z - m) + 1e-12 * np.eye(k)
    cov = cov * len(idx) ** (-2.0 / k)
    return z[idx], np.repeat(cov[None], len(idx), axis=0), np.full(len(idx), 1.0 / len(idx))


def _seeds(problem, target, init, call) -> tuple[np.ndarray, np.ndarray]:
    """Components at the fit's distinct optima (``init``: a ``FitResult``: its optimum and
    its ``optima`` at finite loss; or points in u, (k,) or (c, k)), each with its Laplace
    covariance in z; empty when ``init`` is None."""
    k = len(problem.names)
    if init is None:
        return np.zeros((0, k)), np.zeros((0, k, k))
    lower, upper = np.asarray(problem.lower, dtype=float), np.asarray(problem.upper, dtype=float)
    if not hasattr(init, "params"):  # points in u: (k,) or (c, k)
        points = list(np.atleast_2d(np.asarray(init, dtype=float)))
        if any(p.shape != (k,) or not np.all((p > lower) & (p < upper)) for p in points):
            raise ValueError(
                f"init: points in u of shape (k={k},) or (c, {k}) strictly inside the bounds"
            )
    else:
        points = [fitted_u(init, problem.names, lower, upper)]
    for values, loss in getattr(init, "optima", ()) or ():
        if math.isfinite(loss) and all(n in values for n in problem.names):
            fake = type("Optimum", (), {"params": values, "coordinate": init.coordinate})
            points.append(fitted_u(fake, problem.names, lower, upper))
    distinct = []
    for u in points:
        if not any(np.max(np.abs(u - v)) < 1e-3 for v in distinct):
            distinct.append(u)
    means, covs = [], []
    for u in distinct:
        z = jnp.asarray(problem.to_z(jnp.asarray(u)))
        try:
            _, precision, _ = call(centre, (False, True), target, z)
        except TypeError:  # residuals with a reverse-only (custom_vjp) derivative
            _, precision, _ = call(centre, (False, False), target, z)
        means.append(np.asarray(z))
        covs.append(np.asarray(covariance(np.asarray(precision, dtype=float))))
    return np.stack(means), np.stack(covs)


def _with_seeds(mean, cov, share, seeds):
    """The fitted components with the seeds appended, sharing :data:`SEED_SHARE`."""
    s_mean, s_cov = seeds
    if len(s_mean) == 0:
        return mean, cov, share
    share = np.concatenate(
        [(1 - SEED_SHARE) * share, np.full(len(s_mean), SEED_SHARE / len(s_mean))]
    )
    return np.concatenate([mean, s_mean]), np.concatenate([cov, s_cov]), share


class Adapted(eqx.Module):
    """What the adaptive stages leave (:func:`temper`): the chains' proposal ``mix``; the
    last points (z) and their log weights for the posterior; every point evaluated,
    stacked (z, residuals, tempered log density); the stages run, the beta reached and
    the evaluations spent."""

    mix: TMixture
    last: tuple[np.ndarray, np.ndarray]
    seen: tuple[np.ndarray, np.ndarray, np.ndarray]
    stages: int
    beta: float
    evaluations: int


def temper(sampler, target, init, key, clock, progress: bool) -> Adapted:
    """Stage 1 of :class:`~._mode_mixture.ModeMixture` (``sampler``): tempered adaptive
    importance sampling from the prior box to the posterior, the fit's optima (``init``)
    seeded; its stages counted on stderr from the start (the seeds' compilation
    included)."""
    with progress_bar(
        total=None, desc="posterior stages", unit="stage", enable=progress, starting="compiling"
    ) as bar:
        return _tempered(sampler, target, init, key, clock, bar)


def _tempered(sampler, target, init, key, clock, bar) -> Adapted:
    """:func:`temper`'s stages, each counted on ``bar``."""
    problem = target.problem
    k = len(problem.names)
    n = sampler.particles
    lower, upper = np.asarray(problem.lower, dtype=float), np.asarray(problem.upper, dtype=float)
    log_box = float(np.sum(np.log(upper - lower)))
    seeds = _seeds(problem, target, init, clock.call)
    key, key_u = jax.random.split(key)
    u0 = jax.random.uniform(key_u, (n, k), minval=lower, maxval=upper, dtype=float)
    z = np.asarray(jax.vmap(problem.to_z)(u0))
    ll, log_ref, r = (np.asarray(a) for a in clock.call(evaluate, None, target, jnp.asarray(z)))
    log_q = log_ref - log_box
    seen = [(z, r, ll)]
    beta, stages, components, mix = 0.0, 0, None, None
    history = []  # every stage's points and log(reference / proposal): the EM's data at beta = 1
    rounds = 0
    while stages < sampler.max_stages:
        log_base = log_ref - log_q
        history.append((z, log_base + ll))
        if beta >= 1.0:
            rounds += 1
            if _ess(log_base + ll) >= sampler.efficiency * n or rounds > sampler.rounds:
                break
        bridge = _bridge(ll)
        beta = _next_beta(beta, bridge, log_base, sampler.target_ess)
        key, key_init, key_draw = jax.random.split(key, 3)
        if beta >= 1.0:
            data_z, log_w = _recycled(history)
        else:
            data_z, log_w = z, log_base + beta * bridge
        if components is None:
            components = _initial_components(key_init, data_z, log_w, sampler.components or 12 * k)
        components = split_to(*components, sampler.components or 12 * k)
        components = fit_mixture(data_z, scipy.special.softmax(log_w), *components)
        mix = mixture_of(
            *_with_seeds(*components, seeds), sampler.df, sampler.defensive, lower, upper
        )
        z, log_q = (np.asarray(a) for a in clock.call(_draw, n, target, mix, key_draw))
        ll, log_ref, r = (np.asarray(a) for a in clock.call(evaluate, None, target, jnp.asarray(z)))
        seen.append((z, r, ll))
        stages += 1
        bar.update(1)
    stacked = tuple(np.concatenate([s[i] for s in seen]) for i in range(3))
    return Adapted(mix, (z, log_ref - log_q + ll), stacked, stages, beta, n * (stages + 1))
