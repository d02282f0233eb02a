"""Bundled measured beats (package data under ``axojax/data/``; README.md there gives
source, licence, citation, units and extraction).

- :func:`human_sperm`: a free-swimming human sperm's flagellum in 3D, head-fixed frame,
  272 frames at 90 frames/s (Ren et al., repository ``polymaths-lab/3d-sperm-counter-vortices``,
  CC0 1.0).

A bundled data set's name is accepted wherever a beat file is (``read_beat("human_sperm")``,
``axojax data human_sperm``, ``axojax fit --data human_sperm``).
"""

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


def human_sperm(**kwargs):
    """The bundled human sperm beat, reduced: a :class:`~axojax.fitting.BeatData`.

    Data: smoothed 3D centrelines (100 points, base to tip, um) of one free-swimming human
    sperm in the head-fixed frame (the head's translation and rotation removed), 272 frames
    at 90 frames/s (3.0 s, about 31 beats); the authors' head-frame beat frequency
    (``published_frequency_hz``) is 10.257 Hz. The beat is strongly non-planar (s3/s2 of
    the point cloud ~0.7), so both transverse components are reduced (``out_of_plane``).
    The raw arrays are in :func:`path` ``("human_sperm")``: ``x_um``, ``y_um``, ``z_um``
    (frames, points), ``frame_rate_hz``, ``published_frequency_hz``.

    Args:
        **kwargs: passed to :func:`axojax.fitting.read_beat` (e.g. ``length_um``).
    """
    from ..fitting import read_beat

    return read_beat(path("human_sperm"), **kwargs)


__all__ = ["FILES", "human_sperm", "path", "resolve"]
