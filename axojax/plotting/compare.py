"""Figure of a comparison (``axojax compare --out REPORT.json``, :func:`axojax.compare`).

Top: the observed psi_1 amplitude |psi_1| and phase arg psi_1 along s (points) with every
row's fit (lines; legend: mechanism, base, R^2, delta BIC, BIC weight, and the table's
status mark: ``*`` not successful, dashed; ``n/a`` not applicable, dotted). The title
carries the verdict line (:func:`axojax.inverse.comparison.verdict.verdict`). Bottom: the waveform over one
cycle, observed first, then each row's, side by side (centrelines integrated from
psi(s, phase) = psi_0(s) + Re(psi_1(s) e^{i phase}); every fit uses the observed psi_0,
which a linear mode does not predict).
"""

from __future__ import annotations

import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from ..inverse.comparison.table import physical_text
from ..inverse.comparison.verdict import mark, verdict
from .fit_report import _centrelines

MAX_ROWS = 8
"""Rows drawn (the best by BIC); the rest are in the report."""


def _complex(pairs) -> np.ndarray:
    a = np.array([[np.nan, np.nan] if p is None else p for p in pairs], dtype=float)
    return a[:, 0] + 1j * a[:, 1]


def _phase(psi: np.ndarray) -> np.ndarray:
    """Unwrapped phase, shifted so that its mean is in (-pi, pi]."""
    ph = np.unwrap(np.angle(psi))
    return ph - 2 * np.pi * np.round(np.mean(ph) / (2 * np.pi))


def plot_comparison(doc: dict):
    """The figure of a comparison document (:meth:`axojax.inverse.Comparison.to_json`)."""
    data, rows = doc["data"], doc["rows"][:MAX_ROWS]
    s = np.asarray(data["s_um"], dtype=float)
    obs = _complex(data["psi1"])
    psi0 = np.zeros_like(s) if data.get("psi0") is None else np.asarray(data["psi0"], float)
    n = len(rows) + 1
    fig = plt.figure(figsize=(max(10, 2.2 * n), 7.0), layout="constrained")
    grid = fig.add_gridspec(2, n, height_ratios=[1.4, 1])
    amp = fig.add_subplot(grid[0, : n // 2 or 1])
    pha = fig.add_subplot(grid[0, n // 2 or 1 :])
    amp.plot(s, np.abs(obs), "ko", ms=3, label="observed")
    pha.plot(s, _phase(obs), "ko", ms=3)
    colours = plt.get_cmap("tab10")
    fits = []
    for i, r in enumerate(rows):
        fit = _complex(r["psi1_model"])
        fits.append(fit)
        r2 = "-" if r["r2"] is None else f"{r['r2']:.3f}"
        dbic = "-" if r["delta_bic"] is None else f"{r['delta_bic']:.0f}"
        status = r.get("status", "successful")
        weight = "" if r.get("weight") is None else f", w {r['weight']:.2f}"
        flag = mark(r)
        label = f"{flag + ' ' if flag else ''}{r['mechanism']} ({r['base']}): R^2 {r2}, dBIC {dbic}{weight}"
        if flag:
            label += f" [{status}]"
        style = "-" if not flag else (":" if status == "not_applicable" else "--")
        amp.plot(s, np.abs(fit), style, color=colours(i % 10), label=label)
        # the fitted phase follows the observed one's branch
        ph = _phase(fit)
        ph += 2 * np.pi * np.round(np.nanmean(_phase(obs) - ph) / (2 * np.pi))
        pha.plot(s, ph, style, color=colours(i % 10))
    amp.set(xlabel="s (um)", ylabel="|psi_1| (rad)", title="psi_1 amplitude")
    pha.set(xlabel="s (um)", ylabel="arg psi_1 (rad)", title="psi_1 phase")
    amp.legend(fontsize=7, loc="best")
    model = doc.get("model", {})
    v = doc.get("verdict") or verdict(doc)
    width = int(8 * fig.get_figwidth())  # characters of the title font across the figure
    lines = [f"verdict: {v['text']}"]
    if rows:
        lines.append(f"{rows[0]['mechanism']} on {rows[0]['base']}: {physical_text(rows[0])}")
    fig.suptitle(
        f"mechanisms on {data.get('file', 'the beat')}: {data.get('frequency_hz', float('nan')):.4g} Hz, "
        f"model {model.get('preset', '?')} ({model.get('elements', '?')} elements), rows by BIC\n"
        + "\n".join(textwrap.fill(line, width) for line in lines)
    )
    shapes = [("observed", obs, "k")] + [
        (f"{mark(r) + ' ' if mark(r) else ''}{r['mechanism']}\n{r['base']}", f, colours(i % 10))
        for i, (r, f) in enumerate(zip(rows, fits))
    ]
    first = None
    for j, (title, psi1, colour) in enumerate(shapes):
        ax = fig.add_subplot(grid[1, j], sharex=first, sharey=first)
        first = first or ax
        ok = np.isfinite(psi1)
        if ok.sum() >= 2:
            x, y = _centrelines(s[ok], psi0[ok], psi1[ok])
            for xi, yi in zip(x, y):
                ax.plot(xi, yi, color=colour, lw=0.8, alpha=0.7)
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(title, fontsize=8)
        ax.set_xlabel("x (um)", fontsize=7)
        if j == 0:
            ax.set_ylabel("y (um), one cycle", fontsize=7)
        ax.tick_params(labelsize=6)
    return fig
