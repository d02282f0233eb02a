"""The Arnoldi process, shared by the eigen-solver (:mod:`axojax.eigen.arnoldi`) and the
Floquet multipliers of periodic orbits (:mod:`axojax.orbits.floquet`)."""

from __future__ import annotations

import functools
from collections.abc import Callable

import jax
import jax.numpy as jnp
from jaxtyping import Array, Float


def arnoldi_steps(
    op: Callable[[Float[Array, " N"]], Float[Array, " N"]],
    V: Float[Array, "k1 N"],
    H: Float[Array, "k1 k"],
    start,
    stop,
    rows: tuple[int, ...] | None = None,
) -> tuple[Float[Array, "k1 N"], Float[Array, "k1 k"]]:
    """Arnoldi steps j = start, ..., stop - 1 extending ``op V[:j] = V[:j+1] H[:j+1, :j]``.

    Classical Gram-Schmidt, twice, against every row of V: rows not yet reached must be
    zero (start from ``V = zeros.at[0].set(unit start vector)``, ``H = zeros``). A
    breakdown (a zero new vector) leaves a zero row. ``start``/``stop`` may be traced, so
    that the space can grow in stages. Real arithmetic.

    ``rows``: increasing static row counts (the last one V's); step j then orthogonalises
    against the first ``r`` rows of V only, r the smallest of them above j (the rest are
    still zero), chosen by ``lax.switch``, which saves most of the Gram-Schmidt work of
    the first stages. For code that runs unbatched: under ``vmap`` a switch runs every
    branch.
    """
    k1 = V.shape[0]

    def orthogonalise(r, V, w):
        Vr = V[:r]
        h = jnp.zeros((r,), w.dtype)
        for _ in range(2):
            g = Vr @ w
            w = w - Vr.T @ g
            h = h + g
        return w, jnp.zeros((k1,), w.dtype).at[:r].set(h)

    def step(j, carry):
        V, H = carry
        w = op(V[j])
        if rows is None:
            w, h = orthogonalise(k1, V, w)
        else:
            branches = [functools.partial(orthogonalise, r) for r in rows]
            w, h = jax.lax.switch(jnp.searchsorted(jnp.asarray(rows), j + 1), branches, V, w)
        H = H.at[:, j].add(h)
        beta = jnp.linalg.norm(w)
        H = H.at[j + 1, j].set(beta)
        V = V.at[j + 1].set(w / jnp.where(beta > 0, beta, 1.0))
        return V, H

    return jax.lax.fori_loop(start, stop, step, (V, H))
