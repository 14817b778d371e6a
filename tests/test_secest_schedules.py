"""Unit tests of secest.core.schedules (RRL-MAP of li2025, eqs. (2)-(5), Remark 1)."""

from __future__ import annotations

from math import lcm

import numpy as np
import pytest

from secest.core.schedules import (
    rrl_map_period,
    rrl_map_phase,
    rrl_map_selector,
    rrl_map_sets,
    rrl_map_window_counts,
    zero_input_update,
)
from secest.core.validation import ValidationError


def paper_sets(k: int, m: int, n_y: int) -> set[int]:
    """Eq. (2) literally, with the paper's 1-based labels."""
    return {(m * (k - 1) + s) % n_y + 1 for s in range(m)}


def test_example_schedule_li2025() -> None:
    """n_y = 4, m = 2 (Section IV): U = 2, {1,2} at odd k, {3,4} at even k."""
    assert rrl_map_period(2, 4) == 2
    sets = rrl_map_sets(np.arange(1, 7), 2, 4)
    assert sets.tolist() == [[0, 1], [2, 3]] * 3
    assert rrl_map_phase(np.arange(1, 6), 2, 4).tolist() == [1, 2, 1, 2, 1]
    assert rrl_map_sets(1, 2, 4).tolist() == [0, 1]


@pytest.mark.parametrize(
    ("m", "n_y"), [(1, 1), (1, 3), (2, 3), (2, 4), (3, 4), (4, 6), (3, 7), (5, 5)]
)
def test_sets_match_eq2_and_fairness(m: int, n_y: int) -> None:
    U = rrl_map_period(m, n_y)
    assert U == lcm(m, n_y) // m
    k = np.arange(1, 5 * U + 3)
    sets = rrl_map_sets(k, m, n_y)
    assert sets.shape == (k.size, m)
    for kk, row in zip(k, sets, strict=True):
        assert {int(r) + 1 for r in row} == paper_sets(int(kk), m, n_y)
        assert len(set(row.tolist())) == m  # |eps(k)| = m, no sensor on two channels
    # periodic with period U
    np.testing.assert_array_equal(sets[U:], sets[:-U])
    # every sliding window of U steps serves each sensor lcm(m, n_y)/n_y times
    counts = rrl_map_window_counts(sets, n_y)
    assert counts.shape == (k.size - U + 1, n_y)
    assert np.all(counts == lcm(m, n_y) // n_y)
    # the phase o(k) indexes the period
    o = rrl_map_phase(k, m, n_y)
    assert o.min() == 1 and o.max() == U
    for kk in range(1, U + 1):
        same = k[o == kk]
        assert np.all(rrl_map_sets(same, m, n_y) == rrl_map_sets(kk, m, n_y))


def test_selector_and_zero_input() -> None:
    Phi = rrl_map_selector(2, 2, 4)
    np.testing.assert_array_equal(Phi, np.diag([0.0, 0.0, 1.0, 1.0]))
    stack = rrl_map_selector(np.arange(1, 5), 3, 4)
    assert stack.shape == (4, 4, 4)
    assert np.all(np.trace(stack, axis1=1, axis2=2) == 3)
    np.testing.assert_array_equal(stack[1], np.diag([1.0, 1.0, 0.0, 1.0]))
    y = np.arange(1.0, 9.0).reshape(2, 4)
    np.testing.assert_array_equal(zero_input_update(y, 1, 2, 4), [[1, 2, 0, 0], [5, 6, 0, 0]])
    np.testing.assert_array_equal(zero_input_update(y[0], 2, 2, 4), y[0] @ Phi)


def test_window_counts_detects_unfair_schedule() -> None:
    unfair = np.array([[0, 1], [0, 1], [2, 3], [0, 1]])
    counts = rrl_map_window_counts(unfair, 4)
    assert counts.tolist() == [[2, 2, 0, 0], [1, 1, 1, 1], [1, 1, 1, 1]]
    assert rrl_map_window_counts(unfair, 4, window=4).tolist() == [[3, 3, 1, 1]]


@pytest.mark.parametrize(
    ("m", "n_y", "message"),
    [
        (3, 2, "m must not exceed n_y"),
        (0, 4, "m must be >= 1"),
        (2, 0, "n_y must be >= 1"),
        (2.0, 4, "m must be an integer"),
        (2, 4.5, "n_y must be an integer"),
        (True, 4, "m must be an integer"),
    ],
)
def test_bad_channels_rejected(m: object, n_y: object, message: str) -> None:
    for fn in (
        lambda: rrl_map_period(m, n_y),
        lambda: rrl_map_sets(1, m, n_y),
        lambda: rrl_map_phase(1, m, n_y),
        lambda: rrl_map_selector(1, m, n_y),
    ):
        with pytest.raises(ValidationError, match=message):
            fn()


def test_bad_steps_rejected() -> None:
    with pytest.raises(ValidationError, match="k must be >= 1"):
        rrl_map_sets(0, 2, 4)
    with pytest.raises(ValidationError, match="k must be an integer"):
        rrl_map_sets(1.5, 2, 4)
    with pytest.raises(ValidationError, match="k must be a single time instant"):
        zero_input_update(np.ones(4), np.array([1, 2]), 2, 4)
    msg = r"Incompatible dimensions of y: expected \(\.\.\., 4\)"
    with pytest.raises(ValidationError, match=msg):
        zero_input_update(np.ones(3), 1, 2, 4)


def test_bad_window_input_rejected() -> None:
    good = rrl_map_sets(np.arange(1, 5), 2, 4)
    with pytest.raises(ValidationError, match="sets must be a 2-D integer array"):
        rrl_map_window_counts(good.astype(float), 4)
    with pytest.raises(ValidationError, match="sets must hold sensor indices in 0..3"):
        rrl_map_window_counts(good + 1, 4)
    with pytest.raises(ValidationError, match="same sensor on two channels"):
        rrl_map_window_counts(np.array([[1, 1], [2, 3]]), 4)
    with pytest.raises(ValidationError, match="window must not exceed the number of steps 4"):
        rrl_map_window_counts(good, 4, window=5)
    msg = r"Incompatible dimensions of sets: expected \(\*, 3\)"
    with pytest.raises(ValidationError, match=msg):
        rrl_map_window_counts(good, 4, m=3)
