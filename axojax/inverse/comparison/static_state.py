"""The static state of a normal-force row (issue 55; docs/model.md section 8): the
observed static bend, and the static moment that gives the model the same one.

Normal-force control responds to departures of the normal force N_a = kappa_a,0 F_a +
F_a,0 kappa_a from the static state, so a row needs that state: as Sartori et al. (2016)
take C_0 from the recording, a row's static moment m0 is the one whose equilibrium has the
observed static curvature (the least-squares slope of psi_0 over arc length, rad/um, as
:func:`axojax.waveform.measures.static_curvature` measures it). The equilibrium is linear
in m0 (the passive model under the static load), so one solve at a unit moment gives it.

Where the beat's static curvature is below :data:`SIGNIFICANT` standard errors there is no
static normal force to regulate by: the rows are ``not_applicable`` with that reason
(:func:`not_applicable_reason`). The standard error is the least-squares slope's with
psi_0's sigma at each point taken as psi_1's over sqrt(2) (the same frames average to
both; a Fourier-mode file's sigma is its psi_1's).
"""

from __future__ import annotations

import numpy as np

from ...assembly import assemble
from ...beats.targets import ShapeTarget
from ...models.section import Model
from ...params import MECHANISM_NAMES, Params
from ...units import Units
from ...waveform import measures as wm
from ...waveform.shapes import centreline

SIGNIFICANT = 2.0
"""A static curvature counts when it is at least this many standard errors from 0."""
NORMAL_MECHANISMS = ("normal-force", "sliding+normal-force")
"""The mechanisms regulated by the normal force (their rows need a static bend)."""


def observed_static_curvature(shape: ShapeTarget) -> tuple[float, float]:
    """(static curvature, its standard error), rad/um: the weighted least-squares slope of
    the observed psi_0 over s (module docstring). One-line ``ValueError`` without psi_0."""
    if shape.psi0 is None:
        raise ValueError("shape: normal-force rows need the observed psi_0 (the static bend)")
    s = np.asarray(shape.s_um, dtype=float)
    psi0 = np.asarray(shape.psi0, dtype=float)
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
    passive = params.replace(**{n: 0.0 for n in MECHANISM_NAMES if n != "omega0"}, m0=1.0)
    system = assemble(model, passive)
    q0 = np.linalg.solve(np.asarray(system.A), np.asarray(system.b))
    s = np.asarray(shape.s_um, dtype=float)
    slope = np.asarray(centreline(model, q0[None], s / units.length_um, 1))[0]  # (d, S)
    slope = slope[np.argmax(np.linalg.norm(slope, axis=1))]  # the bend's direction
    per_m0 = float(wm.static_curvature(s, slope))
    if per_m0 == 0.0:
        raise ValueError("m0: the model's static moment bends nothing (no active pairs?)")
    return observed_static_curvature(shape)[0] / per_m0
