"""The terms of ``C dq/dt + A q = b`` (docs/model.md sections 3 and 8): each a truss matrix
over (filament, direction) pairs times a filament-level matrix, as pure functions of the
model's static arrays and the traced :class:`~axojax.Params`; knot profiles (non-uniform
EI, drag and p) enter as sums over knot matrices (:mod:`axojax.fem.knots`)."""

from __future__ import annotations

from typing import Union

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..fem.knots import KnotMatrix, knot_matrices, knot_matrix
from ..models.section import Model
from ..params import NORMAL_NAMES, Params


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
    pairs (docs/model.md section 3, asymmetric beats); plus the static moment ``m0``
    (:func:`static_moment_direction`)."""
    couple = params.a0 * jnp.einsum(
        "a,ai->i", imbalanced_forces(model, params), jnp.asarray(model.pair_w)
    )
    return couple + jnp.asarray(params.m0, dtype=float) * static_moment_direction(model)


def static_moment_direction(model: Model) -> np.ndarray:
    """(n_fd,) the couple per unit of ``Params.m0`` on each (filament, direction): active
    group 0's pairs' ``sum_a w_a``, scaled so that the net couple on the cross-section
    (summed over filaments) has magnitude 1. So m0 is the net static moment per length,
    in the direction of an imbalance R > 1's couple p a0 (1 - 1/R); zeros for a model
    without active pairs. Static (numpy)."""
    w = np.asarray(model.pair_w, dtype=float)
    group0 = w[np.asarray(model.pair_group) == 0].sum(axis=0) if w.size else np.zeros(w.shape[-1])
    net = group0.reshape(-1, model.n_dirs).sum(axis=0)
    norm = float(np.linalg.norm(net))
    return group0 / norm if norm > 0 else np.zeros_like(group0)


def refuse_normal_force(params: Params) -> Params:
    """One-line ``ValueError`` where a concrete ``params`` has a non-zero normal-force gain:
    the plain system (:func:`~axojax.assembly.assemble` and the eigen-solvers on it) has no
    unknowns for the pairs' forces, and would drop it. Traced values pass. Returns
    ``params``."""
    for name in NORMAL_NAMES:
        value = getattr(params, name)
        if isinstance(value, jax.core.Tracer):
            continue
        if bool(np.any(np.asarray(value, dtype=float) != 0)):
            raise ValueError(
                f"parameter {name} is {np.asarray(value).tolist()!r}: normal-force control has unknowns of its own, "
                "solve it with axojax.assembly.normal_force (or axojax modes --mechanism normal-force)"
            )
    return params


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


MatrixName = Union[str, KnotMatrix]
"""A filament-level matrix's name: a field of :class:`axojax.fem.FilamentMatrices` (or
``"F0T"``, F0's transpose), or a :class:`axojax.fem.knots.KnotMatrix`."""
Term = tuple[Float[Array, "n_fd n_fd"], MatrixName]
"""One term of a system matrix: a truss matrix over (filament, direction) pairs and the
name of the filament-level matrix it multiplies (a field of
:class:`axojax.fem.FilamentMatrices`, or a :class:`axojax.fem.knots.KnotMatrix`): the
term is ``kron(truss, matrix)``."""

_PROFILE_OF = {
    "ei_knots": "ei",
    "p_knots": "p",
}  # the static Profiles field a knot profile replaces


def _knot_profile(model: Model, params: Params, field: str):
    """(values (K,), knot positions) of the knot profile ``field``, or None when uniform;
    one-line ``ValueError`` for a profile the model cannot take."""
    values = params.knot_values(field)
    if values is None:
        return None
    static = _PROFILE_OF.get(field)
    if static and getattr(model.profiles, static) is not None:
        raise ValueError(
            f"parameter {field}: the model already has a static {static} profile "
            f"(Profiles.{static}); give one of the two"
        )
    if field == "p_knots" and model.section.load == "tip":
        raise ValueError(
            "parameter p_knots: the beck preset's load is a tip force, not a force along the length"
        )
    v = jnp.asarray(values, dtype=float)
    if v.ndim != 1:
        raise ValueError(
            f"parameter {field} must hold one value per knot at one parameter point (shape "
            f"(K,)), got shape {v.shape}: map over a batch with jax.vmap"
        )
    return v, model.knot_positions(field, v.shape[0])


def _profiled(model: Model, params: Params, field: str, truss: Array, matrix: str) -> list[Term]:
    """``truss (x) matrix``, or with the knot profile ``field`` (docs/model.md section 8,
    non-uniform properties) ``sum_k (v_k truss) (x) knot matrix k``."""
    profile = _knot_profile(model, params, field)
    if profile is None:
        return [(truss, matrix)]
    v, knots = profile
    return [(v[k] * truss, KnotMatrix(matrix, k, knots)) for k in range(len(knots))]


def moment_load(model: Model, params: Params, base_dofs: tuple[int, ...] = ()) -> Array:
    """(r,) filament-level static moment row ``int p(x) phi'`` on the mesh that keeps
    ``base_dofs`` (uniform p: :attr:`FilamentMatrices.f1`)."""
    profile = _knot_profile(model, params, "p_knots")
    if profile is None:
        m = model.base_matrices if base_dofs else model.matrices
        return jnp.asarray(m.f1)
    v, knots = profile
    return v @ jnp.asarray(knot_matrices(model.n_elements, tuple(base_dofs), knots)["f1"])


def terms(model: Model, params: Params) -> tuple[list[Term], list[Term], Float[Array, " n"]]:
    """The terms of A and C and the load b (filament-major) at ``params``.

    The single source of the equations (docs/model.md section 3): :func:`assemble` sums the
    terms as dense Kronecker products, :func:`assemble_blocks` as node blocks.
    """
    refuse_normal_force(params)  # concrete values; the pre-jit checks of the solvers too
    nfd = model.n_fd
    drag = jnp.repeat(jnp.asarray(model.section.drag, dtype=float), model.n_dirs)
    ei = bending_rigidity(model, params)
    p = jnp.asarray(params.p, dtype=float)
    eye = jnp.eye(nfd)

    C_terms: list[Term] = _profiled(model, params, "drag_knots", jnp.diag(drag), "M0")
    A_terms: list[Term] = _profiled(model, params, "ei_knots", jnp.diag(ei), "K0")
    b = jnp.zeros(model.n_dof)

    if model.link_B.shape[0]:
        B = jnp.asarray(model.link_B)
        C_terms.append((_truss(B, jnp.full(B.shape[0], 1.0) * params.cl), "M0"))
        A_terms.append((_truss(B, link_stiffness(model, params)), "Mk"))
        A_terms.append((params.ktheta * jnp.asarray(model.theta_laplacian), "D0"))

    load = model.section.load
    if load == "distributed":
        # Unbalanced distributed follower load on every filament: K0 - p G0 + p F0.
        A_terms += _profiled(model, params, "p_knots", p * eye, "F0")
        A_terms += _profiled(model, params, "p_knots", -p * eye, "G0")
    elif load == "tip":
        # Beck's column: constant compression P and tip transverse force -P u'(1).
        _knot_profile(model, params, "p_knots")  # refused: a tip force has no profile
        A_terms += [(p * eye, "tip"), (-p * eye, "D0")]
    elif model.pair_B.shape[0]:
        pa = pair_forces(model, params)
        nu = jnp.einsum("a,ai->i", pa, jnp.asarray(model.pair_sign))
        follow = jnp.einsum("a,aij->ij", pa, jnp.asarray(model.pair_follow))
        gain = params.gamma * jnp.einsum(
            "a,ai,aj->ij", pa, jnp.asarray(model.pair_w), jnp.asarray(model.pair_B)
        )
        for truss, name in ((jnp.diag(nu), "G0"), (-follow, "F0"), (-gain, "F0T")):
            A_terms += _profiled(model, params, "p_knots", truss, name)
        b = jnp.kron(static_couple(model, params), moment_load(model, params))
        stiff, damp = mechanism_terms(model, params)
        A_terms += stiff
        C_terms += damp
    return A_terms, C_terms, b


def _filament_matrix(model: Model, name: MatrixName) -> np.ndarray:
    if isinstance(name, KnotMatrix):
        return knot_matrix(model.n_elements, (), name)
    m = model.matrices
    return np.asarray(m.F0).T if name == "F0T" else np.asarray(getattr(m, name))
