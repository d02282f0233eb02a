"""``posterior``: Bayesian posterior of an inverse problem's free parameters by NUTS.

The sampler runs in the problem's unconstrained coordinate ``z`` (R^k), where
``problem.log_density(z)`` is the log posterior: ``-1/2 |residuals(u)|^2 + log_prior(u)``
plus the log-Jacobian of the logistic map ``u = to_u(z)`` onto the bounds of the fitted
coordinate ``u`` (log of positive parameters, linear for ``gamma``). The prior is
therefore stated in ``u``: uniform between the bounds by default (the problem's
``log_prior``), or replaced here (a callable ``log_prior(u)``, or a normal in ``u`` per
parameter: :func:`normal_prior`).

Sampler: the No-U-Turn sampler of blackjax (``blackjax.nuts``) with Stan's window
adaptation (``blackjax.window_adaptation``: dual-averaged step size, mass matrix from
the warm-up draws). blackjax rather than numpyro because the model is already a pure
jax function of ``z``: blackjax takes that log density as it is, exposes the kernel to
``jax.vmap``/``lax.scan`` (chains vmapped, steps scanned, all inside one ``jit``), and
adds no model language, tracing runtime or handlers on top of axojax's own derivatives.

Chains: every chain adapts its own step size and mass matrix (Stan's convention: the
chains stay independent, so R-hat compares independent runs), the warm-ups vmapped
together, then the NUTS kernels of all chains are vmapped and stepped with
``jax.lax.scan``. They start from the maximum of the posterior density (optimistix
Levenberg-Marquardt in ``z`` from ``problem.u0``, then Gauss-Newton steps on the whole
density) and a spread around it drawn from its Laplace approximation (Gauss-Newton
``J^T J`` plus the prior's and the map's curvature). The sampler runs in coordinates
whitened by that approximation (``w = L^-1 (z - z_c)``, ``L L^T`` its covariance: an
affine map, so the same posterior), where the adaptation starts from the identity:
on the benchmark's sloppy model it took about 8x fewer gradients per effective
sample than sampling in z (one short run each: ``benchmarks/bench_posterior.py``).

Result: :class:`Posterior` (draws per chain in ``u`` and in parameter values, mean, sd,
5/50/95 % quantiles, rank-normalised R-hat and bulk/tail ESS per parameter, divergences,
timings) with ``to_json()`` (the ``"posterior"`` block of ``axojax fit --posterior``)
and ``save(path)`` (an ``.npz`` that :func:`axojax.plotting.corner.plot_corner` draws).
"""

from __future__ import annotations

import math
import os
import time
import warnings
from collections.abc import Callable, Mapping
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array

from ..._progress import progress as progress_bar
from ..._progress import stage
from ...cache import posterior_cache_dir
from ...results import RESULTS, message
from . import _nuts, _warm_cache, diagnostics
from ._densities import InverseProblem, _Target, _Whitened, normal_prior
from ._laplace import Laplace, _starts, laplace_of
from ._nuts import DEFAULT_NUTS, NUTS, _init_states, _sample, _to_u, _warmup
from ._posterior_result import Posterior
from ._smc import SMC
from ._summaries import _Clock, _statistics, _value_draws
from .modes import ModeMixture, mode_posterior
from .smc import smc_posterior
from .transport import PROFILE_DROP, ProfileMap, ProfileTransport, build_map, profile_ends

SAMPLE_CHUNK = 50
"""Draws per compiled sampling call: one program for any number of draws (the last
chunk's surplus is dropped)."""
SATURATION_WARN = 0.01
"""Warn when more than this share of the draws' trees reached ``max_num_doublings``."""


def posterior(
    problem: InverseProblem,
    *,
    draws: int = 1000,
    chains: int = 4,
    warmup: int = 500,
    seed: int = 0,
    init: Any = None,
    prior: Callable[[Array], Array] | Mapping[str, tuple[float, float]] | None = None,
    sampler: NUTS | SMC | ModeMixture = DEFAULT_NUTS,
    vectorize: bool = True,
    progress: bool = False,
    on_laplace: Callable[[Laplace], None] | None = None,
    cache: bool | str | os.PathLike | None = None,
    transport: ProfileTransport | None = None,
) -> Posterior:
    """Sample the posterior of ``problem``'s free parameters with NUTS.

    Args:
        problem: an :class:`InverseProblem` (e.g. :class:`axojax.inverse.Problem`).
        draws: draws per chain kept after warm-up.
        chains: independent chains (vmapped unless ``vectorize=False``).
        warmup: window-adaptation steps per chain (Stan's schedule; at least 150 gives
            its full set of windows), discarded.
        seed: seed of the chains and their starts.
        init: where the chains start. ``None``: the posterior mode (Levenberg-Marquardt
            in ``z`` from ``problem.u0``) and a spread drawn from its Laplace approximation;
            a (k,) point in ``u``, or a least-squares result
            (:func:`axojax.inverse.least_squares`' ``FitResult``, its optimum): a spread
            around it; a (chains, k) array in ``u``: these starts exactly.
        prior: replaces ``problem.log_prior``: a jax-traceable ``log_prior(u)``, or
            ``{name: (mean_u, sd_u)}`` (:func:`normal_prior`). ``None``: the problem's
            own prior (uniform in ``u`` by default).
        sampler: :class:`NUTS` settings, or :class:`SMC`: ``chains`` independent runs of
            adaptive tempered SMC from the prior (:mod:`.smc`; for several modes or cliffs;
            ``init``, ``warmup``, ``vectorize``, ``on_laplace`` and ``cache`` then do not
            apply, a ``transport`` is refused); or :class:`ModeMixture`: independence
            Metropolis-Hastings chains from a mixture fitted to every mode (:mod:`.modes`;
            ``init`` seeds the fit's optima; a ``transport`` is refused).
        vectorize: run the chains vmapped (they step together, each NUTS step costing
            the longest of the chains' trajectories; batched model evaluations), or,
            ``False``, one after another inside the same compiled program (each chain
            pays only for its own trajectories: faster where a batch of k model
            evaluations costs k single ones, e.g. LAPACK-bound eigen-solves on few cores).
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
            or a callable prior, runs uncached (:mod:`._warm_cache`).
            ``Posterior.warm_cache`` says what happened: "off", "stored", "loaded".
        transport: sample in coordinates that straighten a curved ridge
            (:class:`~axojax.inverse.sampling.transport.ProfileTransport`, e.g.
            ``ProfileTransport("ks")``: the profile along ks is tabulated from the centre
            before the warm-up; the posterior is exactly the same, the trajectories
            shorter). ``None``: the affine whitening alone.

    Returns:
        :class:`Posterior`. Warns (one line each) when a parameter's R-hat exceeds
        ``diagnostics.RHAT_MAX`` (1.01), when its bulk or tail ESS is below
        ``diagnostics.ESS_MIN_PER_CHAIN`` (100) per chain, or when transitions diverged,
        and when more than ``SATURATION_WARN`` of the draws' trees reached
        ``sampler.max_num_doublings`` (what to do: in the warning).
    """
    t_start = time.perf_counter()
    own_prior = prior is None
    names, lower, upper, prior = _check(problem, draws, chains, warmup, sampler, prior)
    if isinstance(sampler, SMC):  # independent runs from the prior: .smc
        return smc_posterior(problem, sampler, (draws, chains, seed), prior, progress, transport)
    if isinstance(sampler, ModeMixture):  # a mixture proposal fitted to every mode: .modes
        if transport is not None:
            raise ValueError("transport: applies to NUTS; ModeMixture samples z as it is")
        return mode_posterior(problem, sampler, (draws, chains, seed), prior, progress, init)
    along = _check_transport(transport, names)
    directory = posterior_cache_dir(cache)
    target = _Target(problem, prior)
    clock = _Clock()
    key_init, key_warm, key_sample = jax.random.split(jax.random.PRNGKey(seed), 3)
    t0 = time.perf_counter()
    run_key, file, warm = _cached(
        directory, problem, prior, sampler, warmup, chains, seed, init, vectorize, transport
    )
    warm_cache = "off" if file is None else ("loaded" if warm is not None else "stored")
    if warm is not None:  # an identical run's start-up: straight to the draws
        start = (None, None, None, warm.start_u, (warm.u_c, warm.precision_u))
    else:
        start = _starts(target, init, chains, key_init, clock.call)
    start_u, (u_c, precision_u) = start[3:]
    laplace = laplace_of(problem, names, u_c, precision_u)
    seconds = {"start": time.perf_counter() - t0}
    if on_laplace is not None:
        on_laplace(laplace)
    compile_start = clock.seconds

    t0 = time.perf_counter()
    sampled, states, step_size, imm, warm_grads = _warm_up(
        target,
        sampler,
        warm,
        start,
        key_warm,
        clock,
        _transport_spec(transport, along, init, own_prior),
        cache=(file, run_key),
        shape=(chains, warmup),
        vectorize=vectorize,
        progress=progress,
    )
    seconds["warmup"] = 0.0 if warm_cache == "loaded" else time.perf_counter() - t0
    t0, compile_draws = time.perf_counter(), clock.seconds
    out = _draw(
        sampled, sampler, states, step_size, imm, draws, vectorize, key_sample, progress, clock
    )
    seconds["sampling"] = time.perf_counter() - t0
    seconds["compile_chains"] = clock.seconds - compile_start
    seconds["compile_draws"] = clock.seconds - compile_draws
    return _summarise(
        problem,
        target,
        sampled,
        sampler,
        clock,
        out,
        names=names,
        bounds=(lower, upper),
        shape=(chains, draws, warmup),
        adapted=(step_size, warm_grads),
        laplace=laplace,
        transport=transport,
        start_u=start_u,
        warm_cache=warm_cache,
        seconds=seconds,
        t_start=t_start,
    )


def _cached(directory, problem, prior, sampler, warmup, chains, seed, init, vectorize, transport):
    """The warm cache of this run (:mod:`._warm_cache`): its key and file (None: uncached)
    and the start-up an identical run stored there (None: none, or none that fits)."""
    run_key = None
    if directory is not None:
        run_key = _warm_cache.run_key(
            problem, prior, sampler, warmup, chains, seed, init, vectorize, transport
        )
    file = None if run_key is None else _warm_cache.path_of(directory, run_key)
    warm = None if file is None else _warm_cache.load(file, run_key, chains, len(problem.names))
    if warm is not None and (transport is not None) != bool(warm.profile):
        warm = None  # cannot happen with an honest key; recompute rather than guess
    return run_key, file, warm


def _transport_spec(transport, along, init, own_prior):
    """What :func:`_adapt` takes of a transport: (index, knots, respread, built), or None
    without one."""
    if transport is None:
        return None
    return along, int(transport.knots), _spread(init), _built(transport, own_prior)


def _warm_up(target, sampler, warm, start, key, clock, spec, *, cache, shape, vectorize, progress):
    """The sampled density and, per chain, the state after the warm-up, its step size,
    inverse mass matrix and gradients spent: resumed from ``warm`` (an identical run's,
    from the warm cache) when given, else adapted from ``start`` (what :func:`._starts`
    returned) with the transport ``spec`` (:func:`_transport_spec`) and kept in the
    ``cache`` = (file, run_key) when it has a file. ``shape``: (chains, warmup)."""
    if warm is not None:
        return _resume(target, sampler, warm, None if spec is None else spec[0])
    chains, warmup = shape
    z_start, z_c, cov, start_u, (u_c, precision_u) = start
    with stage(f"posterior warm-up ({chains} x {warmup} steps)", enable=progress):
        adapted = _adapt(
            target, sampler, warmup, vectorize, key, z_start, z_c, cov, clock.call, spec
        )
    file, run_key = cache
    if file is not None:
        sampled, *rest = adapted
        _store(file, run_key, sampled, sampler, (z_c, cov, u_c, precision_u, start_u), rest)
    return adapted


def _store(file, run_key, sampled, sampler, start, adapted) -> None:
    """Keep the run's start-up in the warm cache: ``start`` = (z_c, cov, u_c, precision_u,
    start_u), ``adapted`` = the warm-up's (states, step_size, imm, warm_grads), with the
    whitening's Cholesky factor and the transport's map."""
    z_c, cov, u_c, precision_u, start_u = start
    states, step_size, imm, warm_grads = adapted
    chol = sampled.chol if sampler.whiten else jnp.eye(len(z_c))
    transported = isinstance(sampled, _Whitened) and sampled.transport is not None
    profile = _profile_arrays(sampled.transport) if transported else ()
    warm = _warm_cache.Warm(
        *(np.asarray(x) for x in (z_c, cov, chol, u_c, precision_u, start_u)),
        state=tuple(np.asarray(x) for x in states),
        step_size=np.asarray(step_size),
        imm=np.asarray(imm),
        warm_grads=np.asarray(warm_grads),
        profile=profile,
    )
    _warm_cache.save(file, run_key, warm)


def _summarise(
    problem,
    target,
    sampled,
    sampler,
    clock,
    out,
    *,
    names,
    bounds,
    shape,
    adapted,
    laplace,
    transport,
    start_u,
    warm_cache,
    seconds,
    t_start,
) -> Posterior:
    """The :class:`Posterior` of the draws ``out`` (what :func:`_draw` returned, in the
    sampled coordinate), warning (for :func:`posterior`'s caller) when the chains are not
    to be trusted or the trees were cut short. ``shape``: (chains, draws, warmup);
    ``adapted``: the warm-up's (step_size, warm_grads); ``seconds``: start, warmup,
    sampling, compile_chains and compile_draws; ``t_start``: when the run began."""
    z, logd, divergent, n_steps, accept, depth, spent = out
    chains, draws, warmup = shape
    step_size, warm_grads = adapted
    if isinstance(sampled, _Whitened):
        z = np.asarray(sampled.to_z(jnp.asarray(z)))
    u = np.asarray(clock.call(_to_u, None, target, jnp.asarray(z)))
    value_names, values, log_coordinate = _value_draws(problem, names, u, clock.call)
    k = len(names)
    summ = diagnostics.summary(values[..., :k])
    flat_u = u.reshape(-1, k)
    gradients = int(np.sum(warm_grads)) + spent  # every evaluation of the chains, warm-up included
    total = time.perf_counter() - t_start
    ess_min = float(np.min(summ["ess_bulk"]))
    n_div = int(np.sum(divergent))
    notes = diagnostics.sampler_notes(names, summ, chains, chains * draws, n_div)
    if n_div and transport is not None:
        notes.append(_cliff_note(sampled.transport, problem, transport.along, laplace))
    for note in notes:
        warnings.warn(note, stacklevel=3)
    saturated = float(np.mean(depth >= sampler.max_num_doublings))
    if saturated > SATURATION_WARN:
        warnings.warn(_saturation_note(saturated, sampler, n_steps), stacklevel=3)
    stats = _statistics(names, summ, flat_u)
    moved = laplace.check(stats["mean_u"], stats["sd_u"])
    work = seconds["warmup"] + seconds["sampling"] - seconds["compile_chains"]
    result = RESULTS.successful if not notes else RESULTS.chains_not_converged
    return Posterior(
        names=names,
        u=u,
        value_names=value_names,
        values=values,
        log_density=np.asarray(logd),
        divergent=np.asarray(divergent, dtype=bool),
        lower=bounds[0],
        upper=bounds[1],
        log_coordinate=log_coordinate,
        **stats,
        divergences=n_div,
        step_size=np.asarray(step_size, dtype=float),
        acceptance=float(np.mean(accept)),
        warmup=int(warmup),
        gradients=gradients,
        seconds=total,
        seconds_compile=clock.seconds,
        seconds_start=seconds["start"],
        seconds_warmup=seconds["warmup"],
        seconds_sampling=seconds["sampling"],
        seconds_per_gradient=work / max(gradients, 1),
        seconds_per_ess=total / ess_min if ess_min > 0 else math.inf,
        start_u=start_u,
        message="; ".join(notes) or message(result),
        result=result,
        laplace=laplace,
        sd_ratio=moved["sd_ratio"],
        shift=moved["shift"],
        tree_depth=float(np.mean(depth)),
        tree_depth_saturated=saturated,
        max_num_doublings=int(sampler.max_num_doublings),
        gradients_per_draw=float(np.mean(n_steps)),
        warm_cache=warm_cache,
        seconds_compile_draws=seconds["compile_draws"],
        transport=None if transport is None else transport.along,
    )


def _cliff_note(profile, problem, along: str, laplace: Laplace) -> str:
    """Where the transport's profile ends (a cliff of the log density that trajectories
    reaching it diverge at), for the divergence warning."""
    ends = profile_ends(profile, problem.to_u, laplace.log_coordinate.get(along, False))
    if not ends:
        return f"the profile of {along} spans its bounds: the divergences are not at its ends"
    where = " and ".join(f"{v:.4g}" for v in ends)
    return (
        f"the profile of {along} ends at {along} ~ {where} (the log density falls by over "
        f"{PROFILE_DROP:g} there, e.g. where another eigenmode becomes the dominant one): "
        "trajectories that reach such a cliff diverge"
    )


def _saturation_note(saturated: float, sampler: NUTS, n_steps: np.ndarray) -> str:
    """One line: how often the trees hit the depth limit, and what to do."""
    return (
        f"NUTS tree depth reached max_num_doublings={sampler.max_num_doublings} in "
        f"{100 * saturated:.0f} % of draws ({float(np.mean(n_steps)):.0f} gradients per draw): "
        "the trajectories were cut short, so the draws are more correlated than they need be; "
        f"raise it (NUTS(max_num_doublings={sampler.max_num_doublings + 2})), or, for a long "
        "curved ridge, sample along its profile (transport=ProfileTransport(NAME); "
        "axojax fit --along NAME)"
    )


def _check(problem, draws, chains, warmup, sampler, prior):
    """The problem's names and bounds in u, and the prior as a callable (or None), after
    checking every argument (one-line ``ValueError`` / ``TypeError``)."""
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
    if not (isinstance(warmup, (int, np.integer)) and warmup >= 0):
        raise ValueError(f"warmup must be an integer >= 0, got {warmup!r}")
    if not isinstance(sampler, (NUTS, SMC, ModeMixture)):
        raise TypeError(
            f"sampler must be an axojax.inverse.NUTS, SMC or ModeMixture, got {type(sampler).__name__}"
        )
    if isinstance(prior, Mapping):
        prior = normal_prior(names, prior)
    elif prior is not None and not callable(prior):
        raise TypeError(
            f"prior must be a callable log_prior(u), a {{name: (mean_u, sd_u)}} mapping or "
            f"None, got {type(prior).__name__}"
        )
    return names, lower, upper, prior


def _check_transport(transport, names) -> int | None:
    """Index of the transport's parameter (None without one); one-line errors."""
    if transport is None:
        return None
    if not isinstance(transport, ProfileTransport):
        raise TypeError(
            f"transport must be an axojax.inverse.ProfileTransport or None, got {type(transport).__name__}"
        )
    along = transport.index(names)
    profile = transport.profile
    if profile is not None and (profile.along != along or len(profile.rest) != len(names) - 1):
        raise ValueError(
            f"ProfileTransport: its profile map goes along coordinate {profile.along} of "
            f"{len(profile.rest) + 1}; this problem's {transport.along!r} is coordinate {along} "
            f"of {len(names)} (build the map for this problem, or leave profile=None)"
        )
    return along


def _spread(init) -> bool:
    """Whether the starts are a spread the sampler may redraw (not given per chain)."""
    return init is None or hasattr(init, "params") or np.ndim(init) != 2


def _built(transport, own_prior: bool):
    """``transport``'s map already tabulated (checked to go along coordinate ``along``),
    where it can serve: for the problem's own prior; else None."""
    return transport.profile if own_prior else None


def _adapt(target, sampler, warmup, vectorize, key, z_start, z_c, cov, call, transport=None):
    """The sampled density (whitened unless ``NUTS(whiten=False)``; straightened first by
    the profile map of ``transport`` = (index, knots, respread, built) when given: the map
    ``built`` if not None, else tabulated from ``z_c``; the starts then redrawn from the
    profile's marginal unless ``respread`` is False) and, per chain, the state after the
    warm-up, its step size, inverse mass matrix and gradients spent."""
    k = z_c.shape[0]
    chains = z_start.shape[0]
    if transport is not None:  # y = the profile's coordinates: standard normal to its accuracy
        along, knots, respread, built = transport
        profile = built if built is not None else call(build_map, (along, knots), target, z_c)
        sampled = _Whitened(target, jnp.zeros(k), jnp.eye(k), profile)
        if respread:  # the chains start spread along the whole ridge
            key, key_starts = jax.random.split(key)
            x_start = profile.draw_y(key_starts, chains)
        else:
            x_start = sampled.to_w(z_start)
        x_c, cov_x = jnp.zeros(k), jnp.eye(k)
    elif sampler.whiten:  # sample w = L^-1 (z - z_c): the Laplace covariance becomes the identity
        sampled = _Whitened(target, z_c, jnp.linalg.cholesky(cov))
        x_start, x_c, cov_x = sampled.to_w(z_start), jnp.zeros(k), jnp.eye(k)
    else:
        sampled, x_start, x_c, cov_x = target, z_start, z_c, cov
    imm0 = cov_x if sampler.dense_mass else jnp.diag(cov_x)
    if warmup > 0:
        states, step_size, imm, warm_grads = call(
            _warmup,
            (sampler, int(warmup), bool(vectorize)),
            sampled,
            jax.random.split(key, chains),
            x_start,
            x_c,
            imm0,
        )
    else:  # no adaptation: the Laplace covariance as mass matrix, a moderate step
        states = call(_init_states, None, sampled, x_start, x_c)
        step_size = jnp.full(chains, 0.5)
        imm = jnp.broadcast_to(imm0, (chains, *imm0.shape))
        warm_grads = jnp.full(chains, _nuts.START_EVALUATIONS)
    jax.block_until_ready(states)
    return sampled, states, step_size, imm, warm_grads


def _profile_arrays(profile: ProfileMap) -> tuple:
    return tuple(np.asarray(getattr(profile, n)) for n in _warm_cache.PROFILE_FIELDS)


def _resume(target, sampler, warm, along=None):
    """The sampled density and the chains' state, step sizes, inverse mass matrices and
    warm-up gradients kept by an identical run (:mod:`._warm_cache`), as :func:`_adapt`
    returned them (with a transport along coordinate ``along``: its map too)."""
    from blackjax.mcmc.hmc import HMCState

    if along is not None:
        k = len(warm.z_c)
        profile = ProfileMap(
            along=along,
            rest=tuple(i for i in range(k) if i != along),
            **{n: jnp.asarray(x) for n, x in zip(_warm_cache.PROFILE_FIELDS, warm.profile)},
        )
        sampled = _Whitened(target, jnp.zeros(k), jnp.eye(k), profile)
    elif sampler.whiten:
        sampled = _Whitened(target, jnp.asarray(warm.z_c), jnp.asarray(warm.chol))
    else:
        sampled = target
    states = HMCState(*(jnp.asarray(x) for x in warm.state))
    return sampled, states, jnp.asarray(warm.step_size), jnp.asarray(warm.imm), warm.warm_grads


def _draw(sampled, sampler, states, step_size, imm, draws, vectorize, key, progress, clock):
    """``draws`` NUTS steps of every chain, in chunks of :data:`SAMPLE_CHUNK` (one
    compiled program): positions, log densities, divergent, gradients, acceptance
    rates and tree depths, each (chains, draws, ...), and the gradients of every step
    run (the last chunk's dropped surplus included: evaluated, so counted)."""
    chains = step_size.shape[0]
    n_chunks = -(-draws // SAMPLE_CHUNK)
    keys = jax.random.split(key, n_chunks * chains * SAMPLE_CHUNK).reshape(
        n_chunks, chains, SAMPLE_CHUNK, -1
    )
    outs = []
    with progress_bar(
        total=chains * draws, desc="posterior draws", unit="draw", enable=progress
    ) as bar:
        for i in range(n_chunks):
            states, out = clock.call(
                _sample, (sampler, bool(vectorize)), sampled, states, step_size, imm, keys[i]
            )
            outs.append(jax.device_get(out))
            bar.update(chains * min(SAMPLE_CHUNK, draws - i * SAMPLE_CHUNK))
    spent = int(sum(np.sum(o[3]) for o in outs))
    return (*(np.concatenate([o[j] for o in outs], axis=1)[:, :draws] for j in range(6)), spent)
