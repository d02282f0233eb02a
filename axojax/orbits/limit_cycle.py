"""``ax.limit_cycle``: the periodic orbit of the nonlinear beat, computed directly."""

from __future__ import annotations

import math

from ..models.section import Model
from ..params import DEFAULT_CUBIC, Params
from ..well_posed import require_passive_friction
from ._solve import solve_jit
from .branch import continue_to
from .cycle import LimitCycle
from .solvers import AbstractOrbitSolver, HarmonicBalance


def limit_cycle(
    model: Model,
    params: Params,
    kappa: float = DEFAULT_CUBIC,
    *,
    solver: AbstractOrbitSolver = HarmonicBalance(),
    start: LimitCycle | None = None,
    throw: bool = False,
) -> LimitCycle:
    """The limit cycle of ``C dq/dt = -A q - f_nl(q) + b`` (the equation of
    :func:`axojax.simulate`, cubic link stiffening ``kappa``), computed directly: Newton on
    the periodic-orbit equations with a phase condition, started from the Hopf normal
    form of the dominant mode (or from ``start``, a nearby orbit).

    Args:
        model: e.g. ``ax.models.seven()``; needs links (the cubic force lives in them).
        params: dimensionless parameters, past the Hopf point (p > p_c).
        kappa: cubic link stiffening (1/L^2), > 0.
        solver: an :class:`AbstractOrbitSolver` (default :class:`HarmonicBalance`).
        start: a nearby :class:`LimitCycle` to start from (continuation).
        throw: raise ``ValueError`` (one line saying why) when no orbit is found.
            Default False, as everywhere (:mod:`axojax.results`): then check
            ``cycle.result == RESULTS.successful`` (``cycle.message`` says why not; the
            coefficients of a failed cycle are a finite stand-in, not an orbit).

    Returns:
        :class:`LimitCycle`: period, frequency, tip amplitude, waveform, wavelength,
        Floquet multipliers. Where the normal form is no start (far past the Hopf
        point, e.g. where the dominant mode no longer oscillates) the orbit is continued
        in p from the Hopf point (:func:`axojax.orbits.branch.continue_to`).
        Differentiable in ``params`` and ``kappa`` (implicit function theorem; use the
        jit-able ``solver.solve`` inside your own transformations).
    """
    params = params.validate()
    model.require_held("limit_cycle")
    require_passive_friction(model, params, "limit_cycle")
    kappa = float(kappa)
    if not math.isfinite(kappa) or kappa <= 0:
        raise ValueError(
            f"kappa must be a finite number > 0 (the cubic stiffening that bounds the beat), got {kappa!r}"
        )
    if model.link_B.shape[0] == 0:
        raise ValueError(
            f"model {model.name!r} has no links: the cubic link force cannot bound a beat (limit cycles need links)"
        )
    if not isinstance(solver, AbstractOrbitSolver):
        raise ValueError(
            f"solver must be an axojax.orbits solver (e.g. HarmonicBalance()), got {solver!r}"
        )
    cycle = solve_jit(model, params, kappa, solver, start)
    if not bool(cycle.converged) and start is None and complex(cycle.linear_eigenvalue).real > 0:
        # Far from the Hopf point the normal form is no start: continue from it instead.
        try:
            found = continue_to(model, params, kappa, solver, [float(params.p)])[0]
        except ValueError:
            found = None
        if found is not None:
            cycle = found
    if throw and not bool(cycle.converged):
        raise ValueError(failure_reason(cycle, params))
    return cycle


def failure_reason(cycle: LimitCycle, params: Params) -> str:
    """One line saying why no orbit was found."""
    lam = complex(cycle.linear_eigenvalue)
    p = float(params.p)
    if lam.real <= 0:
        return (
            f"no limit cycle at p = {p:g}: the equilibrium is linearly stable there (growth "
            f"rate {lam.real:.4g} per tau); raise p past the Hopf point"
        )
    if abs(lam.imag) <= 1e-9 * abs(lam):
        return (
            f"no limit cycle at p = {p:g}: the dominant mode does not oscillate (divergence, "
            f"eigenvalue {lam.real:.4g})"
        )
    if not bool(cycle.started):
        return (
            f"no limit cycle at p = {p:g}: the Hopf bifurcation is not supercritical here (the "
            "normal form has no small orbit); start from a nearby orbit"
        )
    return (
        f"no limit cycle found at p = {p:g}: Newton did not converge in {int(cycle.steps)} "
        f"steps (last correction {float(cycle.correction):.2g}); start from a nearby orbit "
        "(continuation)"
    )
