"""Linear matrix inequalities with cvxpy: symmetric assembly, certified solves.

Helpers for the recursive-LMI designs of the reproductions (ma2021 first):

``block_symmetric``
   assemble a symmetric block matrix from its lower triangle
``block_diag``
   block-diagonal matrix of cvxpy expressions / arrays
``symmetrize``
   ``(M + M^T) / 2`` for expressions and arrays
``lmi``
   the constraint ``sym(M) << -eps I`` (negative semidefinite form)
``solve_certified``
   solve (CLARABEL), check ``prob.status``, certify every LMI with numpy eigenvalues,
   fall back to SCS *visibly* (warning + report)
``InfeasibleLMIError``, ``UnboundedLMIError``
   raised when no solver returns a certified solution (infeasible, inaccurate or not
   certified), respectively when a solver reports the problem unbounded (and none
   reports it infeasible). Both are ``LMISolveError``; the message names the step and
   the node (or link) of the problem.

What a certificate means: an LMI ``M < 0`` is imposed as ``M <= -eps I`` (:func:`lmi`).
With ``certify="margin"`` (default) a solution is accepted only if every LMI satisfies the
constraint the solver was given, up to ``tol``: ``max eig sym(M) <= -eps + tol``. With
``certify="strict"`` it is accepted if the strict inequality holds beyond ``tol``,
``max eig sym(M) <= -tol``, even where the solver used up part of the margin ``eps``
(interior-point solvers meet ``eps`` only to their own tolerance).

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

from secest.core import validation as V
from secest.core.validation import ValidationError

__all__ = [
    "InfeasibleLMIError",
    "LMISolveError",
    "LMISolveReport",
    "UnboundedLMIError",
    "block_diag",
    "block_symmetric",
    "lmi",
    "max_eigenvalue",
    "solve_certified",
    "symmetrize",
]

Block = Any  # cvxpy expression, numpy array, scalar, or None (zero block)

_INFEASIBLE = (cp.INFEASIBLE, cp.INFEASIBLE_INACCURATE)
_UNBOUNDED = (cp.UNBOUNDED, cp.UNBOUNDED_INACCURATE)
_CERTIFY = ("margin", "strict")


class LMISolveError(RuntimeError):
    """No solver returned a certified solution of an LMI problem.

    Parameters
    ----------
    message : str
        One-line description naming the step, the node and every solver's status.
    step : int, optional
        Time step of the recursive design at which the problem failed.
    node : str or int, optional
        Node (or link, or "all nodes") whose LMI failed.
    statuses : mapping of str to str, optional
        Solver name -> cvxpy status (or exception text) of every attempt.
    outcomes : mapping of str to str, optional
        Solver name -> ``"infeasible"``, ``"unbounded"``, ``"inaccurate"``,
        ``"not certified"`` or ``"solver error"``.

    Attributes
    ----------
    step, node, statuses, outcomes
        As passed (``statuses`` and ``outcomes`` as dicts).
    """

    def __init__(
        self,
        message: str,
        *,
        step: int | None = None,
        node: str | int | None = None,
        statuses: Mapping[str, str] | None = None,
        outcomes: Mapping[str, str] | None = None,
    ) -> None:
        super().__init__(message)
        self.step = step
        self.node = node
        self.statuses = dict(statuses or {})
        self.outcomes = dict(outcomes or {})


class InfeasibleLMIError(LMISolveError):
    """The LMIs are infeasible, or no solver returned an accurate, certified solution.

    Parameters
    ----------
    message, step, node, statuses, outcomes
        As in :class:`LMISolveError` (and so are the attributes).
    """


class UnboundedLMIError(LMISolveError):
    """A solver reported the problem unbounded (the LMIs are feasible; the objective is not bounded).

    Parameters
    ----------
    message, step, node, statuses, outcomes
        As in :class:`LMISolveError` (and so are the attributes).
    """


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
    certify : str
        ``"margin"`` or ``"strict"``, see :func:`solve_certified`.
    eps, tol : float
        The margin the LMIs were built with and the certification tolerance.
    bound : float
        The certificate: every ``max_eig`` is at most ``bound`` (``-eps + tol`` or ``-tol``).
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
    certify: str = "margin"
    eps: float = 0.0
    tol: float = 0.0
    bound: float = 0.0

    @property
    def worst_eig(self) -> float:
        """Largest ``max_eig`` over all LMIs of the problem."""
        return max(self.max_eig.values()) if self.max_eig else float("-inf")


def _is_expr(x: Any) -> bool:
    return isinstance(x, cp.Expression)


def _shape2(x: Block, name: str = "m") -> tuple[int, int]:
    if _is_expr(x):
        shp = x.shape
    else:
        shp = V.as_matrix(name, x).shape
    if len(shp) == 0:
        return (1, 1)
    if len(shp) == 1:
        return (shp[0], 1)
    if len(shp) != 2:
        raise ValidationError(f"{name} must be at most 2-D, found shape {tuple(shp)}")
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


def _blocks(name: str, value: object) -> list:
    if isinstance(value, str | bytes | np.ndarray) or _is_expr(value) or not hasattr(value, "__len__"):
        raise ValidationError(f"{name} must be a list of blocks, found {type(value).__name__}")
    return list(value)


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
    blocks = _blocks("blocks", blocks)
    if len(blocks) == 0:
        raise ValidationError("blocks must contain at least one block, found 0")
    shapes = []
    for k, b in enumerate(blocks):
        if b is None:
            raise ValidationError(f"blocks[{k}] is None: give an explicit zero array")
        shapes.append(_shape2(b, f"blocks[{k}]"))
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
    lower = [_blocks(f"lower[{r}]", row) for r, row in enumerate(_blocks("lower", lower))]
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
    dims: list[int | None] = [None] * nb
    if sizes is not None:
        dims = [V.check_int(f"sizes[{k}]", d, minimum=1) for k, d in enumerate(_blocks("sizes", sizes))]
    if len(dims) != nb:
        raise ValidationError(f"sizes must have {nb} entries, found {len(dims)}")
    for r in range(nb):
        d = lower[r][r]
        if d is not None:
            a, b = _shape2(d, f"lower[{r}][{r}]")
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
            a, b = _shape2(blk, f"lower[{r}][{c}]")
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
    eps = _check_nonneg("eps", eps)
    if not _is_expr(m):
        raise ValidationError(f"m must be a cvxpy expression, found {type(m).__name__}")
    r, _ = _shape2(m)
    return symmetrize(m) << -eps * np.eye(r)


def _check_nonneg(name: str, value: float) -> float:
    try:
        return V.check_real(name, value, lower=0.0)
    except ValidationError as exc:
        raise ValidationError(f"{name} must be a finite number >= 0, found {value!r}") from exc


def max_eigenvalue(m: Any) -> float:
    """Largest eigenvalue of the symmetric part of a numeric matrix (``numpy.linalg.eigvalsh``).

    Parameters
    ----------
    m : (n, n) array_like
        Finite, non-empty square matrix.

    Returns
    -------
    float
    """
    a = V.as_matrix("m", m, square=True)
    return float(np.linalg.eigvalsh(0.5 * (a + a.T))[-1])


def _certify(lmis: Mapping[str, Any]) -> tuple[dict[str, float], dict[str, float]]:
    eigs: dict[str, float] = {}
    asym: dict[str, float] = {}
    for name, expr in lmis.items():
        a = np.asarray(expr.value if expr.value is not None else np.nan, dtype=float)
        if a.ndim != 2 or not np.all(np.isfinite(a)):
            eigs[name] = asym[name] = float("inf")
            continue
        asym[name] = float(np.max(np.abs(a - a.T)))
        eigs[name] = max_eigenvalue(a)
    return eigs, asym


def _attempt(
    problem: cp.Problem, lmis: Mapping[str, Any], solver: str, opts: dict, bound: float
) -> tuple[str, str, dict[str, float], dict[str, float]]:
    """Solve once: (outcome, status text, max eigenvalues, asymmetries)."""
    try:
        problem.solve(solver=solver, **opts)
    except cp.error.SolverError as exc:  # numerical failure inside the solver
        return "solver error", f"solver_error: {exc}", {}, {}
    status = str(problem.status)
    if status in _INFEASIBLE:
        return "infeasible", status, {}, {}
    if status in _UNBOUNDED:
        return "unbounded", status, {}, {}
    if status != cp.OPTIMAL:
        return "inaccurate", status, {}, {}
    eigs, asym = _certify(lmis)
    worst = max(eigs, key=eigs.get)  # type: ignore[arg-type]
    if eigs[worst] > bound:
        text = f"{status} but not certified ({worst}: max eig {eigs[worst]:.3e} > {bound:.3g})"
        return "not certified", text, eigs, asym
    return "certified", status, eigs, asym


def _check_solve_args(problem, lmis, solver, fallback, certify, step, node, opts) -> None:
    if not isinstance(problem, cp.Problem):
        raise ValidationError(f"problem must be a cvxpy Problem, found {type(problem).__name__}")
    if not isinstance(lmis, Mapping) or not lmis:
        raise ValidationError("lmis must name at least one LMI matrix to certify, found 0")
    for name, expr in lmis.items():
        square = _is_expr(expr) and expr.ndim == 2 and expr.shape[0] == expr.shape[1]
        if not (isinstance(name, str) and square):
            raise ValidationError(f"lmis must map names to square cvxpy expressions, found {name!r}")
    installed = cp.installed_solvers()
    for arg, value in (("solver", solver), ("fallback", fallback)):
        if (value is not None or arg == "solver") and value not in installed:
            raise ValidationError(f"{arg} must be an installed solver {installed}, found {value!r}")
    V.check_choice("certify", certify, _CERTIFY)
    if step is not None:
        V.check_int("step", step)
    if node is not None and (isinstance(node, bool) or not isinstance(node, str | int | np.integer)):
        raise ValidationError(f"node must be a string, an integer or None, found {node!r}")
    for arg, value in opts.items():
        if value is not None and not isinstance(value, Mapping):
            raise ValidationError(f"{arg} must be a mapping of options, found {type(value).__name__}")


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
    certify: str = "margin",
    solver_opts: Mapping[str, Any] | None = None,
    fallback_opts: Mapping[str, Any] | None = None,
) -> LMISolveReport:
    """Solve an LMI problem, check its status and certify every LMI numerically.

    The primary solver's solution is accepted only if ``problem.status`` is
    ``optimal`` (``optimal_inaccurate`` does not pass) and every LMI matrix ``M``
    in ``lmis`` satisfies the certificate (numpy eigenvalues of ``sym(M)``):

    * ``certify="margin"``: ``max eig <= -eps + tol``, the constraint ``M <= -eps I`` the
      solver was given, up to ``tol``;
    * ``certify="strict"``: ``max eig <= -tol``, the strict LMI ``M < 0`` beyond ``tol``.

    Otherwise a :class:`UserWarning` is issued (never silent) and the fallback
    solver is tried under the same rules.

    Parameters
    ----------
    problem : cvxpy.Problem
        The (DPP, parameterised) problem, with current parameter values set.
    lmis : mapping of str to cvxpy.Expression
        Name -> square matrix expression ``M`` of each constraint ``M <= -eps I`` to certify
        (the *unsymmetrised* block matrix as built; it is symmetrised for the check).
    step, node : optional
        Identification used in the report, the warning and the error message.
    solver : str, default "CLARABEL"
        cvxpy name of an installed solver.
    fallback : str or None, default "SCS"
        Solver tried next; ``None`` disables the fallback.
    tol : float, default 1e-8
        Certification tolerance on the largest eigenvalue, ``>= 0``.
    eps : float, default 0
        Margin the LMIs were built with (``M <= -eps I``, see :func:`lmi`), ``>= 0``.
    certify : {"margin", "strict"}, default "margin"
        Which statement the certificate makes (see above and the module docstring).
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
    UnboundedLMIError
        If a solver reports the problem unbounded and none reports it infeasible.
    """
    tol = _check_nonneg("tol", tol)
    eps = _check_nonneg("eps", eps)
    _check_solve_args(problem, lmis, solver, fallback, certify, step, node,
                      {"solver_opts": solver_opts, "fallback_opts": fallback_opts})
    bound = -eps + tol if certify == "margin" else -tol
    where = f"step {step}, node {node}"
    attempts: dict[str, str] = {}
    outcomes: dict[str, str] = {}
    order = [(solver, dict(solver_opts or {}))]
    if fallback is not None:
        order.append((fallback, dict(fallback_opts or {})))
    for n_try, (name, opts) in enumerate(order):
        outcome, attempts[name], eigs, asym = _attempt(problem, lmis, name, opts, bound)
        outcomes[name] = outcome
        if outcome == "certified":
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
                certify=certify,
                eps=eps,
                tol=tol,
                bound=bound,
            )
        if n_try + 1 < len(order):
            warnings.warn(
                f"LMI solve failed with {name} at {where} ({attempts[name]}); "
                f"falling back to {order[n_try + 1][0]}",
                UserWarning,
                stacklevel=2,
            )
    detail = "; ".join(f"{k}: {v}" for k, v in attempts.items())
    found = set(outcomes.values())
    if "unbounded" in found and "infeasible" not in found:
        raise UnboundedLMIError(f"LMI problem unbounded at {where} ({detail})", step=step, node=node,
                                statuses=attempts, outcomes=outcomes)
    raise InfeasibleLMIError(
        f"LMI infeasible or not certified at {where} ({detail})",
        step=step,
        node=node,
        statuses=attempts,
        outcomes=outcomes,
    )
