"""System assembly: C, A, b of ``C dq/dt + A q = b`` as pure functions of Params.

docs/model.md section 3::

    A = K_bend + K_link + K_theta + K_G - P_follow - P_gain (+ regulated dynein, section 8)
    C = C_fluid + C_link (+ regulated dynein's friction, section 8)

Each term is a small truss matrix over (filament, direction) pairs, built from the
model's static arrays and the traced parameters, Kronecker-multiplied by a
filament-level matrix (:func:`terms`). They are summed either as dense matrices in
filament-major order (:func:`assemble`) or as node blocks in node-major order
(:func:`assemble_blocks`, block-tridiagonal: what the structured eigen-solver uses). No
Python loop runs over elements or grid points: both are jit-able and vmap-able in
``params``.
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .linalg import BlockTridiagonal
from .models.section import Model
from .params import Params


class System(eqx.Module):
    """Assembled system ``C dq/dt + A q = b``; N = ``model.n_unknowns`` = n + m: the
    n = ``model.n_dof`` node unknowns (filament-major), then the m = ``model.n_border``
    unknowns of a base that is not clamped (m = 0 for the clamped base).

    Attributes:
        C: (N, N) damping (drag + link damping; symmetric positive definite with the
            steady load).
        A: (N, N) non-symmetric stiffness-minus-load matrix.
        b: (N,) static load (the constant dynein moment; zero when moments cancel).
    """

    C: Float[Array, "N N"]
    A: Float[Array, "N N"]
    b: Float[Array, " N"]


def imbalanced_forces(model: Model, params: Params) -> Float[Array, " P"]:
    """p_a of an R : 1 force ratio (R = ``params.imbalance``): p for group 0, p / R for
    group 1. Its moments give the static load b in both readings of the imbalance."""
    p = jnp.asarray(params.p, dtype=float)
    scale = jnp.where(
        jnp.asarray(model.pair_group) == 0, 1.0, 1.0 / jnp.asarray(params.imbalance, dtype=float)
    )
    return p * scale


def pair_forces(model: Model, params: Params) -> Float[Array, " P"]:
    """Force p_a on each active pair, as it enters A: :func:`imbalanced_forces` in the
    force reading of the imbalance, p on every pair in the moment reading
    (``model.imbalance_kind``, docs/model.md section 3)."""
    if model.imbalance_kind == "force":
        return imbalanced_forces(model, params)
    p = jnp.asarray(params.p, dtype=float)
    return p * jnp.ones(model.pair_group.shape)


def static_couple(model: Model, params: Params) -> Float[Array, " n_fd"]:
    """The constant dynein couple per unit length on each (filament, direction),
    ``a0 sum_a p_a w_a`` with the R : 1 forces of :func:`imbalanced_forces` (both readings):
    zero for balanced presets at R = 1; at R != 1 the net couple p a0 (1 - 1/R) of group 0's
    pairs (docs/model.md section 3, asymmetric beats)."""
    return params.a0 * jnp.einsum(
        "a,ai->i", imbalanced_forces(model, params), jnp.asarray(model.pair_w)
    )


def link_stiffness(model: Model, params: Params) -> Float[Array, " E"]:
    """k_e of each link: k_s for spokes, k_l (times inactive_factor if not active) otherwise."""
    ring = jnp.where(model.link_is_active, 1.0, params.inactive_factor) * params.kl
    return jnp.where(model.link_is_spoke, params.ks, ring)


def bending_rigidity(model: Model, params: Params) -> Float[Array, " n_fd"]:
    """EI_{f,a}: filament rigidity, times ``out_of_plane`` in the z direction."""
    per_dir = (
        jnp.array([1.0, 0.0])[: model.n_dirs]
        + jnp.array([0.0, 1.0])[: model.n_dirs] * params.out_of_plane
    )
    return (jnp.asarray(model.section.ei)[:, None] * per_dir[None, :]).ravel()


def _truss(rows: Float[Array, "E n_fd"], weights: Float[Array, " E"]) -> Float[Array, "n_fd n_fd"]:
    """sum_e w_e B_e B_e^T."""
    return jnp.einsum("e,ei,ej->ij", weights, rows, rows)


def _per_omega0(value: Array, omega0: Array) -> Array:
    """value / omega0, 0 where omega0 <= 0 (there value must be 0: Params.validate), with
    a finite derivative everywhere."""
    positive = omega0 > 0
    return jnp.where(positive, value / jnp.where(positive, omega0, 1.0), 0.0)


def mechanism_terms(model: Model, params: Params) -> tuple[list["Term"], list["Term"]]:
    """The regulated dynein's terms of A and of C (docs/model.md, regulated dynein).

    Each active pair a gets a motor force per length f_a, which enters only through its
    couple a0 f_a on u_bar = (u_i + u_j)/2, as the virtual work -int a0 f_a n_a . delta
    u_bar' dx: the sign that makes a positive chi' a passive shear stiffness (the
    two-filament continuum limit is then Sartori et al. 2016's equations with their chi
    and beta; section 3's "+" for the steady couple would make it a negative one). With
    n_a . u_bar = w_a . U (w_a holds n_a / 2 at i and j, ``model.pair_w``) and the clamped
    base (no basal sliding):

    - sliding, Delta_a = a0 n_a . u_bar': A += a0^2 chi' (w w^T) (x) D0,
      C += a0^2 (chi''/omega0) (w w^T) (x) D0;
    - curvature, kappa_a = n_a . u_bar'': A += a0 beta' (w w^T) (x) H0,
      C += a0 (beta''/omega0) (w w^T) (x) H0, with H0 = int phi' phi''^T.

    At lambda = i omega0 the sum A + lambda C holds chi' + i chi'' and beta' + i beta''
    exactly. All coefficients 0 (the default): every term is zero.

    Returns:
        (A terms, C terms), each a list of (truss (n_fd, n_fd), filament-matrix name).
    """
    w = jnp.asarray(model.pair_w)
    ww = jnp.einsum("ai,aj->ij", w, w)
    a0 = jnp.asarray(params.a0, dtype=float)
    omega0 = jnp.asarray(params.omega0, dtype=float)
    chi_re = jnp.asarray(params.chi_re, dtype=float)
    beta_re = jnp.asarray(params.beta_re, dtype=float)
    chi_d = _per_omega0(jnp.asarray(params.chi_im, dtype=float), omega0)
    beta_d = _per_omega0(jnp.asarray(params.beta_im, dtype=float), omega0)
    stiff = [(a0**2 * chi_re * ww, "D0"), (a0 * beta_re * ww, "H0")]
    damp = [(a0**2 * chi_d * ww, "D0"), (a0 * beta_d * ww, "H0")]
    return stiff, damp


Term = tuple[Float[Array, "n_fd n_fd"], str]
"""One term of a system matrix: a truss matrix over (filament, direction) pairs and the
name of the filament-level matrix it multiplies (a field of
:class:`axojax.fem.FilamentMatrices`): the term is ``kron(truss, matrix)``."""


def terms(model: Model, params: Params) -> tuple[list[Term], list[Term], Float[Array, " n"]]:
    """The terms of A and C and the load b (filament-major) at ``params``.

    The single source of the equations (docs/model.md section 3): :func:`assemble` sums the
    terms as dense Kronecker products, :func:`assemble_blocks` as node blocks.
    """
    m = model.matrices
    nfd = model.n_fd
    drag = jnp.repeat(jnp.asarray(model.section.drag, dtype=float), model.n_dirs)
    ei = bending_rigidity(model, params)
    p = jnp.asarray(params.p, dtype=float)
    eye = jnp.eye(nfd)

    C_terms: list[Term] = [(jnp.diag(drag), "M0")]
    A_terms: list[Term] = [(jnp.diag(ei), "K0")]
    b = jnp.zeros(model.n_dof)

    if model.link_B.shape[0]:
        B = jnp.asarray(model.link_B)
        C_terms.append((_truss(B, jnp.full(B.shape[0], 1.0) * params.cl), "M0"))
        A_terms.append((_truss(B, link_stiffness(model, params)), "Mk"))
        A_terms.append((params.ktheta * jnp.asarray(model.theta_laplacian), "D0"))

    load = model.section.load
    if load == "distributed":
        # Unbalanced distributed follower load on every filament: K0 - p G0 + p F0.
        A_terms += [(p * eye, "F0"), (-p * eye, "G0")]
    elif load == "tip":
        # Beck's column: constant compression P and tip transverse force -P u'(1).
        A_terms += [(p * eye, "tip"), (-p * eye, "D0")]
    elif model.pair_B.shape[0]:
        pa = pair_forces(model, params)
        nu = jnp.einsum("a,ai->i", pa, jnp.asarray(model.pair_sign))
        follow = jnp.einsum("a,aij->ij", pa, jnp.asarray(model.pair_follow))
        gain = params.gamma * jnp.einsum(
            "a,ai,aj->ij", pa, jnp.asarray(model.pair_w), jnp.asarray(model.pair_B)
        )
        A_terms += [(jnp.diag(nu), "G0"), (-follow, "F0"), (-gain, "F0T")]
        b = jnp.kron(static_couple(model, params), jnp.asarray(m.f1))
        stiff, damp = mechanism_terms(model, params)
        A_terms += stiff
        C_terms += damp
    return A_terms, C_terms, b


def _filament_matrix(model: Model, name: str) -> np.ndarray:
    m = model.matrices
    return np.asarray(m.F0).T if name == "F0T" else np.asarray(getattr(m, name))


def assemble(model: Model, params: Params) -> System:
    """Assemble C, A, b for ``model`` at ``params`` (docs/model.md section 3).

    Args:
        model: static structure (mesh, topology, base), e.g. ``ax.models.seven()``.
        params: dimensionless parameters; may be traced.

    Returns:
        :class:`System` with dense (N, N) matrices, N = ``model.n_unknowns``: the node
        unknowns filament-major, then the base's border (:mod:`axojax.models.base`).
    """
    A_terms, C_terms, b = terms(model, params)

    def total(ts: list[Term]) -> Array:
        return sum(jnp.kron(t, jnp.asarray(_filament_matrix(model, name))) for t, name in ts)

    A, C = total(A_terms), total(C_terms)
    if not model.n_border:
        return System(C=C, A=A, b=b)
    border = border_terms(model, params, A_terms, C_terms)

    def bordered(nn, nb, bn, bb):
        return jnp.concatenate(
            [jnp.concatenate([nn, nb], axis=1), jnp.concatenate([bn, bb], axis=1)], axis=0
        )

    return System(
        C=bordered(C, border.C_nb, border.C_bn, border.C_bb),
        A=bordered(A, border.A_nb, border.A_bn, border.A_bb),
        b=jnp.concatenate([b, border.b]),
    )


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
                f"parameter xib must be > 0 with basal compliance (it keeps the damping matrix regular), got {xib.tolist()!r}"
            )
    return params


def _base_parts(model: Model, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(node-base, base-node, base-base) parts of a filament-level matrix on the mesh
    that keeps node 0's base dofs (they come first: :mod:`axojax.fem.hermite`)."""
    m = model.base_matrices
    X = np.asarray(m.F0).T if name == "F0T" else np.asarray(getattr(m, name))
    k = len(model.base.dofs)
    return X[k:, :k], X[:k, k:], X[:k, :k]


@functools.lru_cache(maxsize=64)
def _base_vectors(model: Model) -> dict[str, np.ndarray]:
    """Filament-level rows (length k + 2 N_e, base dofs first) of u'(0) (``d0``),
    int phi' = u(1) - u(0) (``g``) and int phi'' = u'(1) - u'(0) (``t``)."""
    rows = {(x, r): model.interpolation(np.array([x]), r)[0] for x in (0.0, 1.0) for r in (0, 1)}
    return {
        "d0": rows[(0.0, 1)],
        "g": rows[(1.0, 0)] - rows[(0.0, 0)],
        "t": rows[(1.0, 1)] - rows[(0.0, 1)],
    }


def _per_filament(model: Model) -> int:
    """Size of the border before node 0 is shared: node 0's dofs per (filament,
    direction), then the basal slidings (the space :func:`border_terms` sums in)."""
    return model.n_fd * len(model.base.dofs) + model.n_border - model.n_base_dofs


@functools.lru_cache(maxsize=64)
def _shared(model: Model) -> np.ndarray:
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


def _split(model: Model, w: np.ndarray, row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vector w (x) row (truss (n_fd,) times filament row (k + 2 N_e,)) as its node
    part (n,) and per-filament border part (basal sliding entries 0)."""
    k = len(model.base.dofs)
    full = np.einsum("i,r->ir", w, row)
    border = np.zeros(_per_filament(model))
    border[: model.n_fd * k] = full[:, :k].ravel()
    return full[:, k:].ravel(), border


def _sliding_unit(model: Model, a: int) -> np.ndarray:
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
        vec = _base_vectors(model)
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
            Dn, Db = _split(model, w, vec["d0"])
            Gn, Gb = _split(model, w, vec["g"])
            Tn, Tb = _split(model, w, vec["t"])
            e = _sliding_unit(model, a) if base.compliance else np.zeros(m)
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
    R = jnp.asarray(_shared(model))
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
        f1 = np.asarray(model.base_matrices.f1)[:k]
        b = b.at[: model.n_fd * k].set(jnp.kron(static_couple(model, params), jnp.asarray(f1)))
    b = R.T @ b
    (A_nb, A_bn, A_bb), (C_nb, C_bn, C_bb) = fa["A"], fa["C"]
    return Border(A_nb, A_bn, A_bb, C_nb, C_bn, C_bb, b)


class BlockSystem(eqx.Module):
    """The system ``C dq/dt + A q = b`` in node-major order (see :func:`node_major`):
    A and C block-tridiagonal with N_e node blocks of size b = 2 F d, and a border of
    m = ``model.n_border`` unknowns after the n node unknowns (a base that is not
    clamped; m = 0 gives arrays of shape (n, 0), (0, n), (0, 0)).

    Attributes:
        C, A: the node-node blocks.
        A_nb, C_nb: (n, m) node (node-major) to border couplings; A_bn, C_bn: (m, n);
            A_bb, C_bb: (m, m).
        b: (n + m,) static load, node-major, then the border.
    """

    C: BlockTridiagonal
    A: BlockTridiagonal
    b: Float[Array, " N"]
    A_nb: Float[Array, "n m"]
    A_bn: Float[Array, "m n"]
    A_bb: Float[Array, "m m"]
    C_nb: Float[Array, "n m"]
    C_bn: Float[Array, "m n"]
    C_bb: Float[Array, "m m"]


@functools.lru_cache(maxsize=64)
def _node_blocks(model: Model, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(lower, diag, upper) 2 x 2 node blocks of a filament-level matrix (Hermite
    elements couple neighbouring nodes only: the matrix is block-tridiagonal)."""
    M = _filament_matrix(model, name)
    N = model.n_elements
    blocks = M.reshape(N, 2, N, 2).transpose(0, 2, 1, 3)  # (N, N, 2, 2)
    k = np.arange(N)
    outside = blocks.copy()
    outside[k, k] = 0
    outside[k[1:], k[:-1]] = 0
    outside[k[:-1], k[1:]] = 0
    if np.any(outside != 0):
        raise AssertionError(f"filament matrix {name} is not block-tridiagonal")
    return blocks[k[1:], k[:-1]], blocks[k, k], blocks[k[:-1], k[1:]]


@functools.lru_cache(maxsize=64)
def node_major(model: Model) -> np.ndarray:
    """Permutation ``perm`` with ``q_node_major = q[perm]``: node k, then filament and
    direction (f, a), then (u, u') — the order of :class:`BlockSystem`."""
    N, nfd = model.n_elements, model.n_fd
    fd, node, r = np.meshgrid(
        np.arange(nfd), np.arange(N), np.arange(2), indexing="ij"
    )  # filament-major shape
    index = fd * 2 * N + node * 2 + r  # (nfd, N, 2): filament-major flat index
    return np.ascontiguousarray(index.transpose(1, 0, 2).reshape(-1))


def _grouped(ts: list[Term]) -> tuple[tuple[str, ...], Float[Array, "g n_fd n_fd"]]:
    """Terms summed per filament-level matrix: (names, stacked truss matrices)."""
    names = tuple(dict.fromkeys(name for _, name in ts))
    trusses = jnp.stack([sum(t for t, nm in ts if nm == name) for name in names])
    return names, trusses


@functools.lru_cache(maxsize=64)
def _stacked_node_blocks(model: Model, names: tuple[str, ...]) -> np.ndarray:
    """(g, 3 N_e - 2, 2, 2): the lower, diagonal and upper node blocks of each named
    filament-level matrix, concatenated along the block axis."""
    return np.stack([np.concatenate(_node_blocks(model, name)) for name in names])


def assemble_blocks(model: Model, params: Params) -> BlockSystem:
    """Assemble A, C (block-tridiagonal, node-major) and b (node-major) at ``params``;
    the same terms as :func:`assemble`, at O(N_e (F d)^2) memory instead of O((N_e F d)^2)."""
    A_terms, C_terms, b = terms(model, params)
    N, bs = model.n_elements, 2 * model.n_fd

    def total(ts: list[Term]) -> BlockTridiagonal:
        names, trusses = _grouped(ts)
        blocks = jnp.asarray(_stacked_node_blocks(model, names))
        # One contraction over the filament-level matrices: block (i a, j b) of node pair
        # k is sum_g truss_g[i, j] * node_block_g[k][a, b].
        out = jnp.einsum("gij,gkab->kiajb", trusses, blocks).reshape(-1, bs, bs)
        return BlockTridiagonal(out[: N - 1], out[N - 1 : 2 * N - 1], out[2 * N - 1 :])

    perm = node_major(model)
    n, m = model.n_dof, model.n_border
    if m:
        border = border_terms(model, params, A_terms, C_terms)
    else:
        empty = jnp.zeros((0, 0))
        border = Border(
            jnp.zeros((n, 0)),
            jnp.zeros((0, n)),
            empty,
            jnp.zeros((n, 0)),
            jnp.zeros((0, n)),
            empty,
            jnp.zeros(0),
        )
    return BlockSystem(
        C=total(C_terms),
        A=total(A_terms),
        b=jnp.concatenate([b[perm], border.b]) if m else b[perm],
        A_nb=border.A_nb[perm],
        A_bn=border.A_bn[:, perm],
        A_bb=border.A_bb,
        C_nb=border.C_nb[perm],
        C_bn=border.C_bn[:, perm],
        C_bb=border.C_bb,
    )
