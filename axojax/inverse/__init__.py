"""Inverse problems: fits, global fits across conditions, and posteriors, as one
:class:`Problem` seen by different solver objects.

>>> problem = ax.inverse.Problem(model, [ax.inverse.Condition({"p": 150}, [Target(...)]), ...], ["ks", "cl"])
>>> result = ax.inverse.least_squares(problem, ax.inverse.LevenbergMarquardt(), starts=8)
>>> post = ax.inverse.posterior(problem, draws=1000, chains=4)

The same problem from a file: ``ax.inverse.load_spec("FIT.toml")`` (:mod:`.spec`).

Three jobs, three rooms: this folder fits (the problem, its conditions and parameters,
the least-squares solvers, the report and its checks); :mod:`.sampling` samples
posteriors (``posterior``; ``transport`` and ``transport_choice`` straighten a curved
ridge for the sampler; private: ``_densities`` what a sampler needs of a problem and the
priors, ``_laplace`` where chains start, ``_nuts`` the sampler's compiled programs,
``_posterior_result`` :class:`Posterior`, ``_warm_cache``; ``diagnostics``);
:mod:`.comparison` ranks the dynein mechanisms on a beat (``mechanisms``, ``compare``).
Layers, no circle: the rooms import the fit layer (comparison also the Laplace
approximation of sampling; Problem.fingerprint calls the warm cache when asked), never
this package.
"""

from . import checks
from .comparison.compare import CompareRow, Comparison, compare
from .comparison.mechanisms import AVAILABLE_BASES, BASES, MECHANISMS
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
from .problem import SHAPE_FLOOR, Problem
from .quality import information_criteria, r2
from .report import FitResult, build_report
from .sampling import diagnostics
from .sampling._densities import InverseProblem, NormalPrior, ScaledSigmas, normal_prior
from .sampling._nuts import NUTS
from .sampling._posterior_result import Posterior, load_truth
from .sampling._smc import SMC
from .sampling.modes import ModeMixture
from .sampling.posterior import posterior
from .sampling.transport import ProfileTransport
from .sampling.transport_choice import suggest_transport
from .spec import FitSpec, load_spec, read_spec

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
    "SMC",
    "ModeMixture",
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
