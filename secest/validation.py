"""Input validation shared by every secest function.

All checks raise :class:`ValidationError`, a :class:`ValueError` subclass whose
message names the offending argument and states what was expected, e.g.
``Incompatible dimensions of R: expected (2, 2), found (2, 3)``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray


class ValidationError(ValueError):
    """Bad input to a secest function; the message names the argument."""


def as_matrix(
    name: str,
    value: ArrayLike,
    shape: Sequence[int | None] | None = None,
    *,
    square: bool = False,
    finite: bool = True,
) -> NDArray[np.float64]:
    """Return ``value`` as a float array after checking its shape.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : array_like
        The value to check.
    shape : sequence of int or None, optional
        Expected shape; ``None`` entries match any length. The number of
        dimensions must match exactly.
    square : bool, default False
        Require a 2-D square matrix.
    finite : bool, default True
        Reject NaN and infinite entries.

    Returns
    -------
    ndarray
        ``value`` converted to ``float64``.

    Raises
    ------
    ValidationError
        If the shape, squareness or finiteness does not hold.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValidationError(f"{name} must be numeric, found {type(value).__name__}") from exc
    if shape is not None:
        expected = tuple(shape)
        ok = arr.ndim == len(expected) and all(
            e is None or e == s for e, s in zip(expected, arr.shape, strict=False)
        )
        if not ok:
            shown = tuple("*" if e is None else e for e in expected)
            raise ValidationError(
                f"Incompatible dimensions of {name}: expected {_fmt(shown)}, found {_fmt(arr.shape)}"
            )
    if square and (arr.ndim != 2 or arr.shape[0] != arr.shape[1]):
        raise ValidationError(f"{name} must be a square matrix, found shape {_fmt(arr.shape)}")
    if finite and not np.all(np.isfinite(arr)):
        raise ValidationError(f"{name} contains NaN or infinite entries")
    return arr


def check_probability(name: str, value: float, *, open_interval: bool = False) -> float:
    """Check that ``value`` is a probability in [0, 1] (or (0, 1) if ``open_interval``).

    Raises
    ------
    ValidationError
        If ``value`` is outside the interval or not a real number.
    """
    try:
        p = float(value)
    except (TypeError, ValueError) as exc:
        raise ValidationError(f"{name} must be a real number, found {value!r}") from exc
    inside = 0.0 < p < 1.0 if open_interval else 0.0 <= p <= 1.0
    if not inside:
        interval = "(0, 1)" if open_interval else "[0, 1]"
        raise ValidationError(f"{name} must lie in {interval}, found {value!r}")
    return p


def check_positive_int(name: str, value: int, *, minimum: int = 1) -> int:
    """Check that ``value`` is an integer no smaller than ``minimum``.

    Raises
    ------
    ValidationError
        If ``value`` is not an integer or is below ``minimum``.
    """
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValidationError(f"{name} must be an integer, found {value!r}")
    if value < minimum:
        raise ValidationError(f"{name} must be >= {minimum}, found {value}")
    return int(value)


def _fmt(shape: tuple) -> str:
    """Format a shape tuple as ``(2, 3)`` (``(2,)`` for 1-D)."""
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
