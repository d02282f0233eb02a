"""Saturating motors (issue 47 item 2; docs/model.md section 8): the regulated force
through ``f_sat tanh(f / f_sat)``, with motor kinetics.

With motor kinetics (:mod:`axojax.dynamics.motors`) each active pair a carries the force
per length ``f_a = c_inf Delta_a[q] + d_inf kappa_a[q] + c_1 Delta_a[y] + d_1 kappa_a[y]``
(dimensionless, EI / L^3 per unit force per length, the scale of ``p``), whose virtual
work ``int f_a delta Delta_a dx`` is the regulated part of A' X. A saturating motor
delivers ``f_sat tanh(f_a / f_sat)`` instead: the same force for |f_a| << f_sat, bounded by
f_sat, the nonlinearity that sets the amplitude of a regulated beat. The integrator takes
the difference as a nonlinear force on q (zero on y)::

    f_sat(X) = sum_a int (f_sat tanh(f_a / f_sat) - f_a) delta Delta_a dx,

with its exact tangent ``-sum_a int tanh^2(f_a / f_sat) delta Delta_a (x) df_a/dX dx``.

Delta_a and kappa_a are linear in the state, on every base: Delta_a(x) = a0 n_a .
(u_bar'(x) - u_bar'(0)) + Delta_b,a and kappa_a(x) = n_a . u_bar''(x) (docs/model.md
section 8, bases). :func:`pair_rows` tabulates them at the Gauss points of
:data:`~axojax.dynamics.nonlinear.POINTS_PER_ELEMENT` per element (exact for the linear
terms, whose integrands are polynomials: sum_q w_q Delta^T Delta is dA/dchi' and
sum_q w_q Delta^T kappa is dA/dbeta', tests/regulation/test_motor_kinetics_time.py), node 0's dofs
and the basal slidings mapped to the shared border as :mod:`axojax.assembly.border` does.
The tangent is formed dense (2N, 2N) and read into the blocks of
:func:`~axojax.dynamics.motors.motor_order` (a Gauss point couples its element's nodes and
the border only).
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Inexact, Int

from ..assembly.border import base_vectors, shared_node_map, sliding_unit, split_border
from ..assembly.motor_kinetics import motor_coefficients
from ..fem import make_mesh
from ..linalg import BlockTridiagonal, Bordered
from ..models.section import Model
from ..params import MAX_MAGNITUDE, Params
from .motors import blocks_of, motor_order
from .nonlinear import POINTS_PER_ELEMENT, CubicLinks, cubic_links


@functools.lru_cache(maxsize=32)
def pair_rows(model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The pairs' slidings and curvatures at the Gauss points as rows over the state q
    (N = ``model.n_unknowns``): (slope (P, Q, N), basal (P, N), curvature (P, Q, N),
    weights (Q,)), so that Delta_a(x_q) = (a0 slope[a, q] + basal[a]) . q and
    kappa_a(x_q) = curvature[a, q] . q; ``basal`` is Delta_b,a's unit row (zero without
    basal compliance)."""
    mesh = make_mesh(model.n_elements, POINTS_PER_ELEMENT)
    k, n = len(model.base.dofs), model.n_dof
    R = shared_node_map(model) if model.n_border else np.zeros((0, 0))
    d0 = base_vectors(model)["d0"] if k else 0.0  # u'(0): zero on a clamped base
    slope_rows = model.interpolation(mesh.x, 1) - d0
    curvature_rows = model.interpolation(mesh.x, 2)
    w = np.asarray(model.pair_w, dtype=float)
    P, Q = w.shape[0], mesh.x.shape[0]

    def rows(filament_rows: np.ndarray) -> np.ndarray:
        out = np.zeros((P, Q, model.n_unknowns))
        for a in range(P):
            for q in range(Q):
                node, border = split_border(model, w[a], filament_rows[q])
                out[a, q, :n] = node
                if model.n_border:
                    out[a, q, n:] = border @ R
        return out

    basal = np.zeros((P, model.n_unknowns))
    if model.base.compliance:
        for a in range(P):
            basal[a, n:] = sliding_unit(model, a) @ R
    return rows(slope_rows), basal, rows(curvature_rows), np.asarray(mesh.weights, dtype=float)


class MotorSaturation(eqx.Module):
    """The saturating motors' nonlinear force on X = (q, y) (module docstring), as data
    for the integrator (:class:`~axojax.dynamics.chord.MassSystem`).

    Attributes:
        sliding: (P, Q, N) rows of Delta_a at the Gauss points.
        curvature: (P, Q, N) rows of kappa_a.
        weights: (Q,) quadrature weights.
        coefficients: (4,) c_inf, d_inf, c_1, d_1 (:func:`~axojax.assembly.motor_kinetics.
            motor_coefficients`).
        f_sat: the saturation force per length (dimensionless, EI / L^3), > 0.
        perm: (2N,) :func:`~axojax.dynamics.motors.motor_order`.
        n_blocks, block_size, n_border: the blocks of the tangent (N_e, 4 F d, 2 m).
    """

    sliding: Float[Array, "P Q N"]
    curvature: Float[Array, "P Q N"]
    weights: Float[Array, " Q"]
    coefficients: Float[Array, " 4"]
    f_sat: Float[Array, ""]
    perm: Int[Array, " M"]
    n_blocks: int = eqx.field(static=True)
    block_size: int = eqx.field(static=True)
    n_border: int = eqx.field(static=True)

    def _response(self, X: Inexact[Array, " M"]) -> tuple[Array, Array]:
        """(f (P, Q), df/dX rows (P, Q, 2N)): each pair's regulated force at the Gauss
        points and its rows over X."""
        c_inf, d_inf, c_1, d_1 = self.coefficients
        on_q = c_inf * self.sliding + d_inf * self.curvature
        on_y = c_1 * self.sliding + d_1 * self.curvature
        rows = jnp.concatenate([on_q, on_y], axis=-1)
        return rows @ X, rows

    def force(self, X: Inexact[Array, " M"]) -> Inexact[Array, " M"]:
        """(2N,) ``sum_a int (f_sat tanh(f_a / f_sat) - f_a) delta Delta_a``, zero on y."""
        f, _ = self._response(X)
        g = self.f_sat * jnp.tanh(f / self.f_sat) - f
        on_q = jnp.einsum("q,pq,pqn->n", self.weights, g, self.sliding)
        return jnp.concatenate([on_q, jnp.zeros_like(on_q)])

    def tangent(self, X: Inexact[Array, " M"]) -> Inexact[Array, "M M"]:
        """(2N, 2N) d force / dX (dense): ``-sum_a int tanh^2(f_a/f_sat) delta Delta_a
        (x) df_a/dX``, zero rows on y."""
        f, rows = self._response(X)
        slope = -(jnp.tanh(f / self.f_sat) ** 2)
        on_q = jnp.einsum("q,pq,pqn,pqm->nm", self.weights, slope, self.sliding, rows)
        return jnp.concatenate([on_q, jnp.zeros_like(on_q)], axis=0)

    def tangent_blocks(self, X: Inexact[Array, " M"]) -> BlockTridiagonal | Bordered:
        """:meth:`tangent` in the blocks of :func:`~axojax.dynamics.motors.motor_order`."""
        return blocks_of(self.tangent(X), self.perm, self.n_blocks, self.block_size, self.n_border)


def check_saturation(f_sat: ArrayLike) -> float:
    """``f_sat`` as a float; one-line ``ValueError`` naming it unless it is one number in
    [1 / MAX_MAGNITUDE, MAX_MAGNITUDE] (dimensionless force per length, > 0)."""
    value = np.asarray(f_sat, dtype=float)
    if value.shape != () or not (
        np.isfinite(value) and 1 / MAX_MAGNITUDE <= value <= MAX_MAGNITUDE
    ):
        raise ValueError(
            f"motor saturation f_sat must be one number in [{1 / MAX_MAGNITUDE:g}, {MAX_MAGNITUDE:g}] "
            f"(dimensionless force per length, EI/L^3), got {f_sat!r}"
        )
    return float(value)


def motor_saturation(
    model: Model, params: Params, tau_m: ArrayLike, f_sat: ArrayLike
) -> MotorSaturation:
    """:class:`MotorSaturation` of ``model`` at ``params`` with motor time ``tau_m`` (tau)
    and saturation ``f_sat`` (EI / L^3; both may be traced)."""
    slope, basal, curvature, weights = pair_rows(model)
    a0 = jnp.asarray(params.a0, dtype=float)
    sliding = a0 * jnp.asarray(slope) + jnp.asarray(basal)[:, None, :]
    c_inf, c_1 = motor_coefficients(params.chi_re, params.chi_im, params.omega0, tau_m)
    d_inf, d_1 = motor_coefficients(params.beta_re, params.beta_im, params.omega0, tau_m)
    return MotorSaturation(
        sliding=sliding,
        curvature=jnp.asarray(curvature),
        weights=jnp.asarray(weights),
        coefficients=jnp.stack([c_inf, d_inf, c_1, d_1]),
        f_sat=jnp.asarray(f_sat, dtype=float),
        perm=jnp.asarray(motor_order(model)),
        n_blocks=model.n_elements,
        block_size=4 * model.n_fd,
        n_border=2 * model.n_border,
    )


def motor_forces(
    model: Model, params: Params, kappa: ArrayLike, tau_m: ArrayLike, f_sat: ArrayLike | None
) -> tuple[CubicLinks, MotorSaturation | None]:
    """The nonlinear forces on the augmented state X = (q, y) of motor kinetics: the cubic
    links (stiffening ``kappa``, 1/L^2) on q only, and the saturating motors where
    ``f_sat`` is given (EI / L^3; None: linear motors). What the time integration
    (:func:`axojax.dynamics.integrate.mass_system`) and the periodic orbit
    (:mod:`axojax.orbits.fourier`) both add to ``A' X``; all values may be traced."""
    links = cubic_links(model, params, kappa, n_extra=model.n_unknowns)
    saturation = None if f_sat is None else motor_saturation(model, params, tau_m, f_sat)
    return links, saturation


def nonlinear_force(
    links: CubicLinks, saturation: MotorSaturation | None, X: Inexact[Array, " M"]
) -> Inexact[Array, " M"]:
    """f_nl(X) (M,): the links' cubic force plus the saturating motors' where there are
    (dimensionless, EI / L^3 per unit length, as ``A X``)."""
    f = links.force(X)
    return f if saturation is None else f + saturation.force(X)


def nonlinear_tangent(
    links: CubicLinks, saturation: MotorSaturation | None, X: Inexact[Array, " M"]
) -> Inexact[Array, "M M"]:
    """d f_nl / dX (M, M), dense and exact: :meth:`CubicLinks.tangent` plus
    :meth:`MotorSaturation.tangent`."""
    K = links.tangent(X)
    return K if saturation is None else K + saturation.tangent(X)
