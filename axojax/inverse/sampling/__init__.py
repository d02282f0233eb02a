"""Posteriors of an inverse problem (:class:`axojax.inverse.Problem`), one sampler object
each (an :class:`AbstractSampler`), all run by :func:`posterior`, which checks the
arguments they share and calls the sampler's ``run``: :class:`NUTS` chains (its settings,
defaults and run in ``_nuts``, its compiled programs in ``_nuts_kernels``), adaptive
tempered :class:`SMC` runs for several modes and cliffs (``_smc``), :class:`ModeMixture`'s
independence chains from a fitted mixture (``_mode_mixture``; its tempered fit in
``_mode_tempering``); the coordinates that straighten a curved ridge for NUTS
(:mod:`.transport`, :mod:`.transport_choice`), the Laplace approximation where chains
start, their start-up cache and diagnostics; which sampler a posterior gets when none is
named (:func:`choose_sampler`, ``axojax fit --sampler auto``) and the eigen-solver its
problem should use (:func:`posterior_eigen_solver`). What every sampler shares, and a sampler of
one's own may use, is public: :mod:`.summaries` (draws as values, statistics, a
gradient-free sampler's :class:`Posterior`) and :mod:`.programs` (compiled pieces and
their clock).

The defaults are those of ``axojax fit --posterior`` (whose default ``--sampler auto``
picks the sampler by the problem, :func:`choose_sampler`; ``posterior``'s is NUTS): an
axojax ``Problem`` given no start is fitted from :data:`POSTERIOR_STARTS` starts first,
the warm-up follows the draws (:func:`warmup_steps`), the chains run one after another on
a CPU (:func:`vectorize_chains`) and NUTS samples along the ridge that fit suggests.

Imports the problem core and the fit layer (:mod:`axojax.inverse.fitting`), never the
comparison or the whole beat; this ``__init__`` is the only way in from outside.
"""

from . import diagnostics
from ._densities import InverseProblem, NormalPrior, ScaledSigmas, normal_prior
from ._laplace import POSTERIOR_STARTS, Laplace, laplace_of
from ._mode_mixture import ModeMixture
from ._nuts import (
    MAX_ALONG_WARMUP,
    MAX_DEFAULT_WARMUP,
    MIN_WARMUP,
    NUTS,
    vectorize_chains,
    warmup_steps,
)
from ._posterior import posterior
from ._posterior_result import Posterior, load_truth
from ._sampler import AbstractSampler
from ._smc import SMC
from .choice import MODES_MAX_FREE, choose_sampler, posterior_eigen_solver
from .transport import ProfileTransport
from .transport_choice import suggest_transport

__all__ = [
    "MAX_ALONG_WARMUP",
    "MAX_DEFAULT_WARMUP",
    "MIN_WARMUP",
    "MODES_MAX_FREE",
    "NUTS",
    "POSTERIOR_STARTS",
    "SMC",
    "AbstractSampler",
    "InverseProblem",
    "Laplace",
    "ModeMixture",
    "NormalPrior",
    "Posterior",
    "ProfileTransport",
    "ScaledSigmas",
    "choose_sampler",
    "diagnostics",
    "laplace_of",
    "load_truth",
    "normal_prior",
    "posterior",
    "posterior_eigen_solver",
    "suggest_transport",
    "vectorize_chains",
    "warmup_steps",
]
