"""The warm-state cache of :func:`axojax.inverse.posterior`: what a run computes before
its first draw, kept in a small file, so that an identical run goes straight to the
draws.

A posterior run spends most of its start-up on work that its inputs fix completely: the
centre of the starts (the posterior mode, or the given point) and the Laplace
approximation there, the chains' starts, and the window adaptation (step sizes, inverse
mass matrices, the chains' states after the warm-up). The persistent compilation cache
(:mod:`axojax.cache`) saves the compilation of those programs, not their tracing nor
their running. This cache keeps their *results* instead: one ``.npz`` per run (a few
kB) named by :func:`run_key`, a sha256 of everything that determines them (the problem's
:meth:`~axojax.inverse.Problem.fingerprint`: models, conditions, data, targets, fixed
parameters, free names, bounds; the prior; the sampler's settings, warm-up steps,
chains, seed, start; vectorisation; the versions of axojax, jax, jaxlib, blackjax,
optimistix, equinox and numpy, a digest of axojax's own source, the backend). A run that
finds its file loads it and neither traces nor compiles nor runs the start-up programs:
only the draws' program is built. The draws are bitwise those of an uncached run (the
same states, step sizes, mass matrices and keys enter the same program).

Not cached (the run simply computes everything): a problem without a ``fingerprint()``
(the :class:`InverseProblem` protocol does not require one), one whose fingerprint
raises ``TypeError`` (a user-given callable prior, a profile given as a lambda), or a
callable ``prior=`` argument (a :func:`normal_prior` is fingerprinted by its values). A
file that cannot be read or does not match (truncated, corrupt, another format) is
ignored with one warning and rewritten by the run.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import json
import math
import pathlib
import platform
import warnings
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from ..fingerprint import digest

FORMAT = 3
"""Bumped whenever what a file holds, or what the key covers, changes."""
SUFFIX = ".warm.npz"


@functools.lru_cache(maxsize=1)
def environment() -> tuple:
    """What else determines a run's start-up: the versions of the libraries, a digest of
    axojax's source files, the python and platform."""
    import blackjax
    import equinox
    import jax
    import jaxlib
    import optimistix

    root = pathlib.Path(__file__).resolve().parents[1]  # the axojax package
    src = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        src.update(str(path.relative_to(root)).encode() + b"\0")
        src.update(path.read_bytes() + b"\0")
    return (
        ("axojax", _version(), src.hexdigest()),
        ("jax", jax.__version__),
        ("jaxlib", jaxlib.__version__),
        ("blackjax", blackjax.__version__),
        ("optimistix", optimistix.__version__),
        ("equinox", equinox.__version__),
        ("numpy", np.__version__),
        ("python", platform.python_version(), platform.machine()),
    )


def _version() -> str:
    try:
        return importlib.metadata.version("axojax")
    except importlib.metadata.PackageNotFoundError:  # a checkout on PYTHONPATH
        return "unknown"


def run_key(
    problem, prior, sampler, warmup, chains, seed, init, vectorize, transport=None
) -> str | None:
    """The key of a run's start-up (module docstring), or None when it cannot be cached."""
    import jax

    from ._densities import NormalPrior
    from ._laplace import fitted_u

    fingerprint = getattr(problem, "fingerprint", None)
    if not callable(fingerprint) or not (prior is None or isinstance(prior, NormalPrior)):
        return None
    try:
        problem_key = fingerprint()
        if init is None:
            start = None
        elif hasattr(init, "params") and hasattr(init, "coordinate"):  # a FitResult
            lower = np.asarray(problem.lower, dtype=float)
            upper = np.asarray(problem.upper, dtype=float)
            start = ("fit", fitted_u(init, tuple(problem.names), lower, upper))
        else:
            start = ("u", np.asarray(init, dtype=float))
        return digest(
            (
                "axojax.posterior.warm",
                FORMAT,
                problem_key,
                prior,
                sampler,
                int(warmup),
                int(chains),
                int(seed),
                start,
                bool(vectorize),
                # the transport's kind, not a map it carries: a resumed run takes the
                # stored map with the stored states
                None if transport is None else (transport.along, int(transport.knots)),
                environment(),
                (jax.default_backend(), bool(jax.config.jax_enable_x64)),
            )
        )
    except (TypeError, ValueError):  # Unfingerprintable, a bad init (the run says why)
        return None


class Warm(NamedTuple):
    """A run's start-up: the centre ``z_c`` (k,) and Laplace covariance ``cov`` (k, k) in
    z, the whitening factor ``chol`` (k, k; the identity when not whitened), the centre
    ``u_c`` and precision ``precision_u`` in u (the Laplace approximation), the starts'
    mean ``start_u``, per chain the sampler's state after the warm-up (``state``:
    blackjax's HMCState fields), step size, inverse mass matrix and gradients spent, and
    with a transport its map's arrays (``profile``: :data:`PROFILE_FIELDS` of a
    :class:`~axojax.inverse.sampling.transport.ProfileMap`; empty without one)."""

    z_c: np.ndarray
    cov: np.ndarray
    chol: np.ndarray
    u_c: np.ndarray
    precision_u: np.ndarray
    start_u: np.ndarray
    state: tuple
    step_size: np.ndarray
    imm: np.ndarray
    warm_grads: np.ndarray
    profile: tuple = ()


PROFILE_FIELDS = ("z_knots", "s_knots", "centre", "log_diag", "lower", "log_density")
_ARRAYS = ("z_c", "cov", "chol", "u_c", "precision_u", "start_u", "step_size", "imm", "warm_grads")


def path_of(directory: pathlib.Path, key: str) -> pathlib.Path:
    return pathlib.Path(directory) / f"{key}{SUFFIX}"


def load(path: pathlib.Path, key: str, chains: int, k: int) -> Warm | None:
    """The start-up kept in ``path`` for ``key``; None when there is none, or (one
    warning) when the file cannot be read or does not hold what a run of ``chains``
    chains of ``k`` parameters needs."""
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            arrays = {name: np.asarray(f[name]) for name in _ARRAYS}
            state = tuple(np.asarray(f[f"state_{i}"]) for i in range(int(meta["n_state"])))
            profile = tuple(np.asarray(f[f"profile_{n}"]) for n in meta.get("profile", []))
        warm = Warm(state=state, profile=profile, **arrays)
        _check(warm, meta, key, chains, k)
    except Exception as err:  # noqa: BLE001 - whatever is wrong with the file: run uncached
        warnings.warn(
            f"posterior warm-state cache: ignoring {str(path)!r} ({type(err).__name__}: {err}); recomputing",
            stacklevel=3,
        )
        return None
    return warm


def _check(warm: Warm, meta: Mapping, key: str, chains: int, k: int) -> None:
    from blackjax.mcmc.hmc import HMCState

    if meta.get("format") != FORMAT or meta.get("key") != key:
        raise ValueError("another format or key")
    if meta.get("state") != list(HMCState._fields) or len(warm.state) != len(HMCState._fields):
        raise ValueError("another sampler state")
    shapes = {
        "z_c": (k,),
        "cov": (k, k),
        "chol": (k, k),
        "u_c": (k,),
        "precision_u": (k, k),
        "start_u": (k,),
        "step_size": (chains,),
        "warm_grads": (chains,),
    }
    for name, shape in shapes.items():
        if getattr(warm, name).shape != shape:
            raise ValueError(f"{name} has shape {getattr(warm, name).shape}, expected {shape}")
    if warm.imm.shape not in ((chains, k), (chains, k, k)):
        raise ValueError(f"imm has shape {warm.imm.shape}")
    position, logdensity, grad = warm.state
    if position.shape != (chains, k) or logdensity.shape != (chains,) or grad.shape != (chains, k):
        raise ValueError("the chains' states have the wrong shapes")
    for name in ("z_c", "cov", "chol", "step_size", "imm"):
        if not np.all(np.isfinite(getattr(warm, name))):
            raise ValueError(f"{name} is not finite")
    if not all(math.isfinite(float(s)) and s > 0 for s in warm.step_size):
        raise ValueError("a step size is not > 0")


def save(path: pathlib.Path, key: str, warm: Warm) -> None:
    """Keep ``warm`` in ``path`` (written whole: :func:`axojax._io.atomic_path`); a
    directory that cannot be written is skipped silently (the run has its result)."""
    from blackjax.mcmc.hmc import HMCState

    from ..._io import atomic_path

    meta = {
        "format": FORMAT,
        "key": key,
        "n_state": len(warm.state),
        "state": list(HMCState._fields),
        "profile": list(PROFILE_FIELDS) if warm.profile else [],
    }
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp, open(tmp, "wb") as f:
            np.savez(
                f,
                meta=json.dumps(meta),
                **{name: np.asarray(getattr(warm, name)) for name in _ARRAYS},
                **{f"state_{i}": np.asarray(x) for i, x in enumerate(warm.state)},
                **{f"profile_{n}": np.asarray(x) for n, x in zip(PROFILE_FIELDS, warm.profile)},
            )
    except OSError:
        pass
