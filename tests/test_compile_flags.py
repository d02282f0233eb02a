"""The suite compiles with XLA's backend optimisation level 0 and the older fusion emitters (tests/conftest.py), which
makes it faster but is not what users run. This checks that the level changes how the
machine code is made, not what it computes: the dominant eigenvalue and its gradient in
p and k_s, computed in a process with the default (fully optimised) XLA flags, equal this
process's to 1e-12 relative."""

import json
import os
import subprocess
import sys

import jax
import numpy as np

import axojax as ax

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

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
    env = {**os.environ, "PYTHONPATH": ROOT, "XLA_FLAGS": xla_flags, "AXOJAX_TEST_FULL_OPTIMISATION": "1"}
    env.pop("AXOJAX_CACHE_DIR", None)  # no cached program from the suite's flags
    done = subprocess.run([sys.executable, "-c", COMPUTE], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_suite_flags_do_not_change_results():
    assert "xla_backend_optimization_level=0" in os.environ.get("XLA_FLAGS", "") or os.environ.get("AXOJAX_TEST_FULL_OPTIMISATION")
    optimised = _run("")
    model = ax.models.two(n_elements=6)
    for name, part in (("growth", "real"), ("freq", "imag")):
        v, g = jax.value_and_grad(lambda p, kl: getattr(ax.dominant_mode(model, ax.Params(p=p, kl=kl)).eigenvalue, part), argnums=(0, 1))(240.0, 1000.0)
        here = np.array([float(v), float(g[0]), float(g[1])])
        np.testing.assert_allclose(here, optimised[name], rtol=1e-12, atol=1e-12 * np.abs(here).max())
        assert np.all(np.abs(here[1:]) > 0)  # gradients that are there to compare
