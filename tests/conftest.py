"""Shared fixtures: execute a notebook in fast mode into a temporary directory."""

from __future__ import annotations

import copy
import fcntl
import hashlib
import json
import os
import shutil
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from secest.repro.results import repo_root
from secest.repro.run import execute_notebook


def _not_json(constant: str) -> None:
    raise ValueError(f"claims.json holds {constant}, which strict JSON does not allow")


def _shared_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder every pytest-xdist worker of this session sees (this session's own base
    temporary folder; without xdist, the base temporary folder itself)."""
    base = tmp_path_factory.getbasetemp()
    shared = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "executions"
    shared.mkdir(parents=True, exist_ok=True)
    return shared


def bench_harness() -> Any:
    """``benchmarks/harness.py`` as a module (it is not part of the package), loaded once."""
    import importlib.util
    import sys

    name = "secest_bench_harness"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, repo_root() / "benchmarks" / "harness.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def perturbation_point(key: str, **parameters: Any) -> dict[str, Any]:
    """``parameters``, checked to be one of ``key``'s perturbation points (so that the module's
    execution is the one tests/test_notebooks.py shares, not a second one)."""
    from secest.repro import spaces

    points = spaces.perturbation_points(spaces.load(key))
    if parameters not in points:
        raise AssertionError(f"{parameters} is not a perturbation point of {key}: {points}")
    return parameters


@pytest.fixture(scope="session")
def run_notebook(tmp_path_factory: pytest.TempPathFactory) -> Callable[..., dict[str, Any]]:
    """Return ``run(key, **parameters) -> claims`` executing ``notebooks/<key>.ipynb``.

    The notebook runs with ``mode="fast"`` (unless overridden) and writes its
    figures and claims into a temporary folder, never into the repo; the claims
    carry that folder's figures as ``"_fig_dir"``. Each (key, parameters) is executed
    once per test session, whichever worker asks first: a module's fixture and a
    perturbation test at the same point share one execution (the other worker waits
    on a file lock and reads the result). Every call gets its own copy of the claims.
    """
    shared = _shared_folder(tmp_path_factory)
    done: dict[str, dict[str, Any]] = {}

    def run(key: str, **parameters: Any) -> dict[str, Any]:
        params = {"mode": "fast", **parameters}
        signature = json.dumps([key, params], sort_keys=True, default=str)
        if signature not in done:
            out = shared / f"{key}-{hashlib.sha256(signature.encode()).hexdigest()[:16]}"
            with open(f"{out}.lock", "w") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file closes
                if not (out / "done").exists():
                    shutil.rmtree(out, ignore_errors=True)  # a failed attempt's leftovers
                    params |= {
                        "fig_dir": str(out / "figures"),
                        "results_path": str(out / "claims.json"),
                    }
                    execute_notebook(key, params, out / f"{key}.ipynb")
                    (out / "done").write_text(signature)
            claims = json.loads((out / "claims.json").read_text(), parse_constant=_not_json)
            claims["_fig_dir"] = str(out / "figures")
            done[signature] = claims
        return copy.deepcopy(done[signature])

    return run


TOY_PY = '''# %% [markdown]
# # toy

# %% tags=["parameters"]
mode = "paper"  # "paper" or "fast" (ours)
T = 40  # horizon (MISSING)
scale = 0.15  # Taylor scale (MISSING)
twin = 0.15  # tied to scale (MISSING)
alpha = 0.67  # OCR reading (RECONSTRUCTED)
flag = False  # a switch (ours)
seed = 0  # seed (MISSING)
gains = [0.4, 0.5]  # printed gains (PAPER)
fig_dir = "figures/toy"
results_path = "figures/toy/claims.json"

# %%
print(T)
'''

TOY_TOML = '''
[sweep]
base = { mode = "fast" }
n = 4
seed = 3

[parameters.mode]
type = "str"
choices = ["paper", "fast"]

[parameters.T]
type = "int"
min = 1

[parameters.scale]
type = "float"
exclusive_min = 0.0
space = { low = 0.1, high = 0.3 }
reason = "premise (12) holds above 0.1"

[parameters.twin]
type = "float"
space = { same_as = "scale" }

[parameters.alpha]
type = "float"
min = 0.0
max = 1.0
space = { values = [0.6, 0.67], labels = ["brief", "OCR"] }

[parameters.seed]
type = "int"
min = 0
space = { values = [0, 1] }

[parameters.gains]
type = "list"
items = "float"
length = 2
'''


@pytest.fixture
def toy(tmp_path: Path) -> Path:
    """A repository root holding a toy notebook source and its declared space."""
    (tmp_path / "notebooks").mkdir()
    (tmp_path / "notebooks" / "toy.py").write_text(TOY_PY)
    (tmp_path / "notebooks" / "toy.toml").write_text(TOY_TOML)
    return tmp_path


ALONE = ("test_notebook_runs_off_its_default_point", "test_a_remote_cluster")
"""Tests scheduled one by one: each is a long notebook execution of its own."""
FIRST = ("tests/test_site.py", "test_a_remote_cluster")
"""Work queued first: the longest single units (build then browse the site; start two Dask
clusters). Then the modules executing notebooks, then the ALONE tests, then the rest."""


def _scope(nodeid: str) -> str:
    return nodeid if any(name in nodeid for name in ALONE) else nodeid.split("::", 1)[0]


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Queue order (see :data:`FIRST`); modules stay whole and keep their own order. Every
    xdist worker sorts its own collection the same way (the scheduler sends indexes into it)."""
    executes = {f"tests/test_{p.stem}.py" for p in (repo_root() / "notebooks").glob("*.py")}
    counts = Counter(_scope(item.nodeid) for item in items)

    def rank(item: pytest.Item) -> tuple[int, int]:
        scope = _scope(item.nodeid)
        first, module, alone = any(n in scope for n in FIRST), scope in executes, scope == item.nodeid
        group = 0 if first else 1 if module else 2 if alone else 3
        return group, -counts[scope]

    items.sort(key=rank)


def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    """Send each test module to one worker whole (its notebook executions are then shared by
    its tests), except the tests of :data:`ALONE`, which are spread one by one, in the order
    of the collection (:func:`pytest_collection_modifyitems`: long units first, so that no
    worker is left with one at the end while the other idles; xdist's own order, by number of
    tests, queued the Dask test last).

    ``--dist loadgroup`` would do this with ``xdist_group`` marks, but pytest 9.2 silently
    drops them (pytest-dev/pytest-xdist#1386): tests were spread as under ``--dist load``.
    """
    from xdist.scheduler import LoadScopeScheduling

    config.option.loadscopereorder = False  # the collection's order instead

    class ModuleOrAlone(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _scope(nodeid)

    return ModuleOrAlone(config, log)
