"""Regulated beats in time with motor kinetics (issue 47 items 1 and 3): ``ax.simulate`` /
``axojax simulate --motor-tau-ms`` integrate the augmented system of
:mod:`axojax.dynamics.motors`, where without motor kinetics an active friction is refused;
and saturating motors (item 2, :mod:`axojax.dynamics.saturation`, ``--motor-saturation``).

Every reference is built here from :func:`ax.assemble` alone (the friction-form assembly,
verified against continuum solutions elsewhere) and solved by scipy: the augmented pencil
A' = [[A_inf, M], [-I, I]], C' = [[C_0, 0], [0, tau_m I]] with A_inf, C_0 assembled at
chi = c_inf (real) and M = c_1 dA/dchi' + d_1 dA/dbeta' as the difference of two assemblies
(A is linear in chi' and beta'), never
from :mod:`axojax.assembly.motor_kinetics`.
"""

import json
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.integrate
import scipy.linalg as sl

import axojax as ax
from axojax.dynamics.integrate import integrate
from axojax.dynamics.motors import motor_blocks, motor_order
from axojax.dynamics.nonlinear import cubic_link_force
from axojax.dynamics.simulate import tip_deflection
from axojax.models import Base
from tests.regulation.test_motor_kinetics import SARTORI_BASE, _curvature_row, _hopf, _sliding_row  # noqa: E402
from tests.regulation.test_sartori import UNITS as SARTORI_UNITS  # noqa: E402
from tests.regulation.test_sartori import _params as sartori_params  # noqa: E402

TAU_MS = 5.0
COMPLIANT = Base("clamped", compliance=True)


def _augmented(model, params, tau_m):
    """(A', C', b') of motor kinetics, dense, from ax.assemble only (module docstring)."""
    w = float(params.omega0)
    parts = {}
    for field in ("chi", "beta"):
        re, im = float(getattr(params, f"{field}_re")), float(getattr(params, f"{field}_im"))
        wt = w * tau_m
        parts[field] = (re + im / wt, -im * (1 + wt**2) / wt) if im else (re, 0.0)
    (c_inf, c_1), (d_inf, d_1) = parts["chi"], parts["beta"]
    elastic = ax.assemble(
        model, params.replace(chi_re=c_inf, chi_im=0.0, beta_re=d_inf, beta_im=0.0)
    )
    zero = params.replace(chi_re=0.0, chi_im=0.0, beta_re=0.0, beta_im=0.0)
    M = np.asarray(ax.assemble(model, zero.replace(chi_re=c_1, beta_re=d_1)).A) - np.asarray(
        ax.assemble(model, zero).A
    )  # c_1 dA/dchi' + d_1 dA/dbeta': A is linear in both
    n = model.n_unknowns
    eye, z = np.eye(n), np.zeros((n, n))
    A = np.block([[np.asarray(elastic.A), M], [-eye, eye]])
    C = np.block([[np.asarray(elastic.C), z], [z, tau_m * eye]])
    return A, C, np.concatenate([np.asarray(elastic.b), np.zeros(n)])


def _dominant(A, C):
    """scipy's rightmost finite eigenvalue of (A + lambda C) v = 0."""
    lam = sl.eig(-A, C, right=False)
    lam = lam[np.isfinite(lam)]
    return lam[np.argmax(lam.real)]


def _scaled(params, field, factor, parts=("re", "im")):
    """params with the ``parts`` of the complex coefficient ``field`` scaled by ``factor``
    (past its Hopf point)."""
    return params.replace(
        **{f"{field}_{k}": factor * float(getattr(params, f"{field}_{k}")) for k in parts}
    )


def _sliding_clamped():
    """Clamped two-filament sliding control (chi'' < 0), 10 % past its Hopf point."""
    return ax.models.two(n_elements=8), _scaled(_sliding_row(), "chi", 1.1), ax.Units()


def _curvature_compliant():
    """Sartori et al.'s curvature control (beta'' < 0) on a clamped base with basal
    compliance, moved onto that base's Hopf point, then 5 % past it; their units."""
    model = ax.models.two(n_elements=8, base=COMPLIANT)
    params = sartori_params()
    params = _hopf(model, params, "beta", complex(params.beta_re, params.beta_im))
    return model, _scaled(params, "beta", 1.05), SARTORI_UNITS


def _sliding_compliant():
    """Sliding control (chi'' < 0) on a clamped base with basal compliance, Sartori's base
    and units, at a Hopf point in chi, then chi'' 5 % past it (chi' scaled too would make
    the basal sliding diverge: its spring k_b + c_inf < 0)."""
    model = ax.models.two(n_elements=8, base=COMPLIANT)
    params = sartori_params().replace(beta_im=0.0)
    params = _hopf(model, params, "chi", complex(params.chi_re, -params.chi_re))
    return model, _scaled(params, "chi", 1.05, ("im",)), SARTORI_UNITS


def _curvature_free_compliant():
    """Sartori et al.'s wild-type row on their own base (free, with basal compliance; the
    rigid motions are zero eigenvalues, below the beat), 5 % past its Hopf point."""
    model = ax.models.two(n_elements=8, base=SARTORI_BASE)
    return model, _scaled(_curvature_row(), "beta", 1.05), SARTORI_UNITS


ROWS = {
    "sliding-clamped": _sliding_clamped,
    "curvature-clamped+compliance": _curvature_compliant,
    "sliding-clamped+compliance": _sliding_compliant,
    "curvature-free+compliance": _curvature_free_compliant,
}


def _tau_m(units):
    return TAU_MS * 1e-3 / units.tau_s


@pytest.mark.parametrize("base", [Base("clamped"), COMPLIANT, Base("free", compliance=True)])
def test_the_augmented_matrices_are_block_tridiagonal_in_motor_order(base):
    """What the implicit stages factor is the whole augmented matrix: nothing of A' or C'
    lies outside the node blocks (q then y per node) and the border."""
    model = ax.models.two(n_elements=6, base=base)
    params = _sliding_row().replace(kb=50.0, xib=0.5)
    A, C, _ = _augmented(model, params, 0.01)
    perm = motor_order(model)
    assert sorted(perm) == list(range(2 * model.n_unknowns))
    from axojax.assembly.motor_kinetics import assemble_motor

    s = assemble_motor(model, params, 0.01)
    for ours, ref in ((s.A, A), (s.C, C)):
        np.testing.assert_allclose(
            np.asarray(ours), ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max()
        )
        blocks = np.asarray(motor_blocks(model, ours).to_dense())
        assert np.array_equal(blocks, np.asarray(ours)[perm][:, perm])


def test_an_active_sliding_row_runs_in_time_with_motor_kinetics(tmp_path):
    """(a) A sliding-control row with an active friction (chi'' < 0) at its Hopf point:
    refused without motor kinetics, with tau_m the beat runs (cubic links on), stays
    finite, and says which tau_m it used."""
    model, params, units = ax.models.two(n_elements=8), _sliding_row(), ax.Units()
    assert float(params.chi_im) < 0
    with pytest.raises(ValueError, match="active friction"):
        ax.simulate(model, params, 0.01)
    tau_m = _tau_m(units)
    sim = ax.simulate(model, params, 0.05, tau_m=tau_m, perturbation_um=0.5)
    assert sim.meta["solver"]["ok"] and sim.state != "solver_failed"
    assert np.all(np.isfinite(sim.psi_rad)) and np.all(np.isfinite(sim.tip_um))
    assert np.abs(sim.tip_um).max() < 5.0  # at its Hopf point: no blow-up
    lam = _dominant(*_augmented(model, params, tau_m)[:2])
    assert abs(lam.real) < 1e-6 * abs(lam.imag)  # the Hopf point, kept with the motors
    assert sim.linear["frequency_hz"] == pytest.approx(
        abs(lam.imag) / (2 * math.pi * units.tau_s), rel=1e-8
    )
    doc = sim.to_json()
    assert doc["motor_kinetics"] == {
        "tau_m": pytest.approx(tau_m),
        "tau_ms": pytest.approx(TAU_MS),
        "f_sat": None,
        "f_sat_pn_per_um": None,
    }
    path = tmp_path / "beat.npz"
    sim.save(path)
    assert ax.Simulation.load(path).meta["motor_kinetics"]["tau_ms"] == pytest.approx(TAU_MS)


def _crossings(t, y):
    """Times where y changes sign (linear interpolation)."""
    k = np.nonzero(np.sign(y[:-1]) * np.sign(y[1:]) < 0)[0]
    return t[k] - y[k] * (t[k + 1] - t[k]) / (y[k + 1] - y[k])


def _growth_and_frequency(t, y):
    """(growth rate, frequency) of a late signal y(t) ~ e^{g t} cos(omega t + phi): the
    frequency from the zero crossings' least-squares spacing (half periods), the growth
    rate from the least-squares slope of log |y| at each half period's peak (a parabola
    through the largest sample and its neighbours)."""
    tc = _crossings(t, y)
    half = np.polyfit(np.arange(tc.size), tc, 1)[0]
    peaks_t, peaks_y = [], []
    for a, b in zip(tc[:-1], tc[1:]):
        idx = np.nonzero((t > a) & (t < b))[0]
        k = idx[np.argmax(np.abs(y[idx]))]
        y0, y1, y2 = np.abs(y[k - 1 : k + 2])
        d = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)  # vertex offset, in samples
        peaks_t.append(t[k] + d * (t[k + 1] - t[k]))
        peaks_y.append(y1 - 0.25 * (y0 - y2) * d)
    growth = np.polyfit(peaks_t, np.log(peaks_y), 1)[0]
    return growth, 1.0 / (2.0 * half)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("row", list(ROWS))
def test_linear_growth_and_frequency_are_the_augmented_pencils(row):
    """(b) Near the linear regime (a 0.3 nm initial bend, cubic links on) the simulated
    beat's growth rate and frequency, fitted on the late signal (zero crossings, log
    amplitude of the peaks), equal scipy's dominant eigenvalue of the augmented pencil
    assembled here (growth rate to 1e-3, frequency to 1e-4; measured 3e-4 and 2e-6)."""
    model, params, units = ROWS[row]()
    tau_m = _tau_m(units)
    lam = _dominant(*_augmented(model, params, tau_m)[:2]) / units.tau_s  # 1/s
    assert lam.real > 0 and lam.imag != 0  # growing flutter, the beat
    t_end = 4.5 / lam.real  # the beat grows e^4.5 = 90 times: 11 to 23 periods
    if model.rigid_modes().shape[1]:  # a free base: the rigid modes are not the beat
        assert abs(lam.imag) > 0.5 * float(params.omega0) / units.tau_s
    assert t_end > 10 * 2 * math.pi / abs(lam.imag)
    sim = ax.simulate(
        model, params, t_end, units=units, tau_m=tau_m, perturbation_um=3e-4, atol=1e-11
    )
    assert sim.meta["solver"]["ok"]
    late = sim.t_s > 0.5 * t_end  # the decaying modes of the initial bend are gone
    growth, frequency = _growth_and_frequency(sim.t_s[late], sim.tip_beat_um[late])
    assert growth == pytest.approx(lam.real, rel=1e-3)  # measured 1e-5 to 3e-4
    assert frequency == pytest.approx(abs(lam.imag) / (2 * math.pi), rel=1e-4)  # measured 2e-6
    assert sim.linear["growth_rate_per_s"] == pytest.approx(lam.real, rel=1e-8)
    assert np.abs(sim.tip_beat_um).max() < 0.2  # linear regime: the tip within 0.2 um


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("row", ["sliding-clamped", "curvature-clamped+compliance"])
def test_linear_integration_is_the_matrix_exponential(row):
    """With the cubic links off the integrated state X = (q, y) is scipy's matrix
    exponential of the augmented system, y included."""
    model, params, units = ROWS[row]()
    tau_m = _tau_m(units)
    A, C, _ = _augmented(model, params, tau_m)
    n = model.n_unknowns
    rng = np.random.default_rng(0)
    X0 = np.concatenate([tip_deflection(model), np.zeros(model.n_border), np.zeros(n)]) * 1e-3
    X0 = X0 + 1e-4 * rng.normal(size=2 * n)
    G = -np.linalg.solve(C, A)
    t = np.linspace(0.0, 3 * tau_m, 4)
    traj = integrate(
        model, params, 0.0, jnp.asarray(X0), jnp.asarray(t), rtol=1e-10, atol=1e-13, tau_m=tau_m
    )
    assert bool(traj.ok)
    for ti, Xi in zip(t, np.asarray(traj.q)):
        ref = sl.expm(G * ti) @ X0
        assert np.linalg.norm(Xi - ref) <= 1e-7 * np.linalg.norm(ref), ti


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_nonlinear_integration_with_motor_kinetics_matches_radau():
    """Cubic links on, a large bend: the chord's padded block Jacobian (links on q, none
    on y) against scipy's Radau on the dense augmented vector field (basal compliance:
    the border of q and of y too)."""
    model, params, units = _curvature_compliant()
    tau_m, kappa = _tau_m(units), 1e4
    A, C, b = _augmented(model, params, tau_m)
    n = model.n_unknowns
    force = jax.jit(lambda q: cubic_link_force(model, params, kappa, q))
    rng = np.random.default_rng(3)
    q0 = np.concatenate([tip_deflection(model), np.zeros(model.n_border)]) * 0.2
    X0 = np.concatenate(
        [q0 + 0.05 * rng.normal(size=n), 0.01 * rng.normal(size=n)]
    )  # links stretched
    t = np.linspace(0.0, 2e-3, 4)

    def rhs(_, X, links=True):
        f = np.asarray(force(jnp.asarray(X[:n]))) if links else np.zeros(n)
        return np.linalg.solve(C, b - A @ X - np.concatenate([f, np.zeros(n)]))

    solve = lambda f: scipy.integrate.solve_ivp(
        f, (0, t[-1]), X0, "Radau", t_eval=t, rtol=1e-10, atol=1e-13
    )
    ref, linear = solve(rhs), solve(lambda t_, X: rhs(t_, X, links=False))
    traj = integrate(
        model, params, kappa, jnp.asarray(X0), jnp.asarray(t), rtol=1e-10, atol=1e-13, tau_m=tau_m
    )
    assert bool(traj.ok) and ref.success and linear.success
    err = np.linalg.norm(np.asarray(traj.q) - ref.y.T, axis=1)
    assert np.all(err <= 1e-6 * np.linalg.norm(ref.y, axis=0)), err
    moved = np.linalg.norm(ref.y[:, -1] - linear.y[:, -1])
    assert moved > 1e-3 * np.linalg.norm(ref.y[:, -1]), moved  # the links matter


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), 1e300])
def test_a_bad_motor_time_is_one_line_naming_it(bad):
    """(c) ax.simulate refuses a bad tau_m in one line that names the value."""
    model, params = ax.models.two(n_elements=4), _sliding_row()
    with pytest.raises(ValueError) as err:
        ax.simulate(model, params, 0.01, tau_m=bad)
    message = str(err.value)
    assert "\n" not in message and "tau_m" in message and repr(bad) in message


def _argv(units=ax.Units()):
    params = _sliding_row()
    chi = complex(params.chi_re, params.chi_im) * units.ei_pn_um2 / units.length_um**4  # pN/um^2
    hz = float(params.omega0) / (2 * math.pi * units.tau_s)
    argv = ["simulate", "--model", "two", "--elements", "8", "--p", "0", "--mechanism", "sliding"]
    return argv + [f"--chi={chi.real!r},{chi.imag!r}", "--omega0-hz", repr(hz), "--t-end", "0.02"]


@pytest.mark.parametrize("value", ["0", "-3", "1e300"])
def test_cli_refuses_a_bad_motor_time_on_one_line(capsys, value):
    """(c) on the command line: one line on stderr naming the flag and the value, exit 2."""
    from axojax.cli.main import main

    code = main([*_argv(), f"--motor-tau-ms={value}", "--json"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("axojax: error: --motor-tau-ms: ") and f"{float(value):g}" in err


def test_cli_motor_time_needs_a_regulated_beat(capsys):
    from axojax.cli.main import main

    code = main(
        ["simulate", "--model", "two", "--elements", "4", "--t-end", "0.01", "--motor-tau-ms", "5"]
    )
    err = capsys.readouterr().err
    assert (
        code == 2 and err.count("\n") == 1 and "--motor-tau-ms: needs a regulated mechanism" in err
    )


def test_cli_simulates_an_active_sliding_row_with_motor_kinetics(capsys, tmp_path):
    """``axojax simulate --mechanism sliding --chi ... --motor-tau-ms 5``: refused without
    the motors (--chi, one line), runs with them; the JSON says which tau_m it used and
    its linear eigenvalue is scipy's Hopf point of the augmented pencil."""
    from axojax.cli.main import main

    code = main([*_argv(), "--json"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("axojax: error: --chi: simulate") and err.count("\n") == 1
    out = tmp_path / "beat.npz"
    assert main([*_argv(), "--motor-tau-ms", str(TAU_MS), "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    units = ax.Units()
    tau_m = _tau_m(units)
    assert (
        doc["motor_kinetics"]["tau_m"] == pytest.approx(tau_m)
        and doc["motor_kinetics"]["tau_ms"] == TAU_MS
    )
    assert doc["solver"]["ok"] and doc["state"] != "solver_failed"
    lam = _dominant(*_augmented(ax.models.two(n_elements=8), _sliding_row(), tau_m)[:2])
    hz = abs(lam.imag) / (2 * math.pi * units.tau_s)
    assert doc["linear"]["frequency_hz"] == pytest.approx(hz, rel=1e-6)  # CLI units: 1e-6 of Hz
    assert ax.Simulation.load(out).meta["motor_kinetics"]["tau_ms"] == TAU_MS
    assert main([*_argv(), "--motor-tau-ms", str(TAU_MS)]) == 0
    assert f"motor kinetics: tau_m = {TAU_MS:g} ms" in capsys.readouterr().out


# -- saturating motors (issue 47 item 2) ------------------------------------------------


@pytest.mark.parametrize(
    "base", [Base("clamped"), COMPLIANT, SARTORI_BASE, Base("head", False, 1.0, 0.2)]
)
def test_the_pairs_rows_at_the_gauss_points_give_the_assembled_mechanism(base):
    """Delta_a and kappa_a tabulated at the Gauss points (the saturating force's
    quadrature): sum_q w_q Delta^T Delta and sum_q w_q Delta^T kappa are the assembled
    dA/dchi' and dA/dbeta' (differences of ax.assemble), border included."""
    from axojax.dynamics.saturation import pair_rows

    params = _sliding_row().replace(kb=50.0, xib=0.5)
    for model in (ax.models.two(n_elements=6, base=base), ax.models.seven(n_elements=3, base=base)):
        slope, basal, curvature, w = pair_rows(model)
        delta = float(params.a0) * slope + basal[:, None, :]
        zero = params.replace(chi_re=0.0, chi_im=0.0, beta_re=0.0, beta_im=0.0)
        A0 = np.asarray(ax.assemble(model, zero).A)
        for field, rows in (("chi_re", delta), ("beta_re", curvature)):
            ref = (np.asarray(ax.assemble(model, zero.replace(**{field: 1e3})).A) - A0) / 1e3
            ours = np.einsum("q,pqn,pqm->nm", w, delta, rows)
            assert np.abs(ours - ref).max() <= 1e-9 * np.abs(ref).max(), (model.name, field)


def _saturated_field(model, params, tau_m, f_sat):
    """The dense vector field with saturating motors, from the test's augmented matrices
    and the Gauss-point rows: C'^-1 (b' - A' X - sum_a int (f_sat tanh(f/f_sat) - f)
    delta Delta_a), f = c_inf Delta[q] + d_inf kappa[q] + c_1 Delta[y] + d_1 kappa[y]."""
    from axojax.dynamics.saturation import pair_rows

    A, C, b = _augmented(model, params, tau_m)
    slope, basal, curvature, w = pair_rows(model)
    delta = float(params.a0) * slope + basal[:, None, :]
    wt, n = float(params.omega0) * tau_m, model.n_unknowns
    c = {}
    for field in ("chi", "beta"):
        re, im = float(getattr(params, f"{field}_re")), float(getattr(params, f"{field}_im"))
        c[field] = (re + im / wt, -im * (1 + wt**2) / wt)
    on_q = c["chi"][0] * delta + c["beta"][0] * curvature
    on_y = c["chi"][1] * delta + c["beta"][1] * curvature

    def rhs(_, X):
        f = on_q @ X[:n] + on_y @ X[n:]
        g = f_sat * np.tanh(f / f_sat) - f
        force = np.concatenate([np.einsum("q,pq,pqn->n", w, g, delta), np.zeros(n)])
        return np.linalg.solve(C, b - A @ X - force)

    return rhs


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_saturating_motors_match_radau():
    """Saturating motors (cubic links off): the chord's saturation tangent in the motor
    blocks against scipy's Radau on the dense vector field built here; the saturation
    acts (against the unsaturated solution)."""
    model, params, units = _curvature_compliant()
    tau_m, f_sat = _tau_m(units), 30.0
    rng = np.random.default_rng(5)
    n = model.n_unknowns
    X0 = np.concatenate([tip_deflection(model), np.zeros(model.n_border), np.zeros(n)]) * 0.3
    X0 = X0 + 0.02 * rng.normal(size=2 * n)
    t = np.linspace(0.0, 3e-3, 4)
    solve = lambda f: scipy.integrate.solve_ivp(
        f, (0, t[-1]), X0, "Radau", t_eval=t, rtol=1e-10, atol=1e-13
    )
    ref = solve(_saturated_field(model, params, tau_m, f_sat))
    linear = solve(_saturated_field(model, params, tau_m, 1e12))
    traj = integrate(
        model,
        params,
        0.0,
        jnp.asarray(X0),
        jnp.asarray(t),
        rtol=1e-10,
        atol=1e-13,
        tau_m=tau_m,
        f_sat=f_sat,
    )
    assert bool(traj.ok) and ref.success and linear.success
    err = np.linalg.norm(np.asarray(traj.q) - ref.y.T, axis=1)
    assert np.all(err <= 1e-6 * np.linalg.norm(ref.y, axis=0)), err
    moved = np.linalg.norm(ref.y[:, -1] - linear.y[:, -1])
    assert moved > 1e-2 * np.linalg.norm(ref.y[:, -1]), moved  # the saturation matters


def test_the_saturation_tangent_is_the_exact_jacobian():
    from axojax.dynamics.saturation import motor_saturation

    model = ax.models.seven(n_elements=3, base=COMPLIANT)
    params = sartori_params().replace(beta_re=-100.0)
    sat = motor_saturation(model, params, 0.02, 5.0)
    X = jnp.asarray(np.random.default_rng(6).normal(size=2 * model.n_unknowns)) * 0.05
    ours, ref = np.asarray(sat.tangent(X)), np.asarray(jax.jacfwd(sat.force)(X))
    assert np.abs(ours).max() > 0 and np.abs(ours - ref).max() <= 1e-10 * np.abs(ref).max()
    blocks = np.asarray(sat.tangent_blocks(X).to_dense())
    assert np.array_equal(blocks, ours[np.asarray(sat.perm)][:, np.asarray(sat.perm)])


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_saturating_motors_set_the_amplitude_of_a_regulated_beat():
    """Past its Hopf point a regulated beat grows until its motors saturate: a limit cycle
    whose amplitude is proportional to f_sat (cubic links off, the equations are then
    homogeneous in (X, f_sat): the cycle scales, its frequency stays)."""
    model, params, units = _curvature_compliant()
    cycles = []
    for f_sat in (10.0, 20.0):
        sim = ax.simulate(
            model, params, 0.6, units=units, tau_m=_tau_m(units), f_sat=f_sat, cubic=0.0
        )
        assert sim.state == "limit_cycle", (f_sat, sim.state)
        cycles.append(sim.limit_cycle)
        assert sim.meta["motor_kinetics"]["f_sat_pn_per_um"] == pytest.approx(
            float(units.p_to_pn_per_um(f_sat))
        )
    ratio = cycles[1]["tip_amplitude_um"] / cycles[0]["tip_amplitude_um"]
    assert ratio == pytest.approx(2.0, rel=1e-2)
    assert cycles[1]["frequency_hz"] == pytest.approx(cycles[0]["frequency_hz"], rel=1e-3)


def test_a_bad_saturation_is_one_line():
    model, params = ax.models.two(n_elements=4), _sliding_row()
    for bad in (0.0, -1.0, float("inf")):
        with pytest.raises(ValueError, match="f_sat") as err:
            ax.simulate(model, params, 0.01, tau_m=0.01, f_sat=bad)
        assert "\n" not in str(err.value) and repr(bad) in str(err.value)
    with pytest.raises(ValueError, match="needs motor kinetics"):
        ax.simulate(model, params, 0.01, f_sat=1.0)


def test_cli_motor_saturation(capsys):
    """``--motor-saturation PN_PER_UM``: needs --motor-tau-ms, > 0, one line; with it the
    JSON reports the saturation in pN/um and in EI/L^3."""
    from axojax.cli.main import main

    for extra, needle in (([], "needs motor kinetics"), (["--motor-tau-ms", "5"], "must be > 0")):
        value = "2" if not extra else "-2"
        code = main([*_argv(), f"--motor-saturation={value}", *extra, "--json"])
        err = capsys.readouterr().err
        assert (
            code == 2
            and err.count("\n") == 1
            and err.startswith("axojax: error: --motor-saturation: ")
        )
        assert needle in err
    assert main([*_argv(), "--motor-tau-ms", "5", "--motor-saturation", "2", "--json"]) == 0
    m = json.loads(capsys.readouterr().out)["motor_kinetics"]
    assert m["f_sat_pn_per_um"] == pytest.approx(2.0) and m["f_sat"] == pytest.approx(
        float(ax.Units().p_from_pn_per_um(2.0))
    )
