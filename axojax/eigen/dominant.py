"""The dominant eigenpair and its exact derivative.

``dominant_eigenpair(A, C)`` returns the eigenvalue of largest real part (taken in the
upper half plane, Im >= 0, so that conjugate pairs give one answer) and its unit
right eigenvector. Its derivative is defined by a custom JVP rule (implicit
differentiation of ``(A + lambda C) v = 0``, ``v^H v = 1``); reverse mode follows by
JAX's transposition of that linear rule.

Derivative rule (simple eigenvalue)::

    [A + lambda C   C v ] [dv     ]   [-(dA + lambda dC) v]
    [v^H            0   ] [dlambda] = [ 0                 ]

one bordered LU factorisation per point, two triangular solves per tangent. The
eigenvalue derivative is taken from the left eigenvector w,
``dlambda = -w^H (dA + lambda dC) v / (w^H C v)``, which equals the bordered solution.

Degenerate eigenvalues. Eigenvalues within ``CLUSTER_RTOL * (1 + |lambda|)`` of the
dominant one (up to ``MAX_CLUSTER`` of them; e.g. the multiple eigenvalues of
isotropic cross-sections, ``out_of_plane = 1``) form a *cluster*:

- the returned eigenvalue is the cluster mean, and its derivative is the derivative of
  the mean, ``trace((W^H C V)^{-1} W^H (-(dA + lambda dC)) V) / m`` — smooth, unlike
  the individual branches;
- the returned eigenvector is one vector of the cluster's eigenspace; its derivative is
  the component outside the cluster (the border then holds every cluster vector), which
  is finite. Functions of v that do not depend on which vector of the eigenspace was
  chosen get exact derivatives; others get a well-defined, finite gauge choice.

Gauge: values are normalised to unit norm with the largest entry real and positive;
tangents satisfy ``v^H dv = 0``. Scale- and phase-invariant functions of v (every mode
metric of :mod:`axojax.eigen.metrics`) therefore get exact derivatives.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.linalg import lu_factor, lu_solve
from jaxtyping import Array, Complex, Float

from .pencil import eigensystem, reduced_matrix

CLUSTER_RTOL = 1e-7
MAX_CLUSTER = 4


def _select(lam: Complex[Array, " n"]) -> tuple[Array, Array]:
    """Index of the dominant eigenvalue (largest real part, Im >= 0) followed by the
    indices of its ``MAX_CLUSTER - 1`` nearest neighbours, and the 0/1 membership mask
    (first entry 1) of those within ``CLUSTER_RTOL * (1 + |lambda|)``. Neighbours come
    from both half planes: a real multiple eigenvalue may be returned by LAPACK as a
    real value plus a pair +-1e-10 i."""
    upper = jnp.imag(lam) >= 0
    j1 = jnp.argmax(jnp.where(upper, jnp.real(lam), -jnp.inf))
    dist = jnp.where(jnp.arange(lam.shape[0]) == j1, -1.0, jnp.abs(lam - lam[j1]))
    order = jnp.argsort(dist)[:MAX_CLUSTER]  # j1 first
    mask = (dist[order] <= CLUSTER_RTOL * (1.0 + jnp.abs(lam[j1]))).astype(float)
    return order, mask


def normalise(v: Complex[Array, " n"]) -> Complex[Array, " n"]:
    v = v / jnp.linalg.norm(v)
    big = v[jnp.argmax(jnp.abs(v))]
    return v * (jnp.conj(big) / jnp.abs(big))


def _primal(A, C, left: bool, select=None):
    """Eigenvalue (cluster mean), cluster vectors and left vectors of the eigenvalue that
    ``select`` (default: the dominant one, :func:`_select`) picks."""
    lam, V, W = eigensystem(A, C, left=left)
    order, mask = (select or _select)(lam)
    lam_c = jnp.sum(mask * lam[order]) / jnp.sum(mask)
    if select is None:
        # real clusters: drop the +-0i noise
        lam_c = jnp.where(jnp.imag(lam_c) < 0, jnp.conj(lam_c), lam_c)
    Vc = jax.vmap(normalise, in_axes=1, out_axes=1)(V[:, order])
    Wc = None if W is None else W[:, order]
    return lam_c, Vc, Wc, mask


def _inverse_iteration(A, C, lam, steps: int = 2):
    """Eigenvector of (A + lam C) v = 0 by inverse iteration from a fixed start: one
    complex LU, ``steps`` solves. Much cheaper than all n eigenvectors."""
    n = A.shape[0]
    cdt = jnp.result_type(lam, jnp.complex64)
    shift = lam * (1.0 + 1e-13) + 1e-13  # avoid an exactly singular factor
    lu = lu_factor(A.astype(cdt) + shift * C.astype(cdt))
    v = (jnp.cos(jnp.arange(n) * 0.7) + 1j * jnp.sin(jnp.arange(n) * 1.3)).astype(cdt)
    for _ in range(steps):
        v = lu_solve(lu, C.astype(cdt) @ v)
        v = v / jnp.linalg.norm(v)
    return normalise(v)


@jax.custom_jvp
def dominant_eigenpair(
    A: Float[Array, "n n"], C: Float[Array, "n n"]
) -> tuple[Complex[Array, ""], Complex[Array, " n"]]:
    """Dominant eigenvalue (Im >= 0; cluster mean if degenerate) and unit eigenvector
    of ``(A + lambda C) v = 0``. Differentiable in A and C (see module docstring).

    Values: all eigenvalues (LAPACK, no eigenvectors), then the eigenvector by inverse
    iteration; the derivative rule computes the full left/right eigen-system."""
    S, _, _ = reduced_matrix(A, C)
    lam = jax.lax.linalg.eig(S, compute_left_eigenvectors=False, compute_right_eigenvectors=False)[
        0
    ]
    order, mask = _select(lam)
    lam_c = jnp.sum(mask * lam[order]) / jnp.sum(mask)
    lam_c = jnp.where(jnp.imag(lam_c) < 0, jnp.conj(lam_c), lam_c)
    return lam_c, _inverse_iteration(A, C, lam[order[0]])


@dominant_eigenpair.defjvp
def _dominant_jvp(primals, tangents):
    A, C = primals
    dA, dC = tangents
    return eigenpair_jvp(A, C, dA, dC, *_primal(A, C, left=True))


def eigenpair_jvp(A, C, dA, dC, lam, Vc, Wc, mask):
    """The tangent of a selected eigenpair (see the module docstring): ``lam`` the
    (cluster-mean) eigenvalue, ``Vc``/``Wc`` the right/left vectors of the selected
    eigenvalue and its ``MAX_CLUSTER - 1`` neighbours, ``mask`` their cluster membership."""
    n, k = A.shape[0], mask.shape[0]
    cdt = Vc.dtype
    v1 = Vc[:, 0]
    K = A.astype(cdt) + lam * C.astype(cdt)
    CV = C.astype(cdt) @ Vc
    # Bordered matrix with one border per cluster member; borders of non-members are
    # switched off (a decoupled unit row/column), so a simple eigenvalue gets the
    # classic single border [[K, C v], [v^H, 0]].
    top = jnp.concatenate([K, CV * mask[None, :]], axis=1)
    bottom = jnp.concatenate(
        [jnp.conj(Vc).T * mask[:, None], jnp.diag(1.0 - mask).astype(cdt)], axis=1
    )
    lu = lu_factor(jnp.concatenate([top, bottom], axis=0))

    dK = dA.astype(cdt) + lam * dC.astype(cdt)
    rhs = jnp.concatenate([-(dK @ v1), jnp.zeros(k, cdt)])
    dv = lu_solve(lu, rhs)[:n]

    # Eigenvalue derivative: mean of the cluster's eigenvalue derivatives,
    # trace((W^H C V)^{-1} W^H (-dK) V) / m (one term if the eigenvalue is simple).
    outer = mask[:, None] * mask[None, :]
    M = (jnp.conj(Wc).T @ CV) * outer + jnp.diag(1.0 - mask)
    T = (jnp.conj(Wc).T @ (-(dK @ Vc))) * outer
    dlam = jnp.trace(jnp.linalg.inv(M) @ T) / jnp.sum(mask)
    dlam = jnp.where(jnp.imag(lam) == 0, jnp.real(dlam).astype(cdt), dlam)
    return (lam, v1), (dlam, dv)
