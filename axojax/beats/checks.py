"""Values no flagellum has, refused with the likely unit mistake (one line naming the
file, :func:`axojax.beats.readers.fail`): a length outside :data:`FLAGELLUM_LENGTH_UM`,
tangent angles that look like degrees, angles that are not finite radians."""

from __future__ import annotations

import numpy as np

from ..waveform import FourierModes
from .readers import fail

FLAGELLUM_LENGTH_UM = (1.0, 500.0)
"""Lengths (um) a flagellum or cilium has, with a wide margin (the shortest motile cilia
are a few um, the longest sperm flagella a few hundred): a length or an arc-length range
outside is a unit mistake (mm, nm, pixels), an error."""


def _unit_guess(value_um: float) -> str:
    """What a length of ``value_um`` outside :data:`FLAGELLUM_LENGTH_UM` more likely is."""
    return "mm" if value_um < FLAGELLUM_LENGTH_UM[0] else "pixels or nm"


def check_length(source, what: str, value_um: float, names: str) -> None:
    """Refuse a length ``value_um`` (``what``: how it was found) outside
    :data:`FLAGELLUM_LENGTH_UM`, naming the likely unit (``names``: the quantity)."""
    lo, hi = FLAGELLUM_LENGTH_UM
    if not lo <= value_um <= hi:
        fail(
            source,
            f"{what} {value_um:.3g} um: {names} like {_unit_guess(value_um)}? axojax expects"
            f" um (a flagellum is {lo:g} to {hi:g} um long)",
        )


DEGREES = "psi looks like degrees? axojax expects radians (multiply by pi/180)"


def check_degrees(source, modes: FourierModes, psi=None, t=None, bounds=None) -> None:
    """Refuse tangent angles that are more likely degrees than radians: a dynamic amplitude
    (mean |psi_1|) above pi, |psi_1| above pi anywhere (a swing of more than 2 pi over a
    period), or frames ``psi`` (T, S) at times ``t`` whose range at some point within a
    beat period (median over the cycles ``bounds``) exceeds 2 pi."""
    amplitude = float(modes.dynamic_amplitude)
    if amplitude > np.pi:
        fail(source, f"dynamic amplitude {amplitude:.3g} rad (above pi): {DEGREES}")
    peak = float(np.max(np.abs(modes.psi1)))
    if peak > np.pi:
        fail(
            source,
            f"|psi_1| reaches {peak:.3g} rad (a swing of {2 * peak:.3g} rad over a period,"
            f" above 2 pi): {DEGREES}",
        )
    if psi is None or bounds is None or len(bounds) < 2:
        return
    swings = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        w = (t >= a) & (t <= b)
        if w.sum() >= 2:
            swings.append(float(np.max(psi[w].max(axis=0) - psi[w].min(axis=0))))
    swing = float(np.median(swings)) if swings else 0.0
    if swing > 2 * np.pi:
        fail(source, f"psi swings {swing:.3g} rad within a beat period (above 2 pi): {DEGREES}")


MAX_PSI_RAD = 100.0
"""Largest |tangent angle| (rad) accepted in a beat: unwrapped angles of a real beat stay
within a few turns, so anything larger is not an angle in radians (degrees, pixels or an
overflow), and would overflow the reduction."""


def check_angles(source, name: str, psi: np.ndarray) -> None:
    """Refuse tangent angles ``psi`` (any shape, rad) that are not finite radians with
    ``|psi| <= MAX_PSI_RAD``: one line naming ``source`` and ``name``."""
    peak = float(np.max(np.abs(psi))) if np.size(psi) else 0.0
    if not (np.isfinite(peak) and peak <= MAX_PSI_RAD):
        hint = f": {DEGREES}" if np.isfinite(peak) and peak <= np.degrees(MAX_PSI_RAD) else ""
        fail(
            source,
            f"{name}: tangent angles must be radians with |psi| <= {MAX_PSI_RAD:g}, got "
            f"{peak:.3g}{hint}",
        )
