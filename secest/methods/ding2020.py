"""Distributed secure filter over a shared Gilbert-Elliott channel with a chi-square detector.

Implements the filter of Ding, Wang, Han and Zhang (2020), "Recursive secure
filtering over Gilbert-Elliott channels in sensor networks: the distributed
case", for every node at once (:func:`secure_filter_step`, vectorised over
nodes and any leading batch axes such as Monte Carlo runs) and for one node
with a plain loop over its neighbours (:func:`secure_filter_node_step`, the
reference used by equivalence tests and by the timing of Remark 4).

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
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csgraph

from secest.core import validation as V
from secest.core.validation import ValidationError, as_matrix

__all__ = [
    "FilterHealthWarning",
    "SecureStep",
    "consensus_prediction",
    "matrix_max",
    "matrix_min",
    "received_indicator",
    "secure_filter_node_step",
    "secure_filter_step",
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
    """``sum_j W[i, j] X[..., j, ...]`` over the node axis ``axis`` of ``X``."""
    Xm = np.moveaxis(X, axis, 0)
    out = W @ Xm.reshape(Xm.shape[0], -1)
    return np.moveaxis(np.asarray(out).reshape(Xm.shape), 0, axis)


def _sym(X: NDArray[np.float64]) -> NDArray[np.float64]:
    return 0.5 * (X + np.swapaxes(X, -1, -2))


def _leq(
    X: NDArray[np.float64],
    Y: NDArray[np.float64],
    scale: NDArray[np.float64],
    tol: float,
    strict: bool,
) -> NDArray[np.bool_]:
    """``X <= Y`` (``X < Y`` if strict) in the Loewner order, relative tolerance ``tol*scale``."""
    lam = np.linalg.eigvalsh(_sym(Y - X))[..., 0]
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
    ex = np.linalg.eigvalsh(_sym(X))
    ey = np.linalg.eigvalsh(_sym(Y))
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


def _check_states(x_post: ArrayLike) -> NDArray[np.float64]:
    x = as_matrix("x_post", x_post)
    if x.ndim < 2:
        raise ValidationError(f"x_post must have shape (..., m, n), found {x.shape}")
    return x


def _csr(name: str, W: ArrayLike, m: int) -> sp.csr_array:  # m: number of nodes of x_post
    """``W`` (dense or sparse) as a finite CSR array of shape (m, m) without explicit zeros."""
    if sp.issparse(W):
        out = sp.csr_array(W, dtype=float)
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
    received : (..., m, m, n) array_like, optional
        What node ``i`` receives from ``j`` before the channel, ``received[..., i, j, :]``
        (the arena's falsified messages); by default ``x_{j,k}^+`` itself, as in (3).
        Entries off the edges are ignored. Dense ``adj`` and ``weights`` are used then.
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
    if validate:
        r = as_matrix("received", r, (*x.shape[:-1], m, x.shape[-1]), note="to match x_post")
    d = np.asarray(delta, dtype=float)[..., None, None, None]
    xr = d * r
    a, h = (W.toarray() if sp.issparse(W) else np.asarray(W, dtype=float) for W in (adj, weights))
    heard = np.einsum("ij,...ij->...i", a, np.linalg.norm(xr, axis=-1))
    return np.einsum("ij,...ijn->...in", h, xr), (heard > 0).astype(float)


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


def _validate_step(x_post, Pi_post, Gamma_post, delta, y, A, BBt, C, DDt, adj, weights, tol):
    """Shapes, finiteness and the standing assumptions of ding2020 (module docstring)."""
    x = _check_states(x_post)
    m, n = x.shape[-2:]
    batch = x.shape[:-2]
    note = "to match x_post"
    as_matrix("A", A, (n, n), note=note)
    V.check_psd("BBt", as_matrix("BBt", BBt, (n, n), note=note), tol=tol)
    C = as_matrix("C", C, (m, None, n), note=note)
    ny = C.shape[1]
    V.check_psd("DDt", as_matrix("DDt", DDt, (ny, ny), note="to match C"), strict=True, tol=tol)
    Pi = V.check_psd("Pi_post", as_matrix("Pi_post", Pi_post, (*batch, m, n, n), note=note), tol=tol)
    Gam = V.check_psd("Gamma_post", as_matrix("Gamma_post", Gamma_post, (*batch, m, n, n), note=note),
                      tol=tol)
    V.check_loewner_order("Gamma_post", Gam, "Pi_post", Pi, tol=tol)
    as_matrix("y", y, (*batch, m, ny), note="to match x_post and C")
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
    ev = np.linalg.eigvalsh(Pi)
    Pi_psd = ev[..., 0] >= -tol * np.abs(ev).max(axis=-1)
    gap = np.linalg.eigvalsh(Pi - Gam)[..., 0]
    scale = np.maximum(np.abs(ev).max(axis=-1), np.abs(np.linalg.eigvalsh(Gam)).max(axis=-1))
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
    received : (..., m, m, n) array_like, optional
        Per-link messages ``received[..., i, j, :]`` replacing ``x_{j,k}^+`` in (3), e.g.
        falsified in transit (see :func:`consensus_prediction`); by default (3) as printed.
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
        if received is not None:
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
    ev = np.linalg.eigvalsh(_sym(Q1))
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
    ev = np.linalg.eigvalsh(_sym(Q1))
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
