"""The programs each command compiles, and their compile times (issue 56 item 1): every
command below in a fresh process, a fresh folder and a fresh compilation cache (cold: what a
new user meets), with ``axojax --profile-compile``; prints per command its wall time, the
seconds spent building programs, how many builds of how many programs, and the longest
programs. docs/internals.md lists what it printed.

    python benchmarks/bench_programs.py [--only modes,fit] [--top 3]

One run each on one machine, not assertions.
"""

import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time

COMMANDS = {
    "modes": "axojax modes --model seven --p 300",
    "critical": "axojax critical --model seven",
    "sweep": "axojax sweep --model seven --p 250:350:8 --ks log:1e5:1e6:8 --kl-ratio 1000 --out map.npz",
    "data": "axojax data human_sperm",
    "fit": (
        "axojax fit --model seven --free p,ks --kl-ratio 1000 --data human_sperm --ei 90.9 "
        "--cn 0.000285 --shape-floor 0.2"
    ),
    "compare": "axojax compare --data human_sperm",
}
HEAD = re.compile(
    r"compilation: ([0-9.]+) s of ([0-9.]+) s wall; (\d+) builds of (\d+) programs "
    r"\((\d+) of them loaded"
)


def profile(command: str, top: int) -> dict:
    """Run ``command`` cold with --profile-compile; its table's totals and top programs."""
    with tempfile.TemporaryDirectory(prefix="axojax-programs-") as folder:
        env = {**os.environ, "AXOJAX_CACHE_DIR": os.path.join(folder, "cache")}
        argv = shlex.split(command)
        argv = [argv[0], "--profile-compile", "--quiet", *argv[1:]]
        t0 = time.perf_counter()
        done = subprocess.run(argv, cwd=folder, env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
    lines = done.stderr.splitlines()
    at = next((i for i, line in enumerate(lines) if HEAD.match(line)), None)
    if at is None:
        return {"wall": wall, "status": done.returncode, "error": done.stderr[-300:]}
    compile_s, _, builds, programs, hits = HEAD.match(lines[at]).groups()
    rows = [line.split() for line in lines[at + 2 : at + 2 + top]]
    return {
        "wall": wall,
        "status": done.returncode,
        "compile_s": float(compile_s),
        "builds": int(builds),
        "programs": int(programs),
        "top": [(r[-1], float(r[0]), int(r[1])) for r in rows if len(r) >= 6],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default=None, help="comma-separated names of COMMANDS")
    parser.add_argument("--top", type=int, default=3, help="programs listed per command")
    args = parser.parse_args()
    names = list(COMMANDS) if args.only is None else args.only.split(",")
    print(f"load before: {os.getloadavg()[0]:.2f}; python {sys.version.split()[0]}")
    print(
        "| command | wall (s) | building (s) | builds of programs | longest programs (s, builds) |"
    )
    print("|---|---:|---:|---:|---|")
    for name in names:
        got = profile(COMMANDS[name], args.top)
        if "error" in got:
            print(
                f"| `{COMMANDS[name]}` | {got['wall']:.1f} | - | - | exit {got['status']}: {got['error']!r} |"
            )
            continue
        top = ", ".join(f"`{n}` {s:.1f} ({b})" for n, s, b in got["top"])
        print(
            f"| `{COMMANDS[name]}` | {got['wall']:.1f} | {got['compile_s']:.1f} | "
            f"{got['builds']} of {got['programs']} | {top} |"
        )
    print(f"load after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
