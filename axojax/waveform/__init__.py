"""Beat waveforms: cycle detection, Fourier modes of the tangent angle, the waveform
measures (:mod:`axojax.waveform.measures`: wavelength, direction, static curvature,
dynamic and tip amplitude, one implementation for models and data), waveform frames.

Shared by the linear modes, the limit cycles, the simulation analysis
(:mod:`axojax.dynamics`) and observed beats.
"""

from . import measures
from .fourier import Cycles, FourierModes, detect_cycles, fourier_modes
from .shapes import mode_frames

__all__ = ["Cycles", "FourierModes", "detect_cycles", "fourier_modes", "measures", "mode_frames"]
