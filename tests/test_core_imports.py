"""Importing the core of secest loads neither the notebook stack nor cvxpy (a core install has neither)."""

from __future__ import annotations

import json
import subprocess
import sys

CORE = [f"core.{m}" for m in ("validation", "tolerances", "graphs", "channels", "covariance", "detectors",
                               "montecarlo", "systems", "estimation", "schedules")]
CORE += ["methods.ding2020", "methods.guo2023", "methods.lee2020", "methods.li2025"]
HEAVY = ["matplotlib", "papermill", "cvxpy", "IPython", "nbformat", "jupyter_client", "dask"]


def _loaded_after(imports: str) -> list[str]:
    code = f"import sys, json; {imports}; print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_core_modules_import_without_heavy_dependencies() -> None:
    assert _loaded_after("; ".join(f"import secest.{m}" for m in CORE)) == []


def test_lmi_imports_cvxpy_but_not_the_notebook_stack() -> None:
    assert _loaded_after("import secest.core.lmi") == ["cvxpy"]


def test_the_arena_registers_every_method_on_first_use() -> None:
    code = ("import json; from secest.arena.estimators import METHODS; print(json.dumps(list(METHODS)))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    names = json.loads(out.stdout)
    assert {"oracle", "kf", "chi2-kf", "consensus-kf"} <= set(names)
    assert {"ding2020", "guo2023", "lee2020", "li2025", "ma2021"} <= set(names)
    assert _loaded_after("import secest.arena.matrix") == []  # ma2021 imports cvxpy only when it runs
