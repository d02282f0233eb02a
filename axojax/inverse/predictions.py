"""The model's side of a target: the dominant mode's (or limit cycle's) value of each
observable, and the model's psi_1 scaled to an observed one (:mod:`axojax.beats.targets`
holds the observed records)."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from ..beats.targets import ShapeTarget
from ..eigen.metrics import beat_plane
from ..eigen.mode import Mode
from ..fem import interpolation_matrix
from ..models.section import Model
from ..units import Units

K_FLOOR = 1e-6  # rad/L: a standing (real) mode has k = 0; its wavelength is capped, not infinite


def scalar_value(mode: Mode, name: str, units: Units) -> Float[Array, ""]:
    """Observable ``name`` of the dominant mode in physical units, finite everywhere
    (wavelength and velocity use ``max(|k|, K_FLOOR)``) so that fits never see inf/NaN."""
    if name in ("wavelength_um", "velocity_um_per_s"):
        wavelength = 2 * jnp.pi / jnp.maximum(jnp.abs(mode.wavenumber), K_FLOOR) * units.length_um
        if name == "wavelength_um":
            return wavelength
        return wavelength * mode.frequency_hz(units)
    return {"frequency_hz": mode.frequency_hz, "growth_rate_per_s": mode.growth_rate_per_s}[name](
        units
    )


def model_psi1(model: Model, mode: Mode, s: Float[np.ndarray, " S"]) -> Complex[Array, " S"]:
    """The model's complex psi_1 at ``s`` (units of L) in its beat plane (up to scale)."""
    dphi = jnp.asarray(interpolation_matrix(model.n_elements, np.asarray(s), 1))
    q = jnp.reshape(mode.eigenvector, (model.n_filaments, model.n_dirs, model.mesh.n_dof)).mean(
        axis=0
    )
    du = q @ dphi.T  # (d, S)
    if model.n_dirs == 1:
        return du[0]
    _, _, angle, _ = beat_plane(model, mode.eigenvector)
    return jnp.cos(angle) * du[0] + jnp.sin(angle) * du[1]


def shape_fit(
    model: Model, mode: Mode, target: ShapeTarget, units: Units, at_um=None
) -> tuple[Array, Array]:
    """(alpha psi_model at ``at_um`` (default the target's s_um), alpha): the model's psi_1
    scaled by the complex alpha that best fits the observed psi_1 in weighted least squares
    (weights 1 / sigma^2) over the target's points."""
    psi_m = model_psi1(model, mode, np.asarray(target.s_um) / units.length_um)
    obs = jnp.asarray(target.psi1)
    w = 1.0 / jnp.broadcast_to(jnp.asarray(target.sigma, dtype=float), obs.shape) ** 2
    alpha = jnp.vdot(psi_m, w * obs) / jnp.vdot(psi_m, w * psi_m)  # weighted least squares
    if at_um is None:
        return alpha * psi_m, alpha
    return alpha * model_psi1(model, mode, np.asarray(at_um) / units.length_um), alpha


def shape_residuals(
    model: Model, mode: Mode, target: ShapeTarget, units: Units
) -> Float[Array, " 2S"]:
    """(psi_obs - alpha psi_model) / sigma, real and imaginary parts, alpha the best complex scale
    (weighted by 1 / sigma^2 where sigma varies along s)."""
    fitted, _ = shape_fit(model, mode, target, units)
    obs = jnp.asarray(target.psi1)
    r = (obs - fitted) / jnp.broadcast_to(jnp.asarray(target.sigma, dtype=float), obs.shape)
    return jnp.concatenate([jnp.real(r), jnp.imag(r)])


def cycle_value(cycle, name: str, units: Units) -> Float[Array, ""]:
    """Limit-cycle observable ``name`` (``CYCLE_SCALARS``) in physical units."""
    return {
        "frequency_hz": cycle.frequency_hz,
        "amplitude_um": cycle.amplitude_um,
        "wavelength_um": cycle.wavelength_um,
    }[name](units)
