"""A persistent cache of compiled programs, so that a command does not recompile.

Every ``axojax`` command is a new process, and each compiles its programs afresh: about
3 s for a seven-filament sweep with the structured solver (its eigenvalues then take
~2 ms a point), more than the work of a few hundred points. JAX can keep compiled
programs on disk (``jax_compilation_cache_dir``); the command line turns that on:

- ``AXOJAX_CACHE_DIR=PATH``: keep them in PATH;
- unset: ``$XDG_CACHE_HOME/axojax/jax`` (``~/.cache/axojax/jax``);
- ``AXOJAX_CACHE_DIR=off`` (or empty): no cache.

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

import os
import pathlib

CACHE_ENV = "AXOJAX_CACHE_DIR"
WARM_SUBDIR = "posterior"
"""The posterior warm-state files' folder inside the cache directory."""
MIN_COMPILE_SECONDS = 0.5
"""Programs that compile faster than this are not worth a file."""


def default_cache_dir() -> pathlib.Path:
    """``$XDG_CACHE_HOME/axojax/jax``, or ``~/.cache/axojax/jax``."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return pathlib.Path(base) / "axojax" / "jax"


def enable_compilation_cache(path: str | os.PathLike | None = None) -> pathlib.Path:
    """Keep compiled programs in ``path`` (default :func:`default_cache_dir`) from now on,
    for this process. Returns the directory."""
    import jax

    directory = pathlib.Path(path) if path is not None else default_cache_dir()
    directory.mkdir(parents=True, exist_ok=True)
    jax.config.update("jax_compilation_cache_dir", str(directory))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", MIN_COMPILE_SECONDS)
    jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
    return directory


def command_line_cache() -> pathlib.Path | None:
    """The command line's choice (module docstring): the directory now in use, or None."""
    import jax

    setting = os.environ.get(CACHE_ENV)
    if setting is not None and _off(setting):
        return None
    if not quiet_loader(jax.__version__):
        return None
    try:
        return enable_compilation_cache(setting or None)
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
        setting = os.environ.get(CACHE_ENV)
        if setting is not None and _off(setting):
            return None
        return (pathlib.Path(setting) if setting else default_cache_dir()) / WARM_SUBDIR
    if isinstance(cache, (str, os.PathLike)) and str(cache):
        return pathlib.Path(cache)
    raise TypeError(f"cache must be None, True, False or a directory path, got {cache!r}")
