"""``posterior(problem, sampler=SMC(...))``: the posterior of an inverse problem by
adaptive tempered sequential Monte Carlo (:class:`~._smc.SMC`, blackjax), for posteriors
with several separated modes (as many targets as free parameters: several exact
solutions) or cliffs (where the dominant eigenmode changes identity and the predicted
frequency jumps), which NUTS chains started at one optimum neither leave nor cross.

``chains`` independent runs play the chains' part: each run's equally weighted particles
are its "draws" (in the order the last resampling left them: copies of one ancestor side
by side, so the autocorrelation along a run sees what resampling duplicated), and R-hat
and ESS are computed from the (runs, particles, k) array as for chains. R-hat < 1.01
then says the runs agree, the ESS how many independent draws the particles are worth.
Every log-density evaluation is counted (``Posterior.gradients``, none of them a
gradient): per stage and particle, the mutation steps plus three (:meth:`SMC.evaluations_per_stage`),
and one per particle for the draws' log densities.
"""

from __future__ import annotations

import time

import jax
import jax.numpy as jnp
import numpy as np

from ..._progress import progress as progress_bar
from . import diagnostics
from ._densities import InverseProblem, _Target
from ._nuts import _to_u
from ._posterior_result import Posterior
from ._smc import SMC, _run
from ._summaries import _Clock, _value_draws, gradient_free_posterior


def smc_posterior(
    problem: InverseProblem,
    sampler: SMC,
    shape: tuple[int, int, int],
    prior,
    progress: bool = False,
    transport=None,
) -> Posterior:
    """The posterior of ``problem`` by ``chains`` independent SMC runs of ``sampler``
    (:func:`axojax.inverse.posterior` with ``sampler=SMC(...)`` calls this).

    Args:
        problem: an :class:`InverseProblem`.
        sampler: the :class:`SMC` settings; its ``particles`` (else ``draws``) per run.
        shape: (draws, chains, seed): the particles per run when ``sampler.particles``
            is None, the independent runs (R-hat and ESS compare them as chains) and the
            seed of the runs.
        prior: a log prior in u replacing the problem's (callable or None), already
            checked by ``posterior``.
        progress: a progress bar over the runs on stderr.
        transport: must be None (``ValueError``: SMC samples z as it is).

    Returns:
        :class:`Posterior` with ``u`` (runs, particles, k), ``sampler="smc"``,
        ``gradients`` every log-density evaluation (no gradients), ``tempering_stages``
        and ``log_evidence`` per run; warnings as ``posterior``'s (R-hat, ESS), and when a
        run stopped at ``max_stages`` before beta reached 1.
    """
    t_start = time.perf_counter()
    draws, chains, seed = shape
    if transport is not None:
        raise ValueError("transport: applies to NUTS; SMC samples z as it is")
    names = tuple(problem.names)
    k = len(names)
    lower = np.asarray(problem.lower, dtype=float).reshape(-1)
    upper = np.asarray(problem.upper, dtype=float).reshape(-1)
    n = sampler.n_particles(draws)
    if n < 4:
        raise ValueError(f"SMC: particles per run must be >= 4 (R-hat splits each run), got {n}")
    target = _Target(problem, prior)
    clock = _Clock()
    keys = jax.random.split(jax.random.PRNGKey(seed), chains)
    runs = []
    with progress_bar(total=chains, desc="SMC runs", unit="run", enable=progress) as bar:
        for key in keys:
            out = clock.call(
                _run, (sampler, n), target, key, jnp.asarray(lower), jnp.asarray(upper)
            )
            runs.append(jax.device_get(out))
            bar.update(1)
    z = np.stack([r[0] for r in runs])
    log_density = np.stack([r[1] for r in runs])
    stages = tuple(int(r[2]) for r in runs)
    accept = float(np.mean([r[3] for r in runs]))
    log_evidence = tuple(float(r[4]) for r in runs)
    u = np.asarray(clock.call(_to_u, None, target, jnp.asarray(z)))
    value_names, values, log_coordinate = _value_draws(problem, names, u, clock.call)
    summ = diagnostics.summary(values[..., :k])
    evaluations = sum(sampler.evaluations_per_stage(n) * s + n for s in stages)
    notes = diagnostics.sampler_notes(names, summ, chains, chains * n, 0)
    short = [i for i, s in enumerate(stages) if s >= sampler.max_stages]
    if short or not np.all(np.isfinite(log_density)):
        notes.append(
            f"SMC: runs {', '.join(map(str, short))} stopped at max_stages={sampler.max_stages} "
            "before the tempering reached the posterior (raise max_stages or target_ess)"
        )
    return gradient_free_posterior(
        names=names,
        u=u,
        draws_info=(value_names, values, log_coordinate, log_density),
        bounds=(lower, upper),
        summ=summ,
        notes=notes,
        evaluations=evaluations,
        clock=clock,
        t_start=t_start,
        acceptance=accept,
        warmup=0,
        seconds_warmup=0.0,
        seconds_sampling=time.perf_counter() - t_start,
        sampler="smc",
        tempering_stages=stages,
        log_evidence=log_evidence,
    )
