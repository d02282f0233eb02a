"""Bundled measured beats (package data under ``axojax/data/``; README.md there gives
source, licence, citation, units and extraction).

- :func:`human_sperm`: a free-swimming human sperm's flagellum in 3D, head-fixed frame,
  272 frames at 90 frames/s (Ren et al., repository ``polymaths-lab/3d-sperm-counter-vortices``,
  CC0 1.0).

A bundled data set's name is accepted wherever a beat file is (``read_beat("human_sperm")``,
``axojax data human_sperm``, ``axojax fit --data human_sperm``). :func:`names` lists them,
:func:`info` gives one's source and licence (``axojax data --list`` prints both).
"""

from __future__ import annotations

from ..beats import read_beat
from ..beats.bundled import DATA, DATASETS, FILES, Dataset, path, resolve


def human_sperm(**kwargs):
    """The bundled human sperm beat, reduced: a :class:`~axojax.beats.BeatData`.

    Data: smoothed 3D centrelines (100 points, base to tip, um) of one free-swimming human
    sperm in the head-fixed frame (the head's translation and rotation removed), 272 frames
    at 90 frames/s (3.0 s, about 31 beats); the authors' head-frame beat frequency
    (``published_frequency_hz``) is 10.257 Hz. The beat is strongly non-planar (s3/s2 of
    the point cloud ~0.7), so both transverse components are reduced about the beat frame
    (:mod:`axojax.beats.reduction`; ``modes`` in-plane, ``out_of_plane``; each one's
    wavelength in ``components``; both as one shape target: ``joint_shape_target()``).
    The raw arrays are in :func:`path` ``("human_sperm")``: ``x_um``, ``y_um``, ``z_um``
    (frames, points), ``frame_rate_hz``, ``published_frequency_hz``.

    Args:
        **kwargs: passed to :func:`axojax.beats.read_beat` (e.g. ``length_um``).
    """
    return read_beat(path("human_sperm"), **kwargs)


def names() -> tuple[str, ...]:
    """The names of the bundled data sets (each accepted wherever a beat file is)."""
    return tuple(DATASETS)


def info(name: str) -> Dataset:
    """Bundled data set ``name``: its file, description, source, licence and citation.

    Raises:
        ValueError: ``name`` is not a bundled data set (the message lists them).
    """
    if name not in DATASETS:
        raise ValueError(f"unknown data set {name!r}; bundled: {', '.join(DATASETS)}")
    return DATASETS[name]


__all__ = [
    "DATA",
    "DATASETS",
    "FILES",
    "Dataset",
    "human_sperm",
    "info",
    "names",
    "path",
    "resolve",
]
