"""li2025: fast-mode executions of the notebook; measured values, identities and consistency.

Tests measure, they do not vote: a claim whose outcome depends on a MISSING value (the
horizon, the weights, the E{xhat xhat^T} surrogate, the attack signal) is checked for the
consistency of measured / threshold / holds / verdict and for its measured numbers at the
default point, never for a required outcome. Exact statements (the corrected bound, the
Kalman limit, the RRL-MAP counts, identities at psi_check = 1) are asserted as such.
"""

from __future__ import annotations

import csv
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import perturbation_point
from papermill.exceptions import PapermillExecutionError

from secest.core.validation import ValidationError
from secest.repro.results import point_verdict, repo_root, rescience_verdict
from secest.repro.run import execute_notebook

ROOT = repo_root()
FIG = ROOT / "figures" / "li2025"
NO_ATTACK = {"psi_check": [1.0, 1.0, 1.0], "T": 30}
CLAIM_IDS = {"C1b", "C1c", "C2", "C3", "C3a", "C3b", "C4", "C5", "C7", "C8", "C8b", "X1", "X2", "X3",
             "X4", "X5", "X6", "X7", "X8", "X9"}


@pytest.fixture(scope="module")
def claims(run_notebook):
    """The default point, figures off (they are checked at the no-attack point)."""
    return run_notebook("li2025", figures=False)


@pytest.fixture(scope="module")
def no_attack(run_notebook):
    """psi_check = 1 for every target (a PAPER value changed by a reader), short horizon: the
    first perturbation point of notebooks/li2025.toml (tests/test_notebooks.py shares the run)."""
    return run_notebook("li2025", **perturbation_point("li2025", **NO_ATTACK))


def _consistent(entry: dict) -> None:
    assert entry["holds"] is None or isinstance(entry["holds"], bool)
    point = point_verdict(entry)
    rob = entry.get("robustness")
    if rob is None:
        assert entry["verdict"] == point
    else:
        assert entry["verdict"] == rob["verdict"]
        frac = rob["fraction_holds"]
        if rob["verdict"] == "undetermined":
            assert 0.0 < frac < 1.0 or len({k for k, v in rob["outcomes"].items() if v}) > 1
        elif rob["verdict"] == "holds":
            assert frac == 1.0 and entry["holds"] is True
        elif rob["verdict"] in ("fails-premise", "not-checked"):  # no point decided: no fraction
            assert frac is None and point == rob["verdict"]
        else:
            assert frac == 0.0 and point == rob["verdict"]


def test_every_claim_has_source_section_and_a_consistent_verdict(claims) -> None:
    assert CLAIM_IDS <= set(claims)
    for cid in CLAIM_IDS:
        entry = claims[cid]
        assert entry["source"] and entry["section"], cid
        _consistent(entry)


def _tolerance(entry: dict, value: float) -> float:
    tol = entry["tolerance"]
    return tol["atol"] + tol["rtol"] * abs(value)


def test_x5_corrected_bound_is_certified_exactly(claims) -> None:
    """Corrected Theorem 1 with deterministic gains: S_i(k|k) >= P_i(k) at every k (a theorem)."""
    x5 = claims["X5"]
    m = x5["measured"]
    assert x5["source"].startswith("ours") and not x5.get("decides")
    assert x5["key"] == "max_share" and x5["threshold"] == 1 + 1e-9
    shares = m["max_share_per_scenario"]
    assert set(shares) == {"paper psi_check", "psi_check = 1", "psi_check = 0.99",
                           "psi_check = 0.9", "psi_check = 0.5", "psi_check = 0.3"}
    assert m["max_share"] == max(max(v) for v in shares.values()) <= 1 + 1e-9
    assert all(min(v) >= -1e-9 for v in m["min_eig_S_minus_P_per_scenario"].values())
    # without attack the corrected bound is nearly tight (the Kalman recursion inflated by lambda)
    assert min(shares["psi_check = 1"]) > 0.99
    assert min(m["min_trS_over_trP_k5"]) > 1.0
    # margin-aware: the scenarios within the tolerance of the level are tight, the others decide
    level = x5["threshold"]
    tight = {n for n, v in shares.items() if abs(max(v) - level) <= _tolerance(x5, max(v))}
    assert set(m["tight_scenarios"]) == tight == {"psi_check = 1"}
    decided = [max(v) for n, v in shares.items() if n not in tight]
    assert m["max_share_decided"] == max(decided)
    assert x5["holds"] is all(v <= level for v in decided)
    assert m["old_rule_holds"] is (m["max_share"] <= level)


def test_c1c_printed_fig7_rule_on_intervals(claims) -> None:
    c = claims["C1c"]
    iv, m = c["interval"], c["measured"]
    assert not c["source"].startswith("ours")
    assert iv["low"] <= m["worst_cell_relative_margin"] <= iv["high"]
    assert iv["level"] == pytest.approx(1 - 0.05 / (3 * 100))
    assert c["holds"] is (iv["high"] >= 0)
    assert (m["cells_below_zero"] > 0) is (iv["high"] < 0)
    # default point: the printed 'bound' lies wholly below the MSE at most cells
    assert m["cells"] == 300 and m["cells_below_zero"] == 280


def test_x6_monte_carlo_rule_on_intervals(claims) -> None:
    c = claims["X6"]
    iv, m = c["interval"], c["measured"]
    assert c["source"].startswith("ours")
    assert iv["low"] <= m["worst_cell_relative_margin"] <= iv["high"]
    assert iv["level"] == pytest.approx(1 - 0.05 / (3 * 100))
    assert c["holds"] is (iv["high"] >= 0)
    assert 1 <= m["worst_cell_k"] <= 100 and 1 <= m["worst_cell_target"] <= 3
    # default point: the mean bound is 4-28 times the MSE past k = 5
    assert m["min_trS_over_mse_k5"] == pytest.approx([3.98, 9.57, 28.1], rel=0.01)


def test_c1b_printed_coefficients_measured(claims) -> None:
    c = claims["C1b"]
    m = c["measured"]
    assert abs(m["max_share"] - (1 + 1e-9)) > _tolerance(c, m["max_share"])  # decided robustly
    assert c["holds"] is (m["max_share"] <= 1 + 1e-9)
    # Theorem 1's premise: positive-definite solutions of (17)-(18) at every k
    assert c["premise"]["holds"] is (m["min_eig_S"] is not None and m["min_eig_S"] > 0)
    # default weights: an exact counterexample from k = 2 on, the 'bound' 1e3-3e5 times too small
    assert m["max_share_per_target"] == pytest.approx([2869.6, 18319.7, 336498.6], rel=1e-4)
    assert m["first_violating_k"] == [2, 2, 2]
    assert max(m["max_share_alpha2_gt_alpha3"]) <= 1.0
    assert all(r < 0.01 for r in m["trS_over_mse_exact"])
    # the two printed errors apart, same weights: the printed c0 with the derived kappa's, and the
    # derived c0 with the printed kappa_x (its bound overflows float64 after k = 58: max over finite steps)
    split = m["one_printed_coefficient"]
    c0_only, kx_only = split["printed c0, corrected kappa_x"], split["corrected c0, printed kappa_x"]
    assert c0_only["last_finite_k"] == 100 and kx_only["last_finite_k"] == 58
    assert c0_only["max_share"] == pytest.approx([2829.18, 18276.68, 334974.69], rel=1e-4)
    assert kx_only["max_share"] == pytest.approx([0.7675, 0.5612, 0.3793], abs=1e-4)


def test_c2_decided_on_informative_targets_only(claims) -> None:
    c = claims["C2"]
    m = c["measured"]
    informative = [g >= 0.01 for g in m["gain_share"]]
    assert m["informative"] == informative
    for i, status in enumerate(m["status"]):
        lo, hi = m["interval_low"][i], m["interval_high"][i]
        assert lo <= m["ratio"][i] <= hi
        if not informative[i]:
            assert status.startswith("undetermined")
        else:
            assert status == ("fails (ZOH better)" if hi < 1 else "holds")
    assert c["premise"]["holds"] is any(informative)
    expected = any(informative) and all(
        m["interval_high"][i] >= 1 for i in range(3) if informative[i])
    assert c["holds"] is expected
    # default point: only target 1 has a non-negligible gain
    assert informative == [True, False, False]
    assert m["decisive_target"] == 1
    assert m["ratio"][0] == pytest.approx(1.0735, abs=1e-3)


def test_c3_theorem3_premise_and_vacuous_envelope(claims) -> None:
    a, b, x7 = claims["C3a"], claims["C3b"], claims["X7"]
    # Assumption 1 needs full-rank E E^T and (sum B)(sum B)^T: E_i is 4 x 1, sum B has two zero rows
    assert a["measured"]["rank_E_Et_max"] == 1
    assert a["measured"]["rank_Bsum_Bsum_t_per_target"] == [0, 2, 2]
    assert a["premise"]["holds"] is False and a["verdict"] == "fails-premise"
    # C3a reads Assumption 1's empty sum over K_1 = {} as C3 does (b_* = b^* = 0): the b-condition is
    # asked only of targets with upstream subsystems (2, 3); E E^T of rank 1 fails the premise alone
    assert "empty K_i" in a["premise"]["statement"] and "empty-sum" in claims["C3"]["premise"]["statement"]
    ranks_b = a["measured"]["rank_Bsum_Bsum_t_per_target"]
    assert a["premise"]["holds"] is (a["measured"]["rank_E_Et_max"] == 4
                                     and all(r == 4 for r in ranks_b[1:]))
    assert not a.get("decides")  # a failed premise on the example does not decide Theorem 3
    # Theorem 3 decides on our declared instance; the example's evaluation (C3a) does not
    c3 = claims["C3"]
    assert c3["decides"] and c3["basis"] == "measured"
    assert c3["measured"]["example_rank_E_Et_max"] == a["measured"]["rank_E_Et_max"]
    # (36) asks Gamma_* I <= L Phi C H with Gamma_* > 0: the rank is at most m = 2 < 4
    assert a["measured"]["max_rank_L_Phi_C_H"] <= 2
    rows = a["measured"]["printed_weights_in_use"]
    search = x7["measured"]["search"]
    met_in_use = [x and y for x, y in zip(rows["a_alpha56_exist"], rows["bc_pair_on_grid"], strict=True)]
    assert a["measured"]["conditions_met_at_weights_in_use"] == met_in_use
    assert a["holds"] is all(met_in_use)
    met = [u or n > 0 for u, n in zip(met_in_use, search["all_conditions"], strict=True)]
    assert x7["holds"] is not any(met) and x7["measured"]["all_targets_met"] is all(met)
    assert x7["source"].startswith("ours") and not x7.get("decides")
    assert search["all_conditions"] == x7["measured"]["search_weight_sets_meeting_all"]
    assert all(n <= m for n, m in zip(search["all_conditions"], search["all_conditions_pi_ignored"],
                                      strict=True))
    # the weight-free floor (a proof): no searched weight set with kappa_x >= 0 gets below it
    for floor, ratio in zip(search["floor_kappa_x_nonnegative"],
                            search["min_ratio_kappa_x_nonnegative"], strict=True):
        assert floor is not None and (ratio is None or ratio >= floor)
    assert b["premise"]["holds"] is (a["premise"]["holds"] and x7["measured"]["all_targets_met"])
    assert b["holds"] is None if not b["premise"]["holds"] else isinstance(b["holds"], bool)
    m = b["measured"]
    ratios = [r for r in m["UB_T_over_max_mse"] if r is not None]
    assert ratios and min(ratios) > 1e9  # the data-driven envelope is vacuous where defined
    lam = np.array([1e-3, 1e-2, 1e-2])
    np.testing.assert_allclose(m["rho"], lam / (1 + lam), rtol=1e-10)  # claims carry 11 digits


def test_c3_theorem3_on_our_instance(claims) -> None:
    """C3 on the declared instance: the measured ratio, its decision, the reported proof steps."""
    c = claims["C3"]
    m = c["measured"]
    # the instance and the search are fixed (no parameter of the declared space enters them)
    assert m["weight_sets_searched"] == 4096
    assert m["eligible_weight_sets"] == 38 and m["eligible_cases"] == 7719
    np.testing.assert_allclose(m["X_star_sq"], [3.0, 3.0], rtol=1e-9)
    assert m["max_ratio"] == pytest.approx(0.08612, rel=1e-3)
    assert m["max_ratio_subsystem2"] <= m["max_ratio"]
    assert c["threshold"] == 1.0
    assert abs(m["max_ratio"] - 1.0) > _tolerance(c, m["max_ratio"])
    # the old precondition (until session 14, kept as a record): an informative gain (C2's level)
    level = m["informative_level"]
    assert level == 0.01  # C2's gain_negligible
    informative = m["max_gain_share"] >= level and m["max_error_reduction"] >= level
    assert m["gain_informative"] is informative
    # the re-review's weight set: in the declared box, eligible, with an informative gain (measured)
    rev = m["reviewer_set"]
    assert rev["weights"] == [1.115, 1.305, 14.916, 14.914, 0.0072] and rev["in_declared_box"]
    assert rev["eligible_pairs"] == [42, 42]
    np.testing.assert_allclose(rev["gain_share"], [0.0589, 0.0403], rtol=2e-3)
    np.testing.assert_allclose(rev["error_reduction"], [0.0708, 0.0450], rtol=2e-3)
    np.testing.assert_allclose(rev["max_ratio"], [9.326e-5, 1.7374e-4], rtol=1e-3)
    np.testing.assert_allclose(rev["max_ratio_zero_gain"], [1.0036e-4, 1.8006e-4], rtol=1e-3)
    assert rev["old_precondition_holds"] is all(v >= level for v in rev["gain_share"] + rev["error_reduction"])
    # the precondition (restated in session 14, part of C3's premise, CONVENTIONS point 6): the
    # measurement discriminates, L = 0 violates the envelope at some eligible case, searched or the
    # re-review's; where it fails, fails-premise
    worst0 = max([m["max_ratio_zero_gain"], *rev["max_ratio_zero_gain"]])
    assert m["max_ratio_zero_gain_with_reviewer_set"] == pytest.approx(worst0, rel=1e-9)
    assert m["zero_gain_violates_envelope"] is (worst0 > 1.0)
    assert c["premise"]["holds"] is (m["eligible_weight_sets"] > 0 and m["zero_gain_violates_envelope"])
    assert "discriminates" in c["premise"]["statement"] and "RESTATED in session 14" in c["check"]
    if c["premise"]["holds"]:
        assert c["holds"] is (m["max_ratio"] <= 1.0)
    else:
        assert c["holds"] is None and point_verdict(c) == "fails-premise"
    x9 = claims["X9"]
    assert x9["premise"]["holds"] is (m["eligible_weight_sets"] > 0)
    assert x9["measured"] == m and x9["source"].startswith("ours") and not x9.get("decides")
    assert x9["holds"] is (m["max_ratio"] <= 1.0)
    # measured at the default point (the instance is fixed): the gains are ~0 and L = 0 gives the ratio
    assert m["max_gain_share"] == pytest.approx(2.883e-4, rel=1e-3)
    assert m["max_error_reduction"] == pytest.approx(3.574e-4, rel=1e-3)
    assert m["max_ratio_zero_gain"] == pytest.approx(0.0861239, rel=1e-5)
    assert abs(m["max_ratio_zero_gain"] - m["max_ratio"]) < 1e-5 * m["max_ratio"]
    for key in ("stage1_holds_cases", "lambda_53_holds_cases", "literal_56_holds_cases"):
        assert 0 <= m[key] <= m["eligible_cases"], key
    # (52)'s Lambda is not an upper bound of ||L||^2 in most eligible cases; the gains are ~0
    assert m["lambda_53_holds_cases"] == 273 and m["literal_56_holds_cases"] == 1840
    assert m["max_gain_norm_sq"] == pytest.approx(8.313e-8, rel=1e-3)
    assert m["max_gain_share"] ** 2 <= m["max_gain_norm_sq"] * (1 + 1e-9)  # ||L G|| <= ||L||, ||G|| <= 1


def test_deciding_claims_and_verdict_line(claims) -> None:
    """The main claims chosen in the notebook decide; the verdict line names exactly them."""
    claims = {cid: e for cid, e in claims.items() if not cid.startswith("_")}
    deciding = {cid for cid, e in claims.items() if e.get("decides")}
    assert deciding == {"C1b", "C3", "C7", "C8"}
    assert all(claims[cid]["basis"] == "measured" for cid in deciding)
    assert not any(claims[cid]["source"].startswith("ours") for cid in deciding)
    for cid in ("C4", "C5", "C8b", "X8"):
        assert claims[cid]["basis"] == "by-construction" and not claims[cid].get("decides"), cid
    assert all(claims[cid]["source"].startswith("ours") for cid in claims if cid.startswith("X"))
    line = rescience_verdict(claims)["line"]
    assert all(f"{cid} " in line for cid in deciding)
    for cid in ("C1c", "C2", "C3b", "X3", "X4", "X6"):
        assert isinstance(claims[cid]["runs"], int) and claims[cid]["runs"] >= 2, cid


def test_c4_rrl_map_fairness(claims) -> None:
    m = claims["C4"]["measured"]
    assert m["U"] == 2
    assert m["window_counts_min"] == m["window_counts_max"] == [1, 1, 1, 1]
    assert m["distinct_per_step_min"] == m["distinct_per_step_max"] == 2
    assert claims["C4"]["holds"] is True


def test_c5_attack_frequencies_inside_wilson_intervals(claims) -> None:
    c = claims["C5"]
    m = c["measured"]
    expected = np.array([0.3, 0.5, 0.7])
    inside = (np.array(m["interval_low"]) <= expected) & (expected <= np.array(m["interval_high"]))
    assert c["holds"] is bool(inside.all())
    assert np.all(np.abs(np.array(m["frequency"]) - expected) < 0.02)


def test_x8_kalman_limit(claims) -> None:
    assert claims["X8"]["measured"]["S"] <= 1e-10
    assert claims["X8"]["measured"]["xhat"] <= 1e-10
    assert claims["X8"]["holds"] is True


def test_c8_theorem2_gain_perturbations(claims) -> None:
    """Theorem 2: Pi's smallest relative eigenvalue decides; the perturbations agree with it."""
    c, cb = claims["C8"], claims["C8b"]
    m = c["measured"]
    grid = [m["printed, Remark-4 weights"], m["printed, alpha2 > alpha3 weights"]]
    declared = m["printed, declared weights (thm2_weights)"]
    assert c["key"] == cb["key"] == "min_eig_pi_relative"
    assert m["min_eig_pi_relative"] == min(r["min_eig_pi_relative"] for r in grid + [declared])
    assert m["min_relative_change"] == min(r["min_relative_change"] for r in grid + [declared])
    level = c["threshold"]
    assert level == -1e-10 and cb["threshold"] == level
    assert abs(m["min_eig_pi_relative"] - level) > _tolerance(c, m["min_eig_pi_relative"])
    assert c["holds"] is (m["min_eig_pi_relative"] >= level)
    for r in grid + [declared, m["printed, declared weights on the Remark-4 trajectory"],
                     m["corrected, weights in use"]]:
        # (28) is a stationary point of (18): the symmetric differences vanish to rounding
        assert r["max_relative_first_order"] <= 1e-10
        # second order: tr S cannot decrease in any direction iff Pi >= 0
        assert (r["min_eig_pi"] >= 0) is (r["min_relative_change"] >= level)
        assert (r["steps_with_pi_indefinite"] == 0) is (r["min_eig_pi"] >= 0)
        assert (r["min_eig_pi_relative"] >= 0) is (r["min_eig_pi"] >= 0)
        assert r["indefinite_pi_steps_with_S_pd"] <= r["steps_with_pi_indefinite"] <= r["steps"]
    # C8b: our grid's weights have printed c0 > 0 and kappa_x >= 0, so Pi > 0 by construction
    assert cb["basis"] == "by-construction" and not cb.get("decides")
    assert cb["measured"]["min_c0"] > 0 and cb["measured"]["min_kappa_x"] >= 0
    assert cb["measured"]["min_eig_pi_relative"] == min(r["min_eig_pi_relative"] for r in grid)
    assert all(r["min_eig_pi"] > 0 for r in grid)
    # the declared weights (0.1, 1, 9.5, 10, 0.01): printed c0 = 1 - 0.5 (1 - psi) > 0,
    # kappa_x = psi - 0.89 < 0 at the paper's psi = 0.7, 0.5, 0.3
    np.testing.assert_allclose(declared["c0_per_target"], [0.85, 0.75, 0.65], rtol=1e-12)
    np.testing.assert_allclose(declared["kappa_x_per_target"], [-0.19, -0.39, -0.59], rtol=1e-12)
    # default point, declared weights along their own trajectory: Pi indefinite at 145 of 300
    # (step, target) pairs, S(k|k) at (28) positive definite at every one of them
    assert declared["steps_with_pi_indefinite"] == m["steps_with_pi_indefinite_declared"] == 145
    assert declared["steps"] == 300
    assert declared["indefinite_pi_steps_with_S_pd"] == 145
    assert m["min_eig_S_at_indefinite_pi_declared"] == pytest.approx(5.287e-6, rel=1e-3)
    assert m["declared_trajectory_min_eig_S"] > 0  # Theorem 1's positive-definite solutions
    # a step along Pi's most negative direction lowers tr (18) and keeps S(k|k) positive definite
    assert m["declared_indefinite_steps"] == declared["steps_with_pi_indefinite"]
    assert 0 <= m["declared_descent_keeping_S_pd"] <= m["declared_indefinite_steps"]
    assert m["declared_descent_keeping_S_pd"] == 145
    # the two printed errors apart along each mixed design's own trajectory: with kappa_x >= 0 and
    # c0 > 0 Pi > 0 (algebra), measured; the printed kappa_x alone leaves Pi indefinite
    split = m["one_printed_coefficient"]
    for r in split.values():
        assert (r["indefinite_steps"] == 0) is (r["min_eig_pi_relative"] >= level)
        assert r["descent_keeping_S_pd"] <= r["indefinite_steps"]
    assert split["printed c0, corrected kappa_x"]["min_eig_pi_relative"] > 0
    assert split["corrected c0, printed kappa_x"]["min_eig_pi_relative"] < level
    # default point: Pi is positive definite along the printed design (min eigenvalue ~10)
    assert grid[0]["min_eig_pi"] == pytest.approx(10.011, rel=1e-3)
    # (18)'s first factor read literally moves the minimiser away from (28)
    assert grid[0]["literal_18_excess"] > 0.1


def test_c7_rows_measured_exactly(claims) -> None:
    c = claims["C7"]
    m = c["measured"]
    rows = m["relative_rms"]
    # no scale in the paper: recorded, not judged (not-checked, deciding as such)
    assert c["holds"] is None and c["threshold"] is None and "no scale" in c["not_checked"]
    assert c["decides"] and point_verdict(c) == "not-checked"
    assert m["max_relative_rms"] == max(rows["our corrected design"])
    assert m["max_relative_rms_printed"] == max(rows["printed-coefficient design"])
    # next to each design: its relative RMS over the open-loop prediction's
    for design in ("our corrected design", "printed-coefficient design"):
        assert m["ratio_to_open_loop"][design] == pytest.approx(
            [p / o for p, o in zip(rows[design], rows["open-loop prediction"], strict=True)], rel=1e-9)
    assert m["ratio_to_open_loop"]["our corrected design"] == pytest.approx([0.708, 0.972, 0.955], abs=2e-3)
    assert m["ratio_to_open_loop"]["printed-coefficient design"] == pytest.approx([0.961, 0.991, 0.986],
                                                                                 abs=2e-3)
    # exact expectations at the default point (T = 100, grid weights)
    assert rows["our corrected design"] == pytest.approx([0.339, 0.319, 0.214], abs=2e-3)
    assert rows["printed-coefficient design"] == pytest.approx([0.460, 0.326, 0.221], abs=2e-3)
    assert rows["per-step optimal gain for (8)"] == pytest.approx([0.174, 0.188, 0.164], abs=2e-3)
    assert rows["debiased innovation, optimal gain"] == pytest.approx([0.114, 0.126, 0.115], abs=2e-3)
    assert rows["no attack (psi_check = 1)"] == pytest.approx([0.0118, 0.0068, 0.0034], abs=5e-4)
    lo, hi = m["oracle_interval"]
    assert all(a <= v <= b for a, v, b in zip(lo, rows["oracle Kalman filter"], hi, strict=True))
    # the per-step optimal gain cannot do worse than (28)'s gain at any step: same class (8)
    for design in ("our corrected design", "printed-coefficient design"):
        assert all(o <= p + 1e-12 for o, p in zip(rows["per-step optimal gain for (8)"], rows[design],
                                                   strict=True))


def test_x_claims_measured(claims) -> None:
    x1, x3, x4 = claims["X1"], claims["X3"], claims["X4"]
    assert x1["holds"] is (x1["measured"]["mse_reduction_target1"] >= 0.25
                           and abs(x1["measured"]["mean_err_Xp_T_debiased"][0])
                           < abs(x1["measured"]["mean_err_Xp_T_paper"][0]))
    assert claims["X2"]["measured"] <= 1e-9
    # exact time-averaged E||e||^2 of the design with the theorem's E{xhat xhat^T}
    assert x3["measured"]["exact"] == pytest.approx([55.37, 148.02, 283.41], abs=0.02)
    assert x3["interval"]["low"] <= x3["measured"]["worst_relative_difference"] <= x3["interval"]["high"]
    assert x4["holds"] is (x4["measured"]["max_relative_rms_optimal_gain"] > 0.1
                           and max(x4["measured"]["oracle_upper"]) <= 0.1)


def test_identities_without_attack(no_attack) -> None:
    """psi_check = 1: debiasing changes nothing, 'no attack' is the design in use, no attacks drawn."""
    c7 = no_attack["C7"]["measured"]["relative_rms"]
    np.testing.assert_allclose(c7["no attack (psi_check = 1)"], c7["our corrected design"], rtol=1e-12)
    assert abs(no_attack["X1"]["measured"]["mse_reduction_target1"]) < 1e-12
    assert no_attack["C5"]["measured"]["frequency"] == [0.0, 0.0, 0.0]
    shares = no_attack["X5"]["measured"]["max_share_per_scenario"]
    np.testing.assert_allclose(shares["paper psi_check"], shares["psi_check = 1"], rtol=1e-12)
    assert no_attack["X5"]["measured"]["max_share"] <= 1 + 1e-9
    assert no_attack["X8"]["holds"] is True


def test_bad_input_names_the_parameter(tmp_path: Path) -> None:
    with pytest.raises(ValidationError, match="parameter m must be"):
        execute_notebook("li2025", {"mode": "fast", "m": 4}, tmp_path / "a.ipynb")
    params = {"mode": "fast", "psi_check": [1.5, 0.5, 0.3], "fig_dir": str(tmp_path / "f"),
              "results_path": str(tmp_path / "c.json")}
    with pytest.raises(PapermillExecutionError, match="parameter psi_check must be 3 probabilities"):
        execute_notebook("li2025", params, tmp_path / "b.ipynb")


def test_figures_and_data_written(no_attack) -> None:
    """Every manifest figure with its data, and the plotted numbers are the ones the claims measure."""
    fig_dir = Path(no_attack["_fig_dir"])
    manifest = tomllib.loads((ROOT / "figures" / "manifest.toml").read_text())
    stems = {Path(n).stem for fig in manifest["li2025"]["figures"] for n in fig["files"]}
    assert {"fig5_attack_and_errors", "fig6_attack_and_errors_zoh", "fig7_mse_and_bound",
            "extra_exact_bound_certificate", "extra_tracking_baselines"} <= stems
    for stem in stems:
        assert (fig_dir / f"{stem}.png").stat().st_size > 10_000, stem
        assert (fig_dir / f"{stem}.csv").exists(), stem
    rows = np.loadtxt(fig_dir / "fig7_mse_and_bound.csv", delimiter=",", skiprows=1)
    assert rows.shape == (NO_ATTACK["T"], 10)
    np.testing.assert_array_equal(rows[:, 0], np.arange(1, NO_ATTACK["T"] + 1))
    below = np.mean(rows[:, 1:4] <= rows[:, 4:7], axis=0)  # plotted MSE against the plotted bound
    assert below.tolist() == pytest.approx(no_attack["X6"]["measured"]["fraction_k_mse_below"])
    with (fig_dir / "extra_tracking_baselines.csv").open() as fh:
        last = list(csv.DictReader(fh))[-1]
    ours = no_attack["C7"]["measured"]["relative_rms"]["our corrected design"]
    assert [float(last[f"our_corrected_design[{i}]"]) for i in range(3)] == pytest.approx(ours, rel=1e-8)


def _robustness_rows() -> list[dict]:
    with (FIG / "robustness.csv").open() as fh:
        return list(csv.DictReader(fh))


def test_robustness_table_and_committed_verdicts() -> None:
    rows = _robustness_rows()
    summary = json.loads((FIG / "robustness.json").read_text())
    committed = json.loads((FIG / "claims.json").read_text())
    assert len(rows) == 65 and all(r["status"] == "ok" for r in rows)
    axes = {"T", "mc_seed", "xhat_moment", "coupling_factor", "attack_signal", "weight_rule"}
    assert axes <= set(rows[0])
    for cid in CLAIM_IDS:
        assert {f"{cid}.outcome", f"{cid}.holds", f"{cid}.value"} <= set(rows[0]), cid
        s = summary[cid]
        outcomes = [r[f"{cid}.outcome"] for r in rows]
        assert s["points"] == len(rows) and s["outcomes"]["holds"] == outcomes.count("holds")
        assert s["verdict"] == (outcomes[0] if len(set(outcomes)) == 1 else "undetermined")
        if s["verdict"] == "undetermined":
            assert len(set(outcomes)) > 1
            if "holds" in outcomes:
                assert 0.0 < s["fraction_holds"] < 1.0
        assert committed[cid]["verdict"] == s["verdict"]
    # copied cells are marked; C3 (its premise: an informative gain) fails it at every point, C7 has no scale
    assert rows[0]["copied"] == "" and all("C3" in r["copied"] and "C7" in r["copied"] for r in rows[1:])
    assert {r["C3.outcome"] for r in rows} == {"fails-premise"} and {r["C7.outcome"] for r in rows} == {"not-checked"}
    # claims.json's interval is over the independent draws (T, mc_seed) of the decided points, or over
    # their distinct records where fewer; the package's interval over records is kept beside it
    for cid in CLAIM_IDS:
        rob = committed[cid]["robustness"]
        decided = [r for r in rows if r[f"{cid}.outcome"] in ("holds", "fails")]
        draws = {(r["T"], r["mc_seed"]) for r in decided}
        records = {(r[f"{cid}.outcome"], r[f"{cid}.record"]) for r in decided}
        assert rob["draws"] == len(draws) <= 5, cid
        assert rob["independent"] == min(len(draws), len(records)), cid
        assert rob["interval"]["method"].startswith("wilson over the independent draws"), cid
        assert "independent_holding counts the draws at which every decided cell holds" in rob["interval"]["method"]
        for outcome, words in (("fails-premise", "premise fails at all"), ("not-checked", "not checked at any")):
            if rob["outcomes"][outcome] == rob["points"]:
                assert rob["region"].startswith(words), cid
        kept, package = rob["interval_records"], summary[cid]["interval"]
        assert kept["method"] == package["method"], cid
        assert [kept["low"], kept["high"]] == pytest.approx([package["low"], package["high"]], rel=1e-9), cid
    # the first row is the default point: it agrees with the committed claims
    default = rows[0]
    assert (default["T"], default["weight_rule"], default["mc_seed"]) == ("100", "grid", "2025")
    for cid in CLAIM_IDS:
        holds = committed[cid]["holds"]
        assert default[f"{cid}.holds"] == ("" if holds is None else str(holds)), cid  # CSV: None -> ""
        value = committed[cid]["measured"]
        if "key" in committed[cid] and value[committed[cid]["key"]] is not None:
            assert float(default[f"{cid}.value"]) == pytest.approx(
                value[committed[cid]["key"]], rel=1e-6), cid
