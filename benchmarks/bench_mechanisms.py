"""The structured solver's speed with regulated dynein against the steady load (issue 30).

Prints, measured in one run, for the seven-filament model at 10 and 40 elements and
vmapped batches of parameter points (p and ks drawn as in bench_sweep.py), the time per
point (compilation excluded, best of 5, the cases timed in turns) of ``ax.eigen.Arnoldi`` (its per-point path,
the CPU default) for:

- ``eigenpair`` (dominant mode) with the steady load: the reference;
- ``eigenpair`` with a regulated mechanism that keeps C symmetric positive definite
  (chi', chi'' >= 0, beta', beta'' = 0: the structured solver certifies there);
- the same with strong dynamic sliding control (chi' = 5e3 pN/um^2, chi'' = 3 chi':
  overdamped modes crowd the real axis; certified by the right disc);
- the same on a free base and on a head base (rigid-body modes deflated through a
  border, :mod:`axojax.eigen.deflation`: structured, not dense), each beside the steady
  load on the same base (the reference of its "same method" ratio);
- ``nearest`` (eigenvalue nearest i omega0) with the steady load and with a regulated
  mechanism whose C is non-symmetric and indefinite (beta'' != 0, chi'' < 0), shifted
  at i omega0 with omega0 the point's steady-load beat (often far from any eigenvalue:
  the random points grow fast), and ``nearest-pinned``, shifted 1 % of |lambda| from
  the eigenvalue it finds, as in a fit that pins the beat at the shift;

and the ratios ``steady time / regulated time``, against the steady-load eigenpair and
against the steady load with the same method (the issue's target: >= 0.8, i.e. the
regulated solve keeps >= 80 % of the steady-load speed), with the share of points
certified (a point not certified pays for a dense solve). The machine's load
average is printed before and after.

Measured (2026-12-04, 2 CPU cores shared with other helpers' jobs, load average 5-7;
seven filaments, 32 points at 10 and 8 at 40 elements), ms per point, and in brackets
the speed relative to the steady-load eigenpair / to the steady load with the same
method (docs/benchmarks.md has the run of the previous commit next to it):

    N_e  steady     regulated    steady     regulated          steady     regulated
         eigenpair  eigenpair    nearest    nearest            pinned     pinned
    10   2.63       2.02 (1.30)  5.77       7.02 (0.38/0.82)   1.73       1.57 (1.67/1.10)
    40   10.3       10.4 (0.99)  26.8       28.3 (0.36/0.95)   8.95       7.99 (1.29/1.12)

Free and head bases (2026-12-05, load ~1.7, same run as above's successor): the
regulated eigenpair (C symmetric positive definite) with the rigid-body modes deflated
through a border runs at 1.11x (free) and 0.96x (head) the clamped steady load's
eigenpair at 10 elements, 0.94x and 0.79x at 40, every point certified (before: the
dense solver, 10 ms at 10 elements, 300 ms at 40). Against the steady load on the same
base (rows added 2026-12-05; `--points 16 --points40 8`, load 0.5-1.2): free 1.02x and
0.94x, head 0.92x and 0.93x at 10 and 40 elements, every point certified; in that run
every regulated row kept 0.92-1.12x of the steady load's speed with the same method.

Strong dynamic sliding control (2026-12-05, `--points 16 --points40 8`, load 1.9-3.3):
0.88x at 10 elements, 0.98x at 40, every point certified (with the pole's disc alone,
i.e. before the right disc, the same points took 1.2x longer).

Single numbers move by tens of per cent between runs on this machine. Every regulated
point certified (no dense fallback; one steady point at 10 elements falls back, which
makes the steady eigenpair slower there). The dominant eigenpair with a regulated
mechanism (C symmetric positive definite) meets the 80 % target, and so does
``nearest`` with the shift near the beat (pinned, as in a fit): first Krylov stages of
6 and 8 vectors, a packed complex factorisation, real matrices on complex vectors as
two real products. With the shift far from any eigenvalue ``nearest`` keeps its own
steady-load speed but is ~2.6x slower than the dominant eigenpair: its certificate
needs 8-48 Krylov vectors (mean 30 at 10 elements, against 20) and a complex
shift-invert step costs 3.8x a real one. It is linear in N_e and certified for any C,
where the dense ``nearest`` is O(N_e^3).

    python benchmarks/bench_mechanisms.py [--points 32] [--points40 8] [--quick]
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
from axojax.models import Base

SPD = dict(chi_re=2e4, chi_im=2e4, beta_re=100.0)
"""A regulated mechanism with C symmetric positive definite (omega0 set per point)."""

STRONG_SLIDING = dict(chi_re=1.4256e6, chi_im=4.2768e6)
"""Strong dynamic sliding control, C symmetric positive definite (chi' = 5e3 pN/um^2, chi'' =
3 chi' in the default units): overdamped modes crowd the real axis left of the dominant one,
certified by the right disc (axojax/eigen/arnoldi.py; the pole's disc alone sent such
points dense)."""

GENERAL = dict(chi_re=2e3, chi_im=-3e3, beta_re=300.0, beta_im=500.0)
"""A regulated mechanism with C non-symmetric (beta'') and indefinite (chi'' < 0)."""


def points(n: int, seed: int = 0) -> ax.Params:
    rng = np.random.default_rng(seed)
    ks = 10 ** rng.uniform(3, 6, n)
    return ax.Params().replace(p=rng.uniform(250, 700, n), ks=ks, kl=ks / 1000).broadcast()


def timed_round_robin(cases: dict, repeats: int = 5) -> dict[str, tuple[float, object]]:
    """{name: (best seconds, output)} of ``cases`` {name: (f, args)}, compiled first and
    then timed in turns (case 1, 2, ..., 1, 2, ...), so that the load of a shared machine
    falls on every case alike."""
    outs = {name: jax.block_until_ready(f(*args)) for name, (f, args) in cases.items()}
    best = dict.fromkeys(cases, np.inf)
    for _ in range(repeats):
        for name, (f, args) in cases.items():
            t = time.perf_counter()
            jax.block_until_ready(f(*args))
            best[name] = min(best[name], time.perf_counter() - t)
    return {name: (best[name], outs[name]) for name in cases}


def run(n_elements: int, n_points: int) -> dict[str, tuple[float, float]]:
    """{case: (seconds per point, share certified)}."""
    model = ax.models.seven(n_elements=n_elements)
    solver = Arnoldi()
    base = points(n_points)
    dominant = jax.jit(jax.vmap(lambda q: _dominant_mode_impl(model, q, solver)))
    nearest = jax.jit(jax.vmap(lambda q, s: nearest_mode_impl(model, q, s, solver)))
    steady = dominant(base)
    # omega0 at each point's steady beat: the mechanism's terms at i omega0 are then
    # chi and beta, and the shift sits near the eigenvalue a fit would pin.
    omega0 = jnp.maximum(steady.angular_frequency, 1.0)
    shifts = (1j * omega0).astype(complex)
    spd = base.replace(omega0=omega0, **{k: jnp.full(n_points, v) for k, v in SPD.items()})
    gen = base.replace(omega0=omega0, **{k: jnp.full(n_points, v) for k, v in GENERAL.items()})
    strong = base.replace(
        omega0=omega0, **{k: jnp.full(n_points, v) for k, v in STRONG_SLIDING.items()}
    )
    # As a fit that pins the beat sees it: the shift 1 % of |lambda| from the eigenvalue.
    pinned_steady = steady.eigenvalue * (1 + 0.01j)
    pinned_gen = nearest(gen, shifts).eigenvalue * (1 + 0.01j)
    # Bases that let the axoneme move rigidly: the rigid-body modes deflated through a
    # border of the structured pencil (axojax/eigen/deflation.py), not solved densely.
    on_base = {
        kind: jax.jit(
            jax.vmap(
                lambda q, m=ax.models.seven(n_elements=n_elements, base=b): _dominant_mode_impl(
                    m, q, solver
                )
            )
        )
        for kind, b in (("free", "free"), ("head", Base("head", False, 1.0, 0.2)))
    }
    res = timed_round_robin(
        {
            "steady eigenpair": (dominant, (base,)),
            "regulated eigenpair": (dominant, (spd,)),
            "regulated eigenpair, strong chi''": (dominant, (strong,)),
            "free base, steady eigenpair": (on_base["free"], (base,)),
            "free base, regulated eigenpair": (on_base["free"], (spd,)),
            "head base, steady eigenpair": (on_base["head"], (base,)),
            "head base, regulated eigenpair": (on_base["head"], (spd,)),
            "steady nearest": (nearest, (base, shifts)),
            "regulated nearest": (nearest, (gen, shifts)),
            "steady nearest-pinned": (nearest, (base, pinned_steady)),
            "regulated nearest-pinned": (nearest, (gen, pinned_gen)),
        }
    )
    return {
        name: (t / n_points, float(jnp.mean(mode.certified))) for name, (t, mode) in res.items()
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=32, help="points at 10 elements")
    parser.add_argument("--points40", type=int, default=8, help="points at 40 elements")
    parser.add_argument(
        "--quick", action="store_true", help="10 elements only (the 40-element model is skipped)"
    )
    args = parser.parse_args()
    print(f"load average (1, 5, 15 min) at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    print(f"backend: {jax.default_backend()}, {os.cpu_count()} cpus")
    sizes = ((10, args.points),) if args.quick else ((10, args.points), (40, args.points40))
    for n_elements, n_points in sizes:
        res = run(n_elements, n_points)
        ref = res["steady eigenpair"][0]
        print(f"\nseven, {n_elements} elements, {n_points} points (vmapped, per-point path):")
        print("  (speed relative to the clamped steady load's eigenpair, and to the steady")
        print("   load's time on the same base with the same method)")
        for name, (t, cert) in res.items():
            # the steady load on the same base with the same method
            same = res[name.replace("regulated", "steady").replace(", strong chi''", "")][0]
            print(
                f"  {name:34s} {1e3 * t:8.2f} ms/point  certified {100 * cert:5.1f} %"
                f"  vs steady eigenpair {ref / t:5.2f}  vs steady, same method {same / t:5.2f}"
            )
    print(f"\nload average (1, 5, 15 min) at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
