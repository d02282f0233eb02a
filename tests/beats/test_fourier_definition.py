"""One definition of psi_0 and psi_n for data and model (issue 54 item 2): per whole cycle
k, psi_n = (2 / T_k) int psi(t) exp(-i n omega_k (t - t_k)) dt (psi_0 with 1 / T_k),
averaged over the cycles; and a slow rotation of the recording removed before it
(item 1).

The kymograph is synthetic and non-sinusoidal: psi = A(s) + Re(B(s) e^{i phi}) +
Re(C(s) e^{2 i phi}), its phase phi advancing uniformly within each of ten cycles of
unequal length (0.85 to 1.2 times 20 ms), sampled at 1000 frames/s (20 frames a cycle,
a real recording's rate). The second harmonic is not orthogonal to the first, so the
beat phase axojax projects does not advance uniformly in time: a least-squares fit in
that phase (the reduction before issue 54) misses psi_0 by 0.08 rad and psi_1 by 0.22
rad here. The reference integrals are scipy's adaptive quadrature of the analytic
kymograph over the reduction's own cycle bounds.
"""

import numpy as np
import pytest
from scipy.integrate import quad_vec

import axojax as ax
from axojax.beats.data import beat_from_kymograph

S_UM = np.linspace(0.0, 12.0, 13)
A = 0.3 - 0.15 * S_UM
B = 0.8 * np.exp(-2j * np.pi * S_UM / 10) * (0.5 + S_UM / 12)
C = 0.3 * np.exp(-2j * np.pi * S_UM / 7) * (S_UM / 12)
PERIODS = 0.02 * np.array([1.0, 1.15, 0.9, 1.1, 0.85, 1.05, 0.95, 1.2, 0.9, 1.0])
STARTS = np.concatenate([[0.0], np.cumsum(PERIODS)])
RATE = 1000.0


def psi(t: float, rotation: float = 0.0) -> np.ndarray:
    """The kymograph at time t (S,), turning at ``rotation`` rad/s."""
    k = int(np.clip(np.searchsorted(STARTS, t, side="right") - 1, 0, PERIODS.size - 1))
    phi = 2 * np.pi * (k + (t - STARTS[k]) / PERIODS[k]) + 0.7
    return A + np.real(B * np.exp(1j * phi)) + np.real(C * np.exp(2j * phi)) + rotation * t


def beat(rotation: float = 0.0):
    t = np.arange(0.0, STARTS[-1], 1.0 / RATE)
    return beat_from_kymograph(t, S_UM, np.stack([psi(x, rotation) for x in t]))


def reference(bounds) -> tuple[np.ndarray, np.ndarray]:
    """(psi_0, psi_1) of the kymograph without rotation: the time Fourier coefficients of
    each cycle between consecutive ``bounds`` by adaptive quadrature (split where the
    phase's rate changes), averaged."""
    psi0, psi1 = [], []
    for a, b in zip(bounds[:-1], bounds[1:]):
        kinks = STARTS[(STARTS > a) & (STARTS < b)]
        period = b - a
        kernel = lambda x, a=a, period=period: np.exp(-2j * np.pi * (x - a) / period)  # noqa: E731
        mean = quad_vec(psi, a, b, points=kinks, epsabs=1e-12)[0] / period
        first = quad_vec(lambda x: psi(x) * kernel(x), a, b, points=kinks, epsabs=1e-12)[0]
        psi0.append(mean)
        psi1.append(2 * first / period)
    return np.mean(psi0, axis=0), np.mean(psi1, axis=0)


def test_psi_n_are_each_cycles_time_fourier_coefficients_averaged():
    """psi_0 and psi_1 of the reduction are the quadrature's to the error of a cubic
    spline through 20 frames a cycle (measured 3.1e-5 and 8.0e-5 rad); the cycles found
    are the record's whole ones, and psi_0's slope is A's."""
    got = beat()
    bounds = got.cycle_bounds_s
    assert got.cycles == len(bounds) - 1 >= 8
    psi0, psi1 = reference(bounds)
    np.testing.assert_allclose(got.modes.psi0, psi0, atol=1e-4)
    np.testing.assert_allclose(got.modes.psi1, psi1, atol=3e-4)
    np.testing.assert_allclose(got.psi1_cycles.mean(axis=0), got.modes.psi1, atol=1e-12)
    assert got.static_curvature_rad_per_um == pytest.approx(-0.15, abs=1e-3)
    assert got.rotation_rad_per_s == 0.0  # none in the record (below 0.01 rad: left)


def test_a_slow_rotation_is_removed_before_the_fourier_analysis():
    """The same kymograph turning at 3 rad/s (0.6 rad over the record, as much as the
    beat's amplitude): the reduction finds the rate (measured 3.0016), and psi_1 and psi_0
    are the unturned beat's quadrature values, psi_0 less the turn at the middle of the
    cycles used (the angle psi_0 refers to); the note says so."""
    got = beat(rotation=3.0)
    bounds = got.cycle_bounds_s
    assert got.rotation_rad_per_s == pytest.approx(3.0, abs=0.01)
    psi0, psi1 = reference(bounds)
    middle = (bounds[0] + bounds[-1]) / 2
    np.testing.assert_allclose(got.modes.psi1, psi1, atol=3e-4)
    np.testing.assert_allclose(got.modes.psi0, psi0 + 3.0 * middle, atol=1e-3)
    assert any("mean rotation 3" in n for n in got.notes)
    assert got.summary()["rotation_rad_per_s"] == got.rotation_rad_per_s


def test_the_orbits_harmonics_are_its_time_fourier_coefficients():
    """A model's psi_0, psi_1 (harmonic balance: LimitCycle.tangent_modes) equal the time
    Fourier coefficients of its tangent angle sampled over one period (numpy means of 64
    frames: exact for the orbit's few harmonics)."""
    model = ax.models.two(n_elements=4)
    base = ax.Params(p=160.0)
    p_c = float(ax.critical_force(model, base).p)
    cycle = ax.limit_cycle(model, base.replace(p=1.06 * p_c, a0=0.025), 6.0)
    x = np.linspace(0.0, 1.0, 9)
    t, slope = cycle.centreline_beat(x, n_frames=64, derivative=1)
    omega = 2 * np.pi / (t[1] - t[0]) / 64
    psi0, psi1 = cycle.tangent_modes(x)
    np.testing.assert_allclose(np.asarray(psi0), slope.mean(axis=0), atol=1e-12)
    first = 2 * np.mean(slope * np.exp(-1j * omega * t)[:, None], axis=0)
    np.testing.assert_allclose(np.asarray(psi1), first, atol=1e-12)
    assert np.max(np.abs(first)) > 0.01  # a beat, not a rest state
