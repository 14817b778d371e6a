"""Timing harness of the benchmark suite: ratios in one process, alternating repeats.

Every comparison times two callables computing the same thing ("ours" and an
"alternative"): one call of each first (warm-up, excluded from the timings, whose
results are handed to ``agree``), then ``repeats`` calls of each, alternating, so
that drifts of the machine load hit both sides alike. It reports the median of
each side and the ratio alternative / ours (a speed-up of ours when > 1). A
disagreement is an error (``agree`` raises), not a row. Plain ``time.perf_counter``
is enough here and keeps the suite free of a benchmark framework.
"""

from __future__ import annotations

import ast
import contextlib
import io
import symtable
import sys
import tempfile
import time
import types
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import jupytext
import numpy as np

from secest.repro.results import repo_root

__all__ = [
    "MIN_REPEATS",
    "Row",
    "compare",
    "format_table",
    "load_notebook",
    "measure",
    "notebook_definitions",
    "not_measured",
]

MIN_REPEATS = 5


@dataclass
class Row:
    """One line of the benchmark table (times in seconds, per ``unit``)."""

    what: str
    ours: str
    alternative: str
    ours_s: float | None
    alternative_s: float | None
    ratio: float | None
    agreement: str
    target: str
    met: bool | None
    unit: str = "call"
    repeats: int = 0

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def _check_repeats(repeats: int) -> None:
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < MIN_REPEATS:
        raise ValueError(f"repeats must be an integer >= {MIN_REPEATS}, found {repeats!r}")


def compare(
    what: str,
    ours: tuple[str, Callable[[], Any]],
    alternative: tuple[str, Callable[[], Any]],
    agree: Callable[[Any, Any], str],
    *,
    repeats: int = MIN_REPEATS,
    target: tuple[str, Callable[[float], bool]] | None = None,
    per: float = 1.0,
    unit: str = "call",
) -> Row:
    """Time ``ours`` against ``alternative`` with alternating repeats (median of each).

    Parameters
    ----------
    what : description of the comparison.
    ours, alternative : (label, zero-argument callable) pairs.
    agree : called once with the two warm-up results; returns a short description
        of the agreement (e.g. ``"max |diff| 3e-15 <= 1e-10"``) or raises
        AssertionError. It is called before any timing.
    repeats : timed calls of each side (after the warm-up), at least 5.
    target : (description, predicate on the ratio) of the goal, if any. A missed
        target is reported (``met=False``), never raised.
    per : both medians are divided by ``per`` (e.g. the number of node-steps one
        call performs); the ratio is unaffected.
    unit : what one timed unit is (shown in the table).
    """
    _check_repeats(repeats)
    a_label, a_fn = ours
    b_label, b_fn = alternative
    agreement = agree(a_fn(), b_fn())  # also the warm-up
    t_a, t_b = [], []
    for _ in range(repeats):
        for fn, store in ((a_fn, t_a), (b_fn, t_b)):
            t0 = time.perf_counter()
            fn()
            store.append(time.perf_counter() - t0)
    med_a, med_b = float(np.median(t_a)) / per, float(np.median(t_b)) / per
    ratio = med_b / med_a
    return Row(
        what=what,
        ours=a_label,
        alternative=b_label,
        ours_s=med_a,
        alternative_s=med_b,
        ratio=ratio,
        agreement=agreement,
        target=target[0] if target else "",
        met=bool(target[1](ratio)) if target else None,
        unit=unit,
        repeats=repeats,
    )


def measure(
    what: str,
    ours: tuple[str, Callable[[], Any]],
    check: Callable[[Any], str],
    *,
    repeats: int = MIN_REPEATS,
    per: float = 1.0,
    unit: str = "call",
) -> Row:
    """Median time of one callable (no alternative), after a warm-up checked by ``check``."""
    _check_repeats(repeats)
    label, fn = ours
    agreement = check(fn())
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return Row(what, label, "-", float(np.median(times)) / per, None, None, agreement, "", None,
               unit, repeats)


def not_measured(what: str, reason: str) -> Row:
    """A row for a comparison that could not be run, with the reason."""
    return Row(what, "not measured", "-", None, None, None, reason, "", None)


def _fmt_time(t: float | None) -> str:
    if t is None:
        return "-"
    for scale, suffix in ((1.0, "s"), (1e-3, "ms"), (1e-6, "us")):
        if t >= scale:
            return f"{t / scale:.3g} {suffix}"
    return f"{t * 1e9:.3g} ns"


def format_table(rows: list[Row]) -> str:
    """Plain-text (Markdown) table of the rows."""
    head = ["what", "ours", "alternative", "ours time", "alt. time", "ratio alt/ours",
            "agreement check", "target", "met"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        unit = f" /{r.unit}" if r.ours_s is not None and r.unit != "call" else ""
        met = {None: "-", True: "yes", False: "NO"}[r.met]
        ratio = "-" if r.ratio is None else f"{r.ratio:.3g}"
        cells = [r.what, r.ours, r.alternative, _fmt_time(r.ours_s) + unit,
                 _fmt_time(r.alternative_s) + (unit if r.alternative_s is not None else ""),
                 ratio, r.agreement, r.target or "-", met]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines)


def _parameter_names(source: str) -> set[str]:
    names: set[str] = set()
    for node in ast.parse(source).body:
        targets = node.targets if isinstance(node, ast.Assign) else (
            [node.target] if isinstance(node, ast.AnnAssign) else [])
        names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def _definitions_only(source: str) -> ast.Module:
    tree = ast.parse(source)
    keep = (ast.Import, ast.ImportFrom, ast.FunctionDef, ast.ClassDef)
    tree.body = [node for node in tree.body if isinstance(node, keep)]
    return tree


def load_notebook(
    key: str, stop_before: str | None = None, *, quiet: bool = True, **parameters: Any
) -> dict[str, Any]:
    """Execute the code cells of ``notebooks/<key>.py`` in a fresh namespace and return it.

    Parameters given here replace the defaults of the ``parameters`` cell (as papermill
    would inject them); a name that cell does not assign raises ValueError before
    anything runs. Execution stops at the first code cell whose source contains
    ``stop_before`` (e.g. the first figure section); of that cell only the imports and
    the function / class definitions are executed, so a function defined next to its
    first use is still reachable. ``quiet`` swallows what the cells print. The namespace
    is that of a module ``notebook_<key>`` registered in ``sys.modules``.
    """
    import matplotlib

    matplotlib.use("Agg")
    nb = jupytext.read(repo_root() / "notebooks" / f"{key}.py")
    code = [c for c in nb.cells if c.cell_type == "code"]
    tagged = [c for c in code if "parameters" in c.metadata.get("tags", [])]
    if len(tagged) != 1:
        raise ValueError(f"notebook {key} must have exactly one cell tagged 'parameters'")
    unknown = set(parameters) - _parameter_names(tagged[0].source)
    if unknown:
        raise ValueError(f"parameters {sorted(unknown)} are not declared by notebook {key}")
    if stop_before is not None and not any(stop_before in c.source for c in code):
        raise ValueError(f"no code cell of notebook {key} contains {stop_before!r}")
    module = types.ModuleType(f"notebook_{key}")  # registered: dataclasses look their module up
    sys.modules[module.__name__] = module
    namespace: dict[str, Any] = module.__dict__
    sink = contextlib.redirect_stdout(io.StringIO()) if quiet else contextlib.nullcontext()
    with sink:
        for cell in code:
            if stop_before is not None and stop_before in cell.source:
                exec(compile(_definitions_only(cell.source), f"{key}.py", "exec"), namespace)  # noqa: S102
                break
            exec(compile(cell.source, f"{key}.py", "exec"), namespace)  # noqa: S102
            if cell is tagged[0]:
                namespace.update(parameters)
    return namespace


def _global_names(statement: ast.stmt) -> set[str]:
    """Names a top-level statement reads from the module namespace (symtable: locals of its
    functions, comprehension variables and closures excluded)."""
    names: set[str] = set()

    def visit(table: symtable.SymbolTable, top: bool) -> None:
        for sym in table.get_symbols():
            if sym.is_referenced() and (top or sym.is_global()):
                names.add(sym.get_name())
        for child in table.get_children():
            visit(child, False)

    visit(symtable.symtable(ast.unparse(statement), "<notebook>", "exec"), True)
    # what the statement binds itself (loop variables, names assigned in its body) is not a need:
    # if such a name is wanted elsewhere, all its definers run anyway; if not, a read before the
    # binding fails loudly (NameError), never silently
    names -= _bound_names(statement)
    # a module-level ``x += 1`` reads x, which symtable does not count as a reference
    names |= {n.target.id for n in _module_level_nodes(statement)
              if isinstance(n, ast.AugAssign) and isinstance(n.target, ast.Name)}
    return names


def _module_level_nodes(statement: ast.stmt) -> list[ast.AST]:
    """The nodes of a top-level statement that run in module scope (not inside a function,
    class, lambda or comprehension); nested ``def`` / ``class`` nodes themselves are included."""
    nodes: list[ast.AST] = []
    todo: list[ast.AST] = [statement]
    while todo:
        node = todo.pop()
        nodes.append(node)
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef | ast.Lambda
                          | ast.ListComp | ast.SetComp | ast.DictComp | ast.GeneratorExp):
            todo.extend(ast.iter_child_nodes(node))
    return nodes


def _bound_names(statement: ast.stmt) -> set[str]:
    """Module-level names a top-level statement binds (in ``if`` / ``for`` / ``with`` / ``try``
    blocks too; not the locals of the functions, classes, lambdas or comprehensions in it)."""
    if isinstance(statement, ast.Import | ast.ImportFrom):
        return set()
    names: set[str] = set()
    for node in _module_level_nodes(statement):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
    return names


def _root(node: ast.expr) -> str | None:
    while isinstance(node, ast.Subscript | ast.Attribute):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


def _mutated_names(statement: ast.stmt) -> set[str]:
    """Names a top-level statement changes in place: ``x[k] = ...``, ``x.a = ...``, ``x += ...``
    anywhere in it (loops included), and a top-level ``x.method(...)`` call."""
    if isinstance(statement, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef | ast.Import
                  | ast.ImportFrom):
        return set()
    names: set[str | None] = set()
    for node in _module_level_nodes(statement):
        if isinstance(node, ast.Subscript | ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(_root(node))
        elif isinstance(node, ast.AugAssign):
            names.add(_root(node.target))
    if (isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Call)
            and isinstance(statement.value.func, ast.Attribute)):
        names.add(_root(statement.value.func.value))
    return {n for n in names if n is not None}


def _scratch_outputs(key: str, declared: set[str]) -> dict[str, Any]:
    """Output parameters pointing into a fresh temporary folder and figures off: a statement
    that saves a figure or claims never writes over the committed ``figures/<key>/``."""
    out = Path(tempfile.mkdtemp(prefix=f"secest-{key}-"))
    scratch = {"fig_dir": str(out / "figures"), "results_path": str(out / "claims.json"),
               "figures": False}
    return {name: value for name, value in scratch.items() if name in declared}


def notebook_definitions(key: str, *names: str, **parameters: Any) -> dict[str, Any]:
    """The named functions / classes / values of ``notebooks/<key>.py``, by name, nothing else.

    No text marker: the code cells are parsed with ``ast`` and only what the named objects
    need is executed, in notebook order: the ``parameters`` cell (``parameters`` replacing its
    defaults, unknown names refused as in ``load_notebook``), every import, and the top-level
    statements binding the names asked for (``def``, ``class``, assignments, also inside a
    top-level ``if`` / ``for`` / ``with`` / ``try``), the statements
    that change them in place (``x[k] = ...``, ``x += ...``, ``x.update(...)``, loops doing so)
    and, transitively, the same for the module-level names these read (found with ``symtable``,
    so a function's local variables never pull in a computation that happens to share their
    name). The notebook's other statements (prints, figures, computations the named objects do
    not need) are not run. Import modules such as ``np`` are never "changed in place".

    The output parameters (``fig_dir``, ``results_path``) point into a temporary folder and
    ``figures`` is off unless given, so nothing is written over the committed results.

    Raises
    ------
    ValueError
        A name the notebook does not define at top level, or an undeclared parameter.
    """
    nb = jupytext.read(repo_root() / "notebooks" / f"{key}.py")
    code = [c for c in nb.cells if c.cell_type == "code"]
    tagged = [c for c in code if "parameters" in c.metadata.get("tags", [])]
    if len(tagged) != 1:
        raise ValueError(f"notebook {key} must have exactly one cell tagged 'parameters'")
    import matplotlib

    matplotlib.use("Agg")
    declared = _parameter_names(tagged[0].source)
    unknown = set(parameters) - declared
    if unknown:
        raise ValueError(f"parameters {sorted(unknown)} are not declared by notebook {key}")
    parameters = {**_scratch_outputs(key, declared), **parameters}
    statements = [node for c in code if c is not tagged[0] for node in ast.parse(c.source).body]
    imports = [s for s in statements if isinstance(s, ast.Import | ast.ImportFrom)]
    imported = {(a.asname or a.name).split(".")[0] for s in imports for a in s.names}
    definers: dict[str, list[int]] = {}
    for i, s in enumerate(statements):
        for name in _bound_names(s):
            definers.setdefault(name, []).append(i)
    missing = [n for n in names if n not in definers and n not in declared]
    if missing:
        raise ValueError(f"notebook {key} defines no top-level {', '.join(map(repr, missing))}")
    needed: set[int] = set()
    wanted = {n for n in names if n not in declared}
    while True:  # to a fixed point: what the needed statements read is needed in turn
        grown = {i for name in wanted for i in definers.get(name, [])}
        grown |= {i for i, s in enumerate(statements) if _mutated_names(s) & (wanted - imported)}
        if grown <= needed:
            break
        for i in grown - needed:
            wanted |= {n for n in _global_names(statements[i]) if n not in declared}
        needed |= grown
    module = types.ModuleType(f"notebook_{key}_definitions")  # registered: dataclasses look it up
    sys.modules[module.__name__] = module
    namespace: dict[str, Any] = module.__dict__
    body = ast.Module(body=imports + [statements[i] for i in sorted(needed)], type_ignores=[])
    with contextlib.redirect_stdout(io.StringIO()):
        exec(compile(tagged[0].source, f"{key}.py", "exec"), namespace)  # noqa: S102
        namespace.update(parameters)
        exec(compile(body, f"{key}.py", "exec"), namespace)  # noqa: S102
    return namespace
