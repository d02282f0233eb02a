"""Stand-ins for real recordings of a whole beat (issue 54: real Chlamydomonas cycles are
kept outside the project): a model limit cycle made unlike any model's, as a real cell's
is, and written as the kymograph a lab would give.

:func:`chlamydomonas_standin`: curvature control on a clamped base (two filaments, 10
elements; tests/whole_beat/test_whole_beat_fit.py's truth: 20 % past its Hopf point,
omega0 tau_m = 1, f_sat 1000 pN/um, m0 -70 pN) at 12 um and 50 Hz, then

- psi_1's amplitude tilted (x 1 + 0.3 (s/L - 1/2)) and its phase bent (e^{0.6 i (s/L)^2}),
  psi_0 stretched (x 1 + 0.4 (s/L - 1/2)): harmonics no row of the model reproduces;
- a second harmonic of its own, 0.15 (s/L) sin(2 theta + 1 + 2 s/L) rad (non-sinusoidal);
- the model's own higher harmonics kept;
- the base angle 1.7 rad (the camera's direction);
- noise of 5 % of the mean |psi_1| on every frame (fixed seed), 8 cycles of 48 frames.
"""

import numpy as np

import axojax as ax
from axojax.inverse.comparison.mechanisms import build_model, row
from tests.whole_beat.test_whole_beat_fit import F_SAT, HZ, M0, UNITS, W0, _hopf

BASE_ANGLE = 1.7


def chlamydomonas_standin(path, points: int = 31, seed: int = 3):
    """Write the stand-in kymograph (module docstring) to ``path`` (.npz: psi, s_um,
    frame_rate_hz, length_um) and return the truth's cycle."""
    model = build_model("two", 10, "clamped", UNITS)
    spec = row("curvature", "clamped", model, UNITS, HZ)
    hopf = _hopf(model, spec.params, "beta")
    truth = hopf.replace(beta_re=1.2 * hopf.beta_re, beta_im=1.2 * hopf.beta_im, m0=M0)
    cycle = ax.limit_cycle(model, truth, 0.0, tau_m=1.0 / W0, f_sat=F_SAT, throw=True)
    f = float(cycle.frequency_hz(UNITS))
    x = np.linspace(0.0, 1.0, points)
    t, psi = cycle.centreline_beat(x, n_frames=48, derivative=1)
    p0, p1 = (np.asarray(a) for a in cycle.tangent_modes(x))
    theta = float(cycle.omega) * t
    higher = psi - p0[None] - np.real(p1[None] * np.exp(1j * theta)[:, None])
    q1 = p1 * (1 + 0.3 * (x - 0.5)) * np.exp(0.6j * x**2)
    q0 = p0 * (1 + 0.4 * (x - 0.5))
    th = 2 * np.pi * np.arange(8 * 48) / 48
    k = np.arange(th.size) % 48
    P = q0[None] + np.real(q1[None] * np.exp(1j * th)[:, None]) + higher[k]
    P = P + 0.15 * x[None, :] * np.sin(2 * th[:, None] + 1.0 + 2 * x[None, :]) + BASE_ANGLE
    rng = np.random.default_rng(seed)
    P = P + 0.05 * np.mean(np.abs(q1)) * rng.normal(size=P.shape)
    np.savez(path, psi=P, s_um=x * UNITS.length_um, frame_rate_hz=48 * f, length_um=UNITS.length_um)
    return cycle
