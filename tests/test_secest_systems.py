"""Unit tests of secest.core.systems (observability helpers, 2q-redundant observability)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from secest.core.systems import (
    RedundancyResult,
    discretize_zoh,
    integrate_switched_linear,
    is_observable,
    observability_matrix,
    observability_rank,
    observable_subspace,
    redundant_observability,
    stack_banks,
    unobservable_subspace,
)
from secest.core.validation import ValidationError


def three_inertia() -> tuple[np.ndarray, np.ndarray]:
    """The lee2020 example (Section IV): A and the five single-sensor banks."""
    J, b, k = 0.01, 0.007, 1.37
    A = np.array(
        [
            [0, 1, 0, 0, 0, 0],
            [-k / J, -b / J, k / J, 0, 0, 0],
            [0, 0, 0, 1, 0, 0],
            [k / J, 0, -2 * k / J, -b / J, k / J, 0],
            [0, 0, 0, 0, 0, 1],
            [0, 0, k / J, 0, -k / J, -b / J],
        ]
    )
    C = np.array(
        [
            [1, 0, 0, 0, 0, 0],
            [0, 0, 1, 0, 0, 0],
            [0, 0, 0, 0, 1, 0],
            [1, 0, -1, 0, 0, 0],
            [0, 0, 1, 0, -1, 0],
        ],
        dtype=float,
    )
    return A, C


def test_observability_matrix_blocks():
    A = np.array([[0.0, 1.0], [-2.0, -3.0]])
    C = np.array([[1.0, 0.0]])
    obs = observability_matrix(A, C)
    np.testing.assert_allclose(obs, np.vstack([C, C @ A]))
    O4 = observability_matrix(A, C[0], steps=4)  # 1-D C is one row
    assert O4.shape == (4, 2)
    np.testing.assert_allclose(O4[3], C[0] @ np.linalg.matrix_power(A, 3))


def test_matches_python_control_obsv():
    control = pytest.importorskip("control")
    A, C = three_inertia()
    np.testing.assert_allclose(observability_matrix(A, C[:2]), control.obsv(A, C[:2]))


def test_three_inertia_ranks_and_subspaces():
    A, C = three_inertia()
    ranks = [observability_rank(A, c) for c in C]
    assert ranks == [6, 4, 6, 4, 4]
    rigid = np.array([[1, 0, 1, 0, 1, 0], [0, 1, 0, 1, 0, 1]], dtype=float).T
    for i in (3, 4):  # theta differences cannot see the rigid-body motion
        U = unobservable_subspace(A, C[i])
        assert U.shape == (6, 2)
        np.testing.assert_allclose(U.T @ U, np.eye(2), atol=1e-12)
        # same span as the rigid-body subspace
        P = U @ U.T
        np.testing.assert_allclose(P @ rigid, rigid, atol=1e-9)
    U2 = unobservable_subspace(A, C[1])
    mode = np.array([[1, 0, 0, 0, -1, 0], [0, 1, 0, 0, 0, -1]], dtype=float).T
    np.testing.assert_allclose(U2 @ U2.T @ mode, mode, atol=1e-9)
    # A-invariance and U in ker C
    for c in C:
        U = unobservable_subspace(A, c)
        if U.shape[1]:
            np.testing.assert_allclose(c @ U, 0, atol=1e-12)
            np.testing.assert_allclose(U @ U.T @ A @ U, A @ U, atol=1e-9)
    assert unobservable_subspace(A, C[0]).shape == (6, 0)
    assert is_observable(A, C[0]) and not is_observable(A, C[1])


def test_observable_subspace_complements_unobservable():
    A, C = three_inertia()
    Q = observable_subspace(A, C[1])
    U = unobservable_subspace(A, C[1])
    np.testing.assert_allclose(np.hstack([Q, U]).T @ np.hstack([Q, U]), np.eye(6), atol=1e-10)


def test_zero_output_and_diagonal_cases():
    A = np.diag([1.0, 2.0, 3.0])
    assert unobservable_subspace(A, np.zeros((1, 3))).shape == (3, 3)
    U = unobservable_subspace(A, [1.0, 0.0, 1.0])
    np.testing.assert_allclose(np.abs(U[:, 0]), [0.0, 1.0, 0.0], atol=1e-12)
    # repeated eigenvalue, one output: never observable
    assert not is_observable(np.eye(2), [[1.0, 1.0]])


def test_redundant_observability_example():
    A, C = three_inertia()
    res1 = redundant_observability(A, list(C), q=1)
    assert isinstance(res1, RedundancyResult)
    assert res1.holds and res1.failing == () and res1.n_subsets == 10
    res2 = redundant_observability(A, list(C), q=2)
    assert not res2.holds
    assert res2.n_subsets == 5
    assert res2.failing == ((1,), (3,), (4,))
    res0 = redundant_observability(A, list(C), q=0)
    assert res0.holds and res0.n_subsets == 1


def test_redundant_observability_multi_sensor_banks():
    A, C = three_inertia()
    banks = [C[:2], C[2:3], C[3:]]  # banks of 2, 1 and 2 sensors
    res = redundant_observability(A, banks, q=1)
    # each single bank must be observable; the difference bank misses the rigid body
    assert not res.holds and res.failing == ((2,),) and res.n_subsets == 3
    assert redundant_observability(A, banks, q=0).holds
    np.testing.assert_allclose(stack_banks(banks), C)


def test_bad_input_non_square_A():
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of A.*\(2, 3\)"):
        observability_matrix(np.zeros((2, 3)), np.zeros((1, 3)))
    with pytest.raises(ValidationError, match="Incompatible dimensions of A"):
        redundant_observability(np.zeros((3, 2)), [np.zeros((1, 2))], q=0)
    msg = r"Incompatible dimensions of A: expected \(\*, \*\), found \(3,\)"
    with pytest.raises(ValidationError, match=msg):
        unobservable_subspace(np.zeros(3), np.zeros((1, 3)))


def test_bad_input_mismatched_C():
    A, C = three_inertia()
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of C: expected \(m, 6\)"):
        unobservable_subspace(A, np.zeros((1, 5)))
    banks = [C[0], C[1], np.zeros((1, 4))]
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of C_banks\[2\]"):
        redundant_observability(A, banks, q=1)
    with pytest.raises(ValidationError, match="sequence of per-bank"):
        redundant_observability(A, C, q=1)
    with pytest.raises(ValidationError, match="C contains NaN or infinite"):
        observability_rank(A, np.full((1, 6), np.nan))


def test_bad_input_q():
    A, C = three_inertia()
    msg = r"q is too large.*N = 5, q = 3.*largest admissible q is 2"
    with pytest.raises(ValidationError, match=msg):
        redundant_observability(A, list(C), q=3)
    with pytest.raises(ValidationError, match="q must be a non-negative integer"):
        redundant_observability(A, list(C), q=-1)
    with pytest.raises(ValidationError, match="q must be a non-negative integer"):
        redundant_observability(A, list(C), q=1.5)


def test_bad_input_steps_and_rtol():
    A, C = three_inertia()
    with pytest.raises(ValidationError, match="steps must be >= 1, found 0"):
        observability_matrix(A, C, steps=0)
    with pytest.raises(ValidationError, match=r"rtol must lie in \(0, 1\)"):
        observable_subspace(A, C, rtol=0.0)


def test_validation_error_is_value_error():
    assert issubclass(ValidationError, ValueError)


# ----------------------------------------------------------------------------- integrator
def _zero_w(t: float) -> np.ndarray:
    return np.zeros(1)


def test_discretize_zoh_matches_closed_form():
    M = np.array([[0.0, 1.0], [-4.0, -0.4]])
    E = np.array([[0.0], [1.0]])
    dt = 0.05
    Phi, Gam = discretize_zoh(M, E, dt)
    np.testing.assert_allclose(Phi, sla.expm(M * dt), rtol=1e-12)
    np.testing.assert_allclose(Gam, np.linalg.solve(M, (Phi - np.eye(2)) @ E), atol=1e-13)
    # singular M (pure integrator) is fine
    Phi0, Gam0 = discretize_zoh(np.zeros((1, 1)), np.ones((1, 1)), 0.1)
    np.testing.assert_allclose([Phi0[0, 0], Gam0[0, 0]], [1.0, 0.1])


def test_expeuler_exact_for_linear_systems_with_constant_input():
    M = np.array([[0.0, 1.0], [-400.0, -0.7]])  # lightly damped, 20 rad/s
    E_w = np.array([[0.0], [1.0]])
    x0 = np.array([1.0, 0.0])
    dt, n_steps = 0.01, 300
    out = integrate_switched_linear(
        M,
        E_w,
        lambda t: np.array([2.0]),
        np.zeros((2, 1)),
        np.zeros((1, 2)),
        np.sign,
        x0,
        dt,
        n_steps,
        record_every=100,
    )
    assert out.shape == (4, 2)
    aug = np.zeros((3, 3))
    aug[:2, :2], aug[:2, 2:] = M, 2.0 * E_w
    exact = sla.expm(aug * n_steps * dt) @ np.r_[x0, 1.0]
    np.testing.assert_allclose(out[-1], exact[:2], atol=1e-9)


def test_euler_first_order_and_unstable_above_its_step():
    M = np.array([[0.0, 1.0], [-400.0, -0.7]])
    args = (M, np.zeros((2, 1)), _zero_w, np.zeros((2, 1)), np.zeros((1, 2)), np.sign)
    x0 = np.array([1.0, 0.0])
    ref = integrate_switched_linear(*args, x0, 1e-2, 100)[-1]
    err = [
        np.abs(
            integrate_switched_linear(*args, x0, h, round(1.0 / h), method="euler")[-1] - ref
        ).max()
        for h in (2e-4, 1e-4)
    ]
    assert 1.7 < err[0] / err[1] < 2.3  # order one
    # |1 + dt*lambda| > 1 for dt > 0.7/400: the explicit Euler amplitude grows
    blow = integrate_switched_linear(*args, x0, 2e-3, 20000, method="euler")
    assert np.abs(blow[-1]).max() > 1.0
    assert np.abs(integrate_switched_linear(*args, x0, 2e-3, 20000)[-1]).max() < 1e-3


def test_sliding_mode_of_sign_feedback():
    # x' = -sgn(x): reaches 0 at t = 1, then slides (Filippov: x = 0), chattering O(dt)
    dt = 1e-3
    out = integrate_switched_linear(
        np.zeros((1, 1)),
        np.zeros((1, 1)),
        _zero_w,
        -np.ones((1, 1)),
        np.ones((1, 1)),
        np.sign,
        np.array([1.0]),
        dt,
        2000,
        record_every=100,
    )
    np.testing.assert_allclose(out[5, 0], 0.5, atol=1e-12)
    assert np.abs(out[11:, 0]).max() <= dt + 1e-12


def test_batch_columns_match_single_runs():
    M = np.array([[-1.0, 2.0], [0.0, -3.0]])
    E_s = np.array([[0.0], [1.0]])
    R = np.array([[1.0, 0.0]])
    E_w = np.eye(2)

    def w(t):
        return np.array([[np.sin(t), 0.0], [0.0, 1.0]])

    X0 = np.array([[1.0, -2.0], [0.5, 0.0]])
    both = integrate_switched_linear(M, E_w, w, E_s, R, np.sign, X0, 0.01, 50)
    for b in range(2):
        single = integrate_switched_linear(
            M, E_w, lambda t, b=b: w(t)[:, b], E_s, R, np.sign, X0[:, b], 0.01, 50
        )
        np.testing.assert_allclose(both[..., b], single, atol=1e-14)


def test_integrator_bad_input():
    M = np.zeros((2, 2))
    ok = dict(
        E_w=np.zeros((2, 1)),
        w=_zero_w,
        E_s=np.zeros((2, 1)),
        R=np.zeros((1, 2)),
        phi=np.sign,
        x0=np.zeros(2),
        dt=0.1,
        n_steps=3,
    )
    with pytest.raises(ValidationError, match="Incompatible dimensions of M"):
        integrate_switched_linear(np.zeros((2, 3)), **ok)
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of R: expected \(1, 2\)"):
        integrate_switched_linear(M, **{**ok, "R": np.zeros((2, 2))})
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of x0: expected \(2,\)"):
        integrate_switched_linear(M, **{**ok, "x0": np.zeros(3)})
    with pytest.raises(ValidationError, match="dt must be > 0, found 0.0"):
        integrate_switched_linear(M, **{**ok, "dt": 0.0})
    with pytest.raises(ValidationError, match="n_steps must be a non-negative integer"):
        integrate_switched_linear(M, **{**ok, "n_steps": 2.5})
    with pytest.raises(ValidationError, match="record_every must be a positive integer"):
        integrate_switched_linear(M, **ok, record_every=0)
    with pytest.raises(ValidationError, match=r"method must be one of \('expeuler', 'euler'\), found 'rk4'"):
        integrate_switched_linear(M, **ok, method="rk4")
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of E: expected \(2, \*\)"):
        discretize_zoh(M, np.zeros((3, 1)), 0.1)
