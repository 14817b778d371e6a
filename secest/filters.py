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
10. upper posterior bound (35) ``Pi_i^+ = Pi_i^- - theta_i K_i C_i Pi_i^-``.

Every bound is symmetrised after it is formed.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from secest.validation import ValidationError, as_matrix

__all__ = [
    "SecureStep",
    "consensus_prediction",
    "matrix_max",
    "matrix_min",
    "received_indicator",
    "secure_filter_node_step",
    "secure_filter_step",
]

_INSPECTION = ("Gamma", "Pi")


def _operator(name: str, W: ArrayLike, m: int) -> NDArray[np.float64] | sp.csr_array:
    """``W`` as a node-mixing operator: CSR if given sparse, else a dense float array.

    Large networks should pass ``adj`` / ``weights`` as scipy.sparse matrices: every
    node-mixing product then costs O(edges) instead of O(m^2), which keeps the
    per-node cost of a step independent of the network size (Remark 4).
    """
    op = sp.csr_array(W, dtype=float) if sp.issparse(W) else np.asarray(W, dtype=float)
    if op.shape != (m, m):
        raise ValidationError(f"Incompatible dimensions of {name}: expected {(m, m)}, found {op.shape}")
    return op


def _dense(W: ArrayLike) -> NDArray[np.float64]:
    """Dense copy of a possibly sparse matrix, for validation only."""
    return W.toarray() if sp.issparse(W) else np.asarray(W, dtype=float)


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
    x = np.asarray(X, dtype=float)
    y = np.asarray(Y, dtype=float)
    if x.ndim < 2 or x.shape[-1] != x.shape[-2]:
        raise ValidationError(f"X must be square in its last two axes, found shape {x.shape}")
    if y.shape != x.shape:
        raise ValidationError(f"Incompatible dimensions of Y: expected {x.shape}, found {y.shape}")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValidationError("X and Y must be finite")
    if not tol >= 0:
        raise ValidationError(f"tol must be non-negative, found {tol!r}")
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
        If the shapes differ, are not square, or entries are not finite.
    """
    x, y = _check_pair(X, Y, tol)
    return _min_max(x, y, tol, strict, "min")


def matrix_max(
    X: ArrayLike, Y: ArrayLike, *, tol: float = 1e-10, strict: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.int8]]:
    """The paper's ``max{X, Y}`` of two symmetric matrices (Section III, used in (27)).

    ``max{X, Y} = Y`` if ``X <= Y``; ``X`` if ``Y < X``; otherwise
    ``lambda_max I`` with ``lambda_max`` the largest eigenvalue of X and Y.

    Parameters and returns as in :func:`matrix_min`; ``branch`` is 0 where Y was
    returned, 1 where X was returned and 2 for ``lambda_max I``.
    """
    x, y = _check_pair(X, Y, tol)
    return _min_max(x, y, tol, strict, "max")


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
        0/1 adjacency, ``adj[i, j] = 1`` if node ``i`` receives from ``j``.

    Returns
    -------
    x_received : (..., m, n) ndarray
        ``x_{j,k}^{r+} = delta_k x_{j,k}^+`` (3).
    delta_r : (..., m) ndarray
        ``1`` where ``sum_{j in N_i} ||x_{j,k}^{r+}|| > 0``, else ``0`` (4).
    """
    x = np.asarray(x_post, dtype=float)
    d = np.asarray(delta, dtype=float)
    if x.ndim < 2:
        raise ValidationError(f"x_post must have shape (..., m, n), found {x.shape}")
    a = _operator("adj", adj, x.shape[-2])
    if not np.all((d == 0) | (d == 1)):
        raise ValidationError("delta must contain only 0 and 1")
    xr = d[..., None, None] * x
    heard = _mix(a, np.linalg.norm(xr, axis=-1), -1)
    return xr, (heard > 0).astype(float)


def consensus_prediction(
    x_post: ArrayLike,
    delta: ArrayLike,
    adj: ArrayLike,
    weights: ArrayLike,
    A: ArrayLike,
    kappa: float,
    *,
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
        0/1 adjacency (``adj[i, j] = 1`` iff ``j in N_i``) and weights ``h_ij``.
    A : (n, n) array_like
        System matrix.
    kappa : float
        Coupling strength.
    validate : bool, default True
        Check shapes and values.

    Returns
    -------
    x_prior : (..., m, n) ndarray
        Predictions ``x_{i,k+1}^-``.
    delta_r : (..., m) ndarray
        Indicators (4).
    """
    x = np.asarray(x_post, dtype=float)
    if validate:
        if not (np.isfinite(kappa) and kappa >= 0):
            raise ValidationError(f"kappa must be a non-negative number, found {kappa!r}")
        x = as_matrix("x_post", x)
        if x.ndim < 2:
            raise ValidationError(f"x_post must have shape (..., m, n), found {x.shape}")
        as_matrix("A", A, (x.shape[-1], x.shape[-1]))
        as_matrix("weights", _dense(weights), (x.shape[-2], x.shape[-2]))
    H = _operator("weights", weights, x.shape[-2])
    xr, dr = received_indicator(x, delta, adj)
    row_sums = np.asarray(H.sum(axis=1)).ravel()
    xi = _mix(H, xr, -2) - dr[..., None] * row_sums[:, None] * x
    return (x + kappa * xi) @ np.asarray(A, dtype=float).T, dr


class SecureStep(NamedTuple):
    """Result of one step ``k -> k+1`` of the secure filter (all nodes).

    Attributes
    ----------
    x_post, Pi_post, Gamma_post : estimates and bounds at ``k+1`` (34), (35), (18).
    x_prior, Pi_prior, Gamma_prior : predictions and bounds (7), (26), (17).
    gain : (..., m, n, ny) gains (32).
    theta : (..., m) detector outcomes (25), 1 = accepted.
    nis : (..., m) test statistics ``eta^T Gamma_eta^{-1} eta`` (or with ``Pi_eta``).
    delta_r : (..., m) channel indicators (4) at ``k``.
    q1_psd : (..., m) bool, where ``Q1 >= 0`` so (17) took its first branch.
    min_branch : (..., m) int8, branch of ``min{Gamma^-, S1}`` in (18), see :func:`matrix_min`.
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


def _check_scalars(kappa: float, threshold: float, inspection_cov: str, tol: float) -> None:
    if not (np.isfinite(kappa) and kappa >= 0):
        raise ValidationError(f"kappa must be a non-negative number, found {kappa!r}")
    if not (np.isfinite(threshold) and threshold > 0):
        raise ValidationError(f"threshold must be positive, found {threshold!r}")
    if inspection_cov not in _INSPECTION:
        raise ValidationError(f"inspection_cov must be one of {_INSPECTION}, found {inspection_cov!r}")
    if not tol >= 0:
        raise ValidationError(f"tol must be non-negative, found {tol!r}")


def _validate_step(x_post, Pi_post, Gamma_post, delta, y, A, BBt, C, DDt, adj, weights):
    x = as_matrix("x_post", x_post)
    if x.ndim < 2:
        raise ValidationError(f"x_post must have shape (..., m, n), found {x.shape}")
    m, n = x.shape[-2:]
    batch = x.shape[:-2]
    A = as_matrix("A", A, (n, n))
    BBt = as_matrix("BBt", BBt, (n, n))
    C = as_matrix("C", C, (m, None, n))
    ny = C.shape[1]
    DDt = as_matrix("DDt", DDt, (ny, ny))
    for name, val in (("Pi_post", Pi_post), ("Gamma_post", Gamma_post)):
        as_matrix(name, val, (*batch, m, n, n))
    as_matrix("y", y, (*batch, m, ny))
    d = np.asarray(delta, dtype=float)
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
    a = as_matrix("adj", _dense(adj), (m, m))
    if not np.all((a == 0) | (a == 1)) or np.any(np.diag(a) != 0):
        raise ValidationError("adj must be a 0/1 matrix with zero diagonal")
    h = as_matrix("weights", _dense(weights), (m, m))
    if np.any((h > 0) != (a > 0)) or np.any(h < 0):
        raise ValidationError(
            "weights must be positive exactly on the edges of adj (h_ij > 0 iff (i, j) in E)"
        )


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
    validate: bool = True,
) -> SecureStep:
    """One step ``k -> k+1`` of the distributed secure filter (7)/(34), all nodes at once.

    Vectorised over the ``m`` nodes and over any leading batch axes (e.g.
    Monte Carlo runs); see the module docstring for the ten sub-steps and
    their equation numbers.

    Parameters
    ----------
    x_post : (..., m, n) array_like
        Posterior estimates ``x_{i,k}^+``.
    Pi_post, Gamma_post : (..., m, n, n) array_like
        Upper bounds ``Pi_{i,k}^+`` (35) and lower bounds ``Gamma_{i,k}^+`` (18).
    delta : scalar or (...) array_like of {0, 1}
        Shared Gilbert-Elliott channel state ``delta_k``.
    y : (..., m, ny) array_like
        Measurements ``y_{i,k+1}`` (including any injected attack).
    A, BBt : (n, n) array_like
        System matrix and process-noise covariance ``B B^T`` of (1).
    C : (m, ny, n) array_like
        Measurement matrices ``C_i`` of (2).
    DDt : (ny, ny) array_like
        Measurement-noise covariance ``D D^T``.
    adj : (m, m) array_like or scipy.sparse matrix (sparse: O(edges) per step)
        0/1 adjacency, ``adj[i, j] = 1`` iff ``j in N_i`` (``i`` receives from ``j``).
    weights : (m, m) array_like or scipy.sparse matrix
        ``H = [h_ij]``, positive exactly on the edges.
    kappa : float
        Coupling strength ``kappa >= 0``.
    threshold : float
        Chi-square threshold of (25).
    inspect : bool, default True
        Apply the test (25); ``False`` sets ``theta = 1`` in (34) and (35) (no inspection).
    inspection_cov : {"Gamma", "Pi"}, default "Gamma"
        Normalise the test with the lower bound ``Gamma_eta`` (the paper's (25)) or,
        as an ablation that is not the paper's scheme, with ``Pi_eta``.
    tol : float, default 1e-10
        Relative tolerance of the PSD test in (17) and of :func:`matrix_min`.
    strict : bool, default False
        Strict reading of ``Y < X`` in the min operation of (18).
    validate : bool, default True
        Check shapes and values (switch off inside tight loops).

    Returns
    -------
    SecureStep

    Raises
    ------
    ValidationError
        If shapes disagree or a value is out of range (when ``validate``).
    """
    if validate:
        _check_scalars(kappa, threshold, inspection_cov, tol)
        _validate_step(x_post, Pi_post, Gamma_post, delta, y, A, BBt, C, DDt, adj, weights)
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

    # (3), (4), (7): channel indicator and consensus prediction
    x_prior, dr = consensus_prediction(x, delta, adj, H, A, kappa, validate=False)
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
    # (34): update; (35): upper posterior bound
    x_new = x_prior + theta[..., None] * np.einsum("...iny,...iy->...in", K, eta)
    Pi_new = _sym(Pi_prior - theta[..., None, None] * (K @ C @ Pi_prior))
    return SecureStep(
        x_new,
        Pi_new,
        _sym(Gamma_new),
        x_prior,
        Pi_prior,
        Gamma_prior,
        K,
        theta,
        nis,
        dr,
        q1_psd,
        branch,
    )


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
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]:
    """One step ``k -> k+1`` of node ``i`` alone: the plain per-node reference.

    Uses only the node's own quantities and those it receives from its
    neighbours ``N_i`` (one loop over neighbours), as Remark 4 describes; the
    arithmetic follows the module docstring step by step, without vectorisation.

    Parameters
    ----------
    x_self : (n,) array_like
        ``x_{i,k}^+``.
    Pi_self, Gamma_self : (n, n) array_like
        ``Pi_{i,k}^+`` and ``Gamma_{i,k}^+``.
    x_nbrs : (``|N_i|``, n) array_like
        Neighbours' estimates ``x_{j,k}^+`` (before the channel; (3) is applied here).
    Pi_nbrs : (``|N_i|``, n, n) array_like
        Neighbours' bounds ``Pi_{j,k}^+`` (sent in the same packet as ``x_{j,k}^+``).
    h_nbrs : (``|N_i|``,) array_like
        Weights ``h_ij`` of the neighbours.
    delta : {0, 1}
        Channel state ``delta_k``.
    y_i : (ny,) array_like
        Measurement ``y_{i,k+1}``.
    A, BBt, C_i, DDt, kappa, threshold, inspect, inspection_cov, tol, strict
        As in :func:`secure_filter_step`, with ``C_i`` of shape (ny, n).

    Returns
    -------
    x_post : (n,) ndarray
    Pi_post, Gamma_post : (n, n) ndarray
    theta : int
        Detector outcome (25), 1 = accepted.

    Raises
    ------
    ValidationError
        If shapes disagree or a value is out of range.
    """
    _check_scalars(kappa, threshold, inspection_cov, tol)
    x_i = as_matrix("x_self", x_self, (None,))
    n = x_i.shape[0]
    P_i = as_matrix("Pi_self", Pi_self, (n, n))
    G_i = as_matrix("Gamma_self", Gamma_self, (n, n))
    xs = as_matrix("x_nbrs", x_nbrs, (None, n))
    nb = xs.shape[0]
    Ps = as_matrix("Pi_nbrs", Pi_nbrs, (nb, n, n))
    hs = as_matrix("h_nbrs", h_nbrs, (nb,))
    A = as_matrix("A", A, (n, n))
    BBt = as_matrix("BBt", BBt, (n, n))
    C_i = as_matrix("C_i", C_i, (None, n))
    DDt = as_matrix("DDt", DDt, (C_i.shape[0], C_i.shape[0]))
    y_i = as_matrix("y_i", y_i, (C_i.shape[0],))
    if delta not in (0, 1):
        raise ValidationError(f"delta must be 0 or 1, found {delta!r}")

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
    # (34), (35)
    x_post = x_prior + theta * (K @ eta)
    Pi_post = _sym(Pi_prior - theta * (K @ C_i @ Pi_prior))
    return x_post, Pi_post, _sym(Gamma_post), theta
