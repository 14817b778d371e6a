"""ding2020: papermill fast-mode execution, claims asserted against the paper and the brief.

Thresholds are those of the reproduction brief (shared/briefs/ding2020.md, section 6). A claim
that does not hold in our reproduction (C2a, C8a, X1, X2) is asserted as measured-false.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from secest import filters

pytestmark = pytest.mark.xdist_group("ding2020")

ATTACKED = ("sensor4", "sensor12")


@pytest.fixture(scope="module")
def claims(run_notebook):
    return run_notebook("ding2020")


def test_c1_every_attacked_sample_rejected_and_no_false_alarm(claims) -> None:
    c = claims["C1"]["measured"]
    assert c["default_attacked_samples"] == 12
    assert c["default_rejected_in_windows"] == 12
    assert c["default_rejections_elsewhere"] == 0
    assert min(c["mc_reject_rate_window"][s] for s in ATTACKED) >= 0.99
    assert claims["C1"]["holds"] is True


def test_c2a_node20_leak_reported_over_topologies(claims) -> None:
    c = claims["C2a"]["measured"]
    by_top = c["sensor20_by_topology"]
    assert len(by_top) == c["topologies"] >= 10
    assert str(c["default_topology_seed"]) in by_top
    assert by_top[str(c["default_topology_seed"])]["leak"] == pytest.approx(c["sensor20_default"])
    assert min(c["hops_sensor20_default"]) == by_top[str(c["default_topology_seed"])]["hops"]
    assert all(v["hops"] >= 1 for v in by_top.values())
    # a direct neighbour of an attacked sensor is never unaffected in the 1e-3 sense
    assert all(v["leak"] > 1e-3 for v in by_top.values() if v["hops"] == 1)
    n_ok = sum(v["leak"] <= 1e-3 for v in by_top.values())
    assert c["topologies_sensor20_le_1e-3"] == n_ok
    # the paper's statement holds only if node 20 stays below 1e-3 in every stand-in topology
    assert claims["C2a"]["holds"] is (n_ok == len(by_top))
    assert claims["C2a"]["holds"] is False  # measured-false: node 20 is a direct neighbour in some


def test_c2b_leak_decays_with_hop_distance(claims) -> None:
    by_hops = claims["C2b"]["measured"]["by_hops"]
    keys = sorted(by_hops, key=int)
    assert keys[0] == "1" and len(keys) >= 3
    medians = [by_hops[h]["median"] for h in keys]
    maxima = [by_hops[h]["max"] for h in keys]
    assert all(a >= 10 * b for a, b in zip(medians[:-1], medians[1:], strict=True))  # our criterion: 10x per hop
    assert maxima == sorted(maxima, reverse=True)
    assert by_hops["1"]["min"] > 1e-3  # every direct neighbour is affected
    assert 0.03 <= by_hops["1"]["max"] <= 1.0  # ... by up to a sizeable fraction of the RMSE
    assert all(by_hops[h]["max"] <= 2e-3 for h in keys if int(h) >= 3)
    assert all(by_hops[h]["fraction_le_1e-3"] == 1.0 for h in keys if int(h) >= 4)
    assert claims["C2b"]["holds"] is True


def test_c3_mild_effect_with_detection(claims) -> None:
    c = claims["C3"]["measured"]
    assert max(c["mc_median_ratio"][s] for s in ATTACKED) <= 3.0
    assert max(c["default_max_abs_error"][s] for s in ATTACKED) <= 2.0
    assert claims["C3"]["holds"] is True


def test_c4_no_inspection_degrades(claims) -> None:
    c = claims["C4"]["measured"]
    assert min(c["default_ratio_vs_A"][s] for s in ATTACKED) >= 5.0
    assert min(c["mc_p05_ratio_vs_B"][s] for s in ATTACKED) >= 2.5
    assert claims["C4"]["holds"] is True


def test_c5_bounds_against_exact_covariance(claims) -> None:
    c = claims["C5"]["measured"]
    assert c["case_a_all_accepted"] is True
    assert c["mc_runs_all_accepted"] >= 0.95 * c["mc_runs"]  # false alarms are rare
    assert c["min_eig_Pi_minus_P_rel"] >= -1e-9
    assert c["min_eig_P_minus_Gamma_rel"] >= -1e-9
    assert c["median_trPi_over_trP"] > 1.0  # conservative upper bound
    assert c["mc_median_rel_frobenius_error"] <= 0.12 * np.sqrt(300 / c["mc_runs_all_accepted"])
    assert claims["C5"]["holds"] is True


def test_c6_channel_rates(claims) -> None:
    c = claims["C6"]["measured"]
    assert c["chain_steps"] >= 100_000
    assert abs(c["p_hat"] - 0.1) <= 0.005
    assert abs(c["q_hat"] - 0.92) <= 0.015
    assert abs(c["fraction_ones"] - 0.92 / 1.02) <= 0.005
    assert claims["C6"]["holds"] is True


def test_c8a_theorem4_condition_fails_for_the_example(claims) -> None:
    c = claims["C8a"]["measured"]
    # independent evaluation of (42)-(43) for the example
    T = 0.05
    A = np.array([[1, T, T**2 / 2], [0, 1, T], [0, 0, 1.0]])
    alpha2 = np.linalg.norm(A, 2) ** 2
    c_lo2, c_hi2 = 4.0**2 + 0.8**2 + 1.0**2, 4.5**2 + 0.8**2 + 0.5**2
    sigma = stats.chi2.sf(25.0, 1)
    zeta = (c_lo2 + c_hi2 * (1 - sigma)) / c_lo2
    assert zeta * alpha2 == pytest.approx(2.35948, abs=1e-5)
    assert c["zeta_alpha2"] == pytest.approx(zeta * alpha2)
    kappa, p, q, n_bar = 0.004, 0.1, 0.92, c["N_bar"]
    for form, f in (("printed", 1.0), ("factor2", 2.0)):
        bracket = (1 + kappa) * (1 + f * kappa * n_bar)
        assert c["xi"][form]["xi_q"] == pytest.approx(zeta * alpha2 * (1 - q + q * bracket))
        assert c["xi"][form]["xi_p"] == pytest.approx(zeta * alpha2 * (p + (1 - p) * bracket))
        assert c["xi"][form]["xi_q"] > 1 and c["xi"][form]["xi_p"] > 1
    assert claims["C8a"]["holds"] is False  # measured-false: the sufficient condition fails


def test_c8b_pi_bounded_over_long_run(claims) -> None:
    c = claims["C8b"]["measured"]
    assert c["steps"] >= 600
    assert c["max_trPi_second_half"] <= 1.5 * c["max_trPi_first_half"]
    assert claims["C8b"]["holds"] is True


def test_c9_constant_gain_comparison(claims) -> None:
    c = claims["C9"]["measured"]
    for s in ("sensor4", "sensor12", "sensor20"):
        assert 0.8 <= c["overall_ratio_const_vs_proposed"][s] <= 1.6
    assert min(c["window_ratio_const_B_vs_A"][s] for s in ATTACKED) >= 5.0
    assert claims["C9"]["holds"] is True


def test_c10_vectorised_equals_per_node(claims) -> None:
    assert claims["C10"]["measured"] <= 1e-10
    assert claims["C10"]["holds"] is True


def test_x1_lockout_is_reported_and_does_not_hold(claims) -> None:
    c = claims["X1"]["measured"]
    locked = [c["locked_at_end"][s] for s in ATTACKED]
    after = [c["any_reject_after_window"][s] for s in ATTACKED]
    assert max(locked) > 0.0  # measured-false: the paper's scheme locks out
    assert all(0.0 <= lk <= a <= 0.5 for lk, a in zip(locked, after, strict=True))
    assert claims["X1"]["holds"] is False


def test_x2_pi_ablation_is_not_a_fix_by_our_criterion(claims) -> None:
    c = claims["X2"]["measured"]
    locked = max(c[s]["locked_at_end"] for s in ATTACKED)
    rate = min(c[s]["reject_rate_window"] for s in ATTACKED)
    assert c["removes_lockout"] is (locked == 0.0)
    assert c["keeps_detection"] is (rate >= 0.99)
    assert claims["X2"]["holds"] is (locked == 0.0 and rate >= 0.99)
    assert locked == 0.0  # the Pi-normalised test does not lock out ...
    assert rate < 0.99  # ... but lets attacked samples through
    assert claims["X2"]["holds"] is False


def test_figures_and_data_written(claims) -> None:
    fig_dir = Path(claims["_fig_dir"])
    for name in ("fig1_topology", "fig2_channel_state", "fig3_measurements_attack",
                 "fig4a_estimates_case_a", "fig4b_estimates_case_b",
                 "fig4c_estimates_no_inspection", "fig5_measurements_comparison",
                 "fig6a_constant_gain_case_a", "fig6b_constant_gain_case_b",
                 "extra_bound_consistency", "extra_lockout_rate", "extra_pi_long_run",
                 "extra_leak_by_hop"):
        assert (fig_dir / f"{name}.png").stat().st_size > 10_000, name
        assert (fig_dir / f"{name}.csv").exists(), name
    header = (fig_dir / "fig4b_estimates_case_b.csv").read_text().splitlines()[0]
    assert header == "k,x1,xhat4,xhat12,xhat20"


def _example():
    T = 0.05
    A = np.array([[1, T, T**2 / 2], [0, 1, T], [0, 0, 1.0]])
    m = 20
    C = np.array([[4.5, -0.8, -0.5] if i < 7 else [4.0, -0.8, 1.0] for i in range(m)])
    return A, 0.04 * np.eye(3), C, 0.0025


def test_kappa0_no_inspection_equals_textbook_kalman_filter() -> None:
    """With kappa = 0, no inspection and no attack, every node is a Kalman filter (to 1e-10)."""
    A, Q, C, R = _example()
    m, n, steps = C.shape[0], 3, 150
    rng = np.random.default_rng(7)
    adj = (rng.random((m, m)) < 0.3).astype(float)
    adj = np.triu(adj, 1)
    adj = adj + adj.T
    adj[np.arange(m), (np.arange(m) + 1) % m] = 1.0  # every node has a neighbour
    np.fill_diagonal(adj, 0.0)
    H = adj / adj.sum(axis=1, keepdims=True)
    delta = rng.integers(0, 2, steps)
    x = rng.standard_normal(n)
    xs, ys = [], []
    for _ in range(steps):
        x = A @ x + np.sqrt(Q[0, 0]) * rng.standard_normal(n)
        xs.append(x)
        ys.append(C @ x + np.sqrt(R) * rng.standard_normal(m))
    x_post = rng.standard_normal((m, n))
    Pi = np.broadcast_to(2 * np.eye(n), (m, n, n)).copy()
    Gam = Pi.copy()
    # textbook Kalman filter, one per node, written independently of secest
    kf_x = x_post.copy()
    kf_P = Pi.copy()
    worst = 0.0
    for k in range(steps):
        st = filters.secure_filter_step(
            x_post, Pi, Gam, delta[k], ys[k][:, None], A=A, BBt=Q, C=C[:, None, :],
            DDt=np.array([[R]]), adj=adj, weights=H, kappa=0.0, threshold=25.0, inspect=False)
        x_post, Pi, Gam = st.x_post, st.Pi_post, st.Gamma_post
        for i in range(m):
            xp = A @ kf_x[i]
            Pp = A @ kf_P[i] @ A.T + Q
            S = C[i] @ Pp @ C[i] + R
            gain = Pp @ C[i] / S
            kf_x[i] = xp + gain * (ys[k][i] - C[i] @ xp)
            kf_P[i] = Pp - np.outer(gain, C[i] @ Pp)
        worst = max(worst, float(np.abs(x_post - kf_x).max()))
        assert np.allclose(Pi, kf_P, rtol=0, atol=1e-10)
    assert worst <= 1e-10
