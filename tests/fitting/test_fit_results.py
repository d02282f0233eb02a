"""The result convention of fits (issue 32, :mod:`axojax.results`): a FitResult carries
the least-squares solver's own result (optimistix's, for Levenberg-Marquardt) beside
``targets_met`` (the targets reproduced within 2 sigma; ``converged``, its old name,
warns), both in the JSON report, and ``save`` writes atomically."""

import json

import jax.numpy as jnp
import optimistix as optx
import pytest

import axojax as ax
from axojax import _io
from axojax.beats import Target
from axojax.inverse import Condition, LevenbergMarquardt, Problem, least_squares
from axojax.results import RESULTS, message


@pytest.fixture(scope="module")
def problem():
    """p of the two-filament model from one frequency (it beats between p ~ 150 and 200)."""
    target = Target("frequency_hz", 40.0, 2.0)
    return Problem(
        ax.models.two(n_elements=4), [Condition({}, [target])], ["p"], params=ax.Params(p=170.0)
    )


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_levenberg_marquardt_keeps_optimistix_result(problem):
    done = least_squares(problem, LevenbergMarquardt(), starts=1)
    assert done.result == RESULTS.successful and done.result_message == "successful"
    assert done.targets_met
    cut = least_squares(problem, LevenbergMarquardt(max_steps=1), starts=1)
    # optimistix's own verdict on the same residuals, solver and start
    z0 = problem.to_z(jnp.asarray(problem.u0))
    sol = optx.least_squares(
        lambda z, _: problem.residuals(problem.to_u(z)),
        optx.LevenbergMarquardt(rtol=1e-5, atol=1e-6),
        z0,
        max_steps=1,
        throw=False,
    )
    assert sol.result != optx.RESULTS.successful
    assert cut.result == RESULTS.promote(sol.result)
    assert cut.result_message == message(cut.result) != "successful"
    doc = cut.to_json()
    assert doc["result"] == "nonlinear_max_steps_reached"
    assert doc["result_message"] == cut.result_message


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_other_solvers_say_when_they_ran_out_of_steps(problem):
    adam = least_squares(problem, ax.inverse.Adam(max_steps=2), starts=1)
    assert adam.result == RESULTS.max_steps_reached  # Adam has no termination test
    lbfgs = least_squares(problem, ax.inverse.LBFGS(max_steps=1), starts=1)
    assert lbfgs.result == RESULTS.max_steps_reached


def test_targets_met_replaces_converged(problem):
    done = least_squares(problem, LevenbergMarquardt(), starts=1)
    with pytest.warns(DeprecationWarning, match="targets_met"):
        old = done.converged
    assert old is done.targets_met is True
    doc = done.to_json()
    assert doc["converged"] is doc["targets_met"] is True  # the JSON key stays
    far = Problem(
        ax.models.two(n_elements=4), [Condition({}, [Target("frequency_hz", 5000.0, 1.0)])], ["p"]
    )
    miss = least_squares(far, LevenbergMarquardt(), starts=1)
    assert not miss.targets_met and miss.to_json()["converged"] is False


def test_save_is_atomic(problem, tmp_path, monkeypatch):
    done = least_squares(problem, LevenbergMarquardt(), starts=1)
    path = tmp_path / "fit.json"
    done.save(path)
    assert json.loads(path.read_text())["targets_met"] is True
    used = []
    real = _io.atomic_path

    def spy(p):
        used.append(p)
        return real(p)

    monkeypatch.setattr(_io, "atomic_path", spy)
    done.save(path)
    assert used == [path]
    assert sorted(x.name for x in tmp_path.iterdir()) == ["fit.json"]  # no temporary left
