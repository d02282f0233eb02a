"""Physical units: converting dimensionless results to Hz, 1/s and um, and physical
parameters to the dimensionless ones (docs/model.md section 1).

Scales: length L, force EI / L^2 (EI of one filament), time tau = c_n L^4 / EI.
"""

from __future__ import annotations

import dataclasses
import math

import jax.numpy as jnp
from jaxtyping import ArrayLike

UNIT_RANGE = (1e-9, 1e9)
"""Accepted range of each physical scale (so tau = c_n L^4 / EI and every conversion stay
finite in float64)."""


def _check_scale(what: str, name: str, v) -> None:
    """One-line ``ValueError`` unless ``v`` is a finite positive number in :data:`UNIT_RANGE`."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
        raise ValueError(f"{what} {name} must be a finite positive number, got {v!r}")
    if not UNIT_RANGE[0] <= v <= UNIT_RANGE[1]:
        raise ValueError(
            f"{what} {name} must be in {UNIT_RANGE[0]:g}..{UNIT_RANGE[1]:g}, got {v!r}"
        )


@dataclasses.dataclass(frozen=True)
class Units:
    """Physical scales of a model (defaults: paper table 2).

    Attributes:
        length_um: cilium length L in um.
        ei_pn_um2: flexural rigidity of one filament in pN um^2 (800/11: one of 11
            microtubules of an 800 pN um^2 axoneme).
        cn_pn_s_um2: resistive-force coefficient of one filament in pN s um^-2.
    """

    length_um: float = 12.0
    ei_pn_um2: float = 800.0 / 11.0
    cn_pn_s_um2: float = 0.003

    def __post_init__(self) -> None:
        for name in ("length_um", "ei_pn_um2", "cn_pn_s_um2"):
            _check_scale("unit", name, getattr(self, name))

    # -- scales ---------------------------------------------------------------------
    @property
    def tau_s(self) -> float:
        """Time scale tau = c_n L^4 / EI in seconds."""
        return self.cn_pn_s_um2 * self.length_um**4 / self.ei_pn_um2

    @property
    def force_pn(self) -> float:
        """Force scale EI / L^2 in pN."""
        return self.ei_pn_um2 / self.length_um**2

    # -- results to physical ----------------------------------------------------------
    def frequency_hz(self, eigenvalue: ArrayLike) -> ArrayLike:
        """|Im lambda| / (2 pi tau)."""
        return jnp.abs(jnp.imag(eigenvalue)) / (2 * jnp.pi * self.tau_s)

    def growth_rate_per_s(self, eigenvalue: ArrayLike) -> ArrayLike:
        """Re lambda / tau."""
        return jnp.real(eigenvalue) / self.tau_s

    def length_to_um(self, length: ArrayLike) -> ArrayLike:
        return length * self.length_um

    # -- physical parameters to dimensionless ---------------------------------------
    def p_from_pn_per_um(self, p_pn_per_um: ArrayLike) -> ArrayLike:
        """Dynein force per length (pN/um) to p = p_dim L^3 / EI."""
        return p_pn_per_um * self.length_um**3 / self.ei_pn_um2

    def p_to_pn_per_um(self, p: ArrayLike) -> ArrayLike:
        return p * self.ei_pn_um2 / self.length_um**3

    def k_from_pn_per_um2(self, k_pn_per_um2: ArrayLike) -> ArrayLike:
        """Distributed stiffness (pN/um^2) to k = k_dim L^4 / EI."""
        return k_pn_per_um2 * self.length_um**4 / self.ei_pn_um2

    def k_to_pn_per_um2(self, k: ArrayLike) -> ArrayLike:
        return k * self.ei_pn_um2 / self.length_um**4

    def c_from_pn_s_per_um2(self, c_pn_s_per_um2: ArrayLike) -> ArrayLike:
        """Link damping (pN s/um^2) to c = c_dim / c_n."""
        return c_pn_s_per_um2 / self.cn_pn_s_um2

    def c_to_pn_s_per_um2(self, c: ArrayLike) -> ArrayLike:
        """Link damping c (dimensionless, c_dim / c_n) to pN s/um^2."""
        return c * self.cn_pn_s_um2

    def ktheta_from_pn_um2(self, ktheta_pn_um2: ArrayLike) -> ArrayLike:
        """Tangent-angle coupling (pN um^2 per rad, per length) to k_theta L^2 / EI."""
        return ktheta_pn_um2 * self.length_um**2 / self.ei_pn_um2

    # -- regulated dynein (docs/model.md, regulated dynein) ----------------------------
    # With kappa = 2 EI, xi_n = 2 c_n and a = a0 L (the two-filament continuum limit),
    # Sartori et al.'s groups are Sp = omega0 (the dimensionless omega0 below),
    # chi_bar = chi a^2 L^2 / kappa = a0^2 chi / 2 and beta_bar = beta a L / kappa
    # = a0 beta / 2, with chi and beta the dimensionless values below.
    def chi_from_pn_per_um2(self, chi_pn_per_um2: ArrayLike) -> ArrayLike:
        """Sliding-control coefficient chi (pN/um^2, a force per length per sliding) to
        chi_dim L^4 / EI (the scaling of a distributed stiffness)."""
        return chi_pn_per_um2 * self.length_um**4 / self.ei_pn_um2

    def chi_to_pn_per_um2(self, chi: ArrayLike) -> ArrayLike:
        return chi * self.ei_pn_um2 / self.length_um**4

    def beta_from_pn(self, beta_pn: ArrayLike) -> ArrayLike:
        """Curvature-control coefficient beta (pN, a force per length per curvature) to
        beta_dim L^2 / EI."""
        return beta_pn * self.length_um**2 / self.ei_pn_um2

    def beta_to_pn(self, beta: ArrayLike) -> ArrayLike:
        return beta * self.ei_pn_um2 / self.length_um**2

    def moment_from_pn(self, m0_pn: ArrayLike) -> ArrayLike:
        """Static dynein moment per length m0 (pN um per um = pN) to m0_dim L^2 / EI
        (:attr:`axojax.Params.m0`)."""
        return m0_pn * self.length_um**2 / self.ei_pn_um2

    def moment_to_pn(self, m0: ArrayLike) -> ArrayLike:
        return m0 * self.ei_pn_um2 / self.length_um**2

    def time_from_ms(self, t_ms: ArrayLike) -> ArrayLike:
        """A time in ms (e.g. the motors' tau_m) to units of tau."""
        return t_ms * 1e-3 / self.tau_s

    def time_to_ms(self, t: ArrayLike) -> ArrayLike:
        return t * self.tau_s * 1e3

    def omega0_from_hz(self, frequency_hz: ArrayLike) -> ArrayLike:
        """Beat frequency (Hz) to the dimensionless angular frequency omega0 = 2 pi f tau."""
        return 2 * jnp.pi * frequency_hz * self.tau_s

    def omega0_to_hz(self, omega0: ArrayLike) -> ArrayLike:
        return omega0 / (2 * jnp.pi * self.tau_s)

    # -- bases (docs/model.md section 8, bases) -----------------------------------------
    # With kappa = 2 EI and a = a0 L, Sartori et al.'s basal group is
    # chi_b_bar = chi_b a^2 L / kappa = a0^2 (kb + i omega0 xib) / 2.
    def kb_from_pn_per_um(self, kb_pn_per_um: ArrayLike) -> ArrayLike:
        """Basal sliding spring k_b (pN/um: force per basal sliding) to k_b L^3 / EI."""
        return kb_pn_per_um * self.length_um**3 / self.ei_pn_um2

    def kb_to_pn_per_um(self, kb: ArrayLike) -> ArrayLike:
        return kb * self.ei_pn_um2 / self.length_um**3

    def cb_to_um_per_pn(self, cb: ArrayLike) -> ArrayLike:
        """Basal compliance cb = EI / (k_b L^3) (:data:`axojax.params.DERIVED_NAMES`) to
        1 / k_b in um/pN (0: a rigid base)."""
        return cb * self.length_um**3 / self.ei_pn_um2

    def xib_from_pn_s_per_um(self, xib_pn_s_per_um: ArrayLike) -> ArrayLike:
        """Basal sliding friction xi_b (pN s/um) to xi_b / (c_n L)."""
        return xib_pn_s_per_um / (self.cn_pn_s_um2 * self.length_um)

    def xib_to_pn_s_per_um(self, xib: ArrayLike) -> ArrayLike:
        return xib * self.cn_pn_s_um2 * self.length_um

    def head_translational_drag(self, zeta_pn_s_per_um: ArrayLike) -> ArrayLike:
        """A body's translational drag zeta_t (pN s/um) to zeta_t / (c_n L)."""
        return zeta_pn_s_per_um / (self.cn_pn_s_um2 * self.length_um)

    def head_rotational_drag(self, zeta_pn_um_s: ArrayLike) -> ArrayLike:
        """A body's (or a pivot's) rotational drag zeta_r (pN um s) to zeta_r / (c_n L^3)."""
        return zeta_pn_um_s / (self.cn_pn_s_um2 * self.length_um**3)

    def pivot_stiffness_from_pn_um(self, k_pn_um_per_rad: ArrayLike) -> ArrayLike:
        """A pivot's rotational spring k_r (pN um/rad) to k_r L / EI."""
        return k_pn_um_per_rad * self.length_um / self.ei_pn_um2


@dataclasses.dataclass(frozen=True)
class Flagellum:
    """Typical physical properties of a kind of flagellum, from the literature: what a
    measured beat's fit assumes when the user gives no units (a bundled data set carries
    its organism's: :mod:`axojax.beats.bundled`).

    Attributes:
        bending_rigidity_pn_um2: kappa, the whole flagellum's flexural rigidity (pN um^2).
        normal_drag_pn_s_um2: xi_n, its normal resistive-force coefficient per length
            (pN s/um^2) in the medium of the observation.
        source: where the two values come from (citations, in words).
    """

    bending_rigidity_pn_um2: float
    normal_drag_pn_s_um2: float
    source: str = ""

    def __post_init__(self) -> None:
        for name in ("bending_rigidity_pn_um2", "normal_drag_pn_s_um2"):
            _check_scale("flagellum", name, getattr(self, name))

    def units(self, length_um: float, n_filaments: int) -> Units:
        """The :class:`Units` of a model of ``n_filaments`` filaments of this flagellum,
        ``length_um`` long: each filament carries 1/F of kappa and of xi_n (kappa = F EI,
        xi_n = F c_n: for the two-filament preset Sartori et al.'s kappa = 2 EI). The
        paper's own default for its seven-filament preset gives each filament 1/11 of the
        axoneme's rigidity instead (one of its 11 microtubules: :class:`Units`); pass
        explicit :class:`Units` to follow that convention."""
        if not (isinstance(n_filaments, int) and n_filaments >= 1):
            raise ValueError(f"n_filaments: expected a positive integer, got {n_filaments!r}")
        return Units(
            float(length_um),
            self.bending_rigidity_pn_um2 / n_filaments,
            self.normal_drag_pn_s_um2 / n_filaments,
        )

    def to_json(self) -> dict:
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True)
class Organism:
    """A preset of one organism's flagellum for a comparison (``axojax compare --organism``):
    its :class:`Flagellum` (kappa, xi_n in water) and its head or cell body as a prolate
    ellipsoid's semi-axes (um) for the ``head`` base, each with its source in words
    (docs/mechanisms.md, units; a value marked "to be confirmed" still needs a source)."""

    name: str
    flagellum: Flagellum
    head_um: tuple[float, float]
    head_source: str = ""


def _lighthill(radius_um: float, wavelength_um: float, viscosity_pa_s: float = 1e-3) -> float:
    """Lighthill's (1976) resistive-force coefficient 4 pi mu / (ln(2q/a) + 1/2), q = 0.09
    lambda, in pN s/um^2 (mu in Pa s = pN s/um^2)."""
    return 4 * math.pi * viscosity_pa_s / (math.log(2 * 0.09 * wavelength_um / radius_um) + 0.5)


ORGANISMS: dict[str, Organism] = {
    o.name: o
    for o in (
        Organism(
            "human_sperm",
            Flagellum(
                1900.0,
                3.2e-3,
                "kappa: Saggiorato et al., Nat. Commun. 8:1415 (2017), fig. 4 (uniform rigidity "
                "reproducing human sperm beats); xi_n: Lighthill (1976), a 0.25 um, lambda 45 um, water",
            ),
            (2.5, 1.5),
            "a human sperm head, about 5 x 3 um (WHO laboratory manual, 5th ed. 2010: head length "
            "4-5.5 um, width 2.5-3.5 um)",
        ),
        Organism(
            "bull_sperm",
            Flagellum(
                1700.0,
                3.4e-3,
                "kappa 1700 pN um^2 and xi_n 3.4e-3 pN s/um^2: Riedel-Kruse et al., HFSP J 1:192 "
                "(2007), as their fitting code states them (JHowardLab/AxonemeFits, parameters.m: "
                "defBendingRigidity = 1700, defNormalFriction = 0.0034, the bull sperm example)",
            ),
            (4.75, 2.35),
            "a bull sperm head, a flat paddle 9.53 x 4.73 um (major, minor axis; 1219 sperm of two "
            "Jersey bulls, Asian J. Anim. Vet. Adv. 2:196 (2007)) taken as a prolate ellipsoid",
        ),
        Organism(
            "sea_urchin_sperm",
            Flagellum(
                900.0,
                round(_lighthill(0.1, 30.0), 5),
                "kappa: Okuno & Hiramoto, J. Exp. Biol. 79:235 (1979), live echinoderm sperm flagella "
                "0.3-1.5e-21 N m^2 (0.9e-21 taken); xi_n: Lighthill (1976), a 0.1 um, lambda 30 um, water",
            ),
            (2.5, 0.75),
            "a sea urchin sperm head, conical, about 5 x 1.5 um (to be confirmed)",
        ),
        Organism(
            "chlamydomonas",
            Flagellum(
                580.0,
                4.9e-3,
                "Sartori et al., eLife 5:e13258 (2016), appendix 5: 'a bending rigidity of 580 pN um^2' "
                "and 'xi_n ~ 0.0049 pN s um^-2' (water at 24 C, 0.55 um above the surface); their "
                "code's Chlamydomonas examples use 400 pN um^2 and 3.4e-3",
            ),
            (5.0, 4.0),
            "a Chlamydomonas cell body, about 10 um across (Nikon MicroscopyU: 'typically only ten "
            "microns in diameter'), 10 x 8 um taken (to be confirmed against a primary source)",
        ),
    )
}
"""The organism presets of ``axojax compare --organism NAME``: kappa, xi_n and the head's
semi-axes of each, with sources (docs/mechanisms.md, units)."""
