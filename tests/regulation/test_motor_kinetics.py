"""Motor kinetics (issue 47 item 1; docs/model.md section 8): the augmented pencil of
:func:`axojax.assembly.motor_kinetics.assemble_motor` against today's friction form, every
reference from scipy's full decomposition of a dense pencil.

(a) at a Hopf point of an active-friction row (chi'' < 0 or beta'' < 0) the augmented
pencil keeps the eigenvalue i omega0 and psi_1 (1e-8); (b) its largest growth rate
converges with the mesh, where the friction form's grows without bound; (c) tau_m -> 0
tends to the friction form; tau_m = None is today's assembly, bit for bit.
"""

import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sl

import axojax as ax
from axojax.assembly.motor_kinetics import assemble_motor, mechanism_matrices, motor_coefficients
from axojax.models import Base
from tests.regulation.test_sartori import _params as sartori_params  # noqa: E402

A0 = 0.2 / 12
W0 = 1000.0
SARTORI_BASE = Base("free", compliance=True)


def _spectrum(A, C, vectors=False):
    """Finite eigenvalues (and eigenvectors) of (A + lambda C) v = 0, by scipy."""
    if vectors:
        lam, V = sl.eig(-np.asarray(A), np.asarray(C))
        keep = np.isfinite(lam)
        return lam[keep], V[:, keep]
    lam = sl.eig(-np.asarray(A), np.asarray(C), right=False)
    return lam[np.isfinite(lam)]


def _hopf(model, params, field, target):
    """params with the complex coefficient ``field`` ("chi" or "beta") set where i omega0
    is an eigenvalue of today's pencil, the solution nearest ``target``: the unit terms by
    differences of :func:`ax.assemble` (A is linear in chi', beta'), solved by scipy."""
    w0 = float(params.omega0)
    zero = params.replace(**{f"{field}_re": 0.0, f"{field}_im": 0.0})
    s0, s1 = ax.assemble(model, zero), ax.assemble(model, zero.replace(**{f"{field}_re": 1.0}))
    k0 = np.asarray(s0.A) + 1j * w0 * np.asarray(s0.C)
    g = sl.eig(k0, -(np.asarray(s1.A) - np.asarray(s0.A)), right=False)
    g = g[np.isfinite(g)]
    c = g[np.argmin(np.abs(g - target))]
    return params.replace(**{f"{field}_re": float(c.real), f"{field}_im": float(c.imag)})


def _sliding_row(n_elements=8):
    """Clamped two-filament sliding control at a Hopf point, chi'' < 0 (chi a0^2 about
    -37 - 50i, the scale of tests/eigen/test_structured_mechanisms.py's SLIDING)."""
    params = ax.Params(p=0.0, a0=A0, omega0=W0)
    return _hopf(ax.models.two(n_elements=8), params, "chi", -1.3e5 - 1.8e5j)


def _curvature_row():
    """Sartori et al.'s wild-type curvature control (beta'' = -6.5 nN, free base with basal
    compliance; tests/regulation/test_sartori.py), beta moved by 0.02 % onto the Hopf point of the
    8-element mesh."""
    params = sartori_params()
    model = ax.models.two(n_elements=8, base=SARTORI_BASE)
    return _hopf(model, params, "beta", complex(params.beta_re, params.beta_im))


def _seven_row():
    """Seven filaments (several active pairs), clamped, curvature control at a Hopf point
    with beta'' < 0 (beta about 279 - 1256i)."""
    params = ax.Params(p=0.0, omega0=W0)
    return _hopf(ax.models.seven(n_elements=4), params, "beta", 280 - 1250j)


CASES = {
    "sliding-clamped": (lambda: ax.models.two(n_elements=8), _sliding_row),
    "curvature-sartori": (lambda: ax.models.two(n_elements=8, base=SARTORI_BASE), _curvature_row),
    "curvature-seven": (lambda: ax.models.seven(n_elements=4), _seven_row),
}


def test_coefficients_give_chi_at_i_omega0_and_the_friction_form_as_tau_goes_to_zero():
    for re, im, w0, tau in [
        (3.0, -2.0, 5.0, 0.1),
        (-40.0, 7.0, 1000.0, 2e-3),
        (1.0, 0.0, 0.0, 1.0),
    ]:
        c_inf, c_1 = (complex(x) for x in motor_coefficients(re, im, w0, tau))
        assert abs(c_inf + c_1 / (1 + 1j * w0 * tau) - (re + 1j * im)) <= 1e-13 * abs(re + 1j * im)
    c_inf, c_1 = (float(x) for x in motor_coefficients(3.0, -2.0, 5.0, 1e-7))
    s = 2.0 + 7.0j  # any growth rate: c_inf + c_1 / (1 + tau s) -> chi' + chi'' s / omega0
    assert abs(c_inf + c_1 / (1 + 1e-7 * s) - (3.0 - 2.0 * s / 5.0)) < 1e-4


@pytest.mark.parametrize("case", list(CASES))
def test_none_is_todays_assembly_bit_for_bit(case):
    model_of, row = CASES[case]
    model, params = model_of(), row()
    old, new = ax.assemble(model, params), assemble_motor(model, params, None)
    for name in ("A", "C", "b"):
        assert np.array_equal(np.asarray(getattr(old, name)), np.asarray(getattr(new, name)))


@pytest.mark.parametrize("case", list(CASES))
def test_mechanism_matrices_are_the_regulated_terms(case):
    """dA/dchi' and dA/dbeta' against differences of today's assembly, and C's friction
    per unit chi'' and beta'' is the same matrix over omega0 (section 8's terms)."""
    model_of, row = CASES[case]
    model, params = model_of(), row()
    m_chi, m_beta = (np.asarray(m) for m in mechanism_matrices(model, params))
    zero = params.replace(chi_re=0.0, chi_im=0.0, beta_re=0.0, beta_im=0.0)
    s0 = ax.assemble(model, zero)
    for m, field in ((m_chi, "chi"), (m_beta, "beta")):
        s_re = ax.assemble(model, zero.replace(**{f"{field}_re": 1.0}))
        s_im = ax.assemble(model, zero.replace(**{f"{field}_im": 1.0}))
        scale = np.abs(np.asarray(s0.A)).max()
        assert np.abs(np.asarray(s_re.A) - np.asarray(s0.A) - m).max() <= 1e-14 * scale
        dC = (np.asarray(s_im.C) - np.asarray(s0.C)) * float(params.omega0)
        assert np.abs(dC - m).max() <= 1e-9 * max(np.abs(m).max(), 1e-300) + 1e-14 * scale


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("tau_w0", [0.3, 1.0, 5.0])
def test_hopf_point_keeps_its_eigenvalue_and_psi1(case, tau_w0):
    """(a) At a fitted point with active friction, the augmented pencil's eigenvalue nearest
    i omega0 is today's (both i omega0, 1e-8) and its eigenvector restricted to the
    original unknowns is today's psi_1 (1e-8, up to scale); the motor copy is q / (1 +
    tau_m lambda)."""
    model_of, row = CASES[case]
    model, params = model_of(), row()
    assert float(params.chi_im) < 0 or float(params.beta_im) < 0
    w0 = float(params.omega0)
    old = ax.assemble(model, params)
    lam0, V0 = _spectrum(old.A, old.C, vectors=True)
    i0 = np.argmin(np.abs(lam0 - 1j * w0))
    assert abs(lam0[i0] - 1j * w0) <= 1e-8 * w0  # a Hopf point of today's form
    new = assemble_motor(model, params, tau_w0 / w0)
    n = model.n_unknowns
    assert new.A.shape == (2 * n, 2 * n) and new.n == n
    lam1, V1 = _spectrum(new.A, new.C, vectors=True)
    i1 = np.argmin(np.abs(lam1 - 1j * w0))
    assert abs(lam1[i1] - lam0[i0]) <= 1e-8 * w0, (lam1[i1], lam0[i0])
    v0, v1 = V0[:, i0], V1[:, i1]
    k = np.argmax(np.abs(v0))
    psi0, psi1 = v0 / v0[k], v1[:n] / v1[k]
    assert np.abs(psi1 - psi0).max() <= 1e-8, np.abs(psi1 - psi0).max()
    y = v1[n:] / v1[k]
    assert np.abs(y - psi1 / (1 + tau_w0 / w0 * lam1[i1])).max() <= 1e-8


def test_schur_complement_is_todays_pencil_at_i_omega0():
    """Eliminating the motor copy from A' + i omega0 C' gives today's A + i omega0 C (the
    response equals chi + i chi'' there exactly), with both mechanisms at once, p != 0 and
    a base with compliance."""
    model = ax.models.seven(n_elements=4, base=Base("clamped", compliance=True))
    params = ax.Params(
        p=200.0, chi_re=-9e4, chi_im=-2e5, beta_re=300.0, beta_im=-900.0, omega0=400.0
    )
    params = params.replace(kb=50.0, xib=2.0)
    tau = 0.7 / 400.0
    lam = 400j
    new, old = assemble_motor(model, params, tau), ax.assemble(model, params)
    n = model.n_unknowns
    P = np.asarray(new.A) + lam * np.asarray(new.C)
    schur = P[:n, :n] - P[:n, n:] @ np.linalg.solve(P[n:, n:], P[n:, :n])
    ref = np.asarray(old.A) + lam * np.asarray(old.C)
    assert np.abs(schur - ref).max() <= 1e-12 * np.abs(ref).max()
    assert np.array_equal(np.asarray(new.b[:n]), np.asarray(old.b)) and not np.any(
        np.asarray(new.b[n:])
    )


def _growth(model, params, tau):
    system = ax.assemble(model, params) if tau is None else assemble_motor(model, params, tau)
    return float(_spectrum(system.A, system.C).real.max())


def test_small_tau_tends_to_the_friction_form():
    """(c) Off the Hopf point (chi' 10 % off), the eigenvalue nearest today's tends to it
    linearly in tau_m (the response's error is O(tau_m chi'' lambda^2 / omega0))."""
    model = ax.models.two(n_elements=8)
    params = _sliding_row()
    params = params.replace(chi_re=1.1 * float(params.chi_re))
    w0 = float(params.omega0)
    old = ax.assemble(model, params)
    lam0 = _spectrum(old.A, old.C)
    ref = lam0[np.argmin(np.abs(lam0 - 1j * w0))]
    assert abs(ref - 1j * w0) > 0.05 * w0  # not the Hopf point: a real test of the limit
    errors = []
    for tau_w0 in (1e-2, 1e-3, 1e-4):
        new = assemble_motor(model, params, tau_w0 / w0)
        lam = _spectrum(new.A, new.C)
        errors.append(abs(lam[np.argmin(np.abs(lam - ref))] - ref) / abs(ref))
    assert errors[1] < 1e-3 and errors[2] < 1e-4, errors
    assert 5 < errors[0] / errors[1] < 20, errors


def test_refuses_a_bad_tau_and_is_traceable():
    model, params = ax.models.two(n_elements=4), ax.Params(p=0.0, chi_im=-1.0, omega0=10.0)
    for bad in (0.0, -1.0, float("nan"), np.array([0.1, 0.2])):
        with pytest.raises(ValueError, match="tau_m"):
            assemble_motor(model, params, bad)
    with pytest.raises(ValueError, match="omega0"):
        assemble_motor(model, params.replace(omega0=0.0), 0.1)
    import jax

    grad = jax.grad(lambda t: jnp.trace(assemble_motor(model, params, t).C))(jnp.asarray(0.1))
    assert float(grad) == model.n_unknowns


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_nearest_mode_with_motor_kinetics_is_the_dense_augmented_pencils():
    """``ax.nearest_mode(..., tau_m=)``: at the Hopf point the same mode as today's (eigenvalue
    and unit eigenvector, 1e-8); off it the eigenvalue is scipy's nearest of the augmented
    pencil and its derivative in tau_m matches central differences; dense only."""
    model, params = ax.models.two(n_elements=8), _sliding_row()
    w0 = float(params.omega0)
    old = ax.nearest_mode(model, params, 1j * w0)
    new = ax.nearest_mode(model, params, 1j * w0, tau_m=1.0 / w0)
    assert abs(complex(new.eigenvalue) - complex(old.eigenvalue)) <= 1e-8 * w0
    assert np.abs(np.asarray(new.eigenvector) - np.asarray(old.eigenvector)).max() <= 1e-8
    off = params.replace(chi_re=1.1 * float(params.chi_re))
    tau = 0.5 / w0
    system = assemble_motor(model, off, tau)
    lam = _spectrum(system.A, system.C)
    ref = lam[np.argmin(np.abs(lam - 1j * w0))]
    mode = ax.nearest_mode(model, off, 1j * w0, tau_m=tau)
    assert abs(complex(mode.eigenvalue) - ref) <= 1e-9 * abs(ref)
    import jax

    def growth(t):
        return ax.eigen.nearest.nearest_mode_impl(
            model, off, 1j * w0, ax.eigen.Dense(), t
        ).growth_rate

    g = float(jax.grad(growth)(jnp.asarray(tau)))
    h = 1e-3 * tau
    fd = (float(growth(jnp.asarray(tau + h))) - float(growth(jnp.asarray(tau - h)))) / (2 * h)
    assert abs(g - fd) <= 1e-5 * abs(fd), (g, fd)
    with pytest.raises(ValueError, match="densely"):
        ax.nearest_mode(model, params, 1j * w0, solver=ax.eigen.Arnoldi(), tau_m=tau)
    with pytest.raises(ValueError, match="tau_m"):
        ax.nearest_mode(model, params, 1j * w0, tau_m=-1.0)


def _both_row():
    """Clamped two-filament sliding+curvature control at a Hopf point with both frictions
    active: beta = 150 - 400i fixed, chi (chi'' < 0) where i omega0 is an eigenvalue."""
    params = ax.Params(p=0.0, a0=A0, omega0=W0, beta_re=150.0, beta_im=-400.0)
    return _hopf(ax.models.two(n_elements=8), params, "chi", -1.3e5 - 1.8e5j)


MESH_CASES = [
    ("sliding-clamped", lambda ne: ax.models.two(n_elements=ne), _sliding_row),
    (
        "curvature-sartori",
        lambda ne: ax.models.two(n_elements=ne, base=SARTORI_BASE),
        _curvature_row,
    ),
    ("sliding+curvature-clamped", lambda ne: ax.models.two(n_elements=ne), _both_row),
]


@pytest.mark.parametrize("case", MESH_CASES, ids=lambda c: c[0])
@pytest.mark.parametrize(
    "meshes",
    [(6, 12, 24), pytest.param((10, 20, 40), marks=pytest.mark.slow)],
    ids=lambda m: "-".join(map(str, m)),
)
def test_largest_growth_rate_converges_with_the_mesh(case, meshes):
    """(b) With an active friction (sliding, curvature, both) the friction form's largest
    growth rate grows without bound with the mesh (more than doubling per refinement: the
    indefinite C meets bending k^4 against friction k^2); with motor kinetics (tau_m omega0
    = 1) it changes by less than 2 % of omega0 from mesh to mesh and nothing outgrows the
    Hopf point (max < 2 % of omega0). Issue 47's acceptance meshes are 10, 20 and 40
    elements (slow); the quick run takes 6, 12 and 24. Measured, in units of omega0 on 10,
    20, 40 elements: friction form 242, 969, 3876 (sliding), 18.8, 58.3, 184 (curvature),
    97.0, 291, 932 (both); with motor kinetics -2.0e-4, -3.4e-4, -3.5e-4; 4.9e-4, 8.3e-4,
    8.5e-4; -2.5e-4, -4.1e-4, -4.2e-4 (the Hopf point's own mesh is 8 elements)."""
    _, model_of, row = case
    params = row()
    w0 = float(params.omega0)
    assert float(params.chi_im) < 0 or float(params.beta_im) < 0
    friction = [_growth(model_of(ne), params, None) for ne in meshes]
    motor = [_growth(model_of(ne), params, 1.0 / w0) for ne in meshes]
    assert friction[0] > w0 and all(b > 2.0 * a for a, b in zip(friction, friction[1:])), friction
    assert all(abs(b - a) < 0.02 * w0 for a, b in zip(motor, motor[1:])), motor
    assert max(motor) < 0.02 * w0
