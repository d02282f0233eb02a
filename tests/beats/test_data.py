"""Beat data in (issue 19): the bundled human sperm beat, Fourier-mode files, 3D
centrelines and their planarity, MATLAB files, honest uncertainties, the basal stretch,
``axojax data`` and one-line errors naming the file.

References are independent of the reduction: the data's authors' frequency
(``HF_Freq`` = 10.257 Hz, stored beside the frames), numbers put into synthetic files and
computed here in closed form from the functions that made them.
"""

import json

import numpy as np
import pytest
import scipy.io

import axojax as ax
from axojax.beats import read_beat
from axojax.beats.reduction import FREQUENCY_REL_FLOOR, PLANARITY_THRESHOLD, PSI1_FLOOR_RAD
from axojax.cli.main import main

L = 30.0
S = np.linspace(0.0, L, 61)
F = 12.5
# psi0 = a + b s + c (s - L/2)^2: on a grid symmetric about L/2 its least-squares slope is b.
A0, B0, C0 = 0.1, -0.02, 4e-4
# psi1 = (m0 + m1 s / L) exp(-i k s + i phi): |psi1| linear (trapezoidal mean m0 + m1 / 2),
# phase slope -k (wavelength 2 pi / k).
M0, M1, K, PHI = 0.4, 0.5, 2 * np.pi / 45.0, 0.3


def psi0_true(s):
    return A0 + B0 * s + C0 * (s - L / 2) ** 2


def psi1_true(s):
    return (M0 + M1 * s / L) * np.exp(-1j * K * s + 1j * PHI)


def run_cli(capsys, *argv):
    code = main(["data", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def write_fourier_csv(path, frequency=True, length=True):
    head = []
    if length:
        head.append(f"# length_um = {L}")
    if frequency:
        head += [f"# frequency_hz = {F}", "# frequency_sigma_hz = 0.3"]
    p1 = psi1_true(S)
    rows = [
        f"{float(s)!r},{float(a)!r},{float(b.real)!r},{float(b.imag)!r}"
        for s, a, b in zip(S, psi0_true(S), p1)
    ]
    path.write_text("\n".join(head + ["s_um,psi0_rad,psi1_re_rad,psi1_im_rad"] + rows) + "\n")
    return path


def test_bundled_human_sperm_frequency(capsys):
    raw = np.load(ax.datasets.path("human_sperm"))
    published = float(raw["published_frequency_hz"])
    assert published == pytest.approx(10.257, abs=1e-3)  # HF_Freq of the source repository
    code, out, _ = run_cli(capsys, "human_sperm", "--json")
    doc = json.loads(out)
    assert code == 0
    assert doc["frequency_hz"] == pytest.approx(10.26, abs=0.1)
    assert doc["frequency_hz"] == pytest.approx(published, abs=0.1)
    # Honest: at least the 1 % floor, and not a shrug either.
    assert (
        FREQUENCY_REL_FLOOR * doc["frequency_hz"]
        <= doc["frequency_sigma_hz"]
        < 0.05 * doc["frequency_hz"]
    )
    for key in (
        "file",
        "kind",
        "length_um",
        "frequency_hz",
        "frequency_sigma_hz",
        "wavelength_um",
        "static_curvature_rad_per_um",
        "dynamic_amplitude_rad",
        "planarity",
    ):
        assert key in doc
    assert doc["kind"] == "centreline-3d"
    # The point cloud itself (independent SVD here): clearly non-planar.
    pts = np.stack([raw["x_um"], raw["y_um"], raw["z_um"]], -1).astype(float)
    rel = (pts - pts[:, :1]).reshape(-1, 3)
    sv = np.linalg.svd(rel - rel.mean(0), compute_uv=False)
    assert doc["planarity"]["ratios"]["s3_over_s2"] == pytest.approx(sv[2] / sv[1], rel=1e-6)
    assert not doc["planarity"]["planar"]
    lengths = np.linalg.norm(np.diff(pts, axis=1), axis=-1).sum(1)
    assert doc["length_um"] == pytest.approx(np.median(lengths), rel=1e-9)
    beat = ax.datasets.human_sperm()
    assert beat.out_of_plane is not None and beat.cycles >= 25


@pytest.mark.parametrize("fmt", ["csv", "npz"])
def test_fourier_file_gives_back_every_number(tmp_path, fmt, capsys):
    if fmt == "csv":
        path = write_fourier_csv(tmp_path / "modes.csv")
    else:
        p1 = psi1_true(S)
        path = tmp_path / "modes.npz"
        np.savez(
            path,
            s_um=S,
            psi0_rad=psi0_true(S),
            psi1_re_rad=p1.real,
            psi1_im_rad=p1.imag,
            length_um=L,
            frequency_hz=F,
            frequency_sigma_hz=0.3,
        )
    code, out, _ = run_cli(capsys, str(path), "--json")
    assert code == 0
    doc = json.loads(out)
    assert doc["kind"] == "fourier" and doc["planarity"] is None
    assert doc["length_um"] == pytest.approx(L, rel=1e-12)
    assert doc["frequency_hz"] == pytest.approx(F, rel=1e-12)
    assert doc["frequency_sigma_hz"] == pytest.approx(0.3, rel=1e-12)
    # the least-squares slope of the unwrapped phase (numpy's unwrap and polyfit on the 61
    # points): the wave's phase is linear, so both give the continuous wave's 2 pi / K
    p1 = psi1_true(S)
    k = np.polyfit(S, np.unwrap(np.angle(p1)), 1)[0]
    assert doc["wavelength_um"] == pytest.approx(2 * np.pi / abs(k), rel=1e-9)
    assert doc["wavelength_um"] == pytest.approx(2 * np.pi / K, rel=1e-9)
    assert doc["static_curvature_rad_per_um"] == pytest.approx(B0, rel=1e-9)
    assert doc["dynamic_amplitude_rad"] == pytest.approx(M0 + M1 / 2, rel=1e-9)
    beat = read_beat(path)
    np.testing.assert_allclose(beat.modes.psi1, psi1_true(S), atol=1e-12)
    targets, shape = beat.targets()
    assert targets[0].value == F and np.allclose(shape.psi0, psi0_true(S))


def test_fourier_file_without_frequency_says_so(tmp_path, capsys):
    path = write_fourier_csv(tmp_path / "modes.csv", frequency=False)
    code, out, _ = run_cli(capsys, str(path), "--json")
    doc = json.loads(out)
    assert code == 0 and doc["frequency_hz"] is None and doc["frequency_sigma_hz"] is None
    assert any("--target-frequency" in n for n in doc["notes"])
    freq_targets, shape = read_beat(path).targets()
    assert freq_targets == [] and shape.psi1.shape == S.shape
    # Length from the command line when the file lacks it; a conflicting one is an error.
    nolen = write_fourier_csv(tmp_path / "nolen.csv", length=False)
    code, out, err = run_cli(capsys, str(nolen), "--length-um", "30", "--json")
    assert code == 0 and json.loads(out)["length_um"] == 30.0
    code, out, err = run_cli(capsys, str(path), "--length-um", "31")
    assert code == 2 and "modes.csv" in err and "--length-um" in err and err.count("\n") == 1


def kymograph(fps, seconds, noise, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(int(fps * seconds)) / fps
    psi = psi0_true(S)[None] + np.real(psi1_true(S)[None] * np.exp(2j * np.pi * F * t)[:, None])
    return t, psi + noise * rng.normal(size=psi.shape)


def test_kymograph_recovers_modes_with_honest_sigmas(tmp_path):
    # Noisy: the psi_1 sigma is the scatter of per-cycle estimates, which for white noise
    # of sd n over N samples is n sqrt(2 / N) per real/imaginary part.
    fps, seconds, noise = 100.0, 2.0, 0.3
    t, psi = kymograph(fps, seconds, noise)
    path = tmp_path / "k.npz"
    np.savez(path, psi=psi, s_um=S, frame_rate_hz=fps, length_um=L)
    beat = read_beat(path)
    assert beat.frequency_hz == pytest.approx(F, abs=2 * beat.frequency_sigma_hz)
    expected = noise * np.sqrt(2.0 / (beat.cycles / F * fps))
    assert 0.6 * expected < np.median(beat.psi1_sigma) < 1.6 * expected
    # Phase reference is arbitrary: align, then every point within 4 sigma of the truth.
    rot = np.vdot(beat.modes.psi1, psi1_true(S))
    psi1 = beat.modes.psi1 * rot / abs(rot)
    assert np.all(np.abs(psi1 - psi1_true(S)) < 4 * np.sqrt(2) * beat.psi1_sigma)
    # Clean and tiled (zero scatter): the floors speak, never a 0.01 Hz precision.
    t, psi = kymograph(200.0, 2.0, 0.0)
    clean = ax.beats.beat_from_kymograph(t, S, psi)
    assert clean.frequency_hz == pytest.approx(F, rel=1e-3)
    assert clean.frequency_sigma_hz == pytest.approx(
        FREQUENCY_REL_FLOOR * clean.frequency_hz, rel=1e-9
    )
    assert np.all(clean.psi1_sigma >= PSI1_FLOOR_RAD)
    assert clean.wavelength_um == pytest.approx(2 * np.pi / K, rel=1e-3)
    assert clean.static_curvature_rad_per_um == pytest.approx(B0, rel=1e-3)


def helix_points(planar: bool, noise: float, frames=120, fps=100.0, seed=0):
    """Points (T, P, 3): a wave along x with transverse y (and z when not planar: a
    helical wave), turned by a fixed rotation, plus noise (um)."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0, 40.0, 60)
    t = np.arange(frames)[:, None] / fps
    arg = 2 * np.pi * (x / 35.0 - 8.0 * t)
    env = 4.0 * x / 40.0
    y = env * np.sin(arg)
    z = np.zeros_like(y) if planar else env * np.cos(arg)
    pts = np.stack([np.broadcast_to(x, y.shape), y, z], -1)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return pts @ q.T + noise * rng.normal(size=pts.shape), fps


@pytest.mark.parametrize("planar", [True, False])
def test_3d_centreline_planarity_decision(tmp_path, planar):
    pts, fps = helix_points(planar, noise=0.05)
    path = tmp_path / "c.npz"
    np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], z_um=pts[..., 2], frame_rate_hz=fps)
    beat = read_beat(path)
    assert beat.kind == "centreline-3d"
    assert beat.planarity.planar is planar
    assert (beat.planarity.ratio < PLANARITY_THRESHOLD) is planar
    assert beat.frequency_hz == pytest.approx(8.0, abs=2 * beat.frequency_sigma_hz)
    assert (beat.out_of_plane is None) is planar
    if planar:
        # The best plane recovers the beat plane: the same psi_1 amplitude as the
        # unrotated 2D centreline.
        flat, _ = helix_points(True, noise=0.0)
        q = np.linalg.qr(np.random.default_rng(0).normal(size=(3, 3)))[0]
        xy = flat @ q  # undo the rotation
        np.savez(tmp_path / "c2.npz", x_um=xy[..., 0], y_um=xy[..., 1], frame_rate_hz=fps)
        ref = read_beat(tmp_path / "c2.npz")
        np.testing.assert_allclose(np.abs(beat.modes.psi1), np.abs(ref.modes.psi1), atol=0.03)
    else:
        # A helical wave: both transverse components beat with comparable amplitude.
        a, b = beat.dynamic_amplitude_rad, float(np.mean(np.abs(beat.out_of_plane[0].psi1)))
        assert 0.5 < a / b < 2.0
        assert len(beat.shape_targets()) == 2


def test_mat_files_with_named_variables_and_cells(tmp_path):
    pts, fps = helix_points(False, noise=0.05)
    cells = {c: np.empty((1, 3), dtype=object) for c in "XYZ"}
    for c in cells.values():
        for i in range(3):
            c[0, i] = np.zeros((0, 0))
    for j, c in enumerate("XYZ"):
        cells[c][0, 1] = pts[..., j].T  # MATLAB style: (points, frames)
    path = tmp_path / "cells.mat"
    scipy.io.savemat(path, {**cells, "frame_rate_hz": fps})
    a = read_beat(path)
    np.savez(
        tmp_path / "same.npz",
        x_um=pts[..., 0],
        y_um=pts[..., 1],
        z_um=pts[..., 2],
        frame_rate_hz=fps,
    )
    b = read_beat(tmp_path / "same.npz")
    assert a.frequency_hz == pytest.approx(b.frequency_hz, rel=1e-6)
    np.testing.assert_allclose(a.modes.psi1, b.modes.psi1, atol=1e-5)
    # Renamed variables, frames first.
    _, psi = kymograph(100.0, 2.0, 0.05)
    path = tmp_path / "kymo.mat"
    scipy.io.savemat(path, {"angles": psi, "fps": 100.0, "s_um": S, "length_um": L})
    beat = read_beat(path, variables={"psi": "angles", "frame_rate_hz": "fps"})
    assert beat.frequency_hz == pytest.approx(F, abs=2 * beat.frequency_sigma_hz)
    # Two filled cells: choose one, else a one-line error naming the file.
    for c in "XYZ":
        cells[c][0, 2] = cells[c][0, 1]
    scipy.io.savemat(tmp_path / "two.mat", {**cells, "frame_rate_hz": fps})
    with pytest.raises(ValueError, match="two.mat.*cell=") as info:
        read_beat(tmp_path / "two.mat")
    assert "\n" not in str(info.value)
    assert read_beat(tmp_path / "two.mat", cell=2).frequency_hz == pytest.approx(
        a.frequency_hz, rel=1e-9
    )


def test_exclude_base(tmp_path):
    path = write_fourier_csv(tmp_path / "modes.csv")
    beat = read_beat(path)
    cut = beat.exclude_base(5.0)
    assert cut.s_um[0] >= 5.0 - 1e-12 and cut.s_um[-1] == L
    assert cut.s_um.size == np.sum(S >= 5.0) and cut.excluded_base_um == 5.0
    np.testing.assert_allclose(cut.modes.psi1, psi1_true(S[S >= 5.0]))
    assert cut.targets()[1].s_um.size == cut.s_um.size
    with pytest.raises(ValueError, match="leaves"):
        beat.exclude_base(L - 0.1)
    with pytest.raises(ValueError, match=">= 0"):
        beat.exclude_base(-1.0)


def test_plot(tmp_path, capsys):
    path = write_fourier_csv(tmp_path / "modes.csv")
    out = tmp_path / "fig.png"
    code, text, _ = run_cli(capsys, str(path), "--plot", str(out))
    assert code == 0 and out.stat().st_size > 10_000 and "wavelength" in text


@pytest.mark.parametrize(
    "name, content, problem",
    [
        ("missing.csv", None, "does not exist"),
        ("beat.txt", "1,2,3\n", "unknown format"),
        ("bad.npz", "not a zip", "cannot read"),
        ("bad.mat", "not matlab", "cannot read"),
        ("nolen.csv", "s_um,psi0_rad,psi1_re_rad,psi1_im_rad\n0,0,0.1,0\n1,0,0.1,0\n", "length_um"),
        ("odd.csv", "# length_um = 3\nfoo,bar\n1,2\n", "missing column"),
        (
            "nan.csv",
            "# length_um = 3\ns_um,psi0_rad,psi1_re_rad,psi1_im_rad\n0,0,nan,0\n1,0,0.1,0\n",
            "NaN",
        ),
        ("empty.npz", "", "cannot read"),
        (
            "dup.csv",
            "# length_um = 3\ns_um,psi0_rad,psi1_re_rad,psi1_im_rad,psi1_im_rad\n0,0,0.1,0,1\n1,0,0.1,0,1\n",
            "psi1_im_rad appear more than once",
        ),
        (
            "frames.npz",
            lambda p: np.savez(
                p, x_um=np.zeros((0, 8)), y_um=np.zeros((0, 8)), frame_rate_hz=100.0
            ),
            "x_um is empty",
        ),
        (
            "complex.npz",
            lambda p: np.savez(
                p, x_um=np.ones((5, 8)) + 1j, y_um=np.ones((5, 8)), frame_rate_hz=100.0
            ),
            "x_um is complex",
        ),
        (
            "rate.csv",
            "# frame_rate_hz = 1e308\nframe,x_um,y_um\n"
            + "".join(f"{f},{k},{0.1 * f * k}\n" for f in range(3) for k in range(5)),
            "outside",
        ),
    ],
)
def test_bad_files_give_one_line_naming_the_file(tmp_path, capsys, name, content, problem):
    path = tmp_path / name
    if callable(content):
        content(path)
    elif content is not None:
        path.write_text(content)
    with pytest.raises(ValueError, match=problem) as info:
        read_beat(path)
    assert name in str(info.value) and "\n" not in str(info.value)
    code, out, err = run_cli(capsys, str(path), "--json")
    assert code == 2 and out == "" and name in err and err.count("\n") == 1


def test_csv_3d_centreline_and_frame_rate_flag(tmp_path, capsys):
    pts, fps = helix_points(True, noise=0.05, frames=60)
    rows = [f"{k},{x!r},{y!r},{z!r}" for k in range(pts.shape[0]) for x, y, z in pts[k].tolist()]
    path = tmp_path / "c3.csv"
    path.write_text("frame,x_um,y_um,z_um\n" + "\n".join(rows) + "\n")
    # No frame rate in the file: the flag gives it; without it, a one-line error.
    code, _, err = run_cli(capsys, str(path))
    assert code == 2 and "frame_rate_hz" in err and "c3.csv" in err
    code, out, _ = run_cli(capsys, str(path), "--frame-rate-hz", str(fps), "--json")
    doc = json.loads(out)
    np.savez(
        tmp_path / "c3.npz", x_um=pts[..., 0], y_um=pts[..., 1], z_um=pts[..., 2], frame_rate_hz=fps
    )
    ref = read_beat(tmp_path / "c3.npz")
    assert code == 0 and doc["kind"] == "centreline-3d" and doc["planarity"]["planar"]
    assert doc["frequency_hz"] == pytest.approx(ref.frequency_hz, rel=1e-9)
    # A frame rate in the file and a different one on the command line: an error.
    code, _, err = run_cli(capsys, str(tmp_path / "c3.npz"), "--frame-rate-hz", str(2 * fps))
    assert code == 2 and "conflicts" in err and "--frame-rate-hz" in err


def test_kymograph_wavelength_is_the_phase_slope(tmp_path, capsys):
    """Issue 44's acceptance: ``axojax data`` on a kymograph reports the wavelength of the
    least-squares slope of psi_1's unwrapped phase: an independent numpy unwrap + polyfit
    of the true psi_1 agrees within 1 %, on a beat whose phase turns unevenly and whose
    amplitude varies, where the retired |psi_1|^2-weighted mean gradient is 20 % off."""
    s = np.linspace(0.0, L, 61)
    amp = 0.1 + 0.6 * (s / L) ** 2  # small near the base, where the phase turns fastest
    phase = -2.4 * np.sqrt(s / L + 0.05) * 2 * np.pi
    psi1 = amp * np.exp(1j * phase)
    fps, seconds = 200.0, 2.0
    t = np.arange(int(fps * seconds)) / fps
    psi = np.real(psi1[None] * np.exp(2j * np.pi * F * t)[:, None])
    psi = psi + 0.01 * np.random.default_rng(4).normal(size=psi.shape)
    path = tmp_path / "uneven.npz"
    np.savez(path, psi=psi, s_um=s, frame_rate_hz=fps, length_um=L)
    code, out, _ = run_cli(capsys, str(path), "--json")
    assert code == 0
    reported = json.loads(out)["wavelength_um"]
    k = np.polyfit(s, np.unwrap(np.angle(psi1)), 1)[0]
    assert reported == pytest.approx(2 * np.pi / abs(k), rel=0.01)
    dpsi = np.gradient(psi1, s)
    k_weighted = np.trapezoid(np.imag(np.conj(psi1) * dpsi), s) / np.trapezoid(np.abs(psi1) ** 2, s)
    assert abs(2 * np.pi / abs(k_weighted) / reported - 1) > 0.2
