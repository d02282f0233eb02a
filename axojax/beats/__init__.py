"""Observed beats, and nothing of the model: beat-file readers (:mod:`.readers`), their
reduction to Fourier modes of the tangent angle (:mod:`.reduction`, :class:`BeatData`),
what a fit matches as records (:mod:`.targets`), published observations
(:mod:`.observations`), where the bundled data sets lie (:mod:`.bundled`) and the units a
fit of a beat assumes (:mod:`.units`).

Everything that compares a model with these lives in :mod:`axojax.inverse`; the bundled
data sets' user-facing list is :mod:`axojax.datasets` (it depends on this package, never
the reverse).
"""

from .bundled import FILES, resolve
from .data import BeatData, beat_from_kymograph, read_beat
from .observations import OBSERVATIONS, observation_targets
from .readers import BeatFileError
from .reduction import Planarity
from .targets import (
    COMPONENTS,
    CYCLE_SCALARS,
    SCALARS,
    ShapeTarget,
    Target,
    join_components,
    observed_target,
)
from .units import beat_units

__all__ = [
    "COMPONENTS",
    "CYCLE_SCALARS",
    "FILES",
    "OBSERVATIONS",
    "SCALARS",
    "BeatData",
    "BeatFileError",
    "Planarity",
    "ShapeTarget",
    "Target",
    "beat_from_kymograph",
    "beat_units",
    "join_components",
    "observation_targets",
    "observed_target",
    "read_beat",
    "resolve",
]
