"""From frames to what a fit matches: tangent angles of 2D/3D centrelines (with the
planarity decision), the beat phase and frequency, the mean rotation, psi_0 and psi_1 per
cycle, and their uncertainties with documented floors. Plain numpy (finished records, not traced).

**Planarity** (3D centrelines): the singular values s1 >= s2 >= s3 of the point cloud of
every frame's points relative to its base (centred) give the long axis, the direction
of largest transverse extent and the out-of-plane direction. The beat is called
planar when ``s3 / s2 < PLANARITY_THRESHOLD`` (0.2): the out-of-plane rms excursion is
under a fifth of the in-plane transverse one, so projecting on the best plane changes
a tangent angle by under ``1 - cos(atan 0.2)`` ~ 2 % (below a measured psi_1's
uncertainty). Planar: psi is the angle of the projected tangent in the best plane (an
in-plane rotation of the axes only shifts psi by a constant, removed with the mean base
angle).

**The beat frame** (non-planar 3D centrelines, :func:`beat_frame`): both transverse
components are reduced, psi_a = atan2(t.e2, t.e1) (``in_plane``) and
psi_b = atan2(t.e3, t.e1) (``out_of_plane``), on a common beat phase, about

- e1: the mean unit tangent of the basal tenth of the flagellum (all frames): the axis
  of a model clamped at its base, from which the model's psi is measured;
- e2: the principal axis of largest variance of the *oscillating* displacement, i.e. of
  ``r(s, t) - mean_t r(s)`` (r relative to the base) projected perpendicular to e1 (all
  points and frames): the direction of the beat's largest transverse motion, as a
  model's beat direction is the principal axis of its mode's centreline displacement
  (:func:`axojax.eigen.metrics.beat_plane`);
- e3 = e1 x e2 (right-handed, so that a model's cross-section directions (y, z) map to
  (e2, e3) by a rotation, never a mirror image).

The point cloud's axes are not used for this. Its long axis is the mean chord, which a
static bend tilts away from the base (14 degrees for the bundled sperm): psi measured
from it carries the tilt and mixes the components. Its second axis is the largest
*extent* of the positions, static shape included, so a static out-of-plane bend can turn
it towards e3; the fit's psi_1 is the oscillation only. A helical beat (circular
transverse motion) has no preferred e2: any choice differs by a rotation phi about e1,
which for a circular wave multiplies both psi_1 by exp(+-i phi) (absorbed by a fit's
complex scale; the wavelengths are unchanged); the nearer to circular, the less
significant e2's orientation (:attr:`Planarity.frame_ratio` reports the square root of
the ratio of the two transverse variances, as a model's ``out_of_plane_ratio`` does).
Between these limits a component's own wavelength depends on e2: the bundled sperm
(ratio 0.70) gives 130 um in-plane and 52 um out-of-plane about the displacement's axis
(the phase slope of docs/model.md section 5; the axis of the oscillating tangent, 27
degrees away, gives other values); the displacement's axis is the model's definition, so
that a fit compares like with like. A record in the lab frame of a rolling
cell (its beat plane turning with the body) must first be brought into a frame fixed to
the cell (the head's orientation, which a centreline alone does not give; the bundled
sperm is in its head-fixed frame): otherwise the roll, at the rolling frequency, mixes
the components.

**Beat phase and frequency**: the spectral peak f0 of the mean-removed angles (summed
over s and components, zero-padded 8x) gives a first psi_1; projecting every frame on the
quadrature pair (Re psi_1, Im psi_1) gives the beat phase theta(t) (all points at once,
robust to noise at any one point; a standing wave, whose pair is degenerate, uses the
analytic signal of its one spatial mode). A cycle ends where theta crosses a multiple of
2 pi. Frequency = 1 / (least-squares slope of the crossing times against the cycle
number), refined twice.

**psi_0 and psi_n** (one definition for data and model, docs/model.md): per whole cycle k,
[t_k, t_k + T_k] between consecutive crossings, the time Fourier coefficients
psi_n = (2 / T_k) int psi(t) exp(-i n omega_k (t - t_k)) dt, omega_k = 2 pi / T_k (psi_0
with 1 / T_k; :func:`cycle_coefficients`: the cubic spline through the frames,
integrated), averaged over the cycles. Every cycle's time origin is its start t_k (the
beat phase at a multiple of 2 pi), one time shift common to all harmonics. A model's
orbit is one exact cycle: its harmonics are these coefficients
(:meth:`axojax.orbits.LimitCycle.tangent_modes`). (Until issue 54 the reduction fitted
psi = a0 + Re(c exp(i theta)) by least squares in the beat phase theta; on a
non-sinusoidal beat, whose theta does not advance uniformly in time, that is not the
time average: static curvature -0.158 against -0.137 rad/um on a real Chlamydomonas
cycle.)

**Mean rotation**: a cell or axoneme that turns slowly in the field of view adds
omega_rot t to psi at every s (Sartori et al. 2016 remove it). omega_rot is the
least-squares slope of each whole cycle's mean angle (averaged along s) against the
cycle's middle time (a periodic beat's cycle means are equal), found on the cycles of the
record as it is, then on those of the record without it, twice; each component's own.
``omega_rot (t - t_m)`` is subtracted before the Fourier analysis, t_m the middle of the
cycles used (psi_0 is the mean angle there). A rotation that turns psi by no more than
``PSI1_FLOOR_RAD`` over the cycles is the angles' noise, not removed (the record then
reduces exactly as one without it); with one cycle nothing is removed.

**Uncertainties** (each never below its floor):

- frequency: the cycle-to-cycle scatter, ``f^2 std(periods) / sqrt(n)``. Floors: the
  timing resolution, ``f^2 (dt / sqrt 6) / n`` (each end of the n counted cycles known to
  a uniform frame, dt / sqrt 12), and ``FREQUENCY_REL_FLOOR`` = 1 % of f: the beat
  frequency of one flagellum wanders by a few percent over seconds, and a camera's frame
  clock (the only time reference) is rarely calibrated better, so no single record pins
  a cell's frequency below 1 %. (A phase-averaged or tiled record has zero scatter: the
  floor then speaks.)
- psi_1(s): per point, the scatter of the per-cycle psi_1 estimates (above),
  ``sqrt((var Re + var Im) / 2 / n)``; with one cycle, the residual of the two-mode
  reconstruction. Floor ``PSI1_FLOOR_RAD`` = 0.01 rad: the angle resolution of tracked
  centrelines (sub-pixel localisation ~0.1 um over the ~10 um on which the smoothed
  tangent is resolved).
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
from scipy.interpolate import CubicSpline

from ..waveform import FourierModes
from .readers import fail

PLANARITY_THRESHOLD = 0.2
FREQUENCY_REL_FLOOR = 0.01
PSI1_FLOOR_RAD = 0.01
N_POINTS = 41
ZERO_PAD = 8


@dataclasses.dataclass(frozen=True)
class Planarity:
    """Planarity of a 3D centreline record, and the frame a non-planar one is reduced in.

    Attributes:
        singular_values: (3,) of the base-relative point cloud, descending (um).
        axes: (3, 3) the point cloud's axes, rows: long axis (base to tip), largest
            transverse extent, their cross product; a planar beat's angles are measured
            in the plane of the first two.
        ratio: s3 / s2 (out-of-plane over in-plane transverse extent).
        planar: ``ratio < threshold``.
        threshold: :data:`PLANARITY_THRESHOLD`.
        frame: (3, 3) rows e1, e2, e3 of the beat frame (:func:`beat_frame`, module
            docstring) a non-planar beat's two components are measured in; ``None`` when
            planar.
        frame_ratio: sqrt of the oscillating displacement's variance along e3 over that
            along e2 (0: one plane of motion, 1: circular); ``None`` when planar.
    """

    singular_values: np.ndarray
    axes: np.ndarray
    ratio: float
    planar: bool
    threshold: float = PLANARITY_THRESHOLD
    frame: np.ndarray | None = None
    frame_ratio: float | None = None

    @property
    def treatment(self) -> str:
        if self.planar:
            return (
                f"planar (s3/s2 = {self.ratio:.3g} < {self.threshold:g}): angles in the best plane"
            )
        ratio = "" if self.frame_ratio is None else f", transverse ratio {self.frame_ratio:.3g}"
        return (
            f"not planar (s3/s2 = {self.ratio:.3g} >= {self.threshold:g}): two transverse"
            " components reduced about the beat frame (e1 the base tangent, e2 the largest"
            f" oscillation{ratio}); wavelength_um is the in-plane one's"
        )

    def as_dict(self) -> dict:
        s = self.singular_values
        return {
            "singular_values_um": [float(v) for v in s],
            "ratios": {
                "s2_over_s1": float(s[1] / s[0]),
                "s3_over_s1": float(s[2] / s[0]),
                "s3_over_s2": float(self.ratio),
            },
            "threshold": self.threshold,
            "planar": bool(self.planar),
            "treatment": self.treatment,
            "frame": None
            if self.frame is None
            else {n: [float(v) for v in e] for n, e in zip(("e1", "e2", "e3"), self.frame)},
            "frame_ratio": None if self.frame_ratio is None else float(self.frame_ratio),
        }


BASE_FRACTION = 0.1
"""Basal fraction of the length whose mean tangent is the beat frame's e1."""


def beat_frame(points: np.ndarray) -> tuple[np.ndarray, float]:
    """The beat frame of ``points`` (T, P, 3), each frame's points from base to tip
    (module docstring): ((3, 3) rows e1, e2, e3; sqrt of the transverse variance ratio
    along e3 over e2). e1: mean unit tangent of the segments in the basal
    :data:`BASE_FRACTION` (at least one); e2: principal axis of largest variance,
    perpendicular to e1, of the base-relative points minus their time mean (sign: its
    largest coordinate positive); e3 = e1 x e2."""
    d = np.diff(points, axis=1)
    t = d / np.linalg.norm(d, axis=-1, keepdims=True)
    n_base = max(1, int(round(BASE_FRACTION * t.shape[1])))
    e1 = t[:, :n_base].mean(axis=(0, 1))
    e1 = e1 / np.linalg.norm(e1)
    rel = points - points[:, :1]
    osc = (rel - rel.mean(axis=0)).reshape(-1, 3)
    osc = osc - np.outer(osc @ e1, e1)
    w, v = np.linalg.eigh(osc.T @ osc)  # ascending; the smallest is ~0 (along e1)
    e2 = v[:, -1] - (v[:, -1] @ e1) * e1
    e2 = e2 / np.linalg.norm(e2)
    e2 = e2 * np.sign(e2[np.argmax(np.abs(e2))])
    ratio = float(np.sqrt(max(w[-2], 0.0) / w[-1])) if w[-1] > 0 else 0.0
    return np.stack([e1, e2, np.cross(e1, e2)]), ratio


def planarity(points: np.ndarray, threshold: float = PLANARITY_THRESHOLD) -> Planarity:
    """Planarity of ``points`` (T, P, 3), each frame's points from base to tip, with the
    beat frame (:func:`beat_frame`) when it is not planar."""
    rel = points - points[:, :1]
    cloud = rel.reshape(-1, 3)
    _, sv, vt = np.linalg.svd(cloud - cloud.mean(axis=0), full_matrices=False)
    e = vt.copy()
    if rel[:, -1].mean(axis=0) @ e[0] < 0:
        e[0] = -e[0]
    e[2] = np.cross(e[0], e[1])
    ratio = float(sv[2] / max(sv[1], 1e-300))
    planar = ratio < threshold
    frame, frame_ratio = (None, None) if planar else beat_frame(points)
    return Planarity(
        singular_values=sv,
        axes=e,
        ratio=ratio,
        planar=planar,
        threshold=threshold,
        frame=frame,
        frame_ratio=frame_ratio,
    )


def _interp_extrapolate(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """``np.interp`` with linear extrapolation from the two end intervals."""
    out = np.interp(x, xp, fp)
    lo, hi = x < xp[0], x > xp[-1]
    out[lo] = fp[0] + (x[lo] - xp[0]) * (fp[1] - fp[0]) / (xp[1] - xp[0])
    out[hi] = fp[-1] + (x[hi] - xp[-1]) * (fp[-1] - fp[-2]) / (xp[-1] - xp[-2])
    return out


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """Per-frame measured length (T,) of ``points`` (T, P, d)."""
    seg = np.linalg.norm(np.diff(points, axis=1), axis=-1)
    return seg.sum(axis=1)


def tangent_angles(
    points: np.ndarray, axes: np.ndarray, length_um: float, path="data", n_points: int = N_POINTS
) -> tuple[np.ndarray, list[np.ndarray]]:
    """Angles of the tangent of ``points`` (T, P, d) in the planes (axes[0], axes[j]),
    j = 1 .. len(axes) - 1, on a uniform arc length in [0, length_um].

    Segment angles belong to segment midpoints; the ends lie half a segment beyond the
    first and last midpoints, so they are extrapolated linearly (holding the end value
    would put the base angle half a segment up). Each frame's arc length is scaled to
    [0, 1] (a fraction of its own measured length). The mean base angle is subtracted.

    Returns:
        s (n_points,) um and one (T, n_points) angle array (rad) per transverse axis.
    """
    if points.ndim != 3 or points.shape[1] < 4:
        fail(
            path,
            f"centreline needs (frames, points >= 4) coordinates, got shape {points.shape[:2]}",
        )
    d = np.diff(points, axis=1)
    seg = np.linalg.norm(d, axis=-1)
    if np.any(seg <= 0):
        fail(path, "centreline has repeated points (zero-length segments)")
    s_mid = (np.cumsum(seg, axis=1) - seg / 2) / seg.sum(axis=1, keepdims=True)
    comp = d @ np.asarray(axes).T  # (T, P-1, k)
    s = np.linspace(0.0, length_um, n_points)
    out = []
    for j in range(1, comp.shape[-1]):
        angle = np.unwrap(np.arctan2(comp[..., j], comp[..., 0]), axis=1)
        psi = np.stack(
            [_interp_extrapolate(s / length_um, s_mid[k], angle[k]) for k in range(points.shape[0])]
        )
        out.append(psi - psi[:, 0].mean())
    return s, out


@dataclasses.dataclass(frozen=True)
class Reduction:
    """Frequency and modes of one or more angle components on a common beat phase.

    Attributes:
        frequency_hz, frequency_sigma_hz: beat frequency and its standard error.
        frequency_scatter_hz: the cycle-to-cycle part of the sigma before the floors.
        cycles: number of whole cycles used.
        periods_s: (cycles,) their durations.
        modes: one :class:`FourierModes` per component (psi_0, psi_1 = means over cycles
            of each cycle's time Fourier coefficients, module docstring).
        psi1_sigma: one (S,) array per component (rad; each of Re and Im).
        psi1_scatter: the same before the floor.
        crossings_s: (cycles + 1,) the times the beat phase crosses a multiple of 2 pi:
            the used cycles' bounds.
        psi1_cycles: one (n, S) array per component: psi_1 of each whole cycle with at
            least 3 frames (the estimates whose mean is psi_1; one phase reference), or
            None with fewer than 2 such cycles (resampled by
            :func:`axojax.inverse.comparison.robustness.cycle_bootstrap`).
        rotation_rad_per_s: one per component: the mean rotation rate removed before
            the Fourier analysis (module docstring).
    """

    frequency_hz: float
    frequency_sigma_hz: float
    frequency_scatter_hz: float
    cycles: int
    periods_s: np.ndarray
    modes: list
    psi1_sigma: list
    psi1_scatter: list
    crossings_s: np.ndarray | None = None
    psi1_cycles: list | None = None
    rotation_rad_per_s: list | None = None


MIN_PERIODS = 1.5
"""Shortest record (beat periods; T frames at interval dt span T dt) a frequency is
measured from: one whole cycle between two crossings of the beat phase fits in it
whatever the phase it starts at."""


def _too_few(source, t: np.ndarray, f: float, whole: int):
    """One line: the record's length in beat periods (``f``: the best estimate so far),
    the whole cycles found, and the frames needed."""
    dt = float(np.mean(np.diff(t)))
    spans = (t[-1] - t[0] + dt) * f  # T frames cover T frame intervals
    need = int(np.ceil(MIN_PERIODS / (f * dt) - 1e-6))
    fail(
        source,
        f"too few frames: {t.size} frames span {spans:.3g} beat periods (at {f:.3g} Hz) and"
        f" hold {whole} whole cycle{'s' if whole != 1 else ''} between crossings of the beat"
        f" phase; need at least {MIN_PERIODS:g} periods and 1 whole cycle: record at least"
        f" {need} frames at this frame rate",
    )


def _spectral_peak(t: np.ndarray, x: np.ndarray) -> float:
    dt = float(np.mean(np.diff(t)))
    n = ZERO_PAD * t.size
    power = (np.abs(np.fft.rfft(x, n=n, axis=0)) ** 2).sum(axis=1)
    freq = np.fft.rfftfreq(n, dt)
    ok = freq >= 1.0 / (t[-1] - t[0])
    if not np.any(ok) or not np.any(power[ok] > 0):
        return float("nan")
    return float(freq[ok][np.argmax(power[ok])])


def _phase(t: np.ndarray, x: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Unwrapped beat phase theta(t): frames x (T, K) projected on Re c, Im c (K,)."""
    m = np.stack([c.real, -c.imag], axis=1)
    sv = np.linalg.svd(m, compute_uv=False)
    if sv[1] > 1e-3 * sv[0]:
        uv = np.linalg.lstsq(m, x.T, rcond=None)[0]
        return np.unwrap(np.arctan2(uv[1], uv[0]))
    from scipy.signal import hilbert  # standing wave: one spatial mode

    u = x @ (np.abs(c) * np.sign(c.real + 1e-300))
    return np.unwrap(np.angle(hilbert(u - u.mean())))


def _crossings(t: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Times where theta first reaches each multiple of 2 pi inside the record (linear
    interpolation between frames; theta may step back a little between frames)."""
    out = []
    for k in np.arange(np.ceil(theta[0] / (2 * np.pi)), np.floor(theta.max() / (2 * np.pi)) + 1):
        level = 2 * np.pi * k
        i = int(np.argmax(theta >= level))
        if i == 0:
            out.append(t[0])
            continue
        w = (level - theta[i - 1]) / (theta[i] - theta[i - 1])
        out.append(t[i - 1] + w * (t[i] - t[i - 1]))
    return np.asarray(out)


FINE = 16
"""Points per frame interval at which a cycle's spline is integrated."""


def _coefficients(spline, dt: float, a: float, b: float, harmonics: int) -> np.ndarray:
    """(harmonics + 1, S) time Fourier coefficients of ``spline`` (psi(t), (S,)) over the
    cycle [a, b] (:func:`cycle_coefficients`); ``dt``: the frame interval."""
    period = b - a
    tt = np.linspace(a, b, max(int(np.ceil(period / dt)) * FINE, 64) + 1)
    kernel = np.exp(-2j * np.pi * np.outer(np.arange(harmonics + 1), tt - a) / period)
    psi = spline(tt)
    out = 2 * np.trapezoid(kernel[:, :, None] * psi[None], tt, axis=1) / period
    out[0] = out[0].real / 2
    # rounding, not signal (a point that does not move): exactly 0, phase 0
    out[np.abs(out) <= 1e-12 * max(float(np.max(np.abs(psi))), 1e-300)] = 0.0
    return out


def cycle_coefficients(
    t: np.ndarray, psi: np.ndarray, a: float, b: float, harmonics: int = 1
) -> np.ndarray:
    """The time Fourier coefficients of one cycle [a, b] of psi (T, S) sampled at t:
    (harmonics + 1, S) complex, row n = (2 / T) int_a^b psi(t) exp(-i n omega (t - a)) dt
    with T = b - a, omega = 2 pi / T (row 0 with 1 / T, real). psi(t) between frames is
    the cubic spline through them (not-a-knot), integrated on :data:`FINE` points per
    frame interval: at 9 frames a cycle (the bundled sperm's) its coefficients are
    within 0.2 % of a two-harmonic wave's, where linear interpolation misses by 2 %."""
    t = np.asarray(t, dtype=float)
    spline = CubicSpline(t, np.asarray(psi, dtype=float), axis=0)
    return _coefficients(spline, float(np.mean(np.diff(t))), a, b, harmonics)


def _cycles_modes(t, psi, bounds) -> tuple[np.ndarray, np.ndarray, float, int]:
    """(psi_0 (n, S), psi_1 (n, S), residual rms, frames) of every whole cycle between
    consecutive ``bounds`` holding at least 3 frames: :func:`cycle_coefficients`; the
    residual is that of psi_0 + Re(psi_1 exp(i omega (t - t_k))) with each cycle's own."""
    spline, dt = CubicSpline(t, psi, axis=0), float(np.mean(np.diff(t)))
    psi0, psi1, resid = [], [], []
    for a, b in itertools.pairwise(bounds):
        w = (t >= a) & (t <= b)
        if w.sum() < 3:
            continue
        c = _coefficients(spline, dt, a, b, 1)
        psi0.append(c[0].real)
        psi1.append(c[1])
        phase = np.exp(2j * np.pi * (t[w] - a) / (b - a))[:, None]
        resid.append(psi[w] - c[0].real - np.real(c[1] * phase))
    r = np.concatenate(resid) if resid else np.zeros((0, psi.shape[1]))
    rms = float(np.sqrt(np.mean(r**2))) if r.size else 0.0
    return np.asarray(psi0), np.asarray(psi1), rms, int(r.shape[0])


def _rotation(t, psi, bounds) -> float:
    """The mean rotation rate (rad per unit of t) of psi (T, S): the least-squares slope
    of each whole cycle's time-mean angle (averaged along s) against the cycle's middle
    time (a periodic beat's cycle means are equal; a rotation omega_rot t adds omega_rot
    times the middle time). 0 with fewer than 2 cycles."""
    if len(bounds) < 3:
        return 0.0
    spline, dt = CubicSpline(t, psi, axis=0), float(np.mean(np.diff(t)))
    means = [
        _coefficients(spline, dt, a, b, 0)[0].real.mean() for a, b in itertools.pairwise(bounds)
    ]
    mids = (np.asarray(bounds[:-1]) + np.asarray(bounds[1:])) / 2
    return float(np.polyfit(mids, means, 1)[0])


def reduce_frames(
    t_s: np.ndarray, s_um: np.ndarray, components: list[np.ndarray], source="data"
) -> Reduction:
    """Frequency, psi_0, psi_1 and their uncertainties of angle components, each (T, S)
    sampled at times ``t_s`` (T,) (module docstring)."""
    t = np.asarray(t_s, dtype=float)
    comps = [np.asarray(c, dtype=float) for c in components]
    too_few = (
        f"too few frames for one beat period ({t.size} frames; need at least {MIN_PERIODS:g}"
        " periods)"
    )
    if t.size < 6:
        fail(source, too_few)
    dt = np.diff(t)
    if np.any(dt <= 0):
        fail(source, "frame times must increase")
    if not any(np.any(c - c.mean(axis=0)) for c in comps):
        fail(source, "the angles do not change: no beat in the record")
    # The mean rotation (module docstring), from the whole cycles of the beat phase found
    # without it, then with it removed, twice.
    rot = [0.0] * len(comps)
    tc, f, n, period = first = _cycle_bounds(t, comps, source)
    for _ in range(2):
        rot = [r + _rotation(t, c - r * t[:, None], tc) for r, c in zip(rot, comps)]
        rot = [r if abs(r) * (tc[-1] - tc[0]) > PSI1_FLOOR_RAD else 0.0 for r in rot]
        turned = [c - r * t[:, None] for c, r in zip(comps, rot)]
        tc, f, n, period = _cycle_bounds(t, turned, source) if any(rot) else first
    if t[-1] - t[0] + float(np.mean(dt)) < MIN_PERIODS * period * (1 - 1e-9):
        _too_few(source, t, f, n)
    periods = np.diff(tc)
    scatter = f**2 * float(periods.std(ddof=1)) / np.sqrt(n) if n > 1 else 0.0
    resolution = f**2 * float(np.mean(dt)) / np.sqrt(6.0) / n
    sigma_f = max(scatter, resolution, FREQUENCY_REL_FLOOR * f)
    middle = (tc[0] + tc[-1]) / 2  # psi_0 is the mean angle at the used cycles' middle
    modes, sigmas, scatters, cycles = [], [], [], []
    for comp, r in zip(comps, rot):
        psi0s, psi1s, rms, frames = _cycles_modes(t, comp - r * (t - middle)[:, None], tc)
        if len(psi1s) >= 2:
            spread = np.sqrt(
                (psi1s.real.var(axis=0, ddof=1) + psi1s.imag.var(axis=0, ddof=1)) / 2 / len(psi1s)
            )
            cycles.append(psi1s)
        else:
            cycles.append(None)
            spread = np.full(psi1s.shape[1], rms * np.sqrt(2.0 / max(frames, 1)))
        modes.append(
            FourierModes(
                s=np.asarray(s_um, dtype=float),
                psi0=psi0s.mean(axis=0),
                psi1=psi1s.mean(axis=0),
                omega=2 * np.pi * f,
                residual_rms=rms,
                n_samples=frames,
            )
        )
        scatters.append(spread)
        sigmas.append(np.maximum(spread, PSI1_FLOOR_RAD))
    return Reduction(
        frequency_hz=f,
        frequency_sigma_hz=sigma_f,
        frequency_scatter_hz=scatter,
        cycles=n,
        periods_s=periods,
        modes=modes,
        psi1_sigma=sigmas,
        psi1_scatter=scatters,
        crossings_s=tc,
        psi1_cycles=cycles,
        rotation_rad_per_s=rot,
    )


def _cycle_bounds(t, comps, source) -> tuple[np.ndarray, float, int, float]:
    """(the crossings of the beat phase (n + 1,), frequency, n, period) of the angle
    components (each (T, S)): spectral peak -> phase -> crossing-time regression, twice
    refined (module docstring)."""
    x = np.concatenate([c - c.mean(axis=0) for c in comps], axis=1)
    f = _spectral_peak(t, x)
    if not np.isfinite(f):
        fail(
            source,
            f"too few frames for one beat period ({t.size} frames; need at least "
            f"{MIN_PERIODS:g} periods)",
        )
    for _ in range(3):
        c = 2 * np.mean(x * np.exp(-2j * np.pi * f * t)[:, None], axis=0)
        theta = _phase(t, x, c)
        if theta[-1] < theta[0]:
            theta = -theta
        tc = _crossings(t, theta)
        if tc.size < 2:  # the phase's mean rate: better than a short record's spectrum
            _too_few(source, t, float(np.polyfit(t, theta, 1)[0]) / (2 * np.pi), 0)
        n = tc.size - 1
        period = float(np.polyfit(np.arange(tc.size), tc, 1)[0]) if n > 1 else float(tc[1] - tc[0])
        f = 1.0 / period
    return tc, f, n, period
