"""Periodic-orbit solvers as objects, in the style of lineax's and diffrax's solvers.

``ax.limit_cycle(..., solver=ax.orbits.HarmonicBalance(harmonics=10))``. A solver holds
only static options (hashable: a static argument of ``jax.jit``) and turns
(model, params, kappa, start) into a :class:`~axojax.orbits.LimitCycle`.

- :class:`WarmStart`: another solver started from a nearby orbit (a fit's last
  iterate), falling back to the Hopf normal form.
- :class:`Recording`: another solver that reports the Newton iterations of every orbit
  it solves to a host function (diagnostics: what warm starts save).
- :class:`HarmonicBalance`: Fourier-Galerkin (trigonometric) collocation with exact
  alternating frequency-time projection of the cubic force
  (:mod:`axojax.orbits.fourier`), damped Newton with the exact Jacobian and the
  implicit-function-theorem derivative (:mod:`axojax.orbits.newton`), Floquet
  multipliers by Hill's method (:mod:`axojax.orbits.floquet`). Spectrally accurate in
  the number of harmonics; indifferent to the stiffness of the links.
"""

from __future__ import annotations

import abc
import dataclasses
from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp

from ..models.section import Model
from ..params import Params
from ..results import RESULTS
from .cycle import LimitCycle, measures
from .floquet import floquet_multipliers, rigid_floquet
from .fourier import pad
from .guess import hopf_guess
from .linear import orbit_factor
from .motors import Motors, default_samples, orbit_problem
from .newton import Restart, implicit_solve
from .rigid import DRIFT_RTOL, drift_ratio


class AbstractOrbitSolver(eqx.Module):
    """Finds the periodic orbit of ``C dq/dt = -A q - f_nl(q) + b`` (with ``motors``: of
    the augmented state X = (q, y) of motor kinetics, :mod:`axojax.orbits.motors`)."""

    @abc.abstractmethod
    def solve(
        self,
        model: Model,
        params: Params,
        kappa,
        start: LimitCycle | None = None,
        motors: Motors | None = None,
    ) -> LimitCycle:
        """The orbit, started from the Hopf normal form (``start=None``, or a ``start``
        that did not converge, or parameters before the Hopf point) or from a nearby orbit
        (continuation; where Newton fails from it, the returned stand-in is the start
        itself). ``motors``: motor kinetics and saturating motors
        (:class:`~axojax.orbits.motors.Motors`; None: the friction form). Differentiable in
        ``params``, ``kappa`` and ``motors``; the start is data, never differentiated."""

    def solve_from(
        self,
        model: Model,
        params: Params,
        kappa,
        start: LimitCycle,
        warm_steps: int,
        motors: Motors | None = None,
    ) -> LimitCycle:
        """The orbit from ``start`` within ``warm_steps`` Newton iterations; where that
        fails, :meth:`solve` from the Hopf normal form with the full budget (``steps``
        counts both attempts). This default traces both attempts (a ``lax.cond``);
        :class:`HarmonicBalance` does both in one Newton loop."""
        capped = self
        if hasattr(self, "max_steps"):
            capped = dataclasses.replace(self, max_steps=min(int(self.max_steps), int(warm_steps)))
        warm = call_solve(capped, model, params, kappa, start, motors)

        def cold():
            cycle = call_solve(self, model, params, kappa, None, motors)
            return eqx.tree_at(lambda c: c.steps, cycle, cycle.steps + warm.steps)

        # (an unconverged start is no start: the warm attempt then began at the Hopf
        # guess, and a failure within the cap is retried with the full budget too)
        return jax.lax.cond(warm.started & ~warm.converged, cold, lambda: warm)


class HarmonicBalance(AbstractOrbitSolver):
    """Harmonic balance with H harmonics (see the module docstring).

    Attributes:
        harmonics: H, the degree of the trigonometric polynomial (the orbit's harmonics
            decay geometrically: 10 gives ~1e-9 in the frequency of the 4-element two-filament
            beat at 1.04 p_c, cubic 10).
        samples: phases of the alternating frequency-time projection (default 4H + 2:
            exact for the cubic force).
        rtol: Newton's tolerance on the scaled correction.
        max_steps: Newton iterations.
        floquet: multipliers returned (largest modulus first); 0 skips them (fits).
        krylov: Arnoldi steps of the Floquet computation.
    """

    harmonics: int = 10
    samples: int | None = None
    rtol: float = 1e-10
    max_steps: int = 40
    floquet: int = 8
    krylov: int = 60

    def __check_init__(self):
        if int(self.harmonics) < 1:
            raise ValueError(f"harmonics must be an integer >= 1, got {self.harmonics!r}")
        if self.samples is not None and int(self.samples) < 2 * int(self.harmonics) + 1:
            raise ValueError(
                f"samples must be >= 2 harmonics + 1 = {2 * int(self.harmonics) + 1}, got {self.samples!r}"
            )

    def _problem(self, model: Model, H: int, motors: Motors | None):
        given = self.samples is not None and H == self.harmonics
        samples = self.samples if given else default_samples(H, motors)

        def make(theta):
            params, kappa, motors = theta
            return orbit_problem(model, params, kappa, H, samples, motors)

        return make

    def solve(self, model, params, kappa, start=None, motors=None):
        return self._solve(model, params, kappa, start, None, motors)

    def solve_from(self, model, params, kappa, start, warm_steps, motors=None):
        """As :meth:`AbstractOrbitSolver.solve_from`, in one Newton loop
        (:class:`~axojax.orbits.newton.Restart`): one traced iteration, not two."""
        return self._solve(model, params, kappa, start, int(warm_steps), motors)

    def _solve(self, model, params, kappa, start, warm_steps, motors=None):
        H = int(self.harmonics)
        theta = (params, jnp.asarray(kappa, dtype=float), motors)
        make = self._problem(model, H, motors)
        prob = make(theta)
        fixed = make(
            jax.lax.stop_gradient(theta)
        )  # the start and the multipliers are not differentiated
        x_hopf, ref_hopf, lam, fallback_hopf = hopf_guess(fixed)
        x0, ref, fallback, restart, accept = x_hopf, ref_hopf, fallback_hopf, None, None
        if start is not None:
            # An unconverged (or non-finite) start is no start: the Hopf guess. Nor is any
            # start before the Hopf point (a stable equilibrium, Re lambda <= 0): there
            # is no orbit of the supercritical branch to continue to (a fit's trial step
            # there fails at once, as from the Hopf guess, instead of after max_steps).
            X0 = resize(start.coefficients, H)
            x_warm = prob.join(X0, start.omega)
            warm = start.converged & jnp.all(jnp.isfinite(x_warm)) & (jnp.real(lam) > 0)
            x0 = jnp.where(warm, x_warm, x_hopf)
            ref = jnp.where(warm, start.phase_ref, ref_hopf)
            fallback = jnp.where(warm, x_warm, fallback_hopf)
            if warm_steps is not None:  # where the start fails: the Hopf guess, full budget
                restart = Restart(x_hopf, ref_hopf, fallback_hopf, warm_steps)
                accept = lambda p, x: _nontrivial(p.split(x)[0])
        x, info, ref = implicit_solve(
            make,
            orbit_factor,
            theta,
            x0,
            ref,
            rtol=self.rtol,
            max_steps=self.max_steps,
            fallback=fallback,
            restart=restart,
            accept=accept,
        )
        X, omega = prob.split(x)
        drift = prob.drift(x)
        # Newton may also land on the equilibrium (zero amplitude, any omega): not an orbit.
        info = info.at[0].set(jnp.where(_nontrivial(X), info[0], 0.0))
        # On a base that moves, a drift (a net rigid-body load) leaves no periodic orbit.
        drifts = jnp.array(False)
        if prob.r:
            drifts = (info[0] > 0.5) & ~(drift_ratio(drift, X, omega) <= DRIFT_RTOL)
            info = info.at[0].set(jnp.where(drifts, 0.0, info[0]))
        started = jnp.where(info[3] > 0.5, jnp.all(jnp.isfinite(x_hopf)), jnp.all(jnp.isfinite(x0)))
        amplitude, angle, k = measures(model, X[:, : model.n_unknowns])  # q, without y
        if self.floquet > 0:
            rho = floquet_multipliers(
                fixed,
                jax.lax.stop_gradient(X),
                jax.lax.stop_gradient(omega),
                count=self.floquet,
                krylov=self.krylov,
            )
            rigid_rho = rigid_floquet(fixed, jax.lax.stop_gradient(X), jax.lax.stop_gradient(omega))
        else:
            rho = jnp.full((0,), jnp.nan + 0j)
            rigid_rho = jnp.full((prob.r,), jnp.nan + 0j)
        return LimitCycle(
            model=model,
            coefficients=X,
            omega=omega,
            amplitude=amplitude,
            beat_angle=angle,
            wavenumber=k,
            floquet=rho,
            converged=info[0] > 0.5,
            started=started,
            steps=info[1].astype(int),
            correction=info[2],
            linear_eigenvalue=lam,
            phase_ref=ref,
            result=RESULTS.where(
                info[0] > 0.5,
                RESULTS.successful,
                RESULTS.where(
                    drifts,
                    RESULTS.rigid_drift,
                    RESULTS.where(started, RESULTS.nonlinear_max_steps_reached, RESULTS.no_start),
                ),
            ),
            rigid_drift=drift,
            rigid_floquet=rigid_rho,
        )


def _nontrivial(X):
    """Whether harmonic coefficients (2H+1, n) are an orbit, not the equilibrium."""
    return jnp.linalg.norm(X[1:]) > 1e-9 * jnp.maximum(1.0, jnp.linalg.norm(X[0]))


class WarmStart(AbstractOrbitSolver):
    """Another solver, started from a nearby orbit where one is given, with the Hopf
    normal form as the fallback: for fits, profiles and continuation, where each orbit
    is near the last one solved.

    With ``start``: Newton from it for at most ``warm_steps`` iterations (the inner
    solver's ``max_steps`` capped); where that fails, the inner solver again from the
    Hopf normal form with its full budget (the inner solver's
    :meth:`~AbstractOrbitSolver.solve_from`). So the orbit is the cold one (up to the
    solver's tolerance and the arbitrary time origin) at a few Newton steps when the
    start is near. The returned ``steps`` count both attempts. Without ``start``: the
    inner solver. The start is data, never differentiated. :class:`HarmonicBalance`
    makes both attempts in one Newton loop, so compilation costs little more than the
    inner solver's; other solvers trace both (a ``lax.cond``).

    Attributes:
        solver: the inner solver (e.g. :class:`HarmonicBalance` with ``floquet=0``).
        warm_steps: Newton iterations the warm attempt gets.
    """

    solver: AbstractOrbitSolver = HarmonicBalance(floquet=0)
    warm_steps: int = 10

    def solve(self, model, params, kappa, start=None, motors=None):
        if start is None:
            return call_solve(self.solver, model, params, kappa, None, motors)
        start = jax.lax.stop_gradient(start)
        if motors is None:
            return self.solver.solve_from(model, params, kappa, start, int(self.warm_steps))
        return self.solver.solve_from(model, params, kappa, start, int(self.warm_steps), motors)


class Recording(AbstractOrbitSolver):
    """Another solver, reporting the Newton iterations of every orbit it solves.

    ``callback(steps)`` runs on the host (``jax.debug.callback``) with the orbit's
    ``LimitCycle.steps`` as a 0-d numpy array, also inside ``jax.jit`` and a fit's
    compiled loop, and once per orbit under ``vmap``: one call per orbit solved. Warm
    starts (:meth:`solve_from`) go to the inner solver's own, so a wrapped
    :class:`HarmonicBalance` keeps its one-loop warm start. For diagnostics and tests
    (e.g. how many Newton steps a warm-started fit saves)::

        steps = []
        solver = ax.orbits.Recording(ax.orbits.HarmonicBalance(floquet=0), lambda k: steps.append(int(k)))

    Attributes:
        solver: the inner solver.
        callback: the host function.
    """

    solver: AbstractOrbitSolver
    callback: Callable = eqx.field(static=True)

    def solve(self, model, params, kappa, start=None, motors=None):
        return self._record(call_solve(self.solver, model, params, kappa, start, motors))

    def solve_from(self, model, params, kappa, start, warm_steps, motors=None):
        extra = () if motors is None else (motors,)
        return self._record(self.solver.solve_from(model, params, kappa, start, warm_steps, *extra))

    def _record(self, cycle: LimitCycle) -> LimitCycle:
        jax.debug.callback(self.callback, cycle.steps)
        return cycle


def call_solve(
    solver: AbstractOrbitSolver,
    model: Model,
    params: Params,
    kappa,
    start: LimitCycle | None,
    motors: Motors | None,
) -> LimitCycle:
    """``solver.solve``, passing ``motors`` only where there are some: a solver written
    before motor kinetics (``solve(model, params, kappa, start)``) still serves the
    friction form."""
    if motors is None:
        return solver.solve(model, params, kappa, start)
    return solver.solve(model, params, kappa, start, motors)


def resize(X, harmonics: int):
    """Coefficients (2H+1, n) as those of ``harmonics`` harmonics (padded or truncated)."""
    H = (X.shape[0] - 1) // 2
    if harmonics >= H:
        return pad(X, harmonics)
    return jnp.concatenate([X[: harmonics + 1], X[H + 1 : H + 1 + harmonics]], axis=0)


OrbitSolver = AbstractOrbitSolver
"""The former name of :class:`AbstractOrbitSolver`, kept for existing code."""
