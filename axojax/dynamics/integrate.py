"""Time integration of ``C dq/dt = -A q - f_nl(q) + b`` with diffrax.

The system is stiff (spoke relaxation rates ~ k_s / c_l, bending ~ N_e^4), so the solver
is an L-stable implicit Runge-Kutta method (``diffrax.Kvaerno5``) with a PID step-size
controller (PI coefficients 0.3/0.3, diffrax's advice for stiff problems: it halves the
rejected steps of the nonlinear beat here). ``C`` is symmetric positive definite: the vector field is
``dq/dt = C^{-1} (b - A q - f_nl(q))`` with ``C^{-1} A`` and ``C^{-1} b`` formed once per
solve. Pure function of (params, kappa, q0): jit-able and differentiable (diffrax's
checkpointed adjoint).
"""

from __future__ import annotations

import diffrax
import equinox as eqx
import jax.numpy as jnp
import jax.scipy.linalg as jsl
from jaxtyping import Array, Float

from ..assembly import assemble
from ..models.section import Model
from ..params import Params
from .nonlinear import cubic_link_force


class Trajectory(eqx.Module):
    """States at the save times (dimensionless: time in tau, displacement in L).

    Attributes:
        t: (T,) save times.
        q: (T, n) states; rows after a failure are not finite.
        ok: True when the solver reached ``t[-1]``.
        steps: accepted steps taken.
    """

    t: Float[Array, " T"]
    q: Float[Array, "T n"]
    ok: Array
    steps: Array


def vector_field(model: Model, params: Params, kappa: Float[Array, ""]):
    """dq/dt as a diffrax-style ``f(t, q, args)``."""
    s = assemble(model, params)
    C_inv = jsl.cho_solve(jsl.cho_factor(s.C, lower=True), jnp.eye(s.C.shape[0]))
    CA = C_inv @ s.A
    Cb = C_inv @ s.b

    def f(t, q, args):
        return Cb - CA @ q - C_inv @ cubic_link_force(model, params, kappa, q)

    return f


def integrate(
    model: Model,
    params: Params,
    kappa: Float[Array, ""],
    q0: Float[Array, " n"],
    t: Float[Array, " T"],
    *,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    max_steps: int = 200_000,
    progress: bool = False,
) -> Trajectory:
    """Integrate from ``q0`` at ``t[0]`` and save at the (increasing) times ``t``.

    Args:
        model: static structure.
        params: dimensionless parameters (may be traced).
        kappa: cubic stiffening coefficient of the links (1/L^2); 0 gives the linear system.
        q0: (n,) initial state (L).
        t: (T,) save times (tau), ``t[0]`` the start.
        rtol, atol: step-size controller tolerances (atol in L).
        max_steps: solver step limit; reaching it ends with ``ok = False``.
        progress: show a tqdm progress bar (diffrax's ``TqdmProgressMeter``).
    """
    term = diffrax.ODETerm(vector_field(model, params, jnp.asarray(kappa, dtype=float)))
    sol = diffrax.diffeqsolve(
        term,
        diffrax.Kvaerno5(),
        t0=t[0],
        t1=t[-1],
        dt0=None,
        y0=q0,
        saveat=diffrax.SaveAt(ts=t),
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol, pcoeff=0.3, icoeff=0.3),
        max_steps=max_steps,
        throw=False,
        progress_meter=diffrax.TqdmProgressMeter() if progress else diffrax.NoProgressMeter(),
    )
    ok = sol.result == diffrax.RESULTS.successful
    return Trajectory(t=sol.ts, q=sol.ys, ok=ok, steps=sol.stats["num_accepted_steps"])
