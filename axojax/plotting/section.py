"""The cross-section of a model (the paper's figure 3): filaments, links, spokes, active
pairs, each dynein group's net bending direction and the beat plane."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch  # noqa: E402

from ..models.section import CrossSection, Model  # noqa: E402
from . import style  # noqa: E402

GROUP_COLORS = (style.ORANGE, style.PURPLE)
PLANE = style.BLUE


def group_bending_directions(section: CrossSection) -> dict[int, np.ndarray]:
    """Each active group's net dynein bending direction: the sum of its pairs' unit
    vectors n_a (from filament i to j) in (y, z). docs/model.md section 4 turns every 3D
    preset until these lie along +-y."""
    pos = section.positions
    out: dict[int, np.ndarray] = {}
    for a in section.active_pairs:
        n = pos[a.j] - pos[a.i]
        out[a.group] = out.get(a.group, np.zeros(2)) + n / np.linalg.norm(n)
    return out


def _axial_sign(section: CrossSection) -> np.ndarray:
    """(F,) sign of each filament's net dynein axial force: -1 baseward, +1 tipward, 0 none."""
    nu = np.zeros(section.n_filaments)
    for a in section.active_pairs:
        nu[a.i] -= 1.0
        nu[a.j] += 1.0
    return np.sign(nu)


def plot_section(
    section: CrossSection | Model, ax: plt.Axes | None = None, title: str | None = None
) -> plt.Figure:
    """Draw a cross-section in the (y, z) plane, y horizontal.

    Ring links are solid grey lines, spokes dotted; each active pair (i, j) is an arrow
    from i (pulled baseward) to j (pulled tipward), coloured by dynein group; a thick
    arrow from each group's centre shows its net bending direction (the sum of its pairs'
    unit vectors); the beat plane is the line z = 0. Filaments are numbered, marked by the
    sign of their net dynein axial force (dot: baseward, cross: tipward).

    Args:
        section: a :class:`CrossSection`, or a :class:`Model` (its section is drawn).
        ax: axes to draw into (default: a new figure).
        title: default: the section's name and size.

    Returns:
        The figure (a new one sized for a slide, :mod:`axojax.plotting.style`, its title the
        figure's; or ``ax``'s, its title the axes').
    """
    with style.slide_style():
        return _draw(section, ax, title)


def _draw(section, ax, title):
    if isinstance(section, Model):
        section = section.section
    own = ax is None
    if own:
        fig = style.slide_figure()
        ax = fig.subplots()
    else:
        fig = ax.figure
    pos = section.positions
    span = max(np.ptp(pos[:, 0]), np.ptp(pos[:, 1]), 1.0)
    dist = [np.linalg.norm(pos[l.j] - pos[l.i]) for l in section.links] or [span]
    radius = 0.13 * min(min(dist), span)
    lo, hi = pos.min(axis=0) - 0.45 * span, pos.max(axis=0) + 0.45 * span

    ax.axhline(0.0, color=PLANE, lw=1.4, ls="--", zorder=0)
    ax.text(lo[0], 0.0, " beat plane (z = 0)", color=PLANE, va="bottom", ha="left", fontsize=10)
    for l in section.links:
        (y0, z0), (y1, z1) = pos[l.i], pos[l.j]
        look = (
            dict(color="0.55", lw=1.0, ls=":")
            if l.kind == "spoke"
            else dict(color="0.35", lw=2.0, ls="-")
        )
        ax.plot([y0, y1], [z0, z1], zorder=1, **look)
    for a in section.active_pairs:
        color = GROUP_COLORS[a.group % len(GROUP_COLORS)]
        n = (pos[a.j] - pos[a.i]) / np.linalg.norm(pos[a.j] - pos[a.i])
        start, end = pos[a.i] + 1.15 * radius * n, pos[a.j] - 1.15 * radius * n
        ax.add_patch(
            FancyArrowPatch(
                start,
                end,
                arrowstyle="-|>",
                mutation_scale=16,
                lw=2.2,
                color=color,
                shrinkA=0,
                shrinkB=0,
                zorder=3,
            )
        )
    groups = group_bending_directions(section)
    for g, direction in sorted(groups.items()):
        members = sorted({f for a in section.active_pairs if a.group == g for f in (a.i, a.j)})
        centre = pos[members].mean(axis=0)
        centre = centre + 0.45 * (pos.mean(axis=0) - centre)  # inside the ring, clear of the pairs
        n = direction / max(np.linalg.norm(direction), 1e-300)
        color = GROUP_COLORS[g % len(GROUP_COLORS)]
        ax.add_patch(
            FancyArrowPatch(
                centre - 0.2 * span * n,
                centre + 0.2 * span * n,
                arrowstyle="simple",
                mutation_scale=22,
                color=color,
                alpha=0.55,
                zorder=2,
            )
        )
    sign = _axial_sign(section)
    for f, (y, z) in enumerate(pos):
        ax.add_patch(Circle((y, z), radius, facecolor="white", edgecolor="black", lw=1.2, zorder=4))
        ax.text(y, z, str(f), ha="center", va="center", fontsize=11, zorder=5)
        if sign[f]:
            ax.plot(
                y + 0.8 * radius,
                z + 0.8 * radius,
                marker="o" if sign[f] < 0 else "X",
                ms=5,
                color="black",
                mfc="black" if sign[f] < 0 else "white",
                zorder=6,
            )

    handles = [
        Line2D([], [], color="0.35", lw=2.0, label="link (k_l)"),
        Line2D([], [], color="0.55", lw=1.0, ls=":", label="spoke (k_s)"),
        *(
            Line2D(
                [],
                [],
                color=GROUP_COLORS[g % 2],
                lw=2.2,
                marker=">",
                label=f"active pair i -> j, group {g}",
            )
            for g in sorted(groups)
        ),
        *(
            Line2D(
                [],
                [],
                color=GROUP_COLORS[g % 2],
                lw=6,
                alpha=0.55,
                label=f"group {g} net bending direction",
            )
            for g in sorted(groups)
        ),
        Line2D([], [], color=PLANE, ls="--", label="beat plane (z = 0)"),
        Line2D([], [], ls="", marker="o", color="black", ms=5, label="pulled baseward"),
        Line2D([], [], ls="", marker="X", color="black", mfc="white", ms=5, label="pulled tipward"),
    ]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("y (beat-plane direction)")
    ax.set_ylabel("z")
    size = f"{section.n_filaments} filaments, {len(section.active_pairs)} active pairs"
    if not own:
        ax.set_title(title if title is not None else f"{section.name}: {size}")
        return fig
    return style.finish(
        fig, title if title is not None else f"Cross-section of {section.name}: {size}"
    )
