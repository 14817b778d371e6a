"""li2025: unit tests of secest.methods.li2025 on the paper's example, and the arena method.

The example's data (the coordinated-turn model of Section IV, RRL-MAP with m = 2 of n_y = 4, the
Bernoulli replacement (6) with the sin/cos attack, the Monte Carlo draws of ``mc_seed``) are built
here as the notebook builds them; the library's estimator must then give the numbers committed in
figures/li2025 (Figs. 2-4 and 7), and its functions the identities of the derivation (the Kalman
limit, the stationarity of the gain (28), the ``|K_i|`` factor of (17)). Tests measure; none asserts
that a contested claim holds or fails.
"""

from __future__ import annotations

import csv
from dataclasses import replace

import numpy as np
import pytest

from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.arena.papers import li2025 as arena_li2025
from secest.core import graphs, montecarlo, schedules
from secest.core.validation import ValidationError
from secest.methods import li2025
from secest.repro.results import repo_root

FIG = repo_root() / "figures" / "li2025"
N, NX, NY, M_CH, T = 3, 4, 4, 2, 100  # targets, states, sensors, channels, horizon (paper / notebook)
EPS, W, V, XI_STAR, PSI = 0.05, 0.03, 0.03, 0.3, np.array([0.7, 0.5, 0.3])
WEIGHTS = [(1e-3, 1.0, 1e-2, 0.1, 0.1), (1e-2, 1.0, 1e-4, 1e-4, 0.3), (1e-2, 1.0, 1e-4, 1e-4, 0.1)]
K_SETS = li2025.EXAMPLE_PARENTS
H_EPS = np.diag([1.0, 1.0, EPS, EPS])
CH = li2025.EXAMPLE_C @ H_EPS
BH = {key: b @ H_EPS for key, b in li2025.EXAMPLE_B.items()}
X0_OFFSET = li2025.EXAMPLE_X0
A_ALL, E_ALL = li2025.turn_model(T)
AH_ALL = A_ALL @ H_EPS
EWE_ALL = W * (E_ALL[:, :, None] * E_ALL[:, None, :])
SETS = schedules.rrl_map_sets(np.arange(1, T + 1), M_CH, NY)
_KK = np.arange(T + 1)[:, None]
XI = np.sqrt(2 * XI_STAR / NY) * np.where(np.arange(NY) % 2 == 0, np.sin(_KK), np.cos(_KK))


def _plant(runs: int, seed: int = 2025) -> tuple[np.ndarray, np.ndarray]:
    """States (runs, T+1, N, 4) and received scheduled entries (runs, T, N, m) of the example."""
    rng = montecarlo.spawn_rngs(seed, 1)[0]
    sigma = rng.uniform(0.0, 1.0, (runs, N, NX))
    w = np.sqrt(W) * rng.standard_normal((runs, T, N))
    v = np.sqrt(V) * rng.standard_normal((runs, T, N, NY))
    psi = (rng.uniform(0.0, 1.0, (runs, T, N)) < PSI).astype(float)
    x, y = np.zeros((runs, T + 1, N, NX)), np.zeros((runs, T, N, M_CH))
    x[:, 0] = X0_OFFSET + sigma
    for k in range(1, T + 1):
        for i in range(N):
            xn = x[:, k - 1, i] @ AH_ALL[k - 1].T + E_ALL[k - 1] * w[:, k - 1, i, None]
            for j in K_SETS[i]:
                xn = xn + x[:, k - 1, j] @ BH[(i, j)].T
            x[:, k, i] = xn
            ok = psi[:, k - 1, i, None]
            y_raw = xn @ CH.T + v[:, k - 1, i]
            y[:, k - 1, i] = ok * y_raw[:, SETS[k - 1]] + (1 - ok) * XI[k, SETS[k - 1]]
    return x, y


def _estimate(x, y, **kw):
    return li2025.estimate(y, SETS, AH_ALL[:T], EWE_ALL[:T], CH, x[:, 0], np.eye(NX),
                           kw.pop("weights", WEIGHTS), kw.pop("psi_bar", PSI), XI_STAR, V,
                           parents=kw.pop("parents", K_SETS), BH=BH, **kw)


@pytest.fixture(scope="module")
def example():
    """The paper's example with the notebook's default draws (F = 100 runs, mc_seed = 2025)."""
    x, y = _plant(100)
    return x, y, _estimate(x, y), _estimate(x, y, update="zoh")


def _csv(name: str) -> dict[str, np.ndarray]:
    with (FIG / f"{name}.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def _match(measured: np.ndarray, committed: np.ndarray) -> None:
    """The committed CSV keeps about 11 significant digits (and absolute 1e-13)."""
    assert np.allclose(measured, committed, rtol=1e-9, atol=1e-12)


def test_fig7_mse_and_mean_bound_are_the_committed_ones(example) -> None:
    """MSE_i(k) and the mean tr S_i(k|k) of the zero-input and ZOH designs over the 100 runs."""
    x, _, zero, zoh = example
    ref = _csv("fig7_mse_and_bound")
    for i in range(N):
        _match(np.sum((x - zero["xhat"]) ** 2, axis=-1).mean(axis=0)[1:, i], ref[f"mse[{i}]"])
        _match(np.trace(zero["S"], axis1=-2, axis2=-1).mean(axis=0)[1:, i], ref[f"mean_tr_S[{i}]"])
        _match(np.sum((x - zoh["xhat"]) ** 2, axis=-1).mean(axis=0)[1:, i], ref[f"mse_zoh[{i}]"])


def test_figs2_to_4_trajectories_of_run_0_are_the_committed_ones(example) -> None:
    x, _, zero, _ = example
    for i in range(N):
        ref = _csv(f"fig{i + 2}_target{i + 1}_trajectories")
        for c in range(NX):
            _match(x[0, :, i, c], ref[f"x[{c}]"])
            _match(zero["xhat"][0, :, i, c], ref[f"xhat[{c}]"])


def test_shapes_schedule_columns_and_symmetric_positive_bounds(example) -> None:
    _, _, zero, zoh = example
    assert zero["xhat"].shape == (100, T + 1, N, NX) and zero["L"].shape == (100, T + 1, N, NX, NY)
    assert zero["S"].shape == zero["S_pred"].shape == (100, T + 1, N, NX, NX)
    for k in range(1, T + 1):  # the zero-input gain has columns on eps(k) only; ZOH uses every sensor
        off = np.setdiff1d(np.arange(NY), SETS[k - 1])
        assert np.all(zero["L"][:, k][..., off] == 0) and np.any(zero["L"][:, k][..., SETS[k - 1]] != 0)
    assert np.any(zoh["L"][:, 1:][..., np.setdiff1d(np.arange(NY), SETS[0])] != 0)
    for out in (zero, zoh):
        assert np.array_equal(out["S"], np.swapaxes(out["S"], -1, -2))
        assert np.all(np.linalg.eigvalsh(out["S"][:, 1:]) > 0)


def test_the_batch_over_runs_equals_a_loop_over_runs(example) -> None:
    """X2: each run's estimate depends on its own data only (moment = "run")."""
    x, y, zero, _ = example
    for f in range(3):
        one = _estimate(x[f:f + 1], y[f:f + 1])
        for key in ("xhat", "S", "L"):
            assert np.allclose(one[key][0], zero[key][f], rtol=1e-12, atol=1e-14), key


def test_ensemble_moment_is_common_to_the_runs(example) -> None:
    """With the runs' mean of xhat xhat^T the gain, hence the bound, is the same in every run."""
    x, y, _, _ = example
    ens = _estimate(x[:6], y[:6], moment="ensemble")
    assert np.allclose(ens["S"], ens["S"][:1], rtol=1e-12, atol=0)
    assert np.allclose(ens["L"], ens["L"][:1], rtol=1e-12, atol=0)


def test_fixed_gains_reproduce_the_run_and_drop_the_bound(example) -> None:
    """Feeding a run's own gains (28) back as fixed gains gives its estimates; S is not computed."""
    x, y, zero, _ = example
    fixed = _estimate(x[:1], y[:1], gains=zero["L"][0])
    assert np.allclose(fixed["xhat"], zero["xhat"][:1], rtol=1e-12, atol=1e-13)
    assert np.all(np.isnan(fixed["S"][:, 1:])) and np.array_equal(fixed["L"], zero["L"][:1])


def test_open_loop_and_debiased_updates(example) -> None:
    """Open loop: x_hat(k|k) is the prediction (7). Debiased: innovation y - psi_check G x_hat^-."""
    x, y, zero, _ = example
    ol = _estimate(x[:4], y[:4], update="open_loop")
    assert np.all(ol["L"] == 0)
    assert np.all(np.isfinite(ol["S"]))  # still the bound of the zero-input gain, on its own x_hat
    for k in (1, 7):
        for i in range(N):
            xp = ol["xhat"][:, k - 1, i] @ AH_ALL[k - 1].T + sum(
                ol["xhat"][:, k - 1, j] @ BH[(i, j)].T for j in K_SETS[i])
            assert np.allclose(ol["xhat"][:, k, i], xp, rtol=1e-13, atol=1e-15)
    db = _estimate(x[:4], y[:4], update="debiased")
    k, i = 5, 1
    xp = db["xhat"][:, k - 1, i] @ AH_ALL[k - 1].T + db["xhat"][:, k - 1, 0] @ BH[(1, 0)].T
    G, L = CH[SETS[k - 1]], db["L"][:, k, i][..., SETS[k - 1]]
    nu = y[:4, k - 1, i] - PSI[i] * xp @ G.T
    assert np.allclose(db["xhat"][:, k, i], xp + np.einsum("frc,fc->fr", L, nu), rtol=1e-12, atol=1e-14)


def test_bound_coefficients_of_the_example_and_their_readings() -> None:
    lam, a1, a2, a3, a4 = WEIGHTS[0]
    assert li2025.bound_coefficients(0.7, a2, a3, a4) == pytest.approx((1.033, 3.33, 33.3, 0.7))
    # printed Theorem 2: c0 = 1 - (a3 - a2)(1 - psi) < 1 when a3 > a2; kappa_x = 2 at psi = 1, alpha = 1
    assert li2025.bound_coefficients(0.7, a2, a3, a4, "paper") == pytest.approx((0.973, 9.8, 33.3, 0.7))
    assert li2025.bound_coefficients(1.0, 1.0, 1.0, 1.0, "paper") == (1.0, 2.0, 0.0, 1.0)
    assert li2025.bound_coefficients(0.7, a2, a3, a4, "additive") == pytest.approx((1.003, 0.0, 30.3, 1.0))
    # vectorised over candidates, as the notebook's grid uses it
    c0, kx, kxi, kv = li2025.bound_coefficients(0.5, np.array([0.1, 1.0]), 0.1, 0.1)
    assert c0 == pytest.approx([1.1, 1.55]) and kx == pytest.approx(5.55) and kv == 0.5
    assert kxi == pytest.approx([0.5 * (1 + 10 + 10), 0.5 * (1 + 1 + 10)])


def _gsg(S, G):
    return G @ S @ G.T


def test_without_attack_the_gain_and_bound_are_the_kalman_update() -> None:
    """psi_check = 1 (corrected coefficients): (28), (18) are K = P G^T (G P G^T + V)^-1, (I - K G) P."""
    rng = np.random.default_rng(3)
    a = rng.standard_normal((5, NX, NX))
    S = a @ np.swapaxes(a, -1, -2) + np.eye(NX)
    X_hat = rng.standard_normal((5, NX, 1))
    X_hat = X_hat @ np.swapaxes(X_hat, -1, -2)
    G = CH[SETS[0]]
    coefs = li2025.bound_coefficients(1.0, 1e-2, 0.1, 0.1)
    L, S_new, R = li2025.gain_and_bound(S, X_hat, G, coefs, 1.0, XI_STAR, V)
    K = S @ G.T @ np.linalg.inv(G @ S @ G.T + V * np.eye(2))
    assert np.allclose(L, K, rtol=1e-12) and np.allclose(R, V * np.eye(2), rtol=0, atol=1e-15)
    assert np.allclose(S_new, (np.eye(NX) - K @ G) @ S, rtol=1e-11, atol=1e-13)


def test_the_gain_28_minimises_the_trace_of_the_bound_18() -> None:
    """At psi_check = 0.5 any perturbation of L raises tr(c0 M S M^T + L R L^T)."""
    rng = np.random.default_rng(4)
    a = rng.standard_normal((NX, NX))
    S = a @ a.T + np.eye(NX)
    xp = rng.standard_normal(NX)
    G = CH[SETS[1]]
    coefs = li2025.bound_coefficients(0.5, 1e-2, 0.1, 0.1)
    L, S_new, R = li2025.gain_and_bound(S[None], np.outer(xp, xp)[None], G, coefs, 1.0, XI_STAR, V)

    def trace(Lm):
        Mm = np.eye(NX) - Lm @ G
        return np.trace(coefs[0] * Mm @ S @ Mm.T + Lm @ R[0] @ Lm.T)

    assert trace(L[0]) == pytest.approx(np.trace(S_new[0]), rel=1e-12)
    for _ in range(20):
        assert trace(L[0] + 1e-3 * rng.standard_normal(L[0].shape)) > trace(L[0])


def test_bound_for_gain_is_18_term_by_term_and_equals_the_bound_at_the_gain_28() -> None:
    """bound_for_gain at (28) is gain_and_bound's S(k|k); at other gains it is (18) as printed."""
    rng = np.random.default_rng(7)
    a, b = rng.standard_normal((NX, NX)), rng.standard_normal((NX, NX))
    S, X = a @ a.T + np.eye(NX), b @ b.T
    G = CH[SETS[1]]
    for variant in ("corrected", "paper"):
        coefs = li2025.bound_coefficients(0.5, 0.2, 0.3, 0.1, variant)
        L, S_new, _ = li2025.gain_and_bound(S[None], X[None], G, coefs, 2.0, XI_STAR, V)
        np.testing.assert_allclose(li2025.bound_for_gain(S, X, G, L[0], coefs, 2.0, XI_STAR, V),
                                   S_new[0], rtol=1e-12, atol=1e-12)
        Lm = rng.standard_normal(L[0].shape)  # any gain: the printed terms of (18), one by one
        c0, kx, kxi, kv = coefs
        Mm, LG = np.eye(NX) - Lm @ G, Lm @ G
        expected = (c0 * Mm @ S @ Mm.T + 3.0 * kx * LG @ S @ LG.T + 1.5 * kx * LG @ X @ LG.T
                    + (kxi * XI_STAR + kv * V) * Lm @ Lm.T)
        np.testing.assert_allclose(li2025.bound_for_gain(S, X, G, Lm, coefs, 2.0, XI_STAR, V),
                                   expected, rtol=1e-12, atol=1e-12)
    with pytest.raises(ValidationError, match="must match S_pred"):
        li2025.bound_for_gain(S, X, G, np.zeros((NX, NX)), coefs, 2.0, XI_STAR, V)


def test_an_exploding_candidate_gets_a_nan_gain_not_an_error() -> None:
    S = np.stack([np.eye(NX), 1e20 * np.eye(NX)])
    L, _, _ = li2025.gain_and_bound(S, np.zeros((2, NX, NX)), CH[SETS[0]],
                                    li2025.bound_coefficients(0.7, 1e-2, 0.1, 0.1), 1.0, XI_STAR, V)
    assert np.all(np.isfinite(L[0])) and np.all(np.isnan(L[1]))


def test_predicted_bound_17_and_its_coupling_factor() -> None:
    """Target 3 (K_3 = {1, 2}): the coupling term is multiplied by |K_3| = 2 with k_factor."""
    S = [np.eye(NX) * s for s in (1.0, 2.0, 3.0)]
    ah, ewe, lam = AH_ALL[4], EWE_ALL[4], 1e-2
    bh = [BH[(2, 0)], BH[(2, 1)]]
    own = (1 + lam) * ah @ S[2] @ ah.T + ewe
    coupling = (1 + 1 / lam) * sum(b @ s @ b.T for b, s in zip(bh, S[:2], strict=True))
    with_factor = li2025.predicted_bound(S[2], S[:2], ah, bh, lam, ewe)
    without = li2025.predicted_bound(S[2], S[:2], ah, bh, lam, ewe, k_factor=False)
    assert np.allclose(with_factor, li2025.sym(own + 2 * coupling), rtol=1e-13)
    assert np.allclose(without, li2025.sym(own + coupling), rtol=1e-13)
    alone = li2025.predicted_bound(S[0], [], ah, [], 0.0, ewe)  # lambda unused without parents
    assert np.allclose(alone, li2025.sym(ah @ ah.T + ewe), rtol=1e-13)


def test_prediction_7_and_update_8_of_target_3() -> None:
    rng = np.random.default_rng(5)
    xh = rng.standard_normal((6, N, NX))
    ah, bh = AH_ALL[3], [BH[(2, 0)], BH[(2, 1)]]
    xp = li2025.predict(xh[:, 2], [xh[:, 0], xh[:, 1]], ah, bh)
    assert np.allclose(xp, xh[:, 2] @ ah.T + xh[:, 0] @ bh[0].T + xh[:, 1] @ bh[1].T, rtol=1e-14)
    G, L, y = CH[SETS[3]], rng.standard_normal((6, NX, 2)), rng.standard_normal((6, 2))
    for c in (1.0, 0.3):
        want = xp + np.einsum("frc,fc->fr", L, y - c * xp @ G.T)
        assert np.allclose(li2025.correct(xp, y, G, L, c), want, rtol=1e-14)
    assert np.array_equal(li2025.correct(xp, y, G, np.zeros_like(L)), xp)


def _theorem3_example_constants(x2: float = 1000.0) -> dict[str, float]:
    """Assumption-1 constants of the Section IV example (target 3), as the notebook computes them."""
    a, e = li2025.turn_model(100)
    aat = np.linalg.eigvalsh(a[:100] @ np.swapaxes(a[:100], -1, -2))
    ee = np.linalg.eigvalsh(e[:100, :, None] * e[:100, None, :])
    bsum = li2025.EXAMPLE_B[(2, 0)] + li2025.EXAMPLE_B[(2, 1)]
    bb = np.linalg.eigvalsh(bsum @ bsum.T)
    return {"a_lo2": aat.min(), "a_hi2": aat.max(), "h_lo": 0.05, "h_hi": 1.0, "c_lo2": 1.0,
            "c_hi2": 1.0, "e_lo2": 0.0, "e_hi2": ee.max(), "b_lo2": max(bb.min(), 0.0),
            "b_hi2": bb.max(), "q_lo": 0.03, "q_hi": 0.03, "r_lo": 0.03, "r_hi": 0.03,
            "wp": 0.05**2, "x2": x2, "xi_star": 0.3}


def test_theorem3_floor_bounds_eta_upper_for_every_weight_set_with_nonnegative_kappa_x() -> None:
    """theorem3_c_floor is a lower bound of eta^*/phi^* (a proof): check it on random weights."""
    const = _theorem3_example_constants()
    floor = li2025.theorem3_c_floor(const)
    assert floor == pytest.approx((1 - 1 / (4 * (1 - 0.05**2))) * const["a_hi2"], rel=1e-12)
    rng = np.random.default_rng(3)
    w = 10 ** rng.uniform(-6, 6, size=(5, 20000))
    phi_lo, phi_hi = 10 ** rng.uniform(-12, 0, 20000), 10 ** rng.uniform(0, 12, 20000)
    for variant in ("paper", "corrected"):
        r = li2025.theorem3_eta(phi_lo, phi_hi, 0.3, list(w), const, variant)
        keep = (r["kappa_x"] >= 0) & (r["c0"] >= 1)
        assert keep.sum() > 1000
        assert np.all(r["eta_hi"][keep] / phi_hi[keep] >= floor * (1 - 1e-12))


def test_theorem3_refuses_bad_constants_and_weights() -> None:
    const = _theorem3_example_constants()
    with pytest.raises(ValidationError, match="missing"):
        li2025.theorem3_eta(1.0, 1.0, 0.3, [1.0] * 5, {"a_lo2": 1.0})
    with pytest.raises(ValidationError, match="weights"):
        li2025.theorem3_eta(1.0, 1.0, 0.3, [1.0, -1.0, 1.0, 1.0, 1.0], const)
    with pytest.raises(ValidationError, match="xi"):
        li2025.theorem3_c_floor(const | {"xi_star": 2.0})


def test_bad_input_is_refused_with_the_argument_named() -> None:
    with pytest.raises(ValidationError, match="variant must be one of"):
        li2025.bound_coefficients(0.5, 0.1, 0.1, 0.1, "printed")
    with pytest.raises(ValidationError, match="S_parents and bh_list"):
        li2025.predicted_bound(np.eye(2), [np.eye(2)], np.eye(2), [], 0.1, np.eye(2))
    with pytest.raises(ValidationError, match="xh_parents and bh_list"):
        li2025.predict(np.zeros(2), [], np.eye(2), [np.eye(2)])
    coefs = li2025.bound_coefficients(0.5, 0.1, 0.1, 0.1)
    with pytest.raises(ValidationError, match="G must have one column per state of S_pred"):
        li2025.gain_and_bound(np.eye(3), np.eye(3), np.ones((1, 2)), coefs, 1.0, 0.1, 0.1)
    with pytest.raises(ValidationError, match="coefs must be"):
        li2025.gain_and_bound(np.eye(2), np.eye(2), np.ones((1, 2)), coefs[:3], 1.0, 0.1, 0.1)
    args = (np.zeros((2, 3, 1, 1)), np.zeros((3, 1), int), np.eye(2), np.eye(2), np.ones((1, 2)),
            np.zeros((2, 1, 2)), np.eye(2), [(1e-3, 1, 1, 1, 1)], 1.0, 0.0, 1.0)
    for name, bad in (("update", "hold"), ("moment", "mean"), ("variant", "x")):
        with pytest.raises(ValidationError, match=f"{name} must be one of"):
            li2025.estimate(*args, **{name: bad})
    with pytest.raises(ValidationError, match="Incompatible dimensions of AH"):
        li2025.estimate(*args[:2], np.eye(3), *args[3:])
    with pytest.raises(ValidationError, match="Incompatible dimensions of y"):
        li2025.estimate(np.zeros((2, 3, 1)), *args[1:])
    with pytest.raises(ValidationError, match="x0, sched and weights must match y"):
        li2025.estimate(*args[:5], np.zeros((2, 2, 2)), *args[6:])
    with pytest.raises(ValidationError, match="Incompatible dimensions of gains"):
        li2025.estimate(*args, gains=np.zeros((3, 1, 2, 1)))
    with pytest.raises(ValidationError, match="psi_bar must be finite"):
        li2025.estimate(*args[:8], np.nan, *args[9:])


# ------------------------------------------------------------------------------------ the arena
def _kalman(sc, y):
    """Centralised Kalman filter predicting from the prior, first update at k = 1 (Algorithm 1)."""
    C = sc.C.reshape(-1, sc.plant.n)
    R = np.diag(np.concatenate([np.diag(r) for r in sc.R]))
    A, Q = sc.plant.A, sc.plant.Q
    runs, K1 = y.shape[:2]
    x, P = np.zeros((runs, sc.plant.n)), sc.plant.x0_std**2 * np.eye(sc.plant.n)
    out = np.zeros((runs, K1, sc.plant.n))
    for k in range(1, K1):
        x, P = x @ A.T, A @ P @ A.T + Q
        K = P @ C.T @ np.linalg.inv(C @ P @ C.T + R)
        x = x + (y[:, k].reshape(runs, -1) - x @ C.T) @ K.T
        P = (np.eye(len(P)) - K @ C) @ P
        out[:, k] = x
    return out


def test_without_attack_on_a_complete_graph_it_is_the_centralised_kalman_filter() -> None:
    """psi_check = 1 and lambda -> 0: (17)-(18)-(28) is the Kalman recursion (notebook C6)."""
    sc = scenarios.scenario("inertia5", "none", runs=3, horizon=40)
    sc = replace(sc, network=replace(sc.network, edges=graphs.complete_edges(5)))
    t = scenarios.simulate(sc)
    est = arena_li2025.Li2025(weights=(1e-300, 1.0, 1e-2, 0.1, 0.1)).run(t)
    ref = _kalman(sc, t.y)
    assert np.abs(est.xhat - ref[:, :, None]).max() <= 1e-8 * np.abs(ref).max()


def test_runs_whose_links_never_fail_are_those_of_the_scenario_without_dos() -> None:
    dos = scenarios.simulate(scenarios.scenario("tank12", "dos", runs=6, horizon=60))
    none = scenarios.simulate(scenarios.scenario("tank12", "none", runs=6, horizon=60))
    a, b = METHODS["li2025"].run(dos).xhat, METHODS["li2025"].run(none).xhat
    intact = np.all(dos.link == 1, axis=1)
    assert np.array_equal(a[intact], b[intact])
    assert not intact.all() and not np.allclose(a[~intact], b[~intact])


@pytest.mark.parametrize("attack", ["none", "replacement", "dos"])
def test_the_method_runs_on_a_small_scenario(attack: str) -> None:
    sc = scenarios.scenario("inertia5", attack, runs=4, horizon=50)
    method = METHODS["li2025"]
    assert method.kind == "paper" and method.not_applicable(sc) is None
    est = method.run(scenarios.simulate(sc))
    assert est.xhat.shape == (4, 51, 5, 6) and np.all(np.isfinite(est.xhat))
    assert est.alarms is None and est.bound.shape == (4, 51, 5, 6, 6)
    assert np.all(np.linalg.eigvalsh(est.bound) > 0)


def test_the_attacked_packet_gets_the_paper_coefficients() -> None:
    """psi_check = 0.7 (card): c0, kappa_x, kappa_xi of the corrected bound at the arena weights."""
    lam, a1, a2, a3, a4 = arena_li2025.ARENA_WEIGHTS
    c0, kx, kxi, kv = li2025.bound_coefficients(0.7, a2, a3, a4)
    assert (c0, kx, kxi, kv) == pytest.approx((1.033, 3.33, 33.3, 0.7))
    assert li2025.bound_coefficients(1.0, a2, a3, a4) == (1.0, 0.0, 0.0, 1.0)


def test_outside_the_replacement_model_and_without_local_observability_it_runs_marked() -> None:
    attack = ("every attack on the measurement packets is the Bernoulli replacement (6) of a bounded "
              "value with known psi_check, xi* (or none)")
    for kind in ("bias", "message"):
        sc = scenarios.scenario("inertia5", kind, runs=2)
        assert METHODS["li2025"].outside_theory(sc) == [attack]
        assert METHODS["li2025"].not_applicable(sc) is None  # it still runs: one rule for all
    sc = scenarios.scenario("inertia5", "none", runs=2)
    diffs = replace(sc, network=replace(sc.network, measures=np.array([[3], [4], [3], [4], [3]])))
    marks = METHODS["li2025"].outside_theory(diffs)
    assert len(marks) == 1 and marks[0].startswith("(A, C) is observable from every node's closed")


def test_the_arena_method_refuses_bad_options_with_the_argument_named() -> None:
    with pytest.raises(ValidationError, match="weights must be 5 positive numbers"):
        arena_li2025.Li2025(weights=(1.0, 1.0))
    with pytest.raises(ValidationError, match="variant must be one of"):
        arena_li2025.Li2025(variant="x")


# ------------------------------------------------------------------ Theorem 2 and Theorem 3 helpers
def _small_instance(psi: float, horizon: int = 30):
    """One subsystem (no parents), n = 2, C = I, m = 1 of n_y = 2: the data of exact_design_moments."""
    ah = 0.6 * np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]]) @ np.diag([1, 0.05])
    sched = schedules.rrl_map_sets(np.arange(1, horizon + 1), 1, 2)
    k = np.arange(horizon + 1)[:, None]
    xi = np.sqrt(0.3) * np.hstack([np.sin(k), np.cos(k)])
    return dict(AH=ah, BH={}, parents={0: ()}, EWE=0.03 * np.eye(2), CH=np.diag([1, 0.05]),
                sched=sched, psi_bar=[psi], xi=xi, xi_star=0.3, V=0.03, mean0=np.ones(2),
                cov0=np.eye(2), S0=np.eye(2))


def test_exact_design_moments_is_the_kalman_filter_without_attack() -> None:
    """psi = 1, lambda = 0 (no parents), corrected: (17)-(18)-(28) are the Riccati recursion, S = P."""
    rec = li2025.exact_design_moments(**_small_instance(1.0), weights=[(0.0, 1.0, 1.0, 1.0, 1.0)],
                                      variant="corrected")
    np.testing.assert_allclose(rec["S"], rec["P"], atol=1e-12)
    assert np.all(np.linalg.eigvalsh(rec["P"][1:]) > 0)


def test_exact_design_moments_with_zero_gain_is_the_open_loop_prediction() -> None:
    """zero_gain: the update (8) with L = 0, so E{e e^T} is the prediction's A P A^T + E W E^T."""
    data = _small_instance(0.5)
    w = [(0.1, 1.0, 1.0, 1.0, 1.0)]
    rec0 = li2025.exact_design_moments(**data, weights=w, zero_gain=True)
    rec = li2025.exact_design_moments(**data, weights=w)
    ah, p = data["AH"], data["cov0"].copy()  # x_hat(0|0) = mean0: e(0) ~ N(0, cov0)
    for k in range(1, 31):
        p = ah @ p @ ah.T + data["EWE"]
        np.testing.assert_allclose(rec0["P"][k, 0], p, rtol=1e-10, atol=1e-14)
    # the gain (28) is used in the other run and lowers the error; L records (28) in both
    assert np.abs(rec["L"][1:]).max() > 0 and np.abs(rec0["L"][1:]).max() > 0
    assert np.trace(rec["P"][-1, 0]) < np.trace(rec0["P"][-1, 0])


def test_theorem3_candidates_are_the_declared_log_uniform_sobol_sets() -> None:
    box = [[-6.0, 3.0]] + [[-6.0, 6.0]] * 4
    cand = li2025.theorem3_candidates(64, box)
    assert cand.shape == (64, 5)
    logs = np.log10(cand)
    assert np.all(logs >= np.array(box)[:, 0]) and np.all(logs <= np.array(box)[:, 1])
    np.testing.assert_array_equal(cand, li2025.theorem3_candidates(64, box))  # seeded, one generator
    with pytest.raises(ValidationError, match="power of 2"):
        li2025.theorem3_candidates(100, box)
    with pytest.raises(ValidationError, match="log10_box"):
        li2025.theorem3_candidates(64, box[:4])


def test_exact_design_moments_refuses_bad_dimensions() -> None:
    data = _small_instance(0.5)
    data["cov0"] = np.eye(3)
    with pytest.raises(ValidationError, match="Incompatible dimensions"):
        li2025.exact_design_moments(**data, weights=[(0.1, 1.0, 1.0, 1.0, 1.0)])


def test_theorem2_check_corrected_coefficients_have_no_saddle() -> None:
    """Corrected c0, kappa_x > 0 for every positive weight set: Pi > 0, (28) minimises (18)."""
    data = _small_instance(0.5)
    w = [(0.1, 1.0, 9.5, 10.0, 0.01)]  # printed kappa_x < 0 at psi = 0.5, corrected > 0
    rec = li2025.exact_design_moments(**data, weights=w, variant="corrected")
    G = [data["CH"][s] for s in data["sched"]]
    r = li2025.theorem2_check(rec["Sp"], rec["Xh"], G, [0.5], w, 0.3, 0.03, "corrected", n_random=4)
    assert r["steps_with_pi_indefinite"] == 0 and r["min_eig_pi_relative"] > 0
    assert r["min_relative_change"] >= -1e-10 and r["max_relative_first_order"] <= 1e-10
    assert r["min_eig_S_at_indefinite_pi"] is None and r["steps"] == len(G)
    printed = li2025.theorem2_check(rec["Sp"], rec["Xh"], G, [0.5], w, 0.3, 0.03, "paper", n_random=4)
    assert printed["kappa_x_per_target"][0] < 0
    assert (printed["min_eig_pi"] >= 0) is (printed["min_relative_change"] >= -1e-10)
    with pytest.raises(ValidationError, match="T = len"):
        li2025.theorem2_check(rec["Sp"][:-1], rec["Xh"], G, [0.5], w, 0.3, 0.03)


def test_theorem3_proof_envelope_uses_the_best_alpha5_to_alpha7() -> None:
    """mu of (55) at the closed-form alpha_5..7 is the minimum over a grid of admissible ones."""
    const = {"a_lo2": 0.36, "a_hi2": 0.36, "h_lo": 0.05, "h_hi": 1.0, "c_lo2": 1.0, "c_hi2": 1.0,
             "e_lo2": 1.0, "e_hi2": 1.0, "b_lo2": 0.04, "b_hi2": 0.04, "q_lo": 0.03, "q_hi": 0.03,
             "r_lo": 0.03, "r_hi": 0.03, "wp": 0.0025, "x2": 3.0, "xi_star": 0.3}
    w = (0.2, 100.0, 0.05, 0.01, 5.0)  # printed c0 = 1 + 0.04 (1 - 0.5) > 1
    env = li2025.theorem3_proof_envelope(1e-3, 2.0, 0.5, w, const, 2.0, 20, 2, 2)
    c0 = li2025.bound_coefficients(0.5, 0.05, 0.01, 5.0, "paper")[0]
    a5 = np.linspace(1e-4, c0 - 1 - 1e-4, 201)[:, None]
    a7 = np.logspace(-4, 4, 401)[None, :]
    grid = ((1 + 1 / a5 + a7) * env["mu1"] + (1 + 1 / (c0 - 1 - a5) + 1 / a7) * env["mu2"]).min()
    assert env["mu"] <= grid * (1 + 1e-12) and env["mu"] >= grid * (1 - 1e-3)
    assert env["UB"][0] == pytest.approx(2.0 / 1e-3 * 2.0) and np.all(np.diff(env["UB"][3:]) != 0)
    assert 0 < env["rho"] <= 1 and env["t_bar"] > 0 > env["t_bar_printed"]
    low_c0 = li2025.theorem3_proof_envelope(1e-3, 2.0, 0.5, (0.2, 1.0, 0.01, 0.05, 5.0), const,
                                            2.0, 20, 2, 2)
    assert np.isnan(low_c0["mu"]) and np.all(np.isnan(low_c0["UB"]))
    with pytest.raises(ValidationError, match="phi_lo"):
        li2025.theorem3_proof_envelope(0.0, 2.0, 0.5, w, const, 2.0, 20, 2, 2)
