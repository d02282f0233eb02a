"""Simulation-based calibration (Talts et al. 2018) of ``posterior(sampler=ModeMixture())``
on issue 48's problem class (issue 48's calibration item).

The model: seven filaments (``--elements``, default 4), kl = ks / 1000, cl 0.005, free p and
ks. The prior: uniform in (log p, log ks) on a box (``--box``: BOXES; the problem's
bounds, so the sampler's prior is the one the truths are drawn from). Each truth: its dominant
mode's frequency and wavelength; the data are those plus normal noise of fixed sd
(SIGMA_HZ, SIGMA_UM: the likelihood the sampler assumes, the same for every truth). A
truth whose prediction fails (no beating mode) is redrawn: the prior is then conditioned
on a beat, as is the posterior (a failed prediction has zero likelihood).

Per truth: a 4-start least-squares fit (its optima seed the sampler), the posterior
(``--chains`` x ``--draws``), the rank of the truth among ``--thin``-thinned draws per
parameter, whether each 90 % interval (5-95 % quantiles) holds it, the modes with more
than 5 % of the mass, whether a switch line was met, R-hat, ESS, evaluations and wall
time: one JSON line per truth appended to ``--out`` (a rerun resumes). ``--summary``
prints, for every parameter, the coverage of the 90 % intervals with a two-sided
binomial test against 0.90 and a Kolmogorov-Smirnov test of the ranks against the
uniform, for all truths and apart for those near a switch line and those with two
modes. ``--part I/N`` runs every N-th truth from I (two processes on two cores).

    python benchmarks/calibrate_posterior_modes.py --truths 100 --out sbc.jsonl --part 0/2 &
    python benchmarks/calibrate_posterior_modes.py --truths 100 --out sbc.jsonl --part 1/2 &
    python benchmarks/calibrate_posterior_modes.py --out sbc.jsonl --summary
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
import warnings

import numpy as np
import scipy.stats

import axojax as ax
from axojax.beats import Target
from axojax.inverse import ModeMixture, build_problem, least_squares, posterior
from axojax.results import name as result_name

BOXES = {
    "ridge": ((150.0, 600.0), (1e4, 1e6)),
    "wide": ((150.0, 1000.0), (1e4, 5e7)),
}
"""The priors (p, ks boxes): ``ridge`` the beating ridge, ``wide`` beyond the line where a
non-oscillating mode becomes dominant (issue 48's switch line, p 720-910, ks 2e7-4e7)."""
SIGMA_HZ = 3.0
SIGMA_UM = 0.6
KL_RATIO = 1000.0
CL = 0.005


def predictions(model, p: float, ks: float) -> tuple[float, float]:
    """The dominant mode's frequency (Hz) and wavelength (um) at (p, ks)."""
    prm = ax.Params().with_values({"p": p, "ks": ks, "cl": CL}, KL_RATIO)
    mode = ax.dominant_mode(model, prm)
    return float(mode.frequency_hz()), float(mode.wavelength_um())


def one_truth(model, index: int, args) -> dict:
    """Draw truth ``index`` (its own seed), its data, fit, posterior; the record."""
    P_BOX, KS_BOX = BOXES[args.box]
    rng = np.random.default_rng(1000 + index)
    while True:
        p, ks = (float(np.exp(rng.uniform(np.log(a), np.log(b)))) for a, b in (P_BOX, KS_BOX))
        f, lam = predictions(model, p, ks)
        if math.isfinite(f) and math.isfinite(lam) and f > 0 and lam > 0:
            break
    f_obs, lam_obs = f + SIGMA_HZ * rng.normal(), lam + SIGMA_UM * rng.normal()
    targets = [Target("frequency_hz", f_obs, SIGMA_HZ), Target("wavelength_um", lam_obs, SIGMA_UM)]
    start = ax.Params().with_values({"p": 300.0, "ks": 1e5, "cl": CL}, KL_RATIO)
    problem = build_problem(
        model, start, targets, ["p", "ks"], kl_ratio=KL_RATIO, bounds={"p": P_BOX, "ks": KS_BOX}
    )
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = least_squares(problem, starts=4, seed=index)
        t_fit = time.perf_counter() - t0
        post = posterior(
            problem,
            draws=args.draws,
            chains=args.chains,
            seed=index,
            sampler=ModeMixture(particles=args.particles),
            init=fit,
        )
    truth = {"p": p, "ks": ks}
    record = {
        "index": index,
        "truth": truth,
        "data": [f_obs, lam_obs],
        "seconds": time.perf_counter() - t0,
    }
    record["seconds_fit"] = t_fit
    record["seconds_compile"] = post.seconds_compile
    for name, value in truth.items():
        draws = post.value_draws(name)[:, :: args.thin].ravel()
        record[f"rank_{name}"] = int(np.sum(draws < value))
        record[f"inside_{name}"] = bool(post.q05[name] <= value <= post.q95[name])
    record["draws_ranked"] = int(post.value_draws("p")[:, :: args.thin].size)
    record["modes"] = sum(1 for m in post.modes if m["mass"] > 0.05)
    record["switches"] = len(post.switches)
    record["rhat"] = max(post.rhat.values())
    record["ess"] = min(post.ess.values())
    record["evaluations_per_ess"] = post.gradients_per_ess
    record["result"] = result_name(post.result)
    return record


def summary(path: str) -> None:
    rows = [json.loads(line) for line in open(path)]
    rows = list({r["index"]: r for r in rows}.values())
    print(
        f"{len(rows)} truths; median wall {np.median([r['seconds'] for r in rows]):.1f} s per truth"
    )
    print(
        f"R-hat: max {max(r['rhat'] for r in rows):.3f}, share < 1.01: "
        f"{np.mean([r['rhat'] < 1.01 for r in rows]):.2f}; ESS min {min(r['ess'] for r in rows):.0f}; "
        f"evaluations per effective draw: median {np.median([r['evaluations_per_ess'] for r in rows]):.1f}"
    )
    groups = {
        "all": rows,
        "near a switch line": [r for r in rows if r["switches"] > 0],
        "two or more modes (> 5 % each)": [r for r in rows if r["modes"] >= 2],
    }
    for label, group in groups.items():
        if not group:
            print(f"{label}: none")
            continue
        print(f"{label}: {len(group)} truths")
        for name in ("p", "ks"):
            hits = sum(r[f"inside_{name}"] for r in group)
            binom = scipy.stats.binomtest(hits, len(group), 0.9).pvalue
            n_ranked = group[0]["draws_ranked"]
            rng = np.random.default_rng(0)  # ranks made continuous for the KS test
            ranks = np.array([r[f"rank_{name}"] for r in group]) + rng.uniform(size=len(group))
            ks_p = scipy.stats.kstest(ranks / (n_ranked + 1), "uniform").pvalue
            print(
                f"  {name}: 90 % coverage {hits}/{len(group)} = {hits / len(group):.3f} "
                f"(binomial p {binom:.3f}); ranks KS p {ks_p:.3f}"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--truths", type=int, default=100)
    parser.add_argument(
        "--box", choices=sorted(BOXES), default="ridge", help="the prior box (ridge)"
    )
    parser.add_argument("--elements", type=int, default=4)
    parser.add_argument("--draws", type=int, default=500, help="draws per chain (500)")
    parser.add_argument("--chains", type=int, default=4)
    parser.add_argument("--thin", type=int, default=5, help="rank among every THIN-th draw (5)")
    parser.add_argument("--particles", type=int, default=500, help="ModeMixture particles (500)")
    parser.add_argument("--out", default="sbc_modes.jsonl")
    parser.add_argument("--part", default="0/1", help="I/N: every N-th truth from I")
    parser.add_argument("--summary", action="store_true", help="summarise --out and stop")
    args = parser.parse_args()
    if args.summary:
        summary(args.out)
        return
    part, parts = (int(x) for x in args.part.split("/"))
    done = set()
    if os.path.exists(args.out):
        done = {json.loads(line)["index"] for line in open(args.out)}
    model = ax.models.seven(n_elements=args.elements)
    for index in range(part, args.truths, parts):
        if index in done:
            continue
        record = one_truth(model, index, args)
        with open(args.out, "a") as f:
            f.write(json.dumps(record) + "\n")
        print(
            f"{index}: p {record['truth']['p']:.4g} ks {record['truth']['ks']:.4g} inside "
            f"{record['inside_p']}/{record['inside_ks']} modes {record['modes']} switches "
            f"{record['switches']} rhat {record['rhat']:.3f} {record['seconds']:.1f} s",
            flush=True,
        )


if __name__ == "__main__":
    main()
