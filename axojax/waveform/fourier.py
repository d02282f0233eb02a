"""Cycles of a periodic signal and the Fourier modes of a tangent-angle kymograph.

Conventions (Geyer et al. 2016, used in the paper's section 3.7.1): over a whole number
of periods of angular frequency omega, the tangent angle is decomposed as::

    psi(s, t) ~ psi_0(s) + Re(psi_1(s) exp(i omega t))

``psi_0`` is the static mode (time mean), ``psi_1`` the first (complex) Fourier mode.
Their measures (static curvature, dynamic amplitude, wavelength, direction) are those of
:mod:`axojax.waveform.measures`, the one implementation for models and data. Plain numpy:
these analyse finished time series, they are not traced.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import measures


@dataclasses.dataclass(frozen=True)
class Cycles:
    """Cycles of a scalar signal y(t), delimited by its upward crossings of a level.

    Attributes:
        starts: (k + 1,) crossing times (interpolated); cycle i is [starts[i], starts[i+1]].
        periods: (k,) durations.
        amplitudes: (k,) half peak-to-peak of y within each cycle.
        level: the crossing level (median of y over the last half of the record: robust to
            growth and to a static offset).
    """

    starts: np.ndarray
    periods: np.ndarray
    amplitudes: np.ndarray
    level: float

    @property
    def count(self) -> int:
        return int(self.periods.size)


def detect_cycles(t: np.ndarray, y: np.ndarray) -> Cycles:
    """Upward crossings of ``y`` through its late-time median, linearly interpolated.

    Args:
        t: (T,) increasing times.
        y: (T,) signal (e.g. tip displacement along the beat direction).
    """
    t, y = np.asarray(t, dtype=float), np.asarray(y, dtype=float)
    level = float(np.median(y[y.size // 2 :]))
    z = y - level
    up = np.nonzero((z[:-1] < 0) & (z[1:] >= 0))[0]
    starts = t[up] - z[up] * (t[up + 1] - t[up]) / (z[up + 1] - z[up])
    amps = []
    for a, b in zip(up[:-1], up[1:]):
        seg = y[a : b + 2]
        amps.append(measures.tip_amplitude(seg))
    return Cycles(
        starts=starts,
        periods=np.diff(starts),
        amplitudes=np.asarray(amps, dtype=float),
        level=level,
    )


@dataclasses.dataclass(frozen=True)
class FourierModes:
    """Static and first Fourier mode of psi(s, t) over whole periods.

    Attributes:
        s: (S,) arc length (caller's units).
        psi0: (S,) static mode (rad).
        psi1: (S,) complex first mode (rad); psi ~ psi0 + Re(psi1 exp(i omega t)).
        omega: angular frequency used (rad per caller's time unit).
        residual_rms: rms of psi - psi_0 - Re(psi_1 exp(i omega t)) over the window (rad).
        n_samples: time samples in the window.
    """

    s: np.ndarray
    psi0: np.ndarray
    psi1: np.ndarray
    omega: float
    residual_rms: float = 0.0
    n_samples: int = 0

    @property
    def static_curvature(self) -> float:
        """Least-squares slope of psi_0(s) (rad per unit of s)."""
        return float(measures.static_curvature(self.s, self.psi0))

    @property
    def dynamic_amplitude(self) -> float:
        """Arc-length (trapezoidal) mean of |psi_1(s)| (rad)."""
        return float(measures.dynamic_amplitude(self.s, self.psi1))

    @property
    def wavenumber(self) -> float:
        """Least-squares slope of psi_1(s)'s unwrapped phase (rad per unit of s; the
        samples weighted by the trapezoidal rule; negative: travelling towards larger s;
        :func:`axojax.waveform.measures.sampled_wavenumber`)."""
        return float(measures.sampled_wavenumber(self.s, self.psi1))

    @property
    def wavelength(self) -> float:
        """2 pi / |wavenumber| (units of s); inf for a standing wave."""
        return float(measures.wavelength(self.wavenumber, self.s[-1] - self.s[0]))

    @property
    def direction(self) -> int:
        """+1 anterograde (base to tip), -1 retrograde, 0 standing (or omega = 0)."""
        # omega > 0 by construction (a Fourier-mode file may leave it NaN)
        return int(measures.direction(self.wavenumber, 1.0, self.s[-1] - self.s[0]))


def fourier_modes(t: np.ndarray, s: np.ndarray, psi: np.ndarray, period: float) -> FourierModes:
    """psi_0 and psi_1 of ``psi`` (T, S) over the largest whole number of periods that
    ends at ``t[-1]`` (trapezoidal rule on the samples; samples need not be uniform).

    Raises:
        ValueError: when the record is shorter than one period.
    """
    t, psi = np.asarray(t, dtype=float), np.asarray(psi, dtype=float)
    if not period > 0 or t[-1] - t[0] < period:
        raise ValueError(
            f"need at least one period ({period:g}) of data, got a record of {t[-1] - t[0]:g}"
        )
    n = int(np.floor((t[-1] - t[0]) / period + 1e-9))
    t0 = t[-1] - n * period
    keep = t >= t0 - 1e-12 * max(1.0, abs(t0))
    tt, pp = t[keep], psi[keep]
    if tt[0] > t0:  # start exactly at t0 by linear interpolation
        i = np.nonzero(keep)[0][0]
        w = (t0 - t[i - 1]) / (t[i] - t[i - 1])
        tt = np.concatenate([[t0], tt])
        pp = np.concatenate([(1 - w) * psi[i - 1][None] + w * psi[i][None], pp])
    omega = 2 * np.pi / period
    span = tt[-1] - tt[0]
    psi0 = np.trapezoid(pp, tt, axis=0) / span
    psi1 = 2 * np.trapezoid(pp * np.exp(-1j * omega * tt)[:, None], tt, axis=0) / span
    resid = pp - psi0[None] - np.real(psi1[None] * np.exp(1j * omega * tt)[:, None])
    return FourierModes(
        s=np.asarray(s, dtype=float),
        psi0=psi0,
        psi1=psi1,
        omega=omega,
        residual_rms=float(np.sqrt(np.mean(resid**2))),
        n_samples=int(tt.size),
    )
