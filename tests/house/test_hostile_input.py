"""Hostile input, one class of defect per test (issue 21), parametrised over subcommands.

Every case ends in one line on stderr naming the flag or file, exit status 2, nothing on
stdout and no file written. The classes:

1. sizes: models and grids that cannot fit in memory are refused before any work, with
   the estimate (``--elements``, ``--model-file``, sweep axes, ``--harmonics``).
2. magnitudes: parameters beyond float64's reach (|value| > 1e9), units, rotations,
   cubic stiffening, perturbations and durations out of range.
3. conflicts: ``--kl-ratio`` with ``--kl`` in every command that takes both.
4. output paths: one rule in every command, before the work: the suffix it writes, an
   existing writable directory (never created), not a directory itself.
5. files read back: ``axojax plot`` on truncated, foreign, empty or inconsistent files;
   a resumed sweep recomputes damaged chunks.
6. concurrency and interruption: a second sweep on the same ``--out`` refuses while the
   first runs; ``kill -9`` at any moment leaves no file or a complete one.
7. pipes: a reader that goes away (``| head``) ends the command quietly.
8. argparse: no abbreviated flags, values starting with '-' are values.
9. data: beat data that no fit can use.
10. wrong diagnoses: the flag named is the one at fault.
"""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import axojax as ax
import axojax.sweeps.engine as engine
from axojax import _io
from axojax.cli.main import EXIT_SIGPIPE, main

TWO = ["--model", "two", "--elements", "4"]


def one_line(argv, capsys, flag, code=2):
    rc = main(argv)
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert rc == code, err
    assert out == ""
    assert len(lines) == 1 and lines[0].startswith("axojax: error: ") and flag in lines[0], err
    return lines[0]


# -- 1. sizes ----------------------------------------------------------------------------


def test_sizes_refused_with_the_estimate(tmp_path, capsys):
    n = 3000
    big = tmp_path / "big.json"
    big.write_text(
        json.dumps(
            {
                "filaments": [{"position": [float(i), 0.0]} for i in range(n)],
                "links": [{"between": [i, i + 1]} for i in range(n - 1)],
            }
        )
    )
    cases = [
        (["modes", "--elements", "100000000"], "--elements"),
        (["modes", "--elements", "50000"], "--elements"),
        (["critical", "--model-file", str(big)], "--model-file"),
        (
            ["sweep", "--p", "0:1:100000", "--ks", "0:1:100000", "--out", str(tmp_path / "h.npz")],
            "--p",
        ),
        (["sweep", "--p", "0:1:100000000000", "--out", str(tmp_path / "h.npz")], "--p"),
        (["orbit", "--elements", "40", "--harmonics", "99"], "--harmonics"),
        # the full spectrum's dense matrices are checked before the model is built (a
        # 1000-element model took minutes to build before the refusal)
        (["modes", "--elements", "1000"], "--elements"),
        (
            [
                "fit",
                "--model",
                "two",
                "--elements",
                "3",
                "--free",
                "p",
                "--target-frequency",
                "40",
                "--starts",
                "100000000000",
            ],
            "--starts",
        ),
    ]
    spec = tmp_path / "big.toml"
    spec.write_text('elements = 100000\nfree = ["p"]\n[[condition]]\nfrequency_hz = 40\n')
    cases.append((["fit", "--spec", str(spec)], "--spec"))
    for argv, flag in cases:
        line = one_line(argv, capsys, flag)
        assert any(s in line for s in ("GiB", "more than", "1..100000", "1..10000,")), line
    assert not list(tmp_path.glob("h.npz*"))


# -- 2. magnitudes -----------------------------------------------------------------------

COMMANDS = {
    "modes": ["modes", *TWO],
    "critical": ["critical", *TWO],
    "simulate": ["simulate", *TWO, "--t-end", "0.01"],
    "orbit": ["orbit", *TWO],
    "sweep": ["sweep", *TWO, "--out", "s.npz"],
    "fit": ["fit", "--no-mesh-check", *TWO, "--free", "ks", "--target-frequency", "30"],
}


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize(
    "flag,value",
    [
        ("--p", "1e300"),
        ("--ks", "1e300"),
        ("--cl", "1e300"),
        ("--gamma", "-1e300"),
        ("--imbalance", "1e-300"),
        ("--length-um", "1e300"),
        ("--rotation-deg", "1e300"),
    ],
)
def test_magnitudes_refused(command, flag, value, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = COMMANDS[command] + [flag, value]
    if command == "sweep" and flag not in ("--length-um", "--rotation-deg"):
        argv = argv + (["--gamma", "0:1:2"] if flag != "--gamma" else ["--p", "100:200:2"])
    elif command == "sweep":
        argv = argv + ["--p", "100:200:2"]
    if flag == "--rotation-deg":
        argv = [a if a != "two" else "four" for a in argv]
    one_line(argv, capsys, flag)
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["simulate", *TWO, "--t-end", "0.01", "--cubic", "1e300"], "--cubic"),
        (["orbit", *TWO, "--p", "300", "--cubic", "1e300"], "--cubic"),
        (["simulate", *TWO, "--t-end", "0.01", "--perturbation-um", "1e300"], "--perturbation-um"),
        (["simulate", *TWO, "--t-end", "1e300"], "--t-end"),
        (["simulate", *TWO, "--t-end", "0.01", "--max-steps", "100000000000"], "--max-steps"),
        (["sweep", *TWO, "--p", "1:1e300:3", "--out", "s.npz"], "--p"),
        (["sweep", *TWO, "--p", "log:1:1e300:3", "--out", "s.npz"], "--p"),
    ],
)
def test_other_magnitudes_refused(argv, flag, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    one_line(argv, capsys, flag)
    assert not list(tmp_path.iterdir())


def test_magnitude_limit_is_where_float64_still_answers():
    """The limit (1e9) is inside the range where the dominant eigenvalue still agrees with
    scipy's QZ on the same matrices; 1e300 is refused in Python too."""
    import scipy.linalg

    model = ax.models.two(n_elements=4)
    for name in ("ks", "kl", "cl", "p"):
        params = ax.Params().replace(**{name: ax.params.MAX_MAGNITUDE})
        lam = complex(ax.dominant_mode(model, params, ax.eigen.Dense()).eigenvalue)
        s = ax.assemble(model, params)
        ev = scipy.linalg.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
        top = ev[np.argmax(ev.real)]
        assert lam.real == pytest.approx(top.real, rel=1e-6, abs=1e-6 * abs(top)), name
        with pytest.raises(ValueError, match=f"{name} must be at most"):
            ax.dominant_mode(model, ax.Params().replace(**{name: 1e300}))


# -- 3. conflicts ------------------------------------------------------------------------


@pytest.mark.parametrize("command", list(COMMANDS))
def test_kl_ratio_with_kl_refused(command, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = (
        COMMANDS[command]
        + ["--kl-ratio", "1000", "--kl", "5"]
        + (["--p", "100:200:2"] if command == "sweep" else [])
    )
    one_line(argv, capsys, "--kl-ratio")


# -- 4. output paths ---------------------------------------------------------------------

OUTPUTS = [
    (["simulate", *TWO, "--t-end", "0.01"], "--out", ".npz"),
    (["simulate", *TWO, "--t-end", "0.01"], "--gif", ".gif"),
    (["orbit", *TWO, "--p", "300"], "--out", ".npz"),
    (["orbit", *TWO, "--p", "300"], "--plot", ".png"),
    (["sweep", *TWO, "--p", "100:200:2"], "--out", ".npz"),
    (["sweep", *TWO, "--p", "100:200:2", "--out", "ok.npz"], "--netcdf", ".nc"),
    (["plot", "--model", "seven"], "--out", ".png"),
]


@pytest.mark.parametrize("argv,flag,suffix", OUTPUTS, ids=[f"{a[0]}{f}" for a, f, _ in OUTPUTS])
@pytest.mark.parametrize("where", ["proc", "missing-dir", "file-as-dir", "suffix", "directory"])
def test_output_paths_one_rule(argv, flag, suffix, where, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "somefile").write_text("x")
    (tmp_path / f"adir{suffix}").mkdir()
    path = {
        "proc": f"/proc/x{suffix}",
        "missing-dir": f"missing/dir/x{suffix}",
        "file-as-dir": f"somefile/x{suffix}",
        "suffix": "x.txt",
        "directory": f"adir{suffix}",
    }[where]
    before = sorted(os.listdir(tmp_path))
    one_line(argv + [flag, path], capsys, flag)
    assert sorted(os.listdir(tmp_path)) == before  # nothing written, no directory created


def test_check_output_path_rule(tmp_path):
    assert _io.check_output_path(tmp_path / "a.npz", (".npz",)) == tmp_path / "a.npz"
    for bad, match in (
        (tmp_path / "a.txt", "expected a .npz"),
        (tmp_path / "no" / "a.npz", "does not exist"),
        (tmp_path, "expected a .npz"),
    ):
        with pytest.raises(ValueError, match=match):
            _io.check_output_path(bad, (".npz",))
    assert list(tmp_path.iterdir()) == []  # the probe file is gone


# -- 5. files read back ------------------------------------------------------------------


@pytest.fixture(scope="module")
def good_files(tmp_path_factory):
    d = tmp_path_factory.mktemp("good")
    sweep = ax.sweep(
        ax.models.two(n_elements=4), ax.Params(), {"p": [100.0, 200.0]}, progress=False
    )
    sweep.save(d / "sweep.npz")
    return d


def _bad_files(d, good):
    data = (good / "sweep.npz").read_bytes()
    (d / "truncated.npz").write_bytes(data[: len(data) // 2])
    (d / "zero.npz").write_bytes(b"")
    (d / "text.npz").write_text("not a zip")
    np.savez(d / "foreign.npz", a=np.arange(3))
    np.savez(d / "empty.npz")
    np.savez(d / "badkind.npz", meta=np.array(json.dumps({"kind": "banana"})))
    np.savez(d / "metalist.npz", meta=np.array(json.dumps([1, 2])))
    np.savez(d / "metanotjson.npz", meta=np.array("{"))
    np.savez(d / "simulation-only-meta.npz", meta=np.array(json.dumps({"kind": "simulation"})))
    np.savez(
        d / "sweep-without-metrics.npz",
        meta=np.array(json.dumps({"kind": "sweep", "axes": ["p"]})),
        p=np.arange(3.0),
    )
    np.savez(d / "branch-only-meta.npz", meta=np.array(json.dumps({"kind": "orbit_branch"})))
    with np.load(good / "sweep.npz") as f:
        arrays = {k: f[k] for k in f.files}
    arrays["frequency_hz"] = arrays["frequency_hz"][:1]
    np.savez(d / "sweep-wrong-shape.npz", **arrays)
    return sorted(p.name for p in d.iterdir())


def test_plot_checks_kind_and_contents(good_files, tmp_path, capsys):
    names = _bad_files(tmp_path, good_files)
    assert len(names) == 12
    for name in names:
        one_line(["plot", str(tmp_path / name), "--out", str(tmp_path / "fig.png")], capsys, "FILE")
    assert not (tmp_path / "fig.png").exists()
    assert main(["plot", str(good_files / "sweep.npz"), "--out", str(tmp_path / "fig.png")]) == 0
    capsys.readouterr()


def test_resumed_sweep_recomputes_damaged_chunks(tmp_path, monkeypatch):
    model = ax.models.two(n_elements=4)
    axes = {"p": np.array([100.0, 200.0, 300.0, 400.0]), "gamma": np.array([0.0, 1.0])}
    reference = ax.sweep(model, ax.Params(), axes, chunk_size=2, progress=False)
    out = tmp_path / "s.npz"

    def interrupted(self, path):
        raise KeyboardInterrupt  # every chunk written, the merged file not

    monkeypatch.setattr(engine.SweepResult, "save", interrupted)
    with pytest.raises(KeyboardInterrupt):
        ax.sweep(model, ax.Params(), axes, chunk_size=2, progress=False, out=out)
    monkeypatch.undo()
    parts = sorted((tmp_path / "s.npz.parts").glob("chunk_*.npz"))
    assert len(parts) == 4 and not out.exists()
    parts[0].write_bytes(parts[0].read_bytes()[:100])  # truncated
    parts[1].write_bytes(b"")  # empty
    np.savez(parts[2], a=np.arange(2))  # foreign
    lines = []
    result = ax.sweep(
        model, ax.Params(), axes, chunk_size=2, progress=False, out=out, log=lines.append
    )
    assert len(lines) == 1 and "1 of 4 chunks were done" in lines[0] and "3 damaged" in lines[0]
    for k in result.data:
        np.testing.assert_array_equal(result.data[k], reference.data[k])
    assert not (tmp_path / "s.npz.parts").exists() and not list(tmp_path.glob(".*tmp*"))


# -- 6. concurrency and interruption -------------------------------------------------------


def test_second_sweep_on_same_out_refuses_cleanly(tmp_path, capsys):
    out = tmp_path / "s.npz"
    with _io.exclusive(tmp_path / "s.npz.lock", str(out)):  # what a running sweep holds
        one_line(["sweep", *TWO, "--p", "100:200:2", "--out", str(out)], capsys, "--out")
    assert not out.exists()
    assert main(["sweep", *TWO, "--p", "100:200:2", "--out", str(out)]) == 0
    capsys.readouterr()
    assert out.exists() and not (tmp_path / "s.npz.lock").exists()


def test_atomic_path_never_leaves_a_partial_file(tmp_path):
    target = tmp_path / "x.npz"
    with pytest.raises(RuntimeError):
        with _io.atomic_path(target) as tmp:
            tmp.write_bytes(b"partial")
            raise RuntimeError("killed")
    assert list(tmp_path.iterdir()) == []
    names = set()
    for _ in range(3):
        with _io.atomic_path(target) as tmp:
            names.add(tmp.name)
            assert tmp.parent == tmp_path and tmp.name.endswith(".npz")
            np.savez(tmp, a=np.arange(3))
    assert len(names) == 3 and [p.name for p in tmp_path.iterdir()] == ["x.npz"]
    # a temporary of a process that died (pid 2**22 + 1 is above any pid_max default)
    stale = tmp_path / f".x.npz.{2**22 + 1}.abcd.tmp.npz"
    stale.write_bytes(b"half")
    with _io.atomic_path(target) as tmp:
        np.savez(tmp, a=np.arange(2))
    assert not stale.exists()


def _cli(*args):
    return [sys.executable, "-m", "axojax.cli.main", *args]


def test_two_identical_sweeps_at_once(tmp_path):
    """Both finish, or one refuses in one line; the file equals a one-process run."""
    out = tmp_path / "s.npz"
    argv = _cli(
        "sweep", *TWO, "--p", "100:400:24", "--gamma", "0:1:2", "--chunk", "2", "--out", str(out)
    )
    procs = [
        subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(2)
    ]
    results = [(p.wait(timeout=600), p.stderr.read()) for p in procs]
    for code, err in results:
        assert code == 0 or (
            code == 2 and len(err.strip().splitlines()) == 1 and "--out: another process" in err
        ), err
    assert any(code == 0 for code, _ in results)
    reference = ax.sweep(
        ax.models.two(n_elements=4),
        ax.Params(),
        {"p": np.linspace(100, 400, 24), "gamma": np.array([0.0, 1.0])},
        progress=False,
    )
    got = ax.SweepResult.load(out)
    for k in reference.data:
        np.testing.assert_array_equal(got.data[k], reference.data[k])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.npz"]


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", *TWO, "--p", "300", "--t-end", "0.05", "--out", "{out}"],
        [
            "orbit",
            "--model",
            "seven",
            "--elements",
            "3",
            "--harmonics",
            "3",
            "--p",
            "300",
            "--out",
            "{out}",
        ],
        ["sweep", *TWO, "--p", "100:400:40", "--chunk", "2", "--out", "{out}"],
    ],
    ids=["simulate", "orbit", "sweep"],
)
def test_kill_minus_nine_leaves_no_file_or_a_complete_one(argv, tmp_path, capsys):
    """Killed at a random moment of its start, and while it writes (the moment its
    temporary file appears): no output file or a complete one, which `axojax plot` says
    in one line; the killed process's temporary file is removed by the next write; a
    killed sweep resumes."""
    out = tmp_path / "o.npz"
    cmd = _cli(*[a.replace("{out}", str(out)) for a in argv])
    for delay in (float(np.random.default_rng(0).uniform(0.5, 3.0)), None):
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        t0 = time.monotonic()
        while proc.poll() is None:
            if delay is None and any(
                n.startswith(".o.npz") and ".tmp" in n for n in os.listdir(tmp_path)
            ):
                break  # its temporary output exists: kill it now
            if delay is not None and time.monotonic() - t0 > delay:
                break
            time.sleep(0.0005)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        code = main(["plot", str(out), "--out", str(tmp_path / "f.png")])
        err = capsys.readouterr().err
        if out.exists():
            assert code == 0, err  # complete
        else:
            assert code == 2 and len(err.strip().splitlines()) == 1 and "does not exist" in err, err
    _io.remove_stale_temporaries(out)
    assert [n for n in os.listdir(tmp_path) if n.startswith(".o.npz")] == []
    if argv[0] == "sweep":
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr
        assert not (tmp_path / "o.npz.parts").exists()


# -- 7. pipes ----------------------------------------------------------------------------


class _ClosedPipe:
    def write(self, text):
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self):
        raise BrokenPipeError(32, "Broken pipe")

    def fileno(self):
        raise OSError("no descriptor")


@pytest.mark.parametrize("json_flag", [[], ["--json"]])
def test_broken_pipe_exits_quietly(json_flag, capsys, monkeypatch):
    monkeypatch.setattr(sys, "stdout", _ClosedPipe())
    assert main(["modes", *TWO, *json_flag]) == EXIT_SIGPIPE
    assert capsys.readouterr().err == ""


def test_broken_pipe_in_a_real_pipe():
    r = subprocess.run(
        f"{sys.executable} -m axojax.cli.main modes --model seven --top 280 | head -c 10",
        shell=True,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.stderr == "" and len(r.stdout) == 10


# -- 8. argparse -------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["modes", "--gam", "1"], "--gam"),
        (["sweep", "--p", "100:300:3", "--gam=-1:1:3", "--out", "x.npz"], "--gam"),
        (["critical", "--elem", "4"], "--elem"),
        (["simulate", "--t-e", "1"], "--t-e"),
    ],
)
def test_abbreviations_refused(argv, flag, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    one_line(argv, capsys, flag)


def test_negative_values_are_values(tmp_path, capsys):
    out = tmp_path / "s.npz"
    assert main(["sweep", *TWO, "--p", "100:300:3", "--gamma", "-1:1:3", "--out", str(out)]) == 0
    assert main(["modes", *TWO, "--gamma", "-0.5", "--json"]) == 0
    assert main(["modes", *TWO, "--gamma", "-1e-3", "--json"]) == 0
    capsys.readouterr()
    result = ax.SweepResult.load(out)
    assert list(result.coords) == ["p", "gamma"] and result.coords["gamma"].tolist() == [
        -1.0,
        0.0,
        1.0,
    ]
    one_line(["modes", *TWO, "--p", "-5"], capsys, "--p")


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.startswith("axojax ")


# -- 9. data -----------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["huge", "one-point"])
def test_fit_data_no_fit_can_use(kind, tmp_path, capsys):
    t = np.arange(64) / 500.0
    s = np.linspace(0, 12, 21)
    psi = 0.5 * np.sin(2 * np.pi * 40 * t[:, None] - s[None, :] / 3)
    if kind == "huge":
        psi = psi * 1e300
    else:
        psi, s = psi[:, :1], s[:1]
    path = tmp_path / "beat.npz"
    np.savez(path, psi=psi, s_um=s, frame_rate_hz=500.0, length_um=12.0)
    one_line(["fit", *TWO, "--free", "p", "--data", str(path)], capsys, "--data")


# -- 10. wrong diagnoses -----------------------------------------------------------------


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["modes", "--rotation-deg", "1e300"], "--rotation-deg"),
        (["orbit", "--p", "300", "--cubic", "1e300"], "--cubic"),
        (["modes", "--kl-ratio", "1e-12"], "--kl-ratio"),
    ],
)
def test_the_flag_at_fault_is_named(argv, flag, capsys):
    one_line(argv, capsys, flag)


# -- 11. traced inputs and the result convention ------------------------------------------


def test_traced_parameters_out_of_range_give_nan_and_a_code():
    import jax
    import jax.numpy as jnp

    from axojax.results import RESULTS

    model = ax.models.two(n_elements=4)
    f = jax.jit(lambda p: ax.dominant_mode(model, ax.Params(p=p)))
    good = f(300.0)
    assert good.result == RESULTS.successful and np.isfinite(complex(good.eigenvalue))
    for bad in (float("nan"), -5.0, 1e300):
        mode = f(bad)
        assert mode.result == RESULTS.invalid_params and np.isnan(complex(mode.eigenvalue)), bad
    batch = jax.vmap(lambda p: ax.dominant_mode(model, ax.Params(p=p)))(jnp.array([300.0, jnp.nan]))
    assert np.isfinite(complex(batch.eigenvalue[0])) and np.isnan(complex(batch.eigenvalue[1]))
    with pytest.raises(ValueError, match="jax.vmap"):
        ax.dominant_mode(model, ax.Params(p=jnp.array([1.0, 2.0])))
    with pytest.raises(ValueError, match="jax.vmap"):
        ax.critical_force(model, ax.Params(ks=np.array([1.0, 2.0])))
    with pytest.raises(Exception, match="invalid|out of its range"):
        jax.block_until_ready(
            jax.jit(lambda p: ax.dominant_mode(model, ax.Params(p=p), throw=True))(jnp.nan)
        )


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_one_result_convention():
    from axojax.results import RESULTS, message

    model = ax.models.two(n_elements=4)
    full = ax.critical_force(model, ax.Params())
    assert full.result == RESULTS.successful and bool(full.found)
    short = ax.critical_force(model, ax.Params(), max_iter=2)  # runs out: reported, not silent
    assert short.result == RESULTS.max_steps_reached and "maximum number" in message(short.result)
    assert abs(float(short.p) - float(full.p)) < 0.1 * float(full.p)
    none = ax.critical_force(model, ax.Params(), p_max=20.0)
    assert none.result == RESULTS.no_crossing and not bool(none.found) and float(none.p) == np.inf
    with pytest.raises(Exception, match="maximum number"):
        ax.critical_force(model, ax.Params(), max_iter=2, throw=True).p.block_until_ready()
    # Trajectory.result: diffrax's code promoted (the simulation's own test, test_simulate.py,
    # checks the message it gives when the step budget runs out)
    import diffrax

    promoted = RESULTS.promote(diffrax.RESULTS.max_steps_reached)  # what Trajectory.result holds
    assert promoted == RESULTS.max_steps_reached and message(promoted).startswith(
        "The maximum number of solver steps"
    )
