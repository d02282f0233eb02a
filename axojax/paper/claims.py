"""The numbers the paper states that axojax can compute, and the rows comparing them.

Woodhams, Shen & Bayly, J. R. Soc. Interface 19:20220264 (2022). Each :class:`Claim` is
one stated number (or range, or bound) with where the paper states it, the model and
parameters it belongs to, and what the paper leaves unstated. This module is data only:
:mod:`axojax.paper.modes`, :mod:`axojax.paper.survey` and :mod:`axojax.paper.beat`
compute axojax's answer to each claim as a :class:`Row`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Literal, Mapping

from .inferred_fig7 import INFERRED_FIG7

Kind = Literal["mode", "survey", "beat", "inferred"]
Bound = Literal["value", "range", "below"]

GROUPS = {
    "fig. 7": "Figure 7: the dominant mode at the stated parameters",
    "fig. 11": "Figure 11 and section 3.5: wavelength, velocity and direction over a map",
    "fig. 12": "Figure 12 and sections 3.6-3.7: planarity and the asymmetric beat",
}
"""Claim groups, in table order, with their headings (one gallery notebook per group)."""

UNITS = {
    "frequency_hz": "Hz",
    "wavelength_um": "um",
    "velocity_um_per_s": "um/s",
    "out_of_plane_ratio": "",
    "anterograde_fraction": "",
    "dynamic_amplitude_rad": "rad",
    "static_curvature_rad_per_um": "rad/um",
}
"""The quantities a claim can be about, with their units."""

FIG7 = {"ks": 1e6, "kl": 1e3, "cl": 1 / 200}
"""Multi-filament parameters of figure 7 (caption): k_s = 1e6, k_l = 1e3, c_l = 1/200."""


@dataclasses.dataclass(frozen=True)
class Claim:
    """One number the paper states.

    Attributes:
        key: short identifier, e.g. ``"7b"``.
        group: a key of :data:`GROUPS`.
        source: where the paper states it, e.g. ``"fig. 7b"``.
        label: what it is about, e.g. ``"two filaments, p = 300"``.
        model: axojax preset.
        params: dimensionless parameters (``axojax.Params`` fields) the paper states.
        quantity: a key of :data:`UNITS`.
        paper: the stated value, or (low, high) for ``bound="range"``, or the upper bound
            for ``bound="below"``.
        kind: ``"mode"`` (dominant eigenmode at one point), ``"survey"`` (over a map of
            points), ``"beat"`` (time-domain simulation), ``"inferred"`` (the limit cycle at
            the parameters axojax infers for the figure, :mod:`axojax.paper.inferred`).
        bound: ``"value"``, ``"range"`` or ``"below"``.
        unstated: what the paper leaves unstated, and the choice axojax makes for it.
    """

    key: str
    group: str
    source: str
    label: str
    model: str
    params: Mapping[str, float]
    quantity: str
    paper: float | tuple[float, float]
    kind: Kind = "mode"
    bound: Bound = "value"
    unstated: str = ""

    @property
    def unit(self) -> str:
        return UNITS[self.quantity]


_KS_UNSTATED = "k_s not stated (asterisks of fig. 8d)"
_MAP_UNSTATED = "the map's grid is not stated"
_BEAT_UNSTATED = "p, dynein arm spacing and nonlinearity not stated"
_INFERRED = "with inferred parameters"

CLAIMS: tuple[Claim, ...] = (
    Claim(
        "7a",
        "fig. 7",
        "fig. 7a",
        "one filament, p = 300",
        "single",
        {"p": 300.0},
        "frequency_hz",
        347.0,
    ),
    Claim(
        "7b",
        "fig. 7",
        "fig. 7b",
        "two filaments, p = 300",
        "two",
        {"p": 300.0, **FIG7},
        "frequency_hz",
        83.0,
    ),
    Claim(
        "7c",
        "fig. 7",
        "fig. 7c",
        "four filaments, p = 300",
        "four",
        {"p": 300.0, **FIG7},
        "frequency_hz",
        49.0,
    ),
    Claim(
        "7d",
        "fig. 7",
        "fig. 7d",
        "seven filaments, p = 300",
        "seven",
        {"p": 300.0, **FIG7},
        "frequency_hz",
        51.0,
    ),
    Claim(
        "7e",
        "fig. 7",
        "fig. 7e",
        "seven, p = 150",
        "seven",
        {"p": 150.0, **FIG7},
        "frequency_hz",
        17.0,
        unstated=_KS_UNSTATED,
    ),
    Claim(
        "7f",
        "fig. 7",
        "fig. 7f",
        "seven, p = 200",
        "seven",
        {"p": 200.0, **FIG7},
        "frequency_hz",
        22.0,
        unstated=_KS_UNSTATED,
    ),
    Claim(
        "7g",
        "fig. 7",
        "fig. 7g",
        "seven, p = 400",
        "seven",
        {"p": 400.0, **FIG7},
        "frequency_hz",
        66.0,
        unstated=_KS_UNSTATED,
    ),
    Claim(
        "7h",
        "fig. 7",
        "fig. 7h",
        "seven, p = 800",
        "seven",
        {"p": 800.0, **FIG7},
        "frequency_hz",
        245.0,
        unstated=_KS_UNSTATED,
    ),
    *(
        Claim(
            f"{k}i",
            "fig. 7",
            f"fig. {k}",
            f"seven, p = {pv:g} {_INFERRED}",
            "seven",
            {"p": pv, **INFERRED_FIG7["params"]},
            "frequency_hz",
            hz,
            "inferred",
            unstated="fitted: one set of ks, kl, cl, gamma over the five panels (axojax.paper.inferred_fig7)",
        )
        for k, pv, hz in (
            ("7d", 300.0, 51.0),
            ("7e", 150.0, 17.0),
            ("7f", 200.0, 22.0),
            ("7g", 400.0, 66.0),
            ("7h", 800.0, 245.0),
        )
    ),
    Claim(
        "11a",
        "fig. 11",
        "sec. 3.5, fig. 11a",
        "wavelength over the map",
        "seven",
        {},
        "wavelength_um",
        (6.4, 50.0),
        "survey",
        "range",
        _MAP_UNSTATED,
    ),
    Claim(
        "11b",
        "fig. 11",
        "sec. 3.5, fig. 11b",
        "velocity over the map",
        "seven",
        {},
        "velocity_um_per_s",
        (50.0, 1350.0),
        "survey",
        "range",
        _MAP_UNSTATED,
    ),
    Claim(
        "11c",
        "fig. 11",
        "sec. 3.5",
        "oscillating points that run base to tip",
        "seven",
        {},
        "anterograde_fraction",
        1.0,
        "survey",
        unstated=_MAP_UNSTATED,
    ),
    Claim(
        "12a",
        "fig. 12",
        "sec. 3.6",
        "out-of-plane ratio, seven, p = 300",
        "seven",
        {"p": 300.0, **FIG7},
        "out_of_plane_ratio",
        0.05,
        bound="below",
    ),
    Claim(
        "12b",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        "asymmetric beat (5:1): frequency",
        "seven",
        {"imbalance": 5.0},
        "frequency_hz",
        17.0,
        "beat",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12c",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        "asymmetric beat (5:1): wavelength",
        "seven",
        {"imbalance": 5.0},
        "wavelength_um",
        17.0,
        "beat",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12d",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        "asymmetric beat (5:1): dynamic amplitude",
        "seven",
        {"imbalance": 5.0},
        "dynamic_amplitude_rad",
        0.71,
        "beat",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12e",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        "asymmetric beat (5:1): static curvature",
        "seven",
        {"imbalance": 5.0},
        "static_curvature_rad_per_um",
        -0.044,
        "beat",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12f",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        f"asymmetric beat (5:1) {_INFERRED}: frequency",
        "seven",
        {"imbalance": 5.0},
        "frequency_hz",
        17.0,
        "inferred",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12g",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        f"asymmetric beat (5:1) {_INFERRED}: wavelength",
        "seven",
        {"imbalance": 5.0},
        "wavelength_um",
        17.0,
        "inferred",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12h",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        f"asymmetric beat (5:1) {_INFERRED}: dynamic amplitude",
        "seven",
        {"imbalance": 5.0},
        "dynamic_amplitude_rad",
        0.71,
        "inferred",
        unstated=_BEAT_UNSTATED,
    ),
    Claim(
        "12i",
        "fig. 12",
        "sec. 3.7.1, fig. 12b",
        f"asymmetric beat (5:1) {_INFERRED}: static curvature",
        "seven",
        {"imbalance": 5.0},
        "static_curvature_rad_per_um",
        -0.044,
        "inferred",
        unstated=_BEAT_UNSTATED,
    ),
)

ELASTICITIES = ("p", "ks", "kl", "follower")
"""What a row's elasticities differentiate by (:mod:`axojax.paper.modes`): the parameters
p, k_s, k_l, and a factor on the follower-force term alone."""

TOLERANCE = 0.05
"""Rows further than this (relative) from the paper must say why in their note."""


@dataclasses.dataclass(frozen=True)
class Row:
    """axojax's answer to one :class:`Claim`.

    Attributes:
        claim: the claim.
        value: axojax's number (or (low, high) for a range); None where the quantity does
            not exist (e.g. a frequency where the mode is stable).
        shown: the text of the axojax column (e.g. ``"50.30 Hz"`` or ``"stable"``).
        elasticity: d ln X / d ln theta of the row's quantity X, for theta in
            ``axojax.paper.modes.ELASTICITIES`` (percent change of X per 1 % of theta);
            None where not computed.
        note: why the row differs (required when :attr:`differs`), or context.
    """

    claim: Claim
    value: float | tuple[float, float] | None
    shown: str
    elasticity: Mapping[str, float] | None = None
    note: str = ""

    @property
    def difference(self) -> float | None:
        """Relative difference from the paper (largest over a range's two ends); 0 when a
        bound holds; None when there is no value."""
        c, v = self.claim, self.value
        if v is None:
            return None
        if c.bound == "below":
            return 0.0 if v < c.paper else v / c.paper - 1.0
        if c.bound == "range":
            ends = [v[k] / c.paper[k] - 1.0 for k in (0, 1)]
            return max(ends, key=abs)
        return v / c.paper - 1.0 if c.paper != 0 else math.inf

    @property
    def differs(self) -> bool:
        """True when axojax has no value or is more than :data:`TOLERANCE` from the paper."""
        d = self.difference
        return d is None or not abs(d) <= TOLERANCE
