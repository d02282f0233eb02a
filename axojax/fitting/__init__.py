"""Inverse estimation: fit stiffness, damping and dynein force to observed beats."""

from .data import BeatData, beat_from_kymograph, read_beat
from .fit import DEFAULT_BOUNDS, FitResult, fit
from .observations import OBSERVATIONS, observation_targets
from .readers import BeatFileError
from .reduction import Planarity
from .targets import SCALARS, ShapeTarget, Target

__all__ = ["DEFAULT_BOUNDS", "OBSERVATIONS", "SCALARS", "BeatData", "BeatFileError", "FitResult", "Planarity", "ShapeTarget", "Target", "beat_from_kymograph", "fit", "observation_targets", "read_beat"]
