"""Make docs/images/gallery_*.png, the figures of docs/gallery.md: one of every kind
``axojax plot`` draws (and ``axojax data --plot``'s), from the bundled data set and the
small stored results in tests/plotting/fixtures/ (scripts/make_plot_fixtures.py made
them, by the commands docs/gallery.md shows), drawn by the function ``axojax plot`` calls
for each, at the figures' own slide size (10 x 6.25 in) and 100 dpi.

    python scripts/make_gallery.py [--out docs/images]
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "tests" / "plotting" / "fixtures"
DPI = 100


def figures():
    """(name, figure) of every kind, in the gallery's order."""
    import axojax as ax
    from axojax.beats import read_beat
    from axojax.dynamics import Simulation
    from axojax.inverse import Posterior, load_truth
    from axojax.orbits.branch import Branch
    from axojax.plotting import plot_section, plot_simulation, plot_sweep
    from axojax.plotting.beat_data import plot_beat_data
    from axojax.plotting.compare import plot_comparison
    from axojax.plotting.corner import plot_corner
    from axojax.plotting.fit_report import plot_fit_report
    from axojax.plotting.orbits import plot_branch
    from axojax.sweeps import SweepResult

    posterior = FIXTURES / "fit.posterior.npz"
    yield "data", lambda: plot_beat_data(read_beat("human_sperm"))
    yield "compare", lambda: plot_comparison(json.loads((FIXTURES / "compare.json").read_text()))
    yield (
        "whole_beat",
        lambda: plot_comparison(json.loads((FIXTURES / "whole_beat.json").read_text())),
    )
    yield "fit", lambda: plot_fit_report(json.loads((FIXTURES / "fit.json").read_text()))
    yield (
        "posterior",
        lambda: plot_corner(Posterior.load(posterior), truth=load_truth(posterior)),
    )
    yield "map", lambda: plot_sweep(SweepResult.load(FIXTURES / "map.npz"))
    yield "simulation", lambda: plot_simulation(Simulation.load(FIXTURES / "simulation.npz"))
    yield "orbit_branch", lambda: plot_branch(*Branch.load(FIXTURES / "branch.npz"))
    yield "section", lambda: plot_section(ax.models.preset("seven"))


def make(out: pathlib.Path) -> list[pathlib.Path]:
    import matplotlib.pyplot as plt

    from axojax._io import save_figure

    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, draw in figures():
        fig = draw()
        path = out / f"gallery_{name}.png"
        save_figure(fig, path, dpi=DPI)  # written whole
        plt.close(fig)
        written.append(path)
        print(f"wrote {path}")
    return written


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "docs" / "images")
    make(ap.parse_args().out)
    sys.exit(0)
