"""``axojax fit --data FILE`` on every documented beat format (issue 32): Fourier modes
(``.csv`` and ``.npz``), kymographs (``.csv`` and ``.npz``), 2D and 3D centrelines and
MATLAB ``.mat`` files. A Fourier-mode file has no frames, and the fit used to refuse it
("needs at least 3 arc-length points per frame, got 0") while ``axojax data`` read it.

Every file holds the same beat: the two-filament model's own dominant mode at p = 170
(a travelling wave, computed here by ``ax.dominant_mode``), written as psi_1(s) or as
frames psi(s, t) = psi_0 + Re(psi_1 e^{i omega t}) or as the centreline these angles
draw. A fit of p from p = 160 must come back to the frequency within its sigma (exit 0)
and find p near 170: the data are the model itself, so every format reduces to the same
targets.
"""

import json

import numpy as np
import pytest
import scipy.io

import axojax as ax
from axojax.cli.main import main
from axojax.inverse.predictions import model_psi1

L = 12.0  # um: the default length, so the model's units are the data's
P_TRUE = 170.0
N_S = 25
FPS = 400.0
FRAMES = 120


@pytest.fixture(scope="module")
def wave():
    """psi_0 (S,), psi_1 (S,) (rad, amplitude 0.5) on s (S,) um and the frequency (Hz)."""
    model = ax.models.two(n_elements=4)
    mode = ax.dominant_mode(model, ax.Params(p=P_TRUE))
    f = float(mode.frequency_hz())
    assert f > 5  # a travelling wave, not a divergence
    s = np.linspace(0.0, L, N_S)
    psi1 = np.asarray(model_psi1(model, mode, s / L))
    psi1 = 0.5 * psi1 / np.abs(psi1).max()
    return dict(s=s, psi0=0.05 + 0.0 * s, psi1=psi1, f=f)


def frames(w):
    t = np.arange(FRAMES) / FPS
    return w["psi0"][None] + np.real(w["psi1"][None] * np.exp(2j * np.pi * w["f"] * t)[:, None])


def centreline(w, dim: int):
    """(T, S, dim) points of the frames' angles: x' = cos psi, y' = sin psi (trapezoid);
    in 3D the plane is turned about x by 30 degrees."""
    psi = frames(w)
    ds = np.diff(w["s"])[None]
    x = np.concatenate(
        [
            np.zeros((FRAMES, 1)),
            np.cumsum(ds * 0.5 * (np.cos(psi[:, 1:]) + np.cos(psi[:, :-1])), 1),
        ],
        1,
    )
    y = np.concatenate(
        [
            np.zeros((FRAMES, 1)),
            np.cumsum(ds * 0.5 * (np.sin(psi[:, 1:]) + np.sin(psi[:, :-1])), 1),
        ],
        1,
    )
    if dim == 2:
        return np.stack([x, y], -1)
    a = np.radians(30.0)
    return np.stack([x, y * np.cos(a), y * np.sin(a)], -1)


def write(kind: str, w, tmp_path):
    s, psi0, psi1, f = w["s"], w["psi0"], w["psi1"], w["f"]
    if kind == "fourier-csv":
        path = tmp_path / "modes.csv"
        rows = [
            f"{a},{b},{c.real},{c.imag}"
            for a, b, c in zip(s.tolist(), psi0.tolist(), psi1.tolist())
        ]
        head = [f"# length_um = {L}", f"# frequency_hz = {f}"]
        path.write_text("\n".join(head + ["s_um,psi0_rad,psi1_re_rad,psi1_im_rad", *rows]) + "\n")
    elif kind == "fourier-npz":
        path = tmp_path / "modes.npz"
        np.savez(
            path,
            s_um=s,
            psi0_rad=psi0,
            psi1_re_rad=psi1.real,
            psi1_im_rad=psi1.imag,
            length_um=L,
            frequency_hz=f,
        )
    elif kind == "kymograph-csv":
        path = tmp_path / "kymo.csv"
        psi = frames(w)
        rows = [f"{i},{s[j]},{psi[i, j]}" for i in range(FRAMES) for j in range(N_S)]
        head = [f"# frame_rate_hz = {FPS}", f"# length_um = {L}"]
        path.write_text("\n".join(head + ["frame,s_um,psi_rad", *rows]) + "\n")
    elif kind == "kymograph-npz":
        path = tmp_path / "kymo.npz"
        np.savez(path, psi=frames(w), s_um=s, frame_rate_hz=FPS, length_um=L)
    elif kind == "centreline-2d":
        path = tmp_path / "c2.npz"
        pts = centreline(w, 2)
        np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], frame_rate_hz=FPS, length_um=L)
    elif kind == "centreline-3d":
        path = tmp_path / "c3.csv"
        pts = centreline(w, 3)
        rows = [f"{i},{p[0]},{p[1]},{p[2]}" for i in range(FRAMES) for p in pts[i].tolist()]
        head = [f"# frame_rate_hz = {FPS}", f"# length_um = {L}"]
        path.write_text("\n".join(head + ["frame,x_um,y_um,z_um", *rows]) + "\n")
    elif kind == "mat":
        path = tmp_path / "c.mat"
        pts = centreline(w, 2)  # MATLAB style: (points, frames)
        scipy.io.savemat(
            path, {"X": pts[..., 0].T, "Y": pts[..., 1].T, "frame_rate_hz": FPS, "length_um": L}
        )
    return path


KINDS = {
    "fourier-csv": "fourier",
    "fourier-npz": "fourier",
    "kymograph-csv": "kymograph",
    "kymograph-npz": "kymograph",
    "centreline-2d": "centreline-2d",
    "centreline-3d": "centreline-3d",
    "mat": "centreline-2d",
}


@pytest.mark.parametrize("kind", list(KINDS))
def test_fit_data_reads_every_documented_format(kind, wave, tmp_path, capsys):
    path = write(kind, wave, tmp_path)
    argv = ["--model", "two", "--elements", "4", "--free", "p", "--p", "160", "--starts", "1"]
    code = main(["fit", "--no-mesh-check", *argv, "--data", str(path), "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    doc = json.loads(out)
    assert doc["data"]["kind"] == KINDS[kind]
    assert doc["data"]["frequency_hz"] == pytest.approx(wave["f"], rel=0.01)
    assert doc["converged"] is True
    # The data are the model's own mode at P_TRUE: the fit finds it.
    assert doc["params"]["p"] == pytest.approx(P_TRUE, rel=0.01)
    achieved = doc["conditions"][0]["achieved"]["frequency_hz"]
    assert achieved == pytest.approx(wave["f"], rel=0.02)


def test_fit_data_fourier_csv_of_the_issue(tmp_path, capsys):
    """The file of the report: 44 points over 60 um at 21 Hz, no frames. ``axojax data``
    and ``axojax fit --data`` read it alike; the fit (whatever it reaches) reports."""
    s = np.linspace(0.0, 60.0, 44)
    psi1 = 0.4 * np.exp(-2j * np.pi * s / 30.0)
    rows = [f"{a},0.1,{c.real},{c.imag}" for a, c in zip(s.tolist(), psi1.tolist())]
    path = tmp_path / "beat.csv"
    path.write_text(
        "\n".join(
            ["# length_um = 60", "# frequency_hz = 21", "s_um,psi0_rad,psi1_re_rad,psi1_im_rad"]
            + rows
        )
        + "\n"
    )
    assert main(["data", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    code = main(
        [
            "fit",
            "--no-mesh-check",
            "--model",
            "two",
            "--elements",
            "4",
            "--free",
            "p",
            "--starts",
            "1",
            "--data",
            str(path),
            "--json",
        ]
    )
    out, err = capsys.readouterr()
    assert code in (0, 1), err
    doc = json.loads(out)
    assert doc["data"]["n_points"] == data["n_points"] == 44
    assert doc["data"]["frequency_hz"] == 21.0 and doc["problem"] is not None


@pytest.mark.parametrize(
    "content, problem",
    [
        (
            "s_um,psi0_rad,psi1_re_rad,psi1_im_rad\n0,0,0.1,0\n6,0,0.1,0.1\n",
            "at least 3 points of s_um",
        ),
        ("s_um,psi0_rad,psi1_re_rad,psi1_im_rad\n0,0,1e300,0\n6,0,0.1,0\n12,0,0,0\n", "|psi| <="),
    ],
)
def test_fourier_file_no_fit_can_use_is_one_line(content, problem, tmp_path, capsys):
    """Too few points or angles that are not radians: refused by the reader for ``axojax
    data`` and ``axojax fit`` alike, one line naming the file."""
    path = tmp_path / "bad.csv"
    path.write_text("# length_um = 12\n# frequency_hz = 20\n" + content)
    for argv in (
        ["data", str(path)],
        ["fit", "--model", "two", "--free", "p", "--data", str(path)],
    ):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "bad.csv" in err[0] and problem in err[0], err
