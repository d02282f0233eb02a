"""Axoneme models: cross-sections, presets and model files.

``ax.models.seven(n_elements=10)`` builds a preset; ``ax.models.from_file(path)`` a
user's cross-section; ``ax.models.build_model(section)`` any :class:`CrossSection`.
"""

from ..fem import Profiles
from .base import BASE_KINDS, Base, spheroid_drags
from .io import load_section, section_from_dict
from .presets import PRESETS, beck, four, nine, preset, seven, single, two
from .section import IMBALANCE_KINDS, ActivePair, CrossSection, Link, Model, build_model
from .section_motions import section_motions


def from_file(
    path,
    n_elements: int = 10,
    profiles: Profiles = Profiles(),
    imbalance_kind: str = "moment",
    base: Base | str = "clamped",
) -> Model:
    """Build a model from a TOML/JSON cross-section file (see :mod:`axojax.models.io`)."""
    return build_model(load_section(path), n_elements, profiles, imbalance_kind, base)


__all__ = [
    "section_motions",
    "BASE_KINDS",
    "Base",
    "spheroid_drags",
    "IMBALANCE_KINDS",
    "ActivePair",
    "CrossSection",
    "Link",
    "Model",
    "Profiles",
    "PRESETS",
    "beck",
    "build_model",
    "four",
    "from_file",
    "load_section",
    "nine",
    "preset",
    "section_from_dict",
    "seven",
    "single",
    "two",
]
