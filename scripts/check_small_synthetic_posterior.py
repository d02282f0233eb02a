"""The converged posterior of tests/sampling/test_laplace.py's small synthetic problem
(p and ks of the seven-filament model at 4 elements, kl = ks / 1000, a frequency and a
wavelength made at p 300, ks 1e6 with 2 % and 5 % noise, rng seed 1), to show where its
mass lies: 4 chains x 1000 draws along ks (what ``axojax fit --posterior`` picks).

Measured 2026-12-05 (173 s on 2 cores): p 159.6-280.7, ks 1.8e3-7.1e5 (90 %), R-hat
1.001-1.002, ESS ~2300: the truth lies outside both marginal intervals (the targets fit
the whole ridge up to the cliff near ks 2.5e6, and the prior is uniform in log ks), while
the Laplace intervals at the optimum (p 229-328, ks 2.3e5-1.7e6) contain it. The test
therefore checks that the truth lies in the sampled 90 % highest-density region.

    python scripts/check_small_synthetic_posterior.py [--draws 1000]
"""

import argparse
import pathlib
import sys
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np

from axojax.inverse import posterior, suggest_transport

# the problem is the test's own, defined once there
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
from test_posterior_laplace import SMALL_SYNTHETIC_TRUTH as TRUTH  # noqa: E402
from test_posterior_laplace import small_synthetic_problem  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--draws", type=int, default=1000)
    ap.add_argument("--chains", type=int, default=4)
    args = ap.parse_args()
    problem, fit = small_synthetic_problem()
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(
            problem,
            draws=args.draws,
            chains=args.chains,
            warmup=200,
            seed=0,
            init=fit,
            transport=suggest_transport(problem, fit),
        )
    print(f"{args.chains} x {args.draws} draws in {time.perf_counter() - t0:.0f} s")
    lap = post.laplace.to_json()
    for n, truth in TRUTH.items():
        print(
            f"{n}: 90 % {post.q05[n]:.4g}-{post.q95[n]:.4g} (truth {truth:g}), R-hat "
            f"{post.rhat[n]:.4f}, ESS {post.ess[n]:.0f}; Laplace {lap['q05'][n]:.4g}-{lap['q95'][n]:.4g}"
        )
    loglik = -np.asarray(jax.vmap(problem.loss)(jnp.asarray(post.u.reshape(-1, 2))))
    truth_loglik = -float(problem.loss(jnp.log(jnp.array([TRUTH[n] for n in post.names]))))
    print(
        f"log likelihood at the truth {truth_loglik:.2f}; draws' 10 % quantile "
        f"{np.quantile(loglik, 0.1):.2f} (the truth is in the 90 % HPD region when above it)"
    )


if __name__ == "__main__":
    main()
