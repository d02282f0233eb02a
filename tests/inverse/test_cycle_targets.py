"""Limit-cycle waveform targets (axojax/inverse/cycle_targets.py): a fit of the whole beat on
synthetic data from a known orbit recovers its parameters, and the residuals' exact
Jacobian agrees with central finite differences."""

import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
import pytest

import axojax as ax
from axojax.beats.targets import ShapeTarget
from axojax.inverse.cycle_targets import CycleTarget, waveform_residuals
from axojax.orbits.measures import cycle_measures

SOLVER = ax.orbits.HarmonicBalance(harmonics=4, floquet=0, rtol=1e-11)
S_UM = np.linspace(0.0, 12.0, 21)


@pytest.fixture(scope="module")
def problem():
    """Truth: two filaments (4 elements; one active pair, so its moment is a static load
    b ~ a0 like an imbalance's), p = 1.06 p_c, a0 = 0.3 um, cubic 6; observed psi_0,
    psi_1 (with noise, seeded) and frequency."""
    model = ax.models.two(n_elements=4)
    base = ax.Params(p=160.0)
    p_c = float(ax.critical_force(model, base).p)
    truth = np.array([1.06 * p_c, 0.3 / 12, 6.0])
    cyc = ax.limit_cycle(model, base.replace(p=truth[0], a0=truth[1]), truth[2], solver=SOLVER)
    m = cycle_measures(cyc, S_UM)
    sigma = 0.002
    rng = np.random.default_rng(7)
    psi1 = np.asarray(m.psi1) * np.exp(0.9j) + sigma * (
        rng.standard_normal(21) + 1j * rng.standard_normal(21)
    )
    psi0 = np.asarray(m.psi0) + sigma * rng.standard_normal(21)
    shape = ShapeTarget(S_UM, psi1, sigma, psi0=psi0)
    freq = CycleTarget("frequency_hz", float(m.frequency_hz) * (1 + 1e-4), 0.01)
    return model, base, truth, shape, freq


def residual_fn(model, base, shape, freq):
    """Residuals in log(p, a0, kappa); ``start`` (the warm start) travels as ``args``."""

    def r(z, start):
        p, a0, kappa = jnp.exp(z)
        return waveform_residuals(
            model,
            base.replace(p=p, a0=a0),
            kappa,
            shape=shape,
            scalars=[freq],
            solver=SOLVER,
            start=start,
        )

    return r


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_fit_recovers_the_orbit_parameters(problem):
    model, base, truth, shape, freq = problem
    guess = truth * np.array([1.01, 1.15, 1.3])
    start = ax.limit_cycle(model, base.replace(p=guess[0], a0=guess[1]), guess[2], solver=SOLVER)
    fn = residual_fn(model, base, shape, freq)
    sol = optx.least_squares(
        fn,
        optx.LevenbergMarquardt(rtol=1e-8, atol=1e-8),
        jnp.log(jnp.asarray(guess)),
        args=start,
        max_steps=40,
        throw=False,
    )
    z = sol.value
    fitted = np.exp(np.asarray(z))
    for got, want, tol in zip(fitted, truth, (1e-3, 2e-2, 5e-2)):  # p, a0, kappa
        assert got == pytest.approx(want, rel=tol)
    r = np.asarray(fn(z, start))
    assert np.sum(r**2) / (r.size - 3) < 2.0  # chi^2 per dof ~ 1: the noise, nothing more


def test_residual_jacobian_matches_finite_differences(problem):
    model, base, truth, shape, freq = problem
    start = ax.limit_cycle(model, base.replace(p=truth[0], a0=truth[1]), truth[2], solver=SOLVER)
    z = jnp.log(jnp.asarray(truth * np.array([1.002, 1.05, 0.9])))
    fn = residual_fn(model, base, shape, freq)
    r = jax.jit(fn)
    J = np.asarray(jax.jit(jax.jacfwd(fn))(z, start))
    h = 1e-5
    fd = np.stack(
        [
            (np.asarray(r(z.at[i].add(h), start)) - np.asarray(r(z.at[i].add(-h), start))) / (2 * h)
            for i in range(3)
        ],
        axis=1,
    )
    np.testing.assert_allclose(J, fd, atol=1e-5 * np.abs(fd).max())
