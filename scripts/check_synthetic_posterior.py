"""The synthetic seven-filament posterior of issue 31 by quadrature, to check the
sampler's quantiles (``benchmarks/bench_posterior_speed.py synthetic``) independently.

The problem is the benchmark's: p and ks (kl = ks / 1000) of the seven-filament model at
10 elements from the frequency and wavelength of its dominant mode at p 300, ks 1e6 with
the command line's default sigmas (5 % of the frequency, 10 % of the wavelength), no
noise, uniform priors in log p and log ks within the default bounds, the solver
``axojax fit --posterior`` uses. The posterior is a ridge p(ks); the quadrature
runs in the coordinates ``(z_ks, b)`` of the profile map (``z_p = c(z_ks) + L(z_ks) b``,
Jacobian ``L(z_ks)``: any smooth coordinates give the same integral), on a grid of
``--along`` x ``--across`` points over the knots' range and ``|b| <= 6``. It prints the
5/50/95 % quantiles of p and ks, and the mass of the separate mode at p ~ 280, ks < 1e3
(a different eigenmode matching the targets; NUTS started on the ridge does not visit
it) from a plain grid in (log p, log ks).

    python scripts/check_synthetic_posterior.py [--along 400] [--across 49] [--plot OUT.png]

``--plot``: the posterior on the plain grid in (log10 ks, p) with the profile's ridge
(the knots' conditional maxima) and the truth (docs/images/synthetic_ridge.png).
"""

import argparse
import time

import jax
import jax.numpy as jnp
import numpy as np

import axojax as ax
from axojax.beats.targets import Target
from axojax.eigen.solvers import Auto
from axojax.inverse import build_problem
from axojax.inverse.sampling._densities import LogDensity
from axojax.inverse.sampling.programs import compiled
from axojax.inverse.sampling.transport import build_map

TRUTH = {"p": 300.0, "ks": 1e6}


def problem():
    model = ax.models.seven(n_elements=10)
    mode = ax.dominant_mode(model, ax.Params().with_values(TRUTH, 1000.0))
    f, lam = float(mode.frequency_hz()), float(mode.wavelength_um())
    return build_problem(
        model,
        ax.Params().with_values({"p": 280.0, "ks": 8e5}, 1000.0),
        [Target("frequency_hz", f, 0.05 * f), Target("wavelength_um", lam, 0.10 * lam)],
        ["p", "ks"],
        kl_ratio=1000.0,
        solver=Auto(min_batch_points=1),
    )


def quantiles(x, w, qs=(0.05, 0.5, 0.95)):
    order = np.argsort(x)
    cdf = np.cumsum(w[order]) / np.sum(w)
    return [float(x[order][np.searchsorted(cdf, q)]) for q in qs]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--along", type=int, default=400)
    ap.add_argument("--across", type=int, default=49)
    ap.add_argument("--plot", default=None, help="save the figure here")
    args = ap.parse_args()
    prob = problem()
    target = LogDensity(prob)
    z_c = prob.to_z(jnp.log(jnp.array([TRUTH["p"], TRUTH["ks"]])))
    t0 = time.perf_counter()
    profile, _ = compiled(build_map, (1, 96), (target, z_c))
    print(f"profile map: {time.perf_counter() - t0:.1f} s")
    good = np.isfinite(np.asarray(profile.log_density))
    zk = np.asarray(profile.z_knots)[good]
    za = np.linspace(zk.min(), zk.max(), args.along)
    b = np.linspace(-6.0, 6.0, args.across)

    def point(za, b):
        c, L, logdet = profile._tables(za)
        z = jnp.stack([c[0] + L[0, 0] * b, za])
        return target(z) + logdet, prob.to_u(z)

    grid = jnp.asarray(np.stack(np.meshgrid(za, b, indexing="ij"), -1).reshape(-1, 2))
    f = jax.jit(jax.vmap(lambda x: point(x[0], x[1])))
    t0 = time.perf_counter()
    parts = [f(grid[i : i + 2000]) for i in range(0, grid.shape[0], 2000)]
    logw = np.concatenate([np.asarray(p[0]) for p in parts])
    u = np.concatenate([np.asarray(p[1]) for p in parts])
    print(f"quadrature: {grid.shape[0]} points, {time.perf_counter() - t0:.1f} s")
    w = np.exp(np.where(np.isfinite(logw), logw - np.nanmax(logw), -np.inf))
    edge = w.reshape(args.along, args.across)[:, [0, -1]].sum() / w.sum()
    print(f"mass at |b| = 6 (the grid's edge across the ridge): {edge:.2e}")
    for i, name in enumerate(("p", "ks")):
        q = np.exp(quantiles(u[:, i], w))
        print(f"{name}: 5 % {q[0]:.4g}, 50 % {q[1]:.4g}, 95 % {q[2]:.4g} (truth {TRUTH[name]:g})")

    # the separate mode: a plain grid in (log p, log ks) around it and around the ridge
    lp = jax.jit(jax.vmap(lambda uu: -0.5 * jnp.sum(prob.residuals(uu) ** 2)))
    P = np.linspace(np.log(100.0), np.log(600.0), 201)
    K = np.linspace(np.log(10.0), np.log(1e7), 81)
    U = jnp.asarray(np.stack(np.meshgrid(P, K, indexing="ij"), -1).reshape(-1, 2))
    L = np.concatenate([np.asarray(lp(U[i : i + 2000])) for i in range(0, U.shape[0], 2000)])
    L = L.reshape(len(P), len(K))
    post = np.exp(np.nan_to_num(L - np.nanmax(L), nan=-np.inf))
    island = (np.exp(P)[:, None] > 240) & (K[None, :] < np.log(10**3.2))
    print(
        f"separate mode (p > 240, ks < 10^3.2) on a plain grid: {post[island].sum() / post.sum():.3f} of the mass"
    )
    if args.plot:
        plot(args.plot, P, K, L, profile, prob)


def plot(path, P, K, L, profile, prob) -> None:
    """The posterior's log density on the grid, the profile's ridge and the truth."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    good = np.isfinite(np.asarray(profile.log_density))
    z = np.stack([np.asarray(profile.centre)[good, 0], np.asarray(profile.z_knots)[good]], 1)
    u = np.asarray(jax.vmap(prob.to_u)(jnp.asarray(z)))
    fig, ax = plt.subplots(figsize=(6.4, 4.2), constrained_layout=True)
    shown = np.maximum(np.nan_to_num(L - np.nanmax(L), nan=-30.0), -12.0)
    im = ax.contourf(K / np.log(10), np.exp(P), shown, levels=24, cmap="viridis")
    fig.colorbar(im, ax=ax, label="log posterior density (max 0; floor -12)")
    ax.plot(u[:, 1] / np.log(10), np.exp(u[:, 0]), "w--", lw=1.2, label="profile along ks")
    ax.plot(np.log10(TRUTH["ks"]), TRUTH["p"], "r*", ms=12, label="truth (p 300, ks 1e6)")
    ax.set_xlabel("log10 ks (dimensionless spoke stiffness)")
    ax.set_ylabel("p (dimensionless dynein force)")
    ax.set_title("p and ks from a frequency and a wavelength: a curved ridge", fontsize=10)
    ax.legend(loc="upper left", fontsize=8)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
