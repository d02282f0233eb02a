"""The figure of a file an axojax command wrote (``axojax plot FILE``): a sweep, simulation,
orbit branch or posterior ``.npz`` (each type reads and checks its own file: ``read``), a
fit report or a comparison ``.json`` (each says whether a document is its own:
``is_document``). Anything else is one :class:`~axojax.results.ResultFileError` naming
the file."""

from __future__ import annotations

import json
import pathlib

from ..results import ResultFileError, file_meta

NPZ_KINDS = ("sweep", "simulation", "orbit_branch", "posterior")
"""The ``meta`` kinds of the ``.npz`` files drawn (a sweep's file names no kind)."""
DRAW_ERRORS = (ValueError, IndexError, KeyError, TypeError)
"""What a figure of contents that make none raises."""


def npz_kind(path) -> str:
    """The kind of an ``.npz`` file axojax wrote (:data:`NPZ_KINDS`)."""
    kind = file_meta(path).get("kind", "sweep")
    if kind not in NPZ_KINDS:
        raise ResultFileError(
            f"{str(path)!r} has kind {kind!r}; axojax plots {', '.join(NPZ_KINDS)} files"
        )
    return kind


def figure_of_npz(path) -> tuple[object, str]:
    """(figure, kind) of a sweep's stability map, a simulation's beat, an orbit branch or
    a posterior's corner plot (with the truth the file marks)."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise ResultFileError(
            f"{str(path)!r} does not exist" + (" (a directory)" if path.is_dir() else "")
        )
    kind = npz_kind(path)
    if kind == "sweep":
        from ..sweeps import SweepResult

        obj = SweepResult.read(path)
    elif kind == "posterior":
        from ..inverse import Posterior

        obj = Posterior.read(path)
    elif kind == "orbit_branch":
        from ..orbits.branch import Branch

        obj = Branch.read(path)
    else:
        from ..dynamics import Simulation

        obj = Simulation.read(path)
    try:
        return _draw(path, kind, obj), kind
    except DRAW_ERRORS as err:
        detail = str(err).splitlines()[0] if str(err) else "no detail"
        raise ResultFileError(
            f"{str(path)!r} is a {kind} file whose contents do not make a figure "
            f"({type(err).__name__}: {detail})"
        ) from None


def _draw(path: pathlib.Path, kind: str, obj):
    if kind == "sweep":
        from . import plot_sweep

        return plot_sweep(obj)
    if kind == "posterior":
        from ..inverse import load_truth
        from .corner import plot_corner

        return plot_corner(obj, truth=load_truth(path))
    if kind == "orbit_branch":
        from .orbits import plot_branch

        return plot_branch(*obj)
    from . import plot_simulation

    return plot_simulation(obj)


def figure_of_report(path) -> tuple[object, str]:
    """(figure, kind) of a JSON report: a comparison, linear or of the whole beat
    (``axojax compare --out``, :meth:`~axojax.inverse.comparison.compare.Comparison.is_document`,
    :meth:`~axojax.inverse.whole_beat.compare.WholeBeatComparison.is_document`) or a fit report
    (``axojax fit --out``, :meth:`~axojax.inverse.FitResult.is_document`)."""
    from ..inverse.comparison.compare import Comparison
    from ..inverse.whole_beat.compare import WholeBeatComparison

    try:
        doc = json.loads(pathlib.Path(path).read_text())
    except (OSError, UnicodeDecodeError, ValueError):
        doc = None  # _fit_report says what is wrong with the file
    if not (Comparison.is_document(doc) or WholeBeatComparison.is_document(doc)):
        return _fit_report(path), "fit"
    from .compare import plot_comparison

    try:
        return plot_comparison(doc), "comparison"
    except (KeyError, TypeError, ValueError, IndexError) as err:
        raise ResultFileError(f"{str(path)!r}: malformed comparison ({err})") from None


def _fit_report(path):
    from ..inverse import FitResult
    from .fit_report import plot_fit_report

    path = pathlib.Path(path)
    if not path.is_file():
        raise ResultFileError(f"{str(path)!r} does not exist")
    try:
        doc = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, ValueError) as err:
        raise ResultFileError(f"cannot read {str(path)!r} as JSON ({err})") from None
    if not FitResult.is_document(doc):
        raise ResultFileError(
            f"{str(path)!r} is not a fit report (write one with 'axojax fit --out FIT.json')"
        )
    try:
        return plot_fit_report(doc)
    except (KeyError, TypeError, ValueError) as err:
        raise ResultFileError(f"{str(path)!r}: malformed fit report ({err})") from None


def figure_of_file(path) -> tuple[object, str]:
    """(figure, kind) of any file axojax wrote: a ``.json`` report
    (:func:`figure_of_report`), else an ``.npz`` result (:func:`figure_of_npz`)."""
    if str(path).endswith(".json"):
        return figure_of_report(path)
    return figure_of_npz(path)
