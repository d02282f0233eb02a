"""Mode shapes and mode metrics (MODEL.md section 5).

An eigenvector ``v`` (n,) is reshaped to ``(F, d, 2 N_e)`` and interpolated with the
Hermite shape functions. The centreline displacement is the mean over filaments. In 3D
the beat direction is the principal axis of ``R = Re int u u^H dx`` (2 x 2) and the
out-of-plane ratio is ``sqrt(smaller / larger eigenvalue of R)``. With ``u(x)`` the
complex in-plane displacement, the mean phase gradient is::

    k = int Im(conj(u) u') dx / int |u|^2 dx

wavelength ``2 pi / |k|`` (units of L); propagation is anterograde (base to tip) when
``k * sign(Im lambda) < 0``. Integrals use Gauss-Legendre points on the mesh (at least
200 points along x, exact for these piecewise polynomials). Every metric is invariant
to the complex scale of v, so its derivative through
:func:`axojax.eigen.dominant.dominant_eigenpair` is exact.
"""

from __future__ import annotations

import functools
import math

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from ..fem import interpolation_matrix, make_mesh
from ..models.section import Model

MIN_POINTS = 200


@functools.lru_cache(maxsize=64)
def _quadrature(n_elements: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    per = max(4, math.ceil(MIN_POINTS / n_elements))
    mesh = make_mesh(n_elements, per)
    return mesh.x, mesh.weights, mesh.phi, mesh.dphi


def mode_shapes(
    model: Model, v: Complex[Array, " n"], x: Float[Array, " m"] | None = None, derivative: int = 0
) -> Complex[Array, "F d m"]:
    """Displacement (or its x-derivative) of every filament and direction at points x.

    Args:
        model: the model that ``v`` belongs to.
        v: eigenvector (n,) complex (or a real state vector).
        x: points in [0, 1]; default 201 equally spaced points.
        derivative: 0 for u, 1 for u', 2 for u''.

    Returns:
        (F, d, m) array, in units of L (u) or L^0 (u').
    """
    if x is None:
        x = np.linspace(0.0, 1.0, 201)
    phi = jnp.asarray(interpolation_matrix(model.n_elements, np.asarray(x), derivative))
    q = jnp.reshape(v, (model.n_filaments, model.n_dirs, model.mesh.n_dof))
    return jnp.einsum("mr,fdr->fdm", phi, q)


def _safe_sqrt(x):
    pos = x > 0
    return jnp.where(pos, jnp.sqrt(jnp.where(pos, x, 1.0)), 0.0)


def beat_plane(
    model: Model, v: Complex[Array, " n"]
) -> tuple[Complex[Array, " m"], Complex[Array, " m"], Array, Array]:
    """Complex in-plane centreline displacement u and u' at the quadrature points, the
    beat-direction angle (radians from y towards z) and the out-of-plane ratio."""
    x, w, phi, dphi = _quadrature(model.n_elements)
    q = jnp.reshape(v, (model.n_filaments, model.n_dirs, model.mesh.n_dof)).mean(axis=0)  # (d, r)
    u = q @ jnp.asarray(phi).T  # (d, m)
    du = q @ jnp.asarray(dphi).T
    if model.n_dirs == 1:
        return u[0], du[0], jnp.zeros(()), jnp.zeros(())
    R = jnp.real(jnp.einsum("am,bm,m->ab", u, jnp.conj(u), jnp.asarray(w)))
    a, b, c = R[0, 0], R[0, 1], R[1, 1]
    half = (a - c) / 2
    rad = _safe_sqrt(half**2 + b**2)
    big, small = (a + c) / 2 + rad, (a + c) / 2 - rad
    # Principal axis; (a - c, 2b) = 0 only for exactly circular motion, where any axis will do.
    degenerate = rad <= 1e-300
    angle = 0.5 * jnp.arctan2(jnp.where(degenerate, 0.0, 2 * b), jnp.where(degenerate, 1.0, a - c))
    e = jnp.stack([jnp.cos(angle), jnp.sin(angle)])
    ratio = _safe_sqrt(jnp.maximum(small, 0.0) / big)
    return e @ u, e @ du, angle, ratio


def wavenumber(model: Model, v: Complex[Array, " n"]) -> Float[Array, ""]:
    """Mean phase gradient k of the in-plane centreline displacement (rad per L)."""
    _, w, _, _ = _quadrature(model.n_elements)
    u, du, _, _ = beat_plane(model, v)
    w = jnp.asarray(w)
    return jnp.sum(w * jnp.imag(jnp.conj(u) * du)) / jnp.sum(w * jnp.abs(u) ** 2)
