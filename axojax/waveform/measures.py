"""The waveform measures of a beat, one implementation for models and data (docs/model.md,
"Mode metrics").

A beat's tangent angle along the beat direction is decomposed over whole periods as::

    psi(s, t) ~ psi_0(s) + Re(psi_1(s) exp(i omega t)),   omega > 0

(for a linear mode ``v exp(lambda t)``: psi_1 = u'(x), the slope of the mean centreline
in the beat plane, with omega = |Im lambda|). Its measures:

- wavenumber ``k``: the **least-squares slope over the arc length of the unwrapped phase
  phi(s) of psi_1** (uniform weight on [0, L]; Geyer et al. 2016, the paper's fig. 12;
  docs/model.md section 5), rad per unit of s. Two discretisations of the one definition:
  :func:`phase_slope` takes psi_1 and psi_1' at quadrature points (the smooth form
  ``k = int s (L - s) phi'(s) ds / int s (L - s) ds``, ``phi' = Im(conj(psi_1) psi_1') /
  |psi_1|^2``, by parts: no unwrapping, differentiable wherever psi_1 != 0; a model's
  mode and orbit, :func:`axojax.eigen.metrics.tangent_wavenumber`), and
  :func:`sampled_wavenumber` takes psi_1 sampled at arc lengths (data, a simulation:
  unwrap by summing ``arg(conj(psi_j) psi_{j+1})``, then the least-squares line with the
  trapezoidal rule's weights, so that any spacing approximates the same integral).
  psi_1 at an end is taken by continuity (a clamped base has psi_1(0) = 0). Where psi_1
  (nearly) vanishes inside the flagellum its phase turns fast there and the measure
  counts that turn: the wavelength is then sensitive to small changes of the beat;
  :func:`amplitude_dip` (min |psi_1| / max |psi_1| over the middle of the length) below
  :data:`SENSITIVE_DIP` flags it. The retired |psi_1|^2-weighted mean phase gradient is
  :func:`weighted_phase_gradient` (only under that name, never a "wavelength");
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
"""A beat whose phase slope turns its phase by less than this along the whole
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


def phase_slope(
    s: Float[ArrayLike, " m"],
    psi: Inexact[ArrayLike, " m"],
    dpsi: Inexact[ArrayLike, " m"],
    weights: Float[ArrayLike, " m"],
    length: float = 1.0,
) -> Float[ArrayLike, ""]:
    """Least-squares slope k of the unwrapped phase of psi over [0, ``length``] (rad per
    unit of s), by quadrature of its smooth form::

        k = sum w s (L - s) phi' / sum w s (L - s),   phi' = Im(conj(psi) dpsi) / |psi|^2

    with ``psi`` and its s-derivative ``dpsi`` at quadrature points ``s`` (measured from
    the base) with weights ``w``. Points where ``psi = 0`` contribute no phase turn (an
    exact zero has no phase; at an end the phase is taken by continuity); 0 for
    ``psi = 0`` everywhere. Differentiable wherever psi != 0."""
    xp = _xp(s, psi, dpsi, weights)
    a2 = xp.abs(psi) ** 2
    nz = a2 > 0
    dphi = xp.where(nz, xp.imag(xp.conj(psi) * dpsi) / xp.where(nz, a2, 1.0), 0.0)
    g = weights * s * (length - s)
    return xp.sum(g * dphi) / xp.sum(g)


def weighted_phase_gradient(
    psi: Inexact[ArrayLike, " m"], dpsi: Inexact[ArrayLike, " m"], weights: Float[ArrayLike, " m"]
) -> Float[ArrayLike, ""]:
    """Retired (2026-12-03 to 2026-12-06): ``k = sum w Im(conj(psi) dpsi) / sum w |psi|^2``,
    the |psi|^2-weighted mean phase gradient. It discounts the phase that turns where the
    amplitude is small (it called the paper's 17 um fig. 12 beat 50 um), so it is never a
    wavelength; kept for comparison only (:func:`axojax.eigen.metrics.weighted_wavenumber`).
    0 for ``psi = 0`` everywhere."""
    xp = _xp(psi, dpsi, weights)
    num = xp.sum(weights * xp.imag(xp.conj(psi) * dpsi))
    den = xp.sum(weights * xp.abs(psi) ** 2)
    ok = den > 0
    return xp.where(ok, num / xp.where(ok, den, 1.0), 0.0)


def unwrapped_phase(psi1: Complex[ArrayLike, " S"]) -> Float[ArrayLike, " S"]:
    """Phase of samples psi_1 unwrapped by summing ``arg(conj(psi_j) psi_{j+1})`` from
    ``arg(psi_0)`` (rad). A sample that is exactly 0 (a clamped base) has no phase: it
    takes its next neighbour's (its previous one's at the far end), so it adds no turn;
    :func:`sampled_wavenumber` gives it no weight."""
    xp = _xp(psi1)
    after = xp.concatenate([psi1[1:], psi1[-2:-1]])
    psi1 = xp.where(psi1 == 0, after, psi1)
    step = _angle(xp, xp.conj(psi1[:-1]) * psi1[1:])
    start = _angle(xp, psi1[:1])
    return xp.concatenate([start, start + xp.cumsum(step)])


def _angle(xp, z):
    """arg z, 0 where z = 0, with a finite derivative there (no 0/0)."""
    nz = z != 0
    return xp.where(nz, xp.angle(xp.where(nz, z, 1.0)), 0.0)


def trapezoid_weights(s: Float[ArrayLike, " S"]) -> Float[ArrayLike, " S"]:
    """Weights of the trapezoidal rule on samples at ``s`` (any spacing; units of s)."""
    xp = _xp(s)
    ds = xp.diff(s)
    zero = xp.zeros_like(s[:1])
    return xp.concatenate([ds, zero]) / 2 + xp.concatenate([zero, ds]) / 2


def sampled_wavenumber(
    s: Float[ArrayLike, " S"], psi1: Complex[ArrayLike, " S"]
) -> Float[ArrayLike, ""]:
    """Least-squares slope k of the unwrapped phase of psi_1 sampled at increasing arc
    lengths ``s`` (rad per unit of s): :func:`unwrapped_phase`, then the line fitted with
    the trapezoidal rule's weights (:func:`trapezoid_weights`), the discrete form of the
    uniform weight on [s_0, s_end] whatever the spacing (for evenly spaced samples it
    differs from ``np.polyfit`` only by the half weight of the two ends). A sample that is
    exactly 0 has no phase and no weight (at an end: the phase by continuity)."""
    xp = _xp(s, psi1)
    w = xp.where(psi1 == 0, 0.0, trapezoid_weights(s))
    return ls_slope(s, unwrapped_phase(psi1), w)


MIDDLE = 0.1
""":func:`amplitude_dip` looks at the middle of the length, ``[MIDDLE L, (1 - MIDDLE) L]``:
psi_1 may vanish at an end (a clamped base) without making the phase ill defined."""

SENSITIVE_DIP = 0.1
"""A beat whose :func:`amplitude_dip` is below this has a near-zero of psi_1 inside the
flagellum, where the phase turns fast: its wavelength is sensitive (reports flag it)."""


def amplitude_dip(
    s: Float[ArrayLike, " S"], psi1: Complex[ArrayLike, " S"]
) -> Float[ArrayLike, ""]:
    """min |psi_1| / max |psi_1| over the middle of the length (:data:`MIDDLE`; points
    ``s`` in any order, as quadrature points or samples). Below :data:`SENSITIVE_DIP` the
    wavelength is sensitive (module docstring); 0 for psi_1 = 0 everywhere."""
    xp = _xp(s, psi1)
    a = xp.abs(psi1)
    lo, hi = xp.min(s), xp.max(s)
    inside = (s >= lo + MIDDLE * (hi - lo)) & (s <= hi - MIDDLE * (hi - lo))
    top = xp.max(a)
    low = xp.min(xp.where(inside, a, xp.inf))
    return xp.where(top > 0, low / xp.where(top > 0, top, 1.0), 0.0)


def is_sensitive(dip) -> bool:
    """True where :func:`amplitude_dip` says the wavelength is sensitive."""
    return dip is not None and bool(float(dip) < SENSITIVE_DIP)


def sensitive_note(dip) -> str:
    """What the command line adds after a wavelength whose :func:`amplitude_dip` is below
    :data:`SENSITIVE_DIP` (``""`` otherwise, or for ``None``)."""
    if not is_sensitive(dip):
        return ""
    return (
        f"  (sensitive: |psi_1| dips to {float(dip):.2g} of its maximum inside the flagellum,"
        " where the phase turns fast)"
    )


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
    "MIDDLE",
    "STANDING_PHASE_RAD",
    "along",
    "direction",
    "dynamic_amplitude",
    "finite_or_none",
    "ls_slope",
    "SENSITIVE_DIP",
    "amplitude_dip",
    "is_sensitive",
    "phase_slope",
    "sensitive_note",
    "sampled_wavenumber",
    "trapezoid_weights",
    "unwrapped_phase",
    "weighted_phase_gradient",
    "static_curvature",
    "tip_amplitude",
    "wavelength",
    "wavelength_text",
]
