"""Sweep throughput: the whole ``axojax sweep`` command (start-up and compilation
included) against a plain loop of ``scipy.linalg.eig`` over the same matrices.

Prints, measured in one run: points/s of each and their ratio (axojax / scipy).
Seven-filament model, 10 elements (280 unknowns).

    python benchmarks/bench_sweep.py [--p 100:900:20] [--ks log:1e2:1e7:10]
"""

import axojax as ax  # first: it sets the XLA flags before jax starts
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy.linalg
from threadpoolctl import threadpool_limits

from axojax.cli.common import parse_axis


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--p", default="100:900:20")
    ap.add_argument("--ks", default="log:1e2:1e7:10")
    ap.add_argument("--model", default="seven")
    args = ap.parse_args()
    p, ks = parse_axis(args.p, "--p"), parse_axis(args.ks, "--ks")
    n = p.size * ks.size

    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "axojax.cli.main", "sweep", "--model", args.model, "--p", args.p, "--ks", args.ks, "--kl-ratio", "1000", "--out", os.path.join(tmp, "s.npz"), "--json"]
        t = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        t_ax = time.perf_counter() - t

    model = ax.models.preset(args.model)
    mats = []
    for pv in p:
        for kv in ks:
            s = ax.assemble(model, ax.Params(p=pv, ks=kv, kl=kv / 1000))
            mats.append((-np.asarray(s.A), np.asarray(s.C)))
    # importing axojax gave scipy's BLAS one thread (axojax/_runtime.py); the reference
    # loop gets every core back, as a plain scipy script would have them
    with threadpool_limits(limits=os.cpu_count(), user_api="blas"):
        t = time.perf_counter()
        for A, C in mats:
            lam, vec = scipy.linalg.eig(A, C)
            vec[:, np.argmax(lam.real)]
        t_sp = time.perf_counter() - t

    print(f"model {args.model} ({model.n_dof} dof), {n} points, {os.cpu_count()} cores")
    print(f"axojax sweep command (incl. start-up, compile):       {t_ax:8.2f} s  {n / t_ax:8.2f} points/s")
    print(f"scipy.linalg.eig loop (matrices prebuilt, all cores): {t_sp:8.2f} s  {n / t_sp:8.2f} points/s")
    print(f"ratio (axojax throughput / scipy throughput):         {t_sp / t_ax:8.2f}x")


if __name__ == "__main__":
    main()
