"""Limit cycles as first-class objects (issue 15): the periodic orbit computed directly
(harmonic balance + Newton) against a long simulation, its Floquet multipliers against a
scipy monodromy matrix, derivatives against finite differences, a fit to limit-cycle
targets, the branch in p and bad input."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.integrate

import axojax as ax
from axojax.beats import Target
from axojax.cli.main import main
from axojax.dynamics.nonlinear import cubic_link_force
from axojax.models import Base
from axojax.orbits import HarmonicBalance
from axojax.orbits.branch import Branch, hopf_point
from axojax.waveform import fourier_modes
from axojax.waveform import measures as wm

KAPPA = 10.0
SOLVER = HarmonicBalance(harmonics=8)


@pytest.fixture(scope="module")
def two4():
    return ax.models.two(n_elements=4)


@pytest.fixture(scope="module")
def p_hopf(two4):
    """Hopf point of the (statically bent) equilibrium of two filaments."""
    p_h, lam = hopf_point(two4, ax.Params(), KAPPA)
    assert abs(lam.real) < 1e-6 * abs(lam.imag)
    return p_h


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "base, tol",
    [
        ("clamped", 1e-4),
        (Base("clamped", compliance=True), 1e-4),
        (Base("pivot", rotational_stiffness=2.0), 3e-3),
    ],
    ids=["clamped", "compliant", "pivot-spring"],
)
def test_orbit_equals_long_simulation(base, tol):
    """Frequency (to 1e-4), tip amplitude, period, Fourier measures and wavelength (to ``tol``) of the
    orbit equal those of a long ax.simulate run at 1.04 p_c (transients decay by 0.2 a
    period on the clamped base). Bases with unknowns of their own that still hold the
    axoneme (basal sliding; a pivot's slope on a spring): the orbit is one dense block,
    both in the body frame; the pivot's 3.3 Hz beat runs 5 periods in the 1.5 s, its
    transient not gone: 3e-3 there."""
    model = ax.models.two(n_elements=4, base=base)
    start = ax.Params(kb=50.0, xib=0.5)  # the basal spring and friction where there is one
    params = start.replace(p=1.04 * float(ax.critical_force(model, start).p))
    cycle = ax.limit_cycle(model, params, KAPPA, solver=SOLVER)
    assert bool(cycle.converged)
    sim = ax.simulate(
        model, params, 1.5, cubic=KAPPA, samples_per_period=1000, rtol=1e-9, atol=1e-12
    )
    assert sim.state == "limit_cycle"
    lc = sim.limit_cycle
    assert abs(float(cycle.frequency_hz()) / lc["frequency_hz"] - 1) < 1e-4
    assert abs(float(cycle.amplitude_um()) / lc["tip_amplitude_um"] - 1) < tol
    assert abs(float(cycle.period_s()) / lc["period_s"] - 1) < 1e-4
    # The waveform's static and first Fourier modes over the simulation's last 5 periods.
    P = lc["period_s"]
    late = sim.t_s >= sim.t_s[-1] - 5 * P - 1e-6 * P
    fm = fourier_modes(sim.t_s[late], sim.x_um, sim.psi_rad[late], P)
    rep = cycle.to_json()
    assert abs(rep["static_curvature_rad_per_um"] / fm.static_curvature - 1) < tol
    assert abs(rep["dynamic_amplitude_rad"] / fm.dynamic_amplitude - 1) < tol
    # One wavelength: the orbit's (from its psi_1) is the simulation's (from its psi, both
    # in the lab frame; on the pivot the body frame's psi gave 427 against 56 um). Sampled
    # at the simulation's 41 points, the orbit's psi_1 gives the simulation's wavelength;
    # the exact form (Gauss points) differs from that sampling by its discretisation
    # (5.6e-3 on the clamped base: the phase slope weights every point alike, and 41
    # samples resolve the quick turn where |psi_1| is small less well).
    psi1 = np.asarray(ax.orbits.cycle_measures(cycle, np.asarray(sim.x_um)).psi1)
    sampled = float(wm.wavelength(wm.sampled_wavenumber(np.asarray(sim.x_um), psi1)))
    assert abs(sampled / lc["wavelength_um"] - 1) < 2e-3, (sampled, lc["wavelength_um"])
    assert abs(rep["wavelength_um"] / sampled - 1) < 1e-2, (rep["wavelength_um"], sampled)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_floquet_multipliers_past_hopf(two4, p_hopf):
    """Just past the Hopf point on the supercritical branch: one multiplier is 1 (the
    phase), the others lie inside the unit circle and equal the eigenvalues of the
    monodromy matrix from scipy's Radau integration of the variational equations."""
    params = ax.Params(p=1.01 * p_hopf)
    cycle = ax.limit_cycle(two4, params, KAPPA, solver=SOLVER)
    rho = np.asarray(cycle.floquet)
    rho = rho[np.isfinite(rho)]
    trivial = np.argmin(np.abs(rho - 1))
    assert abs(rho[trivial] - 1) < 1e-8
    others = np.delete(rho, trivial)
    assert others.size >= 1 and np.all(np.abs(others) < 1)
    assert bool(cycle.stable)

    s = ax.assemble(two4, params)
    A, C, b = (np.asarray(v) for v in (s.A, s.C, s.b))
    Ci = np.linalg.inv(C)
    f = jax.jit(lambda q: cubic_link_force(two4, params, KAPPA, q))
    Jf = jax.jit(jax.jacfwd(lambda q: cubic_link_force(two4, params, KAPPA, q)))
    n = two4.n_dof

    def rhs(t, z):
        q, Phi = z[:n], z[n:].reshape(n, n)
        return np.concatenate(
            [Ci @ (b - A @ q - np.asarray(f(q))), (-Ci @ (A + np.asarray(Jf(q))) @ Phi).ravel()]
        )

    q0 = cycle.states(1)[1][0]
    sol = scipy.integrate.solve_ivp(
        rhs,
        (0, float(cycle.period)),
        np.concatenate([q0, np.eye(n).ravel()]),
        method="Radau",
        rtol=1e-10,
        atol=1e-12,
    )
    assert np.abs(sol.y[:n, -1] - q0).max() < 1e-5 * np.abs(q0).max()  # the orbit closes
    ref = np.linalg.eigvals(sol.y[n:, -1].reshape(n, n))
    ref = ref[np.argsort(-np.abs(ref))]
    assert abs(ref[0] - 1) < 1e-5
    assert 0.3 < abs(ref[1]) < 1  # slow decay just past the Hopf point
    assert abs(np.sort(np.abs(others))[-1] - abs(ref[1])) < 1e-5


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_derivatives_match_finite_differences():
    """d(frequency)/d(p, ks, cl) by the implicit function theorem (forward and reverse
    mode) equal central finite differences to 1e-5."""
    model = ax.models.seven(n_elements=3)
    solver = HarmonicBalance(harmonics=6, floquet=0)
    base = ax.Params(p=280.0)

    def freq(v):
        return solver.solve(model, base.replace(p=v[0], ks=v[1], cl=v[2]), KAPPA).frequency_hz()

    v0 = jnp.array([280.0, 1e6, 0.005])
    f = jax.jit(freq)
    grad = np.asarray(jax.jit(jax.grad(freq))(v0))
    for i in range(3):
        h = 1e-4 * float(v0[i])
        e = jnp.zeros(3).at[i].set(h)
        fd = (float(f(v0 + e)) - float(f(v0 - e))) / (2 * h)
        assert abs(grad[i] - fd) <= 1e-5 * abs(fd), (i, grad[i], fd)


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_fit_recovers_parameters_from_limit_cycle(two4):
    """A fit of p and cl to a limit cycle's frequency and tip amplitude recovers them."""
    true = ax.Params(p=160.0, cl=0.005)
    cycle = ax.limit_cycle(two4, true, KAPPA, solver=SOLVER)
    f, a = float(cycle.frequency_hz()), float(cycle.amplitude_um())
    targets = [
        Target("frequency_hz", f, 1e-3 * f, source="limit_cycle"),
        Target("amplitude_um", a, 1e-3 * a, source="limit_cycle"),
    ]

    def fit(**method):
        start = ax.Params(p=175.0, cl=0.004)
        return ax.fit(
            two4, start, targets, ["p", "cl"], starts=1, cubic=KAPPA, orbit_solver=SOLVER, **method
        )

    res = fit()
    assert res.targets_met
    assert abs(res.achieved["limit_cycle_frequency_hz"] - f) <= 0.5 * 1e-3 * f
    # Fits with limit-cycle targets stop once the Gauss-Newton step is within 0.3
    # standard errors: each value that close to the truth (cl's is 50 %: the beat's
    # frequency and amplitude hardly see it).
    for name, truth in (("p", 160.0), ("cl", 0.005)):
        assert abs(res.params[name] - truth) <= 0.5 * res.stderr[name], name
    # With that rule off, optimistix's own termination: exact Jacobians of the orbit
    # carry the fit down cl's flat direction to the truth.
    exact = fit(method=ax.inverse.LevenbergMarquardt(standard_errors=0.0))
    assert abs(exact.params["p"] / 160.0 - 1) < 1e-4
    assert abs(exact.params["cl"] / 0.005 - 1) < 1e-4
    assert abs(exact.achieved["limit_cycle_frequency_hz"] / f - 1) < 1e-6


def test_branch_cli(two4, p_hopf, tmp_path, capsys):
    """`axojax orbit --p a:b:n`: the branch from the Hopf point, amplitude rising with p
    (supercritical), stable, saved and plotted."""
    out, fig = tmp_path / "branch.npz", tmp_path / "branch.png"
    code = main(
        [
            "orbit",
            "--model",
            "two",
            "--elements",
            "4",
            "--p",
            "140:200:4",
            "--harmonics",
            "8",
            "--json",
            "--out",
            str(out),
            "--plot",
            str(fig),
        ]
    )
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert abs(doc["hopf"]["p"] / p_hopf - 1) < 1e-8
    assert doc["missing"] == [140.0]  # below the Hopf point
    orbits = doc["orbits"]
    assert [o["p"] for o in orbits] == [160.0, 180.0, 200.0]
    amp = [o["tip_amplitude_um"] for o in orbits]
    assert amp == sorted(amp) and all(o["stable"] for o in orbits)
    arrays, meta = Branch.load(out)
    assert meta["kind"] == "orbit_branch" and np.isnan(arrays["frequency_hz"][0])
    assert np.allclose(arrays["tip_amplitude_um"][1:], amp)
    assert fig.stat().st_size > 10_000
    replot = tmp_path / "replot.png"
    assert main(["plot", str(out), "--out", str(replot), "--json"]) == 0
    assert (
        json.loads(capsys.readouterr().out)["kind"] == "orbit_branch"
        and replot.stat().st_size > 10_000
    )


def test_bad_input_one_line(two4, p_hopf, capsys):
    with pytest.raises(ValueError, match="equilibrium is linearly stable"):  # throw: default False
        ax.limit_cycle(two4, ax.Params(p=0.9 * p_hopf), KAPPA, solver=SOLVER, throw=True)
    with pytest.raises(ValueError, match="kappa must be"):
        ax.limit_cycle(two4, ax.Params(p=160.0), 0.0)
    with pytest.raises(ValueError, match="has no links"):
        ax.limit_cycle(ax.models.single(n_elements=4), ax.Params(p=100.0), KAPPA)
    with pytest.raises(ValueError, match="harmonics"):
        HarmonicBalance(harmonics=0)
    with pytest.raises(ValueError, match="source"):
        Target("frequency_hz", 10.0, 1.0, source="cycle")
    with pytest.raises(ValueError, match="amplitude_um"):
        Target("amplitude_um", 10.0, 1.0)  # the amplitude is a limit-cycle target only
    for argv, flag in (
        (["orbit", "--model", "two", "--cubic", "0"], "--cubic"),
        (["orbit", "--model", "two", "--ks", "1:2:3"], "--ks"),
        (["orbit", "--model", "single"], "--model"),
        (["fit", "--model", "two", "--free", "p", "--target-amplitude", "3"], "--target-amplitude"),
        (
            [
                "fit",
                "--model",
                "two",
                "--free",
                "p",
                "--target",
                "limit-cycle",
                "--target-frequency",
                "20",
                "--marginal",
                "1",
            ],
            "--marginal",
        ),
    ):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"axojax: error: {flag}") and "\n" not in err


def test_warm_start_and_its_fallback_in_one_newton_loop(two4):
    """WarmStart (one compiled program, warm_steps=1): from the orbit itself, one Newton
    step; from a nearby orbit that one step cannot finish, the Hopf-guess solve follows
    in the same loop, and its answer and steps are exactly the cold solve's, plus one."""
    solver = HarmonicBalance(harmonics=6, floquet=0)
    prm = ax.Params(p=160.0)
    cold = ax.limit_cycle(two4, prm, KAPPA, solver=solver)
    near = ax.limit_cycle(two4, ax.Params(p=160.3), KAPPA, solver=solver)
    warm_solve = jax.jit(
        lambda params, start: ax.orbits.WarmStart(solver, warm_steps=1).solve(
            two4, params, KAPPA, start
        )
    )
    warm, fell_back = warm_solve(prm, cold), warm_solve(prm, near)
    assert bool(cold.converged) and bool(warm.converged) and bool(fell_back.converged)
    assert int(warm.steps) == 1 < int(cold.steps)
    assert float(warm.frequency_hz()) == pytest.approx(float(cold.frequency_hz()), rel=1e-9)
    assert float(warm.amplitude_um()) == pytest.approx(float(cold.amplitude_um()), rel=1e-8)
    assert int(fell_back.steps) == int(cold.steps) + 1
    assert float(fell_back.frequency_hz()) == pytest.approx(float(cold.frequency_hz()), rel=1e-12)
    np.testing.assert_allclose(
        np.asarray(fell_back.phase_ref), np.asarray(cold.phase_ref)
    )  # the Hopf guess's phase condition
