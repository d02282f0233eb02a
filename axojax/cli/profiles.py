"""Command-line flags of the non-uniform profiles (docs/model.md section 8): EI(x), drag
c(x) and dynein force p(x) as relative values at knots along x."""

from __future__ import annotations

import argparse

import numpy as np

from ..fem.knots import check_knots
from ._values import CLIError, finite_float

PROFILE_FLAGS = {"ei-knots": "ei_knots", "drag-knots": "drag_knots", "p-knots": "p_knots"}
"""Flag -> :class:`~axojax.Params` field of each knot profile."""
_WHAT = {
    "ei-knots": "bending stiffness EI(x)",
    "drag-knots": "fluid drag c(x)",
    "p-knots": "dynein force p(x) (the steady load)",
}


def add_profile_flags(group) -> None:
    """``--ei-knots``, ``--drag-knots``, ``--p-knots`` and ``--knots`` on ``group``."""
    for flag, what in _WHAT.items():
        group.add_argument(
            f"--{flag}",
            default=None,
            metavar="V0,V1,...",
            help=f"non-uniform {what}: relative values (1 = uniform) at knots along x, linear between "
            "them; K >= 2 values at K equally spaced knots from base to tip, or at --knots",
        )
    group.add_argument(
        "--knots",
        default=None,
        metavar="X0,...,1",
        help="positions x/L of the profiles' knots, increasing from 0 to 1 (default: equally spaced)",
    )


def _numbers(text: str, flag: str) -> np.ndarray:
    try:
        return np.array([finite_float(t) for t in text.split(",")])
    except argparse.ArgumentTypeError as err:
        raise CLIError(f"{flag}: {err}") from None


def knots_from_args(args: argparse.Namespace) -> tuple[float, ...] | None:
    """The ``--knots`` positions (checked), or None."""
    text = getattr(args, "knots", None)
    if text is None:
        return None
    try:
        return check_knots(_numbers(text, "--knots"), "knot positions")
    except ValueError as err:
        raise CLIError(f"--knots: {err}") from None


def profile_values(args: argparse.Namespace) -> dict[str, np.ndarray]:
    """The knot profiles given on the command line, by Params field; a one-line
    :class:`CLIError` naming the flag for a count that differs from ``--knots`` (the
    values themselves are checked with the other parameters, by
    :func:`axojax.cli.common.check_params`)."""
    knots = knots_from_args(args)
    out = {}
    for flag, field in PROFILE_FLAGS.items():
        text = getattr(args, field, None)
        if text is None:
            continue
        values = _numbers(text, f"--{flag}")
        if knots is not None and values.size != len(knots):
            raise CLIError(
                f"--{flag}: {values.size} values, but --knots gives {len(knots)} positions"
            )
        out[field] = values
    if knots is not None and not out:
        raise CLIError(
            "--knots: places the knots of --ei-knots, --drag-knots or --p-knots; give one"
        )
    return out
