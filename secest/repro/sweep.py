"""Robustness sweeps: run a notebook over the design of its declared space, on Dask.

A verdict measured at one point of a space the paper does not pin down is an
opinion. ``make robustness [NB=<key>]`` (``python -m secest.repro.sweep KEY ...``)
executes each notebook with papermill at every point of the design of its
declared space (:func:`secest.repro.spaces.design`), figures off, and writes

``figures/<key>/robustness.csv``
   one row per point: its parameters, status, and for each claim ``<id>.outcome``
   (holds / fails / fails-premise), ``<id>.holds`` and ``<id>.value``;
``figures/<key>/robustness.json``
   per claim: the verdict over the space (``holds``, ``fails``, ``fails-premise``
   everywhere, else ``undetermined``), the fraction of points where it holds with a
   Wilson interval, and the region;
``figures/<key>/robustness_<id>.png``
   for every claim whose outcome varies: where it holds over the swept axes.

The notebooks read ``robustness.json`` when they write their claims
(:func:`secest.repro.results.write_claims`), so run ``make robustness`` before ``make figures``.

Execution: a Dask ``LocalCluster`` with one single-threaded worker process per
core by default, or an existing cluster with ``--scheduler tcp://host:port``
(its workers must run this environment and see this repository's folder).
Each point runs in its own folder ``build/sweeps/<key>/<id>/``, where ``<id>``
hashes the point's parameters, the notebook source and the ``secest`` sources (the arena's
methods and scenario cards included; not the tooling: this module, ``verify``, ``site``):
a re-run reuses every finished point, a changed notebook or library re-runs
them all. A failed point is reported with its parameters and the last line of
its error, counted, and makes the command exit non-zero; it is never dropped.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import os
import sys
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from secest.core.validation import ValidationError, check_positive_int
from secest.repro import spaces
from secest.repro.results import POINT_OUTCOMES, headline_value, point_verdict, repo_root

__all__ = [
    "describe_region",
    "main",
    "run_point",
    "run_sweep",
    "summarise",
    "tabulate",
]

OUTCOMES = POINT_OUTCOMES


# ---------------------------------------------------------------------------- points and caching


TOOLING = frozenset({"secest/repro/sweep.py", "secest/repro/verify.py", "secest/repro/site.py"})
"""Modules that never run inside a notebook: they do not enter a point's id."""


def source_hash(key: str, root: Path | None = None) -> str:
    """Hash of ``notebooks/<key>.py`` (under ``root``, default this repository) and every
    source and card file of ``secest`` a notebook can run (its ``*.py`` and ``*.toml``,
    subpackages such as ``secest/methods`` included; not :data:`TOOLING`): what a point's
    result depends on."""
    package_root = repo_root()
    h = hashlib.sha256()
    package = sorted(
        p
        for p in (package_root / "secest").rglob("*")
        if p.suffix in (".py", ".toml") and p.is_file()
        and p.relative_to(package_root).as_posix() not in TOOLING
    )
    h.update(f"notebooks/{key}.py".encode())
    h.update(((root or package_root) / "notebooks" / f"{key}.py").read_bytes())
    for path in package:
        h.update(path.relative_to(package_root).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def point_id(key: str, parameters: Mapping[str, Any], src: str) -> str:
    """Short id of a point: a hash of the key, its parameters and the source hash."""
    text = json.dumps({"key": key, "parameters": parameters, "source": src}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def build_source(key: str, folder: Path, src: str, root: Path | None = None) -> Path:
    """Build ``notebooks/<key>.py`` into a fresh ``.ipynb`` (so sweeps never run a stale one)."""
    from secest.repro.build import notebook_from_source

    path = folder / f"source-{src[:12]}.ipynb"
    if not path.exists():
        folder.mkdir(parents=True, exist_ok=True)
        notebook_from_source(key, path, root)
    return path


def run_point(
    key: str, source: str, parameters: Mapping[str, Any], folder: str, root: str | None = None
) -> dict[str, Any]:
    """Execute one point (on a Dask worker) and return its status and claims.

    Parameters
    ----------
    key : str
        Paper key.
    source : str
        The notebook to execute (built from the ``.py`` by :func:`build_source`).
    parameters : mapping
        Every parameter injected at this point (base and swept values).
    folder : str
        The point's own folder; holds ``params.json``, the executed notebook,
        ``claims.json`` and ``status.json``.
    root : str, optional
        Folder holding ``notebooks/`` (see :func:`run_sweep`); default: this repository.

    Returns
    -------
    dict
        ``{"status": "ok", "claims": {...}}`` or ``{"status": "failed", "error": last line}``.
    """
    from secest.repro.run import execute_notebook

    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    (out / "params.json").write_text(json.dumps(parameters, indent=1, sort_keys=True) + "\n")
    params = dict(parameters) | {
        "figures": False,
        "fig_dir": str(out / "figures"),
        "results_path": str(out / "claims.json"),
    }
    try:
        execute_notebook(key, params, out / f"{key}.ipynb", source=source, root=root)
        result: dict[str, Any] = {
            "status": "ok",
            "claims": json.loads((out / "claims.json").read_text()),
        }
    except Exception as exc:  # noqa: BLE001 - every failure is recorded with its last line
        result = {"status": "failed", "error": _last_line(exc)}
    (out / "status.json").write_text(
        json.dumps({k: v for k, v in result.items() if k != "claims"}) + "\n"
    )
    return result


def _last_line(exc: BaseException) -> str:
    ename, evalue = getattr(exc, "ename", None), getattr(exc, "evalue", None)
    if ename:
        return f"{ename}: {evalue}".splitlines()[-1] if evalue else ename
    lines = [line for line in str(exc).strip().splitlines() if line.strip()]
    return f"{type(exc).__name__}: {lines[-1] if lines else ''}"


def _cached(folder: Path) -> dict[str, Any] | None:
    status, claims = folder / "status.json", folder / "claims.json"
    if status.exists() and claims.exists() and json.loads(status.read_text())["status"] == "ok":
        return {"status": "ok", "claims": json.loads(claims.read_text())}
    return None


# ---------------------------------------------------------------------------- execution on Dask


def _client(scheduler: str | None, workers: int | None) -> tuple[Any, Any]:
    from dask.distributed import Client, LocalCluster

    if scheduler is not None:
        return Client(scheduler), None
    n = workers if workers is not None else len(os.sched_getaffinity(0))
    # ":0": the scheduler's HTTP server on a free port (no clash with another cluster's 8787)
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0")
    return Client(cluster), cluster


def run_sweep(
    keys: Sequence[str],
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    build: str | Path = "build/sweeps",
    out: str | Path | None = None,
    points: Mapping[str, list[dict[str, Any]]] | None = None,
    base: Mapping[str, Mapping[str, Any]] | None = None,
    fresh: bool = False,
    progress: bool = True,
    root: str | Path | None = None,
) -> dict[str, dict[str, Any]]:
    """Run the robustness sweep of every notebook in ``keys`` on one Dask cluster.

    Parameters
    ----------
    keys : sequence of str
        Paper keys.
    scheduler : str, optional
        Address of an existing Dask scheduler (``tcp://host:port``); a
        ``LocalCluster`` of ``workers`` processes (default: one per core) otherwise.
    workers : int, optional
        Size of the ``LocalCluster``.
    build : str or Path
        Folder of the point folders (resolved from the repository root).
    out : str or Path, optional
        Where ``<key>/robustness.*`` are written; ``figures/`` by default.
    points, base : mapping of key to points / parameters, optional
        Replace the design of :func:`secest.repro.spaces.design` and the ``[sweep] base``
        (used by tests and benchmarks to run small sweeps).
    fresh : bool
        Ignore finished points and run everything again.
    progress : bool
        Show a progress bar on standard error.
    root : str or Path, optional
        Folder laid out like this repository whose ``notebooks/<key>.py`` and
        ``.toml`` are swept (a test's toy notebook); default: this repository. The
        workers must see it at the same path.

    Returns
    -------
    dict
        Per key: ``rows`` (the table), ``summary`` (per claim) and ``failed`` (count).
    """
    from dask.distributed import as_completed

    if workers is not None:
        check_positive_int("workers", workers)
    if scheduler is not None and (not isinstance(scheduler, str) or "://" not in scheduler):
        raise ValidationError(f"scheduler must be an address like 'tcp://host:8786', "
                              f"found {scheduler!r}")
    build_dir, out_dir = Path(build), Path(out) if out is not None else repo_root() / "figures"
    build_dir = build_dir if build_dir.is_absolute() else repo_root() / build_dir
    top = Path(root) if root is not None else None
    plans = {k: _plan(k, build_dir, points, base, top) for k in keys}
    results: dict[str, dict[str, dict]] = {k: {} for k in keys}
    todo = []
    for key, plan in plans.items():
        for pid, params in plan["points"]:
            hit = None if fresh else _cached(build_dir / key / pid)
            if hit is not None:
                results[key][pid] = hit
            else:
                todo.append((key, pid, params))
    if todo:
        client, cluster = _client(scheduler, workers)
        try:
            futures = {
                client.submit(
                    run_point,
                    key,
                    str(plans[key]["source"]),
                    params,
                    str(build_dir / key / pid),
                    None if top is None else str(top),
                    key=f"{key}-{pid}",
                    pure=False,
                ): (key, pid)
                for key, pid, params in todo
            }
            bar = _progress(len(todo), len(plans), progress)
            for fut in as_completed(futures):
                key, pid = futures[fut]
                results[key][pid] = fut.result()
                if results[key][pid]["status"] == "failed":
                    _report_failure(key, plans[key]["swept"][pid], results[key][pid]["error"], bar)
                bar.update(1)
            bar.close()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    return {key: _finish(key, plans[key], results[key], out_dir) for key in keys}


def _plan(
    key: str, build_dir: Path, points: Mapping | None, base: Mapping | None, root: Path | None
) -> dict[str, Any]:
    space = spaces.load(key, root)
    src = source_hash(key, root)
    design = list(points[key]) if points is not None and key in points else spaces.design(space)
    fixed = dict(base[key]) if base is not None and key in base else dict(space.base)
    planned, swept = [], {}
    for point in design:
        params = spaces.validate(space, fixed | point)
        pid = point_id(key, params, src)
        planned.append((pid, params))
        swept[pid] = point
    return {
        "space": space,
        "points": planned,
        "swept": swept,
        "source": build_source(key, build_dir / key, src, root),
    }


def _progress(total: int, notebooks: int, enabled: bool) -> Any:
    from tqdm import tqdm

    return tqdm(
        total=total,
        desc=f"sweep ({notebooks} notebooks)",
        unit="point",
        disable=not enabled,
        file=sys.stderr,
    )


def _report_failure(key: str, point: Mapping[str, Any], error: str, bar: Any) -> None:
    shown = ", ".join(f"{k}={spaces.format_value(v)}" for k, v in point.items())
    bar.write(f"FAILED {key} point ({shown}): {error}")


# ---------------------------------------------------------------------------- tables and summaries


def tabulate(space: spaces.Space, swept: Sequence[tuple[str, Mapping]], results: Mapping) -> list[dict]:
    """One row per point: id, swept parameters (labels), status, and each claim's outcome.

    Parameters
    ----------
    space : Space
        The notebook's declared space (for axis labels).
    swept : sequence of (id, point)
        The design in order.
    results : mapping id -> result of :func:`run_point`
    """
    ids = sorted(
        {cid for r in results.values() if r["status"] == "ok" for cid in r["claims"]}, key=_cid_key
    )
    names = list(dict.fromkeys(name for _, point in swept for name in point))
    rows = []
    for pid, point in swept:
        res = results[pid]
        row: dict[str, Any] = {"point": pid}
        for name in names:
            value = point.get(name)
            if name not in point:
                row[name] = ""
            elif name in space.axes:
                row[name] = space.axes[name].label(value)
            else:
                row[name] = spaces.format_value(value)
        row["status"] = res["status"]
        row["error"] = res.get("error", "")
        for cid in ids:
            entry = res.get("claims", {}).get(cid)
            row[f"{cid}.outcome"] = (
                point_verdict(entry) if entry else ("" if res["status"] == "ok" else "error")
            )
            row[f"{cid}.holds"] = "" if entry is None or entry["holds"] is None else bool(entry["holds"])
            value = headline_value(entry) if entry else None
            row[f"{cid}.value"] = "" if value is None else float(format(value, ".7g"))
            row[f"{cid}.record"] = _fingerprint(entry["measured"]) if entry else ""
        rows.append(row)
    return rows


def _fingerprint(measured: Any) -> str:
    """Short hash of a claim's whole measured record (numbers to 10 significant digits).

    Two points with the same fingerprint evaluated the claim identically (replicates); a
    headline value shared by different experiments (a rate saturating at 1) does not make
    them replicates.
    """
    def plain(x: Any) -> Any:
        if isinstance(x, Mapping):
            return {str(k): plain(v) for k, v in x.items()}
        if isinstance(x, list | tuple):
            return [plain(v) for v in x]
        if isinstance(x, float):
            return format(x, ".10g")
        return x

    text = json.dumps(plain(measured), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _cid_key(cid: str) -> tuple:
    import re

    parts = re.findall(r"\d+|\D+", cid)
    return (cid[0] != "C",) + tuple(int(p) if p.isdigit() else p for p in parts)


def summarise(space: spaces.Space, rows: Sequence[Mapping[str, Any]], points: Sequence[Mapping]) -> dict:
    """Per claim: verdict over the declared space, fraction holding (Wilson 95 %), region.

    The verdict is decided on the points where the claim was checked and its premise
    holds (outcome ``holds`` or ``fails``): ``holds`` (``fails``) when it holds (fails) at
    every such point, else ``undetermined``. With no such point it is ``fails-premise`` if
    the premise fails somewhere, else ``not-checked``. Points where the premise fails or
    that were not checked are counted and shown, never counted as failures. The fraction
    holding and its Wilson interval are over the decided points, treated as a sample of
    the declared space, but the interval counts each distinct record of the decided points
    once: points that reproduce one measurement are not independent samples. A record is a
    decided outcome with the claim's whole measured record (``<id>.record``, a fingerprint: a
    headline value shared by different experiments, such as a rate saturating at 1, does not
    make them one; rows without records fall back to the headline value); at a point where the
    premise fails or the claim was not checked, the outcome with its headline value.
    ``evaluations`` counts the distinct (outcome, headline value) pairs of all its points: 1
    means every point gave the same outcome and value (the swept axes do not change it, whether
    or not they enter it), so "holds everywhere" is one evaluation; ``records`` counts the
    distinct records (1: every point measured exactly the same, exact replicates).

    Parameters
    ----------
    space : Space
        The notebook's declared space (for the axes and their kinds).
    rows : sequence of mapping
        The table of :func:`tabulate`, one row per point.
    points : sequence of mapping
        The design points (parameter name -> value), aligned with ``rows``.

    Returns
    -------
    dict
        Claim id -> ``verdict``, ``points`` (finished points with an outcome),
        ``decided`` (points with outcome holds or fails), ``evaluations`` (distinct
        outcome-value pairs), ``records`` (distinct records), ``failed_points`` (points
        that did not finish), ``outcomes``
        (count per outcome), ``fraction_holds``, ``interval`` (a :func:`secest.repro.results.interval`
        entry), ``region`` (:func:`describe_region`) and ``axes`` (the axes it was
        described over). Claims without any finished point are left out.
    """
    from secest.core.montecarlo import wilson_interval
    from secest.repro.results import interval

    columns = dict.fromkeys(c for row in rows for c in row)
    claim_ids = [c[: -len(".outcome")] for c in columns if c.endswith(".outcome")]
    summary = {}
    for cid in claim_ids:
        ok = [(r, p) for r, p in zip(rows, points, strict=True) if r.get(f"{cid}.outcome") in OUTCOMES]
        outcomes = [r[f"{cid}.outcome"] for r, _ in ok]
        counts = {o: outcomes.count(o) for o in OUTCOMES}
        n = len(outcomes)
        if n == 0:
            continue
        verdict, decided = _space_verdict(counts)
        evaluations = len({(r[f"{cid}.outcome"], r.get(f"{cid}.value")) for r, _ in ok})
        evaluated = [_evaluation(r, cid) for r, _ in ok]
        distinct = {e for e in evaluated if e[0] in ("holds", "fails")}
        held = sum(o == "holds" for o, _ in distinct)
        lo, hi = wilson_interval(held, len(distinct)) if distinct else (0.0, 1.0)
        names = dict.fromkeys(name for _, p in ok for name in p)
        axes = {
            name: [p[name] for _, p in ok]
            for name in names
            if all(name in p for _, p in ok)
            and (name not in space.axes or space.axes[name].kind != "tied")
        }
        summary[cid] = {
            "verdict": verdict,
            "points": n,
            "decided": decided,
            "evaluations": evaluations,
            "records": len(set(evaluated)),
            "failed_points": sum(1 for r in rows if r["status"] != "ok"),
            "outcomes": counts,
            "fraction_holds": counts["holds"] / decided if decided else None,
            "interval": interval(
                lo, hi, method="wilson, distinct records of the decided design points as a sample "
                "of the declared space"
            ),
            "region": _region(space, axes, outcomes),
            "axes": list(axes),
        }
    return summary


def _evaluation(row: Mapping[str, Any], cid: str) -> tuple:
    """A point's evaluation of ``cid``: a decided outcome with its whole measured record (where
    tabulated); a point whose premise fails or that was not checked did not evaluate the claim,
    so there the outcome with its headline value (the premise's measure, typically)."""
    outcome = row[f"{cid}.outcome"]
    if outcome in ("holds", "fails") and row.get(f"{cid}.record"):
        return (outcome, row[f"{cid}.record"])
    return (outcome, row.get(f"{cid}.value"))


def _space_verdict(counts: Mapping[str, int]) -> tuple[str, int]:
    """The verdict over the space from the outcome counts, and the number of decided points."""
    decided = counts["holds"] + counts["fails"]
    if decided == 0:
        return ("fails-premise" if counts["fails-premise"] else "not-checked"), 0
    if counts["fails"] == 0:
        return "holds", decided
    return ("fails" if counts["holds"] == 0 else "undetermined"), decided


def _region(space: spaces.Space, axes: Mapping[str, list], outcomes: Sequence[str]) -> str:
    """:func:`describe_region` of the outcomes; when the claim never fails where its
    premise holds, the region says so and describes where the premise fails."""
    if "fails" in outcomes or "holds" not in outcomes or "fails-premise" not in outcomes:
        return describe_region(space, axes, [o == "holds" for o in outcomes])
    where = describe_region(space, axes, [o == "fails-premise" for o in outcomes],
                            words=("the premise fails", "the premise holds"))
    held = f"{outcomes.count('holds')} of {len(outcomes)} points"
    return f"holds wherever its premise holds ({held}); {where}"


def describe_region(
    space: spaces.Space, axes: Mapping[str, list], holds: Sequence[bool],
    words: tuple[str, str] = ("holds", "fails"),
) -> str:
    """Where a claim holds, in words: the best one-axis rule and how often it is right.

    For a numeric axis the rule is a threshold (holds where the value is below, or
    above, a cut between two swept values); for a set of non-numeric values it is
    a subset of levels; for a seed (an axis declared with ``draw = true``) it names the
    draws where the claim fails (or holds, if fewer), never a threshold: a seed's values
    are not ordered. When no rule is right at every point the best one is given
    with its accuracy, followed by the fraction holding at each level of every set.

    Parameters
    ----------
    space : Space
        The notebook's declared space (axis kinds and labels).
    axes : mapping of str to list
        Axis name -> its value at each point (a parameter not declared as an axis
        of ``space`` is treated as a set of its values).
    holds : sequence of bool
        Whether the claim holds at each point, aligned with the lists of ``axes``.
    words : tuple of str, optional
        What ``holds`` true and false say (default the claim's ``"holds"`` and
        ``"fails"``; e.g. ``("the premise fails", "the premise holds")``).

    Returns
    -------
    str
        One sentence, e.g. ``"holds exactly where n >= 4 (the next swept value, 3,
        is on the other side) (12 of 16 points)"``.
    """
    n = len(holds)
    if all(holds):
        return f"{words[0]} at all {n} points of the declared space"
    if not any(holds):
        return f"{words[0]} at none of the {n} points of the declared space"
    rules = [_best_rule(space, name, values, holds, words) for name, values in axes.items()]
    rules = [r for r in rules if r is not None]
    accuracy, text = max(rules, key=lambda r: r[0]) if rules else (0.0, "")
    if accuracy == 1.0:
        return f"{words[0]} exactly where {text} ({sum(holds)} of {n} points)"
    pair = _pair_region(space, axes, holds, words)
    if pair is not None:
        return f"{pair} ({sum(holds)} of {n} points; no single axis separates it)"
    levels = []
    for name, values in axes.items():
        axis = space.axes.get(name)
        if axis is not None and axis.kind == "set" and len(axis.values) > 1:
            parts = []
            for v in axis.values:
                sel = [h for x, h in zip(values, holds, strict=True) if spaces._same(x, v)]
                if sel:
                    parts.append(f"{axis.label(v)}: {sum(sel)}/{len(sel)}")
            levels.append(f"{name} ({', '.join(parts)})")
    counted = "holding" if words[0] == "holds" else words[0]
    tail = f"; {counted} per level: " + "; ".join(levels) if levels else ""
    best = f", the best rule is '{text}' (right at {accuracy:.0%} of points)" if rules else ""
    return f"{words[0]} at {sum(holds)} of {n} points; no one- or two-axis rule separates it{best}{tail}"


def _pair_region(
    space: spaces.Space, axes: Mapping[str, list], holds: Sequence[bool],
    words: tuple[str, str] = ("holds", "fails"),
) -> str | None:
    """A region that two set-valued axes decide together, in words, or None.

    When every combination of levels of two axes holds everywhere or fails everywhere,
    the region is the list of combinations where it fails (or holds, if shorter).
    """
    names = [n for n in axes if n in space.axes and space.axes[n].kind == "set"]
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            cells: dict[tuple[str, str], set[bool]] = {}
            for va, vb, h in zip(axes[a], axes[b], holds, strict=True):
                cells.setdefault((space.axes[a].label(va), space.axes[b].label(vb)), set()).add(h)
            if all(len(v) == 1 for v in cells.values()):
                fail = sorted(c for c, v in cells.items() if True not in v)
                hold = sorted(c for c, v in cells.items() if True in v)
                shown, verb = (fail, words[1]) if len(fail) <= len(hold) else (hold, words[0])
                where = "; ".join(f"{a} = {x} and {b} = {y}" for x, y in shown)
                other = words[0] if verb == words[1] else words[1]
                return f"{verb} exactly where {where}, {other} elsewhere"
    return None


def _best_rule(space: spaces.Space, name: str, values: list, holds: Sequence[bool],
               words: tuple[str, str] = ("holds", "fails")) -> tuple | None:
    axis = space.axes.get(name, spaces.Axis(values=tuple(dict.fromkeys(map(json.dumps, values)))))
    if axis.draw:
        return _draw_rule(name, values, holds, words)
    if name not in space.axes:
        values = [json.dumps(v) for v in values] if not _numeric(values) else values
    if _numeric(values) and len(set(values)) > 1:
        cuts = sorted(set(values))
        best = None
        for lo, hi in zip(cuts, cuts[1:], strict=False):
            below = [v <= lo for v in values]
            for sign, pred in (("<=", below), (">=", [not b for b in below])):
                acc = sum(p == h for p, h in zip(pred, holds, strict=True)) / len(holds)
                bound = lo if sign == "<=" else hi
                other = hi if sign == "<=" else lo
                text = (
                    f"{name} {sign} {spaces.format_value(bound)} "
                    f"(the next swept value, {spaces.format_value(other)}, is on the other side)"
                )
                if best is None or acc > best[0]:
                    best = (acc, text)
        return best
    if axis.kind == "set" and len(axis.values) > 1:
        good = [
            v
            for v in axis.values
            if _mean([h for x, h in zip(values, holds, strict=True) if spaces._same(x, v)]) > 0.5
        ]
        if not good or len(good) == len(axis.values):
            return None  # "holds at every level" or "at none" says nothing about where
        pred = [any(spaces._same(x, g) for g in good) for x in values]
        acc = sum(p == h for p, h in zip(pred, holds, strict=True)) / len(holds)
        shown = ", ".join(axis.label(g) for g in good)
        return acc, f"{name} in {{{shown}}}"
    return None


def _draw_rule(name: str, values: list, holds: Sequence[bool], words: tuple[str, str]) -> tuple | None:
    """The rule of a seed axis (``draw = true``): the draws where the claim fails, by name.

    A seed's values are draws and carry no order, so no threshold is offered: the rule is the
    set of draws where ``words[1]`` is the majority (or, if fewer, where ``words[0]`` is), named.
    """
    draws = list(dict.fromkeys(json.dumps(v) for v in values))
    if len(draws) < 2:
        return None
    keyed = [json.dumps(v) for v in values]
    bad = [d for d in draws if _mean([h for x, h in zip(keyed, holds, strict=True) if x == d]) < 0.5]
    if not bad or len(bad) == len(draws):
        return None  # the same at every draw: a seed says nothing about where
    pred = [x not in bad for x in keyed]
    acc = sum(p == h for p, h in zip(pred, holds, strict=True)) / len(holds)
    good = [d for d in draws if d not in bad]
    shown, side = (bad, words[1]) if len(bad) <= len(good) else (good, words[0])
    listed = ", ".join(spaces.format_value(json.loads(d)) for d in shown)
    noun = "draw" if len(shown) == 1 else "draws"
    if side == words[1]:
        text = f"{name} is not the {noun} {listed} ({words[1]} there"
    else:
        text = f"{name} is the {noun} {listed} ({words[1]} at the other {len(bad)}"
    return acc, text + f"; {name} is a seed: its {len(draws)} swept draws are named, not ordered)"


def _numeric(values: Sequence[Any]) -> bool:
    return all(isinstance(v, int | float) and not isinstance(v, bool) for v in values)


def _mean(xs: list[bool]) -> float:
    return sum(xs) / len(xs) if xs else 0.0


# ---------------------------------------------------------------------------- outputs


def _finish(
    key: str, plan: Mapping[str, Any], results: Mapping[str, dict], out_dir: Path
) -> dict[str, Any]:
    space = plan["space"]
    swept = [(pid, plan["swept"][pid]) for pid, _ in plan["points"]]
    rows = tabulate(space, swept, results)
    summary = summarise(space, rows, [p for _, p in swept])
    folder = out_dir / key
    folder.mkdir(parents=True, exist_ok=True)
    _write_csv(folder / "robustness.csv", rows)
    (folder / "robustness.json").write_text(json.dumps(summary, indent=2, sort_keys=True) + "\n")
    for old in folder.glob("robustness_*.png"):
        old.unlink()
    for cid, entry in summary.items():
        if entry["verdict"] == "undetermined":
            plot_claim(space, cid, rows, [p for _, p in swept], entry, folder / f"robustness_{cid}.png",
                       threshold=_common_threshold(results, cid))
    failed = sum(1 for r in rows if r["status"] != "ok")
    return {"rows": rows, "summary": summary, "failed": failed}


def _common_threshold(results: Mapping[str, dict], cid: str) -> float | None:
    """The claim's threshold when it is one number, the same at every finished point."""
    values = {
        json.dumps(r["claims"][cid].get("threshold"))
        for r in results.values()
        if r["status"] == "ok" and cid in r["claims"]
    }
    if len(values) != 1:
        return None
    value = json.loads(values.pop())
    return float(value) if isinstance(value, int | float) and not isinstance(value, bool) else None


def _write_csv(path: Path, rows: Sequence[Mapping[str, Any]]) -> None:
    columns = list(dict.fromkeys(c for row in rows for c in row)) or ["point"]
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=columns, restval="", lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


def plot_claim(
    space: spaces.Space,
    cid: str,
    rows: Sequence[Mapping[str, Any]],
    points: Sequence[Mapping[str, Any]],
    entry: Mapping[str, Any],
    path: Path,
    *,
    threshold: float | None = None,
) -> Path:
    """Where claim ``cid`` holds: its value (or outcome) against the most telling swept axis.

    One panel per level of a second set-valued axis with 2–4 levels; markers by
    outcome (holds ●, fails ✕, premise fails ▲); ``threshold`` (the claim's, when it
    is one number) dashed; a positive numeric axis spanning two decades or more on
    a logarithmic scale. Saved deterministically as ``path``.
    """
    import matplotlib.pyplot as plt

    from secest.repro.plotting import COLUMN_WIDTH, use_style

    use_style()
    ok = [(r, p) for r, p in zip(rows, points, strict=True) if r[f"{cid}.outcome"] in OUTCOMES]
    axes = [a for a in entry["axes"] if a in space.axes]
    if not axes:  # points given by hand, outside the declared axes: plot against their index
        space = _indexed(space)
        ok = [(r, {"point index": i} | dict(p)) for i, (r, p) in enumerate(ok)]
        axes = ["point index"]
    x_axis = _x_axis(space, axes, ok, cid)
    facet = next(
        (
            a
            for a in axes
            if a != x_axis and space.axes[a].kind == "set" and 2 <= len(space.axes[a].values) <= 4
        ),
        None,
    )
    levels = list(space.axes[facet].values) if facet else [None]
    fig, panels = plt.subplots(
        1,
        len(levels),
        figsize=(COLUMN_WIDTH * min(2.0, 1.0 + 0.5 * len(levels)), COLUMN_WIDTH * 0.8),
        sharex=True,
        sharey=True,
        squeeze=False,
    )
    has_values = all(r[f"{cid}.value"] != "" for r, _ in ok)
    xs_all = [p[x_axis] for _, p in ok]  # one x scale for every panel, from all points
    log_x = space.axes[x_axis].log or (
        _numeric(xs_all) and bool(xs_all) and min(xs_all) > 0 and max(xs_all) / min(xs_all) >= 100)
    for ax, level in zip(panels[0], levels, strict=True):
        sel = [(r, p) for r, p in ok if level is None or spaces._same(p[facet], level)]
        _scatter(ax, space, x_axis, sel, cid, has_values, log_x)
        if threshold is not None and has_values:
            ax.axhline(threshold, color="0.4", ls="--", lw=0.9, label="threshold", zorder=2)
        title = f"{facet} = {space.axes[facet].label(level)}\n" if facet else ""
        held = sum(r[f"{cid}.outcome"] == "holds" for r, _ in sel)
        ax.set_title(f"{title}holds at {held}/{len(sel)}", fontsize=8)
        ax.set_xlabel(_axis_label(space, x_axis))
    panels[0][0].set_ylabel(f"{cid}: measured value" if has_values else f"{cid}: outcome")
    shown: dict[str, Any] = {}
    for ax in panels[0]:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            shown.setdefault(label, handle)
    handles, labels = list(shown.values()), list(shown)
    fig.legend(handles, labels, loc="outside lower center", ncols=len(labels), fontsize=7, frameon=False)
    fig.suptitle(
        f"{space.key} {cid}: holds at {entry['outcomes']['holds']} of {entry['points']} points "
        f"of the declared space",
        fontsize=9,
    )
    fig.set_layout_engine("constrained")
    fig.savefig(path, metadata={"Software": None})
    plt.close(fig)
    return path


def _indexed(space: spaces.Space) -> spaces.Space:
    from dataclasses import replace

    index = spaces.Parameter(
        name="point index", default=0, comment="", type="int", space=spaces.Axis(low=0.0, high=1.0)
    )
    return replace(space, parameters=space.parameters | {"point index": index})


def _x_axis(space: spaces.Space, axes: list[str], ok: list, cid: str) -> str:
    holds = [r[f"{cid}.outcome"] == "holds" for r, _ in ok]
    scored = [
        (rule[0], name)
        for name in axes
        if (rule := _best_rule(space, name, [p[name] for _, p in ok], holds)) is not None
    ]
    numeric = [s for s in scored if space.axes[s[1]].kind != "set" or _numeric(space.axes[s[1]].values)]
    pool = numeric or scored or [(0.0, axes[0])]
    return max(pool)[1]


def _axis_label(space: spaces.Space, name: str) -> str:
    unit = space.parameters[name].unit
    return f"{name} [{unit}]" if unit else name


def _scatter(ax: Any, space: spaces.Space, x_axis: str, sel: list, cid: str, has_values: bool,
             log_x: bool) -> None:
    axis = space.axes[x_axis]
    categorical = axis.kind == "set" and not _numeric(axis.values)
    if log_x and not categorical:
        ax.set_xscale("log")
    style = {"holds": ("o", "tab:blue"), "fails": ("x", "tab:red"), "fails-premise": ("^", "tab:gray"),
             "not-checked": ("D", "tab:olive")}
    for outcome, (marker, colour) in style.items():
        pts = [(r, p) for r, p in sel if r[f"{cid}.outcome"] == outcome]
        if not pts:
            continue
        xs = [_position(axis, p[x_axis]) if categorical else p[x_axis] for _, p in pts]
        ys = [
            float(r[f"{cid}.value"]) if has_values else (1.0 if outcome == "holds" else 0.0)
            for r, _ in pts
        ]
        ax.scatter(xs, ys, marker=marker, color=colour, s=18, label=outcome, zorder=3)
    if categorical:
        ax.set_xticks(range(len(axis.values)), [axis.label(v) for v in axis.values], rotation=20)
    if not has_values:
        ax.set_yticks([0, 1], ["fails", "holds"])


def _position(axis: spaces.Axis, value: Any) -> int:
    return next(i for i, v in enumerate(axis.values) if spaces._same(v, value))


# ---------------------------------------------------------------------------- manifest and CLI


def check_manifest(key: str, out_dir: Path | None = None) -> list[str]:
    """Problems with the robustness files of ``key``: listed but missing, or made but unlisted."""
    root = repo_root()
    with (root / "figures" / "manifest.toml").open("rb") as fh:
        manifest = tomllib.load(fh)
    listed = {name for entry in manifest.get(key, {}).get("robustness", []) for name in entry["files"]}
    folder = (out_dir or root / "figures") / key
    made = {f"figures/{key}/{p.name}" for p in folder.glob("robustness*")}
    problems = [f"listed in figures/manifest.toml but not produced: {n}" for n in sorted(listed - made)]
    problems += [f"produced but not listed in figures/manifest.toml: {n}" for n in sorted(made - listed)]
    return problems


def _print_summary(key: str, outcome: Mapping[str, Any]) -> None:
    print(f"{key}: {len(outcome['rows'])} points, {outcome['failed']} failed")
    for cid, s in sorted(outcome["summary"].items(), key=lambda kv: _cid_key(kv[0])):
        ci = s["interval"]
        share = ("no decided point" if s["fraction_holds"] is None else
                 f"{s['fraction_holds']:.0%} of {s['decided']} decided, 95 % CI "
                 f"[{ci['low']:.2f}, {ci['high']:.2f}]")
        print(
            f"  {cid:6s} {s['verdict']:13s} holds at {s['outcomes']['holds']}/{s['points']} ({share})"
            + (f": {s['region']}" if s["verdict"] == "undetermined" else "")
        )


def main(argv: Iterable[str] | None = None) -> int:
    """Command-line entry point: ``python -m secest.repro.sweep [KEY ...] [--scheduler ADDR]``.

    Parameters
    ----------
    argv : iterable of str, optional
        The arguments after the program name: paper keys (default: every notebook)
        and the options ``--scheduler ADDR``, ``--workers N``, ``--fresh`` and
        ``--list`` (see ``--help``). Default: ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 when every point finished and the robustness files match
        ``figures/manifest.toml``, 1 otherwise, 2 when a key or declared space is
        invalid (printed to stderr). argparse exits with status 2 on malformed arguments.
    """
    parser = argparse.ArgumentParser(
        prog="python -m secest.repro.sweep",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("keys", nargs="*", help="paper keys (default: every notebook)")
    parser.add_argument("--scheduler", help="address of an existing Dask scheduler, tcp://host:port")
    parser.add_argument("--workers", type=int, help="LocalCluster workers (default: one per core)")
    parser.add_argument("--fresh", action="store_true", help="re-run finished points too")
    parser.add_argument("--list", action="store_true", help="print each design's points and exit")
    args = parser.parse_args(list(argv) if argv is not None else None)
    keys = args.keys or sorted(p.stem for p in (repo_root() / "notebooks").glob("*.py"))
    try:
        if args.list:
            for key in keys:
                design = spaces.design(spaces.load(key))
                print(f"{key}: {len(design)} points")
                for point in design:
                    print("  " + ", ".join(f"{k}={spaces.format_value(v)}" for k, v in point.items()))
            return 0
        outcomes = run_sweep(keys, scheduler=args.scheduler, workers=args.workers, fresh=args.fresh)
    except ValidationError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    status = 0
    for key, outcome in outcomes.items():
        _print_summary(key, outcome)
        problems = check_manifest(key)
        for problem in problems:
            print(f"  {problem}", file=sys.stderr)
        status |= bool(outcome["failed"] or problems)
    return int(status)


if __name__ == "__main__":
    sys.exit(main())
