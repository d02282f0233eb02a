"""The dominant mode of a model at a parameter point, with all its metrics."""

from __future__ import annotations

from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Complex, Float, Int

from .. import results
from ..assembly import assemble, check_base_params, refuse_normal_force
from ..models.section import Model
from ..params import Params, require_scalars, valid
from ..results import RESULTS
from ..units import Units
from ..waveform import measures
from . import deflation, pencil
from .dominant import dominant_eigenpair, normalise
from .metrics import beat_plane, tangent_measures
from .solvers import AbstractEigenSolver, Auto, Dense

STABLE, FLUTTER, DIVERGENCE = 0, 1, 2
CLASSES = ("stable", "flutter", "divergence")
IMAG_RTOL = 1e-9


def classify(eigenvalue: Complex[Array, "..."]) -> Int[Array, "..."]:
    """0 stable (Re <= 0), 1 flutter (Re > 0, Im != 0), 2 divergence (Re > 0, Im = 0)."""
    re, im = jnp.real(eigenvalue), jnp.abs(jnp.imag(eigenvalue))
    oscillating = im > IMAG_RTOL * (1.0 + jnp.abs(eigenvalue))
    return jnp.where(re <= 0, STABLE, jnp.where(oscillating, FLUTTER, DIVERGENCE))


class Mode(eqx.Module):
    """Dominant mode; every field dimensionless (time in tau, length in L).

    Attributes:
        eigenvalue: lambda with Im >= 0 (complex scalar).
        eigenvector: (n,) unit eigenvector (see :mod:`axojax.eigen.dominant` for gauge).
        growth_rate: Re lambda (1/tau).
        angular_frequency: |Im lambda| (rad/tau).
        wavenumber: phase slope k of the tangent angle psi_1 = u' along the beat
            direction: the least-squares slope of its unwrapped phase over the length
            (rad/L; :mod:`axojax.waveform.measures`).
        wavelength: 2 pi / |k| (L); inf for a standing wave.
        velocity: wavelength * |Im lambda| / (2 pi) (L/tau).
        direction: +1 anterograde (base to tip), -1 retrograde, 0 not oscillating.
        out_of_plane_ratio: sqrt(minor/major) of the centreline motion (0 in 2D).
        amplitude_dip: min |psi_1| / max |psi_1| over the middle of the length; below
            :data:`axojax.waveform.measures.SENSITIVE_DIP` psi_1 nearly vanishes inside
            the flagellum and the wavelength is sensitive there.
        beat_angle: beat direction, radians from y towards z.
        classification: 0 stable, 1 flutter, 2 divergence.
        certified: True when the solver certified the eigenvalue as the rightmost
            (always for :class:`~axojax.eigen.Dense`); False where a structured solver
            could not, and the dense fallback supplied it.
        result: :class:`axojax.results.RESULTS` item: ``successful``,
            ``invalid_params`` (a traced parameter out of range: every number is NaN) or
            ``nonfinite`` (the eigen-solve gave no finite eigenvalue).
    """

    eigenvalue: Complex[Array, ""]
    eigenvector: Complex[Array, " n"]
    growth_rate: Float[Array, ""]
    angular_frequency: Float[Array, ""]
    wavenumber: Float[Array, ""]
    wavelength: Float[Array, ""]
    velocity: Float[Array, ""]
    direction: Int[Array, ""]
    out_of_plane_ratio: Float[Array, ""]
    amplitude_dip: Float[Array, ""]
    beat_angle: Float[Array, ""]
    classification: Int[Array, ""]
    certified: Array = True
    result: RESULTS = eqx.field(default_factory=lambda: RESULTS.successful)

    # -- physical units ------------------------------------------------------------
    def frequency_hz(self, units: Units = Units()) -> Float[Array, "..."]:
        return self.angular_frequency / (2 * jnp.pi * units.tau_s)

    def growth_rate_per_s(self, units: Units = Units()) -> Float[Array, "..."]:
        return self.growth_rate / units.tau_s

    def wavelength_um(self, units: Units = Units()) -> Float[Array, "..."]:
        return self.wavelength * units.length_um

    def velocity_um_per_s(self, units: Units = Units()) -> Float[Array, "..."]:
        return self.velocity * units.length_um / units.tau_s

    @property
    def message(self) -> str:
        """``result``'s message on one line ("successful"; for a batch of modes, how many
        failed: :func:`axojax.results.message`)."""
        return results.message(self.result)

    def to_json(self, units: Units = Units()) -> dict[str, Any]:
        """Plain-Python summary in physical units (the ``dominant`` block of
        ``axojax modes --json``). Infinite wavelengths (standing waves) and those of modes
        that do not oscillate are reported as ``None``."""
        lam = complex(self.eigenvalue)
        cls = CLASSES[int(self.classification)]
        oscillating = int(self.direction) != 0
        num = measures.finite_or_none

        return results.jsonable(
            {
                "eigenvalue": [lam.real, lam.imag],
                "classification": cls,
                "growth_rate_per_s": num(self.growth_rate_per_s(units)),
                "frequency_hz": num(self.frequency_hz(units)),
                "wavelength_um": num(self.wavelength_um(units)) if oscillating else None,
                "velocity_um_per_s": num(self.velocity_um_per_s(units)) if oscillating else None,
                "direction": {1: "anterograde", -1: "retrograde"}.get(int(self.direction)),
                "out_of_plane_ratio": num(self.out_of_plane_ratio),
                "amplitude_dip": num(self.amplitude_dip),
                "wavelength_sensitive": oscillating and measures.is_sensitive(self.amplitude_dip),
            }
        )


def mode_from_eigenpair(
    model: Model, lam: Complex[Array, ""], v: Complex[Array, " n"], certified=True
) -> Mode:
    """All metrics of an eigenpair (differentiable through lam and v)."""
    _, _, angle, ratio = beat_plane(model, v)
    k, dip = tangent_measures(model, v, angle)  # psi_1 evaluated once for both
    omega = jnp.abs(jnp.imag(lam))
    cls = classify(lam)
    oscillating = jnp.abs(jnp.imag(lam)) > IMAG_RTOL * (1.0 + jnp.abs(lam))
    wavelength = measures.wavelength(k)
    direction = jnp.where(oscillating, measures.direction(k, jnp.imag(lam)), 0)
    return Mode(
        eigenvalue=lam,
        eigenvector=v,
        growth_rate=jnp.real(lam),
        angular_frequency=omega,
        wavenumber=k,
        wavelength=wavelength,
        velocity=wavelength * omega / (2 * jnp.pi),
        direction=direction,
        out_of_plane_ratio=ratio,
        amplitude_dip=dip,
        beat_angle=angle,
        classification=cls,
        certified=jnp.asarray(certified) > 0.5,
    )


DEFAULT_SOLVER = Auto()


class RigidDeflated(AbstractEigenSolver):
    """Dense, without the rigid-body zero eigenvalues of a base that leaves the axoneme
    free to move (:meth:`axojax.models.Model.rigid_modes`, Z): the dominant mode of a
    free axoneme is its largest-real-part *deforming* mode.

    Z is a right null space of A (A Z = 0: internal forces do not resist rigid motion,
    tests/model/test_bases.py). With Y^T = (Z^T C Z)^{-1} Z^T C (Y^T Z = I) the pencil
    (A + sigma C Z Y^T, C) has every eigenvalue of (A, C) except that the rigid ones move
    from 0 to -sigma (Brauer's theorem), and an eigenvector v' of it at lambda gives the
    original's, v = v' + (sigma / lambda) Z Y^T v' (exact; both differentiable). sigma =
    10 max|A| / max|C| puts the rigid modes among the fastest-decaying ones. (The
    structured solver does the same through a border: :mod:`axojax.eigen.deflation`.)
    """

    def eigenpair(self, model, params):
        system = assemble(model, params)
        A, C = system.A, system.C
        Z = jnp.asarray(model.rigid_modes())
        ZtC = Z.T @ C
        Yt = jnp.linalg.solve(ZtC @ Z, ZtC)
        sigma = deflation.scale_of(jnp.max(jnp.abs(A)), jnp.max(jnp.abs(C)))
        lam, w = dominant_eigenpair(A + sigma * (C @ Z) @ Yt, C)
        v = normalise(w + (sigma / lam) * (Z @ (Yt @ w)))
        return lam, v, jnp.ones((), float)


def for_base(model: Model, solver: AbstractEigenSolver) -> AbstractEigenSolver:
    """``solver``, except where the base leaves rigid-body motion free (free, head, a
    pivot without a spring): their zero eigenvalues are no mode of deformation. The
    dense solver is replaced by :class:`RigidDeflated`, which moves them out of the way;
    :class:`~axojax.eigen.Arnoldi` deflates them itself, through a border
    (:mod:`axojax.eigen.deflation`); :class:`~axojax.eigen.Auto` resolves first. A border
    without rigid motion (basal compliance on a clamped base) is solved by every solver
    as it is: both eliminate the border by a Schur complement."""
    if not model.n_border or model.rigid_modes().shape[1] == 0:
        return solver
    if isinstance(solver, Auto):
        return for_base(model, solver.resolve(model))
    if isinstance(solver, Dense):
        return RigidDeflated()
    return solver


def with_result(model: Model, lam, v, certified, ok) -> Mode:
    """The :class:`Mode` of an eigenpair with its ``result``: NaN numbers and
    ``invalid_params`` where ``ok`` is False (parameters out of range), ``nonfinite``
    where the eigenvalue is not finite (:mod:`axojax.results`)."""
    lam = jnp.where(ok, lam, jnp.nan + 0j)
    v = jnp.where(ok, v, jnp.nan + 0j)
    mode = mode_from_eigenpair(model, lam, v, certified)
    result = RESULTS.where(
        ok,
        RESULTS.where(jnp.isfinite(lam), RESULTS.successful, RESULTS.nonfinite),
        RESULTS.invalid_params,
    )
    return eqx.tree_at(lambda m: m.result, mode, result)


def dominant_mode_impl(
    model: Model, params: Params, solver: AbstractEigenSolver = DEFAULT_SOLVER
) -> Mode:
    """:func:`dominant_mode` without its validation and its own ``jax.jit``: the entry
    point for code that traces it inside its own transformations (the sweep engine,
    fits). Parameters out of range give NaN numbers and ``result = invalid_params``
    (:mod:`axojax.results`)."""
    require_scalars(params, "dominant_mode")
    solver = for_base(model, solver)
    ok = valid(params)
    if model.base.compliance:  # check_base_params's rule, traceable
        ok = ok & (jnp.asarray(params.xib, dtype=float) > 0)
    lam, v, certified = solver.eigenpair(model, params)
    return with_result(model, lam, v, certified, ok)


_dominant_mode_impl = dominant_mode_impl  # the old private name, for existing callers


def _spectrum_impl(model: Model, params: Params, top: int | None = None) -> Complex[Array, " k"]:
    system = assemble(model, params)
    lam = pencil.eigenvalues(system.A, system.C)
    return lam if top is None else lam[:top]


# The model is a static, identity-hashed argument: one compilation per model.
_dominant_mode_jit = jax.jit(dominant_mode_impl, static_argnums=(0, 2))
_spectrum_jit = jax.jit(_spectrum_impl, static_argnums=(0, 2))


def dominant_mode(
    model: Model,
    params: Params,
    solver: AbstractEigenSolver = DEFAULT_SOLVER,
    *,
    throw: bool = False,
) -> Mode:
    """The dominant (largest real part) mode of ``model`` at ``params``.

    Jit-compiled per (model, solver), and composable: call it under ``jax.jit``,
    ``jax.vmap`` over a batch of ``params``, ``jax.grad``/``jax.jacfwd``/``jax.jacrev``.
    Concrete parameters are validated first (one-line ``ValueError`` naming the bad
    value); traced ones cannot be, and a NaN or out-of-range one gives NaN numbers with
    ``mode.result == RESULTS.invalid_params`` (:mod:`axojax.results`). Array-valued
    ``Params`` are refused with a message naming ``jax.vmap``. ``solver`` is an
    :mod:`axojax.eigen.solvers` object (default :class:`~axojax.eigen.Auto`: dense for
    small models, certified Arnoldi for large). ``throw=True`` raises (at run time, also
    under ``jit``) when ``mode.result`` is not ``successful``; default False, as everywhere
    (:mod:`axojax.results`): read ``mode.result`` and ``mode.message``.
    """
    if not isinstance(solver, AbstractEigenSolver):
        raise TypeError(
            f"solver must be an axojax eigen-solver (ax.eigen.Dense(), ax.eigen.Arnoldi(), ...), got {solver!r}"
        )
    if not isinstance(model, Model):
        raise TypeError(
            f"model must be an axojax model (ax.models.seven(), ax.models.from_file(...), ...), got {model!r}"
        )
    if not isinstance(params, Params):
        raise TypeError(f"params must be an ax.Params, got {params!r}")
    require_scalars(params, "dominant_mode")
    mode = _dominant_mode_jit(
        model, check_base_params(model, refuse_normal_force(params.validate())), solver
    )
    if throw:
        mode = mode.result.error_if(mode, mode.result != RESULTS.successful)
    return mode


def spectrum(model: Model, params: Params, top: int | None = None) -> Complex[Array, " k"]:
    """Eigenvalues of the pencil (A + lambda C) v = 0 sorted by decreasing real part;
    the ``top`` first (all n by default). Dimensionless (1/tau)."""
    return _spectrum_jit(
        model, check_base_params(model, refuse_normal_force(params.validate())), top
    )
