"""Help texts name the units the output prints (issue 57, item 5: ``compare --params``'s
help said "k_b pN/um" while the table printed "1/k_b ... um/pN"; ``--cn`` said "pN s
um^-2" where every report prints "pN s/um^2").

The printed side is rendered from stored documents (tests/plotting/fixtures: a real
``axojax compare`` document and a real ``axojax fit`` report) by the functions the
commands print with, without running a fit; the reference units are written here from
the physics (docs/model.md sections 1 and 8), not taken from the code under test."""

import argparse
import json
import pathlib
import re

import pytest

from axojax.cli.fit.text import render as render_fit
from axojax.cli.main import build_parser
from axojax.inverse.comparison.table import render_params, render_table

FIXTURES = pathlib.Path(__file__).resolve().parents[1] / "plotting" / "fixtures"

UNIT = r"pN s/um\^2|pN s/um|pN/um\^2|pN/um|um/pN|pN um\^2|pN|ms|Hz|um"
"""Every unit these outputs print, the longest spelling first (so "pN" never matches the
start of "pN/um")."""
UNIT_AT = re.compile(rf"(?<![\w/^])({UNIT})(?![\w/^])")

PARAMS = {  # compare --params: each printed label's unit
    "chi'": "pN/um^2",
    "chi''": "pN/um^2",
    "beta'": "pN",
    "beta''": "pN",
    "p": "pN/um",
    "k_b": "pN/um",
    "1/k_b": "um/pN",  # the basal compliance, fitted instead of the spring
    "xi_b": "pN s/um",
    "k_l": "pN/um^2",
    "k_s": "pN/um^2",
    "c_l": "pN s/um^2",
    "gamma": "",  # a number
    "m0": "pN",
    "f_sat": "pN/um",
    "tau_m": "ms",
}


def _help(command: str, flag: str) -> str:
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    action = next(a for a in sub.choices[command]._actions if flag in a.option_strings)
    return action.help


def _unit_after(text: str, start: int) -> str | None:
    """The first unit in ``text`` from ``start`` on."""
    match = UNIT_AT.search(text, start)
    return None if match is None else match.group(1)


def _label_at(text: str, label: str) -> int:
    """Where ``label`` stands on its own in ``text`` ("k_b" is not the end of "1/k_b",
    "chi'" not the start of "chi''"); -1 if nowhere."""
    match = re.search(rf"(?<![\w'/]){re.escape(label)}(?![\w'])", text)
    return -1 if match is None else match.start()


def _printed_params(text: str) -> list[tuple[str, str]]:
    """(label, unit) of every value a ``--params`` table prints: "chi' 237 +- 5.9 pN/um^2",
    "chi' -34.4 pN/um^2 (pinned)", "gamma -1.22 +- 0.066"."""
    out = []
    for line in text.splitlines():
        if not re.match(r"\s+\d+", line):
            continue
        for part in line.split(": ", 1)[1].split("; "):
            words = part.replace("(pinned)", "").split()
            unit = words[4:] if len(words) > 2 and words[2] == "+-" else words[2:]
            out.append((words[0], " ".join(unit)))
    return out


@pytest.fixture(scope="module")
def compare_doc() -> dict:
    """The stored comparison, and one more row holding the values its rows do not (the
    basal spring, compliance and friction, k_s, a whole beat's m0, f_sat, tau_m)."""
    doc = json.loads((FIXTURES / "compare.json").read_text())
    extra = {
        "mechanism": "sliding",
        "base": "clamped+compliance",
        "status": "successful",
        "physical": {
            "kb_pn_per_um": 3.0e3,
            "cb_um_per_pn": 3.3e-4,
            "xib_pn_s_per_um": 12.0,
            "ks_pn_per_um2": 2.0e3,
            "m0_pn": 40.0,
            "f_sat_pn_per_um": 900.0,
            "tau_m_ms": 5.0,
        },
        "physical_stderr": {"kb_pn_per_um": 10.0, "cb_um_per_pn": 1e-5},
        "pinned": ["xib_pn_s_per_um"],
    }
    return {**doc, "rows": [*doc["rows"], extra]}


def test_params_help_names_the_unit_the_table_prints(compare_doc):
    printed = _printed_params(render_params(compare_doc))
    assert {label for label, _ in printed} == set(PARAMS)  # every kind of value is seen
    help_text = _help("compare", "--params")
    for label, unit in printed:
        assert unit == PARAMS[label], (label, unit)  # the table prints the physics' unit
        at = _label_at(help_text, label)
        assert at >= 0, f"--params' help does not name {label!r}, which the table prints"
        if unit:
            said = _unit_after(help_text, at)
            assert said == unit, f"--params' help gives {label} in {said}, the table {unit}"
    assert "pinned" in help_text  # and says what "(pinned)" means


UNITS_FLAGS = [  # (command, flag, the printed label, its unit)
    ("compare", "--ei", "EI", "pN um^2"),
    ("compare", "--cn", "c_n", "pN s/um^2"),
    ("compare", "--kappa", "kappa", "pN um^2"),
    ("compare", "--xi-n", "xi_n", "pN s/um^2"),
    ("fit", "--ei", "EI", "pN um^2"),
    ("fit", "--cn", "c_n", "pN s/um^2"),
    ("fit", "--length-um", "L", "um"),
    ("fit", "--target-frequency", "achieved:", "Hz"),
    ("fit", "--target-wavelength", "wavelength", "um"),
]


@pytest.mark.parametrize(("command", "flag", "label", "unit"), UNITS_FLAGS)
def test_a_flags_help_names_the_unit_its_value_is_printed_in(command, flag, label, unit):
    """compare's table (its units lines) and fit's report print these values with their
    units; the flag's help gives the same unit."""
    if command == "compare":
        text = render_table(json.loads((FIXTURES / "compare.json").read_text()))
    else:
        text = render_fit(json.loads((FIXTURES / "fit.json").read_text()))
    match = re.search(rf"(?<![\w/]){re.escape(label)} -?[\d.]+(?:e[+-]?\d+)? ({UNIT})", text)
    assert match is not None, f"{command} prints no {label} with a unit"
    assert match.group(1) == unit
    said = _unit_after(_help(command, flag), 0)
    assert said == unit, f"{command} {flag}'s help gives {said}, the output prints {unit}"
