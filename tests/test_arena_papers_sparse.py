"""The five paper methods on per-edge messages: the same numbers as the dense code, and no dense
(N, N) array on a network above ``scenarios.DENSE_NODES``.

The reference ``tests/data/arena_papers_dense_reference.npz`` was written by
``tests/data/make_papers_dense_reference.py`` with the dense wrappers, before their port.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import secest.arena.papers  # noqa: F401  (registers the five methods)
from secest.arena import scenarios
from secest.arena.estimators import METHODS

REF = np.load(Path(__file__).parent / "data" / "arena_papers_dense_reference.npz")
NAMES = ("ding2020", "guo2023", "lee2020", "li2025", "ma2021")
CELLS = [(net, att) for net in ("target20", "inertia5", "tank12")
         for att in ("none", "bias", "replacement", "message", "dos")]
RTOL = 1e-10
"""Relative deviation allowed from the dense code: the per-edge sums add the same terms in
another order (measured at most 2e-12, guo2023's fusion). A method whose declared tolerance is
looser (ma2021: gains from CLARABEL's interior-point iterates, `Method.tolerance`) is held to that
one: the reference was written on Python 3.11, and another Python's solver and BLAS builds give
other iterates (measured on 3.13: 1.1 % relative on tank12)."""


SOLVER_DRIVEN = ("ma2021",)
"""Methods held to their declared tolerance instead of RTOL (their numbers come from a solver's
iterates); the others passed at RTOL on Python 3.11 and 3.13 and stay at it."""


def _bound(name: str, scale: float) -> float:
    """The deviation allowed from the frozen reference at a quantity of size ``scale``."""
    if name not in SOLVER_DRIVEN:
        return RTOL * scale
    tol = METHODS[name].tolerance
    return max(RTOL * scale, tol.atol + tol.rtol * scale)


@pytest.fixture(scope="module", params=CELLS, ids=["/".join(c) for c in CELLS])
def trial(request) -> scenarios.Trial:
    net, att = request.param
    return scenarios.simulate(scenarios.scenario(net, att, runs=2, horizon=30, seed=7))


@pytest.mark.parametrize("name", NAMES)
def test_per_edge_estimates_are_the_dense_ones(trial, name) -> None:
    est = METHODS[name].run(trial)
    key = f"{trial.scenario.name}/{name}"
    last, sse = REF[f"{key}/last"], REF[f"{key}/sse"]
    assert np.abs(est.xhat[:, -1] - last).max() <= _bound(name, np.abs(last).max())
    new_sse = ((est.xhat - trial.x[:, :, None]) ** 2).sum(axis=(0, 2, 3))
    assert np.abs(new_sse - sse).max() <= _bound(name, sse.max())
    if f"{key}/alarms" in REF:
        assert np.array_equal(est.alarms.sum(axis=(0, 2)), REF[f"{key}/alarms"])


@pytest.fixture(scope="module")
def big_ring() -> scenarios.Trial:
    """A ring above DENSE_NODES: network.adj refuses, so any dense (N, N) use would fail."""
    N = scenarios.DENSE_NODES + 100
    extra = {"network": {"bigring": {"title": "ring", "plant": "quadruple_tank", "N": N,
                                     "graph": "ring", "measures": [[i % 4] for i in range(N)]}}}
    return scenarios.simulate(scenarios.scenario("bigring", "dos", runs=2, horizon=3, seed=1,
                                                 extra=extra))


@pytest.mark.parametrize("name", NAMES)
def test_runs_on_a_ring_too_large_for_a_dense_adjacency(big_ring, name) -> None:
    method = METHODS[name]
    assert method.not_applicable(big_ring.scenario) is None
    est = method.run(big_ring)
    N = big_ring.scenario.network.N
    assert est.xhat.shape == (2, 4, N, 4) and np.all(np.isfinite(est.xhat))
