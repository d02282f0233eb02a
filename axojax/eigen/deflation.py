"""Rigid-body deflation of a structured (bordered block-tridiagonal) pencil.

A base that leaves the axoneme free to move (free, head, a pivot without a spring) gives
the pencil ``(A + lambda C) v = 0`` zero eigenvalues whose eigenvectors are the rigid
motions Z (``A Z = 0``, :meth:`axojax.models.Model.rigid_modes`): no mode of deformation.
The dense solver moves them away by Brauer's theorem (:class:`axojax.eigen.mode.
RigidDeflated`): with ``Y^T = (Z^T C Z)^{-1} Z^T C`` (so ``Y^T Z = I``) the pencil
``(A + s C Z Y^T, C)`` has every eigenvalue of (A, C) except that the rigid ones move
from 0 to -s.

``C Z Y^T`` is dense (a rigid motion moves every node), so here it is a *border*, not a
reason to go dense: r = rank Z extra unknowns ``y = Y^T v`` after the model's own border,

    A_ext = [[A,    s C Z],      C_ext = [[C, 0],
             [Y^T,  -I   ]]               [0, 0]]

``(A_ext + lambda C_ext) [v'; y] = 0`` is exactly ``(A + s C Z Y^T + lambda C) v' = 0``:
the structured solvers factor it through the bordered LU (:mod:`axojax.linalg.bordered`)
at O(N_e) cost, and the derivative rule (:mod:`axojax.eigen.tangent`) applies as it is.
An eigenvector v' of the deflated pencil at lambda gives the original's,
``v = v' + (s / lambda) Z Y^T v' = v' + (s / lambda) Z y`` (exact). The finite
eigenvalues of the extended pencil are those of (A, C) but the rigid ones, so a pole to
the right of (A, C)'s spectrum (:func:`axojax.eigen.arnoldi.pole`, computed on the
pencil without the r deflation unknowns: :func:`truncate`) lies to the right of it too.

The scale s is :data:`SCALE` max|A| / max|C| (as the dense solver's): the rigid modes go
to -s, among the fastest-decaying ones; the extra unknowns y = Y^T v' are of the size of
v' (s sits in the border column, beside A's own stiff entries).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jaxtyping import Array, Complex, Float

from ..linalg import Bordered
from .dominant import dominant_eigenpair, normalise

SCALE = 10.0
"""The rigid modes move to -SCALE max|A| / max|C| (as :class:`~axojax.eigen.mode.
RigidDeflated`'s)."""


def scale_of(max_abs_a, max_abs_c) -> Float[Array, ""]:
    """s = :data:`SCALE` max|A| / max|C| from the two maxima (no derivative: any s > 0
    gives the same deforming eigenpairs). Shared by this module and the dense
    :class:`~axojax.eigen.mode.RigidDeflated`."""
    return jax.lax.stop_gradient(SCALE * max_abs_a / max_abs_c)


def deflate(
    A: Bordered, C: Bordered, Z: Float[Array, "nm r"]
) -> tuple[Bordered, Bordered, Float[Array, ""]]:
    """The extended pencil (A_ext, C_ext) of the module docstring, r unknowns longer, and
    the scale s. ``Z``: (n + m, r) rigid motions in the pencil's order (node-major
    unknowns, then the border)."""
    r = Z.shape[1]
    n = A.n_nodes
    Z = jnp.asarray(Z, dtype=A.nb.dtype)
    CZ = jax.vmap(C.matvec, in_axes=1, out_axes=1)(Z)  # (n + m, r)
    ZtC = jax.vmap(C.T.matvec, in_axes=1, out_axes=0)(Z)  # (r, n + m): Z^T C
    Yt = jnp.linalg.solve(ZtC @ Z, ZtC)
    s = scale_of(A.max_abs(), C.max_abs())
    col = s * CZ
    zeros_nr = jnp.zeros((n, r), C.nb.dtype)
    zeros_mr = jnp.zeros((C.m, r), C.bb.dtype)
    A_ext = Bordered(
        A.tri,
        jnp.concatenate([A.nb, col[:n]], axis=1),
        jnp.concatenate([A.bn, Yt[:, :n]], axis=0),
        jnp.block([[A.bb, col[n:]], [Yt[:, n:], -jnp.eye(r, dtype=A.bb.dtype)]]),
    )
    C_ext = Bordered(
        C.tri,
        jnp.concatenate([C.nb, zeros_nr], axis=1),
        jnp.concatenate([C.bn, zeros_nr.T], axis=0),
        jnp.block([[C.bb, zeros_mr], [zeros_mr.T, jnp.zeros((r, r), C.bb.dtype)]]),
    )
    return A_ext, C_ext, s


def truncate(M: Bordered, r: int) -> Bordered:
    """``M`` without its last ``r`` border unknowns (the extended pencil's original)."""
    m = M.m - r
    return Bordered(M.tri, M.nb[:, :m], M.bn[:m], M.bb[:m, :m])


def restore(
    x: Complex[Array, " nmr"], lam: Complex[Array, ""], Z: Float[Array, "nm r"], s
) -> Complex[Array, " nm"]:
    """The original pencil's unit eigenvector ``v' + (s / lambda) Z y`` from the extended
    one's ``[v'; y]``."""
    r = Z.shape[1]
    v, y = x[:-r], x[-r:]
    return normalise(v + (s / lam) * (jnp.asarray(Z, dtype=v.dtype) @ y))


def dense_eigenpair(
    A_ext: Bordered, C_ext: Bordered, r: int
) -> tuple[Complex[Array, ""], Complex[Array, " nmr"]]:
    """The extended pencil's dominant eigenpair, densely (the structured solvers'
    fallback): the r trailing unknowns (no C there) eliminated, ``A' = A11 - A12
    A22^{-1} A21``, the dominant eigenpair of (A', C11), then ``y = -A22^{-1} A21 v'``."""
    E, F = A_ext.to_dense(), C_ext.to_dense()
    k = E.shape[0] - r
    elim = jnp.linalg.solve(E[k:, k:], E[k:, :k])
    lam, v = dominant_eigenpair(E[:k, :k] - E[:k, k:] @ elim, F[:k, :k])
    return lam, normalise(jnp.concatenate([v, -(elim.astype(v.dtype) @ v)]))
