"""ma2021 in the arena (secest.methods.ma2021): equivalence with the notebook, the arena method.

The notebook's own objects are taken by name with ``benchmarks/harness.py``'s
``notebook_definitions``: only the statements defining them (and what those read) run, no text
marker. The Taylor scales are passed as the notebook's parameters ``L_scale`` and ``aleph_scale``
(so its rule choosing them, which runs the estimators, is not executed); the names and calls used
here exist in the notebook both before and after its reviewer-grade restructuring.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import bench_harness

import secest.arena.papers  # noqa: F401  (registers the methods)
from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.arena.papers import ma2021 as arena_ma2021
from secest.core import covariance, montecarlo
from secest.core.validation import ValidationError
from secest.methods import ma2021 as my

notebook_definitions = bench_harness().notebook_definitions

pytest.importorskip("cvxpy")

STEPS_NB = 4  # steps of the paper's example run by the equivalence test
S_TAYLOR = 0.15  # L_i = aleph_i = 0.15 I, the notebook's rule value

NOTEBOOK_NAMES = (
    "B_mat", "E_mat", "N", "NPHI", "NU", "NV", "NX", "NY", "P0", "Q0", "THETA", "U_inv", "V_inv",
    "PROBLEMS", "W0", "alpha_bar", "alpha_sequence", "build_op2_problem", "chi", "e1", "e3", "eps_lmi", "f",
    "g", "jac_f", "jac_g", "lam2_max", "mu_noise", "phi", "r_bound", "seed", "shared_multipliers",
    "simulate", "v_noise", "varpi_form", "x0", "xhat0",
)


@pytest.fixture(scope="module")
def nb():
    """The notebook's functions and example values, by name (fast mode, no figures, nothing run)."""
    ns = notebook_definitions("ma2021", *NOTEBOOK_NAMES, mode="fast", figures=False,
                              L_scale=S_TAYLOR, aleph_scale=S_TAYLOR)
    # The notebook caches its OP1/OP2 problems (PROBLEMS) and the statement defining its Taylor
    # scale runs the estimators once, filling that cache. A re-solved cached problem differs from
    # a freshly built one at the solver's tolerance (~1e-7: cvxpy maps parameters through another
    # path after the first solve, the notebook's X5 "DPP gap"), so the reference is rebuilt fresh,
    # like the problems the secest side builds.
    ns["PROBLEMS"].clear()
    rng = montecarlo.spawn_rngs(ns["seed"], 1)[0]
    ns["_alpha"] = ns["alpha_sequence"](rng, STEPS_NB, ns["alpha_bar"])
    return ns


def _algorithm1(ns, estimator):
    """The notebook's `simulate` (Algorithm 1) rebuilt from secest.methods.ma2021's functions."""
    theta, N, alpha = ns["THETA"], ns["N"], ns["_alpha"]
    dims = my.Dims(ns["NX"], ns["NY"], ns["NV"], ns["NU"], ns["NPHI"])
    nn = estimator == "nn"
    sp = my.build_op2(theta, dims, nn=nn, alpha_bar=ns["alpha_bar"], e3=ns["e3"], eps=ns["eps_lmi"],
                      shared=ns["shared_multipliers"], r_bound=ns["r_bound"])
    op1 = my.build_op1(theta, dims, e1=ns["e1"], eps=ns["eps_lmi"], lam2_box=ns["lam2_max"])
    links = my.links(theta)
    f, g, jac_f, jac_g, E_mat = ns["f"], ns["g"], ns["jac_f"], ns["jac_g"], ns["E_mat"]
    x = np.zeros((alpha.size + 1, dims.nx))
    x[0] = ns["x0"]
    for k in range(alpha.size):
        x[k + 1] = f(x[k]) + ns["B_mat"](k) @ ns["v_noise"](k)
    xh = np.zeros((alpha.size + 1, N, dims.nx))
    xh[0] = ns["xhat0"]
    P = np.asarray(ns["P0"], float)
    Ps = [P]
    What = {lk: np.asarray(ns["W0"], float).copy() for lk in links}
    Q = {lk: np.asarray(ns["Q0"], float).copy() for lk in links}
    for i in range(N):
        sp.params["L"][i].value = S_TAYLOR * np.eye(dims.nx)
        sp.params["aleph"][i].value = S_TAYLOR * np.eye(dims.ny, dims.nx)
    sp.params["Vinv"].value, sp.params["Uinv"].value = ns["V_inv"], ns["U_inv"]
    lam = []
    for k in range(alpha.size):
        S = np.linalg.cholesky(covariance.symmetrize(P))
        z = np.array([g(i, x[k]) + E_mat(i, k) @ ns["mu_noise"](k) - g(i, xh[k, i]) for i in range(N)])
        z_recv = np.array([z[j] + alpha[k] * ns["chi"](z[j]) for j in range(N)])
        ph = ns["phi"](z)
        Mbar = {lk: my.mbar(Q[lk], dims.nphi) for lk in links}
        my.set_op2_parameters(sp, S=S, xhat=xh[k], fhat=[f(xh[k, i]) for i in range(N)],
                              Phi=[jac_f(xh[k, i]) for i in range(N)],
                              Psi=[jac_g(i, xh[k, i]) for i in range(N)],
                              E=[E_mat(i, k) for i in range(N)], B=ns["B_mat"](k),
                              W_hat=What, phi=ph, Mbar=Mbar)
        my.solve(sp, k, "OP2")
        F = np.stack([v.value for v in sp.vars["F"]])
        G = np.stack([v.value for v in sp.vars["G"]])
        H = np.zeros((N, N, dims.nx, dims.ny))
        for lk in links:
            H[lk] = sp.vars["H"][lk].value
        W_arr = np.zeros((N, N, dims.ny, dims.nphi))
        for lk in links:
            W_arr[lk] = What[lk]
        recv = np.broadcast_to(z_recv[None], (N, N, dims.ny))
        xh[k + 1] = my.estimator_update(F, G, H, xh[k], z, recv, theta, W_hat=W_arr if nn else None,
                                        phi_own=ph, alpha_bar=ns["alpha_bar"])
        P = covariance.symmetrize(np.asarray(sp.vars["P"].value))
        Ps.append(P)
        if not nn:
            continue
        z1 = np.array([g(i, x[k + 1]) + E_mat(i, k + 1) @ ns["mu_noise"](k + 1) - g(i, xh[k + 1, i])
                       for i in range(N)])
        Hd = {lk: sp.vars["H"][lk].value for lk in links}
        vp = my.varpi(Hd, [jac_g(i, xh[k + 1, i]) for i in range(N)], z1, theta, ns["alpha_bar"],
                      ns["varpi_form"])
        my.set_op1_parameters(op1, vp, ph, Mbar)
        my.solve(op1, k, "OP1", chordal=False)
        step = []
        for lk in links:
            l1, l2 = float(op1.vars[lk]["l1"].value), float(op1.vars[lk]["l2"].value)
            What[lk] = my.weight_update(What[lk], l1, l2, vp[lk], ph[lk[0]])
            Q[lk] = covariance.symmetrize(op1.vars[lk]["Q"].value)
            step.append((l1, l2))
        lam.append(step)
    return {"xh": xh, "P": np.array(Ps), "lam": np.array(lam)}


@pytest.mark.parametrize("estimator", ["nn", "conv"])
def test_algorithm1_equals_the_notebook_on_the_paper_example(nb, estimator) -> None:
    ref = nb["simulate"](alpha=nb["_alpha"], estimator=estimator)  # at L_scale = aleph_scale = S_TAYLOR
    mine = _algorithm1(nb, estimator)
    assert not ref["failures"]
    pairs = [("xh", ref["xh"]), ("P", ref["P"])]
    if estimator == "nn":
        pairs.append(("lam", ref["lam"]))
    for key, want in pairs:
        scale = max(np.abs(want).max(), 1.0)
        assert np.abs(mine[key] - want).max() <= 1e-10 * scale, key


def test_op2_builder_options_give_the_notebook_problem_data(nb) -> None:
    """Printed shared multipliers, one r-bound per link and OP3: the same canonical problem."""
    opts = dict(alpha_bar=0.67, e3=3.0, eps=1e-6)
    theirs = nb["build_op2_problem"](nn=True, alpha_bar_=0.67, e3_=3.0, eps=1e-6, shared=True,
                                     r_bound_="per_link", design="op3").problem
    mine = my.build_op2(nb["THETA"], my.Dims(2, 2, 1, 1, 2), nn=True, shared=True, r_bound="per_link",
                        design="op3", **opts).problem
    rng = np.random.default_rng(0)
    values = {}
    for q in theirs.parameters():
        v = rng.standard_normal(q.shape)
        values[q.name()] = v + v.T if q.is_symmetric() and v.ndim == 2 else v
    for prob in (theirs, mine):
        for q in prob.parameters():
            q.value = values[q.name()]
    data = [prob.get_problem_data("CLARABEL")[0] for prob in (theirs, mine)]
    for key in ("A", "b", "c"):
        a, b = (d[key].toarray() if hasattr(d[key], "toarray") else d[key] for d in data)
        assert np.array_equal(a, b), key


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


def test_sensor_attacks_are_outside_assumption_1() -> None:
    for attack in ("bias", "replacement"):
        reason = METHODS["ma2021"].not_applicable(_small(attack))
        assert reason is not None and reason.startswith("Assumption 1 (2)")
    with pytest.raises(ValidationError, match="not applicable"):
        METHODS["ma2021"].run(scenarios.simulate(_small("bias")))


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
    net = replace(sc.network, adj=ring, measures=np.array([[0], [1], [1]]))
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
