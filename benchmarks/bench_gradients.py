"""Cost of value + gradient over value alone (seven-filament model, 10 elements).

Prints, measured in one run, for each eigen-solver (dense and the certified Arnoldi):
wall time per point of the three metrics (growth rate, frequency, wavelength), of the
metrics plus their gradient with respect to five parameters in reverse mode (one scalar
loss: a weighted sum, as in a fit) and in forward mode (the full 3 x 5 Jacobian), and
the ratios. Target: value + gradient under 1.5x value.

    python benchmarks/bench_gradients.py [--points 64] [--repeats 5]
"""

import axojax as ax  # first: it sets the XLA flags before jax starts
import argparse
import time

import jax
import jax.numpy as jnp
import numpy as np


NAMES = ("p", "ks", "kl", "cl", "gamma")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=64)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--model", default="seven")
    args = ap.parse_args()
    model = ax.models.preset(args.model)
    rng = np.random.default_rng(0)
    Z = jnp.asarray(np.column_stack([rng.uniform(400, 700, args.points), 10 ** rng.uniform(4, 6, args.points), 10 ** rng.uniform(1, 3, args.points), 10 ** rng.uniform(-3, -1, args.points), rng.uniform(-1, 0.3, args.points)]))

    for solver in (ax.eigen.Dense(), ax.eigen.Arnoldi()):
        report(model, solver, Z, args)


def report(model, solver, Z, args) -> None:
    def metrics(z):
        mode = ax.dominant_mode(model, ax.Params().with_values(dict(zip(NAMES, z))), solver=solver)
        return jnp.stack([mode.growth_rate_per_s(), mode.frequency_hz(), mode.wavelength_um()])

    def loss(z):
        m = metrics(z)
        return m[0] * 1e-3 + m[1] + m[2], m

    value = jax.jit(jax.vmap(metrics))
    value_grad = jax.jit(jax.vmap(jax.value_and_grad(loss, has_aux=True)))
    value_jac = jax.jit(jax.vmap(lambda z: (metrics(z), jax.jacfwd(metrics)(z))))

    def clock(f):
        jax.block_until_ready(f(Z))  # compile
        best = np.inf
        for _ in range(args.repeats):
            t = time.perf_counter()
            jax.block_until_ready(f(Z))
            best = min(best, time.perf_counter() - t)
        return best / args.points

    t_v, t_r, t_f = clock(value), clock(value_grad), clock(value_jac)
    print(f"solver {solver}, device: {jax.devices()[0].device_kind}, model {args.model} ({model.n_dof} dof), {args.points} points, best of {args.repeats}")
    print(f"value (3 metrics)                     {t_v * 1e3:8.3f} ms/point")
    print(f"value + reverse-mode gradient (5)     {t_r * 1e3:8.3f} ms/point   ratio {t_r / t_v:5.2f}x")
    print(f"value + forward-mode Jacobian (3x5)   {t_f * 1e3:8.3f} ms/point   ratio {t_f / t_v:5.2f}x")


if __name__ == "__main__":
    main()
