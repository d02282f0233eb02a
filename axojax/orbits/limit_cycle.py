"""``ax.limit_cycle``: the periodic orbit of the nonlinear beat, computed directly."""

from __future__ import annotations

import math

import numpy as np

from ..models.section import Model
from ..params import DEFAULT_CUBIC, Params
from ..results import RESULTS
from ..well_posed import require_passive_friction
from ._solve import solve_jit
from .branch import continue_to
from .cycle import LimitCycle
from .motors import motors_of
from .solvers import AbstractOrbitSolver, HarmonicBalance


def limit_cycle(
    model: Model,
    params: Params,
    kappa: float = DEFAULT_CUBIC,
    *,
    solver: AbstractOrbitSolver = HarmonicBalance(),
    start: LimitCycle | None = None,
    throw: bool = False,
    tau_m: float | None = None,
    f_sat: float | None = None,
) -> LimitCycle:
    """The limit cycle of ``C dq/dt = -A q - f_nl(q) + b`` (the equation of
    :func:`axojax.simulate`, cubic link stiffening ``kappa``), computed directly: Newton on
    the periodic-orbit equations with a phase condition, started from the Hopf normal
    form of the dominant mode (or from ``start``, a nearby orbit).

    A regulated mechanism (``params.chi_*``, ``beta_*``) with an active friction (chi'' or
    beta'' < 0) is refused (:func:`axojax.well_posed.require_passive_friction`) unless
    ``tau_m`` gives it motor kinetics: the orbit is then that of the doubled state
    X = (q, y) of ``ax.simulate(..., tau_m=, f_sat=)``, the same equations
    (:mod:`axojax.orbits.motors`).

    Args:
        model: e.g. ``ax.models.seven()``; needs links (the cubic force lives in them),
            unless saturating motors (``f_sat``) bound the beat. Any base, with or
            without basal compliance: on one that lets the axoneme move rigidly (free,
            head, a pivot without a spring) the orbit's rigid offset is fixed by one phase
            condition per rigid motion and its drift solved for (``cycle.rigid_drift``,
            ~0: docs/model.md section 8, :mod:`axojax.orbits.rigid`); the rigid motions'
            Floquet multipliers are ``cycle.rigid_floquet``.
        params: dimensionless parameters, past the Hopf point (p > p_c; for a regulated
            mechanism, past its Hopf point in chi or beta).
        kappa: cubic link stiffening (1/L^2), > 0 (>= 0 with ``f_sat``).
        solver: an :class:`AbstractOrbitSolver` (default :class:`HarmonicBalance`).
        start: a nearby :class:`LimitCycle` to start from (continuation).
        throw: raise ``ValueError`` (one line saying why) when no orbit is found.
            Default False, as everywhere (:mod:`axojax.results`): then check
            ``cycle.result == RESULTS.successful`` (``cycle.message`` says why not; the
            coefficients of a failed cycle are a finite stand-in, not an orbit).
        tau_m: the motors' relaxation time, dimensionless (seconds / ``units.tau_s``), in
            [1e-9, 1e9]; None (default): no motor kinetics. With it the cycle's
            ``coefficients`` are those of X = (q, y) (``q_coefficients``: q's) and its
            ``linear_eigenvalue`` the augmented pencil's.
        f_sat: with ``tau_m``, saturating motors: the regulated force through
            ``f_sat tanh(f / f_sat)`` (dimensionless force per length,
            ``units.p_from_pn_per_um``), > 0; None (default): linear motors.

    Returns:
        :class:`LimitCycle`: period, frequency, tip amplitude, waveform, wavelength,
        Floquet multipliers. Where the normal form is no start (far past the Hopf
        point, e.g. where the dominant mode no longer oscillates) the orbit is continued
        in p from the Hopf point (:func:`axojax.orbits.branch.continue_to`).
        Differentiable in ``params``, ``kappa`` and the motors (implicit function theorem;
        use the jit-able ``solver.solve`` inside your own transformations, ``motors`` an
        :class:`axojax.orbits.motors.Motors`). With motor kinetics there is no
        continuation in p (the normal form is the only start besides ``start``).
    """
    params = params.validate()
    motors = motors_of(params, tau_m, f_sat)
    if motors is None:
        require_passive_friction(model, params, "limit_cycle")
    saturating = f_sat is not None
    kappa = float(kappa)
    if not math.isfinite(kappa) or kappa < 0 or (kappa == 0 and not saturating):
        bound = (
            ">= 0 (with saturating motors)"
            if saturating
            else "> 0 (the cubic stiffening that bounds the beat)"
        )
        raise ValueError(f"kappa must be a finite number {bound}, got {kappa!r}")
    if model.link_B.shape[0] == 0 and not saturating:
        raise ValueError(
            f"model {model.name!r} has no links: the cubic link force cannot bound a beat (limit cycles need links)"
        )
    if not isinstance(solver, AbstractOrbitSolver):
        raise ValueError(
            f"solver must be an axojax.orbits solver (e.g. HarmonicBalance()), got {solver!r}"
        )
    cycle = solve_jit(model, params, kappa, solver, start, motors)
    if (
        not bool(cycle.converged)
        and start is None
        and motors is None
        and complex(cycle.linear_eigenvalue).real > 0
        and not bool(cycle.result == RESULTS.rigid_drift)
    ):
        # Far from the Hopf point the normal form is no start: continue from it instead.
        try:
            found = continue_to(model, params, kappa, solver, [float(params.p)])[0]
        except ValueError:
            found = None
        if found is not None:
            cycle = found
    if throw and not bool(cycle.converged):
        raise ValueError(failure_reason(cycle, params, motors is not None))
    return cycle


def drift_reason(cycle: LimitCycle, at: str) -> str:
    """One line for an orbit refused for its drift (``RESULTS.rigid_drift``)."""
    v = np.asarray(cycle.rigid_drift, dtype=float)
    return (
        f"no periodic orbit {at}: the static load has a net rigid-body force or torque on this "
        f"{cycle.model.base.kind} base, so the beat drifts (drift velocities "
        f"{np.array2string(v, precision=3)} L or rad per tau; docs/model.md section 8)"
    )


def failure_reason(cycle: LimitCycle, params: Params, motors: bool = False) -> str:
    """One line saying why no orbit was found (``motors``: with motor kinetics, where the
    regulation's coefficients, not p, move the Hopf point)."""
    lam = complex(cycle.linear_eigenvalue)
    at = "with motor kinetics" if motors else f"at p = {float(params.p):g}"
    if cycle.result == RESULTS.rigid_drift:
        return drift_reason(cycle, at)
    past = "move chi or beta past the Hopf point" if motors else "raise p past the Hopf point"
    if lam.real <= 0:
        return (
            f"no limit cycle {at}: the equilibrium is linearly stable there (growth "
            f"rate {lam.real:.4g} per tau); {past}"
        )
    if abs(lam.imag) <= 1e-9 * abs(lam):
        return (
            f"no limit cycle {at}: the dominant mode does not oscillate (divergence, "
            f"eigenvalue {lam.real:.4g})"
        )
    if not bool(cycle.started):
        return (
            f"no limit cycle {at}: the Hopf bifurcation is not supercritical here (the "
            "normal form has no small orbit); start from a nearby orbit"
        )
    return (
        f"no limit cycle found {at}: Newton did not converge in {int(cycle.steps)} "
        f"steps (last correction {float(cycle.correction):.2g}); start from a nearby orbit "
        "(continuation)"
    )
