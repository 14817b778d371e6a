"""The arena: every registered method on every scenario, scored against the oracle on shared runs.

:func:`run_matrix` runs :func:`secest.arena.estimators.evaluate` once per scenario, so that every
method of a scenario is fed the same :class:`~secest.arena.scenarios.Trial` (truth, noises,
attacks, channel), and keeps, besides the :class:`~secest.arena.estimators.Score` of each cell,
the network-mean RMS error of each method over time (:class:`Curves`) and what each method
cost (wall time, machine-dependent: never written to a committed file). :func:`cell_text`
and :func:`table_rows` turn a cell into the words of the arena's table: every number with
its 95 % interval, or ``N/A: <the failed condition>``, or ``diverged``.

A new scenario is one card (``secest/arena/cards.toml`` or ``extra=`` of
:func:`secest.arena.scenarios.matrix`); a new method is one :class:`~secest.arena.estimators.Method`
passed to :func:`~secest.arena.estimators.register`. Both appear in the matrix without any change
here.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from secest.arena import estimators
from secest.arena.estimators import METHODS, Estimate, Score
from secest.arena.scenarios import Scenario, Trial, check_scenario, simulate
from secest.core.validation import ValidationError, check_bool, check_instance

__all__ = [
    "CELL_FIELDS",
    "STATUSES",
    "Curves",
    "Matrix",
    "attack_activity",
    "cell_text",
    "check_dask_arguments",
    "check_matrix",
    "plan_tasks",
    "dask_client",
    "error_curve",
    "fmt_interval",
    "run_matrix",
    "scaled",
    "scenario_task",
    "table_rows",
]

STATUSES = ("ok", "n/a", "diverged", "error")
"""What a cell of the matrix can be: scored, not applicable (condition named), diverged."""


@dataclass
class Curves:
    """Error over time of every method that ran on one scenario.

    Attributes
    ----------
    t : (K + 1,) array
        Time of each step in seconds (``k dt``).
    rms : dict
        Method name -> (K + 1,) network-mean RMS error: ``sqrt(mean over runs and nodes of
        ||x_hat_i(k) - x(k)||^2)``; NaN where an estimate is not finite.
    active : (K + 1,) array
        Fraction of runs in which the attack acts at step ``k`` (a sensor attacked, a
        falsified message, a link down); zero without attack.
    settle : int
        First step of the steady window (:func:`secest.arena.estimators.settle_steps`).
    """

    t: NDArray[np.float64]
    rms: dict[str, NDArray[np.float64]]
    active: NDArray[np.float64]
    settle: int


@dataclass
class Matrix:
    """The arena's result: a :class:`~secest.arena.estimators.Score` per (scenario, method).

    Attributes
    ----------
    scenarios : list of Scenario
    methods : list of str
        Method names in registration order.
    cells : dict
        ``(scenario name, method name) -> Score``.
    curves : dict
        Scenario name -> :class:`Curves`.
    seconds : dict
        ``(scenario name, method name) -> wall time of its run`` (machine-dependent).
    tasks : list of float
        Wall time of each task inside its process (machine-dependent): one per scenario in this
        process, one per batch on Dask (:func:`plan_tasks`). Their sum over the wall time of the
        call times the workers is the share of the workers' time spent on the arena's work.
    """

    scenarios: list[Scenario]
    methods: list[str]
    cells: dict[tuple[str, str], Score]
    curves: dict[str, Curves] = field(default_factory=dict)
    seconds: dict[tuple[str, str], float] = field(default_factory=dict)
    tasks: list[float] = field(default_factory=list)

    def cell(self, scenario: str, method: str) -> Score:
        """The score of ``method`` on the scenario named ``scenario``."""
        try:
            return self.cells[(scenario, method)]
        except KeyError:
            raise ValidationError(f"no cell ({scenario!r}, {method!r}) in the matrix") from None


def check_matrix(label: str, value: object) -> Matrix:
    """``value`` if it is a :class:`Matrix` (from :func:`run_matrix`).

    Parameters
    ----------
    label : str
        The argument's name, used in the message.
    value : object
        The value to check.

    Returns
    -------
    Matrix
        ``value``.

    Raises
    ------
    ValidationError
        If ``value`` is not a Matrix.
    """
    return check_instance(label, value, Matrix, "secest.arena.matrix.run_matrix")


def scaled(sc: Scenario, factor: float) -> Scenario:
    """``sc`` with its attack's magnitude multiplied by ``factor`` (same random draws).

    Bias, replacement and message attacks have a magnitude; ``none`` and ``dos`` are
    returned unchanged.

    Parameters
    ----------
    sc : Scenario
        The scenario.
    factor : float
        Positive finite factor on the attack magnitude.
    """
    if not (isinstance(factor, int | float) and not isinstance(factor, bool) and factor > 0
            and math.isfinite(factor)):
        raise ValidationError(f"factor must be a positive finite number, found {factor!r}")
    if check_scenario("sc", sc).attack.kind not in ("bias", "replacement", "message") or factor == 1:
        return sc
    return replace(sc, attack=replace(sc.attack, magnitude=sc.attack.magnitude * float(factor)))


def error_curve(xhat: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Network-mean RMS error over time: ``sqrt(mean_{runs, nodes} ||xhat - x||^2)``, shape (K + 1,).

    Parameters
    ----------
    xhat : (runs, K + 1, N, n) array
    x : (runs, K + 1, n) array
    """
    if xhat.ndim != 4 or x.ndim != 3 or xhat.shape[:2] != x.shape[:2] or xhat.shape[3] != x.shape[2]:
        raise ValidationError(
            f"Incompatible dimensions of xhat and x: expected (runs, K+1, N, n) and (runs, K+1, n), "
            f"found {xhat.shape} and {x.shape}"
        )
    with np.errstate(all="ignore"):
        sq = np.sum((xhat - x[:, :, None, :]) ** 2, axis=-1)
        out = np.sqrt(np.mean(sq, axis=(0, 2)))
    return np.where(np.isfinite(out), out, np.nan)


def attack_activity(trial: Trial) -> NDArray[np.float64]:
    """Fraction of runs in which the scenario's attack acts at each step, shape (K + 1,).

    Parameters
    ----------
    trial : Trial
        One simulated scenario (``secest.arena.scenarios.simulate``).
    """
    kind = estimators.check_trial("trial", trial).scenario.attack.kind
    if kind in ("bias", "replacement"):
        acting = trial.attacked.any(axis=2)
    elif kind == "message":
        acting = trial.hits.any(axis=2)
    elif kind == "dos":
        acting = trial.link == 0
    else:
        acting = np.zeros(trial.x.shape[:2], bool)
    return acting.mean(axis=0)


def run_matrix(
    scenarios: Sequence[Scenario],
    methods: Sequence[str] | None = None,
    *,
    curves: bool = True,
    short: bool = False,
    scheduler: str | None = None,
    workers: int | None = None,
) -> Matrix:
    """Score ``methods`` (default: every registered one) on every scenario.

    One :func:`~secest.arena.scenarios.simulate` per scenario feeds every method
    (:func:`secest.arena.estimators.evaluate`); the oracle is the reference of each ratio.
    In this process a scenario (its trial and every method on it) is one task; with ``scheduler``
    or ``workers`` the design runs as batches on Dask distributed (:func:`plan_tasks`), with the
    same result (every draw comes from the scenario's own seed).

    Parameters
    ----------
    scenarios : sequence of Scenario
        Names must be unique.
    methods : sequence of str, optional
        Registered method names; the oracle is always scored (it is the reference).
    curves : bool
        Keep each method's error over time (:class:`Curves`).
    short : bool
        Allow horizons without a steady window (smoke tests only; see
        :func:`~secest.arena.estimators.settle_steps`).
    scheduler : str, optional
        Address of a running Dask scheduler (``"tcp://host:8786"``); its workers need
        ``secest`` (and any module a method of one's own comes from) importable.
    workers : int, optional
        Without ``scheduler``: the number of single-threaded worker processes of a Dask
        ``LocalCluster`` started for this call (the ``sweep`` extra brings Dask).
    """
    names = list(METHODS) if methods is None else estimators.check_names("methods", methods)
    if "oracle" not in names:
        names.insert(0, "oracle")
    scenarios = _check_scenarios(scenarios)
    curves, short = check_bool("curves", curves), check_bool("short", short)
    check_dask_arguments(scheduler, workers)
    for sc in scenarios:  # every horizon checked before any work starts
        estimators.settle_steps(sc, short=short)
    shipped = [METHODS[n] for n in names]
    if scheduler is None and workers is None:
        done = [_timed_batch([sc], shipped, curves, short) for sc in scenarios]
    else:
        done = _on_dask(scenarios, shipped, curves, short, scheduler, workers)
    return _assemble(scenarios, names, done)


def _assemble(scenarios: list[Scenario], names: list[str],
              done: list[tuple[list, float]]) -> Matrix:
    """The matrix of the batches' parts, cells in scenario then method order (as in one process)."""
    cells: dict[str, dict[str, Score]] = {sc.name: {} for sc in scenarios}
    seconds: dict[str, dict[str, float]] = {sc.name: {} for sc in scenarios}
    curves: dict[str, Curves] = {}
    for parts, _ in done:
        for name, (c, t, curve) in parts:
            cells[name].update(c)
            seconds[name].update(t)
            if curve is not None and name in curves:
                curves[name].rms.update(curve.rms)
            elif curve is not None:
                curves[name] = curve
    out = Matrix(list(scenarios), names, {}, tasks=[t for _, t in done])
    for sc in scenarios:
        out.cells.update({(sc.name, n): cells[sc.name][n] for n in names})
        out.seconds.update({(sc.name, n): seconds[sc.name][n] for n in names if n in seconds[sc.name]})
        if sc.name in curves:
            rms = curves[sc.name].rms
            out.curves[sc.name] = replace(curves[sc.name], rms={n: rms[n] for n in names if n in rms})
    return out


def _check_scenarios(scenarios: object) -> list[Scenario]:
    """A non-empty list of scenarios with distinct names."""
    if isinstance(scenarios, Scenario) or not isinstance(scenarios, Sequence) or not scenarios:
        raise ValidationError(f"scenarios must be a non-empty list of Scenario, found "
                              f"{type(scenarios).__name__}")
    for sc in scenarios:
        check_scenario("scenarios: each entry", sc)
    seen = [sc.name for sc in scenarios]
    if len(set(seen)) != len(seen):
        raise ValidationError(f"scenarios: scenario names must be unique, found {seen}")
    return list(scenarios)


def scenario_task(
    sc: Scenario, methods: Sequence[estimators.Method], curves: bool, short: bool
) -> tuple[dict[str, Score], dict[str, float], Curves | None]:
    """One scenario of :func:`run_matrix`: its trial, every method's cell, wall times and curves.

    The methods travel with the task (a worker of an existing cluster may not have registered
    one's own); they are put in the worker's registry under their names before scoring.

    Parameters
    ----------
    sc : Scenario
        The scenario whose trial is simulated once and fed to every method.
    methods : sequence of Method
        The methods scored on that trial, in the order of the matrix's columns.
    curves : bool
        Keep each method's RMS error curve (for the figures) as well as its score.
    short : bool
        Accept a horizon shorter than the plant's time scale asks for (smoke tests only).

    Returns
    -------
    cells : dict of str to Score
        Each method's cell.
    seconds : dict of str to float
        Each method's wall time on the trial (for ``make bench``; never committed).
    curves : Curves or None
        The error curves and the windows, when ``curves`` is true.
    """
    for m in methods:
        METHODS[m.name] = m  # a worker process's own registry: the caller's methods, by name
    seconds: dict[str, float] = {}
    kept: dict[str, NDArray[np.float64]] = {}

    def observe(name: str, trial: Trial, est: Estimate) -> None:
        if curves:
            kept[name] = error_curve(est.xhat, trial.x)

    def timed(method: estimators.Method, trial: Trial) -> Estimate:
        t0 = time.perf_counter()
        est = method.run(trial)
        seconds[method.name] = time.perf_counter() - t0
        return est

    trial = simulate(sc)
    cells = estimators.evaluate(sc, [m.name for m in methods], timed, observe=observe,
                                trial=trial, short=short)
    curve = None
    if curves:
        curve = Curves(t=np.arange(sc.horizon + 1) * sc.plant.dt, rms=kept,
                       active=attack_activity(trial), settle=estimators.settle_steps(sc, short=short))
    return cells, seconds, curve


def check_dask_arguments(scheduler: object, workers: object) -> None:
    """Refuse a ``scheduler`` that is not an address, a ``workers`` that is not a count, or both.

    Parameters
    ----------
    scheduler : object
        ``None`` or the address of a running Dask scheduler, such as ``'tcp://127.0.0.1:8786'``.
    workers : object
        ``None`` or the number of worker processes of a LocalCluster, an integer from 1 to 256.

    Raises
    ------
    ValidationError
        Naming the argument and what was expected.
    """
    if scheduler is not None and not (isinstance(scheduler, str) and "://" in scheduler):
        raise ValidationError(f"scheduler must be a Dask scheduler address such as "
                              f"'tcp://127.0.0.1:8786', found {scheduler!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or not 1 <= workers <= 256):
        raise ValidationError(f"workers must be an integer from 1 to 256, found {workers!r}")
    if scheduler is not None and workers is not None:
        raise ValidationError("give scheduler (an existing cluster) or workers (a LocalCluster), "
                              f"not both: found scheduler={scheduler!r}, workers={workers!r}")


USER_MODULE_PREFIX = "secest_user_"
"""Module names of methods loaded from a file (:func:`secest.arena.cli.load_method`); on Dask
they are pickled by value, since a worker cannot import them by name."""


def _cost(sc: Scenario) -> float:
    """A scenario's relative cost: runs x steps x nodes (the order in which tasks are sent)."""
    return float(sc.runs * sc.horizon * sc.network.N)


@contextmanager
def dask_client(methods: Sequence[estimators.Method], scheduler: str | None,
                workers: int | None) -> Iterator[Any]:
    """A Dask client for arena tasks: a LocalCluster of ``workers`` processes, or ``scheduler``'s.

    A method loaded from a file (``--method path.py:Class``) cannot be imported by name on a
    worker, so its module is pickled by value. The cluster started here is closed on exit.

    Parameters
    ----------
    methods : sequence of Method
        The methods the tasks will carry.
    scheduler : str or None
        Address of a running scheduler; ``None`` starts a LocalCluster.
    workers : int or None
        Worker processes of the LocalCluster (one thread each).

    Yields
    ------
    dask.distributed.Client

    Raises
    ------
    ValidationError
        If Dask is not installed (the ``sweep`` extra).
    """
    try:
        from dask.distributed import Client, LocalCluster
    except ModuleNotFoundError:
        raise ValidationError("scheduler/workers need Dask: pip install 'secest[sweep]'") from None
    import cloudpickle

    for m in methods:
        module = sys.modules.get(type(m).__module__)
        if module is not None and module.__name__.startswith(USER_MODULE_PREFIX):
            cloudpickle.register_pickle_by_value(module)
    cluster = None
    if scheduler is None:
        # ":0": the scheduler's HTTP server on a free port (no clash with another cluster's 8787)
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0")
    client = Client(cluster if cluster is not None else scheduler)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


TASKS_PER_WORKER = 4
"""A design on Dask is cut into about this many batches per worker (:func:`plan_tasks`)."""


def plan_tasks(scenarios: Sequence[Scenario], methods: Sequence[str],
               workers: int) -> list[tuple[list[Scenario], list[str]]]:
    """The batches of a design on Dask: (scenarios, methods) pairs, largest first.

    A method's design (gains, LMIs, observer banks) depends on the plant, the network and the
    horizon, not on the attack or the seed, and is cached on the method: so every scenario of one
    (network, horizon) goes into the batches of that group, and each method into exactly one of
    them, so that no design is computed twice. A group's methods are dealt into as many batches
    as give about :data:`TASKS_PER_WORKER` batches per worker over the design (at most one batch
    per method), of about equal :attr:`~secest.arena.estimators.Method.cost`. Each batch draws
    its scenarios' trials and runs the oracle on them (the unit of every score): cheap beside the
    methods, and what keeps every draw equal to the one in a single process.

    Parameters
    ----------
    scenarios : sequence of Scenario
        The design's scenarios (distinct names).
    methods : sequence of str
        The method names scored on every scenario (the oracle among them).
    workers : int
        Worker processes the batches are for (>= 1).

    Returns
    -------
    list of (list of Scenario, list of str)
        The batches, by decreasing estimated cost (runs x steps x nodes x the methods' costs):
        the order to submit them in (a greedy balance).
    """
    groups: dict[tuple[str, int], list[Scenario]] = {}
    for sc in scenarios:
        groups.setdefault((sc.network.name, sc.horizon), []).append(sc)
    per_group = min(len(methods), max(1, math.ceil(TASKS_PER_WORKER * workers / len(groups))))
    batches = [(group, names) for group in groups.values()
               for names in _deal(list(methods), per_group)]
    return sorted(batches, key=lambda b: -sum(map(_cost, b[0])) * sum(METHODS[n].cost for n in b[1]))


def _deal(names: list[str], chunks: int) -> list[list[str]]:
    """``names`` dealt into ``chunks`` lists of about equal :attr:`Method.cost`, costliest first;
    each list in the order of ``names``."""
    dealt: list[list[str]] = [[] for _ in range(chunks)]
    loads = [0.0] * chunks
    for name in sorted(names, key=lambda n: -METHODS[n].cost):
        i = loads.index(min(loads))
        dealt[i].append(name)
        loads[i] += METHODS[name].cost
    return [sorted(d, key=names.index) for d in dealt]


def _timed_batch(scenarios: list[Scenario], methods: list[estimators.Method], curves: bool,
                 short: bool) -> tuple[list[tuple[str, Any]], float]:
    """:func:`scenario_task` of every scenario of a batch, and the batch's wall time."""
    t0 = time.perf_counter()
    parts = [(sc.name, scenario_task(sc, methods, curves, short)) for sc in scenarios]
    return parts, time.perf_counter() - t0


def _on_dask(scenarios: list[Scenario], methods: list[estimators.Method], curves: bool, short: bool,
             scheduler: str | None, workers: int | None) -> list[tuple[list, float]]:
    """:func:`plan_tasks`'s batches on Dask, submitted largest first; their parts and wall times."""
    with dask_client(methods, scheduler, workers) as client:
        n_workers = max(1, len(client.scheduler_info()["workers"]))
        by_name = dict(zip((m.name for m in methods), client.scatter(methods, broadcast=True),
                           strict=True))
        batches = plan_tasks(scenarios, list(by_name), n_workers)
        futures = [client.submit(_timed_batch, group, [by_name[n] for n in names], curves, short,
                                 pure=False, priority=len(batches) - i)
                   for i, (group, names) in enumerate(batches)]
        return client.gather(futures)


# ---------------------------------------------------------------------------------- words


def _sig(value: float, digits: int = 3) -> str:
    if value == 0 or not math.isfinite(value):
        return f"{value:g}"
    text = f"{value:.{digits}g}"
    if "e" in text:
        mant, exp = text.split("e")
        return f"{mant}e{int(exp)}"
    return text


def fmt_interval(value: tuple[float, float, float] | None, *, percent: bool = False) -> str:
    """``"1.23 [1.10, 1.40]"`` (3 significant digits; ``percent``: values as %), ``"–"`` for None.

    Parameters
    ----------
    value : tuple of float or None
        ``(value, low, high)``.
    percent : bool
        Show the numbers as percentages.
    """
    if value is None:
        return "–"
    if (not isinstance(value, tuple | list) or len(value) != 3
            or not all(isinstance(v, int | float | np.floating) for v in value)):
        raise ValidationError(f"value must be None or (value, low, high) numbers, found {value!r}")
    scale, unit = (100.0, " %") if percent else (1.0, "")
    v, lo, hi = (scale * float(u) for u in value)
    return f"{_sig(v)}{unit} [{_sig(lo)}, {_sig(hi)}]"


CELL_FIELDS = ("status", "steady", "worst", "transient", "detection", "false_alarm", "outside")
"""The words of a cell (:func:`cell_text`), in table order."""


def cell_text(s: Score) -> dict[str, str]:
    """The words of one cell: status, steady and worst-node scores, transient score, rates, marks.

    A scored cell gives every number with its interval ("–" where the method has no
    detector, or the scenario no attacked sample) and ``outside`` the failed conditions of
    the method's theory ("" inside it); an N/A cell names the missing requirement; a
    diverged one says why (not finite, or its growth factor), never a score; an error cell
    gives the error (``"error: <message>"``, or ``"needs extra: lmi ..."``).

    Parameters
    ----------
    s : Score
        The score of one (scenario, method) cell.
    """
    if not isinstance(s, Score):
        raise ValidationError(f"s must be a Score, found {type(s).__name__}")
    if s.status not in STATUSES:
        raise ValidationError(f"status must be one of {STATUSES}, found {s.status!r}")
    blank = dict.fromkeys(CELL_FIELDS, "")
    outside = "; ".join(s.outside)
    if s.status == "n/a":
        if not s.reason:
            raise ValidationError("an N/A cell must name the failed requirement (reason)")
        return blank | {"status": "N/A", "steady": f"N/A: {s.reason}"}
    if s.status == "diverged":
        text = f"diverged: {s.reason}" if s.reason else "diverged"
        return blank | {"status": "diverged", "steady": text, "outside": outside}
    if s.status == "error":
        text = s.reason if s.reason.startswith("needs extra") else f"error: {s.reason}"
        return blank | {"status": "error", "steady": text}
    if s.steady is None or s.steady_worst is None or s.transient is None:
        raise ValidationError("a scored cell must carry its steady, worst-node and transient scores")
    return {
        "status": "ok",
        "steady": fmt_interval(s.steady),
        "worst": fmt_interval(s.steady_worst),
        "transient": fmt_interval(s.transient),
        "detection": fmt_interval(s.detection, percent=True),
        "false_alarm": fmt_interval(s.false_alarm, percent=True),
        "outside": outside,
    }


def table_rows(m: Matrix) -> list[dict[str, str]]:
    """One row per (scenario, method), in scenario then method order, with :func:`cell_text`.

    Parameters
    ----------
    m : Matrix
        The scored matrix (:func:`run_matrix`).
    """
    rows = []
    for sc in check_matrix("m", m).scenarios:
        for name in m.methods:
            rows.append({"scenario": sc.name, "method": name} | cell_text(m.cell(sc.name, name)))
    return rows
