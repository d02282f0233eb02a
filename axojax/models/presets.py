"""The preset cross-sections of MODEL.md section 4.

Positions are (y, z) = (sin theta, cos theta) on the unit circle, y the beat-plane
direction. In the 3D presets ring links that are not active pairs are stiffer by
``Params.inactive_factor`` and z-bending by ``Params.out_of_plane`` (paper, section 2.2).
"""

from __future__ import annotations

import numpy as np

from ..fem import Profiles
from .section import ActivePair, CrossSection, Link, Model, build_model


def _ring(angles_deg: list[float], central: bool) -> np.ndarray:
    th = np.deg2rad(np.asarray(angles_deg, dtype=float))
    ring = np.stack([np.sin(th), np.cos(th)], axis=1)
    return np.vstack([np.zeros((1, 2)), ring]) if central else ring


def single_section() -> CrossSection:
    return CrossSection("single", np.zeros((1, 2)), n_dirs=1, load="distributed")


def beck_section() -> CrossSection:
    return CrossSection("beck", np.zeros((1, 2)), n_dirs=1, load="tip")


def two_section() -> CrossSection:
    return CrossSection("two", np.array([[0.0, 0.0], [1.0, 0.0]]), links=(Link(0, 1, "link"),), active_pairs=(ActivePair(0, 1, 0),), n_dirs=1)


def four_section() -> CrossSection:
    ring = [Link(k, (k + 1) % 4, "link") for k in range(4)]
    spokes = [Link(0, 2, "spoke"), Link(1, 3, "spoke")]
    return CrossSection(
        "four",
        _ring([90, 0, -90, 180], central=False),
        links=tuple(ring + spokes),
        active_pairs=(ActivePair(0, 1, 0), ActivePair(2, 3, 1)),
    )


def _central_ring(name: str, angles: list[float], pairs: list[tuple[int, int, int]]) -> CrossSection:
    m = len(angles)
    spokes = [Link(0, k, "spoke") for k in range(1, m + 1)]
    ring = [Link(k, k % m + 1, "link") for k in range(1, m + 1)]
    return CrossSection(name, _ring(angles, central=True), links=tuple(spokes + ring), active_pairs=tuple(ActivePair(*p) for p in pairs))


def seven_section() -> CrossSection:
    return _central_ring("seven", [90, 30, -30, -90, -150, 150], [(1, 2, 0), (2, 3, 0), (4, 5, 1), (5, 6, 1)])


def nine_section() -> CrossSection:
    return _central_ring("nine", [90 - 40 * k for k in range(9)], [(2, 3, 0), (3, 4, 0), (7, 8, 1), (8, 9, 1)])


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
    def make(n_elements: int = 10, profiles: Profiles = Profiles()) -> Model:
        return build_model(SECTIONS[name](), n_elements, profiles)

    make.__name__ = name
    make.__doc__ = f"The ``{name}`` preset of MODEL.md section 4 with ``n_elements`` elements per filament."
    return make


single = _preset("single")
beck = _preset("beck")
two = _preset("two")
four = _preset("four")
seven = _preset("seven")
nine = _preset("nine")


def preset(name: str, n_elements: int = 10, profiles: Profiles = Profiles()) -> Model:
    """Build a preset by name; unknown names raise a one-line ``ValueError``."""
    if name not in SECTIONS:
        raise ValueError(f"unknown model {name!r}; choose one of {', '.join(PRESETS)}")
    return build_model(SECTIONS[name](), n_elements, profiles)
