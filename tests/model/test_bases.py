"""Base conditions and basal compliance (issue 30, item 2; docs/model.md section 8, bases)
against an independent solution of the two-filament continuum equations.

The reference is written here with numpy/scipy, not with axojax. Lengths in L, forces in
kappa / L^2, time in xi_n L^4 / kappa; with f = chi_bar (psi - psi(0) + delta)
+ beta_bar psi' (delta = Delta_b / a, the basal sliding) the first mode at lambda = i Sp
solves ``i Sp psi = -psi'''' + f''``, so psi = sum_j A_j exp(k_j x) with
k^4 - beta_bar k^3 - chi_bar k^2 + i Sp = 0. The boundary conditions follow from the
virtual work of bending, drag, the motors (-int f delta Delta, delta Delta =
a (delta psi(x) - delta psi(0)) + delta Delta_b) and the basal spring:

- tip: psi'(1) = 0, psi''(1) = f(1);
- clamped: psi(0) = 0 and psi'''(0) = f'(0) (u(0) = 0);
- free: psi''(0) = f(0) (no force at the base), psi'(0) = -int f (no moment);
- head (drags zeta_t, zeta_r on u(0), psi(0)): psi''(0) - f(0) = zeta_t (psi'''(0) - f'(0)),
  psi'(0) + int f = i Sp zeta_r psi(0);
- pivot (spring k_r, drag zeta_r): psi'''(0) = f'(0), psi'(0) + int f = (k_r + i Sp zeta_r) psi(0);
- basal compliance: chi_b_bar delta = -int f (Sartori et al.'s chi_b_bar = chi_b a^2 L / kappa),
  or delta = 0 without it.

At a complex chi_bar (or beta_bar) where the 5 x 5 boundary matrix on (A_1..A_4, delta)
is singular, Sp is an eigen-frequency. axojax's ``two`` preset at p = 0 is the same
problem with kappa = 2 EI, xi_n = 2 c_n, a = a0 L: Sp = omega0, chi_bar = a0^2 chi / 2,
beta_bar = a0 beta / 2, chi_b_bar = a0^2 (kb + i omega0 xib) / 2, and the body's
constants halved (zeta_t / 2, ...), so its eigenvalue nearest i omega0 must converge to
i omega0 under mesh refinement, with the reference's psi_1.
"""

import warnings

import numpy as np
import pytest
import scipy.linalg as sl
from scipy.optimize import fsolve

import axojax as ax
from axojax.eigen import Arnoldi, Dense
from axojax.models import Base

A0 = 0.2 / 12


# -- independent continuum reference ----------------------------------------------------
def _boundary(chi, beta, sp, base, chib):
    """5 x 5 boundary matrix on (A_1..A_4, delta) and the roots k; ``base`` is
    (kind, c1, c2) in the reference's units, ``chib`` chi_b_bar (None: no compliance)."""
    k = np.roots([1, -beta, -chi, 0, 1j * sp])
    e = np.exp(k)

    def row(a, d=0.0):
        return np.concatenate([a, [d]])

    psi0, dpsi0, ddpsi0, dddpsi0 = row(np.ones(4)), row(k), row(k**2), row(k**3)
    dpsi1, ddpsi1 = row(k * e), row(k**2 * e)
    f0 = row(beta * k, chi)
    f1 = row(chi * (e - 1) + beta * k * e, chi)
    df0 = row(chi * k + beta * k**2)
    intf = row(chi * ((e - 1) / k - 1) + beta * (e - 1), chi)
    kind, c1, c2 = base
    rows = [dpsi1, ddpsi1 - f1]
    if kind == "clamped":
        rows += [psi0, dddpsi0 - df0]
    elif kind == "pivot":
        rows += [dddpsi0 - df0, dpsi0 + intf - (c1 + 1j * sp * c2) * psi0]
    elif kind == "free":
        rows += [ddpsi0 - f0, dpsi0 + intf]
    else:  # head
        rows += [ddpsi0 - f0 - c1 * (dddpsi0 - df0), dpsi0 + intf - 1j * sp * c2 * psi0]
    rows.append(intf + row(np.zeros(4), chib) if chib is not None else row(np.zeros(4), 1.0))
    return np.array(rows), k


def _det(chi, beta, sp, base, chib) -> complex:
    """Boundary determinant with the exponential columns scaled and the Vandermonde
    factor of the roots divided out (repeated roots would give spurious zeros)."""
    M, k = _boundary(chi, beta, sp, base, chib)
    vdm = np.prod([k[j] - k[i] for i in range(4) for j in range(i + 1, 4)])
    scale = np.ones(5)
    scale[:4] = np.exp(np.maximum(k.real, 0)) * (1 + np.abs(k)) ** 3
    return np.linalg.det(M / scale) / vdm * np.prod(1 + np.abs(k)) ** 3


def _hopf(sp, guess, solve_for, other, base, chib) -> complex:
    """The complex chi_bar (``solve_for="chi"``, beta_bar = other) or beta_bar at which
    i Sp is an eigenvalue."""

    def coeffs(z):
        return (z, other) if solve_for == "chi" else (other, z)

    def f(xy):
        d = _det(*coeffs(xy[0] + 1j * xy[1]), sp, base, chib)
        return [d.real, d.imag]

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        xy = fsolve(f, [guess.real, guess.imag], xtol=1e-13)
    z = xy[0] + 1j * xy[1]
    assert abs(_det(*coeffs(z), sp, base, chib)) < 1e-10, z
    return z


def _shape(chi, beta, sp, base, chib, s):
    M, k = _boundary(chi, beta, sp, base, chib)
    coeffs = np.linalg.svd(M)[2][-1].conj()
    return np.exp(np.outer(s, k)) @ coeffs[:4], coeffs[4]


def _r2(model_psi, ref):
    """Sartori's R^2 with a free complex amplitude on the model's psi_1."""
    c = np.vdot(model_psi, ref) / np.vdot(model_psi, model_psi)
    return 1 - np.sum(np.abs(ref - c * model_psi) ** 2) / np.sum(np.abs(ref - ref.mean()) ** 2)


CHIB = 20.0 + 5.0j
"""chi_b_bar of the compliant cases (Sartori's wild type: about 42 + 2.2i nN/um, i.e.
chi_b_bar of order 10-100 for L = 11.7 um)."""


def test_reference_solves_its_equations():
    """The free-free reference with basal compliance at a Hopf point satisfies the ODE and
    its five conditions (finite differences on a fine grid): the reference checked by
    itself."""
    sp, chi = 200.0, 10.0
    beta = _hopf(sp, -2.47 + 13.18j, "beta", chi, ("free", 0, 0), CHIB)
    s = np.linspace(0, 1, 20001)
    h = s[1] - s[0]
    psi, delta = _shape(chi, beta, sp, ("free", 0, 0), CHIB, s)
    d = [psi]
    for _ in range(4):
        d.append(np.gradient(d[-1], h, edge_order=2))
    scale = np.max(np.abs(d[4]))
    residual = 1j * sp * psi + d[4] - chi * d[2] - beta * d[3]
    assert np.max(np.abs(residual[50:-50])) < 1e-4 * scale
    f = chi * (psi - psi[0] + delta) + beta * d[1]
    int_f = np.sum((f[1:] + f[:-1]) / 2) * h
    bcs = [d[1][-1], d[2][-1] - f[-1], d[2][0] - f[0], d[1][0] + int_f, CHIB * delta + int_f]
    assert max(abs(b) for b in bcs) < 1e-3 * scale
    assert abs(delta) > 1e-3 * np.max(np.abs(psi))  # the basal sliding takes part


# -- axojax against the reference --------------------------------------------------------
def _params(chi=0.0, beta=0.0, sp=1.0, chib=None) -> ax.Params:
    c, b = 2 * chi / A0**2, 2 * beta / A0
    kb = 0.0 if chib is None else 2 * chib / A0**2
    return ax.Params(
        p=0.0,
        a0=A0,
        chi_re=float(np.real(c)),
        chi_im=float(np.imag(c)),
        beta_re=float(np.real(b)),
        beta_im=float(np.imag(b)),
        omega0=sp,
        kb=float(np.real(kb)),
        xib=float(np.imag(kb)) / sp,
    )


def _base(base, chib) -> Base:
    kind, c1, c2 = base
    compliance = chib is not None
    if kind == "head":
        return Base(kind, compliance, translational_drag=2 * c1, rotational_drag=2 * c2)
    if kind == "pivot":
        return Base(kind, compliance, rotational_stiffness=2 * c1, rotational_drag=2 * c2)
    return Base(kind, compliance)


def _nearest_mode(n_elements, base, params, sp):
    """axojax's eigenpair nearest i omega0 (scipy on axojax's assembled A, C) and psi_1,
    the slope of its centreline at 201 points (read through the model's interpolation)."""
    model = ax.models.two(n_elements=n_elements, base=base)
    system = ax.assemble(model, params)
    assert system.A.shape == (model.n_unknowns,) * 2
    w, V = sl.eig(-np.asarray(system.A), np.asarray(system.C))
    i = np.argmin(np.abs(w - 1j * sp))
    s = np.linspace(0, 1, 201)
    psi = ax.waveform.shapes.centreline(model, V[:, i], s, derivative=1)[0]
    return w[i], psi, s


CASES = {
    # name: (mechanism solved for, Sp, guess, the other coefficient, base, chi_b_bar)
    "sliding-clamped-compliant": ("chi", 1000.0, -16.5 - 7.9j, 0.0, ("clamped", 0, 0), CHIB),
    "curvature-clamped-compliant": ("beta", 200.0, -3.57 + 15.72j, 10.0, ("clamped", 0, 0), CHIB),
    "sliding-free-compliant": ("chi", 1000.0, -20.79 - 19.12j, 0.0, ("free", 0, 0), CHIB),
    "curvature-free-compliant": ("beta", 200.0, -2.47 + 13.18j, 10.0, ("free", 0, 0), CHIB),
    "sliding-free": ("chi", 1000.0, -22.40 - 17.67j, 0.0, ("free", 0, 0), None),
    "sliding-head-compliant": ("chi", 1000.0, -12.21 - 9.71j, 0.0, ("head", 0.5, 0.05), CHIB),
    "curvature-pivot": ("beta", 200.0, -4.08 + 14.18j, 10.0, ("pivot", 3.0, 0.1), None),
}


@pytest.mark.parametrize("case", list(CASES))
def test_two_converges_to_the_continuum(case):
    """At the continuum's Hopf point, axojax's eigenvalue nearest i omega0 converges to it
    (like N_e^-4: each halving of h shrinks the error more than 8 times) and psi_1 matches
    the reference's (R^2 > 0.999 at the finest mesh)."""
    solve_for, sp, guess, other, base, chib = CASES[case]
    z = _hopf(sp, guess, solve_for, other, base, chib)
    chi, beta = (z, other) if solve_for == "chi" else (other, z)
    params = _params(chi, beta, sp, chib)
    errors = []
    for n in (8, 16, 32):
        lam, psi, s = _nearest_mode(n, _base(base, chib), params, sp)
        errors.append(abs(lam - 1j * sp) / sp)
    assert errors[0] > 8 * errors[1] > 64 * errors[2], errors
    assert errors[-1] < 1e-4
    ref, _ = _shape(chi, beta, sp, base, chib, s)
    assert _r2(psi, ref) > 0.999
    if base[0] != "clamped":  # the base moves: it is displaced, or (pivot) turns
        model = ax.models.two(n_elements=8, base=_base(base, chib))
        system = ax.assemble(model, params)
        w, V = sl.eig(-np.asarray(system.A), np.asarray(system.C))
        v = V[:, np.argmin(np.abs(w - 1j * sp))]
        held = ax.waveform.shapes.centreline(model, v, s, int(base[0] == "pivot"))[0]
        assert abs(held[0]) > 0.02 * np.abs(held).max()


def test_clamped_limit_of_basal_compliance():
    """A stiff basal spring (kb -> infinity) gives the clamped base's eigenvalues, with an
    error falling like 1 / kb: basal compliance is a border that vanishes in the limit."""
    params = ax.Params(p=0.0, chi_re=3e4, beta_re=200.0, beta_im=300.0, omega0=100.0)
    top = np.asarray(ax.spectrum(ax.models.two(n_elements=6), params, top=4))
    model = ax.models.two(n_elements=6, base=Base("clamped", compliance=True))
    errors = [
        np.abs(np.asarray(ax.spectrum(model, params.replace(kb=kb, xib=1.0), top=4)) - top).max()
        / np.abs(top).max()
        for kb in (1e7, 1e8, 1e9)
    ]
    assert 20 > errors[0] / errors[1] > 5 and 20 > errors[1] / errors[2] > 5
    assert errors[2] < 1e-4


# -- structure -----------------------------------------------------------------------------
def _rigid_modes(model: ax.models.Model, rotation: bool = True) -> np.ndarray:
    """Rigid translations u = 1 (and rotations u = x) of every direction, as unknown
    vectors built from node positions, not from axojax's shape functions."""
    N, F, d = model.n_elements, model.n_filaments, model.n_dirs
    xs = np.linspace(0, 1, N + 1)
    out = []
    for a in range(d):
        for kind in ("translation", "rotation") if rotation else ("translation",):
            node = np.zeros((F, d, N, 2))
            base = np.zeros((d, 2))  # node 0, shared by every filament
            if kind == "translation":
                node[:, a, :, 0], base[a, 0] = 1.0, 1.0
            else:
                node[:, a, :, 0], node[:, a, :, 1] = xs[1:], 1.0
                base[a, 1] = 1.0
            k = [j for j in (0, 1) if j in model.base.dofs]
            v = np.concatenate(
                [node.ravel(), base[..., k].ravel(), np.zeros(model.n_border - model.n_base_dofs)]
            )
            out.append(v)
    return np.array(out).T


@pytest.mark.parametrize("kind", ["free", "head"])
def test_rigid_body_motion_is_free(kind):
    """An isolated axoneme (free, or carrying a head) has the rigid translations and
    rotations as zero modes: A Z = 0 and Z^T A = 0 (internal forces neither resist rigid
    motion nor exert a net force or couple), with every regulated term on and basal
    compliance, at p = 0. The planar ``two`` has exactly these two zero eigenvalues (in 3D
    the cross-section's twist, uniform or growing along x, is free too: the model has no
    torsional stiffness)."""
    base = Base(kind, True, 1.0, 0.2) if kind == "head" else Base(kind, True)
    params = ax.Params(
        p=0.0, chi_re=2e4, chi_im=-1e4, beta_re=100.0, beta_im=50.0, omega0=30, kb=5e3, xib=2
    )
    model = ax.models.seven(n_elements=5, base=base)
    A = np.asarray(ax.assemble(model, params).A)
    Z = _rigid_modes(model)
    assert np.abs(A @ Z).max() < 1e-9 * np.abs(A).max()
    assert np.abs(Z.T @ A).max() < 1e-9 * np.abs(A).max()
    lam = np.asarray(ax.spectrum(ax.models.two(n_elements=5, base=base), params))
    assert np.sum(np.abs(lam) < 1e-6) == 2
    assert np.sort(np.abs(lam))[2] > 1.0


def test_pivot_holds_the_base_but_lets_it_turn():
    """A pivot without a spring has the rigid rotation about x = 0 as its only zero mode;
    its spring removes it."""
    model = ax.models.two(n_elements=6, base="pivot")
    params = ax.Params(p=0.0)
    lam = np.asarray(ax.spectrum(model, params))
    assert np.sum(np.abs(lam) < 1e-6 * np.abs(lam).max()) == 1
    sprung = model.with_base(Base("pivot", rotational_stiffness=5.0))
    lam = np.asarray(ax.spectrum(sprung, params))
    assert np.all(np.real(lam) < -1e-3)


@pytest.mark.parametrize(
    "base",
    [
        Base("clamped", True),
        Base("free"),
        Base("pivot", True, 0, 0.1, 2.0),
        Base("head", True, 1.0, 0.1),
    ],
    ids=["clamped-compliant", "free", "pivot-compliant", "head-compliant"],
)
def test_blocks_match_dense(base):
    """The structured form (block-tridiagonal node blocks, node-major, and the border) holds
    exactly the dense matrices' entries."""
    model = ax.models.seven(n_elements=5, base=base)
    params = ax.Params(
        chi_re=2e4, chi_im=1e4, beta_re=100.0, beta_im=50.0, omega0=30, kb=5e3, xib=2
    )
    dense = ax.assemble(model, params)
    blocks = ax.assembly.assemble_blocks(model, params)
    perm = ax.assembly.node_major(model)
    n, m = model.n_dof, model.n_border
    assert m > 0 and blocks.A_nb.shape == (n, m) and blocks.C_bb.shape == (m, m)
    for M, tri, nb, bn, bb in (
        (dense.A, blocks.A, blocks.A_nb, blocks.A_bn, blocks.A_bb),
        (dense.C, blocks.C, blocks.C_nb, blocks.C_bn, blocks.C_bb),
    ):
        M = np.asarray(M)
        tol = dict(rtol=1e-13, atol=1e-13 * np.abs(M).max())  # sums taken in another order
        np.testing.assert_allclose(np.asarray(tri.to_dense()), M[:n, :n][np.ix_(perm, perm)], **tol)
        np.testing.assert_allclose(np.asarray(nb), M[:n, n:][perm], **tol)
        np.testing.assert_allclose(np.asarray(bn), M[n:, :n][:, perm], **tol)
        np.testing.assert_allclose(np.asarray(bb), M[n:, n:], **tol)
    np.testing.assert_array_equal(
        np.asarray(blocks.b),
        np.concatenate([np.asarray(dense.b)[:n][perm], np.asarray(dense.b)[n:]]),
    )


def test_clamped_base_has_an_empty_border():
    model = ax.models.seven(n_elements=4)
    assert model.with_base("clamped") is model and model.n_border == 0
    blocks = ax.assembly.assemble_blocks(model, ax.Params())
    n = model.n_dof
    assert (
        blocks.A_nb.shape == (n, 0) and blocks.C_bn.shape == (0, n) and blocks.A_bb.shape == (0, 0)
    )
    assert ax.assemble(model, ax.Params()).A.shape == (n, n)


def test_interpolation_reads_the_base_node_and_skips_the_sliding():
    """The centreline of a free model at x = 0 is node 0's value (from the border, shared
    by both filaments); the basal sliding unknowns do not enter it."""
    model = ax.models.two(n_elements=4, base=Base("free", compliance=True))
    assert model.n_border == 3
    q = np.zeros(model.n_unknowns)
    q[model.n_dof : model.n_dof + model.n_base_dofs] = [0.3, 0.5]  # u(0), u'(0)
    q[-1] = 7.0  # basal sliding
    u = ax.waveform.shapes.centreline(model, q, np.array([0.0, 0.1]))
    slope = ax.waveform.shapes.centreline(model, q, np.array([0.0]), derivative=1)
    np.testing.assert_allclose(u[0, 0], 0.3)
    np.testing.assert_allclose(slope[0, 0], 0.5)
    # Hermite: on element 1 with node 1 at rest, u(0.1) = 0.3 H1(0.4) + 0.5 h H2(0.4).
    xi, h = 0.4, 0.25
    np.testing.assert_allclose(
        u[0, 1], 0.3 * (1 - 3 * xi**2 + 2 * xi**3) + 0.5 * h * (xi - 2 * xi**2 + xi**3)
    )


@pytest.mark.parametrize(
    "preset,base",
    [
        ("two", Base("clamped", True)),
        ("two", Base("pivot", False, 0.0, 0.1, 1.0)),
        ("two", Base("free")),
        ("two", Base("head", False, 2.0, 0.1)),
        ("four", Base("free", True)),
        ("four", "ellipsoid"),
    ],
    ids=["clamped-compliant", "pivot", "free", "head", "free-compliant-3d", "head-ellipsoid-3d"],
)
def test_each_base_gives_a_mode(preset, base):
    """Every kind (with and without compliance) builds, solves with the default solver
    (dense where the model has a border) and gives finite metrics."""
    if base == "ellipsoid":
        base = Base.head_from_ellipsoid(2.5, 1.5, 1e-3, ax.Units(), compliance=True)
    params = ax.Params(
        p=100.0, chi_re=1e4, beta_re=50.0, beta_im=80.0, omega0=100.0, kb=1e4, xib=1.0
    )
    model = ax.models.preset(preset, n_elements=3, base=base)
    mode = ax.dominant_mode(model, params)  # Auto: dense where there is a border
    assert mode.eigenvector.shape == (model.n_unknowns,)
    assert np.isfinite(complex(mode.eigenvalue)) and np.isfinite(float(mode.out_of_plane_ratio))


# -- units and the head's drag -----------------------------------------------------------
def test_units_give_sartoris_basal_group():
    """Physical k_b (pN/um), xi_b (pN s/um) and f (Hz) to axojax's kb, xib, checked against
    Sartori's chi_b_bar = chi_b a^2 L / kappa (kappa = 2 EI) computed from the physical
    numbers; chi_b = 42 + 2.2i nN/um at 68 Hz (Sartori's wild type)."""
    u = ax.Units()
    a_um, L, kappa = A0 * u.length_um, u.length_um, 2 * u.ei_pn_um2
    f_hz = 68.0
    omega = 2 * np.pi * f_hz
    kb_pn, xib_pn = 42000.0, 2200.0 / omega
    chib_bar = (kb_pn + 1j * omega * xib_pn) * a_um**2 * L / kappa
    kb, xib, omega0 = (
        float(u.kb_from_pn_per_um(kb_pn)),
        float(u.xib_from_pn_s_per_um(xib_pn)),
        float(u.omega0_from_hz(f_hz)),
    )
    np.testing.assert_allclose(A0**2 * (kb + 1j * omega0 * xib) / 2, chib_bar, rtol=1e-12)
    np.testing.assert_allclose(float(u.kb_to_pn_per_um(kb)), kb_pn)
    np.testing.assert_allclose(float(u.xib_to_pn_s_per_um(xib)), xib_pn)


def test_spheroid_drags():
    """A sphere's Stokes drags (6 pi mu a, 8 pi mu a^3), the slender-body limits
    (8 pi mu a / (ln(2a/b) + 1/2), 8 pi mu a^3 / (3 (ln(2a/b) - 1/2))), and no jump at the
    switch to the near-sphere series."""
    mu = 1e-3
    zt, zr = ax.models.spheroid_drags(2.0, 2.0, mu)
    np.testing.assert_allclose([zt, zr], [6 * np.pi * mu * 2.0, 8 * np.pi * mu * 8.0], rtol=1e-12)
    a, b = 1.0, 1e-3
    zt, zr = ax.models.spheroid_drags(a, b, mu)
    ln = np.log(2 * a / b)
    np.testing.assert_allclose(zt, 8 * np.pi * mu * a / (ln + 0.5), rtol=1e-5)
    np.testing.assert_allclose(zr, 8 * np.pi * mu * a**3 / (3 * (ln - 0.5)), rtol=1e-5)
    e_switch = 1e-2
    b_switch = np.sqrt(1 - e_switch**2)
    lo = ax.models.spheroid_drags(1.0, b_switch * (1 + 1e-9), mu)
    hi = ax.models.spheroid_drags(1.0, b_switch * (1 - 1e-9), mu)
    np.testing.assert_allclose(lo, hi, rtol=1e-8)
    base = Base.head_from_ellipsoid(2.0, 2.0, mu, ax.Units())
    np.testing.assert_allclose(base.translational_drag, 6 * np.pi * mu * 2.0 / (0.003 * 12.0))


# -- bad input -------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "make,word",
    [
        (lambda: ax.models.two(n_elements=4, base="hinged"), "hinged"),
        (lambda: ax.models.two(n_elements=4, base="head"), "translational_drag"),
        (lambda: Base("head", translational_drag=1.0), "rotational_drag"),
        (lambda: Base("head", translational_drag=-1.0, rotational_drag=1.0), "-1.0"),
        (lambda: Base("pivot", rotational_stiffness=-2.0), "rotational_stiffness"),
        (lambda: Base("free", translational_drag=1.0), "translational_drag"),
        (lambda: Base("clamped", compliance="yes"), "yes"),
        (lambda: Base.head_from_ellipsoid(1.0, 2.0, 1e-3, ax.Units()), "semi_minor_um"),
        (lambda: Base.head_from_ellipsoid(1.0, 0.5, float("nan"), ax.Units()), "viscosity_pa_s"),
        (lambda: ax.dominant_mode(ax.models.two(n_elements=4), ax.Params(kb=-1.0)), "kb"),
        (lambda: ax.dominant_mode(ax.models.two(n_elements=4), ax.Params(xib=-1.0)), "xib"),
        (
            lambda: ax.dominant_mode(
                ax.models.two(n_elements=4, base=Base("clamped", True)), ax.Params(kb=1.0)
            ),
            "xib",
        ),
    ],
)
def test_bad_bases_are_refused_in_one_line(make, word):
    with pytest.raises(ValueError) as info:
        make()
    message = str(info.value)
    assert word in message and "\n" not in message


def test_gradients_through_the_border_match_finite_differences():
    """Exact derivatives of the dominant eigenvalue (a flutter with a compliant clamped
    base, where no rigid-body mode competes) with respect to kb and xib."""
    import jax
    import jax.numpy as jnp

    model = ax.models.two(n_elements=6, base=Base("clamped", compliance=True))
    base = dict(p=300.0, chi_re=2e4, beta_re=30.0, beta_im=40.0, omega0=200.0, kb=3e4, xib=20.0)
    for name in ("kb", "xib"):

        def lam(x, name=name):
            return ax.dominant_mode(model, ax.Params(**{**base, name: x}), Dense()).eigenvalue

        x0 = base[name]
        g = complex(
            jax.grad(lambda x: jnp.real(lam(x)))(x0) + 1j * jax.grad(lambda x: jnp.imag(lam(x)))(x0)
        )
        h = 1e-5 * x0
        fd = (complex(lam(x0 + h)) - complex(lam(x0 - h))) / (2 * h)
        assert abs(fd) > 0  # the basal sliding takes part in this mode
        np.testing.assert_allclose(g, fd, rtol=1e-5, atol=1e-9)


@pytest.mark.parametrize("kind", ["free", Base("head", False, 1.0, 0.2), "pivot"])
def test_held_only_paths_refuse_a_base_that_moves_rigidly(kind):
    model = ax.models.two(n_elements=4, base=kind)
    with pytest.raises(ValueError) as info:
        model.require_held("limit_cycle")
    message = str(info.value)
    assert message.startswith("limit_cycle needs a base that holds the axoneme")
    assert "\n" not in message


@pytest.mark.parametrize(
    "kind",
    ["clamped", Base("clamped", compliance=True), Base("pivot", rotational_stiffness=2.0)],
    ids=["clamped", "compliant", "pivot-spring"],
)
def test_bases_that_hold_the_axoneme_pass(kind):
    ax.models.two(n_elements=4, base=kind).require_held("limit_cycle")


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("solver", [Dense(), Arnoldi()], ids=["dense", "arnoldi"])
@pytest.mark.parametrize(
    "preset,base,p",
    [
        ("seven", "free", 100.0),
        ("two", Base("head", True, 1.0, 0.2), 30.0),
        ("two", "pivot", 100.0),
    ],
    ids=["seven-free", "two-head", "two-pivot"],
)
def test_dominant_mode_skips_rigid_body_motion(preset, base, p, solver):
    """The dominant mode of a base that lets the axoneme move rigidly is its rightmost
    *deforming* mode: the rightmost eigenvalue of the full pencil (every eigenvalue, by
    the dense ``ax.spectrum``) that is not one of its rigid-body zeros, with an
    eigenvector of the full pencil; exact derivatives. Both solvers: the dense one
    deflates the rigid modes on the whole pencil, the structured one through a border
    (certified, no dense fallback)."""
    import jax
    import jax.numpy as jnp

    model = ax.models.preset(preset, n_elements=5, base=base)
    params = ax.Params(p=p, chi_re=1e4, kb=1e3, xib=1.0)
    n_rigid = model.rigid_modes().shape[1]
    lam = np.asarray(ax.spectrum(model, params))
    assert np.sum(np.abs(lam) < 1e-6) == n_rigid > 0
    deforming = lam[np.abs(lam) >= 1e-6]
    mode = ax.dominant_mode(model, params, solver)
    assert bool(mode.certified)
    expected = deforming[0] if deforming[0].imag >= 0 else np.conj(deforming[0])
    assert abs(complex(mode.eigenvalue) - expected) < 1e-8 * abs(expected)
    system = ax.assemble(model, params)
    v = np.asarray(mode.eigenvector)
    residual = (np.asarray(system.A) + complex(mode.eigenvalue) * np.asarray(system.C)) @ v
    assert np.linalg.norm(residual) < 1e-8 * np.abs(np.asarray(system.A)).max()

    def growth(x):
        return jnp.real(ax.dominant_mode(model, params.replace(p=x), solver).eigenvalue)

    h = 1e-4 * p
    fd = (float(growth(p + h)) - float(growth(p - h))) / (2 * h)
    np.testing.assert_allclose(float(jax.grad(growth)(p)), fd, rtol=1e-5)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "solver",
    [Arnoldi(batched=True), Arnoldi(krylov_dims=(2,))],
    ids=["batched", "fallback"],
)
def test_structured_deflation_paths_agree_with_dense(solver):
    """The structured solver's other paths on a head base (rigid modes deflated through a
    border): the batched one (vmapped over points) and the dense fallback of an
    uncertified point (a Krylov space too small to certify: it eliminates the deflation
    unknowns, ``deflation.dense_eigenpair``) give the dense solver's eigenvalues, and the
    fallback is flagged as uncertified."""
    import jax
    import jax.numpy as jnp

    from axojax.eigen.mode import dominant_mode_impl

    model = ax.models.two(n_elements=4, base=Base("head", True, 1.0, 0.2))
    ps = jnp.array([30.0, 100.0])

    def eig(s):
        return jax.vmap(
            lambda p: dominant_mode_impl(model, ax.Params(p=p, chi_re=1e4, kb=1e3, xib=1.0), s)
        )(ps)

    dense, structured = eig(Dense()), eig(solver)
    np.testing.assert_allclose(
        np.asarray(structured.eigenvalue), np.asarray(dense.eigenvalue), rtol=1e-8
    )
    expect_certified = solver.krylov_dims != (2,)
    assert np.all(np.asarray(structured.certified) == expect_certified)
