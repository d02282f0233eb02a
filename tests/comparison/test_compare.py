"""``ax.compare`` and ``axojax compare`` (issue 30): mechanisms ranked on one beat.

The synthetic beat is the two-filament continuum solution of curvature control (Sartori
et al. 2016) at a Hopf point, computed independently of axojax by tests/regulation/test_mechanisms.py's
reference (exponential solution, 4 x 4 boundary determinant, numpy/scipy), written as a
Fourier-mode file. Every R^2 the report states is recomputed here from the report's own
arrays with numpy.
"""

import json
import math

import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import main
from axojax.inverse.comparison.mechanisms import row
from tests.regulation.test_mechanisms import _hopf, _shape

SP, CHI_BAR = 200.0, 10.0  # the synthetic beat: Sp = omega xi L^4 / kappa, chi' a^2 L^2 / kappa
LENGTH, EI, CN = 10.0, 100.0, 0.001  # tau = CN L^4 / EI = 0.1 s
UNITS = ax.Units(LENGTH, EI, CN)
FREQ = SP / (2 * math.pi * UNITS.tau_s)  # the frequency at which omega0 = Sp
ROW_KEYS = {
    "mechanism",
    "base",
    "free",
    "params",
    "frequency_hz",
    "r2",
    "chi2_per_dof",
    "aic",
    "bic",
    "delta_bic",
    "at_bound",
    "psi1_model",
}


def _r2(obs: np.ndarray, fit: np.ndarray) -> float:
    return 1 - np.sum(np.abs(obs - fit) ** 2) / np.sum(np.abs(obs - obs.mean()) ** 2)


def _complex(pairs) -> np.ndarray:
    a = np.asarray(pairs, dtype=float)
    return a[:, 0] + 1j * a[:, 1]


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory) -> str:
    """A Fourier-mode file of the continuum curvature-control beat (chi' = CHI_BAR,
    beta at the Hopf point of Sp), scaled to 0.5 rad at the tip."""
    beta_bar = _hopf(SP, -2.7 + 10.6j, solve_for="beta", other=CHI_BAR)
    s = np.linspace(0, 1, 25)
    psi1 = _shape(CHI_BAR, beta_bar, SP, s)
    psi1 = 0.5 * psi1 / psi1[-1]
    path = tmp_path_factory.mktemp("beat") / "curvature.npz"
    return fourier_file(path, s, psi1, LENGTH, FREQ)


def fourier_file(path, s, psi1, length_um: float, frequency_hz: float) -> str:
    """A Fourier-mode beat file at ``path``: psi_1 on s in [0, 1] (sigma 0.01 rad), psi_0
    zero, the frequency with a 1 % sigma."""
    np.savez(
        path,
        s_um=s * length_um,
        psi0_rad=np.zeros_like(s),
        psi1_re_rad=psi1.real,
        psi1_im_rad=psi1.imag,
        psi1_sigma_rad=np.full_like(s, 0.01),
        length_um=length_um,
        frequency_hz=frequency_hz,
        frequency_sigma_hz=0.01 * frequency_hz,
    )
    return str(path)


@pytest.fixture(scope="module")
def report(synthetic):
    """The comparison of steady, sliding and curvature control on the synthetic beat."""
    result = ax.compare(
        synthetic,
        mechanisms=("steady", "sliding", "curvature"),
        bases=("clamped",),
        n_elements=10,
        units=UNITS,
        starts=2,
        progress=False,
    )
    return result, result.to_json()


@pytest.mark.slow  # the fits of a comparison: about 1-2 min (the slow set, .ci/run)
def test_true_mechanism_is_recovered_and_ranked_first(report):
    result, doc = report
    best = doc["rows"][0]
    assert best["mechanism"] == "curvature"
    assert best["r2"] > 0.995
    assert best["delta_bic"] == 0.0
    assert all(r["delta_bic"] > 10 for r in doc["rows"][1:])  # very strong evidence
    # its beat is pinned: the observed frequency within the pin tolerance, no growth
    assert abs(best["frequency_hz"] - FREQ) <= 3 * 1e-3 * FREQ
    assert abs(best["growth_rate_per_s"]) <= 3 * 1e-3 * 2 * math.pi * FREQ
    # the fitted chi' is the continuum's (chi_bar = a0^2 chi / 2), to the mesh's accuracy
    a0 = ax.Params().a0
    assert a0**2 * best["params"]["chi_re"] / 2 == pytest.approx(CHI_BAR, rel=0.05)


@pytest.mark.slow  # the fits of a comparison: about 1-2 min (the slow set, .ci/run)
def test_every_reported_r2_is_sartoris_on_the_reported_arrays(report):
    """R^2 = 1 - sum |obs - model|^2 / sum |obs - mean obs|^2, recomputed with numpy from
    the report's observed psi_1 and each row's psi1_model (and the FitResult's own)."""
    result, doc = report
    obs = _complex(doc["data"]["psi1"])
    assert len(obs) == len(doc["data"]["s_um"]) == 25
    for r, row_obj in zip(doc["rows"], result.rows):
        fit = _complex(r["psi1_model"])
        assert fit.shape == obs.shape
        assert r["r2"] == pytest.approx(_r2(obs, fit), abs=1e-12)
        shape = row_obj.fit.to_json()["conditions"][0]["shape"]
        o = np.asarray(shape["psi1_obs_re"]) + 1j * np.asarray(shape["psi1_obs_im"])
        f = np.asarray(shape["psi1_fit_re"]) + 1j * np.asarray(shape["psi1_fit_im"])
        assert row_obj.fit.to_json()["r2"] == pytest.approx(_r2(o, f), abs=1e-12)


@pytest.mark.slow  # the fits of a comparison: about 1-2 min (the slow set, .ci/run)
def test_rows_are_ordered_by_bic_with_the_stated_criteria(report):
    """BIC = chi^2 + n_free ln n, AIC = chi^2 + 2 n_free, from the fit's own residuals;
    n_free = the fitted values + 2 (the complex amplitude); at most 6."""
    result, doc = report
    bics = [r["bic"] for r in doc["rows"]]
    assert bics == sorted(bics)
    for r in result.rows:
        fit = r.fit
        chi2 = 2 * fit.loss
        n = 2 + 2 * 25  # two pins, Re and Im of 25 points
        assert r.n_free == len(r.free) + 2 <= 6
        assert fit.bic == pytest.approx(chi2 + r.n_free * math.log(n), rel=1e-9)
        assert fit.aic == pytest.approx(chi2 + 2 * r.n_free, rel=1e-9)
        assert r.delta_bic == pytest.approx(r.bic - bics[0], abs=1e-9)


def test_fit_report_carries_the_hypothesis():
    """Every FitResult (not only compare's) reports r2, aic, bic, n_free, mechanism, base;
    a steady-load fit is 'steady' on a 'clamped' base."""
    model = ax.models.two(n_elements=6)
    truth = ax.dominant_mode(model, ax.Params(p=400.0))
    target = ax.Target("frequency_hz", float(truth.frequency_hz(ax.Units())), 1.0)
    result = ax.fit(model, ax.Params(p=350.0), [target], ["p"], starts=1)
    doc = result.to_json()
    assert doc["mechanism"] == "steady" and doc["base"] == "clamped"
    assert doc["n_free"] == 1  # no shape: no complex amplitude
    assert doc["r2"] is None
    chi2 = 2 * doc["loss"]
    assert doc["aic"] == pytest.approx(chi2 + 2)
    assert doc["bic"] == pytest.approx(chi2 + math.log(1))


def test_regulated_row_is_posed_as_its_anchors():
    """A regulated row: p = 0, omega0 at the observed frequency, the beat nearest
    i omega0, pins of growth 0 and the frequency; the steady row: the dominant mode."""
    model = ax.models.two(n_elements=6)
    r = row("curvature", "clamped", model, UNITS, FREQ)
    assert float(r.params.p) == 0.0
    assert float(r.params.omega0) == pytest.approx(SP)
    assert r.shift == pytest.approx(1j * SP)
    assert set(r.free) == {"chi_re", "beta_re", "beta_im"}
    assert [(t.name, t.value) for t in r.targets] == [
        ("growth_rate_per_s", 0.0),
        ("frequency_hz", FREQ),
    ]
    steady = row("steady", "clamped", model, UNITS, FREQ)
    assert steady.shift is None and float(steady.params.omega0) == 0.0


@pytest.mark.slow  # the fits of a comparison: about 1-2 min (the slow set, .ci/run)
def test_cli_json_has_every_interface_key(synthetic, tmp_path, capsys):
    out = tmp_path / "cmp.json"
    code = main(
        [
            "compare",
            "--data",
            synthetic,
            "--mechanisms",
            "steady,curvature",
            "--bases",
            "clamped,head",
            "--elements",
            "8",
            "--starts",
            "1",
            "--ei",
            str(EI),
            "--sperm-number",
            str(SP),
            "--out",
            str(out),
            "--json",
        ]
    )
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert {"data", "rows"} <= set(doc)
    assert doc["model"]["sperm_number"] == pytest.approx(SP, rel=1e-9)  # c_n set to give it
    assert doc["model"]["cn_pn_s_um2"] == pytest.approx(CN, rel=1e-9)
    assert {"s_um", "psi1", "frequency_hz"} <= set(doc["data"])
    assert len(doc["rows"]) == 4
    assert {(r["mechanism"], r["base"]) for r in doc["rows"]} == {
        (m, b) for m in ("steady", "curvature") for b in ("clamped", "head")
    }
    for r in doc["rows"]:
        assert ROW_KEYS <= set(r)
        assert len(r["psi1_model"]) == len(doc["data"]["s_um"])
    saved = json.loads(out.read_text())
    assert saved["rows"][0]["mechanism"] == doc["rows"][0]["mechanism"]
    png = tmp_path / "cmp.png"
    assert main(["plot", str(out), "--out", str(png)]) == 0
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["--mechanisms", "flutter"], "--mechanisms"),
        (["--mechanisms", "steady,chi_re"], "--mechanisms"),
        (["--mechanisms", "beta"], "--mechanisms"),
        (["--bases", "hinge"], "--bases"),
        (["--bases", "free,free"], "--bases"),
        (["--bases", "clamped", "--head-um", "2,1"], "--head-um"),
        (["--head-um", "1,2"], "--head-um"),
        (["--head-um", "2,1", "--viscosity-pa-s", "-1"], "--viscosity-pa-s"),
        (["--elements", "1"], "--elements"),
        (["--starts", "0"], "--starts"),
        (["--out", "x.txt"], "--out"),
        (["--sperm-number", "20", "--cn", "0.001"], "--sperm-number"),
        (["--sperm-number", "-1"], "--sperm-number"),
    ],
)
def test_cli_bad_input_is_one_line(argv, flag, capsys):
    code = main(["compare", "--data", "human_sperm", *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert err.startswith(f"axojax: error: {flag}")


def test_library_bad_names_raise_one_line():
    with pytest.raises(ValueError, match="^mechanisms: unknown name 'flutter'"):
        ax.compare("human_sperm", mechanisms=("flutter",))
    with pytest.raises(ValueError, match="^bases: each name once"):
        ax.compare("human_sperm", bases=("head", "head"))
