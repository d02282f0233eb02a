"""Entry point of the ``axojax`` command."""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import re
import sys

from .. import _progress, _runtime
from ..cache import cache_contents, command_line_cache
from .common import CLIError, emit_json

SUBCOMMANDS = {
    "modes": "spectrum and dominant mode at one parameter point",
    "critical": "Hopf point in p, optionally along a second parameter",
    "sweep": "dominant mode over a parameter grid, saved to .npz",
    "fit": (
        "estimate free parameters from observed beats "
        "(least squares: Levenberg-Marquardt by default; posteriors by the mode-aware "
        "sampler or NUTS, chosen by the problem)"
    ),
    "simulate": "nonlinear beat in the time domain (diffrax), saved to .npz",
    "orbit": "limit cycle computed directly, or its branch in p from the Hopf point",
    "data": "what axojax extracts from beat data (frequency, psi_0, psi_1, planarity) before any fit",
    "compare": "rank mechanisms (steady load, sliding and curvature control) x base conditions on one observed beat",
    "plot": "figures of a sweep, simulation, orbit branch, posterior or fit report, or of a cross-section",
    "cache": "what the compiled-program cache holds (later runs skip compilation); 'clear' empties it",
}

COMPILING = ("modes", "critical", "sweep", "fit", "simulate", "orbit", "compare")
"""The commands whose first run on a machine is mostly compilation."""


VALUE_LIKE = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)
"""Arguments that are values although they start with '-': numbers and axes such as
``-1``, ``-1e3``, ``-1:1:3``, ``-0.5,0,0.5`` (no axojax flag starts with a digit)."""

EXIT_SIGPIPE = 128 + 13
"""Exit status after the reader of stdout went away (as a Unix tool killed by SIGPIPE)."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage block) on stderr, no abbreviated flags
    (``--gam`` is not ``--gamma``: a sweep's axis order follows its flags), and values
    that start with '-' (``--gamma -1:1:3``) taken as values."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = VALUE_LIKE

    def error(self, message: str) -> None:  # noqa: D401
        raise CLIError(message)


def version() -> str:
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as dist_version

    try:
        return dist_version("axojax")
    except PackageNotFoundError:  # a source tree on PYTHONPATH
        return "unknown"


QUIET_HELP = (
    "no progress on stderr (by default long runs show it after 2 s: bars on a terminal, "
    "else one plain line per step or stage, done / total and elapsed time; warnings and "
    "errors still print)"
)


PROFILE_HELP = (
    "at the end, a table on stderr of the programs this run compiled (seconds tracing, "
    "lowering, XLA; how often each; programs loaded from the cache instead)"
)


def add_quiet_flag(parser: argparse.ArgumentParser, default) -> None:
    """``--quiet`` and ``--profile-compile``, before or after the subcommand's name (the
    subcommand's default is ``SUPPRESS``, so that it keeps a flag given before it)."""
    parser.add_argument("--quiet", action="store_true", default=default, help=QUIET_HELP)
    parser.add_argument(
        "--profile-compile", action="store_true", default=default, help=PROFILE_HELP
    )


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The full parser; with ``only``, the flags of that subcommand alone (the others
    listed but not imported: ``axojax sweep`` never loads diffrax, optax or matplotlib)."""
    parser = _Parser(
        prog="axojax",
        description="Flutter of the ciliary axoneme: eigen-analysis, sweeps, fits and simulations.",
    )
    parser.add_argument("--version", action="version", version=f"axojax {version()}")
    add_quiet_flag(parser, False)
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    for name, help_text in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        add_quiet_flag(p, argparse.SUPPRESS)
        if only is None or name == only:
            module = importlib.import_module(f"axojax.cli.{name}")
            module.add_arguments(p)
            p.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    first = _command(argv)
    parser = build_parser(first if first in SUBCOMMANDS else None)
    try:
        args = parser.parse_args(argv)
        args._argv = argv
        if args.command is None:
            parser.print_help(sys.stderr)
            return 2
        with _progress.quiet(args.quiet), _profiled(args.profile_compile):
            doc = args._module.run(args)
    except CLIError as err:
        print(f"axojax: error: {err}", file=sys.stderr)
        return 2
    if doc is not None:
        try:
            if getattr(args, "json", False):
                emit_json(doc)
            else:
                print(args._module.render(doc))
            sys.stdout.flush()
        except BrokenPipeError:
            return _stdout_gone()
    return getattr(args, "_exit_code", 0)


@contextlib.contextmanager
def _profiled(on: bool):
    """``--profile-compile``: the run inside :func:`~axojax.compile_profile.compile_profile`,
    its table on stderr after (also when the run stops with an error)."""
    if not on:
        yield
        return
    from ..compile_profile import compile_profile

    try:
        with compile_profile() as profile:
            yield
    finally:
        print(profile.table(), file=sys.stderr)


def _stdout_gone() -> int:
    """The reader of stdout went away (``axojax ... | head``): stop quietly, as Unix tools
    do; stdout goes to /dev/null so the interpreter's final flush cannot complain."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout without a file descriptor (tests capture it)
        pass
    return EXIT_SIGPIPE


def console() -> int:
    """The ``axojax`` command: :func:`main` with compiled programs kept across commands
    (:mod:`axojax.cache`)."""
    argv = sys.argv[1:]
    if many_programs(argv):
        _runtime.compile_for_many_programs()
    try:
        directory = command_line_cache()
    except ValueError as err:  # AXOJAX_CACHE_MAX_MB
        print(f"axojax: error: {err}", file=sys.stderr)
        return 2
    if directory is not None and first_run(argv, cache_contents(directory).programs):
        print(
            f"axojax: the first run on this machine compiles its programs (minutes); they are "
            f"kept in {directory}, so later runs start faster",
            file=sys.stderr,
        )
    return main(argv)


def many_programs(argv: list[str]) -> bool:
    """Whether this command builds many programs and runs each briefly (the linear
    ``compare``: two per row), so that XLA's backend optimisation level 0 saves more
    compilation than it costs (``axojax._runtime``, item 5)."""
    whole_beat = any(
        a == "--target=limit-cycle" or (a == "--target" and b == "limit-cycle")
        for a, b in zip(argv, [*argv[1:], ""])
    )
    return _command(argv) == "compare" and not whole_beat


def first_run(argv: list[str], programs: int) -> bool:
    """Whether to say that this run compiles and later ones will not: a compiling command
    (:data:`COMPILING`), not asked for help or quiet, and a cache with no programs yet."""
    asked = {"-h", "--help", "--quiet", "--version"} & set(argv)
    return _command(argv) in COMPILING and not asked and programs == 0


def _command(argv: list[str]) -> str | None:
    """The subcommand's name: the first argument that is not a flag (the flags before it,
    --quiet and --profile-compile, take no value)."""
    return next((a for a in argv if not a.startswith("-")), None)


if __name__ == "__main__":
    sys.exit(console())
