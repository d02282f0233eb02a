"""Progress bars for long runs: one rule for when they show, one way to make them.

Every run that can take more than a few seconds (posterior warm-up and draws, multi-start
fits, spec fits, sweeps, comparisons) wraps its loop in :func:`progress`::

    from axojax._progress import progress

    with progress(total=n_draws, desc="draws", unit="draw", enable=flag) as bar:
        for ...:
            bar.update(k)

    for start in progress(starts, desc="fit starts", unit="start", enable=flag):
        ...

The bar is tqdm's (rate and time left), written to stderr, and shown only after
``DELAY_S`` seconds, so short runs print nothing. When it is shown is decided by
:func:`enabled`:

- ``AXOJAX_PROGRESS=1`` forces bars on (no delay; e.g. a test reading stderr through a
  pipe), ``AXOJAX_PROGRESS=0`` forces them off;
- otherwise bars show only when stderr is a terminal, and never when the output is JSON
  going to a pipe (``axojax fit --json | jq``): a caller that writes JSON to stdout passes
  ``json_output=True``.

A step that is one compiled program (e.g. the posterior's warm-up, blackjax's window
adaptation in one ``lax.scan``) has no steps to count from Python; :func:`stage` shows
its elapsed time instead. (A host callback inside the program could count them, but jax
keeps no program with host callbacks in its persistent compilation cache, so every run
would compile it again.)

Bars never touch stdout, so JSON on stdout stays parseable whatever the setting.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
from collections.abc import Iterable, Iterator
from typing import Any

from tqdm.auto import tqdm

PROGRESS_ENV = "AXOJAX_PROGRESS"
DELAY_S = 2.0
"""Seconds before a bar first shows: runs shorter than this print nothing."""


def forced() -> bool | None:
    """``AXOJAX_PROGRESS``: True for ``1``/``on``, False for ``0``/``off``, else None."""
    value = os.environ.get(PROGRESS_ENV, "").strip().lower()
    if value in ("1", "on", "true", "yes"):
        return True
    if value in ("0", "off", "false", "no"):
        return False
    return None


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # replaced or closed streams
        return False


def enabled(json_output: bool = False) -> bool:
    """Whether a bar shows (module docstring): forced by ``AXOJAX_PROGRESS``, else only when
    stderr is a terminal and not (``json_output`` and stdout is a pipe or file)."""
    force = forced()
    if force is not None:
        return force
    if not _isatty(sys.stderr):
        return False
    return not (json_output and not _isatty(sys.stdout))


def progress(
    iterable: Iterable | int | None = None,
    *,
    total: int | None = None,
    desc: str = "",
    unit: str = "it",
    enable: bool | None = None,
    json_output: bool = False,
    **kwargs: Any,
) -> tqdm:
    """A tqdm bar on stderr over ``iterable`` (or ``total`` steps, or ``iterable`` given
    as an int): an iterator and a context manager, with ``update(n)``, ``set_postfix``.

    Args:
        iterable: what to iterate over, or the number of steps (``update`` by hand).
        total: number of steps when ``iterable`` is None or has no length.
        desc: what runs, e.g. ``"posterior draws"``.
        unit: what one step is, e.g. ``"draw"``.
        enable: True/False from the caller (e.g. a ``progress=`` argument); None: the
            rule of :func:`enabled`. ``AXOJAX_PROGRESS`` overrides both.
        json_output: the caller writes JSON to stdout (see :func:`enabled`).
        **kwargs: passed to ``tqdm`` (e.g. ``leave``).

    A disabled bar is tqdm's no-op bar: iterating it costs nothing extra.
    """
    if isinstance(iterable, int):
        iterable, total = None, iterable
    force = forced()
    show = force if force is not None else (enabled(json_output) if enable is None else enable)
    options = {"delay": 0.0 if force else DELAY_S, "dynamic_ncols": True, "file": sys.stderr}
    options.update(kwargs)
    return tqdm(iterable, total=total, desc=desc, unit=unit, disable=not show, **options)


TICK_S = 0.5
"""Seconds between the refreshes of a :func:`stage` bar."""


@contextlib.contextmanager
def stage(desc: str, *, enable: bool | None = None, json_output: bool = False) -> Iterator[tqdm]:
    """A bar for one step that cannot count its progress: its elapsed time, refreshed
    every ``TICK_S`` by a thread while the ``with`` block runs (same rule and delay as
    :func:`progress`)."""
    bar = progress(
        total=None,
        desc=desc,
        unit="",
        enable=enable,
        json_output=json_output,
        bar_format="{desc}: {elapsed}",
    )
    done = threading.Event()

    def tick():
        while not done.wait(TICK_S):
            bar.update(0)

    thread = threading.Thread(target=tick, daemon=True)
    if not bar.disable:
        thread.start()
    try:
        yield bar
    finally:
        done.set()
        if thread.is_alive():
            thread.join()
        bar.close()
