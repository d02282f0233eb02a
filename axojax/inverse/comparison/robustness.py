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
    share}, "best", "best_share"}``; ``best`` is the first successful row of ``rows``."""
    ok = [r for r in rows if r.get("status", "successful") == "successful" and r["psi1_model"]]
    if psi1_cycles is None or len(psi1_cycles) < MIN_CYCLES or not ok:
        return None
    cycles = np.asarray(psi1_cycles, dtype=complex)
    n = len(cycles)
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, n, size=(int(resamples), n))
    psi = cycles[picks].mean(axis=1)  # (B, S)
    n_res = 2 * cycles.shape[1] + 2
    bic = np.stack(
        [
            shape_chi2(psi, np.asarray(r["psi1_model"], float) @ [1, 1j], sigma)
            + pins_chi2(r, frequency_hz, tolerance)
            + r["n_free"] * math.log(n_res)
            for r in ok
        ]
    )  # (rows, B)
    first = np.bincount(np.argmin(bic, axis=0), minlength=len(ok)) / bic.shape[1]
    names = [f"{r['mechanism']}/{r['base']}" for r in ok]
    return {
        "method": "bootstrap over the recording's cycles, each row's shape held and its "
        "amplitude refitted",
        "cycles": n,
        "resamples": int(resamples),
        "shares": dict(zip(names, (float(x) for x in first))),
        "best": names[0],
        "best_share": float(first[0]),
    }
