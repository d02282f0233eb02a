"""The No-U-Turn sampler (:class:`NUTS`): its settings, the defaults of a run (the
warm-up: :func:`warmup_steps`; the chains' layout: :func:`vectorize_chains`) and the run
(:meth:`NUTS.run`, what :func:`~axojax.inverse.posterior` calls; its compiled programs in
:mod:`._nuts_kernels`).

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
chains stay independent, so R-hat compares independent runs), the warm-ups together,
then the NUTS kernels of all chains stepped with ``jax.lax.scan``, the chains vmapped on
an accelerator and one after another on a CPU (:func:`vectorize_chains`). They start
from a least-squares optimum (``init``; an axojax ``Problem`` given none: the best of
its 16-start fit, :func:`._laplace.fitted_init`), or else from the maximum of the
posterior density (optimistix Levenberg-Marquardt in ``z`` from ``problem.u0``, then
Gauss-Newton steps on the whole density), and a spread around it drawn from its
Laplace approximation (Gauss-Newton
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
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np

from ..._progress import stage
from ...cache import posterior_cache_dir
from ...results import RESULTS, message
from . import _nuts_kernels as kernels
from . import _warm_cache, diagnostics
from ._densities import LogDensity, Whitened
from ._laplace import Laplace, chain_starts, fitted_init, laplace_of
from ._posterior_result import Posterior
from ._sampler import AUTO, AbstractSampler
from .programs import Clock
from .summaries import statistics, to_u, value_draws
from .transport import PROFILE_DROP, ProfileMap, ProfileTransport, profile_ends
from .transport_choice import suggest_transport

MIN_WARMUP = 150
"""Fewest warm-up steps by default: Stan's schedule has its full set of adaptation
windows from 150."""
MAX_DEFAULT_WARMUP = 500
"""Most warm-up steps by default (:func:`warmup_steps`)."""
MAX_ALONG_WARMUP = 200
"""Most warm-up steps by default with a transport: the chains start from draws of the
profile's approximation of the posterior, in coordinates where it is about a standard
normal, so a shorter warm-up does (synthetic benchmark, 4 x 1000 draws: 500 steps R-hat
1.0003/1.0005, ESS 2736/2495; 200 steps 1.0004/1.0007, 2394/2313: docs/benchmarks.md)."""
SATURATION_WARN = 0.01
"""Warn when more than this share of the draws' trees reached ``max_num_doublings``."""


def warmup_steps(draws: int, warmup: int | None = None, along: str | None = None) -> int:
    """The warm-up of a run: ``warmup`` when given, else ``draws`` clipped to
    [:data:`MIN_WARMUP`, :data:`MAX_DEFAULT_WARMUP`] (:data:`MAX_ALONG_WARMUP` with a
    transport along the parameter ``along``)."""
    if warmup is not None:
        return int(warmup)
    top = MAX_DEFAULT_WARMUP if along is None else MAX_ALONG_WARMUP
    return min(max(int(draws), MIN_WARMUP), top)


def vectorize_chains() -> bool:
    """Whether the chains run vmapped by default: not on a CPU, where they run one after
    another (vmapped, every NUTS step costs the longest of the chains' trees, and a batch
    of eigen-solves costs about as much as the same solves one by one). Measured on 2
    cores, 4 chains x 1000 draws (docs/benchmarks.md): the human sperm 245.5 s vmapped,
    205.4 s sequential (6.1 and 4.3 ms per gradient); the synthetic target with a
    transport along ks 8.8 and 5.2 ms per gradient. On an accelerator (not measured)
    vmapped."""
    return jax.default_backend() != "cpu"


class NUTS(AbstractSampler):
    """The No-U-Turn sampler (blackjax) and its window adaptation.

    Attributes:
        max_num_doublings: tree depth limit (at most ``2**max_num_doublings - 1``
            gradients per draw).
        target_acceptance_rate: the step-size adaptation's target (Stan: 0.8; raise it
            towards 0.95 when there are divergences).
        dense_mass: adapt a dense mass matrix (default: the fitted parameters of a
            sloppy model are strongly correlated and k is small, so the k x k
            covariance costs nothing and removes the correlation); ``False``: diagonal.
        divergence_threshold: energy error above which a trajectory counts as divergent.
        whiten: sample in ``w = L^-1 (z - z_c)``, where ``z_c`` is the centre of the
            starts and ``L L^T`` the Laplace covariance there (an affine map: its
            Jacobian is a constant, the posterior is exactly the same). The adaptation
            then starts from a near-identity covariance, whose scale its regularisation
            (blackjax/Stan shrink the estimated covariance towards ``1e-3 I``) does not
            distort; in z a sloppy model's stiffest direction has an sd of ~1e-3, which
            that shrinkage inflates several-fold, forcing small steps (measured: see
            ``benchmarks/bench_posterior.py``).
    """

    max_num_doublings: int = 8
    target_acceptance_rate: float = 0.8
    dense_mass: bool = True
    divergence_threshold: float = 1000.0
    whiten: bool = True

    def __check_init__(self):
        if not (1 <= self.max_num_doublings <= 15):
            raise ValueError(
                f"NUTS: max_num_doublings must be in 1..15, got {self.max_num_doublings}"
            )
        if not (0.0 < self.target_acceptance_rate < 1.0):
            raise ValueError(
                f"NUTS: target_acceptance_rate must be in (0, 1), got {self.target_acceptance_rate}"
            )

    def run(
        self,
        problem,
        *,
        draws,
        chains,
        warmup,
        seed,
        init,
        prior,
        vectorize,
        progress,
        on_laplace,
        cache,
        transport,
    ) -> Posterior:
        """``chains`` chains of ``draws`` draws after ``warmup`` window-adaptation steps
        (None: :func:`warmup_steps`), from ``init`` (None, for an axojax
        :class:`~axojax.inverse.Problem`: its :data:`._laplace.POSTERIOR_STARTS`-start
        least-squares fit, :func:`._laplace.fitted_init`), in the coordinates
        ``transport`` straightens (``"auto"``: what
        :func:`~axojax.inverse.suggest_transport` picks from a least-squares fit it
        starts from, else the affine whitening alone), vmapped or one after another
        (``vectorize``; None: :func:`vectorize_chains`). :func:`~axojax.inverse.posterior`
        says the rest."""
        names = tuple(problem.names)
        directory = posterior_cache_dir(cache)
        if not _is_auto(transport):  # refused before any work
            _check_transport(transport, names)
        init = fitted_init(problem, init, progress)
        if _is_auto(transport):
            transport = _suggested(problem, init, progress)
        along = _check_transport(transport, names)
        warmup = warmup_steps(draws, warmup, None if transport is None else transport.along)
        vectorize = vectorize_chains() if vectorize is None else bool(vectorize)
        t_start = time.perf_counter()
        target = LogDensity(problem, prior)
        clock = Clock()
        key_init, key_warm, key_sample = jax.random.split(jax.random.PRNGKey(seed), 3)
        t0 = time.perf_counter()
        run_key, file, warm = _cached(
            directory, problem, prior, self, warmup, chains, seed, init, vectorize, transport
        )
        warm_cache = "off" if file is None else ("loaded" if warm is not None else "stored")
        if warm is not None:  # an identical run's start-up: straight to the draws
            start = (None, None, None, warm.start_u, (warm.u_c, warm.precision_u))
        else:
            start = chain_starts(target, init, chains, key_init, clock.call)
        start_u, (u_c, precision_u) = start[3:]
        laplace = laplace_of(problem, names, u_c, precision_u)
        seconds = {"start": time.perf_counter() - t0}
        if on_laplace is not None:
            on_laplace(laplace)
        compile_start = clock.seconds

        t0 = time.perf_counter()
        sampled, states, step_size, imm, warm_grads = _warm_up(
            target,
            self,
            warm,
            start,
            key_warm,
            clock,
            _transport_spec(transport, along, init, prior is None),
            cache=(file, run_key),
            shape=(chains, warmup),
            vectorize=vectorize,
            progress=progress,
        )
        seconds["warmup"] = 0.0 if warm_cache == "loaded" else time.perf_counter() - t0
        t0, compile_draws = time.perf_counter(), clock.seconds
        out = kernels.draw(
            sampled, self, states, step_size, imm, draws, vectorize, key_sample, progress, clock
        )
        seconds["sampling"] = time.perf_counter() - t0
        seconds["compile_chains"] = clock.seconds - compile_start
        seconds["compile_draws"] = clock.seconds - compile_draws
        return _summarise(
            problem,
            target,
            sampled,
            self,
            clock,
            out,
            names=names,
            bounds=(
                np.asarray(problem.lower, dtype=float).reshape(-1),
                np.asarray(problem.upper, dtype=float).reshape(-1),
            ),
            shape=(chains, draws, warmup),
            adapted=(step_size, warm_grads),
            laplace=laplace,
            transport=transport,
            start_u=start_u,
            warm_cache=warm_cache,
            seconds=seconds,
            t_start=t_start,
        )


DEFAULT_NUTS = NUTS()


def _is_auto(transport) -> bool:
    return isinstance(transport, str) and transport == AUTO


def _suggested(problem, init, progress: bool) -> ProfileTransport | None:
    """``transport="auto"``: :func:`~axojax.inverse.suggest_transport` of the least-squares
    fit ``init`` (a ``FitResult``: what ``axojax fit --posterior`` samples along); from any
    other start, None (the affine whitening alone)."""
    if not (hasattr(init, "params") and hasattr(init, "correlation")):
        return None
    with stage("posterior coordinates (profiles)", enable=progress):
        return suggest_transport(problem, init)


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
    """What :func:`._nuts_kernels.adapt` takes of a transport: (index, knots, respread, built), or None
    without one."""
    if transport is None:
        return None
    return along, int(transport.knots), _spread(init), _built(transport, own_prior)


def _warm_up(target, sampler, warm, start, key, clock, spec, *, cache, shape, vectorize, progress):
    """The sampled density and, per chain, the state after the warm-up, its step size,
    inverse mass matrix and gradients spent: resumed from ``warm`` (an identical run's,
    from the warm cache) when given, else adapted from ``start`` (what
    :func:`._laplace.chain_starts` returned) with the transport ``spec``
    (:func:`_transport_spec`) and kept in the ``cache`` = (file, run_key) when it has a
    file. ``shape``: (chains, warmup)."""
    if warm is not None:
        return kernels.resume(target, sampler, warm, None if spec is None else spec[0])
    chains, warmup = shape
    z_start, z_c, cov, start_u, (u_c, precision_u) = start
    with stage(f"posterior warm-up ({chains} x {warmup} steps)", enable=progress):
        adapted = kernels.adapt(
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
    transported = isinstance(sampled, Whitened) and sampled.transport is not None
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
    """The :class:`Posterior` of the draws ``out`` (what :func:`._nuts_kernels.draw` returned, in the
    sampled coordinate), warning (for :func:`~axojax.inverse.posterior`'s caller) when the chains are not
    to be trusted or the trees were cut short. ``shape``: (chains, draws, warmup);
    ``adapted``: the warm-up's (step_size, warm_grads); ``seconds``: start, warmup,
    sampling, compile_chains and compile_draws; ``t_start``: when the run began."""
    z, logd, divergent, n_steps, accept, depth, spent = out
    chains, draws, warmup = shape
    step_size, warm_grads = adapted
    if isinstance(sampled, Whitened):
        z = np.asarray(sampled.to_z(jnp.asarray(z)))
    u = np.asarray(clock.call(to_u, None, target, jnp.asarray(z)))
    value_names, values, log_coordinate = value_draws(problem, names, u, clock.call)
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
        warnings.warn(note, stacklevel=4)
    saturated = float(np.mean(depth >= sampler.max_num_doublings))
    if saturated > SATURATION_WARN:
        warnings.warn(_saturation_note(saturated, sampler, n_steps), stacklevel=4)
    stats = statistics(names, summ, flat_u)
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


def _check_transport(transport, names) -> int | None:
    """Index of the transport's parameter (None without one); one-line errors."""
    if transport is None:
        return None
    if not isinstance(transport, ProfileTransport):
        raise TypeError(
            "transport must be an axojax.inverse.ProfileTransport, 'auto' or None, got "
            f"{type(transport).__name__}"
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


def _profile_arrays(profile: ProfileMap) -> tuple:
    return tuple(np.asarray(getattr(profile, n)) for n in _warm_cache.PROFILE_FIELDS)
