"""The hypotheses that :func:`axojax.compare` ranks on one beat: a mechanism (how the dynein
force is set) on a base condition, each posed as its anchors fit it (docs/model.md
section 8, docs/mechanisms.md).

Every row fits the observed psi_1 (first Fourier mode of the tangent angle) with a free
complex amplitude (:func:`axojax.inverse.predictions.shape_fit`), and *pins* the beat
to the observation with two scalar targets of a small sigma (``pin_tolerance``, 0.1 % by
default): growth rate 0 +- tol * omega and frequency f +- tol * f. The pins are
residuals like the shape's, so a row that cannot reach the observed beat pays for it in
chi^2 (and the report shows its frequency and growth rate).

- ``steady`` (the paper's flutter under a steady load): the beat is the *dominant* mode.
  Free: p, the inter-doublet stiffness (ks for presets with radial spokes, kl tied to
  ks / 1000 as in the README's sperm fit; kl for the two-filament preset), the link
  damping cl and the dynein moment gain gamma (4 values, 2 of them used by the pins).
- ``sliding``: chi' and chi'' (2 values: the pins fix them, as in Sartori et al.).
- ``curvature``: beta', beta'' and a passive shear stiffness chi' (3 values; Sartori's
  curvature-control fits have chi' != 0).
- ``sliding+curvature``: chi', chi'', beta', beta'' (4 values).

A regulated row has p = 0 (no steady load) and omega0 fixed at the observed angular
frequency, so its terms equal chi(omega0) and beta(omega0) at the beat; its beat is the
eigenvalue *nearest* i omega0 (:func:`axojax.nearest_mode`), which with an active
friction (chi'' < 0) is not the dominant one. Without basal compliance a row has at
most 4 free values (the complex amplitude, 2 more, not counted).

Bounds of chi and beta come from Sartori's dimensionless groups of the two-filament
continuum limit (``chi_bar = a0^2 chi / 2``, ``beta_bar = a0 beta / 2``, docs/model.md
section 8): ``|chi_bar| <= 20 (1 + sqrt(Sp))`` and ``|beta_bar| <= 10 (1 + Sp^(1/4))``
with Sp = omega0, the sperm number of the beat (the dispersion relation
k^4 - beta_bar k^3 - chi_bar k^2 + i Sp = 0 gives wavenumbers k ~ Sp^(1/4) and
chi_bar ~ k^2 at a balance). For presets of F filaments the factor 2 becomes F.

Bases (docs/model.md section 8): ``clamped`` (the paper's), ``pivot``, ``free`` (an
isolated axoneme) and ``head`` (a body with drag; by default a prolate ellipsoid of
semi-axes :data:`DEFAULT_HEAD_UM` in water, a human sperm head). On a base that is not
clamped the rigid-body motions are neutral modes (eigenvalue 0), so every row there,
the steady one too, follows the mode nearest i omega0 instead of the dominant one: the
pins then ask that mode to be the beat. The default set is :data:`DEFAULT_BASES`, each
without and with an elastic basal compliance (:data:`DEFAULT_COMPLIANCE`, below).

Basal compliance (``compliance=True`` of :func:`axojax.compare`, or a base named
``"<kind>+compliance"``, e.g. ``"head+compliance"``): the basal sliding of each active pair
is resisted by chi_b = k_b + i omega xi_b (``Params.kb``, ``Params.xib``), as in Sartori
et al.'s free-base fits and Riedel-Kruse et al.'s clamped-head sperm fit. The spring is
fitted as its compliance ``cb = 1/k_b`` (:data:`axojax.params.DERIVED_NAMES`; linear, from
0: a rigid base, which is the base without compliance), the friction xib in log (> 0). An
*elastic* compliance (``compliance="elastic"``, bases ``"<kind>+elastic"``) fits cb only,
xib fixed at the negligible low end of its range (a basal spring).

Nested hypotheses (issue 45): a row's free values are its mechanism's own (above) and
:data:`BASAL_FREE` of its base, so every row contains the rows of :func:`contained`
(sliding+curvature contains sliding and curvature on the same base; ``+compliance``
contains ``+elastic``, which contains the base without), the others' values at their
floor (chi, beta 0, cb 0, xib at its low end). :func:`axojax.compare` fits them in
:func:`nested_order` and starts each row from the optima of the rows it contains too, so
that no row fits worse than one it contains. A row has at most 6 free values (the complex
amplitude not counted).

Starts: at lambda = i omega0 the pencil is linear in the complex chi_b, so for any values
of the others the chi_b that puts an eigenvalue exactly at the observed beat is a small
generalised eigenvalue problem (Sartori et al. determine chi_b so):
:func:`axojax.inverse.comparison.starts.hopf_starts` solves it on a grid of the row's own
values; an elastic row takes the mechanism's Hopf points along a ladder of kb.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...beats.targets import Target
from ...eigen.normal_force import NormalForce
from ...eigen.solvers import AbstractEigenSolver
from ...fem import Profiles
from ...models import Base, presets
from ...models import build_model as build_section_model
from ...models.section import Model
from ...params import CB_FLOOR, Params
from ...units import Units
from ..fitting.fit import build_problem
from ..parameters import DEFAULT_BOUNDS
from ..problem import SHAPE_FLOOR, Problem

MECHANISMS = (
    "steady",
    "sliding",
    "curvature",
    "sliding+curvature",
    "normal-force",
    "sliding+normal-force",
)
"""Every mechanism a row can have (docs/model.md section 8); the default set of compare.
The normal-force rows need a static bend and a clamped base
(:mod:`~axojax.inverse.comparison.static_state`; elsewhere ``not_applicable``)."""
ORBIT_MECHANISMS = ("sliding", "curvature", "sliding+curvature")
"""The regulated mechanisms with a limit cycle (the whole beat's rows)."""
BASES = ("clamped", "pivot", "free", "head")
"""Base conditions of docs/model.md section 8."""
AVAILABLE_BASES = BASES
"""The bases this version builds (every one of :data:`BASES`)."""
COMPLIANCE = "+compliance"
"""Suffix of a base name with basal compliance, kb and xib fitted (``"head+compliance"``)."""
ELASTIC = "+elastic"
"""Suffix of a base name with an elastic basal compliance: kb fitted, xib fixed at
:data:`CHI_B_RANGE`'s negligible low end (``"clamped+elastic"``)."""
SUFFIXES = {"": "", COMPLIANCE: "compliance", ELASTIC: "elastic"}
DEFAULT_BASES = ("clamped", "free", "head")
"""The bases of a comparison by default: held, isolated, and carrying a head."""
DEFAULT_HEAD_UM = (2.5, 1.5)
"""The default head's semi-axes (um): a prolate ellipsoid the size of a human sperm head
(about 5 by 3 um)."""
DEFAULT_VISCOSITY_PA_S = 1e-3
"""The default head's fluid (water, Pa s)."""
COMPARE_PRESETS = ("two", "four", "seven", "nine")
"""Presets with active pairs (``single`` and ``beck`` have no regulated dynein)."""
DEFAULT_PRESET = "two"
"""Sartori's two-filament continuum limit: the regulated mechanisms' equations are the
anchors' there, and it is the smallest model (docs/mechanisms.md: why)."""
DEFAULT_ELEMENTS = 16
PIN_TOLERANCE = 1e-3
"""Relative sigma of the pins: growth rate 0 +- 1e-3 omega, frequency f +- 1e-3 f."""
STEADY_KL_RATIO = 1000.0
"""kl = ks / 1000 for the steady rows of presets with spokes (the README's sperm fit)."""

FREE = {
    "sliding": ("chi_re", "chi_im"),
    "curvature": ("chi_re", "beta_re", "beta_im"),
    "sliding+curvature": ("chi_re", "chi_im", "beta_re", "beta_im"),
    "normal-force": ("normal_re", "normal_im"),
    "sliding+normal-force": ("chi_re", "chi_im", "normal_re", "normal_im"),
}
BASAL_FREE = {"": (), "elastic": ("cb",), "compliance": ("cb", "xib")}
"""What a basal compliance adds to a row's free values (module docstring): the compliance
cb = 1/k_b (from 0: the base without it), and the friction xib for a full compliance."""


def free_values(mechanism: str, model: Model, mode: str = "") -> tuple[str, ...]:
    """A row's free values: the mechanism's own (:func:`steady_free` or :data:`FREE`),
    then :data:`BASAL_FREE` of the base's compliance ``mode`` ("", "elastic",
    "compliance"). Nested by construction: every row contains the rows of
    :func:`contained`."""
    own = steady_free(model) if mechanism == "steady" else FREE[mechanism]
    return (*own, *BASAL_FREE[mode])


MECHANISM_CONTAINS = {
    "sliding+curvature": ("sliding", "curvature"),
    "sliding+normal-force": ("sliding", "normal-force"),
}
"""The mechanisms each generalises (its free values contain theirs, the rest at 0)."""
COMPLIANCE_CONTAINS = {"compliance": ("elastic", ""), "elastic": ("",)}
"""The compliance modes each generalises: xib at its low end is the elastic base, cb = 0
the base without compliance."""


def contained(mechanism: str, base: str) -> list[tuple[str, str]]:
    """Every (mechanism, base) the row (``mechanism``, ``base``) contains, itself excluded:
    its free values include theirs, and its other values at their floor (chi, beta 0; cb
    0; xib at its low end) make it theirs (issue 45: a row can never fit worse than a row
    it contains, since it starts from their optima too)."""
    kind, mode = parse_base(base)
    mechs = (mechanism, *MECHANISM_CONTAINS.get(mechanism, ()))
    modes = (mode, *COMPLIANCE_CONTAINS.get(mode, ()))
    suffix = {v: k for k, v in SUFFIXES.items()}
    out = [(m, kind + suffix[c]) for c in modes for m in mechs]
    return [x for x in out if x != (mechanism, base)]


def nested_order(combos) -> list[tuple[str, str]]:
    """``combos`` (mechanism, base) ordered so that every row comes after the rows it
    contains (:func:`contained`), otherwise as given."""
    level = {"": 0, "elastic": 1, "compliance": 2}
    return sorted(
        combos,
        key=lambda mb: (level[parse_base(mb[1])[1]], mb[0] in MECHANISM_CONTAINS),
    )


CHI_B_RANGE = (1e-3, 1e2)
"""Bounds of each part of chi_b_bar = a0^2 (kb + i omega0 xib) / F (Sartori's basal group,
F filaments) in units of 1 + Sp^(1/2), as chi's (Sartori's chi_b_bar is about 4 at
Sp 68; Riedel-Kruse's bull sperm about 100)."""


@dataclasses.dataclass(frozen=True)
class Row:
    """One hypothesis, ready to fit: everything :func:`axojax.inverse.build_problem`
    needs besides the observed shape.

    Attributes:
        mechanism, base: its names.
        model: the model (one preset for every row of a comparison).
        params: fixed values and the start of the free ones (dimensionless).
        free: the fitted :class:`~axojax.Params` fields.
        bounds: (low, high) per free field (values).
        kl_ratio: kl = ks / kl_ratio, or None.
        shift: None (the beat is the dominant mode) or i omega0 (the mode nearest it).
        targets: the pins (growth rate 0 and the observed frequency, sigma ``tol``).
        omega: the observed angular frequency (dimensionless, omega0 of the beat).
        solver: the eigen-solver its beat needs (None: the problem's default;
            :class:`~axojax.eigen.NormalForce` for normal-force control).
    """

    mechanism: str
    base: str
    model: Model
    params: Params
    free: tuple[str, ...]
    bounds: dict[str, tuple[float, float]]
    kl_ratio: float | None
    shift: complex | None
    targets: tuple[Target, ...]
    omega: float = 0.0
    solver: AbstractEigenSolver | None = None

    @property
    def compliance(self) -> bool:
        """Whether the row's base has basal compliance (kb free; xib too unless elastic)."""
        return bool(self.model.base.compliance)


def parse_base(name: str) -> tuple[str, str]:
    """A base name -> (kind, compliance): ``"head+compliance"`` -> ``("head",
    "compliance")``, ``"clamped+elastic"`` -> ``("clamped", "elastic")``, ``"free"`` ->
    ``("free", "")``."""
    for suffix, mode in SUFFIXES.items():
        if suffix and isinstance(name, str) and name.endswith(suffix):
            return name[: -len(suffix)], mode
    return name, ""


COMPLIANCE_FORMS = {
    False: ("",),
    True: (COMPLIANCE,),
    "elastic": (ELASTIC,),
    "both": ("", COMPLIANCE),
    "both-elastic": ("", ELASTIC),
    "all": ("", COMPLIANCE, ELASTIC),
}
"""Each ``compliance`` value of :func:`with_compliance` and the base-name suffixes it
gives every base ("": none; :data:`COMPLIANCE`: kb and xib; :data:`ELASTIC`: kb)."""
DEFAULT_COMPLIANCE = "both-elastic"
"""The default set's compliance: every default base without and with a basal spring
(docs/mechanisms.md: why)."""


def with_compliance(bases, compliance=None) -> tuple[str, ...] | None:
    """``bases`` (None: :data:`DEFAULT_BASES`) with basal compliance, by
    :data:`COMPLIANCE_FORMS`: ``False`` leaves them as named (None stays None), ``True``
    gives each :data:`COMPLIANCE`, ``"elastic"`` :data:`ELASTIC`, ``"both"`` lists each
    without and with :data:`COMPLIANCE`, ``"both-elastic"`` without and with
    :data:`ELASTIC`, ``"all"`` all three. ``None`` (the default): the default bases with
    :data:`DEFAULT_COMPLIANCE`, named bases as named. One-line ``ValueError`` for another
    value."""
    if compliance is None:
        compliance = DEFAULT_COMPLIANCE if bases is None else False
    if isinstance(compliance, np.bool_):
        compliance = bool(compliance)
    if not any(
        compliance is k or (isinstance(k, str) and compliance == k) for k in COMPLIANCE_FORMS
    ):
        raise ValueError(
            "compliance: expected True, False, 'elastic', 'both', 'both-elastic' or 'all', "
            f"got {compliance!r}"
        )
    if compliance is False:
        return None if bases is None else tuple(bases)
    names = DEFAULT_BASES if bases is None else tuple(bases)
    kinds = [parse_base(n)[0] for n in names]
    forms = COMPLIANCE_FORMS[compliance]
    return tuple(k + f if isinstance(k, str) else k for k in kinds for f in forms)


def check_names(
    mechanisms, bases, *, mechanism_flag="mechanisms", base_flag="bases"
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The mechanisms and bases as tuples, each known and available, no repeats
    (one-line ``ValueError`` starting with the flag's name otherwise). A base is a kind of
    :data:`BASES`, with :data:`COMPLIANCE` or :data:`ELASTIC` appended for basal compliance."""
    mechanisms = tuple(MECHANISMS if mechanisms is None else mechanisms)
    bases = tuple(DEFAULT_BASES if bases is None else bases)
    known_bases = tuple(b + suffix for suffix in SUFFIXES for b in BASES)
    for flag, names, known, shown in (
        (mechanism_flag, mechanisms, MECHANISMS, MECHANISMS),
        (base_flag, bases, known_bases, (*BASES, f"each with {COMPLIANCE} or {ELASTIC}")),
    ):
        if not names:
            raise ValueError(f"{flag}: give at least one name ({', '.join(shown)})")
        for n in names:
            if n not in known:
                raise ValueError(f"{flag}: unknown name {n!r}; choose from {', '.join(shown)}")
        if len(set(names)) < len(names):
            raise ValueError(f"{flag}: each name once, got {', '.join(names)}")
    for b in bases:
        if parse_base(b)[0] not in AVAILABLE_BASES:
            raise ValueError(
                f"{base_flag}: base {b!r} is not built yet in this version; available: "
                + ", ".join(AVAILABLE_BASES)
            )
    return mechanisms, bases


def _has_spokes(model: Model) -> bool:
    return bool(np.any(np.asarray(model.link_is_spoke)))


def steady_free(model: Model) -> tuple[str, ...]:
    """The steady row's free values on ``model`` (module docstring)."""
    return ("p", "ks", "cl", "gamma") if _has_spokes(model) else ("p", "kl", "cl", "gamma")


def coefficient_bounds(model: Model, params: Params) -> dict[str, tuple[float, float]]:
    """Bounds of chi', chi'', beta', beta'' (dimensionless, module docstring)."""
    a0 = float(params.a0)
    sp = max(float(params.omega0), 0.0)
    f = model.n_filaments
    chi = 20.0 * (1.0 + math.sqrt(sp)) * f / a0**2
    beta = 10.0 * (1.0 + sp**0.25) * f / a0
    # the normal-force gain acts through the static moment: g m0 / F plays beta's part
    normal = beta * a0 / max(abs(float(params.m0)), 1e-12)
    return {
        "chi_re": (-chi, chi),
        "chi_im": (-chi, chi),
        "beta_re": (-beta, beta),
        "beta_im": (-beta, beta),
        "normal_re": (-normal, normal),
        "normal_im": (-normal, normal),
    }


def compliance_bounds(model: Model, params: Params, omega: float) -> dict[str, tuple[float, float]]:
    """Bounds of kb and xib (dimensionless, positive): each part of
    chi_b_bar = a0^2 (kb + i omega xib) / F in :data:`CHI_B_RANGE` times 1 + omega^(1/2),
    omega the beat's (dimensionless: its sperm number; module docstring)."""
    if not (math.isfinite(omega) and omega > 0):
        raise ValueError(f"omega must be > 0 for the bounds of a basal compliance, got {omega!r}")
    scale = (1.0 + math.sqrt(omega)) * model.n_filaments / float(params.a0) ** 2
    lo, hi = (scale * x for x in CHI_B_RANGE)
    return {"kb": (lo, hi), "xib": (lo / omega, hi / omega)}


def pins(frequency_hz: float, tolerance: float = PIN_TOLERANCE) -> tuple[Target, ...]:
    """Growth rate 0 +- tol 2 pi f (1/s) and frequency f +- tol f (Hz)."""
    if not (math.isfinite(frequency_hz) and frequency_hz > 0):
        raise ValueError(f"frequency must be > 0 Hz to pin a beat, got {frequency_hz!r}")
    if not (math.isfinite(tolerance) and 0 < tolerance < 1):
        raise ValueError(f"pin_tolerance must be in (0, 1), got {tolerance!r}")
    return (
        Target("growth_rate_per_s", 0.0, tolerance * 2 * math.pi * frequency_hz),
        Target("frequency_hz", float(frequency_hz), tolerance * frequency_hz),
    )


def build_model(
    preset: str,
    n_elements: int,
    base: str,
    units: Units | None = None,
    head: Base | None = None,
    profiles: Profiles | None = None,
) -> Model:
    """The model of a row: ``preset`` at ``n_elements`` with ``base``; a ``head`` base is
    ``head`` (a :class:`~axojax.models.Base` of kind head), by default the ellipsoid of
    :data:`DEFAULT_HEAD_UM` in water made dimensionless with ``units``; a base named
    ``"<kind>+compliance"`` or ``"<kind>+elastic"`` carries basal compliance
    (:func:`parse_base`). ``profiles``:
    static relative x-profiles of EI, p and the links (:class:`axojax.fem.Profiles`, e.g.
    a stiffer base), uniform by default."""
    if preset not in COMPARE_PRESETS:
        raise ValueError(
            f"model: {preset!r} has no active pairs to regulate; choose from {', '.join(COMPARE_PRESETS)}"
        )
    if not (isinstance(n_elements, (int, np.integer)) and 2 <= n_elements <= 200):
        raise ValueError(f"n_elements: expected an integer in 2..200, got {n_elements!r}")
    check_names(("steady",), (base,), base_flag="base")
    base, mode = parse_base(base)
    compliance = bool(mode)
    if base == "head":
        if head is None:
            head = Base.head_from_ellipsoid(
                *DEFAULT_HEAD_UM, DEFAULT_VISCOSITY_PA_S, Units() if units is None else units
            )
        if not (isinstance(head, Base) and head.kind == "head"):
            raise ValueError(f"head: expected a Base of kind 'head', got {head!r}")
        the_base = dataclasses.replace(head, compliance=compliance)
    else:
        the_base = Base(base, compliance=compliance)
    section = getattr(presets, f"{preset}_section")()
    return build_section_model(section, int(n_elements), profiles or Profiles(), base=the_base)


def row(
    mechanism: str,
    base: str,
    model: Model,
    units: Units,
    frequency_hz: float,
    *,
    params: Params = Params(),  # noqa: B008
    pin_tolerance: float = PIN_TOLERANCE,
) -> Row:
    """The one place a row's parameters, free values, bounds and beat selection are set
    (module docstring). ``model`` must have been built for ``base``
    (:func:`build_model`; a model whose base has compliance fits kb and xib too);
    ``params`` are the fixed values of the rest."""
    check_names((mechanism,), (base,), mechanism_flag="mechanism", base_flag="base")
    kind, mode = parse_base(base)
    if bool(mode) != bool(model.base.compliance) or kind != model.base.kind:
        raise ValueError(f"base: the model's base is not {base!r} (build it with build_model)")
    omega0 = float(units.omega0_from_hz(frequency_hz))
    targets = pins(frequency_hz, pin_tolerance)
    zero = dict.fromkeys(("chi_re", "chi_im", "beta_re", "beta_im", "normal_re", "normal_im"), 0.0)
    zero["omega0"] = 0.0
    free = free_values(mechanism, model, mode)
    solver = None
    if mechanism == "steady":
        ratio = STEADY_KL_RATIO if "ks" in free else None
        prm = params.replace(**zero)
        bounds = {k: DEFAULT_BOUNDS[k] for k in free if k in DEFAULT_BOUNDS}
        # rigid-body modes (eigenvalue 0) of an unclamped base would tie with a beat at
        # growth 0: follow the mode nearest the observed beat there (module docstring)
        shift = None if kind == "clamped" else 1j * omega0
    else:
        prm = params.replace(**zero).replace(p=0.0, omega0=omega0)
        bounds = {k: v for k, v in coefficient_bounds(model, prm).items() if k in free}
        ratio, shift = None, 1j * omega0
        if "normal_re" in free:
            solver = NormalForce()
    if mode:
        basal = compliance_bounds(model, prm, omega0)
        # start at the geometric middle of the box (both > 0: xib keeps C regular); an
        # elastic compliance's xib stays at its negligible low end
        prm = prm.replace(**{k: math.sqrt(basal[k][0] * basal[k][1]) for k in ("kb", "xib")})
        if mode == "elastic":
            prm = prm.replace(xib=basal["xib"][0])
        bounds["cb"] = (0.0, 1.0 / basal["kb"][0])  # from a rigid base (cb = 0)
        if "xib" in free:
            bounds["xib"] = basal["xib"]
    return Row(mechanism, base, model, prm, free, bounds, ratio, shift, targets, omega0, solver)


def row_at_bound(row: Row, values: dict[str, float], at_bound) -> list[str]:
    """The fit's ``at_bound`` names, with cb's read on the scale of a spring: cb spans five
    decades of k_b linearly from 0, so 1 % of its range (the fit report's rule) is most
    of them; cb is at its low end only when the spring is stiffer than the range's
    stiffest (:func:`compliance_bounds`: a base as good as rigid), at its high end when
    softer than 1.01 times the softest."""
    out = [n for n in at_bound if n != "cb"]
    if "cb" in values and "cb" in row.bounds:
        lo, hi = compliance_bounds(row.model, row.params, row.omega)["kb"]
        cb = values["cb"]
        if cb <= compliance_of(hi) or cb >= compliance_of(1.01 * lo):
            out.append("cb")
    return out


def compliance_of(kb: float) -> float:
    """The cb that :meth:`Params.replace` maps to exactly ``kb`` (:data:`DERIVED_NAMES`)."""
    return 1.0 / kb - CB_FLOOR


def row_problem(spec, shape, units: Units, shape_floor: float = SHAPE_FLOOR) -> Problem:
    """The inverse problem of one row (a :class:`~axojax.inverse.comparison.mechanisms.Row`)
    on the observed ``shape`` (a :class:`~axojax.beats.ShapeTarget`)."""
    return build_problem(
        spec.model,
        spec.params,
        list(spec.targets),
        spec.free,
        shape=shape,
        bounds=spec.bounds,
        kl_ratio=spec.kl_ratio,
        units=units,
        shape_floor=shape_floor,
        shift=spec.shift,
        mechanism=spec.mechanism,
        base=spec.base,
        **({} if spec.solver is None else {"solver": spec.solver}),
    )
