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


def test_load_notebook_rejects_unknown_parameters() -> None:
    with pytest.raises(ValueError, match=r"parameters \['no_such_parameter'\] are not declared"):
        harness.load_notebook("guo2023", no_such_parameter=1)


def test_load_notebook_rejects_a_missing_stop_marker() -> None:
    with pytest.raises(ValueError, match="no code cell of notebook guo2023 contains"):
        harness.load_notebook("guo2023", stop_before="this text is in no cell 8c1f")


def test_load_notebook_overrides_parameters_and_stops_at_the_marker() -> None:
    ns = harness.load_notebook("guo2023", stop_before="def example_model", n_steps=250)
    assert ns["n_steps"] == 250 and ns["mode"] == "paper"
    assert callable(ns["example_model"])  # definitions of the stop cell are executed
    assert "model" not in ns  # its other statements are not


def test_notebook_definitions_takes_objects_by_name_and_runs_nothing_else() -> None:
    ns = harness.notebook_definitions("guo2023", "run_estimator", "signal", n_steps=40)
    assert callable(ns["run_estimator"]) and callable(ns["local_update"])  # and what it calls
    assert ns["n_steps"] == 40 and callable(ns["signal"]) and "SIGNAL_NODES" in ns
    assert "model" not in ns and "noise" not in ns  # the notebook's computations are not run
    assert ns["signal"]("d", "2*k", 3).tolist() == [0.0, 2.0, 4.0, 6.0]


def test_notebook_definitions_follows_values_and_in_place_changes() -> None:
    ns = harness.notebook_definitions("guo2023", "d_true", mode="fast", n_steps=10)
    assert ns["d_true"].shape == (11,)
    assert "zero" in ns["signal_sets"]  # signal_sets["zero"] = ... is an in-place change: kept


def test_notebook_definitions_rejects_unknown_names_and_parameters() -> None:
    with pytest.raises(ValueError, match="defines no top-level 'no_such_function_8c1f'"):
        harness.notebook_definitions("guo2023", "no_such_function_8c1f")
    with pytest.raises(ValueError, match=r"parameters \['no_such_parameter'\] are not declared"):
        harness.notebook_definitions("guo2023", "signal", no_such_parameter=1)
