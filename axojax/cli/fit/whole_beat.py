"""``axojax fit --target limit-cycle --data FILE --mechanism M``: the whole beat of a
regulated mechanism (issue 47 item 4; :mod:`axojax.inverse.whole_beat.fit`).

The row is :func:`axojax.compare`'s (``--model``, default ``two``; ``--elements``;
``--base``: any; on a free or head one the orbit's rigid offset is fixed by phase
conditions, :mod:`axojax.orbits.rigid`), fitted first as the linear comparison fits it, then
its limit cycle with motor kinetics (``--motor-tau-ms``, default
:func:`~axojax.inverse.whole_beat.fit.motor_time`), saturating motors and a static dynein
moment against the data's frequency, psi_0 and psi_1 in absolute amplitude.
"""

from __future__ import annotations

import argparse

from ... import _progress
from ...inverse.comparison.mechanisms import build_model, row
from ...inverse.whole_beat.fit import fit_recording
from .. import common
from ..regulation import motor_tau_from_args
from .inputs import data_inputs, finish, given

DEFAULT_MODEL = "two"
EXTRA_FREE = ("tau_m", "cubic")
"""What ``--free`` may add to a whole-beat fit's own free values (the motor time from
``--motor-tau-ms`` or its default, the cubic link stiffening from 0)."""


def _extra_free(args: argparse.Namespace) -> set[str]:
    """The names ``--free`` adds to a whole-beat fit's own free values."""
    return set() if args.free is None else {n.strip() for n in args.free.split(",")}


def check(args: argparse.Namespace) -> None:
    """Flags a whole-beat fit does not take, refused in one line."""
    if _extra_free(args) - set(EXTRA_FREE):
        raise common.CLIError(
            f"--free: a whole-beat fit frees the mechanism's coefficients, f_sat and m0 itself; "
            f"--free adds only {' or '.join(EXTRA_FREE)}, got {args.free!r}"
        )
    for flag, value in (
        ("--spec", args.spec),
        ("--chi", args.chi),
        ("--beta", args.beta),
        ("--posterior", args.posterior),
        ("--observation", args.observation),
        ("--motor-saturation", getattr(args, "motor_saturation", None)),
    ):
        if value is not None:
            raise common.CLIError(
                f"{flag}: a whole-beat fit (--target limit-cycle --mechanism "
                f"{args.mechanism}) fits the mechanism's coefficients, the motors' saturation "
                "and the static moment from the data; leave it out"
            )
    if getattr(args, "basal_compliance", None) is not None:
        raise common.CLIError(
            "--basal-compliance: a whole-beat fit takes the base without compliance in this version"
        )
    if args.data is None:
        raise common.CLIError(
            f"--mechanism {args.mechanism}: a whole-beat fit needs the beat (--data FILE)"
        )


def run(args: argparse.Namespace) -> dict:
    """The whole-beat fit's report (the fit's JSON document plus ``"whole_beat"``)."""
    check(args)
    preset = args.model or DEFAULT_MODEL
    if args.model_file is not None:
        raise common.CLIError("--model-file: a whole-beat fit takes a preset (--model)")
    units = common.units_from_args(args)
    probe = common.model_from_args(argparse.Namespace(**{**vars(args), "model": preset}))
    source = "given" if given(args, "--ei", "--cn") else "axojax's default units"
    args.target = "limit-cycle"
    targets, shape, units, summary, source = data_inputs(args, units, source, probe)
    if shape is None or shape.psi0 is None:
        raise common.CLIError(f"--data: {args.data} gives no psi_0 and psi_1 to fit")
    frequency = next((t for t in targets if t.name == "frequency_hz"), None)
    if frequency is None:
        raise common.CLIError(f"--data: {args.data} gives no beat frequency")
    try:
        elements = int(args.elements)
        model = build_model(preset, elements, args.base, units)
        spec = row(args.mechanism, args.base, model, units, frequency.value)
        tau_m = motor_tau_from_args(args, spec.params)  # at the observed beat; None: default
        extra = _extra_free(args)
        with _progress.stage(
            "fit: the linear row's Hopf point, then the whole beat (compiling, then fitting)"
        ):
            out, linear = fit_recording(
                spec,
                shape,
                frequency,
                units,
                tau_m=tau_m,
                fit_tau_m="tau_m" in extra,
                fit_cubic="cubic" in extra,
                frame=args.frame,
            )
    except ValueError as err:
        raise common.CLIError(f"--mechanism {args.mechanism}: {err}") from None
    extra_free = extra
    extra = {
        "data": summary,
        "units": {
            "length_um": units.length_um,
            "ei_pn_um2": units.ei_pn_um2,
            "cn_pn_s_um2": units.cn_pn_s_um2,
            "source": source,
        },
        "whole_beat": {
            "mechanism": args.mechanism,
            "base": args.base,
            "model": preset,
            "elements": elements,
            "r2_psi1_with_amplitude": out.r2,
            "motor_tau_ms": out.tau_m * units.tau_s * 1e3,
            "motor_tau_omega0": out.tau_m * float(out.params.omega0),
            "motor_tau_source": "fitted"
            if "tau_m" in extra_free
            else ("default" if tau_m is None else "given"),
            "frame": out.frame,
            "psi_offset_rad": out.psi_offset_rad,
            "motor_saturation_pn_per_um": float(units.p_to_pn_per_um(out.f_sat)),
            "static_moment_pn": float(units.moment_to_pn(out.params.m0)),
            "linear_r2": linear.r2,
            "linear_status": linear.status,
        },
    }
    return finish(args, out.fit, extra)


def render(doc: dict) -> list[str]:
    """The whole-beat lines of ``axojax fit``'s text (after the fit's own)."""
    w = doc.get("whole_beat")
    if not w:
        return []
    frame = w.get("frame", "lab")
    if frame == "basal":
        angle = "psi relative to the basal tangent (psi_0 compared exactly)"
    else:
        angle = (
            f"reference angle psi_offset_rad {w.get('psi_offset_rad', 0.0):.4g} (psi_0 "
            "compared up to it: the recording's direction is arbitrary)"
        )
    return [
        f"whole beat: {w['mechanism']} on a {w['base']} base ({w['model']}, {w['elements']} "
        f"elements): motor time {w['motor_tau_ms']:.4g} ms{motor_source(w)}, saturation "
        f"{w['motor_saturation_pn_per_um']:.4g} pN/um, static moment {w['static_moment_pn']:.4g} pN",
        f"R^2 of psi_1 with its amplitude {w['r2_psi1_with_amplitude']:.3f} (the linear row's, "
        f"amplitude free: {w['linear_r2']:.3f}); {angle}",
    ]


def motor_source(w: dict) -> str:
    """Where the motor time came from, as the tables say it: " (default: omega0 tau_m =
    1.5)", " (given)", " (fitted)"; nothing for a document that does not say."""
    source = w.get("motor_tau_source")
    if source == "default":
        return f" (default: omega0 tau_m = {w['motor_tau_omega0']:.3g})"
    return "" if source is None else f" ({source})"
