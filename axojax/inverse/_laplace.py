"""Where a posterior's chains start: the maximum of the log density (or a given point,
e.g. a least-squares optimum), the Laplace approximation there (its covariance: the
spread of the starts and the whitening of the sampled coordinates)."""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from jaxtyping import Array, Float

CENTRE_NEWTON_STEPS = 3
"""Gauss-Newton steps on the whole log density after Levenberg-Marquardt (a non-uniform
prior)."""
MAX_START_SD_Z = 2.0
"""Widest start spread in z: about the logistic prior's own width (pi / sqrt 3)."""


def _logistic_residuals(z: Float[Array, " k"]) -> Float[Array, " k"]:
    """Pseudo-residuals ``q`` of the logistic map's log-Jacobian: ``-|q|^2 / 2`` equals
    ``sum(log sigmoid(z) + log sigmoid(-z)) + k log 4`` exactly (``q`` smooth, ``q ~ z / sqrt 2``
    near 0), so ``-|(r, q)|^2 / 2`` is the log density in z of a uniform prior up to a constant."""
    excess = jnp.logaddexp(0.0, z) + jnp.logaddexp(0.0, -z) - jnp.log(4.0)  # >= 0, ~ z^2 / 4 at 0
    return jnp.sign(z) * jnp.sqrt(2.0 * jnp.maximum(excess, 0.0))


def _centre(settings, target, z0):
    """The centre of the starts and the Laplace precision (k, k) in z there, in one
    program: with ``optimise``, the maximum of the log density from ``z0``:
    Levenberg-Marquardt (optimistix) on the residuals and the logistic map's
    pseudo-residuals (:func:`_logistic_residuals`: the exact log density in z for a
    uniform prior; a sloppy ridge costs it a few dozen steps, where BFGS stalled on the
    benchmark's), then Gauss-Newton steps on the whole log density (a non-uniform prior),
    each kept only if it raises the density; ``z0`` itself if nothing does. Without
    ``optimise``, ``z0``. The precision is the Gauss-Newton ``J^T J`` of the residuals
    minus the Hessian of the log prior and of the log-Jacobian of ``to_u`` (``forward``:
    J by forward mode, else reverse)."""
    optimise, forward = settings
    problem = target.problem

    def r(z):
        return problem.residuals(problem.to_u(z))

    def rest(z):
        return (
            target.log_prior(problem.to_u(z)) + jnp.linalg.slogdet(jax.jacfwd(problem.to_u)(z))[1]
        )

    def precision(z):
        J = (jax.jacfwd if forward else jax.jacrev)(r)(z)
        return J.T @ J - jax.hessian(rest)(z)

    def better(z_new, z_old):
        return jnp.all(jnp.isfinite(z_new)) & (target(z_new) >= target(z_old))

    if optimise:
        lm = optx.least_squares(
            lambda z, _: jnp.concatenate([r(z), _logistic_residuals(z)]),
            optx.LevenbergMarquardt(rtol=1e-8, atol=1e-8),
            z0,
            max_steps=200,
            throw=False,
        )
        z0 = jnp.where(better(lm.value, z0), lm.value, z0)

        def newton(_, z):
            step = jnp.linalg.solve(precision(z), jax.grad(target)(z))
            return jnp.where(better(z + step, z), z + step, z)

        z0 = jax.lax.fori_loop(0, CENTRE_NEWTON_STEPS, newton, z0)
    return z0, precision(z0)


def _starts(target, init, chains: int, key, call) -> tuple[Array, Array, Array, np.ndarray]:
    """Starting points (chains, k) in z, their centre (k,) in z, the Laplace covariance
    (k, k) in z there (the initial inverse mass matrix) and the centre in u (k,)."""
    problem = target.problem
    k = len(problem.names)
    lower, upper = np.asarray(problem.lower, dtype=float), np.asarray(problem.upper, dtype=float)
    given = None
    if init is None:
        z_c = jnp.asarray(problem.to_z(jnp.asarray(problem.u0, dtype=float)), dtype=float)
    else:
        if hasattr(init, "params") and hasattr(init, "coordinate"):  # a least-squares FitResult
            given = _fitted_u(init, problem.names, lower, upper)
        else:
            given = np.asarray(init, dtype=float)
        if given.shape not in ((k,), (chains, k)):
            raise ValueError(
                f"init must be a point (k={k},) or one per chain ({chains}, {k}) in the fitted coordinate, got shape {given.shape}"
            )
        if not (np.all(np.isfinite(given)) and np.all(given > lower) and np.all(given < upper)):
            raise ValueError(
                "init: every start must lie strictly inside the bounds (lower, upper) of the fitted coordinate"
            )
        z_c = jnp.asarray(problem.to_z(jnp.asarray(given.reshape(-1, k).mean(axis=0))), dtype=float)
    try:
        z_c, precision = call(_centre, (init is None, True), target, z_c)
    except TypeError:  # residuals with a reverse-only (custom_vjp) derivative
        z_c, precision = call(_centre, (init is None, False), target, z_c)
    cov = _covariance(np.asarray(precision, dtype=float))
    if given is not None and given.ndim == 2:
        return (
            jnp.asarray(jax.vmap(problem.to_z)(jnp.asarray(given)), dtype=float),
            z_c,
            cov,
            given.mean(axis=0),
        )
    z = z_c + jax.random.normal(key, (chains, k), dtype=float) @ jnp.linalg.cholesky(cov).T
    return z, z_c, cov, np.asarray(problem.to_u(z_c), dtype=float)


def _fitted_u(result, names, lower, upper) -> np.ndarray:
    """The optimum of a least-squares result (``params`` by name, ``coordinate`` "log" or
    "linear") in u, kept 1e-6 of the range inside the bounds (an optimum at a bound)."""
    missing = [n for n in names if n not in result.params]
    if missing:
        raise ValueError(f"init: the fit result has no value of {', '.join(missing)}")
    u = np.array(
        [
            math.log(result.params[n])
            if result.coordinate.get(n, "log") == "log"
            else result.params[n]
            for n in names
        ],
        dtype=float,
    )
    span = upper - lower
    return np.clip(u, lower + 1e-6 * span, upper - 1e-6 * span)


def _covariance(precision: np.ndarray) -> Array:
    """Inverse of a (symmetrised) precision, its variances capped at ``MAX_START_SD_Z**2``
    (eigenvalues floored); a non-finite precision gives sd 0.5 in every z."""
    k = precision.shape[0]
    if not np.all(np.isfinite(precision)):
        return 0.25 * jnp.eye(k)
    lam, vec = np.linalg.eigh(0.5 * (precision + precision.T))
    lam = np.maximum(lam, 1.0 / MAX_START_SD_Z**2)
    return jnp.asarray((vec / lam) @ vec.T)
