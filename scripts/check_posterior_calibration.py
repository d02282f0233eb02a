"""Simulation-based calibration of ``axojax.inverse.posterior`` (issue 31: "the synthetic
posterior's 90 % intervals contain the truth").

One synthetic problem says little about coverage: whether the truth falls inside a 90 %
interval depends on where on the ridge the truth and the noise put it (tests/
test_posterior_laplace.py's truth lies near the ridge's end, outside its converged
posterior's marginal intervals). What a correct posterior guarantees is coverage on
average over truths drawn from its prior (Talts et al., "Validating Bayesian inference
algorithms with simulation-based calibration", 2018): for each of ``--truths`` truths
drawn from the prior, frequency and wavelength are made with Gaussian noise of fixed sd
(the likelihood's), the posterior is sampled exactly as ``axojax fit --posterior`` does
(multi-start least squares, transport along the ridge it suggests, NUTS), and the
script prints, per parameter, the share of truths inside the 90 % interval (expected
0.9, binomial sd sqrt(0.09 / n)) and the truth's rank among the draws (uniform on [0, 1]
for a calibrated posterior: a Kolmogorov-Smirnov p-value).

Model: seven filaments, 4 elements, kl = ks / 1000 (the slow test's); prior uniform in
log p and log ks on [100, 500] x [1e3, 1e6] restricted to where the dominant mode
oscillates (the likelihood of an oscillating beat vanishes elsewhere, so the box
prior's posterior is the restricted one's; truths are drawn by rejection); noise sd 1.5 Hz
and 1.2 um (2 % and 5 % of the slow test's truth).

Measured 2026-12-05 (2579 s on 2 cores, partly shared; ``--truths 16``, the defaults
otherwise): p and ks each inside the 90 % interval for **14 of 16** truths (0.88; expected
0.90 +- 0.07), ranks' KS p-values 0.67 and 0.69. The two misses: one at rank 0.98 (as
often as a calibrated posterior misses), and one at rank 0.00 (truth p 251, ks 9.2e3),
whose fit found two exact solutions, p 255, ks 1.4e4 and p 332, ks 4.5e5: the chains
sampled around the second only (R-hat 1.11 warned). That posterior is not two modes but
one hairpin valley (a grid of its loss, 241 x 121 points in log p, log ks): an arm at
p 255-300 rising from ks 8e3, another at p 320-350 from ks 3e4 to 1e6, the two joined
near ks 2.5e5 within 3 of the smallest loss and apart below it by a ridge 10-30 high
(at ks 2.2e4: 1.8 at p 256, 26 at p 292, 1.0 at p 323); 35 % of its mass lies at ks <
1e5. A profile map gives one value of the other coordinate per knot, so it cannot follow
both arms. Chains started two at each optimum (4 x 200, the suggested transport along
ks) stay in their arms (p 251-289 and 291-379; R-hat 1.78): for NUTS the arms are two
modes, whose masses (35 / 65 %) would have to be estimated, each along its own curved
arm, to weight them; or a sampler that crosses the ridge (tempering). Before the transport was chosen by
importance sampling (axojax/inverse/sampling/transport_choice.py), the first truth (p 279, ks
6.4e3) was missed too: p 215-235, ks 2.3e3-5.0e3.

    python scripts/check_posterior_calibration.py [--truths 20] [--draws 200] [--json FILE]
    python scripts/check_posterior_calibration.py --quadrature 1

``--quadrature I`` integrates the I-th truth's posterior on a grid instead (1601 x 346
points, 0.1 % in p by 2 % in ks; ~15 min on 2 cores) and prints its 90 % intervals:
the reference for the sampler's on that problem.
"""

import argparse
import json
import math
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np

import axojax as ax
from axojax.beats import Target
from axojax.inverse import build_problem, least_squares, posterior, suggest_transport

BOUNDS = {"p": (100.0, 500.0), "ks": (1e3, 1e6)}
SD = {"frequency_hz": 1.5, "wavelength_um": 1.2}
KL_RATIO = 1000.0


def observables(model, values: dict) -> tuple[float, float]:
    mode = ax.dominant_mode(model, ax.Params().with_values(values, KL_RATIO))
    return float(mode.frequency_hz()), float(mode.wavelength_um())


def draw_truth(model, rng) -> tuple[dict, float, float]:
    """A truth from the prior (log-uniform box) where the dominant mode oscillates."""
    while True:
        values = {n: float(np.exp(rng.uniform(*np.log(b)))) for n, b in BOUNDS.items()}
        f, lam = observables(model, values)
        if f > 0 and math.isfinite(lam):
            return values, f, lam


def synthetic_problem(model, f: float, lam: float, rng):
    """The problem of one truth's noisy frequency and wavelength (two normal draws)."""
    targets = [
        Target("frequency_hz", f + SD["frequency_hz"] * rng.normal(), SD["frequency_hz"]),
        Target("wavelength_um", lam + SD["wavelength_um"] * rng.normal(), SD["wavelength_um"]),
    ]
    start = ax.Params().with_values({"p": 250.0, "ks": 3e4}, KL_RATIO)
    return build_problem(model, start, targets, ["p", "ks"], bounds=BOUNDS, kl_ratio=KL_RATIO)


def quadrature(problem, truth: dict) -> None:
    """The posterior's 90 % intervals by a grid in (log p, log ks) (uniform prior)."""
    lp = np.linspace(*np.log(BOUNDS["p"]), 1601)
    lk = np.linspace(*np.log(BOUNDS["ks"]), 346)
    loss = jax.jit(jax.vmap(problem.loss))
    grid = np.stack(
        [np.asarray(loss(jnp.stack([jnp.full(lk.size, x), jnp.asarray(lk)], 1))) for x in lp]
    )
    w = np.exp(-np.where(np.isfinite(grid), grid, np.inf))
    print(
        f"log mass (integral of exp(-loss) over log p, log ks): "
        f"{np.log(w.sum() * (lp[1] - lp[0]) * (lk[1] - lk[0])):.3f}"
    )
    for name, axis, x in (("p", 1, lp), ("ks", 0, lk)):
        cdf = np.cumsum(w.sum(axis)) / w.sum()
        q05, q50, q95 = np.exp(np.interp([0.05, 0.5, 0.95], cdf, x))
        print(f"{name}: 5/50/95 % {q05:.4g} / {q50:.4g} / {q95:.4g} (truth {truth[name]:.4g})")


def trial(model, rng) -> tuple[dict, float, float, object, int, int]:
    """Everything random about one truth, drawn from ``rng`` in the run's order: the
    truth (with its frequency and wavelength), its noisy problem, the fit's seed and the
    posterior's seed (so that ``--quadrature I`` meets the I-th truth's exact data)."""
    truth, f, lam = draw_truth(model, rng)
    problem = synthetic_problem(model, f, lam, rng)
    return truth, f, lam, problem, int(rng.integers(1 << 30)), int(rng.integers(1 << 30))


def one(truth: dict, problem, fit_seed: int, seed: int, args) -> dict:
    fit = least_squares(problem, starts=args.starts, seed=fit_seed)
    transport = suggest_transport(problem, fit)
    sampling = {"draws": args.draws, "chains": args.chains, "warmup": args.warmup, "seed": seed}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # short runs: R-hat and ESS warnings
        post = posterior(problem, init=fit, transport=transport, **sampling)
    record = {"truth": truth, "transport": None if transport is None else transport.along}
    for j, n in enumerate(post.names):
        draws = np.asarray(post.values[..., j]).ravel()
        record[n] = {
            "q05": float(post.q05[n]),
            "q95": float(post.q95[n]),
            "inside": bool(post.q05[n] <= truth[n] <= post.q95[n]),
            "rank": float(np.mean(draws < truth[n])),
            "rhat": float(post.rhat[n]),
        }
    return record


def ks_pvalue(x: np.ndarray) -> float:
    """Two-sided Kolmogorov-Smirnov p-value of x against uniform [0, 1] (asymptotic)."""
    x = np.sort(x)
    n = len(x)
    i = np.arange(1, n + 1)
    d = max(np.max(i / n - x), np.max(x - (i - 1) / n))
    t = (math.sqrt(n) + 0.12 + 0.11 / math.sqrt(n)) * d
    return float(
        min(1.0, 2 * sum((-1) ** (k - 1) * math.exp(-2 * k * k * t * t) for k in range(1, 101)))
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--truths", type=int, default=20)
    ap.add_argument("--draws", type=int, default=200, help="draws per chain")
    ap.add_argument("--chains", type=int, default=2)
    ap.add_argument("--warmup", type=int, default=150)
    ap.add_argument("--starts", type=int, default=6, help="least-squares starts per truth")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", help="write the per-truth records here")
    ap.add_argument("--quadrature", type=int, help="integrate this truth's posterior on a grid")
    args = ap.parse_args()
    model = ax.models.seven(n_elements=4)
    rng = np.random.default_rng(args.seed)
    if args.quadrature:
        for _ in range(args.quadrature):
            truth, _, _, problem, _, _ = trial(model, rng)
        quadrature(problem, truth)
        return
    records = []
    t0 = time.perf_counter()
    for i in range(args.truths):
        truth, f, lam, problem, fit_seed, seed = trial(model, rng)
        rec = one(truth, problem, fit_seed, seed, args)
        records.append(rec)
        print(
            f"[{i + 1}/{args.truths}, {time.perf_counter() - t0:.0f} s] truth p {truth['p']:.1f}"
            f" ks {truth['ks']:.3g} ({f:.1f} Hz, {lam:.1f} um): "
            + "; ".join(
                f"{n} 90 % {rec[n]['q05']:.4g}-{rec[n]['q95']:.4g} "
                f"{'in' if rec[n]['inside'] else 'OUT'} rank {rec[n]['rank']:.2f} "
                f"R-hat {rec[n]['rhat']:.3f}"
                for n in BOUNDS
            ),
            flush=True,
        )
    n = len(records)
    print(
        f"\n{n} truths, {args.chains} x {args.draws} draws each, {time.perf_counter() - t0:.0f} s"
    )
    for name in BOUNDS:
        inside = sum(r[name]["inside"] for r in records)
        ranks = np.array([r[name]["rank"] for r in records])
        print(
            f"{name}: truth inside the 90 % interval {inside}/{n} = {inside / n:.2f} "
            f"(expected 0.90 +- {math.sqrt(0.09 / n):.2f}); ranks' KS p-value vs uniform "
            f"{ks_pvalue(ranks):.2f}"
        )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"args": vars(args), "records": records}, fh, indent=1)


if __name__ == "__main__":
    jax.config.update("jax_enable_x64", True)
    main()
