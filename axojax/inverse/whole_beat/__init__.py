"""The whole beat: a regulated mechanism fitted to a recording's whole limit cycle
(:mod:`.fit`: :func:`fit_recording`, the linear row's Hopf point first, then
Levenberg-Marquardt through the orbit, :func:`fit_whole_beat`), and the mechanisms ranked on it (:mod:`.compare`:
:func:`compare_whole_beat`).

The top layer of :mod:`axojax.inverse`: it imports the linear comparison (its rows,
statuses, ranking and verdict), and nothing below imports it.
"""

from .compare import WholeBeatComparison, WholeBeatRow, compare_whole_beat
from .fit import (
    WholeBeatFit,
    fit_recording,
    fit_whole_beat,
    linear_hopf,
    motor_time,
    start_values,
)

__all__ = [
    "WholeBeatComparison",
    "WholeBeatFit",
    "WholeBeatRow",
    "compare_whole_beat",
    "fit_recording",
    "fit_whole_beat",
    "linear_hopf",
    "motor_time",
    "start_values",
]
