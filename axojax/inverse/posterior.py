"""``posterior``: Bayesian posterior of an inverse problem's free parameters by NUTS.

The sampler runs in the problem's unconstrained coordinate ``z`` (R^k), where
``problem.log_density(z)`` is the log posterior: ``-1/2 |residuals(u)|^2 + log_prior(u)``
plus the log-Jacobian of the logistic map ``u = to_u(z)`` onto the bounds of the fitted
coordinate ``u`` (log of positive parameters, linear for ``gamma``). The prior is
therefore stated in ``u``: uniform between the bounds by default (the problem's
``log_prior``), or replaced here (a callable ``log_prior(u)``, or a normal in ``u`` per
parameter: :func:`normal_prior`).

Sampler: the No-U-Turn sampler of blackjax (``blackjax.nuts``) with Stan's window
adaptation (``blackjax.window_adaptation``: dual-averaged step size, mass matrix from
the warm-up draws). blackjax rather than numpyro because the model is already a pure
jax function of ``z``: blackjax takes that log density as it is, exposes the kernel to
``jax.vmap``/``lax.scan`` (chains vmapped, steps scanned, all inside one ``jit``), and
adds no model language, tracing runtime or handlers on top of axojax's own derivatives.

Chains: every chain adapts its own step size and mass matrix (Stan's convention: the
chains stay independent, so R-hat compares independent runs), the warm-ups vmapped
together, then the NUTS kernels of all chains are vmapped and stepped with
``jax.lax.scan``. They start from the maximum of the posterior density (optimistix
Levenberg-Marquardt in ``z`` from ``problem.u0``, then Gauss-Newton steps on the whole
density) and a spread around it drawn from its Laplace approximation (Gauss-Newton
``J^T J`` plus the prior's and the map's curvature). The sampler runs in coordinates
whitened by that approximation (``w = L^-1 (z - z_c)``, ``L L^T`` its covariance: an
affine map, so the same posterior), where the adaptation starts from the identity:
on the benchmark's sloppy model it took about 8x fewer gradients per effective
sample than sampling in z (one short run each: ``benchmarks/bench_posterior.py``).

Result: :class:`Posterior` (draws per chain in ``u`` and in parameter values, mean, sd,
5/50/95 % quantiles, rank-normalised R-hat and bulk/tail ESS per parameter, divergences,
timings) with ``to_json()`` (the ``"posterior"`` block of ``axojax fit --posterior``)
and ``save(path)`` (an ``.npz`` that :func:`axojax.plotting.corner.plot_corner` draws).
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any, Protocol, runtime_checkable

import blackjax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
from jaxtyping import Array, Float
from tqdm.auto import tqdm

from . import diagnostics

NPZ_KIND = "posterior"
SAMPLE_CHUNK = 50  # draws per compiled sampling call: one program for any number of draws (the last chunk's surplus is dropped)
CENTRE_NEWTON_STEPS = (
    3  # Gauss-Newton steps on the whole log density after Levenberg-Marquardt (a non-uniform prior)
)
MAX_START_SD_Z = 2.0  # widest start spread in z: about the logistic prior's own width (pi / sqrt 3)


@runtime_checkable
class InverseProblem(Protocol):
    """What :func:`posterior` needs of a problem (:class:`axojax.inverse.Problem` has it).

    Attributes:
        names: labels of the k fitted values.
        lower, upper: (k,) bounds in the fitted coordinate ``u`` (log for positive
            parameters, linear for gamma).
        u0: (k,) starting point in ``u``.
    Methods (all jax-traceable except ``values`` needs only be vmappable):
        residuals(u) -> (m,) normalised residuals;
        log_prior(u) -> () log prior density in ``u`` (0: uniform);
        to_u(z), to_z(u): the logistic map between z in R^k and u within the bounds;
        log_density(z) -> () = -1/2 |residuals(to_u(z))|^2 + log_prior(to_u(z)) + log|du/dz|;
        values(u) -> {name: dimensionless value}.
    """

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    u0: np.ndarray

    def residuals(self, u: Float[Array, " k"]) -> Float[Array, " m"]: ...

    def log_prior(self, u: Float[Array, " k"]) -> Float[Array, ""]: ...

    def to_u(self, z: Float[Array, " k"]) -> Float[Array, " k"]: ...

    def to_z(self, u: Float[Array, " k"]) -> Float[Array, " k"]: ...

    def log_density(self, z: Float[Array, " k"]) -> Float[Array, ""]: ...

    def values(self, u: Float[Array, " k"]) -> Mapping[str, Float[Array, ""]]: ...


class NUTS(eqx.Module):
    """The No-U-Turn sampler (blackjax) and its window adaptation.

    Attributes:
        max_num_doublings: tree depth limit (at most ``2**max_num_doublings - 1``
            gradients per draw).
        target_acceptance_rate: the step-size adaptation's target (Stan: 0.8; raise it
            towards 0.95 when there are divergences).
        dense_mass: adapt a dense mass matrix (default: the fitted parameters of a
            sloppy model are strongly correlated and k is small, so the k x k
            covariance costs nothing and removes the correlation); ``False``: diagonal.
        divergence_threshold: energy error above which a trajectory counts as divergent.
        whiten: sample in ``w = L^-1 (z - z_c)``, where ``z_c`` is the centre of the
            starts and ``L L^T`` the Laplace covariance there (an affine map: its
            Jacobian is a constant, the posterior is exactly the same). The adaptation
            then starts from a near-identity covariance, whose scale its regularisation
            (blackjax/Stan shrink the estimated covariance towards ``1e-3 I``) does not
            distort; in z a sloppy model's stiffest direction has an sd of ~1e-3, which
            that shrinkage inflates several-fold, forcing small steps (measured: see
            ``benchmarks/bench_posterior.py``).
    """

    max_num_doublings: int = 8
    target_acceptance_rate: float = 0.8
    dense_mass: bool = True
    divergence_threshold: float = 1000.0
    whiten: bool = True

    def __check_init__(self):
        if not (1 <= self.max_num_doublings <= 15):
            raise ValueError(
                f"NUTS: max_num_doublings must be in 1..15, got {self.max_num_doublings}"
            )
        if not (0.0 < self.target_acceptance_rate < 1.0):
            raise ValueError(
                f"NUTS: target_acceptance_rate must be in (0, 1), got {self.target_acceptance_rate}"
            )


class NormalPrior(eqx.Module):
    """A log prior in ``u``: independent normals (``mean``, ``sd`` in the fitted
    coordinate, e.g. the natural log of ks) on the parameters at ``index``, uniform
    (within the bounds) on the others. Build it with :func:`normal_prior`."""

    index: tuple[int, ...] = eqx.field(static=True)
    mean: Float[Array, " j"]
    sd: Float[Array, " j"]

    def __call__(self, u: Float[Array, " k"]) -> Float[Array, ""]:
        return -0.5 * jnp.sum(((u[jnp.asarray(self.index)] - self.mean) / self.sd) ** 2)


DEFAULT_NUTS = NUTS()


def normal_prior(names: Sequence[str], spec: Mapping[str, tuple[float, float]]) -> NormalPrior:
    """:class:`NormalPrior` from ``{name: (mean_u, sd_u)}`` over the free parameters ``names``."""
    names = list(names)
    for name, (mu, sd) in spec.items():
        if name not in names:
            raise ValueError(
                f"prior: {name!r} is not a free parameter; choose from {', '.join(names)}"
            )
        if not (math.isfinite(mu) and math.isfinite(sd) and sd > 0):
            raise ValueError(f"prior: {name} needs a finite mean and sd > 0, got ({mu!r}, {sd!r})")
    return NormalPrior(
        index=tuple(names.index(n) for n in spec),
        mean=jnp.asarray([float(spec[n][0]) for n in spec]),
        sd=jnp.asarray([float(spec[n][1]) for n in spec]),
    )


class ScaledSigmas(eqx.Module):
    """``problem`` with every uncertainty (sigma) multiplied by ``factor``: residuals
    divided by it, the likelihood tempered by ``1 / factor**2``; prior, bounds and
    coordinates unchanged. An :class:`InverseProblem` that :func:`posterior` samples.

    The use: a model that misfits (chi^2/dof well above 1) gets a posterior too narrow
    for what its data say, because its width assumes the residuals are noise of the
    stated size. ``ScaledSigmas(problem, sqrt(chi2/dof))`` (the Birge ratio) rescales the
    noise to the observed misfit, as scipy's ``curve_fit`` does by default
    (``absolute_sigma=False``): a cruder but more honest width. ``factor`` is an array
    leaf, so posteriors of one problem with different factors share their compilation.
    """

    problem: Any
    factor: Float[Array, ""]

    def __init__(self, problem: InverseProblem, factor: float):
        if not (math.isfinite(float(factor)) and float(factor) > 0):
            raise ValueError(f"ScaledSigmas: factor must be a finite number > 0, got {factor!r}")
        self.problem = problem
        self.factor = jnp.asarray(float(factor))

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.problem.names)

    @property
    def lower(self) -> np.ndarray:
        return self.problem.lower

    @property
    def upper(self) -> np.ndarray:
        return self.problem.upper

    @property
    def u0(self) -> np.ndarray:
        return self.problem.u0

    def residuals(self, u: Float[Array, " k"]) -> Float[Array, " m"]:
        return self.problem.residuals(u) / self.factor

    def log_prior(self, u: Float[Array, " k"]) -> Float[Array, ""]:
        return self.problem.log_prior(u)

    def to_u(self, z: Float[Array, " k"]) -> Float[Array, " k"]:
        return self.problem.to_u(z)

    def to_z(self, u: Float[Array, " k"]) -> Float[Array, " k"]:
        return self.problem.to_z(u)

    def log_density(self, z: Float[Array, " k"]) -> Float[Array, ""]:
        """-|residuals / factor|^2 / 2 + log prior(u) + log|du/dz| (one model evaluation)."""
        u = self.problem.to_u(z)
        log_jac = jnp.linalg.slogdet(jax.jacfwd(self.problem.to_u)(z))[1]
        return -0.5 * jnp.sum(self.residuals(u) ** 2) + self.problem.log_prior(u) + log_jac

    def values(self, u: Float[Array, " k"]) -> Mapping[str, Float[Array, ""]]:
        return self.problem.values(u)


class _Target(eqx.Module):
    """The log density sampled, in z: the problem's, with its prior replaced by ``prior``
    when given; NaN (a failed model evaluation) reads as -inf (a rejected proposal)."""

    problem: Any
    prior: Any = None

    def __call__(self, z: Float[Array, " k"]) -> Float[Array, ""]:
        lp = self.problem.log_density(z)
        if self.prior is not None:
            u = self.problem.to_u(z)
            lp = lp - self.problem.log_prior(u) + self.prior(u)
        return jnp.where(jnp.isnan(lp), -jnp.inf, lp)

    def log_prior(self, u: Float[Array, " k"]) -> Float[Array, ""]:
        return self.problem.log_prior(u) if self.prior is None else self.prior(u)


class _Whitened(eqx.Module):
    """``target`` in whitened coordinates: ``w -> target(centre + chol @ w)`` (the
    constant log-Jacobian left out: it changes no ratio of densities)."""

    target: _Target
    centre: Float[Array, " k"]
    chol: Float[Array, "k k"]

    def __call__(self, w: Float[Array, " k"]) -> Float[Array, ""]:
        return self.target(self.to_z(w))

    def to_z(self, w: Float[Array, "*batch k"]) -> Float[Array, "*batch k"]:
        return self.centre + w @ self.chol.T

    def to_w(self, z: Float[Array, "*batch k"]) -> Float[Array, "*batch k"]:
        return jax.scipy.linalg.solve_triangular(self.chol, (z - self.centre).T, lower=True).T


@dataclasses.dataclass(frozen=True)
class Posterior:
    """Draws of a posterior and their summaries.

    Attributes:
        names: the k free parameters.
        u: (chains, draws, k) draws in the fitted coordinate (log or linear).
        value_names: names of ``values``' last axis (the free parameters first, then
            anything else ``problem.values`` reports, e.g. a tied kl).
        values: (chains, draws, n_values) the same draws as dimensionless parameter values.
        log_density: (chains, draws) log posterior density (in z) of each draw.
        divergent: (chains, draws) whether the draw's trajectory diverged.
        lower, upper: (k,) bounds in ``u``.
        log_coordinate: per name, whether ``u`` is the natural log of the value.
        mean, sd, q05, q50, q95: per name, of the parameter values (pooled over chains).
        mean_u, sd_u: per name, in the fitted coordinate (compare ``sd_u`` with the
            uniform prior's ``(upper - lower) / sqrt(12)``).
        rhat: per name, rank-normalised split R-hat (:mod:`.diagnostics`).
        ess, ess_tail: per name, bulk and tail effective sample size (total over chains).
        divergences: divergent transitions after warm-up (all chains).
        step_size: (chains,) adapted step sizes (in the whitened coordinates unless
            ``NUTS(whiten=False)``); acceptance: mean acceptance rate.
        warmup: warm-up steps per chain.
        gradients: gradient evaluations (leapfrog steps) of all chains, warm-up included.
        seconds: wall time of the whole call (compilation, optimisation, warm-up, sampling).
        seconds_compile: the part spent compiling (0 when a problem of the same structure
            was sampled before in this process: compiled programs are cached).
        seconds_start, seconds_warmup, seconds_sampling: wall time of the starts (mode
            and Laplace approximation), of the warm-up and of the draws (each with its
            compilation, if any).
        seconds_per_gradient: seconds of the warm-up and the draws, less their
            compilation, over ``gradients`` (vmapped chains evaluate theirs together).
        seconds_per_ess: seconds / the smallest bulk ESS.
        start_u: (k,) centre of the starts (the posterior mode unless ``init`` was given).
        message: warnings raised (R-hat, ESS, divergences), or "ok".
    """

    names: tuple[str, ...]
    u: np.ndarray
    value_names: tuple[str, ...]
    values: np.ndarray
    log_density: np.ndarray
    divergent: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    log_coordinate: dict[str, bool]
    mean: dict[str, float]
    sd: dict[str, float]
    q05: dict[str, float]
    q50: dict[str, float]
    q95: dict[str, float]
    mean_u: dict[str, float]
    sd_u: dict[str, float]
    rhat: dict[str, float]
    ess: dict[str, float]
    ess_tail: dict[str, float]
    divergences: int
    step_size: np.ndarray
    acceptance: float
    warmup: int
    gradients: int
    seconds: float
    seconds_compile: float
    seconds_start: float
    seconds_warmup: float
    seconds_sampling: float
    seconds_per_gradient: float
    seconds_per_ess: float
    start_u: np.ndarray
    message: str

    @property
    def chains(self) -> int:
        return int(self.u.shape[0])

    @property
    def draws(self) -> int:
        """Draws per chain."""
        return int(self.u.shape[1])

    def value_draws(self, name: str) -> np.ndarray:
        """(chains, draws) draws of one parameter value."""
        return self.values[..., self.value_names.index(name)]

    @property
    def start(self) -> dict[str, float]:
        """The centre of the starts as parameter values (the posterior mode by default)."""
        return {
            n: float(math.exp(v) if self.log_coordinate[n] else v)
            for n, v in zip(self.names, self.start_u)
        }

    def to_json(self) -> dict[str, Any]:
        """The ``"posterior"`` block of ``axojax fit --posterior --json`` (INTERFACE.md):
        ``draws`` (per chain), ``chains``, ``mean``, ``sd``, ``q05``, ``q95``, ``rhat``,
        ``ess`` (bulk), ``seconds``; also ``q50``, ``ess_tail``, ``divergences``,
        ``warmup``, ``seconds_per_gradient``, ``seconds_per_ess``, ``message``."""
        return {
            "draws": self.draws,
            "chains": self.chains,
            "mean": dict(self.mean),
            "sd": dict(self.sd),
            "q05": dict(self.q05),
            "q50": dict(self.q50),
            "q95": dict(self.q95),
            "rhat": dict(self.rhat),
            "ess": dict(self.ess),
            "ess_tail": dict(self.ess_tail),
            "divergences": self.divergences,
            "warmup": self.warmup,
            "seconds": self.seconds,
            "seconds_per_gradient": self.seconds_per_gradient,
            "seconds_per_ess": self.seconds_per_ess,
            "message": self.message,
        }

    def save(self, path, *, truth: Mapping[str, float] | None = None) -> None:
        """Write an ``.npz`` for ``axojax plot`` (corner plot): arrays ``u``, ``values``,
        ``log_density``, ``divergent``, ``lower``, ``upper``, ``step_size``, ``start_u``
        and a ``meta`` JSON string (``kind = "posterior"``, the names, the scalar
        summaries, optional ``truth`` {name: value} drawn as markers)."""
        meta = {
            "kind": NPZ_KIND,
            "names": list(self.names),
            "value_names": list(self.value_names),
            "log_coordinate": self.log_coordinate,
            "truth": None if truth is None else {k: float(v) for k, v in truth.items()},
            **{
                f.name: getattr(self, f.name)
                for f in dataclasses.fields(self)
                if f.name in _SCALAR_FIELDS
            },
        }
        from .._io import atomic_path

        with atomic_path(path) as tmp:  # a killed run leaves no half-written file
            with open(tmp, "wb") as f:
                np.savez(
                    f,
                    meta=json.dumps(meta),
                    **{name: np.asarray(getattr(self, name)) for name in _ARRAY_FIELDS},
                )

    @classmethod
    def load(cls, path) -> Posterior:
        """Read what :meth:`save` wrote."""
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            if meta.get("kind") != NPZ_KIND:
                raise ValueError(
                    f"{str(path)!r} is not an axojax posterior (kind {meta.get('kind')!r})"
                )
            arrays = {name: np.asarray(f[name]) for name in _ARRAY_FIELDS}
        scalars = {k: meta[k] for k in _SCALAR_FIELDS}
        return cls(
            names=tuple(meta["names"]),
            value_names=tuple(meta["value_names"]),
            log_coordinate=meta["log_coordinate"],
            **scalars,
            **arrays,
        )


_ARRAY_FIELDS = (
    "u",
    "values",
    "log_density",
    "divergent",
    "lower",
    "upper",
    "step_size",
    "start_u",
)
_SCALAR_FIELDS = (
    "mean",
    "sd",
    "q05",
    "q50",
    "q95",
    "mean_u",
    "sd_u",
    "rhat",
    "ess",
    "ess_tail",
    "divergences",
    "acceptance",
    "warmup",
    "gradients",
    "seconds",
    "seconds_compile",
    "seconds_start",
    "seconds_warmup",
    "seconds_sampling",
    "seconds_per_gradient",
    "seconds_per_ess",
    "message",
)


def load_truth(path) -> dict[str, float] | None:
    """The ``truth`` markers stored by :meth:`Posterior.save` (None if none)."""
    with np.load(path, allow_pickle=False) as f:
        return json.loads(str(f["meta"])).get("truth")


def posterior(
    problem: InverseProblem,
    *,
    draws: int = 1000,
    chains: int = 4,
    warmup: int = 500,
    seed: int = 0,
    init: Any = None,
    prior: Callable[[Array], Array] | Mapping[str, tuple[float, float]] | None = None,
    sampler: NUTS = DEFAULT_NUTS,
    vectorize: bool = True,
    progress: bool = False,
) -> Posterior:
    """Sample the posterior of ``problem``'s free parameters with NUTS.

    Args:
        problem: an :class:`InverseProblem` (e.g. :class:`axojax.inverse.Problem`).
        draws: draws per chain kept after warm-up.
        chains: independent chains (vmapped unless ``vectorize=False``).
        warmup: window-adaptation steps per chain (Stan's schedule; at least 150 gives
            its full set of windows), discarded.
        seed: seed of the chains and their starts.
        init: where the chains start. ``None``: the posterior mode (Levenberg-Marquardt
            in ``z`` from ``problem.u0``) and a spread drawn from its Laplace approximation;
            a (k,) point in ``u``, or a least-squares result
            (:func:`axojax.inverse.least_squares`' ``FitResult``, its optimum): a spread
            around it; a (chains, k) array in ``u``: these starts exactly.
        prior: replaces ``problem.log_prior``: a jax-traceable ``log_prior(u)``, or
            ``{name: (mean_u, sd_u)}`` (:func:`normal_prior`). ``None``: the problem's
            own prior (uniform in ``u`` by default).
        sampler: :class:`NUTS` settings.
        vectorize: run the chains vmapped (they step together, each NUTS step costing
            the longest of the chains' trajectories; batched model evaluations), or,
            ``False``, one after another inside the same compiled program (each chain
            pays only for its own trajectories: faster where a batch of k model
            evaluations costs k single ones, e.g. LAPACK-bound eigen-solves on few cores).
        progress: a progress bar over the sampling (tqdm).

    Returns:
        :class:`Posterior`. Warns (one line each) when a parameter's R-hat exceeds
        ``diagnostics.RHAT_MAX`` (1.01), when its bulk or tail ESS is below
        ``diagnostics.ESS_MIN_PER_CHAIN`` (100) per chain, or when transitions diverged.
    """
    t_start = time.perf_counter()
    names = tuple(problem.names)
    k = len(names)
    lower = np.asarray(problem.lower, dtype=float).reshape(-1)
    upper = np.asarray(problem.upper, dtype=float).reshape(-1)
    if k == 0 or lower.shape != (k,) or upper.shape != (k,):
        raise ValueError(
            f"problem: names, lower and upper must have one entry per free parameter, got {k}, {lower.shape}, {upper.shape}"
        )
    for name, value in (("draws", draws), ("chains", chains)):
        if not (isinstance(value, (int, np.integer)) and value >= 1):
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if draws < 4:
        raise ValueError(f"draws must be >= 4 (R-hat splits each chain), got {draws}")
    if not (isinstance(warmup, (int, np.integer)) and warmup >= 0):
        raise ValueError(f"warmup must be an integer >= 0, got {warmup!r}")
    if not isinstance(sampler, NUTS):
        raise TypeError(f"sampler must be an axojax.inverse.NUTS, got {type(sampler).__name__}")
    if isinstance(prior, Mapping):
        prior = normal_prior(names, prior)
    elif prior is not None and not callable(prior):
        raise TypeError(
            f"prior must be a callable log_prior(u), a {{name: (mean_u, sd_u)}} mapping or None, got {type(prior).__name__}"
        )
    target = _Target(problem, prior)
    compile_s = [0.0]

    def call(fn, static, *dynamic):
        out, seconds = _compiled(fn, static, dynamic)
        compile_s[0] += seconds
        return out

    key_init, key_warm, key_sample = jax.random.split(jax.random.PRNGKey(seed), 3)
    t0 = time.perf_counter()
    z_start, z_c, cov, start_u = _starts(target, init, chains, key_init, call)
    seconds_start = time.perf_counter() - t0
    compile_start = compile_s[0]

    t0 = time.perf_counter()
    if sampler.whiten:  # sample w = L^-1 (z - z_c): the Laplace covariance becomes the identity
        sampled = _Whitened(target, z_c, jnp.linalg.cholesky(cov))
        x_start, x_c, cov_x = sampled.to_w(z_start), jnp.zeros(k), jnp.eye(k)
    else:
        sampled, x_start, x_c, cov_x = target, z_start, z_c, cov
    imm0 = cov_x if sampler.dense_mass else jnp.diag(cov_x)
    if warmup > 0:
        states, step_size, imm, warm_grads = call(
            _warmup,
            (sampler, int(warmup), bool(vectorize)),
            sampled,
            jax.random.split(key_warm, chains),
            x_start,
            x_c,
            imm0,
        )
    else:  # no adaptation: the Laplace covariance as mass matrix, a moderate step
        states = call(_init_states, None, sampled, x_start, x_c)
        step_size = jnp.full(chains, 0.5)
        imm = jnp.broadcast_to(imm0, (chains, *imm0.shape))
        warm_grads = jnp.zeros(chains, dtype=int)
    jax.block_until_ready(states)
    seconds_warmup = time.perf_counter() - t0

    chunk = SAMPLE_CHUNK
    n_chunks = -(-draws // chunk)
    keys = jax.random.split(key_sample, n_chunks * chains * chunk).reshape(
        n_chunks, chains, chunk, -1
    )
    t0 = time.perf_counter()
    outs = []
    for i in tqdm(range(n_chunks), desc="posterior", unit="chunk", disable=not progress):
        states, out = call(
            _sample, (sampler, bool(vectorize)), sampled, states, step_size, imm, keys[i]
        )
        outs.append(jax.device_get(out))
    seconds_sampling = time.perf_counter() - t0
    compile_chains = compile_s[0] - compile_start
    z, logd, divergent, n_steps, accept = (
        np.concatenate([o[j] for o in outs], axis=1)[:, :draws] for j in range(5)
    )
    if sampler.whiten:
        z = np.asarray(sampled.to_z(jnp.asarray(z)))

    u = np.asarray(call(_to_u, None, target, jnp.asarray(z)))
    values_dict = _values(problem, u.reshape(-1, k), call)
    value_names = list(names) + [n for n in values_dict if n not in names]
    cols = []
    for i, n in enumerate(value_names):
        cols.append(
            np.asarray(values_dict[n], dtype=float).reshape(chains, draws)
            if n in values_dict
            else u[..., i]
        )
    values = np.stack(cols, axis=-1)
    log_coordinate = {
        n: bool(
            np.all(values[..., i] > 0)
            and np.allclose(np.log(values[..., i]), u[..., i], rtol=1e-9, atol=1e-9)
        )
        for i, n in enumerate(names)
    }

    summ = diagnostics.summary(values[..., :k])
    flat_u = u.reshape(-1, k)
    gradients = int(np.sum(warm_grads)) + int(np.sum(n_steps))
    seconds = time.perf_counter() - t_start
    ess_min = float(np.min(summ["ess_bulk"]))
    per = lambda key: {n: float(summ[key][i]) for i, n in enumerate(names)}

    notes = []
    bad_rhat = [
        f"{n} {summ['rhat'][i]:.3f}"
        for i, n in enumerate(names)
        if not summ["rhat"][i] <= diagnostics.RHAT_MAX
    ]
    if bad_rhat:
        notes.append(
            f"R-hat above {diagnostics.RHAT_MAX}: {', '.join(bad_rhat)} (chains disagree; run longer or look for several modes)"
        )
    ess_floor = diagnostics.ESS_MIN_PER_CHAIN * chains
    low = [
        f"{n} {min(summ['ess_bulk'][i], summ['ess_tail'][i]):.0f}"
        for i, n in enumerate(names)
        if not min(summ["ess_bulk"][i], summ["ess_tail"][i]) >= ess_floor
    ]
    if low:
        notes.append(
            f"effective sample size below {ess_floor} ({diagnostics.ESS_MIN_PER_CHAIN} per chain): {', '.join(low)} (run more draws)"
        )
    n_div = int(np.sum(divergent))
    if n_div:
        notes.append(
            f"{n_div} divergent transitions of {chains * draws} (try NUTS(target_acceptance_rate=0.95), or check the bounds)"
        )
    for note in notes:
        warnings.warn("posterior: " + note, stacklevel=2)
    work = seconds_warmup + seconds_sampling - compile_chains

    return Posterior(
        names=names,
        u=u,
        value_names=tuple(value_names),
        values=values,
        log_density=np.asarray(logd),
        divergent=np.asarray(divergent, dtype=bool),
        lower=lower,
        upper=upper,
        log_coordinate=log_coordinate,
        mean=per("mean"),
        sd=per("sd"),
        q05=per("q05"),
        q50=per("q50"),
        q95=per("q95"),
        mean_u={n: float(v) for n, v in zip(names, flat_u.mean(axis=0))},
        sd_u={n: float(v) for n, v in zip(names, flat_u.std(axis=0, ddof=1))},
        rhat=per("rhat"),
        ess=per("ess_bulk"),
        ess_tail=per("ess_tail"),
        divergences=n_div,
        step_size=np.asarray(step_size, dtype=float),
        acceptance=float(np.mean(accept)),
        warmup=int(warmup),
        gradients=gradients,
        seconds=seconds,
        seconds_compile=compile_s[0],
        seconds_start=seconds_start,
        seconds_warmup=seconds_warmup,
        seconds_sampling=seconds_sampling,
        seconds_per_gradient=work / max(gradients, 1),
        seconds_per_ess=seconds / ess_min if ess_min > 0 else math.inf,
        start_u=start_u,
        message="; ".join(notes) or "ok",
    )


# -- compiled pieces ---------------------------------------------------------------------
# Each runs as fn(static, *dynamic): the arrays of the problem (when it is a pytree, e.g. an
# equinox Module) and of the prior are dynamic, so problems of one structure with other data
# (another seed, another condition) reuse the compiled program (_compiled's cache).


class _Static:
    """A static argument: hashed by value where it can be, else by identity."""

    def __init__(self, obj):
        self.obj = obj
        try:
            self._hash = hash(obj)
            self._by_value = True
        except TypeError:
            self._hash = id(obj)
            self._by_value = False

    def __hash__(self):
        return self._hash

    def __eq__(self, other):
        if not isinstance(other, _Static) or self._by_value != other._by_value:
            return False
        return bool(self.obj == other.obj) if self._by_value else self.obj is other.obj


_CACHE: dict = {}
_CACHE_SIZE = 16


def _compiled(fn, static, dynamic: tuple) -> tuple[Any, float]:
    """``fn(static, *dynamic)`` run by an ahead-of-time compiled program (cached per fn,
    static values and the dynamic arrays' shapes), and the seconds spent compiling."""
    target, *rest = dynamic
    dyn, stat = eqx.partition(target, eqx.is_array)
    leaves, treedef = jax.tree.flatten((dyn, rest))
    key = (
        fn,
        _Static((stat, static)),
        treedef,
        tuple((jnp.shape(x), jnp.result_type(x)) for x in leaves),
    )
    seconds = 0.0
    if key not in _CACHE:
        t0 = time.perf_counter()

        def run(static_, dyn_, rest_):
            stat_, fixed = static_.obj
            return fn(fixed, eqx.combine(dyn_, stat_), *rest_)

        _CACHE[key] = (
            jax.jit(run, static_argnums=0).lower(_Static((stat, static)), dyn, rest).compile()
        )
        seconds = time.perf_counter() - t0
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
    return _CACHE[key](dyn, rest), seconds


def _logistic_residuals(z: Float[Array, " k"]) -> Float[Array, " k"]:
    """Pseudo-residuals ``q`` of the logistic map's log-Jacobian: ``-|q|^2 / 2`` equals
    ``sum(log sigmoid(z) + log sigmoid(-z)) + k log 4`` exactly (``q`` smooth, ``q ~ z / sqrt 2``
    near 0), so ``-|(r, q)|^2 / 2`` is the log density in z of a uniform prior up to a constant."""
    excess = jnp.logaddexp(0.0, z) + jnp.logaddexp(0.0, -z) - jnp.log(4.0)  # >= 0, ~ z^2 / 4 at 0
    return jnp.sign(z) * jnp.sqrt(2.0 * jnp.maximum(excess, 0.0))


def _centre(settings, target, z0):
    """The centre of the starts and the Laplace precision (k, k) in z there, in one
    program: with ``optimise``, the maximum of the log density from ``z0``:
    Levenberg-Marquardt (optimistix) on the residuals and the logistic map's
    pseudo-residuals (:func:`_logistic_residuals`: the exact log density in z for a
    uniform prior; a sloppy ridge costs it a few dozen steps, where BFGS stalled on the
    benchmark's), then Gauss-Newton steps on the whole log density (a non-uniform prior),
    each kept only if it raises the density; ``z0`` itself if nothing does. Without
    ``optimise``, ``z0``. The precision is the Gauss-Newton ``J^T J`` of the residuals
    minus the Hessian of the log prior and of the log-Jacobian of ``to_u`` (``forward``:
    J by forward mode, else reverse)."""
    optimise, forward = settings
    problem = target.problem

    def r(z):
        return problem.residuals(problem.to_u(z))

    def rest(z):
        return (
            target.log_prior(problem.to_u(z)) + jnp.linalg.slogdet(jax.jacfwd(problem.to_u)(z))[1]
        )

    def precision(z):
        J = (jax.jacfwd if forward else jax.jacrev)(r)(z)
        return J.T @ J - jax.hessian(rest)(z)

    def better(z_new, z_old):
        return jnp.all(jnp.isfinite(z_new)) & (target(z_new) >= target(z_old))

    if optimise:
        lm = optx.least_squares(
            lambda z, _: jnp.concatenate([r(z), _logistic_residuals(z)]),
            optx.LevenbergMarquardt(rtol=1e-8, atol=1e-8),
            z0,
            max_steps=200,
            throw=False,
        )
        z0 = jnp.where(better(lm.value, z0), lm.value, z0)

        def newton(_, z):
            step = jnp.linalg.solve(precision(z), jax.grad(target)(z))
            return jnp.where(better(z + step, z), z + step, z)

        z0 = jax.lax.fori_loop(0, CENTRE_NEWTON_STEPS, newton, z0)
    return z0, precision(z0)


def _finite_starts(target, z, z_c):
    """Starts where the log density is finite; the others moved to the centre ``z_c``."""
    ok = jnp.isfinite(jax.vmap(target)(z))
    return jnp.where(ok[:, None], z, z_c)


def _warmup(settings, target, keys, z0, z_c, imm0):
    """Window adaptation of every chain (vmapped or mapped) from ``z0`` (a start with a
    non-finite density moved to ``z_c``): final states, step sizes, inverse mass matrices
    and the gradients spent per chain."""
    sampler, num_steps, vectorize = settings
    z0 = _finite_starts(target, z0, z_c)
    adapt = blackjax.window_adaptation(
        blackjax.nuts,
        target,
        is_mass_matrix_diagonal=not sampler.dense_mass,
        initial_inverse_mass_matrix=imm0,
        target_acceptance_rate=sampler.target_acceptance_rate,
        adaptation_info_fn=blackjax.adaptation.base.get_filter_adapt_info_fn(
            info_keys={"num_integration_steps"}
        ),
        max_num_doublings=sampler.max_num_doublings,
    )

    def one(key, z):
        (state, params), info = adapt.run(key, z, num_steps=num_steps)
        return (
            state,
            params["step_size"],
            params["inverse_mass_matrix"],
            jnp.sum(info.info.num_integration_steps),
        )

    return _over_chains(one, vectorize, keys, z0)


def _init_states(_, target, z0, z_c):
    return jax.vmap(lambda z: blackjax.nuts.init(z, target))(_finite_starts(target, z0, z_c))


def _over_chains(fn, vectorize: bool, *args):
    """``fn`` of one chain applied to every chain (leading axis of ``args``): vmapped
    (the chains step together; a NUTS step costs the longest of their trajectories) or
    one after another (``jax.lax.map``: each chain's trajectories cost only their own)."""
    return jax.vmap(fn)(*args) if vectorize else jax.lax.map(lambda a: fn(*a), args)


def _sample(settings, target, states, step_size, imm, keys):
    """``keys.shape[1]`` NUTS steps of every chain (steps scanned inside each chain,
    chains vmapped or mapped): the final states and, per chain and step, (positions,
    log densities, divergent, gradients, acceptance rates), each (chains, steps, ...)."""
    sampler, vectorize = settings

    def chain(state, eps, m, keys_c):
        kernel = blackjax.nuts(
            target,
            eps,
            m,
            max_num_doublings=sampler.max_num_doublings,
            divergence_threshold=sampler.divergence_threshold,
        )

        def step(state, key):
            state, info = kernel.step(key, state)
            return state, (
                state.position,
                state.logdensity,
                info.is_divergent,
                info.num_integration_steps,
                info.acceptance_rate,
            )

        return jax.lax.scan(step, state, keys_c)

    return _over_chains(chain, vectorize, states, step_size, imm, keys)


def _to_u(_, target, z):
    """Draws z (chains, draws, k) -> u (chains, draws, k)."""
    return jax.vmap(jax.vmap(target.problem.to_u))(z)


def _values_batch(_, target, u):
    return jax.vmap(target.problem.values)(u)


def _values(problem, u: np.ndarray, call) -> dict[str, np.ndarray]:
    """``problem.values`` of every row of u (n, k): vmapped where it is traceable, else
    one call per draw (a ``values`` written in numpy for concrete u)."""
    try:
        return {
            n: np.asarray(v, dtype=float)
            for n, v in call(_values_batch, None, _Target(problem), jnp.asarray(u)).items()
        }
    except TypeError:  # jax's concretisation errors: values() needs concrete u
        rows = [problem.values(x) for x in u]
        return {n: np.array([float(r[n]) for r in rows]) for n in rows[0]}


def _starts(target, init, chains: int, key, call) -> tuple[Array, Array, Array, np.ndarray]:
    """Starting points (chains, k) in z, their centre (k,) in z, the Laplace covariance
    (k, k) in z there (the initial inverse mass matrix) and the centre in u (k,)."""
    problem = target.problem
    k = len(problem.names)
    lower, upper = np.asarray(problem.lower, dtype=float), np.asarray(problem.upper, dtype=float)
    given = None
    if init is None:
        z_c = jnp.asarray(problem.to_z(jnp.asarray(problem.u0, dtype=float)), dtype=float)
    else:
        if hasattr(init, "params") and hasattr(init, "coordinate"):  # a least-squares FitResult
            given = _fitted_u(init, problem.names, lower, upper)
        else:
            given = np.asarray(init, dtype=float)
        if given.shape not in ((k,), (chains, k)):
            raise ValueError(
                f"init must be a point (k={k},) or one per chain ({chains}, {k}) in the fitted coordinate, got shape {given.shape}"
            )
        if not (np.all(np.isfinite(given)) and np.all(given > lower) and np.all(given < upper)):
            raise ValueError(
                "init: every start must lie strictly inside the bounds (lower, upper) of the fitted coordinate"
            )
        z_c = jnp.asarray(problem.to_z(jnp.asarray(given.reshape(-1, k).mean(axis=0))), dtype=float)
    try:
        z_c, precision = call(_centre, (init is None, True), target, z_c)
    except TypeError:  # residuals with a reverse-only (custom_vjp) derivative
        z_c, precision = call(_centre, (init is None, False), target, z_c)
    cov = _covariance(np.asarray(precision, dtype=float))
    if given is not None and given.ndim == 2:
        return (
            jnp.asarray(jax.vmap(problem.to_z)(jnp.asarray(given)), dtype=float),
            z_c,
            cov,
            given.mean(axis=0),
        )
    z = z_c + jax.random.normal(key, (chains, k), dtype=float) @ jnp.linalg.cholesky(cov).T
    return z, z_c, cov, np.asarray(problem.to_u(z_c), dtype=float)


def _fitted_u(result, names, lower, upper) -> np.ndarray:
    """The optimum of a least-squares result (``params`` by name, ``coordinate`` "log" or
    "linear") in u, kept 1e-6 of the range inside the bounds (an optimum at a bound)."""
    missing = [n for n in names if n not in result.params]
    if missing:
        raise ValueError(f"init: the fit result has no value of {', '.join(missing)}")
    u = np.array(
        [
            math.log(result.params[n])
            if result.coordinate.get(n, "log") == "log"
            else result.params[n]
            for n in names
        ],
        dtype=float,
    )
    span = upper - lower
    return np.clip(u, lower + 1e-6 * span, upper - 1e-6 * span)


def _covariance(precision: np.ndarray) -> Array:
    """Inverse of a (symmetrised) precision, its variances capped at ``MAX_START_SD_Z**2``
    (eigenvalues floored); a non-finite precision gives sd 0.5 in every z."""
    k = precision.shape[0]
    if not np.all(np.isfinite(precision)):
        return 0.25 * jnp.eye(k)
    lam, vec = np.linalg.eigh(0.5 * (precision + precision.T))
    lam = np.maximum(lam, 1.0 / MAX_START_SD_Z**2)
    return jnp.asarray((vec / lam) @ vec.T)
