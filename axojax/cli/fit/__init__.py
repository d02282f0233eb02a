"""``axojax fit``: estimate free parameters from target observables or beat data, in one
condition (flags) or several at once (``--spec FIT.toml``).

The spec file's format: :mod:`axojax.inverse.spec` (``ax.inverse.read_spec``).

Exit status 0 when every target is reproduced (and a posterior's chains converged), 1
(with the report) when not.
"""

from __future__ import annotations

import argparse
import dataclasses
import warnings

from ... import _progress
from ...beats import OBSERVATIONS, Target, observation_targets, observed_target
from ...eigen.normal_force import NormalForce
from ...eigen.solvers import AbstractEigenSolver
from ...inverse import (
    SHAPE_FLOOR,
    build_problem,
    least_squares,
    read_spec,
    solver_from_name,
)
from ...inverse.comparison.mechanisms import coefficient_bounds
from ...inverse.fitting.checks import fit_checks
from ...inverse.fitting.least_squares import FIT_STARTS
from ...inverse.sampling import (  # a posterior's fit: the library's defaults
    POSTERIOR_STARTS,
    posterior_eigen_solver,
)
from ...params import DEFAULT_CUBIC
from .. import common
from ..regulation import add_motor_tau_flag, require_static_normal_force
from . import inputs, whole_beat
from . import posterior as fit_posterior
from .text import (
    render,  # noqa: F401  (the command's text output: main calls fit.render)
)

METHODS = ("lm", "lbfgs", "adam")
MAX_STARTS = 10_000
"""Most starts of a multi-start fit (each is a full local fit; 1e11 asked for 745 GiB)."""
DEFAULT_STARTS = FIT_STARTS
"""Starts of a fit without --posterior: the library's."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    add_motor_tau_flag(
        parser,
        "with --target limit-cycle --mechanism M (default: the fastest motors that leave the "
        "fitted beat the onset mode)",
    )
    parser.add_argument(
        "--free",
        default=None,
        metavar="NAMES",
        help="comma-separated parameters to fit, e.g. p,ks; cubic (the stiffening, --cubic its "
        "start) with --target limit-cycle (or free = [...] in --spec)",
    )
    parser.add_argument(
        "--spec",
        default=None,
        metavar="FIT.toml",
        help="fit several conditions at once (global fit): model, free parameters and "
        "[[condition]] tables (format: docs/interface.md, 'The fit spec')",
    )
    common.add_solver_flag(parser)
    parser.add_argument(
        "--target-frequency",
        type=common.finite_float,
        default=None,
        metavar="HZ",
        help="observed beat frequency (Hz)",
    )
    parser.add_argument(
        "--frequency-sigma",
        type=common.finite_float,
        default=None,
        metavar="HZ",
        help="its uncertainty (default 5%% of it)",
    )
    parser.add_argument(
        "--target-wavelength",
        type=common.finite_float,
        default=None,
        metavar="UM",
        help="observed wavelength (um)",
    )
    parser.add_argument(
        "--wavelength-sigma",
        type=common.finite_float,
        default=None,
        metavar="UM",
        help="its uncertainty (default 10%% of it)",
    )
    parser.add_argument(
        "--target-velocity",
        type=common.finite_float,
        default=None,
        metavar="UM_PER_S",
        help="observed wave velocity (um/s), 10%% uncertainty",
    )
    parser.add_argument(
        "--marginal",
        type=common.finite_float,
        default=None,
        metavar="PER_S",
        help="add a growth-rate target 0 +- this (1/s): beat near the Hopf boundary",
    )
    parser.add_argument(
        "--observation",
        default=None,
        metavar="NAME",
        help=f"bundled published targets: {', '.join(OBSERVATIONS)}",
    )
    parser.add_argument(
        "--data",
        default=None,
        metavar="FILE",
        help="beat data (kymograph, centreline or Fourier-mode file, or a bundled name such as "
        "human_sperm): frequency and mode shape, at the data's length; EI and c_n not given "
        "(--ei, --cn) come from a bundled data set's flagellum, as in axojax compare",
    )
    parser.add_argument(
        "--target",
        choices=("linear", "limit-cycle"),
        default="linear",
        help="what --target-frequency/--target-wavelength/--target-amplitude describe: the dominant linear mode "
        "(default) or the nonlinear beat's limit cycle (computed directly, see 'axojax orbit')",
    )
    parser.add_argument(
        "--target-amplitude",
        type=common.finite_float,
        default=None,
        metavar="UM",
        help="observed tip amplitude (um, half peak-to-peak; needs --target limit-cycle)",
    )
    parser.add_argument(
        "--amplitude-sigma",
        type=common.finite_float,
        default=None,
        metavar="UM",
        help="its uncertainty (default 10%% of it)",
    )
    parser.add_argument(
        "--cubic",
        type=common.finite_float,
        default=None,
        metavar="KAPPA",
        help="cubic link stiffening of the limit cycle, 1/L^2 (default 10; with --target limit-cycle)",
    )
    parser.add_argument(
        "--starts",
        type=int,
        default=None,
        metavar="N",
        help=f"multi-start count: the given point plus a Sobol design in the bounds (default {DEFAULT_STARTS}; "
        f"{POSTERIOR_STARTS} with --posterior: a posterior around a local optimum is wrong)",
    )
    parser.add_argument(
        "--method",
        choices=METHODS,
        default="lm",
        help="least-squares solver: lm (Levenberg-Marquardt, default), lbfgs, adam",
    )
    parser.add_argument(
        "--shape-floor",
        type=common.finite_float,
        default=SHAPE_FLOOR,
        metavar="RAD",
        help="model-discrepancy floor added in quadrature to psi_1's sigma (default "
        f"{SHAPE_FLOOR:g} rad: tangent-angle accuracy of tracked centrelines, "
        "5-10%% of a typical |psi_1|)",
    )
    parser.add_argument(
        "--components",
        choices=("in-plane", "joint"),
        default="in-plane",
        help="with --data of a 3D beat: fit psi_1 in the beat plane only (in-plane, default), or the "
        "in-plane and out-of-plane psi_1 together with one complex scale (joint; a 3D model such as "
        "seven, and the linear mode only); a planar beat has the in-plane component alone",
    )
    common.add_planarity_flag(parser)
    parser.add_argument(
        "--frame",
        choices=("lab", "basal"),
        default="lab",
        help="with --target limit-cycle --mechanism M, the frame psi is compared in: lab (as "
        "recorded, default: psi_0 up to the recording's reference angle, reported as "
        "psi_offset_rad) or basal (model and data relative to the basal tangent, psi(s) - "
        "psi(0), psi_0 exactly; docs/model.md section 8, frames)",
    )
    parser.add_argument(
        "--exclude-base-um",
        type=common.finite_float,
        default=0.0,
        metavar="UM",
        help="leave the basal stretch s < UM of the data's shape out of the fit (its misfit is reported)",
    )
    parser.add_argument(
        "--out",
        default=None,
        metavar="FIT.json",
        help="save the fit report (read by 'axojax plot FIT.json')",
    )
    fit_posterior.add_arguments(parser)
    parser.add_argument(
        "--no-mesh-check",
        dest="mesh_check",
        action="store_false",
        help="skip the refit at twice the elements that says how far the fit moves with the mesh "
        '(about as long as the fit; the report\'s "mesh_check")',
    )


def _targets(args: argparse.Namespace) -> list[Target]:
    out = []
    cycle = args.target == "limit-cycle"
    if not cycle:
        for flag, value in (
            ("--target-amplitude", args.target_amplitude),
            ("--amplitude-sigma", args.amplitude_sigma),
            ("--cubic", args.cubic),
        ):
            if value is not None:
                raise common.CLIError(
                    f"{flag}: describes the limit cycle; add --target limit-cycle"
                )
    elif args.target_velocity is not None:
        raise common.CLIError(
            "--target-velocity: not a limit-cycle target (use --target-frequency and --target-wavelength)"
        )
    elif args.marginal is not None:
        raise common.CLIError(
            "--marginal: a limit cycle lives past the Hopf point; drop --marginal with --target limit-cycle"
        )
    elif args.observation is not None:
        raise common.CLIError(
            "--observation: fits the linear mode; with --target limit-cycle give "
            "--target-frequency/--target-wavelength/--target-amplitude or --data"
        )
    spec = (
        ("frequency_hz", args.target_frequency, args.frequency_sigma, "--target-frequency"),
        ("wavelength_um", args.target_wavelength, args.wavelength_sigma, "--target-wavelength"),
        ("velocity_um_per_s", args.target_velocity, None, "--target-velocity"),
        ("amplitude_um", args.target_amplitude, args.amplitude_sigma, "--target-amplitude"),
    )
    for name, value, sigma, flag in spec:
        if value is None:
            continue
        try:  # sigma: RELATIVE_SIGMA of the value unless given
            target = observed_target(name, value, sigma, "limit_cycle" if cycle else "linear")
        except ValueError as err:
            raise common.CLIError(f"{flag}: {str(err).split(': ', 1)[-1]}") from None
        out.append(target)
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


def eigen_solver(args: argparse.Namespace) -> AbstractEigenSolver:
    """``--solver``; with ``--posterior`` the library's choice for a posterior's problem
    (:func:`~axojax.inverse.sampling.posterior_eigen_solver`)."""
    solver = common.solver_from_args(args)
    return solver if args.posterior is None else posterior_eigen_solver(solver)


def _fit_options(args: argparse.Namespace) -> dict:
    starts = args.starts
    if starts is None:
        starts = POSTERIOR_STARTS if args.posterior is not None else DEFAULT_STARTS
    if not 1 <= starts <= MAX_STARTS:
        raise common.CLIError(f"--starts: expected an integer in 1..{MAX_STARTS}, got {starts}")
    if args.shape_floor < 0:
        raise common.CLIError(f"--shape-floor: must be >= 0 rad, got {args.shape_floor:g}")
    if args.exclude_base_um < 0:
        raise common.CLIError(f"--exclude-base-um: must be >= 0 um, got {args.exclude_base_um:g}")
    return {
        "starts": starts,
        "method": args.method,
        "progress": _progress.enabled(),
        "solver": eigen_solver(args),
        "shape_floor": args.shape_floor,
        "exclude_base_um": args.exclude_base_um,
    }


PROBLEM_OPTIONS = ("solver", "shape_floor", "exclude_base_um", "cubic", "bounds", "shift")
"""The options of :func:`_fit_options` that shape the problem (the rest drive its solver)."""


def _run_fit(args, problem, options: dict, flag: str):
    """The fit of ``problem``, then (``--posterior``) the posterior of the same problem
    from its optimum: (fit, None) or (fit, (posterior, why that sampler))."""
    transport = fit_posterior.transport_of(args, problem.names)  # refused before the fit
    try:
        method = solver_from_name(options["method"])
        with warnings.catch_warnings():  # the report says what the warnings would
            warnings.simplefilter("ignore")
            result = least_squares(
                problem, method, starts=options["starts"], progress=options["progress"]
            )
    except ValueError as err:
        raise common.CLIError(f"{flag}: {err}") from None
    if args.posterior is None:
        return result, None
    return result, fit_posterior.sample(args, problem, result, options["progress"], transport)


def run(args: argparse.Namespace) -> dict:
    common.check_output("--out", args.out, (".json",))  # before any work, as every command
    fit_posterior.check_arguments(args)
    if args.target == "limit-cycle" and args.mechanism != "steady":
        return whole_beat.run(args)
    if getattr(args, "frame", "lab") != "lab":
        raise common.CLIError(
            f"--frame {args.frame}: a fit takes a frame with --target limit-cycle --mechanism M "
            "(the whole beat; the linear comparison's: axojax compare --frame)"
        )
    if getattr(args, "motor_tau_ms", None) is not None:
        raise common.CLIError(
            "--motor-tau-ms: a fit takes motor kinetics with --target limit-cycle --mechanism M"
        )
    if args.spec is not None:
        return _run_spec(args)
    if args.free is None:
        raise common.CLIError("--free: name the parameters to fit (or give --spec FIT.toml)")
    model = common.model_from_args(args)
    params = common.params_from_args(args)
    units = common.units_from_args(args)
    free = _free_names(args.free)
    options = _fit_options(args)
    targets = _targets(args)
    shape, extra = None, {}
    units_source = (
        "given" if inputs.given(args, "--ei", "--cn") else "axojax's default units (paper table 2)"
    )
    if args.data is not None:
        data_targets, shape, units, extra["data"], units_source = inputs.data_inputs(
            args, units, units_source, model
        )
        targets += [t for t in data_targets if t.name not in {u.name for u in targets}]
    elif args.exclude_base_um:
        raise common.CLIError("--exclude-base-um: applies to a shape; give --data")
    if not targets and shape is None:
        raise common.CLIError(
            "--free: nothing to fit to; give --target-frequency, --target-wavelength, --observation or --data"
        )
    if args.target == "limit-cycle":
        options["cubic"] = _cubic(args, model)
    elif (args.mechanism or "steady") != "steady":
        options.update(_regulated(args, model, params))
    flag = "--exclude-base-um" if args.exclude_base_um else "--free"
    try:
        problem = build_problem(
            model,
            params,
            targets,
            free,
            shape=shape,
            kl_ratio=common.kl_ratio(args),
            units=units,
            **{k: options[k] for k in PROBLEM_OPTIONS if k in options},
        )
    except ValueError as err:
        raise common.CLIError(f"{flag}: {err}") from None
    result, sampled = _run_fit(args, problem, options, flag)
    extra.update(_checks(args, problem, result))
    extra["units"] = {**dataclasses.asdict(units), "source": units_source}
    return inputs.finish(args, result, extra, sampled)


def _regulated(args: argparse.Namespace, model, params) -> dict:
    """The problem options of a linear fit of regulated dynein (``--mechanism M``), as
    :func:`axojax.compare` sets them for its rows: the beat is the eigenvalue nearest
    i omega0 (``--omega0-hz``, the observed frequency), the coefficients' bounds are the
    comparison's, and normal-force control takes its own eigen-solver (the augmented
    pencil, :class:`~axojax.eigen.NormalForce`)."""
    mechanism = args.mechanism
    omega = float(params.omega0)
    if not omega > 0:
        raise common.CLIError(
            f"--mechanism {mechanism}: a fit of regulated dynein follows the beat nearest "
            "i omega0; give --omega0-hz (the observed frequency)"
        )
    options = {"bounds": coefficient_bounds(model, params), "shift": 1j * omega}
    if "normal-force" in mechanism.split("+"):
        if args.solver not in ("auto", "dense"):
            raise common.CLIError(
                f"--solver {args.solver}: normal-force control has its own eigen-solver (the "
                "augmented pencil, solved densely); leave --solver out"
            )
        require_static_normal_force(params)
        options["solver"] = NormalForce()
    return options


def _checks(args: argparse.Namespace, problem, result) -> dict:
    """The report's ``regime`` and ``mesh_check`` (the mesh check refits on a finer mesh:
    a stage on stderr)."""
    with _progress.stage("fit: checks (regime, mesh)"):
        return fit_checks(problem, result, mesh=args.mesh_check)


def _cubic(args: argparse.Namespace, model) -> float:
    """--cubic (default DEFAULT_CUBIC) for a limit-cycle fit of ``model``."""
    kappa = DEFAULT_CUBIC if args.cubic is None else args.cubic
    if not kappa > 0:
        raise common.CLIError(
            f"--cubic: must be > 0 (the stiffening that bounds the beat), got {kappa:g}"
        )
    if model.link_B.shape[0] == 0:
        raise common.CLIError(
            f"--target: {model.name!r} has no links, so it has no limit cycle; use a model with links"
        )
    return kappa


def _free_names(text: str) -> list[str]:
    """--free: parameter flags, and ``cubic`` (the limit cycle's stiffening; with --target limit-cycle)."""
    names = [t.strip() for t in text.split(",")]
    if "cubic" not in names:
        return common.parse_names(text, "--free")
    rest = [n for n in names if n and n != "cubic"]
    return (common.parse_names(",".join(rest), "--free") if rest else []) + ["cubic"]


# -- --spec: several conditions ----------------------------------------------------------
def _run_spec(args: argparse.Namespace) -> dict:
    for flag, value in (
        ("--free", args.free),
        ("--data", args.data),
        ("--observation", args.observation),
        ("--target-frequency", args.target_frequency),
        ("--target-wavelength", args.target_wavelength),
        ("--model", args.model),
        ("--model-file", args.model_file),
    ):
        if value is not None:
            raise common.CLIError(f"{flag}: with --spec give it in the spec file")
    for flag, field in common.PARAM_FLAGS.items():
        if getattr(args, field, None) is not None:
            raise common.CLIError(f"--{flag}: with --spec give parameters in its [params] table")
    options = _fit_options(args)
    kind = args.imbalance_kind
    try:
        spec = read_spec(
            args.spec,
            units=common.units_from_args(args),
            imbalance_kind=kind,
            kl_ratio=common.kl_ratio(args),
        )
    except ValueError as err:
        raise common.CLIError(f"--spec: {err}") from None
    if kind != common.IMBALANCE_KINDS[0] and spec.imbalance_kind != kind:
        raise common.CLIError(
            f"--imbalance-kind: {kind} conflicts with the spec's imbalance_kind = {spec.imbalance_kind!r} ({args.spec})"
        )
    flag = "--exclude-base-um" if args.exclude_base_um else "--spec"
    try:
        problem = spec.problem(
            solver=options["solver"],
            shape_floor=options["shape_floor"],
            exclude_base_um=options["exclude_base_um"],
        )
    except ValueError as err:
        raise common.CLIError(f"{flag}: {err}") from None
    result, sampled = _run_fit(args, problem, options, flag)
    extra = {"spec": str(args.spec)}
    if spec.data:
        extra["data"] = spec.data[0] if len(spec.data) == 1 else list(spec.data)
    extra.update(_checks(args, problem, result))
    return inputs.finish(args, result, extra, sampled)
