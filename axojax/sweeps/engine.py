"""Batched parameter sweeps: one compiled function over chunks of a grid.

The grid is the outer product of the axes, cut into chunks of ``chunk_size`` points.
Each chunk is evaluated by one jitted function: the points are split over the local
devices with ``jax.shard_map`` and each CPU device runs :func:`axojax.dominant_mode` over
its points one after another (``lax.map``), so every LAPACK call inside works on a
single matrix (see :mod:`axojax._runtime` on jaxlib 0.10's batched CPU kernels; the
batched CPU kernels would gain nothing over the loop). GPUs and TPUs ``vmap`` over their
points. Memory is bounded by the chunk; a chunk is padded to a multiple of the device
count.

With ``out=FILE.npz`` each finished chunk is written to ``FILE.npz.parts/``; an
interrupted sweep rerun with the same arguments recomputes only the missing chunks
(and any chunk file it cannot read whole: a damaged or foreign file is recomputed, not
trusted), then writes ``FILE.npz`` and removes the parts. Every file is written under a
per-process temporary name and renamed (:mod:`axojax._io`), so a killed sweep leaves
complete chunks only. A second sweep started on the same ``FILE.npz`` while one runs
stops at once with :class:`axojax._io.OutputBusy` (a lock file ``FILE.npz.lock`` held
by the first; the kernel releases it when that process ends, however it ends). The chunk layout depends only on the
grid and ``chunk_size`` (not on the devices), so a sweep may be resumed on another
machine or with another number of processes.

Several processes (``jax.distributed``, one per host or per GPU): every process runs
the same ``sweep`` call; process i of n computes chunks i, i + n, ... into the shared
``FILE.npz.parts/`` and every process returns the same merged result (see
:mod:`axojax.sweeps.processes`; docs/scaling_out.md).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import pathlib
import shutil
import zipfile
from collections.abc import Callable
from typing import Any, Mapping

import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import Mesh, NamedSharding, PartitionSpec

from .. import _io
from .._progress import progress as progress_bar
from ..assembly import refuse_normal_force
from ..eigen.mode import DEFAULT_SOLVER, dominant_mode_impl
from ..eigen.solvers import AbstractEigenSolver
from ..models.section import Model
from ..params import PARAM_NAMES, Params
from ..results import code_names, is_successful
from ..units import Units
from .processes import Share, barrier, wait_for_files
from .result import METRICS, SweepResult


def _metrics(
    model: Model, params: Params, units: Units, solver: AbstractEigenSolver
) -> dict[str, jax.Array]:
    mode = dominant_mode_impl(model, params, solver)
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
        "result": mode.result._value.astype(jnp.int8),
    }


@functools.lru_cache(maxsize=32)
def _compiled(
    model: Model,
    names: tuple[str, ...],
    tie: bool,
    units: Units,
    n_dev: int,
    solver: AbstractEigenSolver,
):
    """One jitted evaluator per (model, axes, tie, units, devices, solver); the fixed
    parameters and the kl ratio are traced arguments, so new values do not recompile.
    Points run one after another on each CPU device (``lax.map``; ``vmap`` on GPUs and
    TPUs), the devices in parallel (``shard_map`` over this process's first ``n_dev``
    local devices)."""

    # A solver with a batched path (ax.eigen.Arnoldi(batched=True): plain jnp block
    # kernels) is vmapped on every platform.
    loop = jax.local_devices()[0].platform == "cpu" and not getattr(
        getattr(solver, "options", None), "batched", False
    )

    def batched(params, ratio, rows):
        def one(row):
            return _metrics(
                model,
                params.with_values(dict(zip(names, row)), ratio if tie else None),
                units,
                solver,
            )

        # CPU: one point at a time (jaxlib's batched CPU LAPACK kernels loop over the
        # matrices anyway, and 0.10's block on the intra-op pool). Accelerators: vmap,
        # whose batched kernels are what they are fast at.
        return jax.lax.map(one, rows) if loop else jax.vmap(one)(rows)

    if n_dev > 1:
        mesh = Mesh(np.array(jax.local_devices()[:n_dev]), ("points",))
        # check_vma off: no collectives here, and the solvers' scans/while loops start
        # from unsharded constants (Arnoldi's block factorisations would need pcasts).
        sharded = jax.shard_map(
            batched,
            mesh=mesh,
            in_specs=(PartitionSpec(), PartitionSpec(), PartitionSpec("points")),
            out_specs=PartitionSpec("points"),
            check_vma=False,
        )
        f = jax.jit(sharded)
        rows_sharding = NamedSharding(mesh, PartitionSpec("points"))
        return lambda params, ratio, rows: f(params, ratio, jax.device_put(rows, rows_sharding))
    return jax.jit(batched)


def _evaluator(
    model: Model,
    params: Params,
    names: tuple[str, ...],
    kl_ratio,
    units: Units,
    n_dev: int,
    solver: AbstractEigenSolver,
):
    f = _compiled(model, names, kl_ratio is not None, units, n_dev, solver)
    fixed = params.broadcast(())
    ratio = jnp.asarray(1.0 if kl_ratio is None else kl_ratio, dtype=float)
    return lambda rows: f(fixed, ratio, rows)


def _fingerprint(
    model: Model,
    params: Params,
    axes: Mapping[str, np.ndarray],
    kl_ratio,
    units: Units,
    chunk: int,
    solver: AbstractEigenSolver,
) -> str:
    doc = {
        "model": repr(model),
        "positions": np.asarray(model.section.positions).round(12).tolist(),
        "params": {k: np.asarray(getattr(params, k)).tolist() for k in PARAM_NAMES},
        "knots": {k: np.asarray(v).tolist() for k, v in params.knot_dict().items()},
        "model_knots": model.knots,
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
    solver: AbstractEigenSolver = DEFAULT_SOLVER,
    log: Callable[[str], None] | None = None,
    throw: bool = False,
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
        out: ``.npz`` path; makes the sweep resumable (see module docstring). Needed,
            on a file system every process sees, when ``jax.distributed`` runs several
            processes: each computes its share of the chunks (module docstring).
        progress: progress over chunks on stderr from the start (the first chunk's
            compilation included; :mod:`axojax._progress`; default: its rule, a bar on a
            terminal, plain lines into a file or pipe).
        devices: how many of this process's local devices to split each chunk over
            (default all).
        solver: dominant-eigenpair solver (:mod:`axojax.eigen.solvers`); the result's
            ``certified`` array marks the points a structured solver certified (the
            others were recomputed densely) and ``meta["solver"]`` counts them.
        log: called with one line when the sweep resumes from (or recomputes damaged)
            chunks of an earlier run.
        throw: raise ``ValueError`` (one line: how many points failed, and why) when a
            point's ``result`` is not ``successful`` (after ``out`` is written). Default
            False, as everywhere (:mod:`axojax.results`): the failed points are NaN and
            ``result.result`` holds every point's code.

    Raises:
        axojax._io.OutputBusy: another process is sweeping into the same ``out``.

    Returns:
        :class:`SweepResult` with arrays of shape ``[len(v) for v in axes.values()]``
        (the same merged result in every process).
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
        refuse_normal_force(Params().replace(**{n: v}).validate())
    if kl_ratio is not None and not kl_ratio > 0:
        raise ValueError(f"kl_ratio must be > 0, got {kl_ratio}")
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be >= 1, got {chunk_size}")
    n_local = jax.local_device_count()
    if devices is not None and not 1 <= devices <= n_local:
        raise ValueError(f"devices must be in 1..{n_local} (this process's devices), got {devices}")
    share = Share.current()
    if share.count > 1 and out is None:
        raise ValueError(
            f"a sweep over {share.count} processes (jax.distributed) needs out=FILE.npz on a shared file system"
        )
    params = refuse_normal_force(params.validate())
    shape = tuple(len(v) for v in coords.values())
    solver = solver.resolve(model, int(np.prod(shape)))
    grid = np.stack(
        [g.ravel() for g in np.meshgrid(*coords.values(), indexing="ij")], axis=1
    )  # (N, n_axes)
    n_points = grid.shape[0]
    n_dev = devices or n_local
    chunk = min(
        chunk_size, n_points
    )  # the layout of the parts: independent of devices and processes
    n_chunks = int(np.ceil(n_points / chunk))
    padded = int(np.ceil(chunk / n_dev) * n_dev)

    parts = None
    lock = contextlib.nullcontext()
    if out is not None:
        try:
            out = _io.check_output_path(out, (".npz",))
        except ValueError as err:
            raise ValueError(f"out: {err}") from None
        parts = out.with_name(out.name + ".parts")
        if share.leader:
            lock = _io.exclusive(out.with_name(out.name + ".lock"), str(out))
    with lock:
        done = _run_chunks(
            model,
            params,
            names,
            kl_ratio,
            units,
            n_dev,
            solver,
            grid,
            chunk,
            n_chunks,
            padded,
            share,
            parts,
            coords,
            progress,
            log,
        )
        merged = _merge(
            done,
            n_chunks,
            shape,
            coords,
            model,
            params,
            names,
            kl_ratio,
            units,
            solver,
            share,
            out,
            parts,
        )
    if throw and not is_successful(merged.result):
        raise ValueError(f"sweep: {merged.message}")
    return merged


def _read_chunk(path: pathlib.Path) -> dict[str, np.ndarray] | None:
    """A chunk file's arrays, or None when it is damaged, truncated or not a chunk."""
    try:
        with np.load(path, allow_pickle=False) as f:
            return {k: np.asarray(f[k]) for k in METRICS}
    except (OSError, EOFError, KeyError, ValueError, zipfile.BadZipFile):
        return None


def _run_chunks(
    model,
    params,
    names,
    kl_ratio,
    units,
    n_dev,
    solver,
    grid,
    chunk,
    n_chunks,
    padded,
    share,
    parts,
    coords,
    progress,
    log,
):
    """This process's chunks: read the finished ones, compute the others (each written
    to ``parts`` whole, under a unique temporary name, when ``parts`` is set)."""
    if parts is not None:
        key = _fingerprint(model, params, coords, kl_ratio, units, chunk, solver)
        manifest = parts / "manifest.json"
        if share.leader:
            try:
                old = json.loads(manifest.read_text()).get("key") if manifest.exists() else None
            except (OSError, ValueError, AttributeError):
                old = None
            if parts.exists() and old != key:
                shutil.rmtree(parts)  # left by a different sweep: start again
            parts.mkdir(parents=True, exist_ok=True)
            _io.write_text(
                manifest, json.dumps({"key": key, "n_chunks": n_chunks, "processes": share.count})
            )
        barrier(share, "prepared")
        if not share.leader and json.loads(manifest.read_text()).get("key") != key:
            raise ValueError(
                f"process {share.index}: this sweep's arguments differ from process 0's (fingerprint of {manifest})"
            )

    def part_path(c: int) -> pathlib.Path | None:
        return None if parts is None else parts / f"chunk_{c:06d}.npz"

    evaluate = None
    results: dict[int, dict[str, np.ndarray]] = {}
    mine = [c for c in range(n_chunks) if share.owns(c)]
    resumed = damaged = 0
    for c in progress_bar(
        mine, desc=f"sweep {model.name}", unit="chunk", enable=progress, starting=True
    ):
        part = part_path(c)
        if part is not None and part.exists():
            vals = _read_chunk(part)
            if vals is not None and all(
                v.shape[0] == min(chunk, grid.shape[0] - c * chunk) for v in vals.values()
            ):
                results[c] = vals
                resumed += 1
                continue
            damaged += 1  # recomputed below and written again
        rows = grid[c * chunk : (c + 1) * chunk]
        n = rows.shape[0]
        if n < padded:
            rows = np.concatenate([rows, np.repeat(rows[-1:], padded - n, axis=0)])
        if evaluate is None:
            evaluate = _evaluator(model, params, names, kl_ratio, units, n_dev, solver)
        vals = {k: np.asarray(v)[:n] for k, v in evaluate(jnp.asarray(rows)).items()}
        if part is not None:
            with _io.atomic_path(part) as tmp:
                np.savez(tmp, **vals)
        results[c] = vals
    if log is not None and (resumed or damaged):
        log(
            f"resumed {parts}: {resumed} of {len(mine)} chunks were done"
            + (f", {damaged} damaged chunk file(s) recomputed" if damaged else "")
        )

    if parts is not None:
        wait_for_files([part_path(c) for c in range(n_chunks)])  # the other processes' chunks
        for c in range(n_chunks):
            if c not in results:
                vals = _read_chunk(part_path(c))
                if vals is None:
                    raise ValueError(
                        f"chunk file {part_path(c)} written by another process cannot be read; "
                        "rerun the sweep to recompute it"
                    )
                results[c] = vals
    return results


def _merge(
    results,
    n_chunks,
    shape,
    coords,
    model,
    params,
    names,
    kl_ratio,
    units,
    solver,
    share,
    out,
    parts,
) -> SweepResult:
    data = {
        k: np.concatenate([results[c][k] for c in range(n_chunks)]).reshape(shape) for k in METRICS
    }
    fixed = {k: np.asarray(getattr(params, k)).tolist() for k in PARAM_NAMES if k not in names}
    fixed.update({k: np.asarray(v).tolist() for k, v in params.knot_dict().items()})
    if model.knots is not None:
        fixed["knots"] = list(model.knots)
    if kl_ratio is not None:
        fixed.pop("kl", None)
    meta = {
        "kind": "sweep",
        "model": model.name,
        "n_elements": model.n_elements,
        "n_dof": model.n_dof,
        "imbalance_kind": model.imbalance_kind,
        "axes": list(names),
        "fixed": fixed,
        "kl_ratio": kl_ratio,
        "units": {
            "length_um": units.length_um,
            "ei_pn_um2": units.ei_pn_um2,
            "cn_pn_s_um2": units.cn_pn_s_um2,
            "tau_s": units.tau_s,
        },
        "classification": {"0": "stable", "1": "flutter", "2": "divergence"},
        "direction": {"1": "anterograde", "-1": "retrograde", "0": "none"},
        "result": code_names(),
        "solver": {
            "name": type(solver).__name__.lower(),
            "dense_fallbacks": int(np.sum(data["certified"] == 0)),
        },
    }
    result = SweepResult(coords, data, meta)
    if out is not None:
        barrier(share, "merged")  # every process has read the parts
        if share.leader:
            result.save(out)
            shutil.rmtree(parts, ignore_errors=True)
    return result
