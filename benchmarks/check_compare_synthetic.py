"""``compare`` on synthetic beats of each organism's size and units (issue 45's acceptance).

For each organism of :data:`axojax.units.ORGANISMS` (its kappa, xi_n and head) at a typical
length and frequency, a beat is made with the model: the ``--truth`` row (default
sliding+curvature on clamped+elastic) at one of its exact Hopf points (drawn with the
seed), its psi_1 scaled to a peak of 0.8 rad, plus Gaussian noise of 0.02 rad on each of
Re and Im (the file's sigma). Then the default comparison (24 nested rows) runs with
``organism=...`` and the script prints, per organism: the truth row's status and R^2, the
best row, the rows that are not successful, every nesting violation (a row whose R^2 is
below a row it contains by more than 0.01: there should be none), the bootstrap share of
the best row (from one cycle-free Fourier file: none) and the wall time.

    python benchmarks/check_compare_synthetic.py [--organisms bull_sperm,chlamydomonas]
        [--elements 16] [--starts 3] [--seed 0]

Timings are for one machine and one run, not assertions (the machine may be shared).
"""

import argparse
import math
import pathlib
import tempfile
import time
import warnings

import numpy as np

import axojax as ax
from axojax.inverse.comparison.synthetic import synthetic_beat

SIZES = {  # typical length (um) and beat frequency (Hz)
    "human_sperm": (46.0, 10.0),  # the bundled beat's
    "bull_sperm": (60.0, 21.0),  # Riedel-Kruse et al. 2007
    "sea_urchin_sperm": (40.0, 35.0),  # Brokaw's sea urchin sperm: 40-50 um, 30-40 Hz
    "chlamydomonas": (12.0, 50.0),  # Sartori et al. 2016: about 12 um, 50-70 Hz
}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--organisms", default=",".join(SIZES))
    p.add_argument("--truth", default="sliding+curvature/clamped+elastic")
    p.add_argument("--elements", type=int, default=16)
    p.add_argument("--starts", type=int, default=3)
    p.add_argument("--seed", type=int, default=0)
    args = p.parse_args()
    truth = tuple(args.truth.split("/"))
    rng = np.random.default_rng(args.seed)
    with tempfile.TemporaryDirectory() as folder:
        for name in args.organisms.split(","):
            path, _ = synthetic_beat(
                pathlib.Path(folder) / f"{name}.npz",
                name,
                truth,
                *SIZES[name],
                rng,
                n_elements=args.elements,
            )
            t0 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = ax.compare(
                    path, organism=name, n_elements=args.elements, starts=args.starts
                )
            wall = time.perf_counter() - t0
            doc = result.to_json()
            rows = {f"{r['mechanism']}/{r['base']}": r for r in doc["rows"]}
            t = rows["/".join(truth)]
            bad = [k for k, r in rows.items() if r["status"] != "successful"]
            violations = [
                f"{k} {r['r2']:.3f} < {c} {rows[c]['r2']:.3f}"
                for k, r in rows.items()
                for c in r["contains"]
                if r["r2"] is not None
                and rows[c]["r2"] is not None
                and r["r2"] < rows[c]["r2"] - 0.01
            ]
            best = doc["rows"][0]
            print(
                f"{name}: L {SIZES[name][0]:g} um, {SIZES[name][1]:g} Hz, Sp "
                f"{doc['model']['sperm_number']:.4g}; {wall:.0f} s wall\n"
                f"  truth {args.truth}: {t['status']}, R^2 {t['r2']:.3f}\n"
                f"  best: {best['mechanism']}/{best['base']} R^2 {best['r2']:.3f} ({best['status']})\n"
                f"  not successful ({len(bad)}): {', '.join(bad) or '-'}\n"
                f"  nesting violations: {', '.join(violations) or 'none'}\n"
                f"  verdict: {doc['verdict']['text']}"
            )
            assert math.isfinite(wall)


if __name__ == "__main__":
    main()
