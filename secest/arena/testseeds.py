"""The arena's test stage: the committed tuned constants, once, on the test seeds (issue #28).

After the validation (:mod:`secest.arena.tuning`) has chosen every method's constants per plant
and ``figures/arena/tuned.json`` is committed, :func:`run` scores, for every plant of that file,
every attack of the cards' ``[matrix]`` and every test seed of ``protocol.toml``, one trial
(:func:`secest.arena.scenarios.scenario` with ``horizon="auto"``, ``runs_per_seed`` runs): the
oracle once, then every method at its *printed* point (:func:`~secest.arena.tuning.grid`'s first)
and at its *tuned* point (the committed choice). Where the two are the same constants, the method
runs once and both rows report that run (``shared``).

A task is one trial (:func:`trial_task`); it returns, per method, each run's and node's error
second moments on the windows (:func:`summary`), not a finished score, so that the runs of the
eight test seeds pool as ``protocol.toml`` [score] says (:func:`pool`): the oracle's error
covariance over every pooled run, the 95 % bootstrap over every pooled run, the growth rule on
the pooled runs. With one seed, :func:`pool` gives what :func:`secest.arena.estimators.score`
gives on that trial; with several, what it gives on their runs concatenated into one trial.

The order is enforced here: :func:`committed` refuses a tuned file that git does not track or
that differs from its committed version, and the output records its commit and SHA-256, and the
commit of ``protocol.toml``. The output (``figures/arena/test.json``) holds deterministic content
only; a diverged row's growth numbers are rounded to 4 significant digits (capped at
:data:`GROWTH_CAP`), since amplified round-off differs between machines.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from secest.arena import estimators, matrix, protocol, scenarios, tuning
from secest.arena.estimators import METHODS, Estimate, Method
from secest.arena.scenarios import Scenario, Trial
from secest.core.validation import ValidationError, check_bool, check_positive_int

__all__ = [
    "GROWTH_CAP",
    "PROG",
    "Job",
    "committed",
    "jobs",
    "load_tuned",
    "main",
    "parser",
    "pool",
    "run",
    "summary",
    "trial_task",
]

GROWTH_CAP = 1e6
"""A diverged row's growth factor above this is written ``">1e6"`` (round-off decides its digits)."""
PROG = "python -m secest.arena.tuning test"


# ---------------------------------------------------------------------------------- the order


def _git(where: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["git", "-C", str(where), *args], capture_output=True, text=True,
                          check=False)


def committed(path: str | Path) -> dict[str, str]:
    """``path`` as git has committed it: refused unless tracked and unmodified.

    Parameters
    ----------
    path : str or Path
        The tuned constants (``figures/arena/tuned.json``), inside a git work tree.

    Returns
    -------
    dict
        ``file`` (its path in the repository), ``commit`` (the last commit that changed it) and
        ``sha256`` (of its bytes).

    Raises
    ------
    ValidationError
        If the file is missing, outside a git work tree, not tracked, or differs from ``HEAD``
        (staged or not): the tuned constants must be committed before the test seeds run.
    """
    file = Path(path).resolve()
    if not file.is_file():
        raise ValidationError(f"tuned must be an existing file, found {str(path)!r}")
    top = _git(file.parent, "rev-parse", "--show-toplevel")
    if top.returncode:
        raise ValidationError(f"tuned: {str(path)!r} is not in a git work tree; commit it first")
    rel = file.relative_to(Path(top.stdout.strip()).resolve()).as_posix()
    root = Path(top.stdout.strip())
    if _git(root, "ls-files", "--error-unmatch", "--", rel).returncode:
        raise ValidationError(f"tuned: {rel} is not tracked by git; commit it before the test "
                              "seeds run")
    if _git(root, "diff", "--quiet", "HEAD", "--", rel).returncode:
        raise ValidationError(f"tuned: {rel} differs from its committed version; commit it "
                              "before the test seeds run")
    commit = _git(root, "log", "-1", "--format=%H", "--", rel).stdout.strip()
    return {"file": rel, "commit": commit, "sha256": hashlib.sha256(file.read_bytes()).hexdigest()}


def _protocol_commit() -> str | None:
    """The last commit that changed ``secest/arena/protocol.toml`` (None outside a git checkout)."""
    here = Path(protocol.__file__).resolve().parent
    done = _git(here, "log", "-1", "--format=%H", "--", "protocol.toml")
    return (done.stdout.strip() or None) if done.returncode == 0 else None


def load_tuned(path: str | Path, *, short: bool = False) -> dict[str, Any]:
    """The committed tuned constants (:func:`committed`), read and checked against the protocol.

    Parameters
    ----------
    path : str or Path
        :func:`secest.arena.tuning.tune`'s JSON, committed.
    short : bool
        A smoke test: accept a tuning run of fewer seeds, runs or steps than the protocol's.

    Returns
    -------
    dict
        The file's content, with ``"committed"``: :func:`committed`'s record.

    Raises
    ------
    ValidationError
        Not committed; not a tuning result; made under another ``protocol.toml`` (its SHA-256);
        or, unless ``short``, not the protocol's full validation (seeds, runs, horizon).
    """
    record = committed(path)
    data = json.loads(Path(path).read_text())
    if not isinstance(data, dict) or not {"protocol", "tuned"} <= set(data):
        raise ValidationError(f"tuned: {record['file']} is not a tuning result (keys 'protocol', "
                              "'tuned')")
    if data["protocol"].get("sha256") != tuning._protocol_digest():
        raise ValidationError(f"tuned: {record['file']} was chosen under another protocol.toml "
                              "(its SHA-256 differs from this one's)")
    p = protocol.load()["seeds"]
    full = {"seeds": p["validation"], "runs_per_seed": p["runs_per_seed"], "horizon": "auto",
            "short": False}
    made = {k: data["protocol"].get(k) for k in full}
    if not short and made != full:
        raise ValidationError(f"tuned: {record['file']} is not the protocol's validation "
                              f"({made}, expected {full}); only a smoke test (short) accepts it")
    return data | {"committed": record}


# ---------------------------------------------------------------------------------- the rows


@dataclass
class Job:
    """One method run of a trial and the rows it reports.

    Attributes
    ----------
    method : str
        The registered method's name.
    rows : tuple of str
        ``("printed",)``, ``("tuned",)``, both (the same constants: one run for two rows) or
        ``("reference",)`` (the oracle).
    point : int
        Its grid index (:func:`secest.arena.tuning.grid`).
    estimator : Method
        The method built with the point's constants.
    constants : dict
        The point's search constants (JSON-ready).
    """

    method: str
    rows: tuple[str, ...]
    point: int
    estimator: Method
    constants: dict[str, Any]

    @property
    def key(self) -> str:
        """The job's name in a task's result: ``method/row+row``."""
        return f"{self.method}/{'+'.join(self.rows)}"


def _job(name: str, rows: tuple[str, ...], point: dict[str, Any]) -> Job:
    """The job of ``name`` at a grid point: the method built with the point's arguments."""
    method = type(METHODS[name])(**point["arguments"])
    method.name = name
    return Job(name, rows, point["point"], method, tuning._jsonable(point["constants"]))


def jobs(tuned: dict[str, Any], plant: str, ny: int) -> list[Job]:
    """Every method run of a trial on ``plant``: the oracle, then each method printed and tuned.

    Parameters
    ----------
    tuned : dict
        :func:`load_tuned`'s content.
    plant : str
        A plant (network card) of ``tuned["tuned"]``.
    ny : int
        Outputs per node (the chi-square thresholds of the grid).

    Returns
    -------
    list of Job
        The oracle's, then per method (in the file's order) one job per distinct point.

    Raises
    ------
    ValidationError
        A method not registered, or a chosen point whose constants are not the grid's there.
    """
    out = [Job("oracle", ("reference",), 0, METHODS["oracle"], {})]
    for name, choice in tuned["tuned"][plant].items():
        if name not in METHODS:
            raise ValidationError(f"tuned: method {name!r} is not registered")
        points = tuning.grid(name, ny)
        index = choice["point"]
        if index >= len(points) or tuning._jsonable(points[index]["constants"]) != choice["constants"]:
            raise ValidationError(f"tuned: {plant} {name} point {index} {choice['constants']} is "
                                  "not that point of the registered grid")
        if points[index]["arguments"] == points[0]["arguments"]:
            out.append(_job(name, ("printed", "tuned"), points[0]))
        else:
            out += [_job(name, ("printed",), points[0]), _job(name, ("tuned",), points[index])]
    return out


# ---------------------------------------------------------------------------------- one trial


def _moments(e: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per run and node, ``sum over steps of e e^T``: (runs, k, N, n) -> (runs, N, n, n)."""
    return np.einsum("rkia,rkib->riab", e, e)


def _alarm_counts(alarms: NDArray[np.bool_], attacked: NDArray[np.bool_]) -> dict[str, list[int]]:
    """Per run: alarms on attacked and on clean samples, and how many of each."""
    def per_run(a: NDArray[np.bool_]) -> list[int]:
        return a.reshape(a.shape[0], -1).sum(axis=1).tolist()

    return {"hits_attacked": per_run(alarms & attacked), "attacked": per_run(attacked),
            "hits_clean": per_run(alarms & ~attacked), "clean": per_run(~attacked)}


def summary(trial: Trial, est: Estimate, settle: int) -> dict[str, Any]:
    """What :func:`pool` needs of one method on one trial: error moments per window, alarm counts.

    Parameters
    ----------
    trial : Trial
        The runs.
    est : Estimate
        The method's estimates on them (the oracle's too: its own summary is its row's).
    settle : int
        First step of the steady window (:func:`~secest.arena.estimators.settle_steps`).

    Returns
    -------
    dict
        ``status`` (``"ok"``, or ``"not finite"`` with nothing else); ``transient`` and
        ``steady``: per run and node ``sum e e^T`` over the window (runs, N, n, n) and ``steps``;
        ``mid`` and ``late``: per run and node ``sum e e^T`` over the steps of the steady
        window's second and last quarters (runs, N, n, n); with alarms, their counts per run on the
        steady window (attacked and clean samples).
    """
    if not np.all(np.isfinite(est.xhat)):
        return {"status": "not finite"}
    e = est.xhat - trial.x[:, :, None, :]
    steady = e[:, settle:]
    mid, late = estimators.quarters(steady.shape[1])
    out: dict[str, Any] = {
        "status": "ok", "transient": _moments(e[:, :settle]), "steady": _moments(steady),
        "steps": (settle, steady.shape[1]),
        "mid": _moments(steady[:, mid]), "late": _moments(steady[:, late]),
        "quarter_steps": (len(range(*mid.indices(steady.shape[1]))),
                          len(range(*late.indices(steady.shape[1])))),
    }
    if est.alarms is not None:
        out["alarms"] = _alarm_counts(est.alarms[:, settle:], trial.attacked[:, settle:])
    return out


def _cell(job: Job, trial: Trial, oracle: Estimate, settle: int) -> dict[str, Any]:
    """One job on one trial: n/a, error, or its :func:`summary` with the failed conditions."""
    sc = trial.scenario
    try:
        reason = job.estimator.not_applicable(sc)
        if reason is not None:
            return {"status": "n/a", "reason": reason}
        outside = job.estimator.outside_theory(sc)
        est = oracle if job.method == "oracle" else job.estimator.run(trial)
        estimators._check_estimate("estimate", est, trial)
        return summary(trial, est, settle) | {"outside": outside}
    except Exception as exc:  # one failing method is one error record, never an aborted stage
        return {"status": "error", "reason": estimators._error_reason(exc)}


def trial_task(sc: Scenario, tasks: Sequence[Job], short: bool) -> dict[str, Any]:
    """One trial of the test stage: simulated once, the oracle once, every job on it.

    Parameters
    ----------
    sc : Scenario
        One plant, attack and test seed.
    tasks : sequence of Job
        :func:`jobs` of the plant (the oracle's first).
    short : bool
        Allow a horizon without a steady window (smoke tests only).

    Returns
    -------
    dict
        ``seed`` and ``cells``: job key -> :func:`summary` (with ``outside``), or an ``n/a`` /
        ``error`` record with its reason.
    """
    settle = estimators.settle_steps(sc, short=short)
    trial = scenarios.simulate(sc)
    oracle = METHODS["oracle"].run(trial)
    return {"seed": sc.seed, "cells": {j.key: _cell(j, trial, oracle, settle) for j in tasks}}


# ---------------------------------------------------------------------------------- pooling


def _per_run(moments: NDArray[np.float64], W: NDArray[np.float64], steps: int) -> NDArray[np.float64]:
    """Mean ``q`` per run and node from ``sum e e^T``: ``trace(W^T M W) / (n steps)``."""
    return np.einsum("ac,rnab,bc->rn", W, moments, W) / (W.shape[0] * steps)


def _metric(oracle: list[dict[str, Any]], window: str) -> NDArray[np.float64]:
    """The whitening of the oracle's error second moment over every pooled run of a window."""
    total = sum(o[window][:, 0].sum(axis=0) for o in oracle)
    runs = sum(o[window].shape[0] for o in oracle)
    steps = oracle[0]["steps"][0 if window == "transient" else 1]
    return estimators.whitening(total / (runs * steps))


def _growth(parts: list[dict[str, Any]], W: NDArray[np.float64]) -> estimators.NodeGrowth:
    """Every node's growth factor on the pooled runs, with its interval
    (:func:`~estimators.growth_nodes`)."""
    n_mid, n_late = parts[0]["quarter_steps"]
    mid = np.concatenate([_per_run(p["mid"], W, n_mid) for p in parts])
    late = np.concatenate([_per_run(p["late"], W, n_late) for p in parts])
    return estimators.growth_nodes(mid, late)


def _growth_fields(nodes: estimators.NodeGrowth) -> tuple[tuple[float, float, float], dict[str, Any]]:
    """The decisive node's (value, low, high) and a row's growth fields (Amendment 4: every row).

    ``growth`` and ``growth_interval``: the node whose lower bound is the largest (the growth
    rule reads it); ``growth_upper``: the largest upper bound of any node (the mark
    ``growth_undecided`` reads it); ``growth_largest``: the largest factor of any node (rule 4's
    ties read it).
    """
    g = estimators.decisive(nodes)
    return g, {"growth": g[0], "growth_interval": [g[1], g[2]],
               "growth_upper": float(nodes.high.max()), "growth_largest": float(nodes.value.max())}


def _rates(parts: list[dict[str, Any]]) -> dict[str, Any]:
    """Detection and false-alarm rates of the pooled runs (None without alarms)."""
    if "alarms" not in parts[0]:
        return {"detection": None, "false_alarm": None}
    counts = {k: np.concatenate([p["alarms"][k] for p in parts]) for k in parts[0]["alarms"]}
    detection = None
    if counts["attacked"].sum() > 0:
        detection = estimators.rate_of_counts(counts["hits_attacked"], counts["attacked"])
    return {"detection": detection,
            "false_alarm": estimators.rate_of_counts(counts["hits_clean"], counts["clean"])}


def _failed(parts: list[dict[str, Any]], seeds: list[int]) -> dict[str, Any] | None:
    """The pooled record of a job that did not run on every seed: error (the first seed named),
    n/a or not finite."""
    errors = [(s, p) for s, p in zip(seeds, parts, strict=True) if p["status"] == "error"]
    if errors:
        return {"status": "error", "reason": f"seed {errors[0][0]}: {errors[0][1]['reason']}"}
    na = [p for p in parts if p["status"] == "n/a"]
    if na:  # a requirement on the scenario's cards, the same on every seed
        return {"status": "n/a", "reason": na[0]["reason"]}
    if any(p["status"] == "not finite" for p in parts):
        return {"status": "diverged", "reason": "the estimate is not finite in some run",
                "growth": None}
    return None


def _outside(parts: list[dict[str, Any]]) -> list[str]:
    return list(dict.fromkeys(text for p in parts for text in p.get("outside", [])))


def pool(oracle: list[dict[str, Any]], parts: list[dict[str, Any]], seeds: list[int],
         *, short: bool = False) -> dict[str, Any]:
    """One row's scores on the runs of every seed pooled, by the rules of ``protocol.toml``.

    Parameters
    ----------
    oracle : list of dict
        The oracle's :func:`summary` on each seed's trial (the unit of the score).
    parts : list of dict
        The method's :func:`summary` (or n/a / error record) on the same trials, in that order.
    seeds : list of int
        The seeds of those trials (to name a failing one).
    short : bool
        A smoke test: the growth factor is reported, not ruled on.

    Returns
    -------
    dict
        ``status`` (``ok``, ``diverged``, ``n/a``, ``error``), ``reason``, ``outside``, and for a
        scored row ``steady``, ``worst``, ``transient`` (value, low, high),
        ``growth_undecided`` (True when some node's growth exponent's upper bound is above the
        rule's limit: its runs neither show nor exclude growth, a mark; Amendment 4),
        ``detection`` and ``false_alarm`` (or None); every row that ran, scored or diverged
        (growth or escape: :func:`~secest.arena.estimators.divergence`), carries
        :func:`_growth_fields`' ``growth``, ``growth_interval``, ``growth_upper`` and
        ``growth_largest``; a diverged row no score.
    """
    if not (len(oracle) == len(parts) == len(seeds)) or not parts:
        raise ValidationError(f"Incompatible lengths of oracle, parts and seeds: expected one "
                              f"per seed, found {len(oracle)}, {len(parts)}, {len(seeds)}")
    empty = {"reason": "", "outside": _outside(parts), "steady": None, "worst": None,
             "transient": None, "growth": None, "growth_interval": None, "growth_upper": None,
             "growth_largest": None, "growth_undecided": False, "detection": None,
             "false_alarm": None}
    failed = _failed(parts, seeds)
    lost = [s for s, o in zip(seeds, oracle, strict=True) if o["status"] != "ok"]
    if lost and failed is None:
        failed = {"status": "error", "reason": f"seed {lost[0]}: the oracle did not run"}
    if failed is not None:
        return empty | failed
    W = _metric(oracle, "steady")
    g, fields = _growth_fields(_growth(parts, W))
    settle, length = parts[0]["steps"]
    per_run = np.concatenate([_per_run(p["steady"], W, length) for p in parts])
    why = "" if short else estimators.divergence(g, per_run, settle, length)
    if why:
        return empty | fields | {"status": "diverged", "reason": why}
    steady, worst = estimators.scores_of_runs(per_run)
    Wt = _metric(oracle, "transient")
    transient = estimators.scores_of_runs(np.concatenate(
        [_per_run(p["transient"], Wt, p["steps"][0]) for p in parts]))[0]
    undecided = not short and estimators.growth_not_excluded(fields["growth_upper"], settle, length)
    return empty | fields | {"status": "ok", "steady": steady, "worst": worst,
                             "transient": transient, "growth_undecided": undecided} | _rates(parts)


def data_free_score(sc: Scenario, oracle: list[dict[str, Any]]) -> float | None:
    """The steady-window score of the estimate that uses no data (``x_hat = 0``), in the pooled unit.

    The scale of a plant's scores: a method near it has learnt little from its data.

    Parameters
    ----------
    sc : Scenario
        The scenario (its plant, prior and horizon; computed once, the same for every seed).
    oracle : list of dict
        The oracle's :func:`summary` on each seed's trial of it.

    Returns
    -------
    float or None
        ``sqrt(trace(W^T sum P_k W) / (n steps))``; None when the oracle did not run on a seed.
    """
    if not oracle or any(o["status"] != "ok" for o in oracle):
        return None
    settle, steps = oracle[0]["steps"]
    free = estimators.data_free_moment(sc, settle, settle + steps)  # (sum P_k over the window)
    return float(np.sqrt(_per_run(free[None, None], _metric(oracle, "steady"), steps)[0, 0]))


def _written_growth(row: dict[str, Any]) -> dict[str, Any]:
    """A diverged row's growth numbers to 4 significant digits, ``">1e6"`` above
    :data:`GROWTH_CAP` (amplified round-off decides the digits of a blow-up's; 4 digits keep a
    lower bound near the limit factor, about 1.027, on its side of it)."""
    if row["status"] != "diverged" or row["growth"] is None:
        return row

    def written(g: float) -> float | str:
        return f">{GROWTH_CAP:.0e}".replace("e+0", "e") if not g <= GROWTH_CAP else float(f"{g:.4g}")

    return row | {key: written(row[key]) for key in ("growth", "growth_upper", "growth_largest")} | {
        "growth_interval": [written(g) for g in row["growth_interval"]]}


# ---------------------------------------------------------------------------------- the stage


def _options(seeds: object, runs: object, horizon: object, short: object, workers: object,
             scheduler: object) -> tuple[list[int], int, Any, bool]:
    """Every option of :func:`run` checked before any work: the seeds must be test seeds."""
    p = protocol.load()["seeds"]
    if seeds is None:
        seeds = list(p["test"])
    if (not isinstance(seeds, list) or not seeds or len(set(seeds)) != len(seeds)
            or not all(isinstance(s, int) and not isinstance(s, bool) for s in seeds)):
        raise ValidationError(f"seeds must be a non-empty list of distinct integers, found {seeds!r}")
    other = [s for s in seeds if s not in p["test"]]
    if other:
        raise ValidationError(f"seeds: {other} are not test seeds of protocol.toml ({p['test']}); "
                              "the validation seeds belong to the tuning")
    runs = check_positive_int("runs", p["runs_per_seed"] if runs is None else runs, minimum=2)
    horizon = "auto" if horizon is None else check_positive_int("horizon", horizon)
    short = check_bool("short", short)
    matrix.check_dask_arguments(scheduler, workers)
    return seeds, runs, horizon, short


def _subset(label: str, chosen: object, known: list[str]) -> list[str]:
    if chosen is None:
        return known
    if (not isinstance(chosen, list) or not chosen
            or not all(isinstance(c, str) and c in known for c in chosen)):
        raise ValidationError(f"{label} must be a non-empty list of names from {known}, "
                              f"found {chosen!r}")
    return chosen


def _execute(tasks: list[tuple[Scenario, list[Job]]], short: bool, workers: int | None,
             scheduler: str | None) -> list[dict[str, Any]]:
    """:func:`trial_task` of every task, here or on Dask; a task that raises fails its jobs only."""
    def failed(sc: Scenario, js: list[Job], exc: BaseException) -> dict[str, Any]:
        reason = estimators._error_reason(exc)
        return {"seed": sc.seed, "cells": {j.key: {"status": "error", "reason": reason} for j in js}}

    if scheduler is None and workers is None:
        out = []
        for sc, js in tasks:
            try:
                out.append(trial_task(sc, js, short))
            except Exception as exc:  # a trial that cannot be drawn fails its own rows only
                out.append(failed(sc, js, exc))
        return out
    shipped = [j.estimator for _, js in tasks for j in js]
    with matrix.dask_client(shipped, scheduler, workers) as client:
        futures = [client.submit(trial_task, sc, js, short, pure=False) for sc, js in tasks]
        out = []
        for (sc, js), future in zip(tasks, futures, strict=True):
            try:
                out.append(future.result())
            except Exception as exc:  # a trial that cannot be drawn fails its own rows only
                out.append(failed(sc, js, exc))
        return out


def _rows(job: Job, choice: dict[str, Any] | None, pooled: dict[str, Any],
          runs: int) -> list[dict[str, Any]]:
    """The rows one job reports: printed and/or tuned (or the oracle's reference row)."""
    out = []
    for kind in job.rows:
        tuned = kind == "tuned" and choice is not None
        out.append({
            "method": job.method, "kind": METHODS[job.method].kind, "row": kind,
            "point": choice["point"] if tuned else job.point,
            "constants": choice["constants"] if tuned else job.constants,
            "shared": len(job.rows) > 1, "rule": choice["rule"] if tuned else "",
            "mark": choice["mark"] if tuned else "", "runs": runs,
        } | _written_growth(pooled))
    return out


def _attack_rows(tuned: dict[str, Any], plant: str, attack: str, seeds: list[int],
                 found: dict[tuple[str, str], list[dict[str, Any]]], plan: dict[str, Any],
                 short: bool) -> list[dict[str, Any]]:
    """Every method's rows on one plant under one attack, pooled over the seeds."""
    sc, js = plan[plant]
    choices = tuned["tuned"][plant]
    results = found[(plant, attack)]
    oracle = [r["cells"]["oracle/reference"] for r in results]
    rows = []
    for job in js:
        pooled = pool(oracle, [r["cells"][job.key] for r in results], seeds, short=short)
        rows += _rows(job, choices.get(job.method), pooled, len(seeds) * sc.runs)
    return rows


def _plant_record(tuned: dict[str, Any], plant: str, attacks: list[str], homes: dict[str, str],
                  seeds: list[int], found: dict[tuple[str, str], list[dict[str, Any]]],
                  plan: dict[str, Any], short: bool) -> dict[str, Any]:
    """One plant's rows under every attack and on every home ground of it, pooled over the seeds."""
    sc, _ = plan[plant]
    args = (tuned, plant)
    return {"plant": sc.plant.name, "network": plant, "horizon": sc.horizon,
            "settle": estimators.settle_steps(sc, short=short), "tau": sc.time_constant,
            "data_free": data_free_score(sc, [r["cells"]["oracle/reference"]
                                          for r in found[(plant, attacks[0])]]),
            "home": [n for n in tuned["tuned"][plant] if METHODS[n].home == plant],
            "cells": {a: _attack_rows(*args, a, seeds, found, plan, short) for a in attacks},
            "homes": {name: {"attack": a,
                             "rows": _attack_rows(*args, a, seeds, found, plan, short)}
                      for name, a in homes.items()}}


def home_grounds(plants: list[str], attacks: list[str]) -> dict[str, dict[str, str]]:
    """Per plant, the named scenarios of the cards on it (the papers' home grounds): name -> attack.

    They run on the test seeds at the test stage's runs and horizon like every cell (the tuned
    constants are the plant's); their own ``runs``/``seed`` keys are not used. A named scenario
    whose attack is already a column of the cross is not repeated.
    """
    named = scenarios.cards()["scenario"]
    return {p: {name: c["attack"] for name, c in named.items()
                if c["network"] == p and c["attack"] not in attacks} for p in plants}


def run(
    tuned_path: str | Path,
    *,
    plants: list[str] | None = None,
    attacks: list[str] | None = None,
    seeds: list[int] | None = None,
    runs: int | None = None,
    horizon: int | None = None,
    short: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
) -> dict[str, Any]:
    """The test stage: every plant of the committed tuned file, every attack, every test seed.

    Parameters
    ----------
    tuned_path : str or Path
        The committed :func:`secest.arena.tuning.tune` JSON (``figures/arena/tuned.json``).
    plants : list of str, optional
        Plants of the tuned file to run (default: every one).
    attacks : list of str, optional
        Attack cards (default: the cards' ``[matrix]`` attacks).
    seeds : list of int, optional
        Test seeds (default: ``protocol.toml``'s); any other seed is refused.
    runs : int, optional
        Runs per seed (default ``runs_per_seed``).
    horizon : int, optional
        Steps (default ``"auto"``); shorter than a steady window asks for ``short``.
    short : bool
        A smoke test: a short horizon, a tuned file of a smoke tuning.
    workers : int, optional
        Worker processes of a Dask LocalCluster (one task per plant, attack and seed).
    scheduler : str, optional
        Address of a running Dask scheduler instead.

    Returns
    -------
    dict
        ``protocol`` (file, SHA-256, commit), ``tuned`` (file, commit, SHA-256), ``seeds``,
        ``runs_per_seed``, ``horizon``, ``short``, ``attacks``, ``choices`` (plant -> method ->
        the committed choice) and ``plants`` (plant -> horizon, windows, the data-free score
        (:func:`data_free_score`), home methods, per attack the rows, and per home ground on it
        (:func:`home_grounds`) its attack and rows): JSON-ready, deterministic.
    """
    seeds, runs, horizon, short = _options(seeds, runs, horizon, short, workers, scheduler)
    tuned = load_tuned(tuned_path, short=short)
    plants = _subset("plants", plants, list(tuned["tuned"]))
    attacks = _subset("attacks", attacks, list(scenarios.cards()["matrix"]["attacks"]))
    plan = {}
    for plant in plants:
        sc = scenarios.scenario(plant, attacks[0], horizon=horizon, runs=runs, seed=seeds[0])
        estimators.settle_steps(sc, short=short)  # every horizon checked before any work starts
        plan[plant] = (sc, jobs(tuned, plant, sc.C.shape[1]))
    homes = home_grounds(plants, attacks)
    keys = [(p, a, s) for p in plants for a in attacks + sorted(set(homes[p].values()))
            for s in seeds]
    tasks = [(scenarios.scenario(p, a, horizon=horizon, runs=runs, seed=s), plan[p][1])
             for p, a, s in keys]
    results = _execute(tasks, short, workers, scheduler)
    found: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for (p, a, _), r in zip(keys, results, strict=True):
        found.setdefault((p, a), []).append(r)
    return {
        "protocol": {"file": "secest/arena/protocol.toml", "sha256": tuning._protocol_digest(),
                     "commit": _protocol_commit()},
        "tuned": tuned["committed"], "seeds": seeds, "runs_per_seed": runs, "horizon": horizon,
        "short": short, "attacks": attacks,
        "choices": {p: {m: {k: c[k] for k in ("point", "constants", "rule", "mark")}
                        for m, c in tuned["tuned"][p].items()} for p in plants},
        "plants": {p: _plant_record(tuned, p, attacks, homes[p], seeds, found, plan, short)
                   for p in plants},
    }


# ---------------------------------------------------------------------------------- command line


def parser() -> argparse.ArgumentParser:
    """The argument parser of :func:`main` (its ``--help`` is the reference of every option)."""
    p = tuning._Parser(prog=PROG, description="Score every method printed and tuned on the test "
                       "seeds of secest/arena/protocol.toml, from the committed tuned constants.")
    p.add_argument("--tuned", required=True, type=Path, metavar="FILE",
                   help="the committed tuning result (figures/arena/tuned.json)")
    p.add_argument("--plants", nargs="+", metavar="NETWORK", help="plants of the tuned file")
    p.add_argument("--attacks", nargs="+", metavar="ATTACK", help="attack cards")
    p.add_argument("--seeds", nargs="+", type=int, metavar="SEED",
                   help="test seeds (default: the protocol's; any other seed is refused)")
    p.add_argument("--runs", type=int, help="Monte Carlo runs per seed (default: runs_per_seed)")
    p.add_argument("--horizon", type=int, help="steps (default: the cards' auto horizon)")
    p.add_argument("--short", action="store_true",
                   help="allow a horizon without a steady window and a smoke tuning (tests only)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="worker processes of a Dask LocalCluster")
    where.add_argument("--scheduler", metavar="ADDR", help="address of a running Dask scheduler")
    p.add_argument("--out", required=True, type=Path, metavar="FILE", help="the JSON to write")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run :func:`run` from the command line and write its JSON to ``--out``.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default ``sys.argv[2:]``, after ``test``).

    Returns
    -------
    int
        0 on success; a bad argument, or an uncommitted tuned file, ends with a one-line error
        and status 2.
    """
    args = parser().parse_args(argv)
    listed = {k: None if v is None else tuning._listed(v)
              for k, v in (("plants", args.plants), ("attacks", args.attacks))}
    try:
        result = run(args.tuned, seeds=args.seeds, runs=args.runs, horizon=args.horizon,
                     short=args.short, workers=args.workers, scheduler=args.scheduler, **listed)
    except ValidationError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(tuning._jsonable(result), indent=1, allow_nan=False) + "\n")
    for plant, record in result["plants"].items():
        for attack, rows in record["cells"].items():
            bad = sum(r["status"] != "ok" for r in rows)
            print(f"{plant}/{attack}: {len(rows)} rows, {bad} not scored")
    return 0
