"""The command line's plain values: the one-line user error and the parsers every
command's flags share (numbers, pairs, units)."""

from __future__ import annotations

import argparse
import math

from ..units import Units


class CLIError(Exception):
    """A user error, reported as one line on stderr."""


def finite_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def _complex_pair(text: str, flag: str) -> tuple[float, float]:
    """``RE,IM`` of the flag ``--{flag}`` (named without its dashes)."""
    return _pair(text, f"--{flag}", "RE,IM")


def _pair(text: str, flag: str, form: str = "two numbers X,Y") -> tuple[float, float]:
    """Two finite numbers ``X,Y`` (one line naming ``flag``, with dashes, otherwise;
    ``form`` says what was expected)."""
    parts = text.split(",")
    try:
        if len(parts) != 2:
            raise argparse.ArgumentTypeError(f"expected {form}, got {text!r}")
        return finite_float(parts[0]), finite_float(parts[1])
    except argparse.ArgumentTypeError as err:
        raise CLIError(f"{flag}: {err}") from None


def units_from_args(args: argparse.Namespace) -> Units:
    try:
        return Units(args.length_um, args.ei, args.cn)
    except ValueError as err:
        name = str(err).split()[1]
        flag = {"length_um": "--length-um", "ei_pn_um2": "--ei", "cn_pn_s_um2": "--cn"}.get(
            name, "units"
        )
        raise CLIError(f"{flag}: {err}") from None
