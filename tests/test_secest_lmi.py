"""Unit tests of secest.core.lmi: symmetric assembly, dimensions, certified solves, infeasibility."""

from __future__ import annotations

import cvxpy as cp
import numpy as np
import pytest

from secest.core import lmi
from secest.core.validation import ValidationError


def _values(expr):
    return np.asarray(expr.value, dtype=float)


def test_symmetrize_array_and_expression() -> None:
    a = np.array([[1.0, 2.0], [0.0, 3.0]])
    np.testing.assert_array_equal(lmi.symmetrize(a), [[1.0, 1.0], [1.0, 3.0]])
    x = cp.Variable((2, 2))
    x.value = a
    np.testing.assert_allclose(_values(lmi.symmetrize(x)), [[1.0, 1.0], [1.0, 3.0]])


def test_symmetrize_rejects_non_square() -> None:
    with pytest.raises(ValidationError, match=r"m must be a square matrix, found shape \(2, 3\)"):
        lmi.symmetrize(np.zeros((2, 3)))


def test_block_symmetric_numeric_matches_np_block() -> None:
    rng = np.random.default_rng(0)
    a = rng.standard_normal((3, 3))
    a = a + a.T
    b = rng.standard_normal((2, 3))
    c = np.eye(2)
    d = rng.standard_normal((1, 2))
    m = lmi.block_symmetric([[a], [b, c], [None, d, np.ones((1, 1))]])
    expected = np.block([[a, b.T, np.zeros((3, 1))], [b, c, d.T], [np.zeros((1, 3)), d, np.ones((1, 1))]])
    np.testing.assert_array_equal(m, expected)
    np.testing.assert_array_equal(m, m.T)


def test_block_symmetric_expression_every_block_symmetric_and_dimensions() -> None:
    rng = np.random.default_rng(1)
    p = cp.Variable((2, 2), symmetric=True)
    g = cp.Variable((2, 3))
    s = cp.Variable(nonneg=True)
    par = cp.Parameter((3, 3), symmetric=True)
    gam = lmi.block_diag([cp.reshape(1 - s, (1, 1), order="F"), s * par])
    row = cp.hstack([np.ones((2, 1)), g @ par])
    m = lmi.block_symmetric([[-gam], [row, -p], [0.5 * row, None, -p]])
    assert m.shape == (4 + 2 + 2, 4 + 2 + 2)
    q = rng.standard_normal((3, 3))
    par.value = q + q.T
    p.value = np.array([[2.0, 0.3], [0.3, 1.0]])
    g.value = rng.standard_normal((2, 3))
    s.value = 0.7
    val = _values(m)
    np.testing.assert_allclose(val, val.T, atol=0, rtol=0)
    # each block of the assembled matrix is where it belongs
    np.testing.assert_allclose(val[4:6, 4:6], -p.value)
    np.testing.assert_allclose(val[6:8, 4:6], 0.0)
    np.testing.assert_allclose(val[0:4, 6:8], 0.5 * _values(row).T)


def test_block_symmetric_rejects_bad_blocks() -> None:
    with pytest.raises(ValidationError, match=r"Diagonal block lower\[0\]\[0\] must be square"):
        lmi.block_symmetric([[np.zeros((2, 3))]])
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of lower\[1\]\[0\]: "
                       r"expected \(2, 2\), found \(2, 3\)"):
        lmi.block_symmetric([[np.eye(2)], [np.zeros((2, 3)), np.eye(2)]])
    with pytest.raises(ValidationError, match=r"lower\[0\]\[1\] lies above the diagonal"):
        lmi.block_symmetric([[np.eye(2), np.eye(2)], [None, np.eye(2)]])
    with pytest.raises(ValidationError, match="cannot infer the size"):
        lmi.block_symmetric([[np.eye(2)], [None, None]])
    with pytest.raises(ValidationError, match=r"lower\[1\] must hold 2 blocks"):
        lmi.block_symmetric([[np.eye(2)], []])
    with pytest.raises(ValidationError, match="sizes must have 2 entries"):
        lmi.block_symmetric([[np.eye(2)], [None, np.eye(1)]], sizes=[2])
    m = lmi.block_symmetric([[np.eye(2)], [None, None]], sizes=[2, 3])
    assert m.shape == (5, 5)


def test_block_diag_shapes_and_none() -> None:
    x = cp.Variable(nonneg=True)
    d = lmi.block_diag([x * np.eye(2), np.ones((1, 1))])
    assert d.shape == (3, 3)
    np.testing.assert_array_equal(lmi.block_diag([np.eye(1), 2 * np.eye(2)]), np.diag([1, 2, 2]))
    with pytest.raises(ValidationError, match=r"blocks\[1\] is None"):
        lmi.block_diag([np.eye(1), None])
    with pytest.raises(ValidationError, match="at least one block"):
        lmi.block_diag([])


def test_lmi_rejects_negative_margin() -> None:
    x = cp.Variable((2, 2), symmetric=True)
    assert isinstance(lmi.lmi(x, 1e-6), cp.constraints.PSD)
    with pytest.raises(ValidationError, match="eps must be a finite number >= 0, found -1"):
        lmi.lmi(x, -1)


def test_max_eigenvalue_and_bad_input() -> None:
    assert lmi.max_eigenvalue(np.diag([-1.0, 2.0])) == pytest.approx(2.0)
    with pytest.raises(ValidationError, match="m must be a square matrix"):
        lmi.max_eigenvalue(np.zeros((2, 3)))
    with pytest.raises(ValidationError, match="NaN or infinite"):
        lmi.max_eigenvalue(np.array([[np.nan]]))


def _feasible_problem():
    # min tr X  s.t.  [[-X, I], [I, -I]] <= -eps I   (i.e. X >= I + eps..., by Schur)
    x = cp.Variable((2, 2), symmetric=True)
    m = lmi.block_symmetric([[-x], [np.eye(2), -np.eye(2)]])
    prob = cp.Problem(cp.Minimize(cp.trace(x)), [lmi.lmi(m, 1e-6)])
    return prob, {"node 1": m}, x


def test_solve_certified_feasible_instance() -> None:
    prob, lmis, x = _feasible_problem()
    rep = lmi.solve_certified(prob, lmis, step=3, node=1, eps=1e-6)
    assert rep.solver == "CLARABEL" and not rep.fallback and rep.status == "optimal"
    assert rep.worst_eig <= 1e-8
    assert rep.asymmetry["node 1"] == 0.0
    assert rep.residual["node 1"] >= 0.0
    assert np.trace(x.value) == pytest.approx(2.0, abs=1e-4)


def test_solve_certified_infeasible_instance_raises_documented_error() -> None:
    x = cp.Variable((2, 2), symmetric=True)
    m1 = x + np.eye(2)  # x <= -I
    m2 = np.eye(2) - x  # x >= I
    prob = cp.Problem(cp.Minimize(0), [lmi.lmi(m1), lmi.lmi(m2)])
    with pytest.warns(UserWarning, match="falling back to SCS"):
        with pytest.raises(lmi.InfeasibleLMIError, match=r"at step 7, node 2") as info:
            lmi.solve_certified(prob, {"a": m1, "b": m2}, step=7, node=2)
    err = info.value
    assert err.step == 7 and err.node == 2
    assert set(err.statuses) == {"CLARABEL", "SCS"}
    assert "infeasible" in err.statuses["CLARABEL"]


def test_solve_certified_without_fallback_raises_at_once() -> None:
    x = cp.Variable()
    prob = cp.Problem(cp.Minimize(0), [x >= 1, x <= -1])
    m = cp.reshape(x, (1, 1), order="F") - np.ones((1, 1))
    with pytest.raises(lmi.InfeasibleLMIError, match="step None, node None"):
        lmi.solve_certified(prob, {"m": m}, fallback=None)


def test_solve_certified_bad_arguments() -> None:
    prob, lmis, _ = _feasible_problem()
    with pytest.raises(ValidationError, match="tol must be a finite number >= 0"):
        lmi.solve_certified(prob, lmis, tol=-1.0)
    with pytest.raises(ValidationError, match="eps must be a finite number >= 0"):
        lmi.solve_certified(prob, lmis, eps=float("nan"))
    with pytest.raises(ValidationError, match="lmis must name at least one LMI"):
        lmi.solve_certified(prob, {})


def test_infeasible_error_is_runtime_error() -> None:
    err = lmi.InfeasibleLMIError("x", step=1, node="all nodes", statuses={"CLARABEL": "infeasible"})
    assert isinstance(err, RuntimeError)
    assert err.statuses == {"CLARABEL": "infeasible"}
