"""Rows fitted several at a time (axojax/inverse/comparison/schedule.py): every row equals,
to the last bit, the row fitted one at a time, in the same order, and a row waits for the
rows it contains."""

import threading
import time

import numpy as np
import pytest

import axojax as ax
from axojax.inverse.comparison.schedule import default_workers, fit_rows


def test_a_row_starts_after_the_rows_it_contains_and_results_keep_their_order():
    """A row's fit sees its contained rows' results, whichever thread ran them; the
    results come back in the given order, with two workers as with one."""
    combos = [("a", "x"), ("b", "x"), ("a+b", "x"), ("c", "x")]
    inside = {("a+b", "x"): [("a", "x"), ("b", "x")]}
    started = []

    def fit_one(combo, inner):
        started.append((combo, threading.get_ident()))
        time.sleep(0.05 if combo == ("a", "x") else 0.0)  # the contained row finishes last
        return (combo, [r[0] for r in inner])

    def contained(m, b):
        return inside.get((m, b), [])

    one = fit_rows(combos, fit_one, contained, workers=1)
    two = fit_rows(combos, fit_one, contained, workers=2)
    assert list(one) == list(two) == combos
    assert one == two
    assert two[("a+b", "x")] == (("a+b", "x"), [("a", "x"), ("b", "x")])


def test_workers_by_default_follow_the_setting_or_the_cores(monkeypatch):
    monkeypatch.setenv("AXOJAX_COMPARE_WORKERS", "3")
    assert default_workers() == 3
    monkeypatch.delenv("AXOJAX_COMPARE_WORKERS")
    assert 1 <= default_workers() <= 4
    for bad in ("0", "two", "-1", "1.5"):
        monkeypatch.setenv("AXOJAX_COMPARE_WORKERS", bad)
        with pytest.raises(ValueError, match=f"AXOJAX_COMPARE_WORKERS: .*{bad!r}"):
            default_workers()


def test_a_failing_row_fails_the_schedule():
    def fit_one(combo, inner):
        if combo[0] == "b":
            raise ValueError("row b failed")
        return combo

    with pytest.raises(ValueError, match="row b failed"):
        fit_rows([("a", "x"), ("b", "x"), ("c", "x")], fit_one, lambda m, b: [], workers=2)
    with pytest.raises(ValueError, match="workers"):
        fit_rows([("a", "x")], fit_one, lambda m, b: [], workers=0)


@pytest.mark.slow  # two small comparisons (the quick suite within 20 CPU-minutes)
def test_two_rows_at_a_time_give_the_same_comparison():
    """compare(..., workers=2) on the bundled human sperm (steady, sliding, curvature and
    sliding+curvature on a clamped base, 6 elements) equals workers=1 bit for bit."""
    kwargs = dict(
        mechanisms=["steady", "sliding", "curvature", "sliding+curvature"],
        bases=["clamped"],
        n_elements=6,
    )
    one = ax.compare("human_sperm", workers=1, **kwargs)
    two = ax.compare("human_sperm", workers=2, **kwargs)
    assert [(r.mechanism, r.base) for r in one.rows] == [(r.mechanism, r.base) for r in two.rows]
    for a, b in zip(one.rows, two.rows):
        assert a.params == b.params and a.status == b.status
        np.testing.assert_array_equal(a.psi1_model, b.psi1_model)


def test_a_bad_workers_setting_is_one_line_from_the_command(monkeypatch, capsys):
    from axojax.cli.main import main

    monkeypatch.setenv("AXOJAX_COMPARE_WORKERS", "zero")
    argv = ["compare", "--data", "human_sperm", "--mechanisms", "steady", "--bases", "clamped"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err == "axojax: error: AXOJAX_COMPARE_WORKERS: expected an integer >= 1, got 'zero'"
