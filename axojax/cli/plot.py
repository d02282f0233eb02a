"""``axojax plot``: the figure of a file an axojax command wrote (a sweep, simulation, orbit
branch or posterior ``.npz``, or a fit report ``.json``), or of a model's cross-section
(``--model NAME`` | ``--model-file PATH``).

Where the figure goes: ``--out FIGURE.png``, or by default beside its input with the
input's suffix replaced (``map.npz`` -> ``map.png``, ``fit.json`` -> ``fit.png``,
``section.toml`` -> ``section.png``); a preset's cross-section (``--model NAME``) has no
input file, so it needs ``--out``."""

from __future__ import annotations

import argparse
import pathlib

from .. import _io
from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "file",
        metavar="FILE",
        nargs="?",
        default=None,
        help="what to draw: a map ('axojax sweep' .npz), a beat ('axojax simulate' .npz), "
        "an orbit branch ('axojax orbit --out' .npz), posterior draws ('axojax fit --posterior' "
        "FIT.posterior.npz: corner plot), a fit report ('axojax fit --out' FIT.json) or a "
        "comparison ('axojax compare --out' REPORT.json)",
    )
    g = parser.add_argument_group("cross-section (instead of FILE)")
    common.add_model_source(g, elements=False, default="")
    parser.add_argument(
        "--out",
        default=None,
        metavar="FIGURE.png",
        help=f"figure path ({', '.join(common.FIGURE_SUFFIXES)}); default: beside the input "
        "with its suffix replaced by .png (FILE.npz -> FILE.png, FIT.json -> FIT.png); "
        "required for a preset's cross-section (--model)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _drawn(figure_of, path) -> tuple[object, str]:
    """(figure, kind) of a file an axojax command wrote, by ``figure_of`` (of
    :mod:`axojax.plotting.files`: each result recognises its own file); a file that is
    not one is one line naming FILE."""
    from ..results import ResultFileError

    try:
        return figure_of(path)
    except ResultFileError as err:
        raise common.CLIError(f"FILE: {err}") from None


def _figure(args: argparse.Namespace):
    section = args.model is not None or args.model_file is not None
    if args.file is not None and section:
        raise common.CLIError(
            f"{'--model' if args.model is not None else '--model-file'}: give FILE.npz or a cross-section, not both"
        )
    if section:
        from ..plotting import plot_section

        args.elements = 1  # the cross-section does not depend on the mesh
        model = common.model_from_args(args)
        return plot_section(model), "section", model.name
    if args.file is None:
        raise common.CLIError(
            "FILE: give FILE.npz (a sweep, simulation, orbit branch or posterior), FIT.json (a "
            "fit report), or --model/--model-file for a cross-section"
        )
    if args.rotation_deg != 0.0:
        raise common.CLIError(
            "--rotation-deg: turns a cross-section (--model); FILE.npz has its own"
        )
    from ..plotting.files import figure_of_npz

    fig, kind = _drawn(figure_of_npz, pathlib.Path(args.file))
    return fig, kind, None


def default_out(args: argparse.Namespace) -> str:
    """The figure's path when ``--out`` is not given: beside the input (FILE or
    ``--model-file``) with its suffix replaced by ``.png``."""
    source = args.file if args.file is not None else args.model_file
    if source is None:
        what = "a preset's cross-section" if args.model is not None else "nothing"
        raise common.CLIError(
            f"--out: {what} has no input file to put the figure beside; give --out FIGURE.png"
        )
    return str(pathlib.Path(source).with_suffix(".png"))


def run(args: argparse.Namespace) -> dict:
    if args.out is None and not (
        args.file is None and args.model is None and args.model_file is None
    ):
        args.out = default_out(args)
    common.check_output("--out", args.out, common.FIGURE_SUFFIXES)
    if args.file is not None and str(args.file).endswith(".json"):  # a fit or comparison report
        from ..plotting.files import figure_of_report

        (fig, kind), model = _drawn(figure_of_report, args.file), None
    else:
        fig, kind, model = _figure(args)
    try:
        with _io.atomic_path(args.out) as tmp:
            fig.savefig(tmp, dpi=130)
    except (OSError, ValueError) as err:
        raise common.CLIError(f"--out: cannot write {args.out!r} ({err})") from None
    doc = {"figure": str(args.out), "kind": kind}
    if model is not None:
        doc["model"] = model
    return doc


def render(doc: dict) -> str:
    return f"wrote {doc['figure']}"
