"""A method of one's own: every node runs a Kalman filter on its own sensor with a fixed gain.

No messages, no defence: each node ``i`` uses the steady-state gain ``K_i`` of its own pair
``(A, C_i)`` (the discrete algebraic Riccati equation), computed once per scenario::

    x_i(k) = A x_i(k-1) + K_i (y_i(k) - C_i A x_i(k-1)),     x_i(-1) = 0
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from secest.arena.estimators import Estimate, Method
from secest.arena.scenarios import Scenario, Trial


class FixedGainKF(Method):
    """Local Kalman filter with the steady-state gain of each node's own sensor."""

    name = "fixed-gain-kf"
    title = "local KF, steady-state gain of each node's own sensor"
    kind = "user"
    reading = "ignores its neighbours: nothing it receives can be falsified or lost"

    def requirements(self, sc: Scenario) -> list[tuple[str, bool]]:
        # without it the Riccati equation of a node has no solution: the method cannot run (N/A)
        n = sc.plant.n
        observable = all(
            np.linalg.matrix_rank(np.vstack([C @ np.linalg.matrix_power(sc.plant.A, p)
                                             for p in range(n)])) == n
            for C in sc.C)
        return [("every node observes the state from its own sensor", observable)]

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        A, Q = sc.plant.A, sc.plant.Q
        gains = []
        for C, R in zip(sc.C, sc.R, strict=True):
            P = sla.solve_discrete_are(A.T, C.T, Q, R)  # prior covariance in steady state
            gains.append(P @ C.T @ np.linalg.inv(C @ P @ C.T + R))
        K = np.stack(gains)  # (N, n, ny)
        runs, steps, N, _ = trial.y.shape
        x = np.zeros((runs, N, sc.plant.n))
        xhat = np.empty((runs, steps, N, sc.plant.n))
        for k in range(steps):
            pred = x @ A.T if k else x
            innov = trial.y[:, k] - np.einsum("iyn,rin->riy", sc.C, pred)
            x = pred + np.einsum("iny,riy->rin", K, innov)
            xhat[:, k] = x
        return Estimate(xhat)
