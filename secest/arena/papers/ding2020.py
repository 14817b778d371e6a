"""ding2020 in the arena: the distributed secure filter of :mod:`secest.methods.ding2020`.

Ding, Wang, Han, Zhang (2020): every node predicts by consensus over a shared
Gilbert-Elliott channel (7), updates with a chi-square-inspected innovation (25)/(34) and
carries an upper and a lower bound of its error covariance (35)/(18). On a shared scenario:

* the channel state ``delta_k`` is the scenario's link state (all ones without DoS);
* what node ``i`` receives from ``j`` is the scenario's message (falsified under a
  message attack), replacing ``delta_k x_j^+`` of (3);
* ``BB^T = Q``, ``DD^T = R_i`` (the same at every node, a condition), ``Pi_0 = Gamma_0`` the
  exact prior covariance, ``kappa`` and the threshold as in the paper's example (not retuned).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from secest.arena.estimators import Estimate, Method, register
from secest.arena.scenarios import Scenario, Trial
from secest.core import graphs
from secest.core.validation import check_real
from secest.methods import ding2020

__all__ = ["Ding2020"]


@register
class Ding2020(Method):
    """Distributed secure filter over a Gilbert-Elliott channel with a chi-square detector.

    The run is :func:`secest.methods.ding2020.secure_filter`, the recursion the notebook verifies:
    at every step :func:`secest.methods.ding2020.secure_filter_step`, i.e. consensus prediction (7),
    the inspection (25) of the innovation against the lower bound ``Gamma``, the update (34) and
    the upper / lower covariance bounds (35) / (18). Its alarms are the inspected-out
    measurements (``theta = 0``), its ``bound`` the upper bound ``Pi_i^+``.

    Parameters
    ----------
    kappa : float, default 0.004
        Coupling strength ``kappa`` of the consensus term of (7), dimensionless; the paper
        asks ``kappa in (0, 1)`` (after (7)) and uses 0.004 in Sec. V.
    threshold : float, default 25.0
        Inspection threshold ``chi^2_{n^y, sigma}`` of (6) / (25): node ``i`` discards its
        measurement when the squared Mahalanobis distance of its innovation,
        ``eta^T Gamma_eta^{-1} eta``, reaches it; 25 is the paper's value (Sec. V),
        not recomputed from ``n^y`` on other plants.
    """

    name = "ding2020"
    title = "ding2020: secure consensus filter, chi-square inspection"
    kind = "paper"
    home = "target20"
    home_note = (
        "its Sec. V plant (A, B, D, C_i as printed) and 20 nodes of its two sensor types on its "
        "notebook's stand-in for Fig. 1 (not in our copy: random geometric, r = 0.35, seed 2020); "
        "scenario ding2020-home adds its attack (+ 15 on y_4 at k = 90..95, on y_12 at k = 50..55) "
        "over its Gilbert-Elliott channel (p = 0.1, q = 0.92), its 150 steps the first of 410 "
        "(20 tau). Unlike its notebook: noises clipped at 3 sd, every node starts at x_hat = 0 "
        "with Pi_0 = Gamma_0 = I (notebook: x_hat_i0 ~ N(0, I), Pi_0 = Gamma_0 = 2 I), one channel "
        "chain per run (notebook: Fig. 2's chain in every run)"
    )
    reading = "kappa = 0.004 and threshold 25 of the paper's example; Pi_0 = Gamma_0 = prior covariance"

    def __init__(self, kappa: float = 0.004, threshold: float = 25.0) -> None:
        self.kappa = check_real("kappa", kappa, lower=0.0, upper=1.0, lower_open=True, upper_open=True)
        self.threshold = check_real("threshold", threshold, lower=0.0, lower_open=True)

    def conditions(self, sc: Scenario) -> list[tuple[str, bool]]:
        same_R = bool(np.allclose(sc.R, sc.R[0]))
        connected = True
        try:
            graphs.check_connected_edges(sc.network.edges, sc.network.N, strongly=True)
        except ValueError:
            connected = False
        return [
            ("every node has the same measurement-noise covariance DD^T (2)", same_R),
            ("the communication graph is strongly connected (Sec. II)", connected),
            ("its attack model: deception on the measurements (Sec. II) and Gilbert-Elliott losses "
             "(3)-(4); the estimates nodes exchange are not falsified", sc.attack.kind != "message"),
        ]

    def run(self, trial: Trial) -> Estimate:
        sc = trial.scenario
        runs, _, N, _ = trial.y.shape
        n = sc.plant.n
        net = sc.network
        adj = net.adjacency  # sparse, with the per-edge messages of trial.received: O(E) a step
        weights = sp.csr_array((1.0 / net.degree[net.receivers], np.ascontiguousarray(net.senders),
                                net.first_edge), shape=(N, N))  # h_ij = 1/|N_i|
        Pi0 = np.broadcast_to(sc.plant.x0_std**2 * np.eye(n), (runs, N, n, n)).copy()
        res = ding2020.secure_filter(
            np.zeros((runs, N, n)),
            Pi0,
            Pi0.copy(),
            trial.link,
            trial.y,
            A=sc.plant.A,
            BBt=sc.plant.Q,
            C=sc.C,
            DDt=sc.R[0],
            adj=adj,
            weights=weights,
            kappa=self.kappa,
            threshold=self.threshold,
            received=trial.received,  # it sends its state estimate
            keep=("Pi_post",),
        )
        bound = np.concatenate([Pi0[:, None], res.history["Pi_post"]], axis=1)
        return Estimate(res.x, alarms=res.theta == 0, bound=bound)
