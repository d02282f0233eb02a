"""``axojax orbit``: the limit cycle computed directly, or its branch in p from the Hopf
point (harmonic balance, Newton, Floquet multipliers; :mod:`axojax.orbits`). Each orbit's
report adds ``amplitude_dip`` and ``wavelength_sensitive`` of its psi_1
(:meth:`axojax.orbits.CycleMeasures.scalars`, at the 41 points of its other measures); the
text notes a sensitive wavelength at the end of its row. A regulated row with motor
kinetics (``--motor-tau-ms``, and saturating motors ``--motor-saturation``) has its orbit
of the state and the motors' copy y (:mod:`axojax.orbits.motors`; one orbit, no branch in
p); the JSON's ``motor_kinetics`` says which motors."""

from __future__ import annotations

import argparse
import math

import numpy as np

from .. import _io, _progress
from ..params import DEFAULT_CUBIC, Params
from ..waveform.measures import sensitive_note, wavelength_text
from . import common
from .regulation import (
    add_motor_saturation_flag,
    add_motor_tau_flag,
    motor_kinetics_lines,
    motor_saturation_from_args,
    motor_tau_from_args,
)
from .simulate import MAX_CUBIC

MAX_HARMONICS = 100
"""More harmonics than a beat needs (its spectrum decays fast) and than memory allows:
the Newton system grows as (2 H + 1)^2 blocks."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser, axes=True)
    parser.add_argument(
        "--cubic",
        type=common.finite_float,
        default=DEFAULT_CUBIC,
        metavar="KAPPA",
        help=f"cubic link stiffening kappa, 1/L^2 (default {DEFAULT_CUBIC:g})",
    )
    parser.add_argument(
        "--harmonics", default=10, metavar="H", help="harmonics of the orbit (default 10)"
    )
    add_motor_tau_flag(
        parser, "the orbit of the state and the motors' filtered copy of it (2N unknowns)"
    )
    add_motor_saturation_flag(parser)
    parser.add_argument(
        "--out", default=None, metavar="FILE.npz", help="write the orbits (the branch) here"
    )
    parser.add_argument(
        "--plot",
        default=None,
        metavar="FIGURE.png",
        help="figure: the branch (amplitude, frequency, stability against p) or the single orbit's waveform",
    )


SENSITIVITY = ("amplitude_dip", "wavelength_sensitive")


def _sensitivity(cycle, units) -> dict:
    """``amplitude_dip`` and ``wavelength_sensitive`` of an orbit's psi_1 (the default
    arc lengths of :func:`axojax.orbits.cycle_measures`, as its report's other measures)."""
    from ..orbits.measures import cycle_measures

    scalars = cycle_measures(cycle, None, units).scalars()
    return {k: scalars[k] for k in SENSITIVITY}


def run(args: argparse.Namespace) -> dict:
    from ..orbits import HarmonicBalance, limit_cycle
    from ..orbits.branch import Branch, branch

    model = common.model_from_args(args)
    units = common.units_from_args(args)
    fixed, axes = common.split_axes(args, args._argv)
    other = [f for f in axes if f != "p"]
    if other:
        raise common.CLIError(
            f"--{common.FIELD_FLAGS[other[0]]}: only --p takes an axis in 'orbit' (the branch in p)"
        )
    ratio = common.kl_ratio(args)
    common.check_params(Params().with_values(fixed))
    params = Params().with_values(fixed, ratio)
    common.check_params(params, "--kl-ratio")
    tau_m = motor_tau_from_args(args, params)
    f_sat = motor_saturation_from_args(args, tau_m)
    # motor kinetics makes an active friction well posed; any base (a free or head one's rigid
    # offset is fixed by phase conditions, axojax/orbits/rigid.py)
    common.require_passive_friction(model, params, "orbit", motors=tau_m is not None)
    if tau_m is not None and axes:
        raise common.CLIError(
            "--p: a branch in p is not built with motor kinetics (--motor-tau-ms); give one value"
        )
    for value in axes.get("p", []):
        common.check_params(params.replace(p=float(value)))
    saturating = f_sat is not None  # then the saturation bounds the beat: --cubic 0 allowed
    if not (args.cubic > 0 or (saturating and args.cubic == 0)):
        bound = (
            ">= 0 with --motor-saturation"
            if saturating
            else "> 0 (the stiffening that bounds the beat)"
        )
        raise common.CLIError(f"--cubic: must be {bound}, got {args.cubic:g}")
    if args.cubic > MAX_CUBIC:
        raise common.CLIError(
            f"--cubic: expected at most {MAX_CUBIC:g} (1/L^2; default {DEFAULT_CUBIC:g}), got {args.cubic:g}"
        )
    if model.link_B.shape[0] == 0 and not saturating:
        raise common.CLIError(
            f"--model: {model.name!r} has no links, so the cubic link force cannot bound a beat; use a model with links"
        )
    try:
        H = int(str(args.harmonics))
        if not 1 <= H <= MAX_HARMONICS:
            raise ValueError
    except ValueError:
        raise common.CLIError(
            f"--harmonics: expected an integer in 1..{MAX_HARMONICS}, got {args.harmonics!r}"
        ) from None
    common.check_output("--out", args.out, (".npz",))
    common.check_output("--plot", args.plot, common.FIGURE_SUFFIXES)
    # the Newton system: (2H + 1) n unknowns, a dense LU (and its complex Floquet twin)
    n = model.n_dof * (1 if tau_m is None else 2)  # with motor kinetics, and its copy y
    common.check_memory(
        32.0 * ((2 * H + 1) * n) ** 2, "--harmonics", f"an orbit of {H} harmonics on {n} unknowns"
    )
    solver = HarmonicBalance(harmonics=H)
    motors = {}
    if tau_m is not None:  # {"tau_m", "tau_ms", "f_sat", "f_sat_pn_per_um"}: as simulate's JSON
        from ..dynamics.motors import motor_meta

        motors = {"motor_kinetics": motor_meta(tau_m, f_sat, units)}

    if "p" not in axes:
        try:
            with _progress.stage("orbit: the limit cycle (compiling, then solving)"):
                cycle = limit_cycle(
                    model, params, args.cubic, solver=solver, throw=True, tau_m=tau_m, f_sat=f_sat
                )
        except ValueError as err:
            raise common.CLIError(f"{'--p' if tau_m is None else '--mechanism'}: {err}") from None
        report = {"p": float(params.p), **cycle.to_json(units), **_sensitivity(cycle, units)}
        if args.out is not None:
            Branch(
                np.array([float(params.p)]),
                [report],
                math.nan,
                math.nan,
                {
                    "model": model.name,
                    "n_elements": model.n_elements,
                    "cubic": args.cubic,
                    **motors,
                },
            ).save(args.out)  # written whole (axojax._io)
        if args.plot is not None:
            from ..plotting.orbits import plot_orbit, save

            with _io.atomic_path(args.plot) as tmp:
                save(plot_orbit(cycle, units), tmp)
        return {"orbits": [report], **motors}

    p_values = axes["p"]
    if np.any(p_values <= 0):
        raise common.CLIError(f"--p: forces must be > 0, got {p_values.min():g}")
    bar = _progress.progress(
        total=len(p_values),
        desc="orbits",
        unit="p",
        starting="the Hopf point, then the first orbit",
    )
    flags = {}  # p -> the orbit's sensitivity (the branch keeps summaries, not orbits)

    def progress(p, cyc):
        if cyc is not None:
            flags[float(p)] = _sensitivity(cyc, units)
        bar.set_postfix_str(
            f"p={p:.4g} "
            + ("no orbit" if cyc is None else f"{float(cyc.frequency_hz(units)):.3f} Hz")
        )
        bar.update(1)

    try:
        with bar:
            result = branch(
                model, params, args.cubic, p_values, solver=solver, units=units, callback=progress
            )
    except ValueError as err:
        raise common.CLIError(f"--p: {err}") from None
    for c in result.cycles:
        if c is not None:
            c.update(flags.get(c["p"], {}))
    if args.out is not None:
        result.save(args.out)  # written whole (axojax._io)
    if args.plot is not None:
        from ..plotting.orbits import plot_branch, save

        with _io.atomic_path(args.plot) as tmp:
            save(
                plot_branch(
                    result.arrays(),
                    {
                        **result.meta,
                        "p_hopf": result.p_hopf,
                        "hopf_frequency_hz": result.hopf_frequency_hz,
                    },
                ),
                tmp,
            )
    return result.to_json()


def render(doc: dict) -> str:
    lines = motor_kinetics_lines(doc, "the orbit of the state and its motors' copy")
    if "hopf" in doc:
        h = doc["hopf"]
        lines.append(f"Hopf point of the equilibrium: p = {h['p']:.6g}, {h['frequency_hz']:.3f} Hz")
    lines.append(
        f"{'p':>10s}  {'freq (Hz)':>10s}  {'period (ms)':>11s}  {'tip amp (um)':>12s}  "
        f"{'wavelength (um)':>15s}  {'|rho_2|':>8s}  stable"
    )
    for o in doc["orbits"]:
        rho = sorted((abs(complex(*r)) for r in o["floquet"]), reverse=True)
        second = rho[1] if len(rho) > 1 else float("nan")
        lines.append(
            f"{o['p']:10.5g}  {o['frequency_hz']:10.4f}  {o['period_s'] * 1e3:11.3f}  "
            f"{o['tip_amplitude_um']:12.4f}  "
            f"{wavelength_text(o['wavelength_um'], '.3f', ''):>15s}  {second:8.4f}  "
            f"{o['stable']}"
            + sensitive_note(o.get("amplitude_dip") if o.get("wavelength_sensitive") else None)
        )
    rigid = [o for o in doc["orbits"] if o.get("rigid_floquet")]
    if rigid:
        off = max(
            abs(complex(*r) - 1) if r[0] is not None else math.inf
            for o in rigid
            for r in o["rigid_floquet"]
        )
        drift = max(abs(v) for o in rigid for v in o["rigid_drift"])
        lines.append(
            f"rigid motions of the base: {len(rigid[0]['rigid_floquet'])} trivial multipliers "
            f"(|rho - 1| <= {off:.1e}; not in rho_2 nor in stable), drift {drift:.1e} L or rad "
            "per tau (none: a periodic orbit)"
        )
    if doc.get("missing"):
        lines.append("no orbit at p = " + ", ".join(f"{p:g}" for p in doc["missing"]))
    return "\n".join(lines)
