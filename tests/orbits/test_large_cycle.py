"""The large cycle past a subcritical Hopf point (issue 54 item 3,
axojax/orbits/large_cycle.py): clamped two-filament sliding control at 50 Hz with motor
kinetics omega0 tau_m = 2, whose normal form has no small orbit past its Hopf point
(tests/whole_beat/test_whole_beat_fit.py). The orbit started from a simulation begun at a
large bend is a stable periodic orbit that ``ax.simulate`` (diffrax, the independent
integrator of the same equations, from its own small perturbation) settles on: frequency
within 0.5 %, psi_0 and |psi_1| along the flagellum within 2 % of |psi_1| in L2."""

import numpy as np
import pytest

import axojax as ax
from axojax.orbits import cycle_measures
from axojax.orbits.large_cycle import large_cycle
from axojax.orbits.limit_cycle import limit_cycle
from tests.whole_beat.test_whole_beat_fit import UNITS, W0, _hopf

TAU_M = 2.0 / W0


def _past():
    model = ax.models.two(n_elements=10)
    hopf = _hopf(model, ax.Params(p=0.0, omega0=W0), "chi")
    return model, hopf.replace(chi_re=1.1 * hopf.chi_re, chi_im=1.1 * hopf.chi_im)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_large_cycle_is_the_orbit_a_simulation_settles_on():
    model, params = _past()
    f_sat = float(UNITS.p_from_pn_per_um(300.0))
    small = limit_cycle(model, params, 0.0, tau_m=TAU_M, f_sat=f_sat)
    assert not bool(small.started)  # subcritical: no start from the normal form
    cycle = large_cycle(model, params, 0.0, tau_m=TAU_M, f_sat=f_sat)
    assert bool(cycle.converged) and bool(cycle.stable)
    sim = ax.simulate(
        model, params, 0.6, units=UNITS, cubic=0.0, tau_m=TAU_M, f_sat=f_sat, perturbation_um=0.5
    )
    assert sim.state == "limit_cycle"
    modes = sim.settled_modes()
    m = cycle_measures(cycle, modes.s, UNITS)
    assert abs(float(m.frequency_hz) / sim.limit_cycle["frequency_hz"] - 1) < 0.005
    # psi over a cycle, phase aside: psi_0 and |psi_1| together, relative to |psi_1|
    miss = np.hypot(
        np.linalg.norm(np.asarray(m.psi0) - modes.psi0),
        np.linalg.norm(np.abs(np.asarray(m.psi1)) - np.abs(modes.psi1)),
    )
    assert miss <= 0.02 * np.linalg.norm(modes.psi1)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_large_cycle_grows_in_proportion_to_the_saturation_force():
    """Without a static moment and cubic stiffening the equations are homogeneous in
    (q, f_sat): the cycle at twice f_sat is the cycle at f_sat, twice as large."""
    model, params = _past()
    f_sat = float(UNITS.p_from_pn_per_um(300.0))
    one = cycle_measures(large_cycle(model, params, 0.0, tau_m=TAU_M, f_sat=f_sat), None, UNITS)
    two = cycle_measures(large_cycle(model, params, 0.0, tau_m=TAU_M, f_sat=2 * f_sat), None, UNITS)
    assert np.isclose(
        float(two.dynamic_amplitude_rad), 2 * float(one.dynamic_amplitude_rad), rtol=1e-6
    )
    assert np.isclose(float(two.frequency_hz), float(one.frequency_hz), rtol=1e-8)
