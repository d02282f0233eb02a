"""The progress rule (axojax/_progress.py): bars on stderr only, forced on/off by
AXOJAX_PROGRESS, off when stderr is not a terminal, off for JSON on a pipe."""

from __future__ import annotations

import io
import json
import os
import pathlib
import shutil
import subprocess
import sys

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


@pytest.mark.parametrize(
    ("env", "err_tty", "out_tty", "json_output", "expected"),
    [
        (None, True, True, False, True),
        (None, False, True, False, False),  # stderr not a terminal
        (None, True, False, True, False),  # --json into a pipe
        (None, True, False, False, True),  # text into a pipe, bar on the terminal
        (None, True, True, True, True),  # --json on the terminal
        ("1", False, False, True, True),  # forced on
        ("0", True, True, False, False),  # forced off
    ],
)
def test_enabled_rule(monkeypatch, env, err_tty, out_tty, json_output, expected):
    if env is None:
        monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    else:
        monkeypatch.setenv(_progress.PROGRESS_ENV, env)
    monkeypatch.setattr("sys.stderr", _Stream(err_tty))
    monkeypatch.setattr("sys.stdout", _Stream(out_tty))
    assert _progress.enabled(json_output) is expected


def test_bar_goes_to_stderr_only(monkeypatch):
    monkeypatch.setenv(_progress.PROGRESS_ENV, "1")
    err, out = _Stream(False), _Stream(False)
    monkeypatch.setattr("sys.stderr", err)
    monkeypatch.setattr("sys.stdout", out)
    assert list(_progress.progress(range(4), desc="draws", unit="draw")) == [0, 1, 2, 3]
    with _progress.progress(3, desc="starts", unit="start") as bar:
        bar.update(3)
    assert "draws" in err.getvalue() and "4/4" in err.getvalue()
    assert "starts" in err.getvalue() and "3/3" in err.getvalue()
    assert out.getvalue() == ""


def test_disabled_bar_prints_nothing(monkeypatch):
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    err = _Stream(True)
    monkeypatch.setattr("sys.stderr", err)
    assert list(_progress.progress(range(3), desc="x", enable=False)) == [0, 1, 2]
    assert err.getvalue() == ""


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_cli_passes_the_json_rule(monkeypatch, capsys):
    """stderr a terminal, stdout a pipe: ``fit --json`` asks for no bar; text output shows
    the bars of the fit's starts and of the posterior (run in process with no delay, so that
    a fast run shows them too), and the fast answer (the Laplace approximation) comes
    first."""
    monkeypatch.delenv(_progress.PROGRESS_ENV, raising=False)
    monkeypatch.setattr(_progress, "DELAY_S", 0.0)
    monkeypatch.setattr(_progress, "_isatty", lambda stream: stream is sys.stderr)
    text = [a for a in FIT if a != "--json"]
    for argv, shown in ((FIT, False), (text, True)):
        args = build_parser("fit").parse_args(argv)
        assert fit._fit_options(args)["progress"] is shown
    main(text)
    out, err = capsys.readouterr()
    for bar in ("fit starts", "posterior warm-up", "posterior draws"):
        assert bar in err, err
    assert "80/80" in err and "draw/s" in err  # count (2 chains x 40 draws) and rate
    assert out.index("Laplace approximation") < out.index("posterior (2 chains")


@pytest.mark.slow
def test_json_on_a_pipe_has_no_bars_unless_forced(tmp_path):
    """``axojax fit --posterior --json`` into a pipe (a subprocess, the smallest problem):
    stdout is exactly one JSON document and stderr has no bar; forced on, the bars of the
    fit's starts and of the posterior's warm-up and draws appear on stderr and stdout is
    still only the JSON document. (The two runs share a compilation cache; the first run's
    posterior warm state is dropped before the second, which would otherwise skip its
    warm-up and so its bar: tests/sampling/test_warm_cache.py.)"""
    env = {**os.environ, "AXOJAX_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    env.pop(_progress.PROGRESS_ENV, None)
    runs = {}
    for force in (None, "1"):
        if force is not None:
            env[_progress.PROGRESS_ENV] = force
            shutil.rmtree(tmp_path / "cache" / WARM_SUBDIR)
        runs[force] = subprocess.run(
            [sys.executable, "-m", "axojax.cli.main", *FIT],
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
    assert "80/80" in loud and "draw/s" in loud  # count (2 chains x 40) and rate
