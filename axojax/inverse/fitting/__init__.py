"""Fitting: a :class:`~axojax.inverse.Problem`'s least-squares optimum and what it says.

- :mod:`.least_squares`: the solver objects (:class:`LevenbergMarquardt`, :class:`LBFGS`,
  :class:`Adam`) and :func:`least_squares`, multi-start, with warm starts along a branch;
- :mod:`.fit`: :func:`fit` and :func:`build_problem`, a fit from a model, data and names;
- :mod:`.report`: :class:`FitResult`, the fit's JSON report and its verdicts;
- :mod:`.identifiability`: the rule that says which fitted values the data determine,
  and the notes on several starts' optima;
- :mod:`.quality`: R^2, chi^2/dof, AIC and BIC;
- :mod:`.checks`: the regime of each condition's dominant mode and the mesh check.

Imports the problem core (:mod:`axojax.inverse`'s own modules), never sampling,
comparison or the whole beat.
"""

from . import checks
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
from .quality import information_criteria, r2
from .report import FitResult, build_report

__all__ = [
    "LBFGS",
    "METHODS",
    "Adam",
    "FitResult",
    "LeastSquaresSolver",
    "LevenbergMarquardt",
    "WarmSolution",
    "build_problem",
    "build_report",
    "checks",
    "fit",
    "information_criteria",
    "least_squares",
    "r2",
    "solver_from_name",
    "warm_least_squares",
]
