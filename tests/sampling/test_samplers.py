"""Samplers as objects (issue 53 item 2): ``posterior()`` checks the arguments every
sampler shares and calls ``sampler.run`` (an :class:`AbstractSampler`), so a sampler of
one's own works like NUTS, SMC and ModeMixture; and the defaults of ``axojax fit
--posterior`` are the library's own (the warm-up from the draws, the chains' layout, a
problem's 16-start fit as the start, the transport chosen from the fit)."""

import warnings

import equinox as eqx
import jax
import numpy as np
import pytest

from axojax.inverse import (
    NUTS,
    AbstractSampler,
    NormalPrior,
    Posterior,
    least_squares,
    posterior,
    sampling,
    suggest_transport,
)
from axojax.inverse.sampling import diagnostics
from axojax.inverse.sampling.programs import Clock
from axojax.inverse.sampling.summaries import gradient_free_posterior, value_draws
from tests.sampling.test_nuts import linear_problem
from tests.sampling.test_transport import Banana, _Fit
from tests.sampling.test_warm_cache import problem as small_problem


class ExactNormal(AbstractSampler):
    """A sampler of one's own: independent draws from the linear-Gaussian problem's exact
    posterior (a normal in u), made a Posterior by the samplers' public helpers. It keeps
    the arguments ``posterior`` called its ``run`` with."""

    scale: float = 1.0
    calls: list = eqx.field(static=True, default_factory=list)

    def run(self, problem, **kw) -> Posterior:
        self.calls.append(kw)
        mean, cov = problem.exact()
        key = jax.random.PRNGKey(kw["seed"])
        shape = (kw["chains"], kw["draws"])
        u = np.asarray(jax.random.multivariate_normal(key, mean, self.scale**2 * cov, shape))
        names = tuple(problem.names)
        clock = Clock()
        value_names, values, log_coordinate = value_draws(problem, names, u, clock.call)
        return gradient_free_posterior(
            names=names,
            u=u,
            draws_info=(value_names, values, log_coordinate, np.zeros(shape)),
            bounds=(problem.lower, problem.upper),
            summ=diagnostics.summary(values[..., : len(names)]),
            notes=[],
            evaluations=0,
            clock=clock,
            t_start=0.0,
            acceptance=1.0,
            warmup=0,
            seconds_warmup=0.0,
            seconds_sampling=0.0,
            sampler="exact",
        )


def test_posterior_runs_a_sampler_of_one_s_own():
    problem = linear_problem(0)
    sampler = ExactNormal()
    post = posterior(problem, draws=500, chains=3, seed=4, sampler=sampler, prior={"a": (0.3, 1.0)})
    (call,) = sampler.calls  # posterior called run once, with every argument
    assert call["draws"] == 500 and call["chains"] == 3 and call["seed"] == 4
    assert call["warmup"] is None and call["vectorize"] is None and call["init"] is None
    assert call["transport"] == "auto" and call["cache"] is None and call["progress"] is False
    assert isinstance(call["prior"], NormalPrior)  # the mapping, made a callable prior
    assert post.sampler == "exact" and post.u.shape == (3, 500, 2)
    mean, cov = problem.exact()
    for i, n in enumerate(problem.names):  # the known posterior came back through run
        sd = np.sqrt(cov[i, i])
        assert abs(post.mean_u[n] - mean[i]) < 4 * sd / np.sqrt(1500)
        assert abs(post.sd_u[n] / sd - 1) < 0.1
        assert post.rhat[n] < 1.01
    # its settings are its fields: another scale, another posterior
    wide = posterior(problem, draws=500, chains=3, seed=4, sampler=ExactNormal(scale=2.0))
    assert abs(wide.sd_u["a"] / post.sd_u["a"] - 2) < 0.2


def test_what_is_not_a_sampler_is_refused_before_any_work():
    problem = linear_problem(0)
    with pytest.raises(TypeError, match="AbstractSampler"):
        posterior(problem, sampler="nuts")
    with pytest.raises(TypeError, match="abstract"):
        AbstractSampler()

    class NoRun(AbstractSampler):
        pass

    with pytest.raises(TypeError, match="abstract"):
        NoRun()
    sampler = ExactNormal()
    with pytest.raises(ValueError, match="draws"):  # the shared checks run before run()
        posterior(problem, draws=2, sampler=sampler)
    with pytest.raises(ValueError, match="warmup"):
        posterior(problem, warmup=-1, sampler=sampler)
    assert sampler.calls == []
    assert isinstance(NUTS(), AbstractSampler)
    assert isinstance(sampling.SMC(), AbstractSampler)
    assert isinstance(sampling.ModeMixture(), AbstractSampler)


def test_the_command_line_s_rules_are_the_library_s_defaults():
    """What `axojax fit --posterior` ran with (tests/sampling/test_posterior_command.py: the command
    passes none of it) is what a Python caller now gets: the warm-up follows the draws,
    the chains run one after another on a CPU, and the command's fit has the library's
    number of starts."""
    from axojax.cli import fit as cli_fit

    assert sampling.POSTERIOR_STARTS == 16 and cli_fit.POSTERIOR_STARTS == 16
    assert [sampling.warmup_steps(d) for d in (4, 300, 1000)] == [150, 300, 500]
    assert [sampling.warmup_steps(d, along="ks") for d in (4, 180, 1000)] == [150, 180, 200]
    assert sampling.vectorize_chains() is (jax.default_backend() != "cpu")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # short chains warn
        post = posterior(linear_problem(0), draws=20, chains=2, seed=0)
    assert post.warmup == 150  # the rule's, not the 500 posterior() took before


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_a_problem_given_no_start_starts_at_its_16_start_fit():
    """``init=None`` on an axojax Problem samples exactly what starting at its
    POSTERIOR_STARTS-start least-squares fit samples (what `axojax fit --posterior`
    does); the transport "auto" on one free parameter is none."""
    prob = small_problem()
    run = {"draws": 8, "chains": 2, "warmup": 20, "seed": 0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # R-hat, ESS of 2 x 8 draws
        default = posterior(prob, **run)
        fit = least_squares(prob, starts=sampling.POSTERIOR_STARTS)
        given = posterior(prob, init=fit, transport=None, **run)
    assert np.array_equal(default.u, given.u)
    assert np.array_equal(default.log_density, given.log_density)
    assert default.transport is None


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_auto_transport_is_the_one_suggested_from_the_fit():
    """``transport="auto"`` (the default) samples along what suggest_transport picks from
    a least-squares result given as ``init``, bitwise as passing it; from a plain point,
    the affine whitening alone."""
    fit = _Fit(0.0, (1.0, 0.3))  # a ridge by importance sampling: along u0
    kw = {"draws": 20, "chains": 2, "warmup": 30, "seed": 1}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        auto = posterior(Banana(), init=fit, **kw)
        chosen = posterior(Banana(), init=fit, transport=suggest_transport(Banana(), fit), **kw)
        plain = posterior(Banana(), init=np.array([0.5, 0.25]), **kw)
    assert auto.transport == "u0" and np.array_equal(auto.u, chosen.u)
    assert plain.transport is None
