"""The "sensitive wavelength" flag on every report that prints a wavelength (``axojax
data``, ``orbit`` and ``simulate``; ``modes`` in tests/waveform/test_waveform_measures.py): a beat
whose psi_1 nearly vanishes inside the flagellum gets ``amplitude_dip`` and
``wavelength_sensitive: true`` in its JSON and a note after the wavelength on the
terminal; a smooth travelling wave is not flagged.

The beats are closed forms: psi_1(x) = A (x - 0.45 + 0.02 i) exp(-i k x) (a near-node at
x = 0.45 L) and A (0.3 + 0.7 x) exp(-i k x) (smooth), x = s / L. Every reference dip is
min / max of |psi_1| over the middle 80 % of the samples, in numpy. The orbit and the
simulation are stand-ins carrying these psi_1 (their solves take far longer than a test
may): the commands' own measures, JSON and text run on them unchanged.
"""

import json

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax
import axojax.orbits
import axojax.orbits.branch
from axojax.beats import read_beat
from axojax.cli.main import main
from axojax.dynamics.simulate import Simulation, settled_modes, waveform_measures
from axojax.orbits.cycle import LimitCycle
from axojax.orbits.measures import cycle_measures
from axojax.waveform.measures import SENSITIVE_DIP
from tests.comparison.test_compare import fourier_file as write_fourier_file

L_UM, F_HZ, K = 30.0, 20.0, 2 * np.pi / 0.6  # k per unit of x: wavelength 0.6 L = 18 um
NOTE = "(sensitive: |psi_1| dips to"
TWO = ax.models.two(n_elements=4)


def node(x):
    """psi_1 with a near-node at x = 0.45 (rad)."""
    return 0.8 * (x - 0.45 + 0.02j) * np.exp(-1j * K * x)


def smooth(x):
    """A travelling wave growing towards the tip (rad)."""
    return 0.5 * (0.3 + 0.7 * x) * np.exp(-1j * K * x)


def reference_dip(s, psi1):
    """min / max |psi_1| over the middle 80 % of s."""
    s, a = np.asarray(s, float), np.abs(np.asarray(psi1))
    lo, hi = s.min(), s.max()
    inside = (s >= lo + 0.1 * (hi - lo)) & (s <= hi - 0.1 * (hi - lo))
    return a[inside].min() / a.max()


def fourier_file(path, psi1_of):
    x = np.linspace(0.0, 1.0, 41)
    psi1 = psi1_of(x)
    return write_fourier_file(path, x, psi1, L_UM, F_HZ), x * L_UM, psi1


@pytest.mark.parametrize("shape,flagged", [(node, True), (smooth, False)], ids=["node", "smooth"])
def test_data_flags_a_near_node(tmp_path, capsys, shape, flagged):
    path, s, psi1 = fourier_file(tmp_path / "beat.npz", shape)
    dip = reference_dip(s, psi1)
    assert (dip < SENSITIVE_DIP) == flagged
    beat = read_beat(path)
    summary = beat.summary()
    assert summary["amplitude_dip"] == pytest.approx(dip, rel=1e-12)
    assert summary["wavelength_sensitive"] is flagged
    assert summary["components"][0]["amplitude_dip"] == summary["amplitude_dip"]
    assert main(["data", path, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["wavelength_um"] is not None  # the node's turn of pi shortens it (12.6 um)
    assert flagged or doc["wavelength_um"] == pytest.approx(0.6 * L_UM, rel=0.05)
    assert doc["amplitude_dip"] == pytest.approx(dip, rel=1e-12)
    assert doc["wavelength_sensitive"] is flagged
    assert main(["data", path]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if "  wavelength " in ln)
    assert (NOTE in line) == flagged
    if flagged:
        assert f"dips to {dip:.2g} of its maximum" in line


def test_data_components_of_the_bundled_sperm(capsys):
    """The bundled human sperm (3D, not planar): its in-plane psi_1 dips to 0.091 and its
    out-of-plane one to 0.055, both flagged, each on its own line (and the in-plane one on
    the wavelength's). (The in-plane dip was 0.12, not flagged, while psi_1 was a
    least-squares fit in the beat phase rather than the time average: issue 54.)"""
    beat = ax.datasets.human_sperm()
    ref = {
        "in_plane": reference_dip(beat.s_um, beat.modes.psi1),
        "out_of_plane": reference_dip(beat.s_um, beat.out_of_plane[0].psi1),
    }
    assert SENSITIVE_DIP > ref["in_plane"] > ref["out_of_plane"]
    assert main(["data", "human_sperm", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    comps = {c["name"]: c for c in doc["components"]}
    for name, dip in ref.items():
        assert comps[name]["amplitude_dip"] == pytest.approx(dip, rel=1e-12)
        assert comps[name]["wavelength_sensitive"] is bool(dip < SENSITIVE_DIP)
    assert doc["amplitude_dip"] == comps["in_plane"]["amplitude_dip"]
    assert doc["wavelength_sensitive"] is True
    assert main(["data", "human_sperm"]) == 0
    lines = capsys.readouterr().out.splitlines()
    for start in ("  wavelength ", "  in-plane ", "  out-of-plane "):
        line = next(ln for ln in lines if ln.startswith(start))
        assert NOTE in line
    assert f"dips to {ref['in_plane']:.2g} " in next(
        ln for ln in lines if ln.startswith("  in-plane ")
    )
    assert f"dips to {ref['out_of_plane']:.2g} " in next(
        ln for ln in lines if ln.startswith("  out-of-plane ")
    )


def stand_in_cycle(model, shape) -> LimitCycle:
    """A converged, stable orbit of ``model`` whose psi_1 is ``shape`` (zero coefficients:
    the tip trace is only the out-of-plane measure's, 0 here)."""
    n, a = model.n_dof, jnp.asarray
    return LimitCycle(
        model=model,
        coefficients=jnp.zeros((3, n)),
        omega=a(0.3),
        amplitude=a(0.1),
        beat_angle=a(0.0),
        wavenumber=a(-K),
        floquet=a([1.0 + 0j, 0.5 + 0j]),
        converged=a(True),
        started=a(True),
        steps=a(3),
        correction=a(0.0),
        linear_eigenvalue=a(0.01 + 0.3j),
        phase_ref=jnp.zeros(n),
    )


@pytest.fixture
def orbit_of(monkeypatch):
    """Set the stand-in orbit's psi_1 (``orbit_of(shape)``); the solves return it."""
    held = {}
    monkeypatch.setattr(
        LimitCycle,
        "tangent_modes",
        lambda self, x: (jnp.zeros(np.shape(x)), jnp.asarray(held["shape"](np.asarray(x)))),
    )
    monkeypatch.setattr(
        axojax.orbits, "limit_cycle", lambda model, *a, **k: stand_in_cycle(model, held["shape"])
    )
    monkeypatch.setattr(axojax.orbits.branch, "hopf_point", lambda *a, **k: (100.0, 0.3j))

    def continue_to(model, params, kappa, solver, p_targets, p_hopf=None, callback=None):
        out = []
        for p in p_targets:
            out.append(stand_in_cycle(model, held["shape"]))
            callback(float(p), out[-1])
        return out

    monkeypatch.setattr(axojax.orbits.branch, "continue_to", continue_to)
    return lambda shape: held.update(shape=shape)


ORBIT = ["orbit", "--model", "two", "--elements", "4", "--length-um", str(L_UM)]


@pytest.mark.parametrize("shape,flagged", [(node, True), (smooth, False)], ids=["node", "smooth"])
def test_orbit_flags_a_near_node(orbit_of, capsys, shape, flagged):
    orbit_of(shape)
    s = np.linspace(0.0, L_UM, 41)
    dip = reference_dip(s, shape(s / L_UM))
    m = cycle_measures(stand_in_cycle(TWO, shape), None, ax.Units(length_um=L_UM))
    assert float(m.amplitude_dip) == pytest.approx(dip, rel=1e-12)
    assert m.scalars()["wavelength_sensitive"] is flagged
    for p in (["--p", "300"], ["--p", "200:300:2"]):  # one orbit, and a branch
        assert main([*ORBIT, *p, "--json"]) == 0
        orbits = json.loads(capsys.readouterr().out)["orbits"]
        assert len(orbits) == (1 if p[1] == "300" else 2)
        for o in orbits:
            assert o["wavelength_um"] == pytest.approx(0.6 * L_UM)
            assert o["amplitude_dip"] == pytest.approx(dip, rel=1e-12)
            assert o["wavelength_sensitive"] is flagged
        assert main([*ORBIT, *p]) == 0
        rows = capsys.readouterr().out.splitlines()[-len(orbits) :]
        assert all((NOTE in r) == flagged for r in rows)


def test_orbit_without_a_wavelength_is_not_flagged(orbit_of):
    """A standing wave (no wavelength) is not flagged, however deep its dip."""
    orbit_of(node)
    cycle = stand_in_cycle(TWO, node)
    standing = eqx.tree_at(lambda c: c.wavenumber, cycle, jnp.asarray(0.0))
    scalars = cycle_measures(standing).scalars()
    assert scalars["amplitude_dip"] < SENSITIVE_DIP and not np.isfinite(scalars["wavelength_um"])
    assert scalars["wavelength_sensitive"] is False


def settled(shape):
    """The simulation's measures of a beat psi = Re(psi_1 exp(i omega t)) sampled over
    four periods (the settled modes of its last two), and psi_1 on its points."""
    period = 1.0 / F_HZ
    t = np.arange(161) * period / 40
    s = np.linspace(0.0, L_UM, 41)
    psi1 = shape(s / L_UM)
    psi = np.real(psi1[None] * np.exp(2j * np.pi * F_HZ * t[:, None]))
    modes = settled_modes(t, s, psi, period)
    return waveform_measures(modes), s, psi1


@pytest.mark.parametrize("shape,flagged", [(node, True), (smooth, False)], ids=["node", "smooth"])
def test_simulate_flags_a_near_node(monkeypatch, capsys, shape, flagged):
    waveform, s, psi1 = settled(shape)
    dip = reference_dip(s, psi1)
    assert waveform["amplitude_dip"] == pytest.approx(dip, rel=1e-6)
    assert waveform["wavelength_sensitive"] is flagged
    assert waveform["wavelength_um"] is not None
    assert flagged or waveform["wavelength_um"] == pytest.approx(0.6 * L_UM, rel=0.05)
    run = Simulation(
        t_s=np.zeros(1),
        x_um=s,
        centreline_um=np.zeros((1, 1, s.size)),
        psi_rad=np.zeros((1, s.size)),
        tip_um=np.zeros((1, 1)),
        beat_angle_rad=0.0,
        state="limit_cycle",
        limit_cycle={"frequency_hz": F_HZ, "period_s": 1 / F_HZ, "tip_amplitude_um": 2.0}
        | waveform
        | {"cycles": 4},
        linear={"frequency_hz": F_HZ, "growth_rate_per_s": 1.0, "classification": "flutter"},
        meta={"solver": {"name": "stand-in", "ok": True, "steps": 1, "t_reached_s": 0.2}},
    )
    monkeypatch.setattr("axojax.cli.simulate.simulate", lambda *a, **k: run)
    argv = ["simulate", "--model", "two", "--elements", "4", "--t-end", "0.2", "--max-steps", "10"]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["waveform"]["amplitude_dip"] == pytest.approx(dip, rel=1e-6)
    assert doc["waveform"]["wavelength_sensitive"] is flagged
    assert main(argv) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("waveform:"))
    assert (NOTE in line) == flagged


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_fit_reports_the_achieved_modes_dip(capsys):
    """`axojax fit`: the achieved mode's amplitude_dip in the JSON (the dominant mode's at the
    fitted values), and the note on the terminal exactly when it is below SENSITIVE_DIP."""
    argv = ["fit", "--model", "two", "--elements", "6", "--p", "160", "--free", "p"]
    argv += ["--target-frequency", "20", "--starts", "1"]
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    dip = doc["achieved"]["amplitude_dip"]
    model = ax.models.two(6)
    mode = ax.dominant_mode(model, ax.Params(p=doc["params"]["p"]))
    assert dip == pytest.approx(float(mode.amplitude_dip), rel=1e-9)
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert ("sensitive:" in out) == (dip < SENSITIVE_DIP)
