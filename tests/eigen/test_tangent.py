"""The structured eigenpair's derivative rule (axojax/eigen/tangent.py) against independent
references: scipy's left and right eigenvectors (dlambda = -w^H dK x / w^H C x), numpy's
dense bordered solve (dx), scipy eigenvalues at perturbed matrices (finite differences),
and a dense bordered solve in jnp whose transpose JAX derives (reverse mode); with and
without a border, on both paths (per point with packed LAPACK factors; batched with the
jnp kernels), and under vmap. Also the packed block LU it factors with."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sl

from axojax.eigen import tangent as _tangent
from axojax.linalg import (
    BlockTridiagonal,
    bordered,
    bordered_lu,
    lu_factor_local,
    lu_factor_packed,
)

# jitted: the rule's scans run compiled, as in use (eagerly they take ~10 s a test).
eigenpair_tangent = jax.jit(_tangent.eigenpair_tangent, static_argnums=6)


def _blocks(rng, N, b, complex_=False):
    def r(*shape):
        x = rng.standard_normal(shape)
        return x + 1j * rng.standard_normal(shape) if complex_ else x

    return BlockTridiagonal(
        jnp.asarray(r(N - 1, b, b)), jnp.asarray(r(N, b, b)), jnp.asarray(r(N - 1, b, b))
    )


@pytest.mark.parametrize("local", [False, True], ids=["band-pivoting", "local-pivoting"])
@pytest.mark.parametrize("N, b", [(1, 3), (2, 2), (6, 4)])
@pytest.mark.parametrize("complex_", [False, True])
def test_packed_block_lu_solves_against_numpy(N, b, complex_, local):
    """The packed block LUs (pivoting across block rows, and inside the diagonal blocks
    only: the derivative rule's) solve M x = r and M^T x = r as numpy does, with and
    without a border."""
    rng = np.random.default_rng(N + 10 * b)
    M = _blocks(rng, N, b, complex_)
    D = np.asarray(M.to_dense())
    r = rng.standard_normal(N * b) + (1j * rng.standard_normal(N * b) if complex_ else 0)
    lu = lu_factor_local(M) if local else lu_factor_packed(M)
    np.testing.assert_allclose(
        np.asarray(lu.solve(jnp.asarray(r))), np.linalg.solve(D, r), 1e-10, 1e-10
    )
    np.testing.assert_allclose(
        np.asarray(lu.solve_transpose(jnp.asarray(r))), np.linalg.solve(D.T, r), 1e-10, 1e-10
    )
    # With a border of 2 (Schur complement through the packed factors).
    m = 2
    B = bordered(M, rng.standard_normal((N * b, m)), rng.standard_normal((m, N * b)), np.eye(m))
    DB = np.asarray(B.to_dense())
    s = np.concatenate([r, rng.standard_normal(m)])
    blu = bordered_lu(B, packed=True, local=local)
    np.testing.assert_allclose(
        np.asarray(blu.solve(jnp.asarray(s))), np.linalg.solve(DB, s), 1e-10, 1e-10
    )
    np.testing.assert_allclose(
        np.asarray(blu.solve_transpose(jnp.asarray(s))), np.linalg.solve(DB.T, s), 1e-10, 1e-10
    )


def test_packed_factors_need_lapack_kernels():
    M = _blocks(np.random.default_rng(0), 2, 2)
    with pytest.raises(ValueError, match="packed factors need kernels='lapack', got 'jnp'"):
        bordered_lu(M, "jnp", packed=True)
    with pytest.raises(ValueError, match="local pivoting needs packed=True"):
        bordered_lu(M, local=True)


def _pencil(m: int, seed: int = 3):
    """A small bordered pencil (A + lambda C) v = 0: A non-symmetric, C symmetric positive
    definite (N = 5 blocks of 3, border m), and tangents with A's and C's structure."""
    rng = np.random.default_rng(seed)
    N, b = 5, 3

    def border(scale):
        if m == 0:
            return None, None, None
        return (
            scale * rng.standard_normal((N * b, m)),
            scale * rng.standard_normal((m, N * b)),
            scale * rng.standard_normal((m, m)) + 3 * np.eye(m),
        )

    A = bordered(_blocks(rng, N, b), *border(1.0))
    G = bordered(_blocks(rng, N, b), *border(0.3))
    C = (G.T.scale(0.3) + G.scale(0.3)) + bordered(
        BlockTridiagonal(
            jnp.zeros((N - 1, b, b)),
            jnp.broadcast_to(4 * jnp.eye(b), (N, b, b)),
            jnp.zeros((N - 1, b, b)),
        ),
        *((np.zeros((N * b, m)), np.zeros((m, N * b)), 4 * np.eye(m)) if m else (None,) * 3),
    )
    dA = jax.tree.map(lambda a: jnp.asarray(rng.standard_normal(a.shape)), A)
    dC = jax.tree.map(lambda a: jnp.asarray(rng.standard_normal(a.shape)), C)
    return A, C, dA, dC


def _eig(A, C):
    """scipy: the eigenvalue of largest real part of (A + lambda C) v = 0, its unit right
    and left eigenvectors."""
    lam, W, V = sl.eig(-np.asarray(A), np.asarray(C), left=True, right=True)
    i = np.argmax(lam.real + 1e-9 * lam.imag)
    return lam[i], V[:, i] / np.linalg.norm(V[:, i]), W[:, i]


def _dense_tangent(A, C, dA, dC, lam, x):
    """(dlambda, dx) by a dense bordered solve in jnp (JAX transposes it itself)."""
    K = A + lam * C
    n = K.shape[0]
    Cx = C @ x
    B = jnp.block([[K, Cx[:, None]], [jnp.conj(x)[None, :], jnp.zeros((1, 1), K.dtype)]])
    rhs = jnp.concatenate([-(dA @ x + lam * (dC @ x)), jnp.zeros(1, K.dtype)])
    sol = jnp.linalg.solve(B, rhs)
    return sol[n], sol[:n]


@pytest.mark.parametrize("m", [0, 2])
@pytest.mark.parametrize("batched", [False, True])
def test_tangent_matches_scipy_and_finite_differences(m, batched):
    A, C, dA, dC = _pencil(m)
    Ad, Cd, dAd, dCd = (np.asarray(M.to_dense()) for M in (A, C, dA, dC))
    lam, x, w = _eig(Ad, Cd)
    dlam, dx = eigenpair_tangent(A, C, dA, dC, jnp.asarray(lam), jnp.asarray(x), batched)
    dlam, dx = complex(dlam), np.asarray(dx)
    dK = dAd + lam * dCd
    # First-order perturbation theory with scipy's left eigenvector.
    ref = -(np.conj(w) @ dK @ x) / (np.conj(w) @ Cd @ x)
    assert abs(dlam - ref) <= 1e-10 * abs(ref)
    # dx: numpy's dense bordered solve (the gauge x^H dx = 0).
    B = np.block([[Ad + lam * Cd, (Cd @ x)[:, None]], [np.conj(x)[None, :], np.zeros((1, 1))]])
    sol = np.linalg.solve(B, np.concatenate([-dK @ x, [0]]))
    assert np.linalg.norm(dx - sol[:-1]) <= 1e-10 * np.linalg.norm(sol[:-1])
    assert abs(np.vdot(x, dx)) <= 1e-12 * np.linalg.norm(dx)
    # Finite differences of scipy's eigenpairs: lambda, and |x_i|^2 (gauge-free).
    h = 1e-5
    pairs = [_eig(Ad + s * h * dAd, Cd + s * h * dCd)[:2] for s in (2, 1, -1, -2)]
    (l2, x2), (l1, x1), (lm1, xm1), (lm2, xm2) = pairs
    fd = (-l2 + 8 * l1 - 8 * lm1 + lm2) / (12 * h)
    assert abs(dlam - fd) <= 1e-7 * abs(fd)
    a = lambda v: np.abs(v) ** 2
    fd_x = (-a(x2) + 8 * a(x1) - 8 * a(xm1) + a(xm2)) / (12 * h)
    np.testing.assert_allclose(2 * np.real(np.conj(x) * dx), fd_x, atol=1e-7 * np.abs(fd_x).max())


@pytest.mark.parametrize("m", [0, 2])
@pytest.mark.parametrize("batched", [False, True])
def test_reverse_mode_matches_the_dense_transpose(m, batched):
    """The transposed bordered solve (reverse mode) against JAX's own transpose of a
    dense bordered solve, for one cotangent of (dlambda, dx); and under vmap."""
    A, C, dA, dC = _pencil(m, seed=5)
    lam, x, _ = _eig(np.asarray(A.to_dense()), np.asarray(C.to_dense()))
    lam, x = jnp.asarray(lam), jnp.asarray(x)
    rng = np.random.default_rng(7)
    ct = (
        jnp.asarray(0.3 - 0.7j),
        jnp.asarray(rng.standard_normal(x.shape) + 1j * rng.standard_normal(x.shape)),
    )

    def ours(dA, dC):
        return eigenpair_tangent(A, C, dA, dC, lam, x, batched)

    def dense(dA, dC):
        return _dense_tangent(A.to_dense(), C.to_dense(), dA.to_dense(), dC.to_dense(), lam, x)

    got = jax.vjp(ours, dA, dC)[1](ct)
    want = jax.vjp(dense, dA, dC)[1](ct)
    for g, r in zip(jax.tree.leaves(got), jax.tree.leaves(want)):
        np.testing.assert_allclose(
            np.asarray(g), np.asarray(r), rtol=1e-9, atol=1e-9 * np.abs(r).max(initial=0.0)
        )
    # vmapped over tangents (forward mode, several directions): each equals its own call.
    dAs = jax.tree.map(lambda a: jnp.stack([a, -2 * a]), dA)
    dCs = jax.tree.map(lambda a: jnp.stack([a, 0.5 * a]), dC)
    dl, dxs = jax.vmap(ours)(dAs, dCs)
    for k in range(2):
        pick = lambda M: jax.tree.map(lambda a: a[k], M).to_dense()
        ref = _dense_tangent(A.to_dense(), C.to_dense(), pick(dAs), pick(dCs), lam, x)
        np.testing.assert_allclose(np.asarray(dl[k]), np.asarray(ref[0]), rtol=1e-9)
        scale = float(jnp.abs(ref[1]).max())
        np.testing.assert_allclose(
            np.asarray(dxs[k]), np.asarray(ref[1]), rtol=1e-9, atol=1e-9 * scale
        )
