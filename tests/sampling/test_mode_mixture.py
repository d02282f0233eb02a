"""``posterior(sampler=ModeMixture())`` (issue 48): independence Metropolis-Hastings from
a mixture fitted by tempered adaptive importance sampling. Checked against independent
computations: a quadrature of the same density on a grid (each mode's mass, a mean), a
switch line placed by construction (a residual that jumps on a known line), the
evaluation count against a host callback inside the residuals, and the JSON and file
round trip."""

import json
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.special

from axojax.inverse import ModeMixture, Posterior, posterior
from axojax.results import RESULTS
from tests.sampling.test_nuts import LinearGaussian
from tests.sampling.test_smc import COUNT, _bump, quadrature, two_modes


@pytest.fixture(scope="module")
def modes_post():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return posterior(
            two_modes(), draws=1000, chains=4, seed=0, sampler=ModeMixture(particles=400)
        )


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_both_modes_with_the_quadrature_s_masses(modes_post):
    mass, mean_b = quadrature(two_modes())
    u = modes_post.u
    assert u.shape == (4, 1000, 2)
    per_chain = (u[..., 0] > 0).mean(axis=1)
    assert np.all((per_chain > 0.4) & (per_chain < 0.7))  # every chain visits both modes
    assert abs(float((u[..., 0] > 0).mean()) - mass) < 0.05
    assert abs(modes_post.mean_u["b"] - mean_b) < 0.05
    assert max(modes_post.rhat.values()) < 1.01
    assert min(modes_post.ess.values()) > 400
    assert modes_post.result == RESULTS.successful
    # the report's modes: two, their masses (draws and importance weights) the quadrature's
    assert len(modes_post.modes) == 2
    heavy = max(modes_post.modes, key=lambda m: np.log(m["centre"]["a"]))  # a > 0: exp(u) > 1
    assert abs(heavy["mass"] - mass) < 0.05 and abs(heavy["mass_importance"] - mass) < 0.05
    assert abs(np.log(heavy["centre"]["a"]) - 1.0) < 0.1
    assert modes_post.switches == ()  # a smooth density: no switch line


def test_json_and_file_report_the_modes(modes_post, tmp_path):
    doc = modes_post.to_json()
    json.dumps(doc)
    assert doc["sampler"] == "modes" and doc["chains"] == 4 and doc["draws"] == 1000
    assert len(doc["modes"]) == 2 and doc["switches"] == []
    assert doc["gradients_per_ess"] == doc["gradients"] / min(modes_post.ess.values())
    assert doc["gradients_per_ess"] < 50  # the budget, on this easy case
    modes_post.save(tmp_path / "post.npz")
    back = Posterior.load(tmp_path / "post.npz")
    assert back.sampler == "modes" and len(back.modes) == 2
    assert back.modes[0]["mass"] == modes_post.modes[0]["mass"]


class Cliff(LinearGaussian):
    """One residual ``(a + b + 3 [a > 0.5] - 1) / 0.3`` and a weak pull ``(a - 0.5) / 1``
    on the box [-2, 3]^2: the prediction jumps by 3 (10 sigma) on the line a = 0.5, so the
    posterior is two strips (a + b ~ 1 left of it, a + b ~ -2 right of it)."""

    def residuals(self, u):
        a, b = u[0], u[1]
        jump = jnp.where(a > 0.5, 3.0, 0.0)
        return jnp.stack([(a + b + jump - 1.0) / 0.3, (a - 0.5) / 1.0])


def cliff():
    return Cliff(np.eye(2), np.zeros(2), 1.0, [-2.0, -2.0], [3.0, 3.0], ["a", "b"])


def test_the_switch_line_is_found_where_it_was_put():
    problem = cliff()
    g = np.linspace(-2.0, 3.0, 1001)
    a, b = np.meshgrid(g, g, indexing="ij")
    r = jax.jit(jax.vmap(problem.residuals))(jnp.asarray(np.stack([a.ravel(), b.ravel()], 1)))
    logp = -0.5 * np.sum(np.asarray(r) ** 2, axis=1).reshape(a.shape)
    right = float(np.exp(logp - scipy.special.logsumexp(logp))[a > 0.5].sum())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(problem, draws=1000, chains=4, seed=1, sampler=ModeMixture(particles=400))
    a_draws = np.log(post.value_draws("a"))  # values are exp(u)
    assert abs(float(np.mean(a_draws > 0.5)) - right) < 0.05  # both sides weighed
    assert max(post.rhat.values()) < 1.01
    assert len(post.switches) >= 1
    for line in post.switches:
        for point in line["points"]:
            assert abs(np.log(point["a"]) - 0.5) < 1e-3  # on the line a = 0.5
        assert line["jump"] > 5.0
    spans = [np.log(line["range"]["b"]) for line in post.switches]
    assert max(hi - lo for lo, hi in spans) > 0.3  # a line along b, not one point


class CountedCliff(Cliff):
    def residuals(self, u):
        jax.debug.callback(_bump, u)
        return super().residuals(u)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_every_evaluation_is_counted():
    problem = CountedCliff(np.eye(2), np.zeros(2), 1.0, [-2.0, -2.0], [3.0, 3.0], ["a", "b"])
    COUNT[0] = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # 2 x 60 draws: R-hat and ESS warn
        post = posterior(
            problem, draws=60, chains=2, seed=2, sampler=ModeMixture(particles=100, burn=5)
        )
    jax.effects_barrier()
    assert post.gradients == COUNT[0]


def test_settings_are_checked():
    for bad in (
        {"particles": 10},
        {"df": 2.0},
        {"defensive": 0.0},
        {"efficiency": 1.0},
        {"burn": -1},
    ):
        with pytest.raises(ValueError, match=next(iter(bad))):
            ModeMixture(**bad)
    from axojax.inverse import ProfileTransport

    with pytest.raises(ValueError, match="transport"):
        posterior(two_modes(), sampler=ModeMixture(), transport=ProfileTransport("a"))


@pytest.mark.slow
def test_two_exact_solutions_of_a_small_model_weighed_as_the_quadrature():
    """The two-filament model on 4 elements, p free, one frequency target (30 Hz, sigma
    1.5 Hz): two exact solutions, p ~ 160 and p ~ 236 (another eigenmode dominant), the
    first with about 83 % of the mass by quadrature on 6001 points of log p. The draws
    give that share within 0.05, and the report has both modes."""
    import axojax as ax
    from axojax.beats import Target
    from axojax.inverse import build_problem, least_squares

    problem = build_problem(
        ax.models.two(n_elements=4), ax.Params(), [Target("frequency_hz", 30.0, 1.5)], ["p"]
    )
    g = np.linspace(problem.lower[0], problem.upper[0], 6001)
    r = jax.jit(jax.vmap(problem.residuals))(jnp.asarray(g[:, None]))
    logp = -0.5 * np.sum(np.asarray(r) ** 2, axis=1)
    w = np.exp(np.where(np.isfinite(logp), logp, -np.inf) - scipy.special.logsumexp(logp))
    low = float(w[np.exp(g) < 200].sum())
    assert 0.7 < low < 0.95
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = least_squares(problem, starts=4)
        post = posterior(problem, draws=1000, chains=4, seed=0, sampler=ModeMixture(), init=fit)
    p = post.value_draws("p")
    assert np.all(((p > 140) & (p < 180)) | ((p > 215) & (p < 260)))
    assert abs(float(np.mean(p < 200)) - low) < 0.05
    assert post.rhat["p"] < 1.01 and post.ess["p"] > 400
    assert len(post.modes) == 2
    assert abs(post.modes[0]["mass"] - low) < 0.05 and post.modes[0]["centre"]["p"] < 200
    assert post.gradients_per_ess < 50


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_points_in_u_seed_the_mixture_and_bad_ones_are_refused():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(
            two_modes(),
            draws=200,
            chains=2,
            seed=3,
            init=np.array([[1.0, 0.8], [-1.0, -0.2]]),
            sampler=ModeMixture(particles=200),
        )
    assert abs(float((post.u[..., 0] > 0).mean()) - quadrature(two_modes())[0]) < 0.1
    with pytest.raises(ValueError, match="init"):
        posterior(two_modes(), init=np.array([5.0, 0.0]), sampler=ModeMixture())
