"""``axojax compare``: every mechanism x base fitted to one observed beat, ranked by BIC
(:func:`axojax.compare`; docs/mechanisms.md).

Basal compliance: bases named ``KIND+compliance`` / ``KIND+elastic``, or ``--compliance
off|on|elastic|both|both-elastic|all`` for every base (default: the default bases without
and with a basal spring; named bases as named; docs/mechanisms.md, basal compliance).

Units: ``--ei`` and ``--cn`` (per filament); what is not given comes from the data set's
flagellum when it is a bundled one (the human sperm's kappa and xi_n), else from axojax's
defaults (:func:`axojax.inverse.comparison.compare.default_units`); the table says which.

Exit status 0; bad input (an unknown or unavailable mechanism or base, a coefficient
named as a mechanism, a bad --compliance, a bad setting) is one line naming the flag,
exit 2.
"""

from __future__ import annotations

import argparse
import warnings

from .._progress import enabled as progress_enabled
from ..inverse.comparison.compare import compare, default_units, render_params, render_table
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
from ..inverse.problem import SHAPE_FLOOR
from ..models import Base
from ..params import MECHANISM_NAMES
from ..units import Units
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
    **{n: ("sliding" if n.startswith("chi") else "curvature") for n in MECHANISM_NAMES},
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
        "names them), on (kb and xib fitted; a row keeps two values of its own), elastic "
        "(kb fitted, xi_b negligible; a row keeps three), both / both-elastic (every base "
        "without and with 'on' / 'elastic'), all (the three). Default: both-elastic for "
        "the default bases, off when --bases is given",
    )
    parser.add_argument(
        "--model",
        default=DEFAULT_PRESET,
        choices=COMPARE_PRESETS,
        help=f"the preset every row uses (default {DEFAULT_PRESET}: the anchors' two-filament continuum limit, and the fastest)",
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
        "--ei",
        type=common.finite_float,
        default=None,
        metavar="PN_UM2",
        help="EI of one filament, pN um^2 (default: the bundled data set's flagellum, kappa "
        f"shared by the filaments; else {du.ei_pn_um2:.4g}); with --cn it sets the beat's sperm number",
    )
    parser.add_argument(
        "--cn",
        type=common.finite_float,
        default=None,
        metavar="PN_S_UM2",
        help="resistive coefficient of one filament, pN s um^-2 (default: the bundled data "
        f"set's flagellum, xi_n shared by the filaments; else {du.cn_pn_s_um2:g})",
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
        help=f"relative sigma of the pins of the beat: growth rate 0 and the data's frequency (default {PIN_TOLERANCE:g})",
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
        help="also print every row's fitted values in physical units (chi pN/um^2, beta pN, "
        "k_b pN/um, xi_b pN s/um, p pN/um, link stiffness and damping) with standard errors",
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
    # None: the library's default (the data set's flagellum, or axojax's), named in the table
    units = None
    if args.ei is not None or args.cn is not None:
        default, _ = default_units(beat, args.model)
        ei = default.ei_pn_um2 if args.ei is None else args.ei
        cn = default.cn_pn_s_um2 if args.cn is None else args.cn
        try:
            units = Units(beat.length_um, ei, cn)
        except ValueError as err:
            flag = "--ei" if "ei_pn_um2" in str(err) else "--cn"
            raise common.CLIError(f"{flag}: {err}") from None
    head = None
    if args.head_um is not None or args.viscosity_pa_s is not None:
        if bases is not None and not any(b.startswith("head") for b in bases):
            flag = "--head-um" if args.head_um is not None else "--viscosity-pa-s"
            raise common.CLIError(f"{flag}: needs the head base in --bases")
        a, b = DEFAULT_HEAD_UM if args.head_um is None else _values._pair(args.head_um, "--head-um")
        mu = DEFAULT_VISCOSITY_PA_S if args.viscosity_pa_s is None else args.viscosity_pa_s
        try:
            head = Base.head_from_ellipsoid(a, b, mu, units or default_units(beat, args.model)[0])
        except ValueError as err:
            flag = "--viscosity-pa-s" if "viscosity" in str(err) else "--head-um"
            raise common.CLIError(f"{flag}: {err}") from None
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
                progress=progress_enabled(json_output=args.json),
                head=head,
            )
    except ValueError as err:
        raise common.CLIError(f"--data: {err}") from None
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


def render(doc: dict) -> str:
    text = render_table(doc)
    if doc.pop("show_params", False):
        text += "\n\n" + render_params(doc)
    if "out" in doc:
        text += f"\nsaved {doc['out']} (draw it with 'axojax plot {doc['out']}')"
    return text
