"""Run every ``axojax ...`` command README.md shows, as README shows it, and write what each
prints (stdout, then stderr) with elapsed times masked, one file per command, so that two
checkouts' outputs can be compared line by line: a change that should not alter the
command line (a refactoring) is checked with

    python3 scripts/readme_outputs.py OUT_BEFORE     # in the checkout before
    python3 scripts/readme_outputs.py OUT_AFTER      # in the checkout after
    diff -r OUT_BEFORE OUT_AFTER

Each command runs in a fresh temporary directory with a fresh compilation cache and no
progress bars, with this checkout's axojax (its ``axojax`` command's entry point). The
masked values are wall-clock durations ("12.3 s", "4 min", "(5 s)") and the paths of the
checkout, the work and the cache directories; every other character must agree. The
README commands' own checks (what README quotes) are tests/house/test_readme.py's.
"""

from __future__ import annotations

import os
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
ENTRY = (
    "import sys; sys.argv[0] = 'axojax'; from axojax.cli.main import console; sys.exit(console())"
)
ELAPSED = re.compile(r"\b\d+(?:\.\d+)?(?:e[+-]?\d+)?\s?(?:s|ms|min|minutes|seconds)\b")


def commands(readme: pathlib.Path = ROOT / "README.md") -> list[str]:
    """Every ``axojax ...`` line of README's ```bash blocks, comments cut."""
    blocks = re.findall(r"```bash\n(.*?)```", readme.read_text(), re.S)
    return [
        line.split("  #")[0].strip()
        for block in blocks
        for line in block.splitlines()
        if line.startswith("axojax ")
    ]


def masked(text: str, *paths: str) -> str:
    for path in paths:
        text = text.replace(path, "<tmp>")
    return ELAPSED.sub("<elapsed>", text)


def main(out: str) -> int:
    target = pathlib.Path(out)
    target.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as work, tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, AXOJAX_CACHE_DIR=cache, AXOJAX_PROGRESS="0")
        env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(
            os.pathsep
        )
        for i, command in enumerate(commands()):
            argv = [sys.executable, "-c", ENTRY, *command.split()[1:]]
            run = subprocess.run(argv, cwd=work, env=env, capture_output=True, text=True)
            text = f"$ {command}\nexit {run.returncode}\n{run.stdout}\n--- stderr\n{run.stderr}"
            name = f"{i:02d}_{command.split()[1]}.txt"
            (target / name).write_text(masked(text, work, cache, str(ROOT)))
            print(f"{name}: exit {run.returncode}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "readme_outputs"))
