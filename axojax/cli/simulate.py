"""``axojax simulate``: the nonlinear beat in the time domain, saved to .npz."""

from __future__ import annotations

import argparse
import sys
import pathlib

from ..dynamics import DEFAULT_CUBIC, simulate
from ..dynamics.simulate import check_inputs
from . import common

FLAGS = {"t_end_s": "--t-end", "cubic": "--cubic", "perturbation_um": "--perturbation-um", "rtol": "--rtol"}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    parser.add_argument("--t-end", type=common.finite_float, required=True, metavar="SECONDS", help="simulated time (s)")
    parser.add_argument("--cubic", type=common.finite_float, default=None, metavar="KAPPA", help=f"cubic link stiffening kappa, 1/L^2 (default {DEFAULT_CUBIC:g}; 0: linear)")
    parser.add_argument("--perturbation-um", type=common.finite_float, default=0.1, metavar="UM", help="initial tip displacement in y (default 0.1 um)")
    parser.add_argument("--rtol", type=common.finite_float, default=1e-6, metavar="X", help="solver relative tolerance (default 1e-6)")
    parser.add_argument("--max-steps", type=int, default=None, metavar="N", help="solver step budget (default: 10000 + 2000 per period of the linear frequency, rounded up to a multiple of 10000); running out ends in state solver_failed")
    parser.add_argument("--out", default=None, metavar="FILE.npz", help="write the time series here")
    parser.add_argument("--gif", default=None, metavar="FILE.gif", help="also write an animation of the last beat cycles")


def run(args: argparse.Namespace) -> dict:
    model = common.model_from_args(args)
    params = common.params_from_args(args)
    units = common.units_from_args(args)
    cubic = DEFAULT_CUBIC if args.cubic is None else args.cubic
    if model.link_B.shape[0] == 0 and args.cubic is None:
        cubic = 0.0  # nothing to stiffen: single filaments are linear
    try:
        check_inputs(model, args.t_end, cubic, args.perturbation_um, args.rtol, names=FLAGS)
    except ValueError as err:
        raise common.CLIError(str(err)) from None
    if args.max_steps is not None and args.max_steps < 1:
        raise common.CLIError(f"--max-steps: must be a positive integer, got {args.max_steps}")
    for flag, path in (("--out", args.out), ("--gif", args.gif)):
        if path is not None and not pathlib.Path(path).resolve().parent.is_dir():
            raise common.CLIError(f"{flag}: directory of {path!r} does not exist")
    sim = simulate(model, params, args.t_end, cubic=cubic, units=units, perturbation_um=args.perturbation_um, rtol=args.rtol, atol=args.rtol * 1e-3, max_steps=args.max_steps, progress=not args.json and sys.stderr.isatty())
    if args.out is not None:
        sim.save(args.out)
    if args.gif is not None:
        from ..plotting import animate_simulation

        animate_simulation(sim, args.gif)
    return sim.report()


def render(doc: dict) -> str:
    lin = doc["linear"]
    reason = f": {doc['reason']}" if doc.get("reason") else ""
    lines = [f"state: {doc['state']}{reason}", f"linear (dominant eigenvalue): {lin['classification']}, {lin['frequency_hz']:.3f} Hz, growth {lin['growth_rate_per_s']:.3f} /s"]
    lc = doc["limit_cycle"]
    if lc is not None:
        w = doc["waveform"]
        lines.append(f"limit cycle: {lc['frequency_hz']:.3f} Hz (period {lc['period_s'] * 1e3:.2f} ms), tip amplitude {lc['tip_amplitude_um']:.3f} um")
        lines.append(f"waveform: static curvature {w['static_curvature_rad_per_um']:.4f} rad/um, dynamic amplitude {w['dynamic_amplitude_rad']:.3f} rad")
    return "\n".join(lines)
