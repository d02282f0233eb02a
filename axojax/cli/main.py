"""Entry point of the ``axojax`` command."""

from __future__ import annotations

import argparse
import importlib
import sys

from ..cache import command_line_cache
from .common import CLIError, emit_json

SUBCOMMANDS = {
    "modes": "spectrum and dominant mode at one parameter point",
    "critical": "Hopf point in p, optionally along a second parameter",
    "sweep": "dominant mode over a parameter grid, saved to .npz",
    "fit": "estimate free parameters from observed beats (optax)",
    "simulate": "nonlinear beat in the time domain (diffrax), saved to .npz",
    "orbit": "limit cycle computed directly, or its branch in p from the Hopf point",
    "plot": "figures of a sweep or simulation file, or of a cross-section",
}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage block) on stderr."""

    def error(self, message: str) -> None:  # noqa: D401
        raise CLIError(message)


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The full parser; with ``only``, the flags of that subcommand alone (the others
    listed but not imported: ``axojax sweep`` never loads diffrax, optax or matplotlib)."""
    parser = _Parser(prog="axojax", description="Flutter of the ciliary axoneme: eigen-analysis, sweeps, fits and simulations.")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    for name, help_text in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_text, description=help_text)
        if only is None or name == only:
            module = importlib.import_module(f"axojax.cli.{name}")
            module.add_arguments(p)
            p.set_defaults(_module=module)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    first = next((a for a in argv if not a.startswith("-")), None)
    parser = build_parser(first if first in SUBCOMMANDS else None)
    try:
        args = parser.parse_args(argv)
        args._argv = argv
        if args.command is None:
            parser.print_help(sys.stderr)
            return 2
        doc = args._module.run(args)
    except CLIError as err:
        print(f"axojax: error: {err}", file=sys.stderr)
        return 2
    if doc is not None:
        if getattr(args, "json", False):
            emit_json(doc)
        else:
            print(args._module.render(doc))
    return getattr(args, "_exit_code", 0)


def console() -> int:
    """The ``axojax`` command: :func:`main` with compiled programs kept across commands
    (:mod:`axojax.cache`)."""
    command_line_cache()
    return main()


if __name__ == "__main__":
    sys.exit(console())
