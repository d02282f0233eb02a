"""The look every ``axojax plot`` figure shares: sized for a slide, readable there, safe for
colour-blind readers, with one short title and the numbers in a caption.

* :data:`SLIDE_SIZE` (10 x 6.25 in, 16:10) is every figure's size; fonts are set in points
  for it (:data:`SLIDE_RC`) and none is smaller than :data:`MIN_FONT_PT`.
* :func:`slide_style` applies :data:`SLIDE_RC` while a figure is drawn (never globally:
  importing axojax changes no rcParams); :func:`finish` sets the title, the caption and
  the smallest fonts of the figure it made.
* Lines cycle through the Okabe-Ito palette (:data:`OKABE_ITO`: Okabe & Ito 2008, "Color
  Universal Design", distinguishable under the common colour-vision deficiencies); maps
  use viridis, signed maps (a kymograph of psi) ColorBrewer's RdBu, both colour-blind safe.
* :func:`masked_phase`: arg psi_1 only where |psi_1| carries it (at least
  :data:`PHASE_FLOOR` of its maximum): a clamped base, where psi_1 = 0, has no phase.
"""

from __future__ import annotations

import contextlib
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from cycler import cycler  # noqa: E402
from matplotlib.text import Text  # noqa: E402

SLIDE_SIZE = (10.0, 6.25)
"""Every figure's size in inches (16:10, a slide's width)."""

MIN_FONT_PT = 9.0
"""No text of a figure is smaller (points at :data:`SLIDE_SIZE`)."""

MAX_TITLE = 60
"""Characters of a figure's one-line title."""

TITLE_PT = 15.0
CAPTION_PT = 10.5

OKABE_ITO = {
    "blue": "#0072B2",
    "vermillion": "#D55E00",
    "bluish green": "#009E73",
    "orange": "#E69F00",
    "reddish purple": "#CC79A7",
    "sky blue": "#56B4E9",
    "yellow": "#F0E442",
    "black": "#000000",
}
"""The Okabe-Ito colours by name."""

PALETTE = tuple(
    OKABE_ITO[k]
    for k in ("blue", "vermillion", "bluish green", "orange", "reddish purple", "sky blue")
)
"""The line colours in order: Okabe-Ito without black (observed data are drawn black) and
yellow (too pale on white)."""

BLUE, VERMILLION, GREEN, ORANGE, PURPLE, SKY = PALETTE
BLACK = OKABE_ITO["black"]
MAP_CMAP = "viridis"
SIGNED_CMAP = "RdBu_r"

SLIDE_RC = {
    "font.size": 12.0,
    "axes.titlesize": 12.5,
    "axes.labelsize": 12.0,
    "xtick.labelsize": 10.5,
    "ytick.labelsize": 10.5,
    "legend.fontsize": 10.5,
    "legend.title_fontsize": 10.5,
    "figure.titlesize": TITLE_PT,
    "lines.linewidth": 1.8,
    "lines.markersize": 5.0,
    "axes.prop_cycle": cycler(color=PALETTE),
    "image.cmap": MAP_CMAP,
    "figure.figsize": SLIDE_SIZE,
}
"""rcParams of a slide figure (applied by :func:`slide_style`, never at import)."""

PHASE_FLOOR = 0.05
"""arg psi_1 is drawn where |psi_1| >= this fraction of its maximum."""


@contextlib.contextmanager
def slide_style():
    """:data:`SLIDE_RC` while the figure is made (the caller's rcParams come back)."""
    with plt.rc_context(SLIDE_RC):
        yield


def slide_figure(**kwargs) -> plt.Figure:
    """A :data:`SLIDE_SIZE` figure with constrained layout (call inside :func:`slide_style`)."""
    kwargs.setdefault("figsize", SLIDE_SIZE)
    kwargs.setdefault("layout", "constrained")
    return plt.figure(**kwargs)


def short(text: str, limit: int = MAX_TITLE) -> str:
    """``text`` on one line of at most ``limit`` characters (cut with '...')."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3].rstrip() + "..."


def number(value: float) -> str:
    """A value as a slide shows it: 4 significant digits without exponent from 1e-3 to
    1e5 (1558, 0.0229), 3 with one beyond (9.92e+07)."""
    return f"{value:.4g}" if 1e-3 <= abs(value) < 1e5 else f"{value:.3g}"


def readable_log_ticks(axis) -> None:
    """A log axis over less than a decade gets three plain tick labels (matplotlib would
    label its minor ticks in scientific notation, on top of each other)."""
    from matplotlib.ticker import FuncFormatter, MaxNLocator, NullFormatter

    low, high = axis.get_view_interval()
    if low > 0 and high / low < 10:
        axis.set_major_locator(MaxNLocator(3))
        axis.set_major_formatter(FuncFormatter(lambda v, _: number(v)))
        axis.set_minor_formatter(NullFormatter())


def masked_phase(psi1) -> np.ndarray:
    """Unwrapped arg psi_1, NaN where |psi_1| < :data:`PHASE_FLOOR` of its maximum (or
    not finite): where psi_1 is (nearly) zero, at a clamped base, its phase is noise and
    would draw a spike. The kept points are unwrapped in order, across the gaps."""
    psi1 = np.asarray(psi1, dtype=complex)
    amp = np.abs(psi1)
    finite = np.isfinite(psi1)
    out = np.full(psi1.shape, np.nan)
    if not finite.any():
        return out
    keep = finite & (amp >= PHASE_FLOOR * np.max(amp[finite])) & (amp > 0)
    if keep.any():
        out[keep] = np.unwrap(np.angle(psi1[keep]))
    return out


def follow(phase: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """``phase`` shifted by whole turns onto ``reference``'s branch (where both exist)."""
    both = np.isfinite(phase) & np.isfinite(reference)
    if not both.any():
        return phase
    return phase + 2 * np.pi * np.round(np.mean(reference[both] - phase[both]) / (2 * np.pi))


def _wrap(text: str, fig: plt.Figure, size: float) -> str:
    """``text``'s paragraphs (one per line of ``text``) wrapped to the figure's width."""
    # an average character of a proportional font is about 0.5 em wide; 0.55 keeps a margin
    width = max(40, int(fig.get_figwidth() * 72 * 0.96 / (0.55 * size)))
    return "\n".join(textwrap.fill(line, width) for line in text.splitlines() if line.strip())


def finish(fig: plt.Figure, title: str, caption: str = "") -> plt.Figure:
    """Give ``fig`` its one-line title (cut at :data:`MAX_TITLE` characters), the caption
    below the axes (wrapped to the figure's width, the layout leaving room for it), and
    raise every text smaller than :data:`MIN_FONT_PT` to it (tick labels included)."""
    fig.suptitle(short(title), fontsize=TITLE_PT)
    if caption:
        text = _wrap(caption, fig, CAPTION_PT)
        lines = text.count("\n") + 1
        height = (lines * 1.3 * CAPTION_PT / 72 + 0.12) / fig.get_figheight()
        fig.text(
            0.012,
            0.012,
            text,
            ha="left",
            va="bottom",
            fontsize=CAPTION_PT,
            color="0.15",
            linespacing=1.3,
        )
        engine = fig.get_layout_engine()
        if engine is not None and hasattr(engine, "set"):
            try:
                engine.set(rect=(0, height, 1, 1 - height))
            except TypeError:  # a tight layout: no rect to set
                fig.subplots_adjust(bottom=height + 0.06)
    for ax in fig.axes:  # ticks made later (at drawing) take their size from here
        ax.tick_params(which="both", labelsize=max(MIN_FONT_PT, SLIDE_RC["xtick.labelsize"]))
    for t in fig.findobj(Text):
        if t.get_fontsize() < MIN_FONT_PT:
            t.set_fontsize(MIN_FONT_PT)
    return fig
