"""How the mechanism ranking on the bundled human sperm moves with the flagellum's units:
the table "How the ranking moves with the units" of docs/mechanisms.md.

Refits steady, sliding + curvature and curvature control on clamped, clamped + elastic and
head bases (``ax.compare``, its other defaults: the ``two`` preset, 16 elements, 3 starts)
at three alternatives to the data set's kappa 1900 pN um^2 and xi_n 3.2e-3 pN s/um^2 (the
default row of that table is ``axojax compare --data human_sperm``), and prints each table.
About 2.5 minutes on 2 cores (2026-12-04: 53, 46 and 48 s).

    python scripts/compare_units_sensitivity.py
"""

import time
import warnings

import axojax as ax

ALTERNATIVES = (
    (1900.0, 2.0e-3, "Gray and Hancock's xi_n"),
    (3600.0, 3.2e-3, "Gaffney et al.'s mean kappa"),
    (1000.0, 3.2e-3, "a soft flagellum"),
)
"""(kappa pN um^2, xi_n pN s/um^2, why) of each refit."""


def main() -> None:
    beat = ax.datasets.human_sperm()
    for kappa, xi_n, why in ALTERNATIVES:
        units = ax.Flagellum(kappa, xi_n).units(beat.length_um, 2)
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = ax.compare(
                beat,
                mechanisms=("steady", "sliding+curvature", "curvature"),
                bases=("clamped", "clamped+elastic", "head"),
                units=units,
            )
        sp = float(units.omega0_from_hz(beat.frequency_hz))
        print(
            f"== kappa {kappa:g} xi_n {xi_n:g} ({why}), Sp {sp:.0f}, {time.perf_counter() - t0:.0f} s"
        )
        print(result.table(), flush=True)


if __name__ == "__main__":
    main()
