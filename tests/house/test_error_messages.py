"""Bad input ends in one clear line, in Python and on the command line (the defect
classes of issue 21, each tested over the subcommands, are in tests/house/test_hostile_input.py)."""

import json
import subprocess
import sys

import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import main


@pytest.mark.parametrize(
    "change,match",
    [
        ({"ks": -1.0}, "ks must be >= 0"),
        ({"p": float("nan")}, "p must be finite"),
        ({"cl": -0.1}, "cl must be >= 0"),
        ({"out_of_plane": 0.0}, "out_of_plane must be >= 1e-09"),
        ({"ks": 1e300}, "ks must be at most 1e\\+09"),
    ],
)
def test_python_bad_params(change, match):
    with pytest.raises(ValueError, match=match):
        ax.dominant_mode(ax.models.two(), ax.Params().replace(**change))


def test_python_wrong_types_name_the_argument():
    # under the suite's run-time type checker (pyproject.toml) its TypeError comes first;
    # either names the argument
    with pytest.raises(TypeError, match="params"):
        ax.dominant_mode(ax.models.two(), None)
    with pytest.raises(TypeError, match="model"):
        ax.dominant_mode("seven", ax.Params())
    code = (
        "import axojax as ax\ntry:\n    ax.dominant_mode(ax.models.two(), None)\nexcept "
        "TypeError as e:\n    print(e)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=300
    ).stdout
    assert out.strip() == "params must be an ax.Params, got None", out


def test_python_bad_models(tmp_path):
    with pytest.raises(ValueError, match="n_elements must be an integer >= 1"):
        ax.models.seven(n_elements=0)
    with pytest.raises(ValueError, match="n_elements must be at most 100000"):
        ax.models.seven(n_elements=10**9)
    with pytest.raises(ValueError, match="unknown model 'eleven'"):
        ax.models.preset("eleven")
    with pytest.raises(ValueError, match="names filament 5, but filaments are 0..1"):
        ax.models.CrossSection(
            "bad", np.array([[0.0, 0.0], [1.0, 0.0]]), links=(ax.models.Link(0, 5),)
        )
    bad = tmp_path / "bad.toml"
    bad.write_text("filaments = [ {position = [0, 0]} \n")
    with pytest.raises(ValueError, match="malformed"):
        ax.models.from_file(bad)
    nofil = tmp_path / "nofil.json"
    nofil.write_text(json.dumps({"links": []}))
    with pytest.raises(ValueError, match="non-empty 'filaments'"):
        ax.models.from_file(nofil)
    with pytest.raises(ValueError, match="unknown parameter"):
        ax.Params().replace(stiffness=1.0)


def run_cli(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize(
    "args,flag",
    [
        (["modes", "--ks", "-1"], "--ks"),
        (["modes", "--p", "nan"], "--p"),
        (["modes", "--elements", "0"], "--elements"),
        (["modes", "--elements", "ten"], "--elements"),
        (["modes", "--model", "eleven"], "--model"),
        (["modes", "--model-file", "/nonexistent/x.toml"], "--model-file"),
        (["modes", "--cn", "-3"], "--cn"),
        (["modes", "--kl-ratio", "0"], "--kl-ratio"),
        (["modes", "--grad", "p,stiffness"], "--grad"),
        (
            ["fit", "--spec", "SPEC:free = ['p']\nbounds = 5\n[[condition]]\nfrequency_hz = 40\n"],
            "[bounds] must be a table",
        ),
        (
            ["fit", "--spec", "SPEC:free = ['p']\ncondition = [5]\n"],
            "each [[condition]] must be a table",
        ),
    ],
)
def test_cli_errors_one_line(args, flag, capsys, tmp_path):
    if args[-1].startswith("SPEC:"):  # a spec file's text
        spec = tmp_path / "fit.toml"
        spec.write_text(args[-1][5:])
        args = args[:-1] + [str(spec)]
    code, out, err = run_cli(args, capsys)
    assert code != 0
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and flag in lines[0], err


def test_cli_bad_model_file_link(tmp_path, capsys):
    f = tmp_path / "m.json"
    f.write_text(
        json.dumps(
            {
                "filaments": [{"position": [0, 0]}, {"position": [1, 0]}],
                "links": [{"between": [0, 3]}],
            }
        )
    )
    code, out, err = run_cli(["modes", "--model-file", str(f)], capsys)
    assert (
        code == 2
        and "--model-file" in err
        and "filament 3" in err
        and len(err.strip().splitlines()) == 1
    )


TWO = {
    "filaments": [{"position": [0, 1]}, {"position": [0, -1]}],
    "links": [{"between": [0, 1]}],
    "active_pairs": [{"between": [0, 1]}],
}


@pytest.mark.parametrize(
    "text,match",
    [
        (json.dumps({**TWO, "dimensions": 2.0}), "must be the integer 1 or 2, got 2.0"),
        (json.dumps({**TWO, "links": 5}), "'links' must be a list of tables, got 5"),
        (json.dumps({**TWO, "active_pairs": [{"between": [0, 1], "group": 1.0}]}), "group 1.0"),
        (
            json.dumps({**TWO, "filaments": [{"position": [0, 1e308]}, {"position": [0, -1]}]}),
            "magnitude <= 1e\\+06",
        ),
        ("[" * 100000, "nested too deeply"),
    ],
    ids=[
        "float-dimensions",
        "links-not-a-list",
        "float-group",
        "overflowing-position",
        "deep-nesting",
    ],
)
def test_cli_malformed_model_file_one_line(tmp_path, capsys, text, match):
    f = tmp_path / "m.json"
    f.write_text(text)
    code, out, err = run_cli(["modes", "--model-file", str(f)], capsys)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert "--model-file" in err and __import__("re").search(match, err), err


def test_upper_case_npz_suffix_is_written_whole(tmp_path, capsys):
    """numpy appends ".npz" to a name not ending in exactly that: an output named x.NPZ
    is still written whole, with no temporary file left; another suffix is refused
    before any work in Python too."""
    out = tmp_path / "x.NPZ"
    code, _, err = run_cli(
        ["sweep", "--model", "two", "--elements", "3", "--p", "1:900:3", "--out", str(out)], capsys
    )
    assert code == 0, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.NPZ"]
    assert np.load(out)["p"].shape == (3,)
    with pytest.raises(ValueError, match="out: expected a .npz path, got '.*x.txt'"):
        ax.sweep(
            ax.models.two(n_elements=3),
            ax.Params(),
            {"p": [1.0, 2.0]},
            out=tmp_path / "x.txt",
            progress=False,
        )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.NPZ"]


def test_empty_and_infinite_values_are_refused(tmp_path, capsys):
    """An empty entry of a list axis, an infinite end, an empty --model or --grad: one
    line each, not a silently shorter axis, a numpy warning or the default."""
    out = str(tmp_path / "s.npz")
    for args, line in [
        (["sweep", "--p", "1,2,,3", "--out", out], "--p: an empty value in the list '1,2,,3'"),
        (["sweep", "--p", "100:inf:3", "--out", out], "--p: expected finite ends"),
        (["sweep", "--ks", "log:1:1e400:3", "--out", out], "--ks: expected finite ends"),
        (["modes", "--model", ""], "--model: unknown model ''"),
        (["modes", "--grad", ""], "--grad: expected comma-separated parameter names"),
    ]:
        code, stdout, err = run_cli(args, capsys)
        lines = err.strip().splitlines()
        assert code == 2 and stdout == "" and len(lines) == 1 and line in lines[0], err
    assert not list(tmp_path.iterdir())


def test_mat_file_with_structs_names_the_file(tmp_path, capsys):
    import scipy.io

    path = tmp_path / "beat.mat"
    scipy.io.savemat(
        path,
        {
            "X": {"a": np.ones(3), "b": np.ones((2, 2))},
            "Y": {"b": np.ones(4)},
            "frame_rate_hz": 100.0,
        },
    )
    code, out, err = run_cli(["data", str(path)], capsys)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert "beat.mat: unexpected contents" in err, err


def test_console_script_exit_status():
    proc = subprocess.run(
        [sys.executable, "-m", "axojax.cli.main", "modes", "--ks", "-5"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert proc.stdout == "" and proc.stderr.strip().count("\n") == 0 and "--ks" in proc.stderr


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["orbit", "--model", "two", "--harmonics", "100000"], "--harmonics"),
        (
            [
                "sweep",
                "--model",
                "two",
                "--p",
                "100:200:2",
                "--out",
                "x.npz",
                "--coordinator",
                "localhost:99999",
            ],
            "--coordinator",
        ),
        (
            ["sweep", "--model", "two", "--p", "100:200:2", "--out", "x.npz", "--process-id", "-1"],
            "--process-id",
        ),
        (
            [
                "sweep",
                "--model",
                "two",
                "--p",
                "100:200:2",
                "--out",
                "x.npz",
                "--num-processes",
                "2",
                "--process-id",
                "2",
            ],
            "--process-id",
        ),
        (
            [
                "fit",
                "--model",
                "two",
                "--free",
                "p",
                "--target",
                "limit-cycle",
                "--observation",
                "chlamydomonas-wt",
            ],
            "--observation",
        ),
        (
            [
                "fit",
                "--model",
                "two",
                "--free",
                "p",
                "--target-frequency",
                "30",
                "--amplitude-sigma",
                "0.1",
            ],
            "--amplitude-sigma",
        ),
        (["simulate", "--model", "two", "--t-end", "0.1", "--max-steps", "0"], "--max-steps"),
    ],
)
def test_cli_new_flags_one_line(argv, flag, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"axojax: error: {flag}:") and "\n" not in err, err


def test_cli_coordinator_that_never_answers(tmp_path):
    """A process I > 0 whose process 0 never starts stops within --timeout, on one line."""
    cmd = [
        sys.executable,
        "-m",
        "axojax.cli.main",
        "sweep",
        "--model",
        "two",
        "--elements",
        "4",
        "--p",
        "100:200:2",
        "--out",
        str(tmp_path / "x.npz"),
        "--coordinator",
        "localhost:1",
        "--num-processes",
        "2",
        "--process-id",
        "1",
        "--timeout",
        "1",
    ]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert (
        r.returncode == 2
        and r.stderr.strip().startswith("axojax: error: --coordinator: nothing answered")
        and len(r.stderr.strip().splitlines()) == 1
    )


def test_an_observed_scalar_gets_the_commands_default_uncertainty(capsys):
    """ax.beats.observed_target gives what axojax fit's --target-* flags and a fit spec
    give a scalar without its sigma (5 % of a frequency, 10 % of a wavelength, velocity
    or tip amplitude); a value or sigma <= 0 is one line naming the observable, which the
    command names by its flag."""
    from axojax.beats import Target, observed_target
    from axojax.beats.targets import RELATIVE_SIGMA
    from axojax.inverse.spec import SPEC_TARGETS

    assert observed_target("frequency_hz", 30.0) == Target("frequency_hz", 30.0, 1.5)
    assert observed_target("wavelength_um", 20.0, 1.0) == Target("wavelength_um", 20.0, 1.0)
    cycle = observed_target("amplitude_um", 4.0, source="limit_cycle")
    assert cycle == Target("amplitude_um", 4.0, 0.4, source="limit_cycle")
    assert all(rel == RELATIVE_SIGMA[key] for key, (_, _, rel) in SPEC_TARGETS.items())
    with pytest.raises(ValueError, match=r"^wavelength_um: must be > 0, got -2$"):
        observed_target("wavelength_um", -2.0)
    with pytest.raises(ValueError, match=r"^frequency_hz: its uncertainty must be > 0, got 0$"):
        observed_target("frequency_hz", 30.0, 0.0)
    argv = ["fit", "--model", "two", "--free", "p", "--target-frequency", "30"]
    assert main([*argv, "--frequency-sigma", "0"]) == 2
    err = capsys.readouterr().err
    assert err == "axojax: error: --target-frequency: its uncertainty must be > 0, got 0\n"
