"""Normal-force control (docs/model.md section 8; issue 55 item 1, first step): the
geometric clutch in linear form, about the static state.

Each active pair a carries a regulated motor force per length f_a(x, t) that responds
to the pair's normal force (Sartori et al. 2016's third hypothesis)::

    f_a = g' N_a + (g''/omega0) dN_a/dt,   N_a = kappa_a,0 F_a + F_a,0 kappa_a,
    F_a(x) = -int_x^1 f_a dx'  (the pair's integrated regulated force),
    kappa_a = n_a . u_bar''    (the pair's curvature, as for curvature control),

g = g' + i g'' = ``Params.normal_re``, ``normal_im`` (dimensionless). The static state is
the passive model's equilibrium under the static load b (every regulated coefficient 0:
the regulated forces respond to departures from it): kappa_a,0 = n_a . u_bar_0'' with
A_passive q_0 = b, and F_a,0 the integrated static dynein force of the pair, whose couple
is the pair's part of b. b = kron(a0 sum_a c_a w_a, int phi') with c_a = p_a (the R : 1
forces of :func:`~axojax.assembly.terms.imbalanced_forces`) plus m0 / (a0 |net|) on active
group 0's pairs (:func:`~axojax.assembly.terms.static_moment_direction`); a regulated force
f enters with the opposite sign to the steady couple
(:func:`~axojax.assembly.terms.mechanism_terms`), so the pair's static force is f_a,0 =
-c_a and F_a,0(x) = c_a (1 - x). In the two-filament continuum limit (``two``, p = 0, a
uniform m0) kappa_0 = m0 (1 - x) / 2 and a0 F_0 = m0 (1 - x) = kappa C_0: Sartori's static
balance, so that f_perp,1 = C_0 (F_1 + kappa psi_1' / a).

**Discretisation.** F_a is non-local in f_a, so the pairs' forces are unknowns of their
own: f_a continuous and piecewise linear, its values at the N_e + 1 nodes (P (N_e + 1)
unknowns, pair-major), F_a its exact tail integral (piecewise quadratic), and the relation
f = g N tested with each node's hat chi_i (Galerkin; the rows divided by h). The force
enters the beam through its virtual work +a0 int f_a w_a . delta U' dx (the sign of
:func:`~axojax.assembly.terms.mechanism_terms`), ``a0 (w_a (x) E)`` with
E[r, j] = int phi_r' chi_j. The augmented system, X = (q, f)::

    A' = [[A, a0 W (x) E], [-g' c W^T (x) R, M - g' K]],
    C' = [[C, 0], [-(g''/omega0) c W^T (x) R, -(g''/omega0) K]],   b' = (b, 0),

M[i, j] = int chi_i chi_j / h, K_a[i, k] = int chi_i kappa_a,0 T_k / h (T_k(x) =
-int_x^1 chi_k, so F_a = sum_k T_k f_a,k), R[i, r] = int chi_i (1 - x) phi_r'' / h, all by
the mesh's Gauss quadrature (exact: polynomials of degree <= 4 per element). A and C are
today's (:func:`~axojax.assembly.assemble`, with any sliding and curvature control). With
g'' = 0 the force rows carry no time derivative (C' singular: infinite eigenvalues, an
algebraic constraint of index 1); eliminating f gives A + a0 W E (M - g' K)^{-1} g' c W^T R,
a dense filament-level coupling (the clutch is non-local along x). On ``two`` the
eigenvalue converges like h^4 to the continuum's (tests/regulation/test_normal_force.py).

Dense only, clamped base only (this step), uniform p only (no ``p_knots``).
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..models.section import Model
from ..params import MECHANISM_NAMES, Params
from .terms import _per_omega0, imbalanced_forces


class NormalSystem(eqx.Module):
    """The augmented system ``C' dX/dt + A' X = b'`` of normal-force control, X = (q, f).

    Attributes:
        A: (N + P N_e, N + P N_e) stiffness-minus-load with the force rows.
        C: (N + P N_e, N + P N_e) damping (singular where g'' = 0: the force rows are
            algebraic there).
        b: (N + P N_e,) static load: today's b, then zeros.
        n: N, the model's unknowns (``model.n_unknowns``): X[:n] is q.
    """

    A: Float[Array, "M M"]
    C: Float[Array, "M M"]
    b: Float[Array, " M"]
    n: int = eqx.field(static=True)


def check_normal_model(model: Model, params: Params) -> None:
    """One-line ``ValueError`` for a model or parameters this step of normal-force control
    does not take: a base that is not clamped, no active pairs, a ``p_knots`` profile."""
    if model.n_border:
        raise ValueError(
            f"normal-force control is built on the clamped base only so far, got base {model.base.kind!r}"
        )
    if not (model.pair_B.shape[0] and model.section.load == "pairs"):
        raise ValueError(
            f"normal-force control needs active pairs, and model {model.name!r} has none"
        )
    if params.p_knots is not None:
        raise ValueError(
            "normal-force control takes a uniform dynein force only so far, got a p_knots profile"
        )


@functools.lru_cache(maxsize=32)
def _tables(model: Model) -> dict[str, np.ndarray]:
    """Static tables on the model's mesh (numpy; module docstring), with the hats chi_j
    at the nodes x_j = j h, j = 0..N_e, and the rows tested with chi_i / h: ``E`` (2 N_e,
    N_e + 1) = int phi_r' chi_j; ``mass`` (N_e + 1, N_e + 1) = int chi_i chi_j / h;
    ``test`` (N_e + 1, nq) the quadrature of int chi_i (.) / h; ``tail`` (nq, N_e + 1)
    T_j(x) = -int_x^1 chi_j; ``R`` (N_e + 1, 2 N_e) = int chi_i (1 - x) phi_r'' / h;
    ``ddphi`` (nq, 2 N_e) phi'' at the quadrature points."""
    mesh = model.mesh
    ne = mesh.n_elements
    h = 1.0 / ne
    nodes = np.linspace(0.0, 1.0, ne + 1)
    x, wq = np.asarray(mesh.x), np.asarray(mesh.weights)
    hats = np.clip(1.0 - np.abs(x[:, None] - nodes[None, :]) / h, 0.0, None)  # (nq, N_e + 1)
    left = np.where(
        nodes > 0, (np.clip(x[:, None], nodes - h, nodes) - (nodes - h)) ** 2 / (2 * h), 0.0
    )
    right = np.where(
        nodes < 1, h / 2 - (nodes + h - np.clip(x[:, None], nodes, nodes + h)) ** 2 / (2 * h), 0.0
    )
    whole = np.where((nodes > 0) & (nodes < 1), h, h / 2)
    tail = -(whole[None, :] - left - right)
    test = (hats * wq[:, None]).T / h
    ddphi = np.asarray(mesh.ddphi)
    return {
        "E": np.asarray(mesh.dphi).T @ (wq[:, None] * hats),
        "mass": test @ hats,
        "test": test,
        "tail": tail,
        "R": test @ ((1.0 - x)[:, None] * ddphi),
        "ddphi": ddphi,
    }


def static_forces(model: Model, params: Params) -> Float[Array, " P"]:
    """c_a of each active pair: its static force F_a,0(x) = c_a (1 - x) (module docstring):
    p_a of the R : 1 forces plus m0 / (a0 |net|) on active group 0's pairs (0 where a0 = 0:
    a force without a lever arm sets no moment), so that a0 sum_a c_a w_a is the static
    couple of :func:`~axojax.assembly.terms.static_couple` (|net| as in
    :func:`~axojax.assembly.terms.static_moment_direction`)."""
    w = np.asarray(model.pair_w, dtype=float)
    group0 = np.asarray(model.pair_group) == 0
    net = w[group0].sum(axis=0).reshape(-1, model.n_dirs).sum(axis=0)
    norm = float(np.linalg.norm(net))
    a0 = jnp.asarray(params.a0, dtype=float)
    m0 = jnp.asarray(params.m0, dtype=float)
    share = jnp.where(a0 > 0, m0 / jnp.where(a0 > 0, a0, 1.0), 0.0) / (norm if norm > 0 else 1.0)
    return imbalanced_forces(model, params) + jnp.where(jnp.asarray(group0), share, 0.0)


def passive_equilibrium(model: Model, params: Params) -> Float[Array, " N"]:
    """q_0 (N,): the static state the regulated forces respond to, the passive model's
    equilibrium A_passive q_0 = b under the static load (every regulated coefficient 0;
    a clamped base: A_passive regular). Traceable."""
    from . import assemble

    passive = params.replace(**{k: 0.0 for k in MECHANISM_NAMES})
    system = assemble(model, passive)
    return jnp.linalg.solve(system.A, system.b)


def static_curvature(model: Model, params: Params) -> Float[Array, "P nq"]:
    """kappa_a,0 at the mesh's quadrature points: n_a . u_bar_0'' of the passive model's
    equilibrium (:func:`passive_equilibrium`)."""
    q0 = passive_equilibrium(model, params)
    ddu = q0.reshape(model.n_fd, -1) @ jnp.asarray(_tables(model)["ddphi"]).T  # (n_fd, nq)
    return jnp.asarray(model.pair_w) @ ddu


def assemble_normal(model: Model, params: Params) -> NormalSystem:
    """The system with normal-force control (module docstring), a pure function of
    ``params`` (``jit``/``vmap``-able; a one-line ``ValueError`` for a model it does not
    take, :func:`check_normal_model`).

    Args:
        model: static structure with active pairs and a clamped base, e.g.
            ``ax.models.two(n_elements=20)``.
        params: parameters with the gain ``normal_re``, ``normal_im`` at ``omega0``, the
            static load (``m0`` or an imbalance) and any sliding and curvature control.

    Returns:
        :class:`NormalSystem` with (N + P N_e)-square A, C and b, N = ``model.n_unknowns``.
    """
    check_normal_model(model, params)
    return _assemble_normal_jit(model, params)


def _assemble_normal(model: Model, params: Params) -> NormalSystem:
    from . import assemble

    t = _tables(model)
    w = jnp.asarray(model.pair_w, dtype=float)  # (P, n_fd)
    n_pairs, ne, n = w.shape[0], model.n_elements, model.n_unknowns
    a0 = jnp.asarray(params.a0, dtype=float)
    g_re = jnp.asarray(params.normal_re, dtype=float)
    g_d = _per_omega0(jnp.asarray(params.normal_im, dtype=float), jnp.asarray(params.omega0))
    base = assemble(model, params.replace(normal_re=0.0, normal_im=0.0))
    kappa0 = static_curvature(model, params)  # (P, nq)
    c = static_forces(model, params)  # (P,)
    K = jnp.einsum("eq,aq,qk->aek", jnp.asarray(t["test"]), kappa0, jnp.asarray(t["tail"]))
    eye_p, mass = jnp.eye(n_pairs), jnp.asarray(t["mass"])
    nf = n_pairs * (ne + 1)
    couple = a0 * jnp.einsum("ai,re->irae", w, jnp.asarray(t["E"])).reshape(n, nf)
    sensed = jnp.einsum("a,ai,er->aeir", c, w, jnp.asarray(t["R"])).reshape(nf, n)
    per_pair = jnp.einsum("ab,aek->aebk", eye_p, K).reshape(nf, nf)
    ones = jnp.einsum("ab,ek->aebk", eye_p, mass).reshape(nf, nf)
    A = jnp.block([[base.A, couple], [-g_re * sensed, ones - g_re * per_pair]])
    C = jnp.block([[base.C, jnp.zeros((n, nf))], [-g_d * sensed, -g_d * per_pair]])
    return NormalSystem(A=A, C=C, b=jnp.concatenate([base.b, jnp.zeros(nf)]), n=n)


_assemble_normal_jit = jax.jit(_assemble_normal, static_argnums=0)
