"""Nothing executes notebook text outside a kernel: no ``exec`` / ``eval`` in the package, the tests
or the benchmarks (read from the source with ``ast``). What a test or a benchmark needs of a
paper's algorithm it imports from ``secest``; what it needs of a notebook it gets from a papermill
execution of that notebook (its claims, its figure data)."""

from __future__ import annotations

import ast

import pytest
from conftest import repo_root

FORBIDDEN = {"exec", "eval"}


def calls_of_exec(source: str) -> list[int]:
    """Line numbers of every call of the builtins ``exec`` / ``eval`` in ``source``."""
    return [node.lineno for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id in FORBIDDEN]


@pytest.mark.parametrize("folder", ["secest", "tests", "benchmarks"])
def test_no_exec_of_text_in_the_code(folder: str) -> None:
    found = {str(p.relative_to(repo_root())): lines for p in sorted((repo_root() / folder).rglob("*.py"))
             if (lines := calls_of_exec(p.read_text()))}
    assert found == {}


def test_the_scan_sees_an_exec() -> None:
    assert calls_of_exec("x = 1\nexec(compile('y = 2', 'nb.py', 'exec'), {})\n") == [2]
    assert calls_of_exec("def f(s):\n    return eval(s)\n") == [2]
