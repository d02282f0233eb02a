"""``posterior``: the posterior of an inverse problem's free parameters, by a sampler
object (:class:`~._sampler.AbstractSampler`: :class:`~._nuts.NUTS` by default,
:class:`~._smc.SMC`, :class:`~._mode_mixture.ModeMixture` or one's own). This verb checks
the arguments every sampler shares and calls the sampler's ``run``; each sampler family
lives in its own module with its run. Its defaults are those of ``axojax fit
--posterior`` (which picks the sampler by the problem unless ``--sampler`` names one:
:func:`~.choice.choose_sampler`): a problem given no start is fitted from 16 starts
first, the warm-up follows the draws, the chains run one after another on a CPU, and
NUTS samples along the ridge the fit suggests."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from jaxtyping import Array

from ._densities import InverseProblem, normal_prior
from ._laplace import Laplace
from ._nuts import DEFAULT_NUTS
from ._posterior_result import Posterior
from ._sampler import AUTO, AbstractSampler
from .transport import ProfileTransport


def posterior(
    problem: InverseProblem,
    *,
    draws: int = 1000,
    chains: int = 4,
    warmup: int | None = None,
    seed: int = 0,
    init: Any = None,
    prior: Callable[[Array], Array] | Mapping[str, tuple[float, float]] | None = None,
    sampler: AbstractSampler = DEFAULT_NUTS,
    vectorize: bool | None = None,
    progress: bool = False,
    on_laplace: Callable[[Laplace], None] | None = None,
    cache: bool | str | os.PathLike | None = None,
    transport: ProfileTransport | str | None = AUTO,
) -> Posterior:
    """Sample the posterior of ``problem``'s free parameters with ``sampler`` (NUTS by
    default): the arguments every sampler shares are checked here, then
    ``sampler.run(problem, ...)`` does the work (:class:`AbstractSampler`).

    Args:
        problem: an :class:`InverseProblem` (e.g. :class:`axojax.inverse.Problem`).
        draws: draws per chain kept after warm-up.
        chains: independent chains (vmapped unless ``vectorize=False``).
        warmup: window-adaptation steps per chain (Stan's schedule; at least 150 gives
            its full set of windows), discarded. ``None`` (default): ``draws`` clipped to
            150..500 (..200 with a transport), as ``axojax fit --posterior``
            (:func:`~axojax.inverse.sampling.warmup_steps`).
        seed: seed of the chains and their starts.
        init: where the chains start. ``None``: for an axojax :class:`Problem` (or
            :class:`ScaledSigmas` of one), the best optimum of a least-squares fit from 16
            starts (``least_squares(problem, starts=POSTERIOR_STARTS)``, as ``axojax fit
            --posterior`` fits before it samples) and a spread around it; for another
            :class:`InverseProblem`, the posterior mode (Levenberg-Marquardt in ``z``
            from ``problem.u0``) and a spread drawn from its Laplace approximation; a
            (k,) point in ``u``, or a least-squares result
            (:func:`axojax.inverse.least_squares`' ``FitResult``, its optimum): a spread
            around it; a (chains, k) array in ``u``: these starts exactly.
        prior: replaces ``problem.log_prior``: a jax-traceable ``log_prior(u)``, or
            ``{name: (mean_u, sd_u)}`` (:func:`normal_prior`). ``None``: the problem's
            own prior (uniform in ``u`` by default).
        sampler: an :class:`AbstractSampler`, whose ``run`` samples: :class:`NUTS`
            settings (default), or :class:`SMC`: ``chains`` independent runs of adaptive
            tempered SMC from the prior (for several modes or cliffs; ``init``,
            ``warmup``, ``vectorize``, ``on_laplace`` and ``cache`` then do not apply, a
            ``transport`` is refused); or :class:`ModeMixture`: independence
            Metropolis-Hastings chains from a mixture fitted to every mode (``init``
            seeds the fit's optima; a ``transport`` is refused); or one's own subclass.
        vectorize: run the chains vmapped (they step together, each NUTS step costing
            the longest of the chains' trajectories; batched model evaluations), or,
            ``False``, one after another inside the same compiled program (each chain
            pays only for its own trajectories: faster where a batch of k model
            evaluations costs k single ones, e.g. LAPACK-bound eigen-solves on few cores).
            ``None`` (default): vmapped on an accelerator, one after another on a CPU
            (:func:`~axojax.inverse.sampling.vectorize_chains`).
        progress: progress bars on stderr (:mod:`axojax._progress`): the warm-up's
            elapsed time (one compiled program), then the draws with rate and time left.
        on_laplace: called with the :class:`Laplace` approximation at the centre as soon
            as it exists, before the warm-up (e.g. to print the fast answer); the result
            keeps it too (``Posterior.laplace``) and says how far the draws moved from it.
        cache: keep the run's start-up (the centre and Laplace approximation, the
            chains' starts and the warm-up's adapted state) in a small file, and start
            an identical run from it, straight at the draws (bitwise the same draws):
            ``None``/``False``: no (default); ``True``: in ``posterior/`` of the command
            line's cache directory (``AXOJAX_CACHE_DIR``, ``off`` honoured:
            :func:`axojax.cache.posterior_cache_dir`); a path: that directory. Keyed by
            a sha256 of the problem (its ``fingerprint()``), prior, sampler, warm-up,
            chains, seed, init and library versions; a problem without a fingerprint,
            or a callable prior, runs uncached (:mod:`._warm_cache`); the fit that
            ``init=None`` runs first is not kept.
            ``Posterior.warm_cache`` says what happened: "off", "stored", "loaded".
        transport: sample in coordinates that straighten a curved ridge
            (:class:`~axojax.inverse.sampling.transport.ProfileTransport`, e.g.
            ``ProfileTransport("ks")``: the profile along ks is tabulated from the centre
            before the warm-up; the posterior is exactly the same, the trajectories
            shorter). ``None``: the affine whitening alone. ``"auto"`` (default): what
            :func:`suggest_transport` picks from the least-squares fit the chains start
            from (``init``, or the fit ``init=None`` runs), as ``axojax fit --posterior``
            does without ``--along``; the affine whitening from any other start.

    Returns:
        :class:`Posterior`. Warns (one line each) when a parameter's R-hat exceeds
        ``diagnostics.RHAT_MAX`` (1.01), when its bulk or tail ESS is below
        ``diagnostics.ESS_MIN_PER_CHAIN`` (100) per chain, or when transitions diverged,
        and when more than ``SATURATION_WARN`` of the draws' trees reached
        ``sampler.max_num_doublings`` (what to do: in the warning).
    """
    prior = _check(problem, draws, chains, warmup, sampler, prior)
    return sampler.run(
        problem,
        draws=int(draws),
        chains=int(chains),
        warmup=None if warmup is None else int(warmup),
        seed=seed,
        init=init,
        prior=prior,
        vectorize=vectorize,
        progress=progress,
        on_laplace=on_laplace,
        cache=cache,
        transport=transport,
    )


def _check(problem, draws, chains, warmup, sampler, prior):
    """The prior as a callable (or None), after checking the arguments every sampler
    shares (one-line ``ValueError`` / ``TypeError``)."""
    names = tuple(problem.names)
    k = len(names)
    lower = np.asarray(problem.lower, dtype=float).reshape(-1)
    upper = np.asarray(problem.upper, dtype=float).reshape(-1)
    if k == 0 or lower.shape != (k,) or upper.shape != (k,):
        raise ValueError(
            f"problem: names, lower and upper must have one entry per free parameter, got {k}, "
            f"{lower.shape}, {upper.shape}"
        )
    for name, value in (("draws", draws), ("chains", chains)):
        if not (isinstance(value, (int, np.integer)) and value >= 1):
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if draws < 4:
        raise ValueError(f"draws must be >= 4 (R-hat splits each chain), got {draws}")
    if warmup is not None and not (isinstance(warmup, (int, np.integer)) and warmup >= 0):
        raise ValueError(f"warmup must be an integer >= 0 or None, got {warmup!r}")
    if not isinstance(sampler, AbstractSampler):
        raise TypeError(
            "sampler must be an axojax.inverse.AbstractSampler (NUTS, SMC, ModeMixture or "
            f"a subclass of one's own), got {type(sampler).__name__}"
        )
    if isinstance(prior, Mapping):
        prior = normal_prior(names, prior)
    elif prior is not None and not callable(prior):
        raise TypeError(
            f"prior must be a callable log_prior(u), a {{name: (mean_u, sd_u)}} mapping or "
            f"None, got {type(prior).__name__}"
        )
    return prior
