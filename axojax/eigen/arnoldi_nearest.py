"""The eigenpair of a block-tridiagonal pencil nearest a complex shift, by certified
shift-invert Arnoldi (the structured counterpart of :mod:`axojax.eigen.nearest`).

Problem: ``(A + lambda C) v = 0`` with A, C block-tridiagonal (node-major), optionally
with a border of extra unknowns (:class:`axojax.linalg.Bordered`); wanted: the
eigenvalue nearest a given shift ``sigma`` (the beat of a regulated mechanism at
``i omega0``), and a statement that none lies nearer.

Unlike the dominant eigenvalue (:mod:`axojax.eigen.arnoldi`) no pole has to be placed:
the shift is the pole. So nothing is assumed of C (non-symmetric with beta''/omega0,
indefinite with chi'' < 0): only that ``A + sigma C`` is nonsingular, i.e. that sigma
is not itself an eigenvalue.

Algorithm (per parameter point, fixed shapes: jit/vmap-able; the same stages, options,
per-point and batched paths as the dominant solver):

1. One complex pivoted block LU of ``A + sigma C`` (:func:`axojax.linalg.bordered_lu`:
   the border by its Schur complement; per point in LAPACK's packed form, half the
   cost of the block inverses); every shift-invert solve takes one step of iterative
   refinement, as the dominant solver's (real A and C act on the complex vectors as two
   real products).
2. Arnoldi (complex, Hermitian Gram-Schmidt twice) on ``S = (A + sigma C)^{-1} C``; Ritz
   values theta give ``lambda = sigma - 1/theta``; the eigenvalue nearest sigma has the
   largest |theta|. Convergence test as the dominant solver's. Per point the stages
   start small (:data:`FIRST_DIMS`, then ``krylov_dims``): a shift near the eigenvalue
   certifies within 6-8 vectors.
3. Certificate: the returned eigenvalue lambda_r (the converged one nearest sigma) is
   certified when every Ritz value that has not converged lies farther from sigma than
   ``certify_factor * |sigma - lambda_r|``: every eigenvalue within that radius has then
   been resolved (the standard Krylov assumption: the start vector is not deficient in
   it), and none of them is nearer sigma than lambda_r. Points no stage certifies (and
   points where the factorisation is singular) are solved by the dense
   :func:`~axojax.eigen.nearest.nearest_eigenpair` and report ``certified = 0``.
4. Derivatives: the dominant solver's rule (:func:`axojax.eigen.tangent.eigenpair_tangent`:
   one bordered system on a packed complex block LU just off lambda); the shift only
   selects, its tangent is ignored.
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Complex, Float

from ..linalg import BlockTridiagonal, Bordered, bordered, bordered_lu
from .arnoldi import (
    ArnoldiOptions,
    _Primal,
    _ritz,
    eigenpair_tangent,
    per_point_vmap,
    staged_arnoldi,
)
from .nearest import nearest_eigenpair

FIRST_DIMS = (6, 8)
"""Krylov sizes checked before ``krylov_dims``' first (per-point path only): with the
shift near the eigenvalue, as in a fit that pins the beat, the eigenvalue converges and
certifies in a few steps (seven filaments, 10 elements, the shift 0.1 / 1 / 3 / 10 % of
|lambda| from it: every point certified at 4 / 6 / 8 / 12 vectors). A stage that does
not certify costs only its small eigen-problem (the space grows on from it). The
batched path keeps ``krylov_dims``: there every stage is a full-size eigen-solve of the
whole batch."""


def _dense_nearest(A: Bordered, C: Bordered, shift) -> _Primal:
    lam, v = nearest_eigenpair(A.to_dense(), C.to_dense(), shift)
    return _Primal(lam, v, jnp.zeros(()))


def _nearest_point(
    A: Bordered, C: Bordered, shift: Complex[Array, ""], opts: ArnoldiOptions, batched=False
) -> _Primal:
    """One parameter point (see the module docstring). ``batched``: written to be
    ``vmap``-ed over a chunk (jnp kernels, no fallback here: :func:`_batched_points`)."""
    n = A.shape[0]
    first = () if batched else tuple(m for m in FIRST_DIMS if m < min(opts.krylov_dims))
    dims = tuple(sorted({min(m, n - 1) for m in first + opts.krylov_dims}))
    kernels = "jnp" if batched else "lapack"
    cdt = jnp.result_type(shift, A.tri.diag.dtype, jnp.complex64)
    sigma = jnp.asarray(shift, cdt)
    M = A.astype(cdt) + C.astype(cdt).scale(sigma)
    # Per point, T's factors stay packed (triangular solves, no block inverses): the
    # complex factorisation costs half as much (0.44 against 0.86 ms at seven
    # filaments, 10 elements) and the solves about as much: faster overall, measured
    # with the shift near the eigenvalue (8 vectors) and far from it (up to 48).
    lu = bordered_lu(M, kernels, packed=not batched)
    ritz = functools.partial(_ritz, opts=opts, nearest=True)
    result = staged_arnoldi(M, lu, C, sigma, dims, ritz, batched, cdt)
    finite = jnp.isfinite(result.eigenvalue) & jnp.all(jnp.isfinite(result.vector))
    result = result._replace(certified=result.certified * finite)
    if batched or not opts.fallback:
        return result
    return jax.lax.cond(result.certified > 0.5, lambda: result, lambda: _dense_nearest(A, C, sigma))


def _batched_points(A: Bordered, C: Bordered, shift, opts: ArnoldiOptions) -> _Primal:
    """The batched path over a chunk (leading axis): one ``vmap`` of
    :func:`_nearest_point`, then the dense fallback for the uncertified points only."""
    out = jax.vmap(lambda a, c, s: _nearest_point(a, c, s, opts, batched=True))(A, C, shift)
    if not opts.fallback:
        return out

    def fix(args):
        r, a, c, s = args
        return jax.lax.cond(r.certified > 0.5, lambda: r, lambda: _dense_nearest(a, c, s))

    return jax.lax.cond(
        jnp.all(out.certified > 0.5),
        lambda: out,
        lambda: jax.lax.map(fix, (out, A, C, shift)),
    )


@functools.lru_cache(maxsize=None)
def _batched(opts: ArnoldiOptions):
    return per_point_vmap(
        lambda A, C, s: _nearest_point(A, C, s, opts),
        lambda A, C, s: _batched_points(A, C, s, opts),
        opts.batched,
    )


def structured_nearest(
    A: Bordered | BlockTridiagonal,
    C: Bordered | BlockTridiagonal,
    shift: Complex[ArrayLike, ""],
    opts: ArnoldiOptions,
) -> tuple[Complex[Array, ""], Complex[Array, " n"], Float[Array, ""]]:
    """Eigenvalue nearest ``shift`` (cluster mean if degenerate), unit eigenvector
    (node-major, then the border; gauge as :func:`~axojax.eigen.dominant.normalise`) and
    certificate (1.0 certified; 0.0 recomputed densely, or not certified when
    ``opts.fallback`` is off). Differentiable in A and C; ``shift`` only selects."""
    A, C = bordered(A), bordered(C)
    shift = jnp.asarray(shift, jnp.result_type(shift, A.tri.diag.dtype, jnp.complex64))
    return _structured_nearest(A, C, shift, opts)


@functools.partial(jax.custom_jvp, nondiff_argnums=(3,))
def _structured_nearest(A: Bordered, C: Bordered, shift, opts: ArnoldiOptions):
    return tuple(_batched(opts)(A, C, shift))


@_structured_nearest.defjvp
def _nearest_jvp(opts, primals, tangents):
    A, C, shift = primals
    dA, dC, _ = tangents
    lam, x, certified = _structured_nearest(A, C, shift, opts)
    dlam, dx = eigenpair_tangent(A, C, dA, dC, lam, x, opts.batched)
    return (lam, x, certified), (dlam, dx, jnp.zeros_like(certified))
