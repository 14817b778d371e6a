"""Home grounds (issue #28): each paper's estimator on its own example's arena card reproduces the
headline numbers of its notebook (``figures/<key>/claims.json``).

ding2020 (Sec. V): the card is the example's plant, network, attack, channel and, as the first 150
of its 410 steps, horizon; every number on it equals the notebook's. The arena draws its own runs
(noises clipped at 3 sd, every node starting at ``x_hat = 0``, one channel chain per run), so its
Monte Carlo numbers are compared with the notebook's through their 95 % intervals: consistent when
the two intervals overlap.

lee2020 (Sec. IV): the card carries noise (the arena's unit, the oracle's error, needs it). On the
card's plant, ring, attack and sampling, fed the notebook's noise-free data (its ``x_0``, no noise),
the arena's wrapper reproduces the notebook's numbers within the notebook's own chattering tolerance.
"""

from __future__ import annotations

import json
import re
from dataclasses import replace
from functools import cache

import numpy as np
import pytest
from conftest import repo_root

from secest.arena import scenarios
from secest.arena.estimators import METHODS, Estimate
from secest.arena.papers.ding2020 import Ding2020
from secest.arena.papers.lee2020 import Lee2020
from secest.arena.scenarios import Scenario, Trial
from secest.core import graphs, montecarlo
from secest.core.validation import ValidationError
from secest.methods import ding2020
from secest.methods.lee2020 import assumption4_basis
from secest.repro import spaces

LOCK_STEPS = 10  # ding2020 notebook: a node is locked out after 10 consecutive rejections
CHATTER_STEPS = 10  # lee2020 notebook: the chattering tolerance is ten sign steps kappa v_l dt_ex
THETA_SUM = np.array([1.0, 0.0, 1.0, 0.0, 1.0, 0.0])  # theta_1 + theta_2 + theta_3 (lee2020, Fig. 1)


@cache
def _home(name: str) -> Scenario:
    """The named home scenario as the arena runs it (the matrix's defaults)."""
    return next(sc for sc in scenarios.matrix() if sc.name == name)


@cache
def _notebook(key: str) -> dict:
    """The literal parameters of ``notebooks/<key>.py``."""
    return {name: entry.value for name, entry in spaces.parameter_cell(key).items()}


@cache
def _claims(key: str) -> dict:
    return json.loads((repo_root() / "figures" / key / "claims.json").read_text())


def test_every_home_ground_is_in_the_matrix_on_its_wrappers_home_network() -> None:
    names = [sc.name for sc in scenarios.matrix()]
    assert {"ding2020-home", "lee2020-home"} <= set(names)
    for key in ("ding2020", "lee2020"):
        assert METHODS[key].home == _home(f"{key}-home").network.name
    assert all(not METHODS[key].home for key in ("guo2023", "li2025", "ma2021"))


_BIAS = {"title": "t", "kind": "bias", "nodes": [0, 2], "magnitude": 2.0}


@pytest.mark.parametrize("keys, words", [
    ({"start": 0.5, "windows": [[1, 2], [3]]}, "either start or windows, not both"),
    ({}, "either start or windows, not both"),
    ({"windows": [[1, 2]]}, "windows must list, for each of the 2 nodes"),
    ({"windows": [[3, 2], [1]]}, "0 <= first <= last"),
    ({"windows": [[1, 2], [1, 2, 3]]}, "[first, last] or [first] steps"),
    ({"start": 0.5, "p": 0.1}, "needs both p and q, or neither"),
    ({"start": 0.5, "p": 1.5, "q": 0.5}, "attack x: p"),
])
def test_a_bad_bias_window_or_channel_is_refused(keys: dict, words: str) -> None:
    with pytest.raises(ValidationError, match=re.escape(words)):
        scenarios.cards({"attack": {"x": _BIAS | keys}})


def test_a_windowed_bias_over_a_channel_acts_where_its_card_says() -> None:
    extra = {"attack": {"x": _BIAS | {"windows": [[2, 4], [6]], "p": 0.5, "q": 0.5},
                        "y": {"title": "t", "kind": "dos", "p": 0.5, "q": 0.5}}}
    sc = scenarios.scenario("inertia5", "x", runs=3, horizon=8, extra=extra)
    trial = scenarios.simulate(sc)
    acting = np.zeros((9, 5), bool)
    acting[2:5, 0] = acting[6:, 2] = True  # [first, last] inclusive; [first]: to the horizon's end
    np.testing.assert_array_equal(trial.attacked, np.broadcast_to(acting, trial.attacked.shape))
    shift = (trial.y - trial.y_clean)[..., 0]
    np.testing.assert_allclose(shift, 2.0 * sc.plant.r_std[0] * trial.attacked, rtol=1e-12, atol=1e-15)
    assert sc.attack.lossy and not (trial.link == 1).all()  # the links fail on the card's chain
    dos = scenarios.scenario("inertia5", "y", runs=3, horizon=8, extra=extra)
    np.testing.assert_array_equal(scenarios.simulate(dos).link, trial.link)  # a dos card's chain


# ------------------------------------------------------------------------------------- ding2020


def test_ding2020_home_card_is_the_notebook_example() -> None:
    nb, sc = _notebook("ding2020"), _home("ding2020-home")
    ex = ding2020.example(nb["m"], nb["T"], nb["gains_low"], nb["gains_high"])
    plant, att = sc.plant, sc.attack
    assert plant.dt == nb["T"] and sc.network.N == nb["m"]
    np.testing.assert_allclose(plant.A, ex.A, rtol=1e-15, atol=0)
    np.testing.assert_allclose(plant.Q, ex.B @ ex.B.T, rtol=1e-15, atol=0)
    np.testing.assert_allclose(sc.R, np.broadcast_to(ex.D @ ex.D.T, sc.R.shape), rtol=1e-15, atol=0)
    np.testing.assert_array_equal(sc.C[:, 0, :], ex.C)
    assert plant.x0_std**2 == nb["sigma0"]  # x_0 ~ N(0, sigma0 I)
    adj = graphs.random_geometric_graph(nb["m"], nb["radius"], nb["topology_seed"])
    np.testing.assert_array_equal(sc.network.adj, adj)
    attacks = sorted(nb["attacks"])  # [node (1-based), k_first, k_last, value]
    card = sorted((node + 1, *window) for node, window in zip(att.nodes, att.windows, strict=True))
    assert [a[:3] for a in attacks] == [list(c) for c in card]
    for node, *_, value in attacks:
        size = att.magnitude * plant.r_std[sc.network.measures[node - 1]]
        np.testing.assert_allclose(size, [value], rtol=1e-15, atol=0)
    assert (att.p, att.q, att.lossy) == (nb["p"], nb["q"], True)
    assert sc.horizon >= nb["horizon"]
    method = Ding2020()
    assert (method.kappa, method.threshold) == (nb["kappa"], nb["threshold"])
    trial = scenarios.simulate(replace(sc, runs=2))
    injected = np.zeros((nb["horizon"] + 1, nb["m"]))  # the notebook's attack array
    for node, k_first, k_last, value in nb["attacks"]:
        injected[k_first : k_last + 1, node - 1] += value
    shift = (trial.y - trial.y_clean)[:, : nb["horizon"] + 1, :, 0]
    np.testing.assert_allclose(shift, np.broadcast_to(injected, shift.shape), rtol=1e-14, atol=0)
    assert np.all(trial.link[:, 0] == nb["delta0"])


def _prefix(trial: Trial, steps: int) -> Trial:
    """The first ``steps + 1`` samples of ``trial`` (the filters are causal: their estimates there
    are the full run's)."""
    cut = slice(0, steps + 1)
    return Trial(replace(trial.scenario, horizon=steps), trial.x[:, cut], trial.y[:, cut],
                 trial.y_clean[:, cut], trial.attacked[:, cut], trial.link[:, cut],
                 trial.hits[:, cut], None)


def _works(alarms: np.ndarray, node: int, k_last: int) -> np.ndarray:
    """(runs,) bool: ``node`` is never locked out up to ``k_last`` (ding2020 notebook's ``works``)."""
    rejected = alarms[:, 1 : k_last + 1, node]
    windows = np.lib.stride_tricks.sliding_window_view(rejected, LOCK_STEPS, axis=1)
    return ~windows.all(axis=-1).any(axis=1)


def _window_rmse(est: Estimate, trial: Trial, ks: np.ndarray, node: int) -> np.ndarray:
    """Position RMSE of ``node`` over the steps ``ks``, one value per run (the notebook's ``rmse``)."""
    return np.sqrt(np.mean((est.xhat[:, ks, node, 0] - trial.x[:, ks, 0]) ** 2, axis=1))


def _overlap(samples: np.ndarray, notebook: tuple[float, float]) -> None:
    """The 95 % bootstrap interval of the median of ``samples`` overlaps the notebook's."""
    low, high = montecarlo.bootstrap_interval(samples, "median")
    assert low <= notebook[1] and notebook[0] <= high, ((low, high), notebook)


def test_ding2020_on_its_home_card_matches_its_notebook() -> None:
    """C1 (detection), C3 (window RMSE with / without attack), C4 (without inspection), X3."""
    nb, sc = _notebook("ding2020"), _home("ding2020-home")
    control = scenarios.scenario(sc.network.name, "dos", runs=sc.runs, horizon=sc.horizon, seed=sc.seed)
    assert (control.attack.p, control.attack.q) == (sc.attack.p, sc.attack.q)  # the notebook's Case A
    full_b, full_a = scenarios.simulate(sc), scenarios.simulate(control)
    for field in ("x", "y_clean", "link"):  # common random numbers: only the sensor attack differs
        np.testing.assert_array_equal(getattr(full_b, field), getattr(full_a, field))
    case_b, case_a = _prefix(full_b, nb["horizon"]), _prefix(full_a, nb["horizon"])
    est_b, est_a = Ding2020().run(case_b), Ding2020().run(case_a)
    est_n = Ding2020(threshold=np.finfo(float).max).run(case_b)  # no inspection: every y accepted
    claims = _claims("ding2020")
    c1, c3, c4 = (claims[c]["measured"] for c in ("C1", "C3", "C4"))
    for node, window in zip(sc.attack.nodes, sc.attack.windows, strict=True):
        key, ks = f"sensor{node + 1}", np.arange(window[0], window[1] + 1)
        works = _works(est_a.alarms, node, window[1])
        assert works.mean() == c1["mc_working_runs"][key] / c1["mc_runs"] == 1.0
        rejected = est_b.alarms[works][:, ks, node]
        assert rejected.mean() == c1["mc_reject_rate_window"][key] == 1.0
        assert rejected.all(axis=1).mean() == c1["mc_runs_all_rejected"][key] == 1.0
        r_a, r_b, r_n = (_window_rmse(e, case_b, ks, node)[works] for e in (est_a, est_b, est_n))
        _overlap(r_b / r_a, (c3["mc_ci_lower"][key], c3["mc_ci_upper"][key]))
        _overlap(r_n / r_b, (c4["mc_ci_lower"][key], c4["mc_ci_upper"][key]))
    locked = est_a.alarms[:, -LOCK_STEPS:].all(axis=1).any(axis=1)  # X3: no attack, no lockout
    assert locked.mean() == claims["X3"]["measured"]["runs_with_a_locked_node"] == 0.0


# -------------------------------------------------------------------------------------- lee2020


def test_lee2020_home_card_is_the_notebook_example() -> None:
    nb, sc = _notebook("lee2020"), _home("lee2020-home")
    J, b, k = nb["J_inertia"], nb["b_damping"], nb["k_spring"]
    Ac = np.array([  # matrices (1): the notebook's three_inertia(J, b, k)
        [0, 1, 0, 0, 0, 0],
        [-k / J, -b / J, k / J, 0, 0, 0],
        [0, 0, 0, 1, 0, 0],
        [k / J, 0, -2 * k / J, -b / J, k / J, 0],
        [0, 0, 0, 0, 0, 1],
        [0, 0, k / J, 0, -k / J, -b / J],
    ])
    banks = np.array([[1, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 1, 0],
                      [1, 0, -1, 0, 0, 0], [0, 0, 1, 0, -1, 0]], dtype=float)
    np.testing.assert_allclose(sc.plant.Ac, Ac, rtol=1e-14, atol=0)
    np.testing.assert_array_equal(sc.C[:, 0, :], banks)
    order = [i - 1 for i in nb["ring_order"]]
    ring = np.zeros((len(order), len(order)))
    for a, c in zip(order, np.roll(order, -1), strict=True):
        ring[a, c] = ring[c, a] = 1.0
    np.testing.assert_array_equal(sc.network.adj, ring)
    att = sc.attack
    assert att.nodes == (nb["attack_bank"] - 1,) and len(att.windows[0]) == 1  # to the end
    assert att.windows[0][0] * sc.plant.dt == pytest.approx(nb["attack_start"], rel=1e-12)
    assert att.magnitude * sc.plant.r_std[sc.network.measures[att.nodes[0]]][0] == pytest.approx(
        nb["attack_amplitude"], rel=1e-15)
    method = Lee2020()
    assert (method.kappa, method.gamma, method.q) == (nb["kappa"], nb["gamma_ex"], nb["q"])
    assert sc.horizon * sc.plant.dt >= nb["T_ex"]


def _noise_free(sc: Scenario, x0: list[float]) -> Trial:
    """The card's runs with the notebook's data: its x_0, no noise; run 0 attacked, run 1 not."""
    card = scenarios.simulate(replace(sc, runs=2))
    x = np.empty((2, sc.horizon + 1, sc.plant.n))
    x[:, 0] = x0
    for k in range(sc.horizon):
        x[:, k + 1] = x[:, k] @ sc.plant.A.T
    clean = np.einsum("iyn,rkn->rkiy", sc.C, x)
    y = clean + (card.y - card.y_clean) * np.array([1.0, 0.0])[:, None, None, None]
    return Trial(sc, x, y, clean, card.attacked & np.array([True, False])[:, None, None], card.link,
                 card.hits, None)


@pytest.mark.parametrize("poles", ["near", "shifted"])
def test_lee2020_on_its_home_card_matches_its_notebook(poles: str) -> None:
    """C3 (error under attack), X8 (theta-sum offsets) at either pole reading; C5 (convergence
    without attack) at the notebook's reading, "near" (the arena prints "shifted")."""
    nb, sc = _notebook("lee2020"), _home("lee2020-home")
    trial = _noise_free(sc, nb["x0_plant"])
    err = Lee2020(poles=poles).run(trial).xhat - trial.x[:, :, None, :]
    V = assumption4_basis(sc.plant.Ac, list(sc.C)).V  # unit norm: the notebook's "unit" basis
    step = CHATTER_STEPS * nb["kappa"] * nb["dt_ex"]
    tol_inf, tol_sum = step * np.abs(V).max(), step * np.abs(THETA_SUM @ V).max()
    dt, claims = sc.plant.dt, _claims("lee2020")
    last = np.arange(sc.horizon + 1) * dt >= sc.horizon * dt - nb["final_window"] - 1e-9
    inf_err = np.abs(err).max(axis=(2, 3))  # max_i ||x_hat_i - x||_inf, (runs, K + 1)
    c3 = claims["C3"]["measured"]["resilient_inf_error_by_attack"][0]  # pi/3, settled, at 60 s
    assert abs(inf_err[0, last].max() - c3) <= tol_inf
    offsets = (err[0, last] @ THETA_SUM).mean(axis=0)
    x8 = claims["X8"]["measured"]["offsets"][f"{nb['gamma_ex']:g}"]
    np.testing.assert_allclose(offsets, x8, rtol=0, atol=tol_sum)
    if poles == nb["observer_poles"]:
        c5 = claims["C5"]["measured"]
        above = np.nonzero(inf_err[1] >= 0.05)[0]
        assert abs((above.max() + 1) * dt - c5["time_below_0.05"]) <= dt  # one sampling period
        assert abs(inf_err[1, last].max() - c5["final_error"]) <= tol_inf
