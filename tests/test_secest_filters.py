"""Unit tests of secest.methods.ding2020 (the distributed secure filter of ding2020)."""

from __future__ import annotations

import numpy as np
import pytest

from secest.core.validation import ValidationError
from secest.methods.ding2020 import (
    consensus_prediction,
    matrix_max,
    matrix_min,
    received_indicator,
    secure_filter_node_step,
    secure_filter_step,
)

T = 0.05
A = np.array([[1, T, T**2 / 2], [0, 1, T], [0, 0, 1.0]])
BBT = 0.04 * np.eye(3)
DDT = np.array([[0.0025]])


def _network(m: int = 6, seed: int = 0):
    rng = np.random.default_rng(seed)
    adj = np.zeros((m, m))
    for i in range(m):  # ring plus random chords, undirected
        adj[i, (i + 1) % m] = adj[(i + 1) % m, i] = 1.0
    extra = np.triu(rng.random((m, m)) < 0.3, 2).astype(float)
    adj = np.clip(adj + extra + extra.T, 0, 1)
    np.fill_diagonal(adj, 0.0)
    H = adj / adj.sum(axis=1, keepdims=True)
    C = np.array([[[4.5, -0.8, -0.5]] if i % 2 else [[4.0, -0.8, 1.0]] for i in range(m)])
    return adj, H, C


def _kwargs(adj, H, C, **extra):
    kw = dict(A=A, BBt=BBT, C=C, DDt=DDT, adj=adj, weights=H, kappa=0.004, threshold=25.0)
    kw.update(extra)
    return kw


# ---------------------------------------------------------------- min / max operations
def test_matrix_min_ordered_pairs_return_the_smaller() -> None:
    X = np.diag([1.0, 2.0])
    Y = np.diag([2.0, 3.0])
    out, branch = matrix_min(X, Y)
    assert np.array_equal(out, X) and branch == 0
    out, branch = matrix_min(Y, X)
    assert np.array_equal(out, X) and branch == 1


def test_matrix_min_unordered_pair_gives_lambda_min_identity() -> None:
    X = np.diag([1.0, 4.0])
    Y = np.diag([3.0, 0.5])
    out, branch = matrix_min(X, Y)
    assert branch == 2
    assert np.array_equal(out, 0.5 * np.eye(2))
    for Z in (X, Y):  # below both, the only property the proofs use
        assert np.linalg.eigvalsh(Z - out)[0] >= 0


def test_matrix_max_unordered_pair_gives_lambda_max_identity() -> None:
    X = np.diag([1.0, 4.0])
    Y = np.diag([3.0, 0.5])
    out, branch = matrix_max(X, Y)
    assert branch == 2 and np.array_equal(out, 4.0 * np.eye(2))
    out, branch = matrix_max(np.eye(2), 2 * np.eye(2))
    assert branch == 0 and np.array_equal(out, 2 * np.eye(2))


def test_matrix_max_rank_deficient_difference_strict_vs_non_strict() -> None:
    """E6: Pi^- - S* has rank one; only the non-strict order keeps max{Pi^-, S*} = Pi^-."""
    Pi = np.diag([2.0, 1.0])
    S = Pi - np.diag([1.0, 0.0])
    out, branch = matrix_max(Pi, S)
    assert branch == 1 and np.array_equal(out, Pi)
    out, branch = matrix_max(Pi, S, strict=True)
    assert branch == 2 and np.array_equal(out, 2.0 * np.eye(2))


def test_matrix_min_is_vectorised_over_stacks() -> None:
    X = np.stack([np.eye(2), np.diag([1.0, 4.0])])
    Y = np.stack([2 * np.eye(2), np.diag([3.0, 0.5])])
    out, branch = matrix_min(X, Y)
    assert branch.tolist() == [0, 2]
    assert np.array_equal(out[1], 0.5 * np.eye(2))


@pytest.mark.parametrize(
    ("X", "Y", "message"),
    [
        (np.eye(2), np.eye(3), r"Incompatible dimensions of Y: expected \(2, 2\), found \(3, 3\)"),
        (np.ones(3), np.ones(3), "X must be square in its last two axes"),
        (np.eye(2) * np.nan, np.eye(2), "X contains NaN or infinite entries"),
    ],
)
def test_matrix_min_bad_input(X, Y, message) -> None:
    with pytest.raises(ValidationError, match=message):
        matrix_min(X, Y)


def test_matrix_min_negative_tol() -> None:
    with pytest.raises(ValidationError, match="tol must be >= 0, found -1.0"):
        matrix_min(np.eye(2), np.eye(2), tol=-1.0)


# ---------------------------------------------------------------- (3), (4), (7)
def test_received_indicator_follows_the_channel() -> None:
    adj, _, _ = _network()
    x = np.random.default_rng(1).standard_normal((adj.shape[0], 3))
    xr, dr = received_indicator(x, 1, adj)
    assert np.array_equal(xr, x) and np.all(dr == 1)
    xr, dr = received_indicator(x, 0, adj)
    assert np.all(xr == 0) and np.all(dr == 0)


def test_received_indicator_all_zero_estimates_pitfall() -> None:
    """P3: with all-zero estimates, (4) reports a lost channel although delta = 1."""
    adj, _, _ = _network()
    _, dr = received_indicator(np.zeros((adj.shape[0], 3)), 1, adj)
    assert np.all(dr == 0)


def test_received_indicator_bad_input() -> None:
    adj, _, _ = _network()
    x = np.ones((adj.shape[0], 3))
    with pytest.raises(ValidationError, match="delta must contain only 0 and 1"):
        received_indicator(x, 0.5, adj)
    with pytest.raises(ValidationError, match="Incompatible dimensions of adj"):
        received_indicator(x, 1, np.zeros((2, 2)))


def test_consensus_prediction_matches_formula_7() -> None:
    adj, H, _ = _network()
    m = adj.shape[0]
    x = np.random.default_rng(2).standard_normal((m, 3))
    x_prior, dr = consensus_prediction(x, 1, adj, H, A, 0.1)
    for i in range(m):
        xi = sum(H[i, j] * (x[j] - x[i]) for j in np.flatnonzero(adj[i]))
        assert np.allclose(x_prior[i], A @ x[i] + 0.1 * A @ xi, atol=1e-14)
    x_prior, _ = consensus_prediction(x, 0, adj, H, A, 0.1)
    assert np.allclose(x_prior, x @ A.T, atol=1e-14)


def test_consensus_prediction_bad_kappa() -> None:
    adj, H, _ = _network()
    with pytest.raises(ValidationError, match="kappa must be >= 0, found -0.1"):
        consensus_prediction(np.ones((adj.shape[0], 3)), 1, adj, H, A, -0.1)


# ---------------------------------------------------------------- the full step
def _run_both(steps: int = 30, inspection_cov: str = "Gamma", seed: int = 3):
    adj, H, C = _network(seed=seed)
    m = adj.shape[0]
    rng = np.random.default_rng(seed)
    x_vec = rng.standard_normal((1, m, 3))
    Pi_vec = np.broadcast_to(2 * np.eye(3), (1, m, 3, 3)).copy()
    G_vec = Pi_vec.copy()
    x_loop, Pi_loop, G_loop = x_vec[0].copy(), Pi_vec[0].copy(), G_vec[0].copy()
    delta = rng.integers(0, 2, steps)
    worst = 0.0
    thetas = []
    for k in range(steps):
        y = 3.0 * rng.standard_normal((1, m, 1))
        if k in (10, 11, 12):
            y[0, 0] += 15.0  # an injection node 0 must reject
        st = secure_filter_step(x_vec, Pi_vec, G_vec, delta[k], y,
                                **_kwargs(adj, H, C, inspection_cov=inspection_cov))
        x_vec, Pi_vec, G_vec = st.x_post, st.Pi_post, st.Gamma_post
        new = []
        for i in range(m):
            nb = np.flatnonzero(adj[i])
            new.append(secure_filter_node_step(
                x_loop[i], Pi_loop[i], G_loop[i], x_loop[nb], Pi_loop[nb], H[i, nb],
                int(delta[k]), y[0, i], A=A, BBt=BBT, C_i=C[i], DDt=DDT, kappa=0.004,
                threshold=25.0, inspection_cov=inspection_cov))
        x_loop = np.stack([r[0] for r in new])
        Pi_loop = np.stack([r[1] for r in new])
        G_loop = np.stack([r[2] for r in new])
        assert [r[3] for r in new] == st.theta[0].astype(int).tolist()
        thetas.append(st.theta[0])
        worst = max(worst, float(np.abs(x_vec[0] - x_loop).max()),
                    float(np.abs(Pi_vec[0] - Pi_loop).max() / np.abs(Pi_loop).max()),
                    float(np.abs(G_vec[0] - G_loop).max()))
    return worst, np.array(thetas)


@pytest.mark.parametrize("inspection_cov", ["Gamma", "Pi"])
def test_vectorised_step_equals_per_node_reference(inspection_cov) -> None:
    worst, thetas = _run_both(inspection_cov=inspection_cov)
    assert worst <= 1e-10
    assert thetas[10, 0] == 0  # the injection was rejected


def test_step_bounds_are_symmetric_and_ordered() -> None:
    adj, H, C = _network()
    m = adj.shape[0]
    rng = np.random.default_rng(5)
    x = rng.standard_normal((4, m, 3))  # a batch of 4 runs
    Pi = np.broadcast_to(2 * np.eye(3), (4, m, 3, 3)).copy()
    G = Pi.copy()
    for _ in range(20):
        st = secure_filter_step(x, Pi, G, np.array([1, 0, 1, 1]), rng.standard_normal((4, m, 1)),
                                **_kwargs(adj, H, C))
        x, Pi, G = st.x_post, st.Pi_post, st.Gamma_post
        for M in (Pi, G, st.Pi_prior, st.Gamma_prior):
            assert np.array_equal(M, np.swapaxes(M, -1, -2))
        # S* = Pi^- - K C Pi^- <= Pi^- and Gamma^+ <= Gamma^- (min property)
        assert np.linalg.eigvalsh(st.Pi_prior - Pi)[..., 0].min() >= -1e-12
        assert np.linalg.eigvalsh(st.Gamma_prior - G)[..., 0].min() >= -1e-12
    assert st.delta_r[1].max() == 0 and st.delta_r[0].min() == 1


def test_no_inspection_accepts_everything() -> None:
    adj, H, C = _network()
    m = adj.shape[0]
    x = np.zeros((m, 3)) + 1.0
    Pi = np.broadcast_to(np.eye(3), (m, 3, 3)).copy()
    y = np.full((m, 1), 1e3)
    st = secure_filter_step(x, Pi, Pi, 1, y, **_kwargs(adj, H, C, inspect=False))
    assert np.all(st.theta == 1)
    st = secure_filter_step(x, Pi, Pi, 1, y, **_kwargs(adj, H, C))
    assert np.all(st.theta == 0)
    assert np.array_equal(st.Pi_post, st.Pi_prior)  # (35) with theta = 0


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"kappa": -1.0}, "kappa must be >= 0, found -1.0"),
        ({"threshold": 0.0}, "threshold must be > 0, found 0.0"),
        ({"inspection_cov": "P"}, "inspection_cov must be one of"),
        ({"A": np.eye(2)}, r"Incompatible dimensions of A: expected \(3, 3\) to match x_post, found \(2, 2\)"),
        ({"DDt": np.eye(2)}, r"Incompatible dimensions of DDt: expected \(1, 1\)"),
        ({"C": np.ones((5, 1, 3))}, r"Incompatible dimensions of C: expected \(6, \*, 3\)"),
        ({"adj": np.ones((6, 6))}, "adj must be a 0/1 matrix with zero diagonal"),
        ({"weights": np.ones((6, 6)) / 6}, "weights must be positive exactly on the edges"),
    ],
)
def test_secure_filter_step_bad_input(change, message) -> None:
    adj, H, C = _network()
    m = adj.shape[0]
    x = np.zeros((m, 3))
    Pi = np.broadcast_to(np.eye(3), (m, 3, 3)).copy()
    kw = _kwargs(adj, H, C)
    kw.update(change)
    with pytest.raises(ValidationError, match=message):
        secure_filter_step(x, Pi, Pi, 1, np.zeros((m, 1)), **kw)


def test_secure_filter_step_bad_shapes_of_state() -> None:
    adj, H, C = _network()
    m = adj.shape[0]
    Pi = np.broadcast_to(np.eye(3), (m, 3, 3)).copy()
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of y: expected \(6, 1\)"):
        secure_filter_step(np.zeros((m, 3)), Pi, Pi, 1, np.zeros(m), **_kwargs(adj, H, C))
    with pytest.raises(ValidationError, match="Incompatible dimensions of Gamma_post"):
        secure_filter_step(np.zeros((m, 3)), Pi, Pi[:3], 1, np.zeros((m, 1)), **_kwargs(adj, H, C))
    with pytest.raises(ValidationError, match="delta must contain only 0 and 1"):
        secure_filter_step(np.zeros((m, 3)), Pi, Pi, 2, np.zeros((m, 1)), **_kwargs(adj, H, C))
    with pytest.raises(ValidationError, match="Incompatible dimensions of delta"):
        secure_filter_step(np.zeros((m, 3)), Pi, Pi, np.ones(4), np.zeros((m, 1)),
                           **_kwargs(adj, H, C))


def test_node_step_bad_input() -> None:
    kw = dict(A=A, BBt=BBT, C_i=np.array([[4.0, -0.8, 1.0]]), DDt=DDT, kappa=0.004,
              threshold=25.0)
    x, P = np.zeros(3), np.eye(3)
    xs, Ps, hs = np.zeros((2, 3)), np.stack([np.eye(3)] * 2), np.array([0.5, 0.5])
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of Pi_nbrs"):
        secure_filter_node_step(x, P, P, xs, Ps[:1], hs, 1, np.zeros(1), **kw)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of h_nbrs"):
        secure_filter_node_step(x, P, P, xs, Ps, hs[:1], 1, np.zeros(1), **kw)
    with pytest.raises(ValidationError, match=r"delta must be one of \(0, 1\), found 3"):
        secure_filter_node_step(x, P, P, xs, Ps, hs, 3, np.zeros(1), **kw)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of y_i"):
        secure_filter_node_step(x, P, P, xs, Ps, hs, 1, np.zeros(2), **kw)


def test_sparse_and_dense_network_give_identical_steps() -> None:
    """adj / weights as scipy.sparse (large networks) compute exactly the dense result."""
    import scipy.sparse as sp

    from secest.core import graphs

    rng = np.random.default_rng(11)
    m, n = 12, 3
    adj = graphs.random_geometric_graph(m, 0.5, seed=3)
    H = graphs.row_stochastic_weights(adj, self_weight=False)
    A = np.array([[1.0, 0.05, 0.00125], [0.0, 1.0, 0.05], [0.0, 0.0, 1.0]])
    C = rng.standard_normal((m, 1, n))
    P = np.broadcast_to(np.stack([np.eye(n) * (1 + i) for i in range(m)]), (2, m, n, n)).copy()
    common = dict(A=A, BBt=0.04 * np.eye(n), C=C, DDt=np.eye(1) * 0.0025, kappa=0.004, threshold=25.0)
    x = rng.standard_normal((2, m, n))
    y = rng.standard_normal((2, m, 1))
    dense = secure_filter_step(x, P, P, 1, y, adj=adj, weights=H, **common)
    sparse = secure_filter_step(x, P, P, 1, y, adj=sp.csr_array(adj), weights=sp.csr_array(H), **common)
    for a, b in zip(dense, sparse, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-14)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of adj: expected \(12, 12\), found \(3, 3\)"):
        secure_filter_step(x, P, P, 1, y, adj=sp.eye_array(3), weights=H, **common, validate=False)
