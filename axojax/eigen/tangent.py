"""The derivative rule of a simple eigenpair of a (bordered) block-tridiagonal pencil,
shared by the structured solvers (:mod:`axojax.eigen.arnoldi`: the dominant eigenpair;
:mod:`axojax.eigen.arnoldi_nearest`: the one nearest a shift).

For ``(A + lambda C) v = 0`` and tangents (dA, dC), (dlambda, dv) solve the bordered
system ``(A + lambda C) dv + dlambda C v = -(dA + lambda dC) v``, ``v^H dv = 0``
(nonsingular exactly when lambda is simple; the gauge ``v^H dv = 0`` as before). One
complex block LU of ``A + lambda C`` just off lambda, then block elimination and one
step of iterative refinement (:func:`_bordered_solve`): two passes through the factors,
no left eigenvector. Reverse mode solves the transposed system with the same factors
(``lax.custom_linear_solve``), also in two passes.

Cost (seven filaments, 10 elements, one point): the LU kept packed and pivoted inside
each diagonal block only (:func:`axojax.linalg.lu_factor_local`, 0.38 ms; pivoting
across block rows, :func:`axojax.linalg.lu_factor_packed`, 0.61 ms; with the block
inverses the primal keeps for its dozens of solves, 1.28 ms): the refinement step below
uses B's exact residual, so the factors need only be good preconditioners, and the
derivatives agree with band pivoting's to every printed digit (1e-15 to 6e-12 against
an extended-precision dense solve, seven at p = 30-1000, 10 and 40 elements:
scripts/check_tangent_accuracy.py). The rule
before this one (inverse iteration for the left eigenvector, then a projected, refined
solve) made four passes.
Accuracy against a dense bordered solve refined in extended precision (seven, p =
30-1000, 10 and 40 elements; two with a free base): 1e-15 to 2e-10 relative, as good
as or better than that rule's 1e-12 to 4e-10 (``tests/eigen/test_tangent.py`` checks it
against scipy and finite differences).
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
from jaxtyping import Array, Complex

from ..linalg import Bordered, bordered_lu

NEAR_SHIFT = 1e-10
"""The derivative rule factors ``A + (lambda + NEAR_SHIFT (1 + |lambda|)) C``: just off
the eigenvalue, so that the bordered elimination's corrections shrink by about
``NEAR_SHIFT |lambda| / gap`` per step (the gap: the distance to the next eigenvalue)."""


def _near_factor(A: Bordered, C: Bordered, lam: Complex[Array, ""], kernels: str):
    """LU of ``A + shift C`` at a shift just off lambda (:data:`NEAR_SHIFT`), complex.
    On the per-point path packed and pivoted inside the diagonal blocks
    (:func:`axojax.linalg.lu_factor_local`: it is solved with only a few times, each
    solve refined, where the block inverses of the primal's factorisation would cost
    more than they save: 0.38 against 1.28 ms at seven filaments, 10 elements)."""
    cdt = jnp.result_type(lam, jnp.complex64)
    shift = lam + NEAR_SHIFT * (1.0 + jnp.abs(lam))
    M = A.astype(cdt) + C.astype(cdt).scale(shift)
    lapack = kernels == "lapack"
    return bordered_lu(M, kernels, packed=lapack, local=lapack)


def _bordered_solve(lu, A, C, lam, x, b, transpose: bool, restart: bool = False):
    """The bordered system of a simple eigenpair (lambda, x), ``K = A + lambda C``::

        B = [[K,   C x],        B [y; s] = [f; g]        (transpose: B^T, not conjugated)
             [x^H, 0  ]]

    nonsingular exactly when lambda is simple. Block elimination with ``lu``, the
    factors of K just off lambda (:func:`_near_factor`), whose solves are large along x
    (right) or the left eigenvector (transposed): both of the pass's solutions, ``u`` for
    the right-hand side and ``z`` for the border column, share that large part, which
    the elimination cancels (``y = u - s z``); then one step of iterative refinement with
    B's exact residual. Two passes through the factors in all (the first with two
    right-hand sides at once): no separate left eigenvector. ``b = (f, g)``.

    ``restart`` (the batched path, whose factors keep explicit block inverses, less
    accurate for a nearly singular matrix than triangular solves): the first pass gives
    s only; a second solves for y with ``f - s C x``, a right-hand side nearly in K's
    range (small parts to cancel), then the refinement: three passes. At 40 elements
    (seven, p = 280) the two-pass form there was 3e-9 from a dense bordered solve, this
    one 1e-9 (the packed per-point factors: 1e-11 in two passes)."""
    cdt = x.dtype
    K = A.astype(cdt) + C.astype(cdt).scale(lam)
    Cx = C.astype(cdt).matvec(x)
    if transpose:  # B^T = [[K^T, conj(x)], [(C x)^T, 0]]
        solve_k, col, row = lu.solve_transpose, jnp.conj(x), Cx
        apply_k = K.T.matvec
    else:
        solve_k, col, row = lu.solve, Cx, jnp.conj(x)
        apply_k = K.matvec
    f, g = b
    u, z = jax.vmap(solve_k)(jnp.stack([f.astype(cdt), col]))
    rz = row @ z

    def eliminate(u, g):
        s = (row @ u - g) / rz
        return u - s * z, s

    y, s = eliminate(u, g)
    if restart:
        y, t = eliminate(solve_k(f - s * col), g)
        s = s + t
    y2, s2 = eliminate(solve_k(f - apply_k(y) - s * col), g - row @ y)
    return y + y2, s + s2


_bordered_solve_seq = jax.custom_batching.sequential_vmap(
    lambda lu, A, C, lam, x, b: _bordered_solve(lu, A, C, lam, x, b, False)
)
_bordered_solve_t_seq = jax.custom_batching.sequential_vmap(
    lambda lu, A, C, lam, x, b: _bordered_solve(lu, A, C, lam, x, b, True)
)
# The per-point path: under vmap, the derivative rule's factorisation and solves run
# point by point too (LAPACK's kernels one matrix at a time, like the primal), where a
# vmapped complex LU and its scans were measured ~1.5x slower on CPU.
_near_factor_seq = jax.custom_batching.sequential_vmap(
    functools.partial(_near_factor, kernels="lapack")
)


def eigenpair_tangent(
    A: Bordered,
    C: Bordered,
    dA: Bordered,
    dC: Bordered,
    lam: Complex[Array, ""],
    x: Complex[Array, " n"],
    batched: bool,
) -> tuple[Complex[Array, ""], Complex[Array, " n"]]:
    """(dlambda, dx) of a simple eigenpair (lam, x) of the (bordered) pencil for the
    tangents (dA, dC): the bordered system (:func:`_bordered_solve`)
    ``(A + lambda C) dx + dlambda C x = -(dA + lambda dC) x``, ``x^H dx = 0``, by one
    complex LU just off lambda (:func:`_near_factor`) and two passes through it; reverse
    mode solves the transposed system with the same factors, also in two passes. Shared
    by the dominant (:func:`structured_dominant`) and the nearest
    (:mod:`axojax.eigen.arnoldi_nearest`) eigenpairs. ``batched``: the jnp kernels of
    the batched path, else LAPACK's, point by point under ``vmap``."""
    cdt = x.dtype
    if batched:
        lu = _near_factor(A, C, lam, "jnp")
        solve_ = functools.partial(_bordered_solve, transpose=False, restart=True)
        solve_t = functools.partial(_bordered_solve, transpose=True, restart=True)
    else:
        lu = _near_factor_seq(A, C, lam)
        solve_, solve_t = _bordered_solve_seq, _bordered_solve_t_seq
    Ac, Cc = A.astype(cdt), C.astype(cdt)
    Cx = Cc.matvec(x)

    def matvec(z):
        y, s = z
        return Ac.matvec(y) + lam * Cc.matvec(y) + s * Cx, jnp.vdot(x, y)

    dKx = dA.astype(cdt).matvec(x) + lam * dC.astype(cdt).matvec(x)
    # Linear in the right-hand side with a known transpose: reverse mode solves B^T with
    # the same factors instead of transposing the passes. The border's right-hand side
    # is zero, written as a product with the tangent so that it is linear in it too (as
    # the transposition of a linear solve needs).
    dx, dlam = jax.lax.custom_linear_solve(
        matvec,
        (-dKx, 0.0 * dKx[0]),
        lambda _, b: solve_(lu, A, C, lam, x, b),
        lambda _, b: solve_t(lu, A, C, lam, x, b),
    )
    dlam = jnp.where(jnp.imag(lam) == 0, jnp.real(dlam).astype(cdt), dlam)
    return dlam, dx
