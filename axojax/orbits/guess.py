"""Start of the Newton iteration: the Hopf normal form at the equilibrium.

The equilibrium ``A q_e + f_nl(q_e) = b`` (bent when the dynein moments leave a static
load b; Newton from ``A^{-1} b``) is linearised, ``A_e = A + Df(q_e)``, and its dominant
mode ``(A_e + lambda C) v = 0`` with left vector w gives the normal form (Kuznetsov,
*Elements of applied bifurcation theory*, section 3.5; quadratic terms appear because
the cubic force is expanded about a bent state)::

    dz/dt = lambda z + (g21 / 2) |z|^2 z,
    g21 = -w^H (D3f[v, v, conj v] + 2 D2f[v, h11] + D2f[conj v, h20]) / (w^H C v),
    h11 = -A_e^{-1} D2f[v, conj v],   h20 = -(A_e + 2 lambda C)^{-1} D2f[v, v],

and the orbit ``q ~ q_e + |z|^2 h11 + 2 Re(z v e^{i theta}) + Re(z^2 h20 e^{2 i theta})``
with ``|z|^2 = -Re lambda / Re(g21 / 2)``, ``omega = Im lambda + Im(g21 / 2) |z|^2``. It
exists for ``Re lambda > 0`` and ``Re g21 < 0`` (supercritical); elsewhere the start is NaN
and the solver reports failure. The multilinear derivatives of the cubic force are
forward-mode derivatives of :func:`axojax.dynamics.nonlinear.cubic_link_force`, which is a
polynomial and so evaluates at complex states.

On a base that moves (:mod:`axojax.orbits.rigid`) A_e is singular along the rigid motions
Z: the equilibrium and h11 are the solutions with no rigid offset (``Y^T q = 0``), and the
dominant mode is that of the pencil with the rigid eigenvalues moved away (Brauer), so
it is the dominant *deforming* mode, as :func:`axojax.dominant_mode` takes it.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jax.scipy.linalg import lu_factor, lu_solve

from ..eigen.dominant import dominant_eigenpair
from .fourier import Problem
from .rigid import deflated, deflation_scale, gauged_solve, restore

EQUILIBRIUM_STEPS = 12


def equilibrium(prob: Problem):
    """q_e with ``A q_e + f_nl(q_e) = b`` (Newton from ``A^{-1} b``; 0 when b = 0); on a
    base that moves, the one without rigid offset (:func:`~axojax.orbits.rigid.gauged_solve`)."""
    s, rigid = prob.s, prob.rigid

    def step(_, q):
        J = s.A + prob.f_nl_tangent(q)
        return q - gauged_solve(J, s.A @ q + prob.f_nl(q) - s.b, rigid)

    return jax.lax.fori_loop(0, EQUILIBRIUM_STEPS, step, gauged_solve(s.A, s.b, rigid))


def dominant_deforming(prob: Problem, Ae):
    """(lambda, v): the dominant eigenpair of ``(Ae + lambda C) v = 0`` without the rigid
    motions' zero eigenvalues (moved away, :func:`~axojax.orbits.rigid.deflated`; the
    plain dominant pair on a held base). v has unit norm, its largest entry real."""
    C, rigid = prob.s.C, prob.rigid
    if rigid.r == 0:
        return dominant_eigenpair(Ae, C)
    scale = deflation_scale(Ae, C)
    lam, w = dominant_eigenpair(deflated(Ae, rigid, scale), C)
    v = restore(w, lam, rigid, scale)
    return lam, v / jnp.linalg.norm(v)


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
    """(x0, ref, lambda, fallback): the start ``[X.ravel(), v, omega]`` (drift v = 0) on ``prob``'s
    harmonics (NaN where the normal form has no orbit), the phase reference (unit vector
    at the largest entry of the mode: its first-harmonic sine coefficient is held at 0,
    so that entry peaks at theta = 0), the dominant eigenvalue at the equilibrium, and a
    finite stand-in for failed solves (the mode at amplitude 1e-3, frequency |Im lambda|)."""
    s, H, n = prob.s, prob.H, prob.n
    qe = equilibrium(prob)
    Ae = s.A + prob.f_nl_tangent(qe)
    lam, v = dominant_deforming(prob, Ae)
    i = jnp.argmax(jnp.abs(v))
    v = v * jnp.conj(v[i]) / jnp.abs(v[i])  # largest entry real and positive
    w = _left_vector(Ae, s.C, lam)

    qc = qe.astype(v.dtype)
    d1 = lambda q, y: jax.jvp(prob.f_nl, (q,), (y,))[1]
    d2 = lambda q, y, z: jax.jvp(lambda a: d1(a, y), (q,), (z,))[1]
    d3 = lambda y, z, u: jax.jvp(lambda a: d2(a, y, z), (qc,), (u,))[1]
    vb = jnp.conj(v)
    h11 = -gauged_solve(Ae, jnp.real(d2(qc, v, vb)), prob.rigid)
    h20 = -jnp.linalg.solve(Ae + 2 * lam * s.C, d2(qc, v, v))
    g21 = -jnp.vdot(
        w, d3(v, v, vb) + 2 * d2(qc, v, h11.astype(v.dtype)) + d2(qc, vb, h20)
    ) / jnp.vdot(w, s.C @ v)
    ok = (jnp.real(lam) > 0) & (jnp.real(g21) < 0) & (jnp.abs(jnp.imag(lam)) > 0)
    z2 = jnp.where(ok, -jnp.real(lam) / jnp.where(ok, 0.5 * jnp.real(g21), -1.0), jnp.nan)
    z = jnp.sqrt(z2)
    omega = jnp.imag(lam) + 0.5 * jnp.imag(g21) * z2
    omega = jnp.where(omega > 0, omega, jnp.imag(lam))
    X = jnp.zeros((prob.m, n)).at[0].set(qe + z2 * h11)
    X = X.at[1].set(2 * z * jnp.real(v)).at[H + 1].set(-2 * z * jnp.imag(v))
    if H >= 2:
        X = X.at[2].set(z2 * jnp.real(h20)).at[H + 2].set(-z2 * jnp.imag(h20))
    ref = jnp.zeros(n).at[i].set(1.0)
    small = (
        jnp.zeros((prob.m, n))
        .at[0]
        .set(qe)
        .at[1]
        .set(1e-3 * jnp.real(v))
        .at[H + 1]
        .set(-1e-3 * jnp.imag(v))
    )
    fallback = prob.join(small, jnp.abs(jnp.imag(lam)))
    return prob.join(X, omega), ref, lam, fallback
