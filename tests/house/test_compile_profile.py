"""``axojax --profile-compile`` and :func:`axojax.compile_profile.compile_profile` (issue 56
item 1): the programs a run builds, by name, with the seconds of each stage, and nothing
of JAX's compile log reaching stderr otherwise."""

import logging

import jax
import jax.numpy as jnp

from axojax.cli.main import main
from axojax.compile_profile import compile_profile


def test_profile_counts_each_build_by_name(caplog):
    def squares_of_a_kind(x):
        return jnp.cumsum(x) ** 2

    f = jax.jit(squares_of_a_kind)
    with caplog.at_level(logging.DEBUG), compile_profile() as prof:
        f(jnp.ones(7))
        f(jnp.ones(9))  # new shape: built again
        f(jnp.ones(9))  # in memory: not built
        logging.getLogger("jax._src.dispatch").warning("a warning of another kind")
    entry = prof.programs["squares_of_a_kind"]
    assert entry.compilations == 2
    assert entry.total > 0 and entry.total == entry.tracing + entry.lowering + entry.compiling
    assert prof.total_s >= entry.total and prof.wall_s >= prof.total_s
    messages = [r.getMessage() for r in caplog.records]
    assert "a warning of another kind" in messages  # other lines pass
    assert not any("Finished XLA compilation" in m for m in messages)
    assert "squares_of_a_kind" in prof.table().split("\n", 2)[2]
    assert not jax.config.jax_log_compiles  # back as it was
    doc = prof.to_json()
    assert doc["programs"][0]["name"] in prof.programs and doc["compile_s"] == prof.total_s


def test_profile_compile_flag_prints_the_table_on_stderr(capsys):
    assert main(["modes", "--model", "two", "--elements", "3", "--json", "--profile-compile"]) == 0
    captured = capsys.readouterr()
    assert captured.out.lstrip().startswith("{")  # stdout keeps its one JSON document
    head = captured.err.splitlines()
    assert head[0].startswith("compilation: ") and "programs" in head[0], captured.err
    assert head[1].split() == ["seconds", "builds", "tracing", "lowering", "XLA", "program"]
    assert main(["--profile-compile", "modes", "--model", "two", "--elements", "3"]) == 0
    assert capsys.readouterr().err.startswith("compilation: ")
    assert main(["modes", "--model", "two", "--elements", "3"]) == 0
    assert "compilation: " not in capsys.readouterr().err


def test_profile_table_also_after_a_refused_run(capsys):
    assert main(["--profile-compile", "modes", "--model", "two", "--elements", "0"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("compilation: ") and "axojax: error: " in err, err
