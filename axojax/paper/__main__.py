"""``python -m axojax.paper [--write] [--fast | --no-beat]``: the paper-vs-axojax table;
``python -m axojax.paper --inferred [--json]``: the parameters axojax infers for figures
whose parameters the paper leaves unstated (:mod:`axojax.paper.inferred`).

Prints the markdown on stdout; ``--write`` rewrites README.md's block and
docs/paper_table.md instead (the full computation only: the time-domain rows take minutes).
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m axojax.paper",
        description="The paper-vs-axojax table: prints its markdown, or with --write rewrites "
        "README.md's block and docs/paper_table.md.",
    )
    parser.add_argument(
        "--write", action="store_true", help="rewrite README.md's block and docs/paper_table.md"
    )
    speed = parser.add_mutually_exclusive_group()
    speed.add_argument(
        "--fast",
        action="store_true",
        help="simulate the beat coarsely (4 elements, 0.3 s); not with --write",
    )
    speed.add_argument(
        "--no-beat", action="store_true", help="leave out the time-domain rows; not with --write"
    )
    parser.add_argument(
        "--beat-npz",
        default=None,
        metavar="PATH",
        help="save the simulated beat here, and reuse it when its settings match",
    )
    parser.add_argument(
        "--readme",
        default=str(ROOT / "README.md"),
        metavar="PATH",
        help="README to update (default: the repository's)",
    )
    parser.add_argument(
        "--docs",
        default=str(ROOT / "docs" / "paper_table.md"),
        metavar="PATH",
        help="documentation page to write",
    )
    parser.add_argument(
        "--inferred",
        action="store_true",
        help="print the inferred parameter sets (figs. 7d-h and 12) instead of the table",
    )
    parser.add_argument(
        "--json", action="store_true", help="with --inferred: one JSON document on stdout"
    )
    args = parser.parse_args(argv)
    if args.inferred:
        import json

        from .inferred import inferred_json

        doc = inferred_json()
        if args.json:
            json.dump(doc, sys.stdout, indent=2)
            sys.stdout.write("\n")
        else:
            for fig, entry in doc.items():
                print(
                    f"{fig}: {entry['model']}, "
                    + ", ".join(f"{k} = {v:.6g}" for k, v in entry["params"].items())
                    + "".join(
                        f", {k} = {entry[k]}"
                        for k in ("imbalance", "imbalance_kind", "cubic", "elements")
                        if k in entry
                    )
                )
        return 0
    if args.json:
        print("python -m axojax.paper: error: --json goes with --inferred", file=sys.stderr)
        return 2
    if args.write and (args.fast or args.no_beat):
        print(
            "python -m axojax.paper: error: --write needs the full computation (drop --fast/--no-beat)",
            file=sys.stderr,
        )
        return 2

    from . import FAST, FULL, compute_rows, markdown, write
    from .table import block_of

    if args.write:  # fail before minutes of computing, not after
        try:
            block_of(pathlib.Path(args.readme).read_text())
        except (OSError, ValueError) as err:
            print(f"python -m axojax.paper: error: --readme: {err}", file=sys.stderr)
            return 2
    start = time.perf_counter()
    rows = compute_rows(
        beat=not args.no_beat,
        settings=FAST if args.fast else FULL,
        progress=sys.stderr.isatty(),
        saved_beat=args.beat_npz,
    )
    if args.write:
        try:
            write(rows, args.readme, args.docs)
        except (OSError, ValueError) as err:
            print(f"python -m axojax.paper: error: --docs: {err}", file=sys.stderr)
            return 2
        print(
            f"wrote {args.readme} and {args.docs} ({time.perf_counter() - start:.0f} s)",
            file=sys.stderr,
        )
    else:
        sys.stdout.write(markdown(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
