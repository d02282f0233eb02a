"""Fits of the whole beat of a regulated mechanism (issue 47 item 4; docs/fitting.md,
"The whole beat of a regulated mechanism").

The linear comparison fits psi_1's shape with a free complex amplitude at a Hopf point.
The whole-beat fit drops the free amplitude: the limit cycle of the mechanism with motor
kinetics (``tau_m``), saturating motors (``f_sat``) and a static dynein moment (``m0``)
must reproduce the observed frequency, psi_0 (its slope is the static curvature; up to
a constant, the reference angle ``psi_offset_rad``: a recording's psi is measured from an
arbitrary direction, :mod:`axojax.inverse.cycle_targets`) and psi_1 in absolute
amplitude (rad), every residual through the periodic orbit
(:class:`~axojax.inverse.orbit_setup.OrbitSetup`, gradients by the implicit function
theorem through the harmonic balance).

Free by default: the mechanism's coefficients (those of
:data:`~axojax.inverse.comparison.mechanisms.FREE`), ``f_sat`` and ``m0``; ``tau_m`` given
(:func:`motor_time`) or fitted (``fit_tau_m``). The cubic link stiffening is fixed
(``cubic``, default 0: the saturation bounds the beat) and a0 is fixed (it is not
separable from chi, beta and f_sat).

Starts, in order (each orbit solved from the Hopf normal form):

1. the linear row's fit (:func:`axojax.inverse.comparison.compare`'s, pinned at the
   observed frequency): a Hopf point at the observed beat;
2. the mechanism's coefficients scaled by ``past`` (1.1: 10 % past the Hopf point);
3. ``m0`` from the static curvature (psi_0's least-squares slope, whatever its reference
   angle) of the equilibrium at a probe moment (linear in m0
   while the motors are far from saturation);
4. ``f_sat`` from a ladder (:data:`SATURATION_LADDER` decades around the static force
   m0 / a0), the value whose orbit's dynamic amplitude is nearest the observed one; then
   ``m0`` corrected once by the ratio of static curvatures.

Past a subcritical Hopf point (the normal form's Re g21 > 0: no small orbit, a small bend
grows onto a distant cycle) steps 3-4 run on the large cycle instead: a simulation begun
at a large bend settles on it (:func:`axojax.orbits.large_cycle.large_cycle`), f_sat is
scaled to the observed amplitude and m0 set from a probe, each orbit continued from the
last, and the fit's orbits start from it (:attr:`WholeBeatFit.large_cycle`; the report
says so).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import scipy.linalg as sl

from ...beats.frames import shape_in_basal_frame
from ...beats.targets import FRAMES, ShapeTarget, Target
from ...dynamics.motors import deflated_pencil
from ...models.section import Model
from ...orbits import cycle_measures
from ...orbits.cycle import LimitCycle
from ...orbits.large_cycle import large_cycle
from ...orbits.limit_cycle import limit_cycle
from ...params import Params
from ...units import Units
from ...waveform import measures as wm
from .._arguments import SIGNED
from ..comparison.compare import fit_row
from ..comparison.mechanisms import FREE, ORBIT_MECHANISMS, Row
from ..fitting.fit import build_problem
from ..fitting.least_squares import least_squares, solver_from_name
from ..fitting.report import FitResult
from ..parameters import DEFAULT_BOUNDS
from ..problem import SHAPE_FLOOR

MOTOR_TIMES = (1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0)
"""omega0 tau_m tried by :func:`motor_time`, fastest first."""
PAST = 1.1
"""Start 10 % past the linear fit's Hopf point (the mechanism's coefficients scaled)."""
SATURATION_LADDER = np.geomspace(0.3, 300.0, 13)
"""f_sat tried for the start, in units of the motors' static force |m0| / a0 (at least
1 % of :func:`_saturation_scale`'s, for a beat without a static bend): three decades."""
PROBE = 1e-3
"""The probe moment of the m0 start, in units of a0 times :func:`_saturation_scale`'s
force: small enough that the static response is linear."""
CONTINUATION = 8
"""Steps in which the static moment and f_sat move along a large cycle (each orbit
continued from the last: a bend of two radians in one step loses it)."""
ROUNDS = 6
"""Rounds of (m0, f_sat) corrections of a large-cycle start (:func:`_large_start`)."""
MAX_STEPS = 80
"""Levenberg-Marquardt iterations of a whole-beat fit (the synthetic beat of
tests/whole_beat/test_whole_beat_fit.py converges in 15; a row whose orbit is lost pays a full Newton
budget at every step, so a failing row stops early)."""


def motor_time(model: Model, params: Params, times=MOTOR_TIMES, past: float = PAST) -> float:
    """The default motor relaxation time of a regulated row at its Hopf point (``params``:
    the linear fit's; dimensionless): the fastest ``omega0 tau_m`` of ``times`` at which
    the beat is the onset mode of the augmented pencil: at the Hopf point every other
    eigenvalue decays, and ``past`` it (the coefficients scaled, where the whole-beat fit
    starts) the beat still grows fastest.

    Why: motor kinetics leave the beat at i omega0 unchanged for every tau_m, but not the
    rest of the spectrum: too fast motors (small omega0 tau_m) turn an active friction into
    a large negative instantaneous stiffness, whose mode outgrows the beat (clamped
    two-filament sliding control at 50 Hz: at omega0 tau_m = 1 a 100 Hz mode grows at the
    Hopf point; at 1.5 a 115 Hz mode decays there but grows 30 times faster than the beat
    1 % past it), and slower ones stiffen the static response (chi' - chi'' omega0 tau_m).
    The fastest motors that keep the observed beat the onset mode are the least committal
    choice that makes the fitted row a genuine Hopf point; a fit can free ``tau_m`` from
    there. One-line ``ValueError`` when none does."""
    w0 = float(params.omega0)
    beyond = params.replace(
        **{n: past * float(getattr(params, n)) for n in SIGNED if float(getattr(params, n))}
    )

    def split(prm, wt):
        A, C = deflated_pencil(model, prm, wt / w0)  # a base's rigid motions moved away
        ev = sl.eigvals(-A, C)
        ev = ev[np.isfinite(ev)]
        near = ev[np.argmin(np.abs(ev - 1j * w0))]  # the beat, and its conjugate
        beat = (np.abs(ev - near) <= 1e-9 * w0) | (np.abs(ev - np.conj(near)) <= 1e-9 * w0)
        return near.real, (ev[~beat].real.max() if (~beat).any() else -np.inf)

    for wt in times:
        _, others = split(params, wt)
        lead, rest = split(beyond, wt)
        if others < 0 and lead > rest:
            return wt / w0
    raise ValueError(
        f"no motor time omega0 tau_m in {times} makes the fitted beat the onset mode: "
        "another mode outgrows it; give tau_m"
    )


def _scaled_past(params: Params, mechanism: str, past: float) -> Params:
    """The mechanism's coefficients scaled by ``past`` (past the Hopf point)."""
    names = [n for n in FREE[mechanism] if float(getattr(params, n)) != 0.0]
    return params.replace(**{n: past * float(getattr(params, n)) for n in names})


def _saturation_scale(params: Params) -> float:
    """A force per length to measure f_sat in: 1 / a0^2 (the dimensionless chi scale
    times a sliding of a0), so that the ladder spans the regulated forces of a bend of
    order one radian."""
    return 1.0 / float(params.a0) ** 2


def _measures(model, params, cubic, tau_m, f_sat, units, s_um):
    cycle = limit_cycle(model, params, cubic, tau_m=tau_m, f_sat=f_sat)
    return bool(cycle.converged), cycle_measures(cycle, s_um, units)


def subcritical(model, params, cubic, tau_m, f_sat) -> bool:
    """Whether ``params`` lie past a subcritical Hopf bifurcation (the normal form has no
    small orbit, Re g21 > 0: a small bend grows onto a distant cycle, or diverges)."""
    cycle = limit_cycle(model, params, cubic, tau_m=tau_m, f_sat=f_sat)
    lam = complex(cycle.linear_eigenvalue)
    return not bool(cycle.started) and lam.real > 0 and lam.imag != 0


def _large_start(model, prm, cubic, tau_m, static_curvature, dynamic_amplitude, units):
    """(params with m0 set, f_sat, the orbit): the start past a subcritical Hopf point, on
    the large cycle a simulation begun at a large bend settles on
    (:func:`axojax.orbits.large_cycle.large_cycle`). Without a static moment and cubic
    stiffening the cycle's size is proportional to f_sat, so f_sat is first scaled to the
    observed dynamic amplitude; then up to :data:`ROUNDS` rounds move m0 by the static
    curvature still missing (per unit m0 from a probe moment) and f_sat by the ratio of
    amplitudes (a static moment saturates the motors and shrinks the beat), each move
    continued in :data:`CONTINUATION` steps from the last orbit (halved where the orbit is
    lost). One-line ``ValueError`` when the simulation settles on no cycle or no round
    moves."""
    scale = _saturation_scale(prm)
    orbit = large_cycle(model, prm.replace(m0=0.0), cubic, tau_m=tau_m, f_sat=scale)
    if not bool(orbit.converged):
        raise ValueError(
            "its Hopf bifurcation is subcritical and a simulation begun at a large bend "
            "settles on no limit cycle there (it decays or diverges)"
        )

    def at(m0, f_sat, start):
        cycle = limit_cycle(model, prm.replace(m0=m0), cubic, tau_m=tau_m, f_sat=f_sat, start=start)
        m = cycle_measures(cycle, None, units)
        return cycle, float(m.static_curvature_rad_per_um), float(m.dynamic_amplitude_rad)

    def walk(orbit, here, there):
        """The last orbit converged on the way from (m0, f_sat) ``here`` to ``there``."""
        for k in range(2):  # the whole move, then half of it
            goal = there if k == 0 else tuple((a + b) / 2 for a, b in zip(here, there))
            path = zip(
                np.linspace(here[0], goal[0], CONTINUATION + 1)[1:],
                np.geomspace(here[1], goal[1], CONTINUATION + 1)[1:],
            )
            cycle, reached = orbit, here
            for m0, f in path:
                nxt = at(float(m0), float(f), cycle)
                if not bool(nxt[0].converged):
                    break
                cycle, reached = nxt[0], (float(m0), float(f))
            else:
                return cycle, reached
        return cycle, reached

    _, _, amp = at(0.0, scale, orbit)
    orbit, (_, f_sat) = walk(orbit, (0.0, scale), (0.0, scale * dynamic_amplitude / amp))
    probe = PROBE * f_sat * float(prm.a0)
    _, kappa, _ = at(probe, f_sat, orbit)
    per_m0 = kappa / probe
    here = (0.0, f_sat)
    for _ in range(ROUNDS if per_m0 != 0 else 0):
        _, kappa, amp = at(*here, orbit)
        if abs(kappa - static_curvature) <= 0.05 * abs(static_curvature) and (
            abs(amp / dynamic_amplitude - 1) <= 0.05
        ):
            break
        there = (here[0] + (static_curvature - kappa) / per_m0, here[1] * dynamic_amplitude / amp)
        orbit, reached = walk(orbit, here, there)
        if reached == here:
            break
        here = reached
    if here[0] == 0.0 and static_curvature != 0.0:
        raise ValueError(
            "its Hopf bifurcation is subcritical and the large cycle a simulation settles "
            "on is lost when the static moment is set"
        )
    return prm.replace(m0=here[0]), here[1], orbit


def start_values(
    model: Model,
    params: Params,
    mechanism: str,
    *,
    tau_m: float,
    static_curvature: float,
    dynamic_amplitude: float,
    units: Units,
    cubic: float = 0.0,
    past: float = PAST,
) -> tuple[Params, float, LimitCycle | None]:
    """(params with the coefficients past the Hopf point and m0 set, f_sat, orbit): the
    start of a whole-beat fit (module docstring, steps 2-4) from a Hopf point ``params``.
    ``static_curvature`` (rad/um) and ``dynamic_amplitude`` (rad) are the observed ones.
    ``orbit``: None past a supercritical Hopf point (the fit's orbits start from the
    normal form); past a subcritical one, the large cycle the fit starts on
    (:func:`_large_start`)."""
    prm = _scaled_past(params, mechanism, past)
    scale = _saturation_scale(prm)
    big = 1e4 * scale  # the motors far from saturation: the static response is linear
    if subcritical(model, prm, cubic, tau_m, big):
        try:
            return _large_start(
                model, prm, cubic, tau_m, static_curvature, dynamic_amplitude, units
            )
        except ValueError as err:
            raise ValueError(
                f"the fitted {mechanism} row at omega0 tau_m = "
                f"{tau_m * float(params.omega0):.3g}: {err}; give another tau_m (--motor-tau-ms)"
            ) from None
    probe = PROBE * scale * float(prm.a0)
    _, m = _measures(model, prm.replace(m0=probe), cubic, tau_m, big, units, None)
    per_m0 = float(m.static_curvature_rad_per_um) / probe
    m0 = static_curvature / per_m0 if per_m0 != 0 and static_curvature != 0 else 0.0
    prm = prm.replace(m0=m0)
    force = max(abs(m0) / float(prm.a0), scale * 1e-2)
    best = None
    for f in SATURATION_LADDER * force:
        ok, m = _measures(model, prm, cubic, tau_m, float(f), units, None)
        amp = float(m.dynamic_amplitude_rad)
        if not ok or not amp > 0:
            continue
        miss = abs(math.log(amp / dynamic_amplitude))
        if best is None or miss < best[0]:
            best = (miss, float(f), float(m.static_curvature_rad_per_um))
    if best is None:
        raise ValueError(
            f"no limit cycle near the fitted {mechanism} row's Hopf point for any motor "
            f"saturation tried ({SATURATION_LADDER[0] * force:.3g} to "
            f"{SATURATION_LADDER[-1] * force:.3g}): the bifurcation may be subcritical there"
        )
    _, f_sat, kappa0 = best
    if m0 != 0 and kappa0 != 0 and static_curvature / kappa0 > 0:
        prm = prm.replace(m0=m0 * static_curvature / kappa0)
    return prm, f_sat, None


def linear_hopf(
    spec: Row,
    shape: ShapeTarget,
    units: Units,
    *,
    starts: int = 3,
    seed: int = 0,
    frame: str = "lab",
):
    """(complete params, the row's :class:`~axojax.inverse.comparison.compare.CompareRow`):
    the linear fit of ``spec`` to psi_1's shape with a free complex amplitude, pinned at
    the observed frequency (:func:`axojax.compare`'s fit of one row): a Hopf point at
    the observed beat, the whole-beat fit's first start. ``frame``: as
    :func:`fit_whole_beat`'s (give both the same)."""
    f_obs = float(units.omega0_to_hz(float(spec.params.omega0)))
    shape = shape_in_basal_frame(shape) if frame == "basal" else shape
    linear = dataclasses.replace(shape, source="linear")
    r = fit_row(spec, linear, units, solver_from_name("lm"), starts, seed, SHAPE_FLOOR, f_obs)
    return r.fit.full_params, r


def observed_measures(shape: ShapeTarget) -> tuple[float, float]:
    """(static curvature, rad/um; dynamic amplitude, rad) of an observed beat, as the
    orbit's are measured (:mod:`axojax.waveform.measures`: the least-squares slope of
    psi_0, the arc-length mean of |psi_1|)."""
    s = np.asarray(shape.s_um, dtype=float)
    return (
        float(wm.static_curvature(s, np.asarray(shape.psi0, dtype=float))),
        float(wm.dynamic_amplitude(s, np.asarray(shape.psi1, dtype=complex))),
    )


@dataclasses.dataclass
class WholeBeatFit:
    """A whole-beat fit: the report, and what it started from.

    Attributes:
        fit: the :class:`~axojax.inverse.FitResult` (``achieved``: the limit cycle's
            frequency, static curvature, dynamic amplitude... and
            ``r2_psi1_with_amplitude``; ``params``: the fitted
            dimensionless values; ``conditions[0]["params"]`` also ``tau_m``, ``f_sat``).
        r2: R^2 of psi_1 with its amplitude included (no free complex amplitude).
        measures: the fitted orbit's scalar measures (physical units), with
            ``psi_offset_rad``.
        tau_m: the motors' time (dimensionless; fitted or given), ``f_sat`` and
            ``params`` (complete :class:`~axojax.Params`) at the optimum.
        start: the start's params and f_sat.
        problem: the :class:`~axojax.inverse.Problem` fitted.
        psi_offset_rad: the reference angle c (rad; psi0_obs ~ psi0_model + c, fitted in
            the lab frame, 0 in the basal frame: :mod:`axojax.inverse.cycle_targets`).
        frame: ``"lab"`` or ``"basal"``, the frame psi was compared in.
        large_cycle: whether the fit started on the large cycle of a subcritical Hopf
            point (:func:`start_values`), not from the normal form.
    """

    fit: FitResult
    r2: float
    measures: dict[str, float]
    tau_m: float
    f_sat: float
    params: Params
    start: tuple[Params, float]
    problem: object
    psi_offset_rad: float = 0.0
    frame: str = "lab"
    large_cycle: bool = False


def psi1_r2(observed, fitted) -> float:
    """R^2 = 1 - sum |obs - fit|^2 / sum |obs - mean obs|^2 (Sartori's measure, with the
    amplitude included: ``fitted`` is not rescaled)."""
    obs, fit = np.asarray(observed, dtype=complex), np.asarray(fitted, dtype=complex)
    return float(1.0 - np.sum(np.abs(obs - fit) ** 2) / np.sum(np.abs(obs - obs.mean()) ** 2))


def fit_whole_beat(
    spec: Row,
    hopf: Params,
    shape: ShapeTarget,
    frequency: Target,
    units: Units,
    *,
    tau_m: float | None = None,
    fit_tau_m: bool = False,
    cubic: float = 0.0,
    fit_cubic: bool = False,
    past: float = PAST,
    max_steps: int = MAX_STEPS,
    frame: str = "lab",
) -> WholeBeatFit:
    """Fit the limit cycle of the row ``spec`` (a regulated mechanism on any base: on a free
    or head one the orbit's rigid offset is fixed by phase conditions,
    :mod:`axojax.orbits.rigid`) to a whole observed beat.

    Args:
        spec: the row (:func:`axojax.inverse.comparison.mechanisms.row`): model, fixed
            values, the coefficients' bounds.
        hopf: the row's linear fit (a Hopf point at the observed beat), complete params.
        shape: observed psi_1 (rad, absolute amplitude) and psi_0 (rad) at ``s_um``.
        frequency: the observed frequency target (Hz).
        units: physical units.
        tau_m: the motors' time (dimensionless); None: :func:`motor_time`.
        fit_tau_m: fit tau_m too (from ``tau_m``).
        cubic: the links' cubic stiffening (1/L^2; fixed, or the start with ``fit_cubic``:
            0 starts at the low end of its range).
        fit_cubic: fit the cubic stiffening too.
        past: how far past the Hopf point the start is (coefficients scaled).
        max_steps: Levenberg-Marquardt iterations (:data:`MAX_STEPS`).
        frame: ``"lab"`` (default): psi as recorded, psi_0 up to the reference angle
            ``psi_offset_rad`` (the recording's arbitrary direction); ``"basal"``: model
            and data relative to the basal tangent, psi(s, t) - psi(0, t), psi_0 then
            compared exactly (:mod:`axojax.beats.frames`; the shape must start at s = 0,
            and one already in the basal frame is taken as it is). A clamped model's psi is
            0 at the base, so only the data change; a pivot's base angle is subtracted.

    Returns:
        :class:`WholeBeatFit`.
    """
    if spec.mechanism not in ORBIT_MECHANISMS:
        raise ValueError(
            f"mechanism: a whole-beat fit of a regulated row needs sliding, curvature or "
            f"sliding+curvature, got {spec.mechanism!r} (the steady load: axojax fit "
            "--target limit-cycle without --mechanism)"
        )
    if shape.psi0 is None:
        raise ValueError("shape: a whole-beat fit needs the observed psi_0 (the static bend)")
    if frame not in FRAMES:
        raise ValueError(f"frame: expected one of {', '.join(FRAMES)}, got {frame!r}")
    if shape.frame == "basal" and frame == "lab":
        raise ValueError("frame: the shape is in the basal frame; fit it with frame='basal'")
    shape = shape_in_basal_frame(shape) if frame == "basal" else shape
    tau_m = motor_time(spec.model, hopf) if tau_m is None else float(tau_m)
    static, dynamic = observed_measures(shape)
    start, f_sat, orbit = start_values(
        spec.model,
        hopf,
        spec.mechanism,
        tau_m=tau_m,
        static_curvature=static,
        dynamic_amplitude=dynamic,
        units=units,
        cubic=cubic,
        past=past,
    )
    free = [n for n in spec.free if n in FREE[spec.mechanism]] + ["m0", "f_sat"]
    free += ["tau_m"] if fit_tau_m else []
    free += ["cubic"] if fit_cubic else []
    bounds = {k: v for k, v in spec.bounds.items() if k in free}
    coefficient = max(abs(float(start.m0)) * 10, DEFAULT_BOUNDS["m0"][1])
    bounds.update({"m0": (-coefficient, coefficient), "f_sat": (f_sat * 1e-2, f_sat * 1e2)})
    if fit_tau_m:
        bounds["tau_m"] = (tau_m / 30.0, tau_m * 30.0)
    cycle_shape = dataclasses.replace(shape, source="limit_cycle")
    target = Target(frequency.name, frequency.value, frequency.sigma, source="limit_cycle")
    problem = build_problem(
        spec.model,
        start,
        [target],
        free,
        shape=cycle_shape,
        bounds=bounds,
        units=units,
        cubic=cubic,
        tau_m=tau_m,
        f_sat=f_sat,
        mechanism=spec.mechanism,
        base=spec.base,
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = least_squares(
            problem,
            solver_from_name("lm", max_steps),
            starts=1,
            orbits=None if orbit is None else [orbit],
        )
    entry = fit.conditions[0]
    shape_out = entry["shape"]
    fitted = np.asarray(shape_out["psi1_fit_re"]) + 1j * np.asarray(shape_out["psi1_fit_im"])
    orbit = entry["params"]
    r2 = psi1_r2(shape.psi1, fitted)
    fit.achieved["r2_psi1_with_amplitude"] = r2  # beside the orbit's measures
    return WholeBeatFit(
        fit=fit,
        r2=r2,
        measures={k: float(v) for k, v in fit.achieved.items()},
        tau_m=float(orbit.get("tau_m", tau_m)),
        f_sat=float(orbit.get("f_sat", f_sat)),
        params=fit.full_params,
        start=(start, f_sat),
        large_cycle=orbit is not None,
        problem=problem,
        psi_offset_rad=float(fit.achieved.get("psi_offset_rad", 0.0)),
        frame=frame,
    )


def fit_recording(
    spec: Row,
    shape: ShapeTarget,
    frequency: Target,
    units: Units,
    *,
    frame: str = "lab",
    **options,
):
    """The whole-beat fit of the row ``spec`` to a recording, from the start:
    :func:`linear_hopf` (the row's linear fit, a Hopf point at the observed beat), then
    :func:`fit_whole_beat` from it (``frame`` and ``options``, e.g. ``tau_m``,
    ``fit_tau_m``, ``fit_cubic``, as there). Returns ``(WholeBeatFit, the linear row)``
    (a :class:`~axojax.inverse.comparison.compare.CompareRow`)."""
    hopf, linear = linear_hopf(spec, shape, units, frame=frame)
    whole = fit_whole_beat(spec, hopf, shape, frequency, units, frame=frame, **options)
    return whole, linear
