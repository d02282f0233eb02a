"""The :class:`ModeMixture` sampler (``posterior(problem, sampler=ModeMixture())``): a
posterior with several modes, cliffs and curved ridges, sampled by independence
Metropolis-Hastings chains (blackjax's ``irmh``) from a proposal fitted to the posterior
by tempered adaptive importance sampling (:mod:`._mode_tempering`); its settings, its run
(:meth:`ModeMixture.run`) and its report of the modes (:func:`mode_masses`).

1. **Find the mass** (tempered adaptive importance sampling). ``particles`` points from the
   prior box (uniform in u), then stages: the next tempering exponent beta keeps
   ``target_ess`` of the weights' effective sample size for the density ``prior x
   likelihood^beta`` (bisection, as blackjax's adaptive tempering), a Student-t mixture is
   fitted to the weighted points by EM (:func:`._mixture.fit_mixture`), and ``particles``
   fresh points are drawn from it and weighed. The mixture follows the mass as beta
   rises, component by component, into every mode; the fit's optima (``init``) are
   seeded as components at every stage so that a mode narrower than the prior screen
   sees is proposed. At beta = 1, at most ``rounds`` refits follow (each on every point
   drawn at beta = 1 so far), stopping early once the weights' efficiency (ESS over
   points) reaches ``efficiency``; ``max_stages`` bounds everything.
2. **Sample** (exact whatever the fit). ``chains`` independence Metropolis-Hastings chains
   with that mixture as proposal, plus a defensive share from the prior box, started from
   the last weighted points (resampled, so near the posterior), ``burn`` steps dropped.
   A move is proposed anywhere in the box and accepted with the Metropolis-Hastings ratio
   of values: no gradient, so a cliff (where another eigenmode becomes the dominant one and
   the predicted frequency jumps) costs nothing but rejections, and a chain jumps between
   modes in one step, so each mode's share of the draws is its mass.
3. **Report**: each mode (a connected group of mixture components,
   :func:`group_components`) with its centre and mass (by the draws, and by the last importance weights), and the
   switch lines the points met (:mod:`.switches`).

Every log-density evaluation is counted (``Posterior.gradients``, none of them a
gradient): the stages' points, the chains' starts and proposals (burn-in included), the
mode grouping's and the switches' bisections; not the Laplace approximations at the
seeded optima (as NUTS's count leaves out its start), nor the fit.

The modes: a component is *core* when the log density at its centre is within
:data:`REACH` of the best centre's; the others (wide components that cover tails or a
valley) join the mode of the nearest core component (Mahalanobis distance under its scale). Two core components
are one mode when the log density at the midpoint of their centres is at most
:data:`VALLEY` below the lower of the two (no valley between them), and modes are the
connected groups (single linkage): a curved ridge tiled by overlapping components is one
mode, separated solutions are several. A draw belongs to the mode of its most
responsible component.
"""

from __future__ import annotations

import math
import time

import blackjax
import jax
import jax.numpy as jnp
import numpy as np
import scipy.sparse.csgraph
import scipy.special
from jaxtyping import Array, Float, PRNGKeyArray

from ..._progress import stage
from . import diagnostics
from ._densities import LogDensity, log_reference
from ._laplace import fitted_init
from ._mixture import TMixture
from ._mode_tempering import evaluate, systematic, temper
from ._posterior_result import Posterior
from ._sampler import AbstractSampler, refuse_transport
from .programs import Clock
from .summaries import gradient_free_posterior, value_draws
from .switches import find_switches

REACH = 25.0
"""A component whose centre's log density is further than this below the best centre's is
not core (it joins its nearest core component's mode)."""
VALLEY = 3.0
"""Two core components are one mode when the midpoint of their centres is at most this far
below the lower of them in log density."""


class ModeMixture(AbstractSampler):
    """Independence Metropolis-Hastings from a mixture fitted to every mode (module
    docstring): for posteriors of a few parameters with several modes, cliffs or curved
    ridges. Pass it as ``sampler=`` to :func:`axojax.inverse.posterior` (``init``: a
    least-squares ``FitResult`` seeds its optima, by default an axojax ``Problem``'s
    16-start fit; ``warmup``, ``transport`` and the warm cache do not apply).

    Attributes:
        particles: points per adaptive stage (more: a finer fit, more evaluations).
        components: the mixture's components (``None``: 12 per free parameter): EM merges
            or drops some as the density narrows, and the heaviest are split along their
            longest axis back to this count before every fit
            (:func:`._mixture.split_to`), so that they tile a long curved ridge.
        target_ess: share of the weights' effective sample size each tempering stage keeps.
        efficiency: stop adapting at beta = 1 when the weights' ESS over the points
            reaches this (a proposal that close makes chains that accept about as often).
        rounds: at most this many refits at beta = 1 (each on every point drawn at beta
            = 1 so far), whatever the efficiency: a cliff or a ridge that no mixture of
            a few t components fits leaves it below ``efficiency``, and the chains are
            exact with any proposal (they only accept less often).
        max_stages: most stages (tempering and rounds at beta = 1 together).
        df: the t components' degrees of freedom (heavier tails than the target's keep the
            chains uniformly ergodic).
        defensive: share of the chains' proposal drawn from the prior box.
        burn: steps of each chain dropped before its draws.
    """

    particles: int = 500
    components: int | None = None
    target_ess: float = 0.5
    efficiency: float = 0.8
    rounds: int = 4
    max_stages: int = 40
    df: float = 3.0
    defensive: float = 0.05
    burn: int = 50

    def __check_init__(self):
        if not (isinstance(self.particles, int) and self.particles >= 50):
            raise ValueError(
                f"ModeMixture: particles must be an integer >= 50, got {self.particles!r}"
            )
        if self.components is not None and not (
            isinstance(self.components, int) and self.components >= 1
        ):
            raise ValueError(
                f"ModeMixture: components must be an integer >= 1, got {self.components!r}"
            )
        for name in ("target_ess", "efficiency"):
            if not 0.0 < getattr(self, name) < 1.0:
                raise ValueError(
                    f"ModeMixture: {name} must be in (0, 1), got {getattr(self, name)!r}"
                )
        if not (isinstance(self.rounds, int) and self.rounds >= 0):
            raise ValueError(f"ModeMixture: rounds must be an integer >= 0, got {self.rounds!r}")
        if not (isinstance(self.max_stages, int) and self.max_stages >= 1):
            raise ValueError(
                f"ModeMixture: max_stages must be an integer >= 1, got {self.max_stages!r}"
            )
        if not (math.isfinite(self.df) and self.df > 2.0):
            raise ValueError(f"ModeMixture: df must be > 2, got {self.df!r}")
        if not 0.0 < self.defensive < 1.0:
            raise ValueError(f"ModeMixture: defensive must be in (0, 1), got {self.defensive!r}")
        if not (isinstance(self.burn, int) and self.burn >= 0):
            raise ValueError(f"ModeMixture: burn must be an integer >= 0, got {self.burn!r}")

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
        """``chains`` chains of ``draws`` draws each after ``burn`` (``warmup``,
        ``vectorize``, ``on_laplace`` and ``cache`` do not apply; a ``transport`` is
        refused: ModeMixture samples z as it is). ``init``: a least-squares ``FitResult``
        whose optima are seeded, or points in u (None, for an axojax
        :class:`~axojax.inverse.Problem`: its 16-start fit, :func:`._laplace.fitted_init`;
        else nothing seeded).

        Returns:
            :class:`~axojax.inverse.Posterior` with ``sampler="modes"``, ``modes`` (each
            mode's centre and mass, :func:`mode_masses`), ``switches`` (the switch lines
            met, :func:`.switches.find_switches`), ``tempering_stages`` (one entry: the
            stages run), ``gradients`` every log-density evaluation (no gradients) and
            ``acceptance`` the chains' mean acceptance rate.
        """
        refuse_transport("ModeMixture", transport)
        init = fitted_init(problem, init, progress)
        t_start = time.perf_counter()
        names = tuple(problem.names)
        k = len(names)
        lower = np.asarray(problem.lower, dtype=float).reshape(-1)
        upper = np.asarray(problem.upper, dtype=float).reshape(-1)
        target = LogDensity(problem, prior)
        clock = Clock()
        key_adapt, key_start, key_chain = jax.random.split(jax.random.PRNGKey(seed), 3)
        t0 = time.perf_counter()
        adapted = temper(self, target, init, key_adapt, clock, progress)
        seconds_warmup = time.perf_counter() - t0
        z_last, log_w = adapted.last
        z0 = jnp.asarray(z_last[systematic(key_start, log_w, chains)])
        t0 = time.perf_counter()
        steps = self.burn + draws
        with stage(f"posterior chains ({chains} x {steps} steps)", enable=progress):
            z, logd, accept = (
                np.asarray(a)
                for a in clock.call(_chains, steps, target, adapted.mix, key_chain, z0)
            )
        z, logd, accept = z[:, self.burn :], logd[:, self.burn :], accept[:, self.burn :]
        seconds_sampling = time.perf_counter() - t0
        u = np.asarray(jax.vmap(jax.vmap(problem.to_u))(jnp.asarray(z)))
        value_names, values, log_coordinate = value_draws(problem, names, u, clock.call)

        def values_of(zi):
            ui = np.asarray(problem.to_u(jnp.asarray(zi)))
            return {n: float(np.exp(x) if log_coordinate[n] else x) for n, x in zip(names, ui)}

        flat_z = z.reshape(-1, k)

        def log_density(points):
            return clock.call(evaluate, None, target, jnp.asarray(points))[0]

        modes, grouped = mode_masses(
            adapted.mix, flat_z, logd.reshape(-1), adapted.last, values_of, log_density
        )
        centre = flat_z.mean(axis=0)
        chol = np.linalg.cholesky(np.cov(flat_z.T).reshape(k, k) + 1e-12 * np.eye(k))
        switches, bisected = find_switches(
            problem, target, adapted.seen, centre, chol, values_of, clock.call
        )
        summ = diagnostics.summary(values[..., :k])
        # every stage's points, each chain's start and steps, the bisections, the grouping
        evaluations = adapted.evaluations + chains * (steps + 1) + bisected + grouped
        notes = diagnostics.sampler_notes(names, summ, chains, chains * draws, 0)
        if adapted.beta < 1.0:
            notes.append(
                f"ModeMixture: the tempering stopped at beta={adapted.beta:.3g} after max_stages="
                f"{self.max_stages} (raise max_stages or particles)"
            )
        return gradient_free_posterior(
            names=names,
            u=u,
            draws_info=(value_names, values, log_coordinate, logd),
            bounds=(lower, upper),
            summ=summ,
            notes=notes,
            evaluations=evaluations,
            clock=clock,
            t_start=t_start,
            acceptance=float(np.mean(accept)),
            warmup=int(self.burn),
            seconds_warmup=seconds_warmup,
            seconds_sampling=seconds_sampling,
            sampler="modes",
            tempering_stages=(adapted.stages,),
            modes=tuple(modes),
            switches=tuple(switches),
        )


def _chains(shape, target, mix: TMixture, key: PRNGKeyArray, z0: Float[Array, "c k"]):
    """``chains`` independence Metropolis-Hastings chains (blackjax ``irmh``) of ``steps``
    steps from z0: positions (c, steps, k), log densities (c, steps), acceptance (c, steps)."""
    steps = shape
    problem = target.problem

    def log_q(z):
        return mix.log_prob(z, log_reference(problem)(z))

    kernel = blackjax.irmh.build_kernel()

    def step(state, key):
        state, info = kernel(
            key,
            state,
            target,
            lambda k: mix.sample(k, problem.to_z),
            lambda new, prev: log_q(prev.position),
        )
        return state, (state.position, state.logdensity, info.acceptance_rate)

    def chain(key, z):
        state = blackjax.irmh.init(z, target)
        _, out = jax.lax.scan(step, state, jax.random.split(key, steps))
        return out

    return jax.vmap(chain)(jax.random.split(key, z0.shape[0]), z0)


def group_components(mix: TMixture, log_density) -> tuple[np.ndarray, int]:
    """(K,) the mode index of each component of ``mix`` (0, 1, ... in order of first
    appearance) and the evaluations spent; ``log_density(z)`` maps points (n, k) in z to
    their log densities (n,) (-inf where the model fails)."""
    mean = np.asarray(mix.mean)
    chol = np.asarray(mix.chol)
    K = len(mean)
    at = np.asarray(log_density(mean), dtype=float)
    at = np.where(np.isfinite(at), at, -np.inf)
    core = at >= np.max(at) - REACH
    pairs = [(i, j) for i in range(K) for j in range(i + 1, K) if core[i] and core[j]]
    mid = (
        np.asarray(
            log_density(np.array([0.5 * (mean[i] + mean[j]) for i, j in pairs])), dtype=float
        )
        if pairs
        else []
    )
    linked = np.zeros((K, K), dtype=bool)
    for (i, j), m in zip(pairs, mid):
        linked[i, j] = np.isfinite(m) and m >= min(at[i], at[j]) - VALLEY
    cores = np.nonzero(core)[0]
    for i in np.nonzero(~core)[0]:  # a tail or valley component: its nearest core's mode
        d = [np.sum(np.linalg.solve(chol[c], mean[i] - mean[c]) ** 2) for c in cores]
        linked[i, cores[int(np.argmin(d))]] = True
    mode = scipy.sparse.csgraph.connected_components(linked, directed=False)[1]
    _, first, inverse = np.unique(mode, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse].astype(int), K + len(pairs)


def mode_masses(
    mix: TMixture,
    draws_z: np.ndarray,
    draws_log_density: np.ndarray,
    last: tuple[np.ndarray, np.ndarray],
    values_of,
    log_density,
) -> tuple[list[dict], int]:
    """Per mode, heaviest first: ``centre`` (the parameter values of its draw of highest
    log density; ``values_of(z)`` maps a point in z to {name: value}), ``log_density``
    there, ``mass`` (its share of the chains' draws ``draws_z`` (n, k)), ``mass_importance``
    (its share of the last adaptive points' normalised weights ``last`` = (z, log_w)) and
    ``components``, heaviest first (modes with neither draws nor weight left out); and the
    evaluations of ``log_density`` spent (:func:`group_components`)."""
    modes, evaluations = group_components(mix, log_density)
    count = int(modes.max()) + 1

    def which(z):
        return modes[np.argmax(np.asarray(mix.responsibilities(jnp.asarray(z))), axis=1)]

    drawn = which(draws_z)
    z_last, log_w = last
    w = scipy.special.softmax(log_w)
    weighed = which(z_last)
    out = []
    for m in range(count):
        inside = drawn == m
        mass = float(np.mean(inside))
        mass_is = float(np.sum(w[weighed == m]))
        if mass == 0.0 and mass_is < 1e-6:
            continue
        best = None
        if np.any(inside):
            i = int(np.argmax(np.where(inside, draws_log_density, -np.inf)))
            best = (values_of(draws_z[i]), float(draws_log_density[i]))
        out.append(
            {
                "centre": None if best is None else best[0],
                "log_density": math.nan if best is None else best[1],
                "mass": mass,
                "mass_importance": mass_is,
                "components": int(np.sum(modes == m)),
            }
        )
    return sorted(out, key=lambda d: -d["mass"]), evaluations
