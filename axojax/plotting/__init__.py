"""Figures (matplotlib, Agg backend): stability maps of sweeps, simulated beats, mode shapes,
cross-sections."""

from .beats import animate_frames, animate_simulation, plot_mode, plot_simulation, plot_waveform
from .maps import plot_sweep
from .section import group_bending_directions, plot_section

__all__ = [
    "animate_frames",
    "animate_simulation",
    "group_bending_directions",
    "plot_mode",
    "plot_section",
    "plot_simulation",
    "plot_sweep",
    "plot_waveform",
]
