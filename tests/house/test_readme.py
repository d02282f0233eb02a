"""README.md quotes axojax's actual output (so it cannot go stale), and every command it
shows runs: the cheap ones here, the long ones (a comparison, a posterior) in the slow set
(``python3 -m pytest -m slow``)."""

import pathlib
import re
import shlex

import pytest

from axojax.cli.main import main

ROOT = pathlib.Path(__file__).resolve().parents[2]
README = ROOT / "README.md"


def _text() -> str:
    return README.read_text()


def _commands() -> list[str]:
    """Every ``axojax ...`` line of README's ```bash blocks."""
    blocks = re.findall(r"```bash\n(.*?)```", _text(), re.S)
    return [
        line.split("  #")[0].strip()
        for block in blocks
        for line in block.splitlines()
        if line.startswith("axojax ")
    ]


def _output_block(command: str) -> list[str]:
    """The lines of the ``` block that follows README's ```bash block of ``command``."""
    text = _text()
    at = text.index(f"```bash\n{command}\n```")
    match = re.compile(r"```\n(.*?)```", re.S).search(text, at + len(command) + 12)
    assert match is not None, f"README shows no output for {command}"
    return [line for line in match.group(1).splitlines() if line.strip() not in ("", "...")]


def _run(argv: list[str], capsys) -> tuple[int, str]:
    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out + captured.err


def _shown_lines_are_printed(command: str, out: str, check=None) -> None:
    """Every line README shows under ``command`` is (part of) a line it prints; ``check``
    names the lines to compare (default: all)."""
    printed = out.splitlines()
    for line in _output_block(command):
        if check is not None and not check(line):
            continue
        assert any(line.strip() in p for p in printed), (
            f"README's output of `{command}` is stale: {line!r} is not printed; paste the "
            "command's output"
        )


MAIN_JOB = "axojax modes --model seven --p 300"
DATA = "axojax data human_sperm --plot sperm.png"
COMPARE = "axojax compare --data human_sperm --out cmp.json"
PLOT = "axojax plot cmp.json"
FIT = (
    "axojax fit --model seven --free p,ks --kl-ratio 1000 --data human_sperm --ei 90.9"
    " --cn 0.000285 --shape-floor 0.2 --posterior 1000 --sampler nuts --out fit.json"
)
CHECKED = {MAIN_JOB, DATA, COMPARE, PLOT, FIT}


def test_main_job_output_is_current(capsys):
    """The block under "The main job" is what `axojax modes --model seven --p 300` prints."""
    assert main(["modes", "--model", "seven", "--p", "300"]) == 0
    out = capsys.readouterr().out.rstrip("\n")
    assert f"```\n{out}\n```" in README.read_text(), (
        "README's main-job block is stale: paste the command's output"
    )


def test_every_readme_command_is_checked():
    """A command added to README needs its check here (cheap, or in the slow set)."""
    shown = set(_commands())
    assert shown == CHECKED, (
        f"README's commands and tests/house/test_readme.py's differ: only in README "
        f"{sorted(shown - CHECKED)}, only here {sorted(CHECKED - shown)}"
    )


def test_data_output_is_current(tmp_path, monkeypatch, capsys):
    """Step 1 of "Your own beat": `axojax data human_sperm --plot sperm.png`."""
    monkeypatch.chdir(tmp_path)
    code, out = _run(shlex.split(DATA)[1:], capsys)
    assert code == 0, out
    assert (tmp_path / "sperm.png").stat().st_size > 0
    _shown_lines_are_printed(DATA, out)


@pytest.mark.slow
@pytest.mark.timeout(1800)
def test_compare_and_plot_commands_run(tmp_path, monkeypatch, capsys):
    """Steps 2 and 3 of "Your own beat", exactly as README shows them: the comparison
    prints README's table header, model and units lines and each row README quotes (its
    mechanism and base); the plot draws the report."""
    monkeypatch.chdir(tmp_path)
    code, out = _run(shlex.split(COMPARE)[1:], capsys)
    assert code == 0, out
    assert (tmp_path / "cmp.json").exists()
    _shown_lines_are_printed(
        COMPARE, out, check=lambda line: line.lstrip().startswith(("rank", "model", "units"))
    )
    rows = [line.split()[1:3] for line in out.splitlines() if re.match(r"\s+\d+\s+\S", line)]
    shown = [line.split()[1:3] for line in _output_block(COMPARE) if re.match(r"\s+\d+\s+\S", line)]
    assert shown and all(row in rows for row in shown), (shown, rows)

    code, out = _run(shlex.split(PLOT)[1:], capsys)
    assert code == 0, out
    assert (tmp_path / "cmp.png").stat().st_size > 0
    _shown_lines_are_printed(PLOT, out)


@pytest.mark.slow
@pytest.mark.timeout(1800)
def test_posterior_command_runs(tmp_path, monkeypatch, capsys):
    """Step 4 of "Your own beat", exactly as README shows it: exit status 1 (the steady
    load misses the shape, as README says), the posterior's table and its draws' file."""
    monkeypatch.chdir(tmp_path)
    code, out = _run(shlex.split(FIT)[1:], capsys)
    assert code == 1, out
    assert (tmp_path / "fit.posterior.npz").exists()
    _shown_lines_are_printed(
        FIT, out, check=lambda line: line.lstrip().startswith(("parameter", "wrote"))
    )
