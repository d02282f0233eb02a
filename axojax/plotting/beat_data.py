"""Figure of a reduced beat (:class:`~axojax.beats.BeatData`): what ``axojax data --plot``
draws, before any fit."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from ..beats.data import BeatData
from ..waveform import measures as wm


def plot_beat_data(beat: BeatData) -> plt.Figure:
    """psi_0(s); |psi_1(s)| with its 1-sigma band; the unwrapped phase of psi_1(s) with
    the wavelength's line: its least-squares fit (slope k, :mod:`axojax.waveform.measures`,
    through the trapezoid-weighted centre of the phase, as fitted); the kymograph psi(s, t) of the
    first (at most 3) of the whole cycles the reduction used, their bounds marked (frames),
    or the two-mode reconstruction psi_0 + Re(psi_1 exp(i theta)) over one cycle (Fourier
    modes). A non-planar 3D beat shows its out-of-plane component dashed, with its own
    wavelength slope (:attr:`~axojax.beats.BeatData.components`). Values within the data's
    precision are drawn as such: psi_0's axis spans at least +-2 psi_1 sigma (rounding noise
    stays a flat line), and a static curvature within its noise is titled 0."""
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), layout="constrained")
    s = beat.s_um
    comps = [("", beat.modes, beat.psi1_sigma, "-")]
    if beat.out_of_plane is not None:
        comps = [
            (" in plane", beat.modes, beat.psi1_sigma, "-"),
            (" out of plane", beat.out_of_plane[0], beat.out_of_plane[1], "--"),
        ]
    colours = []
    for label, m, sig, ls in comps:
        axes[0, 0].plot(s, m.psi0, ls, label=f"psi_0{label}")
        amp = np.abs(m.psi1)
        (line,) = axes[0, 1].plot(s, amp, ls, label=f"|psi_1|{label}")
        axes[0, 1].fill_between(
            s,
            amp - sig,
            amp + sig,
            color=line.get_color(),
            alpha=0.25,
            lw=0,
            label=f"1 sigma{label}",
        )
        axes[1, 0].plot(
            s,
            np.asarray(wm.unwrapped_phase(m.psi1)),  # the phase the wavelength is fitted to
            ls,
            label=f"phase of psi_1{label}",
            color=line.get_color(),
        )
        colours.append(line.get_color())
    precision = float(np.median(beat.psi1_sigma))
    lo = min(float(np.min(m.psi0)) for _, m, _, _ in comps)
    hi = max(float(np.max(m.psi0)) for _, m, _, _ in comps)
    if hi - lo < 4 * precision:
        centre = precision * np.round((hi + lo) / 2 / precision)
        axes[0, 0].set_ylim(centre - 2 * precision, centre + 2 * precision)
    for (label, m, _, _), colour, measured in zip(comps, colours, beat.components):
        phase = np.asarray(wm.unwrapped_phase(m.psi1))
        w = np.where(m.psi1 == 0, 0.0, wm.trapezoid_weights(s))
        w = w if w.sum() > 0 else np.ones_like(w)
        centre = np.average(s, weights=w), np.average(phase, weights=w)
        fit = centre[1] + measured["wavenumber_rad_per_um"] * (s - centre[0])
        lam = measured["wavelength_um"]
        slope = f"wavelength {lam:.3g} um" if lam else "0: standing wave"
        axes[1, 0].plot(
            s,
            fit,
            ":",
            color="k" if len(comps) == 1 else colour,
            label=f"slope: {slope}" + (f" ({label.strip()})" if len(comps) > 1 else ""),
        )
    curvature = beat.static_curvature_rad_per_um
    noise = beat.static_curvature_noise_rad_per_um
    slope = (
        f"0 rad/um (within its noise, {noise:.2g})"
        if abs(curvature) < noise
        else f"{curvature:.3g} rad/um"
    )
    axes[0, 0].set_title(f"static mode psi_0: slope {slope}")
    axes[0, 1].set_title(f"|psi_1| (band: 1 sigma); mean {beat.dynamic_amplitude_rad:.3g} rad")
    axes[1, 0].set_title("phase of psi_1")
    for a, ylab in (
        (axes[0, 0], "psi_0 (rad)"),
        (axes[0, 1], "|psi_1| (rad)"),
        (axes[1, 0], "arg psi_1 (rad)"),
    ):
        a.set_xlabel("arc length s (um)")
        a.set_ylabel(ylab)
        a.legend(fontsize=8)
    if beat.excluded_base_um > 0:
        for a in axes.flat[:3]:
            a.axvline(beat.excluded_base_um, color="grey", lw=0.8)
    a = axes[1, 1]
    if beat.psi_rad is not None and beat.t_s is not None:
        bounds = beat.cycle_bounds_s
        shown = min(3, beat.cycles)
        t, psi = beat.t_s, beat.psi_rad
        if bounds is not None and shown > 0:
            keep = t <= bounds[shown] + 1e-9 * (t[-1] - t[0])
            keep[: min(int(keep.sum()) + 1, t.size)] = True  # the frame after the last bound
            t, psi = t[keep], psi[keep]
        lim = np.abs(psi).max() or 1.0
        im = a.pcolormesh(t, s, psi.T, shading="auto", cmap="RdBu_r", vmin=-lim, vmax=lim)
        if bounds is not None:
            for b in bounds[: shown + 1]:
                a.axvline(b, color="k", lw=0.8, ls="--")
        which = (
            f"the {beat.cycles} whole cycle{'s' if beat.cycles != 1 else ''} used"
            if shown == beat.cycles
            else f"first {shown} of the {beat.cycles} whole cycles used"
        )
        a.set_xlabel("time (s)")
        plane = " in plane" if beat.out_of_plane is not None else ""
        a.set_title(f"kymograph psi(s, t){plane}: {which}\n(dashed: the cycles' bounds)")
    else:
        theta = np.linspace(0, 2 * np.pi, 64)
        rec = beat.modes.psi0[None] + np.real(beat.modes.psi1[None] * np.exp(1j * theta)[:, None])
        lim = np.abs(rec).max() or 1.0
        im = a.pcolormesh(
            theta / (2 * np.pi), s, rec.T, shading="auto", cmap="RdBu_r", vmin=-lim, vmax=lim
        )
        a.set_xlabel("phase (cycles)")
        a.set_title("reconstruction psi_0 + Re(psi_1 e^{i theta}), one cycle")
    a.set_ylabel("arc length s (um)")
    fig.colorbar(im, ax=a, label="psi (rad)")
    freq = (
        "frequency unknown"
        if beat.frequency_hz is None
        else f"{beat.frequency_hz:.3f} +- {beat.frequency_sigma_hz:.2g} Hz"
    )
    fig.suptitle(
        f"{beat.source.rsplit('/', 1)[-1]}: {beat.kind}, L = {beat.length_um:.3g} um, {freq}",
        fontsize="large",
    )
    fig.get_layout_engine().set(h_pad=0.1)  # the title clear of the panels' titles
    return fig
