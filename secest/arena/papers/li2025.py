"""li2025 in the arena: the ``Method`` that races :mod:`secest.methods.li2025`.

Applies the paper's estimator of :mod:`secest.methods.li2025` to a shared scenario after checking
the conditions of its theory; the reading where the scenario differs from the paper's setting is the
class's ``reading``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from secest.arena.estimators import Estimate, Method, register
from secest.arena.scenarios import Scenario, Trial
from secest.core import systems
from secest.core.validation import ValidationError
from secest.methods.li2025 import (
    VARIANTS,
    bound_coefficients,
    gain_and_bound,
    predict,
    predicted_bound,
)

Array = NDArray[np.float64]


ARENA_WEIGHTS = (1e-3, 1.0, 1e-2, 0.1, 0.1)
"""``(lambda, alpha_1..alpha_4)`` on the arena: the notebook's Remark-4 grid optimum for target 1."""

# ---------------------------------------------------------------------------------- the arena


def _packets(sc: Scenario) -> tuple[list[list[int]], list[list[int]]]:
    """Per node: the clean and the attacked sensors of its closed neighbourhood (the card's)."""
    attacked = set(sc.attacked_nodes) if sc.attack.kind == "replacement" else set()
    net = sc.network
    senders = net.senders.tolist()
    nbhd = [sorted([i, *senders[net.first_edge[i]:net.first_edge[i + 1]]]) for i in range(net.N)]
    clean = [[j for j in nb if j not in attacked] for nb in nbhd]
    return clean, [[j for j in nb if j in attacked] for nb in nbhd]


def _packet_index(sc: Scenario, src: NDArray[np.intp]) -> NDArray[np.intp]:
    """Where node ``i``'s packet from ``src[i, s]`` sits in ``[received per edge, own]``: the edge
    ``(i, src)`` (index < E), or ``E + i`` for its own measurement; 0 for an empty slot (-1)."""
    net = sc.network
    keys = net.receivers.astype(np.int64) * net.N + net.senders  # increasing (edges sorted)
    rows = np.broadcast_to(np.arange(net.N)[:, None], src.shape)
    edge = np.searchsorted(keys, rows.astype(np.int64) * net.N + np.maximum(src, 0))
    return np.where(src == rows, net.E + rows, np.where(src >= 0, edge, 0))


def _clean_layout(sc: Scenario, clean: list[list[int]]) -> tuple[Array, Array, Array]:
    """Zero-padded slots of every node's clean packets: source node (-1 = empty), rows of
    ``C`` (zero on empty slots) and noise variances (1 on empty slots, never used)."""
    N, ny, n = sc.C.shape
    slots = max(len(c) for c in clean)
    src = np.full((N, slots), -1)
    G = np.zeros((N, slots * ny, n))
    var = np.ones((N, slots * ny))
    for i, c in enumerate(clean):
        src[i, : len(c)] = c
        G[i, : len(c) * ny] = sc.C[c].reshape(-1, n)
        var[i, : len(c) * ny] = np.diagonal(sc.R[c], axis1=1, axis2=2).reshape(-1)
    return src, G, var


class Li2025(Method):
    """Bound-minimising recursive estimator under Bernoulli replacement attacks (7)-(8), (17)-(18), (28).

    Design rules (fixed from the paper and its notebook before any arena run; see the module
    docstring): each node estimates the plant from its closed neighbourhood's raw measurements
    (``K_i`` empty, ``H_eps = I``, ``m = n_y``); a lost packet is not used; ``psi_check`` and
    ``xi*`` of the packets the replacement card attacks are read from the card, 1 and 0
    elsewhere; clean packets first, then each attacked one; weights :data:`ARENA_WEIGHTS`;
    corrected coefficients; the run's ``x_hat x_hat^T``; ``x_hat(0|0) = 0``, ``S(0|0)`` the prior.

    Parameters
    ----------
    weights : sequence of 5 positive floats, default :data:`ARENA_WEIGHTS`
        ``(lambda, alpha_1, alpha_2, alpha_3, alpha_4)``, the Lemma 1 weights of the bound:
        ``lambda`` of the cross terms with the upstream errors in (17) (with ``K_i`` empty it
        only inflates the propagated term, ``(1 + lambda) A S A^T``), ``alpha_1`` of (24) in
        the gain (28), ``alpha_2..alpha_4`` of the
        ``e/xi`` (25), ``e/x`` (26) and ``x/xi`` (27) cross terms in the coefficients of
        (18) (:func:`bound_coefficients`). Dimensionless; Remark 4 tunes them.
    variant : {"corrected", "paper"}, default "corrected"
        Bound coefficients of :func:`bound_coefficients`: re-derived from the paper's proof
        (ERRATA.md), or those printed in Theorem 2.
    """

    name = "li2025"
    title = "li2025: bound-minimising gain under Bernoulli replacement"
    kind = "paper"
    home = ""
    home_note = (
        "its Sec. IV example is a time-varying (T_k = 0.8 tanh k, r_k = 0.1 + 0.3 tanh k) singularly "
        "perturbed sequential system of three coupled targets under a round-robin-like multichannel "
        "schedule; the arena's cards have neither time-varying plants, two time scales nor a schedule"
    )
    reading = (
        "each node runs the paper's estimator (K_i empty, H_eps = I, m = n_y) on its own and its "
        "neighbours' raw measurements (the sensor-to-estimator packets); a lost packet is not used; "
        "psi_check = 1 - prob and xi* = (magnitude r_std)^2 for the sensors the replacement card "
        "attacks, 1 elsewhere; weights (1e-3, 1, 1e-2, 0.1, 0.1) = the notebook's Remark-4 optimum "
        "for the paper's target 1 (attack probability 0.3); corrected coefficients"
    )

    def __init__(self, weights: Sequence[float] = ARENA_WEIGHTS, variant: str = "corrected") -> None:
        if (isinstance(weights, str) or not isinstance(weights, Sequence) or len(weights) != 5
                or not all(isinstance(w, int | float) and not isinstance(w, bool)
                           and np.isfinite(w) and w > 0 for w in weights)):
            raise ValidationError(
                f"weights must be 5 positive numbers (lambda, alpha1..alpha4), found {weights!r}"
            )
        if variant not in VARIANTS:
            raise ValidationError(f"variant must be one of {VARIANTS}, found {variant!r}")
        self.weights = tuple(float(w) for w in weights)
        self.variant = variant

    def told(self, sc: Scenario) -> str:
        if sc.attack.kind == "replacement":
            return ("the replaced sensors, the probability and the magnitude (psi_check, xi*: the "
                    "paper assumes them known)")
        return ""

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        A = sc.plant.A
        clean, attacked = _packets(sc)
        observable = all(
            systems.is_observable(A, sc.C[sorted(c + a)].reshape(-1, sc.plant.n))
            for c, a in zip(clean, attacked, strict=True)
        )
        return [
            ("the plant is an SPDSS (1), read with no fast part (n_f = 0, H_eps = I)", True),
            ("one plant: every node's estimator is a subsystem without upstream coupling "
             "(K_i empty, (1))", True),
            ("RRL-MAP (2)-(5) read with m = n_y (no bandwidth limit; Theorems 1-2 hold for any Phi)",
             True),
            ("every attack on the measurement packets is the Bernoulli replacement (6) of a bounded "
             "value with known psi_check, xi* (or none)",
             sc.attack.kind in ("none", "replacement", "dos")),
            ("(A, C) is observable from every node's closed neighbourhood (ours: a bounded S_i(k|k); "
             "Theorem 3's own conditions cannot be met even on the paper's example, notebook C3a)",
             observable),
        ]

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        runs, K1, N, ny = trial.y.shape
        n = sc.plant.n
        lam, a1, a2, a3, a4 = self.weights
        A, Q = sc.plant.A, sc.plant.Q
        clean, attacked = _packets(sc)
        src, G_clean, var_clean = _clean_layout(sc, clean)
        slot_own = src == np.arange(N)[:, None]
        slot_packet = _packet_index(sc, src)  # (N, slots) into [received per edge, own]
        att = sc.attack
        psi_att = 1.0 - att.prob
        x = np.zeros((runs, N, n))
        S = np.broadcast_to(sc.plant.x0_std**2 * np.eye(n), (runs, N, n, n)).copy()
        xs, Ss = np.empty((runs, K1, N, n)), np.empty((runs, K1, N, n, n))
        xs[:, 0], Ss[:, 0] = x, S
        coef_clean = bound_coefficients(1.0, a2, a3, a4, self.variant)
        C_sender = sc.C[sc.network.senders]

        def encode(delta: Array) -> Array:  # a node relays C_j x: a shifted state moves it by C_j delta
            return np.einsum("eyn,ren->rey", C_sender, delta)

        coef_att = bound_coefficients(psi_att, a2, a3, a4, self.variant)
        hearing = {}  # each attacked packet a: the nodes that use it and where their copy sits
        for a in sorted({j for js in attacked for j in js}):
            nodes = [i for i in range(N) if a in attacked[i]]
            hearing[a] = (nodes, _packet_index(sc, np.full((N, 1), a))[nodes, 0])
        for k in range(1, K1):
            # (runs, E + N, ny): the packets of every edge, then every node's own measurement
            recv = np.concatenate([trial.received(k, trial.y[:, k], encode), trial.y[:, k]], axis=1)
            up = trial.link[:, k].astype(bool)
            x = predict(x, [], A, [])  # (7), K_i empty
            S = predicted_bound(S, [], A, [], lam, Q)  # (17)
            # clean packets: psi_check = 1, one update of the received rows (empty slots masked)
            got = (src >= 0) & (slot_own[None] | up[:, None, None])  # (runs, N, slots)
            rows = np.repeat(got, ny, axis=-1)
            G = G_clean[None] * rows[..., None]
            V = np.einsum("rim,mn->rimn", np.where(rows, var_clean[None], 1.0), np.eye(rows.shape[-1]))
            y_rows = np.where(rows, recv[:, slot_packet].reshape(runs, N, -1), 0.0)
            X_hat = x[..., :, None] * x[..., None, :]
            L, S, _ = gain_and_bound(S, X_hat, G, coef_clean, a1, 0.0, V)  # (28), (18)
            x = x + np.einsum("rinc,ric->rin", L, y_rows - np.einsum("ricn,rin->ric", G, x))  # (8)
            for a, (nodes, where) in hearing.items():  # each attacked packet
                xi_star = float(np.sum((att.magnitude * sc.plant.r_std[sc.network.measures[a]]) ** 2))
                xa, Sa = x[:, nodes], S[:, nodes]
                L, S_new, _ = gain_and_bound(Sa, xa[..., :, None] * xa[..., None, :], sc.C[a], coef_att,
                                             a1, xi_star, sc.R[a])  # (28), (18)
                x_new = xa + np.einsum("rinc,ric->rin", L, recv[:, where] - xa @ sc.C[a].T)  # (8)
                use = (np.array(nodes) == a)[None] | up[:, None]  # a lost packet is not used
                x[:, nodes] = np.where(use[..., None], x_new, xa)
                S[:, nodes] = np.where(use[..., None, None], S_new, Sa)
            xs[:, k], Ss[:, k] = x, S
        notes = {"weights": self.weights, "variant": self.variant}
        return Estimate(xs, bound=Ss, notes=notes)


register(Li2025)
