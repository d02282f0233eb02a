"""Waveform measures of a limit cycle, the same as those of an observed beat.

A beat ``psi(s, t) = psi_0(s) + Re(psi_1(s) exp(i omega t)) + ...`` (tangent angle in
the beat plane) is summarised by the measures of :mod:`axojax.waveform.measures` (the
one implementation, shared with ``axojax data``, ``axojax modes`` and ``axojax
simulate``; Geyer et al.'s measures, which the paper uses in section 3.7.1):

- static curvature: least-squares slope of psi_0(s) (rad/um);
- dynamic amplitude: arc-length mean of |psi_1(s)| (rad);
- wavelength: 2 pi / |k|, k the least-squares slope of psi_1(s)'s unwrapped phase (um);

and here also the tip amplitude (half peak-to-peak along the beat direction, um), the
frequency (Hz) and the out-of-plane measure (minor / major axis of the tip trace), and
the amplitude dip of psi_1 at the arc lengths (min / max |psi_1| over the middle 80 %:
below ``SENSITIVE_DIP`` the wavelength is sensitive, :mod:`axojax.waveform.measures`).

For a limit cycle, psi is the small-angle tangent angle of the mean centreline (the
x-derivative of the filaments' mean displacement, docs/model.md) along the beat
direction, and psi_0, psi_1 are exactly the orbit's harmonics 0 and 1, in absolute
amplitude (rad). Static curvature and dynamic amplitude are taken on the arc lengths
asked for (default 41 uniform points, as ``axojax data``); the wavelength is the orbit's
own (:attr:`LimitCycle.wavenumber`: psi_1 and psi_1' exact at the mesh's Gauss points),
whatever the points. Everything is differentiable through the orbit by the implicit
function theorem (solve with ``solver.solve`` inside your own
``jax.grad``/``jax.jacfwd``).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Complex, Float

from ..units import Units
from ..waveform import measures as wm
from ..waveform.shapes import centreline
from .cycle import LimitCycle

N_POINTS = 41
"""Default number of arc lengths, uniform on [0, L] (as ``axojax data``)."""


def tangent_modes(
    cycle: LimitCycle, s_um: Float[ArrayLike, " S"] | None = None, units: Units = Units()
) -> tuple[Float[Array, " S"], Float[Array, " S"], Complex[Array, " S"]]:
    """(s_um (S,), psi_0 (S,) rad, psi_1 (S,) complex rad) of the orbit along its beat
    direction at the concrete arc lengths ``s_um`` (um, in [0, L]; default 41 uniform
    points): :meth:`LimitCycle.tangent_modes`."""
    L = units.length_um
    s_np = np.linspace(0.0, L, N_POINTS) if s_um is None else np.asarray(s_um, dtype=float)
    psi0, psi1 = cycle.tangent_modes(s_np / L)
    return jnp.asarray(s_np), psi0, psi1


def tip_trace_axes(cycle: LimitCycle) -> Float[Array, ""]:
    """Out-of-plane measure: minor / major axis of the tip trace in the cross-section,
    sqrt(smaller / larger eigenvalue of the tip motion's covariance over one period)
    (0 for planar models; the docs/model.md section 3 measure of a simulated beat)."""
    model = cycle.model
    if model.n_dirs == 1:
        return jnp.zeros(())
    tip = centreline(model, cycle.q_coefficients, np.array([1.0]), body=True)[..., 0]
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
        frequency_hz, tip_amplitude_um, wavelength_um (the orbit's: inf for a standing
            wave),
        static_curvature_rad_per_um, dynamic_amplitude_rad, out_of_plane (minor / major
        axis of the tip trace), amplitude_dip (min / max |psi_1| over the middle 80 % of
        ``s_um``; not a fit target, so not in ``SCALARS``).
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
    amplitude_dip: Float[Array, ""]

    SCALARS = (
        "frequency_hz",
        "tip_amplitude_um",
        "wavelength_um",
        "static_curvature_rad_per_um",
        "dynamic_amplitude_rad",
        "out_of_plane",
    )

    def scalars(self) -> dict[str, float | bool]:
        """The scalar measures as Python floats, with ``amplitude_dip`` and
        ``wavelength_sensitive`` (the dip below ``SENSITIVE_DIP``, for a travelling wave)."""
        out = {k: float(getattr(self, k)) for k in self.SCALARS}
        dip = float(self.amplitude_dip)
        sensitive = bool(np.isfinite(out["wavelength_um"])) and wm.is_sensitive(dip)
        return out | {"amplitude_dip": dip, "wavelength_sensitive": sensitive}


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
        wavelength_um=cycle.wavelength_um(units),
        static_curvature_rad_per_um=wm.static_curvature(s, psi0),
        dynamic_amplitude_rad=wm.dynamic_amplitude(s, psi1),
        out_of_plane=tip_trace_axes(cycle),
        amplitude_dip=wm.amplitude_dip(s, psi1),
    )
