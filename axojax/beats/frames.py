"""The frame a beat's tangent angle is compared in (docs/model.md section 8, frames).

A recording gives psi(s, t) in the frame it was filmed in: the lab (microscope) frame of a
swimming cell or an isolated axoneme (Sartori et al. 2016 fit psi in the lab frame, less
the axoneme's steady rotation, with a free base), or a frame that moves with the head or
cell body (Riedel-Kruse et al. 2007's bull sperm, fitted with a clamped base; the bundled
human sperm is head-fixed). The model's psi_1 of a free or head base is in the lab frame
(its rigid motion included); a clamped base has psi_1(0) = 0. So a lab-frame beat is
compared with free and head bases, a head-frame beat with clamped ones, as recorded
(``frame="lab"``, the default). ``frame="basal"`` compares both relative to the basal
tangent, psi(s, t) - psi(0, t): :func:`in_basal_frame` on the data, psi_1(s) - psi_1(0) on
the model (:data:`axojax.beats.targets.FRAMES`), which puts every base on the footing of a
head-fixed recording. Never transform the data alone (its psi_1(0) would be compared with
a model's that is not 0). A whole beat (psi_0 and psi_1 against a limit cycle) is compared
alike: in the lab frame its psi_0 up to a constant (the recording's arbitrary reference
direction, :mod:`axojax.inverse.cycle_targets`), in the basal frame exactly (the basal
tangent is the reference: :func:`shape_in_basal_frame`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .data import BeatData
from .readers import fail
from .targets import ShapeTarget


def _basal_sigma(sigma: np.ndarray) -> np.ndarray:
    """The sigmas of psi(s) - psi(0): each point's and the base's in quadrature, the base's
    own kept (its residual is 0 for every model)."""
    return np.concatenate([sigma[:1], np.sqrt(sigma[1:] ** 2 + sigma[0] ** 2)])


def shape_in_basal_frame(shape: ShapeTarget) -> ShapeTarget:
    """A shape target as recorded (``frame="lab"``) relative to its basal tangent, as
    :func:`in_basal_frame` does to a beat: psi_0 and psi_1 less their values at s = 0,
    ``frame="basal"`` (so that the model is compared alike). Already basal: returned as
    it is. One-line ``ValueError`` when the shape does not start at the base."""
    if shape.frame == "basal":
        return shape
    s = np.asarray(shape.s_um, dtype=float)
    if s.size == 0 or abs(s[0]) > 1e-9 * max(abs(s[-1]), 1.0):
        raise ValueError(
            f"frame: the basal frame needs psi at the base (s = 0), the data start at {s[0]:g} um"
        )
    sigma = np.broadcast_to(np.asarray(shape.sigma, dtype=float), s.shape)
    psi0 = None if shape.psi0 is None else np.asarray(shape.psi0) - np.asarray(shape.psi0)[0]
    psi1 = np.asarray(shape.psi1) - np.asarray(shape.psi1)[0]
    return dataclasses.replace(
        shape, psi1=psi1, psi0=psi0, sigma=_basal_sigma(sigma), frame="basal"
    )


def in_basal_frame(beat: BeatData) -> BeatData:
    """``beat`` relative to its basal tangent: psi(s, t) - psi(0, t) in every frame, so
    psi_0 and psi_1 (and each cycle's psi_1, the out-of-plane component's) less their
    values at s = 0. The point at s = 0 then carries no information: its sigma becomes
    its old value (the residual there is 0 for every model). The beat must start at the
    base (s = 0: transform before :meth:`BeatData.exclude_base`); one-line error otherwise."""
    s = np.asarray(beat.s_um, dtype=float)
    if s.size == 0 or abs(s[0]) > 1e-9 * max(abs(s[-1]), 1.0):
        fail(
            beat.source,
            f"the basal frame needs psi at the base (s = 0), the data start at {s[0]:g} um",
        )

    def shift(m):
        return dataclasses.replace(m, psi0=m.psi0 - m.psi0[0], psi1=m.psi1 - m.psi1[0])

    sigma = np.asarray(beat.psi1_sigma, dtype=float)
    oop = beat.out_of_plane
    return dataclasses.replace(
        beat,
        modes=shift(beat.modes),
        psi1_sigma=_basal_sigma(sigma),
        psi_rad=None if beat.psi_rad is None else beat.psi_rad - beat.psi_rad[:, :1],
        psi1_cycles=None
        if beat.psi1_cycles is None
        else beat.psi1_cycles - beat.psi1_cycles[:, :1],
        out_of_plane=None if oop is None else (shift(oop[0]), oop[1]),
        notes=beat.notes + ("psi relative to the basal tangent (the basal frame)",),
    )
