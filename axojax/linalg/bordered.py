"""Block-tridiagonal matrices with a border of m extra unknowns, and their factorisations.

A model's node unknowns give a block-tridiagonal matrix T (n = N b unknowns, node-major);
unknowns that are not node dofs (basal sliding of each active pair, a head's rigid-body
motion, ...) add a border of m unknowns after them::

    M = [[T,    B_nb],     T: (n, n) block-tridiagonal, B_nb: (n, m)
         [B_bn, B_bb]]     B_bn: (m, n), B_bb: (m, m)

With m small (up to ~20) M is factored through T and the Schur complement
``S = B_bb - B_bn T^{-1} B_nb`` (m solves with T's factors, one small dense
factorisation): O(N b^3 + m N b^2 + m^3), still linear in the number of elements.

- :class:`Bordered`: the matrix (a pytree; ``m = 0`` is a plain block-tridiagonal matrix,
  and every operation then is exactly :class:`~axojax.linalg.BlockTridiagonal`'s).
- :func:`bordered_lu` -> :class:`BorderedLU` (``solve``, ``solve_transpose``).
- :func:`bordered_cholesky` -> :class:`BorderedCholesky` (``solve``, ``ok``: M is
  symmetric positive definite exactly when T and S are).

Vectors are flat, (n + m,): the node unknowns, then the border.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jax.scipy.linalg import solve_triangular
from jaxtyping import Array, ArrayLike, Bool, Float, Inexact

from . import small
from .blocktri import (
    BlockCholesky,
    BlockLU,
    BlockTridiagonal,
    LocalBlockLU,
    PackedBlockLU,
    _check,
    cholesky,
    lu_factor,
    lu_factor_local,
    lu_factor_packed,
)


class Bordered(eqx.Module):
    """An (n + m) x (n + m) matrix: block-tridiagonal ``tri`` (n = N b) and a border.

    Attributes:
        tri: the node-node part, :class:`BlockTridiagonal`.
        nb: (n, m) node-border coupling (columns of the border unknowns).
        bn: (m, n) border-node coupling (rows of the border equations).
        bb: (m, m) border-border block.
    """

    tri: BlockTridiagonal
    nb: Inexact[Array, "n m"]
    bn: Inexact[Array, "m n"]
    bb: Inexact[Array, "m m"]

    @property
    def n_nodes(self) -> int:
        """n: the node unknowns (N blocks of size b)."""
        return self.tri.shape[0]

    @property
    def m(self) -> int:
        """The border's size."""
        return self.bb.shape[-1]

    @property
    def shape(self) -> tuple[int, int]:
        n = self.n_nodes + self.m
        return (n, n)

    def _map(self, f, other=None) -> "Bordered":
        if other is None:
            return Bordered(f(self.tri), f(self.nb), f(self.bn), f(self.bb))
        return Bordered(
            f(self.tri, other.tri), f(self.nb, other.nb), f(self.bn, other.bn), f(self.bb, other.bb)
        )

    def __add__(self, other: "Bordered") -> "Bordered":
        return self._map(lambda x, y: x + y, other)

    def __sub__(self, other: "Bordered") -> "Bordered":
        return self._map(lambda x, y: x - y, other)

    def scale(self, factor) -> "Bordered":
        return Bordered(
            self.tri.scale(factor), factor * self.nb, factor * self.bn, factor * self.bb
        )

    @property
    def T(self) -> "Bordered":
        """The transpose (not conjugated)."""
        return Bordered(self.tri.T, self.bn.T, self.nb.T, self.bb.T)

    def astype(self, dtype) -> "Bordered":
        return self._map(lambda x: x.astype(dtype))

    def matvec(self, x: Inexact[Array, " nm"]) -> Inexact[Array, " nm"]:
        """``M @ x`` for a flat (n + m,) vector."""
        if self.m == 0:
            return self.tri.matvec(x)
        n = self.n_nodes
        xn, xb = x[:n], x[n:]
        return jnp.concatenate(
            [self.tri.matvec(xn) + _mv(self.nb, xb), _mv(self.bn, xn) + _mv(self.bb, xb)]
        )

    def to_dense(self) -> Inexact[Array, "nm nm"]:
        """The full matrix (for tests and the dense fallback)."""
        T = self.tri.to_dense()
        if self.m == 0:
            return T
        dt = jnp.result_type(T, self.nb, self.bn, self.bb)
        return jnp.block(
            [[T.astype(dt), self.nb.astype(dt)], [self.bn.astype(dt), self.bb.astype(dt)]]
        )

    def max_abs(self) -> Array:
        """max |M_ij| (0 for an empty part)."""
        parts = (self.tri.lower, self.tri.diag, self.tri.upper, self.nb, self.bn, self.bb)
        return jnp.max(jnp.stack([jnp.max(jnp.abs(x), initial=0.0) for x in parts]))


def _mv(B: Inexact[Array, "p q"], x: Inexact[Array, " q"]) -> Inexact[Array, " p"]:
    """``B @ x``; a real B times a complex x as two real products (as
    :meth:`BlockTridiagonal.matvec`)."""
    if jnp.iscomplexobj(x) and not jnp.iscomplexobj(B):
        y = B @ jnp.stack([x.real, x.imag], -1)
        return jax.lax.complex(y[:, 0], y[:, 1])
    return B @ x


def bordered(
    tri: "BlockTridiagonal | Bordered",
    nb: Inexact[ArrayLike, "_ _"] | None = None,
    bn: Inexact[ArrayLike, "_ _"] | None = None,
    bb: Inexact[ArrayLike, "_ _"] | None = None,
) -> Bordered:
    """``tri`` with the given border, (n, m), (m, n), (m, m) (``None``: no border,
    m = 0; shapes checked here, in one line). A :class:`Bordered` given as ``tri`` is
    returned as it is."""
    if isinstance(tri, Bordered):
        return tri
    n, dt = tri.shape[0], tri.diag.dtype
    if nb is None and bn is None and bb is None:
        m = 0
        nb, bn, bb = jnp.zeros((n, 0), dt), jnp.zeros((0, n), dt), jnp.zeros((0, 0), dt)
    else:
        nb, bn, bb = jnp.asarray(nb), jnp.asarray(bn), jnp.asarray(bb)
        m = bb.shape[-1]
    if nb.shape[-2:] != (n, m) or bn.shape[-2:] != (m, n) or bb.shape[-2:] != (m, m):
        raise ValueError(
            f"border shapes must be (n, m), (m, n), (m, m) with n = {n}, m = {m}; "
            f"got {nb.shape}, {bn.shape}, {bb.shape}"
        )
    return Bordered(tri, nb, bn, bb)


def _small_inverse_lu(S: Inexact[Array, "m m"], kernels: str) -> Inexact[Array, "m m"]:
    """S^{-1} by pivoted LU (``kernels``: LAPACK, or plain jnp for the batched path)."""
    m = S.shape[-1]
    eye = jnp.eye(m, dtype=S.dtype)
    if kernels == "jnp":
        lu, perm = small.lu_pivoted(S)
        linv = small.triangular_inverse(lu, lower=True, unit_diagonal=True)
        uinv = small.triangular_inverse(lu, lower=False)
    else:
        lu, _, perm = jax.lax.linalg.lu(S)
        linv = solve_triangular(lu, eye, lower=True, unit_diagonal=True)
        uinv = solve_triangular(lu, eye, lower=False)
    # S[perm] = L U, so S^{-1} = U^{-1} L^{-1} P with P the rows' permutation.
    return (uinv @ linv)[:, jnp.argsort(perm)]


class BorderedLU(eqx.Module):
    """Factors of :func:`bordered_lu`: T's block LU (:class:`BlockLU`, or
    :class:`PackedBlockLU` when packed), ``Z = T^{-1} B_nb`` and the inverse of the Schur
    complement (m x m)."""

    tri: BlockLU | PackedBlockLU | LocalBlockLU
    z: Inexact[Array, "n m"]
    sinv: Inexact[Array, "m m"]
    bn: Inexact[Array, "m n"]
    nb: Inexact[Array, "n m"]

    def solve(self, rhs: Inexact[Array, " nm"]) -> Inexact[Array, " nm"]:
        """``M^{-1} rhs``: x0 = T^{-1} f, y = S^{-1} (g - B_bn x0), x = x0 - Z y."""
        m = self.sinv.shape[-1]
        if m == 0:
            return self.tri.solve(rhs)
        n = self.z.shape[-2]
        x0 = self.tri.solve(rhs[:n])
        y = self.sinv @ (rhs[n:] - self.bn @ x0)
        return jnp.concatenate([x0 - self.z @ y, y])

    def solve_transpose(self, rhs: Inexact[Array, " nm"]) -> Inexact[Array, " nm"]:
        """``M^{-T} rhs`` (not conjugated): y = S^{-T} (g - Z^T f),
        x = T^{-T} (f - B_bn^T y)."""
        m = self.sinv.shape[-1]
        if m == 0:
            return self.tri.solve_transpose(rhs)
        n = self.z.shape[-2]
        f, g = rhs[:n], rhs[n:]
        y = self.sinv.T @ (g - self.z.T @ f)
        return jnp.concatenate([self.tri.solve_transpose(f - self.bn.T @ y), y])


def bordered_lu(
    M: Bordered | BlockTridiagonal,
    kernels: str = "lapack",
    packed: bool = False,
    local: bool = False,
) -> BorderedLU:
    """LU of a bordered matrix through T's pivoted block LU
    (:func:`~axojax.linalg.lu_factor`) and the Schur complement's (pivoted, dense).
    ``kernels``: see :data:`axojax.linalg.blocktri.KERNELS`. ``packed``: T's factors in
    LAPACK's packed form (:func:`~axojax.linalg.lu_factor_packed`; LAPACK kernels only),
    about half the factorisation's cost, for a matrix solved only a few times. ``local``
    (with ``packed``): pivoting inside T's diagonal blocks only
    (:func:`~axojax.linalg.lu_factor_local`), half that again, for solves that are
    refined with the exact residual."""
    _check(kernels)
    if packed and kernels != "lapack":
        raise ValueError(f"packed factors need kernels='lapack', got {kernels!r}")
    if local and not packed:
        raise ValueError("local pivoting needs packed=True")
    M = bordered(M)
    if packed:
        lu = lu_factor_local(M.tri) if local else lu_factor_packed(M.tri)
    else:
        lu = lu_factor(M.tri, kernels)
    if M.m == 0:
        return BorderedLU(lu, M.nb, M.bb, M.bn, M.nb)
    z = jax.vmap(lu.solve, in_axes=1, out_axes=1)(M.nb)
    return BorderedLU(lu, z, _small_inverse_lu(M.bb - M.bn @ z, kernels), M.bn, M.nb)


class BorderedCholesky(eqx.Module):
    """Factors of :func:`bordered_cholesky`.

    Attributes:
        ok: whether M was (numerically) positive definite.
    """

    tri: BlockCholesky
    z: Float[Array, "n m"]
    sinv: Float[Array, "m m"]
    nb: Float[Array, "n m"]
    ok: Bool[Array, ""]

    def solve(self, rhs):
        """``M^{-1} rhs`` (as :meth:`BorderedLU.solve`, B_bn = B_nb^T)."""
        m = self.sinv.shape[-1]
        if m == 0:
            return self.tri.solve(rhs)
        n = self.z.shape[-2]
        x0 = self.tri.solve(rhs[:n])
        y = self.sinv @ (rhs[n:] - self.nb.T @ x0)
        return jnp.concatenate([x0 - self.z @ y, y])


def bordered_cholesky(M: Bordered | BlockTridiagonal, kernels: str = "lapack") -> BorderedCholesky:
    """Cholesky of a symmetric bordered matrix (only T's ``diag``/``lower``, ``nb`` and
    ``bb`` are read): T's block Cholesky (:func:`~axojax.linalg.cholesky`), then the
    Schur complement ``B_bb - B_nb^T T^{-1} B_nb``'s. ``ok`` is False, without an error,
    when M is not positive definite (M is exactly when T and the Schur complement are)."""
    _check(kernels)
    M = bordered(M)
    chol = cholesky(M.tri, kernels)
    if M.m == 0:
        return BorderedCholesky(chol, M.nb, M.bb, M.nb, chol.ok)
    z = jax.vmap(chol.solve, in_axes=1, out_axes=1)(M.nb)
    S = M.bb - M.nb.T @ z
    S = (S + S.T) / 2
    eye = jnp.eye(M.m, dtype=S.dtype)
    if kernels == "jnp":
        linv = small.triangular_inverse(small.cholesky_lower(S), lower=True)
    else:
        linv = solve_triangular(jnp.linalg.cholesky(S), eye, lower=True)
    ok = chol.ok & jnp.all(jnp.isfinite(linv))
    return BorderedCholesky(chol, z, linv.T @ linv, M.nb, ok)
