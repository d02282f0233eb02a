"""Corner plot of a posterior: a histogram of every parameter on the diagonal, the draws
of every pair below it, with the 5/50/95 % quantiles, optional truth markers and the
centre of the chains' starts (the posterior mode, or the least-squares optimum given)."""

from __future__ import annotations

import pathlib
from collections.abc import Mapping

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

TRUTH = "tab:red"
START = "black"
DIVERGENT = "tab:orange"


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
        truth: {name: value} markers (red); default: the ``truth`` stored in the .npz.
        optimum: {name: value} markers (black cross); default: the centre of the
            chains' starts (``Posterior.start``).
        names: the parameters to show (default: all free parameters).
        max_points: draws shown in each scatter panel (evenly thinned); divergent
            draws are drawn in orange.
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
    size = 1.9 * k + 0.8
    fig, axes = plt.subplots(k, k, figsize=(size, size), squeeze=False)
    marks = {"truth": truth or {}, "optimum": optimum or {}}
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
                _readable_log_ticks(ax.xaxis)
            if i == k - 1:
                ax.set_xlabel(nj)
            else:
                ax.set_xticklabels([])
            if j == 0 and i > 0:
                ax.set_ylabel(ni)
            elif j > 0 and i != j:
                ax.set_yticklabels([])
    worst = max(post.rhat[n] for n in names)
    fewest = min(post.ess[n] for n in names)
    fig.suptitle(
        f"posterior: {post.chains} chains x {post.draws} draws, R-hat <= {worst:.3f}, ESS >= "
        f"{fewest:.0f}, {post.divergences} divergent",
        fontsize=9,
    )
    fig.tight_layout()
    if out is not None:
        from .._io import save_figure

        save_figure(fig, out, dpi=130)  # written whole
    return fig


def _diagonal(ax, post, name: str, x: np.ndarray, bins: int, marks: dict) -> None:
    """The histogram of one parameter's draws, its quantiles and markers."""
    log_x = post.log_coordinate.get(name, False)
    edges = (
        np.geomspace(x.min(), x.max(), bins + 1)
        if log_x and x.min() > 0 and x.max() > x.min()
        else bins
    )
    ax.hist(x, bins=edges, color="tab:blue", alpha=0.7)
    for q, style in ((post.q05[name], ":"), (post.q50[name], "--"), (post.q95[name], ":")):
        ax.axvline(q, color="tab:blue", ls=style, lw=1)
    if name in marks["truth"]:
        ax.axvline(marks["truth"][name], color=TRUTH, lw=1.5)
    if name in marks["optimum"]:
        ax.axvline(marks["optimum"][name], color=START, lw=1, ls="-.")
    ax.set_yticks([])
    ax.set_title(
        f"{name} = {post.q50[name]:.3g} [{post.q05[name]:.3g}, {post.q95[name]:.3g}]", fontsize=8
    )


def _pair(ax, post, nx: str, ny: str, draws: dict, divergent, step: int, marks: dict) -> None:
    """The draws of two parameters (every ``step``-th; divergent ones all, in orange)."""
    x, y = draws[nx], draws[ny]
    ok = ~divergent
    ax.scatter(x[ok][::step], y[ok][::step], s=2, alpha=0.3, color="tab:blue", rasterized=True)
    if divergent.any():
        ax.scatter(x[divergent], y[divergent], s=6, color=DIVERGENT, label="divergent")
    for key, style, color, size in (("truth", "*", TRUTH, 10), ("optimum", "x", START, 8)):
        if ny in marks[key] and nx in marks[key]:
            ax.plot(marks[key][nx], marks[key][ny], style, color=color, ms=size)
    if post.log_coordinate.get(ny, False):
        ax.set_yscale("log")
        _readable_log_ticks(ax.yaxis)


def _readable_log_ticks(axis) -> None:
    """A log axis over less than a decade gets three plain tick labels (matplotlib would
    label its minor ticks in scientific notation, on top of each other)."""
    from matplotlib.ticker import FormatStrFormatter, MaxNLocator, NullFormatter

    low, high = axis.get_view_interval()
    if low > 0 and high / low < 10:
        axis.set_major_locator(MaxNLocator(3))
        axis.set_major_formatter(FormatStrFormatter("%.3g"))
        axis.set_minor_formatter(NullFormatter())
