"""The profile of the human sperm posterior along ks (issue 31's sperm command: seven
filaments, 10 elements, p and ks free, kl = ks / 1000, EI 90.9 pN um^2 and c_n 0.000285
pN s/um^2 per filament, shape floor 0.2 rad), as ``axojax fit --posterior`` tabulates it
(:func:`axojax.inverse.sampling.transport.build_map`) from the fit's optimum, p 1033.85, ks
4.988e7 (the best of 16 starts; 4 starts stop at a local optimum, p 405, ks 2.9e4, whose
log density is about -223).

Prints, every other knot: log10 ks, p's conditional maximum, the conditional sd of z_p,
the log density there (-inf where the profile was lost) and the knot's normal quantile s.
It shows the ridge the posterior lies on: the log density rises to about -181.7 near ks
4e7-5e7 (p 960-1070) and falls to about -185 at the bound ks 1e8 and -230 at ks 1.4e6;
the conditional sd of z_p is about 0.0015 (0.2 % in p), beside a cliff about 3 % below
the maximum in p (some 12 sd) where another eigenmode becomes the dominant one.

    python scripts/profile_human_sperm.py
"""

import jax.numpy as jnp
import numpy as np

import axojax as ax
from axojax.beats import read_beat
from axojax.eigen.solvers import Auto
from axojax.inverse import build_problem
from axojax.inverse.sampling._densities import LogDensity
from axojax.inverse.sampling.programs import compiled
from axojax.inverse.sampling.transport import build_map
from axojax.units import Units


def main() -> None:
    beat = read_beat("human_sperm")
    targets, shape = beat.targets()
    problem = build_problem(
        ax.models.seven(n_elements=10),
        ax.Params().with_values({"p": 1033.85, "ks": 4.988e7}, 1000.0),
        targets,
        ["p", "ks"],
        shape=shape,
        kl_ratio=1000.0,
        units=Units(beat.length_um, 90.9, 0.000285),
        solver=Auto(min_batch_points=1),
        shape_floor=0.2,
    )
    target = LogDensity(problem)
    z_c = problem.to_z(jnp.log(jnp.array([1033.85, 4.988e7])))
    profile, _ = compiled(build_map, (1, 96), (target, z_c))
    print(f"{'log10 ks':>9} {'p':>8} {'sd z_p':>8} {'log density':>12} {'s':>7}")
    for j in range(0, profile.z_knots.shape[0], 2):
        z = jnp.array([profile.centre[j, 0], profile.z_knots[j]])
        p, ks = np.exp(np.asarray(problem.to_u(z)))
        print(
            f"{np.log10(ks):9.2f} {p:8.1f} {float(jnp.exp(profile.log_diag[j, 0])):8.4f} "
            f"{float(profile.log_density[j]):12.2f} {float(profile.s_knots[j]):7.3f}"
        )


if __name__ == "__main__":
    main()
