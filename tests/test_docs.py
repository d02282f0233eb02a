"""The documentation site builds without a warning (``mkdocs build --strict``).

The build renders the notebooks from their stored outputs (mkdocs-jupyter, execute: false)
and generates the CLI reference from the argparse parser, so it takes seconds.
"""

import json
import os
import pathlib
import subprocess
import sys

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _nav_paths(node):
    if isinstance(node, str):
        yield node
    elif isinstance(node, list):
        for item in node:
            yield from _nav_paths(item)
    elif isinstance(node, dict):
        for value in node.values():
            yield from _nav_paths(value)


def test_mkdocs_build_strict(tmp_path):
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "MPLBACKEND": "Agg"}
    run = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    site = tmp_path / "site"
    cli = (site / "cli" / "index.html").read_text()
    for sub in ("modes", "critical", "sweep", "fit", "simulate", "plot"):
        assert f"axojax {sub}" in cli, f"CLI reference lacks {sub}"
    assert "--kl-ratio" in cli
    api = (site / "api" / "eigen" / "index.html").read_text()
    assert "dominant_mode" in api and "dominant_eigenpair" in api
    assert "Hopf" in (site / "model" / "index.html").read_text()


def test_every_notebook_is_in_the_nav_and_stored_with_figures():
    nav = set(_nav_paths(yaml.safe_load((ROOT / "mkdocs.yml").read_text())["nav"]))
    for path in sorted((ROOT / "notebooks").glob("*.ipynb")):
        assert f"notebooks/{path.name}" in nav, f"{path.name} is not in mkdocs.yml's nav"
        nb = json.loads(path.read_text())
        outputs = [o for c in nb["cells"] if c["cell_type"] == "code" for o in c.get("outputs", [])]
        assert any("image/png" in o.get("data", {}) for o in outputs), (
            f"{path.name} is stored without figures: run scripts/run_notebooks.py"
        )
        assert not any(o.get("output_type") == "error" for o in outputs), (
            f"{path.name} is stored with an error"
        )
