"""The arena's distributed baselines: what a secure distributed estimator is measured against.

Every baseline is a bank of node filters that share one local Kalman filter in information form
and differ only in what a node exchanges once per step (or ``rounds`` times) and how it fuses
what it received. With ``A``, ``Q`` the plant, ``C_i``, ``R_i`` node ``i``'s sensor and
``U_i = C_i^T R_i^{-1} C_i``, ``u_{i,k} = C_i^T R_i^{-1} y_{i,k}`` its measurement information::

    (L1) correction:  Y_i = Y_i^- + U_i,  P_i = Y_i^{-1},
                      xhat_i = x_i^- + P_i (u_{i,k} - U_i x_i^-)   (the Kalman update, information form)
    (L2) prediction:  x_i^- = A xhat_i,  P_i^- = A P_i A^T + Q,  Y_i^- = (P_i^-)^{-1}
    (M)  weights:     w_ij = 1 / (1 + max(d_i, d_j)) on a link that delivered at step k,
                      w_ii = 1 - sum_{j != i} w_ij   (a lost link's weight goes to the node itself:
                      the weights renormalised over what arrived; Metropolis)

Every node starts from the prior ``x^- = 0``, ``P^- = x0_std^2 I`` and corrects at ``k = 0``.

* ``local-kf``: (L1)-(L2) alone, no communication;
* ``consensus-kf-1`` / ``consensus-kf``: consensus on information (CI) / on measurements (CM)
  (Battistelli et al. 2015);
* ``diffusion-kf``: diffusion on the estimates (Cattivelli and Sayed 2010);
* ``kcf``: the Kalman consensus filter (Olfati-Saber 2009);
* ``wmsr-kf``: trimmed (W-MSR) consensus on the estimates (LeBlanc et al. 2013).

The falsified-message and DoS attacks reach every exchange here: each step's messages pass
through :meth:`secest.arena.scenarios.Trial.received`, and a lost message is never replaced by
anything: a node fuses only what arrived (itself at least), so with every link down every
baseline is ``local-kf`` (a test checks it to the last bit). ``encode_<name>`` maps a
perturbation ``delta`` of the state estimate a sender sends to the perturbation of its message.

References
----------
G. Battistelli, L. Chisci, G. Mugnai, A. Farina, A. Graziano, "Consensus-based linear and
nonlinear filtering", IEEE TAC 60(5), 1410-1415, 2015. F. S. Cattivelli, A. H. Sayed, "Diffusion
strategies for distributed Kalman filtering and smoothing", IEEE TAC 55(9), 2069-2084, 2010.
R. Olfati-Saber, "Kalman-consensus filter: optimality, stability, and performance", Proc. 48th
IEEE CDC, 7036-7042, 2009. H. J. LeBlanc, H. Zhang, X. Koutsoukos, S. Sundaram, "Resilient
asymptotic consensus in robust networks", IEEE JSAC 31(4), 766-781, 2013. L. Xiao, S. Boyd,
S. Lall, "A scheme for robust distributed sensor fusion based on average consensus", IPSN 2005
(Metropolis weights).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.arena.estimators import (
    Estimate,
    Method,
    metropolis_weights,
    no_attack_conditions,
    register,
)
from secest.arena.scenarios import Network, Scenario, Trial
from secest.core.tolerances import Tolerance
from secest.core.validation import ValidationError, check_choice, check_int, check_real

__all__ = [
    "ConsensusInformationKF",
    "ConsensusKF",
    "DiffusionKF",
    "KalmanConsensusFilter",
    "LocalKF",
    "WmsrKF",
    "encode_consensus_kf",
    "encode_consensus_kf_1",
    "wmsr",
]


# ---------------------------------------------------------------------------------- node filters


def _sym(M: NDArray[np.float64]) -> NDArray[np.float64]:
    return 0.5 * (M + np.swapaxes(M, -1, -2))


def _information(trial: Trial, k: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``U_i`` (runs, N, n, n) and ``u_{i,k}`` (runs, N, n): node i's measurement information.

    O(N) per step; ``U_i`` is a broadcast view (one copy per node, not per run)."""
    sc = trial.scenario
    Rinv = np.linalg.inv(sc.R)
    U = np.einsum("iyn,iyz,izm->inm", sc.C, Rinv, sc.C)
    u = np.einsum("iyn,iyz,riz->rin", sc.C, Rinv, trial.y[:, k])
    return np.broadcast_to(U, (u.shape[0], *U.shape)), u


class _Prior(NamedTuple):
    """Every node's prior in every run: estimate ``x^-`` (runs, N, n), covariance ``P^-`` and
    information matrix ``Y^- = (P^-)^{-1}`` (runs, N, n, n)."""

    x: NDArray[np.float64]
    P: NDArray[np.float64]
    Y: NDArray[np.float64]


def _start(trial: Trial) -> _Prior:
    """The prior of every node in every run: ``x^- = 0``, ``P^- = x0_std^2 I``."""
    sc = trial.scenario
    runs, _, N, _ = trial.y.shape
    n = sc.plant.n
    P = np.broadcast_to(sc.plant.x0_std**2 * np.eye(n), (runs, N, n, n)).copy()
    return _Prior(np.zeros((runs, N, n)), P, _sym(np.linalg.inv(P)))


def _correct(
    prior: _Prior, U: NDArray[np.float64], u: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(L1): ``Y = Y^- + U``, ``P = Y^{-1}``, ``xhat = x^- + P (u - U x^-)``; returns (xhat, P, Y)."""
    Y = prior.Y + U
    P = _sym(np.linalg.inv(Y))
    innovation = u - np.einsum("rinm,rim->rin", U, prior.x)
    return prior.x + np.einsum("rinm,rim->rin", P, innovation), P, Y


def _predict(
    x: NDArray[np.float64], P: NDArray[np.float64], A: NDArray[np.float64], Q: NDArray[np.float64]
) -> _Prior:
    """(L2): the prior ``x^- = A x``, ``P^- = A P A^T + Q``, ``Y^- = (P^-)^{-1}``."""
    P_prior = _sym(A @ P @ A.T + Q)
    return _Prior(x @ A.T, P_prior, _sym(np.linalg.inv(P_prior)))


class _Weights(NamedTuple):
    """(M) weights of one step: ``edge`` (runs, E) on the delivered links (0 on a lost one) and
    ``own`` (runs, N), ``w_ii = 1 - sum_j w_ij`` over the delivered links."""

    edge: NDArray[np.float64]
    own: NDArray[np.float64]


def _delivered(trial: Trial, k: int) -> NDArray[np.float64]:
    """``a[r, e] = 1`` where edge ``e``'s message arrives at step k (its link is up): (runs, E)."""
    E = trial.scenario.network.E
    return np.broadcast_to(trial.link[:, k].astype(float)[:, None], (trial.link.shape[0], E))


def _weights(net: Network, W: NDArray[np.float64], delivered: NDArray[np.float64]) -> _Weights:
    """(M): the per-edge weights ``W`` (E,) of the delivered links, a lost link's weight given to
    the node."""
    edge = W[None] * delivered
    return _Weights(edge, 1.0 - net.sum_in(edge))


def _fuse(net: Network, Wk: _Weights, own: NDArray[np.float64],
          received: NDArray[np.float64]) -> NDArray[np.float64]:
    """``w_ii m_i + sum_j w_ij m_ij`` of node i's own value (runs, N, ...) and those it received
    (runs, E, ...): vectors or matrices, (runs, N, ...)."""
    dims = (None,) * (own.ndim - 2)
    return Wk.own[(..., *dims)] * own + net.sum_in(Wk.edge[(..., *dims)] * received)


def _ci_round(
    net: Network, Wk: _Weights, x: NDArray[np.float64], Y: NDArray[np.float64],
    received: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """One CI round: ``Y_i <- sum_j w_ij Y_j``, ``q_i <- sum_j w_ij q_j`` with ``q_j = Y_j x_j``.

    ``received[r, e]`` is the information vector ``q_j`` the receiver ``i`` of edge ``e`` got from
    its sender ``j``. The new estimate ``Y_i^{-1} q_i`` is computed as
    ``x_i + Y_i^{-1} sum_{j != i} w_ij (q_j - Y_j x_i)`` (the same, the weights summing to one),
    so that a node that received nothing keeps ``x_i`` to the last bit. Returns the new
    estimates and information matrices.
    """
    Ys = Y[:, net.senders]
    gap = received - np.einsum("renm,rem->ren", Ys, x[:, net.receivers])
    pull = net.sum_in(Wk.edge[..., None] * gap)
    Y = _fuse(net, Wk, Y, Ys)
    return x + np.linalg.solve(Y, pull[..., None])[..., 0], Y


def _undirected(sc: Scenario) -> list[tuple[str, bool]]:
    """A Metropolis-weighted filter's theory: an undirected graph, and no attack of any kind."""
    return ([("the graph is undirected (Metropolis weights)", sc.network.undirected)]
            + no_attack_conditions(sc, links=True))


# ---------------------------------------------------------------------------------- encodings


def _check_delta(delta: ArrayLike) -> NDArray[np.float64]:
    d = np.asarray(delta, dtype=float)
    if d.ndim < 1 or not np.all(np.isfinite(d)):
        raise ValidationError(f"delta must be a finite array of shape (..., n), found shape {d.shape}")
    return d


def _encode_information(delta: ArrayLike, Y: ArrayLike, name: str) -> NDArray[np.float64]:
    d = _check_delta(delta)
    M = np.asarray(Y, dtype=float)
    if M.ndim < 2 or M.shape[-2:] != (d.shape[-1], d.shape[-1]):
        raise ValidationError(f"Incompatible dimensions of {name}: expected (..., {d.shape[-1]}, "
                              f"{d.shape[-1]}) for delta of shape {d.shape}, found {M.shape}")
    return np.einsum("...nm,...m->...n", M, d)


def encode_consensus_kf_1(delta: ArrayLike, Y: ArrayLike) -> NDArray[np.float64]:
    """Message perturbation of ``consensus-kf-1`` for a perturbation of the sent estimate.

    The message of node ``j`` in a round is its information pair ``(Y_j, q_j = Y_j x_j)``;
    moving the estimate to ``x_j + delta`` with ``Y_j`` unchanged moves the information vector
    by ``Y_j delta`` (and the matrix by nothing).

    Parameters
    ----------
    delta : (..., n) array
        Perturbation of the estimate ``x_j = Y_j^{-1} q_j`` the sender's pair carries (state units).
    Y : (..., n, n) array
        The sender's information matrix ``Y_j`` in that round (broadcast against ``delta``).

    Returns
    -------
    (..., n) array
        The perturbation of the information vector ``q_j`` it sends.
    """
    return _encode_information(delta, Y, "Y")


def encode_consensus_kf(delta: ArrayLike, U: ArrayLike) -> NDArray[np.float64]:
    """Message perturbation of ``consensus-kf`` (CM) for a perturbation of the state it implies.

    A CM message is measurement information, not an estimate: ``u_j = U_j x`` for noise-free data,
    so a sender whose information is read as implying the state ``x + delta`` sends
    ``u_j + U_j^{(l)} delta`` in round ``l`` (``U_j^{(l)}`` its matrix in that round; the matrix
    itself is sent unchanged). This reading of "the estimate a CM node sends" is ours.

    Parameters
    ----------
    delta : (..., n) array
        Perturbation of the state the message implies (state units).
    U : (..., n, n) array
        The sender's information matrix in that round.

    Returns
    -------
    (..., n) array
        The perturbation of the information vector it sends.
    """
    return _encode_information(delta, U, "U")


# ---------------------------------------------------------------------------------- baselines


@register
class LocalKF(Method):
    """Every node's own Kalman filter on its own measurements: no communication.

    (L1)-(L2) of the module docstring at every node. Where a node alone does not observe the
    state (tank12: one level per node) its error in the unobserved (stable) modes stays at
    their open-loop level: the cost of not communicating, which every distributed method
    should beat.
    """

    exchanges = False
    name = "local-kf"
    title = "local KF at every node, no communication"
    kind = "baseline"
    reading = "no inter-node links: message and DoS attacks do not reach it"

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        return no_attack_conditions(sc, links=False)

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        A, Q = sc.plant.A, sc.plant.Q
        out = np.empty((*trial.y.shape[:3], sc.plant.n))
        prior = _start(trial)
        for k in range(trial.y.shape[1]):
            x, P, _ = _correct(prior, *_information(trial, k))  # (L1)
            out[:, k] = x
            prior = _predict(x, P, A, Q)  # (L2): the prior of step k + 1
        return Estimate(out)


_MAX_ROUNDS = 1000
"""Most consensus rounds per step a consensus baseline accepts (each round is one exchange)."""


def _check_rounds(rounds: object) -> int:
    return check_int("rounds", rounds, minimum=1, maximum=_MAX_ROUNDS)


@register
class ConsensusInformationKF(Method):
    """Consensus on information (CI, Battistelli et al. 2015), ``rounds`` exchanges per step.

    At every step node ``i`` corrects with its own measurement (L1), sends its information pair
    ``(Y_i, q_i = Y_i xhat_i)`` and fuses what arrived in ``rounds`` rounds of (M)-weighted
    averaging, ``Y_i <- sum_j w_ij Y_j``, ``q_i <- sum_j w_ij q_j``; its estimate is
    ``Y_i^{-1} q_i``, from which (L2) predicts (the CI algorithm of Battistelli et al.:
    correction, consensus, prediction). The fusion is the Kullback-Leibler average of the
    neighbours' Gaussian posteriors (Battistelli and Chisci 2014, who prove the filter stable
    for any number of rounds): it never counts a piece of information more than once, at the
    price of diluting every measurement (by ``w_ii`` at its own node).

    Parameters
    ----------
    rounds : int, default 1
        Consensus rounds ``L`` per step, >= 1 (the first value of the protocol's search set).
    """

    name = "consensus-kf-1"
    kind = "baseline"
    reading = ("messages are the corrected information vectors q_j (falsified) and matrices Y_j; "
               "a lost message is not fused (its weight stays with the receiver)")

    def __init__(self, rounds: int = 1) -> None:
        self.rounds = _check_rounds(rounds)
        per_step = "one exchange" if self.rounds == 1 else f"{self.rounds} exchanges"
        self.title = f"distributed KF, consensus on information, {per_step} per step"

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        return _undirected(sc)

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        A, Q = sc.plant.A, sc.plant.Q
        net = sc.network
        W, _ = metropolis_weights(net)
        out = np.empty((*trial.y.shape[:3], sc.plant.n))
        prior = _start(trial)
        for k in range(trial.y.shape[1]):
            x, P, Y = _correct(prior, *_information(trial, k))  # (L1)
            Wk = _weights(net, W, _delivered(trial, k))  # (M)
            for _ in range(self.rounds):  # CI: average the information pairs that arrived
                sent = np.einsum("rinm,rim->rin", Y, x)  # q_i = Y_i xhat_i
                x, Y = _ci_round(net, Wk, x, Y, trial.received(
                    k, sent, lambda d, Y=Y: encode_consensus_kf_1(d, Y[:, net.senders])))
            P = _sym(np.linalg.inv(Y))
            out[:, k] = x
            prior = _predict(x, P, A, Q)  # (L2): the prior of step k + 1
        return Estimate(out)


@register
class ConsensusKF(Method):
    """Consensus on measurements (CM, Battistelli et al. 2015) with ``rounds`` rounds per step.

    At every step each node averages the measurement information ``(u_j, U_j)`` of the nodes
    in ``rounds`` rounds of (M)-weighted consensus (what it receives may be falsified or lost),
    then corrects (L1) with ``N`` times the averages: the centralised update when the rounds
    converge (one round on a complete graph averages exactly). A step whose links are all
    down delivers nothing: the node then holds its own information alone and uses it once
    (scale 1, not ``N``), i.e. it is its own local filter for that step. The arena's channel is
    one state per step shared by every link (:attr:`Trial.link`), so a step's rounds are all
    delivered or all lost.

    Parameters
    ----------
    rounds : int, default 5
        Consensus rounds ``L`` per step, >= 1 (the first value of the protocol's search set).
    """

    name = "consensus-kf"
    kind = "baseline"
    reading = ("messages are the measurement-information vectors u_j (falsified) and matrices U_j; "
               "with every link down a node uses its own information once")

    def __init__(self, rounds: int = 5) -> None:
        self.rounds = _check_rounds(rounds)
        self.title = f"distributed KF, {self.rounds} consensus rounds on measurement information"

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        return _undirected(sc)

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        net = sc.network
        A, Q = sc.plant.A, sc.plant.Q
        W, _ = metropolis_weights(net)
        out = np.empty((*trial.y.shape[:3], sc.plant.n))
        prior = _start(trial)
        for k in range(trial.y.shape[1]):
            Wk = _weights(net, W, _delivered(trial, k))  # (M)
            U, u = _information(trial, k)
            for _ in range(self.rounds):  # CM: average the measurement information that arrived
                sent = U[:, net.senders]  # the senders' matrices, per edge
                u = _fuse(net, Wk, u, trial.received(k, u, lambda d, M=sent: encode_consensus_kf(d, M)))
                U = _fuse(net, Wk, U, sent)
            f = np.where(trial.link[:, k] > 0, float(net.N), 1.0)[:, None, None]  # N x mean, or own once
            x, P, _ = _correct(prior, f[..., None] * U, f * u)  # (L1)
            out[:, k] = x
            prior = _predict(x, P, A, Q)  # (L2): the prior of step k + 1
        return Estimate(out)


@register
class DiffusionKF(Method):
    """Diffusion KF on estimates (Cattivelli and Sayed 2010), one exchange per step.

    Cattivelli and Sayed's diffusion KF has two steps: an incremental update with the
    neighbours' measurements, and a diffusion (convex combination) of the neighbours'
    intermediate estimates. With one exchange per step of estimates only, the incremental step
    is node ``i``'s own correction (L1), giving ``psi_i`` and ``P_i``; the diffusion step is
    ``xhat_i = sum_j c_ij psi_j`` over what arrived with the (M) weights; the prediction (L2)
    starts from ``xhat_i`` and the local ``P_i`` (the combination does not change ``P_i``, as in
    the paper).

    Parameters
    ----------
    combination : {"metropolis"}, default "metropolis"
        The combination weights ``c_ij``: Metropolis (M), the only one implemented.
    """

    name = "diffusion-kf"
    kind = "baseline"
    title = "diffusion KF on estimates (Cattivelli-Sayed), one exchange per step"
    reading = "messages are the local estimates psi_j; a lost message is not combined"

    def __init__(self, combination: str = "metropolis") -> None:
        self.combination = check_choice("combination", combination, ("metropolis",))

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        return _undirected(sc)

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        A, Q = sc.plant.A, sc.plant.Q
        net = sc.network
        W, _ = metropolis_weights(net)
        out = np.empty((*trial.y.shape[:3], sc.plant.n))
        prior = _start(trial)
        for k in range(trial.y.shape[1]):
            psi, P, _ = _correct(prior, *_information(trial, k))  # (L1)
            x = _fuse(net, _weights(net, W, _delivered(trial, k)), psi, trial.received(k, psi))
            out[:, k] = x
            prior = _predict(x, P, A, Q)  # (L2): the prior of step k + 1
        return Estimate(out)


@register
class KalmanConsensusFilter(Method):
    """Olfati-Saber's Kalman consensus filter (KCF, 2009), one exchange per step.

    Node ``i`` sends its prior estimate ``x_i^-`` and, with what arrived from its neighbours
    ``j``, adds a consensus term to its own correction (L1)::

        xhat_i = psi_i + C_i sum_j (x_j^- - x_i^-),    C_i = epsilon P_i^- / (1 + ||P_i^-||_F)

    (the KCF's consensus gain ``gamma P_i / (1 + ||P_i||)`` with ``gamma = epsilon``); the
    covariance is the local ``P_i`` of (L1), the consensus term left out of it as in the KCF's
    covariance update, and (L2) predicts. Since ``||C_i||_2 < epsilon``, ``epsilon d_max < 1``
    (``d_max`` the largest in-degree) keeps the consensus part a convex combination (the
    Perron-matrix step-size condition of discrete-time consensus). A larger gain is outside that
    theory, not impossible: the filter runs, its cell is marked (:meth:`conditions`) and scored,
    and the growth rule says whether it diverged (``protocol.toml``, Amendment 2).

    Parameters
    ----------
    epsilon : float, default 0.2
        Consensus gain, >= 0; ``epsilon = 0`` is ``local-kf``.
    """

    name = "kcf"
    kind = "baseline"
    title = "Kalman consensus filter (Olfati-Saber), one exchange per step"
    reading = "messages are the prior estimates x_j^-; a lost message leaves its term out"

    def __init__(self, epsilon: float = 0.2) -> None:
        self.epsilon = check_real("epsilon", epsilon, lower=0.0)

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        d_max = float(sc.network.degree.max())
        return [(f"epsilon * max degree < 1 (epsilon = {self.epsilon:g}, max degree {d_max:g}): "
                 "the consensus step is a convex combination", self.epsilon * d_max < 1),
                *no_attack_conditions(sc, links=True)]

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        net = sc.network
        A, Q = sc.plant.A, sc.plant.Q
        out = np.empty((*trial.y.shape[:3], sc.plant.n))
        prior = _start(trial)
        for k in range(trial.y.shape[1]):
            received = trial.received(k, prior.x)
            disagreement = net.sum_in(_delivered(trial, k)[..., None]
                                      * (received - prior.x[:, net.receivers]))
            norm = np.sqrt(np.einsum("rinm,rinm->ri", prior.P, prior.P))[..., None, None]
            gain = self.epsilon * prior.P / (1.0 + norm)
            psi, P, _ = _correct(prior, *_information(trial, k))  # (L1)
            x = psi + np.einsum("rinm,rim->rin", gain, disagreement)
            out[:, k] = x
            prior = _predict(x, P, A, Q)  # (L2): the prior of step k + 1
        return Estimate(out)


def wmsr(
    own: NDArray[np.float64], received: NDArray[np.float64], delivered: NDArray[np.float64],
    receivers: NDArray[np.intp], trimmed: int,
) -> NDArray[np.float64]:
    """One W-MSR step (LeBlanc et al. 2013) on every component of every node's value.

    For each component, node ``i`` takes the values it received from its neighbours (the
    delivered links); of those strictly larger than its own it removes the ``F = trimmed``
    largest (all of them if fewer than ``F``), of those strictly smaller the ``F`` smallest,
    and averages its own value with the rest, with equal weights (ties ranked by edge order,
    i.e. by sender index). Among at most ``F`` faulty neighbours, every kept value lies within
    the range of the normal ones; the resilience guarantee against ``F``-local malicious
    neighbours needs a ``(2F + 1)``-robust graph (LeBlanc et al. 2013), which the arena does not
    check. The values are ranked per node in a (N, max in-degree) table: O(E) memory and
    O(N d log d) work for in-degrees ``d``.

    Parameters
    ----------
    own : (runs, N, n) array
        Every node's own value.
    received : (runs, E, n) array
        ``received[r, e]``: the value the receiver of edge ``e`` got from its sender.
    delivered : (runs, E) array of 0 / 1
        Where edge ``e``'s value arrived.
    receivers : (E,) int array
        The receiver of every edge, non-decreasing (:attr:`Network.receivers`), in ``range(N)``.
    trimmed : int
        ``F``, >= 0.

    Returns
    -------
    (runs, N, n) array
        The W-MSR update of every node.
    """
    F = check_int("trimmed", trimmed, minimum=0)
    runs, N, n = np.shape(own)
    to = np.asarray(receivers)
    if to.ndim != 1 or not np.issubdtype(to.dtype, np.integer) or np.any(np.diff(to) < 0) or (
            to.size and (to.min() < 0 or to.max() >= N)):
        raise ValidationError(f"receivers must be a non-decreasing 1-D integer array in range({N}), "
                              f"found shape {to.shape} and dtype {to.dtype}")
    E = to.size
    for name, value, want in (("received", received, (runs, E, n)), ("delivered", delivered, (runs, E))):
        if np.shape(value) != want:
            raise ValidationError(f"Incompatible dimensions of {name}: expected {want}, "
                                  f"found {np.shape(value)}")
    degree = np.bincount(to, minlength=N)
    slot = np.arange(E) - np.concatenate([[0], np.cumsum(degree)])[to]
    table = np.zeros((runs, N, int(degree.max(initial=0)), n))
    table[:, to, slot] = received
    valid = np.zeros(table.shape, bool)
    valid[:, to, slot] = (np.asarray(delivered) > 0)[..., None]
    above = valid & (table > own[:, :, None])
    below = valid & (table < own[:, :, None])
    drop = np.zeros_like(above)
    for side, key in ((above, -table), (below, table)):  # rank 0 = most extreme
        order = np.argsort(np.where(side, key, np.inf), axis=2, kind="stable")
        drop |= side & (np.argsort(order, axis=2, kind="stable") < F)
    keep = valid & ~drop
    return (own + np.where(keep, table, 0.0).sum(axis=2)) / (1.0 + keep.sum(axis=2))


@register
class WmsrKF(Method):
    """Local KF correction, then W-MSR (trimmed) consensus on the estimates (LeBlanc et al. 2013).

    Node ``i`` corrects with its own measurement (L1), giving ``psi_i`` and ``P_i``, sends
    ``psi_i``, and replaces it by the W-MSR step of :func:`wmsr` over what arrived (per state
    component: the ``F`` largest values above its own and the ``F`` smallest below dropped, the
    rest averaged with its own, equal weights); the prediction (L2) starts from that estimate
    with the local ``P_i``. A Byzantine-resilient baseline: up to ``F`` falsified neighbours
    cannot pull an estimate outside the range of the others. With ``F >= `` a node's degree
    every neighbour's value differing from its own is dropped: ``local-kf``.

    Parameters
    ----------
    trimmed : int, default 1
        ``F``, the number of values dropped at each end, >= 0.
    """

    name = "wmsr-kf"
    kind = "baseline"
    tolerance = Tolerance(
        rtol=1e-3,
        atol=1e-3,
        reason="trimming compares estimates: a last-bit difference changes which neighbour is "
        "dropped where two values nearly tie (tank12: 2.1e-4 relative change of the no-attack "
        "score between two roundings of the same local filter)",
    )
    title = "local KF + W-MSR trimmed consensus on estimates, one exchange per step"
    reading = ("messages are the local estimates psi_j; the graph's (2F + 1)-robustness "
               "(the W-MSR guarantee) is not checked")

    def __init__(self, trimmed: int = 1) -> None:
        self.trimmed = check_int("trimmed", trimmed, minimum=0)

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        """Its guarantee's graph condition (a necessary part of it), and reliable links.

        W-MSR tolerates ``F``-local faulty neighbours (falsified messages, and a node whose own
        sensor is attacked) on a ``(2F + 1)``-robust graph; robustness is not checked (coNP-hard
        in general), its necessary condition, every in-degree at least ``2F + 1``, is.
        """
        d_min = int(sc.network.degree.min())
        need = 2 * self.trimmed + 1
        return [(f"every in-degree >= 2F + 1 = {need} (necessary for the (2F + 1)-robust graph "
                 f"of its guarantee; smallest in-degree {d_min})", d_min >= need),
                ("its model: every link delivers (no losses, no DoS)",
                 sc.attack.kind != "dos" and not sc.attack.lossy)]

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        A, Q = sc.plant.A, sc.plant.Q
        out = np.empty((*trial.y.shape[:3], sc.plant.n))
        prior = _start(trial)
        for k in range(trial.y.shape[1]):
            psi, P, _ = _correct(prior, *_information(trial, k))  # (L1)
            received = trial.received(k, psi)
            x = wmsr(psi, received, _delivered(trial, k), sc.network.receivers, self.trimmed)
            out[:, k] = x
            prior = _predict(x, P, A, Q)  # (L2): the prior of step k + 1
        return Estimate(out)
