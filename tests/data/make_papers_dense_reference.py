"""Freeze the five paper methods' dense-message estimates (run once, before their per-edge port).

The file it writes, ``tests/data/arena_papers_dense_reference.npz``, holds, for each (network,
attack, method) cell of a short trial (2 runs, 30 steps, seed 7), the estimate at the last step,
the squared error summed over runs and nodes at every step and the number of alarms at every step.
The methods' code of this commit exchanges dense (N, N) messages; the trials are the per-edge
ones of :func:`secest.arena.scenarios.simulate`, handed to them through :class:`DenseTrial`,
which lays each step's per-edge messages out as the old (runs, N, N, d) array. The per-edge port
must give the same numbers (``tests/test_arena_papers_sparse.py``).
"""

from pathlib import Path

import numpy as np

import secest.arena.papers  # noqa: F401  (registers the five methods)
from secest.arena import scenarios
from secest.arena.estimators import METHODS

NETWORKS = ("target20", "inertia5", "tank12")
ATTACKS = ("none", "bias", "replacement", "message", "dos")
NAMES = ("ding2020", "guo2023", "lee2020", "li2025", "ma2021")


class DenseTrial:
    """A trial whose ``received`` returns the dense (runs, N, N, d) messages of the old API."""

    def __init__(self, trial: scenarios.Trial) -> None:
        self.trial = trial
        for name in ("scenario", "x", "y", "y_clean", "attacked", "link", "message_delta"):
            setattr(self, name, getattr(trial, name))

    def received(self, k, messages, encode=None):
        net = self.scenario.network
        m = np.asarray(messages, dtype=float)
        out = np.broadcast_to(m[:, None], (m.shape[0], m.shape[1], *m.shape[1:])).copy()
        if self.message_delta is None:
            return out
        delta = np.zeros((*out.shape[:3], self.message_delta.shape[-1]))
        delta[:, net.receivers, net.senders] = (self.trial.hits[:, k, :, None]
                                                * self.message_delta[:, k][:, net.senders])
        return out + (delta if encode is None else encode(delta))


def main() -> None:
    out = {}
    for net in NETWORKS:
        for att in ATTACKS:
            t = scenarios.simulate(scenarios.scenario(net, att, runs=2, horizon=30, seed=7))
            for name in NAMES:
                est = METHODS[name].run(DenseTrial(t))
                out[f"{net}/{att}/{name}/last"] = est.xhat[:, -1]
                out[f"{net}/{att}/{name}/sse"] = ((est.xhat - t.x[:, :, None]) ** 2).sum(axis=(0, 2, 3))
                if est.alarms is not None:
                    out[f"{net}/{att}/{name}/alarms"] = est.alarms.sum(axis=(0, 2))
    np.savez_compressed(Path(__file__).with_name("arena_papers_dense_reference.npz"), **out)


if __name__ == "__main__":
    main()
