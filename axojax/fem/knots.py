"""Filament-level matrices of non-uniform properties given at knots (docs/model.md section 8).

A traced profile v(x) = sum_k v_k h_k(x) is piecewise linear between K knots
0 = t_0 < t_1 < ... < t_{K-1} = 1 (h_k the hat function of knot k: 1 at t_k, 0 at the
other knots). Every filament-level matrix that a profile scales is linear in it, so it is
the sum of K static *knot matrices* times the traced values:

- EI(x):  ``K0 = sum_k v_k int h_k phi'' phi''^T``
- c(x):   ``M0 = sum_k v_k int h_k phi phi^T`` (the fluid drag only)
- p(x):   ``F0 = sum_k v_k int h_k phi phi'^T``, ``G0 = sum_k v_k int n_k phi' phi'^T``
  with ``n_k(x) = int_x^1 h_k``, and the static moment ``f1 = sum_k v_k int h_k phi'``.

The knot matrices are integrated exactly: each element is split at the knots inside it
and every piece gets its own Gauss rule (the integrands are polynomials there), so knots
need not sit on element boundaries. Values 1 at every knot give the uniform matrices.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np

from .hermite import _global_rows

KNOT_MATRICES = ("K0", "M0", "F0", "G0", "F0T")
"""The filament-level matrices that have knot versions (``F0T`` is F0's transpose)."""


class KnotMatrix(NamedTuple):
    """The name of one knot matrix, usable wherever a filament-level matrix's name is
    (:data:`axojax.assembly.Term`): ``matrix`` one of :data:`KNOT_MATRICES`, ``index`` the
    knot k, ``knots`` the knot positions (static)."""

    matrix: str
    index: int
    knots: tuple[float, ...]


def equally_spaced(n_knots: int) -> tuple[float, ...]:
    """K equally spaced knots on [0, 1] (K >= 2)."""
    return tuple(float(x) for x in np.linspace(0.0, 1.0, n_knots))


def check_knots(knots, what: str = "knots") -> tuple[float, ...]:
    """``knots`` as a tuple of floats, or a one-line ``ValueError`` naming ``what``: at
    least 2 positions, finite, strictly increasing, from 0 to 1."""
    try:
        t = np.asarray(knots, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"{what} must be numbers, got {knots!r}") from None
    if t.size < 2 or not np.all(np.isfinite(t)):
        raise ValueError(
            f"{what} must be at least 2 finite positions in [0, 1], got {t.tolist()!r}"
        )
    if t[0] != 0.0 or t[-1] != 1.0 or np.any(np.diff(t) <= 0):
        raise ValueError(f"{what} must increase strictly from 0 to 1 (x / L), got {t.tolist()!r}")
    return tuple(float(x) for x in t)


def hat_values(knots: tuple[float, ...], x: np.ndarray) -> np.ndarray:
    """(K, q) hat functions h_k at the points x."""
    eye = np.eye(len(knots))
    return np.stack([np.interp(x, knots, eye[k]) for k in range(len(knots))])


def hat_tails(knots: tuple[float, ...], x: np.ndarray) -> np.ndarray:
    """(K, q) n_k(x) = int_x^1 h_k(s) ds, exactly (h_k is linear between knots)."""
    t = np.asarray(knots)
    eye = np.eye(len(t))
    dt = np.diff(t)  # (K-1,)
    s = np.clip(np.asarray(x)[:, None] - t[None, :-1], 0.0, dt[None, :])  # (q, K-1)
    out = []
    for k in range(len(t)):
        left, right = eye[k, :-1], eye[k, 1:]
        # int_0^x h_k = sum over segments of int_{t_j}^{t_j + s_j} of the linear piece
        head = (left * s + (right - left) * s**2 / (2 * dt)).sum(axis=1)
        total = ((left + right) * dt / 2).sum()
        out.append(total - head)
    return np.stack(out)


def _split_rule(n_elements: int, knots: tuple[float, ...], points: int = 5):
    """Quadrature points and weights on [0, 1] with every element split at the knots
    inside it (Gauss-Legendre with ``points`` per piece: exact up to degree 2 points - 1)."""
    g, w = np.polynomial.legendre.leggauss(points)
    edges = np.union1d(np.linspace(0.0, 1.0, n_elements + 1), np.asarray(knots))
    left, h = edges[:-1], np.diff(edges)
    keep = h > 1e-14
    left, h = left[keep], h[keep]
    x = (left[:, None] + (g[None, :] + 1) / 2 * h[:, None]).ravel()
    weights = (w[None, :] / 2 * h[:, None]).ravel()
    return x, weights


@functools.lru_cache(maxsize=128)
def knot_matrices(
    n_elements: int, base_dofs: tuple[int, ...], knots: tuple[float, ...]
) -> dict[str, np.ndarray]:
    """Every knot matrix on the mesh of ``n_elements`` with node 0's ``base_dofs`` kept.

    Returns:
        ``{"K0", "M0", "F0", "G0", "F0T": (K, r, r), "f1": (K, r)}`` with r =
        len(base_dofs) + 2 N_e, K = len(knots); read-only arrays.
    """
    x, w = _split_rule(n_elements, knots)
    phi, dphi, ddphi = _global_rows(n_elements, x, base_dofs)
    h = hat_values(knots, x) * w[None, :]  # (K, q)
    n = hat_tails(knots, x) * w[None, :]
    out = {
        "K0": np.einsum("kq,qr,qs->krs", h, ddphi, ddphi),
        "M0": np.einsum("kq,qr,qs->krs", h, phi, phi),
        "F0": np.einsum("kq,qr,qs->krs", h, phi, dphi),
        "G0": np.einsum("kq,qr,qs->krs", n, dphi, dphi),
        "f1": np.einsum("kq,qr->kr", h, dphi),
    }
    out["F0T"] = np.ascontiguousarray(out["F0"].transpose(0, 2, 1))
    for a in out.values():
        a.flags.writeable = False
    return out


def knot_matrix(n_elements: int, base_dofs: tuple[int, ...], name: KnotMatrix) -> np.ndarray:
    """One knot matrix (r, r) (see :func:`knot_matrices`)."""
    return knot_matrices(n_elements, tuple(base_dofs), name.knots)[name.matrix][name.index]
