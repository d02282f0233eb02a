"""Floquet multipliers of a harmonic-balance orbit by Hill's method.

A perturbation ``y = e^{mu t} p(theta)`` of the orbit, p periodic, obeys
``(omega C d/dtheta + A + Df(q(theta))) p = -mu C p``: in the harmonic basis,
``J p = -mu M p`` with J the harmonic-balance Jacobian (at fixed omega) and
``M = I (x) C``. Each exponent mu appears with its aliases ``mu + i k omega``; the
member with ``|Im mu| <= omega / 2`` is the converged one (its eigenvector sits on the
low harmonics), and the multiplier is ``rho = exp(mu T)``, ``T = 2 pi / omega``.

Only the exponents near 0 decide stability (the stiff link modes have ``rho ~ 0``), so
they are found by shift-invert Arnoldi on ``(J + s M)^{-1} M`` (s = ``shift`` omega,
one block-tridiagonal LU in the node layout, ``krylov`` steps with full re-orthogonalisation) rather than by the dense
eigen-decomposition of the whole Hill matrix. The phase exponent 0 is exact up to
round-off (the discretisation keeps the phase-shift symmetry, see
:mod:`axojax.orbits.fourier`).

On a base that moves each rigid motion Z is an exact eigenvector at mu = 0 too (at
harmonic 0): a Krylov space from one start vector holds only one vector of a multiple
eigenvalue, so they are taken out first. :func:`floquet_multipliers` moves them to
mu = -s (Brauer: ``J + s M (e_0 (x) Z)(e_0 (x) Y)^T``, every other exponent kept,
:mod:`axojax.orbits.rigid`), and :func:`rigid_floquet` gives their own multipliers.
"""

from __future__ import annotations

import jax.numpy as jnp

from ..linalg import arnoldi_steps
from .fourier import Problem
from .linear import factor
from .rigid import deflation_scale, rigid_multipliers


def floquet_multipliers(
    prob: Problem,
    X,
    omega,
    *,
    count: int = 8,
    krylov: int = 60,
    shift: float = 0.05,
    tol: float = 1e-8,
):
    """The ``count`` multipliers of largest modulus (complex, NaN-padded), largest first;
    on a base that moves, without the rigid motions' (:func:`rigid_floquet`).

    Args:
        prob: the harmonic-balance problem of the orbit.
        X: (2H+1, n) coefficients of the orbit; omega: its angular frequency (1/tau).
        count: how many multipliers to return.
        krylov: Arnoldi steps (at most the size of the Hill matrix).
        shift: the shift, as a multiple of omega (an exponent mu = shift omega would
            make the factorisation singular; any value away from the exponents works).
        tol: relative Ritz residual below which a multiplier is accepted.
    """
    J = prob.jacobian_blocks(X, omega)
    M = prob.mass_blocks()
    if prob.r:  # one dense block, harmonic-major: the rigid motions at harmonic 0 moved away
        U = jnp.zeros((prob.m, prob.n, prob.r)).at[0].set(prob.rigid.drag)
        V = jnp.zeros((prob.m, prob.n, prob.r)).at[0].set(prob.rigid.coords.T)
        U, V = U.reshape(-1, prob.r), V.reshape(-1, prob.r)
        scale = deflation_scale(prob.s.A, prob.s.C)
        J = type(J)(J.lower, J.diag.at[0].add(scale * U @ V.T), J.upper)
    N = J.shape[0]
    k = min(krylov, N - 1)
    s = -shift * omega  # pencil value nu = -mu
    lu = factor(J - M.scale(s))
    v0 = jnp.cos(0.61 * jnp.arange(N)) + 0.5
    V = jnp.zeros((k + 1, N), v0.dtype).at[0].set(v0 / jnp.linalg.norm(v0))
    V, Hm = arnoldi_steps(lambda v: lu.solve(M.matvec(v)), V, jnp.zeros((k + 1, k), v0.dtype), 0, k)
    theta, Y = jnp.linalg.eig(Hm[:k, :k])
    resid = jnp.abs(Hm[k, k - 1]) * jnp.abs(Y[k - 1, :])
    nu = s + 1.0 / theta
    mu = -nu
    good = (
        (resid <= tol * jnp.abs(theta))
        & (jnp.abs(jnp.imag(mu)) <= 0.5 * omega * (1 + 1e-9))
        & jnp.isfinite(mu)
    )
    rho = jnp.exp(mu * 2 * jnp.pi / omega)
    key = jnp.where(good, jnp.abs(rho), -1.0)
    order = jnp.argsort(-key)
    rho, key = rho[order], key[order]
    # Aliases on |Im mu| = omega / 2 give the same multiplier twice: drop repeats.
    close = jnp.abs(rho[:, None] - rho[None, :]) <= 1e-7 * (1 + jnp.abs(rho[:, None]))
    earlier = jnp.tril(jnp.ones((k, k), bool), -1)
    dup = jnp.any(close & earlier & (key[None, :] >= 0), axis=1)
    keep = (key >= 0) & ~dup
    order = jnp.argsort(jnp.where(keep, -key, jnp.inf))
    rho = jnp.where(keep[order], rho[order], jnp.nan + 0j)
    if k < count:
        rho = jnp.concatenate([rho, jnp.full(count - k, jnp.nan + 0j)])
    return rho[:count]


def rigid_floquet(prob: Problem, X, omega):
    """(r,) the multipliers of the rigid motions (1 to rounding; empty on a held base):
    :func:`~axojax.orbits.rigid.rigid_multipliers` on the mean's Jacobian."""
    if prob.r == 0:
        return jnp.zeros((0,), complex)
    n = prob.n
    J0 = prob.harmonic_jacobian(X, omega)[:n, :n]
    return rigid_multipliers(J0, prob.rigid, prob.s.C, omega)
