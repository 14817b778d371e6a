"""System-theoretic helpers: observability matrices and subspaces, redundant observability.

Plain functions on ``(A, C)`` pairs of a linear time-invariant system

.. math::  \\dot x = A x \\;(\\text{or } x_{k+1} = A x_k), \\qquad y = C x,

used by the notebooks that need local / collective observability (lee2020: unobservable
subspaces of every sensor bank and 2q-redundant observability, Assumption 2; guo2023: local
observability ranks of the nodes).  Observability does not depend on the time domain, so the
same functions serve continuous- and discrete-time models.

It also holds the fixed-step integrator of linear systems with a static, possibly
discontinuous feedback nonlinearity (:func:`integrate_switched_linear`), used by lee2020 for
the sign-driven observer network and by the benchmark suite.

Rank decisions use *relative* tolerances: the observable subspace is grown by an orthogonal
staircase (Krylov iteration with re-orthonormalisation) on ``A / ||A||`` instead of the rank of
the raw observability matrix, whose singular values can span many decades (for the lee2020
three-inertia plant, more than five).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import combinations
from math import comb
from typing import NamedTuple

import numpy as np
import scipy.linalg as sla

from secest.core import validation as V
from secest.core.validation import ValidationError, as_matrix

__all__ = [
    "RedundancyResult",
    "discretize_zoh",
    "integrate_switched_linear",
    "is_observable",
    "observability_matrix",
    "observability_rank",
    "observable_subspace",
    "redundant_observability",
    "stack_banks",
    "unobservable_subspace",
]

_DEFAULT_RTOL = 1e-9


# ----------------------------------------------------------------------------- validation
def _as_matrix(value: object, name: str) -> np.ndarray:
    return as_matrix(name, value, (None, None))


def _check_A(A: object, name: str = "A") -> np.ndarray:
    A = _as_matrix(A, name)
    if A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise ValidationError(
            f"Incompatible dimensions of {name}: expected a non-empty square matrix, found {A.shape}"
        )
    return A


def _check_C(C: object, n: int, name: str = "C") -> np.ndarray:
    arr = as_matrix(name, C, finite=False)
    if arr.ndim == 1:  # a single output row
        arr = arr[None, :]
    arr = _as_matrix(arr, name)
    if arr.shape[1] != n:
        raise ValidationError(
            f"Incompatible dimensions of {name}: expected (m, {n}) to match A of shape "
            f"({n}, {n}), found {arr.shape}"
        )
    return arr


def _check_rtol(rtol: float) -> float:
    return V.check_real("rtol", rtol, lower=0.0, upper=1.0, lower_open=True, upper_open=True)


def _bank_list(C_banks: Sequence[object], name: str = "C_banks") -> list[object]:
    if isinstance(C_banks, np.ndarray) and C_banks.ndim == 2:
        raise ValidationError(
            f"{name} must be a sequence of per-bank output matrices; for a stacked C with one "
            "sensor per bank pass list(C) (or use stack_banks)"
        )
    if isinstance(C_banks, str | bytes):
        raise ValidationError(f"{name} must be a sequence of matrices, found {type(C_banks).__name__}")
    try:
        banks = list(C_banks)
    except TypeError as exc:
        raise ValidationError(
            f"{name} must be a sequence of matrices, found {type(C_banks).__name__}"
        ) from exc
    if not banks:
        raise ValidationError(f"{name} must contain at least one bank")
    return banks


def _check_banks(C_banks: Sequence[object], n: int, name: str = "C_banks") -> list[np.ndarray]:
    return [_check_C(Ci, n, name=f"{name}[{i}]") for i, Ci in enumerate(_bank_list(C_banks, name))]


# ----------------------------------------------------------------------------- functions
def observability_matrix(A: np.ndarray, C: np.ndarray, steps: int | None = None) -> np.ndarray:
    """Observability matrix ``O = col(C, CA, ..., CA^{steps-1})``.

    Parameters
    ----------
    A : (n, n) array_like
        State matrix.
    C : (m, n) or (n,) array_like
        Output matrix (a 1-D array is one output row).
    steps : int, optional
        Number of block rows; default ``n`` (the Kalman rank test).  A larger value is
        the ``steps``-step observability matrix of a discrete-time system
        (``m * steps * n <= MAX_ELEMENTS``).

    Returns
    -------
    (m * steps, n) ndarray

    Raises
    ------
    ValidationError
        Non-square ``A``, ``C`` with the wrong number of columns, ``steps < 1``.
    """
    A = _check_A(A)
    n = A.shape[0]
    C = _check_C(C, n)
    steps = n if steps is None else V.check_int("steps", steps, minimum=1)
    V.check_size("steps", C.shape[0] * steps * n, V.MAX_ELEMENTS, "array entries")
    blocks = [C]
    for _ in range(steps - 1):
        blocks.append(blocks[-1] @ A)
    return np.vstack(blocks)


def observable_subspace(A: np.ndarray, C: np.ndarray, rtol: float = _DEFAULT_RTOL) -> np.ndarray:
    """Orthonormal basis of the observable subspace ``range(O^T)`` of ``(C, A)``.

    The smallest ``A^T``-invariant subspace containing ``range(C^T)`` is grown by an
    orthogonal staircase: ``Q <- orth([Q, Â^T Q])`` with ``Â = A / ||A||_2``, starting from
    ``Q = orth(C^T)``, until the dimension stops growing.  Each ``orth`` uses the relative
    singular-value cut-off ``rtol``.  Its orthogonal complement is the unobservable subspace
    (the largest ``A``-invariant subspace in ``ker C``).

    Parameters
    ----------
    A : (n, n) array_like
    C : (m, n) or (n,) array_like
    rtol : float, default 1e-9
        Relative rank tolerance of every orthonormalisation, in (0, 1).

    Returns
    -------
    (n, r) ndarray
        Orthonormal columns, ``r`` = rank of the observability matrix (``r = 0`` possible).
    """
    A = _check_A(A)
    n = A.shape[0]
    C = _check_C(C, n)
    rtol = _check_rtol(rtol)
    if not np.any(C):
        return np.zeros((n, 0))
    scale = np.linalg.norm(A, 2)
    A_hat = A / scale if scale > 0 else A
    Q = sla.orth(C.T, rcond=rtol)
    while Q.shape[1] < n:
        Q_new = sla.orth(np.hstack([Q, A_hat.T @ Q]), rcond=rtol)
        if Q_new.shape[1] == Q.shape[1]:
            break
        Q = Q_new
    return Q


def unobservable_subspace(A: np.ndarray, C: np.ndarray, rtol: float = _DEFAULT_RTOL) -> np.ndarray:
    """Orthonormal basis of the unobservable subspace ``U = ker O`` of ``(C, A)``.

    ``U`` is the orthogonal complement of :func:`observable_subspace`; it is ``A``-invariant
    and contained in ``ker C`` (lee2020, Section III-A: the subspace ``U_i`` of bank ``i``).

    Parameters
    ----------
    A : (n, n) array_like
    C : (m, n) or (n,) array_like
    rtol : float, default 1e-9
        Relative rank tolerance, in (0, 1).

    Returns
    -------
    (n, n - r) ndarray
        Orthonormal columns (shape ``(n, 0)`` when the pair is observable).
    """
    Q = observable_subspace(A, C, rtol=rtol)
    n = Q.shape[0]
    if Q.shape[1] == 0:
        return np.eye(n)
    if Q.shape[1] == n:
        return np.zeros((n, 0))
    return sla.null_space(Q.T)


def observability_rank(A: np.ndarray, C: np.ndarray, rtol: float = _DEFAULT_RTOL) -> int:
    """Dimension of the observable subspace of ``(C, A)`` (rank of the observability matrix).

    Parameters
    ----------
    A : (n, n) array_like
    C : (m, n) or (n,) array_like
    rtol : float, default 1e-9
        Relative rank tolerance, in (0, 1).

    Returns
    -------
    int
    """
    return int(observable_subspace(A, C, rtol=rtol).shape[1])


def is_observable(A: np.ndarray, C: np.ndarray, rtol: float = _DEFAULT_RTOL) -> bool:
    """``True`` iff ``(C, A)`` is observable (observable subspace of full dimension ``n``).

    Parameters
    ----------
    A : (n, n) array_like
    C : (m, n) or (n,) array_like
    rtol : float, default 1e-9
        Relative rank tolerance, in (0, 1).

    Returns
    -------
    bool
    """
    Q = observable_subspace(A, C, rtol=rtol)
    return Q.shape[1] == Q.shape[0]


def stack_banks(C_banks: Sequence[np.ndarray], n: int | None = None) -> np.ndarray:
    """Stack per-bank output matrices ``C_i`` (each ``(m_i, n)`` or ``(n,)``) into one ``C``.

    Parameters
    ----------
    C_banks : sequence of (m_i, n) or (n,) array_like
        One output matrix per sensor bank (at least one).
    n : int, optional
        State dimension; default the number of columns of the first bank.

    Returns
    -------
    (sum_i m_i, n) ndarray
    """
    banks = _bank_list(C_banks)
    if n is None:
        first = as_matrix("C_banks[0]", banks[0])
        n = first.shape[-1] if first.ndim in (1, 2) else 0
    else:
        n = V.check_int("n", n, minimum=1)
    return np.vstack(_check_banks(banks, n))


class RedundancyResult(NamedTuple):
    """Outcome of :func:`redundant_observability`.

    Attributes
    ----------
    holds : bool
        ``True`` iff every subset of ``N - 2q`` banks gives an observable pair.
    failing : tuple of tuple of int
        The subsets (0-based bank indices, sorted) whose stacked pair is not observable.
    n_subsets : int
        Number of subsets checked, ``binom(N, N - 2q)``.
    """

    holds: bool
    failing: tuple[tuple[int, ...], ...]
    n_subsets: int


def redundant_observability(
    A: np.ndarray,
    C_banks: Sequence[np.ndarray],
    q: int,
    rtol: float = _DEFAULT_RTOL,
) -> RedundancyResult:
    """Check 2q-redundant observability by enumeration (lee2020, Assumption 2).

    The pair is *2q-redundant observable* when, for every set ``N'`` of ``N - 2q`` sensor banks,
    the stacked output matrix ``C_{N'}`` makes ``(C_{N'}, A)`` observable, i.e. the plant stays
    observable after removing any ``2q`` banks.  It is necessary for resilient estimation
    against ``q`` corrupted banks (Fawzi et al. 2014; lee2020, Section I).  All
    ``binom(N, N - 2q)`` subsets are checked (combinatorial; fine for small ``N``).  Removing
    banks can only lose observability, so subsets larger than ``N - 2q`` need no check.

    Parameters
    ----------
    A : (n, n) array_like
    C_banks : sequence of (m_i, n) or (n,) array_like
        One output matrix per sensor bank.
    q : int
        Number of banks that may be corrupted, ``0 <= q`` and ``2q < N``.
    rtol : float, default 1e-9
        Relative rank tolerance (see :func:`observable_subspace`).

    Returns
    -------
    RedundancyResult
        ``holds``, the failing subsets and the number of subsets checked.

    Raises
    ------
    ValidationError
        Non-square ``A``, a bank with the wrong number of columns, a negative or non-integer
        ``q``, or ``q`` too large (``N - 2q < 1``); :class:`~secest.core.validation.SizeLimitError`
        if more than ``MAX_SUBSETS`` subsets would be enumerated.
    """
    A = _check_A(A)
    n = A.shape[0]
    banks = _check_banks(C_banks, n)
    rtol = _check_rtol(rtol)
    N = len(banks)
    if isinstance(q, bool) or not isinstance(q, int | np.integer) or q < 0:
        raise ValidationError(f"q must be a non-negative integer, found {q!r}")
    q = int(q)
    if N - 2 * q < 1:
        raise ValidationError(
            f"q is too large: 2q-redundant observability needs N - 2q >= 1 banks left, "
            f"found N = {N}, q = {q} (largest admissible q is {(N - 1) // 2})"
        )
    V.check_size(f"q = {q} with N = {N} banks (C_banks)", comb(N, 2 * q), V.MAX_SUBSETS, "subsets")
    failing = []
    n_subsets = 0
    for subset in combinations(range(N), N - 2 * q):
        n_subsets += 1
        if not is_observable(A, np.vstack([banks[i] for i in subset]), rtol=rtol):
            failing.append(tuple(subset))
    return RedundancyResult(holds=not failing, failing=tuple(failing), n_subsets=n_subsets)


# ----------------------------------------------------------------------------- integration
def discretize_zoh(M: np.ndarray, E: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact zero-order-hold discretisation of ``X' = M X + E g`` over one step ``dt``.

    Returns ``Phi = exp(M dt)`` and ``Gamma = int_0^dt exp(M s) ds E``, both read off one
    matrix exponential ``expm([[M, E], [0, 0]] dt)`` (Van Loan), so ``M`` may be singular.

    Parameters
    ----------
    M : (nx, nx) array_like
        Linear part.
    E : (nx, ne) array_like
        Input matrix.
    dt : float
        Step, positive and finite.

    Returns
    -------
    Phi : (nx, nx) ndarray
    Gamma : (nx, ne) ndarray

    Raises
    ------
    ValidationError
        Non-square ``M``, ``E`` with the wrong number of rows, ``dt <= 0``.
    """
    M = _check_A(M, "M")
    nx = M.shape[0]
    E = as_matrix("E", E, (nx, None), note="to match M")
    dt = _check_dt(dt)
    ne = E.shape[1]
    aug = np.zeros((nx + ne, nx + ne))
    aug[:nx, :nx] = M * dt
    aug[:nx, nx:] = E * dt
    expo = sla.expm(aug)
    return expo[:nx, :nx], expo[:nx, nx:]


def _check_dt(dt: float) -> float:
    return V.check_real("dt", dt, lower=0.0, lower_open=True)


def integrate_switched_linear(
    M: np.ndarray,
    E_w: np.ndarray,
    w: Callable[[float], np.ndarray],
    E_s: np.ndarray,
    R: np.ndarray,
    phi: Callable[[np.ndarray], np.ndarray],
    x0: np.ndarray,
    dt: float,
    n_steps: int,
    *,
    record_every: int = 1,
    method: str = "expeuler",
) -> np.ndarray:
    """Fixed-step integration of ``X' = M X + E_w w(t) + E_s phi(R X)``.

    The model is linear apart from a static nonlinearity ``phi`` of the linear output ``R X``,
    e.g. ``phi = sign`` (a discontinuous right-hand side whose solutions are understood in the
    Filippov sense).  On every step ``[t_k, t_k + dt]`` the exogenous input is sampled at the
    midpoint, ``w(t_k + dt/2)``, and the nonlinearity at the left end, ``phi(R X_k)``; both are
    held constant over the step.

    ``method="expeuler"`` (exponential Euler; exact zero-order hold of the linear part)::

        X_{k+1} = Phi X_k + Gamma_w w(t_k + dt/2) + Gamma_s phi(R X_k)

    with ``Phi, [Gamma_w, Gamma_s]`` from :func:`discretize_zoh`.  It has no step-size limit
    from the linear part (stiff or lightly damped modes, large coupling gains); on sliding
    surfaces it chatters with an amplitude of order ``||Gamma_s|| = O(dt)``, so it converges
    with order one in ``dt`` to the Filippov solution.

    ``method="euler"`` (explicit Euler, for comparison)::

        X_{k+1} = X_k + dt (M X_k + E_w w(t_k + dt/2) + E_s phi(R X_k))

    stable only while the spectral radius of ``I + dt M`` stays at most one.

    Parameters
    ----------
    M : (nx, nx) array_like
        Linear part.
    E_w : (nx, nw) array_like
        Input matrix of the exogenous signal.
    w : callable ``t -> (nw,)`` or ``(nw, B)`` array
        Exogenous signal (a 2-D value drives ``B`` scenarios at once, one per column).
    E_s : (nx, ns) array_like
        Input matrix of the nonlinearity.
    R : (ns, nx) array_like
        Output whose image goes through the nonlinearity.
    phi : callable ``(ns,) or (ns, B) array -> same shape``
        Static nonlinearity, applied to ``R X``.
    x0 : (nx,) or (nx, B) array_like
        Initial state (``B`` columns are integrated together; every matrix product is
        vectorised over them).
    dt : float
        Step size.
    n_steps : int
        Number of steps; the final time is ``n_steps * dt``.
    record_every : int, default 1
        Keep every ``record_every``-th state (and the initial one).
    method : {"expeuler", "euler"}

    Returns
    -------
    ndarray, shape ``(n_steps // record_every + 1,) + x0.shape``
        The recorded states at ``t = j * record_every * dt``.

    Raises
    ------
    ValidationError
        Inconsistent shapes, ``dt <= 0``, bad ``n_steps`` / ``record_every`` or an unknown
        ``method``.
    """
    M = _check_A(M, "M")
    nx = M.shape[0]
    E_w = as_matrix("E_w", E_w, (nx, None))
    E_s = as_matrix("E_s", E_s, (nx, None))
    R = as_matrix("R", R, (E_s.shape[1], nx), note="to match E_s and M")
    X = np.array(as_matrix("x0", x0), dtype=float)
    if X.ndim not in (1, 2) or X.shape[0] != nx:
        raise ValidationError(
            f"Incompatible dimensions of x0: expected ({nx},) or ({nx}, B), found {X.shape}"
        )
    w = V.check_callable("w", w)
    phi = V.check_callable("phi", phi)
    dt = _check_dt(dt)
    n_steps = _count("n_steps", n_steps, 0, "a non-negative")
    record_every = _count("record_every", record_every, 1, "a positive")
    V.check_size("n_steps", n_steps, V.MAX_STEPS, "integration steps")
    n_rec = n_steps // record_every + 1
    V.check_size("n_steps / record_every", n_rec * X.size, V.MAX_ELEMENTS, "recorded entries")
    method = V.check_choice("method", method, ("expeuler", "euler"))
    if method == "expeuler":
        Phi, Gam = discretize_zoh(M, np.hstack([E_w, E_s]), dt)
        G_w, G_s = Gam[:, : E_w.shape[1]], Gam[:, E_w.shape[1] :]
    else:
        Phi = np.eye(nx) + dt * M
        G_w, G_s = dt * E_w, dt * E_s
    w_shapes = {(E_w.shape[1],), (E_w.shape[1],) + X.shape[1:]}
    out = np.empty((n_rec,) + X.shape)
    out[0] = X
    for k in range(n_steps):
        t = (k + 0.5) * dt
        gw = G_w @ _output("w", w(t), w_shapes, t)
        if gw.ndim < X.ndim:  # one input shared by all B columns
            gw = gw[:, None]
        RX = R @ X
        X = Phi @ X + gw + G_s @ _output("phi", phi(RX), {RX.shape}, t)
        if (k + 1) % record_every == 0:
            out[(k + 1) // record_every] = X
    _check_trajectory(out, record_every * dt, method)
    return out


def _check_trajectory(out: np.ndarray, dt_rec: float, method: str) -> None:
    """Refuse a trajectory that is not finite (NaN from w or phi, or a diverging scheme)."""
    bad = ~np.isfinite(out.reshape(out.shape[0], -1)).all(axis=1)
    if np.any(bad):
        t = int(np.argmax(bad)) * dt_rec
        hint = "; for method='euler' reduce dt" if method == "euler" else ""
        raise ValidationError(
            f"the state is not finite from t = {t:g}: w or phi returned NaN or inf values, or "
            f"the integration with dt diverged{hint}"
        )


def _count(name: str, value: object, minimum: int, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise ValidationError(f"{name} must be {what} integer, found {value!r}")
    return int(value)


def _output(name: str, value: object, shapes: set[tuple[int, ...]], t: float) -> np.ndarray:
    """The value returned by the callable ``name``, checked for type and shape (cheaply)."""
    if isinstance(value, np.ndarray) and value.dtype.kind in "biuf" and value.shape in shapes:
        return value
    arr = np.asarray(value) if not isinstance(value, str | bytes) else np.asarray(None)
    if arr.dtype.kind not in "biuf" or arr.shape not in shapes:
        expected = " or ".join(str(s) for s in sorted(shapes))
        expected += " (to match E_w and x0)" if name == "w" else " (that of R @ x)"
        raise ValidationError(
            f"{name} must return real values of shape {expected}, found {V._show(value)} at t = {t:g}"
        )
    return arr
