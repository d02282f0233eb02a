"""Limit cycles as first-class objects: periodic orbits of the nonlinear beat computed
directly (harmonic balance and Newton; regulated rows with motor kinetics and saturating
motors too, :mod:`axojax.orbits.motors`), their Floquet multipliers, derivatives by the
implicit function theorem, their branch in p from the Hopf point, their waveform
measures (:mod:`axojax.orbits.measures`) and waveform targets for fits
(:mod:`axojax.inverse.cycle_targets`)."""

from ._solve import solve_jit
from .cycle import LimitCycle
from .limit_cycle import limit_cycle
from .measures import CycleMeasures, cycle_measures
from .motors import Motors
from .solvers import AbstractOrbitSolver, HarmonicBalance, OrbitSolver, Recording, WarmStart

__all__ = [
    "AbstractOrbitSolver",
    "CycleMeasures",
    "HarmonicBalance",
    "LimitCycle",
    "Motors",
    "OrbitSolver",
    "Recording",
    "WarmStart",
    "cycle_measures",
    "limit_cycle",
    "solve_jit",
]
