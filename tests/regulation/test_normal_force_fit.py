"""Fits of normal-force control (issue 55, second step): ``ax.fit`` through the beat of
the augmented pencil (:class:`axojax.eigen.NormalForce`, differentiable by one bordered
solve, tests/regulation/test_normal_force.py).

The truth is a Hopf point found here with scipy, independently of axojax's fit: at
lambda = i omega0 the augmented matrix A' + i omega0 C' is K0 - g K1 with g = g' + i g''
(the gain's friction g''/omega0 d/dt is i g'' there), so the gains that put an
eigenvalue at i omega0 are the generalised eigenvalues of (K0, K1).
"""

import json

import numpy as np
import pytest
import scipy.linalg as sl

import axojax as ax
from axojax.assembly import assemble_normal
from axojax.beats.targets import ShapeTarget, Target
from axojax.cli.main import main
from axojax.eigen import normal_force_mode
from axojax.inverse.predictions import model_psi1

SP, M0 = 200.0, 10.0
UNITS = ax.Units()
S_UM = np.linspace(0.0, UNITS.length_um, 21)


def _pencil(params):
    s = assemble_normal(MODEL, params)
    return np.asarray(s.A) + 1j * SP * np.asarray(s.C)


MODEL = ax.models.two(n_elements=6)
BASE = ax.Params(p=0.0, kl=1e3, m0=M0, omega0=SP)


def _hopf_gain() -> complex:
    """The gain of smallest modulus that puts an eigenvalue at i omega0 (scipy)."""
    K0 = _pencil(BASE)
    K1 = K0 - _pencil(BASE.replace(normal_re=1.0))
    g = sl.eig(K0, K1, right=False)
    g = g[np.isfinite(g) & (np.abs(g) < 1e6)]
    return complex(g[np.argmin(np.abs(g))])


@pytest.fixture(scope="module")
def truth():
    g = _hopf_gain()
    params = BASE.replace(normal_re=g.real, normal_im=g.imag)
    s = assemble_normal(MODEL, params)
    lam = sl.eig(-np.asarray(s.A), np.asarray(s.C), right=False)
    assert np.min(np.abs(lam - 1j * SP)) < 1e-8 * SP  # the Hopf point, by scipy's QZ
    mode = normal_force_mode(MODEL, params, 1j * SP)
    psi1 = 0.7 * np.asarray(model_psi1(MODEL, mode, S_UM / UNITS.length_um))
    psi1 = 0.5 * psi1 / np.abs(psi1).max() * np.exp(0.3j)
    return g, params, psi1


def test_fit_recovers_the_normal_force_gain_from_psi1_and_the_beat(truth):
    """psi_1 of the truth's beat (scaled, turned: the fit's free amplitude) and the pins
    (growth 0, the beat's frequency): Levenberg-Marquardt from 30 % off recovers g' and
    g'' to 1e-6 relative."""
    g, params, psi1 = truth
    f_hz = float(UNITS.omega0_to_hz(SP))
    targets = [
        Target("growth_rate_per_s", 0.0, 1e-3 * 2 * np.pi * f_hz),
        Target("frequency_hz", f_hz, 1e-3 * f_hz),
    ]
    shape = ShapeTarget(S_UM, psi1, 0.01)
    bound = 10 * abs(g)
    result = ax.fit(
        MODEL,
        params.replace(normal_re=1.3 * g.real, normal_im=0.7 * g.imag),
        targets,
        ["normal_re", "normal_im"],
        shape=shape,
        bounds={"normal_re": (-bound, bound), "normal_im": (-bound, bound)},
        units=UNITS,
        solver=ax.eigen.NormalForce(),
        shift=1j * SP,
        shape_floor=0.0,
        starts=1,
    )
    assert result.targets_met, result.message
    assert result.params["normal_re"] == pytest.approx(g.real, rel=1e-6)
    assert result.params["normal_im"] == pytest.approx(g.imag, rel=1e-6)


def test_normal_gains_need_their_solver_and_shift(truth):
    """One line each: a gain fitted (or set) without ax.eigen.NormalForce, the solver
    without a shift, a limit-cycle target."""
    g, params, psi1 = truth
    shape = ShapeTarget(S_UM, psi1, 0.01)
    common = dict(shape=shape, bounds={"normal_re": (-1e3, 1e3)}, units=UNITS)
    free = ["normal_re"]
    with pytest.raises(ValueError, match="NormalForce"):
        ax.inverse.build_problem(MODEL, params, [], free, **common)
    with pytest.raises(ValueError, match="NormalForce"):
        ax.inverse.build_problem(MODEL, params, [], ["m0"], shape=shape, units=UNITS)
    with pytest.raises(ValueError, match="shift"):
        ax.inverse.build_problem(MODEL, params, [], free, solver=ax.eigen.NormalForce(), **common)
    cycle = Target("frequency_hz", 10.0, 0.1, source="limit_cycle")
    with pytest.raises(ValueError, match="limit cycle"):
        ax.inverse.build_problem(
            MODEL, params, [cycle], free, solver=ax.eigen.NormalForce(), shift=1j * SP, **common
        )


def _cli_fit(*extra, gain=None, omega0=True, moment=True):
    """``axojax fit --mechanism normal-force`` on the truth's model and values (physical
    flags from the default units), its gain free, the Hopf pins as targets."""
    f_hz = float(UNITS.omega0_to_hz(SP))
    argv = ["fit", "--model", "two", "--elements", "6", "--p", "0", "--kl", "1000"]
    argv += ["--mechanism", "normal-force", "--normal-gain", gain or "-0.4,-0.8"]
    argv += ["--omega0-hz", repr(f_hz)] if omega0 else []
    argv += ["--static-moment-pn", repr(float(UNITS.moment_to_pn(M0)))] if moment else []
    argv += ["--free", "normal_re,normal_im", "--target-frequency", repr(f_hz)]
    argv += ["--frequency-sigma", repr(1e-3 * f_hz), "--marginal", "0.2", "--starts", "1"]
    return main([*argv, "--no-mesh-check", *extra])


@pytest.mark.slow  # an end-to-end fit (the quick suite within 20 CPU-minutes)
def test_fit_command_recovers_the_normal_force_gain(truth, capsys):
    """``axojax fit --mechanism normal-force --free normal_re,normal_im``: the beat nearest
    i omega0 (--omega0-hz) of the augmented pencil pinned at growth 0 and the frequency
    recovers scipy's Hopf gain to 1e-6 relative."""
    g, _, _ = truth
    assert _cli_fit("--json") == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["params"]["normal_re"] == pytest.approx(g.real, rel=1e-6)
    assert doc["params"]["normal_im"] == pytest.approx(g.imag, rel=1e-6)
    assert doc["regime"][0]["regime"] == "near onset"  # the beat's, at the Hopf point


@pytest.mark.parametrize(
    "kwargs, extra, flag",
    [
        ({"omega0": False}, (), "--omega0-hz: "),  # the gain's g'' holds at a frequency
        ({"omega0": False, "gain": "-0.4,0"}, (), "--mechanism normal-force: a fit of"),
        ({"moment": False}, (), "--mechanism normal-force: no static normal force"),
        ({}, ("--solver", "arnoldi"), "--solver arnoldi: "),
    ],
    ids=["no-omega0", "no-omega0-real-gain", "no-static-moment", "other-solver"],
)
def test_fit_command_refuses_a_normal_force_fit_it_cannot_do(capsys, kwargs, extra, flag):
    assert _cli_fit(*extra, **kwargs) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"axojax: error: {flag}") and "\n" not in err, err
