"""guo2023's algorithm (secest.methods.guo2023): unit tests on the paper's Section V example, the
arena method (secest.arena.papers.guo2023)."""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
from conftest import repo_root

from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.arena.papers import guo2023 as arena_guo2023
from secest.core import covariance
from secest.core.estimation import constrained_gain, feedthrough_decomposition
from secest.core.validation import ValidationError
from secest.methods import guo2023

FIG = repo_root() / "figures" / "guo2023"


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def _columns(stem: str) -> dict[str, np.ndarray]:
    """The committed figure data figures/guo2023/<stem>.csv, column by column."""
    with (FIG / f"{stem}.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    return {name: np.array([float(r[name]) for r in rows]) for name in rows[0]}


def section_v_model(h: float = 0.1) -> guo2023.GuoModel:
    """The example of Sec. V as printed (the notebook's ``example_model``): 3 states, d and a
    scalar, 4 nodes with 2 outputs, ring 1-2-3-4-1 with weights 1/3."""
    G = np.array([[0.1], [0.2], [0.1]])
    H = np.array([[[0.1], [0.1]], [[0.1], [0.2]], [[0.2], [0.1]], [[0.2], [0.2]]])
    Gbar = np.hstack([G, np.zeros((3, 1))])
    Hbar = np.concatenate([np.zeros((4, 2, 1)), H], axis=2)

    def A(k: int) -> np.ndarray:
        e = np.sin(k * h) - np.sin(k * h - h)
        Ak = np.zeros((3, 3))
        Ak[0, 0] = Ak[2, 2] = np.exp(-h + e)
        Ak[1, 0] = 2.0 * np.sinh(0.5 * h) * np.exp(-1.5 * h + e)
        Ak[1, 1] = np.exp(-2.0 * h + e)
        return Ak

    def C(k: int) -> np.ndarray:
        s, c = np.sin(k * h), np.cos(k * h)
        return np.array([[[1.0, 0, 2], [0, s, 0]], [[0.0, 0, 0], [0, 1, 0]],
                         [[0.0, 0, 1], [0, 0, 0]], [[c, 1.5, 0], [0, 0, 0]]])

    return guo2023.GuoModel(
        nx=3, N=4, A=A, Q=lambda k: 1e-4 * np.eye(3), C=C, R=lambda k: np.stack([1e-4 * np.eye(2)] * 4),
        Gbar=lambda k: Gbar, Hbar=lambda k: Hbar,
        Pi=np.array([[1, 1, 0, 1], [1, 1, 1, 0], [0, 1, 1, 1], [1, 0, 1, 1]]) / 3.0,
        x0_hat=np.zeros(3), P0=0.01 * np.eye(3))


@pytest.fixture(scope="module")
def example_run():
    """The estimator on the example, 200 steps, 3 runs of random measurements (the bounds, gains
    and weights do not depend on the data)."""
    mdl = section_v_model()
    ya = np.random.default_rng(5).standard_normal((3, 201, 4, 2))
    return mdl, ya, guo2023.run_estimator(mdl, ya)


def test_bounds_and_exact_covariances_are_the_committed_ones(example_run) -> None:
    """P_bar (Fig. 2's bands, extra_consistency's tr P_bar) and the exact tr P of error_covariance
    (x0_spread = 1) against figures/guo2023, written with 11 significant digits."""
    mdl, _, run = example_run
    assert run.P.shape == (201, 4, 3, 3)
    fig2 = _columns("fig2_states_estimates")
    for i in range(4):
        for c in range(3):
            np.testing.assert_allclose(np.sqrt(run.P[:, i, c, c]), fig2[f"sd_bound_node{i + 1}[{c}]"],
                                       rtol=1e-9, atol=1e-12)
    P, P_loc, Psi = guo2023.error_covariance(mdl, run, spread=1.0)
    assert P.shape == (201, 4, 3, 3) and P_loc.shape == (200, 4, 3, 3) and Psi.shape == (200, 4, 3, 2)
    cons = _columns("extra_consistency")
    for i in range(4):
        np.testing.assert_allclose(np.trace(run.P[1:, i], axis1=-2, axis2=-1), cons[f"tr_P_bar[{i}]"],
                                   rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(np.trace(P[1:, i], axis1=-2, axis2=-1), cons[f"tr_P_exact[{i}]"],
                                   rtol=1e-9, atol=1e-12)
    # Theorem 1 as measured (C1): P_bar - P >= 0 with the committed smallest eigenvalue
    c1 = json.loads((FIG / "claims.json").read_text())["C1"]["measured"]
    assert covariance.min_eig(run.P[1:] - P[1:]).min() == pytest.approx(
        c1["min_eig_Pbar_minus_P_k_ge_1"], rel=1e-6)


def test_structure_of_the_example(example_run) -> None:
    """E6: K == 0 in the example; (10) M_bar_2 B_2 = I; G_bar_1 = 0; sum_j W^ij = I (20)."""
    _, _, run = example_run
    assert run.K.shape == run.J.shape == (200, 4, 3, 2) and run.W.shape == (200, 4, 4, 3, 3)
    assert np.abs(run.K).max() < 1e-12
    assert run.checks["KU1"].shape == (200, 4) and run.checks["KU1"].max() < 1e-12
    assert run.checks["M2B2"].max() < 1e-12 and run.checks["G1"].max() == 0.0
    assert np.abs(run.W.sum(axis=2) - np.eye(3)).max() < 1e-12
    assert np.all(run.W[:, 0, 2] == 0)  # nodes 1 and 3 are not neighbours
    assert len(run.gains) == 200 and len(run.gains[0]) == 4
    g = run.gains[-1][2]
    np.testing.assert_array_equal(g.K, run.K[-1, 2])
    np.testing.assert_array_equal(g.P_loc, run.P_loc[-1, 2])
    # (29) and (26): P_loc = P* - K S^T, S = P* C^T - J R
    C, R = section_v_model().C(200)[2], 1e-4 * np.eye(2)
    np.testing.assert_allclose(g.S, g.P_star @ C.T - g.J @ R, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(g.P_loc, covariance.symmetrize(g.P_star - g.K @ g.S.T), atol=1e-18)


def test_fusion_is_information_fusion(example_run) -> None:
    """(19)-(21) of every node against secest.core.covariance.information_fusion."""
    mdl, _, run = example_run
    for i in range(4):
        nb = np.flatnonzero(mdl.Pi[i])
        for r in range(3):
            x_ci, P_ci = covariance.information_fusion(
                [run.x_loc[r, -1, j] for j in nb], [run.P_loc[-1, j] for j in nb], mdl.Pi[i, nb])
            np.testing.assert_allclose(run.x[r, -1, i], x_ci, rtol=1e-10, atol=1e-14)
            np.testing.assert_allclose(run.P[-1, i], P_ci, rtol=1e-10, atol=1e-16)
    P, W, x = guo2023.fuse(run.P_loc[-1], mdl.Pi, np.broadcast_to(run.x_loc[:, -1, None], (3, 4, 4, 3)))
    np.testing.assert_allclose(x, np.einsum("ijab,rjb->ria", W, run.x_loc[:, -1]), rtol=1e-10, atol=1e-14)
    np.testing.assert_array_equal(P, run.P[-1])


def test_input_estimates_and_their_layout(example_run) -> None:
    """u_hat_1 = Sigma^-1 (z_1 - C_1 x_hat) (lines 20-21) with the fused estimate; u_hat in the run."""
    mdl, ya, run = example_run
    assert len(run.u1) == len(run.u_hat) == 4
    assert run.u1[0].shape == (3, 201, 1) and run.u_hat[0].shape == (3, 200, 2)
    decs = guo2023.decompositions(mdl, 7)
    assert [d.rank for d in decs] == [1, 1, 1, 1]
    for i, d in enumerate(decs):
        z1 = ya[:, 7, i] @ d.T1.T
        expected = (z1 - run.x[:, 7, i] @ (d.T1 @ mdl.C(7)[i]).T) / d.Sigma[0, 0]
        np.testing.assert_allclose(run.u1[i][:, 7], expected, rtol=1e-10, atol=1e-12)
        # u_hat_{k-1} = V_1 u_hat_1 + V_2 u_hat_2: its V_1 part is u_hat_1 of step k-1
        np.testing.assert_allclose(run.u_hat[i][:, 6] @ d.V1, run.u1[i][:, 6], rtol=1e-10, atol=1e-12)


def test_step_by_step_equals_the_run(example_run) -> None:
    mdl, ya, run = example_run
    state = guo2023.initial_state(mdl, ya[:, 0])
    assert state.k == 0 and state.P.shape == (4, 3, 3) and state.x.shape == (3, 4, 3)
    for k in range(1, 11):
        state, step = guo2023.estimator_step(mdl, state, ya[:, k])
        assert step.gains is None
    np.testing.assert_array_equal(state.x, run.x[:, 10])
    np.testing.assert_array_equal(state.P, run.P[10])


def test_constrained_gain_on_a_random_instance() -> None:
    """(28): K U_1 = 0 for any Theta; the stacked form equals the 2-D one of secest.core."""
    rng = np.random.default_rng(3)
    S, Theta = rng.standard_normal((2, 4, 3, 5)), rng.standard_normal((2, 4, 5, 5))
    U1 = np.linalg.qr(rng.standard_normal((5, 2)))[0]
    K = constrained_gain(S, Theta, U1, stacked=True)
    assert K.shape == (2, 4, 3, 5)
    assert np.abs(K @ U1).max() < 1e-12 * np.abs(K).max()
    np.testing.assert_allclose(K[1, 2], constrained_gain(S[1, 2], Theta[1, 2], U1), rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(constrained_gain(S, Theta, U1[:, :0], stacked=True), S @ Theta)


def test_local_gains_satisfy_the_unbiasedness_condition() -> None:
    """(10): M_bar_2 B_2 = I on a generic local step (n_y - p > n_u - p: K != 0), and K U_1 = 0."""
    rng = np.random.default_rng(11)
    nx, ny = 4, 5
    Gbar = np.hstack([rng.standard_normal((nx, 2)), np.zeros((nx, 1))])
    Hbar = np.hstack([np.zeros((ny, 2)), rng.standard_normal((ny, 1))])
    L = rng.standard_normal((ny, ny))
    R = L @ L.T / ny + 0.2 * np.eye(ny)
    dec = feedthrough_decomposition(Hbar, R)
    C = rng.standard_normal((ny, nx))
    g = guo2023.local_gains(rng.standard_normal((nx, nx)), 0.1 * np.eye(nx), Gbar, np.eye(nx), dec, dec,
                            C, R)
    np.testing.assert_allclose(g.M2 @ g.B2, np.eye(2), atol=1e-12)
    assert np.abs(g.K).max() > 0.01 and np.abs(g.K @ dec.U1).max() < 1e-12
    np.testing.assert_allclose(g.Xi @ g.Theta, np.eye(ny) - C @ g.J, atol=1e-12)  # (30), line 13
    np.testing.assert_allclose(g.R2, dec.U2.T @ R @ dec.U2, atol=1e-15)


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


def test_sparse_weights_and_per_edge_messages_are_the_dense_fusion() -> None:
    """The O(E) form (sparse Pi, messages per edge) on the Sec. V example with falsified
    messages, with and without failing links: measured relative deviation from the dense form."""
    mdl = section_v_model()
    sparse = replace(mdl, Pi=sp.csr_array(mdl.Pi))
    ya = np.random.default_rng(5).standard_normal((3, 41, 4, 2))
    rows, cols = np.nonzero(mdl.Pi * (1 - np.eye(4)))  # the edges, receiver by receiver
    shifts = np.random.default_rng(6).standard_normal((41, 3, rows.size, 3))

    def dense(k: int, x: np.ndarray) -> np.ndarray:
        out = np.broadcast_to(x[:, None], (3, 4, 4, 3)).copy()
        out[:, rows, cols] += shifts[k]
        return out

    link = np.ones((3, 41), np.int8)
    link[0, 10:13] = 0
    for lk in (None, link):
        a = guo2023.run_estimator(mdl, ya, received=dense, link=lk, keep_steps=lk is None)
        b = guo2023.run_estimator(sparse, ya, received=lambda k, x: x[:, cols] + shifts[k], link=lk,
                                  keep_steps=lk is None)
        assert _rel(b.x, a.x) <= 1e-12 and _rel(b.P, a.P) <= 1e-12
        if lk is None:  # the stored entries of the sparse Pi (diagonal included), row by row
            assert _rel(b.W, a.W[:, *np.nonzero(mdl.Pi)]) <= 1e-12
            with pytest.raises(ValidationError, match="dense"):
                guo2023.error_covariance(sparse, b)
    with pytest.raises(ValidationError, match="per-edge"):
        guo2023.run_estimator(sparse, ya, received=lambda k, x: x)


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


def test_outside_assumption_2_when_the_attack_free_outputs_do_not_observe_the_plant() -> None:
    sc = scenarios.scenario("inertia5", "bias", runs=4, horizon=20)
    assumption2 = "(A, C_2) is observable, C_2 = [C_2^1; ...; C_2^N] the attack-free outputs (Assumption 2)"
    # every sensor attackable (Remark 1 literally): single-output nodes keep no attack-free output,
    # and n_y >= n_u fails as well: that one it needs to run at all (N/A)
    everything = arena_guo2023.Guo2023(threat="all")
    assert assumption2 in everything.outside_theory(sc)
    # node 0 carries the only absolute angle; without it only differences remain (rigid mode lost)
    net = replace(sc.network, measures=np.array([[0], [3], [4], [3], [4]]))
    assert METHODS["guo2023"].outside_theory(replace(sc, network=net)) == [assumption2]
    assert METHODS["guo2023"].not_applicable(replace(sc, network=net)) is None  # it runs, marked
    none = replace(sc, network=net, attack=scenarios.cards()["attack"]["none"])
    assert METHODS["guo2023"].outside_theory(none) == []


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
    with pytest.raises(ValidationError, match="Pi must be row-stochastic, row 0"):
        guo2023.run_estimator(replace(mdl, Pi=2 * mdl.Pi), np.zeros((2, 6, 5, 1)))


def test_bad_input_to_the_library_functions_names_the_argument() -> None:
    mdl = section_v_model()
    ya = np.zeros((1, 4, 4, 2))
    with pytest.raises(ValidationError, match="run must keep its steps"):
        guo2023.error_covariance(mdl, guo2023.run_estimator(mdl, ya, keep_steps=False))
    link = np.ones((1, 4), np.int8)
    link[0, 2] = 0
    with pytest.raises(ValidationError, match="run must have gains shared by its runs"):
        guo2023.error_covariance(mdl, guo2023.run_estimator(mdl, ya, link=link))
    U1 = np.array([[1.0], [0.0]])
    with pytest.raises(ValidationError, match="U1\\^T Theta U1 must be invertible"):
        constrained_gain(np.ones((3, 2)), np.diag([0.0, 1.0]), U1, stacked=True)


def test_the_unconstrained_negative_control_lets_the_attack_in() -> None:
    """gain="unconstrained" (ours): S Xi_breve^+ minimises (26) without K U_1 = 0, so the same
    estimator, fed the attacked and the clean measurements, gives different estimates; a bad
    gain name is refused naming the argument."""
    sc = scenarios.scenario("tank12", "bias", runs=2, horizon=40)
    clean = scenarios.simulate(replace(sc, attack=scenarios.cards()["attack"]["none"]))
    attacked = scenarios.simulate(sc)
    mdl = arena_guo2023.arena_model(sc)
    a = guo2023.run_estimator(mdl, attacked.y, keep_steps=True, gain="unconstrained")
    b = guo2023.run_estimator(mdl, clean.y, keep_steps=True, gain="unconstrained")
    assert np.abs(a.x - b.x).max() > 1e-6 * np.abs(b.x).max()
    assert a.checks["KU1"].max() > 1e-6  # the constraint is not met
    assert np.all(np.linalg.eigvalsh(a.P_loc) > 0)
    rng = np.random.default_rng(11)
    nx, ny = 4, 5
    Gbar = np.hstack([rng.standard_normal((nx, 2)), np.zeros((nx, 1))])
    Hbar = np.hstack([np.zeros((ny, 2)), rng.standard_normal((ny, 1))])
    R = 0.5 * np.eye(ny)
    dec = feedthrough_decomposition(Hbar, R)
    args = (rng.standard_normal((nx, nx)), 0.1 * np.eye(nx), Gbar, np.eye(nx), dec, dec,
            rng.standard_normal((ny, nx)), R)
    g_c, g_u = guo2023.local_gains(*args), guo2023.local_gains(*args, gain="unconstrained")
    assert np.trace(g_u.P_loc) <= np.trace(g_c.P_loc) + 1e-12  # no constraint: not above (28)
    assert np.abs(g_u.K @ dec.U1).max() > 1e-6
    with pytest.raises(ValidationError, match="gain: expected one of"):
        guo2023.local_gains(*args, gain="free")
    with pytest.raises(ValidationError, match="gain: expected one of"):
        guo2023.run_estimator(mdl, clean.y, gain="free")
