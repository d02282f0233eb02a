"""The rightmost eigenpair of a block-tridiagonal pencil by certified shift-invert Arnoldi.

Problem: ``(A + lambda C) v = 0`` with A, C block-tridiagonal (node-major, see
:func:`axojax.assembly.assemble_blocks`), optionally with a border of m extra unknowns
after the node unknowns (:class:`axojax.linalg.Bordered`, :func:`axojax.assembly.pencil_of`: every
factorisation below then eliminates the border by its Schur complement), C symmetric
positive definite; wanted: the eigenvalue of largest real part, exactly (to the accuracy
of a dense solver), and a statement that nothing lies to its right.

Regulated dynein (docs/model.md section 8): its elastic parts (chi', beta') change A
only, and chi'' >= 0 with beta'' = 0 keeps C symmetric positive definite: certified
here as the steady load is. beta'' != 0 makes C non-symmetric and chi'' < 0 indefinite;
such points go to the dense solver (``certified = 0``; the eigenvalue nearest a shift,
:mod:`axojax.eigen.arnoldi_nearest`, needs no pole and is structured for any C). No
rigorous pole close to the spectrum is known there: the field of values of C is not in
the right half plane when C is indefinite (then no bound exists: the spurious modes
grow like N_e^2), and for non-symmetric C the bounds tried (measured on seven at 8 and
16 elements, p = 300, beta = 300 + 500i, omega0 = 300, rightmost Re lambda = -24; the
symmetric case's bound here is ~440) are far off: the Euclidean field of values of
``-A C^{-1}`` (from ``Re(C^T (A + lambda C))``) 1.9e8 / 6.2e9, the ``C^T C_s^{-1} C``
weighted one 5.7e5 / 7.6e6, and ``C_s``'s Cholesky plus the bound
``Re lambda <= (omega + kappa |t|) / (1 + t^2)``, ``|t| <= tau`` (kappa, tau the
C_s-weighted norms of the skew parts of A and C) 8.4e4 / 7.1e5, growing like N_e^3. A
pole there leaves thousands of eigenvalues within the certificate's radius.

Algorithm (per parameter point, fixed shapes: jit/vmap-able):

1. **Pole to the right of the spectrum.** Every eigenvalue satisfies
   ``Re lambda <= omega``, the numerical abscissa: the largest eigenvalue of the
   symmetric pencil ``(-(A + A^T)/2, C)`` (field of values). A block Cholesky of
   ``s C + (A + A^T)/2`` succeeds exactly when ``s > omega``: the smallest passing one
   of the trial values s = 0, 7, 63, 511, ... (found by a search that starts at
   :data:`FIRST_TRIAL`: two factorisations at the usual abscissae) lies within a
   factor ~8 above omega;
   shift-invert Lanczos (``lanczos_dim`` steps, C inner product) at that s estimates it
   from below (Ritz values never exceed the extreme eigenvalue), and the pole ``sigma``
   is the first of ``omega_est + 1e-6 |omega_est|`` and ``omega_est + (s - omega_est)
   / 8^k``, k = 4, 3, 2, 1 (:data:`POLE_FRACTIONS`), that a Cholesky *verifies* (else s
   itself). So, rigorously, no eigenvalue lies to the right of ``sigma``, and
   ``A + sigma C`` (positive definite symmetric part) is nonsingular. On the parameter
   ranges of the paper omega lies within a factor ~2 of the rightmost eigenvalue's real
   part, which makes it a good pole.
2. **Shift-invert Arnoldi.** Arnoldi (classical Gram-Schmidt with reorthogonalisation)
   on ``S = (A + sigma C)^{-1} C`` using the pivoted block LU of :mod:`axojax.linalg`;
   Ritz values ``theta`` give ``lambda = sigma - 1/theta``. Every solve takes one step
   of iterative refinement: the links make ``|A|`` ~1e8 times the eigenvalues of
   interest; at 40 elements (seven, p = 300, ks = 1e6) the eigenvalue is 1.1e-11 from
   the true one with it and 1.4e-10 to 8.5e-10 without (the dense solver: 1.8e-10; true:
   Newton with extended-precision residuals, ``tests/eigen/test_solvers.py``). It costs
   1.1-1.2x per point. The stiff bulk of the spectrum (|lambda| up to ~1e8 from the
   links) maps to theta ~ 0, so the eigenvalues near sigma converge in a few dozen
   steps. A Ritz pair has converged when its residual bound ``|h_{m+1,m} y_m| /
   |theta|^2 <= tol (1 + |lambda|)``. The Krylov space grows in stages (``krylov_dims``,
   default 12, 16, 24, 32, 48 vectors) until the certificate holds. Per-point path (the
   CPU default): under ``jax.vmap`` the points run one after another, so that no point
   pays for another's stages, with LAPACK's small kernels; each step orthogonalises
   against its stage's rows only (measured 1.0-1.15x faster at 10-80 elements than
   against all 49 rows), and each stage's projected eigen-problem has its own size (each
   stage adds ~0.2 s of compilation: more stages were measured to cost more than they
   save).
   Batched path (``ArnoldiOptions.batched``, the default on accelerators): one
   ``vmap`` over the chunk, the block factorisations in plain jnp
   (:mod:`axojax.linalg.small`, no LAPACK custom calls), every point running its
   batch's stages; the projected m x m eigen-problems (``eigh`` of the Lanczos matrix,
   ``eig`` of the Hessenberg matrix) stay library calls, batched.
3. **Certificate** (Cayley view, Meerbergen, Spence & Roose, BIT 34, 1994). The Cayley
   transform ``(A + sigma C)^{-1} (A + alpha C)`` has the same Krylov space as S and maps
   the half-plane right of the line ``(sigma + alpha)/2`` outside the unit disc; in S's
   terms, eigenvalues are resolved from the pole outwards. The returned eigenvalue
   lambda_r (the converged one of largest real part) is *certified* when every Ritz value
   that has not converged lies farther from sigma than ``certify_factor * |sigma -
   lambda_r|``: then every eigenvalue within that radius has been found (the standard
   Krylov assumption: the start vector is not deficient in it), none of them lies to the
   right of lambda_r, and none at all lies to the right of sigma. A missed eigenvalue
   right of lambda_r would have to be at least that far from the pole, i.e. oscillate
   far faster than the dominant mode.
   The *right disc* (:func:`_right_disc`) is a second certificate, tried when the pole's
   disc fails: the outside of a disc of theta's plane about a real centre ``theta_c > 0``
   instead of 0 (a Cayley transform with another alpha: the same Krylov space), i.e. a
   disc of the lambda plane that holds every point of the pole's disc with ``Re lambda >=
   Re lambda_r`` and reaches only a little left of lambda_r. It makes the same statement
   about the eigenvalues that could be to the right of lambda_r and none about those to
   its left, where strong dynamic sliding control (chi'' ~ 1e6 to 1e7) crowds overdamped
   modes on the real axis whose Ritz values converge slowly. Seven filaments at 10
   elements, chi' = 0 to 1e5 pN/um^2 with chi'' = 0, chi' or 3 chi' at 30 Hz (p 100-1000,
   ks 1e4 / 1e6; 252 points): 249 certify against 231 with the pole's disc alone, every
   one equal to the dense solver's eigenvalue to 4e-11; the three left (chi' >= 2e4) have
   dozens of modes within a quarter of ``|sigma - lambda_r|`` left of lambda_r.
   Points that no stage certifies are solved by the dense solver (only those points) and
   report ``certified = 0``.
4. **Derivatives** (custom JVP, no eigen-decomposition, :mod:`axojax.eigen.tangent`):
   ``(A + lambda C) dv + dlambda C v = -(dA + lambda dC) v``, ``v^H dv = 0``, a bordered
   system solved with one complex block LU just off lambda (packed: no block inverses
   on the per-point path) in two passes, the first with two right-hand sides; reverse
   mode solves the transposed system with the same factors. No left eigenvector is
   formed. Assumes a simple dominant eigenvalue: for degenerate ones (e.g.
   out_of_plane = 1 on a symmetric cross-section) use the dense solver, whose
   derivative handles clusters.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import jax
import jax.numpy as jnp
from jaxtyping import Array, Complex, Float

from ..linalg import (
    BlockTridiagonal,
    Bordered,
    arnoldi_steps,
    bordered,
    bordered_cholesky,
    bordered_lu,
)
from . import deflation
from .dominant import CLUSTER_RTOL, dominant_eigenpair, normalise
from .pencil import SYMMETRY_RTOL
from .tangent import eigenpair_tangent

TRIAL_POLES = 9
"""Trial poles 8^k - 1, k < 9: numerical abscissae up to ~1.7e7 are bracketed."""

FIRST_TRIAL = 5
"""The trial pole tried first (8^5 - 1 = 32767): the numerical abscissa of the
seven-filament model lies between 4095 and 2.6e5 on most of the paper's parameter range
(any value gives the same pole; a good guess saves factorisations)."""


POLE_FRACTIONS = (0.0, 8.0**-4, 8.0**-3, 8.0**-2, 8.0**-1)
"""Where between the Lanczos estimate of the abscissa (0) and the bracketing trial pole
(1) the pole is verified, in turn (the first candidate adds 1e-6 relative)."""


class ArnoldiOptions(NamedTuple):
    """Static options of :func:`structured_dominant` (see :class:`axojax.eigen.Arnoldi`)."""

    krylov_dims: tuple[int, ...] = (12, 16, 24, 32, 48)
    lanczos_dim: int = 12
    certify_factor: float = 2.0
    tol: float = 1e-10
    fallback: bool = True
    batched: bool = False
    deflated: int = 0
    """The pencil's last ``deflated`` border unknowns carry a rigid-body deflation
    (:mod:`axojax.eigen.deflation`): the pole is found without them, and the dense
    fallback eliminates them."""


def _start_vector(n: int, dtype=float) -> Array:
    k = jnp.arange(n, dtype=float)
    return (jnp.sin(1.3 * k + 0.4) + jnp.cos(0.71 * k) + 0.1).astype(dtype)


def _symmetric_part_neg(A: Bordered) -> Bordered:
    """G = -(A + A^T) / 2."""
    return (A + A.T).scale(-0.5)


def _symmetric(C: Bordered) -> Array:
    """Whether C is symmetric (to :data:`axojax.eigen.pencil.SYMMETRY_RTOL`): the pole's
    bound holds only then. The friction parts of regulated dynein (beta''/omega0) make C
    non-symmetric; such points are not certified and go to the dense solver."""
    return (C + C.T.scale(-1.0)).max_abs() <= SYMMETRY_RTOL * C.max_abs()


def pole(
    A: Bordered, C: Bordered, lanczos_dim: int, kernels: str = "lapack"
) -> tuple[Float[Array, ""], Array]:
    """A real pole sigma with ``sigma C - G`` positive definite (G the symmetric part of
    -A), close above the numerical abscissa omega. Returns (sigma, verified)."""
    G = _symmetric_part_neg(A)

    def factor(s):
        return bordered_cholesky(C.scale(s) - G, kernels)

    # Trial poles s_k = 8^k - 1, k = 0, ..., TRIAL_POLES - 1 (0, 7, 63, 511, ...): the
    # smallest that passes lies within a factor ~8 above omega when omega > 0; s = 0
    # passes when every mode is damped. Passing is monotone in s (s C - G is positive
    # definite exactly for s > omega), so the smallest passing trial is found by search:
    # first FIRST_TRIAL, then its neighbour, then bisection (2 factorisations at the
    # usual abscissae, at most ~5), instead of trying every trial from k = 0 upwards.
    # Invariant: trial lo fails (or lo = -1), trial hi passes (or hi = TRIAL_POLES: none
    # known to pass); ``chol`` is the factor of trial hi.
    def next_trial(lo, hi, count):
        neighbour = jnp.where(hi == FIRST_TRIAL, hi - 1, lo + 1)
        return jnp.where(count == 0, FIRST_TRIAL, jnp.where(count == 1, neighbour, (lo + hi) // 2))

    def cond(state):
        lo, hi, _, _ = state
        return hi - lo > 1

    def body(state):
        lo, hi, count, chol = state
        k = next_trial(lo, hi, count)
        trial = factor(8.0**k - 1.0)
        chol = jax.tree.map(lambda new, old: jnp.where(trial.ok, new, old), trial, chol)
        return jnp.where(trial.ok, lo, k), jnp.where(trial.ok, k, hi), count + 1, chol

    # The loop starts from a failed stand-in so that one compiled factorisation serves
    # every trial.
    failed = jax.tree.map(
        lambda x: jnp.zeros(x.shape, bool) if x.dtype == bool else jnp.full(x.shape, jnp.nan),
        jax.eval_shape(factor, 0.0),
    )
    _, k, _, chol = jax.lax.while_loop(cond, body, (-1, TRIAL_POLES, 0, failed))
    s = 8.0 ** jnp.minimum(k, TRIAL_POLES - 1) - 1.0
    found = chol.ok
    # Shift-invert Lanczos on T = (s C - G)^{-1} C, self-adjoint in the C inner product.
    n = A.shape[0]
    m = lanczos_dim
    q0 = _start_vector(n)
    q0 = q0 / jnp.sqrt(q0 @ C.matvec(q0))
    Q = jnp.zeros((m + 1, n)).at[0].set(q0)
    P = jnp.zeros((m + 1, n)).at[0].set(C.matvec(q0))  # P = C Q: C inner products are P @ w
    T = jnp.zeros((m + 1, m))

    def lanczos(j, carry):
        Q, P, T = carry
        w = chol.solve(P[j])
        for _ in range(2):  # full reorthogonalisation in the C inner product
            h = P @ w
            w = w - Q.T @ h
            T = T.at[:, j].add(h)
        Cw = C.matvec(w)
        beta = jnp.sqrt(jnp.maximum(w @ Cw, 0.0))
        inv = 1.0 / jnp.where(beta > 0, beta, 1.0)
        return Q.at[j + 1].set(w * inv), P.at[j + 1].set(Cw * inv), T.at[j + 1, j].set(beta)

    Q, P, T = jax.lax.fori_loop(0, m, lanczos, (Q, P, T))
    Tm = (T[:m] + T[:m].T) / 2
    theta, Y = jnp.linalg.eigh(Tm)
    top = theta[-1] + jnp.abs(
        T[m, m - 1] * Y[-1, -1]
    )  # >= the largest eigenvalue of T once it has converged
    omega = s - 1.0 / jnp.maximum(top, 1e-300)
    # Ritz values of Lanczos underestimate the largest eigenvalue of T, so omega can lie
    # below the abscissa when the Lanczos has not converged (poles far above it separate
    # the eigenvalues of T poorly). Verify omega + 1e-6 |omega|, then points from omega
    # towards s (POLE_FRACTIONS of the gap), and keep the first that passes (else s).
    fractions = jnp.asarray(POLE_FRACTIONS)
    gap = jnp.maximum(s - omega, 0.0)

    def candidate(i):
        return jnp.where(i == 0, omega + 1e-6 * (jnp.abs(omega) + 1.0), omega + fractions[i] * gap)

    def untested(state):
        i, ok = state
        return (~ok) & (i < len(POLE_FRACTIONS))

    def test(state):
        i, _ = state
        c = candidate(i)
        return i + 1, factor(c).ok & (c < s)

    i, ok = jax.lax.while_loop(untested, test, (0, jnp.zeros((), bool)))
    sigma = jnp.where(ok, candidate(i - 1), s)
    return sigma, found


class _Primal(NamedTuple):
    eigenvalue: Complex[Array, ""]
    vector: Complex[Array, " n"]
    certified: Float[Array, ""]


def _ritz(
    V, H, sigma, m, opts: ArnoldiOptions, padded: bool = False, nearest: bool = False
) -> _Primal:
    """Rightmost converged Ritz pair of the first m Arnoldi steps and its certificate
    (``nearest``: the converged one nearest the pole sigma, real or complex, with its
    sign of Im kept; the same certificate).

    ``padded`` off: ``m`` is static, and the eigen-problem is the leading m x m block of
    H (the per-point path compiles one per stage, each of its own size: LAPACK's
    Hessenberg QR costs ~m^3, and a zero-padded matrix of the largest stage's size cost
    up to several times more). On (the batched path, where a ``switch`` between stages
    would run every branch): ``m`` may be traced, the leading m x m block is embedded in
    a zero matrix of the full size, one compiled eigen-solve serving every stage; the
    padding gives theta = 0 with zero residual, i.e. lambda at minus infinity, which
    never competes."""
    if padded:
        m_max = H.shape[1]
        k = jnp.arange(m_max)
        Hm = jnp.where((k[:, None] < m) & (k[None, :] < m), H[:m_max, :m_max], 0.0)
        basis = V[:m_max]
    else:
        Hm = H[:m, :m]
        basis = V[:m]
    theta, Y = jnp.linalg.eig(Hm)
    Y = Y / jnp.linalg.norm(Y, axis=0)
    residual = jnp.abs(H[m, m - 1] * Y[m - 1])
    padding = theta == 0  # a breakdown of the Arnoldi process leaves zero rows
    safe_theta = jnp.where(padding, 1.0, theta)
    lam = jnp.where(padding, -jnp.inf, sigma - 1.0 / safe_theta)
    converged = (
        residual / jnp.abs(safe_theta) ** 2 <= opts.tol * (1.0 + jnp.abs(lam))
    ) & jnp.isfinite(lam)
    score = jnp.abs(theta) if nearest else jnp.real(lam)  # |theta| = 1 / |sigma - lambda|
    i = jnp.argmax(jnp.where(converged, score, -jnp.inf))
    lam_r = lam[i]
    # Cluster mean, as the dense solver reports degenerate eigenvalues.
    near = converged & (jnp.abs(lam - lam_r) <= CLUSTER_RTOL * (1.0 + jnp.abs(lam_r)))
    lam_c = jnp.sum(jnp.where(near, lam, 0.0)) / jnp.maximum(jnp.sum(near), 1)
    x = basis.T.astype(Y.dtype) @ Y[:, i]
    if not nearest:
        flip = jnp.imag(lam_c) < 0
        lam_c = jnp.where(flip, jnp.conj(lam_c), lam_c)
        x = jnp.where(flip, jnp.conj(x), x)
    unresolved = jnp.where(converged | padding, 0.0, jnp.abs(theta))
    radius = 1.0 / jnp.maximum(jnp.max(unresolved), 1e-300)
    certified = radius >= opts.certify_factor * jnp.abs(sigma - lam_r)
    if not nearest:
        free = ~(converged | padding)
        certified = certified | _right_disc_certified(lam, free, sigma, lam_r, opts.certify_factor)
    certified = jnp.any(converged) & certified
    return _Primal(lam_c, normalise(x), certified.astype(float))


RIGHT_DISC_MARGINS = (1.0, 0.25)
"""How far left of ``Re lambda_r`` the right discs reach (:func:`_right_disc`), as
fractions of ``sigma - Re lambda_r`` (at least a quarter of ``|sigma - lambda_r|``)."""


def _right_disc(sigma, lam_r, factor, margin) -> tuple[Array, Array]:
    """Centre (real) and radius of a *right* disc of the certificate: the smallest disc
    in the lambda plane with its leftmost point ``m = max(margin (sigma - Re lambda_r),
    |sigma - lambda_r| / 4)`` left of ``Re lambda_r`` that holds every point of the pole's
    disc (centre sigma, radius ``factor |sigma - lambda_r|``) with ``Re lambda >= Re
    lambda_r`` and has its centre at or right of sigma. Under ``theta = 1 / (sigma -
    lambda)`` it is the outside of a disc about a real centre ``theta_c``: the pole's disc
    is the case ``theta_c = 0``."""
    d = jnp.abs(sigma - lam_r)
    a = sigma - jnp.real(lam_r)
    r0 = factor * d
    m = jnp.maximum(margin * a, 0.25 * d)
    x0 = jnp.real(lam_r) - m
    h2 = jnp.maximum(r0**2 - a**2, 0.0)  # half-chord^2 of the pole's disc at Re lambda_r
    rho = jnp.maximum((h2 + m**2) / (2.0 * m), jnp.maximum(sigma - x0, (sigma + r0 - x0) / 2))
    return x0 + rho, rho


def _right_disc_certified(lam, free, sigma, lam_r, factor) -> Array:
    """The certificate with a right disc (:func:`_right_disc`, each of
    :data:`RIGHT_DISC_MARGINS`) in place of the pole's: every Ritz value that has not
    converged lies outside it. Krylov spaces do not depend on a shift of the operator, so
    the standard assumption (the Ritz values outside a disc of theta's plane are resolved
    first) holds about ``theta_c`` as it does about 0, and the statement it gives about
    eigenvalues right of lambda_r is the pole disc's: every eigenvalue within ``factor
    |sigma - lambda_r|`` of sigma with ``Re lambda >= Re lambda_r`` has been found. What it
    leaves out is the region left of lambda_r, where strong dynamic sliding control
    (chi'' ~ 1e6) crowds overdamped modes whose Ritz values converge slowly and kept the
    pole's disc from certifying (docs/benchmarks.md)."""

    def clear(margin):
        centre, rho = _right_disc(sigma, lam_r, factor, margin)
        return ~jnp.any(free & (jnp.abs(lam - centre) <= rho))

    return jnp.any(jnp.stack([jnp.zeros((), bool)] + [clear(m) for m in RIGHT_DISC_MARGINS]))


def _dense_primal(A: Bordered, C: Bordered, deflated: int = 0) -> _Primal:
    if deflated:
        lam, v = deflation.dense_eigenpair(A, C, deflated)
    else:
        lam, v = dominant_eigenpair(A.to_dense(), C.to_dense())
    return _Primal(lam, v, jnp.zeros(()))


def staged_arnoldi(
    M: Bordered, lu, C: Bordered, sigma, dims: tuple[int, ...], ritz, batched: bool, dtype
) -> _Primal:
    """Shift-invert Arnoldi on ``(A + sigma C)^{-1} C`` (``M = A + sigma C`` factorised as
    ``lu``) in stages of ``dims`` Krylov vectors until ``ritz`` certifies a pair: the
    common core of the dominant solver (real pole) and :mod:`axojax.eigen.arnoldi_nearest`
    (complex shift). ``ritz(V, H, sigma, m, padded=...)`` picks and certifies the pair;
    ``dtype`` is the Krylov vectors' (float, or complex for a complex shift)."""
    n = M.shape[0]
    m_max = dims[-1]
    v0 = _start_vector(n, dtype)
    V = jnp.zeros((m_max + 1, n), dtype).at[0].set(v0 / jnp.linalg.norm(v0))
    H = jnp.zeros((m_max + 1, m_max), dtype)

    def shift_invert(v):
        """(A + sigma C)^{-1} C v: the solve, then one step of iterative refinement, as
        two passes through one compiled solve (from w = 0 the first is the plain solve;
        one loop costs less to compile than a second copy of the solve)."""
        b = C.matvec(v)

        def refine(i, w):
            # The first pass skips the product M @ 0 (a cond on the loop index, which
            # ``vmap`` leaves a cond).
            r = jax.lax.cond(i > 0, lambda: b - M.matvec(w), lambda: b)
            return w + lu.solve(r)

        return jax.lax.fori_loop(0, 2, refine, jnp.zeros_like(b))

    starts = jnp.asarray((0,) + dims[:-1])
    ends = jnp.asarray(dims)

    def cond(state):
        stage, _, _, result = state
        return (stage < len(dims)) & (result.certified < 0.5)

    def body(state):
        stage, V, H, _ = state
        # Per point, each stage orthogonalises against its own rows only; vmapped (the
        # batched path), a switch on the step would run every window.
        V, H = arnoldi_steps(
            shift_invert, V, H, starts[stage], ends[stage], windows=() if batched else dims
        )
        if batched:
            result = ritz(V, H, sigma, ends[stage], padded=True)
        else:
            result = jax.lax.switch(
                stage, [functools.partial(ritz, m=m) for m in dims], V, H, sigma
            )
        return stage + 1, V, H, result

    empty = _Primal(jnp.zeros((), complex), jnp.zeros((n,), complex), jnp.zeros(()))
    _, _, _, result = jax.lax.while_loop(cond, body, (0, V, H, empty))
    return result


def _arnoldi_point(
    A: Bordered, C: Bordered, opts: ArnoldiOptions, batched: bool = False
) -> _Primal:
    """One parameter point: pole, factorisation, Arnoldi in stages until certified, and
    the dense solver where no stage certifies (``opts.fallback``). Scalar control flow:
    each stage and the fallback run only when needed.

    ``batched``: written to be ``vmap``-ed over a chunk of points (see :func:`_batched`):
    plain jnp block kernels (:mod:`axojax.linalg.small`), no fallback here (the caller
    runs it for the uncertified points only)."""
    n = A.shape[0]
    dims = tuple(sorted({min(m, n - 1) for m in opts.krylov_dims}))
    kernels = "jnp" if batched else "lapack"
    # With a rigid-body deflation the pole is the original pencil's: every finite
    # eigenvalue of the extended one is one of its eigenvalues, or a rigid mode moved left.
    r = opts.deflated
    A0, C0 = (deflation.truncate(A, r), deflation.truncate(C, r)) if r else (A, C)
    sigma, verified = pole(A0, C0, opts.lanczos_dim, kernels)
    M = A + C.scale(sigma)
    lu = bordered_lu(M, kernels)
    result = staged_arnoldi(
        M, lu, C, sigma, dims, functools.partial(_ritz, opts=opts), batched, float
    )
    result = result._replace(certified=result.certified * verified * _symmetric(C))
    if batched or not opts.fallback:
        return result
    return jax.lax.cond(
        result.certified > 0.5, lambda _: result, lambda _: _dense_primal(A, C, r), None
    )


def _batched_points(A: Bordered, C: Bordered, opts: ArnoldiOptions) -> _Primal:
    """The batched path over a chunk of points (leading axis of A and C): one ``vmap``
    of :func:`_arnoldi_point` (every block operation one batched jnp operation; a point
    that certifies early idles through its batch's remaining stages), then the dense
    fallback for the uncertified points only (one after another, and not at all when
    every point is certified)."""
    out = jax.vmap(lambda a, c: _arnoldi_point(a, c, opts, batched=True))(A, C)
    if not opts.fallback:
        return out

    def fix(args):
        r, a, c = args
        return jax.lax.cond(
            r.certified > 0.5, lambda: r, lambda: _dense_primal(a, c, opts.deflated)
        )

    return jax.lax.cond(
        jnp.all(out.certified > 0.5), lambda: out, lambda: jax.lax.map(fix, (out, A, C))
    )


def per_point_vmap(point, batched_points, batched: bool):
    """``point`` (a function of one parameter point's arrays) with its own ``vmap`` rule.
    ``batched`` off (the per-point path): the points run one after another
    (``lax.map``), every point with its own stages and fallback, where a vmapped
    ``while``/``cond`` would make each point pay for the slowest of its batch. On:
    ``batched_points`` (the same arguments with a leading batch axis)."""

    @jax.custom_batching.custom_vmap
    def one(*args):
        return point(*args)

    @one.def_vmap
    def rule(axis_size, in_batched, *args):
        def full(x, flag):
            return x if flag else jnp.broadcast_to(x, (axis_size,) + jnp.shape(x))

        args = tuple(jax.tree.map(full, a, flags) for a, flags in zip(args, in_batched))
        if batched:
            out = batched_points(*args)
        else:
            out = jax.lax.map(lambda xs: one(*xs), args)
        return out, jax.tree.map(lambda _: True, out)

    return one


@functools.lru_cache(maxsize=None)
def _batched(opts: ArnoldiOptions):
    """:func:`_arnoldi_point` with its own ``vmap`` rule (:func:`per_point_vmap`; the
    batched path is :func:`_batched_points`)."""
    return per_point_vmap(
        lambda A, C: _arnoldi_point(A, C, opts),
        lambda A, C: _batched_points(A, C, opts),
        opts.batched,
    )


def structured_dominant(
    A: Bordered | BlockTridiagonal, C: Bordered | BlockTridiagonal, opts: ArnoldiOptions
) -> tuple[Complex[Array, ""], Complex[Array, " n"], Float[Array, ""]]:
    """Dominant eigenvalue (Im >= 0), unit eigenvector (node-major, then the border) and
    certificate (1.0 certified; 0.0 recomputed densely, or not certified when
    ``opts.fallback`` is off) of the block-tridiagonal pencil, bordered or not (see
    :func:`pencil_of`). Differentiable in A and C (module docstring). Under ``jax.vmap``
    the points are solved one after another (see :func:`_batched`)."""
    return _structured_dominant(bordered(A), bordered(C), opts)


@functools.partial(jax.custom_jvp, nondiff_argnums=(2,))
def _structured_dominant(A: Bordered, C: Bordered, opts: ArnoldiOptions):
    return tuple(_batched(opts)(A, C))


@_structured_dominant.defjvp
def _structured_jvp(opts, primals, tangents):
    A, C = primals
    dA, dC = tangents
    lam, x, certified = _structured_dominant(A, C, opts)
    dlam, dx = eigenpair_tangent(A, C, dA, dC, lam, x, opts.batched)
    return (lam, x, certified), (dlam, dx, jnp.zeros_like(certified))
