"""Pinned values (issue 57, item 3): a compare row's pins (growth rate 0 and the observed
frequency, with a small tolerance) hold its beat at the observation; a value they alone
fix has no error from the data, and ``--params`` says "pinned" instead of quoting the
tolerance's error ("chi' -3.26e+03 +- 0.00029 pN/um^2"). The errors of the other values
are the data's with the pins held exactly. References here are computed by hand (or by
plain matrix inversion), not by the code under test."""

import numpy as np
import pytest

from axojax.inverse.comparison.errors import constrained_covariance, pinned_of
from axojax.inverse.comparison.table import physical_text, render_params

TOL = 1e-3  # a pin's sigma: its Jacobian row carries 1 / TOL


def test_two_pins_fix_two_of_three_values():
    """Pins on a and b alone; the data see a + b + c and a - b + 2c. With a and b held,
    only c moves: its variance is 1 / (1^2 + 2^2) = 0.2, and a and b have none (pinned).
    With the pins' tolerance instead, a's variance is about TOL^2 (the tolerance's)."""
    pins = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]) / TOL
    data = np.array([[1.0, 1.0, 1.0], [1.0, -1.0, 2.0]])
    jac = np.vstack([pins, data])
    held, full = constrained_covariance(jac, [0, 1])
    assert held[2, 2] == pytest.approx(0.2, rel=1e-9)
    assert abs(held[0, 0]) < 1e-12 and abs(held[1, 1]) < 1e-12
    reference = np.linalg.inv(jac.T @ jac)  # the Laplace covariance with the tolerance
    np.testing.assert_allclose(np.diag(full), np.diag(reference), rtol=1e-8)
    assert full[0, 0] == pytest.approx(TOL**2, rel=0.01)
    assert pinned_of(held, full, ["a", "b", "c"]) == ["a", "b"]


def test_a_pin_on_a_combination_pins_no_single_value():
    """One pin on a + b, the data on a, b and c separately (unit rows): held exactly,
    a = -b moves along (1, -1) / sqrt(2) with unit precision there, so a and b each have
    variance 1/2 and c has 1; nothing is pinned."""
    jac = np.vstack([np.array([[1.0, 1.0, 0.0]]) / TOL, np.eye(3)])
    held, full = constrained_covariance(jac, [0])
    np.testing.assert_allclose(np.diag(held), [0.5, 0.5, 1.0], rtol=1e-9)
    assert held[0, 1] == pytest.approx(-0.5, rel=1e-9)
    assert pinned_of(held, full, ["a", "b", "c"]) == []


def test_a_value_the_data_do_not_determine_is_not_pinned():
    """c appears in no residual: infinite variance either way (``?``), not pinned."""
    jac = np.vstack([np.array([[1.0, 0.0, 0.0]]) / TOL, [[1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]])
    held, full = constrained_covariance(jac, [0])
    assert np.isinf(held[2, 2]) and np.isinf(full[2, 2])
    assert held[1, 1] == pytest.approx(0.5, rel=1e-9)  # b in both data rows: 1 / (1 + 1)
    assert pinned_of(held, full, ["a", "b", "c"]) == ["a"]


def test_params_table_says_pinned_and_quotes_no_error():
    row = {
        "mechanism": "sliding",
        "base": "clamped",
        "status": "successful",
        "physical": {"chi_re_pn_per_um2": -3260.0, "chi_im_pn_per_um2": -271.0},
        "physical_stderr": {"chi_re_pn_per_um2": None, "chi_im_pn_per_um2": None},
        "pinned": ["chi_re_pn_per_um2", "chi_im_pn_per_um2"],
    }
    text = physical_text(row)
    assert text == "chi' -3.26e+03 pN/um^2 (pinned); chi'' -271 pN/um^2 (pinned)"
    assert "+-" not in text
    table = render_params({"rows": [row]})
    assert "pinned = fixed by the pins" in table
    # a row of an older document (no "pinned") keeps its errors
    old = {**row, "pinned": None, "physical_stderr": {"chi_re_pn_per_um2": 0.00029}}
    assert "chi' -3.26e+03 +- 0.00029 pN/um^2" in physical_text(old)
