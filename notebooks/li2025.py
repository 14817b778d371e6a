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
# **Verdict: [¬Re]** (by the one rule, computed in the verdict section; decided by C1b, C3, C7, C8) —
# none of the paper's main claims holds: the bound as printed (C1b) and Theorem 2's statement that (28)
# minimises the bound "for given positive scalars" (C8) fail at the example; Theorem 3 (C3) fails its
# premise (the example cannot satisfy it, C3a; on a declared instance of ours $L=0$ meets the envelope at
# every eligible case, so the measurement does not discriminate, its precondition since session 14; the
# ratio is X9, ours); the tracking of Figs. 2–4 (C7) is not checked, since the paper gives no scale for
# "well match" (the relative RMS errors are recorded). Our corrected bound holds (X5), but it is ours and
# does not decide. The counts over the declared space are in the claims table at the end.
#
# **Reading the verdict.** (i) $L=0$ meets C3's envelope at every eligible case, informative gain or not: on this
# stable instance it cannot tell the estimator from the open-loop prediction (an unstable one: future work).
# (ii) C1b and C8 fail through **two printed errors**: (21)'s factor $(\check\psi-1)$ on the
# $L\Gamma\mathbb E\{xx^T\}\Gamma^TL^T$ term (correct: $\mathbb E(\psi-1)^2=1-\check\psi$) gives the printed $\kappa_x$, whose
# sign makes $\Pi$ indefinite (C8); separately, the printed $c_0=1-(\alpha_3-\alpha_2)(1-\check\psi)$ does not follow
# from (21)'s correctly signed $e$–$x$ bracket, which (26) can only add to ($+\alpha_3(1-\check\psi)$): the $-\alpha_3$
# enters when (18) is assembled, and this error alone breaks the bound (C1b; the attribution is measured
# in C1b and C8). With the derived coefficients $c_0\ge1$, $\kappa_x\ge0$ for every positive weight set, so
# $\Pi\succ0$ and (28) is the minimiser (by the derivation; X5 certifies the bound at the weights used).
#
# * **Fails its premise.** Theorem 3 (C3, deciding): on our instance (Assumption 1 met, subsystem 1 with the
#   empty-sum reading, as C3a) the eligible weights of a declared search keep $\mathbb E\|e\|^2$ below our
#   re-derived envelope (largest ratio 0.086, X9, ours), but so does $L=0$ (0.086; and at the re-review's
#   set). On the example its premise fails for every weight set (C3a: $E_iE_i^T$
#   has rank 1); even with $e_*=b_*=0$ admitted no weights meet its conditions (X7, ours); Fig. 8 (C3b) too.
# * **Holds.** At our grid's weights (printed $c_0>0$, $\kappa_x\ge0$) (28) minimises the trace of (18) by
#   construction (C8b, shown, not evidence); RRL-MAP is fair (C4, by construction). Ours: the corrected
#   bound is certified exactly (X5) and Fig. 7's comparison holds for it (X6).
# * **Not reproduced.** Theorem 2 (C8, deciding): at the declared positive weights
#   $(\lambda,\alpha_1..\alpha_4)=(0.1,1,9.5,10,0.01)$ (printed $\kappa_x<0$) Algorithm 1's own trajectory has $\Pi$ of
#   (28) indefinite at 145 of 300 (step, target) pairs, so (28) is a saddle of tr (18); with (18)'s first
#   factor read literally (28) is not the minimiser even at the grid's weights. The printed coefficients
#   are no bound at the weights Remark 4's minimisation picks (C1b: exact counterexample from $k=2$; at the
#   $\alpha_2>\alpha_3$ weights of Theorem 3 they bound, 0.9997 / 0.91 / 0.59, but one counterexample refutes a
#   statement "for given positive scalars"). Fig. 7 as printed (C1c, not deciding) fails at the default.
# * **Not checked.** Figs. 2–4 (C7, deciding): relative RMS error 0.34 / 0.32 / 0.21 (our corrected design;
#   0.71 / 0.97 / 0.95 of the open-loop prediction's), printed-coefficient design beside it; no scale in the
#   paper. Under the replacement attack no gain in (8) gets below X4's level 0.1 (ours): the per-step optimal
#   gain gives 0.17 / 0.19 / 0.16, an oracle dropping attacked packets 0.016 / 0.013 / 0.012.
# * **Undetermined.** "ZOH is not better" (C2, not deciding) holds at every reading cell of 4 of the 5
#   independent draws; it fails at 2 of the 16 cells of the draw with $T=147$ (target 1, ratio 0.98
#   [0.97, 0.996]).

# %% tags=["parameters"]
mode = "paper"  # "paper": full run incl. the Remark-4 grid check; "fast": the grid is skipped (ours)
T = 100  # horizon in steps (MISSING)
F = 100  # Monte Carlo runs (PAPER, Section IV)
mc_seed = 2025  # seed of the Monte Carlo draws (MISSING)
grid_seed = 2026  # seed of the pilot runs of our Remark-4 grid (ours)
grid_pilot_runs = 10  # pilot runs averaged by the grid objective (ours)
epsilon = 0.05  # singular perturbation parameter (PAPER)
n_y = 4  # sensors per target (PAPER)
m = 2  # channels per target (PAPER)
xi_star = 0.3  # attack energy bound (PAPER)
psi_check = [0.7, 0.5, 0.3]  # probabilities of NO attack per target (PAPER)
W = 0.03  # process noise variance (PAPER)
V = 0.03  # measurement noise variance per sensor (PAPER, scalar read as V I)
coef = "corrected"  # bound coefficients of the main design: "corrected" or "paper" (CORRECTED)
xhat_moment = "run"  # surrogate of E[xhat xhat^T] in the Monte Carlo runs: "run" or "ensemble" (MISSING)
coupling_factor = True  # multiply the coupling term of (17) by |K_i| (CORRECTED)
attack_signal = "sincos"  # form of xi_i(k), energy xi_star: "sincos" or "constant" (MISSING)
weight_rule = "grid"  # weights in use: "grid" (Remark-4 minimiser) or "interior" (MISSING)
grid_lambda = [1e-3, 1e-2, 1e-1]  # levels of our Remark-4 grid (ours)
grid_alpha1 = [0.3, 1.0, 3.0, 10.0]  # (ours)
grid_alpha23 = [1e-4, 1e-3, 1e-2, 0.1, 1.0]  # (ours)
grid_alpha4 = [0.03, 0.1, 0.3]  # (ours)
# (lambda, alpha1, alpha2, alpha3, alpha4) of targets 1, 2, 3 as found by the grid (MISSING)
weights_corrected = [[1e-3, 1.0, 1e-2, 0.1, 0.1], [1e-2, 1.0, 1e-4, 1e-4, 0.3], [1e-2, 1.0, 1e-4, 1e-4, 0.1]]
weights_paper = [[1e-3, 3.0, 1e-2, 1.0, 0.1], [1e-1, 10.0, 1e-4, 1.0, 0.03], [1e-1, 10.0, 1e-4, 1.0, 0.03]]
# printed coefficients, grid restricted to alpha2 > alpha3 (the condition of Theorem 3)
weights_paper_thm3 = [[1e-3, 1.0, 1e-3, 1e-4, 0.3], [1e-2, 1.0, 1e-3, 1e-4, 0.3], [1e-2, 1.0, 1e-3, 1e-4, 0.1]]
# (lambda, alpha1..alpha4) of every target under weight_rule "interior" (MISSING)
weights_interior = [0.01, 1.0, 0.01, 0.1, 0.1]
# (lambda, alpha1..alpha4) of every target at which C8 judges Theorem 2 off our grid: printed
# c0 > 0 but kappa_x < 0 (the grid discards kappa_x < 0; Theorem 2 admits any positive weights) (ours)
thm2_weights = [0.1, 1.0, 9.5, 10.0, 0.01]
c1_psi_scan = [1.0, 0.99, 0.9, 0.5, 0.3]  # psi_check of all targets in X5's exact certificate (ours)
gain_negligible = 0.01  # C2: mean ||L_i Gamma_i|| below this makes target i uninformative (ours)
x3_runs = 2000  # Monte Carlo runs of the check of the exact recursion, X3 (ours)
phi_scan = [-12.0, 12.0, 241]  # log10 range and size of the (phi_*, phi^*) scan of Theorem 3 (ours)
plot_run = 0  # Monte Carlo run shown in the single-run figures (ours)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/li2025"
results_path = "figures/li2025/claims.json"

# %%
import csv
import itertools
import json
from math import lcm

import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown, display
from scipy import stats

from secest.core import montecarlo, schedules
from secest.core.validation import ValidationError
from secest.methods import li2025 as M
from secest.methods.li2025 import (
    bound_coefficients,
    gain_and_bound,
    predicted_bound,
    sym,
)
from secest.repro import plotting, results, spaces
from secest.repro.literate import show_source

print(results.environment_summary())

run = results.Run("li2025", globals())  # checks every parameter against notebooks/li2025.toml
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)
N, NX = 3, 4  # targets, states per target


def require(ok: bool, name: str, what: str, value) -> None:
    """Raise a one-line ValidationError naming parameter `name` unless `ok`."""
    if not ok:
        raise ValidationError(f"parameter {name} must be {what}, found {value!r}")


def weight_rows(name: str, table, rows: int) -> list[tuple[float, ...]]:
    """`rows` tuples (lambda, alpha1..alpha4) of positive weights read from parameter `name`."""
    try:
        arr = np.asarray(table, dtype=float)
    except ValueError:  # ragged lists
        arr = np.empty(0)
    arr = arr if arr.ndim == 2 else arr.reshape(1, -1) if arr.ndim == 1 and rows == 1 else arr
    require(arr.shape == (rows, 5) and bool(np.all(arr > 0)), name,
            f"{rows} list(s) of 5 positive weights (lambda, alpha1..alpha4)", table)
    return [tuple(map(float, row)) for row in arr]


PSI = np.asarray(psi_check, float)
require(bool(np.all((PSI >= 0) & (PSI <= 1))), "psi_check", "3 probabilities in [0, 1]", psi_check)
require(len(c1_psi_scan) > 0 and all(0 <= p <= 1 for p in c1_psi_scan), "c1_psi_scan",
        "a non-empty list of probabilities in [0, 1]", c1_psi_scan)
require(plot_run < F, "plot_run", f"an index of a Monte Carlo run, below F = {F}", plot_run)
for _name, _levels in (("grid_lambda", grid_lambda), ("grid_alpha1", grid_alpha1),
                       ("grid_alpha23", grid_alpha23), ("grid_alpha4", grid_alpha4)):
    require(len(_levels) > 0 and min(_levels) > 0, _name, "a non-empty list of positive levels", _levels)
require(phi_scan[0] < 0 < phi_scan[1] and phi_scan[2] == int(phi_scan[2]) and phi_scan[2] >= 3,
        "phi_scan", "[log10 min < 0, log10 max > 0, integer size >= 3]", phi_scan)
WEIGHT_TABLE = {name: weight_rows(f"weights_{name}", table, N) for name, table in
                (("corrected", weights_corrected), ("paper", weights_paper),
                 ("paper_thm3", weights_paper_thm3))}
W_INTERIOR = weight_rows("weights_interior", weights_interior, 1) * N
W_THM2 = weight_rows("thm2_weights", thm2_weights, 1) * N
run_grid = mode == "paper"

# %% [markdown]
# ## Parameter provenance
#
# Every parameter of this notebook with its value, provenance tag, admissible domain and — for the
# values the paper does not pin down — the declared space that `make robustness` sweeps, with the
# reason (rendered from `notebooks/li2025.toml`, which was committed before the sweep ran):

# %%
display(Markdown(spaces.provenance_markdown("li2025")))

# %% [markdown]
# The model constants of Section IV that are not parameters (they are printed in the paper and
# fixed here), and the derived choices that have no parameter:
#
# | name | value | tag | source / reason |
# |---|---|---|---|
# | $N$, $K_1,K_2,K_3$ | 3; $\emptyset$, {1}, {1, 2} | PAPER | Section IV |
# | $U$ | $\mathrm{lcm}(m,n_y)/m$ = 2 | PAPER | (2) |
# | $A_i(k)$, $C_i$, $E_i(k)$, $B_{i,j}$ | coordinated-turn model, $T_k=0.8\tanh k$, $r_k=0.1+0.3\tanh k$ | PAPER | Section IV |
# | $n_s=n_f=2$ | $H_\epsilon=\mathrm{diag}(1,1,\epsilon,\epsilon)$ | PAPER | scales the *Y* position / velocity |
# | $x_i(0)=\hat x_i(0\|0)$ | offsets + $\sigma_{ij}\sim U(0,1)$ | PAPER | Section IV; $\sigma$ redrawn in every Monte Carlo run (the paper does not say); $e_i(0\|0)=0$ |
# | $\mathfrak S_i(0\|0)$ | $I_4$ | PAPER | Section IV |
# | $\check\psi_i$ | $\Pr\{\psi_i=1\}$ | PAPER | the probability of **no** attack (Section II-B) |
# | ZOH variant of Fig. 6 | hold buffer, gain with $\Phi=I$ | MISSING | the paper gives no details; the zero-input gain on held data is the zero-input estimator |
# | $\alpha_5..\alpha_7$, $\phi_*,\phi^*$, Assumption-1 constants | data-driven (Theorem 3 section) | MISSING | the paper gives none; the literal constants degenerate on the example |
# | Theorem 3 instance (C3) | $N=2$, $n_x=n_y=2$, $m=1$, $A_i=0.6R(0.3)$, $B_{2,1}=0.2I$, $C_i=E_i=I$, $\check\psi=(0.7,0.5)$, horizon 100 | ours | a system of ours satisfying Assumption 1 (the example cannot); its weights by X7's declared search (section "Theorem 3 on a declared instance of ours") |

# %% [markdown]
# ## The SPDSS (1)
#
# The paper's Fig. 1 is a schematic, not a result (nothing to regenerate): a distributed sequential
# system of nine subsystems $S_1,\dots,S_9$ drawn as a directed graph whose arcs $\langle S_i,S_j\rangle$
# only go from a lower to a higher index, so the state of $S_j$ is driven by upstream subsystems
# only. The example uses $N=3$ with $K_1=\emptyset$, $K_2=\{1\}$, $K_3=\{1,2\}$: a DAG processed in
# the order 1, 2, 3.
#
# For $i=1,2,3$, with $x_i=\mathrm{col}\{X^p_i,X^v_i,Y^p_i,Y^v_i\}$,
#
# $$x_i(k+1)=A_i(k)H_\epsilon x_i(k)+\sum_{j\in K_i}B_{i,j}H_\epsilon x_j(k)+E_i(k)\omega_i(k),\qquad
# \tilde y_i(k)=C_iH_\epsilon x_i(k)+v_i(k). \tag{1}$$
#
# $T_0=0$ gives $A_i(0)=I$ and $E_i(0)=0$: no process noise enters the first transition.
# Because the output is $C_iH_\epsilon x_i$, sensors 2 and 4 see $\epsilon Y^p_i$ and $\epsilon Y^v_i$.

# %%
K_SETS = M.EXAMPLE_PARENTS  # 0-based K_i
H_EPS = np.diag([1.0, 1.0, epsilon, epsilon])
C_MAT = M.EXAMPLE_C
CH = C_MAT @ H_EPS
SENSOR_SEES = ["$X^p$ [m]", "$\\epsilon Y^p$ [m]", "$X^v$ [m/s]", "$\\epsilon Y^v$ [m/s]"]
B_MAT = M.EXAMPLE_B
BH = {key: b @ H_EPS for key, b in B_MAT.items()}
X0_OFFSET = M.EXAMPLE_X0
show_source(M.turn_model, after="    k = np.arange(")
A_ALL, E_ALL = M.turn_model(T)
AH_ALL = A_ALL @ H_EPS
print("A(5) =\n", np.round(A_ALL[min(5, T)], 4), "\ndet A(k) = 1:", np.allclose(np.linalg.det(A_ALL), 1))

# %% [markdown]
# ## RRL-MAP (2)–(5)
#
# $\varepsilon(k)=\{\mathrm{mod}(m(k-1)+s,n_y)+1: s=0..m-1\}$ (2), period $U=\mathrm{lcm}(m,n_y)/m$,
# $\Phi_{o(k)}=\sum_{r\in\varepsilon(k)}\phi_r$ (4) and the zero-input update
# $\bar y_i(k)=\Phi_{o(k)}\tilde y_i(k)$ (3), (5). The schedule is the reusable
# `secest.core.schedules` (0-based sensor indices = label − 1). Remark 1 (fairness): in every window
# of $U$ steps each sensor is served $\mathrm{lcm}(m,n_y)/n_y$ times (C4).

# %%
U = schedules.rrl_map_period(m, n_y)
require(T >= U, "T", f"at least one RRL-MAP period U = lcm(m, n_y)/m = {U}", T)
SETS = schedules.rrl_map_sets(np.arange(1, T + 1), m, n_y)  # row k-1 holds eps(k)
window_counts = schedules.rrl_map_window_counts(SETS, n_y)
print(f"U = {U}; eps(1..4) (1-based) =", (SETS[:4] + 1).tolist())
print("sensor counts in every U-window:", np.unique(window_counts, axis=0).tolist())

# %% [markdown]
# ## Bernoulli replacement attack (6)
#
# $y_i(k)=\psi_i(k)\bar y_i(k)+(1-\psi_i(k))\Phi_{o(k)}\xi_i(k)$ with
# $\Pr\{\psi_i(k)=1\}=\check\psi_i$: **$\psi_i=1$ means not attacked**, so the attack
# probabilities are 0.3 / 0.5 / 0.7. An attack *replaces* the scheduled entries (an additive
# reading, $y_i=\bar y_i+(1-\psi_i)\Phi\xi_i$, is evaluated as a sensitivity row of C7). Remark 3 leaves
# the form of $\xi_i(k)$ free as long as $\|\xi_i(k)\|^2\le\xi^*_i$; `attack_signal` selects one of two
# forms at the bound, $\sqrt{\xi^*/2}\,[\sin k,\cos k,\sin k,\cos k]^T$ or the constant
# $\sqrt{\xi^*/n_y}\,[1,\dots,1]^T$. The replaced values stand for measurements, so they carry the
# sensors' units: m for sensors 1, 2 and m/s for sensors 3, 4.


# %%
def attack_values(horizon: int) -> np.ndarray:
    """xi(k) for k = 0..horizon, shape (T+1, n_y), ||xi(k)||^2 = xi_star; the same for every target."""
    k = np.arange(horizon + 1)[:, None]
    if attack_signal == "sincos":
        wave = np.where(np.arange(n_y) % 2 == 0, np.sin(k), np.cos(k))
        return np.sqrt(2 * xi_star / n_y) * wave
    return np.full((horizon + 1, n_y), np.sqrt(xi_star / n_y))


XI = attack_values(T)


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
# (43)–(49) and Theorem 3 use $1-(\alpha_3-\alpha_2)(1-\check\psi)$, which we take as "printed". **Two printed
# errors**: (21)'s $(\check\psi-1)$ gives the printed $\kappa_x$ (which also drops, conservatively, the factor
# $1-\check\psi$ on $\alpha_3^{-1},\alpha_4$); and (21)'s $e$–$x$ bracket is correctly signed, so (26) adds
# $\alpha_3(1-\check\psi)M\mathfrak S^-M^T$, yet (18) subtracts it: the printed $c_0$ is $2\alpha_3(1-\check\psi)$ below the
# derived one, $<1$ for $\alpha_3>\alpha_2$, which lets a trace minimiser shrink the "bound" below the covariance. With
# $\check\psi=1$, $K_i=\emptyset$, $\lambda\to0$ the corrected recursion is exactly the Kalman
# Riccati recursion (checked below, X8); the printed one is not ($\kappa_x=\alpha_3^{-1}+\alpha_4$).
#
# **Gain (28).** $\partial\,\mathrm{tr}\,\mathfrak S/\partial L=0$ gives $L=\Psi\Pi^{-1}$, $\Psi=c_0\mathfrak S^-\Gamma^T$,
# $\Pi=c_0\Gamma\mathfrak S^-\Gamma^T+R$ ((29) lacks a minus sign and Lemma 2's first identity is
# garbled; (28) is nevertheless the stationary point). $\Pi$ has rank $m$ (every term is
# sandwiched by $\Phi$): we solve on the scheduled rows, $\Gamma_s=(CH_\epsilon)_{\varepsilon(k)}$,
# $L_s=c_0\mathfrak S^-\Gamma_s^T\Pi_s^{-1}$, which equals $\Psi\Pi^{+}$.
#
# **The additive reading of (6).** If the attack *added* $\Phi\xi_i$ to the received data instead of
# replacing it, (12) would read $e=Me^--L\Phi v-(1-\psi)L\Phi\xi$, and the same steps (Lemma 1 with
# weight $\alpha_2$ on the $e^-/\xi$ bracket) give $c_0=1+\alpha_2(1-\check\psi)$, $\kappa_x=0$,
# $\kappa_\xi=(1-\check\psi)(1+\alpha_2^{-1})$ and $1\cdot\Phi\mathcal V\Phi^T$ (noise in every step). We use it
# only as a sensitivity row of C7.


# %% [markdown]
# The library's prediction (7) and update (8) (`secest.methods.li2025`; `c` is 1 in (8)):

# %%
show_source(M.predict, after="    if len(xh_parents) != len(bh_list):")
show_source(M.correct, after="    return xp + ")

# %% [markdown]
# The coefficients of the table, in the library (`secest.methods.li2025`, which the arena's method
# runs too; `variant="additive"` is the additive reading above, `kappa_v` the weight of
# $\Phi\mathcal V\Phi^T$):

# %%
show_source(M.bound_coefficients, after="    p = 1 - psi_bar")

# %% [markdown]
# The predicted bound (17), batched over the leading axes (Monte Carlo runs, grid candidates):

# %%
show_source(M.predicted_bound, after="    if len(S_parents) != len(bh_list):")

# %% [markdown]
# The gain (28) on the scheduled rows and the updated bound (18); a batch member whose $\Pi$ is not
# finite or exceeds $10^{14}$ (an exploding grid candidate) gets a NaN gain instead of a crash:

# %%
show_source(M.gain_and_bound, after="    c0, kx, kxi, kv = coefs")


# %% [markdown]
# ## Monte Carlo core: Algorithm 1 for all runs at once
#
# `simulate` runs the plant (1) with the attack (6) (`plant_and_packets`, the example's data) and
# then Algorithm 1 for the three targets over $k=1..T$, the library's `estimate` (shown below), with
# the $F$ runs as the leading array axis (no Python loop over runs: the loop is over time and
# targets only). All randomness comes in through `draws`, so a run-by-run loop over slices
# `draws[f:f+1]` gives the same numbers (X2; the benchmark suite times `estimate` on all runs
# against a loop over single runs). Targets are processed in the
# DAG order 1, 2, 3 ($\mathfrak S_3(k|k-1)$ needs $\mathfrak S_1,\mathfrak S_2$ at $k-1$).
#
# `estimator` selects the measurement update:
# - `"zero"`: the paper's zero-input estimator (8);
# - `"zoh"`: the ZOH variant of Fig. 6 — a buffer $z_i$ holds the last received value of each
#   sensor ($z_i(0)=C_iH_\epsilon\hat x_i(0|0)$), the estimator treats $z_i(k)$ as a full fresh
#   measurement, and its gain and bound use (17)–(18), (28) with $\Phi_{o(k)}$ replaced by $I$
#   (feeding $z$ into (8) with the zero-input gain would give back the zero-input estimator, whose
#   off-schedule columns are zero).
#
# `gains`, if given, replaces (28) by fixed gains (then $\mathfrak S$ is not computed; used to check the
# exact recursion below, X3). The updates `"debiased"` and `"open_loop"` of `estimate` are used by the
# arena and the tests only; this notebook runs them in its exact-moment recursion below.

# %%
show_source(M.estimate, after="    xh = np.zeros((runs, T + 1, N, n))")


# %%
EWE_ALL = W * (E_ALL[:, :, None] * E_ALL[:, None, :])  # E_i(k) W E_i^T(k), k = 0..T


def plant_and_packets(draws, parents):
    """The plant (1) and the received scheduled entries (6), Algorithm 1 lines 3-4.

    Returns x (F, T+1, N, 4), the states, and y (F, T, N, m), row k-1 holding
    y_{i, eps(k)}(k): the scheduled entries of C H x_i(k) + v_i(k), replaced by xi when attacked.
    """
    runs, horizon = draws["sigma"].shape[0], draws["psi"].shape[1]
    x = np.zeros((runs, horizon + 1, N, NX))
    y = np.zeros((runs, horizon, N, m))
    x[:, 0] = X0_OFFSET + draws["sigma"]
    for k in range(1, horizon + 1):
        ah, sched = AH_ALL[k - 1], SETS[k - 1]
        for i in range(N):
            xn = x[:, k - 1, i] @ ah.T + E_ALL[k - 1] * draws["w"][:, k - 1, i, None]
            for j in parents[i]:
                xn = xn + x[:, k - 1, j] @ BH[(i, j)].T
            x[:, k, i] = xn
            y_raw = xn @ CH.T + draws["v"][:, k - 1, i]
            ok = draws["psi"][:, k - 1, i, None]
            y[:, k - 1, i] = ok * y_raw[:, sched] + (1 - ok) * XI[k, sched]  # (6)
    return x, y


def simulate(draws, weights, *, variant="corrected", moment="run", estimator="zero",
             k_factor=True, psi_bar=None, parents=None, gains=None):
    """The plant and Algorithm 1 for every target, vectorised over the Monte Carlo runs.

    Parameters: draws from `draw_randomness`; weights[i] = (lambda, alpha1..alpha4) of target i;
    variant of `bound_coefficients`; moment "run"/"ensemble" (surrogate of E[xhat xhat^T]);
    estimator "zero"/"zoh"; psi_bar and parents override PSI and K_SETS (X8 check); gains
    (T+1, N, 4, n_y) fixed gains instead of (28).
    Returns x, xhat (F, T+1, N, 4), S, S_pred (F, T+1, N, 4, 4), L (F, T+1, N, 4, n_y).
    """
    psi_bar = PSI if psi_bar is None else psi_bar
    parents = K_SETS if parents is None else parents
    x, y = plant_and_packets(draws, parents)
    horizon = y.shape[1]
    est = M.estimate(y, SETS[:horizon], AH_ALL[:horizon], EWE_ALL[:horizon], CH, x[:, 0], np.eye(NX),
                     weights, psi_bar, xi_star, V, parents=parents, BH=BH, variant=variant,
                     moment=moment, update=estimator, k_factor=k_factor, gains=gains)
    return {"x": x, **est}


def mse(out):
    """MSE_i(k) of Section IV: (1/F) sum_f ||x_i(k) - x_hat_i(k|k)||^2, shape (T+1, N)."""
    return np.mean(sq_err(out), axis=0)


def sq_err(out):
    """||x_i(k) - x_hat_i(k|k)||^2 per run, shape (F, T+1, N)."""
    return np.sum((out["x"] - out["xhat"]) ** 2, axis=-1)


def mean_trace(out):
    """Monte Carlo mean of tr S_i(k|k), shape (T+1, N)."""
    return np.mean(np.trace(out["S"], axis1=-2, axis2=-1), axis=0)


def t_intervals(samples, level: float):
    """Student-t intervals of the mean over axis 0 (vectorised `montecarlo.mean_interval`)."""
    n = samples.shape[0]
    half = stats.t.ppf(0.5 + level / 2, n - 1) * samples.std(axis=0, ddof=1) / np.sqrt(n)
    centre = samples.mean(axis=0)
    return centre - half, centre + half


# %% [markdown]
# ## Exact second moments for deterministic gains
#
# If the gains $L_i(k)$ do not depend on the data, the joint vector
# $z=\mathrm{col}(x_1,x_2,x_3,\hat x_1,\hat x_2,\hat x_3)\in\mathbb R^{24}$ evolves affinely once
# $\psi(k)$ is fixed, and its mean $\mu=\mathbb E z$ and second moment $Q=\mathbb E zz^T$ propagate
# exactly (no Monte Carlo):
#
# * **prediction**, (1) and (7): $z^-=A_z(k-1)z+\mathrm{col}(E_i\omega_i,0)$ with
#   $A_z=\mathrm{diag}(A_x,A_x)$, $A_x$ the block matrix with $A_iH_\epsilon$ on the diagonal and
#   $B_{i,j}H_\epsilon$ at $(i,j\in K_i)$: $\mu^-=A_z\mu$, $Q^-=A_zQA_z^T+\mathrm{diag}(E_i\mathcal W E_i^T,0)$;
# * **update of target $i$**, (6) and (8): $\hat x_i\leftarrow\hat x_i^-+L_i\nu_i$ with
#   $\nu_i=\psi_i(\Gamma_sx_i+v_s)+(1-\psi_i)\xi_s-c_i\Gamma_s\hat x_i^-$ ($c_i=1$ in (8), $c_i=\check\psi_i$ in the
#   debiased variant below; additive reading: $\nu_i=\Gamma_sx_i+v_s+(1-\psi_i)\xi_s-c_i\Gamma_s\hat x_i^-$). For
#   $\psi_i=b$ this is $z'=J_bz+u_b+(\text{noise})$, and since $\psi_i(k)$ is independent of $z^-$ and $v$,
#   $\mu'=\sum_b p_b(J_b\mu+u_b)$, $Q'=\sum_b p_b\big(J_bQJ_b^T+J_b\mu u_b^T+u_b\mu^TJ_b^T+u_bu_b^T\big)+\check\psi_i\mathcal V L_iL_i^T$
#   (on the $\hat x_i$ block). Targets update different rows and read only their own, so the three
#   updates apply one after the other.
#
# Then $P_i(k)=\mathbb E\{e_ie_i^T\}=Q_{x_ix_i}-Q_{x_i\hat x_i}-Q_{\hat x_ix_i}+Q_{\hat x_i\hat x_i}$, $\mathbb E\|x_i\|^2=\mathrm{tr}\,Q_{x_ix_i}$,
# and — what (18) and (28) ask for — $\mathbb E\{\hat x_i(k|k-1)\hat x_i^T(k|k-1)\}$ is the $\hat x_i$ block of $Q^-$.
# Using it makes the gain (28) deterministic: this is Algorithm 1 **with the theorem's own
# expectation**, for which the corrected Theorem 1 states $\mathfrak S_i(k|k)\succeq P_i(k)$ at every
# $k$ (X5 checks it with eigenvalues). $x(0)=$ offset $+\sigma$, $\sigma\sim U(0,1)^4$: $\mathbb E x(0)=$ offset $+\tfrac12$,
# $\mathrm{Cov}=I/12$, $\hat x(0|0)=x(0)$. (The exact $\mathbb E\{\hat x\hat x^T\}$ involves the attack signal's
# values, so this design checks the theorem; it is not an estimator a defender could run.)
#
# Two other gain rules use the same recursion: the **per-step optimal gain for (8)**, which minimises
# $\mathrm{tr}\,\mathbb E\{e_i(k|k)e_i^T(k|k)\}$ given the exact moments,
# $L_i^\star=\mathbb E\{e_i^-\nu_i^T\}\big(\mathbb E\{\nu_i\nu_i^T\}\big)^{+}$ (greedy in time: the best (8) can do step by
# step, with full knowledge of the moments), and $L=0$ (open-loop prediction).

# %%
NZ = 2 * N * NX  # joint state z = col(x_1..x_N, xhat_1..xhat_N)


def xs(i: int) -> slice:
    """Rows of x_i in z."""
    return slice(i * NX, (i + 1) * NX)


def hs(i: int) -> slice:
    """Rows of xhat_i in z."""
    return slice((N + i) * NX, (N + i + 1) * NX)


def joint_transition(k: int) -> np.ndarray:
    """A_z(k-1): (1) for x and (7) for xhat, without noise, shape (24, 24)."""
    a = np.zeros((NZ, NZ))
    for i in range(N):
        for rows in (xs, hs):
            a[rows(i), rows(i)] = AH_ALL[k - 1]
            for j in K_SETS[i]:
                a[rows(i), rows(j)] = BH[(i, j)]
    return a


AZ = np.stack([np.eye(NZ)] + [joint_transition(k) for k in range(1, T + 1)])
QW = np.zeros((T + 1, NZ, NZ))
for _i in range(N):
    QW[1:, xs(_i), xs(_i)] = W * E_ALL[:T, :, None] * E_ALL[:T, None, :]


def initial_moments() -> tuple[np.ndarray, np.ndarray]:
    """Mean and second moment of z(0): x(0) = offset + U(0,1) noise, xhat(0|0) = x(0)."""
    m0 = (X0_OFFSET + 0.5).ravel()
    second = np.eye(N * NX) / 12 + np.outer(m0, m0)
    return np.concatenate([m0, m0]), np.block([[second, second], [second, second]])


def innovation_map(i: int, b: float, G, xi_s, reading: str, c: float):
    """nu_i = Nz z + n0 + noise for psi_i = b (replacement or additive reading of (6)).

    Returns Nz (rows, 24), n0 (rows,) and the variance of the noise entering nu_i.
    """
    nz = np.zeros((G.shape[0], NZ))
    seen = b if reading == "replace" else 1.0  # weight of the true measurement in y_i
    nz[:, xs(i)] = seen * G
    nz[:, hs(i)] = -c * G
    return nz, (1 - b) * xi_s, seen * V


def bernoulli_update(mu, Q, i, L, G, xi_s, psi_i, reading, c):
    """Exact (mu, Q) after target i's update (8): average over psi_i in {1, 0}."""
    mu_n, Q_n = np.zeros_like(mu), np.zeros_like(Q)
    for b, p in ((1.0, psi_i), (0.0, 1.0 - psi_i)):
        if p == 0.0:
            continue
        nz, n0, var = innovation_map(i, b, G, xi_s, reading, c)
        J = np.eye(NZ)
        J[hs(i)] += L @ nz
        u = np.zeros(NZ)
        u[hs(i)] = L @ n0
        Jm = J @ mu
        mu_n += p * (Jm + u)
        Q_n += p * (J @ Q @ J.T + np.outer(Jm, u) + np.outer(u, Jm) + np.outer(u, u))
        Q_n[hs(i), hs(i)] += p * var * (L @ L.T)
    return mu_n, sym(Q_n)


def optimal_gain(mu, Q, i, G, xi_s, psi_i, reading, c):
    """Per-step MSE-optimal gain of (8): E{e^- nu^T} (E{nu nu^T})^+ from the exact moments."""
    ez = np.zeros((NX, NZ))
    ez[:, xs(i)], ez[:, hs(i)] = np.eye(NX), -np.eye(NX)
    rows = G.shape[0]
    cross, inn = np.zeros((NX, rows)), np.zeros((rows, rows))
    for b, p in ((1.0, psi_i), (0.0, 1.0 - psi_i)):
        if p == 0.0:
            continue
        nz, n0, var = innovation_map(i, b, G, xi_s, reading, c)
        a = nz @ mu
        cross += p * (ez @ Q @ nz.T + np.outer(ez @ mu, n0))
        inn += p * (nz @ Q @ nz.T + np.outer(a, n0) + np.outer(n0, a) + np.outer(n0, n0)
                    + var * np.eye(rows))
    return cross @ np.linalg.pinv(sym(inn))


def coefficients(psi_i, a2, a3, a4, variant):
    """bound_coefficients; a pair (c0's, kappa's variant), "printed" or "corrected", mixes them."""
    if isinstance(variant, tuple):
        c0_v, kappa_v = ("paper" if v == "printed" else v for v in variant)
        return (bound_coefficients(psi_i, a2, a3, a4, c0_v)[0],
                *bound_coefficients(psi_i, a2, a3, a4, kappa_v)[1:])
    return bound_coefficients(psi_i, a2, a3, a4, variant)


def bound_step(S, Q, i, k, w, psi_i, variant, G):
    """(17), (28), (18) for target i with the exact E{xhat(k|k-1) xhat^T(k|k-1)} (block of Q^-).

    Returns the gain, S_i(k|k) and S_i(k|k-1) (the last for the check of Theorem 2, C8)."""
    lam, a1, a2, a3, a4 = w
    ewe = W * np.outer(E_ALL[k - 1], E_ALL[k - 1])
    Sp = predicted_bound(S[i][None], [S[j][None] for j in K_SETS[i]], AH_ALL[k - 1],
                         [BH[(i, j)] for j in K_SETS[i]], lam, ewe, coupling_factor)
    L, S_i, _ = gain_and_bound(Sp, Q[hs(i), hs(i)][None], G,
                               coefficients(psi_i, a2, a3, a4, variant), a1, xi_star, V)
    return L[0], S_i[0], Sp[0]


def exact_moments(weights, *, gain="bound", variant="corrected", reading="replace",
                  debias=False, psi_bar=None):
    """Exact second-moment recursion of the estimator (8) with deterministic gains.

    gain: "bound" ((28) with the exact E{xhat xhat^T}, `variant` coefficients), "optimal"
    (per-step MSE-optimal gain) or "zero" (open loop); reading "replace"/"additive" of (6);
    debias uses y - psi_check Phi C H xhat(k|k-1) as innovation; psi_bar overrides PSI.
    Returns P (T+1, N, 4, 4) = E{e e^T}, S (bound, zeros unless gain "bound"), mean_e
    (T+1, N, 4), ex2 (T+1, N) = E||x_i||^2, L (T+1, N, 4, n_y), and for gain "bound" Sp
    (T+1, N, 4, 4) = S_i(k|k-1) and Xh = E{xhat_i(k|k-1) xhat_i^T(k|k-1)} (zeros otherwise).
    """
    psi_bar = PSI if psi_bar is None else np.asarray(psi_bar, float)
    mu, Q = initial_moments()
    rec = {"P": np.zeros((T + 1, N, NX, NX)), "S": np.zeros((T + 1, N, NX, NX)),
           "mean_e": np.zeros((T + 1, N, NX)), "ex2": np.zeros((T + 1, N)),
           "L": np.zeros((T + 1, N, NX, n_y)),
           "Sp": np.zeros((T + 1, N, NX, NX)), "Xh": np.zeros((T + 1, N, NX, NX))}
    S = np.broadcast_to(np.eye(NX), (N, NX, NX)).copy()  # S_i(0|0) = I
    for k in range(T + 1):
        if k > 0:
            mu, Q = AZ[k] @ mu, AZ[k] @ Q @ AZ[k].T + QW[k]  # prediction (1), (7)
            sched = SETS[k - 1]
            G, xi_s = CH[sched], XI[k, sched]
            S_new, gains = S.copy(), []
            for i in range(N):
                c = psi_bar[i] if debias else 1.0
                if gain == "bound":
                    L, S_new[i], rec["Sp"][k, i] = bound_step(S, Q, i, k, weights[i], psi_bar[i],
                                                              variant, G)
                    rec["Xh"][k, i] = Q[hs(i), hs(i)]
                elif gain == "optimal":
                    L = optimal_gain(mu, Q, i, G, xi_s, psi_bar[i], reading, c)
                else:
                    L = np.zeros((NX, len(sched)))
                gains.append((L, c))
                rec["L"][k, i][:, sched] = L
            for i, (L, c) in enumerate(gains):  # update (8), target by target
                mu, Q = bernoulli_update(mu, Q, i, L, G, xi_s, psi_bar[i], reading, c)
            S = S_new
        for i in range(N):
            qxx, qxh, qhh = Q[xs(i), xs(i)], Q[xs(i), hs(i)], Q[hs(i), hs(i)]
            rec["P"][k, i] = sym(qxx - qxh - qxh.T + qhh)
            rec["mean_e"][k, i] = mu[xs(i)] - mu[hs(i)]
            rec["ex2"][k, i] = np.trace(qxx)
        rec["S"][k] = S if gain == "bound" else 0.0
    return rec


def exact_mse(ex):
    """E||e_i(k|k)||^2 = tr P_i(k), shape (T+1, N)."""
    return np.trace(ex["P"], axis1=-2, axis2=-1)


def oracle_kalman(psi):
    """Centralised Kalman filter over the N targets that knows psi and drops attacked packets.

    Exact covariance given each run's psi sequence (no state simulation needed): returns
    tr P_i(k|k), shape (runs, T+1, N). P(0|0) = 0 since xhat(0|0) = x(0).
    """
    n = N * NX
    P = np.zeros((psi.shape[0], n, n))
    tr = np.zeros((psi.shape[0], T + 1, N))
    for k in range(1, T + 1):
        a = AZ[k][:n, :n]
        P = a @ P @ a.T + QW[k][:n, :n]
        G = CH[SETS[k - 1]]
        for i in range(N):
            h = np.zeros((G.shape[0], n))
            h[:, xs(i)] = G
            gain = np.swapaxes(np.linalg.solve(h @ P @ h.T + V * np.eye(G.shape[0]), h @ P), -1, -2)
            upd = sym(P - gain @ h @ P)
            P = np.where(psi[:, k - 1, i, None, None] == 1, upd, P)
        tr[:, k] = np.stack([np.trace(P[:, xs(i), xs(i)], axis1=-2, axis2=-1) for i in range(N)], -1)
    return tr


# %% [markdown]
# ## Choosing $\lambda,\alpha_1..\alpha_4$ (Remark 4)
#
# Remark 4 suggests minimising the bound over the weights. Our grid: $\lambda\in\{10^{-3},10^{-2},10^{-1}\}$,
# $\alpha_1\in\{0.3,1,3,10\}$, $\alpha_2,\alpha_3\in\{10^{-4},\dots,1\}$, $\alpha_4\in\{0.03,0.1,0.3\}$
# (900 candidates per target); objective $\frac1T\sum_{k=1}^T\mathrm{tr}\,\mathfrak S_i(k|k)$ averaged over
# 10 pilot runs (own seed); targets optimised in DAG order with upstream weights fixed
# ($\mathfrak S_i$ depends only on its own weights and on the upstream bounds). The pilot runs use the
# same (17) reading (`coupling_factor`) and $\mathbb E\{\hat x\hat x^T\}$ surrogate (`xhat_moment`) as the
# Monte Carlo runs, for the upstream targets and for every candidate. Candidates with
# $c_0\le0$ or $\kappa_x<0$ (possible with printed coefficients), or whose bound becomes
# non-finite or exceeds $10^{10}$, are discarded: large $\lambda$ with $\alpha_2+\alpha_3\gtrsim1$
# makes $\mathfrak S$ (and the estimator) explode. All candidates × pilot runs are one array
# pass per target (the candidate index is a second batch axis). In fast mode (and at the sweep's
# points) the grid is skipped and the table in the parameters cell — the grid's result at the
# default point — is used.
#
# `weight_rule` selects the weights in use: `"grid"` (this minimiser) or `"interior"`
# (`weights_interior` for every target, an interior grid point with non-degenerate gains).


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
        # upstream targets with their chosen weights (targets i.. do not influence them)
        up = simulate(pilots, chosen + W_INTERIOR[i:], variant=variant, moment=xhat_moment,
                      k_factor=coupling_factor)
        idx = np.repeat(np.arange(pilot_runs), n_c)  # batch = pilot-major, candidate-minor
        lam, a1, a2, a3, a4 = (np.tile(cand[:, q], pilot_runs)[:, None, None] for q in range(5))
        coefs = bound_coefficients(PSI[i], a2, a3, a4, variant)
        S_i = np.broadcast_to(np.eye(NX), (idx.size, NX, NX))
        xh_i = up["xhat"][idx, 0, i]
        total, peak = np.zeros(idx.size), np.zeros(idx.size)
        with np.errstate(all="ignore"):
            for k in range(1, T + 1):
                ah, sched = AH_ALL[k - 1], SETS[k - 1]
                xp = M.predict(xh_i, [up["xhat"][idx, k - 1, j] for j in K_SETS[i]], ah,
                               [BH[(i, j)] for j in K_SETS[i]])  # (7)
                Sp = predicted_bound(S_i, [up["S"][idx, k - 1, j] for j in K_SETS[i]], ah,
                                     [BH[(i, j)] for j in K_SETS[i]], lam,
                                     W * np.outer(E_ALL[k - 1], E_ALL[k - 1]), coupling_factor)
                xn = up["x"][idx, k, i]
                ok = pilots["psi"][idx, k - 1, i, None]
                y_s = ok * (xn @ CH[sched].T + pilots["v"][idx, k - 1, i][:, sched]) \
                    + (1 - ok) * XI[k, sched]
                G = CH[sched]
                X_hat = xp[:, :, None] * xp[:, None, :]
                if xhat_moment == "ensemble":  # mean over the pilot runs, per candidate
                    X_hat = np.tile(X_hat.reshape(pilot_runs, n_c, NX, NX).mean(axis=0),
                                    (pilot_runs, 1, 1))
                L, S_i, _ = gain_and_bound(Sp, X_hat, G, coefs, a1, xi_star, V)
                xh_i = M.correct(xp, y_s, G, L)  # (8)
                tr_k = np.trace(S_i, axis1=-2, axis2=-1)
                total += tr_k
                peak = np.maximum(peak, np.where(np.isfinite(tr_k), tr_k, np.inf))
        obj = (total / T).reshape(pilot_runs, n_c)
        peak = peak.reshape(pilot_runs, n_c)
        c0v, kxv, *_ = bound_coefficients(PSI[i], cand[:, 2], cand[:, 3], cand[:, 4], variant)
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


def weights_in_use(variant: str) -> list[tuple[float, ...]]:
    """Weights of the design with `variant` coefficients under `weight_rule`."""
    return WEIGHTS[variant] if weight_rule == "grid" else W_INTERIOR


W_MAIN, W_CORR, W_PRINTED = weights_in_use(coef), weights_in_use("corrected"), weights_in_use("paper")

# %% [markdown]
# The grid optimum for targets 2 and 3 sits at its edge $\alpha_2=\alpha_3\to0$, i.e.
# $\kappa_x,\kappa_\xi\to\infty$ and $L\to0$: with attack probability ≥ 0.5 and states of
# magnitude 20–100 (RMS at $k=T$), the replacement attack makes every gain costly in the bound, so the
# trace-optimal design essentially ignores the measurements. With the printed coefficients the
# minimiser instead takes $\alpha_3>\alpha_2$, i.e. $c_0<1$, which shrinks the "bound" (C1b). Theorem 3
# requires $1+\alpha_5+\alpha_6\le c_0$, which with the printed $c_0$ forces $\alpha_2>\alpha_3$; a third grid
# restricted to $\alpha_2>\alpha_3$ (`paper_thm3`) is run for comparison. Coefficients at the weights in use:

# %%
for name, v, table in (("main", coef, W_MAIN), ("printed", "paper", W_PRINTED),
                       ("paper_thm3", "paper", WEIGHTS["paper_thm3"])):
    for i, (lam_, a1_, a2_, a3_, a4_) in enumerate(table):
        c0_, kx_, kxi_, _ = bound_coefficients(PSI[i], a2_, a3_, a4_, v)
        print(f"{name:>10} ({v}) target {i + 1}: lambda={lam_:g} a1={a1_:g} a2={a2_:g} a3={a3_:g} "
              f"a4={a4_:g} -> c0={c0_:.5g}, kappa_x={kx_:.5g}, kappa_xi={kxi_:.5g}")

# %% [markdown]
# ## The numerical example: Monte Carlo runs and exact expectations
#
# One draw of all randomness (`mc_seed`), shared by every Monte Carlo estimator so that differences
# are due to the estimators only; next to it the exact expectations of the same design with the
# theorem's $\mathbb E\{\hat x\hat x^T\}$. Single-run and single-seed numbers vary: Monte Carlo
# values below carry 95 % $t$-intervals over the $F$ runs.

# %%
DRAWS = draw_randomness(montecarlo.spawn_rngs(mc_seed, 1)[0], F, T)
out = simulate(DRAWS, W_MAIN, variant=coef, moment=xhat_moment, k_factor=coupling_factor)
out_zoh = simulate(DRAWS, W_MAIN, variant=coef, moment=xhat_moment, estimator="zoh",
                   k_factor=coupling_factor)
out_printed = simulate(DRAWS, W_PRINTED, variant="paper", moment=xhat_moment,
                       k_factor=coupling_factor)
out_printed_thm3 = simulate(DRAWS, WEIGHTS["paper_thm3"], variant="paper", moment=xhat_moment,
                            k_factor=coupling_factor)
out_corr = out if coef == "corrected" else simulate(DRAWS, W_CORR, moment=xhat_moment,
                                                    k_factor=coupling_factor)
MSE, TRS = mse(out), mean_trace(out)
EX = exact_moments(W_MAIN, variant=coef)  # the main design with the exact E{xhat xhat^T}
EX2 = EX["ex2"]  # E||x_i(k)||^2, the same for every estimator
# X2: the vectorised pass equals a loop over runs (first 5 runs; the benchmark times all 100)
ref = out if xhat_moment == "run" else simulate(DRAWS, W_MAIN, variant=coef,
                                                k_factor=coupling_factor)
loop_dev = 0.0
for f in range(min(5, F)):
    one = simulate({key: val[f:f + 1] for key, val in DRAWS.items()}, W_MAIN, variant=coef,
                   k_factor=coupling_factor)
    for name in ("xhat", "S"):
        scale = max(1.0, float(np.max(np.abs(ref[name][f]))))
        loop_dev = max(loop_dev, float(np.max(np.abs(one[name][0] - ref[name][f]))) / scale)
print(f"max relative |vectorised - loop over runs| (x_hat, S; 5 runs): {loop_dev:.3g}")
kk = np.arange(T + 1)


def time_avg_with_interval(o):
    """Time-averaged MSE per target with its 95 % t-interval over the runs."""
    per_run = sq_err(o)[:, 1:].mean(axis=1)  # (F, N)
    lo, hi = t_intervals(per_run, 0.95)
    return per_run.mean(axis=0), lo, hi


for name, o in (("zero-input (8)", out), ("ZOH", out_zoh), ("printed coef.", out_printed),
                ("printed, a2>a3", out_printed_thm3)):
    mean_, lo_, hi_ = time_avg_with_interval(o)
    print(f"{name:>15}: time-averaged MSE " + ", ".join(
        f"{a:.4g} [{b:.4g}, {c:.4g}]" for a, b, c in zip(mean_, lo_, hi_, strict=True))
        + f"; mean tr S = {np.round(mean_trace(o)[1:].mean(axis=0), 2)}")
print(f"{'exact':>15}: time-averaged E||e||^2 = {np.round(exact_mse(EX)[1:].mean(axis=0), 2)} "
      f"(main design with the exact E{{xhat xhat^T}}), tr S = "
      f"{np.round(np.trace(EX['S'], axis1=-2, axis2=-1)[1:].mean(axis=0), 2)}")

# %% [markdown]
# ### The exact recursion agrees with Monte Carlo (X3)
#
# An independent check of the recursion: Monte Carlo runs of the *same* deterministic gains (those of
# the exact design, fed to `simulate`) must reproduce $\mathbb E\|e_i\|^2$. The per-run time average of
# $\|e_i\|^2$ is strongly skewed (runs with long attacked stretches dominate), so $F=100$ runs
# under-cover; the check uses its own `x3_runs` runs (independent streams of `mc_seed`, in chunks). Rule:
# for every target, the exact time-averaged value lies in the 99.9 % (Bonferroni over the three
# targets) $t$-interval of the Monte Carlo time average.


# %%
def fixed_gain_runs(runs: int, chunk: int = 500) -> np.ndarray:
    """Per-run time-averaged ||e_i||^2 (runs, N) of the exact design's gains in fresh runs."""
    rngs = montecarlo.spawn_rngs(mc_seed, 1 + -(-runs // chunk))[1:]
    per_run = []
    for c, rng in enumerate(rngs):
        draws = draw_randomness(rng, min(chunk, runs - c * chunk), T)
        o = simulate(draws, W_MAIN, variant=coef, k_factor=coupling_factor, gains=EX["L"])
        per_run.append(sq_err(o)[:, 1:].mean(axis=1))
    return np.concatenate(per_run)


X3_LEVEL = 1 - 0.001 / N
x3_runs_avg = fixed_gain_runs(x3_runs)
x3_lo, x3_hi = t_intervals(x3_runs_avg, X3_LEVEL)
x3_exact = exact_mse(EX)[1:].mean(axis=0)
x3_inside = (x3_lo <= x3_exact) & (x3_exact <= x3_hi)
print("exact time-averaged E||e||^2:", np.round(x3_exact, 3))
print(f"Monte Carlo, same gains, {x3_runs} runs:", np.round(x3_runs_avg.mean(axis=0), 3),
      "interval", np.round(np.stack([x3_lo, x3_hi], -1), 3).tolist())

# %% [markdown]
# ## Figs. 2–4 — trajectories of $x_i(k)$ and their estimates (one run)
#
# Solid: true state; dashed: $\hat x_i(k|k)$ of the zero-input estimator (8), Monte Carlo run
# `plot_run`. The *Y* components collapse at $k=1$ (they are multiplied by $\epsilon$ in (1)) and then
# follow $X^v$ through the coupling of $A_i$. One run is one draw: the tracking claim is recorded with
# exact expectations (C7, last sections).

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


# %% [markdown]
# ## Figs. 5 and 6 — attack signals and estimation errors (one run), zero-input and ZOH
#
# Left: the values the attacker puts in place of the scheduled measurements,
# $\Phi_{o(k)}(1-\psi_i(k))\xi_i(k)$, per sensor (markers only at attacked steps and scheduled
# sensors), in the units of the measurement they replace. Middle: the four components of
# $e_i(k|k)$. Fig. 6 uses the same noise and attack realisation with the ZOH estimator, the same
# error axes as Fig. 5, and a third column comparing $\|e_i(k|k)\|$ of both estimators.

# %%
def injected_attack(i: int) -> np.ndarray:
    """Values that replace the scheduled measurements of target i in run plot_run (NaN: none)."""
    inj = np.full((T, n_y), np.nan)
    for k in range(1, T + 1):
        if DRAWS["psi"][plot_run, k - 1, i] == 0:
            inj[k - 1, SETS[k - 1]] = XI[k, SETS[k - 1]]
    return inj


ERR_RUN = {"zero-input": (out["x"] - out["xhat"])[plot_run, 1:],
           "ZOH": (out_zoh["x"] - out_zoh["xhat"])[plot_run, 1:]}  # (T, N, 4)
ERR_LIM = np.max([np.abs(e).max(axis=(0, 2)) for e in ERR_RUN.values()], axis=0) * 1.08


def attack_and_error_figure(which: str, title: str, name: str) -> None:
    compare = which == "ZOH"
    fig, axes = plt.subplots(N, 3 if compare else 2, figsize=(plotting.PAGE_WIDTH, 6.6),
                             sharex=True, layout="constrained", squeeze=False)
    data = {"k": kk[1:]}
    err = ERR_RUN[which]
    for i in range(N):
        injected = injected_attack(i)
        for r in range(n_y):
            axes[i, 0].plot(kk[1:], injected[:, r], "o", ms=2.4,
                            label=f"sensor {r + 1}: {SENSOR_SEES[r]}")
        for c in range(NX):
            axes[i, 1].plot(kk[1:], err[:, i, c], lw=0.9, label=LABELS[c])
        axes[i, 1].set_ylim(-ERR_LIM[i], ERR_LIM[i])
        axes[i, 0].set_ylabel(f"target {i + 1}\nreplaced value\n[m or m/s]")
        axes[i, 1].set_ylabel(f"$e_{{{i + 1}}}(k|k)$ [m, m/s]")
        data[f"attack_target{i + 1}"] = injected
        data[f"error_target{i + 1}"] = err[:, i]
        if compare:
            for label, style in (("ZOH", "-"), ("zero-input", "--")):
                axes[i, 2].plot(kk[1:], np.linalg.norm(ERR_RUN[label][:, i], axis=-1), style,
                                lw=1.0, color="tab:purple" if label == "ZOH" else "k", label=label)
            axes[i, 2].set_ylabel(f"$\\|e_{{{i + 1}}}(k|k)\\|$ [m, m/s]")
            data[f"norm_error_zoh_minus_zero_target{i + 1}"] = (
                np.linalg.norm(ERR_RUN["ZOH"][:, i], axis=-1)
                - np.linalg.norm(ERR_RUN["zero-input"][:, i], axis=-1))
    for col, ax in enumerate(axes[-1]):
        ax.set_xlabel("time step k [–]")
        handles, labels = axes[0, col].get_legend_handles_labels()
        ax.legend(handles, labels, fontsize=6.5, loc="upper center", ncol=2 if col == 0 else 4,
                  bbox_to_anchor=(0.5, -0.32), frameon=False, handletextpad=0.2, columnspacing=0.7)
    fig.suptitle(title)
    plotting.save_figure(fig, FIG_DIR, name, data=data)


attack_and_error_figure("zero-input", f"Fig. 5: attack signals and errors, zero-input, run {plot_run}",
                        "fig5_attack_and_errors")
attack_and_error_figure("ZOH", f"Fig. 6: attack signals and errors, ZOH, run {plot_run}",
                        "fig6_attack_and_errors_zoh")

# %% [markdown]
# ## Fig. 7 — $\mathrm{MSE}_i(k)$ over $F$ runs and the minimum upper bound (C1c)
#
# As the paper runs it: Algorithm 1 with the data-dependent surrogate of $\mathbb E\{\hat x\hat x^T\}$
# (`xhat_moment`), so $\mathfrak S_i$ differs across runs and MSE is compared with the Monte Carlo mean of
# $\mathrm{tr}\,\mathfrak S_i(k|k)$. The derivation of (21) takes $L_i(k)$ out of the expectation, i.e. treats the
# gain as deterministic; with a data-dependent gain the corrected Theorem 1 does not imply the
# inequality, so this is a measurement, decided by a rule on confidence intervals: with
# $d_f(k)=\mathrm{tr}\,\mathfrak S^{(f)}_i(k|k)-\|e^{(f)}_i(k|k)\|^2$, it holds if at every $k$ and target the
# upper end of the two-sided $t$-interval of $\frac1F\sum_fd_f(k)$ (Bonferroni over the $3T$ cells,
# family level 95 %) is $\ge0$ — no step where the MSE is significantly above the mean bound. The
# paper's literal reading (MSE below the bound at every $k$, a fraction equal to 1) is reported; it
# fails spuriously from Monte Carlo noise where the bound is tight (e.g. $\check\psi=1$).
#
# **Which design.** Fig. 7 is judged as printed: C1c applies this rule to the design with the
# coefficients of Theorem 2 at their Remark-4 weights (second figure below, where the "bound" lies
# below the MSE). The same rule on our corrected design is ours, X6: it passes only with our
# correction (first figure).
#
# At $k=1$ the MSE is ~1e−4 or smaller ($E_i(0)=0$); the log axes start at $k=1$ and their lower limit
# follows the data from $k=2$. The ZOH estimator's MSE is drawn on top (purple, dashed).

# %%
C1C_LEVEL = 1 - 0.05 / (N * T)
d_runs = np.trace(out_corr["S"], axis1=-2, axis2=-1)[:, 1:] - sq_err(out_corr)[:, 1:]  # (F, T, N)
d_lo, d_hi = t_intervals(d_runs, C1C_LEVEL)
TRS_C, MSE_C = mean_trace(out_corr), mse(out_corr)
c1c_rel_hi = d_hi / TRS_C[1:]
c1c_worst = np.unravel_index(np.argmin(c1c_rel_hi), c1c_rel_hi.shape)
K5 = slice(min(5, T), T + 1)  # k >= 5: past the first steps where S(0|0) = I dominates
print("worst cell (k, target):", (int(c1c_worst[0]) + 1, int(c1c_worst[1]) + 1),
      f"relative margin {d_runs.mean(axis=0)[c1c_worst] / TRS_C[1:][c1c_worst]:.4g}, "
      f"interval [{d_lo[c1c_worst] / TRS_C[1:][c1c_worst]:.4g}, {c1c_rel_hi[c1c_worst]:.4g}]")
print("min over k >= 5 of mean tr S / MSE:", np.round((TRS_C[K5] / MSE_C[K5]).min(axis=0), 3))
# the same rule on the design as printed (coefficients of Theorem 2, their Remark-4 weights): C1c
d_runs_p = np.trace(out_printed["S"], axis1=-2, axis2=-1)[:, 1:] - sq_err(out_printed)[:, 1:]
dp_lo, dp_hi = t_intervals(d_runs_p, C1C_LEVEL)
TRS_P, MSE_P = mean_trace(out_printed), mse(out_printed)
C1C_P_FINITE = bool(np.all(np.isfinite(dp_hi)) and np.all(TRS_P[1:] > 0))
c1cp_rel_hi = np.where(TRS_P[1:] > 0, dp_hi / np.where(TRS_P[1:] > 0, TRS_P[1:], 1.0), -np.inf)
c1cp_worst = np.unravel_index(np.argmin(c1cp_rel_hi), c1cp_rel_hi.shape)
print("printed coefficients: worst cell (k, target):", (int(c1cp_worst[0]) + 1, int(c1cp_worst[1]) + 1),
      f"upper end of the relative margin {c1cp_rel_hi[c1cp_worst]:.4g}; cells whose whole interval "
      f"lies below 0: {int(np.sum(c1cp_rel_hi < 0))} of {c1cp_rel_hi.size}")


def log_floor(*curves) -> float:
    """Lower y-limit of a log plot: a bit below the smallest positive value from k = 2 on."""
    vals = np.concatenate([np.ravel(c[2:]) for c in curves])
    vals = vals[np.isfinite(vals) & (vals > 0)]
    return 0.5 * vals.min() if vals.size else 1e-3


def fig7(o, o_zoh, title, name):
    fig, axes = plt.subplots(1, N, figsize=(plotting.PAGE_WIDTH, 3.1), sharex=True,
                             layout="constrained")
    m_, t_ = mse(o), mean_trace(o)
    data = {"k": kk[1:], "mse": m_[1:], "mean_tr_S": t_[1:]}
    for i, ax in enumerate(axes):
        ax.semilogy(kk[1:], t_[1:, i], color="tab:blue", label="upper bound (mean tr $\\mathfrak{S}$)")
        ax.semilogy(kk[1:], m_[1:, i], color="tab:red", lw=1.6, label="MSE, zero-input (8)")
        curves = [t_[:, i], m_[:, i]]
        if o_zoh is not None:
            ax.semilogy(kk[1:], mse(o_zoh)[1:, i], "--", color="tab:purple", lw=1.0, zorder=3,
                        label="MSE, ZOH")
            curves.append(mse(o_zoh)[:, i])
        ax.set_title(f"target {i + 1}")
        ax.set_xlabel("time step k [–]")
        ax.set_ylim(bottom=log_floor(*curves))
    if o_zoh is not None:
        data["mse_zoh"] = mse(o_zoh)[1:]
    axes[0].set_ylabel("MSE$_i(k)$, tr bound [m², m²/s²]")
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=3, fontsize=7,
               frameon=False)
    fig.suptitle(title)
    plotting.save_figure(fig, FIG_DIR, name, data=data)


fig7(out_corr, out_zoh if coef == "corrected" else None,
     f"Fig. 7: MSE over {F} runs and minimum upper bound (corrected coefficients)",
     "fig7_mse_and_bound")
fig7(out_printed, None, "Fig. 7 with the printed coefficients: the 'bound' is below the MSE",
     "extra_fig7_printed_coefficients")

# %% [markdown]
# ## X5 — the corrected bound (ours), certified by the exact second-moment recursion
#
# *This is our corrected design, not the paper's* (claim **X5**, ours): it holds only with the
# coefficients we re-derived; the bound as printed is C1b, which is what the verdict judges. The
# certificate below is that of X5 (and, with the printed coefficients, of C1b).
#
# With the theorem's own $\mathbb E\{\hat x\hat x^T\}$ (exact recursion above) the gain is deterministic and
# $\mathfrak S_i(k|k)\succeq P_i(k)=\mathbb E\{e_i(k|k)e_i^T(k|k)\}$ must hold at **every** $k$ as a matrix
# inequality. The certificate is scale-free: $\mathfrak S\succeq P$ if and only if the largest generalised
# eigenvalue $\lambda_{\max}(\mathfrak S^{-1/2}P\,\mathfrak S^{-1/2})$ — the largest share of the bound that the true
# covariance reaches in any direction — is at most 1; we require
# $\max_{k,i}\lambda_{\max}(\mathfrak S_i^{-1/2}P_i\mathfrak S_i^{-1/2})\le1+10^{-9}$ ($10^{-9}$ absorbs rounding) and also report
# $\min_k\lambda_{\min}(\mathfrak S_i-P_i)$. It is evaluated at the paper's $\check\psi$ and at every $\check\psi$ of
# `c1_psi_scan` (the same for all targets; $\check\psi=1$ is the attack-free case, where the corrected
# bound is nearly tight), with the weights in use (`weight_rule`) and the (17) reading in use
# (`coupling_factor`); the sweep covers the other readings. **Margin-aware rule (X5, session 9).** At
# $\check\psi=1$ the largest share is $1-4\cdot10^{-9}$: its margin to $1+10^{-9}$ is below the claim's own
# cross-machine tolerance ($10^{-6}$), so another machine could decide it the other way. A scenario whose
# share lies within that tolerance of $1+10^{-9}$ is recorded as *tight* (equality to rounding, which
# $\mathfrak S\succeq P$ allows but floating point cannot certify) and not decided; X5 holds if every decided
# scenario holds (and one is decided), fails if one fails. The earlier rule (all scenarios
# $\le1+10^{-9}$) is recorded beside it as `old_rule_holds`.


# %%
def share_curve(ex) -> np.ndarray:
    """lambda_max(S_i^{-1/2} P_i S_i^{-1/2}) for k = 1..T, shape (T, N).

    S_i >= P_i at step k iff it is <= 1; inf where S_i is not positive definite (then
    S_i >= P_i fails too).
    """
    d, u = np.linalg.eigh(ex["S"][1:])
    pd = np.all(d > 0, axis=-1)
    root = u * (1 / np.sqrt(np.where(d > 0, d, 1.0)))[..., None, :]  # S^{-1/2} up to a rotation
    whitened = np.swapaxes(root, -1, -2) @ ex["P"][1:] @ root
    return np.where(pd, np.linalg.eigvalsh(sym(whitened))[..., -1], np.inf)


def min_gap(ex) -> np.ndarray:
    """min over k >= 1 of lambda_min(S_i - P_i) per target (absolute, m^2 and m^2/s^2)."""
    return np.linalg.eigvalsh(ex["S"][1:] - ex["P"][1:])[..., 0].min(axis=0)


EX_CORR = EX if coef == "corrected" else exact_moments(W_CORR)
C1_SCENARIOS = {"paper psi_check": EX_CORR} | {
    f"psi_check = {p:g}": exact_moments(W_CORR, psi_bar=np.full(N, p)) for p in c1_psi_scan}
C1_SHARE = {name: share_curve(ex) for name, ex in C1_SCENARIOS.items()}
C1_MAX = max(float(v.max()) for v in C1_SHARE.values())
C1_GAP = {name: min_gap(ex) for name, ex in C1_SCENARIOS.items()}
TRP_C, TRS_EX = exact_mse(EX_CORR), np.trace(EX_CORR["S"], axis1=-2, axis2=-1)
for name, v in C1_SHARE.items():
    print(f"{name:>18}: max_k lambda_max(S^-1/2 P S^-1/2) = "
          f"{np.array2string(v.max(axis=0), precision=4)}, "
          f"min_k lambda_min(S - P) = {np.array2string(C1_GAP[name], precision=3)}")
print("exact: min over k >= 5 of tr S / tr P:", np.round((TRS_EX[K5] / TRP_C[K5]).min(axis=0), 3))

fig, axes = plt.subplots(2, N, figsize=(plotting.PAGE_WIDTH, 5.0), sharex=True, layout="constrained")
share_data = {}
for i in range(N):
    ax = axes[0, i]
    ax.semilogy(kk[1:], TRS_EX[1:, i], color="tab:blue", label="tr $\\mathfrak{S}_i(k|k)$, exact design")
    ax.semilogy(kk[1:], TRP_C[1:, i], color="k", label="tr $P_i(k)=\\mathbb{E}\\|e_i\\|^2$, exact")
    ax.semilogy(kk[1:], MSE_C[1:, i], color="tab:red", lw=0.8, alpha=0.8,
                label=f"MSE, {F} runs ({xhat_moment} surrogate)")
    ax.set_ylim(bottom=log_floor(TRS_EX[:, i], TRP_C[:, i], MSE_C[:, i]))
    ax.set_title(f"target {i + 1}")
    for s_idx, (name, share) in enumerate(C1_SHARE.items()):
        share_data[f"{name} target{i + 1}"] = share[:, i]
        style = ({"color": "k", "ls": "--", "lw": 1.3} if s_idx == 0 else
                 {"color": plt.cm.viridis((s_idx - 1) / max(1, len(C1_SHARE) - 2)), "lw": 0.9})
        axes[1, i].plot(kk[1:], np.minimum(share[:, i], 2.0), label=name, **style)
    axes[1, i].axhline(1.0, color="tab:red", lw=0.8)
    axes[1, i].set_xlabel("time step k [–]")
axes[0, 0].set_ylabel("[m², m²/s²]")
axes[1, 0].set_ylabel("$\\lambda_{\\max}(\\mathfrak{S}^{-1/2}P\\,\\mathfrak{S}^{-1/2})$ [–]")
axes[0, N - 1].legend(fontsize=6.5, loc="lower right")
fig.legend(*axes[1, 0].get_legend_handles_labels(), loc="outside lower center", ncols=6, fontsize=7,
           frameon=False)
fig.suptitle("X5 (ours): the corrected bound against the exact error covariance "
             "(the bound holds where the share is ≤ 1)")
_ = plotting.save_figure(fig, FIG_DIR, "extra_exact_bound_certificate",
                         data={"k": kk[1:], "tr_S_exact": TRS_EX[1:], "tr_P_exact": TRP_C[1:],
                               "mse_monte_carlo": MSE_C[1:]} | share_data)

# %% [markdown]
# ### The printed coefficients are not a bound (C1b)
#
# The same certificate for the design with the coefficients as printed in Theorem 2, with the weights
# the Remark-4 grid picks for them (or the interior weights under `weight_rule="interior"`): a share
# above 1 is an exact counterexample — the "bound" lies below the true error covariance in that
# direction. With the grid restricted to $\alpha_2>\alpha_3$ (Theorem 3's condition) the printed recursion
# stays above the MSE (reported), but its minimiser then drives every gain to ≈ 0; even then the printed
# $c_0$ is below the derived one by $2\alpha_3(1-\check\psi)$, so the induction of Theorem 1 does not go through.
#
# **Two printed errors, measured apart** (recorded in C1b and C8): the certificate with the printed $c_0$ and
# the derived $\kappa$'s, and with the derived $c_0$ and the printed $\kappa_x$, at the same weights (printed
# below). With the derived coefficients the bound holds for every positive weight set by the derivation
# above; X5 certifies it at the weights used. The verdict judges the printed statement.

# %%
EX_PRINTED = exact_moments(W_PRINTED, variant="paper")
EX_PRINTED_THM3 = exact_moments(WEIGHTS["paper_thm3"], variant="paper")
C1B_SHARE, C1B_SHARE_THM3 = share_curve(EX_PRINTED), share_curve(EX_PRINTED_THM3)
C1B_FIRST_K = [int(np.argmax(C1B_SHARE[:, i] > 1 + 1e-9)) + 1 if np.any(C1B_SHARE[:, i] > 1 + 1e-9)
               else 0 for i in range(N)]
print("printed coefficients: max_k share", np.array2string(C1B_SHARE.max(axis=0), precision=4),
      "first violating k per target (0: none)", C1B_FIRST_K)
# Theorem 1's premise: (17)-(18) have positive-definite solutions at every k (C1b's premise)
C1B_MIN_EIG = float(min(np.linalg.eigvalsh(EX_PRINTED["S"][1:]).min(),
                        np.linalg.eigvalsh(EX_PRINTED["Sp"][1:]).min()))
print(f"printed coefficients: min over k, targets of lambda_min of S(k|k-1), S(k|k): {C1B_MIN_EIG:.4g}")
print("printed, alpha2 > alpha3: max_k share", np.array2string(C1B_SHARE_THM3.max(axis=0), precision=4))
print("time-averaged tr S / E||e||^2 (exact, printed):",
      np.round(np.trace(EX_PRINTED["S"], axis1=-2, axis2=-1)[1:].mean(axis=0)
               / exact_mse(EX_PRINTED)[1:].mean(axis=0), 4))
SPLITS = (("printed", "corrected"), ("corrected", "printed"))  # (c0's, kappa's) coefficients


def mixed_design(weights, variant) -> tuple[dict, int]:
    """exact_moments with mixed coefficients, and its last k whose bound is finite (float64 overflow)."""
    with np.errstate(all="ignore"):
        ex = exact_moments(weights, variant=variant)
    finite = np.all(np.isfinite(ex["S"]) & np.isfinite(ex["Sp"]), axis=(1, 2, 3))
    return ex, T if finite.all() else int(np.argmin(finite)) - 1


def split_share(variant) -> dict:
    """C1b's certificate, max over the finite steps, with one printed coefficient (weights W_PRINTED)."""
    ex, last = mixed_design(W_PRINTED, variant)
    share = share_curve({"S": ex["S"][:last + 1], "P": ex["P"][:last + 1]}).max(axis=0) if last else None
    return {"max_share": share, "last_finite_k": last}


# the two printed errors apart (C1b's attribution): printed c0 alone, printed kappa_x alone
C1B_SPLIT = {f"{a} c0, {b} kappa_x": split_share((a, b)) for a, b in SPLITS}
print("one printed coefficient:", {k: (np.round(v["max_share"], 4).tolist(), v["last_finite_k"])
                                   for k, v in C1B_SPLIT.items()})

# %% [markdown]
# ### Theorem 2: does the gain (28) minimise the trace of the bound (18)? (C8)
#
# Theorem 2 states that "the upper-bound $\mathfrak S_i(k|k)$ … can be minimized by designing the estimator
# parameter as" (28), its proof setting $\partial\,\mathrm{tr}\,\mathfrak S_i(k|k)/\partial L_i(k)=0$ (29); Section III's
# opening and the conclusion repeat it ("an appropriate estimator gain matrix … can be obtained by
# minimizing the trace of the presented upper-bound"). We check it at the example along the trajectory of
# Algorithm 1 run at each weight set judged (below): at every $k=1..T$ and target, with that step's $\mathfrak S_i(k|k-1)$ and exact
# $\mathbb E\{\hat x\hat x^T\}$, the gain $L^\star$ of (28) (`gain_and_bound`) is perturbed, $L=L^\star+s\,\delta$, and the trace
# of (18) is evaluated at $L$ term by term as printed (`bound_for_gain`, an evaluation of (18), not
# the gain formula). Directions $\delta$ (unit Frobenius norm): 32 random Gaussian ones, the structured
# ones $e_r v_j^T$ (every state $r$, every eigenvector $v_j$ of $\Pi$ of (28): they span all curvature
# directions, the least-curved one included) and $\pm L^\star$ itself (a larger or smaller gain); steps
# $s=t\max(\|L^\star\|_F,1)$ with $t\in\{10^{-3},10^{-1},1\}$, both signs. Since (18) is quadratic in $L$,
# the symmetric difference measures the first-order term (zero at a stationary point) and the
# mean the second-order one $s^2\,\mathrm{tr}(\delta\,\Pi\,\delta^T)$, which is non-negative in every direction
# iff $\Pi\succeq0$; both are reported, with $\min\lambda(\Pi)$.
#
# **Which weights.** Theorem 2 is stated "for given positive scalars $\epsilon$, $\alpha_l$ ($l=1..4$) and
# $\lambda$". Our Remark-4 grid keeps only weight sets with printed $c_0>0$ and $\kappa_x\ge0$; there
# $\Pi=(c_0+(1+\alpha_1)\kappa_x)G\mathfrak S G^T+(1+\alpha_1^{-1})\kappa_x G\hat XG^T+(\kappa_\xi\xi^*+\kappa_v\mathcal V)I\succ0$
# whatever $\mathfrak S(k|k-1)$ and $\hat X$ are, and the first-order term vanishes at (28) by algebra, so at
# the grid's weights the minimum is **certain before it is measured** (by construction: C8b, shown, not
# evidence). The measured content is a weight set the grid discards: the declared `thm2_weights`
# $(\lambda,\alpha_1..\alpha_4)=(0.1,1,9.5,10,0.01)$ (ours; the reviewer's synthetic counterexample), for every
# target, with printed $c_0=1-0.5(1-\check\psi_i)>0$ and $\kappa_x=\check\psi_i-0.89<0$ for $\check\psi_i<0.89$ (0.65
# and −0.59 at $\check\psi=0.3$). If $\Pi$ is indefinite, (28) is a saddle of $\mathrm{tr}$(18), which is then
# unbounded below in $L$, and "can be minimized by (28)" fails. C8 judges all three weight sets.
#
# **Which trajectory.** Theorem 2 is a statement about Algorithm 1 "for given positive scalars": with
# those weights, $\mathfrak S_i(k|k-1)$ comes from (17) — where $\lambda$ enters — applied to the previous
# $\mathfrak S(k-1|k-1)$ of the same recursion, and $\mathbb E\{\hat x\hat x^T\}$ from the same estimator. That is
# the paper's reading, and C8 now uses it: each weight set is judged along **its own** trajectory (exact
# $\mathbb E\{\hat x\hat x^T\}$). The previous version judged the declared weights along the printed design's
# trajectory at its Remark-4 weights, where their $\lambda$ did not enter (18) or (28); that evaluation is
# kept beside it (reported, not judged) and gives the same outcome. At the declared weights (17)–(18)
# keep positive-definite solutions (Theorem 1's condition, measured below), so the saddle is not a
# breakdown of the recursion: at every step where $\Pi$ is indefinite, $\mathfrak S(k|k)$ at (28) is still
# positive definite (its smallest eigenvalue is recorded in C8), and we count the steps where a small step
# along $\Pi$'s most negative direction lowers tr (18) **and** keeps $\mathfrak S(k|k)$ positive definite.
#
# **Of the two printed errors (C1b section), C8 rests on the first**: (21)'s sign gives the printed
# $\kappa_x=\check\psi+\alpha_3^{-1}+\alpha_4-1<0$ here; with the derived $c_0,\kappa_x\ge0$ (every positive weight set)
# $\Pi\succ0$. The split is measured below (derived $c_0$ with printed $\kappa_x$, and the reverse).
#
# Rule (ours, stated here once): (18) is quadratic in $L$ with its first-order term zero at (28), so (28)
# minimises $\mathrm{tr}$(18) iff $\Pi\succeq0$. **The headline is the quantity that decides**: the smallest
# eigenvalue of $\Pi$ relative to its largest $|\text{eigenvalue}|$, over all steps, targets and the three
# weight sets; the claim holds if it is $\ge-10^{-10}$ (rounding), fails below, and is not-checked when it lies
# within its own cross-machine tolerance of that level. The perturbations corroborate it (reported, not the
# rule): their smallest relative change of the trace is largest at the largest step $t=1$ along the
# most negative direction, so its size (about $-3\cdot10^4$ at the default) says only that the saddle is
# unbounded. It is judged with the coefficients **as printed** in Theorem 2 (the package's `coef="paper"`,
# which also reads (18)'s garbled first factor $(1-(\alpha_3-\alpha_2))(1-\check\psi_i)$ as Theorem 2's
# $1-(\alpha_3-\alpha_2)(1-\check\psi_i)$, as C1b does). Reported, not deciding: the corrected design, and (18)
# with its first factor read literally — then (28) is no longer the stationary point of (18) unless the
# two factors coincide, and the excess of $\mathrm{tr}$(18) at (28) over its minimum (where one exists) is
# given.

# %%
THM2_SEED = 20250  # seed of the random directions (ours)
THM2_RANDOM = 32  # random directions per step and target (ours)
THM2_STEPS = (1e-3, 1e-1, 1.0)  # step sizes relative to max(||L*||_F, 1) (ours)
THM2_LEVEL = -1e-10  # C8's level: lambda_min(Pi) / max|lambda(Pi)| below it, Pi is indefinite (ours: rounding)
THM2_DESCENT = -1e-10  # largest admitted relative decrease of tr S(k|k) under a perturbation (ours: rounding)


show_source(M.theorem2_check, after="    c0_kx = [bound_coefficients(")
G_STEPS = [CH[SETS[k - 1]] for k in range(1, T + 1)]


def theorem2_check(ex, weights, variant, literal=False):
    """The library's Theorem-2 check along the exact design `ex` (its S(k|k-1), E{xhat xhat^T})."""
    return M.theorem2_check(ex["Sp"], ex["Xh"], G_STEPS, PSI, weights, xi_star, V, variant,
                            literal=literal, seed=THM2_SEED, n_random=THM2_RANDOM, steps=THM2_STEPS)


# Algorithm 1 run at the declared weights: (17) with their lambda, (18), (28) along its own trajectory
EX_THM2 = exact_moments(W_THM2, variant="paper")
THM2_OWN_MIN_EIG = float(min(np.linalg.eigvalsh(EX_THM2["S"][1:]).min(),
                             np.linalg.eigvalsh(EX_THM2["Sp"][1:]).min()))
print(f"declared weights, own trajectory: min over k, targets of lambda_min of S(k|k-1), S(k|k) = "
      f"{THM2_OWN_MIN_EIG:.4g} (Theorem 1's positive-definite solutions)")
THM2 = {"printed, Remark-4 weights": theorem2_check(EX_PRINTED, W_PRINTED, "paper", literal=True),
        "printed, alpha2 > alpha3 weights": theorem2_check(EX_PRINTED_THM3, WEIGHTS["paper_thm3"],
                                                           "paper", literal=True),
        "printed, declared weights (thm2_weights)": theorem2_check(EX_THM2, W_THM2, "paper"),
        "printed, declared weights on the Remark-4 trajectory": theorem2_check(EX_PRINTED, W_THM2,
                                                                               "paper"),
        "corrected, weights in use": theorem2_check(EX_CORR, W_CORR, "corrected")}
for name, r in THM2.items():
    print(f"{name:>34}:", "gain not finite" if r is None else
          {key: (round(v, 12) if isinstance(v, float) else v) for key, v in r.items()})


def pi_scan(ex, weights, variant, step=1e-3):
    """Along ex: min relative eigenvalue of Pi of (28), indefinite-Pi steps, and of these the steps where
    L* + s e_r v^T (v: Pi's most negative eigenvector, s = step max(||L*||_F, 1), some state r) lowers
    tr (18) and keeps S(k|k) positive definite (Theorem 1's premise)."""
    worst, indefinite, descent_pd, last = np.inf, 0, 0, T
    for k, G in enumerate(G_STEPS, start=1):
        if not (np.all(np.isfinite(ex["Sp"][k])) and np.all(np.isfinite(ex["Xh"][k]))):
            last = k - 1  # a mixed design whose bound overflowed: the steps before
            break
        for i in range(N):
            co = coefficients(PSI[i], *weights[i][2:], variant)
            L, S_i, R = gain_and_bound(ex["Sp"][k, i][None], ex["Xh"][k, i][None], G, co, weights[i][1],
                                       xi_star, V)
            ev, vec = np.linalg.eigh(sym(co[0] * G @ ex["Sp"][k, i] @ G.T + R[0]))
            worst = min(worst, ev[0] / np.abs(ev).max())
            if ev[0] / np.abs(ev).max() >= THM2_LEVEL:
                continue
            indefinite += 1
            s = step * max(np.linalg.norm(L[0]), 1.0)
            for r in range(NX if np.all(np.isfinite(L[0])) else 0):
                Lp = L[0] + s * np.outer(np.eye(NX)[r], vec[:, 0])
                Mp = np.eye(NX) - Lp @ G
                Sn = sym(co[0] * Mp @ ex["Sp"][k, i] @ Mp.T + Lp @ R[0] @ Lp.T)
                if np.trace(Sn) < np.trace(S_i[0]) and np.linalg.eigvalsh(Sn)[0] > 0:
                    descent_pd += 1
                    break
    return {"min_eig_pi_relative": float(worst), "indefinite_steps": indefinite,
            "descent_keeping_S_pd": descent_pd, "last_finite_k": last}


THM2_PD = pi_scan(EX_THM2, W_THM2, "paper")
C8_SPLIT = {f"{a} c0, {b} kappa_x": pi_scan(mixed_design(W_THM2, (a, b))[0], W_THM2, (a, b))
            for a, b in SPLITS}
print("declared weights, printed:", THM2_PD, "\none printed coefficient:", C8_SPLIT)

# %% [markdown]
# ## Fig. 6 against Fig. 5 — ZOH is not better (C2)
#
# $r_i$ = time-averaged MSE under ZOH / time-averaged MSE under zero-input, same runs, with a paired
# bootstrap 95 % interval over the runs. A target can only say something about the two updates if its
# zero-input gain is not negligible: we call target $i$ **informative** if the mean over runs and $k$ of
# $\|L_i(k)\Gamma_i(k)\|_2$ (the share of the innovation that reaches the state estimate) is at least
# `gain_negligible`; otherwise both estimators are the open-loop prediction and $r_i\approx1$ says
# nothing about the two updates (such a target is *undetermined*, not "holds"). Targets 2 and 3 also
# predict with target 1's estimate (7), so their ratios move with target 1's estimator even when their
# own gain is ≈ 0. Rule: C2 fails if for some informative target the whole interval lies below 1 (ZOH
# significantly better); it holds otherwise, provided at least one target is informative (the
# premise). The rule decides on an interval, so its meaning does not change with $F$ (recorded as
# `runs`). Over the declared space it holds at all but two of the sweep's points, but those 65 points are
# **not 65 samples**: they are five independent random draws — the four Sobol $(T,$ `mc_seed`$)$ pairs, each
# run under all 16 combinations of the four readings, and the default point — and the 16 cells of
# one draw share its noise and attack realisation. Both failures are cells of the one draw with
# $T=147$ (grid weights, ensemble surrogate, sin/cos attack: target 1's ratio 0.98 [0.97, 0.996], ZOH
# better). Counted by independent draws, C2 holds at every cell of 4 of the 5 draws; with one draw at
# each horizon we cannot tell whether the failure belongs to $T=147$ or to that seed. The sweep's region
# rule "mc_seed ≥ 6820" treats correlated cells as independent samples (an artefact of the design); the
# interval in claims.json is over the draws (robustness section). The margin shrinks with the horizon (decisive ratios 1.08–1.26 at
# $T=40$, 0.98–1.04 at $T=147$; the sweep's figure below and `robustness_C2.png`).

# %%
GAIN_SHARE = np.linalg.norm(out["L"][:, 1:] @ CH, ord=2, axis=(-2, -1)).mean(axis=(0, 1))
INFORMATIVE = GAIN_SHARE >= gain_negligible
per_run_zoh, per_run_zero = sq_err(out_zoh)[:, 1:].mean(axis=1), sq_err(out)[:, 1:].mean(axis=1)
C2_RATIO = per_run_zoh.mean(axis=0) / per_run_zero.mean(axis=0)
C2_CI = np.array([montecarlo.bootstrap_interval(np.stack([per_run_zoh[:, i], per_run_zero[:, i]], 1),
                                                seed=mc_seed + i) for i in range(N)])
C2_STATUS = ["undetermined (negligible gain)" if not INFORMATIVE[i]
             else "fails (ZOH better)" if C2_CI[i, 1] < 1 else "holds" for i in range(N)]
for i in range(N):
    print(f"target {i + 1}: mean ||L Gamma|| = {GAIN_SHARE[i]:.3g}, r = {C2_RATIO[i]:.4f} "
          f"[{C2_CI[i, 0]:.4f}, {C2_CI[i, 1]:.4f}] -> {C2_STATUS[i]}")

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
# scalar itself. The formulas live once, in `secest.methods.li2025.theorem3_eta` (shown below).
#
# The paper leaves $\lambda,\alpha_1,\dots,\alpha_7$ free ("and the given positive scalars"; Fig. 8's text:
# "select eligible parameters as claimed in Theorem 3"), so "the conditions fail" needs more than the
# weights we happen to use. **The premise decides first, for all weights.** Assumption 1 asks for
# *positive* $e_*$ and $b_*$ with $e_*^2I\le E_i(k)E_i^T(k)$ and $b_*^2I\le\sum_jB_{i,j}\sum_jB_{i,j}^T$, i.e. both
# matrices of full rank 4. On the example $E_i(k)$ is $4	imes1$ ($E_iE_i^T$ has rank 1) and
# $\sum_jB_{i,j}=\mathrm{diag}\{0,b^X,0,b^Y\}$ (rank 2; the zero matrix for target 1, whose $K_1$ is empty), at
# every $k$ and at every point of the declared space (no parameter changes $E_i$ or $B_{i,j}$). So
# Theorem 3's premise fails on the example whatever the weights: **C3a is fails-premise**, and no
# search is needed for that (the ranks are measured and recorded). The conditions (a)–(c) at the
# weights in use are still measured and recorded in C3a; what follows evaluates them with the
# constants at their literal values $e_*=b_*=0$ — outside the theorem — and is our supporting
# evidence, **X7** (two arguments):
#
# * **A weight-free floor (ours, a proof).** On the example $e_*=0$, $c_*=c^*=h^*=1$, $r_*=r^*$,
#   $\xi^*\le1$ and $h_*=\epsilon$. For every $\lambda>0$ and $\alpha_1..\alpha_4>0$ with $\kappa_x\ge0$ and
#   $c_0\ge1$, and every $\phi_*\le\phi^*$: $\eta^*/\phi^*\ge\big(1-\frac1{4(1-\epsilon^2)}\big)c_0(1+\lambda)(h^*a^*)^2$
#   (`theorem3_c_floor`, proof in its docstring). On the example $(a^*)^2=2.17$, so the floor is
#   $1.63>1$: condition (c) fails for **every** such weight set, and (a) needs $c_0>1$. This covers all
#   weights with the corrected coefficients ($\kappa_x\ge0$ always) and, with the printed ones, every
#   weight set with $\check\psi+\alpha_3^{-1}+\alpha_4\ge1$.
# * **A declared search (ours)** for the rest (printed $\kappa_x<0$): 4096 scrambled Sobol weight sets,
#   log-uniform in $\lambda\in[10^{-6},10^3]$, $\alpha_1..\alpha_4\in[10^{-6},10^6]$, each against every pair of a
#   49-point log grid $\phi_*\le1\le\phi^*$ over `phi_scan`'s range. A candidate meets Theorem 3 if (a), (b)
#   and (c) hold at one pair **and** $\pi_*>0$, $\pi^*>0$: the proof inverts (35),
#   $\pi_*I\le\Pi\le\pi^*I$ ("$(1/\pi^*)I\le\Pi^{-1}\le(1/\pi_*)I$"), which is meaningless otherwise. The
#   count without that requirement is reported too.
#
# Also evaluated: the weights in use (printed and corrected coefficients) and the $\alpha_2>\alpha_3$
# weights (`paper_thm3`), at the data-driven $(\phi_*,\phi^*)$ of the envelope below and on the
# `phi_scan` grid. Independently of all weights, (36) claims $\Gamma_*I\le L_i\Phi_{o(k)}C_iH_\epsilon$ with
# $\Gamma_*>0$; that matrix has rank at most $m=2<4$ for **any** gain ($\Phi_{o(k)}$ has rank $m$), so this
# step of the proof cannot hold (the rank is recorded); it breaks the proof, not the conditions. The
# search is finite: for printed $\kappa_x<0$ its negative answer rests on 4096 points and on our
# $\pi_*,\pi^*>0$ requirement, which is why it is ours (X7) and does not decide.


# %%
show_source(M.theorem3_eta, after="    c0, kx, *_ = bound_coefficients(")
show_source(M.theorem3_c_floor, after="    rho = (const[")
THM3_SEARCH_POINTS = 2**12  # scrambled Sobol points of the weight search (ours)
THM3_SEARCH_LOG10 = np.array([[-6.0, 3.0]] + [[-6.0, 6.0]] * 4)  # log10 box of lambda, alpha1..4 (ours)
THM3_SEARCH_GRID = 49  # (phi_*, phi^*) log grid of the search, same range as phi_scan (ours)
# the candidate weight sets, generated once (secest) and searched on the example (X7) and our instance (C3)
THM3_CAND = M.theorem3_candidates(THM3_SEARCH_POINTS, THM3_SEARCH_LOG10)


def thm3_constants(o, i: int) -> dict[str, float]:
    """Literal Assumption-1 constants of target i on the example; (X*)^2 from the runs o."""
    aat = np.linalg.eigvalsh(A_ALL[:T] @ np.swapaxes(A_ALL[:T], -1, -2))
    c2 = np.linalg.eigvalsh(C_MAT @ C_MAT.T)  # [1, 1, 1, 1]
    ee = np.linalg.eigvalsh(E_ALL[:T, :, None] * E_ALL[:T, None, :])
    bsum = sum((B_MAT[(i, j)] for j in K_SETS[i]), np.zeros((NX, NX)))
    bb = np.linalg.eigvalsh(bsum @ bsum.T)
    exx = np.einsum("fkr,fkc->krc", o["x"][:, 1:, i], o["x"][:, 1:, i]) / o["x"].shape[0]
    return {"a_lo2": aat.min(), "a_hi2": aat.max(), "h_lo": epsilon, "h_hi": 1.0,
            "c_lo2": c2.min(), "c_hi2": c2.max(), "e_lo2": max(ee.min(), 0.0), "e_hi2": ee.max(),
            "b_lo2": max(bb.min(), 0.0), "b_hi2": bb.max(), "q_lo": W, "q_hi": W, "r_lo": V,
            "r_hi": V, "wp": np.linalg.eigvalsh(H_EPS @ C_MAT.T @ C_MAT @ H_EPS).min(),
            "x2": np.linalg.eigvalsh(exx).max(), "xi_star": xi_star}


def phi_pairs(size: int) -> tuple[np.ndarray, np.ndarray]:
    """All pairs phi_* <= 1 <= phi^* of a log grid over phi_scan's range, flattened."""
    axis = np.logspace(phi_scan[0], phi_scan[1], size)
    lo_g, hi_g = np.meshgrid(axis[axis <= 1], axis[axis >= 1], indexing="ij")
    return lo_g.ravel(), hi_g.ravel()


def theorem3_conditions(o, weights, variant):
    """Theorem 3's conditions (a)-(c) at the given weights, per target: at the data-driven
    (phi_*, phi^*) and on the phi_scan grid; `variant` selects the coefficients c0, kappa_x."""
    lo_g, hi_g = phi_pairs(int(phi_scan[2]))
    rows = []
    for i in range(N):
        const = thm3_constants(o, i)
        ev = np.linalg.eigvalsh(o["S"][:, :, i])
        phi_lo, phi_hi = float(ev.min()), float(ev.max())
        at_data = M.theorem3_eta(phi_lo, phi_hi, PSI[i], weights[i], const, variant)
        grid = M.theorem3_eta(lo_g, hi_g, PSI[i], weights[i], const, variant)
        rows.append({
            "c0": float(at_data["c0"]), "a_alpha56_exist": bool(at_data["c0"] > 1),
            "X_star_sq": float(const["x2"]), "phi_lower": phi_lo, "phi_upper": phi_hi,
            "eta_lower": float(at_data["eta_lo"]), "eta_upper": float(at_data["eta_hi"]),
            "b_at_data": bool(at_data["eta_lo"] >= phi_lo),
            "c_at_data": bool(at_data["eta_hi"] <= phi_hi),
            "b_any_on_grid": bool(np.any(grid["eta_lo"] >= lo_g)),
            "c_any_on_grid": bool(np.any(grid["eta_hi"] <= hi_g)),
            "bc_pair_on_grid": bool(np.any((grid["eta_lo"] >= lo_g) & (grid["eta_hi"] <= hi_g))),
            "min_eta_upper_over_phi_upper": float(np.min(grid["eta_hi"] / hi_g)),
        })
    return rows


def finite_or_none(value) -> float | None:
    """float(value), or None where it is not finite (JSON has no infinity)."""
    return float(value) if np.isfinite(value) else None


def theorem3_search(o) -> list[dict]:
    """Declared search over the free weights (printed coefficients), per target.

    THM3_SEARCH_POINTS scrambled Sobol points, log-uniform in THM3_SEARCH_LOG10, each against
    every (phi_*, phi^*) pair of a THM3_SEARCH_GRID log grid. A candidate meets Theorem 3 if
    (a) c0 > 1, (b) eta_* >= phi_*, (c) eta^* <= phi^* at some pair with pi_* > 0 and
    pi^* > 0 (the proof inverts (35)). Also the weight-free floor of eta^*/phi^* for
    kappa_x >= 0 (theorem3_c_floor).
    """
    cand = THM3_CAND
    lo_g, hi_g = phi_pairs(THM3_SEARCH_GRID)
    rows = []
    for i in range(N):
        const = thm3_constants(o, i)
        r = M.theorem3_eta(lo_g[None], hi_g[None], PSI[i], [cand[:, q, None] for q in range(5)],
                           const, "paper")
        a_ok = np.broadcast_to(r["c0"] > 1, r["eta_hi"].shape)
        invertible = (r["pi_lo"] > 0) & (r["pi_hi"] > 0)
        bc = (r["eta_lo"] >= lo_g) & (r["eta_hi"] <= hi_g)
        kx_neg = np.broadcast_to(r["kappa_x"] < 0, a_ok.shape)
        ratio = np.where(a_ok & invertible, r["eta_hi"] / hi_g, np.inf)
        rows.append({
            "candidates": len(cand), "a_holds": int(a_ok[:, 0].sum()),
            "a_and_kappa_x_negative": int((a_ok & kx_neg)[:, 0].sum()),
            "all_conditions": int(np.any(a_ok & invertible & bc, axis=1).sum()),
            "all_conditions_pi_ignored": int(np.any(a_ok & bc, axis=1).sum()),
            # None: no candidate meets (a) with pi_*, pi^* > 0 (e.g. psi_check = 1, where c0 = 1)
            "min_eta_upper_over_phi_upper": finite_or_none(ratio.min()),
            "min_ratio_kappa_x_nonnegative": finite_or_none(np.where(kx_neg, np.inf, ratio).min()),
            "floor_kappa_x_nonnegative": M.theorem3_c_floor(const) if xi_star <= 1 else None})
    return rows


THM3_COND = {
    "printed, weights in use": theorem3_conditions(out_corr, W_CORR, "paper"),
    "corrected, weights in use": theorem3_conditions(out_corr, W_CORR, "corrected"),
    "printed, alpha2 > alpha3 weights": theorem3_conditions(out_printed_thm3,
                                                            WEIGHTS["paper_thm3"], "paper"),
}
THM3_SEARCH = theorem3_search(out_corr)
THM3_RANK = int(np.linalg.matrix_rank(out_corr["L"][:, 1:] @ CH).max())
for name, rows_ in THM3_COND.items():
    for i, r in enumerate(rows_):
        print(f"{name:>32} target {i + 1}: c0 = {r['c0']:.5g} (a) {r['a_alpha56_exist']}; "
              f"at data phi = ({r['phi_lower']:.3g}, {r['phi_upper']:.4g}): eta_* = "
              f"{r['eta_lower']:.3g} (b) {r['b_at_data']}, eta^* = {r['eta_upper']:.3g} "
              f"(c) {r['c_at_data']}; grid: (b) {r['b_any_on_grid']}, (c) {r['c_any_on_grid']}, "
              f"both {r['bc_pair_on_grid']}, min eta^*/phi^* = "
              f"{r['min_eta_upper_over_phi_upper']:.3g}")
for i, r in enumerate(THM3_SEARCH):
    print(f"search target {i + 1}: {r['candidates']} weight sets, (a) at {r['a_holds']} "
          f"({r['a_and_kappa_x_negative']} with kappa_x < 0); (a)-(c) with pi_*, pi^* > 0 at "
          f"{r['all_conditions']} ({r['all_conditions_pi_ignored']} if pi_* <= 0 were allowed); "
          f"min eta^*/phi^* = {r['min_eta_upper_over_phi_upper']} "
          f"(kappa_x >= 0: {r['min_ratio_kappa_x_nonnegative']}, floor "
          f"{r['floor_kappa_x_nonnegative']})")
print(f"max rank of L_i(k) Phi C_i H_eps over runs, k, i: {THM3_RANK} (n_x = {NX}; at most m = {m} "
      "for any gain, since Phi_o(k) has rank m)")


# %% [markdown]
# Condition (c) fails at the default point for the weights in use ($\eta^*$ grows like $(\phi^*)^3$ for large
# $\phi^*$ through $\varpi^*\Gamma^{*2}$ and carries $(X^*)^2\Gamma^{*2}$), and it fails for every weight set: the floor
# covers all weights with $\kappa_x\ge0$, and the search finds no weight set with $\kappa_x<0$ that meets
# (a)–(c) with $\pi_*,\pi^*>0$ (the candidates that meet (a)–(c) all have $\pi_*\le0$ or $\pi^*\le0$, i.e. a
# "bound" of $\Pi$ that is not positive; counts printed above). **Theorem 3's premise is not met on the
# paper's own example at any weights we can find, and provably at none with $\kappa_x\ge0$**, so the
# theorem supplies no envelope there (C3a), and Fig. 8's comparison is recorded with its failed premise
# (C3b). The $UB_i(k)$ below is the data-driven one; where the recipe has no admissible
# $\alpha_5,\alpha_6>0$ ($c_0\le1$, e.g. at $\check\psi=1$) it is undefined and not drawn.


# %%
def theorem3_envelope(o, weights, variant):
    """Data-driven UB_i(k) of the consistent Lemma 3 (NaN where the recipe is undefined)."""
    ev = np.linalg.eigvalsh(o["S"])  # (F, T+1, N, 4)
    ev_pred = np.linalg.eigvalsh(o["S_pred"][:, 1:])
    env, info = np.full((T + 1, N), np.nan), {}
    for i in range(N):
        lam_, a1_, a2_, a3_, a4_ = weights[i]
        c0_ = bound_coefficients(PSI[i], a2_, a3_, a4_, variant)[0]
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
        defined = a5 > 0 and phi_lo > 0 and mu1 > 0
        if defined:
            a7 = np.sqrt(mu2 / mu1)
            mu = (1 + 1 / a5 + a7) * mu1 + ((1 + 1 / a6 + 1 / a7) * mu2 if mu2 > 0 else 0.0)
            e0 = np.mean(np.sum((o["x"][:, 0, i] - o["xhat"][:, 0, i]) ** 2, axis=-1))
            geo = np.concatenate([[0.0], np.cumsum((1 - rho) ** np.arange(T))])
            env[:, i] = phi_hi / phi_lo * e0 * (1 - rho) ** kk + mu * phi_hi * geo
        info[i] = {"phi_lower": phi_lo, "phi_upper": phi_hi, "rho": rho, "defined": defined}
        print(f"target {i + 1}: phi_* = {phi_lo:.3g}, phi^* = {phi_hi:.4g}, rho = {rho:.3g}, "
              f"mu1 = {mu1:.3g}, mu2 = {mu2:.3g}, UB(T) = {env[-1, i]:.3g}")
    return env, info


UB, UB_INFO = theorem3_envelope(out_corr, W_CORR, "corrected")
ERR2 = sq_err(out_corr)  # (F, T+1, N)

fig, axes = plt.subplots(1, N, figsize=(plotting.PAGE_WIDTH, 3.1), sharex=True,
                         layout="constrained")
for i, ax in enumerate(axes):
    ax.semilogy(kk[1:], UB[1:, i], color="tab:blue", label="$UB_i(k)$ (data-driven)")
    ax.semilogy(kk[1:], ERR2[plot_run, 1:, i], color="tab:red", lw=0.9,
                label=f"$\\|e_i(k|k)\\|^2$ (run {plot_run})")
    ax.set_ylim(bottom=log_floor(ERR2[plot_run, :, i]))
    ax.set_title(f"target {i + 1}" + ("" if UB_INFO[i]["defined"] else " (UB undefined)"))
    ax.set_xlabel("time step k [–]")
axes[0].set_ylabel("squared error [m², m²/s²]")
fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=2, fontsize=7,
           frameon=False)
fig.suptitle("Fig. 8: $\\|e_i(k|k)\\|^2$ and the data-driven envelope $UB_i(k)$ "
             "(Theorem 3's conditions fail)")
plotting.save_figure(fig, FIG_DIR, "fig8_error_and_envelope",
                     data={"k": kk[1:], "UB": UB[1:], "err2_run": ERR2[plot_run, 1:]})
UB_RATIO = UB[-1] / mse(out_corr)[1:].max(axis=0)
print("UB_i(T) / max_k MSE_i(k):", np.array2string(UB_RATIO, precision=3))

# %% [markdown]
# Where it is defined, every $\|e_i(k|k)\|^2$ stays below $UB_i(k)$ — but at the default point
# $UB_i(T)$ is $10^{13}$–$10^{17}$, more than $10^{11}$ times the largest MSE (ratio printed above): with
# constants taken from the data the inequality is vacuous, and since the conditions of Theorem 3 fail
# (C3a) it is not evidence for the theorem; C3b records the measurement with its failed premise.
#
# ## Theorem 3 on a declared instance of ours (C3)
#
# Theorem 3 is a general result, and the example cannot exercise it (C3a: its premise fails there for
# every weight set). By the package's one rule (`results.rescience_verdict`) such a result is decided on
# a declared instance of ours that satisfies its premises, and its evaluation at the example (C3a) is shown
# and does not decide. **Our instance** (ours; chosen so that Assumption 1 can hold — full-rank $E_i$,
# $B_{2,1}$, $C_i$ — and with $a^*<1$, which X7's floor shows condition (c) needs; not tuned on the outcome,
# and not swept, since no parameter of the declared space enters it): $N=2$ subsystems, $K_1=\emptyset$, $K_2=\{1\}$, $n_x=2$ ($n_s=n_f=1$,
# $H_\epsilon=\mathrm{diag}(1,\epsilon)$, the paper's $\epsilon=0.05$), $A_i=0.6\,R(0.3)$ ($R$ a rotation, so
# $A_iA_i^T=0.36I$), $B_{2,1}=0.2I$, $C_i=I_2$ ($n_y=2$ sensors, $m=1$ channel, RRL-MAP period $U=2$),
# $E_i=I_2$ with $\omega_i\in\mathbb R^2$, $\mathcal W_i=0.03I$ (the paper's scalar as $qI$), $\mathcal V_i=0.03I$,
# $\xi^*=0.3$ with $\xi(k)=\sqrt{\xi^*}[\sin k,\cos k]^T$, $\check\psi=(0.7,0.5)$, $x(0)\sim\mathcal N(\mathbf 1,I)$,
# $\hat x(0|0)=\mathbf 1$, $\mathfrak S_i(0|0)=I=P_i(0|0)$ ((19)), horizon 100. The plant is stable
# ($\|A_iH_\epsilon\|\le0.6$), which $\mathbb E\{x_ix_i^T\}\le(X^*)^2I$ needs.
#
# * **Assumption 1.** $a_*^2=(a^*)^2=0.36$, $c_*=c^*=1$, $e_*=e^*=1$, $h_*=\epsilon$, $h^*=1$, $q=r=0.03$: all
#   positive. For subsystem 2, $b_*^2=(b^*)^2=0.04>0$. For subsystem 1 the sum over $K_1=\emptyset$ is the zero
#   matrix, and **no sequential system can do otherwise** (the first subsystem has no upstream one): read
#   literally, Assumption 1 holds for no subsystem 1 of any DSS. We read it, for $K_i=\emptyset$, with
#   $b_*=b^*=0$ (the empty sum: the $b$ terms are absent from (17) and (20), and a zero lower constant only
#   weakens $\varpi_*$, $\chi_1$); subsystem 2 meets Assumption 1 literally, and C3 records its outcome
#   alone too. $(X^*)^2=\max_k\lambda_{\max}\mathbb E\{x_ix_i^T\}$ of the plant (exact; the smallest admissible).
# * **The free weights (declared search).** Theorem 3 holds for "the given positive scalars $\epsilon,\alpha_l$
#   ($l = 1-7$) and $\lambda$" that meet its conditions; Fig. 8's text "select[s] eligible parameters". We
#   search them with X7's declared search: the same 4096 scrambled Sobol weight sets
#   $(\lambda,\alpha_1..\alpha_4)$ and the same 49-point log grid of pairs $\phi_*\le1\le\phi^*$ (so that
#   $\phi_*I\le\mathfrak S(0|0)\le\phi^*I$). A weight set is *eligible* if, for both subsystems, at some pair
#   (a) printed $c_0>1$, (b) $\eta_*\ge\phi_*$, (c) $\eta^*\le\phi^*$ hold with $\pi_*,\pi^*>0$ (`theorem3_eta`, as
#   printed, the coefficients of Theorem 3). $\alpha_5..\alpha_7$ enter only the proof's constants; we take
#   the ones that minimise $\mu$ under (a), the tightest envelope the theorem offers.
# * **The conclusion, measured.** The theorem's statement is qualitative ("exponentially bounded in the mean
#   square"); its content is the envelope of its proof, (56). The envelope used here is **our consistent
#   re-derivation** from the proof's constants, not the printed (56) (which is reported); the proof's (36)
#   cannot hold on the instance for any gain (rank of $L\Phi CH_\epsilon\le m=1<n_x=2$). For every eligible weight set Algorithm 1 is
#   run with the printed coefficients and the exact $\mathbb E\{\hat x\hat x^T\}$ (deterministic gains,
#   `exact_design_moments`, exact $\mathbb E\|e_i(k|k)\|^2$), and for every eligible pair the envelope is
#   computed with the proof's own constants (`theorem3_proof_envelope`: $\rho$ (55), $\mu_1$ (49), $\Lambda$
#   (53), $\mu_2$ (51), Lemma 3 with its roles consistent as in the Fig. 8 section; (50) corrected, since
#   printed it is negative here). **Rule (ours):** C3 holds if
#   $\max\mathbb E\|e_i(k|k)\|^2/UB_i(k)\le1$ over all eligible (weight set, pair), both subsystems and
#   $k=1..100$; it fails if one ratio exceeds 1. Its premise: at least one weight set is eligible, **and**
#   the precondition of the measurement (ours; part of the premise, CONVENTIONS point 6): it discriminates —
#   $L=0$, the open-loop prediction (same system, noise, attacks: `exact_design_moments(zero_gain=True)`),
#   violates the envelope at some eligible case, searched or the re-review's set below. An envelope that $L=0$
#   meets as well says nothing about the estimator; where the precondition fails C3 is **fails-premise** and
#   the ratio is X9 (ours, not deciding). **Restated in session 14** from "an informative gain", which the
#   re-review's eligible set $(1.115,1.305,14.916,14.914,0.0072)$ meets (C3 would hold there: [Re, partial]).
#   Reported: the same for subsystem 2 alone; Stage 1, $\phi_*I\le\mathfrak S_i(k|k)\le\phi^*I$;
#   $\Lambda$ of (53) against the measured $\max_k\|L_i(k)\|_2^2$ ((52) claims $L^TL\le\Lambda I$); (56) as
#   printed; the largest gain.

# %%
show_source(M.exact_design_moments, after="    nz = 2 * N * n")
show_source(M.theorem3_proof_envelope, after="    c0, kx, *_ = bound_coefficients(")
INST_EPS, INST_T, INST_PSI, INST_XI = 0.05, 100, np.array([0.7, 0.5]), 0.3  # our instance (ours)
INST_N, INST_NX, INST_NY, INST_M, INST_Q, INST_R = 2, 2, 2, 1, 0.03, 0.03
INST_H = np.diag([1.0, INST_EPS])
INST_A = 0.6 * np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
INST_B = {(1, 0): 0.2 * np.eye(INST_NX)}
INST_PARENTS = {0: (), 1: (0,)}
INST_C, INST_E = np.eye(INST_NY, INST_NX), np.eye(INST_NX)
INST_SCHED = schedules.rrl_map_sets(np.arange(1, INST_T + 1), INST_M, INST_NY)  # (2), 0-based
INST_K = np.arange(INST_T + 1)[:, None]
INST_XI_K = np.sqrt(INST_XI) * np.hstack([np.sin(INST_K), np.cos(INST_K)])  # ||xi(k)||^2 = xi*
INST_MEAN0, INST_COV0 = np.ones(INST_N * INST_NX), np.eye(INST_N * INST_NX)
INST_BH = {key: b @ INST_H for key, b in INST_B.items()}


def instance_run(weights, zero_gain: bool = False) -> dict:
    """Algorithm 1 (printed coefficients, exact E{xhat xhat^T}) on our instance, exact moments;
    zero_gain: the same system, noise and attacks with L = 0 (the open-loop prediction)."""
    return M.exact_design_moments(INST_A @ INST_H, INST_BH, INST_PARENTS, INST_Q * INST_E @ INST_E.T,
                                  INST_C @ INST_H, INST_SCHED, INST_PSI, INST_XI_K, INST_XI, INST_R,
                                  weights, INST_MEAN0, INST_COV0, np.eye(INST_NX), "paper",
                                  zero_gain=zero_gain)


def instance_constants(i: int, x2: float) -> dict[str, float]:
    """Assumption-1 constants of subsystem i of our instance (b = 0 for the empty K_1)."""
    bsum = sum((INST_B[(i, j)] for j in INST_PARENTS[i]), np.zeros((INST_NX, INST_NX)))
    eig = {name: np.linalg.eigvalsh(mat @ mat.T) for name, mat in
           (("a", INST_A), ("c", INST_C), ("e", INST_E), ("b", bsum))}
    return {"a_lo2": eig["a"].min(), "a_hi2": eig["a"].max(), "h_lo": INST_EPS, "h_hi": 1.0,
            "c_lo2": eig["c"].min(), "c_hi2": eig["c"].max(), "e_lo2": eig["e"].min(),
            "e_hi2": eig["e"].max(), "b_lo2": max(eig["b"].min(), 0.0), "b_hi2": eig["b"].max(),
            "q_lo": INST_Q, "q_hi": INST_Q, "r_lo": INST_R, "r_hi": INST_R,
            "wp": np.linalg.eigvalsh(INST_H @ INST_C.T @ INST_C @ INST_H).min(), "x2": x2,
            "xi_star": INST_XI}


# (X*)^2: the plant's exact second moment, max over k of lambda_max E{x_i x_i^T} (no estimator in it)
_ex_x = INST_COV0 + np.outer(INST_MEAN0, INST_MEAN0)
_ax = np.block([[INST_A @ INST_H, np.zeros((INST_NX, INST_NX))], [INST_BH[(1, 0)], INST_A @ INST_H]])
INST_X2 = np.zeros(INST_N)
for _k in range(INST_T + 1):
    INST_X2 = np.maximum(INST_X2, [np.linalg.eigvalsh(_ex_x[2 * i:2 * i + 2, 2 * i:2 * i + 2]).max()
                                   for i in range(INST_N)])
    _ex_x = _ax @ _ex_x @ _ax.T + np.kron(np.eye(INST_N), INST_Q * INST_E @ INST_E.T)  # (1)
INST_CONST = [instance_constants(i, INST_X2[i]) for i in range(INST_N)]
INST_CAND = THM3_CAND  # X7's candidate weight sets (one generator: M.theorem3_candidates)
INST_LO, INST_HI = phi_pairs(THM3_SEARCH_GRID)
def instance_met(cand: np.ndarray) -> list[np.ndarray]:
    """(weight sets, pairs): conditions (a)-(c) with pi_*, pi^* > 0, per subsystem of our instance."""
    out = []
    for i in range(INST_N):
        r_ = M.theorem3_eta(INST_LO[None], INST_HI[None], INST_PSI[i],
                            [cand[:, q, None] for q in range(5)], INST_CONST[i], "paper")
        out.append((r_["c0"] > 1) & (r_["pi_lo"] > 0) & (r_["pi_hi"] > 0)
                   & (r_["eta_lo"] >= INST_LO) & (r_["eta_hi"] <= INST_HI))
    return out


INST_MET = instance_met(INST_CAND)
INST_ELIGIBLE = np.flatnonzero(np.all([np.any(met, axis=1) for met in INST_MET], axis=0))
print(f"our instance: (X*)^2 = {np.round(INST_X2, 4)}; eligible weight sets {INST_ELIGIBLE.size} of "
      f"{len(INST_CAND)} (subsystem 1 alone: {int(np.any(INST_MET[0], axis=1).sum())}, subsystem 2 "
      f"alone: {int(np.any(INST_MET[1], axis=1).sum())})")


def instance_outcome(weights, met: list[np.ndarray]) -> dict:
    """Run an eligible weight set on our instance; ratios E||e||^2 / UB over its eligible pairs met[i]."""
    w = [tuple(weights)] * INST_N
    run_, run0 = instance_run(w), instance_run(w, zero_gain=True)
    rows_ = []
    for i in range(INST_N):
        err2 = np.trace(run_["P"][:, i], axis1=-2, axis2=-1)  # E||e_i(k|k)||^2, exact
        err2_0 = np.trace(run0["P"][:, i], axis1=-2, axis2=-1)  # the same with L = 0
        ev_s = np.linalg.eigvalsh(run_["S"][1:, i])
        gain2 = float(np.max(np.linalg.norm(run_["L"][1:, i], ord=2, axis=(-2, -1)) ** 2))
        # ||L(k) Phi(k) C H_eps||_2, the share of the innovation that reaches the estimate (C2's measure)
        share = float(max(np.linalg.norm(run_["L"][k, i] @ (INST_C @ INST_H)[INST_SCHED[k - 1]], ord=2)
                          for k in range(1, INST_T + 1)))
        # largest relative reduction of E||e_i(k|k)||^2 by the gain (28) against L = 0
        reduction = float(np.max((err2_0[1:] - err2[1:]) / err2_0[1:]))
        for p in np.flatnonzero(met[i]):
            env = M.theorem3_proof_envelope(INST_LO[p], INST_HI[p], INST_PSI[i], w[i],
                                            INST_CONST[i], err2[0], INST_T, INST_NX, INST_NY)
            rows_.append({"subsystem": i + 1, "ratio": float(np.max(err2[1:] / env["UB"][1:])),
                          "ratio_zero_gain": float(np.max(err2_0[1:] / env["UB"][1:])),
                          "gain_share": share, "reduction": reduction,
                          "stage1": bool(ev_s.min() >= INST_LO[p] and ev_s.max() <= INST_HI[p]),
                          "Lambda_holds": bool(gain2 <= env["Lambda"]),
                          "literal_56_holds": bool(np.all(err2[1:] <= env["UB_literal"][1:])),
                          "gain2": gain2, "mu": env["mu"], "rho": env["rho"], "UB": env["UB"],
                          "err2": err2})
    return {"weights": w[0], "rows": rows_}


INST_OUT = [instance_outcome(INST_CAND[c], [m[c] for m in INST_MET]) for c in INST_ELIGIBLE]
INST_ROWS = [r for o in INST_OUT for r in o["rows"]]
INST_RATIO = max((r["ratio"] for r in INST_ROWS), default=None)
INST_RATIO_2 = max((r["ratio"] for r in INST_ROWS if r["subsystem"] == 2), default=None)
INST_GAIN2 = max((r["gain2"] for r in INST_ROWS), default=None)
# C3's precondition until session 14 (ours, kept as a record): the gain is informative. Largest
# ||L Phi C H_eps|| against C2's gain_negligible, and the largest relative reduction of E||e||^2 by (28) against L = 0 on the same cases against the same level.
INST_RATIO_0 = max((r["ratio_zero_gain"] for r in INST_ROWS), default=None)
INST_SHARE = max((r["gain_share"] for r in INST_ROWS), default=None)
INST_REDUCTION = max((r["reduction"] for r in INST_ROWS), default=None)
INST_INFORMATIVE = bool(INST_ROWS) and INST_SHARE >= gain_negligible and INST_REDUCTION >= gain_negligible
# The re-review's weight set (session 14), inside the declared box, eligible and with an informative
# gain: the precondition above holds there, so it is restated as what it guards (the measurement
# discriminates): L = 0 violates the envelope at some eligible case, searched or this one.
REVIEW_W = np.array([[1.115, 1.305, 14.916, 14.914, 0.0072]])
REVIEW_MET = [m[0] for m in instance_met(REVIEW_W)]
REVIEW_ROWS = instance_outcome(REVIEW_W[0], REVIEW_MET)["rows"] if all(m.any() for m in REVIEW_MET) else []
REVIEW = {"weights": REVIEW_W[0].tolist(),
          "in_declared_box": bool(np.all((np.log10(REVIEW_W[0]) >= THM3_SEARCH_LOG10[:, 0])
                                         & (np.log10(REVIEW_W[0]) <= THM3_SEARCH_LOG10[:, 1]))),
          "eligible_pairs": [int(m.sum()) for m in REVIEW_MET]} | {
    key: [max((r[field] for r in REVIEW_ROWS if r["subsystem"] == i + 1), default=None)
          for i in range(INST_N)]
    for key, field in (("gain_share", "gain_share"), ("error_reduction", "reduction"),
                       ("max_ratio", "ratio"), ("max_ratio_zero_gain", "ratio_zero_gain"))}
REVIEW["old_precondition_holds"] = bool(REVIEW_ROWS) and all(
    v is not None and v >= gain_negligible for v in REVIEW["gain_share"] + REVIEW["error_reduction"])
INST_RATIO_0_ALL = max((r["ratio_zero_gain"] for r in INST_ROWS + REVIEW_ROWS), default=None)
INST_DISCRIMINATES = INST_RATIO_0_ALL is not None and INST_RATIO_0_ALL > 1.0
print(f"re-review's set: pairs {REVIEW['eligible_pairs']}, share {np.round(REVIEW['gain_share'], 3)}, reduction "
      f"{np.round(REVIEW['error_reduction'], 3)}, ratio {[f'{v:.2g}' for v in REVIEW['max_ratio']]} (L = 0: "
      f"{[f'{v:.2g}' for v in REVIEW['max_ratio_zero_gain']]}); L = 0 above the envelope anywhere: {INST_DISCRIMINATES}")
print(f"C3 precondition: largest ||L Phi C H|| = {INST_SHARE} (level gain_negligible = {gain_negligible}), "
      f"largest relative reduction of E||e||^2 by (28) against L = 0 = {INST_REDUCTION}; with L = 0 the "
      f"largest ratio to the envelope is {INST_RATIO_0} (with (28): {INST_RATIO}); informative: "
      f"{INST_INFORMATIVE}")
print(f"C3 on our instance: {len(INST_ROWS)} (weight set, pair, subsystem) cases; max E||e||^2 / UB = "
      f"{INST_RATIO} (subsystem 2 alone: {INST_RATIO_2}); Stage 1 holds in "
      f"{sum(r['stage1'] for r in INST_ROWS)}, (52) L^T L <= Lambda I in "
      f"{sum(r['Lambda_holds'] for r in INST_ROWS)}, (56) as printed in "
      f"{sum(r['literal_56_holds'] for r in INST_ROWS)} of them; largest ||L||^2 = {INST_GAIN2}")

fig, axes = plt.subplots(1, INST_N, figsize=(plotting.PAGE_WIDTH, 3.0), sharex=True,
                         layout="constrained")
inst_data = {"k": INST_K[1:, 0]}
for i, ax in enumerate(axes):
    mine = [r for r in INST_ROWS if r["subsystem"] == i + 1]
    if not mine:
        ax.text(0.5, 0.5, "no eligible weight set", ha="center", va="center", transform=ax.transAxes)
        continue
    tight = max(mine, key=lambda r: r["ratio"])  # the case closest to violating the envelope
    err2_i = tight["err2"]
    ax.semilogy(INST_K[1:, 0], tight["UB"][1:], color="tab:blue", label="$UB_i(k)$, proof's constants")
    ax.semilogy(INST_K[1:, 0], err2_i[1:], color="tab:red", label="$\\mathbb{E}\\|e_i(k|k)\\|^2$ (exact)")
    ax.set_title(f"subsystem {i + 1}: largest ratio {tight['ratio']:.3g}")
    ax.set_xlabel("time step k [–]")
    inst_data[f"UB_subsystem{i + 1}"], inst_data[f"err2_subsystem{i + 1}"] = tight["UB"][1:], err2_i[1:]
axes[0].set_ylabel("[squared state units]")
fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=2, fontsize=7,
           frameon=False)
fig.suptitle("C3 on our instance: exact mean-square error against Theorem 3's envelope "
             "(eligible weights, tightest case)")
_ = plotting.save_figure(fig, FIG_DIR, "extra_theorem3_instance", data=inst_data)


# %% [markdown]
# ## Kalman limit (X8)
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
c0_p, kx_p, *_ = bound_coefficients(1.0, 1.0, 1.0, 1.0, "paper")
print(f"printed coefficients at psi = 1, alpha = 1: c0 = {c0_p}, kappa_x = {kx_p} (not Kalman)")

# %% [markdown]
# ## Tracking (Figs. 2–4, C7): the paper's design against its baselines
#
# "Each target's estimated positions and velocities well match its real positions and velocities."
# We record the relative RMS error
# $\rho_i(T)=\sqrt{\sum_{k=1}^T\mathbb E\|e_i(k|k)\|^2\,/\,\sum_{k=1}^T\mathbb E\|x_i(k)\|^2}$, computed **exactly** with the
# second-moment recursion (no seed). The paper gives no scale ("well match"; Remark 5's "minor estimation
# errors"), so **C7 is not-checked**: a threshold of ours would decide by our judgement. Rows, all on the
# same plant, schedule and attack:
#
# * **our corrected design** and the **printed-coefficient design** — (8) with the gain (28) of the bound
#   (exact $\mathbb E\{\hat x\hat x^T\}$, weights in use); the first also in Monte Carlo with the run's
#   surrogate (`xhat_moment`), with a 95 % interval;
# * **per-step optimal gain for (8)** — the best gain (8) admits at each step given the exact moments;
# * **debiased innovation, optimal gain** — $y_i-\check\psi_i\Phi C_iH_\epsilon\hat x_i(k|k-1)$ as innovation (ours);
# * **oracle Kalman filter** — centralised, knows $\psi_i(k)$ and drops attacked packets (exact covariance
#   given each run's $\psi$ sequence, averaged over the $F$ draws, 95 % interval);
# * **no attack** — the design in use with $\check\psi_i=1$;
# * **additive reading of (6)** — the design re-derived for $y_i=\bar y_i+(1-\psi_i)\Phi\xi_i$ (a
#   sensitivity row: the paper's (6) replaces);
# * **open-loop prediction** — $L=0$.
#
# Every design is causal: $\rho_i(T')$ for $T'<T$ is the same computation stopped at $T'$ (the figure).

# %%
C7_ROWS = {
    "our corrected design": EX_CORR,
    "printed-coefficient design": EX_PRINTED,
    "per-step optimal gain for (8)": exact_moments(W_MAIN, gain="optimal"),
    "debiased innovation, optimal gain": exact_moments(W_MAIN, gain="optimal", debias=True),
    "no attack (psi_check = 1)": exact_moments(W_MAIN, variant=coef, psi_bar=np.ones(N)),
    "additive reading of (6)": exact_moments(W_MAIN, variant="additive", reading="additive"),
    "open-loop prediction": exact_moments(W_MAIN, gain="zero"),
}
CUM_X = np.cumsum(EX2[1:], axis=0)  # sum_{k <= T'} E||x_i||^2


def rel_rms_curve(msek: np.ndarray) -> np.ndarray:
    """rho_i(T') for T' = 1..T from E||e_i(k)||^2, shape (T, N)."""
    return np.sqrt(np.cumsum(msek[1:], axis=0) / CUM_X)


C7_CURVES = {name: rel_rms_curve(exact_mse(ex)) for name, ex in C7_ROWS.items()}
oracle_tr = oracle_kalman(DRAWS["psi"])  # (F, T+1, N)
C7_CURVES["oracle Kalman filter"] = rel_rms_curve(oracle_tr.mean(axis=0))


def rel_rms_interval(per_run_sum: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """95 % interval of rho_i(T) from per-run sums of squared errors (t-interval, then sqrt)."""
    lo, hi = t_intervals(per_run_sum, 0.95)
    return np.sqrt(np.maximum(lo, 0) / CUM_X[-1]), np.sqrt(hi / CUM_X[-1])


C7_INTERVALS = {"our corrected design, Monte Carlo": rel_rms_interval(sq_err(out_corr)[:, 1:].sum(axis=1)),
                "oracle Kalman filter": rel_rms_interval(oracle_tr[:, 1:].sum(axis=1))}
C7_MC = np.sqrt(mse(out_corr)[1:].sum(axis=0) / CUM_X[-1])
C7_TABLE = {name: curve[-1] for name, curve in C7_CURVES.items()}
rows_md = ["| row | target 1 | target 2 | target 3 |", "|---|---|---|---|"]
for name, val in C7_TABLE.items():
    ci = C7_INTERVALS.get(name)
    cells = [f"{v:.3f}" + (f" [{ci[0][i]:.3f}, {ci[1][i]:.3f}]" if ci else "")
             for i, v in enumerate(val)]
    rows_md.append(f"| {name} | " + " | ".join(cells) + " |")
ci = C7_INTERVALS["our corrected design, Monte Carlo"]
rows_md.append(f"| our corrected design, Monte Carlo ({xhat_moment} surrogate, {F} runs) | "
               + " | ".join(f"{v:.3f} [{ci[0][i]:.3f}, {ci[1][i]:.3f}]" for i, v in enumerate(C7_MC))
               + " |")
display(Markdown(f"Relative RMS error $\\rho_i(T)$, $T={T}$ (exact unless an interval is given):\n\n"
                 + "\n".join(rows_md)))

fig, axes = plt.subplots(1, N, figsize=(plotting.PAGE_WIDTH, 3.3), sharex=True, sharey=True,
                         layout="constrained")
styles = {"our corrected design": ("tab:red", "-", 1.8),
          "printed-coefficient design": ("tab:brown", "--", 1.4),
          "per-step optimal gain for (8)": ("tab:orange", "-", 1.2),
          "debiased innovation, optimal gain": ("tab:green", "-", 1.2),
          "oracle Kalman filter": ("tab:blue", "-", 1.2),
          "no attack (psi_check = 1)": ("k", "--", 1.0),
          "additive reading of (6)": ("tab:purple", "-.", 1.0),
          "open-loop prediction": ("0.5", ":", 1.2)}
for i, ax in enumerate(axes):
    for name, curve in C7_CURVES.items():
        colour, ls, lw = styles[name]
        ax.semilogy(kk[1:], curve[:, i], ls, color=colour, lw=lw, label=name)
    ax.axhline(0.1, color="k", lw=0.7, alpha=0.6)  # X4's level (ours); C7 has none
    ax.set_title(f"target {i + 1}")
    ax.set_xlabel("horizon $T'$ [steps]")
T_SHOWN = min(5, T) - 1  # the first steps (rho ~ 1e-5 at T' = 1, E_i(0) = 0) are off the axis
axes[0].set_ylim(bottom=0.5 * min(float(c[T_SHOWN:].min()) for c in C7_CURVES.values()))
axes[0].set_ylabel("relative RMS error $\\rho_i(T')$ [–]")
axes[-1].annotate("0.1 (X4's level, ours)", (kk[-1], 0.1), xytext=(-4, -10), textcoords="offset points",
                  ha="right", fontsize=7)
fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncols=4, fontsize=7,
           frameon=False)
fig.suptitle("C7: relative RMS error up to horizon T' (exact expectations; oracle over "
             f"{F} attack draws)")
_ = plotting.save_figure(fig, FIG_DIR, "extra_tracking_baselines",
                         data={"horizon": kk[1:]}
                         | {name.replace(" ", "_"): c for name, c in C7_CURVES.items()})

# %% [markdown]
# No gain inside (8) tracks well. At the default point even the per-step optimal gain leaves 0.17 / 0.19 /
# 0.16 (0.14–0.22 for the worst target over the declared space), and the debiased innovation with optimal
# gain still leaves 0.11 / 0.13 / 0.12. In an attacked step (8) can only add the attack's bias (the
# identity under (12)), and minimising the trace of the bound drives $L$ towards 0 for the targets
# attacked most. The oracle (0.016 / 0.013 / 0.012) and the attack-free design (0.012 / 0.007 / 0.003)
# track to about 1 %, and so does the design under the additive reading of (6) (0.04 / 0.09 / 0.03). The
# gap comes from the *replacement* in (6) with the structure of (8), not from our weights, horizon or
# surrogate: over the sweep our corrected design's largest $\rho_i$ is 0.25–0.39 with the grid weights and
# 0.39–0.66 with the interior ones. Whether that is "well match" the paper does not say: C7 is recorded,
# not judged (its $\rho$ and the ratio to $L=0$'s are in claims.json, for a reader with a scale).
#
# ### The smallest fix: a debiased innovation (ours, X1)
#
# With (8) uncompensated, the expected innovation is
# $\mathbb E\{y_i\}-\Gamma\hat x^-=\check\psi_i\Gamma x_i+(1-\check\psi_i)\Phi\xi_i-\Gamma\hat x^-$, so the mean error obeys
# $\mathbb E e(k|k)=(I-L\Gamma)\mathbb E e(k|k-1)+(1-\check\psi_i)L\Gamma\,\mathbb E x_i(k)-(1-\check\psi_i)L\Phi\xi_i$:
# every attacked step pulls the estimate toward $\xi$, a bias proportional to the state. One factor in
# the innovation, $y_i(k)-\check\psi_i\Phi C_iH_\epsilon\hat x_i(k|k-1)$ (same gain (28)), gives
# $\mathbb E e(k|k)=(I-\check\psi_iL\Gamma)\mathbb E e(k|k-1)-(1-\check\psi_i)L\Phi\xi_i$: only the bounded $\xi$
# remains. Exact expectations below (the paper's $\mathfrak S$ is not claimed to bound this estimator).

# %%
EX_DEBIASED = exact_moments(W_MAIN, variant=coef, debias=True)
EX_OPEN = C7_ROWS["open-loop prediction"]
fig, axes = plt.subplots(2, N, figsize=(plotting.PAGE_WIDTH, 4.6), sharex=True,
                         layout="constrained")
for i in range(N):
    for ex, colour, ls, label in ((EX, "tab:red", "-", "paper (8)"),
                                  (EX_DEBIASED, "tab:green", "-", "debiased innovation (ours)"),
                                  (EX_OPEN, "k", ":", "open-loop prediction")):
        axes[0, i].semilogy(kk[1:], exact_mse(ex)[1:, i], ls, color=colour, label=label)
        axes[1, i].plot(kk, ex["mean_e"][:, i, 0], ls, color=colour, label=label)
    axes[0, i].set_ylim(bottom=log_floor(exact_mse(EX)[:, i], exact_mse(EX_DEBIASED)[:, i]))
    axes[0, i].set_title(f"target {i + 1}")
    axes[1, i].axhline(0.0, color="k", lw=0.6)
    axes[1, i].set_xlabel("time step k [–]")
axes[0, 0].set_ylabel("$\\mathbb{E}\\|e_i(k|k)\\|^2$ [m², m²/s²]")
axes[1, 0].set_ylabel("mean error of $X^p$ [m]")
fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="outside lower center", ncols=3, fontsize=7,
           frameon=False)
fig.suptitle("Ours: removing the attack-induced bias (exact expectations, gains (28))")
plotting.save_figure(fig, FIG_DIR, "extra_debiased_estimator",
                     data={"k": kk, "mse_paper": exact_mse(EX), "mse_debiased": exact_mse(EX_DEBIASED),
                           "mse_open_loop": exact_mse(EX_OPEN),
                           "mean_err_Xp_paper": EX["mean_e"][:, :, 0],
                           "mean_err_Xp_debiased": EX_DEBIASED["mean_e"][:, :, 0],
                           "mean_err_Xp_open_loop": EX_OPEN["mean_e"][:, :, 0]})
X1_REDUCTION = 1 - exact_mse(EX_DEBIASED)[1:, 0].mean() / exact_mse(EX)[1:, 0].mean()
print(f"target 1: time-averaged E||e||^2 reduced by {X1_REDUCTION:.3f}; mean X^p error at T: "
      f"{EX['mean_e'][-1, 0, 0]:.3f} (paper) vs {EX_DEBIASED['mean_e'][-1, 0, 0]:.3f} (debiased)")

# %% [markdown]
# ## The declared space: where each verdict holds
#
# `make robustness` ran this notebook at every point of the declared space (`notebooks/li2025.toml`):
# the four readings `weight_rule`, `xhat_moment`, `coupling_factor`, `attack_signal` crossed with a
# Sobol sample of four (`T`, `mc_seed`) pairs, plus the default point (65 points). Left: C7's recorded
# value (the largest $\rho_i(T)$ of our corrected design) against the horizon; middle: C2's decisive ratio (ZOH /
# zero-input MSE of the informative target) with its outcome; right: the outcome of every claim at every
# point. The figure is drawn from the committed `figures/li2025/robustness.csv`.
#
# Cost: a point is one kernel start (~3.5 s) plus this notebook with figures off (~3 s at $T=100$,
# the Theorem 3 weight search included); the committed sweep used 490 s of user and 130 s of system
# CPU for 65 points (28 minutes of wall time on a shared, heavily loaded 2-core machine; about 5
# minutes on two idle cores). A denser design costs proportionally: $n=8$ Sobol pairs (129 points)
# about twice as much, the full factorial of the four readings with eight horizons and two seeds (256
# points) about four times.
#
# **Samples, not points.** The 65 points are 5 independent random draws (4 Sobol $(T,$ `mc_seed`$)$ pairs
# × 16 reading cells, plus the default point): cells of one draw share its noise and attacks. The sweep's
# Wilson interval (`robustness.json`, package-wide) counts distinct records; claims.json's `robustness`
# gives instead each claim's `independent` draws behind its decided points (its distinct records where
# fewer, e.g. 1 for X9, one evaluation: no swept parameter enters its instance) and the Wilson interval over
# them (`interval`; the package's is kept as `interval_records`). C2 is read per draw (printed below).
# `robustness.csv`'s column `copied` names the cells that are not that point's own evaluation by this
# version of the notebook (one evaluation copied, a rule applied, or a record from an earlier version).

# %%
ROBUSTNESS_CSV = results.resolve("figures/li2025/robustness.csv")
DRAW_SUMMARY: dict[str, dict] = {}


def draw_summary(rows, cid: str) -> dict:
    """Independent draws (T, mc_seed) behind claim cid's decided points, or its distinct records where
    fewer, with the Wilson interval over them (ours: the sweep's interval counts records)."""
    decided = [r for r in rows if r[f"{cid}.outcome"] in ("holds", "fails")]
    by_draw: dict[tuple[str, str], list[bool]] = {}
    for r in decided:
        by_draw.setdefault((r["T"], r["mc_seed"]), []).append(r[f"{cid}.outcome"] == "holds")
    records = {(r[f"{cid}.outcome"], r[f"{cid}.record"]) for r in decided}
    n, held = ((len(records), sum(o == "holds" for o, _ in records)) if len(records) < len(by_draw)
               else (len(by_draw), sum(all(v) for v in by_draw.values())))
    lo, hi = montecarlo.wilson_interval(held, n) if n else (0.0, 1.0)
    return {"draws": len(by_draw), "independent": n, "independent_holding": held, "interval": results.interval(
        lo, hi, method="wilson over the independent draws (T, mc_seed) of the decided points, or over "
        "their distinct records where fewer; independent_holding counts the draws at which every "
        "decided cell holds (li2025, ours)")}

OUTCOME_MARKER = {"holds": "o", "fails": "x", "fails-premise": "^", "not-checked": "s"}
RULE_COLOUR = {"grid": "tab:orange", "interior": "tab:purple"}


def sweep_scatter(ax, rows, cid: str, threshold: float | None, ylabel: str) -> None:
    """Claim cid's headline value against T at every sweep point: marker = outcome, colour = weights."""
    for outcome, marker in OUTCOME_MARKER.items():
        for rule, colour in RULE_COLOUR.items():
            sel = [r for r in rows if r[f"{cid}.outcome"] == outcome and r["weight_rule"] == rule
                   and r[f"{cid}.value"] != ""]
            if sel:
                ax.scatter([float(r["T"]) for r in sel], [float(r[f"{cid}.value"]) for r in sel],
                           marker=marker, s=18, color=colour, label=f"{outcome}, {rule} weights")
    if threshold is not None:
        ax.axhline(threshold, color="k", lw=0.7)
    ax.set_xlabel("horizon T [steps]")
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=6.5, loc="upper center", bbox_to_anchor=(0.5, -0.2), frameon=False)  # below: covers no point


fig, axes = plt.subplots(1, 3, figsize=(plotting.PAGE_WIDTH, 3.4), layout="constrained",
                         gridspec_kw={"width_ratios": [1, 1, 1.3]})
if ROBUSTNESS_CSV.exists():
    with ROBUSTNESS_CSV.open() as fh:
        sweep_rows = [r for r in csv.DictReader(fh) if r["status"] == "ok"]
    sweep_scatter(axes[0], sweep_rows, "C7", None, "C7: max$_i\\,\\rho_i(T)$, corrected design [–]")
    sweep_scatter(axes[1], sweep_rows, "C2", 1.0, "C2: MSE ratio ZOH / zero-input [–]")
    cids = [c[:-len(".outcome")] for c in sweep_rows[0] if c.endswith(".outcome")]
    code = {"holds": 2, "fails": 0, "fails-premise": 1, "not-checked": 1}
    outcome_grid = np.array([[code.get(r[f"{c}.outcome"], np.nan) for r in sweep_rows] for c in cids])
    order = np.argsort([float(r["T"]) for r in sweep_rows], kind="stable")
    outcome_colours = plt.matplotlib.colors.ListedColormap(["tab:red", "0.7", "tab:blue"])
    axes[2].imshow(outcome_grid[:, order], aspect="auto", interpolation="nearest",
                   cmap=outcome_colours, vmin=0, vmax=2)
    axes[2].set_yticks(range(len(cids)), cids)
    axes[2].grid(False)
    axes[2].set_xlabel("design point, sorted by T [–]")
    axes[2].set_title("blue: holds, red: fails, grey: premise fails / not checked", fontsize=8)
    c2_draws: dict[tuple[int, int], list[str]] = {}
    for r in sweep_rows:  # the independent draws of the design: one (T, mc_seed) pair each
        c2_draws.setdefault((int(float(r["T"])), int(float(r["mc_seed"]))), []).append(r["C2.outcome"])
    for (t_, seed_), outs in sorted(c2_draws.items()):
        print(f"C2 at the draw T = {t_}, mc_seed = {seed_}: {outs.count('holds')} of {len(outs)} "
              "reading cells hold")
    DRAW_SUMMARY = {cid: draw_summary(sweep_rows, cid) for cid in cids}
    robustness_data = {"T": [float(r["T"]) for r in sweep_rows]} | {
        f"{cid}_value": [float(r[f"{cid}.value"]) if r[f"{cid}.value"] else np.nan for r in sweep_rows]
        for cid in ("C2", "C7")}
else:
    for ax in axes:
        ax.text(0.5, 0.5, "no sweep yet:\nrun make robustness", ha="center", va="center",
                transform=ax.transAxes)
    robustness_data = {"T": [np.nan], "C2_value": [np.nan], "C7_value": [np.nan]}
fig.suptitle("Robustness sweep over the declared space")
_ = plotting.save_figure(fig, FIG_DIR, "extra_robustness_map", data=robustness_data)

# %% [markdown]
# ## Claims
#
# Outcomes at the default point (the committed run); the counts over the declared space (65 points =
# 5 independent draws, `figures/li2025/robustness.json`) are in the robustness table printed below the
# claims cell. **D**: decides the ReScience verdict; **BC**: true by construction (shown, not evidence).
# X claims are ours; where a claim passes only with our correction it is an X claim and says so.
#
# | id | paper (source) | what we measure | at the default |
# |---|---|---|---|
# | C1b (D) | the bound with the printed coefficients, for any positive weights (Theorems 1–2, Remark 4); premise: (17)–(18) have positive-definite solutions at every $k$ (measured: min $\lambda_{\min}$ 7·10⁻⁷ > 0) | exact certificate $\max\lambda_{\max}(\mathfrak S^{-1/2}P\mathfrak S^{-1/2})\le1+10^{-9}$ at the Remark-4 weights: 2.9·10³ / 1.8·10⁴ / 3.4·10⁵ from $k=2$; printed $c_0$ alone 2.8·10³ / 1.8·10⁴ / 3.3·10⁵, printed $\kappa_x$ alone 0.77 / 0.56 / 0.38 (finite to $k=58$); at the $\alpha_2>\alpha_3$ weights 0.9997 / 0.91 / 0.59 | **fails** |
# | C1c | Fig. 7: MSE always below the bound (Section IV), printed coefficients | Bonferroni $t$-intervals of mean(tr $\mathfrak S$ − $\|e\|^2$) per cell: 280 of 300 cells wholly below 0 | **fails** |
# | C2 | ZOH does not improve on zero-input (Remark 2, Fig. 6) | MSE ratio ZOH / zero-input, paired bootstrap 95 % intervals, informative targets only; default: target 1, 1.07 [1.04, 1.11]; read per independent draw (printed with the sweep figure) | **holds** |
# | C3 (D) | Theorem 3 under Assumption 1 and its conditions (a)–(c): exponential mean-square boundedness (introduction, Section V) | on our declared instance, every eligible weight set: max $\mathbb E\|e\|^2/UB$ (our re-derived envelope) ≤ 1; premise (restated in session 14): eligible weights, and $L=0$ above the envelope somewhere; $L=0$ meets it (0.0861239 against 0.0861238) | **fails-premise** |
# | C3a | Theorem 3 (Assumption 1, conditions (a)–(c)) applies to the example (Fig. 8) | premise: ranks of $E_iE_i^T$ (1) and $\sum_jB\sum_jB^T$ (0 / 2 / 2) against 4; conditions at the weights in use also measured (not met) | **fails-premise** |
# | C3b | Fig. 8: $\|e_i\|^2\le UB_i$ confirms Theorem 3 | data-driven envelope ($10^{13}$–$10^{17}$, vacuous); premise C3a | **fails-premise** |
# | C4 (BC) | RRL-MAP fairness (Remark 1, (2)) | counts per $U$-window, exact: arithmetic of (2) | **holds** |
# | C5 (BC) | $\Pr\{\psi_i=0\}=1-\check\psi_i$ (6), our draws | attack frequency in the 99.99 % Wilson interval | **holds** |
# | C7 (D) | Figs. 2–4: estimates "well match" | recorded, not judged (no scale in the paper): exact relative RMS $\rho_i(T)$ of our corrected design 0.34 / 0.32 / 0.21 (0.71 / 0.97 / 0.95 of the open-loop prediction's), of the printed-coefficient design 0.46 / 0.33 / 0.22 (0.96 / 0.99 / 0.99) | **not-checked** |
# | C8 (D) | Theorem 2: for given positive weights the gain (28) minimises tr $\mathfrak S_i(k\|k)$ | smallest eigenvalue of $\Pi$ of (28) relative to its largest, along each weight set's own trajectory, printed coefficients: −1 at `thm2_weights` ($\kappa_x<0$; indefinite at 145 of 300 pairs, at all 145 a gain step lowers tr (18) with $\mathfrak S(k\|k)$ positive definite); printed $c_0$ alone: $\Pi\succ0$; printed $\kappa_x$ alone: indefinite | **fails** |
# | C8b (BC) | Theorem 2 at our grid's weights (printed $c_0>0$, $\kappa_x\ge0$) | the same rule: $\Pi\succ0$ automatic there; smallest relative eigenvalue 3·10⁻⁷ > 0 | **holds** |
# | X1 | ours: debiased innovation removes the bias | exact: target-1 $\mathbb E\|e\|^2$ −53 %, mean $X^p$ error 6.5 → 0.02 m | **holds** |
# | X2 | ours: vectorised = loop over runs | relative deviation ≤ 1e−9 | **holds** |
# | X3 | ours: the exact recursion is right | Monte Carlo of the same gains (2000 runs) covers the exact value (99.9 % $t$-interval) | **holds** |
# | X4 | ours: the tracking failure is intrinsic to (8) | per-step optimal gain > 0.1 (0.17 / 0.19 / 0.16), oracle ≤ 0.1 (0.016 / 0.013 / 0.012) | **holds** |
# | X5 | ours: the *corrected* bound holds at every $k$ (Theorems 1–2 re-derived; passes only with our correction) | exact certificate per $\check\psi$ scenario, margin-aware: 0.97 / 0.89 / 0.56 at the paper's $\check\psi$; $\check\psi=1$ tight ($1-4\cdot10^{-9}$, within tolerance, not decided) | **holds** |
# | X6 | ours: Fig. 7's comparison on our corrected design | the C1c rule on the corrected coefficients: smallest relative margin 0.79 [0.69, 0.90] | **holds** |
# | X7 | ours: with $e_*=b_*=0$ admitted, no weights meet Theorem 3's (a)–(c) | floor $\eta^*/\phi^*\ge1.63$ for $\kappa_x\ge0$ (proved) and a 4096-point search for $\kappa_x<0$ | **holds** |
# | X8 (BC) | ours: Kalman limit of (17)–(18)–(28) | deviation from the Riccati recursion ≤ 1e−10 | **holds** |
# | X9 | ours: on our instance, at the searched eligible weights, $\mathbb E\|e\|^2$ stays below our re-derivation of Theorem 3's envelope (C3's measurement, not deciding) | max $\mathbb E\|e\|^2/UB$ 0.086 ≤ 1; the open-loop prediction meets it too | **holds** |

# %%
MC_TOL = results.Tolerance(
    rtol=1e-7, atol=1e-10,
    reason="Monte Carlo statistics over the F runs: the random streams are reproducible "
    "(SeedSequence, PCG64) but sums over runs change their last digits with the BLAS build")
EIG_TOL = results.Tolerance(
    rtol=1e-5, atol=1e-12,
    reason="extreme eigenvalues of nearly singular bound matrices (phi_* is ~1e-8 of phi^*) "
    "and products of them: the last digits depend on the LAPACK build")
CERT_TOL = results.Tolerance(
    rtol=1e-6, atol=1e-9,
    reason="smallest eigenvalue of the difference of two matrices of norm up to ~1e4 after a "
    "T-step recursion, relative to the larger: rounding moves it at the 1e-12 level")
THM2_TOL = results.Tolerance(
    rtol=1e-6, atol=1e-12,
    reason="smallest eigenvalue of Pi of (28) relative to its largest, Pi of norm up to ~1e4 (and the "
    "relative change of the trace of (18) reported beside it): the last digits depend on the "
    "BLAS/LAPACK build")


def decided(value, level, tol, holds_if="le"):
    """Margin-aware decision (ours): True/False by `value` against `level`, or None when the
    margin |value - level| is within the value's own cross-machine tolerance `tol` (then another
    machine could decide the other way, so the point is not decided)."""
    if abs(value - level) <= tol.atol + tol.rtol * abs(value):
        return None
    return bool(value <= level) if holds_if == "le" else bool(value >= level)


claims = {}
X5_LEVEL = 1 + 1e-9
X5_SCEN = {n: float(v.max()) for n, v in C1_SHARE.items()}
X5_DEC = {n: decided(v, X5_LEVEL, CERT_TOL) for n, v in X5_SCEN.items()}
X5_TIGHT = [n for n, d in X5_DEC.items() if d is None]
X5_HOLDS = (False if any(d is False for d in X5_DEC.values())
            else None if all(d is None for d in X5_DEC.values()) else True)
claims["X5"] = results.claim(
    paper="(ours) Theorem 1 re-derived: with the corrected coefficients of (18) (and (17) with the "
    "factor |K_i| or the plain sum), S_i(k|k) is an upper bound of the estimation error "
    "covariance at every k",
    source="ours (Theorems 1-2 re-derived from (20)-(27); the printed version is C1b)",
    check="OUR CORRECTED DESIGN, not the paper's: it holds only with our corrected coefficients "
    "(the printed ones: C1b). EXACT: gains (28) with the exact E{xhat xhat^T} (deterministic), "
    "exact P_i(k) = E{e_i e_i^T} by the second-moment recursion; per scenario (the paper's "
    "psi_check and every psi_check of c1_psi_scan, all targets) the certificate max over k = 1..T "
    "and targets of lambda_max(S_i^-1/2 P_i S_i^-1/2) against 1 + 1e-9 (S_i >= P_i as matrices), "
    "weights in use (weight_rule), (17) reading in use (coupling_factor). MARGIN-AWARE (replaces, "
    "session 9, the rule 'max over all scenarios <= 1 + 1e-9', whose margin at psi_check = 1 was "
    "below the claim's own tolerance; that old reading is recorded as old_rule_holds): a scenario "
    "whose share lies within its cross-machine tolerance of 1 + 1e-9 is tight (equality to "
    "rounding, which S >= P allows but floating point cannot certify) and is not decided; holds if "
    "every decided scenario holds and one is decided, fails if a decided one fails. Reported: per "
    "scenario the largest share and min_k lambda_min(S_i - P_i); min over k >= 5 of tr S / tr P",
    measured={"max_share": C1_MAX,
              "max_share_per_scenario": {n: v.max(axis=0) for n, v in C1_SHARE.items()},
              "tight_scenarios": X5_TIGHT,
              "max_share_decided": max([X5_SCEN[n] for n in X5_SCEN if n not in X5_TIGHT],
                                       default=None),
              "old_rule_holds": bool(C1_MAX <= X5_LEVEL),
              "min_eig_S_minus_P_per_scenario": C1_GAP,
              "min_trS_over_trP_k5": (TRS_EX[K5] / TRP_C[K5]).min(axis=0),
              "weight_rule": weight_rule, "coupling_factor": coupling_factor},
    threshold=X5_LEVEL, holds=X5_HOLDS, key="max_share", tolerance=CERT_TOL,
    not_checked=None if X5_HOLDS is not None else
    "every scenario's share lies within its cross-machine tolerance of 1 + 1e-9 (tight)",
    section="X5 — the corrected bound (ours), certified by the exact second-moment recursion",
)
c1cp_cell = (d_runs_p.mean(axis=0) / np.where(TRS_P[1:] > 0, TRS_P[1:], np.nan))[c1cp_worst]
C1C_DEC = decided(float(c1cp_rel_hi.min()), 0.0, MC_TOL, "ge") if C1C_P_FINITE else None
claims["C1c"] = results.claim(
    paper="Fig. 7: MSE_i(k) is always below its minimum upper bound",
    source="Section IV, Fig. 7",
    check="MONTE CARLO as the paper runs it, with the coefficients AS PRINTED (Theorem 2) at their "
    "Remark-4 weights (weights_paper; weights_interior under weight_rule 'interior'), Algorithm 1 "
    "with the xhat_moment surrogate, F runs: d_f(k) = tr S_f(k|k) - ||e_f(k|k)||^2; holds if at "
    "every k = 1..T and target the upper end of the Bonferroni t-interval of mean_f d_f(k) (family "
    "level 95 %, 1 - 0.05/(3T) per cell) is >= 0 (fails if some cell's whole interval lies below "
    "0; not-checked when the smallest upper end is within its tolerance of 0). Headline: mean d / "
    "mean tr S at the cell with the smallest upper end, with its interval. Reported: cells whose "
    "interval lies below 0, the paper's literal reading (fraction of k with MSE <= mean tr S). "
    "The same rule on our corrected design is X6",
    measured={"worst_cell_relative_margin": None if not np.isfinite(c1cp_cell) else float(c1cp_cell),
              "worst_cell_k": int(c1cp_worst[0]) + 1, "worst_cell_target": int(c1cp_worst[1]) + 1,
              "cells_below_zero": int(np.sum(c1cp_rel_hi < 0)), "cells": int(c1cp_rel_hi.size),
              "fraction_k_mse_below": np.mean(MSE_P[1:] <= TRS_P[1:], axis=0)},
    interval=None if not (C1C_P_FINITE and np.isfinite(c1cp_cell)) else results.interval(
        dp_lo[c1cp_worst] / TRS_P[1:][c1cp_worst], c1cp_rel_hi[c1cp_worst], level=C1C_LEVEL,
        method="t over runs, Bonferroni over 3T cells"),
    threshold=0.0, holds=C1C_DEC,
    not_checked=None if C1C_DEC is not None else
    ("the printed bound's mean trace is not positive and finite at every step" if not C1C_P_FINITE
     else "the smallest upper end lies within its tolerance of 0"),
    key="worst_cell_relative_margin", tolerance=MC_TOL, runs=F,
    section="Fig. 7 — $\\mathrm{MSE}_i(k)$ over $F$ runs and the minimum upper bound (C1c)",
)
c1c_cell = (d_runs.mean(axis=0) / TRS_C[1:])[c1c_worst]
claims["X6"] = results.claim(
    paper="(ours) Fig. 7's comparison holds for our corrected design: MSE_i(k) below the mean of "
    "the corrected bound",
    source="ours (Fig. 7 on our corrected coefficients; the printed version is C1c)",
    check="OUR CORRECTED DESIGN (passes only with our corrected coefficients; the printed ones: "
    "C1c). MONTE CARLO (Algorithm 1 with the xhat_moment surrogate, corrected "
    "coefficients, F runs): d_f(k) = tr S_f(k|k) - ||e_f(k|k)||^2; holds if at every k = 1..T and "
    "target the upper end of the Bonferroni t-interval of mean_f d_f(k) (family level 95 %, "
    "1 - 0.05/(3T) per cell) is >= 0. Headline: mean d / mean tr S at the cell with the smallest "
    "upper end, with its interval. Reported: min over k >= 5 of mean tr S / MSE; the paper's literal "
    "reading, the fraction of k with MSE <= mean tr S (noise-sensitive where the bound is tight)",
    measured={"worst_cell_relative_margin": c1c_cell, "worst_cell_k": int(c1c_worst[0]) + 1,
              "worst_cell_target": int(c1c_worst[1]) + 1,
              "min_trS_over_mse_k5": (TRS_C[K5] / MSE_C[K5]).min(axis=0),
              "fraction_k_mse_below": np.mean(MSE_C[1:] <= TRS_C[1:], axis=0),
              "xhat_moment": xhat_moment},
    interval=results.interval(d_lo[c1c_worst] / TRS_C[1:][c1c_worst], c1c_rel_hi[c1c_worst],
                              level=C1C_LEVEL, method="t over runs, Bonferroni over 3T cells"),
    threshold=0.0, holds=bool(c1c_rel_hi.min() >= 0), key="worst_cell_relative_margin",
    tolerance=MC_TOL, runs=F,
    section="Fig. 7 — $\\mathrm{MSE}_i(k)$ over $F$ runs and the minimum upper bound (C1c)",
)
C1B_MAX = C1B_SHARE.max(axis=0)
C1B_DEC = decided(float(C1B_MAX.max()), 1 + 1e-9, CERT_TOL) if np.all(np.isfinite(C1B_MAX)) else False
claims["C1b"] = results.claim(
    paper="Theorems 1-2 with the coefficients as printed: S_i(k|k) bounds the error covariance "
    "for given positive scalars lambda, alpha_1..alpha_4, which 'can be changed arbitrarily' "
    "(Remark 4)",
    source="Theorems 1-2, (18), (28); Remark 4",
    check="EXACT, printed coefficients, the weights our Remark-4 grid picks for them (weights_paper; "
    "weights_interior under weight_rule 'interior'): the certificate of X5, max over k and targets of "
    "lambda_max(S^-1/2 P S^-1/2) <= 1 + 1e-9; a larger value is an exact counterexample (None: S "
    "not positive definite). Reported: first violating k per target (0: none), the same for the "
    "alpha2 > alpha3 weights (Theorem 3's condition; there the printed recursion does bound: "
    "max share < 1), time-averaged tr S / E||e||^2 (exact), the Monte Carlo fraction of k with "
    "MSE <= mean tr S (Fig. 7 with the printed coefficients). TWO PRINTED ERRORS apart (same weights, "
    "max share per target): the printed c0 with the derived kappa's, the derived c0 with the printed "
    "kappa_x (one_printed_coefficient)",
    measured={"max_share": float(C1B_MAX.max()) if np.all(np.isfinite(C1B_MAX)) else None,
              "one_printed_coefficient": C1B_SPLIT,
              "max_share_per_target": [float(v) if np.isfinite(v) else None for v in C1B_MAX],
              "min_eig_S": finite_or_none(C1B_MIN_EIG),
              "first_violating_k": C1B_FIRST_K,
              "max_share_alpha2_gt_alpha3": [float(v) if np.isfinite(v) else None
                                             for v in C1B_SHARE_THM3.max(axis=0)],
              "trS_over_mse_exact": np.trace(EX_PRINTED["S"], axis1=-2, axis2=-1)[1:].mean(axis=0)
              / exact_mse(EX_PRINTED)[1:].mean(axis=0),
              "fraction_monte_carlo": np.mean(mse(out_printed)[1:] <= mean_trace(out_printed)[1:], 0),
              "fraction_monte_carlo_alpha2_gt_alpha3": np.mean(
                  mse(out_printed_thm3)[1:] <= mean_trace(out_printed_thm3)[1:], axis=0)},
    threshold=1 + 1e-9, holds=C1B_DEC, key="max_share", tolerance=CERT_TOL,
    not_checked=None if C1B_DEC is not None else
    "the largest share lies within its cross-machine tolerance of 1 + 1e-9",
    premise=("Theorem 1: the recursions (17)-(18) have positive-definite solutions at every k "
             f"(measured: min over k and targets of lambda_min of S(k|k-1), S(k|k) = {C1B_MIN_EIG:.3g})",
             bool(C1B_MIN_EIG > 0)),
    decides=True, section="The printed coefficients are not a bound (C1b)",
)
THM2_GRID = ("printed, Remark-4 weights", "printed, alpha2 > alpha3 weights")
THM2_DECLARED = "printed, declared weights (thm2_weights)"
THM2_JUDGED = THM2_GRID + (THM2_DECLARED,)


def thm2_decision(names):
    """Headline, margin-aware decision and reason of the C8 rule over the weight sets `names`."""
    if not all(THM2[n] is not None for n in names):
        return None, None, "the gain (28) is not finite at some step"
    value = min(THM2[n]["min_eig_pi_relative"] for n in names)
    dec = decided(value, THM2_LEVEL, THM2_TOL, "ge")
    return value, dec, None if dec is not None else \
        "the smallest relative eigenvalue of Pi lies within its tolerance of the level"


C8_VALUE, C8_DEC, C8_WHY = thm2_decision(THM2_JUDGED)
C8B_VALUE, C8B_DEC, C8B_WHY = thm2_decision(THM2_GRID)
THM2_DECL = THM2[THM2_DECLARED]
claims["C8"] = results.claim(
    paper="Theorem 2: for given positive scalars epsilon, alpha_1..alpha_4 and lambda, the upper "
    "bound S_i(k|k) can be minimized by the gain (28) (proof: d tr S_i(k|k) / d L_i(k) = 0, (29))",
    source="Theorem 2, (28)-(29); Section III (opening), Section V",
    check="EXACT, coefficients AS PRINTED in Theorem 2 (coef 'paper', (18)'s first factor read as "
    "Theorem 2's, as in C1b). Three positive weight sets, each with Algorithm 1 run at those weights "
    "(the paper's reading: (17) with their lambda, (18), (28), exact E{xhat xhat^T}) and judged along "
    "its own trajectory: the Remark-4 weights, the alpha2 > alpha3 weights, and the declared "
    f"thm2_weights {list(thm2_weights)} (ours, the reviewer's counterexample: printed c0 > 0, "
    "kappa_x < 0 for psi < 0.89). (18) is quadratic in L and its first-order term is zero at (28) by "
    "the algebra of (28), so (28) minimises tr (18) iff Pi of (28) is positive semidefinite; an "
    "indefinite Pi makes (28) a saddle and tr (18) unbounded below in L. HEADLINE (the quantity that "
    "decides): the smallest eigenvalue of Pi relative to its largest |eigenvalue|, min over k = 1..T, "
    f"targets and the three sets. Holds if it is >= {THM2_LEVEL:g} (ours: rounding), fails below, "
    "not-checked within its tolerance of that level. Corroboration (reported, not the rule): at every "
    "k and target L* is perturbed, L = L* +- s delta, by "
    f"{THM2_RANDOM} random unit directions, the structured ones e_r v_j^T (v_j the eigenvectors of Pi) "
    f"and L*/||L*||, s = t max(||L*||_F, 1), t in {list(THM2_STEPS)}, tr (18) evaluated term by term "
    "(bound_for_gain): the smallest relative change (its extreme value comes from the largest step "
    "along the most negative direction and measures nothing but the saddle). At the two grid sets (our "
    "grid keeps only printed c0 > 0, kappa_x >= 0) Pi > 0 is automatic (C8b, by construction); the "
    "measured content is the declared set. Reported per set: steps with Pi indefinite (of T x 3), min "
    "eig Pi, lambda_min of S(k|k) at (28) at the indefinite-Pi steps (S stays positive definite: the "
    "saddle is not a breakdown of the recursion), the first-order term, c0 and kappa_x per target; the "
    "declared weights on the Remark-4 trajectory (the previous version's judgement, where their "
    "lambda did not enter); Theorem 1's positive-definite solutions at the declared weights; the corrected "
    "design; and (18) with its first factor read literally, (1 - (alpha3 - alpha2))(1 - psi), where "
    "(28) is not the minimiser: the relative excess of tr (18) at (28) over its minimum. At the declared "
    "weights: of the indefinite-Pi steps, those where L* + s e_r v^T (v Pi's most negative eigenvector, "
    "s = 1e-3 max(||L*||_F, 1)) lowers tr (18) AND keeps S(k|k) positive definite, Theorem 1's premise "
    "(declared_descent_keeping_S_pd); the two printed errors apart (one_printed_coefficient: Pi along "
    "each mixed design's own trajectory)",
    measured={"min_eig_pi_relative": C8_VALUE,
              "steps_with_pi_indefinite_declared": None if THM2_DECL is None
              else THM2_DECL["steps_with_pi_indefinite"],
              "steps_declared": None if THM2_DECL is None else THM2_DECL["steps"],
              "min_eig_S_at_indefinite_pi_declared": None if THM2_DECL is None
              else THM2_DECL["min_eig_S_at_indefinite_pi"],
              "min_relative_change": None if C8_VALUE is None
              else min(THM2[n]["min_relative_change"] for n in THM2_JUDGED),
              "declared_trajectory_min_eig_S": THM2_OWN_MIN_EIG,
              "declared_descent_keeping_S_pd": THM2_PD["descent_keeping_S_pd"],
              "declared_indefinite_steps": THM2_PD["indefinite_steps"],
              "one_printed_coefficient": C8_SPLIT}
    | {n: r for n, r in THM2.items() if r is not None},
    threshold=THM2_LEVEL, holds=C8_DEC, not_checked=C8_WHY,
    key="min_eig_pi_relative", tolerance=THM2_TOL, decides=True,
    section="Theorem 2: does the gain (28) minimise the trace of the bound (18)? (C8)",
)
claims["C8b"] = results.claim(
    paper="Theorem 2 at the weights our Remark-4 grid yields: the gain (28) minimises tr S_i(k|k)",
    source="Theorem 2, (28)-(29), at our grid's weights (weights_paper, weights_paper_thm3)",
    check="BY CONSTRUCTION: C8's rule at the Remark-4 and alpha2 > alpha3 weights only. (18) is "
    "quadratic in L with its first-order term zero at (28) by algebra, and our grid keeps only weights "
    "with printed c0 > 0 and kappa_x >= 0, where Pi of (28) is positive definite whatever S(k|k-1) and "
    "E{xhat xhat^T}: the minimum is certain before it is measured. Shown, not evidence; same level "
    f"{THM2_LEVEL:g} and headline (min relative eigenvalue of Pi) as C8; the perturbations' smallest "
    "relative change is reported",
    measured={"min_eig_pi_relative": C8B_VALUE,
              "min_relative_change": None if C8B_VALUE is None
              else min(THM2[n]["min_relative_change"] for n in THM2_GRID),
              "min_c0": min((min(THM2[n]["c0_per_target"]) for n in THM2_GRID if THM2[n]),
                            default=None),
              "min_kappa_x": min((min(THM2[n]["kappa_x_per_target"]) for n in THM2_GRID
                                  if THM2[n]), default=None)},
    threshold=THM2_LEVEL, holds=C8B_DEC, not_checked=C8B_WHY,
    key="min_eig_pi_relative", tolerance=THM2_TOL, basis="by-construction",
    section="Theorem 2: does the gain (28) minimise the trace of the bound (18)? (C8)",
)
informative = [i for i in range(N) if INFORMATIVE[i]]
decisive = min(informative, key=lambda i: C2_CI[i, 1]) if informative else None
claims["C2"] = results.claim(
    paper="Fig. 6 / Remark 2: the ZOH method did not lead to an improvement of the estimation "
    "performance over zero-input",
    source="Remark 2, Section IV, Fig. 6",
    check=f"r_i = time-averaged MSE (ZOH) / time-averaged MSE (zero-input), same {F} runs, paired "
    "bootstrap 95 % interval over the runs. Only informative targets count: mean over runs and k of "
    f"||L_i Gamma_i||_2 >= gain_negligible = {gain_negligible:g} (otherwise both estimators are the "
    "open-loop prediction and the target is undetermined). Fails if for some informative target the "
    "whole interval lies below 1 (ZOH significantly better); premise: at least one informative "
    "target. Headline: r of the informative target with the smallest upper end, with its interval",
    measured={"decisive_ratio": None if decisive is None else C2_RATIO[decisive],
              "decisive_target": None if decisive is None else decisive + 1,
              "ratio": C2_RATIO, "interval_low": C2_CI[:, 0], "interval_high": C2_CI[:, 1],
              "gain_share": GAIN_SHARE, "informative": INFORMATIVE, "status": C2_STATUS},
    interval=None if decisive is None else results.interval(
        *C2_CI[decisive], method="paired bootstrap over runs, ratio of means"),
    threshold=1.0, holds=bool(informative) and all(C2_CI[i, 1] >= 1 for i in informative),
    premise=("at least one target is informative (mean ||L_i Gamma_i|| >= gain_negligible)",
             bool(informative)),
    key="decisive_ratio", tolerance=MC_TOL, runs=F,
    section="Fig. 6 against Fig. 5 — ZOH is not better (C2)",
)


def cond_summary(rows_):
    return {key: [r[key] for r in rows_] for key in rows_[0]}


cond_main = THM3_COND["printed, weights in use"]
C3A_MET = [r["a_alpha56_exist"] and r["bc_pair_on_grid"] for r in cond_main]  # weights in use
C3A_SEARCH_MET = [r["all_conditions"] > 0 for r in THM3_SEARCH]  # some searched weight set
C3A_HOLDS = bool(all(a or b for a, b in zip(C3A_MET, C3A_SEARCH_MET, strict=True)))
X7_NONE = not any(a or b for a, b in zip(C3A_MET, C3A_SEARCH_MET, strict=True))
RANK_EE = max(int(np.linalg.matrix_rank(np.outer(e_, e_))) for e_ in E_ALL[:T])
RANK_BB = []
for _i in range(N):
    _bsum = sum((B_MAT[(_i, j)] for j in K_SETS[_i]), np.zeros((NX, NX)))
    RANK_BB.append(int(np.linalg.matrix_rank(_bsum @ _bsum.T)))
# an empty K_i (target 1) is read as in C3: its sum is 0 and b_* = b^* = 0 (the reading every sequential
# system needs); the b-condition is asked only of targets with upstream subsystems
ASSUMPTION1_HOLDS = bool(RANK_EE == NX and all(r == NX for r, k_ in zip(RANK_BB, K_SETS, strict=True)
                                               if len(k_) > 0))
C3A_AT_WEIGHTS = bool(all(C3A_MET))
# what C3a and X7 both record: Theorem 3's conditions at the weights in use, the rank of L Phi C H
THM3_MEASURED = {"printed_weights_in_use": cond_summary(cond_main),
                 "corrected_weights_in_use": cond_summary(THM3_COND["corrected, weights in use"]),
                 "printed_alpha2_gt_alpha3_weights": cond_summary(
                     THM3_COND["printed, alpha2 > alpha3 weights"]),
                 "max_rank_L_Phi_C_H": THM3_RANK}
THM3_THRESHOLD = {"c0": 1.0, "eta_upper_over_phi_upper": 1.0, "grid_log10": phi_scan,
                  "rank_needed": NX}
claims["C3a"] = results.claim(
    paper="Theorem 3: with Assumption 1 (positive e_*, b_*, ... bounding E_i E_i^T, "
    "(sum_j B_ij)(sum_j B_ij)^T, ... from below), if 1 + alpha5 + alpha6 <= 1 - (alpha3 - "
    "alpha2)(1 - psi_check), eta_* >= phi_*, eta^* <= phi^* (phi_* I <= S(0|0) <= phi^* I) and "
    "E[x x^T] <= X*^2 I, the error is exponentially bounded in mean square; Fig. 8: 'select "
    "eligible parameters as claimed in Theorem 3' (the paper asserts that the example admits them)",
    source="Theorem 3, Assumption 1, (34)-(38); Section IV, Fig. 8 text",
    check="PREMISE, decided for every weight set: Assumption 1 needs e_*^2 I <= E_i(k) E_i^T(k) and "
    "b_*^2 I <= (sum_j B_ij)(sum_j B_ij)^T with e_*, b_* > 0, i.e. both of full rank 4. On the "
    "example E_i(k) is 4 x 1 (rank of E E^T at most 1) and sum_j B_ij = diag{0, b, 0, b} (rank 2; "
    "0 for target 1, whose K_1 is empty: read, as in C3, with b_* = b^* = 0, so the b-condition is "
    "asked of targets 2, 3 only; the outcome does not depend on it, E E^T fails alone), at every k and at every point of the declared space (no parameter "
    "changes E_i or B_ij): the ranks are measured. Where the premise fails the outcome is "
    "fails-premise whatever the conditions give, with no search needed. Also measured, at the "
    "weights in use with the literal constants (e_* = b_* = 0): conditions (a) c0 > 1, (b) eta_* >= "
    "phi_*, (c) eta^* <= phi^* at one pair of the phi_scan grid with pi_*, pi^* > 0 (holds if met for "
    "every target); the weight-free floor and the 4096-point search are our supporting evidence, "
    "X7. Reported: the same with the corrected coefficients and the alpha2 > alpha3 weights; max "
    "rank of L Phi C H ((36) needs full rank 4; at most m for any gain)",
    measured={"rank_E_Et_max": RANK_EE, "rank_Bsum_Bsum_t_per_target": RANK_BB,
              "rank_needed": NX, "conditions_met_at_weights_in_use": C3A_MET} | THM3_MEASURED,
    threshold=THM3_THRESHOLD,
    holds=C3A_AT_WEIGHTS,
    premise=("Assumption 1 holds on the example: E_i(k) E_i^T(k) and, for every target with a "
             "non-empty K_i, (sum_j B_ij)(sum_j B_ij)^T have full rank (e_*, b_* > 0; an empty K_i "
             "read with b_* = b^* = 0, as in C3)", ASSUMPTION1_HOLDS),
    tolerance=EIG_TOL, runs=F,
    section="Theorem 3's own conditions on the example (C3a)",
)
INST_DEC = None if INST_RATIO is None else decided(INST_RATIO, 1.0, EIG_TOL)
INST_CHECK = ("N = 2 (K_1 empty, K_2 = {1}), n_x = n_y = 2, m = 1, epsilon = 0.05, A_i = 0.6 R(0.3), "
              "B_21 = 0.2 I, C_i = E_i = I, W = V = 0.03 I, xi* = 0.3 (sin/cos), psi_check = (0.7, 0.5), "
              "x(0) ~ N(1, I), xhat(0|0) = 1, S(0|0) = P(0|0) = I, T = 100. Assumption 1 holds with positive "
              "constants for subsystem 2; for subsystem 1 the sum over K_1 = {} is 0 (unavoidable in any "
              "sequential system) and is read with b_* = b^* = 0 (the same reading as C3a). Eligible "
              "weights: X7's declared search (the same 4096 Sobol weight sets, theorem3_candidates, "
              "49-point (phi_*, phi^*) grid with phi_* <= 1 <= phi^*) with conditions (a) printed c0 > 1, "
              "(b) eta_* >= phi_*, (c) eta^* <= phi^* and pi_*, pi^* > 0 for both subsystems at some pair "
              "(theorem3_eta, as printed). For each eligible weight set, Algorithm 1 with the printed "
              "coefficients and the exact E{xhat xhat^T} (exact_design_moments: exact E||e_i(k|k)||^2); "
              "for each eligible pair an envelope UB_i(k) that is OUR consistent re-derivation from the "
              "proof's constants, not the proof's (56) (theorem3_proof_envelope: rho (55), mu_1 (49), "
              "Lambda (53), mu_2 (51) with (50) corrected, alpha_5..7 chosen by us to minimise mu under "
              "(a), Lemma 3 with its roles consistent); the proof's (36) cannot hold on the instance for "
              "any gain (rank of L Phi C H <= m = 1 < n_x = 2). HEADLINE: max of E||e_i(k|k)||^2 / UB_i(k) "
              "over eligible (weight set, pair), both subsystems and k = 1..T")
INST_MEASURED = {
    "max_ratio": INST_RATIO, "max_ratio_subsystem2": INST_RATIO_2,
    "max_ratio_zero_gain": INST_RATIO_0, "max_gain_share": INST_SHARE,
    "max_error_reduction": INST_REDUCTION, "informative_level": gain_negligible,
    "gain_informative": INST_INFORMATIVE, "zero_gain_violates_envelope": INST_DISCRIMINATES,
    "max_ratio_zero_gain_with_reviewer_set": INST_RATIO_0_ALL, "reviewer_set": REVIEW,
    "eligible_weight_sets": int(INST_ELIGIBLE.size), "weight_sets_searched": len(INST_CAND),
    "eligible_cases": len(INST_ROWS),
    "stage1_holds_cases": sum(r["stage1"] for r in INST_ROWS),
    "lambda_53_holds_cases": sum(r["Lambda_holds"] for r in INST_ROWS),
    "literal_56_holds_cases": sum(r["literal_56_holds"] for r in INST_ROWS),
    "max_gain_norm_sq": INST_GAIN2, "X_star_sq": INST_X2,
    "eligible_weights_first": [list(o["weights"]) for o in INST_OUT[:3]],
    "example_rank_E_Et_max": RANK_EE, "example_rank_Bsum_Bsum_t_per_target": RANK_BB}
INST_PREMISE = ("Theorem 3's premise on our instance: Assumption 1 (subsystem 1 with the empty-sum "
                "b_* = b^* = 0) and conditions (a)-(c) with pi_*, pi^* > 0 for both subsystems at some "
                f"searched weight set (measured: {INST_ELIGIBLE.size} of {len(INST_CAND)})",
                bool(INST_ELIGIBLE.size > 0))
C3_PREMISE = (INST_PREMISE[0] + "; and the PRECONDITION of the measurement (ours, restated in session 14): "
              "the measurement discriminates, L = 0 (the open-loop prediction) violates the envelope at "
              "some eligible case of the search or of the re-review's weight set (largest ratio with "
              f"L = 0 measured {INST_RATIO_0_ALL})", INST_PREMISE[1] and INST_DISCRIMINATES)
if not C3_PREMISE[1]:
    C3_HOLDS, C3_NOT_CHECKED = None, (
        "not decided: its premise fails (no eligible case, or L = 0 meets the envelope at every "
        f"eligible case: ratio {INST_RATIO_0_ALL}); the measured ratio is X9, ours, not deciding")
elif INST_DEC is None:
    C3_HOLDS, C3_NOT_CHECKED = None, "the largest ratio lies within its tolerance of 1"
else:
    C3_HOLDS, C3_NOT_CHECKED = INST_DEC, None
claims["C3"] = results.claim(
    paper="Theorem 3 (a main contribution: introduction, 'effectiveness analysis'; Section V): with "
    "Assumption 1 (positive constants bounding A, B, C, E, H_eps, the noises ... from below and above), "
    "if 1 + alpha5 + alpha6 <= 1 - (alpha3 - alpha2)(1 - psi_check), eta_* >= phi_*, eta^* <= phi^* "
    "(phi_* I <= S(0|0) <= phi^* I) and E[x x^T] <= X*^2 I, the estimation error e_i(k|k) is "
    "exponentially bounded in the mean square",
    source="Theorem 3 (its conditions), Assumption 1; Section I (contributions), Section V; "
    "the envelope from the proof's (44)-(56)",
    check="ON A DECLARED INSTANCE OF OURS (the example cannot satisfy the premise: C3a, shown, not "
    "deciding): " + INST_CHECK + ". Holds if <= 1, fails above (margin-aware); premise: at least one "
    "eligible weight set AND the precondition of the measurement (ours, part of the premise since "
    "session 13): L = 0 (same system, noise, attacks) violates the envelope at some eligible case of "
    "the search or of the re-review's set (an envelope the open-loop prediction meets says nothing "
    "about the estimator); where it fails C3 is fails-premise and the result is X9 (ours, not "
    "deciding). RESTATED in session 14: the precondition was 'an informative gain' (largest "
    "||L Phi C H_eps|| and largest error reduction against L = 0 both >= C2's gain_negligible); the "
    "re-review found a weight set in the declared box, (1.115, 1.305, 14.916, 14.914, 0.0072) "
    "(reviewer_set), eligible for both subsystems, at which it holds, where C3 would hold (ratio "
    f"{max(REVIEW['max_ratio'], default=None):.2g}) and the verdict would be [Re, partial], while "
    f"L = 0 meets the envelope there too ({max(REVIEW['max_ratio_zero_gain'], default=None):.2g}). "
    "Reported: the same for subsystem 2 alone (Assumption 1 "
    "literal); the ratio with L = 0; the old precondition; cases where the proof's Stage 1 phi_* I <= S(k|k) <= phi^* I "
    "holds, where (52) L^T L <= Lambda I holds, where (56) as printed holds; the largest ||L||^2; the "
    "example's ranks (C3a)",
    measured=INST_MEASURED,
    threshold=1.0, holds=C3_HOLDS, key="max_ratio", tolerance=EIG_TOL,
    not_checked=C3_NOT_CHECKED,
    premise=C3_PREMISE,
    decides=True,
    section="Theorem 3 on a declared instance of ours (C3)",
)
claims["X9"] = results.claim(
    paper="(ours) on our declared instance, at every searched weight set meeting Theorem 3's "
    "conditions, Algorithm 1's exact mean-square error stays below the envelope of Theorem 3's proof "
    "(our consistent re-derivation); L = 0, the open-loop prediction of a stable plant, meets it too "
    "(the searched eligible gains are negligible; the re-review's set, reviewer_set, is not)",
    source="ours (Theorem 3 on our instance, C3's measurement where its precondition fails)",
    check="EXACT, as C3 (" + INST_CHECK + "): holds if the headline <= 1, fails above "
    "(margin-aware). Measured, not deciding: it holds with L = 0 too (max_ratio_zero_gain)",
    measured=INST_MEASURED,
    threshold=1.0, holds=INST_DEC, key="max_ratio", tolerance=EIG_TOL,
    not_checked=None if INST_DEC is not None or INST_RATIO is None else
    "the largest ratio lies within its tolerance of 1",
    premise=INST_PREMISE,
    section="Theorem 3 on a declared instance of ours (C3)",
)
claims["X7"] = results.claim(
    paper="(ours) even admitting Assumption 1's constants at their literal values on the example "
    "(e_* = b_* = 0, outside the theorem), no weights meet Theorem 3's conditions (a)-(c)",
    source="ours (Theorem 3, (34)-(38), evaluated outside its premise; C3a)",
    check="conditions with the literal Assumption-1 constants of the example, X*^2 = max_k "
    "lambda_max(MC E[x x^T]), printed coefficients, over the free weights: (1) a weight-free floor "
    "of eta^*/phi^* (ours, proved: theorem3_c_floor) for every weight set with kappa_x >= 0, "
    "(2) a declared search, 4096 scrambled Sobol weight sets log-uniform in lambda in [1e-6, 1e3], "
    "alpha1..alpha4 in [1e-6, 1e6], against a 49-point log grid of pairs phi_* <= 1 <= phi^*, "
    "(3) the weights in use on the phi_scan grid. A weight set meets the theorem if (a) c0 > 1, "
    "(b) eta_* >= phi_*, (c) eta^* <= phi^* at one pair with pi_* > 0 and pi^* > 0 (the proof "
    "inverts (35)). FINITE SEARCH: for kappa_x < 0 a negative answer rests on 4096 points and on "
    "our pi_*, pi^* > 0 requirement. Holds if for NO target a searched weight set or the weights in "
    "use meet them (the earlier C3a rule, 'holds if for every target some set meets them', is "
    "its complement: all_targets_met). Reported: the same with the corrected coefficients and with the alpha2 > alpha3 "
    "weights; max rank of L Phi C H ((36) needs full rank 4; at most m for any gain)",
    measured={"any_target_met": not X7_NONE, "all_targets_met": C3A_HOLDS,
              "search_weight_sets_meeting_all": [r["all_conditions"] for r in THM3_SEARCH],
              "search": cond_summary(THM3_SEARCH)} | THM3_MEASURED,
    threshold=THM3_THRESHOLD,
    holds=X7_NONE, tolerance=EIG_TOL, runs=F,
    section="Theorem 3's own conditions on the example (C3a)",
)
UB_DEFINED = [bool(UB_INFO[i]["defined"]) for i in range(N)]
frac_ub_err = [float(np.mean(ERR2[:, 1:, i] <= UB[None, 1:, i])) if UB_DEFINED[i] else None
               for i in range(N)]
frac_ub_mse = [float(np.mean(mse(out_corr)[1:, i] <= UB[1:, i])) if UB_DEFINED[i] else None
               for i in range(N)]
C3B_PREMISE = bool(ASSUMPTION1_HOLDS and C3A_HOLDS)
C3B_HOLDS = bool(all(UB_DEFINED) and all(f == 1.0 for f in frac_ub_err + frac_ub_mse)) if C3B_PREMISE else None
claims["C3b"] = results.claim(
    paper="Fig. 8: ||e_i(k|k)||^2 stays below UB_i(k), which confirms Theorem 3",
    source="Section IV, Fig. 8, (56)",
    check="DATA-DRIVEN envelope (consistent Lemma 3; phi_*, phi^*, Lambda, E||x||^2 read off the "
    "same runs, since Theorem 3's conditions fail, C3a): fraction of (run, k) with "
    "||e_i(k|k)||^2 <= UB_i(k) and of k with MSE_i(k) <= UB_i(k), per target where the recipe is "
    "defined (c0 > 1; None otherwise). holds if all are 1. The envelope reaches 1e13-1e17 at the "
    "default point (UB_T / max MSE reported), so the inequality is vacuous; the premise is C3a",
    measured={"fraction_err": frac_ub_err, "fraction_mse": frac_ub_mse,
              "UB_T": [float(UB[-1, i]) if UB_DEFINED[i] else None for i in range(N)],
              "UB_T_over_max_mse": [float(UB_RATIO[i]) if UB_DEFINED[i] else None for i in range(N)],
              "max_mse": mse(out_corr)[1:].max(axis=0),
              "phi_lower": [UB_INFO[i]["phi_lower"] for i in range(N)],
              "phi_upper": [UB_INFO[i]["phi_upper"] for i in range(N)],
              "rho": [UB_INFO[i]["rho"] for i in range(N)]},
    threshold=1.0, holds=C3B_HOLDS, not_checked=None if C3B_HOLDS is not None else
    "not decided: its premise (C3a, X7) fails; the fractions are recorded",
    premise=("Theorem 3's premise holds on the example: Assumption 1 (C3a) and, for every target, "
             "conditions (a)-(c) at some weights (X7)", C3B_PREMISE),
    tolerance=EIG_TOL, runs=F,
    section="Fig. 8 — $\\|e_i(k|k)\\|^2$ and $UB_i(k)$ (Theorem 3, made consistent)",
)
set_sizes = np.array([len(set(row.tolist())) for row in SETS])
per_window = lcm(m, n_y) // n_y
claims["C4"] = results.claim(
    paper="Remark 1: every sensor gets equal access within each U steps; |eps(k)| = m, no "
    "channel reused",
    source="Remark 1, (2)",
    check=f"BY CONSTRUCTION (an arithmetic property of the index formula (2), evaluated on our "
    f"implementation of it: shown, not evidence): counts of each sensor in every window of U = {U} "
    f"steps equal lcm(m, n_y)/n_y = {per_window}; distinct sensors per step = m (exact)",
    measured={"window_counts_min": window_counts.min(axis=0),
              "window_counts_max": window_counts.max(axis=0), "U": U,
              "distinct_per_step_min": set_sizes.min(), "distinct_per_step_max": set_sizes.max()},
    threshold={"per_window": per_window, "m": m},
    holds=bool(np.all(window_counts == per_window) and np.all(set_sizes == m)),
    basis="by-construction", section="RRL-MAP (2)–(5)",
)
C5_LEVEL = 0.9999
attacks = (DRAWS["psi"] == 0).sum(axis=(0, 1))
c5_ci = np.array([montecarlo.wilson_interval(int(a), F * T, level=C5_LEVEL) for a in attacks])
c5_freq, c5_expected = attacks / (F * T), 1 - PSI
c5_inside = (c5_ci[:, 0] - 1e-12 <= c5_expected) & (c5_expected <= c5_ci[:, 1] + 1e-12)
c5_worst = int(np.argmax(np.abs(c5_freq - c5_expected) / np.maximum(c5_ci[:, 1] - c5_ci[:, 0], 1e-12)))
claims["C5"] = results.claim(
    paper="(6): Pr{psi_i(k) = 0} = 1 - psi_check_i (attack probabilities 0.3 / 0.5 / 0.7)",
    source="Section II-B, (6); Section IV",
    check=f"BY CONSTRUCTION (our draws are Bernoulli with these probabilities: a check of our "
    f"sampling, not evidence about the paper): empirical attack frequency over F x T = {F * T} "
    "draws per target; holds if 1 - psi_check_i "
    f"lies in the {C5_LEVEL:.2%} Wilson interval for every target (family false-alarm rate "
    "< 0.03 %). Headline: the target farthest from its expected value, relative to its interval",
    measured={"worst_frequency": c5_freq[c5_worst], "worst_target": c5_worst + 1,
              "frequency": c5_freq, "interval_low": c5_ci[:, 0], "interval_high": c5_ci[:, 1]},
    interval=results.interval(*c5_ci[c5_worst], level=C5_LEVEL, method="wilson"),
    threshold={"expected": c5_expected}, holds=bool(np.all(c5_inside)), key="worst_frequency",
    tolerance=MC_TOL, runs=F * T, basis="by-construction",
    section="Bernoulli replacement attack (6)",
)
claims["X8"] = results.claim(
    paper="(ours, sanity) the bound recursion (17)-(18)-(28) reduces to the Kalman filter without "
    "attack and coupling",
    source="ours (consistency of Theorems 1-2 with the Kalman filter)",
    check="BY CONSTRUCTION (our corrected recursion against the Riccati recursion it reduces to "
    "algebraically): psi = 1, K_i empty, lambda = 0, corrected coefficients: max relative |S - P_Riccati| "
    "and max |x_hat - x_hat_KF| <= 1e-10 (exact)",
    measured={"S": kal_dev_P, "xhat": kal_dev_x}, threshold=1e-10,
    holds=bool(kal_dev_P <= 1e-10 and kal_dev_x <= 1e-10), basis="by-construction",
    section="Kalman limit (X8)",
)
C7_DESIGNS = ("our corrected design", "printed-coefficient design")
C7_MAX = float(C7_TABLE[C7_DESIGNS[0]].max())
# each design's error relative to the open-loop prediction's (L = 0), per target: how much the gain buys
C7_VS_OPEN = {d: C7_TABLE[d] / C7_TABLE["open-loop prediction"] for d in C7_DESIGNS}
print("C7: relative RMS error / open-loop prediction's:", {d: np.round(v, 3).tolist() for d, v in C7_VS_OPEN.items()})
claims["C7"] = results.claim(
    paper="Figs. 2-4: each target's estimated positions and velocities well match its real "
    "positions and velocities",
    source="Section IV, Figs. 2-4",
    check="NOT CHECKED (since session 13): the paper gives no scale for 'well match' (nor for Remark 5's "
    "'minor estimation errors even under the influence of deception attack'), so any threshold would be "
    "ours and the outcome our judgement (until session 12 C7 failed against our 0.1). RECORDED, EXACT: "
    "relative RMS error rho_i(T) = sqrt(sum_k E||e_i(k|k)||^2 / sum_k E||x_i(k)||^2) of (8) with the gain "
    "(28), exact E{xhat xhat^T}, weights in use, for OUR CORRECTED DESIGN (headline max_i rho_i(T)) and "
    "the PRINTED-COEFFICIENT DESIGN (max_relative_rms_printed), each with ratio_to_open_loop, its rho_i "
    "over the open-loop prediction's (L = 0). Rows reported: our corrected design in Monte Carlo with "
    "the xhat_moment surrogate (95 % t-interval), the per-step optimal gain for (8), the debiased "
    "innovation with optimal gain, an oracle Kalman filter dropping attacked packets (95 % interval over "
    "the psi draws), no attack, the additive reading of (6), the open-loop prediction",
    measured={"max_relative_rms": C7_MAX, "max_relative_rms_printed": float(C7_TABLE[C7_DESIGNS[1]].max()),
              "relative_rms": C7_TABLE, "ratio_to_open_loop": C7_VS_OPEN,
              "monte_carlo_corrected_design": C7_MC,
              "monte_carlo_corrected_design_interval":
                  np.stack(C7_INTERVALS["our corrected design, Monte Carlo"]),
              "oracle_interval": np.stack(C7_INTERVALS["oracle Kalman filter"]),
              "horizon": T, "weight_rule": weight_rule},
    threshold=None, holds=None, key="max_relative_rms", tolerance=MC_TOL, decides=True,
    not_checked="the paper gives no scale for 'well match': the relative RMS errors are recorded, not "
    "judged against a threshold of ours",
    section="Tracking (Figs. 2–4, C7): the paper's design against its baselines",
)
claims["X1"] = results.claim(
    paper="(ours) the innovation y - psi_check Phi C H x_hat(k|k-1) removes the attack bias",
    source="ours",
    check="EXACT, target 1, gains (28) of the design in use: relative reduction of the "
    "time-averaged E||e||^2 >= 0.25 and |E e_Xp(T)| smaller than with (8)",
    measured={"mse_reduction_target1": X1_REDUCTION,
              "mean_err_Xp_T_paper": EX["mean_e"][-1, :, 0],
              "mean_err_Xp_T_debiased": EX_DEBIASED["mean_e"][-1, :, 0]},
    threshold=0.25, key="mse_reduction_target1",
    holds=bool(X1_REDUCTION >= 0.25
               and abs(EX_DEBIASED["mean_e"][-1, 0, 0]) < abs(EX["mean_e"][-1, 0, 0])),
    section="The smallest fix: a debiased innovation (ours, X1)",
)
claims["X2"] = results.claim(
    paper="(ours) the vectorised Monte Carlo pass computes the same runs as a loop over runs",
    source="ours",
    check="max |x_hat, S (vectorised) - x_hat, S (simulate called run by run)| / max(1, |x_hat, S|) "
    "over 5 runs, xhat_moment run, <= 1e-9",
    measured=loop_dev, threshold=1e-9, holds=bool(loop_dev <= 1e-9),
    tolerance=results.ROUNDING_RESIDUAL,
    section="The numerical example: Monte Carlo runs and exact expectations",
)
x3_t = (x3_runs_avg.mean(axis=0) - x3_exact) / (x3_runs_avg.std(axis=0, ddof=1) / np.sqrt(x3_runs))
x3_worst = int(np.argmax(np.abs(x3_t)))
claims["X3"] = results.claim(
    paper="(ours) the exact second-moment recursion gives E||e_i||^2 of the estimator it describes",
    source="ours",
    check=f"Monte Carlo runs of the exact design's deterministic gains ({x3_runs} fresh runs): for "
    "every "
    f"target the exact time-averaged E||e_i||^2 lies in the {X3_LEVEL:.4%} t-interval (Bonferroni "
    "over targets, family level 99.9 %) of the Monte Carlo time average. Headline: relative "
    "difference (MC - exact)/exact of the target with the largest |t|, with its interval",
    measured={"worst_relative_difference": (x3_runs_avg.mean(axis=0)[x3_worst] - x3_exact[x3_worst])
              / x3_exact[x3_worst], "t_statistic": x3_t, "exact": x3_exact,
              "monte_carlo": x3_runs_avg.mean(axis=0)},
    interval=results.interval((x3_lo[x3_worst] - x3_exact[x3_worst]) / x3_exact[x3_worst],
                              (x3_hi[x3_worst] - x3_exact[x3_worst]) / x3_exact[x3_worst],
                              level=X3_LEVEL, method="t over runs, relative to the exact value"),
    threshold=0.0, holds=bool(np.all(x3_inside)), key="worst_relative_difference",
    tolerance=MC_TOL, runs=x3_runs, section="The exact recursion agrees with Monte Carlo (X3)",
)
X4_OPT = C7_TABLE["per-step optimal gain for (8)"]
X4_ORACLE_HI = C7_INTERVALS["oracle Kalman filter"][1]
claims["X4"] = results.claim(
    paper="(ours) the tracking failure of (8) under the replacement attack is intrinsic: no gain "
    "choice fixes it, knowing which packets were attacked does",
    source="ours",
    check="EXACT: the per-step optimal gain for (8) still has max_i rho_i(T) > 0.1, while the "
    "upper end of the oracle Kalman filter's 95 % interval of rho_i(T) is <= 0.1 for every target",
    measured={"max_relative_rms_optimal_gain": float(X4_OPT.max()),
              "relative_rms_optimal_gain": X4_OPT, "oracle_upper": X4_ORACLE_HI,
              "relative_rms_debiased_optimal": C7_TABLE["debiased innovation, optimal gain"]},
    threshold=0.1, holds=bool(X4_OPT.max() > 0.1 and X4_ORACLE_HI.max() <= 0.1),
    key="max_relative_rms_optimal_gain", tolerance=MC_TOL, runs=F,
    section="Tracking (Figs. 2–4, C7): the paper's design against its baselines",
)
written = results.write_claims(results_path, claims, robustness="figures/li2025/robustness.json")
merged = json.loads(written.read_text())  # the interval over independent draws replaces the records'
for cid, entry in merged.items():
    if cid in DRAW_SUMMARY and "robustness" in entry:
        entry["robustness"]["interval_records"] = entry["robustness"]["interval"]
        entry["robustness"].update(DRAW_SUMMARY[cid])
        rob = entry["robustness"]  # robustness.json keeps the package sweep's region text
        for outcome, words in (("fails-premise", "premise fails at all {} points: decided at none"),
                               ("not-checked", "not checked at any of the {} points")):
            if rob["outcomes"].get(outcome) == rob["points"]:
                rob["region"] = words.format(rob["points"])
    d = entry.get("robustness", {})
    print(f"{cid:>4}: {entry['verdict']}" + (f" over the space (holds at every decided cell of "
          f"{d['independent_holding']} of {d['independent']} independent draws)" if d.get("independent")
          else "") + f"; at this run: {results.point_verdict(entry)}")
written = results.write_claims(results_path, merged)

# %% [markdown]
# ## ReScience verdict
#
# The verdict follows the one written rule of `secest.repro.results.rescience_verdict` (the same for
# all five papers): [Re] if every deciding claim holds at the paper's example and over the declared
# space, [¬Re] if none holds at the example, [Re, partial] otherwise. The deciding claims are the
# paper's own main contributions, as its introduction lists them ("The major contributions...") and
# its conclusion repeats them:
#
# * "the RRL-MAP is presented to realize non-collision and efficient transmission" — **C4** (Remark 1's
#   fairness and $m$ distinct channels per step). It is an arithmetic property of the printed index
#   formula (2), true by construction of the check, so it is shown but **does not decide** (a claim true
#   by construction is no evidence);
# * "an upper-bound for each estimation error covariance is derived" — **C1b**, the bound *as printed*
#   (Theorems 1–2 "for given positive scalars", which Remark 4 says "can be changed arbitrarily"). Our
#   corrected bound (X5) holds, but it is our statement, not the paper's, so it does not decide; Fig. 7
#   as printed (C1c) is the simulation's illustration of this contribution and is recorded, not
#   deciding (C1b already decides the bound, exactly);
# * "then an algorithm for determining the estimators' gains is proposed" — **C8**, Theorem 2 (for given
#   positive weights the gain (28) minimises the trace of the bound), which Algorithm 1 implements. It is
#   judged like C1b, as stated "for given positive scalars": at our grid's weights it holds by
#   construction (C8b), so the measured content is a declared weight set the grid discards;
# * "followed by the effectiveness analysis of the algorithm" / "validated by showing that the
#   corresponding estimation errors are exponentially bounded in the mean square" — **C3**, Theorem 3's
#   conclusion. Its premise cannot hold on the example (C3a, fails-premise, shown, not deciding), so by
#   the package convention it is decided on a declared instance of ours satisfying Assumption 1 and the
#   theorem's conditions (the section "Theorem 3 on a declared instance of ours"), where it
#   fails its premise ($L=0$ meets the envelope at every eligible case). C3b (Fig. 8) rests on C3a;
# * "the performance of the developed state estimation method has been further demonstrated" by the
#   simulation — **C7**, the tracking of Figs. 2–4: not-checked, since "well match" has no scale and a
#   threshold of ours would decide by our judgement; a contribution that cannot be measured decides as
#   not-checked (the rule's docstring).
#
# C2 (Remark 2, a side remark), C4 and C5 (true by construction) and the X claims (ours) do not decide.
# Computed from the claims just written:

# %%
VERDICT = results.rescience_verdict(json.loads(written.read_text()))
print(VERDICT["line"])

# %% [markdown]
# The rule gives what the line above prints: at the default point C8 fails (at the declared weights
# $(0.1, 1, 9.5, 10, 0.01)$, printed $\kappa_x<0$, $\Pi$ of (28) is indefinite at 145 of 300 pairs; at our grid's
# weights it holds by construction, C8b); C1b fails (an exact counterexample from $k=2$ at the weights Remark
# 4's minimisation picks; at the $\alpha_2>\alpha_3$ weights it bounds, 0.9997 / 0.91 / 0.59); C3 fails its
# premise ($L=0$ meets the envelope at every eligible case: 0.0861239 against 0.0861238); C7 is not checked. No deciding claim holds: [¬Re]. On our instance (52)'s $\Lambda$ is exceeded
# and (56) as printed fails in most eligible cases. The paper's method with the bound re-derived from its own
# proof gives a valid bound (X5) and (28) minimises it for every positive weight set — our correction, which
# does not raise the verdict.

# %% [markdown]
# ## Deviations from the paper
#
# | item | paper | here | why |
# |---|---|---|---|
# | $\kappa_x$ of (18), Theorems 2–3; (21) | $\check\psi+\alpha_3^{-1}+\alpha_4-1$, from (21)'s $(\check\psi-1)L\Gamma\mathbb E\{xx^T\}\Gamma^TL^T$ | $(1-\check\psi)(1+\alpha_3^{-1}+\alpha_4)$ (`coef="paper"` keeps the printed coefficients) | first printed error: $\mathbb E(\psi-1)^2=1-\check\psi$; $\kappa_x<0$ makes $\Pi$ indefinite (C8) |
# | $c_0$ of (18), Theorems 2–3 | $1-(\alpha_3-\alpha_2)(1-\check\psi)$ ((18): $(1-(\alpha_3-\alpha_2))(1-\check\psi)$) | $1+(\alpha_2+\alpha_3)(1-\check\psi)$ | second printed error: (21)'s $e$–$x$ bracket is correctly signed and (26) adds $+\alpha_3(1-\check\psi)$; the $-\alpha_3$ enters when (18) is assembled, and alone breaks the bound (C1b's `one_printed_coefficient`) |
# | (17), (20) | $(\sum_jBH)\mathfrak S_j(\sum_jH^TB^T)$; $e_je_l^T$ cross terms omitted; stray $H^T$ factors | $\|K_i\|\sum_jB_{i,j}H\mathfrak S_jH^TB_{i,j}^T$; the plain sum as the other reading (`coupling_factor`, swept) | the printed form is undefined for $\|K_3\|=2$ and not a proven bound |
# | (29), Lemma 2 | missing minus sign; garbled first identity | (28) used as printed, solved on the scheduled rows | (28) is the stationary point; $\Pi$ has rank $m$ |
# | $\mathbb E\{\hat x\hat x^T\}$ in (18), (28) | not specified | exact (second-moment recursion) for the certificates and C7; the run's own $\hat x\hat x^T$ or the ensemble mean in the Monte Carlo runs (`xhat_moment`, swept) | the exact one is the theorem's own quantity (deterministic gain); the Monte Carlo surrogates make the gain data-dependent, so Fig. 7 there is a measurement (C1c) |
# | Lemma 3, (56), Fig. 8 text | rate and additive constant swapped; sum from $l=1$ | consistent form, sum from $l=0$ | re-derived from the iteration |
# | Assumption 1 on the example | $e_*,b_*>0$ assumed | $E_iE_i^T$ has rank 1, $\sum_jB\sum_jB^T$ rank ≤ 2: no positive $e_*,b_*$ (C3a fails its premise for every weight set) | the example's $E_i$ is $4\times1$ and $B_{i,j}$ has two zero rows |
# | Theorem 3, where it is decided | the example (Fig. 8) | a declared two-subsystem instance of ours meeting Assumption 1 and conditions (a)–(c) at searched weights (C3) | the example cannot meet the premise (C3a); the package rule decides a general result on an instance of ours |
# | Assumption 1 for $K_i=\emptyset$ | $b_*>0$ with $b_*^2I\le\sum_{j\in K_i}B_{i,j}\sum_jB_{i,j}^T$ | $b_*=b^*=0$ for the empty sum (subsystem 1 of our instance) | the first subsystem of every sequential system has $K_1=\emptyset$: read literally, no DSS meets Assumption 1 |
# | Theorem 2's trajectory (C8) | Algorithm 1 "for given positive scalars" | each weight set judged along Algorithm 1 run at it (its $\lambda$ enters (17)); the previous judgement on the Remark-4 trajectory is reported | the theorem is a statement about Algorithm 1 at the given weights |
# | Theorem 3 conditions | $1+\alpha_5+\alpha_6\le c_0$, $\eta_*\ge\phi_*$, $\eta^*\le\phi^*$ assumed | evaluated with $e_*=b_*=0$ (X7): $\eta^*\le\phi^*$ fails for every $\phi^*\ge1$ on a $10^{0}$–$10^{12}$ grid; (36) needs $L\Phi CH$ of full rank, its rank is $m=2$ | the theorem's premise is not met on the example; C3b is recorded as fails-premise |
# | Theorem 3 constants | Assumption-1 constants, $\pi_*$, (47), (48), (50) | data-driven recipe (Fig. 8 section); vacuous envelope $10^{13}$–$10^{17}$ | literal constants are 0 / undefined on the example; (50) sign; (47), (48) use the wrong-side constants |
# | Assumption 1 | $h_*^2\le H_\epsilon H_\epsilon^T$ | $h_*^2I\le H_\epsilon H_\epsilon^T$, $h_*=\epsilon$ | typo |
# | weights $\lambda,\alpha_1..\alpha_4$ | Remark 4: "can be" chosen by minimising the bound; no values | two readings (`weight_rule`, swept): our grid's minimiser (gains ≈ 0 for targets 2, 3) or an interior grid point | see the Remark-4 section |
# | horizon, seeds, attack signal, $\sigma$ redraw, $\mathcal V$ as $0.03I$ | not given | declared spaces (horizon 30–200, seeds, two attack forms at the energy bound) | provenance table; verdicts over the space |
# | ZOH variant (Fig. 6) | not specified | hold buffer + gain with $\Phi=I$ | the zero-input gain applied to held data is the zero-input estimator |
# | Figs. 2–4 tracking | "well match" | not checked (C7): no scale; $\rho_i$ of our corrected and of the printed-coefficient design recorded; (8) cannot track under the replacement attack (X4); the additive reading of (6) would (sensitivity row) | exact expectations, no seed |
# | Fig. 6 / C2 | ZOH "did not lead to the improvement" | judged only on targets with a non-negligible gain (target 1 with the grid weights); undetermined over the space: it fails at two reading cells of one draw (counts in the robustness table) | gains ≈ 0 make a ratio ≈ 1 uninformative |
# | Fig. 1 | schematic of a 9-subsystem DSS | described, not regenerated | not a result |
# | figures | single trajectories, curves only | first Monte Carlo run; attack values in the units of the measurements they replace; log axes from $k=1$ ($\mathrm{MSE}(1)\approx10^{-4}$ because $E_i(0)=0$) | |

# %%
manifest_path = run.finish(extra={"weights": WEIGHTS})
print("run manifest:", manifest_path.relative_to(results.repo_root()))
