"""The Arnoldi process, shared by the eigen-solver (:mod:`axojax.eigen.arnoldi`) and the
Floquet multipliers of periodic orbits (:mod:`axojax.orbits.floquet`)."""

from __future__ import annotations

import functools
from collections.abc import Callable

import jax
import jax.numpy as jnp
from jaxtyping import Array, Inexact


def arnoldi_steps(
    op: Callable[[Inexact[Array, " N"]], Inexact[Array, " N"]],
    V: Inexact[Array, "k1 N"],
    H: Inexact[Array, "k1 k"],
    start,
    stop,
    windows: tuple[int, ...] = (),
) -> tuple[Inexact[Array, "k1 N"], Inexact[Array, "k1 k"]]:
    """Arnoldi steps j = start, ..., stop - 1 extending ``op V[:j] = V[:j+1] H[:j+1, :j]``.

    Classical Gram-Schmidt, twice, against the rows of V reached so far: rows not yet
    reached must be zero (start from ``V = zeros.at[0].set(unit start vector)``,
    ``H = zeros``). A breakdown (a zero new vector) leaves a zero row. ``start``/``stop``
    may be traced, so that the space can grow in stages. Real or complex arithmetic
    (Hermitian inner products; for real V the conjugation is a no-op).

    ``windows``: static row counts; step j orthogonalises against the first rows of the
    smallest window above j (rows beyond j are zero), so that a space grown in stages
    costs in proportion to its size, not to V's. ``V.shape[0]`` is always a window (by
    default the only one: every row).
    """
    if any(not 0 < r <= V.shape[0] for r in windows):
        raise ValueError(f"windows must be row counts in 1..{V.shape[0]}, got {windows}")
    windows = tuple(sorted(set(windows) | {V.shape[0]}))
    bounds = jnp.asarray(windows)

    def orthogonalise(r, V, w):
        Vr = V[:r]
        h = jnp.zeros(r, w.dtype)
        for _ in range(2):
            c = jnp.conj(Vr) @ w
            w = w - Vr.T @ c
            h = h + c
        return w, jnp.zeros(V.shape[0], w.dtype).at[:r].set(h)

    branches = [functools.partial(orthogonalise, r) for r in windows]

    def step(j, carry):
        V, H = carry
        w = op(V[j])
        which = jnp.minimum(jnp.searchsorted(bounds, j, side="right"), len(windows) - 1)
        w, h = jax.lax.switch(which, branches, V, w)
        H = H.at[:, j].add(h)
        beta = jnp.linalg.norm(w)
        H = H.at[j + 1, j].set(beta)
        V = V.at[j + 1].set(w / jnp.where(beta > 0, beta, 1.0))
        return V, H

    return jax.lax.fori_loop(start, stop, step, (V, H))
