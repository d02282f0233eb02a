"""Progress (axojax/_progress.py, issue 57 item 4): on stderr only, from the start of a
run (its first compilation included); bars on a terminal, one plain line per step or
stage (done / total, elapsed) when stderr is a file or a pipe; silenced by every
command's ``--quiet``, forced on/off by AXOJAX_PROGRESS; stdout's JSON untouched."""

from __future__ import annotations

import io
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time
import types

import pytest

from axojax import _progress
from axojax.cache import WARM_SUBDIR
from axojax.cli import fit
from axojax.cli.main import build_parser, main

ROOT = pathlib.Path(__file__).resolve().parents[2]  # this checkout, whatever the working directory
FIT = [
    "fit",
    "--no-mesh-check",
    "--model",
    "two",
    "--elements",
    "4",
    "--free",
    "p",
    "--target-frequency",
    "30",
    "--posterior",
    "40",
    "--chains",
    "2",
    "--sampler",
    "nuts",  # the warm-up's bar is NUTS's (auto picks the mode-aware sampler for one)
    "--json",
]


class _Stream(io.StringIO):
    def __init__(self, tty: bool):
        super().__init__()
        self._tty = tty

    def isatty(self) -> bool:
        return self._tty


@pytest.fixture
def fast(monkeypatch):
    """The rule as a user meets it (progress not forced), in milliseconds: no delay
    before progress shows or between lines, quick ticks."""
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    monkeypatch.setattr(_progress, "DELAY_S", 0.0)
    monkeypatch.setattr(_progress, "TICK_S", 0.01)


def _streams(monkeypatch, err_tty: bool = False) -> tuple[_Stream, _Stream]:
    err, out = _Stream(err_tty), _Stream(False)
    monkeypatch.setattr("sys.stderr", err)
    monkeypatch.setattr("sys.stdout", out)
    return err, out


@pytest.mark.parametrize(
    ("env", "quiet", "err_tty", "enable", "expected"),
    [
        (None, False, True, None, "bars"),  # a terminal
        (None, False, False, None, "lines"),  # stderr a file or a pipe
        (None, False, False, True, "lines"),
        (None, False, True, False, None),  # the caller's progress=False
        (None, True, True, None, None),  # --quiet
        (None, True, False, True, None),
        ("1", False, False, False, "lines"),  # forced on, over the caller
        ("1", True, True, None, None),  # --quiet wins over AXOJAX_PROGRESS=1
        ("0", False, True, True, None),  # forced off
    ],
)
def test_style_rule(monkeypatch, env, quiet, err_tty, enable, expected):
    if env is None:
        monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    else:
        monkeypatch.setenv(_progress.PROGRESS_ENV, env)
    _streams(monkeypatch, err_tty)
    with _progress.quiet(quiet):
        assert _progress.style(enable) == expected
        assert _progress.enabled(enable) is (expected is not None)


def test_quiet_holds_for_its_block_only(monkeypatch):
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    _streams(monkeypatch)
    with _progress.quiet():
        with _progress.quiet(False):  # an inner run without --quiet stays quiet
            assert _progress.style() is None
        assert _progress.style() is None
    assert _progress.style() == "lines"


def test_bar_goes_to_stderr_only(monkeypatch):
    monkeypatch.setenv(_progress.PROGRESS_ENV, "1")
    err, out = _streams(monkeypatch)
    assert list(_progress.progress(range(4), desc="draws", unit="draw")) == [0, 1, 2, 3]
    with _progress.progress(3, desc="starts", unit="start") as bar:
        bar.update(3)
    assert "draws: 4/4 done" in err.getvalue() and "starts: 3/3 done" in err.getvalue()
    assert out.getvalue() == ""


def test_disabled_bar_prints_nothing(monkeypatch):
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    err = _Stream(True)
    monkeypatch.setattr("sys.stderr", err)
    assert list(_progress.progress(range(3), desc="x", enable=False)) == [0, 1, 2]
    assert err.getvalue() == ""


LINE = re.compile(r"compare rows: (\d)/3 done, (\d+) s elapsed(, .*)?")


FIRST_ROW = re.compile(r"compare rows: 0/(\d) done, \d+ s elapsed \(the first row compiles\)")


def _wait_for(stream: io.StringIO, text: str, timeout: float = 30.0) -> None:
    """Until ``text`` is on ``stream`` (written by a progress ticker's thread)."""
    end = time.monotonic() + timeout
    while text not in stream.getvalue() and time.monotonic() < end:
        time.sleep(0.01)


def test_plain_lines_when_stderr_is_not_a_terminal(monkeypatch, fast):
    """stderr a file or a pipe: one flushed line per step, done / total and elapsed, no
    carriage returns, nothing on stdout."""
    err, out = _streams(monkeypatch)
    for _ in _progress.progress(range(3), desc="compare rows", unit="row"):
        time.sleep(0.02)
    lines = err.getvalue().splitlines()
    assert all(LINE.fullmatch(line) for line in lines), lines
    assert [LINE.fullmatch(line)[1] for line in lines][-3:] == ["1", "2", "3"]
    assert "\r" not in err.getvalue() and out.getvalue() == ""


def test_a_plain_line_says_done_total_elapsed_rate_and_time_left():
    lines = _progress.Lines(None, 24, "compare rows", "row", delay=60.0)
    lines.n = 3
    assert lines._line(41.0, False) == (
        "compare rows: 3/24 done, 41 s elapsed, 13.7 s/row, about 4 min 47 s left"
    )
    lines.close()  # within its delay: nothing written
    assert _progress.duration(7385) == "2 h 03 min" and _progress.duration(65) == "1 min 05 s"


def test_runs_within_the_delay_print_nothing(monkeypatch):
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    err, _ = _streams(monkeypatch)
    assert list(_progress.progress(range(3), desc="rows", unit="row", starting=True)) == [0, 1, 2]
    with _progress.stage("a quick stage"):
        pass
    assert err.getvalue() == ""


def test_a_stage_as_lines(monkeypatch, fast):
    """One compiled step: a line once it has run the delay, one when it is done."""
    err, _ = _streams(monkeypatch)
    with _progress.stage("posterior warm-up (2 x 100 steps)"):
        _wait_for(err, "running")
    lines = err.getvalue().splitlines()
    assert len(lines) == 2, lines
    assert re.fullmatch(r"posterior warm-up \(2 x 100 steps\): running, \d+ s elapsed", lines[0])
    assert re.fullmatch(r"posterior warm-up \(2 x 100 steps\): done, \d+ s elapsed", lines[1])


def test_progress_shows_from_the_start(monkeypatch, fast):
    """While the first step runs (its compilation), a line says what it waits for; the
    later lines do not."""
    err, _ = _streams(monkeypatch)
    for i in _progress.progress(range(2), desc="compare rows", unit="row", starting=True):
        if i == 0:
            _wait_for(err, "compiles")
    lines = err.getvalue().splitlines()
    assert FIRST_ROW.fullmatch(lines[0]) and FIRST_ROW.fullmatch(lines[0])[1] == "2", lines
    assert lines[-1].startswith("compare rows: 2/2 done") and "compiles" not in lines[-1]


def test_bars_on_a_terminal_from_the_start(monkeypatch, fast):
    """stderr a terminal: tqdm's bar, shown (and its elapsed time refreshed) while the
    first step runs, then the counts; nothing on stdout."""
    err, out = _streams(monkeypatch, err_tty=True)
    for i in _progress.progress(range(2), desc="compare rows", unit="row", starting=True):
        if i == 0:
            _wait_for(err, "compiles")
    text = err.getvalue()
    assert "\r" in text and "0/2" in text and "the first row compiles" in text
    assert "2/2" in text and text.endswith("\n") and out.getvalue() == ""
    with _progress.stage("posterior warm-up"):
        _wait_for(err, "warm-up")
    assert re.search(r"posterior warm-up: 00:0\d", err.getvalue())


def test_the_compare_loop_shows_its_first_row(monkeypatch, fast):
    """The library's rows announce the first row's compilation before it is done (a
    stubbed row fit that stops the run)."""
    from axojax.inverse.comparison import compare as compare_module

    class Stop(Exception):
        pass

    def first_row(*args, **kwargs):
        _wait_for(err, "compiles")
        raise Stop

    monkeypatch.setattr(compare_module, "fit_row", first_row)
    err, _ = _streams(monkeypatch)
    with pytest.raises(Stop):
        compare_module.compare("human_sperm", ["steady"], ["clamped"], n_elements=4, progress=True)
    first = FIRST_ROW.fullmatch(err.getvalue().splitlines()[0])
    assert first and first[1] == "1", err.getvalue()


class _Comparison:
    def to_json(self) -> dict:
        return {"data": {}, "rows": []}


COMPARE = ["compare", "--data", "human_sperm", "--mechanisms", "steady", "--json"]


def test_compare_command_lines_quiet_and_json(monkeypatch, capsys, fast):
    """``axojax compare --json`` with stderr not a terminal (the slow fits stubbed): plain
    lines on stderr and one JSON document on stdout; ``--quiet``, before or after the
    subcommand, silences them and passes progress=False."""
    calls = []

    def compare(*args, progress, **kwargs):
        calls.append(progress)
        for _ in _progress.progress(range(2), desc="compare rows", unit="row", enable=progress):
            time.sleep(0.02)
        return _Comparison()

    monkeypatch.setattr("axojax.cli.compare.compare", compare)
    for argv, shown in (
        (COMPARE, True),
        ([*COMPARE, "--quiet"], False),
        (["--quiet", *COMPARE], False),
    ):
        assert main(argv) == 0
        out, err = capsys.readouterr()
        assert json.loads(out)["rows"] == []  # stdout: the document alone
        assert calls.pop() is shown
        assert ("compare rows: 2/2 done" in err) is shown and ("\r" not in err), err
        assert err == "" or shown


def test_simulate_command_shows_its_compilation(monkeypatch, capsys, fast):
    """``axojax simulate`` (the integration stubbed): a stage from the start, as lines."""

    def simulate(*args, **kwargs):
        if _progress.enabled():
            _wait_for(sys.stderr, "running")
        return types.SimpleNamespace(state="successful", to_json=lambda: {"state": "successful"})

    monkeypatch.setattr("axojax.cli.simulate.simulate", simulate)
    argv = [
        "simulate",
        "--model",
        "two",
        "--elements",
        "4",
        "--t-end",
        "0.1",
        "--max-steps",
        "10",
        "--json",
    ]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    assert json.loads(out) == {"state": "successful"}
    stage = r"simulate 0\.1 s \(compiling, then integrating\): "
    lines = err.splitlines()
    assert len(lines) == 2, lines
    assert re.fullmatch(stage + r"running, \d+ s elapsed", lines[0])
    assert re.fullmatch(stage + r"done, \d+ s elapsed", lines[1])
    assert main([*argv, "--quiet"]) == 0
    assert capsys.readouterr().err == ""


def test_a_real_sweep_shows_its_first_chunk(monkeypatch, capsys, fast, tmp_path):
    """A real command, end to end: ``axojax sweep --json`` announces its first chunk's
    compilation, then counts the chunk; stdout stays one JSON document."""
    argv = ["sweep", "--model", "two", "--elements", "4", "--p", "100:3000:4"]
    assert main([*argv, "--out", str(tmp_path / "s.npz"), "--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["points"] == 4
    lines = err.splitlines()
    assert re.fullmatch(
        r"sweep two: 0/1 done, \d+ s elapsed \(the first chunk compiles\)", lines[0]
    )
    assert re.fullmatch(r"sweep two: 1/1 done, \d+ s elapsed, .*", lines[-1]), lines


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_cli_bars_on_a_terminal_with_json_or_text(monkeypatch, capsys):
    """stderr a terminal, stdout a pipe: ``fit`` asks for progress with ``--json`` as with
    text (it goes to stderr), not under ``--quiet``; text output shows the bars of the fit's
    starts and of the posterior (run in process with no delay, so that a fast run shows
    them too), and the fast answer (the Laplace approximation) comes first."""
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    monkeypatch.setattr(_progress, "DELAY_S", 0.0)
    monkeypatch.setattr(_progress, "_isatty", lambda stream: stream is sys.stderr)
    text = [a for a in FIT if a != "--json"]
    for argv in (FIT, text):
        args = build_parser("fit").parse_args(argv)
        assert fit._fit_options(args)["progress"] is True
        with _progress.quiet():
            assert fit._fit_options(args)["progress"] is False
    main(text)
    out, err = capsys.readouterr()
    for bar in ("fit starts", "posterior warm-up", "posterior draws"):
        assert bar in err, err
    assert "80/80" in err and "draw/s" in err  # count (2 chains x 40 draws) and rate
    assert out.index("Laplace approximation") < out.index("posterior (2 chains")


@pytest.mark.slow
def test_json_on_a_pipe_quiet_or_forced_lines(tmp_path):
    """``axojax fit --posterior --json`` into a pipe (a subprocess, the smallest problem):
    stdout is exactly one JSON document; with ``--quiet`` stderr has no progress; forced on
    (no delay), the plain lines of the fit's starts and of the posterior's warm-up and
    draws appear on stderr (no carriage returns) and stdout is still only the JSON
    document. (The two runs share a compilation cache; the first run's posterior warm
    state is dropped before the second, which would otherwise skip its warm-up and so its
    stage: tests/sampling/test_warm_cache.py.)"""
    env = {**os.environ, "AXOJAX_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    env.pop(_progress.PROGRESS_ENV, None)
    runs = {}
    for force in (None, "1"):
        argv = [*FIT, "--quiet"] if force is None else FIT
        if force is not None:
            env[_progress.PROGRESS_ENV] = force
            shutil.rmtree(tmp_path / "cache" / WARM_SUBDIR)
        runs[force] = subprocess.run(
            [sys.executable, "-m", "axojax.cli.main", *argv],
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )
    for run in runs.values():
        assert run.returncode in (0, 1), run.stderr
        doc = json.loads(run.stdout)  # the whole of stdout: nothing but the document
        assert doc["posterior"]["draws"] == 40
        assert "\r" not in run.stdout and "it/s" not in run.stdout
    quiet, loud = runs[None].stderr, runs["1"].stderr
    for bar in ("fit starts", "posterior warm-up", "posterior draws"):
        assert bar not in quiet, quiet
        assert bar in loud, loud
    assert "posterior draws: 80/80 done" in loud and "\r" not in loud  # 2 chains x 40
