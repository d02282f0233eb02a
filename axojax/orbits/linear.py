"""The bordered Newton system of the orbit equations, solved through the
block-tridiagonal structure.

The Jacobian of ``[R(X, omega); e_c . x]`` is ``K = [[J, u], [e_c^T, 0]]``: J the
harmonic-balance Jacobian (block-tridiagonal in the node layout), u = dR/domega, and the
phase condition fixes the unknown c (a one-hot ``e_c``). J itself is singular on the
orbit (the phase shift ``dq/dtheta`` is its null vector), so the border cannot be
eliminated through J. It is eliminated through ``J_a = J + a e_c e_c^T`` instead: a
change of one diagonal entry, so still block-tridiagonal, and regular whenever K is
(the null vector has a component along e_c and e_c is outside J's range). With
``z = J_a^{-1} u``::

    K [x; w] = [f; g]:   x = J_a^{-1}(f + a g e_c) - w z,   w = (e_c . J_a^{-1}(f + a g e_c) - g) / (e_c . z)

and the transposed system likewise with ``J_a^T`` (the implicit-function-theorem
derivative in reverse mode). Exact: no approximation beyond the LU's round-off.

On a base that moves, J has r more null vectors (the rigid motions at harmonic 0) and
the system r more border unknowns and rows (the drift and the rigid offset's phase
conditions, :mod:`axojax.orbits.rigid`); such a model's harmonic balance is one dense
block already (its border couples every node), so :class:`RigidSolver` factors the whole
square system densely. :func:`orbit_factor` picks the solver.
"""

from __future__ import annotations

import jax.numpy as jnp
import jax.scipy.linalg as jsl

from ..linalg import BlockTridiagonal, lu_factor
from .fourier import Problem

DENSE_MAX = 2000
"""Up to this many unknowns a dense LU (LAPACK) is used: for small systems it is as fast
and compiles in a fraction of the time of the blocked factorisation."""


class DenseLU:
    """Dense LU with the interface of :class:`axojax.linalg.BlockLU`."""

    def __init__(self, M: BlockTridiagonal):
        self.lu = jsl.lu_factor(M.to_dense())

    def solve(self, r):
        return jsl.lu_solve(self.lu, r)

    def solve_transpose(self, r):
        return jsl.lu_solve(self.lu, r, trans=1)


def factor(M: BlockTridiagonal):
    """Blocked LU (:func:`axojax.linalg.lu_factor`) of M, or a dense one for small M (or
    a single block)."""
    return DenseLU(M) if M.shape[0] <= DENSE_MAX or M.diag.shape[0] == 1 else lu_factor(M)


class BorderedSolver:
    """Factorisation of K at one point; ``solve`` and ``solve_transpose`` act on flat
    vectors ``[X.ravel(), omega]`` (harmonic-major, filament-major)."""

    def __init__(self, prob: Problem, x, ref):
        X, omega = prob.split(x)
        self.prob = prob
        J = prob.jacobian_blocks(X, omega)
        e_flat = jnp.zeros((prob.m, prob.n)).at[prob.H + 1].set(ref).ravel()
        self.e = prob.to_nodes(e_flat)
        c = jnp.argmax(self.e)
        b = J.block_size
        k, j = c // b, c % b
        diag = jnp.abs(J.diag[k, j, j])
        self.a = jnp.where(diag > 0, diag, 1.0)
        Ja = type(J)(J.lower, J.diag.at[k, j, j].add(self.a), J.upper)
        self.lu = factor(Ja)
        self.u = prob.to_nodes(jnp.ravel((prob.D @ X) @ prob.s.C.T))
        self.z = self.lu.solve(self.u)
        self.y = self.lu.solve_transpose(self.e)

    def solve(self, r):
        p = self.prob
        f, g = p.to_nodes(r[:-1]), r[-1]
        z1 = self.lu.solve(f + self.a * g * self.e)
        w = (self.e @ z1 - g) / (self.e @ self.z)
        return jnp.concatenate([p.from_nodes(z1 - w * self.z), w[None]])

    def solve_transpose(self, r):
        p = self.prob
        f, g = p.to_nodes(r[:-1]), r[-1]
        z1 = self.lu.solve_transpose(f)
        beta = (g - self.u @ z1) / (self.u @ self.y)
        y = z1 + beta * self.y
        t = self.a * (self.e @ y) - beta
        return jnp.concatenate([p.from_nodes(y), t[None]])


class RigidSolver:
    """Dense LU of the whole Newton matrix ``[[J, C Z e_0, u], [Y^T e_0^T, 0, 0],
    [e_c^T, 0, 0]]`` (:meth:`~axojax.orbits.fourier.Problem.jacobian`) at one point, for
    a base with rigid motions; ``solve`` and ``solve_transpose`` act on flat vectors
    ``[X.ravel(), v, omega]``."""

    def __init__(self, prob: Problem, x, ref):
        self.lu = jsl.lu_factor(prob.jacobian(x, ref))

    def solve(self, r):
        return jsl.lu_solve(self.lu, r)

    def solve_transpose(self, r):
        return jsl.lu_solve(self.lu, r, trans=1)


def orbit_factor(prob: Problem, x, ref):
    """The Newton matrix's factorisation at x: :class:`BorderedSolver` (through the
    block-tridiagonal structure), or :class:`RigidSolver` on a base with rigid motions."""
    return RigidSolver(prob, x, ref) if prob.r else BorderedSolver(prob, x, ref)
