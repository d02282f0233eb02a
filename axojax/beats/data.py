"""Observed beats: read a file (:mod:`axojax.beats.readers`: kymograph, 2D or 3D
centreline, Fourier modes; ``.csv``, ``.npz``, ``.mat``), reduce it
(:mod:`axojax.beats.reduction`: planarity, beat phase, frequency, psi_0, psi_1 and their
uncertainties) and hand a fit its targets (:meth:`BeatData.targets`).

Physical inputs a file may lack come from the caller (``read_beat(..., length_um=,
frame_rate_hz=)``, the command line's ``--length-um`` / ``--frame-rate-hz``). When both the
file and the caller give one and they differ (by more than 1e-9 relative), that is an
error: a file's value is a measurement, and silently overriding or ignoring it hides a
mistake. A centreline's length, when neither gives it, is the median of its frames'
measured arc lengths. A Fourier-mode file without a frequency keeps ``frequency_hz = None``
(the fit then needs ``--target-frequency``; :attr:`BeatData.notes` says so).

Every problem (missing field or column, NaN, fewer frames than 1.5 beat periods) is a
one-line ``ValueError`` naming the file and the problem. Values no flagellum has are
problems too, named with the likely unit mistake (:func:`check_units`): a length or an
arc-length range outside :data:`FLAGELLUM_LENGTH_UM` (1 to 500 um: mm, nm or pixels?),
tangent angles that swing more than 2 pi within a beat period or a dynamic amplitude
above pi (degrees?). What a file holds that axojax does not read (an unknown CSV header
key) is a :class:`BeatDataWarning`, one line, also kept in :attr:`BeatData.warnings`.
"""

from __future__ import annotations

import dataclasses
import pathlib
import warnings

import numpy as np

from ..units import Flagellum
from ..waveform import FourierModes
from ..waveform.measures import amplitude_dip, finite_or_none, is_sensitive
from . import reduction
from .bundled import flagellum_of, resolve
from .readers import RawBeat, fail, read_file
from .reduction import FREQUENCY_REL_FLOOR, PSI1_FLOOR_RAD, Planarity
from .targets import ShapeTarget, Target, join_components

N_POINTS = reduction.N_POINTS
FLAGELLUM_LENGTH_UM = (1.0, 500.0)
"""Lengths (um) a flagellum or cilium has, with a wide margin (the shortest motile cilia
are a few um, the longest sperm flagella a few hundred): a length or an arc-length range
outside is a unit mistake (mm, nm, pixels), an error."""


class BeatDataWarning(UserWarning):
    """Something in a beat file that axojax does not read (one line naming the file)."""


@dataclasses.dataclass(frozen=True)
class BeatData:
    """A beat reduced to what a fit uses.

    Attributes:
        s_um: (S,) arc length from the base (um).
        modes: psi_0 and psi_1 (rad) at ``s_um``: the in-plane component for non-planar
            3D beats (about the beat frame's e2, :mod:`axojax.beats.reduction`).
        psi1_sigma: (S,) standard error (rad) of each of Re and Im of psi_1 (per-cycle
            scatter, floored: :mod:`axojax.beats.reduction`).
        frequency_hz, frequency_sigma_hz: beat frequency and its standard error; ``None``
            when the file has frames of unknown timing or is a Fourier-mode file without one.
        length_um: flagellum length (um).
        kind: ``"kymograph"``, ``"centreline-2d"``, ``"centreline-3d"`` or ``"fourier"``.
        source: the file (or ``"data"``).
        t_s: (T,) frame times and psi_rad: (T, S) tangent angle, ``None`` for Fourier modes.
        planarity: :class:`~axojax.beats.reduction.Planarity` of a 3D record, else ``None``.
        out_of_plane: for a non-planar 3D record, the out-of-plane component's (about
            the beat frame's e3) modes and psi_1 sigma ``(FourierModes, (S,))``, else
            ``None``.
        cycles: whole cycles used (0 for Fourier modes); periods_s: their durations.
        excluded_base_um: basal stretch left out (:meth:`exclude_base`).
        notes: what the reduction decided or assumed, in words.
        published_frequency_hz: a frequency stated by the data's authors, if the file has one.
        flagellum: the organism's typical bending rigidity and drag
            (:class:`~axojax.units.Flagellum`) for a bundled data set, else ``None``.
        cycle_bounds_s: (cycles + 1,) times bounding the whole cycles used (the beat
            phase's crossings of multiples of 2 pi), ``None`` for Fourier modes.
        warnings: one line each, what the file holds that axojax did not read
            (:class:`BeatDataWarning`).
        psi1_cycles: (n, S) psi_1 (rad) of each whole cycle, whose mean is ``modes.psi1``
            (:attr:`Reduction.psi1_cycles`); None for Fourier modes or one cycle.
    """

    s_um: np.ndarray
    modes: FourierModes
    psi1_sigma: np.ndarray
    frequency_hz: float | None
    frequency_sigma_hz: float | None
    length_um: float
    kind: str = "kymograph"
    source: str = "data"
    t_s: np.ndarray | None = None
    psi_rad: np.ndarray | None = None
    planarity: Planarity | None = None
    out_of_plane: tuple | None = None
    cycles: int = 0
    periods_s: np.ndarray | None = None
    excluded_base_um: float = 0.0
    notes: tuple = ()
    published_frequency_hz: float | None = None
    flagellum: Flagellum | None = None
    cycle_bounds_s: np.ndarray | None = None
    warnings: tuple = ()
    psi1_cycles: np.ndarray | None = None

    def targets(self) -> tuple[list[Target], ShapeTarget]:
        """Frequency target (none when the frequency is unknown) and the psi_1 shape
        target (per-point sigma, with the observed psi_0)."""
        freq = (
            []
            if self.frequency_hz is None
            else [Target("frequency_hz", self.frequency_hz, self.frequency_sigma_hz)]
        )
        return freq, ShapeTarget(self.s_um, self.modes.psi1, self.psi1_sigma, psi0=self.modes.psi0)

    def shape_targets(self) -> list[ShapeTarget]:
        """Shape targets of every reduced component, labelled (``ShapeTarget.component``):
        the ``"in_plane"`` one, and for a non-planar 3D beat also the ``"out_of_plane"``
        one. A 3D model fits both with one complex scale:
        :meth:`joint_shape_target`."""
        out = [self.targets()[1]]
        if self.out_of_plane is not None:
            m, sig = self.out_of_plane
            out.append(ShapeTarget(self.s_um, m.psi1, sig, psi0=m.psi0, component="out_of_plane"))
        return out

    def joint_shape_target(self) -> ShapeTarget:
        """Every component in one shape target (:func:`~axojax.beats.targets.join_components`):
        a condition with it fits a 3D model's psi_1 along its beat direction to the in-plane
        component and perpendicular to it to the out-of-plane one, with one complex scale
        (they are one mode's two projections). For a planar beat, the in-plane target."""
        return join_components(self.shape_targets())

    @property
    def components(self) -> list[dict]:
        """Measures of each reduced component (``"in_plane"``, and ``"out_of_plane"`` for a
        non-planar 3D beat): ``{"name", "wavelength_um" (None: standing),
        "wavenumber_rad_per_um", "dynamic_amplitude_rad", "amplitude_dip",
        "wavelength_sensitive"}``, each by :mod:`axojax.waveform.measures` (the functions of
        the in-plane properties; the dip of psi_1 at the samples, sensitive below
        ``SENSITIVE_DIP`` and only with a wavelength)."""
        comps = [("in_plane", self.modes)]
        if self.out_of_plane is not None:
            comps.append(("out_of_plane", self.out_of_plane[0]))
        out = []
        for name, m in comps:
            wl, dip = finite_or_none(m.wavelength), float(amplitude_dip(m.s, m.psi1))
            out.append(
                {
                    "name": name,
                    "wavelength_um": wl,
                    "wavenumber_rad_per_um": float(m.wavenumber),
                    "dynamic_amplitude_rad": float(m.dynamic_amplitude),
                    "amplitude_dip": dip,
                    "wavelength_sensitive": wl is not None and is_sensitive(dip),
                }
            )
        return out

    def exclude_base(self, um: float) -> BeatData:
        """The same beat without its basal stretch s < ``um`` (arc lengths stay measured
        from the base, so a model clamped at s = 0 is compared only where s >= um).

        Raises:
            ValueError: ``um`` negative, or fewer than 4 points would remain.
        """
        um = float(um)
        if not (np.isfinite(um) and um >= 0):
            raise ValueError(
                f"{self.source}: the basal stretch to exclude must be >= 0 um, got {um!r}"
            )
        keep = self.s_um >= um - 1e-9 * max(1.0, self.length_um)
        if keep.sum() < 4:
            raise ValueError(
                f"{self.source}: excluding {um:g} um of the base leaves {int(keep.sum())} "
                f"points of {self.s_um.size} (length {self.length_um:g} um); need at least 4"
            )

        def cut(m: FourierModes) -> FourierModes:
            return dataclasses.replace(m, s=m.s[keep], psi0=m.psi0[keep], psi1=m.psi1[keep])

        oop = (
            None
            if self.out_of_plane is None
            else (cut(self.out_of_plane[0]), self.out_of_plane[1][keep])
        )
        return dataclasses.replace(
            self,
            s_um=self.s_um[keep],
            modes=cut(self.modes),
            psi1_sigma=self.psi1_sigma[keep],
            psi_rad=None if self.psi_rad is None else self.psi_rad[:, keep],
            psi1_cycles=None if self.psi1_cycles is None else self.psi1_cycles[:, keep],
            out_of_plane=oop,
            excluded_base_um=max(um, self.excluded_base_um),
            notes=self.notes + (f"basal {um:g} um excluded ({int((~keep).sum())} points)",),
        )

    @property
    def static_curvature_rad_per_um(self) -> float:
        """Least-squares slope of psi_0(s) (rad/um; :mod:`axojax.waveform.measures`)."""
        return self.modes.static_curvature

    @property
    def static_curvature_noise_rad_per_um(self) -> float:
        """The static curvature's noise (rad/um): the standard error of a least-squares
        slope through points each known to the median psi_1 sigma (the data's angle
        precision, at least ``PSI1_FLOOR_RAD``). A static curvature below it is zero to
        the data's precision (``axojax data`` prints and draws it so)."""
        spread = float(np.sqrt(np.sum((self.s_um - self.s_um.mean()) ** 2)))
        return float(np.median(self.psi1_sigma)) / spread if spread > 0 else float("inf")

    @property
    def direction(self) -> str | None:
        """``"anterograde"`` (the wave runs base to tip), ``"retrograde"`` (tip to base) or
        ``None`` (a standing wave): the sign of :attr:`wavenumber_rad_per_um` for a beat
        written ``psi_1 exp(+i omega t)``, omega > 0."""
        return {1: "anterograde", -1: "retrograde"}.get(int(self.modes.direction))

    @property
    def dynamic_amplitude_rad(self) -> float:
        """Arc-length (trapezoidal) mean of |psi_1(s)| (rad)."""
        return self.modes.dynamic_amplitude

    @property
    def wavenumber_rad_per_um(self) -> float:
        """Least-squares slope of psi_1(s)'s unwrapped phase (rad/um; negative: the wave
        runs base to tip), the same function as a model's (:mod:`axojax.waveform.measures`)."""
        return self.modes.wavenumber

    @property
    def wavelength_um(self) -> float | None:
        """2 pi / |k| (um), k = :attr:`wavenumber_rad_per_um`; ``None`` for a standing
        wave."""
        return finite_or_none(self.modes.wavelength)

    def summary(self) -> dict:
        """What ``axojax data --json`` prints (keys in docs/interface.md, plus extras).
        ``wavelength_um``, ``dynamic_amplitude_rad`` and ``static_curvature_rad_per_um`` are
        the in-plane component's, as are ``amplitude_dip`` and ``wavelength_sensitive``;
        ``components`` lists every component's (:attr:`components`)."""
        comps = self.components
        return {
            "file": self.source,
            "kind": self.kind,
            "length_um": float(self.length_um),
            "frequency_hz": self.frequency_hz,
            "frequency_sigma_hz": self.frequency_sigma_hz,
            "wavelength_um": self.wavelength_um,
            "static_curvature_rad_per_um": self.static_curvature_rad_per_um,
            "static_curvature_noise_rad_per_um": self.static_curvature_noise_rad_per_um,
            "dynamic_amplitude_rad": self.dynamic_amplitude_rad,
            "amplitude_dip": comps[0]["amplitude_dip"],
            "wavelength_sensitive": comps[0]["wavelength_sensitive"],
            "direction": self.direction,
            "components": comps,
            "planarity": None if self.planarity is None else self.planarity.as_dict(),
            "n_points": int(self.s_um.size),
            "frames": None if self.t_s is None else int(self.t_s.size),
            "cycles": int(self.cycles),
            "psi1_sigma_rad": {
                "min": float(self.psi1_sigma.min()),
                "median": float(np.median(self.psi1_sigma)),
                "max": float(self.psi1_sigma.max()),
            },
            "floors": {"frequency_relative": FREQUENCY_REL_FLOOR, "psi1_rad": PSI1_FLOOR_RAD},
            "excluded_base_um": self.excluded_base_um,
            "published_frequency_hz": self.published_frequency_hz,
            "flagellum": None if self.flagellum is None else self.flagellum.to_json(),
            "notes": list(self.notes),
            "warnings": list(self.warnings),
        }


PHYSICAL_RANGES = {"frame_rate_hz": (1e-2, 1e7), "length_um": (1e-3, 1e5)}
"""Accepted ranges of a beat's frame rate (Hz) and length (um), from the file or a flag:
far beyond any microscope and flagellum, and bounded so that the sigmas derived from
them stay finite (a frame rate of 1e308 overflowed)."""


def _physical(raw: RawBeat, name: str, given: float | None, flag: str) -> float | None:
    have = raw.scalars.get(name)
    lo, hi = PHYSICAL_RANGES.get(name, (0.0, np.inf))
    if given is not None:
        if not (np.isfinite(given) and given > 0):
            raise ValueError(f"{flag}: must be a finite number > 0, got {given!r}")
        if not lo <= given <= hi:
            raise ValueError(f"{flag}: must be in [{lo:g}, {hi:g}], got {given!r}")
        if have is not None and abs(have - given) > 1e-9 * max(abs(have), abs(given)):
            fail(
                raw.path,
                f"{name} = {have:g} in the file conflicts with {flag} {given:g}; drop {flag} or fix the file",
            )
        return float(given)
    if have is not None and not lo <= have <= hi:
        fail(raw.path, f"{name} = {have:g} in the file is outside [{lo:g}, {hi:g}]")
    return have


def read_beat(
    path: str | pathlib.Path,
    *,
    length_um: float | None = None,
    frame_rate_hz: float | None = None,
    variables: dict | None = None,
    cell: int | None = None,
    planarity_threshold: float = reduction.PLANARITY_THRESHOLD,
) -> BeatData:
    """Read a beat file and reduce it (formats: :mod:`axojax.beats.readers`).

    Args:
        path: the file, or the name of a bundled data set (``"human_sperm"``,
            :mod:`axojax.datasets`).
        length_um, frame_rate_hz: values the file lacks (a file value that differs is an
            error, module docstring).
        variables, cell: for ``.npz``/``.mat``: renamed variables, which cell of a cell array.
        planarity_threshold: s3/s2 below which a 3D beat is planar.
    """
    file = resolve(path)
    beat = _read(file, length_um, frame_rate_hz, variables, cell, planarity_threshold)
    return dataclasses.replace(beat, flagellum=flagellum_of(file))


def _warn(raw: RawBeat) -> None:
    for line in raw.warnings:
        warnings.warn(BeatDataWarning(f"{raw.path}: {line}"), stacklevel=4)


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


def _read(file, length_um, frame_rate_hz, variables, cell, planarity_threshold) -> BeatData:
    raw = read_file(file, variables=variables, cell=cell)
    _warn(raw)
    length = _physical(raw, "length_um", length_um, "--length-um")
    if length is not None:
        check_length(
            raw.path,
            "--length-um" if length_um is not None else "length_um =",
            length,
            "looks",
        )
    notes = []
    published = raw.scalars.get("published_frequency_hz")
    if raw.kind == "fourier":
        if frame_rate_hz is not None:
            notes.append("frame rate ignored: a Fourier-mode file has no frames")
        return dataclasses.replace(_from_modes(raw, length, notes), warnings=raw.warnings)
    rate = _physical(raw, "frame_rate_hz", frame_rate_hz, "--frame-rate-hz")
    if rate is None:
        fail(raw.path, "missing frame_rate_hz (give it in the file or with --frame-rate-hz)")
    a = raw.arrays
    planar = None
    if raw.kind == "kymograph":
        psi = a["psi"]
        if psi.ndim != 2:
            fail(raw.path, f"psi must be (frames, points), got shape {psi.shape}")
        if length is None:
            if "s_um" not in a:
                fail(raw.path, "missing length_um (give it in the file or with --length-um)")
            length = float(a["s_um"][-1])
        s = a.get("s_um", np.linspace(0, length, psi.shape[1]))
        if s.shape != (psi.shape[1],):
            fail(
                raw.path,
                f"s_um must have one value per column of psi ({psi.shape[1]}), got shape {s.shape}",
            )
        if s.size >= MIN_POINTS:
            if np.any(np.diff(s) <= 0) or s[0] < 0:
                fail(raw.path, "s_um must be >= 0 (from the base) and increasing along each frame")
            check_length(raw.path, "s_um spans", float(s[-1] - s[0]), "s looks")
            if "length_um" not in raw.scalars and length_um is None:
                check_length(raw.path, "length (the last s_um)", length, "s looks")
        comps = [psi]
    else:
        names = ("x_um", "y_um", "z_um") if raw.kind == "centreline-3d" else ("x_um", "y_um")
        shapes = {a[n].shape for n in names}
        if len(shapes) != 1 or a["x_um"].ndim != 2:
            fail(
                raw.path,
                f"centreline needs {', '.join(names)} of equal shape (frames, points), got "
                f"{', '.join(str(a[n].shape) for n in names)}",
            )
        pts = np.stack([a[n] for n in names], axis=-1)
        if pts.shape[1] < 4:
            fail(raw.path, f"centreline needs at least 4 points per frame, got {pts.shape[1]}")
        if length is None:
            length = float(np.median(reduction.arc_lengths(pts)))
            check_length(
                raw.path,
                "the centreline's median arc length is",
                length,
                f"{', '.join(names)} look",
            )
            notes.append(f"length {length:.4g} um: median measured arc length of the frames")
        if raw.kind == "centreline-3d":
            planar = reduction.planarity(pts, planarity_threshold)
            axes = planar.axes[:2] if planar.planar else planar.frame
            notes.append(planar.treatment)
        else:
            axes = np.eye(2)
        s, comps = reduction.tangent_angles(pts, axes, length, raw.path)
    if raw.frames is None:
        t = np.arange(comps[0].shape[0]) / rate
    else:
        t = raw.frames / rate
        missing = int(raw.frames[-1] - raw.frames[0] + 1 - raw.frames.size)
        if missing:
            notes.append(
                f"{missing} frame numbers missing between {raw.frames[0]} and"
                f" {raw.frames[-1]}: times from the frame numbers"
            )
    beat = beat_from_kymograph(t, s, comps[0], source=raw.path, extra=comps[1:])
    if raw.kind == "kymograph":
        check_degrees(raw.path, beat.modes, comps[0], t, beat.cycle_bounds_s)
    return dataclasses.replace(
        beat,
        length_um=float(length),
        kind=raw.kind,
        planarity=planar,
        notes=beat.notes + tuple(notes),
        published_frequency_hz=published,
        warnings=raw.warnings,
    )


def _from_modes(raw: RawBeat, length: float | None, notes: list) -> BeatData:
    a = raw.arrays
    s = a["s_um"]
    n = s.size
    for k in ("psi0_rad", "psi1_re_rad", "psi1_im_rad", "psi1_sigma_rad"):
        if k in a and a[k].shape != (n,):
            fail(raw.path, f"{k} must have one value per s_um ({n}), got shape {a[k].shape}")
    if s.ndim != 1 or n < 2 or np.any(np.diff(s) <= 0) or s[0] < 0:
        fail(raw.path, "s_um must be >= 0 and increasing, with at least 2 points")
    if length is None:
        fail(raw.path, "missing length_um (a '# length_um = L' header line, or --length-um)")
    if n >= MIN_POINTS:
        check_length(raw.path, "s_um spans", float(s[-1] - s[0]), "s looks")
    if s[-1] > length * (1 + 1e-9):
        fail(raw.path, f"s_um reaches {s[-1]:g} um, beyond length_um = {length:g}")
    if n < MIN_POINTS:
        fail(
            raw.path,
            f"needs at least {MIN_POINTS} points of s_um (a wavelength needs a phase gradient), got {n}",
        )
    for k in ("psi0_rad", "psi1_re_rad", "psi1_im_rad"):
        check_angles(raw.path, k, a[k])
    psi1 = a["psi1_re_rad"] + 1j * a["psi1_im_rad"]
    check_degrees(raw.path, FourierModes(s=s, psi0=a["psi0_rad"], psi1=psi1, omega=1.0))
    if "psi1_sigma_rad" in a:
        if np.any(a["psi1_sigma_rad"] <= 0):
            fail(raw.path, "psi1_sigma_rad must be > 0")
        sigma = a["psi1_sigma_rad"]
    else:
        sigma = np.full(n, PSI1_FLOOR_RAD)
        notes.append(f"no psi1_sigma_rad column: psi_1 sigma is the floor {PSI1_FLOOR_RAD:g} rad")
    f = raw.scalars.get("frequency_hz")
    fs = raw.scalars.get("frequency_sigma_hz")
    if f is None:
        if fs is not None:
            fail(raw.path, "frequency_sigma_hz given without frequency_hz")
        notes.append("no frequency in the file: a fit needs --target-frequency")
    elif fs is None:
        fs = FREQUENCY_REL_FLOOR * f
        notes.append(f"no frequency_sigma_hz: the {FREQUENCY_REL_FLOOR:.0%} floor")
    modes = FourierModes(
        s=s, psi0=a["psi0_rad"], psi1=psi1, omega=float("nan") if f is None else 2 * np.pi * f
    )
    return BeatData(
        s_um=s,
        modes=modes,
        psi1_sigma=sigma,
        frequency_hz=f,
        frequency_sigma_hz=fs,
        length_um=float(length),
        kind="fourier",
        source=raw.path,
        notes=tuple(notes),
        published_frequency_hz=raw.scalars.get("published_frequency_hz"),
    )


MIN_POINTS = 3
"""Fewest arc-length points (every kind) and frames (frames only) of a beat: a wavelength
needs a phase gradient, a frequency a time series."""
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


def beat_from_kymograph(
    t_s: np.ndarray,
    s_um: np.ndarray,
    psi_rad: np.ndarray,
    source: str = "data",
    extra: list | tuple = (),
) -> BeatData:
    """Frequency, psi_0 and psi_1 (with uncertainties) of a kymograph ``psi_rad`` (T, S)
    sampled at times ``t_s`` (T,) and arc lengths ``s_um`` (S,); ``extra`` angle
    components (each (T, S)) share its beat phase (a 3D beat's out-of-plane angle)."""
    s = np.asarray(s_um, dtype=float)
    psi = np.asarray(psi_rad, dtype=float)
    if psi.ndim != 2 or psi.shape[1] < MIN_POINTS or psi.shape[0] < MIN_POINTS:
        fail(
            source,
            f"needs at least {MIN_POINTS} arc-length points and {MIN_POINTS} frames (a "
            "wavelength needs a phase gradient, a frequency a time series), got "
            f"{psi.shape[1] if psi.ndim == 2 else 0} points x "
            f"{psi.shape[0] if psi.ndim else 0} frames",
        )
    for i, comp in enumerate([psi, *extra]):
        check_angles(source, "psi" if i == 0 else "psi (out of plane)", np.asarray(comp, float))
    red = reduction.reduce_frames(t_s, s, [psi, *extra], source=source)
    return BeatData(
        s_um=s,
        modes=red.modes[0],
        psi1_sigma=red.psi1_sigma[0],
        frequency_hz=red.frequency_hz,
        frequency_sigma_hz=red.frequency_sigma_hz,
        length_um=float(s[-1]),
        kind="kymograph",
        source=str(source),
        t_s=np.asarray(t_s, dtype=float),
        psi_rad=psi,
        cycles=red.cycles,
        periods_s=red.periods_s,
        cycle_bounds_s=red.crossings_s,
        psi1_cycles=red.psi1_cycles[0],
        out_of_plane=(red.modes[1], red.psi1_sigma[1]) if extra else None,
        notes=(
            f"frequency from {red.cycles} cycles: scatter {red.frequency_scatter_hz:.3g} Hz, "
            f"sigma {red.frequency_sigma_hz:.3g} Hz (floor {FREQUENCY_REL_FLOOR:.0%})",
        ),
    )
