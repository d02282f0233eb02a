"""Limit cycles of regulated rows with motor kinetics and saturating motors (issue 47 item
3 for orbits): ``ax.limit_cycle(..., tau_m=, f_sat=)`` and ``axojax orbit --motor-tau-ms
--motor-saturation`` find the periodic orbit of the doubled state X = (q, y) that
``ax.simulate(..., tau_m=, f_sat=)`` integrates.

References are independent of the orbit code: a long simulation from a small bend (the
diffrax integrator), and scipy's eigenvalues of the augmented pencil assembled here from
``ax.assemble`` alone (``_augmented`` of tests/regulation/test_motor_kinetics_time.py). The two rows
are sliding control (chi'' < 0) on a clamped base, with the cubic links on, and Sartori et
al.'s curvature control (beta'' < 0) on a clamped base with basal compliance, with the
saturation alone bounding the beat (cubic links off).
"""

import json
import math

import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.dynamics.nonlinear import cubic_link_force
from axojax.orbits import HarmonicBalance, cycle_measures
from axojax.orbits.fourier import evaluate
from tests.regulation.test_motor_kinetics import _hopf, _sliding_row  # noqa: E402
from tests.regulation.test_motor_kinetics_time import (  # noqa: E402
    COMPLIANT,
    _augmented,
    _dominant,
    _saturated_field,
    _scaled,
    _tau_m,
)
from tests.regulation.test_sartori import UNITS as SARTORI_UNITS  # noqa: E402
from tests.regulation.test_sartori import _params as sartori_params  # noqa: E402


def _sliding():
    """Clamped two-filament sliding control at its Hopf point (chi'' < 0); saturating at
    40 pN/um, cubic links on (default 10). (model, params at the Hopf point, units,
    field, the parts scaled past it, f_sat, cubic)."""
    units = ax.Units()
    f_sat = float(units.p_from_pn_per_um(40.0))
    return ax.models.two(n_elements=8), _sliding_row(), units, "chi", ("re", "im"), f_sat, 10.0


def _curvature():
    """Sartori et al.'s curvature control (beta'' < 0) on a clamped base with basal
    compliance, at that base's Hopf point; saturating at 100 pN/um, no cubic links (the
    saturation alone bounds the beat)."""
    model = ax.models.two(n_elements=8, base=COMPLIANT)
    params = sartori_params()
    params = _hopf(model, params, "beta", complex(params.beta_re, params.beta_im))
    f_sat = float(SARTORI_UNITS.p_from_pn_per_um(100.0))
    return model, params, SARTORI_UNITS, "beta", ("re", "im"), f_sat, 0.0


ROWS = {"sliding-clamped": _sliding, "curvature-clamped+compliance": _curvature}
PAST = {"sliding-clamped": 0.1, "curvature-clamped+compliance": 0.05}
"""How far past the Hopf point the orbit is compared with a simulation (the rows of
tests/regulation/test_motor_kinetics_time.py)."""
SETTLE_S = {"sliding-clamped": 0.25, "curvature-clamped+compliance": 0.5}
"""Simulated time: 44 and 34 periods (the sliding beat grows from the bend in about the
first 10); the orbit's largest Floquet multiplier besides 1 is 0.71 and 0.63 a period, so
the start is forgotten to ~1e-5 or better."""


def _row(name, past):
    model, params, units, field, parts, f_sat, cubic = ROWS[name]()
    return model, _scaled(params, field, 1.0 + past, parts), units, f_sat, cubic


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("name", list(ROWS))
def test_the_orbit_is_the_long_simulation(name):
    """(a) Past the Hopf point a long simulation from a small bend (0.1 um) settles on the
    orbit: frequency within 1e-3, tip amplitude and dynamic amplitude within 1e-2 (measured,
    sliding then curvature: frequency 2.7e-6 and 3.0e-6, tip amplitude 3.3e-5 and 5.7e-5,
    dynamic amplitude 1.4e-5 and 5.3e-5; the simulation's peaks read from 256 samples a
    period). Tip amplitudes 0.63 and 0.13 um."""
    model, params, units, f_sat, cubic = _row(name, PAST[name])
    tau_m = _tau_m(units)
    sim = ax.simulate(
        model,
        params,
        SETTLE_S[name],
        units=units,
        tau_m=tau_m,
        f_sat=f_sat,
        cubic=cubic,
        samples_per_period=256,
        rtol=1e-8,
        atol=1e-11,
    )
    assert sim.state == "limit_cycle", sim.state
    cycle = ax.limit_cycle(model, params, cubic, tau_m=tau_m, f_sat=f_sat, throw=True)
    assert bool(cycle.stable)
    ours = cycle_measures(cycle, None, units)
    lc = sim.limit_cycle
    assert float(cycle.frequency_hz(units)) == pytest.approx(lc["frequency_hz"], rel=1e-3)
    assert float(cycle.amplitude_um(units)) == pytest.approx(lc["tip_amplitude_um"], rel=1e-2)
    assert float(ours.dynamic_amplitude_rad) == pytest.approx(lc["dynamic_amplitude_rad"], rel=1e-2)
    assert lc["tip_amplitude_um"] > 0.1  # a beat the saturation bounds, well above the start's


@pytest.mark.slow
def test_the_orbit_is_the_long_simulation_on_a_pivot():
    """A pivot on a rotational spring (the other held base: the basal slope in the border)
    with sliding control 10 % past its Hopf point there: the orbit is the simulation's
    cycle (frequency 1e-3, tip amplitude in the body frame 1e-2; measured 4e-5, 2.4e-4)."""
    model = ax.models.two(
        n_elements=8, base=ax.models.Base("pivot", rotational_stiffness=50.0, rotational_drag=0.1)
    )
    _, _, units, field, parts, f_sat, cubic = _sliding()
    params = _hopf(model, _sliding_row(), "chi", -1.3e5 - 1.8e5j)
    params = _scaled(params, field, 1.1, parts)
    tau_m = _tau_m(units)
    sim = ax.simulate(
        model, params, 0.25, units=units, tau_m=tau_m, f_sat=f_sat, cubic=cubic,
        samples_per_period=256, rtol=1e-8, atol=1e-11,
    )  # fmt: skip
    assert sim.state == "limit_cycle", sim.state
    cycle = ax.limit_cycle(model, params, cubic, tau_m=tau_m, f_sat=f_sat, throw=True)
    lc = sim.limit_cycle
    assert float(cycle.frequency_hz(units)) == pytest.approx(lc["frequency_hz"], rel=1e-3)
    assert float(cycle.amplitude_um(units)) == pytest.approx(lc["tip_amplitude_um"], rel=1e-2)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("name", list(ROWS))
def test_the_orbit_solves_the_simulated_equations(name):
    """The harmonic balance's X(theta) satisfies the augmented equations built here
    (A', C', b' from ax.assemble, the saturating force from the Gauss-point rows, the cubic
    links): omega dX/dtheta = C'^-1 (b' - A' X - f_nl(X)) at phases between the samples, to
    1e-6 of |dX/dt| with 30 harmonics (measured 1.4e-8 sliding, 2.6e-10 curvature; the
    sliding beat's harmonics decay by ~1e-3 every 10, so 20 harmonics leave 1.7e-5)."""
    model, params, units, f_sat, cubic = _row(name, PAST[name])
    tau_m = _tau_m(units)
    H = 30
    solver = HarmonicBalance(harmonics=H, floquet=0)
    cycle = ax.limit_cycle(model, params, cubic, tau_m=tau_m, f_sat=f_sat, solver=solver)
    assert bool(cycle.converged), cycle.message
    n = model.n_unknowns
    X = np.asarray(cycle.coefficients)
    assert X.shape == (2 * H + 1, 2 * n)
    rhs = _saturated_field(model, params, tau_m, f_sat)
    A, C, _ = _augmented(model, params, tau_m)
    theta = jnp.asarray(2 * np.pi * (np.arange(13) + 0.37) / 13)
    states = np.asarray(evaluate(jnp.asarray(X), theta))
    k = np.arange(1, H + 1)
    dX = X.copy()  # d/dtheta of the series
    dX[0], dX[1 : H + 1], dX[H + 1 :] = 0.0, k[:, None] * X[H + 1 :], -k[:, None] * X[1 : H + 1]
    rates = float(cycle.omega) * np.asarray(evaluate(jnp.asarray(dX), theta))
    for Xi, ri in zip(states, rates):
        f = rhs(0.0, Xi)
        links = np.asarray(cubic_link_force(model, params, cubic, jnp.asarray(Xi[:n])))
        f = f - np.linalg.solve(C, np.concatenate([links, np.zeros(n)]))
        assert np.linalg.norm(ri - f) <= 1e-6 * np.linalg.norm(ri), np.linalg.norm(ri - f)
    np.testing.assert_allclose(cycle.q_coefficients, X[:, :n])


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_saturation_is_sampled_finely_enough():
    """The tanh of saturating motors is projected from samples (not exactly, as a cubic
    is): the default 8 H + 2 samples against 16 H + 2 change the orbit's frequency and
    amplitude by less than 1e-10 (measured 1e-16 and 7e-15 on the sliding row)."""
    model, params, units, f_sat, cubic = _row("sliding-clamped", PAST["sliding-clamped"])
    out = []
    for samples in (None, 162):
        solver = HarmonicBalance(harmonics=10, samples=samples, floquet=0)
        cycle = ax.limit_cycle(
            model, params, cubic, tau_m=_tau_m(units), f_sat=f_sat, solver=solver
        )
        out.append((float(cycle.omega), float(cycle.amplitude)))
    assert out[0][0] == pytest.approx(out[1][0], rel=1e-10)
    assert out[0][1] == pytest.approx(out[1][1], rel=1e-10)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_orbit_is_differentiable_in_the_motors():
    """Forward-mode derivatives of the orbit's frequency and amplitude in tau_m, f_sat and
    beta'' (the implicit function theorem through the harmonic balance, never through
    Newton's iterations) equal central differences (1e-5; measured 1.5e-6 at most, the
    amplitude in f_sat 9e-9: with the links off the cycle scales with f_sat, so the
    frequency's derivative there is 0 and is not compared)."""
    import jax

    from axojax.orbits import Motors

    model, params, units, f_sat, cubic = _row("curvature-clamped+compliance", 0.05)
    solver = HarmonicBalance(floquet=0, rtol=1e-12)

    def measures(tau_m, f_sat, beta_im):
        motors = Motors(tau_m=tau_m, f_sat=f_sat)
        cycle = solver.solve(
            model, params.replace(beta_im=beta_im), jnp.asarray(cubic), None, motors
        )
        return jnp.stack([cycle.omega, cycle.amplitude])

    x0 = [jnp.asarray(v) for v in (_tau_m(units), f_sat, float(params.beta_im))]
    jac = jax.jit(jax.jacfwd(measures, argnums=(0, 1, 2)))(*x0)
    value = jax.jit(measures)
    for i in range(3):
        h = 1e-6 * abs(float(x0[i]))
        up, down = list(x0), list(x0)
        up[i], down[i] = x0[i] + h, x0[i] - h
        fd = np.asarray(value(*up) - value(*down)) / (2 * h)
        compared = [1] if i == 1 else [0, 1]
        np.testing.assert_allclose(np.asarray(jac[i])[compared], fd[compared], rtol=1e-5)


DISTANCES = (0.01, 0.02, 0.04)


@pytest.mark.parametrize("name", list(ROWS))
def test_near_onset_the_orbit_grows_from_the_linear_mode(name):
    """(b) At 1, 2 and 4 % past the Hopf point (chi or beta scaled): the orbit's linear
    eigenvalue is scipy's rightmost eigenvalue of the augmented pencil (1e-8); its squared
    amplitude grows linearly with the distance from onset, measured by that eigenvalue's
    growth rate mu (a^2 / mu constant to 3 %; measured 1.0 % sliding, 1.2 % curvature): both
    Hopf bifurcations are supercritical (no subcritical case among the tested rows); and its
    frequency, extrapolated to mu = 0 (quadratic in mu through the three orbits), is the
    linear mode's at the Hopf point within 1e-3 (measured 4e-5 and 3e-6).

    At a few % past onset the orbit's frequency is *not* within 1e-3 of the linear mode's at
    the same parameters: it is shifted in proportion to a^2 (Stuart-Landau), by 1.2 % at
    1 % past onset for sliding control and 0.6 % for curvature control."""
    model, hopf, units, field, parts, f_sat, cubic = ROWS[name]()
    tau_m = _tau_m(units)
    lam0 = _dominant(*_augmented(model, hopf, tau_m)[:2])
    assert abs(lam0.real) < 1e-6 * abs(lam0.imag)  # the Hopf point, kept with the motors
    solver = HarmonicBalance(floquet=2)
    mu, a2, omega = [], [], []
    for eps in DISTANCES:
        params = _scaled(hopf, field, 1.0 + eps, parts)
        lam = _dominant(*_augmented(model, params, tau_m)[:2])
        cycle = ax.limit_cycle(
            model, params, cubic, tau_m=tau_m, f_sat=f_sat, solver=solver, throw=True
        )
        ours = complex(cycle.linear_eigenvalue)
        assert ours.real == pytest.approx(lam.real, rel=1e-8)
        assert ours.imag == pytest.approx(abs(lam.imag), rel=1e-8)
        assert bool(cycle.stable)  # supercritical: the small orbit attracts
        mu.append(lam.real)
        a2.append(float(cycle.amplitude) ** 2)
        omega.append(float(cycle.omega))
    slope = np.array(a2) / np.array(mu)
    assert slope.max() / slope.min() - 1 < 0.03, slope
    onset = np.polyfit(mu, omega, 2)[-1]
    assert onset == pytest.approx(abs(lam0.imag), rel=1e-3)


def test_before_the_hopf_point_there_is_no_orbit():
    """2 % before onset the equilibrium is stable: one line saying so (and what to move)."""
    model, hopf, units, field, parts, f_sat, cubic = _sliding()
    params = _scaled(hopf, field, 0.98, parts)
    with pytest.raises(ValueError, match="linearly stable") as err:
        ax.limit_cycle(model, params, cubic, tau_m=_tau_m(units), f_sat=f_sat, throw=True)
    assert "\n" not in str(err.value) and "chi or beta" in str(err.value)


# -- (c) bad values: one line naming them -----------------------------------------------


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), 1e300])
def test_a_bad_motor_time_is_one_line(bad):
    model, params, units, f_sat, cubic = _row("sliding-clamped", 0.1)
    with pytest.raises(ValueError) as err:
        ax.limit_cycle(model, params, cubic, tau_m=bad, f_sat=f_sat)
    assert "\n" not in str(err.value) and "tau_m" in str(err.value) and repr(bad) in str(err.value)


@pytest.mark.parametrize("bad", [0.0, -1.0, float("inf")])
def test_a_bad_saturation_is_one_line(bad):
    model, params, units, _, cubic = _row("sliding-clamped", 0.1)
    with pytest.raises(ValueError) as err:
        ax.limit_cycle(model, params, cubic, tau_m=_tau_m(units), f_sat=bad)
    assert "\n" not in str(err.value) and "f_sat" in str(err.value) and repr(bad) in str(err.value)


def test_other_refusals_are_one_line():
    model, params, units, f_sat, _ = _row("sliding-clamped", 0.1)
    tau_m = _tau_m(units)
    cases = [
        (dict(f_sat=f_sat), "needs motor kinetics"),
        (dict(kappa=-1.0, tau_m=tau_m, f_sat=f_sat), "kappa"),
        (dict(kappa=0.0, tau_m=tau_m), "kappa"),  # linear motors: the links must bound it
        ({}, "tau_m"),  # an active friction without motors: refused, pointing to tau_m
    ]
    for kwargs, needle in cases:
        kappa = kwargs.pop("kappa", 10.0)
        with pytest.raises(ValueError) as err:
            ax.limit_cycle(model, params, kappa, **kwargs)
        assert "\n" not in str(err.value) and needle in str(err.value), (kwargs, str(err.value))


def _orbit_argv(past=0.1, units=ax.Units()):
    """``axojax orbit`` on the sliding row ``past`` its Hopf point, in pN/um^2 and Hz."""
    params = _scaled(_sliding_row(), "chi", 1.0 + past)
    chi = complex(params.chi_re, params.chi_im) * units.ei_pn_um2 / units.length_um**4
    hz = float(params.omega0) / (2 * math.pi * units.tau_s)
    argv = ["orbit", "--model", "two", "--elements", "8", "--p", "0", "--mechanism", "sliding"]
    return argv + [f"--chi={chi.real!r},{chi.imag!r}", "--omega0-hz", repr(hz)]


@pytest.mark.parametrize(
    "extra, flag, needle",
    [
        (["--motor-tau-ms=0"], "--motor-tau-ms", "must be > 0"),
        (["--motor-tau-ms=1e300"], "--motor-tau-ms", "tau_m"),
        (["--motor-tau-ms", "5", "--motor-saturation=-2"], "--motor-saturation", "must be > 0"),
        (["--motor-saturation", "2"], "--motor-saturation", "needs motor kinetics"),
        (["--motor-tau-ms", "5", "--cubic", "0"], "--cubic", "> 0"),
        ([], "--chi", "tau_m"),
    ],
)
def test_cli_refuses_bad_motor_values_on_one_line(capsys, extra, flag, needle):
    """(c) on the command line: one line on stderr naming the flag, exit code 2."""
    from axojax.cli.main import main

    code = main([*_orbit_argv(), *extra, "--json"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"axojax: error: {flag}: ") and needle in err, err


def test_cli_refuses_a_branch_with_motors(capsys):
    """(A base that moves is taken: tests/orbits/test_free_base_orbits.py.)"""
    from axojax.cli.main import main

    motors = ["--motor-tau-ms", "5", "--motor-saturation", "40"]
    argv = _orbit_argv()
    for extra, flag in ((["--p", "0,1e-3"], "--p"),):
        code = main([*argv, *motors, *extra, "--json"])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and err.startswith(f"axojax: error: {flag}: ")


def test_cli_orbit_with_motor_kinetics(capsys):
    """``axojax orbit ... --motor-tau-ms 5 --motor-saturation 40``: the library's orbit, in
    Hz and um, and the JSON's ``motor_kinetics`` says which motors were used."""
    from axojax.cli.main import main

    model, params, units, f_sat, cubic = _row("sliding-clamped", 0.1)
    argv = [*_orbit_argv(), "--motor-tau-ms", "5", "--motor-saturation", "40"]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    cycle = ax.limit_cycle(model, params, cubic, tau_m=_tau_m(units), f_sat=f_sat)
    (orbit,) = doc["orbits"]
    assert orbit["frequency_hz"] == pytest.approx(float(cycle.frequency_hz(units)), rel=1e-6)
    assert orbit["tip_amplitude_um"] == pytest.approx(float(cycle.amplitude_um(units)), rel=1e-6)
    assert orbit["stable"] is True
    assert doc["motor_kinetics"]["tau_ms"] == pytest.approx(5.0)
    assert doc["motor_kinetics"]["f_sat_pn_per_um"] == pytest.approx(40.0)
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "motor kinetics: tau_m = 5 ms" in text and "saturating at 40 pN/um" in text


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_warm_starts_take_the_motors_and_older_solvers_still_work():
    """WarmStart passes the motors on (from the regulated orbit itself: one Newton step,
    the same orbit); a solver written before motor kinetics (``solve`` without ``motors``)
    still serves the friction form, through limit_cycle and WarmStart."""
    import jax

    from axojax.orbits import AbstractOrbitSolver, Motors, WarmStart

    model, params, units, f_sat, cubic = _row("curvature-clamped+compliance", 0.05)
    solver = HarmonicBalance(harmonics=6, floquet=0)
    motors = Motors(tau_m=jnp.asarray(_tau_m(units)), f_sat=jnp.asarray(f_sat))
    cold = ax.limit_cycle(model, params, cubic, tau_m=_tau_m(units), f_sat=f_sat, solver=solver)
    warm = jax.jit(
        lambda p, start: WarmStart(solver, warm_steps=2).solve(
            model, p, jnp.asarray(cubic), start, motors
        )
    )(params, cold)
    assert bool(warm.converged) and int(warm.steps) == 1
    assert float(warm.omega) == pytest.approx(float(cold.omega), rel=1e-10)

    class Legacy(AbstractOrbitSolver):
        inner: HarmonicBalance

        def solve(self, model, params, kappa, start=None):
            return self.inner.solve(model, params, kappa, start)

    two, steady = ax.models.two(n_elements=4), ax.Params(p=160.0)
    ref = ax.limit_cycle(two, steady, 10.0, solver=solver)
    legacy = ax.limit_cycle(two, steady, 10.0, solver=Legacy(solver))
    again = WarmStart(Legacy(solver), warm_steps=2).solve(two, steady, jnp.asarray(10.0), legacy)
    for cycle in (legacy, again):
        assert bool(cycle.converged)
        assert float(cycle.omega) == pytest.approx(float(ref.omega), rel=1e-10)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_augmented_harmonic_balance_jacobian_is_exact_in_the_node_layout():
    """The Newton matrix of the doubled state, block-tridiagonal in the integrator's node
    order (each node's q then its y) on a clamped base and one dense block with basal
    compliance, equals forward-mode autodiff of the harmonic-balance residual (1e-10), and
    the mass blocks are I (x) C' (the Floquet pencil)."""
    import jax

    from axojax.orbits.motors import Motors, orbit_problem

    rng = np.random.default_rng(7)
    for base in (ax.models.Base("clamped"), COMPLIANT):
        model = ax.models.seven(n_elements=3, base=base)
        params = sartori_params().replace(chi_re=-50.0, chi_im=-80.0, kb=20.0, xib=0.3)
        motors = Motors(tau_m=jnp.asarray(0.02), f_sat=jnp.asarray(3.0))
        prob = orbit_problem(model, params, 10.0, 3, 26, motors)
        assert prob.n == 2 * model.n_unknowns and prob.bordered == bool(model.n_border)
        X = jnp.asarray(0.05 * rng.normal(size=(prob.m, prob.n)))
        ref = jax.jacfwd(lambda Y: jnp.ravel(prob.harmonic_residual(Y, 3.0)))(X).reshape(
            prob.m * prob.n, -1
        )
        perm = np.asarray(prob.to_nodes(jnp.arange(prob.m * prob.n, dtype=float))).astype(int)
        blocks = np.asarray(prob.jacobian_blocks(X, 3.0).to_dense())
        ref_nodes = np.asarray(ref)[perm][:, perm]
        assert np.abs(blocks - ref_nodes).max() <= 1e-10 * np.abs(ref_nodes).max()
        mass = np.asarray(prob.mass_blocks().to_dense())
        C = np.kron(np.eye(prob.m), np.asarray(prob.s.C))[perm][:, perm]
        assert np.array_equal(mass, C)
