"""What a simulated trajectory did: decayed, grew, diverged, settled on a limit cycle, is
still settling onto one from above, or could not be computed.

Decision rules (tip displacement y(t) along the beat direction, cycles from
:func:`axojax.waveform.detect_cycles`):

- ``solver_failed``: the solver stopped before the end (diffrax's result is not
  ``successful``: step budget spent, step size collapsed, a stage solve failed). Says
  nothing about the physics: the run carries diffrax's reason and the time reached;
- ``divergent`` (the solver was fine): the state stopped being finite, or the tip moved
  away monotonically (no turning point in the second half of the record) to more than
  ``DIVERGE_FACTOR`` times its initial distance from the linear equilibrium ``y_eq``
  (of ``A^{-1} b``);
- ``limit_cycle``: at least 3 cycles and the last two amplitudes agree to ``CYCLE_RTOL``;
- ``growing``: oscillating with amplitudes still rising (the last two cycles, or with
  fewer than 2 cycles the peak of the second half against the first), or moving away
  from an unstable equilibrium without oscillating, by less than ``DIVERGE_FACTOR``
  (run longer, or add stiffening);
- ``settling``: oscillating with amplitudes falling around a linearly unstable
  equilibrium: the beat overshot and is approaching its limit cycle from above (run
  longer);
- ``decaying``: amplitudes falling around a stable equilibrium, or no oscillation and
  no departure: the system returns to its equilibrium (straight, or statically bent
  with imbalance); also, whatever the linear analysis says, when the tip came to rest:
  over the second half of the record it stays within ``REST_FACTOR`` of the record's
  largest excursion from ``y_eq`` (what is left is round-off, whose wiggles must not be
  read as cycles). The straight state can be linearly unstable and still end at rest: a
  static dynein moment (``b``) bends the filaments to an equilibrium of their own, which
  the cubic links can make stable.
"""

from __future__ import annotations

import numpy as np

from ..waveform import Cycles, detect_cycles

CYCLE_RTOL = 0.01
DIVERGE_FACTOR = 10.0
REST_FACTOR = 1e-6
STATES = ("decaying", "limit_cycle", "growing", "settling", "divergent", "solver_failed")


def classify_trajectory(
    t: np.ndarray, y: np.ndarray, y_equilibrium: float, ok: bool, equilibrium_stable: bool = True
) -> tuple[str, Cycles | None]:
    """State name (one of ``STATES``) and the detected cycles (None when not finite).

    Args:
        t: (T,) times, any unit.
        y: (T,) tip displacement along the beat direction, any unit.
        y_equilibrium: the equilibrium's tip displacement (same unit as y).
        ok: whether the solver reached the end; False gives ``solver_failed``.
        equilibrium_stable: whether the linearised equilibrium is stable (dominant
            growth rate < 0); decides ``decaying`` against ``settling``.
    """
    if not ok:
        return "solver_failed", None
    if not np.all(np.isfinite(y)):
        return "divergent", None
    cycles = detect_cycles(t, y)
    dev = np.asarray(y, dtype=float) - y_equilibrium
    if np.abs(dev[dev.size // 2 :]).max() <= REST_FACTOR * np.abs(dev).max():
        return "decaying", cycles
    if cycles.count >= 2:
        a1, a2 = cycles.amplitudes[-2], cycles.amplitudes[-1]
        if cycles.count >= 3 and abs(a2 - a1) <= CYCLE_RTOL * a2:
            return "limit_cycle", cycles
        if a2 > a1:
            return "growing", cycles
        return ("decaying" if equilibrium_stable else "settling"), cycles
    late = dev[dev.size // 2 :]
    slope = np.diff(late)
    if np.count_nonzero(np.diff(np.sign(slope[slope != 0])) != 0) >= 1:
        # Turning back late: oscillating, but too few cycles to measure; compare the
        # halves' peaks.
        if np.abs(late).max() > np.abs(dev[: dev.size // 2]).max():
            return "growing", cycles
        return ("decaying" if equilibrium_stable else "settling"), cycles
    start = max(abs(dev[0]), 1e-12)
    end = abs(dev[-1])
    if end > DIVERGE_FACTOR * start:
        return "divergent", cycles
    if end > start and not equilibrium_stable:
        return "growing", cycles
    return "decaying", cycles
