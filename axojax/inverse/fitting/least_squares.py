"""Least-squares solvers of an inverse :class:`~axojax.inverse.Problem`, as objects.

Each solver minimises ``0.5 |residuals(u(z))|^2`` over the unconstrained coordinate z
(``u = lower + (upper - lower) sigmoid(z)``, :meth:`Problem.to_u`), from one start:

- :class:`LevenbergMarquardt` (the default): ``optimistix.least_squares`` with
  ``optimistix.LevenbergMarquardt``; the Jacobian is exact (forward mode through the
  dominant eigenpair's derivative rule). These problems have a handful of unknowns and
  residuals, so a damped Gauss-Newton step converges in a few iterations where a
  first-order method needs many. With limit-cycle targets each evaluation's orbit is
  warm-started from the last accepted iterate's (:func:`warm_least_squares`:
  optimistix's step-by-step interface in a ``lax.while_loop`` that carries the orbits);
  ``warm_start=False`` starts every orbit from the Hopf normal form.
- :class:`LBFGS`: ``optax.lbfgs`` with a zoom line search on the loss.
- :class:`Adam`: ``optax.adam`` for a fixed number of steps (robust, slow).

:func:`least_squares` runs a solver from several starts (the problem's start, then a
scrambled Sobol design of the bounded box, :meth:`Problem.start_design`), keeps the best
and reports it (:class:`~axojax.inverse.FitResult`).
"""

from __future__ import annotations

import abc
import math
import time
from collections.abc import Callable
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optax
import optimistix as optx
from jaxtyping import Array, PyTree

from ..._progress import progress as progress_bar
from ...results import RESULTS
from ..problem import Problem
from .marquardt import STANDARD_ERRORS, StatisticalLevenbergMarquardt, column_scales
from .report import FitResult, build_report

FIT_STARTS = 4
"""Starts of a fit (the given point plus a Sobol design in the bounds) unless told:
``ax.fit``'s, :func:`least_squares`'s and ``axojax fit``'s default."""


class LeastSquaresSolver(eqx.Module):
    """Minimises a problem's loss from one start in z."""

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def compile(self, problem: Problem):
        """A jitted ``z0 (k,) -> (z, loss, steps, |grad_z|, result)``; ``result`` an
        :class:`axojax.results.RESULTS` item (``successful`` when the solver's own
        termination test passed)."""


class LevenbergMarquardt(LeastSquaresSolver):
    """Levenberg-Marquardt (optimistix) with exact Jacobians.

    Attributes:
        rtol, atol: optimistix's Cauchy termination: stop when the step in z and the
            change in the residuals are both below ``atol + rtol * size`` (defaults: far
            below any standard error these fits can have).
        max_steps: iterations per start.
        warm_start: for problems with limit-cycle targets, start each evaluation's
            orbits from those of the last accepted iterate (:func:`warm_least_squares`)
            instead of the Hopf normal form; the same iterates up to the orbit
            solver's tolerance, fewer Newton steps. False: every orbit cold.
        scaled: for problems with limit-cycle targets, scale the unknowns by the norms
            of their Jacobian's columns at the start (Marquardt's scaling, as a change of
            variables: :func:`~axojax.inverse.fitting.marquardt.column_scales`).
        standard_errors: for problems with limit-cycle targets, also stop when the
            Gauss-Newton step is within this many standard errors, and widen the trust
            region as Moré does
            (:class:`~axojax.inverse.fitting.marquardt.StatisticalLevenbergMarquardt`:
            a whole-beat fit of a real beat otherwise creeps along a flat valley to its
            step limit). Problems without them run optimistix's Levenberg-Marquardt
            unchanged.
    """

    rtol: float = 1e-5
    atol: float = 1e-6
    max_steps: int = 100
    warm_start: bool = True
    scaled: bool = True
    standard_errors: float = STANDARD_ERRORS
    name: ClassVar[str] = "lm"

    def compile(self, problem: Problem):
        cycles = any(problem.needs_cycle)
        if cycles:
            solver = StatisticalLevenbergMarquardt(self.rtol, self.atol, self.standard_errors)
        else:
            solver = optx.LevenbergMarquardt(rtol=self.rtol, atol=self.atol)

        def fn(z, starts):
            return problem.residuals(problem.to_u(z), starts)

        def finish(z, steps, result, starts=None):
            loss, grad = jax.value_and_grad(lambda z: 0.5 * jnp.sum(fn(z, starts) ** 2))(z)
            return z, loss, steps, jnp.linalg.norm(grad), RESULTS.promote(result)

        def scales(z0, starts):
            if cycles and self.scaled:
                return column_scales(lambda z: fn(z, starts), z0)
            return jnp.ones_like(z0)

        def first(z0, orbits):
            """The orbits of the first evaluation: from ``orbits`` (a large cycle), or
            None (the Hopf normal form)."""
            if orbits is None:
                return None
            return problem.residuals_and_cycles(problem.to_u(z0), orbits)[1]

        if self.warm_start and cycles:

            def warm_fn(y, scale, starts):
                return problem.residuals_and_cycles(problem.to_u(y / scale), starts)

            def run(z0, orbits=None):
                starts = first(z0, orbits)
                d = scales(z0, starts)
                sol = warm_least_squares(
                    warm_fn, solver, z0 * d, d, starts, max_steps=self.max_steps
                )
                return finish(sol.value / d, sol.num_steps, sol.result, sol.starts)

            return jax.jit(run)

        def run(z0, orbits=None):
            starts = first(z0, orbits)
            d = scales(z0, starts)
            sol = optx.least_squares(
                lambda y, scale: fn(y / scale, starts),
                solver,
                z0 * d,
                d,
                max_steps=self.max_steps,
                throw=False,
            )
            return finish(sol.value / d, sol.stats["num_steps"], sol.result, starts)

        return jax.jit(run)


class WarmSolution(eqx.Module):
    """What :func:`warm_least_squares` returns.

    Attributes:
        value: the solution y.
        residuals: ``fn``'s residuals at ``value``.
        starts: the orbits (or other warm-start data) at ``value``'s evaluation: the
            starts of a neighbouring solve (continuation, profiles).
        num_steps: iterations taken.
        result: ``optimistix.RESULTS`` item.
    """

    value: PyTree
    residuals: PyTree
    starts: PyTree
    num_steps: Array
    result: optx.RESULTS


def warm_least_squares(
    fn: Callable[[PyTree, PyTree, PyTree], tuple[PyTree, PyTree]],
    solver: optx.AbstractLeastSquaresSolver,
    y0: PyTree,
    args: PyTree = None,
    starts: PyTree | None = None,
    *,
    max_steps: int = 100,
) -> WarmSolution:
    """``optimistix.least_squares`` of ``fn`` with warm-start data refreshed between steps.

    ``fn(y, args, starts) -> (residuals, new_starts)``: ``starts`` is where an inner
    iterative solve begins (the orbits of :meth:`Problem.residuals_and_cycles`); it
    changes the cost of an evaluation, not its value (to the inner solver's
    tolerance). The solve runs optimistix's step-by-step interface (``solver.init``,
    ``solver.step``, ``solver.terminate``) in a ``lax.while_loop`` whose carry holds the
    starts; after each step they become the ``new_starts`` of the last accepted iterate
    (optimistix keeps its aux). So each evaluation starts from the last accepted
    point's orbits; the iterates are those of ``optimistix.least_squares`` on
    ``fn(y, args, None)`` with the same solver. Pure and jit-able; not differentiable
    (the starts are data).

    Args:
        fn: residual function with warm-start data (see above).
        solver: an optimistix Gauss-Newton-type solver (``optx.LevenbergMarquardt``,
            ``optx.Dogleg``, ``optx.GaussNewton``: their state keeps the last accepted
            iterate's aux and residuals).
        y0: the start.
        args: fixed data of ``fn``.
        starts: initial warm-start data (e.g. the previous profile point's
            ``WarmSolution.starts``); None: the unconverged zero pytree of
            ``fn``'s second output (orbits from the Hopf normal form).
        max_steps: iterations.
    """
    y0 = jax.tree_util.tree_map(lambda x: jnp.asarray(x, dtype=float), y0)
    if starts is None:
        _, starts_struct = jax.eval_shape(lambda y: fn(y, args, None), y0)
        starts = jax.tree_util.tree_map(lambda s: jnp.zeros(s.shape, s.dtype), starts_struct)

    def f(y, a):  # optimistix's fn(y, args) -> (residuals, aux)
        return fn(y, a[0], a[1])

    options, tags = {}, frozenset()
    f_struct, aux_struct = jax.eval_shape(f, y0, (args, starts))
    state = solver.init(f, y0, (args, starts), options, f_struct, aux_struct, tags)
    dynamic, static = eqx.partition(state, eqx.is_array)

    def cond(carry):
        y, dynamic, starts, k = carry
        terminate, result = solver.terminate(
            f, y, (args, starts), options, eqx.combine(dynamic, static), tags
        )
        ok = (result == optx.RESULTS.successful) & jnp.all(
            jnp.array([jnp.all(jnp.isfinite(x)) for x in jax.tree_util.tree_leaves(y)])
        )
        return ~terminate & ok & (k < max_steps)

    def body(carry):
        y, dynamic, starts, k = carry
        y, state, _ = solver.step(f, y, (args, starts), options, eqx.combine(dynamic, static), tags)
        return y, eqx.partition(state, eqx.is_array)[0], jax.lax.stop_gradient(state.aux), k + 1

    y, dynamic, starts, k = jax.lax.while_loop(cond, body, (y0, dynamic, starts, jnp.array(0)))
    terminate, result = solver.terminate(
        f, y, (args, starts), options, eqx.combine(dynamic, static), tags
    )
    result = optx.RESULTS.where(
        (result == optx.RESULTS.successful) & ~terminate,
        optx.RESULTS.nonlinear_max_steps_reached,
        result,
    )
    residuals = eqx.combine(dynamic, static).f_info.residual
    return WarmSolution(value=y, residuals=residuals, starts=starts, num_steps=k, result=result)


class LBFGS(LeastSquaresSolver):
    """L-BFGS (optax, zoom line search) on the loss; stops when
    ``|grad| <= gtol max(1, loss)`` or after ``max_steps``."""

    max_steps: int = 80
    gtol: float = 1e-6
    name: ClassVar[str] = "lbfgs"

    def compile(self, problem: Problem):
        def loss(z):
            return problem.loss(problem.to_u(z))

        opt = optax.lbfgs()
        value_and_grad = optax.value_and_grad_from_state(loss)
        gtol, max_steps = self.gtol, self.max_steps

        def run(z0):
            def cond(carry):
                _, _, k, gnorm, value = carry
                return (
                    (k < max_steps) & (gnorm > gtol * jnp.maximum(1.0, value)) & jnp.isfinite(gnorm)
                )

            def body(carry):
                z, state, k, _, _ = carry
                value, grad = value_and_grad(z, state=state)
                updates, state = opt.update(grad, state, z, value=value, grad=grad, value_fn=loss)
                return optax.apply_updates(z, updates), state, k + 1, jnp.linalg.norm(grad), value

            init = (z0, opt.init(z0), 0, jnp.asarray(1e300), jnp.asarray(1e300))
            z, _, k, _, _ = jax.lax.while_loop(cond, body, init)
            value, grad = jax.value_and_grad(loss)(z)
            gnorm = jnp.linalg.norm(grad)
            ok = (gnorm <= gtol * jnp.maximum(1.0, value)) & jnp.isfinite(value)
            result = RESULTS.where(ok, RESULTS.successful, RESULTS.max_steps_reached)
            return z, value, k, gnorm, result

        return jax.jit(run)


class Adam(LeastSquaresSolver):
    """Adam (optax) for ``max_steps`` steps of size ``learning_rate`` in z."""

    max_steps: int = 80
    learning_rate: float = 0.05
    name: ClassVar[str] = "adam"

    def compile(self, problem: Problem):
        def loss(z):
            return problem.loss(problem.to_u(z))

        opt = optax.adam(self.learning_rate)
        max_steps = self.max_steps

        def run(z0):
            def body(carry, _):
                z, state = carry
                grad = jax.grad(loss)(z)
                updates, state = opt.update(grad, state, z)
                return (optax.apply_updates(z, updates), state), None

            (z, _), _ = jax.lax.scan(body, (z0, opt.init(z0)), None, length=max_steps)
            value, grad = jax.value_and_grad(loss)(z)
            # Adam has no termination test: it always stops on its step budget
            return z, value, max_steps, jnp.linalg.norm(grad), RESULTS.max_steps_reached

        return jax.jit(run)


METHODS = {"lm": LevenbergMarquardt, "lbfgs": LBFGS, "adam": Adam}


def solver_from_name(
    method: str | LeastSquaresSolver, max_steps: int | None = None
) -> LeastSquaresSolver:
    """``"lm"``, ``"lbfgs"``, ``"adam"`` or a solver object (``max_steps`` overrides its own)."""
    if isinstance(method, LeastSquaresSolver):
        solver = method
    elif method in METHODS:
        solver = METHODS[method]()
    else:
        raise ValueError(
            f"method must be one of {', '.join(METHODS)} or a least-squares solver object, got {method!r}"
        )
    if max_steps is not None:
        if max_steps < 1:
            raise ValueError(f"max_steps must be >= 1, got {max_steps}")
        solver = eqx.tree_at(lambda s: s.max_steps, solver, int(max_steps))
    return solver


_STEP_LIMITS = (RESULTS.nonlinear_max_steps_reached, RESULTS.max_steps_reached)


def least_squares(
    problem: Problem,
    solver: LeastSquaresSolver | str = "lm",
    *,
    starts: int = FIT_STARTS,
    seed: int = 0,
    progress: bool = False,
    polish: int = 0,
    orbits: list | None = None,
) -> FitResult:
    """Fit ``problem`` by ``solver`` from ``starts`` starts; the report of the best.

    Args:
        problem: the inverse problem.
        solver: :class:`LevenbergMarquardt` (default), :class:`LBFGS`, :class:`Adam` or
            their names.
        starts: the problem's start ``u0`` and ``starts - 1`` points of a scrambled Sobol
            design of the bounded box.
        seed: seed of the design.
        progress: progress over starts on stderr from the start (the first start's
            compilation included; :mod:`axojax._progress`).
        polish: while the best start stopped at the solver's step limit, run the same
            compiled solver on from where it stopped, at most this many more times (a
            slow stretch of a valley, not a failure, often converges so; its steps add
            up in ``iterations``).
        orbits: for a problem with limit-cycle targets, the orbits (one
            :class:`~axojax.LimitCycle` or None per condition) every start's first
            evaluation begins from, instead of the Hopf normal form: the large cycle
            past a subcritical Hopf point (:mod:`axojax.orbits.large_cycle`).
            Levenberg-Marquardt only.
    """
    solver = solver_from_name(solver)
    if orbits is not None and not isinstance(solver, LevenbergMarquardt):
        raise ValueError(f"orbits: starting orbits need the lm solver, got {solver.name!r}")
    t0 = time.perf_counter()
    compiled = solver.compile(problem)

    def run(z):
        return compiled(z) if orbits is None else compiled(z, orbits)

    initial = problem.start_design(starts, seed)
    runs = []
    for u in progress_bar(initial, desc="fit starts", unit="start", enable=progress, starting=True):
        z, value, steps, gnorm, result = run(problem.to_z(jnp.asarray(u)))
        value = float(value)
        runs.append(
            {
                "z": np.asarray(z),
                "loss": value if math.isfinite(value) else math.inf,
                "steps": int(steps),
                "gnorm": float(gnorm),
                "result": result,
            }
        )
    best = min(range(len(runs)), key=lambda i: runs[i]["loss"])
    for _ in range(int(polish)):
        if runs[best]["result"] not in _STEP_LIMITS:
            break
        z, value, steps, gnorm, result = run(jnp.asarray(runs[best]["z"]))
        value = float(value)
        if not (math.isfinite(value) and value <= runs[best]["loss"]):
            break
        steps = runs[best]["steps"] + int(steps)
        runs[best].update(
            z=np.asarray(z), loss=value, steps=steps, gnorm=float(gnorm), result=result
        )
    wall = time.perf_counter() - t0
    u_end = [np.asarray(problem.to_u(jnp.asarray(r["z"]))) for r in runs]
    start_log = [(problem.values(u), r["loss"]) for u, r in zip(initial, runs)]
    ends = [(problem.values(u), r["loss"]) for u, r in zip(u_end, runs)]
    return build_report(
        problem,
        u_end[best],
        method=solver.name,
        loss=runs[best]["loss"],
        gnorm=runs[best]["gnorm"],
        iterations=[r["steps"] for r in runs],
        wall_s=wall,
        starts=start_log,
        optima=ends,
        result=runs[best]["result"],
    )
