"""Time integration of ``C dq/dt = -A q - f_nl(q) + b`` with diffrax.

The system is stiff (spoke relaxation rates ~ k_s / c_l, bending ~ N_e^4), so the solver
is an L-stable implicit Runge-Kutta method (``diffrax.Kvaerno5``) with a PID step-size
controller (PI coefficients 0.3/0.3, diffrax's advice for stiff problems: it halves the
rejected steps of the nonlinear beat here). ``C`` is symmetric positive definite: the vector field is
``dq/dt = C^{-1} (b - A q - f_nl(q))`` with ``C^{-1} A`` and ``C^{-1} b`` formed once per
solve. Pure function of (params, kappa, q0): jit-able and differentiable (diffrax's
checkpointed adjoint).

Each implicit stage is a root-find for the vector-field value f = dq/dt (units L per
tau), not for q, and diffrax hands that root-finder the step controller's tolerances
unchanged unless told otherwise. The controller's ``atol`` is in L (1e-9); in f it sits
below the round-off of f itself, which for the 10-element seven-filament model is up to
~3e-7 L/tau (``|C^-1 A|`` entries reach ~1e9 from the stiff links). The chord iteration
then "converged" or "diverged" by chance, and the step size collapsed from ~1e-4 to
~1e-10 tau at some point of the nonlinear beat (issue 6). The root-finder therefore gets
its own absolute tolerance ``root_atol`` in L/tau (default 1e-6, above that round-off):
the stage value is ``y_partial + h gamma f``, so an f-error of ``1e-2 root_atol`` (the
chord's convergence factor) moves q by ~3e-9 h/tau L, well below ``atol`` for every step
this problem takes (h < 1e-2 tau).
"""

from __future__ import annotations

import diffrax
import equinox as eqx
import jax.numpy as jnp
import jax.scipy.linalg as jsl
import optimistix as optx
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


def stiff_solver(rtol: float = 1e-6, root_atol: float = 1e-6) -> diffrax.Kvaerno5:
    """The implicit solver, with its stage root-finder's tolerances set for f-space
    (``root_atol`` in L per tau; see the module docstring)."""
    return diffrax.Kvaerno5(root_finder=diffrax.VeryChord(rtol=rtol, atol=root_atol, norm=optx.rms_norm))


def integrate(
    model: Model,
    params: Params,
    kappa: Float[Array, ""],
    q0: Float[Array, " n"],
    t: Float[Array, " T"],
    *,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    root_atol: float = 1e-6,
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
        root_atol: absolute tolerance of the implicit stage solves, in L per tau (they
            solve for dq/dt; see the module docstring); ``rtol`` is shared.
        max_steps: solver step limit; reaching it ends with ``ok = False``.
        progress: show a tqdm progress bar (diffrax's ``TqdmProgressMeter``).
    """
    term = diffrax.ODETerm(vector_field(model, params, jnp.asarray(kappa, dtype=float)))
    sol = diffrax.diffeqsolve(
        term,
        stiff_solver(rtol, root_atol),
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
