"""Cubic stiffening of the inter-filament links: the nonlinear force f_nl(q).

Every link e (spoke or inter-doublet link) of stiffness k_e carries the force per unit
length ``k_e (delta_a + kappa delta_a^3)``, with ``delta_a_e(x) = B_e . U(x)`` the change
of spacing (docs/model.md section 3, in units of L; ``kappa`` in 1/L^2). The linear part is
already in A (``K_link``). The cubic part, by virtual work::

    f_nl(q) = kappa sum_e k_e int k(x) delta_a_e(x)^3 (B_e (x) phi(x)) dx

integrated with 7 Gauss points per element (exact: the integrand is a polynomial of
degree 12 on each element). One dense contraction, no loop over links or elements. Its
exact Jacobian (the tangent stiffness, for the implicit solver) is a sum of rank-one
terms at the quadrature points: :meth:`CubicLinks.tangent`.
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Inexact, Real

from ..assembly import link_stiffness
from ..fem import make_mesh
from ..fem.filament import evaluate_profile
from ..linalg import BlockTridiagonal
from ..models.section import Model
from ..params import Params

POINTS_PER_ELEMENT = 7


@functools.lru_cache(maxsize=32)
def _rule(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """(phi (Q, 2 N_e), weight * k-profile (Q,)) on the cubic-exact quadrature."""
    mesh = make_mesh(model.n_elements, POINTS_PER_ELEMENT)
    return mesh.phi, mesh.weights * evaluate_profile(model.profiles.k, mesh.x, "k")


class CubicLinks(eqx.Module):
    """The cubic link force of one model at one parameter point, as data (a pytree: it
    can travel through diffrax as ``args``).

    Attributes:
        B: (E, F d) link rows ``B_e``.
        phi: (Q, 2 N_e) shape functions at the quadrature points.
        weight: (E, Q) ``kappa k_e w_q k(x_q)``.
        n_fd: number of (filament, direction) pairs.
        n_border: unknowns after the node unknowns (a base that is not clamped, basal
            sliding; :attr:`axojax.models.Model.n_border`). The links do not act on them:
            node 0's are shared by every filament (a rigid basal body), so they stretch
            no link, and basal sliding is no spacing. Their force rows are zero.
    """

    B: Float[Array, "E fd"]
    phi: Float[Array, "Q m"]
    weight: Float[Array, "E Q"]
    n_fd: int = eqx.field(static=True)
    n_border: int = eqx.field(static=True, default=0)

    def _nodes(self, q: Inexact[Array, " n"]) -> Inexact[Array, " n_nodes"]:
        return q[: q.shape[0] - self.n_border]

    def _stretch(self, q: Inexact[Array, " n"]) -> Inexact[Array, "E Q"]:
        return self.B @ (
            jnp.reshape(self._nodes(q), (self.n_fd, self.phi.shape[1])) @ self.phi.T
        )  # delta_a_e(x_q)

    def force(self, q: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
        """f_nl(q), shape (n,)."""
        f = jnp.ravel(self.B.T @ (self.weight * self._stretch(q) ** 3) @ self.phi)
        return jnp.concatenate([f, jnp.zeros(self.n_border, f.dtype)]) if self.n_border else f

    def tangent(self, q: Inexact[Array, " n"]) -> Inexact[Array, "n n"]:
        """d f_nl / dq at ``q``, shape (n, n): the exact tangent stiffness::

            sum_e sum_quad 3 kappa k_e w k(x) delta_a_e(x)^2 (B_e (x) phi)(B_e (x) phi)^T

        (symmetric positive semi-definite for kappa >= 0), built as one filament-level
        matrix per link, ``M_e = Phi^T diag(3 weight_e delta_a_e^2) Phi``, Kronecker-
        multiplied by ``B_e B_e^T``: O(E Q m^2 + E n^2) with m = 2 N_e, no
        Jacobian-vector products."""
        n = q.shape[0] - self.n_border
        Me = jnp.einsum(
            "qr,eq,qs->ers", self.phi, 3.0 * self.weight * self._stretch(q) ** 2, self.phi
        )
        K = jnp.einsum("ei,ej,ers->irjs", self.B, self.B, Me).reshape(n, n)
        return jnp.pad(K, ((0, self.n_border), (0, self.n_border))) if self.n_border else K

    def tangent_blocks(self, q: Inexact[Array, " n"]) -> BlockTridiagonal:
        """:meth:`tangent` as node blocks (node-major, the layout of
        :func:`axojax.assembly.assemble_blocks`): each link's filament-level matrix
        ``M_e`` is cut into its 2 x 2 node blocks and Kronecker-multiplied by
        ``B_e B_e^T`` block by block, never forming the n x n matrix. The node blocks
        only: the border's rows and columns are zero."""
        Me = jnp.einsum(
            "qr,eq,qs->ers", self.phi, 3.0 * self.weight * self._stretch(q) ** 2, self.phi
        )
        E, m = Me.shape[0], Me.shape[1]
        N = m // 2
        nodes = Me.reshape(E, N, 2, N, 2)
        k = np.arange(N)
        rows, cols = (
            np.concatenate([k[1:], k, k[:-1]]),
            np.concatenate([k[:-1], k, k[1:]]),
        )  # lower, diag, upper
        blocks = nodes[:, rows, :, cols, :]  # (3N-2, E, 2, 2)
        bs = 2 * self.n_fd
        out = jnp.einsum("ei,ej,keab->kiajb", self.B, self.B, blocks).reshape(-1, bs, bs)
        return BlockTridiagonal(out[: N - 1], out[N - 1 : 2 * N - 1], out[2 * N - 1 :])


def cubic_links(
    model: Model, params: Params, kappa: Real[ArrayLike, ""], n_extra: int = 0
) -> CubicLinks:
    """:class:`CubicLinks` of ``model`` at ``params`` (a model without links gets one
    zero-stiffness placeholder link, so that force and tangent are zero). ``n_extra``:
    unknowns of the state after the model's own (the motor copy y of motor kinetics,
    :mod:`axojax.dynamics.motors`), on which the links do not act, as on the border."""
    phi, wk = (jnp.asarray(a) for a in _rule(model))
    if model.link_B.shape[0] == 0:
        return CubicLinks(
            B=jnp.zeros((1, model.n_fd)),
            phi=phi,
            weight=jnp.zeros((1, wk.shape[0])),
            n_fd=model.n_fd,
            n_border=model.n_border + n_extra,
        )
    k = jnp.asarray(kappa, dtype=float) * link_stiffness(model, params)
    return CubicLinks(
        B=jnp.asarray(model.link_B, dtype=float),
        phi=phi,
        weight=k[:, None] * wk[None, :],
        n_fd=model.n_fd,
        n_border=model.n_border + n_extra,
    )


def cubic_link_force(
    model: Model, params: Params, kappa: Real[ArrayLike, ""], q: Inexact[Array, " n"]
) -> Inexact[Array, " n"]:
    """f_nl(q), shape (n,), dimensionless force (EI/L^2 per unit L); zero without links."""
    return cubic_links(model, params, kappa).force(q)


def cubic_link_tangent(
    model: Model, params: Params, kappa: Real[ArrayLike, ""], q: Inexact[Array, " n"]
) -> Inexact[Array, "n n"]:
    """d f_nl / dq at ``q``, shape (n, n) (:meth:`CubicLinks.tangent`)."""
    return cubic_links(model, params, kappa).tangent(q)
