"""The posterior's warm-state cache (axojax/inverse/sampling/_warm_cache.py, issue 31: a second
identical run starts faster): a second run with ``cache=`` loads the first's start-up
(centre, Laplace approximation, warm-up state) without computing it and draws bitwise
what the first and an uncached run drew; a change in any keyed input misses; a corrupt
file is ignored (one warning) and rewritten; no cache writes nothing; problems without a
fingerprint (or with a callable prior) run uncached. A one-parameter problem on the
two-filament model with 3 elements, 2 chains x 8 draws, 20 warm-up steps."""

import importlib
import json
import warnings

import numpy as np
import pytest
from jaxtyping import TypeCheckError

import axojax as ax
from axojax.beats import Target
from axojax.inverse import ScaledSigmas, build_problem, posterior
from axojax.inverse.sampling._warm_cache import SUFFIX, run_key
from tests.sampling.test_nuts import linear_problem

RUN = {"draws": 8, "chains": 2, "warmup": 20, "seed": 0}
MODEL = ax.models.two(n_elements=3)
nuts_module = importlib.import_module("axojax.inverse.sampling._nuts")
kernels_module = importlib.import_module("axojax.inverse.sampling._nuts_kernels")


def problem(frequency=30.0, bounds=None, prior=None):
    start = ax.Params().with_values({"p": 150.0})
    return build_problem(
        MODEL, start, [Target("frequency_hz", frequency, 1.0)], ["p"], bounds=bounds, prior=prior
    )


def sample(prob, **kw):
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="(?!posterior warm-state)")  # R-hat, ESS
        return posterior(prob, **{**RUN, **kw})


def files(directory):
    return sorted(directory.glob(f"*{SUFFIX}")) if directory.exists() else []


def same_draws(a, b):
    return (
        np.array_equal(a.u, b.u)
        and np.array_equal(a.log_density, b.log_density)
        and np.array_equal(a.divergent, b.divergent)
        and np.array_equal(a.step_size, b.step_size)
        and a.gradients == b.gradients
    )


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_second_run_loads_the_start_up_and_draws_the_same(tmp_path, monkeypatch):
    prob = problem()
    first = sample(prob, cache=tmp_path)
    assert first.warm_cache == "stored" and len(files(tmp_path)) == 1
    plain = sample(prob)
    assert plain.warm_cache == "off" and same_draws(first, plain)

    def refuse(*_, **__):
        raise AssertionError("the start-up ran although it was cached")

    monkeypatch.setattr(nuts_module, "chain_starts", refuse)
    monkeypatch.setattr(kernels_module, "adapt", refuse)
    seen = []
    second = sample(prob, cache=tmp_path, on_laplace=seen.append)
    assert second.warm_cache == "loaded" and second.seconds_warmup == 0.0
    assert same_draws(first, second)
    assert np.array_equal(second.start_u, first.start_u)
    assert np.array_equal(seen[0].cov_u, first.laplace.cov_u)
    assert second.to_json()["warm_cache"] == "loaded"
    # ScaledSigmas: the wrapped problem's fingerprint with the factor
    fp = {f: ScaledSigmas(prob, f).fingerprint() for f in (2.0, 3.0)}
    assert fp[2.0] != fp[3.0] and prob.fingerprint() not in fp.values()
    with pytest.raises(TypeError):
        ScaledSigmas(linear_problem(0), 2.0).fingerprint()


def test_a_changed_input_misses():
    prob = problem()
    base = dict(prior=None, sampler=ax.inverse.NUTS(), warmup=20, chains=2, seed=0, init=None)
    key = run_key(prob, vectorize=True, **base)
    assert key is not None and key == run_key(problem(), vectorize=True, **base)  # rebuilt alike
    changed = [
        run_key(problem(frequency=31.0), vectorize=True, **base),  # data
        run_key(problem(bounds={"p": (1.0, 1e4)}), vectorize=True, **base),  # a bound
        run_key(prob, vectorize=False, **base),
        run_key(prob, vectorize=True, **{**base, "seed": 1}),
        run_key(prob, vectorize=True, **{**base, "warmup": 21}),
        run_key(prob, vectorize=True, **{**base, "chains": 3}),
        run_key(prob, vectorize=True, **{**base, "init": [5.0]}),
        run_key(prob, vectorize=True, **{**base, "sampler": ax.inverse.NUTS(dense_mass=False)}),
        run_key(
            prob,
            vectorize=True,
            **{**base, "prior": ax.inverse.normal_prior(["p"], {"p": (5.0, 1.0)})},
        ),
        run_key(
            build_problem(
                ax.models.two(n_elements=4),
                ax.Params().with_values({"p": 150.0}),
                [Target("frequency_hz", 30.0, 1.0)],
                ["p"],
            ),
            vectorize=True,
            **base,
        ),
    ]
    assert None not in changed and len({key, *changed}) == len(changed) + 1


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_another_seed_misses_and_stores_its_own(tmp_path):
    prob = problem()
    assert sample(prob, cache=tmp_path).warm_cache == "stored"
    other = sample(prob, cache=tmp_path, seed=1)
    assert other.warm_cache == "stored" and len(files(tmp_path)) == 2
    assert not np.array_equal(other.u, sample(prob).u)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("damage", ["truncate", "garbage", "empty", "wrong_key"])
def test_a_corrupt_file_is_ignored_with_one_warning(tmp_path, damage):
    prob = problem()
    first = sample(prob, cache=tmp_path)
    (path,) = files(tmp_path)
    data = path.read_bytes()
    if damage == "truncate":
        path.write_bytes(data[: len(data) // 2])
    elif damage == "garbage":
        path.write_bytes(b"not an npz" * 10)
    elif damage == "empty":
        path.write_bytes(b"")
    else:  # a valid file of another run under this name
        with np.load(path) as f:
            arrays = dict(f)
        meta = json.loads(str(arrays["meta"]))
        arrays["meta"] = json.dumps({**meta, "key": "0" * 64})
        with open(path, "wb") as f:
            np.savez(f, **arrays)
    with pytest.warns(UserWarning, match="warm-state cache: ignoring") as caught:
        again = sample(prob, cache=tmp_path)
    assert len([w for w in caught if "warm-state" in str(w.message)]) == 1
    assert "\n" not in str(caught[0].message)
    assert again.warm_cache == "stored" and same_draws(first, again)
    assert sample(prob, cache=tmp_path).warm_cache == "loaded"  # rewritten whole


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_no_cache_writes_nothing(tmp_path, monkeypatch):
    prob = problem()
    monkeypatch.setenv("AXOJAX_CACHE_DIR", "off")
    assert sample(prob, cache=True).warm_cache == "off"
    assert sample(prob, cache=False).warm_cache == "off"
    monkeypatch.setenv("AXOJAX_CACHE_DIR", str(tmp_path / "jax"))
    assert sample(prob).warm_cache == "off" and not (tmp_path / "jax").exists()
    assert sample(prob, cache=True).warm_cache == "stored"
    assert len(files(tmp_path / "jax" / "posterior")) == 1


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_problems_without_a_fingerprint_run_uncached(tmp_path):
    def log_prior(u):
        return -0.5 * (u[0] - 5.0) ** 2

    assert sample(problem(prior=log_prior), cache=tmp_path).warm_cache == "off"
    assert sample(problem(), prior=log_prior, cache=tmp_path).warm_cache == "off"
    assert sample(linear_problem(0), cache=tmp_path).warm_cache == "off"  # no fingerprint()
    assert files(tmp_path) == []
    with pytest.raises((TypeError, TypeCheckError), match="cache"):
        sample(problem(), cache=3)


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_fit_posterior_uses_the_cache_when_the_compilation_cache_is_on(tmp_path, monkeypatch):
    from axojax.cli.fit import posterior as fit_cli
    from axojax.cli.main import main

    argv = ["fit", "--no-mesh-check", "--model", "two", "--elements", "3", "--free", "p"]
    argv += ["--target-frequency", "30", "--posterior", "8", "--chains", "2", "--json"]
    argv += ["--sampler", "nuts"]  # the warm state is NUTS's (auto: the mode-aware sampler)

    def run():
        import contextlib
        import io

        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            main(argv)
        return json.loads(out.getvalue())["posterior"]

    monkeypatch.setattr(fit_cli, "compilation_cache_dir", lambda: None)
    assert run()["warm_cache"] == "off"  # no compilation cache: no warm states either
    monkeypatch.setattr(fit_cli, "compilation_cache_dir", lambda: tmp_path)
    first, second = run(), run()
    assert (first["warm_cache"], second["warm_cache"]) == ("stored", "loaded")
    assert len(files(tmp_path / "posterior")) == 1
    for key in ("mean", "sd", "q05", "q50", "q95", "rhat", "ess", "divergences", "laplace"):
        assert first[key] == second[key], key


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_scaled_sigmas_of_a_model_problem_samples():
    """ScaledSigmas over a real Problem (whose values are Python floats) passes the
    run-time type checks of its Laplace start, and widens the width by its factor."""
    prob = problem()
    plain = sample(prob)
    scaled = sample(ScaledSigmas(prob, 2.0))
    assert scaled.laplace.names == ("p",)
    assert np.sqrt(scaled.laplace.cov_u[0, 0]) == pytest.approx(
        2.0 * np.sqrt(plain.laplace.cov_u[0, 0]),
        rel=1e-3,  # each at its own mode search's end
    )
