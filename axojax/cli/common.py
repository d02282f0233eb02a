"""Flags shared by every subcommand that builds a model, and their validation.

Every bad value ends in :class:`CLIError`, which ``main`` prints as one line on stderr
naming the flag, with a non-zero exit status.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

import numpy as np

from .. import _io, _memory
from .._memory import (
    DENSE_SPECTRUM_BYTES,
    MEMORY_FRACTION,
    dense_unknowns,
    model_bytes,
    physical_memory,
)
from ..beats.reduction import PLANARITY_THRESHOLD
from ..eigen.solvers import SOLVERS, AbstractEigenSolver, Auto, solver_from_name
from ..fem import hermite
from ..models import (
    BASE_KINDS,
    IMBALANCE_KINDS,
    PRESETS,
    CrossSection,
    Model,
    build_model,
    load_section,
)
from ..models.presets import preset_section
from ..params import KNOT_NAMES, PARAM_NAMES, Params, knot_element
from ..units import Units
from ._values import CLIError, _complex_pair, finite_float, units_from_args  # noqa: F401
from .profiles import PROFILE_FLAGS, add_profile_flags, knots_from_args, profile_values
from .regulation import (  # noqa: F401
    BASE_FLAGS,
    DEFAULT_VISCOSITY_PA_S,
    MECHANISM_FLAGS,
    MECHANISMS,
    basal_values,
    base_from_args,
    mechanism_values,
    require_passive_friction,
)

# flag name -> Params field
PARAM_FLAGS = {
    "p": "p",
    "ks": "ks",
    "kl": "kl",
    "cl": "cl",
    "gamma": "gamma",
    "ktheta": "ktheta",
    "out-of-plane": "out_of_plane",
    "inactive-factor": "inactive_factor",
    "imbalance": "imbalance",
    "a0": "a0",
}
FIELD_FLAGS = {v: k for k, v in PARAM_FLAGS.items()}
PROFILE_FIELD_FLAGS = {v: k for k, v in PROFILE_FLAGS.items()}
MAX_ROTATION_DEG = 360.0
"""``--rotation-deg`` beyond one turn is refused (a huge angle is all rounding error)."""
MAX_ELEMENTS = hermite.MAX_ELEMENTS
"""Elements per filament beyond any use (the memory check below refuses most models far
earlier); refused before anything is built."""
MAX_AXIS = 10_000_000
"""Most values on one axis (``a:b:n``)."""
FIGURE_SUFFIXES = (".png", ".pdf", ".svg", ".eps", ".jpg", ".jpeg")


def add_model_source(group, elements: bool = True, default: str = "seven") -> None:
    """``--model`` | ``--model-file``, ``--rotation-deg`` (and ``--elements``) on ``group``."""
    src = group.add_mutually_exclusive_group()
    src.add_argument(
        "--model",
        default=None,
        help=f"preset: {', '.join(PRESETS)}" + (f" (default {default})" if default else ""),
    )
    src.add_argument(
        "--model-file", default=None, metavar="PATH", help="TOML/JSON cross-section file"
    )
    if elements:
        group.add_argument(
            "--elements", default=10, metavar="N", help="elements per filament (default 10)"
        )
    group.add_argument(
        "--rotation-deg",
        type=finite_float,
        default=0.0,
        metavar="DEG",
        help="turn a 3D preset's cross-section by DEG degrees from +z towards +y (default 0: the paper's beat plane)",
    )


def add_model_flags(
    parser: argparse.ArgumentParser,
    params: tuple[str, ...] = tuple(PARAM_FLAGS),
    axes: bool = False,
) -> None:
    """Model, parameter and unit flags; with ``axes`` the parameter flags also take an
    axis (a:b:n, log:a:b:n or v1,v2,...) and are parsed by :func:`split_axes`."""
    g = parser.add_argument_group("model")
    add_model_source(g)
    d = Params()
    for flag in params:
        field = PARAM_FLAGS[flag]
        kind = str if axes else finite_float
        g.add_argument(
            f"--{flag}",
            type=kind,
            default=None,
            metavar="AXIS" if axes else "X",
            help=f"dimensionless {field} (default {getattr(d, field):g})",
        )
    g.add_argument(
        "--mechanism",
        choices=MECHANISMS,
        default="steady",
        help="dynein regulation (docs/model.md section 8): the steady load (default), sliding "
        "control (--chi), curvature control (--beta), both, or normal-force control "
        "(--normal-gain; axojax modes and the linear fit so far)",
    )
    g.add_argument(
        "--chi",
        default=None,
        metavar="RE,IM",
        help="sliding-control coefficient chi' + i chi'' in pN/um^2 (with --mechanism sliding)",
    )
    g.add_argument(
        "--beta",
        default=None,
        metavar="RE,IM",
        help="curvature-control coefficient beta' + i beta'' in pN (with --mechanism curvature)",
    )
    g.add_argument(
        "--normal-gain",
        default=None,
        metavar="RE,IM",
        help="normal-force gain g' + i g'' (dimensionless: motor force per unit normal force; with "
        "--mechanism normal-force and a static bend, e.g. --static-moment-pn)",
    )
    g.add_argument(
        "--omega0-hz",
        type=finite_float,
        default=None,
        metavar="HZ",
        help="beat frequency at which --chi, --beta and --normal-gain hold (needed when an IM part "
        "is non-zero)",
    )
    g.add_argument(
        "--static-moment-pn",
        type=finite_float,
        default=None,
        metavar="PN",
        help="static dynein moment per length m0 (pN um per um = pN; either sign): the static bend "
        "of an asymmetric beat, with any mechanism (docs/model.md section 8)",
    )
    g.add_argument(
        "--base",
        choices=BASE_KINDS,
        default="clamped",
        help="how the axoneme is held at its base (docs/model.md section 8): clamped (default, the "
        "paper), pivot, free (an isolated axoneme) or head (a body with drag: --head-um or --head-drag)",
    )
    g.add_argument(
        "--basal-compliance",
        default=None,
        metavar="K_B,XI_B",
        help="basal sliding of each active pair resisted by a spring K_B (pN/um) and a friction "
        "XI_B (pN s/um, > 0), with any --base",
    )
    g.add_argument(
        "--head-um",
        default=None,
        metavar="A,B",
        help="--base head: the head as a prolate ellipsoid of semi-axes A >= B (um) in a fluid of "
        "--viscosity-pa-s",
    )
    g.add_argument(
        "--head-drag",
        default=None,
        metavar="XI_T,XI_R",
        help="--base head: its translational (pN s/um) and rotational (pN um s) drags, instead of --head-um",
    )
    g.add_argument(
        "--viscosity-pa-s",
        type=finite_float,
        default=None,
        metavar="MU",
        help=f"fluid viscosity for --head-um (Pa s = pN s/um^2; default {DEFAULT_VISCOSITY_PA_S:g}, water)",
    )
    add_profile_flags(g)
    g.add_argument(
        "--imbalance-kind",
        choices=IMBALANCE_KINDS,
        default=IMBALANCE_KINDS[0],
        help="read --imbalance R as a static couple p a0 (1 - 1/R) with balanced forces (moment, the paper's reading, "
        "default) or as group 1 carrying p / R (force); docs/model.md section 3",
    )
    g.add_argument(
        "--kl-ratio",
        type=finite_float,
        default=None,
        metavar="R",
        help="tie kl = ks / R wherever ks is set, swept or fitted",
    )
    u = parser.add_argument_group("units")
    du = Units()
    u.add_argument(
        "--length-um",
        type=finite_float,
        default=du.length_um,
        metavar="UM",
        help="cilium length L in um (default 12)",
    )
    u.add_argument(
        "--ei",
        type=finite_float,
        default=du.ei_pn_um2,
        metavar="PN_UM2",
        help="EI of one filament, pN um^2 (default 800/11)",
    )
    u.add_argument(
        "--cn",
        type=finite_float,
        default=du.cn_pn_s_um2,
        metavar="PN_S_UM2",
        help="resistive (normal drag) coefficient of one filament, pN s/um^2 (default 0.003)",
    )
    parser.add_argument(
        "--json", action="store_true", help="print one JSON document on stdout and nothing else"
    )


def add_solver_flag(parser: argparse.ArgumentParser) -> None:
    """``--solver {auto,dense,arnoldi}``: the dominant-eigenpair solver."""
    parser.add_argument(
        "--solver",
        default="auto",
        metavar="NAME",
        help=f"dominant-eigenpair solver: {', '.join(SOLVERS)} (default auto: certified Arnoldi on the "
        f"block-tridiagonal pencil for models of {Auto().min_arnoldi_dof}+ unknowns, and for "
        "sweeps (or traced boundaries) of "
        f"{Auto().min_batch_points}+ points on models of {Auto().min_batch_dof}+ unknowns; dense otherwise)",
    )


def add_planarity_flag(parser: argparse.ArgumentParser) -> None:
    """``--planarity-threshold R`` (``axojax data``, ``axojax fit --data``): a 3D beat whose
    transverse singular values have s3/s2 below R is planar (one component of psi_1)."""
    parser.add_argument(
        "--planarity-threshold",
        type=finite_float,
        default=PLANARITY_THRESHOLD,
        metavar="R",
        help=f"3D beats with s3/s2 below R are planar (default {PLANARITY_THRESHOLD:g})",
    )


def check_planarity_threshold(args: argparse.Namespace) -> None:
    """One line for a ``--planarity-threshold`` that is not > 0."""
    value = getattr(args, "planarity_threshold", None)
    if value is not None and not value > 0:
        raise CLIError(f"--planarity-threshold: must be > 0, got {value:g}")


def solver_from_args(args: argparse.Namespace) -> AbstractEigenSolver:
    try:
        return solver_from_name(args.solver)
    except ValueError as err:
        raise CLIError(f"--solver: {err}") from None


def split_axes(
    args: argparse.Namespace, argv: list[str]
) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """Parameter flags given as strings -> (fixed values, axes in command-line order)."""
    fixed, axes = {}, {}
    for flag, field in PARAM_FLAGS.items():
        text = getattr(args, field, None)
        if text is None:
            continue
        if ":" in text or "," in text:
            axes[field] = parse_axis(text, f"--{flag}")
        else:
            try:
                fixed[field] = finite_float(text)
            except argparse.ArgumentTypeError as err:
                raise CLIError(f"--{flag}: {err}") from None
    fixed.update(mechanism_values(args))
    fixed.update(basal_values(args))
    fixed.update(profile_values(args))
    position = {
        f: min(
            [
                i
                for i, a in enumerate(argv)
                if a == f"--{FIELD_FLAGS[f]}" or a.startswith(f"--{FIELD_FLAGS[f]}=")
            ]
            or [0]
        )
        for f in axes
    }
    return fixed, dict(sorted(axes.items(), key=lambda kv: position[kv[0]]))


def check_memory(need_bytes: float, flag: str, what: str) -> None:
    """Refuse (one line naming ``flag``, with the estimate) work whose estimated memory
    exceeds :data:`axojax._memory.MEMORY_FRACTION` of the physical memory."""
    try:
        _memory.check_memory(need_bytes, what)
    except ValueError as err:
        raise CLIError(f"{flag}: {err}") from None


def check_model_size(section: CrossSection, n_elements: int, flag: str) -> None:
    """Refuse (one line naming ``flag``) a model whose estimated memory
    (:func:`axojax._memory.model_bytes`) exceeds the machine's, before it is built."""
    try:
        _memory.check_model_size(section, n_elements)
    except ValueError as err:
        raise CLIError(f"{flag}: {err}") from None


def model_from_args(args: argparse.Namespace, dense_spectrum: bool = False) -> Model:
    """The model of ``--model``/``--model-file``/``--elements``/``--rotation-deg``; its
    size is checked (:func:`check_memory`) before it is built, with ``dense_spectrum``
    also the dense matrices of its full spectrum (``axojax modes`` lists it)."""
    try:
        n = int(str(args.elements))
    except ValueError:
        raise CLIError(f"--elements: expected an integer >= 1, got {args.elements!r}") from None
    if not 1 <= n <= MAX_ELEMENTS:
        raise CLIError(f"--elements: expected an integer in 1..{MAX_ELEMENTS}, got {n}")
    if abs(args.rotation_deg) > MAX_ROTATION_DEG:
        raise CLIError(
            f"--rotation-deg: expected degrees in -{MAX_ROTATION_DEG:g}..{MAX_ROTATION_DEG:g}, "
            f"got {args.rotation_deg:g}"
        )
    if args.model_file is not None:
        source = "--model-file"
        if args.rotation_deg != 0.0:
            raise CLIError(
                "--rotation-deg: applies to presets; a --model-file gives its positions itself"
            )
    else:
        source = "--model"
    try:
        if args.model_file is not None:
            section = load_section(args.model_file)
        else:
            section = preset_section(
                "seven" if args.model is None else args.model, args.rotation_deg
            )
    except ValueError as err:
        flag = "--rotation-deg" if (source == "--model" and "rotation_deg" in str(err)) else source
        raise CLIError(f"{flag}: {err}") from None
    # blame --elements when the cross-section itself would fit at the default mesh
    check_model_size(
        section,
        n,
        "--elements" if model_bytes(section, 10) <= MEMORY_FRACTION * physical_memory() else source,
    )
    if dense_spectrum:
        check_memory(
            DENSE_SPECTRUM_BYTES * dense_unknowns(section, n) ** 2,
            "--elements",
            f"the full spectrum of {dense_unknowns(section, n)} unknowns (dense matrices)",
        )
    knots = knots_from_args(args)
    try:
        model = build_model(
            section,
            n,
            imbalance_kind=getattr(args, "imbalance_kind", IMBALANCE_KINDS[0]),
            base=base_from_args(args),
        )
    except ValueError as err:
        raise CLIError(f"{source}: {err}") from None
    if getattr(args, "p_knots", None) is not None and section.load == "tip":
        raise CLIError(
            f"--p-knots: {source} {section.name!r} is loaded by a tip force, not along its length"
        )
    return model.with_knots(knots)


def check_output(flag: str, path: str | None, suffixes: tuple[str, ...]) -> None:
    """The one output-path rule of every command (:func:`axojax._io.check_output_path`),
    applied before any work; None (flag not given) passes."""
    if path is None:
        return
    try:
        _io.check_output_path(path, suffixes)
    except ValueError as err:
        raise CLIError(f"{flag}: {err}") from None


def kl_ratio(args: argparse.Namespace) -> float | None:
    r = getattr(args, "kl_ratio", None)
    if r is None:
        return None
    if getattr(args, "kl", None) is not None:
        raise CLIError("--kl-ratio: sets kl = ks / R, so it conflicts with --kl; give one of them")
    if not 1e-9 <= r <= 1e9:
        raise CLIError(f"--kl-ratio: expected a ratio in 1e-09..1e+09, got {r:g}")
    return r


def params_from_args(args: argparse.Namespace) -> Params:
    values = {}
    for flag, field in PARAM_FLAGS.items():
        v = getattr(args, field, None)
        if v is not None:
            values[field] = v
    values.update(mechanism_values(args))
    values.update(basal_values(args))
    values.update(profile_values(args))
    ratio = kl_ratio(args)
    check_params(Params().with_values(values))  # the flags as given, before kl is tied
    params = Params().with_values(values, ratio)
    check_params(params, "--kl-ratio" if ratio is not None else None)
    return params


def check_params(params: Params, tied: str | None = None) -> None:
    """:meth:`Params.validate` as a :class:`CLIError` naming the flag (``tied``, e.g.
    ``--kl-ratio``, is blamed for a bad kl when kl is derived from it)."""
    try:
        params.validate()
    except ValueError as err:
        named = str(err).split()[1] if str(err).startswith("parameter ") else None
        bad = (
            named
            if named in PARAM_NAMES + KNOT_NAMES
            else next((f for f in PARAM_NAMES if f" {f} " in f" {err} "), None)
        )
        name = (
            FIELD_FLAGS.get(bad)
            or MECHANISM_FLAGS.get(bad)
            or BASE_FLAGS.get(bad)
            or PROFILE_FIELD_FLAGS.get(bad)
            or bad
        )
        flag = (tied if tied and bad == "kl" else f"--{name}") if bad else "parameters"
        raise CLIError(f"{flag}: {err}") from None


def parse_names(text: str, flag: str) -> list[str]:
    """Comma-separated dimensionless flag names -> Params fields."""
    names = [t.strip() for t in text.split(",") if t.strip()]
    if not names:
        raise CLIError(f"{flag}: expected comma-separated parameter names")
    out = []
    for n in names:
        # a knot value: ei-knots[0] (the flag's spelling) or ei_knots[0]
        element = knot_element(n.replace("-", "_"))
        field = PARAM_FLAGS.get(n) or (n if n in PARAM_NAMES else None)
        if element is not None:
            field = f"{element[0]}[{element[1]}]"
        if field is None:
            raise CLIError(
                f"{flag}: unknown parameter {n!r}; choose from {', '.join(PARAM_FLAGS)} or a "
                "knot value such as ei-knots[0]"
            )
        out.append(field)
    return out


def to_jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, (np.ndarray,)) or hasattr(obj, "__array__"):
        arr = np.asarray(obj)
        return to_jsonable(arr.tolist()) if arr.ndim else to_jsonable(arr.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def emit_json(doc: dict) -> None:
    json.dump(to_jsonable(doc), sys.stdout, indent=2, allow_nan=False)
    sys.stdout.write("\n")


def parse_axis(text: str, flag: str) -> np.ndarray:
    """``a:b:n`` (linear), ``log:a:b:n`` (log-spaced) or ``v1,v2,...`` (explicit) -> values."""
    try:
        if "," in text or ":" not in text:
            items = text.split(",")
            if len(items) > 1 and not all(t.strip() for t in items):
                raise CLIError(f"{flag}: an empty value in the list {text!r}")
            values = np.array([float(t) for t in items if t.strip()])
        else:
            parts = text.split(":")
            log = parts[0] == "log"
            if log:
                parts = parts[1:]
            if len(parts) != 3:
                raise ValueError
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
            if n < 1:
                raise ValueError
            if not (np.isfinite(a) and np.isfinite(b)):
                raise CLIError(f"{flag}: expected finite ends, got {text!r}")
            if n > MAX_AXIS:
                raise CLIError(
                    f"{flag}: an axis of {n} values is more than {MAX_AXIS} (split the sweep), got {text!r}"
                )
            if log:
                if a <= 0 or b <= 0:
                    raise CLIError(f"{flag}: log axis needs positive ends, got {text!r}")
                values = np.logspace(np.log10(a), np.log10(b), n)
            else:
                values = np.linspace(a, b, n)
    except ValueError:
        raise CLIError(
            f"{flag}: expected a:b:n, log:a:b:n or comma-separated values, got {text!r}"
        ) from None
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise CLIError(f"{flag}: expected finite values, got {text!r}")
    return values
