"""Limit cycles of regulated dynein with motor kinetics and saturating motors (issue 47
item 3; docs/model.md section 8).

With motor kinetics of relaxation time tau_m the orbit is that of the doubled state
X = (q, y) (``tau_m dy/dt = -y + q``): the periodic solution of the equations
:func:`axojax.simulate` integrates with ``tau_m`` (and ``f_sat``)::

    C' dX/dt = b' - A' X - f_nl(X),

A', C', b' of :func:`~axojax.assembly.motor_kinetics.assemble_motor` and f_nl the cubic
links on q plus, with ``f_sat``, the saturating motors
(:func:`~axojax.dynamics.saturation.motor_forces`): the same matrices and forces as the
integrator, not a re-derivation. The harmonic balance of :mod:`axojax.orbits.fourier`
then solves it unchanged, with 2 N unknowns per harmonic.

The saturation ``f_sat tanh(f / f_sat)`` is not a polynomial, so its alternating
frequency-time projection is not exact as the cubic links' is: its harmonics beyond the
sampled ones alias. They decay geometrically (tanh of a trigonometric polynomial is
analytic), and :data:`SATURATION_SAMPLES_PER_HARMONIC` samples per harmonic put the
aliasing far below the Newton tolerance on the tested beats (the frequency and amplitude
change by less than 1e-10 relative from 8 H + 2 to 16 H + 2 samples,
tests/orbits/test_orbit_motors.py; measured 1e-14, and 4 H + 2 would have done there too: those
beats are weakly saturated).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from ..assembly import assemble
from ..assembly.motor_kinetics import assemble_motor, check_tau_m
from ..dynamics.saturation import check_saturation, motor_forces
from ..models.section import Model
from ..params import Params
from .fourier import Problem

SATURATION_SAMPLES_PER_HARMONIC = 8
"""Default samples of the alternating frequency-time projection with saturating motors:
``8 H + 2`` (the cubic force alone needs 4 H + 1; module docstring)."""


class Motors(eqx.Module):
    """Motor kinetics of a regulated orbit (a pytree: differentiable, traced through
    ``jax.jit`` like ``params``).

    Attributes:
        tau_m: the motors' relaxation time, dimensionless (seconds / ``Units.tau_s``), > 0.
        f_sat: the saturation force per length (dimensionless, EI / L^3, scaled as p;
            ``Units.p_from_pn_per_um``), > 0; None: linear motors.
    """

    tau_m: Float[Array, ""]
    f_sat: Float[Array, ""] | None = None


def motors_of(params: Params, tau_m: ArrayLike | None, f_sat: ArrayLike | None) -> Motors | None:
    """:class:`Motors` of concrete ``tau_m`` and ``f_sat`` (None without ``tau_m``). One-line
    ``ValueError`` naming the value: tau_m outside
    :func:`~axojax.assembly.motor_kinetics.check_tau_m`'s range, f_sat outside
    :func:`~axojax.dynamics.saturation.check_saturation`'s, or f_sat without tau_m."""
    if f_sat is not None and tau_m is None:
        raise ValueError("a motor saturation f_sat needs motor kinetics (tau_m)")
    if tau_m is None:
        return None
    check_tau_m(params, tau_m)
    sat = None if f_sat is None else jnp.asarray(check_saturation(f_sat))
    return Motors(tau_m=jnp.asarray(float(tau_m)), f_sat=sat)


def orbit_problem(
    model: Model, params: Params, kappa, harmonics: int, samples: int, motors: Motors | None
) -> Problem:
    """The harmonic-balance :class:`~axojax.orbits.fourier.Problem` at ``params``: the
    model's own system, or with ``motors`` the augmented one and its saturating motors."""
    if motors is None:
        return Problem(model, params, assemble(model, params), kappa, harmonics, samples)
    _, saturation = motor_forces(model, params, kappa, motors.tau_m, motors.f_sat)
    system = assemble_motor(model, params, motors.tau_m)
    return Problem(model, params, system, kappa, harmonics, samples, saturation)


def default_samples(harmonics: int, motors: Motors | None) -> int:
    """AFT samples: ``4 H + 2`` (exact for the cubic links), ``8 H + 2`` with saturating
    motors (:data:`SATURATION_SAMPLES_PER_HARMONIC`)."""
    if motors is not None and motors.f_sat is not None:
        return SATURATION_SAMPLES_PER_HARMONIC * harmonics + 2
    return 4 * harmonics + 2
