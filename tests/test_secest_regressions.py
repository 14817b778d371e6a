"""Regression tests, one per defect of issue #14 ("secest as a library people can build on")."""

from __future__ import annotations

import time
import warnings

import cvxpy as cp
import numpy as np
import pytest

from secest.core import channels, covariance, detectors, graphs, lmi, systems
from secest.core.validation import SizeLimitError, ValidationError, check_row_stochastic
from secest.methods import ding2020

T = 0.05
A = np.array([[1, T, T**2 / 2], [0, 1, T], [0, 0, 1.0]])
BBT = 0.04 * np.eye(3)
DDT = np.array([[0.0025]])


# ---------------------------------------------------------------- lmi: certificates
def _two_sided(eps: float = 1e-6):
    """Y <= -eps I and Y >= eps I: strictly infeasible; SCS nevertheless returns Y = 0."""
    Y = cp.Variable((2, 2), symmetric=True)
    prob = cp.Problem(cp.Minimize(0), [lmi.lmi(Y, eps), lmi.lmi(-Y, eps)])
    return prob, {"upper": Y, "lower": -Y}


def test_solve_certified_refuses_the_strictly_infeasible_example() -> None:
    prob, lmis = _two_sided()
    with pytest.warns(UserWarning, match="falling back to SCS"):
        with pytest.raises(lmi.InfeasibleLMIError, match=r"max eig 0\.000e\+00 > -9\.9e-07") as info:
            lmi.solve_certified(prob, lmis, eps=1e-6)
    assert info.value.outcomes == {"CLARABEL": "infeasible", "SCS": "not certified"}


def test_solve_certified_reports_an_unbounded_problem_as_unbounded() -> None:
    x = cp.Variable((1, 1), symmetric=True)
    prob = cp.Problem(cp.Minimize(cp.trace(x)), [lmi.lmi(x, 1e-6)])
    with pytest.raises(lmi.UnboundedLMIError, match="LMI problem unbounded at step 4") as info:
        lmi.solve_certified(prob, {"x": x}, step=4, eps=1e-6, fallback=None)
    assert info.value.outcomes == {"CLARABEL": "unbounded"}
    assert isinstance(info.value, lmi.LMISolveError) and not isinstance(info.value, lmi.InfeasibleLMIError)


def test_margin_and_strict_certificates() -> None:
    """Built with margin 1e-6, claimed with eps = 1e-3: the margin certificate refuses, the strict one holds."""
    x = cp.Variable((2, 2), symmetric=True)
    m = lmi.block_symmetric([[-x], [np.eye(2), -np.eye(2)]])
    prob = cp.Problem(cp.Minimize(cp.trace(x)), [lmi.lmi(m, 1e-6)])
    with pytest.raises(lmi.InfeasibleLMIError, match="not certified"):
        lmi.solve_certified(prob, {"m": m}, eps=1e-3, fallback=None)
    rep = lmi.solve_certified(prob, {"m": m}, eps=1e-3, certify="strict", fallback=None)
    assert rep.certify == "strict" and rep.bound == -rep.tol and rep.worst_eig <= -1e-8
    assert rep.residual["m"] > 0  # the claimed margin is reported as missed, not hidden
    ok = lmi.solve_certified(prob, {"m": m}, eps=1e-6)
    assert ok.bound == pytest.approx(-1e-6 + 1e-8) and ok.worst_eig <= ok.bound


# ---------------------------------------------------------------- systems: integrator
def test_integrator_shared_input_with_square_batch_of_states() -> None:
    """x0 of shape (nx, B) with B = nx and w(t) of shape (nw,): the input drives every column."""
    M = np.array([[-1.0, 2.0], [0.0, -3.0]])
    E_w, E_s, R = np.eye(2), np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]])

    def w(t: float) -> np.ndarray:
        return np.array([np.sin(t), 1.0])

    X0 = np.array([[1.0, -2.0], [0.5, 0.0]])  # B = nx = 2
    both = systems.integrate_switched_linear(M, E_w, w, E_s, R, np.sign, X0, 0.01, 50)
    for b in range(2):
        single = systems.integrate_switched_linear(M, E_w, w, E_s, R, np.sign, X0[:, b], 0.01, 50)
        np.testing.assert_allclose(both[..., b], single, atol=1e-14)


def test_integrator_checks_what_w_and_phi_return() -> None:
    M, E = -np.eye(2), np.eye(2)
    R = np.eye(2)
    with pytest.raises(ValidationError, match=r"w must return real values of shape \(2,\) \(to match E_w and x0\), found an array of shape \(3,\)"):
        systems.integrate_switched_linear(M, E, lambda t: np.ones(3), E, R, np.sign, np.ones(2), 0.1, 3)
    with pytest.raises(ValidationError, match="the state is not finite from t = 0.1: w or phi returned NaN"):
        systems.integrate_switched_linear(M, E, lambda t: np.zeros(2), E, R, lambda r: r * np.nan,
                                          np.ones(2), 0.1, 3)


# ---------------------------------------------------------------- covariance and PSD rule
def test_min_eig_refuses_nan() -> None:
    with pytest.raises(ValidationError, match="P contains NaN or infinite entries"):
        covariance.min_eig([[np.nan, 0.0], [0.0, 1.0]])


@pytest.mark.parametrize(
    "call",
    [
        lambda: covariance.min_eig(np.zeros((0, 0))),
        lambda: covariance.check_psd("P", np.zeros((0, 0))),
        lambda: lmi.max_eigenvalue(np.zeros((0, 0))),
        lambda: graphs.algebraic_connectivity(np.zeros((0, 0))),
    ],
)
def test_empty_matrices_are_refused(call) -> None:
    with pytest.raises(ValidationError, match=r"must not be empty, found shape \(0, 0\)"):
        call()


def test_psd_checks_are_relative() -> None:
    covariance.check_psd("P", 1e-12 * np.eye(3), strict=True)  # positive definite at any scale
    rng = np.random.default_rng(0)
    for _ in range(10):  # PSD of scale 1e8 with a zero eigenvalue, any rotation
        Q, _ = np.linalg.qr(rng.standard_normal((4, 4)))
        P = Q @ np.diag([0.0, 1e8, 2e8, 3e8]) @ Q.T
        covariance.check_psd("P", 0.5 * (P + P.T))
    with pytest.raises(ValidationError, match="P must be positive semidefinite"):
        covariance.check_psd("P", np.diag([1e8, -1e-1]))
    n = 3000  # uniform weights on many neighbours: the row sum is 1 only to round-off
    check_row_stochastic("W", np.full((n, n), 1.0 / n))


def test_fusion_accepts_weights_summing_to_one_up_to_round_off() -> None:
    w = np.full(7, 1 / 7)
    covariance.information_fusion([np.zeros(2)] * 7, [np.eye(2)] * 7, w)


# ---------------------------------------------------------------- composition at defaults
def _ding_network(m: int = 8):
    adj = graphs.ring_graph(m)
    C = np.array([[[4.5, -0.8, -0.5]] if i % 2 else [[4.0, -0.8, 1.0]] for i in range(m)])
    return adj, C


def test_row_stochastic_weights_default_composes_with_the_filter() -> None:
    adj, C = _ding_network()
    H = graphs.row_stochastic_weights(adj)
    P = np.broadcast_to(np.eye(3), (8, 3, 3))
    st = ding2020.secure_filter_step(np.ones((8, 3)), P, P, 1, np.zeros((8, 1)), A=A, BBt=BBT, C=C,
                                    DDt=DDT, adj=adj, weights=H, kappa=0.004, threshold=25.0)
    assert st.x_post.shape == (8, 3) and not st.joseph


def test_gilbert_elliott_accepts_an_int_seed() -> None:
    a = channels.gilbert_elliott(0.1, 0.9, 10, 0)
    b = channels.gilbert_elliott(0.1, 0.9, 10, np.random.default_rng(0))
    assert np.array_equal(a, b)


def test_unseeded_randomness_is_refused() -> None:
    with pytest.raises(ValidationError, match="seed must be a numpy Generator or a non-negative integer seed, found None"):
        graphs.random_geometric_graph(10, 0.5, seed=None)
    with pytest.raises(ValidationError, match="rng must be a numpy Generator"):
        channels.bernoulli(0.5, 3, None)


def test_nis_scalar_case_and_unambiguous_detector_outcome() -> None:
    assert detectors.nis(2.0, 4.0) == pytest.approx(1.0)
    assert detectors.chi2_alarm(3.0, 1.0, 4.0) is True  # 9 > 4: alarm
    assert detectors.chi2_passes(3.0, 1.0, 4.0) is False


def test_max_tries_is_blamed_for_max_tries() -> None:
    with pytest.raises(ValidationError, match="max_tries must be >= 1, found 0"):
        graphs.random_geometric_graph(10, 0.5, 0, max_tries=0)


# ---------------------------------------------------------------- sizes refused cheaply
def test_absurd_sizes_are_refused_at_once() -> None:
    A6 = np.diag(np.arange(1.0, 7.0))
    banks = [np.eye(6)[[i % 6]] for i in range(40)]
    t0 = time.perf_counter()
    with pytest.raises(SizeLimitError, match=r"q = 10 with N = 40 banks \(C_banks\) asks for 1\.38e\+11 subsets"):
        systems.redundant_observability(A6, banks, q=10)
    with pytest.raises(SizeLimitError, match="n asks for 1e\\+05 nodes of a dense adjacency matrix"):
        graphs.complete_graph(10**5)
    with pytest.raises(SizeLimitError, match="steps must be <= 100000000"):
        channels.gilbert_elliott(0.1, 0.9, 10**12, 0)
    assert time.perf_counter() - t0 < 1.0


# ---------------------------------------------------------------- filter: standing assumptions
def _step_args(m: int = 6):
    adj, C = _ding_network(m)
    H = graphs.row_stochastic_weights(adj)
    P = np.broadcast_to(np.eye(3), (m, 3, 3)).copy()
    kw = dict(A=A, BBt=BBT, C=C, DDt=DDT, adj=adj, weights=H, kappa=0.004, threshold=25.0)
    return (np.zeros((m, 3)), P, P, 1, np.zeros((m, 1))), kw


def _two_rings(m: int = 6) -> np.ndarray:
    two = np.zeros((m, m))
    two[:3, :3] = two[3:, 3:] = graphs.ring_graph(3)
    return two


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"DDt": [[-0.1]]}, "DDt must be positive definite, found lambda_min = -0.1"),
        ({"DDt": [[0.0]]}, "DDt must be positive definite, found lambda_min = 0"),
        ({"BBt": np.diag([1.0, -1.0, 1.0])}, "BBt must be positive semidefinite"),
        ({"BBt": np.triu(np.ones((3, 3)))}, r"BBt must be symmetric, found max \|BBt - BBt\^T\| = 1"),
        ({"adj": _two_rings(), "weights": graphs.row_stochastic_weights(_two_rings())},
         "adj must describe a strongly connected graph, found 2 components"),
        ({"weights": 5 * graphs.row_stochastic_weights(graphs.ring_graph(6))},
         "weights must be row-stochastic, row 0 sums to 5"),
        ({"kappa": "a"}, "kappa must be a real number, found 'a'"),
        ({"joseph": "yes"}, "joseph must be True or False, found 'yes'"),
    ],
)
def test_filter_refuses_violated_standing_assumptions(change, message) -> None:
    args, kw = _step_args()
    with pytest.raises(ValidationError, match=message):
        ding2020.secure_filter_step(*args, **{**kw, **change})


def test_filter_refuses_bounds_out_of_order_or_indefinite() -> None:
    (x, P, _, d, y), kw = _step_args()
    with pytest.raises(ValidationError, match=r"Gamma_post\[0\] must lie below Pi_post in the Loewner order"):
        ding2020.secure_filter_step(x, P, 2 * P, d, y, **kw)
    bad = P * np.array([1.0, 1.0, -1.0])
    with pytest.raises(ValidationError, match=r"Pi_post\[0\] must be positive semidefinite"):
        ding2020.secure_filter_step(x, bad, 0 * P, d, y, **kw)


def test_node_step_refuses_negative_weights() -> None:
    P = np.eye(3)
    with pytest.raises(ValidationError, match="h_nbrs must be positive and sum to 1"):
        ding2020.secure_filter_node_step(np.zeros(3), P, P, np.zeros((2, 3)), np.stack([P, P]),
                                        [-0.5, 1.5], 1, np.zeros(1), A=A, BBt=BBT, C_i=[[4.0, -0.8, 1.0]],
                                        DDt=DDT, kappa=0.004, threshold=25.0)


def test_consensus_prediction_validates_adj() -> None:
    H = graphs.row_stochastic_weights(graphs.ring_graph(4))
    with pytest.raises(ValidationError, match="adj must be a 0/1 matrix with zero diagonal"):
        ding2020.consensus_prediction(np.zeros((4, 3)), 1, np.ones((4, 4)), H, A, 0.1)


# ---------------------------------------------------------------- filter: (35) and health
def _ding_run(p0: float, steps: int, *, joseph: bool = False, count: bool = True, seed: int = 0):
    """The ding2020 example on a ring of 8 nodes, initial errors consistent with Pi_0 = p0 I."""
    rng = np.random.default_rng(seed)
    adj, C = _ding_network()
    H = graphs.row_stochastic_weights(adj)
    x = np.sqrt(p0) * rng.standard_normal(3)
    xh = np.zeros((8, 3))
    Pi = np.broadcast_to(p0 * np.eye(3), (8, 3, 3)).copy()
    G, rej, out = Pi.copy(), None, []
    for _ in range(steps):
        x = A @ x + 0.2 * rng.standard_normal(3)
        y = np.einsum("iyn,n->iy", C, x) + 0.05 * rng.standard_normal((8, 1))
        st = ding2020.secure_filter_step(xh, Pi, G, 1, y, A=A, BBt=BBT, C=C, DDt=DDT, adj=adj,
                                        weights=H, kappa=0.004, threshold=25.0, joseph=joseph,
                                        rejections=rej if count else None)
        xh, Pi, G, rej = st.x_post, st.Pi_post, st.Gamma_post, st.rejections
        out.append(st)
    return out


def test_joseph_form_is_recorded_and_agrees_with_35() -> None:
    sub = _ding_run(2.0, 15)
    jos = _ding_run(2.0, 15, joseph=True)
    assert jos[-1].joseph and not sub[-1].joseph
    for a, b in zip(sub, jos, strict=True):
        np.testing.assert_allclose(b.Pi_post, a.Pi_post, rtol=1e-10, atol=1e-13)
        assert np.all(b.Pi_psd) and np.all(b.ordered)


def test_lockout_is_flagged_and_warned_about() -> None:
    """Pi_0 = Gamma_0 = 1e8 I with consistent initial errors: the nodes reject every measurement."""
    with pytest.warns(ding2020.FilterHealthWarning, match="rejected every measurement for lockout_steps = 10"):
        out = _ding_run(1e8, 14)
    assert np.all(out[-1].locked_out) and np.all(out[-1].rejections >= 10)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # without the running count there is nothing to warn about
        _ding_run(1e8, 3, count=False)


def test_loss_of_psd_is_flagged_and_warned_about() -> None:
    (x, P, _, d, y), kw = _step_args()
    bad = np.broadcast_to(np.diag([1.0, 1.0, -5.0]), P.shape)  # only reachable with validate=False
    with pytest.warns(ding2020.FilterHealthWarning, match="Pi\\^\\+ lost PSD at"):
        st = ding2020.secure_filter_step(x, bad, 0 * P, d, y, **kw, validate=False, inspect=False)
    assert not np.all(st.Pi_psd)


def test_feedthrough_without_unknown_input_columns() -> None:
    """n_u = 0 (no attack channel at a node) is a valid case of guo2023's transform: p = 0."""
    from secest.core.estimation import feedthrough_decomposition

    out = feedthrough_decomposition(np.zeros((2, 0)), np.eye(2))
    assert out.rank == 0 and out.U2.shape == (2, 2) and out.T1.shape == (0, 2)
    with pytest.raises(ValidationError, match="H must have at least one row"):
        feedthrough_decomposition(np.zeros((0, 1)), np.eye(0))
