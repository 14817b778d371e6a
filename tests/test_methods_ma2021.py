"""secest.methods.ma2021 on the paper's example (Section IV), and the arena method.

The example's data (the reconstructed f, g_i, E_i, x_0, ...) are the defaults of
``notebooks/ma2021.toml``; the values compared with are the committed ``figures/ma2021`` data of
the notebook's paper-mode run, within the tolerance they declare (LMI_ITERATES).
"""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import numpy as np
import pytest

from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.arena.papers import ma2021 as arena_ma2021
from secest.core import graphs, montecarlo
from secest.core.tolerances import LMI_ITERATES
from secest.core.validation import ValidationError
from secest.methods import ma2021 as my
from secest.repro import results, spaces

pytest.importorskip("cvxpy")

FIGS = results.repo_root() / "figures" / "ma2021"
THETA = np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], dtype=float)
DIMS = my.Dims(2, 2, 1, 1, 2)
_FN = {"x": (lambda u: u, lambda u: np.ones_like(u)), "sin": (np.sin, np.cos),
       "cos": (np.cos, lambda u: -np.sin(u))}


def _terms(terms, x):
    return np.array([sum(c * _FN[fn][0](w * x[v - 1] + b) for c, fn, v, w, b in row)
                     for row in terms])


def _jac(terms, x):
    J = np.zeros((len(terms), 2))
    for r, row in enumerate(terms):
        for c, fn, v, w, b in row:
            J[r, v - 1] += c * w * _FN[fn][1](w * x[v - 1] + b)
    return J


def _example():
    """The paper's example as read (the notebook's defaults): model, data and run settings."""
    d = {name: par.default for name, par in spaces.load("ma2021").parameters.items()}
    gt = [d["g1_terms"], d["g2_terms"], d["g3_terms"]]

    def E(i, k):
        return [np.array([[0.25], [0.2 + d["E1_amp"] * np.cos(k + 1)]]),
                np.array([[0.2], [0.15 + 0.1 * np.sin(2 * k)]]),
                np.array([[0.25 + d["E3_amp"] * np.sin(k)], [0.15]])][i]

    model = my.Model(f=lambda x: _terms(d["f_terms"], x), jac_f=lambda x: _jac(d["f_terms"], x),
                     g=lambda i, x: _terms(gt[i], x), jac_g=lambda i, x: _jac(gt[i], x),
                     B=lambda k: np.array([[0.1 + 0.01 * np.cos(k + 1)], [0.2 + 0.01 * np.sin(k)]]),
                     E=E, phi=np.tanh)
    T = int(d["T"])
    x = np.zeros((T + 1, 2))
    x[0] = d["x0"]
    for k in range(T):
        x[k + 1] = model.f(x[k]) + model.B(k) @ np.array([0.3 * np.cos(2 * k)])
    y = np.array([[model.g(i, x[k]) + E(i, k) @ np.array([0.4 * np.sin(k)]) for i in range(3)]
                  for k in range(T + 1)])
    alpha = (montecarlo.spawn_rngs(d["seed"], 1)[0].random(T) < d["alpha_bar"]).astype(float)

    def received(k, z):  # (5)
        return np.array([zj + alpha[k] * _chi(zj) for zj in z])

    s = d["L_scale"]
    kw = dict(theta=THETA, dims=DIMS, xhat0=d["xhat0"], P0=d["P0"], W0=d["W0"], Q0=d["Q0"],
              alpha_bar=d["alpha_bar"], e1=d["e1"], e3=d["e3"], L=s * np.eye(2), aleph=s * np.eye(2),
              V_inv=np.eye(1), U_inv=np.eye(1), p=d["p"], eps=d["eps_lmi"], lam2_box=d["lam2_max"],
              tol=d["cert_tol"], varpi_form=d["varpi_form"], r_bound=d["r_bound"],
              shared=d["shared_multipliers"], fallback="SCS")
    return model, x, y, received, kw, alpha


def _chi(z):
    """The injected function chi of the example (4)."""
    return np.array([0.15 * np.sin(z[0]), 0.30 * np.cos(z[1])])


def _csv(stem):
    with (FIGS / f"{stem}.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


@pytest.fixture(scope="module")
def example():
    model, x, y, received, kw, alpha = _example()
    cache = {}
    nn = my.run_algorithm1(model, y, received, nn=True, keep_rows=True, cache=cache, **kw)
    conv = my.run_algorithm1(model, y, received, nn=False, cache=cache, **kw)
    return {"model": model, "x": x, "y": y, "received": received, "kw": kw, "nn": nn,
            "conv": conv, "cache": cache, "alpha": alpha}


def _close(mine, committed, what):
    ok = np.abs(mine - committed) <= LMI_ITERATES.atol + LMI_ITERATES.rtol * np.abs(committed)
    assert ok.all(), f"{what}: largest difference {np.max(np.abs(mine - committed)):.3g}"


@pytest.mark.parametrize(("run", "stems"), [("nn", ("fig1_nn_state1", "fig2_nn_state2")),
                                             ("conv", ("fig5_conv_state1", "fig6_conv_state2"))])
def test_algorithm1_gives_the_committed_estimates_of_the_paper_example(example, run, stems) -> None:
    res = example[run]
    for comp, stem in enumerate(stems):
        data = _csv(stem)
        assert np.allclose(example["x"][:, comp], data["x"], rtol=1e-9, atol=1e-9)  # the plant
        for i in range(3):
            _close(res.xh[:, i, comp], data[f"xhat_node{i + 1}"], f"{stem} node {i + 1}")
    diag = _csv("extra_diagnostics")
    _close(np.trace(res.Bell, axis1=1, axis2=2), diag[f"trB_{run}"], f"tr B_k ({run})")


def test_the_run_has_the_committed_count_of_solves_and_uncertified_steps(example) -> None:
    c5 = json.loads((FIGS / "claims.json").read_text())["C5"]["measured"]
    nn, conv = example["nn"], example["conv"]
    assert len(nn.failures) + len(conv.failures) == c5["uncertified_steps"]
    assert len(nn.reports) + len(conv.reports) + c5["uncertified_steps"] == c5["solves"]
    assert nn.solved.sum() + sum("OP1" not in m for m in nn.failures) == 40


def test_the_record_has_the_documented_shapes_and_identities(example) -> None:
    nn, kw = example["nn"], example["kw"]
    n = 40
    assert nn.xh.shape == (n + 1, 3, 2) and nn.P.shape == (n + 1, 2, 2) and nn.S.shape == (n, 2, 2)
    assert nn.z.shape == nn.z_recv.shape == (n, 3, 2) and nn.lam.shape == (n, 4, 2)
    assert len(nn.W_hat) == len(nn.Q) == n + 1 and len(nn.H) == len(nn.rows) == n
    assert nn.links == my.links(THETA) == [(0, 1), (1, 0), (1, 2), (2, 1)]
    assert np.array_equal(nn.Bell[0], np.asarray(kw["P0"]) / (1 - kw["p"]))  # Lemma 4 (E1, P_k = (1 - p) B_k, read from the OCR)
    assert np.allclose(nn.Bell[1:], nn.P[1:] / (1 - kw["p"]), rtol=1e-15, atol=0)
    assert np.allclose(np.einsum("kab,kcb->kac", nn.S, nn.S), nn.P[:-1], rtol=1e-12, atol=1e-14)
    assert np.all(np.isnan(nn.rho))  # OP2: no rho
    for k in range(n):  # the update (8) of every node, written out, with the gains of the record
        z, recv, ph, W = nn.z[k], nn.z_recv[k], nn.phi[k], nn.W_hat[k]
        want = [nn.F[k][i] @ nn.xh[k, i] + nn.G[k][i] @ z[i]
                + sum(nn.H[k][(i, j)] @ (recv[j] - kw["alpha_bar"] * W[(i, j)] @ ph[i])
                      for j in range(3) if THETA[i, j]) for i in range(3)]
        assert np.allclose(nn.xh[k + 1], want, rtol=1e-13, atol=1e-15)
        assert np.allclose(ph, np.tanh(z), rtol=0, atol=0)


def test_the_weights_follow_the_tuning_law_17(example) -> None:
    nn, model, kw = example["nn"], example["model"], example["kw"]
    for k in range(40):
        xh1 = nn.xh[k + 1]
        z1 = np.array([example["y"][k + 1, i] - model.g(i, xh1[i]) for i in range(3)])
        vp = my.varpi(nn.H[k], [model.jac_g(i, xh1[i]) for i in range(3)], z1, THETA,
                      kw["alpha_bar"])
        for a, lk in enumerate(nn.links):
            l1, l2 = nn.lam[k, a]
            want = l1 * nn.W_hat[k][lk] + l2 * np.outer(vp[lk], nn.phi[k][lk[0]])
            assert np.array_equal(nn.W_hat[k + 1][lk], want)


def test_the_row_blocks_of_54_give_the_next_error_at_the_actual_zeta(example) -> None:
    """(54): x~_(i,k+1) = (Xi_i + alpha~_k Xi~_i) zeta_k with zeta built from the run's own
    remainders, delta_j = chi(z_j) (the ideal weight taken as W = 0) and r = -Mbar^-1 rho(W^)."""
    nn, model, x, kw = example["nn"], example["model"], example["x"], example["kw"]
    s, abar = kw["L"][0, 0], kw["alpha_bar"]
    worst = 0.0
    for k in range(40):
        xt = x[k] - nn.xh[k]
        rem_f = [model.f(x[k]) - model.f(nn.xh[k, i]) - model.jac_f(nn.xh[k, i]) @ xt[i]
                 for i in range(3)]
        rem_g = [model.g(i, x[k]) - model.g(i, nn.xh[k, i]) - model.jac_g(i, nn.xh[k, i]) @ xt[i]
                 for i in range(3)]
        zeta = np.concatenate(
            [[1.0]] + [np.linalg.solve(nn.S[k], xt[i]) for i in range(3)]
            + [r / s for r in rem_f] + [r / s for r in rem_g]
            + [np.array([0.3 * np.cos(2 * k)]), np.array([0.4 * np.sin(k)])]
            + [_chi(zj) for zj in nn.z[k]]
            + [np.linalg.solve(nn.Mbar[k][lk], -nn.W_hat[k][lk].flatten()) for lk in nn.links])
        for i in range(3):
            Xi, Xit = nn.rows[k][i]
            pred = (Xi + (example["alpha"][k] - abar) * Xit) @ zeta
            worst = max(worst, float(np.max(np.abs(pred - (x[k + 1] - nn.xh[k + 1, i])))))
    assert worst <= 1e-10


def test_the_problem_cache_returns_the_same_problems_and_fresh_ones_without_it(example) -> None:
    kw = example["kw"]
    const = dict(nn=True, alpha_bar=kw["alpha_bar"], e1=kw["e1"], e3=kw["e3"], eps=kw["eps"],
                 lam2_box=kw["lam2_box"])
    a = my.step_problems(THETA, DIMS, cache=example["cache"], **const)
    b = my.step_problems(THETA, DIMS, cache=example["cache"], **const)
    c = my.step_problems(THETA, DIMS, **const)
    assert a[0] is b[0] and a[1] is b[1] and c[0] is not a[0]
    assert len(example["cache"]) == 3  # NN OP2, conventional OP2, OP1


def test_op3_keeps_the_fixed_ellipsoid_and_scales_it_by_rho() -> None:
    model, x, y, received, kw, alpha = _example()
    run = my.run_algorithm1(model, y[:4], received, nn=True, design="op3", B_fixed=2 * np.eye(2),
                            **kw)
    assert not run.failures and np.isnan(run.rho[0]) and np.all(run.rho[1:] > 0)
    assert np.allclose(run.P[1:], run.rho[1:, None, None] * 2 * np.eye(2), rtol=1e-12, atol=1e-14)
    assert np.array_equal(run.Bell[1:], np.broadcast_to(2 * np.eye(2), (3, 2, 2)))


def test_op3_with_a_sequence_fixes_each_steps_ellipsoid() -> None:
    """Corollary 3 with B_(k+1) given per step (e.g. the OP2 run's): step k uses B_(k+1)."""
    model, x, y, received, kw, alpha = _example()
    B_seq = np.array([(2.0 + 0.5 * k) * np.eye(2) for k in range(4)])
    run = my.run_algorithm1(model, y[:4], received, nn=True, design="op3", B_fixed=B_seq, **kw)
    assert not run.failures and np.all(run.rho[1:] > 0)
    assert np.allclose(run.P[1:], run.rho[1:, None, None] * B_seq[1:], rtol=1e-12, atol=1e-14)
    assert np.array_equal(run.Bell[1:], B_seq[1:])
    with pytest.raises(ValidationError, match="Incompatible dimensions of B_fixed"):
        my.run_algorithm1(model, y[:4], received, design="op3", B_fixed=B_seq[:3], **kw)


def test_a_step_no_solver_certifies_keeps_the_gains_and_doubles_p(monkeypatch) -> None:
    from secest.core.lmi import InfeasibleLMIError

    model, x, y, received, kw, alpha = _example()
    real = my.solve

    def failing(sp, step, label, **opts):
        if step == 2 and "OP1" not in label:
            raise InfeasibleLMIError(f"not certified at step {step}, {label}", step=step)
        return real(sp, step, label, **opts)

    monkeypatch.setattr(my, "solve", failing)
    run = my.run_algorithm1(model, y[:5], received, nn=False, **kw)
    assert not run.solved[2] and run.solved[[0, 1, 3]].all() and len(run.failures) == 1
    assert np.array_equal(run.P[3], 2 * run.P[2])
    for a, b in ((run.F[2], run.F[1]), (run.G[2], run.G[1])):
        assert all(np.array_equal(u, v) for u, v in zip(a, b, strict=True))


def test_algorithm1_refuses_bad_input_naming_the_argument() -> None:
    model, x, y, received, kw, alpha = _example()
    with pytest.raises(ValidationError, match="Incompatible dimensions of y"):
        my.run_algorithm1(model, y[:, :2], received, **kw)
    with pytest.raises(ValidationError, match="received"):
        my.run_algorithm1(model, y, "not callable", **kw)
    with pytest.raises(ValidationError, match="B_fixed"):
        my.run_algorithm1(model, y, received, design="op3", **kw)
    with pytest.raises(ValidationError, match="varpi_form"):
        my.run_algorithm1(model, y, received, **(kw | {"varpi_form": "nope"}))
    with pytest.raises(ValidationError, match="P0"):
        my.run_algorithm1(model, y[:2], received, **(kw | {"P0": np.eye(3)}))
    with pytest.raises(ValidationError, match="xhat0"):
        my.run_algorithm1(model, y[:2], received, **(kw | {"xhat0": np.zeros((2, 2))}))
    with pytest.raises(ValidationError, match="p must lie in"):
        my.run_algorithm1(model, y[:2], received, **(kw | {"p": 1.0}))
    with pytest.raises(ValidationError, match="Incompatible dimensions of V_inv"):
        my.run_algorithm1(model, y[:2], received, **(kw | {"V_inv": np.eye(2)}))
    with pytest.raises(ValidationError, match="model must be a Model"):
        my.run_algorithm1({"f": None}, y[:2], received, **kw)


# ------------------------------------------------------------------------------- the arena


def _small(attack="none", **kw):
    return scenarios.scenario("inertia5", attack, **({"runs": 4, "horizon": 20} | kw))


def test_runs_on_a_small_scenario_with_finite_estimates_of_the_right_shape() -> None:
    sc = _small()
    t = scenarios.simulate(sc)
    est = METHODS["ma2021"].run(t)
    assert est.xhat.shape == (4, 21, 5, 6) and np.all(np.isfinite(est.xhat))
    assert np.broadcast_to(est.bound, (4, 21, 5, 6, 6)).shape == (4, 21, 5, 6, 6)
    assert np.all(np.isfinite(est.bound)) and est.alarms is None
    assert np.array_equal(est.xhat[:, 0], np.zeros((4, 5, 6)))  # x^_{i,0} = 0
    assert set(est.notes) >= {"tr B_K", "LMI types"} and est.notes["LMI types"] == 5


def test_falsified_or_lost_innovations_do_not_change_the_estimate() -> None:
    """H = 0 is the OP2 optimum: what the neighbours send, or whether it arrives, never enters (8)."""
    out = {a: METHODS["ma2021"].run(scenarios.simulate(_small(a))).xhat for a in ("none", "message", "dos")}
    t = scenarios.simulate(_small("message"))
    assert t.hits.any()
    assert np.array_equal(out["none"], out["message"]) and np.array_equal(out["none"], out["dos"])


def test_sensor_attacks_are_outside_assumption_1_and_still_run() -> None:
    for attack in ("bias", "replacement"):
        marks = METHODS["ma2021"].outside_theory(_small(attack))
        assert len(marks) == 1 and marks[0].startswith("Assumption 1 (2)")
        assert METHODS["ma2021"].not_applicable(_small(attack)) is None
    est = METHODS["ma2021"].run(scenarios.simulate(_small("bias")))
    assert np.all(np.isfinite(est.xhat))


def test_a_step_no_solver_certifies_makes_it_not_applicable_and_is_named(monkeypatch) -> None:
    from secest.core.lmi import InfeasibleLMIError

    real = my.solve

    def failing(sp, step, label, **kw):
        if step == 3:
            raise InfeasibleLMIError(f"LMI infeasible or not certified at step {step}, node {label}",
                                     step=step)
        return real(sp, step, label, **kw)

    monkeypatch.setattr(my, "solve", failing)
    sc = _small(horizon=7)  # a horizon of its own: not in the design cache
    reason = arena_ma2021.Ma2021().not_applicable(sc)
    assert reason is not None and reason.startswith("Theorems 2-3") and "at step 3" in reason
    d = arena_ma2021.Ma2021().design(sc)
    assert np.all(np.isfinite(d.P[:4])) and np.all(np.isnan(d.P[4:])) and np.all(np.isnan(d.G[3:]))


def test_the_reduced_design_is_the_optimum_of_the_full_lmi_with_neighbour_innovations() -> None:
    """One step of (30) with every column (neighbours' s_j, mu_j, weight errors r_ij, the sigma-row,
    F free, arbitrary x^ and phi(z)) has the optimum of the reduced LMI (F = A, H = 0)."""
    import cvxpy as cp

    from secest.core import lmi as slmi

    sc = scenarios.scenario("target20", "message", runs=2, horizon=1)
    ring = np.roll(np.eye(3), 1, axis=1) + np.roll(np.eye(3), -1, axis=1)
    net = replace(sc.network, edges=graphs.edge_list(ring), measures=np.array([[0], [1], [1]]))
    sc = replace(sc, network=net)
    A, C, n, N = sc.plant.A, sc.C, sc.plant.n, 3
    V_half, U_half = arena_ma2021.noise_halves(sc)
    P0 = n * sc.plant.x0_std**2 * np.eye(n)
    S = np.linalg.cholesky(P0)
    rng = np.random.default_rng(1)
    xhat, phi = rng.standard_normal((N, n)), np.tanh(rng.standard_normal(N))
    abar, rho = sc.attack.prob, 2.0  # rho: ||(I (x) phi^T) Mbar|| per unit phi (e1)
    sigma = np.sqrt(abar * (1 - abar))
    P = cp.Variable((n, n), symmetric=True)
    F = [cp.Variable((n, n)) for _ in range(N)]
    G = [cp.Variable((n, 1)) for _ in range(N)]
    H = {(i, j): cp.Variable((n, 1)) for i in range(N) for j in range(N) if ring[i, j]}
    cons = []
    for i in range(N):
        nb = [j for j in range(N) if ring[i, j]]
        cl = [i, *nb]
        b = cp.Variable(2 * len(cl) + len(nb) + 1, nonneg=True)
        Gam = slmi.block_diag([cp.reshape(1 - cp.sum(b), (1, 1), order="F")]
                              + [b[a] * np.eye(n) for a in range(len(cl))] + [b[len(cl)] * np.eye(n)]
                              + [b[len(cl) + 1 + a] * np.eye(1) for a in range(len(cl) + len(nb))])
        c = cp.reshape(A @ xhat[i] - F[i] @ xhat[i], (n, 1), order="F")
        row = [c] + [A @ S - G[i] @ C[i] @ S if j == i else -H[(i, j)] @ C[j] @ S for j in cl]
        row += [V_half] + [-G[i] @ U_half[i] if j == i else -H[(i, j)] @ U_half[j] for j in cl]
        row += [-abar * rho * phi[j] * H[(i, j)] for j in nb]
        rowt = [np.zeros((n, 1 + n * len(cl) + n + len(cl)))] + [-rho * phi[j] * H[(i, j)] for j in nb]
        M = slmi.block_symmetric([[-Gam], [cp.hstack(row), -P], [sigma * cp.hstack(rowt), None, -P]])
        cons.append(slmi.lmi(M, my.EPS_LMI))
    full = cp.Problem(cp.Minimize(cp.trace(P)), cons)
    full.solve(solver="CLARABEL", **my.CLARABEL_OPTS)
    reduced = my.linear_design(A, C, V_half, U_half, P0, 1)
    assert full.status == "optimal" and reduced.failure is None
    assert full.value == pytest.approx(np.trace(reduced.P[1]), rel=1e-5)


def test_the_update_per_edge_is_the_update_per_link() -> None:
    """(8) with every argument per edge (O(E)) against the (N, N) form: random F, G, H, W^,
    theta (a lost link per run) and phi on a directed graph of 5 nodes; measured deviation."""
    rng = np.random.default_rng(3)
    N, n, ny, nphi, runs = 5, 3, 2, 2, 4
    adj = (rng.random((N, N)) < 0.5) & ~np.eye(N, dtype=bool)
    rows, cols = np.nonzero(adj)
    F, G = rng.standard_normal((N, n, n)), rng.standard_normal((N, n, ny))
    H, W = rng.standard_normal((N, N, n, ny)), rng.standard_normal((N, N, ny, nphi))
    xhat, z = rng.standard_normal((runs, N, n)), rng.standard_normal((runs, N, ny))
    z_recv, phi = rng.standard_normal((runs, N, N, ny)), rng.standard_normal((runs, N, nphi))
    theta = adj[None] * (rng.random((runs, 1, 1)) < 0.7)
    dense = my.estimator_update(F, G, H * adj[..., None, None], xhat, z, z_recv, theta, W_hat=W,
                                phi_own=phi, alpha_bar=0.3)
    edge = my.estimator_update(F, G, H[rows, cols], xhat, z, z_recv[:, rows, cols], theta[:, rows, cols],
                               W_hat=W[rows, cols], phi_own=phi, alpha_bar=0.3,
                               edges=np.column_stack([rows, cols]))
    assert np.abs(edge - dense).max() <= 1e-12 * np.abs(dense).max()
    with pytest.raises(ValidationError, match="edges"):
        my.estimator_update(F, G, H[rows, cols], xhat, z, z_recv[:, rows, cols], theta[:, rows, cols],
                            edges=np.column_stack([rows, cols])[1:])


def test_bad_inputs_are_refused_with_the_argument_named() -> None:
    sc = _small()
    V_half, U_half = arena_ma2021.noise_halves(sc)
    P0 = np.eye(6)
    with pytest.raises(ValidationError, match="Incompatible dimensions of C"):
        my.linear_design(sc.plant.A, sc.C[:, :, :5], V_half, U_half, P0, 3)
    with pytest.raises(ValidationError, match="Incompatible dimensions of U_half"):
        my.linear_design(sc.plant.A, sc.C, V_half, U_half[:, :, :0], P0, 3)
    with pytest.raises(ValidationError, match="steps"):
        my.linear_design(sc.plant.A, sc.C, V_half, U_half, P0, 0)
    with pytest.raises(ValidationError, match="theta"):
        my.links(np.eye(3))
    with pytest.raises(ValidationError, match="r_bound"):
        my.build_op2(np.ones((2, 2)) - np.eye(2), my.Dims(2, 2, 1, 1, 2), nn=True, alpha_bar=0.5,
                     e3=1.0, r_bound="nope")
    with pytest.raises(ValidationError, match="form"):
        my.varpi({}, np.zeros((2, 2, 2)), np.zeros((2, 2)), np.ones((2, 2)) - np.eye(2), 0.5, "nope")
    with pytest.raises(ValidationError, match="phi_own"):
        my.estimator_update(np.zeros((2, 2, 2)), np.zeros((2, 2, 1)), np.zeros((2, 2, 2, 1)),
                            np.zeros((2, 2)), np.zeros((2, 1)), np.zeros((2, 2, 1)), np.zeros((2, 2)),
                            W_hat=np.zeros((2, 2, 1, 1)))
    op2 = my.build_op2(np.ones((2, 2)) - np.eye(2), my.Dims(2, 2, 1, 1, 2), nn=False, alpha_bar=0.5,
                       e3=1.0)
    good = dict(S=np.eye(2), xhat=np.zeros((2, 2)), fhat=np.zeros((2, 2)), Phi=np.zeros((2, 2, 2)),
                Psi=np.zeros((2, 2, 2)), E=np.zeros((2, 2, 1)), B=np.zeros((2, 1)))
    with pytest.raises(ValidationError, match=r"Incompatible dimensions of Psi: expected \(2, 2, 2\)"):
        my.set_op2_parameters(op2, **(good | {"Psi": np.zeros((2, 1, 2))}))
    with pytest.raises(ValidationError, match="nphi"):
        my.Dims(2, 2, 1, 1, 0)
    with pytest.raises(ValidationError, match="p must lie in"):
        arena_ma2021.Ma2021(p=1.0)
