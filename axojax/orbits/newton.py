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

from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp


def _scaled(dx, x):
    dX, dw = dx[:-1], dx[-1]
    X, w = x[:-1], x[-1]
    return jnp.maximum(
        jnp.linalg.norm(dX) / jnp.maximum(jnp.linalg.norm(X), 1e-300),
        jnp.abs(dw) / jnp.maximum(jnp.abs(w), 1e-300),
    )


class Restart(NamedTuple):
    """A second start for :func:`newton`: where the first attempt has not converged
    within ``after`` steps (or its correction became non-finite, or it converged to a
    point ``accept`` refuses), Newton starts again from ``x`` with ``aux`` and a full
    budget of ``max_steps``. One traced loop does both attempts (a warm start and its
    cold fallback), so a program that uses it compiles one Newton iteration, not two.
    A non-finite ``x`` is no second start."""

    x: Any
    aux: Any
    fallback: Any
    after: int


def newton(
    residual: Callable,
    factor: Callable,
    x0,
    aux=None,
    *,
    rtol: float,
    max_steps: int,
    min_damping: float = 1.0 / 64,
    restart: Restart | None = None,
    accept: Callable | None = None,
):
    """Solve ``residual(x, aux) = 0`` from ``x0``; ``factor(x, aux)`` returns an object
    whose ``solve(r)`` applies the inverse Jacobian at x. With ``restart``: a second
    attempt from ``restart.x`` (see :class:`Restart`); ``accept(x)`` (default: any) says
    whether a converged point of the first attempt counts.

    Returns (x, aux, converged (bool), steps of both attempts (int), last scaled
    correction, restarted (bool)); ``aux`` is the one x solves with."""
    if restart is None:  # one attempt, one budget: the switch below is not traced
        restarted0, stop0 = jnp.array(True), max_steps
    else:
        restarted0 = ~jnp.all(jnp.isfinite(restart.x))  # a non-finite second start is none
        stop0 = min(int(restart.after), max_steps)

    def cond(state):
        x, a, k, done, err, restarted, stop = state
        return (~done) & (((k < stop) & jnp.isfinite(err)) | ~restarted)

    def body(state):
        x, a, k, _, err, restarted, stop = state
        if restart is not None:
            switch = ~restarted & (
                (k >= stop) | ~jnp.isfinite(err)
            )  # the first attempt failed: start again
            x = jnp.where(switch, restart.x, x)
            a = jax.tree_util.tree_map(lambda u, v: jnp.where(switch, u, v), restart.aux, a)
            stop = jnp.where(switch, k + max_steps, stop)
            restarted = restarted | switch
        lu = factor(x, a)
        dx = lu.solve(residual(x, a))
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
            d1 = lu.solve(residual(x - lam * dx, a))
            e1 = jnp.linalg.norm(d1 / jnp.maximum(jnp.abs(x), 1e-12 * jnp.linalg.norm(x)))
            return jnp.isfinite(e1) & (e1 <= (1 - lam / 4) * e0)

        small = err < 1e-3  # near the root Newton converges quadratically: take the full step
        lam, _ = jax.lax.while_loop(ls_cond, ls_body, (1.0, small | _monotone(1.0)))
        x = x - lam * dx
        done = (err < rtol) & (lam == 1.0)
        if (
            restart is not None and accept is not None
        ):  # a refused point of the first attempt: start again (err NaN)
            refused = done & ~restarted & ~accept(x)
            done, err = done & ~refused, jnp.where(refused, jnp.nan, err)
        return x, a, k + 1, done, err, restarted, stop

    state = (
        x0,
        aux,
        jnp.array(0),
        jnp.array(False),
        jnp.array(1e300),
        restarted0,
        jnp.array(stop0),
    )
    x, a, k, done, err, restarted, _ = jax.lax.while_loop(cond, body, state)
    ok = done & jnp.all(jnp.isfinite(x))
    return x, a, ok, k, err, restarted & (restart is not None)


def implicit_solve(
    make: Callable,
    factor: Callable,
    theta,
    x0,
    aux,
    *,
    rtol: float,
    max_steps: int,
    fallback=None,
    restart: Restart | None = None,
    accept: Callable | None = None,
):
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
        restart: a second attempt (:class:`Restart`; its ``fallback`` replaces
            ``fallback`` once it is taken).
        accept: (problem, x) -> bool: whether a converged point of the first attempt
            counts (see :func:`newton`).

    Returns:
        (x*, info, aux*) with info = (converged 0/1, Newton steps, last scaled correction,
        restarted 0/1) as floats and aux* the fixed data x* solves with (``aux``, or
        ``restart.aux`` after a restart).
    """
    fallback = x0 if fallback is None else fallback

    after = None if restart is None else int(restart.after)  # static; the arrays are data

    @jax.custom_jvp
    def solve(theta, x0, aux, fallback, second):
        prob = make(theta)
        restart = None if second is None else Restart(*second, after)
        ok_fn = None if accept is None else (lambda x: accept(prob, x))
        x, a, ok, k, err, restarted = newton(
            prob.residual,
            lambda x, a: factor(prob, x, a),
            x0,
            aux,
            rtol=rtol,
            max_steps=max_steps,
            restart=restart,
            accept=ok_fn,
        )
        fb = fallback if restart is None else jnp.where(restarted, restart.fallback, fallback)
        return (
            jnp.where(ok, x, fb),
            jnp.stack([ok.astype(float), k.astype(float), err, restarted.astype(float)]),
            a,
        )

    @solve.defjvp
    def solve_jvp(primals, tangents):
        theta = primals[0]
        dtheta = tangents[0]  # the start and the fixed data are not differentiated
        x, info, aux = solve(*primals)
        ok = info[0] > 0.5
        prob = make(theta)
        lu = factor(prob, x, aux)
        _, dR = jax.jvp(lambda th: make(th).residual(x, aux), (theta,), (dtheta,))
        matvec = lambda v: jax.jvp(lambda y: prob.residual(y, aux), (x,), (v,))[1]
        # Masked solves: a failed point has zero derivative, never NaN (also in reverse mode).
        dx = -jax.lax.custom_linear_solve(
            matvec,
            dR,
            solve=lambda _, r: jnp.where(ok, lu.solve(r), 0.0),
            transpose_solve=lambda _, r: jnp.where(ok, lu.solve_transpose(r), 0.0),
        )
        return (x, info, aux), (
            dx,
            jnp.zeros_like(info),
            jax.tree_util.tree_map(jnp.zeros_like, aux),
        )

    sg = jax.lax.stop_gradient
    second = None if restart is None else sg((restart.x, restart.aux, restart.fallback))
    return solve(theta, sg(x0), sg(aux), sg(fallback), second)
