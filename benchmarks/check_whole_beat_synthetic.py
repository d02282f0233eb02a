"""Whole-beat rows on synthetic recordings of every base and regulated mechanism (issue 54's
first acceptance item).

For each unit system (Chlamydomonas: 12 um, 50 Hz, static curvature -0.17 rad/um, dynamic
amplitude 0.9 rad; sperm: 50 um, 20 Hz, -0.01 rad/um, 0.6 rad; the organisms' kappa and
xi_n of :data:`axojax.units.ORGANISMS`), each base (clamped, clamped+elastic, free, head)
and each regulated mechanism, a recording is made with the model:

- the truth: the row's first exact Hopf point at the frequency
  (:func:`~axojax.inverse.comparison.starts.hopf_starts`) whose beat is the onset mode for
  some motor time (:func:`~axojax.inverse.whole_beat.fit.motor_time`), its coefficients
  20 % past it, m0 and f_sat set to the unit system's static curvature and amplitude
  (f_sat lowered in steps of 15 % where psi would swing more than 5.5 rad at some point)
  (:func:`~axojax.inverse.whole_beat.fit.start_values`, used here only to place the truth);
- its limit cycle (:func:`axojax.limit_cycle`) written as a kymograph of 8 cycles of 48
  frames: psi(s, t) as the orbit draws it (its own psi_2 and higher harmonics), plus a
  reference angle of 1.7 rad and Gaussian noise of 5 % of the mean |psi_1| (fixed seed).

The file is read as a user's would be (:func:`axojax.beats.read_beat`) and the row fitted
as ``axojax compare --target limit-cycle`` fits it
(:func:`~axojax.inverse.whole_beat.compare.fit_whole_row`: linear fit, then the whole
beat, the motor time its default). Printed per row: status, R^2 with amplitude, frequency,
static curvature and amplitude against the truth's, the worst |fitted - truth| / stderr
over the fitted values, and the wall time. The acceptance: every row successful, R^2 >= 0.95,
every value within 3 standard errors.

    python benchmarks/check_whole_beat_synthetic.py [--units chlamydomonas,sperm]
        [--bases clamped,clamped+elastic,free,head] [--mechanisms sliding,curvature,...]

Timings are for one machine and one run, not assertions (the machine may be shared).
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile
import time
import warnings

import numpy as np

import axojax as ax
from axojax.beats import read_beat
from axojax.beats.targets import ShapeTarget
from axojax.inverse.comparison.compare import row_problem
from axojax.inverse.comparison.mechanisms import build_model, row
from axojax.inverse.comparison.starts import hopf_starts, values_to_u
from axojax.inverse.whole_beat.compare import fit_whole_row
from axojax.inverse.whole_beat.fit import motor_time, start_values
from axojax.units import ORGANISMS

SYSTEMS = {  # organism, length (um), frequency (Hz), static curvature (rad/um), amplitude (rad)
    "chlamydomonas": ("chlamydomonas", 12.0, 50.0, -0.17, 0.9),
    "sperm": ("bull_sperm", 50.0, 20.0, -0.01, 0.6),
}
BASES = ("clamped", "clamped+elastic", "free", "head")
MECHANISMS = ("sliding", "curvature", "sliding+curvature")
PAST = 1.2
BASE_ANGLE = 1.7
CYCLES, FRAMES, POINTS, ELEMENTS = 8, 48, 31, 10
SWING = 5.5  # rad: the largest swing of psi at any point (a reader takes up to 2 pi)


def _swing(cycle) -> float:
    """The largest swing of psi (rad) over one period at any point."""
    _, psi = cycle.centreline_beat(np.linspace(0.0, 1.0, POINTS), n_frames=FRAMES, derivative=1)
    return float(np.max(np.ptp(np.asarray(psi), axis=0)))


def _orbit(spec, prm, tau_m, f_sat, start):
    cycle = ax.limit_cycle(spec.model, prm, 0.0, tau_m=tau_m, f_sat=f_sat, start=start)
    return cycle if bool(cycle.converged) else None


def truth_of(spec, units, static, amplitude):
    """(params, tau_m, f_sat, cycle) of the truth (module docstring): the first Hopf point
    whose start gives an orbit that swings psi at most SWING rad (f_sat lowered, the
    beat's size with it, while it swings more)."""
    s = np.linspace(0.0, units.length_um, 11)
    problem = row_problem(spec, ShapeTarget(s, np.exp(-1j * s / units.length_um), 1.0), units)
    for u in values_to_u(problem, hopf_starts(spec))[:20]:
        hopf = problem.condition_params(u, 0)
        try:
            tau_m = motor_time(spec.model, hopf)
            prm, f_sat, orbit = start_values(
                spec.model,
                hopf,
                spec.mechanism,
                tau_m=tau_m,
                static_curvature=static,
                dynamic_amplitude=amplitude,
                units=units,
                past=PAST,
            )
        except ValueError:
            continue
        cycle = _orbit(spec, prm, tau_m, f_sat, orbit)
        for _ in range(16):  # continued in steps of 15 % (a larger one loses the orbit)
            if cycle is None or _swing(cycle) <= SWING:
                break
            f_sat *= 0.85
            cycle = _orbit(spec, prm, tau_m, f_sat, cycle)
        if cycle is not None and _swing(cycle) <= SWING:
            return prm, tau_m, f_sat, cycle
    raise ValueError("no Hopf point of the row gives an orbit of a recording's size")


def recording(path, cycle, units, seed):
    """Write the kymograph of ``cycle`` (module docstring) to ``path``."""
    x = np.linspace(0.0, 1.0, POINTS)
    _, psi = cycle.centreline_beat(x, n_frames=FRAMES, derivative=1)
    _, p1 = cycle.tangent_modes(x)
    P = np.tile(np.asarray(psi), (CYCLES, 1)) + BASE_ANGLE
    rng = np.random.default_rng(seed)
    P = P + 0.05 * float(np.mean(np.abs(np.asarray(p1)))) * rng.normal(size=P.shape)
    f = float(cycle.frequency_hz(units))
    np.savez(
        path, psi=P, s_um=x * units.length_um, frame_rate_hz=FRAMES * f, length_um=units.length_um
    )


def check(system, base, mechanism, folder, seed=0):
    organism, length, hz, static, amplitude = SYSTEMS[system]
    units = ORGANISMS[organism].flagellum.units(length, 2)
    spec = row(mechanism, base, build_model("two", ELEMENTS, base, units), units, hz)
    t0 = time.perf_counter()
    prm, tau_m, f_sat, cycle = truth_of(spec, units, static, amplitude)
    m = ax.orbits.cycle_measures(cycle, None, units)
    path = pathlib.Path(folder) / f"{system}_{base}_{mechanism}.npz".replace("+", "_")
    recording(path, cycle, units, seed)
    targets, shape = read_beat(path).targets()
    row_out = fit_whole_row(spec, shape, targets[0], units)
    fit = row_out.whole
    worst = None
    if fit is not None:
        truth = {n: float(getattr(prm, n)) for n in fit.fit.params if n != "f_sat"}
        truth["f_sat"] = f_sat
        z = [
            abs(fit.fit.params[n] - v) / fit.fit.stderr[n]
            for n, v in truth.items()
            if fit.fit.stderr.get(n)
        ]
        worst = max(z) if z else None
    ok = row_out.successful and (row_out.r2 or 0) >= 0.95 and worst is not None and worst <= 3.0
    print(
        f"{system:14s} {base:16s} {mechanism:18s} {row_out.status:28s} "
        f"R2 {row_out.r2 if row_out.r2 is not None else float('nan'):6.3f}  "
        f"f {row_out.frequency_hz or float('nan'):7.3f}/{float(m.frequency_hz):7.3f} Hz  "
        f"C0 {row_out.static_curvature_rad_per_um or float('nan'):8.4f}/"
        f"{float(m.static_curvature_rad_per_um):8.4f}  "
        f"amp {row_out.dynamic_amplitude_rad or float('nan'):6.3f}/{float(m.dynamic_amplitude_rad):6.3f}  "
        f"worst {worst if worst is not None else float('nan'):6.2f} SE  "
        f"{time.perf_counter() - t0:6.0f} s  {'ok' if ok else 'FAIL'}"
        + (f"  ({row_out.reason})" if row_out.reason else ""),
        flush=True,
    )
    return ok


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--units", default=",".join(SYSTEMS))
    p.add_argument("--bases", default=",".join(BASES))
    p.add_argument("--mechanisms", default=",".join(MECHANISMS))
    args = p.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for system in args.units.split(","):
            for base in args.bases.split(","):
                for mechanism in args.mechanisms.split(","):
                    try:
                        results.append(check(system, base, mechanism, folder))
                    except ValueError as err:
                        print(
                            f"{system:14s} {base:16s} {mechanism:18s} no truth: {err}", flush=True
                        )
                        results.append(False)
    print(f"{sum(results)} of {len(results)} rows meet the acceptance")


if __name__ == "__main__":
    main()
