"""Beat waveforms: cycle detection, Fourier modes of the tangent angle, waveform frames.

Shared by the simulation analysis (:mod:`axojax.dynamics`) and by fitting observed beats.
"""

from .fourier import Cycles, FourierModes, detect_cycles, fourier_modes
from .shapes import mode_frames

__all__ = ["Cycles", "FourierModes", "detect_cycles", "fourier_modes", "mode_frames"]
