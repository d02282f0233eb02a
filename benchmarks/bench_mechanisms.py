"""The structured solver's speed with regulated dynein against the steady load (issue 30).

Prints, measured in one run, for the seven-filament model at 10 and 40 elements and
vmapped batches of parameter points (p and ks drawn as in bench_sweep.py), the time per
point (compilation excluded, best of 3) of ``ax.eigen.Arnoldi`` (its per-point path,
the CPU default) for:

- ``eigenpair`` (dominant mode) with the steady load: the reference;
- ``eigenpair`` with a regulated mechanism that keeps C symmetric positive definite
  (chi', chi'' >= 0, beta', beta'' = 0: the structured solver certifies there);
- ``nearest`` (eigenvalue nearest i omega0) with the steady load and with a regulated
  mechanism whose C is non-symmetric and indefinite (beta'' != 0, chi'' < 0), shifted
  at i omega0 with omega0 the point's steady-load beat (the beat such a fit pins);

and the ratios ``steady eigenpair time / regulated time`` (the issue's target: >= 0.8,
i.e. the regulated solve keeps >= 80 % of the steady-load speed), with the share of
points certified (a point not certified pays for a dense solve). The machine's load
average is printed before and after.

Measured (2026-12-03, 2 cores shared with 3-4 other helpers' tests, load ~4; seven
filaments, 32 points at 10 and 8 at 40 elements):

    N_e  steady eigenpair  regulated eigenpair  steady nearest  regulated nearest
    10   see docs/benchmarks.md (the numbers of the run recorded there)

    python benchmarks/bench_mechanisms.py [--points 32] [--points40 8]
"""

import argparse
import os
import time

import jax
import jax.numpy as jnp
import numpy as np

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax.eigen import Arnoldi
from axojax.eigen.mode import _dominant_mode_impl
from axojax.eigen.nearest import nearest_mode_impl

SPD = dict(chi_re=2e4, chi_im=2e4, beta_re=100.0)
"""A regulated mechanism with C symmetric positive definite (omega0 set per point)."""

GENERAL = dict(chi_re=2e3, chi_im=-3e3, beta_re=300.0, beta_im=500.0)
"""A regulated mechanism with C non-symmetric (beta'') and indefinite (chi'' < 0)."""


def points(n: int, seed: int = 0) -> ax.Params:
    rng = np.random.default_rng(seed)
    ks = 10 ** rng.uniform(3, 6, n)
    return ax.Params().replace(p=rng.uniform(250, 700, n), ks=ks, kl=ks / 1000).broadcast()


def timed(f, *args, repeats: int = 3) -> tuple[float, object]:
    out = jax.block_until_ready(f(*args))
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(f(*args))
        best = min(best, time.perf_counter() - t)
    return best, out


def run(n_elements: int, n_points: int) -> dict[str, tuple[float, float]]:
    """{case: (seconds per point, share certified)}."""
    model = ax.models.seven(n_elements=n_elements)
    solver = Arnoldi()
    base = points(n_points)
    dominant = jax.jit(jax.vmap(lambda q: _dominant_mode_impl(model, q, solver)))
    nearest = jax.jit(jax.vmap(lambda q, s: nearest_mode_impl(model, q, s, solver)))
    out = {}
    t, steady = timed(dominant, base)
    out["steady eigenpair"] = (t / n_points, float(jnp.mean(steady.certified)))
    # omega0 at each point's steady beat: the mechanism's terms at i omega0 are then
    # chi and beta, and the shift sits near the eigenvalue a fit would pin.
    omega0 = jnp.maximum(steady.angular_frequency, 1.0)
    shifts = (1j * omega0).astype(complex)
    spd = base.replace(omega0=omega0, **{k: jnp.full(n_points, v) for k, v in SPD.items()})
    gen = base.replace(omega0=omega0, **{k: jnp.full(n_points, v) for k, v in GENERAL.items()})
    for name, f, args in (
        ("regulated eigenpair", dominant, (spd,)),
        ("steady nearest", nearest, (base, shifts)),
        ("regulated nearest", nearest, (gen, shifts)),
    ):
        t, mode = timed(f, *args)
        out[name] = (t / n_points, float(jnp.mean(mode.certified)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=32, help="points at 10 elements")
    parser.add_argument("--points40", type=int, default=8, help="points at 40 elements")
    args = parser.parse_args()
    print(f"load average (1, 5, 15 min) at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(f"backend: {jax.default_backend()}, {os.cpu_count()} cpus")
    for n_elements, n_points in ((10, args.points), (40, args.points40)):
        res = run(n_elements, n_points)
        ref = res["steady eigenpair"][0]
        print(f"\nseven, {n_elements} elements, {n_points} points (vmapped, per-point path):")
        for name, (t, cert) in res.items():
            print(
                f"  {name:20s} {1e3 * t:8.2f} ms/point  certified {100 * cert:5.1f} %"
                f"  steady-eigenpair speed ratio {ref / t:5.2f}"
            )
    print(f"\nload average (1, 5, 15 min) at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
