"""The report of a fit: values, what the data determine and what they do not, and why.

Standard errors and correlations come from the Gauss-Newton (Fisher) matrix ``J^T J`` of
the normalised residuals in the fitted coordinate u at the optimum (log for positive
parameters: a log-space standard error 0.1 is a 10 % uncertainty). Rules:

- ``at_bound``: a parameter within 1 % of its bound range (in u) of a bound. The fit
  was stopped by the box, not by the data: it is never called identifiable.
- ``identifiable``: not at a bound, and a standard error (in u) at most
  ``IDENTIFIABLE_MAX_LOG_SE`` = 1 for log parameters (a factor e), at most
  ``IDENTIFIABLE_MAX_LINEAR_FRACTION`` = 5 % of the bound range for linear ones (0.3 for
  gamma's default (-3, 3): gamma is judged on its own scale, not relative to a value
  that may be near 0). Each value gets one verdict (determined, at a bound, only a
  combination with another determined, undetermined) from one rule: :mod:`.verdicts`.
- ``targets_met``: every scalar target reproduced within ``SCALAR_SIGMA_OK`` = 2 sigma (a
  correct model with honest sigmas misses 1 sigma a third of the time, 2 sigma one time
  in twenty) and every shape's rms normalised residual at most ``SHAPE_RMS_OK`` = 2.
  (Called ``converged`` before; that name stays, deprecated, and as the report's JSON
  key.) Whether the solver itself terminated is ``result`` (:mod:`axojax.results`).
- ``chi2_per_dof``: ``sum r^2 / (m - k)`` (None when there are no more residuals than
  fitted values).
- ``r2``, ``aic``, ``bic``, ``n_free`` (:mod:`.quality`): Sartori's R^2 of psi_1 over every
  observed shape point (None without a shape), and the information criteria with
  ``n_free`` = the fitted values plus 2 per shape fitted with a free complex amplitude
  and 1 per reference angle of a whole beat's psi_0 (``psi_offset_rad``).
- ``mechanism`` (``steady``, ``sliding``, ``curvature``, ``sliding+curvature``) and
  ``base`` (``clamped`` until other bases exist): the hypothesis that was fitted.
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
import warnings
from typing import Any

import numpy as np

from ... import _io
from ...params import BASAL_NAMES, MECHANISM_NAMES, NORMAL_NAMES, PARAM_NAMES, Params
from ...results import RESULTS, jsonable, message
from ...results import name as result_name
from .._arguments import SIGNED
from ..problem import CYCLE_FAILED, Problem
from .identifiability import start_notes, strong_pairs, uncertainty, verdicts
from .quality import information_criteria
from .quality import r2 as r2_of

AT_BOUND_FRACTION = 0.01
SHAPE_RMS_OK = 2.0
SCALAR_SIGMA_OK = 2.0


@dataclasses.dataclass
class FitResult:
    """What a least-squares fit found and how well it is determined.

    Attributes:
        params: fitted values by name (dimensionless; ``"ks"``, per-condition ``"p@150"``).
        full_params: the complete :class:`Params` of the first condition at the optimum.
        achieved: every scalar observable at the optimum, physical units (one condition:
            by name; several: ``"<name>@<label>"``).
        residuals: normalised residual of each scalar target (keys as ``achieved``).
        shape_rms: rms normalised residual of the shape target(s) (None without one).
        loss: 0.5 * sum of squared normalised residuals.
        targets_met: every target reproduced (scalars within 2 sigma, shapes rms <= 2).
        message: what is determined, what is not, and why.
        stderr: standard error of each fitted value, in its units (inf if not determined).
        correlation: (k, k) correlation matrix in the fitted coordinates.
        identifiable: per fitted value (never True at a bound).
        starts: (initial values, final loss) of each start.
        optima: (final values, final loss) of each start, in the order of ``starts``:
            where the starts stopped (distinct points at equal loss are distinct optima,
            e.g. several exact solutions of as many targets as parameters; a posterior
            spans them: :func:`axojax.inverse.suggest_transport`).
        names: the fitted values' names, in the order of ``correlation``.
        shared: the shared fitted values.
        chi2_per_dof: sum r^2 / (m - k), None if m <= k.
        dof: m - k (k: the fitted values and the reference angles, n_offsets).
        at_bound: names of values within 1 % of a bound (fitted coordinate).
        stderr_fitted: standard errors in the fitted coordinate (log or linear).
        coordinate: "log" or "linear" per name.
        conditions: per condition: label, complete params, achieved observables, targets
            with residuals, shape data (observed/fitted psi_1, psi_0, sigma) and the
            misfit of an excluded basal stretch.
        method, iterations, wall_s: solver name, iterations per start, wall time (s).
        problem: summary of the problem (bounds, floor, exclusion).
        notes: the message's parts.
        r2: Sartori's R^2 of psi_1 (:mod:`.quality`), None without a shape target.
        aic, bic: information criteria (:mod:`.quality`); n_free: the count they use.
        mechanism, base: the hypothesis fitted (regulated-dynein mechanism, base condition).
        result: the least-squares solver's :class:`axojax.results.RESULTS` item at the
            best start (``successful``: its termination test passed; e.g.
            ``nonlinear_max_steps_reached`` when it ran out of steps). Independent of
            ``targets_met``: a solver can terminate at an optimum that misses them.
    """

    params: dict[str, float]
    full_params: Params
    achieved: dict[str, float]
    residuals: dict[str, float]
    shape_rms: float | None
    loss: float
    targets_met: bool
    message: str
    stderr: dict[str, float]
    correlation: np.ndarray
    identifiable: dict[str, bool]
    starts: list[tuple[dict[str, float], float]]
    names: tuple[str, ...] = ()
    optima: list[tuple[dict[str, float], float]] = dataclasses.field(default_factory=list)
    shared: dict[str, float] = dataclasses.field(default_factory=dict)
    chi2_per_dof: float | None = None
    dof: int = 0
    at_bound: list[str] = dataclasses.field(default_factory=list)
    stderr_fitted: dict[str, float] = dataclasses.field(default_factory=dict)
    coordinate: dict[str, str] = dataclasses.field(default_factory=dict)
    conditions: list[dict[str, Any]] = dataclasses.field(default_factory=list)
    method: str = ""
    iterations: list[int] = dataclasses.field(default_factory=list)
    wall_s: float = 0.0
    problem: dict[str, Any] = dataclasses.field(default_factory=dict)
    notes: list[str] = dataclasses.field(default_factory=list)
    condition_params: list[Params] = dataclasses.field(default_factory=list)
    result: RESULTS = dataclasses.field(default_factory=lambda: RESULTS.successful)
    r2: float | None = None
    aic: float | None = None
    bic: float | None = None
    n_free: int = 0
    mechanism: str = "steady"
    base: str = "clamped"

    @property
    def converged(self) -> bool:
        """Deprecated: :attr:`targets_met` (what it always meant: the targets are
        reproduced, not that the solver converged; that is :attr:`result`)."""
        warnings.warn(
            "FitResult.converged is deprecated: use FitResult.targets_met (targets "
            "reproduced) or FitResult.result (the solver's termination)",
            DeprecationWarning,
            stacklevel=2,
        )
        return self.targets_met

    @property
    def result_message(self) -> str:
        """The message of :attr:`result` on one line (``"successful"``)."""
        return message(self.result)

    @property
    def multi(self) -> bool:
        return len(self.conditions) > 1

    def to_json(self) -> dict[str, Any]:
        """The ``axojax fit --json`` document (plain Python; NaN/inf as None)."""
        doc = {
            "params": dict(self.shared) if self.multi else dict(self.params),
            "fitted": dict(self.params),
            "loss": self.loss,
            "chi2_per_dof": self.chi2_per_dof,
            "dof": self.dof,
            "converged": self.targets_met,
            "targets_met": self.targets_met,
            "result": result_name(self.result),
            "result_message": self.result_message,
            "stderr": self.stderr,
            "stderr_fitted": self.stderr_fitted,
            "coordinate": self.coordinate,
            "at_bound": list(self.at_bound),
            "identifiable": self.identifiable,
            "names": list(self.names),
            "correlation": self.correlation.tolist(),
            "residuals": self.residuals,
            "shape_rms": self.shape_rms,
            "message": self.message,
            "notes": list(self.notes),
            "method": self.method,
            "iterations": list(self.iterations),
            "wall_s": self.wall_s,
            "problem": self.problem,
            "conditions": self.conditions,
            "r2": self.r2,
            "aic": self.aic,
            "bic": self.bic,
            "n_free": self.n_free,
            "mechanism": self.mechanism,
            "base": self.base,
        }
        if not self.multi:
            doc["achieved"] = self.achieved
        return jsonable(doc)

    def report(self) -> dict[str, Any]:
        """Alias of :meth:`to_json` (the historical name)."""
        return self.to_json()

    def save(self, path: str | pathlib.Path) -> None:
        """Write :meth:`to_json` to ``path`` (read by ``axojax plot FILE.json``), through
        a temporary file renamed into place (:func:`axojax._io.write_text`): a killed
        run leaves the old file or none, never half of one."""
        _io.write_text(path, json.dumps(self.to_json(), indent=1, allow_nan=False) + "\n")

    @staticmethod
    def is_document(doc: Any) -> bool:
        """Whether ``doc``, read back from a JSON file, is a fit report (:meth:`to_json`)."""
        return isinstance(doc, dict) and {"loss", "converged", "conditions"} <= set(doc)


def base_name(model) -> str:
    """The report's name of a model's base: its kind, ``+compliance`` with basal
    compliance (docs/model.md section 8)."""
    base = model.base
    return base.kind + ("+compliance" if base.compliance else "")


def _fmt(x: float) -> str:
    return f"{x:.3g}"


def build_report(
    problem: Problem,
    u,
    *,
    method: str = "",
    loss: float | None = None,
    gnorm: float = math.nan,
    iterations=(),
    wall_s: float = 0.0,
    starts=(),
    optima=(),
    result: RESULTS | None = None,
) -> FitResult:
    """The :class:`FitResult` of ``problem`` at the fitted coordinates ``u`` (k,)."""
    u = np.asarray(u, dtype=float)
    ev = problem.evaluate(u)
    r, J = ev["r"], ev["J"]
    loss = float(0.5 * np.sum(r**2)) if loss is None or not math.isfinite(loss) else float(loss)
    names = problem.names
    log = np.array([p.log for p in problem.parameters])
    values = problem.values(u)
    cov, se_u, corr, at_bound, verdict, combos = _uncertainty(problem, u, J)
    ident = {n: verdict[n] == "determined" for n in names}
    stderr = {
        n: float(values[n] * se_u[i]) if log[i] else float(se_u[i]) for i, n in enumerate(names)
    }

    conditions, achieved_all, res_all, off, shape_r = _conditions(problem, u, r, ev)
    reproduced = not off
    shape_rms = float(np.sqrt(np.mean(np.square(shape_r)))) if shape_r.size else None
    targets_met = bool(reproduced and math.isfinite(loss))
    dof = problem.dof
    chi2 = float(np.sum(r**2) / dof) if dof > 0 else None

    quality = _quality(problem, r, conditions)
    notes = _notes(problem, u, values, se_u, cov, verdict, combos)
    notes = _cycle_notes(problem, ev) + notes + _excluded_notes(conditions)
    notes += start_notes(starts, loss)
    text = "; ".join([_headline(targets_met, loss, chi2, off)] + notes)
    shared = {p.name: values[p.name] for p in problem.parameters if p.condition is None}
    return FitResult(
        params=dict(values),
        full_params=problem.condition_params(u, 0),
        achieved=achieved_all,
        residuals=res_all,
        shape_rms=shape_rms,
        loss=loss,
        targets_met=targets_met,
        message=text,
        stderr=stderr,
        correlation=corr,
        identifiable=ident,
        starts=list(starts),
        optima=list(optima),
        names=tuple(names),
        shared=shared,
        chi2_per_dof=chi2,
        dof=dof,
        at_bound=at_bound,
        stderr_fitted={n: float(se_u[i]) for i, n in enumerate(names)},
        coordinate={p.name: "log" if p.log else "linear" for p in problem.parameters},
        conditions=conditions,
        method=method,
        iterations=list(iterations),
        wall_s=float(wall_s),
        problem=problem.describe(),
        notes=notes,
        condition_params=[problem.condition_params(u, i) for i in range(problem.n_conditions)],
        result=RESULTS.successful
        if result is None
        else (result if isinstance(result, RESULTS) else RESULTS.promote(result)),
        **quality,
    )


def _uncertainty(problem: Problem, u, J) -> tuple:
    """What the Gauss-Newton matrix says of each fitted value: the covariance in u, the
    standard errors in u and the correlations (:func:`_covariance`), the values at a
    bound, and each value's verdict with the combinations determined
    (:func:`.verdicts.verdicts`)."""
    names = problem.names
    log = np.array([p.log for p in problem.parameters])
    span = problem.upper - problem.lower
    cov, se_u, corr = _covariance(J)
    frac = (u - problem.lower) / span
    at_bound = [
        n for n, f in zip(names, frac) if f <= AT_BOUND_FRACTION or f >= 1 - AT_BOUND_FRACTION
    ]
    verdict, combos = verdicts(names, cov, log, span, at_bound)
    return cov, se_u, corr, at_bound, verdict, combos


def _headline(targets_met: bool, loss: float, chi2: float | None, off: list[str]) -> str:
    """The message's first part: the targets reproduced (loss, chi^2 per degree of
    freedom), or which were missed."""
    if targets_met:
        return (
            f"targets reproduced (loss {loss:.3g}"
            + (f", chi2/dof {chi2:.3g}" if chi2 is not None else "")
            + ")"
        )
    return (
        "targets not reproduced within their uncertainty (infeasible for this model and "
        "bounds?): " + "; ".join(off)
    )


def mechanism_name(params: Params, free=()) -> str:
    """``steady``, ``sliding``, ``curvature`` or ``sliding+curvature``: which regulated
    coefficients act (non-zero, or fitted)."""
    acts = {f for f in SIGNED if f in free or float(np.asarray(getattr(params, f))) != 0.0}
    parts = [m for m, f in (("sliding", "chi"), ("curvature", "beta")) if any(f in a for a in acts)]
    return "+".join(parts) or "steady"


def _quality(problem: Problem, r, conditions: list[dict]) -> dict[str, Any]:
    """r2, aic, bic, n_free, mechanism and base of a fit (:mod:`.quality`). R^2 pools
    every condition's observed points; a linear-mode shape has a free complex amplitude
    (2 real values in n_free); a limit cycle's is fixed, its psi_0's reference angle not."""
    obs, fit, amplitudes = [], [], 0
    for i, entry in enumerate(conditions):
        data = entry.get("shape")
        if data is None:
            continue
        obs.append(np.asarray(data["psi1_obs_re"]) + 1j * np.asarray(data["psi1_obs_im"]))
        fit.append(np.asarray(data["psi1_fit_re"]) + 1j * np.asarray(data["psi1_fit_im"]))
        amplitudes += problem.shapes[i] is not None and problem.shapes[i].source != "limit_cycle"
        entry["r2"] = _finite(r2_of(obs[-1], fit[-1]))
    n_free = len(problem.names) + 2 * int(amplitudes) + problem.n_offsets
    aic, bic = information_criteria(float(np.sum(np.square(r))), n_free, int(np.size(r)))
    model = problem.models[0]
    return {
        "r2": _finite(r2_of(np.concatenate(obs), np.concatenate(fit))) if obs else None,
        "aic": _finite(aic),
        "bic": _finite(bic),
        "n_free": n_free,
        "mechanism": problem.mechanism
        or mechanism_name(problem.base[0], {p.field for p in problem.parameters}),
        "base": problem.base_name or base_name(model),
    }


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _covariance(J: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Covariance (k, k) in u from the Gauss-Newton matrix ``J^T J`` of the residuals
    (a tiny ridge: a singular direction gets a huge, finite variance; inf when J is not
    finite), the standard errors (k,) and correlations (k, k; NaN where undefined)."""
    k = J.shape[1]
    fisher = J.T @ J
    if np.all(np.isfinite(fisher)):
        ridge = 1e-12 * max(float(np.abs(fisher).max()), 1e-300)
        cov = np.linalg.inv(fisher + ridge * np.eye(k))
    else:
        cov = np.full((k, k), np.inf)
    se_u = np.sqrt(np.abs(np.diag(cov)))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se_u, se_u)
    return cov, se_u, np.where(np.isfinite(corr), corr, np.nan)


def _conditions(problem: Problem, u, r, ev) -> tuple[list, dict, dict, list[str], np.ndarray]:
    """Per condition its report entry; all achieved observables and residuals by name
    (``"<name>@<label>"`` with several conditions); the targets missed, in words; and
    the shape residuals of all conditions (flat)."""
    multi = problem.n_conditions > 1
    conditions, achieved_all, res_all, off, shape_r = [], {}, {}, [], []
    for i, (cond, lay, pred) in enumerate(
        zip(problem.conditions, problem.layout, ev["conditions"])
    ):
        suffix = f"@{problem.labels[i]}" if multi else ""
        entry = _condition_entry(problem, u, i, cond, pred)
        rs = r[lay.start : lay.start + lay.n_scalar]
        for t, rv in zip(problem.scalar_targets[i], rs):
            a = entry["achieved"].get(t.key, math.nan)
            entry["targets"].append(
                {
                    "name": t.key,
                    "value": t.value,
                    "sigma": t.sigma,
                    "achieved": a,
                    "residual": float(rv),
                }
            )
            entry["residuals"][t.key] = float(rv)
            if not abs(rv) <= SCALAR_SIGMA_OK:
                off.append(
                    f"{t.key}{suffix} {a:.4g} vs {t.value:.4g} +- {t.sigma:.3g} ({rv:+.1f} sigma)"
                )
        if lay.n_shape:
            rsh = shape_residuals(r, lay)
            rms = float(np.sqrt(np.mean(rsh**2)))
            entry["shape_rms"] = rms
            shape_r.append(np.asarray(rsh, dtype=float))
            if not rms <= SHAPE_RMS_OK:
                off.append(f"mode shape{suffix} rms residual {rms:.2f} sigma")
            entry["shape"], entry["excluded_base"] = _shape_data(problem, i, pred)
        conditions.append(entry)
        achieved_all |= {kk + suffix: v for kk, v in entry["achieved"].items()}
        res_all |= {kk + suffix: v for kk, v in entry["residuals"].items()}
    flat = np.concatenate(shape_r) if shape_r else np.zeros(0)
    return conditions, achieved_all, res_all, off, flat


def condition_achieved(pred: dict) -> dict[str, float]:
    """A condition's achieved observables from its predictions: the linear mode's, and the
    limit cycle's as ``limit_cycle_<name>`` and a whole beat's reference angle
    ``psi_offset_rad`` (:mod:`axojax.inverse.cycle_targets`; NaN where no orbit was found)."""
    achieved = {kk: float(v) for kk, v in pred.get("achieved", {}).items()}
    ok = bool(pred.get("cycle_converged", False))
    for kk, v in pred.get("cycle", {}).items():
        achieved[f"limit_cycle_{kk}"] = float(v) if ok else math.nan
    if "psi_offset_rad" in pred:  # the reference angle of a whole beat's psi_0
        achieved["psi_offset_rad"] = float(pred["psi_offset_rad"]) if ok else math.nan
    return achieved


def shape_residuals(r, lay) -> np.ndarray:
    """A condition's shape residuals out of the problem's residual vector ``r``."""
    return np.asarray(r[lay.start + lay.n_scalar : lay.start + lay.n_scalar + lay.n_shape])


def _condition_entry(problem: Problem, u, i: int, cond, pred) -> dict[str, Any]:
    """One condition's report entry before its targets are compared: parameters,
    achieved observables (the limit cycle's, NaN where no orbit was found)."""
    full = problem.condition_params(u, i)
    achieved = condition_achieved(pred)
    cubic = problem.orbit.values(problem._fitted_values(u, i)) if problem.needs_cycle[i] else {}
    return {
        "label": problem.labels[i],
        "params": _condition_params(full) | cubic,
        "fixed": dict(cond.params),
        "source": cond.source,
        "achieved": achieved,
        "targets": [],
        "residuals": {},
        "shape_rms": None,
        "shape": None,
        "excluded_base": None,
    }


def _cycle_notes(problem: Problem, ev) -> list[str]:
    """Why a fit with limit-cycle targets could not move, where no orbit was found."""
    failed = [
        problem.labels[i]
        for i, pred in enumerate(ev["conditions"])
        if "cycle" in pred and not bool(pred["cycle_converged"])
    ]
    if not failed:
        return []
    where = " in condition(s) " + ", ".join(failed) if problem.n_conditions > 1 else ""
    return [
        f"no limit cycle found{where} at these parameters (Newton from the Hopf normal form "
        "did not converge, or the straight state does not beat there): its targets count "
        f"{CYCLE_FAILED:g} sigma and give no gradient, so the fit "
        "could not move; start nearer a beating state (p a little above the Hopf point of "
        "`axojax critical`), or follow the branch with `axojax orbit --p a:b:n`"
    ]


def _excluded_notes(conditions: list[dict]) -> list[str]:
    """The misfit of every excluded basal stretch, against the fitted points'."""
    multi = len(conditions) > 1
    out = []
    for c in conditions:
        ex = c["excluded_base"]
        if ex is not None:
            out.append(
                f"basal stretch s < {ex['exclude_base_um']:g} "
                f"um{(' of ' + c['label']) if multi else ''} left out: misfit there "
                f"{ex['rms_rad']:.3g} rad rms "
                f"({ex['rms_sigma']:.2g} sigma) vs {ex['kept_rms_rad']:.3g} rad rms on the fitted points"
            )
    return out


def _shape_data(problem: Problem, i: int, pred) -> tuple[dict, dict | None]:
    """Observed and fitted psi_1 on all observed points (for plots) and the misfit of
    the excluded basal stretch (None when nothing is excluded)."""
    shape = problem.conditions[i].shape
    s = np.asarray(shape.s_um, dtype=float)
    obs = np.asarray(shape.psi1)
    fit = np.asarray(pred["psi1_fit"])
    measured = np.broadcast_to(np.asarray(shape.sigma, dtype=float), s.shape)
    sigma = np.sqrt(measured**2 + problem.shape_floor**2)  # what the residuals are divided by
    kept = s >= problem.exclude_base_um
    data = {
        "s_um": s,
        "psi1_obs_re": obs.real,
        "psi1_obs_im": obs.imag,
        "psi1_fit_re": fit.real,
        "psi1_fit_im": fit.imag,
        "sigma_rad": measured,  # the measurement's sigma (error bars)
        "floor_rad": float(problem.shape_floor),  # the model-discrepancy floor, drawn apart
        "psi0_rad": None if shape.psi0 is None else np.asarray(shape.psi0, dtype=float),
        "psi0_fit_rad": np.asarray(pred["psi0_fit"], dtype=float) if "psi0_fit" in pred else None,
        "source": shape.source,
        "component": list(shape.components),  # issue 33: each point's transverse component
        "kept": kept,
        "length_um": problem.units.length_um,
    }
    if kept.all():
        return data, None
    diff = obs - fit
    norm = np.concatenate([(diff.real / sigma), (diff.imag / sigma)])
    ex = np.concatenate([~kept, ~kept])
    excluded = {
        "exclude_base_um": problem.exclude_base_um,
        "points": int((~kept).sum()),
        "rms_rad": float(np.sqrt(np.mean(np.abs(diff[~kept]) ** 2))),
        "rms_sigma": float(np.sqrt(np.mean(norm[ex] ** 2))),
        "kept_rms_rad": float(np.sqrt(np.mean(np.abs(diff[kept]) ** 2))),
        "fraction_of_chi2": float(np.sum(norm[ex] ** 2) / max(np.sum(norm**2), 1e-300)),
    }
    return data, excluded


def _notes(problem, u, values, se_u, cov, verdict, combos) -> list[str]:
    """Plain-language statements, one verdict per value (:mod:`.verdicts`): determined
    values, values at a bound, combinations, undetermined values; then the strong
    correlations that no verdict already says."""
    names, params = problem.names, problem.parameters
    notes, determined = [], []
    for i, n in enumerate(names):
        if verdict[n] == "determined":
            spread = f"(x/ {math.exp(se_u[i]):.3g})" if params[i].log else f"+- {_fmt(se_u[i])}"
            determined.append(f"{n} = {_fmt(values[n])} {spread}")
    if determined:
        notes.append("determined: " + ", ".join(determined))
    for i, n in enumerate(names):
        if verdict[n] == "at_bound":
            notes.append(_at_bound(n, params[i], u[i]))
    if combos:
        notes.append(
            "only a combination is determined (each alone is not): "
            + ", ".join(f"{a}-{b} (correlation {c:+.3f})" for a, b, c in combos)
        )
    bad = [i for i, n in enumerate(names) if verdict[n] == "undetermined"]
    if bad:
        parts = [
            f"{names[i]} ({uncertainty(se_u[i], params[i].log, params[i].upper - params[i].lower)})"
            for i in bad
        ]
        notes.append(
            "not identifiable from these targets: "
            + ", ".join(parts)
            + " (standard error over a factor e, or over 5 % of a linear range); fix them or add targets"
        )
    pairs = strong_pairs(names, cov, verdict)
    if pairs:
        notes.append("strongly correlated: " + ", ".join(f"{a}-{b} {c:+.3f}" for a, b, c in pairs))
    return notes


def _at_bound(name: str, p, u: float) -> str:
    lower = (u - p.lower) <= (p.upper - u)
    edge = p.lower if lower else p.upper
    edge = math.exp(edge) if p.log else edge
    return (
        f"{name} sits at its {'lower' if lower else 'upper'} bound {_fmt(edge)}: the data push "
        "it out of the box (or do not constrain it); "
        "it is not determined; widen the bound, fix it, or add data that depend on it"
    )


def _condition_params(full: Params) -> dict[str, float]:
    """Every parameter of a condition, less each group that is all 0: the regulated-dynein
    coefficients (the steady load), the normal-force gain, the basal compliance and the
    static moment m0. Its report stays as it was before those existed, and each name it
    lists is a command-line flag, e.g. for ``axojax modes``."""
    values = {f: float(np.asarray(getattr(full, f))) for f in PARAM_NAMES}
    regulated = tuple(n for n in MECHANISM_NAMES if n not in NORMAL_NAMES)
    for group in (regulated, NORMAL_NAMES, BASAL_NAMES, ("m0",)):
        if not any(values[f] for f in group):
            values = {f: v for f, v in values.items() if f not in group}
    return values
