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

Degenerate eigenvalues. When the next eigenvalue in the upper half plane lies within
``CLUSTER_RTOL * (1 + |lambda|)`` of the dominant one (double eigenvalues of
isotropic cross-sections, ``out_of_plane = 1``), the two form a *cluster*:

- the returned eigenvalue is the cluster mean, and its derivative is the derivative of
  the mean, ``trace((W^H C V)^{-1} W^H (-(dA + lambda dC)) V) / 2`` — smooth, unlike
  the individual branches;
- the returned eigenvector is one vector of the cluster's eigenspace; its derivative is
  the component outside the cluster (the border then has both cluster vectors), which
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

from .pencil import eigensystem

CLUSTER_RTOL = 1e-7


def _select(lam: Complex[Array, " n"]) -> tuple[Array, Array, Array]:
    """Indices of the dominant eigenvalue (Im >= 0) and of its nearest upper-half
    neighbour, and the 0/1 cluster flag."""
    upper = jnp.imag(lam) >= 0
    j1 = jnp.argmax(jnp.where(upper, jnp.real(lam), -jnp.inf))
    dist = jnp.abs(lam - lam[j1])
    dist = jnp.where(upper & (jnp.arange(lam.shape[0]) != j1), dist, jnp.inf)
    j2 = jnp.argmin(dist)
    cluster = (dist[j2] <= CLUSTER_RTOL * (1.0 + jnp.abs(lam[j1]))).astype(float)
    return j1, j2, cluster


def _normalise(v: Complex[Array, " n"]) -> Complex[Array, " n"]:
    v = v / jnp.linalg.norm(v)
    big = v[jnp.argmax(jnp.abs(v))]
    return v * (jnp.conj(big) / jnp.abs(big))


def _primal(A, C, left: bool):
    lam, V, W = eigensystem(A, C, left=left)
    j1, j2, cluster = _select(lam)
    lam_c = (lam[j1] + cluster * lam[j2]) / (1.0 + cluster)
    v1, v2 = _normalise(V[:, j1]), _normalise(V[:, j2])
    w = None if W is None else (W[:, j1], W[:, j2])
    return lam_c, v1, v2, w, cluster


@jax.custom_jvp
def dominant_eigenpair(A: Float[Array, "n n"], C: Float[Array, "n n"]) -> tuple[Complex[Array, ""], Complex[Array, " n"]]:
    """Dominant eigenvalue (Im >= 0; cluster mean if degenerate) and unit eigenvector
    of ``(A + lambda C) v = 0``. Differentiable in A and C (see module docstring)."""
    lam, v1, _, _, _ = _primal(A, C, left=False)
    return lam, v1


@dominant_eigenpair.defjvp
def _dominant_jvp(primals, tangents):
    A, C = primals
    dA, dC = tangents
    lam, v1, v2, (w1, w2), cluster = _primal(A, C, left=True)
    n = A.shape[0]
    cdt = v1.dtype
    K = A.astype(cdt) + lam * C.astype(cdt)
    Cv1, Cv2 = C @ v1, C @ v2
    # Bordered matrix; the second border is switched off (decoupled unit row/column)
    # unless the dominant eigenvalue is part of a double cluster.
    top = jnp.concatenate([K, Cv1[:, None], (cluster * Cv2)[:, None]], axis=1)
    row1 = jnp.concatenate([jnp.conj(v1), jnp.zeros(2, cdt)])[None, :]
    row2 = jnp.concatenate([cluster * jnp.conj(v2), jnp.array([0.0, 1.0 - cluster], cdt)])[None, :]
    lu = lu_factor(jnp.concatenate([top, row1, row2], axis=0))

    dK = dA.astype(cdt) + lam * dC.astype(cdt)
    rhs = jnp.concatenate([-(dK @ v1), jnp.zeros(2, cdt)])
    dv = lu_solve(lu, rhs)[:n]

    # Eigenvalue derivative: mean of the cluster's eigenvalue derivatives (one term if
    # the eigenvalue is simple).
    mm = jnp.array([1.0, cluster])
    outer = mm[:, None] * mm[None, :]
    Vc = jnp.stack([v1, v2], axis=1)
    Wc = jnp.stack([w1, w2], axis=1)
    M = (jnp.conj(Wc).T @ (C.astype(cdt) @ Vc)) * outer + jnp.diag(1.0 - mm)
    T = (jnp.conj(Wc).T @ (-(dK @ Vc))) * outer
    dlam = jnp.trace(jnp.linalg.inv(M) @ T) / (1.0 + cluster)
    return (lam, v1), (dlam, dv)
