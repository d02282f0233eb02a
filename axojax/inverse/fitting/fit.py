"""``fit``: estimate unknown parameters from observed beats, one condition or several.

A thin front end to :mod:`axojax.inverse`: it builds an :class:`~axojax.inverse.Problem`
(free parameters in a bounded coordinate, log for positive ones, linear for ``gamma``,
mapped into their bounds by a logistic function), runs a least-squares solver from
several starts (Levenberg-Marquardt by default, L-BFGS or Adam) and returns the
:class:`~axojax.inverse.FitResult`: values, chi^2 per degree of freedom, standard errors
and correlations from the Gauss-Newton matrix ``J^T J`` in the fitted coordinate,
parameters at a bound, identifiability, and a message saying what is determined.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

from ...beats.targets import ShapeTarget, Target
from ...eigen.mode import DEFAULT_SOLVER
from ...eigen.solvers import AbstractEigenSolver
from ...models.section import Model
from ...orbits.solvers import AbstractOrbitSolver, HarmonicBalance
from ...params import DEFAULT_CUBIC, Params
from ...units import Units
from ..conditions import Condition
from ..parameters import DEFAULT_BOUNDS, LINEAR
from ..problem import CYCLE_FAILED, SHAPE_FLOOR, Problem
from .identifiability import IDENTIFIABLE_MAX_LOG_SE
from .least_squares import FIT_STARTS, LeastSquaresSolver, least_squares, solver_from_name
from .report import SHAPE_RMS_OK, FitResult

__all__ = [
    "CYCLE_FAILED",
    "DEFAULT_BOUNDS",
    "IDENTIFIABLE_MAX_LOG_SE",
    "LINEAR",
    "SHAPE_RMS_OK",
    "FitResult",
    "build_problem",
    "fit",
]


def fit(
    model: Model,
    params: Params,
    targets: Sequence[Target] | Sequence[Condition],
    free: Sequence[str],
    *,
    shape: ShapeTarget | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    kl_ratio: float | None = None,
    units: Units = Units(),  # noqa: B008
    starts: int = FIT_STARTS,
    method: str | LeastSquaresSolver = "lm",
    max_steps: int | None = None,
    seed: int = 0,
    progress: bool = False,
    solver: AbstractEigenSolver | LeastSquaresSolver = DEFAULT_SOLVER,
    cubic: float = DEFAULT_CUBIC,
    orbit_solver: AbstractOrbitSolver = HarmonicBalance(),  # noqa: B008
    tau_m: float | None = None,
    f_sat: float | None = None,
    per_condition: Sequence[str] = (),
    shape_floor: float = SHAPE_FLOOR,
    exclude_base_um: float = 0.0,
    prior=None,
    shift: complex | None = None,
) -> FitResult:
    """Fit the ``free`` parameters of ``model`` so that its dominant mode (or limit cycle)
    matches ``targets`` (and ``shape``), in one condition or several at once.

    Args:
        model: e.g. ``ax.models.seven()``.
        params: starting point and fixed values of the other parameters.
        targets: scalar :class:`Target` s (one condition), or a list of
            :class:`axojax.inverse.Condition` (a global fit: each condition has its own
            fixed values, e.g. ``{"p": 150}``, targets and shape).
        free: names of the parameters to fit, shared by all conditions.
        shape: optional observed psi_1(s) of a single condition.
        bounds: per-parameter (low, high); defaults in ``DEFAULT_BOUNDS``.
        kl_ratio: tie kl = ks / kl_ratio (then fit ks, not kl).
        units: physical units of the targets.
        starts: number of starts (the given point, then a Sobol design in the bounds).
        method: ``"lm"`` (Levenberg-Marquardt, default), ``"lbfgs"``, ``"adam"``, or a
            solver object (``ax.inverse.LevenbergMarquardt()``, ``LBFGS()``, ``Adam()``).
        max_steps: iterations per start (default: the solver's own).
        seed: seed of the start design.
        progress: progress bar over starts.
        solver: dominant-eigenpair solver (:mod:`axojax.eigen.solvers`); a
            least-squares solver object here is taken as ``method``.
        cubic: link stiffening kappa (1/L^2) of the limit cycle, for targets with
            ``source="limit_cycle"`` (differentiable by the implicit function theorem).
            Where no orbit is found such a target's residual is ``CYCLE_FAILED``.
        orbit_solver: the periodic-orbit solver (:mod:`axojax.orbits.solvers`).
        tau_m, f_sat: motor kinetics and saturating motors of a regulated mechanism's
            limit cycle (dimensionless, as :func:`axojax.limit_cycle` takes them; None:
            none); the starts of ``"tau_m"`` and ``"f_sat"`` when they are free.
        per_condition: parameters fitted separately in each condition (``"p@<label>"``).
        shape_floor: model-discrepancy floor of psi_1 (rad), added in quadrature to the
            shape's sigma (default 0.05 rad, see :mod:`axojax.inverse.problem`).
        exclude_base_um: leave shape points with s < this out of the fit (um); their
            misfit at the optimum is reported.
        prior: optional log prior in the fitted coordinates (used by samplers).
        shift: None: the beat is the dominant mode; a complex number (dimensionless):
            the eigenvalue nearest it (``1j * omega0`` for a regulated mechanism,
            :mod:`axojax.inverse.comparison.mechanisms`).

    Warns (``UserWarning``) when the targets are not reproduced or a parameter is not
    identifiable.
    """
    if isinstance(solver, LeastSquaresSolver):
        method, solver = solver, DEFAULT_SOLVER
    if starts < 1:
        raise ValueError(f"starts must be >= 1, got {starts}")
    optimiser = solver_from_name(method, max_steps)
    problem = build_problem(
        model,
        params,
        targets,
        free,
        shape=shape,
        bounds=bounds,
        kl_ratio=kl_ratio,
        units=units,
        solver=solver,
        cubic=cubic,
        orbit_solver=orbit_solver,
        tau_m=tau_m,
        f_sat=f_sat,
        per_condition=per_condition,
        shape_floor=shape_floor,
        exclude_base_um=exclude_base_um,
        prior=prior,
        shift=shift,
    )
    result = least_squares(problem, optimiser, starts=starts, seed=seed, progress=progress)
    _warn_if_unsettled(result)
    return result


def _warn_if_unsettled(result: FitResult) -> None:
    """:func:`fit`'s warnings, pointed at its caller: the targets not reproduced (the
    message's first part), and the parameters not identifiable."""
    if not result.targets_met:
        warnings.warn(result.message.split("; ")[0], stacklevel=3)
    bad = [n for n, ok in result.identifiable.items() if not ok]
    if bad:
        warnings.warn(
            f"not identifiable from these targets: {', '.join(bad)}"
            + (f" (at a bound: {', '.join(result.at_bound)})" if result.at_bound else ""),
            stacklevel=3,
        )


def build_problem(
    model: Model,
    params: Params,
    targets: Sequence[Target] | Sequence[Condition],
    free: Sequence[str],
    *,
    shape: ShapeTarget | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    kl_ratio: float | None = None,
    units: Units = Units(),
    solver: AbstractEigenSolver = DEFAULT_SOLVER,
    cubic: float = DEFAULT_CUBIC,
    orbit_solver: AbstractOrbitSolver = HarmonicBalance(),
    tau_m: float | None = None,
    f_sat: float | None = None,
    per_condition: Sequence[str] = (),
    shape_floor: float = SHAPE_FLOOR,
    exclude_base_um: float = 0.0,
    prior=None,
    shift: complex | None = None,
    mechanism: str | None = None,
    base: str | None = None,
) -> Problem:
    """The :class:`~axojax.inverse.Problem` that :func:`fit` solves, from the same
    arguments (less the least-squares settings): hand it to another solver, e.g.
    ``ax.inverse.posterior(build_problem(...), init=fit(...))``."""
    targets = list(targets)
    if targets and all(isinstance(t, Condition) for t in targets):
        if shape is not None:
            raise ValueError("shape: with a list of conditions give each condition its own shape")
        conditions = targets
    elif any(isinstance(t, Condition) for t in targets):
        raise ValueError(
            "targets: either Target objects (one condition) or Condition objects, not both"
        )
    else:
        if not targets and shape is None:
            raise ValueError("targets: give at least one target or a shape")
        conditions = [Condition(targets=targets, shape=shape)]
    params.validate()
    return Problem(
        model,
        conditions,
        free,
        per_condition=per_condition,
        params=params,
        bounds=bounds,
        kl_ratio=kl_ratio,
        units=units,
        solver=solver,
        cubic=cubic,
        orbit_solver=orbit_solver,
        tau_m=tau_m,
        f_sat=f_sat,
        shape_floor=shape_floor,
        exclude_base_um=exclude_base_um,
        prior=prior,
        shift=shift,
        mechanism=mechanism,
        base=base,
    )
