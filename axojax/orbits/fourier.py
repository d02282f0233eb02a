"""Harmonic balance (Fourier-Galerkin) discretisation of a periodic orbit of
``C dq/dt = -A q - f_nl(q) + b``.

With theta = omega t the phase, the orbit is a trigonometric polynomial of degree H::

    q(theta) = c_0 + sum_k a_k cos(k theta) + b_k sin(k theta),   X = [c_0, a_1..a_H, b_1..b_H]  (2H+1, n)

and the residual is the Galerkin projection of the equation onto the same harmonics::

    R(X, omega) = omega (D X) C^T + X A^T + P f_nl(E X) - e_0 b^T          (2H+1, n)

``D`` is d/dtheta on the coefficients, ``E`` (N_t, 2H+1) evaluates the series at
``N_t`` equally spaced phases and ``P`` (2H+1, N_t) projects samples back onto the
harmonics (alternating frequency-time, AFT). f_nl is cubic in q, so f_nl(q(theta)) is a
trigonometric polynomial of degree 3H and ``N_t >= 4H + 1`` samples project it exactly
(no aliasing): the discrete problem is then the exact Galerkin problem, and it keeps
the continuous problem's phase-shift symmetry exactly (the Floquet exponent 0). With
motor kinetics the unknowns are the doubled state X = (q, y) and saturating motors add a
tanh to f_nl, which no finite sampling projects exactly: :mod:`axojax.orbits.motors`
samples it more finely (its aliasing decays geometrically).

Stiffness costs nothing here: the fast link-relaxation modes enter only through the
well-conditioned blocks ``A + i k omega C``.

Structure: ordered node-major (:func:`axojax.assembly.node_major`) with the harmonics
inside each node, the Jacobian is block-tridiagonal (A, C and the cubic force's
Jacobian couple neighbouring nodes only) with N_e blocks of size (2H+1) 2 F d, and is
factored by :func:`axojax.linalg.lu_factor` in O(N_e ((2H+1) 2 F d)^3) instead of
O((N_e (2H+1) 2 F d)^3) (:mod:`axojax.orbits.linear`). A model with a border (basal
compliance, a base that moves) is laid out as one dense block instead: its border
couples every node to the base's unknowns (exact, O((N_e (2H+1) 2 F d)^3)).
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..assembly import System, assemble_blocks, node_major
from ..assembly.motor_kinetics import MotorSystem
from ..dynamics.motors import motor_order
from ..dynamics.nonlinear import cubic_links
from ..dynamics.saturation import MotorSaturation, nonlinear_force, nonlinear_tangent
from ..linalg import BlockTridiagonal
from ..models.section import Model
from ..params import Params
from .rigid import rigid_of


@functools.lru_cache(maxsize=32)
def basis(harmonics: int, samples: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(E (N_t, 2H+1), P (2H+1, N_t), D (2H+1, 2H+1)) for ``harmonics`` H and ``samples`` N_t."""
    H, N = harmonics, samples
    theta = 2 * np.pi * np.arange(N) / N
    k = np.arange(1, H + 1)
    E = np.concatenate(
        [np.ones((N, 1)), np.cos(np.outer(theta, k)), np.sin(np.outer(theta, k))], axis=1
    )
    P = (np.concatenate([[1.0], 2.0 * np.ones(2 * H)]) / N)[:, None] * E.T
    D = np.zeros((2 * H + 1, 2 * H + 1))
    D[1 : H + 1, H + 1 :] = np.diag(k)  # (D X)[cos k] = k b_k
    D[H + 1 :, 1 : H + 1] = -np.diag(k)  # (D X)[sin k] = -k a_k
    return E, P, D


def evaluate(X: Float[Array, "m n"], theta: Float[Array, " T"]) -> Float[Array, "T n"]:
    """q(theta) of the coefficients X (2H+1, n) at phases theta (any shape (T,))."""
    H = (X.shape[0] - 1) // 2
    k = jnp.arange(1, H + 1)
    Et = jnp.concatenate(
        [jnp.ones(theta.shape + (1,)), jnp.cos(theta[:, None] * k), jnp.sin(theta[:, None] * k)],
        axis=1,
    )
    return Et @ X


def pad(X: Float[Array, "m n"], harmonics: int) -> Float[Array, "m2 n"]:
    """Coefficients of degree H as those of degree ``harmonics`` (>= H; zeros above H)."""
    H = (X.shape[0] - 1) // 2
    z = jnp.zeros((harmonics - H, X.shape[1]), X.dtype)
    return jnp.concatenate([X[:1], X[1 : H + 1], z, X[H + 1 :], z], axis=0)


class Problem:
    """The harmonic-balance equations at fixed (model, system, kappa): residual and
    exact Jacobian in the flat unknown ``x = [X.ravel(), v, omega]``, with the phase
    condition ``ref . b_1 = 0`` as the last equation.

    On a base that moves (r = ``rigid.r`` rigid motions, :mod:`axojax.orbits.rigid`) the
    mean's equation gains the drift's drag ``C Z v`` (v: r drift velocities, L or rad per
    tau) and r equations fix the rigid offset, ``Y^T c_0 = 0``, before the phase
    condition; on a held base v is empty and ``x = [X.ravel(), omega]``.

    ``system`` is the model's :class:`~axojax.assembly.System` (n = N unknowns q), or with
    motor kinetics the augmented :class:`~axojax.assembly.motor_kinetics.MotorSystem`
    (n = 2 N unknowns X = (q, y), :mod:`axojax.dynamics.motors`): the orbit of the
    equations :func:`axojax.simulate` integrates, with the cubic links on q and
    ``saturation`` (saturating motors, :mod:`axojax.dynamics.saturation`; None: none)
    from the same pieces as the integrator (:func:`~axojax.dynamics.saturation.motor_forces`).
    Without a border the augmented unknowns are laid out node by node as the integrator's
    (:func:`~axojax.dynamics.motors.motor_order`: each node's q then its y)."""

    def __init__(
        self,
        model: Model,
        params: Params,
        system: System | MotorSystem,
        kappa,
        harmonics: int,
        samples: int,
        saturation: MotorSaturation | None = None,
    ):
        self.model, self.params, self.s, self.kappa = model, params, system, kappa
        self.H, self.N = harmonics, samples
        E, P, D = basis(harmonics, samples)
        self.E, self.P, self.D = jnp.asarray(E), jnp.asarray(P), jnp.asarray(D)
        self.n = system.A.shape[0]
        self.motors = isinstance(system, MotorSystem)
        self.links = cubic_links(model, params, kappa, n_extra=self.n - model.n_unknowns)
        self.saturation = saturation
        self.m = 2 * harmonics + 1
        self.bordered = bool(model.n_border)
        if self.bordered:  # one dense block, harmonic-major (module docstring)
            self.n_blocks, self.block = 1, self.n
            self.perm = np.arange(self.n)
        elif self.motors:
            self.n_blocks, self.block = model.n_elements, 4 * model.n_fd
            self.perm = motor_order(model)
        else:
            self.n_blocks, self.block = model.n_elements, 2 * model.n_fd
            self.perm = node_major(model)
        self.inverse_perm = np.argsort(self.perm)
        self.rigid = rigid_of(model, system.C)
        self.r = self.rigid.r
        if self.r and not self.bordered:
            raise ValueError("a base with rigid motions has a border")  # (node 0's dofs)

    def f_nl(self, q):
        """f_nl(q) (n,): the cubic links' force (and the saturating motors')."""
        return nonlinear_force(self.links, self.saturation, q)

    def f_nl_tangent(self, q):
        """d f_nl / dq, exact (the rank-one sums, not autodiff)."""
        return nonlinear_tangent(self.links, self.saturation, q)

    def split(self, x):
        """(X (2H+1, n), omega) of a flat unknown x."""
        return jnp.reshape(x[: self.m * self.n], (self.m, self.n)), x[-1]

    def drift(self, x):
        """(r,) the drift velocities v of a flat unknown x (empty on a held base)."""
        return x[self.m * self.n : self.m * self.n + self.r]

    def join(self, X, omega, v=None):
        """The flat unknown ``[X.ravel(), v, omega]`` (v: zeros by default)."""
        parts = [jnp.ravel(X), jnp.reshape(omega, (1,)).astype(X.dtype)]
        if self.r:
            parts.insert(1, jnp.zeros(self.r, X.dtype) if v is None else v)
        return jnp.concatenate(parts)

    def harmonic_residual(self, X, omega):
        """R(X, omega), shape (2H+1, n)."""
        s = self.s
        Fq = jax.vmap(self.f_nl)(self.E @ X)
        R = omega * (self.D @ X) @ s.C.T + X @ s.A.T + self.P @ Fq
        return R.at[0].add(-s.b)

    def residual(self, x, ref):
        X, omega = self.split(x)
        R = self.harmonic_residual(X, omega)
        phase = (ref @ X[self.H + 1])[None]
        if not self.r:
            return jnp.concatenate([jnp.ravel(R), phase])
        R = R.at[0].add(self.rigid.drag @ self.drift(x))
        gauge = self.rigid.coords @ X[0]  # (r,): the mean's rigid coordinates
        return jnp.concatenate([jnp.ravel(R), gauge, phase])

    def harmonic_jacobian(self, X, omega):
        """d R / d X, shape (m n, m n): omega D (x) C + I (x) A + Galerkin of d f_nl."""
        s, m, n = self.s, self.m, self.n
        Df = jax.vmap(self.f_nl_tangent)(self.E @ X)  # (N_t, n, n)
        nl = jnp.einsum("mj,jl,jrs->mrls", self.P, self.E, Df).reshape(m * n, m * n)
        return omega * jnp.kron(self.D, s.C) + jnp.kron(jnp.eye(m), s.A) + nl

    def jacobian(self, x, ref):
        """d residual / d x, shape (m n + r + 1, m n + r + 1)."""
        X, omega = self.split(x)
        m, n, H, r = self.m, self.n, self.H, self.r
        J = self.harmonic_jacobian(X, omega)
        d_omega = jnp.ravel((self.D @ X) @ self.s.C.T)
        d_drift = jnp.zeros((m, n, r)).at[0].set(self.rigid.drag).reshape(m * n, r)
        gauge = jnp.zeros((r, m, n)).at[:, 0].set(self.rigid.coords).reshape(r, m * n)
        phase = jnp.zeros((m, n)).at[H + 1].set(ref).ravel()
        top = jnp.concatenate([J, d_drift, d_omega[:, None]], axis=1)
        rows = jnp.concatenate([gauge, phase[None]], axis=0)
        bottom = jnp.concatenate([rows, jnp.zeros((r + 1, r + 1))], axis=1)
        return jnp.concatenate([top, bottom], axis=0)

    # -- node-major layout: (node, harmonic, local dof) ---------------------------------
    def to_nodes(self, v):
        """Flat (m n,) harmonic-major, filament-major vector -> node layout (N_e m b,)."""
        V = jnp.reshape(v, (self.m, self.n))[:, self.perm]
        return jnp.reshape(
            jnp.swapaxes(jnp.reshape(V, (self.m, self.n_blocks, self.block)), 0, 1), (-1,)
        )

    def from_nodes(self, w):
        """Inverse of :meth:`to_nodes`."""
        V = jnp.reshape(
            jnp.swapaxes(jnp.reshape(w, (self.n_blocks, self.m, self.block)), 0, 1),
            (self.m, self.n),
        )
        return jnp.ravel(V[:, self.inverse_perm])

    def _node_blocks(self, M):
        """(lower, diag, upper) node blocks of a dense filament-major (..., n, n) matrix."""
        N, b = self.n_blocks, self.block
        Mn = M[..., self.perm, :][..., :, self.perm]
        B = jnp.reshape(Mn, M.shape[:-2] + (N, b, N, b))
        k = np.arange(N)
        return B[..., k[1:], :, k[:-1], :], B[..., k, :, k, :], B[..., k[:-1], :, k[1:], :]

    def jacobian_blocks(self, X, omega) -> BlockTridiagonal:
        """d R / d X in the node layout: block-tridiagonal, blocks (m b, m b) (one dense
        block with a border)."""
        m, b = self.m, self.block
        if self.bordered:
            return _one_block(self.harmonic_jacobian(X, omega))
        C_blocks, A_blocks = self._pencil_blocks()
        Df = jax.vmap(self.f_nl_tangent)(self.E @ X)  # (N_t, n, n)
        W = jnp.einsum("mj,jl->jml", self.P, self.E)  # (N_t, m, m)
        Dm, I = jnp.asarray(self.D), jnp.eye(m)

        def combine(c, a, d):
            # block (node k, node k'): [(harm, dof), (harm, dof)]
            out = (
                omega * jnp.einsum("ml,kab->kmalb", Dm, c)
                + jnp.einsum("ml,kab->kmalb", I, a)
                + jnp.einsum("jml,kjab->kmalb", W, d)
            )
            return jnp.reshape(out, (-1, m * b, m * b))

        dl, dd, du = self._node_blocks(Df)  # each (K, N_t, b, b)
        return BlockTridiagonal(
            *(combine(c, a, d) for c, a, d in zip(C_blocks, A_blocks, (dl, dd, du)))
        )

    def _pencil_blocks(self):
        """((lower, diag, upper) of C, the same of A) in the node layout: the model's
        assembled blocks, or with motor kinetics those of the augmented matrices."""
        if self.motors:
            return self._node_blocks(self.s.C), self._node_blocks(self.s.A)
        sb = assemble_blocks(self.model, self.params)
        return (sb.C.lower, sb.C.diag, sb.C.upper), (sb.A.lower, sb.A.diag, sb.A.upper)

    def mass_blocks(self) -> BlockTridiagonal:
        """I_m (x) C in the node layout."""
        m, b = self.m, self.block
        if self.bordered:
            return _one_block(jnp.kron(jnp.eye(m), self.s.C))
        C_blocks, _ = self._pencil_blocks()
        widen = lambda c: jnp.reshape(
            jnp.einsum("ml,kab->kmalb", jnp.eye(m), c), (-1, m * b, m * b)
        )
        return BlockTridiagonal(*(widen(c) for c in C_blocks))


def _one_block(M: Float[Array, "k k"]) -> BlockTridiagonal:
    """A dense matrix as a block-tridiagonal one of a single block."""
    empty = jnp.zeros((0,) + M.shape, M.dtype)
    return BlockTridiagonal(empty, M[None], empty)
