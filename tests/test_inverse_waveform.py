"""The whole observed beat as a fit target (issue 20): a ShapeTarget with
``source="limit_cycle"`` matches psi_0 and psi_1 in absolute amplitude with the limit
cycle inside ax.inverse.Problem, so ``ax.fit`` (and ``axojax fit --target limit-cycle
--data FILE``) recovers the parameters of a known orbit. The truth is an orbit computed
here by ax.limit_cycle and measured by axojax.orbits.measures (the same measures
``axojax data`` applies to a beat file); its gradient path is checked against finite
differences in tests/test_cycle_targets.py."""

import warnings

import numpy as np
import pytest

import axojax as ax
from axojax.fitting.targets import ShapeTarget, Target
from axojax.orbits.measures import cycle_measures

SOLVER = ax.orbits.HarmonicBalance(harmonics=4, floquet=0, rtol=1e-11)
S_UM = np.linspace(0.0, 12.0, 21)
CUBIC = 6.0


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
    psi1 = np.asarray(m.psi1) * np.exp(-0.4j) + sigma * (rng.standard_normal(S_UM.size) + 1j * rng.standard_normal(S_UM.size))
    psi0 = np.asarray(m.psi0) + sigma * rng.standard_normal(S_UM.size)
    shape = ShapeTarget(S_UM, psi1, sigma, psi0=psi0, source="limit_cycle")
    freq = Target("frequency_hz", float(m.frequency_hz), 0.01, source="limit_cycle")
    return model, base, truth, shape, freq


def test_waveform_fit_recovers_the_orbit(observed):
    model, base, truth, shape, freq = observed
    start = base.replace(p=truth["p"] * 1.01, a0=truth["a0"] * 1.15)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = ax.fit(model, start, [freq], ["p", "a0"], shape=shape, cubic=CUBIC, orbit_solver=SOLVER, shape_floor=0.0, starts=1)
    assert result.converged, result.message
    for name, want in truth.items():
        assert abs(result.params[name] - want) <= 2 * result.stderr[name] + 1e-9 * want, (name, result.params[name], want, result.stderr[name])
        assert result.stderr[name] < 0.05 * want  # the waveform determines both
    shape_report = result.conditions[0]["shape"]
    assert shape_report["source"] == "limit_cycle" and shape_report["psi0_fit_rad"] is not None
    # The fitted psi_0 is the orbit's in absolute amplitude: it matches the observed to the noise.
    assert np.max(np.abs(np.asarray(shape_report["psi0_fit_rad"]) - shape.psi0)) < 5 * 0.002
