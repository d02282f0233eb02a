"""A comparison's rows fitted several at a time, each after the rows it contains.

A comparison fits its rows in their nested order (:func:`~.mechanisms.nested_order`): a
row starts from the optima of the rows it contains (:func:`~.mechanisms.contained`), so
those come first. Most of a row's time is building its programs (docs/benchmarks.md, "Where
a comparison's time goes"), and XLA builds and runs a program without Python's lock, so on
a machine with two cores two rows at a time take about half the time of one at a time.
:func:`fit_rows` runs them on a pool of threads, submitted in that order: a row waits
only for the rows it contains, which were submitted before it, so every row it waits for
is already running or done. Each row computes what it would alone (the same programs from
the same inputs): the rows are identical to those of one worker.
"""

from __future__ import annotations

import concurrent.futures
import os
import warnings
from collections.abc import Callable, Sequence
from typing import Any

from ..._progress import progress as progress_bar

MAX_WORKERS = 4
"""Rows at a time at most (each holds its programs in memory while it builds them)."""

Combo = tuple[str, str]


WORKERS_ENV = "AXOJAX_COMPARE_WORKERS"
"""Rows at a time when ``compare`` is not told (e.g. 1 where other jobs fill the cores)."""


def default_workers() -> int:
    """Rows at a time by default: ``AXOJAX_COMPARE_WORKERS`` when set (an integer >= 1;
    a ``ValueError`` naming it otherwise), else the machine's cores, at most
    :data:`MAX_WORKERS`."""
    text = os.environ.get(WORKERS_ENV, "").strip()
    if text:
        if not (text.isdigit() and int(text) >= 1):
            raise ValueError(f"{WORKERS_ENV}: expected an integer >= 1, got {text!r}")
        return int(text)
    return max(1, min(os.cpu_count() or 1, MAX_WORKERS))


def fit_rows(
    combos: Sequence[Combo],
    fit_one: Callable[[Combo, list[Any]], Any],
    contained: Callable[[str, str], list[Combo]],
    *,
    workers: int = 1,
    progress: bool = False,
) -> dict[Combo, Any]:
    """``fit_one(combo, inner)`` for every ``(mechanism, base)`` of ``combos`` (in nested
    order), ``inner`` the results of the rows it contains (``contained(*combo)``, those
    among ``combos``), ``workers`` rows at a time. Returns the results by combo; the
    progress bar counts rows in ``combos``' order."""
    if not (isinstance(workers, int) and workers >= 1):
        raise ValueError(f"workers: expected an integer >= 1, got {workers!r}")
    order = list(combos)
    done: dict[Combo, Any] = {}
    bar = progress_bar(order, desc="compare rows", unit="row", enable=progress, starting=True)
    if workers == 1:
        for combo in bar:
            done[combo] = fit_one(combo, [done[c] for c in contained(*combo) if c in done])
        return done
    futures: dict[Combo, concurrent.futures.Future] = {}

    def task(combo: Combo, inner: list[concurrent.futures.Future]):
        return fit_one(combo, [f.result() for f in inner])

    # one filter state for every thread: the rows' own catch_warnings blocks then save and
    # restore the same state whatever their order (warnings' filters are process-wide)
    with warnings.catch_warnings(), concurrent.futures.ThreadPoolExecutor(workers) as pool:
        warnings.simplefilter("ignore")
        for combo in order:
            inner = [futures[c] for c in contained(*combo) if c in futures]
            futures[combo] = pool.submit(task, combo, inner)
        try:
            for combo in bar:
                done[combo] = futures[combo].result()
        except BaseException:
            for future in futures.values():
                future.cancel()
            raise
    return done
