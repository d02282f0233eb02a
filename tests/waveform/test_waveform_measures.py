"""The one implementation of the waveform measures (axojax/waveform/measures.py) against
independent computations: analytic integrals, numpy on a dense scipy eigenvector with
the Hermite interpolation written out here, numpy's unwrap, polyfit and trapezoid; numpy
and jax inputs alike, jit and gradients; the standing-wave convention; the flag on a
psi_1 that nearly vanishes inside the flagellum."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from numpy.polynomial import polynomial as P

import axojax as ax
from axojax.eigen import displacement_wavenumber, weighted_wavenumber
from axojax.waveform import FourierModes
from axojax.waveform import measures as wm

# psi_1(s) = A(s) exp(i phi(s)) on s in [0, 12]; the wavenumber is the least-squares
# slope of phi over [0, L] (uniform weight): int (s - L/2) phi ds / int (s - L/2)^2 ds,
# exactly, by polynomial integration.
A = np.array([0.05, 0.2, -0.01])  # A(s) = 0.05 + 0.2 s - 0.01 s^2 (> 0 on (0, 12])
PHI = np.array([0.4, -0.3, 0.02, -0.002])  # phase turns ~4 rad, not uniformly
L = 12.0


def analytic_k():
    num = P.polyint(P.polymul([-L / 2, 1.0], PHI))
    return (P.polyval(L, num) - P.polyval(0, num)) / (L**3 / 12)


def analytic_weighted_k():
    """The retired |psi_1|^2-weighted mean phase gradient: int A^2 phi' / int A^2."""
    a2 = P.polymul(A, A)
    num = P.polyint(P.polymul(a2, P.polyder(PHI)))
    den = P.polyint(a2)
    return (P.polyval(L, num) - P.polyval(0, num)) / (P.polyval(L, den) - P.polyval(0, den))


def psi1_at(s):
    return P.polyval(s, A) * np.exp(1j * P.polyval(s, PHI))


def dpsi1_at(s):
    a, da = P.polyval(s, A), P.polyval(s, P.polyder(A))
    return (da + 1j * a * P.polyval(s, P.polyder(PHI))) * np.exp(1j * P.polyval(s, PHI))


def test_sampled_wavenumber_converges_to_the_phase_slope_on_any_grid():
    k = analytic_k()
    assert abs(k - analytic_weighted_k()) > 0.05 * abs(k)  # the two forms differ here
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


def test_quadrature_form_is_the_same_slope():
    """The smooth form (by parts) at Gauss points equals the analytic slope."""
    x, w = np.polynomial.legendre.leggauss(60)
    s, w = (x + 1) * L / 2, w * L / 2
    k = wm.phase_slope(s, psi1_at(s), dpsi1_at(s), w, L)
    assert k == pytest.approx(analytic_k(), rel=1e-10)
    assert wm.weighted_phase_gradient(psi1_at(s), dpsi1_at(s), w) == pytest.approx(
        analytic_weighted_k(), rel=1e-10
    )


def test_samples_unwrap_and_fit_like_numpy():
    """np.unwrap then np.polyfit with the trapezoidal weights (and, evenly spaced, a plain
    polyfit within 1 %)."""
    s = np.array([0.0, 0.5, 1.7, 2.0, 4.5, 6.0, 7.2, 9.0, 12.0])
    psi = psi1_at(s)
    w = np.concatenate([np.diff(s), [0]]) / 2 + np.concatenate([[0], np.diff(s)]) / 2
    ref = np.polyfit(s, np.unwrap(np.angle(psi)), 1, w=np.sqrt(w))[0]
    assert wm.sampled_wavenumber(s, psi) == pytest.approx(ref, rel=1e-12)
    u = np.linspace(0, L, 41)
    ref = np.polyfit(u, np.unwrap(np.angle(psi1_at(u))), 1)[0]
    assert wm.sampled_wavenumber(u, psi1_at(u)) == pytest.approx(ref, rel=1e-2)


def test_a_zero_at_an_end_is_taken_by_continuity():
    """psi_1(0) = 0 (a clamped base) adds no phase turn: the slope is the rest's."""
    s = np.linspace(0, L, 81)
    psi = s * np.exp(-0.5j * s)  # zero at the base, phase slope -0.5 everywhere else
    assert wm.sampled_wavenumber(s, psi) == pytest.approx(-0.5, rel=1e-12)
    assert not wm.is_sensitive(wm.amplitude_dip(s, psi))


def test_an_interior_node_is_flagged():
    """psi_1 through 0 at mid-length: the phase jumps by pi there, the measure counts it,
    and amplitude_dip flags the wavelength as sensitive (a clean wave is not flagged)."""
    s = np.linspace(0, L, 200)
    psi = (s - 6.1) * np.exp(-0.3j * s)
    assert wm.is_sensitive(wm.amplitude_dip(s, psi))
    assert wm.sensitive_note(wm.amplitude_dip(s, psi)).startswith("  (sensitive")
    assert abs(wm.sampled_wavenumber(s, psi) + 0.3) > 0.1  # the turn of pi moves the slope
    clean = (1 + 0.1 * s) * np.exp(-0.3j * s)
    assert float(wm.amplitude_dip(s, clean)) > 0.3 and wm.sensitive_note(0.5) == ""


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
    z = jnp.zeros(3, complex)
    assert float(wm.weighted_phase_gradient(z, z, jnp.ones(3))) == 0
    assert float(wm.phase_slope(jnp.linspace(0, 1, 3), z, z, jnp.ones(3))) == 0


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
    assert m.wavenumber == pytest.approx(
        float(np.polyfit(s, np.unwrap(np.angle(psi1)), 1)[0]), rel=0.05
    )


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
    """Fig. 7d mode (seven filaments, p = 300): the wavelength is the phase slope of
    psi_1 = u' along the beat direction, from scipy's dense eigenvector, the Hermite
    interpolation written out here, a fine sampling unwrapped and fitted by numpy
    (docs/model.md section 5: 13.61 um; the retired forms 31.66 um weighted, 20.72 um of the
    displacement)."""
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

    def weighted_k(f):
        df = np.gradient(f, x)
        return np.trapezoid(np.imag(np.conj(f) * df), x) / np.trapezoid(np.abs(f) ** 2, x)

    length = ax.Units().length_um
    psi = e @ du
    k_psi = np.polyfit(x[1:], np.unwrap(np.angle(psi[1:])), 1)[0]  # psi(0) = 0: clamped
    assert float(mode.wavelength_um()) == pytest.approx(2 * np.pi / abs(k_psi) * length, rel=1e-4)
    assert float(mode.wavenumber) == pytest.approx(k_psi, rel=1e-4)
    assert abs(float(mode.wavelength_um()) - 13.61) < 0.005  # docs/model.md section 5
    k_w, k_u = weighted_k(psi), weighted_k(e @ u)
    assert float(weighted_wavenumber(seven, mode.eigenvector)) == pytest.approx(k_w, rel=1e-5)
    assert float(displacement_wavenumber(seven, mode.eigenvector)) == pytest.approx(k_u, rel=1e-5)
    assert abs(2 * np.pi / abs(k_w) * length - 31.66) < 0.005  # the retired forms, by name
    assert abs(2 * np.pi / abs(k_u) * length - 20.72) < 0.005
    assert int(mode.direction) == (1 if k_psi * lam[i].imag < 0 else -1) == 1
    assert float(mode.velocity_um_per_s()) == pytest.approx(
        2 * np.pi / abs(k_psi) * length * float(mode.frequency_hz()), rel=1e-4
    )
    dip = np.abs(psi[(x >= 0.1) & (x <= 0.9)]).min() / np.abs(psi).max()
    assert float(mode.amplitude_dip) == pytest.approx(dip, rel=2e-2)  # at the Gauss points


def test_mode_wavelength_gradient_is_exact(seven):
    """d wavelength / d p of the dominant mode against central differences (psi_1 has no
    zero inside (0, L) at fig. 7d's point)."""
    base = ax.Params(p=300.0, ks=1e6, kl=1e3, cl=1 / 200)
    f = lambda p: ax.dominant_mode(seven, base.with_values({"p": p})).wavelength
    mode = ax.dominant_mode(seven, base)
    assert not wm.is_sensitive(mode.amplitude_dip)
    g = float(jax.grad(f)(jnp.asarray(300.0)))
    h = 1e-3
    fd = (float(f(jnp.asarray(300.0 + h))) - float(f(jnp.asarray(300.0 - h)))) / (2 * h)
    assert g == pytest.approx(fd, rel=1e-5)
