"""``axojax fit --posterior DRAWS [--chains C]`` (docs/interface.md): NUTS from the fit's
optimum on the same problem; the report's "posterior" block, the draws file beside
--out, its corner plot, and one-line errors for bad values. One parameter of a small
model: the posterior of p given one frequency is narrow and single-peaked, so its mean
must sit within a few standard deviations of the least-squares optimum (the two are
computed by different algorithms: Levenberg-Marquardt and NUTS)."""

import json

import pytest

import axojax as ax
from axojax.cli.main import main


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_fit_posterior_report_file_and_corner_plot(tmp_path, capsys):
    out = tmp_path / "fit.json"
    rc = main(
        [
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
            "--warmup",
            "160",
            "--out",
            str(out),
            "--json",
        ]
    )
    out, err = capsys.readouterr()
    doc = json.loads(out)
    # the fit meets its target; the exit status is the posterior's (1: not converged)
    assert rc == (0 if doc["posterior"]["result"] == "successful" else 1)
    # one prefix per line (issue 33: "axojax: fit: posterior: posterior: R-hat ..." doubled it)
    for line in err.splitlines():
        assert line.count("posterior:") <= 1 and line.count("axojax:") == 1, line
    post = doc["posterior"]
    assert {"draws", "chains", "mean", "sd", "q05", "q95", "rhat", "ess", "seconds"} <= set(post)
    assert post["draws"] == 40 and post["chains"] == 2 and post["warmup"] == 160
    p_fit, mean, sd = doc["params"]["p"], post["mean"]["p"], post["sd"]["p"]
    assert 0 < sd < 0.1 * p_fit
    assert abs(mean - p_fit) < 3 * sd
    assert post["q05"]["p"] < p_fit < post["q95"]["p"]
    draws = tmp_path / "fit.posterior.npz"
    assert post["file"] == str(draws) and draws.is_file()
    assert main(["plot", str(draws), "--out", str(tmp_path / "corner.png")]) == 0
    assert (tmp_path / "corner.png").stat().st_size > 10_000


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["--posterior", "2"], "--posterior"),
        (["--posterior", "20", "--chains", "0"], "--chains"),
        (["--chains", "3"], "--chains"),
        (["--warmup", "200"], "--warmup"),
        (["--posterior", "20", "--warmup", "10"], "--warmup"),
        (["--along", "p"], "--along"),
        (["--posterior", "20", "--along", "ks"], "--along"),
        (["--posterior", "20", "--along", "p"], "--along"),
    ],
)
def test_bad_posterior_flags_are_one_line(argv, flag, capsys):
    rc = main(
        [
            "fit",
            "--no-mesh-check",
            "--model",
            "seven",
            "--elements",
            "4",
            "--free",
            "p",
            "--target-frequency",
            "30",
            *argv,
        ]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and flag in err[0]


def test_posterior_default_solver_is_the_structured_one_where_it_pays():
    """A posterior's thousands of gradients make the default solver (auto) choose Arnoldi
    for the seven-filament model at 10 elements (280 unknowns), where a fit alone keeps
    the quicker-to-compile dense solver; two filaments (44 unknowns) stay dense, and an
    explicit --solver is kept."""
    import argparse

    from axojax.cli.fit import eigen_solver

    seven, two = ax.models.seven(n_elements=10), ax.models.two(n_elements=10)

    def chosen(posterior, solver="auto", model=seven):
        args = argparse.Namespace(solver=solver, posterior=posterior)
        return type(eigen_solver(args).resolve(model, 1)).__name__

    assert chosen(None) == "Dense"
    assert chosen(200) == "Arnoldi"
    assert chosen(200, model=two) == "Dense"
    assert chosen(200, solver="dense") == "Dense"


def test_default_warmup_is_the_draws_within_150_to_500():
    """The library's rule (the command passes --warmup as given, None without it)."""
    from axojax.inverse.sampling import warmup_steps

    assert [warmup_steps(d, None) for d in (4, 150, 300, 1000, 100_000)] == [
        150,
        150,
        300,
        500,
        500,
    ]
    assert warmup_steps(1000, 2000) == 2000  # --warmup wins
    # with --along: at most 200 (the chains start from the profile's approximation)
    assert [warmup_steps(d, None, "ks") for d in (4, 180, 1000)] == [150, 180, 200]
    assert warmup_steps(1000, 900, "ks") == 900


def test_the_command_leaves_the_defaults_to_the_library(monkeypatch, capsys):
    """The command passes its flags only: no warm-up, chain layout or transport of its own
    (the library's defaults: the warm-up from the draws, the chains one after another on a
    CPU, the transport chosen from the fit); --along and --warmup reach the sampler as
    given."""
    from axojax.cli.fit import posterior as cli_fit
    from axojax.inverse.sampling import vectorize_chains

    seen = {}

    class Stop(Exception):
        pass

    def posterior(problem, **kw):
        seen.clear()
        seen.update(kw)
        raise Stop

    monkeypatch.setattr(cli_fit, "posterior", posterior)
    argv = ["fit", "--no-mesh-check", "--model", "two", "--elements", "4", "--free", "p,ks"]
    argv += ["--target-frequency", "30", "--target-wavelength", "20", "--posterior", "1000"]
    argv += ["--starts", "2"]  # the fit is not what is tested here
    argv += ["--sampler", "nuts"]  # auto would pick the mode-aware sampler for two
    with pytest.raises(Stop):
        main(argv)
    assert "vectorize" not in seen and seen["warmup"] is None
    assert seen["transport"] == "auto" and hasattr(seen["init"], "params")  # the fit
    with pytest.raises(Stop):
        main(argv + ["--along", "ks", "--warmup", "300"])
    assert seen["transport"].along == "ks" and seen["warmup"] == 300
    import jax

    assert vectorize_chains() is (jax.default_backend() != "cpu")


def test_text_report_names_the_transport():
    from axojax.cli.fit.text import render_posterior

    post = {
        "chains": 4, "draws": 10, "seconds": 1.0, "mean": {"p": 1.0}, "sd": {"p": 0.1},
        "q05": {"p": 0.9}, "q95": {"p": 1.1}, "rhat": {"p": 1.0}, "ess": {"p": 40.0},
        "sd_ratio": {"p": 1.0}, "tree_depth": 2.0, "max_num_doublings": 8,
        "tree_depth_saturated": 0.0, "gradients_per_draw": 4.5,
    }  # fmt: skip
    plain = "\n".join(render_posterior(post))
    along = "\n".join(render_posterior({**post, "transport": "ks"}))
    assert "straightened" not in plain
    assert "4.5 gradients per draw, in coordinates straightened along the profile of ks" in along


def test_along_default_is_chosen_from_the_fit_and_none_turns_it_off():
    import argparse

    from axojax.cli.fit import posterior as fit_posterior

    names = ("p", "ks")
    assert fit_posterior.transport_of(argparse.Namespace(along=None), names) == fit_posterior.AUTO
    assert fit_posterior.transport_of(argparse.Namespace(along="none"), names) is None
    assert fit_posterior.transport_of(argparse.Namespace(along="ks"), names).along == "ks"
