"""Cubic Hermite beam elements on x in [0, 1].

Nodal unknowns are (u, u') at nodes 1..N_e; node 0 (the base) is clamped (u = u' = 0)
and removed, so one filament direction has ``2 * N_e`` unknowns ordered
``[u_1, u'_1, u_2, u'_2, ..., u_Ne, u'_Ne]``. A base that is not clamped keeps some of
node 0's dofs (``base_dofs``: 0 for u(0), 1 for u'(0)); they come first, in that order
(``[u_0, u'_0, u_1, ...]`` for a free base, ``[u'_0, u_1, ...]`` for a pivot).
"""

from __future__ import annotations

import dataclasses

import numpy as np


def shape_functions(xi: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hermite shape functions and their x-derivatives on one element.

    Args:
        xi: local coordinate in [0, 1], shape (q,).
        h: element length.

    Returns:
        (N, dN/dx, d2N/dx2), each of shape (4, q), for the element dofs
        (u_left, u'_left, u_right, u'_right).
    """
    xi = np.asarray(xi, dtype=float)
    n = np.array(
        [
            1 - 3 * xi**2 + 2 * xi**3,
            h * (xi - 2 * xi**2 + xi**3),
            3 * xi**2 - 2 * xi**3,
            h * (-(xi**2) + xi**3),
        ]
    )
    dn = (
        np.array(
            [
                -6 * xi + 6 * xi**2,
                h * (1 - 4 * xi + 3 * xi**2),
                6 * xi - 6 * xi**2,
                h * (-2 * xi + 3 * xi**2),
            ]
        )
        / h
    )
    ddn = np.array([-6 + 12 * xi, h * (-4 + 6 * xi), 6 - 12 * xi, h * (-2 + 6 * xi)]) / h**2
    return n, dn, ddn


@dataclasses.dataclass(frozen=True, eq=False)
class Mesh:
    """A uniform mesh of one filament and its quadrature rule.

    Attributes:
        n_elements: number of elements N_e.
        x: quadrature points, shape (N_e * q,), in [0, 1].
        weights: quadrature weights, shape (N_e * q,) (they sum to 1).
        phi, dphi, ddphi: shape functions of the *free* dofs and their derivatives at the
            quadrature points, each of shape (N_e * q, n_dof). Rows are dense: the matrix
            is small (N_e <= a few hundred) and dense products keep assembly vectorised.
    """

    n_elements: int
    x: np.ndarray
    weights: np.ndarray
    phi: np.ndarray
    dphi: np.ndarray
    ddphi: np.ndarray
    base_dofs: tuple[int, ...] = ()

    @property
    def n_dof(self) -> int:
        """Unknowns per filament and direction, 2 N_e (plus the kept ``base_dofs``)."""
        return 2 * self.n_elements + len(self.base_dofs)


BASE_DOFS = ((), (1,), (0, 1))
"""The accepted ``base_dofs``: clamped (none), pivot (u'(0)), free (u(0), u'(0))."""


def _global_rows(
    n_elements: int, x: np.ndarray, base_dofs: tuple[int, ...] = ()
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Shape-function rows (phi, phi', phi'') of the free dofs at arbitrary points x in
    [0, 1]: node 0's ``base_dofs`` first, then the dofs of nodes 1..N_e."""
    if tuple(base_dofs) not in BASE_DOFS:
        raise ValueError(f"base_dofs must be one of {BASE_DOFS}, got {base_dofs!r}")
    x = np.asarray(x, dtype=float)
    h = 1.0 / n_elements
    elem = np.clip(np.floor(x / h).astype(int), 0, n_elements - 1)
    xi = x / h - elem
    n, dn, ddn = shape_functions(xi, h)  # (4, m)
    m = x.shape[0]
    out = []
    for vals in (n, dn, ddn):
        full = np.zeros((m, 2 * (n_elements + 1)))
        cols = 2 * elem[None, :] + np.arange(4)[:, None]  # (4, m)
        np.put_along_axis(full, cols.T, vals.T, axis=1)
        if base_dofs:
            full = np.concatenate([full[:, list(base_dofs)], full[:, 2:]], axis=1)
        else:
            full = full[:, 2:]  # drop the clamped node 0
        out.append(full)
    return out[0], out[1], out[2]


MAX_ELEMENTS = 100_000
"""Most elements per filament (the command line's ``--elements`` limit too): beyond it the
mesh's dense shape-function tables alone exceed any memory (10^9 raised MemoryError)."""


def make_mesh(
    n_elements: int, points_per_element: int = 5, base_dofs: tuple[int, ...] = ()
) -> Mesh:
    """Uniform mesh with Gauss-Legendre quadrature (``points_per_element`` >= 4 is exact
    for every product of cubic shape functions and derivatives, including the (1 - x)
    weight of G0); ``base_dofs``: node 0's kept dofs (module docstring), first in the
    shape-function tables."""
    if (
        isinstance(n_elements, bool)
        or not isinstance(n_elements, (int, np.integer))
        or n_elements < 1
    ):
        raise ValueError(f"n_elements must be an integer >= 1, got {n_elements!r}")
    if n_elements > MAX_ELEMENTS:
        raise ValueError(
            f"n_elements must be at most {MAX_ELEMENTS} (the mesh's dense tables grow as its "
            f"square), got {n_elements!r}"
        )
    if points_per_element < 4:
        raise ValueError(
            f"points_per_element must be >= 4 for exact quadrature, got {points_per_element}"
        )
    g, w = np.polynomial.legendre.leggauss(points_per_element)
    h = 1.0 / n_elements
    left = np.arange(n_elements) * h
    x = (left[:, None] + (g[None, :] + 1) / 2 * h).ravel()
    weights = np.tile(w / 2 * h, n_elements)
    phi, dphi, ddphi = _global_rows(n_elements, x, base_dofs)
    return Mesh(int(n_elements), x, weights, phi, dphi, ddphi, tuple(base_dofs))


def interpolation_matrix(
    n_elements: int, x: np.ndarray, derivative: int = 0, base_dofs: tuple[int, ...] = ()
) -> np.ndarray:
    """Matrix mapping the free dofs (``base_dofs`` of node 0, then the 2 N_e of nodes
    1..N_e) to u (or its ``derivative``-th x-derivative) at the points ``x``; shape
    (len(x), len(base_dofs) + 2 N_e). Models read it through
    :meth:`axojax.models.Model.interpolation`, which knows their base."""
    return _global_rows(n_elements, np.asarray(x, dtype=float), base_dofs)[derivative]
