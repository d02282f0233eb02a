"""Wall time of one limit cycle computed directly: the seven-filament model on 10
elements (280 unknowns), cubic stiffening 10, p = 1.04 p_c, by harmonic balance and
Newton (:func:`axojax.limit_cycle`), Floquet multipliers included.

The first call includes compilation; the second, identical call does not (reported
separately). ``bench_simulate.py`` calls :func:`orbit_times` beside its 20-period
simulation.

    python benchmarks/bench_orbit.py [--elements 10] [--harmonics 8]
"""

import argparse
import time

import jax

import axojax as ax  # first: it sets the XLA flags before jax starts


def orbit_times(elements: int = 10, harmonics: int = 8, cubic: float = 10.0) -> dict:
    """Times (s) of one orbit with and without compilation, and the orbit's measures."""
    model = ax.models.seven(n_elements=elements)
    params = ax.Params(p=1.04 * float(ax.critical_force(model, ax.Params()).p))
    solver = ax.orbits.HarmonicBalance(harmonics=harmonics)
    times = []
    for _ in range(2):
        t = time.perf_counter()
        cycle = ax.limit_cycle(model, params, cubic, solver=solver)
        jax.block_until_ready(cycle.coefficients)
        times.append(time.perf_counter() - t)
    rep = cycle.to_json()
    return {
        "with_compilation_s": times[0],
        "after_compilation_s": times[1],
        "newton_steps": int(cycle.steps),
        "n_dof": model.n_dof,
        **rep,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", type=int, default=10)
    ap.add_argument("--harmonics", type=int, default=8)
    args = ap.parse_args()
    r = orbit_times(args.elements, args.harmonics)
    rho = sorted((abs(complex(*z)) for z in r["floquet"]), reverse=True)
    print(
        f"one orbit, seven filaments, {args.elements} elements ({r['n_dof']} dof), cubic 10, p "
        f"= 1.04 p_c, {args.harmonics} harmonics: "
        f"{r['after_compilation_s']:.2f} s ({r['with_compilation_s']:.1f} s with compilation), "
        f"{r['newton_steps']} Newton steps; "
        f"{r['frequency_hz']:.3f} Hz, tip amplitude {r['tip_amplitude_um']:.3f} um, wavelength "
        f"{r['wavelength_um']:.2f} um, "
        f"Floquet |rho| = {', '.join(f'{x:.3g}' for x in rho[:4])} ({'stable' if r['stable'] else 'unstable'})"
    )


if __name__ == "__main__":
    main()
