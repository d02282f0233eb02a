"""Inverse problems: fits, global fits across conditions, and posteriors, as one
:class:`Problem` seen by different solver objects.

>>> problem = ax.inverse.Problem(model, [ax.inverse.Condition({"p": 150}, [Target(...)]), ...], ["ks", "cl"])
>>> result = ax.inverse.least_squares(problem, ax.inverse.LevenbergMarquardt(), starts=8)
>>> post = ax.inverse.posterior(problem, draws=1000, chains=4)
"""

from . import diagnostics
from .conditions import Condition
from .fit import build_problem, fit
from .least_squares import (
    LBFGS,
    METHODS,
    Adam,
    LeastSquaresSolver,
    LevenbergMarquardt,
    WarmSolution,
    least_squares,
    solver_from_name,
    warm_least_squares,
)
from .parameters import DEFAULT_BOUNDS, LINEAR, FreeParameter
from .posterior import (
    NUTS,
    InverseProblem,
    NormalPrior,
    Posterior,
    ScaledSigmas,
    normal_prior,
    posterior,
)
from .problem import SHAPE_FLOOR, Problem
from .report import FitResult, build_report

__all__ = [
    "DEFAULT_BOUNDS",
    "LBFGS",
    "LINEAR",
    "METHODS",
    "NUTS",
    "SHAPE_FLOOR",
    "Adam",
    "Condition",
    "FitResult",
    "FreeParameter",
    "InverseProblem",
    "LeastSquaresSolver",
    "LevenbergMarquardt",
    "NormalPrior",
    "Posterior",
    "Problem",
    "ScaledSigmas",
    "WarmSolution",
    "build_report",
    "diagnostics",
    "fit",
    "build_problem",
    "least_squares",
    "normal_prior",
    "posterior",
    "solver_from_name",
    "warm_least_squares",
]
