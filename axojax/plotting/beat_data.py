"""Figure of a reduced beat (:class:`~axojax.beats.BeatData`): what ``axojax data --plot``
draws, before any fit; sized for a slide (:mod:`axojax.plotting.style`)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from ..beats.data import BeatData
from ..waveform import measures as wm
from . import style


def plot_beat_data(beat: BeatData) -> plt.Figure:
    """psi_0(s); |psi_1(s)| with its 1-sigma band; the unwrapped phase of psi_1(s) (where
    |psi_1| is at least 5 % of its maximum: :func:`~axojax.plotting.style.masked_phase`)
    with the wavelength's line: its least-squares fit (slope k,
    :mod:`axojax.waveform.measures`, through the trapezoid-weighted centre of the phase, as
    fitted); the kymograph psi(s, t) of the first (at most 3) of the whole cycles the
    reduction used, their bounds marked (frames), or the two-mode reconstruction
    psi_0 + Re(psi_1 exp(i theta)) over one cycle (Fourier modes). A non-planar 3D beat
    shows its out-of-plane component dashed, with its own wavelength slope
    (:attr:`~axojax.beats.BeatData.components`). Values within the data's precision are
    drawn as such: psi_0's axis spans at least +-2 psi_1 sigma (rounding noise stays a flat
    line), and a static curvature within its noise is titled 0. The title names the file
    and its kind; the caption carries the length, frequency, wavelength and amplitude."""
    with style.slide_style():
        fig = style.slide_figure()
        axes = fig.subplots(2, 2)
        _draw(fig, axes, beat)
        return style.finish(fig, _title(beat), _caption(beat))


def _draw(fig: plt.Figure, axes, beat: BeatData) -> None:
    s = beat.s_um
    comps = [("", beat.modes, beat.psi1_sigma, "-")]
    if beat.out_of_plane is not None:
        comps = [
            (" in plane", beat.modes, beat.psi1_sigma, "-"),
            (" out of plane", beat.out_of_plane[0], beat.out_of_plane[1], "--"),
        ]
    colours = []
    for i, (label, m, sig, ls) in enumerate(comps):
        colour = style.PALETTE[i]
        axes[0, 0].plot(s, m.psi0, ls, color=colour, label=f"psi_0{label}")
        amp = np.abs(m.psi1)
        axes[0, 1].plot(s, amp, ls, color=colour, label=f"|psi_1|{label}")
        axes[0, 1].fill_between(
            s, amp - sig, amp + sig, color=colour, alpha=0.25, lw=0, label=f"1 sigma{label}"
        )
        # drawn where |psi_1| carries a phase, on the branch the wavelength is fitted to
        axes[1, 0].plot(
            s,
            style.follow(style.masked_phase(m.psi1), np.asarray(wm.unwrapped_phase(m.psi1))),
            ls,
            # a 3D beat's components are keyed in the panels above: its legend keeps to slopes
            label="phase of psi_1" if len(comps) == 1 else f"_phase{label}",
            color=colour,
        )
        colours.append(colour)
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
        slope = f"wavelength {lam:.3g} µm" if lam else "0: standing wave"
        axes[1, 0].plot(
            s,
            fit,
            ":",
            lw=2,
            color=style.BLACK if len(comps) == 1 else colour,
            label=f"slope: {slope}" + (f" ({label.strip()})" if len(comps) > 1 else ""),
        )
    curvature = beat.static_curvature_rad_per_um
    noise = beat.static_curvature_noise_rad_per_um
    slope = "0 rad/µm" if abs(curvature) < noise else f"{curvature:.3g} rad/µm"
    axes[0, 0].set_title(f"static mode, slope {slope}")
    axes[0, 1].set_title("amplitude, band: 1 σ")
    axes[1, 0].set_title("phase")
    for a, ylab in (
        (axes[0, 0], r"$\psi_0$ (rad)"),
        (axes[0, 1], r"$|\psi_1|$ (rad)"),
        (axes[1, 0], r"arg $\psi_1$ (rad)"),
    ):
        a.set_xlabel("arc length s (µm)")
        a.set_ylabel(ylab)
        a.legend(fontsize=9.5)
    if beat.excluded_base_um > 0:
        for a in axes.flat[:3]:
            a.axvline(beat.excluded_base_um, color="grey", lw=1)
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
        im = a.pcolormesh(t, s, psi.T, shading="auto", cmap=style.SIGNED_CMAP, vmin=-lim, vmax=lim)
        if bounds is not None:
            for b in bounds[: shown + 1]:
                a.axvline(b, color="k", lw=1, ls="--")
        which = (
            f"the {beat.cycles} whole cycle{'s' if beat.cycles != 1 else ''} used"
            if shown == beat.cycles
            else f"first {shown} of {beat.cycles} whole cycles used"
        )
        a.set_xlabel("time (s)")
        a.set_title(f"kymograph, {which}")
    else:
        theta = np.linspace(0, 2 * np.pi, 64)
        rec = beat.modes.psi0[None] + np.real(beat.modes.psi1[None] * np.exp(1j * theta)[:, None])
        lim = np.abs(rec).max() or 1.0
        im = a.pcolormesh(
            theta / (2 * np.pi),
            s,
            rec.T,
            shading="auto",
            cmap=style.SIGNED_CMAP,
            vmin=-lim,
            vmax=lim,
        )
        a.set_xlabel("phase (cycles)")
        a.set_title("two-mode reconstruction, one cycle")
    a.set_ylabel("arc length s (µm)")
    plane = " in plane" if beat.out_of_plane is not None else ""
    fig.colorbar(im, ax=a, label=rf"$\psi${plane} (rad)")


def _title(beat: BeatData) -> str:
    name = beat.source.rsplit("/", 1)[-1]
    return style.short(f"{name}: {beat.kind} beat before any fit")


def _caption(beat: BeatData) -> str:
    freq = (
        "frequency unknown"
        if beat.frequency_hz is None
        else f"{beat.frequency_hz:.3f} ± {beat.frequency_sigma_hz:.2g} Hz"
    )
    lam = ", ".join(
        f"{c['name'].replace('_', '-')} {c['wavelength_um']:.3g} µm"
        if c.get("wavelength_um")
        else f"{c['name'].replace('_', '-')} none (standing wave)"
        for c in beat.components
    )
    curvature = beat.static_curvature_rad_per_um
    noise = beat.static_curvature_noise_rad_per_um
    static = (
        f"0 rad/µm (within its noise, {noise:.2g})"
        if abs(curvature) < noise
        else f"{curvature:.3g} rad/µm (noise {noise:.2g})"
    )
    lines = [
        f"Length {beat.length_um:.3g} µm; frequency {freq}; wavelength {lam}; mean |psi_1| "
        f"{beat.dynamic_amplitude_rad:.3g} rad; static curvature {static}."
    ]
    if beat.psi_rad is not None and beat.t_s is not None:
        lines.append(
            f"Kymograph: dashed lines bound the cycles ({beat.cycles} whole cycles used); "
            "the phase is drawn where |psi_1| is at least 5 % of its maximum."
        )
    if beat.excluded_base_um > 0:
        lines.append(f"Grey line: the end of the excluded base ({beat.excluded_base_um:g} µm).")
    return "\n".join(lines)
