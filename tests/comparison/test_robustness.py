"""How robust compare's ranking is, from the data (issue 45, item 4): a bootstrap over the
recording's cycles, each row's shape held and its complex amplitude refitted
(axojax/inverse/comparison/robustness.py). References here are independent: scipy's
least squares for the amplitude, and beats made by hand."""

import math

import numpy as np
import pytest
from scipy.optimize import least_squares

from axojax.beats.data import beat_from_kymograph
from axojax.inverse.comparison.robustness import (
    cycle_bootstrap,
    phase_chi2,
    shape_chi2,
    whole_beat_bootstrap,
)
from axojax.inverse.comparison.verdict import verdict

S = np.linspace(0.0, 1.0, 21)
TRUE = (S + 0.2) * np.exp(-2j * np.pi * S)  # a travelling wave, growing to the tip
OTHER = (S + 0.2) * np.exp(-1.5j * np.pi * S)  # a longer wave


def test_shape_chi2_refits_the_complex_amplitude():
    rng = np.random.default_rng(0)
    sigma = 0.05 + 0.05 * rng.random(S.size)
    psi = 0.7j * TRUE + 0.05 * (rng.normal(size=S.size) + 1j * rng.normal(size=S.size))

    def resid(a):
        d = (psi - (a[0] + 1j * a[1]) * OTHER) / sigma
        return np.concatenate([d.real, d.imag])

    best = least_squares(resid, [1.0, 0.0], xtol=1e-14, ftol=1e-14)
    ref = float(np.sum(best.fun**2))
    assert shape_chi2(psi[None], OTHER, sigma)[0] == pytest.approx(ref, rel=1e-9)


def _row(name, model, n_free=4, status="successful"):
    return {
        "mechanism": name,
        "base": "clamped",
        "status": status,
        "psi1_model": [[z.real, z.imag] for z in model],
        "frequency_hz": 10.0,
        "growth_rate_per_s": 0.0,
        "n_free": n_free,
    }


def _cycles(n, noise, seed=1):
    rng = np.random.default_rng(seed)
    return TRUE[None] + noise * (rng.normal(size=(n, S.size)) + 1j * rng.normal(size=(n, S.size)))


def test_the_true_shape_stays_first_and_a_tie_splits():
    """Cycles of the true shape with noise: the row with the true shape is first in every
    resample against a longer wave, while a shape distorted below the noise takes first
    place in some resamples."""
    cycles = _cycles(30, 0.05)
    sigma = np.full(S.size, 0.05 / math.sqrt(30) * 1.5)
    rows = [_row("true", TRUE), _row("other", OTHER)]
    out = cycle_bootstrap(rows, cycles, sigma, 10.0, 1e-3, resamples=200)
    assert out["best"] == "true/clamped" and out["best_share"] == 1.0
    assert out["shares"]["other/clamped"] == 0.0 and out["cycles"] == 30
    # a near-tie: the other row is the true shape times a distortion below the noise
    near = TRUE * (1 + 0.002 * S)
    out = cycle_bootstrap([_row("true", TRUE), _row("near", near)], cycles, sigma, 10.0, 1e-3)
    assert 0.05 < out["best_share"] < 0.99  # some resamples rank them the other way
    assert sum(out["shares"].values()) == pytest.approx(1.0)


def test_no_bootstrap_without_cycles_and_failed_rows_left_out():
    sigma = np.full(S.size, 0.05)
    assert cycle_bootstrap([_row("true", TRUE)], None, sigma, 10.0, 1e-3) is None
    assert cycle_bootstrap([_row("true", TRUE)], _cycles(3, 0.05), sigma, 10.0, 1e-3) is None
    rows = [_row("bad", OTHER, status="nonlinear_max_steps_reached"), _row("true", TRUE)]
    out = cycle_bootstrap(rows, _cycles(10, 0.05), sigma, 10.0, 1e-3, resamples=50)
    assert set(out["shares"]) == {"true/clamped"}


def test_verdict_states_the_share():
    doc = {
        "data": {"s_um": list(S)},
        "rows": [dict(_row("true", TRUE), r2=0.95, chi2_per_dof=1.0, weight=1.0)],
        "robustness": {"best_share": 0.87, "resamples": 1000, "cycles": 30},
    }
    assert "first in 87 % of 1000 bootstrap resamples of the 30 cycles" in verdict(doc)["text"]


def test_a_kymograph_keeps_its_cycles():
    """A valid kymograph (8 cycles of a travelling wave): psi_1 of each whole cycle, whose
    mean is the beat's psi_1; a basal exclusion trims them with the rest."""
    t = np.arange(0, 0.8, 0.002)
    s = np.linspace(0, 10, 11)
    psi = 0.5 * np.cos(2 * np.pi * (10 * t[:, None] - s[None] / 10))
    beat = beat_from_kymograph(t, s, psi)
    assert beat.psi1_cycles.shape == (beat.cycles, s.size) and beat.cycles >= 6
    np.testing.assert_allclose(beat.psi1_cycles.mean(axis=0), beat.modes.psi1, atol=1e-12)
    cut = beat.exclude_base(2.0)
    assert cut.psi1_cycles.shape == (beat.cycles, cut.s_um.size)


def test_phase_chi2_refits_only_the_time_origin():
    """A limit cycle's psi_1 keeps its amplitude; only its time origin is free: scipy's
    minimum over the phase is the closed form's."""
    rng = np.random.default_rng(2)
    sigma = 0.05 + 0.05 * rng.random(S.size)
    psi = 0.7j * TRUE + 0.05 * (rng.normal(size=S.size) + 1j * rng.normal(size=S.size))

    def chi2(phi):
        return float(np.sum(np.abs(psi - np.exp(1j * phi[0]) * 0.9 * OTHER) ** 2 / sigma**2))

    ref = min(least_squares(lambda p: [math.sqrt(chi2(p))], [x]).fun[0] ** 2 for x in (0, 2, 4))
    assert phase_chi2(psi[None], 0.9 * OTHER, sigma)[0] == pytest.approx(ref, rel=1e-7)
    # an amplitude it may not refit costs: the shape's chi^2 is never larger
    assert shape_chi2(psi[None], OTHER, sigma)[0] <= phase_chi2(psi[None], OTHER, sigma)[0]


def _whole(name, model, rest=0.0, n_free=5):
    return dict(_row(name, model, n_free), chi2_rest=rest)


def test_the_whole_beats_bootstrap_holds_each_orbit():
    """Cycles of the true orbit with noise: its row is first in every resample against an
    orbit of the same shape but 20 % too small (a whole beat's amplitude is not refitted)
    and against one as true whose psi_0 fitted worse (its ``chi2_rest``); a time shift
    of the true orbit costs nothing."""
    cycles = _cycles(30, 0.05)
    sigma = np.full(S.size, 0.05 / math.sqrt(30) * 1.5)
    n_res = 3 * S.size + 1
    rows = [_whole("true", TRUE), _whole("small", 0.8 * TRUE), _whole("rest", TRUE, rest=50.0)]
    out = whole_beat_bootstrap(rows, cycles, sigma, n_res, resamples=200)
    assert out["best_share"] == 1.0 and not out["identical"]
    assert out["shares"]["small/clamped"] == out["shares"]["rest/clamped"] == 0.0
    shifted = whole_beat_bootstrap(
        [_whole("late", TRUE * np.exp(0.7j)), _whole("small", 0.8 * TRUE)],
        cycles,
        sigma,
        n_res,
        resamples=200,
    )
    assert shifted["best_share"] == 1.0


def test_copies_of_one_cycle_are_said_to_be_copies():
    """A recording made of copies of one cycle (a noise-free periodic kymograph) gives no
    bootstrap share: resampling copies always keeps the ranking, which says nothing; the
    verdict says so instead of claiming 100 %. A recording with noise still bootstraps."""
    t = np.arange(0, 0.8, 0.002)  # 50 frames per cycle: every cycle the same frames
    s = np.linspace(0, 10, 11)
    psi = 0.5 * np.cos(2 * np.pi * (10 * t[:, None] - s[None] / 10))
    beat = beat_from_kymograph(t, s, psi)
    model = beat.modes.psi1
    sigma = np.full(s.size, 0.05)
    rows = [_row("true", model), _row("other", 0.5 * model * np.exp(0.3j * s))]
    out = cycle_bootstrap(rows, beat.psi1_cycles, sigma, 10.0, 1e-3)
    assert out["identical"] and out["resamples"] == 0 and out["best_share"] is None
    doc = {
        "data": {"s_um": list(s)},
        "rows": [dict(rows[0], r2=0.99, chi2_per_dof=1.0, weight=1.0)],
        "robustness": out,
    }
    text = verdict(doc)["text"]
    assert f"{beat.cycles} cycles are copies of one" in text and "%" not in text
    rng = np.random.default_rng(3)
    noisy = beat_from_kymograph(t, s, psi + 0.02 * rng.normal(size=psi.shape))
    out = cycle_bootstrap(rows, noisy.psi1_cycles, sigma, 10.0, 1e-3, resamples=100)
    assert not out["identical"] and out["best_share"] == 1.0
