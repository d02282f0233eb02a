"""Cubic stiffening of the inter-filament links: the nonlinear force f_nl(q).

Every link e (spoke or inter-doublet link) of stiffness k_e carries the force per unit
length ``k_e (delta_a + kappa delta_a^3)``, with ``delta_a_e(x) = B_e . U(x)`` the change
of spacing (MODEL.md section 3, in units of L; ``kappa`` in 1/L^2). The linear part is
already in A (``K_link``). The cubic part, by virtual work::

    f_nl(q) = kappa sum_e k_e int k(x) delta_a_e(x)^3 (B_e (x) phi(x)) dx

integrated with 7 Gauss points per element (exact: the integrand is a polynomial of
degree 12 on each element). One dense contraction, no loop over links or elements.
"""

from __future__ import annotations

import functools

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..assembly import link_stiffness
from ..fem import make_mesh
from ..fem.filament import _evaluate
from ..models.section import Model
from ..params import Params

POINTS_PER_ELEMENT = 7


@functools.lru_cache(maxsize=32)
def _rule(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """(phi (Q, 2 N_e), weight * k-profile (Q,)) on the cubic-exact quadrature."""
    mesh = make_mesh(model.n_elements, POINTS_PER_ELEMENT)
    return mesh.phi, mesh.weights * _evaluate(model.profiles.k, mesh.x, "k")


def cubic_link_force(model: Model, params: Params, kappa: Float[Array, ""], q: Float[Array, " n"]) -> Float[Array, " n"]:
    """f_nl(q), shape (n,), dimensionless force (EI/L^2 per unit L); zero without links."""
    if model.link_B.shape[0] == 0:
        return jnp.zeros_like(q)
    phi, wk = (jnp.asarray(a) for a in _rule(model))
    B = jnp.asarray(model.link_B)  # (E, F d)
    U = jnp.reshape(q, (model.n_fd, model.mesh.n_dof)) @ phi.T  # (F d, Q)
    da = B @ U  # (E, Q) change of spacing
    g = (kappa * link_stiffness(model, params))[:, None] * wk[None, :] * da**3
    return jnp.ravel(B.T @ g @ phi)
