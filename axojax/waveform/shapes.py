"""Centreline shapes from states or eigenvectors, and frames of a mode's beat cycle."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float, Inexact

from ..models.section import Model


def centreline(
    model: Model,
    q: Inexact[Array | np.ndarray, "*batch n"],
    x: Float[ArrayLike, " S"],
    derivative: int = 0,
    body: bool = False,
) -> Inexact[Array | np.ndarray, "*batch d S"]:
    """Centreline (mean over filaments) displacement, or its x-derivative, at points x.

    Args:
        q: (..., n) states (real or complex), n = ``model.n_unknowns``: a numpy array, or a
            jax array (then the result is one too, traceable and differentiable).
        x: (S,) points in [0, 1].
        body: the displacement in the body frame, from the base's tangent line:
            ``u - u(0) - x u'(0)`` (small slopes; the rigid motion of a base that moves
            taken out). Slopes (``derivative >= 1``) stay the lab frame's: the tangent
            angle psi of modes, orbits, simulations and data is one (docs/model.md,
            "One wavelength everywhere"). On a base that holds node 0 (clamped, with or
            without basal compliance) u(0) = u'(0) = 0 and the frames agree.

    Returns:
        (..., d, S) in units of L (``derivative=0``) or rad (``derivative=1``).
    """
    xp = jnp if isinstance(q, jax.Array) else np
    q = xp.asarray(q)
    x = np.asarray(x, dtype=float)
    phi = xp.asarray(model.interpolation(x, derivative))
    per = model.filament_dofs(q).mean(axis=-3)
    u = xp.einsum("sr,...dr->...ds", phi, per)
    if body and model.base.dofs and derivative == 0:

        def at0(k):  # (..., d, 1): u or u' at x = 0
            return xp.einsum(
                "sr,...dr->...ds", xp.asarray(model.interpolation(np.zeros(1), k)), per
            )

        u = u - at0(0) - xp.asarray(x) * at0(1)
    return u


def mode_frames(
    model: Model,
    v: np.ndarray,
    n_frames: int = 16,
    x: np.ndarray | None = None,
    amplitude: float = 0.1,
) -> tuple[np.ndarray, np.ndarray]:
    """Frames of one beat cycle of an eigenmode: Re(u(x) exp(i theta)), theta in [0, 2 pi).

    The complex scale is fixed so that the largest centreline displacement is
    ``amplitude`` (units of L) and the tip is real at theta = 0.

    Returns:
        (x (S,), frames (n_frames, d, S)) in units of L.
    """
    x = np.linspace(0.0, 1.0, 101) if x is None else np.asarray(x, dtype=float)
    u = centreline(model, np.asarray(v), x)  # (d, S) complex
    tip = u[:, -1]
    u = u * np.exp(-1j * np.angle(tip[np.argmax(np.abs(tip))]))
    u = u * amplitude / max(np.abs(u).max(), 1e-300)
    theta = 2 * np.pi * np.arange(n_frames) / n_frames
    return x, np.real(u[None] * np.exp(1j * theta)[:, None, None])
