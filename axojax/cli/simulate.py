"""``axojax simulate``: the nonlinear beat in the time domain, saved to .npz."""

from __future__ import annotations

import argparse
import math
import sys

from .. import _io, _progress
from ..dynamics import simulate
from ..dynamics.simulate import MIN_STEPS, STEPS_PER_PERIOD, check_inputs
from ..params import DEFAULT_CUBIC
from ..waveform.measures import sensitive_note, wavelength_text
from . import common
from .regulation import (
    add_motor_saturation_flag,
    add_motor_tau_flag,
    motor_kinetics_lines,
    motor_saturation_from_args,
    motor_tau_from_args,
)

MAX_STEPS = 100_000_000
"""Largest solver step budget (given or implied by ``--t-end``): beyond it a run would
take days (about 250 steps a period at ~1e4 steps/s)."""
MAX_CUBIC = 1e6
"""Largest ``--cubic`` (1/L^2; default 10): at 1e6 the links stiffen at a displacement of
L/1000, below the resolution of the beat; beyond, the nonlinear solve breaks down."""

FLAGS = {
    "t_end_s": "--t-end",
    "cubic": "--cubic",
    "perturbation_um": "--perturbation-um",
    "rtol": "--rtol",
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    parser.add_argument(
        "--t-end",
        type=common.finite_float,
        required=True,
        metavar="SECONDS",
        help="simulated time (s)",
    )
    parser.add_argument(
        "--cubic",
        type=common.finite_float,
        default=None,
        metavar="KAPPA",
        help=f"cubic link stiffening kappa, 1/L^2 (default {DEFAULT_CUBIC:g}; 0: linear)",
    )
    parser.add_argument(
        "--perturbation-um",
        type=common.finite_float,
        default=0.1,
        metavar="UM",
        help="initial tip displacement in y (default 0.1 um)",
    )
    parser.add_argument(
        "--rtol",
        type=common.finite_float,
        default=1e-6,
        metavar="X",
        help="solver relative tolerance (default 1e-6)",
    )
    parser.add_argument(
        "--max-steps",
        type=int,
        default=None,
        metavar="N",
        help="solver step budget (default: 10000 + 2000 per period of the linear frequency, "
        "rounded up to a multiple of 10000); running out ends in state solver_failed",
    )
    add_motor_tau_flag(
        parser, "the state grows by the motors' filtered copy of it (2N unknowns, dense matrices)"
    )
    add_motor_saturation_flag(parser)
    parser.add_argument(
        "--out", default=None, metavar="FILE.npz", help="write the time series here"
    )
    parser.add_argument(
        "--gif",
        default=None,
        metavar="FILE.gif",
        help="also write an animation of the last beat cycles",
    )


def run(args: argparse.Namespace) -> dict:
    model = common.model_from_args(args)
    params = common.params_from_args(args)
    tau_m = motor_tau_from_args(args, params)
    f_sat = motor_saturation_from_args(args, tau_m)
    if tau_m is None:  # motor kinetics makes an active friction well posed
        common.require_passive_friction(model, params, "simulate")
    units = common.units_from_args(args)
    cubic = DEFAULT_CUBIC if args.cubic is None else args.cubic
    if model.link_B.shape[0] == 0 and args.cubic is None:
        cubic = 0.0  # nothing to stiffen: single filaments are linear
    try:
        check_inputs(model, args.t_end, cubic, args.perturbation_um, args.rtol, names=FLAGS)
    except ValueError as err:
        raise common.CLIError(str(err)) from None
    if cubic > MAX_CUBIC:
        raise common.CLIError(
            f"--cubic: expected at most {MAX_CUBIC:g} (1/L^2; default {DEFAULT_CUBIC:g}), got {cubic:g}"
        )
    if args.perturbation_um > units.length_um:
        raise common.CLIError(
            f"--perturbation-um: a tip displacement of {args.perturbation_um:g} um exceeds the "
            f"cilium length ({units.length_um:g} um, --length-um)"
        )
    if args.rtol >= 1:
        raise common.CLIError(f"--rtol: expected a relative tolerance < 1, got {args.rtol:g}")
    if args.max_steps is not None and not 1 <= args.max_steps <= MAX_STEPS:
        raise common.CLIError(
            f"--max-steps: expected an integer in 1..{MAX_STEPS}, got {args.max_steps}"
        )
    common.check_output("--out", args.out, (".npz",))
    common.check_output("--gif", args.gif, (".gif",))
    n = model.n_dof * (1 if tau_m is None else 2)  # with motor kinetics, and its copy y
    common.check_memory(96.0 * n**2, "--elements", f"a simulation of {n} unknowns (dense matrices)")
    with _progress.stage(f"simulate {args.t_end:g} s (compiling, then integrating)"):
        if args.max_steps is None:
            _check_duration(model, params, units, args.t_end, tau_m)
        sim = simulate(
            model,
            params,
            args.t_end,
            cubic=cubic,
            units=units,
            perturbation_um=args.perturbation_um,
            rtol=args.rtol,
            atol=args.rtol * 1e-3,
            max_steps=args.max_steps,
            progress=_progress.style() == "bars",  # diffrax's bar (a host callback): terminals only
            tau_m=tau_m,
            f_sat=f_sat,
        )
    if args.out is not None:
        sim.save(args.out)  # written whole (axojax._io)
    if args.gif is not None:
        from ..plotting import animate_simulation

        with _progress.stage(f"simulate: drawing {args.gif}"), _io.atomic_path(args.gif) as tmp:
            animate_simulation(sim, tmp)
    if sim.state == "solver_failed":
        wrote = f"; {args.out} holds the record up to there" if args.out is not None else ""
        # a state, not an input error (docs/interface.md: exit 0, the document says why); one
        # line on stderr so that a script that ignores the document still sees it
        print(f"axojax: simulate: solver_failed: {sim.reason}{wrote}", file=sys.stderr)
    return sim.to_json()


def _check_duration(model, params, units, t_end_s: float, tau_m: float | None = None) -> None:
    """Refuse a ``--t-end`` whose default step budget (as :func:`axojax.simulate` sets it)
    exceeds :data:`MAX_STEPS` (the linear frequency: with motor kinetics ``tau_m``, the
    augmented pencil's)."""
    from ..dynamics.motors import dominant_eigenvalue
    from ..eigen.mode import dominant_mode

    if tau_m is None:
        frequency = float(dominant_mode(model, params).frequency_hz(units))
    else:
        frequency = abs(dominant_eigenvalue(model, params, tau_m).imag) / (
            2 * math.pi * units.tau_s
        )
    steps = MIN_STEPS + STEPS_PER_PERIOD * t_end_s * max(frequency, 20.0)
    if not math.isfinite(steps) or steps > MAX_STEPS:
        raise common.CLIError(
            f"--t-end: {t_end_s:g} s at the linear frequency {frequency:.4g} Hz would need a "
            f"budget of about {steps:.3g} solver steps "
            f"(limit {MAX_STEPS:g}); give a shorter --t-end, or --max-steps"
        )


def render(doc: dict) -> str:
    lin = doc["linear"]
    reason = f": {doc['reason']}" if doc.get("reason") else ""
    lines = [
        f"state: {doc['state']}{reason}",
        f"linear (dominant eigenvalue): {lin['classification']}, {lin['frequency_hz']:.3f} Hz, "
        f"growth {lin['growth_rate_per_s']:.3f} /s",
    ]
    lines += motor_kinetics_lines(doc, "linear: the augmented pencil")
    lc = doc["limit_cycle"]
    if lc is not None:
        w = doc["waveform"]
        lines.append(
            f"limit cycle: {lc['frequency_hz']:.3f} Hz (period {lc['period_s'] * 1e3:.2f} ms), "
            f"tip amplitude {lc['tip_amplitude_um']:.3f} um"
        )
        lines.append(
            f"waveform: wavelength {wavelength_text(w.get('wavelength_um'), '.3f')}, static "
            f"curvature {w['static_curvature_rad_per_um']:.4f} rad/um, dynamic amplitude "
            f"{w['dynamic_amplitude_rad']:.3f} rad"
            + sensitive_note(w.get("amplitude_dip") if w.get("wavelength_sensitive") else None)
        )
    return "\n".join(lines)
