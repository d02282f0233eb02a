"""Make docs/images/orbit_branch.png: the limit-cycle branch of the seven-filament model
(10 elements, cubic 10) in p from its Hopf point, with stability from the Floquet
multipliers. It runs the README's command::

    axojax orbit --model seven --p 240:330:10 --out orbit_branch.npz --plot docs/images/orbit_branch.png

    python scripts/make_orbit_figure.py [--out docs/images/orbit_branch.png]
"""

import argparse
import pathlib
import sys
import tempfile

from axojax.cli.main import main

ROOT = pathlib.Path(__file__).resolve().parents[1]
COMMAND = ["orbit", "--model", "seven", "--p", "240:330:10"]


def make(out: pathlib.Path) -> int:
    out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        return main(
            COMMAND + ["--out", str(pathlib.Path(tmp) / "orbit_branch.npz"), "--plot", str(out)]
        )


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--out", type=pathlib.Path, default=ROOT / "docs" / "images" / "orbit_branch.png"
    )
    sys.exit(make(ap.parse_args().out))
