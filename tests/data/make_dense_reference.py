"""Freeze the dense-message baselines' estimates (run once, at the commit before the per-edge port).

The file it writes, ``tests/data/arena_dense_reference.npz``, holds, for each (network, attack,
method) cell of a short trial, the estimate at the last step and the squared error summed over runs
and nodes at every step; for the message attack also the trial's falsified links (per edge, in the
receiver-then-sender order of the edge list) and perturbations, so that the per-edge code can be
fed the very same falsification (its random draws differ: ``scenarios.simulate``).
"""

from pathlib import Path

import numpy as np

import secest.arena  # noqa: F401  (registers the baselines)
from secest.arena import baselines, scenarios
from secest.arena.estimators import METHODS

NETWORKS = ("target20", "inertia5", "tank12")
ATTACKS = ("none", "replacement", "message", "dos")
NAMES = ("oracle", "kf", "chi2-kf", "local-kf", "consensus-kf-1", "consensus-kf", "diffusion-kf",
         "kcf", "wmsr-kf")
"""Registered defaults, except ``kcf`` (epsilon = 0.05 runs on every network) and
``consensus-kf-1`` (2 rounds)."""
TUNED = {"kcf": baselines.KalmanConsensusFilter(0.05), "consensus-kf-1": baselines.ConsensusInformationKF(2)}


def main() -> None:
    out = {}
    for net in NETWORKS:
        for att in ATTACKS:
            t = scenarios.simulate(scenarios.scenario(net, att, runs=2, horizon=30, seed=7))
            if att == "message":
                i, j = np.nonzero(t.scenario.network.adj)
                out[f"{net}/{att}/hits"] = t.hits[:, :, i, j]
                out[f"{net}/{att}/delta"] = t.message_delta
            for name in NAMES:
                xhat = TUNED.get(name, METHODS[name]).run(t).xhat
                out[f"{net}/{att}/{name}/last"] = xhat[:, -1]
                out[f"{net}/{att}/{name}/sse"] = ((xhat - t.x[:, :, None]) ** 2).sum(axis=(0, 2, 3))
    np.savez_compressed(Path(__file__).with_name("arena_dense_reference.npz"), **out)


if __name__ == "__main__":
    main()
