"""Adaptive tempered sequential Monte Carlo (:class:`SMC`): the sampler's settings, its
run (:meth:`SMC.run`, what ``posterior(problem, sampler=SMC(...))`` calls) and the
compiled program of one run (blackjax's ``adaptive_tempered_smc`` with a random-walk
Metropolis mutation whose proposal follows the particles' covariance, its scale the
acceptance rate).

One run, in the problem's unconstrained coordinate ``z``: ``particles`` points drawn
from the reference distribution (uniform in the fitted coordinate ``u`` between the
bounds, i.e. the default prior), then stages that raise the tempering exponent beta
from 0 to 1 on the rest of the log density (the likelihood ``-1/2 |residuals|^2`` and
the prior's departure from uniform), each as far as keeps ``target_ess`` of the
particles' effective sample size (blackjax's bisection), with a resampling (systematic)
and ``mutation_steps`` random-walk Metropolis steps of every particle at the new beta.
A last stage at beta = 1 resamples the final weights and mutates once more, so the
particles come out equally weighted. The mutation evaluates the log density and never
its gradient: where the dominant eigenmode changes identity the predicted frequency
jumps (a cliff of the likelihood) and a Metropolis step simply accepts or rejects a move
across it, where a gradient-based trajectory diverges. Particles spread over every mode
from the start (the prior covers them all), and the tempering weighs the modes by their
mass.

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

import math
import time

import blackjax
import jax
import jax.numpy as jnp
import numpy as np
from blackjax.smc.tuning.from_kernel_info import update_scale_from_acceptance_rate
from blackjax.smc.tuning.from_particles import particles_covariance_matrix
from blackjax.smc.waste_free import waste_free_smc
from jaxtyping import Array, Float, Int, PRNGKeyArray

from ..._progress import progress as progress_bar
from . import diagnostics
from ._densities import LogDensity, log_reference
from ._posterior_result import Posterior
from ._sampler import AbstractSampler, refuse_transport
from .programs import Clock
from .summaries import gradient_free_posterior, to_u, value_draws

LOG_FLOOR = -1e12
"""Log likelihood given to a failed model evaluation (NaN or -inf): finite, so that
beta = 0 times it is 0 (the reference density) and any beta > 0 rejects it."""
JITTER = 1e-9
"""Added to the diagonal of the particles' covariance before its Cholesky factor (in z,
squared: the proposal of a collapsed direction stays proper)."""


class SMC(AbstractSampler):
    """Adaptive tempered sequential Monte Carlo (blackjax), for posteriors with several
    modes or cliffs (module docstring). Pass it as ``sampler=`` to
    :func:`axojax.inverse.posterior`: ``chains`` independent runs, each started from the
    prior (``init``, ``warmup``, ``transport`` and the warm cache do not apply).

    Attributes:
        particles: particles of a run: the draws per run (``None``: ``posterior``'s
            ``draws``).
        mutation_steps: random-walk Metropolis steps per chain of the mutation (more:
            less correlated particles after a resampling; each step one evaluation of the
            log density per chain).
        waste_free: waste-free SMC (Dau and Chopin 2022; blackjax's ``waste_free_smc``):
            resample ``particles / (mutation_steps + 1)`` particles, run a chain of
            ``mutation_steps`` steps from each and keep every state, so a stage costs
            about 3 evaluations per particle instead of ``mutation_steps + 3`` (the
            particles are rounded up to a multiple of ``mutation_steps + 1``). ``False``:
            every particle mutated ``mutation_steps`` times, the last state kept.
        target_ess: share of the particles' effective sample size each stage keeps (the
            next beta solves ESS = target_ess x particles; smaller: fewer, longer stages).
        proposal_scale: the random walk's first proposal is this times the Cholesky
            factor of the particles' covariance (in z); ``None``: 2.38 / sqrt(k) (Roberts
            and Rosenthal's optimal scaling of a Gaussian target in k dimensions). Each
            stage then moves it by exp(acceptance - target_acceptance) (blackjax's
            ``update_scale_from_acceptance_rate``): across separated modes the particles'
            covariance spans the gap, and steps that size are rejected within a mode.
        target_acceptance: the acceptance rate the scale follows.
        max_stages: stop the tempering after this many stages (the report then says
            beta did not reach 1: ``chains_not_converged``).
    """

    particles: int | None = None
    mutation_steps: int = 8
    waste_free: bool = False
    target_ess: float = 0.5
    proposal_scale: float | None = None
    target_acceptance: float = 0.3
    max_stages: int = 500

    def __check_init__(self):
        if self.particles is not None and not (
            isinstance(self.particles, int) and self.particles >= 4
        ):
            raise ValueError(f"SMC: particles must be an integer >= 4, got {self.particles!r}")
        if not (isinstance(self.mutation_steps, int) and self.mutation_steps >= 1):
            raise ValueError(
                f"SMC: mutation_steps must be an integer >= 1, got {self.mutation_steps!r}"
            )
        if not (0.0 < self.target_ess < 1.0):
            raise ValueError(f"SMC: target_ess must be in (0, 1), got {self.target_ess!r}")
        if self.proposal_scale is not None and not (
            math.isfinite(self.proposal_scale) and self.proposal_scale > 0
        ):
            raise ValueError(f"SMC: proposal_scale must be > 0, got {self.proposal_scale!r}")
        if not (isinstance(self.max_stages, int) and self.max_stages >= 1):
            raise ValueError(f"SMC: max_stages must be an integer >= 1, got {self.max_stages!r}")

    def scale(self, k: int) -> float:
        """The proposal's scale on the particles' covariance (its Cholesky factor), in k
        dimensions."""
        return 2.38 / math.sqrt(k) if self.proposal_scale is None else float(self.proposal_scale)

    def n_particles(self, draws: int) -> int:
        """Particles of a run: ``particles`` (else ``draws``), rounded up to a multiple of
        ``mutation_steps + 1`` when waste-free."""
        n = int(self.particles if self.particles is not None else draws)
        p = self.mutation_steps + 1
        return -(-n // p) * p if self.waste_free else n

    def evaluations_per_stage(self, particles: int) -> int:
        """Log-density evaluations (values, no gradient) of one stage of blackjax's
        tempered kernel: per particle one to choose the next beta (the ESS solver) and one
        for the new weights; the mutation's chains one at their start and one per step
        (waste-free: ``particles / (mutation_steps + 1)`` chains; else one per particle)."""
        chains = particles // (self.mutation_steps + 1) if self.waste_free else particles
        return 2 * particles + chains * (self.mutation_steps + 1)

    def run(
        self,
        problem,
        *,
        draws,
        chains,
        warmup,
        seed,
        init,
        prior,
        vectorize,
        progress,
        on_laplace,
        cache,
        transport,
    ) -> Posterior:
        """``chains`` independent SMC runs of :meth:`n_particles` particles each, from the
        prior (``init``, ``warmup``, ``vectorize``, ``on_laplace`` and ``cache`` do not
        apply; a ``transport`` is refused: SMC samples z as it is).

        Returns:
            :class:`~axojax.inverse.Posterior` with ``u`` (runs, particles, k),
            ``sampler="smc"``, ``gradients`` every log-density evaluation (no gradients),
            ``tempering_stages`` and ``log_evidence`` per run; warnings as
            :func:`~axojax.inverse.posterior`'s (R-hat, ESS), and when a run stopped at
            ``max_stages`` before beta reached 1.
        """
        t_start = time.perf_counter()
        refuse_transport("SMC", transport)
        names = tuple(problem.names)
        k = len(names)
        lower = np.asarray(problem.lower, dtype=float).reshape(-1)
        upper = np.asarray(problem.upper, dtype=float).reshape(-1)
        n = self.n_particles(draws)
        if n < 4:
            raise ValueError(
                f"SMC: particles per run must be >= 4 (R-hat splits each run), got {n}"
            )
        target = LogDensity(problem, prior)
        clock = Clock()
        keys = jax.random.split(jax.random.PRNGKey(seed), chains)
        runs = []
        with progress_bar(
            total=chains, desc="SMC runs", unit="run", enable=progress, starting=True
        ) as bar:
            for key in keys:
                out = clock.call(
                    _one_run, (self, n), target, key, jnp.asarray(lower), jnp.asarray(upper)
                )
                runs.append(jax.device_get(out))
                bar.update(1)
        z = np.stack([r[0] for r in runs])
        log_density = np.stack([r[1] for r in runs])
        stages = tuple(int(r[2]) for r in runs)
        accept = float(np.mean([r[3] for r in runs]))
        log_evidence = tuple(float(r[4]) for r in runs)
        u = np.asarray(clock.call(to_u, None, target, jnp.asarray(z)))
        value_names, values, log_coordinate = value_draws(problem, names, u, clock.call)
        summ = diagnostics.summary(values[..., :k])
        evaluations = sum(self.evaluations_per_stage(n) * s + n for s in stages)
        notes = diagnostics.sampler_notes(names, summ, chains, chains * n, 0)
        short = [i for i, s in enumerate(stages) if s >= self.max_stages]
        if short or not np.all(np.isfinite(log_density)):
            notes.append(
                f"SMC: runs {', '.join(map(str, short))} stopped at max_stages={self.max_stages} "
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


def _strategy(sampler: SMC, n: int) -> dict:
    """The mutation's blackjax arguments: waste-free (``update_strategy``) or
    ``num_mcmc_steps`` steps of every particle."""
    if not sampler.waste_free:
        return {"num_mcmc_steps": sampler.mutation_steps}
    update = waste_free_smc(n, sampler.mutation_steps + 1)
    return {"num_mcmc_steps": None, "update_strategy": update}


def _one_run(
    settings: tuple[SMC, int],
    target,
    key: PRNGKeyArray,
    lower: Float[Array, " k"],
    upper: Float[Array, " k"],
) -> tuple[
    Float[Array, "n k"], Float[Array, " n"], Int[Array, ""], Float[Array, ""], Float[Array, ""]
]:
    """One SMC run (module docstring) of ``target`` (the log density in z): the particles
    (n, k) in z, equally weighted; their log densities (n,); the stages run (the last at
    beta = 1 included); the mutation's mean acceptance rate; and the log of the
    normalising constant of the posterior over the reference (the log evidence, up to
    the prior's own normalisation). ``settings``: (sampler, n particles)."""
    sampler, n = settings
    problem = target.problem
    k = lower.shape[0]
    log_ref = log_reference(problem)

    def log_like(z):
        ll = target(z) - log_ref(z)
        return jnp.where(jnp.isfinite(ll), ll, LOG_FLOOR)

    def rw_step(key, state, logdensity_fn, chol):
        """Random-walk Metropolis with proposal ``chol @ N(0, I)`` (blackjax)."""
        kernel = blackjax.additive_step_random_walk.build_kernel()
        return kernel(key, state, logdensity_fn, blackjax.mcmc.random_walk.normal(chol))

    def algorithm(chol):
        """blackjax's adaptive tempered SMC with the random walk's factor ``chol``."""
        return blackjax.adaptive_tempered_smc(
            logprior_fn=log_ref,
            loglikelihood_fn=log_like,
            mcmc_step_fn=rw_step,
            mcmc_init_fn=blackjax.additive_step_random_walk.init,
            mcmc_parameters={"chol": chol[None]},
            resampling_fn=blackjax.smc.resampling.systematic,
            target_ess=sampler.target_ess,
            **_strategy(sampler, n),
        )

    def factor(particles, scale):
        cov = particles_covariance_matrix(particles) + JITTER * jnp.eye(k)
        return scale * jnp.linalg.cholesky(cov)

    def stage(carry):
        """One stage: the proposal from the particles' covariance times the scale, which
        then follows the acceptance rate (blackjax's ``update_scale_from_acceptance_rate``)."""
        state, key, stages, accept, log_z, scale = carry
        key, key_step = jax.random.split(key)
        step = algorithm(factor(state.particles, scale)).step
        state, info = step(key_step, state)
        rate = jnp.mean(info.update_info.acceptance_rate)
        scale = update_scale_from_acceptance_rate(
            scale[None], rate[None], sampler.target_acceptance
        )[0]
        log_z = log_z + info.log_likelihood_increment
        return state, key, stages + 1, accept + rate, log_z, scale

    def more(carry):
        beta, stages = carry[0].tempering_param, carry[2]
        return (beta < 1.0) & (stages < sampler.max_stages - 1)

    key_init, key_run = jax.random.split(key)
    u0 = jax.random.uniform(key_init, (n, k), minval=lower, maxval=upper)
    state = algorithm(jnp.eye(k)).init(jax.vmap(problem.to_z)(u0))
    zero = jnp.zeros(())
    carry = (state, key_run, jnp.zeros((), int), zero, zero, jnp.asarray(sampler.scale(k)))
    carry = jax.lax.while_loop(more, stage, carry)
    # the last stage at beta = 1 (delta 0): resample the final weights, mutate once more
    state, _, stages, accept, log_z, _ = stage(carry)
    z = state.particles
    log_density = jnp.where(state.tempering_param >= 1.0, jax.vmap(target)(z), jnp.nan)
    return z, log_density, stages, accept / stages, log_z
