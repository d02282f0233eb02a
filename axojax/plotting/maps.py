"""Figures of sweeps: stability/frequency maps with the Hopf boundary, wavelength and
velocity maps (the paper's figures 6 and 8-11), and line plots of 1-D sweeps, sized for a
slide (:mod:`axojax.plotting.style`: viridis maps, the Hopf boundary black, the key and the
model in the caption)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..sweeps.result import SweepResult
from . import style

LOG_AXES = {"ks", "kl", "cl", "ktheta"}
LABELS = {
    "frequency_hz": "frequency (Hz)",
    "wavelength_um": "wavelength (µm)",
    "velocity_um_per_s": "velocity (µm/s)",
    "growth_rate_per_s": "growth rate (1/s)",
}
HOPF = style.BLACK
"""The Hopf boundary's colour (growth rate 0), on the viridis maps."""
DIVERGENCE = "0.55"


def _spaced(name: str, values: np.ndarray) -> bool | np.bool_:
    return name in LOG_AXES and np.all(values > 0) and values.max() / values.min() > 50


def _fixed(result: SweepResult, names: list[str]) -> str:
    """The model and the values the sweep held fixed (its own axes and zeros left out)."""
    meta = result.meta
    model = f"Model {meta.get('model', '?')}"
    if meta.get("n_elements"):
        model += f" ({meta['n_elements']} elements)"
    held = {k: v for k, v in (meta.get("fixed") or {}).items() if k not in names}
    if meta.get("kl_ratio") is not None and "kl" not in names:
        held["kl/ks"] = meta["kl_ratio"]
    parts = [f"{k} {style.number(v)}" for k, v in held.items() if isinstance(v, (int, float)) and v]
    return model + ("; held: " + ", ".join(parts) if parts else "")


def plot_sweep(
    result: SweepResult, panels=("frequency_hz", "wavelength_um", "velocity_um_per_s")
) -> plt.Figure:
    """2-D sweeps: one map per metric over (axis 0 horizontal, axis 1 vertical), unstable
    region coloured (viridis), Hopf boundary (growth rate = 0) black, divergence grey.
    1-D sweeps: metric against the axis with the boundary marked. Higher-dimensional
    sweeps show the slice at index 0 of the extra axes."""
    names = list(result.coords)
    data = result.data
    extra = ""
    if len(names) > 2:
        sl = (slice(None), slice(None)) + (0,) * (len(names) - 2)
        data = {k: v[sl] for k, v in data.items()}
        extra = (
            " Slice at " + ", ".join(f"{n} = {result.coords[n][0]:.4g}" for n in names[2:]) + "."
        )
        names = names[:2]
    growth = data["growth_rate_per_s"]
    cls = data["classification"]
    title = style.short(f"Stability map of the {result.meta.get('model', '')} model")
    with style.slide_style():
        fig = style.slide_figure()
        if len(names) == 1:
            return _line_figure(fig, result, data, names[0], panels, title, extra)
        x, y = result.coords[names[0]], result.coords[names[1]]
        axes = np.atleast_1d(fig.subplots(1, len(panels)))
        for a, key in zip(axes, panels):
            z = np.where(cls == 1, data[key], np.nan).T
            im = a.pcolormesh(x, y, z, shading="auto", cmap=style.MAP_CMAP)
            fig.colorbar(im, ax=a, location="bottom", label=LABELS[key], shrink=0.9)
            div = np.where(cls.T == 2, 1.0, np.nan)
            if np.any(cls == 2):
                a.pcolormesh(x, y, div, shading="auto", cmap="Greys", vmin=0, vmax=2, alpha=0.6)
            if len(x) > 1 and len(y) > 1 and growth.min() < 0 < growth.max():
                a.contour(x, y, growth.T, levels=[0.0], colors=HOPF, linewidths=2.5)
            if _spaced(names[0], x):
                a.set_xscale("log")
            if _spaced(names[1], y):
                a.set_yscale("log")
            a.set_xlabel(names[0])
            a.set_ylabel(names[1])
            a.set_title(LABELS[key].split(" (")[0])
        caption = (
            "Coloured: the unstable (beating) region, the dominant mode's value; black line: "
            "the Hopf boundary (growth rate 0); grey: divergence (a static buckling mode); "
            f"white: stable. {_fixed(result, names)}.{extra}"
        )
        return style.finish(fig, title, caption)


def _line_figure(fig, result, data, name, panels, title, extra) -> plt.Figure:
    x = result.coords[name]
    keys = ("growth_rate_per_s",) + tuple(panels)
    cols = 2 if len(keys) > 2 else 1
    rows = -(-len(keys) // cols)
    axes = np.atleast_1d(fig.subplots(rows, cols, sharex=True, squeeze=False)).ravel()
    for i, (a, key) in enumerate(zip(axes, keys)):
        a.plot(x, data[key], "-o", ms=4, color=style.PALETTE[i % len(style.PALETTE)])
        a.set_ylabel(LABELS[key])
        if _spaced(name, x):
            a.set_xscale("log")
    for a in axes[len(keys) :]:
        a.set_visible(False)
    for a in axes[-cols:]:
        a.set_xlabel(name)
    axes[0].axhline(0, color=HOPF, lw=1.5, ls="--")
    caption = (
        "Growth rate above 0 (dashed line): the dominant mode grows and the flagellum beats. "
        f"{_fixed(result, [name])}.{extra}"
    )
    return style.finish(fig, title, caption)
