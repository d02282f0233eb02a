"""The command line's persistent compilation cache (axojax/cache.py): a second command
loads what the first compiled (counted by jax's own cache-hit events) and computes the
same result, and only the first says it compiles; ``off`` keeps nothing; importing axojax
and calling ``main()`` in Python turn no cache on; the cache keeps within its bound;
``axojax cache`` shows and clears it."""

import json
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
    said = "the first run on this machine compiles" in done.stderr
    return ax.SweepResult.load(out).data, hits, said


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@needs_quiet_loader
def test_second_command_loads_what_the_first_compiled(tmp_path):
    cache = tmp_path / "cache"
    first, hits_first, said_first = sweep(cache, tmp_path / "a.npz")
    assert hits_first == 0 and any(cache.iterdir()), "the first command left no compiled program"
    second, hits_second, said_second = sweep(cache, tmp_path / "b.npz")
    assert hits_second >= 1
    assert said_first and not said_second, "the first run says it compiles, the second not"
    for name in ("eigenvalue_real", "eigenvalue_imag", "certified"):
        np.testing.assert_array_equal(second[name], first[name])


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_off_keeps_nothing_and_python_caches_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _, hits, said = sweep("off", tmp_path / "a.npz")
    assert hits == 0 and not said and sorted(p.name for p in tmp_path.iterdir()) == ["a.npz"]
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


def fake_cache(directory: pathlib.Path) -> None:
    """Files as JAX and the posterior leave them, and one of the user's own."""
    directory.mkdir(parents=True)
    for name in ("jit_a-1f-cache", "jit_a-1f-atime", "jit_b-2e-cache", "jit_b-2e-atime"):
        (directory / name).write_bytes(b"x" * 1000)
    (directory / "posterior").mkdir()
    (directory / "posterior" / "run.warm.npz").write_bytes(b"y" * 500)
    (directory / "notes.txt").write_text("mine")


def test_cache_command_shows_and_clears_only_its_own_files(tmp_path, monkeypatch, capsys):
    """``axojax cache`` counts the programs and warm states; ``clear`` removes them and
    nothing else (a cache pointed at a folder of one's own keeps one's files)."""
    directory = tmp_path / "c"
    fake_cache(directory)
    monkeypatch.setenv("AXOJAX_CACHE_DIR", str(directory))
    monkeypatch.delenv("AXOJAX_CACHE_MAX_MB", raising=False)
    assert main(["cache", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["programs"], doc["warm_states"], doc["max_mb"]) == (2, 1, 1024)
    assert doc["program_mb"] == pytest.approx(4000 / 1e6)
    assert main(["cache", "clear"]) == 0
    out = capsys.readouterr().out
    assert "removed 2 compiled programs and 1 posterior warm states" in out, out
    assert sorted(p.name for p in directory.iterdir()) == ["notes.txt"]
    monkeypatch.setenv("AXOJAX_CACHE_DIR", "off")
    assert main(["cache"]) == 0
    assert "off" in capsys.readouterr().out


@pytest.mark.parametrize(
    "value, expected", [("", 1024.0), ("512", 512.0), ("-1", -1.0), ("0.5", 0.5)]
)
def test_cache_bound_setting_accepts_sizes_and_no_bound(monkeypatch, value, expected):
    monkeypatch.setenv("AXOJAX_CACHE_MAX_MB", value)
    assert ax.cache.max_mb_setting() == expected


@pytest.mark.parametrize("value", ["0", "-5", "lots", "nan", "inf"])
def test_cache_bound_setting_refuses_in_one_line(monkeypatch, capsys, value):
    monkeypatch.setenv("AXOJAX_CACHE_MAX_MB", value)
    assert main(["cache"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("axojax: error: AXOJAX_CACHE_MAX_MB: ") and repr(value) in err, err
    assert "\n" not in err


EVICT = """
import sys, jax, jax.numpy as jnp
from axojax.cache import enable_compilation_cache
directory = enable_compilation_cache(sys.argv[1], max_mb=float(sys.argv[2]))
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)  # keep even tiny ones
for k in range(12):
    jax.jit(lambda x, k=k: jnp.sin(x) * k + jnp.cumsum(x) ** (k % 3 + 1))(jnp.ones(100 + k))
"""


@needs_quiet_loader
def test_cache_keeps_within_its_bound(tmp_path):
    """Twelve small programs take about 90 kB; with a 50 kB bound JAX keeps the most
    recent within it, without one all of them."""

    def kept(bound):
        directory = tmp_path / str(bound)
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        subprocess.run(
            [sys.executable, "-c", EVICT, str(directory), str(bound)],
            env=env,
            check=True,
            timeout=120,
            capture_output=True,
        )
        return ax.cache.cache_contents(directory)

    free, bounded = kept(-1), kept(0.05)
    assert free.program_bytes > 60_000 and free.programs >= 12
    # JAX bounds the programs; each keeps an 8-byte last-use stamp beside it
    assert 0 < bounded.program_bytes <= 50_000 + 8 * bounded.programs
    assert bounded.programs < free.programs


def test_first_run_message_only_for_compiling_commands_on_an_empty_cache():
    from axojax.cli.main import first_run

    assert first_run(["compare", "--data", "human_sperm"], 0)
    assert first_run(["modes", "--model", "seven"], 0)
    assert not first_run(["compare", "--data", "human_sperm"], 3)
    assert not first_run(["compare", "--quiet"], 0)
    assert not first_run(["modes", "--help"], 0)
    assert not first_run(["plot", "a.json"], 0) and not first_run(["cache", "clear"], 0)


def test_cache_clear_that_cannot_remove_says_so_in_one_line(tmp_path, monkeypatch, capsys):
    def refuse(directory):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setenv("AXOJAX_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(ax.cache, "clear_cache", refuse)
    assert main(["cache", "clear"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"axojax: error: cache clear: {tmp_path}: Permission denied", err
