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
reads the blocks out of the dense matrices (tests/test_motor_kinetics_time.py checks
that nothing lies outside them). The cubic link tangent is zero on y: its node blocks are
padded (:meth:`axojax.dynamics.chord.MassSystem.stage_factor`).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
import scipy.linalg as sl
from jaxtyping import Array, Float

from ..assembly import node_major
from ..assembly.motor_kinetics import assemble_motor
from ..eigen.deflation import scale_of
from ..linalg import BlockTridiagonal, Bordered, bordered
from ..models.section import Model
from ..params import Params


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
    perm = jnp.asarray(motor_order(model))
    P = M[perm][:, perm]
    N, b = model.n_elements, 4 * model.n_fd
    nn = N * b
    T = P[:nn, :nn].reshape(N, b, N, b)
    k = np.arange(N)
    tri = BlockTridiagonal(T[k[1:], :, k[:-1], :], T[k, :, k, :], T[k[:-1], :, k[1:], :])
    if model.n_border == 0:
        return tri
    return bordered(tri, P[:nn, nn:], P[nn:, :nn], P[nn:, nn:])


def rigid_motions(model: Model) -> np.ndarray:
    """(2 N, r) rigid motions of the augmented system, (Z; Z) (y = q at rest): A' (Z; Z)
    = ((A_inf + M) Z; 0) = 0, as A Z = 0 at any chi and beta. r = 0 on a held base."""
    Z = np.asarray(model.rigid_modes(), dtype=float)
    return np.concatenate([Z, Z], axis=0)


def dominant_eigenvalue(model: Model, params: Params, tau_m: float) -> complex:
    """The rightmost deforming eigenvalue of the augmented pencil (A' + lambda C') v = 0
    (dimensionless, 1/tau), by a dense eigen-solve (scipy); a base's rigid motions moved to
    -s first (Brauer, as :mod:`axojax.eigen.deflation`; none on a held base)."""
    s = assemble_motor(model, params, tau_m)
    A, C = np.asarray(s.A), np.asarray(s.C)
    Z = rigid_motions(model)
    if Z.shape[1]:
        shift = float(scale_of(jnp.asarray(np.max(np.abs(A))), jnp.asarray(np.max(np.abs(C)))))
        Yt = np.linalg.solve(Z.T @ C @ Z, Z.T @ C)
        A = A + shift * (C @ Z) @ Yt
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
