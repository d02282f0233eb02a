"""``axojax compare --target limit-cycle`` (issue 47 item 5): the regulated mechanisms ranked
on the whole beat, with the linear comparison's statuses and verdict.

The beat is tests/whole_beat/test_whole_beat_fit.py's synthetic curvature-control beat (clamped, 50 Hz,
static curvature -0.14 rad/um, dynamic amplitude 0.9 rad, noise 0.02 rad) as a Fourier-mode
file."""

import json

import pytest
from scipy.stats import chi2

from axojax.cli.main import main
from axojax.inverse.comparison.verdict import verdict
from tests.whole_beat.test_whole_beat_fit import UNITS, beat_file  # noqa: E402

UNIT_FLAGS = ["--ei", str(UNITS.ei_pn_um2), "--cn", str(UNITS.cn_pn_s_um2)]


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "extra, flag",
    [
        (["--mechanisms", "steady"], "--mechanisms"),
        (["--compliance", "on"], "--compliance"),
    ],
)
def test_bad_whole_beat_comparisons_are_one_line(tmp_path, capsys, extra, flag):
    """The steady load (its whole beat is
    ``axojax fit --target limit-cycle``), and flags of the linear comparison only: one line
    naming the flag, exit 2, before any fit."""
    path = beat_file(tmp_path)
    argv = ["compare", "--target", "limit-cycle", "--data", str(path), *UNIT_FLAGS, *extra]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"axojax: error: {flag}: ") and "\n" not in err, err


@pytest.mark.parametrize("frame", ["basal"])  # the default, lab, is every other test's
def test_the_frame_reaches_the_whole_beat(tmp_path, capsys, monkeypatch, frame):
    """``--frame lab|basal`` with ``--target limit-cycle``: compare passes it to
    ``compare_whole_beat``, fit to ``fit_recording`` (each stopped there by a stand-in, so
    no fit runs); a fit that is not of the whole beat refuses ``--frame basal`` in one
    line."""
    import axojax.cli.fit.whole_beat as fit_cli
    import axojax.inverse.whole_beat.compare as wbc

    seen = {}

    def stop(name):
        def stand_in(*args, **kwargs):
            seen[name] = kwargs.get("frame")
            raise ValueError("stopped by the test")

        return stand_in

    monkeypatch.setattr(wbc, "compare_whole_beat", stop("compare"))
    monkeypatch.setattr(fit_cli, "fit_recording", stop("fit_recording"))
    path = beat_file(tmp_path)
    argv = ["compare", "--target", "limit-cycle", "--data", str(path), *UNIT_FLAGS]
    assert main([*argv, "--frame", frame]) == 2
    argv = ["fit", "--target", "limit-cycle", "--mechanism", "curvature", "--data", str(path)]
    assert main([*argv, *UNIT_FLAGS, "--frame", frame]) == 2
    assert seen == {"compare": frame, "fit_recording": frame}
    capsys.readouterr()
    argv = ["fit", "--free", "p", "--target-frequency", "30", "--frame", "basal"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("axojax: error: --frame basal: ") and "\n" not in err, err


def test_the_verdict_counts_the_whole_beats_residuals():
    """The verdict's chi^2 bar takes the document's residual count (3 S + 1 for the whole
    beat: psi_0, Re and Im of psi_1, the frequency) instead of the linear 2 S + 2."""
    S, n_free = 24, 5
    row = {
        "mechanism": "curvature",
        "base": "clamped",
        "status": "successful",
        "r2": 0.99,
        "chi2_per_dof": 1.2,
        "n_free": n_free,
        "weight": 1.0,
    }
    doc = {"rows": [row], "data": {"s_um": list(range(S))}, "n_residuals": 3 * S + 1}
    dof = 3 * S + 1 - n_free
    assert verdict(doc)["chi2_per_dof_max"] == pytest.approx(chi2.ppf(0.99, dof) / dof)
    del doc["n_residuals"]
    dof = 2 * S + 2 - n_free
    assert verdict(doc)["chi2_per_dof_max"] == pytest.approx(chi2.ppf(0.99, dof) / dof)


@pytest.mark.slow
def test_curvature_control_wins_its_own_beat(tmp_path, capsys):
    """On the curvature-control beat, curvature on clamped ranks first, successful, and the
    verdict says it fits (R^2 with the amplitude about 0.997); sliding on clamped, which
    cannot reach that beat as a stable orbit, is ranked below with its reason. The JSON
    has every row's values in physical units and the measures of its orbit."""
    path = beat_file(tmp_path)
    out = tmp_path / "cmp.json"
    argv = ["compare", "--target", "limit-cycle", "--data", str(path), *UNIT_FLAGS]
    argv += ["--mechanisms", "curvature,sliding", "--elements", "10", "--params"]
    argv += ["--out", str(out)]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "verdict: curvature on clamped fits this beat" in text
    doc = json.loads(out.read_text())
    best, other = doc["rows"]
    assert (best["mechanism"], best["status"]) == ("curvature", "successful")
    assert best["r2"] > 0.99 and best["weight"] == pytest.approx(1.0)
    assert best["physical"]["m0_pn"] == pytest.approx(-70.0, rel=0.1)
    assert best["physical"]["f_sat_pn_per_um"] == pytest.approx(1000.0, rel=0.1)
    assert best["static_curvature_rad_per_um"] == pytest.approx(-0.144, rel=0.05)
    assert other["mechanism"] == "sliding"
    assert other["status"] == "successful" or other["reason"]
    assert doc["verdict"]["fits"] == "fits"
