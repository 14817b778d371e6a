"""guo2023: distributed state and input estimation under deception attacks (the one implementation).

Guo & Xia (2023): node ``i`` splits its attacked measurement with an SVD of its
feed-through ``H_bar^i = [0 H^i]`` into ``z_1`` (sees the input part ``u_1``, estimated at
once) and ``z_2`` (input-free; estimates the part ``u_2`` that drives the state, one step
late), makes a local update with a gain constrained by ``K U_1 = 0`` (28), and fuses its
estimate with its neighbours' by consensus on information (19)-(21). The functions below are
the corrected Algorithm 1 (steps A1-A14, stages B-D; corrections E1-E7 of ERRATA.md) that the
guo2023 notebook derives, shows and verifies and that the arena races
(:mod:`secest.arena.papers.guo2023`), vectorised over Monte Carlo runs and over the nodes that
share the same decomposition shapes, and over runs of the covariance bounds when those depend on
the run (links that fail). :func:`error_covariance` (ours) propagates the exact error
covariances that Theorem 1 bounds.

Reading on a shared scenario (:class:`Guo2023`, rules fixed before any arena run):

* **Attack channels** ``H^i``: the paper assumes them known (2); by default (``threat="card"``)
  they are read from the attack card: ``H^i = I`` on the rows of every sensor the card
  attacks, no attack input elsewhere (Remark 1's per-node signals ``a^i``). Only the
  *channel* is read, never the magnitude, timing or probability. ``threat="all"`` (every
  sensor attackable, the paper's Remark 1 taken literally) leaves no attack-free output on
  single-output nodes, so Assumption 2 fails and the method answers "not applicable".
* **Unknown input** ``d``: none (``n_d = 0``): the shared plants have no input besides noise.
* **Exchange**: once per step, after the local update, each node sends ``x^{i,i}`` (falsified
  under a message attack, ``scale = x0_std``). The bounds ``P^{i,i}`` do not depend on the
  data, and the link state is shared by every link, so each node computes its neighbours'
  bounds itself: they are not sent.
* **Lost message**: the node fuses the estimates it received with the weights ``pi_ij``
  renormalised over them (its own estimate alone when every link is down); consensus on
  information stays a consistent fusion (Theorem 1) for any convex weights.
* **Weights** ``Pi``: uniform on the closed neighbourhood, ``pi_ij = 1/(|N_i| + 1)`` (the
  example of Sec. V); ``x0 = 0``, ``P_0`` the prior covariance of the card.
* **Alarms** (ours, not the paper's): the attack estimate ``u_1`` of an attackable node is
  tested against zero with its covariance bound ``Sigma^-1 (C_1 P_bar C_1^T + R_1) Sigma^-T``,
  chi-square at level :data:`secest.arena.estimators.CHI2_ALPHA` (the baseline's).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from numpy.typing import NDArray

from secest.core.covariance import symmetrize
from secest.core.estimation import FeedthroughSVD, constrained_gain, feedthrough_decomposition
from secest.core.validation import RTOL, ValidationError, check_row_stochastic

__all__ = [
    "GuoModel",
    "GuoRun",
    "GuoState",
    "GuoStep",
    "GAINS",
    "LocalGains",
    "decompositions",
    "error_covariance",
    "estimator_step",
    "check_weights",
    "fuse",
    "initial_state",
    "input_one",
    "link_weights",
    "local_estimate",
    "local_gains",
    "run_estimator",
]

Array = NDArray[np.float64]

GAINS = ("constrained", "unconstrained")
"""The local gains :func:`local_gains` can use: (28) with ``K U_1 = 0`` (the paper's), or the
unconstrained minimiser ``S Xi_breve^+`` of (26) (ours: a negative control, which lets the
attack into the local error)."""


def _t(M: Array) -> Array:
    """Transpose of the last two axes."""
    return np.swapaxes(M, -1, -2)


def _apply(M: Array, v: Array) -> Array:
    """``M v`` over the last axes, broadcasting stacks of matrices against stacks of vectors."""
    return (M @ v[..., None])[..., 0]


# ---------------------------------------------------------------------------------- stage A


class LocalGains(NamedTuple):
    """The data-independent matrices of node ``i``'s local step (Algorithm 1, stage A).

    Every field may carry the leading stack axes ``...`` (runs, nodes) of the arguments of
    :func:`local_gains`. ``p = rank H_bar^i_k`` and ``p' = rank H_bar^i_{k-1}`` (the SVD at
    ``k - 1`` splits ``u_{k-1}``, the one at ``k`` splits ``y^{a,i}_k``), ``n_u`` the
    dimension of ``u = [d; a]`` (3).

    Attributes
    ----------
    G1 : (..., n_x, p') array
        ``G_bar_{1,k-1} = G_bar V_1`` (4): zero in this problem class (``u_1`` never drives x).
    G2 : (..., n_x, n_u - p') array
        ``G_bar_{2,k-1} = G_bar V_2`` (4).
    C2 : (..., n_y - p, n_x) array
        ``C_{2,k} = U_2^T C`` (6): the output rows free of the input ``u_1``.
    M2 : (..., n_u - p', n_y - p) array
        ``M_bar_2`` of (13) (A4); ``M2 @ B2 = I`` is the unbiasedness condition (10).
    B2 : (..., n_y - p, n_u - p') array
        ``C_2 G_bar_2`` (A4); full column rank is the solvability condition of (13).
    J : (..., n_x, n_y) array
        ``G_bar_2 M_bar_2 U_2^T`` (A8).
    K : (..., n_x, n_y) array
        Constrained gain (28) (A12), ``K U_1 = 0``.
    P_pred : (..., n_x, n_x) array
        ``P_bar_{k|k-1} = A P_bar_{k-1} A^T + Q`` (23) (A2).
    P_loc : (..., n_x, n_x) array
        ``P_bar^{i,i}_k = P* - K S^T`` (29) (A14), symmetrised: the local bound.
    P_star : (..., n_x, n_x) array
        ``P_bar* = (I - J C) P_bar_{k|k-1} (I - J C)^T + G_bar_2 M_bar_2 R_2 M_bar_2^T G_bar_2^T``
        (24), corrected (A8).
    S : (..., n_x, n_y) array
        ``S = P_bar* C^T - J R`` (26) (A9).
    Xi : (..., n_y, n_y) array
        ``Xi_bar = C P_bar_{k|k-1} C^T + R`` (13) (A10).
    Theta : (..., n_y, n_y) array
        ``Theta = Xi_bar^-1 (I - C J)`` (30), Algorithm 1 line 13 (A11).
    R2 : (..., n_y - p, n_y - p) array
        ``R_2 = U_2^T R U_2``, the noise covariance of ``z_2`` (6).
    """

    G1: Array
    G2: Array
    C2: Array
    M2: Array
    B2: Array
    J: Array
    K: Array
    P_pred: Array
    P_loc: Array
    P_star: Array
    S: Array
    Xi: Array
    Theta: Array
    R2: Array


def local_gains(
    A: Array,
    Q: Array,
    Gbar: Array,
    P_prev: Array,
    dec_prev: FeedthroughSVD,
    dec: FeedthroughSVD,
    C: Array,
    R: Array,
    *,
    gain: str = "constrained",
) -> LocalGains:
    """Gains and covariance bounds of the local step k-1 -> k (A2-A4, A8-A12, A14).

    Every argument but ``A`` and ``Q`` may carry leading stack axes (runs, nodes) that broadcast
    together.

    Parameters
    ----------
    A, Q : (n_x, n_x) arrays
        ``A_{k-1}``, ``Q_{k-1}``.
    Gbar : (..., n_x, n_u) array
        ``G_bar_{k-1} = [G_{k-1} 0]`` (3).
    P_prev : (..., n_x, n_x) array
        Fused bound ``P_bar^i_{k-1}``.
    dec_prev, dec : FeedthroughSVD
        SVD of ``H_bar^i`` at ``k-1`` (for ``V_1, V_2``) and at ``k`` (``U_1, U_2, T_1``),
        possibly stacked over nodes (:func:`secest.core.estimation.feedthrough_decomposition`).
    C, R : (..., n_y, n_x), (..., n_y, n_y) arrays
        ``C^i_k``, ``R^i_k``.
    gain : {"constrained", "unconstrained"}, default "constrained"
        ``"constrained"``: the gain (28), ``K U_1 = 0`` (the paper's). ``"unconstrained"`` (ours,
        a negative control): ``K = S Xi_breve^+`` with ``Xi_breve = (I - C J) Xi_bar (I - C J)^T``
        (26), the minimiser of ``tr P_bar^{i,i}`` without the constraint (pseudo-inverse with
        relative cutoff 1e-9); ``P_loc`` is then (26) corrected evaluated at that gain. It does
        not satisfy ``K U_1 = 0``, so the attack enters the local error.

    Returns
    -------
    LocalGains

    Raises
    ------
    ValidationError
        If ``gain`` is not one of :data:`GAINS`.
    """
    if gain not in GAINS:
        raise ValidationError(f"gain: expected one of {GAINS}, found {gain!r}")
    G1, G2 = Gbar @ dec_prev.V1, Gbar @ dec_prev.V2  # (4) at k-1
    U2t = _t(dec.U2)
    C2, R2 = U2t @ C, U2t @ R @ dec.U2  # (6)
    P_pred = A @ P_prev @ A.T + Q  # A2: (23)
    Xi2 = C2 @ P_pred @ _t(C2) + R2  # A3: (13)
    B2 = C2 @ G2
    Xi2_inv_B2 = np.linalg.solve(Xi2, B2)
    M2 = np.linalg.solve(_t(B2) @ Xi2_inv_B2, _t(Xi2_inv_B2))  # A4: (13)
    J = G2 @ M2 @ U2t
    I_JC = np.eye(A.shape[0]) - J @ C
    P_star = I_JC @ P_pred @ _t(I_JC) + G2 @ M2 @ R2 @ _t(M2) @ _t(G2)  # A8: (24) corrected
    S = P_star @ _t(C) - J @ R  # A9: (26)
    Xi = C @ P_pred @ _t(C) + R  # A10: (13)
    Theta = np.linalg.solve(Xi, np.eye(C.shape[-2]) - C @ J)  # A11: (30), line 13
    if gain == "constrained":
        K = constrained_gain(S, Theta, dec.U1, stacked=True)  # A12: (28)
        P_loc = symmetrize(P_star - K @ _t(S))  # A14: (29)
    else:  # ours, a negative control: the unconstrained minimiser of (26)
        I_CJ = np.eye(C.shape[-2]) - C @ J
        Xi_breve = I_CJ @ Xi @ _t(I_CJ)  # (26), with its final transpose (E4)
        K = S @ np.linalg.pinv(Xi_breve, rcond=1e-9)
        P_loc = symmetrize(P_star + K @ Xi_breve @ _t(K) - K @ _t(S) - S @ _t(K))  # (26) corrected
    return LocalGains(G1, G2, C2, M2, B2, J, K, P_pred, P_loc, P_star, S, Xi, Theta, R2)


def local_estimate(
    g: LocalGains, A: Array, x_prev: Array, u1_prev: Array, dec: FeedthroughSVD, C: Array, ya: Array
) -> tuple[Array, Array, Array]:
    """Node ``i``'s estimates of the local step (A1, A5-A7, A13) for a batch of runs.

    Parameters
    ----------
    g : LocalGains
        From :func:`local_gains` for the same step.
    A : (n_x, n_x) array
        ``A_{k-1}``.
    x_prev, u1_prev : (..., n_x), (..., p_{k-1}) arrays
        Fused ``x_hat^i_{k-1}`` and ``u_hat^i_{1,k-1}`` (leading axes: runs, nodes).
    dec : FeedthroughSVD
        SVD at ``k``.
    C : (..., n_y, n_x) array
        ``C^i_k``.
    ya : (..., n_y) array
        Attacked measurement ``y^{a,i}_k`` (E1: the node has no other).

    Returns
    -------
    x_loc : (..., n_x)
        ``x_hat^{i,i}_k`` (14) row 5.
    u2 : (..., m)
        ``u_hat^i_{2,k-1}`` (14) row 2, the one-step-delayed input estimate.
    z1 : (..., p)
        ``z_{1,k} = T_1 y^a`` (5), kept for stage D.
    """
    z1, z2 = _apply(dec.T1, ya), _apply(_t(dec.U2), ya)  # A1: (5)-(6)
    x_pred = x_prev @ A.T + _apply(g.G1, u1_prev)  # A5: (14) row 3
    u2 = _apply(g.M2, z2 - _apply(g.C2, x_pred))  # A6: (14) row 2
    x_star = x_pred + _apply(g.G2, u2)  # A7: (14) row 4
    x_loc = x_star + _apply(g.K, ya - _apply(C, x_star))  # A13: (14) row 5, with y^a
    return x_loc, u2, z1


# ---------------------------------------------------------------------------------- stage C


def fuse(
    P_loc: Array, weights: Array | sp.sparray, received: Array, *, matrix_weights: bool = True,
    up: Array | None = None,
) -> tuple[Array, Array | None, Array]:
    """Consensus-on-information fusion (19)-(21) of every node at once.

    Dense ``weights`` cost ``O(N^2)`` per step (the notebook's form); a sparse ``weights`` matrix
    makes every sum run over its stored entries (the closed neighbourhoods), ``O(E)``.

    Parameters
    ----------
    P_loc : (..., N, n, n) array
        Local bounds ``P_bar^{j,j}_k``.
    weights : (..., N, N) array or scipy.sparse (N, N) matrix
        ``pi_ij`` (row-stochastic; a row renormalised over the messages received). Sparse: its
        stored entries, row by row (CSR), are the pairs ``(i, j)`` of the closed neighbourhoods,
        the diagonal included.
    received : (..., N, N, n) array, or (..., nnz, n) with sparse ``weights``
        ``received[..., i, j]``: the estimate ``x_hat^{j,j}_k`` as node ``i`` received it
        (``received[..., i, i]`` its own); with sparse ``weights`` one row per stored entry.
    matrix_weights : bool, default True
        Also return the matrix weights ``W`` (not needed for the estimates).
    up : (runs,) array of 0 / 1, optional
        Sparse ``weights`` only (dense ones carry it, :func:`link_weights`): where ``up[r]`` is
        0 every link is down in run ``r`` and each node keeps its own estimate; where 1 the
        rows of ``weights`` are renormalised as :func:`link_weights` does.

    Returns
    -------
    P : (..., N, n, n)
        Fused bounds ``P_bar^i_k = [sum_j pi_ij (P_bar^{j,j})^-1]^-1`` (19), symmetrised.
    W : (..., N, N, n, n), or (..., nnz, n, n) with sparse ``weights``, or None
        Matrix weights ``W^{i,j} = pi_ij P_bar^i (P_bar^{j,j})^-1`` (20); ``sum_j W^{i,j} = I``.
    x : (..., N, n)
        Fused estimates ``x_hat^i_k = sum_j W^{i,j} x_hat^{j,j}_k`` (21), evaluated as
        ``P_bar^i sum_j pi_ij (P_bar^{j,j})^-1 x_hat^{j,j}``.
    """
    if sp.issparse(weights):
        return _fuse_sparse(P_loc, sp.csr_array(weights), received, matrix_weights, up)
    N, n = P_loc.shape[-3], P_loc.shape[-1]
    info = np.linalg.inv(P_loc)
    omega = weights @ info.reshape(*info.shape[:-3], N, n * n)
    P = symmetrize(np.linalg.inv(omega.reshape(*omega.shape[:-1], n, n)))  # (19)
    W = None
    if matrix_weights:
        W = weights[..., None, None] * (P[..., :, None, :, :] @ info[..., None, :, :, :])  # (20)
    info_x = (info[..., None, :, :, :] @ received[..., None])[..., 0]  # (P^{j,j})^-1 x^{j,j} as received
    x = _apply(P, np.sum(weights[..., None] * info_x, axis=-2))  # (20)-(21)
    return P, W, x


def _entries(weights: sp.csr_array) -> tuple[NDArray[np.intp], NDArray[np.intp], sp.csr_array]:
    """Rows and columns of the stored entries of a CSR matrix, and the (N, nnz) 0/1 matrix that
    sums per-entry values over each row."""
    N, nnz = weights.shape[0], weights.nnz
    rows = np.repeat(np.arange(N), np.diff(weights.indptr))
    summer = sp.csr_array((np.ones(nnz), np.arange(nnz), weights.indptr), shape=(N, nnz))
    return rows, weights.indices, summer


def _sum_rows(summer: sp.csr_array, values: Array, axis: int) -> Array:
    """``values`` (per stored entry along ``axis``) summed over the entries of each row."""
    v = np.moveaxis(values, axis, 0)
    out = np.asarray(summer @ v.reshape(v.shape[0], -1))
    return np.moveaxis(out.reshape(summer.shape[0], *v.shape[1:]), 0, axis)


def _fuse_sparse(
    P_loc: Array, weights: sp.csr_array, received: Array, matrix_weights: bool, up: Array | None
) -> tuple[Array, Array | None, Array]:
    """:func:`fuse` over the stored entries of sparse weights (``O(E)``)."""
    rows, cols, summer = _entries(weights)
    w = weights.data
    if up is not None:  # link_weights: rows renormalised where up, the identity where down
        w_up = w / (summer @ w)[rows]
        w = np.where(np.asarray(up)[:, None] == 1, w_up, (rows == cols).astype(float))
    info = np.linalg.inv(P_loc)
    info_e = info[..., cols, :, :]  # (P_bar^{j,j})^-1 of every entry (i, j)
    ww = w[..., None, None]
    P = symmetrize(np.linalg.inv(_sum_rows(summer, ww * info_e, -3)))  # (19)
    W = ww * (P[..., rows, :, :] @ info_e) if matrix_weights else None  # (20)
    info_x = _apply(info_e, received)  # (P^{j,j})^-1 x^{j,j} as received
    x = _apply(P, _sum_rows(summer, w[..., None] * info_x, -2))  # (20)-(21)
    return P, W, x


def check_weights(Pi: Array | sp.sparray) -> Array | sp.csr_array:
    """Fusion weights ``pi_ij`` checked: row-stochastic, non-negative, ``pi_ii > 0``.

    Parameters
    ----------
    Pi : (N, N) array or scipy.sparse matrix
        The weights of (19)-(21); sparse ones are returned as canonical CSR (entries sorted
        row by row), whose stored entries :func:`fuse` reads as the closed neighbourhoods.

    Returns
    -------
    (N, N) array or scipy.sparse CSR array

    Raises
    ------
    ValidationError
        A negative or non-finite entry, a row not summing to one, or (sparse) a missing
        diagonal entry.
    """
    if not sp.issparse(Pi):
        return check_row_stochastic("Pi", Pi)
    w = sp.csr_array(Pi, dtype=float)
    w.sum_duplicates()
    w.sort_indices()
    N = w.shape[0]
    if w.shape != (N, N) or not np.all(np.isfinite(w.data)) or np.any(w.data < 0):
        raise ValidationError(f"Pi must be a square non-negative finite matrix, found shape {w.shape}")
    sums = np.asarray(w.sum(axis=1)).ravel()
    bad = np.flatnonzero(np.abs(sums - 1.0) > RTOL * np.maximum(1.0, sums))
    if bad.size:
        raise ValidationError(f"Pi must be row-stochastic, row {bad[0]} sums to {sums[bad[0]]:.6g}")
    if np.any(w.diagonal() <= 0):
        raise ValidationError("Pi must have pi_ii > 0 stored on its diagonal (a node keeps its own "
                              "estimate)")
    return w


# ---------------------------------------------------------------------------------- driver


@dataclass(frozen=True)
class GuoModel:
    """The model of (1)-(3) as functions of the step ``k`` (any object with these works).

    ``Gbar(k)`` returns one ``(n_x, n_u)`` matrix (the paper's common ``u = [d; a]``) or a
    sequence of one ``(n_x, n_u^i)`` matrix per node (Remark 1's per-node attack signals);
    ``Hbar(k)`` returns one ``(n_y, n_u^i)`` matrix per node.

    Attributes
    ----------
    nx : int
        State dimension ``n_x``.
    N : int
        Number of nodes.
    A : callable ``k -> (n_x, n_x) array``
        ``A_k`` of (1).
    Q : callable ``k -> (n_x, n_x) array``
        Process-noise covariance ``Q_k > 0`` of (1).
    C : callable ``k -> (N, n_y, n_x) array``
        Every node's output matrix ``C^i_k`` of (1), stacked (the same ``n_y`` at every node).
    R : callable ``k -> (N, n_y, n_y) array``
        Every node's measurement-noise covariance ``R^i_k > 0`` of (1), stacked.
    Gbar : callable ``k -> (n_x, n_u) array or sequence of N (n_x, n_u^i) arrays``
        ``G_bar_k = [G_k 0]`` of (3): how the unknown input ``u_k`` enters the state.
    Hbar : callable ``k -> sequence of N (n_y, n_u^i) arrays``
        ``H_bar^i_k = [0 H^i_k]`` of (3): how ``u_k`` enters node ``i``'s measurement
        (``H^i_k`` the attack channel of (2)).
    Pi : (N, N) array or scipy.sparse matrix
        Fusion weights ``pi_ij`` of (19)-(21): row-stochastic, ``pi_ij > 0`` exactly on the
        closed neighbourhood ``N_i cup {i}``. Sparse: every sum of the fusion runs over its
        stored entries (``O(E)`` per step) and the exchanged estimates are per edge
        (:func:`estimator_step`).
    x0_hat : (n_x,) array
        Initial estimate ``x_hat_0`` of every node (Algorithm 1 line 1).
    P0 : (n_x, n_x) array
        Initial bound ``P_bar^i_0 = P_0 > 0`` of every node (Algorithm 1 line 1).
    """

    nx: int
    N: int
    A: Callable[[int], Array]
    Q: Callable[[int], Array]
    C: Callable[[int], Array]
    R: Callable[[int], Array]
    Gbar: Callable[[int], Any]
    Hbar: Callable[[int], Sequence[Array]]
    Pi: Array
    x0_hat: Array
    P0: Array


@dataclass
class GuoRun:
    """Output of :func:`run_estimator` (``runs`` first, as in the arena).

    Attributes
    ----------
    x : (runs, K + 1, N, n_x)
        Fused estimates ``x_hat^i_k`` (``k = 0``: the prior, Algorithm 1 line 1).
    P : (K + 1, N, n_x, n_x) or (runs, K + 1, N, n_x, n_x)
        Fused bounds ``P_bar^i_k`` (per run only when links fail).
    u1 : tuple of N arrays (runs, K + 1, p_i)
        ``u_hat^i_{1,k}`` at step ``k`` (lines 20-21), computed with the fused estimate.
    u_hat : tuple of N arrays (runs, K, n_u^i)
        ``u_hat^i_k = V_1 u_hat_1 + V_2 u_hat_2`` for ``k = 0..K-1`` (known at ``k + 1``).
    K, J : (K, N, n_x, n_y) arrays, optional
        Gains of steps ``1..K`` (``keep_steps``).
    W : (K, N, N, n_x, n_x) array, optional
        Fusion weights (20) of steps ``1..K`` (``keep_steps``).
    P_loc : (K, N, n_x, n_x) array, optional
        Local bounds ``P_bar^{i,i}_k`` (``keep_steps``).
    x_loc : (runs, K, N, n_x) array, optional
        Local estimates ``x_hat^{i,i}_k`` (``keep_steps``).
    checks : dict of (K, N) arrays
        Per step and node: ``KU1`` = ``||K U_1||``, ``M2B2`` = ``max|M_bar_2 B_2 - I|`` (10),
        ``G1`` = ``max|G_bar_1|``.
    gains : list of K lists of N LocalGains, optional
        ``gains[k - 1][i]``: node ``i``'s matrices of stage A at step ``k`` (``keep_steps``).
    """

    x: Array
    P: Array
    u1: tuple[Array, ...]
    u_hat: tuple[Array, ...]
    K: Array | None
    J: Array | None
    W: Array | None
    P_loc: Array | None
    x_loc: Array | None
    checks: dict[str, Array]
    gains: list[list[LocalGains]] | None = None


class _Structure(NamedTuple):
    """Per-node ``G_bar^i_k`` and SVDs of ``H_bar^i_k``, with the model's matrices they came from."""

    source: tuple[Any, Any, Any]
    Gs: list[Array]
    decs: list[FeedthroughSVD]


def _structure(mdl: Any, k: int, rtol: float, prev: _Structure | None = None) -> _Structure:
    """SVD of every ``H_bar^i_k`` (display after (3), before (5)); reused while the model
    returns the very same ``G_bar``, ``H_bar`` and ``R`` objects (a time-invariant model)."""
    G, H, R = mdl.Gbar(k), mdl.Hbar(k), mdl.R(k)
    if prev is not None and all(a is b for a, b in zip(prev.source, (G, H, R), strict=True)):
        return prev
    common = isinstance(G, np.ndarray) and G.ndim == 2
    Gs = [G.astype(float)] * mdl.N if common else [np.asarray(g, float) for g in G]
    return _Structure((G, H, R), Gs, _decompose(H, R, mdl.N, rtol))


def _decompose(H: Sequence[Array], R: Array, N: int, rtol: float) -> list[FeedthroughSVD]:
    """SVD and output transform of every ``H_bar^i`` with its ``R^i``."""
    return [feedthrough_decomposition(H[i], R[i], rtol=rtol) for i in range(N)]


def decompositions(mdl: Any, k: int, *, rtol: float = 1e-10) -> list[FeedthroughSVD]:
    """Every node's SVD of ``H_bar^i_k`` and output transform ``T`` (display after (3), before (5)).

    The decomposition the estimator uses at step ``k``
    (:func:`secest.core.estimation.feedthrough_decomposition` of ``mdl.Hbar(k)[i]`` with
    ``mdl.R(k)[i]``): ``U_1, U_2, Sigma, V_1, V_2`` of ``H_bar^i_k`` and ``T_1`` of (5).

    Parameters
    ----------
    mdl : GuoModel or any object with its attributes
        The model (1)-(3).
    k : int
        Step.
    rtol : float, default 1e-10
        Relative rank tolerance of the SVD.

    Returns
    -------
    list of N FeedthroughSVD
    """
    return _decompose(mdl.Hbar(k), mdl.R(k), int(mdl.N), rtol)


def _stack(decs: Sequence[FeedthroughSVD]) -> FeedthroughSVD:
    """Stack decompositions of equal shapes along a new leading (node) axis."""
    fields = FeedthroughSVD._fields[:-1]
    return FeedthroughSVD(*(np.stack([getattr(d, f) for d in decs]) for f in fields), rank=decs[0].rank)


class _Group(NamedTuple):
    """Nodes whose matrices at ``k - 1`` and ``k`` have equal shapes, stacked."""

    idx: list[int]
    G_prev: Array
    dec_prev: FeedthroughSVD
    dec: FeedthroughSVD


class _Plan(NamedTuple):
    prev: _Structure
    cur: _Structure
    groups: list[_Group]


def _plan(prev: _Structure, cur: _Structure, last: _Plan | None) -> _Plan:
    """Group the nodes by the shapes of their matrices (reused for an unchanged structure)."""
    if last is not None and last.prev is prev and last.cur is cur:
        return last
    keys: dict[tuple, list[int]] = {}
    for i in range(len(cur.decs)):
        mats = (prev.Gs[i], *prev.decs[i][:-1], *cur.decs[i][:-1])
        keys.setdefault(tuple(m.shape for m in mats), []).append(i)
    groups = [
        _Group(idx, np.stack([prev.Gs[i] for i in idx]), _stack([prev.decs[i] for i in idx]),
               _stack([cur.decs[i] for i in idx]))
        for idx in keys.values()
    ]
    return _Plan(prev, cur, groups)


def input_one(dec: FeedthroughSVD, C: Array, z1: Array, x: Array) -> Array:
    """``u_hat_{1,k} = Sigma^-1 (z_1 - C_1 x_hat^i_k)`` with ``C_1 = T_1 C`` (Alg. 1 lines 20-21).

    ``x`` is the **fused** estimate; every argument may carry leading (run, node) axes.

    Parameters
    ----------
    dec : FeedthroughSVD
        SVD of ``H_bar^i_k`` (its ``Sigma`` (..., p, p) and ``T1`` (..., p, n_y)), possibly
        stacked over nodes.
    C : (..., n_y, n_x) array
        ``C^i_k``.
    z1 : (..., p) array
        ``z^i_{1,k} = T_1 y^{a,i}_k`` (5).
    x : (..., n_x) array
        Fused estimate ``x_hat^i_k`` (21).

    Returns
    -------
    (..., p) array
        ``u_hat^i_{1,k}``, the estimate of the input part seen in the output.
    """
    return np.linalg.solve(dec.Sigma, (z1 - _apply(dec.T1 @ C, x))[..., None])[..., 0]


class GuoState(NamedTuple):
    """What the estimator carries from step ``k - 1`` to ``k``.

    Attributes
    ----------
    k : int
        Step of the state (0 after :func:`initial_state`).
    x : (runs, N, n_x) array
        Fused estimates ``x_hat^i_k`` (21).
    P : (N, n_x, n_x) or (runs, N, n_x, n_x) array
        Fused bounds ``P_bar^i_k`` (19); one per run only when links fail.
    u1 : list of N (runs, p_i) arrays
        ``u_hat^i_{1,k}`` (Algorithm 1 line 21), ``p_i = rank H_bar^i_k``.
    structure : internal
        Every node's ``G_bar^i_k`` and SVD of ``H_bar^i_k`` at step ``k``, reused at the next
        step for ``V_1, V_2`` (and kept while the model is time-invariant).
    plan : internal or None, default None
        Grouping of the nodes whose matrices at ``k - 1`` and ``k`` have equal shapes (they are
        processed as one stack); None before the first step.
    """

    k: int
    x: Array
    P: Array
    u1: list[Array]
    structure: _Structure
    plan: _Plan | None = None


class GuoStep(NamedTuple):
    """The matrices and local pairs of one step (the data-independent ones are what the
    notebook's exact joint covariance needs).

    The leading axes ``...`` are those of the bounds: none, or ``runs`` when links fail.
    :func:`run_estimator` drops ``K``, ``J``, ``W`` and ``P_loc`` (None) unless ``keep_steps``.

    Attributes
    ----------
    K : (..., N, n_x, n_y) array or None
        Gains (28) of step ``k``.
    J : (..., N, n_x, n_y) array or None
        ``G_bar_2 M_bar_2 U_2^T`` (A8).
    W : (..., N, N, n_x, n_x) array or None
        Fusion weights (20) ``W^{i,j}_k``; None unless ``matrix_weights``.
    P_loc : (..., N, n_x, n_x) array or None
        Local bounds ``P_bar^{i,i}_k`` (29).
    x_loc : (runs, N, n_x) array
        Local estimates ``x_hat^{i,i}_k`` (14) row 5, before the fusion.
    u_hat : list of N (runs, n_u^i) arrays
        ``u_hat^i_{k-1} = V_1 u_hat^i_{1,k-1} + V_2 u_hat^i_{2,k-1}``, the input estimate one
        step late.
    checks : dict of (N,) arrays
        Per node: ``KU1`` = ``||K U_1||`` (28), ``M2B2`` = ``max|M_bar_2 B_2 - I|`` (10),
        ``G1`` = ``max|G_bar_1|``; all zero up to round-off.
    gains : list of N LocalGains or None, default None
        Node ``i``'s matrices of stage A (:func:`local_gains`: ``M_bar_2``, ``P_bar*``, ``S``,
        ``Xi_bar``, ``Theta``, ...), the leading axes those of the bounds; None unless
        ``keep_gains``.
    """

    K: Array | None
    J: Array | None
    W: Array | None
    P_loc: Array | None
    x_loc: Array
    u_hat: list[Array]
    checks: dict[str, Array]
    gains: list[LocalGains] | None = None


def initial_state(mdl: Any, ya0: Array, *, per_run: bool = False, rtol: float = 1e-10) -> GuoState:
    """Algorithm 1 line 1: ``x_hat^i_0 = x_hat_0``, ``P_bar^i_0 = P_0``, ``u_hat^i_{1,0}``.

    Parameters
    ----------
    mdl : GuoModel or any object with its attributes
        The model (1)-(3).
    ya0 : (runs, N, n_y) array
        Attacked measurements ``y^{a,i}_0``, for ``u_hat^i_{1,0} = Sigma^-1 (z_{1,0} - C_1 x_hat_0)``.
    per_run : bool, default False
        Carry one bound per run, ``P`` of shape (runs, N, n_x, n_x) (needed when links fail
        and the bounds depend on the run); else (N, n_x, n_x).
    rtol : float, default 1e-10
        Relative rank tolerance of the SVD of ``H_bar^i_0``.

    Returns
    -------
    GuoState
        The state at ``k = 0``.
    """
    struct = _structure(mdl, 0, rtol)
    runs, N, nx = ya0.shape[0], int(mdl.N), int(mdl.nx)
    x = np.broadcast_to(np.asarray(mdl.x0_hat, float), (runs, N, nx)).copy()
    P = np.broadcast_to(np.asarray(mdl.P0, float), ((runs,) if per_run else ()) + (N, nx, nx)).copy()
    C0 = np.asarray(mdl.C(0), float)
    u1 = [input_one(d, C0[i], _apply(d.T1, ya0[:, i]), x[:, i]) for i, d in enumerate(struct.decs)]
    return GuoState(0, x, P, u1, struct)


def _checks(g: LocalGains, U1: Array, n_nodes: int) -> dict[str, Array]:
    """Per-node structure checks of one stack: ``||K U_1||``, ``|M_bar_2 B_2 - I|``, ``|G_bar_1|``."""
    m = g.B2.shape[-1]

    def per_node(a: Array) -> Array:
        return a.reshape(-1, n_nodes).max(axis=0)

    return {
        "KU1": per_node(np.linalg.norm(g.K @ U1, axis=(-2, -1))),
        "M2B2": per_node(np.abs(g.M2 @ g.B2 - np.eye(m)).max(axis=(-2, -1), initial=0.0)),
        "G1": per_node(np.abs(g.G1).max(axis=(-2, -1), initial=0.0)),
    }


def estimator_step(
    mdl: Any,
    state: GuoState,
    ya: Array,
    *,
    received: Array | Callable[[Array], Array] | None = None,
    weights: Array | None = None,
    up: Array | None = None,
    matrix_weights: bool = True,
    keep_gains: bool = False,
    rtol: float = 1e-10,
    gain: str = "constrained",
) -> tuple[GuoState, GuoStep]:
    """One step ``k - 1 -> k`` of Algorithm 1 at every node (stages A-D).

    Nodes whose matrices have equal shapes are processed as one stack.

    Parameters
    ----------
    mdl : GuoModel or any object with its attributes
        The model (1)-(3).
    state : GuoState
        From :func:`initial_state` or the previous step.
    ya : (runs, N, n_y) array
        Attacked measurements at step ``k``.
    received : (runs, N, N, n_x) array or callable, optional
        Stage B: what node ``i`` receives from ``j``; a callable gets the local estimates
        ``(runs, N, n_x)`` and returns it. Default: the local estimates as sent. With a sparse
        ``mdl.Pi``: ``(runs, E, n_x)``, one row per off-diagonal stored entry of ``Pi`` (the
        graph's edges, receiver by receiver), the own estimates being inserted here.
    weights : (N, N) or (runs, N, N) array, optional
        Fusion weights of this step; default ``mdl.Pi``.
    up : (runs,) array of 0 / 1, optional
        With a sparse ``mdl.Pi``: the state of every link per run (:func:`fuse`).
    matrix_weights : bool, default True
        Return the fusion weights (20) in the step record.
    keep_gains : bool, default False
        Return every node's :class:`LocalGains` in the step record (``GuoStep.gains``).
    rtol : float
        SVD rank tolerance.
    gain : {"constrained", "unconstrained"}, default "constrained"
        The local gain (:func:`local_gains`): (28), or the unconstrained negative control (ours).

    Returns
    -------
    GuoState, GuoStep
    """
    k = state.k + 1
    N, nx = int(mdl.N), int(mdl.nx)
    A, Q = np.asarray(mdl.A(k - 1), float), np.asarray(mdl.Q(k - 1), float)
    Ck, Rk = np.asarray(mdl.C(k), float), np.asarray(mdl.R(k), float)
    struct = _structure(mdl, k, rtol, state.structure)
    plan = _plan(state.structure, struct, state.plan)
    runs, lead = ya.shape[0], state.P.shape[:-3]
    x_loc, P_loc = np.empty((runs, N, nx)), np.empty_like(state.P)
    K, J = np.empty((*lead, N, nx, Ck.shape[1])), np.empty((*lead, N, nx, Ck.shape[1]))
    u2, z1 = [], []
    gains: list[LocalGains | None] = [None] * N
    checks = {name: np.zeros(N) for name in ("KU1", "M2B2", "G1")}
    for grp in plan.groups:  # stage A
        idx = grp.idx
        P_prev = state.P[..., idx, :, :]
        g = local_gains(A, Q, grp.G_prev, P_prev, grp.dec_prev, grp.dec, Ck[idx], Rk[idx], gain=gain)
        u1_prev = np.stack([state.u1[i] for i in idx], axis=1)
        xl, u2g, z1g = local_estimate(g, A, state.x[:, idx], u1_prev, grp.dec, Ck[idx], ya[:, idx])
        x_loc[:, idx], P_loc[..., idx, :, :] = xl, g.P_loc
        K[..., idx, :, :], J[..., idx, :, :] = g.K, g.J
        u2.append(u2g)
        z1.append(z1g)
        if keep_gains:
            for n_, i in enumerate(idx):  # every field is a matrix: the node axis is -3
                gains[i] = LocalGains(*(f[..., n_, :, :] for f in g))
        for name, val in _checks(g, grp.dec.U1, len(idx)).items():
            checks[name][idx] = val
    Pi = mdl.Pi if weights is None else weights
    if callable(received):  # stage B: exchange
        received = received(x_loc)
    if sp.issparse(Pi):
        received = _closed(sp.csr_array(Pi), x_loc, received)
    elif received is None:
        received = np.broadcast_to(x_loc[:, None], (runs, N, N, nx))
    P, W, x = fuse(P_loc, Pi, received, matrix_weights=matrix_weights, up=up)  # stage C
    u1, u_hat = [None] * N, [None] * N
    for grp, u2g, z1g in zip(plan.groups, u2, z1, strict=True):  # stage D
        idx = grp.idx
        u1_prev = np.stack([state.u1[i] for i in idx], axis=1)
        uh = _apply(grp.dec_prev.V1, u1_prev) + _apply(grp.dec_prev.V2, u2g)  # u_hat_{k-1}
        u1g = input_one(grp.dec, Ck[idx], z1g, x[:, idx])  # lines 20-21, fused x
        for n_, i in enumerate(idx):
            u1[i], u_hat[i] = u1g[:, n_], uh[:, n_]
    step = GuoStep(K, J, W, P_loc, x_loc, u_hat, checks, gains if keep_gains else None)
    return GuoState(k, x, P, u1, struct, plan), step


def _closed(Pi: sp.csr_array, x_loc: Array, received: Array | None) -> Array:
    """Per stored entry of ``Pi``: the own local estimate on the diagonal, ``received`` (per
    off-diagonal entry; default the estimates as sent) elsewhere."""
    rows, cols, _ = _entries(Pi)
    own = rows == cols
    out = x_loc[:, cols]
    if received is not None:
        if np.shape(received) != (x_loc.shape[0], int((~own).sum()), x_loc.shape[-1]):
            raise ValidationError(f"received: expected per-edge estimates of shape "
                                  f"{(x_loc.shape[0], int((~own).sum()), x_loc.shape[-1])}, "
                                  f"found {np.shape(received)}")
        out[:, ~own] = received
    return out


def link_weights(Pi: Array, up: Array) -> Array:
    """Fusion weights of one step when messages may be lost: ``pi_ij`` renormalised over the
    messages node ``i`` received (``up[r]`` = 1: every link up in run ``r``; 0: none).

    Parameters
    ----------
    Pi : (N, N) array
        Weights ``pi_ij`` of (19)-(21), row-stochastic with ``pi_ii > 0`` (a node always has
        its own estimate).
    up : (runs,) array of 0 / 1
        State of the link shared by every edge at this step, per run (``Trial.link[:, k]``).

    Returns
    -------
    (runs, N, N) array
        ``Pi`` where the links are up; the identity (each node keeps its own estimate) where
        they are down.
    """
    mask = np.where(np.asarray(up)[:, None, None] == 1, 1.0, np.eye(Pi.shape[0]))
    w = Pi * mask
    return w / w.sum(axis=-1, keepdims=True)


def run_estimator(
    mdl: Any,
    ya: Array,
    *,
    received: Callable[[int, Array], Array] | None = None,
    link: Array | None = None,
    keep_steps: bool = True,
    rtol: float = 1e-10,
    gain: str = "constrained",
) -> GuoRun:
    """Algorithm 1 (corrected) over all runs and nodes, ``k = 1..K`` (:func:`estimator_step`).

    Parameters
    ----------
    mdl : GuoModel or any object with its attributes (e.g. the notebook's model)
        The model (1)-(3).
    ya : (runs, K + 1, N, n_y) array
        Attacked measurements ``y^{a,i}_k``.
    received : callable, optional
        ``received(k, x_loc) -> (runs, N, N, n_x)``: what node ``i`` receives from ``j`` at
        step ``k`` (stage B); default: the estimates as sent. With a sparse ``mdl.Pi``
        ``(runs, E, n_x)`` per edge (:func:`estimator_step`): every step then costs ``O(E)``.
    link : (runs, K + 1) array of 0/1, optional
        State of every link at step ``k`` (shared by all links); a lost message is left out
        of (19)-(21) and the weights renormalised (:func:`link_weights`). Default: always up.
        With failing links the bounds depend on the run.
    keep_steps : bool, default True
        Also return the gains, fusion weights, local pairs and every node's
        :class:`LocalGains` of every step.
    rtol : float, default 1e-10
        Relative rank tolerance of the SVD of ``H_bar^i``.
    gain : {"constrained", "unconstrained"}, default "constrained"
        The local gain (:func:`local_gains`): (28), the paper's, or ``"unconstrained"``,
        ``S Xi_breve^+`` without ``K U_1 = 0`` (ours: a negative control of the decoupling).

    Returns
    -------
    GuoRun

    Raises
    ------
    ValidationError
        ``ya`` or ``link`` of the wrong shape, ``Pi`` not row-stochastic, or ``gain`` not one
        of :data:`GAINS`.
    """
    if gain not in GAINS:
        raise ValidationError(f"gain: expected one of {GAINS}, found {gain!r}")
    ya = np.asarray(ya, float)
    N = int(mdl.N)
    if ya.ndim != 4 or ya.shape[2] != N:
        raise ValidationError(
            f"Incompatible dimensions of ya: expected (runs, K + 1, {N}, n_y), found {ya.shape}"
        )
    runs, K1 = ya.shape[:2]
    Pi = check_weights(mdl.Pi)
    if link is not None and np.shape(link) != (runs, K1):
        raise ValidationError(
            f"Incompatible dimensions of link: expected {(runs, K1)}, found {np.shape(link)}"
        )
    per_run = link is not None and not np.all(np.asarray(link) == 1)
    state = initial_state(mdl, ya[:, 0], per_run=per_run, rtol=rtol)
    xs, Ps, u1s, steps = [state.x], [state.P], [state.u1], []
    for k in range(1, K1):
        recv = None if received is None else (lambda m, k=k: received(k, m))
        sparse = sp.issparse(Pi)
        weights = link_weights(Pi, link[:, k]) if per_run and not sparse else Pi
        state, step = estimator_step(mdl, state, ya[:, k], received=recv, weights=weights,
                                     up=link[:, k] if per_run and sparse else None,
                                     matrix_weights=keep_steps, keep_gains=keep_steps, rtol=rtol,
                                     gain=gain)
        xs.append(state.x)
        Ps.append(state.P)
        u1s.append(state.u1)
        steps.append(step if keep_steps else step._replace(K=None, J=None, W=None, P_loc=None))
    axis = 1 if per_run else 0

    def stacked(name: str, ax: int) -> Array | None:
        return np.stack([getattr(s, name) for s in steps], axis=ax) if keep_steps and steps else None

    return GuoRun(
        x=np.stack(xs, axis=1),
        P=np.stack(Ps, axis=axis),
        u1=tuple(np.stack([u[i] for u in u1s], axis=1) for i in range(N)),
        u_hat=tuple(np.stack([s.u_hat[i] for s in steps], axis=1) if steps else np.empty((runs, 0, 0))
                    for i in range(N)),
        K=stacked("K", axis), J=stacked("J", axis), W=stacked("W", axis), P_loc=stacked("P_loc", axis),
        x_loc=stacked("x_loc", 1),
        checks={name: np.array([s.checks[name] for s in steps]) for name in ("KU1", "M2B2", "G1")},
        gains=[s.gains for s in steps] if keep_steps else None,
    )


# ---------------------------------------------------------------------------------- analysis


def error_covariance(mdl: Any, run: GuoRun, *, spread: float = 1.0) -> tuple[Array, Array, Array]:
    """Exact covariances of the fused and local errors, propagated with the run's gains (ours).

    The gains do not depend on the data, so with ``Phi^i = (I - K^i C^i)(I - J^i C^i)`` and
    ``Psi^i = (I - K^i C^i) J^i + K^i`` the local errors are
    ``x_tilde^{i,i}_k = Phi^i (A_{k-1} x_tilde^i_{k-1} + w_{k-1}) - Psi^i v^i_k`` ((14)-(16) with
    ``G_bar_1 = 0`` and ``K U_1 = 0``; ``w`` common to every node), and the stacked fused errors
    ``e_k = [x_tilde^1_k; ...; x_tilde^N_k]`` have the covariance

    .. math::  \\Sigma^{loc}_k = F \\Sigma_{k-1} F^T + \\Phi_{col} Q \\Phi_{col}^T
               + \\mathrm{blkdiag}(\\Psi^i R^i \\Psi^{iT}), \\qquad \\Sigma_k = W \\Sigma^{loc}_k W^T

    with ``F = blkdiag(Phi^i A_{k-1})``, ``Phi_col = [Phi^1; ...; Phi^N]``, ``W = [W^{i,j}_k]`` (20)
    and ``Sigma_0 = spread^2 1 1^T (x) P_0``. Its diagonal blocks are the true error covariances
    ``P^i_k`` that Theorem 1 bounds by ``P_bar^i_k``.

    Parameters
    ----------
    mdl : GuoModel or any object with its attributes
        The model (1)-(3) the run was made on.
    run : GuoRun
        From :func:`run_estimator` with ``keep_steps`` and every link up (``K``, ``J``, ``W``
        shared by the runs).
    spread : float, default 1.0
        ``cov(x_0 - x_hat_0) = spread^2 P_0``.

    Returns
    -------
    P : (K + 1, N, n_x, n_x) array
        Covariances of the fused errors ``x_k - x_hat^i_k``.
    P_loc : (K, N, n_x, n_x) array
        Covariances of the local errors ``x_k - x_hat^{i,i}_k``, ``k = 1..K``.
    Psi : (K, N, n_x, n_y) array
        Noise gains ``Psi^i_k``.

    Raises
    ------
    ValidationError
        ``run`` without its steps (``keep_steps=False``), with per-run gains (failing links), or
        on a model with sparse ``Pi`` (its weights are kept per stored entry, not as ``W``).
    """
    if run.K is None or run.J is None or run.W is None:
        raise ValidationError("run must keep its steps (run_estimator(..., keep_steps=True))")
    if sp.issparse(mdl.Pi):
        raise ValidationError("mdl.Pi must be a dense (N, N) array: the joint covariance needs every "
                              "W^{i,j}, which a run with sparse Pi keeps per stored entry only")
    if run.W.ndim != 5:
        raise ValidationError(f"run must have gains shared by its runs (no failing link), found W of "
                              f"shape {run.W.shape}")
    N, nx = int(mdl.N), int(mdl.nx)
    n_steps, ny = run.K.shape[0], run.K.shape[-1]
    Sig = spread**2 * np.kron(np.ones((N, N)), np.asarray(mdl.P0, float))
    P = np.empty((n_steps + 1, N, nx, nx))
    P_loc = np.empty((n_steps, N, nx, nx))
    Psi_all = np.empty((n_steps, N, nx, ny))

    def blocks(S: Array) -> Array:
        return np.array([S[i * nx:(i + 1) * nx, i * nx:(i + 1) * nx] for i in range(N)])

    P[0] = blocks(Sig)
    eye = np.eye(nx)
    for k in range(1, n_steps + 1):
        A, Q, Ck, Rk = mdl.A(k - 1), mdl.Q(k - 1), mdl.C(k), mdl.R(k)
        K, J = run.K[k - 1], run.J[k - 1]
        IKC = [eye - K[i] @ Ck[i] for i in range(N)]
        Phi = [IKC[i] @ (eye - J[i] @ Ck[i]) for i in range(N)]
        Psi = [IKC[i] @ J[i] + K[i] for i in range(N)]
        F = sla.block_diag(*[Ph @ A for Ph in Phi])
        Phi_col = np.vstack(Phi)
        S_loc = (F @ Sig @ F.T + Phi_col @ Q @ Phi_col.T
                 + sla.block_diag(*[Psi[i] @ Rk[i] @ Psi[i].T for i in range(N)]))
        W = run.W[k - 1].transpose(0, 2, 1, 3).reshape(N * nx, N * nx)
        Sig = symmetrize(W @ S_loc @ W.T)
        P[k], P_loc[k - 1], Psi_all[k - 1] = blocks(Sig), blocks(S_loc), np.array(Psi)
    return P, P_loc, Psi_all
