"""Reading a user's cross-section from TOML or JSON.

Format (TOML shown; JSON has the same keys)::

    name = "my-axoneme"
    dimensions = 2            # 1 (planar) or 2
    load = "pairs"            # or "distributed", "tip"

    [[filaments]]
    position = [0.0, 0.0]     # (y, z)
    ei = 1.0                  # optional, relative flexural rigidity
    drag = 1.0                # optional, relative drag

    [[links]]
    between = [0, 1]
    kind = "spoke"            # or "link"

    [[active_pairs]]
    between = [1, 2]          # first pulled baseward, second tipward
    group = 0                 # optional, 0 or 1
"""

from __future__ import annotations

import json
import pathlib
import tomllib
from typing import Any

from .section import ActivePair, CrossSection, Link, _is_int

MAX_COORDINATE = 1e6
"""Largest magnitude of a filament coordinate in a model file (a bound against overflow
in the geometry, far beyond any cross-section)."""


def _pair(entry: Any, where: str) -> tuple[int, int]:
    if not isinstance(entry, dict) or "between" not in entry:
        raise ValueError(f"{where} needs a 'between = [i, j]' entry")
    between = entry["between"]
    if (
        not isinstance(between, list)
        or len(between) != 2
        or not all(isinstance(v, int) and not isinstance(v, bool) for v in between)
    ):
        raise ValueError(
            f"{where}: 'between' must be two integer filament indices, got {between!r}"
        )
    return between[0], between[1]


def section_from_dict(data: dict, default_name: str = "custom") -> CrossSection:
    """Build a :class:`CrossSection` from the dictionary form of a model file."""
    if not isinstance(data, dict):
        raise ValueError("a model file must hold a table/object at top level")
    fils = data.get("filaments")
    if not isinstance(fils, list) or not fils:
        raise ValueError("model file needs a non-empty 'filaments' list")
    positions, ei, drag = [], [], []
    for k, f in enumerate(fils):
        if not isinstance(f, dict) or "position" not in f:
            raise ValueError(f"filament {k} needs a 'position = [y, z]' entry")
        pos = f["position"]
        if (
            not isinstance(pos, list)
            or len(pos) not in (1, 2)
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in pos)
        ):
            raise ValueError(f"filament {k}: position must be [y, z] numbers, got {pos!r}")
        if not all(abs(v) <= MAX_COORDINATE for v in pos):
            raise ValueError(
                f"filament {k}: position must be finite numbers of magnitude <= {MAX_COORDINATE:g}, got {pos!r}"
            )
        positions.append([float(pos[0]), float(pos[1]) if len(pos) == 2 else 0.0])
        for key, store in (("ei", ei), ("drag", drag)):
            v = f.get(key, 1.0)
            if not isinstance(v, (int, float)) or isinstance(v, bool):
                raise ValueError(f"filament {k}: {key} must be a number, got {v!r}")
            store.append(float(v))
    for key, kind in (("links", list), ("active_pairs", list), ("name", str), ("load", str)):
        if key in data and not isinstance(data[key], kind):
            raise ValueError(
                f"model file: {key!r} must be a {'list of tables' if kind is list else 'string'}, got {data[key]!r}"
            )
    dims = data.get("dimensions", 2)
    if not _is_int(dims) or dims not in (1, 2):
        raise ValueError(f"model file: 'dimensions' must be the integer 1 or 2, got {dims!r}")
    links = []
    for k, l in enumerate(data.get("links", [])):
        i, j = _pair(l, f"link {k}")
        links.append(Link(i, j, l.get("kind", "link")))
    pairs = []
    for k, a in enumerate(data.get("active_pairs", [])):
        i, j = _pair(a, f"active pair {k}")
        group = a.get("group", 0)
        if not _is_int(group) or group not in (0, 1):
            raise ValueError(f"active pair {k}: group must be 0 or 1, got group {group!r}")
        pairs.append(ActivePair(i, j, group))
    known = {"name", "dimensions", "load", "filaments", "links", "active_pairs"}
    extra = set(data) - known
    if extra:
        raise ValueError(f"model file has unknown key(s) {sorted(extra)}; expected {sorted(known)}")
    return CrossSection(
        name=str(data.get("name", default_name)),
        positions=positions,
        links=tuple(links),
        active_pairs=tuple(pairs),
        n_dirs=dims,
        ei=ei,
        drag=drag,
        load=data.get("load", "pairs"),
    )


def load_section(path: str | pathlib.Path) -> CrossSection:
    """Read a cross-section from a ``.toml`` or ``.json`` file."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise ValueError(f"model file {str(path)!r} does not exist")
    text = path.read_text()
    try:
        if path.suffix.lower() == ".json":
            data = json.loads(text)
        elif path.suffix.lower() == ".toml":
            data = tomllib.loads(text)
        else:
            raise ValueError(f"model file {str(path)!r} must end in .toml or .json")
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as err:
        raise ValueError(f"model file {str(path)!r} is malformed: {err}") from None
    except RecursionError:
        raise ValueError(f"model file {str(path)!r} is malformed: nested too deeply") from None
    return section_from_dict(data, default_name=path.stem)
