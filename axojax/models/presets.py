"""The preset cross-sections of docs/model.md section 4.

Positions are (y, z) = (sin theta, cos theta) on the unit circle, theta measured from
+z towards +y, y the beat-plane direction. In the 3D presets ring links that are not
active pairs are stiffer by ``Params.inactive_factor`` and z-bending by
``Params.out_of_plane`` (paper, section 2.2).

Orientation (paper, section 2.2 and fig. 3): the two active groups sit on opposite
sides of the beat plane and the plane that divides them is the beat plane, so each
group's net dynein bending direction (the sum of its pairs' unit vectors n_a) lies
along +-y. ``rotation_deg`` turns a preset away from that placement (it is added to
every angle theta): ``seven(rotation_deg=30)`` and ``four(rotation_deg=45)`` give the
placements of axojax 0.1.0, whose active groups bent 30 and 45 degrees out of the beat
plane (the four up to a mirror image, which has the same eigenvalues).
"""

from __future__ import annotations

import numpy as np

from ..fem import Profiles
from .base import Base
from .section import DEFAULT_IMBALANCE_KIND, ActivePair, CrossSection, Link, Model, build_model


def _ring(angles_deg: list[float], central: bool, rotation_deg: float = 0.0) -> np.ndarray:
    """Unit-circle positions at ``angles_deg + rotation_deg`` (from +z towards +y),
    after a central filament at the origin if ``central``."""
    th = np.deg2rad(np.asarray(angles_deg, dtype=float) + rotation_deg)
    ring = np.stack([np.sin(th), np.cos(th)], axis=1)
    return np.vstack([np.zeros((1, 2)), ring]) if central else ring


def _planar(rotation_deg: float, name: str) -> None:
    if rotation_deg != 0.0:
        raise ValueError(
            f"the planar preset {name!r} has no cross-section to rotate (rotation_deg must be 0, got {rotation_deg:g})"
        )


def single_section(rotation_deg: float = 0.0) -> CrossSection:
    _planar(rotation_deg, "single")
    return CrossSection("single", np.zeros((1, 2)), n_dirs=1, load="distributed")


def beck_section(rotation_deg: float = 0.0) -> CrossSection:
    _planar(rotation_deg, "beck")
    return CrossSection("beck", np.zeros((1, 2)), n_dirs=1, load="tip")


def two_section(rotation_deg: float = 0.0) -> CrossSection:
    _planar(rotation_deg, "two")
    return CrossSection(
        "two",
        np.array([[0.0, 0.0], [1.0, 0.0]]),
        links=(Link(0, 1, "link"),),
        active_pairs=(ActivePair(0, 1, 0),),
        n_dirs=1,
    )


FOUR_ANGLES_DEG = (-45.0, 45.0, 135.0, -135.0)
"""The square of two two-doublet systems (paper, fig. 3c): pairs (0, 1) and (2, 3) bend
along +y and -y."""
SEVEN_ANGLES_DEG = (60.0, 0.0, -60.0, -120.0, 180.0, 120.0)
"""Doublets 1..6 around the central pair: group 0 (pairs 1-2, 2-3) on the +y side, group 1
(pairs 4-5, 5-6) on the -y side; each group's net bending direction is along -y or +y."""
NINE_ANGLES_DEG = tuple(90.0 - 40.0 * k for k in range(9))
"""Doublets 1..9; the middles of the groups (3 and 8) sit 10 degrees either side of +z and
-z, the closest a ring of nine comes to the orientation rule."""


def four_section(rotation_deg: float = 0.0) -> CrossSection:
    ring = [Link(k, (k + 1) % 4, "link") for k in range(4)]
    spokes = [Link(0, 2, "spoke"), Link(1, 3, "spoke")]
    return CrossSection(
        "four",
        _ring(list(FOUR_ANGLES_DEG), central=False, rotation_deg=rotation_deg),
        links=tuple(ring + spokes),
        active_pairs=(ActivePair(0, 1, 0), ActivePair(2, 3, 1)),
    )


def _central_ring(
    name: str, angles: tuple[float, ...], pairs: list[tuple[int, int, int]], rotation_deg: float
) -> CrossSection:
    m = len(angles)
    spokes = [Link(0, k, "spoke") for k in range(1, m + 1)]
    ring = [Link(k, k % m + 1, "link") for k in range(1, m + 1)]
    positions = _ring(list(angles), central=True, rotation_deg=rotation_deg)
    return CrossSection(
        name,
        positions,
        links=tuple(spokes + ring),
        active_pairs=tuple(ActivePair(*p) for p in pairs),
    )


def seven_section(rotation_deg: float = 0.0) -> CrossSection:
    return _central_ring(
        "seven", SEVEN_ANGLES_DEG, [(1, 2, 0), (2, 3, 0), (4, 5, 1), (5, 6, 1)], rotation_deg
    )


def nine_section(rotation_deg: float = 0.0) -> CrossSection:
    return _central_ring(
        "nine", NINE_ANGLES_DEG, [(2, 3, 0), (3, 4, 0), (7, 8, 1), (8, 9, 1)], rotation_deg
    )


SECTIONS = {
    "single": single_section,
    "beck": beck_section,
    "two": two_section,
    "four": four_section,
    "seven": seven_section,
    "nine": nine_section,
}
PRESETS = tuple(SECTIONS)


def _preset(name: str):
    def make(
        n_elements: int = 10,
        profiles: Profiles = Profiles(),
        rotation_deg: float = 0.0,
        imbalance_kind: str = DEFAULT_IMBALANCE_KIND,
        base: Base | str = "clamped",
    ) -> Model:
        return build_model(SECTIONS[name](rotation_deg), n_elements, profiles, imbalance_kind, base)

    make.__name__ = name
    make.__doc__ = (
        f"The ``{name}`` preset of docs/model.md section 4 with ``n_elements`` elements per filament;\n"
        "``rotation_deg`` turns its cross-section (degrees from +z towards +y, 3D presets only);\n"
        "``imbalance_kind`` reads ``Params.imbalance`` as a static moment (default) or as unequal forces;\n"
        "``base`` is the base condition (``axojax.models.Base`` or a kind's name; default clamped)."
    )
    return make


single = _preset("single")
beck = _preset("beck")
two = _preset("two")
four = _preset("four")
seven = _preset("seven")
nine = _preset("nine")


def preset_section(name: str, rotation_deg: float = 0.0) -> CrossSection:
    """A preset's cross-section by name (before a mesh is built on it); unknown names (or
    a rotation of a planar preset) raise a one-line ``ValueError``."""
    if name not in SECTIONS:
        raise ValueError(f"unknown model {name!r}; choose one of {', '.join(PRESETS)}")
    rotation_deg = float(rotation_deg)
    if not np.isfinite(rotation_deg):
        raise ValueError(f"rotation_deg must be finite, got {rotation_deg!r}")
    return SECTIONS[name](rotation_deg)


def preset(
    name: str,
    n_elements: int = 10,
    profiles: Profiles = Profiles(),
    rotation_deg: float = 0.0,
    imbalance_kind: str = DEFAULT_IMBALANCE_KIND,
    base: Base | str = "clamped",
) -> Model:
    """Build a preset by name; unknown names (or a rotation of a planar preset) raise a
    one-line ``ValueError``."""
    return build_model(
        preset_section(name, rotation_deg), n_elements, profiles, imbalance_kind, base
    )
