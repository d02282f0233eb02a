"""Figure of a fit report (``FitResult.save`` / ``axojax fit --out fit.json``), sized for
a slide (:mod:`axojax.plotting.style`): a one-line title (the mechanism and whether the
targets are reproduced), the fitted values with their standard errors, the loss and
chi2/dof in the caption.

With a shape target (the first condition that has one): observed vs fitted psi_1
amplitude and phase along s (the excluded basal stretch shaded; the phase only where
|psi_1| is at least 5 % of its maximum, none at a clamped base), the observed psi_0, the
normalised residuals, and the waveform over one cycle, observed beside fitted
(centrelines integrated from psi(s, phase) = psi_0(s) + Re(psi_1(s) e^{i phase}); the
fitted one uses the observed psi_0, which the linear mode does not predict). Without
one: every scalar target against what the fit achieved, in units of its sigma, per
condition.
"""

from __future__ import annotations

import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from . import style

PHASES = 12


def _centrelines(
    s: np.ndarray, psi0: np.ndarray, psi1: np.ndarray, n: int = PHASES
) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) (n, S) of the waveform at n phases over one cycle (trapezoidal integration)."""
    x, y = [], []
    for ph in np.linspace(0, 2 * np.pi, n, endpoint=False):
        psi = psi0 + np.real(psi1 * np.exp(1j * ph))
        ds = np.diff(s)
        x.append(np.concatenate([[0.0], np.cumsum(ds * (np.cos(psi[1:]) + np.cos(psi[:-1])) / 2)]))
        y.append(np.concatenate([[0.0], np.cumsum(ds * (np.sin(psi[1:]) + np.sin(psi[:-1])) / 2)]))
    return np.array(x), np.array(y)


def _arr(v) -> np.ndarray:
    return np.array([np.nan if x is None else x for x in v], dtype=float)


def _title(report: dict) -> str:
    """The mechanism (and base) fitted and whether the targets are met."""
    met = report.get("targets_met", report["converged"])  # reports before targets_met
    what = report.get("mechanism") or "model"
    what = what[0].upper() + what[1:]
    if report.get("base"):
        what += f" ({report['base']})"
    return f"{what} fit: targets {'met' if met else 'missed'}"


def _caption(report: dict, extra: str = "") -> str:
    """The fitted values with their errors; method, loss, chi2/dof, values at a bound."""
    numbers = f"Least squares ({report.get('method', '?')}): loss {report['loss']:.4g}" + (
        f", chi2/dof {report['chi2_per_dof']:.3g}" if report.get("chi2_per_dof") is not None else ""
    )
    if report.get("at_bound"):
        numbers += f"; at a bound: {', '.join(report['at_bound'])}"
    lines = [
        "Fitted: " + _values_line(report) + ".",
        numbers + (f"; {extra}" if extra else "") + ".",
    ]
    return "\n".join(lines)


def _psi0_panel(ax, s: np.ndarray, psi0, psi0_fit) -> None:
    """Observed (and, for a limit cycle, fitted) psi_0(s); a note when none is observed."""
    if psi0 is None:
        ax.text(0.5, 0.5, "no psi_0 observed", ha="center", va="center", transform=ax.transAxes)
        ax.set_axis_off()
        return
    ax.plot(s, psi0, "o", ms=4, color=style.BLACK, label="observed")
    if psi0_fit is not None:
        ax.plot(s, psi0_fit, "-", color=style.BLUE, label="fitted (limit cycle)")
        ax.legend()
    ax.set(xlabel="s (µm)", ylabel=r"$\psi_0$ (rad)", title="static mode")


def _waveform(ax, s: np.ndarray, psi0: np.ndarray, psi1: np.ndarray, name: str) -> None:
    """Centrelines of psi_0 + Re(psi_1 e^{i phase}) over one cycle."""
    x, y = _centrelines(s, psi0, psi1)
    colors = plt.get_cmap(style.MAP_CMAP)(np.linspace(0, 1, len(x)))
    for xi, yi, col in zip(x, y, colors):
        ax.plot(xi, yi, color=col, lw=1.4)
    ax.set(xlabel="x (µm)", ylabel="y (µm)", title=f"{name} waveform")
    ax.set_aspect("equal", adjustable="box")


def plot_fit_report(report: dict | str | pathlib.Path) -> plt.Figure:
    """The figure of a fit report (a ``to_json()`` dict or its saved file)."""
    if not isinstance(report, dict):
        report = json.loads(pathlib.Path(report).read_text())
    shaped = [c for c in report.get("conditions", []) if c.get("shape")]
    with style.slide_style():
        if not shaped:
            return _scalar_figure(report)
        return _shape_figure(report, shaped[0])


def _shape_figure(report: dict, c: dict) -> plt.Figure:
    sh = c["shape"]
    s = _arr(sh["s_um"])
    obs = _arr(sh["psi1_obs_re"]) + 1j * _arr(sh["psi1_obs_im"])
    fit = _arr(sh["psi1_fit_re"]) + 1j * _arr(sh["psi1_fit_im"])
    sigma = _arr(sh["sigma_rad"])  # the measurement's
    floor = float(sh.get("floor_rad") or 0.0)  # the model-discrepancy floor of the fit
    kept = np.array(sh["kept"], dtype=bool)
    psi0 = None if sh.get("psi0_rad") is None else _arr(sh["psi0_rad"])
    # A 3D beat's components (one target, one complex scale) are drawn one curve each;
    # the waveforms are the in-plane component's.
    names = np.array(sh.get("component") or ["in_plane"] * s.size)
    groups = [(n, names == n) for n in dict.fromkeys(names)]
    colours = dict(zip(dict.fromkeys(names), (style.BLUE, style.VERMILLION, style.GREEN)))

    def tag(label: str, name: str) -> str:
        return label if len(groups) == 1 else f"{label} ({name.replace('_', ' ')})"

    fig = style.slide_figure()
    axes = fig.subplots(2, 3)
    (a_amp, a_phase, a_psi0), (a_res, a_obs, a_fit) = axes

    def shade(ax):
        if not kept.all():
            ax.axvspan(s.min(), s[~kept].max(), color="0.88", label="excluded base")

    shade(a_amp)
    for name, m in groups:
        colour = colours[name]
        a_amp.errorbar(
            s[m],
            np.abs(obs[m]),
            yerr=sigma[m],
            fmt="o",
            ms=4,
            color=colour,
            alpha=0.8,
            label=tag("observed", name),
        )
        a_amp.plot(s[m], np.abs(fit[m]), "-", color=style.BLACK, label=tag("fitted", name))
        if floor > 0:  # the floor is not measurement error: a band about the fit, not a bar
            a_amp.fill_between(
                s[m],
                np.abs(fit[m]) - floor,
                np.abs(fit[m]) + floor,
                color=colour,
                alpha=0.15,
                label=tag(f"fitted ± floor {floor:g} rad", name),
            )
    a_amp.set(xlabel="s (µm)", ylabel=r"$|\psi_1|$ (rad)", title="amplitude")
    a_amp.legend(fontsize=9.5, framealpha=0.85)
    shade(a_phase)
    for name, m in groups:
        colour = colours[name]
        # drawn where |psi_1| carries a phase: none at a clamped base, where psi_1 = 0
        obs_phase = style.masked_phase(obs[m])
        a_phase.plot(s[m], obs_phase, "o", ms=4, color=colour, label=tag("observed", name))
        a_phase.plot(
            s[m],
            style.follow(style.masked_phase(fit[m]), obs_phase),
            "-",
            color=style.BLACK,
            label=tag("fitted", name),
        )
    a_phase.set(xlabel="s (µm)", ylabel=r"arg $\psi_1$ (rad)", title="phase")
    if len(groups) > 1:  # one component: the amplitude's legend keys it
        a_phase.legend()
    psi0_fit = None if sh.get("psi0_fit_rad") is None else _arr(sh["psi0_fit_rad"])
    _psi0_panel(a_psi0, s, psi0, psi0_fit)
    shade(a_res)
    d = (obs - fit) / np.sqrt(sigma**2 + floor**2)  # as the fit normalised them
    for name, m in groups:
        a_res.plot(s[m], d[m].real, "o-", ms=4, color=style.BLUE, label=tag("Re", name))
        a_res.plot(s[m], d[m].imag, "s--", ms=4, color=style.VERMILLION, label=tag("Im", name))
    a_res.axhline(0, color="k", lw=0.6)
    a_res.set(xlabel="s (µm)", ylabel="(obs. − fit) / σ", title="normalised residuals")
    a_res.legend()
    base = np.zeros_like(s) if psi0 is None else psi0
    own = groups[0][1]  # the first component's points (in-plane for a joined 3D target)
    fit_base = base if psi0_fit is None else psi0_fit
    a_fit.sharex(a_obs)
    a_fit.sharey(a_obs)  # the two waveforms on one scale
    _waveform(a_obs, s[own], base[own], obs[own], tag("observed", groups[0][0]))
    _waveform(a_fit, s[own], fit_base[own], fit[own], tag("fitted", groups[0][0]))
    extra = (
        f"shape rms {c['shape_rms']:.2f} σ (σ: the data's sigma and the floor in quadrature)"
        if c.get("shape_rms") is not None
        else ""
    )
    return style.finish(fig, _title(report), _caption(report, extra))


def _values_line(report: dict) -> str:
    parts = []
    for k, v in report.get("fitted", report.get("params", {})).items():
        se = report.get("stderr", {}).get(k)
        flag = (
            " (bound)"
            if k in report.get("at_bound", [])
            else ("" if report.get("identifiable", {}).get(k) else " (n.i.)")
        )
        parts.append(f"{k} = {style.number(v)}" + (f" ± {se:.2g}" if se is not None else "") + flag)
    return ", ".join(parts)


def _scalar_figure(report: dict) -> plt.Figure:
    def name(c):
        fixed = ", ".join(f"{k}={v:g}" for k, v in (c.get("fixed") or {}).items())
        return f"{c['label']} ({fixed})" if fixed else str(c["label"])

    rows = [(name(c), t) for c in report.get("conditions", []) for t in c["targets"]]
    names = sorted({t["name"] for _, t in rows})
    # one value panel per target name: each unit (Hz, um, ...) on its own axis
    fig = style.slide_figure()
    axes = fig.subplots(1, len(names) + 1, squeeze=False, width_ratios=[1] * len(names) + [1.4])
    *value_axes, a_res = axes[0]
    for a_val, name in zip(value_axes, names):
        sel = [(lab, t) for lab, t in rows if t["name"] == name]
        x = np.arange(len(sel))
        a_val.errorbar(
            x,
            [t["value"] for _, t in sel],
            yerr=[t["sigma"] for _, t in sel],
            fmt="o",
            color=style.BLACK,
            label="observed",
        )
        achieved = [np.nan if t["achieved"] is None else t["achieved"] for _, t in sel]
        a_val.plot(x, achieved, "x", ms=10, mew=2, color=style.VERMILLION, label="fitted")
        a_val.set_xticks(x, [lab for lab, _ in sel], rotation=30 if len(sel) > 3 else 0)
        a_val.set(xlabel="condition", ylabel=name, title=name.replace("_", " "))
        if all(t["value"] > 0 for _, t in sel):
            a_val.set_yscale("log")
            style.readable_log_ticks(a_val.yaxis)
        a_val.legend()
    labels = [f"{lab}: {t['name']}" for lab, t in rows]
    a_res.barh(np.arange(len(rows)), [t["residual"] for _, t in rows], color=style.BLUE)
    a_res.set_yticks(np.arange(len(rows)), labels)
    for v in (-1, 1):
        a_res.axvline(v, color="k", ls=":", lw=0.8)
    # a title or x label wider than its panel runs off the figure: constrained layout
    # makes room for neither's width
    a_res.set(xlabel="(fit − obs.) / σ", title="residuals")
    return style.finish(fig, _title(report), _caption(report))
