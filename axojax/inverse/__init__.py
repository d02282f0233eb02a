"""Inverse problems: fits, global fits across conditions, and (with samplers) posteriors,
as one :class:`Problem` seen by different solver objects.

>>> problem = ax.inverse.Problem(model, [ax.inverse.Condition({"p": 150}, [Target(...)]), ...], ["ks", "cl"])
>>> result = ax.inverse.least_squares(problem, ax.inverse.LevenbergMarquardt(), starts=8)
"""

from .conditions import Condition
from .least_squares import (
    LBFGS,
    METHODS,
    Adam,
    LeastSquaresSolver,
    LevenbergMarquardt,
    least_squares,
    solver_from_name,
)
from .parameters import DEFAULT_BOUNDS, LINEAR, FreeParameter
from .problem import SHAPE_FLOOR, Problem
from .report import FitResult, build_report

__all__ = [
    "DEFAULT_BOUNDS",
    "LBFGS",
    "LINEAR",
    "METHODS",
    "SHAPE_FLOOR",
    "Adam",
    "Condition",
    "FitResult",
    "FreeParameter",
    "LeastSquaresSolver",
    "LevenbergMarquardt",
    "Problem",
    "build_report",
    "least_squares",
    "solver_from_name",
]
