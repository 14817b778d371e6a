"""Unit tests of secest.core.estimation (feed-through SVD, constrained gain, fusion weights, LTV rank)."""

from __future__ import annotations

import numpy as np
import pytest

from secest.core import systems
from secest.core.estimation import (
    FeedthroughSVD,
    constrained_gain,
    feedthrough_decomposition,
    ltv_observability_matrix,
    relative_rank,
)
from secest.core.validation import ValidationError


def _spd(rng: np.random.Generator, n: int, floor: float = 0.1) -> np.ndarray:
    L = rng.standard_normal((n, n))
    return L @ L.T / n + floor * np.eye(n)


# ----------------------------------------------------------------------------- decomposition
def test_feedthrough_decomposition_properties_generic_R() -> None:
    rng = np.random.default_rng(1)
    ny, nd, na = 5, 2, 2
    H = np.hstack([np.zeros((ny, nd)), rng.standard_normal((ny, na))])
    R = _spd(rng, ny)
    dec = feedthrough_decomposition(H, R)
    assert isinstance(dec, FeedthroughSVD)
    assert dec.rank == na
    assert dec.U1.shape == (ny, na) and dec.U2.shape == (ny, ny - na)
    assert dec.V1.shape == (nd + na, na) and dec.V2.shape == (nd + na, nd)
    np.testing.assert_allclose(H @ dec.V1, dec.U1 @ dec.Sigma, atol=1e-13)
    np.testing.assert_allclose(H @ dec.V2, 0.0, atol=1e-13)
    np.testing.assert_allclose(dec.T1 @ R @ dec.U2, 0.0, atol=1e-13)  # decorrelation
    np.testing.assert_allclose(dec.T1 @ dec.U1, np.eye(na), atol=1e-13)  # T1 U1 Sigma = Sigma
    np.testing.assert_allclose(dec.U2.T @ dec.U1, 0.0, atol=1e-13)
    # V1 lives in the attack coordinates: G_bar V1 = 0 for G_bar = [G 0]
    np.testing.assert_allclose(dec.V1[:nd], 0.0, atol=1e-13)


def test_feedthrough_decomposition_identity_R_gives_T1_equal_U1T() -> None:
    H = np.array([[0.0, 0.1], [0.0, 0.2]])
    dec = feedthrough_decomposition(H, 1e-4 * np.eye(2))
    assert dec.rank == 1
    np.testing.assert_allclose(dec.T1, dec.U1.T, atol=1e-15)
    assert dec.Sigma[0, 0] == pytest.approx(np.hypot(0.1, 0.2))


def test_feedthrough_decomposition_rank_uses_relative_tolerance() -> None:
    H = np.array([[1.0, 1.0], [1.0, 1.0 + 1e-13], [0.0, 0.0]])
    assert feedthrough_decomposition(H, np.eye(3)).rank == 1
    assert feedthrough_decomposition(H, np.eye(3), rtol=1e-15).rank == 2
    full = feedthrough_decomposition(np.eye(2), np.eye(2))  # p = n_y: no U2
    assert full.rank == 2 and full.U2.shape == (2, 0)
    np.testing.assert_allclose(full.T1, full.U1.T)


def test_feedthrough_decomposition_bad_input() -> None:
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of R: expected \(2, 2\)"):
        feedthrough_decomposition(np.ones((2, 1)), np.eye(3))
    with pytest.raises(ValidationError, match="R must be positive definite"):
        feedthrough_decomposition(np.ones((2, 1)), np.diag([1.0, 0.0]))
    with pytest.raises(ValidationError, match="H contains NaN"):
        feedthrough_decomposition(np.array([[np.nan], [1.0]]), np.eye(2))
    with pytest.raises(ValidationError, match=r"rtol must lie in \(0, 1\)"):
        feedthrough_decomposition(np.ones((2, 1)), np.eye(2), rtol=0.0)


# ----------------------------------------------------------------------------- gain (28)
def _random_step(rng: np.random.Generator, nx: int, ny: int, nd: int, na: int):
    """Random instance of the constrained trace minimisation of guo2023 (26)-(28)."""
    H = np.hstack([np.zeros((ny, nd)), rng.standard_normal((ny, na))])
    Gbar = np.hstack([rng.standard_normal((nx, nd)), np.zeros((nx, na))])
    C = rng.standard_normal((ny, nx))
    R = _spd(rng, ny, 0.2)
    P = _spd(rng, nx)
    dec = feedthrough_decomposition(H, R)
    C2, R2 = dec.U2.T @ C, dec.U2.T @ R @ dec.U2
    G2 = Gbar @ dec.V2
    Xi2 = C2 @ P @ C2.T + R2
    B2 = C2 @ G2
    M2 = np.linalg.solve(B2.T @ np.linalg.solve(Xi2, B2), np.linalg.solve(Xi2, B2).T)
    J = G2 @ M2 @ dec.U2.T
    IJC = np.eye(nx) - J @ C
    P_star = IJC @ P @ IJC.T + J @ R @ J.T
    S = P_star @ C.T - J @ R
    Xi = C @ P @ C.T + R
    ICJ = np.eye(ny) - C @ J
    return dec, C, R, J, P_star, S, Xi, ICJ @ Xi @ ICJ.T, np.linalg.solve(Xi, ICJ)


def _trace_bound(C, R, J, P_star, K) -> float:
    IKC = np.eye(C.shape[1]) - K @ C
    cross = IKC @ J @ R @ K.T
    return float(np.trace(IKC @ P_star @ IKC.T + K @ R @ K.T + cross + cross.T))


@pytest.mark.parametrize("shape", [(4, 4, 1, 1), (5, 5, 2, 1), (4, 5, 1, 2), (3, 3, 1, 1)])
def test_constrained_gain_is_the_constrained_minimiser(shape) -> None:
    rng = np.random.default_rng(sum(shape))
    dec, C, R, J, P_star, S, Xi, Xi_breve, Theta = _random_step(rng, *shape)
    K = constrained_gain(S, Theta, dec.U1)
    assert np.linalg.norm(K @ dec.U1) < 1e-12
    # parametrised global minimiser over {K : K U1 = 0} = {L U2^T}
    M = dec.U2.T @ Xi_breve @ dec.U2
    K_par = S @ dec.U2 @ np.linalg.pinv(M, rcond=1e-9) @ dec.U2.T
    t_opt = _trace_bound(C, R, J, P_star, K)
    assert t_opt == pytest.approx(_trace_bound(C, R, J, P_star, K_par), rel=1e-10)
    # (29): the bound at the optimum is P* - K S^T
    assert t_opt == pytest.approx(float(np.trace(P_star - K @ S.T)), rel=1e-10)
    # feasible perturbations never do better
    for _ in range(5):
        dK = 1e-3 * rng.standard_normal(K.shape) @ dec.U2 @ dec.U2.T
        assert _trace_bound(C, R, J, P_star, K + dK) >= t_opt - 1e-12


def test_constrained_gain_without_constraint_and_bad_input() -> None:
    S, Theta = np.ones((3, 2)), np.eye(2)
    np.testing.assert_allclose(constrained_gain(S, Theta, np.zeros((2, 0))), S)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of Theta: expected \(2, 2\)"):
        constrained_gain(S, np.eye(3), np.ones((2, 1)))
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of U1: expected \(2, \*\)"):
        constrained_gain(S, Theta, np.ones((3, 1)))
    with pytest.raises(ValidationError, match="U1\\^T Theta U1 must be invertible"):
        constrained_gain(S, np.diag([0.0, 1.0]), np.array([[1.0], [0.0]]))


# ----------------------------------------------------------------------------- LTV observability
def test_ltv_observability_matrix_constant_pair_equals_lti() -> None:
    rng = np.random.default_rng(4)
    A, C = rng.standard_normal((3, 3)), rng.standard_normal((1, 3))
    obs = ltv_observability_matrix([A] * 3, [C] * 3)
    np.testing.assert_allclose(obs, systems.observability_matrix(A, C), atol=1e-13)
    np.testing.assert_allclose(ltv_observability_matrix([A] * 2, [C] * 3), obs)


def test_ltv_observability_matrix_time_varying_rank() -> None:
    # x2 is seen only at k = 1, x1 only at k = 0: rank 2 over the window, 1 per step
    A = np.eye(2)
    obs = ltv_observability_matrix([A, A], [np.array([[1.0, 0.0]]), np.array([[0.0, 1.0]])])
    assert relative_rank(obs) == 2
    assert relative_rank(obs[:1]) == 1
    assert relative_rank(np.zeros((2, 2))) == 0


def test_ltv_observability_matrix_and_rank_bad_input() -> None:
    with pytest.raises(ValidationError, match="C_seq must contain at least one output matrix"):
        ltv_observability_matrix([], [])
    with pytest.raises(ValidationError, match="A_seq must hold at least len"):
        ltv_observability_matrix([], [np.ones((1, 2))] * 3)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of C_seq\[1\]"):
        ltv_observability_matrix([np.eye(2)], [np.ones((1, 2)), np.ones((1, 3))])
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of A_seq\[0\]"):
        ltv_observability_matrix([np.eye(3)], [np.ones((1, 2))] * 2)
    with pytest.raises(ValidationError, match=r"rtol must lie in \(0, 1\)"):
        relative_rank(np.eye(2), rtol=2.0)
