"""Inverse problems: fits, global fits across conditions, and posteriors, as one
:class:`Problem` seen by different solver objects.

>>> problem = ax.inverse.Problem(model, [ax.inverse.Condition({"p": 150}, [Target(...)]), ...], ["ks", "cl"])
>>> result = ax.inverse.least_squares(problem, ax.inverse.LevenbergMarquardt(), starts=8)
>>> post = ax.inverse.posterior(problem, draws=1000, chains=4)

The same problem from a file: ``ax.inverse.load_spec("FIT.toml")`` (:mod:`.spec`).

The house, by job, each layer importing only the layers below it (tests/house/test_architecture.py
keeps it so; docs/internals.md draws it):

1. the problem core, this folder's own modules: :mod:`.problem` (:class:`Problem`, its
   residuals and coordinates), :mod:`.parameters`, :mod:`.conditions`,
   :mod:`.predictions`, :mod:`.cycle_targets`, :mod:`.orbit_setup`, :mod:`.fingerprint`,
   :mod:`.spec` (a problem from a file);
2. :mod:`.fitting`: least-squares solvers, :func:`fit`, the report, identifiability, checks;
3. :mod:`.sampling`: posteriors, one sampler object each (an :class:`AbstractSampler`:
   :class:`NUTS`, :class:`SMC`, :class:`ModeMixture`), whose ``run`` :func:`posterior` calls;
4. :mod:`.comparison`: the dynein mechanisms fitted to one beat and ranked (it takes the
   Laplace approximation from sampling);
5. :mod:`.whole_beat`: a regulated mechanism fitted to the whole limit cycle, and the
   mechanisms ranked on it (it imports the comparison; nothing imports it).

Outside this package, a subpackage is reached through its ``__init__`` or its public
modules, never a private (``_name``) one.
"""

from . import whole_beat
from .comparison.compare import CompareRow, Comparison, compare
from .comparison.mechanisms import AVAILABLE_BASES, BASES, MECHANISMS
from .conditions import Condition
from .fitting import (
    LBFGS,
    METHODS,
    Adam,
    FitResult,
    LeastSquaresSolver,
    LevenbergMarquardt,
    WarmSolution,
    build_problem,
    build_report,
    checks,
    fit,
    information_criteria,
    least_squares,
    r2,
    solver_from_name,
    warm_least_squares,
)
from .parameters import DEFAULT_BOUNDS, LINEAR, FreeParameter
from .problem import SHAPE_FLOOR, Problem
from .sampling import (
    NUTS,
    SMC,
    AbstractSampler,
    InverseProblem,
    ModeMixture,
    NormalPrior,
    Posterior,
    ProfileTransport,
    ScaledSigmas,
    choose_sampler,
    diagnostics,
    load_truth,
    normal_prior,
    posterior,
    suggest_transport,
)
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
    "AbstractSampler",
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
    "choose_sampler",
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
    "whole_beat",
]
