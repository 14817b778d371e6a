"""The tuning engine (issue #28): the registered grids, the rule, the seeds it may see, one tiny run.

Nothing here runs a test seed, and nothing runs the real tuning: the one end-to-end run is two
grid points of ding2020 on one validation seed, 2 runs of 12 steps (``short``).
"""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from secest.arena import baselines, estimators, protocol, scenarios, testseeds, tuning
from secest.arena.estimators import METHODS
from secest.core.validation import ValidationError

SIZES = {"ding2020": 25, "guo2023": 4, "lee2020": 32, "li2025": 27, "ma2021": 4, "kf": 1,
         "chi2-kf": 4, "local-kf": 1, "consensus-kf-1": 1, "consensus-kf": 3, "diffusion-kf": 1,
         "kcf": 4, "wmsr-kf": 2}
TINY = {"seeds": [101], "runs": 2, "horizon": 12, "short": True}


# ---------------------------------------------------------------------------------- the grid


def test_every_method_but_the_oracle_has_a_grid_of_the_registered_size() -> None:
    search = protocol.load()["search"]
    assert set(search) == set(SIZES) == set(tuning.ARGUMENTS) == set(METHODS) - {"oracle"}
    assert {m: len(tuning.grid(m, 1)) for m in SIZES} == SIZES
    assert sum(SIZES.values()) == 109


@pytest.mark.parametrize("name", sorted(SIZES))
def test_the_printed_point_comes_first_and_no_point_twice(name: str) -> None:
    lists = protocol.load()["search"][name]
    points = tuning.grid(name, 2)
    assert [p["point"] for p in points] == list(range(len(points)))
    assert [p["printed"] for p in points] == [True] + [False] * (len(points) - 1)
    skip = "false_alarm" if name == "ding2020" else None
    assert points[0]["constants"] == {k: v[0] for k, v in lists.items() if k != skip}
    args = [json.dumps(p["arguments"], sort_keys=True) for p in points]
    assert len(set(args)) == len(args)
    for p in points:  # every point builds the method
        assert isinstance(type(METHODS[name])(**p["arguments"]), estimators.Method)


def test_ding2020_prints_threshold_25_and_tunes_kappa_by_false_alarm() -> None:
    lists = protocol.load()["search"]["ding2020"]
    for ny in (1, 2):
        points = tuning.grid("ding2020", ny)
        assert points[0]["arguments"] == {"kappa": 0.004, "threshold": 25.0}
        assert points[0]["threshold"] == 25.0
        tuned = [(p["constants"]["kappa"], p["constants"]["false_alarm"]) for p in points[1:]]
        assert tuned == [(k, f) for k in lists["kappa"] for f in lists["false_alarm"]]
        for p in points[1:]:
            want = stats.chi2.ppf(1 - p["constants"]["false_alarm"], ny)
            assert p["arguments"]["threshold"] == pytest.approx(want, rel=1e-12)
            assert p["threshold"] == p["arguments"]["threshold"]
    assert tuning.grid("ding2020", 1)[1]["threshold"] == pytest.approx(10.8276, abs=1e-4)


def test_a_level_argument_gets_the_level_and_li2025_its_weights() -> None:
    chi2 = tuning.grid("chi2-kf", 3)
    assert [p["arguments"] for p in chi2] == [{"false_alarm": f} for f in (1e-3, 1e-2, 1e-4, 1e-6)]
    assert chi2[3]["threshold"] == pytest.approx(stats.chi2.ppf(1 - 1e-6, 3))
    li = tuning.grid("li2025", 1)
    assert li[0]["arguments"]["weights"] == (1e-3, 1.0, 1e-2, 0.1, 0.1)
    assert all(p["arguments"]["weights"][3] == p["arguments"]["weights"][4] == p["constants"]["alpha_3_4"]
               for p in li)


def test_the_table_maps_every_key_onto_a_constructor_argument() -> None:
    """No key dropped: every search key has an argument, every argument a key or a FIXED entry."""
    search = protocol.load()["search"]
    for name, keys in tuning.ARGUMENTS.items():
        assert set(keys) == set(search[name]), name
        init = set(inspect.signature(type(METHODS[name])).parameters)
        mapped = {a.split("[")[0] for a in keys.values()}
        assert mapped | set(tuning.FIXED.get(name, ())) == init, name


# ---------------------------------------------------------------------------------- the rule


def rec(point: int, score: float | None, status: str = "ok", fa: float | None = None) -> dict:
    """A synthetic record: ``fa`` is the false-alarm upper bound (None: no detector)."""
    return {"point": point, "printed": point == 0, "status": status, "reason": "",
            "score": score if status == "ok" else None,
            "false_alarm": None if fa is None else [fa / 2, 0.0, fa],
            "constants": {"c": point}, "arguments": {"c": point}}


def test_the_lowest_score_wins_and_diverged_points_are_excluded() -> None:
    c = tuning.choose([rec(0, 2.0), rec(1, 0.5, "diverged"), rec(2, 1.2), rec(3, 1.1)])
    assert (c["point"], c["rule"], c["mark"]) == (3, "lowest score", "")
    assert c["admissible"] == [0, 2, 3]
    assert c["excluded"][0]["point"] == 1 and c["excluded"][0]["why"].startswith("diverged")


def test_a_false_alarm_bound_above_the_cap_excludes_a_point() -> None:
    cap = protocol.load()["detection"]["false_alarm_cap"]
    c = tuning.choose([rec(0, 2.0, fa=0.001), rec(1, 1.0, fa=cap * 1.5), rec(2, 1.5, fa=cap)])
    assert c["point"] == 2
    assert "false-alarm upper bound" in c["excluded"][0]["why"]
    assert tuning.choose([rec(0, 2.0, fa=0.001), rec(1, 1.0, fa=0.02)], cap=0.05)["point"] == 1


def test_ties_within_one_percent_go_to_the_printed_point_then_the_first_listed() -> None:
    c = tuning.choose([rec(0, 1.0099), rec(1, 1.0), rec(2, 1.005)])
    assert (c["point"], c["printed"]) == (0, True) and "printed" in c["rule"]
    c = tuning.choose([rec(0, 1.011), rec(1, 1.0)])
    assert c["point"] == 1  # 1.1 % is not a tie
    c = tuning.choose([rec(0, 2.0), rec(1, 1.004), rec(2, 1.0), rec(3, 1.5)])
    assert c["point"] == 1 and "listed first" in c["rule"]
    c = tuning.choose([rec(0, 1.0, "error"), rec(1, 1.004), rec(2, 1.0)])
    assert c["point"] == 1  # a printed point that did not run is not tied


def test_with_no_admissible_point_the_lowest_false_alarm_bound_is_marked() -> None:
    c = tuning.choose([rec(0, 1.0, fa=0.05), rec(1, 0.8, "diverged", fa=0.03),
                       rec(2, 0.9, fa=0.02), rec(3, None, "n/a")])
    assert (c["point"], c["mark"], c["admissible"]) == (2, tuning.NO_ADMISSIBLE, [])
    assert c["rule"] == "lowest false-alarm upper bound"
    c = tuning.choose([rec(0, 1.0, "diverged"), rec(1, None, "n/a"), rec(2, None, "error")])
    assert (c["point"], c["mark"]) == (0, tuning.NO_ADMISSIBLE) and "printed" in c["rule"]


def test_with_no_admissible_point_a_diverged_point_is_chosen_only_if_all_diverged() -> None:
    """Amendment 2 (c): the first rule chose ding2020's diverged point 12 on inertia5."""
    c = tuning.choose([rec(0, 1.0, fa=0.05), rec(1, 0.8, "diverged", fa=0.001), rec(2, 0.9, fa=0.02)])
    assert (c["point"], c["rule"]) == (2, "lowest false-alarm upper bound")
    c = tuning.choose([rec(0, 1.0, "diverged", fa=0.05), rec(1, 0.8, "diverged", fa=0.001)])
    assert c["point"] == 1 and "every point with a false-alarm rate diverged" in c["rule"]


def test_when_every_point_diverged_a_tie_goes_to_the_least_growth() -> None:
    """Amendments 3 (d) and 4 (d): lee2020 on target20, ten points that never alarm, went to the
    first listed; the tie reads the most growing node's factor (``growth_largest``), not the factor
    of the node whose lower bound decided (``growth``)."""
    def diverged(point: int, fa: float, decisive: float | None, largest: float | None) -> dict:
        return rec(point, None, "diverged", fa=fa) | {"growth": decisive, "growth_largest": largest}

    tied = [diverged(0, 0.01, 1.5, 1.5), diverged(1, 0.0, 11.0, 11.0), diverged(2, 0.0, None, None),
            diverged(3, 0.0, 1.2, 2.6), diverged(4, 0.0, 2.0, 2.6), diverged(5, 0.0, 1.1, 3.0)]
    c = tuning.choose(tied)
    assert c["point"] == 3 and "the least growth" in c["rule"]  # a non-finite growth counts as inf


@pytest.mark.parametrize("records, words", [
    ([], "records must be a non-empty list"),
    ({"point": 0}, "records must be a non-empty list"),
    ([{"point": 0}], "records must be a non-empty list"),
    ([rec(1, 1.0), rec(2, 1.0)], "exactly one printed point"),
])
def test_bad_records_are_refused(records: object, words: str) -> None:
    with pytest.raises(ValidationError, match=words):
        tuning.choose(records)


def test_the_pooled_rate_is_the_rate_of_the_samples() -> None:
    rng = np.random.default_rng(1)
    alarms = rng.random((6, 30, 4)) < 0.05
    where = np.ones_like(alarms)
    hits = alarms.reshape(6, -1).sum(axis=1)
    assert estimators.rate_of_counts(hits, np.full(6, 120)) == estimators.rate(alarms, where)
    with pytest.raises(ValidationError, match="Incompatible dimensions of hits and total"):
        estimators.rate_of_counts(hits, np.full(5, 120))


# ---------------------------------------------------------------------------------- refused input


def test_test_seeds_are_refused() -> None:
    seeds = protocol.load()["seeds"]
    test = seeds["test"] + seeds["retired_test"]
    tuning.refuse_test_seeds(seeds["validation"])
    for seed in test:
        with pytest.raises(ValidationError, match=rf"seeds: \[{seed}\] are test seeds"):
            tuning.refuse_test_seeds([101, seed])
    with pytest.raises(ValidationError, match=r"seeds: \[301, 308\] are test seeds"):
        tuning.validate("kf", "target20", **(TINY | {"seeds": [301, 101, 308]}))
    with pytest.raises(ValidationError, match="are test seeds"):
        tuning.tune(["kf"], ["target20"], **(TINY | {"seeds": [304]}))


@pytest.mark.parametrize("kwargs, words", [
    ({"seeds": (101,)}, "seeds must be a non-empty list of integers"),
    ({"seeds": 101}, "seeds must be a non-empty list of integers"),
    ({"seeds": []}, "seeds must be a non-empty list of integers"),
    ({"seeds": ["101"]}, "seeds must be a non-empty list of integers"),
    ({"seeds": [True]}, "seeds must be a non-empty list of integers"),
    ({"seeds": [101, 101]}, "listed twice"),
    ({"seeds": [7]}, r"seeds: \[7\] are not validation seeds"),
    ({"workers": 0}, "workers must be an integer from 1 to 256, found 0"),
    ({"scheduler": "localhost"}, "scheduler must be a Dask scheduler address"),
    ({"runs": 1}, "runs"),
    ({"horizon": 0}, "horizon"),
    ({"short": "yes"}, "short"),
    ({"points": [0.5]}, "points must be a non-empty list of grid indices"),
])
def test_bad_options_are_refused_before_any_work(kwargs: dict, words: str) -> None:
    with pytest.raises(ValidationError, match=words):
        tuning.validate("kf", "target20", **(TINY | kwargs))


@pytest.mark.parametrize("method, plant, words", [
    ("nope", "target20", "method must be a registered method with a .search. set"),
    (3, "target20", "method must be a registered method"),
    ("oracle", "target20", "'oracle' is the reference of every score"),
    ("kf", "target", "plant must be a network card"),
    ("kf", "mars", "plant must be a network card"),
])
def test_unknown_methods_and_plants_are_refused(method: object, plant: object, words: str) -> None:
    with pytest.raises(ValidationError, match=words):
        tuning.validate(method, plant, **TINY)
    if isinstance(method, str):
        with pytest.raises(ValidationError, match=words):
            tuning.tune([method], [plant], **TINY)
    if plant == "target20":
        with pytest.raises(ValidationError, match=words):
            tuning.grid(method, 1)


def test_bad_grid_and_tune_arguments_are_refused() -> None:
    with pytest.raises(ValidationError, match="plant_ny"):
        tuning.grid("ding2020", 0)
    with pytest.raises(ValidationError, match="methods must be a non-empty list"):
        tuning.tune("kf", ["target20"], **TINY)
    with pytest.raises(ValidationError, match="plants must be a non-empty list"):
        tuning.tune(["kf"], [], **TINY)


# ---------------------------------------------------------------------------------- tiny runs


def test_two_points_of_ding2020_on_one_validation_seed() -> None:
    records = tuning.validate("ding2020", "target20", **TINY, points=[0, 1])
    assert [r["point"] for r in records] == [0, 1]
    grid = tuning.grid("ding2020", 1)
    for r, p in zip(records, grid, strict=False):
        assert (r["method"], r["plant"], r["arguments"]) == ("ding2020", "target20", p["arguments"])
        assert r["status"] == "ok" and r["reason"] == ""
        assert r["score"] == r["steady"][0] > 0 and r["steady"][1] <= r["score"] <= r["steady"][2]
        assert r["detector"] and 0 <= r["false_alarm"][0] <= r["false_alarm"][2] <= 1
        assert r["seeds"] == [101]
    choice = tuning.choose(records)
    assert choice["point"] in (0, 1)
    assert json.loads(json.dumps(tuning._jsonable(choice))) == tuning._jsonable(choice)
    assert "ding2020" in METHODS and not [n for n in METHODS if "#" in n or "[" in n]


def test_a_points_seeds_pool_as_the_test_stage_pools_its_seeds() -> None:
    """Amendment 3 (a): one rule in both stages; the tuning's record is the test stage's pooled row
    of the same trials (:func:`testseeds.trial_task`, :func:`testseeds.pool`)."""
    opts = {"seeds": [101, 102], "runs": 3, "horizon": 12, "short": True}
    record = tuning.validate("chi2-kf", "target20", **opts, points=[0])[0]
    job = testseeds.Job("chi2-kf", ("printed",), 0, METHODS["chi2-kf"], {})
    oracle = testseeds.Job("oracle", ("reference",), 0, METHODS["oracle"], {})
    cells = [testseeds.trial_task(scenarios.scenario("target20", "none", horizon=12, runs=3, seed=s),
                                  [oracle, job], True)["cells"] for s in (101, 102)]
    row = testseeds.pool([c[oracle.key] for c in cells], [c[job.key] for c in cells], [101, 102],
                         short=True)
    assert record["score"] == row["steady"][0] and record["worst"] == list(row["worst"])
    assert record["growth"] == row["growth"] and record["false_alarm"] == list(row["false_alarm"])


def test_a_failing_point_is_one_record(monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(self, trial):
        raise RuntimeError("broken on purpose")

    monkeypatch.setattr(baselines.WmsrKF, "run", broken)
    records = tuning.validate("wmsr-kf", "target20", **TINY)
    assert [r["status"] for r in records] == ["error", "error"]
    assert records[0]["reason"] == "seed 101: RuntimeError: broken on purpose"
    c = tuning.choose(records)
    assert (c["point"], c["mark"]) == (0, tuning.NO_ADMISSIBLE)


def test_the_command_line_writes_the_choice_and_every_point(tmp_path: Path) -> None:
    out = tmp_path / "tuned.json"
    argv = ["--methods", "kf,local-kf", "--plants", "tank12", "--seeds", "101", "--runs", "2",
            "--horizon", "8", "--short", "--out", str(out)]
    assert tuning.main(argv) == 0
    data = json.loads(out.read_text())
    assert set(data) == {"protocol", "tuned", "points"}
    assert data["protocol"]["seeds"] == [101] and len(data["protocol"]["sha256"]) == 64
    assert set(data["tuned"]["tank12"]) == {"kf", "local-kf"}
    assert data["tuned"]["tank12"]["kf"]["point"] == 0
    assert len(data["points"]["tank12"]["local-kf"]) == 1
    assert tuning.main(argv[:-1] + [str(tmp_path / "x.json"), "--seeds", "301"]) == 2
    assert not (tmp_path / "x.json").exists()


def test_a_local_cluster_gives_the_records_of_one_process() -> None:
    pytest.importorskip("dask.distributed")
    here = tuning.validate("chi2-kf", "target20", **TINY, points=[0, 3])
    there = tuning.validate("chi2-kf", "target20", **TINY, points=[0, 3], workers=1)
    assert there == here
    assert [r["arguments"]["false_alarm"] for r in there] == [1e-3, 1e-6]
