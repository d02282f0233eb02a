"""The base flags of every model-building command (docs/interface.md): --base,
--basal-compliance, --head-um/--head-drag, --viscosity-pa-s. Each valid kind builds the
model the library builds from the same values (same unknowns, same dominant eigenvalue),
and each bad input ends in one line naming the flag."""

import json

import numpy as np
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
        (["--base", "head", "--head-um", "1e300,1"], "--head-um"),
        (["--base", "head", "--head-drag", "1e300,1"], "--head-drag"),
        (["--base", "head", "--head-um", "nan,1"], "--head-um"),
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


def test_orbit_takes_an_unclamped_base(capsys):
    """A free base is taken (its orbit's rigid offset is gauged:
    tests/orbits/test_free_base_orbits.py); below its Hopf point (the deforming modes' p_c =
    84) there is no orbit, and the line says why, naming --p."""
    argv = ["orbit", "--model", "two", "--elements", "4", "--base", "free", "--p", "50", "--json"]
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("axojax: error: --p: no limit cycle at p = 50: the equilibrium is")


@pytest.mark.parametrize(
    "flags", [["--base", "free"], ["--base", "pivot"], ["--basal-compliance", "500,5"]]
)
def test_simulate_runs_on_a_base_that_moves(flags, capsys, tmp_path):
    """simulate integrates every base (tests/dynamics/test_simulate_bases.py checks the numbers)."""
    argv = ["simulate", "--model", "two", "--elements", "4", "--t-end", "0.01", *flags]
    code, out, err = _run([*argv, "--out", str(tmp_path / "x.npz"), "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["state"] in (
        "decaying",
        "limit_cycle",
        "growing",
        "settling",
        "divergent",
    )


def test_library_limit_cycle_takes_a_free_base():
    """No refusal for the base: the answer is the physics' (linearly stable below p_c)."""
    model = ax.models.two(n_elements=4, base="free")
    cycle = ax.limit_cycle(model, ax.Params(p=50.0))
    assert not bool(cycle.converged) and complex(cycle.linear_eigenvalue).real < 0
    assert cycle.rigid_drift.shape == (2,)


def test_critical_force_skips_the_rigid_modes_of_a_free_base():
    """A free base's rigid-body zero eigenvalues are no onset: the critical force is where
    a deforming mode crosses, checked against scipy's full decomposition of the pencil
    (its eigenvalues at 0 removed) on both sides of the reported p_c."""
    import scipy.linalg as sl

    model = ax.models.two(n_elements=4, base="free")
    crit = ax.critical_force(model, ax.Params(), solver=ax.eigen.Dense())
    assert bool(crit.found)
    p_c = float(crit.p)

    def deforming_growth(p):
        s = ax.assemble(model, ax.Params(p=p))
        w = sl.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
        w = w[np.abs(w) > 1e-6 * np.max(np.abs(w))]
        return float(np.max(w.real))

    assert deforming_growth(0.98 * p_c) < 0 < deforming_growth(1.02 * p_c)
