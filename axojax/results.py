"""One result convention for every solver, as optimistix and diffrax have it.

Every solver's answer carries a ``result`` field: an item of :class:`RESULTS`, an
``equinox.Enumeration`` (a pytree: it passes through ``jit``, ``vmap`` and ``grad``).
``result == RESULTS.successful`` is the one test of success, whatever the solver:

- ``Mode``: successful, invalid_params, nonfinite (``certified`` kept: which solver
  answered);
- ``Critical``: successful, no_crossing, max_steps_reached, invalid_params (``found``
  kept);
- ``LimitCycle``: successful, no_start, nonlinear_max_steps_reached (``converged`` kept);
- ``Trajectory``: diffrax's own codes, promoted (``max_steps_reached``,
  ``dt_min_reached``, ...; ``ok`` kept);
- ``FitResult``: the least-squares solver's, of the best start (optimistix's
  Levenberg-Marquardt codes promoted; ``max_steps_reached`` for the others when they
  stop on their step budget). Whether the targets are reproduced is a separate verdict
  (``targets_met``): a solver can succeed at an optimum that misses them;
- ``Posterior``: successful, chains_not_converged.

``RESULTS`` extends ``diffrax.RESULTS`` (which extends ``optimistix.RESULTS``), so the
codes of an ODE solve or a root find promote into it (``RESULTS.promote(sol.result)``).
``RESULTS[item]`` is the message of an item; :func:`message` gives it for a concrete item
on one line. Functions that can fail take ``throw=``: with ``throw=True`` a failure
raises (``item.error_if``: an error at run time, also under ``jit``); with
``throw=False`` the caller reads ``result``.

Traced inputs (inside ``jit``/``vmap``/``grad``) are not validated when traced (their
values are unknown then): a NaN, infinite, negative or out-of-range parameter gives NaN
outputs and ``result = RESULTS.invalid_params`` (a few elementwise comparisons; no
host callback, so a sweep with one bad point still returns the others). Concrete inputs
are validated first and raise a one-line ``ValueError`` (:meth:`axojax.Params.validate`).
"""

from __future__ import annotations

import diffrax
import optimistix as optx


class RESULTS(diffrax.RESULTS):
    """Result codes of axojax's solvers (module docstring); diffrax's and optimistix's
    codes included."""

    invalid_params = "A parameter is NaN, infinite, out of its range or beyond 1e9 in magnitude (see `axojax.Params.validate`); the numbers are NaN."
    no_crossing = "No Hopf crossing: the dominant eigenvalue's real part stays <= 0 up to `p_max`."
    chains_not_converged = "The posterior's chains are not to be trusted: R-hat above 1.01, too few effective samples or divergent transitions (the posterior's message says which)."
    no_start = "No limit cycle: the Hopf normal form has no small orbit here (subcritical, or not past the Hopf point); start from a nearby orbit."


def message(result: RESULTS | diffrax.RESULTS | optx.RESULTS) -> str:
    """The message of a concrete result item (of :class:`RESULTS` or of an enumeration it
    extends), on one line ("successful" for success)."""
    text = RESULTS.promote(result) if not isinstance(result, RESULTS) else result
    line = " ".join(RESULTS[text].split())
    return line or "successful"


def is_successful(result) -> bool:
    """Whether a concrete result item is ``RESULTS.successful``."""
    return (
        bool(RESULTS.promote(result) == RESULTS.successful)
        if not isinstance(result, RESULTS)
        else bool(result == RESULTS.successful)
    )


def result_name(result: RESULTS) -> str:
    """The name of a concrete :class:`RESULTS` item (``"successful"``, ...), for files;
    ``getattr(RESULTS, name)`` is the item again."""
    result = RESULTS.promote(result) if not isinstance(result, RESULTS) else result
    return next(n for n, item in RESULTS._name_to_item.items() if bool(item == result))
