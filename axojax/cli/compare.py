"""``axojax compare``: every mechanism x base fitted to one observed beat, ranked by BIC
(:func:`axojax.compare`; docs/mechanisms.md).

Basal compliance: bases named ``KIND+compliance`` / ``KIND+elastic``, or ``--compliance
off|on|elastic|both|both-elastic|all`` for every base (default: the default bases without
and with a basal spring; named bases as named; docs/mechanisms.md, basal compliance).

Units: ``--kappa`` and ``--xi-n`` (the whole flagellum's bending rigidity and normal drag),
or ``--ei`` and ``--cn`` (per filament: kappa / F, xi_n / F for the preset's F filaments),
or ``--organism NAME`` (:data:`axojax.units.ORGANISMS`: kappa, xi_n and the head's
semi-axes); what is not given comes from the data set's flagellum when it is a bundled one
(the human sperm's kappa and xi_n), else from axojax's defaults
(:func:`axojax.beats.units.beat_units`), with one warning line on stderr
saying so; the table says which.

Exit status 0; bad input (an unknown or unavailable mechanism or base, a coefficient
named as a mechanism, a bad --compliance, a bad setting) is one line naming the flag,
exit 2.
"""

from __future__ import annotations

import argparse
import sys
import warnings

from .._progress import enabled as progress_enabled
from ..beats import beat_units
from ..inverse.comparison.compare import compare
from ..inverse.comparison.mechanisms import (
    BASES,
    COMPARE_PRESETS,
    COMPLIANCE,
    DEFAULT_BASES,
    DEFAULT_ELEMENTS,
    DEFAULT_HEAD_UM,
    DEFAULT_PRESET,
    DEFAULT_VISCOSITY_PA_S,
    ELASTIC,
    MECHANISMS,
    PIN_TOLERANCE,
    check_names,
    with_compliance,
)
from ..inverse.comparison.table import render_params, render_table
from ..inverse.problem import SHAPE_FLOOR
from ..models import Base
from ..models.presets import preset_section
from ..params import MECHANISM_NAMES
from ..units import ORGANISMS, Units
from . import _values, common

MAX_STARTS = 100
COMPLIANCE_MODES = {
    "off": False,
    "on": True,
    "elastic": "elastic",
    "both": "both",
    "both-elastic": "both-elastic",
    "all": "all",
}
"""``--compliance``'s values and :func:`axojax.compare`'s ``compliance`` for each."""
COEFFICIENTS = {
    "chi": "sliding",
    "beta": "curvature",
    **{
        n: ("sliding" if n.startswith("chi") else "curvature")
        for n in MECHANISM_NAMES
        if not n.startswith("normal")  # normal-force rows of compare: issue 55, later
    },
}
"""Coefficient names a user may type instead of a mechanism, and the mechanism they belong
to (``omega0`` is every regulated mechanism's: it is pinned at the data's frequency)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--data",
        required=True,
        metavar="FILE",
        help="beat data (kymograph, centreline or Fourier-mode file) or a bundled name (human_sperm)",
    )
    parser.add_argument(
        "--mechanisms",
        default=None,
        metavar="LIST",
        help=f"comma-separated mechanisms (default all: {','.join(MECHANISMS)})",
    )
    parser.add_argument(
        "--bases",
        default=None,
        metavar="LIST",
        help=f"comma-separated base conditions of {','.join(BASES)}, each optionally with "
        f"{COMPLIANCE} or {ELASTIC} (e.g. head{COMPLIANCE}; default {','.join(DEFAULT_BASES)})",
    )
    parser.add_argument(
        "--compliance",
        default=None,
        metavar="MODE",
        help="basal compliance chi_b = k_b + i omega xi_b on every base: off (as --bases "
        "names them), on (the compliance 1/k_b and xi_b fitted besides the mechanism's "
        "values), elastic (1/k_b fitted, xi_b negligible), both / both-elastic (every base "
        "without and with 'on' / 'elastic'), all (the three). Default: both-elastic for "
        "the default bases, off when --bases is given",
    )
    parser.add_argument(
        "--frame",
        choices=("lab", "basal"),
        default="lab",
        help="the frame psi is compared in: lab (as recorded, default: a lab-frame beat suits "
        "free and head bases, a head-fixed one clamped bases) or basal (model and data "
        "relative to the basal tangent, psi(s) - psi(0); docs/model.md section 8, frames); "
        "with --target limit-cycle, lab compares psi_0 up to the recording's reference angle "
        "(each row's psi_offset_rad), basal exactly",
    )
    parser.add_argument(
        "--model",
        default=DEFAULT_PRESET,
        choices=COMPARE_PRESETS,
        help=f"the preset every row uses (default {DEFAULT_PRESET}: the two-filament continuum limit of "
        "the published fits this comparison follows, Sartori et al. 2016 and Riedel-Kruse et al. 2007; "
        "the fastest)",
    )
    parser.add_argument(
        "--elements",
        type=int,
        default=DEFAULT_ELEMENTS,
        metavar="N",
        help=f"elements per filament (default {DEFAULT_ELEMENTS})",
    )
    du = Units()
    parser.add_argument(
        "--organism",
        default=None,
        metavar="NAME",
        help="kappa, xi_n and head size of an organism: " + ", ".join(ORGANISMS) + " (sources: "
        "docs/mechanisms.md); --kappa/--xi-n/--ei/--cn/--head-um override its values",
    )
    parser.add_argument(
        "--kappa",
        type=common.finite_float,
        default=None,
        metavar="PN_UM2",
        help="the whole flagellum's bending rigidity kappa, pN um^2 (shared by the model's filaments)",
    )
    parser.add_argument(
        "--xi-n",
        type=common.finite_float,
        default=None,
        metavar="PN_S_UM2",
        help="the whole flagellum's normal drag coefficient xi_n per length, pN s/um^2 (water: about 3e-3)",
    )
    parser.add_argument(
        "--ei",
        type=common.finite_float,
        default=None,
        metavar="PN_UM2",
        help="EI of ONE filament, pN um^2 (= kappa / F, F the model's filaments: 2 for 'two'); "
        f"instead of --kappa (default: the bundled data set's, --organism's, else {du.ei_pn_um2:.4g})",
    )
    parser.add_argument(
        "--cn",
        type=common.finite_float,
        default=None,
        metavar="PN_S_UM2",
        help="normal drag coefficient of ONE filament, pN s/um^2 (= xi_n / F); instead of --xi-n "
        f"(default: the bundled data set's, --organism's, else {du.cn_pn_s_um2:g})",
    )
    parser.add_argument(
        "--sperm-number",
        type=common.finite_float,
        default=None,
        metavar="SP",
        help="the beat's sperm number omega xi_n L^4 / kappa instead of --cn (c_n set to give it, with --ei)",
    )
    parser.add_argument(
        "--head-um",
        default=None,
        metavar="A,B",
        help="the head base's prolate ellipsoid semi-axes A >= B in um (default "
        f"{DEFAULT_HEAD_UM[0]:g},{DEFAULT_HEAD_UM[1]:g}: a human sperm head) in --viscosity-pa-s",
    )
    parser.add_argument(
        "--viscosity-pa-s",
        type=common.finite_float,
        default=None,
        metavar="MU",
        help=f"the head's fluid viscosity, Pa s (default {DEFAULT_VISCOSITY_PA_S:g}, water)",
    )
    parser.add_argument(
        "--starts",
        type=int,
        default=3,
        metavar="N",
        help="least-squares starts per row: the best of the screened Hopf points and Sobol design (default 3)",
    )
    parser.add_argument(
        "--seed", type=int, default=0, metavar="N", help="seed of the Sobol design (default 0)"
    )
    parser.add_argument(
        "--shape-floor",
        type=common.finite_float,
        default=SHAPE_FLOOR,
        metavar="RAD",
        help=f"model-discrepancy floor added in quadrature to psi_1's sigma (default {SHAPE_FLOOR:g} rad)",
    )
    parser.add_argument(
        "--pin-tolerance",
        type=common.finite_float,
        default=PIN_TOLERANCE,
        metavar="REL",
        help="relative uncertainty of the two targets that hold every row's beat at the observation "
        f"(growth rate 0 and the data's frequency; default {PIN_TOLERANCE:g})",
    )
    parser.add_argument(
        "--out",
        default=None,
        metavar="REPORT.json",
        help="save the comparison (drawn by 'axojax plot REPORT.json')",
    )
    parser.add_argument(
        "--params",
        action="store_true",
        help="also print every row's fitted values in physical units with standard errors: "
        "chi' and chi'' in pN/um^2, beta' and beta'' in pN, p in pN/um, the basal compliance "
        "1/k_b in um/pN (or the spring k_b in pN/um) and friction xi_b in pN s/um, the links' "
        "k_l and k_s in pN/um^2 and damping c_l in pN s/um^2, gamma a number; with --target "
        "limit-cycle also m0 in pN, f_sat in pN/um and tau_m in ms. A value the pins alone fix "
        "(the beat held at the observed frequency) is marked pinned, without an error",
    )
    parser.add_argument(
        "--target",
        choices=("linear", "limit-cycle"),
        default="linear",
        help="linear (default): psi_1's shape at a Hopf point, amplitude free; limit-cycle: the "
        "whole beat (frequency, psi_0, psi_1 with its amplitude) by each regulated mechanism's "
        "limit cycle with motor kinetics, saturating motors and a static moment",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _names(text: str | None, flag: str) -> list[str] | None:
    if text is None:
        return None
    names = [t.strip() for t in text.split(",")]
    if not all(names):
        raise common.CLIError(f"{flag}: empty name in {text!r}")
    if flag == "--mechanisms":
        for n in names:
            if n in COEFFICIENTS:
                raise common.CLIError(
                    f"--mechanisms: {n!r} is a coefficient of {COEFFICIENTS[n]}, not a mechanism; "
                    f"give --mechanisms {COEFFICIENTS[n]} (its coefficients are fitted)"
                )
    return names


def run(args: argparse.Namespace) -> dict:
    common.check_output("--out", args.out, (".json",))
    mechanisms = _names(args.mechanisms, "--mechanisms")
    bases = _names(args.bases, "--bases")
    try:
        check_names(mechanisms, bases, mechanism_flag="--mechanisms", base_flag="--bases")
    except ValueError as err:
        raise common.CLIError(str(err)) from None
    if args.compliance is not None and args.compliance not in COMPLIANCE_MODES:
        raise common.CLIError(
            f"--compliance: expected one of {', '.join(COMPLIANCE_MODES)}, got {args.compliance!r}"
        )
    try:
        bases = with_compliance(bases, COMPLIANCE_MODES.get(args.compliance))
        check_names(mechanisms, bases, mechanism_flag="--mechanisms", base_flag="--compliance")
    except ValueError as err:
        raise common.CLIError(str(err)) from None
    if not 2 <= args.elements <= 200:
        raise common.CLIError(f"--elements: expected an integer in 2..200, got {args.elements}")
    if not 1 <= args.starts <= MAX_STARTS:
        raise common.CLIError(
            f"--starts: expected an integer in 1..{MAX_STARTS}, got {args.starts}"
        )
    if args.shape_floor < 0:
        raise common.CLIError(f"--shape-floor: must be >= 0 rad, got {args.shape_floor:g}")
    if not 0 < args.pin_tolerance < 1:
        raise common.CLIError(f"--pin-tolerance: must be in (0, 1), got {args.pin_tolerance:g}")
    if args.sperm_number is not None:
        if args.cn is not None:
            raise common.CLIError("--sperm-number: sets c_n; give --sperm-number or --cn, not both")
        if not args.sperm_number > 0:
            raise common.CLIError(f"--sperm-number: must be > 0, got {args.sperm_number:g}")
    from ..beats import read_beat

    try:
        beat = read_beat(args.data)
    except (ValueError, OSError) as err:
        raise common.CLIError(f"--data: {err}") from None
    units, organism, head = _units_and_head(args, beat, bases)
    if args.target == "limit-cycle":
        return _whole_beat(args, beat, units, organism)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = compare(
                beat,
                mechanisms,
                bases,
                args.model,
                n_elements=args.elements,
                units=units,
                sperm_number=args.sperm_number,
                starts=args.starts,
                seed=args.seed,
                shape_floor=args.shape_floor,
                pin_tolerance=args.pin_tolerance,
                progress=progress_enabled(),
                head=head,
                organism=organism,
                frame=args.frame,
            )
    except ValueError as err:
        if str(err).startswith("AXOJAX_"):  # an environment setting names itself
            raise common.CLIError(str(err)) from None
        raise common.CLIError(f"--data: {err}") from None
    return _document(args, result)


def _document(args: argparse.Namespace, result) -> dict:
    """The comparison's JSON document, the data file named, written to ``--out``."""
    doc = result.to_json()
    doc["data"]["file"] = str(args.data)
    if args.out is not None:
        import json

        from .. import _io

        try:
            _io.write_text(args.out, json.dumps(doc, indent=1, allow_nan=False) + "\n")
        except OSError as err:
            raise common.CLIError(f"--out: cannot write {args.out!r} ({err})") from None
        doc["out"] = str(args.out)
    if args.params and not args.json:
        doc["show_params"] = True  # read by render only (the terminal's second table)
    return doc


def _whole_beat(args: argparse.Namespace, beat, units, organism) -> dict:
    """``--target limit-cycle``: :func:`~axojax.inverse.whole_beat.compare.compare_whole_beat`."""
    from ..inverse.whole_beat.compare import DEFAULT_BASES as WHOLE_BASES
    from ..inverse.whole_beat.compare import MECHANISMS as WHOLE_MECHANISMS
    from ..inverse.whole_beat.compare import compare_whole_beat

    for flag, value in (
        ("--compliance", args.compliance),
        ("--sperm-number", args.sperm_number),
        ("--head-um", args.head_um),
    ):
        if value is not None:
            raise common.CLIError(
                f"{flag}: not with --target limit-cycle (its rows take compliance from --bases, "
                "e.g. clamped+elastic, and the drag and head from the data or --organism)"
            )
    mechanisms = _names(args.mechanisms, "--mechanisms") or WHOLE_MECHANISMS
    bases = _names(args.bases, "--bases") or WHOLE_BASES
    flag = "--mechanisms" if args.mechanisms else "--data"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = compare_whole_beat(
                beat,
                mechanisms,
                bases,
                args.model,
                n_elements=args.elements,
                units=units,
                organism=organism,
                progress=progress_enabled(),
                frame=args.frame,
            )
    except ValueError as err:
        msg = str(err)
        for name in ("bases", "mechanisms"):
            if msg.startswith(f"{name}: "):
                raise common.CLIError(f"--{msg}") from None
        raise common.CLIError(f"{flag}: {msg}") from None
    return _document(args, result)


def _units_and_head(args: argparse.Namespace, beat, bases):
    """The comparison's units (None: the library's default, named in the table), organism
    and head from the flags; one warning line on stderr when a file of one's own comes
    with no units at all."""
    for a, b in (("kappa", "ei"), ("xi_n", "cn")):
        if getattr(args, a) is not None and getattr(args, b) is not None:
            flag = "--" + a.replace("_", "-")
            raise common.CLIError(
                f"{flag}: give --{a.replace('_', '-')} (whole flagellum) or --{b} (per filament), not both"
            )
    if args.xi_n is not None and args.sperm_number is not None:
        raise common.CLIError(
            "--sperm-number: sets the drag; give --sperm-number or --xi-n, not both"
        )
    organism = None
    if args.organism is not None:
        key = args.organism.strip().lower().replace("-", "_")
        if key not in ORGANISMS:
            raise common.CLIError(
                f"--organism: unknown name {args.organism!r}; choose from {', '.join(ORGANISMS)}"
            )
        organism = ORGANISMS[key]
    n_f = preset_section(args.model).n_filaments
    given = {
        "ei": args.ei if args.kappa is None else args.kappa / n_f,
        "cn": args.cn if args.xi_n is None else args.xi_n / n_f,
    }
    units = None
    if any(v is not None for v in given.values()):
        try:
            units, _ = beat_units(
                beat, n_f, ei_pn_um2=given["ei"], cn_pn_s_um2=given["cn"], organism=organism
            )
        except ValueError as err:
            flag = (
                ("--kappa" if args.kappa is not None else "--ei")
                if "ei_pn_um2" in str(err)
                else ("--xi-n" if args.xi_n is not None else "--cn")
            )
            raise common.CLIError(f"{flag}: {err}") from None
    if units is None and organism is None and beat.flagellum is None and args.sperm_number is None:
        u = Units()
        print(
            f"axojax: compare: warning: {args.data} carries no units: using axojax's defaults (kappa "
            f"{u.ei_pn_um2 * n_f:.4g} pN um^2, xi_n {u.cn_pn_s_um2 * n_f:.3g} pN s/um^2: a 12 um cilium's); "
            "give your organism's with --organism NAME or --kappa PN_UM2 --xi-n PN_S_UM2",
            file=sys.stderr,
        )
    head = None
    if args.head_um is not None or args.viscosity_pa_s is not None:
        if bases is not None and not any(b.startswith("head") for b in bases):
            flag = "--head-um" if args.head_um is not None else "--viscosity-pa-s"
            raise common.CLIError(f"{flag}: needs the head base in --bases")
        if args.head_um is not None:
            a, b = _values._pair(args.head_um, "--head-um")
        else:
            a, b = DEFAULT_HEAD_UM if organism is None else organism.head_um
        mu = DEFAULT_VISCOSITY_PA_S if args.viscosity_pa_s is None else args.viscosity_pa_s
        try:
            head_units = units or beat_units(beat, n_f, organism=organism)[0]
            head = Base.head_from_ellipsoid(a, b, mu, head_units)
        except ValueError as err:
            flag = "--viscosity-pa-s" if "viscosity" in str(err) else "--head-um"
            raise common.CLIError(f"{flag}: {err}") from None
    return units, organism, head


def render(doc: dict) -> str:
    if doc.get("kind") == "whole_beat_comparison":
        from ..inverse.whole_beat.compare import render as render_whole

        text = render_whole(doc, doc.pop("show_params", False))
        return text + (f"\nsaved {doc['out']}" if "out" in doc else "")
    text = render_table(doc)
    if doc.pop("show_params", False):
        text += "\n\n" + render_params(doc)
    if "out" in doc:
        text += f"\nsaved {doc['out']} (draw it with 'axojax plot {doc['out']}')"
    return text
