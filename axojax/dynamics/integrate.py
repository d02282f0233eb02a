"""Time integration of ``C dq/dt = -A q - f_nl(q) + b`` with diffrax.

The system is stiff (spoke relaxation rates ~ k_s / c_l, bending ~ N_e^4), so the solver
is an L-stable implicit Runge-Kutta method (``diffrax.Kvaerno5``) with a PID step-size
controller (PI coefficients 0.3/0.3, diffrax's advice for stiff problems: it halves the
rejected steps of the nonlinear beat here). ``C`` is symmetric positive definite: the vector field is
``dq/dt = C^{-1} (b - A q - f_nl(q))`` with ``C^{-1} A`` and ``C^{-1} b`` formed once per
solve (:func:`mass_system`). The implicit stages are solved by a chord iteration with the
exact Jacobian, factorised once a step as a block-tridiagonal matrix
(:class:`axojax.dynamics.chord.MassChord`; diffrax's ``VeryChord`` formed it by ``jacfwd``
and a dense LU, 18 ms a step for the 10-element seven-filament model). Pure function of
(params, kappa, q0): jit-able and differentiable (diffrax's checkpointed adjoint).

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
import numpy as np
import optimistix as optx
from jaxtyping import Array, ArrayLike, Float, Real

from ..assembly import assemble, assemble_blocks, node_major, pencil_of
from ..assembly.motor_kinetics import assemble_motor
from ..eigen.pencil import symmetric_positive_definite
from ..linalg import bordered_lu, lu_factor
from ..models.section import Model
from ..params import Params
from ..results import RESULTS, message
from .chord import MassChord, MassSystem, mass_vector_field
from .motors import motor_blocks, motor_order
from .nonlinear import cubic_links
from .saturation import motor_forces


class Trajectory(eqx.Module):
    """States at the save times (dimensionless: time in tau, displacement in L).

    Attributes:
        t: (T,) save times.
        q: (T, n) states; rows after a solver failure are not finite.
        ok: True when the solver reached ``t[-1]``.
        steps: accepted steps taken.
        rejected: rejected steps.
        result: :class:`axojax.results.RESULTS` item (diffrax's code, promoted:
            ``successful``, ``max_steps_reached``, ...); :func:`result_message` gives
            its message.
        t_reached: the time the solver reached (``t[-1]`` on success).
        q_reached: (n,) the state there.
    """

    t: Float[Array, " T"]
    q: Float[Array, "T n"]
    ok: Array
    steps: Array
    rejected: Array
    result: RESULTS
    t_reached: Array
    q_reached: Float[Array, " n"]


def result_message(code) -> str:
    """The message of a result (a :class:`~axojax.results.RESULTS` item, or an index of
    ``diffrax.RESULTS``), on one line (its first sentence)."""
    line = (
        message(code)
        if hasattr(code, "_value")
        else " ".join(diffrax.RESULTS._index_to_message[int(code)].split())
    )
    return line.split(". ")[0].rstrip(".") if line else "successful"


def _inverse(C: Float[Array, "n n"]) -> Float[Array, "n n"]:
    """C^{-1}: by Cholesky where C is symmetric positive definite, else by LU."""
    eye = jnp.eye(C.shape[0])
    factor = jsl.cho_factor(C, lower=True)
    spd = symmetric_positive_definite(C, factor[0])
    # C is symmetric positive definite except with the friction parts of regulated dynein
    # (beta''/omega0 makes it non-symmetric): then an LU inverse; the select keeps the
    # Cholesky inverse exactly where it applies.
    return jnp.where(
        spd,
        jsl.cho_solve((jnp.where(spd, factor[0], eye), True), eye),
        jnp.linalg.solve(jnp.where(spd, eye, C), eye),
    )


def mass_system(
    model: Model,
    params: Params,
    kappa: Real[ArrayLike, ""],
    tau_m: Real[ArrayLike, ""] | None = None,
    f_sat: Real[ArrayLike, ""] | None = None,
) -> MassSystem:
    """The ODE ``C dq/dt = b - A q - f_nl(q)`` at ``params`` as a :class:`MassSystem`
    (``C^{-1} A``, ``C^{-1} b`` and the block LU of ``C`` formed once). With ``tau_m``
    (dimensionless, > 0): the augmented system of motor kinetics, state X = (q, y) of
    2 N unknowns (:mod:`axojax.dynamics.motors`), and with ``f_sat`` (EI / L^3, > 0)
    saturating motors (:mod:`axojax.dynamics.saturation`; needs ``tau_m``)."""
    if tau_m is not None:
        return _motor_mass_system(model, params, kappa, tau_m, f_sat)
    if f_sat is not None:
        raise ValueError("a motor saturation f_sat needs motor kinetics (tau_m)")
    s = assemble(model, params)
    blocks = assemble_blocks(model, params)
    perm = node_major(model)
    if model.n_border:  # a base that is not clamped: its unknowns border the node blocks
        A_blocks, C_blocks = pencil_of(blocks)
        perm = np.concatenate([perm, model.n_dof + np.arange(model.n_border)])
        C_lu = bordered_lu(C_blocks)
    else:
        A_blocks, C_blocks, C_lu = blocks.A, blocks.C, lu_factor(blocks.C)
    return _system_of(s, perm, A_blocks, C_blocks, C_lu, cubic_links(model, params, kappa))


def _motor_mass_system(
    model: Model,
    params: Params,
    kappa: Real[ArrayLike, ""],
    tau_m: Real[ArrayLike, ""],
    f_sat: Real[ArrayLike, ""] | None,
) -> MassSystem:
    """:func:`mass_system` of the augmented system ``C' dX/dt = b' - A' X - f_nl(X)``
    (:func:`~axojax.assembly.motor_kinetics.assemble_motor`), blocks in
    :func:`~axojax.dynamics.motors.motor_order`; the links act on q only."""
    s = assemble_motor(model, params, tau_m)
    links, saturation = motor_forces(model, params, kappa, tau_m, f_sat)
    A_blocks, C_blocks = motor_blocks(model, s.A), motor_blocks(model, s.C)
    C_lu = bordered_lu(C_blocks) if model.n_border else lu_factor(C_blocks)
    return _system_of(s, motor_order(model), A_blocks, C_blocks, C_lu, links, saturation)


def _system_of(s, perm, A_blocks, C_blocks, C_lu, links, saturation=None) -> MassSystem:
    """The :class:`MassSystem` of an assembled system ``s`` (its ``C``, ``A``, ``b``), with
    ``C^{-1}``, ``C^{-1} A`` and ``C^{-1} b`` formed here: what :func:`mass_system` and
    :func:`_motor_mass_system` share (``perm`` the blocks' order, numpy or jax)."""
    C_inv = _inverse(s.C)
    return MassSystem(
        C=s.C,
        A=s.A,
        b=s.b,
        C_inv=C_inv,
        C_inv_A=C_inv @ s.A,
        C_inv_b=C_inv @ s.b,
        perm=jnp.asarray(perm),
        C_blocks=C_blocks,
        A_blocks=A_blocks,
        C_lu=C_lu,
        links=links,
        saturation=saturation,
    )


def vector_field(
    model: Model,
    params: Params,
    kappa: Real[ArrayLike, ""],
    tau_m: Real[ArrayLike, ""] | None = None,
    f_sat: Real[ArrayLike, ""] | None = None,
):
    """dq/dt (with ``tau_m``: dX/dt of the augmented state) as a diffrax-style
    ``f(t, q, args)`` (``args`` unused)."""
    system = mass_system(model, params, kappa, tau_m, f_sat)
    return lambda t, q, args: mass_vector_field(t, q, system)


def stiff_solver(rtol: float = 1e-6, root_atol: float = 1e-6) -> diffrax.Kvaerno5:
    """The implicit solver, with its stage root-finder (exact-Jacobian chord,
    :class:`MassChord`) and its tolerances set for f-space (``root_atol`` in L per tau;
    see the module docstring). Its ODE ``args`` must be the :func:`mass_system`."""
    return diffrax.Kvaerno5(root_finder=MassChord(rtol=rtol, atol=root_atol, norm=optx.rms_norm))


def integrate(
    model: Model,
    params: Params,
    kappa: Real[ArrayLike, ""],
    q0: Float[Array, " n"],
    t: Float[Array, " T"],
    *,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    root_atol: float = 1e-6,
    max_steps: int = 200_000,
    progress: bool = False,
    tau_m: Real[ArrayLike, ""] | None = None,
    f_sat: Real[ArrayLike, ""] | None = None,
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
        max_steps: solver step limit; reaching it ends with ``ok = False`` and diffrax's
            ``max_steps_reached`` result.
        progress: show a tqdm progress bar (diffrax's ``TqdmProgressMeter``).
        tau_m: motor kinetics of this relaxation time (tau, > 0; may be traced): the
            state is X = (q, y), 2 N unknowns, ``q0`` and the trajectory's ``q`` too
            (:mod:`axojax.dynamics.motors`). None (default): today's system.
        f_sat: with ``tau_m``, saturating motors: the regulated force through
            ``f_sat tanh(f / f_sat)`` (EI / L^3, > 0; :mod:`axojax.dynamics.saturation`).
    """
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(mass_vector_field),
        stiff_solver(rtol, root_atol),
        t0=t[0],
        t1=t[-1],
        dt0=None,
        y0=q0,
        args=mass_system(model, params, kappa, tau_m, f_sat),
        saveat=diffrax.SaveAt(
            subs=[diffrax.SubSaveAt(ts=t), diffrax.SubSaveAt(t1=True)]
        ),  # t1: where it stopped
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol, pcoeff=0.3, icoeff=0.3),
        max_steps=max_steps,
        throw=False,
        progress_meter=diffrax.TqdmProgressMeter() if progress else diffrax.NoProgressMeter(),
    )
    ok = sol.result == diffrax.RESULTS.successful
    return Trajectory(
        t=sol.ts[0],
        q=sol.ys[0],
        ok=ok,
        steps=sol.stats["num_accepted_steps"],
        rejected=sol.stats["num_rejected_steps"],
        result=RESULTS.promote(sol.result),
        t_reached=sol.ts[1][0],
        q_reached=sol.ys[1][0],
    )
