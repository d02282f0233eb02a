"""Wall time of every command README.md shows (issue 57 item 6: each within 3 minutes on
two cores), as a new user meets them: each in a fresh process, in a fresh folder, with a
fresh compilation cache (``AXOJAX_CACHE_DIR``: cold), one after another in README's order
(``axojax plot cmp.json`` draws the comparison's report). With ``--warm`` each command
runs a second time on the filled cache.

    python benchmarks/bench_readme.py [--warm] [--only compare,fit]

Prints per command its wall and CPU time (the children's user + sys: on a shared machine
the wall time grows with the load, the CPU time much less) and its exit status. Timings are
for one machine and one run, not assertions; the machine's load is printed before and after.
"""

import argparse
import os
import pathlib
import re
import resource
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
LIMIT_S = 180.0


def readme_commands() -> list[str]:
    """Every ``axojax ...`` line of README's ```bash blocks, in order."""
    blocks = re.findall(r"```bash\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    return [
        line.split("  #")[0].strip()
        for block in blocks
        for line in block.splitlines()
        if line.startswith("axojax ")
    ]


def run(command: str, folder: pathlib.Path, env: dict) -> tuple[float, float, int]:
    """(wall s, CPU s, exit status) of ``command`` run as ``python -m axojax.cli.main``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    argv = [sys.executable, "-m", "axojax.cli.main", *shlex.split(command)[1:]]
    code = subprocess.run(argv, cwd=folder, env=env, capture_output=True).returncode
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, code


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--warm", action="store_true", help="run each command again, cache filled")
    parser.add_argument("--only", default="", help="comma-separated words a command must contain")
    args = parser.parse_args()
    words = [w for w in args.only.split(",") if w]
    print(f"load average before: {os.getloadavg()[0]:.2f}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        env = dict(os.environ, AXOJAX_CACHE_DIR=str(folder / "cache"), AXOJAX_PROGRESS="0")
        for command in readme_commands():
            if words and not any(w in command for w in words):
                continue
            for label in ("cold", "warm") if args.warm else ("cold",):
                wall, cpu, code = run(command, folder, env)
                mark = "within 3 min" if wall <= LIMIT_S else "OVER 3 min"
                print(
                    f"{wall:7.1f} s wall {cpu:7.1f} s CPU  exit {code}  {label}  {mark}  {command}",
                    flush=True,
                )
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
