"""The posterior report's ``"gradients"`` (issue 48): every log-density evaluation of the
chains, warm-up included, counted independently of the sampler by a host callback inside
the density the chains evaluate."""

import threading
import warnings

import jax
import numpy as np

from axojax.inverse import posterior
from tests.sampling.test_nuts import LinearGaussian, linear_problem


class Counted(LinearGaussian):
    """The linear-Gaussian problem whose ``log_density`` adds the number of points it is
    evaluated at (one, or a vmapped batch) to ``COUNT`` on the host."""

    def log_density(self, z):
        jax.debug.callback(_bump, z)
        return super().log_density(z)


COUNT = [0]


LOCK = threading.Lock()  # XLA may run the callbacks on several threads


def _bump(z):
    with LOCK:
        COUNT[0] += int(np.asarray(z).size // np.shape(z)[-1])


def test_gradients_count_every_evaluation_of_the_chains():
    base = linear_problem(0)
    problem = Counted(
        np.asarray(base.A), np.asarray(base.y), base.sigma, base.lower, base.upper, base.names
    )
    chains, draws = 2, 40  # 40: the compiled chunk of 50 steps runs a surplus of 10, counted too

    def reset(_laplace):  # the starts' optimisation is not the chains' work
        COUNT[0] = 0

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # short chains warn
        post = posterior(
            problem,
            draws=draws,
            chains=chains,
            warmup=30,
            seed=0,
            vectorize=False,
            on_laplace=reset,
        )
    assert post.gradients > chains * (draws + 30)  # at least one leapfrog step a step
    jax.effects_barrier()  # every callback has run
    assert post.gradients == COUNT[0]
    doc = post.to_json()
    assert doc["gradients"] == post.gradients
    assert doc["gradients_per_ess"] == post.gradients / min(post.ess.values())
