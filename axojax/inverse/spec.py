"""Fit specifications: several observed conditions, their model and free parameters in
one TOML file (``axojax fit --spec FIT.toml``), read into a :class:`FitSpec` and from it
an :class:`~axojax.inverse.Problem`.

The format: :func:`load_spec`. Every problem is a one-line ``ValueError`` that starts with the spec's path.
"""

from __future__ import annotations

import dataclasses
import math
import pathlib
import tomllib
from typing import Any

from .. import _memory
from ..beats import Target, read_beat
from ..beats.targets import RELATIVE_SIGMA
from ..eigen.mode import DEFAULT_SOLVER
from ..eigen.solvers import AbstractEigenSolver
from ..fem.hermite import MAX_ELEMENTS
from ..models import IMBALANCE_KINDS, Model, build_model, load_section
from ..models.presets import preset_section
from ..params import PARAM_NAMES, Params
from ..units import Units
from .conditions import Condition
from .problem import SHAPE_FLOOR, Problem

__all__ = ["SPEC_KEYS", "SPEC_TARGETS", "FitSpec", "load_spec", "read_spec"]

SPEC_KEYS = frozenset(
    {
        "model",
        "model_file",
        "elements",
        "imbalance_kind",
        "kl_ratio",
        "length_um",
        "free",
        "free_per_condition",
        "params",
        "condition",
        "bounds",
    }
)
"""The top-level keys of a spec."""
SPEC_TARGETS = {
    # key: (target name, sigma key, default relative sigma)
    key: (key, sigma_key, RELATIVE_SIGMA[key])
    for key, sigma_key in (
        ("frequency_hz", "frequency_sigma_hz"),
        ("wavelength_um", "wavelength_sigma_um"),
        ("velocity_um_per_s", "velocity_sigma_um_per_s"),
    )
}
"""A condition's scalar targets: key -> (target name, its sigma's key, default relative
sigma: :data:`axojax.beats.targets.RELATIVE_SIGMA`, as ``axojax fit``'s flags have it)."""
_SIGMA_KEYS = frozenset(s for _, s, _ in SPEC_TARGETS.values())


@dataclasses.dataclass(frozen=True)
class FitSpec:
    """A fit specification, read and checked (:func:`read_spec`).

    Attributes:
        path: the spec file.
        model: the model it names, built.
        params: base values of every parameter (the start of the free ones).
        conditions: one :class:`~axojax.inverse.Condition` per ``[[condition]]``.
        free: parameters shared by all conditions; per_condition: fitted per condition.
        bounds: per field ``(low, high)`` in values, or ``None`` (the defaults).
        kl_ratio: ``kl = ks / kl_ratio``, or ``None``.
        units: physical units (the spec's ``length_um`` over the caller's).
        imbalance_kind: how the imbalance is read (the model's).
        data: the summary (:meth:`axojax.beats.BeatData.summary`) of every beat file
            read, with its condition's ``"condition"`` label.
    """

    path: pathlib.Path
    model: Model
    params: Params
    conditions: tuple[Condition, ...]
    free: tuple[str, ...]
    per_condition: tuple[str, ...]
    bounds: dict[str, tuple[float, float]] | None
    kl_ratio: float | None
    units: Units
    imbalance_kind: str
    data: tuple[dict[str, Any], ...] = ()

    def problem(
        self,
        *,
        solver: AbstractEigenSolver = DEFAULT_SOLVER,
        shape_floor: float = SHAPE_FLOOR,
        exclude_base_um: float = 0.0,
        prior=None,
    ) -> Problem:
        """The :class:`~axojax.inverse.Problem` of this spec (arguments as
        :class:`~axojax.inverse.Problem`'s)."""
        return Problem(
            self.model,
            self.conditions,
            self.free,
            per_condition=self.per_condition,
            params=self.params,
            bounds=self.bounds,
            kl_ratio=self.kl_ratio,
            units=self.units,
            solver=solver,
            shape_floor=shape_floor,
            exclude_base_um=exclude_base_um,
            prior=prior,
        )


class _Reader:
    """Checks of one spec's values; every failure is ``ValueError("<path>: ...")``."""

    def __init__(self, path: pathlib.Path):
        self.path = path

    def fail(self, problem: str):
        raise ValueError(f"{self.path}: {problem}")

    def number(self, where: str, value) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(f"{where} must be a finite number, got {value!r}")
        if not math.isfinite(value):
            self.fail(f"{where} must be a finite number, got {value!r}")
        return float(value)

    def field(self, where: str, name: str) -> str:
        field = name.replace("-", "_")
        if field not in PARAM_NAMES:
            self.fail(f"{where}: unknown parameter {name!r}; choose from {', '.join(PARAM_NAMES)}")
        return field

    def names(self, key: str, value) -> tuple[str, ...]:
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            self.fail(f'{key} must be a list of parameter names, e.g. ["ks", "cl"]')
        return tuple(self.field(key, v) for v in value)

    def values(self, where: str, table: dict) -> dict[str, float]:
        return {self.field(where, k): self.number(f"{where}.{k}", v) for k, v in table.items()}


def read_spec(
    path: str | pathlib.Path,
    *,
    units: Units = Units(),  # noqa: B008
    imbalance_kind: str | None = None,
    kl_ratio: float | None = None,
) -> FitSpec:
    """Read and check the fit specification at ``path`` (format: :func:`load_spec`).

    Args:
        path: the TOML file; ``model_file`` and ``data`` are relative to its folder.
        units: physical units; the spec's ``length_um`` replaces their length.
        imbalance_kind: the reading of the imbalance when the spec has none (default
            ``"moment"``).
        kl_ratio: ``kl = ks / kl_ratio`` when the spec has no ``kl_ratio``.

    Raises:
        ValueError: one line starting with ``path``: a missing file, bad TOML, an
            unknown key or parameter, a bad value, a model too large for this machine,
            an unreadable beat file.
    """
    path = pathlib.Path(path)
    rd = _Reader(path)
    spec = _load_toml(rd)
    model, kind = _model(rd, spec, imbalance_kind or IMBALANCE_KINDS[0])
    if "length_um" in spec:
        try:
            units = Units(
                rd.number("length_um", spec["length_um"]), units.ei_pn_um2, units.cn_pn_s_um2
            )
        except ValueError as err:
            rd.fail(f"units: {err}")
    if "kl_ratio" in spec:
        kl_ratio = rd.number("kl_ratio", spec["kl_ratio"])
    if kl_ratio is not None and kl_ratio <= 0:
        rd.fail(f"kl_ratio must be > 0, got {kl_ratio:g}")
    free = rd.names("free", spec.get("free", []))
    per = rd.names("free_per_condition", spec.get("free_per_condition", []))
    if not free and not per:
        rd.fail(
            "free: name at least one parameter to fit (free = [...] or free_per_condition = [...])"
        )
    base = spec.get("params", {})
    if not isinstance(base, dict):
        rd.fail("[params] must be a table of parameter values")
    try:
        params = Params().with_values(rd.values("params", base), kl_ratio).validate()
    except ValueError as err:
        rd.fail(f"params: {err}")
    conditions, data = _conditions(rd, spec)
    return FitSpec(
        path=path,
        model=model,
        params=params,
        conditions=conditions,
        free=free,
        per_condition=per,
        bounds=_bounds(rd, spec) or None,
        kl_ratio=kl_ratio,
        units=units,
        imbalance_kind=kind,
        data=data,
    )


def load_spec(path: str | pathlib.Path, **options) -> Problem:
    """The :class:`~axojax.inverse.Problem` of the fit specification at ``path``:
    ``read_spec(path).problem()``.

    The format::

        model = "seven"            # a preset, or model_file = "section.toml" (relative to
                                   # the spec); not both
        elements = 10              # optional: elements per filament (default 10)
        imbalance_kind = "moment"  # optional: how imbalance R is read, "moment" or "force"
                                   # (default: the caller's, itself "moment")
        kl_ratio = 1000            # optional: kl = ks / kl_ratio
        length_um = 12             # optional: the cilium's length (default: the caller's)
        free = ["ks", "kl", "cl", "gamma"]     # shared by all conditions
        free_per_condition = ["p"]             # optional: one value per condition
        [params]                   # fixed values and the start, for every condition
        ks = 4.6e5
        [bounds]                   # optional: [low, high] per parameter, in values
        cl = [1e-3, 10]
        [[condition]]              # one table per observed condition
        label = "p300"             # optional (default: its index)
        source = "fig. 7d"         # optional: where its targets come from
        p = 300                    # its own fixed parameters
        frequency_hz = 51          # targets, each optional; default sigmas 5 % / 10 % / 10 %
        frequency_sigma_hz = 1.0
        wavelength_um = 11
        wavelength_sigma_um = 1
        velocity_um_per_s = 500
        velocity_sigma_um_per_s = 50
        data = "beat.npz"          # a beat file (relative to the spec): its frequency and
                                   # psi_1 shape (:func:`axojax.beats.read_beat`)

    Parameter names are :class:`~axojax.Params` fields (``out_of_plane``) or their flags
    (``out-of-plane``). A scalar target given in a condition overrides the same target of
    its ``data``. The model's size is checked before it is built (the rule of
    :func:`axojax._memory.check_model_size`).

    ``options`` are
    :func:`read_spec`'s keywords (``units``, ``imbalance_kind``, ``kl_ratio``) and
    :meth:`FitSpec.problem`'s (``solver``, ``shape_floor``, ``exclude_base_um``,
    ``prior``).

    >>> problem = ax.inverse.load_spec("fig7.toml")
    >>> result = ax.inverse.least_squares(problem, ax.inverse.LevenbergMarquardt())
    """
    read = {k: options.pop(k) for k in ("units", "imbalance_kind", "kl_ratio") if k in options}
    return read_spec(path, **read).problem(**options)


def _load_toml(rd: _Reader) -> dict:
    if not rd.path.is_file():
        rd.fail("file does not exist")
    try:
        spec = tomllib.loads(rd.path.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        rd.fail(f"not valid TOML ({err})")
    unknown = set(spec) - SPEC_KEYS
    if unknown:
        rd.fail(
            f"unknown key(s) {', '.join(sorted(unknown))}; known: {', '.join(sorted(SPEC_KEYS))}"
        )
    return spec


def _model(rd: _Reader, spec: dict, default_kind: str) -> tuple[Model, str]:
    """The spec's model, its size checked before it is built, and its imbalance kind."""
    elements = spec.get("elements", 10)
    if (
        isinstance(elements, bool)
        or not isinstance(elements, int)
        or not 1 <= elements <= MAX_ELEMENTS
    ):
        rd.fail(f"elements must be an integer in 1..{MAX_ELEMENTS}, got {elements!r}")
    if "model" in spec and "model_file" in spec:
        rd.fail("give model or model_file, not both")
    kind = spec.get("imbalance_kind", default_kind)
    if kind not in IMBALANCE_KINDS:
        rd.fail(f"imbalance_kind must be one of {', '.join(IMBALANCE_KINDS)}, got {kind!r}")
    try:
        if "model_file" in spec:
            section = load_section(rd.path.parent / str(spec["model_file"]))
        else:
            section = preset_section(str(spec.get("model", "seven")))
    except (ValueError, OSError) as err:
        rd.fail(f"model: {err}")
    try:
        _memory.check_model_size(section, elements)
    except ValueError as err:
        rd.fail(f"elements: {err}")
    try:
        return build_model(section, elements, imbalance_kind=kind), kind
    except ValueError as err:
        rd.fail(f"model: {err}")


def _bounds(rd: _Reader, spec: dict) -> dict[str, tuple[float, float]]:
    table = spec.get("bounds", {})
    if not isinstance(table, dict):
        rd.fail(f"[bounds] must be a table of [low, high] pairs, got {table!r}")
    out = {}
    for k, v in table.items():
        field = rd.field("bounds", k)
        if not isinstance(v, list) or len(v) != 2:
            rd.fail(f"bounds.{k} must be [low, high]")
        out[field] = tuple(rd.number(f"bounds.{k}", x) for x in v)
    return out


def _conditions(rd: _Reader, spec: dict) -> tuple[tuple[Condition, ...], tuple[dict, ...]]:
    tables = spec.get("condition", [])
    if not isinstance(tables, list) or not tables:
        rd.fail("no [[condition]] tables: give one per observed condition")
    conditions, data = [], []
    for i, table in enumerate(tables):
        where = f"condition {i + 1}"
        if not isinstance(table, dict):
            rd.fail(f"{where}: each [[condition]] must be a table, got {table!r}")
        conditions.append(_condition(rd, where, str(table.get("label", i)), table, data))
    return tuple(conditions), tuple(data)


def _condition(rd: _Reader, where: str, label: str, table: dict, data: list) -> Condition:
    """One ``[[condition]]`` table; the summary of its beat file (if any) goes to ``data``."""
    fixed, targets, shape, src = {}, [], None, None
    for k, v in table.items():
        if k in ("label", "source") or k in _SIGMA_KEYS:
            continue
        if k == "data":
            src = rd.path.parent / str(v)
            try:
                beat = read_beat(src)
            except (ValueError, OSError) as err:
                rd.fail(f"{where}: data: {err}")
            data.append({**beat.summary(), "condition": label})
            beat_targets, shape = beat.targets()
            have = {u.name for u in targets} | set(table)
            targets += [u for u in beat_targets if u.name not in have]
        elif k in SPEC_TARGETS:
            target = _target(rd, where, k, table)
            targets = [t for t in targets if t.name != target.name] + [target]
        else:
            fixed.update(rd.values(where, {k: v}))
    for sigma_key in _SIGMA_KEYS & set(table):
        if not any(s == sigma_key and k in table for k, (_, s, _) in SPEC_TARGETS.items()):
            rd.fail(f"{where}: {sigma_key} without its target")
    try:
        return Condition(
            params=fixed,
            targets=targets,
            shape=shape,
            label=label,
            source=str(table.get("source", src or rd.path)),
        )
    except ValueError as err:
        rd.fail(f"{where}: {err}")


def _target(rd: _Reader, where: str, key: str, table: dict) -> Target:
    name, sigma_key, rel = SPEC_TARGETS[key]
    value = rd.number(f"{where}.{key}", table[key])
    sigma = (
        rd.number(f"{where}.{sigma_key}", table[sigma_key])
        if sigma_key in table
        else rel * abs(value)
    )
    if value <= 0 or sigma <= 0:
        rd.fail(f"{where}: {key} and its sigma must be > 0, got {value:g} +- {sigma:g}")
    return Target(name, value, sigma)
