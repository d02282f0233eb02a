"""Progress for long runs: one rule for when it shows, one way to make it.

Every run that can take more than a few seconds (comparisons, posterior warm-up and
draws, multi-start fits, sweeps, simulations, orbit branches) wraps its loop in
:func:`progress`, from before its first compilation::

    from axojax._progress import progress

    with progress(total=n_draws, desc="draws", unit="draw", enable=flag) as bar:
        for ...:
            bar.update(k)

    for start in progress(starts, desc="fit starts", unit="start", starting=True):
        ...

It shows after ``DELAY_S`` seconds (short runs print nothing), from the start of the
run: its elapsed time is refreshed while the first step (its compilation) runs, with
``starting`` saying what it waits for. How it shows is decided by :func:`style`:

- on a terminal (stderr a tty, or a notebook): tqdm's bar (rate and time left);
- else (stderr a log file or a pipe): plain lines, one per step done (at most one every
  ``DELAY_S``, and the last), each flushed, e.g.
  ``compare rows: 3/24 done, 41 s elapsed, 13.7 s/row, about 4 min 48 s left``;
- nothing under ``--quiet`` (every command's flag: :func:`quiet`), with
  ``AXOJAX_PROGRESS=0``, or when the caller passes ``enable=False`` (a library call's
  ``progress=False``); ``AXOJAX_PROGRESS=1`` forces it on without the delay (e.g. a test
  reading stderr through a pipe); ``--quiet`` wins over it.

Progress goes to stderr whatever stdout carries: ``--json`` on stdout stays one JSON
document, and ``axojax compare --json > cmp.json`` still shows its rows.

A step that is one compiled program (e.g. the posterior's warm-up, blackjax's window
adaptation in one ``lax.scan``) has no steps to count from Python; :func:`stage` shows
its elapsed time instead (a line when it has run ``DELAY_S``, and one when it is done).
(A host callback inside the program could count them, but jax keeps no program with
host callbacks in its persistent compilation cache, so every run would compile it
again.)
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from collections.abc import Iterable, Iterator
from typing import Any

from tqdm.asyncio import tqdm as console_tqdm
from tqdm.auto import tqdm

PROGRESS_ENV = "AXOJAX_PROGRESS"
DELAY_S = 2.0
"""Seconds before progress first shows (runs shorter than this print nothing), and the
least time between two plain lines of one run."""
TICK_S = 0.5
"""Seconds between the refreshes of a bar's elapsed time while it waits for a step."""
NOTEBOOK = tqdm is not console_tqdm
"""tqdm.auto chose its notebook widgets (a Jupyter kernel): bars there, not lines."""
_quiet = False
"""Set by :func:`quiet` (the commands' ``--quiet``)."""


def forced() -> bool | None:
    """``AXOJAX_PROGRESS``: True for ``1``/``on``, False for ``0``/``off``, else None."""
    value = os.environ.get(PROGRESS_ENV, "").strip().lower()
    if value in ("1", "on", "true", "yes"):
        return True
    if value in ("0", "off", "false", "no"):
        return False
    return None


@contextlib.contextmanager
def quiet(on: bool = True) -> Iterator[None]:
    """No progress at all while the block runs (when ``on``): every command runs inside
    it with its ``--quiet`` flag (``axojax.cli.main``)."""
    global _quiet
    before, _quiet = _quiet, bool(on) or _quiet
    try:
        yield
    finally:
        _quiet = before


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # replaced or closed streams
        return False


def style(enable: bool | None = None) -> str | None:
    """How progress shows (module docstring): ``"bars"`` (stderr a terminal, or a
    notebook), ``"lines"`` (stderr a file or a pipe) or None (:func:`quiet`,
    ``AXOJAX_PROGRESS=0``, or ``enable=False`` unless ``AXOJAX_PROGRESS=1``)."""
    force = forced()
    if _quiet or force is False or (force is None and enable is False):
        return None
    return "bars" if NOTEBOOK or _isatty(sys.stderr) else "lines"


def enabled(enable: bool | None = None) -> bool:
    """Whether progress shows at all (:func:`style`): what a command passes as a library
    call's ``progress=``."""
    return style(enable) is not None


def progress(
    iterable: Iterable | int | None = None,
    *,
    total: int | None = None,
    desc: str = "",
    unit: str = "it",
    enable: bool | None = None,
    starting: str | bool | None = None,
    **kwargs: Any,
) -> tqdm | Lines:
    """Progress on stderr over ``iterable`` (or ``total`` steps, or ``iterable`` given
    as an int): an iterator and a context manager, with ``update(n)``, ``set_postfix``
    and ``set_postfix_str``; a tqdm bar or plain :class:`Lines` (:func:`style`).

    Args:
        iterable: what to iterate over, or the number of steps (``update`` by hand).
        total: number of steps when ``iterable`` is None or has no length.
        desc: what runs, e.g. ``"posterior draws"``.
        unit: what one step is, e.g. ``"draw"``.
        enable: True/False from the caller (e.g. a ``progress=`` argument); None: the
            rule of :func:`style`. ``AXOJAX_PROGRESS`` and ``--quiet`` override both.
        starting: what the run waits for until its first step is done, shown beside
            the elapsed time; True: ``"the first {unit} compiles"``.
        **kwargs: passed to ``tqdm`` (e.g. ``leave``); plain lines ignore them.

    A disabled bar is tqdm's no-op bar: iterating it costs nothing extra.
    """
    if isinstance(iterable, int):
        iterable, total = None, iterable
    if starting is True:
        starting = f"the first {unit} compiles"
    return _make(iterable, total, desc, unit, enable, starting, False, kwargs)


def _make(iterable, total, desc, unit, enable, starting, is_stage, kwargs):
    """The bar or the lines of :func:`progress` and :func:`stage`."""
    how = style(enable)
    delay = 0.0 if forced() else DELAY_S
    if how == "lines":
        return Lines(iterable, total, desc, unit, delay, starting, is_stage)
    options = {"delay": delay, "dynamic_ncols": True, "file": sys.stderr, **kwargs}
    return _Bar(
        iterable,
        total=total,
        desc=desc,
        unit=unit,
        disable=how is None,
        starting=starting,
        **options,
    )


@contextlib.contextmanager
def stage(desc: str, *, enable: bool | None = None) -> Iterator[tqdm | Lines]:
    """Progress of one step that cannot count its progress: its elapsed time while the
    ``with`` block runs (same rule and delay as :func:`progress`); as plain lines, one
    when it has run ``DELAY_S`` and one when it is done."""
    bar = _make(None, None, desc, "", enable, None, True, {"bar_format": "{desc}: {elapsed}"})
    with bar:
        yield bar


class _Ticker:
    """A daemon thread that calls ``tick`` every :data:`TICK_S` until :meth:`stop`."""

    def __init__(self, tick) -> None:
        self._done = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(tick,), daemon=True)

    def _run(self, tick) -> None:
        while not self._done.wait(TICK_S):
            tick()

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._done.set()
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join()


class _Bar(tqdm):
    """tqdm's bar, shown from the start of the run (after its delay): a :class:`_Ticker`
    refreshes its elapsed time while a step runs (the first one's compilation included),
    ``starting`` beside it until the first step is done."""

    def __init__(self, *args: Any, starting: str | None = None, **kwargs: Any) -> None:
        self._ticker = None
        super().__init__(*args, **kwargs)
        self._starting = starting if not self.disable else None
        self._shown = False
        if self._starting:
            self.set_postfix_str(self._starting, refresh=False)
        if not self.disable:
            self._ticker = _Ticker(self._tick)
            self._ticker.start()

    def _tick(self) -> None:
        if self._time() >= self.start_t + self.delay:
            self.refresh()
            self._shown = True

    def update(self, n: int | float | None = 1) -> bool | None:
        if n and self._starting:
            if self.postfix == self._starting:  # not replaced by the caller meanwhile
                self.set_postfix_str("", refresh=False)
            self._starting = None
        return super().update(n)

    def close(self) -> None:
        if getattr(self, "_ticker", None) is not None:
            self._ticker.stop()
        if getattr(self, "_shown", False) and not self.disable:
            # shown by the ticker: tqdm would otherwise think it never was, and leave the
            # bar's line without its final state and newline
            self.last_print_t = max(self.last_print_t, self.start_t + self.delay)
        super().close()


def duration(seconds: int | float) -> str:
    """``41 s``, ``7 min 05 s``, ``2 h 03 min``: a time for a progress line."""
    s = int(round(seconds))
    if s < 60:
        return f"{s} s"
    if s < 3600:
        return f"{s // 60} min {s % 60:02d} s"
    return f"{s // 3600} h {s % 3600 // 60:02d} min"


def _rate(n: int | float, elapsed: float, unit: str) -> str:
    """Steps per second, or seconds per step when slower than one a second."""
    if n >= elapsed:
        return f"{n / max(elapsed, 1e-9):.3g} {unit}/s"
    return f"{elapsed / n:.3g} s/{unit}"


class Lines:
    """Progress as plain lines on stderr (stderr not a terminal: a log file, a pipe), the
    counterpart of tqdm's bar with its interface (iterate, ``with``, ``update``,
    ``set_postfix``, ``close``): one flushed line per step done (at most one every
    :data:`DELAY_S`, and the last) with done / total, elapsed time, rate and time left; a
    first line (0 done, ``starting``) once it has run ``delay`` s with nothing done; a
    stage's (:func:`stage`) when it has run ``delay`` s and when it is done. A run that
    ends within ``delay`` prints nothing."""

    def __init__(self, iterable, total, desc, unit, delay, starting=None, is_stage=False):
        if total is None and hasattr(iterable, "__len__"):
            total = len(iterable)
        self.iterable, self.total, self.desc, self.unit = iterable, total, desc, unit
        self.delay, self.is_stage, self.n, self.disable = delay, is_stage, 0, False
        self._starting, self._postfix = starting or "", ""
        self._start = time.monotonic()
        self._printed: tuple[float, float] | None = None  # (when, n) of the last line
        self._lock = threading.Lock()
        self._ticker = _Ticker(self._tick)
        self._ticker.start()

    def __iter__(self) -> Iterator:
        try:
            for item in self.iterable:
                yield item
                self.update(1)
        finally:
            self.close()

    def __enter__(self) -> Lines:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def update(self, n: int | float = 1) -> None:
        """``n`` more steps done: a line, unless the run is within its delay or a line
        was written within ``DELAY_S``."""
        if not n or self.disable:
            return
        self.n += n
        now = time.monotonic()
        if now - self._start < self.delay:
            return
        if self._printed is None or now - self._printed[0] >= DELAY_S:
            self._write(now)

    def set_postfix_str(self, s: str = "", refresh: bool = True) -> None:
        """Text after the counts of the next line (as tqdm's)."""
        self._postfix = str(s)

    def set_postfix(self, ordered_dict=None, refresh: bool = True, **kwargs: Any) -> None:
        """``key=value`` pairs after the counts of the next line (as tqdm's)."""
        items = {**(ordered_dict or {}), **kwargs}
        self.set_postfix_str(", ".join(f"{k}={v}" for k, v in items.items()))

    def close(self) -> None:
        """Stop; the last state (or the stage's "done") when anything was or is due."""
        if self.disable:
            return
        self.disable = True
        self._ticker.stop()
        now = time.monotonic()
        if self._printed is not None and self._printed[1] == self.n and not self.is_stage:
            return  # the last line already says it
        if self._printed is not None or now - self._start >= self.delay:
            self._write(now, done=True)

    def _tick(self) -> None:
        """The first line, once the run has gone ``delay`` s with none written."""
        now = time.monotonic()
        if self._printed is None and now - self._start >= self.delay:
            self._write(now, first=True)

    def _write(self, now: float, done: bool = False, first: bool = False) -> None:
        """One line (``first``: only if none was written yet; the ticker's thread)."""
        with self._lock:
            if first and self._printed is not None:
                return  # the run's own thread wrote one meanwhile
            self._printed = (now, self.n)
            sys.stderr.write(self._line(now - self._start, done) + "\n")
            sys.stderr.flush()

    def _line(self, elapsed: float, done: bool) -> str:
        """``desc: 3/24 done, 41 s elapsed, 13.7 s/row, about 4 min 48 s left (postfix)``."""
        if self.is_stage:
            return f"{self.desc}: {'done' if done else 'running'}, {duration(elapsed)} elapsed"
        count = f"{self.n:g}" if self.total is None else f"{self.n:g}/{self.total:g}"
        parts = [f"{self.desc}: {count} done", f"{duration(elapsed)} elapsed"]
        if self.n:
            parts.append(_rate(self.n, elapsed, self.unit))
            if self.total and self.n < self.total:
                parts.append(f"about {duration(elapsed * (self.total - self.n) / self.n)} left")
        line = ", ".join(parts)
        postfix = self._postfix or ("" if self.n else self._starting)
        return f"{line} ({postfix})" if postfix else line
