"""``axojax fit --posterior DRAWS --sampler modes`` (issue 48): the posterior by
independence Metropolis-Hastings from a mixture fitted to every mode, the fit's optima
seeded; the report names the modes with their masses, and NUTS-only flags are refused in
one line."""

import json

import pytest

from axojax.cli.main import main

FIT = ["fit", "--no-mesh-check", "--model", "two", "--elements", "4", "--free", "p"]


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_modes_posterior_in_the_report(capsys):
    argv = [
        *FIT,
        "--target-frequency",
        "30",
        "--posterior",
        "300",
        "--chains",
        "2",
        "--sampler",
        "modes",
    ]
    rc = main([*argv, "--json"])
    doc = json.loads(capsys.readouterr().out)
    post = doc["posterior"]
    converged = post["result"] == "successful"
    assert rc == (0 if converged else 1)  # the fit meets its target: the posterior's status
    assert post["sampler"] == "modes" and post["draws"] == 300 and post["chains"] == 2
    assert post["gradients"] > 2 * 300 and post["gradients_per_ess"] > 0
    # two exact solutions (p ~ 160 and ~ 236, tests/sampling/test_smc.py): both reported as
    # modes, their masses summing to 1, the heavier the fit's optimum
    modes = post["modes"]
    assert len(modes) == 2 and abs(sum(m["mass"] for m in modes) - 1.0) < 1e-9
    p_fit = doc["params"]["p"]
    assert abs(modes[0]["centre"]["p"] - p_fit) < 0.05 * p_fit and post["q95"]["p"] > 200
    assert main(argv) == (0 if converged else 1)
    text = capsys.readouterr().out
    assert "independence Metropolis-Hastings chains" in text and "mode 2: p " in text


@pytest.mark.parametrize(
    "extra, flag",
    [
        (["--posterior", "40", "--sampler", "modes", "--along", "p"], "--along"),
        (["--posterior", "40", "--sampler", "modes", "--warmup", "200"], "--warmup"),
    ],
)
def test_nuts_flags_refused_in_one_line(extra, flag, capsys):
    rc = main([*FIT, "--target-frequency", "30", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and flag in err[0], err


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_a_nuts_run_that_warns_suggests_the_modes_sampler(capsys):
    # 31 Hz: a problem of its own. The warm-state cache is keyed by the problem, and
    # tests/house/test_progress.py checks the warm-up bar of the same run at 30 Hz.
    argv = [
        *FIT,
        "--target-frequency",
        "31",
        "--posterior",
        "20",
        "--chains",
        "2",
        "--warmup",
        "150",
    ]
    assert main([*argv, "--json"]) == 1  # the chains did not converge (below)
    err = capsys.readouterr().err.splitlines()
    assert any(
        "R-hat" in line or "effective sample size" in line for line in err
    )  # 2 x 20 draws warn
    hint = [line for line in err if "--sampler modes" in line]
    assert len(hint) == 1 and hint[0].startswith("axojax: fit: posterior: ")
