"""Hopf points: the dynein force p at which the dominant mode crosses Re lambda = 0.

``critical_force`` brackets the first crossing by geometric steps in p from a stable
start, then runs a safeguarded Newton iteration (Newton steps with the exact derivative
of :func:`axojax.eigen.dominant.dominant_eigenpair`, bisection whenever a step leaves
the bracket). Everything is ``lax.while_loop``: jit- and vmap-able. The root is wrapped
in ``jax.lax.custom_root``, so p_c itself is differentiable in every other parameter by
the implicit function theorem (dp_c/dtheta = -(dRe lambda/dtheta) / (dRe lambda/dp)).
"""

from __future__ import annotations

import math
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from . import results
from .eigen.mode import DEFAULT_SOLVER, for_base
from .eigen.solvers import AbstractEigenSolver
from .models.section import Model
from .params import Params, require_scalars, valid
from .results import RESULTS
from .units import Units


class Critical(eqx.Module):
    """A Hopf (or divergence-onset) point.

    Attributes:
        p: critical dimensionless force p_c (inf if none below ``p_max``).
        eigenvalue: dominant eigenvalue at p_c (Re ~ 0), Im >= 0.
        found: whether a crossing was bracketed.
        result: :class:`axojax.results.RESULTS` item: ``successful``, ``no_crossing``
            (none below ``p_max``: ``p = inf``), ``max_steps_reached`` (the Newton
            iteration ran out of ``max_iter`` steps before ``rtol``: ``p`` is its last
            iterate, inside the bracket) or ``invalid_params`` (traced parameters out of
            range: ``p`` is NaN).
    """

    p: Float[Array, ""]
    eigenvalue: Array
    found: Array
    result: RESULTS = eqx.field(default_factory=lambda: RESULTS.successful)

    def frequency_hz(self, units: Units = Units()) -> Float[Array, "..."]:
        """Onset frequency |Im lambda| / (2 pi tau)."""
        return jnp.abs(jnp.imag(self.eigenvalue)) / (2 * jnp.pi * units.tau_s)

    @property
    def message(self) -> str:
        """``result``'s message on one line (:func:`axojax.results.message`)."""
        return results.message(self.result)

    def to_json(self, units: Units = Units()) -> dict[str, Any]:
        """Plain-Python summary of one point (an entry of ``axojax critical --json``):
        ``{"p": p_c, "frequency_hz": f_c}`` (Hz), both ``None`` without a crossing."""
        found = bool(self.found)
        return results.jsonable(
            {
                "p": float(self.p) if found else None,
                "frequency_hz": float(self.frequency_hz(units)) if found else None,
            }
        )


def _eig_at(model: Model, params: Params, p, solver: AbstractEigenSolver):
    # an unclamped base's rigid-body zero eigenvalues are no onset: for_base moves them
    return for_base(model, solver).eigenpair(model, params.replace(p=p))[0]


def _bracket(g, p_start, growth_factor, max_steps):
    """First geometric step (from p = 0) where g > 0: returns (lo, hi, found)."""

    def cond(state):
        lo, hi, ghi, k = state
        return (ghi <= 0) & (k < max_steps)

    def body(state):
        lo, hi, ghi, k = state
        new = hi * growth_factor
        return hi, new, g(new), k + 1

    lo, hi, ghi, _ = jax.lax.while_loop(cond, body, (jnp.zeros(()), p_start, g(p_start), 0))
    return lo, hi, ghi > 0


def _safeguarded_newton(g, lo, hi, rtol, max_iter):
    """Root of g in [lo, hi] with g(lo) <= 0 < g(hi), and whether it met ``rtol``."""
    dg = lambda x: jax.jvp(g, (x,), (jnp.ones_like(x),))

    def cond(state):
        lo, hi, x, k, done = state
        return (~done) & (k < max_iter)

    def body(state):
        lo, hi, x, k, _ = state
        gx, slope = dg(x)
        lo = jnp.where(gx <= 0, x, lo)
        hi = jnp.where(gx > 0, x, hi)
        newton = x - gx / slope
        ok = jnp.isfinite(newton) & (newton > lo) & (newton < hi)
        nxt = jnp.where(ok, newton, 0.5 * (lo + hi))
        done = (jnp.abs(nxt - x) <= rtol * jnp.abs(x)) | (hi - lo <= rtol * hi)
        return lo, hi, nxt, k + 1, done

    x0 = 0.5 * (lo + hi)
    _, _, x, _, done = jax.lax.while_loop(cond, body, (lo, hi, x0, 0, jnp.array(False)))
    return x, done.astype(float)  # a float: custom_root's aux gets a tangent (bool has none)


def _critical_force_impl(
    model: Model,
    params: Params,
    *,
    p_start: float = 10.0,
    growth_factor: float = 1.25,
    p_max: float = 1e7,
    rtol: float = 1e-12,
    max_iter: int = 100,
    solver: AbstractEigenSolver = DEFAULT_SOLVER,
    throw: bool = False,
) -> Critical:
    """The first p (from 0) at which the dominant eigenvalue's real part turns positive.

    Args:
        model: static model.
        params: parameters; ``params.p`` is ignored.
        p_start: first trial force of the bracketing search.
        growth_factor: ratio of successive trial forces (smaller finds earlier crossings
            of re-entrant boundaries more reliably).
        p_max: give up (``found = False``, ``p = inf``) above this force.
        rtol: relative tolerance on p_c.
        max_iter: Newton/bisection steps; running out is reported
            (``result = max_steps_reached``).
        solver: dominant-eigenpair solver (:mod:`axojax.eigen.solvers`).
        throw: raise (at run time, also under ``jit``) when ``result`` is a failure
            (``max_steps_reached``, ``invalid_params``); ``no_crossing`` is an answer,
            not a failure. Default False, as everywhere (:mod:`axojax.results`): read
            ``result``.

    Returns:
        :class:`Critical`; ``p`` is differentiable in every other field of ``params``.
    """
    max_steps = int(math.ceil(math.log(p_max / p_start) / math.log(growth_factor))) + 1

    def g(p, prm):
        return jnp.real(_eig_at(model, prm, p, solver))

    lo, hi, found = _bracket(
        lambda p: g(p, params), jnp.asarray(p_start, float), growth_factor, max_steps
    )

    def solve(f, _guess):
        return _safeguarded_newton(f, lo, hi, rtol, max_iter)

    def tangent_solve(linear_g, y):
        return y / linear_g(jnp.ones_like(y))

    p_c, converged = jax.lax.custom_root(
        lambda p: g(p, params), 0.5 * (lo + hi), solve, tangent_solve, has_aux=True
    )
    lam = _eig_at(model, params, p_c, solver)
    ok = valid(params.replace(p=0.0))
    p_c = jnp.where(ok, jnp.where(found, p_c, jnp.inf), jnp.nan)
    lam = jnp.where(ok, lam, jnp.nan + 0j)
    result = RESULTS.where(
        ok,
        RESULTS.where(
            found,
            RESULTS.where(converged > 0.5, RESULTS.successful, RESULTS.max_steps_reached),
            RESULTS.no_crossing,
        ),
        RESULTS.invalid_params,
    )
    crit = Critical(p=p_c, eigenvalue=lam, found=found & ok, result=result)
    if throw:
        crit = result.error_if(
            crit, (result != RESULTS.successful) & (result != RESULTS.no_crossing)
        )
    return crit


critical_force_impl = (
    _critical_force_impl  # the traceable entry point (no validation, no jit of its own)
)
_critical_force_jit = jax.jit(
    _critical_force_impl,
    static_argnums=0,
    static_argnames=("p_start", "growth_factor", "p_max", "rtol", "max_iter", "solver", "throw"),
)


def critical_force(model: Model, params: Params, **options) -> Critical:
    require_scalars(params, "critical_force")
    return _critical_force_jit(model, params.validate(), **options)


critical_force.__doc__ = _critical_force_impl.__doc__
