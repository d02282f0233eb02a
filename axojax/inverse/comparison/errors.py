"""The standard errors of a compare row's fitted values, in physical units, with its pins
as constraints (:func:`physical_stderr`).

A row holds its beat at the observation with two *pins* (growth rate 0 and the observed
frequency, each with the small sigma ``pin_tolerance``: :mod:`.mechanisms`). The pins are
a device to hold the beat there, not data: the error a pin's sigma gives a value is the
tolerance's, not the data's. Two values and two pins (the sliding row's chi' and chi'',
as in Sartori et al.) are fixed by the pins alone; their Laplace standard error is the
tolerance's (a chi' of -3.26e3 pN/um^2 "+- 0.00029"). So the errors are those of the
data with the pins held exactly: the Laplace approximation of the shape's residuals
restricted to the directions the pins leave free (the null space of the pins' Jacobian),
the limit of the row's Laplace approximation as the tolerance goes to 0
(:func:`constrained_covariance`). A value that the pins alone fix has no error from the
data: it is *pinned* (its variance under the constraint is at most :data:`PINNED_SHARE`
of its Laplace variance with the pins' tolerance), reported as such and its error null.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ...units import Units
from ..sampling import Laplace
from .starts import values_to_u
from .table import PHYSICAL

PINNED_SHARE = 1e-8
"""A value is pinned when its variance with the pins held exactly is at most this share of
its variance with the pins' tolerance (0 up to round-off: the pins alone fix it)."""
RANK_TOL = 1e-10
"""Singular values of the pins' (scaled) Jacobian below this share of the largest are 0."""
LOOSE = 1e-12
"""Directions of (scaled) precision below this share of the largest are not determined
(infinite variance), as in :func:`axojax.inverse.sampling.laplace_of`."""


def _covariance(jac: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """(k, k) covariance of the least-squares problem with Jacobian ``jac`` (m, k) within
    the span of ``basis``'s orthonormal columns (k, r): basis (B^T J^T J B)^-1 basis^T,
    inf in the rows and columns of coordinates that a direction of (near) zero precision
    moves."""
    k, r = basis.shape
    if r == 0:
        return np.zeros((k, k))
    jb = jac @ basis
    lam, vec = np.linalg.eigh(jb.T @ jb)
    good = lam > LOOSE * max(float(np.max(np.abs(lam))), 1e-300)
    directions = basis @ vec
    cov = (directions[:, good] / lam[good]) @ directions[:, good].T
    loose = np.any(np.abs(directions[:, ~good]) > 1e-8, axis=1)
    cov[loose, :] = np.inf
    cov[:, loose] = np.inf
    return cov


def constrained_covariance(
    jacobian: np.ndarray, pin_rows: Sequence[int]
) -> tuple[np.ndarray, np.ndarray]:
    """(covariance with the pins held exactly, covariance with their tolerance), both
    (k, k) in the fitted coordinate u, from the Jacobian (m, k) of the normalised
    residuals in u whose rows ``pin_rows`` are the pins'. Columns are scaled to unit norm
    first (a linear chi of 1e5 beside a log kb), as the row's Laplace approximation does;
    a direction the data (or, for the second, data and pins) do not determine gives its
    coordinates infinite variance."""
    jac = np.asarray(jacobian, dtype=float)
    k = jac.shape[1]
    if not np.all(np.isfinite(jac)):
        inf = np.full((k, k), np.inf)
        return inf, inf
    norms = np.sqrt(np.sum(jac**2, axis=0))
    scale = np.where(norms > 0, 1.0 / np.where(norms > 0, norms, 1.0), 1.0)
    scaled = jac * scale
    pins = np.zeros(jac.shape[0], dtype=bool)
    pins[list(pin_rows)] = True
    full = _covariance(scaled, np.eye(k))
    if pins.any():
        _, sing, vt = np.linalg.svd(scaled[pins])
        rank = int(np.sum(sing > RANK_TOL * sing[0])) if sing.size and sing[0] > 0 else 0
        held = _covariance(scaled[~pins], vt[rank:].T)
    else:
        held = full
    outer = np.outer(scale, scale)
    with np.errstate(invalid="ignore"):  # inf x a finite scale stays inf
        return held * outer, full * outer


def pinned_of(held: np.ndarray, full: np.ndarray, names: Sequence[str]) -> list[str]:
    """The names whose variance with the pins held (``held``) is at most
    :data:`PINNED_SHARE` of that with the pins' tolerance (``full``; finite)."""
    return [
        n
        for n, h, f in zip(names, np.diag(held), np.diag(full))
        if math.isfinite(f) and f > 0 and h <= PINNED_SHARE * f
    ]


def physical_stderr(row, units: Units) -> tuple[dict[str, float | None], list[str]]:
    """Standard errors of ``row.physical`` (a :class:`~.compare.CompareRow` with its
    problem and fit) from the data with the pins held exactly (module docstring; the
    Jacobian from the fit's own compiled report program: no new compilation), and the
    physical names of its pinned values (their error None). inf where the data do not
    determine a value; every error None if it cannot be computed."""
    p = row.problem
    try:
        u = values_to_u(p, np.array([[row.fit.params[n] for n in p.names]]))[0]
        jac = p.evaluate(u)["J"]
        lay = p.layout[0]  # a row has one condition: its scalar targets are the pins
        held, full = constrained_covariance(jac, range(lay.start, lay.start + lay.n_scalar))
        at = row.laplace(jacobian=jac)
        sd = Laplace(at.names, at.centre_u, held, at.log_coordinate).sd()
        pinned = set(pinned_of(held, full, at.names))
    except (ValueError, np.linalg.LinAlgError, KeyError):
        return {k: None for k in row.physical}, []
    out, names = {}, []
    for name, v in sd.items():
        if name in PHYSICAL:
            key, conv = PHYSICAL[name]
            if name in pinned:
                out[key] = None
                names.append(key)
                continue
            se = abs(float(v)) if conv is None else abs(float(getattr(units, conv)(v)))
            out[key] = se if math.isfinite(se) else math.inf
    return out, names
