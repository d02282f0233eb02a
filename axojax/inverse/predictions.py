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
from ..models.section import Model
from ..orbits.measures import cycle_measures
from ..units import Units
from ..waveform import measures
from ..waveform.shapes import centreline
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


def model_psi1(
    model: Model,
    mode: Mode,
    s: Float[np.ndarray, " S"],
    component: str | tuple = "in_plane",
    frame: str = "lab",
) -> Complex[Array, " S"]:
    """The model's complex psi_1 at ``s`` (units of L), up to scale: the centreline slope
    along its beat direction (``component="in_plane"``) or perpendicular to it in the
    cross-section plane, rotated from the beat direction by +90 degrees from y towards z
    (``"out_of_plane"``, the data's e3 = e1 x e2, :mod:`axojax.beats.reduction`).
    ``component``: one name, or one per point of ``s`` (a joined target's). ``frame``
    ``"basal"``: relative to the basal tangent, psi_1(s) - psi_1(0) of the same component
    (:data:`axojax.beats.targets.FRAMES`).

    Raises:
        ValueError: an out-of-plane component asked of a planar (2D) model.
    """
    names = (component,) * len(s) if isinstance(component, str) else tuple(component)
    if len(names) != len(s):
        raise ValueError(f"component: one name or one per point ({len(s)}), got {len(names)}")
    out = np.array([c == "out_of_plane" for c in names], dtype=bool)
    if out.any() and model.n_dirs == 1:
        raise ValueError(
            f"an out-of-plane shape target needs a 3D model; {model.name!r} beats in one plane"
        )
    _, _, angle, _ = beat_plane(model, mode.eigenvector)

    def at(x):
        slope = centreline(model, jnp.asarray(mode.eigenvector), np.asarray(x), derivative=1)
        if not out.any():
            return measures.along(slope, angle)
        return jnp.where(
            jnp.asarray(out),
            measures.along(slope, angle + jnp.pi / 2),
            measures.along(slope, angle),
        )

    psi = at(s)
    return psi - at(np.zeros(len(s))) if frame == "basal" else psi


def shape_fit(
    model: Model, mode: Mode, target: ShapeTarget, units: Units, at_um=None, at_component=None
) -> tuple[Array, Array]:
    """(alpha psi_model at ``at_um`` (default the target's s_um), alpha): the model's psi_1
    (:func:`model_psi1` of the target's ``component``) scaled by the complex alpha that best
    fits the observed psi_1 in weighted least squares (weights 1 / sigma^2) over the
    target's points: one alpha for all of its components. ``at_component``: the
    component at each of ``at_um`` (default the target's ``component`` when it is one
    name, else required)."""
    psi_m = model_psi1(
        model, mode, np.asarray(target.s_um) / units.length_um, target.component, target.frame
    )
    obs = jnp.asarray(target.psi1)
    w = 1.0 / jnp.broadcast_to(jnp.asarray(target.sigma, dtype=float), obs.shape) ** 2
    alpha = jnp.vdot(psi_m, w * obs) / jnp.vdot(psi_m, w * psi_m)  # weighted least squares
    if at_um is None:
        return alpha * psi_m, alpha
    if at_component is None:
        if not isinstance(target.component, str):
            raise ValueError("shape_fit: give at_component for a target of several components")
        at_component = target.component
    at = np.asarray(at_um) / units.length_um
    return alpha * model_psi1(model, mode, at, at_component, target.frame), alpha


def shape_residuals(
    model: Model, mode: Mode, target: ShapeTarget, units: Units
) -> Float[Array, " 2S"]:
    """(psi_obs - alpha psi_model) / sigma, real and imaginary parts, alpha the best complex scale
    (weighted by 1 / sigma^2 where sigma varies along s)."""
    fitted, _ = shape_fit(model, mode, target, units)
    obs = jnp.asarray(target.psi1)
    r = (obs - fitted) / jnp.broadcast_to(jnp.asarray(target.sigma, dtype=float), obs.shape)
    return jnp.concatenate([jnp.real(r), jnp.imag(r)])


def cycle_values(cycle, names, units: Units) -> dict[str, Float[Array, ""]]:
    """Limit-cycle observables ``names`` in physical units, by name: each a name of
    ``CYCLE_SCALARS`` or any scalar of :func:`axojax.orbits.cycle_measures` (the numbers
    ``axojax orbit`` and the paper table print), the measures taken once for all; the
    wavelength at most ``2 pi / K_FLOOR`` (finite for fits)."""
    names = list(names)
    out = {}
    if any(n != "wavelength_um" for n in names):
        measures = cycle_measures(cycle, None, units)
        out = {n: getattr(measures, ALIASES.get(n, n)) for n in names if n != "wavelength_um"}
    if "wavelength_um" in names:
        out["wavelength_um"] = _finite_wavelength(cycle.wavenumber, units)
    return {n: out[n] for n in names}


def cycle_value(cycle, name: str, units: Units) -> Float[Array, ""]:
    """One limit-cycle observable ``name`` (:func:`cycle_values`)."""
    return cycle_values(cycle, [name], units)[name]
