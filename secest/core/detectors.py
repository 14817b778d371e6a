"""Chi-square attack / fault detectors on innovations.

For a Gaussian innovation ``r`` of covariance ``S`` in ``R^m``, the normalised
innovation squared ``g = r^T S^{-1} r`` is chi-square with ``m`` degrees of
freedom. A test with false-alarm probability ``alpha`` raises an alarm (rejects the
innovation) when ``g > chi2.ppf(1 - alpha, m)``.

The outcome of a test has two opposite readings; the names say which one you get:
:func:`chi2_alarm` is ``True`` where the detector *fires* (innovation rejected),
:func:`chi2_passes` is ``True`` where the innovation is *accepted*.
"""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from secest.core import validation as V
from secest.core.validation import ValidationError, check_probability

__all__ = ["chi2_alarm", "chi2_false_alarm", "chi2_passes", "chi2_test", "chi2_threshold", "nis"]


def chi2_threshold(dof: int, alpha: float) -> float:
    """Threshold ``tau`` with ``P{chi2_dof > tau} = alpha``.

    Parameters
    ----------
    dof : int
        Degrees of freedom, ``>= 1``.
    alpha : float
        False-alarm probability in (0, 1).

    Returns
    -------
    float
    """
    dof = V.check_int("dof", dof, minimum=1)
    alpha = check_probability("alpha", alpha, open_interval=True)
    return float(stats.chi2.isf(alpha, dof))


def chi2_false_alarm(dof: int, threshold: float) -> float:
    """False-alarm probability ``P{chi2_dof > threshold}`` of a given threshold.

    Parameters
    ----------
    dof : int
        Degrees of freedom, ``>= 1``.
    threshold : float
        Test threshold, non-negative (may be infinite).

    Returns
    -------
    float
    """
    dof = V.check_int("dof", dof, minimum=1)
    threshold = V.check_real("threshold", threshold, lower=0.0, finite=False)
    return float(stats.chi2.sf(threshold, dof))


def nis(innovation: ArrayLike, S: ArrayLike) -> float | NDArray[np.float64]:
    """Normalised innovation squared ``r^T S^{-1} r``.

    Parameters
    ----------
    innovation : scalar or (..., m) array
        One innovation or a stack of them (leading axes broadcast with ``S``); a scalar
        is a 1-D innovation.
    S : scalar or (..., m, m) array
        Innovation covariance(s), symmetric positive definite; a scalar is a 1 x 1 matrix.

    Returns
    -------
    float or ndarray of shape (...)

    Raises
    ------
    ValidationError
        If the shapes disagree or ``S`` is not symmetric positive definite.
    """
    r = V.as_matrix("innovation", innovation)
    s = V.as_matrix("S", S)
    if r.ndim == 0:
        r = r[None]
    if s.ndim == 0:
        s = s[None, None]
    m = r.shape[-1]
    if s.ndim < 2 or s.shape[-2:] != (m, m):
        raise ValidationError(
            f"Incompatible dimensions of S: expected (..., {m}, {m}) to match innovation of length {m}, "
            f"found {s.shape}"
        )
    try:
        batch = np.broadcast_shapes(r.shape[:-1], s.shape[:-2])
    except ValueError as exc:
        raise ValidationError(
            f"Incompatible dimensions of S: leading axes {s.shape[:-2]} do not broadcast with "
            f"those of innovation {r.shape[:-1]}"
        ) from exc
    V.check_size("innovation, S", int(np.prod(batch, dtype=object)) * m, V.MAX_ELEMENTS, "array entries")
    V.check_psd("S", s, strict=True)
    sol = np.linalg.solve(s, np.broadcast_to(r, (*batch, m))[..., None])[..., 0]
    g = np.einsum("...i,...i->...", r, sol)
    return float(g) if np.ndim(g) == 0 else g


def _outcome(innovation: ArrayLike, S: ArrayLike, threshold: float) -> NDArray[np.bool_] | bool:
    threshold = V.check_real("threshold", threshold, lower=0.0, lower_open=True)
    alarm = np.asarray(nis(innovation, S)) > threshold
    return bool(alarm) if alarm.ndim == 0 else alarm


def chi2_alarm(innovation: ArrayLike, S: ArrayLike, threshold: float) -> bool | NDArray[np.bool_]:
    """``True`` where the detector fires: ``nis > threshold`` (the innovation is rejected).

    Parameters
    ----------
    innovation : scalar or (..., m) array
        Innovation(s), as in :func:`nis`.
    S : scalar or (..., m, m) array
        Innovation covariance(s), symmetric positive definite.
    threshold : float
        Positive threshold, e.g. from :func:`chi2_threshold`.

    Returns
    -------
    bool or ndarray of bool
        ``True`` = alarm.
    """
    return _outcome(innovation, S, threshold)


def chi2_passes(innovation: ArrayLike, S: ArrayLike, threshold: float) -> bool | NDArray[np.bool_]:
    """``True`` where the innovation passes the test: ``nis <= threshold`` (no alarm).

    The negation of :func:`chi2_alarm`.

    Parameters
    ----------
    innovation : scalar or (..., m) array
        Innovation(s), as in :func:`nis`.
    S : scalar or (..., m, m) array
        Innovation covariance(s), symmetric positive definite.
    threshold : float
        Positive threshold.

    Returns
    -------
    bool or ndarray of bool
        ``True`` = accepted.
    """
    alarm = _outcome(innovation, S, threshold)
    return not alarm if isinstance(alarm, bool) else ~alarm


def chi2_test(innovation: ArrayLike, S: ArrayLike, threshold: float) -> bool | NDArray[np.bool_]:
    """Deprecated alias of :func:`chi2_passes` (``True`` = accepted, *not* an alarm).

    The name does not say which outcome ``True`` stands for; it warns
    (``FutureWarning``) and returns exactly what it always returned.

    Parameters
    ----------
    innovation : scalar or (..., m) array
        Innovation(s), as in :func:`nis`.
    S : scalar or (..., m, m) array
        Innovation covariance(s), symmetric positive definite.
    threshold : float
        Positive threshold.

    Returns
    -------
    bool or ndarray of bool
        ``True`` where ``nis <= threshold`` (the innovation passes).
    """
    warnings.warn(
        "chi2_test is ambiguous and will be removed: use chi2_passes (True = accepted) or "
        "chi2_alarm (True = alarm)",
        FutureWarning,
        stacklevel=2,
    )
    return chi2_passes(innovation, S, threshold)
