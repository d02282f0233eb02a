"""The jitted orbit solve shared by :func:`axojax.limit_cycle` and the branch
continuation (:mod:`axojax.orbits.branch`): one compiled program per (model, solver)."""

from __future__ import annotations

import jax

from ..models.section import Model
from ..params import Params
from .cycle import LimitCycle
from .motors import Motors
from .solvers import AbstractOrbitSolver, call_solve


def _solve(
    model: Model,
    params: Params,
    kappa,
    solver: AbstractOrbitSolver,
    start: LimitCycle | None = None,
    motors: Motors | None = None,
) -> LimitCycle:
    return call_solve(solver, model, params, kappa, start, motors)


solve_jit = jax.jit(_solve, static_argnums=(0, 3))
"""``solve_jit(model, params, kappa, solver, start, motors)``: ``solver.solve`` compiled,
model and solver static (``motors``: :class:`~axojax.orbits.motors.Motors` or None)."""
