"""The dominant eigenpair's certificates over a grid of sliding control: how many points
the structured solver certifies with the pole's disc alone and with the right disc too
(``axojax/eigen/arnoldi.py``), and how far every certified eigenvalue lies from the dense
solver's.

Seven filaments at 10 elements (the default units), kl = ks / 1000; chi' = 0 to 1e5
pN/um^2 with chi'' = 0, chi' or 3 chi' at omega0 = 30 Hz; p 100-1000, ks 1e4 / 1e6 (14
points per row, 252 in all). Measured 2026-12-05 (about 2 min on 2 cores): 249 points
certified with the right disc, 231 with the pole's disc alone; every certified eigenvalue
within 4.1e-11 (relative) of the dense one. At 20 elements (``--elements 20``, ~6 min):
249 against 219, within 5.1e-10 (the steady load's rows too: the dense solver's own
error at that size; tests/eigen/test_solvers.py).

    python scripts/check_certificate_grid.py [--elements 10]
"""

import argparse

import jax
import jax.numpy as jnp
import numpy as np

import axojax as ax
from axojax.eigen import arnoldi
from axojax.eigen.mode import _dominant_mode_impl

CHI_PN_PER_UM2 = (0.0, 1e2, 1e3, 5e3, 2e4, 1e5)
CHI_IM_RATIO = (0.0, 1.0, 3.0)
P = (100.0, 200.0, 300.0, 400.0, 500.0, 700.0, 1000.0)
KS = (1e4, 1e6)


def grid(units, chi, ratio):
    p, ks = (jnp.asarray(x.ravel()) for x in np.meshgrid(P, KS))
    c = float(units.chi_from_pn_per_um2(chi))
    omega0 = float(units.omega0_from_hz(30.0)) if ratio else 0.0
    params = ax.Params(p=p, ks=ks, kl=ks / 1e3, chi_re=c, chi_im=ratio * c, omega0=omega0)
    return params.broadcast((p.shape[0],))


def solve(model, params, solver):
    run = jax.vmap(lambda q: _dominant_mode_impl(model, q, solver))
    modes = jax.jit(run)(params)
    return np.asarray(modes.eigenvalue), np.asarray(modes.certified) > 0.5


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=10)
    args = parser.parse_args()
    model = ax.models.seven(n_elements=args.elements)
    units = ax.Units()
    margins = arnoldi.RIGHT_DISC_MARGINS
    totals = {"right": 0, "pole": 0, "points": 0}
    worst = 0.0
    for chi in CHI_PN_PER_UM2:
        for ratio in CHI_IM_RATIO:
            params = grid(units, chi, ratio)
            dense, _ = solve(model, params, ax.eigen.Dense())
            lam, ok = solve(model, params, ax.eigen.Arnoldi(fallback=False))
            arnoldi.RIGHT_DISC_MARGINS = ()
            # another certify_factor (by 1e-12), so that the pole's disc alone is traced
            _, ok_pole = solve(
                model, params, ax.eigen.Arnoldi(fallback=False, certify_factor=2.0 + 1e-12)
            )
            arnoldi.RIGHT_DISC_MARGINS = margins
            err = np.abs(lam - dense) / np.abs(dense)
            worst = max(worst, float(err[ok].max(initial=0.0)))
            totals["right"] += int(ok.sum())
            totals["pole"] += int(ok_pole.sum())
            totals["points"] += ok.size
            print(
                f"chi' {chi:8.0f} pN/um^2, chi'' = {ratio:g} chi': certified {ok.sum():2d}/{ok.size} "
                f"(pole's disc alone {ok_pole.sum():2d}); certified vs dense: {err[ok].max(initial=0):.1e}",
                flush=True,
            )
    print(
        f"{totals['right']}/{totals['points']} certified "
        f"({totals['pole']} with the pole's disc alone); "
        f"largest relative difference from the dense eigenvalue where certified: {worst:.1e}"
    )


if __name__ == "__main__":
    main()
