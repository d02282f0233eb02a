"""``axojax fit --posterior DRAWS --sampler smc`` (issue 48): the posterior by adaptive
tempered SMC runs from the prior (axojax.inverse.SMC) instead of NUTS from the optimum;
the report says which sampler ran and what it cost, and NUTS-only flags are refused in
one line."""

import json

import pytest

from axojax.cli.main import main

FIT = ["fit", "--no-mesh-check", "--model", "two", "--elements", "4", "--free", "p"]


@pytest.mark.slow  # ~40 s on 2 loaded cores: two SMC runs of 200 particles, twice
def test_smc_posterior_in_the_report(capsys):
    argv = [*FIT, "--target-frequency", "30", "--posterior", "200", "--chains", "2"]
    rc = main([*argv, "--sampler", "smc", "--json"])
    doc = json.loads(capsys.readouterr().out)
    post = doc["posterior"]
    converged = post["result"] == "successful"
    assert rc == (0 if converged else 1)  # the fit meets its target: the posterior's status
    assert post["sampler"] == "smc" and post["draws"] == 200 and post["chains"] == 2
    assert post["warmup"] == 0 and len(post["tempering_stages"]) == 2
    assert post["gradients"] > 2 * 200 and post["gradients_per_ess"] > 0
    # two exact solutions (p ~ 160 and ~ 236, tests/sampling/test_smc.py): the median sits
    # in the heavier one, the fit's optimum; the 95 % quantile in the other
    p_fit = doc["params"]["p"]
    assert abs(post["q50"]["p"] - p_fit) < 0.05 * p_fit and post["q95"]["p"] > 200
    # the text report names the sampler instead of NUTS's tree depth
    assert main([*argv, "--sampler", "smc"]) == (0 if converged else 1)
    text = capsys.readouterr().out
    assert "SMC: 2 independent runs from the prior" in text and "tree depth" not in text


@pytest.mark.parametrize(
    "extra, flag",
    [
        (["--sampler", "smc"], "--sampler"),  # no --posterior
        (["--posterior", "40", "--sampler", "smc", "--along", "p"], "--along"),
        (["--posterior", "40", "--sampler", "smc", "--warmup", "200"], "--warmup"),
    ],
)
def test_smc_flags_refused_in_one_line(extra, flag, capsys):
    rc = main([*FIT, "--target-frequency", "30", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and flag in err[0], err
