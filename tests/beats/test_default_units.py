"""The physical units a fit of a measured beat assumes when the user gives none (issue 30:
``axojax compare --data human_sperm`` with its defaults): a bundled data set carries its
organism's flagellum (bending rigidity and drag from the literature), a user's file does
not and keeps axojax's defaults; explicit units always win, and the table says which."""

import math

import numpy as np
import pytest

import axojax as ax
from axojax.beats.bundled import DATASETS, HUMAN_SPERM
from axojax.cli import compare as cli_compare
from axojax.cli.main import main
from axojax.inverse.comparison.compare import default_units, render_table
from axojax.units import Flagellum
from tests.comparison.test_compare import fourier_file


def test_bundled_beat_carries_its_flagellum():
    beat = ax.datasets.human_sperm()
    assert beat.flagellum == HUMAN_SPERM == DATASETS["human_sperm"].flagellum
    assert ax.beats.read_beat("human_sperm").flagellum == HUMAN_SPERM
    assert beat.summary()["flagellum"]["bending_rigidity_pn_um2"] == 1900.0
    assert ax.datasets.info("human_sperm").to_json()["flagellum"]["normal_drag_pn_s_um2"] == 3.2e-3


def test_lighthill_drag_of_the_human_sperm():
    """xi_n is Lighthill's coefficient with the inputs ``source`` states (recomputed here)."""
    mu_pn_s_um2, a, lam = 1e-3, 0.25, 45.0  # 1 mPa s = 1e-3 pN s/um^2
    xi = 4 * math.pi * mu_pn_s_um2 / (math.log(2 * 0.09 * lam / a) + 0.5)
    assert HUMAN_SPERM.normal_drag_pn_s_um2 == pytest.approx(xi, rel=0.02)
    assert "Lighthill" in HUMAN_SPERM.source and "Saggiorato" in HUMAN_SPERM.source


def test_user_file_has_no_flagellum_and_keeps_axojax_units(tmp_path):
    s = np.linspace(0, 1, 12)
    f = fourier_file(tmp_path / "b.npz", s, 0.3 * np.exp(-3j * s), 30.0, 20.0)
    beat = ax.beats.read_beat(f)
    assert beat.flagellum is None and beat.summary()["flagellum"] is None
    units, source = default_units(beat, "two")
    assert units == ax.Units(30.0, ax.Units().ei_pn_um2, ax.Units().cn_pn_s_um2)
    assert source.startswith("axojax's default units")


@pytest.mark.parametrize("model,n", [("two", 2), ("seven", 7)])
def test_flagellum_is_shared_by_the_filaments(model, n):
    beat = ax.datasets.human_sperm()
    units, source = default_units(beat, model)
    assert units.length_um == beat.length_um
    assert units.ei_pn_um2 * n == pytest.approx(1900.0)
    assert units.cn_pn_s_um2 * n == pytest.approx(3.2e-3)
    assert f"shared by {n} filaments" in source
    # the two-filament continuum's sperm number: omega xi_n L^4 / kappa
    sp = 2 * math.pi * float(beat.frequency_hz) * 3.2e-3 * beat.length_um**4 / 1900.0
    assert float(units.omega0_from_hz(beat.frequency_hz)) == pytest.approx(sp, rel=1e-12)


def test_one_rule_gives_the_units_of_a_beat(tmp_path):
    """ax.beats.beat_units is the rule of fit, compare and the whole beat's comparison:
    each value given wins; the one not given is the flagellum's share (an organism's
    before the data set's), else axojax's default; the words say where they came from."""
    from axojax.beats import beat_units
    from axojax.beats.units import DEFAULT_SOURCE
    from axojax.units import ORGANISMS

    sperm, bull = ax.datasets.human_sperm(), ORGANISMS["bull_sperm"]
    units, words = beat_units(sperm, 2)
    assert (units, words) == default_units(sperm, "two")
    assert units == ax.Units(sperm.length_um, 950.0, 1.6e-3)
    assert beat_units(sperm, 2, ei_pn_um2=300.0)[0] == ax.Units(sperm.length_um, 300.0, 1.6e-3)
    assert beat_units(sperm, 2, ei_pn_um2=300.0, cn_pn_s_um2=1e-3) == (
        ax.Units(sperm.length_um, 300.0, 1e-3),
        "given",
    )
    units, words = beat_units(sperm, 7, organism=bull)
    assert units == bull.flagellum.units(sperm.length_um, 7)
    assert words.startswith("the bull_sperm preset: kappa 1700 pN um^2") and "7 filaments" in words
    s = np.linspace(0, 1, 12)
    own = ax.beats.read_beat(fourier_file(tmp_path / "b.npz", s, 0.3 * s, 30.0, 20.0))
    d = ax.Units()
    assert beat_units(own, 2) == (ax.Units(30.0, d.ei_pn_um2, d.cn_pn_s_um2), DEFAULT_SOURCE)
    assert beat_units(own, 2, cn_pn_s_um2=1e-3) == (ax.Units(30.0, d.ei_pn_um2, 1e-3), "given")
    with pytest.raises(ValueError, match="^unit ei_pn_um2 must be"):
        beat_units(own, 2, ei_pn_um2=-1.0)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_bad_flagellum_is_one_line(bad):
    with pytest.raises(ValueError, match="^flagellum bending_rigidity_pn_um2 must be"):
        Flagellum(bad, 1e-3)
    with pytest.raises(ValueError, match="^n_filaments: expected a positive integer"):
        HUMAN_SPERM.units(40.0, 0)


@pytest.mark.parametrize(
    "argv,ei,cn",
    [
        ([], None, None),  # the library's default: the data set's flagellum
        (["--ei", "500"], 500.0, 3.2e-3 / 2),
        (["--cn", "0.002"], 1900.0 / 2, 0.002),
        (["--ei", "500", "--cn", "0.002"], 500.0, 0.002),
    ],
)
def test_cli_units_default_to_the_data_sets_flagellum(argv, ei, cn, monkeypatch):
    seen = {}

    class Stop(Exception):
        pass

    def stub(beat, mechanisms, bases, *args, **kwargs):
        seen["units"] = kwargs["units"]
        raise Stop

    monkeypatch.setattr(cli_compare, "compare", stub)
    with pytest.raises(Stop):
        main(["compare", "--data", "human_sperm", *argv])
    if ei is None:
        assert seen["units"] is None
    else:
        assert seen["units"].ei_pn_um2 == pytest.approx(ei)
        assert seen["units"].cn_pn_s_um2 == pytest.approx(cn)


def test_table_names_the_units():
    doc = {
        "data": {"frequency_hz": 10.0},
        "rows": [],
        "model": {
            "preset": "two",
            "elements": 8,
            "length_um": 46.0,
            "ei_pn_um2": 950.0,
            "cn_pn_s_um2": 1.6e-3,
            "sperm_number": 500.0,
            "units_source": "the data set's flagellum: kappa 1900 pN um^2",
        },
    }
    last = render_table(doc).splitlines()[-1]
    assert last.startswith("units: EI 950 pN um^2 and c_n 0.0016 pN s/um^2 per filament")
    assert last.endswith("(the data set's flagellum: kappa 1900 pN um^2)")


def test_cli_compare_runs_in_the_data_sets_units(capsys):
    """End to end, one small row: the JSON says which units the rows were fitted in."""
    import json

    argv = ["compare", "--data", "human_sperm", "--mechanisms", "sliding", "--bases", "clamped"]
    assert main([*argv, "--elements", "4", "--starts", "1", "--json"]) == 0
    model = json.loads(capsys.readouterr().out)["model"]
    assert model["ei_pn_um2"] == pytest.approx(950.0) and model["cn_pn_s_um2"] == pytest.approx(
        1.6e-3
    )
    assert model["units_source"].startswith("the data set's flagellum: kappa 1900 pN um^2")
    sp = 2 * math.pi * 10.257 * 3.2e-3 * model["length_um"] ** 4 / 1900.0
    assert model["sperm_number"] == pytest.approx(sp, rel=0.01)  # observed f within 1 % of 10.257


@pytest.mark.parametrize(
    "flags, ei, cn, source",
    [
        ([], 1900.0 / 2, 3.2e-3 / 2, "the data set's flagellum"),
        (["--ei", "300"], 300.0, 3.2e-3 / 2, "--ei given"),
        (["--ei", "300", "--cn", "0.001"], 300.0, 1e-3, "given"),
    ],
    ids=["flagellum", "ei-given", "both-given"],
)
def test_cli_fit_data_uses_the_data_sets_flagellum_as_compare_does(flags, ei, cn, source, capsys):
    """``axojax fit --data human_sperm`` takes the units that ``axojax compare`` takes:
    EI and c_n not given come from the data set's flagellum (kappa and xi_n shared by the
    model's filaments: 2 for ``two``), at the data's length; the report says where they
    came from. (Before, fit kept axojax's 12 um cilium's units for a 46 um sperm: 0.12 Hz
    against the measured 10.25.)"""
    import json

    argv = ["fit", "--model", "two", "--elements", "6", "--free", "p", "--data", "human_sperm"]
    code = main(argv + ["--starts", "1", "--no-mesh-check", "--json", *flags])
    assert code in (0, 1)  # 1: the steady load misses this beat's shape (a verdict, not an error)
    units = json.loads(capsys.readouterr().out)["units"]
    assert units["length_um"] == pytest.approx(ax.datasets.human_sperm().length_um)
    assert units["ei_pn_um2"] == pytest.approx(ei) and units["cn_pn_s_um2"] == pytest.approx(cn)
    assert source in units["source"]


def test_cli_fit_user_file_keeps_axojax_units(tmp_path, capsys):
    """A user's own beat file carries no flagellum: axojax's default EI and c_n, the
    file's length, and the report says so."""
    import json

    s = np.linspace(0, 1, 12)
    f = fourier_file(tmp_path / "b.npz", s, 0.3 * np.exp(-3j * s), 30.0, 20.0)
    argv = ["fit", "--model", "two", "--elements", "6", "--free", "p", "--data", str(f)]
    code = main(argv + ["--starts", "1", "--no-mesh-check", "--json"])
    assert code in (0, 1)
    units = json.loads(capsys.readouterr().out)["units"]
    assert units["ei_pn_um2"] == pytest.approx(ax.Units().ei_pn_um2)
    assert units["cn_pn_s_um2"] == pytest.approx(ax.Units().cn_pn_s_um2)
    assert units["length_um"] == pytest.approx(ax.beats.read_beat(f).length_um)
    assert "default" in units["source"]
