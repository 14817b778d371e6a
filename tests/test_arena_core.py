"""The arena's scenarios, baselines, interface and scores (secest.arena.scenarios, secest.arena.estimators)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from secest.arena import estimators, scenarios
from secest.arena.estimators import METHODS, Estimate, Method, register
from secest.core import graphs
from secest.core.validation import ValidationError


def _scenario(network: str = "inertia5", attack: str = "none", **kw) -> scenarios.Scenario:
    return scenarios.scenario(network, attack, **({"runs": 6, "horizon": "auto"} | kw))


def test_every_card_loads_and_the_matrix_crosses_them() -> None:
    c = scenarios.cards()
    assert {"target", "three_inertia", "quadruple_tank"} <= set(c["plant"])
    assert {"none", "bias", "replacement", "message", "dos"} <= set(c["attack"])
    grid = scenarios.matrix(runs=2, horizon=5)
    cross = len(c["matrix"]["networks"]) * len(c["matrix"]["attacks"])
    assert cross >= 15 and len(grid) == cross + len(c["scenario"])  # the cross, then the named ones
    assert [sc.name for sc in grid[cross:]] == list(c["scenario"])
    target = c["plant"]["target"]
    T = target.dt
    assert np.allclose(target.A, [[1, T, T**2 / 2], [0, 1, T], [0, 0, 1]], atol=1e-15)  # ding2020's A


def test_trials_share_truth_and_noise_across_attacks() -> None:
    a = scenarios.simulate(_scenario(attack="none"))
    b = scenarios.simulate(_scenario(attack="bias"))
    assert np.array_equal(a.x, b.x) and np.array_equal(a.y_clean, b.y_clean)
    assert not np.array_equal(a.y, b.y) and b.attacked[:, :, 0].any() and not b.attacked[:, :, 1:].any()
    again = scenarios.simulate(_scenario(attack="bias"))
    assert np.array_equal(b.y, again.y)
    # bounded noise: every component within NOISE_CLIP standard deviations. The clip is exact, but
    # v is recovered as (C x + r z - C x) / r: the addition, the subtraction and the division each
    # round once, by at most eps times the size of their operands (|C x| + r |z|, |z| <= NOISE_CLIP)
    cx, r = np.einsum("iyn,rkn->rkiy", a.scenario.C, a.x), a.scenario.plant.r_std[0]
    v = (a.y_clean - cx) / r
    rounding = 3 * np.finfo(float).eps * (np.abs(cx) + scenarios.NOISE_CLIP * r) / r
    assert np.all(np.abs(v) <= scenarios.NOISE_CLIP + rounding)
    assert np.abs(v).max() > scenarios.NOISE_CLIP - 1e-9  # the clip is reached: the check is not vacuous


def test_message_falsification_shifts_the_sent_estimate_in_physical_units() -> None:
    t = scenarios.simulate(_scenario(attack="message", horizon=40))
    sc = t.scenario
    m = np.random.default_rng(0).standard_normal((6, 5, sc.plant.n)) * 10
    out = t.received(3, m)
    net = sc.network
    diff = out - m[:, net.senders]
    sd = np.sqrt(np.diag(sc.steady_covariance))  # the oracle's steady-state error sd per component
    hit = t.hits[:, 3]
    assert hit.shape == (6, net.E) and hit.any()
    assert np.allclose(np.abs(diff[hit]), sc.attack.magnitude * sd)  # exactly magnitude sd, any sign
    assert not np.any(diff[~hit])  # only on hit links
    # one perturbation per sender and step: every hit edge of a sender carries the same shift
    r, e = np.nonzero(hit)
    assert np.allclose(diff[hit], t.message_delta[r, 3, net.senders[e]])
    # a method whose message is not its estimate maps the same shift by its own encoding
    Cj = sc.C[net.senders]
    y = t.y[:, 3]
    relayed = t.received(3, y, lambda d: np.einsum("eyn,ren->rey", Cj, d))
    shift = relayed - y[:, net.senders]
    assert np.allclose(shift, np.einsum("eyn,ren->rey", Cj, diff))
    with pytest.raises(ValidationError, match="encode: messages of 1 entries are not state estimates"):
        t.received(3, y)
    with pytest.raises(ValidationError, match="encode: expected perturbations of shape"):
        t.received(3, y, lambda d: d)
    assert scenarios.simulate(_scenario(horizon=40)).message_delta is None


def test_time_constants_and_auto_horizons() -> None:
    """tau: the slower of the oracle's error decay and the plant's slowest decaying mode."""
    c = scenarios.cards()
    tank = scenarios.scenario("tank12", "none", runs=2)
    slowest = -1.0 / np.log(np.abs(np.linalg.eigvals(tank.plant.A)).max())  # open loop, 90.3 s
    assert tank.time_constant == pytest.approx(slowest) and tank.plant.dt == 1.0
    assert tank.horizon == scenarios.auto_horizon(c["plant"]["quadruple_tank"], c["network"]["tank12"])
    assert tank.horizon >= scenarios.MIN_HORIZON_TAU * tank.time_constant and tank.horizon % 10 == 0
    target = scenarios.scenario("target20", "none", runs=2)  # marginally stable: the oracle's decay
    P, tau = scenarios.steady_state(target.plant, target.network)
    assert np.allclose(P, target.steady_covariance) and tau == target.time_constant
    assert 1.0 < tau < target.horizon / scenarios.MIN_HORIZON_TAU + 1e-9


def test_bad_cards_and_names_are_refused() -> None:
    with pytest.raises(ValidationError, match="network must be one of"):
        scenarios.scenario("nope", "none")
    with pytest.raises(ValidationError, match="attack must be one of"):
        scenarios.scenario("inertia5", "nope")
    with pytest.raises(ValidationError, match="runs must be >= 2"):
        scenarios.scenario("inertia5", "none", runs=1)


def test_oracle_equals_the_undefended_kf_without_attack_and_scores_one() -> None:
    sc = _scenario()
    t = scenarios.simulate(sc)
    oracle = METHODS["oracle"].run(t)
    kf = METHODS["kf"].run(t)
    assert np.array_equal(oracle.xhat, kf.xhat)
    s = estimators.score(t, kf, oracle)
    # the oracle's own covariance is the unit: it scores 1 on both windows by construction
    assert s.status == "ok" and s.steady[0] == pytest.approx(1.0, rel=1e-12)
    assert s.transient[0] == pytest.approx(1.0, rel=1e-12) and s.steady[1] <= 1.0 <= s.steady[2]
    assert s.growth == pytest.approx(1.0, abs=0.5) and s.outside == ()


def test_the_score_is_unit_free() -> None:
    """q = e' Sigma_o^-1 e / n does not change under any invertible change of state coordinates."""
    rng = np.random.default_rng(1)
    x = rng.standard_normal((5, 30, 3))
    oracle = x + 0.1 * rng.standard_normal(x.shape)
    xhat = x[:, :, None] + 0.3 * rng.standard_normal((5, 30, 4, 3))
    T = np.array([[1e3, 2.0, 0.0], [0.0, 1e-2, 0.0], [5.0, 0.0, 7.0]])  # mixed units
    q = estimators.normalised_errors(xhat, x, oracle)
    qT = estimators.normalised_errors(xhat @ T.T, x @ T.T, oracle @ T.T)
    assert np.allclose(q, qT, rtol=1e-9) and estimators.normalised_errors(
        oracle[:, :, None], x, oracle).mean() == pytest.approx(1.0, rel=1e-12)


def test_a_growing_error_is_diverged_not_a_ratio() -> None:
    sc = _scenario()
    t = scenarios.simulate(sc)
    oracle = METHODS["oracle"].run(t)
    settle = estimators.settle_steps(sc)
    k = np.arange(sc.horizon + 1)
    grow = 1.0 + np.maximum(k - settle, 0) / 40.0  # RMS error grows linearly: finite, unbounded
    est = Estimate(oracle.xhat + grow[None, :, None, None] * (oracle.xhat - t.x[:, :, None]))
    s = estimators.score(t, est, oracle)
    assert s.status == "diverged" and s.steady is None and s.growth > 2 and "k^p" in s.reason
    assert "its error grows" in s.reason
    from secest.arena import matrix
    assert matrix.cell_text(s)["steady"].startswith("diverged: its error grows")


def test_consensus_kf_on_a_complete_graph_is_the_centralised_kf() -> None:
    """One Metropolis round on a complete graph averages exactly: N x average = the sum."""
    sc = _scenario()
    complete = replace(sc.network, edges=graphs.complete_edges(5))
    sc = replace(sc, network=complete)
    t = scenarios.simulate(sc)
    diff = METHODS["consensus-kf"].run(t).xhat - METHODS["oracle"].run(t).xhat
    assert np.abs(diff).max() < 1e-8


def test_chi2_baseline_false_alarms_near_its_level_without_attack() -> None:
    sc = _scenario(network="tank12", runs=20)
    t = scenarios.simulate(sc)
    s = estimators.score(t, METHODS["chi2-kf"].run(t), METHODS["oracle"].run(t))
    lo, hi = s.false_alarm[1:]
    assert s.detection is None
    # clipped noise makes false alarms rarer than the nominal 1e-3, never more frequent
    assert lo <= estimators.CHI2_ALPHA * 1.5 and hi >= 0.0


def test_a_new_method_is_found_in_the_matrix() -> None:
    class Toy(Method):
        name = "toy-zero"
        title = "the centralised KF, shifted by 0.1"

        def conditions(self, sc):
            return [("the plant has three states", sc.plant.n == 3)]

        def requirements(self, sc):
            return [("the plant has at most four states", sc.plant.n <= 4)]

        def run(self, trial):
            x = estimators.centralised_kf(trial.scenario, trial.y) + 0.1
            return Estimate(np.repeat(x[:, :, None], trial.y.shape[2], axis=2))

    register(Toy)
    try:
        out = estimators.evaluate(_scenario(network="target20"), ["oracle", "toy-zero"])
        assert out["toy-zero"].status == "ok" and out["toy-zero"].steady[0] > 1.0
        assert out["toy-zero"].outside == ()
        tank = estimators.evaluate(_scenario(network="tank12"), ["toy-zero"])["toy-zero"]
        assert tank.status == "ok" and tank.outside == ("the plant has three states",)  # scored, marked
        na = estimators.evaluate(_scenario(), ["toy-zero"])["toy-zero"]  # six states: it cannot run
        assert na.status == "n/a" and na.reason == "the plant has at most four states"
    finally:
        METHODS.pop("toy-zero")


def test_register_refuses_what_is_not_a_method() -> None:
    with pytest.raises(ValidationError, match="method must be a secest.arena.estimators.Method"):
        register(object())


def test_register_refuses_a_taken_or_reserved_name() -> None:
    class Impostor(estimators.Method):
        name = "oracle"

    with pytest.raises(ValidationError, match="method name 'oracle' is reserved"):
        register(Impostor)
    with pytest.raises(ValidationError, match="method name 'oracle' is reserved"):
        register(Impostor, replace=True)
    assert type(METHODS["oracle"]).__name__ == "Oracle"

    class Twin(estimators.Method):
        name = "kf"

    before = METHODS["kf"]
    with pytest.raises(ValidationError, match="'kf' is already registered .*replace=True"):
        register(Twin)
    assert METHODS["kf"] is before
    try:
        register(Twin, replace=True)
        assert type(METHODS["kf"]) is Twin
    finally:
        METHODS["kf"] = before


def test_a_diverging_estimate_is_reported_not_scored() -> None:
    t = scenarios.simulate(_scenario())
    oracle = METHODS["oracle"].run(t)
    bad = Estimate(np.full_like(oracle.xhat, np.inf))
    assert estimators.score(t, bad, oracle).status == "diverged"


def test_filter_step_with_per_link_messages_equal_to_the_estimates_is_the_printed_step() -> None:
    """received[i, j] = x_j reproduces (3) exactly; a falsified link changes only its receiver."""
    from secest.core import graphs
    from secest.methods import ding2020

    rng = np.random.default_rng(3)
    m, n = 5, 3
    adj = graphs.ring_graph(m)
    H = graphs.row_stochastic_weights(adj)
    x = rng.standard_normal((2, m, n))
    P = np.broadcast_to(np.eye(n), (2, m, n, n)).copy()
    common = dict(A=np.eye(n), BBt=0.1 * np.eye(n), C=np.ones((m, 1, n)), DDt=np.eye(1), adj=adj,
                  weights=H, kappa=0.2, threshold=25.0)
    y = rng.standard_normal((2, m, 1))
    plain = ding2020.secure_filter_step(x, P, 0.5 * P, 1, y, **common)
    links = np.broadcast_to(x[:, None], (2, m, m, n)).copy()
    same = ding2020.secure_filter_step(x, P, 0.5 * P, 1, y, received=links, **common)
    assert np.array_equal(plain.x_post, same.x_post)
    links[:, 0, 1] += 1.0  # node 0's message from node 1 is falsified
    hit = ding2020.secure_filter_step(x, P, 0.5 * P, 1, y, received=links, **common)
    changed = np.abs(hit.x_prior - plain.x_prior).max(axis=(0, 2)) > 0
    assert changed.tolist() == [True, False, False, False, False]
    with pytest.raises(ValidationError, match="Incompatible dimensions of received"):
        ding2020.secure_filter_step(x, P, 0.5 * P, 1, y, received=links[:, :, :2], **common)


BIAS = {"title": "a bias", "kind": "bias", "nodes": [0], "start": 0.3, "magnitude": 40.0}


@pytest.mark.parametrize("change, match", [
    ({"magnitud": 40.0, "magnitude": None}, r"unknown key 'magnitud' \(did you mean 'magnitude'\?\)"),
    ({"nodes": None}, r"missing key\(s\) \['nodes'\]"),
    ({"start": 1.5}, "start"),
    ({"nodes": [-1]}, "nodes must be a non-empty list of node indices >= 0"),
    ({"nodes": []}, "nodes must be a non-empty list"),
    ({"magnitude": 0.0}, "magnitude must be a positive number"),
    ({"prob": 0.3}, r"unknown key 'prob'"),
])
def test_a_bad_attack_card_is_refused_by_name(change: dict, match: str) -> None:
    card = {k: v for k, v in {**BIAS, **change}.items() if v is not None}
    with pytest.raises(ValidationError, match=match):
        scenarios.cards(extra={"attack": {"mine": card}})


def test_a_bad_network_or_plant_key_is_refused_by_name() -> None:
    net = {"title": "t", "plant": "target", "N": 4, "graph": "ring", "measures": [[0]] * 4}
    scenarios.cards(extra={"network": {"ok4": net}})  # valid as written
    with pytest.raises(ValidationError, match=r"network bad4: unknown key 'degre' \(did you mean 'degree'"):
        scenarios.cards(extra={"network": {"bad4": {**net, "degre": 4}}})
    with pytest.raises(ValidationError, match=r"network rgg4: missing key\(s\) \['radius', 'seed'\]"):
        scenarios.cards(extra={"network": {"rgg4": {**net, "graph": "rgg"}}})
    assert set(scenarios.CARD_KEYS) == {"plant", "network", "attack", "scenario", "matrix"}
    with pytest.raises(ValidationError, match=r"scenario s1: unknown key 'horizn' \(did you mean 'horizon'"):
        scenarios.cards(extra={"scenario": {"s1": {"network": "target20", "attack": "none",
                                                   "horizn": 40}}})
    with pytest.raises(ValidationError, match=r"scenario s2: missing key\(s\) \['attack'\]"):
        scenarios.cards(extra={"scenario": {"s2": {"network": "target20"}}})


def test_score_and_evaluate_check_shapes_trials_and_horizons() -> None:
    sc = _scenario()
    t = scenarios.simulate(sc)
    oracle = METHODS["oracle"].run(t)
    K = sc.horizon
    with pytest.raises(ValidationError, match=r"estimate.xhat: expected \(.*\), found"):
        estimators.score(t, Estimate(oracle.xhat[:, :, :-1]), oracle)  # one node missing
    with pytest.raises(ValidationError, match=r"estimate.xhat"):
        estimators.score(t, Estimate(oracle.xhat[..., :1]), oracle)  # one state component
    short = _scenario(horizon=60)
    with pytest.raises(ValidationError, match=r"horizon of inertia5/none: 60 steps give no steady window"):
        estimators.evaluate(short, ["oracle"])
    assert estimators.evaluate(short, ["oracle"], short=True)["oracle"].status == "ok"
    assert estimators.settle_steps(short, short=True) == 30 and estimators.settle_steps(sc) <= K // 4
    other = scenarios.simulate(replace(sc, seed=sc.seed + 1))
    with pytest.raises(ValidationError, match="trial: drawn for scenario"):
        estimators.evaluate(sc, ["oracle"], trial=other)


def test_a_failing_method_is_one_error_cell() -> None:
    from secest.arena import matrix

    class Broken(Method):
        name, title = "toy-broken", "raises"

        def run(self, trial):
            raise RuntimeError("singular matrix at step 3\nmore detail")

    class NoLMI(Method):
        name, title = "toy-no-lmi", "needs cvxpy"

        def run(self, trial):
            raise ModuleNotFoundError("No module named 'cvxpy'", name="cvxpy")

    register(Broken)
    register(NoLMI)
    try:
        out = estimators.evaluate(_scenario(), ["oracle", "toy-broken", "toy-no-lmi", "kf"])
        assert out["toy-broken"].status == "error"
        assert out["toy-broken"].reason == "RuntimeError: singular matrix at step 3"
        assert out["toy-no-lmi"].reason == "needs extra: lmi (pip install 'secest[lmi]')"
        assert out["kf"].status == "ok" and out["oracle"].status == "ok"
        assert matrix.cell_text(out["toy-broken"])["steady"] == "error: RuntimeError: singular matrix at step 3"
        assert matrix.cell_text(out["toy-no-lmi"])["steady"].startswith("needs extra: lmi")
    finally:
        METHODS.pop("toy-broken")
        METHODS.pop("toy-no-lmi")


def test_sizes_are_checked_before_allocation() -> None:
    from secest.core.validation import SizeLimitError

    net = {"title": "t", "plant": "target", "N": 10**5, "graph": "complete", "measures": [[0]]}
    with pytest.raises(SizeLimitError, match=r"network huge: N \(N - 1\) asks for 1e\+10 edges"):
        scenarios.cards(extra={"network": {"huge": net}})
    dense = {"title": "t", "plant": "target", "N": 1500, "graph": "complete", "measures": [[0]] * 1500}
    with pytest.raises(SizeLimitError, match=r"runs x \(horizon \+ 1\) x edges asks for 2\.27e\+09"):
        scenarios.scenario("dense", "none", runs=10, horizon=100, extra={"network": {"dense": dense}})
    with pytest.raises(SizeLimitError, match="horizon asks for 1e\\+09 steps"):
        _scenario(horizon=10**9)
    with pytest.raises(SizeLimitError, match="runs x \\(horizon \\+ 1\\) x nodes"):
        _scenario(horizon=10**6, runs=1000)
