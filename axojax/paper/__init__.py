"""Paper vs axojax: every number the paper states that the model can compute, beside
axojax's value and its exact sensitivities.

``python -m axojax.paper --write`` regenerates the table in README.md (between
``<!-- paper-table:start -->`` and ``<!-- paper-table:end -->``) and docs/paper_table.md.
In Python::

    from axojax import paper
    rows = paper.compute_rows(beat=False)          # eigen-analysis rows only (seconds)
    print(paper.group_table(rows, "fig. 7"))       # one figure group's markdown table

Modules: :mod:`~axojax.paper.claims` (the paper's numbers, as data),
:mod:`~axojax.paper.modes` (dominant-mode rows and elasticities),
:mod:`~axojax.paper.survey` (map rows), :mod:`~axojax.paper.beat` (the time-domain rows),
:mod:`~axojax.paper.inferred` (inferred parameter sets and their rows),
:mod:`~axojax.paper.table` (markdown and files).
"""

from __future__ import annotations

import pathlib
from typing import Sequence

from ..units import Units
from .beat import FAST, FULL, BeatRun, BeatSettings, beat_measures, beat_rows, run_beat
from .claims import CLAIMS, GROUPS, TOLERANCE, Claim, Row
from .inferred import INFERRED, Inferred, inferred_json, inferred_rows
from .modes import ELASTICITIES, evaluate, mode_rows
from .survey import ks_scan, map_sweep, survey_rows
from .table import group_table, markdown, replace_block, write


def compute_rows(
    claims: Sequence[Claim] = CLAIMS,
    *,
    beat: bool = True,
    settings: BeatSettings = FULL,
    units: Units = Units(),
    progress: bool = False,
    saved_beat: str | pathlib.Path | None = None,
) -> list[Row]:
    """axojax's row for every claim, in ``claims`` order.

    Args:
        beat: also run the time-domain rows (minutes at :data:`FULL`) and the limit-cycle
            rows with inferred parameters (seconds); without it they are left out.
        settings: how the beat is simulated (:data:`FULL` or :data:`FAST`).
        saved_beat: ``.npz`` path where the beat is saved, and reused from when it
            matches (:func:`run_beat`).
    """
    rows = mode_rows(claims, scan=ks_scan, units=units) + survey_rows(claims)
    if beat:
        rows += beat_rows(claims, settings, units, progress, saved_beat)
        rows += inferred_rows(claims, units)
    order = {c.key: k for k, c in enumerate(claims)}
    return sorted(rows, key=lambda r: order[r.claim.key])


__all__ = [
    "BeatRun",
    "BeatSettings",
    "CLAIMS",
    "Claim",
    "ELASTICITIES",
    "FAST",
    "FULL",
    "GROUPS",
    "INFERRED",
    "Inferred",
    "Row",
    "TOLERANCE",
    "beat_measures",
    "beat_rows",
    "compute_rows",
    "evaluate",
    "group_table",
    "inferred_json",
    "inferred_rows",
    "ks_scan",
    "map_sweep",
    "markdown",
    "mode_rows",
    "replace_block",
    "run_beat",
    "survey_rows",
    "write",
]
