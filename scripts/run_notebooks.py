"""Execute the notebooks at full size and store them with their outputs.

    nice -n 5 python scripts/run_notebooks.py [NAME ...]      # all, or notebooks/NAME.ipynb

The notebooks are committed with their outputs (figures visible on GitHub and in the
documentation site, which renders them without running them); this script is the one way
those outputs are made. It runs each notebook top to bottom in a fresh kernel with
``AXOJAX_FAST`` unset (full grids: minutes for the map notebooks, several for the
simulations), in a temporary working directory, and rewrites the file only when every
cell succeeded. The test suite runs the same notebooks with ``AXOJAX_FAST=1`` and
discards the outputs.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys
import tempfile
import time

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

ROOT = pathlib.Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"
NOISE = ("IProgress not found", "from .autonotebook import tqdm as notebook_tqdm")


def run(path: pathlib.Path, timeout: int) -> float:
    """Execute ``path`` in place (full size); returns the wall time in seconds."""
    nb = nbformat.read(path, as_version=4)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as cwd:
        client = NotebookClient(
            nb,
            timeout=timeout,
            kernel_name="python3",
            record_timing=False,
            resources={"metadata": {"path": cwd}},
        )
        try:
            client.execute()
        except CellExecutionError:
            failed = pathlib.Path(tempfile.gettempdir()) / f"{path.stem}.failed.ipynb"
            nbformat.write(nb, failed)  # to read what the cells printed before the failure
            print(f"{path.name}: the executed cells are in {failed}", file=sys.stderr)
            raise
    strip_noise(nb)
    nbformat.write(nb, path)
    return time.perf_counter() - start


def strip_noise(nb) -> None:
    """Drop stderr lines that say nothing about the computation (tqdm's notice that the
    kernel has no widget library)."""
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        kept = []
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out.get("name") == "stderr":
                lines = [
                    l
                    for l in out["text"].splitlines(keepends=True)
                    if not any(n in l for n in NOISE)
                ]
                if not "".join(lines).strip():
                    continue
                out["text"] = "".join(lines)
            kept.append(out)
        cell["outputs"] = kept


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="scripts/run_notebooks.py", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("names", nargs="*", help="notebook names (without .ipynb); default all")
    parser.add_argument("--timeout", type=int, default=3600, help="seconds per cell (default 3600)")
    args = parser.parse_args(argv)
    paths = [NOTEBOOKS / f"{n.removesuffix('.ipynb')}.ipynb" for n in args.names] or sorted(
        NOTEBOOKS.glob("*.ipynb")
    )
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        print(f"run_notebooks.py: error: no such notebook: {', '.join(missing)}", file=sys.stderr)
        return 2
    os.environ.pop("AXOJAX_FAST", None)
    os.environ.pop("MPLBACKEND", None)  # the kernel's inline backend stores the figures
    # this checkout's axojax, whatever is installed (the kernel runs in a temporary directory)
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]
    )
    failed = []
    for path in paths:
        try:
            seconds = run(path, args.timeout)
            print(f"{path.name}: {seconds:.0f} s", flush=True)
        except CellExecutionError as err:
            failed.append(path.name)
            print(
                f"{path.name}: FAILED, left unchanged\n{str(err)[-2000:]}",
                file=sys.stderr,
                flush=True,
            )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
