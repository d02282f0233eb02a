"""The eigen-solver: pencil decomposition, the differentiable dominant eigenpair,
mode shapes and mode metrics."""

from .dominant import CLUSTER_RTOL, dominant_eigenpair
from .metrics import beat_plane, mode_shapes, wavenumber
from .mode import CLASSES, DIVERGENCE, FLUTTER, STABLE, Mode, classify, dominant_mode, mode_from_eigenpair, spectrum
from .pencil import eigensystem, eigenvalues

__all__ = [
    "CLASSES", "CLUSTER_RTOL", "DIVERGENCE", "FLUTTER", "STABLE", "Mode", "beat_plane", "classify",
    "dominant_eigenpair", "dominant_mode", "eigensystem", "eigenvalues", "mode_from_eigenpair",
    "mode_shapes", "spectrum", "wavenumber",
]
