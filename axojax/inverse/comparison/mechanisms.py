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
friction (chi'' < 0) is not the dominant one. With the complex amplitude (2 values),
every row has at most 6 free values.

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
et al.'s free-base fits and Riedel-Kruse et al.'s clamped-head sperm fit. kb and xib are
two more free values (fitted in log: both > 0), so that a row stays within 6 free values
with the amplitude, a row with compliance keeps two values of its own
(:data:`FREE_WITH_COMPLIANCE`): ``steady`` p and kl (ks on presets with spokes; cl and
gamma stay at their :class:`~axojax.Params` defaults), ``sliding`` chi' and chi''
(Riedel-Kruse's sliding control), ``curvature`` chi' and beta'' (Sartori's curvature
control: their beta' = 0), ``sliding+curvature`` chi'' and beta'' (the dynamic parts of
both; chi' = beta' = 0). At lambda = i omega0 the pencil is linear in the complex
chi_b, so for any values of the others the chi_b that puts an eigenvalue exactly at the
observed beat is a small generalised eigenvalue problem (Sartori et al. determine chi_b
so): :func:`hopf_starts` solves it on a grid of the row's own values.

An *elastic* basal compliance (``compliance="elastic"``, bases ``"<kind>+elastic"``) fits
kb only, xib fixed at the negligible low end of its range (a basal spring), so a row keeps
three values of its own (:data:`FREE_ELASTIC`): ``steady`` p, kl, gamma; ``sliding``
chi', chi''; ``curvature`` chi', beta', beta''; ``sliding+curvature`` chi', chi'', beta'
(beta'' = 0: on the human sperm it fits better than beta' = 0, docs/mechanisms.md). Its
starts are the mechanism's Hopf points along a ladder of kb.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...beats.targets import Target
from ...fem import Profiles
from ...models import Base, presets
from ...models import build_model as build_section_model
from ...models.section import Model
from ...params import BASAL_NAMES, MECHANISM_NAMES, Params
from ...units import Units
from ..parameters import DEFAULT_BOUNDS

MECHANISMS = ("steady", "sliding", "curvature", "sliding+curvature")
"""Every mechanism a row can have (docs/model.md section 8); the default set of compare."""
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
}
FREE_WITH_COMPLIANCE = {
    "sliding": ("chi_re", "chi_im", "kb", "xib"),
    "curvature": ("chi_re", "beta_im", "kb", "xib"),
    "sliding+curvature": ("chi_im", "beta_im", "kb", "xib"),
}
"""A regulated row's free values with basal compliance (module docstring); the steady
row's are :func:`steady_free`'s first two and kb, xib."""
FREE_ELASTIC = {
    "sliding": ("chi_re", "chi_im", "kb"),
    "curvature": ("chi_re", "beta_re", "beta_im", "kb"),
    "sliding+curvature": ("chi_re", "chi_im", "beta_re", "kb"),
}
"""A regulated row's free values with an elastic basal compliance (module docstring); the
steady row's are p, kl (or ks), gamma and kb."""
ELASTIC_LADDER = 9
"""Values of kb along which an elastic row's Hopf points are found."""
MAX_HOPF_STARTS = 1024
"""At most about this many Hopf points of an elastic row are screened (evenly taken)."""
COMPLIANCE_GRID = 33 * 33
"""Points of the grid of a compliant row's own free values in :func:`compliance_starts`
(33 values each for two)."""
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
    return {
        "chi_re": (-chi, chi),
        "chi_im": (-chi, chi),
        "beta_re": (-beta, beta),
        "beta_im": (-beta, beta),
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
    zero = {"chi_re": 0.0, "chi_im": 0.0, "beta_re": 0.0, "beta_im": 0.0, "omega0": 0.0}
    if mechanism == "steady":
        free = steady_free(model)
        if mode == "compliance":
            free = (*free[:2], "kb", "xib")
        elif mode == "elastic":
            free = (*free[:2], "gamma", "kb")
        ratio = STEADY_KL_RATIO if "ks" in free else None
        prm = params.replace(**zero)
        bounds = {k: DEFAULT_BOUNDS[k] for k in free if k in DEFAULT_BOUNDS}
        # rigid-body modes (eigenvalue 0) of an unclamped base would tie with a beat at
        # growth 0: follow the mode nearest the observed beat there (module docstring)
        shift = None if kind == "clamped" else 1j * omega0
    else:
        prm = params.replace(**zero).replace(p=0.0, omega0=omega0)
        free = {"": FREE, "compliance": FREE_WITH_COMPLIANCE, "elastic": FREE_ELASTIC}[mode][
            mechanism
        ]
        bounds = {k: v for k, v in coefficient_bounds(model, prm).items() if k in free}
        ratio, shift = None, 1j * omega0
    if mode:
        basal = compliance_bounds(model, prm, omega0)
        # start at the geometric middle of the box (both > 0: xib keeps C regular); an
        # elastic compliance's xib stays at its negligible low end
        prm = prm.replace(**{k: math.sqrt(basal[k][0] * basal[k][1]) for k in ("kb", "xib")})
        if mode == "elastic":
            prm = prm.replace(xib=basal["xib"][0])
        bounds.update({k: v for k, v in basal.items() if k in free})
    return Row(mechanism, base, model, prm, free, bounds, ratio, shift, targets, omega0)


# -- exact Hopf points: starts of a regulated row ------------------------------------------
def _unit_terms(row: Row) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(K0, U_chi, U_beta): at lambda = i omega0 the pencil A + lambda C of the row's
    model is K0 + chi U_chi + beta U_beta, linear in the complex chi = chi' + i chi'' and
    beta = beta' + i beta'' (docs/model.md section 8: the terms equal chi and beta there)."""
    from ...assembly import assemble

    lam = row.shift
    base = row.params.replace(chi_re=0.0, chi_im=0.0, beta_re=0.0, beta_im=0.0)

    def pencil(prm: Params) -> np.ndarray:
        system = assemble(row.model, prm)
        return np.asarray(system.A) + lam * np.asarray(system.C)

    k0 = pencil(base)
    return k0, pencil(base.replace(chi_re=1.0)) - k0, pencil(base.replace(beta_re=1.0)) - k0


def _solve(k: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """Every complex g with K + g U singular (finite generalised eigenvalues)."""
    import scipy.linalg as sl

    g = sl.eig(k, -unit, right=False)
    return g[np.isfinite(g)]


def _grid(bound: float, n: int = 8) -> np.ndarray:
    """0 and +- a geometric ladder up to ``bound`` (n values each side)."""
    ladder = np.geomspace(bound * 1e-3, bound, n)
    return np.concatenate([[0.0], ladder, -ladder])


def _ladder(row: Row, name: str, n: int) -> np.ndarray:
    """``n`` values of a free field inside its bounds: 0 and a signed geometric ladder for
    chi and beta, a geometric one for a positive field."""
    lo, hi = row.bounds[name]
    if name in MECHANISM_NAMES:
        return _grid(hi, n // 2)
    if lo <= 0:  # gamma: signed, fitted linearly
        return np.linspace(lo, hi, n + 2)[1:-1]
    return np.geomspace(lo, hi, n + 2)[1:-1]


def compliance_starts(row: Row) -> np.ndarray:
    """(c, k) values of a row with basal compliance at which i omega (the observed beat)
    is exactly an eigenvalue: on a grid of the row's own free values
    (:data:`COMPLIANCE_GRID` points in all), the complex chi_b = kb + i omega xib that makes the
    pencil A + i omega C singular, kept where kb and xib are inside their bounds. The
    compliance adds kb E + xib E to A and C (E of rank m, the active pairs), so chi_b
    solves det(I + chi_b E K^-1) = 0: m values per grid point (Sartori et al. determine
    chi_b so)."""
    import jax
    import jax.numpy as jnp

    from ...assembly import assemble

    lam = 1j * row.omega
    own = [f for f in row.free if f not in BASAL_NAMES]
    n = max(3, int(round(COMPLIANCE_GRID ** (1 / max(len(own), 1)))))
    grids = np.meshgrid(*[_ladder(row, f, n) for f in own], indexing="ij")
    values = np.stack([g.ravel() for g in grids], axis=1)
    base = row.params.replace(kb=0.0, xib=0.0)

    def pencil(v):
        system = assemble(row.model, base.with_values(dict(zip(own, v)), row.kl_ratio))
        return system.A + lam * system.C

    unit = np.asarray(assemble(row.model, base.replace(kb=1.0)).A) - np.asarray(
        assemble(row.model, base).A
    )
    idx = np.flatnonzero(np.any(unit != 0, axis=1))
    pencils = jax.jit(jax.vmap(pencil))
    kept, chi_b = [], []
    batch = min(256, len(values))  # pencils at a time (bounded memory), one compilation
    for i in range(0, len(values), batch):
        chunk = values[i : i + batch]
        padded = np.vstack([chunk, np.repeat(chunk[-1:], batch - len(chunk), axis=0)])
        k = np.asarray(pencils(jnp.asarray(padded)))[: len(chunk)]
        keep = np.isfinite(k).all(axis=(1, 2)) & (np.linalg.cond(k) < 1e14)
        rhs = np.zeros((int(keep.sum()), k.shape[1], idx.size))
        rhs[:, idx, np.arange(idx.size)] = 1.0
        x = np.linalg.solve(k[keep], rhs)
        mu = np.linalg.eigvals(unit[np.ix_(idx, idx)] @ x[:, idx, :])  # (G, m)
        with np.errstate(divide="ignore", invalid="ignore"):
            chi_b.append(-1.0 / mu)
        kept.append(chunk[keep])
    values, chi_b = np.concatenate(kept), np.concatenate(chi_b)
    rows = []
    for v, gs in zip(values, chi_b):
        for g in gs[np.isfinite(gs)]:
            point = dict(zip(own, v), kb=g.real, xib=g.imag / row.omega)
            rows.append([point[f] for f in row.free])
    return _inside(row, np.array(rows).reshape(-1, len(row.free)))


def _inside(row: Row, out: np.ndarray) -> np.ndarray:
    lo = np.array([row.bounds[f][0] for f in row.free])
    hi = np.array([row.bounds[f][1] for f in row.free])
    return out[np.all((out > lo) & (out < hi), axis=1)]


def hopf_starts(row: Row) -> np.ndarray:
    """(c, k) values of the row's free fields at which i omega0 is exactly an eigenvalue
    (the pins hold), inside the bounds: every Hopf point of ``sliding`` (a generalised
    eigenproblem in chi), of ``curvature`` along a ladder of chi' (one in beta), and of
    ``sliding+curvature`` along a ladder of complex beta (one in chi) and with either
    coefficient 0. With basal compliance, any mechanism: :func:`compliance_starts`.
    Empty for ``steady`` without it (its beat is the dominant mode)."""
    if row.compliance and "xib" in row.free:
        return compliance_starts(row)
    if row.compliance:  # elastic: the Hopf points of the mechanism along a ladder of kb
        lo, hi = row.bounds["kb"]
        rest = dataclasses.replace(row, free=tuple(f for f in row.free if f != "kb"))
        out = [
            np.hstack([p, np.full((len(p), 1), kb)])
            for kb in np.geomspace(lo, hi, ELASTIC_LADDER + 2)[1:-1]
            for p in [_mechanism_hopf(dataclasses.replace(rest, params=row.params.replace(kb=kb)))]
        ]
        order = [*rest.free, "kb"]
        out = np.vstack(out)[:, [order.index(f) for f in row.free]]
        return out[:: max(1, len(out) // MAX_HOPF_STARTS)]
    return _mechanism_hopf(row)


def _mechanism_hopf(row: Row) -> np.ndarray:
    """:func:`hopf_starts` of a row whose compliance, if any, is fixed in its params."""
    if row.shift is None or row.mechanism == "steady":
        return np.zeros((0, len(row.free)))
    k0, u_chi, u_beta = _unit_terms(row)
    b = row.bounds
    points: list[dict[str, float]] = []
    if "chi_im" in row.free:  # sliding, or sliding + curvature: solve for chi
        betas = [0.0]
        if "beta_re" in row.free:  # beta' and (if free) beta'' on a grid
            dynamic = "beta_im" in row.free
            re = _grid(b["beta_re"][1], 3 if dynamic else 8)
            im = _grid(b["beta_re"][1], 3) if dynamic else [0.0]
            betas += [complex(x, y) for x in re for y in im]
        for beta in betas:
            for chi in _solve(k0 + beta * u_beta, u_chi):
                points.append(
                    {
                        "chi_re": chi.real,
                        "chi_im": chi.imag,
                        "beta_re": beta.real,
                        "beta_im": beta.imag,
                    }
                )
    if "beta_im" in row.free:  # curvature (chi' real), or chi'' = 0 of sliding + curvature
        for chi in _grid(b["chi_re"][1]):
            for beta in _solve(k0 + chi * u_chi, u_beta):
                points.append(
                    {"chi_re": chi, "chi_im": 0.0, "beta_re": beta.real, "beta_im": beta.imag}
                )
    out = np.array([[p[f] for f in row.free] for p in points]).reshape(-1, len(row.free))
    return _inside(row, out)
