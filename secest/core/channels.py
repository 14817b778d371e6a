"""Packet-loss channel models: the Gilbert-Elliott chain and Bernoulli sequences.

The Gilbert-Elliott channel is a two-state Markov chain ``delta_k`` in {0, 1}
(1 = good, packets arrive; 0 = bad, packets are lost) with

* failure rate  ``p = P{delta_{k+1} = 0 | delta_k = 1}``,
* recovery rate ``q = P{delta_{k+1} = 1 | delta_k = 0}``,

transition matrix ``[[1 - q, q], [p, 1 - p]]`` over the states (0, 1) and
stationary probability ``P{delta = 1} = q / (p + q)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from secest.core import validation as V
from secest.core.validation import ValidationError, check_probability

__all__ = [
    "bernoulli",
    "gilbert_elliott",
    "gilbert_elliott_stationary",
    "gilbert_elliott_transition",
]


def gilbert_elliott_transition(p: float, q: float) -> NDArray[np.float64]:
    """Transition matrix over states (0 = bad, 1 = good): ``[[1-q, q], [p, 1-p]]``.

    Parameters
    ----------
    p, q : float
        Failure and recovery rates in [0, 1].

    Returns
    -------
    (2, 2) ndarray
        Row-stochastic transition matrix.
    """
    p = check_probability("p", p)
    q = check_probability("q", q)
    return np.array([[1.0 - q, q], [p, 1.0 - p]])


def gilbert_elliott_stationary(p: float, q: float) -> float:
    """Stationary probability of the good state, ``q / (p + q)``.

    Parameters
    ----------
    p, q : float
        Failure and recovery rates in [0, 1], not both zero.

    Returns
    -------
    float

    Raises
    ------
    ValidationError
        If ``p + q = 0`` (the chain never moves and has no unique stationary law).
    """
    p = check_probability("p", p)
    q = check_probability("q", q)
    if p + q == 0:
        raise ValidationError("p + q must be positive for a unique stationary distribution")
    return q / (p + q)


def gilbert_elliott(
    p: float,
    q: float,
    steps: int,
    rng: np.random.Generator | int,
    *,
    initial: int = 1,
    size: int | None = None,
) -> NDArray[np.int8]:
    """Sample a Gilbert-Elliott chain ``delta_0, ..., delta_{steps-1}``.

    Parameters
    ----------
    p, q : float
        Failure and recovery rates in [0, 1].
    steps : int
        Number of samples, including ``delta_0 = initial``, at most ``MAX_STEPS``.
    rng : numpy.random.Generator or int
        Source of randomness, or a non-negative integer seed (``None`` is refused).
    initial : {0, 1}, default 1
        State at ``k = 0``.
    size : int, optional
        Number of independent chains; the result then has shape ``(size, steps)``
        (``size * steps <= MAX_ELEMENTS``).

    Returns
    -------
    ndarray of int8
        Shape ``(steps,)`` or ``(size, steps)``, entries in {0, 1}.
    """
    p = check_probability("p", p)
    q = check_probability("q", q)
    steps = V.check_int("steps", steps, minimum=1, maximum=V.MAX_STEPS)
    initial = V.check_choice("initial", initial, (0, 1))
    n = 1 if size is None else V.check_int("size", size, minimum=1)
    V.check_size("size * steps", n * steps, V.MAX_ELEMENTS, "array entries")
    rng = V.as_rng("rng", rng)
    u = rng.random((n, steps))
    delta = np.empty((n, steps), dtype=np.int8)
    delta[:, 0] = initial
    for k in range(1, steps):
        good = delta[:, k - 1] == 1
        delta[:, k] = np.where(good, u[:, k] >= p, u[:, k] < q)
    return delta[0] if size is None else delta


def bernoulli(
    prob: float, shape: int | tuple[int, ...], rng: np.random.Generator | int
) -> NDArray[np.int8]:
    """Independent Bernoulli(``prob``) indicators of the given shape (1 with probability ``prob``).

    Parameters
    ----------
    prob : float
        Probability of a one, in [0, 1].
    shape : int or tuple of int
        Shape of the result (non-negative lengths, at most ``MAX_ELEMENTS`` entries).
    rng : numpy.random.Generator or int
        Source of randomness, or a non-negative integer seed (``None`` is refused).

    Returns
    -------
    ndarray of int8
        Entries in {0, 1}.
    """
    prob = check_probability("prob", prob)
    dims = (shape,) if not isinstance(shape, tuple | list) else tuple(shape)
    dims = tuple(V.check_int("shape", d, minimum=0) for d in dims)
    V.check_size("shape", int(np.prod(dims, dtype=object)), V.MAX_ELEMENTS, "array entries")
    return (V.as_rng("rng", rng).random(dims) < prob).astype(np.int8)
