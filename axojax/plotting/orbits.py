"""Figures of limit cycles: the branch in p (amplitude and frequency, stability from the
Floquet multipliers) and the waveform of one orbit."""

from __future__ import annotations

import pathlib
import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .._io import save_figure  # noqa: E402
from ..orbits.cycle import LimitCycle  # noqa: E402
from ..units import Units  # noqa: E402
from . import style  # noqa: E402
from .beats import plot_waveform  # noqa: E402


def plot_branch(path_or_arrays, meta: dict | None = None) -> plt.Figure:
    """Tip amplitude and frequency of the limit cycle against p (filled: stable, open
    markers: unstable), from the Hopf point (star), and the largest non-trivial Floquet
    multiplier's modulus. Takes a saved branch path or its (arrays, meta). Sized for a
    slide (:mod:`axojax.plotting.style`): the model and the Hopf point in the caption."""
    if meta is None:
        from ..orbits.branch import Branch

        arrays, meta = Branch.load(path_or_arrays)
    else:
        arrays = path_or_arrays
    p, amp, freq, stable = (
        arrays["p"],
        arrays["tip_amplitude_um"],
        arrays["frequency_hz"],
        arrays["stable"],
    )
    rho = arrays["floquet_real"] + 1j * arrays["floquet_imag"]
    with style.slide_style():
        fig = style.slide_figure()
        axes = fig.subplots(1, 3)
        _draw_branch(axes, p, amp, freq, stable, rho, meta)
        ph = meta.get("p_hopf")
        hopf = (
            f"Hopf point (star) at p = {ph:.4g}, {meta.get('hopf_frequency_hz', float('nan')):.4g} Hz; "
            if ph is not None and np.isfinite(ph)
            else ""
        )
        caption = (
            f"{hopf}filled: stable limit cycle, open: unstable (a Floquet multiplier outside the "
            f"unit circle). Model {meta.get('model', '')}, {meta.get('n_elements', '?')} elements, "
            f"cubic stiffening {meta.get('cubic', '?')}."
        )
        return style.finish(fig, f"Limit cycles of the {meta.get('model', '')} model", caption)


def _draw_branch(axes, p, amp, freq, stable, rho, meta) -> None:
    ok = stable >= 0
    ph = meta.get("p_hopf")
    for ax, y, label in ((axes[0], amp, "tip amplitude (µm)"), (axes[1], freq, "frequency (Hz)")):
        ax.plot(p[ok], y[ok], "-", color="0.6", lw=1, zorder=1)
        ax.plot(p[stable == 1], y[stable == 1], "o", color=style.BLUE, ms=6, label="stable")
        ax.plot(
            p[stable == 0],
            y[stable == 0],
            "o",
            mfc="none",
            mew=1.5,
            color=style.VERMILLION,
            ms=6,
            label="unstable",
        )
        if np.any(stable == 2):
            ax.plot(
                p[stable == 2],
                y[stable == 2],
                "s",
                color="0.5",
                ms=5,
                label="stability not computed",
            )
        ax.set_xlabel("dynein force p")
        ax.set_ylabel(label)
    if ph is not None and np.isfinite(ph):
        axes[0].plot([ph], [0.0], "k*", ms=12, label="Hopf point")
        axes[1].plot([ph], [meta.get("hopf_frequency_hz", np.nan)], "k*", ms=12)
    axes[0].legend(frameon=False)
    axes[0].set_title("amplitude")
    axes[1].set_title("frequency")
    with warnings.catch_warnings(), np.errstate(invalid="ignore"):
        warnings.simplefilter(
            "ignore", RuntimeWarning
        )  # rows of points without an orbit are all NaN
        trivial = (
            np.nanargmin(np.where(np.isfinite(rho), np.abs(rho - 1), np.inf), axis=1)
            if rho.shape[1]
            else np.zeros(len(p), int)
        )
        mod = np.abs(rho)
        mod[np.arange(len(p)), trivial] = np.nan
        second = (
            np.nanmax(np.where(np.isfinite(mod), mod, np.nan), axis=1)
            if rho.shape[1] > 1
            else np.full(len(p), np.nan)
        )
    axes[2].axhline(1.0, color="0.6", lw=1)
    axes[2].plot(p[ok], second[ok], "o-", color=style.PURPLE, ms=5)
    axes[2].set_xlabel("dynein force p")
    axes[2].set_ylabel("largest other |multiplier|")
    axes[2].set_title("Floquet stability")
    axes[2].set_ylim(
        0, 1.1 * max(1.0, float(np.nanmax(second[ok])) if np.any(ok & np.isfinite(second)) else 1.0)
    )


def plot_orbit(cycle: LimitCycle, units: Units = Units(), n_frames: int = 16) -> plt.Figure:
    """The waveform of one orbit (centreline frames over a period) and its tip trace."""
    x = np.linspace(0.0, 1.0, 101)
    t, u = cycle.centreline_beat(x, n_frames)
    fig, axes = plt.subplots(1, 2, figsize=(8, 4), constrained_layout=True)
    plot_waveform(
        axes[0],
        x * units.length_um,
        np.asarray(u) * units.length_um,
        f"{float(cycle.frequency_hz(units)):.2f} Hz, tip amplitude {float(cycle.amplitude_um(units)):.2f} um",
    )
    tt, uu = cycle.centreline_beat(np.array([1.0]), 200)
    axes[1].plot(np.asarray(tt) * units.tau_s * 1e3, np.asarray(uu)[:, 0] * units.length_um)
    axes[1].set_xlabel("time (ms)")
    axes[1].set_ylabel("tip displacement along the beat (um)")
    return fig


def save(fig: plt.Figure, path: str | pathlib.Path) -> None:
    """Write ``fig`` to ``path`` (written whole, :mod:`axojax._io`) and close it."""
    save_figure(fig, path, dpi=130)
    plt.close(fig)
