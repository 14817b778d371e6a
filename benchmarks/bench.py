"""Benchmark suite of secest (``make bench``): every timing claim, side by side.

Each comparison runs in this one process with alternating repeats (median of at
least five, warm-up excluded; see ``harness.compare``) and asserts first that both
sides computed the same thing, to the tolerance printed in the "agreement check"
column. Missed targets are reported (``met = NO``); a disagreement (or any error) marks its
section FAILED in the table, prints the traceback and makes the exit status 1.
Prints one table and writes ``build/bench.json`` (machine-dependent, not committed).

Usage: ``python benchmarks/bench.py [--only KEY[,KEY]] [--repeats N] [--json PATH]``
with KEY among ding2020, guo2023, li2025, lee2020, ma2021, arena, scaling, sweep, arena-dask, runs.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time
import traceback
from collections.abc import Callable
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from harness import (  # noqa: E402
    Row,
    compare,
    format_table,
    measure,
    not_measured,
)

from secest.repro.results import repo_root  # noqa: E402

ROOT = repo_root()
KEYS = ("ding2020", "guo2023", "lee2020", "li2025", "ma2021")


def _max_rel(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max(1, max |b|)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.abs(a - b).max() / max(1.0, float(np.abs(b).max())))


def _agree_within(name: str, dev: float, tol: float) -> str:
    if not dev <= tol:
        raise AssertionError(f"{name}: deviation {dev:.3g} exceeds the tolerance {tol:g}")
    return f"{name} {dev:.1e} <= {tol:g}"


# ---------------------------------------------------------------------------- ding2020
def bench_ding2020(repeats: int) -> list[Row]:
    """Remark 4 (per node-step cost vs N), vectorised vs per-node, filterpy peer baseline."""
    import networkx as nx
    import scipy.sparse as sp
    from filterpy.kalman import KalmanFilter

    from secest.core import graphs
    from secest.methods import ding2020
    from secest.repro import spaces

    nb = {name: e.value for name, e in spaces.parameter_cell("ding2020").items()}  # notebook defaults
    ex = ding2020.example(nb["m"], nb["T"], nb["gains_low"], nb["gains_high"])  # Sec. V's matrices
    A, BBt, DDt, C_rows = ex.A, ex.B @ ex.B.T, ex.D @ ex.D.T, ex.C
    kappa, threshold, n = nb["kappa"], nb["threshold"], ex.A.shape[0]
    common = dict(A=A, BBt=BBt, DDt=DDt, threshold=threshold, tol=nb["tol"], strict=nb["strict"])
    degree = 4  # bounded degree: random 4-regular graphs

    def network(N: int, *, kappa_: float = kappa, inspect: bool = True) -> dict:
        adj = graphs.check_connected(graphs.adjacency(nx.random_regular_graph(degree, N, seed=N)))
        H = graphs.row_stochastic_weights(adj, self_weight=False)
        rng = np.random.default_rng(N)
        C = C_rows[np.arange(N) % C_rows.shape[0]][:, None, :]
        x_true = rng.standard_normal(n)
        L = rng.standard_normal((N, n, n)) * 0.3
        Pi = nb["pi0_scale"] * np.eye(n) + L @ np.swapaxes(L, -1, -2)  # distinct SPD bounds
        net = dict(adj=adj, H=H, adj_sp=sp.csr_array(adj), H_sp=sp.csr_array(H), C=C,
                   x=rng.standard_normal((N, n)), Pi=Pi, Gam=0.5 * Pi,
                   y=np.einsum("iyn,n->iy", C, x_true) + 0.05 * rng.standard_normal((N, 1)),
                   nbrs=graphs.neighbours(adj), kappa=kappa_, inspect=inspect)
        ding2020.secure_filter_step(net["x"], Pi, net["Gam"], 1, net["y"], C=C, adj=adj, weights=H,
                                   kappa=kappa_, inspect=inspect, validate=True, **common)
        return net

    def vectorised(net: dict) -> Callable[[], tuple]:
        def run() -> tuple:
            st = ding2020.secure_filter_step(
                net["x"], net["Pi"], net["Gam"], 1, net["y"], C=net["C"], adj=net["adj_sp"],
                weights=net["H_sp"], kappa=net["kappa"], inspect=net["inspect"], validate=False,
                **common)
            return st.x_post, st.Pi_post, st.Gamma_post
        return run

    def per_node(net: dict, sweeps: int = 1) -> Callable[[], tuple]:
        x, Pi, Gam, y, C, H = net["x"], net["Pi"], net["Gam"], net["y"], net["C"], net["H"]

        def run() -> tuple:
            for _ in range(sweeps):
                res = [ding2020.secure_filter_node_step(
                    x[i], Pi[i], Gam[i], x[nb_], Pi[nb_], H[i, nb_], 1, y[i], C_i=C[i],
                    kappa=net["kappa"], inspect=net["inspect"], **common)
                    for i, nb_ in enumerate(net["nbrs"])]
            return tuple(np.array([r[q] for r in res]) for q in range(3))
        return run

    def check_against_vectorised(net: dict, out: tuple) -> float:
        ref = vectorised(net)()
        return max(_max_rel(o, r) for o, r in zip(out, ref, strict=True))

    tol = 1e-10
    rows: list[Row] = []
    nets = {N: network(N) for N in (20, 200, 2000)}
    work = 2000  # node-steps per timed call on every N (equal work on both sides)
    for N in (200, 2000):
        def agree(a: tuple, b: tuple, N: int = N) -> str:
            dev = max(check_against_vectorised(nets[20], a), check_against_vectorised(nets[N], b))
            return _agree_within("per-node vs vectorised (x, Pi, Gamma), max rel.", dev, tol)

        rows.append(compare(
            f"ding2020 Remark 4: per-node step, cost per node-step at N = {N} vs N = 20 "
            f"(random {degree}-regular graphs)",
            ("N = 20", per_node(nets[20], sweeps=work // 20)),
            (f"N = {N}", per_node(nets[N], sweeps=work // N)),
            agree, repeats=repeats, per=work, unit="node-step",
            target=("ratio in [0.5, 2]", lambda r: 0.5 <= r <= 2.0)))

    def vec_sweeps(net: dict, sweeps: int) -> Callable[[], tuple]:
        one = vectorised(net)

        def run() -> tuple:
            for _ in range(sweeps):
                out = one()
            return out
        return run

    rows.append(compare(
        "ding2020: vectorised all-nodes step, cost per node-step at N = 2000 vs N = 200 "
        "(scipy.sparse adjacency and weights)",
        ("N = 200", vec_sweeps(nets[200], work // 200)),
        ("N = 2000", vec_sweeps(nets[2000], 1)),
        lambda a, b: _agree_within(
            "vectorised vs per-node (x, Pi, Gamma), max rel.",
            max(max(_max_rel(p, q) for p, q in zip(a, per_node(nets[200])(), strict=True)),
                max(_max_rel(p, q) for p, q in zip(b, per_node(nets[2000])(), strict=True))), tol),
        repeats=repeats, per=work, unit="node-step"))

    net = nets[2000]
    rows.append(compare(
        "ding2020: one filter step of all N = 2000 nodes",
        ("secure_filter_step (vectorised)", vectorised(net)),
        ("loop of secure_filter_node_step", per_node(net)),
        lambda a, b: _agree_within("max rel. |diff| (x, Pi, Gamma)",
                                   max(_max_rel(p, q) for p, q in zip(a, b, strict=True)), tol),
        repeats=repeats, target=(">= 10x", lambda r: r >= 10.0)))

    # peer baseline: kappa = 0, no inspection -> N independent local Kalman filters
    for N in (20, 2000):
        pn = network(N, kappa_=0.0, inspect=False)
        kfs = []
        for i in range(N):
            kf = KalmanFilter(dim_x=n, dim_z=1)
            kf.F, kf.Q, kf.H, kf.R = A, BBt, pn["C"][i], DDt
            kfs.append(kf)
        x0 = [pn["x"][i][:, None] for i in range(N)]

        def peer(kfs: list = kfs, x0: list = x0, pn: dict = pn) -> tuple:
            for kf, xi, Pi_i, yi in zip(kfs, x0, pn["Pi"], pn["y"], strict=True):
                kf.x, kf.P = xi, Pi_i  # same prior every call (predict/update do not mutate)
                kf.predict()
                kf.update(yi)
            return (np.array([kf.x[:, 0] for kf in kfs]), np.array([kf.P for kf in kfs]))

        def agree_peer(a: tuple, b: tuple) -> str:
            dev = max(_max_rel(a[0], b[0]), _max_rel(a[1], b[1]))
            return _agree_within("max rel. |diff| (x, P; filterpy Joseph form)", dev, tol)

        rows.append(compare(
            f"ding2020 peer baseline: kappa = 0, no inspection (N local Kalman filters), N = {N}",
            ("secure_filter_step (vectorised)", vectorised(pn)),
            (f"{N} filterpy KalmanFilter predict+update", peer),
            agree_peer, repeats=repeats, target=(">= 10x", lambda r: r >= 10.0)))
    return rows


# ---------------------------------------------------------------------------- guo2023
def bench_guo2023(repeats: int) -> list[Row]:
    """Per-step time of the distributed estimator of secest.methods.guo2023 on an arena scenario
    (inertia5, a sensor bias: the attacked path runs); exact joint covariance vs Monte Carlo."""
    from secest.arena import scenarios
    from secest.arena.papers.guo2023 import arena_model
    from secest.methods import guo2023

    n_mc, horizon = 500, 200
    sc = scenarios.scenario("inertia5", "bias", runs=2, horizon=horizon)  # a scenario has >= 2 runs
    mdl = arena_model(sc)
    ya1 = scenarios.simulate(sc).y[:1]  # one run
    K1 = ya1.shape[1]
    ref = guo2023.run_estimator(mdl, ya1)

    def steps() -> np.ndarray:
        state = guo2023.initial_state(mdl, ya1[:, 0])
        for k in range(1, K1):
            state, _ = guo2023.estimator_step(mdl, state, ya1[:, k])
        return state.x

    rows = [measure(
        f"guo2023: full {mdl.N}-node estimator (stages A-D), one run, {K1 - 1} steps",
        ("estimator_step", steps),
        lambda x: _agree_within("final estimates vs run_estimator, max |diff|",
                                float(np.abs(x - ref.x[:, -1]).max()), 0.0),
        repeats=repeats, per=K1 - 1, unit="step")]

    def exact() -> tuple:
        run = guo2023.run_estimator(mdl, ya1)  # the gains are data-independent: one run gives them
        return guo2023.error_covariance(mdl, run)[0], run.P

    def monte_carlo() -> tuple:
        trial = scenarios.simulate(scenarios.scenario("inertia5", "bias", runs=n_mc, horizon=horizon))
        run = guo2023.run_estimator(mdl, trial.y, keep_steps=False)
        err = trial.x[:, :, None] - run.x  # (runs, K + 1, N, n)
        return np.einsum("rkni,rknj->knij", err, err) / n_mc, run.P

    z_max = 5.0

    def agree(ex: tuple, mc: tuple) -> str:
        P, P_mc = ex[0], mc[0]
        gains_dev = float(np.abs(ex[1] - mc[1]).max())
        if gains_dev != 0.0:
            raise AssertionError(f"P_bar of 1 run and {n_mc} runs differ by {gains_dev:.3g}")
        # errors are zero-mean Gaussian: var(tr of the sample second moment) = 2 tr(P^2) / n
        sd = np.sqrt(2.0 * np.einsum("knij,knji->kn", P, P) / n_mc)
        z = np.abs(np.trace(P_mc, axis1=-2, axis2=-1) - np.trace(P, axis1=-2, axis2=-1)) / sd
        rel = np.abs(np.trace(P_mc, axis1=-2, axis2=-1) / np.trace(P, axis1=-2, axis2=-1) - 1)
        if not z.max() <= z_max:
            raise AssertionError(f"Monte Carlo tr P off the exact one by {z.max():.2f} sd")
        return (f"|tr P_MC - tr P| <= {z.max():.2f} sd <= {z_max:g} sd over {z.size} (k, node); "
                f"MC rel. error up to {rel.max():.0%}")

    rows.append(compare(
        f"guo2023: true error covariances P^i_k, k = 0..{K1 - 1}, {mdl.N} nodes",
        ("exact joint propagation (1 estimator run)", exact),
        (f"Monte Carlo, {n_mc} runs (simulate + estimate)", monte_carlo),
        agree, repeats=repeats))
    return rows


# ---------------------------------------------------------------------------- li2025
def bench_li2025(repeats: int) -> list[Row]:
    """Algorithm 1 (secest.methods.li2025.estimate) vectorised over F runs vs a loop over the runs.

    The data are the paper's example at the notebook's defaults (T = F = 100, mc_seed = 2025,
    the grid weights of the corrected design, xhat_moment = "run"), built here as the notebook
    builds them (the plant and the attack (6) are not timed); nothing is written.
    """
    from secest.core import montecarlo, schedules
    from secest.methods import li2025

    F, T, N, n_y, m, W, V, xi_star, eps = 100, 100, 3, 4, 2, 0.03, 0.03, 0.3, 0.05
    psi_check = np.array([0.7, 0.5, 0.3])
    weights = [(1e-3, 1.0, 1e-2, 0.1, 0.1), (1e-2, 1.0, 1e-4, 1e-4, 0.3), (1e-2, 1.0, 1e-4, 1e-4, 0.1)]
    parents = li2025.EXAMPLE_PARENTS
    H = np.diag([1.0, 1.0, eps, eps])
    CH = li2025.EXAMPLE_C @ H
    BH = {key: b @ H for key, b in li2025.EXAMPLE_B.items()}
    k = np.arange(T + 1)
    A, E = li2025.turn_model(T)
    AH = A @ H
    sets = schedules.rrl_map_sets(np.arange(1, T + 1), m, n_y)
    xi = np.sqrt(2 * xi_star / n_y) * np.where(np.arange(n_y) % 2 == 0, np.sin(k)[:, None],
                                                np.cos(k)[:, None])
    rng = montecarlo.spawn_rngs(2025, 1)[0]
    sigma = rng.uniform(0.0, 1.0, (F, N, 4))
    w = np.sqrt(W) * rng.standard_normal((F, T, N))
    v = np.sqrt(V) * rng.standard_normal((F, T, N, n_y))
    psi = (rng.uniform(0.0, 1.0, (F, T, N)) < psi_check).astype(float)
    x, y = np.zeros((F, T + 1, N, 4)), np.zeros((F, T, N, m))
    x[:, 0] = li2025.EXAMPLE_X0 + sigma
    for kk in range(1, T + 1):
        for i in range(N):
            x[:, kk, i] = x[:, kk - 1, i] @ AH[kk - 1].T + E[kk - 1] * w[:, kk - 1, i, None] + sum(
                x[:, kk - 1, j] @ BH[(i, j)].T for j in parents[i])
            ok = psi[:, kk - 1, i, None]
            y_raw = x[:, kk, i] @ CH.T + v[:, kk - 1, i]
            y[:, kk - 1, i] = ok * y_raw[:, sets[kk - 1]] + (1 - ok) * xi[kk, sets[kk - 1]]
    ewe = W * (E[:T, :, None] * E[:T, None, :])

    def run(sl: slice) -> dict:
        return li2025.estimate(y[sl], sets, AH[:T], ewe, CH, x[sl, 0], np.eye(4), weights, psi_check,
                               xi_star, V, parents=parents, BH=BH, variant="corrected", moment="run")

    def mse(xhat: np.ndarray) -> np.ndarray:
        return np.mean(np.sum((x - xhat) ** 2, axis=-1), axis=0)

    def batch() -> tuple:
        out = run(slice(None))
        return mse(out["xhat"]), out["S"]

    def loop() -> tuple:
        outs = [run(slice(f, f + 1)) for f in range(F)]
        return (mse(np.concatenate([o["xhat"] for o in outs])),
                np.concatenate([o["S"] for o in outs]))

    def agree(a: tuple, b: tuple) -> str:
        dev = max(_max_rel(a[0], b[0]), _max_rel(a[1], b[1]))
        return _agree_within("MSE_i(k) and S_i(k|k), max rel. |diff|", dev, 1e-9)

    return [compare(
        f"li2025: Monte Carlo of Algorithm 1 (methods.li2025.estimate), F = {F} runs, T = {T}, "
        "3 targets",
        ("vectorised over runs", batch),
        ("Python loop over runs (estimate on runs[f:f+1])", loop),
        agree, repeats=repeats, target=(">= 20x", lambda r: r >= 20.0))]


# ---------------------------------------------------------------------------- lee2020 / ma2021
def bench_lee2020(repeats: int) -> list[Row]:
    """Exponential Euler vs explicit Euler and adaptive solvers at matched accuracy.

    Accuracy of a run: RMS over the 0.01 s grid of max_i ||x_hat_i - x_hat_i^ref||_inf, the
    reference being exponential Euler at the notebook's ``accuracy_ref_dt`` (1e-4 s). Ours
    (exponential Euler at ``dt_ex``) sets the error to match; explicit Euler gets the largest
    step dt_ex / k, and the adaptive solvers (sgn smoothed by tanh(./eps), the notebook's
    tolerances) an eps shrunk in steps of 0.8 from a linear prediction, whose error is at most
    ours (an exact sgn stalls them, as the notebook shows). Calibration runs
    are not timed.
    """
    import ast

    from scipy.integrate import solve_ivp

    from secest.core import graphs, systems
    from secest.methods import lee2020 as L
    from secest.repro.results import declared_parameters

    # the notebook's default point, from notebooks/lee2020.toml; the example plant of Section IV
    nb = {k: ast.literal_eval(str(v)) for k, v in declared_parameters("lee2020").items()}
    J, b, k_s = nb["J_inertia"], nb["b_damping"], nb["k_spring"]
    A = np.array([[0, 1, 0, 0, 0, 0], [-k_s / J, -b / J, k_s / J, 0, 0, 0], [0, 0, 0, 1, 0, 0],
                  [k_s / J, 0, -2 * k_s / J, -b / J, k_s / J, 0], [0, 0, 0, 0, 0, 1],
                  [0, 0, k_s / J, 0, -k_s / J, -b / J]], dtype=float)
    B = np.array([0.0, 1.0 / J, 0.0, 0.0, 0.0, 0.0])
    C = np.array([[1, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 0, 1, 0], [1, 0, -1, 0, 0, 0],
                  [0, 0, 1, 0, -1, 0]], dtype=float)
    banks = [C[i : i + 1] for i in range(C.shape[0])]
    basis = L.assumption4_basis(A, banks)
    V = L.normalise_basis(basis.V, nb["basis_normalisation"])
    gains, _ = L.observer_gains(A, V, basis.S, banks, nb["observer_poles"])
    ring = [i - 1 for i in nb["ring_order"]]
    adj = np.zeros((len(ring), len(ring)))
    for i, j in zip(ring, ring[1:] + ring[:1], strict=True):
        adj[i, j] = adj[j, i] = 1.0
    sysm = L.network_system(A, B, banks, V, basis.S, gains, nb["kappa"], nb["gamma_ex"],
                            graphs.laplacian(adj))
    M, E_w, E_s, R, xh0 = sysm.M, sysm.E_w, sysm.E_s, sysm.R, sysm.xh0
    phi, s_flat = L.sign_correction(basis.S), basis.S.reshape(-1).astype(float)
    x0 = np.zeros(M.shape[0])  # z0_guess and xhat0 zero at the default point
    x0[:6] = nb["x0_plant"]
    horizon, amp, dt_ours = nb["accuracy_T"], nb["attack_amplitude"], nb["dt_ex"]

    def w(t: float) -> np.ndarray:
        out = np.zeros((1 + len(banks), 1))
        out[0] = nb["u_amplitude"] * np.sin(nb["u_frequency"] * t)
        if t >= nb["attack_start"]:
            out[nb["attack_bank"]] = amp
        return out

    def simulate(step: float, method: str = "expeuler") -> np.ndarray:
        every = int(round(nb["record_dt"] / step))
        return systems.integrate_switched_linear(M, E_w, w, E_s, R, phi, x0[:, None], step,
                                                 int(round(horizon / step)), record_every=every,
                                                 method=method)

    X_ref = simulate(nb["accuracy_ref_dt"])
    t_ref = np.arange(X_ref.shape[0]) * nb["record_dt"]
    xh_ref = X_ref[:, xh0:, 0].reshape(X_ref.shape[0], len(banks), -1)

    def error(X: np.ndarray) -> float:
        d = np.abs(X[:, xh0:, 0].reshape(xh_ref.shape) - xh_ref).max(axis=(1, 2))
        return float(np.sqrt(np.mean(d**2)))

    def fixed(method: str, step: float) -> Callable[[], np.ndarray]:
        return lambda: simulate(step, method)

    def adaptive(method: str, eps: float) -> Callable[[], np.ndarray]:
        def rhs(t: float, X: np.ndarray) -> np.ndarray:
            return M @ X + E_w @ w(t)[:, 0] + E_s @ (s_flat * np.tanh(R @ X / eps))

        def run() -> np.ndarray:
            sol = solve_ivp(rhs, (0.0, horizon), x0, method=method, t_eval=t_ref, rtol=1e-6,
                            atol=1e-9, max_step=0.01)
            if not sol.success:
                raise RuntimeError(f"{method} failed: {sol.message}")
            return sol.y.T[:, :, None]
        return run

    ours_fn = fixed("expeuler", dt_ours)
    e_ours = error(ours_fn())
    # explicit Euler: error ~ proportional to dt; start at the predicted divisor, step up
    k = max(1, int(np.ceil(error(fixed("euler", dt_ours)()) / e_ours)) - 1)
    while error(fixed("euler", dt_ours / k)()) > e_ours:
        k += 1
        if k > 40:
            raise RuntimeError("explicit Euler did not reach the matched accuracy with dt >= dt_ex/40")
    alternatives = [(f"explicit Euler, dt = {dt_ours / k:.3g} s (dt_ex / {k})",
                     fixed("euler", dt_ours / k))]
    for method in ("RK45", "LSODA"):
        # the smoothing offset is ~ proportional to eps: predict eps, then shrink by 0.8
        eps, fn = 1e-3, adaptive(method, 1e-3)
        e_1 = error(fn())
        if e_1 > e_ours:
            eps = float(f"{1e-3 * e_ours / e_1:.2g}")
            while error((fn := adaptive(method, eps))()) > e_ours:
                eps = float(f"{0.8 * eps:.2g}")
                if eps < 1e-5:
                    raise RuntimeError(f"{method} with tanh smoothing: accuracy not matched")
        alternatives.append((f"{method}, sgn = tanh(./{eps:g}), rtol 1e-6, atol 1e-9", fn))

    def agree(a: np.ndarray, b: np.ndarray) -> str:
        ea, eb = error(a), error(b)
        if not (ea == e_ours and eb <= e_ours):
            raise AssertionError(f"accuracy not matched: ours {ea:.3g}, alternative {eb:.3g}")
        return f"error vs ref. (RMS_t max_i): ours {ea:.2e}, alt. {eb:.2e} <= ours"

    return [compare(
        f"lee2020: example (1), (5), (6), attack pi/3, {horizon:g} s, matched accuracy",
        (f"exponential Euler, dt = {dt_ours:g} s", ours_fn), alt, agree, repeats=repeats)
        for alt in alternatives]


def bench_ma2021(repeats: int) -> list[Row]:
    """Per-step OP2 (LMI (30)): DPP re-solve vs rebuild; CLARABEL vs SCS on the same step.

    A fast-mode run of the NN estimator leaves the cached DPP problem holding the parameter
    values of its last step; every side solves exactly that step. Warm starts are off on
    every side (SCS would otherwise return the previous solution after 0 iterations).
    """
    from secest.core import lmi as slmi
    from secest.core import montecarlo
    from secest.methods import ma2021 as my
    from secest.repro import spaces

    # the paper's example as read (the notebook's defaults in notebooks/ma2021.toml), fast mode
    d = {name: par.default for name, par in spaces.load("ma2021").parameters.items()}
    fn = {"x": (lambda u: u, lambda u: np.ones_like(u)), "sin": (np.sin, np.cos),
          "cos": (np.cos, lambda u: -np.sin(u))}

    def terms(t, x):
        return np.array([sum(c * fn[f][0](w * x[v - 1] + b) for c, f, v, w, b in row) for row in t])

    def jac(t, x):
        J = np.zeros((len(t), 2))
        for r, row in enumerate(t):
            for c, f, v, w, b in row:
                J[r, v - 1] += c * w * fn[f][1](w * x[v - 1] + b)
        return J

    gt = [d["g1_terms"], d["g2_terms"], d["g3_terms"]]

    def E(i, k):
        return [np.array([[0.25], [0.2 + d["E1_amp"] * np.cos(k + 1)]]),
                np.array([[0.2], [0.15 + 0.1 * np.sin(2 * k)]]),
                np.array([[0.25 + d["E3_amp"] * np.sin(k)], [0.15]])][i]

    model = my.Model(f=lambda x: terms(d["f_terms"], x), jac_f=lambda x: jac(d["f_terms"], x),
                     g=lambda i, x: terms(gt[i], x), jac_g=lambda i, x: jac(gt[i], x),
                     B=lambda k: np.array([[0.1 + 0.01 * np.cos(k + 1)], [0.2 + 0.01 * np.sin(k)]]),
                     E=E)
    T_run = min(int(d["T"]), 8)
    x = np.zeros((T_run + 1, 2))
    x[0] = d["x0"]
    for k in range(T_run):
        x[k + 1] = model.f(x[k]) + model.B(k) @ np.array([0.3 * np.cos(2 * k)])
    y = np.array([[model.g(i, x[k]) + E(i, k) @ np.array([0.4 * np.sin(k)]) for i in range(3)]
                  for k in range(T_run + 1)])
    alpha = (montecarlo.spawn_rngs(d["seed"], 1)[0].random(T_run) < d["alpha_bar"]).astype(float)

    def received(k, z):  # (5), chi of the example
        return np.array([zj + alpha[k] * np.array([0.15 * np.sin(zj[0]), 0.3 * np.cos(zj[1])])
                         for zj in z])

    theta = np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], dtype=float)
    dims, problems = my.Dims(2, 2, 1, 1, 2), {}
    s = d["L_scale"]
    res = my.run_algorithm1(
        model, y, received, theta=theta, dims=dims, xhat0=d["xhat0"], P0=d["P0"], W0=d["W0"],
        Q0=d["Q0"], alpha_bar=d["alpha_bar"], e1=d["e1"], e3=d["e3"], L=s * np.eye(2),
        aleph=s * np.eye(2), V_inv=np.eye(1), U_inv=np.eye(1), p=d["p"], eps=d["eps_lmi"],
        lam2_box=d["lam2_max"], tol=d["cert_tol"], shared=d["shared_multipliers"],
        r_bound=d["r_bound"], varpi_form=d["varpi_form"], cache=problems)
    if res.failures:
        raise RuntimeError(f"ma2021 fast run had infeasible steps: {res.failures}")
    const = dict(alpha_bar=d["alpha_bar"], e3=d["e3"], eps=d["eps_lmi"],
                 shared=d["shared_multipliers"], r_bound=d["r_bound"], design="op2")
    cached, _ = my.step_problems(theta, dims, nn=True, e1=d["e1"], lam2_box=d["lam2_max"],
                                 cache=problems, **const)
    values = {q.name(): q.value for q in cached.problem.parameters()}
    nb = {"T_run": T_run, "cert_tol": d["cert_tol"], "CLARABEL_OPTS": my.CLARABEL_OPTS,
          "SCS_OPTS": my.SCS_OPTS}
    step = nb["T_run"] - 1
    cl_opts = {**nb["CLARABEL_OPTS"], "warm_start": False}
    scs_opts = {**nb["SCS_OPTS"], "warm_start": False}

    def fresh():
        sp = my.build_op2(theta, dims, nn=True, **const)
        for q in sp.problem.parameters():
            q.value = values[q.name()]
        return sp

    def solved(sp, solver: str, opts: dict, **kw) -> dict:
        sp.problem.solve(solver=solver, **opts, **kw)
        if sp.problem.status not in ("optimal", "optimal_inaccurate"):
            raise AssertionError(f"{solver}: status {sp.problem.status}")
        max_eig = max(slmi.max_eigenvalue(m.value) for m in sp.lmis.values())
        return {"obj": float(sp.problem.value), "P": np.asarray(sp.vars["P"].value, float),
                "status": sp.problem.status, "max_eig": max_eig,
                "iters": sp.problem.solver_stats.num_iters}

    def agree_rebuild(a: dict, b: dict) -> str:
        dev = abs(a["obj"] - b["obj"]) / max(1.0, abs(a["obj"]))
        p_dev = float(np.abs(a["P"] - b["P"]).max())
        for name, r in (("re-solve", a), ("rebuild", b)):
            if r["status"] != "optimal" or r["max_eig"] > nb["cert_tol"]:
                raise AssertionError(f"{name}: {r['status']}, max LMI eig {r['max_eig']:.2e}")
        return (_agree_within("both optimal and certified; objective rel. diff", dev, 1e-6)
                + f", max abs diff of P {p_dev:.1e}")

    rows = [compare(
        f"ma2021: per-step OP2 + LMI (30), 3 nodes, step k = {step} (CLARABEL)",
        ("DPP problem re-solved with new parameters", lambda: solved(cached, "CLARABEL", cl_opts)),
        ("problem rebuilt and compiled (ignore_dpp)",
         lambda: solved(fresh(), "CLARABEL", cl_opts, ignore_dpp=True)),
        agree_rebuild, repeats=repeats, target=(">= 2x", lambda r: r >= 2.0))]

    scs_problem = fresh()  # its own problem object: switching solvers would recompile
    scs_tol = 1e-3

    def agree_solvers(a: dict, b: dict) -> str:
        dev = abs(a["obj"] - b["obj"]) / max(1.0, abs(a["obj"]))
        return (_agree_within("objective rel. diff", dev, scs_tol)
                + f"; SCS {b['status']} in {b['iters']} it., max LMI eig {b['max_eig']:.1e}, "
                f"CLARABEL {a['iters']} it., {a['max_eig']:.1e} (cert. tol {nb['cert_tol']:g})")

    rows.append(compare(
        f"ma2021: per-step OP2 + LMI (30), step k = {step}, DPP problem, solver choice",
        ("CLARABEL (tol 1e-7)", lambda: solved(cached, "CLARABEL", cl_opts)),
        (f"SCS (max_iters {nb['SCS_OPTS'].get('max_iters', 'default')})",
         lambda: solved(scs_problem, "SCS", scs_opts)),
        agree_solvers, repeats=repeats))
    return rows


# ---------------------------------------------------------------------------- arena
def bench_arena(repeats: int) -> list[Row]:
    """Per-node step cost of every arena method on one common scenario.

    Common scenario: the arena's ``target20/none`` with 4 runs of 50 steps (a method's call
    estimates every node of every run at every step; its time is divided by runs x (K + 1) x N).
    Its growth with N is the ``scaling`` section.
    """
    from secest.arena import scenarios
    from secest.arena.estimators import METHODS

    rows: list[Row] = []
    common = scenarios.scenario("target20", "none", runs=4, horizon=50)
    trial = scenarios.simulate(common)
    per = common.runs * (common.horizon + 1) * common.network.N
    for name, method in METHODS.items():
        reason = method.not_applicable(common)
        what = f"arena {name}: per-node step cost on target20/none (20 nodes, 4 runs x 50 steps)"
        if reason is not None:
            rows.append(not_measured(what, f"N/A on the common scenario: {reason}"))
            continue
        rows.append(measure(what, (name, lambda m=method: m.run(trial).xhat), _finite,
                            repeats=repeats, per=per, unit="node-step"))
    return rows


def _finite(x: np.ndarray) -> str:
    if not np.all(np.isfinite(x)):
        raise AssertionError("non-finite estimate")
    return f"finite estimates, shape {tuple(x.shape)}"


# ---------------------------------------------------------------------------- per-node scaling
SCALING_N = (20, 200, 2000, 10_000)
"""Network sizes of the per-node step cost curve (target plant on a ring of constant degree)."""
SCALING_DEGREE = 4
"""Every node of the ring hears 2 neighbours on each side, whatever N."""
SCALING_RUNS, SCALING_STEPS = 2, 30
"""Monte Carlo runs and steps of each size's trial (a call covers runs x (steps + 1) x N node-steps)."""
SCALING_CALL_BUDGET_S = 30.0
"""A size is not timed when the previous sizes predict one call longer than this (the per-node
cost extrapolated with the growth exponent measured between the two previous sizes, at least 1)."""
SCALING_DESIGN_BUDGET_S = 300.0
"""... or conditions and design (once per network) longer than this (extrapolated like N^2)."""
SCALING_ENUMERATIONS: dict[str, Callable[[object, int], tuple[int, str]]] = {}
"""Methods whose design enumerates sets of nodes: (count, what) at N nodes; none since lee2020's
Assumption 2 is checked from its Assumption-4 basis in O(N n) (``redundant_from_basis``)."""
SCALING_MAX_SUBSETS = 100_000
"""Designs that enumerate subsets of sensor banks are not run beyond this many subsets."""


def _scaling_ring(N: int) -> object:
    from secest.arena import scenarios

    extra = {"network": {f"bench-ring{N}": {
        "title": f"target plant, {N} nodes on a ring (bench)", "plant": "target", "N": N,
        "graph": "ring", "degree": SCALING_DEGREE, "measures": [[i % 2] for i in range(N)]}}}
    return scenarios.scenario(f"bench-ring{N}", "none", runs=SCALING_RUNS, horizon=SCALING_STEPS,
                              seed=N, extra=extra)


def _skip_reason(name: str, method: object, N: int, curve: dict, design: dict) -> str | None:
    """Why size ``N`` is not timed for this method (enumeration, predicted call or design), or None."""
    if name in SCALING_ENUMERATIONS:
        count, enumerated = SCALING_ENUMERATIONS[name](method, N)
        if count > SCALING_MAX_SUBSETS:
            return f"its design enumerates {enumerated}: {count:.2e} > {SCALING_MAX_SUBSETS:.0e}"
    sizes = sorted(curve)
    if not sizes:
        return None
    last = sizes[-1]
    slope = 1.0
    if len(sizes) >= 2:
        prev = sizes[-2]
        slope = max(1.0, math.log(curve[last] * last / (curve[prev] * prev)) / math.log(last / prev))
    call = curve[last] * last * SCALING_RUNS * (SCALING_STEPS + 1) * (N / last) ** slope
    if call > SCALING_CALL_BUDGET_S:
        return (f"one call predicted at {call:.0f} s from N = {last} (growth N^{slope:.2f}; "
                f"> {SCALING_CALL_BUDGET_S:g} s budget)")
    predicted = design[last] * (N / last) ** 2
    if predicted > SCALING_DESIGN_BUDGET_S:
        return (f"its design took {design[last]:.1f} s at N = {last}; like N^2 it predicts "
                f"{predicted:.0f} s (> {SCALING_DESIGN_BUDGET_S:g} s budget)")
    return None


def _scaling_curve(name: str, method: object, trials: dict, repeats: int) -> tuple[dict, dict, str]:
    """Per-node step cost and design seconds at each size; the reason the curve stops, if it does.

    A checked warm-up call per size (in increasing N, which decides where the curve stops), then
    ``repeats`` rounds that call ``run`` once at every kept size (interleaved, so that a change of
    the machine's load hits every size alike); the median of each size's calls. Times are this
    process's CPU time (``time.process_time``): on a shared machine the wall time of a call also
    counts the time it waits for a core, which varied by 3x between identical calls here.
    """
    from secest.arena.scenarios import DENSE_NODES

    warm: dict[int, float] = {}
    design: dict[int, float] = {}
    stop = ""
    for N, (sc, trial) in trials.items():
        stop = _skip_reason(name, method, N, {n: warm[n] / _node_steps(trials[n][0]) for n in warm},
                            design) or ""
        if stop:
            stop = f"N = {N} not timed: {stop}"
            break
        try:
            t0 = time.process_time()
            na = method.not_applicable(sc)  # also builds what a method caches per network
            design[N] = time.process_time() - t0
            if na is not None:
                stop = f"N/A at N = {N}: {na}"
                break
            t0 = time.process_time()
            _finite(method.run(trial).xhat)
            warm[N] = time.process_time() - t0
        except Exception as exc:  # noqa: BLE001 - a method still on dense arrays: reported, not fatal
            dense = "is dense, refused" in str(exc)
            stop = (f"dense: skipped above N={DENSE_NODES}" if dense
                    else f"error at N = {N}: {type(exc).__name__}: {exc}")
            break
    times: dict[int, list[float]] = {N: [] for N in warm}
    for _ in range(repeats):
        for N in warm:
            t0 = time.process_time()
            method.run(trials[N][1])
            times[N].append(time.process_time() - t0)
    return {N: float(np.median(t)) / _node_steps(trials[N][0]) for N, t in times.items()}, design, stop


def _node_steps(sc: object) -> int:
    """What one call estimates: runs x (horizon + 1) x N node-steps."""
    return sc.runs * (sc.horizon + 1) * sc.network.N


def bench_scaling(repeats: int) -> list[Row]:
    """Per-node step cost of every arena method at N = 20, 200, 2000, 10 000 and its design cost.

    The target plant on a ring of degree :data:`SCALING_DEGREE` (constant in N), no attack,
    :data:`SCALING_RUNS` runs of :data:`SCALING_STEPS` steps: each method's ``run`` is timed (CPU
    time, median, :func:`_scaling_curve`) and divided by runs x (steps + 1) x N; its conditions and
    design (what it caches per network, built by ``not_applicable``) are timed once per size.
    Prints the curve per method; one row per method: the per-node cost at the largest timed size
    against N = 20 (target: ratio <= 2 at N = 10 000), the curve and the design times in the
    agreement column.
    """
    from secest.arena import scenarios
    from secest.arena.estimators import METHODS

    trials = {}
    for N in SCALING_N:
        sc = _scaling_ring(N)
        trials[N] = (sc, scenarios.simulate(sc))
    rows: list[Row] = []
    lines = [f"{'method':16s}" + "".join(f"{f'N={N}':>12s}" for N in SCALING_N)
             + f"{'ratio':>8s}  design s at " + ", ".join(str(N) for N in SCALING_N)]
    for name, method in METHODS.items():
        curve, design, stop = _scaling_curve(name, method, trials, repeats)
        cells = "".join(f"{curve[N] * 1e6:10.3g}us" if N in curve else f"{'-':>12s}" for N in SCALING_N)
        top = max(curve) if curve else None
        ratio = curve[top] / curve[SCALING_N[0]] if top and top > SCALING_N[0] else None
        lines.append(f"{name:16s}{cells}{'' if ratio is None else f'{ratio:8.2f}':>8s}  "
                     + ", ".join(f"{design[N]:.3g}" for N in SCALING_N if N in design)
                     + (f"  [{stop}]" if stop else ""))
        what = (f"arena {name}: per-node step cost, N = {SCALING_N[-1]} vs N = {SCALING_N[0]} "
                f"(ring, degree {SCALING_DEGREE})")
        text = ("curve (us/node-step) " + ", ".join(f"{N}: {curve[N] * 1e6:.3g}" for N in curve)
                + "; design (s) " + ", ".join(f"{N}: {design[N]:.3g}" for N in design)
                + (f"; {stop}" if stop else ""))
        if ratio is None:
            rows.append(not_measured(what, text))
            continue
        rows.append(Row(what, f"N = {SCALING_N[0]}", f"N = {top}", curve[SCALING_N[0]], curve[top],
                        ratio, text, f"ratio <= 2 at N = {SCALING_N[-1]}",
                        bool(ratio <= 2.0 and top == SCALING_N[-1]), "node-step", repeats))
    print("\nper-node step cost (target plant, ring of degree "
          f"{SCALING_DEGREE}, {SCALING_RUNS} runs x {SCALING_STEPS} steps):\n  " + "\n  ".join(lines),
          flush=True)
    return rows


# ---------------------------------------------------------------------------- run manifests
def bench_runs(repeats: int) -> list[Row]:
    """Per-notebook wall times from the run manifests (no timing here)."""
    rows: list[Row] = []
    totals = {"paper": [], "fast": []}
    for key in KEYS:
        walls, notes = {}, []
        source_mtime = (ROOT / "notebooks" / f"{key}.py").stat().st_mtime
        for mode, name in (("paper", f"{key}.json"), ("fast", f"{key}.fast.json")):
            path = ROOT / "build" / "runs" / name
            if not path.exists():
                notes.append(f"{mode}: not run")
                continue
            man = json.loads(path.read_text())
            walls[mode] = float(man["wall_time_s"])
            totals[mode].append(walls[mode])
            when = datetime.fromtimestamp(path.stat().st_mtime, UTC).strftime("%H:%M UTC")
            stale = f" (older than notebooks/{key}.py)" if path.stat().st_mtime < source_mtime else ""
            notes.append(f"{mode}: run {when} at {man.get('git_commit', '?')[:7]}{stale}")
        rows.append(Row(
            f"{key}: notebook wall time (run manifest)",
            "paper mode (make figures)", "fast mode (test)",
            walls.get("paper"), walls.get("fast"), None, "; ".join(notes), "", None))
    for mode, label, limit in (("paper", "make figures, all five", 240.0),
                               ("fast", "fast-mode notebook tests, all five", 180.0)):
        n_found = len(totals[mode])
        total = float(sum(totals[mode])) if n_found else None
        rows.append(Row(
            f"{label}: sum of manifest wall times ({n_found}/5 found)", mode, "-", total, None,
            None, "notebook code only: kernel start-up, build, strip and unit tests excluded",
            f"< {limit:g} s" + (" (make test)" if mode == "fast" else ""),
            None if total is None or n_found < 5 else total < limit))
    return rows


# ---------------------------------------------------------------------------- sweeps on Dask
def bench_sweep(repeats: int) -> list[Row]:
    """The same robustness sweep on a Dask LocalCluster of two workers against one worker.

    Six points of guo2023 in fast mode, each a papermill execution (kernel start
    included); both clusters are started before timing and reused; every timed
    sweep starts from an empty point cache. The two tables must be identical.
    Two alternating repeats per side (a sweep takes tens of seconds).
    """
    import shutil
    import tempfile

    from dask.distributed import LocalCluster

    from secest.repro import sweep

    points = {"guo2023": [{"seed": s} for s in range(101, 107)]}
    base = {"guo2023": {"mode": "fast"}}
    tmp = Path(tempfile.mkdtemp(prefix="bench-sweep-"))
    clusters = {
        n: LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
        for n in (1, 2)
    }
    times: dict[int, list[float]] = {1: [], 2: []}
    tables: dict[int, str] = {}
    try:
        for rep in range(2):
            for n, cluster in clusters.items():
                out = tmp / f"w{n}-{rep}"
                t0 = time.perf_counter()
                sweep.run_sweep(["guo2023"], scheduler=cluster.scheduler_address, build=out / "build",
                                out=out / "out", points=points, base=base, fresh=True, progress=False)
                times[n].append(time.perf_counter() - t0)
                tables[n] = (out / "out" / "guo2023" / "robustness.csv").read_text()
    finally:
        for cluster in clusters.values():
            cluster.close()
        shutil.rmtree(tmp, ignore_errors=True)
    if tables[1] != tables[2]:
        raise AssertionError("the 1-worker and 2-worker sweeps wrote different tables")
    one, two = float(np.median(times[1])), float(np.median(times[2]))
    return [Row(
        "sweep engine: 6 guo2023 points (fast mode) on a Dask LocalCluster, 2 workers vs 1",
        "2 workers", "1 worker", two, one, one / two, "robustness.csv identical", ">= 1.7x on 2 cores",
        one / two >= 1.7, "sweep", 2)]


# ---------------------------------------------------------------------------- arena design on Dask
DASK_DESIGN = {"networks": ("target20", "inertia5", "tank12"),
               "attacks": ("none", "bias", "message", "dos"), "seeds": (1, 2), "runs": 8, "horizon": 200}
"""The arena design of the Dask row: plants (networks) x attacks x seeds x every registered method,
short horizons (smoke-test windows: the row measures cost, not scores)."""


def _dask_design() -> list:
    from secest.arena import scenarios

    d = DASK_DESIGN
    return [scenarios.scenario(net, att, runs=d["runs"], horizon=d["horizon"], seed=seed,
                               name=f"{net}/{att}/seed{seed}")
            for net in d["networks"] for att in d["attacks"] for seed in d["seeds"]]


def _same_cells(a: object, b: object) -> str:
    """The two matrices' cells are equal (status, reason, every score); else AssertionError."""
    fields = ("status", "reason", "steady", "steady_worst", "transient", "detection", "false_alarm")
    if list(a.cells) != list(b.cells):
        raise AssertionError("the 1-worker and 2-worker matrices have different cells")
    for key, cell in a.cells.items():
        if [getattr(cell, f) for f in fields] != [getattr(b.cells[key], f) for f in fields]:
            raise AssertionError(f"cell {key} differs between 1 and 2 workers")
    return f"{len(a.cells)} cells identical"


def bench_arena_dask(repeats: int) -> list[Row]:
    """An arena design on a Dask LocalCluster of two workers against one worker.

    The design (:data:`DASK_DESIGN`, every registered method) runs through
    ``secest.arena.matrix.run_matrix(scheduler=...)``: batches of (scenarios, methods) planned by
    ``plan_tasks``. Each side gets a fresh cluster per repeat (no design cached from an earlier
    run), warmed by a two-step design first (imports), not timed; two alternating repeats per side.
    The scheduling overhead of a run is ``1 - sum of the batches' own times / (wall x workers)``:
    the share of the workers' time not spent in the arena's work (waiting, transfers, the tail).
    """
    from dask.distributed import LocalCluster

    from secest.arena import matrix, scenarios

    design = _dask_design()
    warm = [scenarios.scenario("target20", "none", runs=2, horizon=2)]
    times: dict[int, list[float]] = {1: [], 2: []}
    overhead: dict[int, list[float]] = {1: [], 2: []}
    result: dict[int, object] = {}
    for _ in range(2):
        for n in (1, 2):
            with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster:
                matrix.run_matrix(warm, short=True, scheduler=cluster.scheduler_address)
                t0 = time.perf_counter()
                result[n] = matrix.run_matrix(design, short=True, scheduler=cluster.scheduler_address)
                wall = time.perf_counter() - t0
            times[n].append(wall)
            overhead[n].append(1.0 - sum(result[n].tasks) / (wall * n))
    agreement = _same_cells(result[1], result[2])
    one, two = float(np.median(times[1])), float(np.median(times[2]))
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    d = DASK_DESIGN
    what = (f"arena design on Dask: 2 workers vs 1 ({len(d['networks'])} plants x "
            f"{len(d['attacks'])} attacks x {len(d['seeds'])} seeds x {len(result[1].methods)} "
            f"methods, {d['runs']} runs x {d['horizon']} steps; {len(result[2].tasks)} batches)")
    return [Row(what, "2 workers", "1 worker", two, one, one / two,
                f"{agreement}; scheduling overhead 1 worker "
                f"{100 * float(np.median(overhead[1])):.1f} %, 2 workers "
                f"{100 * float(np.median(overhead[2])):.1f} %; load average at the end {load}",
                ">= 1.7x on 2 cores", one / two >= 1.7, "design", 2)]


SECTIONS: dict[str, Callable[[int], list[Row]]] = {
    "ding2020": bench_ding2020,
    "guo2023": bench_guo2023,
    "li2025": bench_li2025,
    "lee2020": bench_lee2020,
    "ma2021": bench_ma2021,
    "arena": bench_arena,
    "scaling": bench_scaling,
    "sweep": bench_sweep,
    "arena-dask": bench_arena_dask,
    "runs": bench_runs,
}


def machine() -> dict:
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    versions = {}
    for pkg in ("numpy", "scipy", "networkx", "cvxpy", "clarabel", "scs", "filterpy"):
        try:
            versions[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            versions[pkg] = "not installed"
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True,
                                capture_output=True, check=True).stdout.strip()
        if subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, text=True,
                          capture_output=True, check=True).stdout.strip():
            commit += "-dirty"
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    return {
        "cpu": cpu,
        "nproc": len(os.sched_getaffinity(0)),
        "load_average": os.getloadavg(),
        "python": platform.python_version(),
        "platform": f"{platform.system()} {platform.machine()}",
        "omp_num_threads": os.environ.get("OMP_NUM_THREADS", "unset"),
        "versions": versions,
        "git_commit": commit,
        "date_utc": datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC"),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default=",".join(SECTIONS), help="comma-separated sections")
    parser.add_argument("--repeats", type=int, default=5, help="timed repeats per side (>= 5)")
    parser.add_argument("--json", default=str(ROOT / "build" / "bench.json"), help="output file")
    args = parser.parse_args(argv)
    chosen = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = sorted(set(chosen) - set(SECTIONS))
    if unknown:
        parser.error(f"unknown sections {unknown}; known: {sorted(SECTIONS)}")
    info = machine()
    print(f"machine: {info['cpu']}, {info['nproc']} cores, load {info['load_average']}, "
          f"OMP_NUM_THREADS={info['omp_num_threads']}, git {info['git_commit']}", flush=True)
    rows: list[Row] = []
    durations: dict[str, float] = {}
    t_start = time.perf_counter()
    failed: list[str] = []
    for name in chosen:
        t0 = time.perf_counter()
        try:
            new = SECTIONS[name](args.repeats)
        except Exception as exc:  # a disagreement or a broken section: shown, then exit 1
            traceback.print_exc()
            failed.append(name)
            new = [not_measured(f"{name}: section FAILED", f"{type(exc).__name__}: {exc}")]
        durations[name] = round(time.perf_counter() - t0, 2)
        print(f"  {name}: {len(new)} rows in {durations[name]:.1f} s", flush=True)
        rows.extend(new)
    total = time.perf_counter() - t_start
    print()
    print(format_table(rows))
    print(f"\nbenchmark wall time {total:.1f} s; repeats per side {args.repeats} (median reported)")
    missed = [r.what for r in rows if r.met is False]
    if missed:
        print("targets missed (reported, not failed):\n  - " + "\n  - ".join(missed))
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    info["load_average_end"] = os.getloadavg()
    out.write_text(json.dumps({"machine": info, "wall_time_s": round(total, 2),
                               "section_s": durations, "repeats": args.repeats,
                               "failed_sections": failed,
                               "rows": [r.as_dict() for r in rows]}, indent=2) + "\n")
    print(f"written {out}")
    if failed:
        print(f"FAILED sections (see the tracebacks above): {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
