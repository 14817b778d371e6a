"""Shared scenarios of the arena: plants, networks and attacks as data (``secest/arena/cards.toml``).

A **scenario** is a plant observed by a sensor network under one attack, over a horizon,
with a number of Monte Carlo runs. Every card lives in ``secest/arena/cards.toml``: a new plant,
network or attack is one TOML table; the ``[matrix]`` crosses every network (with its plant)
with every attack, and a ``[scenario.<name>]`` table adds one named scenario (a network and
an attack, optionally its own horizon, runs and seed) outside the cross. More cards can be
passed to :func:`cards`, :func:`scenario` and :func:`matrix` (``extra=``: a TOML file or the
parsed tables) without editing the package's file. :func:`simulate` draws the runs of a
scenario once, so that every estimator of the arena is fed the very same truth,
measurements, channel and attacks.

The model (every plant is linear and time-invariant)::

    x'(t) = Ac x(t)                                   continuous time (lee2020 integrates it)
    x_{k+1} = A x_k + w_k,   A = expm(Ac dt)          sampled every dt (the truth)
    y_{i,k} = C_i x_k + v_{i,k} + a_{i,k}             node i, rows `measures[i]` of the catalogue

``w`` and ``v`` are Gaussian with standard deviations ``q_std`` and ``r_std``, clipped at
:data:`NOISE_CLIP` standard deviations per component: bounded, so ellipsoidal noise
bounds (ma2021's Assumption 1) hold with ``w^T w <= n NOISE_CLIP^2 q_std^2``, while
their covariance stays within 3 % of the nominal one the Kalman-type estimators assume.
``a`` is the sensor attack (bias, Bernoulli replacement); attacks on what nodes send each
other (falsified messages, denial of service) are drawn here and applied by each estimator
to whatever it exchanges (:meth:`Trial.received`).
"""

from __future__ import annotations

import difflib
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import scipy.linalg as sla
from numpy.typing import NDArray
from scipy.sparse import csr_array

from secest.core import validation
from secest.core.validation import (
    ValidationError,
    as_matrix,
    check_callable,
    check_instance,
    check_positive_int,
)

__all__ = [
    "ATTACK_KINDS",
    "CARD_KEYS",
    "DENSE_NODES",
    "NOISE_CLIP",
    "Attack",
    "Network",
    "Plant",
    "Scenario",
    "SETTINGS",
    "Trial",
    "auto_horizon",
    "cards",
    "check_horizon",
    "check_scenario",
    "horizon_of",
    "matrix",
    "scenario",
    "simulate",
    "steady_state",
]

NOISE_CLIP = 3.0
"""Process and measurement noises are clipped at this many standard deviations per component."""
ATTACK_KINDS = ("none", "bias", "replacement", "message", "dos")

CARD_KEYS: dict[str, dict[str, str]] = {
    "plant": {
        "title": "one line for tables and figures",
        "source": "where the numbers come from",
        "Ac": "continuous-time dynamics x' = Ac x, a square matrix",
        "dt": "sampling period [s], > 0",
        "q_std": "process-noise standard deviation per component, > 0",
        "outputs": "catalogue of sensor rows, a matrix with n columns",
        "r_std": "noise standard deviation of each output, > 0",
        "x0_std": "prior standard deviation of every state component, > 0",
        "state_names": "one name per state component",
    },
    "network": {
        "title": "one line for tables and figures",
        "plant": "name of the plant card it observes",
        "N": "number of nodes, >= 2",
        "graph": "ring, complete or rgg (random geometric graph in the unit square)",
        "degree": "ring only, optional: even degree, >= 2 and < N (default 2)",
        "radius": "rgg only: connection radius",
        "seed": "rgg only: seed of the node positions",
        "measures": "per node, the rows of the plant's outputs it measures (0-based)",
    },
    "attack": {
        "title": "one line for tables and figures",
        "kind": "one of ATTACK_KINDS",
        "nodes": "bias, replacement: attacked sensor nodes, distinct 0-based indices below N",
        "start": "bias: onset as a fraction of the horizon, in [0, 1) (or give windows)",
        "windows": "bias, instead of start: per entry of nodes, the steps [first, last] (inclusive) "
                   "or [first] (to the horizon's end) of its bias",
        "prob": "replacement: probability a measurement is replaced; "
                "message: that a message is falsified; in (0, 1]",
        "magnitude": "bias, replacement: in noise standard deviations; "
                     "message: in the message's scale",
        "p": "dos (bias, optional: the links fail as well): failure probability per step of the "
             "shared Gilbert-Elliott chain, in (0, 1]",
        "q": "dos (bias, optional, with p): recovery probability per step, in [0, 1]",
    },
    "scenario": {
        "title": "optional: one line for tables and figures, a non-empty string",
        "network": "name of a network card (with its plant)",
        "attack": "name of an attack card",
        "horizon": "optional: steps, an integer >= 1, or \"auto\" (20 time constants of the "
                   "plant on the network)",
        "runs": "optional: Monte Carlo runs, an integer >= 2",
        "seed": "optional: seed of the trials, an integer >= 0",
    },
    "matrix": {
        "networks": "network cards crossed with the attacks, a non-empty list of card names "
                    "(an extra file's list is appended)",
        "attacks": "attack cards crossed with the networks, a non-empty list of card names "
                   "(an extra file's list is appended)",
        "horizon": "package file only: steps, an integer >= 1, or \"auto\"; a call passes horizon=",
        "runs": "package file only: Monte Carlo runs, an integer >= 2; a call passes runs=",
        "seed": "package file only: seed of the trials, an integer >= 0; a call passes seed=",
    },
}
"""Every key a card may have, with what it means: the one schema the validator and the docs use.

``plant``, ``network``, ``attack`` and ``scenario`` are named tables (``[<kind>.<name>]``);
``matrix`` is the one ``[matrix]`` table."""

_ATTACK_KEYS = {
    "none": (set(), set()),
    "bias": ({"nodes", "magnitude"}, {"start", "windows", "p", "q"}),
    "replacement": ({"nodes", "prob", "magnitude"}, set()),
    "message": ({"prob", "magnitude"}, set()),
    "dos": ({"p", "q"}, set()),
}
"""Per attack kind: (required keys, optional keys) beyond ``title`` and ``kind``."""
_NETWORK_KEYS = {
    "ring": (set(), {"degree"}),
    "complete": (set(), set()),
    "rgg": ({"radius", "seed"}, set()),
}
"""Per graph kind: (required, optional) keys beyond the common ones."""


def _check_keys(kind: str, name: str, card: Mapping[str, Any], required: set[str],
                allowed: set[str]) -> None:
    """Refuse a card with a key outside ``allowed`` (naming the nearest valid key) or one missing."""
    for key in sorted(set(card) - allowed):
        near = difflib.get_close_matches(key, sorted(allowed), n=1)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        raise ValidationError(f"{kind} {name}: unknown key {key!r}{hint}; valid: {sorted(allowed)}")
    missing = sorted(required - set(card))
    if missing:
        raise ValidationError(f"{kind} {name}: missing key(s) {missing}")


def _check_text(label: str, value: object) -> str:
    """``value`` if it is a non-empty string (a title, a source, a name)."""
    if not isinstance(value, str) or not value.strip():
        raise ValidationError(f"{label} must be a non-empty string, found {value!r}")
    return value


def _check_table(label: str, value: object) -> dict[str, Any]:
    """``value`` as a dict if it is a table (a mapping of keys to values)."""
    if not isinstance(value, Mapping):
        raise ValidationError(f"{label} must be a table (keys and values), found {value!r}")
    return dict(value)


def check_horizon(label: str, value: object) -> int | str:
    """A horizon: ``"auto"`` or an integer number of steps from 1 to ``MAX_STEPS``.

    Parameters
    ----------
    label : str
        What the value is (the argument or card key), used in the message.
    value : object
        The horizon to check.

    Returns
    -------
    int or "auto"
        ``value``.

    Raises
    ------
    ValidationError
        If ``value`` is neither (a :class:`~secest.core.validation.SizeLimitError` above the limit).
    """
    if isinstance(value, str):
        if value != "auto":
            raise ValidationError(f'{label} must be an integer >= 1 or "auto", found {value!r}')
        return value
    steps = check_positive_int(label, value)
    return validation.check_size(label, steps, validation.MAX_STEPS, "steps")


SETTINGS: dict[str, Callable[[str, object], Any]] = {
    "horizon": check_horizon,
    "runs": lambda label, value: validation.check_size(
        label, check_positive_int(label, value, minimum=2), validation.MAX_ELEMENTS, "runs"),
    "seed": lambda label, value: validation.check_int(label, value, minimum=0),
}
"""How the run settings are checked wherever they are given: a ``[scenario.<name>]`` card, the
``[matrix]`` table, or the ``horizon=``, ``runs=``, ``seed=`` arguments (the ranges of
:data:`CARD_KEYS`)."""


def _check_settings(label: str, table: Mapping[str, Any]) -> None:
    """Every run setting (:data:`SETTINGS`) that ``table`` gives, checked."""
    for key, check in SETTINGS.items():
        if key in table:
            check(f"{label} {key}", table[key])


@dataclass(frozen=True)
class Plant:
    """A linear plant: continuous dynamics ``Ac``, sampling ``dt``, noises and output catalogue.

    One ``[plant.<name>]`` card of ``cards.toml``. Times are in seconds; the state and the
    outputs are in the units of the plant's own example (e.g. ``state_names``).

    Attributes
    ----------
    name : str
        Card name (the ``<name>`` of ``[plant.<name>]``), e.g. ``"target"``.
    title : str
        One line for tables and figures.
    source : str
        Where the numbers come from (paper, section, equation; what is ours).
    Ac : (n, n) array [1/s]
        Continuous-time dynamics ``x'(t) = Ac x(t)`` (no input); the truth is sampled as
        ``x_{k+1} = A x_k + w_k`` with ``A = expm(Ac dt)`` (:attr:`A`).
    dt : float [s]
        Sampling period, positive.
    q_std : float
        Standard deviation of every component of the process noise ``w_k`` (state units,
        per sampling step), positive; nominal covariance :attr:`Q` ``= q_std^2 I``, samples
        clipped at :data:`NOISE_CLIP` standard deviations.
    outputs : (n_out, n) array
        Catalogue of sensor rows: a node measuring row ``o`` sees ``outputs[o] x_k`` plus noise
        (:attr:`Network.measures` picks the rows of each node's ``C_i``).
    r_std : (n_out,) array
        Standard deviation of the measurement noise of each catalogue row (output units),
        positive; clipped like ``w``.
    x0_std : float
        Standard deviation of every component of the initial state, ``x_0 ~ N(0, x0_std^2 I)``
        (state units); the prior of every estimator.
    state_names : tuple of n str
        Names of the state components (for axis labels).
    """

    name: str
    title: str
    source: str
    Ac: NDArray[np.float64]
    dt: float
    q_std: float
    outputs: NDArray[np.float64]
    r_std: NDArray[np.float64]
    x0_std: float
    state_names: tuple[str, ...]

    @cached_property
    def A(self) -> NDArray[np.float64]:
        """Sampled dynamics ``expm(Ac dt)``."""
        return sla.expm(self.Ac * self.dt)

    @property
    def n(self) -> int:
        """State dimension."""
        return self.Ac.shape[0]

    @property
    def Q(self) -> NDArray[np.float64]:
        """Nominal covariance of ``w_k``: ``q_std^2 I``."""
        return self.q_std**2 * np.eye(self.n)


DENSE_NODES = 2000
"""Largest network whose dense adjacency :attr:`Network.adj` is handed out (use the edge list above)."""


@dataclass(frozen=True)
class Network:
    """Sensor nodes, who hears whom, and which outputs each node measures.

    One ``[network.<name>]`` card of ``cards.toml`` (the graph built from ``graph``,
    ``degree``, ``radius``, ``seed`` as an edge list and checked connected). The graph is held as
    an edge list, so that a network of constant degree costs O(N) memory: every per-link
    quantity of the arena (:attr:`Trial.hits`, :meth:`Trial.received`, the weights of
    :func:`secest.arena.estimators.metropolis_weights`) is an array over the ``E`` edges in
    this order, and :meth:`sum_in` sums it over each node's in-edges.

    Attributes
    ----------
    name : str
        Card name, e.g. ``"target20"``.
    title : str
        One line for tables and figures.
    plant : str
        Name of the :class:`Plant` card the nodes observe.
    edges : (E, 2) int array
        The links as ``(receiver i, sender j)`` pairs: node ``i`` receives node ``j``'s messages.
        Sorted by receiver then sender, unique, no self loop (symmetric for the ring, complete
        and random geometric graphs of the cards).
    measures : (N, ny) int array
        ``measures[i]``: the rows of :attr:`Plant.outputs` node ``i`` measures (0-based, the
        same number ``ny`` per node), so ``C_i = outputs[measures[i]]`` (:attr:`Scenario.C`).
        Its length is the number of nodes ``N``.
    """

    name: str
    title: str
    plant: str
    edges: NDArray[np.intp]
    measures: NDArray[np.intp]

    def __post_init__(self) -> None:
        from secest.core import graphs

        edges = np.asarray(self.edges)
        if edges.ndim != 2 or edges.shape[1] != 2:
            raise ValidationError(f"network {self.name}: edges must be an (E, 2) array of "
                                  f"(receiver, sender) pairs, found shape {edges.shape}")
        object.__setattr__(self, "edges", graphs.check_connected_edges(edges, self.N, strongly=False))

    @property
    def N(self) -> int:
        """Number of nodes."""
        return int(np.shape(self.measures)[0])

    @property
    def E(self) -> int:
        """Number of (directed) edges."""
        return int(self.edges.shape[0])

    @property
    def receivers(self) -> NDArray[np.intp]:
        """Receiver ``i`` of every edge, shape (E,), non-decreasing."""
        return self.edges[:, 0]

    @property
    def senders(self) -> NDArray[np.intp]:
        """Sender ``j`` of every edge, shape (E,)."""
        return self.edges[:, 1]

    @cached_property
    def degree(self) -> NDArray[np.intp]:
        """In-degree of every node (how many nodes it receives from), shape (N,)."""
        return np.bincount(self.receivers, minlength=self.N)

    @cached_property
    def first_edge(self) -> NDArray[np.intp]:
        """Index of node ``i``'s first in-edge, shape (N + 1,): its in-edges are
        ``first_edge[i] .. first_edge[i + 1] - 1`` (the CSR row pointer)."""
        return np.concatenate([[0], np.cumsum(self.degree)]).astype(np.intp)

    @cached_property
    def adjacency(self) -> csr_array:
        """Sparse adjacency (N, N), ``1.0`` where node ``i`` receives node ``j``."""
        return csr_array((np.ones(self.E), np.ascontiguousarray(self.senders), self.first_edge),
                         shape=(self.N, self.N))  # contiguous indices: csgraph needs them

    @cached_property
    def undirected(self) -> bool:
        """Whether every link is two-way (``j`` hears ``i`` whenever ``i`` hears ``j``)."""
        back = self.edges[np.lexsort((self.receivers, self.senders))][:, ::-1]
        return bool(np.array_equal(back, self.edges))

    @property
    def adj(self) -> NDArray[np.float64]:
        """Dense adjacency (N, N) of 0.0 / 1.0 (``adj[i, j] = 1``: ``i`` receives ``j``).

        For small networks only (N <= :data:`DENSE_NODES`); use :attr:`edges` or
        :attr:`adjacency` otherwise.
        """
        if self.N > DENSE_NODES:
            raise ValidationError(f"network {self.name}: adj is dense, refused for N = {self.N} > "
                                  f"{DENSE_NODES}; use network.edges or network.adjacency")
        return self.adjacency.toarray()

    def sum_in(self, values: NDArray[np.float64]) -> NDArray[np.float64]:
        """Sum per-edge values over each node's in-edges: ``out[r, i] = sum_{e -> i} values[r, e]``.

        Parameters
        ----------
        values : (runs, E, ...) array
            One value (scalar, vector or matrix) per run and edge, in the order of :attr:`edges`.

        Returns
        -------
        (runs, N, ...) array
            Zero for a node without in-edges.
        """
        v = np.asarray(values)
        if v.ndim < 2 or v.shape[1] != self.E:
            raise ValidationError(f"Incompatible dimensions of values: expected (runs, {self.E}, ...) "
                                  f"(one per edge), found {v.shape}")
        out = np.zeros((v.shape[0], self.N, *v.shape[2:]), dtype=np.result_type(v, float))
        has = self.degree > 0
        if has.any():
            out[:, has] = np.add.reduceat(v, self.first_edge[:-1][has], axis=1)
        return out


@dataclass(frozen=True)
class Attack:
    """One attack card (see the comments in ``cards.toml`` for each kind's parameters).

    Attributes
    ----------
    name : str
        Card name, e.g. ``"bias"``.
    title : str
        One line for tables and figures.
    kind : {"none", "bias", "replacement", "message", "dos"}
        :data:`ATTACK_KINDS`: no attack; a constant added to the outputs of ``nodes`` from
        ``start`` on; Bernoulli replacement of the outputs of ``nodes``; falsified inter-node
        messages; denial of service on every link (a shared Gilbert-Elliott chain).
    nodes : tuple of int, default ()
        Attacked sensor nodes (0-based) of a ``"bias"`` or ``"replacement"`` attack; unused
        by the other kinds.
    start : float, default 0.0
        ``"bias"``: onset as a fraction of the horizon in [0, 1]; the bias acts from step
        ``ceil(start K)`` on.
    prob : float, default 0.0
        Probability in [0, 1]: ``"replacement"``, that an attacked node's measurement is
        replaced at a step (independently per run, step and node); ``"message"``, that one
        message on one link at one step is falsified.
    magnitude : float, default 0.0
        Dimensionless size. ``"bias"``: the bias is ``magnitude r_std`` on each output;
        ``"replacement"``: the replacement is uniform in ``+-magnitude r_std`` (``r_std`` of
        the attacked output); ``"message"``: the state estimate a node sends is shifted by
        ``magnitude`` oracle steady-state error standard deviations per component, random
        signs (:meth:`Trial.received` maps it into each method's message).
    p, q : float, defaults 0.0 and 1.0
        ``"dos"``: failure (up -> down) and recovery (down -> up) probabilities per step of the
        Gilbert-Elliott chain shared by every link (:func:`secest.core.channels.gilbert_elliott`);
        the defaults keep every link up. A ``"bias"`` card may set them too: its links then fail
        on that chain while the bias acts (ding2020's Sec. V: deception and lossy channels
        together; :attr:`lossy`).
    windows : tuple of tuple of int, default ()
        ``"bias"`` instead of ``start``: per entry of ``nodes``, the steps ``(first, last)``
        (inclusive) or ``(first,)`` (up to the horizon) during which that node's outputs carry the
        bias; a window beyond the horizon is cut at it.
    """

    name: str
    title: str
    kind: str
    nodes: tuple[int, ...] = ()
    start: float = 0.0
    prob: float = 0.0
    magnitude: float = 0.0
    p: float = 0.0
    q: float = 1.0
    windows: tuple[tuple[int, ...], ...] = ()

    @property
    def lossy(self) -> bool:
        """Whether the links follow a Gilbert-Elliott chain (a ``"dos"`` card, or a bias with ``p``)."""
        return self.kind == "dos" or self.p > 0


@dataclass(frozen=True)
class Scenario:
    """A plant on a network under an attack, over ``horizon`` steps, ``runs`` Monte Carlo runs.

    Built by :func:`scenario` (or :func:`matrix`) from the cards; :func:`simulate` draws its runs.

    Attributes
    ----------
    name : str
        ``"<network>/<attack>"`` for a scenario of the cross, the table name for a
        ``[scenario.<name>]`` card.
    plant : Plant
        The plant of ``network`` (its :attr:`Network.plant` card).
    network : Network
        The sensor nodes, their graph and their measured outputs.
    attack : Attack
        The attack on the sensors, the messages or the links.
    horizon : int
        Number of steps ``K``: the runs cover ``k = 0 .. K`` (``K + 1`` samples, time ``K dt``).
    runs : int
        Number of Monte Carlo runs, at least 2 (intervals need two).
    seed : int
        Root of :class:`numpy.random.SeedSequence` from which :func:`simulate` spawns its
        streams: the same seed gives the same runs.
    """

    name: str
    plant: Plant
    network: Network
    attack: Attack
    horizon: int
    runs: int
    seed: int

    @cached_property
    def C(self) -> NDArray[np.float64]:
        """Measurement matrices ``C_i``, shape (N, ny, n)."""
        return self.plant.outputs[self.network.measures]

    @cached_property
    def R(self) -> NDArray[np.float64]:
        """Measurement-noise covariances ``R_i`` (diagonal), shape (N, ny, ny)."""
        var = self.plant.r_std[self.network.measures] ** 2
        return np.einsum("iy,yz->iyz", var, np.eye(var.shape[1]))

    @cached_property
    def _steady(self) -> tuple[NDArray[np.float64], float]:
        """:func:`steady_state` of the scenario's plant on its network, solved once."""
        return steady_state(self.plant, self.network)

    @cached_property
    def steady_covariance(self) -> NDArray[np.float64]:
        """Error covariance of the oracle's steady-state Kalman filter after its update, (n, n).

        The centralised filter on every node's clean rows: ``P^- = DARE(A, C, Q, R)``,
        ``P = P^- - P^- C^T (C P^- C^T + R)^{-1} C P^-``. Its diagonal is the unit of the
        falsified-message attack (:func:`simulate`).
        """
        return self._steady[0]

    @cached_property
    def time_constant(self) -> float:
        """``tau`` in steps (:func:`steady_state`): the slower of the oracle's error decay and the
        plant's slowest decaying open-loop mode."""
        return self._steady[1]

    @property
    def attacked_nodes(self) -> tuple[int, ...]:
        """Nodes whose sensors the attack touches (empty for message and channel attacks)."""
        return self.attack.nodes if self.attack.kind in ("bias", "replacement") else ()


@dataclass
class Trial:
    """The Monte Carlo runs of one scenario, drawn once and shared by every estimator.

    Attributes
    ----------
    scenario : Scenario
        The scenario the runs were drawn from.
    x : (runs, K + 1, n)
        True states ``x_0 .. x_K``.
    y : (runs, K + 1, N, ny)
        Measurements as the sensors deliver them (sensor attacks included).
    y_clean : (runs, K + 1, N, ny)
        The same without the attack (what the oracle sees).
    attacked : (runs, K + 1, N) bool
        Where a sensor attack is active (the ground truth of detection rates).
    link : (runs, K + 1) int8
        Shared channel state of every inter-node link (1 = up); all ones unless the attack is
        :attr:`Attack.lossy`.
    hits : (runs, K + 1, E) bool
        ``hits[r, k, e]``: the message that the receiver of edge ``e`` (:attr:`Network.edges`)
        gets from its sender at step ``k`` is falsified.
    message_delta : (runs, K + 1, N, n) array, optional
        The falsification of a ``"message"`` attack as a perturbation of the state estimate that
        node ``j`` sends at step ``k``, in the state's own units: ``magnitude`` times the oracle's
        steady-state error standard deviation of each component, with a random sign per
        component (:func:`simulate`); None for every other kind. The same perturbation for every
        method: :meth:`received` maps it into each method's message by the method's encoding.
    """

    scenario: Scenario
    x: NDArray[np.float64]
    y: NDArray[np.float64]
    y_clean: NDArray[np.float64]
    attacked: NDArray[np.bool_]
    link: NDArray[np.int8]
    hits: NDArray[np.bool_]
    message_delta: NDArray[np.float64] | None = field(default=None)

    def received(
        self,
        k: int,
        messages: NDArray[np.float64],
        encode: Callable[[NDArray[np.float64]], NDArray[np.float64]] | None = None,
    ) -> NDArray[np.float64]:
        """What the receiver of every edge receives from its sender at step ``k``.

        Parameters
        ----------
        k : int
            Step index.
        messages : (runs, N, d) array
            What each node sends (its estimate, innovation, information vector...).
        encode : callable, optional
            The method's encoding of a falsified state estimate: ``encode(delta)`` maps the
            perturbations ``delta`` (runs, E, n) of the estimates the sender of each edge sends
            (zero on an edge that is not hit) into perturbations (runs, E, d) of its message (e.g.
            ``C_j delta`` for a sent measurement, ``Y_j delta`` for an information vector, with
            ``j = network.senders``). Default: the message is the state estimate itself (``d = n``).

        Returns
        -------
        (runs, E, d) array
            ``out[r, e] = messages[r, senders[e]]`` plus the falsification where ``hits[r, k, e]``
            (before the channel: the caller applies :attr:`link`, since what a lost packet means is
            method-specific). :meth:`Network.sum_in` sums it over each node's in-edges.

        Raises
        ------
        ValidationError
            If ``k`` is not a step of the trial, ``encode`` is not callable, ``messages`` is not
            one row per node, a message is not a state estimate and no ``encode`` is given, or
            ``encode`` returns another shape. Non-finite messages are passed on (a diverging
            method's; the growth rule marks its cell ``diverged``).
        """
        net = self.scenario.network
        K = self.x.shape[1] - 1
        if isinstance(k, bool) or not isinstance(k, int | np.integer) or not 0 <= k <= K:
            raise ValidationError(f"k must be a step index, an integer in [0, {K}], found {k!r}")
        if encode is not None:
            check_callable("encode", encode)
        m = np.asarray(messages, dtype=float)
        if m.ndim != 3 or m.shape[:2] != self.x.shape[:1] + (net.N,):
            raise ValidationError(f"Incompatible dimensions of messages: expected "
                                  f"({self.x.shape[0]}, {net.N}, d) (runs, nodes, d), found {m.shape}")
        out = m[:, net.senders]
        if self.message_delta is None:
            return out
        delta = self.hits[:, k, :, None] * self.message_delta[:, k, net.senders]
        if encode is None:
            if m.shape[-1] != delta.shape[-1]:
                raise ValidationError(f"encode: messages of {m.shape[-1]} entries are not state "
                                      f"estimates (n = {delta.shape[-1]}); give their encoding")
            return out + delta
        shift = np.asarray(encode(delta), dtype=float)
        if shift.shape != out.shape:
            raise ValidationError(f"encode: expected perturbations of shape {out.shape}, "
                                  f"found {shift.shape}")
        return out + shift


def _check_pair(plant: object, network: object) -> None:
    """``plant`` a :class:`Plant` and ``network`` a :class:`Network` that observes it."""
    if not isinstance(plant, Plant):
        raise ValidationError(f"plant must be a Plant card, found {type(plant).__name__}")
    if not isinstance(network, Network):
        raise ValidationError(f"network must be a Network card, found {type(network).__name__}")
    if network.plant != plant.name:
        raise ValidationError(f"network {network.name} observes plant {network.plant!r}, "
                              f"not plant {plant.name!r}")


def check_scenario(label: str, value: object) -> Scenario:
    """``value`` if it is a :class:`Scenario` (built by :func:`scenario`).

    Parameters
    ----------
    label : str
        The argument's name, used in the message.
    value : object
        The value to check.

    Returns
    -------
    Scenario
        ``value``.

    Raises
    ------
    ValidationError
        If ``value`` is not a Scenario.
    """
    return check_instance(label, value, Scenario, "secest.arena.scenarios.scenario")


def steady_state(plant: Plant, network: Network) -> tuple[NDArray[np.float64], float]:
    """The oracle's steady state on ``network``: its error covariance and the time constant ``tau``.

    ``tau = max(-1 / ln rho((I - K C) A), max over open-loop modes |lambda| < 1 of -1 / ln |lambda|)``
    in steps, with ``K`` the steady-state gain of the centralised Kalman filter on every node's
    rows. The first term is how fast the best estimator forgets its prior; the second how slowly
    an estimator that does not see a decaying mode forgets it (a node that does not observe the
    whole state). The arena's windows are multiples of ``tau`` (``secest/arena/protocol.toml``).

    Parameters
    ----------
    plant : Plant
    network : Network

    Returns
    -------
    (P, tau)
        ``P`` (n, n), the error covariance after the update; ``tau`` in steps (finite, > 0).

    Notes
    -----
    The Riccati equation depends on the nodes' rows only through their information
    ``U = sum_i C_i^T R_i^{-1} C_i`` (n x n), so it is solved with the equivalent measurement
    ``C' = Lambda^{1/2} V^T``, ``R' = I`` (``U = V Lambda V^T``, the positive eigenvalues): O(N)
    to form, never an (N ny) x (N ny) matrix. On the cards' networks ``P`` agrees with the
    stacked rows' to 3.2e-12 relative (inertia5; 1.5e-14 target20, 1.5e-15 tank12; measured).
    """
    _check_pair(plant, network)
    C, R = _equivalent_measurement(plant, network)
    A, Q = plant.A, plant.Q
    try:
        Pm = sla.solve_discrete_are(A.T, C.T, Q, R)
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise ValidationError(f"network {network.name}: the oracle's Riccati equation has no "
                              f"stabilising solution ({exc})") from None
    gain = Pm @ C.T @ np.linalg.inv(C @ Pm @ C.T + R)
    P = Pm - gain @ C @ Pm
    rho = float(np.max(np.abs(np.linalg.eigvals((np.eye(plant.n) - gain @ C) @ A))))
    modes = np.abs(np.linalg.eigvals(A))
    decaying = modes[(modes < 1.0 - 1e-9) & (modes > 0.0)]
    taus = [-1.0 / np.log(rho)] if 0.0 < rho < 1.0 else [1.0]
    taus += list(-1.0 / np.log(decaying))
    return 0.5 * (P + P.T), float(max(taus))


def _equivalent_measurement(
    plant: Plant, network: Network
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(C', I)`` with ``C'^T C' = sum_i C_i^T R_i^{-1} C_i``: at most n rows for all N nodes."""
    C = plant.outputs[network.measures]  # (N, ny, n)
    U = np.einsum("iyn,iy,iym->nm", C, 1.0 / plant.r_std[network.measures] ** 2, C)
    lam, V = np.linalg.eigh(0.5 * (U + U.T))
    keep = lam > 1e-12 * lam.max()
    rows = np.sqrt(lam[keep])[:, None] * V[:, keep].T
    return rows, np.eye(rows.shape[0])


# ---------------------------------------------------------------------------------- cards


CARD_KINDS = ("plant", "network", "attack", "scenario")
"""The tables of a cards file that hold named cards (``[<kind>.<name>]``)."""

Extra = str | Path | Mapping[str, Any] | None
"""More cards: a TOML file (path) or its parsed tables, laid out like ``cards.toml``."""


def _cards(extra: Extra = None) -> dict[str, Any]:
    text = resources.files("secest.arena").joinpath("cards.toml").read_text()
    raw = tomllib.loads(text)
    if extra is None:
        return raw
    if isinstance(extra, str | Path):
        path = Path(extra)
        if not path.is_file():
            raise ValidationError(f"extra must be a cards file or a mapping; {str(path)!r} is no file")
        with path.open("rb") as fh:
            try:
                more = tomllib.load(fh)
            except tomllib.TOMLDecodeError as exc:
                raise ValidationError(f"extra: {str(path)!r} is not a TOML file ({exc})") from None
    elif isinstance(extra, Mapping):
        more = dict(extra)
    else:
        raise ValidationError(f"extra must be a TOML path or a mapping, found {type(extra).__name__}")
    unknown = sorted(set(more) - {*CARD_KINDS, "matrix"})
    if unknown:
        raise ValidationError(f"extra cards: unknown tables {unknown}; known: {[*CARD_KINDS, 'matrix']}")
    for kind in CARD_KINDS:
        for name, card in _check_table(f"extra cards: [{kind}]", more.get(kind, {})).items():
            _check_table(f"extra cards: {kind} {name}", card)
            if name in raw.get(kind, {}):
                raise ValidationError(f"extra cards: {kind} {name!r} already exists in cards.toml")
            raw.setdefault(kind, {})[name] = card
    extends = _check_table("extra cards: [matrix]", more.get("matrix", {}))
    per_call = sorted({"horizon", "runs", "seed"} & set(extends))
    if per_call:
        raise ValidationError(f"extra cards: [matrix] {per_call[0]} is not read from an extra file; "
                              f"pass {per_call[0]}= to matrix() or scenario() (--{per_call[0]} on "
                              "the command line)")
    _check_keys("extra cards:", "[matrix]", extends, set(),
                set(CARD_KEYS["matrix"]) - {"horizon", "runs", "seed"})
    for key in ("networks", "attacks"):  # extra [matrix] lists extend the cross
        names = extends.get(key)
        if names is None:
            continue
        if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
            raise ValidationError(f"extra cards: [matrix] {key} must be a non-empty list of card "
                                  f"names, found {names!r}")
        added = [n for n in names if n not in raw["matrix"][key]]
        raw["matrix"][key] = [*raw["matrix"][key], *added]
    return raw


def _plant(name: str, card: dict[str, Any]) -> Plant:
    keys = set(CARD_KEYS["plant"])
    _check_keys("plant", name, card, keys, keys)
    for key in ("title", "source"):
        _check_text(f"plant {name}: {key}", card[key])
    Ac = as_matrix(f"plant {name}: Ac", card["Ac"], square=True)
    outputs = as_matrix(f"plant {name}: outputs", card["outputs"], (None, Ac.shape[0]))
    r_std = as_matrix(f"plant {name}: r_std", card["r_std"], (outputs.shape[0],))
    for key in ("dt", "q_std", "x0_std"):
        validation.check_real(f"plant {name}: {key}", card[key], lower=0.0, lower_open=True)
    names = card["state_names"]
    if (not isinstance(names, list) or len(names) != Ac.shape[0]
            or not all(isinstance(s, str) for s in names)):
        raise ValidationError(f"plant {name}: state_names must list {Ac.shape[0]} names (one per "
                              f"state component), found {names!r}")
    if np.any(r_std <= 0):
        raise ValidationError(f"plant {name}: every r_std must be positive")
    return Plant(
        name,
        card["title"],
        card["source"],
        Ac,
        float(card["dt"]),
        float(card["q_std"]),
        outputs,
        r_std,
        float(card["x0_std"]),
        tuple(card["state_names"]),
    )


def _graph(name: str, card: dict[str, Any]) -> NDArray[np.intp]:
    """The card's graph as an edge list (never a dense N x N matrix), checked connected."""
    from secest.core import graphs

    N = check_positive_int(f"network {name}: N", card["N"], minimum=2)
    validation.check_size(f"network {name}: N", N, validation.MAX_ELEMENTS, "nodes of a network")
    kind = card["graph"]
    if kind == "complete":
        validation.check_size(f"network {name}: N (N - 1)", N * (N - 1), validation.MAX_ELEMENTS,
                              "edges of a complete network")
        edges = graphs.complete_edges(N)
    elif kind == "ring":
        degree = validation.check_int(f"network {name}: degree", card.get("degree", 2), minimum=2)
        if degree % 2 or degree >= N:
            raise ValidationError(f"network {name}: degree must be even and below N = {N}, "
                                  f"found {degree}")
        edges = graphs.ring_edges(N, degree)
    elif kind == "rgg":
        radius = validation.check_real(f"network {name}: radius", card["radius"], lower=0.0,
                                       lower_open=True)
        seed = validation.check_int(f"network {name}: seed", card["seed"], minimum=0)
        edges = graphs.random_geometric_edges(N, radius, seed)
    else:
        raise ValidationError(f"network {name}: graph must be ring, complete or rgg, found {kind!r}")
    return graphs.check_connected_edges(edges, N)


def _network(name: str, card: dict[str, Any], plants: dict[str, Plant]) -> Network:
    common = {"title", "plant", "N", "graph", "measures"}
    if card.get("graph") not in _NETWORK_KEYS:  # a misspelt key (graph itself?) before the graph
        _check_keys("network", name, card, common, set(CARD_KEYS["network"]))
    required, optional = _NETWORK_KEYS.get(card.get("graph"), (set(), set()))
    _check_keys("network", name, card, common | required, common | optional | required)
    _check_text(f"network {name}: title", card["title"])
    if not isinstance(card["plant"], str) or card["plant"] not in plants:
        raise ValidationError(f"network {name}: plant {card['plant']!r} has no card")
    edges = _graph(name, card)
    N = int(card["N"])
    rows = card["measures"]
    if not isinstance(rows, list) or not all(
            isinstance(r, list) and all(isinstance(i, int) and not isinstance(i, bool) for i in r)
            for r in rows):
        raise ValidationError(f"network {name}: measures must be a list (one per node) of lists of "
                              f"output indices (integers), found {rows!r}")
    measures = np.asarray(rows, dtype=np.intp) if len({len(r) for r in rows}) == 1 else np.empty(0)
    n_out = plants[card["plant"]].outputs.shape[0]
    if measures.ndim != 2 or measures.shape[0] != N or measures.shape[1] == 0:
        raise ValidationError(
            f"network {name}: measures must list the same number (>= 1) of rows for each of "
            f"the {N} nodes"
        )
    if measures.min() < 0 or measures.max() >= n_out:
        raise ValidationError(f"network {name}: measures must index the plant's {n_out} outputs")
    return Network(name, card["title"], card["plant"], edges, measures)


_ATTACK_RANGES = {"start": (0.0, 1.0, False, True), "prob": (0.0, 1.0, True, False),
                  "p": (0.0, 1.0, True, False), "q": (0.0, 1.0, False, False)}
"""Per attack key: (lower, upper, lower open, upper open) of its interval (:data:`CARD_KEYS`)."""


def _attack(name: str, card: dict[str, Any]) -> Attack:
    kind = card.get("kind")
    if kind not in ATTACK_KINDS:  # a misspelt key (kind itself?) before the kind
        _check_keys("attack", name, card, {"kind"}, set(CARD_KEYS["attack"]))
        raise ValidationError(f"attack {name}: kind must be one of {ATTACK_KINDS}, found {kind!r}")
    required, optional = _ATTACK_KEYS[kind]
    base = {"title", "kind"}
    _check_keys("attack", name, card, base | required, base | required | optional)
    _check_text(f"attack {name}: title", card["title"])
    for key, (low, high, low_open, high_open) in _ATTACK_RANGES.items():
        if key in card:
            validation.check_real(f"attack {name}: {key}", card[key], lower=low, upper=high,
                                  lower_open=low_open, upper_open=high_open)
    nodes = card.get("nodes", [0])
    if (not isinstance(nodes, list) or not nodes
            or not all(isinstance(i, int) and not isinstance(i, bool) and i >= 0 for i in nodes)):
        raise ValidationError(f"attack {name}: nodes must be a non-empty list of node indices >= 0, "
                              f"found {nodes!r}")
    if len(set(nodes)) != len(nodes):
        raise ValidationError(f"attack {name}: nodes must be distinct, found {nodes!r}")
    size = card.get("magnitude", 1.0)
    if isinstance(size, bool) or not isinstance(size, int | float) or not (np.isfinite(size)
                                                                           and size > 0):
        raise ValidationError(f"attack {name}: magnitude must be a positive number, found {size!r}")
    if kind == "bias" and ("start" in card) == ("windows" in card):
        raise ValidationError(f"attack {name}: a bias needs either start or windows, not both")
    if kind == "bias" and ("p" in card) != ("q" in card):
        raise ValidationError(f"attack {name}: a bias's channel needs both p and q, or neither")
    return Attack(
        name,
        card["title"],
        kind,
        tuple(int(i) for i in card.get("nodes", ())),
        float(card.get("start", 0.0)),
        float(card.get("prob", 0.0)),
        float(card.get("magnitude", 0.0)),
        float(card.get("p", 0.0)),
        float(card.get("q", 1.0)),
        _windows(name, card.get("windows"), len(nodes)),
    )


def _windows(name: str, windows: Any, n_nodes: int) -> tuple[tuple[int, ...], ...]:
    """The ``windows`` of a bias card, checked: one ``[first, last]`` or ``[first]`` per node."""
    if windows is None:
        return ()
    steps_ok = isinstance(windows, list) and len(windows) == n_nodes and all(
        isinstance(w, list) and len(w) in (1, 2)
        and all(isinstance(k, int) and not isinstance(k, bool) and k >= 0 for k in w)
        and w[0] <= w[-1] for w in windows)
    if not steps_ok:
        raise ValidationError(f"attack {name}: windows must list, for each of the {n_nodes} nodes, "
                              f"[first, last] or [first] steps (0 <= first <= last), found {windows!r}")
    return tuple(tuple(w) for w in windows)


def cards(extra: Extra = None) -> dict[str, dict[str, Any]]:
    """Every card of ``cards.toml`` (and of ``extra``), checked.

    Parameters
    ----------
    extra : path or mapping, optional
        More cards laid out like ``cards.toml``: ``[plant.<name>]``, ``[network.<name>]``,
        ``[attack.<name>]`` and ``[scenario.<name>]`` tables are added (a name that already
        exists is refused); the ``networks`` and ``attacks`` of an extra ``[matrix]`` are
        appended to the cross. The package's file is never modified.

    Returns
    -------
    dict
        ``{"plant": {name: Plant}, "network": {name: Network}, "attack": {name: Attack},
        "scenario": {name: table}, "matrix": {...}}``.
    """
    raw = _cards(extra)
    plants = {n: _plant(n, c) for n, c in raw["plant"].items()}
    networks = {n: _network(n, c, plants) for n, c in raw["network"].items()}
    attacks = {n: _attack(n, c) for n, c in raw["attack"].items()}
    named = {n: _named(n, c, networks, attacks) for n, c in raw.get("scenario", {}).items()}
    return {
        "plant": plants,
        "network": networks,
        "attack": attacks,
        "scenario": named,
        "matrix": _matrix_table(raw["matrix"], networks, attacks),
    }


def _matrix_table(table: dict[str, Any], networks: dict[str, Network],
                  attacks: dict[str, Attack]) -> dict[str, Any]:
    """The ``[matrix]`` table checked: its keys (:data:`CARD_KEYS`), card names and settings."""
    keys = set(CARD_KEYS["matrix"])
    _check_keys("cards", "[matrix]", table, keys, keys)
    for key, known in (("networks", networks), ("attacks", attacks)):
        names = table[key]
        if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
            raise ValidationError(f"[matrix] {key} must be a non-empty list of card names, "
                                  f"found {names!r}")
        unknown = [n for n in names if n not in known]
        if unknown:
            raise ValidationError(f"[matrix] {key}: {unknown} have no card; known: {sorted(known)}")
    _check_settings("[matrix]", table)
    return table


def _named(
    name: str, card: dict[str, Any], networks: dict[str, Network], attacks: dict[str, Attack]
) -> dict[str, Any]:
    _check_keys("scenario", name, card, {"network", "attack"}, set(CARD_KEYS["scenario"]))
    for kind, known in (("network", networks), ("attack", attacks)):
        if not isinstance(card[kind], str) or card[kind] not in known:
            raise ValidationError(f"scenario {name}: {kind} {card[kind]!r} has no card")
    if "title" in card:
        _check_text(f"scenario {name}: title", card["title"])
    _check_settings(f"scenario {name}:", card)
    return dict(card)


def scenario(
    network: str,
    attack: str,
    *,
    horizon: int | None = None,
    runs: int | None = None,
    seed: int | None = None,
    name: str | None = None,
    extra: Extra = None,
) -> Scenario:
    """The scenario of ``network`` (with its plant) under ``attack``; defaults from ``[matrix]``.

    Parameters
    ----------
    network : str
        Name of a ``[network.<name>]`` card; the scenario's plant is the network's.
    attack : str
        Name of an ``[attack.<name>]`` card; its ``nodes`` must exist in ``network``.
    horizon : int or "auto", optional
        Number of steps ``K`` (positive), or ``"auto"``: :func:`auto_horizon`, the shortest
        horizon with a steady window (``protocol.toml``); default the ``[matrix]`` horizon.
    runs : int, optional
        Number of Monte Carlo runs (at least 2); default the ``[matrix]`` runs.
    seed : int, optional
        Root seed of :func:`simulate`; default the ``[matrix]`` seed.
    name : str, optional
        Scenario name; default ``"<network>/<attack>"``.
    extra : path or mapping, optional
        More cards (see :func:`cards`).

    Returns
    -------
    Scenario

    Raises
    ------
    ValidationError
        Unknown network or attack, attacked nodes outside the network, or a non-positive
        horizon or fewer than 2 runs.
    """
    c = cards(extra)
    for label, value, known in (("network", network, c["network"]), ("attack", attack, c["attack"])):
        if not isinstance(value, str) or value not in known:
            near = difflib.get_close_matches(str(value), sorted(known), n=1)
            hint = f" (did you mean {near[0]!r}?)" if near else ""
            raise ValidationError(f"{label} must be one of {sorted(known)}, found {value!r}{hint}")
    if name is not None:
        _check_text("name", name)
    net = c["network"][network]
    m = c["matrix"]
    att = c["attack"][attack]
    if any(i >= net.N for i in att.nodes):
        raise ValidationError(f"attack {attack}: nodes {att.nodes} do not all exist in {network}")
    R = SETTINGS["runs"]("runs", runs if runs is not None else m["runs"])
    seed = SETTINGS["seed"]("seed", seed if seed is not None else m["seed"])
    plant = c["plant"][net.plant]
    K = check_horizon("horizon", horizon if horizon is not None else m["horizon"])
    if K == "auto":
        K = auto_horizon(plant, net)
    widest = max(plant.n, net.measures.shape[1])  # a trial holds every node's output per step
    validation.check_size("runs x (horizon + 1) x nodes", R * (K + 1) * net.N * widest,
                          validation.MAX_ELEMENTS, "array entries of a trial")
    validation.check_size("runs x (horizon + 1) x edges", R * (K + 1) * net.E,
                          validation.MAX_ELEMENTS, "falsification flags of a trial (one per edge)")
    validation.check_size("runs x edges", R * net.E * widest, validation.MAX_ELEMENTS,
                          "entries of one step's messages (one per edge)")
    return Scenario(
        name=name or f"{network}/{attack}",
        plant=plant,
        network=net,
        attack=att,
        horizon=K,
        runs=R,
        seed=seed,
    )


def _card_names(label: str, names: object) -> list[str]:
    """``names`` if it is a non-empty list of distinct card names (not one bare string)."""
    if (isinstance(names, str) or not isinstance(names, list | tuple) or not names
            or not all(isinstance(n, str) for n in names) or len(set(names)) != len(names)):
        raise ValidationError(f"{label} must be a non-empty list of distinct card names, "
                              f"found {names!r}")
    return list(names)


MIN_HORIZON_TAU = 20
"""A horizon of at least this many time constants gives a steady window (``protocol.toml``)."""


def auto_horizon(plant: Plant, network: Network) -> int:
    """The shortest horizon of ``protocol.toml``: ``MIN_HORIZON_TAU tau``, up to a multiple of 10 steps.

    ``tau`` is :func:`steady_state`'s time constant of the plant on the network.

    Parameters
    ----------
    plant : Plant
    network : Network

    Returns
    -------
    int
        The horizon in steps.
    """
    return horizon_of(steady_state(plant, network)[1])


def horizon_of(tau: float) -> int:
    """``MIN_HORIZON_TAU tau`` steps, rounded up to a multiple of 10 (:func:`auto_horizon`).

    Parameters
    ----------
    tau : float
        A time constant in steps (:func:`steady_state`).

    Returns
    -------
    int
        The horizon in steps.
    """
    tau = validation.check_real("tau", tau, lower=0.0, lower_open=True)
    return int(10 * np.ceil(MIN_HORIZON_TAU * tau / 10))


def matrix(
    *,
    networks: list[str] | None = None,
    attacks: list[str] | None = None,
    extra: Extra = None,
    **overrides: Any,
) -> list[Scenario]:
    """Every scenario of the arena: each network (with its plant) under each attack of the
    ``[matrix]``, then each ``[scenario.<name>]`` table.

    Parameters
    ----------
    networks, attacks : list of str, optional
        The networks and attacks to cross (default: the ``[matrix]`` lists); when given,
        they also select the named scenarios (default: every one). Every name must have
        a card.
    extra : path or mapping, optional
        More cards (see :func:`cards`).
    **overrides
        ``horizon``, ``runs``, ``seed`` for every scenario (a named scenario's own values
        are used where it gives them and no override does).
    """
    c = cards(extra)
    m = c["matrix"]
    _check_keys("matrix()", "arguments", overrides, set(), set(SETTINGS))
    nets = list(m["networks"]) if networks is None else _card_names("networks", networks)
    atts = list(m["attacks"]) if attacks is None else _card_names("attacks", attacks)
    for kind, names in (("network", nets), ("attack", atts)):
        unknown = [n for n in names if n not in c[kind]]
        if unknown:
            raise ValidationError(f"{kind}s {unknown} have no card; known: {sorted(c[kind])}")
    out = [scenario(n, a, extra=extra, **overrides) for n in nets for a in atts]
    for name, card in c["scenario"].items():
        if (networks is None or card["network"] in nets) and (attacks is None or card["attack"] in atts):
            own = {k: card[k] for k in ("horizon", "runs", "seed") if k in card}
            out.append(scenario(card["network"], card["attack"], name=name, extra=extra,
                                **(own | {k: v for k, v in overrides.items() if v is not None})))
    return out


# ---------------------------------------------------------------------------------- simulation


def _clipped_normal(rng: np.random.Generator, shape: tuple[int, ...]) -> NDArray[np.float64]:
    return np.clip(rng.standard_normal(shape), -NOISE_CLIP, NOISE_CLIP)


def simulate(sc: Scenario) -> Trial:
    """Draw the ``runs`` Monte Carlo runs of ``sc`` (deterministic in ``sc.seed``).

    Independent streams from ``SeedSequence(seed).spawn(4)`` for the plant and sensor
    noises, the sensor attack, the channel and the message falsification, so that changing
    the attack leaves the truth and the noises unchanged (common random numbers across
    the attack column of the matrix).

    The message stream draws one uniform per run, step and edge (in the order of
    :attr:`Network.edges`) for the falsified links, then the signs of the perturbations. Before
    the per-edge arrays (up to commit f6e10c9) it drew one per run, step and (receiver, sender)
    pair of the dense N x N grid: the message-attack trials of that code differ from these
    (same law, other draws); the noises, sensor attacks and channel are drawn as before.

    Parameters
    ----------
    sc : Scenario
        The scenario: ``x_0 ~ N(0, x0_std^2 I)``, ``x_{k+1} = A x_k + w_k`` and
        ``y_{i,k} = C_i x_k + v_{i,k} + a_{i,k}`` for ``k = 0 .. horizon`` (module docstring),
        ``sc.runs`` runs.

    Returns
    -------
    Trial
        The truth, the clean and the delivered measurements, the attack mask, the link state
        and the message falsifications of every run.
    """
    plant, net, att = check_scenario("sc", sc).plant, sc.network, sc.attack
    R, K, N = sc.runs, sc.horizon, net.N
    noise, attack_rng, channel_rng, message_rng = (
        np.random.default_rng(s) for s in np.random.SeedSequence(sc.seed).spawn(4)
    )
    x = np.empty((R, K + 1, plant.n))
    x[:, 0] = plant.x0_std * noise.standard_normal((R, plant.n))
    w = plant.q_std * _clipped_normal(noise, (R, K, plant.n))
    for k in range(K):
        x[:, k + 1] = x[:, k] @ plant.A.T + w[:, k]
    r_std = plant.r_std[net.measures]
    y_clean = np.einsum("iyn,rkn->rkiy", sc.C, x) + r_std * _clipped_normal(
        noise, (R, K + 1, N, r_std.shape[1])
    )
    y, attacked = _sensor_attack(sc, y_clean, r_std, attack_rng)
    link = np.ones((R, K + 1), dtype=np.int8)
    if att.lossy:
        from secest.core import channels

        link = channels.gilbert_elliott(att.p, att.q, K + 1, channel_rng, size=R)
    hits = np.zeros((R, K + 1, net.E), dtype=bool)
    delta = None
    if att.kind == "message":
        hits = message_rng.random((R, K + 1, net.E)) < att.prob
        signs = np.where(message_rng.random((R, K + 1, N, plant.n)) < 0.5, -1.0, 1.0)
        delta = att.magnitude * np.sqrt(np.diag(sc.steady_covariance)) * signs
    return Trial(sc, x, y, y_clean, attacked, link, hits, delta)


def _sensor_attack(
    sc: Scenario, y_clean: NDArray[np.float64], r_std: NDArray[np.float64], rng: np.random.Generator
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    att = sc.attack
    R, K1, N, ny = y_clean.shape
    y = y_clean.copy()
    attacked = np.zeros((R, K1, N), dtype=bool)
    nodes = list(att.nodes)
    if att.kind == "bias":
        first = int(np.ceil(att.start * (K1 - 1)))
        spans = att.windows or tuple((first,) for _ in nodes)
        for node, span in zip(nodes, spans, strict=True):
            steps = slice(span[0], span[-1] + 1 if len(span) == 2 else K1)
            attacked[:, steps, node] = True
            y[:, steps, node] += att.magnitude * r_std[node]
    elif att.kind == "replacement":
        hit = rng.random((R, K1, len(nodes))) < att.prob
        attacked[:, :, nodes] = hit
        fake = att.magnitude * r_std[nodes] * rng.uniform(-1.0, 1.0, (R, K1, len(nodes), ny))
        y[:, :, nodes] = np.where(hit[..., None], fake, y[:, :, nodes])
    return y, attacked
