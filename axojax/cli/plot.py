"""``axojax plot``: the figure of a file an axojax command wrote (a sweep, simulation, orbit
branch or posterior ``.npz``, or a fit report ``.json``), or of a model's cross-section
(``--model NAME`` | ``--model-file PATH``).

Where the figure goes: ``--out FIGURE.png``, or by default beside its input with the
input's suffix replaced (``map.npz`` -> ``map.png``, ``fit.json`` -> ``fit.png``,
``section.toml`` -> ``section.png``); a preset's cross-section (``--model NAME``) has no
input file, so it needs ``--out``."""

from __future__ import annotations

import argparse
import json
import pathlib
import zipfile

import numpy as np

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


KINDS = ("sweep", "simulation", "orbit_branch", "posterior")
READ_ERRORS = (
    OSError,
    EOFError,
    KeyError,
    ValueError,
    TypeError,
    AttributeError,
    IndexError,
    zipfile.BadZipFile,
)
"""What a truncated, damaged or foreign file raises on the way in (numpy's zip reader,
the JSON meta, the arrays)."""


def _bad(path: pathlib.Path, why: str) -> common.CLIError:
    return common.CLIError(f"FILE: {str(path)!r} {why}")


def _meta(path: pathlib.Path) -> dict:
    """The file's meta, checked: a JSON object whose ``kind`` axojax writes."""
    if not zipfile.is_zipfile(path):
        raise _bad(
            path,
            "is not an .npz file (no zip archive: truncated, damaged or another format); rerun "
            "the command that wrote it",
        )
    try:
        with np.load(path, allow_pickle=False) as f:
            if "meta" not in f.files:
                raise _bad(
                    path,
                    f"is not an axojax file (no 'meta' entry; it holds {', '.join(f.files) or 'nothing'})",
                )
            text = str(f["meta"])
    except common.CLIError:
        raise
    except READ_ERRORS as err:
        raise _bad(
            path,
            f"cannot be read as an .npz file: truncated or damaged ({type(err).__name__}: "
            f"{str(err).splitlines()[0] if str(err) else 'no detail'}); rerun the command that "
            "wrote it",
        ) from None
    try:
        meta = json.loads(text)
    except ValueError:
        raise _bad(path, "has a 'meta' entry that is not JSON: not an axojax file") from None
    if not isinstance(meta, dict):
        raise _bad(
            path,
            f"has a 'meta' entry that is a JSON {type(meta).__name__}, not an object: not an axojax file",
        )
    kind = meta.get("kind", "sweep")
    if kind not in KINDS:
        raise _bad(path, f"has kind {kind!r}; axojax plots {', '.join(KINDS)} files")
    return meta


def _check_shapes(
    path: pathlib.Path, kind: str, arrays: dict[str, np.ndarray], expect: dict[str, tuple]
) -> None:
    for name, shape in expect.items():
        a = np.asarray(arrays[name])
        if (
            a.ndim != len(shape)
            or any(s is not None and n != s for n, s in zip(a.shape, shape))
            or a.size == 0
        ):
            raise _bad(
                path,
                f"is a {kind} file whose {name!r} array has shape {a.shape}, expected "
                f"{tuple('*' if s is None else s for s in shape)} (non-empty)",
            )


def _load(path: pathlib.Path, kind: str):
    """The file's object, with its arrays checked against the kind."""
    try:
        if kind == "sweep":
            from ..sweeps import METRICS, SweepResult

            obj = SweepResult.load(path)
            shape = obj.shape
            missing = [
                k
                for k in ("growth_rate_per_s", "frequency_hz", "classification")
                if k not in obj.data
            ]
            if missing:
                raise _bad(path, f"is a sweep file without its {missing[0]!r} array")
            _check_shapes(
                path,
                kind,
                {
                    **{k: np.asarray(v) for k, v in obj.coords.items()},
                    **{k: obj.data[k] for k in METRICS if k in obj.data},
                },
                {
                    **{k: (len(v),) for k, v in obj.coords.items()},
                    **{k: shape for k in METRICS if k in obj.data},
                },
            )
            return obj
        if kind == "posterior":
            from ..inverse import Posterior

            post = Posterior.load(path)
            _check_shapes(path, kind, {"u": post.u}, {"u": (None, None, len(post.names))})
            return post
        if kind == "orbit_branch":
            from ..orbits.branch import Branch

            arrays, meta = Branch.load(path)
            n = len(np.atleast_1d(arrays.get("p", [])))
            need = (
                "p",
                "tip_amplitude_um",
                "frequency_hz",
                "stable",
                "floquet_real",
                "floquet_imag",
            )
            missing = [k for k in need if k not in arrays]
            if missing:
                raise _bad(path, f"is an orbit branch file without its {missing[0]!r} array")
            _check_shapes(
                path,
                kind,
                arrays,
                {
                    "p": (n,),
                    "tip_amplitude_um": (n,),
                    "frequency_hz": (n,),
                    "stable": (n,),
                    "floquet_real": (n, None),
                    "floquet_imag": (n, None),
                },
            )
            return arrays, meta
        from ..dynamics import Simulation

        sim = Simulation.load(path)
        T, S = len(sim.t_s), len(sim.x_um)
        _check_shapes(
            path,
            kind,
            {
                "t_s": sim.t_s,
                "x_um": sim.x_um,
                "tip_um": sim.tip_um,
                "psi_rad": sim.psi_rad,
                "centreline_um": sim.centreline_um,
            },
            {
                "t_s": (T,),
                "x_um": (S,),
                "tip_um": (T, None),
                "psi_rad": (T, S),
                "centreline_um": (T, None, S),
            },
        )
        return sim
    except common.CLIError:
        raise
    except READ_ERRORS as err:
        detail = str(err).splitlines()[0] if str(err) else "no detail"
        raise _bad(
            path,
            f"is a {kind} file that cannot be read whole ({type(err).__name__}: {detail}); "
            "rerun the command that wrote it",
        ) from None


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
    path = pathlib.Path(args.file)
    if not path.is_file():
        raise common.CLIError(
            f"FILE: {str(path)!r} does not exist" + (" (a directory)" if path.is_dir() else "")
        )
    kind = _meta(path).get("kind", "sweep")
    obj = _load(path, kind)
    try:
        if kind == "sweep":
            from ..plotting import plot_sweep

            return plot_sweep(obj), kind, None
        if kind == "posterior":
            from ..inverse import load_truth
            from ..plotting.corner import plot_corner

            return plot_corner(obj, truth=load_truth(path)), kind, None
        if kind == "orbit_branch":
            from ..plotting.orbits import plot_branch

            return plot_branch(*obj), kind, None
        from ..plotting import plot_simulation

        return plot_simulation(obj), kind, None
    except (ValueError, IndexError, KeyError, TypeError) as err:
        raise _bad(
            path,
            f"is a {kind} file whose contents do not make a figure ({type(err).__name__}: "
            f"{str(err).splitlines()[0] if str(err) else 'no detail'})",
        ) from None


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
    if args.file is not None and str(args.file).endswith(
        ".json"
    ):  # a fit report (axojax fit --out)
        fig, kind, model = _json_figure(args.file)
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


def _json_figure(path: str):
    """(figure, kind, None) of a JSON report: a comparison (``axojax compare --out``) or
    a fit report (``axojax fit --out``)."""
    from .fit import figure_of_report

    try:
        doc = json.loads(pathlib.Path(path).read_text())
    except (OSError, UnicodeDecodeError, ValueError):
        doc = None  # figure_of_report says what is wrong with the file
    if not (isinstance(doc, dict) and doc.get("kind") == "comparison"):
        return figure_of_report(path), "fit", None
    from ..plotting.compare import plot_comparison

    try:
        return plot_comparison(doc), "comparison", None
    except (KeyError, TypeError, ValueError, IndexError) as err:
        raise common.CLIError(f"FILE: {str(path)!r}: malformed comparison ({err})") from None


def render(doc: dict) -> str:
    return f"wrote {doc['figure']}"
