"""What a fit matches, as records (observed values and their sigmas; the model side is
:mod:`axojax.inverse.predictions`): scalar beat observables and an observed mode shape, each with an
uncertainty, turned into normalised residuals ``(model - observed) / sigma``.

Scalar targets (physical units, from the dominant mode): ``frequency_hz``,
``wavelength_um``, ``velocity_um_per_s`` and ``growth_rate_per_s`` (a beating cilium sits
near the Hopf boundary: target 0 with a tolerance). With ``source="limit_cycle"`` a target
is a measure of the nonlinear beat's periodic orbit (:func:`axojax.orbits.limit_cycle`,
differentiable by the implicit function theorem) instead: ``frequency_hz``,
``amplitude_um`` (tip, half peak-to-peak along the beat direction) or ``wavelength_um``. A
:class:`ShapeTarget` is an observed first Fourier mode of the tangent angle, psi_1(s); the model's psi_1 (the dominant
eigenvector's centreline slope in its beat plane) is fitted with the best complex scale
alpha, so the residual ``psi_obs - alpha psi_model`` ignores the mode's arbitrary
amplitude and phase but not its shape or propagation direction.

A 3D beat has two transverse components (:mod:`axojax.beats.reduction`): ``in_plane``
(the tangent angle towards the beat frame's e2, the direction of largest motion; the
default, and a planar beat's only one) and ``out_of_plane`` (towards e3). A
:class:`ShapeTarget`'s ``component`` says which one it observes; a 3D model predicts
its psi_1 along its beat direction or perpendicular to it in the cross-section plane
accordingly (:func:`axojax.inverse.predictions.model_psi1`). :func:`join_components`
puts both in one target, so that one complex scale serves both: they are one mode's two
projections, and fitting each with its own scale would throw away their relative
amplitude and phase.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

SCALARS = ("frequency_hz", "wavelength_um", "velocity_um_per_s", "growth_rate_per_s")
CYCLE_SCALARS = ("frequency_hz", "amplitude_um", "wavelength_um")
SOURCES = ("linear", "limit_cycle")
COMPONENTS = ("in_plane", "out_of_plane")
FRAMES = ("lab", "basal")
"""Frames a shape is compared in (:mod:`axojax.beats.frames`): ``lab``, the tangent angle as
recorded (the model's psi_1 as it is, a moving base's rigid motion included); ``basal``,
relative to the basal tangent, psi(s, t) - psi(0, t) (the model's psi_1(s) - psi_1(0)
as well; the data transformed by :func:`axojax.beats.frames.in_basal_frame`)."""


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


RELATIVE_SIGMA = {
    "frequency_hz": 0.05,
    "wavelength_um": 0.10,
    "velocity_um_per_s": 0.10,
    "amplitude_um": 0.10,
}
"""The uncertainty of an observed scalar given without one, relative to it (``axojax
fit``'s ``--target-*`` flags): 5 % of a frequency, 10 % of a wavelength, a wave velocity
or a tip amplitude."""


def observed_target(
    name: str, value: float, sigma: float | None = None, source: str = "linear"
) -> Target:
    """The :class:`Target` of a scalar observed as ``value`` (> 0) +- ``sigma`` (default
    :data:`RELATIVE_SIGMA` of it), of the linear mode or the limit cycle (``source``).
    One-line ``ValueError`` (starting ``name:``) for a value or uncertainty <= 0."""
    if not value > 0:
        raise ValueError(f"{name}: must be > 0, got {value:g}")
    sigma = RELATIVE_SIGMA[name] * value if sigma is None else sigma
    if not sigma > 0:
        raise ValueError(f"{name}: its uncertainty must be > 0, got {sigma:g}")
    return Target(name, value, sigma, source=source)


@dataclasses.dataclass(frozen=True)
class ShapeTarget:
    """Observed Fourier modes of the tangent angle at arc lengths ``s_um`` (S,):
    psi_1(s) (rad, complex, (S,)) with the standard error ``sigma`` (rad) of each of its
    real and imaginary parts: a scalar, or one value per point (S,). ``psi0`` (rad, (S,))
    is the observed static mode, optional (limit-cycle waveform fits use it; linear-mode
    fits ignore it). ``source``: ``"linear"`` matches psi_1 with the dominant linear
    mode up to a complex scale; ``"limit_cycle"`` matches psi_0 and psi_1 in absolute
    amplitude with the nonlinear beat (:mod:`axojax.inverse.cycle_targets`, up to the orbit's
    arbitrary time origin). ``component``: which transverse component is observed,
    ``"in_plane"`` (default) or ``"out_of_plane"`` (module docstring), one name for
    every point or a tuple of one name per point (:func:`join_components`); limit-cycle
    shapes are in-plane only. ``frame``: :data:`FRAMES` (``"basal"``: model and data
    compared relative to the basal tangent; a limit-cycle shape's psi_0 is then compared
    exactly, in the lab frame up to a constant)."""

    s_um: np.ndarray
    psi1: np.ndarray
    sigma: float | np.ndarray
    psi0: np.ndarray | None = None
    source: str = "linear"
    component: str | tuple[str, ...] = "in_plane"
    frame: str = "lab"

    def __post_init__(self) -> None:
        if self.frame not in FRAMES:
            raise ValueError(f"unknown shape frame {self.frame!r}; choose from {', '.join(FRAMES)}")
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
        if not isinstance(self.component, str):
            object.__setattr__(self, "component", tuple(str(c) for c in self.component))
            if (len(self.component),) != shape:
                raise ValueError(
                    "shape target: component must be one name or one per point of s_um "
                    f"{shape}, got {len(self.component)}"
                )
        bad = sorted(set(self.components) - set(COMPONENTS))
        if bad:
            raise ValueError(
                f"unknown shape component {bad[0]!r}; choose from {', '.join(COMPONENTS)}"
            )
        if self.source == "limit_cycle" and set(self.components) != {"in_plane"}:
            raise ValueError("shape target: a limit-cycle shape is in-plane only")

    @property
    def components(self) -> tuple[str, ...]:
        """The component of every point, (S,) names."""
        if isinstance(self.component, str):
            return (self.component,) * int(np.asarray(self.s_um).size)
        return self.component

    def component_at(self, mask: np.ndarray) -> str | tuple[str, ...]:
        """``component`` of the points a boolean ``mask`` (S,) keeps (one name stays one)."""
        if isinstance(self.component, str):
            return self.component
        return tuple(c for c, keep in zip(self.component, np.asarray(mask)) if keep)


def join_components(targets: list[ShapeTarget] | tuple[ShapeTarget, ...]) -> ShapeTarget:
    """One shape target of the components of one beat (each target's points, in order,
    labelled with their component): a fit scales the model's psi_1 to all of them with one
    complex scale. One target is returned as it is. All must have the same ``source``
    and all or none a ``psi0``."""
    targets = list(targets)
    if not targets:
        raise ValueError("join_components: no shape targets given")
    if len(targets) == 1:
        return targets[0]
    if len({t.source for t in targets}) != 1:
        raise ValueError("join_components: the targets' sources differ")
    if len({t.psi0 is None for t in targets}) != 1:
        raise ValueError("join_components: give psi0 for all targets or none")
    if len({t.frame for t in targets}) != 1:
        raise ValueError("join_components: the targets' frames differ")

    def cat(get) -> np.ndarray:
        return np.concatenate(
            [np.broadcast_to(np.asarray(get(t)), np.asarray(t.s_um).shape) for t in targets]
        )

    return ShapeTarget(
        s_um=cat(lambda t: np.asarray(t.s_um, dtype=float)),
        psi1=cat(lambda t: t.psi1),
        sigma=cat(lambda t: np.asarray(t.sigma, dtype=float)),
        psi0=None if targets[0].psi0 is None else cat(lambda t: t.psi0),
        source=targets[0].source,
        component=tuple(c for t in targets for c in t.components),
        frame=targets[0].frame,
    )
