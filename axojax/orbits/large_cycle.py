"""The large cycle past a subcritical Hopf point, from a simulation begun at a large bend.

Past a supercritical Hopf point the beat grows out of the equilibrium, and the Hopf
normal form (:mod:`axojax.orbits.guess`) starts Newton on it. Past a subcritical one
(the normal form's Re g21 > 0) there is no small orbit: a small bend grows until the
motors saturate, onto a distant cycle, the beat a recording shows. Newton needs a start
on that cycle; :func:`large_cycle` makes one the way a beat is found in a lab:

1. integrate ``C dX/dt = ...`` (:func:`axojax.dynamics.integrate.integrate`, compiled, motor
   kinetics and saturation included) from the static tip deflection scaled to ``bend``
   (L; the motors' copy y starts equal to q, already adapted to the bend) for
   ``periods`` periods of the linear beat;
2. take the last whole period (the tip's upward crossings of its mean) and its Fourier
   coefficients, shifted in time so that the largest component of the first harmonic is
   real (the phase condition ``e_j . b_1 = 0``);
3. refine by Newton on the harmonic balance (:func:`axojax.limit_cycle` with that
   ``start``).

Held bases only (clamped, pivot with a spring: on a base that moves the simulated
record drifts rigidly and the phase conditions of :mod:`axojax.orbits.rigid` take over).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from ..dynamics.simulate import integrate_jit, tip_deflection
from ..models.section import Model
from ..params import Params
from ..waveform.shapes import centreline
from .cycle import LimitCycle
from .limit_cycle import limit_cycle
from .solvers import AbstractOrbitSolver, HarmonicBalance

BEND = 0.3
"""Default initial tip deflection (L): a bend of order one radian."""
PERIODS = 30
"""Default simulated periods of the linear beat before the last one is taken."""
SAMPLES = 64
"""Saved states per linear period."""


def _last_period(t: np.ndarray, tip: np.ndarray) -> tuple[float, float]:
    """(start, period) of the last whole period: between the last two upward crossings of
    the tip's mean (linear interpolation); NaN when it crosses fewer than three times."""
    y = tip - tip[len(tip) // 2 :].mean()
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    if len(up) < 3:
        return math.nan, math.nan
    times = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    return float(times[-2]), float(times[-1] - times[-2])


def harmonics_of(t: np.ndarray, X: np.ndarray, start: float, period: float, H: int):
    """((2H+1, n) coefficients ``[c_0, a_1..a_H, b_1..b_H]``, phase_ref (n,)): the
    Fourier coefficients of X(t) over [start, start + period) (linear interpolation at
    ``4 H + 8`` equal phases), the time origin shifted so that the largest component j
    of the first harmonic is real (``b_1[j] = 0``; phase_ref = e_j)."""
    M = 4 * H + 8
    ts = start + period * np.arange(M) / M
    Xs = np.stack([np.interp(ts, t, X[:, i]) for i in range(X.shape[1])], axis=1)
    F = np.fft.rfft(Xs, axis=0) / M  # X = F_0 + sum_k 2 Re(F_k e^{i k theta})
    z = 2 * F[1 : H + 1]  # a_k - i b_k
    j = int(np.argmax(np.abs(z[0])))
    z = z * np.exp(-1j * np.angle(z[0, j]) * np.arange(1, H + 1))[:, None]
    coefficients = np.concatenate([F[:1].real, z.real, -z.imag])
    ref = np.zeros(X.shape[1])
    ref[j] = 1.0
    return coefficients, ref


def large_cycle(
    model: Model,
    params: Params,
    kappa: float = 0.0,
    *,
    tau_m: float,
    f_sat: float,
    bend: float = BEND,
    periods: int = PERIODS,
    solver: AbstractOrbitSolver = HarmonicBalance(),
) -> LimitCycle:
    """The limit cycle reached from a large bend (module docstring) at ``params`` (past a
    Hopf point, subcritical or not), with motor kinetics ``tau_m`` and saturation
    ``f_sat`` (dimensionless, as :func:`axojax.limit_cycle` takes them), cubic link
    stiffening ``kappa`` (1/L^2). Check ``cycle.converged``: False where the simulation
    did not settle on a cycle Newton could refine (it decayed, or diverged)."""
    template = limit_cycle(model, params, kappa, solver=solver, tau_m=tau_m, f_sat=f_sat)
    lam = complex(template.linear_eigenvalue)
    omega = abs(lam.imag) if lam.imag else float(params.omega0)
    H = (template.coefficients.shape[0] - 1) // 2
    T = 2 * np.pi / omega
    t = np.linspace(0.0, periods * T, periods * SAMPLES + 1)
    q0 = bend * np.concatenate([tip_deflection(model), np.zeros(model.n_border)])
    X0 = np.concatenate([q0, q0])  # the motors' copy adapted to the bend
    traj = integrate_jit(
        model,
        params,
        jnp.asarray(kappa),
        jnp.asarray(X0),
        jnp.asarray(t),
        tau_m=jnp.asarray(tau_m),
        f_sat=jnp.asarray(f_sat),
    )
    X = np.asarray(traj.q)
    if not bool(traj.ok) or not np.all(np.isfinite(X)):
        return template
    n = model.n_unknowns
    tips = np.asarray(centreline(model, X[:, :n], np.ones(1), body=True))[:, :, 0]  # (T, d)
    tip = tips[:, np.argmax(tips[len(t) // 2 :].var(axis=0))]
    start, period = _last_period(t, tip)
    if not np.isfinite(period):
        return template
    coefficients, ref = harmonics_of(t, X, start, period, H)
    guess = eqx.tree_at(
        lambda c: (c.coefficients, c.omega, c.converged, c.phase_ref),
        template,
        (
            jnp.asarray(coefficients),
            jnp.asarray(2 * np.pi / period),
            jnp.asarray(True),
            jnp.asarray(ref),
        ),
    )
    return limit_cycle(model, params, kappa, solver=solver, tau_m=tau_m, f_sat=f_sat, start=guess)
