"""Figures of sweeps: stability/frequency maps with the Hopf boundary, wavelength and
velocity maps (the paper's figures 6 and 8-11), and line plots of 1-D sweeps."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..sweeps.result import SweepResult  # noqa: E402

LOG_AXES = {"ks", "kl", "cl", "ktheta"}
LABELS = {
    "frequency_hz": "frequency (Hz)",
    "wavelength_um": "wavelength (um)",
    "velocity_um_per_s": "velocity (um/s)",
    "growth_rate_per_s": "growth rate (1/s)",
}


def _spaced(name: str, values: np.ndarray) -> bool | np.bool_:
    return name in LOG_AXES and np.all(values > 0) and values.max() / values.min() > 50


def plot_sweep(
    result: SweepResult, panels=("frequency_hz", "wavelength_um", "velocity_um_per_s")
) -> plt.Figure:
    """2-D sweeps: one map per metric over (axis 0 horizontal, axis 1 vertical), unstable
    region coloured, Hopf boundary (growth rate = 0) in red, divergence hatched grey.
    1-D sweeps: metric against the axis with the boundary marked. Higher-dimensional
    sweeps show the slice at index 0 of the extra axes."""
    names = list(result.coords)
    data = result.data
    if len(names) > 2:
        sl = (slice(None), slice(None)) + (0,) * (len(names) - 2)
        data = {k: v[sl] for k, v in data.items()}
        names = names[:2]
    growth = data["growth_rate_per_s"]
    cls = data["classification"]
    title = f"{result.meta['model']} model"
    if len(names) == 1:
        x = result.coords[names[0]]
        fig, axes = plt.subplots(
            len(panels) + 1,
            1,
            figsize=(6, 2.2 * (len(panels) + 1)),
            sharex=True,
            constrained_layout=True,
        )
        for a, key in zip(axes, ("growth_rate_per_s",) + tuple(panels)):
            a.plot(x, data[key], "-o", ms=3)
            a.set_ylabel(LABELS[key])
            if _spaced(names[0], x):
                a.set_xscale("log")
        axes[0].axhline(0, color="r", lw=1)
        axes[-1].set_xlabel(names[0])
        axes[0].set_title(title)
        return fig
    x, y = result.coords[names[0]], result.coords[names[1]]
    fig, axes = plt.subplots(
        1, len(panels), figsize=(5.2 * len(panels), 4.2), constrained_layout=True
    )
    axes = np.atleast_1d(axes)
    for a, key in zip(axes, panels):
        z = np.where(cls == 1, data[key], np.nan).T
        im = a.pcolormesh(x, y, z, shading="auto", cmap="viridis")
        fig.colorbar(im, ax=a, label=LABELS[key])
        div = np.where(cls.T == 2, 1.0, np.nan)
        if np.any(cls == 2):
            a.pcolormesh(x, y, div, shading="auto", cmap="Greys", vmin=0, vmax=2, alpha=0.5)
        if len(x) > 1 and len(y) > 1 and growth.min() < 0 < growth.max():
            a.contour(x, y, growth.T, levels=[0.0], colors="r", linewidths=2)
        if _spaced(names[0], x):
            a.set_xscale("log")
        if _spaced(names[1], y):
            a.set_yscale("log")
        a.set_xlabel(names[0])
        a.set_ylabel(names[1])
        a.set_title(f"{title}: {LABELS[key]}")
    return fig
