"""Batched parameter sweeps and their stored results."""

from .engine import sweep
from .result import METRICS, SweepResult

__all__ = ["METRICS", "SweepResult", "sweep"]
