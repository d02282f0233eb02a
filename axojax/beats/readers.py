"""Beat files as labs publish them, read into plain arrays (no analysis here).

Four kinds of content, in ``.csv``, ``.npz`` or MATLAB ``.mat`` files:

- **kymograph**: tangent angle ``psi`` (frames, S) in rad, optional ``s_um`` (S,);
- **2D centreline**: ``x_um``, ``y_um`` (frames, points), points from base to tip;
- **3D centreline**: ``x_um``, ``y_um``, ``z_um`` (frames, points);
- **Fourier modes** (the summary many papers publish instead of frames): ``s_um``,
  ``psi0_rad``, ``psi1_re_rad``, ``psi1_im_rad`` (S,), with the convention
  psi(s, t) = psi0(s) + Re(psi1(s) exp(i omega t)); optional ``psi1_sigma_rad`` (S,).

Scalars: ``frame_rate_hz`` (frames only), ``length_um``, ``frequency_hz``,
``frequency_sigma_hz`` (Fourier modes only), each optional in the file (what is missing may
come from the caller: :func:`axojax.beats.read_beat`).

``.csv``: header comment lines ``# name = value`` for the scalars, then a header row and
rows of ``frame,s_um,psi_rad`` (kymograph), ``frame,x_um,y_um[,z_um]`` (centreline points,
base to tip, in order) or ``s_um,psi0_rad,psi1_re_rad,psi1_im_rad[,psi1_sigma_rad]``
(Fourier modes, one row per point). ``frame`` is an integer frame number: a frame's time
is ``frame / frame_rate_hz``, so frames may start anywhere and missing frames (rows
deleted) keep the others' timing. A header key that is not one of :data:`SCALARS` is
reported in :attr:`RawBeat.warnings` (a misspelt or mis-unitted key such as
``length_mm`` would otherwise be ignored); a comment line without ``=`` is free text.

``.npz``: the array names above. ``.mat`` (``scipy.io.loadmat``, MATLAB v5-v7.2 files):
the same names, or ``X``, ``Y``[, ``Z``] stored MATLAB-style as (points, frames), one
column per frame; any variable may be a cell array, of which one cell is read (``cell``,
0-based; by default the only non-empty one). ``variables`` renames: e.g.
``{"x_um": "xs", "y_um": "ys"}`` reads the file's ``xs`` as ``x_um``.
"""

from __future__ import annotations

import dataclasses
import pathlib
import zipfile

import numpy as np

SCALARS = (
    "frame_rate_hz",
    "length_um",
    "frequency_hz",
    "frequency_sigma_hz",
    "published_frequency_hz",
)
ARRAYS = (
    "psi",
    "s_um",
    "x_um",
    "y_um",
    "z_um",
    "psi0_rad",
    "psi1_re_rad",
    "psi1_im_rad",
    "psi1_sigma_rad",
)
FOURIER = ("s_um", "psi0_rad", "psi1_re_rad", "psi1_im_rad")
VECTORS = (
    "s_um",
    "psi0_rad",
    "psi1_re_rad",
    "psi1_im_rad",
    "psi1_sigma_rad",
)  # MATLAB stores them (1, n)
MATLAB_XYZ = {"X": "x_um", "Y": "y_um", "Z": "z_um"}  # (points, frames) in the file


COLUMNS = (
    "frame,s_um,psi_rad (kymograph), frame,x_um,y_um[,z_um] (centreline) or"
    " s_um,psi0_rad,psi1_re_rad,psi1_im_rad[,psi1_sigma_rad] (Fourier modes)"
)
"""The CSV header rows a beat file may have, in words (for messages)."""
SHOWN = 5
"""How many frames (or rows) a message about bad rows lists before '...'."""


class BeatFileError(ValueError):
    """A beat file that cannot be read: the message is one line naming the file."""


def fail(path, problem: str):
    raise BeatFileError(f"{path}: {problem}")


@dataclasses.dataclass(frozen=True)
class RawBeat:
    """What a file holds, before any analysis.

    Attributes:
        kind: ``"kymograph"``, ``"centreline-2d"``, ``"centreline-3d"`` or ``"fourier"``.
        arrays: name -> array (names of the module docstring; frames first).
        scalars: name -> float, those present in the file.
        path: the file.
        frames: (T,) the frame numbers of a CSV file's frames (times ``frames /
            frame_rate_hz``), else ``None`` (frames ``0, 1, ...``).
        warnings: one line each, about what the file holds that axojax does not read
            (unknown header keys).
    """

    kind: str
    arrays: dict
    scalars: dict
    path: str
    frames: np.ndarray | None = None
    warnings: tuple = ()


def _kind(arrays: dict, path) -> str:
    if all(k in arrays for k in FOURIER[1:]):
        return "fourier"
    if "psi" in arrays:
        return "kymograph"
    if "x_um" in arrays and "y_um" in arrays:
        return "centreline-3d" if "z_um" in arrays else "centreline-2d"
    have = ", ".join(sorted(arrays)) or "nothing"
    fail(
        path,
        "missing data: need psi (kymograph), x_um and y_um[, z_um] (centreline) or "
        f"s_um,psi0_rad,psi1_re_rad,psi1_im_rad (Fourier modes); found {have}",
    )


def _scalar(path, name: str, value) -> float:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        fail(path, f"{name} must be a number, got {value!r}")
    if v.size != 1:
        fail(path, f"{name} must be one number, got shape {v.shape}")
    v = float(v.reshape(()))
    if not (np.isfinite(v) and v > 0):
        fail(path, f"{name} must be a finite number > 0, got {v!r}")
    return v


def listed(values, shown: int = SHOWN) -> str:
    """``values`` as "a, b, c, ..." (the first ``shown``)."""
    values = [str(v) for v in values]
    return ", ".join(values[:shown]) + (", ..." if len(values) > shown else "")


def _not_finite(path, name: str, a: np.ndarray, frames: bool):
    """One line for ``a`` with NaN or infinite values: which frames (rows of a frames-first
    array) or points, and how to be rid of them."""
    if frames and a.ndim == 2:
        bad = np.flatnonzero(~np.all(np.isfinite(a), axis=1))
        fail(
            path,
            f"{name} has NaN or infinite values in {bad.size} of {a.shape[0]} frames (0-based:"
            f" {listed(bad)}): keep a stretch of frames without them, or fill them (e.g."
            " interpolate in time); a CSV file may instead drop those frames' rows",
        )
    bad = np.flatnonzero(~np.isfinite(np.ravel(a)))
    fail(
        path,
        f"{name} has NaN or infinite values at {bad.size} of {a.size} entries (0-based:"
        f" {listed(bad)}): remove or fill them",
    )


FRAMES_FIRST = ("psi", "x_um", "y_um", "z_um")


def _finish(path, arrays: dict, scalars: dict, frames=None, warnings=()) -> RawBeat:
    kind = _kind(arrays, path)
    out = {}
    for k, a in arrays.items():
        if np.iscomplexobj(a):
            fail(path, f"{k} is complex; give real values")
        try:
            a = np.asarray(a, dtype=float)
        except (TypeError, ValueError):
            fail(path, f"{k} is not numeric")
        if a.size == 0:
            fail(path, f"{k} is empty (shape {a.shape})")
        if not np.all(np.isfinite(a)):
            _not_finite(path, k, a, k in FRAMES_FIRST)
        out[k] = a
    return RawBeat(
        kind=kind,
        arrays=out,
        scalars={k: _scalar(path, k, v) for k, v in scalars.items()},
        path=str(path),
        frames=frames,
        warnings=tuple(warnings),
    )


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _unknown_keys(meta: dict) -> list[str]:
    """One warning line per header key axojax does not read (free-text comments, with no
    identifier before their ``=``, are not keys)."""
    unknown = [k for k in meta if k not in SCALARS and k.isidentifier()]
    if not unknown:
        return []
    return [
        f"unknown header key(s) {', '.join(unknown)} ignored (known: {', '.join(SCALARS)});"
        " lengths are in um, angles in rad (e.g. '# length_um = 30')"
    ]


def _bad_rows(path, cols: list[str], table: np.ndarray):
    """One line for CSV rows with NaN or infinite values: which frames (or rows), and how
    to drop them."""
    bad = np.flatnonzero(~np.all(np.isfinite(table), axis=1))
    names = ", ".join(c for c in cols if not np.all(np.isfinite(table[:, cols.index(c)])))
    if "frame" in cols:
        frame = table[bad, cols.index("frame")]
        if np.all(np.isfinite(frame)):
            which = sorted({int(f) if f == int(f) else float(f) for f in frame})
            fail(
                path,
                f"NaN or infinite {names} in {bad.size} rows of {len(which)} frames"
                f" ({listed(which)}): delete those frames' rows (each frame's time is frame /"
                " frame_rate_hz, so the others keep theirs) or fill the values",
            )
    fail(
        path,
        f"NaN or infinite {names} in {bad.size} data rows ({listed(bad + 1)}, counting"
        " from the first row after the header): delete or fill those rows",
    )


def read_csv(path: pathlib.Path) -> RawBeat:
    try:
        lines = path.read_text().splitlines()
    except (OSError, UnicodeDecodeError) as err:
        fail(path, f"cannot read as text ({err})")
    meta = {}
    for line in lines:
        if line.startswith("#") and "=" in line:
            k, v = line[1:].split("=", 1)
            meta[k.strip()] = v.strip()
    warnings = _unknown_keys(meta)
    body = [ln for ln in lines if ln.strip() and not ln.startswith("#")]
    if not body:
        fail(path, "no data rows")
    cols = [c.strip() for c in body[0].split(",")]
    if all(_is_number(c) for c in cols):
        fail(
            path,
            f"no header row: the first row after the '# key = value' lines must name the"
            f" columns, {COLUMNS}; found {','.join(cols)}",
        )
    repeated = sorted({c for c in cols if cols.count(c) > 1})
    if repeated:
        fail(path, f"column(s) {', '.join(repeated)} appear more than once in the header")
    try:
        table = np.array([[float(v) for v in ln.split(",")] for ln in body[1:]])
    except ValueError:
        fail(path, "non-numeric value in the data rows")
    if table.ndim != 2 or table.shape[0] == 0 or table.shape[1] != len(cols):
        fail(path, f"rows do not match the header {cols}")
    if not np.all(np.isfinite(table)):
        _bad_rows(path, cols, table)
    scalars = {k: meta[k] for k in SCALARS if k in meta}
    col = dict(zip(cols, table.T))
    if all(n in col for n in FOURIER):
        return _finish(
            path,
            {k: col[k] for k in FOURIER + ("psi1_sigma_rad",) if k in col},
            scalars,
            warnings=warnings,
        )
    if "frame" not in col:
        fail(
            path,
            f"missing column 'frame' (header: {','.join(cols)}); a Fourier-mode file needs {','.join(FOURIER)}",
        )
    if np.any(col["frame"] != np.round(col["frame"])):
        fail(path, "frame must be whole frame numbers (a frame's time is frame / frame_rate_hz)")
    frames = col["frame"].astype(int)
    numbers = np.unique(frames)
    nf = numbers.size
    for names in (("s_um", "psi_rad"), ("x_um", "y_um", "z_um"), ("x_um", "y_um")):
        if all(n in col for n in names):
            shape = (nf, len(frames) // max(nf, 1))
            if shape[0] * shape[1] != len(frames):
                fail(path, "every frame must have the same number of rows")
            order = np.argsort(frames, kind="stable")
            a = {n: col[n][order].reshape(shape) for n in names}
            if "psi_rad" in a:
                if np.any(np.abs(a["s_um"] - a["s_um"][:1]) > 1e-9 * np.abs(a["s_um"]).max()):
                    fail(path, "every frame must have the same s_um values, in the same order")
                a = {"psi": a["psi_rad"], "s_um": a["s_um"][0]}
            return _finish(path, a, scalars, frames=numbers, warnings=warnings)
    fail(
        path,
        "missing columns: need frame,s_um,psi_rad or frame,x_um,y_um[,z_um] or "
        f"{','.join(FOURIER)} (header: {','.join(cols)})",
    )


def read_npz(path: pathlib.Path, variables: dict | None = None) -> RawBeat:
    try:
        with np.load(path, allow_pickle=False) as f:
            raw = {k: f[k] for k in f.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as err:
        fail(path, f"cannot read as .npz ({err})")
    return _split(path, _rename(path, raw, variables))


def _rename(path, raw: dict, variables: dict | None) -> dict:
    if not variables:
        return raw
    out = dict(raw)
    for ours, theirs in variables.items():
        if ours not in ARRAYS + SCALARS:
            fail(path, f"unknown variable name {ours!r} (known: {', '.join(ARRAYS + SCALARS)})")
        if theirs not in raw:
            fail(
                path,
                f"variable {theirs!r} (for {ours}) not in the file (it has {', '.join(sorted(raw))})",
            )
        out[ours] = raw[theirs]
    return out


def _split(path, raw: dict) -> RawBeat:
    arrays = {k: raw[k] for k in ARRAYS if k in raw}
    scalars = {k: raw[k] for k in SCALARS if k in raw}
    return _finish(path, arrays, scalars)


def read_mat(path: pathlib.Path, variables: dict | None = None, cell: int | None = None) -> RawBeat:
    import scipy.io

    try:
        raw = {k: v for k, v in scipy.io.loadmat(path).items() if not k.startswith("__")}
    except NotImplementedError:
        fail(
            path,
            "MATLAB v7.3 (HDF5) file: save it with -v7 or read it with h5py and pass arrays to beat_from_kymograph",
        )
    except (
        scipy.io.matlab.MatReadError,
        OSError,
        ValueError,
        TypeError,
        KeyError,
        EOFError,
    ) as err:
        fail(path, f"cannot read as a MATLAB .mat file ({err})")
    try:
        raw = {k: _pick_cell(path, k, v, cell) for k, v in raw.items()}
        raw = {
            k: np.squeeze(v)
            if k in VECTORS or (variables and k in {variables.get(n) for n in VECTORS})
            else v
            for k, v in raw.items()
        }
        renamed = set((variables or {}).values())
        for theirs, ours in MATLAB_XYZ.items():  # MATLAB-style (points, frames) columns
            if theirs in raw and ours not in raw and theirs not in renamed:
                raw[ours] = np.asarray(raw.pop(theirs), dtype=float).T
        return _split(path, _rename(path, raw, variables))
    except BeatFileError:
        raise
    except (ValueError, TypeError) as err:
        fail(path, f"unexpected contents (structs or nested cells?): {err}")


def _pick_cell(path, name: str, value, cell: int | None):
    if not (isinstance(value, np.ndarray) and value.dtype == object):
        return value
    filled = [i for i in range(value.size) if np.asarray(value.flat[i]).size]
    if cell is None:
        if len(filled) != 1:
            fail(
                path,
                f"cell array {name} has {len(filled)} non-empty cells "
                f"({', '.join(map(str, filled[:10]))}): choose one with cell=INDEX (0-based)",
            )
        cell = filled[0]
    if not 0 <= cell < value.size or cell not in filled:
        fail(
            path,
            f"cell {cell} of {name} is missing or empty (non-empty, 0-based: "
            f"{', '.join(map(str, filled[:10])) or 'none'})",
        )
    return value.flat[cell]


def read_file(
    path: str | pathlib.Path, variables: dict | None = None, cell: int | None = None
) -> RawBeat:
    """Read ``path`` (format from its suffix: ``.csv``, ``.npz``, ``.mat``).

    Raises:
        BeatFileError: one line naming the file and the problem.
    """
    path = pathlib.Path(path)
    if not path.is_file():
        fail(path, "file does not exist")
    if path.suffix == ".npz":
        return read_npz(path, variables)
    if path.suffix == ".mat":
        return read_mat(path, variables, cell)
    if path.suffix == ".csv":
        if variables:
            fail(path, "variables= applies to .npz and .mat files; a .csv names its columns")
        return read_csv(path)
    fail(path, f"unknown format {path.suffix!r}: use .csv, .npz or .mat")
