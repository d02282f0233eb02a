"""Which programs a run compiles and how long each took: ``axojax --profile-compile CMD``
(a table on stderr at the end), or :func:`compile_profile` in Python.

JAX says what it compiles through its loggers when ``jax_log_compiles`` is on: for each
program the tracing, the lowering to MLIR and XLA's compilation, each with its seconds.
:func:`compile_profile` turns that on for the duration of a ``with`` block, collects those
lines (not printing them, and letting every other line through), and counts the programs
loaded from the persistent cache (:mod:`axojax.cache`). Programs are grouped by the name JAX
gives them (``jit(fn)``): a name compiled several times was traced again for new shapes
or new static arguments, which is what batching rows into one program removes.

>>> with compile_profile() as prof:
...     ax.compare(beat)
>>> print(prof.table())
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import re
import time
from collections.abc import Iterator

import jax

STAGES = ("tracing", "lowering", "compiling")
"""What JAX reports per program: tracing to a jaxpr, lowering to MLIR, XLA compilation."""

_PATTERNS = (
    (
        "tracing",
        re.compile(r"^Finished tracing(?: \+ transforming)? (.+?) for \S+ in ([0-9.e+-]+) sec"),
    ),
    (
        "lowering",
        re.compile(r"^Finished jaxpr to MLIR module conversion (.+?) in ([0-9.e+-]+) sec"),
    ),
    ("compiling", re.compile(r"^Finished XLA compilation of (.+?) in ([0-9.e+-]+) sec")),
)
_CACHE_HIT = re.compile(r"^Persistent compilation cache hit for '(.+?)'")
_LOGGERS = ("jax._src.dispatch", "jax._src.interpreters.pxla", "jax._src.compiler")
"""Where JAX writes the lines ``jax_log_compiles`` turns on."""
_SILENCED = ("Finished ", "Compiling ", "Persistent compilation cache ")
_JIT_NAME = re.compile(r"^jit\((.+)\)$")


@dataclasses.dataclass
class ProgramTimes:
    """One program name's builds (each a compilation, or a load from the persistent
    cache, whose XLA stage is then the load): how many, and seconds per stage (summed)."""

    name: str
    compilations: int = 0
    tracing: float = 0.0
    lowering: float = 0.0
    compiling: float = 0.0

    @property
    def total(self) -> float:
        return self.tracing + self.lowering + self.compiling


@dataclasses.dataclass
class CompileProfile:
    """What :func:`compile_profile` saw: programs by name, cache hits, wall time (s)."""

    programs: dict[str, ProgramTimes] = dataclasses.field(default_factory=dict)
    cache_hits: int = 0
    wall_s: float = 0.0

    def record(self, stage: str, name: str, seconds: float) -> None:
        match = _JIT_NAME.match(name)
        name = match.group(1) if match else name
        entry = self.programs.setdefault(name, ProgramTimes(name))
        setattr(entry, stage, getattr(entry, stage) + seconds)
        if stage == "compiling":
            entry.compilations += 1

    @property
    def total_s(self) -> float:
        """Seconds spent tracing, lowering and compiling, all programs."""
        return sum((p.total for p in self.programs.values()), 0.0)

    def to_json(self) -> dict:
        return {
            "wall_s": self.wall_s,
            "compile_s": self.total_s,
            "cache_hits": self.cache_hits,
            "programs": [dataclasses.asdict(p) for p in self.sorted()],
        }

    def sorted(self) -> list[ProgramTimes]:
        return sorted(self.programs.values(), key=lambda p: -p.total)

    def table(self, rows: int = 25) -> str:
        """The programs by total seconds, longest first (at most ``rows`` lines, then the
        rest summed), and the totals."""
        programs = self.sorted()
        compiled = sum(p.compilations for p in programs)
        lines = [
            f"compilation: {self.total_s:.1f} s of {self.wall_s:.1f} s wall; {compiled} "
            f"builds of {len(programs)} programs ({self.cache_hits} of them loaded from the "
            "persistent cache)",
            f"{'seconds':>8} {'builds':>8} {'tracing':>8} {'lowering':>8} {'XLA':>8}  program",
        ]
        for p in programs[:rows]:
            lines.append(
                f"{p.total:8.2f} {p.compilations:8d} {p.tracing:8.2f} {p.lowering:8.2f} "
                f"{p.compiling:8.2f}  {p.name}"
            )
        rest = programs[rows:]
        if rest:
            lines.append(
                f"{sum((p.total for p in rest), 0.0):8.2f} {sum(p.compilations for p in rest):8d} "
                f"{'':8} {'':8} {'':8}  ({len(rest)} more programs)"
            )
        return "\n".join(lines)


class _Collector(logging.Filter):
    """On JAX's compile loggers: records the compile lines and drops them (returns
    False); every other line passes."""

    def __init__(self, profile: CompileProfile) -> None:
        super().__init__()
        self.profile = profile

    def filter(self, record: logging.LogRecord) -> bool:
        message = record.getMessage()
        for stage, pattern in _PATTERNS:
            match = pattern.match(message)
            if match:
                self.profile.record(stage, match.group(1), float(match.group(2)))
                return False
        if _CACHE_HIT.match(message):
            self.profile.cache_hits += 1
            return False
        return not message.startswith(_SILENCED)


@contextlib.contextmanager
def compile_profile() -> Iterator[CompileProfile]:
    """Collect what JAX compiles inside the block (its compile lines kept, not printed)."""
    profile = CompileProfile()
    collector = _Collector(profile)
    loggers = [logging.getLogger(name) for name in _LOGGERS]
    was_logging = jax.config.jax_log_compiles
    for logger in loggers:
        logger.addFilter(collector)
    jax.config.update("jax_log_compiles", True)
    t0 = time.perf_counter()
    try:
        yield profile
    finally:
        profile.wall_s = time.perf_counter() - t0
        jax.config.update("jax_log_compiles", was_logging)
        for logger in loggers:
            logger.removeFilter(collector)
