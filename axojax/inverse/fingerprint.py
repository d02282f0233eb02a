"""A problem's fingerprint: a sha256 of everything that determines its residuals
(:meth:`axojax.inverse.Problem.fingerprint`), and the value digest it is made of
(:func:`digest`). The posterior's warm cache (:mod:`axojax.inverse.sampling`) names its
files by it; it lives with the problem, below every solver that uses it."""

from __future__ import annotations

import dataclasses
import enum
import hashlib
from collections.abc import Mapping
from typing import Any

import numpy as np

PROFILE_GRID = 257
"""A profile function (:class:`axojax.fem.Profiles`) is fingerprinted by its values at
this many points of [0, 1] (besides its name): what the model's matrices were built from."""


class Unfingerprintable(TypeError):
    """A part of a problem that cannot be fingerprinted (e.g. a user's callable)."""


def digest(obj: Any) -> str:
    """sha256 (hex) of ``obj``'s value: numbers, strings, arrays (shape, dtype, bytes),
    sequences, mappings, dataclasses and equinox modules (type and fields), enums, and
    axojax's own module-level functions (by name, the source being in the key).
    Raises :class:`Unfingerprintable` for anything else (lambdas, closures, user
    functions, arbitrary objects)."""
    h = hashlib.sha256()
    _feed(h, obj)
    return h.hexdigest()


def _feed(h, obj: Any) -> None:
    import jax

    if obj is None or isinstance(obj, (bool, int, float, complex, str, bytes, np.generic)):
        h.update(f"{type(obj).__name__}:{obj!r};".encode())
    elif isinstance(obj, (np.ndarray, jax.Array)):
        a = np.ascontiguousarray(np.asarray(obj))
        h.update(f"array{a.shape}{a.dtype.str};".encode())
        h.update(a.tobytes())
    elif isinstance(obj, enum.Enum):
        h.update(f"enum:{type(obj).__qualname__}.{obj.name};".encode())
    elif isinstance(obj, (tuple, list)):
        h.update(f"{type(obj).__name__}[{len(obj)}](".encode())
        for x in obj:
            _feed(h, x)
        h.update(b")")
    elif isinstance(obj, Mapping):
        h.update(f"map[{len(obj)}](".encode())
        for key in sorted(obj, key=repr):
            _feed(h, key)
            _feed(h, obj[key])
        h.update(b")")
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        from ..fem.filament import Profiles

        cls = type(obj)
        h.update(f"{cls.__module__}.{cls.__qualname__}(".encode())
        for f in dataclasses.fields(obj):
            value = getattr(obj, f.name)
            h.update(f"{f.name}=".encode())
            if isinstance(obj, Profiles) and callable(value):
                _feed_profile(h, value)
            else:
                _feed(h, value)
        h.update(b")")
    elif callable(obj) and _own_function(obj):
        h.update(f"function:{obj.__module__}.{obj.__qualname__};".encode())
    else:
        raise Unfingerprintable(f"cannot fingerprint a {type(obj).__name__}")


def _own_function(fn) -> bool:
    """A module-level function of axojax (its code is covered by the source digest)."""
    module, name = getattr(fn, "__module__", None) or "", getattr(fn, "__qualname__", "")
    return (
        (module == "axojax" or module.startswith("axojax."))
        and "<" not in name
        and getattr(fn, "__closure__", None) is None
    )


def _feed_profile(h, profile) -> None:
    """A profile function by its values on :data:`PROFILE_GRID` points of [0, 1]."""
    x = np.linspace(0.0, 1.0, PROFILE_GRID)
    try:
        values = np.broadcast_to(np.asarray(profile(x), dtype=float), x.shape)
    except Exception as err:  # noqa: BLE001 - any failure: not fingerprintable
        raise Unfingerprintable(f"profile {profile!r}: {err}") from None
    h.update(b"profile:")
    _feed(h, values)


PROBLEM_FIELDS = (
    "models",
    "conditions",
    "labels",
    "free_shared",
    "free_per_condition",
    "base",
    "bounds",
    "kl_ratio",
    "units",
    "solver",
    "_solvers",
    "cubic",
    "orbit_solver",
    "shape_floor",
    "exclude_base_um",
    "shift",
    "names",
    "lower",
    "upper",
    "u0",
)
"""What :meth:`axojax.inverse.Problem.fingerprint` covers: its models (every array, the
profiles by value), conditions (targets, shapes, fixed parameters, labels), the free
names, base parameters, bounds, tie, units, solvers, shape floor, base exclusion,
shift, and the resulting bounds and start in u."""


def problem_fingerprint(problem) -> str:
    """:meth:`axojax.inverse.Problem.fingerprint`: sha256 of :data:`PROBLEM_FIELDS`;
    ``TypeError`` for a problem with a callable prior, or a part that cannot be
    fingerprinted (:class:`Unfingerprintable`)."""
    if problem.prior is not None:
        raise Unfingerprintable("a problem with a callable prior has no fingerprint")
    cls = type(problem)
    return digest(
        (f"{cls.__module__}.{cls.__qualname__}",)
        + tuple((name, getattr(problem, name)) for name in PROBLEM_FIELDS)
    )
