"""Limit-cycle waveform targets: normalised residuals of a whole observed beat against
the nonlinear orbit, for least squares and posteriors.

An observed beat (``axojax data``, or :class:`axojax.beats.targets.ShapeTarget` with
``psi0``) gives psi_0(s) and psi_1(s) in absolute amplitude (rad) and scalar measures
(:class:`CycleTarget`: frequency, static curvature, dynamic amplitude, wavelength, tip
amplitude, out-of-plane measure). :func:`waveform_residuals` solves the orbit at the
parameters (warm-started from ``start``, a nearby orbit: a fit passes the previous
iterate's orbit, so each evaluation costs a few Newton steps) and returns::

    [(psi0_model + c - psi0_obs) / sigma,                        (S,)   when psi0 is given
     Re, Im of (e^{i phi} psi1_model - psi1_obs) / sigma,       (2 S,) when psi1 is given
     (measure_model - value) / sigma for each scalar target]

with ``e^{i phi}`` the best unit phase factor (the orbit's time origin is arbitrary; its
amplitude is not, unlike a linear mode's) and ``c`` the reference angle
(:func:`psi_offset`): a recording's tangent angle is measured from an arbitrary
direction (the camera's x axis), psi_obs = psi_true + c, so in the lab frame psi_0 is
compared up to a constant, projected out analytically (c = the 1 / sigma^2-weighted mean
of psi0_obs - psi0_model: no extra variable, and the Jacobian through it stays exact; a
fit counts it as one fitted value, :attr:`axojax.inverse.Problem.n_offsets`). Its slope,
the static curvature, and psi_1 are unaffected. In the basal frame
(``shape.frame == "basal"``) model and data are both measured from the basal tangent,
psi(s, t) - psi(0, t), a direction that is not arbitrary: c = 0 there. Pure and
differentiable in ``params`` and
``kappa`` (the orbit by the implicit function theorem, :mod:`axojax.orbits.newton`):
``jax.jacfwd`` of it is the Jacobian a Levenberg-Marquardt step needs.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..beats.targets import ShapeTarget, Target
from ..models.section import Model
from ..orbits.cycle import LimitCycle
from ..orbits.measures import CycleMeasures, cycle_measures, tangent_modes
from ..orbits.solvers import AbstractOrbitSolver, HarmonicBalance
from ..params import Params
from ..units import Units

CYCLE_TARGETS = CycleMeasures.SCALARS
ALIASES = {"amplitude_um": "tip_amplitude_um"}
"""Names of :data:`axojax.beats.targets.CYCLE_SCALARS` that differ from the measures'."""


@dataclasses.dataclass(frozen=True)
class CycleTarget:
    """A scalar measure of the limit cycle (a name of :data:`CYCLE_TARGETS`, physical
    units) observed as ``value +- sigma``."""

    name: str
    value: float
    sigma: float

    def __post_init__(self) -> None:
        name = ALIASES.get(self.name, self.name)
        object.__setattr__(self, "name", name)
        if name not in CYCLE_TARGETS:
            raise ValueError(
                f"unknown limit-cycle target {self.name!r}; choose from {', '.join(CYCLE_TARGETS)}"
            )
        if not math.isfinite(self.value):
            raise ValueError(f"target {self.name} must be finite, got {self.value!r}")
        if not (math.isfinite(self.sigma) and self.sigma > 0):
            raise ValueError(f"uncertainty of target {self.name} must be > 0, got {self.sigma!r}")

    @classmethod
    def of(cls, target: CycleTarget | Target) -> CycleTarget:
        """A :class:`CycleTarget` from itself or from a fitting ``Target`` with
        ``source="limit_cycle"``."""
        if isinstance(target, CycleTarget):
            return target
        if isinstance(target, Target) and target.source == "limit_cycle":
            return cls(target.name, target.value, target.sigma)
        raise ValueError(f"not a limit-cycle target: {target!r}")


def offset_fitted(shape: ShapeTarget | None) -> bool:
    """Whether ``shape``'s psi_0 is compared up to a constant (:func:`psi_offset`): a
    limit-cycle shape with psi_0, in the lab frame."""
    return (
        shape is not None
        and shape.source == "limit_cycle"
        and shape.psi0 is not None
        and shape.frame == "lab"
    )


def shape_measures(cycle: LimitCycle, shape: ShapeTarget, units: Units) -> CycleMeasures:
    """The orbit's measures at ``shape.s_um`` in the shape's frame: psi_0 and psi_1 as
    they are (``"lab"``), or less their values at the base s = 0 (``"basal"``, as
    :func:`axojax.beats.frames.in_basal_frame` does to the data: 0 for a clamped base)."""
    m = cycle_measures(cycle, np.asarray(shape.s_um, dtype=float), units)
    if shape.frame != "basal":
        return m
    _, psi0_b, psi1_b = tangent_modes(cycle, np.zeros(1), units)
    return eqx.tree_at(lambda x: (x.psi0, x.psi1), m, (m.psi0 - psi0_b[0], m.psi1 - psi1_b[0]))


def psi_offset(measures: CycleMeasures, shape: ShapeTarget) -> Float[Array, ""]:
    """The reference angle c (rad) that best fits ``shape``'s psi_0 to the orbit's,
    psi0_obs ~ psi0_model + c: the 1 / sigma^2-weighted mean of psi0_obs - psi0_model over
    the shape's points (``measures`` taken at ``shape.s_um``, :func:`shape_measures`); 0
    where it is not fitted (:func:`offset_fitted`: the basal frame, or no psi_0)."""
    if not offset_fitted(shape):
        return jnp.zeros(())
    obs = jnp.asarray(shape.psi0, dtype=float)
    w = 1.0 / jnp.asarray(shape.sigma, dtype=float) ** 2 * jnp.ones(obs.shape)
    return jnp.sum(w * (obs - measures.psi0)) / jnp.sum(w)


def shape_residuals(measures: CycleMeasures, shape: ShapeTarget) -> Float[Array, " r"]:
    """psi_0 (when observed; up to :func:`psi_offset`) and psi_1 residuals of
    ``measures`` (taken at ``shape.s_um`` in its frame, :func:`shape_measures`)."""
    sigma = jnp.asarray(shape.sigma, dtype=float)
    out = []
    if shape.psi0 is not None:
        fitted = measures.psi0 + psi_offset(measures, shape)
        out.append((fitted - jnp.asarray(shape.psi0, dtype=float)) / sigma)
    obs = jnp.asarray(shape.psi1, dtype=complex)
    d = (_phase(measures, shape) * measures.psi1 - obs) / sigma
    out += [jnp.real(d), jnp.imag(d)]
    return jnp.concatenate(out)


def _phase(measures: CycleMeasures, shape: ShapeTarget):
    """Best unit factor e^{i phi} for the model's psi_1 (the orbit's time origin is
    arbitrary), weighted by 1 / sigma^2 over the shape's points."""
    obs = jnp.asarray(shape.psi1, dtype=complex)
    w = 1.0 / jnp.asarray(shape.sigma, dtype=float) ** 2 * jnp.ones(obs.shape)
    z = jnp.sum(w * jnp.conj(measures.psi1) * obs)
    return z / jnp.maximum(jnp.abs(z), 1e-300)


def aligned_psi1(measures: CycleMeasures, shape: ShapeTarget, at: CycleMeasures | None = None):
    """The orbit's psi_1, turned by the unit phase that best fits ``shape``
    (``measures`` taken at ``shape.s_um``): at ``measures``' points, or at ``at``'s (the
    fitted psi_1 a report draws beside the observed, on every observed point)."""
    return _phase(measures, shape) * (measures if at is None else at).psi1


def scalar_residuals(
    measures: CycleMeasures, scalars: Sequence[CycleTarget | Target]
) -> Float[Array, " k"]:
    """(measure - value) / sigma for each scalar target."""
    ts = [CycleTarget.of(t) for t in scalars]
    if not ts:
        return jnp.zeros(0)
    return jnp.stack([(getattr(measures, t.name) - t.value) / t.sigma for t in ts])


def waveform_residuals(
    model: Model,
    params: Params,
    kappa: Float[Array, ""] | float,
    *,
    shape: ShapeTarget | None = None,
    scalars: Sequence[CycleTarget | Target] = (),
    solver: AbstractOrbitSolver = HarmonicBalance(floquet=0),
    start: LimitCycle | None = None,
    units: Units = Units(),
) -> Float[Array, " r"]:
    """Normalised residuals of the limit cycle at (``params``, ``kappa``) against an
    observed waveform (see the module docstring).

    Args:
        model: static; its ``imbalance_kind`` says how ``params.imbalance`` is read.
        params: dimensionless parameters (may be traced: p, a0, imbalance, cubic... free).
        kappa: cubic link stiffening (1/L^2), may be traced.
        shape: observed psi_1 (and psi_0, compared up to a constant in the lab frame) at
            ``shape.s_um`` (um), absolute amplitude.
        scalars: scalar targets (:class:`CycleTarget`, or fitting ``Target`` with
            ``source="limit_cycle"``).
        solver: the orbit solver (``floquet=0``: fits need no multipliers).
        start: a nearby orbit (warm start; e.g. the previous iterate's); None starts
            from the Hopf normal form.
        units: physical units.

    Returns:
        (r,) residuals; where Newton fails they are those of the solver's finite
        stand-in (with zero derivative), so a fit can step back.
    """
    cyc = solver.solve(model, params, kappa, start)
    parts = []
    if shape is not None:
        parts.append(shape_residuals(shape_measures(cyc, shape, units), shape))
    if scalars:
        parts.append(scalar_residuals(cycle_measures(cyc, None, units), scalars))
    if not parts:
        raise ValueError("waveform_residuals needs a shape or at least one scalar target")
    return jnp.concatenate(parts)
