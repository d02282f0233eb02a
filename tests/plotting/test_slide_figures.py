"""Every ``axojax plot`` kind is a figure for a slide (issue 57 item 1): rendered from the
stored fixture reports (tests/plotting/fixtures/, made by scripts/make_plot_fixtures.py)
through the function ``axojax plot`` calls for it, at 10 x 6.25 in and 160 dpi, each has
one title line of at most 60 characters, no text under 9 pt, its title, caption, labels
and legends inside the canvas, and the phase of psi_1 drawn only where |psi_1| is at least
5 % of its maximum (a clamped base's psi_1 = 0 draws no spike at s = 0)."""

from __future__ import annotations

import io
import json
import pathlib

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.text import Text

from axojax.plotting import style

FIXTURES = pathlib.Path(__file__).parent / "fixtures"
FIXTURE_FILES = (
    "compare.json",
    "whole_beat.json",
    "whole_beat_fit.json",
    "fit.json",
    "fit.posterior.npz",
    "map.npz",
    "simulation.npz",
    "branch.npz",
)
"""The stored files ``axojax plot`` draws (tests/plotting/fixtures/README.md)."""
SIZE = (10.0, 6.25)
DPI = 160


def _comparison():
    from axojax.plotting.compare import plot_comparison

    return plot_comparison(json.loads((FIXTURES / "compare.json").read_text()))


def _whole_beat():
    from axojax.plotting.compare import plot_comparison

    return plot_comparison(json.loads((FIXTURES / "whole_beat.json").read_text()))


def _whole_beat_fit():
    from axojax.plotting.fit_report import plot_fit_report

    return plot_fit_report(json.loads((FIXTURES / "whole_beat_fit.json").read_text()))


def _fit():
    from axojax.plotting.fit_report import plot_fit_report

    return plot_fit_report(json.loads((FIXTURES / "fit.json").read_text()))


def _fit_scalar():
    from axojax.plotting.fit_report import plot_fit_report
    from tests.house.test_new_user import _scalar_report

    return plot_fit_report(_scalar_report())  # a fit to scalar targets: no shape


def _posterior():
    from axojax.inverse import Posterior, load_truth
    from axojax.plotting.corner import plot_corner

    path = FIXTURES / "fit.posterior.npz"
    return plot_corner(Posterior.load(path), truth=load_truth(path))


def _sweep():
    from axojax.plotting import plot_sweep
    from axojax.sweeps import SweepResult

    return plot_sweep(SweepResult.load(FIXTURES / "map.npz"))


def _simulation():
    from axojax.dynamics import Simulation
    from axojax.plotting import plot_simulation

    return plot_simulation(Simulation.load(FIXTURES / "simulation.npz"))


def _orbit_branch():
    from axojax.orbits.branch import Branch
    from axojax.plotting.orbits import plot_branch

    return plot_branch(*Branch.load(FIXTURES / "branch.npz"))


def _data():
    from axojax.beats import read_beat
    from axojax.plotting.beat_data import plot_beat_data

    return plot_beat_data(read_beat("human_sperm"))  # axojax data human_sperm --plot


def _section():
    import axojax as ax
    from axojax.plotting import plot_section

    return plot_section(ax.models.preset("seven"))  # axojax plot --model seven


KINDS = {
    "comparison": _comparison,
    "whole_beat": _whole_beat,
    "whole_beat_fit": _whole_beat_fit,
    "fit": _fit,
    "fit_scalar": _fit_scalar,
    "posterior": _posterior,
    "sweep": _sweep,
    "simulation": _simulation,
    "orbit_branch": _orbit_branch,
    "data": _data,
    "section": _section,
}
"""Each kind as ``axojax plot`` (or ``axojax data --plot``) draws it."""


def _render(fig) -> tuple[int, int]:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    fig.canvas.draw()
    return plt.imread(io.BytesIO(buf.getvalue())).shape[:2]


def _drawn(t: Text) -> bool:
    return (
        bool(t.get_text().strip()) and t.get_visible() and (t.axes is None or t.axes.get_visible())
    )


@pytest.mark.parametrize("kind", KINDS)
def test_every_kind_is_a_slide(kind):
    before = dict(matplotlib.rcParams)
    fig = KINDS[kind]()
    try:
        assert tuple(fig.get_size_inches()) == SIZE
        assert _render(fig) == (1000, 1600)
        title = fig.get_suptitle()
        assert title and "\n" not in title and len(title) <= 60, title
        small = sorted(
            {
                (round(t.get_fontsize(), 2), t.get_text()[:30])
                for t in fig.findobj(Text)
                if t.get_text().strip() and t.get_fontsize() < 9
            }
        )
        assert not small, f"{kind}: text under 9 pt: {small[:5]}"
        # the title, caption, axes titles and labels, legends: inside the canvas
        canvas = fig.bbox
        inner = [fig._suptitle, *fig.texts]
        for a in fig.axes:
            if a.get_visible():
                inner += [a.title, a.xaxis.label, a.yaxis.label]
                legend = a.get_legend()
                inner += legend.get_texts() if legend is not None else []
        for legend in fig.legends:
            inner += legend.get_texts()
        renderer = fig.canvas.get_renderer()
        for t in filter(_drawn, inner):
            box = t.get_window_extent(renderer)
            assert (
                box.x0 >= canvas.x0 - 1
                and box.x1 <= canvas.x1 + 1
                and box.y0 >= canvas.y0 - 1
                and box.y1 <= canvas.y1 + 1
            ), f"{kind}: {t.get_text()[:40]!r} runs off the figure"
    finally:
        plt.close(fig)
    assert dict(matplotlib.rcParams) == before  # the slide style is the figure's, not global


def test_masked_phase_drops_a_clamped_base():
    s = np.linspace(0.0, 1.0, 41)
    psi1 = s * np.exp(-1j * 9.0 * s)  # psi_1 = 0 at s = 0; a wave of 1.4 turns
    ph = style.masked_phase(psi1)
    small = np.abs(psi1) < style.PHASE_FLOOR * np.abs(psi1).max()
    assert small[0] and np.isnan(ph[small]).all() and np.isfinite(ph[~small]).all()
    np.testing.assert_allclose(np.diff(ph[~small]), -9.0 * np.diff(s[~small]), atol=1e-12)
    assert np.isnan(style.masked_phase(np.zeros(5))).all()


def _phase_axes(fig):
    (a,) = [a for a in fig.axes if a.get_title() == "phase"]
    return a


def test_comparison_phase_of_a_clamped_row_is_masked():
    from axojax.plotting.compare import MAX_ROWS, _complex

    doc = json.loads((FIXTURES / "compare.json").read_text())
    fig = _comparison()
    try:
        lines = _phase_axes(fig).get_lines()[1:]  # the observed points first, then the rows
        rows = doc["rows"][:MAX_ROWS]
        assert len(lines) == len(rows)
        clamped = [(r, line) for r, line in zip(rows, lines) if r["base"] == "clamped"]
        assert clamped
        for r, line in clamped:
            amp = np.abs(_complex(r["psi1_model"]))
            assert amp[0] == 0.0  # the clamp
            phase = np.asarray(line.get_ydata(), float)
            small = amp < style.PHASE_FLOOR * amp.max()
            assert np.isnan(phase[small]).all() and np.isfinite(phase[~small]).all()
        # the fitted numbers are in the legend, the verdict in the caption
        labels = [t.get_text() for t in fig.legends[0].get_texts()] if fig.legends else []
        labels += [
            t.get_text() for a in fig.axes if a.get_legend() for t in a.get_legend().get_texts()
        ]
        assert any(f"R² {rows[0]['r2']:.3f}" in x for x in labels)
        caption = " ".join(t.get_text() for t in fig.texts)
        assert "Verdict:" in caption and "pN/um^2" in caption
    finally:
        plt.close(fig)


def test_fit_report_phase_is_masked_at_the_clamped_base():
    report = json.loads((FIXTURES / "fit.json").read_text())
    sh = next(c["shape"] for c in report["conditions"] if c.get("shape"))
    fit = np.asarray(sh["psi1_fit_re"]) + 1j * np.asarray(sh["psi1_fit_im"])
    fig = _fit()
    try:
        fitted = _phase_axes(fig).get_lines()[1]  # observed points, then the fitted line
        phase = np.asarray(fitted.get_ydata(), float)
        small = np.abs(fit) < style.PHASE_FLOOR * np.abs(fit).max()
        assert small[0] and np.isnan(phase[small]).all() and np.isfinite(phase[~small]).all()
        caption = " ".join(t.get_text() for t in fig.texts)
        assert "p = " in caption and "chi2/dof" in caption
    finally:
        plt.close(fig)


@pytest.mark.parametrize("name", FIXTURE_FILES)
def test_axojax_plot_draws_every_fixture(name, tmp_path, capsys):
    """The fixtures are what the commands write: ``axojax plot`` draws each (svg: the
    suffix of --out picks the format)."""
    from axojax.cli.main import main

    out = tmp_path / "figure.svg"
    assert main(["plot", str(FIXTURES / name), "--out", str(out)]) == 0
    assert out.read_text().lstrip().startswith("<?xml")
    capsys.readouterr()


def test_fixtures_are_small():
    sizes = {p.name: p.stat().st_size for p in FIXTURES.iterdir() if p.name != "README.md"}
    assert set(sizes) >= set(FIXTURE_FILES)
    assert max(sizes.values()) < 200_000, sizes
