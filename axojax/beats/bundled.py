"""Where the bundled measured beats lie (package data under ``axojax/data/``) and how a
name becomes a file: :func:`resolve` lets every reader take a bundled data set's name
wherever it takes a path. :mod:`axojax.datasets` is the user-facing list of them;
``axojax/data/README.md`` gives each one's source, licence, citation, units and extraction
in full, :data:`DATASETS` the same in brief (``axojax data --list``)."""

from __future__ import annotations

import dataclasses
import pathlib

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
    """

    name: str
    file: str
    description: str
    source: str
    licence: str
    citation: str

    def to_json(self) -> dict:
        """The fields as a JSON object, with ``path`` (the file on this machine)."""
        return {**dataclasses.asdict(self), "path": str(DATA / self.file)}


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


def resolve(name_or_path) -> pathlib.Path:
    """A bundled data set's file when ``name_or_path`` names one and is not an existing
    file, else the path itself."""
    p = pathlib.Path(name_or_path)
    if str(name_or_path) in FILES and not p.exists():
        return path(str(name_or_path))
    return p
