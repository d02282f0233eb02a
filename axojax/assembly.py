"""System assembly: C, A, b of ``C dq/dt + A q = b`` as pure functions of Params.

MODEL.md section 3::

    A = K_bend + K_link + K_theta + K_G - P_follow - P_gain
    C = C_fluid + C_link

Each term is a small truss matrix over (filament, direction) pairs, built from the
model's static arrays and the traced parameters, Kronecker-multiplied by a
filament-level matrix. No Python loop runs over elements or grid points: the function
is jit-able and vmap-able in ``params``.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .models.section import Model
from .params import Params


class System(eqx.Module):
    """Assembled system ``C dq/dt + A q = b``; n = ``model.n_dof``.

    Attributes:
        C: (n, n) symmetric positive-definite damping (drag + link damping).
        A: (n, n) non-symmetric stiffness-minus-load matrix.
        b: (n,) static load (the constant dynein moment; zero when moments cancel).
    """

    C: Float[Array, "n n"]
    A: Float[Array, "n n"]
    b: Float[Array, " n"]


def pair_forces(model: Model, params: Params) -> Float[Array, " P"]:
    """Force p_a on each active pair: p for group 0, p / imbalance for group 1."""
    p = jnp.asarray(params.p, dtype=float)
    scale = jnp.where(jnp.asarray(model.pair_group) == 0, 1.0, 1.0 / jnp.asarray(params.imbalance, dtype=float))
    return p * scale


def link_stiffness(model: Model, params: Params) -> Float[Array, " E"]:
    """k_e of each link: k_s for spokes, k_l (times inactive_factor if not active) otherwise."""
    ring = jnp.where(model.link_is_active, 1.0, params.inactive_factor) * params.kl
    return jnp.where(model.link_is_spoke, params.ks, ring)


def bending_rigidity(model: Model, params: Params) -> Float[Array, " n_fd"]:
    """EI_{f,a}: filament rigidity, times ``out_of_plane`` in the z direction."""
    per_dir = jnp.array([1.0, 0.0])[: model.n_dirs] + jnp.array([0.0, 1.0])[: model.n_dirs] * params.out_of_plane
    return (jnp.asarray(model.section.ei)[:, None] * per_dir[None, :]).ravel()


def _truss(rows: Float[Array, "E n_fd"], weights: Float[Array, " E"]) -> Float[Array, "n_fd n_fd"]:
    """sum_e w_e B_e B_e^T."""
    return jnp.einsum("e,ei,ej->ij", weights, rows, rows)


def assemble(model: Model, params: Params) -> System:
    """Assemble C, A, b for ``model`` at ``params`` (MODEL.md section 3).

    Args:
        model: static structure (mesh, topology), e.g. ``ax.models.seven()``.
        params: dimensionless parameters; may be traced.

    Returns:
        :class:`System` with (n, n) matrices, n = ``model.n_dof``.
    """
    m = model.matrices
    M0, K0, D0, G0, F0, Mk = (jnp.asarray(a) for a in (m.M0, m.K0, m.D0, m.G0, m.F0, m.Mk))
    nfd = model.n_fd
    drag = jnp.repeat(jnp.asarray(model.section.drag, dtype=float), model.n_dirs)
    ei = bending_rigidity(model, params)
    p = jnp.asarray(params.p, dtype=float)

    C = jnp.kron(jnp.diag(drag), M0)
    A = jnp.kron(jnp.diag(ei), K0)
    b = jnp.zeros(model.n_dof)
    eye = jnp.eye(nfd)

    if model.link_B.shape[0]:
        B = jnp.asarray(model.link_B)
        C = C + jnp.kron(_truss(B, jnp.full(B.shape[0], 1.0) * params.cl), M0)
        A = A + jnp.kron(_truss(B, link_stiffness(model, params)), Mk)
        A = A + params.ktheta * jnp.kron(jnp.asarray(model.theta_laplacian), D0)

    load = model.section.load
    if load == "distributed":
        # Unbalanced distributed follower load on every filament: K0 - p G0 + p F0.
        A = A + p * (jnp.kron(eye, F0) - jnp.kron(eye, G0))
    elif load == "tip":
        # Beck's column: constant compression P and tip transverse force -P u'(1).
        A = A + p * (jnp.kron(eye, jnp.asarray(m.tip)) - jnp.kron(eye, D0))
    elif model.pair_B.shape[0]:
        pa = pair_forces(model, params)
        nu = jnp.einsum("a,ai->i", pa, jnp.asarray(model.pair_sign))
        follow = jnp.einsum("a,aij->ij", pa, jnp.asarray(model.pair_follow))
        gain = params.gamma * jnp.einsum("a,ai,aj->ij", pa, jnp.asarray(model.pair_w), jnp.asarray(model.pair_B))
        A = A + jnp.kron(jnp.diag(nu), G0) - jnp.kron(follow, F0) - jnp.kron(gain, F0.T)
        moment = params.a0 * jnp.einsum("a,ai->i", pa, jnp.asarray(model.pair_w))
        b = jnp.kron(moment, jnp.asarray(m.f1))
    return System(C=C, A=A, b=b)
