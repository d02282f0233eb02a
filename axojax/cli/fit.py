"""``axojax fit``: estimate free parameters from target observables or beat data, in one
condition (flags) or several at once (``--spec FIT.toml``).

The spec file (INTERFACE.md)::

    model = "seven"            # or model_file = "section.toml" (relative to the spec)
    elements = 10              # optional
    imbalance_kind = "moment"  # optional: how imbalance R is read ("moment" or "force";
                               # default --imbalance-kind, itself "moment")
    kl_ratio = 1000            # optional: kl = ks / kl_ratio
    length_um = 12             # optional
    free = ["ks", "kl", "cl", "gamma"]     # shared by all conditions
    free_per_condition = ["p"]             # optional: one value per condition
    [params]                   # fixed values and the start, for every condition
    ks = 4.6e5
    [bounds]                   # optional: (low, high) per parameter
    cl = [1e-3, 10]
    [[condition]]              # one table per condition
    label = "p300"             # optional
    p = 300                    # its own fixed parameters
    frequency_hz = 51          # targets (each optional); default sigmas 5 % / 10 % / 10 %
    frequency_sigma_hz = 1.0
    wavelength_um = 11
    wavelength_sigma_um = 1
    velocity_um_per_s = 500
    data = "beat.npz"          # beat data: frequency and psi_1 shape (relative to the spec)

Exit status 0 when every target is reproduced, 1 (with the report) when not.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import pathlib
import sys
import tomllib
import warnings

from .. import _io
from ..beats import OBSERVATIONS, Target, observation_targets, read_beat
from ..inverse import SHAPE_FLOOR, Condition, fit
from ..models import build_model, load_section
from ..models.presets import preset_section
from ..params import DEFAULT_CUBIC, PARAM_NAMES, Params
from ..units import Units
from . import common

METHODS = ("lm", "lbfgs", "adam")
MAX_DRAWS = 100_000  # draws per chain of --posterior (a 3-parameter posterior needs ~1000)
MAX_CHAINS = 64
MAX_STARTS = 10_000
"""Most starts of a multi-start fit (each is a full local fit; 1e11 asked for 745 GiB)."""
SPEC_TOP = {
    "model",
    "model_file",
    "elements",
    "imbalance_kind",
    "kl_ratio",
    "length_um",
    "free",
    "free_per_condition",
    "params",
    "condition",
    "bounds",
}
SPEC_TARGETS = {
    # key: (target name, sigma key, default relative sigma)
    "frequency_hz": ("frequency_hz", "frequency_sigma_hz", 0.05),
    "wavelength_um": ("wavelength_um", "wavelength_sigma_um", 0.10),
    "velocity_um_per_s": ("velocity_um_per_s", "velocity_sigma_um_per_s", 0.10),
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    parser.add_argument(
        "--free",
        default=None,
        metavar="NAMES",
        help="comma-separated parameters to fit, e.g. p,ks; cubic (the stiffening, --cubic its start) with --target limit-cycle (or free = [...] in --spec)",
    )
    parser.add_argument(
        "--spec",
        default=None,
        metavar="FIT.toml",
        help="fit several conditions at once (global fit): model, free parameters and [[condition]] tables (see the module docs)",
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
        help="beat data (kymograph, centreline or Fourier-mode file): frequency and mode shape",
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
        default=4,
        metavar="N",
        help="multi-start count: the given point plus a Sobol design in the bounds (default 4)",
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
        help=f"model-discrepancy floor added in quadrature to psi_1's sigma (default {SHAPE_FLOOR:g} rad: tangent-angle accuracy of tracked centrelines, "
        "5-10%% of a typical |psi_1|)",
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
    parser.add_argument(
        "--posterior",
        type=int,
        default=None,
        metavar="DRAWS",
        help="then sample the posterior from the optimum with NUTS: DRAWS per chain after as many warm-up steps "
        "(adds \"posterior\" to the report; with --out FIT.json the draws go to FIT.posterior.npz, drawn by 'axojax plot')",
    )
    parser.add_argument(
        "--chains",
        type=int,
        default=4,
        metavar="C",
        help="posterior chains (default 4; with --posterior)",
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
            "--observation: fits the linear mode; with --target limit-cycle give --target-frequency/--target-wavelength/--target-amplitude or --data"
        )
    spec = (
        ("frequency_hz", args.target_frequency, args.frequency_sigma, 0.05, "--target-frequency"),
        (
            "wavelength_um",
            args.target_wavelength,
            args.wavelength_sigma,
            0.10,
            "--target-wavelength",
        ),
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


def _read_data(path, flag: str):
    """(BeatData, its summary: what ``axojax data`` prints) of a beat file; the reader
    refuses data no fit can use (:mod:`axojax.beats.data`)."""
    try:
        beat = read_beat(path)
    except (ValueError, OSError) as err:
        raise common.CLIError(f"{flag}: {err}") from None
    return beat, beat.summary()


def _check_posterior(args: argparse.Namespace) -> None:
    if args.posterior is None:
        if args.chains != 4:
            raise common.CLIError("--chains: applies to the posterior; add --posterior DRAWS")
        return
    if not 4 <= args.posterior <= MAX_DRAWS:
        raise common.CLIError(
            f"--posterior: draws per chain must be in 4..{MAX_DRAWS}, got {args.posterior}"
        )
    if not 1 <= args.chains <= MAX_CHAINS:
        raise common.CLIError(
            f"--chains: expected an integer in 1..{MAX_CHAINS}, got {args.chains}"
        )


def _fit_options(args: argparse.Namespace) -> dict:
    if not 1 <= args.starts <= MAX_STARTS:
        raise common.CLIError(
            f"--starts: expected an integer in 1..{MAX_STARTS}, got {args.starts}"
        )
    if args.shape_floor < 0:
        raise common.CLIError(f"--shape-floor: must be >= 0 rad, got {args.shape_floor:g}")
    if args.exclude_base_um < 0:
        raise common.CLIError(f"--exclude-base-um: must be >= 0 um, got {args.exclude_base_um:g}")
    return {
        "starts": args.starts,
        "method": args.method,
        "progress": not args.json and sys.stderr.isatty(),
        "solver": common.solver_from_args(args),
        "shape_floor": args.shape_floor,
        "exclude_base_um": args.exclude_base_um,
    }


def _length_given(args) -> bool:
    return any(
        a == "--length-um" or a.startswith("--length-um=") for a in getattr(args, "_argv", [])
    )


def _finish(args, result, extra: dict, post=None) -> dict:
    doc = result.to_json()
    doc.update(extra)
    if post is not None:
        doc["posterior"] = post.to_json()
        if args.out is not None:
            draws = pathlib.Path(args.out).with_suffix(".posterior.npz")
            try:
                post.save(draws)
            except OSError as err:
                raise common.CLIError(f"--out: cannot write {str(draws)!r} ({err})") from None
            doc["posterior"]["file"] = str(draws)
    if args.out is not None:
        import json

        try:
            _io.write_text(
                args.out, json.dumps(common.to_jsonable(doc), indent=1, allow_nan=False) + "\n"
            )
        except OSError as err:
            raise common.CLIError(f"--out: cannot write {args.out!r} ({err})") from None
        doc["out"] = str(args.out)
    if not result.converged:
        print(f"axojax: fit: {result.message}", file=sys.stderr)
    args._exit_code = 0 if result.converged else 1
    return doc


LEAST_SQUARES_ONLY = ("starts", "method", "progress", "max_steps", "seed")


def _run_fit(args, *fit_args, flag: str, **kwargs):
    """The fit, then (``--posterior``) NUTS from its optimum on the same problem."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = fit(*fit_args, **kwargs)
    except ValueError as err:
        raise common.CLIError(f"{flag}: {err}") from None
    if args.posterior is None:
        return result, None
    from ..inverse import build_problem, posterior

    problem = build_problem(
        *fit_args, **{k: v for k, v in kwargs.items() if k not in LEAST_SQUARES_ONLY}
    )
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            post = posterior(
                problem,
                draws=args.posterior,
                chains=args.chains,
                warmup=max(args.posterior, 150),
                init=result,
                progress=kwargs.get("progress", False),
            )
    except ValueError as err:
        raise common.CLIError(f"--posterior: {err}") from None
    for w in caught:  # R-hat, ESS and divergence warnings: one line each on stderr
        print(f"axojax: fit: posterior: {w.message}", file=sys.stderr)
    return result, post


def run(args: argparse.Namespace) -> dict:
    common.check_output("--out", args.out, (".json",))  # before any work, as every command
    _check_posterior(args)
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
    if args.data is not None:
        beat, extra["data"] = _read_data(args.data, "--data")
        length = getattr(beat, "length_um", None)
        if length is not None and abs(length - units.length_um) > 1e-6 * length:
            if _length_given(args):
                raise common.CLIError(
                    f"--length-um: {units.length_um:g} um conflicts with the data's length {length:g} um ({args.data})"
                )
            units = Units(length, units.ei_pn_um2, units.cn_pn_s_um2)  # the data's length
        data_targets, shape = beat.targets()
        if args.target == "limit-cycle":
            # The whole waveform against the nonlinear beat: psi_0 and psi_1 in absolute
            # amplitude, and the data's frequency as the limit cycle's.
            data_targets = [
                Target(t.name, t.value, t.sigma, source="limit_cycle")
                for t in data_targets
                if t.name in ("frequency_hz", "wavelength_um")
            ]
            shape = None if shape is None else dataclasses.replace(shape, source="limit_cycle")
        targets += [t for t in data_targets if t.name not in {u.name for u in targets}]
    elif args.exclude_base_um:
        raise common.CLIError("--exclude-base-um: applies to a shape; give --data")
    if not targets and shape is None:
        raise common.CLIError(
            "--free: nothing to fit to; give --target-frequency, --target-wavelength, --observation or --data"
        )
    if args.target == "limit-cycle":
        kappa = DEFAULT_CUBIC if args.cubic is None else args.cubic
        if not kappa > 0:
            raise common.CLIError(
                f"--cubic: must be > 0 (the stiffening that bounds the beat), got {kappa:g}"
            )
        if model.link_B.shape[0] == 0:
            raise common.CLIError(
                f"--target: {model.name!r} has no links, so it has no limit cycle; use a model with links"
            )
        options["cubic"] = kappa
    flag = "--exclude-base-um" if args.exclude_base_um else "--free"
    result, post = _run_fit(
        args,
        model,
        params,
        targets,
        free,
        shape=shape,
        kl_ratio=common.kl_ratio(args),
        units=units,
        flag=flag,
        **options,
    )
    return _finish(args, result, extra, post)


def _free_names(text: str) -> list[str]:
    """--free: parameter flags, and ``cubic`` (the limit cycle's stiffening; with --target limit-cycle)."""
    names = [t.strip() for t in text.split(",")]
    if "cubic" not in names:
        return common.parse_names(text, "--free")
    rest = [n for n in names if n and n != "cubic"]
    return (common.parse_names(",".join(rest), "--free") if rest else []) + ["cubic"]


# -- --spec: several conditions ----------------------------------------------------------
def _spec_error(path, problem: str):
    raise common.CLIError(f"--spec: {path}: {problem}")


def _number(path, where: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        _spec_error(path, f"{where} must be a finite number, got {value!r}")
    return float(value)


def _names(path, key: str, value) -> list[str]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        _spec_error(path, f'{key} must be a list of parameter names, e.g. ["ks", "cl"]')
    out = []
    for v in value:
        field = common.PARAM_FLAGS.get(v) or (v if v in PARAM_NAMES else None)
        if field is None:
            _spec_error(
                path, f"{key}: unknown parameter {v!r}; choose from {', '.join(PARAM_NAMES)}"
            )
        out.append(field)
    return out


def _param_table(path, where: str, table: dict) -> dict[str, float]:
    out = {}
    for k, v in table.items():
        field = common.PARAM_FLAGS.get(k) or (k if k in PARAM_NAMES else None)
        if field is None:
            _spec_error(
                path, f"{where}: unknown parameter {k!r}; choose from {', '.join(PARAM_NAMES)}"
            )
        out[field] = _number(path, f"{where}.{k}", v)
    return out


def _run_spec(args: argparse.Namespace) -> dict:
    path = pathlib.Path(args.spec)
    if not path.is_file():
        raise common.CLIError(f"--spec: {path}: file does not exist")
    try:
        spec = tomllib.loads(path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise common.CLIError(f"--spec: {path}: not valid TOML ({err})") from None
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
    unknown = set(spec) - SPEC_TOP
    if unknown:
        _spec_error(
            path,
            f"unknown key(s) {', '.join(sorted(unknown))}; known: {', '.join(sorted(SPEC_TOP))}",
        )
    here = path.parent
    # Model.
    elements = spec.get("elements", 10)
    if (
        isinstance(elements, bool)
        or not isinstance(elements, int)
        or not 1 <= elements <= common.MAX_ELEMENTS
    ):
        _spec_error(
            path, f"elements must be an integer in 1..{common.MAX_ELEMENTS}, got {elements!r}"
        )
    if "model" in spec and "model_file" in spec:
        _spec_error(path, "give model or model_file, not both")
    kind = spec.get("imbalance_kind", args.imbalance_kind)
    if kind not in common.IMBALANCE_KINDS:
        _spec_error(
            path, f"imbalance_kind must be one of {', '.join(common.IMBALANCE_KINDS)}, got {kind!r}"
        )
    if (
        "imbalance_kind" in spec
        and args.imbalance_kind != common.IMBALANCE_KINDS[0]
        and args.imbalance_kind != kind
    ):
        raise common.CLIError(
            f"--imbalance-kind: {args.imbalance_kind} conflicts with the spec's imbalance_kind = {kind!r} ({path})"
        )
    try:
        if "model_file" in spec:
            section = load_section(here / str(spec["model_file"]))
        else:
            section = preset_section(str(spec.get("model", "seven")))
    except (ValueError, OSError) as err:
        _spec_error(path, f"model: {err}")
    common.check_model_size(
        section, elements, f"--spec: {path}: elements"
    )  # as --elements, before anything is built
    try:
        model = build_model(section, elements, imbalance_kind=kind)
    except ValueError as err:
        _spec_error(path, f"model: {err}")
    length = (
        _number(path, "length_um", spec["length_um"]) if "length_um" in spec else args.length_um
    )
    try:
        units = Units(length, args.ei, args.cn)
    except ValueError as err:
        _spec_error(path, f"units: {err}")
    kl_ratio = (
        _number(path, "kl_ratio", spec["kl_ratio"]) if "kl_ratio" in spec else common.kl_ratio(args)
    )
    if kl_ratio is not None and kl_ratio <= 0:
        _spec_error(path, f"kl_ratio must be > 0, got {kl_ratio:g}")
    free = _names(path, "free", spec.get("free", []))
    per = _names(path, "free_per_condition", spec.get("free_per_condition", []))
    if not free and not per:
        _spec_error(
            path,
            "free: name at least one parameter to fit (free = [...] or free_per_condition = [...])",
        )
    base = spec.get("params", {})
    if not isinstance(base, dict):
        _spec_error(path, "[params] must be a table of parameter values")
    try:
        params = Params().with_values(_param_table(path, "params", base), kl_ratio).validate()
    except ValueError as err:
        _spec_error(path, f"params: {err}")
    bounds = {}
    if not isinstance(spec.get("bounds", {}), dict):
        _spec_error(path, f"[bounds] must be a table of [low, high] pairs, got {spec['bounds']!r}")
    for k, v in spec.get("bounds", {}).items():
        field = _names(path, "bounds", [k])[0]
        if not isinstance(v, list) or len(v) != 2:
            _spec_error(path, f"bounds.{k} must be [low, high]")
        bounds[field] = tuple(_number(path, f"bounds.{k}", x) for x in v)
    # Conditions.
    tables = spec.get("condition", [])
    if not isinstance(tables, list) or not tables:
        _spec_error(path, "no [[condition]] tables: give one per observed condition")
    options = _fit_options(args)
    conditions, data_docs = [], []
    for i, table in enumerate(tables):
        where = f"condition {i + 1}"
        if not isinstance(table, dict):
            _spec_error(path, f"{where}: each [[condition]] must be a table, got {table!r}")
        label = str(table.get("label", i))
        fixed, targets, shape, src = {}, [], None, None
        sigma_keys = {s for _, s, _ in SPEC_TARGETS.values()}
        for k, v in table.items():
            if k in ("label", "source") or k in sigma_keys:
                continue
            if k == "data":
                src = here / str(v)
                beat, doc = _read_data(src, "--spec")
                doc["condition"] = label
                data_docs.append(doc)
                data_targets, shape = beat.targets()
                have = {u.name for u in targets} | set(table)
                targets += [u for u in data_targets if u.name not in have]
            elif k in SPEC_TARGETS:
                name, sigma_key, rel = SPEC_TARGETS[k]
                value = _number(path, f"{where}.{k}", v)
                sigma = (
                    _number(path, f"{where}.{sigma_key}", table[sigma_key])
                    if sigma_key in table
                    else rel * abs(value)
                )
                if value <= 0 or sigma <= 0:
                    _spec_error(
                        path, f"{where}: {k} and its sigma must be > 0, got {value:g} +- {sigma:g}"
                    )
                targets = [t for t in targets if t.name != name] + [Target(name, value, sigma)]
            else:
                fixed.update(_param_table(path, where, {k: v}))
        for sigma_key in sigma_keys & set(table):
            if not any(s == sigma_key and k in table for k, (_, s, _) in SPEC_TARGETS.items()):
                _spec_error(path, f"{where}: {sigma_key} without its target")
        try:
            conditions.append(
                Condition(
                    params=fixed,
                    targets=targets,
                    shape=shape,
                    label=label,
                    source=str(table.get("source", src or path)),
                )
            )
        except ValueError as err:
            _spec_error(path, f"{where}: {err}")
    flag = "--exclude-base-um" if args.exclude_base_um else "--spec"
    result, post = _run_fit(
        args,
        model,
        params,
        conditions,
        free,
        per_condition=per,
        bounds=bounds or None,
        kl_ratio=kl_ratio,
        units=units,
        flag=flag,
        **options,
    )
    extra = {"spec": str(path)}
    if data_docs:
        extra["data"] = data_docs[0] if len(data_docs) == 1 else data_docs
    return _finish(args, result, extra, post)


def render(doc: dict) -> str:
    lines = [f"{'parameter':>12s}  {'value':>12s}  {'stderr':>12s}  note"]
    for k, v in doc["fitted"].items():
        se = doc["stderr"].get(k)
        note = (
            "at bound"
            if k in doc["at_bound"]
            else ("" if doc["identifiable"].get(k) else "not identifiable")
        )
        lines.append(f"{k:>12s}  {v:12.5g}  {se if se is not None else float('inf'):12.3g}  {note}")
    for c in doc["conditions"]:
        a = c["achieved"]
        head = f"[{c['label']}] " if len(doc["conditions"]) > 1 else ""
        if "frequency_hz" in a:
            wl = (
                "none (no travelling wave)"
                if a["wavelength_um"] is None
                else f"{a['wavelength_um']:.3f} um"
            )
            lines.append(
                f"{head}achieved: {a['frequency_hz']:.3f} Hz, wavelength {wl}, growth {a['growth_rate_per_s']:.3f} /s"
            )
        if "limit_cycle_frequency_hz" in a:
            f, amp, wl = (
                a.get(f"limit_cycle_{k}") for k in ("frequency_hz", "amplitude_um", "wavelength_um")
            )
            lines.append(
                f"{head}limit cycle: "
                + (
                    f"{f:.3f} Hz, tip amplitude {amp:.3f} um, wavelength {wl:.3f} um"
                    if f is not None
                    else "no orbit found"
                )
            )
        for t in c["targets"]:
            got = t["achieved"]
            lines.append(
                f"{head}  {t['name']}: {got if got is not None else float('nan'):.4g} vs {t['value']:.4g} +- {t['sigma']:.3g} ({t['residual']:+.2f} sigma)"
            )
        if c.get("shape_rms") is not None:
            lines.append(f"{head}  mode shape rms residual {c['shape_rms']:.2f} sigma")
    chi2 = doc.get("chi2_per_dof")
    lines.append(
        f"loss {doc['loss']:.4g}; chi2/dof {chi2:.3g}"
        if chi2 is not None
        else f"loss {doc['loss']:.4g}; chi2/dof undefined (no more residuals than fitted values)"
    )
    lines.append(f"converged: {doc['converged']}; {doc['message']}")
    post = doc.get("posterior")
    if post:
        lines.append(
            f"posterior ({post['chains']} chains x {post['draws']} draws, {post['seconds']:.1f} s):"
        )
        lines.append(
            f"{'parameter':>12s}  {'mean':>12s}  {'sd':>10s}  {'q05':>12s}  {'q95':>12s}  {'rhat':>6s}  {'ess':>7s}"
        )
        for k, m in post["mean"].items():
            lines.append(
                f"{k:>12s}  {m:12.5g}  {post['sd'][k]:10.3g}  {post['q05'][k]:12.5g}  {post['q95'][k]:12.5g}  {post['rhat'][k]:6.3f}  {post['ess'][k]:7.0f}"
            )
        if post.get("file"):
            lines.append(f"wrote {post['file']} (axojax plot it for a corner plot)")
    if doc.get("out"):
        lines.append(f"wrote {doc['out']}")
    return "\n".join(lines)


def figure_of_report(path) -> object:
    """The figure of a saved fit report (``axojax plot FIT.json``); bad files are a
    one-line :class:`CLIError` naming FILE."""
    import json

    from ..plotting.fit_report import plot_fit_report

    path = pathlib.Path(path)
    if not path.is_file():
        raise common.CLIError(f"FILE: {str(path)!r} does not exist")
    try:
        doc = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, ValueError) as err:
        raise common.CLIError(f"FILE: cannot read {str(path)!r} as JSON ({err})") from None
    if not isinstance(doc, dict) or not {"loss", "converged", "conditions"} <= set(doc):
        raise common.CLIError(
            f"FILE: {str(path)!r} is not a fit report (write one with 'axojax fit --out FIT.json')"
        )
    try:
        return plot_fit_report(doc)
    except (KeyError, TypeError, ValueError) as err:
        raise common.CLIError(f"FILE: {str(path)!r}: malformed fit report ({err})") from None
