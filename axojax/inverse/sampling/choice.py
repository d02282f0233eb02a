"""Which sampler a posterior gets when none is named (``axojax fit --posterior`` with
``--sampler auto``, the default): :func:`choose_sampler`, and why, in words for the report.

Up to :data:`MODES_MAX_FREE` free parameters, :class:`ModeMixture`: as many targets as free
parameters often have several exact solutions, and a cliff where another eigenmode becomes
the dominant one stops NUTS's trajectories, while the mixture's independence chains find
every mode and cross cliffs without a gradient; its fit of the whole posterior by tempered
importance sampling is what limits it to a few parameters (docs/fitting.md, "Which
sampler"). Beyond, :class:`NUTS`, whose cost per effective draw grows slowly with the
number of parameters."""

from __future__ import annotations

import dataclasses
from typing import Any

from ...eigen.solvers import AbstractEigenSolver, Auto
from ._mode_mixture import ModeMixture
from ._nuts import NUTS
from ._sampler import AbstractSampler

MODES_MAX_FREE = 3
"""Free parameters up to which :func:`choose_sampler` picks :class:`ModeMixture`."""


def choose_sampler(problem: Any) -> tuple[AbstractSampler, str]:
    """The sampler for ``problem``'s posterior (an
    :class:`~axojax.inverse.InverseProblem`, by the number of its free parameters) and
    why, one clause: :class:`ModeMixture` up to :data:`MODES_MAX_FREE` free parameters,
    :class:`NUTS` beyond.

    >>> sampler, why = choose_sampler(problem)
    >>> post = ax.inverse.posterior(problem, sampler=sampler, init=fit)
    """
    k = len(tuple(problem.names))
    if k < 1:
        raise ValueError(f"problem: has no free parameters to sample, got names {problem.names!r}")
    counted = f"{k} free parameter{'s' if k > 1 else ''}"
    if k <= MODES_MAX_FREE:
        return ModeMixture(), (
            f"{counted}, at most {MODES_MAX_FREE}: the mode-aware sampler, which finds every "
            "mode and crosses cliffs without gradients"
        )
    return NUTS(), (
        f"{counted}, more than {MODES_MAX_FREE}: NUTS, whose cost grows slowly with their number"
    )


def posterior_eigen_solver(solver: AbstractEigenSolver) -> AbstractEigenSolver:
    """The eigen-solver a problem meant for a posterior should get from ``solver``: the
    default (:class:`~axojax.eigen.solvers.Auto`) counts the posterior's thousands of
    gradient evaluations as a batch, so models of ``Auto.min_batch_dof`` unknowns or more
    (seven filaments at 10 elements: 280) get the structured solver, whose longer
    compilation pays there (benchmarks/bench_gradients.py: value + gradient 6.2 against
    21.2 ms per point on seven filaments); any other solver is kept.

    >>> problem = build_problem(..., solver=posterior_eigen_solver(Auto()))
    """
    if isinstance(solver, Auto):
        return dataclasses.replace(solver, min_batch_points=1)
    return solver
