"""The inverse Problem (issue 19): its coordinates and contract for samplers, exact
Jacobians against finite differences, the solver objects reaching the same optimum,
honest reports (at_bound never identifiable), the shape floor and the basal exclusion,
and the fit report as JSON and as a figure."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.beats import ShapeTarget, Target
from axojax.inverse import LBFGS, Condition, LevenbergMarquardt, Problem, least_squares
from axojax.inverse.predictions import model_psi1

RATIO = 1000.0


@pytest.fixture(scope="module")
def model():
    return ax.models.seven(n_elements=6)


@pytest.fixture(scope="module")
def truth(model):
    """Frequencies and wavelengths of the model at two dynein forces (the 'observations')."""
    out = {}
    for p in (280.0, 360.0):
        mode = ax.dominant_mode(model, ax.Params(p=p, ks=1e5, cl=0.005).with_values({}, RATIO))
        out[p] = (float(mode.frequency_hz()), float(mode.wavelength_um()))
    return out


def _problem(model, truth, **kw):
    conds = [
        Condition(
            {"p": p},
            [Target("frequency_hz", f, 0.01 * f), Target("wavelength_um", w, 0.02 * w)],
            label=f"p{p:g}",
        )
        for p, (f, w) in truth.items()
    ]
    return Problem(
        model, conds, ["ks", "cl"], params=ax.Params(ks=2e5, cl=0.004), kl_ratio=RATIO, **kw
    )


@pytest.fixture(scope="module")
def problem(model, truth):
    """Shared ks, cl (kl tied); two dynein forces, frequency and wavelength each."""
    return _problem(model, truth)


@pytest.fixture(scope="module")
def problem_gamma(model, truth):
    """As ``problem``, plus a gamma fitted separately in each condition."""
    return _problem(model, truth, per_condition=["gamma"])


def test_contract_for_samplers(problem_gamma):
    prob = problem_gamma
    assert prob.names == ("ks", "cl", "gamma@p280", "gamma@p360")
    k = len(prob.names)
    assert prob.lower.shape == prob.upper.shape == prob.u0.shape == (k,)
    # Bounds in the fitted coordinate: log for ks and cl, linear for gamma.
    assert prob.lower[0] == pytest.approx(np.log(ax.inverse.DEFAULT_BOUNDS["ks"][0]))
    assert prob.lower[2] == ax.inverse.DEFAULT_BOUNDS["gamma"][0]
    assert prob.u0[0] == pytest.approx(np.log(2e5))
    z = np.array([0.3, -1.2, 0.5, 2.0])
    u = np.asarray(prob.to_u(z))
    np.testing.assert_allclose(np.asarray(prob.to_z(u)), z, rtol=1e-12)
    assert np.all((u > prob.lower) & (u < prob.upper))
    # log|du/dz| equals the log-determinant of the (diagonal) Jacobian of to_u.
    jac = jax.jacfwd(prob.to_u)(jnp.asarray(z))
    assert float(prob.log_jacobian(z)) == pytest.approx(
        float(np.linalg.slogdet(np.asarray(jac))[1]), rel=1e-12
    )
    r = np.asarray(prob.residuals(u))
    assert r.shape == (prob.n_residuals,) == (4,)
    want = -0.5 * np.sum(r**2) + float(prob.log_jacobian(z))
    assert float(jax.jit(prob.log_density)(jnp.asarray(z))) == pytest.approx(want, rel=1e-10)
    assert float(prob.log_prior(u)) == 0.0
    vals = prob.values(u)
    assert vals["ks"] == pytest.approx(np.exp(u[0])) and vals["gamma@p360"] == pytest.approx(u[3])
    # A per-condition value reaches only its condition.
    assert float(prob.condition_params(u, 1).gamma) == pytest.approx(u[3])
    assert float(prob.condition_params(u, 0).kl) == pytest.approx(np.exp(u[0]) / RATIO)


def test_residuals_are_the_normalised_misfits(model, truth, problem):
    """Independent recomputation: each residual is (dominant mode observable - target) / sigma."""
    u = np.log([1.5e5, 0.006])
    r = problem.residuals_at(u)
    for i, (p, (f, w)) in enumerate(truth.items()):
        mode = ax.dominant_mode(model, ax.Params(p=p, ks=1.5e5, kl=1.5e5 / RATIO, cl=0.006))
        assert r[2 * i] == pytest.approx((float(mode.frequency_hz()) - f) / (0.01 * f), rel=1e-8)
        assert r[2 * i + 1] == pytest.approx(
            (float(mode.wavelength_um()) - w) / (0.02 * w), rel=1e-8
        )


def test_jacobian_matches_finite_differences(problem_gamma):
    prob = problem_gamma
    u = np.array([np.log(1.5e5), np.log(0.006), 0.05, -0.05])
    J = prob.jacobian(u)
    f = prob.residuals_at
    h = 1e-5
    for j in range(len(u)):
        e = np.zeros_like(u)
        e[j] = h
        fd = (np.asarray(f(u + e)) - np.asarray(f(u - e))) / (2 * h)
        np.testing.assert_allclose(J[:, j], fd, rtol=2e-5, atol=1e-6 * np.abs(fd).max())


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("solver", [LevenbergMarquardt(), LBFGS(max_steps=60)], ids=["lm", "lbfgs"])
def test_solvers_reach_the_truth(problem, solver):
    """Noise-free targets made at ks = 1e5, cl = 0.005: both solvers recover them."""
    result = least_squares(problem, solver, starts=1)
    assert result.targets_met, result.message
    assert result.params["ks"] == pytest.approx(1e5, rel=1e-3)
    assert result.params["cl"] == pytest.approx(0.005, rel=1e-3)
    assert result.chi2_per_dof < 1e-4 and result.at_bound == []
    # Standard errors: the Gauss-Newton ones from a finite-difference Jacobian (in log u).
    u = np.log([result.params["ks"], result.params["cl"]])
    f, h = problem.residuals_at, 1e-5
    J = np.stack(
        [(np.asarray(f(u + h * e)) - np.asarray(f(u - h * e))) / (2 * h) for e in np.eye(2)], axis=1
    )
    se = np.sqrt(np.diag(np.linalg.inv(J.T @ J)))
    assert [result.stderr_fitted["ks"], result.stderr_fitted["cl"]] == pytest.approx(
        list(se), rel=1e-3
    )
    assert result.identifiable["ks"] == (se[0] <= 1.0) and result.identifiable["cl"] == (
        se[1] <= 1.0
    )


def test_parameter_at_a_bound_is_never_identifiable(model):
    """A frequency no cl in the box reaches drives cl to its lower bound: listed in
    at_bound, not identifiable, and the message says so."""
    with pytest.warns(UserWarning):
        result = ax.fit(
            model,
            ax.Params(),
            [Target("frequency_hz", 5000.0, 10.0)],
            ["cl"],
            bounds={"cl": (1e-3, 1e2)},
            starts=2,
        )
    assert result.at_bound == ["cl"]
    assert result.identifiable == {"cl": False}
    assert (
        result.params["cl"] <= 1e-3 * (1e5) ** 0.01
    )  # within 1 % of the log range of the lower bound
    assert "lower bound" in result.message and not result.targets_met
    doc = result.to_json()
    assert doc["at_bound"] == ["cl"] and doc["identifiable"]["cl"] is False
    # where each start stopped: one entry per start, the best one the reported optimum
    assert len(result.optima) == len(result.starts) == 2
    best_values, best_loss = min(result.optima, key=lambda o: o[1])
    assert best_loss == result.loss and best_values["cl"] == pytest.approx(result.params["cl"])


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_linear_parameter_judged_on_its_own_scale(problem_gamma):
    """gamma (truth 0) is judged by its standard error against its bound range (5 % of
    (-3, 3)), not against its value near 0; log parameters by a factor e."""
    result = least_squares(problem_gamma, starts=1)
    for name in ("gamma@p280", "gamma@p360"):
        se = result.stderr[name]
        assert result.coordinate[name] == "linear" and result.stderr_fitted[name] == se
        assert result.identifiable[name] == (se <= 0.05 * 6.0 and name not in result.at_bound)
    for name in ("ks", "cl"):
        assert result.coordinate[name] == "log"
        assert result.stderr[name] == pytest.approx(
            result.params[name] * result.stderr_fitted[name]
        )
        assert result.identifiable[name] == (
            result.stderr_fitted[name] <= 1.0 and name not in result.at_bound
        )


def _shape_target(model, params, s, noise=0.0, basal=0.0, seed=0):
    mode = ax.dominant_mode(model, params)
    psi1 = np.asarray(model_psi1(model, mode, s / 12.0))
    psi1 = psi1 / np.abs(psi1).max() * 0.8
    rng = np.random.default_rng(seed)
    psi1 = psi1 + noise * (rng.normal(size=s.size) + 1j * rng.normal(size=s.size))
    psi1 = psi1 + basal * (s < 2.0)  # a swinging base the clamped model cannot follow
    return ShapeTarget(s, psi1, 0.01)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_shape_floor_and_basal_exclusion(model):
    params = ax.Params(p=320.0, ks=1e5).with_values({}, RATIO)
    s = np.linspace(0, 12, 25)
    shape = _shape_target(model, params, s, basal=0.3)
    cond = [Condition(targets=[], shape=shape)]
    # The floor enters in quadrature: sigma_eff = sqrt(0.01^2 + 0.05^2).
    prob = Problem(model, cond, ["p"], params=params, kl_ratio=RATIO)
    np.testing.assert_allclose(prob.shapes[0].sigma, np.hypot(0.01, 0.05))
    no_floor = Problem(model, cond, ["p"], params=params, kl_ratio=RATIO, shape_floor=0.0)
    u = jnp.asarray(prob.u0)
    np.testing.assert_allclose(
        np.asarray(no_floor.residuals(u)) * 0.01 / np.hypot(0.01, 0.05),
        np.asarray(prob.residuals(u)),
        rtol=1e-10,
    )
    # Excluding the base: fewer residuals; the report states the misfit left in the base.
    cut = Problem(model, cond, ["p"], params=params, kl_ratio=RATIO, exclude_base_um=2.0)
    kept = int((s >= 2.0).sum())
    assert cut.n_residuals == 2 * kept
    result = least_squares(cut, starts=1)
    assert result.params["p"] == pytest.approx(
        320.0, rel=1e-3
    )  # the shape without its base is the truth's
    ex = result.conditions[0]["excluded_base"]
    assert ex["points"] == s.size - kept
    assert ex["rms_rad"] == pytest.approx(0.3, rel=0.05) and ex["kept_rms_rad"] < 1e-3
    assert ex["fraction_of_chi2"] > 0.99
    assert "basal stretch" in result.message
    with pytest.raises(ValueError, match="exclude_base_um"):
        Problem(model, cond, ["p"], params=params, exclude_base_um=12.5)


def test_report_json_and_figure(model, tmp_path):
    params = ax.Params(p=320.0, ks=1e5).with_values({}, RATIO)
    s = np.linspace(0, 12, 21)
    shape = _shape_target(model, params, s, noise=0.02)
    mode = ax.dominant_mode(model, params)
    f = float(mode.frequency_hz())
    result = ax.fit(
        model,
        ax.Params(p=300.0, ks=1.2e5),
        [Target("frequency_hz", f, 0.02 * f)],
        ["p", "ks"],
        shape=shape,
        kl_ratio=RATIO,
        starts=1,
    )
    path = tmp_path / "fit.json"
    result.save(path)
    doc = json.loads(path.read_text())
    assert set(doc) >= {
        "params",
        "achieved",
        "loss",
        "converged",
        "stderr",
        "chi2_per_dof",
        "at_bound",
        "identifiable",
        "conditions",
    }
    assert doc["dof"] == 1 + 2 * s.size - 2
    assert doc["chi2_per_dof"] == pytest.approx(2 * doc["loss"] / doc["dof"], rel=1e-9)
    sh = doc["conditions"][0]["shape"]
    assert len(sh["s_um"]) == s.size and len(sh["psi1_fit_re"]) == s.size
    # Error bars are the measurement's sigma; the model-discrepancy floor is kept apart
    # (the plot draws it as a band about the fit), and the residuals use both.
    np.testing.assert_allclose(sh["sigma_rad"], np.broadcast_to(shape.sigma, s.shape))
    assert sh["floor_rad"] == pytest.approx(ax.inverse.SHAPE_FLOOR) and sh["floor_rad"] > 0
    from axojax.cli.main import main

    fig = tmp_path / "fit.png"
    assert main(["plot", str(path), "--out", str(fig)]) == 0
    assert fig.stat().st_size > 10_000
