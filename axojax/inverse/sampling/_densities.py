"""What a sampler needs of an inverse problem (:class:`InverseProblem`), priors in the
fitted coordinate (:class:`NormalPrior`), a problem with rescaled sigmas
(:class:`ScaledSigmas`), and the log density actually sampled (:class:`LogDensity`, in z, and
:class:`Whitened`, in the coordinates whitened by the Laplace approximation), and the
reference density that gradient-free samplers temper from (:func:`log_reference`)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Protocol, runtime_checkable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float


@runtime_checkable
class InverseProblem(Protocol):
    """What :func:`posterior` needs of a problem (:class:`axojax.inverse.Problem` has it).

    Attributes:
        names: labels of the k fitted values.
        lower, upper: (k,) bounds in the fitted coordinate ``u`` (log for positive
            parameters, linear for gamma).
        u0: (k,) starting point in ``u``.
    Methods (all jax-traceable except ``values`` needs only be vmappable):
        residuals(u) -> (m,) normalised residuals;
        log_prior(u) -> () log prior density in ``u`` (0: uniform);
        to_u(z), to_z(u): the logistic map between z in R^k and u within the bounds;
        log_density(z) -> () = -1/2 |residuals(to_u(z))|^2 + log_prior(to_u(z)) + log|du/dz|;
        values(u) -> {name: dimensionless value}.
    """

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    u0: np.ndarray

    def residuals(self, u: Float[Array, " k"]) -> Float[Array, " m"]: ...

    def log_prior(self, u: Float[Array, " k"]) -> Float[Array, ""]: ...

    def to_u(self, z: Float[Array, " k"]) -> Float[Array, " k"]: ...

    def to_z(self, u: Float[Array, " k"]) -> Float[Array, " k"]: ...

    def log_density(self, z: Float[Array, " k"]) -> Float[Array, ""]: ...

    def values(self, u: Float[Array, " k"]) -> Mapping[str, Float[Array, ""]]: ...


class NormalPrior(eqx.Module):
    """A log prior in ``u``: independent normals (``mean``, ``sd`` in the fitted
    coordinate, e.g. the natural log of ks) on the parameters at ``index``, uniform
    (within the bounds) on the others. Build it with :func:`normal_prior`."""

    index: tuple[int, ...] = eqx.field(static=True)
    mean: Float[Array, " j"]
    sd: Float[Array, " j"]

    def __call__(self, u: Float[Array, " k"]) -> Float[Array, ""]:
        return -0.5 * jnp.sum(((u[jnp.asarray(self.index)] - self.mean) / self.sd) ** 2)


def normal_prior(names: Sequence[str], spec: Mapping[str, tuple[float, float]]) -> NormalPrior:
    """:class:`NormalPrior` from ``{name: (mean_u, sd_u)}`` over the free parameters ``names``."""
    names = list(names)
    for name, (mu, sd) in spec.items():
        if name not in names:
            raise ValueError(
                f"prior: {name!r} is not a free parameter; choose from {', '.join(names)}"
            )
        if not (math.isfinite(mu) and math.isfinite(sd) and sd > 0):
            raise ValueError(f"prior: {name} needs a finite mean and sd > 0, got ({mu!r}, {sd!r})")
    return NormalPrior(
        index=tuple(names.index(n) for n in spec),
        mean=jnp.asarray([float(spec[n][0]) for n in spec]),
        sd=jnp.asarray([float(spec[n][1]) for n in spec]),
    )


class ScaledSigmas(eqx.Module):
    """``problem`` with every uncertainty (sigma) multiplied by ``factor``: residuals
    divided by it, the likelihood tempered by ``1 / factor**2``; prior, bounds and
    coordinates unchanged. An :class:`InverseProblem` that :func:`posterior` samples.

    The use: a model that misfits (chi^2/dof well above 1) gets a posterior too narrow
    for what its data say, because its width assumes the residuals are noise of the
    stated size. ``ScaledSigmas(problem, sqrt(chi2/dof))`` (the Birge ratio) rescales the
    noise to the observed misfit, as scipy's ``curve_fit`` does by default
    (``absolute_sigma=False``): a cruder but more honest width. ``factor`` is an array
    leaf, so posteriors of one problem with different factors share their compilation.
    """

    problem: Any
    factor: Float[Array, ""]

    def __init__(self, problem: InverseProblem, factor: float):
        if not (math.isfinite(float(factor)) and float(factor) > 0):
            raise ValueError(f"ScaledSigmas: factor must be a finite number > 0, got {factor!r}")
        self.problem = problem
        self.factor = jnp.asarray(float(factor))

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.problem.names)

    @property
    def lower(self) -> np.ndarray:
        return self.problem.lower

    @property
    def upper(self) -> np.ndarray:
        return self.problem.upper

    @property
    def u0(self) -> np.ndarray:
        return self.problem.u0

    def fingerprint(self) -> str:
        """The wrapped problem's fingerprint with the factor (``TypeError`` when the
        problem has none: :mod:`axojax.inverse.sampling._warm_cache`)."""
        from ..fingerprint import digest

        inner = getattr(self.problem, "fingerprint", None)
        if not callable(inner):
            raise TypeError("the wrapped problem has no fingerprint")
        return digest(("ScaledSigmas", inner(), self.factor))

    def residuals(self, u: Float[Array, " k"]) -> Float[Array, " m"]:
        return self.problem.residuals(u) / self.factor

    def log_prior(self, u: Float[Array, " k"]) -> Float[Array, ""]:
        return self.problem.log_prior(u)

    def to_u(self, z: Float[Array, " k"]) -> Float[Array, " k"]:
        return self.problem.to_u(z)

    def to_z(self, u: Float[Array, " k"]) -> Float[Array, " k"]:
        return self.problem.to_z(u)

    def log_density(self, z: Float[Array, " k"]) -> Float[Array, ""]:
        """-|residuals / factor|^2 / 2 + log prior(u) + log|du/dz| (one model evaluation)."""
        u = self.problem.to_u(z)
        log_jac = jnp.linalg.slogdet(jax.jacfwd(self.problem.to_u)(z))[1]
        return -0.5 * jnp.sum(self.residuals(u) ** 2) + self.problem.log_prior(u) + log_jac

    def values(self, u: Float[ArrayLike, " k"]) -> Mapping[str, Any]:
        """The wrapped problem's values (Python floats for :class:`Problem`)."""
        return self.problem.values(u)


class LogDensity(eqx.Module):
    """The log density sampled, in z: the problem's, with its prior replaced by ``prior``
    when given; NaN (a failed model evaluation) reads as -inf (a rejected proposal)."""

    problem: Any
    prior: Any = None

    def __call__(self, z: Float[Array, " k"]) -> Float[Array, ""]:
        lp = self.problem.log_density(z)
        if self.prior is not None:
            u = self.problem.to_u(z)
            lp = lp - self.problem.log_prior(u) + self.prior(u)
        return jnp.where(jnp.isnan(lp), -jnp.inf, lp)

    def log_prior(self, u: Float[Array, " k"]) -> Float[Array, ""]:
        return self.problem.log_prior(u) if self.prior is None else self.prior(u)

    def split(self):
        """``(r, rest)``: the problem's residuals ``r(z)`` and the rest of the log density
        (log prior and log-Jacobian of ``to_u``), ``self(z) = -|r(z)|^2 / 2 + rest(z)``:
        what Gauss-Newton steps on it need."""
        problem = self.problem

        def r(z):
            return problem.residuals(problem.to_u(z))

        def rest(z):
            u = problem.to_u(z)
            return self.log_prior(u) + jnp.linalg.slogdet(jax.jacfwd(problem.to_u)(z))[1]

        return r, rest


class Whitened(eqx.Module):
    """``target`` in whitened coordinates: ``w -> target(centre + chol @ w)`` (the
    constant log-Jacobian left out: it changes no ratio of densities). With a
    ``transport`` (a :class:`~axojax.inverse.sampling.transport.ProfileMap`), whitened after it:
    ``w -> y = centre + chol @ w -> z = transport.to_z(y)``, the log density in ``y``
    being ``target(z) + transport.log_det(y)`` (``centre`` and ``chol`` then in ``y``)."""

    target: LogDensity
    centre: Float[Array, " k"]
    chol: Float[Array, "k k"]
    transport: Any = None

    def __call__(self, w: Float[Array, " k"]) -> Float[Array, ""]:
        y = self.centre + self.chol @ w
        if self.transport is None:
            return self.target(y)
        lp = self.target(self.transport.to_z(y)) + self.transport.log_det(y)
        return jnp.where(jnp.isnan(lp), -jnp.inf, lp)

    def to_z(self, w: Float[Array, "*batch k"]) -> Float[Array, "*batch k"]:
        y = self.centre + w @ self.chol.T
        if self.transport is None:
            return y
        to_z = self.transport.to_z
        for _ in range(y.ndim - 1):
            to_z = jax.vmap(to_z)
        return to_z(y)

    def to_w(self, z: Float[Array, "*batch k"]) -> Float[Array, "*batch k"]:
        if self.transport is not None:
            to_y = self.transport.to_y
            for _ in range(z.ndim - 1):
                to_y = jax.vmap(to_y)
            z = to_y(z)
        return jax.scipy.linalg.solve_triangular(self.chol, (z - self.centre).T, lower=True).T


def log_reference(problem):
    """The reference log density in z, ``z -> log|du/dz|``: the uniform prior in u between
    the bounds (up to the box's volume), as a density in z. SMC and :class:`ModeMixture`
    temper from it; the rest of :class:`LogDensity` (the likelihood and the prior's departure
    from uniform) is the tempered part."""

    def log_ref(z: Float[Array, " k"]) -> Float[Array, ""]:
        return jnp.linalg.slogdet(jax.jacfwd(problem.to_u)(z))[1]

    return log_ref
