"""The package's layering (issue 32, "one house"), read from the source by AST: every
``import`` and ``from ... import`` of every module, at module level and inside functions.

Nodes are axojax's first-level subpackages and modules (``eigen``, ``inverse``,
``params``, ...). Rules:

- no import circle between nodes (``cli``, ``paper`` and the top-level ``__init__``
  excepted: they sit on top and may import anything);
- nothing imports ``cli`` or ``paper``, and nothing imports the top-level package
  (``import axojax`` inside the library would run every subpackage's import);
- a fit's residual path goes only downward: ``inverse`` (the fits) -> ``waveform`` /
  ``eigen`` / ``orbits`` / ``models``, never back up: nothing below ``inverse`` imports
  it (or ``plotting``, which draws fits), observed beats (``beats``) import no model
  physics, and ``models`` imports none of what is built on it.

And no module of axojax is over ``MAX_LINES`` lines.
"""

from __future__ import annotations

import ast
import pathlib
import re

import pytest

import axojax

ROOT = pathlib.Path(axojax.__file__).parent
TOP = {"cli", "paper", "__init__", "__main__"}
"""Nodes that may import anything."""
MAX_LINES = 600

ABOVE_THE_MODEL = {"inverse", "plotting", "sweeps", "datasets"}
"""What is built on the model and its solvers; none of the model's own packages may
import these."""
MODEL_STACK = {
    "units",
    "params",
    "results",
    "_io",
    "_runtime",
    "_progress",
    "cache",
    "fem",
    "linalg",
    "models",
    "assembly",
    "waveform",
    "eigen",
    "critical",
    "dynamics",
    "orbits",
    "beats",
}
ALLOWED = {
    # observed beats: readers and reduction only, no model physics
    "beats": {"waveform", "units", "params", "results", "_io", "fem"},
    # the model's structure: below every solver
    "models": {"fem", "linalg", "params", "units", "results", "_io"},
    "fem": {"params", "units", "results", "linalg"},
    "units": set(),
    "params": {"units"},
    "results": set(),
}
"""Per node, everything it may import (nodes not listed: any node, within the rules
above)."""


def _module_name(path: pathlib.Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _exists(name: str) -> bool:
    rel = pathlib.Path(*name.split("."))
    return (ROOT.parent / rel).with_suffix(".py").is_file() or (
        ROOT.parent / rel / "__init__.py"
    ).is_file()


def _imported(path: pathlib.Path) -> set[str]:
    """Every axojax module that ``path`` imports (absolute names; ``from x import y``
    gives ``x.y`` when that is a module, else ``x``)."""
    name = _module_name(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            for a in node.names:
                out.add(f"{mod}.{a.name}" if _exists(f"{mod}.{a.name}") else mod)
    return {m for m in out if m == "axojax" or m.startswith("axojax.")}


def _node(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _graph() -> dict[str, dict[str, list[str]]]:
    """node -> imported node -> the files (relative to the package) that import it."""
    graph: dict[str, dict[str, list[str]]] = {}
    for path in sorted(ROOT.rglob("*.py")):
        a = _node(_module_name(path))
        for m in _imported(path):
            b = _node(m)
            if a != b:
                rel = str(path.relative_to(ROOT.parent))
                graph.setdefault(a, {}).setdefault(b, []).append(rel)
    return graph


GRAPH = _graph()


def test_the_walk_sees_imports_inside_functions():
    """The reader itself: a deferred import in a function counts (cli/plot.py imports the
    figures inside its functions)."""
    assert "plotting" in GRAPH["cli"]
    assert any("cli/plot.py" in f for f in GRAPH["cli"]["plotting"])
    assert "eigen" in GRAPH["inverse"] and "waveform" in GRAPH["beats"]


def test_no_import_circle_between_subpackages():
    inner = {a: {b for b in bs if b not in TOP} for a, bs in GRAPH.items() if a not in TOP}
    circles = []

    def visit(node, stack, seen):
        for nxt in sorted(inner.get(node, ())):
            if nxt in stack:
                loop = stack[stack.index(nxt) :]
                first = loop.index(min(loop))  # one rotation per circle
                loop = loop[first:] + loop[:first]
                circles.append(loop + [loop[0]])
            elif nxt not in seen:
                seen.add(nxt)
                visit(nxt, stack + [nxt], seen)

    for start in sorted(inner):
        visit(start, [start], {start})
    described = {
        " -> ".join(c)
        + " ("
        + "; ".join(f"{a}->{b}: {', '.join(GRAPH[a][b])}" for a, b in zip(c, c[1:]))
        + ")"
        for c in circles
    }
    assert not described, "import circles:\n" + "\n".join(sorted(described))


def test_nothing_imports_the_command_line_the_paper_or_the_top_package():
    bad = [
        f"{a} imports {b}: {', '.join(files)}"
        for a, bs in GRAPH.items()
        if a not in TOP
        for b, files in bs.items()
        if b in TOP
    ]
    assert not bad, "\n".join(bad)


def test_the_residual_path_goes_only_downward():
    bad = [
        f"{a} imports {b}, which is built on it: {', '.join(files)}"
        for a, bs in GRAPH.items()
        if a in MODEL_STACK
        for b, files in bs.items()
        if b in ABOVE_THE_MODEL
    ]
    for a, allowed in ALLOWED.items():
        bad += [
            f"{a} may import only {', '.join(sorted(allowed)) or 'nothing of axojax'}; it "
            f"imports {b}: {', '.join(files)}"
            for b, files in GRAPH.get(a, {}).items()
            if b not in allowed
        ]
    assert not bad, "\n".join(bad)


def test_inverse_reaches_the_model_only_through_its_public_packages():
    """The fits sit on top of the model: they import the beats, waveform, eigen, orbits
    and models packages, and nothing that draws or runs sweeps."""
    assert set(GRAPH["inverse"]) <= MODEL_STACK | {"_memory"}, GRAPH["inverse"]
    assert {"beats", "eigen", "orbits", "models"} <= set(GRAPH["inverse"])


@pytest.mark.parametrize(
    "path", sorted(ROOT.rglob("*.py")), ids=lambda p: str(p.relative_to(ROOT.parent))
)
def test_no_module_is_over_max_lines(path):
    lines = len(path.read_text().splitlines())
    assert lines <= MAX_LINES, f"{path.relative_to(ROOT.parent)}: {lines} lines (split it)"


# --- Inside a subpackage: module by module (issue 53) -------------------------------------

NO_CIRCLE_INSIDE = ("inverse", "cli")
"""Subpackages whose modules import one another without a circle (an ``__init__`` that
re-exports its children is the package's front door, not part of a circle: it is left
out, and no module below it may import it: :func:`test_no_module_imports_its_own_front_door`)."""

INVERSE_LAYERS = {"fitting": 1, "sampling": 2, "comparison": 3, "whole_beat": 4}
"""inverse/'s layers, bottom up (its own top-level modules, the problem core, are layer 0;
its ``__init__`` sits on top): a module imports only its own layer and those below."""


def _module_graph(package: str) -> dict[str, set[str]]:
    """module -> the modules of the same subpackage it imports (``__init__`` files left
    out; a ``from pkg import name`` of a package's ``__init__`` counts as that package)."""
    graph = {}
    for path in sorted((ROOT / package).rglob("*.py")):
        if path.name == "__init__.py":
            continue
        name = _module_name(path)
        graph[name] = {
            m for m in _imported(path) if m.startswith(f"axojax.{package}.") and m != name
        }
    return graph


def _inverse_layer(module: str) -> int:
    parts = module.split(".")[2:]  # below axojax.inverse
    if not parts:
        return max(INVERSE_LAYERS.values()) + 1  # the package's front door
    return INVERSE_LAYERS.get(parts[0], 0)


def _is_package(module: str) -> bool:
    return (ROOT.parent / pathlib.Path(*module.split(".")) / "__init__.py").is_file()


@pytest.mark.parametrize("package", NO_CIRCLE_INSIDE)
def test_no_import_circle_between_the_modules_of(package):
    graph = _module_graph(package)
    circles = set()

    def visit(node, stack):
        for nxt in sorted(graph.get(node, ())):
            if nxt in stack:
                loop = stack[stack.index(nxt) :]
                first = loop.index(min(loop))
                circles.add(" -> ".join(loop[first:] + loop[:first] + [min(loop)]))
            elif nxt in graph:
                visit(nxt, stack + [nxt])

    for start in sorted(graph):
        visit(start, [start])
    assert not circles, "import circles:\n" + "\n".join(sorted(circles))


@pytest.mark.parametrize("package", NO_CIRCLE_INSIDE)
def test_no_module_imports_its_own_front_door(package):
    """A module never imports the ``__init__`` of a package it sits in (that front door
    imports it, a circle the module graph above leaves out): cli/fit/whole_beat.py reads
    the shared --data handling from cli/fit/inputs.py, not from cli/fit."""
    bad = []
    for path in sorted((ROOT / package).rglob("*.py")):
        parts = _module_name(path).split(".")
        above = {".".join(parts[:i]) for i in range(2, len(parts))}
        bad += [f"{'.'.join(parts)} imports {m}" for m in _imported(path) if m in above]
    assert not bad, "\n".join(bad)


def _imported_names(path: pathlib.Path) -> list[tuple[str, str]]:
    """(module, name) of every ``from module import name`` in ``path`` (absolute)."""
    name = _module_name(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    out = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.ImportFrom):
            base = package[: len(package) - (node.level - 1)] if node.level else []
            mod = ".".join(base + ([node.module] if node.module else []))
            out += [(mod, a.name) for a in node.names]
    return out


def test_no_private_name_of_a_fit_module_is_imported_by_another():
    """cli/fit's modules share public names only (cli/fit_whole_beat.py imported
    ``_data``, ``_finish`` and ``_given`` from cli/fit.py): no module of the command line
    imports a ``_name`` of another module of cli/fit."""
    bad = [
        f"{_module_name(path)} imports {mod}.{name}"
        for path in sorted((ROOT / "cli").rglob("*.py"))
        for mod, name in _imported_names(path)
        if mod.startswith("axojax.cli.fit")
        and mod != _module_name(path)
        and (name.startswith("_") or "._" in mod)
    ]
    assert not bad, "\n".join(bad)


def test_inverse_layers_import_only_downward():
    """problem core <- fitting <- sampling <- comparison <- whole beat (inverse/__init__)."""
    bad = []
    for path in sorted((ROOT / "inverse").rglob("*.py")):
        a = _module_name(path)
        for b in _imported(path):
            if b.startswith("axojax.inverse") and _inverse_layer(b) > _inverse_layer(a):
                bad.append(
                    f"{a} (layer {_inverse_layer(a)}) imports {b} (layer {_inverse_layer(b)})"
                )
    assert not bad, "\n".join(bad)


def test_the_inverse_layers_are_the_folders():
    """The rule above names every folder of inverse/ (a new one must be given a layer)."""
    folders = {p.parent.name for p in (ROOT / "inverse").glob("*/__init__.py")}
    assert folders == set(INVERSE_LAYERS)


def _private_in(name: str, is_init: bool, source: str) -> list[str]:
    """Every import, in module ``name``'s ``source``, of a private module or name from
    outside the package that owns it: a private module ``a.b._c`` belongs to ``a.b``, a
    private name of module ``a.b.c`` to ``a.b``; its owner's modules and those of the
    packages inside it may import it."""
    package = (name if is_init else name.rsplit(".", 1)[0]).split(".")
    bad = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            mod = ".".join(package[: len(package) - (node.level - 1)] + [node.module or ""])
        else:
            mod = node.module or ""
        mod = mod.rstrip(".")
        if not (mod == "axojax" or mod.startswith("axojax.")):
            continue
        for alias in node.names:
            full = f"{mod}.{alias.name}"
            target = full if _exists(full) else mod
            parts = target.split(".")
            private = [i for i, p in enumerate(parts) if p.startswith("_")]
            if private:
                owner = parts[: private[0]]
            elif alias.name.startswith("_"):
                owner = parts if _is_package(target) else parts[:-1]
            else:
                continue
            if package[: len(owner)] != owner:
                bad.append(f"{name} imports {full} (private to {'.'.join(owner)})")
    return bad


def test_the_private_import_reader():
    """The reader itself, on made-up lines: a private module or name of another
    subpackage is seen; axojax's own private modules and a sibling's private name are
    not."""
    assert _private_in("axojax.inverse", True, "from .sampling._nuts import NUTS")
    assert _private_in("axojax.dynamics.x", False, "from ..assembly.border import _vectors")
    assert not _private_in("axojax.dynamics.x", False, "from ..assembly import border")
    assert _private_in(
        "axojax.inverse.whole_beat.fit", False, "from ..comparison.compare import _fit"
    )
    assert not _private_in("axojax.inverse.problem", False, "from .. import _io")
    assert not _private_in("axojax.inverse.sampling.modes", False, "from ._laplace import _c")
    assert not _private_in("axojax.cli.common", False, "from ._values import _pair")


def test_no_private_name_is_imported_from_another_subpackage():
    bad = [
        line
        for path in sorted(ROOT.rglob("*.py"))
        for line in _private_in(_module_name(path), path.name == "__init__.py", path.read_text())
    ]
    assert not bad, "\n".join(bad)


# --- docs/internals.md's map of the house is the house -----------------------------------

INTERNALS = ROOT.parent / "docs" / "internals.md"


def _house_section() -> str:
    text = INTERNALS.read_text()
    start = text.index("## The house")
    return text[start : text.index("\n## ", start + 1)]


def _mapped_paths() -> set[str]:
    """Every path in the first column of the map's table (a folder ``axojax/NAME/`` or a module ``axojax/NAME.py``)."""
    rows = [line for line in _house_section().splitlines() if line.startswith("| `axojax/")]
    return {p for row in rows for p in re.findall(r"`(axojax/[\w/.]+)`", row.split("|")[1])}


def test_the_house_map_names_every_folder_and_module():
    mapped = _mapped_paths()
    top = {f"axojax/{p.name}/" for p in ROOT.iterdir() if p.is_dir() and p.name != "__pycache__"}
    top |= {
        f"axojax/{p.name}"
        for p in ROOT.glob("*.py")
        if p.name not in ("__init__.py", "__main__.py")
    }
    assert not top - mapped, f"docs/internals.md's map lacks {sorted(top - mapped)}"
    assert all((ROOT.parent / p).exists() for p in mapped), sorted(
        p for p in mapped if not (ROOT.parent / p).exists()
    )


def test_the_house_map_lists_inverse_layers_in_order():
    section = _house_section()
    listed = [m for m in re.findall(r"^\d+\. `(\w+)/`", section, re.M)]
    assert listed == sorted(INVERSE_LAYERS, key=INVERSE_LAYERS.get), listed
