"""Filament-level matrices M0, K0, D0, G0, F0 by Gauss quadrature (docs/model.md section 2).

With phi the free-dof shape functions of one filament direction:

- ``M0 = int phi phi^T``            (mass-like; fluid drag and links)
- ``K0 = int EI(x) phi'' phi''^T``  (bending; EI(x) a relative profile, 1 by default)
- ``D0 = int phi' phi'^T``          (tangent-angle coupling, Beck's constant compression)
- ``G0 = int n(x) phi' phi'^T`` with ``n(x) = int_x^1 p(s) ds`` (= 1 - x for uniform p)
- ``F0[r, s] = int p(x) phi_r phi_s'``
- ``Mk = int k(x) phi phi^T``       (links with a stiffness profile; = M0 by default)
- ``H0[r, s] = int phi_r' phi_s''``  (curvature-controlled dynein: a couple ~ u'' tested
  with the slope's variation; non-symmetric)
- ``f1 = int p(x) phi'``            (static dynein moment load)
- ``tip``: the Beck tip-force matrix, ``tip[u(1), u'(1)] = 1``.
"""

from __future__ import annotations

import dataclasses
from typing import Callable, Optional

import numpy as np

from .hermite import Mesh, interpolation_matrix

Profile = Callable[[np.ndarray], np.ndarray]


@dataclasses.dataclass(frozen=True, eq=False)
class Profiles:
    """Optional relative x-profiles (functions of x in [0, 1], value 1 = uniform).

    ``ei`` scales bending stiffness, ``p`` the dynein force per length, ``k`` the link
    stiffness. They multiply the global parameters (EI_f, p, k_s / k_l).
    """

    ei: Optional[Profile] = None
    p: Optional[Profile] = None
    k: Optional[Profile] = None


def evaluate_profile(profile: Optional[Profile], x: np.ndarray, name: str) -> np.ndarray:
    if profile is None:
        return np.ones_like(x)
    values = np.broadcast_to(np.asarray(profile(x), dtype=float), x.shape)
    if not np.all(np.isfinite(values)) or np.any(values < 0):
        raise ValueError(f"profile {name!r} must be finite and non-negative on [0, 1]")
    return values


def _tail_integral(profile: Optional[Profile], x: np.ndarray) -> np.ndarray:
    """n(x) = int_x^1 profile(s) ds, by 20-point Gauss quadrature on [x, 1]."""
    if profile is None:
        return 1.0 - x
    g, w = np.polynomial.legendre.leggauss(20)
    s = x[:, None] + (g[None, :] + 1) / 2 * (1 - x[:, None])
    vals = evaluate_profile(profile, s.ravel(), "p").reshape(s.shape)
    return (vals * w[None, :]).sum(axis=1) * (1 - x) / 2


@dataclasses.dataclass(frozen=True, eq=False)
class FilamentMatrices:
    """Filament-level matrices, each (2 N_e, 2 N_e) except ``f1`` (2 N_e,)."""

    M0: np.ndarray
    K0: np.ndarray
    D0: np.ndarray
    G0: np.ndarray
    F0: np.ndarray
    Mk: np.ndarray
    f1: np.ndarray
    H0: np.ndarray
    tip: np.ndarray


def filament_matrices(mesh: Mesh, profiles: Profiles = Profiles()) -> FilamentMatrices:
    """Integrate the filament-level matrices on ``mesh`` (vectorised over quadrature points)."""
    x, w = mesh.x, mesh.weights
    phi, dphi, ddphi = mesh.phi, mesh.dphi, mesh.ddphi

    def gram(a: np.ndarray, b: np.ndarray, weight: np.ndarray) -> np.ndarray:
        return np.einsum("qr,qs,q->rs", a, b, w * weight)

    ones = np.ones_like(x)
    pw = evaluate_profile(profiles.p, x, "p")
    tip = np.zeros((mesh.n_dof, mesh.n_dof))
    tip_row = interpolation_matrix(mesh.n_elements, np.array([1.0]), 0, mesh.base_dofs)[0]
    tip_slope = interpolation_matrix(mesh.n_elements, np.array([1.0]), 1, mesh.base_dofs)[0]
    tip += np.outer(tip_row, tip_slope)
    return FilamentMatrices(
        M0=gram(phi, phi, ones),
        K0=gram(ddphi, ddphi, evaluate_profile(profiles.ei, x, "ei")),
        D0=gram(dphi, dphi, ones),
        G0=gram(dphi, dphi, _tail_integral(profiles.p, x)),
        F0=gram(phi, dphi, pw),
        Mk=gram(phi, phi, evaluate_profile(profiles.k, x, "k")),
        f1=dphi.T @ (w * pw),
        tip=tip,
        H0=gram(dphi, ddphi, ones),
    )
