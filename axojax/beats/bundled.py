"""Where the bundled measured beats lie (package data under ``axojax/data/``) and how a
name becomes a file: :func:`resolve` lets every reader take a bundled data set's name
wherever it takes a path. :mod:`axojax.datasets` is the user-facing list of them."""

from __future__ import annotations

import pathlib

DATA = pathlib.Path(__file__).resolve().parent.parent / "data"
FILES = {"human_sperm": "human_sperm.npz"}


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
