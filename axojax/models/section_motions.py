"""The cross-section's rigid motions in its own plane, as subspaces of a model's unknowns
(docs/model.md section 8, "Twist"): its rotation Theta(x) (twist) and its translations
w_y(x), w_z(x) (bending), every finite-element shape of each.

Filament f at (y_f, z_f) moves by Theta (-z_f, y_f) in a twist and by (w_y, w_z) in a
bending translation. Projecting the stiffness, damping and static state on these says
whether a preset couples twist and bending at linear order
(benchmarks/check_twist_coupling.py, tests/model/test_twist.py).
"""

from __future__ import annotations

import numpy as np
from jaxtyping import Float

from .section import Model


def section_motions(model: Model) -> tuple[Float[np.ndarray, "n m"], Float[np.ndarray, "n b"]]:
    """(T, B): the columns of T (n, m) span the section's twists, those of B (n, b = 2 m) its
    y then z translations, in the model's unknowns (filament-major: filament f's
    direction d is row block 2 f + d of m finite-element values each; n =
    ``model.n_unknowns``). One-line ``ValueError`` for a planar model (one direction: no
    twist) or one with a border (a base's extra unknowns)."""
    if model.n_dirs != 2:
        raise ValueError(f"model: {model.name!r} is planar (one direction): it has no twist")
    if model.n_border:
        raise ValueError("model: section motions are defined on a clamped base (no border)")
    pos = np.asarray(model.section.positions, dtype=float)
    m = model.n_unknowns // model.n_fd
    eye = np.eye(m)
    T = np.zeros((model.n_unknowns, m))
    B = np.zeros((model.n_unknowns, 2 * m))
    for f, (y, z) in enumerate(pos):
        for d, c in ((0, -z), (1, y)):
            T[(2 * f + d) * m : (2 * f + d + 1) * m] = c * eye
            B[(2 * f + d) * m : (2 * f + d + 1) * m, d * m : (d + 1) * m] = eye
    return T, B
