"""``axojax compare``'s units (issue 45, item 6): the whole flagellum's ``--kappa`` and
``--xi-n`` beside the per-filament ``--ei`` and ``--cn``, ``--organism`` presets (kappa,
xi_n and the head), and one warning line when a file of one's own comes without units.
Only the flags are parsed and the units made: no fit."""

import numpy as np
import pytest

import axojax as ax
from axojax.cli import compare as cli
from axojax.cli.common import CLIError
from axojax.cli.main import build_parser, main
from axojax.inverse.comparison.compare import organism_of
from axojax.units import ORGANISMS
from tests.comparison.test_compare import fourier_file


@pytest.fixture(scope="module")
def own_file(tmp_path_factory) -> str:
    s = np.linspace(0, 1, 11)
    psi1 = 0.3 * s * np.exp(-3j * s)
    return fourier_file(tmp_path_factory.mktemp("own") / "beat.npz", s, psi1, 40.0, 20.0)


def _units(argv):
    args = build_parser().parse_args(["compare", *argv])
    beat = ax.read_beat(args.data)
    return cli._units_and_head(args, beat, None)


def test_kappa_and_xi_n_are_the_whole_flagellum(own_file):
    whole, _, _ = _units(["--data", own_file, "--kappa", "1700", "--xi-n", "0.0034"])
    per, _, _ = _units(["--data", own_file, "--ei", "850", "--cn", "0.0017"])
    assert whole == per  # the two-filament preset: kappa = 2 EI, xi_n = 2 c_n
    four, _, _ = _units(
        ["--data", own_file, "--model", "four", "--kappa", "1700", "--xi-n", "0.0034"]
    )
    assert four.ei_pn_um2 == pytest.approx(1700 / 4) and four.cn_pn_s_um2 == pytest.approx(
        0.0034 / 4
    )


@pytest.mark.parametrize("name", ["human_sperm", "bull_sperm", "sea_urchin_sperm", "chlamydomonas"])
def test_organism_presets_have_values_and_sources(name, own_file):
    org = ORGANISMS[name]
    assert org.flagellum.source and org.head_source
    assert 100 <= org.flagellum.bending_rigidity_pn_um2 <= 1e4
    assert 1e-3 <= org.flagellum.normal_drag_pn_s_um2 <= 1e-2
    assert org.head_um[0] >= org.head_um[1] > 0
    assert organism_of(name.replace("_", "-")) is org
    # --organism alone: the library takes its units and head; a flag overrides one value
    units, organism, head = _units(["--data", own_file, "--organism", name])
    assert units is None and organism is org and head is None
    units, _, _ = _units(["--data", own_file, "--organism", name, "--kappa", "1000"])
    assert units.ei_pn_um2 == pytest.approx(500.0)
    assert units.cn_pn_s_um2 == pytest.approx(org.flagellum.normal_drag_pn_s_um2 / 2)


def test_a_file_without_units_warns_once(own_file, capsys):
    _units(["--data", own_file])
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "carries no units" in err[0] and "--organism NAME" in err[0] and "--kappa" in err[0]
    _units(["--data", own_file, "--organism", "bull_sperm"])
    _units(["--data", "human_sperm"])  # a bundled data set knows its flagellum
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["--kappa", "1000", "--ei", "500"], "--kappa"),
        (["--xi-n", "0.003", "--cn", "0.001"], "--xi-n"),
        (["--xi-n", "0.003", "--sperm-number", "100"], "--sperm-number"),
        (["--organism", "mouse"], "--organism"),
        (["--kappa", "-1"], "--kappa"),
    ],
)
def test_bad_units_are_one_line(argv, flag, capsys):
    code = main(["compare", "--data", "human_sperm", *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert err.startswith(f"axojax: error: {flag}")


def test_library_unknown_organism():
    with pytest.raises(ValueError, match="^organism: unknown name 'mouse'"):
        organism_of("mouse")
    assert isinstance(CLIError("x"), Exception)
