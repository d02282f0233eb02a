"""The suite compiles with XLA's backend optimisation level 0 (tests/conftest.py), and
axojax itself selects XLA's older CPU fusion emitters on jaxlib 0.10 (axojax/_runtime.py);
both make compilation faster. This checks that the flags change how the machine code is made,
not what it computes: the dominant eigenvalue and its gradient in p and k_l, computed in a
process with XLA's default flags (fully optimised, newer emitters, none of axojax's
runtime settings), equal this process's to 1e-12 relative."""

import json
import os
import subprocess
import sys

import jax
import numpy as np
import pytest

import axojax as ax

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

COMPUTE = """
import json, sys
import jax
import axojax as ax
model = ax.models.two(n_elements=6)
def growth(p, kl):
    return ax.dominant_mode(model, ax.Params(p=p, kl=kl)).eigenvalue.real
def freq(p, kl):
    return ax.dominant_mode(model, ax.Params(p=p, kl=kl)).eigenvalue.imag
out = {}
for name, f in (("growth", growth), ("freq", freq)):
    v, g = jax.value_and_grad(f, argnums=(0, 1))(240.0, 1000.0)
    out[name] = [float(v), float(g[0]), float(g[1])]
print(json.dumps(out))
"""


def _run(xla_flags: str) -> dict:
    # AXOJAX_KEEP_XLA_FLAGS: XLA's own defaults, without the flags axojax itself sets at
    # import (axojax/_runtime.py: the older fusion emitters on jaxlib 0.10, one Eigen thread).
    env = {
        **os.environ,
        "PYTHONPATH": ROOT,
        "XLA_FLAGS": xla_flags,
        "AXOJAX_TEST_FULL_OPTIMISATION": "1",
        "AXOJAX_KEEP_XLA_FLAGS": "1",
    }
    env.pop("AXOJAX_CACHE_DIR", None)  # no cached program from the suite's flags
    done = subprocess.run(
        [sys.executable, "-c", COMPUTE], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_suite_flags_do_not_change_results():
    assert "xla_backend_optimization_level=0" in os.environ.get("XLA_FLAGS", "") or os.environ.get(
        "AXOJAX_TEST_FULL_OPTIMISATION"
    )
    optimised = _run("")
    model = ax.models.two(n_elements=6)
    for name, part in (("growth", "real"), ("freq", "imag")):
        v, g = jax.value_and_grad(
            lambda p, kl: getattr(ax.dominant_mode(model, ax.Params(p=p, kl=kl)).eigenvalue, part),
            argnums=(0, 1),
        )(240.0, 1000.0)
        here = np.array([float(v), float(g[0]), float(g[1])])
        np.testing.assert_allclose(
            here, optimised[name], rtol=1e-12, atol=1e-12 * np.abs(here).max()
        )
        assert np.all(np.abs(here[1:]) > 0)  # gradients that are there to compare


def test_older_fusion_emitters_only_on_jaxlib_0_10(monkeypatch):
    """axojax/_runtime.py adds --xla_cpu_use_fusion_emitters=false on jaxlib 0.10 only
    (where it was measured; XLA aborts on a flag it does not know), never over the
    user's own setting, and nothing under AXOJAX_KEEP_XLA_FLAGS=1."""
    from axojax import _runtime

    def flags_for(version, start="", keep=False):
        monkeypatch.setattr(_runtime, "_jaxlib_version", lambda: version)
        monkeypatch.setenv("XLA_FLAGS", start)
        monkeypatch.setenv("NPROC", "2")  # leave the intra-op pool alone here
        if keep:
            monkeypatch.setenv(_runtime.OPT_OUT, "1")
        else:
            monkeypatch.delenv(_runtime.OPT_OUT, raising=False)
        _runtime.set_xla_flags()
        return os.environ["XLA_FLAGS"].split()

    assert _runtime.EMITTER_FLAG in flags_for("0.10.2")
    for version in ("0.9.2", "0.11.1", "1.0.0", ""):
        assert _runtime.EMITTER_FLAG not in flags_for(version), version
    assert flags_for("0.10.2", "--xla_cpu_use_fusion_emitters=true") == [
        "--xla_cpu_use_fusion_emitters=true",
        "--xla_cpu_multi_thread_eigen=false",
    ]
    assert flags_for("0.10.2", "--foo", keep=True) == ["--foo"]


def test_the_linear_comparison_compiles_at_level_zero():
    """``axojax compare`` (linear) builds two programs a row and runs each briefly: the
    command line sets XLA's backend optimisation level 0 for it, before jax starts, unless
    a level is already set or axojax's settings are opted out of; no other command."""
    from axojax.cli.main import many_programs

    assert many_programs(["compare", "--data", "human_sperm"])
    assert many_programs(["--quiet", "compare", "--data", "human_sperm"])
    assert not many_programs(["compare", "--target", "limit-cycle", "--data", "x"])
    assert not many_programs(["compare", "--target=limit-cycle"])
    assert not many_programs(["modes", "--model", "seven"])
    # one fresh process (jax not started): the three cases in turn
    probe = """
import os
from axojax import _runtime
for flags, keep in (("", None), ("--xla_backend_optimization_level=2", None), ("", "1")):
    os.environ["XLA_FLAGS"] = flags
    os.environ.pop("AXOJAX_KEEP_XLA_FLAGS", None)
    if keep:
        os.environ["AXOJAX_KEEP_XLA_FLAGS"] = keep
    print(_runtime.compile_for_many_programs(), "|", os.environ["XLA_FLAGS"])
"""
    env = {k: v for k, v in os.environ.items() if k not in ("XLA_FLAGS", "AXOJAX_KEEP_XLA_FLAGS")}
    done = subprocess.run(
        [sys.executable, "-c", probe],
        env={**env, "PYTHONPATH": ROOT},
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    )
    seen = [line.split("|") for line in done.stdout.strip().splitlines()]
    seen = [[on.strip(), flags.strip()] for on, flags in seen]
    level0 = "--xla_backend_optimization_level=0"
    assert seen[0][0] == "True" and level0 in seen[0][1].split()  # set
    assert seen[1][0] == "False" and level0 not in seen[1][1].split()  # a level given
    assert seen[2] == ["False", ""]  # opted out
