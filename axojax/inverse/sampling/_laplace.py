"""Where a posterior's chains start: a least-squares fit's optimum (given, or
:func:`fitted_init`'s fit of :data:`POSTERIOR_STARTS` starts), the maximum of the log
density, or a given point; the Laplace approximation there (its covariance: the
spread of the starts and the whitening of the sampled coordinates), and that
approximation as a result of its own (:class:`Laplace`: the fast answer, reported before
sampling starts, and compared with the draws once they exist)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from jaxtyping import Array, Float

from ..fitting.least_squares import least_squares
from ..problem import Problem
from ._densities import ScaledSigmas

Z90 = 1.6448536269514722
"""The standard normal's 95 % quantile: a normal's 90 % interval is mean +- Z90 sd."""
CENTRE_NEWTON_STEPS = 3
"""Gauss-Newton steps on the whole log density after Levenberg-Marquardt (a non-uniform
prior)."""
MAX_START_SD_Z = 2.0
"""Widest start spread in z: about the logistic prior's own width (pi / sqrt 3)."""
POSTERIOR_STARTS = 16
"""Starts of the least-squares fit a posterior of an axojax :class:`~axojax.inverse.Problem`
starts from when given no ``init`` (:func:`fitted_init`; ``axojax fit --posterior``'s fit
too): the draws explore the optimum's mode only, so a local optimum gives a wrong
posterior. On the bundled human sperm (p, ks) 4 of 32 starts reach the best loss, 181.8
(p 1034, ks 5.0e7), the rest a local one (225.0 at p 405, ks 2.9e4 and others): 4 starts
miss it, 16 find it."""


def fitted_init(problem, init: Any, progress: bool = False) -> Any:
    """``init`` as a sampler starts from it: when None and ``problem`` is an axojax
    :class:`~axojax.inverse.Problem` (or :class:`~axojax.inverse.ScaledSigmas` of one:
    sigmas scaled alike move no optimum), the best of a :data:`POSTERIOR_STARTS`-start
    least-squares fit (Levenberg-Marquardt, the design's seed 0: the fit ``axojax fit
    --posterior`` samples from); else ``init`` itself (None: another
    :class:`~axojax.inverse.InverseProblem`'s chains start at the posterior mode found
    from its ``u0``)."""
    while isinstance(problem, ScaledSigmas):
        problem = problem.problem
    if init is not None or not isinstance(problem, Problem):
        return init
    return least_squares(problem, "lm", starts=POSTERIOR_STARTS, progress=progress)


def _logistic_residuals(z: Float[Array, " k"]) -> Float[Array, " k"]:
    """Pseudo-residuals ``q`` of the logistic map's log-Jacobian: ``-|q|^2 / 2`` equals
    ``sum(log sigmoid(z) + log sigmoid(-z)) + k log 4`` exactly (``q`` smooth, ``q ~ z / sqrt 2``
    near 0), so ``-|(r, q)|^2 / 2`` is the log density in z of a uniform prior up to a constant."""
    excess = jnp.logaddexp(0.0, z) + jnp.logaddexp(0.0, -z) - jnp.log(4.0)  # >= 0, ~ z^2 / 4 at 0
    return jnp.sign(z) * jnp.sqrt(2.0 * jnp.maximum(excess, 0.0))


def centre(settings, target, z0):
    """The centre of the starts and the Laplace precision (k, k) in z there, in one
    program: with ``optimise``, the maximum of the log density from ``z0``:
    Levenberg-Marquardt (optimistix) on the residuals and the logistic map's
    pseudo-residuals (:func:`_logistic_residuals`: the exact log density in z for a
    uniform prior; a sloppy ridge costs it a few dozen steps, where BFGS stalled on the
    benchmark's), then Gauss-Newton steps on the whole log density (a non-uniform prior),
    each kept only if it raises the density; ``z0`` itself if nothing does. Without
    ``optimise``, ``z0``. The precision is the Gauss-Newton ``J^T J`` of the residuals
    minus the Hessian of the log prior and of the log-Jacobian of ``to_u`` (``forward``:
    J by forward mode, else reverse). Also the precision in u (the Laplace approximation
    reported, :class:`Laplace`): ``J_u^T J_u`` minus the log prior's Hessian in u, where
    ``J_u = J (du/dz)^-1``, the same Jacobian."""
    optimise, forward = settings
    problem = target.problem
    r, rest = target.split()

    def precisions(z):
        J = (jax.jacfwd if forward else jax.jacrev)(r)(z)
        J_u = J @ jnp.linalg.inv(jax.jacfwd(problem.to_u)(z))
        u = problem.to_u(z)
        return J.T @ J - jax.hessian(rest)(z), J_u.T @ J_u - jax.hessian(target.log_prior)(u)

    def precision(z):
        return precisions(z)[0]

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
    return z0, *precisions(z0)


def chain_starts(
    target, init, chains: int, key, call
) -> tuple[Array, Array, Array, np.ndarray, Any]:
    """Starting points (chains, k) in z, their centre (k,) in z, the Laplace covariance
    (k, k) in z there (the initial inverse mass matrix), the centre in u (k,) and the
    precision (k, k) in u there (:func:`laplace_of`)."""
    problem = target.problem
    k = len(problem.names)
    lower, upper = np.asarray(problem.lower, dtype=float), np.asarray(problem.upper, dtype=float)
    given = None
    if init is None:
        z_c = jnp.asarray(problem.to_z(jnp.asarray(problem.u0, dtype=float)), dtype=float)
    else:
        if hasattr(init, "params") and hasattr(init, "coordinate"):  # a least-squares FitResult
            given = fitted_u(init, problem.names, lower, upper)
        else:
            given = np.asarray(init, dtype=float)
        if given.shape not in ((k,), (chains, k)):
            raise ValueError(
                f"init must be a point (k={k},) or one per chain ({chains}, {k}) in the fitted "
                f"coordinate, got shape {given.shape}"
            )
        if not (np.all(np.isfinite(given)) and np.all(given > lower) and np.all(given < upper)):
            raise ValueError(
                "init: every start must lie strictly inside the bounds (lower, upper) of the fitted coordinate"
            )
        z_c = jnp.asarray(problem.to_z(jnp.asarray(given.reshape(-1, k).mean(axis=0))), dtype=float)
    try:
        z_c, precision, precision_u = call(centre, (init is None, True), target, z_c)
    except TypeError:  # residuals with a reverse-only (custom_vjp) derivative
        z_c, precision, precision_u = call(centre, (init is None, False), target, z_c)
    cov = covariance(np.asarray(precision, dtype=float))
    u_c = np.asarray(problem.to_u(z_c), dtype=float)
    precision_u = np.asarray(precision_u, dtype=float)
    if given is not None and given.ndim == 2:
        return (
            jnp.asarray(jax.vmap(problem.to_z)(jnp.asarray(given)), dtype=float),
            z_c,
            cov,
            given.mean(axis=0),
            (u_c, precision_u),
        )
    z = z_c + jax.random.normal(key, (chains, k), dtype=float) @ jnp.linalg.cholesky(cov).T
    return z, z_c, cov, u_c, (u_c, precision_u)


def fitted_u(result, names, lower, upper) -> np.ndarray:
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


def covariance(precision: np.ndarray) -> Array:
    """Inverse of a (symmetrised) precision, its variances capped at ``MAX_START_SD_Z**2``
    (eigenvalues floored); a non-finite precision gives sd 0.5 in every z."""
    k = precision.shape[0]
    if not np.all(np.isfinite(precision)):
        return 0.25 * jnp.eye(k)
    lam, vec = np.linalg.eigh(0.5 * (precision + precision.T))
    lam = np.maximum(lam, 1.0 / MAX_START_SD_Z**2)
    return jnp.asarray((vec / lam) @ vec.T)


@dataclasses.dataclass(frozen=True)
class Laplace:
    """The Laplace approximation of a posterior: a normal in the fitted coordinate u
    (log for positive parameters, linear for gamma) with mean ``centre_u`` (the least-squares
    optimum, or the posterior mode) and covariance ``cov_u``, the inverse of the
    Gauss-Newton ``J^T J`` of the residuals in u minus the log prior's Hessian (0 for the
    default uniform prior; the bounds are ignored). Costs k model evaluations, so it is
    reported before sampling; once draws exist :meth:`check` says how far they moved.

    Attributes:
        names: the k free parameters.
        centre_u: (k,) the centre, in u.
        cov_u: (k, k) the covariance in u; a direction the data do not constrain
            (``J^T J`` singular) gives its parameters an infinite sd.
        log_coordinate: per name, whether u is the natural log of the value.
    """

    names: tuple[str, ...]
    centre_u: np.ndarray
    cov_u: np.ndarray
    log_coordinate: dict[str, bool]

    @property
    def sd_u(self) -> dict[str, float]:
        """Per name, the sd in u (for a log coordinate: the relative sd of the value)."""
        return {n: float(math.sqrt(max(v, 0.0))) for n, v in zip(self.names, np.diag(self.cov_u))}

    def _value(self, name: str, u: float) -> float:
        return float(math.exp(u)) if self.log_coordinate[name] else float(u)

    def quantiles(self) -> tuple[dict[str, float], dict[str, float], dict[str, float]]:
        """Per name, the 5 %, 50 % and 95 % quantiles of the value (normal in u, mapped);
        NaN for the outer two where the sd is infinite."""
        sd = self.sd_u

        def at(z: float) -> dict[str, float]:
            return {
                n: self._value(n, c + z * sd[n] if z else c)
                if z == 0 or math.isfinite(sd[n])
                else math.nan
                for n, c in zip(self.names, self.centre_u)
            }

        return at(-Z90), at(0.0), at(Z90)

    def sd(self) -> dict[str, float]:
        """Per name, the sd of the value to first order (value x sd_u for a log coordinate)."""
        return {
            n: (math.exp(c) * self.sd_u[n] if self.log_coordinate[n] else self.sd_u[n])
            for n, c in zip(self.names, self.centre_u)
        }

    def check(self, mean_u: Mapping[str, float], sd_u: Mapping[str, float]) -> dict[str, dict]:
        """How far draws (their mean and sd in u, per name) moved from this approximation:
        ``sd_ratio`` (posterior sd / Laplace sd; near 1 where the approximation holds, below
        1 where the bounds or a curved ridge narrow the posterior, above where the ridge is
        longer than its curvature says) and ``shift`` (posterior mean - centre, in Laplace sds)."""
        lap = self.sd_u
        ratio, shift = {}, {}
        for n, c in zip(self.names, self.centre_u):
            s = lap[n]
            ok = math.isfinite(s) and s > 0
            ratio[n] = float(sd_u[n] / s) if ok else math.nan
            shift[n] = float((mean_u[n] - c) / s) if ok else math.nan
        return {"sd_ratio": ratio, "shift": shift}

    def to_json(self) -> dict[str, Any]:
        """``centre`` (values), ``sd`` (first order), ``q05``, ``q95``, ``sd_u`` and the
        correlation matrix ``corr`` (rows in ``names`` order)."""
        q05, q50, q95 = self.quantiles()
        sd = np.sqrt(np.maximum(np.diag(self.cov_u), 0.0))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = self.cov_u / np.outer(sd, sd)
        return {
            "names": list(self.names),
            "centre": q50,
            "sd": self.sd(),
            "q05": q05,
            "q95": q95,
            "sd_u": self.sd_u,
            "corr": [[float(x) if np.isfinite(x) else None for x in row] for row in corr],
        }

    def to_dict(self) -> dict[str, Any]:
        """Everything :meth:`from_dict` needs (lists; JSON-safe where finite)."""
        return {
            "names": list(self.names),
            "centre_u": [float(x) for x in self.centre_u],
            "cov_u": [[float(x) for x in row] for row in self.cov_u],
            "log_coordinate": dict(self.log_coordinate),
        }

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Laplace:
        return cls(
            names=tuple(d["names"]),
            centre_u=np.asarray(d["centre_u"], dtype=float),
            cov_u=np.asarray(d["cov_u"], dtype=float),
            log_coordinate=dict(d["log_coordinate"]),
        )


def laplace_of(problem, names, u_c: np.ndarray, precision_u: np.ndarray) -> Laplace:
    """:class:`Laplace` from a centre (k,) and precision (k, k) in u: the covariance by
    eigen-decomposition of the precision scaled to a unit diagonal (so that coordinates of
    very different scales, e.g. a coefficient of 1e5 in a linear coordinate beside a log
    one, are judged alike), directions of scaled precision <= 1e-12 x its largest (or not
    finite) giving their parameters an infinite variance; log coordinates where the
    problem's value at the centre is exp(u)."""
    k = len(names)
    if np.all(np.isfinite(precision_u)):
        sym = 0.5 * (precision_u + precision_u.T)
        diag = np.diag(sym)
        d = np.where(diag > 0, 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0)), 1.0)
        lam, vec = np.linalg.eigh(d[:, None] * sym * d[None, :])
        good = lam > 1e-12 * max(float(np.max(np.abs(lam))), 1e-300)
        cov = d[:, None] * ((vec[:, good] / lam[good]) @ vec[:, good].T) * d[None, :]
        loose = np.any(np.abs(vec[:, ~good]) > 1e-8, axis=1) | (diag <= 0)
        cov[loose, :] = np.inf
        cov[:, loose] = np.inf
    else:
        cov = np.full((k, k), np.inf)
    values = problem.values(jnp.asarray(u_c, dtype=float))
    log = {}
    for n, u in zip(names, u_c):
        v = float(values[n]) if n in values else math.nan
        log[n] = bool(v > 0 and math.isclose(math.log(v), float(u), rel_tol=1e-9, abs_tol=1e-9))
    return Laplace(tuple(names), np.asarray(u_c, dtype=float), cov, log)
