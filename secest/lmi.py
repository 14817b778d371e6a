"""Linear matrix inequalities with cvxpy: symmetric assembly, certified solves.

Helpers for the recursive-LMI designs of the reproductions (ma2021 first):

``block_symmetric``   assemble a symmetric block matrix from its lower triangle
``block_diag``        block-diagonal matrix of cvxpy expressions / arrays
``symmetrize``        ``(M + M^T) / 2`` for expressions and arrays
``lmi``               the constraint ``sym(M) << -eps I`` (negative semidefinite form)
``solve_certified``   solve (CLARABEL), check ``prob.status``, certify every LMI with
                      numpy eigenvalues, fall back to SCS *visibly* (warning + report)
``InfeasibleLMIError`` raised when no solver returns a certified solution; its
                      message names the step and the node (or link) of the problem.

cvxpy's ``M << 0`` silently constrains the symmetric part of a non-symmetric
expression (and ``cp.bmat`` with transposed blocks is not recognised as
symmetric), so every LMI here is built from its lower triangle and passed
through :func:`symmetrize` before the ``<<``.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import cvxpy as cp
import numpy as np

from secest.validation import ValidationError

__all__ = [
    "InfeasibleLMIError",
    "LMISolveReport",
    "block_diag",
    "block_symmetric",
    "lmi",
    "max_eigenvalue",
    "solve_certified",
    "symmetrize",
]

Block = Any  # cvxpy expression, numpy array, scalar, or None (zero block)

_OK_STATUSES = (cp.OPTIMAL,)


class InfeasibleLMIError(RuntimeError):
    """No solver returned a certified solution of an LMI problem.

    Attributes
    ----------
    step : int or None
        Time step of the recursive design at which the problem failed.
    node : str or int or None
        Node (or link, or "all nodes") whose LMI failed.
    statuses : dict
        Solver name -> cvxpy status (or exception text) of every attempt.
    """

    def __init__(
        self,
        message: str,
        *,
        step: int | None = None,
        node: str | int | None = None,
        statuses: Mapping[str, str] | None = None,
    ) -> None:
        super().__init__(message)
        self.step = step
        self.node = node
        self.statuses = dict(statuses or {})


@dataclass
class LMISolveReport:
    """Outcome of :func:`solve_certified` (deterministic content only, no timings).

    Attributes
    ----------
    step, node : identification of the problem (as passed in).
    solver : str
        Solver whose solution was accepted.
    fallback : bool
        True if the primary solver failed and the fallback solver was used.
    status : str
        cvxpy status of the accepted solve.
    objective : float
        Optimal value.
    iterations : int or None
        Solver iterations reported by cvxpy.
    max_eig : dict
        LMI name -> largest eigenvalue of the symmetrised matrix ``M`` at the solution
        (the certificate: the LMI ``M <= 0`` holds to ``tol`` iff ``max_eig <= tol``).
    asymmetry : dict
        LMI name -> ``max|M - M^T|`` of the numerical value (0 for correctly built blocks).
    residual : dict
        LMI name -> primal residual ``max(0, max_eig + eps)``: violation of the
        constraint ``M <= -eps I`` the solver was given (``eps`` as passed in).
    attempts : dict
        Solver name -> status of every attempt, in order.
    """

    step: int | None
    node: str | int | None
    solver: str
    fallback: bool
    status: str
    objective: float
    iterations: int | None
    max_eig: dict[str, float] = field(default_factory=dict)
    asymmetry: dict[str, float] = field(default_factory=dict)
    residual: dict[str, float] = field(default_factory=dict)
    attempts: dict[str, str] = field(default_factory=dict)

    @property
    def worst_eig(self) -> float:
        """Largest ``max_eig`` over all LMIs of the problem."""
        return max(self.max_eig.values()) if self.max_eig else float("-inf")


def _is_expr(x: Any) -> bool:
    return isinstance(x, cp.Expression)


def _shape2(x: Block) -> tuple[int, int]:
    if _is_expr(x):
        shp = x.shape
    else:
        shp = np.shape(x)
    if len(shp) == 0:
        return (1, 1)
    if len(shp) == 1:
        return (shp[0], 1)
    if len(shp) != 2:
        raise ValidationError(f"Block must be at most 2-D, found shape {tuple(shp)}")
    return (int(shp[0]), int(shp[1]))


def _as2d(x: Block) -> Any:
    if _is_expr(x):
        if x.ndim == 2:
            return x
        return cp.reshape(x, _shape2(x), order="F")
    return np.asarray(x, dtype=float).reshape(_shape2(x))


def _transpose(x: Any) -> Any:
    return x.T


def symmetrize(m: Any) -> Any:
    """Return ``(m + m^T) / 2`` for a square cvxpy expression or array.

    Parameters
    ----------
    m : cvxpy.Expression or array_like
        Square matrix.

    Returns
    -------
    cvxpy.Expression or ndarray
        The symmetric part of ``m``.

    Raises
    ------
    ValidationError
        If ``m`` is not square.
    """
    r, c = _shape2(m)
    if r != c:
        raise ValidationError(f"m must be a square matrix, found shape ({r}, {c})")
    m2 = _as2d(m)
    return 0.5 * (m2 + m2.T)


def block_diag(blocks: Sequence[Block]) -> Any:
    """Block-diagonal matrix of cvxpy expressions and/or arrays.

    Parameters
    ----------
    blocks : sequence
        Square or rectangular blocks (scalars are 1x1). ``None`` is not allowed
        because the size of a zero block would be unknown.

    Returns
    -------
    cvxpy.Expression or ndarray
        ``diag{blocks}``; a numpy array when no block is a cvxpy expression.
    """
    if len(blocks) == 0:
        raise ValidationError("blocks must contain at least one block, found 0")
    shapes = []
    for k, b in enumerate(blocks):
        if b is None:
            raise ValidationError(f"blocks[{k}] is None: give an explicit zero array")
        shapes.append(_shape2(b))
    rows: list[list[Any]] = []
    for i, bi in enumerate(blocks):
        row = []
        for j, (_rows_j, cj) in enumerate(shapes):
            if i == j:
                row.append(_as2d(bi))
            else:
                row.append(np.zeros((shapes[i][0], cj)))
        rows.append(row)
    if not any(_is_expr(b) for b in blocks):
        return np.block(rows)
    return cp.bmat(rows)


def block_symmetric(lower: Sequence[Sequence[Block]], sizes: Sequence[int] | None = None) -> Any:
    """Assemble a symmetric block matrix from its lower triangle.

    ``lower[r][c]`` for ``c <= r`` is block (r, c); the upper blocks are filled with
    transposes, ``None`` is a zero block. Entries with ``c > r`` must be absent or
    ``None``. The diagonal blocks must be symmetric (they are symmetrised anyway when
    the result is passed through :func:`lmi`).

    Parameters
    ----------
    lower : sequence of sequences
        Row ``r`` holds ``r + 1`` blocks (or more, all ``None`` beyond the diagonal).
    sizes : sequence of int, optional
        Block sizes; needed only when a diagonal block is ``None``.

    Returns
    -------
    cvxpy.Expression or ndarray
        The full symmetric matrix (``cp.bmat`` when any block is an expression).

    Raises
    ------
    ValidationError
        If a diagonal block is not square, block dimensions disagree, or a size
        cannot be inferred.
    """
    nb = len(lower)
    if nb == 0:
        raise ValidationError("lower must contain at least one block row, found 0")
    for r, row in enumerate(lower):
        if len(row) < r + 1:
            raise ValidationError(
                f"lower[{r}] must hold {r + 1} blocks (lower triangle), found {len(row)}"
            )
        for c in range(r + 1, len(row)):
            if row[c] is not None:
                raise ValidationError(f"lower[{r}][{c}] lies above the diagonal: pass None")
    dims: list[int | None] = list(sizes) if sizes is not None else [None] * nb
    if len(dims) != nb:
        raise ValidationError(f"sizes must have {nb} entries, found {len(dims)}")
    for r in range(nb):
        d = lower[r][r]
        if d is not None:
            a, b = _shape2(d)
            if a != b:
                raise ValidationError(f"Diagonal block lower[{r}][{r}] must be square, found ({a}, {b})")
            if dims[r] is not None and dims[r] != a:
                raise ValidationError(
                    f"Incompatible dimensions of lower[{r}][{r}]: expected ({dims[r]}, {dims[r]}), "
                    f"found ({a}, {b})"
                )
            dims[r] = a
    for r in range(nb):
        for c in range(r):
            blk = lower[r][c]
            if blk is None:
                continue
            a, b = _shape2(blk)
            for idx, val in ((r, a), (c, b)):
                if dims[idx] is None:
                    dims[idx] = val
            if (a, b) != (dims[r], dims[c]):
                raise ValidationError(
                    f"Incompatible dimensions of lower[{r}][{c}]: expected ({dims[r]}, {dims[c]}), "
                    f"found ({a}, {b})"
                )
    if any(d is None for d in dims):
        missing = [k for k, d in enumerate(dims) if d is None]
        raise ValidationError(f"sizes: cannot infer the size of block(s) {missing}; pass sizes")
    n = [int(d) for d in dims]  # type: ignore[arg-type]
    rows: list[list[Any]] = []
    any_expr = False
    for r in range(nb):
        row = []
        for c in range(nb):
            blk = lower[r][c] if c <= r else lower[c][r]
            if blk is None:
                row.append(np.zeros((n[r], n[c])))
                continue
            any_expr = any_expr or _is_expr(blk)
            b2 = _as2d(blk)
            row.append(b2 if c <= r else _transpose(b2))
        rows.append(row)
    if not any_expr:
        return np.block(rows)
    return cp.bmat(rows)


def lmi(m: Any, eps: float = 0.0) -> cp.Constraint:
    """The constraint ``sym(m) << -eps I`` (``m`` negative semidefinite with margin).

    Parameters
    ----------
    m : cvxpy.Expression
        Square matrix expression, built symmetric (e.g. with :func:`block_symmetric`).
    eps : float, default 0
        Strictness margin; a strict inequality ``m < 0`` is imposed as ``m <= -eps I``.

    Returns
    -------
    cvxpy.Constraint
    """
    if eps < 0 or not np.isfinite(eps):
        raise ValidationError(f"eps must be a finite number >= 0, found {eps}")
    r, _ = _shape2(m)
    return symmetrize(m) << -eps * np.eye(r)


def max_eigenvalue(m: Any) -> float:
    """Largest eigenvalue of the symmetric part of a numeric matrix (``numpy.linalg.eigvalsh``)."""
    a = np.asarray(m, dtype=float)
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ValidationError(f"m must be a square matrix, found shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValidationError("m contains NaN or infinite entries")
    return float(np.linalg.eigvalsh(0.5 * (a + a.T))[-1])


def _certify(lmis: Mapping[str, Any]) -> tuple[dict[str, float], dict[str, float]]:
    eigs: dict[str, float] = {}
    asym: dict[str, float] = {}
    for name, expr in lmis.items():
        val = expr.value
        if val is None:
            eigs[name] = float("inf")
            asym[name] = float("inf")
            continue
        a = np.asarray(val, dtype=float)
        if not np.all(np.isfinite(a)):
            eigs[name] = float("inf")
            asym[name] = float("inf")
            continue
        asym[name] = float(np.max(np.abs(a - a.T)))
        eigs[name] = max_eigenvalue(a)
    return eigs, asym


def solve_certified(
    problem: cp.Problem,
    lmis: Mapping[str, Any],
    *,
    step: int | None = None,
    node: str | int | None = None,
    solver: str = "CLARABEL",
    fallback: str | None = "SCS",
    tol: float = 1e-8,
    eps: float = 0.0,
    solver_opts: Mapping[str, Any] | None = None,
    fallback_opts: Mapping[str, Any] | None = None,
) -> LMISolveReport:
    """Solve an LMI problem, check its status and certify every LMI numerically.

    The primary solver's solution is accepted only if ``problem.status`` is
    ``optimal`` (``optimal_inaccurate`` does not pass) and every LMI matrix ``M``
    in ``lmis`` has ``max eig(sym(M)) <= tol`` at the solution (numpy eigenvalues).
    Otherwise a :class:`UserWarning` is issued (never silent) and the fallback
    solver is tried under the same rules.

    Parameters
    ----------
    problem : cvxpy.Problem
        The (DPP, parameterised) problem, with current parameter values set.
    lmis : mapping of str to cvxpy.Expression
        Name -> matrix expression ``M`` of each constraint ``M <= 0`` to certify
        (the *unsymmetrised* block matrix as built; it is symmetrised for the check).
    step, node : optional
        Identification used in the report, the warning and the error message.
    solver, fallback : str
        cvxpy solver names; ``fallback=None`` disables the fallback.
    tol : float, default 1e-8
        Certification tolerance on the largest eigenvalue.
    eps : float, default 0
        Margin the LMIs were built with (``M <= -eps I``), used for the residuals.
    solver_opts, fallback_opts : mapping, optional
        Keyword options passed to ``problem.solve``.

    Returns
    -------
    LMISolveReport

    Raises
    ------
    InfeasibleLMIError
        If no solver returns an optimal, certified solution; the message names the
        step, the node and every solver's status.
    """
    if tol < 0 or not np.isfinite(tol):
        raise ValidationError(f"tol must be a finite number >= 0, found {tol}")
    if eps < 0 or not np.isfinite(eps):
        raise ValidationError(f"eps must be a finite number >= 0, found {eps}")
    if not lmis:
        raise ValidationError("lmis must name at least one LMI matrix to certify, found 0")
    where = f"step {step}, node {node}"
    attempts: dict[str, str] = {}
    order = [(solver, dict(solver_opts or {}))]
    if fallback is not None:
        order.append((fallback, dict(fallback_opts or {})))
    for n_try, (name, opts) in enumerate(order):
        try:
            problem.solve(solver=name, **opts)
            status = str(problem.status)
        except cp.error.SolverError as exc:  # numerical failure inside the solver
            status = f"solver_error: {exc}"
        eigs, asym = ({}, {})
        certified = False
        if status in _OK_STATUSES:
            eigs, asym = _certify(lmis)
            certified = all(e <= tol for e in eigs.values())
            if not certified:
                worst = max(eigs, key=eigs.get)  # type: ignore[arg-type]
                status = f"{status} but not certified ({worst}: max eig {eigs[worst]:.3e} > {tol:g})"
        attempts[name] = status
        if certified:
            stats = problem.solver_stats
            return LMISolveReport(
                step=step,
                node=node,
                solver=name,
                fallback=n_try > 0,
                status=str(problem.status),
                objective=float(problem.value),
                iterations=None if stats is None else stats.num_iters,
                max_eig=eigs,
                asymmetry=asym,
                residual={k: max(0.0, v + eps) for k, v in eigs.items()},
                attempts=attempts,
            )
        if n_try + 1 < len(order):
            warnings.warn(
                f"LMI solve failed with {name} at {where} ({status}); "
                f"falling back to {order[n_try + 1][0]}",
                UserWarning,
                stacklevel=2,
            )
    detail = "; ".join(f"{k}: {v}" for k, v in attempts.items())
    raise InfeasibleLMIError(
        f"LMI infeasible or not certified at {where} ({detail})",
        step=step,
        node=node,
        statuses=attempts,
    )
