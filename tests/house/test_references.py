"""Every file the project's text points a user to exists in the repository (issue 33).

Users get the repository, nothing beside it: a docstring, help text, README line or
notebook that says "see MODEL.md section 3" or "tests/test_x.py" must name a file they
have, and a "docs/model.md section N" must name a section that page has. Scanned: the
tracked text files of README.md, docs/, axojax/, tests/, scripts/, benchmarks/ and the
notebooks' cell sources (not their stored outputs).
"""

from __future__ import annotations

import json
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCANNED_DIRS = ("docs/", "axojax/", "tests/", "scripts/", "benchmarks/", "notebooks/")
SCANNED_FILES = ("README.md", "mkdocs.yml", "pyproject.toml")
TEXT_SUFFIXES = {".py", ".md", ".ipynb", ".toml", ".yml", ".yaml", ".cfg", ".txt", ".js"}

OUTSIDE_FILES = re.compile(r"\b(MODEL|INTERFACE|INVERSE)\.md\b")
"""The specification files the developers keep outside the repository."""

TOP = r"(?:docs|tests|axojax|scripts|benchmarks|notebooks)"
EXTENSIONS = r"(?:md|py|ipynb|toml|yml|yaml|json|npz|csv|mat|png|gif|txt|cff|js)"
PATH = re.compile(rf"(?<![\w./-]){TOP}/[\w./-]*?\.{EXTENSIONS}\b(?![\w/-])")
"""A repository path such as ``docs/model.md`` or ``axojax/cli/main.py`` (not inside a URL
or another path)."""

PLACEHOLDER = re.compile(r"NAME|FILE|PATH|X|Y|Z")
"""Upper-case stems that stand for any name in usage lines (``notebooks/NAME.ipynb``)."""

MODEL_SECTION = re.compile(r"docs/model\.md,?\s+sections?\s+(\d+)(?:\s*-\s*(\d+))?")

THIS_FILE = pathlib.Path(__file__).resolve()


def _tracked() -> list[pathlib.Path]:
    out = subprocess.run(
        ["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split("\n")
    return [
        ROOT / name
        for name in out
        if name
        and (name in SCANNED_FILES or name.startswith(SCANNED_DIRS))
        and pathlib.Path(name).suffix in TEXT_SUFFIXES
        and (ROOT / name).is_file()
    ]


def _text(path: pathlib.Path) -> str:
    """The text a reader meets: a notebook's cell sources, any other file whole."""
    if path.suffix == ".ipynb":
        cells = json.loads(path.read_text())["cells"]
        return "\n".join("".join(c.get("source", [])) for c in cells)
    return path.read_text(encoding="utf-8", errors="replace")


def _model_sections() -> set[int]:
    text = (ROOT / "docs" / "model.md").read_text()
    return {int(m) for m in re.findall(r"^## (\d+)\. ", text, re.M)}


FILES = _tracked()


def test_the_scan_sees_the_project():
    names = {p.relative_to(ROOT).as_posix() for p in FILES}
    for expected in (
        "README.md",
        "docs/model.md",
        "axojax/cli/main.py",
        "tests/house/test_docs.py",
    ):
        assert expected in names
    assert any(n.endswith(".ipynb") for n in names)


def test_no_reference_to_files_outside_the_repository():
    bad = []
    for path in FILES:
        if path == THIS_FILE:
            continue
        for n, line in enumerate(_text(path).splitlines(), 1):
            for m in OUTSIDE_FILES.finditer(line):
                bad.append(f"{path.relative_to(ROOT)}:{n}: {m.group(0)}: {line.strip()[:100]}")
    assert not bad, (
        "references to files users do not have (cite docs/model.md, docs/interface.md, "
        "docs/api/inverse.md instead):\n" + "\n".join(bad)
    )


def test_every_named_repository_path_exists():
    bad = []
    for path in FILES:
        if path == THIS_FILE:
            continue
        for n, line in enumerate(_text(path).splitlines(), 1):
            for m in PATH.finditer(line):
                name = m.group(0).rstrip(".")
                if PLACEHOLDER.fullmatch(pathlib.PurePosixPath(name).stem):
                    continue  # a pattern such as notebooks/NAME.ipynb
                if not (ROOT / name).exists():
                    bad.append(f"{path.relative_to(ROOT)}:{n}: {name}")
    assert not bad, "named files that are not in the repository:\n" + "\n".join(bad)


def test_every_cited_model_section_exists():
    sections = _model_sections()
    assert sections == set(range(1, 9))  # sections 1-8, as the code cites them
    bad = []
    for path in FILES:
        for n, line in enumerate(_text(path).splitlines(), 1):
            for m in MODEL_SECTION.finditer(line):
                lo = int(m.group(1))
                hi = int(m.group(2) or lo)
                missing = [k for k in range(lo, hi + 1) if k not in sections]
                if missing:
                    bad.append(f"{path.relative_to(ROOT)}:{n}: {m.group(0)}")
    assert not bad, "docs/model.md has no such section:\n" + "\n".join(bad)


@pytest.mark.parametrize(
    "text,found",
    [
        ("see MODEL.md section 3", ["MODEL.md"]),
        ("keys in INTERFACE.md, plus", ["INTERFACE.md"]),
        ("docs/model.md section 3", []),
    ],
)
def test_outside_pattern(text, found):
    assert [m.group(0) for m in OUTSIDE_FILES.finditer(text)] == found


@pytest.mark.parametrize(
    "text,found",
    [
        (
            "(`tests/orbits/test_orbits.py`, `benchmarks/bench_orbit.py`)",
            ["tests/orbits/test_orbits.py", "benchmarks/bench_orbit.py"],
        ),
        ("see docs/model.md.", ["docs/model.md"]),
        ("https://example.org/scripts/x.py and a/docs/y.md", []),
        ("notebooks/gallery_fig*.ipynb", []),
        ("run notebooks/NAME.ipynb", ["notebooks/NAME.ipynb"]),
    ],
)
def test_path_pattern(text, found):
    assert [m.group(0).rstrip(".") for m in PATH.finditer(text)] == found
