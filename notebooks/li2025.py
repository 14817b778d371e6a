# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (secest)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # li2025 — Secure recursive state estimation for singularly perturbed discrete sequential systems under a round-robin-like multichannel access policy
#
# Y. Li, L. Wei, J. Liu, X. Xie and E. Tian, "Secure Recursive State Estimation for Singularly
# Perturbed Discrete Sequential Systems Under Round-Robin-Like Multichannel Access Policy",
# *IEEE Transactions on Automation Science and Engineering*, vol. 22, 2025 (online May 2024),
# doi:10.1109/TASE.2024.3398731.
#
# **Summary.** $N$ subsystems are chained along a directed acyclic ("sequential") order; each has
# a slow and a fast state part, scaled by the singular-perturbation matrix $H_\epsilon$. Each
# subsystem has $n_y$ scalar sensors but only $m<n_y$ wireless channels: a periodic
# round-robin-like schedule (RRL-MAP) lets exactly $m$ sensors transmit per step and the others
# are read as zero. A Bernoulli attacker *replaces* received packets by a bounded signal. One
# recursive estimator per subsystem predicts with its upstream neighbours' estimates and corrects
# with the scheduled, possibly attacked, entries. Since the true error covariance cannot be
# propagated, the paper propagates an upper bound $\mathfrak S_i(k|k)$ built with scalar weights
# $\lambda,\alpha_1,\dots,\alpha_4$ and chooses the gain minimising its trace (Theorems 1–2);
# Theorem 3 claims exponential mean-square boundedness. The example tracks three 2-D
# coordinated-turn targets.
#
# **Verdict: [Re, partial].** The bound claim is reproduced *after correcting the bound's
# coefficients*: with the coefficients re-derived from the paper's own proof, $\mathrm{MSE}_i(k)$
# stays below the bound at every step (Fig. 7) — an empirical result, because our gain depends
# on the run's data while the derivation assumes a deterministic gain (the ensemble variant gives
# the same) — whereas the coefficients as printed in (18) / Theorem 2 are not a bound (the
# trace-minimising weights give a "bound" 140–8000× below the MSE). The RRL-MAP fairness and the
# attack statistics hold; "ZOH is not better" (Fig. 6) holds, but with the grid weights only
# target 1 is informative (gains ≈ 0 for targets 2, 3); with an interior weight set ZOH is worse
# for every target. Theorem 3 is **not** reproduced: its condition $\eta^*\le\phi^*$ cannot be met
# on the example, and Fig. 8's inequality holds only for an envelope built from the data
# (1e13–1e17, i.e. vacuous). The tracking claim of Figs 2–4 ("estimates well match the real
# trajectories") is **not** reproduced, neither with the trace-optimal weights (gains ≈ 0 for
# targets 2 and 3: open-loop prediction; target 1 biased by the replacement attack) nor with an
# interior weight set (non-zero gains pull targets 2 and 3 toward the attack signal; relative
# RMS errors 0.30–0.63). One factor $\check\psi_i$ in the innovation removes target 1's bias (our
# extra, last section).

# %% tags=["parameters"]
mode = "paper"  # "paper": full run incl. the Remark-4 grid; "fast": weights from the table below
T = 100  # horizon in steps (MISSING)
F = 100  # Monte Carlo runs (PAPER, Section IV)
mc_seed = 2025  # seed of the Monte Carlo draws (MISSING)
grid_seed = 2026  # seed of the pilot runs of the Remark-4 grid (MISSING)
grid_pilot_runs = 10  # pilot runs averaged by the grid objective (MISSING)
epsilon = 0.05  # singular perturbation parameter (PAPER)
n_y = 4  # sensors per target (PAPER)
m = 2  # channels per target (PAPER)
xi_star = 0.3  # attack energy bound (PAPER)
psi_check = [0.7, 0.5, 0.3]  # probabilities of NO attack per target (PAPER)
W = 0.03  # process noise variance (PAPER)
V = 0.03  # measurement noise variance per sensor (PAPER, scalar read as V I)
coef = "corrected"  # bound coefficients: "corrected" (re-derived) or "paper" (as printed)
xhat_moment = "run"  # surrogate of E[xhat xhat^T]: "run" or "ensemble" (MISSING)
coupling_factor = True  # multiply the coupling term of (17) by |K_i| (CORRECTED)
grid_lambda = [1e-3, 1e-2, 1e-1]  # Remark-4 grid (MISSING)
grid_alpha1 = [0.3, 1.0, 3.0, 10.0]
grid_alpha23 = [1e-4, 1e-3, 1e-2, 0.1, 1.0]
grid_alpha4 = [0.03, 0.1, 0.3]
# (lambda, alpha1, alpha2, alpha3, alpha4) of targets 1, 2, 3 as found by the grid (used in fast mode)
weights_corrected = [[1e-3, 1.0, 1e-2, 0.1, 0.1], [1e-2, 1.0, 1e-4, 1e-4, 0.3], [1e-2, 1.0, 1e-4, 1e-4, 0.1]]
weights_paper = [[1e-3, 3.0, 1e-2, 1.0, 0.1], [1e-1, 10.0, 1e-4, 1.0, 0.03], [1e-1, 10.0, 1e-4, 1.0, 0.03]]
# printed coefficients, grid restricted to alpha2 > alpha3 (the condition of Theorem 3)
weights_paper_thm3 = [[1e-3, 1.0, 1e-3, 1e-4, 0.3], [1e-2, 1.0, 1e-3, 1e-4, 0.3], [1e-2, 1.0, 1e-3, 1e-4, 0.1]]
# (lambda, alpha1..alpha4) for every target in the sensitivity runs of C2 / C7: an interior
# point of the grid, away from the alpha2 = alpha3 = 1e-4 edge where the gain is ~0 (ours)
weights_interior = [0.01, 1.0, 0.01, 0.1, 0.1]
phi_scan = [-12.0, 12.0, 241]  # log10 range and size of the (phi_*, phi^*) scan of Theorem 3 (ours)
plot_run = 0  # Monte Carlo run shown in the single-run figures (MISSING)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/li2025"
results_path = "figures/li2025/claims.json"

# %%
import itertools
from math import lcm

import matplotlib.pyplot as plt
import numpy as np

from secest import montecarlo, plotting, results, schedules

print(results.environment_summary())

run = results.Run("li2025", globals())
if mode not in ("paper", "fast"):
    raise ValueError(f"mode must be 'paper' or 'fast', found {mode!r}")
if coef not in ("corrected", "paper"):
    raise ValueError(f"coef must be 'corrected' or 'paper', found {coef!r}")
if xhat_moment not in ("run", "ensemble"):
    raise ValueError(f"xhat_moment must be 'run' or 'ensemble', found {xhat_moment!r}")
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)
N, NX = 3, 4  # targets, states per target
PSI = np.asarray(psi_check, float)
if PSI.shape != (N,):
    raise ValueError(f"psi_check must hold {N} probabilities, found {psi_check!r}")
run_grid = mode == "paper"
WEIGHT_TABLE = {
    name: [tuple(map(float, w)) for w in table]
    for name, table in (("corrected", weights_corrected), ("paper", weights_paper),
                        ("paper_thm3", weights_paper_thm3))
}
if any(np.shape(t) != (N, 5) for t in WEIGHT_TABLE.values()):
    raise ValueError("weights_* must hold 5 weights (lambda, alpha1..alpha4) for each of 3 targets")
if np.shape(weights_interior) != (5,) or min(weights_interior) <= 0:
    raise ValueError(f"weights_interior must hold 5 positive weights, found {weights_interior!r}")
W_INTERIOR = [tuple(map(float, weights_interior))] * N
if len(phi_scan) != 3 or not phi_scan[0] < 0 < phi_scan[1] or int(phi_scan[2]) < 3:
    raise ValueError(f"phi_scan must be [log10 min < 0, log10 max > 0, size >= 3], found {phi_scan!r}")

# %% [markdown]
# ## Parameter provenance
#
# | name | value | tag | source / reason |
# |---|---|---|---|
# | $N$, $K_1,K_2,K_3$ | 3; $\emptyset$, {1}, {1, 2} | PAPER | Section IV |
# | $n_y$, $m$, $U$ | 4, 2, 2 | PAPER | Section IV |
# | $A_i(k)$, $C_i$, $E_i(k)$, $B_{i,j}$ | coordinated-turn model, $T_k=0.8\tanh k$, $r_k=0.1+0.3\tanh k$ | PAPER | Section IV |
# | $n_s=n_f=2$, $\epsilon$ | 2, 2, 0.05 | PAPER | $H_\epsilon=\mathrm{diag}(1,1,\epsilon,\epsilon)$ scales the *Y* position / velocity |
# | $x_i(0)=\hat x_i(0\|0)$ | offsets + $\sigma_{ij}\sim U(0,1)$ | PAPER | Section IV; $\sigma$ redrawn in every Monte Carlo run (MISSING: the paper does not say) |
# | $\mathfrak S_i(0\|0)$ | $I_4$ | PAPER | |
# | $\xi^*_i$, $\check\psi_i$ | 0.3; 0.7, 0.5, 0.3 | PAPER | $\check\psi_i=\Pr\{\psi_i=1\}$ is the probability of **no** attack |
# | $\mathcal W_i$, $\mathcal V_i$ | 0.03, $0.03\,I_4$ | PAPER | "positive numbers"; $E_i$ is 4×1 so $\omega_i$ is scalar; $\mathcal V_i$ read as $0.03 I$ |
# | $F$ | 100 | PAPER | Fig. 7 |
# | `T` | 100 | MISSING | $\tanh$ saturates by $k\approx3$; 100 steps show transient and drift |
# | attack $\xi_i(k)$ | $\sqrt{\xi^*/2}\,[\sin k,\cos k,\sin k,\cos k]^T$ | MISSING | deterministic, $\|\xi\|^2=\xi^*$ (the largest admissible energy) |
# | `mc_seed`, `grid_seed` | 2025, 2026 | MISSING | reproducibility (`SeedSequence(seed).spawn`) |
# | `coef` | corrected | CORRECTED | (18)/Theorem 2 coefficients are not a bound (derivation below); `"paper"` keeps the printed ones |
# | `coupling_factor` | $\|K_i\|$ | CORRECTED | (17) writes $(\sum_j BH)\mathfrak S_j(\sum_j H^TB^T)$, undefined for $\|K_i\|\ge2$; the proof omits the $e_j e_l^T$ cross terms |
# | `xhat_moment` | run | MISSING | $\mathbb E\{\hat x\hat x^T\}$ of (18), (28) has no closed form; the run's own $\hat x\hat x^T$ (causal), or the ensemble mean |
# | $\lambda,\alpha_1..\alpha_4$ | grid minimiser of the bound's mean trace | MISSING | Remark 4 suggests minimising the bound; a documented grid (below) |
# | `grid_*`, `grid_pilot_runs` | 3·4·5·5·3 = 900 candidates, 10 pilot runs | MISSING | spans the stable range; larger $\lambda$ or $\alpha_2+\alpha_3$ make the bound explode |
# | `weights_corrected`, `weights_paper`, `weights_paper_thm3` | the grid's results | MISSING | used in fast mode (grid skipped); paper mode re-runs the grid and prints whether it agrees |
# | `weights_interior` | (0.01, 1, 0.01, 0.1, 0.1) for every target | MISSING (ours) | sensitivity of C2 / C7 to the weight choice: an interior grid point, so that targets 2, 3 get a non-negligible gain |
# | `phi_scan` | $10^{-12}..10^{12}$, 241 points per axis | ours | scan for a pair $(\phi_*,\phi^*)$ meeting Theorem 3's conditions |
# | $\alpha_5..\alpha_7$, $\phi_*,\phi^*$, Assumption-1 constants | data-driven (Theorem 3 section) | MISSING | the paper gives none; the literal constants degenerate on the example |
# | ZOH variant | hold buffer, gain with $\Phi=I$ | MISSING | the paper gives no details of its Fig. 6 |
# | `plot_run` | 0 | MISSING | the paper shows single trajectories |

# %% [markdown]
# ## The SPDSS (1)
#
# For $i=1,2,3$, with $x_i=\mathrm{col}\{X^p_i,X^v_i,Y^p_i,Y^v_i\}$,
#
# $$x_i(k+1)=A_i(k)H_\epsilon x_i(k)+\sum_{j\in K_i}B_{i,j}H_\epsilon x_j(k)+E_i(k)\omega_i(k),\qquad
# \tilde y_i(k)=C_iH_\epsilon x_i(k)+v_i(k). \tag{1}$$
#
# $T_0=0$ gives $A_i(0)=I$ and $E_i(0)=0$: no process noise enters the first transition.
# Because the output is $C_iH_\epsilon x_i$, sensors 2 and 4 see $\epsilon Y^p_i$ and $\epsilon Y^v_i$.

# %%
K_SETS = {0: (), 1: (0,), 2: (0, 1)}  # 0-based K_i
H_EPS = np.diag([1.0, 1.0, epsilon, epsilon])
C_MAT = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], float)
CH = C_MAT @ H_EPS
B_MAT = {(1, 0): np.diag([0, 0.05, 0, 0.02]), (2, 0): np.diag([0, 0.06, 0, 0.07]),
         (2, 1): np.diag([0, 0.05, 0, 0.09])}
BH = {key: b @ H_EPS for key, b in B_MAT.items()}
X0_OFFSET = np.array([[0, 1, 0, 1], [2, 1, 2, 1], [2, 2, 2, 2]], float)


def turn_model(horizon: int) -> tuple[np.ndarray, np.ndarray]:
    """A_i(k) (T+1, 4, 4) and E_i(k) (T+1, 4) of Section IV for k = 0..horizon."""
    k = np.arange(horizon + 1)
    tk, rk = 0.8 * np.tanh(k), 0.1 + 0.3 * np.tanh(k)
    s, c = np.sin(rk * tk), np.cos(rk * tk)
    a = np.zeros((horizon + 1, 4, 4))
    a[:, 0, 0] = a[:, 2, 2] = 1.0
    a[:, 0, 1] = a[:, 2, 3] = s / rk
    a[:, 0, 3] = -(1 - c) / rk
    a[:, 2, 1] = (1 - c) / rk
    a[:, 1, 1] = a[:, 3, 3] = c
    a[:, 1, 3] = -s
    a[:, 3, 1] = s
    return a, np.stack([tk**2 / 2, tk, tk**2 / 2, tk], axis=1)


A_ALL, E_ALL = turn_model(T)
AH_ALL = A_ALL @ H_EPS
print("A(5) =\n", np.round(A_ALL[5], 4), "\ndet A(k) = 1:", np.allclose(np.linalg.det(A_ALL), 1))

# %% [markdown]
# ## RRL-MAP (2)–(5)
#
# $\varepsilon(k)=\{\mathrm{mod}(m(k-1)+s,n_y)+1: s=0..m-1\}$ (2), period $U=\mathrm{lcm}(m,n_y)/m$,
# $\Phi_{o(k)}=\sum_{r\in\varepsilon(k)}\phi_r$ (4) and the zero-input update
# $\bar y_i(k)=\Phi_{o(k)}\tilde y_i(k)$ (3), (5). The schedule is the reusable
# `secest.schedules` (0-based sensor indices = label − 1). Remark 1 (fairness): in every window
# of $U$ steps each sensor is served $\mathrm{lcm}(m,n_y)/n_y$ times.

# %%
U = schedules.rrl_map_period(m, n_y)
SETS = schedules.rrl_map_sets(np.arange(1, T + 1), m, n_y)  # row k-1 holds eps(k)
window_counts = schedules.rrl_map_window_counts(SETS, n_y)
print(f"U = {U}; eps(1..4) (1-based) =", (SETS[:4] + 1).tolist())
print("sensor counts in every U-window:", np.unique(window_counts, axis=0).tolist())

# %% [markdown]
# ## Bernoulli replacement attack (6)
#
# $y_i(k)=\psi_i(k)\bar y_i(k)+(1-\psi_i(k))\Phi_{o(k)}\xi_i(k)$ with
# $\Pr\{\psi_i(k)=1\}=\check\psi_i$: **$\psi_i=1$ means not attacked**, so the attack
# probabilities are 0.3 / 0.5 / 0.7. An attack *replaces* the scheduled entries. Our attack
# signal (MISSING in the paper) is $\xi_i(k)=\sqrt{\xi^*/2}\,[\sin k,\cos k,\sin k,\cos k]^T$,
# $\|\xi_i(k)\|^2=\xi^*$.


# %%
def attack_signal(horizon: int) -> np.ndarray:
    """xi(k) for k = 0..horizon, shape (T+1, n_y); the same for every target."""
    k = np.arange(horizon + 1)
    return np.sqrt(xi_star / 2) * np.stack([np.sin(k), np.cos(k), np.sin(k), np.cos(k)], axis=1)


XI = attack_signal(T)


def draw_randomness(rng: np.random.Generator, runs: int, horizon: int) -> dict[str, np.ndarray]:
    """All random inputs of `runs` Monte Carlo runs, drawn once (leading axis = run).

    sigma (runs, N, 4): initial offsets; w (runs, T, N): omega_i(k-1) driving x(k);
    v (runs, T, N, n_y): v_i(k); psi (runs, T, N): psi_i(k) in {0, 1} (1 = not attacked).
    """
    return {
        "sigma": rng.uniform(0.0, 1.0, (runs, N, NX)),
        "w": np.sqrt(W) * rng.standard_normal((runs, horizon, N)),
        "v": np.sqrt(V) * rng.standard_normal((runs, horizon, N, n_y)),
        "psi": (rng.uniform(0.0, 1.0, (runs, horizon, N)) < PSI).astype(float),
    }


# %% [markdown]
# ## Estimator (7)–(8) and error dynamics (11)–(12)
#
# $$\hat x_i(k|k-1)=A_i(k-1)H_\epsilon\hat x_i(k-1|k-1)+\sum_{j\in K_i}B_{i,j}H_\epsilon\hat x_j(k-1|k-1),\tag{7}$$
# $$\hat x_i(k|k)=\hat x_i(k|k-1)+L_i(k)\big(y_i(k)-\Phi_{o(k)}C_iH_\epsilon\hat x_i(k|k-1)\big).\tag{8}$$
#
# With $\Gamma=\Phi_{o(k)}C_iH_\epsilon$ and $M=I-L_i(k)\Gamma$:
# $e_i(k|k-1)=A_iH_\epsilon e_i(k-1|k-1)+\sum_jB_{i,j}H_\epsilon e_j(k-1|k-1)+E_i\omega_i$ (11) and
#
# $$e_i(k|k)=Me_i(k|k-1)-L_i\big[(\psi_i-1)\Gamma x_i(k)+\psi_i\Phi v_i(k)+(1-\psi_i)\Phi\xi_i(k)\big].\tag{12}$$
#
# (12) is correct as printed. In an attacked step ($\psi_i=0$),
# $e(k|k)=e(k|k-1)+L\Phi(C H_\epsilon\hat x(k|k-1)-\xi)$: no gain reduces the error then, it can
# only add a bias that grows with the state.
#
# ## The bound (17)–(18), re-derived from (20)–(27)
#
# **Prediction (17).** From (11), the cross terms $A_iH e_ie_j^TH^TB^T$ are bounded with
# Lemma 1 (weight $\lambda$) and, for $|K_i|\ge2$, the $e_je_l^T$ cross terms (omitted in (20))
# with $\big(\sum_{j}a_j\big)\big(\sum_j a_j\big)^T\le|K_i|\sum_ja_ja_j^T$:
#
# $$\mathfrak S_i(k|k-1)=(1+\lambda)A_iH\mathfrak S_i(k-1|k-1)H^TA_i^T+(1+\lambda^{-1})|K_i|\sum_{j\in K_i}B_{i,j}H\mathfrak S_j(k-1|k-1)H^TB_{i,j}^T+E_i\mathcal W_iE_i^T.$$
#
# **Update (18).** Expanding (12) with $\mathbb E\{(1-\psi)^2\}=1-\check\psi$, $\mathbb E\{\psi^2\}=\check\psi$,
# $\psi(1-\psi)=0$ and $\psi$ independent of everything else gives (21) *with the sign of the
# $x x^T$ term flipped* (printed $(\check\psi-1)$, correct $(1-\check\psi)$):
#
# $$\begin{aligned}P(k|k)&=MP^-M^T+(1-\check\psi)L\Gamma\,\mathbb E\{xx^T\}\Gamma^TL^T+(1-\check\psi)L\Phi\,\mathbb E\{\xi\xi^T\}\Phi^TL^T+\check\psi L\Phi\mathcal V\Phi^TL^T\\
# &\quad+(1-\check\psi)\big[M\,\mathbb E\{e^-x^T\}\Gamma^TL^T+(\cdot)^T\big]-(1-\check\psi)\big[M\,\mathbb E\{e^-\xi^T\}\Phi^TL^T+(\cdot)^T\big]-(1-\check\psi)\big[L\Gamma\,\mathbb E\{x\xi^T\}\Phi^TL^T+(\cdot)^T\big].\end{aligned}$$
#
# Lemma 1 bounds each bracket by $\alpha CC^T+\alpha^{-1}BB^T$ **whatever its sign** (weights
# $\alpha_2$ for $e^-/\xi$ (25), $\alpha_3$ for $e^-/x$ (26), $\alpha_4$ for $x/\xi$ (27)); then
# $\xi\xi^T\le\xi^*I$ (23) and $\mathbb E\{xx^T\}\le(1+\alpha_1)P^-+(1+\alpha_1^{-1})\mathbb E\{\hat x\hat x^T\}$ (24). Collecting terms:
#
# $$\mathfrak S_i(k|k)=c_0M\mathfrak S_i(k|k-1)M^T+LRL^T,\quad
# R=\kappa_x(1+\alpha_1)\Gamma\mathfrak S^-\Gamma^T+\kappa_x(1+\alpha_1^{-1})\Gamma\hat X\Gamma^T+\kappa_\xi\xi^*\Phi\Phi^T+\check\psi\Phi\mathcal V\Phi^T,$$
#
# | coefficient | re-derived (`coef="corrected"`) | printed in Theorem 2 / 3 (`coef="paper"`) |
# |---|---|---|
# | $c_0$ (on $M\mathfrak S^-M^T$) | $1+(\alpha_2+\alpha_3)(1-\check\psi)$ | $1-(\alpha_3-\alpha_2)(1-\check\psi)$ |
# | $\kappa_x$ (on the $x$ terms) | $(1-\check\psi)(1+\alpha_3^{-1}+\alpha_4)$ | $\check\psi+\alpha_3^{-1}+\alpha_4-1$ |
# | $\kappa_\xi$ (on $\xi^*$) | $(1-\check\psi)(1+\alpha_2^{-1}+\alpha_4^{-1})$ | same |
#
# (18) itself prints "$(1-(\alpha_3-\alpha_2))(1-\check\psi)$", which vanishes at $\check\psi=1$; Theorem 2,
# (43)–(49) and Theorem 3 use $1-(\alpha_3-\alpha_2)(1-\check\psi)$, which we take as "printed". The
# printed $c_0$ is always below the derived one: Lemma 1's $\alpha_3$ term enters with the wrong
# sign, and the $(1-\check\psi)$ factor on $\alpha_3^{-1},\alpha_4$ is dropped. With $\alpha_3>\alpha_2$,
# $c_0<1$, which lets a trace minimiser shrink the "bound" below the true covariance. With
# $\check\psi=1$, $K_i=\emptyset$, $\lambda\to0$ the corrected recursion is exactly the Kalman
# Riccati recursion (checked below, C6); the printed one is not ($\kappa_x=\alpha_3^{-1}+\alpha_4$).
#
# **Gain (28).** $\partial\,\mathrm{tr}\,\mathfrak S/\partial L=0$ gives $L=\Psi\Pi^{-1}$, $\Psi=c_0\mathfrak S^-\Gamma^T$,
# $\Pi=c_0\Gamma\mathfrak S^-\Gamma^T+R$ ((29) lacks a minus sign and Lemma 2's first identity is
# garbled; (28) is nevertheless the stationary point). $\Pi$ has rank $m$ (every term is
# sandwiched by $\Phi$): we solve on the scheduled rows, $\Gamma_s=(CH_\epsilon)_{\varepsilon(k)}$,
# $L_s=c_0\mathfrak S^-\Gamma_s^T\Pi_s^{-1}$, which equals $\Psi\Pi^{+}$.


# %%
def bound_coefficients(psi_bar: float, a2, a3, a4, variant: str):
    """(c0, kappa_x, kappa_xi) of (18)/(28): re-derived ("corrected") or as printed ("paper")."""
    if variant == "corrected":
        c0 = 1 + (a2 + a3) * (1 - psi_bar)
        kx = (1 - psi_bar) * (1 + 1 / a3 + a4)
    else:
        c0 = 1 - (a3 - a2) * (1 - psi_bar)
        kx = psi_bar + 1 / a3 + a4 - 1
    return c0, kx, (1 - psi_bar) * (1 + 1 / a2 + 1 / a4)


def sym(a: np.ndarray) -> np.ndarray:
    """Symmetric part over the last two axes."""
    return 0.5 * (a + np.swapaxes(a, -1, -2))


def predicted_bound(S_own, S_parents, ah, bh_list, lam, ewe, k_factor):
    """(17): S(k|k-1), batched over the leading axis; bh_list pairs with S_parents."""
    s = (1 + lam) * (ah @ S_own @ ah.T) + ewe
    factor = len(bh_list) if k_factor else 1
    for bh, S_j in zip(bh_list, S_parents, strict=True):
        s = s + (1 + 1 / lam) * factor * (bh @ S_j @ bh.T)
    return sym(s)


def gain_and_bound(S_pred, X_hat, G, c0, kx, kxi, a1, psi_bar):
    """(28) on the scheduled rows and (18): returns L_s (B, 4, rows), S(k|k), R_s.

    G (rows, 4) = scheduled rows of C H_eps; S_pred, X_hat (B, 4, 4); scalars broadcast as (B,1,1).
    """
    rows = G.shape[0]
    gsg = G @ S_pred @ G.T
    eye = np.eye(rows)
    R = kx * (1 + a1) * gsg + kx * (1 + 1 / a1) * (G @ X_hat @ G.T) + (kxi * xi_star + psi_bar * V) * eye
    Pi = sym(c0 * gsg + R)
    # divergence guard: a grid candidate whose bound exploded gets NaN instead of a crash
    bad = ~np.all(np.isfinite(Pi), axis=(-1, -2)) | ~(np.max(np.abs(Pi), axis=(-1, -2)) < 1e14)
    Pi = np.where(bad[:, None, None], eye, Pi)
    L = np.swapaxes(np.linalg.solve(Pi, c0 * (G @ S_pred)), -1, -2)
    L[bad] = np.nan
    Mm = np.eye(NX) - L @ G
    S_new = c0 * (Mm @ S_pred @ np.swapaxes(Mm, -1, -2)) + L @ R @ np.swapaxes(L, -1, -2)
    return L, sym(S_new), R


# %% [markdown]
# ## Monte Carlo core: Algorithm 1 for all runs at once
#
# `simulate` runs Algorithm 1 for the three targets over $k=1..T$ with the $F$ runs as the
# leading array axis (no Python loop over runs: the loop is over time and targets only). All
# randomness comes in through `draws`, so a run-by-run loop over slices `draws[f:f+1]` gives the
# same numbers (the benchmark suite times exactly this comparison). Targets are processed in the
# DAG order 1, 2, 3 (pitfall: $\mathfrak S_3(k|k-1)$ needs $\mathfrak S_1,\mathfrak S_2$ at $k-1$).
#
# `estimator` selects the measurement update:
# - `"zero"`: the paper's zero-input estimator (8);
# - `"zoh"`: the ZOH variant of Fig. 6 — a buffer $z_i$ holds the last received value of each
#   sensor ($z_i(0)=C_iH_\epsilon\hat x_i(0|0)$), the estimator treats $z_i(k)$ as a full fresh
#   measurement, and its gain and bound use (17)–(18), (28) with $\Phi_{o(k)}$ replaced by $I$
#   (feeding $z$ into (8) with the zero-input gain would give back the zero-input estimator, whose
#   off-schedule columns are zero);
# - `"debiased"`: ours, the same gain with $y_i-\check\psi_i\Phi C_iH_\epsilon\hat x_i(k|k-1)$ as
#   innovation (last section);
# - `"open_loop"`: no measurement update ($L=0$), the reference for "the measurements help".


# %%
def simulate(draws, weights, *, variant="corrected", moment="run", estimator="zero",
             k_factor=True, psi_bar=None, parents=None, horizon=None):
    """Algorithm 1 for every target, vectorised over the Monte Carlo runs (leading axis).

    Parameters: draws from `draw_randomness`; weights[i] = (lambda, alpha1..alpha4) of target i;
    variant "corrected"/"paper" (bound coefficients); moment "run"/"ensemble" (E[xhat xhat^T]);
    estimator "zero"/"zoh"/"debiased"/"open_loop"; psi_bar and parents override PSI and K_SETS (C6 check).
    Returns x, xhat (F, T+1, N, 4), S, S_pred (F, T+1, N, 4, 4), L (F, T+1, N, 4, n_y).
    """
    psi_bar = PSI if psi_bar is None else np.asarray(psi_bar, float)
    parents = K_SETS if parents is None else parents
    horizon = T if horizon is None else horizon
    runs = draws["sigma"].shape[0]
    x = np.zeros((runs, horizon + 1, N, NX))
    xh = np.zeros_like(x)
    S = np.zeros((runs, horizon + 1, N, NX, NX))
    S_pred = np.zeros_like(S)
    L_all = np.zeros((runs, horizon + 1, N, NX, n_y))
    x[:, 0] = X0_OFFSET + draws["sigma"]
    xh[:, 0] = x[:, 0]  # x_hat(0|0) = x(0): e(0|0) = 0
    S[:, 0] = np.eye(NX)
    z = xh[:, 0] @ CH.T  # ZOH buffer z_i(0) = C H x_hat(0|0), shape (F, N, n_y)
    for k in range(1, horizon + 1):
        ah = AH_ALL[k - 1]
        ewe = W * np.outer(E_ALL[k - 1], E_ALL[k - 1])
        sched = SETS[k - 1]
        for i in range(N):
            lam, a1, a2, a3, a4 = weights[i]
            c0, kx, kxi = bound_coefficients(psi_bar[i], a2, a3, a4, variant)
            # plant (1) and measurement, Algorithm 1 lines 3-4
            xn = x[:, k - 1, i] @ ah.T + E_ALL[k - 1] * draws["w"][:, k - 1, i, None]
            xp = xh[:, k - 1, i] @ ah.T  # prediction (7)
            for j in parents[i]:
                xn = xn + x[:, k - 1, j] @ BH[(i, j)].T
                xp = xp + xh[:, k - 1, j] @ BH[(i, j)].T
            x[:, k, i] = xn
            y_raw = xn @ CH.T + draws["v"][:, k - 1, i]
            ok = draws["psi"][:, k - 1, i, None]
            # received scheduled entries (6): replaced by xi when attacked
            y_s = ok * y_raw[:, sched] + (1 - ok) * XI[k, sched]
            Sp = predicted_bound(S[:, k - 1, i], [S[:, k - 1, j] for j in parents[i]], ah,
                                 [BH[(i, j)] for j in parents[i]], lam, ewe, k_factor)  # (17)
            S_pred[:, k, i] = Sp
            X_hat = xp[:, :, None] * xp[:, None, :]
            if moment == "ensemble":
                X_hat = np.broadcast_to(X_hat.mean(axis=0), X_hat.shape)
            if estimator == "zoh":
                z[:, i, sched] = y_s
                G, y_use, cols = CH, z[:, i], np.arange(n_y)
            else:
                G, y_use, cols = CH[sched], y_s, sched
            L, S_new, _ = gain_and_bound(Sp, X_hat, G, c0, kx, kxi, a1, psi_bar[i])  # (28), (18)
            pred = xp @ G.T
            if estimator == "debiased":
                pred = psi_bar[i] * pred
            if estimator == "open_loop":
                L = np.zeros_like(L)
            xh[:, k, i] = xp + np.einsum("frc,fc->fr", L, y_use - pred)  # update (8)
            S[:, k, i] = S_new
            L_all[:, k, i][..., cols] = L
    return {"x": x, "xhat": xh, "S": S, "S_pred": S_pred, "L": L_all}


def mse(out):
    """MSE_i(k) of Section IV: (1/F) sum_f ||x_i(k) - x_hat_i(k|k)||^2, shape (T+1, N)."""
    return np.mean(np.sum((out["x"] - out["xhat"]) ** 2, axis=-1), axis=0)


def mean_trace(out):
    """Monte Carlo mean of tr S_i(k|k), shape (T+1, N)."""
    return np.mean(np.trace(out["S"], axis1=-2, axis2=-1), axis=0)


# %% [markdown]
# ## Choosing $\lambda,\alpha_1..\alpha_4$ (Remark 4)
#
# Remark 4 suggests minimising the bound over the weights. Our grid: $\lambda\in\{10^{-3},10^{-2},10^{-1}\}$,
# $\alpha_1\in\{0.3,1,3,10\}$, $\alpha_2,\alpha_3\in\{10^{-4},\dots,1\}$, $\alpha_4\in\{0.03,0.1,0.3\}$
# (900 candidates per target); objective $\frac1T\sum_{k=1}^T\mathrm{tr}\,\mathfrak S_i(k|k)$ averaged over
# 10 pilot runs (own seed); targets optimised in DAG order with upstream weights fixed
# ($\mathfrak S_i$ depends only on its own weights and on the upstream bounds). Candidates with
# $c_0\le0$ or $\kappa_x<0$ (possible with printed coefficients), or whose bound becomes
# non-finite or exceeds $10^{10}$, are discarded: large $\lambda$ with $\alpha_2+\alpha_3\gtrsim1$
# makes $\mathfrak S$ (and the estimator) explode. All candidates × pilot runs are one array
# pass per target (the candidate index is a second batch axis). In fast mode the grid is skipped
# and the table in the parameters cell (the grid's result) is used.


# %%
def grid_search(variant: str, seed: int, pilot_runs: int,
                thm3_only: bool = False) -> list[tuple[float, ...]]:
    """Sequential Remark-4 grid: per target the candidate minimising the mean tr S_i(k|k).

    thm3_only keeps only alpha2 > alpha3 (needed by Theorem 3 with the printed c0).
    """
    cand = np.array(list(itertools.product(grid_lambda, grid_alpha1, grid_alpha23,
                                           grid_alpha23, grid_alpha4)))
    if thm3_only:
        cand = cand[cand[:, 2] > cand[:, 3]]
    n_c = len(cand)
    pilots = draw_randomness(montecarlo.spawn_rngs(seed, 1)[0], pilot_runs, T)
    chosen: list[tuple[float, ...]] = []
    for i in range(N):
        # upstream targets with their chosen weights, on the pilot runs
        up = simulate(pilots, chosen + [(1e-2, 1.0, 1e-2, 0.1, 0.1)] * (N - i), variant=variant)
        idx = np.repeat(np.arange(pilot_runs), n_c)  # batch = pilot-major, candidate-minor
        lam, a1, a2, a3, a4 = (np.tile(cand[:, q], pilot_runs)[:, None, None] for q in range(5))
        c0, kx, kxi = bound_coefficients(PSI[i], a2, a3, a4, variant)
        S_i = np.broadcast_to(np.eye(NX), (idx.size, NX, NX))
        xh_i = up["xhat"][idx, 0, i]
        total, peak = np.zeros(idx.size), np.zeros(idx.size)
        with np.errstate(all="ignore"):
            for k in range(1, T + 1):
                ah, sched = AH_ALL[k - 1], SETS[k - 1]
                xp = xh_i @ ah.T
                for j in K_SETS[i]:
                    xp = xp + up["xhat"][idx, k - 1, j] @ BH[(i, j)].T
                Sp = predicted_bound(S_i, [up["S"][idx, k - 1, j] for j in K_SETS[i]], ah,
                                     [BH[(i, j)] for j in K_SETS[i]], lam,
                                     W * np.outer(E_ALL[k - 1], E_ALL[k - 1]), coupling_factor)
                xn = up["x"][idx, k, i]
                ok = pilots["psi"][idx, k - 1, i, None]
                y_s = ok * (xn @ CH[sched].T + pilots["v"][idx, k - 1, i][:, sched]) \
                    + (1 - ok) * XI[k, sched]
                G = CH[sched]
                L, S_i, _ = gain_and_bound(Sp, xp[:, :, None] * xp[:, None, :], G, c0, kx, kxi,
                                           a1, PSI[i])
                xh_i = xp + np.einsum("frc,fc->fr", L, y_s - xp @ G.T)
                tr_k = np.trace(S_i, axis1=-2, axis2=-1)
                total += tr_k
                peak = np.maximum(peak, np.where(np.isfinite(tr_k), tr_k, np.inf))
        obj = (total / T).reshape(pilot_runs, n_c)
        peak = peak.reshape(pilot_runs, n_c)
        c0v, kxv, _ = bound_coefficients(PSI[i], cand[:, 2], cand[:, 3], cand[:, 4], variant)
        valid = np.all(np.isfinite(obj) & (peak <= 1e10), axis=0) & (c0v > 0) & (kxv >= 0)
        score = np.where(valid, np.where(np.isfinite(obj), obj, 0).mean(axis=0), np.inf)
        best = int(np.argmin(score))
        chosen.append(tuple(float(v) for v in cand[best]))
        print(f"{variant + (' (a2>a3)' if thm3_only else ''):>17} target {i + 1}: "
              f"(lambda, a1..a4) = {chosen[-1]}, "
              f"mean tr S = {score[best]:.4g}, valid candidates {valid.sum()}/{n_c}")
    return chosen


if run_grid:
    WEIGHTS = {v: grid_search(v, grid_seed, grid_pilot_runs) for v in ("corrected", "paper")}
    WEIGHTS["paper_thm3"] = grid_search("paper", grid_seed, grid_pilot_runs, thm3_only=True)
    for v, table in WEIGHT_TABLE.items():
        same = np.allclose(np.array(WEIGHTS[v]), np.array(table))
        print(f"grid result {v!r} equals the parameter table: {same}")
else:
    WEIGHTS = WEIGHT_TABLE

# %% [markdown]
# The grid optimum for targets 2 and 3 sits at its edge $\alpha_2=\alpha_3\to0$, i.e.
# $\kappa_x,\kappa_\xi\to\infty$ and $L\to0$: with attack probability ≥ 0.5 and states of
# magnitude 20–100 (RMS at $k=T$), the replacement attack makes every gain costly in the bound, so the
# trace-optimal design essentially ignores the measurements. With the printed coefficients the
# minimiser instead takes $\alpha_3>\alpha_2$, i.e. $c_0<1$, which shrinks the "bound" (next
# sections). Theorem 3 requires $1+\alpha_5+\alpha_6\le c_0$, which with the printed $c_0$ forces
# $\alpha_2>\alpha_3$; a third grid restricted to $\alpha_2>\alpha_3$ (`paper_thm3`) is run for
# comparison. Coefficients at the chosen weights:

# %%
for name, v in (("corrected", "corrected"), ("paper", "paper"), ("paper_thm3", "paper")):
    for i, (lam_, a1_, a2_, a3_, a4_) in enumerate(WEIGHTS[name]):
        c0_, kx_, kxi_ = bound_coefficients(PSI[i], a2_, a3_, a4_, v)
        print(f"{name:>10} target {i + 1}: lambda={lam_:g} a1={a1_:g} a2={a2_:g} a3={a3_:g} "
              f"a4={a4_:g} -> c0={c0_:.5g}, kappa_x={kx_:.5g}, kappa_xi={kxi_:.5g}")

# %% [markdown]
# ## The numerical example: Monte Carlo runs
#
# One draw of all randomness (`mc_seed`), shared by every estimator variant so that differences
# are due to the estimators only.

# %%
DRAWS = draw_randomness(montecarlo.spawn_rngs(mc_seed, 1)[0], F, T)
W_MAIN = WEIGHTS[coef]
out = simulate(DRAWS, W_MAIN, variant=coef, moment=xhat_moment, k_factor=coupling_factor)
out_zoh = simulate(DRAWS, W_MAIN, variant=coef, moment=xhat_moment, estimator="zoh",
                   k_factor=coupling_factor)
out_printed = simulate(DRAWS, WEIGHTS["paper"], variant="paper", moment=xhat_moment,
                       k_factor=coupling_factor)
out_printed_thm3 = simulate(DRAWS, WEIGHTS["paper_thm3"], variant="paper", moment=xhat_moment,
                            k_factor=coupling_factor)
out_corr = out if coef == "corrected" else simulate(DRAWS, WEIGHTS["corrected"],
                                                    moment=xhat_moment, k_factor=coupling_factor)
out_other_moment = simulate(DRAWS, WEIGHTS["corrected"], k_factor=coupling_factor,
                            moment="ensemble" if xhat_moment == "run" else "run")
out_debiased = simulate(DRAWS, W_MAIN, variant=coef, moment=xhat_moment, estimator="debiased",
                        k_factor=coupling_factor)
open_loop = simulate(DRAWS, W_MAIN, variant=coef, moment=xhat_moment, estimator="open_loop",
                     k_factor=coupling_factor)
# sensitivity of C2 / C7 to the weights: one interior weight set for every target
out_interior = simulate(DRAWS, W_INTERIOR, variant=coef, moment=xhat_moment,
                        k_factor=coupling_factor)
out_interior_zoh = simulate(DRAWS, W_INTERIOR, variant=coef, moment=xhat_moment, estimator="zoh",
                            k_factor=coupling_factor)
MSE, TRS = mse(out), mean_trace(out)
MSE_C, TRS_C = mse(out_corr), mean_trace(out_corr)
# the vectorised pass equals a loop over runs (first 5 runs; the benchmark times all 100)
ref = out if xhat_moment == "run" else simulate(DRAWS, W_MAIN, variant=coef,
                                                k_factor=coupling_factor)
loop_dev = 0.0
for f in range(5):
    one = simulate({key: val[f:f + 1] for key, val in DRAWS.items()}, W_MAIN, variant=coef,
                   k_factor=coupling_factor)
    for name in ("xhat", "S"):
        loop_dev = max(loop_dev, float(np.max(np.abs(one[name][0] - ref[name][f]))))
print(f"max |vectorised - loop over runs| (x_hat, S; 5 runs): {loop_dev:.3g}")
kk = np.arange(T + 1)
for name, o in (("zero-input", out), ("ZOH", out_zoh), ("printed coef.", out_printed),
                ("printed, a2>a3", out_printed_thm3),
                ("other E[xx^T]", out_other_moment), ("debiased (ours)", out_debiased),
                ("open loop", open_loop), ("interior weights", out_interior),
                ("interior, ZOH", out_interior_zoh)):
    print(f"{name:>16}: time-averaged MSE = {np.round(mse(o)[1:].mean(axis=0), 2)}, "
          f"mean tr S = {np.round(mean_trace(o)[1:].mean(axis=0), 2)}")

# %% [markdown]
# ## Figs. 2–4 — trajectories of $x_i(k)$ and their estimates (one run)
#
# Solid: true state; dashed: $\hat x_i(k|k)$. The *Y* components collapse at $k=1$ (they are
# multiplied by $\epsilon$ in (1)) and then follow $X^v$ through the coupling of $A_i$.

# %%
LABELS = ["$X^p$ [m]", "$X^v$ [m/s]", "$Y^p$ [m]", "$Y^v$ [m/s]"]
for i in range(N):
    fig, axes = plt.subplots(4, 1, figsize=(plotting.COLUMN_WIDTH * 1.6, 5.2), sharex=True)
    for c, ax in enumerate(axes):
        ax.plot(kk, out["x"][plot_run, :, i, c], "k-", lw=1.1, label=f"$x_{{{i + 1}}}$ (true)")
        ax.plot(kk, out["xhat"][plot_run, :, i, c], "--", color="tab:red", lw=1.1,
                label=f"$\\hat x_{{{i + 1}}}(k|k)$")
        ax.set_ylabel(LABELS[c])
    axes[0].legend(loc="best", ncol=2)
    axes[0].set_title(f"Fig. {i + 2}: target {i + 1}, run {plot_run}")
    axes[-1].set_xlabel("time step k [–]")
    plotting.save_figure(fig, FIG_DIR, f"fig{i + 2}_target{i + 1}_trajectories",
                         data={"k": kk, "x": out["x"][plot_run, :, i],
                               "xhat": out["xhat"][plot_run, :, i]})
    plt.show()


# %% [markdown]
# ## Figs. 5 and 6 — attack signals and estimation errors (one run), zero-input and ZOH
#
# Left: the injected signal $\Phi_{o(k)}(1-\psi_i(k))\xi_i(k)$ per channel (markers only at
# attacked steps and scheduled sensors). Right: the four components of $e_i(k|k)$. Fig. 6 uses the
# same noise and attack realisation with the ZOH estimator.

# %%
def attack_and_error_figure(o, title, name):
    fig, axes = plt.subplots(N, 2, figsize=(plotting.PAGE_WIDTH, 6.0), sharex=True,
                             layout="constrained")
    data = {"k": kk[1:]}
    for i in range(N):
        attacked = DRAWS["psi"][plot_run, :, i] == 0
        injected = np.full((T, n_y), np.nan)
        for k in range(1, T + 1):
            if attacked[k - 1]:
                injected[k - 1, SETS[k - 1]] = XI[k, SETS[k - 1]]
        for r in range(n_y):
            axes[i, 0].plot(kk[1:], injected[:, r], "o", ms=2.2, label=f"sensor {r + 1}")
        err = o["x"][plot_run, 1:, i] - o["xhat"][plot_run, 1:, i]
        for c in range(NX):
            axes[i, 1].plot(kk[1:], err[:, c], lw=0.9, label=LABELS[c].split(" ")[0])
        axes[i, 0].set_ylabel(f"target {i + 1}\nattack [–]")
        axes[i, 1].set_ylabel(f"$e_{{{i + 1}}}(k|k)$ [m, m/s]")
        data[f"attack_target{i + 1}"] = injected
        data[f"error_target{i + 1}"] = err
    axes[0, 0].legend(ncol=4, fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 1.02),
                      handletextpad=0.1, columnspacing=0.8)
    axes[0, 1].legend(ncol=4, fontsize=7, loc="lower left", bbox_to_anchor=(0.0, 1.02))
    axes[-1, 0].set_xlabel("time step k [–]")
    axes[-1, 1].set_xlabel("time step k [–]")
    fig.suptitle(title)
    plotting.save_figure(fig, FIG_DIR, name, data=data)
    plt.show()


attack_and_error_figure(out, f"Fig. 5: attack signals and errors, zero-input, run {plot_run}",
                        "fig5_attack_and_errors")
attack_and_error_figure(out_zoh, f"Fig. 6: attack signals and errors, ZOH, run {plot_run}",
                        "fig6_attack_and_errors_zoh")

# %% [markdown]
# ## Fig. 7 — $\mathrm{MSE}_i(k)$ over $F=100$ runs and the minimum upper bound
#
# The gain depends on the run (through $\hat x\hat x^T$), so $\mathfrak S_i$ differs across runs and
# MSE is compared with the Monte Carlo mean of $\mathrm{tr}\,\mathfrak S_i(k|k)$. At $k=1$ the MSE is
# ~1e−4 or smaller ($E_i(0)=0$); the log axes start at $k=1$ and are clipped at $10^{-2}$. First with the corrected
# coefficients (our reproduction of Fig. 7, ZOH MSE added dashed), then with the printed ones.

# %%
def fig7(o, o_zoh, title, name):
    fig, axes = plt.subplots(1, N, figsize=(plotting.PAGE_WIDTH, 2.9), sharex=True,
                             layout="constrained")
    m_, t_ = mse(o), mean_trace(o)
    data = {"k": kk[1:], "mse": m_[1:], "mean_tr_S": t_[1:]}
    for i, ax in enumerate(axes):
        ax.semilogy(kk[1:], t_[1:, i], color="tab:blue", label="upper bound (mean tr $\\mathfrak{S}$)")
        ax.semilogy(kk[1:], m_[1:, i], color="tab:red", label="MSE (zero-input)")
        if o_zoh is not None:
            ax.semilogy(kk[1:], mse(o_zoh)[1:, i], "--", color="tab:gray", lw=0.9, label="MSE (ZOH)")
        ax.set_title(f"target {i + 1}")
        ax.set_xlabel("time step k [–]")
        ax.set_ylim(bottom=1e-2)  # MSE(1) ~ 1e-4..1e-10 (E_i(0) = 0) lies below the axis
    if o_zoh is not None:
        data["mse_zoh"] = mse(o_zoh)[1:]
    axes[0].set_ylabel("MSE$_i(k)$, tr bound [m², m²/s²]")
    axes[0].legend(loc="lower right", fontsize=7)
    fig.suptitle(title)
    plotting.save_figure(fig, FIG_DIR, name, data=data)
    plt.show()


fig7(out_corr, out_zoh if coef == "corrected" else None,
     "Fig. 7: MSE and minimum upper bound (corrected coefficients)", "fig7_mse_and_bound")
fig7(out_printed, None, "Fig. 7 with the printed coefficients: the 'bound' is below the MSE",
     "extra_fig7_printed_coefficients")

# %% [markdown]
# ### What C1 shows, and what it does not
#
# With `xhat_moment="run"` the surrogate of $\mathbb E\{\hat x\hat x^T\}$ in (18), (28) is the run's own
# $\hat x_i(k|k-1)\hat x_i^T(k|k-1)$, so the gain $L_i(k)$ is a function of that run's measurements.
# The derivation of (21) takes $L_i(k)$ out of the expectation, i.e. it treats the gain as
# deterministic; with a data-dependent gain the expectations $\mathbb E\{L e e^TL^T\}$ do not factor
# that way, and the corrected Theorem 1 no longer implies $\mathrm{MSE}_i(k)\le\mathrm{tr}\,\mathfrak S_i(k|k)$.
# **C1 is therefore an empirical result of our runs, not a consequence of the corrected theorem.**
# The ensemble variant (`xhat_moment="ensemble"`: the Monte Carlo mean of $\hat x\hat x^T$, hence the
# same gain in every run — still data-dependent through the ensemble, deterministic only as
# $F\to\infty$) is closer to the derivation's assumption; it gives the same verdict (below,
# and in C1's `measured`).
#
# ### ZOH against zero-input (Fig. 6, C2): only target 1 is informative
#
# For targets 2 and 3 the grid-chosen gain is ~0 ($\kappa_x\approx5000$–$7000$), so both
# estimators are essentially the open-loop prediction and their MSE ratio is ≈ 1 whatever the
# update does; target 3's ratio is even slightly below 1 (ZOH marginally better) and passes only
# through our 0.95 tolerance. Only target 1 (gain ≈ 0.36) supports "ZOH does not improve". With
# the interior weight set `weights_interior` every target has a non-negligible gain; the
# ratios for that run are printed below and recorded in C2.

# %%
def frac_below(o):
    return np.mean(mse(o)[1:] <= mean_trace(o)[1:], axis=0)


def time_avg_ratio(o_num, o_den):
    return mse(o_num)[1:].mean(axis=0) / mse(o_den)[1:].mean(axis=0)


max_gain = {name: np.abs(o["L"]).max(axis=(0, 1, 3, 4)) for name, o in
            (("grid", out), ("interior", out_interior))}
print(f"{'target':>6} | C1 frac (run) | C1 frac (ensemble) | min gap (run / ensemble) | "
      "ZOH/zero (grid w.) | ZOH/zero (interior w.) | max|L| grid / interior")
run_o, ens_o = ((out_corr, out_other_moment) if xhat_moment == "run"
                else (out_other_moment, out_corr))
for i in range(N):
    gap_r = (mean_trace(run_o) - mse(run_o))[1:, i].min()
    gap_e = (mean_trace(ens_o) - mse(ens_o))[1:, i].min()
    print(f"{i + 1:>6} | {frac_below(run_o)[i]:13.3f} | {frac_below(ens_o)[i]:18.3f} | "
          f"{gap_r:10.4f} / {gap_e:10.4f} | {time_avg_ratio(out_zoh, out)[i]:18.4f} | "
          f"{time_avg_ratio(out_interior_zoh, out_interior)[i]:22.4f} | "
          f"{max_gain['grid'][i]:.3g} / {max_gain['interior'][i]:.3g}")

# %% [markdown]
# With the grid restricted to $\alpha_2>\alpha_3$ (Theorem 3's condition) the printed recursion
# stays above the MSE in our runs (C1b, reported), but its minimiser then drives every gain to ~0:
# target 1's MSE becomes that of the open-loop prediction. Either way the printed coefficients
# give no useful proven bound (even with $\alpha_2>\alpha_3$ the printed $c_0$ is below the
# derived one by $2\alpha_3(1-\check\psi)$, so the induction of Theorem 1 does not go through).
#
# ### A one-step counterexample for the printed coefficients
#
# The Monte Carlo failure above has a deterministic core. Take one update step with
# $\mathfrak S^-=P^-$ known, $\hat x^-$ known (so $\mathbb E\{xx^T\}=P^-+\hat x^-\hat x^{-T}$,
# $\mathbb E\{e^-x^T\}=P^-$), a deterministic $\xi$ and zero-mean $e^-$: the exact covariance after
# the update is the corrected (21) without any inequality. We evaluate it for target 3 at
# $k=2$ of run `plot_run` with the weights in use and each variant's own gain, and compare it with
# each variant's bound.

# %%
def one_step_check(o, weights, variant, i=2, k=2, f=plot_run):
    Sp = o["S_pred"][f, k, i]
    xp = (AH_ALL[k - 1] @ o["xhat"][f, k - 1, i]
          + sum(BH[(i, j)] @ o["xhat"][f, k - 1, j] for j in K_SETS[i]))
    lam_, a1_, a2_, a3_, a4_ = weights[i]
    c0_, kx_, kxi_ = bound_coefficients(PSI[i], a2_, a3_, a4_, variant)
    G = CH[SETS[k - 1]]
    Phi_xi = XI[k, SETS[k - 1]]
    L, S_b, _ = gain_and_bound(Sp[None], np.outer(xp, xp)[None], G, c0_, kx_, kxi_, a1_, PSI[i])
    L, S_b = L[0], S_b[0]
    Mm = np.eye(NX) - L @ G
    p = 1 - PSI[i]
    Ex = Sp + np.outer(xp, xp)
    exact = (Mm @ Sp @ Mm.T + p * L @ G @ Ex @ G.T @ L.T + p * L @ np.outer(Phi_xi, Phi_xi) @ L.T
             + PSI[i] * V * L @ L.T + p * (Mm @ Sp @ G.T @ L.T + L @ G @ Sp @ Mm.T)
             - p * (L @ G @ np.outer(xp, Phi_xi) @ L.T + L @ np.outer(Phi_xi, xp) @ G.T @ L.T))
    return np.linalg.eigvalsh(S_b - sym(exact)).min(), np.trace(exact), np.trace(S_b)


one_step = {}
for v, o in (("corrected", out_corr), ("paper", out_printed)):
    one_step[v] = one_step_check(o, WEIGHTS[v], v)
    print(f"{v:>9}: lambda_min(bound - exact covariance) = {one_step[v][0]:.4g}, "
          f"tr exact = {one_step[v][1]:.4g}, tr bound = {one_step[v][2]:.4g}")

# %% [markdown]
# ## Fig. 8 — $\|e_i(k|k)\|^2$ and $UB_i(k)$ (Theorem 3, made consistent)
#
# **Lemma 3 / (56) made consistent.** Lemma 3 as printed swaps the roles of the rate and the
# additive constant. Iterating $\mathbb E V_k\le(1-\rho)\mathbb E V_{k-1}+\mu$ with
# $v_*\|\zeta\|^2\le V\le v^*\|\zeta\|^2$ gives
# $\mathbb E\|\zeta_k\|^2\le\frac{v^*}{v_*}\mathbb E\|\zeta_0\|^2(1-\rho)^k+\frac{\mu}{v_*}\sum_{l=0}^{k-1}(1-\rho)^l$
# (the sum starts at $l=0$). With $V=e^T\mathfrak S^{-1}e$ and $\phi_*I\le\mathfrak S(k|k)\le\phi^*I$,
#
# $$UB_i(k)=\frac{\phi^*}{\phi_*}\mathbb E\|e_i(0|0)\|^2(1-\rho)^k+\mu\phi^*\sum_{l=0}^{k-1}(1-\rho)^l,\qquad
# \rho=1-\Big(1+\lambda+\frac{\chi_1}{(h^*a^*)^2\phi^*}\Big)^{-1},$$
#
# $\mu=(1+\alpha_5^{-1}+\alpha_7)\mu_1+(1+\alpha_6^{-1}+\alpha_7^{-1})\mu_2$ ((56) and the Fig. 8 text have
# $\rho$ and $\mu$ interchanged). On the example the literal constants degenerate ($E_i$ is 4×1 and
# every $B_{i,j}$ singular, so $e_*=b_*=0$, $\chi_1=0$; $\Pi$ is singular so $\pi_*=0$), so we use a
# data-driven recipe per target over all runs and $k$:
# $\phi_*=\min\lambda_{\min}\mathfrak S(k|k)$, $\phi^*=\max\lambda_{\max}\mathfrak S(k|k)$;
# $\rho=\lambda/(1+\lambda)$; $\alpha_5=\alpha_6=(c_0-1)/2$ (meets $1+\alpha_5+\alpha_6\le c_0$);
# $\alpha_7=\sqrt{\mu_2/\mu_1}$ (minimises $\mu$);
# $\mu_1=\bar g/(c_0\min\lambda_{\min}\mathfrak S(k|k-1))$ with
# $\bar g=\max\mathrm{tr}(E_i\mathcal W E_i^T)+|K_i|\sum_{j\in K_i}\|B_{i,j}H_\epsilon\|^2 n_x\phi^*_j$ ((47)–(49) with
# lower/upper constants put where the inequalities need them);
# $\mu_2=\Lambda\bar t/\phi_*$ with $\Lambda=\max\|L_i\|_2^2$ (52) and
# $\bar t=\check\psi n_y\mathcal V+(1-\check\psi)\big(\sqrt{\xi^*}+\|CH_\epsilon\|_2\sqrt{\max_k\mathbb E\|x_i\|^2}\big)^2$
# ((50) with $(1-\check\psi)$ instead of $(\check\psi-1)$ and the missing $\check\psi\,\mathrm{tr}\mathcal V$ term);
# $\mathbb E\|e_i(0|0)\|^2=0$ here. This recipe reads $\phi_*,\phi^*,\Lambda$ and $\mathbb E\|x_i\|^2$ off the
# very trajectories it is then compared with, so $\|e_i(k|k)\|^2\le UB_i(k)$ is **not a test of
# Theorem 3**: it only shows the envelope the theorem's form gives with constants taken from the
# data. Whether the theorem's own conditions hold is checked first.
#
# ### Theorem 3's own conditions on the example (C3a)
#
# Besides Assumption 1 and $\mathbb E\{x_ix_i^T\}\le(X^*)^2I$, Theorem 3 requires, for
# $\phi_*I\le\mathfrak S_i(0|0)=I\le\phi^*I$: (a) $1+\alpha_5+\alpha_6\le1-(\alpha_3-\alpha_2)(1-\check\psi_i)$
# for some positive $\alpha_5,\alpha_6$, i.e. a printed $c_0>1$; (b) $\eta_*\ge\phi_*$; (c) $\eta^*\le\phi^*$,
# where $\eta_*,\eta^*$ are the printed functions of $(\phi_*,\phi^*)$ through $\varpi_*,\varpi^*,\pi_*,\pi^*,\Gamma_*,\Gamma^*$.
# We evaluate them with the literal Assumption-1 constants of the example: $a_*^2,(a^*)^2$ the
# extreme eigenvalues of $A_i(k)A_i^T(k)$, $h_*=\epsilon$, $h^*=1$, $c_*=c^*=1$, $e_*=0$,
# $(e^*)^2=\max_k\|E_i(k)\|^2$, $b_*,b^*$ from $\sum_jB_{i,j}$, $q=\mathcal W$, $r=\mathcal V$,
# $\wp_i=\lambda_{\min}(H_\epsilon C_i^TC_iH_\epsilon)=\epsilon^2$; $(X^*)^2$ the smallest admissible value,
# $\max_k\lambda_{\max}$ of the Monte Carlo $\mathbb E\{x_ix_i^T\}$; "tr" in $\Gamma^*$ read as the
# scalar itself. Weights: those in use, once with the printed coefficients (the theorem as stated)
# and once with the corrected ones substituted; and the $\alpha_2>\alpha_3$ weights (`paper_thm3`),
# the only grid result for which (a) can hold with the printed $c_0$. (b) and (c) are evaluated
# at the data-driven $(\phi_*,\phi^*)$ of the envelope below and on a log grid of all pairs
# $\phi_*\le1\le\phi^*$ (`phi_scan`). Independently, (36) claims $\Gamma_*I\le L_i\Phi_{o(k)}C_iH_\epsilon$
# with $\Gamma_*>0$; that matrix has rank at most $m=2<4$, so this lower bound cannot hold (the
# rank is recorded).


# %%
def theorem3_conditions(o, weights, variant):
    """Theorem 3's conditions (a)-(c) with the printed eta_*, eta^* and literal Assumption-1
    constants; `variant` selects the coefficients c0, kappa_x substituted into them."""
    aat = np.linalg.eigvalsh(A_ALL[:T] @ np.swapaxes(A_ALL[:T], -1, -2))
    a_lo2, a_hi2 = aat.min(), aat.max()
    h_lo, h_hi, c2 = epsilon, 1.0, np.linalg.eigvalsh(C_MAT @ C_MAT.T)  # c2 = [1, 1, 1, 1]
    ee = np.linalg.eigvalsh(E_ALL[:T, :, None] * E_ALL[:T, None, :])
    e_lo2, e_hi2 = max(ee.min(), 0.0), ee.max()
    wp = np.linalg.eigvalsh(H_EPS @ C_MAT.T @ C_MAT @ H_EPS).min()
    axis = np.logspace(phi_scan[0], phi_scan[1], int(phi_scan[2]))
    lo_g, hi_g = np.meshgrid(axis[axis <= 1], axis[axis >= 1], indexing="ij")
    rows = []
    for i in range(N):
        lam_, a1_, a2_, a3_, a4_ = weights[i]
        ps = PSI[i]
        c0_, kx_, _ = bound_coefficients(ps, a2_, a3_, a4_, variant)
        tail = (1 + 1 / a2_ + 1 / a4_) * (1 - ps)  # printed factor of xi^* (and of Gamma^2)
        bsum = sum((B_MAT[(i, j)] for j in K_SETS[i]), np.zeros((NX, NX)))
        bb = np.linalg.eigvalsh(bsum @ bsum.T)
        b_lo2, b_hi2 = max(bb.min(), 0.0), bb.max()
        exx = np.einsum("fkr,fkc->krc", o["x"][:, 1:, i], o["x"][:, 1:, i]) / o["x"].shape[0]
        x2 = np.linalg.eigvalsh(exx).max()

        def eta(p_lo, p_hi, lam_=lam_, a1_=a1_, c0_=c0_, kx_=kx_, tail=tail, ps=ps,
                b_lo2=b_lo2, b_hi2=b_hi2, x2=x2):
            w_lo = ((1 + lam_) * h_lo**2 * a_lo2 + (1 + 1 / lam_) * h_lo**2 * b_lo2) * p_lo + e_lo2 * W
            w_hi = ((1 + lam_) * h_hi**2 * a_hi2 + (1 + 1 / lam_) * h_hi**2 * b_hi2) * p_hi + e_hi2 * W
            pi_lo = (c0_ + (1 + a1_) * kx_) * c2.min() * w_lo + tail * xi_star + ps * V
            pi_hi = ((c0_ + (1 + a1_) * kx_ + kx_ * (1 + 1 / a1_) ** 2) * c2.max() * w_hi
                     + kx_ * (1 + 1 / a1_) * (1 + a1_) * x2 * c2.max() + tail * xi_star + ps * V)
            g_lo = c0_ * w_lo * wp / pi_hi  # Gamma_*
            g_hi = c0_ * w_hi * h_hi**2 * c2.max() / pi_lo  # Gamma^*
            eta_lo = (c0_ * w_lo * (1 - g_hi) ** 2 + (1 + a1_) * kx_ * w_lo * g_lo**2
                      + (tail + ps * V) * g_lo**2)
            eta_hi = (c0_ * w_hi * (1 - g_hi) ** 2 + (1 + a1_) * kx_ * w_hi * g_hi**2
                      + (1 + 1 / a1_) * kx_ * ((1 + a1_) * x2 + (1 + 1 / a1_) * w_hi) * g_hi**2
                      + (tail + ps * V) * g_hi**2)
            return eta_lo, eta_hi

        ev = np.linalg.eigvalsh(o["S"][:, :, i])
        phi_lo, phi_hi = float(ev.min()), float(ev.max())
        eta_lo, eta_hi = eta(phi_lo, phi_hi)
        eta_lo_g, eta_hi_g = eta(lo_g, hi_g)
        rows.append({
            "c0": float(c0_), "a_alpha56_exist": bool(c0_ > 1), "X_star_sq": float(x2),
            "phi_lower": phi_lo, "phi_upper": phi_hi, "eta_lower": float(eta_lo),
            "eta_upper": float(eta_hi), "b_at_data": bool(eta_lo >= phi_lo),
            "c_at_data": bool(eta_hi <= phi_hi),
            "b_any_on_grid": bool(np.any(eta_lo_g >= lo_g)),
            "c_any_on_grid": bool(np.any(eta_hi_g <= hi_g)),
            "bc_pair_on_grid": bool(np.any((eta_lo_g >= lo_g) & (eta_hi_g <= hi_g))),
            "min_eta_upper_over_phi_upper": float(np.min(eta_hi_g / hi_g)),
        })
    return rows


THM3_COND = {
    "printed, weights in use": theorem3_conditions(out_corr, WEIGHTS["corrected"], "paper"),
    "corrected, weights in use": theorem3_conditions(out_corr, WEIGHTS["corrected"], "corrected"),
    "printed, alpha2 > alpha3 weights": theorem3_conditions(out_printed_thm3,
                                                            WEIGHTS["paper_thm3"], "paper"),
}
THM3_RANK = max(int(np.linalg.matrix_rank(out_corr["L"][f, k, i] @ CH))
                for f in range(out_corr["L"].shape[0]) for k in range(1, T + 1) for i in range(N))
for name, rows_ in THM3_COND.items():
    for i, r in enumerate(rows_):
        print(f"{name:>32} target {i + 1}: c0 = {r['c0']:.5g} (a) {r['a_alpha56_exist']}; "
              f"at data phi = ({r['phi_lower']:.3g}, {r['phi_upper']:.4g}): eta_* = "
              f"{r['eta_lower']:.3g} (b) {r['b_at_data']}, eta^* = {r['eta_upper']:.3g} "
              f"(c) {r['c_at_data']}; grid: (b) {r['b_any_on_grid']}, (c) {r['c_any_on_grid']}, "
              f"both {r['bc_pair_on_grid']}, min eta^*/phi^* = "
              f"{r['min_eta_upper_over_phi_upper']:.3g}")
print(f"max rank of L_i(k) Phi C_i H_eps over runs, k, i: {THM3_RANK} (n_x = {NX})")

# %% [markdown]
# Condition (c) fails everywhere: $\eta^*$ grows like $(\phi^*)^3$ for large $\phi^*$ (through
# $\varpi^*\Gamma^{*2}$) and carries $(X^*)^2\Gamma^{*2}$ with $(X^*)^2$ in the hundreds to tens of thousands, so no pair
# $\phi_*\le1\le\phi^*$ on the grid satisfies $\eta^*\le\phi^*$ (the smallest ratio $\eta^*/\phi^*$ is
# printed above), with the printed or the corrected coefficients, and (a) fails for the weights
# in use with the printed $c_0\le1$. **Theorem 3's premise is not met on the paper's own example**,
# so the theorem supplies no envelope there (C3a). The $UB_i(k)$ below is the data-driven one.


# %%
def theorem3_envelope(o, weights, variant):
    ev = np.linalg.eigvalsh(o["S"])  # (F, T+1, N, 4)
    ev_pred = np.linalg.eigvalsh(o["S_pred"][:, 1:])
    env, info = np.zeros((T + 1, N)), {}
    for i in range(N):
        lam_, a1_, a2_, a3_, a4_ = weights[i]
        c0_, _, _ = bound_coefficients(PSI[i], a2_, a3_, a4_, variant)
        phi_lo, phi_hi = ev[:, :, i].min(), ev[:, :, i].max()
        rho = lam_ / (1 + lam_)  # chi_1 = 0 on the example
        g_bar = W * np.max(np.sum(E_ALL**2, axis=1))
        for j in K_SETS[i]:
            g_bar += len(K_SETS[i]) * np.linalg.norm(BH[(i, j)], 2) ** 2 * NX * ev[:, :, j].max()
        mu1 = g_bar / (c0_ * ev_pred[:, :, i].min())
        lam_L = np.max(np.linalg.norm(o["L"][:, 1:, i], ord=2, axis=(-2, -1)) ** 2)
        ex2 = np.max(np.mean(np.sum(o["x"][:, :, i] ** 2, axis=-1), axis=0))
        t_bar = PSI[i] * n_y * V + (1 - PSI[i]) * (np.sqrt(xi_star)
                                                    + np.linalg.norm(CH, 2) * np.sqrt(ex2)) ** 2
        mu2 = lam_L * t_bar / phi_lo
        a5 = a6 = (c0_ - 1) / 2
        a7 = np.sqrt(mu2 / mu1)
        if a5 > 0:
            mu = (1 + 1 / a5 + a7) * mu1 + (1 + 1 / a6 + 1 / a7) * mu2
        else:  # c0 <= 1 (printed coefficients): Theorem 3's condition cannot hold
            mu = np.inf
        e0 = np.mean(np.sum((o["x"][:, 0, i] - o["xhat"][:, 0, i]) ** 2, axis=-1))
        geo = np.concatenate([[0.0], np.cumsum((1 - rho) ** np.arange(T))])
        env[:, i] = phi_hi / phi_lo * e0 * (1 - rho) ** kk + mu * phi_hi * geo
        info[i] = {"phi_lower": phi_lo, "phi_upper": phi_hi, "rho": rho, "mu": mu}
        print(f"target {i + 1}: phi_* = {phi_lo:.3g}, phi^* = {phi_hi:.4g}, rho = {rho:.3g}, "
              f"mu1 = {mu1:.3g}, mu2 = {mu2:.3g}, mu = {mu:.3g}, UB(T) = {env[-1, i]:.3g}")
    return env, info


UB, UB_INFO = theorem3_envelope(out_corr, WEIGHTS["corrected"], "corrected")
ERR2 = np.sum((out_corr["x"] - out_corr["xhat"]) ** 2, axis=-1)  # (F, T+1, N)

fig, axes = plt.subplots(1, N, figsize=(plotting.PAGE_WIDTH, 2.9), sharex=True,
                         layout="constrained")
for i, ax in enumerate(axes):
    ax.semilogy(kk[1:], UB[1:, i], color="tab:blue", label="$UB_i(k)$")
    ax.semilogy(kk[1:], ERR2[plot_run, 1:, i], color="tab:red", lw=0.9,
                label=f"$\\|e_i(k|k)\\|^2$ (run {plot_run})")
    ax.set_ylim(bottom=1e-4)  # ||e(1|1)||^2 can be ~1e-12 (E_i(0) = 0)
    ax.set_title(f"target {i + 1}")
    ax.set_xlabel("time step k [–]")
axes[0].set_ylabel("squared error [m², m²/s²]")
axes[0].legend(loc="center right", fontsize=7)
fig.suptitle("Fig. 8: $\\|e_i(k|k)\\|^2$ and the data-driven envelope $UB_i(k)$ "
             "(Theorem 3's conditions fail)")
plotting.save_figure(fig, FIG_DIR, "fig8_error_and_envelope",
                     data={"k": kk[1:], "UB": UB[1:], "err2_run": ERR2[plot_run, 1:]})
plt.show()
print("UB_i(T) / max_k MSE_i(k):", np.round(UB[-1] / mse(out_corr)[1:].max(axis=0), -6))

# %% [markdown]
# Every $\|e_i(k|k)\|^2$ stays below $UB_i(k)$ — but $UB_i(T)$ is $10^{13}$–$10^{17}$, more than
# $10^{11}$ times the largest MSE (ratio printed above): with constants taken from the data the
# inequality is vacuous, and since the conditions of Theorem 3 fail (C3a) it is not evidence for the
# theorem (C3b records it as measured, no more).
#
# ## Kalman limit (C6)
#
# With no attack ($\check\psi_i=1$, all $\psi_i(k)=1$), no coupling ($K_i=\emptyset$) and
# $\lambda=0$, the corrected $c_0=1$, $\kappa_x=\kappa_\xi=0$ and (17), (18), (28) must reduce to the
# time-varying Kalman filter on the scheduled rows. We compare with a textbook Riccati recursion
# in covariance form, $P^-=FPF^T+Q$, $K=P^-H^T(HP^-H^T+R)^{-1}$, $P=(I-KH)P^-$, and its estimates.

# %%
kal_draws = {key: val[:3].copy() for key, val in DRAWS.items()}
kal_draws["psi"][:] = 1.0
no_parents = {i: () for i in range(N)}
kal = simulate(kal_draws, [(0.0, 1.0, 1.0, 1.0, 1.0)] * N, psi_bar=np.ones(N),
               parents=no_parents)  # lambda = 0 is allowed: without parents 1/lambda is unused
kal_dev_P, kal_dev_x = 0.0, 0.0
for i in range(N):
    P = np.eye(NX)
    xk = kal["x"][:, 0, i].copy()
    for k in range(1, T + 1):
        Fk, Hk = AH_ALL[k - 1], CH[SETS[k - 1]]
        P_pred = Fk @ P @ Fk.T + W * np.outer(E_ALL[k - 1], E_ALL[k - 1])
        K_gain = P_pred @ Hk.T @ np.linalg.inv(Hk @ P_pred @ Hk.T + V * np.eye(m))
        P = (np.eye(NX) - K_gain @ Hk) @ P_pred
        y_k = kal["x"][:, k, i] @ CH.T + kal_draws["v"][:, k - 1, i]
        xk = xk @ Fk.T
        xk = xk + (y_k[:, SETS[k - 1]] - xk @ Hk.T) @ K_gain.T
        kal_dev_P = max(kal_dev_P, np.max(np.abs(kal["S"][:, k, i] - P)) / max(1.0, np.abs(P).max()))
        kal_dev_x = max(kal_dev_x, np.max(np.abs(kal["xhat"][:, k, i] - xk)))
print(f"max relative deviation of S from the Riccati P: {kal_dev_P:.3g}; "
      f"max deviation of the estimates: {kal_dev_x:.3g}")
c0_p, kx_p, _ = bound_coefficients(1.0, 1.0, 1.0, 1.0, "paper")
print(f"printed coefficients at psi = 1, alpha = 1: c0 = {c0_p}, kappa_x = {kx_p} (not Kalman)")

# %% [markdown]
# ## Why the estimates do not track well, and the smallest fix (ours)
#
# With (8) uncompensated, the expected innovation is
# $\mathbb E\{y_i\}-\Gamma\hat x^-=\check\psi_i\Gamma x_i+(1-\check\psi_i)\Phi\xi_i-\Gamma\hat x^-$, so the mean error obeys
# $\mathbb E e(k|k)=(I-L\Gamma)\mathbb E e(k|k-1)+(1-\check\psi_i)L\Gamma\,\mathbb E x_i(k)-(1-\check\psi_i)L\Phi\xi_i$:
# every attacked step pulls the estimate toward $\xi\approx0$, a bias proportional to the
# state. The smallest change that removes it is one factor in the innovation,
# $y_i(k)-\check\psi_i\Phi C_iH_\epsilon\hat x_i(k|k-1)$ (same gain), which gives
# $\mathbb E e(k|k)=(I-\check\psi_iL\Gamma)\mathbb E e(k|k-1)-(1-\check\psi_i)L\Phi\xi_i$: only the bounded
# $\xi$ remains. It helps where the gain is not ~0 (target 1); for targets 2 and 3 the
# trace-optimal gain is ~0 and the estimate is close to the open-loop prediction either way; their
# remaining mean error is mostly the Monte Carlo mean of the open-loop prediction error (dotted:
# the prediction error is unbiased, but with $F=100$ runs its sample mean is of the order of
# $\sqrt{\mathrm{MSE}/F}\approx2$–3 m) plus the small bias that the tiny gains still pick up. This
# estimator is ours, not the paper's, and its $\mathfrak S$ is not claimed to be a bound.
#
# **Is the open-loop behaviour of targets 2, 3 an artefact of the grid edge?** Only partly: with
# the interior weight set `weights_interior` (gains up to ~1 for targets 2, 3) their estimates get
# *worse*, not better (time-averaged MSE and relative RMS in the printout of the Monte Carlo
# section and in C7): with attack probabilities 0.5 and 0.7 a non-zero gain pulls the estimate
# toward $\xi\approx0$ in most steps. "Tracking does not match" therefore holds for a
# non-degenerate gain too; target 1 is nearly unchanged.

# %%
ERR_MEAN = (out["x"] - out["xhat"]).mean(axis=0)  # (T+1, N, 4)
ERR_MEAN_DB = (out_debiased["x"] - out_debiased["xhat"]).mean(axis=0)
ERR_MEAN_OL = (open_loop["x"] - open_loop["xhat"]).mean(axis=0)  # Monte Carlo noise level
fig, axes = plt.subplots(2, N, figsize=(plotting.PAGE_WIDTH, 4.6), sharex=True,
                         layout="constrained")
for i in range(N):
    axes[0, i].semilogy(kk[1:], MSE[1:, i], color="tab:red", label="paper (8)")
    axes[0, i].semilogy(kk[1:], mse(out_debiased)[1:, i], color="tab:green",
                        label="debiased innovation (ours)")
    axes[0, i].semilogy(kk[1:], mse(open_loop)[1:, i], ":", color="k", lw=0.9,
                        label="open-loop prediction")
    axes[0, i].set_title(f"target {i + 1}")
    axes[0, i].set_ylim(bottom=1e-2)
    axes[1, i].plot(kk, ERR_MEAN[:, i, 0], color="tab:red", label="paper (8)")
    axes[1, i].plot(kk, ERR_MEAN_DB[:, i, 0], color="tab:green", label="debiased (ours)")
    axes[1, i].plot(kk, ERR_MEAN_OL[:, i, 0], ":", color="k", lw=0.9, label="open-loop prediction")
    axes[1, i].axhline(0.0, color="k", lw=0.6)
    axes[1, i].set_xlabel("time step k [–]")
axes[0, 0].set_ylabel("MSE$_i(k)$ [m², m²/s²]")
axes[1, 0].set_ylabel("mean error of $X^p$ [m]")
axes[0, 0].legend(fontsize=7, loc="lower right")
fig.suptitle(f"Ours: removing the attack-induced bias ({F} runs)")
plotting.save_figure(fig, FIG_DIR, "extra_debiased_estimator",
                     data={"k": kk, "mse_paper": MSE, "mse_debiased": mse(out_debiased),
                           "mse_open_loop": mse(open_loop), "mean_err_Xp_paper": ERR_MEAN[:, :, 0],
                           "mean_err_Xp_debiased": ERR_MEAN_DB[:, :, 0],
                           "mean_err_Xp_open_loop": ERR_MEAN_OL[:, :, 0]})
plt.show()

# %% [markdown]
# ## Claims
#
# | id | paper | what we measure |
# |---|---|---|
# | C1 | Fig. 7: MSE$_i(k)$ always below the minimum upper bound | MSE$_i(k)\le$ mean$_f$ tr $\mathfrak S^{(f)}_i(k\|k)$ for all $k=1..T$, corrected coefficients; an empirical result (the gain depends on the run's data), the ensemble variant reported next to it |
# | C1b | the same with the coefficients as printed (Theorem 2) | fraction of $k$ where it holds, grid-chosen weights; plus the one-step exact counterexample |
# | C2 | Fig. 6 / Remark 2: ZOH does not improve on zero-input | $r_i$ = time-averaged MSE (ZOH) / time-averaged MSE (zero-input) ≥ 0.95; only target 1 is informative (gain ≈ 0 for 2, 3); ratios with `weights_interior` reported |
# | C3a | Theorem 3: its conditions (a) $1+\alpha_5+\alpha_6\le c_0$, (b) $\eta_*\ge\phi_*$, (c) $\eta^*\le\phi^*$ | evaluated with the literal Assumption-1 constants at the data-driven $\phi$'s and on a $(\phi_*,\phi^*)$ grid; holds if all three can be met for every target |
# | C3b | Fig. 8: $\|e_i(k\|k)\|^2$ below $UB_i(k)$ | with the **data-driven** envelope: $\|e_i(k\|k)\|^2\le UB_i(k)$ for every run and $k$, MSE$_i(k)\le UB_i(k)$; the envelope ($10^{13}$–$10^{17}$) makes this vacuous |
# | C4 | Remark 1: RRL-MAP fairness | every sensor served lcm$(m,n_y)/n_y$ times in every window of $U$ steps, $\|\varepsilon(k)\|=m$ |
# | C5 | (6): $\Pr\{\psi_i=0\}=1-\check\psi_i$ | empirical attack frequency within 4 binomial standard errors |
# | C6 | (sanity) corrected (17)–(18)–(28) at $\check\psi=1$, $K_i=\emptyset$, $\lambda=0$ is the Kalman filter | max relative deviation from the textbook Riccati recursion ≤ 1e−10 |
# | C7 | Figs. 2–4: "estimated positions and velocities well match" the true ones | relative RMS error $\sqrt{\sum_k\mathrm{MSE}_i}/\sqrt{\sum_k\mathbb E\|x_i\|^2}\le0.1$ (our threshold) with the grid weights **or** with `weights_interior`; the open-loop ratio reported |
# | X1 | ours: the debiased innovation removes the bias | time-averaged MSE of target 1 reduced by ≥ 25 % and $\|$mean error of $X^p_1(T)\|$ reduced |
# | X2 | ours: vectorised Monte Carlo = loop over runs | max deviation of $\hat x$, $\mathfrak S$ over 5 runs ≤ 1e−9 |

# %%
claims = {}
frac_c1 = np.mean(MSE_C[1:] <= TRS_C[1:], axis=0)
claims["C1"] = results.claim(
    paper="Fig. 7: MSE_i(k) is always below its minimum upper bound tr S_i(k|k) (Theorems 1-2)",
    check="fraction of k = 1..T with MSE_i(k) <= mean_f tr S_i(k|k) (corrected coefficients), "
    "per target; holds if 1 for every target. Also min_k(tr S - MSE), and the fraction and gap "
    "with the other E[xhat xhat^T] surrogate (reported, not part of the verdict). EMPIRICAL: with "
    "xhat_moment = 'run' the gain depends on the run's data, while (21) assumes a deterministic "
    "gain, so this is a measured result, not a consequence of the corrected Theorem 1.",
    measured={"fraction": frac_c1, "min_gap": (TRS_C[1:] - MSE_C[1:]).min(axis=0),
              "xhat_moment": xhat_moment,
              "fraction_other_xhat_moment": frac_below(out_other_moment),
              "min_gap_other_xhat_moment": (mean_trace(out_other_moment)
                                            - mse(out_other_moment))[1:].min(axis=0)},
    threshold=1.0,
    holds=bool(np.all(frac_c1 == 1.0)),
)
MSE_P, TRS_P = mse(out_printed), mean_trace(out_printed)
frac_c1b = np.mean(MSE_P[1:] <= TRS_P[1:], axis=0)
claims["C1b"] = results.claim(
    paper="Theorems 1-2 with the coefficients as printed: S_i(k|k) bounds the error covariance",
    check="fraction of k with MSE_i(k) <= mean_f tr S_i(k|k), printed coefficients, weights from "
    "the Remark-4 grid; and lambda_min(bound - exact one-step covariance) (target 3, k = 2). "
    "Reported: the same fraction when the grid keeps only alpha2 > alpha3 (Theorem 3's condition)",
    measured={"fraction": frac_c1b, "time_avg_mse": MSE_P[1:].mean(axis=0),
              "time_avg_tr_S": TRS_P[1:].mean(axis=0),
              "fraction_thm3_restricted": np.mean(
                  mse(out_printed_thm3)[1:] <= mean_trace(out_printed_thm3)[1:], axis=0),
              "time_avg_mse_thm3_restricted": mse(out_printed_thm3)[1:].mean(axis=0),
              "one_step_lambda_min": one_step["paper"][0],
              "one_step_lambda_min_corrected": one_step["corrected"][0]},
    threshold=1.0,
    holds=bool(np.all(frac_c1b == 1.0)) and one_step["paper"][0] >= -1e-9,
)
ratio = mse(out_zoh)[1:].mean(axis=0) / MSE[1:].mean(axis=0)
claims["C2"] = results.claim(
    paper="Fig. 6 / Remark 2: ZOH does not improve the estimation performance over zero-input",
    check="r_i = time-averaged MSE under ZOH / time-averaged MSE under zero-input >= 0.95 "
    "(grid weights). Only target 1 is informative: targets 2, 3 have gains ~0, so r_2, r_3 ~ 1 "
    "whatever the update (r_3 < 1 passes through the tolerance). Reported: r_i with "
    "weights_interior (non-negligible gains for every target).",
    measured={"ratio": ratio, "ratio_interior_weights": time_avg_ratio(out_interior_zoh,
                                                                       out_interior),
              "max_abs_gain": max_gain["grid"],
              "max_abs_gain_interior_weights": max_gain["interior"]},
    threshold=0.95, holds=bool(np.all(ratio >= 0.95)),
)
frac_ub_err = np.mean(ERR2[:, 1:] <= UB[None, 1:], axis=(0, 1))
frac_ub_mse = np.mean(mse(out_corr)[1:] <= UB[1:], axis=0)

def cond_summary(rows_):
    return {key: [r[key] for r in rows_] for key in rows_[0]}


cond_main = THM3_COND["printed, weights in use"]
claims["C3a"] = results.claim(
    paper="Theorem 3: if 1 + alpha5 + alpha6 <= 1 - (alpha3 - alpha2)(1 - psi_check), "
    "eta_* >= phi_*, eta^* <= phi^* (phi_* I <= S(0|0) <= phi^* I) and E[x x^T] <= X*^2 I, the "
    "error is exponentially bounded in mean square",
    check="conditions with the literal Assumption-1 constants of the example, X*^2 = max_k "
    "lambda_max(MC E[x x^T]), weights in use, printed coefficients: (a) c0 > 1 (positive "
    "alpha5, alpha6 exist); (b), (c) at the data-driven (phi_*, phi^*) and for some pair "
    "phi_* <= 1 <= phi^* on a log grid (phi_scan). holds if (a) and a grid pair meeting (b) "
    "and (c) exist for every target. Reported: the same with the corrected coefficients and "
    "with the alpha2 > alpha3 weights; max rank of L Phi C H (36 needs full rank 4)",
    measured={"printed_weights_in_use": cond_summary(cond_main),
              "corrected_weights_in_use": cond_summary(THM3_COND["corrected, weights in use"]),
              "printed_alpha2_gt_alpha3_weights": cond_summary(
                  THM3_COND["printed, alpha2 > alpha3 weights"]),
              "max_rank_L_Phi_C_H": THM3_RANK},
    threshold={"c0": 1.0, "grid_log10": phi_scan, "rank_needed": NX},
    holds=bool(all(r["a_alpha56_exist"] and r["bc_pair_on_grid"] for r in cond_main)),
)
claims["C3b"] = results.claim(
    paper="Fig. 8: ||e_i(k|k)||^2 stays below UB_i(k)",
    check="DATA-DRIVEN envelope (consistent Lemma 3; phi_*, phi^*, Lambda, E||x||^2 read off the "
    "same runs, since Theorem 3's conditions fail, C3a): fraction of (run, k) with "
    "||e_i(k|k)||^2 <= UB_i(k) and of k with MSE_i(k) <= UB_i(k). The envelope reaches "
    "1e13-1e17 (UB_T / max MSE reported), which makes the inequality vacuous: holds records the "
    "measurement, it is not evidence for Theorem 3",
    measured={"fraction_err": frac_ub_err, "fraction_mse": frac_ub_mse, "UB_T": UB[-1],
              "max_mse": mse(out_corr)[1:].max(axis=0),
              "UB_T_over_max_mse": UB[-1] / mse(out_corr)[1:].max(axis=0),
              "phi_lower": [UB_INFO[i]["phi_lower"] for i in range(N)],
              "phi_upper": [UB_INFO[i]["phi_upper"] for i in range(N)],
              "rho": [UB_INFO[i]["rho"] for i in range(N)]},
    threshold=1.0,
    holds=bool(np.all(frac_ub_err == 1.0) and np.all(frac_ub_mse == 1.0)),
)
set_sizes = np.array([len(set(row.tolist())) for row in SETS])
per_window = lcm(m, n_y) // n_y
claims["C4"] = results.claim(
    paper="Remark 1: every sensor gets equal access within each U steps; |eps(k)| = m, no "
    "channel reused",
    check=f"counts of each sensor in every window of U = {U} steps equal lcm(m, n_y)/n_y = "
    f"{per_window}; distinct sensors per step = m",
    measured={"window_counts_min": window_counts.min(axis=0),
              "window_counts_max": window_counts.max(axis=0), "U": U,
              "distinct_per_step_min": set_sizes.min(), "distinct_per_step_max": set_sizes.max()},
    threshold={"per_window": per_window, "m": m},
    holds=bool(np.all(window_counts == per_window) and np.all(set_sizes == m)),
)
attack_freq = 1 - DRAWS["psi"].mean(axis=(0, 1))
tol = 4 * np.sqrt(PSI * (1 - PSI) / (F * T))
claims["C5"] = results.claim(
    paper="(6): Pr{psi_i(k) = 0} = 1 - psi_check_i (attack probabilities 0.3 / 0.5 / 0.7)",
    check="empirical attack frequency over F x T draws within 4 binomial standard errors",
    measured=attack_freq, threshold={"expected": 1 - PSI, "tolerance": tol},
    holds=bool(np.all(np.abs(attack_freq - (1 - PSI)) <= tol)),
)
claims["C6"] = results.claim(
    paper="(sanity) the bound recursion (17)-(18)-(28) reduces to the Kalman filter without "
    "attack and coupling",
    check="psi = 1, K_i empty, lambda = 0, corrected coefficients: max relative |S - P_Riccati| "
    "and max |x_hat - x_hat_KF| <= 1e-10",
    measured={"S": kal_dev_P, "xhat": kal_dev_x}, threshold=1e-10,
    holds=bool(kal_dev_P <= 1e-10 and kal_dev_x <= 1e-10),
)
sig2 = np.mean(np.sum(out["x"] ** 2, axis=-1), axis=0)
rel_rms = np.sqrt(MSE[1:].sum(axis=0) / sig2[1:].sum(axis=0))
rel_rms_ol = np.sqrt(mse(open_loop)[1:].sum(axis=0) / sig2[1:].sum(axis=0))
rel_rms_int = np.sqrt(mse(out_interior)[1:].sum(axis=0) / sig2[1:].sum(axis=0))
claims["C7"] = results.claim(
    paper="Figs. 2-4: each target's estimated positions and velocities well match the real ones",
    check="relative RMS error sqrt(sum_k MSE_i) / sqrt(sum_k E||x_i||^2) <= 0.1 (our threshold "
    "for 'well match') for every target, with the grid weights (gains ~0 for targets 2, 3) or "
    "with weights_interior (non-degenerate gains); holds if either weight set tracks. The "
    "open-loop prediction's value is reported for comparison",
    measured={"relative_rms": rel_rms, "relative_rms_interior_weights": rel_rms_int,
              "relative_rms_open_loop": rel_rms_ol,
              "weights_interior": weights_interior,
              "time_avg_mse": MSE[1:].mean(axis=0),
              "time_avg_mse_interior_weights": mse(out_interior)[1:].mean(axis=0),
              "time_avg_mse_open_loop": mse(open_loop)[1:].mean(axis=0)},
    threshold=0.1, holds=bool(np.all(rel_rms <= 0.1) or np.all(rel_rms_int <= 0.1)),
)
mse_db = mse(out_debiased)
gain_db = 1 - mse_db[1:, 0].mean() / MSE[1:, 0].mean()
claims["X1"] = results.claim(
    paper="(ours) the innovation y - psi_check Phi C H x_hat(k|k-1) removes the attack bias",
    check="target 1: relative reduction of the time-averaged MSE >= 0.25 and |mean error of "
    "X^p_1(T)| smaller than with (8)",
    measured={"mse_reduction_target1": gain_db,
              "mean_err_Xp_T_paper": ERR_MEAN[-1, :, 0],
              "mean_err_Xp_T_debiased": ERR_MEAN_DB[-1, :, 0]},
    threshold=0.25,
    holds=bool(gain_db >= 0.25 and abs(ERR_MEAN_DB[-1, 0, 0]) < abs(ERR_MEAN[-1, 0, 0])),
)
claims["X2"] = results.claim(
    paper="(ours) the vectorised Monte Carlo pass computes the same runs as a loop over runs",
    check="max |x_hat, S (vectorised) - x_hat, S (simulate called run by run)| over 5 runs, "
    "xhat_moment run, <= 1e-9",
    measured=loop_dev, threshold=1e-9, holds=bool(loop_dev <= 1e-9),
    tolerance=results.ROUNDING_RESIDUAL,
)
results.write_claims(results_path, claims)
for cid, c in claims.items():
    print(cid, "holds" if c["holds"] else "DOES NOT HOLD")

# %% [markdown]
# ## Deviations from the paper
#
# | item | paper | here | why |
# |---|---|---|---|
# | coefficients of (18), Theorem 2, Theorem 3 | $c_0=1-(\alpha_3-\alpha_2)(1-\check\psi)$ ((18): $(1-(\alpha_3-\alpha_2))(1-\check\psi)$), $\kappa_x=\check\psi+\alpha_3^{-1}+\alpha_4-1$ | $c_0=1+(\alpha_2+\alpha_3)(1-\check\psi)$, $\kappa_x=(1-\check\psi)(1+\alpha_3^{-1}+\alpha_4)$ (`coef="paper"` keeps the printed ones) | re-derived from (12) with Lemma 1; the printed ones are not a bound (C1b, one-step counterexample) |
# | (21) | $(\check\psi-1)L\Gamma\mathbb E\{xx^T\}\Gamma^TL^T$ | $(1-\check\psi)$ | sign error |
# | (17), (20) | $(\sum_jBH)\mathfrak S_j(\sum_jH^TB^T)$; $e_je_l^T$ cross terms omitted; stray $H^T$ factors | $\|K_i\|\sum_jB_{i,j}H\mathfrak S_jH^TB_{i,j}^T$ | the printed form is undefined for $\|K_3\|=2$ and not a proven bound |
# | (29), Lemma 2 | missing minus sign; garbled first identity | (28) used as printed, solved on the scheduled rows | (28) is the stationary point; $\Pi$ has rank $m$ |
# | $\mathbb E\{\hat x\hat x^T\}$ in (18), (28) | not specified | the run's own $\hat x\hat x^T$ (`xhat_moment="ensemble"` as option; nearly identical numbers) | no closed form; the gain then depends on the run's data while (21) assumes a deterministic gain, so C1 is an empirical result (the ensemble variant is reported next to it) |
# | Lemma 3, (56), Fig. 8 text | rate and additive constant swapped; sum from $l=1$ | consistent form, sum from $l=0$ | re-derived from the iteration |
# | Theorem 3 conditions | $1+\alpha_5+\alpha_6\le c_0$, $\eta_*\ge\phi_*$, $\eta^*\le\phi^*$ assumed | evaluated (C3a): $\eta^*\le\phi^*$ fails for every $\phi^*\ge1$ on a $10^{0}$–$10^{12}$ grid, printed or corrected coefficients; (a) fails with the printed $c_0$ at the weights in use; (36) needs $L\Phi CH$ of full rank, its rank is $m=2$ | the theorem's premise is not met on the example |
# | Theorem 3 constants | Assumption-1 constants, $\pi_*$, (47), (48), (50) | data-driven recipe (Fig. 8 section); the envelope is 1e13–1e17 and vacuous (C3b) | literal constants are 0 / undefined on the example; (50) sign; (47), (48) use the wrong-side constants |
# | Assumption 1 | $h_*^2\le H_\epsilon H_\epsilon^T$ | $h_*^2I\le H_\epsilon H_\epsilon^T$, $h_*=\epsilon$ | typo |
# | weights $\lambda,\alpha_1..\alpha_4$ | "intelligent optimisation" suggested (Remark 4), values not given | documented grid, 10 pilot runs | see the Remark-4 section; the optimum for targets 2, 3 is at the grid edge ($L\to0$) |
# | attack signal, horizon, seeds, $\sigma$ redraw, $\mathcal V$ as $0.03I$ | not given | parameter table | |
# | ZOH variant (Fig. 6) | not specified | hold buffer + gain with $\Phi=I$ | the zero-input gain applied to held data is the zero-input estimator |
# | Figs. 2–4 tracking | "well match" | not reproduced (C7): with the grid weights the gains for targets 2, 3 are ~0 (open loop) and target 1 is biased by the attack; with `weights_interior` (non-degenerate gains) targets 2, 3 get worse (relative RMS 0.48, 0.63) | the conclusion does not depend on the grid-edge choice; our debiased innovation (X1) removes target 1's bias |
# | Fig. 6 / C2 | "ZOH does not improve" | holds; with the grid weights only target 1 is informative (ratios ≈ 1 for targets 2, 3, target 3 passes through the 0.95 tolerance); with `weights_interior` all ratios > 1 | gains ≈ 0 for targets 2, 3 at the grid edge |
# | figures | single trajectories, curves only | first Monte Carlo run; log axes from $k=1$ ($\mathrm{MSE}(1)\approx10^{-4}$ because $E_i(0)=0$) | |

# %%
manifest_path = run.finish(extra={"weights": WEIGHTS})
print("run manifest:", manifest_path.relative_to(results.repo_root()))
