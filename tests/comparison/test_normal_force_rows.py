"""Normal-force rows of ``compare`` (issue 55 item 1): their static state is the one whose
static curvature is the observed (Sartori's C_0), their beat the augmented pencil's
(:class:`axojax.eigen.NormalForce`), and a row that cannot apply says why.

The beat fitted is made here: the two-filament model on 8 elements, a static moment, and
the normal-force gain at which i omega0 is an eigenvalue, found with scipy on the
assembled pencil (independently of compare's starts and fit); psi_1 of that mode with
0.01 rad of seeded noise, psi_0 of the static state.
"""

import numpy as np
import pytest
import scipy.linalg as sl

import axojax as ax
from axojax.assembly import assemble_normal
from axojax.beats.targets import ShapeTarget
from axojax.dynamics.motors import equilibrium
from axojax.eigen import normal_force_mode
from axojax.inverse.comparison.mechanisms import build_model, row
from axojax.inverse.comparison.static_state import (
    matching_moment,
    not_applicable_reason,
    observed_static_curvature,
)
from axojax.inverse.comparison.synthetic import write_fourier_modes
from axojax.inverse.predictions import model_psi1
from axojax.waveform.shapes import centreline

UNITS = ax.Units(length_um=12.0, ei_pn_um2=400.0, cn_pn_s_um2=0.003)
HZ, ELEMENTS, M0 = 50.0, 8, -20.0
S_UM = np.linspace(0.0, 12.0, 25)
NOISE = 0.01


def _hopf(model, params):
    """The gain of smallest modulus that puts an eigenvalue at i omega0 (scipy)."""
    w = 1j * float(params.omega0)

    def pencil(prm):
        s = assemble_normal(model, prm)
        return np.asarray(s.A) + w * np.asarray(s.C)

    k0 = pencil(params)
    g = sl.eig(k0, k0 - pencil(params.replace(normal_re=1.0)), right=False)
    g = g[np.isfinite(g) & (np.abs(g) < 1e8)]
    return complex(g[np.argmin(np.abs(g))])


def _static_psi0(model, params):
    q0 = equilibrium(model, params.replace(normal_re=0.0, normal_im=0.0), 1.0)
    return np.asarray(centreline(model, q0[None], S_UM / UNITS.length_um, 1))[0, 0]


@pytest.fixture(scope="module")
def beat(tmp_path_factory):
    """(path of the Fourier-mode file, the truth's params, its gain)."""
    model = build_model("two", ELEMENTS, "clamped", UNITS)
    spec = row("normal-force", "clamped", model, UNITS, HZ, params=ax.Params(m0=M0))
    g = _hopf(model, spec.params)
    truth = spec.params.replace(normal_re=g.real, normal_im=g.imag)
    mode = normal_force_mode(model, truth, 1j * float(truth.omega0))
    psi1 = np.asarray(model_psi1(model, mode, S_UM / UNITS.length_um))
    psi1 = 0.6 * psi1 / np.abs(psi1).max() * np.exp(0.4j)
    rng = np.random.default_rng(5)
    psi1 = psi1 + NOISE * (rng.normal(size=S_UM.size) + 1j * rng.normal(size=S_UM.size))
    psi0 = _static_psi0(model, truth) + 0.7 + NOISE / np.sqrt(2) * rng.normal(size=S_UM.size)
    path = tmp_path_factory.mktemp("nf") / "beat.npz"
    write_fourier_modes(path, S_UM, psi1, NOISE, HZ, 12.0, psi0=psi0)
    return path, truth, g


def test_static_curvature_and_its_standard_error_are_weighted_least_squares():
    """The slope and its SE against numpy's weighted polyfit (sigma_psi0 = sigma / sqrt 2)."""
    rng = np.random.default_rng(1)
    sigma = rng.uniform(0.01, 0.05, S_UM.size)
    psi0 = 0.3 - 0.05 * S_UM + sigma * rng.normal(size=S_UM.size)
    shape = ShapeTarget(S_UM, np.ones(S_UM.size, complex), sigma, psi0=psi0)
    c0, se = observed_static_curvature(shape)
    coef, cov = np.polyfit(S_UM, psi0, 1, w=np.sqrt(2.0) / sigma, cov="unscaled")
    assert c0 == pytest.approx(coef[0], rel=1e-10)
    assert se == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-10)


def test_the_matching_moment_gives_the_observed_static_curvature():
    """m0 from matching_moment: the equilibrium (dynamics.motors.equilibrium, another
    assembly path) at that m0 has the observed least-squares slope of psi_0."""
    model = build_model("two", ELEMENTS, "clamped", UNITS)
    spec = row("normal-force", "clamped", model, UNITS, HZ)
    psi0 = 1.1 - 0.08 * S_UM
    shape = ShapeTarget(S_UM, np.ones(S_UM.size, complex), 0.01, psi0=psi0)
    m0 = matching_moment(model, spec.params, shape, UNITS)
    got = _static_psi0(model, spec.params.replace(m0=m0))
    assert np.polyfit(S_UM, got, 1)[0] == pytest.approx(-0.08, rel=1e-8)


def test_rows_without_a_static_bend_or_off_the_clamped_base_say_why():
    flat = ShapeTarget(S_UM, np.ones(S_UM.size, complex), 0.05, psi0=0.2 + 1e-4 * S_UM)
    bent = ShapeTarget(S_UM, np.ones(S_UM.size, complex), 0.05, psi0=0.2 - 0.1 * S_UM)
    assert "no static normal force" in not_applicable_reason("normal-force", "clamped", flat)
    assert "standard errors" in not_applicable_reason("sliding+normal-force", "clamped", flat)
    assert "clamped base only" in not_applicable_reason("normal-force", "free", bent)
    assert not_applicable_reason("normal-force", "clamped", bent) is None
    assert not_applicable_reason("sliding", "free", flat) is None


@pytest.mark.slow  # the longest quick test (29 s): the quick suite within 20 CPU-minutes
def test_compare_fits_the_normal_force_row_that_made_the_beat(beat):
    """The normal-force row converges with R^2 > 0.99 and its gain within 3 standard
    errors of the truth (the row's reported errors, which hold the measured static
    curvature's: psi_1 and the pins alone fix g m0, the pins alone would pin g);
    sliding+normal-force
    contains it and sliding, and fits at least as well as each (0.01); the free base's
    normal-force rows are not_applicable with the reason."""
    path, truth, g = beat
    result = ax.compare(
        path,
        mechanisms=["sliding", "normal-force", "sliding+normal-force"],
        bases=["clamped", "free"],
        compliance=False,
        n_elements=ELEMENTS,
        units=UNITS,
        starts=2,
    )
    rows = {(r.mechanism, r.base): r for r in result.rows}
    nf = rows[("normal-force", "clamped")]
    assert nf.successful, nf.reason
    assert nf.r2 > 0.99
    for name, want in (("normal_re", g.real), ("normal_im", g.imag)):
        se = nf.physical_stderr[name]  # the data's and the measured static curvature's
        assert name not in nf.pinned and se > 0  # the pins alone would pin it
        assert abs(nf.params[name] - want) <= 3 * se, (name, nf.params, g, se)
    both = rows[("sliding+normal-force", "clamped")]
    assert both.r2 >= max(nf.r2, rows[("sliding", "clamped")].r2) - 0.01
    for mech in ("normal-force", "sliding+normal-force"):
        r = rows[(mech, "free")]
        assert r.status == "not_applicable" and "clamped base only" in r.reason
    doc = result.to_json()
    assert any(r["status"] == "not_applicable" for r in doc["rows"])
    assert "sliding+normal-force" in result.table()
    line = next(
        x for x in result.table(params=True).splitlines() if "normal-force on clamped:" in x
    )
    assert "g' " in line and "g'' " in line and "+-" in line  # the gain with its error
