"""Does ``ax.simulate`` from its default start (the 0.1 um tip bend) reach the limit cycle
of the inferred figure 12 parameters (``axojax.paper.INFERRED["fig12"]``) within 25
periods plus 8 e-foldings of the linear growth rate (the default ``--t-end``)? A check too
slow for the test suite (tests/waveform/test_one_wavelength.py runs it in the slow set).

The orbit (``ax.limit_cycle``, harmonic balance) and the time-domain run (diffrax, from
the tip deflection of :func:`axojax.dynamics.simulate.tip_deflection`) are independent
computations of the same beat; their measures come from the same functions
(:mod:`axojax.waveform.measures`). Asserted: the run ends on a limit cycle with the
orbit's frequency within 0.5 %, and its wavelength, static curvature, dynamic and tip
amplitude within 2 % (the run's are measured at the 41 saved points over its last two
periods, the orbit's exactly). Measured: see docs/benchmarks.md.

    python benchmarks/check_fig12_simulate.py [--t-end SECONDS]
"""

import argparse
import sys
import time

import axojax as ax
from axojax import paper


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--t-end",
        type=float,
        default=None,
        help="simulated time (s); default 25 periods + 8 e-foldings of the linear growth rate",
    )
    args = parser.parse_args(argv)
    inf = paper.INFERRED["fig12"]
    model, params = inf.build()
    m, cyc = paper.inferred.fig12_measures()
    orbit = m.scalars()
    growth = float(ax.dominant_mode(model, params).growth_rate_per_s())
    if args.t_end is None:
        args.t_end = 25 / orbit["frequency_hz"] + 8 / growth
    print(f"linear growth rate {growth:.3g} 1/s; simulating {args.t_end:.3g} s")
    t0 = time.perf_counter()
    sim = ax.simulate(model, params, args.t_end, cubic=inf.cubic)
    wall = time.perf_counter() - t0
    print(f"simulate: {sim.state} after {args.t_end:g} s of beat ({wall:.0f} s wall)")
    if sim.state != "limit_cycle":
        print(f"no limit cycle: {sim.reason}")
        return 1
    lc = sim.limit_cycle
    ok = True
    for name, rel in (
        ("frequency_hz", 0.005),
        ("wavelength_um", 0.02),
        ("static_curvature_rad_per_um", 0.02),
        ("dynamic_amplitude_rad", 0.02),
        ("tip_amplitude_um", 0.02),
    ):
        diff = lc[name] / orbit[name] - 1
        good = abs(diff) <= rel
        ok &= good
        print(
            f"{name:28s} simulate {lc[name]:10.5g}  orbit {orbit[name]:10.5g}  {diff:+.2e}  "
            f"{'ok' if good else 'FAILS'} (within {rel:g})"
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
