"""Motor kinetics (docs/model.md section 8, issue 47 item 1): a well-posed time
domain for an active friction (chi'' < 0 or beta'' < 0).

Today's regulated dynein responds to a pair's sliding Delta_a as chi' Delta_a +
(chi''/omega0) dDelta_a/dt (and to its curvature kappa_a likewise with beta): its friction
enters C, which for chi'' < 0 is indefinite, and the spectrum's largest growth rate then
grows without bound as the mesh is refined. With motor kinetics each active pair carries a
motor field z_a(x, t) relaxing with the motors' time tau_m (dimensionless, in units of
tau = c_n L^4 / EI like every time of :class:`~axojax.Params`)::

    tau_m dz_a/dt = -z_a + c_1 Delta_a + d_1 kappa_a,
    f_a = c_inf Delta_a + d_inf kappa_a + z_a,

    c_inf = chi' + chi''/(omega0 tau_m),  c_1 = -chi'' (1 + omega0^2 tau_m^2)/(omega0 tau_m)

(d_inf, d_1 the same of beta). Its response c_inf + c_1/(1 + tau_m lambda) equals
chi' + i chi'' at lambda = i omega0 (a beat pinned there keeps its eigenvalue and psi_1),
tends to c_inf as |lambda| grows (the spectrum stays bounded above) and to the friction
form chi' + chi'' lambda / omega0 as tau_m -> 0.

**Discretisation.** z_a lives in the space of the quantity it relaxes: z_a = c_1
Delta_a[y] + d_1 kappa_a[y] for a filtered copy y (N unknowns, the same as q) of the state,
tau_m dy/dt = -y + q. Delta_a and kappa_a are linear in the state (for every base,
including its border: u'(0), the basal slidings), so this z_a obeys the field equation
above exactly, and the force of z_a is ``M y`` with the assembled mechanism matrices
``M = c_1 dA/dchi' + d_1 dA/dbeta'``: the same virtual work as today's terms, border
included, with no new quadrature. (Gauss-point values of z_a would need a new quadrature of
the border's non-local parts; the Galerkin form of the field equation in the span of
Delta_a has that span's mass matrix on both sides, which cancels to the copy above.)
Directions of y that no pair's force sees (the null space of M) are modes at
lambda = -1/tau_m exactly, decoupled and stable.

The augmented system, unknowns (q, y) of size 2 N, N = ``model.n_unknowns``::

    A' = [[A_inf, M], [-I, I]],   C' = [[C_0, 0], [0, tau_m I]],   b' = (b, 0)

with A_inf, C_0 today's A and C with chi = c_inf, beta = d_inf real (no friction in C:
C_0 is the drag and link damping, symmetric positive definite on a clamped or damped
base). Eliminating y: A_inf + M / (1 + tau_m lambda) + lambda C_0, the response above.

Dense only: :func:`assemble_motor` returns (2N, 2N) matrices (the reference, and what
:class:`~axojax.eigen.Dense` factors); the structured solvers do not take it yet.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from ..models.section import Model
from ..params import MAX_MAGNITUDE, Params


class MotorSystem(eqx.Module):
    """The augmented system ``C' dX/dt + A' X = b'`` of motor kinetics, X = (q, y).

    Attributes:
        A: (2N, 2N) stiffness-minus-load with the motor coupling (dimensionless, EI / L^3
            per unit length like :class:`~axojax.assembly.System`'s).
        C: (2N, 2N) damping: today's C without the regulated friction, then tau_m I.
        b: (2N,) static load: today's b, then zeros (at rest y = q).
        n: N, the original unknowns (``model.n_unknowns``): X[:n] is q.
    """

    A: Float[Array, "M M"]
    C: Float[Array, "M M"]
    b: Float[Array, " M"]
    n: int = eqx.field(static=True)


def motor_coefficients(
    re: ArrayLike, im: ArrayLike, omega0: ArrayLike, tau_m: ArrayLike
) -> tuple[Array, Array]:
    """(c_inf, c_1) of a regulated coefficient chi' + i chi'' (or beta) held at omega0,
    with motor time tau_m (both dimensionless: omega0 in 1/tau, tau_m in tau; tau_m > 0):
    c_inf = chi' + chi''/(omega0 tau_m), c_1 = -chi'' (1 + (omega0 tau_m)^2)/(omega0 tau_m),
    so that c_inf + c_1 / (1 + i omega0 tau_m) = chi' + i chi''. Same units as chi (or
    beta). ``im = 0`` gives (re, 0) for any omega0 (also 0)."""
    re, im = jnp.asarray(re, dtype=float), jnp.asarray(im, dtype=float)
    wt = jnp.asarray(omega0, dtype=float) * jnp.asarray(tau_m, dtype=float)
    safe = jnp.where(wt > 0, wt, 1.0)
    c_inf = re + jnp.where(im != 0, im / safe, 0.0)
    c_1 = jnp.where(im != 0, -im * (1 + safe**2) / safe, 0.0)
    return c_inf, c_1


def mechanism_matrices(
    model: Model, params: Params
) -> tuple[Float[Array, "N N"], Float[Array, "N N"]]:
    """(dA/dchi', dA/dbeta'): the assembled regulated terms per unit sliding and curvature
    coefficient, border included, (N, N) with N = ``model.n_unknowns`` (A is linear in
    both: forward-mode derivatives are the exact matrices, independent of the point).
    Zero for a model without active pairs or with another load than pairs'."""
    from . import assemble

    def a_of(chi: Array, beta: Array) -> Array:
        return assemble(model, params.replace(chi_re=chi, beta_re=beta)).A

    zero, one = jnp.asarray(0.0), jnp.asarray(1.0)
    _, m_chi = jax.jvp(lambda c: a_of(c, zero), (zero,), (one,))
    _, m_beta = jax.jvp(lambda c: a_of(zero, c), (zero,), (one,))
    return m_chi, m_beta


def check_tau_m(params: Params, tau_m: ArrayLike) -> None:
    """One-line ``ValueError`` unless tau_m is one number in [1 / MAX_MAGNITUDE,
    MAX_MAGNITUDE] (positive; beyond, c_inf and c_1 lose their digits in float64, as any
    parameter beyond :data:`axojax.params.MAX_MAGNITUDE`), and omega0 > 0 where chi'' or
    beta'' is non-zero (concrete values only; traced ones pass)."""
    if isinstance(tau_m, jax.core.Tracer):
        return
    t = np.asarray(tau_m, dtype=float)
    if t.shape != () or not (np.isfinite(t) and 1 / MAX_MAGNITUDE <= t <= MAX_MAGNITUDE):
        raise ValueError(
            f"motor time tau_m must be one number in [{1 / MAX_MAGNITUDE:g}, {MAX_MAGNITUDE:g}] "
            f"(dimensionless), got {tau_m!r}"
        )
    params.validate()


def assemble_motor(model: Model, params: Params, tau_m: ArrayLike | None = None):
    """The system with motor kinetics of relaxation time ``tau_m`` (module docstring).

    Args:
        model: static structure, e.g. ``ax.models.two(n_elements=8)``.
        params: dimensionless parameters with the regulated coefficients chi, beta at
            omega0 (:class:`~axojax.Params`); may be traced.
        tau_m: the motors' relaxation time, dimensionless (seconds / tau,
            :attr:`axojax.Units.tau`), > 0. None (default): no motor kinetics, today's
            friction form: exactly :func:`~axojax.assembly.assemble`'s result.

    Returns:
        :class:`MotorSystem` with (2N, 2N) A, C and (2N,) b, N = ``model.n_unknowns``;
        for ``tau_m=None`` the :class:`~axojax.assembly.System` of
        :func:`~axojax.assembly.assemble` itself.
    """
    from . import assemble

    if tau_m is None:
        return assemble(model, params)
    check_tau_m(params, tau_m)
    c_inf, c_1 = motor_coefficients(params.chi_re, params.chi_im, params.omega0, tau_m)
    d_inf, d_1 = motor_coefficients(params.beta_re, params.beta_im, params.omega0, tau_m)
    elastic = assemble(model, params.replace(chi_re=c_inf, chi_im=0.0, beta_re=d_inf, beta_im=0.0))
    m_chi, m_beta = mechanism_matrices(model, params)
    coupling = c_1 * m_chi + d_1 * m_beta
    n = model.n_unknowns
    eye, zero = jnp.eye(n), jnp.zeros((n, n))
    A = jnp.block([[elastic.A, coupling], [-eye, eye]])
    C = jnp.block([[elastic.C, zero], [zero, jnp.asarray(tau_m, dtype=float) * eye]])
    b = jnp.concatenate([elastic.b, jnp.zeros(n)])
    return MotorSystem(A=A, C=C, b=b, n=n)
