"""Beat-file checks that catch a user's unit mistakes (issue 46): each bad file gets one
line on stderr naming the fix, with exit status 2 (an error) or 0 and an explicit warning
line; valid files of every documented kind and format pass with no warning.

Every beat here is written from closed forms: psi(s, t) = A cos(2 pi f t - 2 pi s /
lambda + phi) (no static part), or the centreline these angles draw.
"""

import json
import re
import warnings

import numpy as np
import pytest
import scipy.io

from axojax.beats import read_beat
from axojax.beats.data import BeatDataWarning
from axojax.cli.main import main

L, N_S, F, FPS, FRAMES, AMP, LAM = 30.0, 31, 20.0, 400.0, 80, 0.5, 25.0


def angles(frames=FRAMES, fps=FPS, f=F, amp=AMP, sign=-1.0):
    """(t, s, psi (T, S)): sign -1 runs base to tip (anterograde)."""
    t = np.arange(frames) / fps
    s = np.linspace(0.0, L, N_S)
    psi = amp * np.cos(2 * np.pi * f * t[:, None] + sign * 2 * np.pi * s[None] / LAM + 0.3)
    return t, s, psi


def points(psi, s, dim):
    """(T, S, dim) centreline drawn by the angles (trapezoid), in 3D turned about x."""
    ds = np.diff(s)[None]

    def integrate(g):
        inc = np.cumsum(ds * 0.5 * (g[:, 1:] + g[:, :-1]), axis=1)
        return np.concatenate([np.zeros((psi.shape[0], 1)), inc], axis=1)

    x, y = integrate(np.cos(psi)), integrate(np.sin(psi))
    if dim == 2:
        return np.stack([x, y], -1)
    a = np.radians(30.0)
    return np.stack([x, y * np.cos(a), y * np.sin(a)], -1)


def csv_text(head, cols, rows):
    body = [",".join(repr(float(v)) if not isinstance(v, int) else str(v) for v in r) for r in rows]
    return "\n".join([*head, ",".join(cols), *body]) + "\n"


def kymograph_csv(path, s=None, psi=None, head=None, frames=None):
    t, s0, psi0 = angles()
    s = s0 if s is None else s
    psi = psi0 if psi is None else psi
    frames = range(psi.shape[0]) if frames is None else frames
    head = [f"# frame_rate_hz = {FPS}", f"# length_um = {L}"] if head is None else head
    rows = [(k, s[j], psi[i, j]) for i, k in enumerate(frames) for j in range(s.size)]
    path.write_text(csv_text(head, ["frame", "s_um", "psi_rad"], rows))
    return path


def fourier_arrays(amp=AMP, s_scale=1.0):
    s = np.linspace(0.0, L, N_S)
    psi1 = amp * np.exp(-2j * np.pi * s / LAM)
    return dict(
        s_um=s * s_scale,
        psi0_rad=0.05 + 0 * s,
        psi1_re_rad=psi1.real,
        psi1_im_rad=psi1.imag,
    )


def fourier_csv(path, amp=AMP, s_scale=1.0, head=None):
    a = fourier_arrays(amp, s_scale)
    head = [f"# length_um = {L * s_scale}", f"# frequency_hz = {F}"] if head is None else head
    rows = list(zip(*(a[k].tolist() for k in a)))
    path.write_text(csv_text(head, list(a), rows))
    return path


def write_valid(kind: str, fmt: str, tmp_path):
    t, s, psi = angles()
    scalars = {"frame_rate_hz": FPS, "length_um": L}
    path = tmp_path / f"{kind}.{fmt}"
    if kind == "fourier":
        arrays = fourier_arrays()
        scalars = {"length_um": L, "frequency_hz": F}
        if fmt == "csv":
            return fourier_csv(path)
    elif kind == "kymograph":
        if fmt == "csv":
            return kymograph_csv(path)
        arrays = {"psi": psi, "s_um": s}
    else:
        pts = points(psi, s, 3 if kind == "centreline-3d" else 2)
        names = ["x_um", "y_um", "z_um"][: pts.shape[-1]]
        if fmt == "csv":
            rows = [(i, *p) for i in range(pts.shape[0]) for p in pts[i].tolist()]
            head = [f"# frame_rate_hz = {FPS}", f"# length_um = {L}"]
            path.write_text(csv_text(head, ["frame", *names], rows))
            return path
        arrays = {n: pts[..., j] for j, n in enumerate(names)}
    if fmt == "npz":
        np.savez(path, **arrays, **scalars)
    else:
        scipy.io.savemat(path, {**arrays, **scalars})
    return path


def run_data(capsys, path, *flags):
    code = main(["data", str(path), *flags])
    out = capsys.readouterr()
    return code, out.out, out.err


KINDS = ["kymograph", "centreline-2d", "centreline-3d", "fourier"]


@pytest.mark.parametrize("fmt", ["csv", "npz", "mat"])
@pytest.mark.parametrize("kind", KINDS)
def test_valid_files_of_every_kind_pass_without_warning(kind, fmt, tmp_path, capsys):
    path = write_valid(kind, fmt, tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        beat = read_beat(path)
    assert not [w for w in caught if issubclass(w.category, BeatDataWarning)]
    assert beat.kind == kind and beat.warnings == ()
    assert beat.dynamic_amplitude_rad == pytest.approx(AMP, rel=0.05)
    code, out, err = run_data(capsys, path)
    assert code == 0 and err == "", err
    assert "direction         anterograde" in out
    doc = json.loads(run_data(capsys, path, "--json")[1])
    assert doc["warnings"] == [] and doc["direction"] == "anterograde"


def one_line_error(capsys, path, *needles):
    """The CLI's stderr: one line naming the file and every needle; exit status 2."""
    code, out, err = run_data(capsys, path)
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 1, err
    assert path.name in lines[0] and all(n in lines[0] for n in needles), lines[0]
    with pytest.raises(ValueError) as info:
        read_beat(path)
    assert "\n" not in str(info.value)
    return lines[0]


def test_unknown_header_key_is_a_warning_naming_the_known_ones(tmp_path, capsys):
    path = kymograph_csv(
        tmp_path / "key.csv",
        head=[f"# frame_rate_hz = {FPS}", "# lenght_um = 30", "# a free-text comment"],
    )
    code, out, err = run_data(capsys, path)
    lines = err.strip().splitlines()
    assert code == 0 and "wavelength" in out and len(lines) == 1, err
    assert lines[0].startswith("axojax: data: warning: ") and "key.csv" in lines[0]
    assert "lenght_um" in lines[0] and "known: frame_rate_hz, length_um" in lines[0]
    doc = json.loads(run_data(capsys, path, "--json")[1])
    assert len(doc["warnings"]) == 1 and "lenght_um" in doc["warnings"][0]
    with pytest.warns(BeatDataWarning, match="lenght_um"):
        read_beat(path)


def test_s_in_mm_warns_of_the_key_then_fails(tmp_path, capsys):
    """The issue's file: s in mm with '# length_mm = 0.03'."""
    t, s, psi = angles()
    path = kymograph_csv(
        tmp_path / "mm.csv", s=s / 1000, head=[f"# frame_rate_hz = {FPS}", "# length_mm = 0.03"]
    )
    code, out, err = run_data(capsys, path)
    lines = err.strip().splitlines()
    assert code == 2 and out == "" and len(lines) == 2, err
    assert "warning" in lines[0] and "length_mm" in lines[0]
    assert "s_um spans 0.03 um: s looks like mm? axojax expects um" in lines[1]


@pytest.mark.parametrize(
    "name, write, needles",
    [
        (
            "fourier_mm.csv",
            lambda p: fourier_csv(p, s_scale=1e-3),
            ["length_um = 0.03 um: looks like mm?"],
        ),
        (
            "kymograph_px.npz",
            lambda p: np.savez(
                p, psi=angles()[2], s_um=angles()[1] * 40, frame_rate_hz=FPS, length_um=1200.0
            ),
            ["length_um = 1.2e+03 um", "pixels or nm?"],
        ),
    ],
)
def test_lengths_no_flagellum_has(name, write, needles, tmp_path, capsys):
    path = tmp_path / name
    write(path)
    one_line_error(capsys, path, *needles, "axojax expects um")


def test_centreline_in_mm(tmp_path, capsys):
    t, s, psi = angles()
    pts = points(psi, s, 2) / 1000
    path = tmp_path / "c_mm.npz"
    np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], frame_rate_hz=FPS)
    one_line_error(capsys, path, "median arc length is 0.03 um", "x_um, y_um look like mm?")
    code, _, err = run_data(capsys, path, "--length-um", "0.03")
    assert code == 2 and "--length-um 0.03 um: looks like mm?" in err


@pytest.mark.parametrize("kind", ["kymograph-csv", "kymograph-npz", "fourier-csv"])
def test_degrees(kind, tmp_path, capsys):
    t, s, psi = angles()
    if kind == "kymograph-csv":
        path = kymograph_csv(tmp_path / "deg.csv", psi=np.degrees(psi))
    elif kind == "kymograph-npz":
        path = tmp_path / "deg.npz"
        np.savez(path, psi=np.degrees(psi), s_um=s, frame_rate_hz=FPS)
    else:
        path = fourier_csv(tmp_path / "deg_modes.csv", amp=np.degrees(AMP))
    line = one_line_error(capsys, path, "psi looks like degrees? axojax expects radians")
    assert "dynamic amplitude 28.6 rad (above pi)" in line


def test_degrees_by_the_swing_within_a_period(tmp_path, capsys):
    """A small dynamic amplitude at most points, a swing over 2 pi at one: |psi_1|."""
    a = fourier_arrays()
    a["psi1_re_rad"][-1] = 3.5
    path = tmp_path / "swing.npz"
    np.savez(path, **a, length_um=L, frequency_hz=F)
    one_line_error(capsys, path, "|psi_1| reaches 3.53 rad", "above 2 pi", "degrees?")
    # A kymograph whose tip swings 7.5 rad within each period, the mean amplitude < pi.
    t, s, psi = angles()
    psi[:, -1] = 3.75 * np.cos(2 * np.pi * F * t)
    path = tmp_path / "swing.npz"
    np.savez(path, psi=psi, s_um=s, frame_rate_hz=FPS)
    one_line_error(capsys, path, "degrees?")


def test_radians_near_the_limits_pass(tmp_path, capsys):
    """A large but real beat (amplitude 2.5 rad), 1.5 um and 400 um long: no error."""
    for amp, scale in ((2.5, 1.0), (0.5, 0.05), (0.5, 400 / L)):
        t, s, psi = angles(amp=amp)
        path = tmp_path / "edge.npz"
        np.savez(path, psi=psi, s_um=s * scale, frame_rate_hz=FPS)
        code, _, err = run_data(capsys, path)
        assert code == 0 and err == "", (amp, scale, err)


def test_missing_header_row(tmp_path, capsys):
    path = tmp_path / "nohead.csv"
    text = kymograph_csv(path).read_text().splitlines()
    path.write_text("\n".join(ln for ln in text if not ln.startswith("frame,")) + "\n")
    line = one_line_error(capsys, path, "no header row", "must name the columns")
    assert "frame,s_um,psi_rad" in line and "s_um,psi0_rad,psi1_re_rad,psi1_im_rad" in line
    assert "more than once" not in line


def test_nan_rows_name_the_frames_and_how_to_drop_them(tmp_path, capsys):
    t, s, psi = angles()
    psi[[5, 6, 40], 3] = np.nan
    psi[7, :] = np.nan
    path = kymograph_csv(tmp_path / "nan.csv", psi=psi)
    line = one_line_error(capsys, path, "NaN", "frames (5, 6, 7, 40)", "delete those frames' rows")
    assert "34 rows of 4 frames" in line
    # Deleting them keeps the others' timing: the frame numbers give the times.
    keep = np.all(np.isfinite(psi), axis=1)
    path = kymograph_csv(tmp_path / "dropped.csv", psi=psi[keep], frames=np.flatnonzero(keep))
    beat = read_beat(path)
    assert beat.frequency_hz == pytest.approx(F, rel=1e-3)
    assert any("4 frame numbers missing" in n for n in beat.notes)
    # Frames-first arrays: which frames, 0-based.
    path = tmp_path / "nan.npz"
    np.savez(path, psi=psi, s_um=s, frame_rate_hz=FPS)
    one_line_error(capsys, path, "4 of 80 frames", "5, 6, 7, 40", "interpolate in time")


@pytest.mark.parametrize("frames, periods, whole", [(20, "1 beat periods", 0), (28, "1.4", 1)])
def test_too_few_cycles_says_what_was_found_and_needed(frames, periods, whole, tmp_path, capsys):
    """One period (20 frames at 400 Hz of a 20 Hz beat) holds no whole cycle between two
    crossings of the beat phase (it starts at phase 0.3); 1.4 periods hold one."""
    t, s, psi = angles(frames=frames)
    path = kymograph_csv(tmp_path / "short.csv", psi=psi)
    line = one_line_error(capsys, path, "too few frames", f"{frames} frames span")
    assert periods in line and f"hold {whole} whole cycle" in line
    assert "need at least 1.5 periods and 1 whole cycle" in line
    # 30 frames at the true 20 Hz; the phase's mean rate over one period is a little off.
    assert int(re.search(r"record at least (\d+) frames", line)[1]) in (30, 31)
    assert read_beat(kymograph_csv(tmp_path / "ok.csv", psi=angles(frames=30)[2])).cycles == 1


def test_data_text_and_plot_agree_on_cycles_and_zero(tmp_path, capsys):
    """60 frames at 600 Hz of a 30 Hz beat with no static part: the whole cycles the
    reduction used are the same in the text and the figure; psi_0's slope is 0."""
    from axojax.plotting.beat_data import plot_beat_data

    t, s, psi = angles(frames=60, fps=600.0, f=30.0)
    path = tmp_path / "k60.npz"
    np.savez(path, psi=psi, s_um=s, frame_rate_hz=600.0)
    beat = read_beat(path)
    code, out, err = run_data(capsys, path, "--plot", str(tmp_path / "k60.png"))
    assert code == 0 and err == ""
    assert f"60 frames, {beat.cycles} whole cycles used" in out
    assert "static curvature  0 rad/um (within its noise" in out
    assert "direction         anterograde (the wave runs base to tip)" in out
    # what the text shows as 0: far below its noise (the spline's 7e-10, not exactly 0)
    assert abs(beat.static_curvature_rad_per_um) < 1e-3 * beat.static_curvature_noise_rad_per_um
    fig = plot_beat_data(beat)
    ax = fig.axes
    assert f"the {beat.cycles} whole cycles used" in ax[3].get_title()
    assert ax[3].get_xlim()[1] < beat.t_s[-1]  # only the cycles used
    assert "slope 0 rad/µm" in ax[0].get_title()
    assert np.ptp(ax[0].get_ylim()) >= 4 * np.median(beat.psi1_sigma) - 1e-12
    labels = [[t.get_text() for t in a.get_legend().get_texts()] for a in ax[:3]]
    assert labels[0] == ["psi_0"] and labels[1] == ["|psi_1|", "1 sigma"]
    assert labels[2][0] == "phase of psi_1"
    # The figure's title clear of the panels' titles.
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    top = fig._suptitle.get_window_extent(renderer)
    for a in ax[:2]:
        assert a.title.get_window_extent(renderer).y1 <= top.y0
    # A wave from tip to base.
    t, s, psi = angles(sign=+1.0)
    np.savez(path, psi=psi, s_um=s, frame_rate_hz=FPS)
    assert "retrograde (the wave runs tip to base)" in run_data(capsys, path)[1]


def test_degrees_past_the_largest_angle_say_degrees(tmp_path, capsys):
    """Angles in degrees beyond |psi| <= 100 (a 143-degree base angle) are refused by the
    size check first: its line names degrees and the fix too, and a valid kymograph with
    the same beat in radians still passes."""
    t, s, psi = angles()
    path = tmp_path / "deg143.npz"
    np.savez(path, psi=np.degrees(psi + 2.5), s_um=s, frame_rate_hz=FPS)
    line = one_line_error(capsys, path, "|psi| <= 100, got 1", "looks like degrees")
    assert "multiply by pi/180" in line
    np.savez(path, psi=psi + 2.5, s_um=s, frame_rate_hz=FPS)
    code, _, err = run_data(capsys, path)
    assert code == 0 and err == "", err
