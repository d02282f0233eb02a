"""Dominant-eigenpair solvers as objects, in the style of lineax's and diffrax's solvers.

Every function that finds a dominant mode (``ax.dominant_mode``, ``ax.sweep``,
``ax.critical_force``, ``ax.fit``) takes ``solver=``; the CLI takes ``--solver``:

- :class:`Dense` (``dense``): all n eigenvalues of the Cholesky-reduced pencil (LAPACK),
  O(n^3). The reference; handles degenerate (clustered) dominant eigenvalues in its
  derivative.
- :class:`Arnoldi` (``arnoldi``): certified shift-invert Arnoldi on the node-major
  block-tridiagonal pencil (:mod:`axojax.eigen.arnoldi`), O(N_e (F d)^3): linear in the
  number of elements; a border of extra unknowns (e.g. a base's) is eliminated by its
  Schur complement. Returns the same eigenvalue as :class:`Dense`; points it cannot
  certify are recomputed densely and flagged (``Mode.certified`` is False there). Its
  ``nearest`` (the eigenpair nearest a shift) is shift-invert Arnoldi about the shift
  (:mod:`axojax.eigen.arnoldi_nearest`).
- :class:`Auto` (``auto``, the default): :class:`Arnoldi` for large models and for
  sweeps, :class:`Dense` for a few points of a small model (chosen statically from the
  model's size and the number of points).

Solvers are hashable equinox modules holding only static options, so they are static
arguments of ``jax.jit``.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float, Inexact

from ..assembly import assemble, assemble_blocks, node_major, pencil_of
from ..models.section import Model
from ..params import Params
from . import deflation
from .arnoldi import ArnoldiOptions, structured_dominant
from .arnoldi_nearest import structured_nearest
from .dominant import dominant_eigenpair
from .nearest import nearest_eigenpair


class AbstractEigenSolver(eqx.Module):
    """Finds the dominant eigenpair of ``(A + lambda C) v = 0`` for a model."""

    @abc.abstractmethod
    def eigenpair(
        self, model: Model, params: Params
    ) -> tuple[Complex[Array, ""], Complex[Array, " n"], Float[Array, ""]]:
        """(eigenvalue with Im >= 0, unit eigenvector in filament-major order, certified
        as 1.0/0.0). Differentiable in ``params``."""

    def nearest(
        self, model: Model, params: Params, shift: Complex[Array, ""]
    ) -> tuple[Complex[Array, ""], Complex[Array, " n"], Float[Array, ""]]:
        """(eigenvalue nearest ``shift``, unit eigenvector in filament-major order,
        certified as 1.0/0.0): the beat of a regulated mechanism at ``shift = i omega0``
        (:mod:`axojax.eigen.nearest`). Differentiable in ``params``. This default is the
        dense eigen-decomposition (certified: every eigenvalue is computed)."""
        system = assemble(model, params)
        lam, v = nearest_eigenpair(system.A, system.C, shift)
        return lam, v, jnp.ones((), float)

    def resolve(self, model: Model, n_points: int = 1) -> "AbstractEigenSolver":
        """The concrete solver for ``n_points`` points of ``model`` (itself, except for
        :class:`Auto`)."""
        return self


class Dense(AbstractEigenSolver):
    """Dense eigen-decomposition of the whole pencil (see :mod:`axojax.eigen.dominant`)."""

    def eigenpair(self, model, params):
        system = assemble(model, params)
        lam, v = dominant_eigenpair(system.A, system.C)
        return lam, v, jnp.ones((), float)


class Arnoldi(AbstractEigenSolver):
    """Certified shift-invert Arnoldi on the block-tridiagonal pencil.

    Attributes:
        krylov_dims: Krylov-space sizes at which the certificate is checked; the
            Arnoldi process stops at the first that certifies (each point on its own).
        lanczos_dim: Lanczos steps that place the pole above the numerical abscissa.
        certify_factor: certify when every eigenvalue within this multiple of the
            returned eigenvalue's distance from the pole has been resolved.
        tol: relative residual tolerance of a converged Ritz value.
        fallback: solve the points that no stage certifies with the dense solver (only
            those points). Off, the uncertified answer is returned as it is (flagged).
        batched: how ``jax.vmap`` over points runs: ``True``, one batched computation
            with plain jnp block kernels (no LAPACK custom calls in the factorisations;
            every point runs its batch's stages); ``False``, one point after another
            with LAPACK's kernels; ``None`` (default), ``False`` on CPU (measured faster
            there: ``benchmarks/bench_sweep.py``) and ``True`` on accelerators. Same
            answers, certificates and fallbacks either way.
    """

    krylov_dims: tuple[int, ...] = eqx.field(default=(12, 16, 24, 32, 48), static=True)
    lanczos_dim: int = eqx.field(default=12, static=True)
    certify_factor: float = eqx.field(default=2.0, static=True)
    tol: float = eqx.field(default=1e-10, static=True)
    fallback: bool = eqx.field(default=True, static=True)
    batched: bool | None = eqx.field(default=None, static=True)

    def __check_init__(self):
        if not self.krylov_dims or min(self.krylov_dims) < 2 or self.lanczos_dim < 2:
            raise ValueError(
                f"krylov_dims and lanczos_dim must be >= 2, got {self.krylov_dims}, {self.lanczos_dim}"
            )
        if not self.certify_factor >= 1.0:
            raise ValueError(f"certify_factor must be >= 1, got {self.certify_factor}")
        if not 0 < self.tol < 1e-3:
            raise ValueError(f"tol must be in (0, 1e-3), got {self.tol}")

    @property
    def options(self) -> ArnoldiOptions:
        batched = self.batched if self.batched is not None else jax.default_backend() != "cpu"
        return ArnoldiOptions(
            tuple(self.krylov_dims),
            self.lanczos_dim,
            self.certify_factor,
            self.tol,
            self.fallback,
            bool(batched),
        )

    def eigenpair(self, model, params):
        """The dominant eigenpair; on a base that lets the axoneme move rigidly, the
        dominant *deforming* one: the rigid-body modes deflated through a border of
        their own (:mod:`axojax.eigen.deflation`), structured as the rest."""
        A, C = pencil_of(assemble_blocks(model, params))
        Z = jnp.asarray(rigid_modes_node_major(model))
        if not Z.shape[1]:
            lam, x, certified = structured_dominant(A, C, self.options)
            return lam, filament_major(model, x), certified
        A, C, s = deflation.deflate(A, C, Z)
        opts = self.options._replace(deflated=Z.shape[1])
        lam, x, certified = structured_dominant(A, C, opts)
        return lam, filament_major(model, deflation.restore(x, lam, Z, s)), certified

    def nearest(self, model, params, shift):
        """The eigenpair nearest ``shift`` by structured shift-invert Arnoldi about the
        shift itself (:mod:`axojax.eigen.arnoldi_nearest`): any C (non-symmetric,
        indefinite), certified as the dominant one, dense where not certified."""
        A, C = pencil_of(assemble_blocks(model, params))
        lam, x, certified = structured_nearest(A, C, shift, self.options)
        return lam, filament_major(model, x), certified


def filament_major(model: Model, x: Inexact[Array, " n"]) -> Inexact[Array, " n"]:
    """A node-major vector (:func:`axojax.assembly.node_major`, then any border
    unknowns) in the dense solver's order: node unknowns filament-major, then the
    border. Where ``node_major`` already covers the border (as many entries as x), it
    is applied as it is."""
    inverse = np.argsort(node_major(model))
    n_nodes = inverse.shape[0]
    if n_nodes == x.shape[-1]:
        return x[inverse]
    return jnp.concatenate([x[:n_nodes][inverse], x[n_nodes:]])


def rigid_modes_node_major(model: Model) -> np.ndarray:
    """:meth:`Model.rigid_modes` (filament-major node unknowns, then the border) in the
    structured pencil's order: node-major (:func:`axojax.assembly.node_major`), then the
    border. (n_unknowns, r); r = 0 on a base that holds the axoneme."""
    Z = model.rigid_modes()
    perm = node_major(model)
    return np.concatenate([Z[: perm.shape[0]][perm], Z[perm.shape[0] :]])


class Auto(AbstractEigenSolver):
    """:class:`Arnoldi` where it pays, :class:`Dense` elsewhere, chosen statically.

    The structured solver's cost per point grows linearly with the mesh and the dense
    solver's as its cube, but the structured solver takes several times longer to compile
    (seconds). So Arnoldi is used for models of ``min_arnoldi_dof`` unknowns or more, and
    for batches of at least ``min_batch_points`` points (a sweep, a traced boundary) on
    models of ``min_batch_dof`` unknowns or more; a handful of points on a small model
    (``axojax modes`` on the ten-element presets) keeps the quicker-to-compile dense path.
    """

    min_arnoldi_dof: int = eqx.field(default=600, static=True)
    min_batch_dof: int = eqx.field(default=200, static=True)
    min_batch_points: int = eqx.field(default=64, static=True)

    def resolve(self, model: Model, n_points: int = 1) -> AbstractEigenSolver:
        n = model.n_dof
        large = n >= self.min_arnoldi_dof or (
            n >= self.min_batch_dof and n_points >= self.min_batch_points
        )
        return Arnoldi() if large else Dense()

    def eigenpair(self, model, params):
        return self.resolve(model).eigenpair(model, params)

    def nearest(self, model, params, shift):
        return self.resolve(model).nearest(model, params, shift)


SOLVERS = {"auto": Auto, "dense": Dense, "arnoldi": Arnoldi}


def solver_from_name(name: str) -> AbstractEigenSolver:
    """``auto``, ``dense`` or ``arnoldi`` -> a solver with default options."""
    try:
        return SOLVERS[name]()
    except KeyError:
        raise ValueError(
            f"unknown eigen-solver {name!r}; choose one of {', '.join(SOLVERS)}"
        ) from None


EigenSolver = AbstractEigenSolver
"""The former name of :class:`AbstractEigenSolver`, kept for existing code."""
