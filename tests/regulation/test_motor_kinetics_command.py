"""``axojax modes --motor-tau-ms`` (issue 47, item 1's first step on the command line): a
regulated beat with an active friction keeps its eigenvalue at i omega0 and gets a
spectrum bounded above, where without motor kinetics the dominant mode is a spurious
short wave growing faster than the beat's frequency."""

import json
import math

import numpy as np

import axojax as ax
from axojax.cli.main import main
from tests.regulation.test_motor_kinetics import A0, W0, _hopf


def test_modes_with_motor_kinetics(capsys):
    units = ax.Units()
    params = _hopf(
        ax.models.two(n_elements=8), ax.Params(p=0.0, a0=A0, omega0=W0), "chi", -1.3e5 - 1.8e5j
    )
    chi = complex(params.chi_re, params.chi_im) * units.ei_pn_um2 / units.length_um**4  # pN/um^2
    f_hz = W0 / (2 * math.pi * units.tau_s)
    assert chi.imag < 0  # an active friction
    argv = ["modes", "--model", "two", "--elements", "8", "--p", "0", "--mechanism", "sliding"]
    argv += ["--chi", f"{chi.real!r},{chi.imag!r}", "--omega0-hz", repr(f_hz), "--top", "3"]
    assert main([*argv, "--motor-tau-ms", "5", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    m = doc["motor_kinetics"]
    omega = 2 * math.pi * f_hz  # 1/s
    beat = complex(*m["beat"]["eigenvalue"]) / units.tau_s
    assert abs(beat - 1j * omega) < 1e-6 * omega  # the Hopf point scipy found, kept
    assert m["max_growth_rate_per_s"] < 0.02 * omega  # bounded: nothing grows much faster
    assert doc["dominant"]["growth_rate_per_s"] > omega  # without: a spurious fast mode
    assert np.isclose(m["tau_m"], 5e-3 / units.tau_s)
    assert main([*argv, "--motor-tau-ms", "5"]) == 0
    assert "with motor kinetics (tau_m = 5 ms)" in capsys.readouterr().out


def test_motor_kinetics_needs_a_regulated_beat(capsys):
    code = main(["modes", "--model", "two", "--elements", "4", "--motor-tau-ms", "5"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--motor-tau-ms" in err
    code = main(["modes", "--model", "two", "--elements", "4", "--motor-tau-ms", "-1"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "--motor-tau-ms" in err
    regulated = ["--p", "0", "--mechanism", "sliding", "--chi=-469,-625", "--omega0-hz", "186"]
    code = main(
        ["modes", "--model", "two", "--elements", "4", *regulated, "--motor-tau-ms", "1e300"]
    )
    err = capsys.readouterr().err  # beyond float64's digits: refused, not a traceback
    assert code == 2 and err.count("\n") == 1 and "--motor-tau-ms" in err and "tau_m" in err
