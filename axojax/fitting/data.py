"""Observed beats: read a tangent-angle kymograph psi(s, t) or centreline coordinates per
frame, and extract the beat frequency, the static mode psi_0(s) and the first Fourier
mode psi_1(s) (:func:`axojax.waveform.fourier_modes`).

Accepted files (``frame_rate_hz`` and ``length_um`` are required in each):

- ``.npz`` kymograph: ``psi`` (frames, S) in rad, optional ``s_um`` (S,);
- ``.npz`` centreline: ``x_um`` and ``y_um`` (frames, P), points from base to tip;
- ``.csv``: header comment lines ``# frame_rate_hz = 100`` and ``# length_um = 12``,
  then a header row and rows of either ``frame,s_um,psi_rad`` (kymograph) or
  ``frame,x_um,y_um`` (centreline points, base to tip, in order).

Every problem (missing field or column, NaN, fewer frames than one beat period) is a
one-line ``ValueError`` naming the file and the problem.
"""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np

from ..waveform import FourierModes, detect_cycles, fourier_modes
from .targets import ShapeTarget, Target

N_POINTS = 41


@dataclasses.dataclass(frozen=True)
class BeatData:
    """A beat reduced to what a fit uses.

    Attributes:
        t_s: (T,) frame times; s_um: (S,) arc length; psi_rad: (T, S) tangent angle.
        frequency_hz, frequency_sigma_hz: beat frequency and its standard error.
        modes: psi_0 and psi_1 over whole periods.
        psi1_sigma: standard error of Re and Im of psi_1(s) (rad), from the residual of
            the two-mode reconstruction.
    """

    t_s: np.ndarray
    s_um: np.ndarray
    psi_rad: np.ndarray
    frequency_hz: float
    frequency_sigma_hz: float
    modes: FourierModes
    psi1_sigma: float

    def targets(self) -> tuple[list[Target], ShapeTarget]:
        """Frequency target and the psi_1 shape target."""
        return [Target("frequency_hz", self.frequency_hz, self.frequency_sigma_hz)], ShapeTarget(self.s_um, self.modes.psi1, self.psi1_sigma)

    @property
    def static_curvature_rad_per_um(self) -> float:
        return self.modes.static_curvature


def _fail(path, problem: str):
    raise ValueError(f"{path}: {problem}")


def _interp_extrapolate(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """``np.interp`` with linear extrapolation from the two end intervals."""
    out = np.interp(x, xp, fp)
    lo, hi = x < xp[0], x > xp[-1]
    out[lo] = fp[0] + (x[lo] - xp[0]) * (fp[1] - fp[0]) / (xp[1] - xp[0])
    out[hi] = fp[-1] + (x[hi] - xp[-1]) * (fp[-1] - fp[-2]) / (xp[-1] - xp[-2])
    return out


def _tangent_angle(x: np.ndarray, y: np.ndarray, length_um: float, path) -> tuple[np.ndarray, np.ndarray]:
    """Centreline points (T, P) -> psi (T, N_POINTS) on a uniform arc length in [0, L]."""
    if x.shape != y.shape or x.ndim != 2 or x.shape[1] < 4:
        _fail(path, f"centreline needs x_um and y_um of equal shape (frames, points >= 4), got {x.shape} and {y.shape}")
    dx, dy = np.diff(x, axis=1), np.diff(y, axis=1)
    seg = np.hypot(dx, dy)
    if np.any(seg <= 0):
        _fail(path, "centreline has repeated points (zero-length segments)")
    s_mid = np.cumsum(seg, axis=1) - seg / 2
    angle = np.unwrap(np.arctan2(dy, dx), axis=1)
    s = np.linspace(0.0, length_um, N_POINTS)
    # Segment angles belong to segment midpoints; the ends (s = 0 and L) lie half a
    # segment beyond the first and last midpoints, so extrapolate linearly there
    # (holding the end value instead would put the base angle half a segment up).
    # Each frame's arc length is scaled to [0, 1] (a fraction of its own measured length).
    total = seg.sum(axis=1)
    psi = np.stack([_interp_extrapolate(s / length_um, s_mid[k] / total[k], angle[k]) for k in range(x.shape[0])])
    base = psi[:, 0].mean()
    return s, psi - base


def _read_csv(path: pathlib.Path) -> dict:
    meta, lines = {}, path.read_text().splitlines()
    for line in lines:
        if line.startswith("#") and "=" in line:
            k, v = line[1:].split("=", 1)
            meta[k.strip()] = v.strip()
    body = [ln for ln in lines if ln.strip() and not ln.startswith("#")]
    if not body:
        _fail(path, "no data rows")
    cols = [c.strip() for c in body[0].split(",")]
    try:
        table = np.array([[float(v) for v in ln.split(",")] for ln in body[1:]])
    except ValueError:
        _fail(path, "non-numeric value in the data rows")
    if table.ndim != 2 or table.shape[1] != len(cols):
        _fail(path, f"rows do not match the header {cols}")
    out = {k: meta[k] for k in ("frame_rate_hz", "length_um") if k in meta}
    col = dict(zip(cols, table.T))
    if "frame" not in col:
        _fail(path, f"missing column 'frame' (header: {','.join(cols)})")
    frames = col["frame"].astype(int)
    nf = len(np.unique(frames))
    for kind, names in (("kymograph", ("s_um", "psi_rad")), ("centreline", ("x_um", "y_um"))):
        if all(n in col for n in names):
            shape = (nf, len(frames) // max(nf, 1))
            if shape[0] * shape[1] != len(frames):
                _fail(path, "every frame must have the same number of rows")
            order = np.argsort(frames, kind="stable")
            a, b = (col[n][order].reshape(shape) for n in names)
            if kind == "kymograph":
                out.update(psi=b, s_um=a[0])
            else:
                out.update(x_um=a, y_um=b)
            return out
    _fail(path, f"missing columns: need frame,s_um,psi_rad or frame,x_um,y_um (header: {','.join(cols)})")


def read_beat(path: str | pathlib.Path) -> BeatData:
    """Read a beat file (formats in the module docstring) and extract its modes."""
    path = pathlib.Path(path)
    if not path.is_file():
        _fail(path, "file does not exist")
    if path.suffix == ".npz":
        try:
            with np.load(path, allow_pickle=False) as f:
                raw = {k: f[k] for k in f.files}
        except (OSError, ValueError) as err:
            _fail(path, f"cannot read as .npz ({err})")
    elif path.suffix == ".csv":
        raw = _read_csv(path)
    else:
        _fail(path, f"unknown format {path.suffix!r}: use .npz or .csv")
    for key in ("frame_rate_hz", "length_um"):
        if key not in raw:
            _fail(path, f"missing {key}")
        try:
            value = float(raw[key])
        except (TypeError, ValueError):
            _fail(path, f"{key} must be a number, got {raw[key]!r}")
        if not (np.isfinite(value) and value > 0):
            _fail(path, f"{key} must be > 0, got {value!r}")
        raw[key] = value
    if "psi" in raw:
        psi = np.asarray(raw["psi"], dtype=float)
        if psi.ndim != 2:
            _fail(path, f"psi must be (frames, points), got shape {psi.shape}")
        s = np.asarray(raw.get("s_um", np.linspace(0, raw["length_um"], psi.shape[1])), dtype=float)
        if not np.all(np.isfinite(psi)) or not np.all(np.isfinite(s)):
            _fail(path, "psi contains NaN or infinite values")
    elif "x_um" in raw and "y_um" in raw:
        x, y = np.asarray(raw["x_um"], dtype=float), np.asarray(raw["y_um"], dtype=float)
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
            _fail(path, "centreline contains NaN or infinite values")
        s, psi = _tangent_angle(x, y, raw["length_um"], path)
    else:
        _fail(path, "missing data: need psi (kymograph) or x_um and y_um (centreline)")
    t = np.arange(psi.shape[0]) / raw["frame_rate_hz"]
    return beat_from_kymograph(t, s, psi, source=str(path))


def beat_from_kymograph(t_s: np.ndarray, s_um: np.ndarray, psi_rad: np.ndarray, source: str = "data") -> BeatData:
    """Frequency, psi_0 and psi_1 of a kymograph psi (T, S) sampled at times t_s."""
    var = psi_rad.var(axis=0)
    cycles = detect_cycles(t_s, psi_rad[:, int(np.argmax(var))])
    if cycles.count < 1 or t_s[-1] - t_s[0] < 1.5 * cycles.periods.mean():
        _fail(source, f"too few frames for one beat period ({len(t_s)} frames, {cycles.count} full cycles found; need at least 1.5 periods)")
    period = float(cycles.periods.mean())
    frame = float(t_s[1] - t_s[0])
    # Standard error of the mean period; floor: a tenth of a frame over the whole record.
    sigma_T = max(float(cycles.periods.std(ddof=1)) / np.sqrt(cycles.count) if cycles.count > 1 else 0.0, 0.1 * frame / cycles.count)
    modes = fourier_modes(t_s, s_um, psi_rad, period)
    sigma_psi1 = max(modes.residual_rms * np.sqrt(2.0 / modes.n_samples), 1e-6)
    f = 1.0 / period
    return BeatData(t_s=t_s, s_um=np.asarray(s_um, dtype=float), psi_rad=psi_rad, frequency_hz=f, frequency_sigma_hz=f * sigma_T / period, modes=modes, psi1_sigma=sigma_psi1)
