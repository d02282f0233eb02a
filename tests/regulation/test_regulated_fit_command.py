"""``axojax fit --mechanism M`` for a regulated mechanism (the linear beat): the beat is the
eigenvalue nearest i omega0 (``--omega0-hz``) and the coefficients take the comparison's
bounds (before, the command refused every regulated coefficient: "no bounds"). Checked
against scipy: the fitted coefficients put an eigenvalue of the assembled pencil at
i omega0."""

import json

import numpy as np
import pytest
import scipy.linalg as sl

import axojax as ax
from axojax.assembly import assemble
from axojax.cli.main import main

UNITS = ax.Units()
F_HZ = 30.0


@pytest.mark.slow  # an end-to-end fit (the quick suite within 20 CPU-minutes)
def test_fit_command_puts_the_curvature_controlled_beat_at_the_hopf_point(capsys):
    argv = ["fit", "--model", "two", "--elements", "6", "--p", "0", "--kl", "1000"]
    argv += ["--mechanism", "curvature", "--beta", "1,1", "--omega0-hz", str(F_HZ)]
    argv += ["--free", "beta_re,beta_im", "--target-frequency", str(F_HZ), "--marginal", "1"]
    assert main([*argv, "--no-mesh-check", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    omega0 = float(UNITS.omega0_from_hz(F_HZ))
    params = ax.Params(p=0.0, kl=1000.0, omega0=omega0, **doc["params"])
    system = assemble(ax.models.two(n_elements=6), params)
    lam = sl.eig(-np.asarray(system.A), np.asarray(system.C), right=False)
    assert np.min(np.abs(lam - 1j * omega0)) < 1e-6 * omega0


def test_fit_command_needs_the_beat_frequency_for_a_regulated_mechanism(capsys):
    argv = ["fit", "--model", "two", "--elements", "4", "--mechanism", "curvature"]
    argv += ["--beta", "1,0", "--free", "beta_re", "--target-frequency", "30"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("axojax: error: --mechanism curvature: a fit of regulated dynein")
    assert "--omega0-hz" in err and "\n" not in err
