"""Draw README's opening figure into docs/images/overview.png.

    nice -n 5 python scripts/make_overview_figure.py [OUT.png]

Left: the frequency of the seven-filament model's dominant mode over dynein force p and
spoke stiffness k_s (k_s / k_l = 10^3, the paper's figure 8d), blank where stable, with the
Hopf boundary p_c(k_s) computed directly by ``ax.critical_force`` (not a contour of the
grid). Right: the dominant mode at the paper's figure 7d point (p = 300, k_s = 10^6)
through one beat cycle, in the beat plane. About two minutes on two cores.
"""

from __future__ import annotations

import pathlib
import sys

import jax
import jax.numpy as jnp
import matplotlib

import axojax as ax  # before jax: sets XLA's CPU flags

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from axojax.waveform import mode_frames  # noqa: E402

RATIO = 1e3


def main(out: str | None = None) -> pathlib.Path:
    path = (
        pathlib.Path(out)
        if out
        else pathlib.Path(__file__).resolve().parents[1] / "docs" / "images" / "overview.png"
    )
    units = ax.Units()
    model = ax.models.seven(n_elements=10)
    p_axis, ks_axis = np.linspace(50, 1000, 39), np.logspace(2, 7, 31)
    res = ax.sweep(model, ax.Params(), {"p": p_axis, "ks": ks_axis}, kl_ratio=RATIO, progress=False)
    ks_line = np.logspace(2, 7, 41)
    boundary = jax.jit(
        jax.vmap(
            lambda lk: (
                ax.critical_force(
                    model, ax.Params(ks=jnp.exp(lk), kl=jnp.exp(lk) / RATIO).broadcast()
                ).p
            )
        )
    )
    p_c = np.asarray(boundary(jnp.log(ks_line)))
    mode = ax.dominant_mode(model, ax.Params(p=300.0, ks=1e6, kl=1e3))
    x, frames = mode_frames(model, np.asarray(mode.eigenvector), n_frames=16)
    angle = float(mode.beat_angle)
    inplane = (np.cos(angle) * frames[:, 0] + np.sin(angle) * frames[:, 1]) * units.length_um

    fig, (a, b) = plt.subplots(
        1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [2.3, 1]}, constrained_layout=True
    )
    f = np.where(res.data["classification"] == 1, res.data["frequency_hz"], np.nan)
    im = a.pcolormesh(
        p_axis, ks_axis, f.T, shading="auto", cmap="viridis", norm=matplotlib.colors.LogNorm()
    )
    fig.colorbar(im, ax=a, label="beat frequency (Hz)")
    a.plot(p_c, ks_line, "r-", lw=2.2, label="Hopf boundary p_c(k_s)")
    a.plot([300], [1e6], "w*", ms=12, mec="k", label="fig. 7d point")
    a.text(70, 3e5, "stable", fontsize=12)
    a.set(
        yscale="log",
        xlim=(p_axis[0], p_axis[-1]),
        xlabel="dynein force p (dimensionless)",
        ylabel="spoke stiffness k_s (k_l = k_s/1e3)",
        title="seven-filament axoneme: flutter (beating) region",
    )
    a.legend(loc="lower right", fontsize=9)
    for k, u in enumerate(inplane):
        b.plot(u, x * units.length_um, color=plt.cm.viridis(k / len(inplane)), lw=1.2)
    b.set(
        xlabel="displacement in the beat plane (um)",
        ylabel="distance from the base (um)",
        title=f"its beating mode at the star:\n{float(mode.frequency_hz(units)):.1f} Hz "
        f"(paper: 51 Hz),\nwavelength {float(mode.wavelength_um(units)):.1f} um",
    )
    b.title.set_fontsize(10)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")
    return path


if __name__ == "__main__":
    main(*sys.argv[1:2])
