"""ding2020's algorithm (secest.methods.ding2020) on the paper's example, and its arena method.

Unit tests of the functions the notebook imports: the Sec. V example's matrices, the recursion
over all steps, the comparison filter, Theorem 4's condition and the exact covariance. Values
come from the paper or from the committed figures/ding2020 data; identities and shapes are exact;
bad input must raise a ValidationError naming the argument. Nothing executes notebook text.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.sparse as sp
from scipy import stats

from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.core import graphs
from secest.core.validation import ValidationError
from secest.methods import ding2020
from secest.repro import spaces
from secest.repro.results import repo_root

PARAMS = {name: entry.value for name, entry in spaces.parameter_cell("ding2020").items()}
FIG = repo_root() / "figures" / "ding2020"


def _example(m: int = 20) -> ding2020.Example:
    return ding2020.example(m, PARAMS["T"], PARAMS["gains_low"], PARAMS["gains_high"])


def _ring(m: int) -> tuple[np.ndarray, np.ndarray]:
    adj = graphs.ring_graph(m)
    return adj, graphs.row_stochastic_weights(adj, self_weight=False)


def _problem(m: int = 8, runs: int = 3, steps: int = 30, seed: int = 4) -> dict:
    """The example's plant on a ring, a batch of runs with an attack on node 2 and a bursty channel."""
    ex = _example(m)
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((runs, 3))
    ys = [ex.C @ x.T]
    for _ in range(steps):
        x = x @ ex.A.T + rng.standard_normal((runs, 3)) @ ex.B.T
        ys.append(ex.C @ x.T)
    y = np.stack(ys, axis=1).transpose(2, 1, 0) + 0.05 * rng.standard_normal((runs, steps + 1, m))
    y[:, 10:14, 1] += 15.0
    adj, H = _ring(m)
    P0 = np.broadcast_to(2.0 * np.eye(3), (runs, m, 3, 3)).copy()
    delta = (rng.random(steps + 1) > 0.2).astype(float)
    model = dict(A=ex.A, BBt=ex.B @ ex.B.T, C=ex.C[:, None, :], DDt=ex.D @ ex.D.T, adj=adj, weights=H,
                 kappa=PARAMS["kappa"], threshold=PARAMS["threshold"])
    return dict(ex=ex, x0=rng.standard_normal((runs, m, 3)), P0=P0, delta=delta, y=y, model=model)


# ---------------------------------------------------------------------------- example


def test_example_is_the_papers_section_v() -> None:
    ex = _example()
    T = 0.05
    assert np.array_equal(ex.A, [[1, T, T**2 / 2], [0, 1, T], [0, 0, 1]])
    assert np.array_equal(ex.B, 0.2 * np.eye(3)) and np.array_equal(ex.D, [[0.05]])
    assert ex.C.shape == (20, 3) and ex.gains.shape == (20, 3)
    assert np.array_equal(ex.C[:7], np.tile([4.5, -0.8, -0.5], (7, 1)))  # "i < 8", 1-based
    assert np.array_equal(ex.C[7:], np.tile([4.0, -0.8, 1.0], (13, 1)))
    assert np.array_equal(ex.gains[:7], np.tile([0.4177, 0.5799, 0.4029], (7, 1)))
    assert np.array_equal(ex.gains[7:], np.tile([0.2883, 0.6150, 0.4457], (13, 1)))
    assert _example(5).C.shape == (5, 3)  # fewer nodes than the first group: all low
    assert np.array_equal(_example(5).gains, np.tile(PARAMS["gains_low"], (5, 1)))


@pytest.mark.parametrize(("kwargs", "name"), [
    (dict(m=0), "m"), (dict(m=2.5), "m"), (dict(T=0.0), "T"), (dict(T="a"), "T"),
    (dict(gains_low=[1.0, 2.0]), "gains_low"), (dict(gains_high=[np.nan, 0, 0]), "gains_high"),
])
def test_example_refuses_bad_input(kwargs: dict, name: str) -> None:
    args = dict(m=20, T=0.05, gains_low=PARAMS["gains_low"], gains_high=PARAMS["gains_high"]) | kwargs
    with pytest.raises(ValidationError, match=name):
        ding2020.example(**args)


# ---------------------------------------------------------------------------- secure_filter


def test_secure_filter_is_the_step_in_a_loop_bit_for_bit() -> None:
    pb = _problem()
    runs, steps1, m = pb["y"].shape
    keep = ("Pi_post", "Gamma_post", "gain", "theta", "nis")
    res = ding2020.secure_filter(pb["x0"], pb["P0"], 0.5 * pb["P0"], pb["delta"], pb["y"][..., None],
                                 keep=keep, **pb["model"])
    assert res.x.shape == (runs, steps1, m, 3) and res.theta.shape == (runs, steps1, m)
    assert res.delta_r.shape == (runs, steps1 - 1, m)
    assert res.history["Pi_post"].shape == (runs, steps1 - 1, m, 3, 3)
    assert res.history["gain"].shape == (runs, steps1 - 1, m, 3, 1)
    assert np.array_equal(res.x[:, 0], pb["x0"]) and np.all(res.theta[:, 0] == 1)
    x, Pi, Gam = pb["x0"], pb["P0"], 0.5 * pb["P0"]
    for k in range(steps1 - 1):
        st = ding2020.secure_filter_step(x, Pi, Gam, pb["delta"][k], pb["y"][:, k + 1, :, None], **pb["model"])
        x, Pi, Gam = st.x_post, st.Pi_post, st.Gamma_post
        assert np.array_equal(res.x[:, k + 1], x) and np.array_equal(res.theta[:, k + 1], st.theta)
        assert np.array_equal(res.history["nis"][:, k], st.nis)
        assert np.array_equal(res.delta_r[:, k], np.broadcast_to(pb["delta"][k], (runs, m)))
    assert np.array_equal(res.Pi_end, Pi) and np.array_equal(res.Gamma_end, Gam)
    assert np.array_equal(res.history["Pi_post"][:, -1], Pi)
    assert np.array_equal(res.history["theta"], res.theta[:, 1:])
    assert (res.theta[:, 10:14, 1] == 0).all()  # the +15 injections are rejected (25)


def test_secure_filter_per_run_channel_and_received_messages() -> None:
    """delta with batch axes (one chain per run) and a received callback, as the arena uses them."""
    pb = _problem(runs=2)
    per_run = np.stack([pb["delta"], 1.0 - pb["delta"]])
    res = ding2020.secure_filter(pb["x0"], pb["P0"], pb["P0"], per_run, pb["y"][..., None], **pb["model"])
    for r in range(2):
        one = ding2020.secure_filter(pb["x0"][r], pb["P0"][r], pb["P0"][r], per_run[r], pb["y"][r, ..., None],
                                     **pb["model"])
        assert np.allclose(res.x[r], one.x, rtol=0, atol=1e-12)
        assert np.array_equal(res.delta_r[r], np.broadcast_to(per_run[r, :-1, None], one.delta_r.shape))
    seen = []

    def received(k: int, x: np.ndarray) -> np.ndarray:
        seen.append(k)
        return np.broadcast_to(x[..., None, :, :], (*x.shape[:-1], *x.shape[-2:]))  # the true messages

    same = ding2020.secure_filter(pb["x0"], pb["P0"], pb["P0"], per_run, pb["y"][..., None], received=received,
                                  **pb["model"])
    assert seen == list(range(pb["y"].shape[1] - 1))
    assert np.allclose(same.x, res.x, rtol=0, atol=1e-12)


def test_per_edge_messages_on_a_sparse_graph_are_the_per_link_ones() -> None:
    """Falsified messages per edge with sparse adj and weights (the arena's O(E) form) give the
    per-link (m, m) result: measured max deviation of x, Pi and the indicators."""
    pb = _problem(runs=2)
    adj, H = pb["model"]["adj"], pb["model"]["weights"]
    rows, cols = np.nonzero(adj)  # row-major: the stored order of the CSR matrices
    rng = np.random.default_rng(7)
    shifts = rng.standard_normal((pb["y"].shape[1], 2, rows.size, 3))

    def dense(k: int, x: np.ndarray) -> np.ndarray:
        out = np.broadcast_to(x[:, None], (2, *x.shape[1:-1], *x.shape[1:])).copy()
        out[:, rows, cols] += shifts[k]
        return out

    def edge(k: int, x: np.ndarray) -> np.ndarray:
        return x[:, cols] + shifts[k]

    sparse = dict(pb["model"], adj=sp.csr_array(adj), weights=sp.csr_array(H))
    args = (pb["x0"], pb["P0"], pb["P0"], pb["delta"], pb["y"][..., None])
    a = ding2020.secure_filter(*args, received=dense, keep=("Pi_post",), **pb["model"])
    b = ding2020.secure_filter(*args, received=edge, keep=("Pi_post",), **sparse)
    assert np.abs(a.x - b.x).max() <= 1e-12 * np.abs(a.x).max()
    assert np.abs(a.history["Pi_post"] - b.history["Pi_post"]).max() <= 1e-12
    assert np.array_equal(a.theta, b.theta) and np.array_equal(a.delta_r, b.delta_r)
    with pytest.raises(ValidationError, match="per-edge"):
        ding2020.secure_filter(*args, received=lambda k, x: x[:, cols[:-1]], **sparse)


@pytest.mark.parametrize(("change", "name"), [
    (dict(keep=("nonexistent",)), "keep"), (dict(keep="Pi_post"), "keep"), (dict(received=3), "received"),
    (dict(delta=np.ones(5)), "delta"), (dict(delta=np.full(40, 0.5)), "delta"),
    (dict(y=np.zeros((3, 31, 7, 1))), "y"), (dict(y=np.zeros((3, 1, 8, 1))), "y"),
    (dict(Pi0=-np.ones((3, 8, 3, 3))), "Pi0"), (dict(Gamma0=np.full((3, 8, 3, 3), 3.0) * np.eye(3)), "Gamma0"), (dict(kappa=-1.0), "kappa"),
])
def test_secure_filter_refuses_bad_input(change: dict, name: str) -> None:
    pb = _problem()
    args = dict(x0=pb["x0"], Pi0=pb["P0"], Gamma0=pb["P0"], delta=pb["delta"], y=pb["y"][..., None])
    with pytest.raises(ValidationError, match=name):
        ding2020.secure_filter(**(args | pb["model"] | change))


# ---------------------------------------------------------------------------- comparison filter


@pytest.mark.parametrize("form", ["corrector", "predictor"])
def test_constant_gain_filter_is_the_printed_recursion(form: str) -> None:
    pb = _problem()
    ex, md = pb["ex"], pb["model"]
    x = ding2020.constant_gain_filter(pb["x0"], pb["delta"], pb["y"], A=ex.A, C=ex.C, gains=ex.gains[:8],
                                      adj=md["adj"], weights=md["weights"], kappa=md["kappa"], form=form)
    assert x.shape == (3, 31, 8, 3) and np.array_equal(x[:, 0], pb["x0"])
    H, kappa = md["weights"], md["kappa"]
    ref = pb["x0"].copy()
    for k in range(30):
        xi = pb["delta"][k] * (H @ ref - ref)  # rows of H sum to 1
        prior = (ref + kappa * xi) @ ex.A.T  # (7)
        if form == "corrector":
            eta = pb["y"][:, k + 1] - np.einsum("in,rin->ri", ex.C, prior)
        else:
            eta = pb["y"][:, k] - np.einsum("in,rin->ri", ex.C, ref)
        ref = prior + ex.gains[:8] * eta[..., None]
        assert np.allclose(x[:, k + 1], ref, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize(("change", "name"), [
    (dict(form="lmi"), "form"), (dict(gains=np.ones((8, 2))), "gains"), (dict(C=np.ones((7, 3))), "C"),
    (dict(y=np.zeros((3, 31, 8, 1))), "y"), (dict(delta=[1, 1]), "delta"), (dict(kappa=-0.1), "kappa"),
])
def test_constant_gain_filter_refuses_bad_input(change: dict, name: str) -> None:
    pb = _problem()
    ex, md = pb["ex"], pb["model"]
    args = dict(x0=pb["x0"], delta=pb["delta"], y=pb["y"], A=ex.A, C=ex.C, gains=ex.gains[:8], adj=md["adj"],
                weights=md["weights"], kappa=md["kappa"])
    with pytest.raises(ValidationError, match=name):
        ding2020.constant_gain_filter(**(args | change))


# ---------------------------------------------------------------------------- Theorem 4


def test_theorem4_on_the_example_gives_the_committed_values() -> None:
    ex = _example()
    committed = json.loads((FIG / "claims.json").read_text())["X7"]["measured"]
    sigma = float(stats.chi2.sf(PARAMS["threshold"], 1))
    kw = dict(p=PARAMS["p"], q=PARAMS["q"], kappa=PARAMS["kappa"], n_bar=committed["N_bar"], nu=PARAMS["nu"],
              sigma=sigma)
    for form, factor in (("printed", 1.0), ("proof_factor2", 2.0)):
        t4 = ding2020.theorem4_condition(ex.A, ex.C, factor=factor, **kw)
        assert t4.xi_q == pytest.approx(committed["xi"][form]["xi_q"], rel=1e-9)
        assert t4.xi_p == pytest.approx(committed["xi"][form]["xi_p"], rel=1e-9)
    assert t4.zeta * t4.alpha_bar**2 == pytest.approx(committed["zeta_alpha2"], rel=1e-9)
    assert t4.zeta * t4.alpha_bar**2 == pytest.approx(2.35948, abs=1e-5)
    assert t4.c_lo == pytest.approx(np.sqrt(4.0**2 + 0.8**2 + 1.0**2))
    assert t4.c_hi == pytest.approx(np.sqrt(4.5**2 + 0.8**2 + 0.5**2))
    # identity: the brackets are >= 1, equal to 1 at kappa = 0, so xi >= zeta alpha^2 with equality there
    k0 = ding2020.theorem4_condition(ex.A, ex.C, **(kw | {"kappa": 0.0}))
    assert k0.xi_q == pytest.approx(k0.zeta * k0.alpha_bar**2) == pytest.approx(k0.xi_p)
    assert t4.xi_q >= k0.xi_q and t4.xi_p >= k0.xi_p


@pytest.mark.parametrize(("change", "name"), [
    (dict(p=1.5), "p"), (dict(q=-0.1), "q"), (dict(nu=2.0), "nu"), (dict(sigma="a"), "sigma"),
    (dict(kappa=-1.0), "kappa"), (dict(n_bar=0), "n_bar"), (dict(C=np.zeros((2, 3))), "C"),
    (dict(C=np.ones((2, 2))), "C"), (dict(A=np.ones((2, 3))), "A"),
])
def test_theorem4_refuses_bad_input(change: dict, name: str) -> None:
    ex = _example()
    args = dict(A=ex.A, C=ex.C, p=0.1, q=0.92, kappa=0.004, n_bar=11, nu=0.0, sigma=1e-6)
    with pytest.raises(ValidationError, match=name):
        ding2020.theorem4_condition(**(args | change))


# ---------------------------------------------------------------------------- exact covariance


def test_exact_covariance_equals_pi_at_kappa0_without_inspection() -> None:
    """X4's identity: at kappa = 0 every node is a Kalman filter, so Pi+ is the exact P+."""
    pb = _problem(runs=1)
    ex, md = pb["ex"], pb["model"]
    m = 8
    res = ding2020.secure_filter(pb["x0"], pb["P0"], pb["P0"], pb["delta"], pb["y"][..., None],
                                 keep=("Pi_post", "gain"), inspect=False, **(md | {"kappa": 0.0}))
    P0 = np.kron(np.ones((m, m)) + np.eye(m), np.eye(3))  # cov(x_0 - x_hat_0) = 2 I on the diagonal
    P = ding2020.exact_error_covariance(res.history["gain"][0, ..., 0], pb["delta"], P0, A=ex.A, B=ex.B,
                                        C=ex.C[:m], D=0.05, weights=md["weights"], kappa=0.0)
    assert P.shape == (31, m, 3, 3)
    assert np.array_equal(P[0], pb["P0"][0])
    assert np.allclose(P[1:], res.history["Pi_post"][0], rtol=1e-9, atol=1e-12)
    # kappa > 0: Pi+ is an upper bound of P+ (Theorem 2), to round-off
    res = ding2020.secure_filter(pb["x0"], pb["P0"], pb["P0"], pb["delta"], pb["y"][..., None],
                                 keep=("Pi_post", "gain"), inspect=False, **md)
    P = ding2020.exact_error_covariance(res.history["gain"][0, ..., 0], pb["delta"], P0, A=ex.A, B=ex.B,
                                        C=ex.C[:m], D=0.05, weights=md["weights"], kappa=md["kappa"])
    gap = np.linalg.eigvalsh(res.history["Pi_post"][0] - P[1:])[..., 0]
    assert gap.min() >= -1e-9 * np.trace(P[1:], axis1=-2, axis2=-1).max()


def test_committed_bound_consistency_data_is_ordered() -> None:
    """The committed Fig. data of C5: tr Gamma+ <= tr P+ <= tr Pi+ at every plotted node and step."""
    import csv

    with (FIG / "extra_bound_consistency.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    for node in PARAMS["plot_nodes"]:
        for r in rows[1:]:
            assert float(r[f"trGamma{node}"]) <= float(r[f"trP{node}"]) * (1 + 1e-9)
            assert float(r[f"trP{node}"]) <= float(r[f"trPi{node}"]) * (1 + 1e-9)


@pytest.mark.parametrize(("change", "name"), [
    (dict(gains=np.ones((3, 8))), "gains"), (dict(P0=np.ones((5, 5))), "P0"), (dict(P0=-np.eye(24)), "P0"),
    (dict(delta=np.ones(2)), "delta"), (dict(C=np.ones((8, 2))), "C"), (dict(weights=np.eye(3)), "weights"),
    (dict(D="a"), "D"), (dict(kappa=-1.0), "kappa"),
])
def test_exact_covariance_refuses_bad_input(change: dict, name: str) -> None:
    ex = _example(8)
    args = dict(gains=np.zeros((4, 8, 3)), delta=np.ones(4), P0=np.eye(24), A=ex.A, B=ex.B, C=ex.C, D=0.05,
                weights=_ring(8)[1], kappa=0.004)
    with pytest.raises(ValidationError, match=name):
        ding2020.exact_error_covariance(**(args | change))


# ---------------------------------------------------------------------------- the arena method


def _old_wrapper_loop(trial: scenarios.Trial) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arena's loop as it was written before secure_filter: the step called once per k."""
    sc = trial.scenario
    runs, K1, N, _ = trial.y.shape
    n = sc.plant.n
    adj = sc.network.adj
    H = graphs.row_stochastic_weights(adj, self_weight=False)
    x = np.zeros((runs, N, n))
    Pi = np.broadcast_to(sc.plant.x0_std**2 * np.eye(n), (runs, N, n, n)).copy()
    Gam = Pi.copy()
    out, alarms, bound = np.empty((runs, K1, N, n)), np.zeros((runs, K1, N), bool), np.empty((runs, K1, N, n, n))
    out[:, 0], bound[:, 0] = x, Pi
    for k in range(K1 - 1):
        st = ding2020.secure_filter_step(
            x, Pi, Gam, trial.link[:, k], trial.y[:, k + 1], A=sc.plant.A, BBt=sc.plant.Q, C=sc.C, DDt=sc.R[0],
            adj=adj, weights=H, kappa=0.004, threshold=25.0, received=trial.received(k, x),
            validate=k == 0)
        x, Pi, Gam = st.x_post, st.Pi_post, st.Gamma_post
        out[:, k + 1], bound[:, k + 1], alarms[:, k + 1] = x, Pi, st.theta == 0
    return out, alarms, bound


@pytest.mark.parametrize("attack", ["none", "bias", "message", "dos"])
def test_the_arena_method_is_the_library_recursion(attack: str) -> None:
    sc = scenarios.scenario("inertia5", attack, runs=3, horizon=40)
    method = METHODS["ding2020"]
    trial = scenarios.simulate(sc)
    est = method.run(trial)
    runs, K1, N, _ = trial.y.shape
    assert est.xhat.shape == (runs, K1, N, sc.plant.n) and np.all(np.isfinite(est.xhat))
    assert est.alarms.shape == (runs, K1, N) and est.alarms.dtype == bool and not est.alarms[:, 0].any()
    out, alarms, bound = _old_wrapper_loop(trial)
    assert np.array_equal(est.xhat, out)
    assert np.array_equal(est.alarms, alarms)
    assert np.array_equal(np.broadcast_to(est.bound, bound.shape), bound)
