"""Small dense kernels in plain ``jnp`` (no LAPACK custom calls, no host callbacks).

The block factorisations of :mod:`axojax.linalg.blocktri` work on blocks of size b
(28 for the seven-filament model). Per point, LAPACK's kernels are the fastest way to
factor them; but a ``vmap`` of a LAPACK call is a *batched* custom call, which XLA runs
matrix by matrix (and jaxlib 0.10's CPU kernels block on the intra-op pool with it, see
:mod:`axojax._runtime`), and some of them have no batched GPU kernel at all. The kernels
here are loops over the b columns (``lax.fori_loop``) of masked rank-1 updates on the
whole matrix: under ``vmap`` every step is one fused elementwise operation over the
batch, on any backend.

- :func:`lu_pivoted`: LU with partial pivoting of an (m, b) panel, m >= b, in LAPACK's
  packed format (``jax.lax.linalg.lu``'s ``lu`` and ``perm``), same pivot rule
  (largest ``|re| + |im|``, first of equals).
- :func:`cholesky_lower`: lower Cholesky factor; NaNs (like LAPACK's in jax) when the
  matrix is not numerically positive definite.
- :func:`triangular_inverse`: inverse of a lower or upper triangular matrix.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jaxtyping import Array, Inexact, Int


def _magnitude(x):
    """LAPACK's pivot magnitude (``i?amax``): |x| for reals, |re| + |im| for complex."""
    return jnp.abs(jnp.real(x)) + jnp.abs(jnp.imag(x)) if jnp.iscomplexobj(x) else jnp.abs(x)


def lu_pivoted(a: Inexact[Array, "m b"]) -> tuple[Inexact[Array, "m b"], Int[Array, " m"]]:
    """(lu, perm) with ``a[perm] = L U``: L (m, b) unit lower (below the diagonal of
    ``lu``), U (b, b) upper (on and above it). A zero pivot leaves its column
    unscaled (LAPACK's ``info > 0``)."""
    m, b = a.shape
    rows = jnp.arange(m)
    cols = jnp.arange(b)

    def step(j, state):
        a, perm = state
        p = jnp.argmax(jnp.where(rows >= j, _magnitude(a[:, j]), -1.0))
        row_j, row_p = a[j], a[p]
        a = jnp.where((rows == j)[:, None], row_p, jnp.where((rows == p)[:, None], row_j, a))
        perm_j, perm_p = perm[j], perm[p]
        perm = jnp.where(rows == j, perm_p, jnp.where(rows == p, perm_j, perm))
        pivot = a[j, j]
        below = rows > j
        multipliers = jnp.where(below, a[:, j] / jnp.where(pivot == 0, 1.0, pivot), 0.0)
        a = a - multipliers[:, None] * jnp.where(cols > j, a[j], 0.0)[None, :]
        a = jnp.where(below[:, None] & (cols == j)[None, :], multipliers[:, None], a)
        return a, perm

    return jax.lax.fori_loop(0, b, step, (a, rows))


def cholesky_lower(a: Inexact[Array, "b b"]) -> Inexact[Array, "b b"]:
    """Lower Cholesky factor of a symmetric positive definite (real) matrix (only its
    lower triangle is read); NaNs where a pivot is not positive."""
    b = a.shape[-1]
    idx = jnp.arange(b)
    a = jnp.where(idx[:, None] >= idx[None, :], a, 0.0)

    def step(j, a):
        pivot = a[j, j]
        d = jnp.sqrt(jnp.where(pivot > 0, pivot, jnp.nan))
        col = jnp.where(idx >= j, a[:, j] / d, 0.0)  # column j of the factor
        below = jnp.where(idx > j, col, 0.0)
        a = a - jnp.where(idx[:, None] >= idx[None, :], below[:, None] * below[None, :], 0.0)
        return jnp.where((idx == j)[None, :], col[:, None], a)

    return jax.lax.fori_loop(0, b, step, a)


def triangular_inverse(
    t: Inexact[Array, "b b"], lower: bool, unit_diagonal: bool = False
) -> Inexact[Array, "b b"]:
    """Inverse of a triangular matrix (only its triangle is read), row by row:
    ``X[i] = (e_i - T[i, others] @ X) / T[i, i]`` in substitution order."""
    b = t.shape[-1]
    idx = jnp.arange(b)
    eye = jnp.eye(b, dtype=t.dtype)

    def step(k, x):
        i = k if lower else b - 1 - k
        strict = (idx < i) if lower else (idx > i)
        row = jnp.where(strict, t[i], 0.0)
        new = eye[i] - row @ x
        if not unit_diagonal:
            new = new / t[i, i]
        return jnp.where((idx == i)[:, None], new[None, :], x)

    return jax.lax.fori_loop(0, b, step, jnp.zeros_like(t))
