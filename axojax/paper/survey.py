"""Map rows of the paper table: wavelength, velocity and direction over a (p, k_s) map.

The paper's figure 11 states ranges over a map of the seven-filament model whose grid it
does not give; axojax evaluates :data:`MAP_P` x :data:`MAP_KS` at k_s / k_l =
:data:`MAP_RATIO` with :func:`axojax.sweep` (N_e = 10). The same map gives the frequency
along k_s at the forces of figure 7e-h, whose k_s the paper does not state either.
"""

from __future__ import annotations

import functools
from typing import Sequence

import numpy as np

from ..params import Params
from ..sweeps import SweepResult, sweep
from .claims import Claim, Row
from .modes import preset_model
from .table import sci

MAP_P = np.array([100.0, 150.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0, 900.0, 1000.0])
"""Forces of the map (figure 7e-h's 150, 200, 400, 800 among them)."""
MAP_KS = np.logspace(2, 7, 11)
"""Spoke stiffnesses of the map, half a decade apart."""
MAP_RATIO = 1e3
"""k_s / k_l on the map (figure 8d's ratio)."""


@functools.lru_cache(maxsize=None)
def map_sweep() -> SweepResult:
    """The seven-filament map (p along axis 0, k_s along axis 1), computed once."""
    return sweep(
        preset_model("seven"),
        Params(),
        {"p": MAP_P, "ks": MAP_KS},
        kl_ratio=MAP_RATIO,
        progress=False,
    )


def ks_scan(p: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(k_s, frequency_hz, flutter) along the map's row at force ``p`` (one of :data:`MAP_P`)."""
    i = int(np.flatnonzero(MAP_P == p)[0]) if np.any(MAP_P == p) else None
    if i is None:
        raise ValueError(f"p = {p:g} is not on the map (p = {', '.join(f'{x:g}' for x in MAP_P)})")
    r = map_sweep()
    return MAP_KS, r.data["frequency_hz"][i], r.data["classification"][i] == 1


def _where(r: SweepResult, values: np.ndarray, flat: int | np.integer) -> str:
    i, j = np.unravel_index(flat, values.shape)
    return f"(p, k_s) = ({r.coords['p'][i]:g}, {sci(r.coords['ks'][j])})"


def survey_rows(claims: Sequence[Claim]) -> list[Row]:
    """Rows for the ``kind == "survey"`` claims (flutter points of :func:`map_sweep`)."""
    r = map_sweep()
    flutter = r.data["classification"] == 1
    grid = (
        f"here {r.meta['model']}, p = {MAP_P[0]:g}..{MAP_P[-1]:g} x k_s = "
        f"{sci(MAP_KS[0])}..{sci(MAP_KS[-1])} ({MAP_P.size} x {MAP_KS.size}, k_s/k_l = "
        f"{sci(MAP_RATIO)}), {flutter.sum()} flutter points"
    )
    rows = []
    for c in claims:
        if c.kind != "survey":
            continue
        note = [c.unstated, grid]
        if c.quantity == "anterograde_fraction":
            ante = int(np.sum(flutter & (r.data["direction"] == 1)))
            value, shown = (
                ante / max(int(flutter.sum()), 1),
                f"{ante} of {flutter.sum()} flutter points",
            )
        else:
            data = np.where(flutter, r.data[c.quantity], np.nan)
            lo, hi = np.nanargmin(data), np.nanargmax(data)
            value = (float(data.flat[lo]), float(data.flat[hi]))
            digits = 1 if c.unit == "um" else 0
            shown = f"{value[0]:.{digits}f}-{value[1]:.{digits}f} {c.unit}"
            note.append(f"lowest at {_where(r, data, lo)}, highest at {_where(r, data, hi)}")
            if c.quantity == "wavelength_um":
                note.append(
                    "the wavelength grows towards the Hopf boundary, so the range depends on "
                    "how near the grid comes to it"
                )
            if c.quantity == "velocity_um_per_s":
                f = r.data["frequency_hz"][flutter]
                note.append(
                    "velocity = wavelength x frequency, and the map's frequencies span "
                    f"{f.min():.0f}-{f.max():.0f} Hz (fig. 7 rows for the paper's)"
                )
        rows.append(Row(c, value, shown, None, "; ".join(note)))
    return rows
