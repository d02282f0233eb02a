"""Physical and numerical invariants of the assembled systems and their spectra."""

import numpy as np
import pytest

import axojax as ax
from axojax.eigen.mode import spectrum

PRESETS = ax.models.PRESETS


@pytest.mark.parametrize("name", PRESETS)
def test_no_load_spectrum_real_negative(name):
    lam = np.asarray(spectrum(ax.models.preset(name), ax.Params(p=0.0, gamma=1.0), None))
    assert np.all(lam.real < 0)
    assert np.max(np.abs(lam.imag)) <= 1e-9 * np.max(np.abs(lam))


@pytest.mark.parametrize("name", PRESETS)
def test_damping_matrix_symmetric_positive_definite(name):
    s = ax.assemble(ax.models.preset(name), ax.Params(cl=0.3))
    C = np.asarray(s.C)
    np.testing.assert_allclose(C, C.T, atol=1e-15)
    assert np.linalg.eigvalsh(C).min() > 0


def sorted_spectrum(model, params):
    lam = np.asarray(spectrum(model, params, None))
    return lam[np.lexsort((lam.imag, np.round(lam.real, 6)))]


def assert_same_spectrum(a, b, rtol=1e-8):
    # Compare as multisets: nearest-neighbour distance, scaled by magnitude.
    for z in a:
        assert np.min(np.abs(b - z)) <= rtol * max(1.0, abs(z)), z


@pytest.mark.parametrize("name", ["four", "seven", "nine"])
@pytest.mark.parametrize("angle", [0.3, np.pi / 2, 2.0])
def test_rotation_invariance_isotropic(name, angle):
    section = ax.models.preset(name).section
    params = ax.Params(p=250.0, ks=1e4, kl=10.0, out_of_plane=1.0, gamma=-0.5, ktheta=3.0)
    base = sorted_spectrum(ax.models.build_model(section), params)
    turned = sorted_spectrum(ax.models.build_model(section.rotated(angle)), params)
    assert_same_spectrum(base, turned)
    assert_same_spectrum(turned, base)


@pytest.mark.parametrize("name", ["two", "four", "seven", "nine"])
def test_relabelling_invariance(name):
    section = ax.models.preset(name).section
    order = np.random.default_rng(1).permutation(section.n_filaments)
    params = ax.Params(p=300.0, ks=1e5, kl=100.0, gamma=0.5, ktheta=2.0, imbalance=2.0)
    a = sorted_spectrum(ax.models.build_model(section), params)
    b = sorted_spectrum(ax.models.build_model(section.relabelled(order)), params)
    assert_same_spectrum(a, b)
    assert_same_spectrum(b, a)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize(
    "name,params",
    [("single", ax.Params(p=300.0)), ("seven", ax.Params(p=300.0)), ("beck", ax.Params(p=40.0))],
)
def test_mesh_convergence(name, params):
    values = [
        complex(spectrum(ax.models.preset(name, n_elements=n), params, 1)[0])
        for n in (5, 10, 20, 40, 80)
    ]
    values = [complex(v.real, abs(v.imag)) for v in values]
    errors = [abs(v - values[-1]) for v in values[:-1]]
    # Cubic Hermite elements: eigenvalue error O(h^4), so each halving gains ~16x.
    assert errors[0] > errors[1] and errors[1] / errors[2] > 8 and errors[2] / errors[3] > 8
    assert errors[3] < 1e-4 * abs(values[-1])
