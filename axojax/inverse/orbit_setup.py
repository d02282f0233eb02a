"""How a fit solves its limit cycles: the orbit solver, the cubic link stiffening and, for a
regulated mechanism, the motor kinetics (relaxation time ``tau_m``) and saturation
(``f_sat``), each fixed or fitted (:data:`~axojax.inverse.parameters.ORBIT_FIELDS`).

A regulated whole-beat fit (issue 47 item 4) is a :class:`~axojax.inverse.Problem` whose
orbit has motors: its limit cycle is that of :func:`axojax.limit_cycle` with ``tau_m=``
and ``f_sat=`` (:mod:`axojax.orbits.motors`), differentiated by the implicit function
theorem through the harmonic balance like the steady load's.
"""

from __future__ import annotations

import dataclasses
import math

import jax.numpy as jnp

from ..models.section import Model
from ..orbits.cycle import LimitCycle
from ..orbits.motors import Motors
from ..orbits.solvers import AbstractOrbitSolver, WarmStart, call_solve
from ..params import Params
from .parameters import ORBIT_FIELDS

WARM_STEPS = 10  # Newton iterations a warm-started orbit gets before the Hopf guess takes over


def without_floquet(solver: AbstractOrbitSolver) -> AbstractOrbitSolver:
    """``solver`` with its Floquet multipliers switched off, also inside wrappers that hold
    another solver (``WarmStart``, ``Recording``: their ``solver`` field)."""
    if getattr(solver, "floquet", 0):
        return dataclasses.replace(solver, floquet=0)
    inner = getattr(solver, "solver", None)
    if isinstance(inner, AbstractOrbitSolver):
        return dataclasses.replace(solver, solver=without_floquet(inner))
    return solver


@dataclasses.dataclass(frozen=True)
class OrbitSetup:
    """The fixed values of the orbit's options and its solver.

    Attributes:
        solver: the orbit solver (Floquet multipliers off: fits need none).
        cubic: the links' cubic stiffening kappa (1/L^2); > 0, or >= 0 with saturating
            motors (``f_sat``), which bound the beat themselves.
        tau_m: the motors' relaxation time (dimensionless, seconds / ``Units.tau_s``), or
            None: no motor kinetics (the friction form, passive friction only).
        f_sat: the motors' saturation force per length (dimensionless, scaled as p), or
            None: linear motors. Needs ``tau_m``.
    """

    solver: AbstractOrbitSolver
    cubic: float
    tau_m: float | None = None
    f_sat: float | None = None

    def start(self, name: str) -> float:
        """The start of a free orbit option ``name`` (its fixed value)."""
        value = {"cubic": self.cubic, "tau_m": self.tau_m, "f_sat": self.f_sat}[name]
        if value is None:
            flag = {"tau_m": "tau_m (--motor-tau-ms)", "f_sat": "f_sat (--motor-saturation)"}
            raise ValueError(f"free: {name} is fitted from its given value; give {flag[name]}")
        return float(value)

    def check(self, models: list[Model], needs_cycle: list[bool], fitted: set) -> OrbitSetup:
        """This setup, checked against the problem (one-line ``ValueError``), with the
        solver's Floquet multipliers off; orbit options fitted without any limit-cycle
        target are refused (nothing depends on them)."""
        if self.f_sat is not None and self.tau_m is None:
            raise ValueError("f_sat: saturating motors need motor kinetics (give tau_m)")
        for name in ("tau_m", "f_sat"):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
        if not any(needs_cycle):
            if fitted & ORBIT_FIELDS:
                names = ", ".join(sorted(fitted & ORBIT_FIELDS))
                raise ValueError(
                    f"free: {names} act on the limit cycle only; only limit-cycle targets "
                    "(source='limit_cycle') depend on them"
                )
            return self
        saturating = self.f_sat is not None or "f_sat" in fitted
        if not (math.isfinite(self.cubic) and (self.cubic > 0 or saturating and self.cubic >= 0)):
            bound = ">= 0 (with saturating motors)" if saturating else "> 0"
            raise ValueError(
                f"cubic must be a finite number {bound} for limit-cycle targets, got {self.cubic!r}"
            )
        for m, need in zip(models, needs_cycle):
            if need and m.link_B.shape[0] == 0 and not saturating:
                raise ValueError(
                    f"limit-cycle targets need a model with links or saturating motors; "
                    f"{m.name!r} has no links"
                )
        return dataclasses.replace(self, solver=without_floquet(self.solver))

    def options(self, fitted: dict) -> tuple:
        """(kappa, motors) at the fitted values ``fitted`` ({field: value}, traceable):
        a free option's fitted value, else its fixed one; motors None without tau_m."""
        kappa = fitted.get("cubic", self.cubic)
        tau_m = fitted.get("tau_m", self.tau_m)
        if tau_m is None:
            return kappa, None
        f_sat = fitted.get("f_sat", self.f_sat)
        return kappa, Motors(
            tau_m=jnp.asarray(tau_m, dtype=float),
            f_sat=None if f_sat is None else jnp.asarray(f_sat, dtype=float),
        )

    def values(self, fitted: dict) -> dict[str, float]:
        """The options at the fitted values (concrete), for a report: ``cubic``, and with
        motor kinetics ``tau_m`` (and ``f_sat`` for saturating motors)."""
        kappa, motors = self.options(fitted)
        out = {"cubic": float(kappa)}
        if motors is not None:
            out["tau_m"] = float(motors.tau_m)
            if motors.f_sat is not None:
                out["f_sat"] = float(motors.f_sat)
        return out

    def solve(
        self, model: Model, params: Params, fitted: dict, start: LimitCycle | None
    ) -> LimitCycle:
        """The orbit at ``params`` and the fitted options: cold (Hopf normal form) without
        ``start``, else warm-started from it (:class:`~axojax.orbits.solvers.WarmStart`)."""
        kappa, motors = self.options(fitted)
        solver = self.solver if start is None else WarmStart(self.solver, WARM_STEPS)
        return call_solve(solver, model, params, kappa, start, motors)
