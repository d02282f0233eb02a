"""Figures (matplotlib, Agg backend)."""

from .maps import plot_sweep

__all__ = ["plot_sweep"]
