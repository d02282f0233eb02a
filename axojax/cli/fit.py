"""``axojax fit``: estimate free parameters from target observables or beat data."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..dynamics.simulate import DEFAULT_CUBIC
from ..fitting import OBSERVATIONS, Target, fit, observation_targets, read_beat
from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    parser.add_argument("--free", required=True, metavar="NAMES", help="comma-separated parameters to fit, e.g. p,ks")
    common.add_solver_flag(parser)
    parser.add_argument("--target-frequency", type=common.finite_float, default=None, metavar="HZ", help="observed beat frequency (Hz)")
    parser.add_argument("--frequency-sigma", type=common.finite_float, default=None, metavar="HZ", help="its uncertainty (default 5%% of it)")
    parser.add_argument("--target-wavelength", type=common.finite_float, default=None, metavar="UM", help="observed wavelength (um)")
    parser.add_argument("--wavelength-sigma", type=common.finite_float, default=None, metavar="UM", help="its uncertainty (default 10%% of it)")
    parser.add_argument("--target-velocity", type=common.finite_float, default=None, metavar="UM_PER_S", help="observed wave velocity (um/s), 10%% uncertainty")
    parser.add_argument("--marginal", type=common.finite_float, default=None, metavar="PER_S", help="add a growth-rate target 0 +- this (1/s): beat near the Hopf boundary")
    parser.add_argument("--observation", default=None, metavar="NAME", help=f"bundled published targets: {', '.join(OBSERVATIONS)}")
    parser.add_argument("--data", default=None, metavar="FILE", help="beat data (.npz or .csv kymograph or centreline): frequency and mode shape")
    parser.add_argument(
        "--target", choices=("linear", "limit-cycle"), default="linear",
        help="what --target-frequency/--target-wavelength/--target-amplitude describe: the dominant linear mode "
        "(default) or the nonlinear beat's limit cycle (computed directly, see 'axojax orbit')",
    )
    parser.add_argument("--target-amplitude", type=common.finite_float, default=None, metavar="UM", help="observed tip amplitude (um, half peak-to-peak; needs --target limit-cycle)")
    parser.add_argument("--amplitude-sigma", type=common.finite_float, default=None, metavar="UM", help="its uncertainty (default 10%% of it)")
    parser.add_argument("--cubic", type=common.finite_float, default=None, metavar="KAPPA", help="cubic link stiffening of the limit cycle, 1/L^2 (default 10; with --target limit-cycle)")
    parser.add_argument("--starts", type=int, default=4, metavar="N", help="multi-start count (default 4)")
    parser.add_argument("--method", choices=("lbfgs", "adam"), default="lbfgs", help="optimiser (default lbfgs)")


def _targets(args: argparse.Namespace) -> list[Target]:
    out = []
    cycle = args.target == "limit-cycle"
    if not cycle:
        for flag, value in (("--target-amplitude", args.target_amplitude), ("--amplitude-sigma", args.amplitude_sigma), ("--cubic", args.cubic)):
            if value is not None:
                raise common.CLIError(f"{flag}: describes the limit cycle; add --target limit-cycle")
    elif args.target_velocity is not None:
        raise common.CLIError("--target-velocity: not a limit-cycle target (use --target-frequency and --target-wavelength)")
    elif args.marginal is not None:
        raise common.CLIError("--marginal: a limit cycle lives past the Hopf point; drop --marginal with --target limit-cycle")
    elif args.observation is not None or args.data is not None:
        flag = "--observation" if args.observation is not None else "--data"
        raise common.CLIError(f"{flag}: fits the linear mode; with --target limit-cycle give --target-frequency/--target-wavelength/--target-amplitude")
    spec = (
        ("frequency_hz", args.target_frequency, args.frequency_sigma, 0.05, "--target-frequency"),
        ("wavelength_um", args.target_wavelength, args.wavelength_sigma, 0.10, "--target-wavelength"),
        ("velocity_um_per_s", args.target_velocity, None, 0.10, "--target-velocity"),
        ("amplitude_um", args.target_amplitude, args.amplitude_sigma, 0.10, "--target-amplitude"),
    )
    for name, value, sigma, rel, flag in spec:
        if value is None:
            continue
        if value <= 0:
            raise common.CLIError(f"{flag}: must be > 0, got {value:g}")
        sigma = rel * value if sigma is None else sigma
        if sigma <= 0:
            raise common.CLIError(f"{flag}: its uncertainty must be > 0, got {sigma:g}")
        out.append(Target(name, value, sigma, source="limit_cycle" if cycle else "linear"))
    if args.marginal is not None:
        if args.marginal <= 0:
            raise common.CLIError(f"--marginal: must be > 0, got {args.marginal:g}")
        out.append(Target("growth_rate_per_s", 0.0, args.marginal))
    if args.observation is not None:
        try:
            obs = observation_targets(args.observation)
        except ValueError as err:
            raise common.CLIError(f"--observation: {err}") from None
        have = {t.name for t in out}
        out += [t for t in obs if t.name not in have]
    return out


def run(args: argparse.Namespace) -> dict:
    model = common.model_from_args(args)
    params = common.params_from_args(args)
    units = common.units_from_args(args)
    free = common.parse_names(args.free, "--free")
    solver = common.solver_from_args(args)
    if args.starts < 1:
        raise common.CLIError(f"--starts: expected an integer >= 1, got {args.starts}")
    targets = _targets(args)
    shape = None
    if args.data is not None:
        try:
            with np.errstate(all="ignore"):  # overflowing data is refused by check_beat
                beat = read_beat(args.data)
            common.check_beat(beat)
            data_targets, shape = beat.targets()
        except ValueError as err:
            raise common.CLIError(f"--data: {err}") from None
        targets += [t for t in data_targets if t.name not in {u.name for u in targets}]
    if not targets and shape is None:
        raise common.CLIError("--free: nothing to fit to; give --target-frequency, --target-wavelength, --observation or --data")
    cubic = {}
    if args.target == "limit-cycle":
        kappa = DEFAULT_CUBIC if args.cubic is None else args.cubic
        if not kappa > 0:
            raise common.CLIError(f"--cubic: must be > 0 (the stiffening that bounds the beat), got {kappa:g}")
        if model.link_B.shape[0] == 0:
            raise common.CLIError(f"--target: {model.name!r} has no links, so it has no limit cycle; use a model with links")
        cubic = {"cubic": kappa}
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = fit(model, params, targets, free, shape=shape, kl_ratio=common.kl_ratio(args), units=units, starts=args.starts, method=args.method, progress=not args.json and sys.stderr.isatty(), solver=solver, **cubic)
    except ValueError as err:
        raise common.CLIError(f"--free: {err}") from None
    doc = result.report()
    if not result.converged:
        print(f"axojax: fit: {result.message}", file=sys.stderr)
    args._exit_code = 0 if result.converged else 1
    return doc


def render(doc: dict) -> str:
    lines = [f"{'parameter':>12s}  {'value':>12s}  {'stderr':>12s}"]
    for k, v in doc["params"].items():
        lines.append(f"{k:>12s}  {v:12.5g}  {doc['stderr'][k]:12.3g}")
    a = doc["achieved"]
    lines.append(f"achieved: {a['frequency_hz']:.3f} Hz, wavelength {a['wavelength_um']:.3f} um, growth {a['growth_rate_per_s']:.3f} /s")
    if "limit_cycle_frequency_hz" in a:
        lines.append(f"limit cycle: {a['limit_cycle_frequency_hz']:.3f} Hz, tip amplitude {a['limit_cycle_amplitude_um']:.3f} um, wavelength {a['limit_cycle_wavelength_um']:.3f} um")
    lines.append(f"loss {doc['loss']:.4g}; converged: {doc['converged']}; {doc['message']}")
    return "\n".join(lines)
