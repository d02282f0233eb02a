"""The eigen-solver: pencil decomposition, pluggable dominant-eigenpair solvers
(:class:`Dense`, :class:`Arnoldi`, :class:`Auto`), mode shapes and mode metrics."""

from .dominant import CLUSTER_RTOL, dominant_eigenpair
from .metrics import (
    beat_plane,
    displacement_wavenumber,
    mode_shapes,
    tangent_measures,
    tangent_wavenumber,
    wavenumber,
    weighted_wavenumber,
)
from .mode import (
    CLASSES,
    DEFAULT_SOLVER,
    DIVERGENCE,
    FLUTTER,
    STABLE,
    Mode,
    classify,
    dominant_mode,
    mode_from_eigenpair,
    spectrum,
)
from .nearest import nearest_eigenpair, nearest_mode
from .normal_force import NormalForce, normal_force_mode, shift_invert_eigenpair
from .pencil import eigensystem, eigenvalues
from .solvers import (
    SOLVERS,
    AbstractEigenSolver,
    Arnoldi,
    Auto,
    Dense,
    EigenSolver,
    solver_from_name,
)

__all__ = [
    "Arnoldi",
    "Auto",
    "CLASSES",
    "CLUSTER_RTOL",
    "DEFAULT_SOLVER",
    "DIVERGENCE",
    "Dense",
    "AbstractEigenSolver",
    "EigenSolver",
    "FLUTTER",
    "SOLVERS",
    "STABLE",
    "Mode",
    "beat_plane",
    "classify",
    "dominant_eigenpair",
    "displacement_wavenumber",
    "dominant_mode",
    "eigensystem",
    "eigenvalues",
    "mode_from_eigenpair",
    "mode_shapes",
    "nearest_eigenpair",
    "nearest_mode",
    "NormalForce",
    "normal_force_mode",
    "shift_invert_eigenpair",
    "solver_from_name",
    "spectrum",
    "tangent_measures",
    "tangent_wavenumber",
    "wavenumber",
    "weighted_wavenumber",
]
