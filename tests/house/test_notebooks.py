"""Every notebook executes top to bottom with small grids (AXOJAX_FAST=1); the paper
gallery's notebooks assert their key numbers against the paper inside (a failed assert is a
failed cell) and end in a paper-vs-axojax table.

The stored outputs (scripts/run_notebooks.py, full size) are not touched: each test runs a
copy and discards it. Every notebook runs here. Fast runs skip what another test already
checks at full size and would only repeat at length: figure 12 simulates its beats on the
coarse paper.FAST mesh (the full beat is tests/model/test_imbalance.py's) and the human sperm
notebook samples one posterior (the second is the same compiled sampler at other sigmas).
"""

import os
import pathlib

import nbformat
import pytest
from nbclient import NotebookClient

from axojax.cache import CACHE_ENV, MIN_COMPILE_SECONDS
from tests.conftest import LEVEL_FLAG

NOTEBOOKS = sorted((pathlib.Path(__file__).resolve().parents[2] / "notebooks").glob("*.ipynb"))
NOT_IN_SUITE: dict[str, str] = {}  # notebook stem -> why it is not executed here
# Kernels that run long computations (posterior chains, beat simulations) more than they
# compile, and so get XLA's full optimisation instead of the suite's level 0
# (tests/conftest.py). Measured fast runs, level 0 -> full: fitting_human_sperm 80 -> 62 s,
# gallery_fig12 40 -> 33 s; every other notebook is faster at level 0 (fig07_mode_shapes
# 15 against 23 s).
RUN_BOUND = {"fitting_human_sperm", "gallery_fig12_asymmetric_beat"}


def _source(nb) -> str:
    return "\n".join(c.source for c in nb.cells if c.cell_type == "code")


@pytest.mark.slow
@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes(path, monkeypatch, tmp_path):
    if path.stem in NOT_IN_SUITE:
        pytest.skip(NOT_IN_SUITE[path.stem])
    monkeypatch.setenv("AXOJAX_FAST", "1")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    # The kernel keeps its compiled programs in the suite's cache (tests/conftest.py), as
    # `axojax.enable_compilation_cache` would: the notebooks share many programs.
    monkeypatch.setenv("JAX_COMPILATION_CACHE_DIR", os.environ[CACHE_ENV])
    monkeypatch.setenv("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", str(MIN_COMPILE_SECONDS))
    if path.stem in RUN_BOUND:
        flags = (
            os.environ.get("XLA_FLAGS", "").replace(LEVEL_FLAG, "").strip()
        )  # axojax's own flags stay
        monkeypatch.setenv("XLA_FLAGS", flags)
    nb = nbformat.read(path, as_version=4)
    NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    ).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    if path.stem.startswith("gallery_"):
        assert "assert " in _source(nb), "a gallery notebook asserts its key numbers"
        tables = [
            o["data"]["text/markdown"] for o in outputs if "text/markdown" in o.get("data", {})
        ]
        assert any("| paper | axojax |" in t for t in tables), "no paper-vs-axojax table"
        assert any(
            o.get("output_type") == "display_data" and "image/png" in o.get("data", {})
            for o in outputs
        ), "no figure"


def test_gallery_covers_every_claim_group():
    """One gallery notebook per figure group of axojax.paper (and figures 8-10)."""
    from axojax.paper import GROUPS

    names = {p.stem for p in NOTEBOOKS}
    for group in list(GROUPS) + ["fig. 8", "fig. 9", "fig. 10"]:
        number = int(group.split()[-1])
        assert any(n.startswith(f"gallery_fig{number:02d}_") for n in names), group
