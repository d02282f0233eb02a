"""Newton's third law on unclamped bases (docs/model.md section 8, bases).

An axoneme that is not held exerts no net force or moment on itself: for every rigid
motion r the base leaves free (``Model.rigid_modes``), the linearised forces of any
deformed state q do no work, r^T A q = 0 (and the static load none, r^T b = 0), and a
rigid motion costs no force, A r = 0. Checked here from the assembled matrices (an invariant of the physics,
not a number from our code): it holds for the regulated mechanisms (p = 0) on every base
and with basal compliance; it does NOT hold for the steady load, whose follower forces
and axial prestress (the paper's model, built for a clamped base) leave a net moment on a
deformed free axoneme. The last test records that limitation, so that a change to it is
seen.
"""

import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.assembly import assemble

B = ax.models.Base
BASES = {
    "free": B("free"),
    "free+compliance": B("free", compliance=True),
    "head+compliance": B("head", translational_drag=1.0, rotational_drag=0.2, compliance=True),
    "pivot": B("pivot"),
}
REGULATED = ax.Params(
    p=0.0, chi_re=50.0, chi_im=20.0, beta_re=3.0, beta_im=-2.0, omega0=10.0, kb=5.0, xib=0.5
)


def _system(preset, base, params):
    model = getattr(ax.models, preset)(5, base=base)
    s = assemble(model, params)
    return model.rigid_modes(), np.asarray(s.A), np.asarray(s.C), np.asarray(s.b)


@pytest.mark.parametrize("preset", ["two", "seven"])
@pytest.mark.parametrize("base", list(BASES))
def test_regulated_forces_have_no_net_force_or_moment(preset, base):
    R, A, C, b = _system(preset, BASES[base], REGULATED)
    assert R.shape[1] >= 1
    scale = np.abs(A).max()
    assert np.abs(A @ R).max() < 1e-12 * scale  # a rigid motion costs no force
    assert np.abs(R.T @ A).max() < 1e-12 * scale  # no net force/moment of any deformation
    assert np.abs(b @ R).max() < 1e-12 * max(1.0, np.abs(b).max())
    # the drags do resist rigid motion (the fluid is outside the axoneme)
    assert np.diag(R.T @ C @ R).min() > 0


@pytest.mark.parametrize("preset", ["two", "seven"])
def test_knot_profiles_keep_the_balance(preset):
    params = REGULATED.replace(
        ei_knots=jnp.array([3.0, 1.0, 0.5]), drag_knots=jnp.array([2.0, 1.0])
    )
    R, A, _, _ = _system(preset, BASES["head+compliance"], params)
    assert np.abs(R.T @ A).max() < 1e-12 * np.abs(A).max()


@pytest.mark.parametrize("preset", ["two", "seven"])
def test_the_steady_load_leaves_a_net_moment_on_a_free_axoneme(preset):
    """The paper's steady load on an unclamped base: rigid motions still cost no force,
    and its net force vanishes, but its net moment does not (the rotation's row of A):
    a clamp would absorb that moment, a free or head base passes it to the whole body."""
    R, A, _, _ = _system(preset, BASES["free"], ax.Params(p=100.0))
    scale = np.abs(A).max()
    assert np.abs(A @ R).max() < 1e-12 * scale
    rotation = [j for j in range(R.shape[1]) if np.any(R[:, j] != np.round(R[:, j]))]
    translation = [j for j in range(R.shape[1]) if j not in rotation]
    assert np.abs(R[:, translation].T @ A).max() < 1e-12 * scale
    assert np.abs(R[:, rotation].T @ A).max() > 1e-6 * scale
