"""A sweep over two processes (jax.distributed on localhost, CPU) equals the same sweep
in one process, bit for bit, and resumes from chunks another job left."""

import json
import os
import pathlib
import socket
import subprocess
import sys

import numpy as np
import pytest

import axojax as ax

ROOT = pathlib.Path(__file__).resolve().parents[2]
TIMEOUT_S = 240  # two processes each import jax and compile once; never hang the suite
AXES = {"p": np.array([150.0, 250.0, 400.0, 600.0, 900.0]), "ks": np.array([1e3, 1e5])}
FLAGS = [
    "--model",
    "two",
    "--elements",
    "4",
    "--p",
    "150,250,400,600,900",
    "--ks",
    "1e3,1e5",
    "--cl",
    "0.02",
    "--chunk",
    "3",
    "--solver",
    "dense",
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def run_job(out, n: int = 2) -> list[dict]:
    """``axojax sweep`` in n processes joined by jax.distributed; their JSON reports."""
    port = free_port()
    env = {**os.environ, "JAX_PLATFORMS": "cpu"}
    cmd = [
        sys.executable,
        "-m",
        "axojax.cli.main",
        "sweep",
        *FLAGS,
        "--out",
        str(out),
        "--json",
        "--coordinator",
        f"localhost:{port}",
        "--num-processes",
        str(n),
    ]
    procs = [
        subprocess.Popen(
            [*cmd, "--process-id", str(i)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
            cwd=ROOT,
        )
        for i in range(n)
    ]
    reports = []
    try:
        for p in procs:
            stdout, stderr = p.communicate(timeout=TIMEOUT_S)
            assert p.returncode == 0, stderr[-3000:]
            reports.append(json.loads(stdout))
    except subprocess.TimeoutExpired:
        pytest.fail(f"the {n}-process sweep did not finish in {TIMEOUT_S} s")
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.communicate()
    return reports


@pytest.fixture(scope="module")
def single():
    return ax.sweep(
        ax.models.two(n_elements=4),
        ax.Params(cl=0.02),
        AXES,
        chunk_size=3,
        progress=False,
        solver=ax.eigen.Dense(),
    )


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_two_processes_resume_and_equal_one(single, tmp_path, monkeypatch):
    """An interrupted one-process run leaves 2 of 4 chunks; a 2-process job resumes it
    (the chunk layout does not depend on the process count) and its merged file equals
    the one-process sweep bit for bit. (One job: each costs two jax start-ups.)"""
    import axojax.sweeps.engine as engine

    out = tmp_path / "map.npz"
    real = engine._evaluator
    calls = {"n": 0}

    def interrupting(*args):
        f = real(*args)

        def wrapped(rows):
            calls["n"] += 1
            if calls["n"] > 2:
                raise KeyboardInterrupt
            return f(rows)

        return wrapped

    monkeypatch.setattr(engine, "_evaluator", interrupting)
    with pytest.raises(KeyboardInterrupt):
        ax.sweep(
            ax.models.two(n_elements=4),
            ax.Params(cl=0.02),
            AXES,
            chunk_size=3,
            out=out,
            progress=False,
            solver=ax.eigen.Dense(),
        )
    parts = tmp_path / "map.npz.parts"
    assert len(list(parts.glob("chunk_*.npz"))) == 2  # of 4 chunks

    reports = run_job(out)
    assert [r["process"] for r in reports] == [[0, 2], [1, 2]]
    assert out.exists() and not parts.exists()
    merged = ax.SweepResult.load(out)
    assert merged.shape == (5, 2)
    for k, v in single.data.items():
        np.testing.assert_array_equal(merged.data[k], v, err_msg=k)
    np.testing.assert_array_equal(merged.coords["p"], AXES["p"])
    assert merged.meta == json.loads(json.dumps(single.meta))
    # independent of the engine: the dominant eigenvalue of one point by numpy's eig
    s = ax.assemble(ax.models.two(n_elements=4), ax.Params(cl=0.02, p=400.0, ks=1e5))
    ev = np.linalg.eigvals(np.linalg.solve(np.asarray(s.C), -np.asarray(s.A)))
    assert merged.data["eigenvalue_real"][2, 1] == pytest.approx(ev.real.max(), rel=1e-8, abs=1e-8)


@pytest.mark.parametrize(
    "flags, message",
    [
        (["--coordinator", "localhost"], "--coordinator"),
        (["--num-processes", "0"], "--num-processes"),
        (["--num-processes", "2", "--process-id", "2"], "--process-id"),
    ],
)
def test_cli_distributed_flag_errors(flags, message, tmp_path, capsys):
    from axojax.cli.main import main

    assert (
        main(
            ["sweep", "--model", "two", "--p", "200,400", "--out", str(tmp_path / "a.npz"), *flags]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_library_refuses_several_processes_without_out(monkeypatch):
    import axojax.sweeps.engine as engine
    from axojax.sweeps.processes import Share

    monkeypatch.setattr(engine.Share, "current", classmethod(lambda cls: Share(1, 2)))
    with pytest.raises(ValueError, match="out=FILE.npz"):
        ax.sweep(ax.models.two(n_elements=4), ax.Params(), {"p": [200.0]}, progress=False)
