"""Batched parameter sweeps: one compiled, vmapped function over chunks of a grid.

The grid is the outer product of the axes. Points are evaluated ``chunk_size`` at a
time by a single jitted ``vmap`` of :func:`axojax.dominant_mode` (memory is bounded by
the chunk), sharded over every visible device with ``jax.sharding`` (the chunk is
padded to a multiple of the device count). With ``out=FILE.npz`` each finished chunk is
written to ``FILE.npz.parts/``; an interrupted sweep rerun with the same arguments
recomputes only the missing chunks, then writes ``FILE.npz`` and removes the parts.

Multi-host: start every process with ``jax.distributed.initialize()``; ``jax.devices()``
then lists every host's devices and the same sharded function spreads each chunk over
all of them (each host must run the same ``sweep`` call).
"""

from __future__ import annotations

import functools
import hashlib
import json
import pathlib
import shutil
from typing import Any, Mapping

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec
from tqdm.auto import tqdm

from ..eigen.mode import DEFAULT_SOLVER, _dominant_mode_impl
from ..eigen.solvers import EigenSolver
from ..models.section import Model
from ..params import PARAM_NAMES, Params
from ..units import Units
from .result import METRICS, SweepResult


def _metrics(model: Model, params: Params, units: Units, solver: EigenSolver) -> dict[str, jax.Array]:
    mode = _dominant_mode_impl(model, params, solver)
    osc = mode.direction != 0
    nan = jnp.nan
    return {
        "eigenvalue_real": jnp.real(mode.eigenvalue),
        "eigenvalue_imag": jnp.imag(mode.eigenvalue),
        "growth_rate_per_s": mode.growth_rate_per_s(units),
        "frequency_hz": mode.frequency_hz(units),
        "wavelength_um": jnp.where(osc, mode.wavelength_um(units), nan),
        "velocity_um_per_s": jnp.where(osc, mode.velocity_um_per_s(units), nan),
        "out_of_plane_ratio": mode.out_of_plane_ratio,
        "direction": mode.direction.astype(jnp.int8),
        "classification": mode.classification.astype(jnp.int8),
        "certified": mode.certified.astype(jnp.int8),
    }


@functools.lru_cache(maxsize=32)
def _compiled(model: Model, names: tuple[str, ...], tie: bool, units: Units, n_dev: int, solver: EigenSolver):
    """One jitted, vmapped evaluator per (model, axes, tie, units, devices, solver); the
    fixed parameters and the kl ratio are traced arguments, so new values do not recompile."""

    def batched(params, ratio, rows):
        def one(row):
            return _metrics(model, params.with_values(dict(zip(names, row)), ratio if tie else None), units, solver)

        return jax.vmap(one)(rows)

    if n_dev > 1:
        mesh = Mesh(np.array(jax.devices()[:n_dev]), ("points",))
        sharding = NamedSharding(mesh, PartitionSpec("points"))
        f = jax.jit(batched, in_shardings=(None, None, sharding), out_shardings=sharding)
        return lambda params, ratio, rows: f(params, ratio, jax.device_put(rows, sharding))
    return jax.jit(batched)


def _evaluator(model: Model, params: Params, names: tuple[str, ...], kl_ratio, units: Units, n_dev: int, solver: EigenSolver):
    f = _compiled(model, names, kl_ratio is not None, units, n_dev, solver)
    fixed = params.broadcast(())
    ratio = jnp.asarray(1.0 if kl_ratio is None else kl_ratio, dtype=float)
    return lambda rows: f(fixed, ratio, rows)


def _fingerprint(model: Model, params: Params, axes: Mapping[str, np.ndarray], kl_ratio, units: Units, chunk: int, solver: EigenSolver) -> str:
    doc = {
        "model": repr(model),
        "positions": np.asarray(model.section.positions).round(12).tolist(),
        "params": {k: np.asarray(getattr(params, k)).tolist() for k in PARAM_NAMES},
        "axes": {k: np.asarray(v).tolist() for k, v in axes.items()},
        "kl_ratio": kl_ratio,
        "units": [units.length_um, units.ei_pn_um2, units.cn_pn_s_um2],
        "chunk": chunk,
        "solver": repr(solver),
    }
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()[:16]


def sweep(
    model: Model,
    params: Params,
    axes: Mapping[str, Any],
    *,
    kl_ratio: float | None = None,
    units: Units = Units(),
    chunk_size: int = 256,
    out: str | pathlib.Path | None = None,
    progress: bool | None = None,
    devices: int | None = None,
    solver: EigenSolver = DEFAULT_SOLVER,
) -> SweepResult:
    """Evaluate the dominant mode on the outer-product grid of ``axes``.

    Args:
        model: static model.
        params: fixed values of every parameter not swept.
        axes: parameter name -> 1-D values, in axis order (e.g.
            ``{"p": np.linspace(100, 900, 41), "ks": np.logspace(2, 7, 26)}``).
        kl_ratio: if set, kl = ks / kl_ratio at every point (ks swept or fixed).
        units: physical units of the outputs.
        chunk_size: points per compiled batch (bounds memory).
        out: ``.npz`` path; makes the sweep resumable (see module docstring).
        progress: tqdm progress bar (default: only on a terminal).
        devices: how many devices to shard over (default all).
        solver: dominant-eigenpair solver (:mod:`axojax.eigen.solvers`); the result's
            ``certified`` array marks the points a structured solver certified (the
            others were recomputed densely) and ``meta["solver"]`` counts them.

    Returns:
        :class:`SweepResult` with arrays of shape ``[len(v) for v in axes.values()]``.
    """
    names = tuple(axes)
    bad = [n for n in names if n not in PARAM_NAMES]
    if bad:
        raise ValueError(f"unknown sweep axis {bad[0]!r}; known: {', '.join(PARAM_NAMES)}")
    if not names:
        raise ValueError("a sweep needs at least one axis")
    coords = {n: np.atleast_1d(np.asarray(axes[n], dtype=float)) for n in names}
    for n, v in coords.items():
        if v.ndim != 1 or v.size == 0:
            raise ValueError(f"axis {n} must be a non-empty 1-D list of values")
        Params().replace(**{n: v}).validate()
    if kl_ratio is not None and not kl_ratio > 0:
        raise ValueError(f"kl_ratio must be > 0, got {kl_ratio}")
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be >= 1, got {chunk_size}")
    params = params.validate()
    shape = tuple(len(v) for v in coords.values())
    solver = solver.resolve(model, int(np.prod(shape)))
    grid = np.stack([g.ravel() for g in np.meshgrid(*coords.values(), indexing="ij")], axis=1)  # (N, n_axes)
    n_points = grid.shape[0]
    n_dev = devices or jax.device_count()
    chunk = int(np.ceil(min(chunk_size, n_points) / n_dev) * n_dev)
    n_chunks = int(np.ceil(n_points / chunk))

    parts = None
    if out is not None:
        out = pathlib.Path(out)
        parts = out.with_name(out.name + ".parts")
        key = _fingerprint(model, params, coords, kl_ratio, units, chunk, solver)
        manifest = parts / "manifest.json"
        if parts.exists() and (not manifest.exists() or json.loads(manifest.read_text()).get("key") != key):
            shutil.rmtree(parts)  # left by a different sweep: start again
        parts.mkdir(parents=True, exist_ok=True)
        manifest.write_text(json.dumps({"key": key, "n_chunks": n_chunks}))

    evaluate = None
    results: list[dict[str, np.ndarray]] = []
    for c in tqdm(range(n_chunks), desc=f"sweep {model.name}", unit="chunk", disable=(None if progress is None else not progress)):
        part = None if parts is None else parts / f"chunk_{c:06d}.npz"
        if part is not None and part.exists():
            with np.load(part) as f:
                results.append({k: f[k] for k in METRICS})
            continue
        rows = grid[c * chunk : (c + 1) * chunk]
        n = rows.shape[0]
        if n < chunk:
            rows = np.concatenate([rows, np.repeat(rows[-1:], chunk - n, axis=0)])
        if evaluate is None:
            evaluate = _evaluator(model, params, names, kl_ratio, units, n_dev, solver)
        vals = {k: np.asarray(v)[:n] for k, v in evaluate(jnp.asarray(rows)).items()}
        if part is not None:
            tmp = part.with_name(part.name + ".tmp.npz")
            np.savez(tmp, **vals)
            tmp.replace(part)
        results.append(vals)

    data = {k: np.concatenate([r[k] for r in results]).reshape(shape) for k in METRICS}
    fixed = {k: np.asarray(getattr(params, k)).tolist() for k in PARAM_NAMES if k not in names}
    if kl_ratio is not None:
        fixed.pop("kl", None)
    meta = {
        "kind": "sweep",
        "model": model.name,
        "n_elements": model.n_elements,
        "n_dof": model.n_dof,
        "axes": list(names),
        "fixed": fixed,
        "kl_ratio": kl_ratio,
        "units": {"length_um": units.length_um, "ei_pn_um2": units.ei_pn_um2, "cn_pn_s_um2": units.cn_pn_s_um2, "tau_s": units.tau_s},
        "classification": {"0": "stable", "1": "flutter", "2": "divergence"},
        "direction": {"1": "anterograde", "-1": "retrograde", "0": "none"},
        "solver": {"name": type(solver).__name__.lower(), "dense_fallbacks": int(np.sum(data["certified"] == 0))},
    }
    result = SweepResult(coords, data, meta)
    if out is not None:
        result.save(out)
        shutil.rmtree(parts, ignore_errors=True)
    return result
