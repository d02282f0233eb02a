"""``axojax plot FILE.npz --out FIGURE.png``: figures of sweeps (and simulations)."""

from __future__ import annotations

import argparse
import json
import pathlib

import numpy as np

from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE.npz", help="output of 'axojax sweep' or 'axojax simulate'")
    parser.add_argument("--out", required=True, metavar="FIGURE.png", help="figure path (.png, .pdf, .svg)")
    parser.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _kind(path: pathlib.Path) -> str:
    try:
        with np.load(path, allow_pickle=False) as f:
            return json.loads(str(f["meta"])).get("kind", "sweep")
    except (OSError, KeyError, ValueError) as err:
        raise common.CLIError(f"FILE: cannot read {str(path)!r} as an axojax .npz ({err})") from None


def run(args: argparse.Namespace) -> dict:
    path = pathlib.Path(args.file)
    if not path.is_file():
        raise common.CLIError(f"FILE: {str(path)!r} does not exist")
    kind = _kind(path)
    if kind == "sweep":
        from ..plotting import plot_sweep
        from ..sweeps import SweepResult

        fig = plot_sweep(SweepResult.load(path))
    else:
        from ..plotting import plot_simulation

        fig = plot_simulation(path)
    try:
        fig.savefig(args.out, dpi=130)
    except (OSError, ValueError) as err:
        raise common.CLIError(f"--out: cannot write {args.out!r} ({err})") from None
    return {"figure": str(args.out), "kind": kind}


def render(doc: dict) -> str:
    return f"wrote {doc['figure']}"
