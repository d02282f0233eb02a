"""Dominant-mode rows of the paper table, with their exact elasticities.

For each claim about the dominant eigenmode at one parameter point (figure 7, section
3.6) axojax's value comes with its elasticities ``d ln X / d ln theta`` (percent change of
the row's quantity X per 1 % of theta), taken with ``jax.jacfwd`` through the
differentiable dominant eigenpair (:func:`axojax.eigen.dominant_eigenpair`), for theta =

- ``p``, ``ks``, ``kl``: the dimensionless parameters;
- ``follower``: a factor s on the balanced follower-force term alone,
  ``A(s) = A - (s - 1) P_follow`` (the distributed follower load of ``single``). It is a
  formulation choice rather than a parameter (docs/model.md section 3), so this elasticity
  measures how strongly a row depends on how the dynein force is formulated
  (docs/model.md section 7).

At s = 1 the pencil is exactly the one :func:`axojax.dominant_mode` solves.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Sequence

import jax
import jax.numpy as jnp
import numpy as np

from ..assembly import assemble
from ..eigen import CLASSES, FLUTTER, dominant_eigenpair, dominant_mode, mode_from_eigenpair
from ..models import Model, preset
from ..params import Params
from ..units import Units
from .claims import ELASTICITIES, Claim, Row
from .table import sci

QUANTITIES = ("frequency_hz", "wavelength_um", "velocity_um_per_s", "out_of_plane_ratio")
"""Mode quantities :func:`evaluate` returns, in this order."""


@functools.lru_cache(maxsize=None)
def preset_model(name: str, n_elements: int = 10) -> Model:
    """One shared instance per preset and mesh (compiled functions are cached per model)."""
    return preset(name, n_elements=n_elements)


def without_follower(model: Model) -> Model:
    """``model`` with its follower-force term removed (everything else unchanged).

    Raises:
        ValueError: for Beck's tip load, whose follower part is not separated here.
    """
    if model.section.load == "pairs":
        return dataclasses.replace(model, pair_follow=np.zeros_like(model.pair_follow))
    if model.section.load == "distributed":  # A = K0 - p G0 + p F0: F0 is the follower part
        return dataclasses.replace(
            model, matrices=dataclasses.replace(model.matrices, F0=np.zeros_like(model.matrices.F0))
        )
    raise ValueError(
        f"the follower part of the {model.section.load!r} load of {model.name!r} is not separated"
    )


@dataclasses.dataclass(frozen=True)
class Evaluation:
    """Dominant modes of a batch of points (N of them) and their elasticities.

    Attributes:
        values: quantity -> (N,) values in physical units (:data:`QUANTITIES`).
        elasticity: quantity -> (N, len(ELASTICITIES)) d ln X / d ln theta.
        eigenvalue: (N,) dimensionless dominant eigenvalues (Im >= 0).
        classification: (N,) 0 stable, 1 flutter, 2 divergence.
    """

    values: dict[str, np.ndarray]
    elasticity: dict[str, np.ndarray]
    eigenvalue: np.ndarray
    classification: np.ndarray


@functools.lru_cache(maxsize=None)
def _evaluator(model: Model, units: Units):
    reduced = without_follower(model)

    def log_quantities(logs, params):
        prm = params.replace(p=jnp.exp(logs[0]), ks=jnp.exp(logs[1]), kl=jnp.exp(logs[2]))
        full, rest = assemble(model, prm), assemble(reduced, prm)
        lam, v = dominant_eigenpair(rest.A + jnp.exp(logs[3]) * (full.A - rest.A), full.C)
        mode = mode_from_eigenpair(model, lam, v)
        values = jnp.stack(
            [
                mode.frequency_hz(units),
                mode.wavelength_um(units),
                mode.velocity_um_per_s(units),
                mode.out_of_plane_ratio,
            ]
        )
        return jnp.log(values), (values, lam, mode.classification)

    def one(params, follower):
        logs = jnp.log(jnp.stack([params.p, params.ks, params.kl, follower]))
        return jax.jacfwd(log_quantities, has_aux=True)(logs, params)

    return jax.jit(jax.vmap(one))


def evaluate(
    model: Model,
    points: Sequence[Params],
    follower: Sequence[float] | None = None,
    units: Units = Units(),
) -> Evaluation:
    """Dominant modes and elasticities at ``points`` (one compilation per model and batch
    size); ``follower`` scales the follower-force term at each point (default 1)."""
    for prm in points:
        prm.validate()
    batch = Params(
        **{k: np.array([float(getattr(prm, k)) for prm in points]) for k in Params().as_dict()}
    )
    scale = np.ones(len(points)) if follower is None else np.asarray(follower, dtype=float)
    jac, (values, lam, cls) = _evaluator(model, units)(batch, scale)
    jac, values = np.asarray(jac), np.asarray(values)
    return Evaluation(
        values={q: values[:, k] for k, q in enumerate(QUANTITIES)},
        elasticity={q: jac[:, k, :] for k, q in enumerate(QUANTITIES)},
        eigenvalue=np.asarray(lam),
        classification=np.asarray(cls),
    )


def _fmt(x: float, unit: str, digits: int = 2) -> str:
    return f"{x:.{digits}f} {unit}".strip()


def _mode_text(lam: complex, cls: int) -> str:
    return f"{CLASSES[cls]} (Re lambda = {lam.real:.1f})" if cls != FLUTTER else ""


def mode_rows(claims: Sequence[Claim], scan=None, units: Units = Units()) -> list[Row]:
    """Rows for the ``kind == "mode"`` claims.

    Args:
        claims: the claims (others are ignored).
        scan: optional ``scan(p) -> (ks, frequency_hz, flutter)``, axojax's frequency along
            k_s at force p (``k_l = k_s / 1e3``), for the notes of claims whose k_s the
            paper does not state (:func:`axojax.paper.survey.ks_scan`).
    """
    claims = [c for c in claims if c.kind == "mode"]
    by_model: dict[str, list[tuple[Params, float, Claim | str]]] = {}
    for c in claims:
        by_model.setdefault(c.model, []).append((Params(**c.params), 1.0, c))
        if c.key == "7b":  # the follower load +-2 % (docs/model.md section 7)
            by_model[c.model] += [(Params(**c.params), s, f"7b@{s}") for s in (0.98, 1.02)]
    results: dict[str, tuple[Evaluation, int]] = {}
    for name, entries in by_model.items():
        ev = evaluate(preset_model(name), [e[0] for e in entries], [e[1] for e in entries], units)
        for k, (_, _, tag) in enumerate(entries):
            results[tag.key if isinstance(tag, Claim) else tag] = (ev, k)

    def get(key: str, quantity: str = "frequency_hz"):
        ev, k = results[key]
        return (
            ev.values[quantity][k],
            ev.elasticity[quantity][k],
            complex(ev.eigenvalue[k]),
            int(ev.classification[k]),
        )

    rows = []
    for c in claims:
        value, elast, lam, cls = get(c.key, c.quantity)
        oscillating = cls == FLUTTER
        if c.quantity == "out_of_plane_ratio":
            shown = f"{value:.3f}"
        else:
            shown = _fmt(value, c.unit) if oscillating else _mode_text(lam, cls)
        row = Row(
            c,
            float(value) if oscillating else None,
            shown,
            dict(zip(ELASTICITIES, map(float, elast))) if oscillating else None,
        )
        rows.append(dataclasses.replace(row, note=_note(row, lam, get, scan, units)))
    return rows


def _note(row: Row, lam: complex, get, scan, units: Units) -> str:
    c = row.claim
    parts = []
    if c.key == "7b":
        low, high = (get(f"7b@{s}")[0] for s in (0.98, 1.02))
        coarse = float(
            dominant_mode(preset_model("two", 6), Params(**c.params)).frequency_hz(units)
        )
        parts.append(
            f"ill-conditioned: Re lambda is {lam.real / lam.imag:.0f}x Im lambda, just past the merger of two real "
            f"eigenvalues; +-2 % of the follower load moves it over {low:.0f}-{high:.0f} Hz and N_e = 6 gives "
            f"{coarse:.0f} Hz, so this row cannot discriminate formulations"
        )
    elif c.key == "7c":
        two = get("7b")[2]
        gap = abs(lam - two) / abs(two)
        same = "equal to 1e-9" if gap < 1e-9 else f"{gap:.0e} apart"
        parts.append(
            "the paper's four differs from its two; here the two pairs moving in step is an exact mode of the "
            f"square, so four = two (eigenvalues {same})"
        )
    if c.unstated:
        parts.append(
            f"{c.unstated}; shown at the stated defaults k_s = {sci(c.params['ks'])}, k_l = {sci(c.params['kl'])}"
        )
        if scan is not None:
            parts.append(_scan_text(c, scan))
    if not parts:
        parts.append("agrees" if not row.differs else "")
    return "; ".join(p for p in parts if p)


def _scan_text(c: Claim, scan) -> str:
    """Where along k_s (k_l = k_s / 1e3) axojax's frequency at the claim's p meets the paper's."""
    ks, f, flutter = scan(c.params["p"])
    if not np.any(flutter):
        return f"stable for every k_s = {sci(ks[0])}..{sci(ks[-1])} at this p"
    text = (
        f"over the map's k_s = {sci(ks[0])}..{sci(ks[-1])} (k_l = k_s/1e3) axojax gives "
        f"{np.min(f[flutter]):.0f}-{np.max(f[flutter]):.0f} Hz at this p"
    )
    cross = [
        k
        for k in range(len(ks) - 1)
        if flutter[k] and flutter[k + 1] and (f[k] - c.paper) * (f[k + 1] - c.paper) < 0
    ]
    if not cross:
        return text + f", never {c.paper:g} Hz"
    spans = ", ".join(f"{sci(ks[k])} and {sci(ks[k + 1])}" for k in cross)
    return text + f", {c.paper:g} Hz between k_s = {spans}"
