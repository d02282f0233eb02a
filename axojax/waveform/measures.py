"""The waveform measures of a beat, one implementation for models and data (docs/model.md,
"Mode metrics").

A beat's tangent angle along the beat direction is decomposed over whole periods as::

    psi(s, t) ~ psi_0(s) + Re(psi_1(s) exp(i omega t)),   omega > 0

(for a linear mode ``v exp(lambda t)``: psi_1 = u'(x), the slope of the mean centreline
in the beat plane, with omega = |Im lambda|). Its measures:

- wavenumber ``k = int Im(conj(psi_1) psi_1') ds / int |psi_1|^2 ds``: the
  |psi_1|^2-weighted mean phase gradient (rad per unit of s; smooth, no unwrapping,
  differentiable). :func:`phase_gradient` is the one formula; :func:`sampled_wavenumber`
  feeds it sampled psi_1 (data, a simulation, an orbit at chosen points) by the midpoint
  rule, and a model feeds it psi_1 and psi_1' at its quadrature points
  (:func:`axojax.eigen.metrics.tangent_wavenumber`);
- wavelength ``2 pi / |k|`` (:func:`wavelength`); a **standing wave** (the phase turns by
  less than :data:`STANDING_PHASE_RAD` along the whole beat) has wavelength ``inf`` in
  arrays, printed ``none`` in text and ``null`` in JSON (:func:`finite_or_none`);
- direction (:func:`direction`): anterograde (base to tip, +1) when
  ``k * sign(omega) < 0``, retrograde (-1), 0 when not oscillating or standing;
- static curvature: least-squares slope of psi_0(s) (:func:`static_curvature`);
- dynamic amplitude: arc-length mean of |psi_1(s)|, trapezoidal rule on the samples
  (:func:`dynamic_amplitude`);
- tip amplitude: half the peak-to-peak tip displacement along the beat direction
  (:func:`tip_amplitude`);
- the component along the beat direction (:func:`along`).

Every function takes numpy or jax arrays (jax in, jax out: jit-able and differentiable;
numpy in, numpy out).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import ArrayLike, Complex, Float, Inexact

STANDING_PHASE_RAD = 1e-9
"""A beat whose mean phase gradient turns its phase by less than this along the whole
length (``|k| * length``) is a standing wave: no wavelength, no direction."""


def _xp(*arrays):
    return jnp if any(isinstance(a, jax.Array) for a in arrays) else np


def along(v: Inexact[ArrayLike, "..."], angle: Float[ArrayLike, ""], axis: int = -2):
    """Component along the beat direction (``angle`` radians from y towards z) of ``v``,
    whose ``axis`` holds the d = 1 (planar) or 2 (y, z) directions; that axis is removed.
    Units of ``v``."""
    xp = _xp(v, angle)
    v = xp.moveaxis(xp.asarray(v), axis, -1)
    if v.shape[-1] == 1:
        return v[..., 0]
    return xp.cos(angle) * v[..., 0] + xp.sin(angle) * v[..., 1]


def phase_gradient(
    psi: Inexact[ArrayLike, " m"], dpsi: Inexact[ArrayLike, " m"], weights: Float[ArrayLike, " m"]
) -> Float[ArrayLike, ""]:
    """``k = sum w Im(conj(psi) dpsi) / sum w |psi|^2``: the quadrature, with points where
    ``psi`` and its s-derivative ``dpsi`` are known and weights ``w``, of the mean phase
    gradient (rad per unit of s). 0 for ``psi = 0`` everywhere."""
    xp = _xp(psi, dpsi, weights)
    num = xp.sum(weights * xp.imag(xp.conj(psi) * dpsi))
    den = xp.sum(weights * xp.abs(psi) ** 2)
    ok = den > 0
    return xp.where(ok, num / xp.where(ok, den, 1.0), 0.0)


def sampled_wavenumber(
    s: Float[ArrayLike, " S"], psi1: Complex[ArrayLike, " S"]
) -> Float[ArrayLike, ""]:
    """Mean phase gradient k of psi_1 sampled at increasing arc lengths ``s`` (any
    spacing), by the midpoint rule: psi_1 and psi_1' at the middle of each interval are
    the mean and the difference quotient of its ends, so
    ``k = sum_j Im(conj(psi_j) psi_{j+1}) / sum_j |psi_j + psi_{j+1}|^2 / 4 (s_{j+1} - s_j)``.
    Rad per unit of s."""
    xp = _xp(s, psi1)
    ds = xp.diff(s)
    mid = (psi1[1:] + psi1[:-1]) / 2
    return phase_gradient(mid, xp.diff(psi1) / ds, ds)


def wavelength(k: Float[ArrayLike, "..."], length: float = 1.0) -> Float[ArrayLike, "..."]:
    """``2 pi / |k|`` (units of s); ``inf`` for a standing wave, ``|k| * length <=``
    :data:`STANDING_PHASE_RAD` (``length``: the beat's length in units of s). Its
    derivative is finite everywhere (0 where standing)."""
    xp = _xp(k)
    a = xp.abs(k)
    standing = a * length <= STANDING_PHASE_RAD
    return xp.where(standing, xp.inf, 2 * xp.pi / xp.where(standing, 1.0, a))


def direction(
    k: Float[ArrayLike, "..."], omega: Float[ArrayLike, "..."], length: float = 1.0
) -> ArrayLike:
    """+1 anterograde (base to tip: ``k * sign(omega) < 0``), -1 retrograde, 0 where
    ``omega = 0`` (not oscillating) or the wave stands (:func:`wavelength`). ``omega``:
    the angular frequency the beat is written with, ``psi_1 exp(i omega t)`` (for a linear
    mode, ``Im lambda``)."""
    xp = _xp(k, omega)
    moving = (omega != 0) & (xp.abs(k) * length > STANDING_PHASE_RAD)
    return xp.where(moving, xp.where(k * xp.sign(omega) < 0, 1, -1), 0)


def finite_or_none(x) -> float | None:
    """A Python float, or ``None`` where ``x`` is not finite (a standing wave's
    wavelength): how a wavelength is printed (``none``) and written to JSON (``null``)."""
    x = float(x)
    return x if np.isfinite(x) else None


def wavelength_text(x, spec: str = ".4g", unit: str = "um") -> str:
    """A wavelength as the command line prints it (``spec``, then ``unit``): ``none`` for
    a standing wave or a mode that does not oscillate (``None`` or not finite)."""
    x = None if x is None else finite_or_none(x)
    return "none" if x is None else f"{x:{spec}} {unit}".rstrip()


def ls_slope(
    s: Float[ArrayLike, " S"],
    y: Float[ArrayLike, " S"],
    weight: Float[ArrayLike, " S"] | None = None,
) -> Float[ArrayLike, ""]:
    """(Weighted) least-squares slope of y(s), shape (); units of y per unit of s."""
    xp = _xp(s, y, weight)
    w = xp.ones_like(s) if weight is None else weight
    sb = xp.sum(w * s) / xp.sum(w)
    yb = xp.sum(w * y) / xp.sum(w)
    return xp.sum(w * (s - sb) * (y - yb)) / xp.sum(w * (s - sb) ** 2)


def static_curvature(
    s: Float[ArrayLike, " S"], psi0: Float[ArrayLike, " S"]
) -> Float[ArrayLike, ""]:
    """Least-squares slope of psi_0(s): rad per unit of s (rad/um for s in um)."""
    return ls_slope(s, psi0)


def dynamic_amplitude(
    s: Float[ArrayLike, " S"], psi1: Complex[ArrayLike, " S"]
) -> Float[ArrayLike, ""]:
    """Arc-length mean of |psi_1(s)| over [s_0, s_end] by the trapezoidal rule (rad; any
    spacing of ``s``)."""
    xp = _xp(s, psi1)
    a = xp.abs(psi1)
    return xp.sum(xp.diff(s) * (a[1:] + a[:-1]) / 2) / (s[-1] - s[0])


def tip_amplitude(y: Float[ArrayLike, "... T"], axis: int = -1) -> Float[ArrayLike, "..."]:
    """Half the peak-to-peak of the tip displacement ``y`` along the beat direction over
    one period (samples along ``axis``, or the refined extremes of a smooth orbit);
    units of ``y``."""
    xp = _xp(y)
    return (xp.max(y, axis=axis) - xp.min(y, axis=axis)) / 2


__all__ = [
    "STANDING_PHASE_RAD",
    "along",
    "direction",
    "dynamic_amplitude",
    "finite_or_none",
    "ls_slope",
    "phase_gradient",
    "sampled_wavenumber",
    "static_curvature",
    "tip_amplitude",
    "wavelength",
    "wavelength_text",
]
