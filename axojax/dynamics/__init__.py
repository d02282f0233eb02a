"""Nonlinear beating in the time domain: cubic link stiffening, diffrax integration,
limit-cycle analysis."""

from .integrate import Trajectory, integrate
from .nonlinear import cubic_link_force
from .simulate import DEFAULT_CUBIC, Simulation, simulate

__all__ = ["DEFAULT_CUBIC", "Simulation", "Trajectory", "cubic_link_force", "integrate", "simulate"]
