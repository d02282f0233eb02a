"""Regulated dynein (issue 30, first step): sliding and curvature control with a clamped
base, against an independent solution of the two-filament continuum equations
(docs/model.md, regulated dynein; Sartori et al., eLife 2016).

The reference below is written here with numpy/scipy, not with axojax: with
psi_1 = sum_j A_j exp(k_j s / L), k^4 - beta_bar k^3 - chi_bar k^2 + i Sp = 0, and the
clamped-free conditions of ``i Sp psi = -psi'''' + (f)'' `` (f = chi_bar psi + beta_bar psi',
lengths in L, forces in kappa / L^2):

- psi(0) = 0 (clamped, no basal sliding);
- psi'(1) = 0 (no bending moment at the free tip: the sliding force vanishes there);
- psi''(1) - f(1) = 0 (no transverse force at the tip);
- psi'''(0) - f'(0) = 0 (u(0) = 0: the displacement equation holds at the base).

A Hopf point is a complex chi_bar (or beta_bar) at which the 4 x 4 boundary matrix is
singular for the given Sp. axojax's ``two`` preset at p = 0 is the same problem with
kappa = 2 EI, xi_n = 2 c_n, a = a0 L: Sp = omega0 (omega0 tau), chi_bar = a0^2 chi / 2,
beta_bar = a0 beta / 2 (axojax.units), so its eigenvalue nearest i omega0 must converge
to i omega0 under mesh refinement, with the reference's psi_1.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import fsolve

import axojax as ax
from axojax.eigen import Arnoldi, Dense
from axojax.fem import interpolation_matrix

A0 = 0.2 / 12


# -- independent continuum reference ----------------------------------------------------
def _roots(chi_bar: complex, beta_bar: complex, sp: float) -> np.ndarray:
    return np.roots([1, -beta_bar, -chi_bar, 0, 1j * sp])


def _boundary_matrix(chi_bar, beta_bar, sp):
    k = _roots(chi_bar, beta_bar, sp)
    e = np.exp(k)
    M = np.array(
        [
            np.ones(4, complex),
            k * e,
            (k**2 - beta_bar * k - chi_bar) * e,
            k**3 - beta_bar * k**2 - chi_bar * k,
        ]
    )
    return M, k


def _det(chi_bar, beta_bar, sp) -> complex:
    """Boundary determinant, with the columns scaled and the Vandermonde factor of the
    roots divided out (repeated roots would otherwise give spurious zeros)."""
    M, k = _boundary_matrix(chi_bar, beta_bar, sp)
    vdm = np.prod([k[j] - k[i] for i in range(4) for j in range(i + 1, 4)])
    scale = np.exp(np.maximum(k.real, 0)) * (1 + np.abs(k)) ** 3
    return np.linalg.det(M / scale) / vdm * np.prod(1 + np.abs(k)) ** 3


def _hopf(sp: float, guess: complex, *, solve_for: str, other: complex = 0.0) -> complex:
    """The complex chi_bar (``solve_for="chi"``, beta_bar = other) or beta_bar
    (``"beta"``, chi_bar = other) at which Sp is an eigen-frequency."""

    def f(xy):
        z = xy[0] + 1j * xy[1]
        d = _det(z, other, sp) if solve_for == "chi" else _det(other, z, sp)
        return [d.real, d.imag]

    xy = fsolve(f, [guess.real, guess.imag], xtol=1e-12)
    z = xy[0] + 1j * xy[1]
    d = _det(z, other, sp) if solve_for == "chi" else _det(other, z, sp)
    assert abs(d) < 1e-10, (z, d)
    return z


def _shape(chi_bar, beta_bar, sp, s):
    M, k = _boundary_matrix(chi_bar, beta_bar, sp)
    coeffs = np.linalg.svd(M)[2][-1].conj()
    return np.exp(np.outer(s, k)) @ coeffs


def _r2(model_psi, ref):
    """Sartori's R^2 with a free complex amplitude on the model's psi_1."""
    c = np.vdot(model_psi, ref) / np.vdot(model_psi, model_psi)
    return 1 - np.sum(np.abs(ref - c * model_psi) ** 2) / np.sum(np.abs(ref - ref.mean()) ** 2)


def test_reference_solves_its_equations():
    """The reference psi_1 at a Hopf point satisfies the ODE and the four boundary
    conditions (finite differences on a fine grid): the reference is checked by itself."""
    sp, chi_bar = 200.0, 10.0
    beta_bar = _hopf(sp, -3.9 + 9.6j, solve_for="beta", other=chi_bar)
    s = np.linspace(0, 1, 20001)
    h = s[1] - s[0]
    psi = _shape(chi_bar, beta_bar, sp, s)
    d = [psi]
    for _ in range(4):
        d.append(np.gradient(d[-1], h, edge_order=2))
    scale = np.max(np.abs(d[4]))
    interior = slice(50, -50)
    residual = 1j * sp * psi + d[4] - chi_bar * d[2] - beta_bar * d[3]
    assert np.max(np.abs(residual[interior])) < 1e-4 * scale
    f = chi_bar * psi + beta_bar * d[1]
    fp = chi_bar * d[1] + beta_bar * d[2]
    bcs = [psi[0], d[1][-1], d[2][-1] - f[-1], d[3][0] - fp[0]]
    assert max(abs(b) for b in bcs) < 1e-3 * scale


# -- axojax against the reference --------------------------------------------------------
def _params(chi_bar=0.0, beta_bar=0.0, sp=1.0) -> ax.Params:
    chi, beta = 2 * chi_bar / A0**2, 2 * beta_bar / A0
    return ax.Params(
        p=0.0,
        a0=A0,
        chi_re=float(np.real(chi)),
        chi_im=float(np.imag(chi)),
        beta_re=float(np.real(beta)),
        beta_im=float(np.imag(beta)),
        omega0=sp,
    )


def _nearest_mode(n_elements, params, sp):
    """axojax's eigenpair nearest i omega0 (scipy on axojax's assembled A, C) and the
    slope of its centreline at 201 points (psi_1)."""
    import scipy.linalg as sl

    model = ax.models.two(n_elements=n_elements)
    system = ax.assemble(model, params)
    w, V = sl.eig(-np.asarray(system.A), np.asarray(system.C))
    i = np.argmin(np.abs(w - 1j * sp))
    n = 2 * n_elements
    s = np.linspace(0, 1, 201)
    psi = interpolation_matrix(n_elements, s, 1) @ ((V[:n, i] + V[n:, i]) / 2)
    return w[i], psi, s


def test_sliding_control_converges_to_the_continuum_hopf_point():
    """Sliding control alone (chi complex, beta = 0) at Sp = 1000: the eigenvalue nearest
    i omega0 converges to it (second order in h^2 or better), and psi_1 matches.

    Its chi'' < 0 (the active part) enters as a negative friction a0^2 (chi''/omega0) D0,
    which at short wavelengths beats the drag: the pencil then has spurious divergent
    modes growing like N_e^2, so the *dominant* eigenvalue is not this one (see
    test_negative_sliding_friction_is_ill_posed)."""
    sp = 1000.0
    chi_bar = _hopf(sp, -20 - 25j, solve_for="chi")
    errors = []
    for n in (10, 20, 40):
        lam, psi, s = _nearest_mode(n, _params(chi_bar=chi_bar, sp=sp), sp)
        errors.append(abs(lam - 1j * sp) / sp)
    assert errors[0] > 8 * errors[1] > 64 * errors[2]
    assert errors[-1] < 1e-5
    assert _r2(psi, _shape(chi_bar, 0.0, sp, s)) > 0.999


@pytest.mark.parametrize("chi_bar,guess", [(0.0, -3.9 + 9.6j), (10.0, -2.7 + 10.6j)])
def test_curvature_control_dominant_mode_converges(chi_bar, guess):
    """Curvature control (beta complex), alone and with a passive shear stiffness chi' > 0
    (sliding + curvature), at Sp = 200: axojax's *dominant* eigenvalue converges to
    i omega0, with the reference's psi_1 (R^2 > 0.999)."""
    sp = 200.0
    beta_bar = _hopf(sp, guess, solve_for="beta", other=chi_bar)
    errors = []
    for n in (8, 16, 32):
        params = _params(chi_bar=chi_bar, beta_bar=beta_bar, sp=sp)
        model = ax.models.two(n_elements=n)
        mode = ax.dominant_mode(model, params, Dense())
        errors.append(abs(complex(mode.eigenvalue) - 1j * sp) / sp)
    assert errors[0] > 8 * errors[1] > 64 * errors[2]
    assert errors[-1] < 1e-4
    s = np.linspace(0, 1, 201)
    v = np.asarray(mode.eigenvector)
    psi = interpolation_matrix(32, s, 1) @ ((v[:64] + v[64:]) / 2)
    assert _r2(psi, _shape(chi_bar, beta_bar, sp, s)) > 0.999


def test_at_i_omega0_the_terms_are_chi_and_beta():
    """A + i omega0 C holds chi' + i chi'' and beta' + i beta'' exactly: the matrices at
    (chi, beta, omega0) equal those of a purely elastic complex chi, beta (by linearity:
    the mechanism part of A + i omega0 C is linear in chi + i chi'' and beta + i beta'')."""
    model = ax.models.two(n_elements=6)
    plain = ax.Params(p=0.0, kl=0.0, cl=0.0)
    base = ax.assemble(model, plain)
    full = ax.assemble(
        model, plain.replace(chi_re=3e4, chi_im=-2e4, beta_re=50.0, beta_im=80.0, omega0=7.0)
    )
    re = ax.assemble(model, plain.replace(chi_re=1e6))
    re_b = ax.assemble(model, plain.replace(beta_re=1e4))
    unit_chi = np.asarray(re.A - base.A) / 1e6
    unit_beta = np.asarray(re_b.A - base.A) / 1e4
    lhs = np.asarray(full.A - base.A) + 7.0j * np.asarray(full.C - base.C)
    rhs = (3e4 - 2e4j) * unit_chi + (50.0 + 80.0j) * unit_beta
    np.testing.assert_allclose(lhs, rhs, rtol=1e-10, atol=1e-10 * np.abs(rhs).max())


def test_positive_chi_is_a_passive_shear_stiffness():
    """The sign rule: chi' > 0 adds a positive semi-definite stiffness and stabilises the
    paper's flutter (seven, p = 300); chi' < 0 destabilises."""
    model = ax.models.seven(n_elements=8)
    base = ax.assemble(model, ax.Params())
    stiff = ax.assemble(model, ax.Params(chi_re=3e4))
    dA = np.asarray(stiff.A - base.A)
    np.testing.assert_allclose(dA, dA.T, atol=1e-12 * np.abs(dA).max())
    assert np.linalg.eigvalsh(dA).min() > -1e-9 * np.abs(dA).max()
    growth = [
        float(ax.dominant_mode(model, ax.Params(chi_re=c), Dense()).growth_rate)
        for c in (-3e4, 0.0, 3e4)
    ]
    assert growth[0] > growth[1] > growth[2]


def test_negative_sliding_friction_is_ill_posed():
    """Documents a limit of the friction form chi''/omega0: with chi'' < 0, C is
    indefinite and spurious divergent modes appear whose growth rate scales like N_e^2."""
    params = ax.Params(p=0.0, chi_im=-1e5, omega0=100.0)
    rates = [
        float(ax.dominant_mode(ax.models.two(n_elements=n), params, Dense()).growth_rate)
        for n in (8, 16)
    ]
    assert rates[0] > 0 and rates[1] > 3 * rates[0]


# -- defaults, solvers, gradients, bad input --------------------------------------------
def test_zero_coefficients_change_nothing():
    """All coefficients 0: A, C, b are exactly those without any mechanism (the steady
    load: the paper's numbers), whatever omega0."""
    model = ax.models.seven(n_elements=6)
    plain = ax.assemble(model, ax.Params())
    other = ax.assemble(model, ax.Params(omega0=3.0))
    for x, y in zip((plain.A, plain.C, plain.b), (other.A, other.C, other.b)):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))
    mode = ax.dominant_mode(ax.models.seven(), ax.Params())
    np.testing.assert_allclose(complex(mode.eigenvalue), 137.696 + 270.311j, atol=2e-3)


@pytest.mark.parametrize(
    "changes",
    [
        dict(chi_re=3e4),
        dict(chi_im=2e4, omega0=300.0),
        dict(beta_re=300.0, beta_im=500.0, omega0=300.0),
    ],
    ids=["chi_re", "chi_im", "beta"],
)
def test_structured_solver_agrees_with_dense(changes):
    model = ax.models.seven(n_elements=12)
    params = ax.Params(**changes)
    dense = complex(ax.dominant_mode(model, params, Dense()).eigenvalue)
    arn = complex(ax.dominant_mode(model, params, Arnoldi(batched=False)).eigenvalue)
    assert abs(arn - dense) <= 1e-8 * abs(dense)
    blocks = ax.assembly.assemble_blocks(model, params)
    perm = ax.assembly.node_major(model)
    dense_sys = ax.assemble(model, params)
    np.testing.assert_allclose(
        np.asarray(blocks.C.to_dense()), np.asarray(dense_sys.C)[np.ix_(perm, perm)], atol=1e-12
    )


@pytest.mark.parametrize("name", ["chi_re", "chi_im", "beta_re", "beta_im", "omega0"])
def test_gradients_match_finite_differences(name):
    model = ax.models.two(n_elements=6)
    base = dict(p=300.0, chi_re=2e4, chi_im=1e4, beta_re=30.0, beta_im=40.0, omega0=200.0)

    def lam(x):
        prm = ax.Params(**{**base, name: x})
        return ax.dominant_mode(model, prm, Dense()).eigenvalue

    x0 = base[name]
    g_re = jax.grad(lambda x: jnp.real(lam(x)))(x0)
    g_im = jax.grad(lambda x: jnp.imag(lam(x)))(x0)
    h = 1e-5 * abs(x0)
    fd = (complex(lam(x0 + h)) - complex(lam(x0 - h))) / (2 * h)
    np.testing.assert_allclose(complex(g_re + 1j * g_im), fd, rtol=1e-5, atol=1e-9)


@pytest.mark.parametrize(
    "changes,word",
    [
        (dict(chi_re=float("nan")), "chi_re"),
        (dict(beta_im=float("nan"), omega0=1.0), "beta_im"),
        (dict(chi_im=1.0), "omega0"),
        (dict(beta_im=1.0, omega0=-2.0), "omega0"),
    ],
)
def test_bad_coefficients_are_refused_in_one_line(changes, word):
    with pytest.raises(ValueError) as info:
        ax.dominant_mode(ax.models.two(n_elements=4), ax.Params(**changes))
    message = str(info.value)
    assert word in message and "\n" not in message


def test_units_give_sartoris_groups():
    """Physical chi (pN/um^2), beta (pN), f (Hz) to axojax's values, checked against
    Sartori's groups computed from the physical numbers (kappa = 2 EI, xi_n = 2 c_n)."""
    u = ax.Units()
    a_um = A0 * u.length_um
    kappa, xi_n, L = 2 * u.ei_pn_um2, 2 * u.cn_pn_s_um2, u.length_um
    chi_pn, beta_pn, f_hz = 19800.0, -6500.0, 68.0
    omega = 2 * np.pi * f_hz
    np.testing.assert_allclose(
        float(u.omega0_from_hz(f_hz)), omega * xi_n * L**4 / kappa, rtol=1e-12
    )
    np.testing.assert_allclose(
        A0**2 * float(u.chi_from_pn_per_um2(chi_pn)) / 2,
        chi_pn * a_um**2 * L**2 / kappa,
        rtol=1e-12,
    )
    np.testing.assert_allclose(
        A0 * float(u.beta_from_pn(beta_pn)) / 2, beta_pn * a_um * L / kappa, rtol=1e-12
    )
    np.testing.assert_allclose(float(u.chi_to_pn_per_um2(u.chi_from_pn_per_um2(5.0))), 5.0)
    np.testing.assert_allclose(float(u.beta_to_pn(u.beta_from_pn(5.0))), 5.0)
    np.testing.assert_allclose(float(u.omega0_to_hz(u.omega0_from_hz(5.0))), 5.0)


# -- command line --------------------------------------------------------------------------
@pytest.mark.parametrize(
    "extra,flag",
    [
        (["--chi", "1,2"], "--chi"),
        (["--beta", "1,2", "--mechanism", "sliding", "--chi", "1,0"], "--beta"),
        (["--mechanism", "curvature"], "--mechanism"),
        (["--omega0-hz", "3"], "--omega0-hz"),
        (["--mechanism", "sliding", "--chi", "1,2"], "--omega0-hz"),
        (["--mechanism", "sliding", "--chi", "1,0", "--omega0-hz", "-3"], "--omega0-hz"),
        (["--mechanism", "sliding", "--chi", "nan,0"], "--chi"),
        (["--mechanism", "sliding", "--chi", "1"], "--chi"),
    ],
)
def test_cli_refuses_bad_mechanism_flags_in_one_line(extra, flag, capsys):
    from axojax.cli.main import main

    assert main(["modes", "--model", "two", "--elements", "4", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and flag in err


def test_cli_mechanism_matches_the_library(capsys):
    """``modes --mechanism sliding+curvature`` with physical coefficients gives the
    eigenvalue of Params built with Units' conversions."""
    import json

    from axojax.cli.main import main

    argv = ["modes", "--model", "two", "--elements", "6", "--mechanism", "sliding+curvature"]
    argv += ["--chi", "19800,-3000", "--beta", "100,-650", "--omega0-hz", "68", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    u = ax.Units()
    params = ax.Params(
        chi_re=float(u.chi_from_pn_per_um2(19800.0)),
        chi_im=float(u.chi_from_pn_per_um2(-3000.0)),
        beta_re=float(u.beta_from_pn(100.0)),
        beta_im=float(u.beta_from_pn(-650.0)),
        omega0=float(u.omega0_from_hz(68.0)),
    )
    mode = ax.dominant_mode(ax.models.two(n_elements=6), params, Dense())
    lam = doc["dominant"]["eigenvalue"]
    np.testing.assert_allclose(lam[0] + 1j * lam[1], complex(mode.eigenvalue), rtol=1e-9)


def test_vmap_over_coefficients_and_simulation_inverse():
    """The coefficients are traced (vmap over chi', matching point-by-point solves), and the
    time integrator's C^{-1} is right when beta'' makes C non-symmetric."""
    from axojax.dynamics.integrate import mass_system

    model = ax.models.two(n_elements=5)
    chis = jnp.array([0.0, 1e4, 3e4])
    batch = ax.Params(chi_re=chis).broadcast()
    lam = jax.vmap(lambda prm: ax.dominant_mode(model, prm, Dense()).eigenvalue)(batch)
    for c, x in zip(np.asarray(chis), np.asarray(lam)):
        one = complex(ax.dominant_mode(model, ax.Params(chi_re=float(c)), Dense()).eigenvalue)
        assert abs(complex(x) - one) <= 1e-10 * abs(one)
    ms = mass_system(model, ax.Params(beta_im=400.0, omega0=50.0), 10.0)
    C = np.asarray(ms.C)
    assert np.abs(C - C.T).max() > 1e-6 * np.abs(C).max()
    np.testing.assert_allclose(np.asarray(ms.C_inv) @ C, np.eye(C.shape[0]), atol=1e-9)
