"""``axojax sweep``: the dominant mode over a parameter grid, saved to ``.npz`` (and NetCDF)."""

from __future__ import annotations

import argparse
import time

import numpy as np

from ..params import Params
from ..sweeps import netcdf, sweep
from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser, axes=True)
    parser.add_argument("--out", required=True, metavar="FILE.npz", help="output file (resumable: rerun to continue)")
    parser.add_argument("--netcdf", metavar="FILE.nc", help="also write the result as NetCDF (needs axojax[netcdf])")
    parser.add_argument("--chunk", type=int, default=256, metavar="N", help="points per compiled batch (default 256)")
    common.add_solver_flag(parser)


def run(args: argparse.Namespace) -> dict:
    model = common.model_from_args(args)
    units = common.units_from_args(args)
    fixed, axes = common.split_axes(args, args._argv)
    if not axes:
        raise common.CLIError("--p: give at least one parameter as an axis, e.g. --p 100:900:41")
    if not str(args.out).endswith(".npz"):
        raise common.CLIError(f"--out: expected a .npz path, got {args.out!r}")
    if args.netcdf is not None:
        if not str(args.netcdf).endswith(".nc"):
            raise common.CLIError(f"--netcdf: expected a .nc path, got {args.netcdf!r}")
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
    t0 = time.perf_counter()
    solver = common.solver_from_args(args)
    result = sweep(model, params, axes, kl_ratio=ratio, units=units, chunk_size=args.chunk, out=args.out, solver=solver)
    if args.netcdf is not None:
        result.to_netcdf(args.netcdf)
    seconds = time.perf_counter() - t0
    cls = result.data["classification"]
    n = int(np.prod(result.shape))
    return {
        "out": str(args.out),
        "netcdf": None if args.netcdf is None else str(args.netcdf),
        "model": model.name,
        "axes": {k: [float(v[0]), float(v[-1]), len(v)] for k, v in result.coords.items()},
        "shape": list(result.shape),
        "points": n,
        "counts": {name: int(np.sum(cls == code)) for code, name in enumerate(("stable", "flutter", "divergence"))},
        "seconds": seconds,
        "points_per_s": n / seconds,
        "solver": result.meta["solver"],
    }


def render(doc: dict) -> str:
    axes = ", ".join(f"{k} {a:g}..{b:g} ({n})" for k, (a, b, n) in doc["axes"].items())
    c = doc["counts"]
    return (
        f"swept {doc['model']} over {axes}: {doc['points']} points in {doc['seconds']:.1f} s ({doc['points_per_s']:.1f} points/s)\n"
        f"stable {c['stable']}, flutter {c['flutter']}, divergence {c['divergence']}\n"
        f"solver {doc['solver']['name']} ({doc['solver']['dense_fallbacks']} points recomputed densely)\n"
        f"saved {doc['out']}" + (f" and {doc['netcdf']}" if doc["netcdf"] else "")
    )
