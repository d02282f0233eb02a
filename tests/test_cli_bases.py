"""The base flags of every model-building command (docs/interface.md): --base,
--basal-compliance, --head-um/--head-drag, --viscosity-pa-s. Each valid kind builds the
model the library builds from the same values (same unknowns, same dominant eigenvalue),
and each bad input ends in one line naming the flag."""

import json

import pytest

import axojax as ax
from axojax.cli.main import main
from axojax.models import Base

MODEL = ["--model", "two", "--elements", "4", "--p", "0", "--top", "1", "--json"]


def _run(argv, capsys):
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def _expected(base: Base, **values) -> tuple[int, complex]:
    model = ax.models.two(n_elements=4, base=base)
    mode = ax.dominant_mode(model, ax.Params(p=0.0, **values), ax.eigen.Dense())
    return model.n_unknowns, complex(mode.eigenvalue)


UNITS = ax.Units()
CASES = {
    "pivot": (["--base", "pivot"], Base("pivot"), {}),
    "free": (["--base", "free"], Base("free"), {}),
    "head-um": (
        ["--base", "head", "--head-um", "2.5,1.5"],
        Base.head_from_ellipsoid(2.5, 1.5, 1e-3, UNITS),
        {},
    ),
    "head-drag": (
        ["--base", "head", "--head-drag", "0.05,0.1"],
        Base(
            "head",
            translational_drag=float(UNITS.head_translational_drag(0.05)),
            rotational_drag=float(UNITS.head_rotational_drag(0.1)),
        ),
        {},
    ),
    "clamped-compliance": (
        ["--basal-compliance", "95000,36"],
        Base("clamped", compliance=True),
        {
            "kb": float(UNITS.kb_from_pn_per_um(95000.0)),
            "xib": float(UNITS.xib_from_pn_s_per_um(36.0)),
        },
    ),
}


@pytest.mark.parametrize("case", list(CASES))
def test_each_base_kind_builds_the_library_model(case, capsys):
    flags, base, values = CASES[case]
    code, out, err = _run(["modes", *MODEL, *flags], capsys)
    assert code == 0, err
    doc = json.loads(out)
    n_dof, lam = _expected(base, **values)
    assert doc["n_dof"] == n_dof > 2 * 2 * 4  # more unknowns than the clamped model
    got = complex(*doc["dominant"]["eigenvalue"])
    assert abs(got - lam) <= 1e-8 * max(1.0, abs(lam))


@pytest.mark.parametrize(
    "flags,flag",
    [
        (["--base", "head"], "--base head"),
        (["--head-um", "2,1"], "--head-um"),
        (["--base", "free", "--head-drag", "1,1"], "--head-drag"),
        (["--base", "head", "--head-drag", "1,-2"], "--head-drag"),
        (["--base", "head", "--head-um", "1,2"], "--head-um"),
        (["--base", "head", "--head-um", "2,1", "--viscosity-pa-s", "-1"], "--viscosity-pa-s"),
        (["--viscosity-pa-s", "1e-3"], "--viscosity-pa-s"),
        (["--basal-compliance", "95000,0"], "--basal-compliance"),
        (["--basal-compliance", "-1,3"], "--basal-compliance"),
        (["--basal-compliance", "1"], "--basal-compliance"),
    ],
)
def test_bad_base_input_is_one_line_naming_the_flag(flags, flag, capsys):
    code, out, err = _run(["modes", *MODEL, *flags], capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith(f"axojax: error: {flag}")


def test_unknown_base_is_refused_by_the_parser(capsys):
    code, out, err = _run(["modes", *MODEL, "--base", "wall"], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1 and "--base" in err
