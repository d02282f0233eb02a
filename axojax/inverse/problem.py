"""The inverse problem: model(s), conditions, free parameters, and one traced residual
function over every condition.

``Problem`` holds what every solver shares (least squares, samplers, profiles): the
model (or one per condition) and units, the :class:`~axojax.inverse.Condition` s, the free
parameters (shared, or one per condition, each with bounds and a fitted coordinate, see
:mod:`axojax.inverse.parameters`), the tie ``kl = ks / kl_ratio`` and a prior. Its
``residuals(u)`` is one jax-traceable function of the fitted coordinates ``u`` (k,):
normalised residuals ``(model - observed) / sigma`` of every target of every condition,
with exact derivatives through the dominant eigenpair (and the limit cycle, by the
implicit function theorem). Conditions that share a model have their dominant modes
computed in one ``jax.vmap``.

Contract used by the samplers (:mod:`axojax.inverse.sampling.posterior`): ``names``, ``lower``,
``upper``, ``u0``, ``residuals(u)``, ``log_prior(u)``, ``to_u(z)``, ``to_z(u)``,
``log_density(z)``, ``values(u)``.

Shape targets. The model's psi_1 is a linear eigenmode of an idealised axoneme with a
clamped base; a measured beat is a finite-amplitude, noisy limit cycle of a real one. A
statistical sigma of psi_1 from many clean cycles can be 0.01 rad or less, and a fit
would then call a 0.05 rad shape difference "24 sigma". ``shape_floor`` (rad) adds a
model-discrepancy term in quadrature, ``sigma_eff = sqrt(sigma^2 + floor^2)``. The default,
0.05 rad (about 3 degrees), is the accuracy of tangent angles from tracked centrelines
(a few pixels over a micrometre-scale segment) and about 5-10 % of a typical |psi_1|
of 0.5-1 rad: a shape that differs by less is as good as the model can claim.
``exclude_base_um`` leaves out the observed points with s < exclude (a basal body that
swings cannot be followed by a clamped base); the misfit there, evaluated at the
optimum with the complex scale fitted to the kept points, is reported separately.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..beats.targets import SCALARS, ShapeTarget
from ..eigen.mode import DEFAULT_SOLVER, dominant_mode_impl
from ..eigen.nearest import nearest_mode_impl
from ..eigen.solvers import AbstractEigenSolver
from ..models.section import Model
from ..orbits.cycle import LimitCycle
from ..orbits.solvers import AbstractOrbitSolver, HarmonicBalance
from ..params import DEFAULT_CUBIC, Params
from ..units import Units
from ._arguments import _check, _coordinate_bounds, check_normal_force
from .conditions import Condition
from .cycle_targets import CYCLE_TARGETS as CYCLE_MEASURES
from .cycle_targets import aligned_psi1, offset_fitted, psi_offset, shape_measures
from .cycle_targets import shape_residuals as cycle_shape_residuals
from .fingerprint import problem_fingerprint
from .orbit_setup import WARM_STEPS, OrbitSetup  # noqa: F401  (WARM_STEPS: its docstrings)
from .parameters import DEFAULT_BOUNDS, ORBIT_FIELDS, FreeParameter
from .predictions import cycle_values, scalar_value, shape_fit

SHAPE_FLOOR = 0.05  # rad: model-discrepancy floor of psi_1 (module docstring)
CYCLE_FAILED = 1e3  # normalised residual of a limit-cycle target where no orbit is found
EDGE = 1e-9  # starts are kept this fraction of the range inside the bounds


def _stack(params: Sequence[Params]) -> Params:
    """A batch (leading axis) of parameter points that share their knot profiles' shapes."""
    return jax.tree.map(lambda *xs: jnp.stack([jnp.asarray(x, dtype=float) for x in xs]), *params)


@dataclasses.dataclass(frozen=True)
class _Layout:
    """Where condition i's residuals sit: [start, start + n_scalar) scalars, then 2 S shape."""

    start: int
    n_scalar: int
    n_shape: int


class Problem:
    """An inverse problem over one or several conditions.

    Args:
        model: the model (a condition may carry its own, ``Condition.model``).
        conditions: a sequence of :class:`~axojax.inverse.Condition`.
        free: parameters shared by all conditions (``Params`` fields, and the limit
            cycle's options when limit-cycle targets are given:
            :data:`~axojax.inverse.parameters.ORBIT_FIELDS`, ``"cubic"``, ``"tau_m"``,
            ``"f_sat"``).
        per_condition: parameters fitted separately in every condition (named
            ``"<field>@<label>"``).
        params: base values of every parameter (each condition's ``params`` override
            them); the start of the free ones.
        bounds: per field ``(low, high)`` in values; defaults ``DEFAULT_BOUNDS``.
        kl_ratio: tie ``kl = ks / kl_ratio`` in every condition (fit ks, not kl).
        units: physical units of the targets.
        solver: dominant-eigenpair solver.
        cubic, orbit_solver: limit-cycle setup for targets with ``source="limit_cycle"``
            (``cubic``: kappa, 1/L^2; the start when it is free).
        tau_m, f_sat: the limit cycle's motor kinetics and saturation
            (:class:`~axojax.inverse.orbit_setup.OrbitSetup`; dimensionless; the starts
            when free). None (default): none, the friction form.
        shape_floor: model-discrepancy floor (rad) added in quadrature to psi_1's sigma.
        exclude_base_um: drop observed shape points with s < this (um).
        prior: optional ``log_prior(u) -> scalar``; default 0 (uniform in u).
        shift: None (default): the beat is the dominant mode (the steady load). A complex
            number (dimensionless, 1/tau): the beat is the eigenvalue nearest it, e.g.
            ``1j * omega0`` for a regulated mechanism (docs/model.md section 8: with an
            active friction the beat is not the dominant mode); its solver must have a
            ``nearest`` method (:mod:`axojax.eigen.solvers`).
        mechanism, base: names the report carries (``FitResult.mechanism``, ``.base``);
            default: read from the parameters and the model.
    """

    def __init__(
        self,
        model: Model,
        conditions: Sequence[Condition],
        free: Sequence[str] = (),
        *,
        per_condition: Sequence[str] = (),
        params: Params = Params(),  # noqa: B008
        bounds: dict[str, tuple[float, float]] | None = None,
        kl_ratio: float | None = None,
        units: Units = Units(),  # noqa: B008
        solver: AbstractEigenSolver = DEFAULT_SOLVER,
        cubic: float = DEFAULT_CUBIC,
        orbit_solver: AbstractOrbitSolver = HarmonicBalance(),  # noqa: B008
        tau_m: float | None = None,
        f_sat: float | None = None,
        shape_floor: float = SHAPE_FLOOR,
        exclude_base_um: float = 0.0,
        prior: Callable[[Array], Array] | None = None,
        shift: complex | None = None,
        mechanism: str | None = None,
        base: str | None = None,
    ):
        conditions, labels = _check(
            conditions, free, per_condition, kl_ratio, shape_floor, exclude_base_um
        )
        free, per_condition = list(free), list(per_condition)
        self.model, self.units, self.solver = model, units, solver
        self.conditions, self.labels = conditions, labels
        self.kl_ratio, self.shape_floor, self.exclude_base_um = (
            kl_ratio,
            float(shape_floor),
            float(exclude_base_um),
        )
        self.prior = prior
        if shift is not None and not np.isfinite(complex(shift)):
            raise ValueError(f"shift must be a finite complex number, got {shift!r}")
        self.shift = None if shift is None else complex(shift)
        self.mechanism, self.base_name = mechanism, base
        self.free_shared, self.free_per_condition = tuple(free), tuple(per_condition)
        self.bounds = {**DEFAULT_BOUNDS, **(bounds or {})}
        self.base = [params.with_values(c.params).validate() for c in conditions]
        self.models = [c.model if c.model is not None else model for c in conditions]

        orbit = OrbitSetup(orbit_solver, float(cubic), tau_m, f_sat)
        self._set_parameters(params, free, per_condition, orbit)
        self._set_targets(orbit, set(free + per_condition))
        check_normal_force(
            solver, self.shift, self.needs_cycle, self.models, self.base, free + per_condition
        )
        self._set_layout()
        self._set_groups(solver)
        self._jit_residuals = jax.jit(self.residuals)
        self._jit_jacobian = jax.jit(jax.jacfwd(self.residuals))
        self._jit_evaluate = None

    def _set_parameters(
        self, params: Params, free: list, per_condition: list, orbit: OrbitSetup
    ) -> None:
        """The free parameters (shared, then per condition), their bounds in u and the
        start ``u0`` (a free orbit option starts at its given value)."""
        labels = self.labels
        start_of = lambda prm, name: (
            orbit.start(name) if name in ORBIT_FIELDS else float(prm.value_of(name))
        )  # noqa: E731
        out, u0 = [], []
        for name in free:
            log, lo, hi = _coordinate_bounds(name, self.bounds)
            out.append(FreeParameter(name, name, None, log, lo, hi))
            u0.append(start_of(params, name))
        for name in per_condition:
            log, lo, hi = _coordinate_bounds(name, self.bounds)
            for i, lab in enumerate(labels):
                out.append(FreeParameter(f"{name}@{lab}", name, i, log, lo, hi))
                u0.append(start_of(self.base[i], name))
        self.parameters: tuple[FreeParameter, ...] = tuple(out)
        self.names: tuple[str, ...] = tuple(p.name for p in out)
        self.lower = np.array([p.lower for p in out])
        self.upper = np.array([p.upper for p in out])
        self._log = np.array([p.log for p in out])
        u0 = np.array([p.to_u(v) if (v > 0 or not p.log) else p.lower for p, v in zip(out, u0)])
        span = self.upper - self.lower
        self.u0 = np.clip(u0, self.lower + EDGE * span, self.upper - EDGE * span)

    def _set_targets(self, orbit: OrbitSetup, fitted: set) -> None:
        """Shapes trimmed to s >= exclude (and the excluded part, for the report), scalar
        targets, and which conditions need the linear mode and which the limit cycle."""
        conditions = self.conditions
        self.shapes: list[ShapeTarget | None] = []
        self.shapes_excluded: list[ShapeTarget | None] = []
        for c in conditions:
            self.shapes.append(
                None if c.shape is None else self._prepare_shape(c.shape, keep=True, label=c.label)
            )
            self.shapes_excluded.append(
                None if c.shape is None else self._prepare_shape(c.shape, keep=False, label=c.label)
            )
        self.scalar_targets = [list(c.targets) for c in conditions]
        cycle_shape = [c.shape is not None and c.shape.source == "limit_cycle" for c in conditions]
        self.needs_mode = [
            any(t.source == "linear" for t in c.targets) or (c.shape is not None and not cs)
            for c, cs in zip(conditions, cycle_shape)
        ]
        self.needs_cycle = [
            any(t.source == "limit_cycle" for t in c.targets) or cs
            for c, cs in zip(conditions, cycle_shape)
        ]
        self.orbit = orbit.check(self.models, self.needs_cycle, fitted)

    def _set_layout(self) -> None:
        """Where each condition's scalar and shape residuals lie in the residual vector."""
        layout, start = [], 0
        for i in range(len(self.conditions)):
            n_scalar = len(self.scalar_targets[i])
            sh = self.shapes[i]
            n_shape = (
                0
                if sh is None
                else (2 + (sh.source == "limit_cycle" and sh.psi0 is not None))
                * len(np.asarray(sh.s_um))
            )
            layout.append(_Layout(start, n_scalar, n_shape))
            start += n_scalar + n_shape
        self.layout, self.n_residuals = layout, start

    def _set_groups(self, solver) -> None:
        """Conditions sharing a model (equal models: built alike), vmapped together, and
        the eigen-solver each group resolves to."""
        groups: dict[Model, list[int]] = {}
        for i, m in enumerate(self.models):
            if self.needs_mode[i]:
                groups.setdefault(m, []).append(i)
        self._groups = list(groups.values())
        self._solvers = {
            self.models[g[0]]: solver.resolve(self.models[g[0]], len(g)) for g in self._groups
        }

    # -- targets ---------------------------------------------------------------------
    def _prepare_shape(self, shape: ShapeTarget, keep: bool, label) -> ShapeTarget | None:
        s = np.asarray(shape.s_um, dtype=float)
        mask = s >= self.exclude_base_um if keep else s < self.exclude_base_um
        if keep and mask.sum() < 2:
            raise ValueError(
                f"exclude_base_um: {self.exclude_base_um:g} um leaves fewer than 2 shape "
                f"points (condition {label}); the data end at {s.max():g} um"
            )
        if not mask.any():
            return None
        sigma = np.broadcast_to(np.asarray(shape.sigma, dtype=float), s.shape)
        sigma = np.sqrt(sigma**2 + self.shape_floor**2)[mask]
        psi0 = None if shape.psi0 is None else np.asarray(shape.psi0)[mask]
        return ShapeTarget(
            s[mask],
            np.asarray(shape.psi1)[mask],
            sigma,
            psi0,
            shape.source,
            shape.component_at(mask),  # issue 33: each kept point's transverse component
            shape.frame,
        )

    def fingerprint(self) -> str:
        """sha256 (hex) of everything that determines the residuals, bounds, start and
        prior: the key of a posterior's warm-state cache (``TypeError`` with a callable
        prior: :func:`axojax.inverse.fingerprint.problem_fingerprint`)."""
        return problem_fingerprint(self)

    @property
    def n_conditions(self) -> int:
        return len(self.conditions)

    @property
    def n_offsets(self) -> int:
        """Reference angles projected out of the residuals (one per limit-cycle shape
        whose psi_0 is compared up to a constant: :mod:`.cycle_targets`)."""
        return sum(offset_fitted(s) for s in self.shapes)

    @property
    def dof(self) -> int:
        """Residuals minus fitted values, the reference angles included (chi^2 degrees
        of freedom)."""
        return self.n_residuals - len(self.names) - self.n_offsets

    # -- coordinates -----------------------------------------------------------------
    def to_u(self, z: Float[Array | np.ndarray, " k"]) -> Float[Array, " k"]:
        """Unconstrained z in R^k -> u inside the bounds (logistic)."""
        lo, hi = jnp.asarray(self.lower), jnp.asarray(self.upper)
        return lo + (hi - lo) * jax.nn.sigmoid(z)

    def to_z(self, u: Float[Array | np.ndarray, " k"]) -> Float[Array, " k"]:
        """u strictly inside the bounds -> z (inverse of :meth:`to_u`)."""
        lo, hi = jnp.asarray(self.lower), jnp.asarray(self.upper)
        frac = (jnp.asarray(u) - lo) / (hi - lo)
        return jnp.log(frac) - jnp.log1p(-frac)

    def log_jacobian(self, z: Float[Array | np.ndarray, " k"]) -> Float[Array, ""]:
        """log |du/dz| of the logistic map."""
        lo, hi = jnp.asarray(self.lower), jnp.asarray(self.upper)
        return jnp.sum(jnp.log(hi - lo) + jax.nn.log_sigmoid(z) + jax.nn.log_sigmoid(-z))

    def log_prior(self, u: Float[Array | np.ndarray, " k"]) -> Float[Array, ""]:
        """log prior density in u (0: uniform in the fitted coordinate within the bounds)."""
        return jnp.zeros(()) if self.prior is None else jnp.asarray(self.prior(u))

    def log_density(self, z: Float[Array | np.ndarray, " k"]) -> Float[Array, ""]:
        """Unnormalised log posterior density in z: -|r(u)|^2 / 2 + log prior(u) + log|du/dz|."""
        u = self.to_u(z)
        r = self.residuals(u)
        return -0.5 * jnp.sum(r**2) + self.log_prior(u) + self.log_jacobian(z)

    def values(self, u) -> dict[str, float]:
        """Dimensionless values of the fitted parameters by name (concrete u)."""
        u = np.asarray(u, dtype=float)
        return {p.name: float(np.exp(x) if p.log else x) for p, x in zip(self.parameters, u)}

    def condition_params(self, u, i: int) -> Params:
        """The complete :class:`Params` of condition ``i`` at ``u`` (traceable)."""
        values = {f: v for f, v in self._fitted_values(u, i).items() if f not in ORBIT_FIELDS}
        return self.base[i].with_values(values, self.kl_ratio)

    @property
    def cubic(self) -> float:
        """The limit cycle's fixed (or starting) link stiffening kappa, 1/L^2."""
        return self.orbit.cubic

    @property
    def orbit_solver(self) -> AbstractOrbitSolver:
        """The orbit solver (Floquet multipliers off when limit cycles are fitted)."""
        return self.orbit.solver

    def condition_cubic(self, u, i: int):
        """The limit cycle's link stiffening kappa (1/L^2) in condition ``i`` at ``u``:
        fitted when ``"cubic"`` is free, else the problem's ``cubic`` (traceable)."""
        return self._fitted_values(u, i).get("cubic", self.cubic)

    def _fitted_values(self, u, i: int) -> dict:
        """{field: value} of the free parameters that act in condition ``i`` at ``u``."""
        return {
            p.field: p.to_value(u[j])
            for j, p in enumerate(self.parameters)
            if p.condition is None or p.condition == i
        }

    # -- the model's predictions -----------------------------------------------------
    def _mode(self, model: Model, prm: Params, solver):
        """The beat's mode: the dominant one, or the one nearest ``shift``."""
        if self.shift is None:
            return dominant_mode_impl(model, prm, solver)
        return nearest_mode_impl(model, prm, self.shift, solver)

    def modes(self, u) -> list:
        """The beat's mode of every condition (None where no target needs it): the
        dominant mode, or the one nearest ``shift``."""
        out: list = [None] * self.n_conditions
        for group in self._groups:
            model = self.models[group[0]]
            solver = self._solvers[model]
            prms = [self.condition_params(u, i) for i in group]
            if len(group) == 1:
                out[group[0]] = self._mode(model, prms[0], solver)
                continue
            batch = jax.vmap(
                lambda prm, model=model, solver=solver: self._mode(model, prm, solver)
            )(_stack(prms))
            for k, i in enumerate(group):
                out[i] = jax.tree_util.tree_map(lambda x, k=k: x[k], batch)
        return out

    def cycles(self, u, starts: Sequence[LimitCycle | None] | None = None) -> list:
        """Limit cycle of every condition with limit-cycle targets (None elsewhere).

        Args:
            u: (k,) fitted coordinates (may be traced).
            starts: per condition, a nearby orbit to start Newton from (warm start: a
                fit passes the orbits of its last accepted iterate) or None; None for
                all: every orbit from the Hopf normal form (the cold path). Starts are
                data: never differentiated (the orbit's derivative is the implicit
                function theorem's at the solution, whatever the start). Solved by
                :class:`~axojax.orbits.solvers.WarmStart` around the orbit solver: an
                unconverged start is no start; where Newton fails within ``WARM_STEPS``
                iterations, the orbit is solved again from the Hopf normal form, so a
                warm-started evaluation returns the cold one's orbit (up to the solver's
                tolerance and the arbitrary time origin).
        """
        starts = [None] * self.n_conditions if starts is None else list(starts)
        if len(starts) != self.n_conditions:
            raise ValueError(f"starts: one per condition ({self.n_conditions}), got {len(starts)}")
        return [
            self._cycle(i, u, starts[i]) if need else None
            for i, need in enumerate(self.needs_cycle)
        ]

    def _cycle(self, i: int, u, start: LimitCycle | None) -> LimitCycle:
        prm, fitted = self.condition_params(u, i), self._fitted_values(u, i)
        return self.orbit.solve(self.models[i], prm, fitted, start)

    def residuals(
        self, u: Float[Array | np.ndarray, " k"], starts: Sequence[LimitCycle | None] | None = None
    ) -> Float[Array, " m"]:
        """Normalised residuals (model - observed) / sigma of every target of every
        condition, in condition order: scalar targets, then Re and Im of the shape.
        ``starts``: warm starts of the limit cycles (:meth:`cycles`; None: cold)."""
        return self.residuals_and_cycles(u, starts)[0]

    def residuals_and_cycles(
        self, u: Float[Array | np.ndarray, " k"], starts: Sequence[LimitCycle | None] | None = None
    ) -> tuple[Float[Array, " m"], list]:
        """(:meth:`residuals`, :meth:`cycles`) at ``u``: the orbits are those a fit
        passes back as the next evaluation's ``starts``."""
        u = jnp.asarray(u)
        modes, cycles = self.modes(u), self.cycles(u, starts)
        parts = []
        for i in range(self.n_conditions):
            mode, cycle = modes[i], cycles[i]
            on_cycle = [t.name for t in self.scalar_targets[i] if t.source == "limit_cycle"]
            measured = cycle_values(cycle, on_cycle, self.units) if on_cycle else {}
            for t in self.scalar_targets[i]:
                if t.source == "limit_cycle":
                    r = (measured[t.name] - t.value) / t.sigma
                    parts.append(jnp.where(cycle.converged, r, CYCLE_FAILED)[None])
                else:
                    parts.append(
                        ((scalar_value(mode, t.name, self.units) - t.value) / t.sigma)[None]
                    )
            shape = self.shapes[i]
            if shape is not None and shape.source == "limit_cycle":
                # The whole waveform against the orbit: psi_0 (up to the reference angle),
                # psi_1 in absolute amplitude.
                measures = shape_measures(cycle, shape, self.units)
                parts.append(
                    jnp.where(cycle.converged, cycle_shape_residuals(measures, shape), CYCLE_FAILED)
                )
            elif shape is not None:
                fitted, _ = shape_fit(self.models[i], mode, shape, self.units)
                r = (jnp.asarray(shape.psi1) - fitted) / jnp.asarray(shape.sigma)
                parts.append(jnp.concatenate([jnp.real(r), jnp.imag(r)]))
        return jnp.concatenate(parts), cycles

    def loss(self, u) -> Float[Array, ""]:
        """0.5 |residuals(u)|^2."""
        return 0.5 * jnp.sum(self.residuals(u) ** 2)

    def residuals_at(self, u) -> np.ndarray:
        """(m,) residuals at a concrete u (compiled once per problem), as numpy."""
        return np.asarray(self._jit_residuals(jnp.asarray(u, dtype=float)))

    def jacobian(self, u) -> np.ndarray:
        """(m, k) exact d residuals / d u (forward mode, compiled once)."""
        return np.asarray(self._jit_jacobian(jnp.asarray(u, dtype=float)))

    def evaluate(self, u) -> dict[str, Any]:
        """Everything a report needs at a concrete u (one compiled program, built once):
        residuals, Jacobian, every condition's scalar observables and, for shapes, the
        fitted psi_1 on all observed points (the excluded basal stretch included)."""
        if self._jit_evaluate is None:
            self._jit_evaluate = jax.jit(
                lambda u: (self.residuals(u), jax.jacfwd(self.residuals)(u), self._predictions(u))
            )
        r, J, preds = self._jit_evaluate(jnp.asarray(u, dtype=float))
        return {
            "r": np.asarray(r),
            "J": np.asarray(J),
            "conditions": jax.tree_util.tree_map(np.asarray, preds),
        }

    def _predictions(self, u) -> list[dict[str, Any]]:
        modes, cycles = self.modes(u), self.cycles(u)
        out = []
        for i in range(self.n_conditions):
            d: dict[str, Any] = {}
            if modes[i] is not None:
                achieved = {k: scalar_value(modes[i], k, self.units) for k in SCALARS}
                travels = (
                    modes[i].direction != 0
                )  # else no wavelength, as `axojax modes` says (NaN -> null)
                for k in ("wavelength_um", "velocity_um_per_s"):
                    achieved[k] = jnp.where(travels, achieved[k], jnp.nan)
                achieved["amplitude_dip"] = modes[i].amplitude_dip  # the wavelength's sensitivity
                d["achieved"] = achieved
                shape = self.conditions[i].shape
                if shape is not None:
                    fitted, alpha = shape_fit(
                        self.models[i],
                        modes[i],
                        self.shapes[i],
                        self.units,
                        at_um=np.asarray(shape.s_um),
                        at_component=shape.component,  # issue 33: per point, as observed
                    )
                    d["psi1_fit"], d["alpha"] = fitted, alpha
            if cycles[i] is not None:
                d["cycle"] = cycle_values(
                    cycles[i],
                    ("frequency_hz", "amplitude_um", "wavelength_um", *CYCLE_MEASURES),
                    self.units,
                )
                d["cycle_converged"] = cycles[i].converged
                shape = self.conditions[i].shape
                if shape is not None and shape.source == "limit_cycle":
                    every = shape_measures(cycles[i], shape, self.units)
                    kept = shape_measures(cycles[i], self.shapes[i], self.units)
                    c = psi_offset(kept, self.shapes[i])  # on the fitted points, as residuals
                    d["psi1_fit"] = aligned_psi1(kept, self.shapes[i], at=every)
                    d["psi0_fit"], d["psi_offset_rad"] = every.psi0 + c, c
            out.append(d)
        return out

    def prefer(self, u: Float[np.ndarray, "c k"] | None) -> None:
        """Starts to use before any other (e.g. exact Hopf points screened by their loss,
        :func:`axojax.inverse.comparison.starts.screened_starts`): :meth:`start_design` returns
        them first, clipped inside the bounds; None: none."""
        if u is None:
            self._preferred = None
            return
        u = np.atleast_2d(np.asarray(u, dtype=float))
        if u.shape[1] != len(self.names) or not np.all(np.isfinite(u)):
            raise ValueError(
                f"starts: expected finite (c, {len(self.names)}) values, got {u.shape}"
            )
        span = self.upper - self.lower
        self._preferred = np.clip(u, self.lower + EDGE * span, self.upper - EDGE * span)

    def start_design(self, n: int, seed: int = 0) -> np.ndarray:
        """(n, k) starts: the preferred ones (:meth:`prefer`) if any, then ``u0``, then
        a scrambled Sobol design of the bounded box (points kept 1e-9 of the range
        inside the bounds)."""
        if n < 1:
            raise ValueError(f"starts must be >= 1, got {n}")
        preferred = getattr(self, "_preferred", None)
        if preferred is not None:
            rest = self._design(max(n - len(preferred), 1), seed)
            return np.vstack([preferred, rest])[:n]
        return self._design(n, seed)

    def _design(self, n: int, seed: int) -> np.ndarray:
        k = len(self.names)
        if n == 1:
            return self.u0[None]
        import warnings

        from scipy.stats import qmc

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # Sobol balance warning for n not a power of 2
            unit = qmc.Sobol(d=k, scramble=True, seed=seed).random(n - 1)
        span = self.upper - self.lower
        design = self.lower + span * np.clip(unit, EDGE, 1 - EDGE)
        return np.vstack([self.u0[None], design])

    def describe(self) -> dict[str, Any]:
        """Plain-Python summary of the problem (names, bounds in values, conditions)."""
        return {
            "names": list(self.names),
            "bounds": {
                p.name: [
                    float(np.exp(p.lower) if p.log else p.lower),
                    float(np.exp(p.upper) if p.log else p.upper),
                ]
                for p in self.parameters
            },
            "coordinate": {p.name: "log" if p.log else "linear" for p in self.parameters},
            "kl_ratio": self.kl_ratio,
            "shape_floor_rad": self.shape_floor,
            "exclude_base_um": self.exclude_base_um,
            "conditions": [
                dict(c.describe(), label=lab) for c, lab in zip(self.conditions, self.labels)
            ],
        }
