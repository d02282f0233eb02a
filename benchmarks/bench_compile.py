"""Compilation against run time under XLA's two CPU fusion emitters (issue 22, cold start).

axojax sets ``--xla_cpu_use_fusion_emitters=false`` at import on jaxlib 0.10
(``axojax/_runtime.py``, item 4). This runs the same programs in fresh processes with and
without it, alternating (``AXOJAX_KEEP_XLA_FLAGS=1`` plus the flag or not, so nothing else
differs), and prints compilation CPU time and run time per point, and their ratios, for:
the 64-point seven-filament (N_e = 10) Arnoldi value program, its reverse-mode gradient in
(p, ks), and the dense solver's. Run: ``python benchmarks/bench_compile.py [--repeats 3]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CHILD = r"""
import json, time
import jax, jax.numpy as jnp
jax.config.update("jax_enable_x64", True)
import axojax as ax
from axojax.eigen import Arnoldi, Dense
model = ax.models.seven(n_elements=10)
P = jnp.linspace(200.0, 800.0, 64); KS = jnp.full(64, 2e5)
out = {"xla_flags": __import__("os").environ.get("XLA_FLAGS", "")}
for name, solver in (("arnoldi", Arnoldi()), ("dense", Dense())):
    f = lambda p, ks: ax.dominant_mode(model, ax.Params(p=p, ks=ks), solver=solver).eigenvalue
    grad = jax.grad(lambda p, ks: f(p, ks).real, argnums=(0, 1))
    for kind, fn in (("value", jax.vmap(f)), ("gradient", jax.vmap(grad))):
        lowered = jax.jit(fn).lower(P, KS)
        t0 = time.process_time(); compiled = lowered.compile(); t1 = time.process_time()
        jax.block_until_ready(compiled(P, KS))
        t2 = time.perf_counter()
        for _ in range(3):
            res = jax.block_until_ready(compiled(P, KS))
        t3 = time.perf_counter()
        first = res[0] if isinstance(res, tuple) else res
        out[f"{name} {kind}"] = {"compile_s": t1 - t0, "ms_per_point": (t3 - t2) / 3 / 64 * 1e3,
                                  "checksum": float(jnp.sum(jnp.abs(jnp.asarray(first))))}
print(json.dumps(out))
"""


def run(emitters_off: bool) -> dict:
    env = {
        **os.environ,
        "AXOJAX_KEEP_XLA_FLAGS": "1",
        "XLA_FLAGS": "--xla_cpu_multi_thread_eigen=false"
        + (" --xla_cpu_use_fusion_emitters=false" if emitters_off else ""),
    }
    done = subprocess.run(
        [sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, timeout=900
    )
    if done.returncode != 0:
        raise SystemExit(done.stderr[-2000:])
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    runs = {False: [], True: []}
    for _ in range(args.repeats):
        for off in (False, True):
            runs[off].append(run(off))
    keys = [k for k in runs[False][0] if k != "xla_flags"]
    print(f"{args.repeats} alternating fresh processes each; median; load {os.getloadavg()[0]:.1f}")
    print(
        f"{'program':18s} {'compile s (new -> old emitters)':>32s} {'ratio':>6s} "
        f"{'ms/point (new -> old)':>24s} {'ratio':>6s}  same result"
    )
    for k in keys:
        c = [statistics.median(r[k]["compile_s"] for r in runs[off]) for off in (False, True)]
        t = [statistics.median(r[k]["ms_per_point"] for r in runs[off]) for off in (False, True)]
        same = abs(runs[False][0][k]["checksum"] / runs[True][0][k]["checksum"] - 1) < 1e-10
        print(
            f"{k:18s} {c[0]:15.2f} -> {c[1]:6.2f} {c[0] / c[1]:14.2f}x {t[0]:13.2f} -> "
            f"{t[1]:6.2f} {t[0] / t[1]:7.2f}x  {same}"
        )


if __name__ == "__main__":
    main()
