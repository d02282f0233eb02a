"""An active friction (chi'' < 0 or, for a base-to-tip curvature-control beat, beta'' < 0)
makes the time domain ill posed: short waves whose growth rates increase under mesh
refinement (checked here with scipy's full eigen-decomposition of the assembled pencil),
so simulate and limit_cycle refuse it with one line, while a passive friction passes."""

import numpy as np
import pytest
import scipy.linalg as sl

import axojax as ax
from axojax.well_posed import friction_margin, require_passive_friction
from tests.regulation.test_mechanisms import _params  # the continuum's chi_bar, beta_bar as Params

# Sartori et al. 2016's wild-type fit in dimensionless form (chi_bar 24.4, beta_bar -11.4 i
# at Sp 68: beta'' < 0) and an active sliding control; then their passive mirror images.
ACTIVE = {"beta": _params(24.4, -11.4j, 68.0), "chi": _params(-20 - 25j, 0.0, 1000.0)}
PASSIVE = {"beta": _params(24.4, 11.4j, 68.0), "chi": _params(20 + 25j, 0.0, 1000.0)}


def _max_growth(params, n):
    s = ax.assemble(ax.models.two(n_elements=n), params)
    w = sl.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
    return float(np.max(w.real[np.isfinite(w)]))


@pytest.mark.parametrize("kind", ["beta", "chi"])
def test_active_friction_grows_with_the_mesh_and_passive_does_not(kind):
    active = [_max_growth(ACTIVE[kind], n) for n in (8, 16, 32)]
    passive = [_max_growth(PASSIVE[kind], n) for n in (8, 16, 32)]
    assert active[0] > 0 and active[1] > 2 * active[0] and active[2] > 2 * active[1]
    assert max(passive) < 0 and abs(passive[2] - passive[1]) < 0.05 * abs(passive[1])
    model = ax.models.two(n_elements=8)
    assert friction_margin(model, ACTIVE[kind]) < -1e-6
    assert friction_margin(model, PASSIVE[kind]) > -1e-12


@pytest.mark.parametrize("kind", ["beta", "chi"])
def test_simulate_and_limit_cycle_refuse_an_active_friction(kind):
    model = ax.models.two(n_elements=6)
    with pytest.raises(ValueError, match=f"simulate: {kind}_im < 0 is an active friction"):
        ax.simulate(model, ACTIVE[kind], 0.01)
    with pytest.raises(ValueError, match="limit_cycle: .* active friction"):
        ax.limit_cycle(model, ACTIVE[kind])


@pytest.mark.parametrize(
    "params",
    [ax.Params(), PASSIVE["beta"], PASSIVE["chi"], ax.Params(p=0.0, chi_re=1e5)],
    ids=["steady", "beta-passive", "chi-passive", "elastic-only"],
)
def test_passive_and_steady_pass(params):
    require_passive_friction(ax.models.two(n_elements=6), params, "simulate")


def _cli(argv, capsys):
    from axojax.cli.main import main

    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


MECHANISM = ["--model", "two", "--elements", "6", "--p", "0", "--mechanism", "curvature"]


def test_cli_refuses_active_friction_in_the_time_domain(capsys, tmp_path):
    active = MECHANISM + ["--beta", "0,-6500", "--omega0-hz", "68"]
    out = str(tmp_path / "x.npz")
    code, _, err = _cli(["simulate", *active, "--t-end", "0.01", "--out", out, "--json"], capsys)
    assert code == 2 and err.count("\n") == 1 and err.startswith("axojax: error: --beta: simulate")
    code, _, err = _cli(["orbit", *active, "--json"], capsys)
    assert code == 2 and err.count("\n") == 1 and "--beta: orbit" in err


@pytest.mark.parametrize("beta_im,active", [("-6500", True), ("6500", False)])
def test_modes_reports_the_beat_nearest_i_omega0(capsys, beta_im, active):
    """``axojax modes`` with a mechanism adds the mode nearest i omega0 (checked against
    scipy on the same assembled pencil) and says whether the friction is active."""
    import json

    argv = MECHANISM + ["--beta", f"0,{beta_im}", "--omega0-hz", "68", "--top", "2", "--json"]
    code, out, _ = _cli(["modes", *argv], capsys)
    assert code == 0
    doc = json.loads(out)
    beat = doc["beat"]
    assert beat["active_friction"] is active
    units = ax.Units()
    params = ax.Params(
        p=0.0,
        beta_im=float(ax.Units().beta_from_pn(float(beta_im))),
        omega0=float(units.omega0_from_hz(68.0)),
    )
    s = ax.assemble(ax.models.two(n_elements=6), params)
    w = sl.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
    expected = w[np.argmin(np.abs(w - 1j * float(params.omega0)))]
    got = complex(*beat["eigenvalue"])
    assert abs(got - expected) < 1e-8 * abs(expected)
