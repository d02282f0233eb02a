"""``axojax critical``: the Hopf point in p, optionally traced along a second parameter."""

from __future__ import annotations

import argparse
import sys

import jax
import numpy as np

from .. import _progress
from ..critical import critical_force
from ..results import RESULTS, message
from . import common

EVALUATIONS_PER_POINT = 20
"""About how many dominant eigenpairs one Hopf point costs (bracketing and Newton): a
traced boundary is a batch for ``--solver auto``."""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    common.add_model_flags(parser)
    parser.add_argument(
        "--along",
        default=None,
        metavar="NAME",
        help="second parameter to trace the boundary along, e.g. ks",
    )
    parser.add_argument(
        "--values",
        default=None,
        metavar="AXIS",
        help="values of --along: a:b:n, log:a:b:n or v1,v2,...",
    )
    parser.add_argument(
        "--chunk", type=int, default=8, metavar="N", help="points per compiled batch (default 8)"
    )
    common.add_solver_flag(parser)


def run(args: argparse.Namespace) -> dict:
    model = common.model_from_args(args)
    params = common.params_from_args(args)
    units = common.units_from_args(args)
    ratio = common.kl_ratio(args)
    solver = common.solver_from_args(args)
    if (args.along is None) != (args.values is None):
        raise common.CLIError("--along: give --along NAME and --values AXIS together")
    if args.chunk < 1:
        raise common.CLIError(f"--chunk: expected an integer >= 1, got {args.chunk}")
    if args.along is None:
        c = critical_force(model, params, solver=solver)
        _report_failures(args, [("", c.result)])
        return {"critical": [c.to_json(units)]}
    (field,) = common.parse_names(args.along, "--along")
    if field == "p":
        raise common.CLIError("--along: the boundary is traced in p, choose another parameter")
    values = common.parse_axis(args.values, "--values")
    solver = solver.resolve(model, len(values) * EVALUATIONS_PER_POINT)
    for v in values:
        common.check_params(params.with_values({field: float(v)}, ratio))

    @jax.jit
    def batch(vals):
        def one(v):
            return critical_force(model, params.with_values({field: v}, ratio), solver=solver)

        return jax.vmap(one)(vals)

    chunk_size = min(args.chunk, len(values))
    out, failures = [], []
    for start in _progress.progress(
        range(0, len(values), chunk_size), desc="critical", unit="chunk", starting=True
    ):
        chunk = values[start : start + chunk_size]
        padded = np.concatenate([chunk, np.repeat(chunk[-1:], chunk_size - len(chunk))])
        crits = jax.tree.map(np.asarray, batch(padded))
        for i, v in enumerate(chunk):
            c = jax.tree.map(lambda a: a[i], crits)  # the point's Critical
            out.append({common.FIELD_FLAGS[field]: float(v), **c.to_json(units)})
            failures.append((f" at --{common.FIELD_FLAGS[field]} {v:g}", c.result))
    _report_failures(args, failures)
    return {"critical": out}


def _report_failures(args: argparse.Namespace, results) -> None:
    """One line on stderr per point whose Hopf search failed (not for "no crossing",
    which is an answer: p is reported as null); exit status 1 then."""
    for where, result in results:
        if bool(result == RESULTS.successful) or bool(result == RESULTS.no_crossing):
            continue
        print(f"axojax: critical{where}: {message(result)}", file=sys.stderr)
        args._exit_code = 1


def render(doc: dict) -> str:
    rows = doc["critical"]
    keys = list(rows[0])
    lines = ["  ".join(f"{k:>14s}" for k in keys)]
    for r in rows:
        lines.append("  ".join(f"{'-':>14s}" if r[k] is None else f"{r[k]:14.6g}" for k in keys))
    return "\n".join(lines)
