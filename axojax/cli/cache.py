"""``axojax cache``: what the compiled-program cache holds (its folder, programs, posterior
warm states, size against its bound); ``axojax cache clear`` empties it
(:mod:`axojax.cache`: ``AXOJAX_CACHE_DIR``, ``AXOJAX_CACHE_MAX_MB``).

JSON: ``{"directory", "enabled", "programs", "program_mb", "warm_states", "warm_mb",
"max_mb", "action", "removed"}`` (``max_mb`` -1: no bound; ``removed``: with ``clear``,
``{"programs", "warm_states", "mb"}``, else null).
"""

from __future__ import annotations

import argparse

from .. import cache
from . import common


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "action",
        nargs="?",
        choices=("info", "clear"),
        default="info",
        help="info (default): what the cache holds; clear: remove its compiled programs and "
        "posterior warm states (the next run of each command compiles again)",
    )
    parser.add_argument(
        "--json", action="store_true", help="print one JSON document on stdout and nothing else"
    )


def run(args: argparse.Namespace) -> dict:
    try:
        bound = cache.max_mb_setting()
    except ValueError as err:
        raise common.CLIError(str(err)) from None
    directory = cache.configured_cache_dir()
    doc = {
        "directory": None if directory is None else str(directory),
        "enabled": directory is not None,
        "max_mb": bound,
        "action": args.action,
        "removed": None,
    }
    if directory is not None and args.action == "clear":
        try:
            gone = cache.clear_cache(directory)
        except OSError as err:  # a read-only folder, a file in the way
            raise common.CLIError(f"cache clear: {directory}: {err.strerror or err}") from None
        doc["removed"] = {
            "programs": gone.programs,
            "warm_states": gone.warm_states,
            "mb": round(gone.total_mb, 3),
        }
    held = cache.cache_contents(directory) if directory is not None else None
    doc.update(
        programs=0 if held is None else held.programs,
        program_mb=0.0 if held is None else round(held.program_bytes / 1e6, 3),
        warm_states=0 if held is None else held.warm_states,
        warm_mb=0.0 if held is None else round(held.warm_bytes / 1e6, 3),
    )
    return doc


def render(doc: dict) -> str:
    if not doc["enabled"]:
        return f"compiled-program cache: off ({cache.CACHE_ENV} is off); every run compiles"
    bound = "no bound" if doc["max_mb"] == -1 else f"bound {doc['max_mb']:g} MB"
    lines = []
    if doc["removed"] is not None:
        r = doc["removed"]
        lines.append(
            f"removed {r['programs']} compiled programs and {r['warm_states']} posterior warm "
            f"states ({r['mb']:.1f} MB) from {doc['directory']}"
        )
    lines.append(
        f"compiled-program cache: {doc['directory']}: {doc['programs']} programs "
        f"({doc['program_mb']:.1f} MB), {doc['warm_states']} posterior warm states "
        f"({doc['warm_mb']:.1f} MB); {bound} ({cache.MAX_MB_ENV})"
    )
    return "\n".join(lines)
