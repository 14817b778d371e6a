"""The arena's distributed baselines (secest.arena.baselines): measured against independent filters."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from secest.arena import baselines, estimators, scenarios
from secest.arena.estimators import METHODS
from secest.core import graphs
from secest.core.validation import ValidationError

DISTRIBUTED = ("consensus-kf-1", "consensus-kf", "diffusion-kf", "kcf", "wmsr-kf")
"""The baselines that exchange messages (``local-kf`` does not)."""


def _trial(network: str = "inertia5", attack: str = "none", **kw) -> scenarios.Trial:
    return scenarios.simulate(scenarios.scenario(network, attack, **({"runs": 4, "horizon": 60} | kw)))


def _textbook_kf(trial: scenarios.Trial) -> np.ndarray:
    """Node by node, run by run: the covariance-form Kalman filter on the node's own measurements."""
    sc = trial.scenario
    A, Q = sc.plant.A, sc.plant.Q
    runs, K1, N, _ = trial.y.shape
    n = sc.plant.n
    out = np.empty((runs, K1, N, n))
    for i in range(N):
        C, R = sc.C[i], sc.R[i]
        for r in range(runs):
            x, P = np.zeros(n), sc.plant.x0_std**2 * np.eye(n)
            for k in range(K1):
                if k:
                    x, P = A @ x, A @ P @ A.T + Q
                K = P @ C.T @ np.linalg.inv(C @ P @ C.T + R)
                x = x + K @ (trial.y[r, k, i] - C @ x)
                P = (np.eye(n) - K @ C) @ P
                out[r, k, i] = x
    return out


def test_every_baseline_is_registered_with_a_title_and_finite_shaped_estimates() -> None:
    t = _trial("tank12")
    for name in ("local-kf", *DISTRIBUTED):
        m = METHODS[name]
        assert m.kind == "baseline" and m.title and m.__doc__
        assert m.not_applicable(t.scenario) is None
        xhat = m.run(t).xhat
        assert xhat.shape == (4, 61, 12, 4) and np.all(np.isfinite(xhat)), name


@pytest.mark.parametrize("network", ["inertia5", "tank12"])
def test_local_kf_is_the_textbook_kalman_filter_of_each_node(network: str) -> None:
    t = _trial(network)
    expected = _textbook_kf(t)
    diff = np.abs(METHODS["local-kf"].run(t).xhat - expected)
    # information form against covariance form: rounding only (1.8e-12 measured on inertia5, |x| <= 7.9)
    assert diff.max() <= 1e-12 * (1.0 + np.abs(expected).max())


def test_many_consensus_rounds_give_the_centralised_kf() -> None:
    """CM with L rounds: the averages converge geometrically to 1/N x the sums (inertia5 ring)."""
    t = _trial("inertia5")
    central = estimators.centralised_kf(t.scenario, t.y)[:, :, None]
    gap = {L: float(np.abs(baselines.ConsensusKF(rounds=L).run(t).xhat - central).max())
           for L in (5, 20, 200)}
    oracle_error = float(np.sqrt(np.mean(np.sum((central - t.x[:, :, None]) ** 2, axis=-1))))
    # measured: 2.5e-2, 2.4e-6, 1.0e-14 (rad, rad/s) against the centralised KF's RMS error 0.12
    assert gap[200] < 1e-9 * oracle_error
    assert gap[200] < gap[20] < gap[5]


def test_one_round_on_a_complete_graph_averages_exactly() -> None:
    t = _trial("inertia5")
    complete = replace(t.scenario.network, edges=graphs.complete_edges(5))
    t = replace(t, scenario=replace(t.scenario, network=complete))
    central = estimators.centralised_kf(t.scenario, t.y)[:, :, None]
    assert np.abs(baselines.ConsensusKF(rounds=1).run(t).xhat - central).max() < 1e-8


@pytest.mark.parametrize("network", ["inertia5", "tank12"])
def test_with_every_link_down_every_distributed_baseline_is_the_local_kf(network: str) -> None:
    """The DoS fallback: a node uses only what arrived, itself; falsified messages never arrive."""
    t = _trial(network, "message")  # falsified messages on every link ...
    t = replace(t, link=np.zeros_like(t.link))  # ... and every link down at every step
    local = METHODS["local-kf"].run(t).xhat
    for name in DISTRIBUTED:
        assert np.array_equal(METHODS[name].run(t).xhat, local), name


def test_consensus_kf_under_dos_counts_its_own_information_once() -> None:
    """At a lost step CM's update is the local one: no N-fold count of its own data."""
    t = _trial("inertia5")
    link = np.ones_like(t.link)
    link[:2, 0] = 0  # runs 0 and 1 lose the first step's rounds, runs 2 and 3 do not
    t = replace(t, link=link)
    cm = baselines.ConsensusKF(rounds=1).run(t).xhat[:, 0]
    local = METHODS["local-kf"].run(t).xhat[:, 0]
    assert np.array_equal(cm[:2], local[:2])
    assert np.abs(cm[2:] - local[2:]).max() > 1e-3 * np.abs(local[2:]).max()


def test_kcf_without_consensus_gain_is_the_local_kf() -> None:
    t = _trial("tank12", "message")
    local = METHODS["local-kf"].run(t).xhat
    assert np.array_equal(baselines.KalmanConsensusFilter(epsilon=0.0).run(t).xhat, local)
    assert not np.allclose(baselines.KalmanConsensusFilter(epsilon=0.2).run(t).xhat, local)


def test_wmsr_trimming_every_neighbour_is_the_local_kf() -> None:
    t = _trial("inertia5", "message")  # ring: degree 2
    local = METHODS["local-kf"].run(t).xhat
    assert np.array_equal(baselines.WmsrKF(trimmed=2).run(t).xhat, local)
    assert not np.allclose(baselines.WmsrKF(trimmed=1).run(t).xhat, local)


def test_wmsr_step_drops_the_extremes_around_its_own_value() -> None:
    """Own 0, neighbours 5, 1, 2 above and -1, -7 below; F = 1 drops 5 and -7: (0+1+2-1)/4."""
    own = np.zeros((1, 6, 1))
    to = np.zeros(5, np.intp)  # node 0 receives from 1 .. 5 (edges in sender order)
    received = np.array([5.0, 1.0, 2.0, -1.0, -7.0]).reshape(1, 5, 1)
    delivered = np.ones((1, 5))
    assert baselines.wmsr(own, received, delivered, to, 1)[0, 0, 0] == pytest.approx(0.5)
    assert baselines.wmsr(own, received, delivered, to, 0)[0, 0, 0] == pytest.approx(0.0)
    assert baselines.wmsr(own, received, delivered, to, 5)[0, 0, 0] == 0.0
    received[0, 0, 0] = 1e9  # a Byzantine neighbour: dropped, the result does not move
    assert baselines.wmsr(own, received, delivered, to, 1)[0, 0, 0] == pytest.approx(0.5)
    delivered[0, 1] = 0.0  # value 1 lost: 1e9 dropped, then 2, -1 kept with -7 dropped
    assert baselines.wmsr(own, received, delivered, to, 1)[0, 0, 0] == pytest.approx(1.0 / 3.0)
    assert np.array_equal(baselines.wmsr(own, received, delivered, to, 1)[0, 1:], own[0, 1:])


def test_encodings_map_a_state_perturbation_to_the_message() -> None:
    rng = np.random.default_rng(0)
    delta = rng.standard_normal((3, 4))
    Y = rng.standard_normal((3, 4, 4))
    assert np.allclose(baselines.encode_consensus_kf_1(delta, Y), np.einsum("rnm,rm->rn", Y, delta))
    assert np.allclose(baselines.encode_consensus_kf(delta, Y[0]), delta @ Y[0].T)
    with pytest.raises(ValidationError, match="Incompatible dimensions of Y"):
        baselines.encode_consensus_kf_1(delta, Y[:, :3, :3])
    with pytest.raises(ValidationError, match="delta must be a finite array"):
        baselines.encode_consensus_kf([np.nan], Y[0, :1, :1])


def test_bad_constants_are_refused_naming_them() -> None:
    for cls, bad in ((baselines.ConsensusKF, "rounds"), (baselines.ConsensusInformationKF, "rounds"),
                     (baselines.WmsrKF, "trimmed")):
        for value in (0 if bad == "rounds" else -1, 1.5, True, "2"):
            with pytest.raises(ValidationError, match=bad):
                cls(**{bad: value})
    with pytest.raises(ValidationError, match="combination"):
        baselines.DiffusionKF(combination="uniform")
    for value in (-0.1, float("nan"), "0.2"):
        with pytest.raises(ValidationError, match="epsilon"):
            baselines.KalmanConsensusFilter(epsilon=value)


def test_kcf_runs_a_gain_beyond_one_over_the_max_degree_marked_outside_its_theory() -> None:
    """One applicability rule (Amendment 2): a stability condition marks the cell, never n/a."""
    t = _trial("target20", runs=2, horizon=5)  # max degree 10
    kcf = baselines.KalmanConsensusFilter(epsilon=0.2)
    assert kcf.not_applicable(t.scenario) is None
    assert any("epsilon * max degree < 1" in text for text in kcf.outside_theory(t.scenario))
    assert kcf.run(t).xhat.shape == (2, 6, t.scenario.network.N, t.scenario.plant.n)
    assert baselines.KalmanConsensusFilter(epsilon=0.05).outside_theory(t.scenario) == []


def test_a_ci_round_is_the_weighted_average_of_the_information_pairs() -> None:
    """``x_i + Y^{-1} sum_{j != i} w_ij (q_j - Y_j x_i)`` is ``(sum_j w_ij Y_j)^{-1} sum_j w_ij q_j``."""
    rng = np.random.default_rng(1)
    runs, N, n = 3, 5, 4
    L = rng.standard_normal((runs, N, n, n))
    Y = L @ np.swapaxes(L, -1, -2) + n * np.eye(n)
    x = rng.standard_normal((runs, N, n))
    q = np.einsum("rinm,rim->rin", Y, x)
    net = scenarios.scenario("inertia5", "none").network
    w, own = estimators.metropolis_weights(net)
    W = np.diag(own)
    W[net.receivers, net.senders] = w
    assert np.allclose(W.sum(axis=1), 1.0) and np.array_equal(W, W.T)  # doubly stochastic
    Wk = baselines._Weights(np.broadcast_to(w, (runs, net.E)), np.broadcast_to(own, (runs, N)))
    x_new, Y_new = baselines._ci_round(net, Wk, x, Y, q[:, net.senders])
    Y_avg = np.einsum("ij,rjnm->rinm", W, Y)
    x_avg = np.linalg.solve(Y_avg, np.einsum("ij,rjn->rin", W, q)[..., None])[..., 0]
    assert np.abs(Y_new - Y_avg).max() < 1e-15 * np.abs(Y_avg).max()  # summation order only
    assert np.abs(x_new - x_avg).max() < 1e-13 * np.abs(x_avg).max()  # measured 4.4e-16 at |x| <= 1.2


def test_wmsr_refuses_inconsistent_shapes() -> None:
    to = np.array([0, 1, 2])
    with pytest.raises(ValidationError, match="Incompatible dimensions of received"):
        baselines.wmsr(np.zeros((1, 3, 2)), np.zeros((1, 3, 3, 2)), np.ones((1, 3)), to, 1)
    with pytest.raises(ValidationError, match="Incompatible dimensions of delivered"):
        baselines.wmsr(np.zeros((1, 3, 2)), np.zeros((1, 3, 2)), np.ones((3, 3)), to, 1)
    with pytest.raises(ValidationError, match="receivers must be a non-decreasing"):
        baselines.wmsr(np.zeros((1, 3, 2)), np.zeros((1, 3, 2)), np.ones((1, 3)), to[::-1], 1)
    with pytest.raises(ValidationError, match="trimmed"):
        baselines.wmsr(np.zeros((1, 3, 2)), np.zeros((1, 3, 2)), np.ones((1, 3)), to, -1)
