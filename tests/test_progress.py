"""The progress rule (axojax/_progress.py): bars on stderr only, forced on/off by
AXOJAX_PROGRESS, off when stderr is not a terminal, off for JSON on a pipe."""

from __future__ import annotations

import io

import pytest

from axojax import _progress


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
