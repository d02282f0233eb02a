"""Samplers as objects (issue 53 item 2): ``posterior()`` checks the arguments every
sampler shares and calls ``sampler.run`` (an :class:`AbstractSampler`), so a sampler of
one's own works like NUTS, SMC and ModeMixture."""

import equinox as eqx
import jax
import numpy as np
import pytest
from test_posterior import linear_problem

from axojax.inverse import (
    NUTS,
    AbstractSampler,
    NormalPrior,
    Posterior,
    posterior,
    sampling,
)
from axojax.inverse.sampling import diagnostics
from axojax.inverse.sampling.programs import Clock
from axojax.inverse.sampling.summaries import gradient_free_posterior, value_draws


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
    assert call["warmup"] == 500 and call["vectorize"] is True and call["init"] is None
    assert call["transport"] is None and call["cache"] is None and call["progress"] is False
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
