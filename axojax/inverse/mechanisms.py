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
pins then ask that mode to be the beat. The default set is :data:`DEFAULT_BASES`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..beats.targets import Target
from ..fem import Profiles
from ..models import Base, presets
from ..models import build_model as build_section_model
from ..models.section import Model
from ..params import Params
from ..units import Units
from .parameters import DEFAULT_BOUNDS

MECHANISMS = ("steady", "sliding", "curvature", "sliding+curvature")
"""Every mechanism a row can have (docs/model.md section 8); the default set of compare."""
BASES = ("clamped", "pivot", "free", "head")
"""Base conditions of docs/model.md section 8."""
AVAILABLE_BASES = BASES
"""The bases this version builds (every one of :data:`BASES`)."""
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


def check_names(
    mechanisms, bases, *, mechanism_flag="mechanisms", base_flag="bases"
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The mechanisms and bases as tuples, each known and available, no repeats
    (one-line ``ValueError`` starting with the flag's name otherwise)."""
    mechanisms = tuple(MECHANISMS if mechanisms is None else mechanisms)
    bases = tuple(DEFAULT_BASES if bases is None else bases)
    for flag, names, known in ((mechanism_flag, mechanisms, MECHANISMS), (base_flag, bases, BASES)):
        if not names:
            raise ValueError(f"{flag}: give at least one name ({', '.join(known)})")
        for n in names:
            if n not in known:
                raise ValueError(f"{flag}: unknown name {n!r}; choose from {', '.join(known)}")
        if len(set(names)) < len(names):
            raise ValueError(f"{flag}: each name once, got {', '.join(names)}")
    for b in bases:
        if b not in AVAILABLE_BASES:
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
    :data:`DEFAULT_HEAD_UM` in water made dimensionless with ``units``. ``profiles``:
    static relative x-profiles of EI, p and the links (:class:`axojax.fem.Profiles`, e.g.
    a stiffer base), uniform by default."""
    if preset not in COMPARE_PRESETS:
        raise ValueError(
            f"model: {preset!r} has no active pairs to regulate; choose from {', '.join(COMPARE_PRESETS)}"
        )
    if not (isinstance(n_elements, (int, np.integer)) and 2 <= n_elements <= 200):
        raise ValueError(f"n_elements: expected an integer in 2..200, got {n_elements!r}")
    check_names(("steady",), (base,), base_flag="base")
    if base == "head":
        if head is None:
            head = Base.head_from_ellipsoid(
                *DEFAULT_HEAD_UM, DEFAULT_VISCOSITY_PA_S, Units() if units is None else units
            )
        if not (isinstance(head, Base) and head.kind == "head"):
            raise ValueError(f"head: expected a Base of kind 'head', got {head!r}")
        the_base = head
    else:
        the_base = Base(base)
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
    (:func:`build_model`); ``params`` are the fixed values of the rest."""
    check_names((mechanism,), (base,), mechanism_flag="mechanism", base_flag="base")
    omega0 = float(units.omega0_from_hz(frequency_hz))
    targets = pins(frequency_hz, pin_tolerance)
    zero = {"chi_re": 0.0, "chi_im": 0.0, "beta_re": 0.0, "beta_im": 0.0, "omega0": 0.0}
    if mechanism == "steady":
        free = steady_free(model)
        ratio = STEADY_KL_RATIO if "ks" in free else None
        prm = params.replace(**zero)
        bounds = {k: DEFAULT_BOUNDS[k] for k in free}
        # rigid-body modes (eigenvalue 0) of an unclamped base would tie with a beat at
        # growth 0: follow the mode nearest the observed beat there (module docstring)
        shift = None if base == "clamped" else 1j * omega0
        return Row(mechanism, base, model, prm, free, bounds, ratio, shift, targets)
    prm = params.replace(**zero).replace(p=0.0, omega0=omega0)
    free = FREE[mechanism]
    bounds = {k: v for k, v in coefficient_bounds(model, prm).items() if k in free}
    return Row(mechanism, base, model, prm, free, bounds, None, 1j * omega0, targets)


# -- exact Hopf points: starts of a regulated row ------------------------------------------
def _unit_terms(row: Row) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(K0, U_chi, U_beta): at lambda = i omega0 the pencil A + lambda C of the row's
    model is K0 + chi U_chi + beta U_beta, linear in the complex chi = chi' + i chi'' and
    beta = beta' + i beta'' (docs/model.md section 8: the terms equal chi and beta there)."""
    from ..assembly import assemble

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


def hopf_starts(row: Row) -> np.ndarray:
    """(c, k) values of the row's free fields at which i omega0 is exactly an eigenvalue
    (the pins hold), inside the bounds: every Hopf point of ``sliding`` (a generalised
    eigenproblem in chi), of ``curvature`` along a ladder of chi' (one in beta), and of
    ``sliding+curvature`` along a ladder of complex beta (one in chi) and with either
    coefficient 0. Empty for ``steady`` (its beat is the dominant mode)."""
    if row.shift is None or row.mechanism == "steady":
        return np.zeros((0, len(row.free)))
    k0, u_chi, u_beta = _unit_terms(row)
    b = row.bounds
    points: list[dict[str, float]] = []
    if "chi_im" in row.free:  # sliding, or sliding + curvature: solve for chi
        betas = [0.0]
        if "beta_re" in row.free:
            re, im = _grid(b["beta_re"][1], 3), _grid(b["beta_im"][1], 3)
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
    lo = np.array([row.bounds[f][0] for f in row.free])
    hi = np.array([row.bounds[f][1] for f in row.free])
    return out[np.all((out > lo) & (out < hi), axis=1)]
