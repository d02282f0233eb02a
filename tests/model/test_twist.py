"""Twist and bending at linear order (issue 55 item 2; docs/model.md section 8, "Twist").

The section's rigid rotation in its own plane (twist) and its translations (bending),
as subspaces of the unknowns (:func:`axojax.models.section_motions`). docs/model.md section 8's
argument: the four and seven presets are symmetric under a half-turn about the axis, under
which bending is odd and twist even, so no linear operator of theirs couples the two; the
references here are that symmetry (coupling 0 to rounding), checked on the assembled
matrices, and the nine preset, which has no such symmetry, where its steady load does
couple them.
"""

import numpy as np
import pytest

import axojax as ax
from axojax.models import section_motions
from axojax.waveform.shapes import centreline

LOADS = {
    "passive": ax.Params(p=0.0),
    "steady": ax.Params(p=300.0),
    "imbalanced": ax.Params(p=300.0, imbalance=2.0),
    "static moment": ax.Params(p=0.0, m0=10.0),
}


def _coupling(model, params):
    T, B = section_motions(model)
    s = ax.assemble(model, params)
    A, C = np.asarray(s.A), np.asarray(s.C)
    return (
        np.linalg.norm(T.T @ A @ B) / np.linalg.norm(T.T @ A @ T),
        np.linalg.norm(T.T @ C @ B) / np.linalg.norm(C),
    )


@pytest.mark.parametrize("preset", ["four", "seven", "nine"])
def test_the_subspaces_are_the_sections_rotation_and_translations(preset):
    """A twist moves no centreline (the section turns about its centre); a y translation
    moves the centreline in y only, by its own amount."""
    model = getattr(ax.models, preset)(n_elements=4)
    T, B = section_motions(model)
    m = T.shape[1]
    x = np.linspace(0.1, 1.0, 5)
    assert np.abs(np.asarray(centreline(model, T.T, x))).max() < 1e-12
    moved = np.asarray(centreline(model, B[:, :m].T, x))  # (m, d, S)
    assert np.all(moved[:, 1] == 0.0) and np.abs(moved[:, 0]).max() > 0.5


@pytest.mark.parametrize("preset", ["four", "seven"])
@pytest.mark.parametrize("load", list(LOADS))
def test_half_turn_symmetric_presets_do_not_couple_twist_and_bending(preset, load):
    stiffness, damping = _coupling(getattr(ax.models, preset)(n_elements=4), LOADS[load])
    assert stiffness < 1e-12 and damping < 1e-12


def test_nine_couples_them_under_its_steady_load_only():
    """nine: no coupling passive or with a static moment (the moment enters the load b
    only), a coupling of order 1e-2 of the twist block under the steady load (the
    followers and the geometric stiffness of its asymmetric active pairs)."""
    model = ax.models.nine(n_elements=4)
    for load in ("passive", "static moment"):
        assert max(_coupling(model, LOADS[load])) < 1e-12
    stiffness, damping = _coupling(model, LOADS["steady"])
    assert stiffness > 1e-3 and damping < 1e-12


def test_a_planar_model_has_no_twist():
    with pytest.raises(ValueError, match="planar"):
        section_motions(ax.models.two(n_elements=4))
