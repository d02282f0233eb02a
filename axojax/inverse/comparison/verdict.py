"""How compare judges its rows: each row's status (:func:`row_status`: successful, a
failure, a missed beat or not applicable, with its reason), their order (:func:`rank`:
successful rows first, by BIC, with BIC weights among them) and the verdict on the best
row (:func:`verdict`); :func:`mark` is a row's mark on the table."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .mechanisms import PIN_TOLERANCE

FREQUENCY_MATCH = 0.02
"""A ``successful`` row's beat is within 2 % of the observed frequency."""
GROWTH_MATCH = 3.0
"""... and its growth rate within 3 of the pin's sigmas (pin_tolerance x omega) of 0."""
RIGID_FREQUENCY = 0.01
"""A fitted beat below 1 % of the observed frequency is a neutral (rigid-body) mode."""
FIT_R2 = 0.9
"""The verdict's bar of R^2 (Sartori et al.'s fits: 0.95; docs/mechanisms.md)."""
FIT_CHI2_QUANTILE = 0.99
"""chi^2/dof within the data's sigmas (the shape floor in them): below this quantile of
the chi^2 distribution of the row's degrees of freedom, over dof."""
STATUS_MARKS = {"failed": "*", "not_applicable": "n/a"}
"""The table's marks: ``*`` a row that did not converge or missed the observed beat,
``n/a`` a row that cannot reach it (its reason below the table)."""


def mark(row: dict[str, Any]) -> str:
    """A row's status mark on the table: "" successful, ``*`` failed (not converged, or
    off the observed beat), ``n/a`` not applicable (:data:`STATUS_MARKS`)."""
    status = row.get("status", "successful")
    if status == "successful":
        return ""
    return STATUS_MARKS["not_applicable" if status == "not_applicable" else "failed"]


def row_status(
    mechanism: str,
    base: str,
    result: str,
    frequency_hz: float,
    growth_rate_per_s: float,
    frequency_obs: float,
    pin_tolerance: float = PIN_TOLERANCE,
) -> tuple[str, str | None]:
    """A fitted row's status and its reason in words (:class:`axojax.inverse.CompareRow`): a beat at
    0 Hz (below :data:`RIGID_FREQUENCY` of the observed) is a neutral, rigid-body mode:
    the row is ``not_applicable`` (on a base that holds nothing the steady load's net
    moment is not balanced at the base, so no mode of it reaches the observed beat);
    a solver that did not converge gives its code; a converged fit off the observed
    frequency (more than :data:`FREQUENCY_MATCH`) or growing or decaying (more than
    :data:`GROWTH_MATCH` pin sigmas) is ``missed_beat``; else ``successful``."""
    omega = 2 * math.pi * frequency_obs
    f, g = frequency_hz, growth_rate_per_s
    if math.isfinite(f) and abs(f) < RIGID_FREQUENCY * frequency_obs:
        why = (
            "its net moment is not held at a free base, so"
            if mechanism == "steady" and not base.startswith(("clamped", "pivot"))
            else "so"
        )
        return "not_applicable", (
            f"the mode it follows is a rigid-body motion at {f:.3g} Hz: {why} this row has no "
            f"beat near the observed {frequency_obs:.4g} Hz to fit"
        )
    if result != "successful":
        return result, f"the least-squares solver stopped before converging ({result})"
    if not (math.isfinite(f) and math.isfinite(g)):
        return "missed_beat", "the fitted beat has no finite frequency or growth rate"
    if abs(f - frequency_obs) > FREQUENCY_MATCH * frequency_obs:
        return "missed_beat", (
            f"its beat is at {f:.4g} Hz, {100 * (f - frequency_obs) / frequency_obs:+.1f} % "
            f"off the observed {frequency_obs:.4g} Hz (at most {100 * FREQUENCY_MATCH:g} %)"
        )
    if abs(g) > GROWTH_MATCH * pin_tolerance * omega:
        return "missed_beat", (
            f"its beat {'grows' if g > 0 else 'decays'} at {g:.3g} 1/s (at most "
            f"{GROWTH_MATCH * pin_tolerance * omega:.3g} 1/s: {GROWTH_MATCH:g} x --pin-tolerance x 2 pi f)"
        )
    return "successful", None


def _rank_key(r) -> tuple[int, float]:
    """Successful rows first, then failed ones, then not applicable; each by BIC."""
    group = 0 if r.status == "successful" else 2 if r.status == "not_applicable" else 1
    return group, math.inf if r.bic is None else r.bic


def rank(rows: list) -> None:
    """Order ``rows`` in place (:func:`_rank_key`) and set each one's ``delta_bic`` (to
    the first row's BIC) and ``weight`` (BIC weights over the successful rows)."""
    rows.sort(key=_rank_key)
    best = rows[0].bic if rows else None
    ok = [r.bic for r in rows if r.successful and r.bic is not None]
    total = sum(math.exp(-0.5 * (b - min(ok))) for b in ok) if ok else 0.0
    for r in rows:
        r.delta_bic = None if r.bic is None or best is None else r.bic - best
        ok_row = r.successful and r.bic is not None and total > 0
        r.weight = math.exp(-0.5 * (r.bic - min(ok))) / total if ok_row else None


def verdict(doc: dict[str, Any]) -> dict[str, Any]:
    """Whether the best row fits the beat, from a comparison document's rows (best
    first): ``fits`` when the best row is successful, has R^2 >= :data:`FIT_R2` and
    chi^2/dof within the data's sigmas (at most the :data:`FIT_CHI2_QUANTILE` quantile of
    chi^2 with its degrees of freedom, over dof: the sigmas hold the shape floor);
    ``shape`` when only the chi^2 bar is missed (the shape is fitted, but residuals
    exceed what the sigmas allow: the model misses something the data resolve);
    ``none`` otherwise. ``text`` says it in one line (with the best row's share of first
    places over bootstrap resamples of the cycles when the document has ``robustness``,
    :mod:`axojax.inverse.comparison.robustness`), ``rule`` states the bars."""
    from scipy.stats import chi2 as chi2_dist

    rows = doc["rows"]
    # Re and Im of each point and the two pins (a whole-beat comparison says its own count)
    n = doc.get("n_residuals") or 2 * len(doc["data"].get("s_um", ())) + 2
    rule = (
        f"a row fits when it is successful, R^2 >= {FIT_R2:g} and chi2/dof <= the "
        f"{100 * FIT_CHI2_QUANTILE:g} % point of chi^2/dof for its degrees of freedom"
    )
    ok = [r for r in rows if r.get("status", "successful") == "successful" and r["r2"] is not None]
    if not ok:
        best_r2 = max((r["r2"] for r in rows if r["r2"] is not None), default=None)
        tail = "" if best_r2 is None else f" (best R^2 {best_r2:.2f}, not converged)"
        return {
            "fits": "none",
            "best": None,
            "rule": rule,
            "chi2_per_dof_max": None,
            "text": f"no row fits this beat: none converged at the observed beat{tail}",
        }
    best = ok[0]
    dof = max(n - best["n_free"], 1)
    limit = float(chi2_dist.ppf(FIT_CHI2_QUANTILE, dof) / dof)
    name = f"{best['mechanism']} on {best['base']}"
    r2, c2 = best["r2"], best["chi2_per_dof"]
    weight = best.get("weight")
    share = "" if weight is None else f", BIC weight {weight:.2f}"
    top_r2 = max(r["r2"] for r in ok)
    if r2 >= FIT_R2 and c2 is not None and c2 <= limit:
        fits, text = (
            "fits",
            f"{name} fits this beat: R^2 {r2:.3f}, chi2/dof {c2:.3g} (<= {limit:.3g}){share}",
        )
    elif r2 >= FIT_R2:
        fits = "shape"
        text = (
            f"{name} fits the shape (R^2 {r2:.3f}{share}) but not within the data's sigmas: "
            f"chi2/dof {c2:.3g} > {limit:.3g} (the model misses what the data resolve)"
        )
    else:
        fits, text = "none", f"no row fits this beat (best R^2 {top_r2:.2f}; best by BIC: {name})"
    close = [
        f"{r['mechanism']} on {r['base']}"
        for r in ok[1:]
        if r.get("delta_bic") is not None and r["delta_bic"] < INDISTINGUISHABLE_BIC
    ]
    if close:
        shown = ", ".join(close[:3]) + (f" and {len(close) - 3} more" if len(close) > 3 else "")
        text += f"; indistinguishable from it by BIC (within {INDISTINGUISHABLE_BIC:g}): {shown}"
    warning = base_warning(doc, best)
    robust = doc.get("robustness")
    if robust and robust.get("identical"):
        text += (
            f"; the recording's {robust['cycles']} cycles are copies of one: no bootstrap "
            "over cycles says how stable the ranking is"
        )
    elif robust:
        text += (
            f"; first in {100 * robust['best_share']:.0f} % of {robust['resamples']} bootstrap "
            f"resamples of the {robust['cycles']} cycles"
        )
    return {
        "fits": fits,
        "best": {"mechanism": best["mechanism"], "base": best["base"]},
        "rule": rule,
        "chi2_per_dof_max": limit,
        "text": text,
        "warning": warning,
        "indistinguishable": close,
    }


INDISTINGUISHABLE_BIC = 2.0
"""Successful rows within this BIC of the best are named as indistinguishable from it
(Kass & Raftery 1995: a difference below 2 is "not worth more than a bare mention")."""
BASE_PSI1_SHARE = 0.2
"""|psi_1(0)| above this share of max |psi_1| (and 3 of the data's median sigmas) contradicts
a winning base that holds the tangent (clamped or pivot on a spring: psi_1(0) = 0)."""


def base_warning(doc: dict[str, Any], best: dict[str, Any]) -> str | None:
    """One line when the data's psi_1 at the base contradicts the best row's base: a held
    base (clamped, with or without compliance) has psi_1(0) = 0, so a beat whose |psi_1(0)|
    is a large share (:data:`BASE_PSI1_SHARE`) of its maximum, in the lab frame, was
    recorded in a frame in which the base moves (docs/model.md section 8, frames); None
    otherwise (or when the data do not start at the base)."""
    data = doc["data"]
    s, psi = data.get("s_um"), data.get("psi1")
    if not s or not psi or abs(s[0]) > 1e-9 or data.get("frame", "lab") != "lab":
        return None
    if not best["base"].startswith("clamped"):
        return None
    a = np.abs(np.asarray(psi, dtype=float) @ [1, 1j])
    sigma = (data.get("psi1_sigma_rad") or {}).get("median", 0.0)
    if a.max() <= 0 or a[0] <= BASE_PSI1_SHARE * a.max() or a[0] <= 3 * sigma:
        return None
    return (
        f"the data's |psi_1| at the base is {a[0] / a.max():.2f} of its maximum, but the best "
        f"row's {best['base']} base holds psi_1(0) = 0: if the base moves in the recording's "
        "frame (a lab-frame beat), free or head bases fit it as recorded, or compare both in "
        "the basal frame (--frame basal)"
    )
