"""Time of ``axojax compare``'s default set on one beat (issue 30: under 5 minutes on 2 cores).

Runs :func:`axojax.compare` with its defaults (every mechanism on the default bases, each
without and with a basal spring: 24 rows; the ``two`` preset, 16 elements, 3 starts per
row; the data set's flagellum's units) on the bundled human sperm beat, and
prints the total wall time, each row's (compilation, screening of its starts and the
least-squares fit), and the table. Timings are for one machine and one run, not
assertions; the machine may be shared, so the CPU time of the process is printed too.

    python benchmarks/bench_compare.py [--elements 16] [--starts 3] [--model two] \\
        [--ei PN_UM2 --cn PN_S_UM2] [--compliance off] [--organism NAME] [--params]
"""

import argparse
import time
import warnings

import axojax as ax
from axojax.inverse.comparison.compare import default_units


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=16)
    parser.add_argument("--starts", type=int, default=3)
    parser.add_argument("--model", default="two")
    parser.add_argument("--ei", type=float, default=None, help="default: the data set's")
    parser.add_argument("--cn", type=float, default=None, help="default: the data set's")
    parser.add_argument("--compliance", default=None, help="default: compare's (both-elastic)")
    parser.add_argument("--organism", default=None, help="an axojax.units.ORGANISMS preset")
    parser.add_argument("--params", action="store_true", help="also print the fitted values")
    args = parser.parse_args()
    beat = ax.datasets.human_sperm()
    units = None
    if args.ei is not None or args.cn is not None:
        default, _ = default_units(beat, args.model)
        units = ax.Units(
            beat.length_um,
            default.ei_pn_um2 if args.ei is None else args.ei,
            default.cn_pn_s_um2 if args.cn is None else args.cn,
        )
    compliance = {"off": False, "on": True}.get(args.compliance, args.compliance)
    wall, cpu = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = ax.compare(
            beat,
            model=args.model,
            n_elements=args.elements,
            units=units,
            starts=args.starts,
            progress=False,
            compliance=compliance,
            organism=args.organism,
        )
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    print(result.table(params=args.params))
    print(
        f"default set ({len(result.rows)} rows, {args.model}, {args.elements} elements, "
        f"{args.starts} starts): {wall:.1f} s wall, {cpu:.1f} s CPU (all threads)"
    )
    for r in result.rows:
        print(f"  {r.mechanism:<18} {r.base:<16} {r.wall_s:6.1f} s  {r.status}")


if __name__ == "__main__":
    main()
