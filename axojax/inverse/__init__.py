"""Inverse problems: fits, global fits across conditions, and posteriors, as one
:class:`Problem` seen by different solver objects.

>>> problem = ax.inverse.Problem(model, [ax.inverse.Condition({"p": 150}, [Target(...)]), ...], ["ks", "cl"])
>>> result = ax.inverse.least_squares(problem, ax.inverse.LevenbergMarquardt(), starts=8)
>>> post = ax.inverse.posterior(problem, draws=1000, chains=4)

The same problem from a file: ``ax.inverse.load_spec("FIT.toml")`` (:mod:`.spec`).
Private modules (re-exported here): ``_densities`` (what a sampler needs of a problem,
priors), ``_laplace`` (where chains start), ``_nuts`` (the sampler's compiled programs),
``_posterior_result`` (:class:`Posterior`); :mod:`.transport` straightens a curved
ridge for the sampler (:class:`ProfileTransport`).
"""

from . import checks, diagnostics
from ._densities import InverseProblem, NormalPrior, ScaledSigmas, normal_prior
from ._nuts import NUTS
from ._posterior_result import Posterior, load_truth
from .compare import CompareRow, Comparison, compare
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
from .mechanisms import AVAILABLE_BASES, BASES, MECHANISMS
from .parameters import DEFAULT_BOUNDS, LINEAR, FreeParameter
from .posterior import posterior
from .problem import SHAPE_FLOOR, Problem
from .quality import information_criteria, r2
from .report import FitResult, build_report
from .spec import FitSpec, load_spec, read_spec
from .transport import ProfileTransport
from .transport_choice import suggest_transport

__all__ = [
    "AVAILABLE_BASES",
    "BASES",
    "MECHANISMS",
    "CompareRow",
    "Comparison",
    "compare",
    "information_criteria",
    "r2",
    "DEFAULT_BOUNDS",
    "LBFGS",
    "LINEAR",
    "METHODS",
    "NUTS",
    "ProfileTransport",
    "suggest_transport",
    "SHAPE_FLOOR",
    "Adam",
    "Condition",
    "FitResult",
    "FitSpec",
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
    "checks",
    "diagnostics",
    "fit",
    "build_problem",
    "least_squares",
    "load_truth",
    "load_spec",
    "normal_prior",
    "posterior",
    "read_spec",
    "solver_from_name",
    "warm_least_squares",
]
