"""Unit tests of the secest core: behaviour and bad input (error class and message)."""

from __future__ import annotations

import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import networkx as nx  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from scipy import stats  # noqa: E402

from secest.core import channels, covariance, detectors, graphs, montecarlo  # noqa: E402
from secest.core.validation import (  # noqa: E402
    ValidationError,
    as_matrix,
    check_positive_int,
    check_probability,
)
from secest.repro import plotting, results

# ---------------------------------------------------------------- validation


def test_as_matrix_accepts_and_converts() -> None:
    out = as_matrix("R", [[1, 0], [0, 1]], (2, 2), square=True)
    assert out.dtype == float and out.shape == (2, 2)
    assert as_matrix("x", np.ones((3, 4)), (None, 4)).shape == (3, 4)


def test_as_matrix_shape_message() -> None:
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of R: expected \(2, 2\), found \(2, 3\)"):
        as_matrix("R", np.zeros((2, 3)), (2, 2))
    with pytest.raises(ValidationError, match=r"A must be a square matrix, found shape \(2, 3\)"):
        as_matrix("A", np.zeros((2, 3)), square=True)
    with pytest.raises(ValidationError, match="P contains NaN or infinite entries"):
        as_matrix("P", [[np.nan]])
    with pytest.raises(ValidationError, match="M must be a real numeric array, found str 'abc'"):
        as_matrix("M", "abc")


def test_check_probability_and_int() -> None:
    assert check_probability("p", 0.3) == 0.3
    with pytest.raises(ValidationError, match=r"p must lie in \[0, 1\], found 1.5"):
        check_probability("p", 1.5)
    with pytest.raises(ValidationError, match=r"alpha must lie in \(0, 1\), found 0"):
        check_probability("alpha", 0, open_interval=True)
    assert check_positive_int("n", 3) == 3
    with pytest.raises(ValidationError, match="n must be an integer, found 2.5"):
        check_positive_int("n", 2.5)
    with pytest.raises(ValidationError, match="n must be >= 3, found 2"):
        check_positive_int("n", 2, minimum=3)


# ---------------------------------------------------------------- graphs


def test_ring_and_complete_graph() -> None:
    ring = graphs.ring_graph(5)
    assert ring.sum(axis=1).tolist() == [2] * 5 and np.array_equal(ring, ring.T)
    full = graphs.complete_graph(4)
    assert full.sum() == 12 and np.all(np.diag(full) == 0)
    with pytest.raises(ValidationError, match="n must be >= 3, found 2"):
        graphs.ring_graph(2)
    with pytest.raises(ValidationError, match="n must be >= 2, found 1"):
        graphs.complete_graph(1)


def test_adjacency_of_digraph_lists_in_neighbours() -> None:
    g = nx.DiGraph([(0, 1), (1, 2), (2, 0), (1, 1)])
    a = graphs.adjacency(g)
    assert a[1, 0] == 1 and a[0, 1] == 0 and a[1, 1] == 0  # node 1 receives from 0


def test_random_geometric_graph_is_connected_and_seeded() -> None:
    a = graphs.random_geometric_graph(20, 0.35, seed=4)
    b, xy = graphs.random_geometric_graph(20, 0.35, seed=4, return_positions=True)
    assert np.array_equal(a, b) and xy.shape == (20, 2)
    dist = np.linalg.norm(xy[:, None] - xy[None], axis=-1)
    assert np.array_equal(a, ((dist <= 0.35) & ~np.eye(20, dtype=bool)).astype(float))
    graphs.check_connected(a)
    with pytest.raises(ValidationError, match="radius = 0.01 gave no connected graph on n = 20 nodes in max_tries = 5"):
        graphs.random_geometric_graph(20, 0.01, seed=0, max_tries=5)
    with pytest.raises(ValidationError, match="radius must be > 0, found 0.0"):
        graphs.random_geometric_graph(20, 0.0, seed=0)


def test_check_connected() -> None:
    a = graphs.ring_graph(4)
    assert np.array_equal(graphs.check_connected(a), a)
    two = np.zeros((4, 4))
    two[0, 1] = two[1, 0] = two[2, 3] = two[3, 2] = 1
    with pytest.raises(ValidationError, match=r"disconnected graph with 2 components: \[\[0, 1\], \[2, 3\]\]"):
        graphs.check_connected(two)
    chain = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)  # 0 -> 1 -> 2
    graphs.check_connected(chain, strongly=False)
    with pytest.raises(ValidationError, match="disconnected graph with 3 components"):
        graphs.check_connected(chain, strongly=True)
    with pytest.raises(ValidationError, match="adj must contain only 0 and 1 entries"):
        graphs.check_connected([[0, 2], [2, 0]])
    with pytest.raises(ValidationError, match="adj must have a zero diagonal"):
        graphs.check_connected([[1, 1], [1, 0]])


def test_neighbours() -> None:
    nb = graphs.neighbours(graphs.ring_graph(4))
    assert nb[0].tolist() == [1, 3]
    assert graphs.neighbours(graphs.ring_graph(4), include_self=True)[0].tolist() == [0, 1, 3]


def test_row_stochastic_weights() -> None:
    w = graphs.row_stochastic_weights(graphs.ring_graph(5), self_weight=True)
    assert np.allclose(w.sum(axis=1), 1) and w[0, 0] == pytest.approx(1 / 3)
    w0 = graphs.row_stochastic_weights(graphs.ring_graph(5))  # default: h_ii = 0 (ding2020)
    assert w0[0, 0] == 0 and w0[0, 1] == pytest.approx(0.5)
    graphs.check_row_stochastic(w)
    with pytest.raises(ValidationError, match=r"adj has nodes without neighbours \[2\]"):
        graphs.row_stochastic_weights(np.array([[0, 1, 0], [1, 0, 0], [0, 0, 0]]), self_weight=False)


def test_check_row_stochastic_messages() -> None:
    with pytest.raises(ValidationError, match="weights must be row-stochastic, row 1 sums to 0.9"):
        graphs.check_row_stochastic([[0.5, 0.5], [0.4, 0.5]])
    with pytest.raises(ValidationError, match=r"weights must be non-negative, found weights\[0, 1\] = -0.5"):
        graphs.check_row_stochastic([[1.5, -0.5], [0.5, 0.5]])


def test_laplacian_and_lambda2_match_closed_forms() -> None:
    for n in (5, 7, 12):
        lam = graphs.algebraic_connectivity(graphs.ring_graph(n))
        assert lam == pytest.approx(2 * (1 - np.cos(2 * np.pi / n)), abs=1e-12)
        assert graphs.algebraic_connectivity(graphs.complete_graph(n)) == pytest.approx(n)
    lap = graphs.laplacian(graphs.ring_graph(4))
    assert np.allclose(lap @ np.ones(4), 0)
    assert np.allclose(lap, nx.laplacian_matrix(nx.cycle_graph(4)).toarray())
    with pytest.raises(ValidationError, match="adj must be symmetric"):
        graphs.algebraic_connectivity([[0, 1], [0, 0]])
    with pytest.raises(ValidationError, match="disconnected"):
        graphs.algebraic_connectivity(np.zeros((3, 3)))


# ---------------------------------------------------------------- channels


def test_gilbert_elliott_transition_and_stationary() -> None:
    P = channels.gilbert_elliott_transition(0.1, 0.92)
    assert np.allclose(P.sum(axis=1), 1)
    pi = channels.gilbert_elliott_stationary(0.1, 0.92)
    assert pi == pytest.approx(0.90196, abs=1e-5)
    assert np.allclose(np.array([1 - pi, pi]) @ P, [1 - pi, pi])
    with pytest.raises(ValidationError, match="p \\+ q must be positive"):
        channels.gilbert_elliott_stationary(0.0, 0.0)
    with pytest.raises(ValidationError, match=r"q must lie in \[0, 1\], found 1.2"):
        channels.gilbert_elliott_transition(0.1, 1.2)


def test_gilbert_elliott_empirical_rates() -> None:
    rng = np.random.default_rng(1)
    p, q = 0.1, 0.92
    d = channels.gilbert_elliott(p, q, 200_000, rng)
    prev, nxt = d[:-1], d[1:]
    p_hat = np.mean(nxt[prev == 1] == 0)
    q_hat = np.mean(nxt[prev == 0] == 1)
    assert p_hat == pytest.approx(p, abs=0.005) and q_hat == pytest.approx(q, abs=0.01)
    assert d.mean() == pytest.approx(q / (p + q), abs=0.005)
    assert d[0] == 1
    many = channels.gilbert_elliott(p, q, 50, np.random.default_rng(0), size=3, initial=0)
    assert many.shape == (3, 50) and np.all(many[:, 0] == 0)


def test_gilbert_elliott_is_seeded_and_validates() -> None:
    a = channels.gilbert_elliott(0.3, 0.5, 100, np.random.default_rng(7))
    b = channels.gilbert_elliott(0.3, 0.5, 100, np.random.default_rng(7))
    assert np.array_equal(a, b)
    with pytest.raises(ValidationError, match=r"initial must be one of \(0, 1\), found 2"):
        channels.gilbert_elliott(0.1, 0.9, 10, np.random.default_rng(0), initial=2)
    with pytest.raises(ValidationError, match="steps must be >= 1, found 0"):
        channels.gilbert_elliott(0.1, 0.9, 0, np.random.default_rng(0))


def test_bernoulli() -> None:
    b = channels.bernoulli(0.3, (100_000,), np.random.default_rng(2))
    assert set(np.unique(b)) <= {0, 1} and b.mean() == pytest.approx(0.3, abs=0.01)
    with pytest.raises(ValidationError, match=r"prob must lie in \[0, 1\], found -0.1"):
        channels.bernoulli(-0.1, 3, np.random.default_rng(0))


# ---------------------------------------------------------------- covariance


def _random_spd(rng: np.random.Generator, n: int) -> np.ndarray:
    m = rng.standard_normal((n, n))
    return m @ m.T + n * np.eye(n)


def test_symmetrize_and_psd_checks() -> None:
    P = np.array([[2.0, 1.0], [0.0, 2.0]])
    assert np.allclose(covariance.symmetrize(P), [[2, 0.5], [0.5, 2]])
    assert covariance.symmetrize(np.stack([P, P])).shape == (2, 2, 2)
    assert covariance.is_psd(np.eye(2)) and not covariance.is_psd(np.diag([1.0, -1.0]))
    assert not covariance.is_psd(P)  # not symmetric
    assert not covariance.is_psd(np.zeros((2, 2)), strict=True)
    assert covariance.min_eig(np.diag([3.0, 1.0])) == pytest.approx(1.0)
    with pytest.raises(ValidationError, match="P must be square in its last two axes"):
        covariance.symmetrize(np.zeros((2, 3)))


def test_check_psd_messages() -> None:
    assert covariance.check_psd("Q", np.eye(2)).shape == (2, 2)
    with pytest.raises(ValidationError, match="Q must be positive semidefinite, found lambda_min = -1"):
        covariance.check_psd("Q", np.diag([1.0, -1.0]))
    with pytest.raises(ValidationError, match="R must be symmetric"):
        covariance.check_psd("R", [[1.0, 0.5], [0.0, 1.0]])
    with pytest.raises(ValidationError, match="P0 must be positive definite"):
        covariance.check_psd("P0", np.zeros((2, 2)), strict=True)
    with pytest.raises(ValidationError, match=r"R must be square in its last two axes, found shape \(2, 3\)"):
        covariance.check_psd("R", np.zeros((2, 3)))


def test_joseph_update_equals_standard_form_for_optimal_gain() -> None:
    rng = np.random.default_rng(3)
    P, R = _random_spd(rng, 4), _random_spd(rng, 2)
    H = rng.standard_normal((2, 4))
    K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
    joseph = covariance.joseph_update(P, K, H, R)
    standard = (np.eye(4) - K @ H) @ P
    assert np.allclose(joseph, standard, atol=1e-10)
    assert np.array_equal(joseph, joseph.T)
    K_bad = K + 0.1
    assert covariance.is_psd(covariance.joseph_update(P, K_bad, H, R))


def test_joseph_update_shape_messages() -> None:
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of K: expected \(3, 1\), found \(3, 2\)"):
        covariance.joseph_update(np.eye(3), np.zeros((3, 2)), np.zeros((1, 3)), np.eye(1))
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of H: expected \(\*, 3\), found \(1, 2\)"):
        covariance.joseph_update(np.eye(3), np.zeros((3, 1)), np.zeros((1, 2)), np.eye(1))


def test_information_fusion_is_consistent_for_any_correlation() -> None:
    rng = np.random.default_rng(5)
    P1, P2 = _random_spd(rng, 3), _random_spd(rng, 3)
    x, P = covariance.information_fusion([np.zeros(3), np.ones(3)], [P1, P2], [0.3, 0.7])
    assert x.shape == (3,) and covariance.is_psd(P, strict=True)
    # CI bound: for the fully correlated extreme (identical errors) the fused P dominates
    # the true covariance of w1 e1 + w2 e2 mapped through the fusion weights.
    omega = 0.3 * np.linalg.inv(P1) + 0.7 * np.linalg.inv(P2)
    G1, G2 = np.linalg.solve(omega, 0.3 * np.linalg.inv(P1)), np.linalg.solve(omega, 0.7 * np.linalg.inv(P2))
    for cross in (np.zeros((3, 3)), np.linalg.cholesky(P1) @ np.linalg.cholesky(P2).T):
        joint = np.block([[P1, cross], [cross.T, P2]])
        G = np.hstack([G1, G2])
        true = G @ joint @ G.T
        assert covariance.min_eig(P - true) >= -1e-10
    # equal inputs give the input back
    xe, Pe = covariance.information_fusion([np.ones(3)] * 2, [P1, P1])
    assert np.allclose(xe, 1) and np.allclose(Pe, P1)


def test_information_fusion_bad_input() -> None:
    with pytest.raises(ValidationError, match="weights must be non-negative and sum to 1, found sum 0.8"):
        covariance.information_fusion([np.zeros(2)] * 2, [np.eye(2)] * 2, [0.4, 0.4])
    with pytest.raises(ValidationError, match="covariances must have one matrix per estimate: expected 2, found 1"):
        covariance.information_fusion([np.zeros(2)] * 2, [np.eye(2)])
    with pytest.raises(ValidationError, match=r"covariances\[1\] must be positive definite"):
        covariance.information_fusion([np.zeros(2)] * 2, [np.eye(2), np.zeros((2, 2))])
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of estimates\[1\]: expected \(2,\), found \(3,\)"):
        covariance.information_fusion([np.zeros(2), np.zeros(3)], [np.eye(2)] * 2)
    with pytest.raises(ValidationError, match="estimates must contain at least one estimate"):
        covariance.information_fusion([], [])


def test_covariance_intersection_optimal_weights() -> None:
    P1, P2 = np.diag([1.0, 100.0]), np.diag([100.0, 1.0])
    x, P, w = covariance.covariance_intersection([np.zeros(2), np.ones(2)], [P1, P2])
    assert w == pytest.approx([0.5, 0.5], abs=1e-4)
    grid = [np.trace(covariance.information_fusion([np.zeros(2)] * 2, [P1, P2], [a, 1 - a])[1])
            for a in np.linspace(0, 1, 101)]
    assert np.trace(P) <= min(grid) + 1e-6
    # a dominating estimate takes all the weight
    _, _, w2 = covariance.covariance_intersection([np.zeros(2)] * 2, [np.eye(2), 10 * np.eye(2)])
    assert w2[0] == pytest.approx(1.0, abs=1e-4)
    _, P_one, w_one = covariance.covariance_intersection([np.zeros(2)], [P1])
    assert np.allclose(P_one, P1) and w_one.tolist() == [1.0]


# ---------------------------------------------------------------- detectors


def test_chi2_threshold_and_false_alarm() -> None:
    tau = detectors.chi2_threshold(3, 0.05)
    assert tau == pytest.approx(stats.chi2.ppf(0.95, 3))
    assert detectors.chi2_false_alarm(3, tau) == pytest.approx(0.05)
    with pytest.raises(ValidationError, match=r"alpha must lie in \(0, 1\), found 1.0"):
        detectors.chi2_threshold(3, 1.0)
    with pytest.raises(ValidationError, match="dof must be >= 1, found 0"):
        detectors.chi2_threshold(0, 0.05)
    with pytest.raises(ValidationError, match="threshold must be >= 0, found -1.0"):
        detectors.chi2_false_alarm(2, -1.0)


def test_nis_and_test_single_and_stacked() -> None:
    S = np.diag([4.0, 1.0])
    assert detectors.nis([2.0, 1.0], S) == pytest.approx(2.0)
    g = detectors.nis(np.array([[2.0, 1.0], [0.0, 3.0]]), S)
    assert g.tolist() == pytest.approx([2.0, 9.0])
    assert detectors.chi2_passes([2.0, 1.0], S, 5.0) is True
    assert detectors.chi2_alarm([2.0, 1.0], S, 5.0) is False
    assert detectors.chi2_passes(np.array([[2.0, 1.0], [0.0, 3.0]]), S, 5.0).tolist() == [True, False]
    assert detectors.chi2_alarm(np.array([[2.0, 1.0], [0.0, 3.0]]), S, 5.0).tolist() == [False, True]


def test_chi2_test_is_a_warning_alias_of_chi2_passes() -> None:
    """chi2_test keeps its old answer (True = passes) but says it is ambiguous."""
    S = np.diag([4.0, 1.0])
    with pytest.warns(FutureWarning, match="use chi2_passes .True = accepted. or chi2_alarm"):
        assert detectors.chi2_test([2.0, 1.0], S, 5.0) is True
    with pytest.warns(FutureWarning):
        assert detectors.chi2_test([0.0, 3.0], S, 5.0) is False


def test_nis_empirical_false_alarm() -> None:
    rng = np.random.default_rng(9)
    S = np.array([[2.0, 0.5], [0.5, 1.0]])
    r = rng.multivariate_normal(np.zeros(2), S, size=100_000)
    tau = detectors.chi2_threshold(2, 0.01)
    rate = detectors.chi2_alarm(r, S, tau).mean()
    assert rate == pytest.approx(0.01, abs=0.002)


def test_detector_bad_input() -> None:
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of S: expected \(\.\.\., 2, 2\) to match innovation of length 2, found \(3, 3\)"):
        detectors.nis([1.0, 2.0], np.eye(3))
    with pytest.raises(ValidationError, match="S must be positive definite, found lambda_min = 0"):
        detectors.nis([1.0, 2.0], np.zeros((2, 2)))
    with pytest.raises(ValidationError, match="threshold must be > 0, found 0.0"):
        detectors.chi2_passes([1.0], np.eye(1), 0.0)


# ---------------------------------------------------------------- montecarlo


def test_spawn_rngs_independent_and_reproducible() -> None:
    a = [g.random() for g in montecarlo.spawn_rngs(3, 4)]
    b = [g.random() for g in montecarlo.spawn_rngs(3, 4)]
    assert a == b and len(set(a)) == 4
    with pytest.raises(ValidationError, match="seed must be a non-negative integer, found -1"):
        montecarlo.spawn_rngs(-1, 2)
    with pytest.raises(ValidationError, match="n must be >= 1, found 0"):
        montecarlo.spawn_rngs(1, 0)


def test_nees_and_anees_bounds() -> None:
    rng = np.random.default_rng(4)
    P = np.array([[2.0, 0.3], [0.3, 0.5]])
    e = rng.multivariate_normal(np.zeros(2), P, size=(50_000,))
    assert montecarlo.nees(e, P).mean() == pytest.approx(2.0, rel=0.02)
    lo, hi = montecarlo.anees_bounds(2, 100)
    assert lo < 2 < hi and hi - lo == pytest.approx(
        (stats.chi2.ppf(0.975, 200) - stats.chi2.ppf(0.025, 200)) / 100)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of P: expected \(\.\.\., 2, 2\) to match errors of length 2, found \(3, 3\)"):
        montecarlo.nees(np.zeros(2), np.eye(3))
    with pytest.raises(ValidationError, match=r"confidence must lie in \(0, 1\)"):
        montecarlo.anees_bounds(2, 10, confidence=1.0)


# ---------------------------------------------------------------- plotting


def test_save_figure_is_deterministic_and_writes_data(tmp_path) -> None:
    plotting.use_style()
    paths = []
    for sub in ("a", "b"):
        fig, ax = plt.subplots()
        ax.plot([0, 1, 2], [1, 3, 2], label="x")
        ax.set_xlabel("t [s]")
        paths.append(plotting.save_figure(fig, tmp_path / sub, "fig1_demo",
                                          data={"t": [0, 1, 2], "x": np.eye(3)}))
        plt.close(fig)
    assert paths[0].read_bytes() == paths[1].read_bytes()
    assert b"Software" not in paths[0].read_bytes()[:2000]
    csv = (tmp_path / "a" / "fig1_demo.csv").read_text().splitlines()
    assert csv[0] == "t,x[0],x[1],x[2]" and csv[1] == "0,1,0,0"


def test_save_figure_bad_input(tmp_path) -> None:
    fig, _ = plt.subplots()
    with pytest.raises(ValidationError, match="name must be a bare file stem"):
        plotting.save_figure(fig, tmp_path, "fig1.png")
    with pytest.raises(ValidationError, match=r"data\['y'\] has 2 rows, expected 3"):
        plotting.save_figure(fig, tmp_path, "fig1", data={"x": [1, 2, 3], "y": [1, 2]})
    with pytest.raises(ValidationError, match=r"data\['z'\] must be 1-D or 2-D"):
        plotting.save_data(tmp_path, "d", {"z": np.zeros((2, 2, 2))})
    with pytest.raises(ValidationError, match="data must hold at least one column"):
        plotting.save_data(tmp_path, "d", {})
    plt.close(fig)


# ---------------------------------------------------------------- results


def test_claim_and_write_claims(tmp_path) -> None:
    c = results.claim("Thm 1", "dist <= bound", np.array([0.1, 0.2]), np.float64(1.0), np.bool_(True),
                      source="Theorem 1")
    assert c == {"paper": "Thm 1", "check": "dist <= bound", "measured": [0.1, 0.2],
                 "threshold": 1.0, "holds": True, "source": "Theorem 1", "verdict": "holds",
                 "basis": "measured", "tolerance": results.DETERMINISTIC.as_dict()}
    path = results.write_claims(tmp_path / "claims.json", {"C1": c, "X1": c})
    assert json.loads(path.read_text())["C1"]["holds"] is True


def test_claim_optional_fields() -> None:
    ci = results.interval(0.1, 0.3, method="wilson")
    tol = results.Tolerance(rtol=0.0, atol=0.05, reason="Monte Carlo")
    c = results.claim("p", "c", {"rate": 0.2, "n": 100}, 0.5, False, source="ours", interval=ci,
                      key="rate", tolerance=tol, section="Claims")
    assert c["interval"] == {"low": 0.1, "high": 0.3, "level": 0.95, "method": "wilson"}
    assert c["key"] == "rate" and results.headline_value(c) == 0.2
    assert c["tolerance"] == {"rtol": 0.0, "atol": 0.05, "reason": "Monte Carlo"}
    assert c["verdict"] == "fails" and c["section"] == "Claims"
    # a claim whose premise fails is not reported as holding, whatever it measured
    d = results.claim("p", "c", 1.0, 1.0, True, premise=("Assumption 3 at x0", False))
    assert d["premise"] == {"statement": "Assumption 3 at x0", "holds": False}
    assert d["verdict"] == "fails-premise" and d["holds"] is True
    assert results.headline_value(results.claim("p", "c", [1.0], 1.0, True)) is None


def test_outcome_vocabulary() -> None:
    # not checked: a reason is required, and the outcome is never a failure
    n = results.claim("p", "c", 1.0, 1.0, None, not_checked="the LMI solver stopped at its limit")
    assert n["holds"] is None and n["verdict"] == "not-checked" and n["not_checked"].startswith("the LMI")
    assert results.point_verdict(n) in results.POINT_OUTCOMES
    b = results.claim("p", "c", 0.0, 0.0, True, basis="by-construction", decides=False, runs=300)
    assert b["basis"] == "by-construction" and b["runs"] == 300 and "decides" not in b
    for kw, match in [({"holds": None}, "not_checked: give the reason"),
                      ({"holds": True, "not_checked": "x"}, "not_checked: give the reason"),
                      ({"holds": True, "basis": "assumed"}, "basis: expected one of"),
                      ({"holds": True, "decides": 1}, "decides must be a bool"),
                      ({"holds": True, "runs": 0}, "runs: expected a run count >= 1"),
                      ({"holds": True, "decides": True, "basis": "by-construction"},
                       "holds by construction is no evidence"),
                      ({"holds": True, "decides": True, "source": "ours (Remark 4)"},
                       "a claim of ours cannot decide")]:
        holds = kw.pop("holds")
        with pytest.raises(ValidationError, match=match):
            results.claim("p", "c", 1.0, 1.0, holds, **kw)


def _decided(holds: bool, verdict: str | None = None, **kw) -> dict:
    e = results.claim("p", "c", 1.0, 1.0, holds, decides=True, **kw)
    if verdict is not None:
        e["verdict"] = verdict
    return e


def test_rescience_verdict_rule() -> None:
    ok, bad = _decided(True), _decided(False)
    extra = results.claim("p", "c", 1.0, 1.0, False)  # does not decide
    built = results.claim("p", "c", 1.0, 1.0, False, basis="by-construction")
    assert results.rescience_verdict({"C1": ok, "C2": ok, "X1": extra, "X2": built})["verdict"] == "[Re]"
    part = results.rescience_verdict({"C10": ok, "C2": _decided(True, "undetermined")})
    assert part["verdict"] == "[Re, partial]"
    assert part["line"] == "[Re, partial]: C2 holds at the example, undetermined over the space; C10 holds"
    assert results.rescience_verdict({"C1": ok, "C2": bad})["verdict"] == "[Re, partial]"
    premise = _decided(True, premise=("A1", False))
    assert results.rescience_verdict({"C1": bad, "C2": premise})["verdict"] == "[¬Re]"
    assert results.rescience_verdict({"C1": _decided(None, not_checked="solver")})["verdict"] == "[¬Re]"
    with pytest.raises(ValidationError, match="no claim has decides=True"):
        results.rescience_verdict({"C1": extra, "X2": built})


def test_write_claims_gives_claims_of_ours_x_ids(tmp_path) -> None:
    ours = results.claim("p", "c", 1.0, 1.0, True, source="ours; a rule of ours")
    results.write_claims(tmp_path / "claims.json", {"X1": ours})
    with pytest.raises(ValidationError, match="claim C2b: a claim of ours .* takes an X id"):
        results.write_claims(tmp_path / "claims.json", {"C2b": ours})


def test_write_claims_merges_the_sweep_verdict(tmp_path) -> None:
    c = results.claim("p", "c", 1.0, 1.0, True, source="Sec. V")
    summary = {"C1": {"verdict": "undetermined", "fraction_holds": 0.5, "points": 4}}
    (tmp_path / "robustness.json").write_text(json.dumps(summary))
    path = results.write_claims(tmp_path / "claims.json", {"C1": c, "C2": c},
                                robustness=tmp_path / "robustness.json")
    out = json.loads(path.read_text())
    assert out["C1"]["verdict"] == "undetermined" and out["C1"]["robustness"]["points"] == 4
    assert out["C2"]["verdict"] == "holds" and "robustness" not in out["C2"]
    missing = results.write_claims(tmp_path / "c2.json", {"C1": c}, robustness=tmp_path / "none.json")
    assert json.loads(missing.read_text())["C1"]["verdict"] == "holds"


def test_claim_bad_input(tmp_path) -> None:
    with pytest.raises(ValidationError, match="holds must be a bool or None, found int"):
        results.claim("p", "c", 1.0, 1.0, 1)
    with pytest.raises(ValidationError, match="paper must be a non-empty string"):
        results.claim("", "c", 1.0, 1.0, True)
    with pytest.raises(ValidationError, match="claim values must be finite"):
        results.claim("p", "c", float("nan"), 1.0, True)
    with pytest.raises(ValidationError, match="claim values must be finite"):
        results.claim("p", "c", float("inf"), 1.0, True)
    with pytest.raises(ValidationError, match="source must be a non-empty string"):
        results.claim("p", "c", 1.0, 1.0, True, source="")
    with pytest.raises(ValidationError, match="key 'x' must name an entry"):
        results.claim("p", "c", {"y": 1.0}, 1.0, True, key="x")
    with pytest.raises(ValidationError, match="premise must be a"):
        results.claim("p", "c", 1.0, 1.0, True, premise=("a", "yes"))
    with pytest.raises(ValidationError, match="interval must come from results.interval"):
        results.claim("p", "c", 1.0, 1.0, True, interval={"low": 0})
    with pytest.raises(ValidationError, match="tolerance must be a results.Tolerance"):
        results.claim("p", "c", 1.0, 1.0, True, tolerance=1e-3)
    with pytest.raises(ValidationError, match="rtol must be a real number >= 0"):
        results.Tolerance(rtol=-1.0, atol=0.0, reason="x")
    with pytest.raises(ValidationError, match="reason must be a non-empty string"):
        results.Tolerance(rtol=0.0, atol=0.0, reason=" ")
    with pytest.raises(ValidationError, match="interval must be finite with low <= high"):
        results.interval(1.0, 0.0, method="t")
    good = results.claim("p", "c", 1.0, 1.0, True)
    with pytest.raises(ValidationError, match="claim id 'claim1' must look like 'C1'"):
        results.write_claims(tmp_path / "c.json", {"claim1": good})
    with pytest.raises(ValidationError, match=r"claim C2 lacks keys \['tolerance'\]"):
        results.write_claims(tmp_path / "c.json", {"C2": {k: 1 for k in results.REQUIRED_KEYS[:-1]}})


def test_resolve_and_declared_parameters() -> None:
    assert results.resolve("figures/x") == results.repo_root() / "figures" / "x"
    assert results.resolve("/tmp/x").as_posix() == "/tmp/x"
    declared = results.declared_parameters("lee2020")
    assert declared["mode"] == '"paper"'


def test_run_manifest_written(toy, monkeypatch) -> None:
    from secest.repro import spaces

    monkeypatch.setattr(results, "repo_root", lambda: toy)
    monkeypatch.setattr(spaces, "_root", lambda: toy)
    run = results.Run("toy", {"mode": "fast", "T": 25})
    path = run.finish(solver="CLARABEL", extra={"steps": np.int64(3)})
    manifest = json.loads(path.read_text())
    assert path.name == "toy.fast.json"
    assert manifest["parameters"]["mode"] == "fast" and manifest["parameters"]["T"] == 25
    assert manifest["parameters"]["scale"] == 0.15  # defaults recorded too
    assert manifest["solver"] == "CLARABEL" and manifest["extra"] == {"steps": 3}
    assert manifest["wall_time_s"] >= 0 and "numpy" in manifest["versions"]
    with pytest.raises(ValidationError, match="parameter T must be an integer >= 1, found 0"):
        results.Run("toy", {"T": 0})  # a notebook run by papermill directly is checked too


def test_parameter_cell_parse_failure_is_an_error(tmp_path, monkeypatch) -> None:
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "language": "python", "display_name": "py"}
    cell = nbformat.v4.new_code_cell('mode = "paper"\nx = 1  # the value = one\n')
    cell.metadata["tags"] = ["parameters"]
    nb.cells = [cell]
    path = tmp_path / "bad.ipynb"
    nbformat.write(nb, path)
    monkeypatch.setattr(results, "notebook_path", lambda key: path)
    with pytest.raises(ValidationError, match="papermill cannot parse a line"):
        results.declared_parameters("bad")


def test_environment_summary_uses_repo_relative_paths() -> None:
    text = results.environment_summary()
    assert text.startswith("python: ") and "secest: <repo>/secest/__init__.py" in text


def test_strip_coalesces_split_streams() -> None:
    from nbformat.v4 import new_output

    from secest.repro.build import _coalesce_streams

    outs = [new_output("stream", name="stdout", text="a\n"), new_output("stream", name="stdout", text="b\n"),
            new_output("stream", name="stderr", text="w\n"), new_output("stream", name="stdout", text="c\n")]
    merged = _coalesce_streams(outs)
    assert [o["text"] for o in merged] == ["a\nb\n", "w\n", "c\n"]


# ---------------------------------------------------------------- remaining bad-input cases


def test_graph_helpers_reject_bad_adjacency() -> None:
    with pytest.raises(ValidationError, match="graph must be a networkx Graph or DiGraph, found ndarray"):
        graphs.adjacency(np.eye(2))
    with pytest.raises(ValidationError, match="adj must contain only 0 and 1 entries"):
        graphs.neighbours([[0, 0.5], [0.5, 0]])
    with pytest.raises(ValidationError, match=r"adj must be a square matrix, found shape \(2, 3\)"):
        graphs.laplacian(np.zeros((2, 3)))
    with pytest.raises(ValidationError, match="adj must have a zero diagonal"):
        graphs.row_stochastic_weights(np.eye(2))


def test_min_eig_and_ci_bad_input() -> None:
    assert np.allclose(covariance.min_eig(np.stack([np.eye(2), 2 * np.eye(2)])), [1.0, 2.0])
    with pytest.raises(ValidationError, match="P must be square in its last two axes"):
        covariance.min_eig(np.zeros(3))
    with pytest.raises(ValidationError, match=r"covariances\[0\] must be symmetric"):
        covariance.covariance_intersection([np.zeros(2)], [[[1.0, 1.0], [0.0, 1.0]]])


def test_build_steps(tmp_path, monkeypatch) -> None:
    from secest.repro import build

    with pytest.raises(ValidationError, match="key 'nope' names no notebook source"):
        build.build_ipynb("nope")
    assert build.check_manifest(["lee2020"]) == []
    with pytest.raises(ValidationError, match=r"figures/manifest.toml has no \[nope\] table"):
        build.check_manifest(["nope"])
    (tmp_path / "figures" / "k").mkdir(parents=True)
    (tmp_path / "figures" / "k" / "old.png").write_bytes(b"x")
    (tmp_path / "figures" / "k" / "claims.json").write_text("{}")
    (tmp_path / "figures" / "manifest.toml").write_text(
        '[k]\nnotebook = "n"\n[[k.figures]]\nfiles = ["figures/k/old.png"]\nstatus = "ours"\n')
    monkeypatch.setattr(build, "repo_root", lambda: tmp_path)
    assert build.check_manifest(["k"]) == []
    assert [p.name for p in build.prepare_figures("k")] == ["old.png"]
    assert build.check_manifest(["k"]) == ["figures/k/old.png"]
    assert (tmp_path / "figures" / "k" / "claims.json").exists()
    assert build.main(["manifest", "k"]) == 1 and build.main(["bogus"]) == 2


def test_run_cli_parses_values_by_declared_type(monkeypatch) -> None:
    from secest.repro import run

    seen = {}
    monkeypatch.setattr(run, "execute_notebook",
                        lambda key, params, out=None: seen.update(key=key, params=params, out=out))
    assert run.main(["lee2020", "-p", "gamma", "2.5", "-p", "mode", "fast", "-p", "z", "[1, 2]",
                     "--in-place"]) == 0
    assert seen == {"key": "lee2020", "params": {"gamma": 2.5, "mode": "fast", "z": [1, 2]}, "out": None}
    assert run.main(["ding2020", "-p", "strict", "false", "--output", "/tmp/x/d.ipynb"]) == 0
    assert seen["params"]["strict"] is False and str(seen["out"]) == "/tmp/x/d.ipynb"
    assert seen["params"]["fig_dir"] == "/tmp/x/figures"  # never over the committed figures


# ---------------------------------------------------------------- confidence intervals


def test_wilson_interval_known_values() -> None:
    lo, hi = montecarlo.wilson_interval(0, 300)
    assert lo == 0.0 and hi == pytest.approx(0.01263, abs=2e-5)
    lo, hi = montecarlo.wilson_interval(45, 300)  # 15 %
    assert lo == pytest.approx(0.1141, abs=1e-3) and hi == pytest.approx(0.1951, abs=1e-3)
    lo, hi = montecarlo.wilson_interval(10, 10)
    assert hi == 1.0 and lo == pytest.approx(0.7225, abs=1e-3)


def test_mean_and_bootstrap_intervals_cover_the_mean() -> None:
    rng = np.random.default_rng(1)
    x = rng.normal(2.0, 1.0, 400)
    lo, hi = montecarlo.mean_interval(x)
    assert lo < x.mean() < hi and hi - lo == pytest.approx(2 * 1.966 * x.std(ddof=1) / 20, rel=1e-3)
    blo, bhi = montecarlo.bootstrap_interval(x)
    assert blo < x.mean() < bhi and abs((bhi - blo) - (hi - lo)) < 0.05
    pairs = np.column_stack([2 * x, x])
    rlo, rhi = montecarlo.bootstrap_interval(pairs)
    assert rlo == pytest.approx(2.0) and rhi == pytest.approx(2.0)


def test_interval_bad_input() -> None:
    with pytest.raises(ValidationError, match=r"successes must lie in \[0, n\]"):
        montecarlo.wilson_interval(5, 3)
    with pytest.raises(ValidationError, match="successes must be an integer"):
        montecarlo.wilson_interval(0.5, 3)
    with pytest.raises(ValidationError, match="samples must hold at least 2 finite values"):
        montecarlo.mean_interval([1.0])
    with pytest.raises(ValidationError, match=r"statistic must be one of \('mean', 'median'\), found 'max'"):
        montecarlo.bootstrap_interval([1.0, 2.0], "max")
    with pytest.raises(ValidationError, match=r"samples must have shape \(runs,\) or \(runs, 2\)"):
        montecarlo.bootstrap_interval(np.ones((3, 3)))


def test_figures_switched_off_write_nothing(tmp_path) -> None:
    plotting.setup(enabled=False)
    try:
        fig, ax = plt.subplots()
        ax.plot([0, 1], [0, 1])
        assert plotting.save_figure(fig, tmp_path, "fig1_demo", data={"t": [0, 1]}) is None
        assert plotting.save_data(tmp_path, "tbl", {"t": [0, 1]}) is None
        assert not plt.fignum_exists(fig.number) and not any(tmp_path.iterdir())
        with pytest.raises(ValidationError, match=r"data\['y'\] has 1 rows"):  # still validated
            plotting.save_figure(plt.figure(), tmp_path, "f", data={"x": [1, 2], "y": [1]})
    finally:
        plotting.setup(enabled=True)
    with pytest.raises(ValidationError, match="enabled must be a bool"):
        plotting.setup(enabled="no")
    plt.close("all")
