"""Unit tests of the benchmark harness (benchmarks/harness.py); fast, no notebook is executed."""

from __future__ import annotations

import pytest
from conftest import bench_harness

harness = bench_harness()


def _same(a, b) -> str:
    if a != b:
        raise AssertionError(f"{a} != {b}")
    return "equal"


def test_compare_reports_ratio_agreement_and_target() -> None:
    calls = {"a": 0, "b": 0}

    def a():
        calls["a"] += 1
        return 42

    def b():
        calls["b"] += 1
        return 42

    row = harness.compare("x", ("a", a), ("b", b), _same, repeats=5, per=2.0, unit="item",
                          target=("anything", lambda r: r > 0))
    assert calls == {"a": 6, "b": 6}  # one warm-up + 5 timed calls each
    assert row.agreement == "equal" and row.met is True and row.repeats == 5
    assert row.ratio == pytest.approx(row.alternative_s / row.ours_s)
    assert "x" in harness.format_table([row])


def test_compare_fails_loudly_on_disagreement() -> None:
    with pytest.raises(AssertionError, match="1 != 2"):
        harness.compare("x", ("a", lambda: 1), ("b", lambda: 2), _same, repeats=5)


def test_missed_target_is_reported_not_raised() -> None:
    row = harness.compare("x", ("a", lambda: 1), ("b", lambda: 1), _same, repeats=5,
                          target=("impossible", lambda r: False))
    assert row.met is False
    assert "NO" in harness.format_table([row])


@pytest.mark.parametrize("repeats", [0, 4, 4.5, True])
def test_fewer_than_five_repeats_are_rejected(repeats) -> None:
    with pytest.raises(ValueError, match="repeats must be an integer >= 5"):
        harness.compare("x", ("a", lambda: 1), ("b", lambda: 1), _same, repeats=repeats)
    with pytest.raises(ValueError, match="repeats must be an integer >= 5"):
        harness.measure("x", ("a", lambda: 1), lambda r: "ok", repeats=repeats)


def test_measure_and_not_measured_rows() -> None:
    row = harness.measure("x", ("a", lambda: 3), lambda r: f"got {r}", repeats=5, per=3)
    assert row.agreement == "got 3" and row.ratio is None and row.ours_s >= 0
    skipped = harness.not_measured("y", "notebook missing")
    assert skipped.ours == "not measured" and skipped.agreement == "notebook missing"
    table = harness.format_table([row, skipped])
    assert "not measured" in table and "notebook missing" in table
