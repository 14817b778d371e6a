"""Round-robin-like multichannel access policy (RRL-MAP) of li2025, eqs. (2)-(5).

A subsystem has ``n_y`` scalar sensors and ``m <= n_y`` non-overlapping
channels. At time ``k = 1, 2, ...`` the sensors allowed to transmit are

.. math::

    \\varepsilon(k) = \\{\\operatorname{mod}(m(k-1) + s, n_y) + 1 \\mid s = 0, \\dots, m-1\\}
    \\qquad (2)

(1-based labels in the paper; the functions below return **0-based** sensor
indices, i.e. label - 1). The schedule is periodic with period
``U = lcm(m, n_y) / m`` and phase ``o(k) = mod(k - 1, U) + 1``; the selector
:math:`\\Phi_{o(k)} = \\sum_{r \\in \\varepsilon(k)} \\phi_r` (4) is the diagonal
0/1 matrix with ones on the scheduled sensors, so the zero-input update (3) is
:math:`\\bar y(k) = \\Phi_{o(k)} \\tilde y(k)` (5).

Fairness (Remark 1): in every window of ``U`` consecutive steps each sensor is
scheduled exactly ``lcm(m, n_y) / n_y`` times, ``|eps(k)| = m`` and no sensor
occupies two channels at the same step. :func:`rrl_map_window_counts` measures
this property on any schedule.
"""

from __future__ import annotations

from math import lcm

import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.core import validation as V
from secest.core.validation import ValidationError

__all__ = [
    "rrl_map_period",
    "rrl_map_phase",
    "rrl_map_selector",
    "rrl_map_sets",
    "rrl_map_window_counts",
    "zero_input_update",
]


def _check_channels(m: int, n_y: int) -> tuple[int, int]:
    """Validate the number of channels ``m`` and of sensors ``n_y`` (1 <= m <= n_y)."""
    n_y = V.check_int("n_y", n_y, minimum=1, maximum=V.MAX_ELEMENTS)
    m = V.check_int("m", m, minimum=1)
    if m > n_y:
        raise ValidationError(
            f"m must not exceed n_y (a sensor cannot use two channels at once): found m={m}, n_y={n_y}"
        )
    return m, n_y


def _check_steps(k: ArrayLike, m: int) -> NDArray[np.int64]:
    """Validate time instants ``k`` (integers >= 1, as in eq. (2), small enough for ``m (k - 1)``)."""
    try:
        arr = np.asarray(k)
    except (TypeError, ValueError) as exc:
        raise ValidationError(
            "k must be an integer or an array of integers, found an irregular sequence"
        ) from exc
    if arr.dtype == bool or not np.issubdtype(arr.dtype, np.integer):
        raise ValidationError(f"k must be an integer or an array of integers, found dtype {arr.dtype}")
    if arr.size and arr.min() < 1:
        raise ValidationError(f"k must be >= 1 (the schedule starts at k = 1), found {arr.min()}")
    if arr.size and int(arr.max()) > 2**62 // m:
        raise ValidationError(
            f"k must be <= 2**62 / m = {2**62 // m} (int64 arithmetic), found {arr.max()}"
        )
    return arr.astype(np.int64)


def rrl_map_period(m: int, n_y: int) -> int:
    """Period ``U = lcm(m, n_y) / m`` of the RRL-MAP schedule (text after eq. (2)).

    Parameters
    ----------
    m : int
        Number of non-overlapping channels, ``1 <= m <= n_y``.
    n_y : int
        Number of scalar sensors.

    Returns
    -------
    int
        The period ``U``.

    Raises
    ------
    ValidationError
        If ``m`` or ``n_y`` is not a positive integer or ``m > n_y``.
    """
    m, n_y = _check_channels(m, n_y)
    return lcm(m, n_y) // m


def rrl_map_phase(k: ArrayLike, m: int, n_y: int) -> NDArray[np.int64]:
    """Phase ``o(k) = mod(k - 1, U) + 1`` selecting :math:`\\Phi_{o(k)}` (eq. (4)).

    Parameters
    ----------
    k : int or array_like of int
        Time instants, ``k >= 1``.
    m, n_y : int
        Channels and sensors, ``1 <= m <= n_y``.

    Returns
    -------
    ndarray of int
        ``o(k)`` in ``1..U``, same shape as ``k``.
    """
    m, n_y = _check_channels(m, n_y)
    kk = _check_steps(k, m)
    return np.mod(kk - 1, rrl_map_period(m, n_y)) + 1


def rrl_map_sets(k: ArrayLike, m: int, n_y: int) -> NDArray[np.int64]:
    """Sensors scheduled at time ``k`` by the RRL-MAP, eq. (2), as 0-based indices.

    Parameters
    ----------
    k : int or array_like of int
        Time instants, ``k >= 1``.
    m : int
        Number of channels (sensors served per step), ``1 <= m <= n_y``.
    n_y : int
        Number of sensors.

    Returns
    -------
    ndarray of int
        Shape ``(m,)`` for scalar ``k`` or ``k.shape + (m,)``: entry ``s`` is
        ``mod(m(k-1) + s, n_y)``, the paper's label minus one. Channel ``s``
        carries that sensor.

    Raises
    ------
    ValidationError
        For bad ``m``, ``n_y`` or ``k``.

    Examples
    --------
    >>> rrl_map_sets([1, 2, 3], m=2, n_y=4).tolist()
    [[0, 1], [2, 3], [0, 1]]
    """
    m, n_y = _check_channels(m, n_y)
    kk = _check_steps(k, m)
    V.check_size("k, m", kk.size * m, V.MAX_ELEMENTS, "array entries")
    return np.mod(m * (kk[..., None] - 1) + np.arange(m), n_y)


def rrl_map_selector(k: ArrayLike, m: int, n_y: int) -> NDArray[np.float64]:
    """Selector matrix :math:`\\Phi_{o(k)} = \\sum_{r\\in\\varepsilon(k)} \\phi_r`, eq. (4).

    Parameters
    ----------
    k : int or array_like of int
        Time instants, ``k >= 1``.
    m, n_y : int
        Channels and sensors, ``1 <= m <= n_y``.

    Returns
    -------
    ndarray
        Diagonal 0/1 matrix of shape ``(n_y, n_y)`` (or ``k.shape + (n_y, n_y)``)
        with rank ``m``.
    """
    m, n_y = _check_channels(m, n_y)
    V.check_size("k, n_y", np.size(_check_steps(k, m)) * n_y * n_y, V.MAX_ELEMENTS, "array entries")
    sets = rrl_map_sets(k, m, n_y)
    diag = np.zeros(sets.shape[:-1] + (n_y,))
    np.put_along_axis(diag, sets, 1.0, axis=-1)
    return diag[..., None] * np.eye(n_y)


def zero_input_update(y: ArrayLike, k: int, m: int, n_y: int) -> NDArray[np.float64]:
    """Zero-input measurement update (3)/(5): keep scheduled entries, zero the rest.

    Parameters
    ----------
    y : array_like, shape (..., n_y)
        Raw measurements :math:`\\tilde y(k)` (leading axes, e.g. Monte Carlo runs,
        broadcast).
    k : int
        Time instant, ``k >= 1``.
    m, n_y : int
        Channels and sensors.

    Returns
    -------
    ndarray, shape (..., n_y)
        :math:`\\bar y(k) = \\Phi_{o(k)} \\tilde y(k)`.
    """
    m, n_y = _check_channels(m, n_y)
    arr = V.as_matrix("y", y)
    if arr.ndim == 0 or arr.shape[-1] != n_y:
        raise ValidationError(f"Incompatible dimensions of y: expected (..., {n_y}), found {arr.shape}")
    if np.ndim(k) != 0:
        raise ValidationError(f"k must be a single time instant, found shape {np.shape(k)}")
    mask = np.zeros(n_y)
    mask[rrl_map_sets(k, m, n_y)] = 1.0
    return arr * mask


def rrl_map_window_counts(
    sets: ArrayLike, n_y: int, window: int | None = None, m: int | None = None
) -> NDArray[np.int64]:
    """How often each sensor is served in every window of consecutive steps.

    Measures the fairness property of Remark 1 on an arbitrary schedule.

    Parameters
    ----------
    sets : array_like of int, shape (T, m)
        0-based scheduled sensor indices per step (e.g. from :func:`rrl_map_sets`).
    n_y : int
        Number of sensors.
    window : int, optional
        Window length; default the RRL-MAP period ``U`` (needs ``m``, taken
        from ``sets.shape[1]`` if not given).
    m : int, optional
        Number of channels; default ``sets.shape[1]``.

    Returns
    -------
    ndarray of int, shape (T - window + 1, n_y)
        Row ``t`` counts how many times each sensor is scheduled in steps
        ``t .. t + window - 1`` (sliding windows). For the RRL-MAP every entry
        equals ``lcm(m, n_y) / n_y``.

    Raises
    ------
    ValidationError
        If ``sets`` is not a 2-D integer array with indices in ``0..n_y-1``, a
        sensor appears twice in one step, or the window is longer than ``T``.
    """
    n_y = V.check_int("n_y", n_y, minimum=1, maximum=V.MAX_ELEMENTS)
    try:
        arr = np.asarray(sets)
    except (TypeError, ValueError) as exc:
        raise ValidationError("sets must be a 2-D integer array of shape (T, m)") from exc
    if arr.ndim != 2 or arr.dtype == bool or not np.issubdtype(arr.dtype, np.integer):
        raise ValidationError(
            f"sets must be a 2-D integer array of shape (T, m), found shape {arr.shape} "
            f"and dtype {arr.dtype}"
        )
    if arr.size and (arr.min() < 0 or arr.max() >= n_y):
        raise ValidationError(f"sets must hold sensor indices in 0..{n_y - 1}")
    V.check_size("sets, n_y", arr.shape[0] * n_y, V.MAX_ELEMENTS, "array entries")
    if m is None:
        m = arr.shape[1]
    m, n_y = _check_channels(m, n_y)
    if arr.shape[1] != m:
        raise ValidationError(f"Incompatible dimensions of sets: expected (*, {m}), found {arr.shape}")
    sorted_sets = np.sort(arr, axis=1)
    if np.any(sorted_sets[:, 1:] == sorted_sets[:, :-1]):
        raise ValidationError("sets schedules the same sensor on two channels at one step")
    if window is None:
        window = rrl_map_period(m, n_y)
    window = V.check_int("window", window, minimum=1)
    if window > arr.shape[0]:
        raise ValidationError(
            f"window must not exceed the number of steps {arr.shape[0]}, found {window}"
        )
    served = np.zeros((arr.shape[0], n_y), dtype=np.int64)
    np.put_along_axis(served, arr, 1, axis=1)
    csum = np.concatenate([np.zeros((1, n_y), dtype=np.int64), np.cumsum(served, axis=0)])
    return csum[window:] - csum[:-window]
