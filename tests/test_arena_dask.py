"""The arena on Dask distributed (issue #29): the same matrix as in one process, checked arguments."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import repo_root

from secest.arena import cli, matrix, race, scenarios
from secest.arena.estimators import METHODS
from secest.core.validation import ValidationError

pytest.importorskip("dask.distributed")
EXAMPLES = repo_root() / "docs" / "examples"


def _same(a: matrix.Matrix, b: matrix.Matrix) -> None:
    assert list(a.cells) == list(b.cells) and a.methods == b.methods
    for key, cell in a.cells.items():
        other = b.cells[key]
        assert (cell.status, cell.reason) == (other.status, other.reason), key
        for f in ("steady", "steady_worst", "transient", "growth", "detection", "false_alarm"):
            x, y = getattr(cell, f), getattr(other, f)
            assert (x is None) == (y is None), (key, f)
            if x is not None:
                assert np.array_equal(np.asarray(x, float), np.asarray(y, float), equal_nan=True), (key, f)
    assert set(a.curves) == set(b.curves)
    for name, c in a.curves.items():
        assert set(c.rms) == set(b.curves[name].rms)
        assert all(np.array_equal(c.rms[m], b.curves[name].rms[m], equal_nan=True) for m in c.rms)


def test_a_local_cluster_gives_the_matrix_of_one_process() -> None:
    import secest.methods  # noqa: F401  (the papers' methods)

    grid = scenarios.matrix(networks=["target20"], attacks=["none", "bias"], runs=3, horizon=12)
    names = ["kf", "local-kf", "guo2023", "li2025"]
    here = matrix.run_matrix(grid, names, short=True)
    there = matrix.run_matrix(grid, names, short=True, workers=2)
    _same(here, there)
    assert set(there.seconds) == set(here.seconds)


def test_a_method_from_a_file_travels_to_the_workers(tmp_path: Path) -> None:
    """``--method path.py:Class`` is a module no worker can import by name: sent by value."""
    before = list(METHODS)
    try:
        name = cli.load_method(f"{EXAMPLES / 'my_method.py'}:FixedGainKF")
        assert type(METHODS[name]).__module__.startswith(matrix.USER_MODULE_PREFIX)
        m = race(None, ["kf", name], plants=["target20"], attacks=["none"], runs=3, horizon=12,
                 short=True, workers=1)
        cell = m.cell("target20/none", name)
        assert cell.status == "ok" and cell.steady is not None
    finally:
        for name in [n for n in METHODS if n not in before]:
            METHODS.pop(name)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"workers": 0}, "workers must be an integer from 1 to 256, found 0"),
        ({"workers": True}, "workers must be an integer from 1 to 256, found True"),
        ({"workers": 2.0}, "workers must be an integer from 1 to 256, found 2.0"),
        ({"scheduler": "localhost"}, "scheduler must be a Dask scheduler address"),
        ({"scheduler": "tcp://127.0.0.1:1", "workers": 2}, "not both"),
    ],
)
def test_bad_dask_arguments_are_refused_before_any_work(kwargs: dict, words: str) -> None:
    grid = scenarios.matrix(networks=["target20"], attacks=["none"], runs=2, horizon=12)
    with pytest.raises(ValidationError, match=words):
        matrix.run_matrix(grid, ["kf"], short=True, **kwargs)
    with pytest.raises(ValidationError, match=words):
        race(None, ["kf"], plants=["target20"], attacks=["none"], runs=2, horizon=12, short=True, **kwargs)


def test_the_command_line_refuses_zero_workers() -> None:
    proc = subprocess.run([sys.executable, "-m", "secest.arena", "--workers", "0", "--out", "x"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert "--workers: expected an integer >= 1, found 0" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_a_design_is_cut_into_batches_that_share_no_design() -> None:
    """Each (network, horizon) group's methods are dealt into batches, each method into one."""
    grid = [scenarios.scenario(net, att, runs=2, horizon=h, seed=s, name=f"{net}/{att}/{h}/{s}")
            for net in ("target20", "inertia5") for att in ("none", "bias") for h in (10, 20)
            for s in (1, 2)]
    names = ["oracle", "kf", "local-kf", "guo2023", "li2025", "ma2021"]
    batches = matrix.plan_tasks(grid, names, workers=2)
    groups = {(sc.network.name, sc.horizon) for sc in grid}
    assert len(batches) == len(groups) * 2  # 4 per worker x 2 workers over 4 groups
    for key in groups:
        mine = [b for b in batches if {(sc.network.name, sc.horizon) for sc in b[0]} == {key}]
        assert sorted(n for _, ns in mine for n in ns) == sorted(names)
        assert all(len(b[0]) == 4 for b in mine)  # 2 attacks x 2 seeds
    costs = [sum(sc.runs * sc.horizon * sc.network.N for sc in b[0]) * sum(METHODS[n].cost for n in b[1])
             for b in batches]
    assert costs == sorted(costs, reverse=True)
    heavy = [b for b in batches if "ma2021" in b[1]]
    assert METHODS["ma2021"].cost > sum(METHODS[n].cost for n in names if n != "ma2021")
    assert all(b[1] == ["ma2021"] for b in heavy)  # the costliest method alone in its batch
    assert batches[0][1] == ["ma2021"]
    assert len(matrix.plan_tasks(grid[:1], names, workers=64)) == len(names)  # one batch per method


def test_the_tasks_of_a_dask_matrix_are_timed() -> None:
    grid = scenarios.matrix(networks=["target20", "tank12"], attacks=["none"], runs=2, horizon=12)
    m = matrix.run_matrix(grid, ["kf", "local-kf", "guo2023"], short=True, workers=2)
    assert len(m.tasks) == len(matrix.plan_tasks(grid, m.methods, 2)) == 8
    assert all(t > 0 for t in m.tasks)
    here = matrix.run_matrix(grid, ["kf", "local-kf", "guo2023"], short=True)
    assert len(here.tasks) == len(grid)
    _same(here, m)
