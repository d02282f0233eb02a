"""The branch of limit cycles in p from the Hopf point: natural-parameter continuation
with a secant predictor and step halving (the simplest of BifurcationKit.jl's
continuation methods; folds of the branch, e.g. of a subcritical Hopf bifurcation, are
not followed: pseudo-arclength continuation would be needed there).

The Hopf point is that of the equilibrium ``A q_e + f_nl(q_e) = b`` (bent when b != 0, so
it can differ from :func:`axojax.critical_force`, which linearises about the straight
state): the root in p of the growth rate of its linearisation (its dominant deforming
mode on a base that moves: :func:`~axojax.orbits.guess.dominant_deforming`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import pathlib
from typing import Callable, Sequence

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import scipy.optimize

from .. import _io
from ..assembly import assemble
from ..critical import critical_force
from ..models.section import Model
from ..params import Params
from ..results import ResultFileError, check_arrays, jsonable, read_checked
from ..units import Units
from ._solve import solve_jit
from .cycle import LimitCycle
from .fourier import Problem
from .guess import dominant_deforming, equilibrium
from .solvers import AbstractOrbitSolver


def _eq_eigenvalue(model: Model, params: Params, kappa):
    prob = Problem(model, params, assemble(model, params), kappa, 1, 6)
    qe = equilibrium(prob)
    return dominant_deforming(prob, prob.s.A + prob.f_nl_tangent(qe))[0]


_eq_eigenvalue_jit = jax.jit(_eq_eigenvalue, static_argnums=0)


def hopf_point(
    model: Model, params: Params, kappa: float, *, rtol: float = 1e-10
) -> tuple[float, complex]:
    """(p_H, eigenvalue there): the first p (from the straight state's p_c upwards or
    downwards) where the equilibrium's dominant growth rate crosses 0.

    Raises:
        ValueError: when no crossing is found within a factor 4 of p_c.
    """
    p_c = float(critical_force(model, params).p)
    if not math.isfinite(p_c):
        raise ValueError("no Hopf point: the straight state stays stable for every p up to 1e7")
    g = lambda p: float(
        jnp.real(_eq_eigenvalue_jit(model, params.replace(p=p), jnp.asarray(kappa, float)))
    )
    lo, hi = p_c, p_c
    glo = ghi = g(p_c)
    step = 1.0 + 1e-3
    while ghi <= 0 and hi < 4 * p_c:  # the bent equilibrium is stabler: look above
        lo, glo = hi, ghi
        hi *= step
        step = 1 + 2 * (step - 1)
        ghi = g(hi)
    while glo > 0 and lo > p_c / 4:  # or less stable: look below
        hi, ghi = lo, glo
        lo /= step
        step = 1 + 2 * (step - 1)
        glo = g(lo)
    if not (glo <= 0 < ghi):
        raise ValueError(f"no Hopf point of the equilibrium within a factor 4 of p_c = {p_c:g}")
    p_h = scipy.optimize.brentq(g, lo, hi, rtol=rtol) if glo < 0 else lo
    return p_h, complex(_eq_eigenvalue_jit(model, params.replace(p=p_h), jnp.asarray(kappa, float)))


def _solve(model, params, kappa, solver, start):
    return solve_jit(model, params, jnp.asarray(kappa, float), solver, start)


def _predict(
    prev: LimitCycle, prev2: LimitCycle | None, p_prev: float, p_prev2: float | None, p: float
) -> LimitCycle:
    """Secant predictor: linear extrapolation of coefficients and omega in p."""
    if prev2 is None:
        return prev
    t = (p - p_prev) / (p_prev - p_prev2)
    X = prev.coefficients + t * (prev.coefficients - prev2.coefficients)
    w = prev.omega + t * (prev.omega - prev2.omega)
    return eqx.tree_at(lambda c: (c.coefficients, c.omega), prev, (X, w))


def continue_to(
    model: Model,
    params: Params,
    kappa: float,
    solver: AbstractOrbitSolver,
    p_targets: Sequence[float] | np.ndarray,
    *,
    p_hopf: float | None = None,
    max_halvings: int = 8,
    callback: Callable | None = None,
) -> list[LimitCycle | None]:
    """Limit cycles at the increasing forces ``p_targets`` (None where there is none),
    continued from the Hopf point; intermediate points are inserted where a step fails."""
    if p_hopf is None:
        p_hopf, _ = hopf_point(model, params, kappa)
    out: list[LimitCycle | None] = []
    prev = prev2 = None
    p_prev = p_prev2 = None
    for p in p_targets:
        p = float(p)
        cyc = None
        if p > p_hopf and prev is None:  # first point past the Hopf point: start near it
            p_start = p_hopf * (1 + 1e-3) if p > p_hopf * (1 + 1e-3) else 0.5 * (p + p_hopf)
            first = _solve(model, params.replace(p=p_start), kappa, solver, None)
            if bool(first.converged):
                prev, p_prev = first, p_start
        if p > p_hopf and prev is not None:
            marched = _march(
                model, params, kappa, solver, prev, prev2, p_prev, p_prev2, p, max_halvings
            )
            if marched is not None:
                cyc, prev2, p_prev2 = marched
                prev, p_prev = cyc, p
        out.append(cyc)
        if callback:
            callback(p, cyc)
    return out


def _march(
    model, params, kappa, solver, prev, prev2, p_prev, p_prev2, p, max_halvings, first_step=0.05
):
    """From the orbit at p_prev to p by adaptive steps (grown by 1.5 after a success,
    halved after a failure, given up after ``max_halvings`` failures in a row).
    Returns (orbit at p, orbit before it, its p) or None."""
    h = min(
        p - p_prev, first_step * p_prev if prev2 is None else max(p - p_prev, abs(p_prev - p_prev2))
    )
    fails = 0
    while p_prev < p:
        q = min(p, p_prev + h)
        cyc = _solve(
            model, params.replace(p=q), kappa, solver, _predict(prev, prev2, p_prev, p_prev2, q)
        )
        if bool(cyc.converged):
            prev2, p_prev2, prev, p_prev = prev, p_prev, cyc, q
            h *= 1.5
            fails = 0
        else:
            h /= 2
            fails += 1
            if fails > max_halvings:
                return None
    return prev, prev2, p_prev2


@dataclasses.dataclass
class Branch:
    """Limit cycles along p (physical summaries) and the Hopf point.

    Attributes:
        p: (P,) forces (dimensionless).
        cycles: per point, :meth:`LimitCycle.to_json` plus ``"p"``, or None (no orbit).
        p_hopf: Hopf point of the equilibrium; hopf_frequency_hz: frequency there.
        meta: model, parameters, cubic, units, solver.
    """

    p: np.ndarray
    cycles: list[dict | None]
    p_hopf: float
    hopf_frequency_hz: float
    meta: dict

    def to_json(self) -> dict:
        """The ``axojax orbit --json`` document (plain Python)."""
        return jsonable(
            {
                "orbits": [c for c in self.cycles if c is not None],
                "hopf": {"p": self.p_hopf, "frequency_hz": self.hopf_frequency_hz},
                "missing": [float(p) for p, c in zip(self.p, self.cycles) if c is None],
            }
        )

    def arrays(self) -> dict[str, np.ndarray]:
        def col(key, default=np.nan):
            return np.array([default if c is None else c[key] for c in self.cycles], dtype=float)

        k = max([len(c["floquet"]) for c in self.cycles if c is not None] or [0])
        fl = np.full((len(self.cycles), k), np.nan + 0j)
        for i, c in enumerate(self.cycles):
            if c is not None:
                for j, (re, im) in enumerate(c["floquet"]):
                    fl[i, j] = re + 1j * im
        return {
            "p": np.asarray(self.p, float),
            "frequency_hz": col("frequency_hz"),
            "period_s": col("period_s"),
            "tip_amplitude_um": col("tip_amplitude_um"),
            "wavelength_um": col("wavelength_um"),
            # 1 stable, 0 unstable, 2 unknown (no multipliers), -1 no orbit
            "stable": np.array(
                [
                    -1 if c is None else (2 if c["stable"] is None else int(c["stable"]))
                    for c in self.cycles
                ]
            ),
            "floquet_real": fl.real,
            "floquet_imag": fl.imag,
        }

    def save(self, path: str | pathlib.Path) -> None:
        """Write :meth:`arrays` and the meta to ``path`` (``.npz``, any case; written
        whole, :mod:`axojax._io`). Raises ``ValueError`` for another suffix or a directory
        that does not take the file (:func:`axojax._io.check_output_path`)."""
        path = _io.check_output_path(path, (".npz",))
        meta = {
            **self.meta,
            "kind": "orbit_branch",
            "p_hopf": self.p_hopf,
            "hopf_frequency_hz": self.hopf_frequency_hz,
        }
        with _io.atomic_path(path) as tmp:
            np.savez_compressed(tmp, **self.arrays(), meta=np.array(json.dumps(meta)))

    @staticmethod
    def load(path: str | pathlib.Path) -> tuple[dict[str, np.ndarray], dict]:
        """(arrays, meta) of a saved branch."""
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            if meta.get("kind") != "orbit_branch":
                raise ValueError(f"{str(path)!r} is not an axojax orbit branch file")
            return {k: f[k] for k in f.files if k != "meta"}, meta

    @staticmethod
    def read(path: str | pathlib.Path) -> tuple[dict[str, np.ndarray], dict]:
        """:meth:`load`, the file checked whole: every array of :meth:`arrays` there, one
        entry per p; a file that is not is one :class:`~axojax.results.ResultFileError`
        naming it."""

        def checked(path):
            arrays, meta = Branch.load(path)
            n = len(np.atleast_1d(arrays.get("p", [])))
            expect = {
                "p": (n,),
                "tip_amplitude_um": (n,),
                "frequency_hz": (n,),
                "stable": (n,),
                "floquet_real": (n, None),
                "floquet_imag": (n, None),
            }
            missing = [k for k in expect if k not in arrays]
            if missing:
                raise ResultFileError(
                    f"{str(path)!r} is an orbit branch file without its {missing[0]!r} array"
                )
            check_arrays(path, "orbit_branch", arrays, expect)
            return arrays, meta

        return read_checked(path, "orbit_branch", checked)


def branch(
    model: Model,
    params: Params,
    kappa: float,
    p_values: Sequence[float] | np.ndarray,
    *,
    solver: AbstractOrbitSolver,
    units: Units = Units(),
    callback: Callable | None = None,
) -> Branch:
    """Continue the limit cycle over ``p_values`` (sorted ascending) from the Hopf point."""
    p_values = np.sort(np.asarray(p_values, dtype=float))
    p_h, lam = hopf_point(model, params, kappa)
    cycles = continue_to(model, params, kappa, solver, p_values, p_hopf=p_h, callback=callback)
    reports = [
        None if c is None else {"p": float(p), **c.to_json(units)} for p, c in zip(p_values, cycles)
    ]
    meta = {
        "model": model.name,
        "n_elements": model.n_elements,
        "imbalance_kind": model.imbalance_kind,
        "cubic": float(kappa),
        "params": {k: float(v) for k, v in params.as_dict().items() if k != "p"},
        "units": {
            "length_um": units.length_um,
            "ei_pn_um2": units.ei_pn_um2,
            "cn_pn_s_um2": units.cn_pn_s_um2,
            "tau_s": units.tau_s,
        },
        "solver": repr(solver),
    }
    return Branch(
        p=p_values,
        cycles=reports,
        p_hopf=p_h,
        hopf_frequency_hz=abs(lam.imag) / (2 * math.pi * units.tau_s),
        meta=meta,
    )
