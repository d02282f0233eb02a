"""How robust a comparison's ranking is, from the data itself (issue 45, item 4).

A recording of whole cycles gives one psi_1 estimate per cycle (:attr:`BeatData.psi1_cycles`;
their mean is the psi_1 every row was fitted to). :func:`cycle_bootstrap` resamples the
cycles with replacement, and for each resample re-scores every successful row on the
resampled mean: its fitted shape held, its complex amplitude refitted (weighted least
squares, closed form), its pins' chi^2 as fitted, its BIC with its own n_free. The best
row's **share** is how often it stays first. The shapes are not refitted per resample
(the "RELL" bootstrap of phylogenetics: resampling the data under each hypothesis's
optimum), so the shares are an upper bound on a full refit's stability: a share well
below 1 says the ranking rests on a few cycles.

Units: psi_1 and sigmas in rad; chi^2 and BIC are numbers.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from jaxtyping import Complex, Float

RESAMPLES = 1000
"""Bootstrap resamples of the cycles."""
MIN_CYCLES = 4
"""Fewer whole cycles than this give no bootstrap (too few to resample)."""


def shape_chi2(
    psi: Complex[np.ndarray, "B S"],
    model: Complex[np.ndarray, " S"],
    sigma: Float[np.ndarray, " S"],
) -> Float[np.ndarray, " B"]:
    """min over complex a of sum_s |psi_s - a model_s|^2 / sigma_s^2 for each row of ``psi``
    (the real and imaginary parts each with ``sigma``): the shape's chi^2 with its
    amplitude refitted."""
    w = 1.0 / np.asarray(sigma, dtype=float) ** 2
    mm = float(np.sum(w * np.abs(model) ** 2))
    cross = (psi * (w * np.conj(model))[None, :]).sum(axis=1)
    total = (w[None, :] * np.abs(psi) ** 2).sum(axis=1)
    return total - (np.abs(cross) ** 2 / mm if mm > 0 else 0.0)


def phase_chi2(
    psi: Complex[np.ndarray, "B S"],
    model: Complex[np.ndarray, " S"],
    sigma: Float[np.ndarray, " S"],
) -> Float[np.ndarray, " B"]:
    """min over a unit phase e^{i phi} of sum_s |psi_s - e^{i phi} model_s|^2 / sigma_s^2
    for each row of ``psi``: the chi^2 of a limit cycle's psi_1, whose amplitude is the
    orbit's own and whose time origin is arbitrary."""
    w = 1.0 / np.asarray(sigma, dtype=float) ** 2
    mm = float(np.sum(w * np.abs(model) ** 2))
    cross = (psi * (w * np.conj(model))[None, :]).sum(axis=1)
    total = (w[None, :] * np.abs(psi) ** 2).sum(axis=1)
    return total + mm - 2.0 * np.abs(cross)


IDENTICAL = 1e-9
"""Cycles whose psi_1 differ by at most this share of max |psi_1| are copies of one."""


def identical_cycles(psi1_cycles: Complex[np.ndarray, "n S"]) -> bool:
    """Whether a recording's cycles are copies of one cycle (:data:`IDENTICAL`): resampling
    them says nothing about the ranking's stability."""
    c = np.asarray(psi1_cycles, dtype=complex)
    scale = float(np.max(np.abs(c))) if c.size else 0.0
    return bool(np.max(np.abs(c - c.mean(axis=0)), initial=0.0) <= IDENTICAL * max(scale, 1e-300))


def pins_chi2(row: dict[str, Any], frequency_hz: float, tolerance: float) -> float:
    """The pins' chi^2 of a fitted row (frequency f +- tol f, growth 0 +- tol 2 pi f)."""
    f, g = row["frequency_hz"], row["growth_rate_per_s"]
    return ((f - frequency_hz) / (tolerance * frequency_hz)) ** 2 + (
        g / (tolerance * 2 * math.pi * frequency_hz)
    ) ** 2


def cycle_bootstrap(
    rows: list[dict[str, Any]],
    psi1_cycles: Complex[np.ndarray, "n S"] | None,
    sigma: Float[np.ndarray, " S"],
    frequency_hz: float,
    tolerance: float,
    *,
    resamples: int = RESAMPLES,
    seed: int = 0,
) -> dict[str, Any] | None:
    """Each successful row's share of first places over ``resamples`` bootstrap resamples of
    the cycles (module docstring), or None without enough cycles (:data:`MIN_CYCLES`) or
    rows. ``rows``: the comparison document's rows (their ``psi1_model`` as [re, im]
    pairs); ``sigma``: the fit's per-point sigma (the data's with the shape floor in
    quadrature). Returns ``{"method", "cycles", "resamples", "shares": {"mechanism/base":
    share}, "best", "best_share", "identical"}``; ``best`` is the first successful row of
    ``rows``; ``identical``: the cycles are copies of one (:func:`identical_cycles`), and
    then nothing is resampled (``resamples`` 0, no shares)."""
    n_res = 2 * np.shape(psi1_cycles)[-1] + 2 if psi1_cycles is not None else 0
    return _bootstrap(
        rows,
        psi1_cycles,
        lambda psi, r: (
            shape_chi2(psi, np.asarray(r["psi1_model"], float) @ [1, 1j], sigma)
            + pins_chi2(r, frequency_hz, tolerance)
            + r["n_free"] * math.log(n_res)
        ),
        "bootstrap over the recording's cycles, each row's shape held and its amplitude refitted",
        resamples,
        seed,
    )


def whole_beat_bootstrap(
    rows: list[dict[str, Any]],
    psi1_cycles: Complex[np.ndarray, "n S"] | None,
    sigma: Float[np.ndarray, " S"],
    n_residuals: int,
    *,
    resamples: int = RESAMPLES,
    seed: int = 0,
) -> dict[str, Any] | None:
    """:func:`cycle_bootstrap` for a whole-beat comparison: each successful row's orbit
    held (psi_1 with its own amplitude, only its time origin refitted: :func:`phase_chi2`),
    its psi_0 and frequency residuals as fitted (the row's ``chi2_rest``), its BIC with
    its own ``n_free`` over ``n_residuals``. ``sigma``: psi_1's per-point sigma as the
    fit divided by it."""
    return _bootstrap(
        rows,
        psi1_cycles,
        lambda psi, r: (
            phase_chi2(psi, np.asarray(r["psi1_model"], float) @ [1, 1j], sigma)
            + r["chi2_rest"]
            + r["n_free"] * math.log(n_residuals)
        ),
        "bootstrap over the recording's cycles, each row's orbit held (psi_1's time origin "
        "refitted, psi_0 and the frequency as fitted)",
        resamples,
        seed,
    )


def _bootstrap(rows, psi1_cycles, bic_of, method: str, resamples: int, seed: int):
    """Shares of first places by ``bic_of(psi (B, S), row) -> (B,)`` over resamples."""
    ok = [r for r in rows if r.get("status", "successful") == "successful" and r.get("psi1_model")]
    if psi1_cycles is None or len(psi1_cycles) < MIN_CYCLES or not ok:
        return None
    cycles = np.asarray(psi1_cycles, dtype=complex)
    n = len(cycles)
    names = [f"{r['mechanism']}/{r['base']}" for r in ok]
    if identical_cycles(cycles):
        return {
            "method": method,
            "cycles": n,
            "resamples": 0,
            "shares": {},
            "best": names[0],
            "best_share": None,
            "identical": True,
        }
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, n, size=(int(resamples), n))
    psi = cycles[picks].mean(axis=1)  # (B, S)
    bic = np.stack([bic_of(psi, r) for r in ok])  # (rows, B)
    first = np.bincount(np.argmin(bic, axis=0), minlength=len(ok)) / bic.shape[1]
    return {
        "method": method,
        "cycles": n,
        "resamples": int(resamples),
        "shares": dict(zip(names, (float(x) for x in first))),
        "best": names[0],
        "best_share": float(first[0]),
        "identical": False,
    }
