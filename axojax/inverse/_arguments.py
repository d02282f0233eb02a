"""Checks of :class:`~axojax.inverse.Problem`'s arguments that need no model, and the
fitted coordinate of each free parameter (kept apart so that ``problem.py`` stays short)."""

from __future__ import annotations

import math

from ..params import MECHANISM_NAMES, NORMAL_NAMES, PARAM_NAMES, is_parameter_name
from .conditions import Condition
from .parameters import ORBIT_FIELDS, coordinate_bounds

SIGNED = frozenset(MECHANISM_NAMES) - {"omega0"}
"""Regulated-dynein coefficients (chi', chi'', beta', beta''): signed, so fitted in a linear
coordinate like ``gamma`` (give their bounds, e.g. :func:`axojax.inverse.comparison.mechanisms.row`)."""


def _coordinate_bounds(name: str, bounds: dict) -> tuple[bool, float, float]:
    """:func:`coordinate_bounds`, with the signed mechanism coefficients linear."""
    if name not in SIGNED:
        return coordinate_bounds(name, bounds)
    if name not in bounds:
        raise ValueError(f"bounds: no bounds for {name!r}; give bounds={{{name!r}: (low, high)}}")
    a, b = (float(v) for v in bounds[name])
    if not (math.isfinite(a) and math.isfinite(b) and a < b):
        raise ValueError(f"bounds of {name} must satisfy low < high, got ({a:g}, {b:g})")
    return False, a, b


def _check(conditions, free, per_condition, kl_ratio, shape_floor, exclude_base_um):
    """The conditions (a list) and their labels, after checking every argument of
    :class:`Problem` that needs no model (one-line ``ValueError`` / ``TypeError``)."""
    conditions = list(conditions)
    if not conditions:
        raise ValueError("conditions: give at least one condition")
    for c in conditions:
        if not isinstance(c, Condition):
            raise TypeError(f"conditions must be axojax.inverse.Condition, got {c!r}")
    free, per_condition = list(free), list(per_condition)
    if not free and not per_condition:
        raise ValueError("free: name at least one parameter to fit")
    for name in free + per_condition:
        if not is_parameter_name(name) and name not in ORBIT_FIELDS:
            raise ValueError(
                f"free: unknown parameter {name!r}; choose from {', '.join((*PARAM_NAMES, *sorted(ORBIT_FIELDS)))}"
            )
    both = set(free) & set(per_condition)
    if both or len(set(free)) < len(free) or len(set(per_condition)) < len(per_condition):
        raise ValueError(
            f"free: each parameter once, shared or per condition (repeated: {', '.join(sorted(both)) or 'a name'})"
        )
    if kl_ratio is not None:
        if not (math.isfinite(kl_ratio) and kl_ratio > 0):
            raise ValueError(f"kl_ratio must be > 0, got {kl_ratio!r}")
        if "kl" in free + per_condition:
            raise ValueError("free: kl is tied to ks by kl_ratio; fit ks instead")
    if not (math.isfinite(shape_floor) and shape_floor >= 0):
        raise ValueError(f"shape_floor must be >= 0 (rad), got {shape_floor!r}")
    if not (math.isfinite(exclude_base_um) and exclude_base_um >= 0):
        raise ValueError(f"exclude_base_um must be >= 0 (um), got {exclude_base_um!r}")
    labels = [str(i) if c.label is None else str(c.label) for i, c in enumerate(conditions)]
    if len(set(labels)) < len(labels):
        raise ValueError(f"conditions: labels must differ, got {labels}")
    return conditions, labels


def check_normal_force(solver, shift, needs_cycle, models, base, fitted) -> None:
    """Normal-force control (a gain free, or non-zero in ``base``, the conditions'
    params) needs its own eigen-solver (:class:`~axojax.eigen.NormalForce`: the augmented
    pencil) and the beat's ``shift``, and has no limit cycle yet; the plain solvers would
    drop the gain silently. One-line ``ValueError``."""
    from ..assembly.normal_force import check_normal_model
    from ..eigen.normal_force import NormalForce

    gains = set(fitted) & set(NORMAL_NAMES) or {
        n for prm in base for n in NORMAL_NAMES if float(getattr(prm, n)) != 0.0
    }
    if isinstance(solver, NormalForce):
        if shift is None:
            raise ValueError(
                "shift: normal-force control follows the beat nearest a shift; give "
                "shift=1j * omega0"
            )
        if any(needs_cycle):
            raise ValueError(
                "targets: normal-force control has no limit cycle yet; fit psi_1 and the "
                "linear beat (source='linear')"
            )
        for model, prm in zip(models, base):
            check_normal_model(model, prm)
    elif gains:
        raise ValueError(
            f"solver: {', '.join(sorted(gains))} (normal-force control) needs "
            "solver=ax.eigen.NormalForce() and shift=1j * omega0"
        )
