"""What a fit matches, as records (observed values and their sigmas; the model side is
:mod:`axojax.inverse.predictions`): scalar beat observables and an observed mode shape, each with an
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

import numpy as np

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
    amplitude with the nonlinear beat (:mod:`axojax.inverse.cycle_targets`, up to the orbit's
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
