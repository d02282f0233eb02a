"""Figures (matplotlib, Agg backend): stability maps of sweeps, simulated beats, mode shapes."""

from .beats import animate_frames, animate_simulation, plot_mode, plot_simulation, plot_waveform
from .maps import plot_sweep

__all__ = ["animate_frames", "animate_simulation", "plot_mode", "plot_simulation", "plot_sweep", "plot_waveform"]
