"""Shared fixtures: execute a notebook in fast mode into a temporary directory."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from secest.run import execute_notebook


@pytest.fixture(scope="module")
def run_notebook(tmp_path_factory: pytest.TempPathFactory) -> Callable[..., dict[str, Any]]:
    """Return ``run(key, **parameters) -> claims`` executing ``notebooks/<key>.ipynb``.

    The notebook runs with ``mode="fast"`` (unless overridden) and writes its
    figures and claims into a fresh temporary directory, never into the repo.
    """

    def run(key: str, **parameters: Any) -> dict[str, Any]:
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
        return claims

    return run
