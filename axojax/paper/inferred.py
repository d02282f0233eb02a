"""Parameters axojax infers for the paper's figures whose parameters the paper leaves
unstated, and the table rows "with inferred parameters" beside the stated ones.

``python -m axojax.paper --inferred --json`` prints :func:`inferred_json`:
``{"fig7": {"params": {...}, "elements", ...},
"fig12": {"params": {...}, "imbalance", "imbalance_kind", "cubic", "elements", ...}}``
(params keyed like the command-line flags without dashes; dimensionless). Each figure
is one :class:`Inferred` entry of :data:`INFERRED`; add a figure by adding an entry.

Figure 12 (section 3.7.1, the asymmetric beat): the paper states wavelength 17 um,
frequency 17 Hz, dynamic amplitude 0.71 rad and static curvature -0.044 rad/um for the
seven-filament model with a 5 : 1 moment imbalance, but not p, the arm spacing a0 or the
nonlinearity. axojax solves the inverse problem on the limit cycle itself
(:func:`axojax.limit_cycle`, differentiable by the implicit function theorem; measures of
:mod:`axojax.orbits.measures`): Levenberg-Marquardt (optimistix) on the four relative
errors over log p, log a0, log cubic, log c_l, log k_l (k_s = 1e6 fixed), each orbit
warm-started from the last (``notebooks/gallery_fig12_asymmetric_beat.ipynb``). The sign
of the curvature: group 0 (the stronger, R : 1) sits on the +y side in the seven preset,
and bends the axoneme to negative tangent angles in the y frame, the paper's sign; the
mirror image (``rotation_deg=180``) has +0.044.

The set was fitted (2026-12-03) with the wavelength as the least-squares slope of
psi_1's unwrapped phase, Geyer et al.'s approach, which the paper names and which is
axojax's one wavelength (docs/model.md, "Mode metrics", since 2026-12-06): 16.91 um at
this set (its exact form at the mesh's Gauss points), with the other three numbers within
0.3 % of the paper's. (From 2026-12-03 to 2026-12-06 axojax printed the |psi_1|^2-weighted mean phase
gradient instead, about 50 um for this orbit; that measure is retired.)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from typing import Any

from ..models import preset
from ..params import Params
from ..units import Units
from .beat import DIGITS
from .claims import Claim, Row
from .inferred_fig7 import FITTED as FIG7_FITTED
from .inferred_fig7 import INFERRED_FIG7


@dataclasses.dataclass(frozen=True)
class Inferred:
    """One figure's inferred parameter set.

    Attributes:
        model: axojax preset.
        params: dimensionless parameters (``axojax.Params`` fields, i.e. the command-line
            flags without dashes), except ``imbalance``.
        elements: elements per filament.
        imbalance: force ratio R of the imbalance (None: balanced).
        imbalance_kind: how R is read (``"moment"`` or ``"force"``).
        cubic: link stiffening kappa (1/L^2) of the nonlinear beat (None: linear).
        harmonics: harmonics of the limit cycle it was inferred with.
        how: what was fitted to what.
    """

    model: str
    params: Mapping[str, float]
    elements: int = 10
    imbalance: float | None = None
    imbalance_kind: str | None = None
    cubic: float | None = None
    harmonics: int | None = None
    how: str = ""

    def as_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "model": self.model,
            "params": dict(self.params),
            "elements": self.elements,
        }
        if self.imbalance is not None:
            out.update(imbalance=self.imbalance, imbalance_kind=self.imbalance_kind)
        if self.cubic is not None:
            out["cubic"] = self.cubic
        if self.harmonics is not None:
            out["harmonics"] = self.harmonics
        out["how"] = self.how
        return out

    def build(self, rotation_deg: float = 0.0):
        """(model, params) of this set."""
        model = preset(
            self.model,
            n_elements=self.elements,
            rotation_deg=rotation_deg,
            imbalance_kind=self.imbalance_kind or "moment",
        )
        params = Params().replace(**self.params)
        if self.imbalance is not None:
            params = params.replace(imbalance=self.imbalance)
        return model, params


FIG12_TARGETS = {
    "wavelength_um": 17.0,
    "frequency_hz": 17.0,
    "dynamic_amplitude_rad": 0.71,
    "static_curvature_rad_per_um": -0.044,
}
"""Figure 12b's beat (paper, section 3.7.1)."""

INFERRED: dict[str, Inferred] = {
    "fig7": Inferred(
        model=INFERRED_FIG7["model"],
        params=dict(INFERRED_FIG7["params"]),
        elements=INFERRED_FIG7["elements"],
        how="one global fit over fig. 7d-h (p = 300, 150, 200, 400, 800 -> 51, 17, 22, 66, 245 Hz, 2 % sigma): "
        "Levenberg-Marquardt over log ks, log kl, log cl, gamma from 16 starts "
        "(notebooks/gallery_fig07_global_fit.ipynb, "
        f"{FIG7_FITTED}); kl is bounded only from above (see the notebook's profile)",
    ),
    "fig12": Inferred(
        model="seven",
        params={
            "p": 307.72683875820366,
            "ks": 1e6,
            "kl": 1866.4863981078927,
            "cl": 1.5620572931203558,
            "a0": 0.021091102991552795,
        },
        elements=10,
        imbalance=5.0,
        imbalance_kind="moment",
        cubic=0.6555247787179226,
        harmonics=6,
        how="limit cycle (6 harmonics) fitted to fig. 12b's wavelength (17 um: the least-squares slope of psi_1's "
        "unwrapped phase, Geyer et al.'s approach and axojax's one wavelength), frequency (17 Hz), dynamic "
        "amplitude (0.71 rad) and static curvature (-0.044 rad/um): Levenberg-Marquardt (optimistix) on the four "
        "relative errors over log p, a0, cubic, cl, kl (ks fixed at 1e6), each orbit warm-started from the last "
        "(notebooks/gallery_fig12_asymmetric_beat.ipynb, 2026-12-03)",
    ),
}
"""The inferred sets, keyed by figure (``"fig7"``: :mod:`.inferred_fig7`; ``"fig12"``;
another figure adds its own key)."""


def inferred_json() -> dict[str, dict[str, Any]]:
    """The ``python -m axojax.paper --inferred --json`` document."""
    return {k: v.as_json() for k, v in INFERRED.items()}


def fig12_measures(units: Units = Units(), rotation_deg: float = 0.0):
    """:class:`axojax.orbits.CycleMeasures` of the limit cycle at the inferred fig. 12
    parameters (seconds), and the cycle."""
    from ..orbits import HarmonicBalance, cycle_measures, limit_cycle

    inf = INFERRED["fig12"]
    model, params = inf.build(rotation_deg)
    cyc = limit_cycle(
        model, params, inf.cubic, solver=HarmonicBalance(harmonics=inf.harmonics or 10, floquet=4)
    )
    return cycle_measures(cyc, None, units), cyc


def _fig7_rows(claims: Sequence[Claim], units: Units) -> list[Row]:
    """Fig. 7d-h with the inferred set: the dominant mode's frequency at each panel's p."""
    from ..eigen import dominant_mode

    inf = INFERRED["fig7"]
    model = preset(inf.model, n_elements=inf.elements)
    context = (
        "inferred: "
        + ", ".join(f"{k} = {v:.4g}" for k, v in inf.params.items())
        + f", N_e = {inf.elements} (one set for all five panels)"
    )
    rows = []
    for c in claims:
        mode = dominant_mode(model, Params(**c.params))
        value = float(mode.frequency_hz(units)) if int(mode.classification) == 1 else None
        rows.append(
            Row(c, value, f"{value:.2f} Hz" if value is not None else "no flutter", None, context)
        )
    return rows


def inferred_rows(claims: Sequence[Claim], units: Units = Units(), measured=None) -> list[Row]:
    """Rows for the ``kind == "inferred"`` claims (figs. 7d-h and 12 with inferred
    parameters); ``measured``: the result of :func:`fig12_measures` when already computed."""
    claims = [c for c in claims if c.kind == "inferred"]
    rows = _fig7_rows([c for c in claims if c.group == "fig. 7"], units)
    claims = [c for c in claims if c.group == "fig. 12"]
    if not claims:
        return rows
    m, cyc = measured if measured is not None else fig12_measures(units)
    inf = INFERRED["fig12"]
    pr = inf.params
    context = (
        f"inferred: p = {pr['p']:.1f}, a0 = {pr['a0'] * units.length_um:.3f} um, cubic {inf.cubic:.3g}, "
        f"cl = {pr['cl']:.3g}, kl = {pr['kl']:.4g}, ks = {pr['ks']:.0e}, {inf.imbalance:g}:1 "
        f"{inf.imbalance_kind} reading, "
        f"N_e = {inf.elements}; limit cycle {'stable' if bool(cyc.stable) else 'unstable'}, out-of-plane "
        f"{float(m.out_of_plane):.3f} (minor/major axis of the tip trace)"
    )
    for c in claims:
        value = float(getattr(m, c.quantity))
        digits = DIGITS[c.quantity]
        note = context
        rows.append(
            Row(
                c,
                value if math.isfinite(value) else None,
                f"{value:.{digits}f} {c.unit}",
                None,
                note,
            )
        )
    return rows
