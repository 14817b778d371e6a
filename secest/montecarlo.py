"""Seeded random generators and Monte Carlo statistics."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from secest.validation import ValidationError, check_positive_int, check_probability

__all__ = ["anees_bounds", "nees", "spawn_rngs"]


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
