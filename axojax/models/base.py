"""Base conditions: how the axoneme is held at x = 0 (docs/model.md section 8, bases).

A :class:`Base` is static structure, like the mesh: it is chosen when the model is built
(``ax.models.two(base="free")``, ``ax.models.seven(base=Base("head", ...))`` or
``model.with_base(...)``), never a traced flag. Kinds:

- ``clamped`` (default, the paper): u = u' = 0 at x = 0 for every filament.
- ``pivot``: u(0) = 0, u'(0) free, with an optional rotational spring and drag on the
  centreline's basal slope.
- ``free``: nothing held (an isolated axoneme); rigid-body motion included.
- ``head``: free, carrying a body whose position and angle are the centreline's basal
  displacement and slope, with a translational and a rotational drag (given, or from
  an ellipsoid's semi-axes: :meth:`Base.head_from_ellipsoid`).

``compliance=True`` adds, with any kind, a basal sliding Delta_b,a per active pair,
resisted by a spring k_b and a friction xi_b (``Params.kb``, ``Params.xib``; traced).

The constants of the body (drags, the pivot's spring) are dimensionless: a translational
drag zeta_t (pN s/um) is zeta_t / (c_n L), a rotational drag zeta_r (pN um s) is
zeta_r / (c_n L^3), a rotational spring k_r (pN um/rad) is k_r L / EI (c_n and EI of one
filament: :class:`axojax.Units`, whose ``head_*`` methods convert them).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from ..params import MAX_MAGNITUDE

BASE_KINDS = ("clamped", "pivot", "free", "head")
MAX_ASPECT = 1e6
"""Largest accepted semi-axis ratio of an ellipsoidal head (beyond, 1 - e rounds to 0)."""
BASE_DOFS = {"clamped": (), "pivot": (1,), "free": (0, 1), "head": (0, 1)}
"""Node 0's dofs each kind keeps (0: u(0), 1: u'(0)), per filament and direction."""


@dataclasses.dataclass(frozen=True)
class Base:
    """A base condition (module docstring).

    Attributes:
        kind: ``"clamped"``, ``"pivot"``, ``"free"`` or ``"head"``.
        compliance: basal sliding per active pair, resisted by ``Params.kb`` and
            ``Params.xib`` (xib must then be > 0: it keeps the damping matrix regular).
        translational_drag: the head's drag against the basal displacement,
            zeta_t / (c_n L) (``head`` only; > 0).
        rotational_drag: the head's or the pivot's drag against the basal slope,
            zeta_r / (c_n L^3) (``head``: > 0; ``pivot``: >= 0).
        rotational_stiffness: the pivot's spring on the basal slope, k_r L / EI
            (``pivot`` only; >= 0).
    """

    kind: str = "clamped"
    compliance: Any = False  # a bool; anything else is a one-line ValueError
    translational_drag: float | int = 0.0
    rotational_drag: float | int = 0.0
    rotational_stiffness: float | int = 0.0

    def __post_init__(self) -> None:
        if self.kind not in BASE_KINDS:
            raise ValueError(f"unknown base {self.kind!r}; choose one of {', '.join(BASE_KINDS)}")
        if not isinstance(self.compliance, bool):
            raise ValueError(f"base compliance must be True or False, got {self.compliance!r}")
        for name in ("translational_drag", "rotational_drag", "rotational_stiffness"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"base {name} must be a number, got {value!r}")
            if not math.isfinite(value) or value < 0:
                raise ValueError(f"base {name} must be finite and >= 0, got {value!r}")
            if value > MAX_MAGNITUDE:
                raise ValueError(
                    f"base {name} must be at most {MAX_MAGNITUDE:g} (dimensionless; float64 "
                    f"loses the answer beyond), got {value!r}"
                )
            object.__setattr__(self, name, float(value))
        allowed = {
            "clamped": (),
            "free": (),
            "pivot": ("rotational_drag", "rotational_stiffness"),
            "head": ("translational_drag", "rotational_drag"),
        }[self.kind]
        for name in ("translational_drag", "rotational_drag", "rotational_stiffness"):
            if name not in allowed and getattr(self, name) != 0:
                raise ValueError(
                    f"a {self.kind} base has no {name} (got {getattr(self, name)!r}); "
                    f"it takes {', '.join(allowed) or 'no constants'}"
                )
        if self.kind == "head":
            for name in allowed:
                if getattr(self, name) <= 0:
                    raise ValueError(
                        f"a head base needs its {name} > 0 (got {getattr(self, name)!r}): "
                        "give both drags or use Base.head_from_ellipsoid"
                    )

    @property
    def dofs(self) -> tuple[int, ...]:
        """Node 0's kept dofs per filament and direction (0: u(0), 1: u'(0))."""
        return BASE_DOFS[self.kind]

    @classmethod
    def head_from_ellipsoid(
        cls,
        semi_major_um: float | int,
        semi_minor_um: float | int,
        viscosity_pa_s: float | int,
        units,
        compliance: bool = False,
    ) -> "Base":
        """A ``head`` base whose drags are a prolate spheroid's (semi-axes in um, the
        long one along the flagellum) moving sideways and turning about a transverse
        axis in a fluid of viscosity ``viscosity_pa_s`` (1 Pa s = 1 pN s/um^2), made
        dimensionless with ``units`` (:class:`axojax.Units`). See
        :func:`spheroid_drags` for the formulas."""
        zeta_t, zeta_r = spheroid_drags(semi_major_um, semi_minor_um, viscosity_pa_s)
        return cls(
            "head",
            compliance=compliance,
            translational_drag=float(units.head_translational_drag(zeta_t)),
            rotational_drag=float(units.head_rotational_drag(zeta_r)),
        )


def spheroid_drags(
    semi_major_um: float | int, semi_minor_um: float | int, viscosity_pa_s: float | int
) -> tuple[float, float]:
    """Stokes drags of a prolate spheroid (semi-axes a >= b, in um) translating
    perpendicular to its axis and rotating about a perpendicular axis (Kim & Karrila,
    *Microhydrodynamics*, 1991, table 3.4; Happel & Brenner): with e = sqrt(1 - b^2/a^2)
    and L_e = ln((1 + e) / (1 - e)),

        zeta_t = 6 pi mu a (16/3) e^3 / (2 e + (3 e^2 - 1) L_e)            (pN s/um)
        zeta_r = 8 pi mu a^3 (4/3) e^3 (2 - e^2) / (-2 e + (1 + e^2) L_e)   (pN um s)

    which tend to the sphere's 6 pi mu a and 8 pi mu a^3 as b -> a (below e = 0.01, where
    the formulas cancel digits, their series 1 - 3 e^2 / 10 and 1 - 9 e^2 / 10, exact to
    O(e^4))."""
    for name, value in (
        ("semi_major_um", semi_major_um),
        ("semi_minor_um", semi_minor_um),
        ("viscosity_pa_s", viscosity_pa_s),
    ):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"head {name} must be a number, got {value!r}")
        if not math.isfinite(value) or value <= 0:
            raise ValueError(f"head {name} must be finite and > 0, got {value!r}")
    a, b, mu = float(semi_major_um), float(semi_minor_um), float(viscosity_pa_s)
    if a / b > MAX_ASPECT:
        raise ValueError(
            f"head semi_major_um / semi_minor_um must be at most {MAX_ASPECT:g} (a body, not a "
            f"needle: the drag formulas lose their digits beyond), got {a:g} / {b:g}"
        )
    if b > a:
        raise ValueError(
            f"head semi_minor_um ({b:g}) must not exceed semi_major_um ({a:g}): a prolate spheroid"
        )
    e = math.sqrt(max(1.0 - (b / a) ** 2, 0.0))
    if e < 1e-2:
        y_a = 1.0 - 0.3 * e**2
        y_c = 1.0 - 0.9 * e**2
    else:
        le = math.log((1 + e) / (1 - e))
        y_a = (16.0 / 3.0) * e**3 / (2 * e + (3 * e**2 - 1) * le)
        y_c = (4.0 / 3.0) * e**3 * (2 - e**2) / (-2 * e + (1 + e**2) * le)
    return 6 * math.pi * mu * a * y_a, 8 * math.pi * mu * a**3 * y_c


def as_base(base: Any) -> Base:
    """A :class:`Base` from a Base or a kind's name (one-line ``ValueError`` otherwise)."""
    if isinstance(base, Base):
        return base
    if isinstance(base, str):
        return Base(base)
    raise ValueError(f"base must be a Base or one of {', '.join(BASE_KINDS)}, got {base!r}")
