"""What a simulated trajectory did: decayed, grew, diverged, or settled on a limit cycle.

Decision rules (tip displacement y(t) along the beat direction, cycles from
:func:`axojax.waveform.detect_cycles`):

- ``divergent``: the solver failed or the state stopped being finite, or the tip moved
  away monotonically (fewer than 3 cycles) to more than ``DIVERGE_FACTOR`` times its
  initial distance from the linear equilibrium ``A^{-1} b``;
- ``limit_cycle``: at least 3 cycles and the last two amplitudes agree to ``CYCLE_RTOL``;
- ``growing``: oscillating with amplitudes still rising (run longer, or add stiffening);
- ``decaying``: oscillation amplitudes falling, or no oscillation and no departure:
  the system returns to its equilibrium (straight, or statically bent with imbalance).
"""

from __future__ import annotations

import numpy as np

from ..waveform import Cycles, detect_cycles

CYCLE_RTOL = 0.01
DIVERGE_FACTOR = 10.0
STATES = ("decaying", "limit_cycle", "growing", "divergent")


def classify_trajectory(t: np.ndarray, y: np.ndarray, y_equilibrium: float, ok: bool) -> tuple[str, Cycles | None]:
    """State name (one of ``STATES``) and the detected cycles (None when not finite)."""
    if not ok or not np.all(np.isfinite(y)):
        return "divergent", None
    cycles = detect_cycles(t, y)
    if cycles.count >= 3:
        a1, a2 = cycles.amplitudes[-2], cycles.amplitudes[-1]
        if abs(a2 - a1) <= CYCLE_RTOL * a2:
            return "limit_cycle", cycles
        return ("growing" if a2 > a1 else "decaying"), cycles
    start = abs(y[0] - y_equilibrium)
    end = abs(y[-1] - y_equilibrium)
    if end > DIVERGE_FACTOR * max(start, 1e-12):
        return "divergent", cycles
    return "decaying", cycles
