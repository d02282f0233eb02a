"""The frame of a whole-beat fit (issue 54 item 1): ``frame="lab"`` compares psi as
recorded, psi_0 up to the reference angle; ``frame="basal"`` compares model and data
relative to the basal tangent, psi(s, t) - psi(0, t), as the linear comparison's
``frame`` does (docs/model.md section 8, frames; tests/comparison/test_frames.py).

The beat is tests/whole_beat/test_whole_beat_fit.py's synthetic curvature-control beat,
sampled from the base (s = 0) so that the basal frame applies, and the same beat as seen
from a frame that turns by 1.7 rad and rocks with the base (a rigid 0.3 rad oscillation of
the whole flagellum, psi_1 + 0.3 e^{0.4 i} at every s): what a lab-frame recording of a
base that moves adds, and what the basal frame removes.
"""

import dataclasses

import numpy as np
import pytest

import axojax as ax
from axojax.beats.targets import ShapeTarget, Target
from axojax.inverse.cycle_targets import psi_offset, shape_measures, shape_residuals
from axojax.inverse.whole_beat.compare import compare_whole_beat
from axojax.inverse.whole_beat.fit import fit_whole_beat, linear_hopf
from axojax.orbits import cycle_measures
from tests.whole_beat.test_whole_beat_fit import F_SAT, UNITS, _truth, _truth_cycle

S0 = np.linspace(0.0, 12.0, 25)
ROCK = 0.3 * np.exp(0.4j)
TURN = 1.7


def _beat(noise=0.02, seed=2):
    """(the beat from the base with noise, the same turned and rocking), lab frame."""
    m = cycle_measures(_truth_cycle(), S0, UNITS)
    rng = np.random.default_rng(seed)
    psi1 = np.asarray(m.psi1) + noise * (rng.normal(size=S0.size) + 1j * rng.normal(size=S0.size))
    psi0 = np.asarray(m.psi0) + noise * rng.normal(size=S0.size)
    clean = ShapeTarget(S0, psi1, noise, psi0=psi0, source="limit_cycle")
    moved = dataclasses.replace(clean, psi0=psi0 + TURN, psi1=psi1 + ROCK)
    return clean, moved


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_the_basal_frame_measures_the_orbit_from_its_basal_tangent():
    """On a pivot (its base turns: |psi_1(0)| well above 0), the orbit's basal-frame psi_0
    and psi_1 are the time Fourier coefficients of psi(s, t) - psi(0, t) sampled over one
    period (numpy, 64 frames)."""
    model = ax.models.two(n_elements=4, base=ax.models.Base("pivot", rotational_stiffness=2.0))
    start = ax.Params()
    params = start.replace(p=1.04 * float(ax.critical_force(model, start).p))
    cycle = ax.limit_cycle(model, params, 10.0)
    units = ax.Units()
    x = np.linspace(0.0, 1.0, 9)
    s = x * units.length_um
    shape = ShapeTarget(s, np.ones(9), 0.02, psi0=np.zeros(9), source="limit_cycle", frame="basal")
    got = shape_measures(cycle, shape, units)
    t, slope = cycle.centreline_beat(x, n_frames=64, derivative=1)
    omega = 2 * np.pi / (64 * (t[1] - t[0]))
    relative = slope - slope[:, :1]
    assert np.max(np.abs(np.asarray(cycle_measures(cycle, s, units).psi1)[0])) > 0.01
    np.testing.assert_allclose(np.asarray(got.psi0), relative.mean(axis=0), atol=1e-12)
    first = 2 * np.mean(relative * np.exp(-1j * omega * t)[:, None], axis=0)
    np.testing.assert_allclose(np.asarray(got.psi1), first, atol=1e-12)


def test_basal_residuals_ignore_the_recordings_turn_and_rocking():
    """At the truth's orbit (clamped: psi is 0 at its base), the basal-frame residuals of
    the turned, rocking beat are the clean beat's, and equal numpy's: psi relative to s = 0
    for data and model, sigmas in quadrature with the base's, psi_1's best unit phase, no
    reference angle. The lab frame absorbs the turn (its reference angle) but not the
    rocking."""
    from axojax.beats.frames import shape_in_basal_frame

    clean, moved = _beat()
    cycle = _truth_cycle()
    basal = [shape_in_basal_frame(b) for b in (clean, moved)]
    r = [np.asarray(shape_residuals(shape_measures(cycle, b, UNITS), b)) for b in basal]
    np.testing.assert_allclose(r[1], r[0], atol=1e-9)
    assert float(psi_offset(shape_measures(cycle, basal[1], UNITS), basal[1])) == 0.0

    m = cycle_measures(cycle, S0, UNITS)
    m0, m1 = np.asarray(m.psi0), np.asarray(m.psi1)
    m0, m1 = m0 - m0[0], m1 - m1[0]
    o0, o1 = moved.psi0 - moved.psi0[0], moved.psi1 - moved.psi1[0]
    sigma = np.full(S0.size, 0.02)
    sigma[1:] = np.hypot(sigma[1:], 0.02)
    z = np.sum(np.conj(m1) * o1 / sigma**2)
    d1 = (z / abs(z) * m1 - o1) / sigma
    expected = np.concatenate([(m0 - o0) / sigma, d1.real, d1.imag])
    np.testing.assert_allclose(r[1], expected, atol=1e-9)

    lab = [np.asarray(shape_residuals(shape_measures(cycle, b, UNITS), b)) for b in (clean, moved)]
    n = S0.size
    np.testing.assert_allclose(lab[1][:n], lab[0][:n], atol=1e-9)  # the turn: c absorbs it
    assert np.max(np.abs(lab[1][n:] - lab[0][n:])) > 5  # the rocking: sigmas off


def test_the_frame_is_checked_in_one_line():
    """An unknown frame, and the basal frame of data that do not start at the base, are
    refused before any fit, in one line naming ``frame``."""
    spec, hopf, _ = _truth()
    clean, _ = _beat()
    freq = Target("frequency_hz", 50.0, 0.5)
    for call in (
        lambda: fit_whole_beat(spec, hopf, clean, freq, UNITS, frame="body"),
        lambda: fit_whole_beat(
            spec, hopf, dataclasses.replace(clean, s_um=S0 + 0.5), freq, UNITS, frame="basal"
        ),
        lambda: compare_whole_beat("no such file", frame="body"),
    ):
        with pytest.raises(ValueError, match="^frame: ") as info:
            call()
        assert "\n" not in str(info.value)


@pytest.mark.slow
def test_a_basal_whole_beat_fit_recovers_the_turned_rocking_beat():
    """The turned, rocking beat fitted in the basal frame: the truth's orbit measures
    (frequency 5 %, static curvature and dynamic amplitude 15 %; measured 0.1 %, 1.7 %,
    0.4 %), every fitted coefficient, m0 and f_sat within 2 standard errors of the truth
    (measured within 0.4: beta'' 6 % off, +- 21 %; they correlate to 0.99), no reference
    angle (psi_offset_rad 0, not among n_free)."""
    spec, _, truth = _truth()
    _, moved = _beat()
    m = cycle_measures(_truth_cycle(), None, UNITS)
    freq = Target("frequency_hz", float(m.frequency_hz), 0.01 * float(m.frequency_hz))
    hopf, _ = linear_hopf(spec, moved, UNITS, frame="basal")
    out = fit_whole_beat(spec, hopf, moved, freq, UNITS, frame="basal")
    assert out.frame == "basal" and out.psi_offset_rad == 0.0
    got = out.measures
    for name, rel in (
        ("frequency_hz", 0.05),
        ("static_curvature_rad_per_um", 0.15),
        ("dynamic_amplitude_rad", 0.15),
    ):
        assert got[f"limit_cycle_{name}"] == pytest.approx(float(getattr(m, name)), rel=rel)
    want = {n: float(getattr(truth, n)) for n in ("beta_re", "beta_im", "m0")} | {"f_sat": F_SAT}
    for name, value in want.items():
        assert abs(out.fit.params[name] - value) <= 2 * out.fit.stderr[name], name
    assert out.fit.n_free == len(out.fit.names)
