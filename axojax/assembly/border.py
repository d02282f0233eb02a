"""The border of a base that is not clamped (docs/model.md section 8, bases): node 0's
kept dofs, the basal slidings of basal compliance, a head's or a pivot's drags, coupled to
the node unknowns; used by both assemblers."""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..fem.knots import KnotMatrix, knot_matrix
from ..models.section import Model
from ..params import Params
from .terms import MatrixName, Term, _per_omega0, moment_load, static_couple


class Border(eqx.Module):
    """The border of a base that is not clamped: its couplings with the n node unknowns
    (filament-major) and among themselves (m = ``model.n_border``), and its static load."""

    A_nb: Float[Array, "n m"]
    A_bn: Float[Array, "m n"]
    A_bb: Float[Array, "m m"]
    C_nb: Float[Array, "n m"]
    C_bn: Float[Array, "m n"]
    C_bb: Float[Array, "m m"]
    b: Float[Array, " m"]


def check_base_params(model: Model, params: Params) -> Params:
    """Raise a one-line ``ValueError`` when concrete ``params`` do not suit the model's
    base: with basal compliance the friction ``xib`` must be > 0 (it keeps C regular;
    docs/model.md section 8, bases). Returns ``params``."""
    if model.base.compliance and not isinstance(params.xib, jax.core.Tracer):
        xib = np.asarray(params.xib, dtype=float)
        if not bool(np.all(xib > 0)):
            raise ValueError(
                "parameter xib must be > 0 with basal compliance (it keeps the damping matrix "
                f"regular), got {xib.tolist()!r}"
            )
    return params


def _base_parts(model: Model, name: "MatrixName") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(node-base, base-node, base-base) parts of a filament-level matrix on the mesh
    that keeps node 0's base dofs (they come first: :mod:`axojax.fem.hermite`)."""
    m = model.base_matrices
    if isinstance(name, KnotMatrix):
        X = knot_matrix(model.n_elements, model.base.dofs, name)
    else:
        X = np.asarray(m.F0).T if name == "F0T" else np.asarray(getattr(m, name))
    k = len(model.base.dofs)
    return X[k:, :k], X[:k, k:], X[:k, :k]


@functools.lru_cache(maxsize=64)
def base_vectors(model: Model) -> dict[str, np.ndarray]:
    """Filament-level rows (length k + 2 N_e, base dofs first) of u'(0) (``d0``),
    int phi' = u(1) - u(0) (``g``) and int phi'' = u'(1) - u'(0) (``t``)."""
    rows = {(x, r): model.interpolation(np.array([x]), r)[0] for x in (0.0, 1.0) for r in (0, 1)}
    return {
        "d0": rows[(0.0, 1)],
        "g": rows[(1.0, 0)] - rows[(0.0, 0)],
        "t": rows[(1.0, 1)] - rows[(0.0, 1)],
    }


@functools.lru_cache(maxsize=64)
def rotation_row(model: Model) -> np.ndarray:
    """Filament-level (k + 2 N_e,) dofs (base dofs first) of the rigid rotation u = x about
    x = 0: u'(0) = 1, each node (x_i, 1); ``row @ int p phi'`` is ``int p dx``."""
    N = model.n_elements
    base = [0.0 if dof == 0 else 1.0 for dof in model.base.dofs]
    nodes = np.stack([np.arange(1, N + 1) / N, np.ones(N)], axis=1).ravel()
    return np.concatenate([base, nodes])


def _per_filament(model: Model) -> int:
    """Size of the border before node 0 is shared: node 0's dofs per (filament,
    direction), then the basal slidings (the space :func:`border_terms` sums in)."""
    return model.n_fd * len(model.base.dofs) + model.n_border - model.n_base_dofs


@functools.lru_cache(maxsize=64)
def shared_node_map(model: Model) -> np.ndarray:
    """(per-filament border, border) matrix R: node 0's dof (f, a, j) of every filament f
    is the shared (a, j) (a rigid basal body); the basal slidings map to themselves."""
    k, F, d = len(model.base.dofs), model.n_filaments, model.n_dirs
    R = np.zeros((_per_filament(model), model.n_border))
    for f in range(F):
        for a in range(d):
            for j in range(k):
                R[(f * d + a) * k + j, a * k + j] = 1.0
    rest = model.n_border - model.n_base_dofs
    R[F * d * k :, model.n_base_dofs :] = np.eye(rest)
    return R


def split_border(model: Model, w: np.ndarray, row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vector w (x) row (truss (n_fd,) times filament row (k + 2 N_e,)) as its node
    part (n,) and per-filament border part (basal sliding entries 0)."""
    k = len(model.base.dofs)
    full = np.einsum("i,r->ir", w, row)
    border = np.zeros(_per_filament(model))
    border[: model.n_fd * k] = full[:, :k].ravel()
    return full[:, k:].ravel(), border


def sliding_unit(model: Model, a: int) -> np.ndarray:
    """Per-filament border vector of pair a's basal sliding Delta_b,a."""
    e = np.zeros(_per_filament(model))
    e[model.n_fd * len(model.base.dofs) + a] = 1.0
    return e


def _body_rows(model: Model, dof: int) -> np.ndarray:
    """(d, m) border rows of the basal displacement (``dof`` 0) or slope (``dof`` 1) of
    the shared node 0, in each direction."""
    k = len(model.base.dofs)
    j = model.base.dofs.index(dof)
    rows = np.zeros((model.n_dirs, model.n_border))
    for a in range(model.n_dirs):
        rows[a, a * k + j] = 1.0
    return rows


def border_terms(model: Model, params: Params, A_terms: list[Term], C_terms: list[Term]) -> Border:
    """The border of ``model``'s base (docs/model.md section 8, bases).

    1. Node 0's kept dofs take part in every term of A and C as the mesh's other nodes
       do: the term's truss times the node-base parts of its filament-level matrix.
    2. Regulated dynein with a base that is not clamped: the pair's sliding is
       Delta_a(x) = a0 n_a . (u_bar'(x) - u_bar'(0)) + Delta_b,a, and its force f_a does
       the virtual work -int f_a delta Delta_a dx. The local parts are the D0 and H0
       terms of :func:`mechanism_terms`; the rest couples the base slope u_bar'(0), the
       tip (through int u_bar' = u_bar(1) - u_bar(0), int u_bar'' = u_bar'(1) - u_bar'(0))
       and Delta_b,a, so it lies in the border. With D = w_a (x) u'(0), G = w_a (x) int phi',
       T = w_a (x) int phi'' and e_a the unit vector of Delta_b,a:
       sliding  chi (a0^2 (D D^T - G D^T - D G^T) + a0 ((G - D) e^T + e (G - D)^T) + e e^T),
       curvature beta (e T^T - a0 D T^T); A takes chi', beta', C chi''/omega0, beta''/omega0.
    3. Basal compliance: kb e_a e_a^T in A, xib e_a e_a^T in C (the basal sliding
       equation is then chi_b Delta_b,a = -int f_a dx: a positive kb is a spring).
    4. A head: drags against the basal displacement and slope, in C; a pivot: its spring
       (A) and drag (C) on the basal slope.
    5. The static load b (the dynein couple m(x) per length of :func:`static_couple`, the
       imbalance's and ``m0``): node 0's part of ``int m phi'``, and where the basal slope
       is free (pivot, free, head) the couple's reaction at the basal body, where the
       filaments are joined: ``-int m dx`` on u'(0). Its work is then
       ``int m (u'(x) - u'(0)) dx``, that of the dynein's sliding relative to the base (as
       the regulated force's in 2.), which no rigid motion does: the load has no net force
       or torque (docs/model.md section 8; without it a free axoneme would spin under its
       static moment).

    Node 0 is shared by every filament (a rigid basal body, :attr:`Model.n_base_dofs`):
    1-3 are summed with a dof of node 0 per filament and direction, then contracted with
    the matrix R that maps each to the shared one (R^T X R, virtual work).
    """
    base = model.base
    n, m = model.n_dof, _per_filament(model)
    fa = {"A": [jnp.zeros((n, m)), jnp.zeros((m, n)), jnp.zeros((m, m))]}
    fa["C"] = [jnp.zeros((n, m)), jnp.zeros((m, n)), jnp.zeros((m, m))]
    has_node0 = bool(base.dofs)

    def add(which, nb=None, bn=None, bb=None):
        parts = fa[which]
        for i, x in enumerate((nb, bn, bb)):
            if x is not None:
                parts[i] = parts[i] + x

    # 1. node 0 in every term.
    if has_node0:
        for which, ts in (("A", A_terms), ("C", C_terms)):
            for t, name in ts:
                Xnb, Xbn, Xbb = (jnp.asarray(x) for x in _base_parts(model, name))
                pad = m - model.n_fd * len(base.dofs)
                add(
                    which,
                    nb=jnp.pad(jnp.kron(t, Xnb), ((0, 0), (0, pad))),
                    bn=jnp.pad(jnp.kron(t, Xbn), ((0, pad), (0, 0))),
                    bb=jnp.pad(jnp.kron(t, Xbb), ((0, pad), (0, pad))),
                )

    # 2-3. regulated dynein's non-local parts and the basal sliding.
    if model.pair_B.shape[0] and model.section.load == "pairs":
        vec = base_vectors(model)
        a0 = jnp.asarray(params.a0, dtype=float)
        omega0 = jnp.asarray(params.omega0, dtype=float)
        coeffs = {
            "A": (
                jnp.asarray(params.chi_re, dtype=float),
                jnp.asarray(params.beta_re, dtype=float),
            ),
            "C": (
                _per_omega0(jnp.asarray(params.chi_im, dtype=float), omega0),
                _per_omega0(jnp.asarray(params.beta_im, dtype=float), omega0),
            ),
        }
        for a, w in enumerate(np.asarray(model.pair_w)):
            Dn, Db = split_border(model, w, vec["d0"])
            Gn, Gb = split_border(model, w, vec["g"])
            Tn, Tb = split_border(model, w, vec["t"])
            e = sliding_unit(model, a) if base.compliance else np.zeros(m)
            for which, (chi, beta) in coeffs.items():
                # sliding: chi (a0^2 (D D^T - G D^T - D G^T) + a0 ((G - D) e^T + e (G - D)^T) + e e^T)
                add(
                    which,
                    nb=chi * (a0**2 * (-np.outer(Gn, Db)) + a0 * np.outer(Gn, e)),
                    bn=chi * (a0**2 * (-np.outer(Db, Gn)) + a0 * np.outer(e, Gn)),
                    bb=chi
                    * (
                        a0**2 * (np.outer(Db, Db) - np.outer(Gb, Db) - np.outer(Db, Gb))
                        + a0 * (np.outer(Gb - Db, e) + np.outer(e, Gb - Db))
                        + np.outer(e, e)
                    ),
                )
                # curvature: beta (e T^T - a0 D T^T)
                add(
                    which,
                    bn=beta * (np.outer(e, Tn) - a0 * np.outer(Db, Tn)),
                    bb=beta * (np.outer(e, Tb) - a0 * np.outer(Db, Tb)),
                )
            if base.compliance:
                add("A", bb=jnp.asarray(params.kb, dtype=float) * np.outer(e, e))
                add("C", bb=jnp.asarray(params.xib, dtype=float) * np.outer(e, e))

    # node 0 shared by every filament: R^T (.) R.
    R = jnp.asarray(shared_node_map(model))
    for which in ("A", "C"):
        nb, bn, bb = fa[which]
        fa[which] = [nb @ R, R.T @ bn, R.T @ bb @ R]

    # 4. the body.
    if base.kind == "head":
        for dof, drag in ((0, base.translational_drag), (1, base.rotational_drag)):
            rows = _body_rows(model, dof)
            add("C", bb=drag * rows.T @ rows)
    if base.kind == "pivot":
        rows = _body_rows(model, 1)
        add("A", bb=base.rotational_stiffness * rows.T @ rows)
        add("C", bb=base.rotational_drag * rows.T @ rows)

    b = jnp.zeros(m)
    if has_node0 and model.pair_B.shape[0] and model.section.load == "pairs":
        k = len(base.dofs)
        row = moment_load(model, params, base.dofs)
        f1 = row[:k]
        if 1 in base.dofs:  # 5. the couple's reaction at the basal body (docstring)
            f1 = f1.at[base.dofs.index(1)].add(-jnp.asarray(rotation_row(model)) @ row)
        b = b.at[: model.n_fd * k].set(jnp.kron(static_couple(model, params), f1))
    b = R.T @ b
    (A_nb, A_bn, A_bb), (C_nb, C_bn, C_bb) = fa["A"], fa["C"]
    return Border(A_nb, A_bn, A_bb, C_nb, C_bn, C_bb, b)
