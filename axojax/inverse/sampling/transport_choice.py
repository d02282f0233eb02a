"""Which coordinates a posterior is sampled in: :func:`suggest_transport`.

NUTS samples well where the density it sees is close to a standard normal. Two maps
make it so, each exact (only the efficiency depends on the choice): the affine
whitening by the Laplace approximation at the optimum (the default), and the profile
transport along one free parameter (:class:`~axojax.inverse.sampling.transport.ProfileTransport`).
From a least-squares fit, :func:`suggest_transport` picks:

- a thin straight ridge (Gauss-Newton correlation at least :data:`RIDGE_CORRELATION`):
  the profile along the parameter of the largest standard error in z, at once (the
  human sperm's p, ks: along ks);
- otherwise, for at most :data:`MAX_PROFILES` free parameters, by importance sampling:
  each map pushes :data:`IMPORTANCE_DRAWS` standard normal draws to the posterior, and
  its log weights give an estimate of the posterior's mass (a map that misses some
  of it reads low) and an efficiency (the effective share of the draws: 1 for a map that
  makes the posterior exactly standard normal). The maps whose mass is within
  :data:`MASS_TOLERANCE` of the largest compete on efficiency, profiles without a
  barrier along their axis (:data:`BARRIER`: where the profile jumps between two
  branches of a valley) first; the Laplace whitening (None) is kept unless a profile is
  :data:`GAIN` times as efficient;
- beyond that many parameters: the profile along the widest parameter when another start
  stopped within ``NEAR_LOSS`` of the best loss but more than :data:`OPTIMA_SDS` local
  standard errors away (``fit.optima``), else None.

Why more than the optimum's correlations: on p, ks of seven (4 elements) from a frequency
and a wavelength made at p 279, ks 6.4e3 (scripts/check_posterior_calibration.py's
first truth) the optimum lies at p 220, ks 3.2e3 with correlation -0.30 and ks x/ 1.35,
while the valley holds mass up to ks 1e6 (its profile); whitened NUTS from the optimum
stayed within ks 2.3e3-5.0e3 and missed the truth. This choice (along p) gives p 217-322,
ks 2.5e3-1.6e4 (90 %, 2 x 200 draws), the truth inside; a grid integration (the script's
``--quadrature 1``) gives p 216-372, ks 2.5e3-4.4e5: the valley's last tenth of mass,
where it turns steeply towards the ks bound, is still under-sampled (divergences there).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import jax
import jax.numpy as jnp
import numpy as np

from ..fitting.identifiability import NEAR_LOSS
from ._densities import LogDensity
from ._laplace import centre, covariance, fitted_u
from .programs import compiled
from .transport import DEFAULT_KNOTS, ProfileTransport, build_map

RIDGE_CORRELATION = 0.99
"""A posterior whose Laplace approximation correlates two parameters at least this
strongly is a thin ridge: :func:`suggest_transport` straightens it."""
OPTIMA_SDS = 4.0
"""A start that stopped this many local standard errors (in z, along some parameter)
from the best optimum, within ``NEAR_LOSS`` of its loss, is a distinct optimum the
posterior spans (used beyond :data:`MAX_PROFILES` parameters)."""
MAX_PROFILES = 3
"""Up to this many free parameters every profile is tried (each costs ~100
conditional maxima)."""
IMPORTANCE_DRAWS = 256
"""Standard normal draws pushed through each candidate map."""
MASS_TOLERANCE = math.log(1.5)
"""A map whose estimate of the posterior's mass (log) is this far below the largest
misses some of it, and is not chosen."""
GAIN = 1.2
"""A profile replaces the Laplace whitening when this many times as efficient."""
BARRIER = 4.0
"""A map whose density along its axis dips this far (log) between two parts of the mass
has a barrier NUTS crosses rarely (a profile that jumps between two branches of a
valley): chosen only if every profile has one."""
BARRIER_RANGE, BARRIER_POINTS = 2.5, 201
"""Where along the map's axis (its standard normal coordinate) dips are looked for."""


def suggest_transport(problem, fit) -> ProfileTransport | None:
    """The transport for sampling ``problem``'s posterior from the least-squares ``fit``
    (a :class:`~axojax.inverse.FitResult` at its optimum), or None for the Laplace
    whitening alone (module docstring). Deterministic (fixed draws)."""
    names = tuple(fit.names)
    corr = np.asarray(fit.correlation, dtype=float)
    if len(names) < 2 or corr.shape != (len(names), len(names)):
        return None
    lower, upper = np.asarray(problem.lower), np.asarray(problem.upper)
    u = jnp.asarray(fitted_u(fit, names, lower, upper))
    dz_du = np.abs(np.diagonal(np.asarray(jax.jacfwd(problem.to_z)(u))))
    sd_z = np.array([fit.stderr_fitted[n] for n in names]) * dz_du
    if not np.any(np.isfinite(sd_z)):
        return None
    widest = names[int(np.nanargmax(np.where(np.isfinite(sd_z), sd_z, np.nan)))]
    off = np.abs(corr[~np.eye(len(names), dtype=bool)])
    if np.any(np.nan_to_num(off) >= RIDGE_CORRELATION):
        return ProfileTransport(widest)
    if len(names) > MAX_PROFILES:
        return ProfileTransport(widest) if _distant_optimum(problem, fit, names, u, sd_z) else None
    scores, maps = _importance(problem, u)
    choice = _best(scores)
    if choice is None:
        return None
    return ProfileTransport(names[choice], DEFAULT_KNOTS, maps[choice])


def importance_scores(problem, u, draws: int = IMPORTANCE_DRAWS, seed: int = 0) -> dict:
    """``{None or parameter index: (log mass estimate, efficiency, barrier)}`` of the
    Laplace whitening at ``u`` (the fitted coordinates of an optimum) and of the profile
    along each free parameter: from the same ``draws`` standard normal draws y, the log
    weights ``log p(z(y)) + log |dz/dy| - log N(y; 0, I)``; the mass estimate is their
    mean weight's log, the efficiency ``(sum w)^2 / (draws sum w^2)`` (in (0, 1]), the
    barrier the deepest dip of the log weight along the profile's axis (its other
    coordinates 0; 0 for the Laplace whitening) between higher values on both sides."""
    return _importance(problem, u, draws, seed)[0]


def _importance(problem, u, draws: int = IMPORTANCE_DRAWS, seed: int = 0) -> tuple[dict, dict]:
    """:func:`importance_scores` and the profile maps it built, ``{index: ProfileMap}``."""
    target = LogDensity(problem)
    z0 = jnp.asarray(problem.to_z(u), dtype=float)
    try:
        z_c, precision, _ = compiled(centre, (False, True), (target, z0))[0]
    except TypeError:  # residuals with a reverse-only (custom_vjp) derivative
        z_c, precision, _ = compiled(centre, (False, False), (target, z0))[0]
    chol = jnp.linalg.cholesky(jnp.asarray(covariance(np.asarray(precision, dtype=float))))
    y = jax.random.normal(jax.random.PRNGKey(seed), (draws, z0.shape[0]), dtype=float)
    s = jnp.linspace(-BARRIER_RANGE, BARRIER_RANGE, BARRIER_POINTS)
    scores = {None: (*_score(compiled(_laplace_log_weights, None, (target, z_c, chol, y))[0]), 0.0)}
    maps = {}
    for a in range(z0.shape[0]):
        maps[a] = compiled(build_map, (a, DEFAULT_KNOTS), (target, z_c))[0]
        log_w, along = compiled(_profile_log_weights, None, (target, maps[a], y, s))[0]
        scores[a] = (*_score(log_w), _dip(along))
    return scores, maps


def _laplace_log_weights(_, target, z_c, chol, y):
    def one(w):
        return target(z_c + chol @ w) + _minus_log_normal(w)

    return jax.vmap(one)(y) + jnp.sum(jnp.log(jnp.diagonal(chol)))


def _profile_log_weights(_, target, profile, y, s):
    """The draws' log weights, and the same along the map's axis (``s``, the others 0)."""

    def one(w):
        return target(profile.to_z(w)) + profile.log_det(w) + _minus_log_normal(w)

    axis = jnp.zeros((s.shape[0], y.shape[1]), dtype=y.dtype).at[:, profile.along].set(s)
    return jax.vmap(one)(y), jax.vmap(one)(axis)


def _dip(log_w) -> float:
    """The deepest dip of ``log_w`` (along an axis) below the lower of the highest
    values on its two sides: a barrier between two parts of the mass (0: none)."""
    x = np.asarray(log_w, dtype=float)
    x = np.where(np.isfinite(x), x, -1e300)
    walls = np.minimum(np.maximum.accumulate(x), np.maximum.accumulate(x[::-1])[::-1])
    return float(np.max(walls - x))


def _minus_log_normal(w):
    """``-log`` of the standard normal density at ``w``."""
    return 0.5 * jnp.sum(w**2) + 0.5 * w.shape[0] * math.log(2 * math.pi)


def _score(log_w) -> tuple[float, float]:
    lw = np.asarray(log_w, dtype=float)
    lw = np.where(np.isfinite(lw), lw, -np.inf)
    if not np.any(np.isfinite(lw)):
        return -math.inf, 0.0
    top = np.max(lw)
    w = np.exp(lw - top)
    log_mass = float(top + np.log(np.mean(w)))
    return log_mass, float(np.sum(w) ** 2 / (lw.size * np.sum(w**2)))


def _best(scores: dict):
    """The candidate chosen from :func:`importance_scores` (module docstring)."""
    most = max(m for m, _, _ in scores.values())
    if not math.isfinite(most):  # no map reached the posterior (failed evaluations)
        return None
    eligible = {c: (e, d) for c, (m, e, d) in scores.items() if m >= most - MASS_TOLERANCE}
    smooth = {c: e for c, (e, d) in eligible.items() if c is not None and d <= BARRIER}
    profiles = smooth or {c: e for c, (e, _) in eligible.items() if c is not None}
    if not profiles:
        return None
    best = max(profiles, key=profiles.get)
    if None in eligible and profiles[best] < GAIN * eligible[None][0]:
        return None
    return best


def _distant_optimum(problem, fit, names, u, sd_z) -> bool:
    """Whether a start of ``fit`` stopped within ``NEAR_LOSS`` of the best loss and more
    than :data:`OPTIMA_SDS` local standard errors ``sd_z`` (in z) from it."""
    z_best = np.asarray(problem.to_z(u))
    lower, upper = np.asarray(problem.lower), np.asarray(problem.upper)
    sd = np.where(np.isfinite(sd_z) & (sd_z > 0), sd_z, np.inf)
    for values, loss in getattr(fit, "optima", ()):
        if not (np.isfinite(loss) and loss <= fit.loss + NEAR_LOSS):
            continue
        if any(n not in values for n in names):
            continue
        end = SimpleNamespace(params=values, coordinate=fit.coordinate)  # as fitted_u reads
        other = fitted_u(end, names, lower, upper)
        dz = np.asarray(problem.to_z(jnp.asarray(other))) - z_best
        if np.max(np.abs(dz) / sd) > OPTIMA_SDS:
            return True
    return False
