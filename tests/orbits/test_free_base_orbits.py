"""Periodic orbits on bases that move (issue 54 item 4; docs/model.md section 8): free and
head bases (a translation and a rotation per direction), whose rigid offset the harmonic
balance fixes by one phase condition per rigid motion, with the drift solved for.

References are independent of the orbit code: a long ``ax.simulate`` run from a small
bend (the diffrax integrator, which needs no gauge: it conserves the drag-weighted rigid
coordinates Z^T C q), the rigid motions built here from the node positions, and the
assembled matrices.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.optimize

import axojax as ax
from axojax.models import Base
from axojax.orbits import HarmonicBalance
from axojax.orbits.fourier import evaluate
from axojax.orbits.rigid import rigid_load
from axojax.results import RESULTS
from axojax.waveform.shapes import centreline
from tests.regulation.test_motor_kinetics import _hopf
from tests.regulation.test_motor_kinetics_time import _scaled, _tau_m
from tests.regulation.test_sartori import UNITS
from tests.regulation.test_sartori import _params as sartori_params

SOLVER = HarmonicBalance(harmonics=6)
ELEMENTS = 4
HEAD = Base("head", translational_drag=1.0, rotational_drag=0.2)


def rigid_modes(model) -> np.ndarray:
    """(n_unknowns, r) the translation (u = 1) and rotation (u = x, u' = 1) of every
    filament in each direction (a pivot: the rotation only), node 0's shared dofs after
    the nodes, built from the mesh (not from ``Model.rigid_modes``)."""
    N, F, d = model.n_elements, model.n_filaments, model.n_dirs
    dofs = model.base.dofs  # node 0's kept (u(0), u'(0)) per direction
    motions = (False, True) if 0 in dofs else (True,)
    x = np.arange(1, N + 1) / N
    cols = []
    for a in range(d):
        for rotation in motions:
            q = np.zeros((F, d, N, 2))
            q[:, a, :, 0] = x if rotation else 1.0
            q[:, a, :, 1] = 1.0 if rotation else 0.0
            border = np.zeros(model.n_border)
            border[a * len(dofs) + dofs.index(int(rotation))] = 1.0
            cols.append(np.concatenate([q.ravel(), border]))
    return np.array(cols).T


def regulated_row(base, past=1.05):
    """Sartori et al.'s curvature control (beta'' < 0, their units) moved onto the Hopf
    point of ``base`` on six elements, then ``past`` it; motor kinetics (5 ms) and
    saturating motors (100 pN/um) bound the beat, no cubic links. (model, params, tau_m,
    f_sat)."""
    model = ax.models.two(n_elements=ELEMENTS, base=base)
    params = sartori_params()
    params = _hopf(model, params, "beta", complex(params.beta_re, params.beta_im))
    params = _scaled(params, "beta", past)
    return model, params, _tau_m(UNITS), float(UNITS.p_from_pn_per_um(100.0))


def psi_coefficients(cycle, x) -> np.ndarray:
    """(2H+1, S) the orbit's tangent angle along its beat direction, per harmonic, at x."""
    slope = centreline(cycle.model, np.asarray(cycle.q_coefficients), np.asarray(x), 1)
    a = float(cycle.beat_angle)
    return np.cos(a) * slope[:, 0] + (np.sin(a) * slope[:, 1] if slope.shape[1] > 1 else 0.0)


def psi_mismatch(cycle, sim, units, offset: bool) -> float:
    """Relative L2 difference of psi(s, t) over the simulation's last period and the
    orbit's, the time shift aligned (and with ``offset`` the constant rigid rotation of a
    base that moves, least squares), over the norm of the simulation's beat about its
    mean."""
    P = 1.0 / float(cycle.frequency_hz(units))
    T = 200
    t = sim.t_s[-1] - P + P * np.arange(T) / T
    psi_sim = np.stack([np.interp(t, sim.t_s, col) for col in sim.psi_rad.T], axis=1)
    coeffs = jnp.asarray(psi_coefficients(cycle, sim.x_um / units.length_um))
    theta = 2 * np.pi * np.arange(T) / T

    def misfit(phi):
        d = psi_sim - np.asarray(evaluate(coeffs, jnp.asarray(theta + phi)))
        return d - d.mean() if offset else d

    grid = 2 * np.pi * np.arange(64) / 64
    phi0 = grid[np.argmin([np.linalg.norm(misfit(p)) for p in grid])]
    best = scipy.optimize.minimize_scalar(
        lambda p: np.linalg.norm(misfit(p)), bounds=(phi0 - 0.1, phi0 + 0.1), method="bounded"
    )
    return float(best.fun / np.linalg.norm(psi_sim - psi_sim.mean(axis=0)))


def test_the_static_load_has_no_rigid_component():
    """docs/model.md section 8: the static dynein moment m0 (and the imbalance's couple of
    a regulated row, p = 0) loads a free or head axoneme without a net force or torque:
    Z^T b = 0 to rounding, Z built here from the mesh, b assembled; ``rigid_load`` says
    the same. b itself is not 0 (the check is not empty), and a clamped base has no rigid
    motion to load."""
    for base in ("free", HEAD, Base("free", compliance=True), "pivot"):
        for preset in ("two", "seven"):
            model = getattr(ax.models, preset)(n_elements=5, base=base)
            params = ax.Params(p=0.0, m0=3.0, chi_re=50.0, beta_re=3.0, omega0=10.0, kb=5.0)
            params = params.replace(xib=0.5)
            b = np.asarray(ax.assemble(model, params).b)
            assert np.abs(b).max() > 0.1
            Z = rigid_modes(model)
            np.testing.assert_allclose(Z, model.rigid_modes(), atol=0)
            assert np.abs(Z.T @ b).max() <= 1e-12 * np.abs(b).max(), (base, preset)
            ours = np.asarray(rigid_load(model, params))
            assert ours.shape == (Z.shape[1],) and np.abs(ours).max() <= 1e-12 * np.abs(b).max()
    assert rigid_load(ax.models.two(n_elements=5), ax.Params(m0=3.0)).shape == (0,)


@pytest.fixture(scope="module")
def free_row():
    """The regulated row 10 % past its Hopf point on a free base with basal compliance
    (Sartori et al.'s own base) and its orbit."""
    model, params, tau_m, f_sat = regulated_row(Base("free", compliance=True), 1.1)
    cycle = ax.limit_cycle(model, params, 0.0, tau_m=tau_m, f_sat=f_sat, solver=SOLVER, throw=True)
    return model, params, tau_m, f_sat, cycle


def _the_orbit_is_the_simulation(model, params, cycle, t_end_s, units, **motors):
    sim = ax.simulate(
        model, params, t_end_s, units=units, cubic=motors.pop("cubic"), samples_per_period=64,
        rtol=1e-8, atol=1e-11, perturbation_um=motors.pop("perturbation_um"), **motors,
    )  # fmt: skip
    assert sim.state == "limit_cycle", sim.state
    f = float(cycle.frequency_hz(units))
    assert sim.limit_cycle["frequency_hz"] == pytest.approx(f, rel=5e-3)
    assert psi_mismatch(cycle, sim, units, offset=True) < 2e-2
    return sim


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_regulated_orbit_on_a_free_base_is_the_long_simulation(free_row):
    """Sartori et al.'s curvature control (beta'' < 0) with motor kinetics and saturating
    motors on a free base with basal compliance: a simulation from a 1 um bend (0.3 s, 20
    periods; the largest multiplier besides the trivial ones 0.44 a period) settles on the
    orbit: frequency within 0.5 % and psi(s, t) over one period within 2 % (relative L2,
    time shift and constant rigid rotation aligned; measured 2e-7 and 8e-4, the 64 samples
    a period of the simulation limit the latter). psi differs by the rigid rotation
    (arbitrary: the orbit's phase condition sets it, the simulation's start another)."""
    model, params, tau_m, f_sat, cycle = free_row
    assert bool(cycle.stable) and float(cycle.amplitude_um(UNITS)) > 0.3
    sim = _the_orbit_is_the_simulation(
        model, params, cycle, 0.3, UNITS, tau_m=tau_m, f_sat=f_sat, cubic=0.0, perturbation_um=1.0
    )
    assert psi_mismatch(cycle, sim, UNITS, offset=False) > 0.1  # the rigid rotation differs


def test_the_trivial_multipliers_are_set_apart(free_row):
    """One multiplier per rigid motion (a translation and a rotation in the plane) and the
    time shift's are 1 (to 1e-8) and named apart; stability is read from the others, which
    lie inside the unit circle. The drift is 0 to rounding (beside the beat's speed)."""
    model, _, _, _, cycle = free_row
    assert cycle.n_rigid == 2 == np.asarray(cycle.rigid_floquet).shape[0]
    trivial = np.asarray(cycle.trivial_multipliers)
    assert trivial.shape == (3,) and np.abs(trivial - 1).max() < 1e-8
    others = np.asarray(cycle.stability_multipliers)
    others = others[np.isfinite(others)]
    assert others.size >= 3 and np.abs(others).max() < 0.6
    assert np.abs(np.asarray(cycle.floquet)[np.isfinite(cycle.floquet)] - 1).min() < 1e-8
    assert bool(cycle.stable) and cycle.result == RESULTS.successful
    speed = float(cycle.omega) * np.abs(np.asarray(cycle.coefficients)[1:]).max()
    assert np.abs(np.asarray(cycle.rigid_drift)).max() < 1e-12 * speed
    doc = cycle.to_json(UNITS)
    assert len(doc["rigid_floquet"]) == 2 and len(doc["rigid_drift"]) == 2


def test_the_phase_conditions_fix_the_rigid_offset(free_row):
    """The mean state has no rigid coordinates, (Z^T C Z)^-1 Z^T C c_0 = 0 with Z built
    here and C the drag without the motors' friction; an orbit moved by a rigid motion
    (q and the motors' copy y alike: a rigid motion is no sliding) is the same orbit, and
    Newton from it returns the orbit at its gauge."""
    model, params, tau_m, f_sat, cycle = free_row
    Z = rigid_modes(model)
    C = np.asarray(ax.assemble(model, params.replace(chi_im=0.0, beta_im=0.0)).C)
    c0 = np.asarray(cycle.q_coefficients)[0]
    coords = np.linalg.solve(Z.T @ C @ Z, Z.T @ C @ c0)
    assert np.abs(coords).max() < 1e-10 * np.abs(c0).max()
    moved = np.asarray(cycle.coefficients).copy()
    shift = Z @ np.array([0.05, -0.1])
    moved[0] += np.concatenate([shift, shift])
    start = eqx.tree_at(lambda c: c.coefficients, cycle, jnp.asarray(moved))
    again = ax.limit_cycle(model, params, 0.0, tau_m=tau_m, f_sat=f_sat, solver=SOLVER, start=start)
    assert bool(again.converged) and int(again.steps) <= 3
    np.testing.assert_allclose(
        np.asarray(again.coefficients),
        np.asarray(cycle.coefficients),
        atol=1e-9 * np.abs(moved).max(),
    )


STEADY_HEAD = Base("head", translational_drag=10.0, rotational_drag=10.0)
"""A head of drags 10 c_n L and 10 c_n L^3: the seven-filament steady load flutters there
(Hopf point of the bent equilibrium p = 256.8, 117 /tau), where on a free base it diverges
(tests/model/test_moment_balance.py)."""


@pytest.mark.slow  # an orbit and a simulation of the seven-filament model: about a minute
def test_the_steady_load_orbit_on_a_head_base_is_the_long_simulation():
    """The paper's steady load, seven filaments with a head, 5 % past the Hopf point (23.5
    Hz, tip 3.3 um): four rigid motions (a translation and a rotation in y and z), their
    four multipliers 1 and the phase's, no drift; a simulation from a 2 um bend (1 s,
    23 periods) settles on the orbit (measured: frequency 1.5e-5, psi 9e-4)."""
    model = ax.models.seven(n_elements=4, base=STEADY_HEAD)
    params = ax.Params(p=1.05 * 256.7966)
    cycle = ax.limit_cycle(model, params, 10.0, solver=SOLVER, throw=True)
    assert bool(cycle.stable) and cycle.n_rigid == 4
    assert np.abs(np.asarray(cycle.trivial_multipliers) - 1).max() < 1e-8
    speed = float(cycle.omega) * np.abs(np.asarray(cycle.coefficients)[1:]).max()
    assert np.abs(np.asarray(cycle.rigid_drift)).max() < 1e-10 * speed
    _the_orbit_is_the_simulation(
        model, params, cycle, 1.0, ax.Units(), cubic=10.0, perturbation_um=2.0
    )


@pytest.mark.slow  # a second regulated model compiled, and its simulation: about a minute
def test_the_regulated_orbit_on_a_head_base_is_the_long_simulation():
    """The regulated row of the free-base test on a head (drags 1 c_n L, 0.2 c_n L^3) with
    basal compliance: the orbit is the simulation's cycle (frequency 0.5 %, psi 2 %;
    measured 2.4e-6 and 8e-4)."""
    model, params, tau_m, f_sat = regulated_row(Base("head", True, 1.0, 0.2), 1.1)
    cycle = ax.limit_cycle(model, params, 0.0, tau_m=tau_m, f_sat=f_sat, solver=SOLVER, throw=True)
    assert bool(cycle.stable) and np.abs(np.asarray(cycle.trivial_multipliers) - 1).max() < 1e-8
    _the_orbit_is_the_simulation(
        model, params, cycle, 0.3, UNITS, tau_m=tau_m, f_sat=f_sat, cubic=0.0, perturbation_um=1.0
    )


def test_a_load_with_a_net_moment_drifts_and_is_refused():
    """The two-filament steady load's static couple b has a net moment (docs/model.md
    section 8, tests/model/test_moment_balance.py): on a head base (flutter at p = 160) the
    bordered Newton system converges to a beat that turns at a constant rate, the drift
    it solves for. That is no periodic orbit: ``rigid_drift`` holds the rate, the result
    says why, and ``throw=True`` raises one line. The drift equals the load's
    (Z^T C Z)^-1 Z^T (b - A c_0) computed here (the mean's balance)."""
    model = ax.models.two(n_elements=4, base=Base("head", False, 10.0, 10.0))
    params = ax.Params(p=160.0)
    cycle = ax.limit_cycle(model, params, 10.0, solver=SOLVER)
    assert not bool(cycle.converged) and cycle.result == RESULTS.rigid_drift
    s = ax.assemble(model, params)
    A, C, b = (np.asarray(v) for v in (s.A, s.C, s.b))
    Z = rigid_modes(model)
    c0 = np.asarray(cycle.coefficients)[0]
    expected = np.linalg.solve(Z.T @ C @ Z, Z.T @ (b - A @ c0))  # Z^T f_nl = 0: links are internal
    np.testing.assert_allclose(np.asarray(cycle.rigid_drift), expected, rtol=1e-8)
    assert abs(expected[1]) > 0.1  # it turns: 0.13 rad per tau
    with pytest.raises(ValueError, match="drifts") as info:
        ax.limit_cycle(model, params, 10.0, solver=SOLVER, throw=True)
    assert "\n" not in str(info.value) and "head base" in str(info.value)


def test_the_steady_load_on_a_free_base_diverges_and_is_refused():
    """On a free base the two-filament steady load's dominant mode is a divergence (a real
    eigenvalue; the net moment of its linearised forces, tests/model/test_moment_balance.py):
    no beat, and one line says so."""
    model = ax.models.two(n_elements=4, base="free")
    with pytest.raises(ValueError, match="does not oscillate"):
        ax.limit_cycle(model, ax.Params(p=200.0), 10.0, solver=SOLVER, throw=True)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_orbit_is_differentiable_on_a_free_base(free_row):
    """d(frequency)/d(beta'', tau_m) through the bordered Newton system (implicit function
    theorem; the phase conditions depend on the drag, the drift column too) equal central
    finite differences (1e-5)."""
    from axojax.orbits import Motors

    model, params, tau_m, f_sat, _ = free_row
    solver = HarmonicBalance(harmonics=6, floquet=0)

    def freq(v):
        prm = params.replace(beta_im=v[0])
        motors = Motors(tau_m=v[1], f_sat=jnp.asarray(f_sat))
        return solver.solve(model, prm, jnp.asarray(0.0), None, motors).omega

    v0 = jnp.array([float(params.beta_im), tau_m])
    f = jax.jit(freq)
    grad = np.asarray(jax.jit(jax.grad(freq))(v0))
    for i in range(2):
        h = 1e-5 * abs(float(v0[i]))
        e = jnp.zeros(2).at[i].set(h)
        fd = (float(f(v0 + e)) - float(f(v0 - e))) / (2 * h)
        assert abs(grad[i] - fd) <= 1e-5 * abs(fd), (i, grad[i], fd)


def test_axojax_orbit_on_a_head_base(capsys):
    """``axojax orbit --base head --head-drag``: the library's orbit (frequency, tip
    amplitude: the seven-filament steady load of the slow test above), its four rigid
    motions' multipliers and drift in the JSON, and a line saying they are set apart."""
    import json

    from axojax.cli.main import main

    units = ax.Units()
    cl = (
        units.cn_pn_s_um2 * units.length_um
    )  # drags of 10 c_n L and 10 c_n L^3, in pN s/um, pN um s
    drag = f"{10 * cl!r},{10 * cl * units.length_um**2!r}"
    p = 1.05 * 256.7966
    argv = ["orbit", "--model", "seven", "--elements", "4", "--base", "head", "--head-drag", drag]
    argv += ["--p", repr(p), "--harmonics", "6"]
    assert main([*argv, "--json"]) == 0
    (orbit,) = json.loads(capsys.readouterr().out)["orbits"]
    cycle = ax.limit_cycle(
        ax.models.seven(n_elements=4, base=STEADY_HEAD), ax.Params(p=p), 10.0, solver=SOLVER
    )
    assert orbit["frequency_hz"] == pytest.approx(float(cycle.frequency_hz()), rel=1e-8)
    assert orbit["tip_amplitude_um"] == pytest.approx(float(cycle.amplitude_um()), rel=1e-8)
    assert orbit["stable"] is True and len(orbit["rigid_floquet"]) == 4
    assert max(abs(complex(*r) - 1) for r in orbit["rigid_floquet"]) < 1e-8
    assert max(abs(v) for v in orbit["rigid_drift"]) < 1e-9
    assert main(argv) == 0
    assert "rigid motions of the base: 4 trivial multipliers" in capsys.readouterr().out
