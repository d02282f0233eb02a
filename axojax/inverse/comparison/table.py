"""Compare's text tables: the ranked rows with their status marks and the verdict
(:func:`render_table`), and the fitted values in physical units with their standard errors
(:func:`render_params`); :data:`PHYSICAL` names each value's unit."""

from __future__ import annotations

from typing import Any

from .verdict import mark, verdict

PHYSICAL = {
    "chi_re": ("chi_re_pn_per_um2", "chi_to_pn_per_um2"),
    "chi_im": ("chi_im_pn_per_um2", "chi_to_pn_per_um2"),
    "beta_re": ("beta_re_pn", "beta_to_pn"),
    "beta_im": ("beta_im_pn", "beta_to_pn"),
    "p": ("p_pn_per_um", "p_to_pn_per_um"),
    "kb": ("kb_pn_per_um", "kb_to_pn_per_um"),
    "cb": ("cb_um_per_pn", "cb_to_um_per_pn"),
    "xib": ("xib_pn_s_per_um", "xib_to_pn_s_per_um"),
    "kl": ("kl_pn_per_um2", "k_to_pn_per_um2"),
    "ks": ("ks_pn_per_um2", "k_to_pn_per_um2"),
    "cl": ("cl_pn_s_per_um2", "c_to_pn_s_per_um2"),
    "gamma": ("gamma", None),
    "normal_re": ("normal_re", None),
    "normal_im": ("normal_im", None),
    "m0": ("m0_pn", "moment_to_pn"),
    "f_sat": ("f_sat_pn_per_um", "p_to_pn_per_um"),
    "tau_m": ("tau_m_ms", "time_to_ms"),
}
"""Each fitted value's physical name (its unit in the name) and the :class:`Units`
conversion to it (docs/model.md section 1 and 8): chi in pN/um^2, beta in pN, the steady
load p in pN/um, the basal spring k_b in pN/um (fitted as its compliance 1/k_b, um/pN: 0 is
a rigid base) and friction xi_b in pN s/um, the links'
stiffness (pN/um^2) and damping (pN s/um^2); the dynein moment gain gamma and the
normal-force gain g = g' + i g'' are numbers; a
whole beat's static moment m0 in pN, motor saturation f_sat in pN/um and motor time tau_m
in ms."""


def render_table(doc: dict[str, Any]) -> str:
    """A comparison document (:meth:`axojax.inverse.Comparison.to_json`) as a text table: the rows (a
    status mark after the rank of each row that is not successful, explained below the
    table), the verdict, and the model and units (the last line)."""

    def num(x, fmt):
        width = "".join(c for c in fmt.split(".")[0] if c.isdigit()) or "0"
        return f"{'-':>{width}}" if x is None else format(x, fmt)

    f_obs = doc["data"].get("frequency_hz")
    wb = max([8] + [len(r["base"]) for r in doc["rows"]])  # "clamped+compliance": 18
    wm = max([18] + [len(r["mechanism"]) for r in doc["rows"]])  # "sliding+normal-force": 20
    head = (
        f"{'rank':>4}{'':4} {'mechanism':<{wm}} {'base':<{wb}} {'R^2':>7} {'f (Hz)':>8} {'df %':>7} "
        f"{'chi2/dof':>9} {'BIC':>10} {'dBIC':>9} {'weight':>6} {'n':>2}  at bound"
    )
    lines = [head]
    for i, r in enumerate(doc["rows"], 1):
        df = (
            None
            if r["frequency_hz"] is None or not f_obs
            else 100 * (r["frequency_hz"] - f_obs) / f_obs
        )
        w = r.get("weight")
        lines.append(
            f"{i:>4}{mark(r):<4} {r['mechanism']:<{wm}} {r['base']:<{wb}} {num(r['r2'], '7.3f')} "
            f"{num(r['frequency_hz'], '8.3f')} {num(df, '+7.2f')} {num(r['chi2_per_dof'], '9.3g')} "
            f"{num(r['bic'], '10.1f')} {num(r['delta_bic'], '9.1f')} {num(w, '6.2f')} "
            f"{len(r.get('free', ())):>2}  " + (", ".join(r["at_bound"]) or "-")
        )
    failed = [(i, r) for i, r in enumerate(doc["rows"], 1) if mark(r)]
    for symbol, meaning in (
        ("*", "not successful: ranked below every successful row, no weight"),
        ("n/a", "not applicable: this row cannot reach the observed beat"),
    ):
        these = [(i, r) for i, r in failed if mark(r) == symbol]
        if these:
            lines.append(f"{symbol} {meaning}:")
            lines += _reason_lines(these)
    v = doc.get("verdict") or verdict(doc)
    lines.append(f"verdict: {v['text']}")
    lines.append(f"  ({v['rule']})")
    if v.get("warning"):
        lines.append(f"warning: {v['warning']}")
    m = doc["model"]
    lines.append(
        f"model {m['preset']} ({m['elements']} elements), sperm number {m['sperm_number']:.4g}; "
        f"observed {num(f_obs, '.4g')} Hz; rows by BIC (lower is better), successful rows first; "
        f"R^2 is Sartori's of psi_1; weight: BIC weight among the successful rows; n: free "
        f"values (the complex amplitude's 2 more count in the BIC)"
    )
    if m.get("units_source"):
        lines.append(
            f"units: EI {m['ei_pn_um2']:.4g} pN um^2 and c_n {m['cn_pn_s_um2']:.3g} pN s/um^2 "
            f"per filament, L {m['length_um']:.4g} um ({m['units_source']})"
        )
    return "\n".join(lines)


PARAM_ORDER = tuple(key for key, _ in PHYSICAL.values())
PARAM_UNITS = {
    "chi_re_pn_per_um2": ("chi'", "pN/um^2"),
    "chi_im_pn_per_um2": ("chi''", "pN/um^2"),
    "beta_re_pn": ("beta'", "pN"),
    "beta_im_pn": ("beta''", "pN"),
    "p_pn_per_um": ("p", "pN/um"),
    "kb_pn_per_um": ("k_b", "pN/um"),
    "cb_um_per_pn": ("1/k_b", "um/pN"),
    "xib_pn_s_per_um": ("xi_b", "pN s/um"),
    "kl_pn_per_um2": ("k_l", "pN/um^2"),
    "ks_pn_per_um2": ("k_s", "pN/um^2"),
    "cl_pn_s_per_um2": ("c_l", "pN s/um^2"),
    "gamma": ("gamma", ""),
    "normal_re": ("g'", ""),
    "normal_im": ("g''", ""),
    "m0_pn": ("m0", "pN"),
    "f_sat_pn_per_um": ("f_sat", "pN/um"),
    "tau_m_ms": ("tau_m", "ms"),
}
"""How :func:`render_params` names each physical value, and its unit."""


def _pm(value: float | None, se: float | None) -> str:
    if value is None:
        return "-"
    if se is None:
        return f"{value:.3g} +- ?"
    return f"{value:.3g} +- {se:.2g}"


def physical_text(row: dict[str, Any]) -> str:
    """One row's fitted values in physical units with standard errors, on one line
    ("chi' -124 +- 5.2 pN/um^2; ..."; a value the row's pins alone fix, listed in its
    ``pinned``, as "chi' -34.4 pN/um^2 (pinned)": no error from the data; ``-`` when it
    has none)."""
    phys, se = row.get("physical") or {}, row.get("physical_stderr") or {}
    pinned = set(row.get("pinned") or ())
    parts = []
    for key in PARAM_ORDER:
        if key in phys:
            label, unit = PARAM_UNITS[key]
            unit = f" {unit}" if unit else ""
            if key in pinned and phys[key] is not None:
                parts.append(f"{label} {phys[key]:.3g}{unit} (pinned)")
            else:
                parts.append(f"{label} {_pm(phys[key], se.get(key))}{unit}")
    return "; ".join(parts) or "-"


def render_params(doc: dict[str, Any]) -> str:
    """Every row's fitted values in physical units with standard errors (the row's
    Laplace approximation with its pins held exactly; ``?`` where the data do not
    determine a value, ``(pinned)`` where the pins alone fix it), rows in the table's
    order (``axojax compare --params``)."""
    lines = ["fitted values (physical units) +- standard error, rows as ranked above:"]
    for i, r in enumerate(doc["rows"], 1):
        lines.append(f"{i:>4}{mark(r):<4} {r['mechanism']} on {r['base']}: " + physical_text(r))
    lines.append(
        "chi = chi' + i chi'' (sliding control), beta = beta' + i beta'' (curvature control), "
        "g = g' + i g'' (normal-force control, dimensionless), "
        "p the steady dynein load, 1/k_b and xi_b the basal compliance and friction, k_l and c_l the "
        "links' stiffness and damping (docs/mechanisms.md); ? = not determined by the data; "
        "pinned = fixed by the pins that hold the row's beat at the observed one (growth rate 0, "
        "the observed frequency), so without an error from the data"
    )
    return "\n".join(lines)


def _reason_lines(rows: list[tuple[int, dict]]) -> list[str]:
    """One line per row and reason; rows that share a reason (more than two) in one line:
    their ranks, mechanisms and bases, then the reason once."""
    groups: dict[str, list[tuple[int, dict]]] = {}
    for i, r in rows:
        groups.setdefault(str(r["reason"]), []).append((i, r))
    out = []
    for reason, these in groups.items():
        if len(these) <= 2:
            out += [f"  {i:>2} {r['mechanism']} on {r['base']}: {reason}" for i, r in these]
            continue
        idx = [i for i, _ in these]
        contiguous = idx == list(range(idx[0], idx[-1] + 1))
        ranks = f"{idx[0]}-{idx[-1]}" if contiguous else ", ".join(map(str, idx))
        mechs = ", ".join(dict.fromkeys(r["mechanism"] for _, r in these))
        bases = ", ".join(dict.fromkeys(r["base"] for _, r in these))
        out.append(f"  {ranks} ({mechs} on {bases}): {reason}")
    return out
