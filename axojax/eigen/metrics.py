"""Mode shapes and mode metrics (docs/model.md section 5).

An eigenvector ``v`` (``model.n_unknowns``,) is read as ``(F, d, r)`` per-filament dofs
(:meth:`axojax.models.Model.filament_dofs`: node 0's dofs too where the base is not
clamped, the basal sliding left out) and interpolated with the Hermite shape functions
(:meth:`axojax.models.Model.interpolation`). The centreline displacement is the mean over filaments. In 3D
the beat direction is the principal axis of ``R = Re int u u^H dx`` (2 x 2) and the
out-of-plane ratio is ``sqrt(smaller / larger eigenvalue of R)``. The mode's tangent
angle along the beat direction is psi_1 = u'(x), and its wavenumber is the one of every
beat (:mod:`axojax.waveform.measures`), the least-squares slope of psi_1's unwrapped
phase over the length, in its smooth form::

    k = int x (1 - x) phi'(x) dx / int x (1 - x) dx,   phi' = Im(conj(psi_1) psi_1') / |psi_1|^2

with psi_1 = u', psi_1' = u''.

wavelength ``2 pi / |k|`` (units of L); propagation is anterograde (base to tip) when
``k * sign(Im lambda) < 0``. Integrals use Gauss-Legendre points on the mesh (at least
200 points along x, with at least four points per element: exact for the polynomial
integrands, and for phi', a rational function smooth wherever psi_1 != 0, accurate to
1e-4 relative at 10 elements, tests/waveform/test_waveform_measures.py). Every metric is
invariant to the complex scale of v, so its derivative through
:func:`axojax.eigen.dominant.dominant_eigenpair` is exact. The same formula applied to
the displacement u instead of its slope (:func:`displacement_wavenumber`) was axojax's
wavenumber until 2026-12, and the |psi_1|^2-weighted mean phase gradient
(:func:`weighted_wavenumber`) from 2026-12-03 to 2026-12-06; both are kept under those
names only, never as a wavelength.
"""

from __future__ import annotations

import functools
import math

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from ..fem import make_mesh
from ..models.section import Model
from ..waveform.measures import along, amplitude_dip, phase_slope, weighted_phase_gradient
from ..waveform.shapes import centreline

MIN_POINTS = 200


@functools.lru_cache(maxsize=64)
def _gauss(n_elements: int) -> tuple[np.ndarray, np.ndarray]:
    """(x, weights): Gauss points on the mesh (at least 4 per element, MIN_POINTS in all)."""
    per = max(4, math.ceil(MIN_POINTS / n_elements))
    mesh = make_mesh(n_elements, per)
    return mesh.x, mesh.weights


def _gauss_points(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """(x, weights) at the Gauss points of ``model``'s mesh."""
    return _gauss(model.n_elements)


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
    phi = jnp.asarray(model.interpolation(np.asarray(x), derivative))
    return jnp.einsum("mr,fdr->fdm", phi, model.filament_dofs(jnp.asarray(v)))


def _safe_sqrt(x):
    pos = x > 0
    return jnp.where(pos, jnp.sqrt(jnp.where(pos, x, 1.0)), 0.0)


def beat_plane(
    model: Model, v: Complex[Array, " n"]
) -> tuple[Complex[Array, " m"], Complex[Array, " m"], Array, Array]:
    """Complex in-plane centreline displacement u and u' at the quadrature points, the
    beat-direction angle (radians from y towards z) and the out-of-plane ratio."""
    x, w = _gauss_points(model)
    v = jnp.asarray(v)
    u = centreline(model, v, x)  # (d, m)
    du = centreline(model, v, x, derivative=1)
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
    ratio = _safe_sqrt(jnp.maximum(small, 0.0) / big)
    return along(u, angle), along(du, angle), angle, ratio


def _tangent(model: Model, v: Complex[Array, " n"], angle: Float[Array, ""]):
    """(x, w, psi_1, psi_1') of the state ``v`` along ``angle`` at the Gauss points."""
    x, w = _gauss_points(model)
    v = jnp.asarray(v)
    psi = along(centreline(model, v, x, derivative=1), angle)
    dpsi = along(centreline(model, v, x, derivative=2), angle)
    return jnp.asarray(x), jnp.asarray(w), psi, dpsi


def tangent_wavenumber(
    model: Model, v: Complex[Array, " n"], angle: Float[Array, ""]
) -> Float[Array, ""]:
    """Phase slope k (rad per L) of psi_1 = u', the slope of the centreline of the complex
    state ``v`` (an eigenvector, or an orbit's first harmonic) along the beat direction
    ``angle``: :func:`axojax.waveform.measures.phase_slope` with the exact psi_1 and
    psi_1' = u'' at the Gauss points."""
    x, w, psi, dpsi = _tangent(model, v, angle)
    return phase_slope(x, psi, dpsi, w)


def tangent_measures(
    model: Model, v: Complex[Array, " n"], angle: Float[Array, ""]
) -> tuple[Float[Array, ""], Float[Array, ""]]:
    """(k, dip): :func:`tangent_wavenumber` and
    :func:`axojax.waveform.measures.amplitude_dip` of psi_1 = u' from one evaluation of
    psi_1 at the Gauss points (below :data:`axojax.waveform.measures.SENSITIVE_DIP` the
    wavelength is sensitive)."""
    x, w, psi, dpsi = _tangent(model, v, angle)
    return phase_slope(x, psi, dpsi, w), amplitude_dip(x, psi)


def wavenumber(model: Model, v: Complex[Array, " n"]) -> Float[Array, ""]:
    """Phase slope k (rad per L) of the mode's tangent angle psi_1 = u' along its beat
    direction (module docstring): what every axojax wavelength is made of."""
    _, _, angle, _ = beat_plane(model, v)
    return tangent_wavenumber(model, v, angle)


def weighted_wavenumber(model: Model, v: Complex[Array, " n"]) -> Float[Array, ""]:
    """Retired: the |psi_1|^2-weighted mean phase gradient of psi_1 = u' (rad per L), the
    wavenumber from 2026-12-03 to 2026-12-06. Kept for comparison only; never a
    wavelength (:func:`wavenumber` is)."""
    _, _, angle, _ = beat_plane(model, v)
    _, w, psi, dpsi = _tangent(model, v, angle)
    return weighted_phase_gradient(psi, dpsi, w)


def displacement_wavenumber(model: Model, v: Complex[Array, " n"]) -> Float[Array, ""]:
    """Retired: the weighted mean phase gradient taken of the displacement u instead of
    its slope (rad per L), axojax's wavenumber until 2026-12. Kept for comparison only;
    never a wavelength (:func:`wavenumber` is)."""
    _, w = _gauss_points(model)
    u, du, _, _ = beat_plane(model, v)
    return weighted_phase_gradient(u, du, jnp.asarray(w))
