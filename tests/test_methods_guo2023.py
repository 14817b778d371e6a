"""guo2023 in the arena (secest.methods.guo2023): equivalence with the notebook, the arena method."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import bench_harness

import secest.arena.papers  # noqa: F401  (registers the methods)
from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.arena.papers import guo2023 as arena_guo2023
from secest.core.validation import ValidationError
from secest.methods import guo2023


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.fixture(scope="module")
def notebook_run():
    """The notebook's own functions on its Section V example (20 runs, 200 steps) and ours.

    The notebook's ``example_model``, ``signal``, ``simulate`` and ``run_estimator`` are taken by
    name (``notebook_definitions``: only those definitions and what they read are executed).
    """
    ns = bench_harness().notebook_definitions("guo2023", "example_model", "signal", "simulate",
                                         "run_estimator", mode="fast")
    model, n = ns["example_model"](), ns["n_steps"]
    d = ns["signal"]("d_signal", ns["d_signal"], n)
    a = ns["signal"]("a_signal", ns["a_signal"], n)
    assert np.abs(a).max() > 0  # the attack is on: the comparison covers the attacked path
    _, ya = ns["simulate"](model, d, a, 20, ns["seed"])
    return ns["run_estimator"](model, ya), guo2023.run_estimator(model, ya)


def test_estimator_equals_the_notebook_on_the_paper_example(notebook_run) -> None:
    est, mine = notebook_run
    steps = est.steps
    assert _rel(mine.x.transpose(1, 2, 0, 3), est.x) <= 1e-10  # notebook: (K+1, N, runs, n)
    assert _rel(mine.P, est.P) <= 1e-10
    assert _rel(np.stack(mine.u_hat).transpose(2, 0, 1, 3), est.u_hat) <= 1e-10
    assert _rel(mine.W, np.array([s.W for s in steps])) <= 1e-10
    assert _rel(mine.J, np.array([s.J for s in steps])) <= 1e-10
    assert _rel(mine.P_loc, np.array([s.P_loc for s in steps])) <= 1e-10
    assert _rel(mine.x_loc.transpose(1, 2, 0, 3), np.array([s.x_loc for s in steps])) <= 1e-10
    # the example's gain is zero to round-off (E6): compare absolutely
    assert np.abs(mine.K - np.array([s.K for s in steps])).max() <= 1e-12
    assert mine.checks["KU1"].max() <= 1e-12 and mine.checks["M2B2"].max() <= 1e-12
    assert mine.checks["G1"].max() == 0.0


def test_failing_links_per_run_match_the_shared_path_where_no_link_fails() -> None:
    sc = scenarios.scenario("inertia5", "bias", runs=4, horizon=40)
    t = scenarios.simulate(sc)
    mdl = arena_guo2023.arena_model(sc)
    link = np.ones((4, 41), np.int8)
    link[0, 10:13] = 0
    shared = guo2023.run_estimator(mdl, t.y, keep_steps=False)
    per_run = guo2023.run_estimator(mdl, t.y, link=link, keep_steps=False)
    assert per_run.P.shape == (4, 41, 5, 6, 6) and shared.P.shape == (41, 5, 6, 6)
    assert _rel(per_run.x[1:], shared.x[1:]) <= 1e-10
    assert _rel(per_run.P[1:], np.broadcast_to(shared.P, per_run.P[1:].shape)) <= 1e-10
    assert np.abs(per_run.x[0, 10:] - shared.x[0, 10:]).max() > 0  # run 0 lost messages
    # while every link is down a node keeps its local pair: P_bar^i = P_bar^{i,i}
    assert np.all(np.isfinite(per_run.x))


def test_the_estimate_does_not_depend_on_the_attack_signal() -> None:
    """K U_1 = 0 (28): with H^i known, the state estimate is the same with and without the bias."""
    sc = scenarios.scenario("tank12", "bias", runs=3, horizon=60)
    clean = scenarios.simulate(replace(sc, attack=scenarios.cards()["attack"]["none"]))
    attacked = scenarios.simulate(sc)
    mdl = arena_guo2023.arena_model(sc)
    a = guo2023.run_estimator(mdl, attacked.y, keep_steps=False)
    b = guo2023.run_estimator(mdl, clean.y, keep_steps=False)
    assert np.abs(a.x - b.x).max() <= 1e-10 * np.abs(b.x).max()
    # the attack estimate u_hat_1 = V_1^T a moves by exactly the bias (sign of the SVD aside)
    bias = sc.attack.magnitude * sc.plant.r_std[sc.network.measures[0, 0]]
    assert np.allclose(np.abs(a.u1[0] - b.u1[0])[..., 0], bias * attacked.attacked[:, :, 0], atol=1e-10)


@pytest.mark.parametrize("attack", ["none", "bias", "message", "dos"])
def test_the_method_runs_on_a_small_scenario(attack: str) -> None:
    sc = scenarios.scenario("inertia5", attack, runs=4, horizon=50)
    method = METHODS["guo2023"]
    assert method.kind == "paper" and method.not_applicable(sc) is None
    est = method.run(scenarios.simulate(sc))
    assert est.xhat.shape == (4, 51, 5, 6) and np.all(np.isfinite(est.xhat))
    assert est.alarms.shape == (4, 51, 5) and est.alarms.dtype == bool
    assert np.broadcast_shapes(est.bound.shape, (4, 51, 5, 6, 6)) == (4, 51, 5, 6, 6)
    if attack in ("none", "message", "dos"):  # no attackable sensor on the card: no alarm
        assert not est.alarms.any()
    if attack in ("message", "dos"):
        assert "outside theory" in est.notes


def test_alarm_statistic_is_the_normalised_attack_estimate() -> None:
    sc = scenarios.scenario("tank12", "bias", runs=3, horizon=20)
    dec = guo2023.feedthrough_decomposition(np.eye(1), sc.R[0])
    P = 0.01 * np.eye(4)
    u1 = np.array([[0.3]])
    cov = (sc.C[0] @ P @ sc.C[0].T + sc.R[0])[0, 0]
    assert arena_guo2023.attack_statistic(dec, sc.C[0], sc.R[0], P, u1)[0] == pytest.approx(0.09 / cov)


def test_not_applicable_when_the_attack_free_outputs_do_not_observe_the_plant() -> None:
    sc = scenarios.scenario("inertia5", "bias", runs=4, horizon=20)
    assumption2 = "(A, C_2) is observable, C_2 = [C_2^1; ...; C_2^N] the attack-free outputs (Assumption 2)"
    # every sensor attackable (Remark 1 literally): single-output nodes keep no attack-free output
    assert arena_guo2023.Guo2023(threat="all").not_applicable(sc) == assumption2
    # node 0 carries the only absolute angle; without it only differences remain (rigid mode lost)
    net = replace(sc.network, measures=np.array([[0], [3], [4], [3], [4]]))
    assert METHODS["guo2023"].not_applicable(replace(sc, network=net)) == assumption2
    none = replace(sc, network=net, attack=scenarios.cards()["attack"]["none"])
    assert METHODS["guo2023"].not_applicable(none) is None


def test_bad_input_is_refused_with_the_argument_named() -> None:
    sc = scenarios.scenario("inertia5", "none", runs=2, horizon=5)
    with pytest.raises(ValidationError, match="threat must be one of"):
        arena_guo2023.Guo2023(threat="some")
    with pytest.raises(ValidationError, match="threat must be one of"):
        arena_guo2023.arena_model(sc, threat="some")
    mdl = arena_guo2023.arena_model(sc)
    with pytest.raises(ValidationError, match="Incompatible dimensions of ya"):
        guo2023.run_estimator(mdl, np.zeros((2, 6, 4, 1)))
    with pytest.raises(ValidationError, match="Incompatible dimensions of link"):
        guo2023.run_estimator(mdl, np.zeros((2, 6, 5, 1)), link=np.ones((2, 5)))
