"""Where each row of a comparison starts (issue 45's global search per row).

A row's starts are, in this order: the optima of the rows it contains
(:func:`nested_starts`); then its exact Hopf points (:func:`hopf_starts`: the coefficients
at which the observed beat i omega0 is exactly an eigenvalue, so both pins hold) and a
Sobol design of its box, screened by their loss in one vmapped, compiled program
(:func:`screened_starts`), of which the best :func:`row_starts` are kept.

Hopf points: at lambda = i omega0 the pencil A + lambda C of a regulated row is
K0 + chi U_chi + beta U_beta, linear in the complex chi and beta (docs/model.md section 8),
so the coefficients that make it singular are generalised eigenvalues: all of them for
sliding, along a ladder of chi' for curvature, along a grid of beta for both. With basal
compliance the pencil is linear in the complex chi_b = kb + i omega xib as well
(:func:`compliance_starts`); an elastic row takes the mechanism's Hopf points along a
ladder of kb. Values are dimensionless (:class:`~axojax.Params`); starts handed to a
problem are in its fitted coordinate u.
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np

from ...params import MECHANISM_NAMES, Params
from ..problem import Problem
from .mechanisms import BASAL_FREE, Row, compliance_bounds, compliance_of

ELASTIC_LADDER = 9
"""Values of kb along which an elastic row's Hopf points are found."""
MAX_HOPF_STARTS = 1024
"""At most about this many Hopf points of an elastic row are screened (evenly taken)."""
COMPLIANCE_GRID = 17**3
"""Points of the grid of a compliant row's own free values in :func:`compliance_starts`
(33 values each for two)."""

SCREEN = 64
"""Sobol points screened (with the Hopf points) for the starts of each row."""
BATCH = 64
"""Candidates per vmapped evaluation while screening (one compiled program per row)."""


def screened_starts(problem: Problem, candidates: np.ndarray, n: int) -> np.ndarray:
    """The ``n`` candidates (c, k; fitted coordinates u) of least loss, best first,
    evaluated in one compiled, vmapped program (batches of :data:`BATCH`)."""
    candidates = np.asarray(candidates, dtype=float)
    if len(candidates) == 0:
        return candidates
    chi2 = jax.jit(jax.vmap(lambda u: jnp.sum(problem.residuals(u) ** 2)))
    losses = []
    for i in range(0, len(candidates), BATCH):
        chunk = candidates[i : i + BATCH]
        padded = np.vstack([chunk, np.repeat(chunk[-1:], BATCH - len(chunk), axis=0)])
        losses.append(np.asarray(chi2(jnp.asarray(padded)))[: len(chunk)])
    loss = np.concatenate(losses)
    loss = np.where(np.isfinite(loss), loss, np.inf)
    order = np.argsort(loss, kind="stable")
    return candidates[order[:n]]


def values_to_u(problem: Problem, values: np.ndarray) -> np.ndarray:
    """Values (c, k) of the problem's free parameters -> fitted coordinates u."""
    out = np.array(values, dtype=float)
    for j, p in enumerate(problem.parameters):
        if p.log:
            out[:, j] = np.log(np.maximum(out[:, j], 1e-300))
    return out


def row_starts(starts: int, n_free: int) -> int:
    """Screened starts of a row with ``n_free`` free values: ``starts``, one more for each
    free value beyond two (a larger box has more optima to find)."""
    return int(starts) + max(0, int(n_free) - 2)


def nested_starts(problem: Problem, spec: Row, inner: list) -> np.ndarray:
    """(c, k) starts in ``problem``'s u: the optima of the rows ``spec`` contains, each
    value taken over by name and the others at the value that makes this row that one
    (chi, beta, cb 0; xib at its low end)."""
    floor = {"xib": spec.bounds.get("xib", (0.0, 0.0))[0]}
    out = []
    for r in inner:
        if not all(math.isfinite(v) for v in r.params.values()):
            continue
        out.append([r.params.get(n, floor.get(n, 0.0)) for n in problem.names])
    if not out:
        return np.zeros((0, len(problem.names)))
    return values_to_u(problem, np.array(out, dtype=float))


# -- exact Hopf points: starts of a regulated row ------------------------------------------
def _unit_terms(row: Row, second: str = "beta") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(K0, U_chi, U_second): at lambda = i omega0 the pencil A + lambda C of the row's
    model is K0 + chi U_chi + beta U_beta, linear in the complex chi = chi' + i chi'' and
    beta = beta' + i beta'' (docs/model.md section 8: the terms equal chi and beta there);
    ``second="normal"``: the augmented pencil of normal-force control
    (:func:`~axojax.assembly.normal_force.assemble_normal`), K0 + chi U_chi + g U_g (the
    gain's friction g''/omega0 d/dt is i g'' there)."""
    from ...assembly import assemble
    from ...assembly.normal_force import assemble_normal

    lam = row.shift
    build = assemble_normal if second == "normal" else assemble
    zero = ("chi_re", "chi_im", f"{second}_re", f"{second}_im")
    base = row.params.replace(**dict.fromkeys(zero, 0.0))

    def pencil(prm: Params) -> np.ndarray:
        system = build(row.model, prm)
        return np.asarray(system.A) + lam * np.asarray(system.C)

    k0 = pencil(base)
    unit = pencil(base.replace(**{f"{second}_re": 1.0})) - k0
    return k0, pencil(base.replace(chi_re=1.0)) - k0, unit


def _solve(k: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """Every complex g with K + g U singular (finite generalised eigenvalues)."""
    import scipy.linalg as sl

    g = sl.eig(k, -unit, right=False)
    return g[np.isfinite(g)]


def _grid(bound: float, n: int = 8) -> np.ndarray:
    """0 and +- a geometric ladder up to ``bound`` (n values each side)."""
    ladder = np.geomspace(bound * 1e-3, bound, n)
    return np.concatenate([[0.0], ladder, -ladder])


def _ladder(row: Row, name: str, n: int) -> np.ndarray:
    """``n`` values of a free field inside its bounds: 0 and a signed geometric ladder for
    chi and beta, a geometric one for a positive field."""
    lo, hi = row.bounds[name]
    if name in MECHANISM_NAMES:
        return _grid(hi, n // 2)
    if lo <= 0:  # gamma: signed, fitted linearly
        return np.linspace(lo, hi, n + 2)[1:-1]
    return np.geomspace(lo, hi, n + 2)[1:-1]


def compliance_starts(row: Row) -> np.ndarray:
    """(c, k) values of a row with basal compliance at which i omega (the observed beat)
    is exactly an eigenvalue: on a grid of the row's own free values
    (:data:`COMPLIANCE_GRID` points in all), the complex chi_b = kb + i omega xib that makes the
    pencil A + i omega C singular, kept where kb and xib are inside their bounds. The
    compliance adds kb E + xib E to A and C (E of rank m, the active pairs), so chi_b
    solves det(I + chi_b E K^-1) = 0: m values per grid point (Sartori et al. determine
    chi_b so)."""
    import jax
    import jax.numpy as jnp

    from ...assembly import assemble

    lam = 1j * row.omega
    own = [f for f in row.free if f not in BASAL_FREE["compliance"]]
    n = max(3, int(round(COMPLIANCE_GRID ** (1 / max(len(own), 1)))))
    grids = np.meshgrid(*[_ladder(row, f, n) for f in own], indexing="ij")
    values = np.stack([g.ravel() for g in grids], axis=1)
    base = row.params.replace(kb=0.0, xib=0.0)

    def pencil(v):
        system = assemble(row.model, base.with_values(dict(zip(own, v)), row.kl_ratio))
        return system.A + lam * system.C

    unit = np.asarray(assemble(row.model, base.replace(kb=1.0)).A) - np.asarray(
        assemble(row.model, base).A
    )
    idx = np.flatnonzero(np.any(unit != 0, axis=1))
    pencils = jax.jit(jax.vmap(pencil))
    kept, chi_b = [], []
    batch = min(256, len(values))  # pencils at a time (bounded memory), one compilation
    for i in range(0, len(values), batch):
        chunk = values[i : i + batch]
        padded = np.vstack([chunk, np.repeat(chunk[-1:], batch - len(chunk), axis=0)])
        k = np.asarray(pencils(jnp.asarray(padded)))[: len(chunk)]
        keep = np.isfinite(k).all(axis=(1, 2)) & (np.linalg.cond(k) < 1e14)
        rhs = np.zeros((int(keep.sum()), k.shape[1], idx.size))
        rhs[:, idx, np.arange(idx.size)] = 1.0
        x = np.linalg.solve(k[keep], rhs)
        mu = np.linalg.eigvals(unit[np.ix_(idx, idx)] @ x[:, idx, :])  # (G, m)
        with np.errstate(divide="ignore", invalid="ignore"):
            chi_b.append(-1.0 / mu)
        kept.append(chunk[keep])
    values, chi_b = np.concatenate(kept), np.concatenate(chi_b)
    rows = []
    for v, gs in zip(values, chi_b):
        for g in gs[np.isfinite(gs)]:
            if g.real <= 0:
                continue  # not a spring
            point = dict(zip(own, v), cb=compliance_of(g.real), xib=g.imag / row.omega)
            rows.append([point[f] for f in row.free])
    return _inside(row, np.array(rows).reshape(-1, len(row.free)))


def _inside(row: Row, out: np.ndarray) -> np.ndarray:
    lo = np.array([row.bounds[f][0] for f in row.free])
    hi = np.array([row.bounds[f][1] for f in row.free])
    return out[np.all((out > lo) & (out < hi), axis=1)]


def hopf_starts(row: Row) -> np.ndarray:
    """(c, k) values of the row's free fields at which i omega0 is exactly an eigenvalue
    (the pins hold), inside the bounds: every Hopf point of ``sliding`` (a generalised
    eigenproblem in chi), of ``curvature`` along a ladder of chi' (one in beta), and of
    ``sliding+curvature`` along a ladder of complex beta (one in chi) and with either
    coefficient 0. With basal compliance, any mechanism: :func:`compliance_starts`.
    Empty for ``steady`` without it (its beat is the dominant mode)."""
    if row.compliance and "xib" in row.free:
        return compliance_starts(row)
    if row.compliance:  # elastic: the Hopf points of the mechanism along a ladder of kb
        lo, hi = compliance_bounds(row.model, row.params, row.omega)["kb"]
        rest = dataclasses.replace(row, free=tuple(f for f in row.free if f != "cb"))
        out = [
            np.hstack([p, np.full((len(p), 1), compliance_of(kb))])
            for kb in np.geomspace(lo, hi, ELASTIC_LADDER + 2)[1:-1]
            for p in [_mechanism_hopf(dataclasses.replace(rest, params=row.params.replace(kb=kb)))]
        ]
        order = [*rest.free, "cb"]
        out = np.vstack(out)[:, [order.index(f) for f in row.free]]
        return out[:: max(1, len(out) // MAX_HOPF_STARTS)]
    return _mechanism_hopf(row)


def _mechanism_hopf(row: Row) -> np.ndarray:
    """:func:`hopf_starts` of a row whose compliance, if any, is fixed in its params."""
    if row.shift is None or row.mechanism == "steady":
        return np.zeros((0, len(row.free)))
    if "normal_re" in row.free:
        return _normal_hopf(row)
    k0, u_chi, u_beta = _unit_terms(row)
    b = row.bounds
    points: list[dict[str, float]] = []
    if "chi_im" in row.free:  # sliding, or sliding + curvature: solve for chi
        betas = [0.0]
        if "beta_re" in row.free:  # beta' and (if free) beta'' on a grid
            dynamic = "beta_im" in row.free
            re = _grid(b["beta_re"][1], 3 if dynamic else 8)
            im = _grid(b["beta_re"][1], 3) if dynamic else [0.0]
            betas += [complex(x, y) for x in re for y in im]
        for beta in betas:
            for chi in _solve(k0 + beta * u_beta, u_chi):
                points.append(
                    {
                        "chi_re": chi.real,
                        "chi_im": chi.imag,
                        "beta_re": beta.real,
                        "beta_im": beta.imag,
                    }
                )
    if "beta_im" in row.free:  # curvature (chi' real), or chi'' = 0 of sliding + curvature
        for chi in _grid(b["chi_re"][1]):
            for beta in _solve(k0 + chi * u_chi, u_beta):
                points.append(
                    {"chi_re": chi, "chi_im": 0.0, "beta_re": beta.real, "beta_im": beta.imag}
                )
    out = np.array([[p[f] for f in row.free] for p in points]).reshape(-1, len(row.free))
    return _inside(row, out)


def _normal_hopf(row: Row) -> np.ndarray:
    """:func:`hopf_starts` of a normal-force row: at lambda = i omega0 the augmented pencil
    (:func:`~axojax.assembly.normal_force.assemble_normal`) is K0 + chi U_chi + g U_g,
    linear in the complex chi and the complex gain g (its friction g''/omega0 d/dt is
    i g'' there). ``normal-force``: every g; ``sliding+normal-force``: g along a ladder
    of complex chi, and chi at g = 0 (the sliding row's points)."""
    k0, u_chi, u_g = _unit_terms(row, "normal")
    chis = [0.0]
    if "chi_im" in row.free:
        ladder = _grid(row.bounds["chi_re"][1], 3)
        chis += [complex(x, y) for x in ladder for y in ladder]
    points = [
        {"chi_re": chi.real, "chi_im": chi.imag, "normal_re": g.real, "normal_im": g.imag}
        for chi in map(complex, chis)
        for g in _solve(k0 + chi * u_chi, u_g)
    ]
    if "chi_im" in row.free:
        points += [
            {"chi_re": chi.real, "chi_im": chi.imag, "normal_re": 0.0, "normal_im": 0.0}
            for chi in _solve(k0, u_chi)
        ]
    out = np.array([[p[f] for f in row.free] for p in points]).reshape(-1, len(row.free))
    return _inside(row, out)
