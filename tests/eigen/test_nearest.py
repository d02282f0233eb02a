"""The eigenpair nearest a shift (axojax.eigen.nearest): the beat of a regulated mechanism
at i omega0, which need not be the dominant eigenvalue. Checked against scipy's full
generalized eigen-decomposition of the same assembled pencil, and its derivative against
central finite differences."""

import jax
import numpy as np
import scipy.linalg as sl

import axojax as ax
from axojax.eigen import Dense

A0 = 0.2 / 12
# Sliding control with an active friction (chi'' < 0) at omega0 = 1000: the pencil has
# faster-growing short-wavelength modes, so the beat near i omega0 is not the dominant one.
PARAMS = ax.Params(p=0.0, a0=A0, chi_re=-2 * 20 / A0**2, chi_im=-2 * 25 / A0**2, omega0=1000.0)


def _scipy_eigenvalues(model, params):
    system = ax.assemble(model, params)
    return sl.eig(-np.asarray(system.A), np.asarray(system.C), right=False)


def test_nearest_matches_scipy_and_is_not_the_dominant_one():
    model = ax.models.two(n_elements=8)
    lam = _scipy_eigenvalues(model, PARAMS)
    shift = 1000j
    expected = lam[np.argmin(np.abs(lam - shift))]
    mode = ax.nearest_mode(model, PARAMS, shift, Dense())
    assert abs(complex(mode.eigenvalue) - expected) < 1e-8 * abs(expected)
    assert np.max(lam.real) > 10 * abs(expected.real) + 1  # the dominant one is elsewhere
    dominant = ax.dominant_mode(model, PARAMS, Dense())
    assert abs(complex(dominant.eigenvalue) - expected) > 1.0


def test_nearest_to_the_dominant_eigenvalue_is_the_dominant_mode():
    """Steady load (paper fig. 7 point): shifting at the dominant eigenvalue returns it,
    with the same wavelength."""
    model = ax.models.seven(n_elements=6)
    params = ax.Params()
    dominant = ax.dominant_mode(model, params, Dense())
    mode = ax.nearest_mode(model, params, complex(dominant.eigenvalue) + 0.1, Dense())
    assert abs(complex(mode.eigenvalue - dominant.eigenvalue)) < 1e-9 * abs(
        complex(dominant.eigenvalue)
    )
    assert abs(float(mode.wavelength - dominant.wavelength)) < 1e-9


def test_nearest_derivative_matches_finite_differences():
    model = ax.models.two(n_elements=6)

    def growth(chi_re):
        return ax.nearest_mode(model, PARAMS.replace(chi_re=chi_re), 1000j, Dense()).growth_rate

    x = float(PARAMS.chi_re)
    g = float(jax.grad(growth)(x))
    h = 1e-6 * abs(x)
    fd = (float(growth(x + h)) - float(growth(x - h))) / (2 * h)
    assert abs(g - fd) < 1e-5 * abs(fd)
    assert abs(fd) > 0


def test_bad_solver_and_batch_are_refused():
    model = ax.models.two(n_elements=4)
    import pytest

    with pytest.raises(TypeError, match="eigen-solver"):
        ax.nearest_mode(model, PARAMS, 1000j, "dense")
    with pytest.raises(ValueError, match="vmap"):
        ax.nearest_mode(model, PARAMS.replace(p=np.zeros(2)), 1000j)
