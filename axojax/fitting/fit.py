"""``fit``: estimate unknown parameters from observed beats with optax.

Free parameters are optimised in a bounded, unconstrained coordinate: positive parameters
in log space, ``gamma`` linearly, each mapped into its bounds by a logistic function. The
loss is ``0.5 * sum(r^2)`` of the normalised residuals of :mod:`axojax.fitting.targets`.
Several starts (the given point and a Latin-hypercube design inside the bounds) run L-BFGS
(or Adam); the best is kept. Standard errors and correlations come from the Gauss-Newton
(Fisher) matrix ``J^T J`` of the residuals in log (or linear) parameter space at the
optimum; a parameter whose Fisher information is (near) singular is reported as not
identifiable, with a warning.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from typing import Any, Sequence

import jax
import jax.numpy as jnp
import numpy as np
import optax
from tqdm.auto import tqdm

from ..dynamics.simulate import DEFAULT_CUBIC
from ..eigen.mode import DEFAULT_SOLVER, _dominant_mode_impl
from ..eigen.solvers import EigenSolver
from ..models.section import Model
from ..params import PARAM_NAMES, Params
from ..units import Units
from ..orbits.solvers import HarmonicBalance, OrbitSolver
from .targets import SCALARS, ShapeTarget, Target, cycle_value, scalar_value, shape_residuals

DEFAULT_BOUNDS = {
    "p": (10.0, 1e4),
    "ks": (1e1, 1e8),
    "kl": (1e-1, 1e7),
    "cl": (1e-5, 1e2),
    "gamma": (-3.0, 3.0),
    "ktheta": (1e-3, 1e4),
    "out_of_plane": (0.1, 10.0),
    "inactive_factor": (0.1, 1e3),
    "imbalance": (0.1, 10.0),
}
LINEAR = {"gamma"}
CYCLE_FAILED = 1e3  # normalised residual of a limit-cycle target where no orbit is found
IDENTIFIABLE_MAX_LOG_SE = 1.0  # a log-space standard error above 1 (a factor e) is not an estimate
SHAPE_RMS_OK = 2.0


@dataclasses.dataclass
class FitResult:
    """Attributes:
    params: fitted values of the free parameters (dimensionless).
    full_params: the complete :class:`Params` at the optimum (kl tied if asked).
    achieved: every scalar observable at the optimum, physical units.
    residuals: normalised residual (model - target) / sigma of each scalar target.
    shape_rms: root-mean-square normalised residual of the shape target (None without one).
    loss: 0.5 * sum of squared normalised residuals.
    converged: the optimiser stopped on a small gradient and every target is reproduced
        (|residual| <= 1, shape rms <= 2).
    message: one line saying what happened.
    stderr: standard error of each free parameter (same units as params; inf if not identifiable).
    correlation: (k, k) correlation matrix of the free parameters (in log space).
    identifiable: per parameter.
    starts: (initial values, final loss) of each start.
    """

    params: dict[str, float]
    full_params: Params
    achieved: dict[str, float]
    residuals: dict[str, float]
    shape_rms: float | None
    loss: float
    converged: bool
    message: str
    stderr: dict[str, float]
    correlation: np.ndarray
    identifiable: dict[str, bool]
    starts: list[tuple[dict[str, float], float]]

    def report(self) -> dict[str, Any]:
        """The ``axojax fit --json`` document."""
        return {
            "params": self.params,
            "achieved": self.achieved,
            "loss": self.loss,
            "converged": self.converged,
            "stderr": self.stderr,
            "residuals": self.residuals,
            "shape_rms": self.shape_rms,
            "identifiable": self.identifiable,
            "correlation": self.correlation.tolist(),
            "message": self.message,
        }


def _latin_hypercube(n: int, k: int, rng: np.random.Generator) -> np.ndarray:
    """n points in [0, 1]^k, one per stratum along every axis."""
    return (np.stack([rng.permutation(n) for _ in range(k)], axis=1) + rng.uniform(size=(n, k))) / n


def fit(
    model: Model,
    params: Params,
    targets: Sequence[Target],
    free: Sequence[str],
    *,
    shape: ShapeTarget | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    kl_ratio: float | None = None,
    units: Units = Units(),
    starts: int = 4,
    method: str = "lbfgs",
    max_steps: int = 80,
    seed: int = 0,
    progress: bool = False,
    solver: EigenSolver = DEFAULT_SOLVER,
    cubic: float = DEFAULT_CUBIC,
    orbit_solver: OrbitSolver = HarmonicBalance(),
) -> FitResult:
    """Fit the ``free`` parameters of ``model`` so that its dominant mode matches ``targets``
    (and ``shape``).

    Args:
        model: e.g. ``ax.models.seven()``.
        params: starting point and fixed values of the other parameters.
        targets: scalar :class:`Target` s (frequency_hz, wavelength_um, ...).
        free: names of the parameters to fit (``Params`` fields).
        shape: optional observed psi_1(s) (:class:`ShapeTarget`, e.g. from
            :func:`axojax.fitting.read_beat`).
        bounds: per-parameter (low, high); defaults in ``DEFAULT_BOUNDS``.
        kl_ratio: tie kl = ks / kl_ratio (then fit ks, not kl).
        units: physical units of the targets.
        starts: number of starts (the given point, then a Latin hypercube in the bounds).
        method: ``"lbfgs"`` (optax.lbfgs with zoom line search) or ``"adam"``.
        max_steps: optimiser iterations per start.
        seed: seed of the start design.
        progress: progress bar over starts.
        solver: dominant-eigenpair solver (:mod:`axojax.eigen.solvers`).
        cubic: link stiffening kappa (1/L^2) of the limit cycle, for targets with
            ``source="limit_cycle"`` (frequency, tip amplitude and wavelength of the
            nonlinear beat, :func:`axojax.orbits.limit_cycle`; differentiable by the
            implicit function theorem). Where no orbit is found (e.g. below the Hopf
            point) such a target's residual is ``CYCLE_FAILED``.
        orbit_solver: the periodic-orbit solver (:mod:`axojax.orbits.solvers`).
    """
    free = list(free)
    targets = list(targets)
    if not free:
        raise ValueError("free: name at least one parameter to fit")
    for name in free:
        if name not in PARAM_NAMES:
            raise ValueError(f"free: unknown parameter {name!r}; choose from {', '.join(PARAM_NAMES)}")
    if kl_ratio is not None and "kl" in free:
        raise ValueError("free: kl is tied to ks by kl_ratio; fit ks instead")
    if not targets and shape is None:
        raise ValueError("targets: give at least one target or a shape")
    if method not in ("lbfgs", "adam"):
        raise ValueError(f"method must be 'lbfgs' or 'adam', got {method!r}")
    if starts < 1:
        raise ValueError(f"starts must be >= 1, got {starts}")
    cycle_targets = [t for t in targets if t.source == "limit_cycle"]
    if cycle_targets:
        if not (math.isfinite(cubic) and cubic > 0):
            raise ValueError(f"cubic must be a finite number > 0 for limit-cycle targets, got {cubic!r}")
        if model.link_B.shape[0] == 0:
            raise ValueError(f"limit-cycle targets need a model with links; {model.name!r} has none")
        if getattr(orbit_solver, "floquet", 0):
            orbit_solver = dataclasses.replace(orbit_solver, floquet=0)  # stability is not fitted: skip it
    params.validate()
    bounds = {**DEFAULT_BOUNDS, **(bounds or {})}
    lo, hi, log = [], [], []
    for name in free:
        a, b = (float(v) for v in bounds[name])
        is_log = name not in LINEAR
        if not (a < b) or (is_log and a <= 0):
            raise ValueError(f"bounds of {name} must satisfy 0 < low < high (log) or low < high, got ({a:g}, {b:g})")
        lo.append(math.log(a) if is_log else a)
        hi.append(math.log(b) if is_log else b)
        log.append(is_log)
    lo, hi, log = jnp.asarray(lo), jnp.asarray(hi), jnp.asarray(log)

    def to_params(u):
        values = jnp.where(log, jnp.exp(u), u)
        return params.with_values(dict(zip(free, values)), kl_ratio)

    def residuals(u):
        prm = to_params(u)
        mode = _dominant_mode_impl(model, prm, solver) if (shape is not None or len(cycle_targets) < len(targets)) else None
        cycle = orbit_solver.solve(model, prm, cubic) if cycle_targets else None
        return _residuals(model, mode, cycle, targets, shape, units)

    def u_of_z(z):
        return lo + (hi - lo) * jax.nn.sigmoid(z)

    def loss(z):
        return 0.5 * jnp.sum(residuals(u_of_z(z)) ** 2)

    run = jax.jit(_optimiser(loss, method, max_steps))
    u0 = np.array([math.log(float(getattr(params, n))) if n not in LINEAR else float(getattr(params, n)) for n in free])
    u0 = np.clip(u0, np.asarray(lo) + 1e-9 * (np.asarray(hi) - np.asarray(lo)), np.asarray(hi) - 1e-9 * (np.asarray(hi) - np.asarray(lo)))
    design = np.asarray(lo) + (np.asarray(hi) - np.asarray(lo)) * _latin_hypercube(starts - 1, len(free), np.random.default_rng(seed))
    initial = np.vstack([u0[None], design])
    results = []
    for u in tqdm(initial, desc="fit starts", unit="start", disable=not progress):
        frac = np.clip((u - np.asarray(lo)) / (np.asarray(hi) - np.asarray(lo)), 1e-9, 1 - 1e-9)
        z, value, gnorm = run(jnp.asarray(np.log(frac / (1 - frac))))
        value = float(value)
        results.append((np.asarray(z), value if math.isfinite(value) else math.inf, float(gnorm)))
    best = min(range(len(results)), key=lambda i: results[i][1])
    z_best, loss_best, gnorm = results[best]
    u_best = u_of_z(jnp.asarray(z_best))
    return _summarise(model, free, log, u_best, to_params, residuals, targets, shape, units, loss_best, gnorm, solver, (cubic, orbit_solver) if cycle_targets else None,
                      [({n: float(np.exp(v) if lg else v) for n, v, lg in zip(free, u, np.asarray(log))}, r[1]) for u, r in zip(initial, results)])


def _residuals(model, mode, cycle, targets, shape, units):
    """Normalised residuals of the scalar targets (linear mode or limit cycle) and the shape."""
    parts = []
    for t in targets:
        if t.source == "limit_cycle":
            r = (cycle_value(cycle, t.name, units) - t.value) / t.sigma
            parts.append(jnp.where(cycle.converged, r, CYCLE_FAILED))
        else:
            parts.append((scalar_value(mode, t.name, units) - t.value) / t.sigma)
    parts = [jnp.stack(parts)] if parts else []
    if shape is not None:
        parts.append(shape_residuals(model, mode, shape, units))
    return jnp.concatenate(parts)


def _optimiser(loss, method: str, max_steps: int, gtol: float = 1e-6):
    """(z0) -> (z, loss, |grad|) by L-BFGS (stopping when |grad| <= gtol * max(1, loss)) or Adam."""
    if method == "adam":
        opt = optax.adam(0.05)

        def run(z0):
            def body(carry, _):
                z, state = carry
                value, grad = jax.value_and_grad(loss)(z)
                updates, state = opt.update(grad, state, z)
                return (optax.apply_updates(z, updates), state), value

            (z, _), _ = jax.lax.scan(body, (z0, opt.init(z0)), None, length=max_steps)
            value, grad = jax.value_and_grad(loss)(z)
            return z, value, jnp.linalg.norm(grad)

        return run

    opt = optax.lbfgs()
    value_and_grad = optax.value_and_grad_from_state(loss)

    def run(z0):
        def cond(carry):
            z, state, k, gnorm, value = carry
            return (k < max_steps) & (gnorm > gtol * jnp.maximum(1.0, value)) & jnp.isfinite(gnorm)

        def body(carry):
            z, state, k, _, _ = carry
            value, grad = value_and_grad(z, state=state)
            updates, state = opt.update(grad, state, z, value=value, grad=grad, value_fn=loss)
            return optax.apply_updates(z, updates), state, k + 1, jnp.linalg.norm(grad), value

        init = (z0, opt.init(z0), 0, jnp.asarray(1e300), jnp.asarray(1e300))
        z, _, _, _, _ = jax.lax.while_loop(cond, body, init)
        value, grad = jax.value_and_grad(loss)(z)
        return z, value, jnp.linalg.norm(grad)

    return run


def _summarise(model, free, log, u, to_params, residuals, targets, shape, units, loss, gnorm, solver, cycle_setup, starts) -> FitResult:
    log = np.asarray(log)
    full = to_params(u)
    mode = jax.jit(_dominant_mode_impl, static_argnums=(0, 2))(model, full, solver)
    achieved = {k: float(scalar_value(mode, k, units)) for k in SCALARS}
    n_scalar = len(targets)

    def final(u):
        # One compiled program for the residuals, their Jacobian and the cycle's measures.
        out = {"r": residuals(u), "J": jax.jacfwd(residuals)(u)}  # d r / d u (u: log or linear)
        if cycle_setup is not None:
            cubic, orbit_solver = cycle_setup
            cycle = orbit_solver.solve(model, to_params(u), cubic)
            out["cycle"] = {k: cycle_value(cycle, k, units) for k in ("frequency_hz", "amplitude_um", "wavelength_um")}
            out["converged"] = cycle.converged
        return out

    out = jax.jit(final)(u)
    if cycle_setup is not None:
        for k, v in out["cycle"].items():
            achieved[f"limit_cycle_{k}"] = float(v) if bool(out["converged"]) else math.nan
    r, J = np.asarray(out["r"]), np.asarray(out["J"])
    res = {t.key: float(v) for t, v in zip(targets, r[:n_scalar])}
    shape_rms = float(np.sqrt(np.mean(r[n_scalar:] ** 2))) if shape is not None else None

    fisher = J.T @ J
    if np.all(np.isfinite(fisher)):
        # Tiny ridge: a singular direction gets a huge (finite) variance, flagged below.
        ridge = 1e-12 * max(float(np.abs(fisher).max()), 1e-300)
        cov = np.linalg.inv(fisher + ridge * np.eye(len(free)))
    else:
        cov = np.full_like(fisher, np.inf)
    se_u = np.sqrt(np.abs(np.diag(cov)))
    values = np.where(log, np.exp(np.asarray(u)), np.asarray(u))
    stderr = {n: float(values[i] * se_u[i] if log[i] else se_u[i]) for i, n in enumerate(free)}
    identifiable = {n: bool(np.isfinite(se_u[i]) and (se_u[i] <= IDENTIFIABLE_MAX_LOG_SE if log[i] else True)) for i, n in enumerate(free)}
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se_u, se_u)
    corr = np.where(np.isfinite(corr), corr, np.nan)

    reproduced = all(abs(v) <= 1.0 for v in res.values()) and (shape_rms is None or shape_rms <= SHAPE_RMS_OK)
    converged = bool(reproduced and math.isfinite(loss))
    if not reproduced:
        off = [f"{t.key} {achieved[t.key]:.4g} vs {t.value:.4g} +- {t.sigma:.3g} ({res[t.key]:+.1f} sigma)" for t in targets if abs(res[t.key]) > 1.0]
        if shape_rms is not None and shape_rms > SHAPE_RMS_OK:
            off.append(f"mode shape rms residual {shape_rms:.2f} sigma")
        message = "targets not reproduced within their uncertainty (infeasible for this model and bounds?): " + "; ".join(off)
        warnings.warn(message, stacklevel=3)
    else:
        message = f"targets reproduced (loss {loss:.3g}, |grad| {gnorm:.2g})"
    bad = [n for n, ok in identifiable.items() if not ok]
    if bad:
        note = f"not identifiable from these targets: {', '.join(bad)} (standard error over a factor e); fix them or add targets"
        warnings.warn(note, stacklevel=3)
        message += "; " + note
    return FitResult(
        params={n: float(v) for n, v in zip(free, values)},
        full_params=full,
        achieved=achieved,
        residuals=res,
        shape_rms=shape_rms,
        loss=float(loss),
        converged=converged,
        message=message,
        stderr=stderr,
        correlation=corr,
        identifiable=identifiable,
        starts=starts,
    )
