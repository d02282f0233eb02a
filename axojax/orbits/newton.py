"""Damped Newton iteration on the orbit equations, differentiable by the implicit
function theorem.

Newton: ``x <- x - lambda J^{-1} R(x)`` with the exact Jacobian, one LU per iteration,
and Deuflhard's natural monotonicity test for the damping ``lambda`` (the simplified
correction ``J^{-1} R(x - lambda dx)``, reusing the LU, must shrink by ``1 - lambda/4``;
otherwise ``lambda`` halves). Converged when the scaled correction
``max(|dX| / |X|, |domega| / |omega|)`` falls below ``rtol``.

Derivative: at the solution ``R(x*, theta) = 0``, so
``dx* = -J^{-1} (dR/dtheta) dtheta`` (implicit function theorem). The rule is a
``jax.custom_jvp`` whose linear solve is ``jax.lax.custom_linear_solve`` with the
factorisation of J and its transpose: forward mode costs one solve per tangent, reverse mode (by JAX's
transposition of the rule) one transposed solve per cotangent; the Newton iterations are
never differentiated.
"""

from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp


def _scaled(dx, x):
    dX, dw = dx[:-1], dx[-1]
    X, w = x[:-1], x[-1]
    return jnp.maximum(jnp.linalg.norm(dX) / jnp.maximum(jnp.linalg.norm(X), 1e-300), jnp.abs(dw) / jnp.maximum(jnp.abs(w), 1e-300))


def newton(residual: Callable, factor: Callable, x0, *, rtol: float, max_steps: int, min_damping: float = 1.0 / 64):
    """Solve residual(x) = 0 from x0; ``factor(x)`` returns an object whose ``solve(r)``
    applies the inverse Jacobian at x. Returns (x, converged (bool), steps (int), last
    scaled correction)."""

    def cond(state):
        x, k, done, err = state
        return (~done) & (k < max_steps) & jnp.isfinite(err)

    def body(state):
        x, k, _, _ = state
        lu = factor(x)
        dx = lu.solve(residual(x))
        err = _scaled(dx, x)
        e0 = jnp.linalg.norm(dx / jnp.maximum(jnp.abs(x), 1e-12 * jnp.linalg.norm(x)))

        def ls_cond(s):
            lam, ok = s
            return (~ok) & (lam > min_damping)

        def ls_body(s):
            lam, _ = s
            lam = lam / 2
            return lam, _monotone(lam)

        def _monotone(lam):
            d1 = lu.solve(residual(x - lam * dx))
            e1 = jnp.linalg.norm(d1 / jnp.maximum(jnp.abs(x), 1e-12 * jnp.linalg.norm(x)))
            return jnp.isfinite(e1) & (e1 <= (1 - lam / 4) * e0)

        small = err < 1e-3  # near the root Newton converges quadratically: take the full step
        lam, _ = jax.lax.while_loop(ls_cond, ls_body, (1.0, small | _monotone(1.0)))
        x = x - lam * dx
        return x, k + 1, (err < rtol) & (lam == 1.0), err

    x, k, done, err = jax.lax.while_loop(cond, body, (x0, 0, jnp.array(False), jnp.array(1e300)))
    ok = done & jnp.all(jnp.isfinite(x))
    return x, ok, k, err


def implicit_solve(make: Callable, factor: Callable, theta, x0, aux, *, rtol: float, max_steps: int, fallback=None):
    """x* with ``make(theta).residual(x*, aux) = 0`` found by :func:`newton` from ``x0``,
    differentiable in ``theta`` (a pytree) by the implicit function theorem.

    Args:
        make: theta -> problem with ``residual(x, aux)``.
        factor: (problem, x, aux) -> the Jacobian's factorisation (``solve`` and
            ``solve_transpose``), e.g. :class:`axojax.orbits.linear.BorderedSolver`.
        theta: differentiable parameters.
        x0, aux: start and fixed data (not differentiated).
        fallback: finite value returned where Newton fails (default x0), so that
            failed points give finite values and zero derivatives (a fit can step
            back from them) instead of NaN.

    Returns:
        (x*, info) with info = (converged 0/1, Newton steps, last scaled correction) as floats.
    """
    fallback = x0 if fallback is None else fallback

    @jax.custom_jvp
    def solve(theta, x0, aux, fallback):
        prob = make(theta)
        x, ok, k, err = newton(lambda x: prob.residual(x, aux), lambda x: factor(prob, x, aux), x0, rtol=rtol, max_steps=max_steps)
        return jnp.where(ok, x, fallback), jnp.stack([ok.astype(float), k.astype(float), err])

    @solve.defjvp
    def solve_jvp(primals, tangents):
        theta, x0, aux, fallback = primals
        dtheta = tangents[0]  # the start and the fixed data are not differentiated
        x, info = solve(theta, x0, aux, fallback)
        ok = info[0] > 0.5
        prob = make(theta)
        lu = factor(prob, x, aux)
        _, dR = jax.jvp(lambda th: make(th).residual(x, aux), (theta,), (dtheta,))
        matvec = lambda v: jax.jvp(lambda y: prob.residual(y, aux), (x,), (v,))[1]
        # Masked solves: a failed point has zero derivative, never NaN (also in reverse mode).
        dx = -jax.lax.custom_linear_solve(
            matvec, dR,
            solve=lambda _, r: jnp.where(ok, lu.solve(r), 0.0),
            transpose_solve=lambda _, r: jnp.where(ok, lu.solve_transpose(r), 0.0),
        )
        return (x, info), (dx, jnp.zeros_like(info))

    sg = jax.lax.stop_gradient
    return solve(theta, sg(x0), sg(aux), sg(fallback))
