"""The whole observed beat as a fit target (issue 20): a ShapeTarget with
``source="limit_cycle"`` matches psi_0 and psi_1 in absolute amplitude with the limit
cycle inside ax.inverse.Problem, so ``ax.fit`` (and ``axojax fit --target limit-cycle
--data FILE``) recovers the parameters of a known orbit. The truth is an orbit computed
here by ax.limit_cycle and measured by axojax.orbits.measures (the same measures
``axojax data`` applies to a beat file); its gradient path is checked against finite
differences in tests/inverse/test_cycle_targets.py.

Warm starts (issue 20): the default Levenberg-Marquardt starts each evaluation's orbit
from the last accepted iterate's; the cold path (``LevenbergMarquardt(warm_start=False)``,
every orbit from the Hopf normal form) must reach the same optimum, and the warm one with
fewer Newton steps per evaluation. The steps are counted by ``ax.orbits.Recording``, which
reports every orbit its inner solver solves (a count, not a time)."""

import warnings

import numpy as np
import pytest

import axojax as ax
from axojax.beats.targets import ShapeTarget, Target
from axojax.inverse import LevenbergMarquardt
from axojax.orbits.measures import cycle_measures

NEWTON_STEPS: list[int] = []  # Newton iterations of every orbit solved by SOLVER, in order
SOLVER = ax.orbits.Recording(
    ax.orbits.HarmonicBalance(harmonics=4, floquet=0, rtol=1e-11),
    lambda k: NEWTON_STEPS.append(int(k)),
)
S_UM = np.linspace(0.0, 12.0, 21)
CUBIC = 6.0


pytestmark = pytest.mark.slow  # module fixtures fit two limit cycles (about 40 s)


@pytest.fixture(scope="module")
def observed():
    """Two filaments, 4 elements (one active pair: its moment is a static load ~ a0),
    p = 1.06 p_c, a0 = 0.3 um; psi_0, psi_1 with seeded noise, and the frequency."""
    model = ax.models.two(n_elements=4)
    base = ax.Params(p=160.0)
    p_c = float(ax.critical_force(model, base).p)
    truth = {"p": 1.06 * p_c, "a0": 0.3 / 12}
    m = cycle_measures(ax.limit_cycle(model, base.replace(**truth), CUBIC, solver=SOLVER), S_UM)
    sigma = 0.002
    rng = np.random.default_rng(3)
    psi1 = np.asarray(m.psi1) * np.exp(-0.4j) + sigma * (
        rng.standard_normal(S_UM.size) + 1j * rng.standard_normal(S_UM.size)
    )
    psi0 = np.asarray(m.psi0) + sigma * rng.standard_normal(S_UM.size)
    shape = ShapeTarget(S_UM, psi1, sigma, psi0=psi0, source="limit_cycle")
    freq = Target("frequency_hz", float(m.frequency_hz), 0.01, source="limit_cycle")
    return model, base, truth, shape, freq


@pytest.fixture(scope="module")
def fits(observed):
    """The same fit warm-started (the default) and cold; each with the Newton steps of
    the orbits it solved (second run of the compiled fit: compilation traces once more)."""
    model, base, truth, shape, freq = observed
    start = base.replace(p=truth["p"] * 1.01, a0=truth["a0"] * 1.15)
    out = {}
    for label, method in (
        ("warm", LevenbergMarquardt()),
        ("cold", LevenbergMarquardt(warm_start=False)),
    ):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            NEWTON_STEPS.clear()
            result = ax.fit(
                model,
                start,
                [freq],
                ["p", "a0"],
                shape=shape,
                cubic=CUBIC,
                orbit_solver=SOLVER,
                shape_floor=0.0,
                starts=1,
                method=method,
            )
        out[label] = (result, list(NEWTON_STEPS))
    return out


def test_waveform_fit_recovers_the_orbit(observed, fits):
    model, base, truth, shape, freq = observed
    result, _ = fits["warm"]
    assert result.targets_met, result.message
    for name, want in truth.items():
        assert abs(result.params[name] - want) <= 2 * result.stderr[name] + 1e-9 * want, (
            name,
            result.params[name],
            want,
            result.stderr[name],
        )
        assert result.stderr[name] < 0.05 * want  # the waveform determines both
    shape_report = result.conditions[0]["shape"]
    assert shape_report["source"] == "limit_cycle" and shape_report["psi0_fit_rad"] is not None
    # The fitted psi_0 is the orbit's in absolute amplitude: it matches the observed to the noise.
    assert np.max(np.abs(np.asarray(shape_report["psi0_fit_rad"]) - shape.psi0)) < 5 * 0.002


def test_warm_started_fit_matches_the_cold_one_in_fewer_newton_steps(fits):
    (warm, warm_steps), (cold, cold_steps) = fits["warm"], fits["cold"]
    assert warm.targets_met and cold.targets_met
    assert warm.iterations == cold.iterations  # the same Levenberg-Marquardt path
    for name in ("p", "a0"):
        assert abs(warm.params[name] / cold.params[name] - 1) < 1e-7, (
            name,
            warm.params[name],
            cold.params[name],
        )
    assert abs(warm.loss - cold.loss) < 1e-6 * cold.loss
    # The orbits are counted in order: one for the unknowns' column scales at the start
    # (LevenbergMarquardt(scaled=True) on limit-cycle targets: a Jacobian at z0, cold in
    # both), one per Levenberg-Marquardt step and one for the final gradient (the fit),
    # then the report's (cold in both). The warm fit's evaluations cost fewer Newton
    # steps each; the report's the same.
    n = warm.iterations[0] + 2
    assert len(warm_steps) == len(cold_steps) > n and all(k > 0 for k in warm_steps + cold_steps)
    assert warm_steps[n:] == cold_steps[n:]
    assert np.mean(warm_steps[:n]) < 0.85 * np.mean(cold_steps[:n]), (warm_steps, cold_steps)
    assert warm_steps[n - 1] <= 2  # the final gradient starts from the optimum's own orbit
