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
"""

from __future__ import annotations

import jax.numpy as jnp

from ..linalg import arnoldi_steps
from .fourier import Problem
from .linear import factor


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
    """The ``count`` multipliers of largest modulus (complex, NaN-padded), largest first.

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
