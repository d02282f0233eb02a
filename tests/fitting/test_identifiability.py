"""One verdict per fitted value (issue 33): the rule of :mod:`axojax.inverse.fitting.identifiability` on
covariances built here by hand (their standard errors, correlations and best-determined
combinations are known in closed form), and the fit message's words: never "determined"
and "only a combination is determined" for the same value, "unbounded" instead of a
factor like 1e+304."""

import math
import re
import types

import numpy as np
import pytest

from axojax.inverse.fitting.identifiability import strong_pairs, uncertainty, verdicts
from axojax.inverse.fitting.report import _notes

SPAN = np.array([20.0, 20.0])  # log bounds spanning a factor e^20
LOG = np.array([True, True])


def rotated(sd_long: float, sd_short: float) -> np.ndarray:
    """Covariance with principal standard errors sd_long, sd_short along (1, 1) / sqrt 2
    and (1, -1) / sqrt 2: se of each value sqrt((sd_long^2 + sd_short^2) / 2)."""
    r = np.array([[1.0, 1.0], [1.0, -1.0]]) / math.sqrt(2)
    return r @ np.diag([sd_long**2, sd_short**2]) @ r.T


def problem(names=("p", "ks")):
    params = [types.SimpleNamespace(log=True, lower=0.0, upper=20.0) for _ in names]
    return types.SimpleNamespace(names=tuple(names), parameters=params)


def message(cov, names=("p", "ks"), at_bound=()):
    verdict, combos = verdicts(names, cov, LOG, SPAN, at_bound)
    se = np.sqrt(np.diag(cov))
    values = {n: 10.0 for n in names}
    return verdict, "; ".join(
        _notes(problem(names), np.array([5.0, 6.0]), values, se, cov, verdict, combos)
    )


def test_correlated_but_each_determined_is_said_as_determined():
    cov = rotated(0.2, 0.01)  # se 0.14 each (< 1: a factor 1.15), correlation ~ +0.995
    verdict, text = message(cov)
    assert verdict == {"p": "determined", "ks": "determined"}
    assert "determined: p" in text and "only a combination" not in text
    assert re.search(r"strongly correlated: p-ks \+0\.99", text)


def test_a_tight_combination_of_two_loose_values():
    cov = rotated(5.0, 0.01)  # se 3.5 each (> 1), the combination p - ks known to 0.01
    verdict, text = message(cov)
    assert verdict == {"p": "combination", "ks": "combination"}
    assert "only a combination is determined" in text and "p-ks" in text
    assert "determined: p" not in text and "not identifiable" not in text
    assert "strongly correlated:" not in text  # said once, as the combination


def test_loose_combination_is_undetermined():
    cov = rotated(5.0, 3.0)  # even the best combination is uncertain by e^3
    verdict, _ = message(cov)
    assert verdict == {"p": "undetermined", "ks": "undetermined"}


def test_determined_value_correlated_with_an_undetermined_one():
    # p known to 0.1, ks to 3 (a factor 20), correlation 0.997: p is determined; the
    # pair is not a "combination" (p is known alone)
    c = 0.997 * 0.1 * 3.0
    cov = np.array([[0.01, c], [c, 9.0]])
    verdict, text = message(cov)
    assert verdict == {"p": "determined", "ks": "undetermined"}
    assert "determined: p" in text and "only a combination" not in text
    assert "ks (uncertain by a factor 20.1)" in text


@pytest.mark.parametrize("se", [700.0, 25.0, math.inf])
def test_overflowing_uncertainty_is_said_in_words(se):
    cov = np.diag([0.01, se**2])
    verdict, text = message(cov)
    assert verdict["ks"] == "undetermined"
    assert not re.search(r"e\+\d\d", text), text
    assert ("no information" if math.isinf(se) else "unbounded") in text
    assert uncertainty(2.0, True, 20.0) == f"uncertain by a factor {math.exp(2.0):.3g}"


def test_at_bound_is_its_only_verdict():
    cov = rotated(5.0, 0.01)
    verdict, text = message(cov, at_bound=("p",))
    assert verdict == {"p": "at_bound", "ks": "undetermined"}
    assert "lower bound" in text and "only a combination" not in text
    assert strong_pairs(("p", "ks"), cov, verdict)  # the correlation is still reported
