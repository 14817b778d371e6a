"""Every parameter of every public function and class of secest is documented.

A parameter counts as documented when it is listed in the numpydoc ``Parameters`` section
of the docstring (for a class: ``Parameters`` or ``Attributes``), alone or in a group such
as ``p, q : float``. Every public module is held to this, subpackages included
(``secest.methods.<name>``); there is no allow-list.
"""

from __future__ import annotations

import functools
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import pytest

import secest

_HEADER = re.compile(r"^(\w[\w ]*)\n-{3,}\s*$", re.MULTILINE)


def _sections(doc: str) -> dict[str, str]:
    """numpydoc section title -> body."""
    heads = list(_HEADER.finditer(doc))
    ends = [h.start() for h in heads[1:]] + [len(doc)] if heads else []
    return {h.group(1).strip(): doc[h.end(): end] for h, end in zip(heads, ends, strict=True)}


def documented(obj: object) -> set[str]:
    """Names listed in the Parameters (and, for classes, Attributes) section of ``obj``."""
    doc = inspect.getdoc(obj) or ""
    secs = _sections(doc)
    bodies = [secs.get("Parameters", "")]
    if inspect.isclass(obj):
        bodies.append(secs.get("Attributes", ""))
    names: set[str] = set()
    for body in bodies:
        for line in body.splitlines():
            if line and not line[0].isspace():
                head = line.split(" : ")[0].split(":")[0]
                names.update(n.strip().lstrip("*") for n in head.split(","))
    return names


def parameters(obj: object) -> list[str]:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values() if p.name not in ("self", "cls")]


def modules() -> list[str]:
    """Every public module of secest, subpackages included: ``"filters"``, ``"methods.x"``.

    A module is public unless a part of its dotted name starts with ``_``.
    """
    names = []
    for info in pkgutil.walk_packages(secest.__path__, prefix="secest."):
        name = info.name.removeprefix("secest.")
        if not any(part.startswith("_") for part in name.split(".")):
            names.append(name)
    return sorted(names)


def public_objects() -> dict[str, object]:
    """``"module.name" -> object`` for every public function and class of every secest module."""
    out: dict[str, object] = {}
    for module in modules():
        mod = importlib.import_module(f"secest.{module}")
        names = getattr(mod, "__all__", None)
        if names is None:
            names = [n for n, o in vars(mod).items() if not n.startswith("_")
                     and (inspect.isfunction(o) or inspect.isclass(o))
                     and getattr(o, "__module__", None) == mod.__name__]
        for name in names:
            obj = getattr(mod, name)
            if inspect.isfunction(obj) or inspect.isclass(obj):
                out[f"{module}.{name}"] = obj
    return out


@functools.cache
def undocumented() -> dict[str, set[str]]:
    found = {}
    for key, obj in public_objects().items():
        if inspect.isclass(obj) and issubclass(obj, Warning | Exception) and not parameters(obj.__init__):
            continue
        missing = {p for p in parameters(obj) if p not in ("args", "kwargs")} - documented(obj)
        if missing:
            found[key] = missing
    return found


def test_documented_parses_groups_and_types() -> None:
    def f(a, b, c):
        """X.

        Parameters
        ----------
        a, b : float
            Two.
        c
            Three.

        Returns
        -------
        float
        """

    assert documented(f) == {"a", "b", "c"}


def test_every_module_is_checked() -> None:
    """Every ``secest/**/*.py`` not private is held to the rule (subpackages included)."""
    root = Path(secest.__file__).parent
    on_disk = set()
    for path in root.rglob("*.py"):
        parts = path.relative_to(root).with_suffix("").parts
        parts = parts[:-1] if parts[-1] == "__init__" else parts
        if parts and not any(part.startswith("_") for part in parts):
            on_disk.add(".".join(parts))
    assert on_disk == set(modules())


@pytest.mark.parametrize("module", modules())
def test_every_parameter_is_documented(module) -> None:
    missing = {k: v for k, v in undocumented().items() if k.rsplit(".", 1)[0] == module}
    assert not missing, f"undocumented parameters: {missing}"
