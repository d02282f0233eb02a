"""Where the bundled measured beats lie (package data under ``axojax/data/``) and how a
name becomes a file: :func:`resolve` lets every reader take a bundled data set's name
wherever it takes a path. :mod:`axojax.datasets` is the user-facing list of them;
``axojax/data/README.md`` gives each one's source, licence, citation, units and extraction
in full, :data:`DATASETS` the same in brief (``axojax data --list``)."""

from __future__ import annotations

import dataclasses
import pathlib

from ..units import Flagellum

DATA = pathlib.Path(__file__).resolve().parent.parent / "data"


@dataclasses.dataclass(frozen=True)
class Dataset:
    """One bundled data set: its file under ``axojax/data/`` and where it comes from.

    Attributes:
        name: the name accepted wherever a beat file is (``read_beat(name)``).
        file: the file name under ``axojax/data/``.
        description: what the data are, in one line.
        source: where the data were taken from (a repository or publication).
        licence: the data's licence, as its source states it.
        citation: the publication to cite.
        flagellum: the organism's typical bending rigidity and drag from the literature
            (:class:`~axojax.units.Flagellum`), which fits of this beat assume unless given
            units (:func:`axojax.compare`); ``None`` when not known.
    """

    name: str
    file: str
    description: str
    source: str
    licence: str
    citation: str
    flagellum: Flagellum | None = None

    def to_json(self) -> dict:
        """The fields as a JSON object, with ``path`` (the file on this machine)."""
        out = {**dataclasses.asdict(self), "path": str(DATA / self.file)}
        out["flagellum"] = None if self.flagellum is None else self.flagellum.to_json()
        return out


HUMAN_SPERM = Flagellum(
    bending_rigidity_pn_um2=1900.0,
    normal_drag_pn_s_um2=3.2e-3,
    source=(
        "kappa 1.9e-21 N m^2: the uniform rigidity that reproduced human sperm beats in "
        "Saggiorato et al., Nat. Commun. 8:1415 (2017), fig. 4 (human flagella are stiffer "
        "near the head, roughly 7e-21 falling to 2e-21 N m^2: Gaffney et al., Annu. Rev. "
        "Fluid Mech. 43:501, 2011); xi_n: Lighthill's (1976) resistive-force coefficient "
        "4 pi mu / (ln(2q/a) + 1/2), q = 0.09 lambda, in water (mu 1 mPa s) with radius "
        "a 0.25 um and lambda 45 um"
    ),
)
"""A human sperm flagellum's typical kappa (pN um^2) and xi_n (pN s/um^2, water):
1900 and 3.2e-3 (sources in ``source``; docs/mechanisms.md)."""


DATASETS: dict[str, Dataset] = {
    d.name: d
    for d in (
        Dataset(
            name="human_sperm",
            file="human_sperm.npz",
            description=(
                "3D centrelines of a free-swimming human sperm's flagellum, head-fixed frame, "
                "100 points x 272 frames at 90 frames/s (authors' beat frequency 10.257 Hz)"
            ),
            source=(
                "https://github.com/polymaths-lab/3d-sperm-counter-vortices "
                "(folder 'Data0_Experimental Sperm/')"
            ),
            licence="CC0 1.0 Universal (public domain dedication)",
            citation=(
                "X. Ren, P. Hernandez-Herrera, F. Montoya, A. Darszon, G. Corkidi, "
                "H. Bloomfield-Gadelha, Fluid flow reconstruction around a free-swimming "
                "sperm in 3D, bioRxiv (2024), PMID 38853842"
            ),
            flagellum=HUMAN_SPERM,
        ),
    )
}
"""Every bundled data set by name."""

FILES = {name: d.file for name, d in DATASETS.items()}
"""File name under ``axojax/data/`` of every bundled data set."""


def path(name: str) -> pathlib.Path:
    """The file of bundled data set ``name`` (one of :data:`FILES`)."""
    if name not in FILES:
        raise ValueError(f"unknown data set {name!r}; bundled: {', '.join(FILES)}")
    return DATA / FILES[name]


def flagellum_of(file) -> Flagellum | None:
    """The :class:`~axojax.units.Flagellum` of the bundled data set whose file ``file``
    is, else ``None`` (a user's file: its organism is not known)."""
    try:
        f = pathlib.Path(file).resolve()
    except (OSError, RuntimeError):
        return None
    for d in DATASETS.values():
        if f == (DATA / d.file).resolve():
            return d.flagellum
    return None


def resolve(name_or_path) -> pathlib.Path:
    """A bundled data set's file when ``name_or_path`` names one and is not an existing
    file, else the path itself."""
    p = pathlib.Path(name_or_path)
    if str(name_or_path) in FILES and not p.exists():
        return path(str(name_or_path))
    return p
