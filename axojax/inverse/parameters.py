"""The free parameters of an inverse problem: which, shared or per condition, their bounds
and fitted coordinate, and the logistic map between the bounded coordinate and R^k.

Fitted coordinate ``u``: ``log(value)`` for positive quantities (every field of
:class:`~axojax.Params` but ``gamma``), ``value`` itself for :data:`LINEAR` ones (the
signed gain ``gamma``; the basal compliance ``cb``, from 0).
Bounds are given as values and held as ``(lower, upper)`` in ``u``. Unconstrained
optimisers and samplers work in ``z`` in R^k, ``u = lower + (upper - lower) sigmoid(z)``.

Names: a shared parameter is named like its :class:`~axojax.Params` field (``"ks"``); one
fitted separately in every condition is ``"<field>@<label>"`` (``"p@150"``), the label
being the condition's (default: its index, ``"p@0"``).
"""

from __future__ import annotations

import dataclasses
import math

from ..params import knot_element

DEFAULT_BOUNDS = {
    "p": (10.0, 1e4),
    "ks": (1e1, 1e8),
    "kl": (1e-1, 1e7),
    "cl": (1e-5, 1e2),
    "gamma": (-3.0, 3.0),
    "ktheta": (1e-3, 1e4),
    "out_of_plane": (0.1, 10.0),
    "inactive_factor": (0.1, 1e3),
    "imbalance": (0.1, 10.0),
    "a0": (1e-4, 1.0),
    "cubic": (1e-3, 1e4),
    "tau_m": (1e-7, 1e3),
    "f_sat": (1e-3, 1e7),
    "m0": (-1e4, 1e4),
    "ei_knots": (0.01, 100.0),
    "drag_knots": (0.01, 100.0),
    "p_knots": (1e-3, 100.0),
}
"""Value bounds by name; a knot value (``"ei_knots[2]"``) takes its profile's bounds
(relative values, 1 = uniform) unless given by its own name."""
ORBIT_FIELDS = frozenset({"cubic", "tau_m", "f_sat"})
"""Free parameters that are not :class:`~axojax.Params` fields but options of the limit
cycle (only limit-cycle targets depend on them): ``cubic``, the link stiffening kappa
(1/L^2) of ``C dq/dt = -A q - f_nl(q) + b``; ``tau_m`` and ``f_sat``, the motor kinetics'
relaxation time and the motors' saturation of a regulated mechanism (dimensionless, as
:func:`axojax.limit_cycle` takes them)."""
LINEAR = frozenset({"gamma", "cb", "m0"})
"""Fitted linearly: the signed gain gamma, the signed static moment m0, and the basal
compliance cb, whose range starts at 0 (a rigid base, the base without compliance)."""


@dataclasses.dataclass(frozen=True)
class FreeParameter:
    """One fitted value.

    Attributes:
        name: its label in results (``"ks"`` or ``"p@150"``).
        field: the :class:`~axojax.Params` field it sets, or ``"cubic"`` (the limit
            cycle's link stiffening, :data:`ORBIT_FIELDS`).
        condition: index of the condition it belongs to, or None when shared.
        log: fitted in log space (positive quantities) or linearly (gamma).
        lower, upper: bounds in the fitted coordinate u.
    """

    name: str
    field: str
    condition: int | None
    log: bool
    lower: float
    upper: float

    def to_value(self, u):
        """u -> the dimensionless value (works on floats and traced arrays)."""
        import jax.numpy as jnp

        return jnp.exp(u) if self.log else u

    def to_u(self, value: float) -> float:
        return math.log(value) if self.log else float(value)


def coordinate_bounds(
    field: str, bounds: dict[str, tuple[float, float]]
) -> tuple[bool, float, float]:
    """(log?, lower u, upper u) of ``field`` from value bounds; one-line ValueError if bad."""
    element = knot_element(field)
    if field not in bounds and element is not None and element[0] in bounds:
        bounds = {field: bounds[element[0]]}
    if field not in bounds:
        raise ValueError(f"bounds: no bounds for {field!r}; give bounds={{{field!r}: (low, high)}}")
    a, b = (float(v) for v in bounds[field])
    log = field not in LINEAR
    if not (math.isfinite(a) and math.isfinite(b) and a < b) or (log and a <= 0):
        raise ValueError(
            f"bounds of {field} must satisfy 0 < low < high (log) or low < high, got ({a:g}, {b:g})"
        )
    return log, (math.log(a) if log else a), (math.log(b) if log else b)
