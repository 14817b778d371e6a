"""Seeded random generators and Monte Carlo statistics."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from secest.validation import ValidationError, check_positive_int, check_probability

__all__ = [
    "anees_bounds",
    "bootstrap_interval",
    "mean_interval",
    "nees",
    "spawn_rngs",
    "wilson_interval",
]


def spawn_rngs(seed: int, n: int) -> list[np.random.Generator]:
    """``n`` independent generators from ``np.random.SeedSequence(seed).spawn(n)``."""
    n = check_positive_int("n", n)
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValidationError(f"seed must be a non-negative integer, found {seed!r}")
    return [np.random.default_rng(s) for s in np.random.SeedSequence(int(seed)).spawn(n)]


def nees(errors: ArrayLike, P: ArrayLike) -> NDArray[np.float64]:
    """Normalised estimation error squared ``e^T P^{-1} e`` over the last axis.

    ``errors`` has shape (..., n) and ``P`` shape (..., n, n), broadcasting over
    the leading axes (runs, steps, nodes).
    """
    e = np.asarray(errors, dtype=float)
    p = np.asarray(P, dtype=float)
    if e.ndim == 0 or p.ndim < 2 or p.shape[-2:] != (e.shape[-1], e.shape[-1]):
        raise ValidationError(
            f"Incompatible dimensions of P: expected (..., {e.shape[-1] if e.ndim else '?'}, "
            f"{e.shape[-1] if e.ndim else '?'}), found {p.shape}"
        )
    sol = np.linalg.solve(p, e[..., None])[..., 0]
    return np.einsum("...i,...i->...", e, sol)


def anees_bounds(dim: int, runs: int, confidence: float = 0.95) -> tuple[float, float]:
    """Two-sided chi-square acceptance interval of the average NEES over ``runs`` runs.

    Under consistency, ``runs * ANEES`` is chi-square with ``runs * dim`` degrees of freedom.
    """
    dim = check_positive_int("dim", dim)
    runs = check_positive_int("runs", runs)
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
    """
    n = check_positive_int("n", n)
    if isinstance(successes, bool) or not isinstance(successes, int | np.integer):
        raise ValidationError(f"successes must be an integer, found {successes!r}")
    if not 0 <= successes <= n:
        raise ValidationError(f"successes must lie in [0, n] = [0, {n}], found {successes}")
    level = check_probability("level", level, open_interval=True)
    ci = stats.binomtest(int(successes), n).proportion_ci(confidence_level=level, method="wilson")
    return float(ci.low), float(ci.high)


def mean_interval(samples: ArrayLike, level: float = 0.95) -> tuple[float, float]:
    """Student-t interval of the mean of independent ``samples`` (at least 2, finite)."""
    x = np.asarray(samples, dtype=float).ravel()
    if x.size < 2 or not np.all(np.isfinite(x)):
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

    ``samples`` of shape (runs,) or (runs, 2): with two columns the statistic is
    the ratio ``stat(col 0) / stat(col 1)`` of paired samples, resampled by run
    (e.g. an RMSE ratio of two estimators fed the same runs).
    """
    x = np.asarray(samples, dtype=float)
    if x.ndim not in (1, 2) or x.shape[0] < 2 or (x.ndim == 2 and x.shape[1] != 2):
        raise ValidationError(f"samples must have shape (runs,) or (runs, 2), found {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValidationError("samples contains NaN or infinite entries")
    if statistic not in ("mean", "median"):
        raise ValidationError(f"statistic must be 'mean' or 'median', found {statistic!r}")
    level = check_probability("level", level, open_interval=True)
    n_boot = check_positive_int("n_boot", n_boot, minimum=100)
    rng = spawn_rngs(seed, 1)[0]
    idx = rng.integers(0, x.shape[0], size=(n_boot, x.shape[0]))
    stat = np.mean if statistic == "mean" else np.median
    resampled = x[idx]
    values = stat(resampled, axis=1)
    if x.ndim == 2:
        if np.any(values[:, 1] == 0):
            raise ValidationError("the denominator statistic is 0 in a bootstrap sample")
        values = values[:, 0] / values[:, 1]
    a = (1 - level) / 2
    return float(np.quantile(values, a)), float(np.quantile(values, 1 - a))
