"""The flags of regulated dynein and base conditions (docs/model.md section 8) as model
and parameter values: ``--mechanism``/``--chi``/``--beta``/``--omega0-hz``, ``--base``,
``--basal-compliance``, ``--head-um``/``--head-drag``/``--viscosity-pa-s``; motor kinetics
``--motor-tau-ms`` and ``--motor-saturation`` (and their line in a text report); and the
refusal of an active friction where the time domain is needed (without motor kinetics)."""

from __future__ import annotations

import argparse

from ..models import Base, Model
from ..params import Params
from ._values import CLIError, _complex_pair, _pair, finite_float, units_from_args

MECHANISMS = ("steady", "sliding", "curvature", "sliding+curvature", "normal-force")
"""``--mechanism`` choices (docs/model.md section 8)."""
NORMAL_FORCE_COMMANDS = ("modes", "fit")
"""The subcommands that take ``--mechanism normal-force`` so far (issue 55: the linear
mode; ``fit`` without ``--target limit-cycle``)."""
MECHANISM_FLAGS = {
    "chi_re": "chi",
    "chi_im": "chi",
    "beta_re": "beta",
    "beta_im": "beta",
    "normal_re": "normal-gain",
    "normal_im": "normal-gain",
    "omega0": "omega0-hz",
    "m0": "static-moment-pn",
}
"""Params fields of regulated dynein (and the static moment) -> the flag that sets them."""
BASE_FLAGS = {"kb": "basal-compliance", "xib": "basal-compliance"}
"""Params fields of the basal compliance -> the flag that sets them."""
DEFAULT_VISCOSITY_PA_S = 1e-3
"""``--viscosity-pa-s`` default (water): the fluid of a head given by ``--head-um``."""


def require_passive_friction(model: Model, params: Params, what: str, motors: bool = False) -> None:
    """The time domain's condition as a CLI error: unless ``motors`` (motor kinetics,
    ``--motor-tau-ms``, makes any friction well posed), no active friction
    (:func:`axojax.well_posed.require_passive_friction`, naming ``--beta`` or ``--chi``).
    Every base is taken (orbits on a base that moves: :mod:`axojax.orbits.rigid`)."""
    from ..well_posed import require_passive_friction as check

    if motors:
        return
    try:
        check(model, params, what)
    except ValueError as err:
        flag = "--beta" if str(err).split(": ", 1)[1].startswith("beta") else "--chi"
        raise CLIError(f"{flag}: {err}") from None


def base_from_args(args: argparse.Namespace) -> Base:
    """The :class:`~axojax.models.Base` of ``--base``, ``--basal-compliance``,
    ``--head-um``/``--head-drag`` and ``--viscosity-pa-s`` (units from the unit flags). A
    base's constant without its base, or a head without its size or drags: one line
    naming the flag."""
    kind = getattr(args, "base", "clamped") or "clamped"
    head_um, head_drag = getattr(args, "head_um", None), getattr(args, "head_drag", None)
    mu = getattr(args, "viscosity_pa_s", None)
    compliance = getattr(args, "basal_compliance", None) is not None
    for flag, value in (("--head-um", head_um), ("--head-drag", head_drag)):
        if value is not None and kind != "head":
            raise CLIError(f"{flag}: needs --base head (got --base {kind})")
    if mu is not None and head_um is None:
        raise CLIError("--viscosity-pa-s: needs --base head with --head-um")
    if kind != "head":
        return Base(kind, compliance=compliance)
    if (head_um is None) == (head_drag is None):
        raise CLIError(
            "--base head: needs its size --head-um A,B or its drags --head-drag XI_T,XI_R (one of them)"
        )
    units = units_from_args(args)
    try:
        if head_um is not None:
            a, b = _positive_pair(head_um, "--head-um")
            mu = DEFAULT_VISCOSITY_PA_S if mu is None else mu
            if not mu > 0:
                raise CLIError(f"--viscosity-pa-s: must be > 0, got {mu:g}")
            return Base.head_from_ellipsoid(a, b, mu, units, compliance=compliance)
        zt, zr = _positive_pair(head_drag, "--head-drag")
        return Base(
            "head",
            compliance=compliance,
            translational_drag=float(units.head_translational_drag(zt)),
            rotational_drag=float(units.head_rotational_drag(zr)),
        )
    except ValueError as err:
        raise CLIError(f"{'--head-um' if head_um is not None else '--head-drag'}: {err}") from None


def _positive_pair(text: str, flag: str) -> tuple[float, float]:
    x, y = _pair(text, flag)
    for v in (x, y):
        if not v > 0:
            raise CLIError(f"{flag}: expected two numbers > 0, got {text!r}")
    return x, y


def basal_values(args: argparse.Namespace) -> dict[str, float]:
    """``kb``, ``xib`` (dimensionless) of ``--basal-compliance K_B,XI_B`` (pN/um, pN s/um);
    XI_B must be > 0 (it keeps the damping regular), K_B >= 0."""
    text = getattr(args, "basal_compliance", None)
    if text is None:
        return {}
    kb, xib = _pair(text, "--basal-compliance")
    if not (kb >= 0 and xib > 0):
        raise CLIError(
            f"--basal-compliance: expected K_B >= 0 (pN/um) and XI_B > 0 (pN s/um), got {text!r}"
        )
    units = units_from_args(args)
    return {
        "kb": float(units.kb_from_pn_per_um(kb)),
        "xib": float(units.xib_from_pn_s_per_um(xib)),
    }


def mechanism_values(args: argparse.Namespace) -> dict[str, float]:
    """The regulated-dynein flags (and ``--static-moment-pn``) as dimensionless Params
    fields (docs/model.md section 8).
    A coefficient without its mechanism, or a mechanism without its coefficient, is
    refused in one line naming the flag."""
    mechanism = getattr(args, "mechanism", "steady") or "steady"
    parts = set(mechanism.split("+")) - {"steady"}
    values: dict[str, float] = {}
    units = units_from_args(args)
    command = getattr(args, "command", None)
    if "normal-force" in parts and command not in NORMAL_FORCE_COMMANDS:
        raise CLIError(
            f"--mechanism normal-force: only axojax {' and '.join(NORMAL_FORCE_COMMANDS)} takes it so far, "
            f"not {command} (issue 55)"
        )
    for flag, part, names, convert in (
        ("chi", "sliding", ("chi_re", "chi_im"), units.chi_from_pn_per_um2),
        ("beta", "curvature", ("beta_re", "beta_im"), units.beta_from_pn),
        ("normal_gain", "normal-force", ("normal_re", "normal_im"), float),
    ):
        text = getattr(args, flag, None)
        shown = flag.replace("_", "-")
        if text is None:
            if part in parts:
                raise CLIError(f"--mechanism {mechanism}: needs --{shown} RE,IM")
            continue
        if part not in parts:
            also = "" if part == "normal-force" else " or sliding+curvature"
            raise CLIError(f"--{shown}: needs --mechanism {part}{also}")
        re, im = _complex_pair(text, shown)
        values[names[0]], values[names[1]] = float(convert(re)), float(convert(im))
    hz = getattr(args, "omega0_hz", None)
    if hz is not None:
        if not parts:
            raise CLIError(
                "--omega0-hz: needs --mechanism sliding, curvature, sliding+curvature or normal-force"
            )
        if hz <= 0:
            raise CLIError(f"--omega0-hz: must be > 0, got {hz:g}")
        values["omega0"] = float(units.omega0_from_hz(hz))
    m0 = getattr(args, "static_moment_pn", None)
    if m0 is not None:
        values["m0"] = float(units.moment_from_pn(m0))
    return values


def add_motor_tau_flag(parser: argparse.ArgumentParser, what: str) -> None:
    """``--motor-tau-ms MS`` (docs/model.md section 8, motor kinetics); ``what`` ends its
    help (what the command does with it)."""
    parser.add_argument(
        "--motor-tau-ms",
        type=finite_float,
        default=None,
        metavar="MS",
        help="motor kinetics of relaxation time MS (ms) for a regulated mechanism (docs/model.md "
        f"section 8): the same beat at omega0, well posed even with an active friction; {what}",
    )


def motor_tau_from_args(args: argparse.Namespace, params: Params) -> float | None:
    """The dimensionless motor time tau_m (``--motor-tau-ms`` ms over the unit flags' tau),
    or None without the flag. One-line :class:`CLIError` naming ``--motor-tau-ms`` for a
    value not > 0, outside :func:`~axojax.assembly.motor_kinetics.check_tau_m`'s range, or
    without a regulated mechanism at a beat frequency (``--omega0-hz``)."""
    from ..assembly.motor_kinetics import check_tau_m

    tau_ms = getattr(args, "motor_tau_ms", None)
    if tau_ms is None:
        return None
    if not tau_ms > 0:
        raise CLIError(f"--motor-tau-ms: must be > 0 ms, got {tau_ms:g}")
    if not float(params.omega0) > 0:
        raise CLIError(
            "--motor-tau-ms: needs a regulated mechanism at a beat frequency (--mechanism, --chi "
            "or --beta, --omega0-hz)"
        )
    tau_m = tau_ms * 1e-3 / units_from_args(args).tau_s
    try:
        check_tau_m(params, tau_m)
    except ValueError as err:
        raise CLIError(f"--motor-tau-ms: {tau_ms:g} ms: {err}") from None
    return tau_m


def add_motor_saturation_flag(parser: argparse.ArgumentParser) -> None:
    """``--motor-saturation PN_PER_UM`` (docs/model.md section 8, saturating motors)."""
    parser.add_argument(
        "--motor-saturation",
        type=finite_float,
        default=None,
        metavar="PN_PER_UM",
        help="saturating motors: the regulated force per length passes through "
        "F tanh(f / F), F in pN/um (with --motor-tau-ms; docs/model.md section 8)",
    )


def motor_saturation_from_args(args: argparse.Namespace, tau_m: float | None) -> float | None:
    """The dimensionless saturation f_sat (``--motor-saturation`` pN/um scaled as ``p``:
    L^3 / EI), or None without the flag. One-line :class:`CLIError` naming the flag for a
    value not > 0 or beyond the library's range, or without ``--motor-tau-ms``
    (``tau_m`` None)."""
    from ..dynamics.saturation import check_saturation

    value = getattr(args, "motor_saturation", None)
    if value is None:
        return None
    if not value > 0:
        raise CLIError(f"--motor-saturation: must be > 0 pN/um, got {value:g}")
    if tau_m is None:
        raise CLIError("--motor-saturation: needs motor kinetics (--motor-tau-ms)")
    try:
        return check_saturation(units_from_args(args).p_from_pn_per_um(value))
    except ValueError as err:
        raise CLIError(f"--motor-saturation: {value:g} pN/um: {err}") from None


def motor_kinetics_lines(doc: dict, what: str) -> list[str]:
    """The text report's line of a result's ``motor_kinetics`` (``tau_ms``, and
    ``f_sat_pn_per_um`` where the motors saturate), ``what`` in its parentheses (what the
    command computed with them); no line without motor kinetics."""
    motors = doc.get("motor_kinetics")
    if motors is None:
        return []
    sat = motors.get("f_sat_pn_per_um")
    return [
        f"motor kinetics: tau_m = {motors['tau_ms']:g} ms ({what})"
        + ("" if sat is None else f", saturating at {sat:g} pN/um")
    ]


def require_static_normal_force(params: Params) -> None:
    """One-line :class:`CLIError` for normal-force control without a static normal force
    (p = 0 and no ``--static-moment-pn``): its gain would act on nothing."""
    if float(params.p) == 0 and float(params.m0) == 0:
        raise CLIError(
            "--mechanism normal-force: no static normal force (p = 0 and no "
            "--static-moment-pn): the gain would act on nothing"
        )
