"""The one implementation of the waveform measures (axojax/waveform/measures.py) against
independent computations: analytic integrals, numpy on a dense scipy eigenvector with
the Hermite interpolation written out here, numpy's polyfit and trapezoid; numpy and jax
inputs alike, jit and gradients; the standing-wave convention."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from numpy.polynomial import polynomial as P

import axojax as ax
from axojax.eigen import displacement_wavenumber
from axojax.waveform import FourierModes
from axojax.waveform import measures as wm

# psi_1(s) = A(s) exp(i phi(s)) on s in [0, 12]: Im(conj psi psi') = A^2 phi', so
# k = int A^2 phi' ds / int A^2 ds, exactly, by polynomial integration.
A = np.array([0.05, 0.2, -0.01])  # A(s) = 0.05 + 0.2 s - 0.01 s^2 (> 0 on (0, 12])
PHI = np.array([0.4, -0.3, 0.02, -0.002])  # phase turns ~4 rad, not uniformly
L = 12.0


def analytic_k():
    a2 = P.polymul(A, A)
    num = P.polyint(P.polymul(a2, P.polyder(PHI)))
    den = P.polyint(a2)
    return (P.polyval(L, num) - P.polyval(0, num)) / (P.polyval(L, den) - P.polyval(0, den))


def psi1_at(s):
    return P.polyval(s, A) * np.exp(1j * P.polyval(s, PHI))


def test_sampled_wavenumber_converges_to_the_integral_on_any_grid():
    k = analytic_k()
    rng = np.random.default_rng(0)
    errors = []
    for n in (200, 400, 800):
        s = np.sort(np.concatenate([[0.0, L], rng.uniform(0, L, n - 2)]))  # non-uniform
        errors.append(abs(wm.sampled_wavenumber(s, psi1_at(s)) - k) / abs(k))
    assert errors[-1] < 2e-4
    u = np.linspace(0, L, 2001)
    assert wm.sampled_wavenumber(u, psi1_at(u)) == pytest.approx(k, rel=1e-6)  # O(h^2)
    assert wm.wavelength(wm.sampled_wavenumber(u, psi1_at(u))) == pytest.approx(
        2 * np.pi / abs(k), rel=1e-6
    )


def test_midpoint_form_is_the_core_formula():
    """sum Im(conj psi_j psi_j+1) / sum |psi_j + psi_j+1|^2 / 4 ds (the brief's form)."""
    s = np.array([0.0, 0.5, 1.7, 2.0, 4.5, 6.0])
    psi = psi1_at(s)
    num = np.sum(np.imag(np.conj(psi[:-1]) * psi[1:]))
    den = np.sum(np.abs(psi[:-1] + psi[1:]) ** 2 / 4 * np.diff(s))
    assert wm.sampled_wavenumber(s, psi) == pytest.approx(num / den, rel=1e-13)


def test_numpy_and_jax_agree_jit_and_gradient():
    s = np.linspace(0, L, 41)
    psi = psi1_at(s)
    psi0 = 0.3 - 0.05 * s
    for f, args in (
        (wm.sampled_wavenumber, (s, psi)),
        (wm.dynamic_amplitude, (s, psi)),
        (wm.static_curvature, (s, psi0)),
    ):
        a = f(*args)
        b = jax.jit(f)(*map(jnp.asarray, args))
        assert isinstance(b, jax.Array) and float(b) == pytest.approx(float(a), rel=1e-13)

    def lam(c):  # wavelength of psi scaled point by point by c
        return wm.wavelength(wm.sampled_wavenumber(jnp.asarray(s), c * jnp.asarray(psi)))

    c = jnp.ones(41).at[0].set(0.0)  # a clamped base (psi = 0) makes no NaN
    g = np.asarray(jax.grad(lam)(c))
    assert np.all(np.isfinite(g))
    i, h = 20, 1e-6
    fd = (float(lam(c.at[i].add(h))) - float(lam(c.at[i].add(-h)))) / (2 * h)
    assert g[i] == pytest.approx(fd, rel=1e-5)


def test_standing_wave_has_no_wavelength():
    s = np.linspace(0, L, 41)
    psi = (0.3 + 0.1 * s) * np.exp(0.7j)  # one phase everywhere
    k = wm.sampled_wavenumber(s, psi)
    assert abs(k) * L < wm.STANDING_PHASE_RAD
    assert np.isinf(wm.wavelength(k, L)) and int(wm.direction(k, 1.0, L)) == 0
    assert wm.finite_or_none(wm.wavelength(k, L)) is None
    assert wm.finite_or_none(np.float64(17.0)) == 17.0
    g = jax.grad(lambda z: wm.wavelength(z))(jnp.asarray(0.0))
    assert float(g) == 0.0
    assert float(wm.phase_gradient(jnp.zeros(3, complex), jnp.zeros(3, complex), jnp.ones(3))) == 0


def test_direction_follows_the_sign_convention():
    """psi = Re(psi_1 e^{i omega t}), psi_1 = e^{-i k0 s}: crests run to larger s
    (anterograde) for omega > 0; reversing time reverses the direction."""
    s = np.linspace(0, L, 81)
    psi = np.exp(-1j * 0.5 * s)
    k = wm.sampled_wavenumber(s, psi)
    assert k < 0
    assert int(wm.direction(k, 2.0)) == 1 and int(wm.direction(k, -2.0)) == -1
    assert int(wm.direction(k, 0.0)) == 0


def test_amplitudes_curvature_and_projection_match_numpy():
    rng = np.random.default_rng(3)
    s = np.sort(rng.uniform(0, L, 30))
    psi0 = 0.3 - 0.05 * s + 0.01 * rng.standard_normal(30)
    psi1 = psi1_at(s)
    assert wm.static_curvature(s, psi0) == pytest.approx(np.polyfit(s, psi0, 1)[0], rel=1e-12)
    assert wm.dynamic_amplitude(s, psi1) == pytest.approx(
        np.trapezoid(np.abs(psi1), s) / (s[-1] - s[0]), rel=1e-12
    )
    y = rng.standard_normal(50)
    assert wm.tip_amplitude(y) == pytest.approx(np.ptp(y) / 2, rel=1e-15)
    v = rng.standard_normal((4, 2, 7))
    np.testing.assert_allclose(
        wm.along(v, 0.3), np.cos(0.3) * v[:, 0] + np.sin(0.3) * v[:, 1], rtol=1e-14
    )
    np.testing.assert_allclose(wm.along(v[:, :1], 0.3), v[:, 0], rtol=0)
    np.testing.assert_allclose(
        wm.along(np.moveaxis(v, 1, -1), 0.3, axis=-1), wm.along(v, 0.3), rtol=1e-15
    )
    # FourierModes (data, simulations) measure with the same functions
    m = FourierModes(s=s, psi0=psi0, psi1=psi1, omega=1.0)
    assert m.static_curvature == wm.static_curvature(s, psi0)
    assert m.dynamic_amplitude == wm.dynamic_amplitude(s, psi1)
    assert m.wavelength == wm.wavelength(wm.sampled_wavenumber(s, psi1), s[-1] - s[0])


def _hermite(nodal: np.ndarray, n_elements: int, x: np.ndarray):
    """u, u' at x of cubic Hermite nodal values (..., 2 N_e) [u_1, u'_1, ...] with a
    clamped node 0: the textbook formulas, written out here."""
    h = 1.0 / n_elements
    full = np.concatenate([np.zeros(nodal.shape[:-1] + (2,)), nodal], axis=-1)
    e = np.clip(np.floor(x / h).astype(int), 0, n_elements - 1)
    t = x / h - e
    u0, d0, u1, d1 = (full[..., 2 * e + j] for j in range(4))
    u = (
        (1 - 3 * t**2 + 2 * t**3) * u0
        + h * (t - 2 * t**2 + t**3) * d0
        + (3 * t**2 - 2 * t**3) * u1
        + h * (t**3 - t**2) * d1
    )
    du = (6 * t**2 - 6 * t) / h * u0 + (1 - 4 * t + 3 * t**2) * d0
    du = du + (6 * t - 6 * t**2) / h * u1 + (3 * t**2 - 2 * t) * d1
    return u, du


def test_mode_wavelength_is_the_tangent_angles(seven):
    """Fig. 7d mode (seven filaments, p = 300): the wavelength of psi_1 = u' along the beat
    direction, from scipy's dense eigenvector, the Hermite interpolation written out here
    and a fine finite-difference sampling; the displacement form gives docs/model.md's 20.72 um."""
    params = ax.Params(p=300.0, ks=1e6, kl=1e3, cl=1 / 200)
    mode = ax.dominant_mode(seven, params)
    s = ax.assemble(seven, params)
    lam, V = scipy.linalg.eig(-np.asarray(s.A), np.asarray(s.C))
    i = np.argmax(np.where(lam.imag > 0, lam.real, -np.inf))
    assert lam[i] == pytest.approx(complex(mode.eigenvalue), rel=1e-9)
    n = seven.n_elements
    q = V[:, i].reshape(seven.n_filaments, seven.n_dirs, 2 * n).mean(axis=0)  # (2, 2 N_e)
    x = np.linspace(0.0, 1.0, 40001)
    u, du = _hermite(q, n, x)  # (2, X)
    R = np.real(np.trapezoid(u[:, None] * np.conj(u[None]), x, axis=-1))
    w, vec = np.linalg.eigh(R)
    e = vec[:, -1]
    assert np.sqrt(w[0] / w[1]) == pytest.approx(float(mode.out_of_plane_ratio), rel=1e-6)

    def k_of(f):
        df = np.gradient(f, x)
        return np.trapezoid(np.imag(np.conj(f) * df), x) / np.trapezoid(np.abs(f) ** 2, x)

    length = ax.Units().length_um
    k_psi, k_u = k_of(e @ du), k_of(e @ u)
    assert float(mode.wavelength_um()) == pytest.approx(2 * np.pi / abs(k_psi) * length, rel=1e-5)
    assert float(mode.wavenumber) == pytest.approx(k_psi, rel=1e-5)
    assert float(displacement_wavenumber(seven, mode.eigenvector)) == pytest.approx(k_u, rel=1e-5)
    assert abs(2 * np.pi / abs(k_u) * length - 20.72) < 0.005  # docs/model.md section 6
    assert int(mode.direction) == (1 if k_psi * lam[i].imag < 0 else -1) == 1
    assert float(mode.velocity_um_per_s()) == pytest.approx(
        2 * np.pi / abs(k_psi) * length * float(mode.frequency_hz()), rel=1e-5
    )
