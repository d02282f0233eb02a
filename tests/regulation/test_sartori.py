"""Sartori et al. (eLife 5:e13258, 2016), wild-type Chlamydomonas axonemes: their published
curvature-control fit is a Hopf point of axojax's two-filament model.

Their Table 1: chi' = 19.8 nN/um^2, chi'' = 0, beta' = 0, beta'' = -6.5 nN, basal impedance
chi_b = 42.2 + 2.2i nN/um, L = 11.7 um, omega = 427 rad/s (68 Hz); free-free axonemes with
basal compliance. The material constants of their fitting code (the authors' AxonemeFits,
github.com/JHowardLab/AxonemeFits, parameters.m): kappa = 400 pN um^2, a = 0.06 um,
xi_n = 0.0034 pN s/um^2. In the two-filament limit (docs/model.md section 8) kappa = 2 EI,
xi_n = 2 c_n, a = a0 L, and chi_b = k_b + i omega xi_b. With these published numbers only,
the eigenvalue of axojax's ``two`` preset nearest i omega must sit at i omega (growth ~ 0,
68 Hz) with a wave travelling from base to tip, as their fits' psi_1 does (its phase
decreases along s, their fig. 3), and the amplitude dips at mid-length (their fig. 3).

This checks the whole chain at once: the sign rule of section 8 (a published chi, beta
means the same in axojax; their e^{+i omega t} convention is ours), the free base, the
basal compliance's force balance chi_b Delta_b = -int f ds, and the units.
"""

import numpy as np
import pytest

import axojax as ax
from axojax.models import Base
from axojax.waveform.shapes import centreline

L_UM, KAPPA, A_UM, XI_N, OMEGA = 11.7, 400.0, 0.06, 0.0034, 427.0
UNITS = ax.Units(length_um=L_UM, ei_pn_um2=KAPPA / 2, cn_pn_s_um2=XI_N / 2)
CHI_B_NN_PER_UM = 42.2 + 2.2j


def _params() -> ax.Params:
    omega0 = float(UNITS.omega0_from_hz(OMEGA / (2 * np.pi)))
    return ax.Params(
        p=0.0,
        a0=A_UM / L_UM,
        chi_re=float(UNITS.chi_from_pn_per_um2(19.8e3)),
        beta_im=float(UNITS.beta_from_pn(-6.5e3)),
        omega0=omega0,
        kb=float(UNITS.kb_from_pn_per_um(CHI_B_NN_PER_UM.real * 1e3)),
        xib=float(UNITS.xib_from_pn_s_per_um(CHI_B_NN_PER_UM.imag * 1e3 / OMEGA)),
    )


@pytest.mark.parametrize("n_elements", [8, 16])
def test_sartori_wild_type_fit_is_a_hopf_point(n_elements):
    params = _params()
    model = ax.models.two(n_elements=n_elements, base=Base("free", compliance=True))
    mode = ax.nearest_mode(model, params, 1j * float(params.omega0))
    ratio = complex(mode.eigenvalue) / float(params.omega0)
    # chi_b is fitted to ~30 % (42.2 +- 12 nN/um): the Hopf point is reproduced to 0.5 %
    assert abs(ratio - 1j) < 5e-3, ratio
    assert int(mode.direction) == 1  # base to tip
    s = np.linspace(0, 1, 21)
    psi = centreline(model, np.asarray(mode.eigenvector), s, derivative=1)[0]
    amplitude = np.abs(psi) / np.abs(psi).max()
    assert amplitude[10] < 0.7 * min(amplitude[0], amplitude[-1])
    phase = np.unwrap(np.angle(psi))
    assert phase[-1] - phase[0] < -np.pi  # the phase falls along s: base-to-tip


def test_the_opposite_beta_sign_is_not_a_hopf_point():
    """beta'' = +6.5 nN (the sign a flipped convention would give) is no Hopf point: the
    nearest eigenvalue is several times farther from i omega than the published fit's
    tolerance above, and decays by over a fifth per period."""
    params = _params()
    params = params.replace(beta_im=-float(params.beta_im))
    model = ax.models.two(n_elements=8, base=Base("free", compliance=True))
    mode = ax.nearest_mode(model, params, 1j * float(params.omega0))
    ratio = complex(mode.eigenvalue) / float(params.omega0)
    assert abs(ratio - 1j) > 0.02 and np.exp(2 * np.pi * ratio.real) < 0.8
