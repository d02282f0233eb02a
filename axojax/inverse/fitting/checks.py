"""Checks of a fit's optimum that the fit itself cannot see: its regime and its mesh.

**Regime.** A fit compares the dominant *linear* mode (or a limit cycle) with a measured
beat. Near the onset of beating (the Hopf point, Re lambda = 0) the linear mode's
frequency is the beat's; far past it, it is not. In the Hopf normal form
``dz/dt = (mu + i omega) z + l1 |z|^2 z`` the cycle's angular frequency is
``omega + mu Im(l1) / (-Re l1)``: it departs from the linear one by a relative
``r |Im l1 / Re l1|``, first order in the ratio ``r = Re lambda / |Im lambda|``, and the
expansion's neglected terms are of order ``r^2``. :func:`regime` reports ``r`` of every
condition's dominant mode at the optimum and names it:

- ``"near onset"``: ``|r| <= NEAR_ONSET`` (0.1): the normal form's correction is at most
  about 10 % (for ``|Im l1 / Re l1| <= 1``) and its neglected terms about 1 %, so the
  linear frequency stands in for the beat's to about 10 %; the linear amplitude grows
  by at most ``exp(2 pi 0.1) = 1.9`` per period;
- ``"far past onset"``: ``r > NEAR_ONSET``: the linear mode grows several-fold in one
  period (``exp(2 pi r)``), the beat is set by the nonlinearity, and a fit of the
  linear frequency to it is a fit of a stand-in;
- ``"decaying"``: ``r < -NEAR_ONSET``: the straight state is stable; this mode does not
  beat at all;
- ``"not oscillating"``: ``Im lambda = 0`` (to ``IMAG_RTOL``): no frequency to compare.

**Mesh.** A fit's parameters are those of a discretised model. :func:`mesh_check` refits
from the optimum on the same problem with ``factor`` (2) times the elements, for a few
Levenberg-Marquardt iterations (``MESH_STEPS``), and reports the refitted values, the
observables there, the observables of the *fitted* values on the finer mesh (the
discretisation error of the predictions) and the relative changes; a change above
``MESH_TOLERANCE`` (5 %) of a fitted value or of a targeted observable is a warning.
5 %: far above the refit's own tolerance (optimistix's 1e-5, so the refit never warns
by itself), and half the standard error of the best-determined parameters of these fits
(about 10 %: p x/ 1.11 in the human-sperm fit), so a warning means the mesh moves the
answer by a sizeable part of its error bar. A fitted value on a ridge (strongly
correlated with another) can move far along it while the observables barely do: the
report then says the fit is not mesh-converged even though it reproduces its targets.

Pure functions of a :class:`~axojax.inverse.Problem` and its
:class:`~axojax.inverse.FitResult`; :func:`fit_checks` runs both and
:func:`render_checks` writes the text lines of the JSON document.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import jax.numpy as jnp
import numpy as np

from ..._memory import check_model_size
from ...eigen.mode import IMAG_RTOL, dominant_mode
from ...eigen.normal_force import NormalForce, normal_force_mode
from ...models.section import Model, build_model
from ...results import jsonable
from ..problem import EDGE, Problem
from .least_squares import LevenbergMarquardt
from .report import FitResult, condition_achieved, shape_residuals

NEAR_ONSET = 0.1
"""|Re lambda| / |Im lambda| up to which a mode counts as near onset (module docstring)."""
MESH_FACTOR = 2
"""The mesh check's element multiplier."""
MESH_STEPS = 10
"""Levenberg-Marquardt iterations of the mesh check's refit (from the optimum)."""
MESH_TOLERANCE = 0.05
"""Relative change of a fitted value or targeted observable that is a warning."""
LINEAR_SCALE = 0.01
"""A linear-coordinate parameter's change is relative to max(|value|, this x its range)."""

NEAR, FAR, DECAYING, STANDING = "near onset", "far past onset", "decaying", "not oscillating"
UNKNOWN = "unknown"  # the eigen-solve gave no finite eigenvalue


def classify_regime(eigenvalue: complex, threshold: float = NEAR_ONSET) -> tuple[str, float]:
    """(regime name, r = Re lambda / |Im lambda|) of a dominant eigenvalue (any time unit).

    ``r`` is ``inf``/``-inf`` and the regime ``"not oscillating"`` when ``|Im lambda| <=
    IMAG_RTOL (1 + |lambda|)`` (a real eigenvalue, as :func:`axojax.eigen.mode.classify`);
    otherwise ``"decaying"`` for ``r < -threshold``, ``"near onset"`` for
    ``|r| <= threshold``, ``"far past onset"`` for ``r > threshold``.
    """
    lam = complex(eigenvalue)
    if not (math.isfinite(lam.real) and math.isfinite(lam.imag)):
        raise ValueError(f"eigenvalue must be finite, got {lam!r}")
    if not (math.isfinite(threshold) and threshold >= 0):
        raise ValueError(f"threshold must be >= 0, got {threshold!r}")
    if abs(lam.imag) <= IMAG_RTOL * (1.0 + abs(lam)):
        return STANDING, math.copysign(math.inf, lam.real)
    r = lam.real / abs(lam.imag)
    if r < -threshold:
        return DECAYING, r
    return (NEAR if r <= threshold else FAR), r


def regime(
    problem: Problem, result: FitResult, threshold: float = NEAR_ONSET
) -> list[dict[str, Any]]:
    """Every condition's dominant mode at the optimum, named by :func:`classify_regime`
    (normal-force control's beat, the mode nearest the problem's shift: its pencil has
    no dominant mode to follow).

    Returns one dict per condition: ``label``, ``regime`` (``"unknown"`` where the
    eigen-solve gave no finite eigenvalue), ``ratio`` (Re lambda / |Im lambda|, None
    when not oscillating or unknown), ``growth_rate_per_s``, ``frequency_hz``
    (linear mode, physical units of the problem) and ``growth_per_period`` (the linear
    amplitude's factor over one period, ``exp(2 pi ratio)``; None when not oscillating).
    """
    out = []
    for i, label in enumerate(problem.labels):
        model, params = problem.models[i], result.condition_params[i]
        if isinstance(problem.solver, NormalForce):  # no dominant mode: the beat's
            mode = normal_force_mode(model, params, problem.shift)
        else:
            mode = dominant_mode(model, params, problem.solver)
        lam = complex(mode.eigenvalue)
        if math.isfinite(lam.real) and math.isfinite(lam.imag):
            name, r = classify_regime(lam, threshold)
        else:  # no eigenvalue at these values (the fit's own report says why)
            name, r = UNKNOWN, math.nan
        finite = math.isfinite(r)
        out.append(
            {
                "label": label,
                "regime": name,
                "ratio": r if finite else None,
                "threshold": threshold,
                "growth_rate_per_s": float(mode.growth_rate_per_s(problem.units)),
                "frequency_hz": float(mode.frequency_hz(problem.units)),
                "growth_per_period": math.exp(min(2 * math.pi * r, 700.0)) if finite else None,
            }
        )
    return out


def refined(problem: Problem, factor: int = MESH_FACTOR) -> Problem:
    """``problem`` on models with ``factor`` times the elements (same sections, profiles,
    bases and imbalance reading; everything else as given: conditions' fixed values, targets,
    free parameters, bounds, tie, units, solvers, floor, exclusion, prior). A finer model
    too large for this machine's memory is a one-line ``ValueError`` before it is built."""
    if not (isinstance(factor, int) and factor >= 1):
        raise ValueError(f"factor must be an integer >= 1, got {factor!r}")
    fine: dict[Model, Model] = {}

    def finer(m: Model) -> Model:
        if m not in fine:
            check_model_size(m.section, factor * m.n_elements)
            fine[m] = build_model(
                m.section, factor * m.n_elements, m.profiles, m.imbalance_kind, m.base
            )
        return fine[m]

    conditions = [
        dataclasses.replace(c, params=base, model=None if c.model is None else finer(c.model))
        for c, base in zip(problem.conditions, problem.base)
    ]
    return Problem(
        finer(problem.model),
        conditions,
        problem.free_shared,
        per_condition=problem.free_per_condition,
        params=problem.base[0],
        bounds=problem.bounds,
        kl_ratio=problem.kl_ratio,
        units=problem.units,
        solver=problem.solver,
        cubic=problem.cubic,
        orbit_solver=problem.orbit_solver,
        tau_m=problem.orbit.tau_m,
        f_sat=problem.orbit.f_sat,
        shape_floor=problem.shape_floor,
        exclude_base_um=problem.exclude_base_um,
        prior=problem.prior,
        shift=problem.shift,
        mechanism=problem.mechanism,
        base=problem.base_name,
    )


def _coordinates(problem: Problem, values: dict[str, float]) -> np.ndarray:
    """(k,) fitted coordinates u of ``values``, kept ``EDGE`` of the range inside the bounds."""
    u = np.array([p.to_u(values[p.name]) for p in problem.parameters])
    span = problem.upper - problem.lower
    return np.clip(u, problem.lower + EDGE * span, problem.upper - EDGE * span)


def _observables(problem: Problem, ev: dict) -> dict[str, float]:
    """Every condition's scalar observables (and limit-cycle ones) and shape rms (sigma),
    keyed as in :attr:`FitResult.achieved` (``@label`` when several conditions)."""
    out: dict[str, float] = {}
    multi = problem.n_conditions > 1
    r = ev["r"]
    for i, (pred, lay) in enumerate(zip(ev["conditions"], problem.layout)):
        suffix = f"@{problem.labels[i]}" if multi else ""
        for k, v in condition_achieved(pred).items():
            out[k + suffix] = v
        if lay.n_shape:
            rs = shape_residuals(r, lay)
            out["shape_rms" + suffix] = float(np.sqrt(np.mean(rs**2)))
    return out


def _relative(new: float, old: float, scale: float | None = None) -> float:
    """(new - old) / |old| (or / max(|old|, scale)); NaN where either is not finite,
    +-inf from 0 to a non-zero value (e.g. a standing mode's frequency 0 that oscillates
    on the finer mesh)."""
    if not (math.isfinite(new) and math.isfinite(old)):
        return math.nan
    den = abs(old) if scale is None else max(abs(old), scale)
    if den == 0:
        return 0.0 if new == old else math.copysign(math.inf, new - old)
    return (new - old) / den


def _targeted(problem: Problem) -> list[str]:
    """Keys of the targeted scalar observables (as in :func:`_observables`)."""
    multi = problem.n_conditions > 1
    keys = []
    for i, targets in enumerate(problem.scalar_targets):
        suffix = f"@{problem.labels[i]}" if multi else ""
        for t in targets:
            keys.append((f"limit_cycle_{t.name}" if t.source == "limit_cycle" else t.name) + suffix)
    return keys


def mesh_check(
    problem: Problem,
    result: FitResult,
    *,
    factor: int = MESH_FACTOR,
    max_steps: int = MESH_STEPS,
    tolerance: float = MESH_TOLERANCE,
) -> dict[str, Any]:
    """Refit ``result``'s optimum on ``problem`` with ``factor`` times the elements.

    Args:
        problem: the fitted problem.
        result: its fit (:func:`~axojax.inverse.least_squares`).
        factor: element multiplier (default 2).
        max_steps: Levenberg-Marquardt iterations of the refit, from the optimum.
        tolerance: relative change above which a fitted value or a targeted observable
            is listed in ``moved`` (a warning).

    Returns:
        ``elements`` (the finer models' elements per filament), ``from_elements``,
        ``steps`` (iterations taken), ``refit_converged`` (the refit stopped on its
        tolerance before ``max_steps``; else the values are where ``max_steps`` got, on
        the way along a ridge), ``params`` (refitted values), ``achieved``
        (observables at the refitted values, 2N), ``achieved_at_fit`` (observables of
        the *fitted* values on the finer mesh), ``relative_change`` (fitted value ->
        refitted value for parameters; N -> 2N at the fitted values for observables;
        a linear-coordinate parameter relative to ``max(|value|, LINEAR_SCALE x range)``),
        ``loss_at_fit`` and ``loss`` on the finer mesh, ``tolerance``, ``moved`` (the
        fitted values and targeted observables whose |relative change| exceeds it) and
        ``mesh_converged`` (``moved`` is empty).
    """
    if not (isinstance(max_steps, int) and max_steps >= 1):
        raise ValueError(f"max_steps must be an integer >= 1, got {max_steps!r}")
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise ValueError(f"tolerance must be > 0, got {tolerance!r}")
    fine = refined(problem, factor)
    u_fit = _coordinates(fine, result.params)
    ev_fit = fine.evaluate(u_fit)
    run = LevenbergMarquardt(max_steps=max_steps).compile(fine)
    z, loss, steps, _, _ = run(fine.to_z(jnp.asarray(u_fit)))
    u_new = np.asarray(fine.to_u(z))
    if not np.all(np.isfinite(u_new)):
        u_new = u_fit  # the refit failed: report the fitted values on the finer mesh
    ev_new = fine.evaluate(u_new)
    params = fine.values(u_new)
    at_fit = _observables(fine, ev_fit)
    coarse = _observables(problem, problem.evaluate(_coordinates(problem, result.params)))
    change: dict[str, float] = {}
    for p in fine.parameters:
        scale = None if p.log else LINEAR_SCALE * (p.upper - p.lower)
        change[p.name] = _relative(params[p.name], result.params[p.name], scale)
    for k, v in at_fit.items():
        change[k] = _relative(v, coarse.get(k, math.nan))
    watched = list(fine.names) + [k for k in _targeted(problem) if k in change]
    moved = [k for k in watched if not abs(change[k]) <= tolerance]
    elements = sorted({m.n_elements for m in fine.models})
    return {
        "factor": factor,
        "elements": elements[0] if len(elements) == 1 else elements,
        "from_elements": (
            problem.models[0].n_elements
            if len(elements) == 1
            else sorted({m.n_elements for m in problem.models})
        ),
        "steps": int(steps),
        "refit_converged": int(steps) < max_steps,
        "params": params,
        "achieved": _observables(fine, ev_new),
        "achieved_at_fit": at_fit,
        "achieved_before": coarse,
        "relative_change": change,
        "loss_at_fit": float(0.5 * np.sum(ev_fit["r"] ** 2)),
        "loss": float(0.5 * np.sum(ev_new["r"] ** 2)) if math.isfinite(float(loss)) else None,
        "tolerance": tolerance,
        "moved": moved,
        "mesh_converged": not moved,
    }


def fit_checks(
    problem: Problem, result: FitResult, *, mesh: bool = True, **mesh_options
) -> dict[str, Any]:
    """``{"regime": regime(...), "mesh_check": mesh_check(...)}``: the JSON entries of a
    fit report (plain numbers; NaN and infinities as None). ``mesh=False``: ``"mesh_check"``
    is None; a finer model too large for memory: ``{"skipped": reason}``. ``mesh_options`` go to :func:`mesh_check`."""
    checked: dict[str, Any] | None = None
    if mesh:
        try:
            checked = mesh_check(problem, result, **mesh_options)
        except MemoryError as err:  # pragma: no cover - the estimate refuses first
            checked = {"skipped": f"out of memory ({err})"}
        except ValueError as err:
            if "memory" not in str(err):
                raise
            checked = {"skipped": str(err)}
    return jsonable({"regime": regime(problem, result), "mesh_check": checked})


def _pct(x: float | None) -> str:
    return "n/a" if x is None or not math.isfinite(x) else f"{100 * x:+.1f} %"


def render_checks(doc: dict[str, Any]) -> list[str]:
    """Text lines of a report's ``regime`` and ``mesh_check`` entries (JSON as written:
    NaN as None); none when the document has neither. Warnings start with ``warning:``."""
    lines = []
    for c in doc.get("regime") or []:
        head = f"[{c['label']}] " if len(doc["regime"]) > 1 else ""
        r = c["ratio"]
        if r is None:
            why = "real dominant eigenvalue" if c["regime"] == STANDING else "no finite eigenvalue"
            lines.append(f"{head}regime: {c['regime']} ({why})")
            continue
        lines.append(
            f"{head}regime: {c['regime']} (Re/|Im| lambda = {r:.3g}, threshold {c['threshold']:g}: "
            f"growth {c['growth_rate_per_s']:.3g} /s at {c['frequency_hz']:.3g} Hz)"
        )
        if c["regime"] == FAR:
            lines.append(
                f"warning: {head}regime: far past the onset of beating (the linear mode grows "
                f"x{c['growth_per_period']:.3g} per period): its frequency and shape are a poor "
                "stand-in for a finite-amplitude beat's; compare with the limit cycle (--target limit-cycle)"
            )
    m = doc.get("mesh_check")
    if m and m.get("skipped"):
        lines.append(f"mesh check skipped: {m['skipped']}")
    elif m:
        change = m["relative_change"]
        parts = [
            f"{k} {doc['fitted'][k]:.3g} -> {v:.3g} ({_pct(change.get(k))})"
            for k, v in m["params"].items()
        ]
        obs = [
            f"{k} {_pct(change.get(k))}"
            for k in m["achieved_at_fit"]
            if k in change and not k.startswith("shape_rms")
        ]
        lines.append(
            f"mesh check ({m['from_elements']} -> {m['elements']} elements, refit {m['steps']} steps"
            + ("" if m.get("refit_converged", True) else ", not converged")
            + "): "
            + ", ".join(parts)
            + ("; observables at the fitted values: " + ", ".join(obs) if obs else "")
        )
        if m["moved"]:
            moved = ", ".join(f"{k} {_pct(change.get(k))}" for k in m["moved"])
            lines.append(
                f"warning: mesh check: {moved} at {m['elements']} elements (tolerance "
                f"{100 * m['tolerance']:g} %): the fit is not mesh-converged; refit with more elements (--elements)"
            )
    return lines
