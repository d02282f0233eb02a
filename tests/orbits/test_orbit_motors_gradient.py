"""A whole-beat fit's loss through a regulated orbit (issue 47, acceptance: "A fit's value
and gradient through the orbit: gradient equal to finite differences (1e-5 relative)").

The row is tests/orbits/test_orbit_motors.py's sliding control (chi'' < 0) on a clamped base,
two filaments on 8 elements, 10 % past its Hopf point, motor kinetics (tau_m = 5 ms),
saturating motors (40 pN/um) and cubic links (10). The loss is the one a whole-beat fit
of item 4 minimises for two of its measures: the squared relative misfits of the orbit's
frequency (Hz) and dynamic amplitude (rad, the arc-length mean of |psi_1|, 41 points)
against fixed targets (170 Hz and 0.12 rad; the orbit's own are 176.1 Hz and 0.1137 rad,
so neither misfit is near zero and each term contributes).

Every parameter the orbit's API takes is traced: the motors' tau_m and f_sat
(:class:`axojax.orbits.Motors`, a pytree), the regulation's chi' and chi'' (``params``)
and the cubic stiffening kappa. None is left out, but on this row two are degenerate:

- kappa does not act: the planar two-filament beat of sliding control at p = 0 leaves
  its one link unstretched (the cubic link force on the orbit is 1e-46), so the orbit is
  the same to every printed digit at kappa 0, 10 and 1e4 (omega 946.6115917479851). Its
  derivative is exactly 0 (the differences give 0.0, the gradient 4e-63), so it is
  checked to vanish, not to a relative tolerance.
- f_sat, with no other nonlinearity acting, only scales the orbit (the equations are
  homogeneous of degree 1 in (X, f_sat)): the frequency does not depend on it and the
  dynamic amplitude is proportional to it, so the loss is quadratic in f_sat and its
  central difference is exact (agreement 3e-11). The gradient still goes through the
  implicit solve (dX/df_sat = X / f_sat), and is compared.

The reverse-mode gradient (``jax.value_and_grad``: the implicit function theorem's
transposed solve through the harmonic balance, never Newton's iterations) is compared
with central differences of the same compiled loss. Its cost against the orbit alone:
benchmarks/bench_orbit_gradient.py.

The difference steps are relative to each value (:data:`STEPS`: 3e-4 for tau_m, 1.5e-5 for
chi', 1.5e-4 for chi''), each where the central difference's truncation is ~1e-7 of the
derivative: measured against the gradient at 4, 2, 1, 1/2 and 1/4 of those steps, the
error falls as h^2 (tau_m 2.1e-6, 5.2e-7, 1.3e-7, 3.3e-8, 7.9e-9; chi' 1.6e-6 ... 9.8e-8
... 5.4e-9; chi'' 1.8e-6 ... 1.1e-7 ... 6.7e-9), so the gradient is right to far better
than the 1e-5 asserted; Newton's tolerance (1e-12) keeps the rounding of the differences
near 1e-10 (f_sat, where the difference is exact: 3e-11).
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from axojax.orbits import HarmonicBalance, Motors, cycle_measures
from tests.orbits.test_orbit_motors import _row  # noqa: E402
from tests.regulation.test_motor_kinetics_time import _tau_m  # noqa: E402

TARGET_HZ = 170.0
TARGET_RAD = 0.12
NAMES = ("tau_m", "f_sat", "chi_re", "chi_im", "kappa")
STEPS = {"tau_m": 3e-4, "f_sat": 2e-4, "chi_re": 1.5e-5, "chi_im": 1.5e-4, "kappa": 2e-4}
"""Relative central-difference steps, each where the truncation is ~1e-7 (module
docstring)."""


def _loss_and_start():
    """(loss(x) -> (value, converged), x0): x = (tau_m, f_sat, chi', chi'', kappa)."""
    model, params, units, f_sat, cubic = _row("sliding-clamped", 0.1)
    solver = HarmonicBalance(floquet=0, rtol=1e-12)

    def loss(x):
        tau_m, f_sat, chi_re, chi_im, kappa = x
        cycle = solver.solve(
            model,
            params.replace(chi_re=chi_re, chi_im=chi_im),
            kappa,
            None,
            Motors(tau_m=tau_m, f_sat=f_sat),
        )
        m = cycle_measures(cycle, None, units)
        misfit = jnp.stack(
            [
                (m.frequency_hz - TARGET_HZ) / TARGET_HZ,
                (m.dynamic_amplitude_rad - TARGET_RAD) / TARGET_RAD,
            ]
        )
        return jnp.sum(misfit**2), cycle.converged

    x0 = jnp.asarray(
        [_tau_m(units), f_sat, float(params.chi_re), float(params.chi_im), float(cubic)]
    )
    return loss, x0


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_loss_gradient_through_the_regulated_orbit_equals_finite_differences():
    """jax.value_and_grad of the loss equals central differences in tau_m, f_sat, chi'
    and chi'' (1e-5 relative per component; measured 1.3e-7, 3e-11, 9.8e-8, 1.1e-7: the differences'
    truncation)
    and both vanish in kappa; the value is the loss's own and the orbit converged at every
    point the differences evaluate."""
    loss, x0 = _loss_and_start()
    value_and_grad = jax.jit(jax.value_and_grad(loss, has_aux=True))
    (value, converged), grad = value_and_grad(x0)
    assert bool(converged)
    value_alone = jax.jit(loss)
    assert float(value) == pytest.approx(float(value_alone(x0)[0]), rel=1e-12)
    grad = np.asarray(grad)
    assert np.all(np.isfinite(grad)), grad
    for i, name in enumerate(NAMES):
        h = STEPS[name] * abs(float(x0[i]))
        (up, ok_up), (down, ok_down) = value_alone(x0.at[i].add(h)), value_alone(x0.at[i].add(-h))
        assert bool(ok_up) and bool(ok_down), name
        fd = (float(up) - float(down)) / (2 * h)
        if name == "kappa":  # does not act on this row (module docstring)
            assert abs(fd) * float(x0[i]) <= 1e-12 * float(value), fd
            assert abs(grad[i]) * float(x0[i]) <= 1e-12 * float(value), grad[i]
            continue
        assert grad[i] != 0.0, name
        assert grad[i] == pytest.approx(fd, rel=1e-5), (name, grad[i], fd)
