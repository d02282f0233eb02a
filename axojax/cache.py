"""A persistent cache of compiled programs, so that a command does not recompile.

Every ``axojax`` command is a new process, and each compiles its programs afresh: about
3 s for a seven-filament sweep with the structured solver (its eigenvalues then take
~2 ms a point), more than the work of a few hundred points. JAX can keep compiled
programs on disk (``jax_compilation_cache_dir``); the command line turns that on:

- ``AXOJAX_CACHE_DIR=PATH``: keep them in PATH;
- unset: ``$XDG_CACHE_HOME/axojax/jax`` (``~/.cache/axojax/jax``);
- ``AXOJAX_CACHE_DIR=off`` (or empty): no cache;
- ``AXOJAX_CACHE_MAX_MB=N``: keep at most N MB of programs, the least recently used
  removed first (default :data:`DEFAULT_MAX_MB`; ``-1``: no bound). JAX's own bounded
  cache does this, with ``filelock`` for the lock several processes share.

A command that finds the cache empty says once on stderr that it compiles and that later
runs start faster; ``axojax cache`` shows what the cache holds and ``axojax cache clear``
empties it (:func:`cache_contents`, :func:`clear_cache`).

Only on jax 0.10 and newer: older jaxlibs log spurious "machine feature" errors on
stderr each time they load a cached CPU program. Only the ``axojax`` command (its
console entry point, and ``python -m axojax.cli.main``) does this; ``main()`` called in
Python, and Python code in general, caches nothing unless asked:
``ax.enable_compilation_cache()``. A cached program is the same program: results are
identical with and without the cache.

Posterior runs also keep their start-up there (:mod:`axojax.inverse.sampling._warm_cache`): the
posterior mode, the Laplace approximation and the warm-up's adapted state, in
``PATH/posterior/`` (:data:`WARM_SUBDIR`), so that an identical second run goes straight
to its draws. ``axojax fit --posterior`` does so whenever the compilation cache is on;
in Python, ``posterior(..., cache=True)`` (the same directory, ``off`` honoured) or
``cache=PATH``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import pathlib
import shutil

CACHE_ENV = "AXOJAX_CACHE_DIR"
MAX_MB_ENV = "AXOJAX_CACHE_MAX_MB"
DEFAULT_MAX_MB = 1024
"""The cache's bound (MB) unless ``AXOJAX_CACHE_MAX_MB`` says otherwise: the programs of
every command in the README take about 100 MB."""
PROGRAM_SUFFIXES = ("-cache", "-atime")
"""JAX's files in the cache directory: a program, and its last use (for the LRU bound)."""
WARM_SUBDIR = "posterior"
"""The posterior warm-state files' folder inside the cache directory."""
MIN_COMPILE_SECONDS = 0.5
"""Programs that compile faster than this are not worth a file."""


def default_cache_dir() -> pathlib.Path:
    """``$XDG_CACHE_HOME/axojax/jax``, or ``~/.cache/axojax/jax``."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return pathlib.Path(base) / "axojax" / "jax"


def enable_compilation_cache(
    path: str | os.PathLike | None = None, max_mb: float | int | None = None
) -> pathlib.Path:
    """Keep compiled programs in ``path`` (default :func:`default_cache_dir`) from now on,
    for this process, at most ``max_mb`` MB of them (default :func:`max_mb_setting`; -1:
    no bound; the least recently used go first). Returns the directory."""
    import jax

    directory = pathlib.Path(path) if path is not None else default_cache_dir()
    directory.mkdir(parents=True, exist_ok=True)
    bound = max_mb_setting() if max_mb is None else _bound(max_mb, "max_mb", repr(max_mb))
    jax.config.update("jax_compilation_cache_dir", str(directory))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", MIN_COMPILE_SECONDS)
    jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
    if bound != -1 and not _can_bound():
        bound = -1  # JAX's eviction needs filelock (a dependency; absent only in odd installs)
    if bound != -1:
        stamp_unstamped(directory)
    jax.config.update("jax_compilation_cache_max_size", -1 if bound == -1 else int(bound * 1e6))
    return directory


def stamp_unstamped(directory: pathlib.Path) -> int:
    """Give each program written without a bound (no ``-atime`` file beside it: axojax
    before the bound, or ``-1``) its last use, from its modification time, as JAX's
    bounded cache writes it; without one every later write fails. Returns how many."""
    stamped = 0
    for program in directory.glob("*-cache"):
        atime = program.with_name(program.name.removesuffix("-cache") + "-atime")
        if not atime.exists():
            try:
                atime.write_bytes(program.stat().st_mtime_ns.to_bytes(8, "little"))
                stamped += 1
            except OSError:  # gone meanwhile, or read-only: JAX copes or says so
                pass
    return stamped


def _can_bound() -> bool:
    try:
        import filelock  # noqa: F401
    except ImportError:
        return False
    return True


def max_mb_setting() -> float:
    """``AXOJAX_CACHE_MAX_MB`` (MB, or -1: no bound), :data:`DEFAULT_MAX_MB` when unset;
    a ``ValueError`` naming the variable for anything else."""
    text = os.environ.get(MAX_MB_ENV)
    if text is None or not text.strip():
        return float(DEFAULT_MAX_MB)
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    return _bound(value, MAX_MB_ENV, repr(text))


def _bound(value: float | int, name: str, shown: str) -> float:
    """``value`` as a cache bound in MB (finite and > 0, or -1), else a one-line
    ``ValueError`` naming ``name`` and the value as given (``shown``)."""
    if not (value == -1 or (math.isfinite(value) and value > 0)):
        raise ValueError(
            f"{name}: expected a finite size in MB > 0, or -1 for no bound, got {shown}"
        )
    return float(value)


def command_line_cache() -> pathlib.Path | None:
    """The command line's choice (module docstring): the directory now in use, or None."""
    import jax

    directory = configured_cache_dir()
    if directory is None or not quiet_loader(jax.__version__):
        return None
    try:
        return enable_compilation_cache(directory)
    except OSError:  # e.g. a read-only home: run without the cache
        return None


def quiet_loader(jax_version: str) -> bool:
    """Whether this jax loads cached CPU programs without spurious errors (>= 0.10)."""
    return tuple(int(x) for x in jax_version.split(".")[:2]) >= (0, 10)


def _off(setting: str) -> bool:
    return setting.strip().lower() in ("", "off", "0", "none")


def compilation_cache_dir() -> pathlib.Path | None:
    """The persistent compilation cache's directory in this process, or None when off."""
    import jax

    directory = jax.config.jax_compilation_cache_dir
    return pathlib.Path(directory) if directory else None


def posterior_cache_dir(cache) -> pathlib.Path | None:
    """Where :func:`axojax.inverse.posterior` keeps warm states for its ``cache=``
    argument: None or False: nowhere; True: ``WARM_SUBDIR`` in the command line's cache
    directory (``AXOJAX_CACHE_DIR``, else :func:`default_cache_dir`; None when that is
    ``off``); a path: that directory."""
    if cache is None or cache is False:
        return None
    if cache is True:
        directory = configured_cache_dir()
        return None if directory is None else directory / WARM_SUBDIR
    if isinstance(cache, (str, os.PathLike)) and str(cache):
        return pathlib.Path(cache)
    raise TypeError(f"cache must be None, True, False or a directory path, got {cache!r}")


@dataclasses.dataclass(frozen=True)
class CacheContents:
    """What a cache directory holds: compiled programs (JAX's ``*-cache`` files, with
    their ``*-atime`` companions) and posterior warm states (``posterior/``), in bytes."""

    directory: pathlib.Path
    programs: int
    program_bytes: int
    warm_states: int
    warm_bytes: int

    @property
    def total_mb(self) -> float:
        return (self.program_bytes + self.warm_bytes) / 1e6


def _program_files(directory: pathlib.Path) -> list[pathlib.Path]:
    if not directory.is_dir():
        return []
    return [f for f in directory.iterdir() if f.is_file() and f.name.endswith(PROGRAM_SUFFIXES)]


def _warm_files(directory: pathlib.Path) -> list[pathlib.Path]:
    warm = directory / WARM_SUBDIR
    return [f for f in warm.rglob("*") if f.is_file()] if warm.is_dir() else []


def cache_contents(directory: str | os.PathLike) -> CacheContents:
    """What ``directory`` (a cache directory) holds; zeros where it does not exist."""
    directory = pathlib.Path(directory)
    programs = _program_files(directory)
    warm = _warm_files(directory)
    return CacheContents(
        directory,
        sum(f.name.endswith("-cache") for f in programs),
        sum(f.stat().st_size for f in programs),
        len(warm),
        sum(f.stat().st_size for f in warm),
    )


def clear_cache(directory: str | os.PathLike) -> CacheContents:
    """Remove the compiled programs and posterior warm states from ``directory`` (nothing
    else: a cache pointed at a folder of one's own keeps one's files). Returns what was
    removed."""
    directory = pathlib.Path(directory)
    removed = cache_contents(directory)
    for f in _program_files(directory):
        f.unlink(missing_ok=True)
    (directory / ".lockfile").unlink(missing_ok=True)
    if (directory / WARM_SUBDIR).is_dir():
        shutil.rmtree(directory / WARM_SUBDIR)
    return removed


def configured_cache_dir() -> pathlib.Path | None:
    """The directory the command line would use (``AXOJAX_CACHE_DIR``, else
    :func:`default_cache_dir`), or None when that is ``off``; nothing is created."""
    setting = os.environ.get(CACHE_ENV)
    if setting is not None and _off(setting):
        return None
    return pathlib.Path(setting) if setting else default_cache_dir()
