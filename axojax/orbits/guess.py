"""Start of the Newton iteration: the Hopf normal form of the dominant mode.

With ``(A + lambda C) v = 0`` the dominant mode and w its left eigenvector, the beat
near the Hopf point is ``q ~ Re(z v e^{i omega t})`` and the complex amplitude obeys
(Galerkin projection onto the mode, first harmonic of the cubic force)::

    dz/dt = lambda z - c |z|^2 z,   c = w^H g / (w^H C v),

g the first harmonic (complex, ``f ~ Re(g e^{i theta})``) of ``f_nl(Re(v e^{i theta}))``.
Its periodic solution ``|z|^2 = Re lambda / Re c``, ``omega = Im lambda - Im c |z|^2``
exists when ``Re lambda > 0`` and ``Re c > 0`` (supercritical); elsewhere the guess is
NaN and the orbit solver reports failure.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.linalg import lu_factor, lu_solve

from ..eigen.dominant import dominant_eigenpair
from .fourier import Problem


def _left_vector(A, C, lam):
    """w with (A + lam C)^H w = 0, by two steps of inverse iteration."""
    n = A.shape[0]
    K = (A + (lam * (1 + 1e-13) + 1e-13) * C).conj().T
    lu = lu_factor(K)
    w = (jnp.cos(jnp.arange(n) * 0.37) + 1j * jnp.sin(jnp.arange(n) * 0.91)).astype(K.dtype)
    for _ in range(2):
        w = lu_solve(lu, w)
        w = w / jnp.linalg.norm(w)
    return w


def hopf_guess(prob: Problem):
    """(x0, ref, lambda, fallback): the start ``[X.ravel(), omega]`` on ``prob``'s
    harmonics (NaN where the normal form has no orbit), the phase reference (unit vector
    at the largest entry of the mode: its first-harmonic sine coefficient is held at 0,
    so that entry peaks at theta = 0), the dominant eigenvalue, and a finite stand-in
    for failed solves (the mode at amplitude 1e-3, frequency |Im lambda|)."""
    s = prob.s
    lam, v = dominant_eigenpair(s.A, s.C)
    i = jnp.argmax(jnp.abs(v))
    v = v * jnp.conj(v[i]) / jnp.abs(v[i])  # largest entry real and positive
    w = _left_vector(s.A, s.C, lam)
    H, n = prob.H, prob.n
    X1 = jnp.zeros((prob.m, n)).at[1].set(jnp.real(v)).at[H + 1].set(-jnp.imag(v))
    F = prob.P @ jax.vmap(prob.f_nl)(prob.E @ X1)
    g = F[1] - 1j * F[H + 1]
    c = jnp.vdot(w, g) / jnp.vdot(w, s.C @ v)
    amp2 = jnp.real(lam) / jnp.real(c)
    ok = (jnp.real(lam) > 0) & (jnp.real(c) > 0)
    amp = jnp.where(ok, jnp.sqrt(jnp.where(ok, amp2, 1.0)), jnp.nan)
    omega = jnp.imag(lam) - jnp.imag(c) * amp**2
    omega = jnp.where(omega > 0, omega, jnp.imag(lam))
    c0 = jnp.linalg.solve(s.A, s.b)
    X = (amp * X1).at[0].set(c0)
    ref = jnp.zeros(n).at[i].set(1.0)
    fallback = jnp.concatenate([jnp.ravel((1e-3 * X1).at[0].set(c0)), jnp.abs(jnp.imag(lam))[None]])
    return jnp.concatenate([jnp.ravel(X), omega[None]]), ref, lam, fallback

