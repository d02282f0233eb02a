"""The rigid-body motions of a periodic orbit on a base that moves (docs/model.md
section 8, "Bases that move"; issue 54 item 4).

A free or head base (and a pivot without a spring) leaves the axoneme r rigid motions Z
(:meth:`axojax.models.Model.rigid_modes`): ``A Z = 0``, and the internal forces have no
net force or torque, ``Z^T A = 0``, ``Z^T f_nl(q) = 0`` (the cubic links and the
saturating motors act between filaments). Projecting ``C dq/dt + A q + f_nl(q) = b`` on
Z gives ``Z^T C dq/dt = Z^T b``: the drag-weighted rigid coordinates move at the constant
rate ``(Z^T C Z)^{-1} Z^T b``. With no net load (``Z^T b = 0``, checked by
:func:`rigid_load`) there is no drift, and the beat is a periodic orbit whose rigid
offset (the mean state's component along Z) is arbitrary.

The harmonic balance fixes it with one phase condition per rigid motion and keeps the
Newton system square with one unknown more per rigid motion, a drift velocity v
(bordered system)::

    R_0(X, omega) + C Z v = 0,        Y^T c_0 = 0,      Y^T = (Z_l^T C Z)^{-1} Z_l^T C,

(R_0 the mean's equation, c_0 the mean state; ``Y^T Z = I``, so ``Y^T q`` are a state's
rigid coordinates). At a solution ``Z_l^T C Z v = Z_l^T b``, so v is the drift the load
would cause: it must come out ~0 (:func:`drift_ratio`), else the orbit is refused
(``RESULTS.rigid_drift``). Z_l spans the left null space of A: Z itself, and with motor
kinetics ``(Z; 0)`` for the doubled state's right null vectors ``(Z; Z)``
(:func:`axojax.dynamics.motors.rigid_motions`).

Each rigid motion is an exact null vector of the harmonic-balance Jacobian, so it has
a Floquet multiplier 1 (besides the time shift's): :func:`rigid_multipliers` computes
them from the Jacobian on span(Z) and the stability-deciding multipliers are computed
with them moved away (:func:`deflate`, Brauer's theorem as in
:mod:`axojax.eigen.deflation`).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from ..assembly import assemble
from ..eigen.deflation import scale_of
from ..models.section import Model
from ..params import Params

DRIFT_RTOL = 1e-8
"""Largest drift accepted: |v| (L or rad per tau) over omega times the orbit's largest
harmonic coefficient (the beat's own speed), :func:`drift_ratio`."""


class Rigid(eqx.Module):
    """The rigid motions of a problem's state (r = 0 on a held base: empty arrays).

    Attributes:
        right: (n, r) Z, right null vectors of A (with motor kinetics (Z; Z)).
        left: (n, r) Z_l, its left null vectors (Z; with motor kinetics (Z; 0)).
        coords: (r, n) Y^T = (Z_l^T C Z)^{-1} Z_l^T C: a state's rigid coordinates
            (Y^T Z = I).
        drag: (n, r) C Z: the drag of each rigid motion (the drift's column).
    """

    right: Float[Array, "n r"]
    left: Float[Array, "n r"]
    coords: Float[Array, "r n"]
    drag: Float[Array, "n r"]

    @property
    def r(self) -> int:
        return self.right.shape[1]


def rigid_vectors(model: Model, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(Z, Z_l) of a state of ``n`` unknowns: ``model.n_unknowns`` (q), or twice that with
    motor kinetics (X = (q, y): (Z; Z) and (Z; 0)). Both (n, r), r = 0 on a held base."""
    Z = np.asarray(model.rigid_modes(), dtype=float)
    if n == model.n_unknowns:
        return Z, Z
    if n != 2 * model.n_unknowns:
        raise ValueError(f"a state of {n} unknowns is not one of model {model.name!r}")
    return np.concatenate([Z, Z]), np.concatenate([Z, np.zeros_like(Z)])


def rigid_of(model: Model, C: Float[Array, "n n"]) -> Rigid:
    """The :class:`Rigid` of a system with damping ``C`` (n, n) (the model's, or the
    augmented one of motor kinetics)."""
    Z, Zl = (jnp.asarray(v, dtype=C.dtype) for v in rigid_vectors(model, C.shape[0]))
    if Z.shape[1] == 0:
        empty = jnp.zeros((0, C.shape[0]), C.dtype)
        return Rigid(Z, Zl, empty, Z)
    ZtC = Zl.T @ C
    return Rigid(Z, Zl, jnp.linalg.solve(ZtC @ Z, ZtC), C @ Z)


def rigid_load(model: Model, params: Params) -> Float[Array, " r"]:
    """Z^T b (r,): the net rigid-body force and torque of the static load b (the static
    dynein moment m0, the imbalance's couple) on a base that moves; dimensionless (EI/L^2
    per direction for a translation, EI/L for a rotation). docs/model.md section 8: it must
    be 0 (to rounding), else the beat drifts; empty on a held base."""
    Z = jnp.asarray(model.rigid_modes(), dtype=float)
    return Z.T @ assemble(model, params).b


def drift_ratio(v: Float[Array, " r"], X: Float[Array, "m n"], omega) -> Float[Array, ""]:
    """|v|_inf / (|omega| max|X[1:]|): the drift velocity over the beat's own speed (0 on
    a held base, r = 0)."""
    if v.shape[0] == 0:
        return jnp.zeros((), X.dtype)
    speed = jnp.abs(omega) * jnp.max(jnp.abs(X[1:]))
    return jnp.max(jnp.abs(v)) / jnp.maximum(speed, 1e-300)


def gauged_solve(M: Array, rhs: Array, rigid: Rigid) -> Array:
    """x with ``M x + C Z v = rhs`` and ``Y^T x = 0`` (M (n, n) singular along Z, e.g. a
    tangent stiffness on a base that moves; rhs (n,), real or complex): the bordered
    solve; ``M^{-1} rhs`` where r = 0."""
    r = rigid.r
    if r == 0:
        return jnp.linalg.solve(M, rhs)
    dt = jnp.result_type(M, rhs)
    K = jnp.block(
        [[M.astype(dt), rigid.drag.astype(dt)], [rigid.coords.astype(dt), jnp.zeros((r, r), dt)]]
    )
    return jnp.linalg.solve(K, jnp.concatenate([rhs.astype(dt), jnp.zeros(r, dt)]))[:-r]


def deflated(M: Array, rigid: Rigid, scale) -> Array:
    """``M + scale C Z Y^T`` (n, n): a pencil (M, C)'s rigid eigenvalues moved from 0 to
    -``scale``, every other kept (Brauer's theorem, :mod:`axojax.eigen.deflation`); M
    where r = 0."""
    if rigid.r == 0:
        return M
    return M + scale * rigid.drag @ rigid.coords


def deflation_scale(A: Array, C: Array):
    """The shift s of :func:`deflated` (as :mod:`axojax.eigen.deflation`'s: 10 max|A| /
    max|C|, no derivative)."""
    return scale_of(jnp.max(jnp.abs(A)), jnp.max(jnp.abs(C)))


def restore(w: Complex[Array, " n"], lam, rigid: Rigid, scale) -> Complex[Array, " n"]:
    """The eigenvector of (M, C) at ``lam`` from the deflated pencil's ``w``:
    ``w + (scale / lam) Z Y^T w`` (exact; not normalised)."""
    if rigid.r == 0:
        return w
    Z, Yt = (x.astype(w.dtype) for x in (rigid.right, rigid.coords))
    return w + (scale / lam) * (Z @ (Yt @ w))


def rigid_multipliers(J0: Array, rigid: Rigid, C: Array, omega) -> Complex[Array, " r"]:
    """(r,) the Floquet multipliers of the rigid motions: ``exp(mu T)``, mu the eigenvalues
    of ``-(Z_l^T C Z)^{-1} Z_l^T J0 Z``, ``J0 Z`` the Jacobian of the mean's equation on
    the rigid motions (its ``J (e_0 (x) Z)`` at harmonic 0; exactly 0 in exact arithmetic,
    so the multipliers are 1 to rounding). ``C``: the damping (n, n)."""
    r = rigid.r
    if r == 0:
        return jnp.zeros((0,), complex)
    Z, Zl = rigid.right, rigid.left
    Lam = -jnp.linalg.solve(Zl.T @ C @ Z, Zl.T @ J0 @ Z)
    mu = jnp.linalg.eigvals(Lam)
    return jnp.exp(mu * 2 * jnp.pi / omega)
