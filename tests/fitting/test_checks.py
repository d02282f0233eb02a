"""A fit's regime and mesh check (issue 33): the regime named from hand-made eigenvalues
and from the spectrum at the optimum; the refit at twice the elements recovers the
parameters of a mesh-converged synthetic fit and reports the move of an under-resolved
one; the report's lines and the CLI's JSON entries."""

import json
import math

import numpy as np
import pytest

import axojax as ax
from axojax.beats import Target
from axojax.inverse import Condition, Problem, build_report
from axojax.inverse.fitting.checks import (
    DECAYING,
    FAR,
    MESH_TOLERANCE,
    NEAR,
    NEAR_ONSET,
    STANDING,
    classify_regime,
    fit_checks,
    mesh_check,
    refined,
    regime,
    render_checks,
)

P_TRUE = 80.0  # the single filament just past its Hopf point (p = 76.1, docs/model.md)


@pytest.mark.parametrize(
    "lam, name, ratio",
    [
        (1.0 + 20.0j, NEAR, 0.05),
        (-1.0 + 20.0j, NEAR, -0.05),
        (
            2.0 - 20.0j,
            NEAR,
            0.1,
        ),  # the threshold itself is near onset; the sign of Im does not count
        (5.0 + 20.0j, FAR, 0.25),
        (100.0 + 20.0j, FAR, 5.0),  # the human-sperm fits' Re lambda up to 5 Im lambda
        (-5.0 + 20.0j, DECAYING, -0.25),
        (0.0 + 3.0j, NEAR, 0.0),
    ],
)
def test_regime_of_hand_made_eigenvalues(lam, name, ratio):
    got, r = classify_regime(lam)
    assert got == name
    assert r == pytest.approx(ratio, rel=1e-12, abs=1e-15)


def test_regime_threshold_and_real_eigenvalues():
    assert classify_regime(3.0 + 0.0j) == (STANDING, math.inf)
    assert classify_regime(-3.0 + 0.0j) == (STANDING, -math.inf)
    assert classify_regime(0.3 + 1.0j, threshold=0.5)[0] == NEAR
    assert classify_regime(0.3 + 1.0j)[0] == FAR
    assert NEAR_ONSET == 0.1
    with pytest.raises(ValueError, match="eigenvalue must be finite"):
        classify_regime(complex(math.nan, 1.0))
    with pytest.raises(ValueError, match="threshold must be >= 0"):
        classify_regime(1j, threshold=-1.0)


def _synthetic(n_elements: int):
    """A synthetic fit of the single filament's p to its own frequency and wavelength at
    P_TRUE (the report built at the truth, which is the optimum: zero residuals)."""
    model = ax.models.single(n_elements=n_elements)
    mode = ax.dominant_mode(model, ax.Params(p=P_TRUE))
    f, w = float(mode.frequency_hz()), float(mode.wavelength_um())
    targets = [Target("frequency_hz", f, 0.01 * f), Target("wavelength_um", w, 0.02 * w)]
    problem = Problem(model, [Condition({}, targets)], ["p"], params=ax.Params(p=90.0))
    result = build_report(problem, np.array([math.log(P_TRUE)]))
    return problem, result


@pytest.fixture(scope="module")
def converged():
    problem, result = _synthetic(8)
    return problem, result, fit_checks(problem, result)


@pytest.fixture(scope="module")
def coarse():
    problem, result = _synthetic(2)
    return problem, result, fit_checks(problem, result)


def test_regime_at_the_optimum_is_the_spectrum_s(converged):
    problem, result, checks = converged
    lam = np.asarray(ax.spectrum(problem.model, ax.Params(p=P_TRUE)))  # the full dense spectrum
    top = complex(lam[np.argmax(np.real(lam))])  # plain numbers for pytest.approx
    (entry,) = checks["regime"]
    assert entry["ratio"] == pytest.approx(abs(top.real / top.imag), rel=1e-6)
    assert entry["regime"] == NEAR  # just past the Hopf point
    assert entry["growth_per_period"] == pytest.approx(np.exp(2 * np.pi * entry["ratio"]))
    far = regime(problem, build_report(problem, np.array([math.log(200.0)])))
    lam = ax.spectrum(problem.model, ax.Params(p=200.0))
    top = lam[np.argmax(np.real(lam))]
    assert far[0]["regime"] == FAR and top.real / abs(top.imag) > NEAR_ONSET


def test_mesh_check_of_a_converged_fit_recovers_the_parameters(converged):
    problem, result, checks = converged
    m = checks["mesh_check"]
    assert m["elements"] == 16 and m["from_elements"] == 8
    assert m["params"]["p"] == pytest.approx(P_TRUE, rel=0.01)
    assert m["moved"] == [] and m["mesh_converged"]
    assert m["refit_converged"]  # stopped on its tolerance, not on MESH_STEPS
    assert abs(m["relative_change"]["p"]) < MESH_TOLERANCE
    # the observables of the fitted p on 16 elements, recomputed without the check
    fine = ax.models.single(n_elements=16)
    f16 = float(ax.dominant_mode(fine, ax.Params(p=P_TRUE)).frequency_hz())
    assert m["achieved_at_fit"]["frequency_hz"] == pytest.approx(f16, rel=1e-9)
    lines = render_checks(result.to_json() | checks)
    assert lines[0].startswith("regime: near onset")
    assert lines[1].startswith("mesh check (8 -> 16 elements")
    assert not any(line.startswith("warning") for line in lines)


def test_mesh_check_of_an_under_resolved_fit_reports_the_move(coarse):
    problem, result, checks = coarse
    m = checks["mesh_check"]
    assert m["elements"] == 4
    f_target = problem.scalar_targets[0][0].value
    # independently: p on 4 elements whose frequency is the target's (scipy's root)
    from scipy.optimize import brentq

    fine = ax.models.single(n_elements=4)

    def gap(p):
        return float(ax.dominant_mode(fine, ax.Params(p=p)).frequency_hz()) - f_target

    p4 = brentq(gap, 60.0, P_TRUE, xtol=1e-6)
    assert abs(p4 / P_TRUE - 1) > MESH_TOLERANCE  # the mesh really moves the answer
    assert m["relative_change"]["p"] == pytest.approx(m["params"]["p"] / P_TRUE - 1)
    assert m["params"]["p"] == pytest.approx(p4, rel=0.02)  # p also carries the wavelength
    assert "p" in m["moved"] and "frequency_hz" in m["moved"] and not m["mesh_converged"]
    lines = render_checks(result.to_json() | checks)
    warning = [line for line in lines if line.startswith("warning: mesh check")]
    assert len(warning) == 1 and "p -" in warning[0] and "tolerance 5 %" in warning[0]


def test_refined_problem_keeps_everything_but_the_mesh(converged):
    problem, _, _ = converged
    fine = refined(problem, 3)
    assert fine.model.n_elements == 24 and fine.model.section == problem.model.section
    assert fine.names == problem.names and fine.n_residuals == problem.n_residuals
    assert np.array_equal(fine.lower, problem.lower) and np.array_equal(fine.upper, problem.upper)
    assert fine.base[0] == problem.base[0]
    with pytest.raises(ValueError, match="factor must be an integer >= 1"):
        refined(problem, 0)
    with pytest.raises(ValueError, match="max_steps must be an integer >= 1"):
        mesh_check(problem, build_report(problem, problem.u0), max_steps=0)


def test_far_past_onset_is_a_warning_line_and_json_is_plain(converged):
    problem, result, _ = converged
    far = build_report(problem, np.array([math.log(200.0)]))
    checks = fit_checks(problem, far, mesh=False)
    assert checks["mesh_check"] is None
    lines = render_checks(far.to_json() | checks)
    assert lines[0].startswith("regime: far past onset")
    assert lines[1].startswith("warning: regime: far past the onset of beating")
    json.dumps(checks, allow_nan=False)  # plain numbers: the CLI writes it as it is


def test_relative_change_from_zero_is_infinite_not_an_error():
    from axojax.inverse.fitting.checks import _relative

    assert _relative(0.5, 0.0) == math.inf and _relative(-0.5, 0.0) == -math.inf
    assert _relative(0.0, 0.0) == 0.0 and math.isnan(_relative(1.0, math.nan))
    assert _relative(1.1, 1.0) == pytest.approx(0.1)
    assert _relative(0.02, 0.0, scale=0.06) == pytest.approx(1 / 3)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_cli_fit_reports_regime_and_mesh_check(tmp_path, capsys):
    """`axojax fit` prints both checks (text), --no-mesh-check leaves the mesh check out
    (JSON null), and a --spec fit of two conditions names each condition's regime and
    checks the per-condition values."""
    from axojax.cli.main import main

    model = ax.models.single(n_elements=4)
    f = {p: float(ax.dominant_mode(model, ax.Params(p=p)).frequency_hz()) for p in (80.0, 90.0)}
    base = ["fit", "--model", "single", "--elements", "4", "--free", "p", "--starts", "1"]
    target = ["--p", "85", "--target-frequency", f"{f[80.0]!r}"]
    assert main(base + target) == 0
    out = capsys.readouterr().out
    assert "regime: near onset" in out and "mesh check (4 -> 8 elements" in out
    assert main(base + target + ["--no-mesh-check", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["mesh_check"] is None and doc["regime"][0]["regime"] == NEAR
    spec = tmp_path / "two.toml"
    lines = ['model = "single"', "elements = 4", 'free_per_condition = ["p"]']
    for p, fp in f.items():
        lines += ["[[condition]]", f'label = "c{p:g}"', f"p = {p + 5}"]
        lines += [f"frequency_hz = {fp!r}", f"frequency_sigma_hz = {0.01 * fp!r}"]
    spec.write_text("\n".join(lines) + "\n")
    assert main(["fit", "--spec", str(spec), "--starts", "1", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [c["label"] for c in doc["regime"]] == ["c80", "c90"]
    m = doc["mesh_check"]
    assert set(m["params"]) == {"p@c80", "p@c90"} and m["elements"] == 8
    assert "frequency_hz@c80" in m["relative_change"]
