"""Basal compliance in the mechanism fits and ``ax.compare`` (issue 30, "Real beats").

The synthetic beat is Sartori et al.'s wild-type fit posed on the two-filament continuum
(their Table 1 in their code's units, Sp = 68, chi_bar = 24.39, beta_bar = -11.41i, a
free base): the chi_b_bar that makes i Sp an eigenvalue, and psi_1, come from
tests/model/test_bases.py's independent reference (exponential solution, 5 x 5 boundary
determinant, numpy/scipy), not from axojax.
"""

import math
import warnings

import numpy as np
import pytest
import scipy.linalg as sl
from scipy.optimize import fsolve

import axojax as ax
from axojax.cli import compare as cli_compare
from axojax.cli.main import main
from axojax.inverse.comparison.mechanisms import (
    BASES,
    COMPLIANCE,
    ELASTIC,
    FREE,
    build_model,
    check_names,
    row,
    steady_free,
    with_compliance,
)
from axojax.inverse.comparison.starts import compliance_starts, hopf_starts
from axojax.params import CB_FLOOR
from tests.comparison.test_compare import fourier_file
from tests.model.test_bases import _det, _shape

SP, CHI_BAR, BETA_BAR = 68.0, 24.39, -11.41j  # Sartori's wild type, dimensionless
LENGTH, EI, CN = 10.0, 100.0, 0.001
UNITS = ax.Units(LENGTH, EI, CN)
FREQ = SP / (2 * math.pi * UNITS.tau_s)
A0 = ax.Params().a0


def _chib() -> complex:
    """chi_b_bar of the continuum free base at which i Sp is an eigenvalue."""

    def f(xy):
        d = _det(CHI_BAR, BETA_BAR, SP, ("free", 0, 0), xy[0] + 1j * xy[1])
        return [d.real, d.imag]

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        xy = fsolve(f, [4.4, 0.4], xtol=1e-13)
    chib = xy[0] + 1j * xy[1]
    assert abs(_det(CHI_BAR, BETA_BAR, SP, ("free", 0, 0), chib)) < 1e-10
    return chib


@pytest.fixture(scope="module")
def beat(tmp_path_factory) -> tuple[str, complex]:
    chib = _chib()
    s = np.linspace(0, 1, 25)
    psi1, _ = _shape(CHI_BAR, BETA_BAR, SP, ("free", 0, 0), chib, s)
    psi1 = 0.5 * psi1 / psi1[-1]
    path = tmp_path_factory.mktemp("beat") / "sartori.npz"
    return fourier_file(path, s, psi1, LENGTH, FREQ), chib


def _own(mech, model):
    return set(steady_free(model) if mech == "steady" else FREE[mech])


def test_a_compliant_row_frees_its_mechanism_and_the_compliance():
    """A full compliance adds cb = 1/kb (linear, from 0: a rigid base) and xib (log: > 0)
    to the mechanism's own free values (nested: issue 45), at most 6 in all; the start
    is inside the bounds, xib > 0."""
    for kind in ("clamped", "head"):
        model = build_model("two", 4, kind + COMPLIANCE, UNITS)
        assert model.base.kind == kind and model.base.compliance
        for mech in ("steady", "sliding", "curvature", "sliding+curvature"):
            r = row(mech, kind + COMPLIANCE, model, UNITS, FREQ)
            assert set(r.free) == _own(mech, model) | {"cb", "xib"} and len(r.free) <= 6
            assert r.bounds["cb"][0] == 0.0
            for name in ("cb", "xib"):
                lo, hi = r.bounds[name]
                assert 0 <= lo < float(r.params.value_of(name)) < hi
    with pytest.raises(ValueError, match="^base: the model's base is not 'head'"):
        row("curvature", "head", build_model("two", 4, "head+compliance", UNITS), UNITS, FREQ)


def test_an_elastic_row_frees_the_compliance_and_a_negligible_friction():
    """'+elastic': cb free, xib fixed at the low end of its range (chi_b_bar'' =
    1e-3 (1 + Sp^1/2), as low as chi_b_bar' can go); cb's range from 0 (a rigid base) to
    the softest spring of the range."""
    model = build_model("two", 4, "clamped" + ELASTIC, UNITS)
    assert model.base.compliance
    for mech in ("steady", "sliding", "curvature", "sliding+curvature"):
        r = row(mech, "clamped" + ELASTIC, model, UNITS, FREQ)
        assert set(r.free) == _own(mech, model) | {"cb"} and len(r.free) <= 5
        assert "xib" not in r.bounds
        chi_b_im = A0**2 * SP * float(r.params.xib) / 2  # Sartori's chi_b_bar''
        assert chi_b_im == pytest.approx(1e-3 * (1 + math.sqrt(SP)))
        lo, hi = r.bounds["cb"]
        assert lo == 0.0 < float(r.params.value_of("cb")) < hi
        chi_b_re = A0**2 * (1 / hi) / 2  # the softest spring: chi_b_bar' = 1e-3 (1 + Sp^1/2)
        assert chi_b_re == pytest.approx(1e-3 * (1 + math.sqrt(SP)))


def test_elastic_hopf_starts_are_hopf_points():
    """The Hopf points of an elastic row (the mechanism's, along a ladder of kb, given as
    cb) put an eigenvalue at i omega with xib fixed."""
    model = build_model("two", 6, "clamped" + ELASTIC, UNITS)
    r = row("sliding+curvature", "clamped" + ELASTIC, model, UNITS, FREQ)
    starts = hopf_starts(r)
    assert len(starts) >= 10
    for values in starts[:: max(1, len(starts) // 8)]:
        prm = r.params.replace(**dict(zip(r.free, values)))
        system = ax.assemble(model, prm)
        w = sl.eigvals(-np.asarray(system.A), np.asarray(system.C))
        assert np.min(np.abs(w - 1j * SP)) < 1e-7 * SP


def test_pencil_is_linear_in_the_complex_chi_b():
    """What compliance_starts relies on: at lambda = i omega, kb and xib enter
    A + lambda C only as chi_b = kb + i omega xib (the same rank-m matrix)."""
    model = ax.models.two(n_elements=4, base=ax.models.Base("free", compliance=True))
    omega = 50.0
    prm = ax.Params(p=0.0, chi_re=300.0, beta_re=2.0, omega0=omega)

    def pencil(kb, xib):
        s = ax.assemble(model, prm.replace(kb=kb, xib=xib))
        return np.asarray(s.A) + 1j * omega * np.asarray(s.C)

    p0 = pencil(0.0, 0.0)
    for kb, xib in ((1.0, 0.0), (0.0, 1.0), (3.0, 0.5)):
        unit = pencil(1.0, 0.0) - p0
        assert np.linalg.matrix_rank(unit) == 1  # one active pair in `two`
        np.testing.assert_allclose(pencil(kb, xib), p0 + (kb + 1j * omega * xib) * unit, atol=1e-9)


def test_compliance_starts_are_hopf_points():
    """Every start puts an eigenvalue of the row's pencil at i omega (scipy on the
    assembled A, C), with kb, xib > 0 inside their bounds."""
    model = build_model("two", 6, "free+compliance", UNITS)
    r = row("curvature", "free+compliance", model, UNITS, FREQ)
    starts = compliance_starts(r)
    assert len(starts) >= 5
    for values in starts[:: max(1, len(starts) // 8)]:
        prm = r.params.replace(**dict(zip(r.free, values)))
        system = ax.assemble(model, prm)
        w = sl.eigvals(-np.asarray(system.A), np.asarray(system.C))
        assert np.min(np.abs(w - 1j * SP)) < 1e-7 * SP
        assert prm.kb > 0 and prm.xib > 0


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_sartoris_free_base_beat_is_recovered_with_compliance(beat):
    """Curvature control on a free base with basal compliance, fitted to the continuum
    beat of Sartori's wild-type values: R^2 > 0.995 (recomputed from the report's arrays),
    the beat pinned, and chi', beta'' and chi_b_bar those of the continuum (5 %, the
    mesh's accuracy at 8 elements)."""
    path, chib = beat
    result = ax.compare(
        path,
        mechanisms=("curvature",),
        bases=("free",),
        compliance=True,
        n_elements=8,
        units=UNITS,
        starts=2,
    )
    doc = result.to_json()
    (r,) = doc["rows"]
    assert (
        r["base"] == "free+compliance" and r["n_free"] == 7
    )  # chi', beta', beta'', cb, xib, amplitude
    obs = np.array(doc["data"]["psi1"]) @ [1, 1j]
    fit = np.array(r["psi1_model"]) @ [1, 1j]
    r2 = 1 - np.sum(np.abs(obs - fit) ** 2) / np.sum(np.abs(obs - obs.mean()) ** 2)
    assert r["r2"] == pytest.approx(r2, abs=1e-12) and r2 > 0.995
    assert abs(r["frequency_hz"] / FREQ - 1) < 3e-3
    p = r["params"]
    assert A0**2 * p["chi_re"] / 2 == pytest.approx(CHI_BAR, rel=0.05)
    assert A0 * p["beta_im"] / 2 == pytest.approx(BETA_BAR.imag, rel=0.05)
    kb = 1 / (p["cb"] + CB_FLOOR)
    fitted = A0**2 * (kb + 1j * SP * p["xib"]) / 2
    assert abs(fitted - chib) < 0.05 * abs(chib)
    assert r["physical"]["cb_um_per_pn"] == pytest.approx(p["cb"] * LENGTH**3 / EI)
    assert r["physical"]["xib_pn_s_per_um"] == pytest.approx(p["xib"] * CN * LENGTH)
    # the Laplace approximation at the optimum: (J^T J)^-1 with J by central differences
    row_obj = result.rows[0]
    lap = row_obj.laplace()
    problem = row_obj.problem
    u = lap.centre_u
    h = 1e-5 * np.where(np.abs(u) > 0, np.abs(u), 1.0)  # cb (linear) may be ~1e-6
    jac = np.stack(
        [
            (problem.residuals_at(u + h[j] * e) - problem.residuals_at(u - h[j] * e)) / (2 * h[j])
            for j, e in enumerate(np.eye(len(u)))
        ],
        axis=1,
    )
    # the exact Jacobian against central differences; the covariance is its (J^T J)^-1
    # (not the differences': they lose ~1e-6 of J, which the inverse of this near-ridge
    # J^T J magnifies to 10 %)
    exact = np.asarray(problem.jacobian(u))
    np.testing.assert_allclose(exact, jac, atol=1e-5 * np.abs(jac).max())
    np.testing.assert_allclose(lap.cov_u, np.linalg.inv(exact.T @ exact), rtol=1e-6)
    assert lap.names == problem.names and lap.log_coordinate["xib"] and not lap.log_coordinate["cb"]


@pytest.mark.slow  # a comparison fit: ~12 s
def test_an_elastic_clamped_beat_is_recovered(tmp_path):
    """Curvature control on a clamped base with an elastic basal compliance (Riedel-Kruse
    et al.'s clamped sperm, a spring at the base): the continuum beat at Sp 200 with
    chi_b_bar = 20 + i (the elastic row's fixed negligible friction), beta at its Hopf
    point (tests/model/test_bases.py's reference). The `+elastic` row reaches R^2 > 0.995 and
    recovers beta within 5 %; chi' and chi_b_bar' within 15 % only: they trade off along a
    ridge of the fit (a stiffer shear with a stiffer base; measured: 10.9 and 22.3 against
    10 and 20 at R^2 0.9993, the same at 8 and 12 elements)."""
    from tests.model.test_bases import _hopf

    sp, chi = 200.0, 10.0
    units = ax.Units(LENGTH, EI, CN)
    freq = sp / (2 * math.pi * units.tau_s)
    chib = 20.0 + 1j * 1e-3 * (1 + math.sqrt(sp))
    beta = _hopf(sp, -3.57 + 15.72j, "beta", chi, ("clamped", 0, 0), chib)
    s = np.linspace(0, 1, 25)
    psi1, _ = _shape(chi, beta, sp, ("clamped", 0, 0), chib, s)
    psi1 = 0.5 * psi1 / psi1[-1]
    path = fourier_file(tmp_path / "elastic.npz", s, psi1, LENGTH, freq)
    result = ax.compare(
        path,
        mechanisms=("curvature",),
        bases=("clamped+elastic",),
        n_elements=8,
        units=units,
        starts=2,
    )
    (r,) = result.to_json()["rows"]
    assert r["base"] == "clamped+elastic" and r["n_free"] == 6 and r["r2"] > 0.995
    p = r["params"]
    assert A0 * (p["beta_re"] + 1j * p["beta_im"]) / 2 == pytest.approx(beta, rel=0.05)
    assert A0**2 * p["chi_re"] / 2 == pytest.approx(chi, rel=0.15)
    assert A0**2 / (p["cb"] + CB_FLOOR) / 2 == pytest.approx(chib.real, rel=0.15)


def test_with_compliance_names_every_kind():
    assert with_compliance(None, False) is None
    assert with_compliance(("free",), True) == ("free+compliance",)
    assert with_compliance(("head+compliance",), True) == ("head+compliance",)
    assert with_compliance(("clamped",), "both") == ("clamped", "clamped+compliance")
    for kind in BASES:  # every kind, with and without, is a valid base name
        assert check_names(None, (kind, kind + COMPLIANCE))[1] == (kind, kind + COMPLIANCE)
    assert with_compliance(("clamped", "head+compliance"), "elastic") == (
        "clamped+elastic",
        "head+elastic",
    )
    for kind in BASES:
        assert check_names(None, (kind + ELASTIC,))[1] == (kind + ELASTIC,)
    assert with_compliance(("free",), "both-elastic") == ("free", "free+elastic")
    assert with_compliance(("pivot",), "all") == ("pivot", "pivot+compliance", "pivot+elastic")
    # the default: the default bases without and with a basal spring; named bases as named
    assert with_compliance(None) == tuple(
        k + f for k in ("clamped", "free", "head") for f in ("", ELASTIC)
    )
    assert with_compliance(("head",)) == ("head",)
    assert with_compliance(None, False) is None
    with pytest.raises(ValueError, match="^compliance: expected True, False, 'elastic', 'both'"):
        ax.compare("human_sperm", compliance="yes")
    with pytest.raises(ValueError, match="^compliance: expected"):
        with_compliance(None, 1)


@pytest.mark.parametrize(
    "argv,bases",
    [
        ([], [k + f for k in ("clamped", "free", "head") for f in ("", ELASTIC)]),
        (["--compliance", "off"], None),
        (["--bases", "head"], ["head"]),
        (["--compliance", "all", "--bases", "free"], ["free", "free+compliance", "free+elastic"]),
        (["--compliance", "off", "--bases", "pivot,head+compliance"], ["pivot", "head+compliance"]),
        (["--compliance", "on"], [b + COMPLIANCE for b in ("clamped", "free", "head")]),
        (["--compliance", "on", "--bases", "pivot,free"], ["pivot+compliance", "free+compliance"]),
        (["--compliance", "both", "--bases", "head"], ["head", "head+compliance"]),
        (["--compliance", "elastic", "--bases", "clamped"], ["clamped+elastic"]),
        (["--bases", "free+elastic,head"], ["free+elastic", "head"]),
        (["--bases", "clamped+compliance", "--head-um", "2,1"], "refused"),
        (["--bases", "head+compliance", "--head-um", "2,1"], ["head+compliance"]),
    ],
)
def test_cli_compliance_reaches_the_library(argv, bases, monkeypatch, capsys):
    """Each valid --compliance / --bases spelling gives compare() these bases (its fits
    replaced by a stub that records them)."""
    seen = {}

    class Stop(Exception):
        pass

    def stub(beat, mechanisms, bases, *args, **kwargs):
        seen["bases"] = None if bases is None else list(bases)
        seen["head"] = kwargs.get("head")
        raise Stop

    monkeypatch.setattr(cli_compare, "compare", stub)
    if bases == "refused":
        assert main(["compare", "--data", "human_sperm", *argv]) == 2
        assert capsys.readouterr().err.startswith("axojax: error: --head-um")
        return
    with pytest.raises(Stop):
        main(["compare", "--data", "human_sperm", *argv])
    assert seen["bases"] == bases
    if "--head-um" in argv:
        assert seen["head"].kind == "head"


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["--compliance", "maybe"], "--compliance"),
        (["--compliance", "ON"], "--compliance"),
        (["--compliance", "both", "--bases", "head,head+compliance"], "--compliance"),
        (["--bases", "hinge+compliance"], "--bases"),
        (["--bases", "head+compliance+compliance"], "--bases"),
        (["--bases", "free,free+compliance,free"], "--bases"),
    ],
)
def test_cli_bad_compliance_is_one_line(argv, flag, capsys):
    code = main(["compare", "--data", "human_sperm", *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert err.startswith(f"axojax: error: {flag}")
