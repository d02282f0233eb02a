"""The profile of the human sperm posterior along ks (issue 31's sperm command: seven
filaments, 10 elements, p and ks free, kl = ks / 1000, EI 90.9 pN um^2 and c_n 0.000285
pN s/um^2 per filament, shape floor 0.2 rad), as ``axojax fit --along ks`` tabulates it
(:func:`axojax.inverse.transport.build_map`, from the fit's optimum p 405.3, ks 2.863e4).

Prints, every third knot: log10 ks, p's conditional maximum, the conditional sd of z_p,
the log density there (-inf where the profile was lost) and the knot's normal quantile s.
It shows that the fit's optimum is a local mode: the log density rises from about -223
there to about -184 near ks 2.4e7, p 820, before a cliff near ks 4e7.

    python scripts/profile_human_sperm.py
"""

import jax.numpy as jnp
import numpy as np

import axojax as ax
from axojax.beats import read_beat
from axojax.eigen.solvers import Auto
from axojax.inverse import build_problem
from axojax.inverse._densities import _Target
from axojax.inverse._nuts import _compiled
from axojax.inverse.transport import build_map
from axojax.units import Units


def main() -> None:
    beat = read_beat("human_sperm")
    targets, shape = beat.targets()
    problem = build_problem(
        ax.models.seven(n_elements=10),
        ax.Params().with_values({"p": 405.0, "ks": 2.86e4}, 1000.0),
        targets,
        ["p", "ks"],
        shape=shape,
        kl_ratio=1000.0,
        units=Units(beat.length_um, 90.9, 0.000285),
        solver=Auto(min_batch_points=1),
        shape_floor=0.2,
    )
    target = _Target(problem)
    z_c = problem.to_z(jnp.log(jnp.array([405.3, 2.863e4])))
    profile, _ = _compiled(build_map, (1, 96), (target, z_c))
    print(f"{'log10 ks':>9} {'p':>8} {'sd z_p':>8} {'log density':>12} {'s':>7}")
    for j in range(0, 96, 3):
        z = jnp.array([profile.centre[j, 0], profile.z_knots[j]])
        p, ks = np.exp(np.asarray(problem.to_u(z)))
        print(
            f"{np.log10(ks):9.2f} {p:8.1f} {float(jnp.exp(profile.log_diag[j, 0])):8.4f} "
            f"{float(profile.log_density[j]):12.2f} {float(profile.s_knots[j]):7.3f}"
        )


if __name__ == "__main__":
    main()
