"""Chord root-finder for the implicit stages of ``C dq/dt = b - A q - f_nl(q)`` with an
exact, block-tridiagonal Jacobian: diffrax's :class:`diffrax.VeryChord` without
``jacfwd``.

diffrax's implicit Runge-Kutta methods solve each stage for the vector-field value
``f`` (f-space)::

    r(f) = f - F(y_partial + c f),   F(q) = C^{-1} (b - A q - f_nl(q)),   c = a_ii dt,

and linearise ``r`` once per step (``VeryChord``: at the step's first implicit stage,
reused by every later stage of the step). ``VeryChord`` forms that Jacobian by ``jacfwd``
(n Jacobian-vector products of the dense vector field) and LU-factorises the dense n x n
result; for the 280-unknown seven-filament model the 18 ms a step went (profiled) to that
``jacfwd``, the dense LU, and in every iteration's ``lu_solve`` jax's 280-step loop that
turns LAPACK pivots into a permutation. Here the Jacobian is exact and cheap: with the tangent stiffness
``K(q) = A + d f_nl / dq`` (:meth:`axojax.dynamics.nonlinear.CubicLinks.tangent`, a
sum of rank-one terms at the quadrature points), ``dr/df = C^{-1} (C + c K)``, so each chord
update solves::

    (C + c K(q_lin)) delta = C r(f) = C f - b + A q + f_nl(q),    q = y_partial + c f,

without ever forming ``C^{-1} K``. ``C + c K`` is block-tridiagonal in node-major order
(element matrices couple neighbouring nodes; links couple filaments inside a node): it
is assembled from node blocks (``C`` and ``A`` from :func:`axojax.assembly.assemble_blocks`,
``K`` from :meth:`CubicLinks.tangent_blocks`) and factorised once a step by
:func:`axojax.linalg.lu_factor` (partial pivoting inside each pair of block rows,
O(N_e (F d)^3)); each update is one block solve. (Measured and dropped: unrolling the
loops over blocks ran slower and doubled the compile time of a gradient through the
solver; composing each panel's pivots by a tree of gathers instead of jax's loop saved
3 %.)
Before a step's first implicit stage diffrax asks for the Jacobian at ``a_ii = 0`` (the
identity, used when an explicit first stage is re-evaluated after a rejected step): that
is ``C^{-1} C``, served from a factorisation of the constant ``C`` made once per solve.

The iteration, its termination test and its failure codes are ``VeryChord``'s, so the
step-size controller treats a non-converging stage exactly as before (step rejected).

The root-finder reads diffrax's stage arguments ``(stage_index, a_ii, vf, prod, t,
y_partial, args, control)`` (``diffrax._solver.runge_kutta._implicit_relation_f``,
diffrax 0.7) and needs the ODE's ``args`` to be a :class:`MassSystem`; it serves
f-space implicit methods (``Kvaerno3/4/5``) on a plain ``ODETerm``.
"""

from __future__ import annotations

from collections.abc import Callable

import equinox as eqx
import jax.lax as lax
import jax.numpy as jnp
import optimistix as optx
from jaxtyping import Array, Float, Int, PyTree, Scalar

from ..linalg import (
    BlockLU,
    BlockTridiagonal,
    Bordered,
    BorderedLU,
    bordered,
    bordered_lu,
    lu_factor,
)
from .nonlinear import CubicLinks
from .saturation import MotorSaturation, nonlinear_force


class MassSystem(eqx.Module):
    """The ODE ``C dq/dt = b - A q - f_nl(q)`` (filament-major unknowns), passed to
    diffrax as ``args``: what the vector field and the chord root-finder need.

    Attributes:
        C: (n, n) symmetric positive-definite damping.
        A: (n, n) linear stiffness-minus-load matrix.
        b: (n,) static load.
        C_inv: (n, n) ``C^{-1}``; ``C_inv_A``, ``C_inv_b``: ``C^{-1} A``, ``C^{-1} b``
            (the vector field costs three matrix-vector products).
        perm: (n,) node-major order (:func:`axojax.assembly.node_major`, then the border).
        C_blocks, A_blocks: C and A as node blocks (:func:`axojax.assembly.assemble_blocks`),
            :class:`~axojax.linalg.Bordered` where the model has a border (a base that is
            not clamped: its unknowns after the nodes').
        C_lu: block LU of ``C`` in node-major order (the ``a_ii = 0`` Jacobian).
        links: the cubic link force ``f_nl`` and its tangent ``d f_nl / dq``.
        saturation: saturating motors' force and tangent (motor kinetics only,
            :mod:`axojax.dynamics.saturation`), part of ``f_nl``; None: none.
    """

    C: Float[Array, "n n"]
    A: Float[Array, "n n"]
    b: Float[Array, " n"]
    C_inv: Float[Array, "n n"]
    C_inv_A: Float[Array, "n n"]
    C_inv_b: Float[Array, " n"]
    perm: Int[Array, " n"]
    C_blocks: BlockTridiagonal | Bordered
    A_blocks: BlockTridiagonal | Bordered
    C_lu: BlockLU | BorderedLU
    links: CubicLinks
    saturation: MotorSaturation | None = None

    def nonlinear_force(self, q: Float[Array, " n"]) -> Float[Array, " n"]:
        """f_nl(q): the cubic links' force, plus the saturating motors' where there are."""
        return nonlinear_force(self.links, self.saturation, q)

    def solve(self, lu: BlockLU | BorderedLU, rhs: Float[Array, " n"]) -> Float[Array, " n"]:
        """``M^{-1} rhs`` for filament-major vectors, ``lu`` a node-major factor of M."""
        return jnp.zeros_like(rhs).at[self.perm].set(lu.solve(rhs[self.perm]))

    def stage_factor(self, c: Scalar, q: Float[Array, " n"]) -> BlockLU | BorderedLU:
        """The block LU of ``C + c K(q)``, ``K = A + d f_nl / dq`` (node-major). Where C's
        node blocks are larger than the links' (motor kinetics: each node block holds the
        node's q then its motor copy y, :mod:`axojax.dynamics.motors`) the link tangent's
        blocks are padded with zeros: the links do not act on y. Saturating motors add
        their tangent, already in those blocks."""
        K = self.links.tangent_blocks(q)
        tri = self.C_blocks.tri if isinstance(self.C_blocks, Bordered) else self.C_blocks
        extra = tri.block_size - K.block_size
        if extra:
            pad = lambda x: jnp.pad(x, ((0, 0), (0, extra), (0, extra)))
            K = BlockTridiagonal(pad(K.lower), pad(K.diag), pad(K.upper))
        if isinstance(self.C_blocks, Bordered):
            m = self.C_blocks.m
            zero = jnp.zeros((K.shape[0], m), K.diag.dtype)
            K = bordered(K, zero, zero.T, jnp.zeros((m, m), K.diag.dtype))
            if self.saturation is not None:
                K = K + self.saturation.tangent_blocks(q)
            return bordered_lu(self.C_blocks + (self.A_blocks + K).scale(c))
        if self.saturation is not None:
            K = K + self.saturation.tangent_blocks(q)
        return lu_factor(self.C_blocks + (self.A_blocks + K).scale(c))


def mass_vector_field(t, q, system: MassSystem):
    """diffrax vector field ``dq/dt = C^{-1} (b - A q - f_nl(q))``."""
    return system.C_inv_b - system.C_inv_A @ q - system.C_inv @ system.nonlinear_force(q)


class _State(eqx.Module):
    lu: BlockLU | BorderedLU
    diffsize: Scalar
    diffsize_prev: Scalar
    result: optx.RESULTS
    step: Scalar


def _stage(y, args):
    """(a_ii dt, the state q at which the stage evaluates f, the system)."""
    _, diagonal, _, prod, _, y_partial, system, control = args
    c = diagonal * prod(jnp.ones_like(y), control)[0]
    return c, y_partial + c * y, system


class MassChord(optx.AbstractRootFinder):
    """:class:`diffrax.VeryChord` with the exact Jacobian ``C^{-1} (C + a_ii dt K)`` of a
    :class:`MassSystem` (module docstring): one block LU a step, one block solve an
    iteration. Same arguments as ``VeryChord``."""

    rtol: float
    atol: float
    norm: Callable[[PyTree], Scalar] = optx.rms_norm
    kappa: float = 1e-2

    def init(self, fn, y, args, options, f_struct, aux_struct, tags) -> _State:
        if "init_state" in options:
            return options["init_state"]
        c, q_lin, system = _stage(y, args)
        lu = lax.cond(c == 0, lambda: system.C_lu, lambda: system.stage_factor(c, q_lin))
        return _State(
            lu=lax.stop_gradient(lu),
            diffsize=jnp.array(jnp.inf, dtype=y.dtype),
            diffsize_prev=jnp.array(1.0, dtype=y.dtype),
            result=optx.RESULTS.successful,
            step=jnp.array(0),
        )

    def step(self, fn, y, args, options, state: _State, tags):
        c, q, system = _stage(y, args)
        diff = system.solve(
            state.lu, system.C @ y - system.b + system.A @ q + system.nonlinear_force(q)
        )
        new_y = y - diff
        diffsize = self.norm(diff / (self.atol + self.rtol * jnp.abs(new_y)))
        result = optx.RESULTS.where(
            jnp.all(jnp.isfinite(diff)), optx.RESULTS.successful, optx.RESULTS.singular
        )
        return (
            new_y,
            _State(
                lu=state.lu,
                diffsize=diffsize,
                diffsize_prev=state.diffsize,
                result=result,
                step=state.step + 1,
            ),
            None,
        )

    def terminate(self, fn, y, args, options, state: _State, tags):
        # VeryChord's test (diffrax._root_finder._verychord), unchanged.
        at_least_two = state.step >= 2
        rate = state.diffsize / state.diffsize_prev
        factor = state.diffsize * rate / (1 - rate)
        small = state.diffsize < 10 ** (2 - jnp.finfo(state.diffsize.dtype).precision)
        diverged = jnp.invert(jnp.isfinite(rate)) | (rate > 2)
        converged = (factor > 0) & (factor < self.kappa)
        terminate = at_least_two & (small | diverged | converged)
        terminate_result = optx.RESULTS.where(
            at_least_two & jnp.invert(small) & (diverged | jnp.invert(converged)),
            optx.RESULTS.nonlinear_divergence,
            optx.RESULTS.successful,
        )
        failed = state.result != optx.RESULTS.successful
        return failed | terminate, optx.RESULTS.where(failed, state.result, terminate_result)

    def postprocess(self, fn, y, aux, args, options, state, tags, result):
        return y, aux, {}
