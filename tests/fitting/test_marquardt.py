"""The Levenberg-Marquardt of fits through a periodic orbit (issue 54 item 3,
axojax/inverse/fitting/marquardt.py): its stopping rule's Gauss-Newton gain against
numpy's least squares, its stop within STANDARD_ERRORS standard errors of an optimum
that scipy finds independently on a sloppy curved valley (a sum of two exponentials,
Transtrum et al.'s example of a sloppy model), and the column scaling."""

import jax
import jax.numpy as jnp
import lineax as lx
import numpy as np
import optimistix as optx
import scipy.optimize as so

from axojax.inverse.fitting.marquardt import (
    STANDARD_ERRORS,
    StatisticalLevenbergMarquardt,
    column_scales,
    gauss_newton_gain,
)

T = np.linspace(0.0, 4.0, 30)
SIGMA = 0.01


def _data():
    rng = np.random.default_rng(7)
    return np.exp(-0.7 * T) + np.exp(-1.3 * T) + SIGMA * rng.normal(size=T.size)


def _residuals(theta, y):
    """Normalised residuals of y = exp(-theta_0 t) + exp(-theta_1 t), theta = exp(z)."""
    k = jnp.exp(theta)
    return (jnp.exp(-k[0] * T) + jnp.exp(-k[1] * T) - y) / SIGMA


def test_gain_is_the_projection_of_the_residuals_on_the_jacobians_range():
    rng = np.random.default_rng(0)
    J, r = rng.normal(size=(12, 3)), rng.normal(size=12)
    info = optx.FunctionInfo.ResidualJac(jnp.asarray(r), lx.MatrixLinearOperator(jnp.asarray(J)))
    step = np.linalg.lstsq(J, r, rcond=None)[0]
    assert np.isclose(float(gauss_newton_gain(info)), np.sum((J @ step) ** 2), rtol=1e-10)


def test_stops_within_the_stated_standard_errors_of_scipys_optimum():
    y = _data()
    truth = so.least_squares(
        lambda z: np.asarray(_residuals(jnp.asarray(z), y)),
        np.log([0.5, 2.0]),
        xtol=1e-15,
        ftol=1e-15,
        gtol=1e-15,
    )
    sol = optx.least_squares(
        lambda z, _: _residuals(z, y),
        StatisticalLevenbergMarquardt(rtol=1e-14, atol=1e-14),
        jnp.log(jnp.array([0.2, 5.0])),
        max_steps=200,
        throw=False,
    )
    assert sol.result == optx.RESULTS.successful
    J = np.asarray(jax.jacfwd(lambda z: _residuals(z, y))(jnp.asarray(truth.x)))
    d = np.asarray(sol.value) - truth.x
    # the distance to the optimum in standard errors (the metric J^T J): the rule's bound,
    # with the quadratic model's slack
    assert np.sqrt(d @ J.T @ J @ d) <= 1.5 * STANDARD_ERRORS
    # and it stopped by the statistical rule, well before the Cauchy one (tolerances 1e-14)
    assert int(sol.stats["num_steps"]) < 200


def test_column_scales_make_the_jacobians_columns_unit_length():
    y = _data()
    z0 = jnp.log(jnp.array([0.2, 5.0]))
    d = column_scales(lambda z: _residuals(z, y), z0)
    J = jax.jacfwd(lambda v: _residuals(v / d, y))(z0 * d)
    assert np.allclose(np.linalg.norm(np.asarray(J), axis=0), 1.0, rtol=1e-10)
