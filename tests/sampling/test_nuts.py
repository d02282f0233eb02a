"""Posterior sampling (issue 20): NUTS on inverse problems whose posterior is known
independently (a linear-Gaussian problem: exact normal posterior; a parameter absent
from the residuals: its uniform prior; a one-parameter seven-filament problem: the
posterior by quadrature on a grid), interval coverage over synthetic data sets, the
R-hat/ESS diagnostics against their definitions, JSON/npz output and the corner plot."""

import json
import os
import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import matplotlib
import numpy as np
import pytest
import scipy.optimize
import scipy.special
import scipy.stats

import axojax as ax
from axojax.beats import Target
from axojax.inverse import (
    NUTS,
    Condition,
    InverseProblem,
    Posterior,
    Problem,
    ScaledSigmas,
    diagnostics,
    posterior,
)
from axojax.plotting.corner import plot_corner
from axojax.results import RESULTS, is_successful

SMALL = {"draws": 400, "chains": 4, "warmup": 300}


class LinearGaussian(eqx.Module):
    """Residuals ``(A u - y) / sigma`` with a uniform prior on ``u`` in [lower, upper],
    values ``exp(u)``: with bounds far from the data the posterior in u is the normal
    N(C A^T y / sigma^2, C), C = (A^T A / sigma^2)^-1."""

    A: jax.Array
    y: jax.Array
    lower: np.ndarray
    upper: np.ndarray
    u0: np.ndarray
    sigma: float = eqx.field(static=True)
    names: tuple = eqx.field(static=True)

    def __init__(self, A, y, sigma, lower, upper, names):
        self.A, self.y, self.sigma = jnp.asarray(A, float), jnp.asarray(y, float), float(sigma)
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)
        self.names, self.u0 = (
            tuple(names),
            0.5 * (np.asarray(lower, float) + np.asarray(upper, float)),
        )

    def residuals(self, u):
        return (self.A @ u - self.y) / self.sigma

    def log_prior(self, u):
        return jnp.zeros(())

    def to_u(self, z):
        return self.lower + (self.upper - self.lower) * jax.nn.sigmoid(z)

    def to_z(self, u):
        f = (u - self.lower) / (self.upper - self.lower)
        return jnp.log(f) - jnp.log1p(-f)

    def log_density(self, z):
        logjac = jnp.sum(
            jnp.log(self.upper - self.lower) + jax.nn.log_sigmoid(z) + jax.nn.log_sigmoid(-z)
        )
        return (
            -0.5 * jnp.sum(self.residuals(self.to_u(z)) ** 2)
            + self.log_prior(self.to_u(z))
            + logjac
        )

    def values(self, u):
        return {n: jnp.exp(u[i]) for i, n in enumerate(self.names)}

    def exact(self):
        C = np.linalg.inv(np.asarray(self.A).T @ np.asarray(self.A) / self.sigma**2)
        return C @ np.asarray(self.A).T @ np.asarray(self.y) / self.sigma**2, C


A = np.array([[1.0, 0.5], [0.3, 1.0], [1.0, -1.0], [0.2, 0.1]])
TRUTH_U = np.array([0.3, -0.2])
SIGMA = 0.1


def linear_problem(seed, A=A):
    y = A @ TRUTH_U + SIGMA * np.random.default_rng(seed).normal(size=A.shape[0])
    return LinearGaussian(A, y, SIGMA, [-3.0, -3.0], [3.0, 3.0], ["a", "b"])


def mc_tol(post, name, n_sd=4.0):
    """n_sd Monte Carlo standard errors of the posterior mean of ``name`` in u."""
    return n_sd * post.sd_u[name] / np.sqrt(post.ess[name])


# -- diagnostics ------------------------------------------------------------------------


def reference_split_rhat(x):
    """Vehtari et al. (2021) rank-normalised split R-hat, eqs. (1)-(4) and section 4.2,
    written out with scipy: max over bulk (ranks) and tail (folded ranks)."""

    def split(x):
        n = x.shape[1] // 2
        return np.concatenate([x[:, :n], x[:, -n:]], axis=0)

    def rank_normal(x):
        r = scipy.stats.rankdata(x, method="average").reshape(x.shape)
        return scipy.stats.norm.ppf((r - 3 / 8) / (x.size + 1 / 4))

    def psrf(x):
        n = x.shape[1]
        W = x.var(axis=1, ddof=1).mean()
        B = n * x.mean(axis=1).var(ddof=1)
        return np.sqrt(((n - 1) / n * W + B / n) / W)

    s = split(x)
    return max(psrf(rank_normal(s)), psrf(rank_normal(np.abs(s - np.median(s)))))


def test_diagnostics_of_iid_normal_draws():
    x = np.random.default_rng(0).normal(size=(4, 1000, 3))
    assert np.all(diagnostics.rhat(x) < 1.01)
    # Independent draws: the effective sample size is the number of draws.
    np.testing.assert_allclose(diagnostics.ess_bulk(x), 4000, rtol=0.15)
    np.testing.assert_allclose(diagnostics.ess_tail(x), 4000, rtol=0.2)
    np.testing.assert_allclose(
        diagnostics.rhat(x), [reference_split_rhat(x[..., i]) for i in range(3)], rtol=1e-9
    )


def test_ess_of_an_autoregressive_chain():
    # AR(1) with coefficient rho: integrated autocorrelation time (1 + rho) / (1 - rho).
    rho, n = 0.8, 5000
    rng = np.random.default_rng(1)
    e = rng.normal(size=(4, n))
    y = np.empty_like(e)
    y[:, 0] = e[:, 0] / np.sqrt(1 - rho**2)
    for t in range(1, n):
        y[:, t] = rho * y[:, t - 1] + e[:, t]
    assert diagnostics.ess_bulk(y) == pytest.approx(4 * n * (1 - rho) / (1 + rho), rel=0.2)


def test_diagnostics_keep_one_value_per_component():
    x = np.random.default_rng(3).normal(size=(2, 50, 1))
    assert diagnostics.rhat(x).shape == (1,) and diagnostics.summary(x)["ess_bulk"].shape == (1,)
    assert diagnostics.rhat(x[..., 0]).shape == ()


def test_rhat_flags_a_chain_that_disagrees():
    x = np.random.default_rng(2).normal(size=(4, 500))
    x[0] += 1.0
    r = float(diagnostics.rhat(x))
    assert r > 1.05
    assert r == pytest.approx(reference_split_rhat(x), rel=1e-9)


# -- toy problems with known posteriors -----------------------------------------------


def test_linear_gaussian_posterior_is_the_exact_normal():
    problem = linear_problem(0)
    assert isinstance(problem, InverseProblem)
    post = posterior(problem, seed=0, **SMALL)
    mean, C = problem.exact()
    sd = np.sqrt(np.diag(C))
    for i, n in enumerate(problem.names):
        assert abs(post.mean_u[n] - mean[i]) < mc_tol(post, n)
        assert post.sd_u[n] == pytest.approx(sd[i], rel=0.1)
        # Quantiles of the values exp(u): the exact normal's, mapped.
        assert np.log(post.q05[n]) == pytest.approx(mean[i] - 1.6449 * sd[i], abs=0.25 * sd[i])
        assert np.log(post.q95[n]) == pytest.approx(mean[i] + 1.6449 * sd[i], abs=0.25 * sd[i])
        assert post.rhat[n] < 1.01
        assert post.log_coordinate[n]
    u = post.u.reshape(-1, 2)
    corr = np.corrcoef(u.T)[0, 1]
    assert corr == pytest.approx(C[0, 1] / (sd[0] * sd[1]), abs=0.08)
    assert post.divergences == 0
    assert post.u.shape == (4, 400, 2) and post.values.shape == (4, 400, 2)
    assert post.gradients > 0 and post.seconds > 0
    # the result convention (axojax.results): R-hat and ESS pass, nothing diverged
    assert post.result == RESULTS.successful and post.message == "successful"
    assert post.to_json()["result"] == "successful"


def test_interval_coverage_over_synthetic_data_sets():
    """Eight data sets from one truth: the 90 % intervals of the two parameters contain
    the truth in about 90 % of the 16 cases (at least 12: P(Bin(16, 0.9) <= 11) = 1.7 %),
    each run converged (R-hat < 1.01). Data sets of one structure share one compilation."""
    hits, rhats = [], []
    for seed in range(8):
        post = posterior(linear_problem(100 + seed), seed=seed, **SMALL)
        for i, n in enumerate(("a", "b")):
            hits.append(post.q05[n] <= np.exp(TRUTH_U[i]) <= post.q95[n])
            rhats.append(post.rhat[n])
    assert sum(hits) >= 12, hits
    assert max(rhats) < 1.01


def test_unidentifiable_parameter_is_as_wide_as_its_prior():
    A1 = np.array(
        [[1.0, 0.0], [0.5, 0.0], [-0.4, 0.0], [0.2, 0.0]]
    )  # b does not enter the residuals
    problem = linear_problem(3, A1)
    post = posterior(problem, seed=1, **SMALL)
    lo, hi = problem.lower[1], problem.upper[1]
    assert post.sd_u["b"] == pytest.approx((hi - lo) / np.sqrt(12), rel=0.1)  # uniform prior's sd
    assert np.log(post.q05["b"]) == pytest.approx(lo + 0.05 * (hi - lo), abs=0.05 * (hi - lo))
    assert np.log(post.q95["b"]) == pytest.approx(lo + 0.95 * (hi - lo), abs=0.05 * (hi - lo))
    # The identified parameter is unaffected: its exact 1-D normal posterior.
    var_a = 1.0 / (np.sum(A1[:, 0] ** 2) / SIGMA**2)
    mean_a = var_a * (A1[:, 0] @ np.asarray(problem.y)) / SIGMA**2
    assert abs(post.mean_u["a"] - mean_a) < mc_tol(post, "a")
    assert post.sd_u["a"] == pytest.approx(np.sqrt(var_a), rel=0.1)
    assert max(post.rhat.values()) < 1.01


def test_a_normal_prior_replaces_the_uniform_one():
    problem = linear_problem(3, np.array([[1.0, 0.0], [0.5, 0.0], [-0.4, 0.0], [0.2, 0.0]]))
    post = posterior(problem, seed=2, prior={"b": (0.5, 0.3)}, **SMALL)  # normal in u = log b
    assert abs(post.mean_u["b"] - 0.5) < mc_tol(post, "b")
    assert post.sd_u["b"] == pytest.approx(0.3, rel=0.1)


def test_scaled_sigmas_widen_the_posterior_by_their_factor():
    """Every sigma times 2: the exact normal posterior's covariance times 4, same mean."""
    problem = linear_problem(0)
    post = posterior(ScaledSigmas(problem, 2.0), seed=0, **SMALL)
    mean, C = problem.exact()
    for i, n in enumerate(problem.names):
        assert abs(post.mean_u[n] - mean[i]) < mc_tol(post, n)
        assert post.sd_u[n] == pytest.approx(2.0 * np.sqrt(C[i, i]), rel=0.1)
        assert post.rhat[n] < 1.01
    z = jnp.array([0.1, -0.3])
    scaled = ScaledSigmas(problem, 3.0)
    u = problem.to_u(z)
    # The log density in z: the likelihood term over 9, prior and log-Jacobian as before.
    chi2 = float(jnp.sum(problem.residuals(u) ** 2))
    assert float(scaled.log_density(z)) == pytest.approx(
        float(problem.log_density(z)) + 0.5 * chi2 * (1 - 1 / 9), rel=1e-12
    )
    with pytest.raises(ValueError, match="factor"):
        ScaledSigmas(problem, 0.0)


def test_start_is_the_mode_of_the_density_in_z():
    """The chains' centre (Levenberg-Marquardt on the residuals and the logistic map's
    pseudo-residuals) against scipy's BFGS maximum of the same log density in z."""
    from axojax.inverse.sampling._laplace import _logistic_residuals

    z = jnp.linspace(-30.0, 30.0, 13)
    exact = jax.nn.log_sigmoid(z) + jax.nn.log_sigmoid(-z) + np.log(4.0)
    np.testing.assert_allclose(-0.5 * _logistic_residuals(z) ** 2, exact, rtol=1e-12, atol=1e-12)
    problem = linear_problem(5)
    problem = LinearGaussian(
        problem.A, problem.y, problem.sigma, [-1.0, -1.0], [1.0, 1.0], ["a", "b"]
    )  # bounds close: the Jacobian term moves the mode
    f = jax.jit(lambda z: -problem.log_density(z))
    ref = scipy.optimize.minimize(
        lambda z: float(f(jnp.asarray(z))),
        np.zeros(2),
        jac=lambda z: np.asarray(jax.grad(f)(jnp.asarray(z))),
        method="BFGS",
        options={"gtol": 1e-10},
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(problem, draws=20, chains=2, warmup=0, seed=0)
    np.testing.assert_allclose(
        post.start_u, np.asarray(problem.to_u(jnp.asarray(ref.x))), atol=1e-6
    )


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_starts_settings_and_errors():
    problem = linear_problem(0)
    starts = np.array([[0.2, -0.1], [0.4, -0.3], [0.3, 0.0], [0.1, -0.2]])
    post = posterior(
        problem, init=starts, seed=0, sampler=NUTS(dense_mass=False), vectorize=False, **SMALL
    )
    mean, _ = problem.exact()
    assert abs(post.mean_u["a"] - mean[0]) < mc_tol(post, "a")
    np.testing.assert_allclose(post.start_u, starts.mean(axis=0))
    # Sampling in z itself (no whitening by the Laplace approximation): the same posterior.
    post = posterior(problem, seed=0, sampler=NUTS(whiten=False), **SMALL)
    for i, n in enumerate(problem.names):
        assert abs(post.mean_u[n] - mean[i]) < mc_tol(post, n)
    # A least-squares result (params by name, coordinate per name) as the centre.
    fitted = type(
        "Fit",
        (),
        {
            "params": {"a": float(np.exp(mean[0])), "b": float(np.exp(mean[1]))},
            "coordinate": {"a": "log", "b": "log"},
        },
    )()
    post = posterior(problem, init=fitted, seed=0, **SMALL)
    np.testing.assert_allclose(post.start_u, mean)
    with pytest.raises(ValueError, match="init"):
        posterior(problem, init=np.zeros(3))
    with pytest.raises(ValueError, match="init"):
        posterior(problem, init=np.array([5.0, 0.0]))
    with pytest.raises(ValueError, match="draws"):
        posterior(problem, draws=2)
    with pytest.raises(ValueError, match="prior"):
        posterior(problem, prior={"c": (0.0, 1.0)})
    with pytest.raises(ValueError, match="max_num_doublings"):
        NUTS(max_num_doublings=0)


def test_short_chains_warn():
    with pytest.warns(UserWarning, match="effective sample size"):
        post = posterior(linear_problem(0), draws=40, chains=4, warmup=300, seed=0)
    assert "effective sample size" in post.message
    assert post.result == RESULTS.chains_not_converged and not is_successful(post.result)
    assert post.to_json()["result"] == "chains_not_converged"


def test_posterior_file_keeps_the_result(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(linear_problem(0), draws=40, chains=4, warmup=300, seed=0)
    post.save(tmp_path / "post.npz")
    back = Posterior.load(tmp_path / "post.npz")
    assert back.result == RESULTS.chains_not_converged and back.message == post.message


def test_json_npz_and_corner_plot(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(linear_problem(0), seed=0, **SMALL)
    doc = post.to_json()
    for key in ("draws", "chains", "mean", "sd", "q05", "q95", "rhat", "ess", "seconds"):
        assert key in doc
    assert doc["draws"] == 400 and doc["chains"] == 4 and set(doc["mean"]) == {"a", "b"}
    json.dumps(doc)
    path = tmp_path / "post.npz"
    post.save(path, truth={"a": float(np.exp(TRUTH_U[0])), "b": float(np.exp(TRUTH_U[1]))})
    back = Posterior.load(path)
    np.testing.assert_array_equal(back.u, post.u)
    assert back.rhat == post.rhat and back.names == post.names
    with np.load(path) as f:
        assert json.loads(str(f["meta"]))["kind"] == "posterior"  # what `axojax plot` dispatches on
    fig = plot_corner(path, out=tmp_path / "corner.png")
    assert isinstance(fig, matplotlib.figure.Figure)
    assert (tmp_path / "corner.png").stat().st_size > 0
    visible = [a for a in fig.axes if a.get_visible()]
    assert len(visible) == 3  # two histograms, one pair
    assert visible[0].get_xscale() == "log"


# -- a real model ---------------------------------------------------------------------


@pytest.mark.skipif(
    os.environ.get("AXOJAX_SLOW_TESTS") != "1",
    reason="50 s: set AXOJAX_SLOW_TESTS=1 (tests/sampling/test_posterior_command.py samples a "
    "seven-filament model in the default run)",
)
def test_seven_filament_posterior_matches_quadrature():
    """One parameter (p) of the four-element seven-filament model from noisy frequency and
    wavelength: the sampled posterior against the posterior by quadrature on a grid of
    the fitted coordinate (an independent computation of the same density), and the
    truth inside the 90 % interval. (Its density in z is skewed, with a shoulder: NUTS
    gets about one effective draw in four, so the run warns about its ESS.)"""
    model = ax.models.seven(n_elements=4)
    base = ax.Params().with_values({"ks": 1e5}, 1000.0)
    truth = 320.0
    mode = ax.dominant_mode(model, base.replace(p=truth))
    f, lam = float(mode.frequency_hz()), float(mode.wavelength_um())
    rng = np.random.default_rng(0)
    targets = [
        Target("frequency_hz", f * (1 + 0.02 * rng.normal()), 0.02 * f),
        Target("wavelength_um", lam * (1 + 0.05 * rng.normal()), 0.05 * lam),
    ]
    problem = Problem(
        model,
        [Condition({}, targets)],
        ["p"],
        params=base.replace(p=300.0),
        bounds={"p": (100.0, 1000.0)},
        kl_ratio=1000.0,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(problem, draws=300, chains=4, warmup=200, seed=0, init=np.log([300.0]))
    assert post.q05["p"] <= truth <= post.q95["p"]
    assert post.rhat["p"] < 1.01
    assert post.divergences <= 0.01 * 4 * 300  # a few, at the steep side of the density
    # Quadrature: the posterior in u = log p (uniform prior) on a grid around the draws.
    residuals = jax.jit(problem.residuals)
    grid = np.linspace(
        np.log(post.q50["p"]) - 8 * post.sd_u["p"], np.log(post.q50["p"]) + 8 * post.sd_u["p"], 321
    )
    logp = np.array([-0.5 * float(jnp.sum(residuals(jnp.array([g])) ** 2)) for g in grid])
    w = np.exp(logp - scipy.special.logsumexp(logp))
    assert w[0] < 1e-6 and w[-1] < 1e-6  # the grid covers the posterior
    mean = np.sum(w * grid)
    sd = np.sqrt(np.sum(w * (grid - mean) ** 2))
    assert abs(post.mean_u["p"] - mean) < mc_tol(post, "p")
    assert post.sd_u["p"] == pytest.approx(sd, rel=0.15)
