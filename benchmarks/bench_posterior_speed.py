"""Issue 31's acceptance runs: 4 chains x 1000 draws of p and ks, each under 5 minutes on
2 cores with R-hat < 1.01 and ESS >= 400 per parameter, on

- ``sperm``: the bundled human sperm beat, the issue's own command
  (``axojax fit --model seven --free p,ks --kl-ratio 1000 --data human_sperm --ei 90.9
  --cn 0.000285 --shape-floor 0.2 --posterior 1000 --chains 4``);
- ``synthetic``: a seven-filament frequency and wavelength (10 elements, the truth p 300,
  ks 1e6, kl = ks / 1000; the command's default sigmas, 5 % of the frequency and 10 % of
  the wavelength; no noise), the same command with
  ``--target-frequency/--target-wavelength`` instead of ``--data``.

Each runs in this process through ``axojax.cli.main.main`` (what a user runs, less the
mesh check: ``--no-mesh-check``), with the CLI's warm-up (DRAWS clipped to 150..500 steps)
unless ``--warmup`` is given. Prints the whole run's wall time and its parts (fit, posterior
start, warm-up, draws, compilation), gradients per draw, tree depth, R-hat, ESS, the
Laplace sd ratio and (synthetic) whether the truth lies in the 90 % intervals.

    python benchmarks/bench_posterior_speed.py [sperm|synthetic ...] [--draws 1000]
        [--chains 4] [--warmup W]

Result (2026-12-04 20:23-20:29 UTC, load 1.0; both commands as the issue gives them, the
command choosing ``--along ks`` from the fit and taking 16 starts): ``sperm`` **156.2 s**
(fit 24.1 s, warm-up 46.4 s, draws 77.6 s, 40.4 s compilation; 5.7 gradients per draw,
3.19 ms per gradient; R-hat 1.0014/1.0015, ESS 1848/1810, 7 divergences) at the global
optimum p 1034, ks 4.99e7 (loss 181.8); ``synthetic`` **152.0 s** (4.7 gradients per
draw, 4.04 ms per gradient; R-hat 1.0019/1.0029, ESS 2441/2209, 40 divergences). The
sperm results below, before, sampled a local mode (loss 225.0 at p 405, ks 2.9e4: the fit's
4 starts missed the best; docs/benchmarks.md).

Result (2026-12-04 17:30-17:34 UTC, load 0.9-1.2): ``synthetic`` as the command runs by
default now (``--along ks``: sequential chains on a CPU, 200 warm-up steps) **215.6 s**
(target 300 s): fit 24.1 s, start 5.6 s, warm-up 57.4 s, draws 123.5 s, compilation 45.5
s, 5.11 ms per gradient; the same draws as the run below (R-hat, ESS and quantiles
identical). The divergence warning names the profile's end: ks ~ 2.3e6.

Result (2026-12-04 16:36-16:40 UTC, load 0.1-1.1): ``synthetic --draws 1000 --warmup 200
--chains-as sequential`` (the command with ``--along ks``, overrides emulating those
defaults) **221.8 s** (target 300 s): fit 24.0 s, posterior start 5.8 s, warm-up 64.5 s
(200 steps), draws 123.2 s, 49.8 s compilation in all; 5.6 gradients per draw, mean tree
depth 2.55, no saturation, 5.22 ms per gradient; **R-hat 1.0004 (p) and 1.0007 (ks), bulk
ESS 2394 and 2313**; 111 divergences (0.03 of the transitions: the density's cliff at
the ridge's end, ks ~ 4e6, where another eigenmode becomes the dominant one). The same
with 500 warm-up steps and vmapped chains (16:25-16:31): 361.8 s, R-hat 1.0003/1.0005,
ESS 2736/2495, 8.83 ms per gradient (every vmapped step pays the longest of the four
trees). The 90 % intervals, p 148-282 and ks 31-7.1e5, do not contain the truth (300,
1e6): this posterior puts most of its mass down the ridge, towards small ks, where the
frequency and wavelength fit as well (the quadrature of
``scripts/check_synthetic_posterior.py`` gives the same quantiles). The small noisy
run of ``tests/sampling/test_laplace.py`` shows the same at 4 elements (converged: p
160-281, ks 1.8e3-7.1e5, truth outside); it checks that the truth lies in the sampled
90 % highest-density region, as it does. A second,
separate mode (p ~ 280, ks < 1e3: another eigenmode matching the targets; about 13 % of
the mass on a plain grid) is not visited by chains started on the ridge: the quantiles
are those of the ridge's mode.

Result (2026-12-04 16:50-16:54 UTC, load 2.2 -> 1.2): ``sperm --draws 1000 --chains-as
sequential`` (as the CLI now runs the chains on a CPU) **205.4 s**: fit 33.0 s, warm-up
77.2 s (500 steps), draws 84.9 s, 37.9 s compilation; 4.7 gradients per draw, 4.26 ms per
gradient; R-hat 1.0026 and 1.0015, ESS 1246 and 1070.

Result (2026-12-04 14:37-14:42 UTC, load 0.8-1.2): ``sperm --draws 1000`` (vmapped) **245.5 s**
(target 300 s): fit 21.6 s, warm-up 104.7 s (500 steps), draws 113.0 s, 32.3 s
compilation; 4.7 gradients per draw, 6.1 ms per gradient; R-hat 1.003 and 1.002, ESS 1305
and 1073 (the command's exit status is 1: its fit misses the shape, not the posterior).
With the previous default warm-up (1000 steps; load 2-3): 378.4 s.

Earlier result, before ``--along`` (2026-12-03 17:41-18:12 UTC, jax 0.10.2, 2 cores shared with three to four other
jobs: load average 7-10 throughout, about 6x the quiet machine's time per gradient):
**the acceptance runs were not made**; the one run made, ``synthetic --draws 100
--warmup 150 --chains-as sequential``, took 1841 s: the fit 165 s (the first start's
compilation 91 s), the posterior 1677 s = start 37 s + warm-up 1149 s + draws 478 s,
137.8 s of it compilation; 25.2 gradients per draw, mean tree depth 3.87 (limit 8,
reached in 3.8 % of draws), 44.7 ms per gradient (7.6 ms on a quieter machine:
bench_gradients.py). The posterior of p and ks from a frequency and a wavelength alone
(5 % and 10 % sigmas) is a long curved ridge: the draws went from the fit's optimum (the truth,
300 and 1e6, recovered exactly) down the ridge to p ~ 190 and ks ~ 8e4 (ks's 90 %
interval 30 to 4.4e5), the chains disagreed (R-hat 1.66 and 1.61, bulk ESS 7) and the
posterior sd of ks was 3.2x its Laplace sd. So on this target the chains need far more
than 100 draws, and the truth lay outside the 90 % intervals of this unconverged run.
Projection for 4 x 1000 draws after 1000 warm-up steps at 25 gradients per draw and
7.6 ms per gradient on a quiet machine: 8000 x 25 x 7.6 ms = 25 min, 5x the target.
A vmapped run of the same (the CLI's default) was stopped after 26 min without output.
"""

import argparse
import contextlib
import io
import json
import os
import pathlib
import sys
import tempfile
import time

import axojax as ax  # first: it sets the XLA flags before jax starts
from axojax.cli.fit import posterior as cli_fit
from axojax.cli.main import main as cli_main

TRUTH = {"p": 300.0, "ks": 1e6}
COMMON = ["fit", "--no-mesh-check", "--model", "seven", "--free", "p,ks", "--kl-ratio", "1000"]
COMMON += ["--sampler", "nuts"]  # NUTS's speed (--sampler auto picks modes for two)
SPERM = ["--data", "human_sperm", "--ei", "90.9", "--cn", "0.000285", "--shape-floor", "0.2"]


def synthetic() -> list[str]:
    mode = ax.dominant_mode(ax.models.seven(n_elements=10), ax.Params().with_values(TRUTH, 1000.0))
    f, lam = float(mode.frequency_hz()), float(mode.wavelength_um())
    print(f"synthetic truth {TRUTH}: {f:.4f} Hz, {lam:.4f} um")
    return ["--p", "280", "--ks", "8e5", "--target-frequency", f"{f:.8g}"] + [
        "--target-wavelength",
        f"{lam:.8g}",
    ]


def run(name: str, argv: list[str], warmup: int | None, vectorize: bool | None = None) -> None:
    original = cli_fit.posterior

    def posterior(*a, **k):
        if warmup is not None:
            k["warmup"] = warmup
        if vectorize is not None:
            k["vectorize"] = vectorize
        return original(*a, **k)

    cli_fit.posterior = posterior
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "fit.json"
        t0 = time.perf_counter()
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            rc = cli_main(argv + ["--out", str(out), "--json"])
        wall = time.perf_counter() - t0
        cli_fit.posterior = original
        doc = json.loads(buf.getvalue())
    post = doc["posterior"]
    fit_s = wall - post["seconds"]
    print(
        f"\n== {name} (exit {rc}, chains "
        f"{dict([(None, 'as the CLI runs them'), (True, 'vmapped'), (False, 'sequential')])[vectorize]}): "
        f"axojax {' '.join(argv)}"
    )
    print(
        f"wall {wall:.1f} s (target 300 s): fit {fit_s:.1f} s, posterior {post['seconds']:.1f} s "
        f"= start {post['seconds_start']:.1f} + warm-up {post['seconds_warmup']:.1f} + draws "
        f"{post['seconds_sampling']:.1f} s (+ values), of which compilation {post['seconds_compile']:.1f} s"
    )
    print(
        f"{post['chains']} chains x {post['draws']} draws after {post['warmup']} warm-up steps; "
        f"{post['gradients_per_draw']:.1f} gradients per draw, mean tree depth "
        f"{post['tree_depth']:.2f} (limit {post['max_num_doublings']}, reached in "
        f"{100 * post['tree_depth_saturated']:.1f} %), {post['divergences']} divergences, "
        f"{1e3 * post['seconds_per_gradient']:.2f} ms per gradient; transport along "
        f"{post.get('transport')}"
    )
    print(
        f"{'name':>4} {'fit':>10} {'q05':>10} {'mean':>10} {'q95':>10} {'R-hat':>7} {'ESS':>6} "
        f"{'tail':>6} {'sd/Lap':>7}"
    )
    for n in post["mean"]:
        ratio = post["sd_ratio"].get(n)
        print(
            f"{n:>4} {doc['params'][n]:10.4g} {post['q05'][n]:10.4g} {post['mean'][n]:10.4g} "
            f"{post['q95'][n]:10.4g} {post['rhat'][n]:7.4f} {post['ess'][n]:6.0f} "
            f"{post['ess_tail'][n]:6.0f} {ratio if ratio is None else round(ratio, 3)!s:>7}"
        )
        if name == "synthetic":
            print(
                f"     truth {TRUTH[n]:g} in the 90 % interval: {post['q05'][n] <= TRUTH[n] <= post['q95'][n]}"
            )
    print(f"message: {post['message']}; load average now {os.getloadavg()}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("problems", nargs="*", default=["synthetic", "sperm"])
    ap.add_argument("--draws", type=int, default=1000)
    ap.add_argument("--chains", type=int, default=4)
    ap.add_argument("--warmup", type=int, default=None)
    ap.add_argument(
        "--no-along",
        action="store_true",
        help="sample with --along none (the affine whitening alone; by default the command "
        "chooses the transport from the fit: along ks on both problems)",
    )
    ap.add_argument(
        "--chains-as",
        choices=("default", "vmapped", "sequential"),
        default="default",
        help="override how the chains run (posterior's vectorize)",
    )
    args = ap.parse_args()
    vectorize = {"default": None, "vmapped": True, "sequential": False}[args.chains_as]
    print(f"{os.cpu_count()} cores, load average at start {os.getloadavg()}", flush=True)
    for name in args.problems:
        extra = {"sperm": SPERM, "synthetic": None}[name]
        argv = COMMON + (extra if extra is not None else synthetic())
        argv += ["--posterior", str(args.draws), "--chains", str(args.chains)]
        if args.no_along:
            argv += ["--along", "none"]
        run(name, argv, args.warmup, vectorize)
    sys.stdout.flush()


if __name__ == "__main__":
    main()
