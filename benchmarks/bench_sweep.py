"""Sweep throughput and how the dominant-mode solver scales with the mesh (issue 14).

Prints, measured in one run:

1. points/s of the whole ``axojax sweep`` command (start-up and compilation included,
   default solver; then again with its compiled programs loaded from the cache that
   the command line keeps, ``axojax/cache.py``) on a 400-point seven-filament 10-element map, against a plain loop of
   ``scipy.linalg.eig`` over the same (prebuilt) matrices (the faster of every core and
   one BLAS thread), and against scipy's shift-invert ARPACK
   (``scipy.sparse.linalg.eigs``, k = 6, sparse LU) given a real shift 1 % (of |lambda|)
   right of the true answer: its best case, which still misses the rightmost eigenvalue
   at some points (counted; ARPACK certifies nothing, and shifts continued from a
   neighbouring grid point miss it at most points). Then the same command on an
   80 x 80 map (6400 points), whose rate is compared with the scipy loops' rates measured
   on the 400 points.
2. the time per point of the dominant eigenpair at N_e = 10, 20, 40, 80 elements for the
   certified Arnoldi solver's per-point path (the CPU default), its batched path
   (``Arnoldi(batched=True)``, up to 40) and the dense solver (up to 40), compilation
   excluded, the growth exponents fitted to log(time) against log(N_e), and at N_e = 10
   the ratios to the scipy loops' time per point of part 1;
3. cold start: the import of the command (``axojax.cli.main`` and its sweep module, in
   a fresh process, best of 3) and the compilation of the sweep's chunk evaluator
   (256 points, wall and CPU seconds, one run).

The machine's load average is printed before and after (timings on a shared machine
vary with it; the ratios are measured within one run). Targets (issue 22): per point
>= 60x the scipy eig loop and >= 8x ARPACK's best case, exponent <= 1.2; the whole
command >= 40x on 6400 points and >= 10x on 400 points cold; import <= 0.8 s and
compilation <= 1.5 s.

    python benchmarks/bench_sweep.py [--p 100:900:20] [--ks log:1e2:1e7:20] [--large 80] [--skip-scaling]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import jax
import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
from threadpoolctl import threadpool_limits

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax.assembly import node_major
from axojax.cli.common import parse_axis
from axojax.eigen import Arnoldi, Dense


def whole_command(args, p_axis: str, ks_axis: str, cache: str = "off") -> tuple[float, dict]:
    """Seconds and JSON report of one ``axojax sweep`` process; ``cache`` is its
    ``AXOJAX_CACHE_DIR`` (axojax/cache.py): ``off`` compiles everything."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [
            sys.executable,
            "-m",
            "axojax.cli.main",
            "sweep",
            "--model",
            args.model,
            "--p",
            p_axis,
            "--ks",
            ks_axis,
            "--kl-ratio",
            "1000",
            "--out",
            os.path.join(tmp, "s.npz"),
            "--json",
        ]
        t = time.perf_counter()
        out = subprocess.run(
            cmd,
            check=True,
            capture_output=True,
            text=True,
            env={**os.environ, "AXOJAX_CACHE_DIR": cache},
        ).stdout
        return time.perf_counter() - t, json.loads(out)


def scipy_loops(model, p, ks):
    mats = []
    for pv in p:
        for kv in ks:
            s = ax.assemble(model, ax.Params(p=pv, ks=kv, kl=kv / 1000))
            mats.append((-np.asarray(s.A), np.asarray(s.C)))
    # importing axojax gave scipy's BLAS one thread (axojax/_runtime.py); the reference
    # loops get every core back, as a plain scipy script would have them; on a shared
    # machine threads can lose more than they gain, so one thread is timed too and the
    # faster of the two is the reference
    t_eig = np.inf
    for threads in (os.cpu_count(), 1):
        with threadpool_limits(limits=threads, user_api="blas"):
            t = time.perf_counter()
            dense = []
            for A, C in mats:
                lam = scipy.linalg.eig(A, C, right=True)[0]
                dense.append(lam[np.argmax(lam.real)])
            t_eig = min(t_eig, time.perf_counter() - t)
    with threadpool_limits(limits=os.cpu_count(), user_api="blas"):
        perm = node_major(model)  # banded order, as a sparse LU would want it
        t = time.perf_counter()
        errors = []
        for (A, C), ref in zip(mats, dense):
            As = scipy.sparse.csc_matrix(A[np.ix_(perm, perm)])
            Cs = scipy.sparse.csc_matrix(C[np.ix_(perm, perm)])
            shift = ref.real + 0.01 * abs(
                ref
            )  # an oracle, real (scipy's real-matrix path ignores complex shifts)
            lam = scipy.sparse.linalg.eigs(
                As, k=6, M=Cs, sigma=shift, which="LM", return_eigenvectors=False
            )
            best = lam[np.argmax(lam.real)]
            errors.append(abs(best - ref) / max(abs(ref), 1.0))
        t_arpack = time.perf_counter() - t
    return t_eig, t_arpack, np.asarray(errors)


def import_seconds(repeats: int = 3) -> float:
    """Best wall time of importing the ``axojax sweep`` command's modules in a fresh process."""
    code = (
        "import time; t = time.perf_counter(); import axojax.cli.main, axojax.cli.sweep; "
        "print(time.perf_counter() - t)"
    )
    return min(
        float(
            subprocess.run(
                [sys.executable, "-c", code], check=True, capture_output=True, text=True
            ).stdout
        )
        for _ in range(repeats)
    )


def compile_seconds(model) -> tuple[float, float]:
    """(wall, CPU) seconds to trace, lower and compile the sweep's evaluator of a
    256-point chunk over (p, ks) with the default solver, as ``axojax sweep`` does."""
    from axojax.sweeps import engine

    solver = ax.eigen.DEFAULT_SOLVER.resolve(model, 400)
    f = engine._compiled(model, ("p", "ks"), True, ax.Units(), jax.local_device_count(), solver)
    args = (ax.Params().validate().broadcast(()), jax.numpy.asarray(1e-3), jax.numpy.ones((256, 2)))
    t, c = time.perf_counter(), time.process_time()
    f.lower(*args).compile() if hasattr(f, "lower") else f(*args)
    return time.perf_counter() - t, time.process_time() - c


def per_point(model, solver, n_points: int, repeats: int = 3) -> float:
    rng = np.random.default_rng(0)
    ks = 10 ** rng.uniform(3, 6, n_points)
    params = ax.Params().replace(p=rng.uniform(250, 700, n_points), ks=ks, kl=ks / 1000).broadcast()
    f = jax.jit(jax.vmap(lambda q: ax.eigen.mode._dominant_mode_impl(model, q, solver).eigenvalue))
    jax.block_until_ready(f(params))
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(f(params))
        best = min(best, time.perf_counter() - t)
    return best / n_points


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--p", default="100:900:20")
    ap.add_argument("--ks", default="log:1e2:1e7:20")
    ap.add_argument("--model", default="seven")
    ap.add_argument("--skip-scaling", action="store_true")
    ap.add_argument("--large", type=int, default=80, help="also time a LARGE x LARGE map (0: skip)")
    args = ap.parse_args()
    p, ks = parse_axis(args.p, "--p"), parse_axis(args.ks, "--ks")
    n = p.size * ks.size
    model = ax.models.preset(args.model)
    print(f"load average (1, 5, 15 min) at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")

    t_ax, doc = whole_command(args, args.p, args.ks)  # compiles everything
    with tempfile.TemporaryDirectory() as cache:
        whole_command(args, args.p, args.ks, cache)  # fills the cache
        t_warm, _ = whole_command(args, args.p, args.ks, cache)
    t_eig, t_arpack, err = scipy_loops(model, p, ks)
    print(
        f"1. model {args.model} ({model.n_dof} dof), {n} points, {os.cpu_count()} cores, "
        f"device {jax.devices()[0].device_kind}"
    )
    solver = doc.get("solver", {})
    print(
        f"axojax sweep command (incl. start-up, compile; solver {solver.get('name')}, "
        f"{solver.get('dense_fallbacks')} dense fallbacks):"
        f" {t_ax:8.2f} s {n / t_ax:8.2f} points/s"
    )
    print(
        "scipy.linalg.eig loop (matrices prebuilt; faster of all cores and one thread): "
        f"{t_eig:8.2f} s {n / t_eig:8.2f} points/s"
    )
    print(
        "scipy ARPACK shift-invert loop (shift 1 % from the answer; equals eig to 1e-6 at "
        f"{np.sum(err < 1e-6)} of {n} points): {t_arpack:8.2f} s {n / t_arpack:8.2f} points/s"
    )
    print(
        "the same command again, compiled programs loaded from its cache (axojax/cache.py): "
        f"{t_warm:8.2f} s {n / t_warm:8.2f} points/s"
    )
    print(
        f"ratio axojax / scipy eig:    {t_eig / t_ax:8.2f}x (with the cache: {t_eig / t_warm:.2f}x)"
    )
    print(f"ratio axojax / scipy ARPACK: {t_arpack / t_ax:8.2f}x")
    if args.large:
        k = args.large
        t_big, doc = whole_command(args, f"100:900:{k}", f"log:1e2:1e7:{k}")
        print(
            f"a larger map, where compilation and start-up matter less: {k} x {k} = {k * k} "
            f"points, whole command {t_big:.2f} s"
            f" ({k * k / t_big:.2f} points/s, {doc['solver']['dense_fallbacks']} dense fallbacks):"
            f" {k * k / t_big / (n / t_eig):.2f}x the scipy eig loop's rate, "
            f"{k * k / t_big / (n / t_arpack):.2f}x ARPACK's"
        )
    if not args.skip_scaling:
        print(
            "\n2. time per point of the dominant eigenpair (vmapped, compile excluded; "
            "per-point path 16 points, batched 64, dense 4)"
        )
        sizes = (10, 20, 40, 80)
        rows = {"arnoldi": [], "arnoldi batched": [], "dense": []}

        def fmt(x):
            return "        -" if np.isnan(x) else f"{x * 1e3:9.2f} ms"

        for ne in sizes:
            m = ax.models.preset(args.model, n_elements=ne)
            rows["arnoldi"].append(per_point(m, Arnoldi(batched=False), 16))
            rows["arnoldi batched"].append(
                per_point(m, Arnoldi(batched=True), 64, repeats=2) if ne <= 40 else np.nan
            )
            rows["dense"].append(per_point(m, Dense(), 4, repeats=1) if ne <= 40 else np.nan)
            print(
                f"N_e = {ne:3d} ({m.n_dof:5d} dof): arnoldi {fmt(rows['arnoldi'][-1])}   "
                f"arnoldi batched {fmt(rows['arnoldi batched'][-1])}"
                f"   dense {fmt(rows['dense'][-1])}",
                flush=True,
            )
        for name, t in rows.items():
            ok = ~np.isnan(t)
            slope = np.polyfit(np.log(np.asarray(sizes)[ok]), np.log(np.asarray(t)[ok]), 1)[0]
            print(
                f"fitted growth exponent, {name} (N_e = "
                f"{', '.join(str(s) for s, k in zip(sizes, ok) if k)}): {slope:5.2f}"
            )
        if model.n_elements == 10:
            t10 = rows["arnoldi"][0]
            print(
                f"per point at N_e = 10, compile excluded: {t_eig / n / t10:.1f}x the scipy "
                f"eig loop (target 60x), {t_arpack / n / t10:.1f}x ARPACK's best case (target "
                "8x);"
                f" batched path {t_eig / n / rows['arnoldi batched'][0]:.1f}x"
            )

    print("\n3. cold start")
    t_imp = import_seconds()
    wall, cpu = compile_seconds(model)
    print(f"import of the sweep command (fresh process, best of 3): {t_imp:.2f} s (target 0.8 s)")
    print(
        f"compilation of the 256-point chunk evaluator: {wall:.2f} s wall, {cpu:.2f} s CPU (target 1.5 s)"
    )
    print(f"load average at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
