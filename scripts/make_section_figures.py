"""Draw the cross-sections of the presets four, seven and nine into docs/images/.

    python scripts/make_section_figures.py [OUTDIR]

The same figure comes from ``axojax plot --model seven --out section.png``.
"""

from __future__ import annotations

import pathlib
import sys

import axojax as ax
from axojax.plotting import plot_section

PRESETS = ("four", "seven", "nine")


def main(outdir: str | None = None) -> None:
    out = (
        pathlib.Path(outdir)
        if outdir
        else pathlib.Path(__file__).resolve().parents[1] / "docs" / "images"
    )
    out.mkdir(parents=True, exist_ok=True)
    for name in PRESETS:
        path = out / f"section_{name}.png"
        plot_section(ax.models.preset(name)).savefig(path, dpi=110)
        print(f"wrote {path}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
