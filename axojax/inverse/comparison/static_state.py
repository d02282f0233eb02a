"""The static state of a normal-force row (issue 55; docs/model.md section 8): the
observed static bend, and the static moment that gives the model the same one.

Normal-force control responds to departures of the normal force N_a = kappa_a,0 F_a +
F_a,0 kappa_a from the static state, so a row needs that state: as Sartori et al. (2016)
take C_0 from the recording, a row's static moment m0 is the one whose equilibrium has the
observed static curvature (the least-squares slope of psi_0 over arc length, rad/um,
weighted by psi_0's sigma, for model and data alike). The equilibrium is linear
in m0 (the passive model under the static load), so one solve at a unit moment gives it.

The static curvature is measured with an error, and the fitted values move with it (the
gain most: psi_1 and the pins determine g m0, not g): :func:`add_static_errors` adds, in
quadrature, the error it carries into each fitted value (the Gauss-Newton sensitivity of
the optimum to m0, from one Jacobian of the row's problem with m0 free too) to the row's
standard errors; a value the pins alone would fix is then no longer "pinned".

Where the beat's static curvature is below :data:`SIGNIFICANT` standard errors there is no
static normal force to regulate by: the rows are ``not_applicable`` with that reason
(:func:`not_applicable_reason`). The standard error is the least-squares slope's with
psi_0's sigma at each point taken as psi_1's over sqrt(2) (the same frames average to
both; a Fourier-mode file's sigma is its psi_1's).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...assembly.normal_force import passive_equilibrium
from ...beats.targets import ShapeTarget
from ...models.section import Model
from ...params import Params
from ...units import Units
from ...waveform.shapes import centreline
from .mechanisms import row
from .table import PHYSICAL

SIGNIFICANT = 2.0
"""A static curvature counts when it is at least this many standard errors from 0."""
NORMAL_MECHANISMS = ("normal-force", "sliding+normal-force")
"""The mechanisms regulated by the normal force (their rows need a static bend)."""


def observed_static_curvature(shape: ShapeTarget) -> tuple[float, float]:
    """(static curvature, its standard error), rad/um: the weighted least-squares slope of
    the observed psi_0 over s (module docstring). One-line ``ValueError`` without psi_0."""
    if shape.psi0 is None:
        raise ValueError("shape: normal-force rows need the observed psi_0 (the static bend)")
    return _weighted_slope(shape, shape.psi0)


def _weighted_slope(shape: ShapeTarget, psi0) -> tuple[float, float]:
    """(slope, its standard error) of ``psi0`` over the shape's s, weighted by psi_0's
    sigma (psi_1's over sqrt 2)."""
    s = np.asarray(shape.s_um, dtype=float)
    psi0 = np.asarray(psi0, dtype=float)
    sigma = np.broadcast_to(np.asarray(shape.sigma, dtype=float), s.shape) / np.sqrt(2.0)
    w = 1.0 / sigma**2
    mean = np.sum(w * s) / np.sum(w)
    spread = np.sum(w * (s - mean) ** 2)
    slope = np.sum(w * (s - mean) * psi0) / spread
    return float(slope), float(1.0 / np.sqrt(spread))


def not_applicable_reason(mechanism: str, base: str, shape: ShapeTarget) -> str | None:
    """Why a ``mechanism`` row on ``base`` cannot apply to the beat of ``shape`` (None
    where it can): normal-force control needs a clamped base (built there only so far)
    and a static bend of at least :data:`SIGNIFICANT` standard errors."""
    if mechanism not in NORMAL_MECHANISMS:
        return None
    if base != "clamped":
        return "normal-force control is built on the clamped base only so far"
    if shape.psi0 is None:
        return "no static normal force: the beat gives no psi_0"
    c0, se = observed_static_curvature(shape)
    if abs(c0) < SIGNIFICANT * se:
        return (
            f"no static normal force: the static curvature {c0:.3g} rad/um is below "
            f"{SIGNIFICANT:g} standard errors ({se:.2g} rad/um)"
        )
    return None


def matching_moment(model: Model, params: Params, shape: ShapeTarget, units: Units) -> float:
    """The static moment m0 (dimensionless) whose equilibrium (the passive model: every
    regulated coefficient 0) has the observed static curvature at the data's points."""
    q0 = np.asarray(passive_equilibrium(model, params.replace(m0=1.0)))
    s = np.asarray(shape.s_um, dtype=float)
    slope = np.asarray(centreline(model, q0[None], s / units.length_um, 1))[0]  # (d, S)
    slope = slope[np.argmax(np.linalg.norm(slope, axis=1))]  # the bend's direction
    per_m0 = _weighted_slope(shape, slope)[0]  # measured as the observed one
    if per_m0 == 0.0:
        raise ValueError("m0: the model's static moment bends nothing (no active pairs?)")
    return observed_static_curvature(shape)[0] / per_m0


def with_static_state(spec, shape: ShapeTarget, units: Units, frequency_hz: float, pin_tolerance):
    """``spec`` itself, or for a normal-force row the same row at the static moment of
    :func:`matching_moment` (its gain's bounds follow the moment)."""
    if spec.mechanism not in NORMAL_MECHANISMS:
        return spec
    m0 = matching_moment(spec.model, spec.params, shape, units)
    return row(spec.mechanism, spec.base, spec.model, units, frequency_hz,
               params=Params(m0=m0), pin_tolerance=pin_tolerance)  # fmt: skip


def static_sensitivity(problem_of, spec, values: dict) -> dict[str, float]:
    """d(fitted value)/d m0 at the optimum ``values`` of the row ``spec`` (a
    :class:`~axojax.inverse.comparison.mechanisms.Row` whose params hold the static
    moment): -(J^T J)^-1 J^T dr/dm0, J the Jacobian of the normalised residuals in the
    fitted values (pins included) and dr/dm0 their derivative in m0, from the row's
    problem with m0 free too (``problem_of(row)``: compare's ``row_problem`` on the
    observed shape; one compiled Jacobian)."""
    m0 = float(spec.params.m0)
    bound = 10.0 * abs(m0) + 1.0
    free = dataclasses.replace(
        spec, free=(*spec.free, "m0"), bounds={**spec.bounds, "m0": (-bound, bound)}
    )
    problem = problem_of(free)
    v = np.array([values[n] for n in spec.free] + [m0])
    J = problem.jacobian(np.array([p.to_u(x) for p, x in zip(problem.parameters, v)]))
    du = -np.linalg.lstsq(J[:, :-1], J[:, -1], rcond=None)[0]  # m0 is linear: u = m0
    # back to values: a log coordinate's d value = value d u
    return {
        p.name: float(du[i] * (v[i] if p.log else 1.0))
        for i, p in enumerate(problem.parameters[:-1])
    }


def add_static_errors(out, spec, shape: ShapeTarget, units: Units, problem_of) -> None:
    """Add to the normal-force row ``out`` (a :class:`~.compare.CompareRow`, fitted) the
    error its static state carries into each fitted value (module docstring), in
    quadrature with the data's, in ``out.physical_stderr`` (and out of ``out.pinned``);
    ``problem_of``: as :func:`static_sensitivity`'s."""
    if out.fit is None or not out.params:
        return
    c0, se_c0 = observed_static_curvature(shape)
    m0 = float(spec.params.m0)
    if c0 == 0.0 or m0 == 0.0:
        return
    se_m0 = abs(m0) * se_c0 / abs(c0)  # m0 is proportional to the static curvature
    try:
        slope = static_sensitivity(problem_of, spec, out.params)
    except (ValueError, np.linalg.LinAlgError):
        return
    for name, d in slope.items():
        if name not in PHYSICAL:
            continue
        key, conv = PHYSICAL[name]
        extra = abs(d) * se_m0
        extra = extra if conv is None else abs(float(getattr(units, conv)(extra)))
        data = out.physical_stderr.get(key)
        out.physical_stderr[key] = float(np.hypot(data or 0.0, extra))
        if key in out.pinned and extra > 0:
            out.pinned.remove(key)
