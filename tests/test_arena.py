"""The arena (secest.arena.matrix, notebooks/arena.py): extensible by one card and one class, every cell
a number with its interval or a named N/A, the notebook's claims well formed. Measures, never votes."""

from __future__ import annotations

import csv
import hashlib
import json
import math
import re
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

from secest.arena import estimators, matrix, protocol, scenarios, tuning
from secest.arena.estimators import METHODS, Estimate, Method, Score, register
from secest.core.validation import ValidationError
from secest.repro.results import REQUIRED_KEYS, VERDICTS, repo_root

ROOT = repo_root()
NUMBER = r"-?\d+(?:\.\d+)?(?:e-?\d+)?"
WITH_INTERVAL = re.compile(rf"^{NUMBER}( %)? \[{NUMBER}, {NUMBER}\]$")

TOY_CARDS = """
[network.toy3]
title = "three sensors, all linked (toy)"
plant = "target"
N = 3
graph = "complete"
measures = [[0], [1], [0]]

[attack.toy-bias]
title = "toy bias on node 1"
kind = "bias"
nodes = [1]
start = 0.5
magnitude = 20.0

[scenario.toy-home]
network = "toy3"
attack = "toy-bias"
runs = 3
horizon = 20
"""


class ToyHold(Method):
    """Holds the prior mean (zero) at every node: a method any reader could add in ten lines."""

    name = "toy-hold"
    title = "toy: x_hat = 0"
    kind = "paper"
    reading = "ignores every measurement"

    def requirements(self, sc: scenarios.Scenario) -> list[tuple[str, bool]]:
        return [("the plant has at most 4 states (toy requirement)", sc.plant.n <= 4)]

    def conditions(self, sc: scenarios.Scenario) -> list[tuple[str, bool]]:
        return [("the plant has 3 states (toy theory)", sc.plant.n == 3)]

    def run(self, trial: scenarios.Trial) -> Estimate:
        r, k1, n_nodes, _ = trial.y.shape
        alarms = np.zeros((r, k1, n_nodes), bool)
        alarms[:, ::2, 0] = True  # a detector that flags node 0 every other step
        return Estimate(np.zeros((r, k1, n_nodes, trial.scenario.plant.n)), alarms=alarms)


@pytest.fixture
def toy_cards(tmp_path: Path) -> Path:
    path = tmp_path / "toy_cards.toml"
    path.write_text(TOY_CARDS)
    return path


@pytest.fixture
def toy_method():
    register(ToyHold)
    try:
        yield METHODS["toy-hold"]
    finally:
        METHODS.pop("toy-hold")


def test_a_toy_method_and_a_toy_scenario_appear_in_the_matrix(toy_cards: Path, toy_method: Method) -> None:
    """One card file and one registered class: both reach the matrix without any other change."""
    every = scenarios.matrix(extra=toy_cards, runs=3, horizon=20)  # smoke-test horizons: short=True
    names = [sc.name for sc in every]
    named = len(scenarios.cards()["scenario"])  # the package's own named scenarios (home grounds)
    assert names[-1] == "toy-home" and len(names) == 15 + named + 1  # the cross, the package's, the toy
    package = scenarios.matrix(runs=3, horizon=20)
    assert "toy-home" not in [sc.name for sc in package]  # the package's cards are untouched
    toy = every[-1]
    assert (toy.network.N, toy.attack.kind, toy.runs, toy.horizon) == (3, "bias", 3, 20)
    three_states = scenarios.scenario("target20", "none", runs=3, horizon=20)
    six_states = scenarios.scenario("inertia5", "none", runs=3, horizon=20)
    m = matrix.run_matrix([toy, three_states, six_states], short=True)  # methods=None: every one
    assert "toy-hold" in m.methods and set(m.methods) == set(METHODS)
    assert {sc.name for sc in m.scenarios} == {"toy-home", "target20/none", "inertia5/none"}
    cell = m.cell("toy-home", "toy-hold")
    assert cell.status == "ok" and cell.steady[1] <= cell.steady[2] and cell.outside == ()
    assert cell.detection is not None and cell.false_alarm is not None
    na = m.cell("inertia5/none", "toy-hold")
    assert na.status == "n/a" and na.reason == "the plant has at most 4 states (toy requirement)"
    assert set(m.curves["toy-home"].rms) >= {"oracle", "toy-hold"}
    assert "toy-hold" not in m.curves["inertia5/none"].rms
    rows = matrix.table_rows(m)
    assert len(rows) == 3 * len(m.methods)
    assert any(r["method"] == "toy-hold" and r["steady"].startswith("N/A: the plant") for r in rows)


def test_extra_cards_are_checked(tmp_path: Path) -> None:
    with pytest.raises(ValidationError, match="plant 'target' already exists"):
        scenarios.cards({"plant": {"target": {}}})
    with pytest.raises(ValidationError, match="unknown tables"):
        scenarios.cards({"plants": {}})
    with pytest.raises(ValidationError, match="is no file"):
        scenarios.cards(tmp_path / "missing.toml")
    with pytest.raises(ValidationError, match="network 'nope' has no card"):
        scenarios.cards({"scenario": {"x": {"network": "nope", "attack": "none"}}})
    with pytest.raises(ValidationError, match=r"scenario x: unknown key 'run' \(did you mean 'runs'"):
        scenarios.cards({"scenario": {"x": {"network": "inertia5", "attack": "none", "run": 3}}})
    with pytest.raises(ValidationError, match=r"networks \['nope'\] have no card"):
        scenarios.matrix(networks=["nope"])
    extended = scenarios.cards({"matrix": {"attacks": ["none", "bias"]}})
    assert extended["matrix"]["attacks"] == scenarios.cards()["matrix"]["attacks"]  # no duplicates


def test_matrix_selects_networks_and_attacks() -> None:
    grid = scenarios.matrix(networks=["inertia5"], attacks=["none", "dos"], runs=2, horizon=5)
    assert [sc.name for sc in grid] == ["inertia5/none", "inertia5/dos"]


class NeedsTheAttackSchedule(Method):
    """A method that cannot run on any card: it needs what no scenario gives."""

    name = "needs-schedule"
    title = "needs the attack schedule"

    def requirements(self, sc: scenarios.Scenario) -> list[tuple[str, bool]]:
        return [("the attack's schedule, which no card gives", False)]

    def run(self, trial: scenarios.Trial) -> Estimate:  # pragma: no cover - never reached
        raise AssertionError("a method that cannot run is never run")


@pytest.fixture()
def needs_schedule():
    register(NeedsTheAttackSchedule)
    yield "needs-schedule"
    METHODS.pop("needs-schedule")


def test_every_cell_is_a_number_with_its_interval_or_a_named_status(needs_schedule: str) -> None:
    sc = [scenarios.scenario(n, a, runs=4) for n, a in
          (("target20", "bias"), ("tank12", "message"), ("target20", "replacement"))]
    sc[0] = scenarios.scenario("inertia5", "bias", runs=4, horizon=300)  # a smoke test's horizon
    m = matrix.run_matrix(sc, ["oracle", "kf", "chi2-kf", "li2025", "kcf", needs_schedule],
                          short=True)
    for row in matrix.table_rows(m):
        if row["status"] == "ok":
            for q in ("steady", "worst", "transient"):
                assert WITH_INTERVAL.match(row[q]), row
            for rate in ("detection", "false_alarm"):
                assert row[rate] == "–" or (WITH_INTERVAL.match(row[rate]) and " %" in row[rate]), row
        else:
            assert row["status"] in ("N/A", "diverged") and re.match(r"^(N/A|diverged): \S", row["steady"]), row
    # outside its theory (a message attack is not its attack model): scored, and marked
    li = m.cell("tank12/message", "li2025")
    assert li.status == "ok" and li.outside[0].startswith("every attack on the measurement packets")
    assert m.cell("target20/replacement", needs_schedule).status == "n/a"
    # epsilon x max degree >= 1 is a stability condition of kcf's theory: it runs, marked (Amendment 2)
    kcf = m.cell("target20/replacement", "kcf")
    assert kcf.status != "n/a" and any("epsilon * max degree < 1" in t for t in kcf.outside)
    assert matrix.cell_text(m.cell("inertia5/bias", "chi2-kf"))["detection"] != "–"
    assert matrix.cell_text(m.cell("inertia5/bias", "kf"))["detection"] == "–"


def test_cell_text_refuses_what_cannot_be_shown() -> None:
    with pytest.raises(ValidationError, match="must name the failed requirement"):
        matrix.cell_text(Score("n/a"))
    with pytest.raises(ValidationError, match="status must be one of"):
        matrix.cell_text(Score("maybe"))
    with pytest.raises(ValidationError, match="must carry its steady, worst-node and transient"):
        matrix.cell_text(Score("ok"))
    assert matrix.cell_text(Score("diverged", "the estimate is not finite"))["steady"].startswith("diverged")
    assert matrix.fmt_interval((0.001234, 0.001, 0.0015), percent=True) == "0.123 % [0.1, 0.15]"
    assert matrix.fmt_interval((12345.0, 1e4, 2e4)) == "1.23e4 [1e4, 2e4]"


def test_rate_interval_is_never_narrower_than_wilson_and_widens_with_correlation() -> None:
    from secest.core.montecarlo import wilson_interval

    rng = np.random.default_rng(0)
    where = np.ones((20, 50, 4), bool)
    iid = rng.random(where.shape) < 0.1
    clustered = np.zeros(where.shape, bool)
    clustered[:2] = True  # two runs alarm throughout: the same count, all in two runs
    for alarms in (iid, clustered):
        value, low, high = estimators.rate(alarms, where)
        w_low, w_high = wilson_interval(int(alarms.sum()), int(where.sum()))
        assert value == pytest.approx(alarms.mean())
        assert low <= w_low and high >= w_high
    assert estimators.rate(clustered, where)[2] > 2 * wilson_interval(int(clustered.sum()), where.size)[1]
    assert estimators.rate(np.zeros_like(where), where)[1:] == wilson_interval(0, where.size)
    with pytest.raises(ValidationError, match="at least one sample"):
        estimators.rate(iid, np.zeros_like(where))


def test_scaled_attacks_keep_the_draws() -> None:
    sc = scenarios.scenario("inertia5", "replacement", runs=3, horizon=20)
    big = matrix.scaled(sc, 10.0)
    assert big.attack.magnitude == pytest.approx(10 * sc.attack.magnitude)
    a, b = scenarios.simulate(sc), scenarios.simulate(big)
    assert np.array_equal(a.attacked, b.attacked) and np.array_equal(a.y_clean, b.y_clean)
    hit = a.attacked[..., 0]
    assert np.allclose(b.y[hit][:, 0], 10 * a.y[hit][:, 0])  # the uniform draw, scaled
    dos = scenarios.scenario("inertia5", "dos", runs=3, horizon=20)
    assert matrix.scaled(dos, 10.0) is dos
    with pytest.raises(ValidationError, match="factor must be a positive finite number"):
        matrix.scaled(sc, 0.0)


def test_error_curve_and_activity() -> None:
    t = scenarios.simulate(scenarios.scenario("target20", "bias", runs=3, horizon=20))
    xhat = np.broadcast_to(t.x[:, :, None, :], (3, 21, 20, 3)).copy()
    assert np.array_equal(matrix.error_curve(xhat, t.x), np.zeros(21))
    xhat[0, 4] = np.inf
    curve = matrix.error_curve(xhat, t.x)
    assert np.isnan(curve[4]) and np.isfinite(np.delete(curve, 4)).all()
    active = matrix.attack_activity(t)
    assert active[:6].max() == 0 and active[6:].min() == 1  # the bias starts at 30 % of 20 steps
    with pytest.raises(ValidationError, match="Incompatible dimensions of xhat and x"):
        matrix.error_curve(xhat[..., :2], t.x)


def test_evaluate_observes_every_run_and_refuses_unknown_methods() -> None:
    sc = scenarios.scenario("inertia5", "none", runs=3, horizon=20)
    seen: list[str] = []
    out = estimators.evaluate(sc, ["oracle", "kf", "li2025"], observe=lambda n, t, e: seen.append(n),
                              short=True)
    assert seen == ["oracle", "kf", "li2025"] and set(out) == {"oracle", "kf", "li2025"}
    with pytest.raises(ValidationError, match=r"methods \['nope'\] are not registered"):
        estimators.evaluate(sc, ["nope"])
    with pytest.raises(ValidationError, match="not registered"):
        matrix.run_matrix([sc], ["nope"])
    with pytest.raises(ValidationError, match="scenario names must be unique"):
        matrix.run_matrix([sc, sc], ["kf"], short=True)


def git(repo: Path, *args: str) -> None:
    subprocess.run(["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t", *args],
                   check=True, capture_output=True)


@pytest.fixture(scope="module")
def arena_files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """A smoke tuning (every method, every plant: 2 runs of 8 steps on one validation seed)
    committed in a temporary git repository, and the test stage on it (2 test seeds, 2 runs of 8
    steps): the files the notebook reads, made the way `make robustness` and `make arena-test` do."""
    root = tmp_path_factory.mktemp("arena-repo")
    git(root, "init", "-q")
    tuned, test = root / "tuned.json", root / "test.json"
    assert tuning.main(["--seeds", "101", "--runs", "2", "--horizon", "8", "--short",
                        "--out", str(tuned)]) == 0
    git(root, "add", "tuned.json")
    git(root, "commit", "-q", "-m", "tuned")
    assert tuning.main(["test", "--tuned", str(tuned), "--seeds", "301", "302", "--runs", "2",
                        "--horizon", "8", "--short", "--out", str(test)]) == 0
    return {"tuned_path": str(tuned), "test_path": str(test)}


@pytest.mark.notebook
def test_arena_notebook_fast_mode(run_notebook, arena_files: dict[str, str]) -> None:
    """Fast mode on a smoke test's files: claims well formed and consistent, both heatmaps made."""
    claims = run_notebook("arena", **arena_files)
    fig_dir = Path(claims.pop("_fig_dir"))
    ids = set(claims)
    assert {"X1", "X2", "X3", "X5", "X6", "X7", "X8"} <= ids
    attacks = scenarios.cards()["matrix"]["attacks"]
    assert {f"X4_{a}" for a in attacks if a != "none"} <= ids
    for cid, entry in claims.items():
        assert set(REQUIRED_KEYS) <= set(entry), cid
        assert entry["verdict"] in VERDICTS and isinstance(entry["holds"], bool), cid
        assert entry["basis"] == "measured" and entry["source"] == "ours", cid
        assert entry["measured"][entry["key"]] is not None, cid
        printed = entry["measured"]["printed"]
        assert set(printed) == {entry["key"], "holds", "premise"}, cid
    # the rules, re-applied to the measured values (consistency of measured / threshold / holds)
    x1 = claims["X1"]["measured"]
    assert x1["min_upper"] == min(v["min_upper"] for v in x1["per_plant"].values())
    assert claims["X1"]["holds"] == (x1["min_upper"] >= 1.0)
    assert not [v for v in x1["per_plant"].values() if re.search(r", (kf|chi2-kf|oracle)$", v["cell"])]
    assert claims["X8"]["holds"] == (claims["X8"]["measured"]["diverged"] == 0)
    assert claims["X8"]["measured"]["diverged"] == len(claims["X8"]["measured"]["cells"])
    x6 = claims["X6"]["measured"]
    assert claims["X6"]["holds"] == all(v <= 0.01 for v in x6["upper"].values())
    x2, x3, x5, x7 = (claims[c]["measured"] for c in ("X2", "X3", "X5", "X7"))
    outside = {n for per in x2["per_plant"].values() for n, v in per.items() if v > 2.0}
    assert {n.split(" ")[0] for n in outside} <= set(x2["outside"])
    assert claims["X2"]["holds"] == (x2["n_outside"] == 0 == len(x2["outside"]))
    assert x3["n_not_degraded"] == sum(not v for v in x3["degrades"].values())
    assert claims["X3"]["holds"] == (x3["n_not_degraded"] == 0)
    assert claims["X5"]["holds"] == (x5["n_na"] == sum(len(v) for v in x5["n/a"].values()) == 0)
    if x7["lower"]:
        assert x7["worst_lower"] == min(x7["lower"].values())
    for a in attacks:
        if a == "none":
            continue
        c = claims[f"X4_{a}"]
        x4 = c["measured"]
        assert sorted(x4["within"]) == sorted(n for n, v in x4["upper"].items() if v <= 2.0)
        assert x4["upper"] == {n: max(v.values()) for n, v in x4["upper_per_plant"].items()}
        paper = [n for n in x4["within"] if METHODS[n].kind == "paper"]
        assert x4["paper_within"] == len(paper)
        assert c["holds"] == (len(paper) >= 1)
        assert c["premise"]["holds"] == bool(x4["plants"])
        assert c["verdict"] == ("fails-premise" if not x4["plants"] else "holds" if paper else "fails")
        assert not [n for n in x4["upper"] if not METHODS[n].exchanges] or a in ("bias", "replacement")
    manifest = tomllib.loads((ROOT / "figures" / "manifest.toml").read_text())
    expected = {Path(n).name for fig in manifest["arena"]["figures"] for n in fig["files"]}
    assert expected <= {p.name for p in fig_dir.iterdir()}
    test = json.loads(Path(arena_files["test_path"]).read_text())
    for kind in ("printed", "tuned"):
        with (fig_dir / f"extra_heatmap_{kind}.csv").open() as fh:
            rows = list(csv.DictReader(fh))
        assert len(rows) == 3 * len(attacks) * (len(tuning.ARGUMENTS) + 1)
        for row in rows:
            net, att = row["scenario"].split("/")
            mine = [r for r in test["plants"][net]["cells"][att] if r["method"] == row["method"]
                    and r["row"] in (kind, "reference")]
            assert len(mine) == 1 and row["status"] == mine[0]["status"], row
            if row["status"] == "ok":
                assert float(row["steady"]) == pytest.approx(mine[0]["steady"][0], rel=1e-2), row
                lo, hi = float(row["steady_low"]), float(row["steady_high"])
                assert math.isfinite(lo) and lo <= hi, row
            else:
                assert row["reason"].strip() and math.isnan(float(row["steady"])), row


def test_committed_arena_covers_the_acceptance_matrix() -> None:
    """The committed test stage: at least 3 plants x 5 attacks, every registered method printed and
    tuned in every cell, each row a number with its interval, a diverged row's growth, or a reason;
    run on the committed tuned.json (its SHA-256)."""
    test = json.loads((ROOT / "figures" / "arena" / "test.json").read_text())
    tuned = (ROOT / "figures" / "arena" / "tuned.json").read_bytes()
    assert test["tuned"]["sha256"] == hashlib.sha256(tuned).hexdigest()
    registered = protocol.load()["seeds"]
    assert not test["short"] and test["runs_per_seed"] == registered["runs_per_seed"]
    assert test["seeds"] and set(test["seeds"]) <= set(registered["test"])
    if test["seeds"] != registered["test"]:  # a deviation is declared where readers look for it
        errata = (ROOT / "ERRATA.md").read_text()
        assert "DEVIATION FROM THE REGISTERED PROTOCOL" in errata
        assert f"{test['seeds'][0]}–{test['seeds'][-1]}" in errata
    assert len(test["plants"]) >= 3 and len(test["attacks"]) >= 5
    for net, record in test["plants"].items():
        groups = list(record["cells"].items())
        groups += [(name, h["rows"]) for name, h in record.get("homes", {}).items()]
        window = (record["settle"], record["horizon"] + 1 - record["settle"])
        for att, rows in groups:
            kinds = {(r["method"], r["row"]) for r in rows}
            for name in set(METHODS) - {"oracle"}:
                assert {(name, "printed"), (name, "tuned")} <= kinds, (net, att, name)
            for r in rows:
                if r["status"] == "ok":
                    assert r["steady"][1] <= r["steady"][0] <= r["steady"][2], r
                    low, high = r["growth_interval"]
                    assert low <= r["growth"] <= min(high, r["growth_largest"]), r
                    assert high <= r["growth_upper"], r
                    if att in record["cells"]:  # the growth rule and its mark, on this plant's window
                        assert not estimators.grows((r["growth"], low, high), *window), r
                        assert r["growth_undecided"] == estimators.growth_not_excluded(
                            r["growth_upper"], *window), r
                elif r["status"] == "diverged":
                    assert r["steady"] is None and r["reason"].startswith(
                        ("its error grows", "it escaped", "the estimate is not finite")), r
                    if r["reason"].startswith("its error grows"):  # Amendment 4: auditable
                        low = r["growth_interval"][0]
                        assert low == ">1e6" or estimators.grows((r["growth"], low, low), *window), r
                    assert r["growth"] is None or r["growth"] == ">1e6" or r["growth"] > 0, r
                else:
                    assert r["reason"].strip(), r
