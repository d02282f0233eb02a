"""Inverse problems: posteriors of fitted parameters (NUTS) and their diagnostics."""

from . import diagnostics
from .posterior import NUTS, InverseProblem, Posterior, normal_prior, posterior

__all__ = ["InverseProblem", "NUTS", "Posterior", "diagnostics", "normal_prior", "posterior"]
