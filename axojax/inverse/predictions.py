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
from ..orbits.measures import cycle_measures
from ..units import Units
from ..waveform import measures
from .cycle_targets import ALIASES

K_FLOOR = 1e-6  # rad/L: a standing wave has no wavelength (inf); a fit sees 2 pi / K_FLOOR


def _finite_wavelength(k: Float[Array, ""], units: Units) -> Float[Array, ""]:
    """The wavelength of :mod:`axojax.waveform.measures` (um), at most 2 pi / K_FLOOR L."""
    return jnp.minimum(measures.wavelength(k), 2 * jnp.pi / K_FLOOR) * units.length_um


def scalar_value(mode: Mode, name: str, units: Units) -> Float[Array, ""]:
    """Observable ``name`` of the dominant mode in physical units, finite everywhere
    (wavelength and velocity at most ``2 pi / K_FLOOR``) so that fits never see inf/NaN."""
    if name in ("wavelength_um", "velocity_um_per_s"):
        wavelength = _finite_wavelength(mode.wavenumber, units)
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
    _, _, angle, _ = beat_plane(model, mode.eigenvector)
    return measures.along(q @ dphi.T, angle)


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
    """Limit-cycle observable ``name`` in physical units: a name of ``CYCLE_SCALARS`` or
    any scalar of :func:`axojax.orbits.cycle_measures` (the numbers ``axojax orbit`` and
    the paper table print); the wavelength at most ``2 pi / K_FLOOR`` (finite for fits)."""
    if name == "wavelength_um":
        return _finite_wavelength(cycle.wavenumber, units)
    return getattr(cycle_measures(cycle, None, units), ALIASES.get(name, name))
