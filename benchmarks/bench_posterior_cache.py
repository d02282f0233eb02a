"""A second identical posterior run against the first: the persistent compilation cache
and the posterior's warm-state cache (issue 31's target: the second starts at least 3x
faster).

Runs the same ``axojax fit ... --posterior`` command twice, each in a fresh process
(``python -m axojax.cli.main``, which keeps compiled programs in ``AXOJAX_CACHE_DIR``:
:mod:`axojax.cache`), with a new, empty cache directory for the pair, and prints for
each run its wall time, the posterior's compilation seconds (``seconds_compile``: the
programs' ``compile()`` calls, which load from the cache in the second run) and the wall
time up to the first draw (the whole run less the draws' sampling), then the ratios
first / second measured in this one run. The default command is a short posterior (2
chains x 20 draws, 150 warm-up steps) of p and ks of the seven-filament model (10
elements, kl = ks / 1000) from a frequency and a wavelength; the draws are short on
purpose, so that start-up dominates, as it does when a user iterates.

    python benchmarks/bench_posterior_cache.py [--draws 20] [--chains 2] [-- EXTRA FIT ARGS]

With the posterior's warm-state cache (:mod:`axojax.inverse.sampling._warm_cache`, kept in the same
directory's ``posterior/``), the second run loads the first's start-up (posterior mode,
Laplace approximation, warm-up state) and goes straight to its draws. "Start" below is
the wall time up to the first draw: the whole run less the draws' sampling, the
compilation of the draws' program counted in it (``seconds_compile_draws``).

Result (2026-12-04 13:58-14:05 UTC, jax 0.10.2, 2 cores shared with other jobs: load
average 4.2 at start, 4.4 at end; default command): first run 242.2 s whole, start 197.4
s (posterior mode and Laplace 8.8 s, warm-up 121.0 s, the draws' compilation 13.5 s);
second 85.5 s whole, start 43.4 s (warm-state cache loaded in 0.1 s, warm-up 0 s: never
traced; the draws' program traced, lowered and loaded 26.4 s); sampling 58.3 and 68.5 s
(the draws' compilation included); the two runs' summaries identical. **Start 4.55x
faster (target 3x: met), the whole command 2.83x.** What the second run still spends:
Python's import and the least-squares fit (about 17 s together) and the draws' tracing
and lowering (jax's persistent cache is keyed by the lowered program, so the tracing
cannot be skipped through it; 26.4 s against 13.5 s in the first run, probably because
there the warm-up had traced the model's functions already: not measured).

Before the warm-state cache (2026-12-03 17:46-18:14 UTC, load 7.7 -> 5.0): first run
1155.9 s, second 508.0 s: posterior compilation 4.3x faster (290.8 -> 67.7 s), the whole
command 2.28x, start 1060.7 -> 466.6 s (2.27x).
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
TRUTH = {"p": 300.0, "ks": 1e6}


def synthetic() -> list[str]:
    """The fit arguments of the synthetic problem: the frequency and wavelength of the
    truth (computed here, default units), the fit started at p 280, ks 8e5."""
    import axojax as ax

    mode = ax.dominant_mode(ax.models.seven(n_elements=10), ax.Params().with_values(TRUTH, 1000.0))
    f, lam = float(mode.frequency_hz()), float(mode.wavelength_um())
    return [
        "--model",
        "seven",
        "--free",
        "p,ks",
        "--kl-ratio",
        "1000",
        "--p",
        "280",
        "--ks",
        "8e5",
        "--target-frequency",
        f"{f:.6g}",
        "--target-wavelength",
        f"{lam:.6g}",
    ]


def run(argv: list[str], cache: pathlib.Path) -> tuple[float, dict]:
    env = {**os.environ, "AXOJAX_CACHE_DIR": str(cache), "PYTHONPATH": str(ROOT)}
    env.pop("AXOJAX_PROGRESS", None)
    t0 = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "axojax.cli.main", *argv],
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.perf_counter() - t0
    if done.returncode not in (0, 1):
        sys.exit(f"the command failed ({done.returncode}):\n{done.stderr}")
    return wall, json.loads(done.stdout)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--draws", type=int, default=20)
    ap.add_argument("--chains", type=int, default=2)
    ap.add_argument("extra", nargs="*", help="fit arguments instead of the synthetic problem")
    args = ap.parse_args()
    problem = args.extra or synthetic()
    argv = ["fit", "--no-mesh-check", *problem, "--posterior", str(args.draws), "--sampler", "nuts"]
    argv += ["--chains", str(args.chains), "--json"]
    print(f"{os.cpu_count()} cores, load average at start {os.getloadavg()}")
    print("axojax " + " ".join(argv))
    with tempfile.TemporaryDirectory() as tmp:
        cache = pathlib.Path(tmp) / "cache"
        rows, docs = [], []
        for label in ("first (empty cache)", "second (same command)"):
            wall, doc = run(argv, cache)
            post = doc["posterior"]
            start = wall - post["seconds_sampling"] + post["seconds_compile_draws"]
            rows.append((wall, post["seconds_compile"], start))
            docs.append(doc)
            print(
                f"{label:22s} whole run {wall:7.1f} s; start (up to the first draw) {start:6.1f} s "
                f"(posterior start-up {post['seconds_start']:.1f} s, warm-up {post['seconds_warmup']:.1f} s, "
                f"warm-state cache {post.get('warm_cache')}); "
                f"posterior compilation {post['seconds_compile']:6.1f} s; sampling {post['seconds_sampling']:.1f} s "
                f"(its compilation {post['seconds_compile_draws']:.1f} s)"
            )
        files = sum(1 for _ in cache.rglob("*") if _.is_file())
        size = sum(f.stat().st_size for f in cache.rglob("*") if f.is_file()) / 1e6
    (w1, c1, s1), (w2, c2, s2) = rows
    p1, p2 = docs[0]["posterior"], docs[1]["posterior"]
    same = all(p1[key] == p2[key] for key in ("mean", "sd", "q05", "q95"))
    print(f"cache: {files} files, {size:.1f} MB; the two runs' summaries identical: {same}")
    print(
        f"first / second: start (up to the first draw) {s1 / s2:.2f}x, whole run {w1 / w2:.2f}x, "
        f"posterior compilation {c1 / max(c2, 1e-9):.1f}x (target: the second starts >= 3x faster)"
    )
    print(f"load average at end {os.getloadavg()}")


if __name__ == "__main__":
    main()
