"""Shared fixtures: execute a notebook in fast mode into a temporary directory."""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from secest.run import execute_notebook


@pytest.fixture(scope="session")
def run_notebook(tmp_path_factory: pytest.TempPathFactory) -> Callable[..., dict[str, Any]]:
    """Return ``run(key, **parameters) -> claims`` executing ``notebooks/<key>.ipynb``.

    The notebook runs with ``mode="fast"`` (unless overridden) and writes its
    figures and claims into a fresh temporary directory, never into the repo.
    Each (key, parameters) is executed once per test session (pytest-xdist may
    interleave modules on a worker, which would rebuild module-scoped fixtures);
    every call gets its own copy of the claims.
    """
    done: dict[str, dict[str, Any]] = {}

    def run(key: str, **parameters: Any) -> dict[str, Any]:
        signature = json.dumps([key, parameters], sort_keys=True, default=str)
        if signature not in done:
            out: Path = tmp_path_factory.mktemp(key)
            params = {
                "mode": "fast",
                "fig_dir": str(out / "figures"),
                "results_path": str(out / "claims.json"),
                **parameters,
            }
            execute_notebook(key, params, out / f"{key}.ipynb")
            claims = json.loads((out / "claims.json").read_text())
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
