"""The documentation site builds without a warning (``mkdocs build --strict``).

The build renders the notebooks from their stored outputs (mkdocs-jupyter, execute: false)
and generates the CLI reference from the argparse parser, so it takes seconds.
"""

import json
import os
import pathlib
import subprocess
import sys

import pytest
import yaml

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _nav_paths(node):
    if isinstance(node, str):
        yield node
    elif isinstance(node, list):
        for item in node:
            yield from _nav_paths(item)
    elif isinstance(node, dict):
        for value in node.values():
            yield from _nav_paths(value)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
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


def _interface() -> str:
    return (ROOT / "docs" / "interface.md").read_text()


def test_interface_page_names_every_fit_spec_key_the_command_accepts():
    """docs/interface.md's fit spec against what ``axojax fit --spec`` really accepts."""
    from axojax.inverse import spec as fit

    text = _interface()
    spec = text[text.index("## The fit spec") : text.index("## Beat data files")]
    tops = {"condition": "[[condition]]", "params": "[params]", "bounds": "[bounds]"}
    for key in fit.SPEC_KEYS:
        assert tops.get(key, f"{key} =") in spec, key
    for key, (_, sigma_key, _) in fit.SPEC_TARGETS.items():
        assert key in spec and sigma_key in spec, key
    for key in ("label", "data", "source"):
        assert key in spec, key


def test_interface_page_lists_the_json_keys_commands_print(capsys):
    """The keys of ``axojax modes --json`` and ``axojax data --list --json`` (run here on
    a small model) are the ones docs/interface.md lists."""
    from axojax.cli.main import main

    text = _interface()
    modes = text[text.index("### `axojax modes`") : text.index("### `axojax critical`")]
    assert main(["modes", "--model", "two", "--elements", "4", "--grad", "p", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    for key in (*doc, *doc["dominant"], *doc["gradients"]):
        assert f'"{key}"' in modes, key
    data = text[text.index("### `axojax data`") : text.index("### `axojax simulate`")]
    assert main(["data", "--list", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    for key in doc["datasets"][0]:
        assert f'"{key}"' in data, key


def test_model_page_has_the_sections_the_code_cites():
    """docs/model.md keeps the specification's numbering (the code cites "docs/model.md
    section N"); section 5 defines the one wavelength on the tangent angle."""
    import re

    text = (ROOT / "docs" / "model.md").read_text()
    titles = re.findall(r"^## (\d+)\. (.+)$", text, re.M)
    assert [int(n) for n, _ in titles] == list(range(1, 9))
    assert dict(titles)["5"] == "Mode metrics" and "One wavelength everywhere" in text
    assert dict(titles)["6"] == "Numbers to reproduce"
    section3 = text[text.index("## 3.") : text.index("## 4.")]
    assert "`moment`" in section3 and "`force`" in section3
