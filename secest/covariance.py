"""Covariance helpers: symmetrisation, PSD checks, Joseph form and fusion.

Conventions follow the estimation literature: ``P`` is an error covariance,
``H`` a measurement matrix, ``R`` a measurement-noise covariance, ``K`` a gain.
Symmetrisation is explicit (keyword ``symmetrize``) so a reader sees where it
happens.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.validation import ValidationError, as_matrix

__all__ = [
    "check_psd",
    "covariance_intersection",
    "information_fusion",
    "is_psd",
    "joseph_update",
    "min_eig",
    "symmetrize",
]


def symmetrize(P: ArrayLike) -> NDArray[np.float64]:
    """Symmetric part ``(P + P^T) / 2`` (works on stacks of matrices, last two axes)."""
    arr = np.asarray(P, dtype=float)
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2]:
        raise ValidationError(f"P must be square in its last two axes, found shape {arr.shape}")
    return 0.5 * (arr + np.swapaxes(arr, -1, -2))


def min_eig(P: ArrayLike) -> float | NDArray[np.float64]:
    """Smallest eigenvalue of the symmetric part of ``P`` (per matrix for a stack)."""
    return np.linalg.eigvalsh(symmetrize(P))[..., 0]


def is_psd(P: ArrayLike, *, tol: float = 1e-10, strict: bool = False) -> bool:
    """Whether ``P`` is symmetric and PSD (PD if ``strict``) up to ``tol``.

    Symmetry is judged relative to ``max(1, ||P||_max)``; the eigenvalue test is
    ``lambda_min >= -tol`` (``> tol`` if ``strict``).
    """
    arr = np.asarray(P, dtype=float)
    if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or not np.all(np.isfinite(arr)):
        return False
    scale = max(1.0, float(np.max(np.abs(arr))))
    if np.max(np.abs(arr - arr.T)) > tol * scale:
        return False
    lam = float(min_eig(arr))
    return lam > tol if strict else lam >= -tol


def check_psd(
    name: str, P: ArrayLike, *, tol: float = 1e-10, strict: bool = False
) -> NDArray[np.float64]:
    """Validate that ``P`` is a symmetric PSD (or PD) matrix and return it as float.

    Raises
    ------
    ValidationError
        Naming ``name`` and the offending property (shape, symmetry, eigenvalue).
    """
    arr = as_matrix(name, P, square=True)
    scale = max(1.0, float(np.max(np.abs(arr)))) if arr.size else 1.0
    asym = float(np.max(np.abs(arr - arr.T))) if arr.size else 0.0
    if asym > tol * scale:
        raise ValidationError(f"{name} must be symmetric, found max |P - P^T| = {asym:.3g}")
    lam = float(min_eig(arr))
    if strict and lam <= tol:
        raise ValidationError(f"{name} must be positive definite, found lambda_min = {lam:.3g}")
    if lam < -tol:
        raise ValidationError(f"{name} must be positive semidefinite, found lambda_min = {lam:.3g}")
    return arr


def joseph_update(
    P: ArrayLike, K: ArrayLike, H: ArrayLike, R: ArrayLike, *, symmetrize_result: bool = True
) -> NDArray[np.float64]:
    """Joseph-form covariance update ``(I - K H) P (I - K H)^T + K R K^T``.

    Valid for any gain ``K`` (not only the optimal one) and PSD by construction.

    Parameters
    ----------
    P : (n, n) prior error covariance.
    K : (n, m) gain.
    H : (m, n) measurement matrix.
    R : (m, m) measurement-noise covariance.
    symmetrize_result : bool, default True
        Return the symmetric part, removing round-off asymmetry.
    """
    P = as_matrix("P", P, square=True)
    n = P.shape[0]
    H = as_matrix("H", H, (None, n))
    m = H.shape[0]
    K = as_matrix("K", K, (n, m))
    R = as_matrix("R", R, (m, m))
    ikh = np.eye(n) - K @ H
    out = ikh @ P @ ikh.T + K @ R @ K.T
    return symmetrize(out) if symmetrize_result else out


def _stack_estimates(
    estimates: Sequence[ArrayLike], covariances: Sequence[ArrayLike], weights: ArrayLike | None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    xs = [np.atleast_1d(as_matrix(f"estimates[{i}]", x)) for i, x in enumerate(estimates)]
    if not xs:
        raise ValidationError("estimates must contain at least one estimate")
    n = xs[0].shape[0]
    x = np.stack([as_matrix(f"estimates[{i}]", v, (n,)) for i, v in enumerate(xs)])
    if len(covariances) != len(xs):
        raise ValidationError(
            f"covariances must have one matrix per estimate: expected {len(xs)}, "
            f"found {len(covariances)}"
        )
    P = np.stack([check_psd(f"covariances[{i}]", c, strict=True) for i, c in enumerate(covariances)])
    if P.shape[1:] != (n, n):
        raise ValidationError(
            f"Incompatible dimensions of covariances: expected ({n}, {n}), found {P.shape[1:]}"
        )
    if weights is None:
        w = np.full(len(xs), 1.0 / len(xs))
    else:
        w = as_matrix("weights", weights, (len(xs),))
        if np.any(w < 0) or abs(w.sum() - 1.0) > 1e-12:
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
    covariances : sequence of (n, n) positive definite arrays
    weights : (N,) array, optional
        Non-negative, summing to one; uniform if omitted.
    """
    x, P, w = _stack_estimates(estimates, covariances, weights)
    info = np.linalg.inv(P)  # (N, n, n): small, well-conditioned by check_psd(strict)
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

    Returns
    -------
    x, P, weights
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
