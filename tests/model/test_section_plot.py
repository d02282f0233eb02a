"""The orientation rule of docs/model.md section 4, rotation_deg, and the cross-section figure
(``axojax.plotting.plot_section``, ``axojax plot --model``)."""

import json

import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import main
from axojax.plotting import group_bending_directions, plot_section
from tests.model.test_invariants import assert_same_spectrum, sorted_spectrum


def net_directions(section):
    """Sum of each group's unit vectors n_a, computed here from the positions."""
    out = {}
    for a in section.active_pairs:
        d = section.positions[a.j] - section.positions[a.i]
        out.setdefault(a.group, []).append(d / np.hypot(*d))
    return {g: np.sum(v, axis=0) for g, v in out.items()}


@pytest.mark.parametrize("name", ["four", "seven"])
def test_active_groups_bend_along_y(name):
    """Each active group's net bending direction lies along +-y, the two opposite."""
    dirs = net_directions(ax.models.preset(name).section)
    assert sorted(dirs) == [0, 1]
    for v in dirs.values():
        assert abs(v[1]) < 1e-12 * np.hypot(*v) and abs(v[0]) > 0.5
    assert np.sign(dirs[0][0]) == -np.sign(dirs[1][0])
    for g, v in group_bending_directions(ax.models.preset(name).section).items():
        np.testing.assert_allclose(v, dirs[g], atol=1e-14)


def test_nine_groups_closest_to_the_rule():
    """Nine: the groups' middles sit 10 degrees from +-z, so each net direction is 10
    degrees from +-y (docs/model.md section 4)."""
    for v in net_directions(ax.models.nine().section).values():
        assert np.degrees(np.arccos(abs(v[0]) / np.hypot(*v))) == pytest.approx(10.0, abs=1e-9)


@pytest.mark.parametrize("name,deg", [("four", 45.0), ("seven", 30.0), ("nine", -17.0)])
def test_rotation_deg_is_a_pure_rotation(name, deg):
    """rotation_deg turns every position (from +z towards +y), i.e. CrossSection.rotated by
    -deg, and leaves links and pairs alone; with isotropic bending the spectrum is unchanged."""
    base = ax.models.preset(name).section
    turned = ax.models.preset(name, rotation_deg=deg).section
    np.testing.assert_allclose(
        turned.positions, base.rotated(np.radians(-deg)).positions, atol=1e-14
    )
    assert turned.links == base.links and turned.active_pairs == base.active_pairs
    iso = ax.Params(p=300.0, ks=1e4, kl=10.0, out_of_plane=1.0)
    a = sorted_spectrum(ax.models.preset(name, n_elements=4), iso)
    b = sorted_spectrum(ax.models.preset(name, n_elements=4, rotation_deg=deg), iso)
    assert_same_spectrum(a, b)
    assert_same_spectrum(b, a)


def test_rotation_moves_the_mode_out_of_plane():
    """With the paper's out_of_plane = 2 the orientation matters: seven at rotation 0 beats
    in the y plane (out-of-plane 0.022, docs/model.md section 6), the old 30-degree placement does not."""
    params = ax.Params(p=300.0)
    planar = ax.dominant_mode(ax.models.seven(n_elements=6), params)
    old = ax.dominant_mode(ax.models.seven(n_elements=6, rotation_deg=30.0), params)
    assert float(planar.out_of_plane_ratio) < 0.05 < float(old.out_of_plane_ratio)


@pytest.mark.parametrize("name", ["single", "two", "four", "seven", "nine"])
def test_plot_section_draws_every_part(name):
    fig = plot_section(ax.models.preset(name))
    a = fig.axes[0]
    section = ax.models.preset(name).section
    texts = {t.get_text() for t in a.texts}
    assert {str(f) for f in range(section.n_filaments)} <= texts  # numbered filaments
    labels = [t.get_text() for t in a.get_legend().get_texts()]
    assert "beat plane (z = 0)" in labels
    if section.active_pairs:
        assert any("net bending direction" in l for l in labels)
        assert len(a.patches) >= section.n_filaments + len(section.active_pairs) + len(
            group_bending_directions(section)
        )


def test_cli_plot_section(tmp_path, capsys):
    out = tmp_path / "section.png"
    assert main(["plot", "--model", "seven", "--out", str(out), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc == {"figure": str(out), "kind": "section", "model": "seven"}
    assert out.stat().st_size > 10_000 and out.read_bytes()[:4] == b"\x89PNG"
    out2 = tmp_path / "old.png"
    assert main(["plot", "--model", "four", "--rotation-deg", "45", "--out", str(out2)]) == 0
    assert out2.is_file()
    model_file = tmp_path / "pair.json"
    model_file.write_text(
        json.dumps(
            {
                "filaments": [{"position": [0, 0]}, {"position": [1, 0]}],
                "links": [{"between": [0, 1]}],
                "active_pairs": [{"between": [0, 1]}],
            }
        )
    )
    assert main(["plot", "--model-file", str(model_file), "--out", str(tmp_path / "file.png")]) == 0


@pytest.mark.parametrize(
    "args,flag",
    [
        (["--out", "x.png"], "FILE"),
        (["--model", "eleven", "--out", "x.png"], "--model"),
        (["--model", "two", "--rotation-deg", "10", "--out", "x.png"], "--rotation-deg"),
        (["--model", "seven", "--rotation-deg", "nan", "--out", "x.png"], "--rotation-deg"),
        (["some.npz", "--model", "seven", "--out", "x.png"], "--model"),
        (["some.npz", "--rotation-deg", "5", "--out", "x.png"], "--rotation-deg"),
        (["--model", "seven", "--out", "/nonexistent-dir/x.png"], "--out"),
    ],
)
def test_cli_plot_errors(args, flag, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["plot", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and flag in err, err
