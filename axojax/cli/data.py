"""``axojax data FILE``: what axojax extracts from beat data before any fit (length,
frequency and its sigma, wavelength, static curvature, dynamic amplitude, planarity),
optionally with a figure. ``axojax data --list``: the bundled data sets, each with its
source and licence (JSON: ``{"datasets": [{"name", "file", "description", "source",
"licence", "citation", "flagellum", "path"}, ...]}``).

Physical inputs the file may lack: ``--length-um`` and ``--frame-rate-hz``. A value in the
file and a different one on the command line is an error (one line naming both); a
centreline without either length uses the median measured arc length of its frames.

JSON: the keys of docs/interface.md (``file``, ``kind``, ``length_um``, ``frequency_hz``,
``frequency_sigma_hz``, ``wavelength_um``, ``static_curvature_rad_per_um``,
``dynamic_amplitude_rad``, ``planarity``) plus ``amplitude_dip`` (min / max of |psi_1|
over the middle 80 % of the length, at the samples), ``wavelength_sensitive`` (true below
0.1 with a wavelength: a near-node of psi_1 where the phase turns fast; the text adds a
note after the wavelength), ``n_points``, ``frames``, ``cycles``,
``psi1_sigma_rad`` (min/median/max), ``floors``, ``excluded_base_um``,
``published_frequency_hz``, ``notes`` (what the reduction decided, in words),
``direction`` (``anterograde``: base to tip, ``retrograde`` or null: standing),
``static_curvature_noise_rad_per_um`` (below it the text and the figure show the static
curvature as 0) and ``warnings`` (what the file holds that axojax did not read: each also
one line ``axojax: data: warning: ...`` on stderr).
``planarity`` is null except for 3D centrelines: ``{"singular_values_um": [s1, s2, s3],
"ratios": {"s2_over_s1", "s3_over_s1", "s3_over_s2"}, "threshold", "planar", "treatment",
"frame", "frame_ratio"}`` (``frame``: the beat frame's axes ``{"e1", "e2", "e3"}`` of a
non-planar beat, else null; :mod:`axojax.beats.reduction`). ``wavelength_um``,
``static_curvature_rad_per_um``, ``dynamic_amplitude_rad``, ``amplitude_dip`` and
``wavelength_sensitive`` are the in-plane component's; ``components`` lists ``{"name",
"wavelength_um", "wavenumber_rad_per_um", "dynamic_amplitude_rad", "amplitude_dip",
"wavelength_sensitive"}`` of every reduced component (``in_plane``, and ``out_of_plane``
for a non-planar 3D beat). A frequency the file cannot give (a Fourier-mode file
without one) is null.
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings

from .. import _io
from ..beats.data import BeatDataWarning, read_beat
from ..waveform.measures import sensitive_note, wavelength_text
from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "file",
        metavar="FILE",
        nargs="?",
        default=None,
        help=(
            "beat file (.csv, .npz, .mat: kymograph, 2D/3D centreline or Fourier modes) or a "
            "bundled data set's name (--list lists them)"
        ),
    )
    parser.add_argument(
        "--list",
        action="store_true",
        help="list the bundled data sets with their source and licence (instead of FILE)",
    )
    parser.add_argument(
        "--length-um",
        type=common.finite_float,
        default=None,
        metavar="UM",
        help="flagellum length, when the file lacks it",
    )
    parser.add_argument(
        "--frame-rate-hz",
        type=common.finite_float,
        default=None,
        metavar="HZ",
        help="frames per second, when the file lacks it",
    )
    parser.add_argument(
        "--cell",
        type=int,
        default=None,
        metavar="INDEX",
        help=".mat cell arrays: which cell (0-based; default the only non-empty one)",
    )
    common.add_planarity_flag(parser)
    parser.add_argument(
        "--exclude-base-um",
        type=common.finite_float,
        default=None,
        metavar="UM",
        help="leave out the basal stretch s < UM",
    )
    parser.add_argument(
        "--plot",
        default=None,
        metavar="OUT.png",
        help="figure: psi_0, |psi_1| and phase along s, kymograph or reconstruction",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _list(args: argparse.Namespace) -> dict:
    """The document of ``axojax data --list``."""
    from ..datasets import info, names

    given = [
        flag
        for flag, value in (
            ("FILE", args.file),
            ("--plot", args.plot),
            ("--length-um", args.length_um),
            ("--frame-rate-hz", args.frame_rate_hz),
            ("--cell", args.cell),
            ("--exclude-base-um", args.exclude_base_um),
        )
        if value is not None
    ]
    if given:
        raise common.CLIError(f"--list: lists the bundled data sets; give it without {given[0]}")
    return {"datasets": [info(name).to_json() for name in names()]}


def run(args: argparse.Namespace) -> dict:
    if args.list:
        return _list(args)
    if args.file is None:
        raise common.CLIError(
            "FILE: give a beat file or a bundled data set's name ('axojax data --list' lists them)"
        )
    common.check_output(
        "--plot", args.plot, common.FIGURE_SUFFIXES
    )  # before any work, as every command
    for flag, value in (
        ("--length-um", args.length_um),
        ("--frame-rate-hz", args.frame_rate_hz),
        ("--planarity-threshold", args.planarity_threshold),
    ):
        if value is not None and not value > 0:
            raise common.CLIError(f"{flag}: must be > 0, got {value:g}")
    if args.cell is not None and args.cell < 0:
        raise common.CLIError(f"--cell: must be >= 0, got {args.cell}")
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", BeatDataWarning)
            try:
                beat = read_beat(
                    args.file,
                    length_um=args.length_um,
                    frame_rate_hz=args.frame_rate_hz,
                    cell=args.cell,
                    planarity_threshold=args.planarity_threshold,
                )
            finally:  # before any error: a warning may name its cause (length_mm = ...)
                for w in caught:
                    if issubclass(w.category, BeatDataWarning):
                        print(f"axojax: data: warning: {w.message}", file=sys.stderr)
                    else:
                        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        if args.exclude_base_um is not None:
            beat = beat.exclude_base(args.exclude_base_um)
    except ValueError as err:
        raise common.CLIError(str(err)) from None
    doc = beat.summary()
    if args.plot is not None:
        from ..plotting.beat_data import plot_beat_data

        fig = plot_beat_data(beat)
        try:
            with _io.atomic_path(args.plot) as tmp:
                fig.savefig(tmp, dpi=110)
        except (OSError, ValueError) as err:
            raise common.CLIError(f"--plot: cannot write {args.plot!r} ({err})") from None
        doc["plot"] = args.plot
    return doc


def _num(v, fmt: str, unit: str) -> str:
    return (
        "unknown"
        if v is None or (isinstance(v, float) and not math.isfinite(v))
        else f"{v:{fmt}} {unit}"
    )


def _render_list(doc: dict) -> str:
    lines = []
    for d in doc["datasets"]:
        lines += [
            f"{d['name']}: {d['description']}",
            f"  file      {d['path']}",
            f"  source    {d['source']}",
            f"  licence   {d['licence']}",
            f"  citation  {d['citation']}",
        ]
        f = d.get("flagellum")
        if f:
            lines.append(
                f"  flagellum kappa {f['bending_rigidity_pn_um2']:g} pN um^2, xi_n "
                f"{f['normal_drag_pn_s_um2']:g} pN s/um^2 (fits' default units; {f['source']})"
            )
    lines.append("(source, units and extraction in full: axojax/data/README.md)")
    return "\n".join(lines)


def _component_lines(components: list[dict]) -> list[str]:
    """One line per transverse component of a non-planar 3D beat (none for one component)."""
    if len(components) < 2:
        return []
    return [
        f"  {c['name'].replace('_', '-'):17s} wavelength {wavelength_text(c['wavelength_um'])},"
        f" dynamic amplitude {_num(c['dynamic_amplitude_rad'], '.4g', 'rad')}" + _note(c)
        for c in components
    ]


def _note(d: dict) -> str:
    """The note after a sensitive wavelength (``""`` for none, or a report without the key)."""
    return sensitive_note(d.get("amplitude_dip") if d.get("wavelength_sensitive") else None)


def _static_curvature(doc: dict) -> str:
    """The static curvature, or 0 where it is below its noise (the data's precision)."""
    value, noise = doc["static_curvature_rad_per_um"], doc.get("static_curvature_noise_rad_per_um")
    if noise is not None and value is not None and abs(value) < noise:
        return f"0 rad/um (within its noise, {noise:.2g} rad/um)"
    return _num(value, ".4g", "rad/um")


DIRECTIONS = {
    "anterograde": "anterograde (the wave runs base to tip)",
    "retrograde": "retrograde (the wave runs tip to base)",
    None: "none (a standing wave)",
}


def render(doc: dict) -> str:
    if "datasets" in doc:
        return _render_list(doc)
    freq = (
        "unknown (give --target-frequency to a fit)"
        if doc["frequency_hz"] is None
        else f"{doc['frequency_hz']:.4g} +- {doc['frequency_sigma_hz']:.2g} Hz"
    )
    lines = [
        f"{doc['file']}: {doc['kind']}, {doc['n_points']} points"
        + (
            f", {doc['frames']} frames, {doc['cycles']} whole"
            f" cycle{'s' if doc['cycles'] != 1 else ''} used"
            if doc["frames"]
            else ""
        ),
        f"  length            {_num(doc['length_um'], '.4g', 'um')}",
        f"  frequency         {freq}",
        f"  wavelength        {wavelength_text(doc['wavelength_um'])}"
        + (" (in-plane component)" if len(doc.get("components", [])) > 1 else "")
        + _note(doc),
        f"  direction         {DIRECTIONS.get(doc.get('direction'), doc.get('direction'))}",
        f"  static curvature  {_static_curvature(doc)}",
        f"  dynamic amplitude {_num(doc['dynamic_amplitude_rad'], '.4g', 'rad')}",
        *_component_lines(doc.get("components", [])),
        f"  psi_1 sigma       {doc['psi1_sigma_rad']['min']:.2g} .. "
        f"{doc['psi1_sigma_rad']['max']:.2g} rad (floor {doc['floors']['psi1_rad']:g})",
    ]
    if doc["planarity"] is not None:
        r = doc["planarity"]["ratios"]
        lines.append(
            f"  planarity         s2/s1 {r['s2_over_s1']:.3g}, s3/s1 {r['s3_over_s1']:.3g}, s3/s2 {r['s3_over_s2']:.3g}"
        )
    if doc.get("published_frequency_hz") is not None:
        lines.append(f"  published frequency {doc['published_frequency_hz']:.4g} Hz")
    f = doc.get("flagellum")
    if f:
        lines.append(
            f"  flagellum         kappa {f['bending_rigidity_pn_um2']:.4g} pN um^2, xi_n "
            f"{f['normal_drag_pn_s_um2']:.3g} pN s/um^2 (literature; axojax compare's default units)"
        )
    lines += [f"  note: {n}" for n in doc["notes"]]
    if "plot" in doc:
        lines.append(f"  figure: {doc['plot']}")
    return "\n".join(lines)
