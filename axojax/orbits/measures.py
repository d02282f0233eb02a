"""Waveform measures of a limit cycle, the same as those of an observed beat.

A beat ``psi(s, t) = psi_0(s) + Re(psi_1(s) exp(i omega t)) + ...`` (tangent angle in
the beat plane) is summarised by (INTERFACE.md, ``axojax data``; Geyer et al.'s
measures, which the paper uses in section 3.7.1):

- static curvature: least-squares slope of psi_0(s) (rad/um);
- dynamic amplitude: arc-length mean of |psi_1(s)| (rad);
- wavelength: 2 pi / |least-squares slope of the unwrapped phase of psi_1(s)| (um);

and here also the tip amplitude (half peak-to-peak along the beat direction, um), the
frequency (Hz) and the out-of-plane measure (minor / major axis of the tip trace).

For a limit cycle, psi is the small-angle tangent angle of the mean centreline (the
x-derivative of the filaments' mean displacement, MODEL.md section 5) along the beat
direction, and psi_0, psi_1 are exactly the orbit's harmonics 0 and 1, in absolute
amplitude (rad). The array functions (:func:`static_curvature`,
:func:`dynamic_amplitude`, :func:`phase_wavelength`) take numpy or jax arrays, so data
and model are measured by the same code. Everything is differentiable: through the
orbit by the implicit function theorem (solve with ``solver.solve`` inside your own
``jax.grad``/``jax.jacfwd``), and the unwrapped phase in a smooth form (a cumulative sum
of the angles between neighbouring points, which equals ``np.unwrap`` while neighbours
differ by less than pi).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Complex, Float

from ..units import Units
from ..waveform.shapes import centreline
from .cycle import LimitCycle

N_POINTS = 41
"""Default number of arc lengths, uniform on [0, L] (as ``axojax data``)."""


def _xp(*arrays):
    return jnp if any(isinstance(a, jax.Array) for a in arrays) else np


def ls_slope(
    s: Float[Array | np.ndarray, " S"],
    y: Float[Array | np.ndarray, " S"],
    weight: Float[Array | np.ndarray, " S"] | None = None,
) -> Float[ArrayLike, ""]:
    """(Weighted) least-squares slope of y(s), shape ()."""
    xp = _xp(s, y, weight)
    w = xp.ones_like(s) if weight is None else weight
    sb = xp.sum(w * s) / xp.sum(w)
    yb = xp.sum(w * y) / xp.sum(w)
    return xp.sum(w * (s - sb) * (y - yb)) / xp.sum(w * (s - sb) ** 2)


def static_curvature(
    s_um: Float[Array | np.ndarray, " S"], psi0: Float[Array | np.ndarray, " S"]
) -> Float[ArrayLike, ""]:
    """Least-squares slope of psi_0(s), rad per unit of s (rad/um for s in um)."""
    return ls_slope(s_um, psi0)


def dynamic_amplitude(psi1: Complex[Array | np.ndarray, " S"]) -> Float[ArrayLike, ""]:
    """Arc-length mean of |psi_1| (rad) on a uniform grid."""
    xp = _xp(psi1)
    return xp.mean(xp.abs(psi1))


def _safe_angle(z, xp):
    """angle(z), with zero value and zero derivative where z = 0 (no NaN gradient)."""
    ok = xp.abs(z) > 0
    zs = xp.where(ok, z, 1.0)
    return xp.where(ok, xp.arctan2(xp.imag(zs), xp.real(zs)), 0.0)


def unwrapped_phase(
    psi1: Complex[Array | np.ndarray, " S"],
) -> tuple[Float[Array | np.ndarray, " S"], Float[Array | np.ndarray, " S"]]:
    """(phase (S,), weight (S,)): the phase of psi_1 unwrapped as the cumulative sum of
    the angles between neighbours (0 at the first point with psi_1 != 0), and a 0/1
    weight that drops points where psi_1 = 0 exactly (the clamped base of a model),
    whose phase is undefined."""
    xp = _xp(psi1)
    scale = xp.max(xp.abs(psi1))
    live = xp.abs(psi1) > 1e-12 * scale
    if xp is jnp:
        live = jax.lax.stop_gradient(live)
    # step into a live point from the previous live point (dead points are skipped: their
    # product is 0, angle 0); a dead point keeps the phase of the previous one.
    z = psi1[1:] * xp.conj(psi1[:-1])
    steps = _safe_angle(z, xp)
    phase = xp.concatenate([xp.zeros(1), xp.cumsum(steps)])
    return phase, live.astype(float)


def phase_slope(
    s: Float[Array | np.ndarray, " S"], psi1: Complex[Array | np.ndarray, " S"]
) -> Float[ArrayLike, ""]:
    """Least-squares slope of the unwrapped phase of psi_1 (rad per unit of s; negative
    for a wave travelling towards larger s with psi ~ Re(psi_1 e^{i omega t}))."""
    phase, w = unwrapped_phase(psi1)
    return ls_slope(s, phase, w)


def phase_wavelength(
    s_um: Float[Array | np.ndarray, " S"], psi1: Complex[Array | np.ndarray, " S"]
) -> Float[ArrayLike, ""]:
    """2 pi / |least-squares slope of the unwrapped phase of psi_1(s)| (units of s)."""
    xp = _xp(s_um, psi1)
    return 2 * xp.pi / xp.abs(phase_slope(s_um, psi1))


def tangent_modes(
    cycle: LimitCycle, s_um: Float[ArrayLike, " S"] | None = None, units: Units = Units()
) -> tuple[Float[Array, " S"], Float[Array, " S"], Complex[Array, " S"]]:
    """(s_um (S,), psi_0 (S,) rad, psi_1 (S,) complex rad) of the orbit along its beat
    direction at the concrete arc lengths ``s_um`` (um, in [0, L]; default 41 uniform points)
    psi = psi_0 + Re(psi_1 e^{i theta}) + higher harmonics, theta = omega t
    (the orbit's phase: theta = 0 where its phase condition holds)."""
    L = units.length_um
    s_np = (
        np.linspace(0.0, L, N_POINTS) if s_um is None else np.asarray(s_um, dtype=float)
    )  # concrete (static)
    X = cycle.coefficients
    H = cycle.harmonics
    slope = centreline(cycle.model, jnp.stack([X[0], X[1], X[H + 1]]), s_np / L, 1)  # (3, d, S)
    s = jnp.asarray(s_np)
    psi = _along(slope, cycle.beat_angle)
    return s, psi[0], psi[1] - 1j * psi[2]


def _along(v, angle):
    if v.shape[-2] == 1:
        return v[..., 0, :]
    return jnp.cos(angle) * v[..., 0, :] + jnp.sin(angle) * v[..., 1, :]


def tip_trace_axes(cycle: LimitCycle) -> Float[Array, ""]:
    """Out-of-plane measure: minor / major axis of the tip trace in the cross-section,
    sqrt(smaller / larger eigenvalue of the tip motion's covariance over one period)
    (0 for planar models; the MODEL.md section 3 measure of a simulated beat)."""
    model = cycle.model
    if model.n_dirs == 1:
        return jnp.zeros(())
    tip = centreline(model, cycle.coefficients, np.array([1.0]))[..., 0]  # (2H+1, 2)
    osc = tip[1:]
    R = osc.T @ osc / 2
    half_tr = 0.5 * (R[0, 0] + R[1, 1])
    disc = jnp.sqrt(0.25 * (R[0, 0] - R[1, 1]) ** 2 + R[0, 1] ** 2 + 1e-300)
    lo, hi = half_tr - disc, half_tr + disc
    return jnp.sqrt(jnp.maximum(lo, 0.0) / hi)


class CycleMeasures(eqx.Module):
    """Measures of one limit cycle (physical units; jax arrays, differentiable).

    Attributes:
        s_um: (S,) arc lengths; psi0: (S,) static mode (rad); psi1: (S,) complex first
            mode (rad, absolute amplitude; its phase is the orbit's).
        frequency_hz, tip_amplitude_um, wavelength_um (from the phase of psi_1),
        static_curvature_rad_per_um, dynamic_amplitude_rad, out_of_plane (minor / major
        axis of the tip trace).
    """

    s_um: Float[Array, " S"]
    psi0: Float[Array, " S"]
    psi1: Complex[Array, " S"]
    frequency_hz: Float[Array, ""]
    tip_amplitude_um: Float[Array, ""]
    wavelength_um: Float[Array, ""]
    static_curvature_rad_per_um: Float[Array, ""]
    dynamic_amplitude_rad: Float[Array, ""]
    out_of_plane: Float[Array, ""]

    SCALARS = (
        "frequency_hz",
        "tip_amplitude_um",
        "wavelength_um",
        "static_curvature_rad_per_um",
        "dynamic_amplitude_rad",
        "out_of_plane",
    )

    def scalars(self) -> dict[str, float]:
        """The scalar measures as Python floats."""
        return {k: float(getattr(self, k)) for k in self.SCALARS}


def cycle_measures(
    cycle: LimitCycle, s_um: Float[ArrayLike, " S"] | None = None, units: Units = Units()
) -> CycleMeasures:
    """All measures of ``cycle`` at arc lengths ``s_um`` (default: 41 uniform points on
    [0, L], as ``axojax data``). Jit-able and differentiable (see the module docstring)."""
    s, psi0, psi1 = tangent_modes(cycle, s_um, units)
    return CycleMeasures(
        s_um=s,
        psi0=psi0,
        psi1=psi1,
        frequency_hz=cycle.frequency_hz(units),
        tip_amplitude_um=cycle.amplitude_um(units),
        wavelength_um=phase_wavelength(s, psi1),
        static_curvature_rad_per_um=static_curvature(s, psi0),
        dynamic_amplitude_rad=dynamic_amplitude(psi1),
        out_of_plane=tip_trace_axes(cycle),
    )
