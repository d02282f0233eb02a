"""How well a fit reproduces an observed beat, in numbers that rank hypotheses.

- ``r2``: Sartori et al.'s (eLife 2016) coefficient of determination of psi_1, the measure
  the anchors of docs/model.md section 8 report::

      R^2 = 1 - sum_s |psi_obs(s) - psi_model(s)|^2 / sum_s |psi_obs(s) - mean_s psi_obs|^2

  over the observed arc lengths, psi_model being the fit (the model's psi_1 times its
  fitted complex amplitude). 1 is a perfect shape; 0 is no better than a constant.
  Unweighted: it does not depend on the sigmas.
- ``aic``, ``bic``: Akaike's and Schwarz's criteria with the stated sigmas (known
  variances), so that the log-likelihood is ``-chi^2 / 2`` up to a constant that is the
  same for every model of the same data::

      AIC = chi^2 + 2 n_free,   BIC = chi^2 + n_free ln(n)

  chi^2 the sum of the squared normalised residuals (every target: shape points, and the
  pins of the beat where there are any), n the number of residuals (real numbers: a
  complex psi_1 point counts 2), n_free the fitted parameters plus 2 per complex
  amplitude of a shape fitted with a free one (its real and imaginary parts). Lower is
  better; differences between models of the same data are what count (a BIC difference
  over 10 is "very strong" evidence, Kass & Raftery 1995).
"""

from __future__ import annotations

import math

import numpy as np
from jaxtyping import Complex


def r2(observed: Complex[np.ndarray, " S"], model: Complex[np.ndarray, " S"]) -> float:
    """Sartori's R^2 of psi_1 (module docstring); NaN where the observation is constant."""
    obs, fit = np.asarray(observed, dtype=complex), np.asarray(model, dtype=complex)
    if obs.shape != fit.shape or obs.size == 0:
        raise ValueError(f"r2: observed {obs.shape} and model {fit.shape} must be equal, non-empty")
    total = float(np.sum(np.abs(obs - obs.mean()) ** 2))
    if not total > 0:
        return math.nan
    return 1.0 - float(np.sum(np.abs(obs - fit) ** 2)) / total


def information_criteria(chi2: float, n_free: int, n: int) -> tuple[float, float]:
    """(AIC, BIC) = (chi^2 + 2 n_free, chi^2 + n_free ln n) (module docstring)."""
    if n < 1:
        return math.nan, math.nan
    return chi2 + 2.0 * n_free, chi2 + n_free * math.log(n)
