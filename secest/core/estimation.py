"""Joint state / unknown-input estimation helpers (guo2023 and any filter with feed-through).

Plain functions for estimators of the Gillijns--De Moor / Yong--Zhu--Frazzoli family, where an
unknown input ``u`` enters the output through a feed-through matrix ``H``:

.. math::  x_{k+1} = A_k x_k + G_k u_k + w_k, \\qquad y_k = C_k x_k + H_k u_k + v_k .

``feedthrough_decomposition``
   SVD of ``H`` and the decorrelating output transform ``T``
   (guo2023, display after (3) and before (5))
``constrained_gain``
   trace-minimising gain under ``K U_1 = 0`` (guo2023, (28))
``ltv_observability_matrix``
   observability matrix of a linear time-varying pair
   ``col(C_k, C_{k+1} A_k, C_{k+2} A_{k+1} A_k, ...)``
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.core import validation as V
from secest.core.covariance import check_psd
from secest.core.validation import ValidationError, as_matrix

__all__ = [
    "FeedthroughSVD",
    "constrained_gain",
    "feedthrough_decomposition",
    "ltv_observability_matrix",
    "relative_rank",
]


class FeedthroughSVD(NamedTuple):
    """Output of :func:`feedthrough_decomposition` (guo2023 notation).

    Attributes
    ----------
    U1 : (n_y, p) ndarray
        Left singular vectors of the range of ``H``.
    U2 : (n_y, n_y - p) ndarray
        Orthonormal basis of the left null space of ``H``.
    Sigma : (p, p) ndarray
        Diagonal matrix of the non-zero singular values.
    V1 : (n_u, p) ndarray
        Right singular vectors: ``u_1 = V1^T u`` is seen in the output.
    V2 : (n_u, n_u - p) ndarray
        The rest: ``u_2 = V2^T u`` is not seen in the output.
    T1 : (p, n_y) ndarray
        First block row of the output transform ``T``; ``T1 R U2 = 0``.
    rank : int
        ``p = rank H`` decided with the relative tolerance ``rtol``.
    """

    U1: NDArray[np.float64]
    U2: NDArray[np.float64]
    Sigma: NDArray[np.float64]
    V1: NDArray[np.float64]
    V2: NDArray[np.float64]
    T1: NDArray[np.float64]
    rank: int


def relative_rank(M: ArrayLike, rtol: float = 1e-10) -> int:
    """Number of singular values of ``M`` larger than ``rtol`` times the largest one.

    Parameters
    ----------
    M : (p, q) array_like
        Finite matrix (may have no entries: rank 0).
    rtol : float, default 1e-10
        Relative cut-off, in (0, 1).

    Returns
    -------
    int

    Raises
    ------
    ValidationError
        If ``M`` is not a finite 2-D array or ``rtol`` is not in (0, 1).
    """
    M = as_matrix("M", M, (None, None), empty=True)
    rtol = _check_rtol(rtol)
    if M.size == 0:
        return 0
    s = np.linalg.svd(M, compute_uv=False)
    if s[0] == 0.0:
        return 0
    return int(np.sum(s > rtol * s[0]))


def feedthrough_decomposition(H: ArrayLike, R: ArrayLike, *, rtol: float = 1e-10) -> FeedthroughSVD:
    """SVD of a feed-through matrix and the noise-decorrelating output transform.

    With ``H = [U1 U2] diag(Sigma, 0) [V1 V2]^T`` (one SVD call, so the signs of ``U`` and
    ``V`` match) and ``p = rank H``, the transform of guo2023 (display before (5)) is

    .. math::  T = \\begin{bmatrix} I & -U_1^T R U_2 (U_2^T R U_2)^{-1} \\\\ 0 & I \\end{bmatrix}
               \\begin{bmatrix} U_1^T \\\\ U_2^T \\end{bmatrix},

    so that ``z1 = T1 y = T1 C x + Sigma u_1 + T1 v`` and ``z2 = U2^T y = U2^T C x + U2^T v``
    with uncorrelated noises (``T1 R U2 = 0``). When ``R`` is a multiple of the identity,
    ``T1 = U1^T``.

    Parameters
    ----------
    H : (n_y, n_u) array_like
        Feed-through matrix of the unknown input (guo2023: ``H_bar = [0 H]``); ``n_u = 0``
        (no unknown input reaches these outputs) is allowed and gives ``p = 0``.
    R : (n_y, n_y) array_like
        Measurement-noise covariance, symmetric positive definite.
    rtol : float, default 1e-10
        Singular values ``<= rtol * sigma_max`` count as zero.

    Returns
    -------
    FeedthroughSVD

    Raises
    ------
    ValidationError
        Non-finite or non-2-D ``H``; ``R`` of the wrong shape or not positive definite;
        ``rtol`` outside (0, 1).
    """
    H = as_matrix("H", H, (None, None), empty=True)  # n_u = 0 columns: no unknown input
    ny, nu = H.shape
    if ny == 0:
        raise ValidationError(f"H must have at least one row (output), found shape (0, {nu})")
    R = check_psd("R", as_matrix("R", R, (ny, ny), note="to match H"), strict=True)
    rtol = _check_rtol(rtol)
    U, s, Vt = np.linalg.svd(H)
    p = int(np.sum(s > rtol * s[0])) if s.size and s[0] > 0 else 0
    U1, U2 = U[:, :p], U[:, p:]
    V1, V2 = Vt[:p].T, Vt[p:].T
    if U2.shape[1] > 0:
        T1 = U1.T - U1.T @ R @ U2 @ np.linalg.solve(U2.T @ R @ U2, U2.T)
    else:
        T1 = U1.T.copy()
    return FeedthroughSVD(U1=U1, U2=U2, Sigma=np.diag(s[:p]), V1=V1, V2=V2, T1=T1, rank=p)


def constrained_gain(
    S: ArrayLike, Theta: ArrayLike, U1: ArrayLike, *, stacked: bool = False
) -> NDArray[np.float64]:
    """Gain minimising ``tr P`` subject to ``K U1 = 0`` (guo2023, Lemma 2, (28)).

    .. math::  K = S \\Theta \\left[I - U_1 (U_1^T \\Theta U_1)^{-1} U_1^T \\Theta\\right]

    Any ``Theta`` of the family of Lemma 1, or ``Theta = Xi^{-1}(I - C J)`` of Algorithm 1
    line 13, gives the same gain (see the guo2023 notebook). ``K U1 = 0`` holds by
    construction, whatever ``S`` is.

    Parameters
    ----------
    S : (n_x, n_y) array_like
        Cross term ``P* C^T - J R`` of (26).
    Theta : (n_y, n_y) array_like
        Weighting matrix of (27)-(28).
    U1 : (n_y, p) array_like
        Directions of the output that the unknown input can excite (``p = 0`` allowed).
    stacked : bool, default False
        Accept stacks of matrices over leading axes that broadcast against each other
        (``S`` (..., n_x, n_y), ``Theta`` (..., n_y, n_y), ``U1`` (..., n_y, p)): every run and
        node of guo2023's estimator at once; only the trailing shapes and finiteness are checked.

    Returns
    -------
    (..., n_x, n_y) ndarray

    Raises
    ------
    ValidationError
        Incompatible shapes, or ``U1^T Theta U1`` singular (relative condition > 1e12).
    """
    if stacked:
        S, Theta, U1 = _stacks(S, Theta, U1)
    else:
        S = as_matrix("S", S, (None, None))
        ny = S.shape[1]
        Theta = as_matrix("Theta", Theta, (ny, ny), note="to match S")
        U1 = as_matrix("U1", U1, (ny, None), empty=True, note="to match S")
    if U1.shape[-1] == 0:
        return S @ Theta
    U1t = np.swapaxes(U1, -1, -2)
    ThU1 = Theta @ U1
    inner = U1t @ ThU1
    cond = np.linalg.cond(inner)
    if np.any(cond > 1e12):
        raise ValidationError(
            f"U1^T Theta U1 must be invertible, found condition number {np.max(cond):.3g}"
        )
    return S @ Theta - S @ ThU1 @ np.linalg.solve(inner, U1t @ Theta)  # (28)


def _stacks(S: ArrayLike, Theta: ArrayLike, U1: ArrayLike) -> tuple[NDArray, NDArray, NDArray]:
    """Stacks of ``S``, ``Theta``, ``U1`` with compatible trailing shapes and finite entries."""
    arrays = [np.asarray(a, dtype=np.float64) for a in (S, Theta, U1)]
    for name, a in zip(("S", "Theta", "U1"), arrays, strict=True):
        if a.ndim < 2:
            raise ValidationError(f"{name} must be a stack of matrices (ndim >= 2), "
                                  f"found shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise ValidationError(f"{name} must be finite")
    S_, Th, U = arrays
    ny = S_.shape[-1]
    if Th.shape[-2:] != (ny, ny) or U.shape[-2] != ny:
        raise ValidationError(f"Incompatible dimensions: S (..., n_x, {ny}) needs Theta "
                              f"(..., {ny}, {ny}) and U1 (..., {ny}, p), found {Th.shape} and {U.shape}")
    return S_, Th, U


def ltv_observability_matrix(
    A_seq: Sequence[ArrayLike], C_seq: Sequence[ArrayLike]
) -> NDArray[np.float64]:
    """Observability matrix of ``x_{k+1} = A_k x_k``, ``y_k = C_k x_k`` over a window.

    ``O = col(C_0, C_1 A_0, C_2 A_1 A_0, ..., C_{L-1} A_{L-2} ... A_0)`` for
    ``C_seq = [C_0, ..., C_{L-1}]`` and ``A_seq = [A_0, ..., A_{L-2}]`` (the last ``A`` is not
    needed; a sequence of length ``L`` is accepted too). ``rank O = n`` means the initial
    state of the window is determined by the outputs of the window. For a constant pair it
    equals :func:`secest.core.systems.observability_matrix`.

    Parameters
    ----------
    A_seq : sequence of (n, n) array_like
        ``L - 1`` or ``L`` state matrices.
    C_seq : sequence of (m_k, n) array_like
        ``L`` output matrices (row counts may differ).

    Returns
    -------
    (sum_k m_k, n) ndarray

    Raises
    ------
    ValidationError
        Empty ``C_seq``, too few ``A`` matrices, or incompatible shapes.
    """
    Cs = _sequence("C_seq", C_seq)
    As = _sequence("A_seq", A_seq)
    if not Cs:
        raise ValidationError("C_seq must contain at least one output matrix")
    if len(As) < len(Cs) - 1:
        raise ValidationError(
            f"A_seq must hold at least len(C_seq) - 1 = {len(Cs) - 1} matrices, found {len(As)}"
        )
    C0 = np.atleast_2d(as_matrix("C_seq[0]", Cs[0]))
    n = C0.shape[1]
    rows_total = sum(np.size(Ck) for Ck in Cs)
    V.check_size("C_seq", rows_total + len(Cs) * n * n, V.MAX_ELEMENTS, "array entries")
    Phi = np.eye(n)
    rows = []
    for k, Ck in enumerate(Cs):
        Ck = np.atleast_2d(as_matrix(f"C_seq[{k}]", Ck))
        if Ck.ndim != 2 or Ck.shape[1] != n:
            raise ValidationError(
                f"Incompatible dimensions of C_seq[{k}]: expected (*, {n}), found {Ck.shape}"
            )
        rows.append(Ck @ Phi)
        if k < len(Cs) - 1:
            Ak = as_matrix(f"A_seq[{k}]", As[k], (n, n), note="to match the columns of C_seq")
            Phi = Ak @ Phi
    return np.vstack(rows)


def _check_rtol(rtol: float) -> float:
    return V.check_real("rtol", rtol, lower=0.0, upper=1.0, lower_open=True, upper_open=True)


def _sequence(name: str, value: object) -> list:
    text = isinstance(value, str | bytes)
    flat = isinstance(value, np.ndarray) and value.ndim < 2
    if text or flat or not hasattr(value, "__iter__"):
        raise ValidationError(f"{name} must be a sequence of matrices, found {V._show(value)}")
    return list(value)
