"""Claims JSON, run manifests and papermill parameter validation.

Every notebook ends by writing its claims to ``results_path`` (default
``figures/<key>/claims.json``): one entry per claim id with the keys
``paper``, ``check``, ``measured``, ``threshold`` and ``holds``. Every execution
also writes a run manifest ``build/runs/<key>.json`` (not committed) with
package versions, solver, git commit, parameters and wall time.
"""

from __future__ import annotations

import json
import math
import platform
import subprocess
import time
from collections.abc import Mapping
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from secest.validation import ValidationError

__all__ = [
    "Run",
    "claim",
    "declared_parameters",
    "environment_summary",
    "notebook_path",
    "repo_root",
    "resolve",
    "validate_parameters",
    "write_claims",
]

CLAIM_KEYS = ("paper", "check", "measured", "threshold", "holds")
_PACKAGES = ("numpy", "scipy", "networkx", "cvxpy", "clarabel", "scs", "control", "matplotlib")


def repo_root() -> Path:
    """The repository root (the folder holding ``secest/``); paths resolve from here."""
    return Path(__file__).resolve().parent.parent


def environment_summary() -> str:
    """Interpreter and secest location, repository paths shown as ``<repo>/...``.

    The first code cell of every notebook prints this, so a wrong interpreter is
    visible while the committed output does not depend on where the repository lives.
    """
    import sys

    import secest

    def show(path: str) -> str:
        p = Path(path)
        try:
            return "<repo>/" + p.relative_to(repo_root()).as_posix()
        except ValueError:
            return str(p)

    return f"python: {show(sys.executable)}\nsecest: {show(secest.__file__)}"


def resolve(path: str | Path) -> Path:
    """``path`` if absolute, else ``repo_root() / path``."""
    p = Path(path)
    return p if p.is_absolute() else repo_root() / p


def notebook_path(key: str) -> Path:
    """``notebooks/<key>.ipynb`` under the repository root (must exist)."""
    path = repo_root() / "notebooks" / f"{key}.ipynb"
    if not path.exists():
        raise ValidationError(f"key {key!r} names no notebook: {path} does not exist")
    return path


def declared_parameters(key: str) -> dict[str, Any]:
    """Names and defaults of the ``parameters`` cell of ``notebooks/<key>.ipynb``."""
    import papermill

    path = notebook_path(key)
    info = papermill.inspect_notebook(str(path))
    assigned = _parameter_cell_names(path)
    if set(info) != assigned:
        raise ValidationError(
            f"papermill parses parameters {sorted(info)} from notebook {key!r} but its "
            f"parameters cell assigns {sorted(assigned)}: papermill cannot parse a line "
            "(e.g. an '=' inside a comment); rewrite that line"
        )
    return {name: spec["default"] for name, spec in info.items()}


def _parameter_cell_names(path: Path) -> set[str]:
    """Names assigned at top level of the cell tagged ``parameters`` (parsed with ast)."""
    import ast

    import nbformat

    nb = nbformat.read(path, as_version=4)
    cells = [c for c in nb.cells if "parameters" in c.metadata.get("tags", [])]
    if len(cells) != 1:
        raise ValidationError(f"{path.name} must have exactly one cell tagged 'parameters'")
    names: set[str] = set()
    for node in ast.parse(cells[0].source).body:
        if not isinstance(node, ast.Assign | ast.AnnAssign):
            raise ValidationError(f"the parameters cell of {path.name} must hold literals only")
        targets = node.targets if isinstance(node, ast.Assign) else [node.target]
        names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def validate_parameters(key: str, parameters: Mapping[str, Any]) -> None:
    """Reject parameter names the notebook does not declare (papermill only warns).

    Raises
    ------
    ValidationError
        Listing the unknown names and the declared ones.
    """
    declared = declared_parameters(key)
    unknown = sorted(set(parameters) - set(declared))
    if unknown:
        raise ValidationError(
            f"parameters {unknown} are not declared by notebook {key!r}; declared: {sorted(declared)}"
        )


def _plain(value: Any) -> Any:
    """Convert numpy scalars / arrays to JSON-ready Python values; reject NaN."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.bool_ | bool):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating | float):
        v = float(value)
        if math.isnan(v):
            raise ValidationError("claim values must not be NaN")
        return v
    return value


def claim(
    paper: str, check: str, measured: Any, threshold: Any, holds: bool | np.bool_
) -> dict[str, Any]:
    """One claims-JSON entry.

    Parameters
    ----------
    paper : what the paper states (with its equation / figure reference).
    check : what we measure and against what.
    measured : the measured value(s).
    threshold : the value the measurement is compared with.
    holds : whether the paper's statement holds in our reproduction.
    """
    if not isinstance(holds, bool | np.bool_):
        raise ValidationError(f"holds must be a bool, found {type(holds).__name__}")
    for name, text in (("paper", paper), ("check", check)):
        if not isinstance(text, str) or not text.strip():
            raise ValidationError(f"{name} must be a non-empty string")
    return {
        "paper": paper,
        "check": check,
        "measured": _plain(measured),
        "threshold": _plain(threshold),
        "holds": bool(holds),
    }


def write_claims(path: str | Path, claims: Mapping[str, Mapping[str, Any]]) -> Path:
    """Write ``claims`` (id -> :func:`claim` entry) as sorted, indented JSON.

    Raises
    ------
    ValidationError
        If an id is not of the form ``C<number>`` or ``X<number>`` (ours), or an
        entry lacks one of ``paper, check, measured, threshold, holds``.
    """
    for cid, entry in claims.items():
        if not (cid[:1] in "CX" and cid[1:].replace("_", "").isalnum() and len(cid) > 1):
            raise ValidationError(f"claim id {cid!r} must look like 'C1' (paper) or 'X1' (ours)")
        missing = [k for k in CLAIM_KEYS if k not in entry]
        if missing:
            raise ValidationError(f"claim {cid} lacks keys {missing}")
    out = resolve(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(_plain(dict(claims)), indent=2, sort_keys=True) + "\n"
    out.write_text(text)
    return out


def _git_commit() -> str:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=repo_root(),
            capture_output=True,
            text=True,
            check=True,
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain"], cwd=repo_root(), capture_output=True, text=True
        ).stdout.strip()
        return out.stdout.strip() + ("-dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


class Run:
    """Run manifest of one notebook execution, written to ``build/runs/<key>.json``.

    Create it right after the parameters cell with the notebook's parameters;
    call :meth:`finish` at the end. Machine-dependent content (timings,
    versions) lives only here, never in committed outputs.

    Parameters
    ----------
    key : paper key, e.g. ``"lee2020"``.
    namespace : mapping holding the parameter values (pass ``globals()``).
    """

    def __init__(self, key: str, namespace: Mapping[str, Any]) -> None:
        declared = declared_parameters(key)
        self.key = key
        self.parameters = {name: _plain(namespace.get(name, declared[name])) for name in declared}
        self._start = time.perf_counter()

    def finish(self, *, solver: str | None = None, extra: Mapping[str, Any] | None = None) -> Path:
        """Write the manifest (versions, solver, git commit, parameters, wall time)."""
        versions = {"python": platform.python_version()}
        for pkg in _PACKAGES:
            try:
                versions[pkg] = metadata.version(pkg)
            except metadata.PackageNotFoundError:
                versions[pkg] = "not installed"
        manifest = {
            "key": self.key,
            "git_commit": _git_commit(),
            "machine": f"{platform.system()} {platform.machine()}",
            "versions": versions,
            "solver": solver,
            "parameters": self.parameters,
            "wall_time_s": round(time.perf_counter() - self._start, 3),
            "extra": _plain(dict(extra or {})),
        }
        path = repo_root() / "build" / "runs" / f"{self.key}.json"
        if self.parameters.get("mode") not in (None, "paper"):
            path = path.with_name(f"{self.key}.{self.parameters['mode']}.json")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n")
        return path
