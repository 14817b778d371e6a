# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (secest)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # ding2020 — Distributed secure filtering over Gilbert–Elliott channels with a χ² detector
#
# D. Ding, Z. Wang, Q.-L. Han and X.-M. Zhang, "Recursive Secure Filtering over
# Gilbert–Elliott Channels in Sensor Networks: The Distributed Case", IEEE, 2020 (journal
# name and volume are not in our copy of the text).
#
# **Summary.** One linear target (1) is watched by $m$ sensor nodes, each taking a scalar
# measurement (2). Every node runs a Kalman-like filter whose prediction adds a weak consensus
# pull (coupling $\kappa$) towards its neighbours' latest estimates. Those estimates travel over
# **one shared** bursty channel, a two-state Gilbert–Elliott Markov chain $\delta_k$ with failure
# rate $p$ and recovery rate $q$: when it is down, nobody hears anybody. Each node screens its
# innovation with a χ² test (25) and skips the update when the test fails, so injected false
# data is discarded. The true covariance is not computable locally, so the test is normalised by
# a recursively propagated **lower** bound $\Gamma$ ((17)–(18)), and the gain (32) minimises the
# trace of a recursively propagated **upper** bound $\Pi$ ((26), (35)). Both recursions need only
# the node's own and its neighbours' quantities (Remark 4). Theorem 4 gives a sufficient
# condition on $(p, q, \kappa)$ for the mean upper bound to stay bounded. Section V tracks a
# position/velocity/acceleration target with 20 nodes.
#
# **Verdict: [Re, partial]** (computed in the verdict section; deciding claims listed there). Two of the
# paper's three contributions hold vacuously or by construction wherever they can be evaluated here, and so
# decide as not checked by the project's one rule ("a contribution that cannot be measured here decides as
# not-checked", the same for all five papers): Theorem 4's boundedness (C8), because the example cannot meet
# its condition (X7), and wherever the condition holds (at any threshold whose false-alarm probability is at
# most $1/(1+2m)$, the whole declared space) the conclusion follows from it alone, without the filter (C8c);
# and the cost independent of the network size (C12), which holds by construction of the per-node step (C7)
# and is timed only by `make bench`. The verdict is therefore partial before anything is measured.
#
# At the default point (paper mode, 300 Monte Carlo runs) the detector rejects every attacked sample (C1),
# the window RMSE rises with detection (C3) and more without it (C4), the bounds hold against the exact
# covariance (C5), and the constant-gain filter is several times worse under attack (C9); the gain (32)
# minimises the bound by the algebra of (31)–(32) (C11). "No obvious effect" between Figs. 4(a) and 4(b) (C2a)
# is decided over the Monte Carlo runs, not on the figure's one run: by our per-run rule (no plotted curve moved
# by the attack further than its own error without attack) it fails — only about a third of the runs meet it.
# Our default run meets it; the paper's figure, read as its median run, is our reading (we have no data for
# it). The paper does not show the χ²
# **lockout**: a share of the runs ends with the attacked sensor rejecting its last 10 measurements (X1), and
# many of the runs that fail C2a fail through it. The κ = 0 control, where $\Gamma$ does not collapse, locks out
# too (X5); that (17)–(18), which do not let $\Gamma$ grow while updates are skipped, are the cause is our
# reading of the mechanism. Without any attack a smaller valid $\Gamma_0$ can lock nodes out as well (X3). The
# numbers of this run are in the summary after the claims table, generated from the claims.

# %% tags=["parameters"]
mode = "paper"  # "paper": full Monte Carlo and long runs; "fast": fewer runs for the tests (ours)
seed = 2020  # master seed of SeedSequence(seed).spawn(6), see the provenance table (MISSING)
topology_seed = 2020  # seed of secest.core.graphs.random_geometric_graph, stand-in of Fig. 1 (MISSING)
leak_topology_seeds = [2020, 2021, 2022, 2023, 2024, 2025, 2026, 2027, 2028, 2029]  # X6 sample (ours)
m = 20  # number of sensor nodes (PAPER, Sec. V)
radius = 0.35  # connection radius of the random geometric graph, unit square (MISSING)
T = 0.05  # sampling period [s] (PAPER)
horizon = 150  # k in [0, horizon] (PAPER)
p = 0.1  # failure rate of the Gilbert-Elliott chain (PAPER)
q = 0.92  # recovery rate (PAPER)
kappa = 0.004  # coupling strength (PAPER)
threshold = 25.0  # chi-square threshold of (25) (PAPER)
inspection = True  # apply the chi-square test (25) in the proposed filter; False: accept every y (ours)
attacks = [[4, 90, 95, 15.0], [12, 50, 55, 15.0]]  # [node (1-based), k_first, k_last, value] (PAPER)
plot_nodes = [4, 12, 20]  # nodes shown in Figs. 3-6 (PAPER)
delta0 = 1  # channel state delta_0 (MISSING)
sigma0 = 1.0  # x_0 and each x_hat_{i,0} ~ N(0, sigma0 I), independent (MISSING)
pi0_scale = 2.0  # Pi_0 is pi0_scale * sigma0 * I; 2 gives the exact initial covariance P_0 (MISSING)
gamma0_scale = 2.0  # Gamma_0 is gamma0_scale * sigma0 * I; valid from 0 up to P_0 (MISSING)
tol = 1e-10  # relative tolerance of every Loewner-order test (ours)
strict = False  # strict reading of "Y < X" in the min operation (RECONSTRUCTED; non-strict, E6)
nu = 0.0  # Assumption 2 probability bound used in Theorem 4 (MISSING; E8)
thm4_a_scale = 0.5  # C8c: Theorem 4's instance, the example's plant with A scaled by this factor (ours)
gains_low = [0.4177, 0.5799, 0.4029]  # constant gain, nodes 1-7 (PAPER, comparison filter)
gains_high = [0.2883, 0.6150, 0.4457]  # constant gain, nodes 8-20 (PAPER)
cmp_form = "corrector"  # structure of the comparison filter: "corrector" or "predictor" (MISSING)
mc_runs = 300  # Monte Carlo runs (fast mode: at most 100) (ours)
long_steps = 2000  # steps of the long run for Pi's boundedness (fast mode: at most 600) (ours)
recovery_steps = 400  # locked Monte Carlo runs are continued to this step (ours)
chain_steps = 100000  # length of the chain for estimating p, q (ours)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/ding2020"
results_path = "figures/ding2020/claims.json"

# %%
import csv
import json
import sys
from collections import Counter

import matplotlib.pyplot as plt
import networkx as nx
import numpy as np
from IPython.display import Markdown, display

from secest.core import channels, detectors, graphs, montecarlo
from secest.core.validation import ValidationError
from secest.methods import ding2020
from secest.repro import plotting, results, spaces
from secest.repro.literate import show_source

print(results.environment_summary())

run = results.Run("ding2020", globals())
LOCK_STEPS = 10  # a node is locked out at step k if it rejected each of its last 10 measurements (ours)
CMP_FORMS = ("corrector", "predictor")  # the two readings of the comparison filter's structure


def check_parameters() -> None:
    """Cross-parameter checks the declared domains cannot express (one line naming the parameter)."""
    if not attacks:
        raise ValidationError("parameter attacks must name at least one attacked sensor")
    for entry in attacks:
        if len(entry) != 4 or not all(isinstance(v, int) for v in entry[:3]):
            raise ValidationError(f"parameter attacks: each entry is [node, k_first, k_last, value], found {entry!r}")
        node, k_first, k_last, _ = entry
        if not 1 <= node <= m:
            raise ValidationError(f"parameter attacks: node {node} is not one of the nodes 1..{m}")
        if not 1 <= k_first <= k_last <= horizon - LOCK_STEPS:
            raise ValidationError(
                f"parameter attacks: window [{k_first}, {k_last}] must lie in [1, horizon - {LOCK_STEPS}] = "
                f"[1, {horizon - LOCK_STEPS}], so that a lockout after it can be measured")
    if len({entry[0] for entry in attacks}) != len(attacks):
        raise ValidationError("parameter attacks: one window per attacked node")
    if not plot_nodes or not all(1 <= node <= m for node in plot_nodes):
        raise ValidationError(f"parameter plot_nodes must name nodes in 1..{m}, found {plot_nodes!r}")
    if gamma0_scale > pi0_scale:
        raise ValidationError(
            f"parameter gamma0_scale ({gamma0_scale:g}) must not exceed pi0_scale ({pi0_scale:g}): Gamma_0 <= Pi_0")
    if recovery_steps <= horizon:
        raise ValidationError(f"parameter recovery_steps ({recovery_steps}) must exceed horizon ({horizon})")
    if not leak_topology_seeds or min(leak_topology_seeds) < 0:
        raise ValidationError("parameter leak_topology_seeds must list at least one seed >= 0")
    if p + q == 0:
        raise ValidationError("parameters p and q: p + q must be positive (the chain must move)")
    if kappa >= 1:
        raise ValidationError(f"parameter kappa must be < 1 ((7) takes kappa in (0, 1)), found {kappa!r}")


check_parameters()
R_MC = mc_runs if mode == "paper" else min(mc_runs, 100)
L_LONG = long_steps if mode == "paper" else min(long_steps, 600)
N = int(horizon)
FIG_DIR = results.resolve(fig_dir)
rng_channel, rng_world, rng_mc, rng_chain, rng_long, rng_rec = montecarlo.spawn_rngs(seed, 6)
plotting.setup(enabled=figures)
PLOT = [i - 1 for i in plot_nodes]  # 0-based indices of the plotted nodes (P1)


def save(fig, name: str, data: dict | None = None, tolerance=None) -> None:
    """Save fig (and its data, with its reproduction tolerance) under FIG_DIR and show it inline."""
    plotting.save_figure(fig, FIG_DIR, name, data=data, tolerance=tolerance)


MC_TOL = results.Tolerance(
    rtol=0.02, atol=0.01,
    reason="Monte Carlo decisions: a chi-square statistic within round-off of the threshold can flip on "
    "another BLAS, moving a fraction by 1/runs and a run's RMSE")
RUN_TOL = results.Tolerance(
    rtol=1e-6, atol=1e-9,
    reason="single runs downstream of chi-square accept/reject decisions: round-off of the 150-step "
    "recursions, unless a statistic lies within round-off of the threshold")

# %% [markdown]
# ## Parameter provenance
#
# Every parameter of the notebook, its admissible domain, its tag and, for every value the paper
# does not pin down, the declared space the robustness sweep (`make robustness`) samples, with the
# reason it was chosen (`notebooks/ding2020.toml`, committed before the sweep was run):

# %%
display(Markdown(spaces.provenance_markdown("ding2020")))

# %% [markdown]
# The model constants and implementation choices that are not parameters:
#
# | item | value | tag | source / reason |
# |---|---|---|---|
# | topology | `random_geometric_graph(m, radius, seed=topology_seed)`, unit square, undirected | MISSING | Fig. 1 is not in our copy; "randomly deployed". The default seed 2020 is the first candidate, the master seed the reproduction brief proposed before any run. An earlier version switched to seed 2021 after seeing the outcome; that was dropped. The draw is now an axis of the declared space |
# | weights | $h_{ij}=1/\lvert\mathcal N_i\rvert$, $h_{ii}=0$ | PAPER | Sec. V; $\mathcal N_i$ excludes $i$ |
# | $A$ | constant-acceleration model with period $T$ | PAPER | Sec. V |
# | $B$, $D$ | $0.2I_3$, $0.05$ | PAPER | Sec. V; $w_k\sim\mathcal N(0,I_3)$, $v_{i,k}\sim\mathcal N(0,1)$ |
# | $C_i$ | $[4.5, -0.8, -0.5]$ for nodes 1–7, $[4.0, -0.8, 1.0]$ for nodes 8–20 | PAPER | "$i<8$" is 1-based |
# | attack | added to $y_{i,k}$ only, windows inclusive | PAPER | Sec. V, "attack strength 15"; "normal = attacked minus 15" |
# | $x_0$, $\hat x_{i,0}^+$ | i.i.d. $\mathcal N(0, \sigma_0 I_3)$, independent | MISSING | "randomly produced"; zero mean keeps (9)–(10); non-zero estimates make (4) exact at $k=0$. Then $P_0=\mathrm{cov}(x_0-\hat x_{i,0})=2\sigma_0I$ |
# | $\Pi_0^+$, $\Gamma_0^+$ | `pi0_scale`$\cdot\sigma_0 I$, `gamma0_scale`$\cdot\sigma_0 I$ | MISSING | two separate parameters; both bounds hold at $k=0$ iff $\Gamma_0\preceq P_0\preceq\Pi_0$, i.e. `gamma0_scale` ≤ 2 ≤ `pi0_scale` (the premise of C5) |
# | first update | at $k=1$ | MISSING | (7) updates at $k+1$ |
# | seeds | `SeedSequence(seed).spawn(6)`: channel, world, Monte Carlo, long chain, long run, recovery | MISSING | |
# | common random numbers | Cases A, B, no inspection, the κ = 0 control and the comparison filter share $\delta$, $x_0$, $\hat x_0$, $w$, $v$ | PAPER (comparison) / ours | the paper says so for the comparison |
# | delivery of $\Pi^+_{j,k}$ | in the same packet as $\hat x^+_{j,k}$, lost with it | MISSING | (26) needs the neighbours' bounds only when $\delta^r=1$ |
# | lockout | node $i$ is *locked out* at $k$ if its test rejected each of $y_{i,k-9},\dots,y_{i,k}$ (10 steps) | ours | a definition for the lockout claims X1, X3, X5 |
# | κ = 0 control | $\kappa=0$ and $\Pi_0=\Gamma_0=P_0=2\sigma_0I$, everything else as in the run | ours | X4, X5 |

# %% [markdown]
# ## Setup
#
# ### Plant (1) and sensors (2)
#
# $x_{k+1}=Ax_k+Bw_k$ and $y_{i,k}=C_ix_k+Dv_{i,k}+n_{i,k}$, where $n_{i,k}$ is the injected
# data of the attack model below (5). Each node measures one scalar ($n_y=1$). The example's
# matrices (and the comparison filter's printed gains, split between nodes 1–7 and 8–20 like
# $C_i$; "$i<8$" is 1-based, P1) come from `ding2020.example`:

# %%
show_source(ding2020.example, after="    A = np.array")

# %%
example = ding2020.example(m, T, gains_low, gains_high)
A, B, D, C_rows, K_const = example.A, example.B, example.D, example.C, example.gains
BBt, DDt = B @ B.T, D @ D.T
C = C_rows[:, None, :]  # (m, ny=1, n)
n_x = A.shape[0]
attack = np.zeros((N + 1, m))
for node, k_first, k_last, value in attacks:
    attack[k_first : k_last + 1, node - 1] += value
windows = {node: np.arange(k_first, k_last + 1) for node, k_first, k_last, _ in attacks}
ATT = [node - 1 for node in windows]  # 0-based indices of the attacked nodes
P0_exact = 2.0 * sigma0 * np.eye(n_x)  # cov(x_0 - x_hat_{i,0})
sigma_fa = detectors.chi2_false_alarm(1, threshold)
print(f"false-alarm probability of threshold {threshold:g}: sigma = {sigma_fa:.4g}")
print("every (A, C_i) observable:", all(np.linalg.matrix_rank(
    np.vstack([c @ np.linalg.matrix_power(A, j) for j in range(3)])) == 3 for c in C_rows))

# %% [markdown]
# ### Network (Fig. 1) and weights
#
# Edge $(i,j)\in\mathcal E$ means node $i$ receives from $j$; $\mathcal N_i=\{j:(i,j)\in\mathcal E\}$
# excludes $i$. $H=[h_{ij}]$ is row-stochastic with $h_{ij}=1/\lvert\mathcal N_i\rvert$ on the edges.
# The paper's "Laplacian" $\mathcal G=H-\mathrm{diag}(H\mathbf 1)=H-I$ has the opposite sign to the
# usual $D-A$. It only enters the proof of Lemma 1, so the code never forms it.
# An undirected connected graph is strongly connected as a digraph, as Section II assumes.

# %%
adj, positions = graphs.random_geometric_graph(m, radius, topology_seed, return_positions=True)
adj = graphs.check_connected(adj)
H = graphs.check_row_stochastic(graphs.row_stochastic_weights(adj, self_weight=False))
degree = adj.sum(axis=1).astype(int)
G_nx = nx.from_numpy_array(adj)
hops = dict(nx.all_pairs_shortest_path_length(G_nx))
N_bar = 1 + degree.max()
print(f"degrees: min {degree.min()}, max {degree.max()}, mean {degree.mean():.2f}; N_bar = {N_bar}")
for node in plot_nodes:
    print(f"node {node}: neighbours {[int(j) + 1 for j in np.flatnonzero(adj[node - 1])]}, "
          f"hops to attacked nodes {[hops[node - 1][a] for a in ATT]}")

# %%
fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH * 1.3, plotting.COLUMN_WIDTH * 1.2))
for i, j in zip(*np.nonzero(np.triu(adj)), strict=True):
    ax.plot(*positions[[i, j]].T, color="0.6", lw=0.8, zorder=1)
colors = ["tab:red" if i in ATT else "tab:blue" if i in PLOT else "white" for i in range(m)]
ax.scatter(*positions.T, s=170, c=colors, edgecolors="k", zorder=2)
for i, (px, py) in enumerate(positions):
    ax.annotate(str(i + 1), (px, py), ha="center", va="center", fontsize=7, zorder=3,
                color="white" if colors[i] != "white" else "k")
ax.scatter([], [], s=60, c="tab:red", edgecolors="k",
           label=f"attacked ({', '.join(str(n) for n in windows)})")
shown = [n for n in plot_nodes if n - 1 not in ATT]
if shown:
    ax.scatter([], [], s=60, c="tab:blue", edgecolors="k",
               label=f"plotted, unattacked ({', '.join(map(str, shown))})")
ax.set_xlabel("position in the field, x [side of the unit square]")
ax.set_ylabel("position in the field, y [side of the unit square]")
ax.set_title(f"Fig. 1 (stand-in): random geometric graph, r = {radius:g}, seed {topology_seed}")
ax.set_aspect("equal")
ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
plotting.save_data(FIG_DIR, "fig1_topology_edges",
                   {"i": np.nonzero(np.triu(adj))[0] + 1, "j": np.nonzero(np.triu(adj))[1] + 1})
save(fig, "fig1_topology", data={"node": np.arange(1, m + 1), "pos": positions, "degree": degree})

# %% [markdown]
# ### One shared Gilbert–Elliott chain (Fig. 2)
#
# One Markov chain $\delta_k\in\{0,1\}$ serves every link. Its transition matrix over the states $(0,1)$ is
# $\mathbf P=\begin{bmatrix}1-q & q\\ p & 1-p\end{bmatrix}$, with
# $p=\mathbb P\{\delta_{k+1}=0\mid\delta_k=1\}$ and $q=\mathbb P\{\delta_{k+1}=1\mid\delta_k=0\}$.
# Its stationary probability of $\delta=1$ is $q/(p+q)$. The channel state at $k$ decides
# whether the prediction $k\to k+1$ contains consensus (P2).

# %%
delta = channels.gilbert_elliott(p, q, N + 1, rng_channel, initial=delta0).astype(float)
print("P =", channels.gilbert_elliott_transition(p, q).tolist(),
      f"; stationary P(delta=1) = {channels.gilbert_elliott_stationary(p, q):.5f}")
print(f"delta_k = 1 at {int(delta.sum())} of {N + 1} instants")

fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 1.8))
ax.step(np.arange(N + 1), delta, where="post", color="tab:blue", label=r"$\delta_k$")
for k in np.flatnonzero(delta == 0):
    ax.axvspan(k, k + 1, color="tab:red", alpha=0.25, lw=0)
ax.axvspan(0, 0, color="tab:red", alpha=0.25, label=r"channel down ($\delta_k = 0$)")
ax.set_xlabel("time step k")
ax.set_ylabel(r"channel state $\delta_k$")
ax.set_ylim(-0.1, 1.15)
ax.set_yticks([0, 1])
ax.set_xlim(0, N)
ax.set_title(f"Fig. 2: Gilbert–Elliott channel, p = {p:g}, q = {q:g}")
ax.legend(loc="lower left")
save(fig, "fig2_channel_state", data={"k": np.arange(N + 1), "delta": delta})

# %% [markdown]
# ## Derivation of the filter
#
# ### Received estimates (3) and channel indicator (4)
#
# $\hat x^{r+}_{j,k}=\delta_k\hat x^+_{j,k}$ and
# $\delta^r_{i,k}=\mathbb 1\big[\sum_{j\in\mathcal N_i}\lVert\hat x^{r+}_{j,k}\rVert>0\big]$, which
# equals $\delta_k$ almost surely. We implement (4) literally and assert the equality at every step.
# The bounds $\Pi^+_{j,k}$ a node needs from its neighbours are not covered by the paper. We send them in
# the same packet as $\hat x^+_{j,k}$: they are lost when $\delta_k=0$, and then they are not needed.
#
# ### Filter (7) with the inspected update (34)
#
# $$\hat\xi_{i,k}=\sum_{j\in\mathcal N_i}h_{ij}\big(\hat x^{r+}_{j,k}-\delta^r_{i,k}\hat x^+_{i,k}\big),\qquad
# \hat x^-_{i,k+1}=A\hat x^+_{i,k}+\kappa A\hat\xi_{i,k},\qquad
# \hat x^+_{i,k+1}=\hat x^-_{i,k+1}+\tilde\vartheta_{i,k+1}K_{i,k+1}\eta_{i,k+1},$$
#
# with innovation $\eta_{i,k+1}=y_{i,k+1}-C_i\hat x^-_{i,k+1}$.
#
# ### Lemma 1 (11)–(12): the covariance the filter cannot compute
#
# $P^-_{i,k+1}\preceq(1+\kappa\delta^r_{i,k})AP^+_{i,k}A^T+BB^T+\delta^r_{i,k}\kappa(1+\kappa)A\Xi^+_{i,k}A^T$
# with $\Xi^+_{i,k}=2\sum_{j\in\mathcal N_i\cup\{i\}}P^+_{j,k}$. This bounds the consensus cross terms
# with Young's inequality (13)–(14). The update (12) is the Joseph form
# $(I-\vartheta KC_i)P^-(I-\vartheta KC_i)^T+\vartheta KDD^TK^T$.
#
# ### Upper bounds (26), gain (32), and (35)
#
# Replacing $P^+_{j,k}$ by upper bounds $\Pi^+_{j,k}$ gives $\tilde\Xi^+_{i,k}=2\sum_{j\in\mathcal N_i\cup\{i\}}\Pi^+_{j,k}$,
# $\tilde Q_{2i,k}=BB^T+\delta^r_{i,k}\kappa(1+\kappa)A\tilde\Xi^+_{i,k}A^T$ and
#
# $$\Pi^-_{i,k+1}=(1+\kappa\delta^r_{i,k})A\Pi^+_{i,k}A^T+\tilde Q_{2i,k}\quad(26).$$
#
# The trace of $\tilde S_{2}=KDD^TK^T+(I-KC_i)\Pi^-(I-KC_i)^T$ is minimised by
# $K_{i,k+1}=\Pi^-_{i,k+1}C_i^T\Pi_{\eta,i,k+1}^{-1}$, $\Pi_\eta=C_i\Pi^-C_i^T+DD^T$ (32). The minimum is
# $S^*=\Pi^--KC_i\Pi^-$ (33). Then (27) becomes (35):
# $\Pi^+_{i,k+1}=\Pi^-_{i,k+1}-\tilde\vartheta_{i,k+1}K_{i,k+1}C_i\Pi^-_{i,k+1}$. (35) drops the
# $\max\{\Pi^-,S^*\}$ of (27). This is correct only if "$Y\prec X$" is read non-strictly, because
# $\Pi^--S^*$ has rank 1 (E6).
#
# ### Lower bounds (17)–(19)
#
# $\tilde Q_{1i,k}=(1-\kappa\delta^r_{i,k})A\Gamma^+_{i,k}A^T+\delta^r_{i,k}\kappa(\kappa-1)A\tilde\Xi^+_{i,k}A^T$.
# Its second term uses the *upper* bounds and has a negative coefficient.
# $\Gamma^-_{i,k+1}=\tilde Q_{1i,k}+BB^T$ if $\tilde Q_{1i,k}\succeq0$, else $BB^T$ (17).
# $\Gamma^+_{i,k+1}=\min\{\Gamma^-_{i,k+1},\tilde S_{1i,k+1}\}$ with
# $\tilde S_{1i,k+1}=KDD^TK^T+(I-KC_i)\Gamma^-_{i,k+1}(I-KC_i)^T$ (18)–(19). The paper's
# $\min\{X,Y\}$ is $X$ if $X\preceq Y$, $Y$ if $Y\prec X$, and otherwise $\lambda_{\min}I$, where
# $\lambda_{\min}$ is the smallest eigenvalue of $X$ and $Y$ together. $\Gamma^+$ is computed whether or not
# the update is accepted: it is valid for both outcomes (23)–(24).
#
# ### χ² test (5)–(6) made implementable (25)
#
# The ideal statistic $\eta^TP_\eta^{-1}\eta\sim\chi^2_{n_y}$ needs the unknown $P^-$. (25) uses the lower bound:
# $\tilde\vartheta_{i,k}=\mathbb 1\big[\eta_{i,k}^T\Gamma_{\eta,i,k}^{-1}\eta_{i,k}<\chi^2_{n_y,\sigma}\big]$ with
# $\Gamma_{\eta,i,k}=C_i\Gamma^-_{i,k}C_i^T+DD^T\preceq P_\eta$. It therefore rejects at least as often as (6).
#
# ### The code
#
# `secest/methods/ding2020.py` implements these steps twice. `secure_filter_step` is vectorised over
# nodes and Monte Carlo runs. `secure_filter_node_step` is a plain per-node reference that loops over
# the neighbours (shown with claim X8). Their agreement is claim X8. First the pieces the step
# calls: the received estimates (3) and the indicator (4), the consensus prediction (7), and the
# paper's $\min\{X,Y\}$ / $\max\{X,Y\}$ of Section III (`_min_max`, its branches numbered 0, 1, 2):

# %%
show_source(ding2020._received)
show_source(ding2020.consensus_prediction, after="    x = np.asarray(x_post")
show_source(ding2020._min_max)

# %% [markdown]
# The vectorised step, with the equation numbers next to each line:

# %%
show_source(ding2020.secure_filter_step, after="    if validate:")

# %% [markdown]
# ## Simulation driver
#
# The world ($x_0$, $\hat x_{i,0}$, $w$, $v$) is drawn once per run. Cases A and B, the filter
# without inspection, the κ = 0 control and the constant-gain filter all reuse it (common random
# numbers). `ding2020.secure_filter` runs the step over all steps, all nodes and a batch of runs at
# once (the first measurement update at $k=1$):

# %%
show_source(ding2020.secure_filter, after="    d = np.asarray(delta")

# %% [markdown]
# `simulate` sets the example's model, topology and initial bounds, runs it (or the constant-gain
# filter of Figs. 5–6) and checks that the literal indicator (4) equals $\delta_k$ at every step (P3).


# %%
def propagate(x0: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Trajectories of (1), x_{k+1} = A x_k + B w_k, from x0 (R, n) with noise w (R, steps, n)."""
    x = np.empty((x0.shape[0], w.shape[1] + 1, n_x))
    x[:, 0] = x0
    for k in range(w.shape[1]):
        x[:, k + 1] = x[:, k] @ A.T + w[:, k] @ B.T
    return x


def measure(x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Clean measurements (2), y_{i,k} = C_i x_k + D v_{i,k}, shape (R, steps + 1, m)."""
    return np.einsum("in,rkn->rki", C_rows, x) + D[0, 0] * v


def draw_world(rng: np.random.Generator, runs: int, steps: int) -> dict[str, np.ndarray]:
    """x_0, x_hat_0 ~ N(0, sigma0 I); trajectories x_k and clean measurements y_{i,k}."""
    s = np.sqrt(sigma0)
    x0 = s * rng.standard_normal((runs, n_x))
    xh0 = s * rng.standard_normal((runs, m, n_x))
    w = rng.standard_normal((runs, steps, n_x))
    v = rng.standard_normal((runs, steps + 1, m))
    x = propagate(x0, w)
    return {"x": x, "xh0": xh0, "y": measure(x, v)}


def continue_world(rng: np.random.Generator, x_start: np.ndarray, steps: int) -> dict[str, np.ndarray]:
    """The same target continued from x_start (R, n) for `steps` more steps, without attacks."""
    w = rng.standard_normal((x_start.shape[0], steps, n_x))
    v = rng.standard_normal((x_start.shape[0], steps + 1, m))
    x = propagate(x_start, w)
    return {"x": x, "y": measure(x, v)}


def initial_bound(value: np.ndarray | None, scale: float, runs: int) -> np.ndarray:
    """Pi_0 or Gamma_0 for every run and node: scale * sigma0 * I unless an array is given."""
    base = scale * sigma0 * np.eye(n_x) if value is None else np.asarray(value, dtype=float)
    return np.broadcast_to(base, (runs, m, n_x, n_x)).copy()


def simulate(xh0, y, delta_seq, *, kappa_=kappa, inspect_=inspection, inspection_cov="Gamma",
             const_gain=None, form=cmp_form, Pi0=None, Gam0=None, keep_bounds=False, net=None):
    """Run the secure filter (7)/(34) (or the constant-gain filter) of the example over all steps.

    Parameters
    ----------
    xh0 : (R, m, n) initial estimates; y : (R, steps + 1, m) measurements incl. attacks;
    delta_seq : (>= steps,) channel states. kappa_ : coupling; inspect_ : apply (25);
    inspection_cov : "Gamma" (25) or "Pi" (ablation); const_gain : (m, n) gains of the comparison
    filter in structure `form`; Pi0, Gam0 : initial bounds ((n, n) or (R, m, n, n); default
    pi0_scale, gamma0_scale times sigma0 I); net : (adjacency, weights) of another topology.

    Returns
    -------
    dict with estimates "x" (R, steps + 1, m, n), test outcomes "theta" (R, steps + 1, m)
    (theta[:, 0] = 1: no update at k = 0), the final bounds "Pi_end", "Gamma_end" and, with
    keep_bounds, Pi, Gamma (R, steps + 1, m, n, n), gains K (R, steps, m, n), the branches of
    (17) and (18) and the test normalisers Gamma_eta, Pi_eta (R, steps, m).
    """
    adj_, H_ = (adj, H) if net is None else net
    if const_gain is not None:
        x = ding2020.constant_gain_filter(xh0, delta_seq, y, A=A, C=C_rows, gains=const_gain, adj=adj_,
                                          weights=H_, kappa=kappa_, form=form)
        return {"x": x, "theta": np.ones(x.shape[:-1])}
    Pi, Gam = initial_bound(Pi0, pi0_scale, xh0.shape[0]), initial_bound(Gam0, gamma0_scale, xh0.shape[0])
    keep = ("Pi_post", "Gamma_post", "gain", "q1_psd", "min_branch", "Gamma_prior", "Pi_prior")
    run_ = ding2020.secure_filter(
        xh0, Pi, Gam, delta_seq, y[..., None], A=A, BBt=BBt, C=C, DDt=DDt, adj=adj_, weights=H_,
        kappa=kappa_, threshold=threshold, inspect=inspect_, inspection_cov=inspection_cov, tol=tol,
        strict=strict, keep=keep if keep_bounds else ())
    if not np.all(run_.delta_r == delta_seq[: y.shape[1] - 1, None]):  # literal (4) equals delta_k (P3)
        raise AssertionError("indicator (4) differs from delta_k")
    res = {"x": run_.x, "theta": run_.theta, "Pi_end": run_.Pi_end, "Gamma_end": run_.Gamma_end}
    if keep_bounds:
        h = run_.history
        res.update(Pi=np.concatenate([Pi[:, None], h["Pi_post"]], axis=1),
                   Gamma=np.concatenate([Gam[:, None], h["Gamma_post"]], axis=1), K=h["gain"][..., 0],
                   q1_psd=h["q1_psd"], min_branch=h["min_branch"], Pi_prior=h["Pi_prior"],
                   Gamma_eta=np.einsum("iyn,rkinm,iym->rki", C, h["Gamma_prior"], C) + DDt[0, 0],
                   Pi_eta=np.einsum("iyn,rkinm,iym->rki", C, h["Pi_prior"], C) + DDt[0, 0])
    return res


def pos_err(sim: dict, x: np.ndarray) -> np.ndarray:
    """Position error x_hat_{i,k}(1) - x_{1,k}, shape (R, steps + 1, m)."""
    return sim["x"][..., 0] - x[:, :, None, 0]


def rmse(err: np.ndarray, ks: np.ndarray, i: int) -> np.ndarray:
    """Position RMSE over the steps ks at node index i, one value per run."""
    return np.sqrt(np.mean(err[:, ks, i] ** 2, axis=1))


def locked(theta: np.ndarray, k: int) -> np.ndarray:
    """(R, m) bool: the node rejected each of its last LOCK_STEPS measurements up to step k."""
    return np.all(theta[:, k - LOCK_STEPS + 1 : k + 1] == 0, axis=1)


def works(theta: np.ndarray, i: int, k_last: int) -> np.ndarray:
    """(R,) bool: node index i is never locked out (LOCK_STEPS consecutive rejections) at a step <= k_last."""
    rej = theta[:, 1 : k_last + 1, i] == 0
    if rej.shape[1] < LOCK_STEPS:
        return np.ones(theta.shape[0], dtype=bool)
    return ~np.lib.stride_tricks.sliding_window_view(rej, LOCK_STEPS, axis=1).all(axis=-1).any(axis=1)

# %% [markdown]
# ## The example (Section V): Cases A and B, no inspection, constant gains
#
# One run with the default seed. Case A has no attack. Case B adds the injections of `attacks`
# ($+15$ to $y_{4,k}$ for $k\in[90,95]$ and to $y_{12,k}$ for $k\in[50,55]$). The attacked data is not
# transmitted and touches no other sensor. "No inspection" is Case B with $\tilde\vartheta\equiv1$
# in (34) and (35). The constant-gain comparison filter runs in both readings of its structure.

# %%
world = draw_world(rng_world, 1, N)
x_true, y_clean = world["x"], world["y"]
y_attacked = y_clean + attack
case_a = simulate(world["xh0"], y_clean, delta, keep_bounds=True)
case_b = simulate(world["xh0"], y_attacked, delta, keep_bounds=True)
no_insp = simulate(world["xh0"], y_attacked, delta, inspect_=False)
const = {form: {case: simulate(world["xh0"], y_, delta, const_gain=K_const, form=form)
                for case, y_ in (("A", y_clean), ("B", y_attacked))} for form in CMP_FORMS}
k_all = np.arange(N + 1)
err = {name: pos_err(sim, x_true) for name, sim in
       (("A", case_a), ("B", case_b), ("N", no_insp), ("cA", const[cmp_form]["A"]),
        ("cB", const[cmp_form]["B"]))}
rej_a = np.argwhere(case_a["theta"][0] == 0)
rej_b = np.argwhere(case_b["theta"][0] == 0)
print("Case A rejections (k, node):", [(int(k), int(i) + 1) for k, i in rej_a][:40])
print("Case B rejections (k, node):", [(int(k), int(i) + 1) for k, i in rej_b][:40])

# %% [markdown]
# ## Fig. 3 — measurements under attack
#
# Received $y_{i,k}$ of the attacked sensors. The normal measurement, without the injection, is dashed.
# The paper's note that normal curves are "attacked minus 15" confirms an additive constant.


# %%
def label_windows(ax, nodes=None, text=True) -> None:
    """Shade the attack windows of `nodes` (default: all) and name the attacked sensor above each."""
    for node, ks in windows.items():
        if nodes is not None and node not in nodes:
            continue
        ax.axvspan(ks[0], ks[-1], color="tab:red", alpha=0.12, lw=0)
        if text:
            ax.annotate(f"sensor {node} attacked", ((ks[0] + ks[-1]) / 2, 1.0),
                        xycoords=("data", "axes fraction"), xytext=(0, 1.5), textcoords="offset points",
                        ha="center", va="bottom", fontsize=7, color="tab:red")


def measurement_figure(nodes, name, title):
    fig, axes = plt.subplots(len(nodes), 1, figsize=(plotting.PAGE_WIDTH, 1.7 * len(nodes) + 0.5),
                             sharex=True, squeeze=False)
    data = {"k": k_all[1:]}
    for ax, node in zip(axes[:, 0], nodes, strict=True):
        i = node - 1
        ax.plot(k_all[1:], y_attacked[0, 1:, i], color="tab:red", label=f"received $y_{{{node},k}}$")
        ax.plot(k_all[1:], y_clean[0, 1:, i], color="k", ls="--", lw=0.9, label="normal (no injection)")
        label_windows(ax, [node], text=False)
        ax.set_ylabel(f"$y_{{{node},k}}$ [sensor units]")
        ax.legend(loc="upper left", ncol=2, fontsize=7)
        data[f"y{node}_received"] = y_attacked[0, 1:, i]
        data[f"y{node}_normal"] = y_clean[0, 1:, i]
    axes[-1, 0].set_xlabel("time step k")
    axes[-1, 0].set_xlim(0, N)
    axes[0, 0].set_title(title)
    save(fig, name, data=data)


measurement_figure(list(windows), "fig3_measurements_attack", "Fig. 3: measurements subject to attacks (shaded: attack window)")

# %% [markdown]
# ## Fig. 4 — position $x_{1,k}$ and its estimates at the plotted nodes
#
# (a) Case A. (b) Case B with the inspection (25). (c) Case B without the inspection. The estimates
# of sensors 12 and 20 nearly coincide at the scale of the position, so each figure has a second panel
# with the estimation errors $\hat x^+_{i,k}(1)-x_{1,k}$; sensor 20 is drawn dashed under the others.

# %%
PALETTE = ["tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan"]
node_colors = {node: PALETTE[j % len(PALETTE)] for j, node in enumerate(plot_nodes)}
node_styles = {node: "-" if node - 1 in ATT else "--" for node in plot_nodes}


def estimate_figure(sim, name, title, shade=True):
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(plotting.PAGE_WIDTH, 4.6), sharex=True,
                                  height_ratios=[3, 2])
    ax.plot(k_all, x_true[0, :, 0], color="k", lw=1.6, label=r"position $x_{1,k}$")
    data = {"k": k_all, "x1": x_true[0, :, 0]}
    for node in sorted(plot_nodes, key=lambda n: n - 1 in ATT):  # unattacked first, underneath
        est = sim["x"][0, :, node - 1, 0]
        style = {"color": node_colors[node], "ls": node_styles[node], "lw": 1.0}
        ax.plot(k_all, est, label=f"estimate $\\hat x^+_{{{node},k}}(1)$, sensor {node}", **style)
        ax2.plot(k_all, est - x_true[0, :, 0], **style)
        data[f"xhat{node}"] = est
    data = {"k": data["k"], "x1": data["x1"], **{f"xhat{n}": data[f"xhat{n}"] for n in plot_nodes}}
    if shade:
        label_windows(ax)
        label_windows(ax2, text=False)
    ax2.axhline(0.0, color="k", lw=0.6)
    ax.set_ylabel("position [length unit]")
    ax2.set_ylabel("estimation error\n[length unit]")
    ax2.set_xlabel("time step k")
    ax2.set_xlim(0, N)
    ax.set_title(title, pad=13 if shade else 6)
    ax2.legend(*ax.get_legend_handles_labels(), loc="upper center", bbox_to_anchor=(0.5, -0.32), ncol=2)
    save(fig, name, data=data)


estimate_figure(case_a, "fig4a_estimates_case_a", "Fig. 4(a): Case A, no attack", shade=False)
estimate_figure(case_b, "fig4b_estimates_case_b", "Fig. 4(b): Case B, attacks, with inspection (25)")
estimate_figure(no_insp, "fig4c_estimates_no_inspection",
                "Fig. 4(c): Case B, attacks, inspection removed")

# %% [markdown]
# ## "No obvious effect" between Figs. 4(a) and 4(b) (claim C2a) and the leak by hop (X6)
#
# The paper's words: "Combining Fig. 4(a) and Fig. 4(b), we can find that there is no obvious effect on
# the filtering performance with or without attacks benefiting from the capability of designed
# detection scheme." That is a statement about what a reader sees. We measure it on the plotted curves:
# for each plotted sensor the largest shift of its estimate between Cases B and A,
# $\max_k\lvert\hat x^+_{i,k}(1)\,\text{(B)}-\hat x^+_{i,k}(1)\,\text{(A)}\rvert$, as a fraction of the
# axis range of Fig. 4(a), next to the same sensor's own largest error in Case A (from $k=1$). Our rule
# for "no obvious effect" in one run (the threshold is ours, the paper gives none): no curve is moved by the
# attack further than its own error without attack already reaches in Fig. 4(a). Applied to each Monte Carlo
# run, it decides C2a over the runs (claims section).
#
# The injected data never leaves the attacked sensor. It still reaches other nodes in two ways. The
# attacked node's estimate drifts during its open-loop predictions, and the consensus term of (7)
# passes that drift to its neighbours. Its bound $\Pi^+$ also grows while updates are skipped; that
# bound enters the neighbours' $\tilde\Xi$ in (26), so their gains change. Each further hop attenuates
# the effect again. How much an unattacked node moves therefore depends on its distance from the
# attacked sensors in Fig. 1, which we do not have. X6 (ours) quantifies this on ten stand-in
# topologies fixed in advance (`leak_topology_seeds`, seeds 2020–2029, each with one Case A and one Case B
# run on the default channel and world): the leak
# $\max_k\lVert\hat x^+_{i,k}(\text{B})-\hat x^+_{i,k}(\text{A})\rVert_\infty$ of every unattacked node
# against its hop distance to the nearest attacked sensor, over the topologies whose attacked sensors
# work without attack. A leak at or below $10^{-12}$, the leak data's declared resolution, is recorded as
# zero (ERRATA.md says why and when).

# %%
axis_range = float(np.ptp(np.concatenate([x_true[0, :, 0], *(case_a["x"][0, :, i, 0] for i in PLOT)])))
c2a = {}
for node in plot_nodes:
    i = node - 1
    shift = float(np.abs(case_b["x"][0, :, i, 0] - case_a["x"][0, :, i, 0]).max())
    own = float(np.abs(err["A"][0, 1:, i]).max())
    c2a[f"sensor{node}"] = {"shift": shift, "shift_fraction_of_axis": shift / axis_range,
                            "case_a_error": own, "case_a_error_fraction_of_axis": own / axis_range,
                            "hops_to_attacked": min(hops[i][a] for a in ATT)}
    print(f"sensor {node}: shift {shift:.3g} ({shift / axis_range:.2%} of the axis range {axis_range:.3g}); "
          f"own Case A error up to {own:.3g} ({own / axis_range:.2%})")

# a leak at or below the leak data's declared resolution (CANCELLATION's atol, 1e-12: round-off of
# estimates of size ~1, which another CPU or BLAS build replaces by other round-off) is recorded as 0
LEAK_FLOOR = results.CANCELLATION.atol
leak_rows = []  # (topology seed, node (1-based), hops to the nearest attacked sensor, leak)
leak_kept = 0  # topologies whose attacked sensors work without attack up to their windows' end (X6's precondition)
for s_top in leak_topology_seeds:
    adj_s = graphs.check_connected(graphs.random_geometric_graph(m, radius, s_top))
    H_s = graphs.row_stochastic_weights(adj_s, self_weight=False)
    pair = simulate(np.concatenate([world["xh0"]] * 2), np.concatenate([y_clean, y_attacked]),
                    delta, net=(adj_s, H_s))
    if not all(bool(works(pair["theta"][:1], a, windows[a + 1][-1])[0]) for a in ATT):
        continue
    leak_kept += 1
    leak_s = np.abs(pair["x"][1] - pair["x"][0]).max(axis=(0, 2))
    leak_s[leak_s <= LEAK_FLOOR] = 0.0
    hops_s = dict(nx.all_pairs_shortest_path_length(nx.from_numpy_array(adj_s)))
    for i in range(m):
        h_i = min(hops_s[i][a] for a in ATT)
        if h_i > 0:
            leak_rows.append((s_top, i + 1, h_i, float(leak_s[i])))
leak_tab = np.array(leak_rows).reshape(-1, 4)
leak_stats = {}
for h_ in np.unique(leak_tab[:, 2]).astype(int):
    v = leak_tab[leak_tab[:, 2] == h_, 3]
    leak_stats[str(h_)] = {"nodes": int(v.size), "min": float(v.min()), "median": float(np.median(v)),
                           "max": float(v.max())}
    print(f"{h_} hop(s): {v.size:3d} node-topologies, leak min {v.min():.1e}, median {np.median(v):.1e}, "
          f"max {v.max():.1e}")

# %%
fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 2.8))
positive = leak_tab[:, 3] > 0
jitter = (np.arange(len(leak_tab)) % 9 - 4) * 0.03
ax.scatter(leak_tab[positive, 2] + jitter[positive], leak_tab[positive, 3], s=10, color="0.45",
           label=f"unattacked nodes ({len(leak_topology_seeds)} stand-in topologies)")
hop_axis = np.array([int(h_) for h_ in leak_stats])
medians = np.array([leak_stats[str(h_)]["median"] for h_ in hop_axis])
ax.plot(hop_axis[medians > 0], medians[medians > 0], color="k", marker="_", ms=14, lw=1.0,
        label="median over nodes and topologies")
if not positive.any():
    ax.text(0.5, 0.5, "every leak is exactly 0 (kappa = 0: the nodes are decoupled)",
            transform=ax.transAxes, ha="center")
else:
    ax.set_yscale("log")
ax.set_xticks(hop_axis)
ax.set_xlabel("hop distance to the nearest attacked sensor")
ax.set_ylabel(r"leak $\max_k \|\hat x^+_B - \hat x^+_A\|_\infty$" + "\n[state units]")
ax.set_title("Extra: leak of the attack into unattacked nodes, Case B vs Case A (X6)")
ax.legend(loc="lower left", fontsize=7)
save(fig, "extra_leak_by_hop", data={"topology_seed": leak_tab[:, 0].astype(int), "node": leak_tab[:, 1].astype(int),
                                     "hops": leak_tab[:, 2].astype(int), "leak": leak_tab[:, 3]},
     tolerance={"leak": results.CANCELLATION})

# %% [markdown]
# **What the numbers say.** In the default run, the figure's run, the attack's effect on the unattacked
# sensor 20 is invisible and the attacked sensors move by less than their own error without attack. That is one
# run: C2a applies the same per-run rule to each of the Monte Carlo runs (the claims section) and decides on the
# fraction of runs that meet it, against one half (ours, post hoc: set in r7 of the review after the
# 98-of-300 result and the sweep at e86f45a were known; a figure offered as typical is read as the median
# run), by its Wilson interval, so that the rule means the same at any run count; the default run is kept as an
# illustration (until r7 of the review C2a was decided on it alone). A plotted sensor that its own Case A locks
# out in a run runs open loop with or without attack, so the rule leaves it out of that run; and since the
# unattacked sensor 20 cannot show an attack's effect on its own, a run counts only if an *attacked* plotted
# sensor is compared. The leak is real and decays geometrically with the hop distance, more than twenty-fold
# per hop (X6). An earlier reading, "node 20 is unaffected" at a threshold of $10^{-3}$ of ours, put words in
# the paper's mouth and is dropped.

# %% [markdown]
# ## Figs. 5 and 6 — the constant-gain comparison filter
#
# The paper's comparison filter comes from LMIs of its refs. [9], [13] and is not specified
# beyond its gains. We use the same prediction (7), with the same $\kappa$, $\delta$ and $H$, and the
# printed constant gains without a detector, in two readings of the structure: **corrector**
# $\hat x^+=\hat x^-+K_i(y_{i,k+1}-C_i\hat x^-)$ and **predictor**
# $\hat x_{k+1}=A\hat x_k+\kappa A\hat\xi_k+K_i(y_{i,k}-C_i\hat x_k)$. Both are stable: the spectral
# radii of $(I-K_iC_i)A$ and $A-K_iC_i$ are printed below. Fig. 6 shows the reading `cmp_form`; C9 is
# measured in both. The measurements are the same draws as in Fig. 3 (common random numbers), so Fig. 5
# shows the plotted sensors. The filter, which `simulate` runs when given `const_gain`:

# %%
show_source(ding2020.constant_gain_filter, after="    d = np.asarray(delta")

# %%
for label, kk, cc in (("nodes 1-7", K_const[0], C_rows[0]), (f"nodes 8-{m}", K_const[-1], C_rows[-1])):
    rho_c = max(abs(np.linalg.eigvals((np.eye(3) - np.outer(kk, cc)) @ A)))
    rho_p = max(abs(np.linalg.eigvals(A - np.outer(kk, cc))))
    print(f"{label}: C_i K_i = {cc @ kk:.4f}; spectral radius of (I - K_i C_i) A = {rho_c:.4f} (corrector), "
          f"of A - K_i C_i = {rho_p:.4f} (predictor)")
measurement_figure(plot_nodes, "fig5_measurements_comparison",
                   "Fig. 5: measurements of the comparison run (same draws as Fig. 3)")
estimate_figure(const[cmp_form]["A"], "fig6a_constant_gain_case_a",
                f"Fig. 6(a): constant-gain filter ({cmp_form}), no attack", shade=False)
estimate_figure(const[cmp_form]["B"], "fig6b_constant_gain_case_b",
                f"Fig. 6(b): constant-gain filter ({cmp_form}), attacks (no detector)")

# %% [markdown]
# ## What the bounds do in practice (P6, P8)
#
# Two counters show how the lower bound behaves. Whenever $\delta^r=1$ (after $k=0$),
# $\tilde Q_1$ is indefinite, so $\Gamma^-=BB^T$. $\Gamma^-$ and $\tilde S_1$ are never ordered, so
# $\Gamma^+=\lambda_{\min}I$ with $\lambda_{\min}\approx10^{-4}$. The test (25) therefore runs with
# an almost constant normaliser $\Gamma_\eta\approx C_iBB^TC_i^T+DD^T$. The printout lists these values.

# %%
q1 = case_a["q1_psd"][0]
branch = case_a["min_branch"][0]
d_steps = delta[:N].astype(bool)
print(f"Q1 >= 0 (first branch of (17)): {int(q1.sum())} of {q1.size} node-steps; "
      f"when delta = 1: {int(q1[d_steps].sum())} of {q1[d_steps].size}")
print("branch of min{Gamma^-, S1} (X, Y, lambda_min I):", np.bincount(branch.ravel(), minlength=3))
lam_gamma = np.linalg.eigvalsh(case_a["Gamma"][0, 1:])[..., -1]
print(f"largest eigenvalue of Gamma^+ over k >= 1: {lam_gamma.max():.3g}")
g_eta = case_a["Gamma_eta"][0]
for lo_, hi_, lab in ((0, min(7, m), "nodes 1-7"), (7, m, f"nodes 8-{m}")):
    if hi_ > lo_:
        cb = C_rows[lo_] @ BBt @ C_rows[lo_] + DDt[0, 0]
        print(f"{lab}: Gamma_eta median {np.median(g_eta[:, lo_:hi_]):.4f} "
              f"(C BB^T C^T + DD^T = {cb:.4f}); accepted |eta| < {np.sqrt(threshold * cb):.3f}")
print(f"for comparison, Pi_eta = C Pi^- C^T + DD^T of (32): median {np.median(case_a['Pi_eta'][0]):.3f}")

# %% [markdown]
# ## Exact covariance against the bounds (claim C5, extra figure)
#
# When every update is accepted ($\tilde\vartheta\equiv1$) the conditioning on the test
# outcome behind Lemma 1 and Theorem 2 is trivial (E12), and the gains $K_{i,k}$ depend only
# on $\delta$. So the exact stacked error covariance can be propagated. With
# $e_{i,k}=x_k-\hat x_{i,k}$ and $L=I-H$:
#
# $$e^-_{k+1}=\big(I\otimes A-\kappa\delta_k\,L\otimes A\big)e^+_k+(\mathbf 1\otimes B)w_k,\qquad
# e^+_{i,k+1}=(I-K_{i,k+1}C_i)e^-_{i,k+1}-K_{i,k+1}Dv_{i,k+1},$$
#
# with $\mathrm{cov}(e^+_0)=(\mathbf 1\mathbf 1^T+I)\otimes\sigma_0I$. We check
# $\lambda_{\min}(\Pi^+_{i,k}-P^+_{ii,k})\ge-10^{-9}\,\mathrm{tr}P^+_{ii,k}$ and the same for
# $P^+-\Gamma^+$ on Case A. Theorems 1–2 start their induction from $\Gamma_0\preceq P_0\preceq\Pi_0$, the
# premise of C5. Our propagation cannot condition on the test (E12): where a Case-A update is rejected, C5
# is `not-checked` (a limit of our check). A Monte Carlo run of Case A cross-checks the propagation, which is:

# %%
show_source(ding2020.exact_error_covariance, after="    n3 = m * n")


# %%
def exact_covariance(gains: np.ndarray, kappa_: float = kappa) -> np.ndarray:
    """Diagonal blocks (steps + 1, m, n, n) of the exact covariance for recorded gains (steps, m, n),
    from cov(e_0^+) = (1 1^T + I) kron sigma0 I on the run's channel delta."""
    P0 = np.kron(np.ones((m, m)) + np.eye(m), sigma0 * np.eye(n_x))
    return ding2020.exact_error_covariance(gains, delta, P0, A=A, B=B, C=C_rows, D=D[0, 0], weights=H,
                                           kappa=kappa_)


all_accepted_a = bool(np.all(case_a["theta"] == 1))
initial_order = bool(gamma0_scale <= 2.0 <= pi0_scale)
P_exact = exact_covariance(case_a["K"][0])
tr_P = np.trace(P_exact, axis1=-2, axis2=-1)
Pi_a, Gam_a = case_a["Pi"][0], case_a["Gamma"][0]
gap_up = np.linalg.eigvalsh(Pi_a - P_exact)[..., 0] / tr_P
gap_low = np.linalg.eigvalsh(P_exact - Gam_a)[..., 0] / tr_P
ratio_tr = np.trace(Pi_a, axis1=-2, axis2=-1) / tr_P
print(f"Case A all accepted: {all_accepted_a}; Gamma_0 <= P_0 <= Pi_0: {initial_order}")
print(f"min_(i,k) lambda_min(Pi+ - P+)/tr P+ = {gap_up[1:].min():.3g}")
print(f"min_(i,k) lambda_min(P+ - Gamma+)/tr P+ = {gap_low[1:].min():.3g}")
print(f"median tr Pi+ / tr P+ = {np.median(ratio_tr[1:]):.3f}")

# %%
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(plotting.PAGE_WIDTH, 4.4), sharex=True,
                              height_ratios=[2, 1])
data = {"k": k_all}
for node in plot_nodes:
    i = node - 1
    c = node_colors[node]
    tr_pi_i = np.trace(Pi_a[:, i], axis1=-2, axis2=-1)
    ax.plot(k_all, tr_pi_i, color=c, label=f"sensor {node}: " + r"tr $\Pi^+$ (upper bound)")
    ax.plot(k_all, tr_P[:, i], color=c, ls="--", label=f"sensor {node}: " + r"tr $P^+$ (exact)")
    data[f"trPi{node}"], data[f"trP{node}"] = tr_pi_i, tr_P[:, i]
    data[f"trGamma{node}"] = np.trace(Gam_a[:, i], axis1=-2, axis2=-1)
for node in plot_nodes:
    # curves equal to within 0.1 % share one line (nodes with the same C_i usually do)
    same = [n for n in plot_nodes if np.allclose(data[f"trGamma{n}"], data[f"trGamma{node}"], rtol=1e-3, atol=0)]
    if same[0] == node:
        ax2.semilogy(k_all, data[f"trGamma{node}"], color=node_colors[node], ls=":",
                     label=(f"sensors {', '.join(map(str, same))} (coincide)" if len(same) > 1 else f"sensor {node}")
                     + r": tr $\Gamma^+$ (lower bound)")
for a in (ax, ax2):
    for k in np.flatnonzero(delta == 0):
        a.axvspan(k, k + 1, color="0.85", lw=0)
ax.axvspan(0, 0, color="0.85", label=r"$\delta_k = 0$ (channel down)")
upper = np.concatenate([data[f"trPi{n}"][1:] for n in plot_nodes] + [data[f"trP{n}"][1:] for n in plot_nodes])
lower = np.concatenate([data[f"trGamma{n}"][1:] for n in plot_nodes])
ax.set_yscale("log")
ax.set_ylim(0.8 * upper.min(), 1.25 * upper.max())
ax.set_xlim(0, N)
ax.set_ylabel("trace [mixed units]")
ax.set_title(r"Extra: consistency of the bounds, Case A ($\Gamma^+ \preceq P^+ \preceq \Pi^+$)")
ax2.set_ylim(0.5 * lower.min(), 2.0 * lower.max())
ax2.set_xlabel("time step k")
ax2.set_ylabel("trace [mixed units]")
handles = ax.get_legend_handles_labels()
handles2 = ax2.get_legend_handles_labels()
fig.legend(handles[0] + handles2[0], handles[1] + handles2[1], loc="outside lower center", ncol=3,
           fontsize=7)
fig.set_layout_engine("constrained")
save(fig, "extra_bound_consistency", data=data)

# %% [markdown]
# The upper bound is conservative (median $\mathrm{tr}\,\Pi^+/\mathrm{tr}\,P^+$ printed above) but
# valid. It is tight along the measured direction, so $\lambda_{\min}(\Pi^+-P^+)$ sits at round-off
# level. One effect runs against intuition (P8): the crude consensus term
# $\tilde\Xi=2\sum\Pi$ inflates $\Pi^-$ by roughly $\kappa(1+\kappa)\,2(\lvert\mathcal N_i\rvert+1)$
# per step when $\delta=1$. So $\Pi^+$ *drops* when the channel fails, while the exact $P^+$ rises
# slightly because consensus is lost. The lower bound has collapsed to about $10^{-4}$ (P6).

# %% [markdown]
# ## The gain (32) minimises the upper bound (claim C11)
#
# Theorem 3's "locally optimized upper bounds": for any gain $K$ an accepted update bounds the error by
# $\tilde S_2(K)=KDD^TK^T+(I-KC_i)\Pi^-(I-KC_i)^T$, and (31)–(32) pick the $K$ minimising its trace. At
# every node and step of Case A we move the recorded gain (32) to $K+\varepsilon\lVert K\rVert\Delta$ for
# 200 random unit directions $\Delta$ (seed 0), the six signed coordinate axes and $\pm K/\lVert K\rVert$,
# with $\varepsilon\in\{10^{-3},10^{-1},1\}$, and record the smallest relative change of $\mathrm{tr}\,\tilde S_2$.
#
# **This holds by algebra, so C11 is by construction and does not decide.** $\tilde S_2$ is quadratic in $K$:
# with $K^*=\Pi^-C_i^T\Pi_\eta^{-1}$ of (32) and any $\Delta$,
# $\tilde S_2(K^*+\Delta)=\tilde S_2(K^*)+\Delta\,\Pi_\eta\Delta^T$, because the first-order term
# $\Delta(K^{*}\Pi_\eta-\Pi^-C_i^T)^T+(K^{*}\Pi_\eta-\Pi^-C_i^T)\Delta^T$ vanishes at (32). The change of the trace is
# $\mathrm{tr}(\Delta\Pi_\eta\Delta^T)=\Pi_\eta\lVert\Delta\rVert^2\ge0$ ($n_y=1$, $\Pi_\eta>0$): it cannot be negative
# whatever the run, and it is the same for every direction of a given length, so the smallest relative change
# grows exactly as $\varepsilon^2$. The perturbations check our code against this identity; they are no evidence
# for the paper (which claims decide is said in the claims section).


# %%
def s2_trace(K: np.ndarray, Pm: np.ndarray) -> np.ndarray:
    """tr S2(K) = tr(K DD^T K^T + (I - K C_i) Pi^- (I - K C_i)^T) for gains K (..., m, n), priors Pm (..., m, n, n)."""
    I_KC = np.eye(n_x) - K[..., :, None] * C_rows[:, None, :]
    return np.einsum("...ab,...bc,...ac->...", I_KC, Pm, I_KC) + DDt[0, 0] * (K**2).sum(axis=-1)


K_a, Pm_a = case_a["K"][0], case_a["Pi_prior"][0]  # (N, m, n), (N, m, n, n): steps k + 1 = 1..N
u_rand = np.random.default_rng(0).standard_normal((200, n_x))
K_unit = K_a / np.linalg.norm(K_a, axis=-1, keepdims=True)
dirs = np.concatenate([np.broadcast_to(u / np.linalg.norm(u), K_a.shape)[None] for u in
                       (*u_rand, *np.eye(n_x), *-np.eye(n_x))] + [K_unit[None], -K_unit[None]])
tr_opt = s2_trace(K_a, Pm_a)
c11 = {}
for eps in (1e-3, 1e-1, 1.0):
    K_pert = K_a[None] + eps * np.linalg.norm(K_a, axis=-1, keepdims=True)[None] * dirs
    c11[f"{eps:g}"] = float(((s2_trace(K_pert, Pm_a[None]) - tr_opt) / tr_opt).min())
tr_35 = np.trace(Pm_a - K_a[..., :, None] * (C_rows[:, None, :] @ Pm_a), axis1=-2, axis2=-1)  # S* of (33)
s_star_gap = float(np.abs(tr_35 - tr_opt).max() / tr_opt.max())
print(f"smallest relative change of tr S2 by step size: {c11}; |tr S* (33) - tr S2(K)| / max tr = {s_star_gap:.2g}")

# %% [markdown]
# ## κ = 0: the nodes decouple exactly (claim X4)
#
# With $\kappa=0$ the prediction (7) is $\hat x^-_{i,k+1}=A\hat x^+_{i,k}$ and (26) is
# $\Pi^-_{i,k+1}=A\Pi^+_{i,k}A^T+BB^T$: every node is a local Kalman filter of its own
# measurements, whatever the channel. Two exact consequences: the attack cannot leak (the unattacked
# nodes' estimates in Cases A and B are bit-for-bit equal), and without inspection $\Pi^+$ is the
# exact covariance $P^+$ (the Riccati recursion with its optimal gain) when $\Pi_0=P_0$. The κ = 0
# control uses $\Pi_0=\Gamma_0=P_0=2\sigma_0I$ and the run's other settings.

# %%
k0_a = simulate(world["xh0"], y_clean, delta, kappa_=0.0, Pi0=P0_exact, Gam0=P0_exact)
k0_b = simulate(world["xh0"], y_attacked, delta, kappa_=0.0, Pi0=P0_exact, Gam0=P0_exact, keep_bounds=True)
k0_free = simulate(world["xh0"], y_clean, delta, kappa_=0.0, inspect_=False, Pi0=P0_exact, Gam0=P0_exact,
                   keep_bounds=True)
unattacked = np.setdiff1d(np.arange(m), ATT)
leak0 = float(np.abs(k0_b["x"][0][:, unattacked] - k0_a["x"][0][:, unattacked]).max())
P_exact0 = exact_covariance(k0_free["K"][0], kappa_=0.0)
pi_vs_p0 = float((np.linalg.norm(k0_free["Pi"][0] - P_exact0, axis=(-2, -1))
                  / np.linalg.norm(P_exact0, axis=(-2, -1))).max())
first_rej = np.array([np.flatnonzero(k0_b["theta"][0, :, i] == 0)[0] if (k0_b["theta"][0, :, i] == 0).any()
                      else N + 1 for i in range(m)])
gam_vs_pi = np.linalg.norm(k0_b["Gamma"][0] - k0_b["Pi"][0], axis=(-2, -1)) / np.linalg.norm(
    k0_b["Pi"][0], axis=(-2, -1))
gam_pi_before = float(max(gam_vs_pi[:first_rej[i], i].max() for i in range(m)))
lam_k0 = np.linalg.eigvalsh(k0_b["Gamma"][0, 1:])[..., -1]
print(f"kappa = 0: leak into unattacked nodes = {leak0!r} (exactly 0 expected)")
print(f"kappa = 0, no inspection: max_(i,k) ||Pi+ - P+||_F / ||P+||_F = {pi_vs_p0:.2g}")
print(f"kappa = 0, Case B: max ||Gamma+ - Pi+|| / ||Pi+|| before each node's first rejection = {gam_pi_before:.2g}"
      f"; largest eigenvalue of Gamma+ over k >= 1: {lam_k0.max():.3g} (kappa = {kappa:g}: {lam_gamma.max():.3g})")

# %% [markdown]
# ## Monte Carlo: detection, degradation, comparison and the χ² lockout
#
# We redraw $x_0$, $\hat x_{i,0}$, $w$ and $v$ in every run. The topology and the channel
# sequence $\delta$ of Fig. 2 stay fixed. All runs go through the vectorised step at once: Cases A and
# B, Case B without inspection, the constant-gain filter in both structures, and two runs of ours
# that are not the paper's scheme: the test normalised by $\Pi_\eta$ instead of $\Gamma_\eta$ (ablation
# X2) and the κ = 0 control (X5), without attack (its working runs) and with it.

# %%
mc_world = draw_world(rng_mc, R_MC, N)
mc_clean, mc_att = mc_world["y"], mc_world["y"] + attack
mc = {
    "A": simulate(mc_world["xh0"], mc_clean, delta),
    "B": simulate(mc_world["xh0"], mc_att, delta),
    "N": simulate(mc_world["xh0"], mc_att, delta, inspect_=False),
    "B_Pi": simulate(mc_world["xh0"], mc_att, delta, inspection_cov="Pi"),
    "A0": simulate(mc_world["xh0"], mc_clean, delta, kappa_=0.0, Pi0=P0_exact, Gam0=P0_exact),
    "B0": simulate(mc_world["xh0"], mc_att, delta, kappa_=0.0, Pi0=P0_exact, Gam0=P0_exact),
}
for form in CMP_FORMS:
    mc[f"cA_{form}"] = simulate(mc_world["xh0"], mc_clean, delta, const_gain=K_const, form=form)
    mc[f"cB_{form}"] = simulate(mc_world["xh0"], mc_att, delta, const_gain=K_const, form=form)
mc_err = {key: pos_err(sim, mc_world["x"]) for key, sim in mc.items()}
mc_locked = {key: locked(mc[key]["theta"], N) for key in ("A", "B", "B_Pi", "A0", "B0")}
ks_all = np.arange(1, N + 1)


def wilson(count: int, n: int) -> dict:
    """95 % Wilson interval of count / n as a claims entry."""
    lo, hi = montecarlo.wilson_interval(int(count), int(n))
    return results.interval(lo, hi, method="wilson")


def boot(samples: np.ndarray, statistic: str = "median") -> dict:
    """95 % percentile bootstrap interval (2000 resamples of the runs, seed 0) as a claims entry."""
    lo, hi = montecarlo.bootstrap_interval(samples, statistic)
    what = "ratio of means, paired by run" if np.ndim(samples) == 2 else statistic
    return results.interval(lo, hi, method=f"bootstrap ({what})")


MIN_RUNS = 30  # fewest runs a bootstrap interval is computed from (ours: a percentile bootstrap undercovers below)
MC_UNDECIDED = (f"the 95 % interval contains the level at this run count (or fewer than {MIN_RUNS} runs are left for a "
                "bootstrap interval): too few Monte Carlo runs (ours) to decide either way")


def decide(ci: dict | None, level: float, side: str) -> bool | None:
    """Three-way rule on a 95 % interval, the same at any run count (ours).

    ``side="above"``: the quantity is at least ``level`` (holds if ``ci["low"] >= level``, fails if
    ``ci["high"] < level``); ``side="below"``: it is at most ``level`` (holds if ``ci["high"] <= level``,
    fails if ``ci["low"] > level``). None when the interval contains the level: the run count, not the
    claim, is then what decides, and the claim is recorded as not checked.
    """
    if side not in ("above", "below"):
        raise ValidationError(f"side: expected 'above' or 'below', found {side!r}")
    if ci is None:  # too few runs: no interval
        return None
    lo, hi = ci["low"], ci["high"]
    if side == "above":
        return True if lo >= level else (False if hi < level else None)
    return True if hi <= level else (False if lo > level else None)


def all3(*parts: bool | None) -> bool | None:
    """Three-valued 'and': False if any part is False, else None if any is None, else True."""
    if any(v is False for v in parts):
        return False
    return None if any(v is None for v in parts) else True


def ratio(num: np.ndarray, den: np.ndarray) -> tuple[float | None, dict | None]:
    """Median of num / den over runs and its bootstrap interval (None without runs / with fewer than MIN_RUNS)."""
    r = num / den
    return (float(np.median(r)) if r.size else None), (boot(r) if r.size >= MIN_RUNS else None)


mc_stats = {}
for node, ks in windows.items():
    i = node - 1
    after = np.arange(ks[-1] + 1, N + 1)
    # runs where this sensor works without attack (Case A never locks it out up to the window's end / to N):
    # the attack-effect claims are measured over these runs only (their precondition)
    wk, wk_h = works(mc["A"]["theta"], i, ks[-1]), works(mc["A"]["theta"], i, N)
    wk_n = int(wk.sum())
    wk0_h = works(mc["A0"]["theta"], i, N)  # the same at kappa = 0: X5 counts its lockouts over these runs
    r_a, r_b, r_n = (rmse(mc_err[c], ks, i)[wk] for c in ("A", "B", "N"))
    th_b, th_pi = mc["B"]["theta"][wk][:, :, i], mc["B_Pi"]["theta"][wk][:, :, i]
    (med_ba, ci_ba), (med_nb, ci_nb) = ratio(r_b, r_a), ratio(r_n, r_b)
    s = {
        "working_runs": wk_n, "working_runs_to_N": int(wk_h.sum()),
        "runs_all_window_rejected": int((th_b[:, ks] == 0).all(axis=1).sum()),
        "reject_rate_window": float(1 - th_b[:, ks].mean()) if wk_n else None,
        "median_B_over_A": med_ba, "ci_B_over_A": ci_ba,
        "median_noinsp_over_B": med_nb, "ci_noinsp_over_B": ci_nb,
        "p05_noinsp_over_B": float(np.percentile(r_n / r_b, 5)) if wk_n else None,
        "locked": int((mc_locked["B"][:, i] & wk_h).sum()),
        "any_reject_after": float(np.mean((mc["B"]["theta"][:, after, i] == 0).any(axis=1))),
        "Pi_test_runs_all_window_rejected": int((th_pi[:, ks] == 0).all(axis=1).sum()),
        "Pi_test_reject_rate_window": float(1 - th_pi[:, ks].mean()) if wk_n else None,
        "Pi_test_locked": int((mc_locked["B_Pi"][:, i] & wk_h).sum()),
        "kappa0_working_runs_to_N": int(wk0_h.sum()),
        "kappa0_locked": int((mc_locked["B0"][:, i] & wk0_h).sum()),
    }
    for form in CMP_FORMS:
        r_c = rmse(mc_err[f"cB_{form}"], ks, i)[wk]
        s[f"const_{form}_over_B"] = float(r_c.mean() / r_b.mean()) if wk_n else None
        s[f"ci_const_{form}_over_B"] = boot(np.stack([r_c, r_b], axis=1), "mean") if wk_n >= MIN_RUNS else None
    mc_stats[node] = s
locked_a = mc_locked["A"]
runs_alarm_a = int((mc["A"]["theta"] == 0).any(axis=(1, 2)).sum())
print(f"{R_MC} runs. Case A: {int((mc['A']['theta'] == 0).sum())} rejections in total, in {runs_alarm_a} runs; "
      f"{int(locked_a.any(axis=1).sum())} runs with a node locked out at k = {N}; "
      f"y_1 rejected by {np.mean(mc['A']['theta'][:, 1] == 0):.1%} of the nodes")
for node, s in mc_stats.items():
    print(f"sensor {node}: " + ", ".join(f"{k} {v:.3f}" if isinstance(v, float) else f"{k} {v}"
                                         for k, v in s.items() if not k.startswith("ci_")))

# %% [markdown]
# ### Recovery over a longer horizon
#
# A run is *locked out* at $k=150$ when the attacked sensor rejected each of its last ten measurements.
# Does it stay locked? We continue every run in which an attacked sensor is locked at the horizon to
# step `recovery_steps` (400 by default), with the same target, fresh noise, a continuation of the
# channel chain from $\delta_{150}$ and no attack, and record when the sensor accepts a measurement again.

# %%
runs_cont = np.flatnonzero(mc_locked["B"][:, ATT].any(axis=1))
S_REC = recovery_steps - N
recovery = {}
rec_curve = {}
if runs_cont.size:
    d_cont = channels.gilbert_elliott(p, q, S_REC + 1, rng_rec, initial=int(delta[N])).astype(float)
    w_cont = continue_world(rng_rec, mc_world["x"][runs_cont, N], S_REC)
    cont = simulate(mc["B"]["x"][runs_cont, N], w_cont["y"], d_cont, Pi0=mc["B"]["Pi_end"][runs_cont],
                    Gam0=mc["B"]["Gamma_end"][runs_cont])
    cont_err = pos_err(cont, w_cont["x"])
    for node in windows:
        i = node - 1
        sel = mc_locked["B"][runs_cont, i]
        if not sel.any():
            continue
        th = cont["theta"][sel, 1:, i]
        still = locked(cont["theta"][sel], S_REC)[:, i]
        recovery[f"sensor{node}"] = {
            "locked_runs": int(sel.sum()), "resumed": int((th == 1).any(axis=1).sum()),
            "locked_at_end": int(still.sum()),
            "median_abs_error_at_end_if_locked": float(np.median(np.abs(cont_err[sel, -1, i])[still]))
            if still.any() else None}
        rec_curve[node] = np.concatenate([[1.0], 1 - (np.cumsum(th == 1, axis=1) > 0).mean(axis=0)])
        print(f"sensor {node}: of {int(sel.sum())} runs locked at k = {N}, {recovery[f'sensor{node}']['resumed']} "
              f"accept a measurement again by k = {recovery_steps}; "
              f"{int(still.sum())} are locked at k = {recovery_steps}")
else:
    print(f"no run is locked out at k = {N}: nothing to continue")
resumed = sum(v["resumed"] for v in recovery.values())
locked_pairs = sum(v["locked_runs"] for v in recovery.values())

# %%
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(plotting.PAGE_WIDTH, 4.6), height_ratios=[3, 2])
data = {"k": k_all}
for node in windows:
    i = node - 1
    c = node_colors.get(node, "tab:gray")
    for key, ls, lab in (("B", "-", r"test (25) with $\Gamma_\eta$ (paper)"),
                         ("B_Pi", ":", r"test with $\Pi_\eta$ (ablation, ours)"),
                         ("B0", "--", r"$\kappa = 0$ control (ours)")):
        rate = 1 - mc[key]["theta"][:, :, i].mean(axis=0)
        ax.plot(k_all, rate, color=c, ls=ls, label=f"sensor {node}, {lab}")
        data[f"reject_rate_{key}{node}"] = rate
label_windows(ax)
ax.set_xlabel("time step k")
ax.set_ylabel(r"fraction of runs rejecting $y_{i,k}$")
ax.set_xlim(0, N)
ax.set_ylim(-0.02, 1.02)
ax.set_title(f"Extra: rejection rate over {R_MC} Monte Carlo runs, Case B (lockout after the windows)", pad=13)
ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
k_rec = np.arange(N, recovery_steps + 1)
rec_data = {"k": k_rec}
for node, curve in rec_curve.items():
    ax2.step(k_rec, curve, where="post", color=node_colors.get(node, "tab:gray"),
             label=f"sensor {node} ({recovery[f'sensor{node}']['locked_runs']} runs locked at k = {N})")
    rec_data[f"still_rejecting{node}"] = curve
if not rec_curve:
    ax2.text(0.5, 0.5, f"no run locked out at k = {N}", transform=ax2.transAxes, ha="center")
ax2.set_xlim(N, recovery_steps)
ax2.set_ylim(-0.02, 1.02)
ax2.set_xlabel("time step k (continuation without attack)")
ax2.set_ylabel("fraction not yet\nresumed")
ax2.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
fig.set_layout_engine("constrained")
plotting.save_data(FIG_DIR, "extra_lockout_recovery", rec_data)  # k only when no run is locked
save(fig, "extra_lockout_rate", data=data)

# %% [markdown]
# **The lockout mechanism (P5) and its cause.** $\Gamma^+$ is a lower bound that holds whether or
# not the update happens: (18) takes $\min\{\Gamma^-,\tilde S_1\}$, the smaller of the two outcomes,
# so $\Gamma$ does not grow while updates are skipped. With the paper's $\kappa$ it has collapsed to
# about $10^{-4}I$ anyway (P6), and $\Gamma_\eta$ stays at its floor $C_iBB^TC_i^T+DD^T$. The prediction
# error, however, grows during the skipped updates of an attack window. If the first clean innovation
# after the window exceeds $\sqrt{\chi^2\,\Gamma_\eta}$ (about 4.2–4.6 at threshold 25), it is rejected
# too. The next prediction is then worse again, and the node runs open loop. The κ = 0 control
# separates the two effects: there $\tilde Q_1\succeq0$ and $\Gamma^+=\Pi^+=P^+$ until a node's first
# rejection (no collapse; printed above), yet the lockout persists (X5 measures that it occurs, against a
# level that can fail). Our reading of the mechanism, not a measured claim: after the first skipped update
# (18) still returns the updated-looking $\tilde S_1$, so the cause is (17)–(18), not the consensus terms. A test normalised by $\Pi_\eta$, which grows while updates are skipped, does not lock
# out, but it lets part of the attack through (X2). Over a longer horizon some locked runs resume
# when an innovation happens to fall inside the acceptance band again; the others keep diverging. The
# paper's Fig. 4(b), like our default run, shows a run without a lockout.

# %% [markdown]
# ## The lockout over the declared space (from the robustness sweep)
#
# `make robustness` runs this notebook in fast mode (100 Monte Carlo runs, a 600-step long run; the same
# interval rules, with wider intervals) at the 33 points of the declared
# space (`notebooks/ding2020.toml`: a 32-point scrambled Sobol design over the eleven swept axes, plus the
# default point) and writes `figures/ding2020/robustness.csv`, which the figure below reads. A point is one
# papermill execution with figures off, about 15 s of CPU; the cost grows linearly with the design.
#
# **Reading the map.** Without attack (right), a $\Gamma_0$ below $P_0$ leaves $\tilde Q_1$ of (17)
# indefinite at $k=0$ (its negative term scales with $\Pi_0$), so $\Gamma^-_1=BB^T$ and the first innovation,
# whose variance is set by $P_0$, is judged against that floor: X3 holds exactly where `gamma0_scale` ≥ 1.01,
# and below it the lockout rate ranges from a few per cent (small $\sigma_0$) to every run (large $\sigma_0$).
# With attack (left), the lockout rate falls with the threshold; at small thresholds almost every run locks out.

# %%
sweep_csv = results.resolve("figures/ding2020/robustness.csv")
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 3.0), layout="constrained")
map_data = {}
if sweep_csv.exists():
    with sweep_csv.open() as fh:
        rows = [r for r in csv.DictReader(fh) if r["status"] == "ok" and r.get("X1.value", "") != ""]
    thr = np.array([float(r["threshold"]) for r in rows])
    g0 = np.array([float(r["gamma0_scale"]) for r in rows])
    x1v = np.array([float(r["X1.value"]) for r in rows])
    x3v = np.array([float(r["X3.value"]) for r in rows])
    is_default = np.array([r["point"] == rows[0]["point"] for r in rows])
    sc = ax.scatter(thr, x1v, c=np.log10(g0), cmap="viridis", s=22, edgecolors="k", lw=0.3)
    sc2 = ax2.scatter(g0, x3v, c=thr, cmap="plasma", s=22, edgecolors="k", lw=0.3)
    for a, xs, ys in ((ax, thr, x1v), (ax2, g0, x3v)):
        a.scatter(xs[is_default], ys[is_default], s=120, facecolors="none", edgecolors="tab:red", lw=1.3,
                  label="default point")
    fig.colorbar(sc, ax=ax, label=r"$\log_{10}$ gamma0_scale")
    fig.colorbar(sc2, ax=ax2, label="threshold")
    map_data = {"threshold": thr, "gamma0_scale": g0, "X1_locked_fraction": x1v, "X3_runs_with_lockout": x3v}
    ax.legend(loc="upper right", fontsize=7)
else:
    for a in (ax, ax2):
        a.text(0.5, 0.5, "no sweep yet: run make robustness", transform=a.transAxes, ha="center")
for a in (ax, ax2):
    a.set_ylim(-0.03, 1.03)
    a.set_ylabel("fraction of Monte Carlo runs")
ax.set_xlabel(r"threshold $\chi^2_{1,\sigma}$ of (25)")
ax.set_title("X1: an attacked sensor locked out at k = 150", fontsize=8)
ax2.set_xscale("log")
ax2.set_xlabel(r"gamma0_scale ($\Gamma_0$ = gamma0_scale $\sigma_0 I$)")
ax2.set_title("X3: runs with a node locked out at k = 150, no attack", fontsize=8)
fig.suptitle("Extra: the chi-square lockout over the declared space (robustness sweep)", fontsize=9)
save(fig, "extra_lockout_map", data=map_data or None)

# %% [markdown]
# ## Theorem 4 for the example
#
# $\xi_q=\zeta\bar\alpha^2\big(1-q+q(1+\kappa)(1+\kappa\bar N)\big)$ and
# $\xi_p=\zeta\bar\alpha^2\big(p+(1-p)(1+\kappa)(1+\kappa\bar N)\big)$ (42)–(43), with
# $\zeta=\big((1+\nu)\underline c^2+\bar c^2(1-\sigma)\big)/\underline c^2$. (41) holds if both are
# below 1.
#
# **Which form the proof implies.** The proof bounds the consensus part of (39) by
# $\tilde\Pi_{\mathcal N_i}=2\kappa(1+\kappa)\sum_{j\in\mathcal N_i\cup\{i\}}A\Pi^+_jA^T$ (36), i.e. with
# $\tilde\kappa=2\kappa(1+\kappa)$ in (44)–(45): the factor 2 is the one of $\tilde\Xi=2\sum\Pi^+_j$.
# Summing (45) over the nodes in (47), each $\lVert\mathbb E\Pi^+_j\rVert$ appears once for its own node and
# once for every neighbour, at most $1+\lvert\mathcal N_j\rvert\le\bar N$ times (undirected graph), so the
# coefficient of $\sum_i\lVert\mathbb E\Pi^+_i\rVert$ under $\mathbf P_{k,0}$ is
# $\zeta\bar\alpha^2\big(1-q+q(1+\kappa)+q\tilde\kappa\bar N\big)=\zeta\bar\alpha^2\big(1-q+q(1+\kappa)(1+2\kappa\bar N)\big)$,
# and likewise for $\xi_p$. The proof therefore implies $(1+\kappa)(1+2\kappa\bar N)$; the printed
# (42)–(43) drop the 2, which makes the printed condition weaker than what the proof establishes (E9). We
# evaluate both; X7 decides on the printed form, the theorem as stated.

# %%
show_source(ding2020.theorem4_condition, after="    c_norms = ")

# %%
thm4 = {}
for form, f in (("printed", 1.0), ("proof_factor2", 2.0)):
    t4 = ding2020.theorem4_condition(A, C_rows, p=p, q=q, kappa=kappa, n_bar=N_bar, nu=nu, sigma=sigma_fa,
                                     factor=f)
    thm4[form] = {"xi_q": t4.xi_q, "xi_p": t4.xi_p}
alpha_bar, zeta, c_lo, c_hi = t4.alpha_bar, t4.zeta, t4.c_lo, t4.c_hi
thm4_holds = bool(thm4["printed"]["xi_q"] < 1 and thm4["printed"]["xi_p"] < 1)
print(f"alpha_bar^2 = {alpha_bar**2:.7f}, c_lo = {c_lo:.4f}, c_hi = {c_hi:.7f}, "
      f"zeta = {zeta:.6f}, zeta*alpha^2 = {zeta * alpha_bar**2:.5f}, N_bar = {N_bar}")
for form, v in thm4.items():
    print(f"{form:>14}: xi_q = {v['xi_q']:.4f}, xi_p = {v['xi_p']:.4f}")

# %% [markdown]
# **The condition fails, and it cannot hold for this plant.** The brackets are at least 1 for
# every $p,q\in[0,1]$ and $\kappa\ge0$, so $\xi_q,\xi_p\ge\zeta\bar\alpha^2$ (equality at $\kappa=0$).
# $\zeta\ge2-\sigma$ whatever $\nu\ge 0$, and $\bar\alpha^2=1.073$, so $\zeta\bar\alpha^2>2$: the condition
# needs $\lVert A\rVert^2\lesssim0.5$, and the paper's target is marginally unstable. So at the example C8b
# fails its premise (its long Case A run is shown).
#
# **Where the condition holds, the conclusion does not need the filter.** By (35),
# $\Pi^+\preceq\Pi^-$ whatever the test decides: an update can only shrink the bound, while the proof's step
# (46) multiplies by $\zeta\ge2-\sigma$. Replace (46) by $\lVert\mathbb E\Pi^+\rVert\le\lVert\mathbb E\Pi^-\rVert$
# ($\zeta$ by 1) in (44)–(47), with the bracket the proof implies, $b_2=(1+\kappa)(1+2\kappa\bar N)$: that
# recursion, which has no measurement in it, contracts if $\bar\alpha^2(1-w+wb_2)<1$ for $w\in\{q,1-p\}$.
# (42)–(43) say $\zeta\bar\alpha^2(1-w+wb_1)<1$ with $b_1=(1+\kappa)(1+\kappa\bar N)$. Since
# $b_2-b_1=(1+\kappa)\kappa\bar N\le b_1-1$ and $\zeta-1\ge1-\sigma$, the first follows from the second whenever
# $\sigma(1+\kappa)\kappa\bar N\le1-\sigma$; for $\kappa<1$ on $m$ nodes, whenever $\sigma\le1/(1+2m)$ (0.024 for
# $m=20$; the declared space has $\sigma\le10^{-2}$). On every such instance that meets (42)–(43), the plant
# itself is stable ($\bar\alpha^2<1/\zeta<1$) and the bound stays bounded without any measurement update,
# whatever the detector, the gains and the channel do: Theorem 4 says nothing about the filter there. No
# instance of ours can exercise it, so contribution 3 is recorded **not checked** (C8, deciding).
#
# The declared instance C8c (the example with $A$ scaled by `thm4_a_scale` = 0.5, ours, where (42)–(43) hold at
# every point of the declared space) shows it. There the contraction is even deterministic: with
# $S_k=\sum_i\lVert\Pi^+_{i,k}\rVert$, (26) and (35) give $S_{k+1}\le cS_k+m\lVert BB^T\rVert$ for every channel
# sequence and every test outcome, with $c=\bar\alpha^2(1+\kappa)(1+2\kappa\bar N)$, because each $\Pi^+_j$ enters
# the $\tilde\Xi$ of itself and its neighbours, at most $\bar N$ times. C8c records $c$ (printed below) and checks
# the long run against $S_k\le c^kS_0+m\lVert BB^T\rVert(1-c^k)/(1-c)$: by construction, not evidence. Until
# round 4 of issue #30, C8c decided Theorem 4, with C8b's growth level 1.5, which was set post hoc.

# %%
delta_long = channels.gilbert_elliott(p, q, L_LONG + 1, rng_long, initial=delta0).astype(float)
world_long = draw_world(rng_long, 1, L_LONG)
long_run = simulate(world_long["xh0"], world_long["y"], delta_long, keep_bounds=True)
tr_pi_max = np.trace(long_run["Pi"][0], axis1=-2, axis2=-1).max(axis=1)
split = L_LONG // 2
burn = min(100, split // 2)
early = float(tr_pi_max[burn:split + 1].max())
late = float(tr_pi_max[split:].max())
long_rejections = int((long_run["theta"] == 0).sum())
print(f"{L_LONG} steps: max_i tr Pi+ in [{burn}, {split}] = {early:.3f}, in [{split}, {L_LONG}] = "
      f"{late:.3f}, min over k >= {burn} = {tr_pi_max[burn:].min():.3f}; rejections: {long_rejections}")

fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 2.2))
ax.plot(np.arange(L_LONG + 1), tr_pi_max, color="tab:blue", lw=0.7,
        label=r"$\max_i \mathrm{tr}\,\Pi^+_{i,k}$")
ax.axhline(1.5 * early, color="k", ls="--", lw=0.8, label="1.5 × max over the first half (C8b limit)")
ax.set_yscale("log")
ax.set_xlabel("time step k")
ax.set_ylabel(r"$\max_i \mathrm{tr}\,\Pi^+_{i,k}$" + "\n[mixed units]")
ax.set_xlim(0, L_LONG)
ax.set_title(f"Extra: the upper bound over {L_LONG} steps (Case A); (42)–(43) fail")
ax.set_ylim(0.5 * tr_pi_max.min(), 3 * max(early, tr_pi_max.max()))
ax.legend(loc="lower right", fontsize=7)
save(fig, "extra_pi_long_run", data={"k": np.arange(L_LONG + 1), "max_tr_Pi": tr_pi_max})

# C8c: the declared instance, A scaled by thm4_a_scale, on the same channel chain and fresh draws
A_s = thm4_a_scale * A
thm4_s = {form: {k_: getattr(ding2020.theorem4_condition(A_s, C_rows, p=p, q=q, kappa=kappa, n_bar=N_bar, nu=nu,
                                                          sigma=sigma_fa, factor=f), k_) for k_ in ("xi_q", "xi_p")}
          for form, f in (("printed", 1.0), ("proof_factor2", 2.0))}
thm4_s_holds = bool(max(thm4_s["printed"].values()) < 1)
zeta_alpha2_s = {f"nu{nu_:g}": float((t_ := ding2020.theorem4_condition(
    A_s, C_rows, p=p, q=q, kappa=kappa, n_bar=N_bar, nu=nu_, sigma=sigma_fa)).zeta * t_.alpha_bar**2)
    for nu_ in (0.0, 1.0)}  # the instance's infimum of xi at the ends of the declared nu range
x_s = np.empty((1, L_LONG + 1, n_x))
x_s[:, 0] = np.sqrt(sigma0) * rng_long.standard_normal((1, n_x))
xh0_s = np.sqrt(sigma0) * rng_long.standard_normal((1, m, n_x))
w_s = rng_long.standard_normal((1, L_LONG, n_x))
for k in range(L_LONG):
    x_s[:, k + 1] = x_s[:, k] @ A_s.T + w_s[:, k] @ B.T
y_s = measure(x_s, rng_long.standard_normal((1, L_LONG + 1, m)))
run_s = ding2020.secure_filter(
    xh0_s, initial_bound(None, pi0_scale, 1), initial_bound(None, gamma0_scale, 1), delta_long, y_s[..., None],
    A=A_s, BBt=BBt, C=C, DDt=DDt, adj=adj, weights=H, kappa=kappa, threshold=threshold, inspect=inspection,
    inspection_cov="Gamma", tol=tol, strict=strict, keep=("Pi_post",))
tr_s = np.trace(run_s.history["Pi_post"][0], axis1=-2, axis2=-1).max(axis=1)  # k = 1..L_LONG
early_s, late_s = float(tr_s[burn - 1:split].max()), float(tr_s[split - 1:].max())
rej_s = int((run_s.theta == 0).sum())
print(f"C8c instance (A x {thm4_a_scale:g}): xi {thm4_s}; max_i tr Pi+ in [{burn}, {split}] = {early_s:.4f}, "
      f"in [{split}, {L_LONG}] = {late_s:.4f}; rejections: {rej_s}")


def contraction_factor(A_: np.ndarray) -> float:
    """c = ||A||^2 (1 + kappa)(1 + 2 kappa N_bar): S_{k+1} <= c S_k + m ||BB^T|| by (26), (35), any delta, any test."""
    return float(np.linalg.norm(A_, 2) ** 2 * (1 + kappa) * (1 + 2 * kappa * N_bar))


c_s, c_ex = contraction_factor(A_s), contraction_factor(A)
S_s = np.linalg.eigvalsh(np.concatenate([initial_bound(None, pi0_scale, 1)[:, None], run_s.history["Pi_post"]], axis=1)[0])
S_s = S_s[..., -1].sum(axis=1)  # S_k = sum_i ||Pi+_{i,k}||, k = 0..L_LONG
tau = float(np.linalg.eigvalsh(BBt)[-1])
powers = c_s ** np.arange(L_LONG + 1)
S_bound = powers * S_s[0] + m * tau * (1 - powers) / (1 - c_s) if c_s < 1 else np.full(L_LONG + 1, np.inf)
S_excess = float(np.max(S_s[1:] / S_bound[1:]))  # k >= 1 (equality at k = 0); <= 1 whenever c < 1, by (26), (35)
# (42)-(43) imply the contraction of (44)-(47) without the update whenever sigma (1 + kappa) kappa N_bar <= 1 - sigma
implication_lhs = float(sigma_fa * (1 + kappa) * kappa * N_bar)
print(f"contraction factor c = ||A||^2 (1+kappa)(1+2 kappa N_bar): instance {c_s:.4f}, example {c_ex:.4f}; "
      f"instance: max_k S_k / bound_k = {S_excess:.4f}, limsup bound m||BB^T||/(1-c) = "
      f"{m * tau / (1 - c_s) if c_s < 1 else float('inf'):.4f}, S at the end {S_s[-1]:.4f}; "
      f"sigma (1+kappa) kappa N_bar = {implication_lhs:.3g} <= 1 - sigma = {1 - sigma_fa:.6f}")

# %% [markdown]
# ## The channel statistics (C6)
#
# $\hat p=\#(1\to0)/\#1$ and $\hat q=\#(0\to1)/\#0$ over consecutive pairs, on a long chain and on
# the samples of Fig. 2. Given the number of visits to a state, each transition count is binomial,
# so a Wilson interval applies to each rate.


# %%
def transitions(d: np.ndarray) -> tuple[int, int, int, int]:
    """(#(1 -> 0), #1, #(0 -> 1), #0) over consecutive pairs of the 0/1 sequence d."""
    a, b = d[:-1], d[1:]
    return (int(np.sum((a == 1) & (b == 0))), int(np.sum(a == 1)),
            int(np.sum((a == 0) & (b == 1))), int(np.sum(a == 0)))


chain = channels.gilbert_elliott(p, q, chain_steps, rng_chain, initial=delta0)
n10, n1, n01, n0 = transitions(chain)
p_hat, q_hat, frac1 = n10 / n1, n01 / n0, float(chain.mean())
p_ci = montecarlo.wilson_interval(n10, n1, level=0.999)
q_ci = montecarlo.wilson_interval(n01, n0, level=0.999)
f10, f1, f01, f0 = transitions(delta)
stationary = channels.gilbert_elliott_stationary(p, q)
print(f"{chain_steps} steps: p_hat = {p_hat:.4f} (99.9 % Wilson {p_ci[0]:.4f}-{p_ci[1]:.4f}), q_hat = {q_hat:.4f} "
      f"({q_ci[0]:.4f}-{q_ci[1]:.4f}), fraction of ones = {frac1:.4f} (stationary {stationary:.5f}); "
      f"Fig. 2: {f10}/{f1} failures, {f01}/{f0} recoveries")

# %% [markdown]
# ## Vectorised against per-node implementation (X8) and Remark 4 (C7)
#
# Twenty steps of Case B, once with `secure_filter_step` for all nodes and once with
# `secure_filter_node_step` node by node. The per-node step receives only the node's own data and its
# neighbours' packets:

# %%
show_source(ding2020.secure_filter_node_step, after="    x_i, P_i, G_i, xs")

# %% [markdown]
# **Remark 4 (C7)** says that node $i$'s step needs two inversions and $52+3\lvert\mathcal N_i\rvert$ matrix
# products, a cost independent of the network size. That cost is measured only by `make bench` (timings,
# not committed) and is not evidence here. C7 records, at a fixed degree as the network grows, the size of
# the step's arguments and its calls of `np.linalg.inv`: constant by construction (the step receives only
# local data). So contribution 2's "computational complexity ... unrelated to the scale of underlying SNs"
# cannot be measured here: C12 records it, deciding, as not checked. X8, the agreement of the per-node step
# with the network-wide one, is a check of our code.

# %%
nbrs = graphs.neighbours(adj)
x_vec, Pi_vec, G_vec = world["xh0"].copy(), initial_bound(None, pi0_scale, 1), initial_bound(None, gamma0_scale, 1)
x_loop, Pi_loop, G_loop = x_vec[0].copy(), Pi_vec[0].copy(), G_vec[0].copy()
steps_c10 = min(20, N)
for k in range(steps_c10):
    st = ding2020.secure_filter_step(x_vec, Pi_vec, G_vec, delta[k], y_attacked[:, k + 1, :, None],
                                    A=A, BBt=BBt, C=C, DDt=DDt, adj=adj, weights=H, kappa=kappa,
                                    threshold=threshold, inspect=inspection, tol=tol, strict=strict)
    x_vec, Pi_vec, G_vec = st.x_post, st.Pi_post, st.Gamma_post
    new = [ding2020.secure_filter_node_step(
        x_loop[i], Pi_loop[i], G_loop[i], x_loop[nbrs[i]], Pi_loop[nbrs[i]], H[i, nbrs[i]],
        int(delta[k]), y_attacked[0, k + 1, i:i + 1], A=A, BBt=BBt, C_i=C[i], DDt=DDt,
        kappa=kappa, threshold=threshold, inspect=inspection, tol=tol, strict=strict) for i in range(m)]
    x_loop = np.stack([r[0] for r in new])
    Pi_loop = np.stack([r[1] for r in new])
    G_loop = np.stack([r[2] for r in new])
c10_diff = float(max(np.abs(x_vec[0] - x_loop).max(),
                     np.abs(Pi_vec[0] - Pi_loop).max() / np.abs(Pi_loop).max(),
                     np.abs(G_vec[0] - G_loop).max() / max(np.abs(G_loop).max(), 1e-300)))
C7_SIZES = (20, 40, 80, 160, 320)  # network sizes at a fixed degree (ours)
C7_DEGREE = 4  # every node of the ring lattice circulant_graph(N, [1, 2]) has 4 neighbours (ours)


def node_step_footprint(m_net: int) -> dict:
    """What one call of secure_filter_node_step for node 1 of an m_net-node ring lattice reads and calls.

    The network's estimates and bounds are drawn with seed m_net; the step is profiled (sys.setprofile):
    elements read = total size of its arguments; Python-level calls, and among them calls of np.linalg.inv.
    Matrix products are operators, invisible to the profiler, so they are not counted.
    """
    adj_r = nx.to_numpy_array(nx.circulant_graph(m_net, [1, 2]))
    H_r = graphs.row_stochastic_weights(adj_r, self_weight=False)
    rng_r = np.random.default_rng(m_net)
    x_r = rng_r.standard_normal((m_net, n_x))
    Pi_r = np.broadcast_to(pi0_scale * sigma0 * np.eye(n_x), (m_net, n_x, n_x))
    nb = np.flatnonzero(adj_r[0])
    args = (x_r[0], Pi_r[0], gamma0_scale * sigma0 * np.eye(n_x), x_r[nb], Pi_r[nb], H_r[0, nb], 1,
            C_rows[0] @ x_r[0] + rng_r.standard_normal(1))
    calls: Counter = Counter()

    def profile(frame, event, arg):
        if event == "call":
            calls[frame.f_code.co_name] += 1

    sys.setprofile(profile)
    try:
        ding2020.secure_filter_node_step(*args, A=A, BBt=BBt, C_i=C[0], DDt=DDt, kappa=kappa, threshold=threshold,
                                         inspect=inspection, tol=tol, strict=strict, validate=False)
    finally:
        sys.setprofile(None)
    return {"neighbours": int(nb.size), "elements_read": int(sum(np.size(a) for a in args)),
            "python_calls": int(sum(calls.values())), "inversions": int(calls["inv"])}


c7 = {str(n_): node_step_footprint(n_) for n_ in C7_SIZES}
for n_, f_ in c7.items():
    print(f"N = {n_:>3}: {f_}")
print(f"max |vectorised - per-node| after {steps_c10} steps: x {np.abs(x_vec[0] - x_loop).max():.2g}, "
      f"Pi {np.abs(Pi_vec[0] - Pi_loop).max():.2g}, Gamma {np.abs(G_vec[0] - G_loop).max():.2g}")

# %% [markdown]
# ## Claims
#
# RMSE means position RMSE; a window is the attacked sensor's attack window. Each claim carries the
# paper's place (`source`), the rule (`check`) and, for Monte Carlo values, a 95 % interval (Wilson for
# fractions, bootstrap for medians and ratios, from at least 30 runs) and the run count (`runs`). Every level
# not in the paper is ours, with its reason or marked post hoc (set after the brief's indicative run).
#
# **Outcomes.** `holds`, `fails`, `fails-premise` (the paper's premise, or a stated precondition of our
# measurement, fails) and `not-checked` (a limit of ours: too few runs, an undecided working precondition, a
# check our propagation cannot make, or a statement no measurement here can test: C8, C12). Basis `by-construction` (C6, C7, C8c, C11, X4,
# X8) marks a claim true by how we built it or by the algebra of the recursion: shown, never evidence.
#
# **The interval rule (ours), the same at every run count.** A Monte Carlo claim states a level once and
# decides on its 95 % interval: holds if the interval lies on the claimed side, fails if wholly on the other, `not-checked` if
# it contains the level (`decide` above). An earlier rule ("lower bound ≥ 0.95, else fails") needed every one
# of 100 runs at 100 runs but allowed 7 misses at 300.
#
# **The measured sensors must work without attack (precondition).** A sensor that its own attack-free
# Case A locks out runs open loop with or without attack, so its curve or rate cannot show the attack.
# C1, C3, C4, C9 (under attack), X1 and X2 are measured over the Monte Carlo runs where the attacked sensor
# works without attack; C2a, in each run, compares the plotted sensors free of lockout in that run's Case A and
# counts the run only if an attacked one is among them (the unattacked sensor 20 alone cannot show an attack's
# effect). The precondition itself is decided on an interval, like the claims: the working (eligible)
# fraction's 95 % Wilson interval against 0.5 (`WORKING_LEVEL`, ours, post hoc: set in r7 of the review after the
# 98-of-300 result of C2a and the sweep at e86f45a were known; a filter that works without attack in
# fewer than half of its runs is not a working filter): fails-premise if the interval lies wholly below 0.5,
# not checked if it contains 0.5, whatever the run count. C1 and C3 also need it in the default run, which
# their own check uses (C1 is thus decided partly on that one run). C9's precondition gates its part (ii) only:
# part (i), "similar when there are no attacks", is measured over all runs and decides alone (a filter that locks
# out without attack is what would fail it). X5 counts, as X1 does, only the runs where the sensor works without
# attack up to k = N, here at κ = 0, under the same rule. X6 uses the topologies where the sensors work: a count
# over a fixed list of 10 declared topologies, one run each, not over Monte Carlo runs. Until r7 of the review the precondition was
# "in at least one Monte Carlo run", a count whose meaning changed with the run count (a filter locking out
# without attack in 299 of 300 runs met it); before 2026-12-03 it was a level 0.8 on X3's rate, set after the
# first review.
#
# **Which claims decide the verdict (`decides`).** The paper's main statements (abstract, Sec. I's three
# contributions, Remark 6, Sec. VI), each by a measured claim that can fail, or `not-checked` where none can:
# (1) the filter with an embedded χ² detector, shown effective in Sec. V: C1 (Remark 1's "remove"), C2a, C4.
# The paper's aim R1), "an upper bound of estimation error covariance is guaranteed ... $P^+_{i,k}\le\Pi^+_{i,k}$"
# (8), achieved by Theorem 3 (with Theorem 1's lower bound): C5. (The abstract's "sufficient conditions ...
# ensure the existence of an upper bound" begins "By means of the failure and recovery rates": in the paper's
# usage those are Theorem 4's conditions on $p$, $q$, contribution 3, not C5.) That the gain (32) minimises
# the bound's trace holds by the algebra of (31)–(32) (C11, by construction). (2) "the computational
# complexity is ... unrelated to the scale of underlying SNs" holds by construction where it is measured: the
# per-node step's footprint is constant because it receives only local data (C7), and its cost is timed only
# by `make bench`; so contribution 2 decides as not checked (C12). (3) The boundedness under the condition on
# the failure and recovery rates (Theorem 4) holds vacuously where it can be evaluated: the example cannot
# meet (42)–(43) (X7; C8b at the example fails its premise), and on every instance that meets them the
# conclusion follows from the premise without the filter (C8c, by construction); so contribution 3 decides as
# not checked (C8). This is the project's one rule (`rescience_verdict`: "a contribution that cannot be
# measured here decides as not-checked"), the same for all five papers: it makes the verdict at best
# [Re, partial] before anything is measured, and says so. C3 and C9 are further readings of the figures.

# %%
INSPECTION_PREMISE = ("the chi-square inspection (25) is applied (inspection = true)", inspection)
# A claim about the attack's effect needs the measured sensors to work without attack (precondition of
# the measurement): a sensor its own Case A locks out (LOCK_STEPS consecutive rejections) runs open loop
# with or without attack, so there the attack cannot show. The Monte Carlo claims are measured over the runs
# where the sensor works; the precondition is decided on the working fraction's 95 % Wilson interval against
# WORKING_LEVEL (ours), so that its meaning does not change with the run count: it fails if the interval lies
# wholly below the level, and leaves the claim not checked if it contains the level.
# ours, post hoc: set in r7 of the review, after the 98-of-300 result and the sweep at e86f45a were known: an attack-free filter that works in fewer than half of its runs is not a working filter
WORKING_LEVEL = 0.5
runs_locked_a = int(locked_a.any(axis=1).sum())
x3_ci = wilson(runs_locked_a, R_MC)
default_works = all(bool(works(case_a["theta"], n - 1, ks[-1])[0]) for n, ks in windows.items())
PREMISE_UNDECIDED = (f"the 95 % Wilson interval of an attacked sensor's working fraction (runs without a Case-A "
                     f"lockout) contains the precondition's level {WORKING_LEVEL:g} (ours) at this run count: "
                     "whether the attack-free filter works is itself undecided")


def works_premise(counts: list[int], text: str, extra: bool = True) -> tuple[tuple[str, bool], bool]:
    """The working precondition on the Wilson intervals of the working fractions counts / R_MC (ours).

    Returns the claim's premise pair (fails if inspection is off, `extra` is False, or an interval lies wholly
    below WORKING_LEVEL) and whether it is undecided (an interval contains the level; the claim is then not
    checked).
    """
    votes = [decide(wilson(c, R_MC), WORKING_LEVEL, "above") for c in counts]
    statement = (f"inspection (25) applied; precondition of the measurement (ours): {text}, decided on the 95 % "
                 f"Wilson interval of the working fraction over the {R_MC} Monte Carlo runs against "
                 f"{WORKING_LEVEL:g} (ours, post hoc: set in r7 of the review, after the 98-of-300 result and the sweep at "
                 f"e86f45a were known; fails if it lies wholly below; not checked if it contains "
                 f"{WORKING_LEVEL:g}); until r7 of the review: 'in at least one Monte Carlo run', a count")
    return (statement, bool(inspection and extra and not any(v is False for v in votes))), any(v is None for v in votes)


def gated(holds_: bool | None, undecided: bool, reason: str | None = None) -> tuple[bool | None, str | None]:
    """(holds, not_checked) of a claim whose premise may be undecided (then not checked, whatever was measured)."""
    if undecided:
        return None, PREMISE_UNDECIDED
    return holds_, (None if holds_ is not None else (reason or MC_UNDECIDED))


WORKS_TEXT = "each attacked sensor works without attack (no Case-A lockout up to its window's end)"
MC_PREMISE, MC_UNDECIDED_PREMISE = works_premise([mc_stats[n]["working_runs"] for n in windows],
                                                 WORKS_TEXT + " in at least half of the runs")
MC_DEFAULT_PREMISE, _ = works_premise(
    [mc_stats[n]["working_runs"] for n in windows],
    WORKS_TEXT + " in at least half of the runs, and in the default run (whose own check needs it)",
    extra=default_works)
N_PREMISE, N_UNDECIDED_PREMISE = works_premise(
    [mc_stats[n]["working_runs_to_N"] for n in windows],
    f"each attacked sensor works without attack up to k = {N} in at least half of the runs")
working_fraction = {f"sensor{n}": mc_stats[n]["working_runs"] / R_MC for n in windows}


def frac(count: int, n: int) -> float | None:
    """count / n, None without runs."""
    return count / n if n else None


def worst(values: dict, pick=min):
    """The key of `values` with the smallest (pick=min) or largest (max) value, None entries last."""
    big = float("inf") if pick is min else -float("inf")
    return pick(values, key=lambda k: big if values[k] is None else values[k])


claims = {}
att_names = [f"sensor{node}" for node in windows]

# C1: detection
rejected_b = {(int(k), int(i) + 1) for k, i in rej_b}
expected_b = {(int(k), node) for node, ks in windows.items() for k in ks}
c1_runs = {n: frac(mc_stats[n]["runs_all_window_rejected"], mc_stats[n]["working_runs"]) for n in windows}
c1_worst = worst(c1_runs)
c1_ci = (wilson(mc_stats[c1_worst]["runs_all_window_rejected"], mc_stats[c1_worst]["working_runs"])
         if mc_stats[c1_worst]["working_runs"] else None)
claims["C1"] = results.claim(
    paper="Remark 1: 'the innovation inspection is introduced to remove the abnormal data or outliers that might "
    "result from false data-injection attacks or abnormal interferences of sensors'; its effect shown in Sec. V, "
    "Fig. 4(b) ('benefiting from the capability of designed detection scheme')",
    check="default run: every attacked (k, sensor) sample rejected in Case B; Monte Carlo, over the runs where "
    "the sensor works without attack: fraction rejecting every attacked sample, worse sensor, against 0.95 "
    "by the interval rule (Wilson); rejections outside the windows reported. The level is ours: 'remove' "
    "(Remark 1), unqualified, means every run, which no finite Monte Carlo can confirm; 0.95 is the strictest level on a "
    "5 % grid that a flawless result at the sweep's 100 runs can confirm (Wilson lower bound at 100 of 100: "
    "0.963), so the rule asks as much as the design can show. C1 is decided partly on the single default run "
    "(the figure's seed): a missed attacked sample there makes C1 fail, and a Case-A lockout of an attacked sensor "
    "there makes it fail its premise, whatever the Monte Carlo runs say (at the example that run rejects all of "
    "its attacked samples)",
    measured={"default_rejected_in_windows": len(rejected_b & expected_b),
              "default_attacked_samples": len(expected_b),
              "default_rejections_elsewhere": len(rejected_b - expected_b) + int(rej_a.shape[0]),
              "mc_runs_all_rejected": {f"sensor{n}": v for n, v in c1_runs.items()},
              "mc_runs_all_rejected_min": c1_runs[c1_worst],
              "mc_reject_rate_window": {f"sensor{n}": mc_stats[n]["reject_rate_window"] for n in windows},
              "mc_working_runs": {f"sensor{n}": mc_stats[n]["working_runs"] for n in windows}, "mc_runs": R_MC},
    threshold={"mc_runs_all_rejected_lower_bound": 0.95, "working_fraction_premise_level": WORKING_LEVEL},
    holds=(c1_g := gated(all3(expected_b <= rejected_b, decide(c1_ci, 0.95, "above")), MC_UNDECIDED_PREMISE))[0],
    not_checked=c1_g[1],
    source="Remark 1; Sec. V, Fig. 4(b); test (25)", interval=c1_ci, premise=MC_DEFAULT_PREMISE,
    key="mc_runs_all_rejected_min", tolerance=MC_TOL, decides=True, runs=R_MC,
    section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# C2a: the paper's visual statement, decided over the Monte Carlo runs (the default run is an illustration)
c2a_ok = [f"sensor{n}" for n in plot_nodes if bool(works(case_a["theta"], n - 1, N)[0])]  # free of Case-A lockout
c2a_att_ok = [f"sensor{n}" for n in plot_nodes if n in windows and f"sensor{n}" in c2a_ok]  # attacked among them
c2a_ratio = max((c2a[k]["shift"] / c2a[k]["case_a_error"] for k in c2a_ok), default=None)
PLOT_ATT = [n - 1 for n in plot_nodes if n in windows]  # attacked plotted sensors (indices)
c2a_free = np.stack([works(mc["A"]["theta"], n - 1, N) for n in plot_nodes], axis=1)  # (R, plotted)
c2a_shift = np.abs(mc["B"]["x"][..., 0] - mc["A"]["x"][..., 0]).max(axis=1)[:, PLOT]  # (R, plotted)
c2a_own = np.abs(mc_err["A"][:, 1:]).max(axis=1)[:, PLOT]
c2a_run_ratio = np.where(c2a_free, c2a_shift / c2a_own, -np.inf).max(axis=1)  # per run, over its compared sensors
c2a_eligible = c2a_free[:, [k for k, n in enumerate(plot_nodes) if n in windows]].any(axis=1)
c2a_n = int(c2a_eligible.sum())
c2a_meet = int((c2a_run_ratio[c2a_eligible] <= 1.0).sum())
c2a_ci = wilson(c2a_meet, c2a_n) if c2a_n else None
c2a_med, c2a_med_ci = ratio(c2a_run_ratio[c2a_eligible], np.ones(c2a_n))
c2a_lock = mc_locked["B"][:, PLOT_ATT].any(axis=1)[c2a_eligible]  # an attacked plotted sensor locked out at N (X1)
c2a_runs_meet = c2a_run_ratio[c2a_eligible] <= 1.0
# ours, post hoc: set in r7 of the review, after the 98-of-300 result and the sweep at e86f45a were known: Fig. 4 is one run offered as typical; the median run must show no obvious effect
C2A_LEVEL = 0.5
c2a_prem = decide(wilson(c2a_n, R_MC), WORKING_LEVEL, "above")
claims["C2a"] = results.claim(
    paper="Sec. V: 'Combining Fig. 4(a) and Fig. 4(b), we can find that there is no obvious effect on the "
    "filtering performance with or without attacks benefiting from the capability of designed detection "
    "scheme'",
    check="per run (rule ours, the paper gives none): each plotted sensor's shift max_k |x_hat_B(1) - x_hat_A(1)| "
    "against its own Case A error max_{k>=1} |x_hat_A(1) - x_1|; a run shows no obvious effect if no compared "
    "curve is moved by the attack further than its own error without attack (max over sensors of shift / Case A "
    "error <= 1), over the plotted sensors free of Case-A lockout in that run, of which at least one must be "
    "attacked (else the run is not eligible: an unattacked sensor alone cannot show an attack's effect). Decided "
    f"over the Monte Carlo runs: the fraction of eligible runs meeting the per-run rule against {C2A_LEVEL:g} by "
    "the interval rule (Wilson); the level is ours, post hoc (set in r7 of the review, after the 98-of-300 result "
    "and the sweep at e86f45a were known): Fig. 4 shows one run offered as typical, read as the median "
    "run (at least half the runs), which is our reading; the median ratio and its bootstrap interval are reported, and the fraction "
    "meeting the rule among the eligible runs with and without an attacked plotted sensor locked out at k = N in "
    "Case B (X1's lockout). The default run "
    "(seed 2020, the figure's run) is an illustration, not the decision (until r7 of the review C2a was decided "
    "on it alone)",
    measured={"default_run": {**c2a, "axis_range": axis_range, "max_shift_over_case_a_error": c2a_ratio,
                              "compared_sensors": c2a_ok, "compared_attacked_sensors": c2a_att_ok},
              "mc_runs": R_MC, "mc_eligible_runs": c2a_n, "mc_runs_meeting_rule": c2a_meet,
              "mc_fraction_meeting_rule": frac(c2a_meet, c2a_n),
              "mc_median_max_shift_over_case_a_error": c2a_med,
              "mc_median_ci": [c2a_med_ci["low"], c2a_med_ci["high"]] if c2a_med_ci else None,
              "mc_eligible_fraction": c2a_n / R_MC,
              "mc_eligible_runs_locked_in_case_b": int(c2a_lock.sum()),
              "mc_fraction_meeting_rule_if_locked": frac(int(c2a_runs_meet[c2a_lock].sum()), int(c2a_lock.sum())),
              "mc_fraction_meeting_rule_if_not_locked": frac(int(c2a_runs_meet[~c2a_lock].sum()),
                                                             int((~c2a_lock).sum()))},
    threshold={"mc_fraction_meeting_rule_lower_bound": C2A_LEVEL, "per_run_max_shift_over_case_a_error": 1.0,
               "eligible_fraction_premise_level": WORKING_LEVEL},
    holds=(c2a_g := gated(decide(c2a_ci, C2A_LEVEL, "above"), c2a_prem is None))[0], not_checked=c2a_g[1],
    source="Sec. V, Figs. 4(a)-(b)", key="mc_fraction_meeting_rule", interval=c2a_ci, runs=R_MC,
    premise=(f"inspection (25) applied; precondition of the measurement (ours): an attacked sensor is plotted, and "
             f"a run is eligible when an attacked plotted sensor is free of Case-A lockout in it; the eligible "
             f"fraction's 95 % Wilson interval over the {R_MC} runs does not lie wholly below {WORKING_LEVEL:g} "
             "(ours, post hoc: set in r7 of the review, after the 98-of-300 result and the sweep at e86f45a were "
             "known; not checked if it contains it). Until r7 of the review: at least one attacked plotted sensor free of "
             "lockout in the default run",
             bool(inspection and PLOT_ATT and c2a_prem is not False)),
    tolerance=MC_TOL, decides=True,
    section='"No obvious effect" between Figs. 4(a) and 4(b) (claim C2a) and the leak by hop (X6)',
)

# X6 (was C2b): how the leak decays with the hop distance (ours)
hop_keys = sorted(leak_stats, key=int)
meds = [leak_stats[h_]["median"] for h_ in hop_keys]
decays = [b <= 0.1 * a for a, b in zip(meds[:-1], meds[1:], strict=True)]
ratios = [a / b if b > 0 else None for a, b in zip(meds[:-1], meds[1:], strict=True)]
finite = [r for r in ratios if r is not None]
claims["X6"] = results.claim(
    paper="(ours, no paper statement) the attack reaches unattacked nodes only through the consensus term "
    "and the neighbours' bounds, so its effect decays with the hop distance from the attacked sensors",
    check=f"criterion (ours): over all unattacked nodes of the {len(leak_topology_seeds)} stand-in "
    "topologies of leak_topology_seeds, the median leak max_k ||x_hat_B - x_hat_A||_inf at hop distance "
    "h+1 is at most 1/10 of that at h, for every h (exactly 0 leaks, as at kappa = 0, satisfy it; a leak at "
    "or below 1e-12, the leak data's declared resolution, is recorded as 0); only topologies whose attacked "
    "sensors work without attack (no Case-A lockout up to their windows' end) are used",
    measured={"by_hops": leak_stats, "median_ratio_per_hop": ratios,
              "min_median_ratio_per_hop": min(finite) if finite else None, "topologies_used": leak_kept},
    threshold={"median_ratio_per_hop": 10.0},
    holds=bool(decays and all(decays)),
    source="ours", key="min_median_ratio_per_hop", tolerance=RUN_TOL,
    premise=("inspection (25) applied; precondition: in at least one topology the attacked sensors work "
             "without attack (no Case-A lockout up to their windows' end); a count over a fixed list of "
             f"{len(leak_topology_seeds)} declared stand-in topologies (leak_topology_seeds, one run each), not "
             "over Monte Carlo runs, so its meaning does not depend on a run count (not the interval rule of the "
             "other claims' working precondition)",
             bool(inspection and leak_kept > 0)),
    section='"No obvious effect" between Figs. 4(a) and 4(b) (claim C2a) and the leak by hop (X6)',
)

# C3: mild effect with detection
c3_worst = worst({n: mc_stats[n]["median_B_over_A"] for n in windows}, max)
c3_ci = mc_stats[c3_worst]["ci_B_over_A"]
max_err_b = {f"sensor{node}": float(np.abs(err["B"][0, ks, node - 1]).max()) for node, ks in windows.items()}
med_ratio = {f"sensor{node}": mc_stats[node]["median_B_over_A"] for node in windows}
claims["C3"] = results.claim(
    paper="Sec. V: 'there is no obvious effect on the filtering performance with or without attacks benefiting "
    "from the capability of designed detection scheme'",
    check="our reading (ours) on the attacked sensors' windows: Monte Carlo, over the runs where the sensor works "
    "without attack: median RMSE_B/RMSE_A over the window at each attacked sensor against 3 by the interval "
    "rule (bootstrap); default run: max |position error| in the window <= 2; both levels post hoc (set after "
    "the brief's indicative run), so C3 does not decide",
    measured={"mc_median_ratio": med_ratio, "mc_median_ratio_max": mc_stats[c3_worst]["median_B_over_A"],
              "mc_ci_upper": {f"sensor{n}": (mc_stats[n]["ci_B_over_A"] or {}).get("high") for n in windows},
              "mc_ci_lower": {f"sensor{n}": (mc_stats[n]["ci_B_over_A"] or {}).get("low") for n in windows},
              "default_max_abs_error": max_err_b, "mc_working_fraction": working_fraction},
    threshold={"mc_median_ratio_upper_bound": 3.0, "default_max_abs_error": 2.0,
               "working_fraction_premise_level": WORKING_LEVEL},
    holds=(c3_g := gated(all3(*(decide(mc_stats[n]["ci_B_over_A"], 3.0, "below") for n in windows),
                              max(max_err_b.values()) <= 2.0), MC_UNDECIDED_PREMISE))[0],
    not_checked=c3_g[1],
    source="Sec. V, Figs. 4(a)-(b)", interval=c3_ci, premise=MC_DEFAULT_PREMISE, key="mc_median_ratio_max",
    tolerance=MC_TOL, runs=R_MC, section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# C4: degradation without inspection
c4_worst = worst({n: mc_stats[n]["median_noinsp_over_B"] for n in windows})
ratio_na = {f"sensor{node}": float(rmse(err["N"], ks, node - 1)[0] / rmse(err["A"], ks, node - 1)[0])
            for node, ks in windows.items()}
med_nb = {f"sensor{n}": mc_stats[n]["median_noinsp_over_B"] for n in windows}
claims["C4"] = results.claim(
    paper="Sec. V, Fig. 4(c): without the inspection 'the filtering performance is degraded at attack "
    "instants' (in comparison with Fig. 4(b))",
    check="Monte Carlo, over the runs where the sensor works without attack: median RMSE_noinsp/RMSE_B over "
    "the window at each attacked sensor against 1 ('degraded': worse than with the inspection) by the "
    "interval rule (bootstrap); the default run's ratio to Case A and the 5th percentiles reported; until "
    "2026-12-03 the level was 2.5, set after the brief's indicative run",
    measured={"mc_median_ratio_vs_B": med_nb, "mc_median_ratio_vs_B_min": mc_stats[c4_worst]["median_noinsp_over_B"],
              "mc_ci_lower": {f"sensor{n}": (mc_stats[n]["ci_noinsp_over_B"] or {}).get("low") for n in windows},
              "mc_ci_upper": {f"sensor{n}": (mc_stats[n]["ci_noinsp_over_B"] or {}).get("high") for n in windows},
              "mc_p05_ratio_vs_B": {f"sensor{n}": mc_stats[n]["p05_noinsp_over_B"] for n in windows},
              "default_ratio_vs_A": ratio_na, "mc_working_fraction": working_fraction},
    threshold={"mc_median_ratio_lower_bound": 1.0, "working_fraction_premise_level": WORKING_LEVEL},
    holds=(c4_g := gated(all3(*(decide(mc_stats[n]["ci_noinsp_over_B"], 1.0, "above") for n in windows)),
                         MC_UNDECIDED_PREMISE))[0],
    not_checked=c4_g[1],
    source="Sec. V, Fig. 4(c)", interval=mc_stats[c4_worst]["ci_noinsp_over_B"], premise=MC_PREMISE,
    key="mc_median_ratio_vs_B_min", tolerance=MC_TOL, decides=True, runs=R_MC,
    section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# C5: bounds against the exact covariance, with MC cross-check
clean_runs = np.all(mc["A"]["theta"] == 1, axis=(1, 2))
n_clean = int(clean_runs.sum())
C5_BAND = (0.9, 1.1)  # ours: a gross-error check of our propagation against our simulation (reason in C5's check)
mc_tr_ratio, mc_tr_ci, mc_ok = None, None, True
if n_clean >= 30:  # a bootstrap over fewer runs is not trusted (ours); the cross-check is then skipped
    e_mc = (mc_world["x"][:, :, None, :] - mc["A"]["x"])[clean_runs]
    sq = (e_mc[:, 1:] ** 2).sum(axis=(1, 2, 3))  # per run: sum over k >= 1, nodes, components
    tr_sum = np.full(n_clean, tr_P[1:].sum())
    mc_tr_ratio, mc_tr_ci = float(sq.mean() / tr_sum[0]), boot(np.stack([sq, tr_sum], axis=1), "mean")
    mc_ok = all3(decide(mc_tr_ci, C5_BAND[0], "above"), decide(mc_tr_ci, C5_BAND[1], "below"))
min_gap = float(min(gap_up[1:].min(), gap_low[1:].min()))
c5_half = (f"{(mc_tr_ci['high'] - mc_tr_ci['low']) / 2:.1%} at {n_clean} runs" if mc_tr_ci is not None
           else "no interval: fewer than 30 runs without rejection")
c5_holds, c5_nc = bool(min_gap >= -1e-9), None  # the cross-check is ours vs ours: it can only leave C5 unchecked
if not all_accepted_a:
    c5_holds, c5_nc = None, ("an update of the default Case A run was rejected: the exact covariance of Lemma 1 is "
                             "then conditioned on the test, which our propagation cannot represent (a limit of our check)")
elif mc_ok is not True:
    c5_holds, c5_nc = None, ("our propagation disagrees with our simulation (Monte Carlo cross-check fails)"
                             if mc_ok is False else MC_UNDECIDED)
claims["C5"] = results.claim(
    paper="aim R1), (8): 'an upper bound of estimation error covariance is guaranteed in the presence of abnormal "
    "measurements or sensor attacks, that is, there exists a sequence of positive-definite matrices Pi+_{i,k|k} "
    "satisfying P+_{i,k} <= Pi+_{i,k}, for all k > 0'; Theorem 3: with (32), (34) 'the objective R1) ... is "
    "achieved'; Theorem 1: Gamma+_{i,k} <= P+_{i,k} (the lower bounds used by the test (25))",
    check="Case A, P+ the exact stacked covariance: min over (i, k >= 1) of lambda_min(Pi+ - P+)/tr P+ and "
    "lambda_min(P+ - Gamma+)/tr P+ >= -1e-9 (ours: a round-off tolerance on eigenvalues of differences of "
    "matrices of size ~tr P+, the paper's order is exact) (not checked if a Case-A update is rejected: E12); Monte Carlo "
    "cross-check of our propagation on the runs without rejection (when >= 30): mean squared error over sum "
    "tr P+ inside [0.9, 1.1] by the interval rule; if it fails or is undecided C5 is not checked. The band is "
    "ours; its reason: the propagation is exact by derivation (its expectation equals sum tr P+), and the "
    "cross-check, ours against ours, only guards against a gross error of our propagation code (a dropped or "
    "misplaced term), so it can only leave C5 unchecked; 10 % is a round tolerance for such an error, set wider "
    f"than the interval's Monte Carlo half-width so that the rule can decide (this run: {c5_half}); it replaces (2026-12-03) "
    "'median relative Frobenius error <= 0.12 sqrt(300/runs)', a level changing with n",
    measured={"min_eig_rel": min_gap, "min_eig_Pi_minus_P_rel": float(gap_up[1:].min()),
              "min_eig_P_minus_Gamma_rel": float(gap_low[1:].min()),
              "median_trPi_over_trP": float(np.median(ratio_tr[1:])),
              "mc_mean_sq_error_over_trP": mc_tr_ratio, "mc_runs_all_accepted": n_clean, "mc_runs": R_MC,
              "case_a_all_accepted": all_accepted_a},
    threshold={"min_eig_rel": -1e-9, "mc_mean_sq_error_over_trP": list(C5_BAND)},
    holds=c5_holds, interval=mc_tr_ci,
    not_checked=c5_nc,
    source="R1), (8); Theorems 1 and 3, (17)-(18), (26), (35)", key="min_eig_rel",
    premise=("the paper's premise Gamma_0 <= P_0 <= Pi_0 (gamma0_scale <= 2 <= pi0_scale)", initial_order),
    decides=True, runs=R_MC,
    section="Exact covariance against the bounds (claim C5, extra figure)",
)

# C6: channel statistics
claims["C6"] = results.claim(
    paper="Sec. II: delta_k is a Gilbert-Elliott chain with failure rate p and recovery rate q",
    check=f"by construction (our generator of the chain, read back): on {chain_steps} steps: p lies in the 99.9 % Wilson interval of p_hat = #(1->0)/#1 and q in that "
    "of q_hat = #(0->1)/#0; the fraction of ones and Fig. 2's counts are reported",
    measured={"p_hat": p_hat, "q_hat": q_hat, "p_hat_interval": list(p_ci), "q_hat_interval": list(q_ci),
              "fraction_ones": frac1, "stationary": stationary,
              "fig2_counts": {"failures": f10, "ones": f1, "recoveries": f01, "zeros": f0},
              "chain_steps": chain_steps},
    threshold={"p": p, "q": q},
    holds=bool(p_ci[0] <= p <= p_ci[1] and q_ci[0] <= q <= q_ci[1]),
    source="Sec. II, Fig. 2", key="p_hat", basis="by-construction",
    interval=results.interval(*p_ci, level=0.999, method="wilson"),
    section="The channel statistics (C6)",
)

# X7 (was C8a): Theorem 4's sufficient condition evaluated for the example (ours: the paper never claims it)
claims["X7"] = results.claim(
    paper="(ours: the paper states Theorem 4's condition (42)-(43) but neither evaluates it for its example nor "
    "says the example meets it) does the example satisfy xi_q < 1 and xi_p < 1?",
    check="exact: xi_q and xi_p for the run's (p, q, kappa, nu, threshold), A, C_i, N_bar = 1 + max "
    "degree, in the printed form of (42)-(43) (holds uses it) and in the form (1+kappa)(1+2 kappa N_bar) the "
    "proof (36), (44)-(47) implies; also the infimum over all p, q in [0, 1], kappa >= 0: zeta alpha^2",
    measured={"xi": thm4, "N_bar": int(N_bar), "zeta_alpha2": float(zeta * alpha_bar**2),
              "max_xi_printed": float(max(thm4["printed"].values()))},
    threshold={"xi": 1.0},
    holds=thm4_holds,
    source="ours (Theorem 4, (42)-(43); proof (44)-(47))", key="max_xi_printed",
    section="Theorem 4 for the example",
)

# C8b: Pi bounded over a long run at the example (Theorem 4's conclusion; its premise cannot hold: shown)
claims["C8b"] = results.claim(
    paper="Theorem 4, (41): sum_i ||E Pi+_{i,k}|| stays bounded as k grows (R2)",
    check=f"at the example, one Case A run of {L_LONG} steps with its own channel chain: "
    f"max_i tr Pi+ over the second half <= 1.5 x its max over k in [{burn}, {split}] (1.5 ours, post hoc: "
    "set after the brief's indicative run); the premise cannot hold for this plant (X7), so C8b does not decide "
    "(contribution 3 is recorded not checked, C8)",
    measured={"max_trPi_first_half": early, "max_trPi_second_half": late, "steps": L_LONG,
              "rejections": long_rejections, "growth": late / early},
    threshold={"growth": 1.5},
    holds=bool(late <= 1.5 * early),
    source="Theorem 4, (41)", key="growth", tolerance=MC_TOL,
    premise=("(42)-(43) hold for the example (printed form, X7)", thm4_holds),
    section="Theorem 4 for the example",
)

# C8c: Theorem 4 on a declared instance that meets (42)-(43): its conclusion follows from (26), (35) alone
claims["C8c"] = results.claim(
    paper="Theorem 4, (41): under (42)-(43), sum_i ||E Pi+_{i,k}|| stays bounded as k grows (R2)",
    check=f"by construction, not evidence: declared instance (ours), the example with A scaled by thm4_a_scale = "
    f"{thm4_a_scale:g}, everything else as in the run. With S_k = sum_i ||Pi+_{{i,k}}||, (26) and (35) give "
    "S_{k+1} <= c S_k + m ||BB^T|| for every channel sequence and every test outcome (Pi+ <= Pi- by (35); each "
    "Pi+_j enters the Xi of at most N_bar nodes), c = ||A||^2 (1 + kappa)(1 + 2 kappa N_bar); holds if c < 1 "
    f"(the conclusion then holds without any measurement update, so it says nothing about the filter) and one "
    f"Case A run of {L_LONG} steps on C8b's channel chain stays below c^k S_0 + m ||BB^T|| (1 - c^k)/(1 - c) "
    "(an identity check of our code); zeta alpha^2 of the instance at nu = 0 and nu = 1 (the ends of the declared "
    "nu range) reported; the growth of max_i tr Pi+ is reported without a level (until round 4 of "
    "issue #30 C8c decided with C8b's growth level 1.5, set post hoc)",
    measured={"contraction_factor": c_s, "max_S_over_bound": S_excess, "S_end": float(S_s[-1]),
              "max_trPi_first_half": early_s, "max_trPi_second_half": late_s, "steps": L_LONG,
              "rejections": rej_s, "growth": late_s / early_s, "thm4_a_scale": thm4_a_scale, "xi": thm4_s,
              "instance_zeta_alpha2_at_nu": zeta_alpha2_s},
    threshold={"contraction_factor": 1.0, "max_S_over_bound": 1.0},
    holds=bool(c_s < 1 and S_excess <= 1 + 1e-9),
    source="Theorem 4, (41)-(43)", key="contraction_factor", tolerance=MC_TOL, basis="by-construction",
    premise=("inspection (25) applied and (42)-(43) hold at the instance (printed form)",
             bool(inspection and thm4_s_holds)),
    section="Theorem 4 for the example",
)

# C8: contribution 3 (Theorem 4's boundedness): cannot be measured here, decides as not checked
claims["C8"] = results.claim(
    paper="Sec. I, contribution 3): 'rigorous analysis is carried out on the failure and recovery rates of "
    "channels in order to ensure the boundedness of designed secure filtering algorithm'; Theorem 4: under "
    "(42)-(43), sum_i ||E Pi+_{i,k}|| stays bounded (41)",
    check="not measurable here (recorded, not checked): the example cannot meet (42)-(43) for any p, q, kappa, nu "
    "(X7: xi >= zeta alpha^2 > 2), and wherever (42)-(43) hold the conclusion follows from the premise alone: by "
    "(35) Pi+ <= Pi- whatever the test decides, so (44)-(47) with the update step (46) replaced by ||E Pi+|| <= "
    "||E Pi-|| (zeta by 1) and the proof's bracket (1 + kappa)(1 + 2 kappa N_bar) contract whenever sigma (1 + "
    "kappa) kappa N_bar <= 1 - sigma (for kappa < 1 on m nodes whenever sigma <= 1/(1 + 2m); the declared space "
    "has sigma <= 1e-2, m = 20): the bound is then bounded without any measurement, and no instance can show "
    "what the filter contributes; on the declared instance the contraction is deterministic (C8c); reported: "
    "zeta alpha^2 of the example, the contraction factor c = ||A||^2 (1 + kappa)(1 + 2 kappa N_bar) of the "
    "example and of the instance, and the implication's condition at this run",
    measured={"example_zeta_alpha2": float(zeta * alpha_bar**2), "example_contraction_factor": c_ex,
              "instance_contraction_factor": c_s, "sigma_1pk_kappa_Nbar": implication_lhs,
              "one_minus_sigma": float(1 - sigma_fa),
              "premise_implies_contraction_without_update": bool(implication_lhs <= 1 - sigma_fa)},
    threshold={"instance_contraction_factor": 1.0},
    holds=None,
    not_checked="Theorem 4 cannot be exercised: the example cannot meet (42)-(43) (X7), and on every instance "
    "that meets them with sigma (1 + kappa) kappa N_bar <= 1 - sigma (the whole declared space) its conclusion "
    "holds without the filter's measurement updates (C8c), so no measurement here can fail because of the filter",
    source="Sec. I, contribution 3); Theorem 4, (41)-(43)", key="instance_contraction_factor", decides=True,
    section="Theorem 4 for the example",
)

# C9: comparison with the constant-gain filter, both readings of its structure
c9 = {}
for form in CMP_FORMS:
    r_cA = {n: rmse(mc_err[f"cA_{form}"], ks_all, n - 1) for n in plot_nodes}
    r_pA = {n: rmse(mc_err["A"], ks_all, n - 1) for n in plot_nodes}
    no_att = {f"sensor{n}": float(np.median(r_cA[n] / r_pA[n])) for n in plot_nodes}
    no_att_ci = {f"sensor{n}": boot(r_cA[n] / r_pA[n]) if R_MC >= MIN_RUNS else None for n in plot_nodes}
    under = {f"sensor{n}": mc_stats[n][f"const_{form}_over_B"] for n in windows}  # over the working runs
    under_ci = {f"sensor{n}": mc_stats[n][f"ci_const_{form}_over_B"] for n in windows}
    c9[form] = {"no_attack_median_ratio": no_att,
                "no_attack_ci": {k: [v["low"], v["high"]] if v else None for k, v in no_att_ci.items()},
                "attack_window_ratio": under,
                "attack_window_ci": {k: [v["low"], v["high"]] if v else None for k, v in under_ci.items()},
                "similar": all3(*(all3(decide(v, 0.8, "above"), decide(v, 1.6, "below"))
                                  for v in no_att_ci.values())),
                "more_reliable": all3(*(decide(v, 1.0, "above") for v in under_ci.values()))}
c9_form, c9_node = worst({(f, n): mc_stats[n][f"const_{f}_over_B"] for f in CMP_FORMS for n in windows})
# (i) is measured over all runs and decides alone: a filter that locks out without attack is what would fail it,
# so the working precondition (which only says over which runs (ii) is measured) gates part (ii) only
c9_i = all3(*(c9[f]["similar"] for f in CMP_FORMS))
c9_ii = all3(*(c9[f]["more_reliable"] for f in CMP_FORMS))
c9_g = (False, None) if c9_i is False else gated(all3(c9_i, c9_ii), MC_UNDECIDED_PREMISE)
c9_premise = (MC_PREMISE[0] + "; this precondition gates part (ii) only: part (i), over all runs, decides alone "
              "(C9 fails if (i) fails, whatever the precondition; until r8 of the review it gated both parts)",
              bool(inspection and (c9_i is False or MC_PREMISE[1])))
claims["C9"] = results.claim(
    paper="Sec. V, Figs. 5-6: 'these two schemes have similar filtering performance ... when there are no "
    "attacks. Furthermore, the reliability of developed scheme is clearly verified' (under attack)",
    check="Monte Carlo, in both readings of the comparison filter: (i) no attack, all runs: median "
    "RMSE_const,A/RMSE_A over k = 1..N at each plotted sensor inside [0.8, 1.6] (ours, post hoc: set after "
    "the brief's indicative run); (ii) under "
    "attack, over the runs where the sensor works without attack: RMSE_const,B/RMSE_B over each window "
    "(ratio of means) against 1; both by the interval rule (bootstrap); holds if (i) and (ii) hold in both; "
    "fails if (i) fails, whatever the working precondition, which gates (ii) only",
    measured={**c9, "attack_window_ratio_min": mc_stats[c9_node][f"const_{c9_form}_over_B"],
              "part_i_no_attack_similar": c9_i, "part_ii_more_reliable": c9_ii,
              "mc_working_fraction": working_fraction},
    threshold={"no_attack_ratio": [0.8, 1.6], "attack_window_ratio_lower_bound": 1.0,
               "working_fraction_premise_level": WORKING_LEVEL},
    holds=c9_g[0], not_checked=c9_g[1],
    source="Sec. V, Figs. 5-6", interval=mc_stats[c9_node][f"ci_const_{c9_form}_over_B"],
    premise=c9_premise, key="attack_window_ratio_min", tolerance=MC_TOL, runs=R_MC,
    section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# C11: Theorem 3, the gain (32) minimises tr S2 (the locally optimized upper bound): true by algebra
c11_min = min(c11.values())
claims["C11"] = results.claim(
    paper="(31)-(33), Theorem 3: with the gain (32) 'the trace of matrix S2 is minimized' ('locally optimized "
    "upper bounds of error covariance'; abstract: 'designed by minimizing the trace of such an upper bound')",
    check="by construction, not evidence: S2(K) = K DD^T K^T + (I - K C_i) Pi- (I - K C_i)^T is quadratic in K, "
    "its first-order term vanishes at the gain (32), so S2(K + Delta) - S2(K) = Delta Pi_eta Delta^T and the change "
    "of the trace is Pi_eta ||Delta||^2 >= 0 (Pi_eta > 0): it cannot be negative. Checked against our code: "
    f"default Case A, every node and step, tr S2 at K + eps ||K|| Delta ({dirs.shape[0]} unit directions: 200 "
    "random, the signed axes, +-K; eps = 1e-3, 1e-1, 1): smallest relative change >= -1e-12 (ours: round-off of a "
    "trace), and it grows as eps^2 (rel_change_over_eps2 the same at every eps); tr S* of (33) against tr S2(K) "
    "reported",
    measured={"min_rel_change_by_eps": c11, "min_rel_change": c11_min, "s_star_rel_gap": s_star_gap,
              "rel_change_over_eps2": {k: v / float(k) ** 2 for k, v in c11.items()},
              "directions": int(dirs.shape[0])},
    threshold={"min_rel_change": -1e-12},
    holds=bool(c11_min >= -1e-12),
    source="(31)-(33), Theorem 3; abstract", key="min_rel_change", basis="by-construction",
    tolerance=RUN_TOL, section="The gain (32) minimises the upper bound (claim C11)",
)

# C7: Remark 4, the per-node cost does not depend on the network size
c7_const = {k: len({f_[k] for f_ in c7.values()}) == 1 for k in ("elements_read", "inversions")}
claims["C7"] = results.claim(
    paper="Remark 4: node i's step needs '2 times of the matrix inversion operation'; its 'computational "
    "complexity on node i as O(n_x^3), which is independence of the scale of whole sensor networks'",
    check=f"one call of secure_filter_node_step, a node with {C7_DEGREE} neighbours in ring lattices of "
    f"N = {', '.join(map(str, C7_SIZES))}: summed size of its arguments ('elements_read') and np.linalg.inv calls "
    "the same at every N; by construction (the step takes only local data), it measures no cost; matrix "
    "products not counted; the cost is measured only by make bench (timings), not evidence here",
    measured={"by_network_size": c7, "inversions": c7[str(C7_SIZES[-1])]["inversions"],
              "same_at_every_size": c7_const},
    threshold={"inversions_paper": 2},
    holds=all(c7_const.values()),
    source="Remark 4; Sec. I, contribution 2)", key="inversions", basis="by-construction",
    section="Vectorised against per-node implementation (X8) and Remark 4 (C7)",
)

# C12: contribution 2 (the cost does not grow with the network): cannot be measured here, decides as not checked
claims["C12"] = results.claim(
    paper="Sec. I, contribution 2): 'the gains of the designed distributed filters are dependent on the solution "
    "to a Riccati-like difference equation, and the computational complexity is therefore unrelated to the scale "
    "of underlying SNs' (Remark 6, 2): 'the computational burden is unrelated to the dimension of the underlying "
    "SNs')",
    check="not measured: the contribution holds by construction of the per-node step (C7); by the written rule a "
    "main contribution that cannot be measured here decides as not-checked. In detail (recorded, not checked): the "
    "per-node step receives only the node's own data and "
    "its neighbours' packets, so what it reads and inverts cannot depend on the network's size (C7, by "
    "construction: the same at every N); the cost itself is time, machine-dependent, and is measured only by make "
    "bench, never in a committed notebook (CONVENTIONS); reported: C7's footprint. Contribution 2 thus holds by "
    "construction where it is measured (C7, basis by-construction, never deciding) and decides as not-checked "
    "through this entry (rescience_verdict: 'a contribution that cannot be measured here decides as "
    "not-checked'); its basis reads 'measured' only because a deciding entry must have that basis in the "
    "vocabulary of secest.repro.results (a by-construction entry cannot decide): nothing is measured here",
    measured={"inversions": c7[str(C7_SIZES[-1])]["inversions"], "same_at_every_size": c7_const,
              "network_sizes": list(C7_SIZES)},
    threshold={"inversions_paper": 2},
    holds=None,
    not_checked="a cost claim: by construction of the per-node step here (C7), timed only by make bench "
    "(machine-dependent, not committed)",
    source="Sec. I, contribution 2); Remark 4; Remark 6", key="inversions", decides=True,
    section="Vectorised against per-node implementation (X8) and Remark 4 (C7)",
)

# X8 (was C10): vectorised against per-node
claims["X8"] = results.claim(
    paper="(ours, a check of our code) our vectorised step and our per-node step, which receives only the "
    "node's own data and its neighbours' packets, compute the same filter (Remark 4's own claim, the cost "
    "per node independent of the network size, is C7)",
    check=f"after {steps_c10} steps of Case B: max of |x_vec - x_loop|, |Pi_vec - Pi_loop|/max|Pi| "
    "and |Gamma_vec - Gamma_loop|/max|Gamma| <= 1e-10 (two implementations of ours of one recursion: an "
    "identity of our code, by construction)",
    measured=c10_diff,
    threshold=1e-10,
    holds=c10_diff <= 1e-10,
    source="ours (Remark 4 context)", section="Vectorised against per-node implementation (X8) and Remark 4 (C7)",
    tolerance=results.ROUNDING_RESIDUAL, basis="by-construction",
)

# X1: lockout after the attack (ours)
x1_by = {n: frac(mc_stats[n]["locked"], mc_stats[n]["working_runs_to_N"]) for n in windows}
x1_frac = {f"sensor{n}": v for n, v in x1_by.items()}
x1_worst = worst(x1_by, max)
x1_ci = (wilson(mc_stats[x1_worst]["locked"], mc_stats[x1_worst]["working_runs_to_N"])
         if mc_stats[x1_worst]["working_runs_to_N"] else None)
claims["X1"] = results.claim(
    paper="(implied by Fig. 4(b), not stated) after its attack window an attacked sensor resumes normal "
    "filtering",
    check=f"Monte Carlo, over the runs where the attacked sensor works without attack up to k = {N}: fraction "
    f"locked out at k = {N} in Case B, worse sensor, against 0.05 (ours: C1's 1 run in 20) by the interval rule "
    "(Wilson); "
    f"recovery of all locked runs by k = {recovery_steps} reported",
    measured={"locked_fraction": x1_frac, "locked_fraction_max": x1_by[x1_worst],
              "working_runs": {f"sensor{n}": mc_stats[n]["working_runs_to_N"] for n in windows},
              "any_reject_after_window": {f"sensor{n}": mc_stats[n]["any_reject_after"] for n in windows},
              "recovery": recovery, "recovery_resumed_fraction": resumed / locked_pairs if locked_pairs else None,
              "case_a_runs_with_rejection": runs_alarm_a / R_MC, "mc_runs": R_MC},
    threshold={"locked_fraction_upper_bound": 0.05, "working_fraction_premise_level": WORKING_LEVEL},
    holds=(x1_g := gated(decide(x1_ci, 0.05, "below"), N_UNDECIDED_PREMISE))[0],
    not_checked=x1_g[1],
    source="ours (Sec. V, Fig. 4(b))", interval=x1_ci, key="locked_fraction_max",
    premise=N_PREMISE,
    tolerance=MC_TOL, runs=R_MC, section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# X2: ablation with Pi_eta (ours)
x2_lock = {n: frac(mc_stats[n]["Pi_test_locked"], mc_stats[n]["working_runs_to_N"]) for n in windows}
x2_det = {n: frac(mc_stats[n]["Pi_test_runs_all_window_rejected"], mc_stats[n]["working_runs"]) for n in windows}
x2_lw, x2_dw = worst(x2_lock, max), worst(x2_det)
x2_lock_ci = (wilson(mc_stats[x2_lw]["Pi_test_locked"], mc_stats[x2_lw]["working_runs_to_N"])
              if mc_stats[x2_lw]["working_runs_to_N"] else None)
x2_det_ci = (wilson(mc_stats[x2_dw]["Pi_test_runs_all_window_rejected"], mc_stats[x2_dw]["working_runs"])
             if mc_stats[x2_dw]["working_runs"] else None)
claims["X2"] = results.claim(
    paper="(ours, no paper statement) question: does normalising the test by Pi_eta instead of Gamma_eta fix "
    "the lockout (X1) without giving up detection?",
    check="criterion (ours): at both attacked sensors, lockout as in X1 (0.05, over the runs where the sensor "
    "works without attack up to k = N) and detection as in C1 (0.95, over the runs where it works up to its "
    "window's end), each by the interval rule; holds if both hold",
    measured={**{f"sensor{n}": {"runs_all_window_rejected": x2_det[n],
                                "reject_rate_window": mc_stats[n]["Pi_test_reject_rate_window"],
                                "locked_fraction": x2_lock[n]} for n in windows},
              "locked_fraction_max": x2_lock[x2_lw], "runs_all_rejected_min": x2_det[x2_dw],
              "removes_lockout": decide(x2_lock_ci, 0.05, "below"), "keeps_detection": decide(x2_det_ci, 0.95, "above"),
              "mc_runs": R_MC},
    threshold={"locked_fraction_upper_bound": 0.05, "runs_all_rejected_lower_bound": 0.95,
               "working_fraction_premise_level": WORKING_LEVEL},
    holds=(x2_g := gated(all3(decide(x2_lock_ci, 0.05, "below"), decide(x2_det_ci, 0.95, "above")),
                         N_UNDECIDED_PREMISE))[0],
    not_checked=x2_g[1],
    source="ours", interval=x2_det_ci, key="runs_all_rejected_min", tolerance=MC_TOL,
    premise=N_PREMISE,
    runs=R_MC,
    section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# X3: lockout without attack (ours)
claims["X3"] = results.claim(
    paper="(implied by Fig. 4(a), not stated) without attacks every node keeps filtering",
    check=f"Monte Carlo, Case A: fraction of runs with a node locked out at k = {N} against 0.05 (ours: C1's 1 run "
    "in 20) by the interval rule (Wilson)",
    measured={"runs_with_a_locked_node": runs_locked_a / R_MC, "node_runs_locked": float(locked_a.mean()),
              "nodes_rejecting_y1": float(np.mean(mc["A"]["theta"][:, 1] == 0)),
              "gamma0_scale": gamma0_scale, "mc_runs": R_MC},
    threshold={"runs_with_a_locked_node_upper_bound": 0.05},
    holds=(x3_holds := decide(x3_ci, 0.05, "below")),
    not_checked=None if x3_holds is not None else MC_UNDECIDED,
    source="ours (Sec. V, Fig. 4(a))", interval=x3_ci, premise=INSPECTION_PREMISE, key="runs_with_a_locked_node",
    tolerance=MC_TOL, runs=R_MC, section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# X4: exact decoupling at kappa = 0 (ours)
claims["X4"] = results.claim(
    paper="(ours, a sanity check of (7), (26)) at kappa = 0 the nodes decouple: every node is a local Kalman "
    "filter",
    check="exact identities of (7), (26) at kappa = 0 (by construction), kappa = 0 control (Pi_0 = Gamma_0 = P_0): "
    "the unattacked nodes' estimates in Cases A and B "
    "are identical (max |difference| == 0), and without inspection max_(i,k) ||Pi+ - P+||_F/||P+||_F <= 1e-9 "
    "against the exact covariance",
    measured={"leak_unattacked": leak0, "max_rel_Pi_minus_P": pi_vs_p0},
    threshold={"leak_unattacked": 0.0, "max_rel_Pi_minus_P": 1e-9},
    holds=bool(leak0 == 0.0 and pi_vs_p0 <= 1e-9),
    source="ours", key="max_rel_Pi_minus_P", section="κ = 0: the nodes decouple exactly (claim X4)",
    basis="by-construction",
)

# X5: the lockout occurs at kappa = 0 too, where Gamma does not collapse (ours)
X5_LEVEL = 0.05  # ours: X1's level, the locked fraction at which X1 says an attacked sensor does not resume
# counted as X1 counts: over the runs where the sensor works without attack up to k = N, here at kappa = 0 (its
# attack-free kappa = 0 run has no lockout), so that a lockout started by false alarms alone is not counted; the
# precondition by X1's rule (the working fraction's Wilson interval against WORKING_LEVEL)
x5_by = {n: frac(mc_stats[n]["kappa0_locked"], mc_stats[n]["kappa0_working_runs_to_N"]) for n in windows}
x5_frac = {f"sensor{n}": v for n, v in x5_by.items()}
x5_worst = max(windows, key=lambda n: -1.0 if x5_by[n] is None else x5_by[n])
x5_ci = (wilson(mc_stats[x5_worst]["kappa0_locked"], mc_stats[x5_worst]["kappa0_working_runs_to_N"])
         if mc_stats[x5_worst]["kappa0_working_runs_to_N"] else None)
X5_PREMISE, X5_UNDECIDED_PREMISE = works_premise(
    [mc_stats[n]["kappa0_working_runs_to_N"] for n in windows],
    f"each attacked sensor works without attack at kappa = 0 (kappa = 0 control without attack, no lockout up to "
    f"k = {N}) in at least half of the runs (X1's rule)")
claims["X5"] = results.claim(
    paper="(ours, no paper statement) the lockout occurs at kappa = 0 too, where Gamma does not collapse (P6: "
    "Gamma+ = Pi+ = P+ until a node's first rejection, reported): the collapse is not needed for it. That its "
    "cause is then (17)-(18), which do not let Gamma grow while updates are skipped, is our reading of the "
    "mechanism, not tested here",
    check=f"kappa = 0 control (Pi_0 = Gamma_0 = P_0), Case B, over the runs where the attacked sensor works "
    f"without attack at kappa = 0 up to k = {N} (as X1 counts; a lockout started by false alarms alone is not "
    f"counted): locked fraction at k = {N} of the attacked sensor with the largest one against {X5_LEVEL:g} (ours: "
    f"X1's level) by the interval rule (Wilson): holds if the lower bound >= {X5_LEVEL:g}, fails if the upper "
    f"bound < {X5_LEVEL:g}, not checked otherwise; precondition by X1's rule (the working fraction's interval "
    "against 0.5). Until r7 of the review 'lower bound > 0', which could not fail; in r7 counted over all runs, "
    "attack-free lockouts included. Reported, an identity at kappa = 0 (by construction): Gamma+ = Pi+ before "
    "each node's first rejection",
    measured={"locked_fraction": x5_frac, "locked_fraction_max": x5_by[x5_worst],
              "working_runs": {f"sensor{n}": mc_stats[n]["kappa0_working_runs_to_N"] for n in windows},
              "locked_fraction_all_runs": {f"sensor{n}": int(mc_locked["B0"][:, n - 1].sum()) / R_MC
                                           for n in windows},
              "gamma_vs_pi_before_first_rejection": gam_pi_before, "mc_runs": R_MC},
    threshold={"locked_fraction_level": X5_LEVEL, "working_fraction_premise_level": WORKING_LEVEL},
    holds=(x5_g := gated(decide(x5_ci, X5_LEVEL, "above"), X5_UNDECIDED_PREMISE))[0],
    not_checked=x5_g[1],
    source="ours", interval=x5_ci, premise=X5_PREMISE, key="locked_fraction_max", tolerance=MC_TOL,
    runs=R_MC,
    section="Monte Carlo: detection, degradation, comparison and the χ² lockout",
)

# Claims whose rule changed after the committed sweep was made would say so here (`robustness_note`: the counts
# were made under the previous rule, and which). Empty: `make robustness` was re-run with the present rules (r8 of the review).
SWEPT_UNDER_PREVIOUS_RULE: dict[str, str] = {}
for cid, note in SWEPT_UNDER_PREVIOUS_RULE.items():
    claims[cid]["robustness_note"] = note
written = results.write_claims(results_path, claims, robustness="figures/ding2020/robustness.json")
merged = json.loads(written.read_text())
for cid, c in claims.items():
    print(f"{cid:4s} {c['verdict']} here ({c['basis']}); over the declared space {merged[cid]['verdict']}")

# %% [markdown]
# The claims with their verdicts, read back from the claims file (over the declared space when the
# robustness sweep has been run: the outcomes at the 33 design points and, for `undetermined`, the region
# where the claim holds):

# %%
lines = ["| id | source | holds here | verdict | where it holds over the declared space |", "|---|---|---|---|---|"]
for cid, c in merged.items():
    rob = c.get("robustness")
    where = (f"{results.counts_text(rob['outcomes'])} (of {rob['points']} points); {rob['region']}" if rob
             else "(no sweep)") + (" — counts under the previous rule (robustness_note)" if "robustness_note" in c
                                   else "")
    lines.append(f"| {cid} | {c.get('source', '')} | {c['holds']} | **{c['verdict']}** | {where} |")
display(Markdown("\n".join(lines)))

# %% [markdown]
# **This run in numbers** (generated from the claims just written; the introduction quotes none of them):


# %%
def span(values, fmt: str = ".1f", unit: str = "") -> str:
    """'a–b' (or 'a') over the values that are not None, formatted with fmt; 'n/a' without any."""
    v = sorted(x for x in values if x is not None)
    if not v:
        return "n/a"
    lo, hi = format(v[0], fmt), format(v[-1], fmt)
    return (lo if lo == hi else f"{lo}–{hi}") + unit


cm = {cid: c["measured"] for cid, c in merged.items()}  # as written (rounded)
c9_ratios = [cm["C9"][f]["attack_window_ratio"][k] for f in CMP_FORMS for k in att_names]
display(Markdown("\n".join([
    f"- {R_MC} Monte Carlo runs. C1: the default run rejects {cm['C1']['default_rejected_in_windows']} of its "
    f"{cm['C1']['default_attacked_samples']} attacked samples; the worse sensor rejects every attacked sample in "
    f"{span([cm['C1']['mc_runs_all_rejected_min']], '.1%')} of the working runs.",
    f"- C2a: {cm['C2a']['mc_runs_meeting_rule']} of {cm['C2a']['mc_eligible_runs']} eligible runs show no "
    f"obvious effect by the per-run rule ({span([cm['C2a']['mc_fraction_meeting_rule']], '.0%')}; median largest "
    f"shift / own Case-A error {span([cm['C2a']['mc_median_max_shift_over_case_a_error']], '.2f')}). In the "
    "default run (the figure's, an illustration) the attack shifts the compared plotted sensors by "
    + ", ".join(f"{k.removeprefix('sensor')}: {100 * cm['C2a']['default_run'][k]['shift_fraction_of_axis']:.2g} %"
                for k in cm["C2a"]["default_run"]["compared_sensors"])
    + " of the axis range (largest shift / own Case-A error "
    + f"{span([cm['C2a']['default_run']['max_shift_over_case_a_error']], '.2f')}).",
    f"- C3: the window RMSE rises {span(cm['C3']['mc_median_ratio'].values())}× with detection (medians); "
    f"C4: without inspection it is {span(cm['C4']['mc_median_ratio_vs_B'].values())}× that with it.",
    f"- C5: smallest relative eigenvalue gap {cm['C5']['min_eig_rel']:.2g}; median tr Π⁺ / tr P⁺ "
    f"{cm['C5']['median_trPi_over_trP']:.2f}.",
    f"- C9: under attack the constant-gain filter's window RMSE is {span(c9_ratios)}× the proposed filter's "
    "(both readings, both attacked sensors).",
    f"- X1: locked out at k = {N} after the attack: "
    + ", ".join(f"sensor {k.removeprefix('sensor')} {v:.0%}" for k, v in cm["X1"]["locked_fraction"].items() if v is not None)
    + " of the working runs; X5, κ = 0 control (lockout without the collapse of Γ): "
    + ", ".join(f"sensor {k.removeprefix('sensor')} {v:.0%}" for k, v in cm["X5"]["locked_fraction"].items()
                if v is not None) + " of its working runs.",
    f"- C8c: contraction factor c = {cm['C8c']['contraction_factor']:.3f} on the declared instance "
    f"({cm['C8']['example_contraction_factor']:.3f} at the example's plant).",
])))

# %% [markdown]
# ## Verdict
#
# By the project's one written rule (`results.rescience_verdict`): `[Re]` if every deciding claim holds
# at the paper's example and over the declared space, `[¬Re]` if none holds at the example, `[Re, partial]`
# otherwise. Computed from the claims file just written:

# %%
verdict = results.rescience_verdict(json.loads(written.read_text()))
print(verdict["line"])

# %% [markdown]
# C2a is decided at the example over its 300 Monte Carlo runs (the figure's run is an illustration), and C1,
# C4 likewise; C8 and C12 record contributions 3 and 2, which hold vacuously or by construction wherever they
# can be evaluated here, as not checked, so the verdict is partial whatever was measured. The declared
# space also sweeps three printed values (the threshold, $p$, $q$): its counts map the sensitivity to them and
# to our choices, they are not verdicts on the paper's example (the default point).

# %% [markdown]
# ## Deviations from the paper
#
# | # | item | paper | here | why |
# |---|---|---|---|---|
# | E1 | statistic in R1 | $M=\eta^T\Gamma_\eta^{-1}$, bound $\Pi^+_{i,k\mid k}$ | $\eta^T\Gamma_\eta^{-1}\eta$, $\Pi^+_{i,k}$ | typos |
# | E2 | index of $\tilde S_1$ | $k+1$ in (18), $k$ in (23) | $\tilde S_{1i,k+1}$ from $K_{i,k+1}$, $\Gamma^-_{i,k+1}$ | consistency |
# | E3 | $Q$ in (35), (36) | $Q_{2i,k}$, $Q_{i,k}$ (true $P$) | $\tilde Q_{2i,k}$ with $\tilde\Xi=2\sum\Pi^+_j$ | only the bounds are computable |
# | E4 | which $\Pi^-$ in (32) | not stated | $\Pi^-_{i,k+1}$ of (26) with the neighbours' $\Pi^+_{j,k}$ | |
# | E5 | $\delta_k$ vs $\delta^r_{i,k}$ | both used | $\delta_k$ in (3), $\delta^r$ elsewhere; asserted equal each step | a.s. equal |
# | E6 | (35) vs (27) | (35) drops $\max\{\Pi^-,S^*\}$ | (35), equal to (27) under the non-strict order | $\Pi^--S^*$ has rank 1; a strict reading gives $\lambda_{\max}I$ |
# | E7 | (6) vs (25) | (6) needs unknown $P_\eta$ | (25) with $\Gamma_\eta$ | as the paper does |
# | E8 | $\nu$ in Assumption 2 | bounds $\mathbb P\{\vartheta=0,\tilde\vartheta=1\}\equiv0$ | read as the extra rejection probability; $\nu=0$ by default, swept over $[0,1]$ | the printed event is empty |
# | E9 | (42)–(43) vs the proof | $(1+\kappa)(1+\kappa\bar N)$ | the proof ((36), (44)–(47), $\tilde\kappa=2\kappa(1+\kappa)$) implies $(1+\kappa)(1+2\kappa\bar N)$; both evaluated, X7 decides on the printed form | the factor 2 of $\tilde\Xi$ is dropped in print; neither form holds |
# | E10 | noise index in (10), (16) | $v_{i,k}$ | $v_{i,k+1}$ | typo |
# | E11 | Remark 2 | $\sigma$ "detection probability" | false-alarm probability $5.73\cdot10^{-7}$ | threshold 25 is the $(1-\sigma)$-quantile |
# | E12 | Lemma 1 / Thm 2 conditioning | conditional on the test outcome | bounds checked against the exact covariance on Case A with every update accepted; else C5 is not-checked (our limit) | conditioning on $\vartheta$ truncates $\eta$ |
# | — | "no obvious effect" (Figs. 4(a)–(b)) | one run, by eye | per-run rule (ours): no plotted curve moved by the attack further than its own Case-A error; decided over the Monte Carlo runs, fraction meeting it against 1/2 (ours, post hoc: set after the 98-of-300 result and the sweep at e86f45a were known; the median run), Wilson; the default run shown as an illustration | a figure shows one run; until r7 of the review C2a was decided on the default run alone |
# | — | "more reliable" under attack (Figs. 5–6) | stated for the LMI filter | C9 measures constant-gain B against proposed B over the attack windows (Monte Carlo, paired bootstrap), and similarity without attack (over all runs; it decides alone, the working precondition gates only the part under attack, since r8 of the review), in both readings of the comparison filter | an earlier version compared constant-gain B with constant-gain A |
# | — | comparison filter | LMI design of refs. [9], [13] | printed constant gains in prediction (7) without detector, as corrector (default in Fig. 6) and as predictor; C9 holds only if it holds in both | structure not given |
# | — | Fig. 1 topology | a figure we do not have | random geometric graph, $r=0.35$, seed 2020 by default; seed and radius are axes of the declared space; X6 uses ten topologies fixed in advance (seeds 2020–2029) | an earlier version switched to seed 2021 after seeing seed 2020's result; that was dropped |
# | — | $\Pi^+_0$, $\Gamma^+_0$ | not given | two parameters, $\Pi_0=$ `pi0_scale`$\,\sigma_0I$, $\Gamma_0=$ `gamma0_scale`$\,\sigma_0I$; default both $2\sigma_0I=P_0$, the exact initial covariance; swept over $\Pi_0\in[P_0,10P_0]$, $\Gamma_0\in[P_0/1000,P_0]$ (log-uniform) | any valid bounds; a smaller valid $\Gamma_0$ locks nodes out without attack (X3) |
# | — | initial values | "randomly produced" | $x_0$, $\hat x^+_{i,0}$ i.i.d. $\mathcal N(0,\sigma_0I)$, independent; $\sigma_0=1$, swept over $[0.1,10]$ | zero mean keeps (9)–(10); non-zero estimates make (4) exact at $k=0$ (P3) |
# | — | $\delta_0$, first update | not given | $\delta_0=1$ (swept over $\{0,1\}$); first measurement update at $k=1$ | (7) updates at $k+1$ |
# | — | `tol`, `strict` | order relations without a numerical tolerance | relative tolerance $10^{-10}$; non-strict reading of "$Y\prec X$" | round-off; only the non-strict reading makes (35) equal (27) (E6) |
# | — | threshold, $p$, $q$ | printed: 25, 0.1, 0.92 | defaults as printed; swept (threshold over the χ²₁ quantiles of $\sigma=10^{-2}\dots10^{-9}$, $p$ and $1-q$ within a factor 2) to map the lockout | the verdicts over the declared space therefore also carry the sensitivity to these three printed values |
# | — | seeds and common random numbers | not given; the comparison uses "the same" channel and noises | `SeedSequence(seed).spawn(6)`; Cases A, B, no inspection, the κ = 0 control and the comparison filter share $\delta$, $x_0$, $\hat x_0$, $w$, $v$; the Monte Carlo runs share the topology and the $\delta$ of Fig. 2 | comparable curves, lower variance of the ratios |
# | — | delivery of $\Pi^+_{j,k}$ | not stated | sent in the same packet as $\hat x^+_{j,k}$, lost with it | (26) needs the neighbours' bounds only when $\delta^r=1$ |

# %%
manifest_path = run.finish(extra={"mc_runs": R_MC, "long_steps": L_LONG})
print("run manifest:", manifest_path.relative_to(results.repo_root()))
