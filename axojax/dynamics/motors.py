"""Motor kinetics in the time domain (issue 47 items 1 and 3; docs/model.md section 8).

With motor kinetics of relaxation time tau_m the state grows by the filtered copy y of
:mod:`axojax.assembly.motor_kinetics` (``tau_m dy/dt = -y + q``), so the time domain is
the augmented system of :func:`~axojax.assembly.motor_kinetics.assemble_motor` with the
cubic link force on q::

    C' dX/dt = b' - A' X - f_nl(X),   X = (q, y) (2 N unknowns, N = model.n_unknowns),
    A' = [[A_inf, M], [-I, I]],   C' = [[C_0, 0], [0, tau_m I]],   b' = (b, 0),

whose linearisation about X = 0 is the augmented pencil itself (the same matrices, not a
re-derivation). C' has no friction (C_0 is the drag and link damping; tau_m I > 0), so the
integrator's Cholesky inverse and its implicit stages apply as they are.

The implicit stages factor ``C' + c K'`` as block-tridiagonal with a border, like the
model's own pencil: in :func:`motor_order` each node block holds that node's q unknowns
then its y unknowns (2 b = 4 F d), and the border is q's border then y's (2 m). A' and C'
are block-tridiagonal in that order because A_inf, M and the identities are (M is an
assembled mechanism matrix, local along x but through the border): :func:`motor_blocks`
reads the blocks out of the dense matrices (tests/regulation/test_motor_kinetics_time.py checks
that nothing lies outside them). The cubic link tangent is zero on y: its node blocks are
padded (:meth:`axojax.dynamics.chord.MassSystem.stage_factor`).
"""

from __future__ import annotations

import math
from typing import Any

import jax.numpy as jnp
import numpy as np
import scipy.linalg as sl
from jaxtyping import Array, ArrayLike, Float

from ..assembly import node_major
from ..assembly.motor_kinetics import assemble_motor
from ..eigen.deflation import scale_of
from ..eigen.mode import CLASSES, classify
from ..linalg import BlockTridiagonal, Bordered, bordered
from ..models.section import Model
from ..params import Params
from ..units import Units


def motor_order(model: Model) -> np.ndarray:
    """(2 N,) permutation ``X_ordered = X[perm]`` of X = (q, y): node k's q unknowns
    (node-major, :func:`~axojax.assembly.node_major`) then its y unknowns, for every node;
    then q's border, then y's border."""
    n, bs = model.n_unknowns, 2 * model.n_fd
    nodes = np.asarray(node_major(model)).reshape(model.n_elements, bs)
    border = model.n_dof + np.arange(model.n_border)
    return np.concatenate([np.concatenate([nodes, nodes + n], axis=1).ravel(), border, border + n])


def motor_blocks(model: Model, M: Float[Array, "M M"]) -> BlockTridiagonal | Bordered:
    """A (2 N, 2 N) matrix of the augmented system (filament-major X = (q, y)) as blocks in
    :func:`motor_order`: block-tridiagonal with blocks of size 4 F d, bordered by the
    2 m border unknowns where the model has a border (else a plain
    :class:`~axojax.linalg.BlockTridiagonal`). Entries outside the band are dropped (there
    are none for the augmented A' and C')."""
    return blocks_of(M, motor_order(model), model.n_elements, 4 * model.n_fd, 2 * model.n_border)


def blocks_of(
    M: Float[Array, "M M"], perm: ArrayLike, n_blocks: int, block_size: int, m: int
) -> BlockTridiagonal | Bordered:
    """:func:`motor_blocks` from the order ``perm`` and the sizes (``n_blocks`` node
    blocks of ``block_size``, then a border of ``m``; m = 0: a plain block-tridiagonal
    matrix)."""
    perm = jnp.asarray(perm)
    P = M[perm][:, perm]
    nn = n_blocks * block_size
    T = P[:nn, :nn].reshape(n_blocks, block_size, n_blocks, block_size)
    k = np.arange(n_blocks)
    tri = BlockTridiagonal(T[k[1:], :, k[:-1], :], T[k, :, k, :], T[k[:-1], :, k[1:], :])
    if m == 0:
        return tri
    return bordered(tri, P[:nn, nn:], P[nn:, :nn], P[nn:, nn:])


def rigid_motions(model: Model) -> np.ndarray:
    """(2 N, r) rigid motions of the augmented system, (Z; Z) (y = q at rest): A' (Z; Z)
    = ((A_inf + M) Z; 0) = 0, as A Z = 0 at any chi and beta. r = 0 on a held base."""
    Z = np.asarray(model.rigid_modes(), dtype=float)
    return np.concatenate([Z, Z], axis=0)


def deflated_pencil(model: Model, params: Params, tau_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(A', C') of the augmented system (numpy, dense) with a base's rigid motions moved
    from eigenvalue 0 to -s (Brauer, as :mod:`axojax.eigen.deflation`; unchanged on a held
    base): every other eigenvalue of (A', C') kept, so the spectrum's deforming modes."""
    s = assemble_motor(model, params, tau_m)
    A, C = np.asarray(s.A), np.asarray(s.C)
    Z = rigid_motions(model)
    if Z.shape[1]:
        shift = float(scale_of(jnp.asarray(np.max(np.abs(A))), jnp.asarray(np.max(np.abs(C)))))
        Yt = np.linalg.solve(Z.T @ C @ Z, Z.T @ C)
        A = A + shift * (C @ Z) @ Yt
    return A, C


def dominant_eigenvalue(model: Model, params: Params, tau_m: float) -> complex:
    """The rightmost deforming eigenvalue of the augmented pencil (A' + lambda C') v = 0
    (dimensionless, 1/tau), by a dense eigen-solve (scipy); a base's rigid motions moved to
    -s first (Brauer, as :mod:`axojax.eigen.deflation`; none on a held base)."""
    A, C = deflated_pencil(model, params, tau_m)
    lam = sl.eigvals(-A, C)
    lam = lam[np.isfinite(lam)]
    return complex(lam[np.argmax(lam.real)])


def equilibrium(model: Model, params: Params, tau_m: float) -> np.ndarray:
    """(N,) the static state q of the augmented system, A' X = b' (y = q at rest); the
    least-norm one on a base that moves (A' singular)."""
    s = assemble_motor(model, params, tau_m)
    b = np.asarray(s.b)
    if not np.any(b):
        return np.zeros(model.n_unknowns)
    A = np.asarray(s.A)
    X = np.linalg.lstsq(A, b, rcond=None)[0] if model.n_border else np.linalg.solve(A, b)
    return X[: model.n_unknowns]


def motor_linear(model: Model, params: Params, tau_m: float, units: Units) -> dict[str, Any]:
    """:func:`dominant_eigenvalue` as ``simulate``'s ``linear``: ``frequency_hz``,
    ``growth_rate_per_s`` and ``classification`` (:data:`axojax.eigen.mode.CLASSES`)."""
    lam = dominant_eigenvalue(model, params, tau_m)
    return {
        "frequency_hz": abs(lam.imag) / (2 * math.pi * units.tau_s),
        "growth_rate_per_s": lam.real / units.tau_s,
        "classification": CLASSES[int(classify(jnp.asarray(lam)))],
    }


def motor_meta(tau_m: float, f_sat: float | None, units: Units) -> dict[str, Any]:
    """``simulate``'s ``meta["motor_kinetics"]``: the motor time ``tau_m`` (tau) and
    ``tau_ms``, the saturation ``f_sat`` (EI / L^3) and ``f_sat_pn_per_um`` (None
    without one)."""
    return {
        "tau_m": tau_m,
        "tau_ms": tau_m * units.tau_s * 1e3,
        "f_sat": f_sat,
        "f_sat_pn_per_um": None if f_sat is None else float(units.p_to_pn_per_um(f_sat)),
    }
