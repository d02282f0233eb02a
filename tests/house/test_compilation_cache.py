"""The command line's persistent compilation cache (axojax/cache.py): a second command
loads what the first compiled (counted by jax's own cache-hit events) and computes the
same result; ``off`` keeps nothing; importing axojax and calling ``main()`` in Python
turn no cache on."""

import os
import pathlib
import subprocess
import sys

import jax
import numpy as np
import pytest

import axojax as ax
from axojax.cache import quiet_loader
from axojax.cli.main import main

needs_quiet_loader = pytest.mark.skipif(
    not quiet_loader(jax.__version__), reason=f"the cache is off on jax {jax.__version__} (< 0.10)"
)

# The `axojax` command (console entry point), counting jax's persistent-cache hits.
COMMAND = """
import sys
import jax
import jax.monitoring
hits = []
jax.monitoring.register_event_listener(lambda name, **_: hits.append(name == "/jax/compilation_cache/cache_hits"))
from axojax.cli.main import console
print("cache dir on import:", jax.config.jax_compilation_cache_dir, file=sys.stderr)
code = console()
print("cache dir after:", jax.config.jax_compilation_cache_dir, file=sys.stderr)
print("cache hits:", sum(hits), file=sys.stderr)
sys.exit(code)
"""


ROOT = pathlib.Path(__file__).resolve().parents[2]  # this checkout, whatever the working directory


def sweep(cache, out):
    args = [
        "sweep",
        "--model",
        "seven",
        "--p",
        "250:350:2",
        "--ks",
        "log:1e5:1e6:2",
        "--kl-ratio",
        "1000",
        "--solver",
        "arnoldi",
        "--out",
        str(out),
        "--json",
    ]
    done = subprocess.run(
        [sys.executable, "-c", COMMAND, *args],
        env={**os.environ, "AXOJAX_CACHE_DIR": str(cache), "PYTHONPATH": str(ROOT)},
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    hits = int(done.stderr.rsplit("cache hits:", 1)[1])
    on_import = done.stderr.split("cache dir on import:", 1)[1].split("\n", 1)[0].strip()
    after = done.stderr.split("cache dir after:", 1)[1].split("\n", 1)[0].strip()
    assert on_import == "None", "importing axojax turned a cache on"
    assert after == ("None" if str(cache) == "off" else str(cache))
    return ax.SweepResult.load(out).data, hits


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@needs_quiet_loader
def test_second_command_loads_what_the_first_compiled(tmp_path):
    cache = tmp_path / "cache"
    first, hits_first = sweep(cache, tmp_path / "a.npz")
    assert hits_first == 0 and any(cache.iterdir()), "the first command left no compiled program"
    second, hits_second = sweep(cache, tmp_path / "b.npz")
    assert hits_second >= 1
    for name in ("eigenvalue_real", "eigenvalue_imag", "certified"):
        np.testing.assert_array_equal(second[name], first[name])


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_off_keeps_nothing_and_python_caches_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _, hits = sweep("off", tmp_path / "a.npz")
    assert hits == 0 and sorted(p.name for p in tmp_path.iterdir()) == ["a.npz"]
    monkeypatch.setenv("AXOJAX_CACHE_DIR", "off")
    assert ax.cache.command_line_cache() is None
    # main() called in Python leaves this process's setting as it was (None in a plain
    # process, as the commands above print on import; tests/conftest.py set the suite's).
    before = jax.config.jax_compilation_cache_dir
    monkeypatch.setenv("AXOJAX_CACHE_DIR", str(tmp_path / "not-this"))
    assert main(["modes", "--model", "two", "--elements", "4", "--json"]) == 0
    assert jax.config.jax_compilation_cache_dir == before and not (tmp_path / "not-this").exists()


def test_default_directory_follows_xdg(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert ax.cache.default_cache_dir() == tmp_path / "axojax" / "jax"
    assert not quiet_loader("0.9.2") and quiet_loader("0.10.2") and quiet_loader("1.0.0")
