"""The arena's estimators behind one interface, and how they are scored.

Every estimator, the five papers' and the baselines', is a :class:`Method`: it names what
it needs to run at all (:meth:`Method.requirements`) and the conditions of its theory
(:meth:`Method.conditions`), both checked on a scenario before it runs, and :meth:`Method.run`
turns one :class:`secest.arena.scenarios.Trial` (all Monte Carlo runs at once) into an
:class:`Estimate`: every node's estimate at every step, and the method's alarms and covariance
bounds where it has them. A method whose requirement fails on a scenario does not run there
(the arena reports "N/A: <requirement>"); a failed condition of its theory marks the cell,
which is scored all the same.

Register a new method with :func:`register` (a test registers a toy method and finds it in
the matrix). :func:`score` compares an estimate with the oracle's on the same runs.

Baselines (every scenario):

* ``oracle``: centralised Kalman filter fed the clean measurements of every node;
* ``kf``: the same fed the measurements as delivered (attacks included), no defence;
* ``chi2-kf``: centralised Kalman filter that drops every node's measurement whose
  normalised innovation exceeds the chi-square quantile ``1 - CHI2_ALPHA`` (the classic
  bad-data detector); its drops are its alarms.

The centralised baselines have no inter-node links: falsified messages and denial of
service do not reach them (they are the references, not competitors, on those columns).
The distributed baselines (``local-kf``, ``consensus-kf-1``, ``consensus-kf``, ``diffusion-kf``,
``kcf``, ``wmsr-kf``) live in :mod:`secest.arena.baselines`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from secest.arena.scenarios import Network, Scenario, Trial, check_scenario
from secest.core.tolerances import DETERMINISTIC, Tolerance
from secest.core.validation import (
    ValidationError,
    check_bool,
    check_callable,
    check_instance,
    check_probability,
)

__all__ = [
    "BOOTSTRAP",
    "CENTRAL_BLOCK",
    "CHI2_ALPHA",
    "ESCAPE_LIMIT",
    "EXTRAS",
    "GROWTH_EXPONENT",
    "METHODS",
    "NodeGrowth",
    "RESERVED",
    "SETTLE_TAU",
    "Estimate",
    "Method",
    "Score",
    "check_names",
    "check_trial",
    "data_free_moment",
    "decisive",
    "divergence",
    "escape_reason",
    "escaped",
    "evaluate",
    "growth",
    "growth_exponent",
    "growth_nodes",
    "growth_not_excluded",
    "grows",
    "no_attack_conditions",
    "normalised_errors",
    "rate",
    "rate_of_counts",
    "register",
    "score",
    "scores_of_runs",
    "settle_steps",
    "whitening",
]

CHI2_ALPHA = 1e-3
"""False-alarm probability per measurement of the ``chi2-kf`` baseline's test."""


@dataclass
class Estimate:
    """What a method returns for one trial.

    Attributes
    ----------
    xhat : (runs, K + 1, N, n)
        Node ``i``'s estimate of ``x_k`` after using the data of step ``k``.
    alarms : (runs, K + 1, N) bool, optional
        Where the method flags node ``i``'s data at step ``k`` as attacked.
    bound : array, optional
        The covariance (or bound) the method reports, broadcastable to (runs, K + 1, N, n, n).
    notes : dict
        Anything else worth reporting (e.g. how a method was read on this scenario).
    """

    xhat: NDArray[np.float64]
    alarms: NDArray[np.bool_] | None = None
    bound: NDArray[np.float64] | None = None
    notes: dict[str, Any] = field(default_factory=dict)


class Method:
    """One estimator of the arena. Subclass it, set the attributes, implement :meth:`run`.

    Attributes
    ----------
    name : str
        Short id used in the matrix (e.g. ``"ding2020"``).
    title : str
        One line for tables and legends.
    kind : str
        ``"paper"`` (one of the five reproduced estimators) or ``"baseline"``.
    reading : str
        How the method is read on the shared scenarios where its paper's setting differs.
    tolerance : secest.repro.results.Tolerance
        How closely a re-run on another machine reproduces its estimates (and the scores
        made of them): :data:`~secest.repro.results.DETERMINISTIC` unless the method amplifies
        rounding (sign-driven dynamics, interior-point solves).
    home : str
        The network card of its paper's own example where the arena's cards host it (``""``
        for a baseline, or where they cannot: ``home_note`` says why).
    home_note : str
        How the home card differs from the paper's example, or why there is none.
    exchanges : bool
        Whether its nodes send each other messages (False: falsified or lost messages cannot
        reach it, so the message and DoS columns do not test it).
    cost : float
        Rough cost of the method on one scenario, its design included, relative to a Kalman
        filter's (1): it only orders the batches of a design on Dask, largest first
        (:func:`secest.arena.matrix.plan_tasks`), and never changes a result.
    """

    name: str = ""
    title: str = ""
    kind: str = "baseline"
    reading: str = ""
    tolerance: Tolerance = DETERMINISTIC
    home: str = ""
    home_note: str = ""
    exchanges: bool = True
    cost: float = 1.0

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        """The conditions of the method's theory on ``sc``: (statement, holds) pairs.

        A failed condition does not stop the method: its cell is scored and marked as
        outside its theory (:meth:`outside_theory`), so a mark never hides a result.
        """
        return []

    def told(self, sc: Scenario) -> str:
        """What the method is told about ``sc``'s attack from its card; ``""``: nothing.

        Some papers assume parts of the attack known (its channels, its probability): the
        arena gives them from the card, as the paper does. A told method does not find the
        attack by itself, so the findings on the attacks decide on the methods told nothing
        and report the told ones beside them.
        """
        return ""

    def requirements(self, sc: Scenario) -> list[tuple[str, bool]]:
        """What the method needs to run at all on ``sc``: (statement, holds) pairs.

        The one applicability rule of the arena, the same for every method: a cell is
        ``n/a`` only when the method cannot produce an estimate (it needs information the
        scenario does not give, or its design does not exist there).
        """
        return []

    def not_applicable(self, sc: Scenario) -> str | None:
        """The first requirement that fails on ``sc``, or None when the method can run."""
        return next((text for text, ok in self.requirements(sc) if not ok), None)

    def outside_theory(self, sc: Scenario) -> list[str]:
        """Every condition of the method's theory that fails on ``sc`` (empty: inside it)."""
        return [text for text, ok in self.conditions(sc) if not ok]

    def run(self, trial: Trial) -> Estimate:  # pragma: no cover - abstract
        """Estimate every node's state over every run of ``trial``."""
        raise NotImplementedError


METHODS: dict[str, Method] = {}
"""Every registered method by name, in registration order (baselines first)."""


RESERVED = frozenset({"oracle"})
"""Names that no method may take over: the oracle is the reference of every score."""


def register(method: Method | type[Method], *, replace: bool = False) -> Method | type[Method]:
    """Add ``method`` to :data:`METHODS` and return it unchanged (usable as a class decorator).

    Parameters
    ----------
    method : Method instance, or a Method subclass
        A class is instantiated without arguments for the registry; the class itself
        is returned, so it stays constructible with other design parameters.
    replace : bool, default False
        Replace a method already registered under the same name (never a :data:`RESERVED` one).

    Returns
    -------
    Method or type
        ``method`` itself.

    Raises
    ------
    ValidationError
        If ``method`` is not a :class:`Method` with a non-empty name, or its name is taken
        (unless ``replace``) or reserved.
    """
    replace = check_bool("replace", replace)
    inst = method() if isinstance(method, type) and issubclass(method, Method) else method
    if not isinstance(inst, Method) or not isinstance(inst.name, str) or not inst.name:
        raise ValidationError("method must be a secest.arena.estimators.Method with a non-empty name")
    if inst.name in METHODS:
        if inst.name in RESERVED:
            raise ValidationError(f"method name {inst.name!r} is reserved "
                                  "(the reference of every score)")
        if not replace:
            taken = type(METHODS[inst.name]).__name__
            raise ValidationError(f"method name {inst.name!r} is already registered ({taken}); "
                                  "pass replace=True to replace it")
    METHODS[inst.name] = inst
    return method


# ---------------------------------------------------------------------------------- Kalman filters


CENTRAL_BLOCK = 20
"""The centralised filters update with the nodes' measurements in blocks of this many nodes."""


def _blocks(sc: Scenario) -> list[tuple[slice, NDArray[np.float64], NDArray[np.float64]]]:
    """Per block of :data:`CENTRAL_BLOCK` nodes: its node slice, stacked ``C`` and diagonal ``R``."""
    N, n = sc.network.N, sc.plant.n
    r = np.diagonal(sc.R, axis1=1, axis2=2)  # (N, ny): the nodes' noise variances
    out = []
    for start in range(0, N, CENTRAL_BLOCK):
        nodes = slice(start, min(start + CENTRAL_BLOCK, N))
        out.append((nodes, sc.C[nodes].reshape(-1, n), np.diag(r[nodes].reshape(-1))))
    return out


def _prior(sc: Scenario, runs: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    n = sc.plant.n
    return np.zeros((runs, n)), sc.plant.x0_std**2 * np.eye(n)


def centralised_kf(
    sc: Scenario, y: NDArray[np.float64], use: NDArray[np.bool_] | None = None
) -> NDArray[np.float64]:
    """Kalman filter on every node's measurements; ``use[r, k, i]`` False drops node i's rows.

    The measurement noises of different nodes are independent, so the update with all nodes'
    rows is the same as updates with one block of nodes after the other (sequential processing):
    blocks of :data:`CENTRAL_BLOCK` nodes, each a stacked Joseph-form update of O((B ny)^3),
    so a step costs O(N) and never builds the (N ny) x (N ny) innovation covariance. A network
    of at most :data:`CENTRAL_BLOCK` nodes is one block: the plain stacked update. Vectorised
    over runs; with ``use`` the covariance depends on the run and is carried per run.

    Parameters
    ----------
    sc : Scenario
        The plant and the nodes' measurement matrices and noise covariances.
    y : (runs, K + 1, N, ny) array
        The measurements to filter.
    use : (runs, K + 1, N) bool array, optional
        Which nodes' measurements each step uses (default all).

    Returns
    -------
    (runs, K + 1, n) array
        The filtered estimates.
    """
    runs, K1 = y.shape[:2]
    A, Q = sc.plant.A, sc.plant.Q
    blocks = _blocks(sc)
    x, P = _prior(sc, runs)
    P = np.broadcast_to(P, (runs, *P.shape)).copy()
    out = np.empty((runs, K1, sc.plant.n))
    for k in range(K1):
        if k > 0:
            x, P = x @ A.T, A @ P @ A.T + Q
        x, P = _blocked_update(blocks, x, P, y[:, k], None if use is None else use[:, k])
        out[:, k] = x
    return out


def _blocked_update(
    blocks: list[tuple[slice, NDArray[np.float64], NDArray[np.float64]]], x: NDArray[np.float64],
    P: NDArray[np.float64], y: NDArray[np.float64], use: NDArray[np.bool_] | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The update with every node's rows ``y`` (runs, N, ny), one block (:func:`_blocks`) after
    another."""
    runs, _, ny = y.shape
    for nodes, C, R in blocks:
        rows = (np.ones((runs, C.shape[0]), bool) if use is None
                else np.repeat(use[:, nodes], ny, axis=1))
        x, P = _update(x, P, y[:, nodes].reshape(runs, -1), C, R, rows)
    return x, P


def _update(
    x: NDArray[np.float64],
    P: NDArray[np.float64],
    y: NDArray[np.float64],
    C: NDArray[np.float64],
    R: NDArray[np.float64],
    rows: NDArray[np.bool_],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Kalman update (Joseph form) of every run, using only the measurement rows ``rows[r]``.

    A dropped row has its row of ``C`` and its measurement set to zero: it carries no
    information and its gain column is exactly zero.
    """
    Cm = C[None] * rows[:, :, None]
    S = Cm @ P @ np.swapaxes(Cm, -1, -2) + R
    K = np.swapaxes(np.linalg.solve(S, Cm @ P), -1, -2)
    x = x + np.einsum("rnm,rm->rn", K, y * rows - np.einsum("rmn,rn->rm", Cm, x))
    IKC = np.eye(P.shape[-1]) - K @ Cm
    P = IKC @ P @ np.swapaxes(IKC, -1, -2) + K @ R @ np.swapaxes(K, -1, -2)
    return x, 0.5 * (P + np.swapaxes(P, -1, -2))


def _every_node(x: NDArray[np.float64], N: int) -> NDArray[np.float64]:
    return np.broadcast_to(x[:, :, None, :], (x.shape[0], x.shape[1], N, x.shape[2])).copy()


@register
class Oracle(Method):
    """Centralised Kalman filter on the clean measurements (the reference of every score)."""

    exchanges = False
    name = "oracle"
    title = "oracle: centralised KF, clean data"
    reading = "sees every node's measurement without the attack"

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        return Estimate(_every_node(centralised_kf(sc, trial.y_clean), sc.network.N))


def no_attack_conditions(sc: Scenario, *, links: bool) -> list[tuple[str, bool]]:
    """The attack model of a textbook filter: none. (statement, holds) pairs on ``sc``.

    The baselines' counterpart of the papers' attack models (:meth:`Method.conditions`): a
    Kalman filter's optimality assumes the measurements are its model's, and a distributed
    filter's (``links``) that every message is true and delivered; each attack outside that
    marks the cell, as a paper method's attack model marks its cells.

    Parameters
    ----------
    sc : Scenario
    links : bool
        The filter exchanges messages (falsified messages and lost links are then in its scope).
    """
    att = sc.attack
    out = [("its model: no attack on the measurements (a textbook Kalman filter)",
            att.kind not in ("bias", "replacement"))]
    if links:
        out += [("its model: every message true (no falsified messages)", att.kind != "message"),
                ("its model: every link delivers (no losses, no DoS)",
                 att.kind != "dos" and not att.lossy)]
    return out


@register
class UndefendedKF(Method):
    """Centralised Kalman filter on the delivered (attacked) measurements, no defence."""

    exchanges = False
    name = "kf"
    title = "centralised KF, no defence"
    reading = "no inter-node links: message and DoS attacks do not reach it"

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        return no_attack_conditions(sc, links=False)

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        return Estimate(_every_node(centralised_kf(sc, trial.y), sc.network.N))


@register
class Chi2KF(Method):
    """Centralised Kalman filter with a chi-square bad-data test on every node's innovation.

    Parameters
    ----------
    false_alarm : float, default :data:`CHI2_ALPHA`
        False-alarm probability per measurement of the test, in (0, 1): node ``i``'s data are
        dropped when its normalised innovation exceeds ``chi2(1 - false_alarm, n_y)``
        (the protocol's search set, ``protocol.toml`` [search.chi2-kf]).
    """

    exchanges = False
    name = "chi2-kf"
    title = "centralised KF + chi-square bad-data detector"
    reading = "drops node i's data when its normalised innovation exceeds chi2(1 - 1e-3, ny)"

    def __init__(self, false_alarm: float = CHI2_ALPHA) -> None:
        self.false_alarm = check_probability("false_alarm", false_alarm, open_interval=True)

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        runs, K1, N, ny = trial.y.shape
        threshold = float(stats.chi2.ppf(1 - self.false_alarm, ny))
        A, Q = sc.plant.A, sc.plant.Q
        blocks = _blocks(sc)
        x, P0 = _prior(sc, runs)
        P = np.broadcast_to(P0, (runs, *P0.shape)).copy()
        out = np.empty((runs, K1, sc.plant.n))
        alarms = np.zeros((runs, K1, N), bool)
        for k in range(K1):
            if k > 0:
                x, P = x @ A.T, A @ P @ A.T + Q
            eta = trial.y[:, k] - np.einsum("iyn,rn->riy", sc.C, x)
            S = np.einsum("iyn,rnm,izm->riyz", sc.C, P, sc.C) + sc.R
            nis = np.einsum("riy,riy->ri", eta, np.linalg.solve(S, eta[..., None])[..., 0])
            alarms[:, k] = nis > threshold
            x, P = _blocked_update(blocks, x, P, trial.y[:, k], ~alarms[:, k])
            out[:, k] = x
        return Estimate(_every_node(out, N), alarms=alarms)


def metropolis_weights(network: Network) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Metropolis-Hastings weights of an undirected graph, per edge: symmetric, doubly stochastic.

    ``w_ij = 1 / (1 + max(d_i, d_j))`` on every edge ``(i, j)`` of :attr:`Network.edges`
    (``d`` the in-degree), and ``w_ii = 1 - sum_j w_ij``: O(E), no N x N matrix.

    Parameters
    ----------
    network : Network
        The graph (its edge list and degrees).

    Returns
    -------
    edge : (E,) array
        ``w_ij`` of every edge, in the order of ``network.edges``.
    own : (N,) array
        ``w_ii`` of every node.
    """
    if not isinstance(network, Network):
        raise ValidationError(f"network must be a secest.arena.scenarios.Network, "
                              f"found {type(network).__name__}")
    d = network.degree
    edge = 1.0 / (1.0 + np.maximum(d[network.receivers], d[network.senders]))
    return edge, 1.0 - network.sum_in(edge[None])[0]


# ---------------------------------------------------------------------------------- scoring


SETTLE_TAU = 5
"""The transient window is the first ``SETTLE_TAU tau`` steps (``protocol.toml`` [score])."""
GROWTH_EXPONENT = 0.05
"""A cell is diverged when, at some node, the lower bound (95 % together over the nodes) of the
exponent ``p`` of a mean
squared error growing as ``k^p`` over the steady window exceeds this (:func:`grows`;
``protocol.toml`` [divergence], Amendment 3: a network growth factor of 4, then 2, read an error
growing as ``k`` (a random walk) as a score, and the network mean hid a node that grows; an
exponent means the same on every horizon, its interval the same at every run count)."""
ESCAPE_LIMIT = 1e4
"""A cell is diverged when its steady-window RMS error, pooled over its runs, exceeds this many
times the oracle's (``protocol.toml`` [divergence], Amendments 2 and 3: :func:`escaped`)."""
BOOTSTRAP = 2000
"""Percentile-bootstrap resamples of the runs for every score interval (seed 0)."""


@dataclass
class Score:
    """How one method did on one scenario, in the oracle's units, on the same runs.

    The unit-free error of node ``i`` at step ``k`` in run ``r`` is
    ``q = e^T Sigma_o^{-1} e / n`` with ``e = xhat - x`` and ``Sigma_o`` the oracle's error
    covariance pooled over runs and the window (:func:`score`); a score is
    ``sqrt(mean q)``: 1 is the oracle's accuracy on every plant, in any state coordinates.
    Every interval is a 95 % percentile bootstrap over the runs, ``(value, low, high)``.

    Attributes
    ----------
    status : {"ok", "n/a", "diverged", "error"}
        ``"ok"``: scored; ``"n/a"``: the method cannot run on the scenario (a requirement
        fails, :meth:`Method.requirements`); ``"diverged"``: an estimate is not finite, its
        error grows (:func:`grows`) or it escaped (:func:`escaped`): it shows no
        score; ``"error"``: it raised (its message, or ``needs extra: lmi``). The other cells
        are not affected.
    reason : str
        Why the status is not ``"ok"``; empty otherwise.
    outside : tuple of str
        The conditions of the method's theory that fail on the scenario
        (:meth:`Method.outside_theory`): the cell is scored and marked, never hidden.
    steady, steady_worst : (value, low, high) floats, optional
        Network score on the steady window ``[settle, K]`` (the mean over nodes of the
        per-node scores), and the worst node's.
    transient : (value, low, high) floats, optional
        Network score on the transient window ``[0, settle)``.
    growth : float, optional
        Mean ``q`` over the last quarter of the steady window over that of its second quarter
        (:func:`growth`); about 1 in a steady state; the divergence rule reads it as an
        exponent (:func:`growth_exponent`).
    growth_undecided : bool
        A scored cell some of whose nodes' growth exponent has an upper bound above
        :data:`GROWTH_EXPONENT` (:func:`growth_not_excluded`): its runs neither show nor exclude
        the growth; a mark (``‡`` in the arena's tables).
    detection, false_alarm : (value, low, high) floats, optional
        Alarm rates on the attacked / attack-free (run, step, node) samples of the steady
        window (:func:`rate`); None without alarms (or without an attacked sample).
    notes : dict
        The method's :attr:`Estimate.notes`, copied.
    """

    status: str
    reason: str = ""
    outside: tuple[str, ...] = ()
    steady: tuple[float, float, float] | None = None
    steady_worst: tuple[float, float, float] | None = None
    transient: tuple[float, float, float] | None = None
    growth: float | None = None
    growth_undecided: bool = False
    detection: tuple[float, float, float] | None = None
    false_alarm: tuple[float, float, float] | None = None
    notes: dict[str, Any] = field(default_factory=dict)


def settle_steps(sc: Scenario, *, short: bool = False) -> int:
    """First step of the steady window: ``ceil(SETTLE_TAU tau)`` (:attr:`Scenario.time_constant`).

    Parameters
    ----------
    sc : Scenario
    short : bool
        Allow a horizon shorter than ``MIN_HORIZON_TAU tau`` (a smoke test, fast mode): the
        windows are then halves of the horizon and mean nothing about a steady state.

    Raises
    ------
    ValidationError
        If the horizon is shorter than ``MIN_HORIZON_TAU tau`` and ``short`` is False.
    """
    from secest.arena.scenarios import MIN_HORIZON_TAU, horizon_of

    short = check_bool("short", short)
    tau = check_scenario("sc", sc).time_constant
    if sc.horizon < MIN_HORIZON_TAU * tau:
        if not short:
            raise ValidationError(
                f"horizon of {sc.name}: {sc.horizon} steps give no steady window; at least "
                f"{MIN_HORIZON_TAU} tau = {MIN_HORIZON_TAU * tau:.0f} steps (tau = {tau:.3g} steps; "
                f"horizon = \"auto\" gives {horizon_of(tau)})"
            )
        return max(1, sc.horizon // 2)
    return int(np.ceil(SETTLE_TAU * tau))


def normalised_errors(
    xhat: NDArray[np.float64], x: NDArray[np.float64], oracle: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``q = e^T Sigma_o^{-1} e / n`` per (run, step, node), ``Sigma_o`` pooled over the given steps.

    ``Sigma_o`` is the oracle's error second moment ``mean(e_o e_o^T)`` over the runs and steps
    (uncentred, so that the oracle's mean ``q`` is exactly 1; its error has mean about zero).

    Parameters
    ----------
    xhat : (runs, k, N, n) array
        The scored estimates on the window's steps.
    x : (runs, k, n) array
        The truth on the same steps.
    oracle : (runs, k, n) array
        The oracle's estimate on the same steps (one per step: it is centralised).

    Returns
    -------
    (runs, k, N) array
        The unit-free squared errors; their mean for the oracle is exactly 1.
    """
    xhat, x, oracle = (np.asarray(a, dtype=float) for a in (xhat, x, oracle))
    if (xhat.ndim != 4 or x.ndim != 3 or oracle.shape != x.shape
            or xhat.shape[:2] + xhat.shape[3:] != x.shape):
        raise ValidationError(f"Incompatible dimensions of xhat, x and oracle: expected (runs, k, N, "
                              f"n), (runs, k, n) and (runs, k, n), found {xhat.shape}, {x.shape} "
                              f"and {oracle.shape}")
    eo = (oracle - x).reshape(-1, x.shape[-1])
    e = xhat - x[:, :, None, :]
    white = e @ whitening(eo.T @ eo / eo.shape[0])
    return np.sum(white**2, axis=-1) / x.shape[-1]


def data_free_moment(sc: Scenario, start: int, stop: int) -> NDArray[np.float64]:
    """``sum over k in [start, stop) of P_k``: the error covariances of the estimate that uses no data.

    Without measurements or messages the best estimate of ``x_k`` is its prior mean, 0
    (``x_0 ~ N(0, x0_std^2 I)``, zero-mean noise), whose error covariance follows
    ``P_0 = x0_std^2 I``, ``P_{k+1} = A P_k A^T + Q``. It is the same for every method, attack
    and seed: the scale of a plant's scores (:func:`secest.arena.testseeds.data_free_score`).

    Parameters
    ----------
    sc : Scenario
    start, stop : int
        The window's steps, ``0 <= start < stop <= K + 1``.

    Returns
    -------
    (n, n) array
    """
    sc = check_scenario("sc", sc)
    if not (isinstance(start, (int, np.integer)) and isinstance(stop, (int, np.integer))
            and 0 <= start < stop <= sc.horizon + 1):
        raise ValidationError(f"start, stop must be steps with 0 <= start < stop <= K + 1 = "
                              f"{sc.horizon + 1}, found {start!r}, {stop!r}")
    A, Q = sc.plant.A, sc.plant.Q
    P = sc.plant.x0_std**2 * np.eye(sc.plant.n)
    total = np.zeros_like(P)
    for k in range(stop):
        if k >= start:
            total += P
        P = A @ P @ A.T + Q
    return total


def escaped(per_run: NDArray[np.float64]) -> bool:
    """Whether a cell escaped: its mean ``q`` over every run above ``ESCAPE_LIMIT^2``.

    A cell whose steady-window RMS error exceeds :data:`ESCAPE_LIMIT` times the oracle's has left
    every bounded regime of the arena; it is diverged even when its error stopped growing inside
    the window (an early blow-up, frozen by a detector that then rejects everything). In the
    score's own unit, so it means the same on every plant and horizon, and on the runs pooled
    (Amendment 3; per run before, where any one run of ``R`` decided, so the rule's meaning
    changed with the run count).

    Parameters
    ----------
    per_run : (runs,) or (runs, N) array
        Mean unit-free squared error ``q`` of each run (and node) over the steady window's steps.

    Returns
    -------
    bool
    """
    per_run = np.asarray(per_run, dtype=float)
    if per_run.ndim not in (1, 2) or per_run.size == 0 or not np.all(per_run >= 0):
        raise ValidationError("per_run must be a non-empty (runs,) or (runs, N) array of "
                              "non-negative mean squared errors")
    return bool(per_run.mean() > ESCAPE_LIMIT**2)


def escape_reason(per_run: NDArray[np.float64]) -> str:
    """The reason of an escaped cell (:func:`escaped`), its RMS error in the oracle's unit.

    Parameters
    ----------
    per_run : (runs,) or (runs, N) array
        The runs' mean ``q`` :func:`escaped` was given.
    """
    rms = np.sqrt(np.asarray(per_run, dtype=float).mean())
    return (f"it escaped: steady-window RMS error {rms:.2g} x the oracle's > "
            f"{ESCAPE_LIMIT:.0e}").replace("e+0", "e")


def whitening(sigma: NDArray[np.float64]) -> NDArray[np.float64]:
    """``W`` with ``W W^T = Sigma_o^{-1}``: ``q = |e W|^2 / n`` (:func:`normalised_errors`).

    A window of fewer oracle errors than states (a smoke test's) has a singular ``Sigma_o``: its
    null directions are floored at 1e-12 of the largest variance instead of failing.

    Parameters
    ----------
    sigma : (n, n) array
        The oracle's error second moment over a window (symmetric, positive semi-definite).

    Returns
    -------
    (n, n) array
        ``V diag(lambda)^{-1/2}``, ``V diag(lambda) V^T`` the floored eigendecomposition of ``sigma``.
    """
    lam, V = np.linalg.eigh(sigma)
    lam = np.maximum(lam, 1e-12 * lam.max())
    return V / np.sqrt(lam)


def _scores(q: NDArray[np.float64]) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Network and worst-node scores of ``q`` (runs, k, N), each with its bootstrap interval."""
    return scores_of_runs(q.mean(axis=1))


def scores_of_runs(
    per_run: NDArray[np.float64],
) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """Network and worst-node scores from each run's and node's mean ``q``, with their intervals.

    The interval of each is the 95 % percentile bootstrap over the runs (:data:`BOOTSTRAP`
    resamples, seed 0). Runs of several trials pool by stacking their rows (the test seeds).

    Parameters
    ----------
    per_run : (runs, N) array
        Mean unit-free squared error ``q`` over a window's steps, per run and node.

    Returns
    -------
    network, worst : (value, low, high)
        The mean over nodes of the per-node scores ``sqrt(mean over runs)``, and the largest.
    """
    rng = np.random.default_rng(0)
    resampled = per_run[rng.integers(0, per_run.shape[0], (BOOTSTRAP, per_run.shape[0]))].mean(axis=1)
    nodes, nodes_b = np.sqrt(per_run.mean(axis=0)), np.sqrt(resampled)

    def triple(value: float, draws: NDArray[np.float64]) -> tuple[float, float, float]:
        lo, hi = np.percentile(draws, [2.5, 97.5])
        return float(value), float(lo), float(hi)

    return (triple(nodes.mean(), nodes_b.mean(axis=1)), triple(nodes.max(), nodes_b.max(axis=1)))


class NodeGrowth(NamedTuple):
    """Every node's growth factor (:func:`growth_nodes`) and its 95 % bounds.

    Attributes
    ----------
    value : (N,) array
        Each node's factor: mean over runs of the last quarter / of the second quarter.
    low, high : (N,) arrays
        Its bounds, 95 % together over the ``N`` nodes.
    """

    value: NDArray[np.float64]
    low: NDArray[np.float64]
    high: NDArray[np.float64]


def quarters(length: int) -> tuple[slice, slice]:
    """The second and the last quarter of a window of ``length`` steps (:func:`growth`)."""
    return slice(length // 4, max(length // 2, length // 4 + 1)), slice((3 * length) // 4, None)


def growth(q: NDArray[np.float64]) -> tuple[float, float, float]:
    """The growth factor: mean ``q`` over the last quarter of the steps / over the second quarter.

    Parameters
    ----------
    q : (runs, k, N) array
        Unit-free squared errors on the steady window (:func:`normalised_errors`).

    Returns
    -------
    (value, low, high)
        Per node ``mean q[:, 3k/4:, i] / mean q[:, k/4:k/2, i]`` over the runs, with its 95 %
        interval over the runs; the node whose lower bound is the largest
        (:func:`growth_nodes`, :func:`decisive`). :func:`growth_exponent` turns a factor into the
        exponent the divergence rule reads.
    """
    if not isinstance(q, np.ndarray) or q.ndim != 3 or q.size == 0:
        raise ValidationError(f"q must be a (runs, k, N) array with k >= 1, found "
                              f"{getattr(q, 'shape', type(q).__name__)}")
    if not np.all(np.isfinite(q) & (q >= 0)):
        raise ValidationError("q must hold finite non-negative squared errors")
    return decisive(_growth_of_nodes(q))


def _growth_of_nodes(q: NDArray[np.float64]) -> NodeGrowth:
    """:func:`growth_nodes` of each run's means over the second and the last quarter of ``q``."""
    mid, late = quarters(q.shape[1])
    return growth_nodes(q[:, mid].mean(axis=1), q[:, late].mean(axis=1))


def growth_nodes(mid: NDArray[np.float64], late: NDArray[np.float64]) -> NodeGrowth:
    """Every node's growth factor with its interval over the runs.

    Per node ``i`` the factor is ``g_i = mean over runs of late / mean over runs of mid`` (each
    run's quarters have the same number of steps). Its interval treats the runs as independent
    draws: ``ln g_i +- t se_i``, ``se_i`` the standard error of the mean of
    ``late_r / mean(late) - mid_r / mean(mid)`` over the runs (the delta method for a log ratio
    of means) and ``t`` Student's ``1 - 0.025 / N`` quantile with ``runs - 1`` degrees of
    freedom: a few runs give a wide interval, not an overconfident one, and the ``N`` intervals
    hold together at 95 % (Bonferroni). ``N`` is the plant's, the same for every method on it (a
    centralised filter's ``N`` identical columns get the same, wider, quantile: more lenient for it
    than one test in the growth rule, harsher in the mark :func:`growth_not_excluded`).

    Parameters
    ----------
    mid, late : (runs,) or (runs, N) arrays
        Each run's (and node's) mean ``q`` over the steady window's second and last quarters
        (one run gives every node the interval ``(0, inf)``).

    Returns
    -------
    NodeGrowth
        ``value``, ``low``, ``high``: (N,) arrays; inf where a node's mean over the second quarter
        is 0 (its interval too).
    """
    mid, late = np.asarray(mid, dtype=float), np.asarray(late, dtype=float)
    if mid.ndim not in (1, 2) or mid.shape != late.shape or mid.size == 0:
        raise ValidationError(f"mid, late must be two (runs,) or (runs, N) arrays of one shape, "
                              f"found shapes {mid.shape}, {late.shape}")
    mid, late = mid.reshape(mid.shape[0], -1), late.reshape(late.shape[0], -1)
    m, l_ = mid.mean(axis=0), late.mean(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.where(m > 0, l_ / np.where(m > 0, m, 1.0), np.inf)
        d = late / np.where(l_ > 0, l_, 1.0) - mid / np.where(m > 0, m, 1.0)
    runs, nodes = mid.shape
    quantile = 1 - 0.025 / nodes  # simultaneous over the nodes (Bonferroni): one level for any N
    spread = (stats.t.ppf(quantile, runs - 1) * d.std(axis=0, ddof=1) / np.sqrt(runs) if runs > 1
              else np.full(nodes, np.inf))  # one run decides no growth: (0, inf)
    low = np.where(np.isfinite(value), value * np.exp(-spread), np.inf)
    high = np.where(np.isfinite(value), value * np.exp(spread), np.inf)
    return NodeGrowth(value, low, high)


def decisive(nodes: NodeGrowth) -> tuple[float, float, float]:
    """The factor and bounds of the node the growth rule (:func:`grows`) reads.

    Parameters
    ----------
    nodes : NodeGrowth
        Every node's factor and bounds (:func:`growth_nodes`).

    Returns
    -------
    (value, low, high)
        Those of the node whose lower bound is the largest (the first such).
    """
    worst = int(np.argmax(nodes.low))
    return float(nodes.value[worst]), float(nodes.low[worst]), float(nodes.high[worst])


def growth_exponent(factor: float, settle: int, length: int) -> float:
    """The exponent ``p`` of a mean squared error growing as ``k^p`` that gives ``factor``.

    With the steady window's steps ``settle .. settle + length - 1`` and ``k_mid``, ``k_late`` the
    mean steps of its second and last quarters (:func:`quarters`),
    ``p = ln(factor) / ln(k_late / k_mid)``: for a power law of the step it returns ``p`` exactly
    for ``p = 1`` and to within 1 % for ``0 < p <= 2`` on the arena's windows, whatever the
    horizon (a factor's meaning depends on where the window lies: 1.71 is ``k^1`` on a window
    ``[5 tau, 20 tau]``). A cell is diverged when ``p > GROWTH_EXPONENT``
    (``protocol.toml`` [divergence], Amendment 3).

    Parameters
    ----------
    factor : float
        :func:`growth`'s factor (>= 0, or inf).
    settle : int
        The steady window's first step (>= 1).
    length : int
        Its number of steps (>= 4: two distinct quarters).

    Returns
    -------
    float
        ``p``; inf for an infinite factor, -inf for 0.
    """
    if not (isinstance(settle, (int, np.integer)) and settle >= 1
            and isinstance(length, (int, np.integer)) and length >= 4):
        raise ValidationError(f"settle, length must be integers >= 1 and >= 4, found "
                              f"{settle!r}, {length!r}")
    if not factor >= 0:
        raise ValidationError(f"factor must be a non-negative growth factor, found {factor!r}")
    mid, late = (settle + np.mean(range(*part.indices(length))) for part in quarters(length))
    with np.errstate(divide="ignore"):
        return float(np.log(factor) / np.log(late / mid))


def grows(factor: tuple[float, float, float], settle: int, length: int) -> bool:
    """The growth rule: a node's growth exponent's lower bound above ``GROWTH_EXPONENT``.

    A window of fewer than 4 steps has no two distinct quarters: no growth is ruled there.

    A rule on the interval, as every rule on a rate (``protocol.toml`` [detection]): what it
    tests, a mean squared error growing faster than ``k^GROWTH_EXPONENT``, does not change with
    the run count; more runs only narrow the interval (Amendment 3).

    Parameters
    ----------
    factor : (value, low, high)
        :func:`growth`'s factor and interval.
    settle, length : int
        The steady window (:func:`growth_exponent`).
    """
    return length >= 4 and not growth_exponent(factor[1], settle, length) <= GROWTH_EXPONENT


def growth_not_excluded(upper: float, settle: int, length: int) -> bool:
    """The mark ``growth_undecided``: some node's growth exponent's upper bound above the limit.

    Read on a row that :func:`grows` did not rule diverged: its runs neither show a node growing
    faster than ``k^GROWTH_EXPONENT`` nor exclude it (Amendment 4; a row is *bounded* only when
    every node's upper bound is at most the limit). What the runs resolve is each row's interval,
    reported beside it.

    Parameters
    ----------
    upper : float
        The largest upper bound of the nodes' growth factors (:func:`growth_nodes`).
    settle, length : int
        The steady window (:func:`growth_exponent`); a window of fewer than 4 steps rules nothing.
    """
    return length >= 4 and not growth_exponent(upper, settle, length) <= GROWTH_EXPONENT


def divergence(factor: tuple[float, float, float], per_run: NDArray[np.float64], settle: int,
               length: int) -> str:
    """Why a scored cell is diverged by the rules of ``protocol.toml`` [divergence], or ``""``.

    The growth rule (:func:`grows`) first, then escape (:func:`escaped`); one place for both
    :func:`score` and the test stage's pooled rows. A non-finite estimate is decided before.
    The growth reason holds no number: its factor is reported beside it (round-off amplified by
    a divergence decides its digits).

    Parameters
    ----------
    factor : (value, low, high)
        :func:`growth`'s factor and interval.
    per_run : (runs,) or (runs, N) array
        Mean ``q`` over the steady window per run (and node), as :func:`escaped` takes it.
    settle, length : int
        The steady window (:func:`growth_exponent`).
    """
    if grows(factor, settle, length):
        return (f"its error grows: some node's mean squared error grows as k^p with p above "
                f"{GROWTH_EXPONENT:g} (lower bound, 95 % over the nodes)")
    return escape_reason(per_run) if escaped(per_run) else ""


def score(trial: Trial, estimate: Estimate, oracle: Estimate, *, short: bool = False) -> Score:
    """Unit-free scores on the transient and steady windows, divergence by growth, alarm rates.

    Parameters
    ----------
    trial : Trial
        The runs both estimates were computed on.
    estimate : Estimate
        The scored method's estimates, ``xhat`` (runs, K + 1, N, n), with its ``alarms``.
    oracle : Estimate
        The oracle's estimates on the same trial (:class:`Oracle`): its error covariance is the
        unit of the score, per window.
    short : bool
        Allow a horizon without a steady window (:func:`settle_steps`); the growth factor is
        then reported, not ruled on.

    Returns
    -------
    Score
        ``"ok"`` with the scores (and rates when the method raises alarms), or ``"diverged"``
        with the reason (not finite, its growth exponent, or its escape).
    """
    trial = check_trial("trial", trial)
    _check_estimate("estimate", estimate, trial)
    _check_estimate("oracle", oracle, trial)
    _check_oracle_of(oracle, trial)
    settle = settle_steps(trial.scenario, short=short)
    if not np.all(np.isfinite(estimate.xhat)):
        return Score("diverged", "the estimate is not finite in some run")
    x, xo = trial.x, oracle.xhat[:, :, 0]
    q_steady = normalised_errors(estimate.xhat[:, settle:], x[:, settle:], xo[:, settle:])
    nodes = _growth_of_nodes(q_steady)
    g, length = decisive(nodes), q_steady.shape[1]
    why = "" if short else divergence(g, q_steady.mean(axis=1), settle, length)
    if why:  # a short horizon has no steady window to grow in: reported, not ruled
        return Score("diverged", why, growth=g[0])
    steady, worst = _scores(q_steady)
    transient = _scores(normalised_errors(estimate.xhat[:, :settle], x[:, :settle], xo[:, :settle]))[0]
    undecided = not short and growth_not_excluded(float(nodes.high.max()), settle, length)
    result = Score("ok", steady=steady, steady_worst=worst, transient=transient, growth=g[0],
                   growth_undecided=undecided, notes=dict(estimate.notes))
    if estimate.alarms is not None:
        attacked = trial.attacked[:, settle:]
        alarms = estimate.alarms[:, settle:]
        if attacked.any():
            result.detection = rate(alarms, attacked)
        result.false_alarm = rate(alarms, ~attacked)
    return result


def _scenario_key(sc: Scenario) -> tuple:
    """What identifies a scenario's draws: its name, cards, horizon, runs and seed."""
    return (sc.name, sc.plant.name, sc.network.name, sc.attack, sc.horizon, sc.runs, sc.seed)


def check_trial(label: str, value: object) -> Trial:
    """``value`` if it is a :class:`~secest.arena.scenarios.Trial` (drawn by ``simulate``).

    Parameters
    ----------
    label : str
        The argument's name, used in the message.
    value : object
        The value to check.

    Returns
    -------
    Trial
        ``value``.

    Raises
    ------
    ValidationError
        If ``value`` is not a Trial.
    """
    return check_instance(label, value, Trial, "secest.arena.scenarios.simulate")


def check_names(label: str, names: object) -> list[str]:
    """``names`` if it is a non-empty list of distinct registered method names.

    Parameters
    ----------
    label : str
        The argument's name, used in the message (``names``, ``methods``).
    names : object
        The value to check.

    Returns
    -------
    list of str
        The names, in the order given.

    Raises
    ------
    ValidationError
        If ``names`` is a bare string, not a non-empty list of strings, lists a name twice, or
        names a method that is not registered.
    """
    if (isinstance(names, str) or not isinstance(names, list | tuple) or not names
            or not all(isinstance(n, str) for n in names)):
        raise ValidationError(f"{label} must be a non-empty list of registered method names, "
                              f"found {names!r}")
    if len(set(names)) != len(names):
        raise ValidationError(f"{label}: a method is listed twice in {list(names)}")
    unknown = [n for n in names if n not in METHODS]
    if unknown:
        raise ValidationError(f"{label}: methods {unknown} are not registered; registered: "
                              f"{list(METHODS)}")
    return list(names)


def _check_oracle_of(oracle: Estimate, trial: Trial) -> None:
    """``oracle`` is the oracle's estimate on ``trial``: its first step is recomputed and compared.

    The first step is the prior updated with the clean measurements of step 0 (one Kalman update),
    so an oracle run on another trial (of the same shapes) is refused at the cost of one update.
    """
    sc = trial.scenario
    first = centralised_kf(sc, trial.y_clean[:, :1])[:, 0]
    if not np.allclose(oracle.xhat[:, 0, 0], first, rtol=1e-6, atol=1e-9 * sc.plant.x0_std):
        raise ValidationError(f"oracle: not the oracle's estimate on this trial of {sc.name!r} "
                              "(computed on another trial?)")


def _check_estimate(name: str, est: Estimate, trial: Trial) -> None:
    """``est`` has one estimate per run, step, node and state component of ``trial``."""
    runs, K1, N, _ = trial.y.shape
    want = (runs, K1, N, trial.scenario.plant.n)
    xhat = getattr(est, "xhat", None)
    if not isinstance(est, Estimate) or not isinstance(xhat, np.ndarray):
        raise ValidationError(f"{name} must be an Estimate with an array xhat, found "
                              f"{type(est).__name__}")
    if xhat.shape != want:
        raise ValidationError(f"Incompatible dimensions of {name}.xhat: expected {want} "
                              f"(runs, K + 1, nodes, states), found {xhat.shape}")
    if not np.issubdtype(xhat.dtype, np.number) or np.issubdtype(xhat.dtype, np.complexfloating):
        raise ValidationError(f"{name}.xhat must hold real numbers, found dtype {xhat.dtype}")
    if est.alarms is not None and (np.shape(est.alarms) != want[:3]
                                   or np.asarray(est.alarms).dtype != bool):
        raise ValidationError(f"{name}.alarms must be a bool array of shape {want[:3]}, found "
                              f"{np.shape(est.alarms)} of {np.asarray(est.alarms).dtype}")
    if est.bound is not None:
        try:
            np.broadcast_shapes(np.shape(est.bound), (*want, want[-1]))
        except ValueError:
            raise ValidationError(f"Incompatible dimensions of {name}.bound: expected an array "
                                  f"broadcastable to {(*want, want[-1])}, found "
                                  f"{np.shape(est.bound)}") from None


def rate(alarms: NDArray[np.bool_], where: NDArray[np.bool_]) -> tuple[float, float, float]:
    """Fraction of the samples ``where`` that carry an alarm, with a 95 % interval.

    Samples are (run, step, node); the alarms of one run are correlated (a detector that
    locks out alarms for many steps), so the interval is the union of the Wilson interval
    (samples taken as independent) and a percentile bootstrap over runs (the ratio of the
    per-run sums, runs resampled): never narrower than either.

    Parameters
    ----------
    alarms, where : (runs, K, N) bool arrays

    Returns
    -------
    (rate, low, high)
    """
    for label, a in (("alarms", alarms), ("where", where)):
        if not isinstance(a, np.ndarray) or a.dtype != bool or a.ndim == 0:
            raise ValidationError(f"{label} must be a bool array of (run, ...) samples, found "
                                  f"{getattr(a, 'dtype', type(a).__name__)}")
    if alarms.shape != where.shape:
        raise ValidationError(f"Incompatible dimensions of alarms and where: {alarms.shape} and "
                              f"{where.shape}")
    hits = (alarms & where).reshape(alarms.shape[0], -1).sum(axis=1)
    total = where.reshape(where.shape[0], -1).sum(axis=1)
    return rate_of_counts(hits, total)


def rate_of_counts(hits: NDArray[np.int_], total: NDArray[np.int_]) -> tuple[float, float, float]:
    """:func:`rate` from per-run counts: ``sum(hits) / sum(total)`` with the same 95 % interval.

    Runs of several trials (e.g. the validation seeds of the tuning) pool by concatenating their
    counts: the Wilson interval of the pooled samples united with a bootstrap over the runs.

    Parameters
    ----------
    hits, total : (runs,) integer arrays
        Per run, the alarms on the selected samples and the number of selected samples.

    Returns
    -------
    (rate, low, high)
    """
    from secest.core.montecarlo import bootstrap_interval, wilson_interval

    hits, total = np.asarray(hits), np.asarray(total)
    if hits.ndim != 1 or hits.shape != total.shape:
        raise ValidationError(f"Incompatible dimensions of hits and total: expected two (runs,) "
                              f"arrays, found {hits.shape} and {total.shape}")
    if not all(np.issubdtype(a.dtype, np.integer) for a in (hits, total)):
        raise ValidationError(f"hits and total must be integer counts, found {hits.dtype} and "
                              f"{total.dtype}")
    if np.any(hits < 0) or np.any(hits > total):
        raise ValidationError("hits and total: every run needs 0 <= hits <= total")
    n_hits, n = int(hits.sum()), int(total.sum())
    if n == 0:
        raise ValidationError("where must select at least one sample")
    low, high = wilson_interval(n_hits, n)
    used = total > 0
    if used.sum() >= 2 and 0 < n_hits:
        try:
            b_low, b_high = bootstrap_interval(np.column_stack([hits[used], total[used]]), "mean")
        except ValidationError:  # a resample of runs without a single sample: Wilson only
            pass
        else:
            low, high = min(low, b_low), max(high, b_high)
    return n_hits / n, low, high


def evaluate(
    sc: Scenario,
    names: list[str] | None = None,
    runner: Callable | None = None,
    *,
    observe: Callable[[str, Trial, Estimate], None] | None = None,
    trial: Trial | None = None,
    short: bool = False,
) -> dict[str, Score]:
    """Score every method (or ``names``) on scenario ``sc``: one trial, the oracle as the unit.

    Every method runs unless it cannot (:meth:`Method.not_applicable`: ``n/a``); a method
    outside its theory is scored and marked (:attr:`Score.outside`); one that raises is an
    ``error`` cell.

    Parameters
    ----------
    sc : Scenario
    names : list of str, optional
        Registered method names, a non-empty list (default: every one, in registration order).
    runner : callable, optional
        ``runner(method, trial) -> Estimate`` instead of ``method.run(trial)`` (e.g. to time it).
    observe : callable, optional
        Called as ``observe(name, trial, estimate)`` for every method that ran (the oracle
        first), e.g. to keep error curves without holding every estimate in memory.
    trial : Trial, optional
        The runs to use (default: :func:`secest.arena.scenarios.simulate` of ``sc``).
    short : bool
        Allow a horizon without a steady window (:func:`settle_steps`; smoke tests only).
    """
    from secest.arena.scenarios import simulate

    sc = check_scenario("sc", sc)
    names = list(METHODS) if names is None else check_names("names", names)
    for label, fn in (("runner", runner), ("observe", observe)):
        if fn is not None:
            check_callable(label, fn)
    if trial is not None and _scenario_key(check_trial("trial", trial).scenario) != _scenario_key(sc):
        raise ValidationError(f"trial: drawn for scenario {trial.scenario.name!r}, not for {sc.name!r}")
    settle_steps(sc, short=short)
    trial = simulate(sc) if trial is None else trial
    oracle = METHODS["oracle"].run(trial)
    if observe is not None:
        observe("oracle", trial, oracle)
    out: dict[str, Score] = {}
    for name in names:
        out[name] = _cell(METHODS[name], trial, oracle, runner, observe, short)
    return out


def _cell(method: Method, trial: Trial, oracle: Estimate, runner: Callable | None,
          observe: Callable | None, short: bool) -> Score:
    """One cell: n/a, error, or the score marked with the failed conditions of its theory."""
    sc = trial.scenario
    try:
        reason = method.not_applicable(sc)
        if reason is not None:
            return Score("n/a", reason)
        outside = tuple(method.outside_theory(sc))
        if method.name == "oracle":
            est = oracle
        else:
            est = (runner or (lambda m, t: m.run(t)))(method, trial)
            if observe is not None:
                observe(method.name, trial, est)
        result = score(trial, est, oracle, short=short)
    except Exception as exc:  # one failing method is one cell, never an aborted matrix
        return Score("error", _error_reason(exc))
    result.outside = outside
    return result


EXTRAS = {"cvxpy": "lmi", "clarabel": "lmi", "scs": "lmi"}
"""Optional packages a method may need, and the extra of ``pyproject.toml`` that brings them."""


def _error_reason(exc: Exception) -> str:
    """One line for an ``"error"`` cell: the missing extra, or the exception's type and message."""
    if isinstance(exc, ModuleNotFoundError) and (exc.name or "").split(".")[0] in EXTRAS:
        extra = EXTRAS[exc.name.split(".")[0]]
        return f"needs extra: {extra} (pip install 'secest[{extra}]')"
    first = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__
