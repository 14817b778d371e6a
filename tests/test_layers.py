"""The direction of imports between secest's layers, read from the source (nothing is imported).

core (the estimation library) <- methods (the papers' estimators) <- arena <- repro (tooling):
a module may import its own layer and the layers before it, never one after it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from conftest import repo_root

LAYERS = ("core", "methods", "arena", "repro")


def layer_of(module: str) -> int | None:
    """Rank of ``secest.<layer>...`` in :data:`LAYERS`; None for ``secest`` itself or a non-secest name."""
    parts = module.split(".")
    if parts[0] != "secest" or len(parts) < 2:
        return None
    if parts[1] not in LAYERS:
        raise AssertionError(f"{module}: not in a layer {LAYERS}")
    return LAYERS.index(parts[1])


def imported_modules(source: str, module: str) -> list[str]:
    """Every secest module ``source`` imports (function-level imports included); ``from secest.x
    import y`` counts as ``secest.x.y`` so that ``from secest import core`` names its layer."""
    package = module.rsplit(".", 1)[0]
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1]
                                + ([base] if base else []))
            out += [f"{base}.{a.name}" for a in node.names]
    return [m for m in out if m.split(".")[0] == "secest"]


def violations(source: str, module: str) -> list[str]:
    """The imports of ``module`` (its ``source``) that point to a later layer."""
    own = layer_of(module)
    if own is None:  # secest/__init__.py: the package's front, may name every layer
        return []
    return [f"{module} ({LAYERS[own]}) imports {m} ({LAYERS[layer_of(m)]})"
            for m in imported_modules(source, module)
            if layer_of(m) is not None and layer_of(m) > own]


def package_modules() -> dict[str, Path]:
    root = repo_root() / "secest"
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def test_every_module_sits_in_a_layer() -> None:
    modules = package_modules()
    assert {m.split(".")[1] for m in modules if m != "secest"} == set(LAYERS)
    assert set(p.parent.name for p in (repo_root() / "secest").glob("*/__init__.py")) == set(LAYERS)
    assert [p.name for p in (repo_root() / "secest").glob("*.py")] == ["__init__.py"]


def test_no_module_imports_a_later_layer() -> None:
    found = [v for m, p in package_modules().items() for v in violations(p.read_text(), m)]
    assert found == []


@pytest.mark.parametrize("module, source", [
    ("secest.core.graphs", "from secest.repro import results\n"),
    ("secest.core.graphs", "def f():\n    from secest.arena.scenarios import Scenario\n"),
    ("secest.methods.guo2023", "import secest.arena.estimators\n"),
    ("secest.arena.matrix", "from secest import repro\n"),
    ("secest.core.graphs", "from ..repro import plotting\n"),
])
def test_the_rule_catches_a_library_module_importing_tooling(module: str, source: str) -> None:
    assert len(violations(source, module)) == 1


def test_the_rule_allows_earlier_layers() -> None:
    assert violations("from secest.core import graphs\nfrom secest.methods import lee2020\n",
                      "secest.arena.matrix") == []
    assert violations("from . import validation\n", "secest.core.graphs") == []
