"""The robustness sweep engine: tables, verdicts over a space, regions, Dask execution."""

from __future__ import annotations

import csv
import io
import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import TOY_TOML

from secest.repro import spaces, sweep
from secest.repro.results import repo_root

ROOT = repo_root()


def _space(root: Path) -> spaces.Space:
    return spaces.load("toy", root)


def _results(points: list[dict], rule) -> tuple[list, dict]:
    swept, results = [], {}
    for i, p in enumerate(points):
        pid = f"p{i}"
        swept.append((pid, p))
        holds = rule(p)
        results[pid] = {
            "status": "ok",
            "claims": {
                "C1": {"holds": holds, "verdict": "holds" if holds else "fails", "measured": p["scale"]},
                "C2": {"holds": True, "verdict": "holds", "measured": {"r": 1.0}, "key": "r"},
                "X1": {"holds": True, "premise": {"statement": "A3", "holds": False}, "measured": 0.0},
            },
        }
    return swept, results


def test_summary_maps_where_a_claim_holds(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    swept, results = _results(points, lambda p: p["scale"] < 0.2)
    rows = sweep.tabulate(space, swept, results)
    assert rows[0]["alpha"] == "OCR" and rows[0]["C1.outcome"] == "holds" and rows[0]["C2.value"] == 1.0
    summary = sweep.summarise(space, rows, points)
    n = len(points)
    held = sum(p["scale"] < 0.2 for p in points)
    c1 = summary["C1"]
    assert c1["verdict"] == "undetermined" and c1["points"] == n and c1["outcomes"]["holds"] == held
    assert c1["fraction_holds"] == pytest.approx(held / n)
    assert c1["interval"]["low"] < held / n < c1["interval"]["high"]
    assert c1["region"].startswith("holds exactly where scale <= ")
    assert summary["C2"]["verdict"] == "holds" and summary["C2"]["region"].startswith("holds at all")
    assert summary["X1"]["verdict"] == "fails-premise"


def test_region_without_a_single_separating_axis(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    # holds where both the scale is small and the seed is 0: no one-axis rule is exact
    swept, results = _results(points, lambda p: p["scale"] < 0.2 and p["seed"] == 0)
    rows = sweep.tabulate(space, swept, results)
    region = sweep.summarise(space, rows, points)["C1"]["region"]
    assert "no one- or two-axis rule separates it" in region and "holding per level: alpha (brief:" in region


def test_region_decided_by_two_set_axes_together(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    swept, results = _results(points, lambda p: not (p["alpha"] == 0.6 and p["seed"] == 1))
    rows = sweep.tabulate(space, swept, results)
    region = sweep.summarise(space, rows, points)["C1"]["region"]
    assert region.startswith("fails exactly where alpha = brief and seed = 1, holds elsewhere")


def test_region_of_a_claim_that_holds_wherever_its_premise_holds(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    swept, results = _results(points, lambda p: True)
    for (pid, p) in swept:  # X1's premise holds only at seed 0, and X1 holds there
        results[pid]["claims"]["X1"]["premise"]["holds"] = p["seed"] == 0
    rows = sweep.tabulate(space, swept, results)
    x1 = sweep.summarise(space, rows, points)["X1"]
    kept = sum(p["seed"] == 0 for p in points)
    assert x1["verdict"] == "holds" and x1["outcomes"]["fails"] == 0 and x1["decided"] == kept
    assert x1["region"] == (f"holds wherever its premise holds ({kept} of {len(points)} points); "
                            "the premise fails exactly where seed >= 1 (the next swept value, 0, is "
                            f"on the other side) ({len(points) - kept} of {len(points)} points)")


def test_not_checked_points_are_not_failures_and_replicates_are_counted(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    swept, results = _results(points, lambda p: True)
    for (pid, p) in swept:  # C1 could not be checked at seed 1 (a numerical limit of ours)
        if p["seed"] == 1:
            results[pid]["claims"]["C1"]["holds"] = None
    rows = sweep.tabulate(space, swept, results)
    summary = sweep.summarise(space, rows, points)
    c1, c2 = summary["C1"], summary["C2"]
    skipped = sum(p["seed"] == 1 for p in points)
    assert c1["verdict"] == "holds" and c1["outcomes"]["not-checked"] == skipped
    assert c1["decided"] == len(points) - skipped and c1["fraction_holds"] == 1.0
    # C2 measures 1.0 at every point: one evaluation, whatever the number of points
    assert c2["evaluations"] == 1 and c1["evaluations"] > 1
    assert sweep._space_verdict({"holds": 0, "fails": 0, "fails-premise": 0, "not-checked": 3}) == (
        "not-checked", 0)


def test_a_saturating_headline_of_different_experiments_is_not_one_evaluation(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    swept, results = _results(points, lambda p: True)
    for pid, _p in swept:  # every point's rate is 1.0, from a different run count
        results[pid]["claims"]["C2"]["measured"] = {"r": 1.0, "runs": 10 + len(pid)}
    rows = sweep.tabulate(space, swept, results)
    c2 = sweep.summarise(space, rows, points)["C2"]
    assert {r["C2.value"] for r in rows} == {1.0} and c2["evaluations"] == 1
    assert c2["records"] == len({10 + len(pid) for pid, _ in swept}) > 1
    low = c2["interval"]["low"]  # the interval counts the records, not the one headline
    assert low > sweep.summarise(space, [{k: v for k, v in r.items() if not k.endswith(".record")}
                                         for r in rows], points)["C2"]["interval"]["low"]


def test_failed_points_are_counted_and_reported(toy: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)[:3]
    swept, results = _results(points, lambda p: True)
    results["p1"] = {"status": "failed", "error": "ValidationError: bad"}
    rows = sweep.tabulate(space, swept, results)
    assert rows[1]["status"] == "failed" and rows[1]["error"] == "ValidationError: bad"
    assert rows[1]["C1.outcome"] == "error"
    summary = sweep.summarise(space, rows, points)
    assert summary["C1"]["points"] == 2 and summary["C1"]["failed_points"] == 1


def test_plot_of_an_undetermined_claim(toy: Path, tmp_path: Path) -> None:
    space = _space(toy)
    points = spaces.design(space)
    swept, results = _results(points, lambda p: p["scale"] < 0.2)
    rows = sweep.tabulate(space, swept, results)
    entry = sweep.summarise(space, rows, points)["C1"]
    a = sweep.plot_claim(space, "C1", rows, points, entry, tmp_path / "a.png")
    b = sweep.plot_claim(space, "C1", rows, points, entry, tmp_path / "b.png")
    assert a.read_bytes() == b.read_bytes() and a.stat().st_size > 10_000


def test_last_line_of_an_error() -> None:
    class Exec(Exception):
        ename, evalue = "ValidationError", "parameter T must be an integer"

    assert sweep._last_line(Exec()) == "ValidationError: parameter T must be an integer"
    assert sweep._last_line(RuntimeError("a\nb\n")) == "RuntimeError: b"


# ---------------------------------------------------------------------------- a real cluster


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_for_workers(address: str, n: int, timeout: float = 60.0) -> None:
    from dask.distributed import Client

    with Client(address, timeout=timeout) as client:
        client.wait_for_workers(n, timeout=timeout)


SWEEP_TOY = """# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% tags=["parameters"]
mode = "paper"  # "paper" or "fast" (ours)
scale = 0.15  # a MISSING value (MISSING)
seed = 0  # seed (MISSING)
figures = True  # figure making (ours)
fig_dir = "figures/sweeptoy"
results_path = "figures/sweeptoy/claims.json"

# %%
import json
import os
import sys

value = scale * (seed + 1)
claims = {"C1": {"paper": "value below 0.2", "source": "ours", "check": "value < 0.2",
                 "measured": value, "threshold": 0.2, "holds": value < 0.2,
                 "verdict": "holds" if value < 0.2 else "fails"}}
os.makedirs(os.path.dirname(results_path), exist_ok=True)
with open(results_path, "w") as fh:
    json.dump(claims, fh)
print(sys.executable)
"""


def test_a_remote_cluster_gives_the_same_table_as_a_local_one(tmp_path: Path) -> None:
    """A scheduler and two workers started as separate processes on 127.0.0.1 run a toy
    notebook's sweep (a real papermill execution per point, in about a second)."""
    root = tmp_path / "repo"
    (root / "notebooks").mkdir(parents=True)
    (root / "notebooks" / "sweeptoy.py").write_text(SWEEP_TOY)
    points = {"sweeptoy": [{"scale": 0.1, "seed": 0}, {"scale": 0.15, "seed": 1}]}
    base = {"sweeptoy": {"mode": "fast"}}
    local = sweep.run_sweep(
        ["sweeptoy"],
        workers=2,
        build=tmp_path / "b1",
        out=tmp_path / "o1",
        points=points,
        base=base,
        progress=False,
        root=root,
    )
    address = f"tcp://127.0.0.1:{_free_port()}"
    dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    procs = [
        subprocess.Popen(
            [*dask, "--host", "127.0.0.1", "--port", address.rsplit(":", 1)[1], "--no-dashboard"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        time.sleep(1.0)
        for _ in range(2):
            procs.append(
                subprocess.Popen(
                    [
                        sys.executable,
                        "-m",
                        "distributed.cli.dask_worker",
                        address,
                        "--nthreads",
                        "1",
                        "--no-dashboard",
                    ],
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                    cwd=ROOT,
                )
            )
        _wait_for_workers(address, 2)
        remote = sweep.run_sweep(
            ["sweeptoy"],
            scheduler=address,
            build=tmp_path / "b2",
            out=tmp_path / "o2",
            points=points,
            base=base,
            progress=False,
            root=root,
        )
    finally:
        for proc in reversed(procs):
            proc.terminate()
        for proc in procs:
            proc.wait(timeout=30)
    assert local["sweeptoy"]["failed"] == remote["sweeptoy"]["failed"] == 0
    table = (tmp_path / "o1" / "sweeptoy" / "robustness.csv").read_text()
    assert table == (tmp_path / "o2" / "sweeptoy" / "robustness.csv").read_text()
    assert table.count("\n") == 3 and ",ok," in table
    assert [row["C1.holds"] for row in csv.DictReader(io.StringIO(table))] == ["True", "False"]
    summary = json.loads((tmp_path / "o2" / "sweeptoy" / "robustness.json").read_text())
    assert summary["C1"]["verdict"] == "undetermined" and summary["C1"]["points"] == 2
    for build in ("b1", "b2"):  # each point executed in its own folder, figures off
        executed = sorted((tmp_path / build / "sweeptoy").glob("*/sweeptoy.ipynb"))
        assert len(executed) == 2
        for e in executed:
            injected = json.loads(e.read_text())["metadata"]["papermill"]["parameters"]
            assert injected["mode"] == "fast" and injected["figures"] is False


def test_robustness_markdown_lists_every_claim_of_the_summary() -> None:
    from secest.repro import results

    summary = json.loads((ROOT / "figures" / "lee2020" / "robustness.json").read_text())
    table = results.robustness_markdown("lee2020").splitlines()
    assert table[0] == "| claim | verdict over the space | holds at | region |"
    assert [row.split(" | ")[0].lstrip("| ") for row in table[2:]] == list(summary)
    assert all(row.count(" | ") == 3 for row in table[2:])  # '|' in a region is escaped
    assert results.robustness_markdown("no-such-notebook") is None


@pytest.mark.parametrize("kw, match", [
    ({"workers": 0}, "workers"),
    ({"workers": -2}, "workers"),
    ({"scheduler": "localhost"}, "scheduler must be an address"),
])
def test_run_sweep_refuses_a_bad_cluster_before_starting_one(kw: dict, match: str) -> None:
    from secest.core.validation import ValidationError

    with pytest.raises(ValidationError, match=match):
        sweep.run_sweep(["guo2023"], progress=False, **kw)


def test_region_on_a_seed_axis_names_the_failing_draws(toy: Path) -> None:
    """An axis declared as a seed (``draw = true``) is not ordered: the region names the draws
    where the claim fails, never a threshold; the same axis without ``draw`` gives a threshold."""
    toml = toy / "notebooks" / "toy.toml"
    draws = [0, 603371, 994542, 29109]
    for draw in (False, True):
        toml.write_text(TOY_TOML.replace(
            "space = { values = [0, 1] }",
            f"space = {{ values = {draws}{', draw = true' if draw else ''} }}"))
        space = _space(toy)
        assert space.axes["seed"].draw is draw
        points = [{"scale": 0.2, "alpha": 0.6, "seed": s} for s in draws for _ in range(2)]
        swept, results = _results(points, lambda p: p["seed"] != 994542)
        rows = sweep.tabulate(space, swept, results)
        region = sweep.summarise(space, rows, points)["C1"]["region"]
        if draw:
            assert region == ("holds exactly where seed is not the draw 994542 (fails there; seed is a "
                              "seed: its 4 swept draws are named, not ordered) (6 of 8 points)")
        else:
            assert region.startswith("holds exactly where seed <= 603371")  # ordered: a threshold
    # two failing draws are both named; a draw that fails everywhere names no region
    swept, results = _results(points, lambda p: p["seed"] in (0, 29109))
    rows = sweep.tabulate(space, swept, results)
    assert sweep.summarise(space, rows, points)["C1"]["region"].startswith(
        "holds exactly where seed is not the draws 603371, 994542 (fails there")
    toml.write_text(TOY_TOML.replace("space = { values = [0, 1] }",
                                              "space = { values = [0, 1], draw = 1 }"))
    with pytest.raises(ValueError, match="draw must be true or false"):
        _space(toy)


def test_a_sampled_seed_range_is_a_draw_axis(toy: Path) -> None:
    toml = toy / "notebooks" / "toy.toml"
    toml.write_text(TOY_TOML.replace(
        "space = { values = [0, 1] }", "space = { low = 0, high = 1000000, integer = true, draw = true }"))
    space = _space(toy)
    assert space.axes["seed"].draw and space.axes["seed"].kind == "sample"
    points = [{"scale": 0.2, "alpha": 0.6, "seed": s} for s in (17, 400003, 999, 123456)]
    swept, results = _results(points, lambda p: p["seed"] != 999)
    rows = sweep.tabulate(space, swept, results)
    region = sweep.summarise(space, rows, points)["C1"]["region"]
    assert region.startswith("holds exactly where seed is not the draw 999 (fails there")
    assert "draws of a seed (unordered)" in space.parameters["seed"].space_text()
