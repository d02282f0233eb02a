"""``LimitCycle``: a periodic orbit and its measures (dimensionless fields; physical
units through :class:`axojax.Units`)."""

from __future__ import annotations

from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Complex, Float

from .. import results
from ..eigen.metrics import tangent_wavenumber
from ..models.section import Model
from ..results import RESULTS
from ..units import Units
from ..waveform import FourierModes
from ..waveform import measures as wm
from ..waveform.shapes import centreline
from .fourier import evaluate

REFINE_GRID = 512


class LimitCycle(eqx.Module):
    """A periodic orbit ``q(theta) = c_0 + sum_k a_k cos(k theta) + b_k sin(k theta)``,
    ``theta = omega t`` (t in tau, q in L).

    Attributes:
        model: the model (static).
        coefficients: (2H+1, n) ``[c_0, a_1..a_H, b_1..b_H]``; n = N (``model.n_unknowns``),
            or with motor kinetics 2 N: the state X = (q, y) (:mod:`axojax.orbits.motors`;
            :attr:`q_coefficients` holds q's).
        omega: angular frequency (rad per tau).
        amplitude: half peak-to-peak tip displacement along the beat direction (L).
        beat_angle: beat direction (radians from y towards z; 0 in planar models).
        wavenumber: phase slope of psi_1 (least-squares, over the length), the first
            harmonic of the tangent angle
            along the beat direction (rad per L; negative: anterograde; docs/model.md,
            :mod:`axojax.waveform.measures`).
        floquet: (k,) multipliers of largest modulus, largest first (NaN-padded); one is
            1 (the phase). On a base that moves, without the rigid motions' (those are
            :attr:`rigid_floquet`); :attr:`trivial_multipliers` and
            :attr:`stability_multipliers` set the trivial ones apart.
        converged: whether Newton converged (otherwise the coefficients are a finite
            stand-in: the linear mode at small amplitude).
        started: whether there was a start (False: the Hopf normal form has no orbit here).
        steps: Newton iterations (last stage).
        correction: last scaled Newton correction.
        linear_eigenvalue: dominant eigenvalue of the equilibrium the orbit surrounds (bent
            by the static moment b where b != 0) at these parameters (with motor kinetics:
            of the augmented pencil).
        phase_ref: (n,) the phase condition ``phase_ref . b_1 = 0``.
        result: :class:`axojax.results.RESULTS` item: ``successful``, ``no_start``
            (no start: ``started`` False), ``nonlinear_max_steps_reached`` (Newton did
            not converge) or ``rigid_drift`` (a base that moves, under a load with a net
            rigid-body force or torque: no periodic orbit).
        rigid_drift: (r,) on a base that moves (r = ``model.rigid_modes()`` columns:
            free and head bases a translation and a rotation per direction, a pivot
            without a spring a rotation), the drift velocities (L or rad per tau) of the
            rigid motions that the bordered Newton system solves for: ~0 (to rounding) for a
            periodic orbit (:mod:`axojax.orbits.rigid`; the rigid offset of the mean
            state is fixed at 0, ``Y^T c_0 = 0``). Empty on a held base.
        rigid_floquet: (r,) the rigid motions' Floquet multipliers (1 to rounding; NaN
            when no multipliers were computed). Empty on a held base.
    """

    model: Model = eqx.field(static=True)
    coefficients: Float[Array, "m n"]
    omega: Float[Array, ""]
    amplitude: Float[Array, ""]
    beat_angle: Float[Array, ""]
    wavenumber: Float[Array, ""]
    floquet: Complex[Array, " k"]
    converged: Array
    started: Array
    steps: Array
    correction: Array
    linear_eigenvalue: Complex[Array, ""]
    phase_ref: Float[Array, " n"]
    result: RESULTS = eqx.field(default_factory=lambda: RESULTS.successful)
    rigid_drift: Float[Array, " r"] = eqx.field(default_factory=lambda: jnp.zeros(0))
    rigid_floquet: Complex[Array, " r"] = eqx.field(default_factory=lambda: jnp.zeros(0, complex))

    # -- physical units -------------------------------------------------------------
    @property
    def period(self) -> Float[Array, ""]:
        """Period (tau)."""
        return 2 * jnp.pi / self.omega

    @property
    def q_coefficients(self) -> Float[Array, "m N"]:
        """(2H+1, N) the coefficients of the model's state q (without the motors' copy y
        of motor kinetics): what the waveform is read from."""
        return self.coefficients[..., : self.model.n_unknowns]

    @property
    def harmonics(self) -> int:
        return (self.coefficients.shape[-2] - 1) // 2

    def frequency_hz(self, units: Units = Units()) -> Float[Array, ""]:
        return self.omega / (2 * jnp.pi * units.tau_s)

    def period_s(self, units: Units = Units()) -> Float[Array, ""]:
        return self.period * units.tau_s

    def amplitude_um(self, units: Units = Units()) -> Float[Array, ""]:
        """Tip amplitude along the beat direction (um; half peak-to-peak)."""
        return self.amplitude * units.length_um

    def wavelength_um(self, units: Units = Units()) -> Float[Array, ""]:
        """2 pi / |wavenumber| (um); inf for a standing wave."""
        return wm.wavelength(self.wavenumber) * units.length_um

    @property
    def direction(self) -> Array:
        """+1 anterograde (base to tip), -1 retrograde, 0 standing."""
        return wm.direction(self.wavenumber, self.omega)

    @property
    def n_rigid(self) -> int:
        """r, the rigid motions the base leaves free (0 on a held base)."""
        return int(self.model.rigid_modes().shape[1])

    def _phase_index(self) -> Array:
        """Index in :attr:`floquet` of the time shift's multiplier (the closest to 1)."""
        rho = self.floquet
        return jnp.argmin(jnp.where(jnp.isfinite(rho), jnp.abs(rho - 1), jnp.inf), axis=-1)

    @property
    def trivial_multipliers(self) -> Complex[Array, " t"]:
        """(r + 1,) the multipliers that are 1 by symmetry: the rigid motions' (r of them,
        :attr:`rigid_floquet`), then the time shift's (of :attr:`floquet`, the closest to
        1). Empty when no multipliers were computed."""
        rho = self.floquet
        if rho.shape[-1] == 0:
            return rho
        phase = jnp.take_along_axis(rho, self._phase_index()[..., None], axis=-1)
        return jnp.concatenate([self.rigid_floquet, phase], axis=-1)

    @property
    def stability_multipliers(self) -> Complex[Array, " k1"]:
        """(k - 1,) the multipliers that decide stability: :attr:`floquet` without the
        time shift's (NaN-padded as :attr:`floquet`; the rigid motions' are not in it)."""
        rho = self.floquet
        k = rho.shape[-1]
        if k == 0:
            return rho
        idx = jnp.arange(k - 1)
        idx = idx + (idx >= self._phase_index()[..., None])
        return jnp.take_along_axis(rho, idx, axis=-1)

    @property
    def stable(self) -> Array:
        """All :attr:`stability_multipliers` (every multiplier but the trivial ones: the
        time shift's and, on a base that moves, the rigid motions') inside the unit circle
        (False when none were computed: ``HarmonicBalance(floquet=0)``)."""
        rho = self.floquet
        if rho.shape[-1] == 0:
            return jnp.zeros(rho.shape[:-1], bool)
        others = self.stability_multipliers
        return jnp.max(jnp.where(jnp.isfinite(others), jnp.abs(others), 0.0), axis=-1) < 1.0

    # -- the waveform -----------------------------------------------------------------
    def states(self, n_frames: int = 64) -> tuple[np.ndarray, np.ndarray]:
        """(t (T,) in tau over one period, q (T, N)) at ``n_frames`` equal phase steps
        (q only: without the motors' copy y)."""
        theta = 2 * np.pi * np.arange(n_frames) / n_frames
        q = evaluate(self.q_coefficients, jnp.asarray(theta))
        return theta / float(self.omega), np.asarray(q)

    def centreline_beat(
        self, x: np.ndarray, n_frames: int = 64, derivative: int = 0
    ) -> tuple[np.ndarray, np.ndarray]:
        """(t (T,) tau, centreline (or slope) along the beat direction (T, S), L or rad):
        the displacement in the body frame, the slope in the lab frame (as
        :func:`axojax.waveform.shapes.centreline` with ``body=True``)."""
        t, q = self.states(n_frames)
        u = centreline(self.model, q, np.asarray(x, dtype=float), derivative, body=True)
        return t, wm.along(u, float(self.beat_angle))

    def tangent_modes(
        self, x: Float[ArrayLike, " S"]
    ) -> tuple[Float[Array, " S"], Complex[Array, " S"]]:
        """(psi_0 (S,), psi_1 (S,)) in rad at the concrete points ``x`` in [0, 1]: the
        orbit's harmonics 0 and 1 of the tangent angle along its beat direction,
        psi = psi_0 + Re(psi_1 e^{i theta}) + higher harmonics, theta = omega t (the
        orbit's phase: theta = 0 where its phase condition holds). Differentiable."""
        X, H = self.q_coefficients, self.harmonics
        slope = centreline(self.model, jnp.stack([X[0], X[1], X[H + 1]]), np.asarray(x), 1)
        psi = wm.along(slope, self.beat_angle)  # (3, S)
        return psi[0], psi[1] - 1j * psi[2]

    def fourier_modes(self, n_points: int = 41, units: Units = Units()) -> FourierModes:
        """Static and first Fourier modes of the tangent angle psi(s, t) along the beat
        direction (s in um, ``n_points`` uniform on [0, L]): exactly the orbit's
        harmonics 0 and 1."""
        x = np.linspace(0.0, 1.0, n_points)
        psi0, psi1 = self.tangent_modes(x)
        return FourierModes(
            s=x * units.length_um,
            psi0=np.asarray(psi0),
            psi1=np.asarray(psi1),
            omega=float(self.frequency_hz(units)) * 2 * np.pi,
        )

    @property
    def message(self) -> str:
        """``result``'s message on one line (:func:`axojax.results.message`)."""
        return results.message(self.result)

    def to_json(self, units: Units = Units()) -> dict[str, Any]:
        """Plain-Python summary in physical units (``axojax orbit --json``): the measures
        of :func:`axojax.orbits.cycle_measures` (the same numbers a fit and the paper
        table give); a standing wave's wavelength is ``None``."""
        from .measures import cycle_measures  # measures builds on this module

        m = cycle_measures(self, None, units)
        rho = np.asarray(self.floquet)
        rho = rho[np.isfinite(rho)]
        return results.jsonable(
            {
                "frequency_hz": float(m.frequency_hz),
                "period_s": float(self.period_s(units)),
                "tip_amplitude_um": float(m.tip_amplitude_um),
                "wavelength_um": wm.finite_or_none(m.wavelength_um),
                "direction": {1: "anterograde", -1: "retrograde"}.get(int(self.direction)),
                "static_curvature_rad_per_um": float(m.static_curvature_rad_per_um),
                "dynamic_amplitude_rad": float(m.dynamic_amplitude_rad),
                "floquet": [[float(r.real), float(r.imag)] for r in rho],
                "rigid_floquet": [
                    [float(r.real), float(r.imag)] for r in np.asarray(self.rigid_floquet)
                ],
                "rigid_drift": [float(v) for v in np.asarray(self.rigid_drift)],
                "stable": bool(self.stable) if rho.size else None,
                "converged": bool(self.converged),
                "harmonics": self.harmonics,
            }
        )


def measures(model: Model, X: Float[Array, "m n"]) -> tuple[Array, Array, Array]:
    """(tip amplitude (L), beat angle, wavenumber of psi_1 (rad/L)) of the orbit X;
    differentiable."""
    H = (X.shape[0] - 1) // 2
    tip = centreline(model, X, np.array([1.0]), body=True)[..., 0]  # (2H+1, d)
    if model.n_dirs == 1:
        angle = jnp.zeros(())
        y = tip[:, 0]
    else:
        osc = tip[1:]
        R = osc.T @ osc / 2  # covariance of the tip motion (2 x 2)
        angle = 0.5 * jnp.arctan2(2 * R[0, 1], R[0, 0] - R[1, 1])
        e = jnp.stack([jnp.cos(angle), jnp.sin(angle)])
        # sign convention of ax.simulate: the larger component of the direction is positive
        flip = jnp.where(jnp.abs(e[0]) >= jnp.abs(e[1]), e[0] < 0, e[1] < 0)
        angle = jnp.where(flip, angle + jnp.pi, angle)
        angle = jnp.where(angle > jnp.pi, angle - 2 * jnp.pi, angle)
        y = tip @ jnp.stack([jnp.cos(angle), jnp.sin(angle)])
    amplitude = wm.tip_amplitude(jnp.stack([_extreme(y, H, 1.0), _extreme(y, H, -1.0)]))
    Q1 = X[1] - 1j * X[H + 1]
    return amplitude, angle, tangent_wavenumber(model, Q1, angle)


def _extreme(y, H: int, sign: float):
    """max (sign=1) or min (sign=-1) of the trigonometric polynomial with coefficients y:
    the best of a fine grid, refined by Newton steps on y'(theta) = 0."""
    k = jnp.arange(1, H + 1)
    a, b = y[1 : H + 1], y[H + 1 :]
    grid = 2 * jnp.pi * jnp.arange(REFINE_GRID) / REFINE_GRID
    vals = evaluate(y[:, None], grid)[:, 0]
    th = jax.lax.stop_gradient(grid[jnp.argmax(sign * vals)])
    for _ in range(3):
        d1 = jnp.sum(k * (-a * jnp.sin(k * th) + b * jnp.cos(k * th)))
        d2 = jnp.sum(k**2 * (-a * jnp.cos(k * th) - b * jnp.sin(k * th)))
        th = jax.lax.stop_gradient(th - d1 / jnp.where(d2 != 0, d2, 1.0))
    return evaluate(y[:, None], th[None])[0, 0]
