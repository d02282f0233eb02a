"""The limit cycle's stiffening ``cubic`` (kappa, 1/L^2) as a fitted parameter (issue 20:
"the imbalance, the cubic stiffening and the arm spacing a0 among the free parameters"):
a waveform fit of a known orbit (computed here by ax.limit_cycle) recovers p, a0 and
cubic together; the Jacobian column of cubic agrees with central finite differences; a
fit that has no limit-cycle target refuses it in one line."""

import warnings

import numpy as np
import pytest

import axojax as ax
from axojax.beats.targets import ShapeTarget, Target
from axojax.cli.main import main
from axojax.inverse import Condition, Problem
from axojax.orbits.measures import cycle_measures

SOLVER = ax.orbits.HarmonicBalance(harmonics=4, floquet=0, rtol=1e-11)
S_UM = np.linspace(0.0, 12.0, 21)
TRUTH_CUBIC = 4.0
SIGMA = 0.002


@pytest.fixture(scope="module")
def observed():
    """Two filaments, 4 elements, p = 1.06 p_c, a0 = 0.3 um, cubic 4: psi_0, psi_1
    (absolute amplitude, seeded noise) and the frequency of the orbit."""
    model = ax.models.two(n_elements=4)
    base = ax.Params(p=160.0)
    p_c = float(ax.critical_force(model, base).p)
    truth = {"p": 1.06 * p_c, "a0": 0.3 / 12}
    m = cycle_measures(
        ax.limit_cycle(model, base.replace(**truth), TRUTH_CUBIC, solver=SOLVER), S_UM
    )
    rng = np.random.default_rng(5)
    psi1 = np.asarray(m.psi1) * np.exp(0.7j) + SIGMA * (
        rng.standard_normal(S_UM.size) + 1j * rng.standard_normal(S_UM.size)
    )
    psi0 = np.asarray(m.psi0) + SIGMA * rng.standard_normal(S_UM.size)
    shape = ShapeTarget(S_UM, psi1, SIGMA, psi0=psi0, source="limit_cycle")
    freq = Target("frequency_hz", float(m.frequency_hz), 0.01, source="limit_cycle")
    return model, base, {**truth, "cubic": TRUTH_CUBIC}, shape, freq


@pytest.mark.slow
def test_fit_recovers_the_stiffening(observed):
    model, base, truth, shape, freq = observed
    start = base.replace(p=truth["p"] * 1.01, a0=truth["a0"] * 1.1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = ax.fit(
            model,
            start,
            [freq],
            ["p", "a0", "cubic"],
            shape=shape,
            cubic=1.5 * TRUTH_CUBIC,
            orbit_solver=SOLVER,
            shape_floor=0.0,
            starts=1,
        )
    assert result.targets_met, result.message
    for name, want in truth.items():
        assert abs(result.params[name] - want) <= 2.5 * result.stderr[name] + 1e-9 * want, (
            name,
            result.params[name],
            want,
            result.stderr[name],
        )
        assert result.identifiable[name]
    assert result.conditions[0]["params"]["cubic"] == pytest.approx(result.params["cubic"])


def test_cubic_jacobian_matches_finite_differences(observed):
    model, base, truth, shape, freq = observed
    problem = Problem(
        model,
        [Condition(targets=[freq], shape=shape)],
        ["p", "cubic"],
        params=base.replace(p=truth["p"], a0=truth["a0"]),
        cubic=TRUTH_CUBIC,
        orbit_solver=SOLVER,
        shape_floor=0.0,
    )
    u = np.asarray(problem.u0)
    jac = problem.jacobian(u)
    h = 1e-5
    e = np.array([0.0, h])
    fd = (problem.residuals_at(u + e) - problem.residuals_at(u - e)) / (2 * h)
    assert np.max(np.abs(jac[:, 1] - fd)) < 1e-5 * max(1.0, np.max(np.abs(fd)))
    assert np.max(np.abs(fd)) > 1.0  # the waveform does depend on the stiffening


def test_cubic_needs_a_limit_cycle_target(observed, capsys):
    model, base, truth, shape, freq = observed
    with pytest.raises(ValueError, match="cubic"):
        Problem(
            model,
            [Condition(targets=[Target("frequency_hz", 50.0, 1.0)])],
            ["p", "cubic"],
            params=base,
        )
    assert (
        main(
            [
                "fit",
                "--no-mesh-check",
                "--model",
                "two",
                "--elements",
                "4",
                "--free",
                "p,cubic",
                "--target-frequency",
                "50",
                "--json",
            ]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert "--free" in err and "cubic" in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_no_orbit_at_the_start_is_said(observed):
    """Started where the straight state does not beat (p = 0.5 p_c), the fit cannot move
    (no orbit, no gradient): the report says so and what to do, not only "no information"."""
    model, base, truth, shape, freq = observed
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = ax.fit(
            model,
            base.replace(p=0.5 * truth["p"] / 1.06, a0=truth["a0"]),
            [freq],
            ["p"],
            shape=shape,
            cubic=TRUTH_CUBIC,
            orbit_solver=SOLVER,
            starts=1,
            max_steps=3,
        )
    assert not result.targets_met
    assert "no limit cycle found" in result.message and "axojax critical" in result.message
