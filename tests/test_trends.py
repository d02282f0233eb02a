"""Paper trends (MODEL.md section 6) on the seven-filament preset."""

import jax
import numpy as np
import pytest

import axojax as ax


@pytest.fixture(scope="module")
def model():
    return ax.models.seven()


def test_critical_force_rises_with_spoke_stiffness(model):
    ks = np.logspace(2, 7, 6)
    pc = jax.vmap(lambda k: ax.critical_force(model, ax.Params(ks=k, kl=k / 1e3).broadcast()).p)(ks)
    assert np.all(np.diff(np.asarray(pc)) > 0)


@pytest.mark.parametrize("ks", [1e3, 1e4, 1e5, 1e6])
def test_near_boundary_frequency_rises_wavelength_falls(model, ks):
    params = ax.Params(ks=ks, kl=ks / 1e3)
    pc = float(ax.critical_force(model, params).p)
    ps = pc * np.array([1.0001, 1.05, 1.1, 1.2, 1.35, 1.5])
    modes = jax.vmap(lambda p: ax.dominant_mode(model, params.replace(p=p).broadcast()))(ps)
    assert np.all(np.asarray(modes.classification) == 1)
    assert np.all(np.diff(np.asarray(modes.frequency_hz())) > 0)
    wl = np.asarray(modes.wavelength_um())
    assert wl[-1] < 0.75 * wl[0]  # wavelength falls from the boundary to 1.5 p_c
    if ks == 1e5:  # and, on this line, monotonically up to 1.35 p_c (it flattens after)
        assert np.all(np.diff(wl[:-1]) < 0)


def test_unstable_oscillations_anterograde_wavelength_order(model):
    ps, kss = np.meshgrid(np.linspace(100, 1000, 10), np.logspace(2, 7, 11))
    params = ax.Params(p=ps.ravel(), ks=kss.ravel(), kl=kss.ravel() / 1e3).broadcast()
    modes = jax.vmap(lambda prm: ax.dominant_mode(model, prm))(params)
    flutter = np.asarray(modes.classification) == 1
    assert flutter.sum() > 40
    wl = np.asarray(modes.wavelength_um())
    # Travelling waves (phase changing by more than 36 degrees along the cilium, i.e.
    # wavelength < 10 L) all run base to tip. Just past the boundary at soft spokes
    # (p ~ 100, ks ~ 1e3-1e4) the dominant mode is a near-standing wave (wavelength
    # 15-30 L) whose tiny phase gradient may point either way; those are excluded.
    travelling = flutter & (wl < 10 * 12.0)
    assert travelling.sum() >= flutter.sum() - 4
    assert np.all(np.asarray(modes.direction)[travelling] == 1)
    assert np.all((wl[travelling] > 5) & (wl[travelling] < 60))
    assert 10 < np.median(wl[travelling]) < 50
