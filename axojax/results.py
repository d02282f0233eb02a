"""One result convention for every solver, as optimistix and diffrax have it.

Every answer a user meets carries a ``result``: an item of :class:`RESULTS`, an
``equinox.Enumeration`` (a pytree: it passes through ``jit``, ``vmap`` and ``grad``).
``result == RESULTS.successful`` is the one test of success, whatever the solver, and
``.message`` is the item's message on one line ("successful" for success):

- :class:`~axojax.eigen.mode.Mode` (:func:`axojax.dominant_mode`): successful,
  invalid_params, nonfinite (``certified`` kept: which solver answered);
- :class:`~axojax.critical.Critical` (:func:`axojax.critical_force`): successful,
  no_crossing, max_steps_reached, invalid_params (``found`` kept);
- :class:`~axojax.orbits.LimitCycle` (:func:`axojax.limit_cycle`): successful, no_start,
  nonlinear_max_steps_reached, rigid_drift (``converged`` kept);
- :class:`~axojax.dynamics.simulate.Simulation` (:func:`axojax.simulate`): diffrax's
  codes, promoted (``max_steps_reached``, ``dt_min_reached``, ...; ``state`` and
  ``meta["solver"]["ok"]`` kept);
- :class:`~axojax.sweeps.SweepResult` (:func:`axojax.sweep`): one code per grid point, a
  :class:`RESULTS` item holding an array (as ``jax.vmap`` of :func:`axojax.dominant_mode`
  gives), and a one-line ``.message`` counting the failures (:func:`summary`).
- :class:`~axojax.inverse.FitResult` (:func:`axojax.fit`): the least-squares solver's,
  of the best start (optimistix's Levenberg-Marquardt codes promoted; ``max_steps_reached``
  for the others when they stop on their step budget). Whether the targets are reproduced
  is a separate verdict (``targets_met``): a solver can succeed at an optimum that misses
  them;
- :class:`~axojax.inverse.Posterior` (:func:`axojax.posterior`): successful,
  chains_not_converged.

``RESULTS`` extends ``diffrax.RESULTS`` (which extends ``optimistix.RESULTS``), so the
codes of an ODE solve or a root find promote into it (``RESULTS.promote(sol.result)``).
``RESULTS[item]`` is the message of an item; :func:`message` gives it on one line.

``throw``: every function that can fail takes ``throw=``, and its default is ``False``
everywhere (:func:`axojax.dominant_mode`, :func:`axojax.critical_force`,
:func:`axojax.limit_cycle`, :func:`axojax.simulate`, :func:`axojax.sweep`): a failure is
data, reported in ``result``. That is the default that fits axojax, whose functions run
inside ``jit``, ``vmap`` and ``grad``: under ``vmap`` one failing point must not discard
the batch (a sweep with one bad point still returns the others), and a run-time error
cannot be caught by type inside a compiled program. Bad *input* is not a result: concrete
arguments are validated first and raise a one-line ``ValueError`` whatever ``throw`` is.
With ``throw=True`` a failure raises: inside the jit-compiled functions
(:func:`~axojax.dominant_mode`, :func:`~axojax.critical_force`) ``item.error_if`` (an
``equinox`` run-time error, also under ``jit``), in the host-side ones
(:func:`~axojax.limit_cycle`, :func:`~axojax.simulate`, :func:`~axojax.sweep`) a
one-line ``ValueError`` saying why.

Plain-Python documents and files: every result type has ``to_json()``, the plain-Python
document of the ``--json`` output it appears in (numbers, strings, lists, dicts, None;
NaN and infinities as None: :func:`jsonable`); the types stored in files
(:class:`~axojax.sweeps.SweepResult`, :class:`~axojax.dynamics.simulate.Simulation`) have
``save(path)`` (written whole, :mod:`axojax._io`) and ``load(path)``, and
``load(path).to_json() == to_json()``. Files store a code by its name (:func:`name`,
:func:`from_names`, :func:`code_names`): the integer codes depend on the installed
diffrax and optimistix. Each type written to a file recognises its own: the ``.npz``
ones' ``read(path)`` is ``load`` with the file checked whole (:func:`file_meta`,
:func:`read_checked`, :func:`check_arrays`: a truncated, damaged or foreign file is one
:class:`ResultFileError`), the JSON reports' ``is_document(doc)`` says whether a document
read back is theirs (:mod:`axojax.plotting.files` draws any of them).

Traced inputs (inside ``jit``/``vmap``/``grad``) are not validated when traced (their
values are unknown then): a NaN, infinite, negative or out-of-range parameter gives NaN
outputs and ``result = RESULTS.invalid_params`` (a few elementwise comparisons; no
host callback, so a sweep with one bad point still returns the others). Concrete inputs
are validated first and raise a one-line ``ValueError`` (:meth:`axojax.Params.validate`).
"""

from __future__ import annotations

import json
import math
import zipfile
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import diffrax
import equinox as eqx
import numpy as np
import optimistix as optx


class RESULTS(diffrax.RESULTS):
    """Result codes of axojax's solvers (module docstring); diffrax's and optimistix's
    codes included."""

    invalid_params = (
        "A parameter is NaN, infinite, out of its range or beyond 1e9 in magnitude (see "
        "`axojax.Params.validate`); the numbers are NaN."
    )
    no_crossing = "No Hopf crossing: the dominant eigenvalue's real part stays <= 0 up to `p_max`."
    chains_not_converged = (
        "The posterior's chains are not to be trusted: R-hat above 1.01, too few effective "
        "samples or divergent transitions (the posterior's message says which)."
    )
    no_start = (
        "No limit cycle: the Hopf normal form has no small orbit here (subcritical, or not "
        "past the Hopf point); start from a nearby orbit."
    )
    rigid_drift = (
        "No periodic orbit: on this base, which lets the axoneme move rigidly, the static load "
        "has a net force or torque, so the beat drifts (docs/model.md section 8; "
        "`LimitCycle.rigid_drift`)."
    )


NAMES: tuple[str, ...] = tuple(
    sorted(RESULTS._name_to_item, key=lambda n: int(RESULTS._name_to_item[n]._value))
)
"""Every item's name, in code order (``NAMES[code]``)."""


def _as_results(result) -> RESULTS:
    return result if isinstance(result, RESULTS) else RESULTS.promote(result)


def codes(result) -> np.ndarray:
    """The integer codes of a concrete item (a 0-d array for one result, an array of the
    batch's shape for a vmapped one or a sweep's)."""
    return np.asarray(_as_results(result)._value)


def from_codes(values) -> RESULTS:
    """The :class:`RESULTS` item holding integer ``values`` (any shape), e.g. codes taken
    out of a batch."""
    values = np.asarray(values, dtype=np.int32)
    if values.size and (values.min() < 0 or values.max() >= len(NAMES)):
        raise ValueError(f"result codes must be in 0..{len(NAMES) - 1}, got {values.min()}")
    return eqx.tree_at(lambda item: item._value, RESULTS.successful, values)


def name(result) -> str:
    """The name of a concrete one-point item (``"successful"``, ``"no_crossing"``, ...):
    how files store it."""
    return NAMES[int(codes(result))]


def from_names(names: str | Sequence[str] | np.ndarray) -> RESULTS:
    """The item (or array item) of a stored name (or array of names)."""
    arr = np.asarray(names, dtype=str)
    unknown = sorted(set(arr.ravel().tolist()) - set(NAMES))
    if unknown:
        raise ValueError(f"unknown result name {unknown[0]!r}; known: {', '.join(NAMES)}")
    index = {n: i for i, n in enumerate(NAMES)}
    return from_codes(np.vectorize(index.__getitem__, otypes=[np.int32])(arr))


def code_names() -> dict[str, str]:
    """``{"0": "successful", "1": "max_steps_reached", ...}``: the code table a file
    stores next to an array of codes (a sweep's ``meta["result"]``)."""
    return {str(i): n for i, n in enumerate(NAMES)}


def recode(values, table: Mapping[str, str]) -> RESULTS:
    """The item of codes ``values`` written with the code table ``table``
    (:func:`code_names` of the writer), mapped to this installation's codes."""
    values = np.asarray(values)
    unknown = sorted({str(int(c)) for c in np.unique(values)} - set(table))
    if unknown:
        raise ValueError(f"result code {unknown[0]} is not in the code table {dict(table)}")
    lookup = np.vectorize(lambda c: table[str(int(c))], otypes=[object])
    return from_names(lookup(values).astype(str) if values.size else values.astype(str))


def message(result: RESULTS | diffrax.RESULTS | optx.RESULTS) -> str:
    """The message of a concrete result item on one line ("successful" for success); for
    an array item (a batch, a sweep), :func:`summary`."""
    item = _as_results(result)
    if np.ndim(item._value):
        return summary(item)
    line = " ".join(RESULTS[item].split())
    return line or "successful"


def summary(result) -> str:
    """One line on an array of results: ``"all 12 successful"``, or how many failed, by
    name, with the first failure's message, e.g. ``"2 of 12 failed (invalid_params 2):
    A parameter is NaN, ..."``."""
    values = codes(result).ravel()
    n = values.size
    failed = values[values != 0]
    if not failed.size:
        return f"all {n} successful"
    kinds, counts = np.unique(failed, return_counts=True)
    by_name = ", ".join(f"{NAMES[k]} {c}" for k, c in zip(kinds, counts))
    first = message(from_codes(failed[0]))
    return f"{failed.size} of {n} failed ({by_name}): {first}"


def jsonable(obj: Any) -> Any:
    """``obj`` as plain Python for ``json.dumps(..., allow_nan=False)``: arrays and numpy
    scalars to lists and numbers, NaN and infinities to None (what every ``to_json``
    returns)."""
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray) or hasattr(obj, "__array__"):
        arr = np.asarray(obj)
        return jsonable(arr.tolist() if arr.ndim else arr.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def is_successful(result) -> bool:
    """Whether a concrete result item (every point of an array item) is
    ``RESULTS.successful``."""
    return bool(np.all(codes(result) == 0))


class ResultFileError(ValueError):
    """A file that is not the whole axojax result it should be, in one line naming it in
    quotes (``axojax plot`` puts ``FILE:`` before it)."""


READ_ERRORS = (
    OSError,
    EOFError,
    KeyError,
    ValueError,
    TypeError,
    AttributeError,
    IndexError,
    zipfile.BadZipFile,
)
"""What a truncated, damaged or foreign file raises on the way in (numpy's zip reader,
the JSON meta, the arrays)."""


def _first_line(err: BaseException) -> str:
    return f"{type(err).__name__}: {str(err).splitlines()[0] if str(err) else 'no detail'}"


def file_meta(path) -> dict:
    """The ``meta`` of an ``.npz`` file axojax wrote: a JSON object (its ``kind`` names
    the result: ``"simulation"``, ``"orbit_branch"``, ``"posterior"``; a sweep's has
    none); :class:`ResultFileError` for anything else."""
    where = repr(str(path))
    if not zipfile.is_zipfile(path):
        raise ResultFileError(
            f"{where} is not an .npz file (no zip archive: truncated, damaged or another "
            "format); rerun the command that wrote it"
        )
    try:
        with np.load(path, allow_pickle=False) as f:
            if "meta" not in f.files:
                raise ResultFileError(
                    f"{where} is not an axojax file (no 'meta' entry; it holds "
                    f"{', '.join(f.files) or 'nothing'})"
                )
            text = str(f["meta"])
    except ResultFileError:
        raise
    except READ_ERRORS as err:
        raise ResultFileError(
            f"{where} cannot be read as an .npz file: truncated or damaged ({_first_line(err)}); "
            "rerun the command that wrote it"
        ) from None
    try:
        meta = json.loads(text)
    except ValueError:
        raise ResultFileError(
            f"{where} has a 'meta' entry that is not JSON: not an axojax file"
        ) from None
    if not isinstance(meta, dict):
        raise ResultFileError(
            f"{where} has a 'meta' entry that is a JSON {type(meta).__name__}, not an "
            "object: not an axojax file"
        )
    return meta


def check_arrays(path, kind: str, arrays: Mapping[str, Any], expect: Mapping[str, tuple]) -> None:
    """Each array of ``arrays`` non-empty and of its ``expect`` shape (None: any length);
    :class:`ResultFileError` naming the first that is not."""
    for key, shape in expect.items():
        a = np.asarray(arrays[key])
        if (
            a.ndim != len(shape)
            or any(s is not None and n != s for n, s in zip(a.shape, shape))
            or a.size == 0
        ):
            raise ResultFileError(
                f"{str(path)!r} is a {kind} file whose {key!r} array has shape {a.shape}, "
                f"expected {tuple('*' if s is None else s for s in shape)} (non-empty)"
            )


def read_checked(path, kind: str, read: Callable[[Any], Any]) -> Any:
    """``read(path)``, with what a truncated or damaged file raises on the way in one
    :class:`ResultFileError` naming the file (``kind``: what it claims to be)."""
    try:
        return read(path)
    except ResultFileError:
        raise
    except READ_ERRORS as err:
        raise ResultFileError(
            f"{str(path)!r} is a {kind} file that cannot be read whole ({_first_line(err)}); "
            "rerun the command that wrote it"
        ) from None
