"""Input validation shared by every secest function.

Every public function of secest checks its arguments with the helpers below before it
computes anything, and every refusal is a :class:`ValidationError` (a :class:`ValueError`)
whose one-line message names the argument and states what was expected, e.g.
``Incompatible dimensions of R: expected (2, 2), found (2, 3)`` or
``kappa must be a real number, found 'a'``.

Tolerance rule (one rule, used everywhere)
------------------------------------------
Matrix properties are judged *relative to the size of the matrix*, never with an absolute
threshold, so that a test does not depend on the units of the data. With ``rtol`` (default
:data:`RTOL` ``= 1e-10``), ``sym P = (P + P^T) / 2`` and ``rho(P)`` the largest eigenvalue
magnitude of ``sym P``:

* symmetric:          ``max |P - P^T| <= rtol * max |P|``
* positive semidefinite: ``lambda_min(sym P) >= -rtol * rho(P)``
* positive definite:  ``lambda_min(sym P) >  rtol * rho(P)`` (the zero matrix is not PD)
* Loewner order ``X <= Y``: ``lambda_min(sym(Y - X)) >= -rtol * max(rho(X), rho(Y))``
* stochastic rows:    ``|sum_j W_ij - 1| <= rtol * max(1, sum_j |W_ij|)``

So ``1e-12 I`` is positive definite and a PSD matrix of scale ``1e8`` with a zero
eigenvalue is PSD whatever its rotation: eigenvalues computed in floating point are exact
only to about ``1e-16 * rho(P)``.

Size limits
-----------
Arguments that set the size of an allocation, of an enumeration or of a Python-level loop
are bounded, so that a typo is refused at once instead of running for hours or exhausting
memory (:class:`SizeLimitError`, naming the argument and the limit). The limits are module
attributes read at call time; raise them deliberately if you need more:

* :data:`MAX_ELEMENTS` -- entries of an array built from size arguments (1e8, 800 MB),
* :data:`MAX_DENSE_NODES` -- nodes of a network held as a dense ``N x N`` matrix (5000),
* :data:`MAX_SUBSETS` -- subsets enumerated by a combinatorial check (1e6),
* :data:`MAX_STEPS` -- steps of a Python-level time loop (1e8),
* :data:`MAX_GENERATORS` -- random generators spawned at once (1e5; each holds a few kB).
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Sequence
from numbers import Integral, Real
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "MAX_DENSE_NODES",
    "MAX_ELEMENTS",
    "MAX_GENERATORS",
    "MAX_STEPS",
    "MAX_SUBSETS",
    "RTOL",
    "SizeLimitError",
    "ValidationError",
    "as_matrix",
    "as_rng",
    "check_bool",
    "check_callable",
    "check_instance",
    "check_choice",
    "check_int",
    "check_loewner_order",
    "check_positive_int",
    "check_probability",
    "check_psd",
    "check_real",
    "check_row_stochastic",
    "check_size",
    "check_symmetric",
]

RTOL = 1e-10
MAX_ELEMENTS = 10**8
MAX_DENSE_NODES = 5_000
MAX_SUBSETS = 10**6
MAX_STEPS = 10**8
MAX_GENERATORS = 10**5


class ValidationError(ValueError):
    """Bad input to a secest function; the message names the argument."""


class SizeLimitError(ValidationError):
    """An argument asks for more work or memory than the limits of :mod:`secest.core.validation`."""


def _show(value: object) -> str:
    """Short description of a value for an error message."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {_fmt(value.shape)} and dtype {value.dtype}"
    text = repr(value)
    return text if len(text) <= 60 else f"{type(value).__name__} {text[:50]}..."


def _fmt(shape: tuple) -> str:
    """Format a shape tuple as ``(2, 3)`` (``(2,)`` for 1-D)."""
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def _check_name(name: object, label: str = "name") -> str:
    if not isinstance(name, str) or not name:
        raise ValidationError(f"{label} must be a non-empty string, found {_show(name)}")
    return name


# ----------------------------------------------------------------------------- scalars
def check_real(
    name: str,
    value: object,
    *,
    lower: float | None = None,
    upper: float | None = None,
    lower_open: bool = False,
    upper_open: bool = False,
    finite: bool = True,
) -> float:
    """Check that ``value`` is a real number, optionally inside an interval.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check: a Python or numpy real number (not a bool, a string or None).
    lower, upper : float, optional
        Bounds of the admissible interval.
    lower_open, upper_open : bool, default False
        Exclude the bound itself (``value > lower`` instead of ``>=``).
    finite : bool, default True
        Reject NaN and infinities.

    Returns
    -------
    float

    Raises
    ------
    ValidationError
        If ``value`` is not a real number or lies outside the interval.
    """
    _check_name(name)
    for flag, val in (("lower_open", lower_open), ("upper_open", upper_open), ("finite", finite)):
        check_bool(flag, val)
    for bound, val in (("lower", lower), ("upper", upper)):
        if val is not None and (isinstance(val, bool) or not isinstance(val, Real) or np.isnan(val)):
            raise ValidationError(f"{bound} must be a real number or None, found {_show(val)}")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, bool | np.bool_) or not isinstance(value, Real):
        raise ValidationError(f"{name} must be a real number, found {_show(value)}")
    x = float(value)
    if np.isnan(x) or (finite and not np.isfinite(x)):
        raise ValidationError(f"{name} must be a finite real number, found {x!r}")
    low_bad = lower is not None and (x <= lower if lower_open else x < lower)
    high_bad = upper is not None and (x >= upper if upper_open else x > upper)
    if low_bad or high_bad:
        if lower is not None and upper is not None:
            lb, ub = "(" if lower_open else "[", ")" if upper_open else "]"
            raise ValidationError(f"{name} must lie in {lb}{lower:g}, {upper:g}{ub}, found {x!r}")
        op = (">" if lower_open else ">=") if low_bad else ("<" if upper_open else "<=")
        bound = lower if low_bad else upper
        raise ValidationError(f"{name} must be {op} {bound:g}, found {x!r}")
    return x


def check_int(
    name: str, value: object, *, minimum: int | None = None, maximum: int | None = None
) -> int:
    """Check that ``value`` is an integer (Python or numpy, not a bool) in ``[minimum, maximum]``.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.
    minimum, maximum : int, optional
        Admissible range (inclusive).

    Returns
    -------
    int

    Raises
    ------
    ValidationError
        If ``value`` is not an integer or lies outside the range; :class:`SizeLimitError`
        if it exceeds ``maximum``.
    """
    _check_name(name)
    for bound, val in (("minimum", minimum), ("maximum", maximum)):
        if val is not None and (isinstance(val, bool) or not isinstance(val, Integral)):
            raise ValidationError(f"{bound} must be an integer or None, found {_show(val)}")
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, bool | np.bool_) or not isinstance(value, Integral):
        raise ValidationError(f"{name} must be an integer, found {_show(value)}")
    v = int(value)
    if minimum is not None and v < minimum:
        raise ValidationError(f"{name} must be >= {minimum}, found {v}")
    if maximum is not None and v > maximum:
        raise SizeLimitError(f"{name} must be <= {maximum}, found {v}")
    return v


def check_positive_int(name: str, value: object, *, minimum: int = 1) -> int:
    """Check that ``value`` is an integer no smaller than ``minimum``.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.
    minimum : int, default 1
        Smallest admissible value.

    Returns
    -------
    int

    Raises
    ------
    ValidationError
        If ``value`` is not an integer or is below ``minimum``.
    """
    return check_int(name, value, minimum=check_int("minimum", minimum))


def check_probability(name: str, value: object, *, open_interval: bool = False) -> float:
    """Check that ``value`` is a probability in [0, 1] (or (0, 1) if ``open_interval``).

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.
    open_interval : bool, default False
        Exclude 0 and 1.

    Returns
    -------
    float

    Raises
    ------
    ValidationError
        If ``value`` is not a real number or lies outside the interval.
    """
    open_interval = check_bool("open_interval", open_interval)
    return check_real(
        name, value, lower=0.0, upper=1.0, lower_open=open_interval, upper_open=open_interval
    )


def check_bool(name: str, value: object) -> bool:
    """Check that ``value`` is a bool (Python or numpy), not a number or a string.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.

    Returns
    -------
    bool

    Raises
    ------
    ValidationError
        If ``value`` is not a bool.
    """
    _check_name(name)
    if not isinstance(value, bool | np.bool_):
        raise ValidationError(f"{name} must be True or False, found {_show(value)}")
    return bool(value)


def check_choice(name: str, value: object, choices: Collection[Any]) -> Any:
    """Check that ``value`` is one of ``choices``.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.
    choices : collection
        The admissible values (hashable).

    Returns
    -------
    object
        ``value``.

    Raises
    ------
    ValidationError
        If ``value`` is not one of ``choices``.
    """
    _check_name(name)
    if isinstance(choices, str | bytes) or not isinstance(choices, Collection) or not choices:
        raise ValidationError(f"choices must be a non-empty collection, found {_show(choices)}")
    try:
        ok = value in choices
    except (TypeError, ValueError):  # unhashable value or an array
        ok = False
    if not ok or isinstance(value, bool | np.bool_) != any(isinstance(c, bool) for c in choices):
        raise ValidationError(f"{name} must be one of {tuple(choices)}, found {_show(value)}")
    return value


def check_callable(name: str, value: object) -> Callable[..., Any]:
    """Check that ``value`` is callable.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.

    Returns
    -------
    callable

    Raises
    ------
    ValidationError
        If ``value`` is not callable.
    """
    _check_name(name)
    if not callable(value):
        raise ValidationError(f"{name} must be callable, found {_show(value)}")
    return value


def check_instance(name: str, value: object, cls: type, made_by: str) -> Any:
    """Check that ``value`` is an instance of ``cls``.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : object
        The value to check.
    cls : type
        The class it must be an instance of.
    made_by : str
        What makes such objects (e.g. ``"secest.arena.scenarios.simulate"``), named in the message.

    Returns
    -------
    object
        ``value``.

    Raises
    ------
    ValidationError
        If ``value`` is not an instance of ``cls``.
    """
    _check_name(name)
    if not isinstance(cls, type):
        raise ValidationError(f"cls must be a class, found {_show(cls)}")
    if not isinstance(made_by, str) or not made_by.strip():
        raise ValidationError(f"made_by must be a non-empty string, found {_show(made_by)}")
    if not isinstance(value, cls):
        raise ValidationError(f"{name} must be a {cls.__name__} ({made_by}), "
                              f"found {type(value).__name__}")
    return value


def as_rng(name: str, rng: object) -> np.random.Generator:
    """A numpy Generator from a Generator, a non-negative integer seed or a SeedSequence.

    ``None`` is refused: every random draw of secest is seeded, so that runs reproduce.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    rng : numpy.random.Generator, int or numpy.random.SeedSequence
        Source of randomness.

    Returns
    -------
    numpy.random.Generator
        ``rng`` itself if it is a Generator, else ``numpy.random.default_rng(rng)``.

    Raises
    ------
    ValidationError
        If ``rng`` is None, a negative integer or of another type.
    """
    _check_name(name)
    if isinstance(rng, np.random.Generator):
        return rng
    if isinstance(rng, np.random.SeedSequence):
        return np.random.default_rng(rng)
    if isinstance(rng, Integral) and not isinstance(rng, bool | np.bool_):
        return np.random.default_rng(check_int(name, rng, minimum=0))
    raise ValidationError(
        f"{name} must be a numpy Generator or a non-negative integer seed, found {_show(rng)}"
    )


def check_size(name: str, value: int, limit: int, what: str) -> int:
    """Refuse a size that exceeds ``limit`` (raise :class:`SizeLimitError`).

    Parameters
    ----------
    name : str
        Argument (or combination of arguments) responsible, used in the message.
    value : int
        The size it asks for.
    limit : int
        The largest size accepted (one of the ``MAX_*`` attributes of this module).
    what : str
        What is counted, e.g. ``"array entries"``.

    Returns
    -------
    int
        ``value``.

    Raises
    ------
    SizeLimitError
        If ``value > limit``.
    """
    _check_name(name)
    value = check_int(name, value)
    limit = check_int("limit", limit)
    if not isinstance(what, str):
        raise ValidationError(f"what must be a string, found {_show(what)}")
    if value > limit:
        raise SizeLimitError(
            f"{name} asks for {value:.3g} {what}, more than the limit {limit:.3g} "
            f"(secest.core.validation; raise it deliberately if you need more)"
        )
    return value


# ----------------------------------------------------------------------------- arrays
def as_matrix(
    name: str,
    value: ArrayLike,
    shape: Sequence[int | None] | None = None,
    *,
    square: bool = False,
    finite: bool = True,
    empty: bool = False,
    note: str = "",
) -> NDArray[np.float64]:
    """Return ``value`` as a float array after checking its type, shape and entries.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    value : array_like
        The value to check: numbers, nested sequences of numbers or an array (bool arrays
        are read as 0/1). Strings, None, complex numbers and ragged sequences are refused.
    shape : sequence of int or None, optional
        Expected shape; ``None`` entries match any length. The number of dimensions must
        match exactly.
    square : bool, default False
        Require a 2-D square matrix.
    finite : bool, default True
        Reject NaN and infinite entries.
    empty : bool, default False
        Accept an array with no entries (e.g. shape ``(3, 0)``).
    note : str, default ""
        Said after the expected shape, e.g. ``"to match x_post"``, when the expectation
        comes from another argument.

    Returns
    -------
    ndarray
        ``value`` converted to ``float64``.

    Raises
    ------
    ValidationError
        If the type, shape, squareness, size or finiteness does not hold.
    """
    _check_name(name)
    for flag, val in (("square", square), ("finite", finite), ("empty", empty)):
        check_bool(flag, val)
    if not isinstance(note, str):
        raise ValidationError(f"note must be a string, found {_show(note)}")
    _check_shape_spec(shape)
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested sequences
        raise ValidationError(
            f"{name} must be a numeric array, found an irregular nested sequence"
        ) from exc
    if raw.dtype.kind not in "biuf":
        what = "complex" if raw.dtype.kind == "c" else type(value).__name__
        raise ValidationError(f"{name} must be a real numeric array, found {what} {_show(value)}")
    arr = raw.astype(float, copy=False)
    if shape is not None:
        expected = tuple(shape)
        ok = arr.ndim == len(expected) and all(
            e is None or e == s for e, s in zip(expected, arr.shape, strict=False)
        )
        if not ok:
            shown = tuple("*" if e is None else e for e in expected)
            said = f"{_fmt(shown)} {note}" if note else _fmt(shown)
            raise ValidationError(
                f"Incompatible dimensions of {name}: expected {said}, found {_fmt(arr.shape)}"
            )
    if square and (arr.ndim != 2 or arr.shape[0] != arr.shape[1]):
        raise ValidationError(f"{name} must be a square matrix, found shape {_fmt(arr.shape)}")
    if not empty and arr.size == 0:
        raise ValidationError(f"{name} must not be empty, found shape {_fmt(arr.shape)}")
    if finite and not np.all(np.isfinite(arr)):
        raise ValidationError(f"{name} contains NaN or infinite entries")
    return arr


def _check_shape_spec(shape: object) -> None:
    if shape is None:
        return
    ok = not isinstance(shape, str | bytes) and isinstance(shape, Sequence)
    ok = ok and all(e is None or (isinstance(e, Integral) and not isinstance(e, bool) and e >= 0)
                    for e in shape)
    if not ok:
        raise ValidationError(f"shape must be a sequence of ints >= 0 or None, found {_show(shape)}")


def _as_stack(name: str, P: ArrayLike) -> NDArray[np.float64]:
    arr = as_matrix(name, P)
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2]:
        raise ValidationError(
            f"{name} must be square in its last two axes, found shape {_fmt(arr.shape)}"
        )
    return arr


def _where(name: str, arr: NDArray, bad: NDArray[np.bool_]) -> str:
    """``name`` or ``name[i, j]`` locating the first offending matrix of a stack."""
    if arr.ndim == 2:
        return name
    idx = np.unravel_index(int(np.flatnonzero(bad)[0]), bad.shape)
    return f"{name}[{', '.join(str(int(i)) for i in idx)}]"


def check_symmetric(name: str, P: ArrayLike, *, rtol: float = RTOL) -> NDArray[np.float64]:
    """Check that ``P`` (a matrix or a stack ``(..., n, n)``) is symmetric, relative to its size.

    The rule is ``max |P - P^T| <= rtol * max |P|`` per matrix (see the module docstring).

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    P : array_like, shape (..., n, n)
        Matrix or stack of matrices.
    rtol : float, default RTOL
        Relative tolerance.

    Returns
    -------
    ndarray
        ``P`` as a float array.

    Raises
    ------
    ValidationError
        If ``P`` is not a finite stack of square matrices or is not symmetric.
    """
    arr = _as_stack(name, P)
    rtol = check_real("rtol", rtol, lower=0.0)
    unit, scale = _normalised(arr)
    rel = np.abs(unit - np.swapaxes(unit, -1, -2)).max(axis=(-2, -1))
    bad = rel > rtol
    asym = rel * scale
    if np.any(bad):
        where = _where(name, arr, bad)
        worst = float(asym[bad].max())
        raise ValidationError(f"{where} must be symmetric, found max |{name} - {name}^T| = {worst:.3g}")
    return arr


def _normalised(arr: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Each matrix divided by its largest entry magnitude (1 for a zero matrix), and that scale.

    The rules are scale-invariant; working on the normalised matrices keeps sums, differences
    and eigenvalue iterations from overflowing for entries near the largest float.
    """
    scale = np.abs(arr).max(axis=(-2, -1))
    safe = np.where(scale > 0, scale, 1.0)
    return arr / safe[..., None, None], scale


def _extreme_eigs(arr: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Smallest eigenvalue and spectral radius of the symmetric part of each matrix."""
    unit, scale = _normalised(arr)
    ev = np.linalg.eigvalsh(0.5 * (unit + np.swapaxes(unit, -1, -2)))
    s = np.where(scale > 0, scale, 1.0)
    return ev[..., 0] * s, np.abs(ev).max(axis=-1) * s


def check_psd(
    name: str, P: ArrayLike, *, strict: bool = False, tol: float = RTOL
) -> NDArray[np.float64]:
    """Check that ``P`` is symmetric positive semidefinite (definite if ``strict``).

    Relative rule of the module docstring: ``lambda_min >= -tol * rho(P)`` (PSD) or
    ``lambda_min > tol * rho(P)`` (PD), after a relative symmetry test. Works on one
    matrix or a stack ``(..., n, n)``; the message locates the first failing matrix.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    P : array_like, shape (..., n, n)
        Matrix or stack of matrices.
    strict : bool, default False
        Require positive definiteness.
    tol : float, default RTOL
        Relative tolerance of the symmetry and eigenvalue tests.

    Returns
    -------
    ndarray
        ``P`` as a float array.

    Raises
    ------
    ValidationError
        Naming ``name`` and the offending property (shape, finiteness, symmetry, eigenvalue).
    """
    strict = check_bool("strict", strict)
    tol = check_real("tol", tol, lower=0.0)
    arr = check_symmetric(name, P, rtol=tol)
    lam, rho = _extreme_eigs(arr)
    bad = lam <= tol * rho if strict else lam < -tol * rho
    if np.any(bad):
        where = _where(name, arr, bad)
        worst = float(lam[bad].min())
        kind = "positive definite" if strict else "positive semidefinite"
        raise ValidationError(f"{where} must be {kind}, found lambda_min = {worst:.3g}")
    return arr


def check_loewner_order(
    name_low: str, low: ArrayLike, name_high: str, high: ArrayLike, *, tol: float = RTOL
) -> None:
    """Check ``low <= high`` in the Loewner order (``high - low`` PSD), matrix by matrix.

    Parameters
    ----------
    name_low, name_high : str
        Argument names used in the error message.
    low, high : array_like, shape (..., n, n)
        Symmetric matrices or stacks of the same shape.
    tol : float, default RTOL
        Relative tolerance: ``lambda_min(high - low) >= -tol * max(rho(low), rho(high))``.

    Raises
    ------
    ValidationError
        If the shapes differ or the order fails somewhere (the message names the first index).
    """
    _check_name(name_low, "name_low")
    _check_name(name_high, "name_high")
    lo = _as_stack(name_low, low)
    hi = _as_stack(name_high, high)
    if lo.shape != hi.shape:
        raise ValidationError(
            f"Incompatible dimensions of {name_high}: expected {_fmt(lo.shape)}, found {_fmt(hi.shape)}"
        )
    tol = check_real("tol", tol, lower=0.0)
    gap, _ = _extreme_eigs(hi - lo)
    scale = np.maximum(_extreme_eigs(lo)[1], _extreme_eigs(hi)[1])
    bad = gap < -tol * scale
    if np.any(bad):
        where = _where(name_low, lo, bad)
        raise ValidationError(
            f"{where} must lie below {name_high} in the Loewner order, found "
            f"lambda_min({name_high} - {name_low}) = {float(gap[bad].min()):.3g}"
        )


def check_row_stochastic(
    name: str, W: ArrayLike, *, tol: float = RTOL, diagonal: bool = True
) -> NDArray[np.float64]:
    """Check that ``W`` is a non-negative square matrix whose rows sum to one.

    Rule of the module docstring: ``|sum_j W_ij - 1| <= tol * max(1, sum_j |W_ij|)``.

    Parameters
    ----------
    name : str
        Argument name used in error messages.
    W : array_like, shape (N, N)
        Weights.
    tol : float, default RTOL
        Relative tolerance of the row sums (negative entries are refused exactly).
    diagonal : bool, default True
        Allow non-zero diagonal entries (self-weights); ``False`` requires a zero diagonal.

    Returns
    -------
    ndarray

    Raises
    ------
    ValidationError
        Naming the first offending entry or row.
    """
    w = as_matrix(name, W, square=True)
    tol = check_real("tol", tol, lower=0.0)
    diagonal = check_bool("diagonal", diagonal)
    if np.any(w < 0):
        i, j = np.argwhere(w < 0)[0]
        raise ValidationError(f"{name} must be non-negative, found {name}[{i}, {j}] = {w[i, j]:.6g}")
    if not diagonal and np.any(np.diag(w) != 0):
        i = int(np.flatnonzero(np.diag(w))[0])
        raise ValidationError(
            f"{name} must have a zero diagonal, found {name}[{i}, {i}] = {w[i, i]:.6g}"
        )
    sums = w.sum(axis=1)
    bad = np.flatnonzero(np.abs(sums - 1.0) > tol * np.maximum(1.0, np.abs(w).sum(axis=1)))
    if bad.size:
        raise ValidationError(f"{name} must be row-stochastic, row {bad[0]} sums to {sums[bad[0]]:.6g}")
    return w
