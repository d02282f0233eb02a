"""The units of a model fitted to an observed beat: which EI and c_n a fit or a comparison
of a beat assumes when it is given some, none, or an organism's (``axojax fit --data``,
``axojax compare``, :func:`axojax.compare`, the whole beat's comparison: one rule)."""

from __future__ import annotations

from ..units import Organism, Units
from .data import BeatData

DEFAULT_SOURCE = (
    "axojax's default units (paper table 2, a 12 um cilium's); give the organism's "
    "(--ei, --cn) for a fit that means something"
)
"""Where the units come from, in words, when neither they nor a flagellum are known."""


def beat_units(
    beat: BeatData,
    n_filaments: int,
    *,
    ei_pn_um2: float | None = None,
    cn_pn_s_um2: float | None = None,
    organism: Organism | None = None,
) -> tuple[Units, str]:
    """The units of a model of ``n_filaments`` filaments fitted to ``beat``, at the
    beat's length, and where they come from in words.

    Each of EI and c_n (per filament): the value given; else the flagellum's share (its
    kappa and xi_n shared by the filaments, :meth:`~axojax.units.Flagellum.units`), of
    ``organism`` when given, else of the data set (:attr:`BeatData.flagellum`: a bundled
    beat's); else axojax's :class:`~axojax.Units` (paper table 2: a 12 um cilium's). The
    shape a model can reach depends on the sperm number they give (docs/mechanisms.md),
    so a user's own beat should come with its organism's units.

    The words: the flagellum's (``"the data set's flagellum: kappa ..., xi_n ..., shared
    by F filaments"``, ``"the NAME preset: ..."`` for an organism) when it gives either
    value; otherwise ``"given"`` when either was given, else :data:`DEFAULT_SOURCE`.
    Raises ``ValueError`` (:class:`~axojax.Units`'s, naming the unit) for a given value
    no unit takes.
    """
    flagellum = beat.flagellum if organism is None else organism.flagellum
    default = Units()
    ei, cn = default.ei_pn_um2, default.cn_pn_s_um2
    if flagellum is not None and (ei_pn_um2 is None or cn_pn_s_um2 is None):
        own = flagellum.units(beat.length_um, n_filaments)
        ei, cn = own.ei_pn_um2, own.cn_pn_s_um2
        name = "the data set's flagellum" if organism is None else f"the {organism.name} preset"
        source = (
            f"{name}: kappa {flagellum.bending_rigidity_pn_um2:.4g} pN um^2, "
            f"xi_n {flagellum.normal_drag_pn_s_um2:.3g} pN s/um^2, shared by {n_filaments} filaments"
        )
    elif ei_pn_um2 is None and cn_pn_s_um2 is None:
        source = DEFAULT_SOURCE
    else:
        source = "given"
    ei = ei if ei_pn_um2 is None else ei_pn_um2
    cn = cn if cn_pn_s_um2 is None else cn_pn_s_um2
    return Units(beat.length_um, ei, cn), source
