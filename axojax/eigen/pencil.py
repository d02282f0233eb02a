"""Dense eigen-decomposition of the pencil (-A, C).

When C is symmetric positive definite (every model with the steady load or with the
elastic parts chi', beta' of regulated dynein), ``(A + lambda C) v = 0`` is reduced with
the Cholesky factor C = L L^T to the standard problem ``S y = lambda y``,
``S = -L^{-1} A L^{-T}``, ``v = L^{-T} y``; left eigenvectors
(``w^H (A + lambda C) = 0``) map the same way, ``w = L^{-T} u``.

Otherwise (the friction parts chi''/omega0, beta''/omega0 of regulated dynein make C
non-symmetric or indefinite) ``S = -C^{-1} A`` by LU, ``v = y`` and ``w = C^{-T} u``. The
choice is made on the values (a select, so it is jit- and vmap-able); the Cholesky path
is exactly the one used before C could be anything else.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.linalg import solve_triangular
from jaxtyping import Array, Complex, Float

SYMMETRY_RTOL = 1e-12
"""C counts as symmetric when max |C - C^T| <= SYMMETRY_RTOL * max |C|."""


def symmetric_positive_definite(C: Float[Array, "n n"], L: Float[Array, "n n"]) -> Array:
    """Whether C is symmetric and its Cholesky factor L finite (C positive definite)."""
    sym = jnp.max(jnp.abs(C - C.T)) <= SYMMETRY_RTOL * jnp.max(jnp.abs(C))
    return sym & jnp.all(jnp.isfinite(L))


def reduced_matrix(
    A: Float[Array, "n n"], C: Float[Array, "n n"]
) -> tuple[Float[Array, "n n"], Float[Array, "n n"], Array]:
    """(S, L, spd): the reduced matrix S, L = chol(C) (the identity where C is not
    symmetric positive definite) and whether it is (see the module docstring)."""
    L = jnp.linalg.cholesky(C)
    spd = symmetric_positive_definite(C, L)
    eye = jnp.eye(C.shape[0], dtype=C.dtype)
    L = jnp.where(spd, L, eye)
    LA = solve_triangular(L, A, lower=True)
    S_chol = -solve_triangular(L, LA.T, lower=True).T
    S_gen = -jnp.linalg.solve(jnp.where(spd, eye, C), A)
    return jnp.where(spd, S_chol, S_gen), L, spd


def eigenvalues(A: Float[Array, "n n"], C: Float[Array, "n n"]) -> Complex[Array, " n"]:
    """All n eigenvalues of the pencil, sorted by decreasing real part."""
    S, _, _ = reduced_matrix(A, C)
    lam = jax.lax.linalg.eig(S, compute_left_eigenvectors=False, compute_right_eigenvectors=False)[
        0
    ]
    return lam[jnp.argsort(-jnp.real(lam))]


def eigensystem(
    A: Float[Array, "n n"], C: Float[Array, "n n"], left: bool = False
) -> tuple[Complex[Array, " n"], Complex[Array, "n n"], Complex[Array, "n n"] | None]:
    """Eigenvalues, right eigenvectors V (columns) and optionally left eigenvectors W,
    in LAPACK order (not sorted)."""
    S, L, spd = reduced_matrix(A, C)
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
    if ul is None:
        W = None
    else:
        Ct = jnp.where(spd, jnp.eye(C.shape[0], dtype=C.dtype), C.T).astype(ul.dtype)
        W = jnp.where(spd, solve_triangular(Lt, ul, lower=False), jnp.linalg.solve(Ct, ul))
    return lam, V, W
