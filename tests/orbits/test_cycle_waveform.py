"""Waveform measures of limit cycles (axojax/orbits/measures.py): exact derivatives
through the orbit (implicit function theorem) against central finite differences, the
measures of an orbit against those of an independent time-domain simulation, the warm
start (the array measures themselves: tests/waveform/test_waveform_measures.py)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.orbits.measures import cycle_measures
from axojax.waveform import fourier_modes

SOLVER = ax.orbits.HarmonicBalance(harmonics=5, floquet=0, rtol=1e-12)
KAPPA = 10.0


@pytest.fixture(scope="module")
def setup():
    model = ax.models.seven(n_elements=4)
    base = ax.Params(imbalance=5.0)
    p_c = float(ax.critical_force(model, base).p)
    params = base.replace(p=1.06 * p_c)
    cyc = ax.limit_cycle(model, params, KAPPA, solver=SOLVER)
    return model, params, cyc


@pytest.mark.slow
def test_gradients_match_finite_differences(setup):
    model, params, start = setup
    point = np.array([3.0, 9.0])  # arc lengths (um) for psi_0 and |psi_1|

    def values(theta):
        p, a0, cl, kappa = theta
        cyc = SOLVER.solve(model, params.replace(p=p, a0=a0, cl=cl), kappa, start)
        m = cycle_measures(cyc)
        pt = cycle_measures(cyc, point)
        return jnp.stack(
            [
                m.frequency_hz,
                m.tip_amplitude_um,
                m.wavelength_um,
                m.static_curvature_rad_per_um,
                m.dynamic_amplitude_rad,
                m.out_of_plane,
                pt.psi0[0],
                pt.psi0[1],
                jnp.abs(pt.psi1[0]),
                jnp.abs(pt.psi1[1]),
            ]
        )

    theta = jnp.array([float(params.p), float(params.a0), float(params.cl), KAPPA])
    f = jax.jit(values)
    J = np.asarray(jax.jit(jax.jacfwd(values))(theta))
    rel = np.array([1e-5, 1e-4, 1e-4, 1e-5])

    def central(step):
        return np.stack(
            [
                (
                    np.asarray(f(theta.at[i].mul(1 + step[i])))
                    - np.asarray(f(theta.at[i].mul(1 - step[i])))
                )
                / (2 * step[i] * float(theta[i]))
                for i in range(4)
            ],
            axis=1,
        )

    fd, fd2 = central(rel), central(2 * rel)
    scale = np.abs(fd).max(axis=1, keepdims=True)
    assert np.all(scale > 0)
    # The differences' own error (truncation, and the orbit solved to 1e-12 differing
    # with the Newton steps taken: ~1e-5 of the small out-of-plane ratio's derivative)
    # is estimated by the same difference at twice the step.
    fd_error = np.abs(fd - fd2) / scale
    assert np.max(fd_error) < 1e-3  # the differences themselves are meaningful
    assert np.all(np.abs(J - fd) / scale <= 2e-5 + 2 * fd_error), np.max(
        np.abs(J - fd) / scale - 2 * fd_error
    )
    # reverse mode (the transposed implicit solve) gives the same
    g = np.asarray(jax.jit(jax.grad(lambda th: values(th)[4]))(theta))
    np.testing.assert_allclose(g, J[4], rtol=1e-8, atol=1e-12 * np.abs(J[4]).max())


@pytest.mark.slow
def test_measures_agree_with_a_simulation(setup):
    """The orbit's psi_0, psi_1 and measures against the Fourier modes of an independent
    time-domain run (diffrax, ax.simulate) from a small perturbation, over its last whole
    periods, with the same array measures."""
    model, params, cyc = setup
    sim = ax.simulate(model, params, 1.5, cubic=KAPPA)
    assert sim.state == "limit_cycle"
    period = sim.limit_cycle["period_s"]
    keep = sim.t_s >= sim.t_s[-1] - 8 * period
    modes = fourier_modes(sim.t_s[keep], sim.x_um, sim.psi_rad[keep], period)
    m = cycle_measures(cyc, sim.x_um)
    assert float(m.frequency_hz) == pytest.approx(sim.limit_cycle["frequency_hz"], rel=1e-3)
    assert float(m.tip_amplitude_um) == pytest.approx(sim.limit_cycle["tip_amplitude_um"], rel=1e-2)
    np.testing.assert_allclose(np.asarray(m.psi0), modes.psi0, atol=2e-3 * np.abs(modes.psi0).max())
    np.testing.assert_allclose(
        np.abs(np.asarray(m.psi1)), np.abs(modes.psi1), atol=1e-2 * np.abs(modes.psi1).max()
    )
    # the simulation's psi_0, psi_1 measured by numpy here (least squares, trapezoid, and
    # the phase slope: np.unwrap, then np.polyfit with the trapezoidal rule's weights)
    assert float(m.static_curvature_rad_per_um) == pytest.approx(
        np.polyfit(modes.s, modes.psi0, 1)[0], rel=1e-2
    )
    a = np.abs(modes.psi1)
    assert float(m.dynamic_amplitude_rad) == pytest.approx(
        np.trapezoid(a, modes.s) / (modes.s[-1] - modes.s[0]), rel=1e-2
    )
    keep1 = np.abs(modes.psi1) > 1e-9 * a.max()  # a clamped base: psi_1(0) = 0, no phase
    s1, p1 = modes.s[keep1], modes.psi1[keep1]
    w = np.r_[(s1[1] - s1[0]) / 2, (s1[2:] - s1[:-2]) / 2, (s1[-1] - s1[-2]) / 2]
    k = np.polyfit(s1, np.unwrap(np.angle(p1)), 1, w=np.sqrt(w))[0]
    assert float(m.wavelength_um) == pytest.approx(2 * np.pi / abs(k), rel=2e-2)
    assert float(m.wavelength_um) == pytest.approx(modes.wavelength, rel=1e-2)
    assert sim.limit_cycle["wavelength_um"] == pytest.approx(modes.wavelength, rel=1e-2)
    assert float(m.static_curvature_rad_per_um) < 0  # the stronger group 0 sits on +y


def test_warm_start_takes_few_newton_steps(setup):
    model, params, start = setup
    """A fit's next evaluation starts from the previous orbit: a 1 % step in p and a0
    costs a few Newton steps (measured 7 at rtol 1e-12) and lands on the orbit a cold
    start (the Hopf normal form) finds."""
    near = params.replace(p=float(params.p) * 1.01, a0=float(params.a0) * 1.01)
    warm = ax.limit_cycle(model, near, KAPPA, solver=SOLVER, start=start)
    cold = ax.limit_cycle(model, near, KAPPA, solver=SOLVER)
    assert int(warm.steps) <= 8
    assert float(warm.omega) == pytest.approx(float(cold.omega), rel=1e-9)
    assert float(warm.amplitude) == pytest.approx(float(cold.amplitude), rel=1e-8)
