"""Figure of a comparison (``axojax compare --out REPORT.json``, :func:`axojax.compare`),
sized for a slide (:mod:`axojax.plotting.style`).

Top: the observed psi_1 amplitude |psi_1| and phase arg psi_1 along s (black points)
with the best rows' fits (lines, Okabe-Ito colours; a row that is not successful dashed,
one not applicable dotted). The phase is drawn only where |psi_1| carries it (at least
5 % of its maximum: a clamped base has none). The legend under them names each row with
its R^2, delta BIC and BIC weight, and the table's status mark (``*`` not successful,
``n/a`` not applicable). Bottom: the waveform over one cycle, observed first, then the
best rows' (centrelines integrated from psi(s, phase) = psi_0(s) + Re(psi_1(s) e^{i phase});
a linear row uses the observed psi_0, which a linear mode does not predict; a whole-beat
row its orbit's, drawn with the observed in a third panel on top). The title names
the beat; the caption carries the verdict
(:func:`axojax.inverse.comparison.verdict.verdict`), the best row's fitted values and the
model.
"""

from __future__ import annotations

import numpy as np

from ..inverse.comparison.table import physical_text
from ..inverse.comparison.verdict import mark, verdict
from . import style
from .fit_report import _centrelines

MAX_ROWS = 6
"""Rows drawn (the best by BIC); the rest are in the report."""
SHAPES = 3
"""Rows whose waveform is drawn beside the observed one (the best by BIC)."""


def _complex(pairs) -> np.ndarray:
    a = np.array([[np.nan, np.nan] if p is None else p for p in pairs], dtype=float)
    return a[:, 0] + 1j * a[:, 1]


def _phase(psi: np.ndarray) -> np.ndarray:
    """Unwrapped phase where |psi| carries it (:func:`~axojax.plotting.style.masked_phase`),
    shifted so that its mean is in (-pi, pi]."""
    ph = style.masked_phase(psi)
    if not np.isfinite(ph).any():
        return ph
    return ph - 2 * np.pi * np.round(np.nanmean(ph) / (2 * np.pi))


def _label(r: dict) -> str:
    r2 = "-" if r["r2"] is None else f"{r['r2']:.3f}"
    dbic = "-" if r["delta_bic"] is None else f"{r['delta_bic']:.0f}"
    weight = "" if r.get("weight") is None else f", w {r['weight']:.2f}"
    flag = mark(r)
    label = (
        f"{flag + ' ' if flag else ''}{r['mechanism']} on {r['base']}: R² {r2}, ΔBIC {dbic}{weight}"
    )
    return label + (f" [{r.get('status', '')}]" if flag else "")


def _style(r: dict) -> str:
    flag = mark(r)
    return "-" if not flag else (":" if r.get("status") == "not_applicable" else "--")


def _psi0_of(r: dict, observed: np.ndarray) -> np.ndarray:
    """A row's psi_0: its orbit's (a whole-beat row, with its reference angle), else the
    observed one (a linear mode predicts none)."""
    return observed if r.get("psi0_model") is None else _arr(r["psi0_model"])


def _arr(values) -> np.ndarray:
    return np.array([np.nan if x is None else x for x in values], dtype=float)


def plot_comparison(doc: dict):
    """The figure of a comparison document (:meth:`axojax.inverse.Comparison.to_json`,
    or a whole-beat comparison's: then a third panel on top, observed and fitted psi_0,
    and each row's waveform with its own orbit's psi_0)."""
    data, rows = doc["data"], doc["rows"][:MAX_ROWS]
    s = np.asarray(data["s_um"], dtype=float)
    obs = _complex(data["psi1"])
    psi0 = np.zeros_like(s) if data.get("psi0") is None else np.asarray(data["psi0"], float)
    whole = doc.get("kind") == "whole_beat_comparison"
    fits = [
        np.full(s.shape, np.nan + 0j) if not r.get("psi1_model") else _complex(r["psi1_model"])
        for r in rows
    ]
    colours = [style.PALETTE[i % len(style.PALETTE)] for i in range(len(rows))]
    shapes = 1 + min(SHAPES, len(rows))
    with style.slide_style():
        fig = style.slide_figure()
        legend_lines = (len(rows) + 2) // 2
        grid = fig.add_gridspec(3, 12, height_ratios=[2.2, 0.28 * max(legend_lines, 1) + 0.1, 1.25])
        top = (
            (slice(0, 4), slice(4, 8), slice(8, 12)) if whole else (None, slice(0, 6), slice(6, 12))
        )
        amp = fig.add_subplot(grid[0, top[1]])
        pha = fig.add_subplot(grid[0, top[2]])
        obs_phase = _phase(obs)
        amp.plot(s, np.abs(obs), "o", color=style.BLACK, ms=4, label="observed")
        pha.plot(s, obs_phase, "o", color=style.BLACK, ms=4)
        for r, fit, colour in zip(rows, fits, colours):
            amp.plot(s, np.abs(fit), _style(r), color=colour, label=_label(r))
            # the fitted phase follows the observed one's branch
            pha.plot(s, style.follow(_phase(fit), obs_phase), _style(r), color=colour)
        if whole:
            stat = fig.add_subplot(grid[0, top[0]])
            stat.plot(s, psi0, "o", color=style.BLACK, ms=4)
            for r, colour in zip(rows, colours):
                if r.get("psi0_model") is not None:
                    stat.plot(s, _psi0_of(r, psi0), _style(r), color=colour)
            stat.set(xlabel="arc length s (µm)", ylabel=r"$\psi_0$ (rad)", title="static mode")
        amp.set(xlabel="arc length s (µm)", ylabel=r"$|\psi_1|$ (rad)", title="amplitude")
        pha.set(xlabel="arc length s (µm)", ylabel=r"arg $\psi_1$ (rad)", title="phase")
        key = fig.add_subplot(grid[1, :])
        key.set_axis_off()
        handles, labels = amp.get_legend_handles_labels()
        key.legend(
            handles, labels, loc="center", ncols=2, frameon=False, borderaxespad=0, handlelength=2.5
        )
        shown = [("observed", psi0, obs, style.BLACK)] + [
            (
                f"{mark(r) + ' ' if mark(r) else ''}{r['mechanism']}\non {r['base']}",
                _psi0_of(r, psi0),
                f,
                c,
            )
            for r, f, c in zip(rows[: shapes - 1], fits, colours)
        ]
        width = 12 // shapes
        first = None
        for j, (title, static, psi1, colour) in enumerate(shown):
            ax = fig.add_subplot(grid[2, j * width : (j + 1) * width], sharex=first, sharey=first)
            first = first or ax
            ok = np.isfinite(psi1) & np.isfinite(static)
            if ok.sum() >= 2:
                x, y = _centrelines(s[ok], static[ok], psi1[ok])
                for xi, yi in zip(x, y):
                    ax.plot(xi, yi, color=colour, lw=1.0, alpha=0.75)
            ax.set_aspect("equal", adjustable="box")
            ax.set_title(title, fontsize=10.5)
            ax.set_xlabel("x (µm)")
            if j == 0:
                ax.set_ylabel("y (µm)")
            else:
                ax.tick_params(labelleft=False)
        return style.finish(fig, _title(data, whole), _caption(doc, rows))


def _title(data: dict, whole: bool = False) -> str:
    name = str(data.get("file", "the beat")).rsplit("/", 1)[-1]
    what = "Whole beats" if whole else "Mechanisms"
    return style.short(f"{what} fitted to {name}", style.MAX_TITLE)


def _caption(doc: dict, rows: list) -> str:
    data, model = doc["data"], doc.get("model", {})
    v = doc.get("verdict") or verdict(doc)
    lines = [f"Verdict: {v['text']}."]
    if rows:
        angle = rows[0].get("psi_offset_rad")
        angle = "" if angle is None else f"; reference angle {angle:.3g} rad"
        lines.append(
            f"Best row, {rows[0]['mechanism']} on {rows[0]['base']}: "
            f"{physical_text(rows[0])}{angle}."
        )
    total = len(doc["rows"])
    drawn = f"the best {len(rows)} of {total} rows by BIC" if total > len(rows) else "rows by BIC"
    lines.append(
        f"Observed {data.get('frequency_hz', float('nan')):.4g} Hz; model {model.get('preset', '?')} "
        f"({model.get('elements', '?')} elements); {drawn}; waveforms over one cycle."
    )
    return "\n".join(lines)
