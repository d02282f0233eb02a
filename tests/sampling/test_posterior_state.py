"""A posterior says its state where the user looks (issue 57, item 2): the terminal's first
line after the posterior's table gives its result (``chains_not_converged`` and why), the
table names its ESS columns (bulk, tail; the JSON keeps ``ess`` and has ``ess_tail``), the
command exits with status 1 when the chains did not converge (as when a fit misses its
targets), and ``--sampler auto`` (the default) picks the sampler by the problem and says
which and why. The posterior is stubbed (no chains run): a hand-made :class:`Posterior`
with the issue's numbers, on a fit that meets its target."""

import argparse
import json
import re
import warnings

import numpy as np
import pytest

from axojax.cli.fit import posterior as cli_posterior
from axojax.cli.main import main
from axojax.inverse import NUTS, ModeMixture, Posterior
from axojax.results import RESULTS

FIT = ["fit", "--no-mesh-check", "--model", "two", "--elements", "4", "--free", "p"]
FIT += [
    "--p",
    "180",
    "--target-frequency",
    "30",
    "--starts",
    "1",
    "--posterior",
    "1000",
    "--chains",
    "4",
]
NOTE = "effective sample size below 400 (100 per chain): p tail 373 (run more draws)"


def _stub(result: RESULTS, seen: dict):
    """A ``posterior`` that runs no chains: bulk ESS 765 and tail ESS 373 for p (the
    issue's), its note warned as the library warns it, ``result`` as given."""

    def posterior(problem, **kw):
        seen.update(kw)
        ok = result == RESULTS.successful
        if not ok:
            warnings.warn(NOTE, stacklevel=2)
        u = np.full((4, 8, 1), np.log(160.0))
        one = {"p": 160.0}
        return Posterior(
            names=("p",),
            u=u,
            value_names=("p",),
            values=np.exp(u),
            log_density=np.zeros((4, 8)),
            divergent=np.zeros((4, 8), dtype=bool),
            lower=np.array([0.0]),
            upper=np.array([10.0]),
            log_coordinate={"p": True},
            mean=one,
            sd={"p": 1.5},
            q05={"p": 157.5},
            q50=one,
            q95={"p": 162.5},
            mean_u={"p": float(np.log(160.0))},
            sd_u={"p": 0.01},
            rhat={"p": 1.004},
            ess={"p": 765.0},
            ess_tail={"p": 373.0},
            divergences=0,
            step_size=np.full(4, np.nan),
            acceptance=0.6,
            warmup=50,
            gradients=9000,
            seconds=1.0,
            seconds_compile=0.0,
            seconds_start=0.0,
            seconds_warmup=0.5,
            seconds_sampling=0.5,
            seconds_per_gradient=1e-4,
            seconds_per_ess=1e-3,
            start_u=np.array([np.nan]),
            message="successful" if ok else NOTE,
            result=result,
            sampler="modes",
            tempering_stages=(7,),
        )

    return posterior


def _run(monkeypatch, capsys, result, *extra):
    seen: dict = {}
    monkeypatch.setattr(cli_posterior, "posterior", _stub(result, seen))
    rc = main([*FIT, *extra])
    out, err = capsys.readouterr()
    return rc, out, err, seen


def test_a_posterior_that_did_not_converge_says_so_and_exits_1(monkeypatch, capsys):
    rc, out, err, seen = _run(monkeypatch, capsys, RESULTS.chains_not_converged)
    assert "targets met: True" in out  # the fit is fine: the status is the posterior's
    assert rc == 1
    assert f"axojax: fit: posterior: {NOTE}" in err.splitlines()
    lines = out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.split()[:2] == ["parameter", "mean"])
    columns = re.split(r"\s{2,}", lines[head].strip())
    assert columns[-3:-1] == ["bulk ess", "tail ess"]
    row = dict(zip(columns, lines[head + 1].split()))
    assert (row["bulk ess"], row["tail ess"]) == ("765", "373")
    # the first line after the table: the result and why
    assert lines[head + 2] == f"result: chains_not_converged: {NOTE}"
    # --sampler auto, one free parameter: the mode-aware sampler, and the report says why
    assert isinstance(seen["sampler"], ModeMixture)
    assert lines[head + 3].startswith("sampler: modes (--sampler auto: 1 free parameter, at most 3")


def test_a_converged_posterior_exits_0_and_the_json_names_both_ess(monkeypatch, capsys):
    rc, out, err, _ = _run(monkeypatch, capsys, RESULTS.successful, "--json")
    assert rc == 0 and "axojax: fit: posterior" not in err
    post = json.loads(out)["posterior"]
    assert post["result"] == "successful"
    assert post["ess"] == {"p": 765.0} and post["ess_tail"] == {"p": 373.0}  # bulk, tail
    assert post["sampler"] == "modes"
    assert post["sampler_reason"].startswith("--sampler auto: 1 free parameter, at most 3")
    rc, out, _, _ = _run(monkeypatch, capsys, RESULTS.successful)
    assert rc == 0 and "\nresult: successful\n" in out


class _Problem:
    def __init__(self, k: int):
        self.names = tuple(f"x{i}" for i in range(k))


def _args(sampler="auto", along=None, warmup=None):
    return argparse.Namespace(sampler=sampler, along=along, warmup=warmup)


@pytest.mark.parametrize(("k", "chosen"), [(1, "modes"), (3, "modes"), (4, "nuts"), (9, "nuts")])
def test_auto_picks_modes_up_to_three_free_parameters_and_nuts_beyond(k, chosen):
    name, why = cli_posterior.sampler_of(_args(), _Problem(k))
    assert name == chosen
    assert why.startswith(f"--sampler auto: {k} free parameter")
    assert ("at most 3" if chosen == "modes" else "more than 3") in why


def test_auto_with_a_nuts_flag_and_a_named_sampler():
    assert cli_posterior.sampler_of(_args(along="ks"), _Problem(2)) == (
        "nuts",
        "--sampler auto: --along given (NUTS's settings)",
    )
    name, why = cli_posterior.sampler_of(_args(warmup=300), _Problem(2))
    assert name == "nuts" and "--warmup given" in why
    assert cli_posterior.sampler_of(_args("nuts"), _Problem(1)) == ("nuts", "--sampler nuts: given")
    assert cli_posterior.sampler_of(_args("smc"), _Problem(5))[0] == "smc"


def test_the_library_choice():
    from axojax.inverse import choose_sampler

    assert isinstance(choose_sampler(_Problem(2))[0], ModeMixture)
    assert isinstance(choose_sampler(_Problem(4))[0], NUTS)
    with pytest.raises(ValueError, match="no free parameters"):
        choose_sampler(_Problem(0))
