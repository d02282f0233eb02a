"""The command line's persistent compilation cache (axojax/cache.py): a second command
loads what the first compiled and computes the same result; ``off`` keeps nothing."""

import os
import subprocess
import sys

import numpy as np

import axojax as ax


def sweep(cache, out):
    command = [sys.executable, "-m", "axojax.cli.main", "sweep", "--model", "seven", "--p", "250:350:2", "--ks", "log:1e5:1e6:2",
               "--kl-ratio", "1000", "--solver", "arnoldi", "--out", str(out), "--json"]
    subprocess.run(command, env={**os.environ, "AXOJAX_CACHE_DIR": str(cache)}, capture_output=True, text=True, timeout=300, check=True)
    return ax.SweepResult.load(out).data


def test_second_command_uses_the_cache_and_agrees(tmp_path):
    cache = tmp_path / "cache"
    first = sweep(cache, tmp_path / "a.npz")
    files = sorted(p.name for p in cache.iterdir())
    assert files, "the first command left no compiled program"
    second = sweep(cache, tmp_path / "b.npz")
    assert sorted(p.name for p in cache.iterdir()) == files  # loaded, not compiled again
    for name in ("eigenvalue_real", "eigenvalue_imag", "certified"):
        np.testing.assert_array_equal(second[name], first[name])


def test_off_keeps_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sweep("off", tmp_path / "a.npz")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.npz"]
    monkeypatch.setenv("AXOJAX_CACHE_DIR", "off")
    assert ax.cache.command_line_cache() is None


def test_default_directory_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert ax.cache.default_cache_dir() == tmp_path / "axojax" / "jax"
