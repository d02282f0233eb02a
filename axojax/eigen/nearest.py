"""The eigenpair nearest a given point of the complex plane, and its exact derivative.

A regulated mechanism is fitted the way its anchors pose it (docs/model.md, regulated
dynein): the beat is the eigenvalue at ``i omega0``, the observed angular frequency, and
it need not be the dominant one (with an active friction, chi'' < 0, the pencil also has
short-wavelength modes that grow faster; they are not the beat). So a fit follows the
eigenvalue *nearest* a shift instead of the rightmost one.

``nearest_eigenpair(A, C, shift)`` picks, among the pencil's eigenvalues, the one closest
to ``shift`` (a cluster within :data:`~axojax.eigen.dominant.CLUSTER_RTOL` is averaged as
for the dominant one), with the same derivative rule as
:func:`~axojax.eigen.dominant.dominant_eigenpair` (implicit differentiation of
``(A + lambda C) v = 0``). The shift only selects: its tangent is ignored (the selected
eigenvalue does not move with it).

``nearest_mode(model, params, shift, solver)`` is the model-level entry point: every
metric of :class:`~axojax.eigen.Mode` for that eigenpair. The solvers' ``nearest`` method
does the eigen-solve (dense by default; :class:`~axojax.eigen.Arnoldi` by structured
shift-invert Arnoldi about the shift, :mod:`axojax.eigen.arnoldi_nearest`).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Complex, Float

from ..assembly import refuse_normal_force
from ..models.section import Model
from ..params import Params, require_scalars, valid
from .dominant import CLUSTER_RTOL, MAX_CLUSTER, _inverse_iteration, _primal, eigenpair_jvp
from .pencil import reduced_matrix


def _select_near(shift: Complex[Array, ""]):
    """A selection rule for :func:`axojax.eigen.dominant._primal`: the eigenvalue nearest
    ``shift`` first, then its nearest neighbours, and their cluster mask."""

    def select(lam: Complex[Array, " n"]) -> tuple[Array, Array]:
        j1 = jnp.argmin(jnp.abs(lam - shift))
        dist = jnp.where(jnp.arange(lam.shape[0]) == j1, -1.0, jnp.abs(lam - lam[j1]))
        order = jnp.argsort(dist)[:MAX_CLUSTER]
        mask = (dist[order] <= CLUSTER_RTOL * (1.0 + jnp.abs(lam[j1]))).astype(float)
        return order, mask

    return select


@jax.custom_jvp
def nearest_eigenpair(
    A: Float[Array, "n n"], C: Float[Array, "n n"], shift: Complex[Array, ""]
) -> tuple[Complex[Array, ""], Complex[Array, " n"]]:
    """Eigenvalue of ``(A + lambda C) v = 0`` nearest ``shift`` (cluster mean if
    degenerate) and its unit eigenvector (gauge as :func:`dominant_eigenpair`).
    Differentiable in A and C; ``shift`` only selects."""
    S, _, _ = reduced_matrix(A, C)
    lam = jax.lax.linalg.eig(S, compute_left_eigenvectors=False, compute_right_eigenvectors=False)[
        0
    ]
    order, mask = _select_near(shift)(lam)
    lam_c = jnp.sum(mask * lam[order]) / jnp.sum(mask)
    return lam_c, _inverse_iteration(A, C, lam[order[0]])


@nearest_eigenpair.defjvp
def _nearest_jvp(primals, tangents):
    A, C, shift = primals
    dA, dC, _ = tangents
    return eigenpair_jvp(A, C, dA, dC, *_primal(A, C, left=True, select=_select_near(shift)))


def nearest_mode_impl(
    model: Model, params: Params, shift: ArrayLike, solver, tau_m: ArrayLike | None = None
) -> "Mode":  # noqa: F821
    """:func:`nearest_mode` without its validation and ``jax.jit`` (for code that traces
    it inside its own transformations, e.g. fits)."""
    from .mode import with_result

    require_scalars(params, "nearest_mode")
    ok = valid(params)
    if model.base.compliance:  # check_base_params's rule, traceable
        ok = ok & (jnp.asarray(params.xib, dtype=float) > 0)
    if tau_m is None:
        lam, v, certified = solver.nearest(model, params, jnp.asarray(shift, dtype=complex))
    else:
        lam, v, certified = _nearest_with_motors(model, params, shift, tau_m)
        ok = ok & (jnp.asarray(tau_m, dtype=float) > 0)
    return with_result(model, lam, v, certified, ok)


def _nearest_with_motors(
    model: Model, params: Params, shift: ArrayLike, tau_m: ArrayLike
) -> tuple[Complex[Array, ""], Complex[Array, " n"], Float[Array, ""]]:
    """The dense eigenpair nearest ``shift`` of the pencil with motor kinetics
    (:func:`axojax.assembly.motor_kinetics.assemble_motor`, 2 N unknowns), its eigenvector
    restricted to the model's N unknowns (the motor copy y = q / (1 + tau_m lambda) dropped)
    and normalised as the dense solver's."""
    from ..assembly.motor_kinetics import assemble_motor
    from .dominant import normalise

    system = assemble_motor(model, params, tau_m)
    lam, v = nearest_eigenpair(system.A, system.C, jnp.asarray(shift, dtype=complex))
    return lam, normalise(v[: system.n]), jnp.ones((), float)


_nearest_mode_jit = jax.jit(nearest_mode_impl, static_argnums=(0, 3))


def nearest_mode(
    model: Model, params: Params, shift: ArrayLike, solver=None, tau_m: ArrayLike | None = None
) -> "Mode":  # noqa: F821
    """The mode whose eigenvalue is nearest ``shift`` (dimensionless, 1/tau; e.g.
    ``1j * params.omega0`` for the beat of a regulated mechanism).

    Like :func:`axojax.dominant_mode` (validation, ``jit``, ``vmap``, ``grad``) except for
    the selection; ``mode.certified`` says whether the solver certified that no eigenvalue
    lies nearer the shift. ``solver`` defaults to :class:`~axojax.eigen.Dense`.

    ``tau_m`` (dimensionless, in tau; > 0): motor kinetics of that relaxation time instead
    of the regulated friction (:mod:`axojax.assembly.motor_kinetics`, docs/model.md
    section 8): the same eigenvalue and psi_1 where i omega0 is one, a bounded spectrum
    with active friction. **Dense solves only** (the (2N, 2N) augmented pencil): with
    ``tau_m`` the solver must be :class:`~axojax.eigen.Dense` (or None). None (default):
    today's friction form, unchanged.
    """
    from .solvers import AbstractEigenSolver, Dense

    solver = Dense() if solver is None else solver
    if not isinstance(solver, AbstractEigenSolver):
        raise TypeError(f"solver must be an axojax eigen-solver, got {solver!r}")
    require_scalars(params, "nearest_mode")
    shift = complex(shift) if not isinstance(shift, jax.core.Tracer) else shift
    if tau_m is None:
        return _nearest_mode_jit(model, refuse_normal_force(params.validate()), shift, solver)
    if type(solver) is not Dense:
        raise ValueError(
            f"motor kinetics (tau_m) is solved densely only: pass solver=Dense() or none, got {solver!r}"
        )
    from ..assembly.motor_kinetics import check_tau_m

    check_tau_m(params, tau_m)
    return _nearest_mode_jit(model, refuse_normal_force(params.validate()), shift, solver, tau_m)
