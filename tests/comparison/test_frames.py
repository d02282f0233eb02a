"""The frame psi is compared in (issue 45, item 7; docs/model.md section 8, frames): as
recorded (``lab``), or model and data both relative to the basal tangent (``basal``:
psi(s) - psi(0)); and the warning when a held base wins on a beat whose psi_1(0) is large."""

import json

import numpy as np
import pytest

import axojax as ax
from axojax.beats import ShapeTarget
from axojax.beats.data import beat_from_kymograph
from axojax.beats.frames import in_basal_frame
from axojax.cli.main import main
from axojax.inverse.comparison.verdict import base_warning
from axojax.inverse.predictions import model_psi1
from tests.comparison.test_compare import fourier_file


def _kymograph(phase_at_base=0.4):
    t = np.arange(0, 0.6, 0.0025)
    s = np.linspace(0, 10, 11)
    wave = 0.5 * np.cos(2 * np.pi * (10 * t[:, None] - s[None] / 12))
    wobble = phase_at_base * np.sin(2 * np.pi * 10 * t[:, None] + 0.3)  # the base's rotation
    return t, s, wave + wobble


def test_basal_frame_of_a_kymograph_is_the_reduction_of_the_shifted_angles():
    """in_basal_frame (psi_1 - psi_1(0), per cycle too) = reducing psi(s, t) - psi(0, t)
    from scratch: the reduction is linear in psi on one beat phase."""
    t, s, psi = _kymograph()
    beat = beat_from_kymograph(t, s, psi)
    moved = in_basal_frame(beat)
    ref = beat_from_kymograph(t, s, psi - psi[:, :1])
    np.testing.assert_allclose(moved.modes.psi1, ref.modes.psi1, atol=1e-3)
    np.testing.assert_allclose(moved.psi1_cycles.mean(axis=0), moved.modes.psi1, atol=1e-12)
    assert moved.modes.psi1[0] == 0 and abs(beat.modes.psi1[0]) > 0.3
    with pytest.raises(ValueError, match="basal frame needs psi at the base"):
        in_basal_frame(beat.exclude_base(2.0))


def test_model_psi1_in_the_basal_frame():
    """psi_1(s) - psi_1(0) of the same component, for a free base's mode (whose psi_1(0)
    is not 0: the rigid motion turns the base)."""
    model = ax.models.two(n_elements=6, base=ax.models.Base("free"))
    prm = ax.Params(p=0.0, chi_re=2000.0, beta_re=30.0, beta_im=-80.0, omega0=200.0)
    mode = ax.nearest_mode(model, prm, 200.0j)
    s = np.linspace(0, 1, 7)
    lab = np.asarray(model_psi1(model, mode, s))
    basal = np.asarray(model_psi1(model, mode, s, frame="basal"))
    assert abs(lab[0]) > 1e-3 * np.abs(lab).max()
    np.testing.assert_allclose(basal, lab - lab[0], atol=1e-12 * np.abs(lab).max())
    with pytest.raises(ValueError, match="unknown shape frame"):
        ShapeTarget(s, lab, 0.1, frame="head")


def _doc(psi0_share, base="clamped+elastic", frame="lab"):
    s = np.linspace(0, 1, 11)
    psi = s + psi0_share
    return {
        "data": {
            "s_um": list(s),
            "psi1": [[x, 0.0] for x in psi],
            "psi1_sigma_rad": {"median": 0.01},
            "frame": frame,
        }
    }, {"base": base}


def test_warning_when_a_held_base_wins_on_a_moving_base():
    doc, best = _doc(0.5)
    assert "holds psi_1(0) = 0" in base_warning(doc, best) and "--frame basal" in base_warning(
        doc, best
    )
    assert base_warning(*_doc(0.01)) is None  # psi_1(0) small: consistent with a held base
    assert base_warning(*_doc(0.5, base="free")) is None
    assert base_warning(*_doc(0.5, frame="basal")) is None


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_cli_compares_in_the_basal_frame(tmp_path, capsys):
    """A valid Fourier-mode file whose psi_1(0) is large: compared in the basal frame, the
    JSON says so and the data's psi_1(0) is 0; a file not starting at the base is refused
    in one line."""
    s = np.linspace(0, 1, 21)
    psi1 = 0.3 + 0.5 * s * np.exp(-4j * s)
    path = fourier_file(tmp_path / "b.npz", s, psi1, 12.0, 30.0)
    out = tmp_path / "b.json"
    argv = ["compare", "--data", path, "--mechanisms", "curvature", "--bases", "free"]
    argv += ["--elements", "4", "--starts", "1", "--ei", "100", "--cn", "0.001", "--frame", "basal"]
    assert main([*argv, "--out", str(out)]) == 0
    capsys.readouterr()
    doc = json.loads(out.read_text())
    assert doc["data"]["frame"] == "basal" and doc["data"]["psi1"][0] == [0.0, 0.0]
    assert np.isfinite(doc["rows"][0]["r2"])
    cut = fourier_file(tmp_path / "c.npz", s[3:], psi1[3:], 12.0, 30.0)
    code = main(["compare", "--data", cut, "--frame", "basal", "--ei", "100", "--cn", "0.001"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "basal frame" in err
