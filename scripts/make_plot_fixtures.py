"""Make tests/plotting/fixtures/: one small stored file of every kind ``axojax plot`` draws,
from the bundled data set (human_sperm) or a small model, by the quickest real commands
(tests/plotting/test_slide_figures.py renders them; scripts/make_gallery.py draws the
docs' gallery from them). Each kind's command is in :data:`COMMANDS` and the fixtures'
README.md; the minutes are on a shared two-core machine.

    python scripts/make_plot_fixtures.py [KIND ...]   # default: every kind

Kinds: compare (5 min), fit (10 min: the fit report and its posterior), sweep (1 min),
orbit (8 min), simulation (2 min), whole_beat (a whole-beat comparison of a synthetic
beat) and whole_beat_fit (its whole-beat fit). The beat data kind needs no file: it reads the bundled
``human_sperm``.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
FIXTURES = ROOT / "tests" / "plotting" / "fixtures"

WHOLE_BEAT_UNITS = ["--ei", "290.0", "--cn", "0.00245"]
"""The synthetic whole beat's units (tests/whole_beat/test_whole_beat_fit.py's ``UNITS``;
checked when the beat is written)."""

COMMANDS = {
    "compare": [
        "compare", "--data", "human_sperm", "--bases", "clamped,free", "--compliance", "off",
        "--elements", "6", "--starts", "1", "--out", "compare.json",
    ],
    "fit": [
        "fit", "--model", "seven", "--elements", "4", "--free", "p,ks", "--kl-ratio", "1000",
        "--data", "human_sperm", "--ei", "90.9", "--cn", "0.000285", "--shape-floor", "0.2",
        "--starts", "2", "--posterior", "100", "--chains", "2", "--warmup", "150",
        "--no-mesh-check", "--out", "fit.json",
    ],
    "sweep": [
        "sweep", "--model", "seven", "--elements", "4", "--p", "100:900:17",
        "--ks", "log:1e2:1e7:16", "--kl-ratio", "1000", "--out", "map.npz",
    ],
    "orbit": [
        "orbit", "--model", "seven", "--elements", "4", "--p", "240:330:10",
        "--out", "branch.npz",
    ],
    "whole_beat": [
        "compare", "--target", "limit-cycle", "--data", "whole_beat_beat.npz",
        "--mechanisms", "curvature,sliding", "--elements", "10", *WHOLE_BEAT_UNITS,
        "--out", "whole_beat.json",
    ],
    "whole_beat_fit": [
        "fit", "--target", "limit-cycle", "--mechanism", "curvature", "--data",
        "whole_beat_beat.npz", "--elements", "10", *WHOLE_BEAT_UNITS, "--no-mesh-check",
        "--out", "whole_beat_fit.json",
    ],
}  # fmt: skip
"""The ``axojax`` command of each kind (run in the fixtures' folder; the whole beat's
first writes its beat, :func:`whole_beat_beat`)."""

SIMULATION = {"p": 300.0, "t_end_s": 1.0, "samples_per_period": 16, "n_points": 21, "every": 5}
"""``axojax.dynamics.simulate(seven(n_elements=4), Params(p=300), 1.0 s, samples_per_period=16,
n_points=21)``, then every 5th saved frame kept in float32 (the solver saves at least 2000
frames per second: 1 MB; kept, 400 frames, 15 per period of the 26.5 Hz limit cycle)."""


def simulation(out: pathlib.Path) -> None:
    """The simulation fixture (:data:`SIMULATION`): a limit cycle of the seven-filament
    model, thinned to stay small."""
    import numpy as np

    import axojax as ax
    from axojax.dynamics import simulate

    c = SIMULATION
    sim = simulate(
        ax.models.seven(n_elements=4),
        ax.Params(p=c["p"]),
        c["t_end_s"],
        samples_per_period=c["samples_per_period"],
        n_points=c["n_points"],
    )
    k = c["every"]
    small = dataclasses.replace(
        sim,
        t_s=sim.t_s[::k].astype(np.float32),
        centreline_um=sim.centreline_um[::k].astype(np.float32),
        psi_rad=sim.psi_rad[::k].astype(np.float32),
        tip_um=sim.tip_um[::k].astype(np.float32),
    )
    small.save(out)
    print(f"{sim.state}: {len(sim.t_s)} frames, {len(small.t_s)} kept; wrote {out}")


def whole_beat_beat() -> None:
    """The synthetic curvature-control beat of tests/whole_beat/test_whole_beat_fit.py
    (clamped, 50 Hz, noise 0.02 rad) as a Fourier-mode file, ``whole_beat_beat.npz``."""
    sys.path.insert(0, str(ROOT))
    from tests.whole_beat.test_whole_beat_fit import UNITS, beat_file

    given = [float(WHOLE_BEAT_UNITS[1]), float(WHOLE_BEAT_UNITS[3])]
    if given != [UNITS.ei_pn_um2, UNITS.cn_pn_s_um2]:
        raise SystemExit(f"WHOLE_BEAT_UNITS {given} are not the test beat's {UNITS}")
    beat_file(FIXTURES).rename(FIXTURES / "whole_beat_beat.npz")


def make(kind: str) -> int:
    from axojax.cli.main import main

    FIXTURES.mkdir(parents=True, exist_ok=True)
    here = os.getcwd()
    os.chdir(FIXTURES)  # relative paths in what the commands write (fit.json names its .npz)
    try:
        if kind == "simulation":
            simulation(FIXTURES / "simulation.npz")
            return 0
        if kind.startswith("whole_beat"):
            whole_beat_beat()
        return main(COMMANDS[kind])
    finally:
        os.chdir(here)


if __name__ == "__main__":
    kinds = [*COMMANDS, "simulation"]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kinds", nargs="*", metavar="KIND", help=f"of {', '.join(kinds)} (default all)")
    chosen = ap.parse_args().kinds or kinds
    for k in chosen:
        if k not in kinds:
            ap.error(f"KIND: {k!r} is not one of {', '.join(kinds)}")
    codes = [make(k) for k in chosen]
    # axojax fit exits 1 when the targets are missed: the fixture is still written
    sys.exit(0 if all(c in (0, 1) for c in codes) else 2)
