"""The structure-exploiting eigen-solver (issues 14, 22): block-tridiagonal algebra and
the plain-jnp small kernels against numpy, node-major assembly against the dense one,
and ``ax.eigen.Arnoldi`` (per-point and batched paths) against ``ax.eigen.Dense`` (same
eigenvalue to 1e-9, same classification) on seven, nine, a 40-element mesh and a user's
cross-section; derivatives against finite differences; the dense fallback; the command
line."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.assembly import assemble_blocks, node_major
from axojax.cli.main import main
from axojax.eigen import Arnoldi, Dense
from axojax.linalg import BlockTridiagonal, arnoldi_steps, cholesky, lu_factor, small

RTOL = 1e-9
PATHS = [Arnoldi(batched=False), Arnoldi(batched=True)]
PATH_IDS = ["per-point", "batched"]


def random_blocks(rng, N, b, complex_=False, diag_scale=0.1):
    def mk(*shape):
        x = rng.normal(size=shape)
        return x + 1j * rng.normal(size=shape) if complex_ else x

    # A weak diagonal forces row exchanges between block rows.
    return BlockTridiagonal(
        jnp.asarray(mk(N - 1, b, b)),
        jnp.asarray(diag_scale * mk(N, b, b)),
        jnp.asarray(mk(N - 1, b, b)),
    )


@pytest.mark.parametrize("kernels", ["lapack", "jnp"])
@pytest.mark.parametrize(
    "N,b,complex_", [(1, 3, False), (2, 4, False), (7, 5, False), (6, 4, True)]
)
def test_block_lu_solves_against_numpy(N, b, complex_, kernels):
    rng = np.random.default_rng(N * 10 + b)
    M = random_blocks(rng, N, b, complex_)
    D = np.asarray(M.to_dense())
    r = rng.normal(size=N * b) + (1j * rng.normal(size=N * b) if complex_ else 0)
    lu = lu_factor(M, kernels)
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


@pytest.mark.parametrize("kernels", ["lapack", "jnp"])
def test_block_cholesky_solves_and_tests_definiteness(kernels):
    rng = np.random.default_rng(3)
    N, b = 6, 5
    lower = rng.normal(size=(N - 1, b, b))
    diag = np.stack([x @ x.T + 3 * b * np.eye(b) for x in rng.normal(size=(N, b, b))])
    M = BlockTridiagonal(
        jnp.asarray(lower), jnp.asarray(diag), jnp.asarray(np.swapaxes(lower, 1, 2))
    )
    D = np.asarray(M.to_dense())
    assert np.linalg.eigvalsh(D).min() > 0
    r = rng.normal(size=N * b)
    chol = cholesky(M, kernels)
    assert bool(chol.ok)
    np.testing.assert_allclose(
        np.asarray(chol.solve(jnp.asarray(r))), np.linalg.solve(D, r), rtol=1e-10
    )
    shifted = M - BlockTridiagonal(
        0 * M.lower, jnp.asarray(np.eye(b)[None] * (np.linalg.eigvalsh(D).min() + 1.0)), 0 * M.upper
    )
    assert not bool(cholesky(shifted, kernels).ok)


def test_small_jnp_kernels_against_numpy_and_scipy():
    """Pivoted LU (same pivots as LAPACK: scipy), Cholesky and triangular inverses,
    real and complex, with no LAPACK custom call when vmapped."""
    import scipy.linalg

    rng = np.random.default_rng(7)
    for a in (rng.normal(size=(10, 6)), rng.normal(size=(8, 8)) + 1j * rng.normal(size=(8, 8))):
        lu, perm = small.lu_pivoted(jnp.asarray(a))
        p, l, u = scipy.linalg.lu(a)  # a = p l u
        np.testing.assert_array_equal(np.asarray(perm), np.argmax(p, axis=0))
        np.testing.assert_allclose(
            np.tril(np.asarray(lu), -1)[:, : a.shape[1]] + np.eye(*a.shape), l, atol=1e-12
        )
        np.testing.assert_allclose(np.triu(np.asarray(lu))[: a.shape[1]], u, atol=1e-12)
    s = rng.normal(size=(7, 7))
    s = s @ s.T + np.eye(7)
    np.testing.assert_allclose(
        np.asarray(small.cholesky_lower(jnp.asarray(s))), np.linalg.cholesky(s), atol=1e-12
    )
    assert np.isnan(np.asarray(small.cholesky_lower(jnp.asarray(s - 50 * np.eye(7))))).any()
    t = np.tril(rng.normal(size=(7, 7))) + 4 * np.eye(7)
    np.testing.assert_allclose(
        np.asarray(small.triangular_inverse(jnp.asarray(t), lower=True)),
        np.linalg.inv(t),
        atol=1e-12,
    )
    np.testing.assert_allclose(
        np.asarray(small.triangular_inverse(jnp.asarray(t.T), lower=False)),
        np.linalg.inv(t.T),
        atol=1e-12,
    )
    unit = np.tril(t, -1) + np.eye(7)
    np.testing.assert_allclose(
        np.asarray(small.triangular_inverse(jnp.asarray(t), lower=True, unit_diagonal=True)),
        np.linalg.inv(unit),
        atol=1e-12,
    )
    hlo = (
        jax.jit(jax.vmap(lambda m: lu_factor(m, "jnp").solve(jnp.ones(m.shape[0]))))
        .lower(jax.tree.map(lambda x: jnp.stack([x, x]), random_blocks(rng, 3, 4)))
        .as_text()
    )
    assert "custom_call" not in hlo


def test_arnoldi_steps_in_stages_with_windows():
    """Arnoldi grown in stages, orthogonalising against a window of rows per stage: the
    Arnoldi relation op V[:m] = V[:m+1] H and orthonormality hold (numpy), and V and H
    equal those of Gram-Schmidt against every row."""
    rng = np.random.default_rng(3)
    n, dims = 30, (4, 7, 12)
    S = rng.normal(size=(n, n))
    v0 = rng.normal(size=n)
    V0 = jnp.zeros((dims[-1] + 1, n)).at[0].set(v0 / np.linalg.norm(v0))
    H0 = jnp.zeros((dims[-1] + 1, dims[-1]))
    op = lambda v: jnp.asarray(S) @ v
    out = {}
    for windows in ((), dims):
        V, H = V0, H0
        for start, stop in zip((0,) + dims[:-1], dims):
            V, H = jax.jit(arnoldi_steps, static_argnums=(0, 5))(op, V, H, start, stop, windows)
        out[windows] = np.asarray(V), np.asarray(H)
    V, H = out[dims]
    m = dims[-1]
    np.testing.assert_allclose(S @ V[:m].T, V.T @ H, atol=1e-12)
    np.testing.assert_allclose(V @ V.T, np.eye(m + 1), atol=1e-12)
    np.testing.assert_allclose(V, out[()][0], atol=1e-12)
    np.testing.assert_allclose(H, out[()][1], atol=1e-12)
    with pytest.raises(ValueError, match="windows must be row counts in 1..13"):
        arnoldi_steps(op, V0, H0, 0, 1, windows=(4, 14))


@pytest.mark.parametrize("name", ["single", "beck", "two", "four", "seven", "nine"])
def test_block_assembly_is_the_dense_assembly_reordered(name):
    model = ax.models.preset(name, n_elements=5)
    params = ax.Params(p=123.0, gamma=0.3, ktheta=2.0, imbalance=2.0)
    dense, blocks, perm = (
        ax.assemble(model, params),
        assemble_blocks(model, params),
        node_major(model),
    )
    for D, B in ((dense.A, blocks.A), (dense.C, blocks.C)):
        D = np.asarray(D)[np.ix_(perm, perm)]
        np.testing.assert_allclose(
            np.asarray(B.to_dense()), D, rtol=1e-12, atol=1e-12 * np.abs(D).max()
        )
    np.testing.assert_allclose(np.asarray(blocks.b), np.asarray(dense.b)[perm])


def batch_modes(model, params, solver):
    return jax.jit(jax.vmap(lambda prm: ax.eigen.mode._dominant_mode_impl(model, prm, solver)))(
        params
    )


def grid_params(ps, kss, ratio=1e3, **fixed):
    P, K = np.meshgrid(ps, kss, indexing="ij")
    return ax.Params(**fixed).replace(p=P.ravel(), ks=K.ravel(), kl=K.ravel() / ratio).broadcast()


def assert_same_modes(dense, fast):
    lam_d, lam_f = np.asarray(dense.eigenvalue), np.asarray(fast.eigenvalue)
    err = np.abs(lam_f - lam_d) / np.maximum(np.abs(lam_d), 1.0)
    assert err.max() < RTOL, (err.max(), lam_d[err.argmax()], lam_f[err.argmax()])
    np.testing.assert_array_equal(np.asarray(fast.classification), np.asarray(dense.classification))
    # Same eigenvector up to phase (where the eigenvalue is simple).
    overlap = np.abs(
        np.sum(np.conj(np.asarray(dense.eigenvector)) * np.asarray(fast.eigenvector), axis=-1)
    )
    assert np.all(overlap > 1 - 1e-6), overlap.min()


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("arnoldi", PATHS, ids=PATH_IDS)
def test_seven_sweep_arnoldi_equals_dense(capsys, arnoldi):
    model = ax.models.seven()
    axes = {"p": np.linspace(100, 900, 5), "ks": np.logspace(2, 7, 6)}
    dense = ax.sweep(model, ax.Params(), axes, kl_ratio=1e3, solver=Dense(), progress=False)
    fast = ax.sweep(model, ax.Params(), axes, kl_ratio=1e3, solver=arnoldi, progress=False)
    lam_d = dense.data["eigenvalue_real"] + 1j * dense.data["eigenvalue_imag"]
    lam_f = fast.data["eigenvalue_real"] + 1j * fast.data["eigenvalue_imag"]
    assert np.max(np.abs(lam_f - lam_d) / np.maximum(np.abs(lam_d), 1.0)) < RTOL
    np.testing.assert_array_equal(fast.data["classification"], dense.data["classification"])
    certified = fast.data["certified"]
    assert np.all(dense.data["certified"] == 1) and dense.meta["solver"] == {
        "name": "dense",
        "dense_fallbacks": 0,
    }
    assert fast.meta["solver"] == {
        "name": "arnoldi",
        "dense_fallbacks": int((certified == 0).sum()),
    }
    with capsys.disabled():
        print(
            f"\nseven, 30 points: {certified.sum()} certified by Arnoldi, "
            f"{(certified == 0).sum()} by the dense fallback"
        )
    assert certified.mean() >= 0.8


def test_auto_picks_arnoldi_for_large_models_and_sweeps():
    auto = ax.eigen.Auto()
    seven, seven40, four = ax.models.seven(), ax.models.seven(n_elements=40), ax.models.four()
    assert isinstance(auto.resolve(seven), Dense) and isinstance(
        auto.resolve(seven, n_points=400), Arnoldi
    )
    assert isinstance(auto.resolve(seven40), Arnoldi)
    assert isinstance(auto.resolve(four, n_points=400), Dense)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("arnoldi", PATHS, ids=PATH_IDS)
def test_nine_and_other_parameters_arnoldi_equals_dense(arnoldi):
    model = ax.models.nine()
    params = ax.Params(
        p=jnp.array([150.0, 300.0, 500.0, 250.0]),
        ks=jnp.array([1e3, 1e6, 1e4, 1e5]),
        kl=jnp.array([1.0, 1e3, 1e4, 1e-1]),
        cl=jnp.array([1e-4, 0.005, 1.0, 0.05]),
        gamma=jnp.array([-1.0, 0.0, 0.5, 0.2]),
        ktheta=jnp.array([0.0, 5.0, 0.0, 1.0]),
        imbalance=jnp.array([1.0, 1.0, 2.0, 5.0]),
    ).broadcast()
    assert_same_modes(batch_modes(model, params, Dense()), batch_modes(model, params, arnoldi))


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "arnoldi", [PATHS[0], pytest.param(PATHS[1], marks=pytest.mark.slow)], ids=PATH_IDS
)
def test_forty_elements_arnoldi_equals_dense(arnoldi):
    # Away from Re lambda = 0: at 40 elements the dense solver's own error is ~1e-7 in
    # absolute terms (eps times the norm of the reduced matrix), which is above 1e-9 of
    # |lambda| only for eigenvalues of modulus below ~100, e.g. right at a Hopf point.
    model = ax.models.seven(n_elements=40)
    params = grid_params(np.array([300.0, 600.0]), np.array([1e4, 1e6]))
    fast = batch_modes(model, params, arnoldi)
    assert_same_modes(batch_modes(model, params, Dense()), fast)
    # Against the true eigenvalue: the refined shift-invert solves keep Arnoldi within
    # 3e-11 (without the refinement 8.5e-10 here at p = 300, ks = 1e6; dense 1.8e-10).
    for i in range(4):
        system = ax.assemble(model, jax.tree.map(lambda x: x[i], params))
        lam = complex(fast.eigenvalue[i])
        true = true_eigenvalue(
            np.asarray(system.A), np.asarray(system.C), lam, np.asarray(fast.eigenvector[i])
        )
        assert abs(lam - true) <= 3e-11 * abs(true), (i, lam, true)


def true_eigenvalue(A, C, lam, x, steps=4):
    """The eigenvalue of (A + lambda C) x = 0 near (lam, x), by Newton's method on the
    bordered system with its residuals in extended precision (numpy longdouble): the
    reference the float64 solvers are measured against."""
    n = A.shape[0]
    Al, Cl = A.astype(np.longdouble), C.astype(np.longdouble)
    xr, xi = x.real.astype(np.longdouble), x.imag.astype(np.longdouble)
    lr, li = np.longdouble(lam.real), np.longdouble(lam.imag)
    c = np.conj(x) / np.vdot(x, x)
    for _ in range(steps):
        rr = Al @ xr + lr * (Cl @ xr) - li * (Cl @ xi)
        ri = Al @ xi + lr * (Cl @ xi) + li * (Cl @ xr)
        xf, lf = xr.astype(float) + 1j * xi.astype(float), complex(float(lr), float(li))
        border = np.block([[A + lf * C, (C @ xf)[:, None]], [c[None, :], np.zeros((1, 1))]])
        d = np.linalg.solve(
            border, -np.concatenate([rr.astype(float) + 1j * ri.astype(float), [c @ xf - 1.0]])
        )
        xr, xi = xr + d[:n].real.astype(np.longdouble), xi + d[:n].imag.astype(np.longdouble)
        lr, li = lr + np.longdouble(d[n].real), li + np.longdouble(d[n].imag)
    return complex(float(lr), float(li))


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("arnoldi", PATHS, ids=PATH_IDS)
def test_model_file_cross_section_arnoldi_equals_dense(tmp_path, arnoldi):
    """A five-filament cross-section of a user's own, with unequal rigidity and drag."""
    path = tmp_path / "five.toml"
    path.write_text(
        'name = "five"\n'
        + "".join(
            f"[[filaments]]\nposition = [{np.sin(a):.6f}, {np.cos(a):.6f}]\nei = {1 + 0.2 * k}\ndrag = {1 + 0.1 * k}\n"
            for k, a in enumerate(np.deg2rad([40, -40, -140, 140]))
        )
        + "[[filaments]]\nposition = [0.0, 0.0]\n"
        + "".join(f"[[links]]\nbetween = [{k}, {(k + 1) % 4}]\n" for k in range(4))
        + "".join(f'[[links]]\nbetween = [4, {k}]\nkind = "spoke"\n' for k in range(4))
        + "[[active_pairs]]\nbetween = [0, 1]\n[[active_pairs]]\nbetween = [2, 3]\ngroup = 1\n"
    )
    model = ax.models.from_file(path, n_elements=12)
    params = grid_params(np.array([200.0, 500.0]), np.array([1e3, 1e6]))
    assert_same_modes(batch_modes(model, params, Dense()), batch_modes(model, params, arnoldi))


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("batched", [False, True], ids=PATH_IDS)
def test_fallback_when_not_certified_gives_the_dense_answer(batched):
    """A certificate radius no Krylov space of this size can reach: every point goes to
    the dense solver, and says so."""
    model = ax.models.seven(n_elements=6)
    params = grid_params(np.array([300.0, 700.0]), np.array([1e5]))
    strict = Arnoldi(krylov_dims=(8,), certify_factor=1e12, batched=batched)
    fast = batch_modes(model, params, strict)
    assert not np.any(np.asarray(fast.certified))
    assert_same_modes(batch_modes(model, params, Dense()), fast)
    # fallback off: the uncertified Krylov answer comes back as it is, flagged
    loose = batch_modes(
        model,
        params,
        Arnoldi(krylov_dims=(8,), certify_factor=1e12, fallback=False, batched=batched),
    )
    assert not np.any(np.asarray(loose.certified)) and np.all(
        np.isfinite(np.asarray(loose.eigenvalue))
    )


def metrics(model, solver):
    def f(z):  # log p, log ks, log cl, gamma
        mode = ax.eigen.mode._dominant_mode_impl(
            model,
            ax.Params(
                p=jnp.exp(z[0]),
                ks=jnp.exp(z[1]),
                kl=jnp.exp(z[1]) / 1e3,
                cl=jnp.exp(z[2]),
                gamma=z[3],
            ),
            solver,
        )
        return jnp.stack([mode.growth_rate_per_s(), mode.frequency_hz(), mode.wavelength_um()])

    return f


@pytest.mark.slow
def test_arnoldi_gradients_match_finite_differences_and_dense():
    model = ax.models.seven(
        n_elements=5
    )  # the derivative rules, not the size: 5 elements compile faster than 10
    z = jnp.array([np.log(420.0), np.log(2e5), np.log(0.01), -0.3])
    f = metrics(model, Arnoldi())
    at_z = ax.Params(
        p=float(np.exp(z[0])),
        ks=float(np.exp(z[1])),
        kl=float(np.exp(z[1])) / 1e3,
        cl=float(np.exp(z[2])),
        gamma=float(z[3]),
    )
    assert bool(
        ax.dominant_mode(model, at_z, solver=Arnoldi(fallback=False)).certified
    )  # Arnoldi's own answer and rule, not the fallback's
    fwd = np.asarray(jax.jit(jax.jacfwd(f))(z))
    rev = np.asarray(jax.jit(jax.jacrev(f))(z))
    h = 1e-4
    steps = np.eye(4) * h
    fz = jax.jit(jax.vmap(metrics(model, Dense())))
    vals = np.asarray(
        fz(jnp.asarray(np.concatenate([z + 2 * steps, z + steps, z - steps, z - 2 * steps])))
    )
    a, b, c, d = vals[:4], vals[4:8], vals[8:12], vals[12:]
    fd = ((-a + 8 * b - 8 * c + d) / (12 * h)).T  # (3 metrics, 4 params)
    scale = np.linalg.norm(fd, axis=1, keepdims=True)
    assert np.max(np.abs(fwd - fd) / scale) < 1e-6
    assert np.max(np.abs(rev - fd) / scale) < 1e-6
    dense = np.asarray(jax.jit(jax.jacfwd(metrics(model, Dense())))(z))
    assert (
        np.max(np.abs(fwd - dense) / scale) < 1e-8
    )  # the dense solver's derivative rule, independently
    # The batched path (vmapped: its jnp kernels, also in the derivative rule's complex LU).
    batched = np.asarray(
        jax.jit(jax.vmap(jax.jacrev(metrics(model, Arnoldi(batched=True)))))(jnp.stack([z, z]))
    )
    assert np.max(np.abs(batched - fd[None]) / scale[None]) < 1e-6


@pytest.mark.slow
def test_critical_force_with_arnoldi_equals_dense():
    model = ax.models.seven(n_elements=8)
    a = ax.critical_force(model, ax.Params(ks=1e5, kl=100.0), solver=Arnoldi())
    d = ax.critical_force(model, ax.Params(ks=1e5, kl=100.0), solver=Dense())
    assert float(a.p) == pytest.approx(float(d.p), rel=1e-9)
    assert float(a.frequency_hz()) == pytest.approx(float(d.frequency_hz()), rel=1e-8)


def test_cli_solver_flag(capsys):
    """docs/model.md section 6: seven at p = 300 is 137.696 +- 270.311i (50.30 Hz)."""
    assert (
        main(
            [
                "modes",
                "--model",
                "seven",
                "--p",
                "300",
                "--solver",
                "arnoldi",
                "--json",
                "--top",
                "2",
            ]
        )
        == 0
    )
    d = json.loads(capsys.readouterr().out)["dominant"]
    assert abs(complex(*d["eigenvalue"]) - complex(137.696, 270.311)) < 5e-4
    assert d["classification"] == "flutter" and round(d["frequency_hz"], 2) == 50.30
    assert (
        main(
            ["modes", "--model", "seven", "--p", "300", "--solver", "dense", "--json", "--top", "2"]
        )
        == 0
    )
    dense = json.loads(capsys.readouterr().out)["dominant"]
    assert abs(complex(*dense["eigenvalue"]) - complex(*d["eigenvalue"])) < RTOL * abs(
        complex(*d["eigenvalue"])
    )
    assert main(["modes", "--model", "seven", "--solver", "qr"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("axojax: error: --solver:") and "\n" not in err and "qr" in err
