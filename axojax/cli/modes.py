"""``axojax modes``: spectrum and dominant mode at one parameter point."""

from __future__ import annotations

import argparse

import jax
import numpy as np

from ..eigen.mode import DEFAULT_SOLVER, dominant_mode, spectrum
from ..units import Units
from ..waveform.measures import sensitive_note, wavelength_text
from . import common
from .regulation import add_motor_tau_flag, motor_tau_from_args, require_static_normal_force

METRICS = ("growth_rate_per_s", "frequency_hz", "wavelength_um")
INFINITE_RATIO = 1e8
"""An eigenvalue of normal-force control's pencil with |lambda| beyond this times
max |A| / max |C| is an infinite one (QZ's beta at rounding level), not listed."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    parser.add_argument(
        "--top", type=int, default=10, metavar="K", help="how many eigenvalues to list (default 10)"
    )
    parser.add_argument(
        "--grad",
        default=None,
        metavar="NAMES",
        help="comma-separated parameters to differentiate by, e.g. p,ks",
    )
    common.add_solver_flag(parser)
    add_motor_tau_flag(
        parser,
        "a spectrum bounded as the mesh is refined even with an active friction (dense solve)",
    )


def motor_kinetics(model, params, units: Units, tau_m: float, tau_ms: float) -> dict:
    """``axojax modes --motor-tau-ms``: the augmented pencil's largest growth rate (dense
    eigenvalues, 1/s) and the beat, the eigenvalue nearest i omega0, with motor kinetics of
    relaxation time ``tau_m`` (dimensionless, checked by
    :func:`~axojax.cli.regulation.motor_tau_from_args`; ``tau_ms`` the flag's value)."""
    import scipy.linalg as sl

    from ..assembly.motor_kinetics import assemble_motor
    from ..eigen import Dense, nearest_mode

    system = assemble_motor(model, params, tau_m)
    lam = sl.eigvals(-np.asarray(system.A), np.asarray(system.C))
    lam = lam[np.isfinite(lam)]
    beat = nearest_mode(model, params, 1j * float(params.omega0), Dense(), tau_m=tau_m)
    return {
        "tau_ms": float(tau_ms),
        "tau_m": float(tau_m),
        "max_growth_rate_per_s": float(np.max(lam.real)) / units.tau_s,
        "beat": beat.to_json(units),
    }


def normal_force(args: argparse.Namespace, model, params, units: Units) -> dict:
    """``axojax modes --mechanism normal-force``: the augmented pencil of normal-force
    control (:func:`axojax.assembly.assemble_normal`, dense): its eigenvalues (LAPACK's QZ,
    the infinite ones of an algebraic force row left out), the dominant mode and, with
    ``--omega0-hz``, the beat (each by a shift-and-invert about it,
    :func:`axojax.eigen.normal_force_mode`)."""
    import scipy.linalg as sl

    from ..assembly import assemble_normal
    from ..eigen import normal_force_mode

    for flag, given in (
        ("--grad", args.grad is not None),
        ("--motor-tau-ms", getattr(args, "motor_tau_ms", None) is not None),
        ("--solver", getattr(args, "solver", None) not in (None, "auto", "dense")),
    ):
        if given:
            raise common.CLIError(
                f"{flag}: not with --mechanism normal-force yet (its pencil is solved densely, issue 55)"
            )
    require_static_normal_force(params)
    try:
        system = assemble_normal(model, params)
    except ValueError as err:
        raise common.CLIError(f"--mechanism normal-force: {err}") from None
    A, C = np.asarray(system.A), np.asarray(system.C)
    alpha, beta = sl.eigvals(-A, C, homogeneous_eigvals=True)
    # QZ leaves an infinite eigenvalue (an algebraic force row, g'' = 0) as beta ~ eps |C|:
    # |lambda| ~ |A| / (eps |C|), far beyond any finite one (~ 1e2 |A| / |C| at most)
    finite = np.abs(alpha) < INFINITE_RATIO * np.max(np.abs(A)) / np.max(np.abs(C)) * np.abs(beta)
    lam = alpha[finite] / beta[finite]
    lam = lam[np.argsort(-lam.real)]
    mode = normal_force_mode(model, params, complex(lam[0]))
    doc = {
        "model": model.name,
        "n_dof": model.n_unknowns,
        "tau_s": units.tau_s,
        "eigenvalues": [[float(z.real), float(z.imag)] for z in lam[: args.top]],
        "dominant": mode.to_json(units),
        "normal_force": {
            "gain": [float(params.normal_re), float(params.normal_im)],
            "n_unknowns": int(system.A.shape[0]),
        },
    }
    if float(params.omega0) > 0:
        beat = normal_force_mode(model, params, 1j * float(params.omega0))
        doc["beat"] = {
            **beat.to_json(units),
            "omega0_hz": float(params.omega0) / (2 * np.pi * units.tau_s),
        }
    return doc


def metric_gradients(
    model, params, names: list[str], kl_ratio, units: Units, solver=DEFAULT_SOLVER
) -> dict:
    """d(metric)/d(name) for the INTERFACE metrics (forward mode, one jvp per name)."""

    def metrics(values):
        mode = dominant_mode(model, params.with_values(values, kl_ratio), solver)
        return {
            "growth_rate_per_s": mode.growth_rate_per_s(units),
            "frequency_hz": mode.frequency_hz(units),
            "wavelength_um": mode.wavelength_um(units),
        }

    values = {n: jax.numpy.asarray(getattr(params, n), dtype=float) for n in names}
    jac = jax.jit(jax.jacfwd(metrics))(values)
    return {m: {common.FIELD_FLAGS[n]: float(jac[m][n]) for n in names} for m in METRICS}


def run(args: argparse.Namespace) -> dict:
    model = common.model_from_args(args, dense_spectrum=True)
    params = common.params_from_args(args)
    units = common.units_from_args(args)
    if args.top < 1:
        raise common.CLIError(f"--top: expected an integer >= 1, got {args.top}")
    if args.mechanism == "normal-force":
        return normal_force(args, model, params, units)
    names = common.parse_names(args.grad, "--grad") if args.grad is not None else []
    tau_m = motor_tau_from_args(args, params)  # one line naming --motor-tau-ms, before the solves
    # the spectrum is the dense pencil's, whatever --solver finds the dominant mode with
    # (its memory was checked with the model's, before the model was built)
    lam = np.asarray(spectrum(model, params, min(args.top, model.n_unknowns)))
    solver = common.solver_from_args(args)
    mode = dominant_mode(model, params, solver)
    doc = {
        "model": model.name,
        "n_dof": model.n_unknowns,
        "tau_s": units.tau_s,
        "eigenvalues": [[float(z.real), float(z.imag)] for z in lam],
        "dominant": mode.to_json(units),
    }
    if float(params.omega0) > 0:
        # a regulated mechanism's beat is the eigenvalue at i omega0 (docs/model.md section
        # 8); with an active friction the dominant one is a spurious short wave
        from ..eigen import nearest_mode
        from ..well_posed import TOLERANCE, friction_margin

        beat = nearest_mode(model, params, 1j * float(params.omega0), solver)
        doc["beat"] = {
            **beat.to_json(units),
            "omega0_hz": float(params.omega0) / (2 * np.pi * units.tau_s),
            "active_friction": friction_margin(model, params) < -TOLERANCE,
        }
    if tau_m is not None:
        doc["motor_kinetics"] = motor_kinetics(model, params, units, tau_m, args.motor_tau_ms)
    if names:
        doc["gradients"] = metric_gradients(
            model, params, names, common.kl_ratio(args), units, solver
        )
    return doc


def render(doc: dict) -> str:
    d = doc["dominant"]
    lines = [
        f"model {doc['model']}: {doc['n_dof']} unknowns, tau = {doc['tau_s']:.5g} s",
        "",
        "  #        Re(lambda)        Im(lambda)",
    ]
    for k, (re, im) in enumerate(doc["eigenvalues"]):
        lines.append(f"{k:3d}  {re:16.6f}  {im:+16.6f}")

    def fmt(x, unit, spec=".4g"):
        return "-" if x is None else f"{x:{spec}} {unit}"

    lines += [
        "",
        f"dominant mode: {d['classification']}",
        f"  eigenvalue      {d['eigenvalue'][0]:.6f} {d['eigenvalue'][1]:+.6f}i",
        f"  growth rate     {fmt(d['growth_rate_per_s'], '1/s')}",
        f"  frequency       {fmt(d['frequency_hz'], 'Hz')}",
        f"  wavelength      {wavelength_text(d['wavelength_um'])}"
        + sensitive_note(d.get("amplitude_dip") if d["wavelength_um"] is not None else None),
        f"  velocity        {fmt(d['velocity_um_per_s'], 'um/s')}",
        f"  direction       {d['direction'] or '-'}",
        f"  out-of-plane    {fmt(d['out_of_plane_ratio'], '', '.3g')}",
    ]
    if "beat" in doc:
        b = doc["beat"]
        lines += [
            "",
            f"beat (the eigenvalue nearest i omega0, omega0 = 2 pi x {b['omega0_hz']:.4g} Hz):",
            f"  eigenvalue      {b['eigenvalue'][0]:.6f} {b['eigenvalue'][1]:+.6f}i",
            f"  growth rate     {fmt(b['growth_rate_per_s'], '1/s')}",
            f"  frequency       {fmt(b['frequency_hz'], 'Hz')}",
            f"  wavelength      {wavelength_text(b['wavelength_um'])}"
            + sensitive_note(b.get("amplitude_dip") if b["wavelength_um"] is not None else None),
            f"  direction       {b['direction'] or '-'}",
        ]
        if b.get("active_friction"):
            lines.append(
                "  note: the friction is active (chi'' or beta'' < 0), so the dominant mode above is a "
                "spurious short wave that grows faster on finer meshes; read the mode nearest i omega0 as the beat"
            )
    if "normal_force" in doc:
        g = doc["normal_force"]["gain"]
        lines += [
            "",
            f"normal-force control, gain g = {g[0]:.6g} {g[1]:+.6g}i: a pencil of "
            f"{doc['normal_force']['n_unknowns']} unknowns with the pairs' forces (dense)",
        ]
    if "motor_kinetics" in doc:
        m, b = doc["motor_kinetics"], doc["motor_kinetics"]["beat"]
        lines += [
            "",
            f"with motor kinetics (tau_m = {m['tau_ms']:g} ms): largest growth rate of the spectrum "
            f"{m['max_growth_rate_per_s']:.4g} 1/s",
            f"  beat            {b['eigenvalue'][0]:.6f} {b['eigenvalue'][1]:+.6f}i, "
            f"{fmt(b['frequency_hz'], 'Hz')}, growth {fmt(b['growth_rate_per_s'], '1/s')}",
        ]
    if "gradients" in doc:
        lines += ["", "gradients (per unit of the dimensionless parameter):"]
        for metric, g in doc["gradients"].items():
            lines.append(f"  d {metric:18s} " + "  ".join(f"/d{k}: {v:.6g}" for k, v in g.items()))
    return "\n".join(lines)
