"""The modes of a posterior sampled by :class:`~.modes.ModeMixture`: the proposal's
components grouped into modes, and each mode's centre and mass (:func:`mode_masses`).

A component is *core* when the log density at its centre is within :data:`REACH` of the
best centre's; the others (wide components that cover tails or a valley) join the mode of
the nearest core component (Mahalanobis distance under its scale). Two core components
are one mode when the log density at the midpoint of their centres is at most
:data:`VALLEY` below the lower of the two (no valley between them), and modes are the
connected groups (single linkage): a curved ridge tiled by overlapping components is one
mode, separated solutions are several. A draw belongs to the mode of its most
responsible component.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np
import scipy.sparse.csgraph
import scipy.special

from ._mixture import TMixture

REACH = 25.0
"""A component whose centre's log density is further than this below the best centre's is
not core (it joins its nearest core component's mode)."""
VALLEY = 3.0
"""Two core components are one mode when the midpoint of their centres is at most this far
below the lower of them in log density."""


def group_components(mix: TMixture, log_density) -> tuple[np.ndarray, int]:
    """(K,) the mode index of each component of ``mix`` (0, 1, ... in order of first
    appearance) and the evaluations spent; ``log_density(z)`` maps points (n, k) in z to
    their log densities (n,) (-inf where the model fails)."""
    mean = np.asarray(mix.mean)
    chol = np.asarray(mix.chol)
    K = len(mean)
    at = np.asarray(log_density(mean), dtype=float)
    at = np.where(np.isfinite(at), at, -np.inf)
    core = at >= np.max(at) - REACH
    pairs = [(i, j) for i in range(K) for j in range(i + 1, K) if core[i] and core[j]]
    mid = (
        np.asarray(
            log_density(np.array([0.5 * (mean[i] + mean[j]) for i, j in pairs])), dtype=float
        )
        if pairs
        else []
    )
    linked = np.zeros((K, K), dtype=bool)
    for (i, j), m in zip(pairs, mid):
        linked[i, j] = np.isfinite(m) and m >= min(at[i], at[j]) - VALLEY
    cores = np.nonzero(core)[0]
    for i in np.nonzero(~core)[0]:  # a tail or valley component: its nearest core's mode
        d = [np.sum(np.linalg.solve(chol[c], mean[i] - mean[c]) ** 2) for c in cores]
        linked[i, cores[int(np.argmin(d))]] = True
    mode = scipy.sparse.csgraph.connected_components(linked, directed=False)[1]
    _, first, inverse = np.unique(mode, return_index=True, return_inverse=True)
    return np.argsort(np.argsort(first))[inverse].astype(int), K + len(pairs)


def mode_masses(
    mix: TMixture,
    draws_z: np.ndarray,
    draws_log_density: np.ndarray,
    last: tuple[np.ndarray, np.ndarray],
    values_of,
    log_density,
) -> tuple[list[dict], int]:
    """Per mode, heaviest first: ``centre`` (the parameter values of its draw of highest
    log density; ``values_of(z)`` maps a point in z to {name: value}), ``log_density``
    there, ``mass`` (its share of the chains' draws ``draws_z`` (n, k)), ``mass_importance``
    (its share of the last adaptive points' normalised weights ``last`` = (z, log_w)) and
    ``components``, heaviest first (modes with neither draws nor weight left out); and the
    evaluations of ``log_density`` spent (:func:`group_components`)."""
    modes, evaluations = group_components(mix, log_density)
    count = int(modes.max()) + 1

    def which(z):
        return modes[np.argmax(np.asarray(mix.responsibilities(jnp.asarray(z))), axis=1)]

    drawn = which(draws_z)
    z_last, log_w = last
    w = scipy.special.softmax(log_w)
    weighed = which(z_last)
    out = []
    for m in range(count):
        inside = drawn == m
        mass = float(np.mean(inside))
        mass_is = float(np.sum(w[weighed == m]))
        if mass == 0.0 and mass_is < 1e-6:
            continue
        best = None
        if np.any(inside):
            i = int(np.argmax(np.where(inside, draws_log_density, -np.inf)))
            best = (values_of(draws_z[i]), float(draws_log_density[i]))
        out.append(
            {
                "centre": None if best is None else best[0],
                "log_density": math.nan if best is None else best[1],
                "mass": mass,
                "mass_importance": mass_is,
                "components": int(np.sum(modes == m)),
            }
        )
    return sorted(out, key=lambda d: -d["mass"]), evaluations
