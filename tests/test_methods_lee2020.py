"""lee2020 in the arena (secest.methods.lee2020): equivalence with the notebook, the sampled reading.

The notebook's own objects are taken by name with ``benchmarks/harness.py``'s
``notebook_definitions``: only the statements defining them (and what those read) run, so the
loop printing the transient peaks of every ``exp(F_i t)`` (8 s, no result used here) and the
figures are skipped without any text marker.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import bench_harness

from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.core import graphs, systems
from secest.core.validation import ValidationError
from secest.methods import lee2020 as L

notebook_definitions = bench_harness().notebook_definitions

NOTEBOOK_NAMES = (
    "A", "B", "N", "V", "W", "S_ind", "T_modal", "U_sub", "a4_resid", "adj_ex", "attack_amplitude",
    "banks", "dt", "dt_ex", "exogenous", "gamma", "gamma_ex", "hi", "kappa", "L_gain", "lap_ex", "lo",
    "modes", "network_system", "observers", "pattern", "record_dt", "runs", "s_vals",
    "simulate", "X_init", "x_init", "z_vals",
)


@pytest.fixture(scope="module")
def nb() -> dict:
    """What the tests compare, taken from the notebook by name (fast mode, no figures)."""
    return notebook_definitions("lee2020", *NOTEBOOK_NAMES, mode="fast", figures=False, T=0.5,
                                sweep_T=0.2, basis_normalisation="unit")


@pytest.fixture(scope="module")
def basis(nb) -> L.Basis:
    return L.assumption4_basis(nb["A"], nb["banks"])


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / max(np.abs(b).max(), 1e-300))


# ------------------------------------------------------------------- equivalence with the notebook


def test_median_set_and_solver_equal_the_notebook(nb) -> None:
    assert L.median_set(nb["z_vals"], nb["s_vals"]) == (nb["lo"], nb["hi"])
    t, xs = L.median_solver(graphs.ring_graph(nb["N"]), nb["z_vals"], nb["s_vals"], nb["x_init"],
                            nb["gamma"], nb["T"], nb["dt"])
    ref = nb["runs"]["ring"]
    assert np.array_equal(t, ref["t"]) and _rel(xs, ref["x"]) <= 1e-12


def test_basis_of_assumption4_equals_the_notebook(nb, basis) -> None:
    assert basis.construction == "modes" and basis.ok
    assert _rel(basis.V, nb["V"]) <= 1e-12 and _rel(basis.W, nb["W"]) <= 1e-12
    assert np.array_equal(basis.S, nb["S_ind"])
    V, S, T = L.common_basis(nb["modes"], nb["pattern"])
    assert _rel(T, nb["T_modal"]) <= 1e-12
    ok, resid = L.check_assumption4(V, S, nb["U_sub"])
    assert ok and resid == pytest.approx(nb["a4_resid"], abs=1e-15)


@pytest.mark.parametrize("poles", ["near", "shifted"])
def test_observer_gains_equal_the_notebook(nb, basis, poles) -> None:
    gains, closed = L.observer_gains(nb["A"], basis.V, basis.S, nb["banks"], poles)
    ref = nb["observers"][("unit", poles)]  # the notebook's reading (basis normalisation, poles)
    ref_gains, ref_closed = ref.L, ref.F
    for mine, ref in zip(gains + closed, ref_gains + ref_closed, strict=True):
        assert _rel(mine, ref) <= 1e-10


def test_network_system_and_the_example_trajectory_equal_the_notebook(nb, basis) -> None:
    """(1), (5), (6) stacked and integrated: the notebook's simulate() against our functions."""
    args = (nb["A"], nb["B"], nb["banks"], basis.V, basis.S, nb["L_gain"], nb["kappa"])
    mine = L.network_system(*args, nb["gamma_ex"], nb["lap_ex"])
    ref = nb["network_system"](nb["L_gain"], nb["gamma_ex"])
    for a, b in zip(mine[:4], ref, strict=True):
        assert _rel(a, b) <= 1e-12
    # variant (11): any corrected basis passes through
    rng = np.random.default_rng(0)
    v_corr, w_corr = rng.standard_normal((2, 6, 6))
    mine11 = L.network_system(*args, nb["gamma_ex"], nb["lap_ex"], v_corr=v_corr, w_corr=w_corr)
    for a, b in zip(mine11[:4], nb["network_system"](nb["L_gain"], nb["gamma_ex"], v_corr, w_corr),
                    strict=True):
        assert _rel(a, b) <= 1e-12
    amp = nb["attack_amplitude"]
    _, X_ref = nb["simulate"]([amp], horizon_s=12.0)  # past the attack at 10 s
    every = int(round(nb["record_dt"] / nb["dt_ex"]))
    X = systems.integrate_switched_linear(
        mine.M, mine.E_w, nb["exogenous"]([amp]), mine.E_s, mine.R, L.sign_correction(basis.S),
        nb["X_init"][:, None], nb["dt_ex"], int(round(12.0 / nb["dt_ex"])), record_every=every)
    assert X.shape == X_ref.shape and _rel(X, X_ref) <= 1e-10


def test_sampled_reading_converges_to_the_continuous_observer(nb, basis) -> None:
    """The arena's reading (y held, neighbours exchanged once per period) -> (6) as dt -> 0.

    The paper's example without input, attacked bank 1 from 10 s, well-conditioned ("shifted")
    gains; sub-step 1 ms throughout. Measured: RMS deviation of every x_hat_i from the continuous
    (6) over 12 s, at sampling periods 2 ms and 4 ms (order one: the ratio is about 2).
    """
    A, banks, V, S = nb["A"], nb["banks"], basis.V, basis.S
    gains = nb["observers"][("unit", "shifted")].L
    h, K, amp = 1e-3, 12000, nb["attack_amplitude"]
    cont = L.network_system(A, np.zeros(6), banks, V, S, gains, nb["kappa"], nb["gamma_ex"], nb["lap_ex"])

    def w(t: float) -> np.ndarray:
        return np.array([[0.0], [amp if t >= 10.0 else 0.0], [0.0], [0.0], [0.0], [0.0]])

    Xc = systems.integrate_switched_linear(cont.M, cont.E_w, w, cont.E_s, cont.R, L.sign_correction(S),
                                           nb["X_init"][:, None], h, K)[..., 0]
    C = np.stack(banks)
    y = np.einsum("iyn,kn->kiy", C, Xc[:, :6])
    y[h * np.arange(K + 1) >= 10.0, 0, 0] += amp
    rms = {}
    for s in (2, 4):
        obs = L.sampled_observer(A, V, S, gains, C, nb["adj_ex"], nb["kappa"], nb["gamma_ex"], h * s, s)
        ys = y[::s][None]
        run = L.run_sampled(obs, ys, lambda k, m: np.broadcast_to(m[:, None], (1, 5, 5, 6)),
                            np.ones(ys.shape[:2], int))
        dev = run.xhat[0] - Xc[::s, cont.xh0:].reshape(-1, 5, 6)
        rms[s] = float(np.sqrt(np.mean(dev**2)))
    assert rms[2] <= 1e-2
    assert 1.5 <= rms[4] / rms[2] <= 2.5


# ----------------------------------------------------------------------------- the arena method


def test_method_runs_on_a_small_scenario() -> None:
    sc = scenarios.scenario("inertia5", "none", runs=4, horizon=50)
    method = METHODS["lee2020"]
    assert method.kind == "paper" and method.not_applicable(sc) is None
    est = method.run(scenarios.simulate(sc))
    assert est.xhat.shape == (4, 51, 5, 6) and np.all(np.isfinite(est.xhat))
    assert est.alarms.shape == (4, 51, 5) and est.alarms.dtype == bool
    assert np.all(est.xhat[:, 0] == 0.0)
    first = np.asarray(est.notes["alarms_from_step"])
    steps = np.arange(51)[None, :, None]
    assert not np.any(est.alarms & (steps < first[None, None, :]))
    assert est.notes["substeps"] == 15  # kappa dt / (0.1 * 0.01 / sqrt(2)) = 14.1 -> 15


def test_method_runs_under_dos_and_falsified_messages() -> None:
    for attack in ("dos", "message"):
        sc = scenarios.scenario("tank12", attack, runs=3, horizon=20)
        est = METHODS["lee2020"].run(scenarios.simulate(sc))
        assert np.all(np.isfinite(est.xhat)) and len(est.notes["outside_theory"]) == 2


def test_a_lost_link_means_no_coupling() -> None:
    """Every link down: each node runs (5) and (6) on its own data, whatever the messages say."""
    sc = scenarios.scenario("tank12", "message", runs=3, horizon=20)
    trial = scenarios.simulate(sc)
    method = METHODS["lee2020"]
    obs = method._design(sc)["observer"]
    down = np.zeros_like(trial.link)
    alone = L.run_sampled(obs, trial.y, lambda k, m: trial.received(k, m, 1.0), down)
    garbage = L.run_sampled(obs, trial.y, lambda k, m: np.full((3, 12, 12, 4), 1e6), down)
    assert np.array_equal(alone.xhat, garbage.xhat)


@pytest.mark.parametrize(
    ("change", "condition"),
    [
        ("graph", "Assumption 3"),
        ("two attacked", "Assumption 1"),
        ("redundancy", "Assumption 2"),
        ("basis", "Assumption 4"),
    ],
)
def test_not_applicable_names_the_failed_assumption(change, condition) -> None:
    sc = scenarios.scenario("inertia5", "bias", runs=2, horizon=5)
    net = sc.network
    if change == "graph":
        adj = net.adj.copy()
        adj[0, 1] = 0.0  # a directed edge
        sc = replace(sc, network=replace(net, adj=adj))
    elif change == "two attacked":
        sc = replace(sc, attack=replace(sc.attack, nodes=(0, 1)))
    elif change == "redundancy":  # banks theta2, theta2, theta2: alone they miss the (1, 0, -1) mode
        sc = replace(sc, network=replace(net, measures=np.array([[1], [1], [1], [3], [4]])))
    else:  # A = 0 in the plane, five sensing directions: no basis makes five lines coordinate axes
        plant = replace(sc.plant, Ac=np.zeros((2, 2)), r_std=np.full(5, 0.01), state_names=("a", "b"),
                        outputs=np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, -1.0], [1.0, 2.0]]))
        sc = replace(sc, plant=plant)
    reason = METHODS["lee2020"].not_applicable(sc)
    assert reason is not None and reason.startswith(condition)
    with pytest.raises(ValidationError, match="not applicable"):
        METHODS["lee2020"].run(scenarios.simulate(replace(sc, runs=2, horizon=3)))


def test_repeated_eigenvalues_use_the_intersection_basis() -> None:
    """The target (triple integrator): every bank observes the plant; any basis works."""
    sc = scenarios.scenario("target20", "none", runs=2, horizon=5)
    b = L.assumption4_basis(sc.plant.Ac, list(sc.C))
    assert b.construction == "intersections" and b.ok
    assert np.allclose(b.V, np.eye(3)) and np.all(b.S == 1)


def test_bad_input_is_refused_naming_the_argument() -> None:
    cls = type(METHODS["lee2020"])  # register() returns the instance
    with pytest.raises(ValidationError, match="poles must be"):
        cls(poles="far")
    with pytest.raises(ValidationError, match="kappa must be a positive number"):
        cls(kappa=0.0)
    with pytest.raises(ValidationError, match="indicators must mark"):
        L.median_set(np.array([1.0, 2.0]), np.zeros(2))
    with pytest.raises(ValidationError, match="Euler stability limit"):
        L.median_solver(graphs.ring_graph(5), np.ones(5), np.ones(5), np.zeros(5), 100.0, 1.0, 0.01)
    with pytest.raises(ValidationError, match="repeated eigenvalues"):
        L.real_invariant_subspaces(np.zeros((2, 2)))
    sc = scenarios.scenario("inertia5", "none", runs=2, horizon=5)
    obs = METHODS["lee2020"]._design(sc)["observer"]
    with pytest.raises(ValidationError, match="Incompatible dimensions of y"):
        L.run_sampled(obs, np.zeros((2, 6, 4, 1)), lambda k, m: m, np.ones((2, 6)))
    with pytest.raises(ValidationError, match="Incompatible dimensions of values"):
        L.median_solver(graphs.ring_graph(5), np.ones(4), np.ones(5), np.zeros(5), 1.0, 1.0, 0.01)
    with pytest.raises(ValidationError, match="Incompatible dimensions of link"):
        L.run_sampled(obs, np.zeros((2, 6, 5, 1)), lambda k, m: m, np.ones((2, 5)))
    with pytest.raises(ValidationError, match="m must be >= 1"):
        L.sampled_observer(sc.plant.Ac, obs.V, np.ones((5, 6)), [], sc.C, sc.network.adj, 0.5, 2.0, 0.02, 0)
