"""Figures and animations of beat waveforms: simulated beats (kymograph, tip trace,
waveform; the paper's figure 12) and eigenmodes (3D shape and projections)."""

from __future__ import annotations

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import animation  # noqa: E402

from .._io import atomic_path  # noqa: E402
from ..dynamics.simulate import Simulation  # noqa: E402
from . import style  # noqa: E402


def _last_cycles(sim: Simulation, n: int = 1) -> np.ndarray:
    """Indices of the last ``n`` periods (limit cycle) or the last 20% of the record."""
    t = sim.t_s
    span = n * sim.limit_cycle["period_s"] if sim.limit_cycle else 0.2 * (t[-1] - t[0])
    return np.nonzero(t >= t[-1] - span)[0]


def plot_waveform(ax: plt.Axes, x_um: np.ndarray, frames_um: np.ndarray, title: str = "") -> None:
    """Centreline shapes (frames (N, S), um) over one cycle, coloured by phase."""
    colors = plt.get_cmap(style.MAP_CMAP)(np.linspace(0, 1, len(frames_um)))
    for f, c in zip(frames_um, colors):
        ax.plot(f, x_um, color=c, lw=1.4)
    ax.set_xlabel("displacement in beat plane (um)")
    ax.set_ylabel("arc length x (um)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title)


def plot_simulation(sim: Simulation | str | pathlib.Path) -> plt.Figure:
    """Tip displacement against time, kymograph of the tangent angle psi(s, t), waveform
    of the last cycle, and the tip trace in the cross-section plane; sized for a slide
    (:mod:`axojax.plotting.style`: the state, frequency and amplitude in the caption)."""
    if not isinstance(sim, Simulation):
        sim = Simulation.load(sim)
    with style.slide_style():
        fig = style.slide_figure()
        axes = fig.subplots(2, 2)
        a = axes[0, 0]
        a.plot(sim.t_s, sim.tip_beat_um, lw=1.2, color=style.BLUE)
        a.set_xlabel("time (s)")
        a.set_ylabel("tip (µm)")
        a.set_title("tip displacement, beat direction")

        idx = _last_cycles(sim, 3)
        a = axes[0, 1]
        lim = np.nanmax(np.abs(sim.psi_rad[idx])) or 1.0
        im = a.pcolormesh(
            sim.t_s[idx],
            sim.x_um,
            sim.psi_rad[idx].T,
            shading="auto",
            cmap=style.SIGNED_CMAP,
            vmin=-lim,
            vmax=lim,
        )
        fig.colorbar(im, ax=a, label=r"$\psi$ (rad)")
        a.set_xlabel("time (s)")
        a.set_ylabel("arc length (µm)")
        a.set_title(r"kymograph of $\psi$, last cycles")

        last = _last_cycles(sim, 1)
        pick = last[np.linspace(0, len(last) - 1, min(12, len(last))).astype(int)]
        plot_waveform(axes[1, 0], sim.x_um, sim.centreline_beat_um[pick], "waveform, last cycle")
        axes[1, 0].set_xlabel("displacement (µm)")
        axes[1, 0].set_ylabel("arc length (µm)")

        a = axes[1, 1]
        if sim.tip_um.shape[1] == 2:
            a.plot(sim.tip_um[:, 0], sim.tip_um[:, 1], lw=0.8, color="0.65", label="whole record")
            a.plot(
                sim.tip_um[last, 0],
                sim.tip_um[last, 1],
                lw=2,
                color=style.VERMILLION,
                label="last cycle",
            )
            a.set_xlabel("tip y (µm)")
            a.set_ylabel("tip z (µm)")
            a.set_aspect("equal", adjustable="datalim")
            a.set_title("tip trace, cross-section plane")
            a.legend(loc="best")
        else:
            a.plot(sim.t_s[idx], sim.tip_beat_um[idx], color=style.BLUE)
            a.set_xlabel("time (s)")
            a.set_ylabel("tip (µm)")
            a.set_title("tip, last cycles")
        state = sim.state.replace("_", " ")
        if sim.limit_cycle:
            state += (
                f" at {sim.limit_cycle['frequency_hz']:.2f} Hz, tip amplitude "
                f"{sim.limit_cycle['tip_amplitude_um']:.2f} µm"
            )
        caption = (
            f"State: {state}. Model {sim.meta['model']}, p = {sim.meta['params']['p']:.4g}, "
            f"cubic stiffening {sim.meta['cubic']:g}; {sim.t_s[-1] - sim.t_s[0]:.3g} s simulated."
        )
        title = f"Simulated beat: {sim.meta['model']} model, p = {sim.meta['params']['p']:.4g}"
        return style.finish(fig, title, caption)


def plot_mode(x_um: np.ndarray, frames_um: np.ndarray, title: str = "") -> plt.Figure:
    """An eigenmode's beat cycle (frames (N, d, S), um, e.g. from
    :func:`axojax.waveform.mode_frames` times L): 3D shape and its projections."""
    d = frames_um.shape[1]
    if d == 1:
        fig, a = plt.subplots(figsize=(4, 5), constrained_layout=True)
        plot_waveform(a, x_um, frames_um[:, 0], title)
        return fig
    fig = plt.figure(figsize=(13, 4.2), constrained_layout=True)
    colors = plt.cm.viridis(np.linspace(0, 1, len(frames_um)))
    a3 = fig.add_subplot(1, 4, 1, projection="3d")
    for f, c in zip(frames_um, colors):
        a3.plot(f[0], f[1], x_um, color=c, lw=1)
    a3.set_xlabel("y (um)")
    a3.set_ylabel("z (um)")
    a3.set_zlabel("x (um)")
    a3.set_title(title)
    for k, (i, j, li, lj) in enumerate(
        ((0, None, "y", "x"), (1, None, "z", "x"), (0, 1, "y", "z"))
    ):
        a = fig.add_subplot(1, 4, k + 2)
        for f, c in zip(frames_um, colors):
            a.plot(f[i], x_um if j is None else f[j], color=c, lw=1)
        a.set_xlabel(f"{li} (um)")
        a.set_ylabel(f"{lj} (um)")
        a.set_aspect("equal", adjustable="datalim")
        a.set_title(f"{lj}-{li} projection")
    return fig


def animate_frames(
    x_um: np.ndarray,
    frames_um: np.ndarray,
    path: str | pathlib.Path,
    title: str = "",
    fps: int = 20,
) -> pathlib.Path:
    """Animated GIF of centreline frames (N, S) in the beat plane (Pillow writer)."""
    fig, a = plt.subplots(figsize=(3.6, 4.8), constrained_layout=True)
    lim = max(np.abs(frames_um).max(), 1e-12) * 1.1
    a.set_xlim(-lim, lim)
    a.set_ylim(0, x_um[-1] * 1.02)
    a.set_aspect("equal")
    a.set_xlabel("displacement (um)")
    a.set_ylabel("x (um)")
    a.set_title(title, fontsize=9)
    (line,) = a.plot(frames_um[0], x_um, lw=2)

    def update(k):
        line.set_xdata(frames_um[k])
        return (line,)

    anim = animation.FuncAnimation(fig, update, frames=len(frames_um), blit=True)
    path = pathlib.Path(path)
    with atomic_path(path) as tmp:  # written whole
        anim.save(tmp, writer=animation.PillowWriter(fps=fps))
    plt.close(fig)
    return path


def animate_simulation(
    sim: Simulation, path: str | pathlib.Path, cycles: int = 2, frames_per_cycle: int = 24
) -> pathlib.Path:
    """Animated GIF of the last ``cycles`` beat cycles (the last 20% of the record when
    there is no limit cycle)."""
    idx = _last_cycles(sim, cycles)
    n = cycles * frames_per_cycle if sim.limit_cycle else 48
    pick = idx[np.linspace(0, len(idx) - 1, min(n, len(idx))).astype(int)]
    return animate_frames(
        sim.x_um,
        sim.centreline_beat_um[pick],
        path,
        title=f"{sim.meta['model']}: {sim.state.replace('_', ' ')}",
    )
