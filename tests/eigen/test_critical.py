"""Hopf points: docs/model.md values, agreement with bisection on the dense spectrum, and the
implicit derivative of p_c."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
from axojax.cli.main import main
from tests.conftest import scipy_max_real


@pytest.mark.parametrize("name,pc,om", [("single", "76.10", "196.59"), ("beck", "37.70", "191.26")])
def test_model_values(name, pc, om):
    c = ax.critical_force(ax.models.preset(name, n_elements=40), ax.Params())
    assert bool(c.found)
    assert abs(float(c.p) - float(pc)) <= 0.005
    assert abs(abs(complex(c.eigenvalue).imag) - float(om)) <= 0.005


def bisect(model, params, lo, hi, rtol=1e-12):
    """Independent reference: bisection on scipy's dense spectrum."""
    g = lambda p: scipy_max_real(model, params.replace(p=p)).real
    assert g(lo) <= 0 < g(hi)
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) <= 0 else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("ks", [1e3, 1e5, 1e6])
def test_seven_boundary_matches_bisection(ks, seven):
    model = seven  # the session's model: critical_force compiles once for all three
    params = ax.Params(ks=ks, kl=ks / 1e3)
    c = ax.critical_force(model, params)
    ref = bisect(model, params, 0.9 * float(c.p), 1.1 * float(c.p))
    assert abs(float(c.p) - ref) < 1e-6 * ref
    # and nothing below it is unstable (first crossing): a coarse scan from 0
    for p in np.linspace(1.0, 0.99 * ref, 12):
        assert scipy_max_real(model, params.replace(p=p)).real <= 0


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_boundary_along_ks_vmapped_and_differentiable(seven):
    model = seven
    f = jax.jit(jax.vmap(lambda ks: ax.critical_force(model, ax.Params(ks=ks, kl=ks / 1e3)).p))
    values = jnp.array([1e3, 1e4])
    batched = np.asarray(f(values))
    single = [float(ax.critical_force(model, ax.Params(ks=v, kl=v / 1e3)).p) for v in values]
    np.testing.assert_allclose(batched, single, rtol=1e-10)
    # implicit derivative dp_c/dlog ks against a central difference
    pc = lambda z: ax.critical_force(model, ax.Params(ks=jnp.exp(z), kl=jnp.exp(z) / 1e3)).p
    z = jnp.log(1e4)
    g = float(jax.grad(pc)(z))
    fd = (float(pc(z + 1e-4)) - float(pc(z - 1e-4))) / 2e-4
    assert g == pytest.approx(fd, rel=1e-6)


def test_cli_critical_json(capsys, seven):
    import json

    assert (
        main(
            [
                "critical",
                "--model",
                "seven",
                "--along",
                "ks",
                "--values",
                "1e3,1e5",
                "--kl-ratio",
                "1000",
                "--json",
            ]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    rows = doc["critical"]
    assert [r["ks"] for r in rows] == [1e3, 1e5]
    for r in rows:
        c = ax.critical_force(seven, ax.Params(ks=r["ks"], kl=r["ks"] / 1e3))
        assert r["p"] == pytest.approx(float(c.p), rel=1e-10)
        assert r["frequency_hz"] == pytest.approx(float(c.frequency_hz()), rel=1e-8)
