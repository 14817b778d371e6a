"""The adversarial sweep of the arena's public API (``benchmarks/api_sweep.py``, issue #29): every
invalid call ends in a one-line ValidationError naming its argument or card key.
"""

from __future__ import annotations

import importlib.util
import sys

from conftest import repo_root

SWEEP = repo_root() / "benchmarks" / "api_sweep.py"


def _module():
    spec = importlib.util.spec_from_file_location("api_sweep", SWEEP)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks itself up there
    spec.loader.exec_module(module)
    return module


def test_every_invalid_call_of_the_arena_api_is_refused_clearly() -> None:
    sweep = _module()
    results = sweep.sweep(list(sweep.GROUPS))
    assert len(results) >= 750
    bad = [f"{r['outcome']}: {r['target']}: {r['said']}" for r in results if r["outcome"] != "clear"]
    assert bad == []
