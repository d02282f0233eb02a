"""``posterior(problem, sampler=ModeMixture())``: a posterior with several modes, cliffs
and curved ridges, sampled by independence Metropolis-Hastings chains (blackjax's
``irmh``) from a proposal fitted to the posterior by tempered adaptive importance
sampling.

1. **Find the mass** (tempered adaptive importance sampling). ``particles`` points from the
   prior box (uniform in u), then stages: the next tempering exponent beta keeps
   ``target_ess`` of the weights' effective sample size for the density ``prior x
   likelihood^beta`` (bisection, as blackjax's adaptive tempering), a Student-t mixture is
   fitted to the weighted points by EM (:func:`._mixture.fit_mixture`), and ``particles``
   fresh points are drawn from it and weighed. The mixture follows the mass as beta
   rises, component by component, into every mode; the fit's optima (``init``) are
   seeded as components at every stage so that a mode narrower than the prior screen
   sees is proposed. At beta = 1, at most ``rounds`` refits follow (each on every point
   drawn at beta = 1 so far), stopping early once the weights' efficiency (ESS over
   points) reaches ``efficiency``; ``max_stages`` bounds everything.
2. **Sample** (exact whatever the fit). ``chains`` independence Metropolis-Hastings chains
   with that mixture as proposal, plus a defensive share from the prior box, started from
   the last weighted points (resampled, so near the posterior), ``burn`` steps dropped.
   A move is proposed anywhere in the box and accepted with the Metropolis-Hastings ratio
   of values: no gradient, so a cliff (where another eigenmode becomes the dominant one and
   the predicted frequency jumps) costs nothing but rejections, and a chain jumps between
   modes in one step, so each mode's share of the draws is its mass.
3. **Report**: each mode (a connected group of mixture components, :mod:`.mode_report`)
   with its centre and mass (by the draws, and by the last importance weights), and the
   switch lines the points met (:mod:`.switches`).

Every log-density evaluation is counted (``Posterior.gradients``, none of them a
gradient): the stages' points, the chains' starts and proposals (burn-in included), the
mode grouping's and the switches' bisections; not the Laplace approximations at the
seeded optima (as NUTS's count leaves out its start), nor the fit.
"""

from __future__ import annotations

import math
import time

import blackjax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import scipy.special
from jaxtyping import Array, Float, PRNGKeyArray

from ..._progress import progress as progress_bar
from . import diagnostics
from ._densities import InverseProblem, _Target
from ._laplace import _centre, _covariance, _fitted_u
from ._mixture import TMixture, fit_mixture, mixture_of, split_to
from ._posterior_result import Posterior
from ._smc import _reference
from ._summaries import _Clock, _value_draws, gradient_free_posterior
from .mode_report import mode_masses
from .switches import find_switches

EVALUATION_BATCH = 128
"""Points evaluated together (vmapped) at a time: bounds the memory of a stage."""
BRIDGE_FLOOR = 1000.0
"""The tempering's bridge floors the log likelihood this far below its best (:func:`_bridge`)."""
SEED_SHARE = 0.05
"""Share of the proposal given to the seeded optima's components (together)."""


class ModeMixture(eqx.Module):
    """Independence Metropolis-Hastings from a mixture fitted to every mode (:mod:`.modes`):
    for posteriors of a few parameters with several modes, cliffs or curved ridges. Pass
    it as ``sampler=`` to :func:`axojax.inverse.posterior` (``init``: a least-squares
    ``FitResult`` seeds its optima; ``warmup``, ``transport`` and the warm cache do not
    apply).

    Attributes:
        particles: points per adaptive stage (more: a finer fit, more evaluations).
        components: the mixture's components (``None``: 12 per free parameter): EM merges
            or drops some as the density narrows, and the heaviest are split along their
            longest axis back to this count before every fit
            (:func:`._mixture.split_to`), so that they tile a long curved ridge.
        target_ess: share of the weights' effective sample size each tempering stage keeps.
        efficiency: stop adapting at beta = 1 when the weights' ESS over the points
            reaches this (a proposal that close makes chains that accept about as often).
        rounds: at most this many refits at beta = 1 (each on every point drawn at beta
            = 1 so far), whatever the efficiency: a cliff or a ridge that no mixture of
            a few t components fits leaves it below ``efficiency``, and the chains are
            exact with any proposal (they only accept less often).
        max_stages: most stages (tempering and rounds at beta = 1 together).
        df: the t components' degrees of freedom (heavier tails than the target's keep the
            chains uniformly ergodic).
        defensive: share of the chains' proposal drawn from the prior box.
        burn: steps of each chain dropped before its draws.
    """

    particles: int = 500
    components: int | None = None
    target_ess: float = 0.5
    efficiency: float = 0.8
    rounds: int = 4
    max_stages: int = 40
    df: float = 3.0
    defensive: float = 0.05
    burn: int = 50

    def __check_init__(self):
        if not (isinstance(self.particles, int) and self.particles >= 50):
            raise ValueError(
                f"ModeMixture: particles must be an integer >= 50, got {self.particles!r}"
            )
        if self.components is not None and not (
            isinstance(self.components, int) and self.components >= 1
        ):
            raise ValueError(
                f"ModeMixture: components must be an integer >= 1, got {self.components!r}"
            )
        for name in ("target_ess", "efficiency"):
            if not 0.0 < getattr(self, name) < 1.0:
                raise ValueError(
                    f"ModeMixture: {name} must be in (0, 1), got {getattr(self, name)!r}"
                )
        if not (isinstance(self.rounds, int) and self.rounds >= 0):
            raise ValueError(f"ModeMixture: rounds must be an integer >= 0, got {self.rounds!r}")
        if not (isinstance(self.max_stages, int) and self.max_stages >= 1):
            raise ValueError(
                f"ModeMixture: max_stages must be an integer >= 1, got {self.max_stages!r}"
            )
        if not (math.isfinite(self.df) and self.df > 2.0):
            raise ValueError(f"ModeMixture: df must be > 2, got {self.df!r}")
        if not 0.0 < self.defensive < 1.0:
            raise ValueError(f"ModeMixture: defensive must be in (0, 1), got {self.defensive!r}")
        if not (isinstance(self.burn, int) and self.burn >= 0):
            raise ValueError(f"ModeMixture: burn must be an integer >= 0, got {self.burn!r}")


def _log_ref(problem, z: Float[Array, " k"]) -> Float[Array, ""]:
    """log|du/dz|: the uniform prior in u, as a density in z (up to the box's volume):
    SMC's reference density (:func:`._smc._reference`)."""
    return _reference(problem)(z)


def _evaluate(_, target, z: Float[Array, "n k"]):
    """At each point z: the log density's tempered part (log likelihood and the prior's
    departure from uniform; failed evaluations -inf), log|du/dz| and the residuals."""
    problem = target.problem

    def one(zi):
        u = problem.to_u(zi)
        r = problem.residuals(u)
        log_ref = _log_ref(problem, zi)
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
    log_q = jax.vmap(lambda zi: mix.log_prob(zi, _log_ref(problem, zi)))(z)
    return z, log_q


def _chains(shape, target, mix: TMixture, key: PRNGKeyArray, z0: Float[Array, "c k"]):
    """``chains`` independence Metropolis-Hastings chains (blackjax ``irmh``) of ``steps``
    steps from z0: positions (c, steps, k), log densities (c, steps), acceptance (c, steps)."""
    steps = shape
    problem = target.problem

    def log_q(z):
        return mix.log_prob(z, _log_ref(problem, z))

    kernel = blackjax.irmh.build_kernel()

    def step(state, key):
        state, info = kernel(
            key,
            state,
            target,
            lambda k: mix.sample(k, problem.to_z),
            lambda new, prev: log_q(prev.position),
        )
        return state, (state.position, state.logdensity, info.acceptance_rate)

    def chain(key, z):
        state = blackjax.irmh.init(z, target)
        _, out = jax.lax.scan(step, state, jax.random.split(key, steps))
        return out

    return jax.vmap(chain)(jax.random.split(key, z0.shape[0]), z0)


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


def _systematic(key: PRNGKeyArray, log_w: np.ndarray, n: int) -> np.ndarray:
    """n indices resampled systematically (blackjax) from weights given as logs."""
    w = jnp.asarray(scipy.special.softmax(log_w))
    return np.asarray(blackjax.smc.resampling.systematic(key, w, n))


def _initial_components(key, z: np.ndarray, log_w: np.ndarray, count: int):
    """``count`` components at points resampled by weight, each with the weighted
    covariance of all points shrunk by count^(2/k): a start that spans the weighted cloud."""
    k = z.shape[1]
    idx = np.unique(_systematic(key, log_w, count))
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
        points = [_fitted_u(init, problem.names, lower, upper)]
    for values, loss in getattr(init, "optima", ()) or ():
        if math.isfinite(loss) and all(n in values for n in problem.names):
            fake = type("Optimum", (), {"params": values, "coordinate": init.coordinate})
            points.append(_fitted_u(fake, problem.names, lower, upper))
    distinct = []
    for u in points:
        if not any(np.max(np.abs(u - v)) < 1e-3 for v in distinct):
            distinct.append(u)
    means, covs = [], []
    for u in distinct:
        z = jnp.asarray(problem.to_z(jnp.asarray(u)))
        try:
            _, precision, _ = call(_centre, (False, True), target, z)
        except TypeError:  # residuals with a reverse-only (custom_vjp) derivative
            _, precision, _ = call(_centre, (False, False), target, z)
        means.append(np.asarray(z))
        covs.append(np.asarray(_covariance(np.asarray(precision, dtype=float))))
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


class _Adapted(eqx.Module):
    """What the adaptive stages leave (:func:`_adapt`): the chains' proposal ``mix``; the
    last points (z) and their log weights for the posterior; every point evaluated,
    stacked (z, residuals, tempered log density); the stages run, the beta reached and
    the evaluations spent."""

    mix: TMixture
    last: tuple[np.ndarray, np.ndarray]
    seen: tuple[np.ndarray, np.ndarray, np.ndarray]
    stages: int
    beta: float
    evaluations: int


def _adapt(sampler: ModeMixture, target, init, key, clock, progress: bool) -> _Adapted:
    """Stage 1 of :mod:`.modes`: tempered adaptive importance sampling from the prior box
    to the posterior, the fit's optima (``init``) seeded."""
    problem = target.problem
    k = len(problem.names)
    n = sampler.particles
    lower, upper = np.asarray(problem.lower, dtype=float), np.asarray(problem.upper, dtype=float)
    log_box = float(np.sum(np.log(upper - lower)))
    seeds = _seeds(problem, target, init, clock.call)
    key, key_u = jax.random.split(key)
    u0 = jax.random.uniform(key_u, (n, k), minval=lower, maxval=upper, dtype=float)
    z = np.asarray(jax.vmap(problem.to_z)(u0))
    ll, log_ref, r = (np.asarray(a) for a in clock.call(_evaluate, None, target, jnp.asarray(z)))
    log_q = log_ref - log_box
    seen = [(z, r, ll)]
    beta, stages, components, mix = 0.0, 0, None, None
    history = []  # every stage's points and log(reference / proposal): the EM's data at beta = 1
    rounds = 0
    with progress_bar(total=None, desc="posterior stages", unit="stage", enable=progress) as bar:
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
                components = _initial_components(
                    key_init, data_z, log_w, sampler.components or 12 * k
                )
            components = split_to(*components, sampler.components or 12 * k)
            components = fit_mixture(data_z, scipy.special.softmax(log_w), *components)
            mix = mixture_of(
                *_with_seeds(*components, seeds), sampler.df, sampler.defensive, lower, upper
            )
            z, log_q = (np.asarray(a) for a in clock.call(_draw, n, target, mix, key_draw))
            ll, log_ref, r = (
                np.asarray(a) for a in clock.call(_evaluate, None, target, jnp.asarray(z))
            )
            seen.append((z, r, ll))
            stages += 1
            bar.update(1)
    stacked = tuple(np.concatenate([s[i] for s in seen]) for i in range(3))
    return _Adapted(mix, (z, log_ref - log_q + ll), stacked, stages, beta, n * (stages + 1))


def mode_posterior(
    problem: InverseProblem,
    sampler: ModeMixture,
    shape: tuple[int, int, int],
    prior,
    progress: bool = False,
    init=None,
) -> Posterior:
    """The posterior of ``problem`` by :class:`ModeMixture` (:func:`axojax.inverse.posterior`
    with ``sampler=ModeMixture()`` calls this).

    Args:
        problem: an :class:`InverseProblem`.
        sampler: the :class:`ModeMixture` settings.
        shape: (draws, chains, seed): draws kept per chain, chains, seed.
        prior: a log prior in u replacing the problem's (callable or None), checked.
        progress: progress bars on stderr.
        init: a least-squares ``FitResult`` whose optima are seeded (or None).

    Returns:
        :class:`Posterior` with ``sampler="modes"``, ``modes`` (each mode's centre and
        mass, :func:`.mode_report.mode_masses`), ``switches`` (the switch lines met,
        :func:`.switches.find_switches`), ``tempering_stages`` (one entry: the stages
        run), ``gradients`` every log-density evaluation (no gradients) and
        ``acceptance`` the chains' mean acceptance rate.
    """
    t_start = time.perf_counter()
    draws, chains, seed = shape
    names = tuple(problem.names)
    k = len(names)
    lower = np.asarray(problem.lower, dtype=float).reshape(-1)
    upper = np.asarray(problem.upper, dtype=float).reshape(-1)
    target = _Target(problem, prior)
    clock = _Clock()
    key_adapt, key_start, key_chain = jax.random.split(jax.random.PRNGKey(seed), 3)
    t0 = time.perf_counter()
    adapted = _adapt(sampler, target, init, key_adapt, clock, progress)
    seconds_warmup = time.perf_counter() - t0
    z_last, log_w = adapted.last
    z0 = jnp.asarray(z_last[_systematic(key_start, log_w, chains)])
    t0 = time.perf_counter()
    steps = sampler.burn + draws
    z, logd, accept = (
        np.asarray(a) for a in clock.call(_chains, steps, target, adapted.mix, key_chain, z0)
    )
    z, logd, accept = z[:, sampler.burn :], logd[:, sampler.burn :], accept[:, sampler.burn :]
    seconds_sampling = time.perf_counter() - t0
    u = np.asarray(jax.vmap(jax.vmap(problem.to_u))(jnp.asarray(z)))
    value_names, values, log_coordinate = _value_draws(problem, names, u, clock.call)

    def values_of(zi):
        ui = np.asarray(problem.to_u(jnp.asarray(zi)))
        return {n: float(np.exp(x) if log_coordinate[n] else x) for n, x in zip(names, ui)}

    flat_z = z.reshape(-1, k)

    def log_density(points):
        return clock.call(_evaluate, None, target, jnp.asarray(points))[0]

    modes, grouped = mode_masses(
        adapted.mix, flat_z, logd.reshape(-1), adapted.last, values_of, log_density
    )
    centre = flat_z.mean(axis=0)
    chol = np.linalg.cholesky(np.cov(flat_z.T).reshape(k, k) + 1e-12 * np.eye(k))
    switches, bisected = find_switches(
        problem, target, adapted.seen, centre, chol, values_of, clock.call
    )
    summ = diagnostics.summary(values[..., :k])
    evaluations = adapted.evaluations + chains * (steps + 1) + bisected + grouped  # +1: each start
    notes = diagnostics.sampler_notes(names, summ, chains, chains * draws, 0)
    if adapted.beta < 1.0:
        notes.append(
            f"ModeMixture: the tempering stopped at beta={adapted.beta:.3g} after max_stages="
            f"{sampler.max_stages} (raise max_stages or particles)"
        )
    return gradient_free_posterior(
        names=names,
        u=u,
        draws_info=(value_names, values, log_coordinate, logd),
        bounds=(lower, upper),
        summ=summ,
        notes=notes,
        evaluations=evaluations,
        clock=clock,
        t_start=t_start,
        acceptance=float(np.mean(accept)),
        warmup=int(sampler.burn),
        seconds_warmup=seconds_warmup,
        seconds_sampling=seconds_sampling,
        sampler="modes",
        tempering_stages=(adapted.stages,),
        modes=tuple(modes),
        switches=tuple(switches),
    )
