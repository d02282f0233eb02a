"""``axojax compare --target limit-cycle``: the regulated mechanisms ranked on the whole
beat (issue 47 item 5; docs/mechanisms.md, "The whole beat").

Each row is a mechanism on a base, fitted as :func:`axojax.compare` fits it (the
linear row: psi_1's shape with a free amplitude, pinned at the observed frequency) and
then as a whole (:func:`axojax.inverse.whole_beat.fit.fit_whole_beat`: the limit cycle with
motor kinetics, saturating motors and a static moment against the frequency, psi_0 and
psi_1 in absolute amplitude). Rows are ranked as the linear comparison ranks them
(:func:`~axojax.inverse.comparison.verdict.rank`: successful rows first, by BIC, BIC
weights among them) and judged by the same verdict
(:func:`~axojax.inverse.comparison.verdict.verdict`), on the whole beat's residuals
(3 S + 1: psi_0, Re and Im of psi_1 at S points, the frequency; psi_0 up to the
reference angle, counted among a row's fitted values).

A row's status: ``successful`` (converged, its orbit within 2 % of the observed
frequency), the solver's code, ``missed_beat`` (no orbit at the optimum, or off the
observed frequency), or ``not_applicable`` (no start: no motor time makes the fitted beat
the onset mode, or no orbit near its Hopf point for any saturation tried: e.g. a
subcritical bifurcation), with its reason.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from typing import Any

import numpy as np

from ... import _io
from ..._progress import progress as progress_bar
from ...beats.data import BeatData
from ...beats.frames import in_basal_frame
from ...beats.targets import FRAMES
from ...beats.units import beat_units
from ...models.presets import preset_section
from ...results import jsonable
from ...results import name as result_name
from ...units import Units
from ..comparison.compare import as_beat, model_json, organism_of, physical_values
from ..comparison.mechanisms import (
    DEFAULT_PRESET,
    ORBIT_MECHANISMS,
    build_model,
    check_names,
    row,
)
from ..comparison.robustness import phase_chi2, whole_beat_bootstrap
from ..comparison.table import physical_text
from ..comparison.verdict import FREQUENCY_MATCH, mark, rank, verdict
from .fit import WholeBeatFit, fit_recording, observed_measures

MECHANISMS = ORBIT_MECHANISMS
"""The regulated mechanisms (the steady load's whole beat: ``axojax fit --target
limit-cycle`` without ``--mechanism``)."""
DEFAULT_BASES = ("clamped",)
DEFAULT_ELEMENTS = 10


@dataclasses.dataclass
class WholeBeatRow:
    """One mechanism on one base, fitted to the whole beat.

    Attributes:
        mechanism, base: the hypothesis.
        status, reason: as :class:`~axojax.inverse.comparison.compare.CompareRow`'s
            (module docstring).
        free: fitted names; params: their dimensionless values; physical and
            physical_stderr: the same in physical units (:data:`PHYSICAL`).
        motor_tau_ms: the motors' time; motor_tau_omega0: the same times the observed
            omega0 (dimensionless); motor_tau_source: where it came from (``"default"``:
            :func:`~axojax.inverse.whole_beat.fit.motor_time`'s choice).
        r2: R^2 of psi_1 with its amplitude; linear_r2: the linear row's (amplitude free).
        frequency_hz, static_curvature_rad_per_um, dynamic_amplitude_rad: the fitted
            orbit's (None where none); psi_offset_rad: the reference angle of psi_0
            (psi0_obs ~ psi0_model + c, :mod:`axojax.inverse.cycle_targets`).
        chi2_per_dof, aic, bic, n_free, at_bound: the fit's.
        psi0_model: the orbit's psi_0 (rad) on the data's s, plus its reference angle
            (comparable with the observed); psi1_model: its psi_1 as [re, im] pairs (rad),
            turned to the observed time origin; chi2_rest: the chi^2 of its psi_0 and
            frequency residuals (what the bootstrap over cycles holds).
        large_cycle: whether its Hopf point is subcritical and the fit started on the
            large cycle a simulation from a large bend settles on
            (:func:`~axojax.inverse.whole_beat.fit.start_values`).
        delta_bic, weight: set by the ranking.
        whole: the :class:`~axojax.inverse.whole_beat.fit.WholeBeatFit` (not in the JSON).
    """

    mechanism: str
    base: str
    status: str
    reason: str | None = None
    free: tuple[str, ...] = ()
    params: dict[str, float] = dataclasses.field(default_factory=dict)
    physical: dict[str, float] = dataclasses.field(default_factory=dict)
    physical_stderr: dict[str, float | None] = dataclasses.field(default_factory=dict)
    motor_tau_ms: float | None = None
    motor_tau_omega0: float | None = None
    motor_tau_source: str = "default"
    r2: float | None = None
    linear_r2: float | None = None
    frequency_hz: float | None = None
    static_curvature_rad_per_um: float | None = None
    dynamic_amplitude_rad: float | None = None
    psi_offset_rad: float | None = None
    chi2_per_dof: float | None = None
    aic: float | None = None
    bic: float | None = None
    n_free: int = 0
    at_bound: list[str] = dataclasses.field(default_factory=list)
    delta_bic: float | None = None
    weight: float | None = None
    psi0_model: list[float] | None = None
    psi1_model: list[list[float]] | None = None
    chi2_rest: float | None = None
    large_cycle: bool = False
    wall_s: float = 0.0
    whole: WholeBeatFit | None = dataclasses.field(default=None, repr=False)

    @property
    def successful(self) -> bool:
        return self.status == "successful"

    def to_json(self) -> dict[str, Any]:
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "whole"}
        out["free"] = list(self.free)
        return jsonable(out)


def _physical(fit: WholeBeatFit, units: Units) -> tuple[dict, dict]:
    """The fitted values and their standard errors in physical units (compare's linear
    conversion, :func:`~axojax.inverse.comparison.compare.physical_values`; None where a
    value has no standard error)."""
    values = {**fit.fit.params, "f_sat": fit.f_sat}
    phys = physical_values(values, units)
    se = physical_values({n: fit.fit.stderr.get(n) for n in values}, units)
    return phys, {k: None if k not in se else abs(se[k]) for k in phys}


def fit_whole_row(spec, shape, frequency, units: Units, frame: str = "lab") -> WholeBeatRow:
    """The whole-beat row of ``spec`` (a :func:`~axojax.inverse.comparison.mechanisms.row`)
    in ``frame`` (:func:`~axojax.inverse.whole_beat.fit.fit_whole_beat`'s)."""
    t0 = time.perf_counter()
    try:
        fit, linear = fit_recording(spec, shape, frequency, units, frame=frame)
    except ValueError as err:
        out = WholeBeatRow(spec.mechanism, spec.base, "not_applicable", str(err))
        out.wall_s = time.perf_counter() - t0
        return out
    got = fit.measures
    f = got.get("limit_cycle_frequency_hz")
    f = None if f is None or not math.isfinite(f) else float(f)
    code = result_name(fit.fit.result)
    if code != "successful":
        status, reason = code, f"the least-squares solver stopped before converging ({code})"
    elif f is None:
        status, reason = "missed_beat", "no limit cycle at the optimum"
    elif abs(f - frequency.value) > FREQUENCY_MATCH * frequency.value:
        status = "missed_beat"
        reason = f"its orbit beats at {f:.4g} Hz, off the observed {frequency.value:.4g} Hz"
    else:
        status, reason = "successful", None
    phys, se = _physical(fit, units)
    r = fit.fit
    drawn = r.conditions[0]["shape"]
    psi1 = np.asarray(drawn["psi1_fit_re"]) + 1j * np.asarray(drawn["psi1_fit_im"])
    psi0 = drawn.get("psi0_fit_rad")
    out = WholeBeatRow(
        spec.mechanism,
        spec.base,
        status,
        reason,
        free=tuple(r.names),
        params=dict(r.params),
        physical=phys,
        physical_stderr=se,
        motor_tau_ms=float(units.time_to_ms(fit.tau_m)),
        motor_tau_omega0=float(fit.tau_m * float(fit.params.omega0)),
        r2=fit.r2,
        linear_r2=linear.r2,
        frequency_hz=f,
        static_curvature_rad_per_um=got.get("limit_cycle_static_curvature_rad_per_um"),
        dynamic_amplitude_rad=got.get("limit_cycle_dynamic_amplitude_rad"),
        psi_offset_rad=fit.psi_offset_rad,
        chi2_per_dof=r.chi2_per_dof,
        aic=r.aic,
        bic=r.bic,
        n_free=r.n_free,
        at_bound=list(r.at_bound),
        psi0_model=None if psi0 is None else np.asarray(psi0, dtype=float).tolist(),
        psi1_model=[[float(z.real), float(z.imag)] for z in psi1],
        chi2_rest=_chi2_rest(fit, psi1),
        large_cycle=fit.large_cycle,
        whole=fit,
    )
    out.wall_s = time.perf_counter() - t0
    return out


def n_residuals(points: int) -> int:
    """A whole-beat fit's residual count at ``points`` arc-length points: psi_0, Re and Im
    of psi_1 at each, and the frequency (3 S + 1)."""
    return 3 * points + 1


def psi1_sigma(fit: WholeBeatFit) -> np.ndarray:
    """(S,) the sigma (rad) each of Re and Im of psi_1 was divided by in ``fit``: the
    data's with the problem's shape floor in quadrature."""
    shape = fit.problem.conditions[0].shape
    sigma = np.broadcast_to(np.asarray(shape.sigma, dtype=float), np.shape(shape.s_um))
    return np.sqrt(sigma**2 + float(fit.problem.shape_floor) ** 2)


def _chi2_rest(fit: WholeBeatFit, psi1_model: np.ndarray) -> float | None:
    """The fit's chi^2 less its psi_1 part: what psi_0 and the frequency contribute."""
    r = fit.fit
    if r.chi2_per_dof is None:
        return None
    n_res = n_residuals(len(psi1_model))
    total = r.chi2_per_dof * max(n_res - r.n_free, 1)
    shape = fit.problem.conditions[0].shape
    obs = np.asarray(shape.psi1, dtype=complex)[None, :]
    part = phase_chi2(obs, psi1_model, psi1_sigma(fit))[0]
    return float(total - part)


@dataclasses.dataclass
class WholeBeatComparison:
    """The rows of :func:`compare_whole_beat`, best first, and the observed beat."""

    data: dict[str, Any]
    s_um: np.ndarray
    frequency_hz: float
    model: str
    n_elements: int
    units: Units
    units_source: str
    rows: list[WholeBeatRow]
    wall_s: float
    frame: str = "lab"
    psi0: np.ndarray | None = dataclasses.field(default=None, repr=False)
    psi1: np.ndarray | None = dataclasses.field(default=None, repr=False)
    psi1_cycles: np.ndarray | None = dataclasses.field(default=None, repr=False)

    @property
    def best(self) -> WholeBeatRow:
        return self.rows[0]

    @staticmethod
    def is_document(doc: Any) -> bool:
        """Whether ``doc``, read back from a JSON file, is a whole-beat comparison."""
        return isinstance(doc, dict) and doc.get("kind") == "whole_beat_comparison"

    def robustness(self) -> dict | None:
        """Each successful row's share of first places over bootstrap resamples of the
        recording's cycles, orbits held
        (:func:`~axojax.inverse.comparison.robustness.whole_beat_bootstrap`); None for a
        Fourier-mode file, too few cycles or no successful row."""
        fitted = next((r.whole for r in self.rows if r.successful and r.whole), None)
        if self.psi1_cycles is None or fitted is None:
            return None
        rows = [r.to_json() for r in self.rows]
        return whole_beat_bootstrap(
            rows, self.psi1_cycles, psi1_sigma(fitted), n_residuals(len(self.s_um))
        )

    def to_json(self) -> dict[str, Any]:
        """The ``axojax compare --target limit-cycle --json`` document."""
        data = dict(self.data, s_um=np.asarray(self.s_um, dtype=float).tolist())
        if self.psi1 is not None:
            data["psi1"] = [[float(z.real), float(z.imag)] for z in np.asarray(self.psi1)]
        if self.psi0 is not None:
            data["psi0"] = np.asarray(self.psi0, dtype=float).tolist()
        doc = jsonable(
            {
                "kind": "whole_beat_comparison",
                "data": data,
                "model": model_json(
                    self.model, self.n_elements, self.units, self.frequency_hz, self.units_source
                ),
                "n_residuals": n_residuals(len(self.s_um)),
                "frame": self.frame,
                "rows": [r.to_json() for r in self.rows],
                "wall_s": self.wall_s,
            }
        )
        doc["robustness"] = jsonable(self.robustness())
        doc["verdict"] = jsonable(verdict(doc))
        return doc

    def save(self, path) -> None:
        """Write :meth:`to_json` (read by ``axojax plot REPORT.json``), atomically."""
        _io.write_text(path, json.dumps(self.to_json(), indent=1, allow_nan=False) + "\n")

    def table(self, params: bool = False) -> str:
        return render(self.to_json(), params)


def render(doc: dict[str, Any], params: bool = False) -> str:
    """A whole-beat comparison document as text: the ranked rows (status marks as
    compare's), the verdict, each row's values in physical units."""

    def num(x, fmt):
        width = "".join(c for c in fmt.split(".")[0] if c.isdigit()) or "0"
        return f"{'-':>{width}}" if x is None else format(x, fmt)

    lines = [
        f"{'rank':>4}{'':4} {'mechanism':<18} {'base':<8} {'R^2':>7} {'f (Hz)':>8} "
        f"{'psi0_s (rad/um)':>15} {'|psi1| (rad)':>12} {'chi2/dof':>9} {'BIC':>9} {'dBIC':>8} "
        f"{'weight':>6}"
    ]
    for i, r in enumerate(doc["rows"], 1):
        lines.append(
            f"{i:>4}{mark(r):<4} {r['mechanism']:<18} {r['base']:<8} {num(r['r2'], '7.3f')} "
            f"{num(r['frequency_hz'], '8.3f')} {num(r['static_curvature_rad_per_um'], '15.4f')} "
            f"{num(r['dynamic_amplitude_rad'], '12.3f')} {num(r['chi2_per_dof'], '9.3g')} "
            f"{num(r['bic'], '9.1f')} {num(r['delta_bic'], '8.1f')} {num(r.get('weight'), '6.2f')}"
        )
    for i, r in enumerate(doc["rows"], 1):
        if mark(r):
            lines.append(f"{mark(r)} {i:>2} {r['mechanism']} on {r['base']}: {r['reason']}")
    for i, r in enumerate(doc["rows"], 1):
        if r.get("large_cycle"):
            lines.append(
                f"    {i:>2} {r['mechanism']} on {r['base']}: subcritical Hopf point, fitted from "
                "the large cycle a simulation begun at a large bend settles on"
            )
    d = doc["data"]
    frame = " (relative to the basal tangent)" if doc.get("frame") == "basal" else ""
    lines.append(
        f"observed{frame}: {d['frequency_hz']:.4g} Hz, static curvature "
        f"{d['static_curvature_rad_per_um']:.4f} rad/um, dynamic amplitude "
        f"{d['dynamic_amplitude_rad']:.3f} rad"
    )
    v = doc["verdict"]
    lines += [f"verdict: {v['text']}", f"  ({v['rule']}; R^2 with psi_1's amplitude included)"]
    if params:
        lines.append("fitted values (physical units) +- standard error:")
        lines += [
            f"{i:>4}{mark(r):<4} {r['mechanism']} on {r['base']}: "
            + physical_text(r)
            + (
                ""
                if r["motor_tau_ms"] is None
                else f"; tau_m {r['motor_tau_ms']:.3g} ms{_tau_source(r)}"
            )
            for i, r in enumerate(doc["rows"], 1)
        ]
    m = doc["model"]
    lines.append(
        f"model {m['preset']} ({m['elements']} elements); units: EI {m['ei_pn_um2']:.4g} pN um^2 "
        f"and c_n {m['cn_pn_s_um2']:.3g} pN s/um^2 per filament, L {m['length_um']:.4g} um "
        f"({m['units_source']})"
    )
    return "\n".join(lines)


def _tau_source(r: dict[str, Any]) -> str:
    """Where a row's motor time came from: " (default: omega0 tau_m = 1.5)", " (given)"."""
    source = r.get("motor_tau_source", "default")
    if source == "default" and r.get("motor_tau_omega0") is not None:
        return f" (default: omega0 tau_m = {r['motor_tau_omega0']:.3g})"
    return f" ({source})"


def compare_whole_beat(
    data,
    mechanisms=None,
    bases=None,
    model: str = DEFAULT_PRESET,
    *,
    n_elements: int = DEFAULT_ELEMENTS,
    units: Units | None = None,
    organism=None,
    progress: bool = False,
    frame: str = "lab",
) -> WholeBeatComparison:
    """Fit every regulated mechanism x base to the whole of one beat and rank them.

    Args:
        data: a :class:`~axojax.beats.BeatData`, a beat file or a bundled name; it must
            give psi_0, psi_1 and the frequency.
        mechanisms: names of :data:`MECHANISMS` (default all three).
        bases: base names (:func:`~axojax.inverse.comparison.mechanisms.check_names`;
            default clamped; on a free or head base the orbit's rigid offset is fixed by
            phase conditions, :mod:`axojax.orbits.rigid`).
        model: the preset (default two filaments); n_elements: elements per filament.
        units: EI and c_n per filament (the beat's length is the data's); organism: an
            organism preset's instead; default: the data set's flagellum or axojax's.
        progress: progress over rows on stderr, as :func:`axojax.compare`'s.
        frame: ``"lab"`` (psi as recorded, psi_0 up to each row's reference angle) or
            ``"basal"`` (model and data relative to the basal tangent, psi_0 exact;
            :func:`~axojax.inverse.whole_beat.fit.fit_whole_beat`), as
            :func:`axojax.compare`'s.

    Returns:
        :class:`WholeBeatComparison`, rows best first.
    """
    mechanisms = tuple(MECHANISMS if mechanisms is None else mechanisms)
    bases = tuple(DEFAULT_BASES if bases is None else bases)
    check_names(mechanisms, bases)
    for m in mechanisms:
        if m not in MECHANISMS:
            raise ValueError(
                f"mechanisms: the whole beat compares regulated mechanisms ({', '.join(MECHANISMS)}); "
                f"got {m!r}"
            )
    if frame not in FRAMES:
        raise ValueError(f"frame: expected one of {', '.join(FRAMES)}, got {frame!r}")
    beat: BeatData = as_beat(data)
    beat = in_basal_frame(beat) if frame == "basal" else beat
    targets, shape = beat.targets()
    if shape is None or shape.psi0 is None or not targets:
        raise ValueError("data: the whole beat needs psi_0, psi_1 and the beat frequency")
    shape = dataclasses.replace(shape, frame=frame)
    frequency = targets[0]
    org = organism_of(organism)
    given = units
    units, source = beat_units(
        beat,
        preset_section(model).n_filaments,
        ei_pn_um2=None if given is None else given.ei_pn_um2,
        cn_pn_s_um2=None if given is None else given.cn_pn_s_um2,
        organism=org,
    )
    if given is None and org is not None:
        source = f"the {org.name} preset"  # the whole beat's table names the preset alone
    t0 = time.perf_counter()
    rows = []
    combos = [(m, b) for b in bases for m in mechanisms]
    for mech, base in progress_bar(
        combos, desc="whole-beat rows", unit="row", enable=progress, starting=True
    ):
        the_model = build_model(model, n_elements, base, units)
        spec = row(mech, base, the_model, units, frequency.value)
        rows.append(fit_whole_row(spec, shape, frequency, units, frame))
    rank(rows)
    s = np.asarray(shape.s_um, dtype=float)
    static, dynamic = observed_measures(shape)
    summary = dict(
        beat.summary(),
        frequency_hz=frequency.value,
        static_curvature_rad_per_um=static,
        dynamic_amplitude_rad=dynamic,
    )
    return WholeBeatComparison(
        summary,
        s,
        frequency.value,
        model,
        int(n_elements),
        units,
        source,
        rows,
        time.perf_counter() - t0,
        frame,
        psi0=np.asarray(shape.psi0, dtype=float),
        psi1=np.asarray(shape.psi1, dtype=complex),
        psi1_cycles=beat.psi1_cycles,
    )
