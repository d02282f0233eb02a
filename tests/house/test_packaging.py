"""Packaging: the wheel carries every module and the package data; the metadata says
what the code needs (Python >= 3.11: tomllib); LICENSE and CITATION.cff are there.

The wheel is built with ``python -m build --wheel --no-isolation`` (no network) from a
copy of the source tree; installing it into a fresh venv and running a command takes
minutes, so that check is ``slow`` (skipped unless ``AXOJAX_SLOW_TESTS=1``)."""

import os
import pathlib
import shutil
import subprocess
import sys
import tomllib
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    pytest.importorskip("build")
    import setuptools

    if tuple(int(x) for x in setuptools.__version__.split(".")[:2]) < (70, 1):
        pytest.importorskip("wheel")  # bdist_wheel moved into setuptools in 70.1
    src = tmp_path_factory.mktemp("src")
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, src / name)
    shutil.copytree(
        ROOT / "axojax", src / "axojax", ignore=shutil.ignore_patterns("__pycache__", "*.pyc")
    )
    out = tmp_path_factory.mktemp("dist")
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "build",
            "--wheel",
            "--no-isolation",
            "--skip-dependency-check",
            "--outdir",
            str(out),
        ],
        cwd=src,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    (path,) = out.glob("axojax-*.whl")
    return path


def test_wheel_carries_modules_and_package_data(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    source = [
        p.relative_to(ROOT).as_posix()
        for p in (ROOT / "axojax").rglob("*")
        if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"
    ]
    missing = sorted(set(source) - names)
    assert not missing, f"not in the wheel: {missing}"
    assert "axojax/cli/main.py" in names and "axojax/_io.py" in names
    metadata = next(n for n in names if n.endswith(".dist-info/METADATA"))
    text = zipfile.ZipFile(wheel).read(metadata).decode()
    assert "Requires-Python: >=3.11" in text
    assert any(n.endswith("entry_points.txt") for n in names)


def test_metadata_files():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["requires-python"] == ">=3.11"
    assert meta["license"] == {"text": "MIT"} and "MIT License" in (ROOT / "LICENSE").read_text()
    cff = (ROOT / "CITATION.cff").read_text()
    assert "cff-version" in cff and "10.1098/rsif.2022.0264" in cff and "Woodhams" in cff
    assert "## [Unreleased]" in (ROOT / "CHANGELOG.md").read_text()


@pytest.mark.skipif(
    os.environ.get("AXOJAX_SLOW_TESTS") != "1",
    reason="installs the wheel into a fresh venv (minutes); AXOJAX_SLOW_TESTS=1",
)
def test_wheel_installs_and_runs(wheel, tmp_path):
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run(
        [str(py), "-m", "pip", "install", "--no-deps", "--no-index", str(wheel)],
        check=True,
        capture_output=True,
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    r = subprocess.run(
        [str(venv / "bin" / "axojax"), "modes", "--model", "two", "--elements", "4", "--json"],
        capture_output=True,
        text=True,
        timeout=600,
        cwd=tmp_path,
        env=env,
    )
    assert r.returncode == 0, r.stderr
    r = subprocess.run(
        [str(py), "-c", "import axojax, pathlib; print(pathlib.Path(axojax.__file__).parent)"],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
    )
    assert str(venv) in r.stdout
