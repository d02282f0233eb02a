"""3D beats reduced in 3D (issue 33): a non-planar centreline's two transverse components
about the beat frame, each with its wavelength (``BeatData.components``, ``axojax data``),
and 3D models fitted to both with one complex scale.

References are independent of axojax's reduction: the wavenumber put into a synthetic
helix, the bundled sperm re-reduced here in plain numpy (a Fourier projection at the
beat frequency, not axojax's per-cycle phase fit), and the model's own parameters for
the fits.
"""

import dataclasses
import json

import numpy as np
import pytest

import axojax as ax
from axojax.beats import ShapeTarget, join_components, read_beat
from axojax.beats.reduction import beat_frame
from axojax.cli.main import main
from axojax.inverse import Condition, Problem, least_squares
from axojax.inverse.predictions import model_psi1
from axojax.plotting.beat_data import plot_beat_data
from axojax.plotting.fit_report import plot_fit_report

L_UM = 45.0
WAVELENGTH_UM = 25.0
K = 2 * np.pi / WAVELENGTH_UM
F_HZ = 10.0
FPS = 90.0  # 9 frames a cycle, as the bundled sperm (90 frames/s at 10.3 Hz)


def random_rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))  # proper: a mirror would change the beat's chirality


def helix_record(a_um, b_um, bend_per_um=0.0, cycles=4, noise_um=0.0, seed=0):
    """A travelling helical wave along a straight base axis x: y = A(s) cos(k x - w t),
    z = B(s) sin(k x - w t) + c x^2 (an optional static bend out of the plane of largest
    motion), A(s), B(s) growing from 30 % at the base; rotated in space. (T, P, 3) um."""
    x = np.linspace(0.0, L_UM, 81)
    t = np.arange(int(cycles * FPS / F_HZ) + 1)[:, None] / FPS
    env = 0.3 + 0.7 * x / L_UM
    arg = K * x - 2 * np.pi * F_HZ * t
    y = a_um * env * np.cos(arg)
    z = b_um * env * np.sin(arg) + bend_per_um * x**2
    pts = np.stack([np.broadcast_to(x, y.shape), y, z], -1)
    rng = np.random.default_rng(seed)
    return pts @ random_rotation(seed).T + noise_um * rng.normal(size=pts.shape)


def save(tmp_path, pts, name="c.npz"):
    path = tmp_path / name
    np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], z_um=pts[..., 2], frame_rate_hz=FPS)
    return path


@pytest.mark.parametrize(
    "a_um,b_um,bend",
    [(0.8, 0.8, 0.0), (1.0, 0.5, 0.0), (1.0, 0.5, 0.005)],
    ids=["circular", "elliptical", "elliptical-bent"],
)
def test_helical_beat_recovers_both_wavelengths(tmp_path, a_um, b_um, bend):
    """Both components' wavelengths within 5 % of 2 pi / k (the amplitudes keep the
    arc length within 2 % of the axial coordinate, A k <= 0.25), on the frequency put in.
    With the static bend the wave, k per unit of x, is measured along the arc: its
    wavelength there is 2 pi / k times the |psi_1|^2-weighted ds/dx of the bent axis,
    int w ds / int w dx, w = A(x)^2 (here 1.049; 1 without the bend)."""
    x = np.linspace(0.0, L_UM, 4001)
    w = (0.3 + 0.7 * x / L_UM) ** 2
    ds_dx = np.sqrt(1 + (2 * bend * x) ** 2)
    expected = WAVELENGTH_UM * np.trapezoid(w * ds_dx, x) / np.trapezoid(w, x)
    beat = read_beat(save(tmp_path, helix_record(a_um, b_um, bend, noise_um=0.02)))
    assert not beat.planarity.planar and beat.out_of_plane is not None
    assert beat.frequency_hz == pytest.approx(F_HZ, abs=2 * beat.frequency_sigma_hz)
    comps = {c["name"]: c for c in beat.components}
    assert list(comps) == ["in_plane", "out_of_plane"]
    for c in comps.values():
        assert c["wavelength_um"] == pytest.approx(expected, rel=0.05)
        assert c["wavenumber_rad_per_um"] < 0  # base to tip
    # wavelength_um stays: the in-plane component's.
    assert beat.summary()["wavelength_um"] == comps["in_plane"]["wavelength_um"]
    assert beat.summary()["components"] == beat.components
    # Amplitude ratio of the two components ~ B / A (small angles: psi ~ k A(s)).
    ratio = (
        comps["out_of_plane"]["dynamic_amplitude_rad"] / comps["in_plane"]["dynamic_amplitude_rad"]
    )
    assert ratio == pytest.approx(b_um / a_um, rel=0.1)


def test_beat_frame_is_the_base_axis_not_the_chord(tmp_path):
    """With a static bend (tip turned ~0.45 rad out of the plane of largest motion) the
    point cloud's long axis tilts towards the chord; the beat frame's e1 stays on the
    base axis and e2 on the direction of largest motion (y before the rotation), and
    the frame is right-handed."""
    q = random_rotation(0)
    pts = helix_record(1.0, 0.5, bend_per_um=0.005, noise_um=0.0)
    frame, ratio = beat_frame(pts)
    np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(frame) == pytest.approx(1.0)
    base_axis, motion = q[:, 0], q[:, 1]
    assert np.degrees(np.arccos(frame[0] @ base_axis)) < 2.0
    assert np.degrees(np.arccos(abs(frame[1] @ motion))) < 2.0
    assert ratio == pytest.approx(0.5, rel=0.05)  # B / A of the displacement
    cloud = ax.beats.reduction.planarity(pts).axes[0]
    assert np.degrees(np.arccos(abs(cloud @ base_axis))) > 5.0


def test_planar_beats_reduce_as_before(tmp_path):
    """A planar 3D record (and a 2D one) keep one component: no frame, no out-of-plane
    part, the joint shape target is the in-plane one, the same psi_1 as the unrotated 2D
    record (the best plane, as before)."""
    q = random_rotation(3)
    flat = helix_record(1.0, 0.0, seed=3) @ q  # undo the rotation: z = 0
    beat3 = read_beat(save(tmp_path, helix_record(1.0, 0.0, seed=3)))
    np.savez(tmp_path / "c2.npz", x_um=flat[..., 0], y_um=flat[..., 1], frame_rate_hz=FPS)
    beat2 = read_beat(tmp_path / "c2.npz")
    for beat in (beat2, beat3):
        assert beat.out_of_plane is None
        assert [c["name"] for c in beat.components] == ["in_plane"]
        assert beat.components[0]["wavelength_um"] == beat.wavelength_um
        target = beat.joint_shape_target()
        assert target.component == "in_plane"
        np.testing.assert_array_equal(target.psi1, beat.targets()[1].psi1)
    assert beat3.planarity.planar and beat3.planarity.frame is None
    assert beat3.planarity.as_dict()["frame"] is None
    # The sign of the best plane's normal is free: compare psi_1 up to sign.
    p3, p2 = beat3.modes.psi1, beat2.modes.psi1
    sign = np.sign(np.real(np.vdot(p2, p3)))
    np.testing.assert_allclose(p3, sign * p2, atol=1e-6)
    assert beat3.wavelength_um == pytest.approx(beat2.wavelength_um, rel=1e-6)
    assert beat2.wavelength_um == pytest.approx(WAVELENGTH_UM, rel=0.05)


def independent_sperm_reduction() -> dict:
    """The bundled sperm re-reduced in plain numpy, from the definitions (module docstring
    of axojax.beats.reduction: the beat frame; docs/model.md: the least-squares slope of
    psi_1's unwrapped phase), with different estimators: the beat frequency from a 16x zero-padded
    FFT peak, psi_1 = the Fourier coefficient at that frequency over a whole number of
    cycles (not a per-cycle fit on the beat phase), angles interpolated at each frame's
    arc-length fraction (held, not extrapolated, at the ends), the phase slope by numpy's
    unwrap and an unweighted polyfit."""
    raw = np.load(ax.datasets.path("human_sperm"))
    pts = np.stack([raw["x_um"], raw["y_um"], raw["z_um"]], -1).astype(float)
    fps = float(raw["frame_rate_hz"])
    n_frames, n_pts, _ = pts.shape
    d = np.diff(pts, axis=1)
    seg = np.linalg.norm(d, axis=-1)
    tangent = d / seg[..., None]
    e1 = tangent[:, : round(0.1 * (n_pts - 1))].mean(axis=(0, 1))
    e1 /= np.linalg.norm(e1)
    rel = pts - pts[:, :1]
    osc = rel - rel.mean(axis=0)
    osc -= (osc @ e1)[..., None] * e1
    e2 = np.linalg.eigh(np.einsum("tpi,tpj->ij", osc, osc))[1][:, -1]
    e3 = np.cross(e1, e2)
    frac = (np.cumsum(seg, 1) - seg / 2) / seg.sum(1, keepdims=True)
    grid = np.linspace(0.0, 1.0, 41)
    s = grid * float(np.median(seg.sum(1)))
    angles = {}
    for name, e in (("in_plane", e2), ("out_of_plane", e3)):
        a = np.unwrap(np.arctan2(d @ e, d @ e1), axis=1)
        angles[name] = np.stack([np.interp(grid, frac[k], a[k]) for k in range(n_frames)])
    x = np.concatenate([a - a.mean(0) for a in angles.values()], axis=1)
    n_fft = 16 * n_frames
    power = (np.abs(np.fft.rfft(x, n=n_fft, axis=0)) ** 2).sum(1)
    freq = np.fft.rfftfreq(n_fft, 1 / fps)
    power[freq < 2.0] = 0.0
    f = freq[np.argmax(power)]
    n = int(np.floor(int(n_frames * f / fps) * fps / f))  # whole cycles
    t = np.arange(n) / fps
    out = {"frequency_hz": f}
    for name, a in angles.items():
        c = 2 * np.mean(a[:n] * np.exp(-2j * np.pi * f * t)[:, None], axis=0)
        k = np.polyfit(s, np.unwrap(np.angle(c)), 1)[0]
        out[name] = 2 * np.pi / abs(k)
    return out


def test_bundled_sperm_wavelengths_against_an_independent_reduction(capsys):
    """Both reported wavelengths within 15 % of the independent reduction's. Tolerance:
    axojax's psi_1 is the first harmonic in the beat phase theta(t), phase-aligned cycle
    by cycle; the independent one is the Fourier coefficient at one fixed frequency over
    3 s, which a beat whose phase speed varies within and between cycles (period scatter
    ~2 %) blurs: the two estimates differ by 9 % in-plane and 5 % out-of-plane here (the
    same psi_1 fed to both wavenumber formulas agrees to 0.1 %). Both put the out-of-plane
    wavelength under half the in-plane one, which is over twice the flagellum."""
    ref = independent_sperm_reduction()
    beat = ax.datasets.human_sperm()
    assert ref["frequency_hz"] == pytest.approx(beat.frequency_hz, abs=2 * beat.frequency_sigma_hz)
    comps = {c["name"]: c["wavelength_um"] for c in beat.components}
    for name in ("in_plane", "out_of_plane"):
        assert comps[name] == pytest.approx(ref[name], rel=0.15), name
    assert comps["out_of_plane"] < 0.5 * comps["in_plane"]
    assert ref["out_of_plane"] < 0.5 * ref["in_plane"]
    assert comps["in_plane"] > 2 * beat.length_um
    # The command line: the extra JSON keys, and one text line per component.
    assert main(["data", "human_sperm", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [c["name"] for c in doc["components"]] == ["in_plane", "out_of_plane"]
    assert doc["wavelength_um"] == pytest.approx(doc["components"][0]["wavelength_um"])
    assert doc["planarity"]["frame"] is not None and 0 < doc["planarity"]["frame_ratio"] < 1
    assert main(["data", "human_sperm"]) == 0
    text = capsys.readouterr().out
    assert f"out-of-plane      wavelength {comps['out_of_plane']:.4g} um" in text
    assert "(in-plane component)" in text
    assert "flagellum         kappa 1900 pN um^2, xi_n 0.0032 pN s/um^2" in text
    assert doc["flagellum"]["normal_drag_pn_s_um2"] == 3.2e-3
    # The figure: a wavelength slope per component.
    fig = plot_beat_data(beat)
    labels = [t.get_text() for t in fig.axes[2].get_legend().get_texts()]
    assert f"slope: wavelength {comps['out_of_plane']:.3g} µm (out of plane)" in labels
    assert f"slope: wavelength {comps['in_plane']:.3g} µm (in plane)" in labels


def test_shape_target_components_validated():
    s = np.linspace(0, 10, 5)
    with pytest.raises(ValueError, match="unknown shape component 'sideways'"):
        ShapeTarget(s, np.ones(5, complex), 0.1, component="sideways")
    with pytest.raises(ValueError, match="one name or one per point"):
        ShapeTarget(s, np.ones(5, complex), 0.1, component=("in_plane",) * 4)
    with pytest.raises(ValueError, match="limit-cycle shape is in-plane only"):
        ShapeTarget(
            s,
            np.ones(5, complex),
            0.1,
            psi0=np.zeros(5),
            source="limit_cycle",
            component="out_of_plane",
        )
    joint = join_components(
        [
            ShapeTarget(s, np.ones(5, complex), 0.1),
            ShapeTarget(s, 2j * np.ones(5), 0.2, component="out_of_plane"),
        ]
    )
    assert joint.components == ("in_plane",) * 5 + ("out_of_plane",) * 5
    np.testing.assert_array_equal(joint.sigma, [0.1] * 5 + [0.2] * 5)
    assert joint.component_at(joint.s_um > 5) == ("in_plane",) * 2 + ("out_of_plane",) * 2


RATIO = 1000.0
TRUTH = ax.Params(p=320.0, ks=1e5).with_values({}, RATIO)


@pytest.fixture(scope="module")
def model3d():
    """seven, turned 30 degrees: its dominant mode is not planar (out-of-plane ratio 0.14)."""
    return ax.models.seven(n_elements=6, rotation_deg=30.0)


def test_model_components_are_the_principal_axes(model3d):
    """The in-plane and out-of-plane psi_1 integrate (clamped base) to displacements along
    the principal axes of the mode's centreline motion: uncorrelated, in-plane the larger
    (the beat direction's definition, checked here with numpy on a fine grid)."""
    mode = ax.dominant_mode(model3d, TRUTH)
    s = np.linspace(0.0, 1.0, 401)
    disp = {}
    for c in ("in_plane", "out_of_plane"):
        psi = np.asarray(model_psi1(model3d, mode, s, c))
        disp[c] = np.concatenate([[0], np.cumsum((psi[1:] + psi[:-1]) / 2 * np.diff(s))])
    a, b = disp["in_plane"], disp["out_of_plane"]
    cross = np.trapezoid(np.real(a * np.conj(b)), s)
    var_a, var_b = np.trapezoid(np.abs(a) ** 2, s), np.trapezoid(np.abs(b) ** 2, s)
    assert abs(cross) < 1e-3 * var_a
    assert np.sqrt(var_b / var_a) == pytest.approx(float(mode.out_of_plane_ratio), rel=1e-3)
    with pytest.raises(ValueError, match="needs a 3D model"):
        model_psi1(ax.models.preset("two", n_elements=4), mode, s[:5], "out_of_plane")


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_3d_fit_to_both_components_recovers_the_parameters(model3d):
    """A target made of the model's own two components at p = 320 (one complex scale,
    sigma 0.01 rad) is fitted from p = 300 back to 320 with the scale recovered; with the
    out-of-plane component mirrored the same parameters no longer fit (the components
    share one scale: each with its own would absorb the sign)."""
    mode = ax.dominant_mode(model3d, TRUTH)
    s = np.linspace(0.0, 12.0, 25)
    a, b = (
        np.asarray(model_psi1(model3d, mode, s / 12.0, c)) for c in ("in_plane", "out_of_plane")
    )
    alpha = 0.8 / np.abs(a).max() * np.exp(0.7j)
    parts = [
        ShapeTarget(s, alpha * a, 0.01),
        ShapeTarget(s, alpha * b, 0.01, component="out_of_plane"),
    ]
    target = join_components(parts)
    start = TRUTH.with_values({"p": 300.0}, RATIO)
    problem = Problem(model3d, [Condition(shape=target)], ["p"], params=start, kl_ratio=RATIO)
    assert problem.n_residuals == 4 * s.size
    result = least_squares(problem, starts=1)
    assert result.params["p"] == pytest.approx(320.0, rel=1e-4)
    assert result.shape_rms < 1e-3
    fit = result.conditions[0]["shape"]
    np.testing.assert_allclose(
        fit["psi1_fit_re"] + 1j * fit["psi1_fit_im"],
        np.concatenate([alpha * a, alpha * b]),
        atol=1e-6,
    )
    assert fit["component"] == ["in_plane"] * s.size + ["out_of_plane"] * s.size
    fig = plot_fit_report(result.to_json())  # one curve per component
    labels = {t.get_text() for t in fig.axes[0].get_legend().get_texts()}
    assert {"observed (in plane)", "fitted (out of plane)"} <= labels
    mirrored = join_components(
        [parts[0], ShapeTarget(s, -alpha * b, 0.01, component="out_of_plane")]
    )
    at_truth = Problem(model3d, [Condition(shape=mirrored)], ["p"], params=TRUTH, kl_ratio=RATIO)
    r = at_truth.residuals_at(at_truth.u0)
    # |2 b alpha| / sigma_eff on the out-of-plane points, less what the shared scale can absorb.
    assert np.sqrt(np.mean(r**2)) > 1.0


def test_3d_centreline_of_the_model_reduces_and_fits_back(tmp_path, model3d):
    """End to end: a 3D centreline that beats with the model's mode (small amplitude,
    turned in space) is read and reduced in 3D; its joint two-component target fits the
    model back to p = 320 (the reduction's frame and signs agree with the model's:
    e3 = e1 x e2 is the beat direction turned from y towards z)."""
    from axojax.fem import interpolation_matrix

    mode = ax.dominant_mode(model3d, TRUTH)
    x = np.linspace(0.0, 1.0, 61)
    q = np.asarray(mode.eigenvector).reshape(model3d.n_filaments, model3d.n_dirs, -1).mean(0)
    u = q @ interpolation_matrix(model3d.n_elements, x, 0).T  # (2, P): y, z displacement
    u = 0.04 * u / np.abs(u).max()
    f = 12.0  # Hz, with frames at 12 per cycle: only the shape matters for the fit
    t = np.arange(61)[:, None, None] / (12 * f)
    yz = np.real(u[None] * np.exp(2j * np.pi * f * t))  # (T, 2, P)
    pts = np.concatenate([np.broadcast_to(x, (t.size, 1, x.size)), yz], axis=1)
    pts = 12.0 * np.moveaxis(pts, 1, 2) @ random_rotation(5).T  # um, L = 12
    path = tmp_path / "model.npz"
    np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], z_um=pts[..., 2], frame_rate_hz=12 * f)
    beat = read_beat(path, planarity_threshold=0.05)  # the mode's out-of-plane ratio is 0.14
    assert beat.out_of_plane is not None
    target = beat.joint_shape_target()
    assert target.components.count("out_of_plane") == beat.s_um.size
    start = TRUTH.with_values({"p": 300.0}, RATIO)
    units = ax.Units(length_um=beat.length_um)
    problem = Problem(
        model3d, [Condition(shape=target)], ["p"], params=start, kl_ratio=RATIO, units=units
    )
    result = least_squares(problem, starts=1)
    assert result.params["p"] == pytest.approx(320.0, rel=0.01)
    assert result.shape_rms < 0.05
    # Handedness: at the truth the reduced components fit; the out-of-plane one mirrored
    # (a left-handed frame) does not, the shared scale cannot absorb it.
    out = np.array(target.components) == "out_of_plane"
    mirrored = dataclasses.replace(target, psi1=np.where(out, -1, 1) * target.psi1)
    rms = [
        np.sqrt(np.mean(p.residuals_at(p.u0) ** 2))
        for p in (
            Problem(model3d, [Condition(shape=t)], ["p"], params=TRUTH, kl_ratio=RATIO, units=units)
            for t in (target, mirrored)
        )
    ]
    assert rms[0] < 0.05 and rms[1] > 10 * rms[0]


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_cli_fit_of_a_3d_beat_with_joint_components(tmp_path, model3d, capsys):
    """``axojax fit --data FILE --components joint`` fits the in-plane and out-of-plane
    psi_1 of a 3D centreline with one complex scale (the library's
    ``BeatData.joint_shape_target()``), back to the truth p = 320; the default fits the
    in-plane component alone; a planar model and the limit cycle are refused in one line."""
    from axojax.fem import interpolation_matrix

    mode = ax.dominant_mode(model3d, TRUTH)
    x = np.linspace(0.0, 1.0, 61)
    q = np.asarray(mode.eigenvector).reshape(model3d.n_filaments, model3d.n_dirs, -1).mean(0)
    u = q @ interpolation_matrix(model3d.n_elements, x, 0).T
    u = 0.04 * u / np.abs(u).max()
    t = np.arange(61)[:, None, None] / (12 * 12.0)
    yz = np.real(u[None] * np.exp(2j * np.pi * 12.0 * t))
    pts = np.concatenate([np.broadcast_to(x, (t.size, 1, x.size)), yz], axis=1)
    pts = 12.0 * np.moveaxis(pts, 1, 2) @ random_rotation(5).T
    path = tmp_path / "model.npz"
    np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], z_um=pts[..., 2], frame_rate_hz=144.0)
    # the frames at 12 per cycle of the truth's own frequency at the data's length and the
    # default EI and c_n, so that the frequency target agrees with the shape
    f = float(mode.frequency_hz(ax.Units(length_um=read_beat(path).length_um)))
    np.savez(path, x_um=pts[..., 0], y_um=pts[..., 1], z_um=pts[..., 2], frame_rate_hz=12 * f)
    common = ["fit", "--model", "seven", "--elements", "6", "--rotation-deg", "30", "--free", "p"]
    common += [
        "--ks",
        "1e5",
        "--kl-ratio",
        "1000",
        "--p",
        "300",
        "--data",
        str(path),
        "--starts",
        "1",
    ]
    common += ["--planarity-threshold", "0.05", "--no-mesh-check", "--json"]
    docs = {}
    for comp in ("in-plane", "joint"):
        assert main([*common, "--components", comp]) == 0, comp
        docs[comp] = json.loads(capsys.readouterr().out)
    shapes = {k: d["conditions"][0]["shape"]["component"] for k, d in docs.items()}
    assert set(shapes["in-plane"]) == {"in_plane"}
    assert shapes["joint"].count("out_of_plane") == shapes["joint"].count("in_plane") > 0
    assert docs["joint"]["params"]["p"] == pytest.approx(320.0, rel=0.01)
    flat = ["fit", "--model", "two", "--free", "p", "--data", str(path), "--components", "joint"]
    flat += ["--planarity-threshold", "0.05"]
    assert main(flat) == 2
    assert "in one plane" in capsys.readouterr().err
    bad = [
        "fit",
        "--model",
        "seven",
        "--free",
        "p",
        "--data",
        str(path),
        "--planarity-threshold",
        "0",
    ]
    assert main(bad) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--planarity-threshold: must be > 0, got 0" in err
