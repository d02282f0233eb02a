"""What a fit matches: scalar beat observables and an observed mode shape, each with an
uncertainty, turned into normalised residuals ``(model - observed) / sigma``.

Scalar targets (physical units, from the dominant mode): ``frequency_hz``,
``wavelength_um``, ``velocity_um_per_s`` and ``growth_rate_per_s`` (a beating cilium sits
near the Hopf boundary: target 0 with a tolerance). With ``source="limit_cycle"`` a target
is a measure of the nonlinear beat's periodic orbit (:func:`axojax.orbits.limit_cycle`,
differentiable by the implicit function theorem) instead: ``frequency_hz``,
``amplitude_um`` (tip, half peak-to-peak along the beat direction) or ``wavelength_um``. A :class:`ShapeTarget` is an observed
first Fourier mode of the tangent angle, psi_1(s); the model's psi_1 (the dominant
eigenvector's centreline slope in its beat plane) is fitted with the best complex scale
alpha, so the residual ``psi_obs - alpha psi_model`` ignores the mode's arbitrary
amplitude and phase but not its shape or propagation direction.
"""

from __future__ import annotations

import dataclasses
import math

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from ..eigen.metrics import beat_plane
from ..eigen.mode import Mode
from ..fem import interpolation_matrix
from ..models.section import Model
from ..units import Units

SCALARS = ("frequency_hz", "wavelength_um", "velocity_um_per_s", "growth_rate_per_s")
CYCLE_SCALARS = ("frequency_hz", "amplitude_um", "wavelength_um")
SOURCES = ("linear", "limit_cycle")


@dataclasses.dataclass(frozen=True)
class Target:
    """A scalar observable ``name`` observed as ``value +- sigma`` (physical units), of the
    dominant linear mode (``source="linear"``) or of the limit cycle
    (``source="limit_cycle"``: ``frequency_hz``, ``amplitude_um``, ``wavelength_um``)."""

    name: str
    value: float
    sigma: float
    source: str = "linear"

    @property
    def key(self) -> str:
        """Name in results: ``name`` (linear) or ``limit_cycle_<name>``."""
        return self.name if self.source == "linear" else f"{self.source}_{self.name}"

    def __post_init__(self) -> None:
        if self.source not in SOURCES:
            raise ValueError(
                f"unknown target source {self.source!r}; choose from {', '.join(SOURCES)}"
            )
        names = SCALARS if self.source == "linear" else CYCLE_SCALARS
        if self.name not in names:
            raise ValueError(
                f"unknown {self.source} target {self.name!r}; choose from {', '.join(names)}"
            )
        if not math.isfinite(self.value):
            raise ValueError(f"target {self.name} must be finite, got {self.value!r}")
        if not (math.isfinite(self.sigma) and self.sigma > 0):
            raise ValueError(f"uncertainty of target {self.name} must be > 0, got {self.sigma!r}")


@dataclasses.dataclass(frozen=True)
class ShapeTarget:
    """Observed Fourier modes of the tangent angle at arc lengths ``s_um`` (S,):
    psi_1(s) (rad, complex, (S,)) with the standard error ``sigma`` (rad) of each of its
    real and imaginary parts: a scalar, or one value per point (S,). ``psi0`` (rad, (S,))
    is the observed static mode, optional (limit-cycle waveform fits use it; linear-mode
    fits ignore it). ``source``: ``"linear"`` matches psi_1 with the dominant linear
    mode up to a complex scale; ``"limit_cycle"`` matches psi_0 and psi_1 in absolute
    amplitude with the nonlinear beat (:mod:`axojax.orbits.targets`, up to the orbit's
    arbitrary time origin)."""

    s_um: np.ndarray
    psi1: np.ndarray
    sigma: float | np.ndarray
    psi0: np.ndarray | None = None
    source: str = "linear"

    def __post_init__(self) -> None:
        if self.source not in SOURCES:
            raise ValueError(
                f"unknown shape source {self.source!r}; choose from {', '.join(SOURCES)}"
            )
        sigma = np.asarray(self.sigma, dtype=float)
        if not (np.all(np.isfinite(sigma)) and np.all(sigma > 0)):
            raise ValueError(f"shape uncertainty must be finite and > 0, got {self.sigma!r}")
        shape = np.asarray(self.s_um).shape
        if shape != np.asarray(self.psi1).shape:
            raise ValueError("shape target: s_um and psi1 must have the same length")
        if sigma.ndim and sigma.shape != shape:
            raise ValueError(
                f"shape target: sigma must be a scalar or have the shape of s_um {shape}, got {sigma.shape}"
            )
        if self.psi0 is not None and np.asarray(self.psi0).shape != shape:
            raise ValueError("shape target: psi0 must have the shape of s_um")


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
