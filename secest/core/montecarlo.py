"""Seeded random generators and Monte Carlo statistics."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from secest.core import validation as V
from secest.core.validation import ValidationError, check_probability

__all__ = [
    "anees_bounds",
    "bootstrap_interval",
    "mean_interval",
    "nees",
    "spawn_rngs",
    "wilson_interval",
]


def _seed(name: str, seed: object) -> int:
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValidationError(f"{name} must be a non-negative integer, found {seed!r}")
    return int(seed)


def spawn_rngs(seed: int, n: int) -> list[np.random.Generator]:
    """``n`` independent generators from ``np.random.SeedSequence(seed).spawn(n)``.

    Parameters
    ----------
    seed : int
        Non-negative root seed.
    n : int
        Number of generators, ``1 <= n <= MAX_GENERATORS``.

    Returns
    -------
    list of numpy.random.Generator
    """
    n = V.check_int("n", n, minimum=1, maximum=V.MAX_GENERATORS)
    seed = _seed("seed", seed)
    return [np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(n)]


def nees(errors: ArrayLike, P: ArrayLike) -> NDArray[np.float64]:
    """Normalised estimation error squared ``e^T P^{-1} e`` over the last axis.

    Parameters
    ----------
    errors : (..., n) array_like
        Estimation errors; leading axes (runs, steps, nodes) broadcast with those of ``P``.
    P : (..., n, n) array_like
        Covariances, symmetric positive definite.

    Returns
    -------
    ndarray
        NEES of shape ``broadcast(errors.shape[:-1], P.shape[:-2])``.
    """
    e = V.as_matrix("errors", errors)
    p = V.as_matrix("P", P)
    if e.ndim == 0 or p.ndim < 2 or p.shape[-2:] != (e.shape[-1], e.shape[-1]):
        n = e.shape[-1] if e.ndim else "?"
        raise ValidationError(
            f"Incompatible dimensions of P: expected (..., {n}, {n}) to match errors of length {n}, "
            f"found {p.shape}"
        )
    try:
        batch = np.broadcast_shapes(e.shape[:-1], p.shape[:-2])
    except ValueError as exc:
        raise ValidationError(
            f"Incompatible dimensions of P: leading axes {p.shape[:-2]} do not broadcast with "
            f"those of errors {e.shape[:-1]}"
        ) from exc
    V.check_size("errors, P", int(np.prod(batch, dtype=object)) * e.shape[-1], V.MAX_ELEMENTS,
                 "array entries")
    V.check_psd("P", p, strict=True)
    sol = np.linalg.solve(p, np.broadcast_to(e, (*batch, e.shape[-1]))[..., None])[..., 0]
    return np.einsum("...i,...i->...", e, sol)


def anees_bounds(dim: int, runs: int, confidence: float = 0.95) -> tuple[float, float]:
    """Two-sided chi-square acceptance interval of the average NEES over ``runs`` runs.

    Under consistency, ``runs * ANEES`` is chi-square with ``runs * dim`` degrees of freedom.

    Parameters
    ----------
    dim : int
        State dimension, ``>= 1``.
    runs : int
        Number of Monte Carlo runs, ``>= 1``.
    confidence : float, default 0.95
        Coverage of the interval, in (0, 1).

    Returns
    -------
    (float, float)
        Lower and upper bounds of the ANEES.
    """
    dim = V.check_int("dim", dim, minimum=1)
    runs = V.check_int("runs", runs, minimum=1)
    confidence = check_probability("confidence", confidence, open_interval=True)
    a = (1.0 - confidence) / 2
    dof = dim * runs
    return float(stats.chi2.ppf(a, dof) / runs), float(stats.chi2.ppf(1 - a, dof) / runs)


def wilson_interval(successes: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a binomial fraction ``successes / n``.

    Unlike the normal (Wald) interval it stays inside [0, 1] and is not
    degenerate at 0 or n successes, so "0 of 300 runs locked out" still gets
    an upper bound (about 0.0126 at 95 %). Computed by ``scipy.stats.binomtest``.

    Parameters
    ----------
    successes, n : int
        Count of successes and trials, ``0 <= successes <= n``, ``n >= 1``.
    level : float, default 0.95
        Confidence level in (0, 1).

    Returns
    -------
    (float, float)
        Lower and upper bounds.
    """
    n = V.check_int("n", n, minimum=1)
    successes = V.check_int("successes", successes)
    if not 0 <= successes <= n:
        raise ValidationError(f"successes must lie in [0, n] = [0, {n}], found {successes}")
    level = check_probability("level", level, open_interval=True)
    ci = stats.binomtest(successes, n).proportion_ci(confidence_level=level, method="wilson")
    return float(ci.low), float(ci.high)


def mean_interval(samples: ArrayLike, level: float = 0.95) -> tuple[float, float]:
    """Student-t interval of the mean of independent ``samples``.

    Parameters
    ----------
    samples : array_like
        At least 2 finite values (flattened).
    level : float, default 0.95
        Confidence level in (0, 1).

    Returns
    -------
    (float, float)
        Lower and upper bounds.
    """
    x = V.as_matrix("samples", samples).ravel()
    if x.size < 2:
        raise ValidationError(f"samples must hold at least 2 finite values, found {x.size}")
    level = check_probability("level", level, open_interval=True)
    half = float(stats.t.ppf(0.5 + level / 2, x.size - 1) * x.std(ddof=1) / np.sqrt(x.size))
    return float(x.mean() - half), float(x.mean() + half)


def bootstrap_interval(
    samples: ArrayLike,
    statistic: str = "mean",
    *,
    level: float = 0.95,
    n_boot: int = 2000,
    seed: int = 0,
) -> tuple[float, float]:
    """Percentile bootstrap interval of ``statistic`` (``"mean"`` or ``"median"``) over axis 0.

    With two columns the statistic is the ratio ``stat(col 0) / stat(col 1)`` of paired
    samples, resampled by run (e.g. an RMSE ratio of two estimators fed the same runs).

    Parameters
    ----------
    samples : (runs,) or (runs, 2) array_like
        Finite values, ``runs >= 2``.
    statistic : {"mean", "median"}, default "mean"
        Statistic to resample.
    level : float, default 0.95
        Confidence level in (0, 1).
    n_boot : int, default 2000
        Bootstrap resamples, ``>= 100`` and ``n_boot * runs <= MAX_ELEMENTS``.
    seed : int, default 0
        Non-negative seed of the resampling.

    Returns
    -------
    (float, float)
        Lower and upper bounds.
    """
    x = V.as_matrix("samples", samples)
    if x.ndim not in (1, 2) or x.shape[0] < 2 or (x.ndim == 2 and x.shape[1] != 2):
        raise ValidationError(f"samples must have shape (runs,) or (runs, 2), found {x.shape}")
    statistic = V.check_choice("statistic", statistic, ("mean", "median"))
    level = check_probability("level", level, open_interval=True)
    n_boot = V.check_int("n_boot", n_boot, minimum=100)
    V.check_size("n_boot * runs", n_boot * x.size, V.MAX_ELEMENTS, "array entries")
    rng = spawn_rngs(_seed("seed", seed), 1)[0]
    idx = rng.integers(0, x.shape[0], size=(n_boot, x.shape[0]))
    stat = np.mean if statistic == "mean" else np.median
    values = stat(x[idx], axis=1)
    if x.ndim == 2:
        if np.any(values[:, 1] == 0):
            raise ValidationError("samples: the denominator statistic is 0 in a bootstrap sample")
        values = values[:, 0] / values[:, 1]
    a = (1 - level) / 2
    return float(np.quantile(values, a)), float(np.quantile(values, 1 - a))
