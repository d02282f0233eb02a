"""The structured eigen-solver with regulated dynein and with a border of extra unknowns
(issue 30): ``Arnoldi.nearest`` (shift-invert about i omega0, any C) against the dense
``nearest_eigenpair`` and scipy's full decomposition, on its per-point and batched
paths, with derivatives; the dominant solver where C stays symmetric positive definite;
bordered block algebra against numpy; bordered pencils (random border blocks on a real
model's pencil, and one node block more than the model's elements) against scipy."""

import types

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sl

import axojax as ax
from axojax.assembly import assemble_blocks, pencil_of
from axojax.eigen import Arnoldi, Dense
from axojax.eigen.arnoldi import structured_dominant
from axojax.eigen.arnoldi_nearest import structured_nearest
from axojax.eigen.nearest import nearest_eigenpair
from axojax.linalg import BlockTridiagonal, bordered, bordered_cholesky, bordered_lu

A0 = 0.2 / 12
# Sliding control with an active friction (chi'' < 0: C indefinite) at omega0 = 1000: the
# beat near i omega0 is not the dominant eigenvalue (tests/eigen/test_nearest.py).
SLIDING = ax.Params(p=0.0, a0=A0, chi_re=-2 * 20 / A0**2, chi_im=-2 * 25 / A0**2, omega0=1000.0)
# Curvature control with beta'' != 0 (C non-symmetric through H0 = int phi' phi''^T), on
# top of the paper's steady load.
CURVATURE = ax.Params(p=300.0, beta_re=300.0, beta_im=500.0, chi_im=-3e3, omega0=300.0)
PATHS = [Arnoldi(batched=False), Arnoldi(batched=True)]
PATH_IDS = ["per-point", "batched"]
SLOW = pytest.mark.slow  # the batched path: the same checks at several times the compilation
METRICS = ("eigenvalue", "wavelength", "growth_rate", "angular_frequency", "velocity", "beat_angle")


def _scipy_nearest(A, C, shift):
    lam = sl.eig(-np.asarray(A), np.asarray(C), right=False)
    return lam[np.argmin(np.abs(lam - shift))]


def _near_modes(model, params, shifts, solver):
    return jax.jit(
        jax.vmap(lambda prm, s: ax.eigen.nearest.nearest_mode_impl(model, prm, s, solver))
    )(params, shifts)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("arnoldi", [PATHS[0], pytest.param(PATHS[1], marks=SLOW)], ids=PATH_IDS)
def test_nearest_matches_dense_and_scipy_for_indefinite_and_nonsymmetric_c(arnoldi):
    cases = [
        (ax.models.two(n_elements=8), SLIDING, [1000j, 1050j]),
        (ax.models.seven(n_elements=6), CURVATURE, [300j, 100 + 250j]),
    ]
    for model, params, shifts in cases:
        C = np.asarray(ax.assemble(model, params).C)
        assert np.abs(C - C.T).max() > 1e-6 * np.abs(C).max() or np.linalg.eigvalsh(C).min() < 0
        batch = jax.tree.map(lambda x: jnp.stack([x, x]), params)
        shifts = jnp.asarray(shifts, complex)
        fast = _near_modes(model, batch, shifts, arnoldi)
        dense = _near_modes(model, batch, shifts, Dense())
        assert np.all(np.asarray(fast.certified)), np.asarray(fast.certified)
        for name in METRICS:
            f, d = np.asarray(getattr(fast, name)), np.asarray(getattr(dense, name))
            assert np.all(np.abs(f - d) <= 1e-8 * np.abs(d)), (name, f, d)
        system = ax.assemble(model, params)
        for lam, shift in zip(np.asarray(fast.eigenvalue), np.asarray(shifts)):
            ref = _scipy_nearest(system.A, system.C, shift)
            assert abs(lam - ref) <= 1e-8 * abs(ref), (lam, ref)


def test_nearest_certifies_exactly_with_the_shift_near_or_between_eigenvalues():
    """The per-point path's small first stages (FIRST_DIMS): a shift 0.1 % and 1 % of
    |lambda| from the eigenvalue (a fit that pins the beat) certifies and is exact; so
    is one almost midway between the two eigenvalues nearest i omega0, where the
    certificate needs both resolved (no fallback: certified by Arnoldi itself)."""
    model = ax.models.seven(n_elements=6)
    A, C = pencil_of(assemble_blocks(model, CURVATURE))
    system = ax.assemble(model, CURVATURE)
    lam = sl.eig(-np.asarray(system.A), np.asarray(system.C), right=False)
    order = np.argsort(np.abs(lam - 300j))
    l1, l2 = lam[order[0]], lam[order[1]]
    shifts = [l1 * (1 + 0.001j), l1 * (1 + 0.01j), l1 + 0.48 * (l2 - l1)]
    opts = Arnoldi(fallback=False).options
    batch = jax.tree.map(lambda x: jnp.stack([x] * len(shifts)), (A, C))
    near, _, cert = jax.jit(jax.vmap(lambda a, c, s: structured_nearest(a, c, s, opts)))(
        *batch, jnp.asarray(shifts, complex)
    )
    assert np.all(np.asarray(cert) == 1.0), np.asarray(cert)
    for got, shift in zip(np.asarray(near), shifts):
        ref = lam[np.argmin(np.abs(lam - shift))]
        assert abs(got - ref) <= 1e-8 * abs(ref), (got, ref, shift)


@pytest.mark.slow  # 20-40 s of compilation; the dense rule is tests/eigen/test_nearest.py's
def test_nearest_derivatives_match_the_dense_rule_and_finite_differences():
    model = ax.models.seven(n_elements=5)

    def metrics(z, solver):  # beta'', chi', p
        prm = CURVATURE.replace(beta_im=z[0], chi_re=z[1], p=z[2])
        mode = ax.eigen.nearest.nearest_mode_impl(model, prm, 300j, solver)
        return jnp.stack([mode.growth_rate, mode.angular_frequency, mode.wavelength])

    z = jnp.array([500.0, 2e3, 300.0])
    fast = np.asarray(jax.jit(jax.jacfwd(lambda z: metrics(z, Arnoldi())))(z))
    rev = np.asarray(jax.jit(jax.jacrev(lambda z: metrics(z, Arnoldi())))(z))
    dense = np.asarray(jax.jit(jax.jacfwd(lambda z: metrics(z, Dense())))(z))
    scale = np.abs(dense).max(axis=1, keepdims=True)
    assert np.max(np.abs(fast - dense) / scale) < 1e-7
    assert np.max(np.abs(rev - dense) / scale) < 1e-7
    h = 1e-4 * np.abs(np.asarray(z))
    f = jax.jit(lambda z: metrics(z, Dense()))
    fd = np.stack(
        [
            (np.asarray(f(z + h[i] * np.eye(3)[i])) - np.asarray(f(z - h[i] * np.eye(3)[i])))
            / (2 * h[i])
            for i in range(3)
        ],
        axis=1,
    )
    assert np.max(np.abs(fast - fd) / scale) < 1e-5


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_dominant_is_structured_and_certified_when_c_stays_positive_definite():
    """chi'' >= 0 and beta'' = 0 keep C symmetric positive definite: the dominant solver
    certifies on its own (no fallback) and agrees with the dense one; with beta'' != 0
    (C non-symmetric) it says it did not certify (the dense fallback answered)."""
    model = ax.models.seven(n_elements=8)
    spd = ax.Params(p=300.0, chi_re=2e4, chi_im=2e4, beta_re=100.0, omega0=300.0)
    mode = ax.dominant_mode(model, spd, Arnoldi(fallback=False))
    dense = ax.dominant_mode(model, spd, Dense())
    assert bool(mode.certified)
    assert abs(complex(mode.eigenvalue - dense.eigenvalue)) <= 1e-8 * abs(complex(dense.eigenvalue))
    skew = ax.dominant_mode(model, spd.replace(beta_im=50.0), Arnoldi())
    assert not bool(skew.certified)


# Strong dynamic sliding control (chi' = 5e3 pN/um^2, chi'' = 3 chi', omega0 at 30 Hz in
# dimensionless units): C stays symmetric positive definite, but chi'' crowds overdamped
# modes on the real axis left of the dominant one.
STRONG_SLIDING = dict(chi_re=1.4256e6, chi_im=4.2768e6, omega0=161.23)


def _strong_sliding_grid():
    P, K = np.meshgrid([300.0, 500.0, 700.0, 1000.0], [1e4, 1e6])
    p, ks = jnp.asarray(P.ravel()), jnp.asarray(K.ravel())
    return ax.Params(p=p, ks=ks, kl=ks / 1e3, **STRONG_SLIDING).broadcast((P.size,))


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("batched", [False, pytest.param(True, marks=SLOW)], ids=PATH_IDS)
def test_strong_dynamic_sliding_control_certifies_with_the_right_disc(monkeypatch, batched):
    """Overdamped modes crowding the real axis left of the dominant eigenvalue kept the
    pole's disc from certifying (their Ritz values converge slowly), and those points went
    dense. The right disc (which covers the pole disc's part right of Re lambda_r)
    certifies them: every point structured, each equal to scipy's rightmost eigenvalue to
    1e-8; without the right disc some point of this grid is not certified."""
    model = ax.models.seven(n_elements=10)
    params = _strong_sliding_grid()

    def certified(solver):
        run = jax.vmap(lambda q: ax.eigen.mode._dominant_mode_impl(model, q, solver))
        modes = jax.jit(run)(params)
        return np.asarray(modes.certified), np.asarray(modes.eigenvalue)

    ok, lam = certified(Arnoldi(fallback=False, batched=batched))
    assert ok.all()
    for i in range(lam.shape[0]):
        A, C = pencil_of(assemble_blocks(model, jax.tree.map(lambda x: x[i], params)))
        ref = sl.eigvals(-np.asarray(A.to_dense()), np.asarray(C.to_dense()))
        ref = ref[np.isfinite(ref)]
        rightmost = ref[np.argmax(ref.real)]
        rightmost = complex(rightmost.real, abs(rightmost.imag))
        assert abs(lam[i] - rightmost) <= 1e-8 * abs(rightmost), i
    monkeypatch.setattr(ax.eigen.arnoldi, "RIGHT_DISC_MARGINS", ())
    # another certify_factor (by 1e-12) so that the pole's disc alone is traced afresh
    ablated, _ = certified(Arnoldi(fallback=False, certify_factor=2.0 + 1e-12, batched=batched))
    assert not ablated.all()


@pytest.mark.parametrize("margin", ax.eigen.arnoldi.RIGHT_DISC_MARGINS)
@pytest.mark.parametrize("lam_r", [-40.0 + 176.0j, 264.0 + 221.0j, -100.0 + 0.0j, 530.0 + 300.0j])
def test_the_right_disc_holds_the_pole_discs_right_part(margin, lam_r):
    """The claim the right disc's certificate rests on, checked by sampling: every point of
    the pole's disc (centre sigma, radius 2 |sigma - lambda_r|) with Re >= Re lambda_r lies
    in the right disc, whose leftmost point is left of Re lambda_r."""
    sigma, factor = 538.0, 2.0
    centre, rho = (float(x) for x in ax.eigen.arnoldi._right_disc(sigma, lam_r, factor, margin))
    r0 = factor * abs(sigma - lam_r)
    rng = np.random.default_rng(0)
    z = sigma + r0 * np.sqrt(rng.uniform(size=20000)) * np.exp(2j * np.pi * rng.uniform(size=20000))
    z = np.concatenate([z, sigma + r0 * np.exp(2j * np.pi * np.linspace(0, 1, 4001))])
    right = z[z.real >= lam_r.real]
    assert np.all(np.abs(right - centre) <= rho * (1 + 1e-12))
    assert centre - rho < lam_r.real and centre >= sigma


# -- bordered block algebra -------------------------------------------------------------
def _random_bordered(rng, N, b, m, complex_=False, symmetric=False):
    def mk(*shape):
        x = rng.normal(size=shape)
        return x + 1j * rng.normal(size=shape) if complex_ else x

    lower = mk(N - 1, b, b)
    diag = mk(N, b, b)
    if symmetric:
        diag = np.stack([d @ d.T + 3 * b * np.eye(b) for d in diag])
        upper = np.swapaxes(lower, 1, 2)
        nb = mk(N * b, m)
        bb = mk(m, m)
        bb = bb @ bb.T + 40 * N * b * np.eye(m)
        bn = nb.T
    else:
        upper = mk(N - 1, b, b)
        nb, bn, bb = mk(N * b, m), mk(m, N * b), mk(m, m)
    tri = BlockTridiagonal(jnp.asarray(lower), jnp.asarray(diag), jnp.asarray(upper))
    return bordered(tri, jnp.asarray(nb), jnp.asarray(bn), jnp.asarray(bb))


@pytest.mark.parametrize("kernels", ["lapack", "jnp"])
@pytest.mark.parametrize("m,complex_", [(0, False), (3, False), (5, True)])
def test_bordered_lu_and_cholesky_against_numpy(m, complex_, kernels):
    rng = np.random.default_rng(m + 7)
    M = _random_bordered(rng, 5, 4, m, complex_)
    D = np.asarray(M.to_dense())
    assert D.shape == (20 + m, 20 + m)
    r = rng.normal(size=20 + m) + (1j * rng.normal(size=20 + m) if complex_ else 0)
    lu = bordered_lu(M, kernels)
    np.testing.assert_allclose(
        np.asarray(lu.solve(jnp.asarray(r))), np.linalg.solve(D, r), rtol=1e-9, atol=1e-9
    )
    np.testing.assert_allclose(
        np.asarray(lu.solve_transpose(jnp.asarray(r))),
        np.linalg.solve(D.T, r),
        rtol=1e-9,
        atol=1e-9,
    )
    np.testing.assert_allclose(np.asarray(M.matvec(jnp.asarray(r))), D @ r, rtol=1e-12, atol=1e-12)
    if not complex_:  # a real matrix on a complex vector (two real products)
        rc = r + 1j * rng.normal(size=20 + m)
        np.testing.assert_allclose(
            np.asarray(M.matvec(jnp.asarray(rc))), D @ rc, rtol=1e-12, atol=1e-12
        )
    S = _random_bordered(rng, 5, 4, m, symmetric=True)
    Ds = np.asarray(S.to_dense())
    assert np.linalg.eigvalsh(Ds).min() > 0
    chol = bordered_cholesky(S, kernels)
    assert bool(chol.ok)
    rr = r.real
    np.testing.assert_allclose(
        np.asarray(chol.solve(jnp.asarray(rr))), np.linalg.solve(Ds, rr), rtol=1e-9
    )
    if m:  # indefinite through the border alone: T stays positive definite
        bad = bordered(
            S.tri, S.nb, S.bn, S.bb - 2 * np.linalg.eigvalsh(np.asarray(S.bb)).max() * np.eye(m)
        )
        assert np.linalg.eigvalsh(np.asarray(bad.to_dense())).min() < 0
        assert not bool(bordered_cholesky(bad, kernels).ok)


# -- bordered pencils -------------------------------------------------------------------
def _bordered_pencil(model, params, m, seed, extra_block=False):
    """The model's pencil with m random border unknowns: A's border random (scaled to
    A's entries), C's symmetric with a positive definite corner (C stays SPD), weakly
    coupled. ``extra_block``: one more node block (a copy of the last, coupled to it),
    as a free base adds."""
    rng = np.random.default_rng(seed)
    s = assemble_blocks(model, params)
    A, C = s.A, s.C
    if extra_block:
        # A copy of the last node block (A's made stiffer, so that it adds no unstable
        # mode), weakly coupled to it.
        def grow(M, shift, sym):
            cpl = 1e-2 * M.lower[-1]
            return BlockTridiagonal(
                jnp.concatenate([M.lower, cpl[None]]),
                jnp.concatenate([M.diag, M.diag[-1:] + shift * jnp.eye(M.block_size)]),
                jnp.concatenate([M.upper, (cpl.T if sym else 1e-2 * M.upper[-1])[None]]),
            )

        a_max = float(jnp.abs(A.diag).max())
        A, C = grow(A, a_max, False), grow(C, 0.0, True)
    n = A.shape[0]
    # Scales of the diagonal blocks' largest entries (drag and stiffness per node).
    a_scale = float(np.median(np.abs(np.asarray(A.diag)).max(axis=(1, 2))))
    c_scale = float(np.median(np.abs(np.asarray(C.diag)).max(axis=(1, 2))))
    A_nb = 1e-3 * a_scale * rng.normal(size=(n, m))
    A_bn = 1e-3 * a_scale * rng.normal(size=(m, n))
    A_bb = a_scale * (np.eye(m) + 0.1 / np.sqrt(m) * rng.normal(size=(m, m)))
    C_nb = 0.01 * c_scale * rng.normal(size=(n, m))
    X = rng.normal(size=(m, m))
    # C's Schur complement c_scale (I + 0.1 X X^T): C symmetric positive definite.
    Cd = np.asarray(C.to_dense())
    C_bb = c_scale * (np.eye(m) + 0.1 * X @ X.T) + C_nb.T @ np.linalg.solve(Cd, C_nb)
    C_bb = (C_bb + C_bb.T) / 2
    system = types.SimpleNamespace(
        A=A, C=C, b=None, A_nb=A_nb, A_bn=A_bn, A_bb=A_bb, C_nb=C_nb, C_bn=C_nb.T, C_bb=C_bb
    )
    return pencil_of(system)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "arnoldi,cases",
    [
        (PATHS[0], ((3, 1, False), (4, 3, True))),
        pytest.param(PATHS[1], ((12, 2, False),), marks=SLOW),
    ],
    ids=PATH_IDS,
)
def test_bordered_pencils_against_scipy(arnoldi, cases):
    """m = 3, 4 (with one node block more than the model's elements) on the per-point
    path, m = 12 on the batched one (each shape compiles its own solver)."""
    model = ax.models.seven(n_elements=6)
    params = ax.Params(p=300.0)
    cases = [_bordered_pencil(model, params, m, seed, extra) for m, seed, extra in cases]
    opts = arnoldi.options._replace(fallback=False)
    for A, C in cases:
        assert A.tri.n_blocks in (6, 7) and A.m in (3, 4, 12)
        Ad, Cd = np.asarray(A.to_dense()), np.asarray(C.to_dense())
        assert np.linalg.eigvalsh(Cd).min() > 0 and np.allclose(Cd, Cd.T)
        lam = sl.eig(-Ad, Cd, right=False)
        top = lam[np.argmax(np.where(lam.imag >= -1e-9, lam.real, -np.inf))]
        batch = jax.tree.map(lambda x: jnp.stack([x, x]), (A, C))
        dom, vec, cert = jax.jit(jax.vmap(lambda a, c: structured_dominant(a, c, opts)))(*batch)
        assert np.all(np.asarray(cert) == 1.0)
        assert np.all(np.abs(np.asarray(dom) - top) <= 1e-8 * abs(top)), (dom, top)
        v = np.asarray(vec[0])
        assert v.shape == (Ad.shape[0],)
        assert np.linalg.norm((Ad + complex(dom[0]) * Cd) @ v) <= 1e-8 * np.linalg.norm(Ad)
        shift = complex(top) + 40.0 - 60j
        ref = lam[np.argmin(np.abs(lam - shift))]
        shifts = jnp.asarray([shift, shift])
        near, _, cert = jax.jit(jax.vmap(lambda a, c, s: structured_nearest(a, c, s, opts)))(
            *batch, shifts
        )
        assert np.all(np.asarray(cert) == 1.0)
        assert np.all(np.abs(np.asarray(near) - ref) <= 1e-8 * abs(ref)), (near, ref)


@pytest.mark.slow
def test_bordered_derivatives_match_the_dense_rule():
    """The JVP of both structured eigenpairs along random tangents of every block (the
    border's included) equals the dense solvers' (full eigen-decomposition) rule."""
    model = ax.models.seven(n_elements=5)
    A, C = _bordered_pencil(model, ax.Params(p=300.0), 3, 4)
    rng = np.random.default_rng(5)
    dA = jax.tree.map(lambda x: jnp.asarray(rng.normal(size=x.shape)) * jnp.abs(x).max() * 1e-3, A)
    dC = jax.tree.map(lambda x: jnp.asarray(rng.normal(size=x.shape)) * jnp.abs(x).max() * 1e-3, C)
    dense = lambda M: M.to_dense()
    opts = Arnoldi().options
    lam, dlam = jax.jvp(lambda a, c: structured_dominant(a, c, opts)[0], (A, C), (dA, dC))
    ref, dref = jax.jvp(
        lambda a, c: ax.eigen.dominant.dominant_eigenpair(dense(a), dense(c))[0], (A, C), (dA, dC)
    )
    assert abs(complex(lam - ref)) <= 1e-9 * abs(complex(ref))
    assert abs(complex(dlam - dref)) <= 1e-7 * abs(complex(dref))
    shift = jnp.asarray(complex(ref) + 30.0 - 50j)
    lam, dlam = jax.jvp(lambda a, c: structured_nearest(a, c, shift, opts)[0], (A, C), (dA, dC))
    ref, dref = jax.jvp(
        lambda a, c: nearest_eigenpair(dense(a), dense(c), shift)[0], (A, C), (dA, dC)
    )
    assert abs(complex(lam - ref)) <= 1e-9 * abs(complex(ref))
    assert abs(complex(dlam - dref)) <= 1e-7 * abs(complex(dref))


def test_filament_major_keeps_the_border_last_and_bad_borders_are_refused():
    """The solvers' eigenvector order: node unknowns back to the dense solver's
    filament-major order, the border unknowns after them, as they are."""
    from axojax.assembly import node_major
    from axojax.eigen.solvers import filament_major

    model = ax.models.two(n_elements=3)
    perm = node_major(model)
    q = np.arange(perm.size + 2, dtype=float)  # filament-major values, then a border of 2
    x = jnp.asarray(np.concatenate([q[perm], q[perm.size :]]))
    np.testing.assert_array_equal(np.asarray(filament_major(model, x)), q)
    tri = assemble_blocks(model, ax.Params()).A
    n = tri.shape[0]
    with pytest.raises(ValueError, match="border shapes") as info:
        bordered(tri, np.zeros((n, 2)), np.zeros((2, n)), np.zeros((3, 3)))
    assert "\n" not in str(info.value)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_arnoldi_on_a_compliant_clamped_base_is_structured_and_equals_dense():
    """Basal compliance on a clamped base is a border without rigid motion: the structured
    solver takes it itself (certified, no dense fallback) and agrees with the dense one."""
    from axojax.models import Base

    model = ax.models.seven(n_elements=6, base=Base("clamped", compliance=True))
    params = ax.Params(kb=1e3, xib=1.0)
    dense = ax.dominant_mode(model, params, Dense())
    arnoldi = ax.dominant_mode(model, params, Arnoldi())
    assert bool(arnoldi.certified)
    lam = complex(dense.eigenvalue)
    assert abs(complex(arnoldi.eigenvalue) - lam) < 1e-8 * abs(lam)
    assert abs(float(arnoldi.wavelength - dense.wavelength)) < 1e-7 * float(dense.wavelength)
