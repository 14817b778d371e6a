"""The arena's tuning engine: the registered rule of ``protocol.toml`` [tuning], on validation seeds.

Per method and plant (network card), independently (issue #28):

1. :func:`grid`: the points of the method's search set ``[search.<method>]``, the printed point
   (the first entry of every list) first, then the product of the lists in their order;
2. :func:`validate`: every point runs the plant's no-attack card on every validation seed
   (``[seeds] validation``, ``runs_per_seed`` runs each): one task per (point, seed), in this
   process or on Dask; per point the runs of every seed pooled by the test stage's own rule
   (:func:`secest.arena.testseeds.pool`, Amendment 3): its steady-window network score, its
   divergence (growth exponent, escape, non-finite estimates) and, for a method with a
   detector, the false-alarm rate of the pooled runs with its upper 95 % bound
   (:func:`~secest.arena.estimators.rate_of_counts`); a point that fails is one record with
   its error, never an aborted validation;
3. :func:`choose`: the rule: diverged points and points whose false-alarm upper bound exceeds
   ``false_alarm_cap`` are excluded (so are points that could not run: ``n/a`` or ``error``);
   the lowest pooled score wins; ties within 1 % go to the printed point, then to the point
   listed first; with no admissible point, the point of lowest false-alarm upper bound among
   those that did not diverge (among all if every one did; ties: the least largest growth factor
   over the nodes) is chosen and marked ``"no admissible point"`` (a method without a detector: the
   printed point).

The engine sees the validation seeds only: a test seed is refused (:func:`refuse_test_seeds`),
and so is any seed the protocol does not list as a validation seed. :func:`tune` runs many
(method, plant) pairs on one cluster; the command line ``python -m secest.arena.tuning`` writes
its result as JSON (the future ``figures/arena/tuned.json``): deterministic content only, no
timing.

How each search key reaches a method (:data:`ARGUMENTS`, :data:`PRINTED_ONLY`, :data:`FIXED`);
no key is dropped: :func:`grid` refuses a key this table does not map.

==============  ============  =================  ========================================================
method          search key    argument           note
==============  ============  =================  ========================================================
ding2020        kappa         ``kappa``
ding2020        threshold     ``threshold``      the printed row only (25, Sec. V)
ding2020        false_alarm   ``threshold``      the tuned rows: ``chi2.ppf(1 - false_alarm, n_y)``
guo2023         false_alarm   ``false_alarm``    its test's level; the threshold
                                                 ``chi2(1 - false_alarm, p_i)``, ``p_i = n_y``, is
                                                 computed in ``run``. Its alarms do not feed the
                                                 estimate, and the no-attack card gives no node an
                                                 attack channel (``threat="card"``): its points score
                                                 alike, the tie rule returns the printed one
guo2023         threat        ``threat``         ``"card"`` only: a reading, not tuned
lee2020         kappa         ``kappa``
lee2020         gamma         ``gamma``
lee2020         poles         ``poles``
li2025          lambda        ``weights[0]``
li2025          alpha_1       ``weights[1]``
li2025          alpha_2       ``weights[2]``
li2025          alpha_3_4     ``weights[3:5]``   ``alpha_3 = alpha_4``
li2025          variant       ``variant``        ``"corrected"`` only
ma2021          p             ``p``              sets only the reported ellipsoid, not the estimate: its
                                                 points score alike (the tie rule: the printed one)
kf              (none)        (none)             no free constant: one point
chi2-kf         false_alarm   ``false_alarm``    threshold ``chi2(1 - false_alarm, n_y)`` in ``run``
local-kf        (none)        (none)             no free constant: one point
consensus-kf-1  rounds        ``rounds``         ``1`` only
consensus-kf    rounds        ``rounds``
diffusion-kf    combination   ``combination``    ``"metropolis"`` only
kcf             epsilon       ``epsilon``        ``epsilon * max degree >= 1``: outside its theory, the
                                                 point runs, marked (Amendment 2); out only if diverged
wmsr-kf         trimmed       ``trimmed``
oracle          (no entry)    (none)             the reference of every score: never tuned (refused)
==============  ============  =================  ========================================================

Constructor arguments no search key sets keep their defaults (:data:`FIXED`): guo2023's
``rtol``, lee2020's ``q`` and ``chatter``.
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import sys
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from scipy import stats

from secest.arena import estimators, matrix, protocol, scenarios, testseeds
from secest.arena.estimators import METHODS, Method
from secest.arena.scenarios import Scenario
from secest.core.validation import ValidationError, check_bool, check_positive_int, check_probability

__all__ = [
    "ARGUMENTS",
    "FIXED",
    "NO_ADMISSIBLE",
    "PRINTED_ONLY",
    "PROG",
    "TIE",
    "choose",
    "grid",
    "main",
    "parser",
    "point_task",
    "refuse_test_seeds",
    "tune",
    "validate",
]

ARGUMENTS: dict[str, dict[str, str]] = {
    "ding2020": {"kappa": "kappa", "threshold": "threshold", "false_alarm": "threshold"},
    "guo2023": {"false_alarm": "false_alarm", "threat": "threat"},
    "lee2020": {"kappa": "kappa", "gamma": "gamma", "poles": "poles"},
    "li2025": {"lambda": "weights[0]", "alpha_1": "weights[1]", "alpha_2": "weights[2]",
               "alpha_3_4": "weights[3,4]", "variant": "variant"},
    "ma2021": {"p": "p"},
    "kf": {},
    "chi2-kf": {"false_alarm": "false_alarm"},
    "local-kf": {},
    "consensus-kf-1": {"rounds": "rounds"},
    "consensus-kf": {"rounds": "rounds"},
    "diffusion-kf": {"combination": "combination"},
    "kcf": {"epsilon": "epsilon"},
    "wmsr-kf": {"trimmed": "trimmed"},
}
"""Per method, the constructor argument each search key sets (the module's table). A
``false_alarm`` key on a ``threshold`` argument passes ``chi2.ppf(1 - false_alarm, n_y)``;
``weights[i,j]`` puts the value at those places of li2025's ``weights`` tuple."""

PRINTED_ONLY: dict[str, tuple[str, str]] = {"ding2020": ("threshold", "false_alarm")}
"""Method -> (key of the printed row only, key it stands for in the tuned rows)."""

FIXED: dict[str, tuple[str, ...]] = {"guo2023": ("rtol",), "lee2020": ("q", "chatter")}
"""Constructor arguments that no search key sets: they keep their defaults."""

TIE = 0.01
"""Scores within this fraction of the lowest one tie (``protocol.toml`` [tuning], rule 3)."""
NO_ADMISSIBLE = "no admissible point"
"""The mark of a choice made by the fallback (rule 4)."""


# ---------------------------------------------------------------------------------- the grid


def _method_name(name: object, search: dict[str, Any], label: str = "method") -> str:
    """``name`` if it is a registered method with a search set; else a one-line error."""
    if name == "oracle":
        raise ValidationError(f"{label} 'oracle' is the reference of every score: it is not tuned")
    if not isinstance(name, str) or name not in search or name not in METHODS:
        known = sorted(n for n in search if n in METHODS)
        raise ValidationError(f"{label} must be a registered method with a [search] set in "
                              f"protocol.toml, one of {known}; found {name!r}")
    return name


def _threshold(false_alarm: float, ny: int) -> float:
    """``chi2.ppf(1 - false_alarm, ny)``, the protocol's reading of a ``false_alarm`` entry."""
    return float(stats.chi2.ppf(1.0 - false_alarm, ny))


def _arguments(name: str, constants: dict[str, Any], ny: int) -> dict[str, Any]:
    """The constructor arguments of ``name`` that the search constants of one point set."""
    kwargs: dict[str, Any] = {}
    weights: dict[int, float] = {}
    for key, value in constants.items():
        target = ARGUMENTS[name][key]
        if target.startswith("weights["):
            weights.update({int(i): float(value) for i in target[8:-1].split(",")})
        elif key == "false_alarm" and target == "threshold":
            kwargs[target] = _threshold(value, ny)
        else:
            kwargs[target] = value
    if weights:
        if sorted(weights) != list(range(len(weights))):
            raise ValidationError(f"search.{name}: the keys set weights {sorted(weights)}, "
                                  "not every one of them")
        kwargs["weights"] = tuple(weights[i] for i in range(len(weights)))
    return kwargs


def _point(name: str, index: int, constants: dict[str, Any], ny: int) -> dict[str, Any]:
    """One grid point: its search constants, the constructor arguments, the threshold it means."""
    fa = constants.get("false_alarm")
    threshold = constants.get("threshold", None if fa is None else _threshold(fa, ny))
    return {"point": index, "printed": index == 0, "constants": dict(constants),
            "arguments": _arguments(name, constants, ny), "threshold": threshold}


def grid(method_name: str, plant_ny: int) -> list[dict[str, Any]]:
    """The search points of one method on a plant whose nodes measure ``plant_ny`` outputs each.

    Parameters
    ----------
    method_name : str
        A registered method with a ``[search.<method_name>]`` set in ``protocol.toml``.
    plant_ny : int
        Outputs per node ``n_y`` (:attr:`Scenario.C` ``.shape[1]``): the degrees of freedom of the
        chi-square threshold a ``false_alarm`` entry means.

    Returns
    -------
    list of dict
        The printed point first (the first entry of every list; ding2020: ``threshold = 25``),
        then the product of the lists in their order, the printed point not repeated. Each point:
        ``point`` (its index), ``printed``, ``constants`` (the search keys' values),
        ``arguments`` (the constructor arguments, :data:`ARGUMENTS`) and ``threshold`` (the
        chi-square threshold it means, or None).

    Raises
    ------
    ValidationError
        Unknown method, ``plant_ny`` not a positive integer, or a search key that
        :data:`ARGUMENTS` does not map (never dropped silently).
    """
    search = protocol.load()["search"]
    name = _method_name(method_name, search)
    ny = check_positive_int("plant_ny", plant_ny)
    lists = search[name]
    unmapped = sorted(set(lists) - set(ARGUMENTS.get(name, {})))
    if unmapped:
        raise ValidationError(f"search.{name}: keys {unmapped} have no constructor argument in "
                              "secest.arena.tuning.ARGUMENTS")
    printed_key, tuned_key = PRINTED_ONLY.get(name, (None, None))
    printed = {k: v[0] for k, v in lists.items() if k != tuned_key}
    tuned = {k: v for k, v in lists.items() if k != printed_key}
    points = [printed]
    for values in itertools.product(*tuned.values()):
        constants = dict(zip(tuned, values, strict=True))
        if _arguments(name, constants, ny) != _arguments(name, printed, ny):
            points.append(constants)
    return [_point(name, i, c, ny) for i, c in enumerate(points)]


# ---------------------------------------------------------------------------------- arguments


def refuse_test_seeds(seeds: Sequence[int], test: Sequence[int] | None = None) -> None:
    """Refuse any test seed: the tuning sees the validation seeds only (``protocol.toml`` [seeds]).

    Parameters
    ----------
    seeds : sequence of int
        The seeds a tuning run is asked to use.
    test : sequence of int, optional
        The test seeds; default the protocol's test seeds and its retired ones
        (``retired_test``, Amendment 4).

    Raises
    ------
    ValidationError
        If a seed of ``seeds`` is a test seed.
    """
    if test is None:
        registered = protocol.load()["seeds"]
        test = [*registered["test"], *registered.get("retired_test", [])]
    for label, values in (("seeds", seeds), ("test", test)):
        if isinstance(values, str) or not isinstance(values, Sequence) or not all(
                isinstance(s, int) and not isinstance(s, bool) for s in values):
            raise ValidationError(f"{label} must be a list of integer seeds, found {values!r}")
    bad = [s for s in seeds if s in set(test)]
    if bad:
        raise ValidationError(f"seeds: {bad} are test seeds of protocol.toml (or retired ones); "
                              "the tuning sees the validation seeds only")


def _seeds(seeds: object, p: dict[str, Any]) -> list[int]:
    """The validation seeds to run: ``seeds`` checked, or the protocol's."""
    validation = p["seeds"]["validation"]
    if seeds is None:
        return list(validation)
    if (not isinstance(seeds, list) or not seeds
            or not all(isinstance(s, int) and not isinstance(s, bool) for s in seeds)):
        raise ValidationError(f"seeds must be a non-empty list of integers, found {seeds!r}")
    if len(set(seeds)) != len(seeds):
        raise ValidationError(f"seeds: a seed is listed twice in {seeds!r}")
    refuse_test_seeds(seeds, p["seeds"]["test"])
    other = [s for s in seeds if s not in validation]
    if other:
        raise ValidationError(f"seeds: {other} are not validation seeds of protocol.toml "
                              f"({validation})")
    return seeds


def _plant(plant: object, label: str = "plant") -> str:
    """``plant`` if it names a network card (a plant on its sensor network)."""
    networks = sorted(scenarios.cards()["network"])
    if not isinstance(plant, str) or plant not in networks:
        raise ValidationError(f"{label} must be a network card, one of {networks}; found {plant!r}")
    return plant


def _names(label: str, values: object) -> list[str]:
    """A non-empty list of distinct strings (the methods or plants of :func:`tune`)."""
    if (not isinstance(values, list | tuple) or not values
            or not all(isinstance(v, str) for v in values) or len(set(values)) != len(values)):
        raise ValidationError(f"{label} must be a non-empty list of distinct names, found {values!r}")
    return list(values)


# ---------------------------------------------------------------------------------- the tasks


def point_task(sc: Scenario, method: Method, short: bool) -> dict[str, Any]:
    """One (point, seed) of the validation: the oracle and ``method`` on ``sc``'s trial, summarised.

    The trial is summarised as the test stage summarises its trials
    (:func:`secest.arena.testseeds.trial_task`: per run and node the error moments on each window,
    the alarm counts), so that the seeds of a point pool into one row by the test stage's own rule
    (:func:`secest.arena.testseeds.pool`, Amendment 3).

    Parameters
    ----------
    sc : Scenario
        The plant's no-attack card on one validation seed.
    method : Method
        The method built with the point's constants.
    short : bool
        Allow a horizon without a steady window (smoke tests only).

    Returns
    -------
    dict
        ``seed``, ``oracle`` and ``cell``: the oracle's and the method's summaries (or an ``n/a``
        / ``error`` record with its reason).
    """
    scenarios.check_scenario("sc", sc)
    if not isinstance(method, Method):
        raise ValidationError(f"method must be a Method, found {type(method).__name__}")
    short = check_bool("short", short)
    oracle = testseeds.Job("oracle", ("reference",), 0, METHODS["oracle"], {})
    job = testseeds.Job(method.name, ("point",), 0, method, {})
    cells = testseeds.trial_task(sc, [oracle, job], short)["cells"]
    return {"seed": sc.seed, "oracle": cells[oracle.key], "cell": cells[job.key]}


def _floats(value: tuple[float, ...] | None) -> list[float] | None:
    return None if value is None else [float(v) for v in value]


def _finite(value: float | None) -> float | None:
    return None if value is None or not np.isfinite(value) else float(value)


def _failed(seed: int, exc: BaseException) -> dict[str, Any]:
    """The result of a task that raised: an error cell, the other tasks unaffected."""
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    error = {"status": "error", "reason": f"{type(exc).__name__}: {text}".rstrip(": ")}
    return {"seed": seed, "oracle": error, "cell": error}


def _run_here(jobs: list[tuple[Scenario, Method]], short: bool) -> list[dict[str, Any]]:
    out = []
    for sc, method in jobs:
        try:
            out.append(point_task(sc, method, short))
        except Exception as exc:  # one failing point is one record, never an abort
            out.append(_failed(sc.seed, exc))
    return out


def _run_on_dask(jobs: list[tuple[Scenario, Method]], short: bool, scheduler: str | None,
                 workers: int | None) -> list[dict[str, Any]]:
    """:func:`point_task` of every job on Dask (the client of :func:`matrix.dask_client`).

    One task per point: the seeds of a point run in one process on one copy of its method, so a
    design the method caches (it depends on the plant, not on the seed) is computed once.
    """
    batches: dict[int, list[int]] = {}
    for i, (_, method) in enumerate(jobs):
        batches.setdefault(id(method), []).append(i)
    with matrix.dask_client([m for _, m in jobs], scheduler, workers) as client:
        futures = [client.submit(_run_here, [jobs[i] for i in idx], short, pure=False)
                   for idx in batches.values()]
        out: list[dict[str, Any]] = [{} for _ in jobs]
        for idx, future in zip(batches.values(), futures, strict=True):
            try:
                results = future.result()
            except Exception as exc:  # one failing point is one record, never an abort
                results = [_failed(jobs[i][0].seed, exc) for i in idx]
            for i, result in zip(idx, results, strict=True):
                out[i] = result
        return out


# ---------------------------------------------------------------------------------- validation


def _build(name: str, point: dict[str, Any]) -> Method | str:
    """The method with the point's constants, renamed ``name[point]``; or why it cannot be built."""
    try:
        method = type(METHODS[name])(**point["arguments"])
    except Exception as exc:  # a point the constructor refuses is an error record
        return _failed(0, exc)["reason"]
    method.name = f"{name}[{point['point']}]"
    return method


def _false_alarms(parts: list[dict[str, Any]]) -> list[float] | None:
    """The false-alarm rate (rate, low, high) of the pooled runs that raised alarms, or None."""
    counted = [p for p in parts if "alarms" in p]  # the test stage's rates, on these parts
    return None if not counted else [float(v) for v in testseeds._rates(counted)["false_alarm"]]


def _record(name: str, plant: str, point: dict[str, Any], results: list[dict[str, Any]],
            short: bool) -> dict[str, Any]:
    """One point's record: its seeds' runs pooled by the test stage's rule, and its false alarms.

    The score, the growth rule and the escape rule are :func:`secest.arena.testseeds.pool`'s on
    the runs of every validation seed together (Amendment 3: per seed before, so that a point
    could be diverged in the tuning and bounded in the test); the false-alarm rate counts every
    pooled run that raised alarms (a diverged point's too: the fallback of rule 4 reads it).
    """
    parts = [r["cell"] for r in results]
    row = testseeds.pool([r["oracle"] for r in results], parts, [r["seed"] for r in results],
                         short=short)
    false_alarm = _false_alarms(parts)
    return {
        "method": name, "plant": plant, **point, "status": row["status"], "reason": row["reason"],
        "outside": row["outside"],
        "score": row["steady"][0] if row["status"] == "ok" else None,
        "steady": _floats(row["steady"]), "worst": _floats(row["worst"]),
        "growth": _finite(row["growth"]),
        "growth_interval": (None if row["growth_interval"] is None
                            else [_finite(g) for g in row["growth_interval"]]),
        "growth_upper": _finite(row["growth_upper"]),
        "growth_largest": _finite(row["growth_largest"]),
        "growth_undecided": row["growth_undecided"],
        "detector": false_alarm is not None, "false_alarm": false_alarm,
        "seeds": [r["seed"] for r in results],
    }


def _unbuilt(name: str, plant: str, point: dict[str, Any], reason: str,
             seeds: list[int]) -> dict[str, Any]:
    """The record of a point whose method could not be built: one error record, no task."""
    return {"method": name, "plant": plant, **point, "status": "error", "reason": reason,
            "outside": [], "score": None, "steady": None, "worst": None, "growth": None,
            "growth_interval": None, "growth_upper": None, "growth_largest": None,
            "growth_undecided": False,
            "detector": False, "false_alarm": None, "seeds": list(seeds)}


def _check_options(seeds: object, runs: object, horizon: object, short: object,
                   workers: object, scheduler: object) -> tuple[list[int], int, Any, bool]:
    """Every option of :func:`validate` and :func:`tune` checked before any work."""
    p = protocol.load()
    seeds = _seeds(seeds, p)
    runs = check_positive_int("runs", p["seeds"]["runs_per_seed"] if runs is None else runs,
                              minimum=2)
    if horizon is not None:
        horizon = check_positive_int("horizon", horizon)
    short = check_bool("short", short)
    matrix.check_dask_arguments(scheduler, workers)
    return seeds, runs, horizon, short


def _many(pairs: list[tuple[str, str]], seeds: list[int], runs: int, horizon: int | None,
          short: bool, workers: int | None, scheduler: str | None,
          points: list[int] | None = None) -> dict[tuple[str, str], list]:
    """Records of every point of every (method, plant) pair, all tasks on one cluster."""
    cards = {plant: {s: scenarios.scenario(plant, "none", horizon=horizon, runs=runs, seed=s,
                                           name=f"{plant}/none")
                     for s in seeds} for plant in {p for _, p in pairs}}
    for by_seed in cards.values():  # every horizon checked before any work starts
        estimators.settle_steps(next(iter(by_seed.values())), short=short)
    plan, jobs = [], []
    for name, plant in pairs:
        ny = next(iter(cards[plant].values())).C.shape[1]
        for point in grid(name, ny):
            if points is not None and point["point"] not in points:
                continue
            method = _build(name, point)
            first = len(jobs)
            if isinstance(method, Method):
                jobs += [(cards[plant][s], method) for s in seeds]
            plan.append((name, plant, point, method, first))
    if scheduler is None and workers is None:
        results = _run_here(jobs, short)
    else:
        results = _run_on_dask(jobs, short, scheduler, workers)
    out: dict[tuple[str, str], list] = {pair: [] for pair in pairs}
    for name, plant, point, method, first in plan:
        if isinstance(method, Method):
            out[(name, plant)].append(_record(name, plant, point,
                                              results[first: first + len(seeds)], short))
        else:
            out[(name, plant)].append(_unbuilt(name, plant, point, method, seeds))
    return out


def validate(
    method_name: str,
    plant: str,
    *,
    seeds: list[int] | None = None,
    runs: int | None = None,
    horizon: int | None = None,
    short: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    points: list[int] | None = None,
) -> list[dict[str, Any]]:
    """Every point of ``method_name``'s grid on ``plant``'s no-attack card, on the validation seeds.

    Parameters
    ----------
    method_name : str
        A registered method with a search set (:func:`grid`).
    plant : str
        A network card (a plant on its sensor network), e.g. ``"target20"``.
    seeds : list of int, optional
        Validation seeds (default: ``protocol.toml`` [seeds] validation); a test seed, or any
        seed the protocol does not list as a validation seed, is refused.
    runs : int, optional
        Monte Carlo runs per seed, >= 2 (default ``runs_per_seed``).
    horizon : int, optional
        Steps (default: the cards' ``"auto"`` horizon); shorter than the plant's steady window
        asks for ``short``.
    short : bool
        Allow a horizon without a steady window (smoke tests; nothing is then ruled diverged
        by growth).
    workers : int, optional
        Worker processes of a Dask LocalCluster (one task per (point, seed)).
    scheduler : str, optional
        Address of a running Dask scheduler instead.
    points : list of int, optional
        Only these grid indices (smoke tests); the rule's choice needs every point (default).

    Returns
    -------
    list of dict
        One record per point, in grid order: the point (:func:`grid`), and its seeds' runs
        pooled (:func:`secest.arena.testseeds.pool`): ``status`` (``"ok"``, ``"diverged"``,
        ``"n/a"``, ``"error"``), ``reason``, ``outside``, ``score`` (the pooled steady-window
        network score; None unless ok), ``steady`` and ``worst`` (value, low, high), ``growth``
        (the factor), ``growth_interval`` (its 95 % bounds), ``growth_upper``,
        ``growth_largest`` (every point that ran, diverged too: Amendment 4) and
        ``growth_undecided`` (:func:`secest.arena.testseeds.pool`), ``detector``,
        ``false_alarm`` (rate, low, high of the pooled runs; None without a detector) and
        ``seeds``.

    Raises
    ------
    ValidationError
        Unknown method or plant, bad seeds (a test seed above all), runs, horizon or Dask
        arguments: before any work.
    """
    name = _method_name(method_name, protocol.load()["search"])
    plant = _plant(plant)
    seeds, runs, horizon, short = _check_options(seeds, runs, horizon, short, workers, scheduler)
    if points is not None and (not isinstance(points, list) or not points or not all(
            isinstance(i, int) and not isinstance(i, bool) for i in points)):
        raise ValidationError(f"points must be a non-empty list of grid indices, found {points!r}")
    if points is not None:
        size = len(grid(name, scenarios.cards()["network"][plant].measures.shape[1]))
        if not all(0 <= i < size for i in points):
            raise ValidationError(f"points must be grid indices from 0 to {size - 1}, found {points!r}")
    return _many([(name, plant)], seeds, runs, horizon, short, workers, scheduler,
                 points)[(name, plant)]


# ---------------------------------------------------------------------------------- the rule


_RECORD_KEYS = ("point", "printed", "status", "score", "false_alarm", "constants", "arguments")


def _check_records(records: object) -> list[dict[str, Any]]:
    if (not isinstance(records, list) or not records
            or not all(isinstance(r, dict) and set(_RECORD_KEYS) <= set(r) for r in records)):
        raise ValidationError(f"records must be a non-empty list of validate()'s records (dicts with "
                              f"{list(_RECORD_KEYS)}), found {type(records).__name__}")
    if sum(bool(r["printed"]) for r in records) != 1:
        raise ValidationError("records must hold exactly one printed point")
    if len({r["point"] for r in records}) != len(records):
        raise ValidationError("records: a point is listed twice")
    for r in records:
        score = r["score"]
        if score is not None and (isinstance(score, bool) or not isinstance(score, int | float)
                                  or not np.isfinite(score)):
            raise ValidationError(f"records: point {r['point']} has score {score!r}, expected a "
                                  "finite number or None")
    return records


def _exclusion(r: dict[str, Any], cap: float) -> str:
    """Why a record is not admissible under the rule ("" when it is)."""
    if r["status"] != "ok" or r["score"] is None:
        return f"{r['status']}: {r.get('reason', '')}".rstrip(": ")
    if r["false_alarm"] is not None and r["false_alarm"][2] > cap:
        return f"false-alarm upper bound {r['false_alarm'][2]:.3g} > cap {cap:g}"
    return ""


def _preferred(tied: list[dict[str, Any]]) -> dict[str, Any]:
    """Among tied records: the printed point, else the one listed first."""
    printed = [r for r in tied if r["printed"]]
    return printed[0] if printed else min(tied, key=lambda r: r["point"])


def _least_growth(tied: list[dict[str, Any]]) -> dict[str, Any]:
    """Among tied records: the least growth factor of its most growing node (one not finite or
    unknown counts as infinite; Amendment 3, the node whose lower bound is the largest before
    Amendment 4), then :func:`_preferred`."""
    def factor(r: dict[str, Any]) -> float:
        g = r.get("growth_largest")
        return float("inf") if g is None else g

    least = min(factor(r) for r in tied)
    return _preferred([r for r in tied if factor(r) == least])


def choose(records: list[dict[str, Any]], *, cap: float | None = None) -> dict[str, Any]:
    """The registered rule (``protocol.toml`` [tuning]) on one method's records on one plant.

    Parameters
    ----------
    records : list of dict
        :func:`validate`'s records (or synthetic ones with the same keys: ``point``,
        ``printed``, ``status``, ``score``, ``false_alarm``, ``constants``, ``arguments``).
    cap : float, optional
        The false-alarm cap (default ``protocol.toml`` [detection] ``false_alarm_cap``).

    Returns
    -------
    dict
        ``point`` (the chosen index), ``printed``, ``constants``, ``arguments``, ``score``,
        ``false_alarm``, ``rule`` (how it was chosen), ``mark`` (:data:`NO_ADMISSIBLE` or
        ""), ``admissible`` (indices) and ``excluded`` (index and why, per excluded point).

    Raises
    ------
    ValidationError
        If ``records`` is not a non-empty list of records with exactly one printed point.
    """
    records = _check_records(records)
    cap = protocol.load()["detection"]["false_alarm_cap"] if cap is None else cap
    cap = check_probability("cap", cap)
    why = {r["point"]: _exclusion(r, cap) for r in records}
    admissible = [r for r in records if not why[r["point"]]]
    mark = ""
    if admissible:
        best = min(r["score"] for r in admissible)
        tied = [r for r in admissible if r["score"] <= best * (1 + TIE)]
        pick = _preferred(tied)
        rule = ("lowest score" if len(tied) == 1 else
                f"within {TIE:.0%} of the lowest score: "
                + ("the printed point" if pick["printed"] else "the point listed first"))
    else:
        mark = NO_ADMISSIBLE
        rated = [r for r in records if r["false_alarm"] is not None]
        bounded = [r for r in rated if r["status"] == "ok"]  # Amendment 2: never a diverged point
        if bounded or rated:
            among = bounded or rated
            low = min(r["false_alarm"][2] for r in among)
            pick = _least_growth([r for r in among if r["false_alarm"][2] == low])
            rule = ("lowest false-alarm upper bound" + ("" if bounded else
                    " (every point with a false-alarm rate diverged; ties: the least growth)"))
        else:
            pick = next(r for r in records if r["printed"])
            rule = "no false-alarm bound (no detector, or none ran): the printed point"
    return {
        "point": pick["point"], "printed": bool(pick["printed"]), "constants": pick["constants"],
        "arguments": pick["arguments"], "score": pick["score"], "false_alarm": pick["false_alarm"],
        "rule": rule, "mark": mark, "admissible": [r["point"] for r in admissible],
        "excluded": [{"point": p, "why": w} for p, w in why.items() if w],
    }


# ---------------------------------------------------------------------------------- many pairs


def _protocol_digest() -> str:
    text = resources.files("secest.arena").joinpath("protocol.toml").read_bytes()
    return hashlib.sha256(text).hexdigest()


def tune(
    methods: list[str],
    plants: list[str],
    *,
    seeds: list[int] | None = None,
    runs: int | None = None,
    horizon: int | None = None,
    short: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
) -> dict[str, Any]:
    """:func:`validate` and :func:`choose` for every (method, plant), every task on one cluster.

    Parameters
    ----------
    methods : list of str
        Registered methods with a search set.
    plants : list of str
        Network cards.
    seeds, runs, horizon, short, workers, scheduler
        As in :func:`validate`.

    Returns
    -------
    dict
        ``protocol`` (the file's SHA-256, seeds, runs, horizon, short), ``tuned``
        (``plant -> method ->`` :func:`choose`'s result) and ``points`` (``plant -> method ->``
        :func:`validate`'s records): deterministic content only, JSON-ready.
    """
    search = protocol.load()["search"]
    methods = [_method_name(m, search, "methods: each method") for m in _names("methods", methods)]
    plants = [_plant(p, "plants: each plant") for p in _names("plants", plants)]
    seeds, runs, horizon, short = _check_options(seeds, runs, horizon, short, workers, scheduler)
    pairs = [(m, p) for p in plants for m in methods]
    found = _many(pairs, seeds, runs, horizon, short, workers, scheduler)
    return {
        "protocol": {"file": "secest/arena/protocol.toml", "sha256": _protocol_digest(),
                     "seeds": seeds, "runs_per_seed": runs,
                     "horizon": "auto" if horizon is None else horizon, "short": short},
        "tuned": {p: {m: choose(found[(m, p)]) for m in methods} for p in plants},
        "points": {p: {m: found[(m, p)] for m in methods} for p in plants},
    }


# ---------------------------------------------------------------------------------- command line


PROG = "python -m secest.arena.tuning"


class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (exit status 2)."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def _listed(values: list[str]) -> list[str]:
    """Names given as separate words, comma-separated, or both."""
    return [n.strip() for v in values for n in v.split(",") if n.strip()]


def parser() -> argparse.ArgumentParser:
    """The argument parser of :func:`main` (its ``--help`` is the reference of every option)."""
    p = _Parser(prog=PROG, description="Tune methods on the validation seeds by the rule of "
                "secest/arena/protocol.toml and write the chosen constants and every point as JSON. "
                f"The test stage is '{PROG} test' (its own --help); '{PROG} validate' is this one.")
    p.add_argument("--methods", nargs="+", metavar="NAME",
                   help="methods with a [search] set (words or a comma-separated list; default: "
                   "every registered method with one)")
    p.add_argument("--plants", nargs="+", metavar="NETWORK",
                   help="network cards, e.g. target20 inertia5 tank12 (default: the cards' "
                   "[matrix] networks)")
    p.add_argument("--seeds", nargs="+", type=int, metavar="SEED",
                   help="validation seeds (default: the protocol's; a test seed is refused)")
    p.add_argument("--runs", type=int, help="Monte Carlo runs per seed (default: runs_per_seed)")
    p.add_argument("--horizon", type=int, help="steps (default: the cards' auto horizon)")
    p.add_argument("--short", action="store_true",
                   help="allow a horizon without a steady window (smoke tests only)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="worker processes of a Dask LocalCluster")
    where.add_argument("--scheduler", metavar="ADDR", help="address of a running Dask scheduler")
    p.add_argument("--out", required=True, type=Path, metavar="FILE", help="the JSON to write")
    return p


def _jsonable(value: Any) -> Any:
    """``value`` with tuples as lists and every non-finite float as None (strict JSON)."""
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def _defaults(methods: list[str] | None, plants: list[str] | None) -> tuple[list[str], list[str]]:
    """The methods and plants of the command line, or every method with a search set and the
    cards' ``[matrix]`` networks."""
    search = protocol.load()["search"]
    every = [m for m in METHODS if m in search]
    nets = list(scenarios.cards()["matrix"]["networks"])
    return (every if methods is None else _listed(methods), nets if plants is None else _listed(plants))


def main(argv: Sequence[str] | None = None) -> int:
    """Run :func:`tune` (or, after ``test``, the test stage) and write its JSON to ``--out``.

    ``python -m secest.arena.tuning [validate] --out FILE ...`` is the validation;
    ``python -m secest.arena.tuning test --tuned FILE --out FILE ...`` the test stage
    (:func:`secest.arena.testseeds.main`).

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 on success; a bad argument ends with a one-line error and status 2.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["test"]:
        from secest.arena import testseeds

        return testseeds.main(argv[1:])
    args = parser().parse_args(argv[1:] if argv[:1] == ["validate"] else argv)
    try:
        if args.out.is_dir():
            raise ValidationError(f"--out must be a JSON file's path, found the folder "
                                  f"{str(args.out)!r}")
        methods, plants = _defaults(args.methods, args.plants)
        result = tune(methods, plants, seeds=args.seeds,
                      runs=args.runs, horizon=args.horizon, short=args.short,
                      workers=args.workers, scheduler=args.scheduler)
    except ValidationError as exc:
        print(f"{PROG}: error: {exc}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(_jsonable(result), indent=1, allow_nan=False) + "\n")
    for plant, by_method in result["tuned"].items():
        for name, c in by_method.items():
            mark = f" [{c['mark']}]" if c["mark"] else ""
            print(f"{plant} {name}: point {c['point']} {c['constants']} ({c['rule']}){mark}")
    return 0


if __name__ == "__main__":  # the package's module, not a second copy as __main__
    from secest.arena import tuning

    raise SystemExit(tuning.main())
