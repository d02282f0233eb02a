"""Time-domain beating (issues 6, 15): linear growth matches the eigenvalue, a
supercritical limit cycle just past the Hopf point, decay, divergence, the static bend of
an imbalance, gradients through the solver, the exact Jacobian of the implicit solver
against autodiff and the trajectory against scipy's Radau, solver failures reported as
such, files and the command line."""

import json
import math
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.dynamics import integrate
from axojax.dynamics.integrate import vector_field
from axojax.dynamics.nonlinear import cubic_link_force, cubic_link_tangent
from axojax.dynamics.simulate import tip_deflection
from axojax.waveform import detect_cycles
from axojax.waveform.shapes import centreline


@pytest.fixture(scope="module")
def seven6():
    """Seven filaments on 6 elements: the same physics as 10, a quarter of the solver cost."""
    return ax.models.seven(n_elements=6)


@pytest.fixture(scope="module")
def hopf6(seven6):
    c = ax.critical_force(seven6, ax.Params())
    return float(c.p), float(c.frequency_hz())


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_linear_growth_and_frequency_match_dominant_eigenvalue(seven):
    pc = float(ax.critical_force(seven, ax.Params()).p)
    params = ax.Params(p=1.04 * pc)
    sim = ax.simulate(seven, params, 0.3, cubic=0.0)
    mode = ax.dominant_mode(seven, params)
    cyc = detect_cycles(sim.t_s, sim.tip_beat_um)
    assert cyc.count >= 5
    # Late cycles: the decaying modes excited by the initial bend are gone.
    growth = np.log(cyc.amplitudes[-1] / cyc.amplitudes[-4]) / (cyc.starts[-1] - cyc.starts[-4])
    freq = 3 / (cyc.starts[-1] - cyc.starts[-4])
    assert sim.state == "growing"
    assert growth == pytest.approx(float(mode.growth_rate_per_s()), rel=0.01)
    assert freq == pytest.approx(float(mode.frequency_hz()), rel=0.01)


@pytest.mark.slow
def test_limit_cycle_just_past_hopf_is_supercritical(seven6, hopf6, capsys):
    pc, f_hopf = hopf6
    out = {}
    for factor in (1.02, 1.04):
        params = ax.Params(p=factor * pc)
        sim = ax.simulate(seven6, params, 0.45, perturbation_um=2.5)
        assert sim.state == "limit_cycle", factor
        out[factor] = (sim.limit_cycle, float(ax.dominant_mode(seven6, params).frequency_hz()))
    with capsys.disabled():
        for factor, (lc, f_lin) in out.items():
            print(
                f"\np = {factor} p_c: limit cycle {lc['frequency_hz']:.3f} Hz, tip amplitude "
                f"{lc['tip_amplitude_um']:.3f} um; "
                f"linear: Im(lambda)/2pi at this p {f_lin:.3f} Hz, at the Hopf point {f_hopf:.3f} Hz"
            )
    lc4, f_lin4 = out[1.04]
    lc2, f_lin2 = out[1.02]
    # Onset frequency: near a Hopf point the cycle's frequency moves linearly with
    # p - p_c (normal form), so the two frequencies extrapolate to the linear prediction
    # at the bifurcation (at 1.04 p_c itself the beat is already 6 % above it).
    f_onset = lc2["frequency_hz"] - (lc4["frequency_hz"] - lc2["frequency_hz"]) * (1.02 - 1.0) / (
        1.04 - 1.02
    )
    with capsys.disabled():
        print(
            f"limit-cycle frequency extrapolates to {f_onset:.3f} Hz at p_c (Hopf frequency {f_hopf:.3f} Hz)"
        )
    assert abs(f_onset - f_hopf) / f_hopf < 0.02
    # Close to the boundary the beat tracks the eigenvalue at its own p, too.
    assert abs(lc2["frequency_hz"] - f_lin2) / f_lin2 < 0.05
    # Supercritical Hopf: amplitude^2 grows linearly from zero at p_c. Extrapolating the
    # two amplitudes^2 to zero must land on the Hopf point (a subcritical branch would
    # carry a finite amplitude there and extrapolate far below it).
    a2, a4 = lc2["tip_amplitude_um"] ** 2, lc4["tip_amplitude_um"] ** 2
    assert a4 > a2 > 0
    p_zero = 1.02 - a2 * (1.04 - 1.02) / (a4 - a2)
    with capsys.disabled():
        print(f"amplitude^2 extrapolates to zero at p = {p_zero:.4f} p_c")
    assert abs(p_zero - 1.0) < 0.015


def test_stable_point_decays_to_straight(seven6, hopf6):
    sim = ax.simulate(seven6, ax.Params(p=0.9 * hopf6[0]), 0.3)
    assert sim.state == "decaying"
    assert sim.limit_cycle is None
    assert np.abs(sim.tip_um[-1]).max() < 0.01 * sim.meta["perturbation_um"]


def test_divergent_point_is_reported_not_beating(seven6):
    params = ax.Params(p=300.0, gamma=0.5)  # dominant eigenvalue real and positive
    assert ax.dominant_mode(seven6, params).classification == 2
    sim = ax.simulate(seven6, params, 0.05, cubic=0.0)
    assert sim.state == "divergent"
    assert sim.limit_cycle is None
    # Physics, not numerics: the solver reached the end.
    assert sim.meta["solver"]["ok"] and sim.reason is None
    assert sim.t_s[-1] == pytest.approx(0.05)


def test_solver_failure_is_reported_as_such():
    """A step budget far too small for the run: the solver stops early, and the result says
    so (state, diffrax's reason on one line, the time reached) instead of calling it
    physics. The record ends where the solver stopped."""
    model = ax.models.two(n_elements=4)
    sim = ax.simulate(model, ax.Params(p=300.0), 0.05, cubic=10.0, max_steps=50)  # it needs ~4500
    assert sim.state == "solver_failed"
    assert sim.limit_cycle is None
    solver = sim.meta["solver"]
    assert not solver["ok"] and solver["steps"] + solver["rejected"] == 50
    assert 0.0 < solver["t_reached_s"] < 0.05
    assert np.all(np.isfinite(sim.tip_um)) and sim.t_s[-1] <= solver["t_reached_s"]
    reason = sim.reason
    assert "\n" not in reason and "maximum number of solver steps" in reason.lower()
    assert f"{solver['t_reached_s']:.4g} s" in reason
    assert sim.to_json()["reason"] == reason


def test_tangent_stiffness_is_the_exact_jacobian():
    """The implicit solver's Jacobian of f_nl (a sum of rank-one terms at the quadrature
    points) equals autodiff's, including a non-uniform link-stiffness profile."""
    model = ax.models.seven(n_elements=4)
    params = ax.Params(p=200.0, ks=3e3, kl=50.0)
    q = jnp.asarray(np.random.default_rng(0).normal(size=model.n_dof) * 0.05)
    K = cubic_link_tangent(model, params, 7.0, q)
    J = jax.jacfwd(lambda x: cubic_link_force(model, params, 7.0, x))(q)
    np.testing.assert_allclose(K, J, rtol=1e-12, atol=1e-12 * float(jnp.abs(J).max()))
    np.testing.assert_allclose(K, K.T, rtol=1e-12, atol=1e-12 * float(jnp.abs(J).max()))


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_trajectory_matches_scipy_radau():
    """The same ODE integrated by scipy's Radau (its own step control and Newton
    iteration, autodiff Jacobian) lands on the same state: growth into the cubic
    saturation of the two-filament model."""
    import scipy.integrate

    model = ax.models.two(n_elements=4)
    params = ax.Params(p=300.0)
    q0 = 0.02 * tip_deflection(model)
    t_end = 0.01
    traj = integrate(
        model, params, 30.0, jnp.asarray(q0), jnp.array([0.0, t_end]), rtol=1e-9, atol=1e-12
    )
    assert bool(traj.ok)
    f = vector_field(model, params, 30.0)
    fun = jax.jit(lambda q: f(0.0, q, None))
    jac = jax.jit(jax.jacfwd(lambda q: f(0.0, q, None)))
    ref = scipy.integrate.solve_ivp(
        lambda t, q: np.asarray(fun(q)),
        (0.0, t_end),
        q0,
        method="Radau",
        jac=lambda t, q: np.asarray(jac(q)),
        rtol=1e-10,
        atol=1e-13,
    )
    assert ref.success
    q_ref = ref.y[:, -1]
    assert np.abs(q_ref).max() > 5 * np.abs(q0).max()  # it grew: the cubic term matters
    np.testing.assert_allclose(
        np.asarray(traj.q[-1]), q_ref, rtol=0, atol=1e-8 * np.abs(q_ref).max()
    )  # measured: 3e-11


def test_imbalance_bends_to_the_static_solution(seven6):
    """A stable point with unequal dynein groups settles on A q = b (independent numpy
    solve), the static moment bending the axoneme."""
    params = ax.Params(p=150.0, imbalance=5.0)
    sim = ax.simulate(seven6, params, 0.6, cubic=0.0)  # slowest decay 17/s: e^-10 left
    s = ax.assemble(seven6, params)
    q_eq = np.linalg.solve(np.asarray(s.A), np.asarray(s.b))
    tip_eq = centreline(seven6, q_eq, np.array([1.0]))[:, 0] * 12.0
    assert np.abs(tip_eq).max() > 0.1  # a visible bend, in um
    np.testing.assert_allclose(sim.tip_um[-1], tip_eq, rtol=1e-3, atol=1e-6)


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_solver_is_differentiable():
    """Reverse mode through the implicit integration (two filaments, 4 elements: what is
    checked is the solver's derivative, not the model's size)."""
    model = ax.models.two(n_elements=4)
    t = jnp.linspace(0.0, 0.005, 2)
    q0 = jnp.asarray(0.05 * tip_deflection(model))

    @jax.jit
    def tip_end(p):
        traj = integrate(model, ax.Params(p=p), 10.0, q0, t, rtol=1e-9, atol=1e-12)
        return traj.q[-1] @ q0

    g = jax.jit(jax.grad(tip_end))(170.0)
    h = 1e-3
    fd = (tip_end(170.0 + h) - tip_end(170.0 - h)) / (2 * h)
    assert abs(float(fd)) > 1e-6 * abs(float(tip_end(170.0)))  # p moves the tip
    assert float(g) == pytest.approx(float(fd), rel=1e-4)


def test_bad_simulation_input_is_one_line_error(seven6):
    with pytest.raises(ValueError, match="t_end_s"):
        ax.simulate(seven6, ax.Params(), -1.0)
    with pytest.raises(ValueError, match="cubic"):
        ax.simulate(ax.models.single(), ax.Params(), 0.1, cubic=1.0)
    # refused before any work (found by a probe: these ran 10-20k steps or raised from
    # numpy/diffrax)
    for kwargs, match in [
        (dict(atol=float("nan")), "atol must be a finite number > 0, got nan"),
        (dict(rtol=1e-300), "rtol must be in \\[1e-12, 0.1\\]"),
        (dict(n_points=0), "n_points must be an integer >= 2"),
        (dict(max_steps=0), "max_steps must be an integer >= 1"),
    ]:
        with pytest.raises(ValueError, match=match):
            ax.simulate(seven6, ax.Params(), 0.01, **kwargs)
    with pytest.raises(ValueError, match="t_end_s must be at least 1e-09 s"):
        ax.simulate(seven6, ax.Params(), 1e-300)


@pytest.mark.slow
def test_cli_simulate_json_file_and_plot(tmp_path, hopf6, capsys):
    from axojax.cli.main import main

    out, fig, gif = tmp_path / "sim.npz", tmp_path / "sim.png", tmp_path / "sim.gif"
    cmd = [
        sys.executable,
        "-m",
        "axojax.cli.main",
        "simulate",
        "--model",
        "seven",
        "--elements",
        "6",
        "--p",
        str(1.04 * hopf6[0]),
        "--t-end",
        "0.35",
        "--perturbation-um",
        "3",
        "--out",
        str(out),
        "--gif",
        str(gif),
        "--json",
    ]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert set(doc["limit_cycle"]) == {"frequency_hz", "tip_amplitude_um", "period_s"}
    assert set(doc["linear"]) >= {"frequency_hz", "growth_rate_per_s"}
    assert math.isclose(
        doc["limit_cycle"]["period_s"] * doc["limit_cycle"]["frequency_hz"], 1.0, rel_tol=1e-9
    )
    sim = ax.Simulation.load(out)
    assert (
        sim.state == "limit_cycle"
        and sim.limit_cycle["frequency_hz"] == doc["limit_cycle"]["frequency_hz"]
    )
    assert gif.stat().st_size > 0
    assert (
        main(["plot", str(out), "--out", str(fig)]) == 0
    )  # in this process: the file is what is checked
    assert fig.stat().st_size > 0
    # a bad flag ends before any work: main() in this process (the exit status of a
    # process is tests/house/test_error_messages.py::test_console_script_exit_status)
    assert main(["simulate", "--t-end", "-2"]) == 2
    err = capsys.readouterr().err
    assert "--t-end" in err and len(err.strip().splitlines()) == 1


def test_cli_reports_solver_failure_on_one_line(capsys):
    from axojax.cli.main import main
    from axojax.cli.simulate import render

    base = [
        sys.executable,
        "-m",
        "axojax.cli.main",
        "simulate",
        "--model",
        "two",
        "--elements",
        "4",
        "--p",
        "300",
        "--t-end",
        "0.05",
        "--max-steps",
        "50",
    ]
    r = subprocess.run(base + ["--json"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert doc["state"] == "solver_failed" and doc["limit_cycle"] is None
    assert "\n" not in doc["reason"] and "maximum number of solver steps" in doc["reason"].lower()
    assert doc["solver"]["ok"] is False and doc["solver"]["t_reached_s"] < 0.05
    assert (
        doc["solver"]["reason"] == doc["reason"]
    )  # docs/interface.md: {"ok": false, "reason": ...}
    # The text output (same document) leads with the state and that reason.
    assert render(doc).splitlines()[0] == f"state: solver_failed: {doc['reason']}"
    assert main(base[3:-1] + ["0"]) == 2  # in this process, as above
    err = capsys.readouterr().err
    assert "--max-steps" in err and len(err.strip().splitlines()) == 1
