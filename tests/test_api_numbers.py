"""Numbers from numpy and None where a number is required: accepted as numbers, or refused in one line naming the
argument -- never a numba TypingError, an OverflowError or a bare conversion error from deep inside."""

from __future__ import annotations

import numpy as np
import pytest

import frictionflow as ff

MODEL, LAW = ff.BeltOscillator(zeta=0.05, vb=0.01), ff.Stribeck(fd=0.02, fs=0.04)


@pytest.fixture(scope="module")
def run():
    return ff.simulate(MODEL, LAW, t_end=100.0)


@pytest.mark.parametrize("value", [3.0, np.float64(3), np.int64(3), np.array(3.0)])
def test_a_whole_min_periods_of_any_numeric_type_is_the_integer(run, value):
    """min_periods=3.0 went to the compiled classifier as a float: a numba TypingError."""
    assert ff.steady_state(run, min_periods=value) == ff.steady_state(run, min_periods=3)
    assert ff.analyze(run, min_periods=value).quantities()["period"] == ff.analyze(run).quantities()["period"]


@pytest.mark.parametrize("value", [None, float("nan"), float("inf"), [3], "3", True, 2.5, 0])
def test_a_min_periods_that_is_no_positive_integer_is_refused_by_name(run, value):
    with pytest.raises(ValueError, match="min_periods must be an integer >= 1"):
        ff.analyze(run, min_periods=value)


@pytest.mark.parametrize("name", ["t_end", "max_memory"])
def test_none_for_a_required_number_of_simulate_is_refused_by_name(name):
    """t_end=None reached the compiled run (a TypingError); max_memory=None a comparison with None."""
    with pytest.raises(ValueError, match=f"{name} must be finite"):
        ff.simulate(MODEL, LAW, **{name: None})


@pytest.mark.parametrize("value", ["no", 1, None])
def test_progress_must_be_true_or_false(value):
    with pytest.raises(TypeError, match="progress must be True or False"):
        ff.simulate(MODEL, LAW, t_end=10.0, progress=value)
