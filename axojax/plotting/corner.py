"""Corner plot of a posterior: a histogram of every parameter on the diagonal, the draws
of every pair below it, with the 5/50/95 % quantiles, optional truth markers and the
centre of the chains' starts (the posterior mode, or the least-squares optimum given).
Sized for a slide (:mod:`axojax.plotting.style`): the key to the right of the panels, the
medians, 90 % intervals and the sampler's diagnostics in the caption."""

from __future__ import annotations

import pathlib
from collections.abc import Mapping

import numpy as np
from matplotlib.lines import Line2D

from . import style

DRAWS = style.BLUE
TRUTH = style.VERMILLION
START = style.BLACK
DIVERGENT = style.PURPLE


def plot_corner(
    source,
    *,
    truth: Mapping[str, float] | None = None,
    optimum: Mapping[str, float] | None = None,
    names: tuple[str, ...] | None = None,
    max_points: int = 4000,
    bins: int = 40,
    out: str | pathlib.Path | None = None,
):
    """Corner plot of ``source``: a :class:`axojax.inverse.Posterior` or the path of the
    ``.npz`` its ``save`` wrote (``axojax plot FILE.npz``).

    Args:
        truth: {name: value} markers (vermillion); default: the ``truth`` stored in the .npz.
        optimum: {name: value} markers (black cross); default: the centre of the
            chains' starts (``Posterior.start``).
        names: the parameters to show (default: all free parameters).
        max_points: draws shown in each scatter panel (evenly thinned); divergent
            draws are drawn in purple.
        bins: histogram bins.
        out: optional figure path (.png, .pdf, .svg).

    Axes are in parameter values (dimensionless), logarithmic for parameters fitted in
    log coordinates. Returns the matplotlib Figure.
    """
    from ..inverse import Posterior, load_truth

    if isinstance(source, (str, pathlib.Path)):
        post = Posterior.load(source)
        if truth is None:
            truth = load_truth(source)
    else:
        post = source
    names = tuple(post.names if names is None else names)
    for n in names:
        if n not in post.names:
            raise ValueError(
                f"names: {n!r} is not a free parameter of this posterior ({', '.join(post.names)})"
            )
    optimum = post.start if optimum is None else optimum
    k = len(names)
    draws = {n: post.value_draws(n).reshape(-1) for n in names}
    divergent = post.divergent.reshape(-1)
    step = max(1, draws[names[0]].size // max_points)
    marks = {"truth": truth or {}, "optimum": optimum or {}}
    with style.slide_style():
        fig = style.slide_figure()
        axes = fig.subplots(k, k, squeeze=False)
        for i, ni in enumerate(names):
            for j, nj in enumerate(names):
                ax = axes[i, j]
                if j > i:
                    ax.set_visible(False)
                    continue
                if i == j:
                    _diagonal(ax, post, ni, draws[ni], bins, marks)
                else:
                    _pair(ax, post, nj, ni, draws, divergent, step, marks)
                if post.log_coordinate.get(nj, False):
                    ax.set_xscale("log")
                    style.readable_log_ticks(ax.xaxis)
                if i == k - 1:
                    ax.set_xlabel(nj)
                else:
                    ax.set_xticklabels([])
                if j == 0 and i > 0:
                    ax.set_ylabel(ni)
                elif j > 0 and i != j:
                    ax.set_yticklabels([])
        keys = _key(marks, bool(divergent.any()))
        if k > 1:  # in the empty corner above the diagonal
            fig.legend(
                handles=keys,
                loc="center",
                bbox_to_anchor=(0, 0, 1, 1),
                bbox_transform=axes[0, k - 1].transAxes,
                frameon=False,
            )
        else:
            fig.legend(handles=keys, loc="outside right upper", frameon=False)
        style.finish(fig, style.short(f"Posterior of {', '.join(names)}"), _caption(post, names))
    if out is not None:
        from .._io import save_figure

        save_figure(fig, out, dpi=130)  # written whole
    return fig


def _key(marks: dict, divergent: bool) -> list:
    """The legend's entries: what each mark and line of the panels is."""
    keys = [
        Line2D([], [], ls="", marker="o", color=DRAWS, alpha=0.6, label="posterior draws"),
        Line2D([], [], color=DRAWS, ls="--", label="median"),
        Line2D([], [], color=DRAWS, ls=":", label="5 % and 95 %"),
    ]
    if divergent:
        keys.append(Line2D([], [], ls="", marker="o", color=DIVERGENT, label="divergent draws"))
    if marks["truth"]:
        keys.append(Line2D([], [], color=TRUTH, marker="*", ms=10, label="truth"))
    if marks["optimum"]:
        keys.append(Line2D([], [], color=START, ls="-.", marker="x", ms=8, label="chains' start"))
    return keys


def _caption(post, names) -> str:
    """The medians and 90 % intervals, the chains and their diagnostics."""
    worst = max(post.rhat[n] for n in names)
    fewest = min(post.ess[n] for n in names)
    values = "; ".join(
        f"{n} {style.number(post.q50[n])} [{style.number(post.q05[n])}, "
        f"{style.number(post.q95[n])}]"
        for n in names
    )
    logs = [n for n in names if post.log_coordinate.get(n, False)]
    return (
        f"Median [5 %, 95 %]: {values}.\n"
        f"{post.chains} chains × {post.draws} draws; R-hat ≤ {worst:.3f}, ESS ≥ {fewest:.0f}, "
        f"{post.divergences} divergent."
        + (f" Logarithmic axes: {', '.join(logs)} (sampled in log coordinates)." if logs else "")
    )


def _diagonal(ax, post, name: str, x: np.ndarray, bins: int, marks: dict) -> None:
    """The histogram of one parameter's draws, its quantiles and markers."""
    log_x = post.log_coordinate.get(name, False)
    edges = (
        np.geomspace(x.min(), x.max(), bins + 1)
        if log_x and x.min() > 0 and x.max() > x.min()
        else bins
    )
    ax.hist(x, bins=edges, color=DRAWS, alpha=0.55)
    for q, ls in ((post.q05[name], ":"), (post.q50[name], "--"), (post.q95[name], ":")):
        ax.axvline(q, color=DRAWS, ls=ls, lw=1.5)
    if name in marks["truth"]:
        ax.axvline(marks["truth"][name], color=TRUTH, lw=2)
    if name in marks["optimum"]:
        ax.axvline(marks["optimum"][name], color=START, lw=1.5, ls="-.")
    ax.set_yticks([])
    ax.set_title(name)


def _pair(ax, post, nx: str, ny: str, draws: dict, divergent, step: int, marks: dict) -> None:
    """The draws of two parameters (every ``step``-th; divergent ones all, in purple)."""
    x, y = draws[nx], draws[ny]
    ok = ~divergent
    ax.scatter(x[ok][::step], y[ok][::step], s=3, alpha=0.3, color=DRAWS, rasterized=True)
    if divergent.any():
        ax.scatter(x[divergent], y[divergent], s=10, color=DIVERGENT, label="divergent")
    for key, marker, color, size in (("truth", "*", TRUTH, 14), ("optimum", "x", START, 10)):
        if ny in marks[key] and nx in marks[key]:
            ax.plot(marks[key][nx], marks[key][ny], marker, color=color, ms=size, mew=2)
    if post.log_coordinate.get(ny, False):
        ax.set_yscale("log")
        style.readable_log_ticks(ax.yaxis)
