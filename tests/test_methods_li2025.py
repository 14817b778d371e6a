"""li2025 in the arena (secest.methods.li2025): equivalence with the notebook, the arena method."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import bench_harness

import secest.arena.papers  # noqa: F401  (registers the methods)
from secest.arena import scenarios
from secest.arena.estimators import METHODS
from secest.arena.papers import li2025 as arena_li2025
from secest.core import montecarlo
from secest.core.validation import ValidationError
from secest.methods import li2025

T_NB, F_NB = 30, 8


@pytest.fixture(scope="module")
def nb():
    """The notebook's objects, by name (fast mode: the weight table, no grid), and its draws."""
    ns = bench_harness().notebook_definitions(
        "li2025", "AH_ALL", "BH", "CH", "E_ALL", "K_SETS", "N", "NX", "NZ", "PSI", "SETS", "V", "W",
        "WEIGHTS", "XI", "bound_coefficients", "draw_randomness", "gain_and_bound", "hs",
        "innovation_map", "m", "n_y", "predicted_bound", "simulate", "xi_star", "xs",
        mode="fast", T=T_NB, F=F_NB)
    ns["_draws"] = ns["draw_randomness"](montecarlo.spawn_rngs(5, 1)[0], F_NB, T_NB)
    return ns


def _received(ns, out):
    """The received scheduled entries (6) of the notebook's simulation, rebuilt from its states."""
    d, y = ns["_draws"], np.empty((F_NB, T_NB, ns["N"], ns["m"]))
    for k in range(1, T_NB + 1):
        sched = ns["SETS"][k - 1]
        for i in range(ns["N"]):
            y_raw = out["x"][:, k, i] @ ns["CH"].T + d["v"][:, k - 1, i]
            ok = d["psi"][:, k - 1, i, None]
            y[:, k - 1, i] = ok * y_raw[:, sched] + (1 - ok) * ns["XI"][k, sched]
    return y


def _estimate(nb, out, variant, moment, update):
    """The method's :func:`li2025.estimate` on the received data of the notebook's run ``out``."""
    E = nb["E_ALL"][:T_NB]
    return li2025.estimate(
        _received(nb, out), nb["SETS"], nb["AH_ALL"][:T_NB], nb["W"] * np.einsum("ka,kb->kab", E, E),
        nb["CH"], out["xhat"][:, 0], np.eye(4), nb["WEIGHTS"][variant], nb["PSI"], nb["xi_star"],
        nb["V"], parents=nb["K_SETS"], BH=nb["BH"], variant=variant, moment=moment, update=update,
    )


@pytest.mark.parametrize("variant", ["corrected", "paper"])
@pytest.mark.parametrize("moment", ["run", "ensemble"])
@pytest.mark.parametrize("update", ["zero", "zoh"])
def test_estimator_equals_the_notebook_on_the_paper_example(nb, variant, moment, update) -> None:
    """Whole trajectories against the notebook's Monte Carlo ``simulate`` (its estimators: zero, zoh).

    The reviewer-grade notebook's ``simulate`` knows only ``"zero"`` and ``"zoh"`` (and treats any
    other name as ``"zero"``); its debiased innovation and open-loop prediction live in the
    exact-moment recursion: the next test compares those two.
    """
    weights = nb["WEIGHTS"][variant]
    out = nb["simulate"](nb["_draws"], weights, variant=variant, moment=moment, estimator=update)
    mine = _estimate(nb, out, variant, moment, update)
    for key in ("xhat", "S", "S_pred", "L"):
        scale = max(np.abs(out[key]).max(), 1.0)
        assert np.abs(mine[key] - out[key]).max() <= 1e-10 * scale, key


def _close(a, b, what: str) -> None:
    assert np.abs(a - b).max() <= 1e-10 * max(np.abs(b).max(), 1.0), what


@pytest.mark.parametrize("variant", ["corrected", "paper"])
@pytest.mark.parametrize("moment", ["run", "ensemble"])
@pytest.mark.parametrize("update", ["debiased", "open_loop"])
def test_debiased_and_open_loop_updates_are_the_notebooks(nb, variant, moment, update) -> None:
    """``"debiased"`` and ``"open_loop"`` step by step against the notebook's own definitions.

    The notebook now runs these two only in its exact-moment recursion (``exact_moments``:
    deterministic gains from the exact ``E{x_hat x_hat^T}``, which no defender can compute), the
    method on sampled runs with the run's (or the runs' mean) ``x_hat x_hat^T``, the surrogate of
    the notebook's ``simulate``. What is the same, checked at every step ``k``, target ``i`` and
    run from the method's own previous values: the prediction (7) (the notebook's ``simulate``
    with zero gains for the open loop, whole trajectories), the bound (17) and the gain and bound
    (28), (18) of the zero-input design (the notebook's ``bound_step`` calls the same functions),
    and the innovation: ``innovation_map(i, psi_i, ...)`` with ``c = psi_check_i`` (debiased) —
    ``psi_i (Gamma x_i + v) + (1 - psi_i) xi - psi_check_i Gamma x_hat_i(k|k-1)`` — and ``L = 0``
    (open loop). What differs by design: the method's open loop still reports the zero-input
    design's bound ``S`` (the notebook's ``exact_moments(gain="zero")`` reports none).
    """
    weights = nb["WEIGHTS"][variant]
    zero = nb["simulate"](nb["_draws"], weights, variant=variant, moment=moment)  # x: the plant
    mine = _estimate(nb, zero, variant, moment, update)
    if update == "open_loop":
        gains = np.zeros((T_NB + 1, nb["N"], nb["NX"], nb["n_y"]))
        ref = nb["simulate"](nb["_draws"], weights, variant=variant, moment=moment, gains=gains)
        assert np.array_equal(mine["L"], gains[None].repeat(F_NB, axis=0))
        _close(mine["xhat"], ref["xhat"], "xhat")
    d, xh, S = nb["_draws"], mine["xhat"], mine["S"]
    for k in range(1, T_NB + 1):
        ah, sched = nb["AH_ALL"][k - 1], nb["SETS"][k - 1]
        G, xi_s = nb["CH"][sched], nb["XI"][k, sched]
        ewe = nb["W"] * np.outer(nb["E_ALL"][k - 1], nb["E_ALL"][k - 1])
        z = np.zeros((F_NB, nb["NZ"]))  # col(x_1..x_N, x_hat_1(k|k-1)..x_hat_N(k|k-1))
        for i in range(nb["N"]):
            xp = xh[:, k - 1, i] @ ah.T + sum(xh[:, k - 1, j] @ nb["BH"][(i, j)].T
                                               for j in nb["K_SETS"][i])  # (7)
            z[:, nb["xs"](i)], z[:, nb["hs"](i)] = zero["x"][:, k, i], xp
        for i in range(nb["N"]):
            lam, a1, a2, a3, a4 = weights[i]
            parents = nb["K_SETS"][i]
            Sp = nb["predicted_bound"](S[:, k - 1, i], [S[:, k - 1, j] for j in parents], ah,
                                       [nb["BH"][(i, j)] for j in parents], lam, ewe, True)  # (17)
            _close(mine["S_pred"][:, k, i], Sp, f"S_pred at k={k}, i={i}")
            xp = z[:, nb["hs"](i)]
            X_hat = xp[:, :, None] * xp[:, None, :]
            if moment == "ensemble":
                X_hat = np.broadcast_to(X_hat.mean(axis=0), X_hat.shape)
            coefs = nb["bound_coefficients"](nb["PSI"][i], a2, a3, a4, variant)
            L, S_new, _ = nb["gain_and_bound"](mine["S_pred"][:, k, i], X_hat, G, coefs, a1)  # (28)
            _close(S[:, k, i], S_new, f"S at k={k}, i={i}")
            if update == "open_loop":
                _close(xh[:, k, i], xp, f"xhat at k={k}, i={i}")
                continue
            _close(mine["L"][:, k, i][..., sched], L, f"L at k={k}, i={i}")
            nu = np.zeros((F_NB, len(sched)))
            for b in (1.0, 0.0):  # the runs whose packet was received (psi_i = 1) / replaced
                nz, n0, _ = nb["innovation_map"](i, b, G, xi_s, "replace", nb["PSI"][i])
                nu += (d["psi"][:, k - 1, i, None] == b) * (z @ nz.T + n0 + b * d["v"][:, k - 1, i, sched])
            _close(xh[:, k, i], xp + np.einsum("frc,fc->fr", L, nu), f"xhat at k={k}, i={i}")


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
    sc = replace(sc, network=replace(sc.network, adj=np.ones((5, 5)) - np.eye(5)))
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
    c0, kx, kxi = li2025.bound_coefficients(0.7, a2, a3, a4)
    assert (c0, kx, kxi) == pytest.approx((1.033, 3.33, 33.3))
    assert li2025.bound_coefficients(1.0, a2, a3, a4) == (1.0, 0.0, 0.0)


def test_not_applicable_outside_the_replacement_model_and_without_local_observability() -> None:
    attack = ("every attack on the measurement packets is the Bernoulli replacement (6) of a bounded "
              "value with known psi_check, xi* (or none)")
    for kind in ("bias", "message"):
        assert METHODS["li2025"].not_applicable(scenarios.scenario("inertia5", kind, runs=2)) == attack
    sc = scenarios.scenario("inertia5", "none", runs=2)
    diffs = replace(sc, network=replace(sc.network, measures=np.array([[3], [4], [3], [4], [3]])))
    reason = METHODS["li2025"].not_applicable(diffs)
    assert reason is not None and reason.startswith("(A, C) is observable from every node's closed")


def test_bad_input_is_refused_with_the_argument_named() -> None:
    with pytest.raises(ValidationError, match="variant must be one of"):
        li2025.bound_coefficients(0.5, 0.1, 0.1, 0.1, "printed")
    with pytest.raises(ValidationError, match="weights must be 5 positive numbers"):
        arena_li2025.Li2025(weights=(1.0, 1.0))
    with pytest.raises(ValidationError, match="variant must be one of"):
        arena_li2025.Li2025(variant="x")
    args = (np.zeros((2, 3, 1, 1)), np.zeros((3, 1), int), np.eye(2), np.eye(2), np.ones((1, 2)),
            np.zeros((2, 1, 2)), np.eye(2), [(1e-3, 1, 1, 1, 1)], 1.0, 0.0, 1.0)
    with pytest.raises(ValidationError, match="update must be one of"):
        li2025.estimate(*args, update="hold")
    with pytest.raises(ValidationError, match="Incompatible dimensions of AH"):
        li2025.estimate(*args[:2], np.eye(3), *args[3:])
    with pytest.raises(ValidationError, match="x0, sched and weights must match y"):
        li2025.estimate(*args[:5], np.zeros((2, 2, 2)), *args[6:])
