"""Eigenpairs of normal-force control (docs/model.md section 8; issue 55 item 1, first
step): the augmented pencil of :func:`axojax.assembly.normal_force.assemble_normal`.

Its C' is singular where the gain's friction g'' is 0 (the pairs' force rows are
algebraic: infinite eigenvalues), so the Cholesky or LU reduction of :mod:`.pencil` does
not apply. A shift-and-invert does: ``(A' + lambda C') v = 0`` is
``-(A' + sigma C')^{-1} C' v = mu v`` with ``mu = 1 / (lambda - sigma)``; the infinite
eigenvalues go to mu = 0, and the eigenvalue nearest the shift sigma is the mu of largest
modulus. Dense, ``jit``-able.

**Derivative.** Implicit differentiation of ``(A' + lambda C') v = 0`` with the gauge
``v^H dv = 0``: ``[[A' + lambda C', C' v], [v^H, 0]] [dv; dlambda] = [-(dA' + lambda dC') v; 0]``,
one bordered solve that gives the eigenvalue's and the eigenvector's tangents together
(the bordered matrix is regular at a simple finite eigenvalue, whether or not C' is).
The shift only selects. :class:`NormalForce` is the eigen-solver object a fit of
normal-force control uses (its ``nearest``).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Complex, Float

from ..assembly.normal_force import assemble_normal, check_normal_model
from ..models.section import Model
from ..params import Params, require_scalars, valid
from .dominant import normalise
from .solvers import AbstractEigenSolver


@jax.custom_jvp
def shift_invert_eigenpair(
    A: Float[Array, "n n"], C: Float[Array, "n n"], shift: Complex[Array, ""]
) -> tuple[Complex[Array, ""], Complex[Array, " n"]]:
    """The eigenvalue of ``(A + lambda C) v = 0`` nearest ``shift`` and its unit
    eigenvector (C may be singular: module docstring), the eigenvalue refined by the
    least-squares quotient ``-(Cv)^H A v / |Cv|^2`` of its eigenvector. Differentiable in
    A and C (the module docstring's bordered solve); ``shift`` only selects."""
    A, C = A.astype(complex), C.astype(complex)
    X = -jnp.linalg.solve(A + shift * C, C)
    mu, V = jax.lax.linalg.eig(X, compute_left_eigenvectors=False, compute_right_eigenvectors=True)
    j = jnp.argmax(jnp.abs(mu))
    v = V[:, j] / jnp.linalg.norm(V[:, j])
    Cv = C @ v
    lam = -jnp.vdot(Cv, A @ v) / jnp.vdot(Cv, Cv)
    return lam, v


@shift_invert_eigenpair.defjvp
def _shift_invert_jvp(primals, tangents):
    A, C, shift = primals
    dA, dC, _ = tangents
    lam, v = shift_invert_eigenpair(A, C, shift)
    n = A.shape[0]
    K = A.astype(complex) + lam * C.astype(complex)
    Cv = C.astype(complex) @ v
    bordered = jnp.block([[K, Cv[:, None]], [jnp.conj(v)[None, :], jnp.zeros((1, 1), complex)]])
    rhs = jnp.concatenate([-((dA.astype(complex) + lam * dC.astype(complex)) @ v), jnp.zeros(1)])
    out = jnp.linalg.solve(bordered, rhs)
    return (lam, v), (out[n], out[:n])


def _normal_force_mode(model: Model, params: Params, shift: ArrayLike) -> "Mode":  # noqa: F821
    from .mode import with_result

    lam, v, certified = NormalForce().nearest(model, params, shift)
    return with_result(model, lam, v, certified, valid(params))


_normal_force_mode_jit = jax.jit(_normal_force_mode, static_argnums=(0,))


def normal_force_mode(model: Model, params: Params, shift: ArrayLike) -> "Mode":  # noqa: F821
    """The mode of normal-force control whose eigenvalue is nearest ``shift``
    (dimensionless, 1/tau: ``1j * params.omega0`` for the beat, or the rightmost eigenvalue
    for the dominant mode), by a dense shift-and-invert of the augmented pencil; its
    eigenvector restricted to the model's N unknowns (the pairs' forces dropped).

    Validates ``params`` (one-line ``ValueError``) and the model
    (:func:`~axojax.assembly.normal_force.check_normal_model`); ``jit``-ed.
    """
    require_scalars(params, "normal_force_mode")
    check_normal_model(model, params.validate())
    return _normal_force_mode_jit(model, params, complex(shift))


class NormalForce(AbstractEigenSolver):
    """The eigen-solver of normal-force control: the dense shift-and-invert of the
    augmented pencil (:func:`~axojax.assembly.normal_force.assemble_normal`, module
    docstring), differentiable. Only ``nearest`` (the beat at ``i omega0``): the pencil's
    infinite eigenvalues (g'' = 0) leave no dominant mode to follow."""

    def eigenpair(self, model, params):
        raise ValueError(
            "normal-force control follows the beat nearest i omega0 (nearest), not the "
            "dominant mode"
        )

    def nearest(self, model, params, shift):
        system = assemble_normal(model, params)
        lam, v = shift_invert_eigenpair(system.A, system.C, jnp.asarray(shift, dtype=complex))
        return lam, normalise(v[: system.n]), jnp.ones((), float)
