"""``axojax plot``: figures of sweeps and simulations (``FILE.npz --out FIGURE.png``), or of
a model's cross-section (``--model NAME`` | ``--model-file PATH`` ``--out FIGURE.png``)."""

from __future__ import annotations

import argparse
import json
import pathlib

import numpy as np

from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE.npz", nargs="?", default=None, help="output of 'axojax sweep' or 'axojax simulate'")
    g = parser.add_argument_group("cross-section (instead of FILE.npz)")
    common.add_model_source(g, elements=False, default="")
    parser.add_argument("--out", required=True, metavar="FIGURE.png", help="figure path (.png, .pdf, .svg)")
    parser.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _kind(path: pathlib.Path) -> str:
    try:
        with np.load(path, allow_pickle=False) as f:
            return json.loads(str(f["meta"])).get("kind", "sweep")
    except (OSError, KeyError, ValueError) as err:
        raise common.CLIError(f"FILE: cannot read {str(path)!r} as an axojax .npz ({err})") from None


def _figure(args: argparse.Namespace):
    section = args.model is not None or args.model_file is not None
    if args.file is not None and section:
        raise common.CLIError(f"{'--model' if args.model is not None else '--model-file'}: give FILE.npz or a cross-section, not both")
    if section:
        from ..plotting import plot_section

        args.elements = 1  # the cross-section does not depend on the mesh
        model = common.model_from_args(args)
        return plot_section(model), "section", model.name
    if args.file is None:
        raise common.CLIError("FILE: give FILE.npz (a sweep, simulation or orbit branch), or --model/--model-file for a cross-section")
    if args.rotation_deg != 0.0:
        raise common.CLIError("--rotation-deg: turns a cross-section (--model); FILE.npz has its own")
    path = pathlib.Path(args.file)
    if not path.is_file():
        raise common.CLIError(f"FILE: {str(path)!r} does not exist")
    kind = _kind(path)
    if kind == "sweep":
        from ..plotting import plot_sweep
        from ..sweeps import SweepResult

        return plot_sweep(SweepResult.load(path)), kind, None
    if kind == "orbit_branch":
        from ..orbits.plot import plot_branch

        return plot_branch(path), kind, None
    from ..plotting import plot_simulation

    return plot_simulation(path), kind, None


def run(args: argparse.Namespace) -> dict:
    if args.file is not None and str(args.file).endswith(".json"):  # a fit report (axojax fit --out)
        from .fit import figure_of_report

        fig, kind, model = figure_of_report(args.file), "fit", None
    else:
        fig, kind, model = _figure(args)
    try:
        fig.savefig(args.out, dpi=130)
    except (OSError, ValueError) as err:
        raise common.CLIError(f"--out: cannot write {args.out!r} ({err})") from None
    doc = {"figure": str(args.out), "kind": kind}
    if model is not None:
        doc["model"] = model
    return doc


def render(doc: dict) -> str:
    return f"wrote {doc['figure']}"
