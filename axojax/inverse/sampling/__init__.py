"""Posteriors of an inverse problem (:class:`axojax.inverse.Problem`), one sampler
object each, all run by :func:`posterior`: :class:`NUTS` chains (:mod:`.posterior`),
adaptive tempered :class:`SMC` runs for several modes and cliffs (:mod:`.smc`),
:class:`ModeMixture`'s independence chains from a fitted mixture (:mod:`.modes`); the
coordinates that straighten a curved ridge for them (:mod:`.transport`,
:mod:`.transport_choice`), the Laplace approximation where chains start, their start-up
cache and diagnostics.

Imports the problem core and the fit layer (:mod:`axojax.inverse.fitting`), never the
comparison or the whole beat; this ``__init__`` is the only way in from outside.
"""

from . import diagnostics
from ._densities import InverseProblem, NormalPrior, ScaledSigmas, normal_prior
from ._laplace import Laplace, laplace_of
from ._nuts import NUTS
from ._posterior_result import Posterior, load_truth
from ._smc import SMC
from .modes import ModeMixture
from .posterior import posterior
from .transport import ProfileTransport
from .transport_choice import suggest_transport

__all__ = [
    "NUTS",
    "SMC",
    "InverseProblem",
    "Laplace",
    "ModeMixture",
    "NormalPrior",
    "Posterior",
    "ProfileTransport",
    "ScaledSigmas",
    "diagnostics",
    "laplace_of",
    "load_truth",
    "normal_prior",
    "posterior",
    "suggest_transport",
]
