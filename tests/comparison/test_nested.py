"""Nested hypotheses in ``compare`` (issue 45, item 1).

Each row's free values contain those of every row it generalises (sliding+curvature
contains sliding and curvature on the same base; a base with a full compliance (cb, xib)
contains the same base with a spring only (cb), which contains the base without), a basal
spring is fitted as its compliance cb = 1/k_b from 0 (a rigid base: the base without it),
and each row starts from the optima of the rows it contains, so no row fits worse than a
row it contains. The first tests are instant; the last fits a small comparison.
"""

import itertools
import json
import math

import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import main
from axojax.inverse.comparison.mechanisms import (
    MECHANISMS,
    build_model,
    contained,
    nested_order,
    row,
)
from axojax.params import CB_FLOOR

UNITS = ax.Units(10.0, 100.0, 0.001)
FREQ = 200.0 / (2 * math.pi * UNITS.tau_s)  # sperm number 200
BASES = [k + s for k in ("clamped", "free", "head") for s in ("", "+elastic", "+compliance")]


def _row(mechanism, base):
    model = build_model("two", 6, base, UNITS)
    return row(mechanism, base, model, UNITS, FREQ)


@pytest.mark.parametrize("mechanism,base", list(itertools.product(MECHANISMS, BASES)))
def test_each_row_frees_what_the_rows_it_contains_free(mechanism, base):
    """The free values of every contained row are among the row's, and the row's others
    can take the value that makes it that row (0 for chi, beta and cb; xib's low end,
    where an elastic base holds it), inside their bounds; at most 6 free values."""
    r = _row(mechanism, base)
    assert len(r.free) <= 6
    for m, b in contained(mechanism, base):
        inner = _row(m, b)
        assert set(inner.free) <= set(r.free), (m, b, inner.free, r.free)
        for name in set(r.free) - set(inner.free):
            lo, hi = r.bounds[name]
            floor = lo if name == "xib" else 0.0
            assert lo <= floor < hi, (name, lo, hi)
            if name == "xib" and "cb" in inner.free:  # the elastic base holds xib there
                assert float(inner.params.xib) == pytest.approx(lo)


def test_contained_rows_and_their_order():
    assert set(contained("sliding+curvature", "head+compliance")) == {
        (m, "head" + s)
        for m in ("sliding", "curvature", "sliding+curvature")
        for s in ("", "+elastic", "+compliance")
    } - {("sliding+curvature", "head+compliance")}
    assert contained("steady", "clamped+elastic") == [("steady", "clamped")]
    assert contained("curvature", "free") == []
    combos = [
        (m, b) for b in ("clamped+compliance", "clamped+elastic", "clamped") for m in MECHANISMS
    ]
    order = nested_order(combos)
    for i, (m, b) in enumerate(order):  # every row after the rows it contains
        assert set(contained(m, b)) <= set(order[:i])


def test_zero_compliance_is_the_base_without_it():
    """cb = 0 (k_b = 1 / CB_FLOOR) puts the beat's eigenvalue where the base without
    compliance has it, to 1e-6 of the frequency, on a curvature-control point."""
    prm = ax.Params(p=0.0, omega0=200.0, chi_re=2000.0, beta_re=30.0, beta_im=-80.0)
    shift = 200.0j
    without = ax.nearest_mode(build_model("two", 8, "clamped", UNITS), prm, shift)
    model = build_model("two", 8, "clamped+elastic", UNITS)
    rigid = ax.nearest_mode(model, prm.replace(cb=0.0, xib=1e-3), shift)
    assert float(prm.replace(cb=0.0).kb) == pytest.approx(1 / CB_FLOOR)
    assert abs(complex(rigid.eigenvalue) - complex(without.eigenvalue)) < 1e-6 * 200.0
    soft = ax.nearest_mode(model, prm.replace(cb=1e-2, xib=1e-3), shift)
    assert abs(complex(soft.eigenvalue) - complex(without.eigenvalue)) > 1e-3 * 200.0


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_no_row_fits_worse_than_a_row_it_contains(tmp_path, capsys):
    """A small comparison (curvature and sliding+curvature on a clamped base without and
    with a spring) on the continuum curvature-control beat with noise: each row's R^2 is
    at least that of every row it contains (0.01 slack; the rigid spring of cb = 0 differs
    from no compliance by 1e-9), those not asked for (sliding control) fitted for their
    optima only, and the JSON names them."""
    from tests.comparison.test_compare import fourier_file
    from tests.regulation.test_mechanisms import _hopf, _shape

    rng = np.random.default_rng(1)
    beta_bar = _hopf(200.0, -2.7 + 10.6j, solve_for="beta", other=10.0)
    s = np.linspace(0, 1, 21)
    psi1 = _shape(10.0, beta_bar, 200.0, s)
    psi1 = 0.5 * psi1 / psi1[-1] + 0.01 * (rng.normal(size=21) + 1j * rng.normal(size=21))
    path = fourier_file(tmp_path / "curvature.npz", s, psi1, 10.0, FREQ)
    out = tmp_path / "nested.json"
    argv = ["compare", "--data", str(path), "--mechanisms", "curvature,sliding+curvature"]
    argv += ["--bases", "clamped,clamped+elastic", "--elements", "6", "--starts", "1"]
    argv += ["--ei", "100", "--cn", "0.001", "--out", str(out)]
    assert main(argv) == 0
    capsys.readouterr()
    doc = json.loads(out.read_text())
    rows = {f"{r['mechanism']}/{r['base']}": r for r in doc["rows"]}
    assert set(rows["sliding+curvature/clamped+elastic"]["contains"]) == {
        f"{m}/clamped{s}"
        for m in ("sliding", "curvature", "sliding+curvature")
        for s in ("", "+elastic")
    } - {"sliding+curvature/clamped+elastic"}
    assert rows["curvature/clamped"]["contains"] == []
    # the contained rows not asked for (sliding control) were fitted for their optima only
    aux = {f"{r['mechanism']}/{r['base']}": r for r in doc["auxiliary_rows"]}
    assert set(aux) == {"sliding/clamped", "sliding/clamped+elastic"}
    every = {**rows, **aux}
    for name, r in rows.items():
        for inner in r["contains"]:
            assert r["r2"] >= every[inner]["r2"] - 0.01, (name, r["r2"], inner, every[inner]["r2"])
    assert "cb_um_per_pn" in rows["curvature/clamped+elastic"]["physical"]
    assert np.isfinite(rows["curvature/clamped"]["r2"])


@pytest.mark.slow  # a comparison of 6 rows: about a minute
def test_a_synthetic_organism_beat_is_found_and_nested(tmp_path):
    """Issue 45's acceptance on a synthetic beat of an organism's size and units: a
    Chlamydomonas flagellum (12 um, 50 Hz, its preset's kappa and xi_n), the beat of
    sliding+curvature on clamped+elastic at one of its exact Hopf points plus 0.02 rad of
    noise (axojax.inverse.comparison.synthetic). The truth row is successful at the
    observed beat and fits to the noise (R^2 > 0.97); no row falls below a row it contains."""
    from axojax.inverse.comparison.synthetic import synthetic_beat

    truth = ("sliding+curvature", "clamped+elastic")
    rng = np.random.default_rng(3)
    path, _ = synthetic_beat(
        tmp_path / "c.npz", "chlamydomonas", truth, 12.0, 50.0, rng, n_elements=8
    )
    doc = ax.compare(
        path,
        mechanisms=("curvature", "sliding+curvature"),
        bases=("clamped", "clamped+elastic"),
        organism="chlamydomonas",
        n_elements=8,
        starts=2,
    ).to_json()
    rows = {f"{r['mechanism']}/{r['base']}": r for r in doc["rows"]}
    every = {**rows, **{f"{r['mechanism']}/{r['base']}": r for r in doc["auxiliary_rows"]}}
    t = rows["/".join(truth)]
    assert t["status"] == "successful" and t["r2"] > 0.97, (t["status"], t["r2"])
    assert abs(t["frequency_hz"] - 50.0) < 0.02 * 50.0
    for name, r in rows.items():
        for inner in r["contains"]:
            assert r["r2"] >= every[inner]["r2"] - 0.01, (name, r["r2"], inner, every[inner]["r2"])
