"""lee2020: the distributed median solver and the median-embedded observer.

Lee, Kim, Shim (2020), "Fully distributed resilient state estimation based on distributed
median solver", IEEE TAC, doi:10.1109/TAC.2020.2989275. Equation numbers are the paper's.

Two layers, both plain functions on arrays:

* **The paper's continuous-time design**, which the notebook ``notebooks/lee2020.py`` derives and
  runs (it imports these functions and shows their source): the median set and the median solver
  (4), for one gain or a batch of gains; the real invariant subspaces of ``A``, the observation
  pattern of every bank and the common basis of Assumption 4 (a grouped projected-orthonormal
  construction, ours; for repeated eigenvalues the brief's subset-intersection fallback, ours) and
  its scaling; the partial-observer gains of (5); the stacked matrices of (1), (5), (6) [or (11),
  with the ``P`` of :func:`lyapunov_correction`] integrated by
  :func:`secest.core.systems.integrate_switched_linear` (exponential Euler).
* **The sampled-data reading on a shared scenario** (ours): the same (5) and (6), integrated by
  the same exponential-Euler scheme with sub-steps of the sampling period, fed the sampled
  measurements, and coupled through messages exchanged once per sampling period.

The arena method (:class:`Lee2020`) reads a scenario as follows.

* Node ``i`` is the paper's agent ``i`` and its sensor rows ``C_i`` are its bank. The plant is the
  scenario's continuous-time model ``Ac`` (no input, ``B = 0``); process and sensor noise are
  outside the paper's noise-free model (1).
* Measurements: the observer ODE over ``(t_{k-1}, t_k]`` is integrated when ``y_k`` arrives, with
  ``y_k`` held over the interval (a causal "latest sample" hold), so the estimate of ``x_k`` uses
  the data of step ``k`` as the arena's convention asks; a zero-order hold of ``y_{k-1}`` would
  make every estimate a one-step prediction.
* Messages: at ``t_k`` every node sends its resilient estimate ``x_hat_i(t_k)`` (scale: the prior
  standard deviation ``x0_std``); over the next interval the consensus term of (6) uses the
  received (possibly falsified) neighbour estimates held, and the node's own estimate
  continuously: ``kappa gamma sum_j (x_hat_j(t_k) - x_hat_i(t))``. As the sampling period goes
  to zero this is (6) (measured in the tests). A lost message (DoS) removes the neighbour from
  the sum over the interval, i.e. the receiver runs on its own data, the reading of the paper's
  graph without that edge. The paper's links are reliable (Assumption 3): falsified and lost
  messages are outside its theory, recorded in ``Estimate.notes``.
* Design parameters, fixed from the paper before any arena run: ``kappa = 0.5``, ``gamma = 2``
  and ``q = 1`` of Section IV; the basis of Assumption 4 by the notebook's construction (unit
  norm); observer poles by the notebook's ``"shifted"`` rule (real parts at ``-1``, the paper's
  "near -1", imaginary parts of ``eig(W_i A V_i)`` kept). Rule for the poles: the literal
  ``"near"`` placement needs gains up to 1.5e3 on the three-inertia plant (notebook), which would
  multiply the scenario's sensor noise (absent from the paper) by as much; both rules coincide
  on plants with real eigenvalues (the target and the quadruple tank).
* Sub-step (rule from the notebook's integrator study: exponential Euler chatters on the sliding
  surfaces with amplitude ``kappa ||v_l|| h``, order one in ``h``): the largest ``h = dt / m``
  with ``kappa max_l ||v_l|| h <= CHATTER_FRACTION`` times the smallest sensor-noise standard
  deviation in state units, ``min r_std / ||C row||``, but no finer than the notebook's own
  step ``FINEST_SUBSTEP = 1e-3`` s.
* Alarms (the Conclusion's identification, ``z_i`` against ``W_i x_hat_i``; threshold rule
  ours): node ``i`` raises an alarm at step ``k`` when some coordinate of ``z_i - W_i x_hat_i``
  exceeds ``2 z_{1 - alpha / (2 o_i)}`` standard deviations of the partial observer's stationary
  error under the scenario's noise (``alpha = CHI2_ALPHA``; the factor 2 bounds the resilient
  estimate's own error by the partial one's), and only once the partial observers' 3-sigma
  transient from the prior and the sign correction's slew across a 3-sigma prior error
  (``3 x0_std max ||w_l|| / kappa``) are over.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import combinations
from typing import NamedTuple

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from secest.core import graphs, systems
from secest.core.validation import ValidationError, as_matrix, check_positive_int

__all__ = [
    "CHATTER_FRACTION",
    "FINEST_SUBSTEP",
    "GAMMA",
    "KAPPA",
    "POLES",
    "Q",
    "Basis",
    "NetworkSystem",
    "SampledObserver",
    "SampledRun",
    "alarm_rule",
    "assumption4_basis",
    "check_assumption4",
    "redundant_from_basis",
    "common_basis",
    "euler_limit",
    "in_span",
    "intersection_basis",
    "lyapunov_correction",
    "median_set",
    "median_solver",
    "mode_pattern",
    "network_system",
    "normalise_basis",
    "observer_gains",
    "real_invariant_subspaces",
    "run_sampled",
    "sampled_observer",
    "sign_correction",
    "substeps",
]

KAPPA = 0.5
"""Gain of the sign correction in (6) (Section IV)."""
GAMMA = 2.0
"""Coupling gain of (6) (Section IV)."""
Q = 1
"""Number of corruptible banks (Section IV: "2-redundant observable")."""
POLES = "shifted"
"""Observer-pole rule of the arena (see the module docstring)."""
CHATTER_FRACTION = 0.1
"""Chattering amplitude ``kappa ||v|| h`` allowed, as a fraction of the smallest sensor noise."""
FINEST_SUBSTEP = 1e-3
"""Finest sub-step [s]: the notebook's own step, validated by its integrator study."""

Array = NDArray[np.float64]


def _key(*arrays: ArrayLike) -> bytes:
    """Bytes identifying a tuple of arrays (values and shapes): equal keys, equal per-node results.

    The per-node designs below depend only on the node's own matrices, so nodes with equal ones
    (a card's repeated sensor types) share one computation: the results are the same, the cost
    grows with the number of distinct nodes instead of ``N``.
    """
    parts = (np.ascontiguousarray(a, dtype=float) for a in arrays)
    return b"|".join(a.tobytes() + str(a.shape).encode() for a in parts)


# ------------------------------------------------------------------------ Section II: (4)


def median_set(values: Array, indicators: Array) -> tuple[float, float]:
    """Median set ``[lo, hi]`` of the indicated values (a single point when ``S`` is odd).

    The minimiser set of ``sum_i s_i |z_i - x|`` (Section II): with ``z^s`` the ``S`` indicated
    values sorted, ``[z^s_{(S-1)//2}, z^s_{S//2}]`` (0-based), which covers both parities.

    Parameters
    ----------
    values : (N,) array
        The local values ``z_i`` (Section II: ``z_i = y_i / C_i``).
    indicators : (N,) array of 0 / 1
        ``s_i``: 1 when node ``i``'s value counts (``C_i != 0``); at least one must be 1.

    Returns
    -------
    lo, hi : float
        Ends of the median set ``M_Z^S`` (equal when ``S`` is odd).
    """
    values = as_matrix("values", values, (None,))
    indicators = as_matrix("indicators", indicators, values.shape)
    zs = np.sort(values[indicators == 1])
    if zs.size == 0:
        raise ValidationError("indicators must mark at least one value (s_i = 1)")
    return float(zs[(zs.size - 1) // 2]), float(zs[zs.size // 2])  # M_Z^S (Section II)


def euler_limit(adj: Array, gains: float | Array) -> float:
    """Largest stable explicit-Euler step ``2 / (gamma_max lambda_max(L))`` of (4).

    Parameters
    ----------
    adj : (N, N) array
        Adjacency of the graph of (4); ``L`` its Laplacian.
    gains : float or (G,) array
        The coupling gain(s) ``gamma`` of (4); the largest one sets the limit.

    Returns
    -------
    float
        The step [s] at and above which ``I - step gamma L`` has an eigenvalue at or below -1.
    """
    return float(2.0 / (np.max(gains) * np.linalg.eigvalsh(graphs.laplacian(adj))[-1]))


def median_solver(
    adj: Array,
    values: Array,
    indicators: Array,
    x_start: Array,
    gain: float | Array,
    horizon_s: float,
    step: float,
) -> tuple[Array, Array]:
    """Explicit-Euler solution of the distributed median solver (4).

    ``x_i' = s_i sgn(z_i - x_i) + gamma sum_{j in N_i} (x_j - x_i)``, i.e.
    ``x' = s (.) sgn(z - x) - gamma L x`` with ``sgn(0) = 0`` (Filippov solutions; on a sliding
    surface the iterate chatters within ``step`` of it).  # (4)

    Parameters
    ----------
    adj : (N, N) array
        0/1 adjacency of an undirected connected graph (Assumption 3); ``L`` its Laplacian.
    values : (N,) array
        ``z_i`` of (4).
    indicators : (N,) array of 0 / 1
        ``s_i`` of (4).
    x_start : (N,) array
        Initial solver states ``x_i(0)`` (the same for every gain).
    gain : float or (G,) array
        Coupling gain ``gamma > 0`` of (4); an array runs one solver per gain, all gains as
        columns of one recursion (Theorem 1 across gains).
    horizon_s : float
        Final time [s]; the number of steps is ``round(horizon_s / step)``.
    step : float
        Euler step [s], below ``2 / (gamma lambda_max(L))`` (:func:`euler_limit`) for every gain.

    Returns
    -------
    t : (K + 1,) array
        Times ``0, step, ..., horizon_s``.
    x : (K + 1, N) array, or (K + 1, N, G) for an array of gains
        The solver states.

    Raises
    ------
    ValidationError
        Inputs of the wrong shape, a gain that is not positive, or ``step`` at or above the
        Euler stability limit ``2 / (gamma lambda_max(L))``.

    Notes
    -----
    A scalar gain evaluates ``(gamma L) x``, an array ``gamma (.) (L x)`` column by column: equal
    in exact arithmetic, and each is the order of floating-point operations of the notebook's
    run (scalar: Fig. S1; array: the Theorem 1 sweep), whose figure data are committed.
    """
    lap = graphs.laplacian(graphs.check_connected(adj))
    n_agents = lap.shape[0]
    values = as_matrix("values", values, (n_agents,))
    indicators = as_matrix("indicators", indicators, (n_agents,))
    x_start = as_matrix("x_start", x_start, (n_agents,))
    batch = np.ndim(gain) > 0
    gains = as_matrix("gain", gain, (None,)) if batch else np.array([float(gain)])
    if gains.size == 0 or np.any(gains <= 0):
        raise ValidationError(f"gain must be positive (at least one), found {gain!r}")
    limit = euler_limit(adj, gains)
    if step >= limit:
        raise ValidationError(
            f"step={step} is above the Euler stability limit 2/(gamma*lambda_max(L)) = {limit:.3g}"
        )
    steps = int(round(horizon_s / step))
    if batch:
        xs = np.empty((steps + 1, n_agents, gains.size))
        xs[0] = np.repeat(x_start[:, None], gains.size, axis=1)
        s_col, z_col, g_row = indicators[:, None], values[:, None], gains[None, :]
        for k in range(steps):
            xs[k + 1] = xs[k] + step * (s_col * np.sign(z_col - xs[k]) - g_row * (lap @ xs[k]))  # (4)
        return step * np.arange(steps + 1), xs
    xs = np.empty((steps + 1, n_agents))
    xs[0] = x_start
    g = gains[0]
    for k in range(steps):
        xs[k + 1] = xs[k] + step * (indicators * np.sign(values - xs[k]) - g * lap @ xs[k])  # (4)
    return step * np.arange(steps + 1), xs


# ------------------------------------------------------------- Assumption 4: the common basis


def real_invariant_subspaces(A: Array) -> list[tuple[complex, Array]]:
    """Real invariant subspaces of a matrix with distinct eigenvalues (Section III-A).

    One column (unit real eigenvector) per real eigenvalue, two columns ``[Re v, Im v]`` per
    conjugate pair, with ``v`` rotated so that ``Re v`` is orthogonal to ``Im v`` and scaled so
    that ``||Re v|| = 1``. Ordered by decreasing real part.

    Parameters
    ----------
    A : (n, n) array
        Plant matrix of (1), with distinct eigenvalues.

    Returns
    -------
    list of (complex, (n, 1) or (n, 2) array)
        Each real mode: its eigenvalue (the one with positive imaginary part for a pair) and
        the real basis ``X_k`` of its invariant subspace.

    Raises
    ------
    ValidationError
        Repeated eigenvalues (use :func:`intersection_basis`).
    """
    lam, vec = np.linalg.eig(as_matrix("A", A, square=True))
    if np.min(np.abs(lam[:, None] - lam[None, :]) + np.eye(lam.size) * 1e9) < 1e-9 * max(
        1.0, np.abs(lam).max()
    ):
        raise ValidationError("A has repeated eigenvalues: use intersection_basis")
    out = []
    for idx in np.argsort(-lam.real + 1e-9 * np.abs(lam.imag)):
        mu = lam[idx]
        if abs(mu.imag) <= 1e-12 * max(1.0, abs(mu)):
            v = vec[:, idx].real
            out.append((complex(mu.real), (v / np.linalg.norm(v))[:, None]))
        elif mu.imag > 0:
            v = vec[:, idx]
            th = 0.5 * np.arctan2(2 * v.real @ v.imag, v.real @ v.real - v.imag @ v.imag)
            v = v * np.exp(-1j * th)
            v = v / np.linalg.norm(v.real)
            out.append((complex(mu), np.column_stack([v.real, v.imag])))
    return out


def in_span(vec: Array, basis: Array, tol: float = 1e-7) -> bool:
    """True iff ``vec`` lies in ``range(basis)`` (orthonormal columns), relative residual <= tol.

    Parameters
    ----------
    vec : (n,) array
        The vector tested.
    basis : (n, d) array
        Orthonormal columns (``d = 0``: the zero subspace, which contains only ``vec = 0``).
    tol : float, default 1e-7
        Largest ``||vec - basis basis^T vec|| / ||vec||`` accepted.
    """
    resid = vec - basis @ (basis.T @ vec) if basis.shape[1] else vec
    return bool(np.linalg.norm(resid) <= tol * np.linalg.norm(vec))


def mode_pattern(
    modes: list[tuple[complex, Array]], U_sub: Sequence[Array], banks: Sequence[Array]
) -> Array:
    """Observation pattern of every real mode: ``pattern[k, i] = 1`` iff bank ``i`` sees mode ``k``.

    Read off the unobservable subspaces ``U_i`` (staircase,
    :func:`secest.core.systems.unobservable_subspace`) and cross-checked with
    the PBH test ``C_i X_k != 0``.

    Parameters
    ----------
    modes : list of (complex, (n, d_k) array)
        The real modes ``(lambda_k, X_k)`` of :func:`real_invariant_subspaces`.
    U_sub : sequence of N (n, n - o_i) arrays
        Orthonormal bases of the unobservable subspaces ``U_i`` of ``(C_i, A)`` (Section III-A).
    banks : sequence of N (m_i, n) arrays
        ``C_i`` of every sensor bank.

    Returns
    -------
    (n_modes, N) int array
        ``pattern[k, i]``.

    Raises
    ------
    ValidationError
        If the two tests disagree (a rank decision too close to call).
    """
    pattern = np.array(
        [[0 if all(in_span(X[:, c], U) for c in range(X.shape[1])) else 1 for U in U_sub]
         for _, X in modes]
    )
    pbh = np.array(
        [[int(np.linalg.norm(Ci @ X) > 1e-9 * np.linalg.norm(Ci) * np.linalg.norm(X)) for Ci in banks]
         for _, X in modes]
    )
    if not np.array_equal(pattern, pbh):
        raise ValidationError("banks: the staircase and PBH tests disagree on the observation pattern")
    return pattern


def common_basis(modes: list[tuple[complex, Array]], pattern: Array) -> tuple[Array, Array, Array]:
    """Grouped projected-orthonormal basis of Assumption 4 (our construction; Section III-A).

    Modes with equal observation patterns are grouped; in each group, Gram-Schmidt on the
    orthogonal projections of ``e_1, e_2, ...`` onto the group's span (dependent projections,
    norm < 1e-6, skipped); groups ordered by the number of observing banks.

    Parameters
    ----------
    modes : list of (complex, (n, d_k) array)
        The real modes of :func:`real_invariant_subspaces`.
    pattern : (n_modes, N) int array
        Which bank observes which mode (:func:`mode_pattern`).

    Returns
    -------
    V : (n, n) array
        The basis ``[v_1 ... v_n]`` (unit-norm columns).
    S : (N, n) int array
        Indicators ``s_i^l`` (bank ``i`` observes coordinate ``l``).
    T : (n, n) array
        The real modal matrix, grouped like ``V``.
    """
    dim = modes[0][1].shape[0]
    groups: dict[tuple[int, ...], list[int]] = {}
    for kk, row in enumerate(pattern):
        groups.setdefault(tuple(int(v) for v in row), []).append(kk)
    cols, ind, modal = [], [], []
    for pat, ks in sorted(groups.items(), key=lambda g: (sum(g[0]), min(g[1]))):
        span = np.hstack([modes[kk][1] for kk in ks])
        q_span = sla.orth(span)
        proj = q_span @ q_span.T
        basis: list[Array] = []
        for e in np.eye(dim):
            v = proj @ e
            for bv in basis:
                v = v - (bv @ v) * bv
            if np.linalg.norm(v) > 1e-6:
                basis.append(v / np.linalg.norm(v))
            if len(basis) == q_span.shape[1]:
                break
        cols += basis
        ind += [pat] * len(basis)
        modal += list(span.T)
    return np.column_stack(cols), np.array(ind).T, np.column_stack(modal)


def _intersection(spaces: Sequence[Array], n: int) -> Array:
    """Orthonormal basis of the intersection of subspaces given by orthonormal bases."""
    if not spaces:
        return np.eye(n)
    if any(U.shape[1] == 0 for U in spaces):
        return np.zeros((n, 0))
    return sla.null_space(np.vstack([np.eye(n) - U @ U.T for U in spaces]), rcond=1e-9)


def intersection_basis(U_sub: Sequence[Array]) -> tuple[Array, Array]:
    """Basis of Assumption 4 by intersecting unobservable subspaces (brief Sec. 3.2 step 6; ours).

    For every set ``J`` of distinct subspaces ``U_i``, from the largest sets to the smallest
    (``J`` empty: the whole space), the vectors already chosen inside ``Z_J = cap_{i in J} U_i``
    are extended to a basis of ``Z_J`` by Gram-Schmidt on the projections of ``e_1, e_2, ...``
    onto ``Z_J``. Needed when ``A`` has repeated eigenvalues; the result must still pass
    :func:`check_assumption4` (a failure does not prove that no basis exists).

    Parameters
    ----------
    U_sub : sequence of N (n, n - o_i) arrays
        Orthonormal bases of the unobservable subspaces ``U_i``.

    Returns
    -------
    V : (n, n) array
        Unit-norm columns.
    S : (N, n) int array
        Indicators (``s_i^l = 0`` iff ``v_l`` lies in ``U_i``).
    """
    n = U_sub[0].shape[0]
    distinct: list[Array] = []
    for U in U_sub:
        if not any(D.shape == U.shape and all(in_span(u, D) for u in U.T) for D in distinct):
            distinct.append(U)
    chosen: list[Array] = []
    for size in range(len(distinct), -1, -1):
        for J in combinations(range(len(distinct)), size):
            Z = _intersection([distinct[j] for j in J], n)
            if Z.shape[1] == 0:
                continue
            family = [v for v in chosen if in_span(v, Z)]
            ortho = list(sla.orth(np.column_stack(family)).T) if family else []
            added = 0
            for e in Z @ Z.T:
                if len(family) + added == Z.shape[1]:
                    break
                v = e.copy()
                for b in ortho:
                    v = v - (b @ v) * b
                if np.linalg.norm(v) > 1e-6:
                    v = v / np.linalg.norm(v)
                    ortho.append(v)
                    chosen.append(v)
                    added += 1
    V = np.column_stack(chosen)
    S = np.array([[0 if in_span(v, U) else 1 for v in V.T] for U in U_sub])
    return V, S


def check_assumption4(V: Array, S: Array, U_sub: Sequence[Array]) -> tuple[bool, float]:
    """Verify Assumption 4: ``v_l in U_i <=> s_i^l = 0`` and ``#{l: s_i^l = 0} = dim U_i``.

    Also that ``V`` is square and invertible (a basis of ``R^n``).

    Parameters
    ----------
    V : (n, n) array
        Candidate basis, columns ``v_l``.
    S : (N, n) int array
        Indicators ``s_i^l``.
    U_sub : sequence of N (n, n - o_i) arrays
        Orthonormal bases of the unobservable subspaces ``U_i``.

    Returns
    -------
    ok : bool
    residual : float
        Largest projection residual of a member ``v_l`` of some ``U_i``.
    """
    n = V.shape[0]
    resid = 0.0
    ok = V.shape == (n, n) and np.linalg.matrix_rank(V) == n
    for i, U in enumerate(U_sub):
        ok &= int((S[i] == 0).sum()) == U.shape[1]
        for ll in range(n):
            member = in_span(V[:, ll], U)
            ok &= member == (S[i, ll] == 0)
            if member and U.shape[1]:
                resid = max(resid, float(np.linalg.norm(V[:, ll] - U @ (U.T @ V[:, ll]))))
    return bool(ok), resid


def redundant_from_basis(S: Array, q: int) -> bool:
    """2q-redundant observability (Assumption 2) read off the indicators of a basis of Assumption 4.

    With a verified basis (:func:`check_assumption4`), bank ``i``'s unobservable subspace is
    ``U_i = span{v_l : s_i^l = 0}``, so the unobservable subspace of a set ``J`` of banks is
    ``cap_{i in J} U_i = span{v_l : s_i^l = 0 for every i in J}`` and ``J`` observes the plant
    iff every coordinate ``l`` is seen by some bank of ``J``. Every set of ``N - 2q`` banks then
    observes it iff every coordinate is seen by at least ``2q + 1`` banks: one count per
    coordinate, ``O(N n)``, instead of the ``binom(N, 2q)`` subsets of
    :func:`secest.core.systems.redundant_observability` (which needs no basis; the two agree
    whenever the basis passes :func:`check_assumption4`, measured in the tests).

    Parameters
    ----------
    S : (N, n) array of 0 / 1
        Indicators ``s_i^l`` of a verified basis of Assumption 4 (:attr:`Basis.S` with ``ok``).
    q : int
        Number of banks that may be corrupted, ``q >= 0``.

    Returns
    -------
    bool
        True iff ``N - 2q >= 1`` and ``sum_i s_i^l >= 2q + 1`` for every ``l``.

    Raises
    ------
    ValidationError
        ``S`` not a 2-D 0/1 array, or ``q`` not a non-negative integer.
    """
    S = as_matrix("S", S, (None, None))
    if not np.all((S == 0) | (S == 1)):
        raise ValidationError("S must hold 0/1 indicators s_i^l")
    if isinstance(q, bool) or not isinstance(q, int | np.integer) or q < 0:
        raise ValidationError(f"q must be a non-negative integer, found {q!r}")
    return bool(S.shape[0] - 2 * q >= 1 and np.all(S.sum(axis=0) >= 2 * q + 1))


class Basis(NamedTuple):
    """A basis of Assumption 4 and what it was built from.

    Attributes
    ----------
    V : (n, d) array
        Columns ``v_l`` (unit norm); ``d = n`` whenever ``ok``.
    W : (n, n) array or None
        ``V^{-1}`` (rows ``w_l^T``); None when the check failed (``V`` need not be square).
    S : (N, n) int array
        Indicators ``s_i^l`` (1: bank ``i`` observes the coordinate ``w_l^T x``).
    U_sub : list of N (n, n - o_i) arrays
        Unobservable subspace ``U_i`` of every bank (orthonormal columns).
    construction : {"modes", "intersections"}
        ``"modes"`` (:func:`common_basis`) or ``"intersections"`` (:func:`intersection_basis`).
    ok : bool
        :func:`check_assumption4` passed.
    """

    V: Array
    W: Array | None
    S: Array
    U_sub: list[Array]
    construction: str
    ok: bool


def assumption4_basis(A: Array, banks: Sequence[Array]) -> Basis:
    """Basis of Assumption 4: :func:`common_basis` for distinct eigenvalues, else intersections.

    Parameters
    ----------
    A : (n, n) array
        Plant matrix of (1).
    banks : sequence of (m_i, n) arrays
        ``C_i`` of every bank.
    """
    A = as_matrix("A", A, square=True)
    seen: dict[bytes, Array] = {}
    U_sub = []
    for Ci in banks:  # one staircase per distinct bank
        key = _key(Ci)
        if key not in seen:
            seen[key] = systems.unobservable_subspace(A, Ci)
        U_sub.append(seen[key])
    try:
        modes = real_invariant_subspaces(A)
    except ValidationError:
        V, S = intersection_basis(U_sub)
        construction = "intersections"
    else:
        V, S, _ = common_basis(modes, mode_pattern(modes, U_sub, banks))
        construction = "modes"
    ok, _ = check_assumption4(V, S, U_sub)
    return Basis(V, np.linalg.inv(V) if ok else None, S, U_sub, construction, ok)


def normalise_basis(V: Array, how: str = "unit") -> Array:
    """Scale the columns of a unit-norm basis of Assumption 4 (the paper fixes no scaling).

    Any scaling keeps Assumption 4 (membership of ``v_l`` in ``U_i`` does not depend on it), but
    the correction of (6) moves ``x_hat_i`` along ``kappa v_l``, so it changes offsets.

    Parameters
    ----------
    V : (n, n) array
        Unit-norm columns ``v_l`` (:func:`common_basis`).
    how : {"unit", "integer"}, default "unit"
        ``"unit"``: ``V`` as is; ``"integer"``: every column divided by its smallest nonzero
        ``|entry|`` (Section IV's ``[1,0,1,0,1,0]^T``, ``[0,1,0,1,0,1]^T`` for the rigid body).

    Returns
    -------
    (n, n) array
        The scaled basis.
    """
    V = as_matrix("V", V, square=True)
    if how == "unit":
        return V
    if how != "integer":
        raise ValidationError(f"how must be 'unit' or 'integer', found {how!r}")
    scale = [np.abs(col[np.abs(col) > 1e-9 * np.abs(col).max()]).min() for col in V.T]
    return V / np.array(scale)


def lyapunov_correction(V: Array, T: Array) -> tuple[Array, Array, Array, Array]:
    """The ``P`` of (11) from the real modal matrix and the correction directions of (11).

    ``P_bar = (W T)^{-T} (W T)^{-1}`` (``W = V^{-1}``), ``P = W^T P_bar W``, which satisfies
    ``P A + A^T P <= 0`` when ``A`` is Lyapunov stable with distinct eigenvalues and ``T`` is its
    real modal matrix (our choice: the paper does not give ``P``); (11) uses
    ``V_bar = V P_bar^{-1/2}`` and ``W_bar = P_bar^{1/2} W`` in the correction.

    Parameters
    ----------
    V : (n, n) array
        Basis of Assumption 4.
    T : (n, n) array
        Real modal matrix grouped like ``V`` (:func:`common_basis`).

    Returns
    -------
    P_bar, P, V_bar, W_bar : (n, n) arrays
    """
    V = as_matrix("V", V, square=True)
    T = as_matrix("T", T, V.shape)
    W = np.linalg.inv(V)
    wt_inv = np.linalg.inv(W @ T)
    p_bar = wt_inv.T @ wt_inv
    p_bar = 0.5 * (p_bar + p_bar.T)
    p_half = np.real(sla.sqrtm(p_bar))
    return p_bar, W.T @ p_bar @ W, np.linalg.solve(p_half.T, V.T).T, p_half @ W  # (11)


# ------------------------------------------------------------------ (5) and (6): the observers


def observer_gains(
    A: Array, V: Array, S: Array, banks: Sequence[Array], poles: str = "near"
) -> tuple[list[Array], list[Array]]:
    """Gains ``L_i`` of the partial observers (5) by pole placement (scipy's ``place_poles``, YT).

    ``F_i = W_i A V_i - L_i C_i V_i`` Hurwitz, with ``V_i`` the columns ``v_l`` and ``W_i`` the rows
    ``w_l^T`` of ``W = V^{-1}`` with ``s_i^l = 1``. Poles (the paper: "near -1"):
    ``"near"``: ``-1, -1.1, ...`` (first ``o_i``); ``"shifted"``: the imaginary parts of
    ``eig(W_i A V_i)`` kept with real parts ``-1``, real eigenvalues moved to ``-1, -1.1, ...``.

    Parameters
    ----------
    A : (n, n) array
        Continuous-time plant matrix of (1) [1/s].
    V : (n, n) array
        Basis of Assumption 4 (columns ``v_l``).
    S : (N, n) int array
        Indicators ``s_i^l``; ``o_i = sum_l s_i^l``.
    banks : sequence of N (m_i, n) arrays
        ``C_i`` of every bank.
    poles : {"near", "shifted"}, default "near"
        Pole rule (above); poles in [1/s].

    Returns
    -------
    gains : list of (o_i, m_i) arrays
    closed : list of (o_i, o_i) arrays
        ``F_i``.
    """
    from scipy.signal import place_poles  # python-control's place() calls it the same way

    W = np.linalg.inv(V)
    gains, closed = [], []
    seen: dict[bytes, tuple[Array, Array]] = {}
    for i, Ci in enumerate(banks):
        mask = S[i] == 1
        key = _key(Ci, mask)
        if key in seen:  # a bank already placed: the same gain (one placement per distinct bank)
            gains.append(seen[key][0].copy())
            closed.append(seen[key][1].copy())
            continue
        f_i, h_i = W[mask] @ A @ V[:, mask], Ci @ V[:, mask]
        o_i = int(mask.sum())
        if poles == "near":
            placed = -1.0 - 0.1 * np.arange(o_i)
        elif poles == "shifted":
            ev = np.linalg.eigvals(f_i)
            real = ev[np.abs(ev.imag) < 1e-9]
            cplx = ev[np.abs(ev.imag) >= 1e-9]
            placed = np.concatenate([-1.0 - 0.1 * np.arange(real.size), -1.0 + 1j * cplx.imag])
        else:
            raise ValidationError(f"poles must be 'near' or 'shifted', found {poles!r}")
        gain = place_poles(f_i.T, h_i.T, np.atleast_1d(placed), method="YT").gain_matrix.T
        gains.append(gain)
        closed.append(f_i - gain @ h_i)  # F_i of (5), Hurwitz
        seen[key] = (gain, closed[-1])
    return gains, closed


class NetworkSystem(NamedTuple):
    """Stacked system ``X' = M X + E_w w + E_s phi(R X)`` of (1), (5), (6) [or (11)].

    ``X = [x; z_1; ...; z_N; x_hat_1; ...; x_hat_N]`` has ``n_X = n + sum_i o_i + N n`` rows,
    ``w = [u; a_1; ...; a_N]`` (:func:`network_system`).

    Attributes
    ----------
    M : (n_X, n_X) array
        Linear part: ``A`` on ``x``; ``W_i A V_i - L_i C_i V_i`` and ``L_i C_i`` of (5);
        ``I_N kron A - kappa gamma (L kron I_n)`` of (6) [1/s].
    E_w : (n_X, 1 + N) array
        Input matrix of ``w``: ``B`` on ``x`` and every ``x_hat_i``, ``W_i B`` and the attack
        column ``L_i`` on ``z_i``.
    E_s : (n_X, N n) array
        ``kappa (I_N kron V)`` on the ``x_hat`` rows: how the sign terms enter (6)
        (``kappa (I_N kron v_corr)`` for (11)).
    R : (N n, n_X) array
        Sign arguments: row block ``i`` is ``W (V_i z_i - x_hat_i)`` (``w_corr`` for ``W`` in (11)).
    z_start : (N + 1,) int array
        ``z_i`` occupies rows ``z_start[i]:z_start[i + 1]`` of ``X``.
    xh0 : int
        First row of ``x_hat_1``; ``x_hat_i`` occupies ``xh0 + i n`` to ``xh0 + (i + 1) n``.
    """

    M: Array
    E_w: Array
    E_s: Array
    R: Array
    z_start: NDArray[np.intp]
    xh0: int


def network_system(
    A: Array,
    B: Array,
    banks: Sequence[Array],
    V: Array,
    S: Array,
    gains: Sequence[Array],
    kappa: float,
    gamma: float,
    laplacian: Array,
    v_corr: Array | None = None,
    w_corr: Array | None = None,
) -> NetworkSystem:
    """Matrices of the plant (1), the partial observers (5) and the median observer (6).

    ``X = [x; z_1; ...; z_N; x_hat_1; ...; x_hat_N]``, ``w = [u; a_1; ...; a_N]`` (one sensor per
    bank, as in the paper's example):

    * ``x' = A x + B u``;
    * (5) ``z_i' = W_i (A V_i z_i + B u) + L_i (C_i x + a_i - C_i V_i z_i)``;
    * (6) ``x_hat_i' = A x_hat_i + B u + kappa sum_l s_i^l sgn(w_l^T (V_i z_i - x_hat_i)) v_l
      + kappa gamma sum_j (x_hat_j - x_hat_i)``: the sign arguments are ``R X`` (row block ``i``:
      ``W (V_i z_i - x_hat_i)``), their images enter through ``E_s = kappa (I_N kron V)``, and
      ``phi = s (.) sgn`` (:func:`sign_correction`).

    Variant (11) is (6) with ``v_corr = V Pbar^{-1/2}`` and ``w_corr = Pbar^{1/2} W`` in the
    correction (valid when ``Pbar`` is block-diagonal over the indicator groups; ERRATA).

    Parameters
    ----------
    A : (n, n) array
        Plant matrix of (1) [1/s].
    B : (n,) array
        Input vector of (1) (one scalar input ``u``).
    banks : sequence of N (1, n) arrays
        ``C_i`` of every bank (one sensor per bank: ``a_i`` is scalar).
    V : (n, n) array
        Basis of Assumption 4 (columns ``v_l``); ``W = V^{-1}``.
    S : (N, n) int array
        Indicators ``s_i^l``.
    gains : sequence of N (o_i, 1) arrays
        Observer gains ``L_i`` of (5) (:func:`observer_gains`).
    kappa, gamma : float
        Positive gains of (6): the sign correction ``kappa`` and the coupling ``gamma``.
    laplacian : (N, N) array
        Graph Laplacian ``L`` (the consensus term ``kappa gamma sum_j (x_hat_j - x_hat_i)``).
    v_corr, w_corr : (n, n) arrays, optional
        The correction's directions and sign rows: default ``V`` and ``W`` (6); ``V Pbar^{-1/2}``
        and ``Pbar^{1/2} W`` for (11).

    Returns
    -------
    NetworkSystem
    """
    n = A.shape[0]
    N = len(banks)
    W = np.linalg.inv(V)
    v_corr = V if v_corr is None else v_corr
    w_corr = W if w_corr is None else w_corr
    masks = [S[i] == 1 for i in range(N)]
    V_i = [V[:, m] for m in masks]
    W_i = [W[m] for m in masks]
    o_i = np.array([int(m.sum()) for m in masks])
    z_start = n + np.r_[0, np.cumsum(o_i)]
    xh0 = n + int(o_i.sum())
    n_state = xh0 + N * n
    m_mat = np.zeros((n_state, n_state))
    e_w = np.zeros((n_state, 1 + N))
    r_mat = np.zeros((N * n, n_state))
    m_mat[:n, :n], e_w[:n, 0] = A, B
    for i in range(N):
        zi = slice(z_start[i], z_start[i + 1])
        m_mat[zi, zi] = W_i[i] @ A @ V_i[i] - gains[i] @ banks[i] @ V_i[i]  # (5)
        m_mat[zi, :n] = gains[i] @ banks[i]  # (5): L_i y_i, y_i = C_i x (+ a_i through e_w)
        e_w[zi, 0], e_w[zi, 1 + i] = W_i[i] @ B, gains[i][:, 0]
        rows = slice(i * n, (i + 1) * n)
        r_mat[rows, zi] = w_corr @ V_i[i]  # (6): w_l^T V_i z_i
        r_mat[rows, xh0 + i * n : xh0 + (i + 1) * n] = -w_corr  # (6): - w_l^T x_hat_i
    m_mat[xh0:, xh0:] = np.kron(np.eye(N), A) - kappa * gamma * np.kron(laplacian, np.eye(n))  # (6)
    e_w[xh0:, 0] = np.tile(B, N)
    e_s = np.zeros((n_state, N * n))
    e_s[xh0:] = kappa * np.kron(np.eye(N), v_corr)  # (6) [(11): v_corr = V Pbar^-1/2]
    return NetworkSystem(m_mat, e_w, e_s, r_mat, z_start, xh0)


def sign_correction(S: Array) -> Callable[[Array], Array]:
    """``phi(r) = s (.) sgn(r)``: the median correction of (6) / (11), ``sgn(0) = 0``.

    ``r`` stacks the agents' sign arguments, shape ``(N n,)`` or ``(N n, B)``.

    Parameters
    ----------
    S : (N, n) array of 0 / 1
        Indicators ``s_i^l``, flattened row by row like ``r``.

    Returns
    -------
    callable
        ``phi``, with ``phi(r)`` of the shape of ``r``.
    """
    s_flat = np.asarray(S, dtype=float).reshape(-1)

    def phi(r: Array) -> Array:
        return s_flat.reshape(-1, *([1] * (r.ndim - 1))) * np.sign(r)

    return phi


# ----------------------------------------------------------- the sampled-data reading (arena)


def substeps(
    kappa: float, V: Array, C: Array, r_std: Array, dt: float, fraction: float, finest: float
) -> int:
    """Sub-steps per sampling period: least ``m`` with ``kappa max||v_l|| dt / m <= fraction sigma``.

    ``sigma = min r_std / ||C row||``: the smallest sensor-noise standard deviation expressed as
    a displacement of the state along the measured direction. The exponential Euler scheme chatters
    on sliding surfaces with amplitude ``kappa ||v_l|| h`` (the notebook's integrator study). The
    sub-step is never finer than ``finest`` (``m <= ceil(dt / finest)``): nearly noise-free
    sensors would otherwise ask for an unbounded number of sub-steps.

    Parameters
    ----------
    kappa : float
        Gain of the sign correction of (6).
    V : (n, n) array
        Basis of Assumption 4 (columns ``v_l``).
    C : (N, m_i, n) array
        Every node's sensor rows.
    r_std : (N, m_i) array
        Their noise standard deviations (output units).
    dt : float
        Sampling period [s].
    fraction : float
        Chattering amplitude allowed, as a fraction of ``sigma`` (:data:`CHATTER_FRACTION`).
    finest : float
        Finest sub-step [s] (:data:`FINEST_SUBSTEP`).

    Returns
    -------
    int
        ``m >= 1``; the sub-step is ``h = dt / m``.
    """
    sigma = float(np.min(r_std / np.linalg.norm(C, axis=-1)))
    amplitude = kappa * float(np.linalg.norm(V, axis=0).max()) * dt
    m = int(np.ceil(amplitude / (fraction * sigma) - 1e-9))
    return max(1, min(m, int(np.ceil(dt / finest - 1e-9))))


class SampledObserver(NamedTuple):
    """Exponential-Euler matrices of (5) and (6) over one sub-step, every node at once.

    Node ``i``'s state is ``X_i = [zbar_i; xbar_i]`` with ``zbar_i = W V_i z_i`` (``z_i`` scattered
    into the positions ``s_i^l = 1``, zero elsewhere) and ``xbar_i = W x_hat_i``, so the sign
    arguments of (6) are ``zbar_i - xbar_i`` entrywise. Over a sub-step ``h``::

        X_i <- P_i X_i + G_i sgn(zbar_i - xbar_i) + Y_i y_i + H_i nb_i

    with ``nb_i = kappa gamma sum_j a_ij W x_hat_j^recv``. Index 0 / 1 of the first axis of the
    link-dependent arrays: links down (no coupling) / up. ``Abar = W A V``, ``Fbar_i`` is
    ``W_i A V_i - L_i C_i V_i`` of (5) scattered into the rows and columns ``s_i^l = 1``, ``d_i``
    the degree of node ``i`` and ``h = dt / substeps``.

    Attributes
    ----------
    V : (n, n) array
        Basis of Assumption 4 (columns ``v_l``).
    W : (n, n) array
        ``V^{-1}`` (rows ``w_l^T``).
    P : (2, N, 2n, 2n) array
        ``blockdiag(exp(Fbar_i h), exp(M_i h))``, ``M_i = Abar - kappa gamma d_i I``.
    G : (2, N, 2n, n) array
        ``[0; int_0^h exp(M_i s) ds diag(kappa s_i)]`` (the sign correction).
    Y : (N, 2n, m_i) array
        ``[int_0^h exp(Fbar_i s) ds Lbar_i; 0]`` (the held measurement).
    H : (2, N, 2n, n) array
        ``[0; int_0^h exp(M_i s) ds]`` (the held neighbour estimates; 0 when down).
    coupling : (N, N) array or scipy.sparse CSR array
        ``kappa gamma`` times the adjacency (CSR when :func:`sampled_observer` was given a
        sparse one: its ``E`` stored entries, receiver by receiver, are the edges of the
        per-edge messages of :func:`run_sampled`).
    substeps : int
        Sub-steps ``m`` per sampling period.
    """

    V: Array
    W: Array
    P: Array
    G: Array
    Y: Array
    H: Array
    coupling: Array
    substeps: int


def sampled_observer(
    A: Array,
    V: Array,
    S: Array,
    gains: Sequence[Array],
    C: Array,
    adj: Array,
    kappa: float,
    gamma: float,
    dt: float,
    m: int,
) -> SampledObserver:
    """Exponential-Euler matrices of (5) and (6) for the sub-step ``h = dt / m``.

    (5) is linear with the held measurement as input, so its sub-steps are exact; (6) is
    integrated by exponential Euler (the notebook's scheme: linear part exact, the sign held over
    each sub-step), with the neighbours' received estimates held over the sampling period.

    Parameters
    ----------
    A : (n, n) array
    V, S : basis and indicators of Assumption 4.
    gains : list of (o_i, m_i) arrays
        ``L_i`` of (5).
    C : (N, m_i, n) array
        Sensor rows of every node.
    adj : (N, N) array or scipy.sparse matrix
        Adjacency (``adj[i, j] = 1``: ``i`` receives from ``j``). Sparse: kept as CSR in
        :attr:`SampledObserver.coupling`, and :func:`run_sampled` takes per-edge messages.
    kappa, gamma : float
        Gains of (6).
    dt : float
        Sampling period.
    m : int
        Sub-steps per period.
    """
    m = check_positive_int("m", m)
    n = A.shape[0]
    N = len(gains)
    C = as_matrix("C", C, (N, None, n))
    adj = _adjacency(adj, N)
    ny = C.shape[1]
    h = dt / m
    W = np.linalg.inv(V)
    A_bar = W @ A @ V
    P = np.zeros((2, N, 2 * n, 2 * n))
    G = np.zeros((2, N, 2 * n, n))
    Y = np.zeros((N, 2 * n, ny))
    H = np.zeros((2, N, 2 * n, n))
    degree = np.asarray(adj.sum(axis=1)).ravel()
    seen: dict[bytes, int] = {}
    for i in range(N):
        mask = S[i] == 1
        key = _key(mask, gains[i], C[i], degree[i])
        if key in seen:  # a node like an earlier one: the same matrices
            j = seen[key]
            P[:, i], G[:, i], Y[i], H[:, i] = P[:, j], G[:, j], Y[j], H[:, j]
            continue
        seen[key] = i
        F_bar, L_bar = np.zeros((n, n)), np.zeros((n, ny))
        F_bar[np.ix_(mask, mask)] = A_bar[np.ix_(mask, mask)] - gains[i] @ C[i] @ V[:, mask]
        L_bar[mask] = gains[i]
        Pz, Y[i, :n] = systems.discretize_zoh(F_bar, L_bar, h)
        for up in (0, 1):
            M_i = A_bar - kappa * gamma * degree[i] * up * np.eye(n)
            Px, Gam = systems.discretize_zoh(M_i, np.eye(n), h)
            P[up, i, :n, :n], P[up, i, n:, n:] = Pz, Px
            G[up, i, n:] = Gam * (kappa * mask)
            H[up, i, n:] = up * Gam  # links down: no neighbour input
    return SampledObserver(V, W, P, G, Y, H, kappa * gamma * adj, m)


def _adjacency(adj: ArrayLike | sp.sparray, N: int) -> Array | sp.csr_array:
    """``adj`` checked (N, N): a dense array, or a canonical CSR array if given sparse."""
    if not sp.issparse(adj):
        return as_matrix("adj", adj, (N, N))
    out = sp.csr_array(adj, dtype=float)
    if out.shape != (N, N) or not np.all(np.isfinite(out.data)):
        raise ValidationError(f"adj must be a finite ({N}, {N}) matrix, found shape {out.shape}")
    out.sum_duplicates()
    out.sort_indices()
    return out


class SampledRun(NamedTuple):
    """What :func:`run_sampled` returns (every array: runs, K + 1, N, n; zero at ``k = 0``).

    Attributes
    ----------
    xhat : (runs, K + 1, N, n) array
        Resilient estimates ``x_hat_i(t_k)`` of (6) (state units).
    zbar : (runs, K + 1, N, n) array
        Partial estimates of (5), scattered: ``W V_i z_i(t_k)`` (zero where ``s_i^l = 0``).
    xbar : (runs, K + 1, N, n) array
        ``W x_hat_i(t_k)``; the identification residual is ``zbar - xbar`` on ``s_i^l = 1``.
    """

    xhat: Array
    zbar: Array
    xbar: Array


def run_sampled(
    obs: SampledObserver,
    y: Array,
    exchange: Callable[[int, Array], Array],
    link: NDArray[np.integer],
) -> SampledRun:
    """Run (5) and (6) on sampled measurements, every run and node at once.

    At ``t_k`` every node sends ``x_hat_i(t_k)``; ``exchange(k, x_hat)`` returns what every node
    receives: ``(runs, N, N, n)`` (``[r, i, j]`` from ``j`` to ``i``) or, with a sparse
    :attr:`SampledObserver.coupling`, ``(runs, E, n)`` per edge in the order of its stored
    entries (then a step costs ``O(E)``, not ``O(N^2)``). Over ``(t_k, t_{k+1}]`` node ``i``
    integrates (5) with ``y_{k+1}`` held and (6) with
    ``kappa gamma sum_j a_ij (x_hat_j^recv - x_hat_i(t))`` when ``link[r, k] = 1``, without the
    coupling term when it is 0. ``z_i(0) = 0`` and ``x_hat_i(0) = 0`` (the prior mean).

    Parameters
    ----------
    obs : SampledObserver
    y : (runs, K + 1, N, m_i) array
        Measurements (``y[:, 0]`` is not used: the first interval ends at ``t_1``).
    exchange : callable ``(k, x_hat) -> received``
        What every node receives at ``t_k`` (above).
    link : (runs, K + 1) array of 0 / 1
        State of every link over ``(t_k, t_{k+1}]``.

    Returns
    -------
    SampledRun
    """
    y = as_matrix("y", y, (None, None, obs.coupling.shape[0], obs.Y.shape[-1]))
    runs, K1, N, _ = y.shape
    n = obs.V.shape[0]
    link = np.asarray(link)
    if link.shape != (runs, K1):
        raise ValidationError(
            f"Incompatible dimensions of link: expected {(runs, K1)}, found {link.shape}"
        )
    X = np.zeros((N, 2 * n, runs))
    out = np.zeros((3, runs, K1, N, n))
    for k in range(K1 - 1):
        nb = _neighbour_input(obs, exchange(k, out[0, :, k]))
        held_y = obs.Y @ np.transpose(y[:, k + 1], (1, 2, 0))
        for up in np.unique(link[:, k]):
            sel = link[:, k] == up
            X[:, :, sel] = _interval(X[:, :, sel], obs.P[up], obs.G[up], held_y[:, :, sel]
                                     + obs.H[up] @ nb[:, :, sel], obs.substeps)
        out[0, :, k + 1] = np.einsum("nl,ilr->rin", obs.V, X[:, n:])
        out[1, :, k + 1] = np.transpose(X[:, :n], (2, 0, 1))
        out[2, :, k + 1] = np.transpose(X[:, n:], (2, 0, 1))
    return SampledRun(*out)


def _neighbour_input(obs: SampledObserver, recv: Array) -> Array:
    """``nb_i = kappa gamma sum_j a_ij W x_hat_j^recv`` as (N, n, runs), dense or per edge."""
    if not sp.issparse(obs.coupling):
        return np.einsum("ij,rijn,ln->ilr", obs.coupling, recv, obs.W)
    c = obs.coupling
    runs, n = recv.shape[0], recv.shape[-1]
    if recv.shape[1:] != (c.nnz, n):
        raise ValidationError(f"exchange: expected per-edge messages of shape {(runs, c.nnz, n)}, "
                              f"found {recv.shape}")
    per_node = sp.csr_array((c.data, np.arange(c.nnz), c.indptr), shape=(c.shape[0], c.nnz))
    summed = per_node @ np.transpose(recv, (1, 0, 2)).reshape(c.nnz, -1)  # (N, runs n)
    return np.einsum("irn,ln->ilr", summed.reshape(-1, runs, n), obs.W)


def _interval(X: Array, P: Array, G: Array, held: Array, m: int) -> Array:
    """``m`` exponential-Euler sub-steps of (5) and (6) (nodes batched, runs as columns)."""
    n = G.shape[-1]
    for _ in range(m):
        X = P @ X + G @ np.sign(X[:, :n] - X[:, n:]) + held
    return X


def alarm_rule(
    A: Array,
    V: Array,
    S: Array,
    gains: Sequence[Array],
    C: Array,
    R: Array,
    Q_w: Array,
    x0_std: float,
    kappa: float,
    dt: float,
    horizon: int,
    alpha: float,
) -> tuple[Array, NDArray[np.intp]]:
    """Thresholds and first alarm step of the identification test (Conclusion; rule ours).

    The partial observer's error ``e_i = z_i - W_i x`` at the sampling instants is propagated as
    ``e_k = Phi e_{k-1} + Psi v_k - (I - Psi C_i V_i) W_i w_{k-1}`` with ``Phi = exp(F_i dt)`` and
    ``Psi = int_0^dt exp(F_i s) ds L_i``; its stationary covariance ``Sigma_i`` (discrete Lyapunov
    equation) gives the threshold ``2 z_{1 - alpha / (2 o_i)} sqrt(Sigma_i[l, l])`` per coordinate.
    Alarms start at the first step from which the 3-sigma transient of ``Phi^k e_0``
    (``e_0 = -W_i x_0``, prior ``x0_std^2 I``) stays below the thresholds, and not before the sign
    correction, at rate ``kappa``, can cross a 3-sigma prior error ``3 x0_std max ||w_l||``.

    Parameters
    ----------
    A : (n, n) array
        Continuous-time plant matrix of (1) [1/s].
    V : (n, n) array
        Basis of Assumption 4 (columns ``v_l``).
    S : (N, n) int array
        Indicators ``s_i^l``; ``o_i = sum_l s_i^l``.
    gains : sequence of N (o_i, m_i) arrays
        Observer gains ``L_i`` of (5).
    C : (N, m_i, n) array
        Sensor rows ``C_i`` of every node.
    R : (N, m_i, m_i) array
        Covariance of the sampled measurement noise ``v_k`` of every node.
    Q_w : (n, n) array
        Covariance of the sampled process noise ``w_k`` (per sampling period).
    x0_std : float
        Prior standard deviation of every state component (state units).
    kappa : float
        Gain of the sign correction of (6).
    dt : float
        Sampling period [s].
    horizon : int
        Number of steps ``K``.
    alpha : float
        False-alarm level per node and step, in (0, 1), split over the ``o_i`` coordinates
        (two-sided Bonferroni).

    Returns
    -------
    tau : (N, n) array
        Thresholds on ``|zbar_i - xbar_i|`` (``inf`` where ``s_i^l = 0``).
    first : (N,) int array
        First step at which node ``i`` may raise an alarm (``horizon + 1``: never).
    """
    n = A.shape[0]
    N = C.shape[0]
    W = np.linalg.inv(V)
    tau = np.full((N, n), np.inf)
    first = np.empty(N, dtype=np.intp)
    slew = int(np.ceil(3.0 * x0_std * np.linalg.norm(W, axis=1).max() / kappa / dt - 1e-9))
    seen: dict[bytes, int] = {}
    for i in range(N):
        mask = S[i] == 1
        key = _key(mask, gains[i], C[i], R[i])
        if key in seen:  # a node like an earlier one: the same rule
            tau[i], first[i] = tau[seen[key]], first[seen[key]]
            continue
        seen[key] = i
        W_i, V_i = W[mask], V[:, mask]
        F = W_i @ A @ V_i - gains[i] @ C[i] @ V_i
        Phi, Psi = systems.discretize_zoh(F, gains[i], dt)
        G = (np.eye(int(mask.sum())) - Psi @ C[i] @ V_i) @ W_i
        Sigma = sla.solve_discrete_lyapunov(Phi, Psi @ R[i] @ Psi.T + G @ Q_w @ G.T)
        z = stats.norm.ppf(1.0 - alpha / (2 * mask.sum()))
        tau[i, mask] = 2.0 * z * np.sqrt(np.diag(Sigma))
        P, below = x0_std**2 * W_i @ W_i.T, np.empty(horizon + 1, dtype=bool)
        for k in range(horizon + 1):
            below[k] = np.all(3.0 * np.sqrt(np.diag(P)) <= tau[i, mask])
            P = Phi @ P @ Phi.T
        above = np.flatnonzero(~below)
        first[i] = max(slew, above[-1] + 1 if above.size else 0)
    return tau, first
