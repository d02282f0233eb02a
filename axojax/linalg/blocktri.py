"""Block-tridiagonal matrices and their factorisations, in pure JAX.

Ordered node-major (all filaments and directions of node k together), the finite-element
matrices of every model are block-tridiagonal: element matrices couple neighbouring nodes
only, and inter-filament coupling stays inside a node block. With N node blocks of size b
a factorisation then costs O(N b^3) and a solve O(N b^2): linear in the number of
elements, where a dense LU costs O((N b)^3).

- :class:`BlockTridiagonal`: the matrix (``lower``, ``diag``, ``upper`` blocks), a pytree.
- :func:`lu_factor` -> :class:`BlockLU`: LU with partial pivoting across each pair of
  block rows (the blocked form of LAPACK's banded ``gbtrf``; as stable as partial
  pivoting on the band). ``solve`` and ``solve_transpose`` (for left eigenvectors).
- :func:`lu_factor_packed` -> :class:`PackedBlockLU`: the same elimination, kept as
  LAPACK's packed panel factors (no block inverses): about half the factorisation's cost,
  for matrices that are solved with only a few times (the derivative rule of
  :mod:`axojax.eigen.arnoldi`).
- :func:`lu_factor_local` -> :class:`LocalBlockLU`: pivoting inside each diagonal block
  only (block Thomas), about half the flops again, for a matrix whose solves are refined
  with the exact residual (the derivative rule).
- :func:`cholesky` -> :class:`BlockCholesky`: for symmetric positive definite matrices;
  its ``ok`` flag doubles as a positive-definiteness test.

Everything is ``lax.scan`` over the blocks: jit-, vmap- and (for the matrices' entries)
grad-able, real or complex. The factorisations take ``kernels="lapack"`` (default) or
``"jnp"`` (no LAPACK custom calls: the batched path, see :data:`KERNELS`).
"""

from __future__ import annotations

from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
from jax.scipy.linalg import solve_triangular
from jaxtyping import Array, Bool, Float, Inexact

from . import small

KERNELS = ("lapack", "jnp")
"""Small-block kernels of the factorisations: ``lapack`` (``jax.lax.linalg``: LAPACK on
CPU, fastest per point) or ``jnp`` (:mod:`axojax.linalg.small`: plain jnp loops, which
``vmap`` turns into batched elementwise operations on any backend)."""


def _check(kernels: str) -> None:
    if kernels not in KERNELS:
        raise ValueError(f"kernels must be one of {KERNELS}, got {kernels!r}")


class BlockTridiagonal(eqx.Module):
    """An (N b) x (N b) block-tridiagonal matrix.

    Attributes:
        lower: (N-1, b, b); ``lower[k]`` is block (k+1, k).
        diag: (N, b, b); ``diag[k]`` is block (k, k).
        upper: (N-1, b, b); ``upper[k]`` is block (k, k+1).
    """

    lower: Inexact[Array, "N1 b b"]
    diag: Inexact[Array, "N b b"]
    upper: Inexact[Array, "N1 b b"]

    @property
    def n_blocks(self) -> int:
        return self.diag.shape[-3]

    @property
    def block_size(self) -> int:
        return self.diag.shape[-1]

    @property
    def shape(self) -> tuple[int, int]:
        n = self.n_blocks * self.block_size
        return (n, n)

    def __add__(self, other: "BlockTridiagonal") -> "BlockTridiagonal":
        return BlockTridiagonal(
            self.lower + other.lower, self.diag + other.diag, self.upper + other.upper
        )

    def __sub__(self, other: "BlockTridiagonal") -> "BlockTridiagonal":
        return BlockTridiagonal(
            self.lower - other.lower, self.diag - other.diag, self.upper - other.upper
        )

    def scale(self, factor) -> "BlockTridiagonal":
        return BlockTridiagonal(factor * self.lower, factor * self.diag, factor * self.upper)

    @property
    def T(self) -> "BlockTridiagonal":
        """The transpose (not conjugated)."""
        tr = lambda x: jnp.swapaxes(x, -1, -2)
        return BlockTridiagonal(tr(self.upper), tr(self.diag), tr(self.lower))

    def astype(self, dtype) -> "BlockTridiagonal":
        return BlockTridiagonal(
            self.lower.astype(dtype), self.diag.astype(dtype), self.upper.astype(dtype)
        )

    def matvec(self, x: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M @ x`` for a flat (N b,) vector. A real M times a complex x is two real
        products (its real and imaginary parts as two columns), not a complex product
        with M promoted: half the flops, and no complex copy of M (the shift-invert
        steps of :mod:`axojax.eigen.arnoldi_nearest`)."""
        N, b = self.n_blocks, self.block_size
        if jnp.iscomplexobj(x) and not jnp.iscomplexobj(self.diag):
            X = jnp.stack([x.real, x.imag], -1).reshape(N, b, 2)
            y = jnp.einsum("kij,kjc->kic", self.diag, X)
            y = y.at[1:].add(jnp.einsum("kij,kjc->kic", self.lower, X[:-1]))
            y = y.at[:-1].add(jnp.einsum("kij,kjc->kic", self.upper, X[1:]))
            return jax.lax.complex(y[..., 0], y[..., 1]).reshape(-1)
        X = x.reshape(N, b)
        y = jnp.einsum("kij,kj->ki", self.diag, X)
        y = y.at[1:].add(jnp.einsum("kij,kj->ki", self.lower, X[:-1]))
        y = y.at[:-1].add(jnp.einsum("kij,kj->ki", self.upper, X[1:]))
        return y.reshape(-1)

    def to_dense(self) -> Inexact[Array, "n n"]:
        """The full matrix (for tests and small problems)."""
        N, b = self.n_blocks, self.block_size
        M = jnp.zeros((N, b, N, b), dtype=self.diag.dtype)
        k = jnp.arange(N)
        M = M.at[k, :, k, :].set(self.diag)
        M = M.at[k[1:], :, k[:-1], :].set(self.lower)
        M = M.at[k[:-1], :, k[1:], :].set(self.upper)
        return M.reshape(N * b, N * b)


class _Padded(NamedTuple):
    """M's blocks with one extra identity block appended (decoupled from the rest), so
    that every elimination step of :func:`lu_factor` has the same shapes. Not a
    :class:`BlockTridiagonal`: ``upper`` has two padding blocks (step k reads block
    (k+1, k+2), up to (N, N+1)), one more than ``lower``."""

    lower: Inexact[Array, "N b b"]
    diag: Inexact[Array, "Np1 b b"]
    upper: Inexact[Array, "Np1 b b"]


def _padded(M: BlockTridiagonal) -> _Padded:
    b, dt = M.block_size, M.diag.dtype
    zero = jnp.zeros((1, b, b), dt)
    return _Padded(
        jnp.concatenate([M.lower, zero]),
        jnp.concatenate([M.diag, jnp.eye(b, dtype=dt)[None]]),
        jnp.concatenate([M.upper, zero, zero]),
    )


class BlockLU(eqx.Module):
    """Factors of :func:`lu_factor`, stored so that solves are matrix-vector products.

    For block column k: ``fwd[k]`` (2b, 2b) is the elimination ``L_k^{-1} P_k`` of block
    rows (k, k+1) (row exchange, then the panel's unit-lower factor), ``uinv[k]`` the
    inverse of the diagonal block of U, ``u12[k]``, ``u13[k]`` U's blocks (k, k+1) and
    (k, k+2) (the latter is fill-in from row exchanges), and ``w12 = uinv u12``,
    ``w13 = uinv u13``. One padding block is kept internally.
    """

    fwd: Inexact[Array, "N b2 b2"]
    uinv: Inexact[Array, "N b b"]
    u12: Inexact[Array, "N b b"]
    u13: Inexact[Array, "N b b"]
    w12: Inexact[Array, "N b b"]
    w13: Inexact[Array, "N b b"]

    @property
    def n_blocks(self) -> int:
        return self.uinv.shape[-3]

    def solve(self, rhs: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M^{-1} rhs`` for a flat (N b,) vector."""
        N, b = self.n_blocks, self.uinv.shape[-1]
        R = jnp.concatenate([rhs.reshape(N, b), jnp.zeros((1, b), rhs.dtype)]).astype(
            self.uinv.dtype
        )

        def forward(carry, k):
            out = self.fwd[k] @ jnp.concatenate([carry, R[k + 1]])
            return out[b:], out[:b]

        _, Z = jax.lax.scan(forward, R[0], jnp.arange(N))

        def backward(carry, k):
            x1, x2 = carry
            x = self.uinv[k] @ Z[k] - self.w12[k] @ x1 - self.w13[k] @ x2
            return (x, x1), x

        zeros = jnp.zeros((b,), Z.dtype)
        _, X = jax.lax.scan(backward, (zeros, zeros), jnp.arange(N), reverse=True)
        return X.reshape(-1)

    def solve_transpose(self, rhs: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M^{-T} rhs`` (transpose, not conjugated; conjugate around it for ``M^{-H}``).

        With E_k = L_k^{-1} P_k the elimination of block column k, ``U = E ... E_0 M``,
        so ``M^T x = r`` is ``U^T y = r`` followed by ``x = E_0^T ... E_{N-1}^T y``."""
        N, b = self.n_blocks, self.uinv.shape[-1]
        R = rhs.reshape(N, b).astype(self.uinv.dtype)
        tr = lambda a: jnp.swapaxes(a, -1, -2)

        def forward(carry, k):
            y1, y2 = carry  # y_{k-1}, y_{k-2}
            u12_prev = jnp.where(k >= 1, tr(self.u12[k - 1]), 0.0)
            u13_prev = jnp.where(k >= 2, tr(self.u13[k - 2]), 0.0)
            y = tr(self.uinv[k]) @ (R[k] - u12_prev @ y1 - u13_prev @ y2)
            return (y, y1), y

        zeros = jnp.zeros((b,), R.dtype)
        _, Y = jax.lax.scan(forward, (zeros, zeros), jnp.arange(N))

        def backward(carry, k):
            w = tr(self.fwd[k]) @ jnp.concatenate([Y[k], carry])  # carry: current block row k+1
            return w[:b], w[b:]

        x0, X = jax.lax.scan(backward, zeros, jnp.arange(N), reverse=True)
        # Block row k of the answer is the second half produced at step k-1 (k >= 1), and
        # the final carry for k = 0.
        return jnp.concatenate([x0[None], X[:-1]]).reshape(-1)


def lu_factor(M: BlockTridiagonal, kernels: str = "lapack") -> BlockLU:
    """LU factorisation with partial pivoting inside each pair of block rows.

    Step k factors the (2b, b) panel [row k; block (k+1, k)] with partial pivoting
    (``jax.lax.linalg.lu``), applies the same row exchanges to the next two block
    columns and updates block row k+1. Row exchanges bring block row k+1's entries into
    row k, hence the fill-in block ``u13``. Cost O(N b^3); the inverses kept for the
    solves cost about as much as the factorisation itself. ``kernels``: see :data:`KERNELS`.
    """
    _check(kernels)
    N, b = M.n_blocks, M.block_size
    P = _padded(M)
    eye = jnp.eye(b, dtype=M.diag.dtype)

    def step(carry, k):
        row_k, row_k1 = carry  # current block row k in columns (k, k+1)
        panel = jnp.concatenate([row_k, P.lower[k]])
        if kernels == "jnp":
            lu, perm = small.lu_pivoted(panel)
        else:
            lu, _, perm = jax.lax.linalg.lu(panel)
        l11 = jnp.tril(lu[:b], -1) + eye
        u11 = jnp.triu(lu[:b])
        l21 = lu[b:]
        right = jnp.block([[row_k1, jnp.zeros((b, b), lu.dtype)], [P.diag[k + 1], P.upper[k + 1]]])[
            perm
        ]
        if kernels == "jnp":
            l11inv = small.triangular_inverse(l11, lower=True, unit_diagonal=True)
            u1 = l11inv @ right[:b]
            uinv = small.triangular_inverse(u11, lower=False)
        else:
            u1 = solve_triangular(l11, right[:b], lower=True, unit_diagonal=True)
            l11inv = solve_triangular(l11, eye, lower=True, unit_diagonal=True)
            uinv = solve_triangular(u11, eye, lower=False)
        schur = right[b:] - l21 @ u1
        elim = jnp.block([[l11inv, jnp.zeros((b, b), lu.dtype)], [-l21 @ l11inv, eye]])
        fwd = elim[:, jnp.argsort(perm)]  # fwd @ v == elim @ v[perm]
        u12, u13 = u1[:, :b], u1[:, b:]
        return (schur[:, :b], schur[:, b:]), (fwd, uinv, u12, u13, uinv @ u12, uinv @ u13)

    _, factors = jax.lax.scan(step, (P.diag[0], P.upper[0]), jnp.arange(N))
    return BlockLU(*factors)


class PackedBlockLU(eqx.Module):
    """Factors of :func:`lu_factor_packed`: the elimination of :func:`lu_factor`, kept in
    LAPACK's packed form, so that solves are triangular solves (cheaper to factor than
    :class:`BlockLU`, whose block inverses pay off only over many solves).

    For block column k: ``lu[k]`` (2b, b) the pivoted panel factors (unit-lower L11 and
    U11 packed in the top b rows, L21 below), ``perm[k]`` (2b,) its row permutation (the
    panel's rows ``perm`` are ``L U``), ``u12[k]``, ``u13[k]`` U's blocks (k, k+1) and
    (k, k+2). One padding block is kept internally.
    """

    lu: Inexact[Array, "N b2 b"]
    perm: Array
    u12: Inexact[Array, "N b b"]
    u13: Inexact[Array, "N b b"]

    @property
    def n_blocks(self) -> int:
        return self.lu.shape[-3]

    def solve(self, rhs: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M^{-1} rhs`` for a flat (N b,) vector."""
        N, b = self.n_blocks, self.lu.shape[-1]
        R = jnp.concatenate([rhs.reshape(N, b), jnp.zeros((1, b), rhs.dtype)]).astype(self.lu.dtype)

        def forward(carry, k):
            v = jnp.concatenate([carry, R[k + 1]])[self.perm[k]]
            z = solve_triangular(self.lu[k, :b], v[:b], lower=True, unit_diagonal=True)
            return v[b:] - self.lu[k, b:] @ z, z

        _, Z = jax.lax.scan(forward, R[0], jnp.arange(N))

        def backward(carry, k):
            x1, x2 = carry
            r = Z[k] - self.u12[k] @ x1 - self.u13[k] @ x2
            x = solve_triangular(self.lu[k, :b], r, lower=False)
            return (x, x1), x

        zeros = jnp.zeros((b,), Z.dtype)
        _, X = jax.lax.scan(backward, (zeros, zeros), jnp.arange(N), reverse=True)
        return X.reshape(-1)

    def solve_transpose(self, rhs: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M^{-T} rhs`` (transpose, not conjugated), as :meth:`BlockLU.solve_transpose`:
        ``U^T y = r``, then the transposed eliminations in reverse order."""
        N, b = self.n_blocks, self.lu.shape[-1]
        R = rhs.reshape(N, b).astype(self.lu.dtype)
        tr = lambda a: jnp.swapaxes(a, -1, -2)

        def forward(carry, k):
            y1, y2 = carry  # y_{k-1}, y_{k-2}
            u12_prev = jnp.where(k >= 1, tr(self.u12[k - 1]), 0.0)
            u13_prev = jnp.where(k >= 2, tr(self.u13[k - 2]), 0.0)
            r = R[k] - u12_prev @ y1 - u13_prev @ y2
            y = solve_triangular(self.lu[k, :b], r, lower=False, trans=1)
            return (y, y1), y

        zeros = jnp.zeros((b,), R.dtype)
        _, Y = jax.lax.scan(forward, (zeros, zeros), jnp.arange(N))

        def backward(carry, k):
            # E_k^T [y_k; carry] with E_k = L_k^{-1} P_k: L_k^{-T} first, then P_k^T.
            top = Y[k] - tr(self.lu[k, b:]) @ carry
            top = solve_triangular(self.lu[k, :b], top, lower=True, unit_diagonal=True, trans=1)
            w = jnp.zeros((2 * b,), top.dtype).at[self.perm[k]].set(jnp.concatenate([top, carry]))
            return w[:b], w[b:]

        x0, X = jax.lax.scan(backward, zeros, jnp.arange(N), reverse=True)
        return jnp.concatenate([x0[None], X[:-1]]).reshape(-1)


def lu_factor_packed(M: BlockTridiagonal) -> PackedBlockLU:
    """The pivoted block LU of :func:`lu_factor` (same elimination, same stability), with
    LAPACK's kernels, kept packed (:class:`PackedBlockLU`): no block inverses, about half
    the cost of :func:`lu_factor` for complex blocks (measured 0.69 against 1.28 ms at
    seven filaments, 10 elements), solves as fast. For a matrix solved only a few times."""
    N, b = M.n_blocks, M.block_size
    P = _padded(M)

    def step(carry, k):
        row_k, row_k1 = carry
        lu, _, perm = jax.lax.linalg.lu(jnp.concatenate([row_k, P.lower[k]]))
        right = jnp.block([[row_k1, jnp.zeros((b, b), lu.dtype)], [P.diag[k + 1], P.upper[k + 1]]])[
            perm
        ]
        # The unit-lower L11 is read from the packed factors (the triangular solve reads
        # only the strictly lower part).
        u1 = solve_triangular(lu[:b], right[:b], lower=True, unit_diagonal=True)
        schur = right[b:] - lu[b:] @ u1
        return (schur[:, :b], schur[:, b:]), (lu, perm, u1[:, :b], u1[:, b:])

    _, factors = jax.lax.scan(step, (P.diag[0], P.upper[0]), jnp.arange(N))
    return PackedBlockLU(*factors)


class LocalBlockLU(eqx.Module):
    """Factors of :func:`lu_factor_local`: block LU with partial pivoting inside each
    diagonal block only, ``M = L U`` with L block lower bidiagonal (diagonal blocks
    ``P_k^T L_k``, sub-diagonal ``l21[k]``) and U block upper bidiagonal (diagonal
    ``U_k``, super-diagonal ``u12[k]``).

    For block row k: ``lu[k]`` (b, b) the packed ``L_k``, ``U_k`` of the k-th Schur
    complement, ``perm[k]`` (b,) its row permutation, ``u12[k]`` = ``L_k^{-1} P_k``
    times block (k, k+1), ``l21[k]`` = block (k+1, k) times ``U_k^{-1}``.
    """

    lu: Inexact[Array, "N b b"]
    perm: Array
    u12: Inexact[Array, "N1 b b"]
    l21: Inexact[Array, "N1 b b"]

    def _shifted(self, blocks, first: bool):
        """``blocks`` (N-1, b, b) padded with a zero block at the start (``first``: entry k
        is block k-1) or at the end (entry k is block k)."""
        zero = jnp.zeros((1,) + blocks.shape[1:], blocks.dtype)
        return jnp.concatenate([zero, blocks] if first else [blocks, zero])

    def solve(self, rhs: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M^{-1} rhs`` for a flat (N b,) vector: ``z_k = L_k^{-1} P_k (r_k - l21[k-1]
        z_{k-1})``, then ``x_k = U_k^{-1} (z_k - u12[k] x_{k+1})``."""
        N, b = self.lu.shape[-3], self.lu.shape[-1]
        R = rhs.reshape(N, b).astype(self.lu.dtype)
        l21, u12 = self._shifted(self.l21, True), self._shifted(self.u12, False)

        def forward(z, k):
            r = (R[k] - l21[k] @ z)[self.perm[k]]
            z = solve_triangular(self.lu[k], r, lower=True, unit_diagonal=True)
            return z, z

        _, Z = jax.lax.scan(forward, jnp.zeros((b,), R.dtype), jnp.arange(N))

        def backward(x, k):
            x = solve_triangular(self.lu[k], Z[k] - u12[k] @ x, lower=False)
            return x, x

        _, X = jax.lax.scan(backward, jnp.zeros((b,), R.dtype), jnp.arange(N), reverse=True)
        return X.reshape(-1)

    def solve_transpose(self, rhs: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """``M^{-T} rhs`` (transpose, not conjugated): ``U^T w = r`` forward, then
        ``L^T x = w`` backward."""
        N, b = self.lu.shape[-3], self.lu.shape[-1]
        R = rhs.reshape(N, b).astype(self.lu.dtype)
        u12, l21 = self._shifted(self.u12, True), self._shifted(self.l21, False)
        tr = lambda a: jnp.swapaxes(a, -1, -2)

        def forward(w, k):
            w = solve_triangular(self.lu[k], R[k] - tr(u12[k]) @ w, lower=False, trans=1)
            return w, w

        _, W = jax.lax.scan(forward, jnp.zeros((b,), R.dtype), jnp.arange(N))

        def backward(x, k):
            t = W[k] - tr(l21[k]) @ x
            t = solve_triangular(self.lu[k], t, lower=True, unit_diagonal=True, trans=1)
            x = jnp.zeros_like(t).at[self.perm[k]].set(t)
            return x, x

        _, X = jax.lax.scan(backward, jnp.zeros((b,), R.dtype), jnp.arange(N), reverse=True)
        return X.reshape(-1)


def lu_factor_local(M: BlockTridiagonal) -> LocalBlockLU:
    """Block LU of a block-tridiagonal matrix with partial pivoting inside each diagonal
    block only (block Thomas: factor the k-th Schur complement ``S_k = D_k - l21[k-1]
    u12[k-1]``, eliminate the next block row through it), LAPACK's kernels, packed
    (:class:`LocalBlockLU`). About half the flops of :func:`lu_factor_packed` (b x b
    instead of 2b x b panels, no 2b-wide Schur update): 0.38 against 0.61 ms for a
    complex matrix at seven filaments, 10 elements.

    Not pivoting across block rows, it is as stable as the Schur complements of M's
    leading block rows are well conditioned: for the finite-element pencils here (the
    node blocks dominated by their stiff in-node couplings) the solves' backward error is
    ~1e-17, as with band pivoting. Its one user, the derivative rule of
    :mod:`axojax.eigen.tangent`, refines every solve with the exact residual, which would
    correct a loss of accuracy; ``tests/eigen/test_tangent.py`` checks the rule against scipy,
    finite differences and an extended-precision solve."""
    N, b = M.n_blocks, M.block_size
    dt = M.diag.dtype
    lower = jnp.concatenate([M.lower, jnp.zeros((1, b, b), dt)])
    upper = jnp.concatenate([M.upper, jnp.zeros((1, b, b), dt)])
    nxt = jnp.concatenate([M.diag[1:], jnp.eye(b, dtype=dt)[None]])  # D_{k+1}, padded

    def step(S, k):
        lu, _, perm = jax.lax.linalg.lu(S)
        u12 = solve_triangular(lu, upper[k][perm], lower=True, unit_diagonal=True)
        # l21 U_k = lower_k  <=>  U_k^T l21^T = lower_k^T
        l21 = jnp.swapaxes(
            solve_triangular(lu, jnp.swapaxes(lower[k], -1, -2), lower=False, trans=1), -1, -2
        )
        return nxt[k] - l21 @ u12, (lu, perm, u12, l21)

    _, (lu, perm, u12, l21) = jax.lax.scan(step, M.diag[0], jnp.arange(N))
    return LocalBlockLU(lu, perm, u12[:-1], l21[:-1])


class BlockCholesky(eqx.Module):
    """Lower block-bidiagonal Cholesky factor: ``lower[k]`` is block (k+1, k) and
    ``dinv[k]`` the inverse of diagonal block (k, k) (kept for matrix-vector solves).

    Attributes:
        ok: whether the matrix was (numerically) positive definite; when False the
            factors hold NaNs.
    """

    dinv: Float[Array, "N b b"]
    lower: Float[Array, "N1 b b"]
    ok: Bool[Array, ""]

    def solve(self, rhs: Float[Array, " n"]) -> Float[Array, " n"]:
        N, b = self.dinv.shape[-3], self.dinv.shape[-1]
        R = rhs.reshape(N, b)
        zero = jnp.zeros((1, b, b), self.dinv.dtype)
        low = jnp.concatenate([zero, self.lower])  # low[k] = block (k, k-1)

        def forward(carry, k):
            y = self.dinv[k] @ (R[k] - low[k] @ carry)
            return y, y

        _, Y = jax.lax.scan(forward, jnp.zeros((b,), R.dtype), jnp.arange(N))
        up = jnp.concatenate([self.lower, zero])  # up[k]^T = block (k, k+1) of L^T

        def backward(carry, k):
            x = self.dinv[k].T @ (Y[k] - up[k].T @ carry)
            return x, x

        _, X = jax.lax.scan(backward, jnp.zeros((b,), R.dtype), jnp.arange(N), reverse=True)
        return X.reshape(-1)


def cholesky(M: BlockTridiagonal, kernels: str = "lapack") -> BlockCholesky:
    """Block Cholesky of a symmetric block-tridiagonal M (only ``diag`` and ``lower`` are
    read). ``ok`` is False, without an error, when M is not positive definite.
    ``kernels``: see :data:`KERNELS`."""
    _check(kernels)
    N, b = M.n_blocks, M.block_size
    low = jnp.concatenate([M.lower, jnp.zeros((1, b, b), M.diag.dtype)])
    eye = jnp.eye(b, dtype=M.diag.dtype)

    def step(prev_lower, k):
        schur = M.diag[k] - prev_lower @ prev_lower.T
        if kernels == "jnp":
            cinv = small.triangular_inverse(small.cholesky_lower(schur), lower=True)
        else:
            cinv = solve_triangular(jnp.linalg.cholesky(schur), eye, lower=True)
        nxt = low[k] @ cinv.T  # block (k+1, k) = A_{k+1,k} C^{-T}
        return nxt, (cinv, nxt)

    _, (dinv, lower) = jax.lax.scan(step, jnp.zeros((b, b), M.diag.dtype), jnp.arange(N))
    ok = jnp.all(jnp.isfinite(dinv))
    return BlockCholesky(dinv, lower[:-1], ok)
