"""What a new user meets (issue 33): the bundled data sets listed with source and licence
(``ax.datasets.names()``, ``axojax data --list``), ``axojax plot`` without ``--out``
(the figure beside its input), the plot and fit help texts saying what the code does, and
a scalar fit report's figure with each unit on its own axis."""

from __future__ import annotations

import json
import pathlib
import re

import matplotlib
import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import build_parser, main

matplotlib.use("Agg")

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA_README = (ROOT / "axojax" / "data" / "README.md").read_text()


def _one_line_error(capsys, argv: list[str], flag: str) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and flag in err, err
    return err


# -- bundled data sets --------------------------------------------------------------------


def test_datasets_names_cover_every_bundled_file_with_source_and_licence():
    names = ax.datasets.names()
    assert names == ("human_sperm",)
    bundled = sorted(p.name for p in ax.datasets.DATA.glob("*.npz"))
    assert sorted(ax.datasets.info(n).file for n in names) == bundled
    for name in names:
        d = ax.datasets.info(name)
        assert (ax.datasets.DATA / d.file).is_file()
        assert ax.datasets.path(name) == ax.datasets.DATA / d.file
        # the README (the full record) states this data set's file, source and licence
        assert f"`{d.file}`" in DATA_README
        repo = re.search(r"github\.com/[\w.-]+/[\w.-]+", d.source).group(0)
        assert repo in DATA_README
        assert d.licence.split(" (")[0] in DATA_README  # "CC0 1.0 Universal"
        assert "Ren" in d.citation and "PMID 38853842" in d.citation
        assert "PMID 38853842" in DATA_README
    with pytest.raises(ValueError, match="unknown data set 'nope'; bundled: human_sperm"):
        ax.datasets.info("nope")


def test_cli_data_list_text_and_json(capsys):
    assert main(["data", "--list"]) == 0
    text = capsys.readouterr().out
    assert text.startswith("human_sperm: ")
    assert "licence   CC0 1.0 Universal" in text
    assert "source    https://github.com/polymaths-lab/3d-sperm-counter-vortices" in text
    assert main(["data", "--list", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [d["name"] for d in doc["datasets"]] == list(ax.datasets.names())
    entry = doc["datasets"][0]
    assert set(entry) == {
        "name",
        "file",
        "description",
        "source",
        "licence",
        "citation",
        "flagellum",
        "path",
    }
    assert entry["flagellum"]["bending_rigidity_pn_um2"] == 1900.0
    assert "flagellum kappa 1900 pN um^2, xi_n 0.0032 pN s/um^2" in text
    assert pathlib.Path(entry["path"]).is_file()
    assert entry["licence"] == ax.datasets.info("human_sperm").licence


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["data"], "FILE"),
        (["data", "human_sperm", "--list"], "--list"),
        (["data", "--list", "--plot", "x.png"], "--list"),
    ],
)
def test_cli_data_list_and_file_errors(argv, flag, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _one_line_error(capsys, argv, flag)


# -- axojax plot: the figure beside its input --------------------------------------------


def _scalar_report() -> dict:
    """A saved fit report's fields that its figure reads (``FitResult.to_json``): two
    conditions of a limit-cycle fit, one target in Hz and one in um each."""

    def target(name, value, sigma, achieved):
        return {
            "name": name,
            "value": value,
            "sigma": sigma,
            "achieved": achieved,
            "residual": (achieved - value) / sigma,
        }

    return {
        "method": "lm",
        "loss": 0.5,
        "chi2_per_dof": 0.25,
        "converged": True,
        "at_bound": [],
        "params": {"p": 300.0},
        "stderr": {"p": 3.0},
        "identifiable": {"p": True},
        "conditions": [
            {
                "label": label,
                "fixed": {"cubic": 10.0},
                "targets": [
                    target("frequency_hz", f, 0.5, f + 0.1),
                    target("amplitude_um", a, 0.2, a - 0.05),
                ],
                "shape": None,
            }
            for label, f, a in (("a", 17.0, 2.5), ("b", 20.0, 3.0))
        ],
    }


def test_plot_without_out_writes_beside_the_input(tmp_path, capsys):
    sweep = ax.sweep(
        ax.models.two(n_elements=4), ax.Params(), {"p": [100.0, 200.0]}, progress=False
    )
    sweep.save(tmp_path / "map.npz")
    (tmp_path / "fit.json").write_text(json.dumps(_scalar_report()))
    (tmp_path / "section.json").write_text(
        json.dumps(
            {
                "filaments": [{"position": [0, 0]}, {"position": [1, 0]}],
                "links": [{"between": [0, 1]}],
                "active_pairs": [{"between": [0, 1]}],
            }
        )
    )
    for argv, figure in (
        ([str(tmp_path / "map.npz")], tmp_path / "map.png"),
        ([str(tmp_path / "fit.json")], tmp_path / "fit.png"),
        (["--model-file", str(tmp_path / "section.json")], tmp_path / "section.png"),
    ):
        assert main(["plot", *argv, "--json"]) == 0
        doc = json.loads(capsys.readouterr().out)
        assert doc["figure"] == str(figure)
        assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # --out still wins
    assert main(["plot", str(tmp_path / "map.npz"), "--out", str(tmp_path / "other.svg")]) == 0
    assert (tmp_path / "other.svg").is_file()
    capsys.readouterr()


def test_plot_of_a_preset_section_needs_out(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    err = _one_line_error(capsys, ["plot", "--model", "seven"], "--out")
    assert "no input file" in err
    assert list(tmp_path.iterdir()) == []


def _help(name: str) -> str:
    parser = build_parser(name)
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return " ".join(sub.choices[name].format_help().split())


def test_plot_help_lists_every_input_it_reads():
    text = _help("plot")
    for kind in ("sweep", "simulate", "orbit", "posterior", "fit report", "FIT.json"):
        assert kind in text, kind
    # every kind the code reads is named in the help
    from axojax.plotting.files import NPZ_KINDS as KINDS

    words = {
        "sweep": "'axojax sweep'",
        "simulation": "'axojax simulate'",
        "orbit_branch": "'axojax orbit --out'",
        "posterior": "'axojax fit --posterior'",
    }
    assert set(KINDS) == set(words)
    for kind in KINDS:
        assert words[kind] in text, kind


def test_fit_help_names_its_default_solver_and_the_warm_up():
    from axojax.cli import fit as cli_fit
    from axojax.cli.main import SUBCOMMANDS
    from axojax.inverse.sampling import warmup_steps

    assert "optax" not in SUBCOMMANDS["fit"]
    assert "Levenberg-Marquardt by default" in SUBCOMMANDS["fit"]
    # the default least-squares solver really is Levenberg-Marquardt (optimistix)
    args = build_parser("fit").parse_args(["fit", "--free", "p"])
    assert args.method == "lm"
    assert cli_fit.METHODS[0] == "lm"
    text = _help("fit")
    assert "as many warm-up" not in text
    assert "after --warmup steps" in text
    assert "(default: DRAWS, at least 150 and at most 500" in text
    # ... and that is what the library does with the warm-up the command passes on
    assert [warmup_steps(d, None) for d in (20, 300, 1000)] == [150, 300, 500]
    source = (ROOT / "axojax" / "cli" / "fit" / "posterior.py").read_text()
    assert "warmup=args.warmup," in source


def test_scalar_fit_report_gives_each_unit_its_own_axis():
    from axojax.plotting.fit_report import plot_fit_report

    report = _scalar_report()
    fig = plot_fit_report(report)
    value_axes = [a for a in fig.axes if a.get_xlabel() == "condition"]
    assert sorted(a.get_ylabel() for a in value_axes) == ["amplitude_um", "frequency_hz"]
    for a in value_axes:
        name = a.get_ylabel()
        expected = sorted(
            v
            for c in report["conditions"]
            for t in c["targets"]
            if t["name"] == name
            for v in (t["value"], t["achieved"])
        )
        plotted = sorted(
            float(y)
            for line in a.get_lines()
            for y in np.atleast_1d(line.get_ydata())
            if np.isfinite(y)
        )
        # an axis carries its own unit's numbers only (error-bar caps excluded by value)
        assert set(expected) <= set(plotted)
        others = {
            t["value"] for c in report["conditions"] for t in c["targets"] if t["name"] != name
        }
        assert not others & set(plotted)
