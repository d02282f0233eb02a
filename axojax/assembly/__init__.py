"""System assembly: C, A, b of ``C dq/dt + A q = b`` as pure functions of Params.

docs/model.md section 3::

    A = K_bend + K_link + K_theta + K_G - P_follow - P_gain (+ regulated dynein, section 8)
    C = C_fluid + C_link (+ regulated dynein's friction, section 8)

Each term is a small truss matrix over (filament, direction) pairs, built from the
model's static arrays and the traced parameters, Kronecker-multiplied by a
filament-level matrix (:func:`terms`). They are summed either as dense matrices in
filament-major order (:func:`assemble`) or as node blocks in node-major order
(:func:`assemble_blocks`, block-tridiagonal: what the structured eigen-solver uses). No
Python loop runs over elements or grid points: both are jit-able and vmap-able in
``params``.
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..linalg import BlockTridiagonal, Bordered, bordered
from ..models.section import Model
from ..params import Params
from .border import Border, border_terms, check_base_params
from .normal_force import NormalSystem, assemble_normal
from .terms import (
    MatrixName,
    Term,
    _filament_matrix,
    bending_rigidity,
    imbalanced_forces,
    link_stiffness,
    mechanism_terms,
    moment_load,
    pair_forces,
    refuse_normal_force,
    static_couple,
    terms,
)

__all__ = [
    "Border",
    "BlockSystem",
    "MatrixName",
    "NormalSystem",
    "System",
    "Term",
    "assemble",
    "assemble_normal",
    "assemble_blocks",
    "bending_rigidity",
    "border_terms",
    "check_base_params",
    "imbalanced_forces",
    "link_stiffness",
    "mechanism_terms",
    "moment_load",
    "node_major",
    "pair_forces",
    "pencil_of",
    "refuse_normal_force",
    "static_couple",
    "terms",
]


class System(eqx.Module):
    """Assembled system ``C dq/dt + A q = b``; N = ``model.n_unknowns`` = n + m: the
    n = ``model.n_dof`` node unknowns (filament-major), then the m = ``model.n_border``
    unknowns of a base that is not clamped (m = 0 for the clamped base).

    Attributes:
        C: (N, N) damping (drag + link damping; symmetric positive definite with the
            steady load).
        A: (N, N) non-symmetric stiffness-minus-load matrix.
        b: (N,) static load (the constant dynein moment; zero when moments cancel).
    """

    C: Float[Array, "N N"]
    A: Float[Array, "N N"]
    b: Float[Array, " N"]


def assemble(model: Model, params: Params) -> System:
    """Assemble C, A, b for ``model`` at ``params`` (docs/model.md section 3).

    Args:
        model: static structure (mesh, topology, base), e.g. ``ax.models.seven()``.
        params: dimensionless parameters; may be traced.

    Returns:
        :class:`System` with dense (N, N) matrices, N = ``model.n_unknowns``: the node
        unknowns filament-major, then the base's border (:mod:`axojax.models.base`).
    """
    A_terms, C_terms, b = terms(model, params)

    def total(ts: list[Term]) -> Array:
        return sum(jnp.kron(t, jnp.asarray(_filament_matrix(model, name))) for t, name in ts)

    A, C = total(A_terms), total(C_terms)
    if not model.n_border:
        return System(C=C, A=A, b=b)
    border = border_terms(model, params, A_terms, C_terms)

    def bordered(nn, nb, bn, bb):
        return jnp.concatenate(
            [jnp.concatenate([nn, nb], axis=1), jnp.concatenate([bn, bb], axis=1)], axis=0
        )

    return System(
        C=bordered(C, border.C_nb, border.C_bn, border.C_bb),
        A=bordered(A, border.A_nb, border.A_bn, border.A_bb),
        b=jnp.concatenate([b, border.b]),
    )


class BlockSystem(eqx.Module):
    """The system ``C dq/dt + A q = b`` in node-major order (see :func:`node_major`):
    A and C block-tridiagonal with N_e node blocks of size b = 2 F d, and a border of
    m = ``model.n_border`` unknowns after the n node unknowns (a base that is not
    clamped; m = 0 gives arrays of shape (n, 0), (0, n), (0, 0)).

    Attributes:
        C, A: the node-node blocks.
        A_nb, C_nb: (n, m) node (node-major) to border couplings; A_bn, C_bn: (m, n);
            A_bb, C_bb: (m, m).
        b: (n + m,) static load, node-major, then the border.
    """

    C: BlockTridiagonal
    A: BlockTridiagonal
    b: Float[Array, " N"]
    A_nb: Float[Array, "n m"]
    A_bn: Float[Array, "m n"]
    A_bb: Float[Array, "m m"]
    C_nb: Float[Array, "n m"]
    C_bn: Float[Array, "m n"]
    C_bb: Float[Array, "m m"]


@functools.lru_cache(maxsize=64)
def _node_blocks(model: Model, name: "MatrixName") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lower, diag, upper) 2 x 2 node blocks of a filament-level matrix (Hermite
    elements couple neighbouring nodes only: the matrix is block-tridiagonal)."""
    M = _filament_matrix(model, name)
    N = model.n_elements
    blocks = M.reshape(N, 2, N, 2).transpose(0, 2, 1, 3)  # (N, N, 2, 2)
    k = np.arange(N)
    outside = blocks.copy()
    outside[k, k] = 0
    outside[k[1:], k[:-1]] = 0
    outside[k[:-1], k[1:]] = 0
    if np.any(outside != 0):
        raise AssertionError(f"filament matrix {name} is not block-tridiagonal")
    return blocks[k[1:], k[:-1]], blocks[k, k], blocks[k[:-1], k[1:]]


@functools.lru_cache(maxsize=64)
def node_major(model: Model) -> np.ndarray:
    """Permutation ``perm`` with ``q_node_major = q[perm]``: node k, then filament and
    direction (f, a), then (u, u') — the order of :class:`BlockSystem`."""
    N, nfd = model.n_elements, model.n_fd
    fd, node, r = np.meshgrid(
        np.arange(nfd), np.arange(N), np.arange(2), indexing="ij"
    )  # filament-major shape
    index = fd * 2 * N + node * 2 + r  # (nfd, N, 2): filament-major flat index
    return np.ascontiguousarray(index.transpose(1, 0, 2).reshape(-1))


def _grouped(ts: list[Term]) -> tuple[tuple["MatrixName", ...], Float[Array, "g n_fd n_fd"]]:
    """Terms summed per filament-level matrix: (names, stacked truss matrices)."""
    names = tuple(dict.fromkeys(name for _, name in ts))
    trusses = jnp.stack([sum(t for t, nm in ts if nm == name) for name in names])
    return names, trusses


@functools.lru_cache(maxsize=64)
def _stacked_node_blocks(model: Model, names: tuple["MatrixName", ...]) -> np.ndarray:
    """(g, 3 N_e - 2, 2, 2): the lower, diagonal and upper node blocks of each named
    filament-level matrix, concatenated along the block axis."""
    return np.stack([np.concatenate(_node_blocks(model, name)) for name in names])


def assemble_blocks(model: Model, params: Params) -> BlockSystem:
    """Assemble A, C (block-tridiagonal, node-major) and b (node-major) at ``params``;
    the same terms as :func:`assemble`, at O(N_e (F d)^2) memory instead of O((N_e F d)^2)."""
    A_terms, C_terms, b = terms(model, params)
    N, bs = model.n_elements, 2 * model.n_fd

    def total(ts: list[Term]) -> BlockTridiagonal:
        names, trusses = _grouped(ts)
        blocks = jnp.asarray(_stacked_node_blocks(model, names))
        # One contraction over the filament-level matrices: block (i a, j b) of node pair
        # k is sum_g truss_g[i, j] * node_block_g[k][a, b].
        out = jnp.einsum("gij,gkab->kiajb", trusses, blocks).reshape(-1, bs, bs)
        return BlockTridiagonal(out[: N - 1], out[N - 1 : 2 * N - 1], out[2 * N - 1 :])

    perm = node_major(model)
    n, m = model.n_dof, model.n_border
    if m:
        border = border_terms(model, params, A_terms, C_terms)
    else:
        empty = jnp.zeros((0, 0))
        border = Border(
            jnp.zeros((n, 0)),
            jnp.zeros((0, n)),
            empty,
            jnp.zeros((n, 0)),
            jnp.zeros((0, n)),
            empty,
            jnp.zeros(0),
        )
    return BlockSystem(
        C=total(C_terms),
        A=total(A_terms),
        b=jnp.concatenate([b[perm], border.b]) if m else b[perm],
        A_nb=border.A_nb[perm],
        A_bn=border.A_bn[:, perm],
        A_bb=border.A_bb,
        C_nb=border.C_nb[perm],
        C_bn=border.C_bn[:, perm],
        C_bb=border.C_bb,
    )


def pencil_of(system) -> tuple[Bordered, Bordered]:
    """(A, C) of a node-major block system (:func:`assemble_blocks`, or any object with its
    fields) as bordered matrices
    (:class:`axojax.linalg.Bordered`): its border blocks ``A_nb``, ``A_bn``, ``A_bb``,
    ``C_nb``, ... (extra unknowns after the node unknowns, e.g. a base's) where it has
    them, else none (m = 0). What the structured eigen-solver and the time integrator
    factor."""
    A_nb = getattr(system, "A_nb", None)
    if A_nb is None:
        return bordered(system.A), bordered(system.C)
    return (
        bordered(system.A, A_nb, system.A_bn, system.A_bb),
        bordered(system.C, system.C_nb, system.C_bn, system.C_bb),
    )
