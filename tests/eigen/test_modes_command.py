"""``axojax modes`` JSON output against the library and docs/model.md."""

import json

import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import main


def modes_json(args, capsys):
    assert main(["modes", *args, "--json"]) == 0
    out, err = capsys.readouterr()
    return json.loads(out)


def test_modes_single(capsys):
    doc = modes_json(["--model", "single", "--p", "300", "--top", "3"], capsys)
    assert doc["model"] == "single" and doc["n_dof"] == 20
    assert doc["tau_s"] == pytest.approx(0.85536, rel=1e-12)
    assert len(doc["eigenvalues"]) == 3
    d = doc["dominant"]
    assert d["classification"] == "flutter" and d["direction"] == "anterograde"
    assert d["eigenvalue"][0] == pytest.approx(4360.456, abs=5e-4)
    assert d["frequency_hz"] == pytest.approx(1865.222 / (2 * np.pi * 0.85536), rel=1e-6)
    assert d["growth_rate_per_s"] == pytest.approx(4360.456 / 0.85536, rel=1e-6)
    assert d["velocity_um_per_s"] == pytest.approx(
        d["wavelength_um"] * d["frequency_hz"], rel=1e-12
    )
    assert d["out_of_plane_ratio"] == 0.0


def test_modes_units_and_tie(capsys, seven):
    doc = modes_json(
        [
            "--model",
            "seven",
            "--p",
            "300",
            "--ks",
            "1e4",
            "--kl-ratio",
            "1000",
            "--length-um",
            "10",
            "--cn",
            "0.002",
        ],
        capsys,
    )
    mode = ax.dominant_mode(seven, ax.Params(p=300.0, ks=1e4, kl=10.0))
    units = ax.Units(length_um=10.0, cn_pn_s_um2=0.002)
    assert doc["dominant"]["frequency_hz"] == pytest.approx(
        float(mode.frequency_hz(units)), rel=1e-10
    )
    assert doc["dominant"]["wavelength_um"] == pytest.approx(
        float(mode.wavelength_um(units)), rel=1e-10
    )


def test_modes_stable_has_no_wave(capsys):
    doc = modes_json(["--model", "seven", "--p", "10"], capsys)
    d = doc["dominant"]
    assert d["classification"] == "stable" and d["eigenvalue"][0] < 0
    assert d["direction"] is None and d["wavelength_um"] is None


def test_modes_table(capsys):
    assert main(["modes", "--model", "two", "--p", "300"]) == 0
    out = capsys.readouterr().out
    assert "dominant mode: flutter" in out and "Hz" in out


def test_model_file_equals_preset(tmp_path, capsys):
    sec = ax.models.seven().section
    toml = ['name = "mine"', "dimensions = 2"]
    for y, z in sec.positions:
        toml += ["[[filaments]]", f"position = [{float(y)!r}, {float(z)!r}]"]
    for l in sec.links:
        toml += ["[[links]]", f"between = [{l.i}, {l.j}]", f'kind = "{l.kind}"']
    for a in sec.active_pairs:
        toml += ["[[active_pairs]]", f"between = [{a.i}, {a.j}]", f"group = {a.group}"]
    path = tmp_path / "mine.toml"
    path.write_text("\n".join(toml) + "\n")
    a = modes_json(["--model-file", str(path), "--p", "280"], capsys)
    b = modes_json(["--model", "seven", "--p", "280"], capsys)
    assert a["model"] == "mine"
    np.testing.assert_allclose(a["dominant"]["eigenvalue"], b["dominant"]["eigenvalue"], rtol=1e-10)
