"""Chi-square attack / fault detectors on innovations.

For a Gaussian innovation ``r`` of covariance ``S`` in ``R^m``, the normalised
innovation squared ``g = r^T S^{-1} r`` is chi-square with ``m`` degrees of
freedom. A test with false-alarm probability ``alpha`` rejects when
``g > chi2.ppf(1 - alpha, m)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from secest.validation import ValidationError, check_positive_int, check_probability

__all__ = ["chi2_false_alarm", "chi2_test", "chi2_threshold", "nis"]


def chi2_threshold(dof: int, alpha: float) -> float:
    """Threshold ``tau`` with ``P{chi2_dof > tau} = alpha``."""
    dof = check_positive_int("dof", dof)
    alpha = check_probability("alpha", alpha, open_interval=True)
    return float(stats.chi2.isf(alpha, dof))


def chi2_false_alarm(dof: int, threshold: float) -> float:
    """False-alarm probability ``P{chi2_dof > threshold}`` of a given threshold."""
    dof = check_positive_int("dof", dof)
    if not threshold >= 0:
        raise ValidationError(f"threshold must be non-negative, found {threshold!r}")
    return float(stats.chi2.sf(threshold, dof))


def nis(innovation: ArrayLike, S: ArrayLike) -> float | NDArray[np.float64]:
    """Normalised innovation squared ``r^T S^{-1} r``.

    Parameters
    ----------
    innovation : (..., m) array
        One innovation or a stack of them (leading axes broadcast with ``S``).
    S : (..., m, m) array
        Innovation covariance(s), positive definite.

    Raises
    ------
    ValidationError
        If the shapes disagree or ``S`` is singular.
    """
    r = np.asarray(innovation, dtype=float)
    s = np.asarray(S, dtype=float)
    if r.ndim == 0 or s.ndim < 2 or s.shape[-1] != s.shape[-2] or s.shape[-1] != r.shape[-1]:
        raise ValidationError(
            f"Incompatible dimensions of S: expected (..., {r.shape[-1] if r.ndim else '?'}, "
            f"{r.shape[-1] if r.ndim else '?'}), found {s.shape}"
        )
    try:
        sol = np.linalg.solve(s, r[..., None])[..., 0]
    except np.linalg.LinAlgError as exc:
        raise ValidationError("S must be nonsingular (positive definite)") from exc
    g = np.einsum("...i,...i->...", r, sol)
    return float(g) if np.ndim(g) == 0 else g


def chi2_test(innovation: ArrayLike, S: ArrayLike, threshold: float) -> bool | NDArray[np.bool_]:
    """``True`` where the innovation passes (``nis <= threshold``), ``False`` where it is rejected."""
    if not threshold > 0:
        raise ValidationError(f"threshold must be positive, found {threshold!r}")
    g = nis(innovation, S)
    return bool(g <= threshold) if np.ndim(g) == 0 else g <= threshold
