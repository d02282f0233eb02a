"""The No-U-Turn sampler's compiled programs (blackjax) and the steps of a run built on
them (:class:`~._nuts.NUTS` runs them): the sampled density and the chains' window
adaptation (:func:`adapt`), or their state resumed from the warm cache (:func:`resume`),
then the draws in chunks (:func:`draw`). The programs run through
:meth:`.programs.Clock.call` (compiled ahead of time, cached)."""

from __future__ import annotations

import blackjax
import jax
import jax.numpy as jnp
import numpy as np
from blackjax.mcmc.hmc import HMCState

from ..._progress import progress as progress_bar
from . import _warm_cache
from ._densities import Whitened
from .transport import ProfileMap, build_map

SAMPLE_CHUNK = 50
"""Draws per compiled sampling call: one program for any number of draws (the last
chunk's surplus is dropped)."""
START_EVALUATIONS = 2
"""Log-density evaluations of a chain before its first step: the check that its start is
finite (:func:`finite_starts`, a value) and blackjax's initial state (value and gradient)."""


def finite_starts(target, z, z_c):
    """Starts where the log density is finite; the others moved to the centre ``z_c``."""
    ok = jnp.isfinite(jax.vmap(target)(z))
    return jnp.where(ok[:, None], z, z_c)


def window_adaptation(settings, target, keys, z0, z_c, imm0):
    """Window adaptation of every chain (vmapped or mapped) from ``z0`` (a start with a
    non-finite density moved to ``z_c``): final states, step sizes, inverse mass matrices
    and the log-density evaluations spent per chain (:data:`START_EVALUATIONS` and every
    leapfrog step's value and gradient)."""
    sampler, num_steps, vectorize = settings
    z0 = finite_starts(target, z0, z_c)
    adaptation = blackjax.window_adaptation(
        blackjax.nuts,
        target,
        is_mass_matrix_diagonal=not sampler.dense_mass,
        initial_inverse_mass_matrix=imm0,
        target_acceptance_rate=sampler.target_acceptance_rate,
        adaptation_info_fn=blackjax.adaptation.base.get_filter_adapt_info_fn(
            info_keys={"num_integration_steps"}
        ),
        max_num_doublings=sampler.max_num_doublings,
    )

    def one(key, z):
        (state, params), info = adaptation.run(key, z, num_steps=num_steps)
        return (
            state,
            params["step_size"],
            params["inverse_mass_matrix"],
            jnp.sum(info.info.num_integration_steps) + START_EVALUATIONS,
        )

    return over_chains(one, vectorize, keys, z0)


def init_states(_, target, z0, z_c):
    """blackjax's initial NUTS state of every chain (no warm-up), a start with a non-finite
    density moved to ``z_c``."""
    return jax.vmap(lambda z: blackjax.nuts.init(z, target))(finite_starts(target, z0, z_c))


def over_chains(fn, vectorize: bool, *args):
    """``fn`` of one chain applied to every chain (leading axis of ``args``): vmapped
    (the chains step together; a NUTS step costs the longest of their trajectories) or
    one after another (``jax.lax.map``: each chain's trajectories cost only their own)."""
    return jax.vmap(fn)(*args) if vectorize else jax.lax.map(lambda a: fn(*a), args)


def nuts_steps(settings, target, states, step_size, imm, keys):
    """``keys.shape[1]`` NUTS steps of every chain (steps scanned inside each chain,
    chains vmapped or mapped): the final states and, per chain and step, (positions,
    log densities, divergent, gradients, acceptance rates, tree depths), each
    (chains, steps, ...)."""
    sampler, vectorize = settings

    def chain(state, eps, m, keys_c):
        kernel = blackjax.nuts(
            target,
            eps,
            m,
            max_num_doublings=sampler.max_num_doublings,
            divergence_threshold=sampler.divergence_threshold,
        )

        def step(state, key):
            state, info = kernel.step(key, state)
            return state, (
                state.position,
                state.logdensity,
                info.is_divergent,
                info.num_integration_steps,
                info.acceptance_rate,
                info.num_trajectory_expansions,
            )

        return jax.lax.scan(step, state, keys_c)

    return over_chains(chain, vectorize, states, step_size, imm, keys)


def adapt(target, sampler, warmup, vectorize, key, z_start, z_c, cov, call, transport=None):
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
        sampled = Whitened(target, jnp.zeros(k), jnp.eye(k), profile)
        if respread:  # the chains start spread along the whole ridge
            key, key_starts = jax.random.split(key)
            x_start = profile.draw_y(key_starts, chains)
        else:
            x_start = sampled.to_w(z_start)
        x_c, cov_x = jnp.zeros(k), jnp.eye(k)
    elif sampler.whiten:  # sample w = L^-1 (z - z_c): the Laplace covariance becomes the identity
        sampled = Whitened(target, z_c, jnp.linalg.cholesky(cov))
        x_start, x_c, cov_x = sampled.to_w(z_start), jnp.zeros(k), jnp.eye(k)
    else:
        sampled, x_start, x_c, cov_x = target, z_start, z_c, cov
    imm0 = cov_x if sampler.dense_mass else jnp.diag(cov_x)
    if warmup > 0:
        states, step_size, imm, warm_grads = call(
            window_adaptation,
            (sampler, int(warmup), bool(vectorize)),
            sampled,
            jax.random.split(key, chains),
            x_start,
            x_c,
            imm0,
        )
    else:  # no adaptation: the Laplace covariance as mass matrix, a moderate step
        states = call(init_states, None, sampled, x_start, x_c)
        step_size = jnp.full(chains, 0.5)
        imm = jnp.broadcast_to(imm0, (chains, *imm0.shape))
        warm_grads = jnp.full(chains, START_EVALUATIONS)
    jax.block_until_ready(states)
    return sampled, states, step_size, imm, warm_grads


def resume(target, sampler, warm, along=None):
    """The sampled density and the chains' state, step sizes, inverse mass matrices and
    warm-up gradients kept by an identical run (:mod:`._warm_cache`), as :func:`adapt`
    returned them (with a transport along coordinate ``along``: its map too)."""
    if along is not None:
        k = len(warm.z_c)
        profile = ProfileMap(
            along=along,
            rest=tuple(i for i in range(k) if i != along),
            **{n: jnp.asarray(x) for n, x in zip(_warm_cache.PROFILE_FIELDS, warm.profile)},
        )
        sampled = Whitened(target, jnp.zeros(k), jnp.eye(k), profile)
    elif sampler.whiten:
        sampled = Whitened(target, jnp.asarray(warm.z_c), jnp.asarray(warm.chol))
    else:
        sampled = target
    states = HMCState(*(jnp.asarray(x) for x in warm.state))
    return sampled, states, jnp.asarray(warm.step_size), jnp.asarray(warm.imm), warm.warm_grads


def draw(sampled, sampler, states, step_size, imm, draws, vectorize, key, progress, clock):
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
        total=chains * draws,
        desc="posterior draws",
        unit="draw",
        enable=progress,
        starting="the first chunk compiles",
    ) as bar:
        for i in range(n_chunks):
            states, out = clock.call(
                nuts_steps, (sampler, bool(vectorize)), sampled, states, step_size, imm, keys[i]
            )
            outs.append(jax.device_get(out))
            bar.update(chains * min(SAMPLE_CHUNK, draws - i * SAMPLE_CHUNK))
    spent = int(sum(np.sum(o[3]) for o in outs))
    return (*(np.concatenate([o[j] for o in outs], axis=1)[:, :draws] for j in range(6)), spent)
