"""ding2020: recursive secure filtering over a Gilbert-Elliott channel, distributed case.

Ding, Wang, Han and Zhang (2020), "Recursive secure filtering over Gilbert-Elliott channels in
sensor networks: the distributed case". A linear target ``x_{k+1} = A x_k + B w_k`` (1) is
measured by ``m`` nodes, ``y_{i,k} = C_i x_k + D v_{i,k}`` plus injected data (2), (5); node ``i``
hears its neighbours ``N_i`` (``adj[i, j] = 1``, weights ``H = [h_ij]``) over one shared
Gilbert-Elliott channel ``delta_k`` (failure rate ``p``, recovery rate ``q``). Every node runs a
Kalman-like filter with a consensus pull ``kappa`` (7), screens its innovation with a chi-square
test normalised by a lower covariance bound ``Gamma`` (25) and takes the gain (32) minimising an
upper bound ``Pi`` (26), (35). The functions, with the equations they implement:
:func:`received_indicator` (3)-(4); :func:`consensus_prediction` (7);
:func:`matrix_min` / :func:`matrix_max` the ``min`` / ``max`` of Section III used in (18), (27);
:func:`secure_filter_step` one step ``k -> k+1`` of every node at once, (3)-(4), (7), (17)-(19),
(25)-(26), (32), (34)-(35) (vectorised over nodes and any leading batch axes such as Monte
Carlo runs); :func:`secure_filter_node_step` the same step for one node with a plain loop over
its neighbours (the reference of Remark 4); :func:`secure_filter` the recursion over ``K``
steps; :func:`constant_gain_filter` Sec. V's comparison filter (7) with constant gains;
:func:`theorem4_condition` Theorem 4's condition (42)-(43); :func:`exact_error_covariance` the
exact error covariance ``P`` that (8) bounds, every update accepted (Lemma 1, (12));
:func:`example` the Sec. V example's matrices.

Equation numbers refer to the paper. One step ``k -> k+1`` of node ``i``:

1. received estimates (3) ``xr_j = delta_k x_j^+`` and indicator (4)
   ``d_i = 1[sum_{j in N_i} ||xr_j|| > 0]``;
2. consensus prediction (7) ``x_i^- = A x_i^+ + kappa A sum_j h_ij (xr_j - d_i x_i^+)``;
3. neighbour bound ``Xi_i = 2 sum_{j in N_i u {i}} Pi_j^+`` (19);
4. upper prediction bound (26)
   ``Pi_i^- = (1 + kappa d_i) A Pi_i^+ A^T + BB^T + d_i kappa (1 + kappa) A Xi_i A^T``;
5. gain (32) ``K_i = Pi_i^- C_i^T (C_i Pi_i^- C_i^T + DD^T)^{-1}``;
6. lower prediction bound (17) with
   ``Q1_i = (1 - kappa d_i) A Gamma_i^+ A^T + d_i kappa (kappa - 1) A Xi_i A^T``:
   ``Gamma_i^- = Q1_i + BB^T`` if ``Q1_i >= 0`` else ``BB^T``;
7. lower posterior bound (18)-(19) ``Gamma_i^+ = min{Gamma_i^-, S1_i}`` with
   ``S1_i = K DD^T K^T + (I - K C_i) Gamma_i^- (I - K C_i)^T``;
8. innovation ``eta_i = y_i - C_i x_i^-`` and test (25)
   ``theta_i = 1[eta_i^T (C_i Gamma_i^- C_i^T + DD^T)^{-1} eta_i < threshold]``;
9. update (34) ``x_i^+ = x_i^- + theta_i K_i eta_i``;
10. upper posterior bound (35) ``Pi_i^+ = Pi_i^- - theta_i K_i C_i Pi_i^-`` (the paper's
    subtraction form, the default), or with ``joseph=True`` the Joseph form
    ``Pi_i^+ = (I - theta_i K_i C_i) Pi_i^- (I - theta_i K_i C_i)^T + theta_i K_i DD^T K_i^T``,
    equal in exact arithmetic for the gain (32) and PSD by construction.

Every bound is symmetrised after it is formed.

Standing assumptions (ding2020, Section II), checked at entry when ``validate``: the graph
of ``adj`` is strongly connected without self-loops; ``h_ij > 0`` exactly on its edges and
every row of ``H`` sums to one; ``BB^T`` is PSD and ``DD^T`` positive definite; every
``Pi_i^+`` and ``Gamma_i^+`` is symmetric PSD with ``Gamma_i^+ <= Pi_i^+``; ``kappa >= 0``.

Health of the recursion, checked at every step: ``Pi_i^+`` must stay PSD and above
``Gamma_i^+`` (relative rule of :mod:`secest.core.validation`; the subtraction form (35) subtracts
two nearly equal matrices when the prior is large, the Joseph form adds PSD terms), and a node
whose test (25) rejects every measurement for ``lockout_steps``
consecutive steps is *locked out*: its estimate runs open loop and diverges (pitfall P5 of
the reproduction). Both are flagged in :class:`SecureStep` and warned about with
:class:`FilterHealthWarning`.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csgraph

from secest.core import validation as V
from secest.core.validation import ValidationError, as_matrix

__all__ = [
    "Example",
    "FilterHealthWarning",
    "SecureRun",
    "SecureStep",
    "Theorem4",
    "consensus_prediction",
    "constant_gain_filter",
    "exact_error_covariance",
    "example",
    "matrix_max",
    "matrix_min",
    "received_indicator",
    "secure_filter",
    "secure_filter_node_step",
    "secure_filter_step",
    "theorem4_condition",
]

_INSPECTION = ("Gamma", "Pi")


class FilterHealthWarning(UserWarning):
    """A bound of the secure filter stopped being PSD or ordered, or a node is locked out."""


def _operator(name: str, W: ArrayLike, m: int) -> NDArray[np.float64] | sp.csr_array:
    """``W`` as a node-mixing operator: CSR if given sparse, else a dense float array.

    Large networks should pass ``adj`` / ``weights`` as scipy.sparse matrices: every
    node-mixing product then costs O(edges) instead of O(m^2), which keeps the
    per-node cost of a step independent of the network size (Remark 4).
    """
    op = sp.csr_array(W, dtype=float) if sp.issparse(W) else as_matrix(name, W, finite=False)
    if op.shape != (m, m):
        raise ValidationError(f"Incompatible dimensions of {name}: expected {(m, m)}, found {op.shape}")
    return op


def _mix(W: NDArray[np.float64] | sp.csr_array, X: NDArray[np.float64], axis: int) -> NDArray:
    """``sum_j W[i, j] X[..., j, ...]`` over the node (or edge) axis ``axis`` of ``X``."""
    Xm = np.moveaxis(X, axis, 0)
    out = W @ Xm.reshape(Xm.shape[0], -1)
    return np.moveaxis(np.asarray(out).reshape(W.shape[0], *Xm.shape[1:]), 0, axis)


def _sym(X: NDArray[np.float64]) -> NDArray[np.float64]:
    return 0.5 * (X + np.swapaxes(X, -1, -2))


def _eigvalsh(X: NDArray[np.float64]) -> NDArray[np.float64]:
    """Ascending eigenvalues of each symmetric matrix of a stack; NaN for a matrix that is not
    finite (a bound that overflowed), so that one diverged node or run propagates NaN, which
    the caller sees as a non-finite estimate, instead of stopping every other one."""
    finite = np.isfinite(X).all(axis=(-2, -1))
    if finite.all():
        return np.linalg.eigvalsh(X)
    ev = np.linalg.eigvalsh(np.where(finite[..., None, None], X, 0.0))
    return np.where(finite[..., None], ev, np.nan)


def _leq(
    X: NDArray[np.float64],
    Y: NDArray[np.float64],
    scale: NDArray[np.float64],
    tol: float,
    strict: bool,
) -> NDArray[np.bool_]:
    """``X <= Y`` (``X < Y`` if strict) in the Loewner order, relative tolerance ``tol*scale``."""
    lam = _eigvalsh(_sym(Y - X))[..., 0]
    return lam > tol * scale if strict else lam >= -tol * scale


def _check_pair(X: ArrayLike, Y: ArrayLike, tol: float) -> tuple[NDArray, NDArray]:
    x = V.check_symmetric("X", X, rtol=V.RTOL)
    y = as_matrix("Y", Y)
    if y.shape != x.shape:
        raise ValidationError(f"Incompatible dimensions of Y: expected {x.shape}, found {y.shape}")
    V.check_symmetric("Y", y, rtol=V.RTOL)
    V.check_real("tol", tol, lower=0.0)
    return x, y


def _min_max(
    X: NDArray, Y: NDArray, tol: float, strict: bool, which: str
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    ex = _eigvalsh(_sym(X))
    ey = _eigvalsh(_sym(Y))
    scale = np.maximum(np.abs(ex).max(-1), np.abs(ey).max(-1))
    x_le_y = _leq(X, Y, scale, tol, strict=False)
    y_lt_x = _leq(Y, X, scale, tol, strict=strict) & ~x_le_y
    if which == "min":
        lam = np.minimum(ex[..., 0], ey[..., 0])
        first, second = X, Y
    else:
        lam = np.maximum(ex[..., -1], ey[..., -1])
        first, second = Y, X
    out = lam[..., None, None] * np.eye(X.shape[-1])
    out = np.where(x_le_y[..., None, None], first, out)
    out = np.where(y_lt_x[..., None, None], second, out)
    branch = np.where(x_le_y, 0, np.where(y_lt_x, 1, 2)).astype(np.int8)
    return out, branch


def matrix_min(
    X: ArrayLike, Y: ArrayLike, *, tol: float = 1e-10, strict: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """The paper's ``min{X, Y}`` of two symmetric matrices (Section III).

    ``min{X, Y} = X`` if ``X <= Y``; ``Y`` if ``Y < X``; otherwise
    ``lambda_min I`` with ``lambda_min`` the smallest eigenvalue of X and Y.
    The result is below both X and Y in the Loewner order.

    Parameters
    ----------
    X, Y : (..., n, n) array_like
        Symmetric matrices (stacks broadcast elementwise over leading axes).
    tol : float, default 1e-10
        Relative tolerance: ``X <= Y`` when
        ``lambda_min(Y - X) >= -tol * max(|eig X|, |eig Y|)``.
    strict : bool, default False
        Read the printed ``Y < X`` as a strict order (``lambda_min(X - Y) > tol*scale``);
        the default reads it as ``Y <= X``.

    Returns
    -------
    out : (..., n, n) ndarray
        ``min{X, Y}``.
    branch : (...) ndarray of int8
        0 where X was returned, 1 where Y was returned, 2 for ``lambda_min I``.

    Raises
    ------
    ValidationError
        If the shapes differ, are not square, entries are not finite, or a matrix is not
        symmetric (relative rule of :mod:`secest.core.validation`).
    """
    x, y = _check_pair(X, Y, tol)
    return _min_max(x, y, tol, V.check_bool("strict", strict), "min")


def matrix_max(
    X: ArrayLike, Y: ArrayLike, *, tol: float = 1e-10, strict: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """The paper's ``max{X, Y}`` of two symmetric matrices (Section III, used in (27)).

    ``max{X, Y} = Y`` if ``X <= Y``; ``X`` if ``Y < X``; otherwise
    ``lambda_max I`` with ``lambda_max`` the largest eigenvalue of X and Y.

    Parameters
    ----------
    X, Y : (..., n, n) array_like
        Symmetric matrices (stacks broadcast elementwise over leading axes).
    tol : float, default 1e-10
        Relative tolerance, as in :func:`matrix_min`.
    strict : bool, default False
        Strict reading of ``Y < X``.

    Returns
    -------
    out : (..., n, n) ndarray
        ``max{X, Y}``.
    branch : (...) ndarray of int8
        0 where Y was returned, 1 where X was returned, 2 for ``lambda_max I``.
    """
    x, y = _check_pair(X, Y, tol)
    return _min_max(x, y, tol, V.check_bool("strict", strict), "max")


def _check_delta(delta: ArrayLike, batch: tuple[int, ...]) -> NDArray[np.float64]:
    d = as_matrix("delta", delta)
    if not np.all((d == 0) | (d == 1)):
        raise ValidationError("delta must contain only 0 and 1")
    try:
        ok = np.broadcast_shapes(d.shape, batch) == batch
    except ValueError:
        ok = False
    if not ok:
        raise ValidationError(
            f"Incompatible dimensions of delta: expected a scalar or {batch}, found {d.shape}"
        )
    return d


def _check_states(x_post: ArrayLike, name: str = "x_post") -> NDArray[np.float64]:
    x = as_matrix(name, x_post)
    if x.ndim < 2:
        raise ValidationError(f"{name} must have shape (..., m, n), found {x.shape}")
    return x


def _csr(name: str, W: ArrayLike, m: int) -> sp.csr_array:  # m: number of nodes of x_post
    """``W`` (dense or sparse) as a finite CSR array of shape (m, m) without explicit zeros."""
    if sp.issparse(W):
        out = sp.csr_array(W, dtype=float, copy=True)  # own contiguous index arrays (csgraph needs them)
        if not np.all(np.isfinite(out.data)):
            raise ValidationError(f"{name} contains NaN or infinite entries")
    else:
        out = sp.csr_array(as_matrix(name, W, square=True))
    if out.shape != (m, m):
        raise ValidationError(
            f"Incompatible dimensions of {name}: expected {(m, m)} to match x_post, found {out.shape}"
        )
    out.eliminate_zeros()
    return out


def _check_adjacency(adj: ArrayLike, m: int) -> sp.csr_array:
    a = _csr("adj", adj, m)
    if np.any(a.data != 1) or np.any(a.diagonal() != 0):
        raise ValidationError("adj must be a 0/1 matrix with zero diagonal")
    return a


def _check_network(adj: ArrayLike, weights: ArrayLike, m: int) -> None:
    """Standing assumptions on the graph: strongly connected, H on its edges, rows summing to 1."""
    a = _check_adjacency(adj, m)
    count = csgraph.connected_components(a, directed=True, connection="strong", return_labels=False)
    if count > 1:
        raise ValidationError(f"adj must describe a strongly connected graph, found {count} components")
    h = _csr("weights", weights, m)
    if np.any(h.data < 0):
        raise ValidationError("weights must be non-negative")
    pattern = (h > 0).astype(float) - a
    pattern.eliminate_zeros()
    if pattern.nnz:
        raise ValidationError(
            "weights must be positive exactly on the edges of adj (h_ij > 0 iff (i, j) in E)"
        )
    sums = np.asarray(h.sum(axis=1)).ravel()
    bad = np.flatnonzero(np.abs(sums - 1.0) > V.RTOL * np.maximum(1.0, sums))
    if bad.size:
        raise ValidationError(f"weights must be row-stochastic, row {bad[0]} sums to {sums[bad[0]]:.6g}")


def _received(
    x: NDArray[np.float64], delta: ArrayLike, adj: NDArray | sp.csr_array
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    d = np.asarray(delta, dtype=float)
    xr = d[..., None, None] * x
    heard = _mix(adj, np.linalg.norm(xr, axis=-1), -1)
    return xr, (heard > 0).astype(float)


def received_indicator(
    x_post: ArrayLike, delta: ArrayLike, adj: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Received estimates (3) and the channel indicator (4) of every node.

    Parameters
    ----------
    x_post : (..., m, n) array_like
        Posterior estimates ``x_{j,k}^+``.
    delta : scalar or (...) array_like of {0, 1}
        Channel state ``delta_k`` (shared by all links), broadcast over batch axes.
    adj : (m, m) array_like or scipy.sparse matrix
        0/1 adjacency with zero diagonal, ``adj[i, j] = 1`` if node ``i`` receives from ``j``.

    Returns
    -------
    x_received : (..., m, n) ndarray
        ``x_{j,k}^{r+} = delta_k x_{j,k}^+`` (3).
    delta_r : (..., m) ndarray
        ``1`` where ``sum_{j in N_i} ||x_{j,k}^{r+}|| > 0``, else ``0`` (4).
    """
    x = _check_states(x_post)
    _check_delta(delta, x.shape[:-2])
    _check_adjacency(adj, x.shape[-2])
    return _received(x, delta, _operator("adj", adj, x.shape[-2]))


def consensus_prediction(
    x_post: ArrayLike,
    delta: ArrayLike,
    adj: ArrayLike,
    weights: ArrayLike,
    A: ArrayLike,
    kappa: float,
    *,
    received: ArrayLike | None = None,
    validate: bool = True,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Consensus prediction (7) of every node over the shared channel (3)-(4).

    ``x_{i,k+1}^- = A x_{i,k}^+ + kappa A xi_{i,k}`` with
    ``xi_{i,k} = sum_{j in N_i} h_ij (x_{j,k}^{r+} - delta^r_{i,k} x_{i,k}^+)``.

    Parameters
    ----------
    x_post : (..., m, n) array_like
        Posterior estimates ``x_{i,k}^+``.
    delta : scalar or (...) array_like of {0, 1}
        Channel state ``delta_k``.
    adj, weights : (m, m) array_like or scipy.sparse matrices
        0/1 adjacency of a strongly connected graph (``adj[i, j] = 1`` iff ``j in N_i``)
        and row-stochastic weights ``h_ij``, positive exactly on its edges.
    A : (n, n) array_like
        System matrix.
    kappa : float
        Coupling strength, ``kappa >= 0``.
    received : (..., m, m, n) or (..., E, n) array_like, optional
        What node ``i`` receives from ``j`` before the channel (the arena's falsified
        messages); by default ``x_{j,k}^+`` itself, as in (3). Per link,
        ``received[..., i, j, :]`` (entries off the edges are ignored; ``O(m^2)``), or per
        edge, one row for each stored entry of ``adj`` as a canonical CSR matrix (receiver by
        receiver, senders increasing; ``O(E)``).
    validate : bool, default True
        Check shapes, values and the standing assumptions on the graph.

    Returns
    -------
    x_prior : (..., m, n) ndarray
        Predictions ``x_{i,k+1}^-``.
    delta_r : (..., m) ndarray
        Indicators (4).
    """
    if V.check_bool("validate", validate):
        V.check_real("kappa", kappa, lower=0.0)
        x = _check_states(x_post)
        as_matrix("A", A, (x.shape[-1], x.shape[-1]), note="to match x_post")
        _check_delta(delta, x.shape[:-2])
        _check_network(adj, weights, x.shape[-2])
    x = np.asarray(x_post, dtype=float)
    H = _operator("weights", weights, x.shape[-2])
    row_sums = np.asarray(H.sum(axis=1)).ravel()
    if received is None:
        xr, dr = _received(x, delta, _operator("adj", adj, x.shape[-2]))
        mixed = _mix(H, xr, -2)
    else:
        mixed, dr = _received_per_link(x, received, delta, adj, weights, validate)
    xi = mixed - dr[..., None] * row_sums[:, None] * x
    return (x + kappa * xi) @ np.asarray(A, dtype=float).T, dr


def _received_per_link(
    x: NDArray[np.float64], received: ArrayLike, delta: ArrayLike, adj: ArrayLike, weights: ArrayLike,
    validate: bool,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``sum_j h_ij delta_k r_ij`` and the indicator (4) when each link carries its own message."""
    m = x.shape[-2]
    r = np.asarray(received, dtype=float)
    if r.ndim == x.ndim:
        return _received_per_edge(x, r, delta, adj, weights)
    if validate:
        r = as_matrix("received", r, (*x.shape[:-1], m, x.shape[-1]), note="to match x_post")
    d = np.asarray(delta, dtype=float)[..., None, None, None]
    xr = d * r
    a, h = (W.toarray() if sp.issparse(W) else np.asarray(W, dtype=float) for W in (adj, weights))
    heard = np.einsum("ij,...ij->...i", a, np.linalg.norm(xr, axis=-1))
    return np.einsum("ij,...ijn->...in", h, xr), (heard > 0).astype(float)


def _received_per_edge(
    x: NDArray[np.float64], r: NDArray[np.float64], delta: ArrayLike, adj: ArrayLike, weights: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`_received_per_link` with one message per edge (stored entry of ``adj``): ``O(E)``."""
    a = sp.csr_array(adj, dtype=float) if sp.issparse(adj) else sp.csr_array(np.asarray(adj, float))
    a.sum_duplicates()
    a.sort_indices()
    m, E = a.shape[0], a.nnz
    if r.shape != (*x.shape[:-2], E, x.shape[-1]):
        raise ValidationError(f"Incompatible dimensions of received: expected per-edge messages "
                              f"{(*x.shape[:-2], E, x.shape[-1])} (one per edge of adj), "
                              f"found {r.shape}")
    rows = np.repeat(np.arange(m), np.diff(a.indptr))
    h = weights[rows, a.indices] if sp.issparse(weights) else np.asarray(weights, float)[rows, a.indices]
    xr = np.asarray(delta, dtype=float)[..., None, None] * r
    per_node = sp.csr_array((np.ones(E), np.arange(E), a.indptr), shape=(m, E))  # sums in-edges
    heard = _mix(per_node, np.linalg.norm(xr, axis=-1), -1)
    mixed = _mix(per_node, np.asarray(h).ravel()[:, None] * xr, -2)
    return mixed, (heard > 0).astype(float)


class SecureStep(NamedTuple):
    """Result of one step ``k -> k+1`` of the secure filter (all nodes).

    Attributes
    ----------
    x_post, Pi_post, Gamma_post : ndarray
        Estimates and bounds at ``k+1`` (34), (35), (18).
    x_prior, Pi_prior, Gamma_prior : ndarray
        Predictions and bounds (7), (26), (17).
    gain : (..., m, n, ny) ndarray
        Gains (32).
    theta : (..., m) ndarray
        Detector outcomes (25), 1 = accepted.
    nis : (..., m) ndarray
        Test statistics ``eta^T Gamma_eta^{-1} eta`` (or with ``Pi_eta``).
    delta_r : (..., m) ndarray
        Channel indicators (4) at ``k``.
    q1_psd : (..., m) ndarray of bool
        Where ``Q1 >= 0``, so (17) took its first branch.
    min_branch : (..., m) ndarray of int8
        Branch of ``min{Gamma^-, S1}`` in (18), see :func:`matrix_min`.
    joseph : bool
        Whether (35) was evaluated in Joseph form (``False``: the paper's subtraction form).
    Pi_psd : (..., m) ndarray of bool
        Where ``Pi^+`` is PSD (relative tolerance ``tol``); ``False`` is a failed bound.
    ordered : (..., m) ndarray of bool
        Where ``Gamma^+ <= Pi^+`` (relative tolerance ``tol``); ``False`` is a failed bound.
    rejections : (..., m) ndarray of int
        Consecutive rejected measurements up to ``k+1`` (0 where ``theta = 1``).
    locked_out : (..., m) ndarray of bool
        Where ``rejections >= lockout_steps``.
    """

    x_post: NDArray[np.float64]
    Pi_post: NDArray[np.float64]
    Gamma_post: NDArray[np.float64]
    x_prior: NDArray[np.float64]
    Pi_prior: NDArray[np.float64]
    Gamma_prior: NDArray[np.float64]
    gain: NDArray[np.float64]
    theta: NDArray[np.float64]
    nis: NDArray[np.float64]
    delta_r: NDArray[np.float64]
    q1_psd: NDArray[np.bool_]
    min_branch: NDArray[np.int8]
    joseph: bool
    Pi_psd: NDArray[np.bool_]
    ordered: NDArray[np.bool_]
    rejections: NDArray[np.int64]
    locked_out: NDArray[np.bool_]


def _check_scalars(
    kappa: float, threshold: float, inspection_cov: str, tol: float, flags: dict[str, object]
) -> None:
    V.check_real("kappa", kappa, lower=0.0)
    V.check_real("threshold", threshold, lower=0.0, lower_open=True)
    V.check_choice("inspection_cov", inspection_cov, _INSPECTION)
    V.check_real("tol", tol, lower=0.0)
    for name, value in flags.items():
        V.check_bool(name, value)


def _validate_step(x_post, Pi_post, Gamma_post, delta, y, A, BBt, C, DDt, adj, weights, tol,
                   names=("x_post", "Pi_post", "Gamma_post")):
    """Shapes, finiteness and the standing assumptions of ding2020 (module docstring)."""
    x_name, pi_name, gamma_name = names
    x = _check_states(x_post, x_name)
    m, n = x.shape[-2:]
    batch = x.shape[:-2]
    note = f"to match {x_name}"
    as_matrix("A", A, (n, n), note=note)
    V.check_psd("BBt", as_matrix("BBt", BBt, (n, n), note=note), tol=tol)
    C = as_matrix("C", C, (m, None, n), note=note)
    ny = C.shape[1]
    V.check_psd("DDt", as_matrix("DDt", DDt, (ny, ny), note="to match C"), strict=True, tol=tol)
    Pi = V.check_psd(pi_name, as_matrix(pi_name, Pi_post, (*batch, m, n, n), note=note), tol=tol)
    Gam = V.check_psd(gamma_name, as_matrix(gamma_name, Gamma_post, (*batch, m, n, n), note=note),
                      tol=tol)
    V.check_loewner_order(gamma_name, Gam, pi_name, Pi, tol=tol)
    as_matrix("y", y, (*batch, m, ny), note=f"{note} and C")
    _check_delta(delta, batch)
    _check_network(adj, weights, m)


def _check_rejections(rejections: ArrayLike | None, shape: tuple[int, ...]) -> NDArray[np.int64]:
    if rejections is None:
        return np.zeros(shape, dtype=np.int64)
    r = as_matrix("rejections", rejections, shape)
    if np.any(r < 0) or np.any(r != np.round(r)):
        raise ValidationError("rejections must hold non-negative integer counts")
    return r.astype(np.int64)


def _health(
    Pi: NDArray, Gam: NDArray, theta: NDArray, rejections: NDArray, lockout_steps: int, tol: float
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """PSD and order of the new bounds, and the lockout counters (module docstring)."""
    ev = _eigvalsh(Pi)
    Pi_psd = ev[..., 0] >= -tol * np.abs(ev).max(axis=-1)
    gap = _eigvalsh(Pi - Gam)[..., 0]
    scale = np.maximum(np.abs(ev).max(axis=-1), np.abs(_eigvalsh(Gam)).max(axis=-1))
    ordered = gap >= -tol * scale
    count = np.where(theta == 1, 0, rejections + 1)
    if not (np.all(Pi_psd) and np.all(ordered)):
        warnings.warn(
            f"secure filter: Pi^+ lost PSD at {int(np.sum(~Pi_psd))} and Gamma^+ <= Pi^+ failed at "
            f"{int(np.sum(~ordered))} node(s); consider joseph=True",
            FilterHealthWarning,
            stacklevel=3,
        )
    if np.any(count == lockout_steps):
        warnings.warn(
            f"secure filter: {int(np.sum(count == lockout_steps))} node(s) rejected every measurement "
            f"for lockout_steps = {lockout_steps} consecutive steps (locked out, open loop)",
            FilterHealthWarning,
            stacklevel=3,
        )
    return Pi_psd, ordered, count, count >= lockout_steps


def secure_filter_step(
    x_post: ArrayLike,
    Pi_post: ArrayLike,
    Gamma_post: ArrayLike,
    delta: ArrayLike,
    y: ArrayLike,
    *,
    A: ArrayLike,
    BBt: ArrayLike,
    C: ArrayLike,
    DDt: ArrayLike,
    adj: ArrayLike,
    weights: ArrayLike,
    kappa: float,
    threshold: float,
    inspect: bool = True,
    inspection_cov: str = "Gamma",
    tol: float = 1e-10,
    strict: bool = False,
    joseph: bool = False,
    rejections: ArrayLike | None = None,
    lockout_steps: int = 10,
    received: ArrayLike | None = None,
    validate: bool = True,
) -> SecureStep:
    """One step ``k -> k+1`` of the distributed secure filter (7)/(34), all nodes at once.

    Vectorised over the ``m`` nodes and over any leading batch axes (e.g.
    Monte Carlo runs); see the module docstring for the ten sub-steps, their
    equation numbers, the standing assumptions checked at entry and the health checks.

    Parameters
    ----------
    x_post : (..., m, n) array_like
        Posterior estimates ``x_{i,k}^+``.
    Pi_post, Gamma_post : (..., m, n, n) array_like
        Upper bounds ``Pi_{i,k}^+`` (35) and lower bounds ``Gamma_{i,k}^+`` (18): symmetric
        PSD with ``Gamma_{i,k}^+ <= Pi_{i,k}^+``.
    delta : scalar or (...) array_like of {0, 1}
        Shared Gilbert-Elliott channel state ``delta_k``.
    y : (..., m, ny) array_like
        Measurements ``y_{i,k+1}`` (including any injected attack).
    A : (n, n) array_like
        System matrix of (1).
    BBt : (n, n) array_like
        Process-noise covariance ``B B^T`` of (1), symmetric PSD.
    C : (m, ny, n) array_like
        Measurement matrices ``C_i`` of (2).
    DDt : (ny, ny) array_like
        Measurement-noise covariance ``D D^T``, symmetric positive definite.
    adj : (m, m) array_like or scipy.sparse matrix (sparse: O(edges) per step)
        0/1 adjacency of a strongly connected graph, ``adj[i, j] = 1`` iff ``j in N_i``
        (``i`` receives from ``j``), zero diagonal.
    weights : (m, m) array_like or scipy.sparse matrix
        ``H = [h_ij]``, positive exactly on the edges, rows summing to one (e.g.
        :func:`secest.core.graphs.row_stochastic_weights` at its default).
    kappa : float
        Coupling strength ``kappa >= 0``.
    threshold : float
        Chi-square threshold of (25), positive.
    inspect : bool, default True
        Apply the test (25); ``False`` sets ``theta = 1`` in (34) and (35) (no inspection).
    inspection_cov : {"Gamma", "Pi"}, default "Gamma"
        Normalise the test with the lower bound ``Gamma_eta`` (the paper's (25)) or,
        as an ablation that is not the paper's scheme, with ``Pi_eta``.
    tol : float, default 1e-10
        Relative tolerance of every matrix test: the standing assumptions, the PSD test
        in (17), :func:`matrix_min` and the health flags.
    strict : bool, default False
        Strict reading of ``Y < X`` in the min operation of (18).
    joseph : bool, default False
        Evaluate (35) in Joseph form instead of the paper's subtraction form; recorded in
        :attr:`SecureStep.joseph`.
    rejections : (..., m) array_like of int, optional
        Consecutive rejected measurements of every node before this step (the
        ``rejections`` of the previous step's result); default zeros.
    lockout_steps : int, default 10
        A node is flagged (``locked_out``) and a :class:`FilterHealthWarning` is issued
        when it has rejected this many consecutive measurements.
    received : (..., m, m, n) or (..., E, n) array_like, optional
        Per-link messages ``received[..., i, j, :]``, or per-edge ones (one per stored entry of
        ``adj`` as canonical CSR), replacing ``x_{j,k}^+`` in (3), e.g. falsified in transit
        (see :func:`consensus_prediction`); by default (3) as printed.
    validate : bool, default True
        Check shapes, values and the standing assumptions (switch off inside tight loops;
        the health checks run at every step regardless).

    Returns
    -------
    SecureStep

    Raises
    ------
    ValidationError
        If shapes disagree, a value is out of range or a standing assumption fails
        (when ``validate``).
    """
    validate = V.check_bool("validate", validate)
    if validate:
        _check_scalars(kappa, threshold, inspection_cov, tol, {"inspect": inspect, "strict": strict,
                                                                "joseph": joseph, "validate": validate})
        V.check_int("lockout_steps", lockout_steps, minimum=1)
        _validate_step(x_post, Pi_post, Gamma_post, delta, y, A, BBt, C, DDt, adj, weights, tol)
        if received is not None and np.ndim(received) != np.ndim(x_post):  # per edge: checked below
            shape = np.shape(x_post)
            as_matrix("received", received, (*shape[:-1], shape[-2], shape[-1]), note="to match x_post")
    x = np.asarray(x_post, dtype=float)
    Pi = np.asarray(Pi_post, dtype=float)
    Gam = np.asarray(Gamma_post, dtype=float)
    y = np.asarray(y, dtype=float)
    A = np.asarray(A, dtype=float)
    BBt = np.asarray(BBt, dtype=float)
    C = np.asarray(C, dtype=float)
    DDt = np.asarray(DDt, dtype=float)
    m = x.shape[-2]
    adj = _operator("adj", adj, m)
    H = _operator("weights", weights, m)
    n = x.shape[-1]
    Ct = np.swapaxes(C, -1, -2)
    rejections = _check_rejections(rejections, x.shape[:-1])

    # (3), (4), (7): channel indicator and consensus prediction
    x_prior, dr = consensus_prediction(x, delta, adj, H, A, kappa, received=received, validate=False)
    d = dr[..., None, None]
    # (19): Xi_i = 2 sum_{j in N_i u {i}} Pi_j^+
    AXiA = A @ (2.0 * (Pi + _mix(adj, Pi, -3))) @ A.T
    # (26): upper prediction bound
    Pi_prior = _sym((1 + kappa * d) * (A @ Pi @ A.T) + BBt + d * kappa * (1 + kappa) * AXiA)
    # (32): gain K = Pi^- C^T Pi_eta^{-1}
    PCt = Pi_prior @ Ct
    Pi_eta = C @ PCt + DDt
    K = np.swapaxes(np.linalg.solve(Pi_eta, np.swapaxes(PCt, -1, -2)), -1, -2)
    # (17), (19): lower prediction bound
    Q1 = (1 - kappa * d) * (A @ Gam @ A.T) + d * kappa * (kappa - 1) * AXiA
    ev = _eigvalsh(_sym(Q1))
    q1_psd = ev[..., 0] >= -tol * np.abs(ev).max(axis=-1)
    Gamma_prior = _sym(np.where(q1_psd[..., None, None], Q1 + BBt, BBt))
    # (18)-(19): lower posterior bound
    IKC = np.eye(n) - K @ C
    S1 = _sym(K @ DDt @ np.swapaxes(K, -1, -2) + IKC @ Gamma_prior @ np.swapaxes(IKC, -1, -2))
    Gamma_new, branch = _min_max(Gamma_prior, S1, tol, strict, "min")
    # innovation and test (25)
    eta = y - np.einsum("iyn,...in->...iy", C, x_prior)
    S_test = C @ Gamma_prior @ Ct + DDt if inspection_cov == "Gamma" else Pi_eta
    nis = np.einsum("...y,...y->...", eta, np.linalg.solve(S_test, eta[..., None])[..., 0])
    theta = (nis < threshold).astype(float) if inspect else np.ones_like(nis)
    # (34): update; (35): upper posterior bound, subtraction (paper) or Joseph form
    x_new = x_prior + theta[..., None] * np.einsum("...iny,...iy->...in", K, eta)
    tK = theta[..., None, None] * K
    if joseph:
        I_tKC = np.eye(n) - tK @ C
        Pi_new = _sym(I_tKC @ Pi_prior @ np.swapaxes(I_tKC, -1, -2) + tK @ DDt @ np.swapaxes(tK, -1, -2))
    else:
        Pi_new = _sym(Pi_prior - tK @ C @ Pi_prior)
    Gamma_new = _sym(Gamma_new)
    health = _health(Pi_new, Gamma_new, theta, rejections, lockout_steps, tol)
    return SecureStep(x_new, Pi_new, Gamma_new, x_prior, Pi_prior, Gamma_prior, K, theta, nis, dr,
                      q1_psd, branch, bool(joseph), *health)


def _validate_node(x_self, Pi_self, Gamma_self, x_nbrs, Pi_nbrs, h_nbrs, delta, y_i, A, BBt, C_i, DDt,
                   tol):
    """Shapes, finiteness and the standing assumptions one node can see."""
    x_i = as_matrix("x_self", x_self, (None,))
    n = x_i.shape[0]
    note = "to match x_self"
    P_i = V.check_psd("Pi_self", as_matrix("Pi_self", Pi_self, (n, n), note=note), tol=tol)
    G_i = V.check_psd("Gamma_self", as_matrix("Gamma_self", Gamma_self, (n, n), note=note), tol=tol)
    V.check_loewner_order("Gamma_self", G_i, "Pi_self", P_i, tol=tol)
    nb = as_matrix("x_nbrs", x_nbrs, (None, n), note=note).shape[0]
    V.check_psd("Pi_nbrs", as_matrix("Pi_nbrs", Pi_nbrs, (nb, n, n)), tol=tol)
    hs = as_matrix("h_nbrs", h_nbrs, (nb,))
    if np.any(hs <= 0) or abs(hs.sum() - 1.0) > V.RTOL * max(1.0, float(hs.sum())):
        raise ValidationError(f"h_nbrs must be positive and sum to 1, found sum {hs.sum():.6g}")
    as_matrix("A", A, (n, n), note=note)
    V.check_psd("BBt", as_matrix("BBt", BBt, (n, n), note=note), tol=tol)
    ny = as_matrix("C_i", C_i, (None, n), note=note).shape[0]
    V.check_psd("DDt", as_matrix("DDt", DDt, (ny, ny), note="to match C_i"), strict=True, tol=tol)
    as_matrix("y_i", y_i, (ny,), note="to match C_i")
    V.check_choice("delta", delta, (0, 1))


def secure_filter_node_step(
    x_self: ArrayLike,
    Pi_self: ArrayLike,
    Gamma_self: ArrayLike,
    x_nbrs: ArrayLike,
    Pi_nbrs: ArrayLike,
    h_nbrs: ArrayLike,
    delta: int,
    y_i: ArrayLike,
    *,
    A: ArrayLike,
    BBt: ArrayLike,
    C_i: ArrayLike,
    DDt: ArrayLike,
    kappa: float,
    threshold: float,
    inspect: bool = True,
    inspection_cov: str = "Gamma",
    tol: float = 1e-10,
    strict: bool = False,
    joseph: bool = False,
    validate: bool = True,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]:
    """One step ``k -> k+1`` of node ``i`` alone: the plain per-node reference.

    Uses only the node's own quantities and those it receives from its
    neighbours ``N_i`` (one loop over neighbours), as Remark 4 describes; the
    arithmetic follows the module docstring step by step, without vectorisation.
    The standing assumptions that one node can see are checked at entry.

    Parameters
    ----------
    x_self : (n,) array_like
        ``x_{i,k}^+``.
    Pi_self, Gamma_self : (n, n) array_like
        ``Pi_{i,k}^+`` and ``Gamma_{i,k}^+``, symmetric PSD, ``Gamma_{i,k}^+ <= Pi_{i,k}^+``.
    x_nbrs : (``|N_i|``, n) array_like
        Neighbours' estimates ``x_{j,k}^+`` (before the channel; (3) is applied here);
        at least one neighbour.
    Pi_nbrs : (``|N_i|``, n, n) array_like
        Neighbours' bounds ``Pi_{j,k}^+`` (sent in the same packet as ``x_{j,k}^+``), PSD.
    h_nbrs : (``|N_i|``,) array_like
        Weights ``h_ij`` of the neighbours, positive and summing to one.
    delta : {0, 1}
        Channel state ``delta_k``.
    y_i : (ny,) array_like
        Measurement ``y_{i,k+1}``.
    A, BBt, DDt, kappa, threshold, inspect, inspection_cov, tol, strict, joseph, validate
        As in :func:`secure_filter_step` (``validate=False`` for timing loops such as Remark 4's).
    C_i : (ny, n) array_like
        Measurement matrix of node ``i``.

    Returns
    -------
    x_post : (n,) ndarray
    Pi_post, Gamma_post : (n, n) ndarray
    theta : int
        Detector outcome (25), 1 = accepted.

    Raises
    ------
    ValidationError
        If shapes disagree, a value is out of range or a standing assumption fails
        (when ``validate``).
    """
    if V.check_bool("validate", validate):
        _check_scalars(kappa, threshold, inspection_cov, tol, {"inspect": inspect, "strict": strict,
                                                                "joseph": joseph, "validate": validate})
        _validate_node(x_self, Pi_self, Gamma_self, x_nbrs, Pi_nbrs, h_nbrs, delta, y_i, A, BBt, C_i,
                       DDt, tol)
    x_i, P_i, G_i, xs, Ps, hs, y_i, A, BBt, C_i, DDt = (
        np.asarray(v, dtype=float)
        for v in (x_self, Pi_self, Gamma_self, x_nbrs, Pi_nbrs, h_nbrs, y_i, A, BBt, C_i, DDt)
    )
    n, nb = x_i.shape[0], xs.shape[0]

    # (3): what node i receives; (4): indicator
    received = [delta * xs[j] for j in range(nb)]
    d = 1.0 if sum(float(np.linalg.norm(r)) for r in received) > 0 else 0.0
    # (7): consensus prediction
    xi = np.zeros(n)
    for j in range(nb):
        xi = xi + hs[j] * (received[j] - d * x_i)
    x_prior = A @ x_i + kappa * (A @ xi)
    # (19): Xi = 2 (Pi_i + sum_j Pi_j)
    Xi = 2.0 * P_i
    for j in range(nb):
        Xi = Xi + 2.0 * Ps[j]
    AXiA = A @ Xi @ A.T
    # (26)
    Pi_prior = _sym((1 + kappa * d) * (A @ P_i @ A.T) + BBt + d * kappa * (1 + kappa) * AXiA)
    # (32)
    Pi_eta = C_i @ Pi_prior @ C_i.T + DDt
    K = Pi_prior @ C_i.T @ np.linalg.inv(Pi_eta)
    # (17)
    Q1 = (1 - kappa * d) * (A @ G_i @ A.T) + d * kappa * (kappa - 1) * AXiA
    ev = _eigvalsh(_sym(Q1))
    Gamma_prior = _sym(Q1 + BBt) if ev[0] >= -tol * np.abs(ev).max() else BBt.copy()
    # (18)-(19)
    IKC = np.eye(n) - K @ C_i
    S1 = _sym(K @ DDt @ K.T + IKC @ Gamma_prior @ IKC.T)
    Gamma_post, _ = _min_max(Gamma_prior, S1, tol, strict, "min")
    # (25)
    eta = y_i - C_i @ x_prior
    S_test = C_i @ Gamma_prior @ C_i.T + DDt if inspection_cov == "Gamma" else Pi_eta
    nis = float(eta @ np.linalg.inv(S_test) @ eta)
    theta = 1 if (nis < threshold or not inspect) else 0
    # (34), (35): subtraction (paper) or Joseph form
    x_post = x_prior + theta * (K @ eta)
    if joseph:
        I_tKC = np.eye(n) - theta * (K @ C_i)
        Pi_post = _sym(I_tKC @ Pi_prior @ I_tKC.T + theta * (K @ DDt @ K.T))
    else:
        Pi_post = _sym(Pi_prior - theta * (K @ C_i @ Pi_prior))
    return x_post, Pi_post, _sym(Gamma_post), theta


# ---------------------------------------------------------------------------- the whole recursion


class SecureRun(NamedTuple):
    """Result of :func:`secure_filter`: the recursion (7)/(34) run over ``K`` steps.

    Attributes
    ----------
    x : (..., K+1, m, n) ndarray
        Estimates ``x_{i,k}^+`` for ``k = 0..K`` (``x[..., 0, :, :]`` is ``x0``).
    theta : (..., K+1, m) ndarray
        Detector outcomes (25), 1 = accepted; ``theta[..., 0, :] = 1`` (no test at ``k = 0``).
    delta_r : (..., K, m) ndarray
        Channel indicators (4) of the predictions ``k -> k+1``, ``k = 0..K-1``.
    Pi_end, Gamma_end : (..., m, n, n) ndarray
        The bounds ``Pi_{i,K}^+`` and ``Gamma_{i,K}^+`` after the last step.
    history : dict of str to ndarray
        For every :class:`SecureStep` field named in ``keep``, its values at ``k = 1..K`` stacked
        on a time axis right after the batch axes (as in ``x``).
    """

    x: NDArray[np.float64]
    theta: NDArray[np.float64]
    delta_r: NDArray[np.float64]
    Pi_end: NDArray[np.float64]
    Gamma_end: NDArray[np.float64]
    history: dict[str, NDArray]


def _check_sequence(x0: ArrayLike, delta: ArrayLike, y: ArrayLike, trailing: int) -> tuple[NDArray, int]:
    """``y`` as (..., K+1, m[, ny]) matching ``x0`` (..., m, n), ``delta`` (..., >= K): (y, K)."""
    x = _check_states(x0, "x0")
    batch, m = x.shape[:-2], x.shape[-2]
    y = as_matrix("y", y)
    b = len(batch)
    if y.ndim != b + 2 + trailing or y.shape[:b] != batch or y.shape[b + 1] != m:
        what = "(..., K+1, m, ny)" if trailing else "(..., K+1, m)"
        raise ValidationError(
            f"Incompatible dimensions of y: expected {what} with batch {batch} and m = {m} to match x0, "
            f"found {y.shape}")
    steps = y.shape[b] - 1
    if steps < 1:
        raise ValidationError(f"y must hold at least two instants (k = 0 and k = 1), found {steps + 1}")
    d = as_matrix("delta", delta)
    if d.ndim < 1 or d.shape[-1] < steps:
        raise ValidationError(
            f"Incompatible dimensions of delta: expected (..., >= {steps}) to match y, found {d.shape}")
    if not np.all((d == 0) | (d == 1)):
        raise ValidationError("delta must contain only 0 and 1")
    _check_delta(d[..., 0], batch)
    return y, steps


_KEEP = tuple(f for f in SecureStep._fields if f != "joseph")


def secure_filter(
    x0: ArrayLike,
    Pi0: ArrayLike,
    Gamma0: ArrayLike,
    delta: ArrayLike,
    y: ArrayLike,
    *,
    A: ArrayLike,
    BBt: ArrayLike,
    C: ArrayLike,
    DDt: ArrayLike,
    adj: ArrayLike,
    weights: ArrayLike,
    kappa: float,
    threshold: float,
    inspect: bool = True,
    inspection_cov: str = "Gamma",
    tol: float = 1e-10,
    strict: bool = False,
    joseph: bool = False,
    received: Callable[[int, NDArray[np.float64]], ArrayLike] | None = None,
    keep: Sequence[str] = (),
    validate: bool = True,
) -> SecureRun:
    """The distributed secure filter (7)/(34) over ``K`` steps: :func:`secure_filter_step` in a loop.

    Starts from ``x_{i,0}^+ = x0``, ``Pi_{i,0}^+ = Pi0``, ``Gamma_{i,0}^+ = Gamma0`` and takes the
    first measurement update at ``k = 1`` (the prediction ``0 -> 1`` uses ``delta_0``).

    Parameters
    ----------
    x0 : (..., m, n) array_like
        Initial estimates; leading axes are a batch (e.g. Monte Carlo runs).
    Pi0, Gamma0 : (..., m, n, n) array_like
        Initial upper and lower bounds, as ``Pi_post`` / ``Gamma_post`` of :func:`secure_filter_step`.
    delta : (..., >= K) array_like of {0, 1}
        Channel states ``delta_k``, ``k = 0..K-1`` (time last; extra entries are ignored); without
        batch axes one sequence is shared by the whole batch.
    y : (..., K+1, m, ny) array_like
        Measurements ``y_{i,k}`` (``y[..., 0, :, :]`` is not used).
    A, BBt, C, DDt, adj, weights, kappa, threshold, inspect, inspection_cov, tol, strict, joseph
        As in :func:`secure_filter_step`.
    received : callable ``(k, x_post) -> (..., m, m, n) or (..., E, n)``, optional
        Per-link or per-edge messages of step ``k`` (see :func:`secure_filter_step`); default
        (3) as printed. With sparse ``adj`` and ``weights`` and per-edge messages a step costs
        ``O(E)``.
    keep : sequence of str, default ()
        Fields of :class:`SecureStep` to record at every step (e.g. ``("Pi_post", "gain")``).
    validate : bool, default True
        Check the arguments and the standing assumptions at the first step (later steps skip them).

    Returns
    -------
    SecureRun

    Raises
    ------
    ValidationError
        If shapes disagree, a value is out of range or a standing assumption fails (when ``validate``).
    """
    validate = V.check_bool("validate", validate)
    if isinstance(keep, str) or not isinstance(keep, Sequence):
        raise ValidationError(f"keep must be a sequence of SecureStep field names, found {keep!r}")
    for name in keep:
        V.check_choice("keep", name, _KEEP)
    if received is not None:
        V.check_callable("received", received)
    if validate:
        _check_scalars(kappa, threshold, inspection_cov, tol, {"inspect": inspect, "strict": strict,
                                                                "joseph": joseph})
        y, steps = _check_sequence(x0, delta, y, trailing=1)
        d0 = np.asarray(delta, dtype=float)[..., 0]
        _validate_step(x0, Pi0, Gamma0, d0, y[..., 1, :, :], A, BBt, C, DDt, adj, weights, tol,
                       names=("x0", "Pi0", "Gamma0"))
    else:
        y = np.asarray(y, dtype=float)
        steps = y.shape[-3] - 1
    d = np.asarray(delta, dtype=float)
    x = np.array(x0, dtype=float)
    Pi = np.array(Pi0, dtype=float)
    Gam = np.array(Gamma0, dtype=float)
    axis = x.ndim - 2  # the time axis of every stacked output
    xs, thetas, drs = [x], [np.ones(x.shape[:-1])], []
    hist: dict[str, list] = {name: [] for name in keep}
    for k in range(steps):
        st = secure_filter_step(
            x, Pi, Gam, d[..., k], y[..., k + 1, :, :], A=A, BBt=BBt, C=C, DDt=DDt, adj=adj,
            weights=weights, kappa=kappa, threshold=threshold, inspect=inspect,
            inspection_cov=inspection_cov, tol=tol, strict=strict, joseph=joseph,
            received=None if received is None else received(k, x), validate=validate and k == 0)
        x, Pi, Gam = st.x_post, st.Pi_post, st.Gamma_post
        xs.append(x)
        thetas.append(st.theta)
        drs.append(st.delta_r)
        for name in keep:
            hist[name].append(getattr(st, name))
    return SecureRun(np.stack(xs, axis=axis), np.stack(thetas, axis=axis), np.stack(drs, axis=axis),
                     Pi, Gam, {name: np.stack(v, axis=axis) for name, v in hist.items()})


_FORMS = ("corrector", "predictor")


def constant_gain_filter(
    x0: ArrayLike,
    delta: ArrayLike,
    y: ArrayLike,
    *,
    A: ArrayLike,
    C: ArrayLike,
    gains: ArrayLike,
    adj: ArrayLike,
    weights: ArrayLike,
    kappa: float,
    form: str = "corrector",
    validate: bool = True,
) -> NDArray[np.float64]:
    """The comparison filter of Sec. V: the prediction (7) with constant gains and no detector.

    The paper takes its gains from the LMI designs of its refs. [9], [13] and prints them without
    the filter's structure, so two readings are offered (scalar measurements, as in Sec. V):

    * ``"corrector"``: ``x_{i,k+1}^+ = x_{i,k+1}^- + K_i (y_{i,k+1} - C_i x_{i,k+1}^-)``;
    * ``"predictor"``: ``x_{i,k+1} = A x_{i,k} + kappa A xi_{i,k} + K_i (y_{i,k} - C_i x_{i,k})``,

    with ``x_{i,k+1}^-`` the consensus prediction (7) over the shared channel (3)-(4).

    Parameters
    ----------
    x0 : (..., m, n) array_like
        Initial estimates; leading axes are a batch.
    delta : (..., >= K) array_like of {0, 1}
        Channel states ``delta_k``, time last, as in :func:`secure_filter`.
    y : (..., K+1, m) array_like
        Scalar measurements ``y_{i,k}``.
    A : (n, n) array_like
        System matrix.
    C : (m, n) array_like
        Measurement rows ``C_i``.
    gains : (m, n) array_like
        Constant gains ``K_i``.
    adj, weights, kappa
        As in :func:`consensus_prediction`.
    form : {"corrector", "predictor"}, default "corrector"
        The reading of the structure.
    validate : bool, default True
        Check the arguments (and the standing assumptions on the graph at the first step).

    Returns
    -------
    (..., K+1, m, n) ndarray
        The estimates for ``k = 0..K``.

    Raises
    ------
    ValidationError
        If shapes disagree or a value is out of range (when ``validate``).
    """
    if V.check_bool("validate", validate):
        V.check_choice("form", form, _FORMS)
        y, steps = _check_sequence(x0, delta, y, trailing=0)
        m, n = np.shape(x0)[-2:]
        as_matrix("C", C, (m, n), note="to match x0")
        as_matrix("gains", gains, (m, n), note="to match x0")
    else:
        y = np.asarray(y, dtype=float)
        steps = y.shape[-2] - 1
    d = np.asarray(delta, dtype=float)
    C = np.asarray(C, dtype=float)
    gains = np.asarray(gains, dtype=float)
    x_post = np.array(x0, dtype=float)
    axis = x_post.ndim - 2
    xs = [x_post]
    for k in range(steps):
        # (3), (4), (7): consensus prediction over the shared channel
        x_prior, _ = consensus_prediction(x_post, d[..., k], adj, weights, A, kappa,
                                          validate=validate and k == 0)
        if form == "predictor":  # x_{k+1} = A x_k + kappa A xi_k + K_i (y_k - C_i x_k)
            eta = y[..., k, :] - np.einsum("in,...in->...i", C, x_post)
        else:  # corrector: x+ = x- + K_i (y_{k+1} - C_i x-)
            eta = y[..., k + 1, :] - np.einsum("in,...in->...i", C, x_prior)
        x_post = x_prior + gains * eta[..., None]
        xs.append(x_post)
    return np.stack(xs, axis=axis)


class Theorem4(NamedTuple):
    """The quantities of Theorem 4's condition (42)-(43), see :func:`theorem4_condition`.

    Attributes
    ----------
    xi_q, xi_p : float
        ``xi_q`` (42) and ``xi_p`` (43); the condition is ``xi_q < 1`` and ``xi_p < 1``.
    zeta : float
        ``((1 + nu) c_lo^2 + c_hi^2 (1 - sigma)) / c_lo^2``.
    alpha_bar : float
        ``||A||`` (spectral norm).
    c_lo, c_hi : float
        Smallest and largest ``||C_i||``.
    """

    xi_q: float
    xi_p: float
    zeta: float
    alpha_bar: float
    c_lo: float
    c_hi: float


def theorem4_condition(
    A: ArrayLike,
    C: ArrayLike,
    *,
    p: float,
    q: float,
    kappa: float,
    n_bar: int,
    nu: float,
    sigma: float,
    factor: float = 1.0,
) -> Theorem4:
    """Theorem 4's sufficient condition (42)-(43) for the mean upper bound to stay bounded (41).

    ``xi_q = zeta alpha^2 (1 - q + q (1 + kappa)(1 + factor kappa N_bar))`` (42) and
    ``xi_p = zeta alpha^2 (p + (1 - p)(1 + kappa)(1 + factor kappa N_bar))`` (43), with
    ``zeta = ((1 + nu) c_lo^2 + c_hi^2 (1 - sigma)) / c_lo^2``, ``alpha = ||A||`` and ``c_lo``,
    ``c_hi`` the extreme ``||C_i||``. ``factor = 1`` is the printed form; ``factor = 2`` is the form
    the proof ((36), (44)-(47), with the factor 2 of ``Xi = 2 sum Pi_j^+``) implies (erratum E9).

    Parameters
    ----------
    A : (n, n) array_like
        System matrix.
    C : (m, n) array_like
        Measurement rows ``C_i`` (scalar measurements), none zero.
    p, q : float
        Failure and recovery rates of the Gilbert-Elliott chain, in [0, 1].
    kappa : float
        Coupling strength, ``kappa >= 0``.
    n_bar : int
        ``N_bar = 1 + max_i |N_i|``.
    nu : float
        Assumption 2's probability bound, in [0, 1].
    sigma : float
        False-alarm probability of the threshold of (25), in [0, 1].
    factor : float, default 1.0
        Factor of ``kappa N_bar`` in the bracket: 1 printed, 2 the proof's.

    Returns
    -------
    Theorem4

    Raises
    ------
    ValidationError
        If a shape or value is out of range.
    """
    A = as_matrix("A", A, square=True)
    C = as_matrix("C", C, (None, A.shape[0]), note="to match A")
    for name, value in (("p", p), ("q", q), ("nu", nu), ("sigma", sigma)):
        V.check_probability(name, value)
    V.check_real("kappa", kappa, lower=0.0)
    V.check_int("n_bar", n_bar, minimum=1)
    V.check_real("factor", factor, lower=0.0)
    c_norms = np.linalg.norm(C, axis=1)
    c_lo, c_hi = c_norms.min(), c_norms.max()
    if c_lo == 0:
        raise ValidationError("C must have no zero row (c_lo = min ||C_i|| divides zeta)")
    alpha_bar = np.linalg.norm(A, 2)
    zeta = ((1 + nu) * c_lo**2 + c_hi**2 * (1 - sigma)) / c_lo**2
    bracket = (1 + kappa) * (1 + factor * kappa * n_bar)
    return Theorem4(float(zeta * alpha_bar**2 * (1 - q + q * bracket)),  # (42)
                    float(zeta * alpha_bar**2 * (p + (1 - p) * bracket)),  # (43)
                    float(zeta), float(alpha_bar), float(c_lo), float(c_hi))


def exact_error_covariance(
    gains: ArrayLike,
    delta: ArrayLike,
    P0: ArrayLike,
    *,
    A: ArrayLike,
    B: ArrayLike,
    C: ArrayLike,
    D: float,
    weights: ArrayLike,
    kappa: float,
) -> NDArray[np.float64]:
    """Exact error covariance of the filter (7)/(34) for given gains, every update accepted.

    With ``theta = 1`` the gains depend only on ``delta``, and the stacked error
    ``e_k = x_k - x_hat_k`` evolves linearly (the Joseph form (12) of Lemma 1, exactly):
    ``e_{k+1}^- = (I kron A - kappa delta_k (I - H) kron A) e_k^+ + (1 kron B) w_k`` and
    ``e_{i,k+1}^+ = (I - K_i C_i) e_{i,k+1}^- - K_i D v_{i,k+1}``. Its covariance ``P_k^+`` is what
    ``Gamma^+ <= P^+ <= Pi^+`` (8) bounds. Scalar measurements, as in Sec. V.

    Parameters
    ----------
    gains : (K, m, n) array_like
        Gains ``K_{i,k}``, ``k = 1..K`` (the filter's ``gain[..., 0]``).
    delta : (>= K,) array_like of {0, 1}
        Channel states ``delta_k``, ``k = 0..K-1``.
    P0 : (m n, m n) array_like
        Covariance of the stacked initial error ``e_0^+``, symmetric PSD.
    A, B : (n, n) array_like
        System and process-noise input matrices of (1).
    C : (m, n) array_like
        Measurement rows ``C_i``.
    D : float
        Measurement-noise gain of (2).
    weights : (m, m) array_like
        Row-stochastic ``H``.
    kappa : float
        Coupling strength, ``kappa >= 0``.

    Returns
    -------
    (K+1, m, n, n) ndarray
        The diagonal blocks ``P_{ii,k}^+``, ``k = 0..K``.

    Raises
    ------
    ValidationError
        If shapes disagree or a value is out of range.
    """
    K = as_matrix("gains", gains, (None, None, None))
    steps, m, n = K.shape
    A = as_matrix("A", A, (n, n), note="to match gains")
    B = as_matrix("B", B, (n, None), note="to match gains")
    C = as_matrix("C", C, (m, n), note="to match gains")
    H = as_matrix("weights", weights, (m, m), note="to match gains")
    P = V.check_psd("P0", as_matrix("P0", P0, (m * n, m * n), note="to match gains"))
    d = as_matrix("delta", delta, (None,))
    if d.shape[0] < steps or not np.all((d == 0) | (d == 1)):
        raise ValidationError(f"delta must hold at least {steps} values in {{0, 1}}, found {d.shape[0]}")
    D = V.check_real("D", D)
    V.check_real("kappa", kappa, lower=0.0)
    n3 = m * n
    L_mat = np.eye(m) - H
    bw = np.kron(np.ones((m, 1)), B)
    blocks = [np.stack([P[n * i:n * (i + 1), n * i:n * (i + 1)] for i in range(m)])]
    for k in range(steps):
        F = np.kron(np.eye(m), A) - kappa * d[k] * np.kron(L_mat, A)  # prediction (7) of the errors
        Pm = F @ P @ F.T + bw @ bw.T
        KC = np.zeros((n3, n3))
        KD = np.zeros((n3, m))
        for i in range(m):
            KC[n * i:n * (i + 1), n * i:n * (i + 1)] = np.outer(K[k, i], C[i])
            KD[n * i:n * (i + 1), i] = K[k, i] * D
        G = np.eye(n3) - KC
        P = G @ Pm @ G.T + KD @ KD.T  # update (34), every theta = 1: Joseph form of (12)
        P = 0.5 * (P + P.T)
        blocks.append(np.stack([P[n * i:n * (i + 1), n * i:n * (i + 1)] for i in range(m)]))
    return np.stack(blocks)


class Example(NamedTuple):
    """The numerical example of Sec. V, see :func:`example`.

    Attributes
    ----------
    A : (3, 3) ndarray
        Constant-acceleration model with sampling period ``T``.
    B : (3, 3) ndarray
        ``0.2 I_3``.
    D : (1, 1) ndarray
        ``0.05``.
    C : (m, 3) ndarray
        ``[4.5, -0.8, -0.5]`` for nodes 1-7, ``[4.0, -0.8, 1.0]`` for nodes 8-m.
    gains : (m, 3) ndarray
        The comparison filter's constant gains, ``gains_low`` for nodes 1-7, ``gains_high`` after.
    """

    A: NDArray[np.float64]
    B: NDArray[np.float64]
    D: NDArray[np.float64]
    C: NDArray[np.float64]
    gains: NDArray[np.float64]


_LOW_GROUP = 7  # "i < 8" of Sec. V, 1-based: nodes 1-7


def example(m: int, T: float, gains_low: ArrayLike, gains_high: ArrayLike) -> Example:
    """The plant (1), sensors (2) and comparison gains of the paper's Sec. V example.

    A position / velocity / acceleration target sampled with period ``T``,
    ``x_{k+1} = A x_k + B w_k`` and ``y_{i,k} = C_i x_k + D v_{i,k}`` (plus the attack), with
    ``w_k ~ N(0, I_3)`` and ``v_{i,k} ~ N(0, 1)``; nodes 1-7 and 8-m have different ``C_i`` and
    constant gains.

    Parameters
    ----------
    m : int
        Number of sensor nodes (20 in Sec. V), at least 1.
    T : float
        Sampling period, positive (0.05 s in Sec. V).
    gains_low, gains_high : (3,) array_like
        Constant gains of the comparison filter for nodes 1-7 and 8-m (printed in Sec. V).

    Returns
    -------
    Example

    Raises
    ------
    ValidationError
        If a value or shape is out of range.
    """
    m = V.check_int("m", m, minimum=1)
    T = V.check_real("T", T, lower=0.0, lower_open=True)
    low = as_matrix("gains_low", gains_low, (3,))
    high = as_matrix("gains_high", gains_high, (3,))
    A = np.array([[1.0, T, T**2 / 2], [0.0, 1.0, T], [0.0, 0.0, 1.0]])
    C = np.array([[4.5, -0.8, -0.5] if i < _LOW_GROUP else [4.0, -0.8, 1.0] for i in range(m)])
    gains = np.array([low if i < _LOW_GROUP else high for i in range(m)])
    return Example(A, 0.2 * np.eye(3), np.array([[0.05]]), C, gains)
