"""Dense eigen-decomposition of the pencil (-A, C) with C symmetric positive definite.

``(A + lambda C) v = 0`` is reduced with the Cholesky factor C = L L^T to the standard
problem ``S y = lambda y``, ``S = -L^{-1} A L^{-T}``, ``v = L^{-T} y``; left
eigenvectors (``w^H (A + lambda C) = 0``) map the same way, ``w = L^{-T} u``.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.linalg import solve_triangular
from jaxtyping import Array, Complex, Float


def reduced_matrix(
    A: Float[Array, "n n"], C: Float[Array, "n n"]
) -> tuple[Float[Array, "n n"], Float[Array, "n n"]]:
    """(S, L): the symmetrically reduced matrix S = -L^{-1} A L^{-T} and L = chol(C)."""
    L = jnp.linalg.cholesky(C)
    LA = solve_triangular(L, A, lower=True)
    S = -solve_triangular(L, LA.T, lower=True).T
    return S, L


def eigenvalues(A: Float[Array, "n n"], C: Float[Array, "n n"]) -> Complex[Array, " n"]:
    """All n eigenvalues of the pencil, sorted by decreasing real part."""
    S, _ = reduced_matrix(A, C)
    lam = jax.lax.linalg.eig(S, compute_left_eigenvectors=False, compute_right_eigenvectors=False)[
        0
    ]
    return lam[jnp.argsort(-jnp.real(lam))]


def eigensystem(
    A: Float[Array, "n n"], C: Float[Array, "n n"], left: bool = False
) -> tuple[Complex[Array, " n"], Complex[Array, "n n"], Complex[Array, "n n"] | None]:
    """Eigenvalues, right eigenvectors V (columns) and optionally left eigenvectors W,
    in LAPACK order (not sorted)."""
    S, L = reduced_matrix(A, C)
    if left:
        lam, ul, ur = jax.lax.linalg.eig(
            S, compute_left_eigenvectors=True, compute_right_eigenvectors=True
        )
    else:
        lam, ur = jax.lax.linalg.eig(
            S, compute_left_eigenvectors=False, compute_right_eigenvectors=True
        )
        ul = None
    Lt = L.T.astype(ur.dtype)
    V = solve_triangular(Lt, ur, lower=False)
    W = None if ul is None else solve_triangular(Lt, ul, lower=False)
    return lam, V, W
