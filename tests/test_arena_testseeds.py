"""The arena's test stage (issue #28): order enforced, test seeds only, pooling, rows, isolation.

Nothing here runs the real test stage: a tiny tuning (2 runs of 8 steps on one validation seed,
``short``) is committed in a temporary git repository, and the stage runs on it at 2 runs of 8
steps. The pooling identity runs at the protocol's horizon (target20, 410 steps, 3 runs a seed).
"""

from __future__ import annotations

import json
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import block_diag

from secest.arena import baselines, estimators, protocol, scenarios, testseeds, tuning
from secest.arena.estimators import METHODS, Estimate
from secest.arena.scenarios import Trial
from secest.core.validation import ValidationError

TINY = {"runs": 2, "horizon": 8, "short": True, "seeds": [301, 302], "attacks": ["none", "bias"]}
METHODS_TUNED = ["kf", "chi2-kf", "wmsr-kf"]


def git(repo: Path, *args: str) -> None:
    subprocess.run(["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t", *args],
                   check=True, capture_output=True)


@pytest.fixture(scope="module")
def repo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A git repository holding a committed smoke tuning of three methods on tank12."""
    root = tmp_path_factory.mktemp("repo")
    git(root, "init", "-q")
    out = root / "figures" / "arena" / "tuned.json"
    assert tuning.main(["--methods", ",".join(METHODS_TUNED), "--plants", "tank12", "--seeds",
                        "101", "--runs", "2", "--horizon", "8", "--short", "--out", str(out)]) == 0
    git(root, "add", "figures/arena/tuned.json")
    git(root, "commit", "-q", "-m", "tuned")
    return root


def tuned_file(repo: Path) -> Path:
    return repo / "figures" / "arena" / "tuned.json"


# ---------------------------------------------------------------------------------- the order


def test_an_uncommitted_tuned_file_is_refused(tmp_path: Path) -> None:
    loose = tmp_path / "tuned.json"
    loose.write_text("{}")
    with pytest.raises(ValidationError, match="not in a git work tree"):
        testseeds.run(loose, **TINY)
    git(tmp_path, "init", "-q")
    with pytest.raises(ValidationError, match="tuned.json is not tracked by git"):
        testseeds.run(loose, **TINY)
    with pytest.raises(ValidationError, match="tuned must be an existing file"):
        testseeds.run(tmp_path / "none.json", **TINY)


def test_a_modified_tuned_file_is_refused_staged_or_not(repo: Path) -> None:
    path = tuned_file(repo)
    text = path.read_text()
    try:
        path.write_text(text.replace('"point": 0', '"point": 1', 1))
        with pytest.raises(ValidationError, match="differs from its committed version"):
            testseeds.run(path, **TINY)
        git(repo, "add", "figures/arena/tuned.json")
        with pytest.raises(ValidationError, match="differs from its committed version"):
            testseeds.committed(path)
    finally:
        git(repo, "checkout", "HEAD", "--", "figures/arena/tuned.json")
    record = testseeds.committed(path)
    assert record["file"] == "figures/arena/tuned.json" and len(record["commit"]) == 40
    assert len(record["sha256"]) == 64


def test_a_smoke_tuning_is_refused_outside_a_smoke_test(repo: Path) -> None:
    with pytest.raises(ValidationError, match="is not the protocol's validation"):
        testseeds.load_tuned(tuned_file(repo))
    assert set(testseeds.load_tuned(tuned_file(repo), short=True)["tuned"]) == {"tank12"}


@pytest.mark.parametrize("seeds", [[101], [301, 104], [7]])
def test_seeds_other_than_test_seeds_are_refused(repo: Path, seeds: list[int]) -> None:
    with pytest.raises(ValidationError, match=r"are not test seeds of protocol.toml"):
        testseeds.run(tuned_file(repo), **(TINY | {"seeds": seeds}))


@pytest.mark.parametrize("kwargs, words", [
    ({"seeds": [301, 301]}, "seeds must be a non-empty list of distinct integers"),
    ({"runs": 1}, "runs"),
    ({"horizon": 0}, "horizon"),
    ({"short": False}, "is not the protocol.s validation"),
    ({"plants": ["target20"]}, "plants must be a non-empty list of names from"),
    ({"attacks": ["nope"]}, "attacks must be a non-empty list of names from"),
    ({"workers": 0}, "workers must be an integer from 1 to 256"),
])
def test_bad_options_are_refused_before_any_work(repo: Path, kwargs: dict, words: str) -> None:
    with pytest.raises(ValidationError, match=words):
        testseeds.run(tuned_file(repo), **(TINY | kwargs))


# ---------------------------------------------------------------------------------- pooling


def concatenated(trials: list[Trial]) -> Trial:
    """The runs of several trials of one scenario (other seeds) as one trial."""
    sc = replace(trials[0].scenario, runs=sum(t.scenario.runs for t in trials))
    fields = ("x", "y", "y_clean", "attacked", "link", "hits")
    return Trial(sc, **{f: np.concatenate([getattr(t, f) for t in trials]) for f in fields})


def joined(estimates: list[Estimate]) -> Estimate:
    alarms = None if estimates[0].alarms is None else np.concatenate([e.alarms for e in estimates])
    return Estimate(np.concatenate([e.xhat for e in estimates]), alarms=alarms)


def pooled_and_score(seeds: list[int], estimate, short: bool = False):
    """:func:`testseeds.pool` over ``seeds`` and :func:`estimators.score` on their runs joined."""
    trials, ests, oracles, parts, oparts = [], [], [], [], []
    for s in seeds:
        sc = scenarios.scenario("target20", "bias", horizon="auto", runs=3, seed=s)
        trial = scenarios.simulate(sc)
        oracle = METHODS["oracle"].run(trial)
        est = estimate(trial, oracle)
        settle = estimators.settle_steps(sc)
        trials.append(trial), ests.append(est), oracles.append(oracle)
        parts.append(testseeds.summary(trial, est, settle))
        oparts.append(testseeds.summary(trial, oracle, settle))
    pooled = testseeds.pool(oparts, parts, seeds, short=short)
    whole = estimators.score(concatenated(trials), joined(ests), joined(oracles), short=short)
    return pooled, whole


def chi2(trial: Trial, oracle: Estimate) -> Estimate:
    return METHODS["chi2-kf"].run(trial)


@pytest.mark.parametrize("seeds", [[901], [901, 902]])
def test_pooled_scores_are_the_scores_of_the_runs_concatenated(seeds: list[int]) -> None:
    pooled, whole = pooled_and_score(seeds, chi2)
    assert pooled["status"] == whole.status == "ok"
    assert pooled["growth_undecided"] == whole.growth_undecided  # one mark, one seed or many
    for mine, theirs in (("steady", whole.steady), ("worst", whole.steady_worst),
                         ("transient", whole.transient)):
        assert pooled[mine] == pytest.approx(theirs, rel=1e-10), mine
    assert pooled["growth"] == pytest.approx(whole.growth, rel=1e-10)
    assert pooled["detection"] == whole.detection and pooled["false_alarm"] == whole.false_alarm
    assert pooled["detection"][0] > 0  # the bias is seen on some attacked sample


def test_the_oracle_pooled_scores_one() -> None:
    # short: its growth on 6 runs is reported, not ruled on (the score is what this test checks)
    pooled, _ = pooled_and_score([901, 902], lambda trial, oracle: oracle, short=True)
    assert pooled["steady"][0] == pytest.approx(1.0, rel=1e-9)
    assert pooled["transient"][0] == pytest.approx(1.0, rel=1e-9)


def growing(trial: Trial, oracle: Estimate) -> Estimate:
    """The oracle's estimate plus an error growing as k^2 (steps k): diverged by growth."""
    k = np.arange(trial.x.shape[1], dtype=float)
    drift = ((k / k[-1]) ** 2)[:, None] * 50.0 * trial.scenario.steady_covariance.diagonal() ** 0.5
    return Estimate(oracle.xhat + drift[None, :, None, :])


def test_a_diverged_row_reports_its_growth_and_no_score() -> None:
    pooled, whole = pooled_and_score([901, 902], growing)
    assert pooled["status"] == whole.status == "diverged"
    assert pooled["growth"] == pytest.approx(whole.growth, rel=1e-10) and pooled["growth"] > 4
    assert all(pooled[k] is None for k in ("steady", "worst", "transient", "detection"))
    job = testseeds.Job("kf", ("printed", "tuned"), 0, METHODS["kf"], {})
    rows = testseeds._rows(job, {"point": 0, "constants": {}, "rule": "r", "mark": ""}, pooled, 6)
    assert [r["row"] for r in rows] == ["printed", "tuned"] and all(r["shared"] for r in rows)
    low, high = pooled["growth_interval"]  # Amendment 4 (c): a diverged row stores its growth
    assert low <= pooled["growth"] <= min(high, pooled["growth_largest"]) <= pooled["growth_upper"]
    for r in rows:
        assert r["status"] == "diverged" and r["steady"] is None
        assert r["growth"] == float(f"{pooled['growth']:.4g}")
        assert r["growth_interval"] == [float(f"{low:.4g}"), float(f"{high:.4g}")]
        assert r["growth_upper"] == float(f"{pooled['growth_upper']:.4g}")
    huge = testseeds._written_growth(pooled | {"growth": 7.2e21})
    assert huge["growth"] == ">1e6"
    assert testseeds._written_growth(pooled | {"status": "ok", "growth": 1.23456})["growth"] == 1.23456


def frozen_blow_up(trial: Trial, oracle: Estimate) -> Estimate:
    """One run of each trial jumps to 1e5 times the oracle's error early in the steady window and
    stays there.

    The pooled late / mid factor stays near 1 (the first design's miss: ding2020 tuned on
    inertia5 under replacement scored 1.59e29 as a ratio); the run escapes (Amendment 2).
    """
    xhat = oracle.xhat.copy()
    settle = estimators.settle_steps(trial.scenario)
    e = oracle.xhat[:, settle:, 0] - trial.x[:, settle:]
    level = 1e5 * np.sqrt(np.mean(e**2))
    xhat[0, settle + 5:] += level * np.sqrt(trial.x.shape[-1])
    return Estimate(xhat)


def test_a_cell_that_escaped_is_diverged_whatever_its_growth() -> None:
    pooled, whole = pooled_and_score([901, 902], frozen_blow_up)
    sc = scenarios.scenario("target20", "bias", horizon="auto", runs=3, seed=901)
    settle = estimators.settle_steps(sc)
    length = sc.horizon + 1 - settle
    assert not estimators.grows((whole.growth,) * 3, settle, length)
    assert pooled["growth"] == pytest.approx(whole.growth, rel=1e-10)
    assert pooled["status"] == whole.status == "diverged" and pooled["steady"] is None
    # the pooled runs and the runs joined into one trial: one verdict, one reason
    assert pooled["reason"] == whole.reason and whole.reason.startswith("it escaped: steady-window RMS")
    short, _ = pooled_and_score([901], frozen_blow_up, short=True)
    assert short["status"] == "ok"  # a smoke test reports, it does not rule


def linear(trial: Trial, oracle: Estimate) -> Estimate:
    """The oracle's estimate plus an error growing linearly in k: unbounded, factor 2.9."""
    k = np.arange(trial.x.shape[1], dtype=float)
    drift = (k / k[-1])[:, None] * 30.0 * trial.scenario.steady_covariance.diagonal() ** 0.5
    return Estimate(oracle.xhat + drift[None, :, None, :])


def test_an_error_growing_linearly_is_diverged() -> None:
    """Amendment 2 (b): the first limit, 4, read this error (factor about 2.9) as a score."""
    pooled, whole = pooled_and_score([901, 902], linear)
    assert 2.5 < whole.growth < 3.2 and pooled["growth"] == pytest.approx(whole.growth, rel=1e-10)
    assert pooled["status"] == whole.status == "diverged" and "k^p" in pooled["reason"]


def random_walk(trial: Trial, oracle: Estimate) -> Estimate:
    """The oracle's estimate plus an error whose mean square grows as k (a random walk's): factor
    about 1.7 on the steady window, which Amendment 2's limit 2 read as a score."""
    k = np.arange(trial.x.shape[1], dtype=float)
    drift = np.sqrt(k / k[-1])[:, None] * 30.0 * trial.scenario.steady_covariance.diagonal() ** 0.5
    return Estimate(oracle.xhat + drift[None, :, None, :])


def test_an_error_growing_as_a_random_walk_is_diverged() -> None:
    """Amendment 3 (b): the rule is on the exponent, 1 here, not on a factor."""
    pooled, whole = pooled_and_score([901, 902], random_walk)
    assert 1.4 < whole.growth < 2.0  # below the factor 2 of Amendment 2
    assert pooled["status"] == whole.status == "diverged"
    assert pooled["reason"] == whole.reason and whole.reason.startswith("its error grows")


def of_runs(mid: np.ndarray, late: np.ndarray) -> tuple[float, float, float]:
    """The factor and interval the growth rule reads (the node of the largest lower bound)."""
    return estimators.decisive(estimators.growth_nodes(mid, late))


def test_the_mark_reads_every_nodes_upper_bound() -> None:
    """Amendment 4 (b): a row is bounded only when every node's upper bound of p is at most the
    limit; a wide interval around a small factor is marked, not read as bounded."""
    rng = np.random.default_rng(4)
    mid = rng.gamma(4.0, 0.25, (320, 3))
    late = mid * np.array([1.0, 1.0, 1.0]) + rng.normal(0, 0.02, (320, 3))
    late[:, 2] = mid[:, 2] * rng.gamma(2.0, 0.5, 320)  # node 2: no growth on average, noisy
    nodes = estimators.growth_nodes(mid, np.abs(late))
    g, fields = testseeds._growth_fields(nodes)
    window = (715, 2146)
    assert not estimators.grows(g, *window)
    assert fields["growth_upper"] == nodes.high.max() and fields["growth_largest"] == nodes.value.max()
    assert estimators.growth_exponent(nodes.value[2], *window) < estimators.GROWTH_EXPONENT
    assert estimators.growth_not_excluded(fields["growth_upper"], *window)  # node 2's interval
    quiet = estimators.growth_nodes(mid[:, :2], np.abs(late[:, :2]))
    assert not estimators.growth_not_excluded(quiet.high.max(), *window)
    assert not estimators.growth_not_excluded(10.0, 5, 3)  # no two quarters: nothing ruled
    # the decisive node is the node of the largest lower bound
    worst = int(np.argmax(nodes.low))
    assert g == (nodes.value[worst], nodes.low[worst], nodes.high[worst])


def test_the_divergence_constants_are_the_protocols_and_escape_is_pooled() -> None:
    div = protocol.load()["divergence"]
    assert (estimators.ESCAPE_LIMIT, estimators.GROWTH_EXPONENT) == (div["escape_limit"],
                                                                      div["growth_exponent"])
    # the cell's mean over its runs decides: the same mean, the same verdict, at any run count
    assert estimators.escaped(np.full(4, 2e8)) and estimators.escaped(np.full(4000, 2e8))
    assert not estimators.escaped(np.full(4, 0.5e8)) and not estimators.escaped(np.full(4000, 0.5e8))
    assert estimators.escaped(np.array([4e8, 1.0, 1.0])) and estimators.escaped(np.ones((2, 3)) * 2e8)
    for bad in (np.array([-1.0]), np.ones((2, 2, 2)), np.array([])):
        with pytest.raises(ValidationError, match="per_run"):
            estimators.escaped(bad)


@pytest.mark.parametrize("p", [0.25, 0.5, 1.0, 2.0])
def test_the_growth_exponent_of_a_power_law_is_its_exponent(p: float) -> None:
    """Within 1 % on the arena's windows (exact for p = 1), whatever the horizon."""
    for settle, length in ((103, 308), (715, 2146), (5, 20)):
        k = np.arange(settle, settle + length, dtype=float)
        g = estimators.growth((k**p)[None, :, None])[0]
        assert estimators.growth_exponent(g, settle, length) == pytest.approx(p, rel=1e-2)
    assert estimators.growth_exponent(1.0, 103, 308) == 0.0
    assert estimators.growth_exponent(float("inf"), 103, 308) == float("inf")
    assert estimators.grows((2.0, 1.04, 3.0), 103, 308) and not estimators.grows((2.0, 1.02, 3.0), 103, 308)
    assert not estimators.grows((9.0, 9.0, 9.0), 1, 3)  # no two distinct quarters: not ruled
    # the interval is over the runs: runs alike give a point, one run apart a spread; the node
    # that grows most surely is the one reported
    assert of_runs(np.ones(5), np.full(5, 2.0)) == (2.0, 2.0, 2.0)
    value, low, high = of_runs(np.ones(40), np.r_[np.ones(39), 100.0])
    assert low < value < high and value == pytest.approx(139 / 40)
    two = of_runs(np.ones((40, 2)), np.c_[np.full(40, 1.5), np.r_[np.ones(39), 100.0]])
    assert two == (1.5, 1.5, 1.5)
    rng = np.random.default_rng(3)
    few, many = (of_runs(rng.exponential(size=r), rng.exponential(size=r))
                 for r in (5, 500))
    assert few[2] - few[1] > many[2] - many[1]  # a few runs: a wide interval
    with pytest.raises(ValidationError, match="mid, late"):
        of_runs(np.ones(3), np.ones(4))
    assert of_runs(np.ones(1), np.full(1, 9.0)) == (9.0, 0.0, np.inf)
    assert estimators.growth_exponent(0.0, 103, 308) == -np.inf
    for bad in ((1.0, 0, 308), (1.0, 103, 3), (-1.0, 103, 308), (float("nan"), 103, 308)):
        with pytest.raises(ValidationError):
            estimators.growth_exponent(*bad)


def test_the_data_free_score_is_what_the_zero_estimate_scores() -> None:
    """:func:`testseeds.data_free_score` is the expected score of x_hat = 0: its sample matches."""
    seeds = [901, 902, 903, 904]
    oparts, parts = [], []
    for s in seeds:
        sc = scenarios.scenario("tank12", "none", horizon="auto", runs=10, seed=s)
        trial = scenarios.simulate(sc)
        settle = estimators.settle_steps(sc)
        oracle = METHODS["oracle"].run(trial)
        oparts.append(testseeds.summary(trial, oracle, settle))
        parts.append(testseeds.summary(trial, Estimate(np.zeros_like(oracle.xhat)), settle))
    free = testseeds.data_free_score(sc, oparts)
    zero = testseeds.pool(oparts, parts, seeds)
    # 40 runs of a stationary plant (tau = 90 steps, 1358 steady steps): a few % of sampling error
    assert zero["status"] == "ok" and zero["steady"][0] == pytest.approx(free, rel=0.1)
    assert testseeds.data_free_score(sc, oparts[:1] + [{"status": "error"}]) is None


def test_the_data_free_moment_is_the_prior_propagated() -> None:
    sc = scenarios.scenario("tank12", "none", horizon="auto", runs=2, seed=901)
    A, Q, n = sc.plant.A, sc.plant.Q, sc.plant.n
    P0 = sc.plant.x0_std**2 * np.eye(n)
    assert np.allclose(estimators.data_free_moment(sc, 0, 1), P0)
    assert np.allclose(estimators.data_free_moment(sc, 1, 3), A @ P0 @ A.T + Q
                       + A @ (A @ P0 @ A.T + Q) @ A.T + Q)
    for start, stop in ((0, 0), (-1, 2), (0, sc.horizon + 2), (0.5, 2)):
        with pytest.raises(ValidationError, match="start, stop"):
            estimators.data_free_moment(sc, start, stop)


def test_a_short_run_reports_growth_without_ruling_on_it() -> None:
    pooled, whole = pooled_and_score([901], growing, short=True)
    assert pooled["status"] == whole.status == "ok" and pooled["growth"] > 4


def test_a_method_that_fails_on_one_seed_is_an_error_row() -> None:
    ok = {"status": "ok"}
    row = testseeds.pool([ok, ok], [ok, {"status": "error", "reason": "RuntimeError: x"}], [901, 902])
    assert (row["status"], row["reason"], row["steady"]) == ("error", "seed 902: RuntimeError: x", None)
    row = testseeds.pool([ok, ok], [{"status": "not finite"}, ok], [901, 902])
    assert (row["status"], row["growth"]) == ("diverged", None)
    row = testseeds.pool([ok, {"status": "error", "reason": "x"}], [ok, ok], [901, 902])
    assert (row["status"], row["reason"]) == ("error", "seed 902: the oracle did not run")
    with pytest.raises(ValidationError, match="Incompatible lengths of oracle, parts and seeds"):
        testseeds.pool([ok], [ok, ok], [901, 902])


# ---------------------------------------------------------------------------------- the stage


def test_the_stage_writes_printed_and_tuned_rows_deterministically(repo: Path, tmp_path: Path) -> None:
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    argv = ["test", "--tuned", str(tuned_file(repo)), "--seeds", "301", "302", "--runs", "2",
            "--horizon", "8", "--short", "--attacks", "none,bias"]
    assert tuning.main([*argv, "--out", str(a)]) == 0
    assert tuning.main([*argv, "--out", str(b)]) == 0
    assert a.read_bytes() == b.read_bytes()
    data = json.loads(a.read_text())
    tuned = json.loads(tuned_file(repo).read_text())
    assert data["tuned"] == testseeds.committed(tuned_file(repo))
    assert data["protocol"]["sha256"] == tuned["protocol"]["sha256"]
    assert data["seeds"] == [301, 302] and data["attacks"] == ["none", "bias"]
    plant = data["plants"]["tank12"]
    assert plant["horizon"] == 8 and plant["home"] == []
    for attack, rows in plant["cells"].items():
        assert [r["method"] for r in rows][0] == "oracle", attack
        assert rows[0]["steady"][0] == pytest.approx(1.0)
        for name in METHODS_TUNED:
            mine = [r for r in rows if r["method"] == name]
            assert [r["row"] for r in mine] == ["printed", "tuned"]
            choice = tuned["tuned"]["tank12"][name]
            assert mine[1]["constants"] == choice["constants"] and mine[1]["rule"] == choice["rule"]
            assert mine[0]["shared"] == mine[1]["shared"] == (choice["point"] == 0)
            if mine[0]["shared"]:
                assert mine[0]["steady"] == mine[1]["steady"]
            assert all(r["runs"] == 4 for r in mine)
    assert tuning.main(["test", "--tuned", str(tuned_file(repo)), "--seeds", "104",
                        "--out", str(tmp_path / "c.json")]) == 2
    assert not (tmp_path / "c.json").exists()


def test_a_failing_method_is_its_own_rows_only(repo: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def broken(self, trial):
        raise RuntimeError("broken on purpose")

    monkeypatch.setattr(baselines.WmsrKF, "run", broken)
    data = testseeds.run(tuned_file(repo), **TINY)
    for rows in data["plants"]["tank12"]["cells"].values():
        for r in rows:
            if r["method"] == "wmsr-kf":
                assert (r["status"], r["reason"]) == ("error", "seed 301: RuntimeError: broken on purpose")
            else:
                assert r["status"] == "ok", r


def test_a_local_cluster_gives_the_rows_of_one_process(repo: Path) -> None:
    pytest.importorskip("dask.distributed")
    small = TINY | {"seeds": [303], "attacks": ["bias"]}
    assert testseeds.run(tuned_file(repo), **small, workers=1) == testseeds.run(tuned_file(repo), **small)


def test_the_protocol_commit_is_recorded() -> None:
    commit = testseeds._protocol_commit()
    assert commit is None or len(commit) == 40
    assert protocol.load()["seeds"]["test"] == [301, 302, 303, 304, 305, 306, 307, 308]


def test_local_kf_on_inertia5_grows_at_the_exponent_the_protocol_states() -> None:
    """Amendment 4 (b): the node filters that do not see the rigid-body mode grow as k^0.082 on the
    steady window, from their exact error covariance (Riccati recursion: the node filter's model is
    the truth's, so its own covariance is its error's), in the unit of the score (the oracle's
    covariance over the same window): between the limit and what the runs resolve."""
    sc = scenarios.scenario("inertia5", "none", horizon="auto", runs=2, seed=101)
    A, Q, n = sc.plant.A, sc.plant.Q, sc.plant.n

    def covariances(C: np.ndarray, R: np.ndarray) -> np.ndarray:
        P, out = sc.plant.x0_std**2 * np.eye(n), []
        for k in range(sc.horizon + 1):
            if k:
                P = A @ P @ A.T + Q
            G = P @ C.T @ np.linalg.inv(C @ P @ C.T + R)
            P = (np.eye(n) - G @ C) @ P @ (np.eye(n) - G @ C).T + G @ R @ G.T
            out.append(P)
        return np.array(out)

    settle = estimators.settle_steps(sc)
    oracle = covariances(sc.C.reshape(-1, n), block_diag(*sc.R))[settle:]
    metric = np.linalg.inv(oracle.mean(axis=0))
    length = sc.horizon + 1 - settle
    mid, late = estimators.quarters(length)
    p = []
    for i in range(sc.network.N):
        q = np.einsum("ab,kba->k", metric, covariances(sc.C[i], sc.R[i])[settle:]) / n
        p.append(estimators.growth_exponent(float(q[late].mean() / q[mid].mean()), settle, length))
    assert np.round(p, 3).tolist() == [0.0, 0.0, 0.0, 0.082, 0.082]
