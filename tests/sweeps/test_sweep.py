"""Sweeps: agreement with dominant_mode and scipy, resumability, sharding, CLI, plot."""

import importlib.metadata
import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import scipy.linalg

import axojax as ax
import axojax.sweeps.engine as engine
from axojax._runtime import blocking_batched_lapack
from axojax.cli.main import main

AXES = {"p": np.array([150.0, 300.0, 600.0]), "ks": np.array([1e3, 1e5])}
BASE = ax.Params(cl=0.02)


@pytest.fixture(scope="module")
def model():
    return ax.models.four()


@pytest.fixture(scope="module")
def reference(model):
    return ax.sweep(model, BASE, AXES, kl_ratio=100.0, chunk_size=4, progress=False)


def test_every_point_equals_dominant_mode_and_scipy(model, reference):
    assert reference.shape == (3, 2)
    for i, p in enumerate(AXES["p"]):
        for j, ks in enumerate(AXES["ks"]):
            params = BASE.replace(p=p, ks=ks, kl=ks / 100.0)
            mode = ax.dominant_mode(model, params)
            lam = complex(mode.eigenvalue)
            assert reference.data["eigenvalue_real"][i, j] == pytest.approx(
                lam.real, rel=1e-10, abs=1e-9
            )
            assert reference.data["eigenvalue_imag"][i, j] == pytest.approx(
                lam.imag, rel=1e-10, abs=1e-9
            )
            assert reference.data["frequency_hz"][i, j] == pytest.approx(
                float(mode.frequency_hz()), rel=1e-10, abs=1e-9
            )
            assert reference.data["classification"][i, j] == int(mode.classification)
            if int(mode.direction):
                assert reference.data["wavelength_um"][i, j] == pytest.approx(
                    float(mode.wavelength_um()), rel=1e-8
                )
            else:
                assert np.isnan(reference.data["wavelength_um"][i, j])
            # independent: scipy's QZ on the same matrices
            s = ax.assemble(model, params)
            ev = scipy.linalg.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
            top = ev[np.argmax(ev.real)]
            assert reference.data["eigenvalue_real"][i, j] == pytest.approx(
                top.real, rel=1e-8, abs=1e-8
            )
            assert reference.data["eigenvalue_imag"][i, j] == pytest.approx(
                abs(top.imag), rel=1e-8, abs=1e-6
            )


def test_interrupted_sweep_resumes(model, reference, tmp_path, monkeypatch):
    out = tmp_path / "map.npz"
    real = engine._evaluator
    calls = {"n": 0}

    def counting(*args, fail_after=None):
        f = real(*args)

        def wrapped(rows):
            calls["n"] += 1
            if fail_after is not None and calls["n"] > fail_after:
                raise KeyboardInterrupt
            return f(rows)

        return wrapped

    monkeypatch.setattr(engine, "_evaluator", lambda *a: counting(*a, fail_after=1))
    with pytest.raises(KeyboardInterrupt):
        ax.sweep(model, BASE, AXES, kl_ratio=100.0, chunk_size=2, out=out, progress=False)
    assert not out.exists() and len(list((tmp_path / "map.npz.parts").glob("chunk_*.npz"))) == 1
    calls["n"] = 0
    monkeypatch.setattr(engine, "_evaluator", lambda *a: counting(*a))
    resumed = ax.sweep(model, BASE, AXES, kl_ratio=100.0, chunk_size=2, out=out, progress=False)
    assert calls["n"] == 2  # 3 chunks of 2 points, 1 already done
    assert out.exists() and not (tmp_path / "map.npz.parts").exists()
    loaded = ax.SweepResult.load(out)
    for k in reference.data:
        np.testing.assert_array_equal(resumed.data[k], reference.data[k])
        np.testing.assert_array_equal(loaded.data[k], reference.data[k])
    np.testing.assert_array_equal(loaded.coords["ks"], AXES["ks"])
    assert loaded.meta["fixed"]["cl"] == 0.02 and loaded.meta["kl_ratio"] == 100.0


def run_two_device_script(script: str, marker: str, what: str) -> None:
    """Run ``script`` in a fresh process (its own XLA flags); it must print ``marker``
    within 180 s, which a jaxlib 0.10 pool deadlock would prevent."""
    try:
        proc = subprocess.run(
            [sys.executable, "-c", script], capture_output=True, text=True, timeout=180
        )
    except subprocess.TimeoutExpired:
        pytest.fail(
            f"{what} did not finish in 180 s (jaxlib 0.10 pool deadlock; see axojax/_runtime.py)"
        )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert marker in proc.stdout


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_two_cpu_devices_identical(tmp_path):
    script = textwrap.dedent(
        """
        import os
        os.environ["XLA_FLAGS"] = "--xla_force_host_platform_device_count=2"
        import numpy as np, jax, axojax as ax
        assert jax.device_count() == 2
        m = ax.models.two()
        axes = {"p": np.linspace(200, 500, 5), "kl": np.array([1e2, 1e3])}
        a = ax.sweep(m, ax.Params(), axes, chunk_size=4, devices=2, progress=False)
        b = ax.sweep(m, ax.Params(), axes, chunk_size=4, devices=1, progress=False)
        for k in a.data:
            np.testing.assert_array_equal(a.data[k], b.data[k])
        # the structured solver's loops inside shard_map (no collectives: check_vma off)
        small, few = ax.models.two(n_elements=4), {"p": np.array([200.0, 400.0, 800.0])}
        c = ax.sweep(small, ax.Params(), few, chunk_size=4, devices=2, progress=False, solver=ax.eigen.Arnoldi())
        d = ax.sweep(small, ax.Params(), few, chunk_size=4, devices=1, progress=False, solver=ax.eigen.Dense())
        assert (c.data["certified"] == 1).all()
        for k in ("eigenvalue_real", "eigenvalue_imag"):
            np.testing.assert_allclose(c.data[k], d.data[k], rtol=1e-8, atol=1e-8)
        print("identical")
        """
    )
    run_two_device_script(script, "identical", "the 2-device sweep")


def test_cli_sweep_and_plot(tmp_path, capsys):
    out = tmp_path / "s.npz"
    code = main(
        [
            "sweep",
            "--model",
            "two",
            "--kl",
            "1e2:1e3:2",
            "--p",
            "200,400,600",
            "--cl",
            "0.01",
            "--out",
            str(out),
            "--json",
        ]
    )
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["shape"] == [2, 3] and doc["points"] == 6  # axes in command-line order: kl, then p
    with np.load(out) as f:
        assert list(json.loads(str(f["meta"]))["axes"]) == ["kl", "p"]
        np.testing.assert_allclose(f["p"], [200, 400, 600])
        assert f["frequency_hz"].shape == (2, 3) and f["classification"].dtype == np.int8
        mode = ax.dominant_mode(ax.models.two(), ax.Params(p=400.0, kl=1e3, cl=0.01))
        assert f["frequency_hz"][1, 1] == pytest.approx(float(mode.frequency_hz()), rel=1e-10)
    fig = tmp_path / "s.png"
    assert main(["plot", str(out), "--out", str(fig)]) == 0
    assert fig.stat().st_size > 10_000


def test_cli_sweep_errors(tmp_path, capsys):
    assert main(["sweep", "--model", "two", "--p", "1:2:x", "--out", str(tmp_path / "a.npz")]) == 2
    err = capsys.readouterr().err
    assert "--p" in err and len(err.strip().splitlines()) == 1
    assert (
        main(["sweep", "--model", "two", "--ks", "log:-1:2:3", "--out", str(tmp_path / "a.npz")])
        == 2
    )
    assert "--ks" in capsys.readouterr().err
    assert main(["plot", str(tmp_path / "missing.npz"), "--out", str(tmp_path / "x.png")]) == 2


def test_netcdf_export_matches_npz(reference, tmp_path, capsys):
    """The NetCDF file holds the same coordinates, arrays and metadata as the .npz, with
    units and flag meanings; the CLI writes both."""
    xr = pytest.importorskip("xarray")
    path = tmp_path / "s.nc"
    reference.to_netcdf(path)
    with xr.open_dataset(path) as ds:
        assert tuple(ds.sizes) == tuple(AXES) and tuple(ds.sizes.values()) == reference.shape
        for k, v in AXES.items():
            np.testing.assert_array_equal(ds[k].values, v)
        for k, v in reference.data.items():
            np.testing.assert_array_equal(ds[k].values, v)
        assert ds["frequency_hz"].attrs["units"] == "Hz"
        assert ds["classification"].attrs["flag_meanings"] == "stable flutter divergence"
        assert ds["direction"].attrs["flag_meanings"] == "retrograde none anterograde"
        assert json.loads(ds.attrs["axojax_meta"]) == reference.meta
        assert ds.attrs["fixed_cl"] == pytest.approx(0.02)
    npz, nc = tmp_path / "c.npz", tmp_path / "c.nc"
    assert (
        main(
            [
                "sweep",
                "--model",
                "two",
                "--p",
                "200,400",
                "--out",
                str(npz),
                "--netcdf",
                str(nc),
                "--json",
            ]
        )
        == 0
    )
    assert json.loads(capsys.readouterr().out)["netcdf"] == str(nc)
    with xr.open_dataset(nc) as ds, np.load(npz) as f:
        np.testing.assert_array_equal(ds["growth_rate_per_s"].values, f["growth_rate_per_s"])
    assert (
        main(
            [
                "sweep",
                "--model",
                "two",
                "--p",
                "200,400",
                "--out",
                str(npz),
                "--netcdf",
                str(tmp_path / "c.cdf"),
            ]
        )
        == 2
    )
    assert "--netcdf" in capsys.readouterr().err


def test_netcdf_without_xarray_is_one_line_error(reference, tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "xarray", None)  # import xarray now raises ImportError
    with pytest.raises(ImportError, match=r"axojax\[netcdf\]"):
        reference.to_xarray()
    assert (
        main(
            [
                "sweep",
                "--model",
                "two",
                "--p",
                "200,400",
                "--out",
                str(tmp_path / "c.npz"),
                "--netcdf",
                str(tmp_path / "c.nc"),
            ]
        )
        == 2
    )
    err = capsys.readouterr().err
    assert "--netcdf" in err and "axojax[netcdf]" in err and len(err.strip().splitlines()) == 1


@pytest.mark.skipif(
    not blocking_batched_lapack(importlib.metadata.version("jaxlib")),
    reason="this jaxlib has no blocking batched-LAPACK path (only 0.10.x and 0.11.0 do)",
)
def test_batched_lapack_over_two_devices_does_not_deadlock():
    """The evaluator the sweep used before it looped over points: jit(vmap) of the dense
    metrics, sharded over 2 host CPU devices, so every eig/LU/Cholesky is a *batched*
    LAPACK call in both shards at once. On jaxlib 0.10.x this deadlocked XLA's 2-thread
    intra-op pool (axojax/_runtime.py); the wider pool axojax sets there must let it run."""
    script = textwrap.dedent(
        """
        import os
        os.environ["XLA_FLAGS"] = "--xla_force_host_platform_device_count=2"
        import numpy as np, jax, jax.numpy as jnp, axojax as ax
        from jax.sharding import Mesh, NamedSharding, PartitionSpec as P
        from axojax.sweeps.engine import _metrics
        m, params = ax.models.two(), ax.Params().broadcast(())
        sh = NamedSharding(Mesh(np.array(jax.devices()), ("x",)), P("x"))
        one = lambda r: _metrics(m, params.with_values({"p": r[0], "kl": r[1]}), ax.Units(), ax.eigen.Dense())
        f = jax.jit(jax.vmap(one), in_shardings=sh, out_shardings=sh)
        grid = np.stack(np.meshgrid(np.linspace(200, 500, 6), [1e2, 1e3], indexing="ij"), -1).reshape(-1, 4, 2)
        lam = [np.asarray(f(jax.device_put(jnp.asarray(rows), sh))["eigenvalue_real"]) for rows in grid]
        last = ax.Params(p=float(grid[-1, -1, 0]), kl=float(grid[-1, -1, 1]))
        ref = ax.dominant_mode(m, last, solver=ax.eigen.Dense())
        assert abs(lam[-1][-1] - float(ref.eigenvalue.real)) <= 1e-9 * (1 + abs(lam[-1][-1]))
        print("finished", jax.__version__, os.environ.get("NPROC"))
        """
    )
    run_two_device_script(script, "finished", "batched LAPACK calls over 2 CPU devices")


@pytest.mark.parametrize(
    "version, affected",
    [
        ("0.9.2", False),
        ("0.10.0", True),
        ("0.10.2", True),
        ("0.11.0", True),
        ("0.11.1", False),
        ("0.12.0", False),
        ("0.10.2.dev20260101+cuda", True),
    ],
)
def test_which_jaxlib_blocks_on_batched_lapack(version, affected):
    from axojax import _runtime

    assert _runtime.blocking_batched_lapack(version) is affected
