"""``compare``: every hypothesis (mechanism x base) fitted to one observed beat, ranked.

Each row is built by :func:`axojax.inverse.comparison.mechanisms.row` (the one place that sets its
model, fixed values, free values, bounds and beat selection), fitted by least squares
(Levenberg-Marquardt by default) from ``starts`` starts, and reported with Sartori's R^2
of psi_1, chi^2/dof, AIC and BIC (:mod:`axojax.inverse.fitting.quality`). Rows are ordered by
BIC; ``delta_bic`` is each row's BIC minus the best's.

Starts. A regulated row's pins hold exactly on a discrete set of coefficients (its Hopf
points at the observed frequency); :func:`axojax.inverse.comparison.starts.hopf_starts` finds
them as generalised eigenvalues, and these candidates, with a Sobol design of the box,
are *screened*: their loss is evaluated in one vmapped, compiled program, and the
``starts`` best become the fit's starts (:meth:`Problem.prefer`). The steady row
screens a Sobol design only. Every start of a row shares that row's compiled programs.
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
import time
import warnings
from typing import Any

import numpy as np

from ... import _io
from ...beats.data import BeatData, read_beat
from ...beats.frames import in_basal_frame
from ...beats.targets import FRAMES
from ...beats.units import beat_units
from ...models.presets import preset_section
from ...results import jsonable
from ...results import name as result_name
from ...units import ORGANISMS, Organism, Units
from ..fitting.identifiability import distinct_optima
from ..fitting.least_squares import least_squares, solver_from_name
from ..fitting.report import FitResult
from ..problem import SHAPE_FLOOR, Problem
from . import static_state
from .errors import physical_stderr
from .mechanisms import (
    DEFAULT_ELEMENTS,
    DEFAULT_PRESET,
    DEFAULT_VISCOSITY_PA_S,
    PIN_TOLERANCE,
    build_model,
    check_names,
    contained,
    nested_order,
    row,
    row_at_bound,
    row_problem,
    with_compliance,
)
from .robustness import cycle_bootstrap
from .schedule import default_workers, fit_rows
from .starts import SCREEN, hopf_starts, nested_starts, row_starts, screened_starts, values_to_u
from .table import PHYSICAL, render_params, render_table
from .verdict import rank, row_status, verdict

POLISH = 4
"""Further runs of a row's solver from its best start's end while that stopped at the step
limit (:func:`axojax.inverse.least_squares`'s ``polish``)."""


@dataclasses.dataclass
class CompareRow:
    """One fitted hypothesis.

    Attributes:
        mechanism, base: the hypothesis.
        free: its fitted values' names (dimensionless :class:`~axojax.Params` fields).
        params: their fitted values (dimensionless); ``physical``: the same in physical
            units (:data:`axojax.inverse.comparison.table.PHYSICAL`), ``physical_stderr`` their standard errors (the
            Laplace approximation at the optimum with the pins held exactly:
            :mod:`axojax.inverse.comparison.errors`; inf where the data do not determine a
            value, None where the row was not fitted or the value is pinned).
        pinned: the physical names of the values the pins alone fix (the beat held at
            the observed frequency; e.g. the sliding row's chi' and chi''): no error from
            the data, so their ``physical_stderr`` is None.
        status: ``"successful"`` (the solver converged and the beat sits at the observed
            frequency, within 2 %, with growth rate 0 within 3 of the pins' sigmas), the
            solver's failure code (e.g. ``"nonlinear_max_steps_reached"``),
            ``"missed_beat"`` (converged, but off the observed beat) or
            ``"not_applicable"`` (the row cannot reach the beat); ``reason`` in words
            (None when successful).
        weight: the row's BIC weight exp(-dBIC/2) / sum, over the successful rows (None
            for the others): the probability of the row among them.
        frequency_hz, growth_rate_per_s: the beat's (the pins' achieved values).
        r2, chi2_per_dof, aic, bic, n_free: :mod:`axojax.inverse.fitting.quality`.
        delta_bic: BIC minus the best row's.
        at_bound: fitted values at a bound.
        optima (JSON only): the distinct points its starts stopped at, best first, with
            their losses (:func:`axojax.inverse.fitting.identifiability.distinct_optima`).
        contains: the rows this one contains ("mechanism/base",
            :func:`~axojax.inverse.comparison.mechanisms.contained`): it started from
            their optima too, so it fits at least as well as each (they are fitted
            first even when not asked for, and then not ranked).
        psi1_model: (S,) complex: the fitted psi_1 (rad) at the data's s.
        fit: the row's full :class:`~axojax.inverse.FitResult` (None for a row that
            cannot apply, found before any fit).
        problem: the row's :class:`~axojax.inverse.Problem` (not in the JSON), e.g. for
            its posterior: ``ax.posterior(row.problem, init=row.fit, ...)``.
    """

    mechanism: str
    base: str
    free: tuple[str, ...]
    params: dict[str, float]
    physical: dict[str, float]
    frequency_hz: float
    growth_rate_per_s: float
    r2: float | None
    chi2_per_dof: float | None
    aic: float | None
    bic: float | None
    n_free: int
    at_bound: list[str]
    psi1_model: np.ndarray
    fit: FitResult | None
    wall_s: float
    delta_bic: float | None = None
    problem: Problem | None = dataclasses.field(default=None, repr=False)
    status: str = "successful"
    reason: str | None = None
    physical_stderr: dict[str, float | None] = dataclasses.field(default_factory=dict)
    weight: float | None = None
    contains: list[str] = dataclasses.field(default_factory=list)
    pinned: list[str] = dataclasses.field(default_factory=list)

    @property
    def successful(self) -> bool:
        return self.status == "successful"

    @classmethod
    def not_applicable(cls, mechanism: str, base: str, free, reason: str) -> CompareRow:
        """A row that cannot apply to the beat and was not fitted (``fit`` None)."""
        nan = math.nan
        return cls(mechanism, base, tuple(free), {}, {}, nan, nan, None, None, None, None,
                   len(free), [], np.zeros(0, complex), None, 0.0,
                   status="not_applicable", reason=reason)  # fmt: skip

    def laplace(self, jacobian=None):
        """The Laplace approximation of the row's posterior at its optimum: normal in the
        fitted coordinate u (log for positive values, linear for chi and beta) with
        covariance (J^T J)^-1, J the Jacobian of the normalised residuals (shape points
        and pins) in u, uniform prior (:class:`axojax.inverse.sampling.Laplace`: its
        ``quantiles``, ``sd`` and ``to_json`` with the correlations). J^T J is inverted
        after scaling its diagonal to 1 (a linear chi of 1e5 and a log kb differ by
        1e10 in scale, which alone would pass for an unconstrained direction). k model
        derivatives: seconds, where sampling (:func:`axojax.posterior`) takes minutes.
        ``jacobian``: J at the optimum when already known (the fit's report has it)."""
        from ..sampling import Laplace, laplace_of

        if self.problem is None:
            raise ValueError("laplace: this row has no problem (rows read from JSON do not)")
        p = self.problem
        u = values_to_u(p, np.array([[self.fit.params[n] for n in p.names]]))[0]
        jac = np.asarray(p.jacobian(u) if jacobian is None else jacobian, dtype=float)
        precision = jac.T @ jac
        diag = np.diag(precision)
        scale = np.where(diag > 0, 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0)), np.inf)
        finite = np.where(np.isfinite(scale), scale, 1.0)
        lap = laplace_of(p, p.names, u, precision * np.outer(finite, finite))
        cov = lap.cov_u * np.outer(scale, scale)
        return Laplace(lap.names, lap.centre_u, cov, lap.log_coordinate)

    def to_json(self) -> dict[str, Any]:
        return {
            "mechanism": self.mechanism,
            "base": self.base,
            "free": list(self.free),
            "params": dict(self.params),
            "physical": dict(self.physical),
            "physical_stderr": dict(self.physical_stderr),
            "pinned": list(self.pinned),
            "status": self.status,
            "reason": self.reason,
            "weight": self.weight,
            "frequency_hz": self.frequency_hz,
            "growth_rate_per_s": self.growth_rate_per_s,
            "r2": self.r2,
            "chi2_per_dof": self.chi2_per_dof,
            "aic": self.aic,
            "bic": self.bic,
            "delta_bic": self.delta_bic,
            "n_free": self.n_free,
            "at_bound": list(self.at_bound),
            "contains": list(self.contains),
            "optima": [] if self.fit is None else distinct_optima(self.fit.optima),
            "psi1_model": [[float(z.real), float(z.imag)] for z in self.psi1_model],
            "result": None if self.fit is None else result_name(self.fit.result),
            "wall_s": self.wall_s,
        }


@dataclasses.dataclass
class Comparison:
    """The rows of :func:`compare`, best (lowest BIC) first, and the observed beat.

    Attributes:
        data: the beat's summary (what ``axojax data`` prints).
        s_um: (S,) observed arc lengths; psi1: (S,) observed psi_1 (rad, complex);
            psi0: (S,) observed psi_0 (rad) or None.
        frequency_hz: the observed frequency (every row's pin).
        model, n_elements, units: the model all rows share.
        units_source: where ``units`` came from (given, the data set's flagellum, or
            axojax's defaults), in words.
        rows: :class:`CompareRow` s ordered by BIC.
        auxiliary: rows not asked for but contained in asked ones, fitted only for their
            optima (the JSON's ``auxiliary_rows``: names, values, R^2, status; not ranked).
        wall_s: total time (s).
    """

    data: dict[str, Any]
    s_um: np.ndarray
    psi1: np.ndarray
    psi0: np.ndarray | None
    frequency_hz: float
    model: str
    n_elements: int
    units: Units
    rows: list[CompareRow]
    wall_s: float
    pin_tolerance: float = PIN_TOLERANCE
    shape_floor: float = SHAPE_FLOOR
    units_source: str = "given"
    psi1_cycles: np.ndarray | None = dataclasses.field(default=None, repr=False)
    psi1_sigma: np.ndarray | None = dataclasses.field(default=None, repr=False)
    frame: str = "lab"
    auxiliary: list = dataclasses.field(default_factory=list, repr=False)

    @property
    def best(self) -> CompareRow:
        return self.rows[0]

    def to_json(self) -> dict[str, Any]:
        """The ``axojax compare --json`` document (docs/interface.md)."""
        data = dict(self.data)
        data.update(
            frame=self.frame,
            s_um=self.s_um.tolist(),
            psi1=[[float(z.real), float(z.imag)] for z in self.psi1],
            psi0=None if self.psi0 is None else np.asarray(self.psi0, dtype=float).tolist(),
        )
        doc = jsonable(
            {
                "kind": "comparison",
                "data": data,
                "model": model_json(
                    self.model, self.n_elements, self.units, self.frequency_hz, self.units_source
                ),
                "pin_tolerance": self.pin_tolerance,
                "shape_floor_rad": self.shape_floor,
                "rows": [r.to_json() for r in self.rows],
                "auxiliary_rows": [
                    {k: d[k] for k in ("mechanism", "base", "free", "params", "r2", "status")}
                    for d in (r.to_json() for r in self.auxiliary)
                ],
                "wall_s": self.wall_s,
            }
        )
        doc["robustness"] = jsonable(self.robustness(doc["rows"]))
        doc["verdict"] = jsonable(verdict(doc))
        return doc

    def robustness(self, rows: list[dict] | None = None) -> dict | None:
        """Each successful row's share of first places over bootstrap resamples of the
        recording's cycles (:func:`axojax.inverse.comparison.robustness.cycle_bootstrap`;
        None for a Fourier-mode file or too few cycles)."""
        if self.psi1_cycles is None or self.psi1_sigma is None:
            return None
        rows = [r.to_json() for r in self.rows] if rows is None else rows
        sigma = np.sqrt(np.asarray(self.psi1_sigma, float) ** 2 + self.shape_floor**2)
        return cycle_bootstrap(rows, self.psi1_cycles, sigma, self.frequency_hz, self.pin_tolerance)

    def save(self, path: str | pathlib.Path) -> None:
        """Write :meth:`to_json` (read by ``axojax plot REPORT.json``), atomically."""
        _io.write_text(path, json.dumps(self.to_json(), indent=1, allow_nan=False) + "\n")

    @staticmethod
    def is_document(doc: Any) -> bool:
        """Whether ``doc``, read back from a JSON file, is a comparison (:meth:`to_json`)."""
        return isinstance(doc, dict) and doc.get("kind") == "comparison"

    def table(self, params: bool = False) -> str:
        """The rows as a text table, best first, with the status marks' footnotes and the
        verdict; ``params``: the fitted values in physical units with their standard
        errors as a second table (:func:`axojax.inverse.comparison.table.render_params`)."""
        doc = self.to_json()
        return render_table(doc) + ("\n\n" + render_params(doc) if params else "")


def model_json(preset: str, elements: int, units: Units, frequency_hz: float, source: str):
    """A comparison document's ``"model"``: the preset, mesh, units and sperm number."""
    return {
        "preset": preset,
        "elements": elements,
        "length_um": units.length_um,
        "ei_pn_um2": units.ei_pn_um2,
        "cn_pn_s_um2": units.cn_pn_s_um2,
        "sperm_number": float(units.omega0_from_hz(frequency_hz)),
        "units_source": source,
    }


def physical_values(values: dict[str, float], units: Units) -> dict[str, float]:
    """Fitted values (dimensionless) in physical units (:data:`axojax.inverse.comparison.table.PHYSICAL`); the same
    linear conversion turns a standard error into its physical one."""
    out = {}
    for name, v in values.items():
        if name in PHYSICAL and v is not None:
            key, conv = PHYSICAL[name]
            out[key] = float(v) if conv is None else float(getattr(units, conv)(v))
    return out


def default_units(
    beat: BeatData, model: str = DEFAULT_PRESET, n_filaments: int | None = None
) -> tuple[Units, str]:
    """The units a comparison (or ``axojax fit --data``) of ``beat`` assumes when given
    none, and where they come from in words (:func:`axojax.beats.units.beat_units`): the
    data set's flagellum when it is known (a bundled beat: :attr:`BeatData.flagellum`,
    kappa and xi_n shared by the preset's F filaments, or by ``n_filaments``), else
    axojax's :class:`~axojax.Units` (paper table 2: a 12 um cilium's EI and c_n per
    filament), at the beat's length either way."""
    if n_filaments is None:
        n_filaments = preset_section(model).n_filaments
    return beat_units(beat, n_filaments)


def organism_of(organism) -> Organism | None:
    """An :class:`~axojax.units.Organism` from its name (:data:`~axojax.units.ORGANISMS`;
    ``-`` or ``_`` alike), itself, or None; one-line ``ValueError`` for an unknown name."""
    if organism is None or isinstance(organism, Organism):
        return organism
    key = str(organism).strip().lower().replace("-", "_")
    if key not in ORGANISMS:
        raise ValueError(f"organism: unknown name {organism!r}; choose from {', '.join(ORGANISMS)}")
    return ORGANISMS[key]


def as_beat(data) -> BeatData:
    """``data`` as a :class:`~axojax.beats.BeatData`: itself, or read from a file or a
    bundled name (:func:`~axojax.beats.read_beat`)."""
    if isinstance(data, BeatData):
        return data
    if isinstance(data, (str, pathlib.Path)):
        return read_beat(data)
    raise TypeError(f"data must be a BeatData, a file or a bundled name, got {data!r}")


def compare(
    data,
    mechanisms=None,
    bases=None,
    model: str = DEFAULT_PRESET,
    *,
    n_elements: int = DEFAULT_ELEMENTS,
    units: Units | None = None,
    sperm_number: float | None = None,
    starts: int = 3,
    seed: int = 0,
    shape_floor: float = SHAPE_FLOOR,
    pin_tolerance: float = PIN_TOLERANCE,
    method: str = "lm",
    progress: bool = False,
    head=None,
    profiles=None,
    compliance: bool | str | None = None,
    organism: str | Organism | None = None,
    frame: str = "lab",
    workers: int | None = None,
) -> Comparison:
    """Fit every mechanism x base to one beat and rank them by BIC.

    Args:
        data: a :class:`~axojax.beats.BeatData`, a beat file or a bundled name
            (``"human_sperm"``).
        mechanisms: names of :data:`~axojax.inverse.comparison.mechanisms.MECHANISMS` (default all:
            steady, sliding, curvature, sliding+curvature, normal-force,
            sliding+normal-force).
        bases: names of :data:`~axojax.inverse.comparison.mechanisms.BASES` (default
            :data:`~axojax.inverse.comparison.mechanisms.DEFAULT_BASES`: clamped, free, head), each
            optionally with ``+compliance`` (``"head+compliance"``: a basal compliance,
            kb and xib fitted too; :mod:`axojax.inverse.comparison.mechanisms`).
        model: the preset every row uses (default ``two``: the continuum limit of the
            anchors, and the fastest; docs/mechanisms.md).
        n_elements: elements per filament.
        units: EI and c_n (per filament; the length is the data's). Default
            :func:`default_units`: the data set's flagellum when known (the bundled human
            sperm: kappa 1900 pN um^2, xi_n 3.2e-3 pN s/um^2), else :class:`~axojax.Units`.
        sperm_number: Sp = omega xi_n L^4 / kappa of the beat (the dimensionless omega0
            of every regulated row): when given, c_n is set to give it (EI from
            ``units``). The shape a model can reach depends on it most
            (docs/mechanisms.md).
        starts: least-squares starts per row (the best of the screened candidates).
        seed: seed of the Sobol part of the screened design.
        shape_floor: model-discrepancy floor (rad) added in quadrature to psi_1's sigma.
        pin_tolerance: relative sigma of the pins (growth rate and frequency).
        method: least-squares solver (``"lm"``, ``"lbfgs"``, ``"adam"``).
        head: the ``head`` base's :class:`~axojax.models.Base` (default: an ellipsoid of
            :data:`~axojax.inverse.comparison.mechanisms.DEFAULT_HEAD_UM` in water).
        profiles: static relative x-profiles of EI, p and the links for every row's model
            (:class:`axojax.fem.Profiles`; e.g. ``Profiles(ei=lambda x: 3 - 2 * x)``, a base
            three times stiffer than the tip); uniform by default.
        compliance: basal compliance chi_b = k_b + i omega xi_b on the bases
            (:data:`~axojax.inverse.comparison.mechanisms.COMPLIANCE_FORMS`): ``True`` every base with
            it (kb and xib fitted; a row keeps two values of its own, so that it stays
            within 6 with the amplitude: docs/mechanisms.md), ``"elastic"`` a basal spring
            (kb fitted; three of its own), ``"both"`` / ``"both-elastic"`` every base
            without and with the one or the other, ``"all"`` all three, ``False`` the bases
            as named. Default ``None``: the default bases without and with a basal spring
            (``"both-elastic"``: 36 rows), named bases as named.
        organism: a name of :data:`axojax.units.ORGANISMS` (``"human_sperm"``,
            ``"bull_sperm"``, ``"sea_urchin_sperm"``, ``"chlamydomonas"``) or an
            :class:`~axojax.units.Organism`: its kappa and xi_n (unless ``units`` are given)
            and its head's semi-axes (unless ``head`` is given).
        frame: ``"lab"`` (psi as recorded) or ``"basal"`` (model and data relative to the
            basal tangent, psi(s) - psi(0): :mod:`axojax.beats.frames`).
        workers: rows fitted at a time (default: the cores, at most 4; each row the
            same as alone: :mod:`axojax.inverse.comparison.schedule`).
        progress: progress over rows on stderr from the start (the first row's
            compilation included): a bar on a terminal, plain lines into a file or pipe
            (:mod:`axojax._progress`'s rule; ``axojax compare --quiet`` turns it off).

    Raises:
        ValueError: an unknown or unavailable mechanism or base, a bad setting (one
            line naming it).
    """
    mechanisms, bases = check_names(mechanisms, with_compliance(bases, compliance))
    if not (isinstance(starts, (int, np.integer)) and 1 <= starts <= 1000):
        raise ValueError(f"starts: expected an integer in 1..1000, got {starts!r}")
    optimiser = solver_from_name(method)
    if frame not in FRAMES:
        raise ValueError(f"frame: expected one of {', '.join(FRAMES)}, got {frame!r}")
    beat = as_beat(data)
    if frame == "basal":
        beat = in_basal_frame(beat)
    targets, shape = beat.targets()
    if shape is None:
        raise ValueError("data: the beat has no psi_1 shape to compare mechanisms on")
    shape = dataclasses.replace(shape, frame=frame)
    f_obs = float(beat.frequency_hz)
    org = organism_of(organism)
    if org is not None and head is None:
        head = org.head_um  # made a Base below, in the units chosen
    units, units_source = beat_units(
        beat,
        preset_section(model).n_filaments,
        ei_pn_um2=None if units is None else units.ei_pn_um2,
        cn_pn_s_um2=None if units is None else units.cn_pn_s_um2,
        organism=org,
    )
    if sperm_number is not None:
        if not (math.isfinite(sperm_number) and sperm_number > 0):
            raise ValueError(f"sperm_number: must be > 0, got {sperm_number!r}")
        cn = sperm_number / float(units.omega0_from_hz(f_obs)) * units.cn_pn_s_um2
        units = Units(beat.length_um, units.ei_pn_um2, cn)
        units_source += f"; c_n set by the sperm number {sperm_number:g}"
    if isinstance(head, tuple):
        from ...models import Base

        head = Base.head_from_ellipsoid(*head, DEFAULT_VISCOSITY_PA_S, units)
    t0 = time.perf_counter()
    asked = [(m, b) for b in bases for m in mechanisms]
    # the rows each asked row contains are fitted first, for their optima, even when not
    # asked for (then not ranked): a row's fit must never fall below theirs
    combos = nested_order(list(dict.fromkeys(c for a in asked for c in [*contained(*a), a])))

    def fit_one(combo: tuple[str, str], inner: list[CompareRow]) -> CompareRow:
        mech, base = combo
        the_model = build_model(model, n_elements, base, units, head, profiles)
        spec = row(mech, base, the_model, units, f_obs, pin_tolerance=pin_tolerance)
        reason = static_state.not_applicable_reason(mech, base, shape)
        if reason is not None:
            return CompareRow.not_applicable(mech, base, spec.free, reason)
        spec = static_state.with_static_state(spec, shape, units, f_obs, pin_tolerance)
        return fit_row(
            spec, shape, units, optimiser, starts, seed, shape_floor, f_obs, pin_tolerance, inner
        )

    workers = default_workers() if workers is None else workers
    fitted = fit_rows(combos, fit_one, contained, workers=workers, progress=progress)
    rows = [fitted[c] for c in combos if c in set(asked)]  # in the order they were fitted
    auxiliary = [r for c, r in fitted.items() if c not in asked]
    rank(rows)
    return Comparison(
        data=beat.summary(),
        s_um=np.asarray(shape.s_um, dtype=float),
        psi1=np.asarray(shape.psi1, dtype=complex),
        psi0=None if shape.psi0 is None else np.asarray(shape.psi0, dtype=float),
        frequency_hz=f_obs,
        model=model,
        n_elements=int(n_elements),
        units=units,
        rows=rows,
        wall_s=time.perf_counter() - t0,
        pin_tolerance=pin_tolerance,
        shape_floor=shape_floor,
        units_source=units_source,
        psi1_cycles=beat.psi1_cycles,
        psi1_sigma=np.asarray(shape.sigma, dtype=float),
        frame=frame,
        auxiliary=auxiliary,
    )


def fit_row(
    spec,
    shape,
    units,
    optimiser,
    starts,
    seed,
    shape_floor,
    f_obs,
    pin_tolerance=PIN_TOLERANCE,
    inner: list[CompareRow] = (),
) -> CompareRow:
    """One row (``spec``) fitted to the observed psi_1 ``shape`` and frequency ``f_obs``
    (Hz): Hopf-point and screened starts (and the optima of the rows it contains,
    ``inner``), then ``optimiser``; its statistics, status and reason."""
    t0 = time.perf_counter()
    problem = row_problem(spec, shape, units, shape_floor)
    candidates = np.vstack(
        [values_to_u(problem, hopf_starts(spec)), problem.start_design(SCREEN, seed)]
    )
    preferred = np.vstack(
        [
            nested_starts(problem, spec, list(inner)),
            screened_starts(problem, candidates, row_starts(starts, len(spec.free))),
        ]
    )
    problem.prefer(preferred)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = least_squares(problem, optimiser, starts=len(preferred), seed=seed, polish=POLISH)
    shape_data = fit.conditions[0]["shape"]
    psi1 = np.asarray(shape_data["psi1_fit_re"]) + 1j * np.asarray(shape_data["psi1_fit_im"])
    values = dict(fit.params)
    frequency = float(fit.achieved.get("frequency_hz", math.nan))
    growth = float(fit.achieved.get("growth_rate_per_s", math.nan))
    status, reason = row_status(
        spec.mechanism, spec.base, result_name(fit.result), frequency, growth, f_obs, pin_tolerance
    )
    out = CompareRow(
        mechanism=spec.mechanism,
        base=spec.base,
        free=tuple(spec.free),
        params=values,
        physical=physical_values(values, units),
        frequency_hz=frequency,
        growth_rate_per_s=growth,
        r2=fit.r2,
        chi2_per_dof=fit.chi2_per_dof,
        aic=fit.aic,
        bic=fit.bic,
        n_free=fit.n_free,
        at_bound=row_at_bound(spec, values, fit.at_bound),
        psi1_model=psi1,
        fit=fit,
        wall_s=0.0,
        problem=problem,
        status=status,
        reason=reason,
        contains=[f"{r.mechanism}/{r.base}" for r in inner],
    )
    out.physical_stderr, out.pinned = physical_stderr(out, units)
    if spec.mechanism in static_state.NORMAL_MECHANISMS:  # the measured static state's error
        problem_of = lambda s: row_problem(s, shape, units, shape_floor)  # noqa: E731
        static_state.add_static_errors(out, spec, shape, units, problem_of)
    out.wall_s = time.perf_counter() - t0
    return out
