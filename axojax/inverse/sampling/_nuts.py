"""The No-U-Turn sampler's settings (:class:`NUTS`) and the compiled programs of a
posterior run: window adaptation and sampling of every chain (blackjax), the draws'
coordinates and values, each compiled ahead of time and cached (:func:`_compiled`)."""

from __future__ import annotations

import time
from typing import Any

import blackjax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._densities import _Target


class NUTS(eqx.Module):
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


DEFAULT_NUTS = NUTS()

START_EVALUATIONS = 2
"""Log-density evaluations of a chain before its first step: the check that its start is
finite (:func:`_finite_starts`, a value) and blackjax's initial state (value and gradient)."""


# -- compiled pieces ---------------------------------------------------------------------
# Each runs as fn(static, *dynamic): the arrays of the problem (when it is a pytree, e.g. an
# equinox Module) and of the prior are dynamic, so problems of one structure with other data
# (another seed, another condition) reuse the compiled program (_compiled's cache).


class _Static:
    """A static argument: hashed by value where it can be, else by identity."""

    def __init__(self, obj):
        self.obj = obj
        try:
            self._hash = hash(obj)
            self._by_value = True
        except TypeError:
            self._hash = id(obj)
            self._by_value = False

    def __hash__(self):
        return self._hash

    def __eq__(self, other):
        if not isinstance(other, _Static) or self._by_value != other._by_value:
            return False
        return bool(self.obj == other.obj) if self._by_value else self.obj is other.obj


_CACHE: dict = {}
_CACHE_SIZE = 16


def _compiled(fn, static, dynamic: tuple) -> tuple[Any, float]:
    """``fn(static, *dynamic)`` run by an ahead-of-time compiled program (cached per fn,
    static values and the dynamic arrays' shapes), and the seconds spent compiling."""
    target, *rest = dynamic
    dyn, stat = eqx.partition(target, eqx.is_array)
    leaves, treedef = jax.tree.flatten((dyn, rest))
    key = (
        fn,
        _Static((stat, static)),
        treedef,
        tuple((jnp.shape(x), jnp.result_type(x)) for x in leaves),
    )
    seconds = 0.0
    if key not in _CACHE:
        t0 = time.perf_counter()

        def run(static_, dyn_, rest_):
            stat_, fixed = static_.obj
            return fn(fixed, eqx.combine(dyn_, stat_), *rest_)

        _CACHE[key] = (
            jax.jit(run, static_argnums=0).lower(_Static((stat, static)), dyn, rest).compile()
        )
        seconds = time.perf_counter() - t0
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
    return _CACHE[key](dyn, rest), seconds


def _finite_starts(target, z, z_c):
    """Starts where the log density is finite; the others moved to the centre ``z_c``."""
    ok = jnp.isfinite(jax.vmap(target)(z))
    return jnp.where(ok[:, None], z, z_c)


def _warmup(settings, target, keys, z0, z_c, imm0):
    """Window adaptation of every chain (vmapped or mapped) from ``z0`` (a start with a
    non-finite density moved to ``z_c``): final states, step sizes, inverse mass matrices
    and the log-density evaluations spent per chain (:data:`START_EVALUATIONS` and every
    leapfrog step's value and gradient)."""
    sampler, num_steps, vectorize = settings
    z0 = _finite_starts(target, z0, z_c)
    adapt = blackjax.window_adaptation(
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
        (state, params), info = adapt.run(key, z, num_steps=num_steps)
        return (
            state,
            params["step_size"],
            params["inverse_mass_matrix"],
            jnp.sum(info.info.num_integration_steps) + START_EVALUATIONS,
        )

    return _over_chains(one, vectorize, keys, z0)


def _init_states(_, target, z0, z_c):
    return jax.vmap(lambda z: blackjax.nuts.init(z, target))(_finite_starts(target, z0, z_c))


def _over_chains(fn, vectorize: bool, *args):
    """``fn`` of one chain applied to every chain (leading axis of ``args``): vmapped
    (the chains step together; a NUTS step costs the longest of their trajectories) or
    one after another (``jax.lax.map``: each chain's trajectories cost only their own)."""
    return jax.vmap(fn)(*args) if vectorize else jax.lax.map(lambda a: fn(*a), args)


def _sample(settings, target, states, step_size, imm, keys):
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

    return _over_chains(chain, vectorize, states, step_size, imm, keys)


def _to_u(_, target, z):
    """Draws z (chains, draws, k) -> u (chains, draws, k)."""
    return jax.vmap(jax.vmap(target.problem.to_u))(z)


def _values_batch(_, target, u):
    return jax.vmap(target.problem.values)(u)


def _values(problem, u: np.ndarray, call) -> dict[str, np.ndarray]:
    """``problem.values`` of every row of u (n, k): vmapped where it is traceable, else
    one call per draw (a ``values`` written in numpy for concrete u)."""
    try:
        return {
            n: np.asarray(v, dtype=float)
            for n, v in call(_values_batch, None, _Target(problem), jnp.asarray(u)).items()
        }
    except TypeError:  # jax's concretisation errors: values() needs concrete u
        rows = [problem.values(x) for x in u]
        return {n: np.array([float(r[n]) for r in rows]) for n in rows[0]}
