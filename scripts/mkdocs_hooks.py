"""MkDocs hooks of the documentation site (``hooks:`` in mkdocs.yml).

- The notebooks stay in ``notebooks/`` (where users run them); :func:`on_files` adds them
  to the site under ``notebooks/``, where mkdocs-jupyter renders them with their stored
  outputs (``execute: false``: building the site never runs a computation).
- ``<!-- readme-section: TITLE -->`` in a page becomes README.md's ``## TITLE`` section
  (one source for text that both show, e.g. the benchmark timings).
- ``<!-- cli-reference -->`` in a page becomes the reference of every ``axojax``
  subcommand, generated from the argparse parser itself (:func:`cli_reference`), so the
  page cannot drift from the command.
"""

from __future__ import annotations

import argparse
import pathlib
import re

from mkdocs.plugins import event_priority
from mkdocs.structure.files import File, Files

ROOT = pathlib.Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
CLI_MARKER = "<!-- cli-reference -->"
README_MARKER = re.compile(r"<!-- readme-section: (.+?) -->")


@event_priority(100)  # before mkdocs-jupyter wraps the notebook files
def on_files(files: Files, config) -> Files:
    for path in sorted(NOTEBOOKS.glob("*.ipynb")):
        files.append(
            File(
                f"notebooks/{path.name}",
                str(ROOT),
                config["site_dir"],
                config["use_directory_urls"],
            )
        )
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    if CLI_MARKER in markdown:
        markdown = markdown.replace(CLI_MARKER, cli_reference())
    return README_MARKER.sub(lambda m: readme_section(m.group(1)), markdown)


def readme_section(title: str) -> str:
    """README.md's ``## title`` section (heading included, up to the next ``## ``).

    Raises:
        ValueError: when README.md has no such section (the strict build then fails).
    """
    text = (ROOT / "README.md").read_text()
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    if match is None:
        raise ValueError(f"README.md has no section '## {title}'")
    return f"## {title}\n{match.group(1)}"


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _flag(action: argparse.Action) -> str:
    if not action.option_strings:
        return f"`{action.metavar or action.dest}`"
    metavar = "" if action.nargs == 0 else f" {action.metavar or action.dest.upper()}"
    return ", ".join(f"`{s}{metavar}`" for s in action.option_strings)


def _parser_section(name: str, parser: argparse.ArgumentParser) -> str:
    lines = [
        f"## `axojax {name}`",
        "",
        _cell(parser.description or ""),
        "",
        "```text",
        parser.format_usage().strip(),
        "```",
        "",
    ]
    for group in parser._action_groups:  # argparse's own grouping: options, model, units, ...
        actions = [
            a
            for a in group._group_actions
            if not isinstance(a, argparse._HelpAction) and a.help != argparse.SUPPRESS
        ]
        if not actions:
            continue
        lines += [f"**{group.title}**", "", "| flag | meaning |", "|---|---|"]
        lines += [
            f"| {_flag(a)}{' (required)' if a.required else ''} | {_cell(a.help or '')} |"
            for a in actions
        ]
        lines.append("")
    return "\n".join(lines)


def cli_reference() -> str:
    """Markdown reference of every ``axojax`` subcommand, from :func:`axojax.cli.main.build_parser`."""
    from axojax.cli.main import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return "\n".join(_parser_section(name, p) for name, p in sub.choices.items())
