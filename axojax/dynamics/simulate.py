"""``simulate``: the nonlinear beat in the time domain, analysed and in physical units."""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from .. import _io, results
from ..assembly import assemble
from ..assembly.motor_kinetics import check_tau_m
from ..eigen.mode import CLASSES, dominant_mode
from ..models.section import Model
from ..params import DEFAULT_CUBIC, Params
from ..results import RESULTS
from ..units import Units
from ..waveform import FourierModes, fourier_modes
from ..waveform.measures import along, amplitude_dip, finite_or_none, is_sensitive
from ..waveform.shapes import centreline
from ..well_posed import require_passive_friction
from .analysis import classify_trajectory
from .integrate import integrate, result_message
from .motors import equilibrium, motor_linear, motor_meta
from .saturation import check_saturation

MIN_SAMPLES_PER_S = 2000.0
MAX_SAMPLES = 200_000
STEPS_PER_PERIOD = 2000
"""Default step budget per period (of the linear frequency, at least 20 Hz) on top of
``MIN_STEPS``: the nonlinear beat takes about 250 steps a period (10 elements,
``benchmarks/bench_simulate.py``: 4257 accepted and 698 rejected in 20 periods); a solve whose step size collapses
stops at the budget and ends in the state ``solver_failed`` (with diffrax's reason and the
time reached) instead of running for most of an hour."""
MIN_STEPS = 10_000
MEASURE_PERIODS = 2
"""Whole periods at the end of a limit-cycle record whose psi_0, psi_1 give the waveform
measures (the frequency comes from the last two cycles too)."""

integrate_jit = jax.jit(
    integrate, static_argnums=0, static_argnames=("rtol", "atol", "max_steps", "progress")
)
""":func:`~axojax.dynamics.integrate.integrate` compiled once per model (the simulation's,
and the large cycle's start: :mod:`axojax.orbits.large_cycle`)."""


@dataclasses.dataclass
class Simulation:
    """A simulated beat, in physical units, and what it did.

    Attributes:
        t_s: (T,) times (s).
        x_um: (S,) arc length along the axoneme (um).
        centreline_um: (T, d, S) centreline displacement (mean over filaments) in y (, z),
            in the lab frame (with the base's motion where the base is not clamped).
        psi_rad: (T, S) tangent angle of the centreline in the beat plane (small slopes),
            in the lab frame: the psi of modes, orbits and data (docs/model.md, "One
            wavelength everywhere").
        tip_um: (T, d) tip displacement in the body frame (from the base's tangent line:
            ``u(L) - u(0) - L u'(0)``, the rigid motion of a base that moves taken out:
            what the state, the beat direction and the amplitude are read from; the lab
            frame's on a base that holds node 0).
        beat_angle_rad: beat direction, radians from y towards z.
        state: ``decaying``, ``limit_cycle``, ``growing``, ``settling``, ``divergent`` or
            ``solver_failed`` (rules in :mod:`axojax.dynamics.analysis`). After a solver
            failure the time series end where the solver stopped.
        limit_cycle: on a limit cycle: ``frequency_hz``, ``period_s``, ``tip_amplitude_um``
            (half peak-to-peak along the beat direction), ``wavelength_um`` (None for a
            standing wave), ``direction`` (``anterograde``, ``retrograde`` or None),
            ``static_curvature_rad_per_um``, ``dynamic_amplitude_rad``,
            ``amplitude_dip`` and ``wavelength_sensitive`` (the measures of
            :mod:`axojax.waveform.measures` on psi_0, psi_1 of the last
            ``MEASURE_PERIODS`` whole periods at the ``n_points`` saved points:
            :func:`waveform_measures`); otherwise None.
        linear: dominant eigenvalue at the same parameters: ``frequency_hz``,
            ``growth_rate_per_s``, ``classification`` (with motor kinetics: of the
            augmented pencil).
        meta: parameters, cubic coefficient, units, model, solver statistics
            (``meta["solver"]``: steps, rejected steps, ``ok``, diffrax's ``result``
            message, ``t_reached_s``), ``motor_kinetics`` (``tau_m`` in tau and
            ``tau_ms`` in ms, or None: :func:`simulate`'s ``tau_m``).
        result: :class:`axojax.results.RESULTS` item of the time integration (diffrax's
            code, promoted): ``successful``, or why the solver stopped
            (``max_steps_reached``, ``dt_min_reached``, ...; then ``state`` is
            ``solver_failed``). A beat that decays, grows or diverges is an answer,
            not a failure.
    """

    t_s: np.ndarray
    x_um: np.ndarray
    centreline_um: np.ndarray
    psi_rad: np.ndarray
    tip_um: np.ndarray
    beat_angle_rad: float
    state: str
    limit_cycle: dict[str, float] | None
    linear: dict[str, Any]
    meta: dict[str, Any]
    result: RESULTS = dataclasses.field(default_factory=lambda: RESULTS.successful)

    @property
    def message(self) -> str:
        """``result``'s message on one line (:func:`axojax.results.message`); the state's
        own explanation is :attr:`reason`."""
        return results.message(self.result)

    @property
    def tip_beat_um(self) -> np.ndarray:
        """(T,) tip displacement along the beat direction (um)."""
        return along(self.tip_um, self.beat_angle_rad, axis=-1)

    @property
    def centreline_beat_um(self) -> np.ndarray:
        """(T, S) centreline displacement along the beat direction (um)."""
        return along(self.centreline_um, self.beat_angle_rad, axis=1)

    def settled_modes(self) -> FourierModes | None:
        """psi_0, psi_1 (s in um, omega in rad/s) of the last ``MEASURE_PERIODS`` whole
        periods of a limit cycle, whose measures :attr:`limit_cycle` holds; None when the
        run did not settle on one."""
        if self.limit_cycle is None:
            return None
        return settled_modes(self.t_s, self.x_um, self.psi_rad, self.limit_cycle["period_s"])

    @property
    def reason(self) -> str | None:
        """One line explaining the state where it needs explaining, else None:
        ``solver_failed`` (where the solver stopped, diffrax's reason), and ``decaying``
        although the straight state is linearly unstable (the tip came to rest; where the
        filaments are)."""
        rest = self.meta.get("at_rest")
        if self.state == "decaying" and rest is not None:
            return (
                f"the straight state is linearly unstable ({self.linear['classification']}) "
                "but the tip came to rest: the run ended "
                f"at a static state with filament tips up to {rest['max_filament_tip_um']:.3g} um from the axis "
                f"(centreline tip {rest['centreline_tip_um']:.2g} um)"
            )
        if self.state != "solver_failed":
            return None
        solver = self.meta["solver"]
        accepted = solver["steps"]
        mean = (
            f"mean accepted step {solver['t_reached_s'] / accepted:.2g} s"
            if accepted
            else "none accepted"
        )
        return (
            f"the solver stopped at t = {solver['t_reached_s']:.4g} s of {self.meta['t_end_s']:.4g} s after "
            f"{accepted + solver['rejected']} steps ({accepted} accepted, {mean}): {solver['result']}"
        )

    def to_json(self) -> dict[str, Any]:
        """The ``axojax simulate --json`` document (plain Python)."""
        lc = (
            None
            if self.limit_cycle is None
            else {k: self.limit_cycle[k] for k in ("frequency_hz", "tip_amplitude_um", "period_s")}
        )
        # docs/interface.md: a failed solver's reason also under "solver"
        solver = {
            **self.meta["solver"],
            "reason": self.reason if self.state == "solver_failed" else None,
        }
        doc = {
            "state": self.state,
            "reason": self.reason,
            "limit_cycle": lc,
            "linear": dict(self.linear),
            "waveform": self.limit_cycle,
            "solver": solver,
        }
        if self.meta.get("motor_kinetics") is not None:  # {"tau_m", "tau_ms"}: the motor time used
            doc["motor_kinetics"] = dict(self.meta["motor_kinetics"])
        return results.jsonable(doc)

    def save(self, path: str | pathlib.Path) -> None:
        """Write the simulation to ``path`` (``.npz``, any case; written whole, see
        :mod:`axojax._io`): the time series and a ``meta`` JSON string (``kind =
        "simulation"``, :attr:`meta`, the state, the result by name, ...). Raises
        ``ValueError`` for another suffix or a directory that does not take the file
        (:func:`axojax._io.check_output_path`)."""
        path = _io.check_output_path(path, (".npz",))
        meta = {
            **self.meta,
            "kind": "simulation",
            "state": self.state,
            "limit_cycle": self.limit_cycle,
            "linear": self.linear,
            "beat_angle_rad": self.beat_angle_rad,
            "result": results.name(self.result),
        }
        with _io.atomic_path(path) as tmp:
            np.savez_compressed(
                tmp,
                t_s=self.t_s,
                x_um=self.x_um,
                centreline_um=self.centreline_um,
                psi_rad=self.psi_rad,
                tip_um=self.tip_um,
                meta=np.array(json.dumps(meta)),
            )

    @classmethod
    def load(cls, path: str | pathlib.Path) -> "Simulation":
        """Read what :meth:`save` wrote (files written before the result was stored get
        ``successful`` where the solver was fine, else the code whose message they
        hold)."""
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            arrays = {k: f[k] for k in ("t_s", "x_um", "centreline_um", "psi_rad", "tip_um")}
        if meta.get("kind") != "simulation":
            raise ValueError(f"{str(path)!r} is not an axojax simulation file")
        state, lc, lin, angle = (
            meta.pop(k) for k in ("state", "limit_cycle", "linear", "beat_angle_rad")
        )
        stored = meta.pop("result", None)
        result = results.from_names(stored) if stored is not None else _result_of(meta)
        if result is None:
            raise ValueError(
                f"{str(path)!r}: unknown solver result {meta['solver'].get('result')!r}"
            )
        return cls(
            **arrays,
            beat_angle_rad=angle,
            state=state,
            limit_cycle=lc,
            linear=lin,
            meta=meta,
            result=result,
        )

    @classmethod
    def read(cls, path: str | pathlib.Path) -> "Simulation":
        """:meth:`load`, the file checked whole (every array on the same times and points);
        a file that is not is one :class:`~axojax.results.ResultFileError` naming it."""

        def checked(path):
            sim = cls.load(path)
            T, S = len(sim.t_s), len(sim.x_um)
            expect = {"t_s": (T,), "x_um": (S,), "tip_um": (T, None), "psi_rad": (T, S)}
            expect["centreline_um"] = (T, None, S)
            results.check_arrays(path, "simulation", {k: getattr(sim, k) for k in expect}, expect)
            return sim

        return results.read_checked(path, "simulation", checked)


def _result_of(meta: dict[str, Any]) -> RESULTS | None:
    """The result of a file written without one: ``successful`` where the solver was
    fine, else the item whose one-line message
    (:func:`~axojax.dynamics.integrate.result_message`) the file holds (None if none)."""
    solver = meta.get("solver") or {}
    if solver.get("ok", True):
        return RESULTS.successful
    return next(
        (
            getattr(RESULTS, n)
            for n in results.NAMES
            if result_message(getattr(RESULTS, n)) == solver.get("result")
        ),
        None,
    )


def settled_modes(t: np.ndarray, s: np.ndarray, psi: np.ndarray, period: float) -> FourierModes:
    """psi_0, psi_1 of the tangent angle ``psi`` (T, S) at times ``t`` (T,) and arc
    lengths ``s`` (S,) over the last ``MEASURE_PERIODS`` whole periods: the settled beat,
    not the growth from rest that the earlier periods hold."""
    late = t >= t[-1] - (MEASURE_PERIODS + 0.5) * period
    return fourier_modes(t[late], s, psi[late], period)


def waveform_measures(modes: FourierModes) -> dict[str, Any]:
    """The waveform measures of a settled beat's psi_0, psi_1 (s in um): wavelength (None
    for a standing wave), direction, static curvature, dynamic amplitude, and the
    ``amplitude_dip`` of psi_1 with ``wavelength_sensitive`` (a wavelength and a dip below
    ``SENSITIVE_DIP``: a near-node of psi_1, where the phase turns fast)."""
    wavelength, dip = finite_or_none(modes.wavelength), float(amplitude_dip(modes.s, modes.psi1))
    return {
        "wavelength_um": wavelength,
        "direction": {1: "anterograde", -1: "retrograde"}.get(modes.direction),
        "static_curvature_rad_per_um": modes.static_curvature,
        "dynamic_amplitude_rad": modes.dynamic_amplitude,
        "amplitude_dip": dip,
        "wavelength_sensitive": wavelength is not None and is_sensitive(dip),
    }


RTOL_RANGE = (1e-12, 1e-1)
"""Accepted relative tolerances of the time integration."""
MIN_T_END_S = 1e-9
"""Shortest simulated duration (s)."""


def check_inputs(
    model: Model,
    t_end_s: float,
    cubic: float,
    perturbation_um: float,
    rtol: float,
    names: dict[str, str] | None = None,
) -> tuple[float, float, float, float]:
    """Validate :func:`simulate`'s scalar inputs; returns them as floats.

    ``names`` renames the arguments in the error messages (the CLI passes its flags).
    Raises ``ValueError`` with one line naming the bad value.
    """
    names = names or {}

    def check(name: str, value: float, positive: bool = True) -> float:
        value = float(value)
        if not math.isfinite(value) or (value <= 0 if positive else value < 0):
            raise ValueError(
                f"{names.get(name, name)} must be a finite number {'> 0' if positive else '>= 0'}, got {value!r}"
            )
        return value

    t_end_s, cubic = check("t_end_s", t_end_s), check("cubic", cubic, positive=False)
    perturbation_um, rtol = check("perturbation_um", perturbation_um), check("rtol", rtol)
    # a step-size controller cannot go below ~1e-13 relative in float64, and a duration of
    # 1e-300 s spent every step without advancing
    if not RTOL_RANGE[0] <= rtol <= RTOL_RANGE[1]:
        raise ValueError(
            f"{names.get('rtol', 'rtol')} must be in [{RTOL_RANGE[0]:g}, {RTOL_RANGE[1]:g}], got {rtol!r}"
        )
    if t_end_s < MIN_T_END_S:
        raise ValueError(
            f"{names.get('t_end_s', 't_end_s')} must be at least {MIN_T_END_S:g} s, got {t_end_s!r}"
        )
    if model.link_B.shape[0] == 0 and cubic > 0:
        raise ValueError(
            f"{names.get('cubic', 'cubic')} = {cubic:g} needs a model with links; {model.name!r} has none (use 0)"
        )
    return t_end_s, cubic, perturbation_um, rtol


def simulate(
    model: Model,
    params: Params,
    t_end_s: float,
    *,
    cubic: float = DEFAULT_CUBIC,
    units: Units = Units(),
    perturbation_um: float = 0.1,
    samples_per_period: int = 64,
    n_points: int = 41,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    max_steps: int | None = None,
    progress: bool = False,
    throw: bool = False,
    tau_m: float | None = None,
    f_sat: float | None = None,
) -> Simulation:
    """Integrate ``C dq/dt = -A q - f_nl(q) + b`` from a small perturbation of the straight
    state (the static deflection of every filament under a tip force in y, see
    :func:`tip_deflection`), then analyse the beat.

    A regulated mechanism (``params.chi_*``, ``beta_*``) with an active friction (chi'' or
    beta'' < 0) is refused (:func:`axojax.well_posed.require_passive_friction`) unless
    ``tau_m`` gives it motor kinetics: the state then grows by the motors' filtered copy y
    (``tau_m dy/dt = -y + q``, started at y = 0: the motors have not yet responded to the
    initial bend) and the integrated system is the augmented one of
    :func:`~axojax.assembly.motor_kinetics.assemble_motor` with the cubic links on q
    (:mod:`axojax.dynamics.motors`), well posed whatever the signs of chi'' and beta''.

    Args:
        model: e.g. ``ax.models.seven()``, on any base (a base that moves: the tip in
            the body frame, see :class:`Simulation`).
        params: dimensionless parameters; ``imbalance != 1`` gives a static moment b
            that bends the axoneme (asymmetric beat).
        t_end_s: simulated time (s).
        cubic: link stiffening kappa (1/L^2): link force k (delta + kappa delta^3).
            0 integrates the linear system.
        units: physical units (L, EI, c_n).
        perturbation_um: initial tip displacement in y (um).
        samples_per_period: save times per period of the linear frequency (at least
            ``MIN_SAMPLES_PER_S`` per second (enough for beats up to ~100 Hz when the
            dominant mode does not oscillate), at most ``MAX_SAMPLES`` in all.
        n_points: points along x for the saved centreline and tangent angle.
        rtol, atol: solver tolerances (atol in units of L).
        max_steps: solver step limit; running out ends in ``solver_failed``. Default:
            ``MIN_STEPS + STEPS_PER_PERIOD`` per linear period, rounded up to 10 000.
        progress: show a progress bar.
        throw: raise ``ValueError`` (one line: where and why the solver stopped) when
            the time integration fails; default False, as everywhere
            (:mod:`axojax.results`): the result has ``state = "solver_failed"`` and
            ``result`` says why.
        tau_m: the motors' relaxation time, dimensionless (seconds / ``units.tau_s``),
            in [1e-9, 1e9]; None (default): no motor kinetics (today's friction form).
            With it ``linear`` is the augmented pencil's rightmost eigenvalue (dense), and
            ``meta["motor_kinetics"]`` holds ``tau_m`` and ``tau_ms`` (milliseconds).
        f_sat: with ``tau_m``, saturating motors: the regulated force through
            ``f_sat tanh(f / f_sat)`` (:mod:`axojax.dynamics.saturation`), f_sat
            dimensionless (``units.p_from_pn_per_um``), > 0; None (default): linear motors.

    Returns:
        :class:`Simulation`.
    """
    params = params.validate()
    if f_sat is not None:
        if tau_m is None:
            raise ValueError("a motor saturation f_sat needs motor kinetics (tau_m)")
        f_sat = check_saturation(f_sat)
    if tau_m is None:
        require_passive_friction(model, params, "simulate")
    else:
        check_tau_m(params, tau_m)  # one line naming the value
        tau_m = float(tau_m)
    t_end_s, cubic, perturbation_um, rtol = check_inputs(
        model, t_end_s, cubic, perturbation_um, rtol
    )
    if not (math.isfinite(atol) and atol > 0):
        raise ValueError(f"atol must be a finite number > 0, got {atol!r}")
    for name, value, low in (
        ("n_points", n_points, 2),
        ("samples_per_period", samples_per_period, 2),
        ("max_steps", 1 if max_steps is None else max_steps, 1),
    ):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
    tau = units.tau_s
    linear = _linear(model, params, units, tau_m)
    t_end = t_end_s / tau
    per_second = max(samples_per_period * linear["frequency_hz"], MIN_SAMPLES_PER_S)
    n_save = int(min(MAX_SAMPLES, max(200, math.ceil(t_end_s * per_second) + 1)))
    t = np.linspace(0.0, t_end, n_save)

    if max_steps is None:
        periods = t_end_s * max(linear["frequency_hz"], 20.0)
        max_steps = 10_000 * math.ceil((MIN_STEPS + STEPS_PER_PERIOD * periods) / 10_000)
    x = np.linspace(0.0, 1.0, n_points)
    q0 = (perturbation_um / units.length_um) * np.concatenate(
        [tip_deflection(model), np.zeros(model.n_border)]
    )
    if tau_m is not None:
        q0 = np.concatenate([q0, np.zeros(model.n_unknowns)])  # the motors' copy y(0) = 0

    traj = integrate_jit(
        model,
        params,
        jnp.asarray(cubic),
        jnp.asarray(q0),
        jnp.asarray(t),
        rtol=rtol,
        atol=atol,
        max_steps=max_steps,
        progress=progress,
        tau_m=None if tau_m is None else jnp.asarray(tau_m),
        f_sat=None if f_sat is None else jnp.asarray(f_sat),
    )
    q = np.asarray(traj.q)[:, : model.n_unknowns]  # without the motors' copy y
    ok = bool(traj.ok)
    t_reached = float(traj.t_reached)
    if not ok:
        # The record ends where the solver stopped (diffrax leaves later rows at inf).
        keep = (t <= t_reached) & np.all(np.isfinite(q), axis=1)
        keep[0] = True
        t, q = t[keep], q[keep]
    u = centreline(model, q, x)  # (T, d, S), L, lab frame
    du = centreline(model, q, x, derivative=1)
    tip_t = centreline(model, q, np.ones(1), body=True)[:, :, 0]
    angle = _beat_angle(tip_t)

    q_eq = _equilibrium(model, params, tau_m)
    tip_eq = centreline(model, q_eq, np.ones(1), body=True)[:, 0]
    y_eq = float(along(tip_eq, angle, axis=-1))
    y = along(tip_t, angle, axis=-1)
    psi = along(du, angle)  # (T, S)
    state, cycles = classify_trajectory(
        t, y, y_eq, ok, equilibrium_stable=linear["growth_rate_per_s"] < 0
    )

    limit_cycle = None
    if state == "limit_cycle":
        period = float(np.mean(cycles.periods[-2:]))
        modes = settled_modes(t * tau, x * units.length_um, psi, period * tau)
        limit_cycle = {
            "frequency_hz": 1.0 / (period * tau),
            "period_s": period * tau,
            "tip_amplitude_um": float(cycles.amplitudes[-1]) * units.length_um,
            **waveform_measures(modes),
            "cycles": cycles.count,
        }
    at_rest = None
    if state == "decaying" and linear["growth_rate_per_s"] > 0:
        # u at each filament's tip node, from the base's tangent line (body frame)
        rigid = centreline(model, q[-1], np.ones(1)) - centreline(
            model, q[-1], np.ones(1), body=True
        )
        tips = (model.filament_dofs(q[-1])[:, :, -2] - rigid[None, :, 0]) * units.length_um
        at_rest = {
            "max_filament_tip_um": float(np.abs(tips).max()),
            "centreline_tip_um": float(np.abs(tip_t[-1]).max() * units.length_um),
        }
    meta = {
        "at_rest": at_rest,
        "model": model.name,
        "n_elements": model.n_elements,
        "params": {k: float(v) for k, v in params.as_dict().items()},
        "imbalance_kind": model.imbalance_kind,
        "cubic": cubic,
        "motor_kinetics": None if tau_m is None else motor_meta(tau_m, f_sat, units),
        "t_end_s": t_end_s,
        "perturbation_um": perturbation_um,
        "units": {
            "length_um": units.length_um,
            "ei_pn_um2": units.ei_pn_um2,
            "cn_pn_s_um2": units.cn_pn_s_um2,
            "tau_s": tau,
        },
        "solver": {
            "name": "Kvaerno5",
            "rtol": rtol,
            "atol": atol,
            "steps": int(traj.steps),
            "rejected": int(traj.rejected),
            "max_steps": int(max_steps),
            "ok": ok,
            "result": result_message(traj.result),
            "t_reached_s": t_reached * tau,
        },
    }
    L = units.length_um
    sim = Simulation(
        t_s=t * tau,
        x_um=x * L,
        centreline_um=u * L,
        psi_rad=psi,
        tip_um=tip_t * L,
        beat_angle_rad=angle,
        state=state,
        limit_cycle=limit_cycle,
        linear=linear,
        meta=meta,
        result=jax.tree.map(np.asarray, traj.result),
    )
    if throw and not results.is_successful(sim.result):
        raise ValueError(sim.reason)
    return sim


def _linear(model: Model, params: Params, units: Units, tau_m: float | None) -> dict[str, Any]:
    """The dominant eigenvalue at ``params`` as ``frequency_hz``, ``growth_rate_per_s`` and
    ``classification``: :func:`~axojax.eigen.mode.dominant_mode`'s, or with ``tau_m`` the
    augmented pencil's (:func:`axojax.dynamics.motors.motor_linear`)."""
    if tau_m is not None:
        return motor_linear(model, params, tau_m, units)
    mode = dominant_mode(model, params)
    return {
        "frequency_hz": float(mode.frequency_hz(units)),
        "growth_rate_per_s": float(mode.growth_rate_per_s(units)),
        "classification": CLASSES[int(mode.classification)],
    }


def _equilibrium(model: Model, params: Params, tau_m: float | None) -> np.ndarray:
    """(N,) the static state (zero without a static load b)."""
    if tau_m is not None:
        return equilibrium(model, params, tau_m)
    s = assemble(model, params)
    if not np.any(np.asarray(s.b)):
        return np.zeros(model.n_unknowns)
    # on a base that moves, A is singular (rigid motions): the least-norm equilibrium,
    # the same shape in the body frame
    A_, b_ = np.asarray(s.A), np.asarray(s.b)
    return np.linalg.lstsq(A_, b_, rcond=None)[0] if model.n_border else np.linalg.solve(A_, b_)


def tip_deflection(model: Model) -> np.ndarray:
    """(n,) state: every filament bent in y as a clamped cantilever under a tip force,
    scaled to unit tip displacement (L). Excites every planar mode, whatever the
    dominant one looks like (its centreline may be still, e.g. a torsional mode)."""
    K0 = model.matrices.K0
    f = np.zeros(model.mesh.n_dof)
    f[-2] = 1.0  # transverse force at the tip node
    shape = np.linalg.solve(K0, f)
    shape = shape / shape[-2]
    q = np.zeros((model.n_filaments, model.n_dirs, model.mesh.n_dof))
    q[:, 0, :] = shape
    return q.ravel()


def _beat_angle(tip: np.ndarray) -> float:
    """Principal direction of the tip's motion over the second half of the record."""
    if tip.shape[1] == 1 or not np.all(np.isfinite(tip)):
        return 0.0
    late = tip[tip.shape[0] // 2 :]
    late = late - late.mean(axis=0)
    w, vec = np.linalg.eigh(late.T @ late)
    e = vec[:, np.argmax(w)]
    if e[np.argmax(np.abs(e))] < 0:
        e = -e
    return float(np.arctan2(e[1], e[0]))
