"""Limit cycles as first-class objects: periodic orbits of the nonlinear beat computed
directly (harmonic balance and Newton), their Floquet multipliers, derivatives by the
implicit function theorem, and their branch in p from the Hopf point."""

from .cycle import LimitCycle
from .limit_cycle import limit_cycle
from .solvers import HarmonicBalance, OrbitSolver

__all__ = ["HarmonicBalance", "LimitCycle", "OrbitSolver", "limit_cycle"]
