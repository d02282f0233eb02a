"""Observed beats and what a fit matches: beat-file readers and their reduction
(:mod:`.data`), targets (:mod:`.targets`), published observations, and :func:`fit`, the
one-call front end of :mod:`axojax.inverse`.

``fit``, ``FitResult`` and ``DEFAULT_BOUNDS`` come from :mod:`axojax.inverse`, whose
conditions are built from this package's targets: they are imported on first use, so
that importing ``axojax.fitting.targets`` (as ``axojax.inverse`` does) never needs
``axojax.inverse`` half-built.
"""

import importlib
from typing import TYPE_CHECKING

from .data import BeatData, beat_from_kymograph, read_beat
from .observations import OBSERVATIONS, observation_targets
from .readers import BeatFileError
from .reduction import Planarity
from .targets import SCALARS, ShapeTarget, Target

if TYPE_CHECKING:  # the same names for static tools (the API docs' griffe)
    from .fit import DEFAULT_BOUNDS, FitResult, build_problem, fit

_FROM_FIT = ("DEFAULT_BOUNDS", "FitResult", "build_problem", "fit")


def __getattr__(name: str):
    if name in _FROM_FIT:
        value = getattr(importlib.import_module(".fit", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "DEFAULT_BOUNDS",
    "OBSERVATIONS",
    "SCALARS",
    "BeatData",
    "BeatFileError",
    "FitResult",
    "Planarity",
    "ShapeTarget",
    "Target",
    "beat_from_kymograph",
    "build_problem",
    "fit",
    "observation_targets",
    "read_beat",
]
