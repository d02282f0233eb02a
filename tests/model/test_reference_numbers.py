"""The numbers of docs/model.md section 6, and an independent re-implementation check."""

import numpy as np
import pytest
import scipy.linalg
import scipy.optimize

import axojax as ax
from axojax.eigen.mode import dominant_mode
from tests.conftest import scipy_dominant, scipy_max_real


def agrees(value, stated: str):
    """``value`` equals the number written ``stated`` to its last stated digit (half a
    unit), i.e. relative error < 1e-6 wherever the stated digits allow it."""
    decimals = len(stated.split(".")[1]) if "." in stated else 0
    return abs(value - float(stated)) <= 0.5 * 10.0**-decimals


def test_single_p300():
    mode = dominant_mode(ax.models.single(), ax.Params(p=300.0))
    lam = complex(mode.eigenvalue)
    assert agrees(lam.real, "4360.456") and agrees(lam.imag, "1865.222")
    assert abs(lam - complex(4360.456, 1865.222)) < 1e-6 * abs(lam)
    assert agrees(float(mode.frequency_hz()), "347.06")  # paper fig. 7a: 347 Hz


def test_two_p300():
    lam = complex(dominant_mode(ax.models.two(), ax.Params(p=300.0, kl=1e3, cl=1 / 200)).eigenvalue)
    assert agrees(lam.real, "3566.50") and agrees(lam.imag, "294.07")


def test_seven_p300(seven):
    """docs/model.md section 6 (paper fig. 7d: 51 Hz; sec. 3.6: out of plane < 5 %)."""
    mode = dominant_mode(seven, ax.Params(p=300.0, ks=1e6, kl=1e3, cl=1 / 200))
    lam = complex(mode.eigenvalue)
    assert agrees(lam.real, "137.696") and agrees(lam.imag, "270.311"), lam
    assert agrees(float(mode.frequency_hz()), "50.30")
    # docs/model.md's 20.72 um is the retired displacement form; the wavelength (psi_1's,
    # 31.7 um) is checked against scipy and numpy in tests/waveform/test_waveform_measures.py
    k_u = float(ax.eigen.displacement_wavenumber(seven, mode.eigenvector))
    assert agrees(2 * np.pi / abs(k_u) * ax.Units().length_um, "20.72")
    assert int(mode.direction) == 1  # anterograde
    assert agrees(float(mode.out_of_plane_ratio), "0.022")


def test_nine_p300():
    mode = dominant_mode(ax.models.nine(), ax.Params(p=300.0, ks=1e6, kl=1e3, cl=1 / 200))
    lam = complex(mode.eigenvalue)
    assert agrees(lam.real, "368.453") and agrees(lam.imag, "402.720"), lam
    assert agrees(float(mode.frequency_hz()), "74.93")


def test_four_equals_two():
    """The two pairs of the square moving in step is an exact mode (docs/model.md section 6)."""
    params = ax.Params(p=300.0, ks=1e6, kl=1e3, cl=1 / 200)
    four = dominant_mode(ax.models.four(), params)
    two = complex(dominant_mode(ax.models.two(), params).eigenvalue)
    assert abs(complex(four.eigenvalue) - two) < 1e-9 * abs(two), (four.eigenvalue, two)
    assert agrees(float(four.frequency_hz()), "54.72")


@pytest.mark.parametrize(
    "ks,pc_ref", [(1e3, "66.9"), (1e4, "88.8"), (1e5, "136.6"), (1e6, "249.8")]
)
def test_seven_critical_force_scipy(seven, ks, pc_ref):
    """p_c of the seven preset at k_l = k_s / 1e3 (docs/model.md section 6), by scipy's brentq on
    scipy.linalg.eig; the stable checks below it make sure the root is the first crossing."""
    params = ax.Params(ks=ks, kl=ks / 1e3)
    growth = lambda p: scipy_max_real(seven, params.replace(p=p)).real
    ref = float(pc_ref)
    assert all(growth(f * ref) < 0 for f in (0.1, 0.5, 0.9))
    pc = scipy.optimize.brentq(growth, 0.995 * ref, 1.005 * ref, xtol=1e-4)
    assert agrees(pc, pc_ref), pc


def hopf(model, lo, hi):
    f = lambda p: scipy_max_real(model, ax.Params(p=p)).real
    pc = scipy.optimize.brentq(f, lo, hi, xtol=1e-10)
    return pc, abs(scipy_max_real(model, ax.Params(p=pc)).imag)


@pytest.mark.parametrize("name,pc_ref,om_ref", [("single", 76.10, 196.59), ("beck", 37.70, 191.26)])
def test_hopf_points_converged_mesh(name, pc_ref, om_ref):
    pc, om = hopf(ax.models.preset(name, n_elements=40), 20.0, 120.0)
    assert agrees(pc, f"{pc_ref:.2f}"), pc
    assert agrees(om, f"{om_ref:.2f}"), om


def independent_two(p, kl, cl, ne=10):
    """The two-filament model assembled from textbook element matrices (no axojax code)."""
    h = 1 / ne
    g, w = np.polynomial.legendre.leggauss(6)
    n = 2 * (ne + 1)
    M0, K0, G0, F0 = (np.zeros((n, n)) for _ in range(4))
    for e in range(ne):
        xi = (g + 1) / 2
        x = e * h + xi * h
        N = np.array(
            [
                1 - 3 * xi**2 + 2 * xi**3,
                h * (xi - 2 * xi**2 + xi**3),
                3 * xi**2 - 2 * xi**3,
                h * (xi**3 - xi**2),
            ]
        )
        dN = (
            np.array(
                [
                    6 * xi**2 - 6 * xi,
                    h * (1 - 4 * xi + 3 * xi**2),
                    6 * xi - 6 * xi**2,
                    h * (3 * xi**2 - 2 * xi),
                ]
            )
            / h
        )
        ddN = np.array([12 * xi - 6, h * (6 * xi - 4), 6 - 12 * xi, h * (6 * xi - 2)]) / h**2
        sl = slice(2 * e, 2 * e + 4)
        ww = w * h / 2
        M0[sl, sl] += (N * ww) @ N.T
        K0[sl, sl] += (ddN * ww) @ ddN.T
        G0[sl, sl] += (dN * ww * (1 - x)) @ dN.T
        F0[sl, sl] += (N * ww) @ dN.T
    M0, K0, G0, F0 = (a[2:, 2:] for a in (M0, K0, G0, F0))
    BB = np.array([[1.0, -1.0], [-1.0, 1.0]])
    A = np.kron(np.eye(2), K0) + kl * np.kron(BB, M0) + np.kron(np.diag([-p, p]), G0)
    A -= p * np.kron(np.array([[-0.5, -0.5], [0.5, 0.5]]), F0)
    C = np.kron(np.eye(2), M0) + cl * np.kron(BB, M0)
    lam = scipy.linalg.eig(-A, C, right=False)
    top = lam[np.argmax(lam.real)]
    return complex(top.real, abs(top.imag))


@pytest.mark.parametrize("p,kl,cl", [(300.0, 1e3, 1 / 200), (150.0, 50.0, 0.1), (500.0, 1e4, 1e-3)])
def test_two_matches_independent_assembly(p, kl, cl):
    ours = complex(dominant_mode(ax.models.two(), ax.Params(p=p, kl=kl, cl=cl)).eigenvalue)
    ref = independent_two(p, kl, cl)
    assert abs(ours - ref) < 1e-7 * abs(ref)


@pytest.mark.parametrize(
    "name,params",
    [
        ("single", ax.Params(p=120.0)),
        ("beck", ax.Params(p=50.0)),
        ("four", ax.Params(p=300.0)),
        ("seven", ax.Params(p=300.0)),
        ("seven", ax.Params(p=250.0, ks=1e4, kl=10.0, gamma=-1.0, ktheta=5.0)),
        ("nine", ax.Params(p=200.0, ks=1e5, kl=100.0, cl=0.05)),
    ],
)
def test_dominant_matches_scipy(name, params):
    model = ax.models.preset(name)
    ours = complex(dominant_mode(model, params).eigenvalue)
    ref = scipy_dominant(model, params)
    assert abs(ours - ref) < 1e-8 * max(1.0, abs(ref))
