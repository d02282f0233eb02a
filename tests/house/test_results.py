"""One result convention (issue 32, "Results"): every result type a user meets (mode,
critical point, sweep, simulation, limit cycle) has ``result``, an item of
``axojax.results.RESULTS``, successful on a normal small case and not on a failing one,
and a one-line ``message``; ``to_json()`` is plain JSON (the ``--json`` blocks keep their
keys) and round-trips through ``save``/``load`` where a type has them; files are written
whole; ``throw`` defaults to False everywhere; ``axojax sweep --timeout`` is refused where
it is unused or not positive."""

import inspect
import json
import os

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax import _io, results
from axojax.cli.main import main
from axojax.orbits import HarmonicBalance
from axojax.results import RESULTS
from axojax.sweeps import SweepResult

KAPPA = 10.0
ORBIT = HarmonicBalance(harmonics=4)


@pytest.fixture(scope="module")
def two():
    return ax.models.two(n_elements=2)


def one_line(text: str) -> bool:
    return bool(text) and "\n" not in text


def strict_json(doc) -> dict:
    """``doc`` through strict JSON (no NaN): what a file or a pipe would carry."""
    return json.loads(json.dumps(doc, allow_nan=False))


def is_item(result) -> bool:
    return isinstance(result, RESULTS)


# -- throw ------------------------------------------------------------------------------


def test_one_throw_default():
    """Every public function that can fail takes throw=, defaulting to False
    (``critical_force`` forwards its options to the traceable implementation)."""
    from axojax.critical import critical_force_impl

    for f in (ax.dominant_mode, critical_force_impl, ax.limit_cycle, ax.simulate, ax.sweep):
        assert inspect.signature(f).parameters["throw"].default is False, f.__name__


# -- mode -------------------------------------------------------------------------------


def test_mode(two):
    mode = ax.dominant_mode(two, ax.Params(p=300.0))
    assert is_item(mode.result) and mode.result == RESULTS.successful
    assert mode.message == "successful"
    doc = strict_json(mode.to_json())
    assert set(doc) == {
        "eigenvalue",
        "classification",
        "growth_rate_per_s",
        "frequency_hz",
        "wavelength_um",
        "velocity_um_per_s",
        "direction",
        "out_of_plane_ratio",
        "amplitude_dip",
        "wavelength_sensitive",
    }
    tau = ax.Units().tau_s
    assert doc["frequency_hz"] == pytest.approx(
        abs(complex(mode.eigenvalue).imag) / (2 * np.pi * tau)
    )
    # failing: a traced parameter out of range (concrete ones are refused before any work)
    bad = jax.jit(lambda p: ax.dominant_mode(two, ax.Params(p=p)))(jnp.nan)
    assert is_item(bad.result) and bad.result == RESULTS.invalid_params
    assert not results.is_successful(bad.result)
    assert one_line(bad.message) and "out of its range" in bad.message
    # a batch: one item holding an array, and a one-line count of the failures
    batch = jax.vmap(lambda p: ax.dominant_mode(two, ax.Params(p=p)))(jnp.array([300.0, jnp.nan]))
    assert is_item(batch.result)
    assert np.array_equal(np.asarray(batch.result == RESULTS.successful), [True, False])
    assert one_line(batch.message) and batch.message.startswith("1 of 2 failed (invalid_params 1)")


# -- critical point ---------------------------------------------------------------------


def test_critical(two):
    crit = ax.critical_force(two, ax.Params())
    assert is_item(crit.result) and crit.result == RESULTS.successful
    assert crit.message == "successful"
    doc = strict_json(crit.to_json())
    assert doc["p"] == float(crit.p)
    lam = complex(crit.eigenvalue)
    assert doc["frequency_hz"] == pytest.approx(abs(lam.imag) / (2 * np.pi * ax.Units().tau_s))
    none = ax.critical_force(two, ax.Params(), p_max=20.0)  # no crossing below p = 20
    assert is_item(none.result) and none.result == RESULTS.no_crossing
    assert not results.is_successful(none.result)
    assert one_line(none.message) and "No Hopf crossing" in none.message
    assert strict_json(none.to_json()) == {"p": None, "frequency_hz": None}


def test_critical_cli_keys_unchanged(capsys):
    argv = ["critical", "--model", "two", "--elements", "2", "--json"]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    assert list(doc) == ["critical"] and list(doc["critical"][0]) == ["p", "frequency_hz"]
    argv += ["--along", "ks", "--values", "1e5,1e6", "--chunk", "2"]
    assert main(argv) == 0
    rows = json.loads(capsys.readouterr().out)["critical"]
    assert [list(r) for r in rows] == [["ks", "p", "frequency_hz"]] * 2
    assert [r["ks"] for r in rows] == [1e5, 1e6] and all(r["p"] > 0 for r in rows)


# -- sweep ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def swept(two, tmp_path_factory):
    path = tmp_path_factory.mktemp("sweep") / "s.npz"
    return ax.sweep(two, ax.Params(), {"p": [100.0, 300.0]}, out=path), path


def test_sweep(swept):
    res, path = swept
    assert is_item(res.result) and np.shape(results.codes(res.result)) == res.shape == (2,)
    assert bool(np.all(res.result == RESULTS.successful)) and res.message == "all 2 successful"
    doc = strict_json(res.to_json())
    assert doc["points"] == 2 and doc["results"] == {"successful": 2}
    assert doc["axes"] == {"p": [100.0, 300.0, 2]}
    loaded = SweepResult.load(path)
    assert strict_json(loaded.to_json()) == doc
    assert bool(np.all(loaded.result == res.result))


def test_sweep_failures_and_code_tables(swept, tmp_path):
    """A sweep file with a failed point reads back with its code, by name, even when it
    was written with another code table (another diffrax/optimistix)."""
    res, path = swept
    data = dict(res.data)
    data["result"] = np.asarray(data["result"]).copy()
    data["result"][1] = results.codes(RESULTS.invalid_params)
    failed = SweepResult(res.coords, data, dict(res.meta))
    assert np.array_equal(np.asarray(failed.result == RESULTS.successful), [True, False])
    msg = failed.message
    assert one_line(msg) and msg.startswith("1 of 2 failed (invalid_params 1): A parameter")
    # another installation's table: the same names under other integers
    with np.load(path) as f:
        arrays = {k: f[k] for k in f.files}
    meta = json.loads(str(arrays["meta"]))
    theirs = {str(i): n for i, n in enumerate(reversed(results.NAMES))}
    index = {n: int(i) for i, n in theirs.items()}
    arrays["result"] = np.array([index["successful"], index["invalid_params"]], dtype=np.int8)
    arrays["meta"] = np.array(json.dumps({**meta, "result": theirs}))
    other = tmp_path / "other.npz"
    np.savez(other, **arrays)
    back = SweepResult.load(other)
    assert np.array_equal(results.codes(back.result), results.codes(failed.result))
    assert back.message == msg
    # a file written before the result was stored: successful where the numbers are finite
    old = tmp_path / "old.npz"
    arrays.pop("result")
    arrays["meta"] = np.array(json.dumps({k: v for k, v in meta.items() if k != "result"}))
    np.savez(old, **arrays)
    assert SweepResult.load(old).message == "all 2 successful"


def test_sweep_cli_keys_unchanged(tmp_path, capsys):
    out = tmp_path / "s.npz"
    argv = ["sweep", "--model", "two", "--elements", "2", "--p", "100:300:2", "--out", str(out)]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert list(doc) == [
        "out",
        "netcdf",
        "model",
        "axes",
        "shape",
        "points",
        "counts",
        "seconds",
        "points_per_s",
        "solver",
        "process",
    ]
    assert doc["points"] == 2 and doc["counts"]["stable"] + doc["counts"]["flutter"] <= 2
    with np.load(out) as f:
        assert {"p", "eigenvalue_real", "classification", "result", "meta"} <= set(f.files)
        assert json.loads(str(f["meta"]))["result"]["0"] == "successful"


@pytest.mark.parametrize(
    "extra",
    [
        ["--timeout", "0"],
        ["--timeout", "-5"],
        ["--timeout", "30"],  # unused: not a distributed run
        ["--timeout", "0", "--distributed"],
    ],
)
def test_sweep_timeout_refused(extra, tmp_path, capsys):
    argv = ["sweep", "--model", "two", "--elements", "2", "--p", "100:300:2"]
    assert main([*argv, "--out", str(tmp_path / "s.npz"), *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("axojax: error: --timeout:") and "\n" not in err, err
    assert not (tmp_path / "s.npz").exists()


# -- simulation -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def simulations(two):
    """One compilation (the same step budget and number of save times): 0.002 s takes
    about 50 steps, 0.05 s needs far more than 60."""
    run = lambda t_end: ax.simulate(two, ax.Params(p=300.0), t_end, cubic=KAPPA, max_steps=60)
    return run(0.002), run(0.05)


def test_simulation(simulations, tmp_path):
    good, failed = simulations
    assert is_item(good.result) and good.result == RESULTS.successful
    assert good.message == "successful" and good.meta["solver"]["ok"]
    assert is_item(failed.result) and failed.result == RESULTS.max_steps_reached
    assert failed.state == "solver_failed" and not failed.meta["solver"]["ok"]
    assert one_line(failed.message) and "maximum number of solver steps" in failed.message
    for sim in (good, failed):
        path = tmp_path / f"{sim.state}.npz"
        sim.save(path)
        back = ax.Simulation.load(path)
        assert back.result == sim.result and back.state == sim.state
        assert strict_json(back.to_json()) == strict_json(sim.to_json())
        assert np.array_equal(back.tip_um, sim.tip_um)
    assert set(strict_json(good.to_json())) >= {"state", "limit_cycle", "linear", "solver"}
    # a file written before the result was stored: the code comes from the solver's message
    with np.load(tmp_path / "solver_failed.npz") as f:
        arrays = {k: f[k] for k in f.files}
    meta = json.loads(str(arrays["meta"]))
    meta.pop("result")
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "old.npz", **arrays)
    assert ax.Simulation.load(tmp_path / "old.npz").result == RESULTS.max_steps_reached


def test_simulation_throw(two):
    with pytest.raises(ValueError, match="maximum number of solver steps") as err:
        ax.simulate(two, ax.Params(p=300.0), 0.05, cubic=KAPPA, max_steps=60, throw=True)
    assert one_line(str(err.value))


def test_saves_are_atomic(simulations, tmp_path, monkeypatch):
    """A write that fails at the last moment leaves the previous file whole and no
    temporary file; a wrong suffix is refused before anything is written."""
    good, failed = simulations
    path = tmp_path / "sim.npz"
    good.save(path)
    before = path.read_bytes()

    def fail(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(_io.os, "replace", fail)
    with pytest.raises(OSError, match="disk full"):
        failed.save(path)
    monkeypatch.undo()
    assert path.read_bytes() == before and ax.Simulation.load(path).state == good.state
    assert sorted(os.listdir(tmp_path)) == ["sim.npz"]
    with pytest.raises(ValueError, match="expected a .npz path"):
        good.save(tmp_path / "sim.txt")


# -- limit cycle ------------------------------------------------------------------------


def test_limit_cycle(two):
    p_c = float(ax.critical_force(two, ax.Params()).p)
    cycle = ax.limit_cycle(two, ax.Params(p=1.05 * p_c), KAPPA, solver=ORBIT)
    assert is_item(cycle.result) and cycle.result == RESULTS.successful
    assert cycle.message == "successful" and bool(cycle.converged)
    doc = strict_json(cycle.to_json())
    assert doc["frequency_hz"] == pytest.approx(float(cycle.omega) / (2 * np.pi * ax.Units().tau_s))
    assert doc["converged"] is True
    # below the Hopf point there is no orbit: reported (throw defaults to False) ...
    below = ax.limit_cycle(two, ax.Params(p=0.9 * p_c), KAPPA, solver=ORBIT)
    assert is_item(below.result) and not results.is_successful(below.result)
    assert below.result == RESULTS.no_start and not bool(below.converged)
    assert one_line(below.message) and "No limit cycle" in below.message
    strict_json(below.to_json())  # plain JSON even for the stand-in (period inf -> None)
    # ... or raised, on one line
    with pytest.raises(ValueError, match="linearly stable") as err:
        ax.limit_cycle(two, ax.Params(p=0.9 * p_c), KAPPA, solver=ORBIT, throw=True)
    assert one_line(str(err.value))


# -- files: each result recognises its own -----------------------------------------------


def test_each_result_reads_and_recognises_its_own_file(swept, simulations, tmp_path):
    """``read`` is ``load`` with the file checked whole, a foreign or damaged file one
    ResultFileError naming it (what ``axojax plot`` prints after ``FILE:``); a JSON report
    type says whether a document is its own; the plotting registry takes each kind to its
    reader."""
    from axojax.inverse import FitResult, Posterior
    from axojax.inverse.comparison.compare import Comparison
    from axojax.orbits.branch import Branch
    from axojax.plotting.files import npz_kind

    _, path = swept
    assert SweepResult.read(path).shape == (2,) and npz_kind(path) == "sweep"
    sim = tmp_path / "sim.npz"
    simulations[0].save(sim)
    assert ax.Simulation.read(sim).state == simulations[0].state
    assert npz_kind(sim) == "simulation"
    foreign = tmp_path / "foreign.npz"
    np.savez(foreign, meta=np.array(json.dumps({"kind": "simulation"})))
    for reader, kind in (
        (SweepResult.read, "sweep"),
        (ax.Simulation.read, "simulation"),
        (Posterior.read, "posterior"),
        (Branch.read, "orbit_branch"),
    ):
        with pytest.raises(results.ResultFileError) as err:
            reader(foreign)
        assert one_line(str(err.value)) and str(err.value).startswith(f"{str(foreign)!r} is a")
        assert isinstance(err.value, ValueError)
    with np.load(path) as f:
        arrays = {k: f[k] for k in f.files}
    arrays["frequency_hz"] = arrays["frequency_hz"][:1]
    np.savez(tmp_path / "short.npz", **arrays)
    with pytest.raises(results.ResultFileError, match="'frequency_hz' array has shape"):
        SweepResult.read(tmp_path / "short.npz")
    (tmp_path / "text.npz").write_text("not a zip")
    with pytest.raises(results.ResultFileError, match="is not an .npz file"):
        npz_kind(tmp_path / "text.npz")
    np.savez(tmp_path / "banana.npz", meta=np.array(json.dumps({"kind": "banana"})))
    with pytest.raises(results.ResultFileError, match="has kind 'banana'; axojax plots sweep"):
        npz_kind(tmp_path / "banana.npz")
    fit_doc = {"loss": 1.0, "converged": True, "conditions": []}
    assert FitResult.is_document(fit_doc) and not Comparison.is_document(fit_doc)
    assert Comparison.is_document({"kind": "comparison"}) and not FitResult.is_document([1])
