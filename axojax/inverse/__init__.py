"""Inverse problems: fits, global fits across conditions, and (with samplers) posteriors,
as one :class:`Problem` seen by different solver objects (see ``docs/api/inverse.md``)."""

from .conditions import Condition
from .parameters import DEFAULT_BOUNDS, LINEAR, FreeParameter
from .problem import SHAPE_FLOOR, Problem

__all__ = ["DEFAULT_BOUNDS", "LINEAR", "SHAPE_FLOOR", "Condition", "FreeParameter", "Problem"]
