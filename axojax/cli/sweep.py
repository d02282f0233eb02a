"""``axojax sweep``: the dominant mode over a parameter grid, saved to ``.npz`` (and NetCDF).

Several processes (hosts, or one process per GPU): start the same command in each with
``--distributed`` (``jax.distributed`` finds the coordinator, process count and index
itself under SLURM, Open MPI and the other clusters it knows) or with explicit
``--coordinator HOST:PORT --num-processes N --process-id I``. Each process computes its
share of the chunks into ``FILE.npz.parts/`` (a file system all of them see); process 0
writes ``FILE.npz`` (docs/scaling_out.md).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from .. import _io, _progress
from ..params import Params
from ..results import is_successful
from ..sweeps import netcdf, sweep
from . import common

DEFAULT_TIMEOUT_S = 120
"""How long the processes of a distributed sweep wait for each other by default (s)."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser, axes=True)
    parser.add_argument(
        "--out",
        required=True,
        metavar="FILE.npz",
        help="output file (resumable: rerun to continue)",
    )
    parser.add_argument(
        "--netcdf", metavar="FILE.nc", help="also write the result as NetCDF (needs axojax[netcdf])"
    )
    parser.add_argument(
        "--chunk",
        type=int,
        default=256,
        metavar="N",
        help="points per compiled batch (default 256)",
    )
    common.add_solver_flag(parser)
    group = parser.add_argument_group(
        "several processes (jax.distributed; see docs/scaling_out.md)"
    )
    group.add_argument(
        "--distributed",
        action="store_true",
        help="join a jax.distributed job; coordinator, process count and index found from the "
        "cluster (SLURM, Open MPI, ...) unless given below",
    )
    group.add_argument(
        "--coordinator",
        metavar="HOST:PORT",
        help="address of process 0's coordination service (implies --distributed)",
    )
    group.add_argument(
        "--num-processes",
        type=int,
        metavar="N",
        help="processes in the job (implies --distributed)",
    )
    group.add_argument(
        "--process-id",
        type=int,
        metavar="I",
        help="this process's index, 0..N-1 (implies --distributed)",
    )
    group.add_argument(
        "--timeout",
        type=int,
        default=None,
        metavar="SECONDS",
        help=(
            f"how long to wait for every process to join (default {DEFAULT_TIMEOUT_S}; only "
            "with the flags above): a process I > 0 stops with a one-line error when "
            "process 0 does not answer; process 0 stops with jax's error when the others "
            "do not join"
        ),
    )


def _distributed(args: argparse.Namespace) -> bool:
    """Whether the flags ask for a ``jax.distributed`` run."""
    return args.distributed or any(
        v is not None for v in (args.coordinator, args.num_processes, args.process_id)
    )


def check_timeout(args: argparse.Namespace) -> int:
    """``--timeout`` in seconds: an integer >= 1, and only given for a distributed run
    (it is unused otherwise); the default where it is not given."""
    if args.timeout is None:
        return DEFAULT_TIMEOUT_S
    if args.timeout < 1:
        raise common.CLIError(f"--timeout: expected seconds >= 1, got {args.timeout}")
    if not _distributed(args):
        raise common.CLIError(
            "--timeout: only used by a distributed sweep (with --distributed, --coordinator, "
            f"--num-processes or --process-id), got --timeout {args.timeout} without one"
        )
    return args.timeout


def _wait_for_coordinator(host: str, port: int, timeout_s: float) -> None:
    """A one-line error when nothing listens at process 0's address within the timeout
    (jax's own client would abort the process with a C++ stack trace)."""
    import socket
    import time

    deadline = time.monotonic() + timeout_s
    while True:
        try:
            socket.create_connection((host, port), timeout=1.0).close()
            return
        except OSError:
            if time.monotonic() > deadline:
                raise common.CLIError(
                    f"--coordinator: nothing answered at {host}:{port} within {timeout_s:g} s "
                    "(--timeout); is process 0 running?"
                ) from None
            time.sleep(0.5)


def init_distributed(args: argparse.Namespace) -> None:
    """``jax.distributed.initialize`` from the flags, before anything touches a device."""
    explicit = {
        "coordinator_address": args.coordinator,
        "num_processes": args.num_processes,
        "process_id": args.process_id,
    }
    timeout = check_timeout(args)
    if not _distributed(args):
        return
    host, port = None, None
    if args.coordinator is not None:
        host, _, port = args.coordinator.rpartition(":")
        if not host or not port.isdigit() or not 1 <= int(port) <= 65535:
            raise common.CLIError(
                f"--coordinator: expected HOST:PORT with a port in 1..65535, got {args.coordinator!r}"
            )
    if args.num_processes is not None and args.num_processes < 1:
        raise common.CLIError(
            f"--num-processes: expected an integer >= 1, got {args.num_processes}"
        )
    if args.process_id is not None and args.process_id < 0:
        raise common.CLIError(f"--process-id: expected an integer >= 0, got {args.process_id}")
    if (
        args.process_id is not None
        and args.num_processes is not None
        and args.process_id >= args.num_processes
    ):
        raise common.CLIError(
            f"--process-id: expected 0..{args.num_processes - 1} (--num-processes "
            f"{args.num_processes}), got {args.process_id}"
        )
    if host is not None and args.process_id:
        _wait_for_coordinator(host, int(port), timeout)
    import jax

    try:
        jax.distributed.initialize(
            **{k: v for k, v in explicit.items() if v is not None},
            initialization_timeout=timeout,
        )
    except (RuntimeError, ValueError) as e:
        flag = next(
            (
                f
                for f, v in (
                    ("--coordinator", args.coordinator),
                    ("--process-id", args.process_id),
                    ("--num-processes", args.num_processes),
                )
                if v is not None
            ),
            "--distributed",
        )
        raise common.CLIError(
            f"{flag}: jax.distributed.initialize failed: {str(e).splitlines()[0]}"
        ) from None


GRID_BYTES_PER_POINT = 3 * (8 * 10 + 8 * 4)
"""Memory of one grid point (bytes): its coordinates and ten metrics, held about three
times (the chunks, their concatenation, the saved arrays)."""


def check_grid(model, axes: dict[str, np.ndarray], chunk: int) -> None:
    """Refuse a grid whose arrays, or whose chunks (accelerators evaluate a chunk's
    points at once), cannot fit in memory; with the estimate."""
    import jax

    n_points = int(np.prod([len(v) for v in axes.values()], dtype=float))
    flags = " x ".join(f"--{common.FIELD_FLAGS[k]} {len(v)}" for k, v in axes.items())
    common.check_memory(
        float(n_points) * (GRID_BYTES_PER_POINT + 8 * len(axes)),
        "--" + common.FIELD_FLAGS[next(iter(axes))],
        f"a grid of {n_points:.4g} points ({flags})",
    )
    per_point = common.model_bytes(model.section, model.n_elements)
    at_once = 1 if jax.local_devices()[0].platform == "cpu" else min(chunk, n_points)
    common.check_memory(
        at_once * per_point,
        "--chunk",
        f"a chunk of {at_once} points evaluated at once on {model.n_dof} unknowns",
    )


def run(args: argparse.Namespace) -> dict:
    init_distributed(args)
    common.check_output("--out", args.out, (".npz",))
    common.check_output("--netcdf", args.netcdf, (".nc",))
    model = common.model_from_args(args)
    units = common.units_from_args(args)
    fixed, axes = common.split_axes(args, args._argv)
    if not axes:
        raise common.CLIError("--p: give at least one parameter as an axis, e.g. --p 100:900:41")
    if args.netcdf is not None:
        try:
            netcdf.require_xarray()
        except ImportError as e:
            raise common.CLIError(f"--netcdf: {e}") from None
    if args.chunk < 1:
        raise common.CLIError(f"--chunk: expected an integer >= 1, got {args.chunk}")
    ratio = common.kl_ratio(args)
    params = Params().with_values(fixed)
    common.check_params(params)
    for name, values in axes.items():
        common.check_params(Params().replace(**{name: values}))
    if ratio is not None:
        ks = axes.get("ks", np.asarray([params.ks]))
        common.check_params(Params(kl=np.asarray(ks) / ratio), "--kl-ratio")
    check_grid(model, axes, args.chunk)
    t0 = time.perf_counter()
    solver = common.solver_from_args(args)
    try:
        result = sweep(
            model,
            params,
            axes,
            kl_ratio=ratio,
            units=units,
            chunk_size=args.chunk,
            out=args.out,
            solver=solver,
            progress=_progress.enabled(),
            log=lambda line: print(f"axojax: sweep: {line}", file=sys.stderr),
        )
    except _io.OutputBusy as err:
        raise common.CLIError(f"--out: {err}") from None
    import jax

    if args.netcdf is not None and jax.process_index() == 0:
        result.to_netcdf(args.netcdf)
    seconds = time.perf_counter() - t0

    if not is_successful(result.result):  # NaN points in the file: say so, on one line
        print(f"axojax: sweep: {result.message}", file=sys.stderr)
    summary = result.to_json()
    return {
        "out": str(args.out),
        "netcdf": None if args.netcdf is None else str(args.netcdf),
        **{k: summary[k] for k in ("model", "axes", "shape", "points", "counts")},
        "seconds": seconds,
        "points_per_s": summary["points"] / seconds,
        "solver": summary["solver"],
        "process": [jax.process_index(), jax.process_count()],
    }


def render(doc: dict) -> str:
    axes = ", ".join(f"{k} {a:g}..{b:g} ({n})" for k, (a, b, n) in doc["axes"].items())
    c = doc["counts"]
    return (
        f"swept {doc['model']} over {axes}: {doc['points']} points in {doc['seconds']:.1f} s "
        f"({doc['points_per_s']:.1f} points/s)\n"
        f"stable {c['stable']}, flutter {c['flutter']}, divergence {c['divergence']}\n"
        f"solver {doc['solver']['name']} ({doc['solver']['dense_fallbacks']} points recomputed densely)\n"
        f"saved {doc['out']}"
        + (f" and {doc['netcdf']}" if doc["netcdf"] else "")
        + (
            f" (process {doc['process'][0]} of {doc['process'][1]})"
            if doc["process"][1] > 1
            else ""
        )
    )
