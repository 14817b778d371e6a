"""Covariance helpers: symmetrisation, PSD checks, Joseph form and fusion.

Conventions follow the estimation literature: ``P`` is an error covariance,
``H`` a measurement matrix, ``R`` a measurement-noise covariance, ``K`` a gain.
Symmetrisation is explicit (keyword ``symmetrize_result``) so a reader sees where it
happens. Every PSD / PD test uses the relative rule of :mod:`secest.core.validation`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.core import validation as V
from secest.core.validation import ValidationError, as_matrix, check_psd

__all__ = [
    "check_psd",
    "covariance_intersection",
    "information_fusion",
    "is_psd",
    "joseph_update",
    "min_eig",
    "symmetrize",
]


def _square_stack(name: str, P: ArrayLike) -> NDArray[np.float64]:
    arr = as_matrix(name, P)
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2]:
        raise ValidationError(f"{name} must be square in its last two axes, found shape {arr.shape}")
    return arr


def symmetrize(P: ArrayLike) -> NDArray[np.float64]:
    """Symmetric part ``(P + P^T) / 2`` (works on stacks of matrices, last two axes).

    Parameters
    ----------
    P : array_like, shape (..., n, n)
        Finite matrix or stack of matrices.

    Returns
    -------
    ndarray, shape (..., n, n)
    """
    arr = _square_stack("P", P)
    return 0.5 * (arr + np.swapaxes(arr, -1, -2))


def min_eig(P: ArrayLike) -> float | NDArray[np.float64]:
    """Smallest eigenvalue of the symmetric part of ``P`` (per matrix for a stack).

    Parameters
    ----------
    P : array_like, shape (..., n, n)
        Finite matrix or stack of matrices (NaN or infinite entries are refused).

    Returns
    -------
    float or ndarray of shape (...)
    """
    lam = np.linalg.eigvalsh(symmetrize(P))[..., 0]
    return float(lam) if lam.ndim == 0 else lam


def is_psd(P: ArrayLike, *, tol: float = V.RTOL, strict: bool = False) -> bool:
    """Whether ``P`` is a finite symmetric PSD (PD if ``strict``) matrix.

    Same relative rule as :func:`check_psd` (see :mod:`secest.core.validation`); a matrix
    that is not square or not finite is not PSD.

    Parameters
    ----------
    P : array_like, shape (n, n)
        Matrix to test.
    tol : float, default secest.core.validation.RTOL
        Relative tolerance.
    strict : bool, default False
        Test positive definiteness.

    Returns
    -------
    bool
    """
    tol = V.check_real("tol", tol, lower=0.0)
    strict = V.check_bool("strict", strict)
    arr = as_matrix("P", P, finite=False)
    if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or not np.all(np.isfinite(arr)):
        return False
    try:
        check_psd("P", arr, tol=tol, strict=strict)
    except ValidationError:
        return False
    return True


def joseph_update(
    P: ArrayLike, K: ArrayLike, H: ArrayLike, R: ArrayLike, *, symmetrize_result: bool = True
) -> NDArray[np.float64]:
    """Joseph-form covariance update ``(I - K H) P (I - K H)^T + K R K^T``.

    Valid for any gain ``K`` (not only the optimal one) and PSD by construction when
    ``P`` and ``R`` are.

    Parameters
    ----------
    P : (n, n) array_like
        Prior error covariance, symmetric PSD.
    K : (n, m) array_like
        Gain.
    H : (m, n) array_like
        Measurement matrix.
    R : (m, m) array_like
        Measurement-noise covariance, symmetric PSD.
    symmetrize_result : bool, default True
        Return the symmetric part, removing round-off asymmetry.

    Returns
    -------
    (n, n) ndarray
    """
    P = check_psd("P", as_matrix("P", P, square=True))
    n = P.shape[0]
    H = as_matrix("H", H, (None, n))
    m = H.shape[0]
    K = as_matrix("K", K, (n, m))
    R = check_psd("R", as_matrix("R", R, (m, m)))
    ikh = np.eye(n) - K @ H
    out = ikh @ P @ ikh.T + K @ R @ K.T
    return symmetrize(out) if V.check_bool("symmetrize_result", symmetrize_result) else out


def _sequence(name: str, value: object) -> list:
    if isinstance(value, str | bytes) or not hasattr(value, "__len__"):
        raise ValidationError(f"{name} must be a sequence of arrays, found {type(value).__name__}")
    return list(value)


def _stack_estimates(
    estimates: Sequence[ArrayLike], covariances: Sequence[ArrayLike], weights: ArrayLike | None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    xs = _sequence("estimates", estimates)
    Ps = _sequence("covariances", covariances)
    if not xs:
        raise ValidationError("estimates must contain at least one estimate")
    n = np.atleast_1d(as_matrix("estimates[0]", xs[0])).shape[0]
    x = np.stack([as_matrix(f"estimates[{i}]", np.atleast_1d(v), (n,)) for i, v in enumerate(xs)])
    if len(Ps) != len(xs):
        raise ValidationError(
            f"covariances must have one matrix per estimate: expected {len(xs)}, found {len(Ps)}"
        )
    P = np.stack([as_matrix(f"covariances[{i}]", c, (n, n)) for i, c in enumerate(Ps)])
    for i in range(len(P)):
        check_psd(f"covariances[{i}]", P[i], strict=True)
    if weights is None:
        w = np.full(len(xs), 1.0 / len(xs))
    else:
        w = as_matrix("weights", weights, (len(xs),))
        scale = max(1.0, float(np.abs(w).sum()))
        if np.any(w < 0) or abs(w.sum() - 1.0) > V.RTOL * scale:
            raise ValidationError(f"weights must be non-negative and sum to 1, found sum {w.sum():.6g}")
    return x, P, w


def information_fusion(
    estimates: Sequence[ArrayLike],
    covariances: Sequence[ArrayLike],
    weights: ArrayLike | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Weighted fusion in information form (covariance intersection for given weights).

    ``Omega = sum_i w_i P_i^{-1}``, ``x = Omega^{-1} sum_i w_i P_i^{-1} x_i``,
    returned as ``(x, P = Omega^{-1})``. With weights summing to one this is
    covariance intersection: ``P`` bounds the true error covariance whatever the
    (unknown) cross-covariances of the inputs are.

    Parameters
    ----------
    estimates : sequence of (n,) arrays
        Estimates to fuse (at least one).
    covariances : sequence of (n, n) arrays
        Their covariance bounds, symmetric positive definite.
    weights : (N,) array, optional
        Non-negative, summing to one (relative tolerance); uniform if omitted.

    Returns
    -------
    x : (n,) ndarray
        Fused estimate.
    P : (n, n) ndarray
        Fused covariance bound (symmetrised).
    """
    x, P, w = _stack_estimates(estimates, covariances, weights)
    info = np.linalg.inv(P)  # (N, n, n), each numerically PD by check_psd(strict)
    omega = np.einsum("i,ijk->jk", w, info)
    xi = np.einsum("i,ijk,ik->j", w, info, x)
    P_fused = symmetrize(np.linalg.inv(omega))
    return np.linalg.solve(omega, xi), P_fused


def covariance_intersection(
    estimates: Sequence[ArrayLike], covariances: Sequence[ArrayLike]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Covariance intersection with trace-optimal weights.

    Chooses weights on the simplex minimising ``tr P`` of
    :func:`information_fusion` (scipy SLSQP from uniform weights).

    Parameters
    ----------
    estimates : sequence of (n,) arrays
        Estimates to fuse (at least one).
    covariances : sequence of (n, n) arrays
        Their covariance bounds, symmetric positive definite.

    Returns
    -------
    x : (n,) ndarray
        Fused estimate.
    P : (n, n) ndarray
        Fused covariance bound.
    weights : (N,) ndarray
        The trace-optimal weights.
    """
    from scipy.optimize import minimize

    x, P, _ = _stack_estimates(estimates, covariances, None)
    m = len(x)
    if m == 1:
        return x[0], P[0], np.ones(1)
    info = np.linalg.inv(P)

    def trace_of_fused(w: NDArray[np.float64]) -> float:
        return float(np.trace(np.linalg.inv(np.einsum("i,ijk->jk", w, info))))

    res = minimize(
        trace_of_fused,
        np.full(m, 1.0 / m),
        method="SLSQP",
        bounds=[(0.0, 1.0)] * m,
        constraints=[{"type": "eq", "fun": lambda w: np.sum(w) - 1.0}],
    )
    w = np.clip(res.x, 0.0, None)
    w = w / w.sum()
    xf, Pf = information_fusion(x, P, w)
    return xf, Pf, w
