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
# **Verdict: [Re, partial].** The simulation claims reproduce on our stand-in for the missing
# topology, with one qualification. The χ² detector rejects every attacked sample. Without the detector the
# error grows more than ten-fold in the attack windows. The attack still reaches unattacked nodes
# through the consensus term. The leak falls by more than an order of magnitude per hop, but direct
# neighbours of an attacked sensor move by about 0.03 (up to 0.18). In our default stand-in topology node 20 is such
# a neighbour, so the paper's "node 20 is unaffected" (≤ 10⁻³) fails there (C2a), though the shift is
# invisible at the scale of Fig. 4. The bounds $\Gamma^+\preceq P^+\preceq\Pi^+$
# hold against the exact covariance. But Theorem 4's condition (42)–(43) **fails** for the paper's own example, and for
# every $(p,q,\kappa)$ with this plant; $\Pi$ nevertheless stays bounded empirically. The
# detector also has a **lockout** failure mode the paper does not show: after an attack window,
# in about 10–20 % of Monte Carlo runs the attacked node rejects every later measurement and diverges.

# %% tags=["parameters"]
mode = "paper"  # "paper": full Monte Carlo and long runs; "fast": fewer runs for the tests
seed = 2020  # master seed: SeedSequence(seed).spawn(5) -> channel, world, mc, chain, long run
topology_seed = 2020  # seed of secest.graphs.random_geometric_graph (MISSING, see provenance)
leak_topology_seeds = [2020, 2021, 2022, 2023, 2024, 2025, 2026, 2027, 2028, 2029]  # C2 sweep (MISSING)
m = 20  # number of sensor nodes (PAPER, Sec. V)
radius = 0.35  # connection radius of the random geometric graph, unit square (MISSING)
T = 0.05  # sampling period [s] (PAPER)
horizon = 150  # k in [0, horizon] (PAPER)
p = 0.1  # failure rate of the Gilbert-Elliott chain (PAPER)
q = 0.92  # recovery rate (PAPER)
kappa = 0.004  # coupling strength (PAPER)
threshold = 25.0  # chi-square threshold of (25) (PAPER)
attacks = [[4, 90, 95, 15.0], [12, 50, 55, 15.0]]  # [node (1-based), k_first, k_last, value] (PAPER)
plot_nodes = [4, 12, 20]  # nodes shown in Figs. 3-6 (PAPER)
delta0 = 1  # channel state delta_0 (MISSING)
sigma0 = 1.0  # x_0 and each x_hat_{i,0} ~ N(0, sigma0 I), independent (MISSING)
pi0_scale = 2.0  # Pi_0 and Gamma_0 are pi0_scale * sigma0 * I (MISSING; the exact initial cov.)
tol = 1e-10  # relative tolerance of every Loewner-order test (MISSING)
strict = False  # strict reading of "Y < X" in the min operation (MISSING; non-strict, E6)
nu = 0.0  # Assumption 2 probability bound used in Theorem 4 (MISSING; E8)
gains_low = [0.4177, 0.5799, 0.4029]  # constant gain, nodes 1-7 (PAPER, comparison filter)
gains_high = [0.2883, 0.6150, 0.4457]  # constant gain, nodes 8-20 (PAPER)
cmp_form = "corrector"  # structure of the comparison filter: "corrector" | "predictor" (MISSING)
mc_runs = 300  # Monte Carlo runs (fast mode: at most 100) (MISSING)
long_steps = 2000  # steps of the long run for Pi's boundedness (fast mode: 600) (MISSING)
chain_steps = 100000  # length of the chain for estimating p, q (MISSING)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/ding2020"
results_path = "figures/ding2020/claims.json"

# %%
import inspect

import matplotlib.pyplot as plt
import networkx as nx
import numpy as np

from secest import channels, detectors, filters, graphs, montecarlo, plotting, results

print(results.environment_summary())

run = results.Run("ding2020", globals())
if mode not in ("paper", "fast"):
    raise ValueError(f"mode must be 'paper' or 'fast', found {mode!r}")
if cmp_form not in ("corrector", "predictor"):
    raise ValueError(f"cmp_form must be 'corrector' or 'predictor', found {cmp_form!r}")
R_MC = mc_runs if mode == "paper" else min(mc_runs, 100)
L_LONG = long_steps if mode == "paper" else min(long_steps, 600)
N = int(horizon)
FIG_DIR = results.resolve(fig_dir)
rng_channel, rng_world, rng_mc, rng_chain, rng_long = montecarlo.spawn_rngs(seed, 5)
plotting.setup(enabled=figures)
PLOT = [i - 1 for i in plot_nodes]  # 0-based indices of the plotted nodes (P1)

# %% [markdown]
# ## Parameter provenance
#
# | name | value | tag | source / reason |
# |---|---|---|---|
# | `m` | 20 | PAPER | Sec. V |
# | topology | `random_geometric_graph(20, 0.35, seed=2020)`, unit square, undirected | MISSING | Fig. 1 is not in our copy; "randomly deployed". The seed is the first candidate: the master seed, which the reproduction brief proposed before any run. In this draw node 20 is a direct neighbour of attacked node 12, so the paper's "node 20 unaffected" fails here (C2a). An earlier version of this notebook switched to seed 2021 after seeing that outcome (there node 20 is 2 hops away). That choice depended on the result, so it was dropped. C2 is now measured over a list of topologies fixed in advance. |
# | `leak_topology_seeds` | 2020–2029 | MISSING | the first ten seeds from the default, a list fixed in advance for C2 (C2a, C2b). Each gets one Case A and one Case B run on the default channel and world. Node 20's leak and its hop distance to the attacked sensors are reported, with the leak by hop distance over all unattacked nodes |
# | weights | $h_{ij}=1/\lvert\mathcal N_i\rvert$, $h_{ii}=0$ | PAPER | Sec. V; $\mathcal N_i$ excludes $i$ |
# | $A$, $T$ | constant-acceleration model, $T=0.05$ s | PAPER | Sec. V |
# | $B$, $D$ | $0.2I_3$, $0.05$ | PAPER | Sec. V; $w_k\sim\mathcal N(0,I_3)$, $v_{i,k}\sim\mathcal N(0,1)$ |
# | $C_i$ | $[4.5, -0.8, -0.5]$ for nodes 1–7, $[4.0, -0.8, 1.0]$ for nodes 8–20 | PAPER | "$i<8$" is 1-based |
# | threshold | 25 ($\sigma = P\{\chi^2_1\ge 25\} = 5.73\cdot10^{-7}$) | PAPER | Sec. V |
# | $p, q, \kappa$ | 0.1, 0.92, 0.004 | PAPER | Sec. V |
# | horizon | $k\in[0,150]$ | PAPER | Sec. V |
# | attacks | $+15$ on sensor 4 for $k\in[90,95]$, on sensor 12 for $k\in[50,55]$ (inclusive) | PAPER | Sec. V, "attack strength 15"; added to $y_{i,k}$ only |
# | constant gains | $[0.4177, 0.5799, 0.4029]^T$ (nodes 1–7), $[0.2883, 0.6150, 0.4457]^T$ | PAPER | comparison filter, Sec. V |
# | comparison structure | `cmp_form = "corrector"`: prediction (7) with the same $\kappa$, update $\hat x^+=\hat x^-+K_i\eta$, no detector | MISSING | the paper only cites its refs. [9], [13] |
# | `delta0` | 1 | MISSING | channel initially good |
# | $x_0$, $\hat x_{i,0}^+$ | i.i.d. $\mathcal N(0, I_3)$, independent | MISSING | "randomly produced"; zero mean keeps (9)–(10); non-zero estimates make (4) exact at $k=0$ |
# | $\Pi_0^+$, $\Gamma_0^+$ | $2I_3$ | MISSING | the exact initial error covariance $\mathrm{cov}(x_0-\hat x_{i,0})$, so both bounds hold at $k=0$ |
# | first update | at $k=1$ | MISSING | (7) updates at $k+1$ |
# | `seed` | 2020 | MISSING | `SeedSequence(2020).spawn(5)`: channel, world ($x_0$, $\hat x_0$, $w$, $v$), Monte Carlo, long chain, long run |
# | common random numbers | Cases A, B, no inspection and the comparison filter share $\delta$, $x_0$, $\hat x_0$, $w$, $v$ | PAPER (comparison) / MISSING | the paper says so for the comparison |
# | `tol`, `strict` | $10^{-10}$ relative, non-strict | MISSING | order tests of (17), (18); see E6 |
# | `nu` | 0 | MISSING | Theorem 4, most favourable value (E8) |
# | `mc_runs` | 300 (fast: 100) | MISSING | fixed topology and $\delta$; $x_0$, $\hat x_0$, $w$, $v$ redrawn |
# | `long_steps` | 2000 (fast: 600) | MISSING | Π boundedness (C8b) |
# | `chain_steps` | $10^5$ | MISSING | estimate of $p$, $q$ (C6) |

# %% [markdown]
# ## Setup
#
# ### Plant (1) and sensors (2)
#
# $x_{k+1}=Ax_k+Bw_k$ and $y_{i,k}=C_ix_k+Dv_{i,k}+n_{i,k}$, where $n_{i,k}$ is the injected
# data of the attack model below (5). Each node measures one scalar ($n_y=1$).

# %%
A = np.array([[1.0, T, T**2 / 2], [0.0, 1.0, T], [0.0, 0.0, 1.0]])
B = 0.2 * np.eye(3)
D = np.array([[0.05]])
BBt, DDt = B @ B.T, D @ D.T
C_rows = np.array([[4.5, -0.8, -0.5] if i < 7 else [4.0, -0.8, 1.0] for i in range(m)])  # P1
C = C_rows[:, None, :]  # (m, ny=1, n)
n_x = A.shape[0]
K_const = np.array([gains_low if i < 7 else gains_high for i in range(m)])
attack = np.zeros((N + 1, m))
for node, k_first, k_last, value in attacks:
    attack[k_first : k_last + 1, node - 1] += value
windows = {node: np.arange(k_first, k_last + 1) for node, k_first, k_last, _ in attacks}
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
          f"hops to attacked nodes {[hops[node - 1][a - 1] for a in windows]}")

# %%
fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH * 1.3, plotting.COLUMN_WIDTH * 1.2))
for i, j in zip(*np.nonzero(np.triu(adj)), strict=True):
    ax.plot(*positions[[i, j]].T, color="0.6", lw=0.8, zorder=1)
colors = ["tab:red" if i + 1 in windows else "tab:blue" if i in PLOT else "white" for i in range(m)]
ax.scatter(*positions.T, s=170, c=colors, edgecolors="k", zorder=2)
for i, (px, py) in enumerate(positions):
    ax.annotate(str(i + 1), (px, py), ha="center", va="center", fontsize=7, zorder=3,
                color="white" if colors[i] != "white" else "k")
ax.scatter([], [], s=60, c="tab:red", edgecolors="k", label="attacked (4, 12)")
ax.scatter([], [], s=60, c="tab:blue", edgecolors="k", label="plotted, unattacked (20)")
ax.set_xlabel("position in the field, x [unit length]")
ax.set_ylabel("position in the field, y [unit length]")
ax.set_title(f"Fig. 1 (stand-in): random geometric graph, r = {radius}, seed {topology_seed}")
ax.set_aspect("equal")
ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2)
plotting.save_figure(fig, FIG_DIR, "fig1_topology",
                     data={"node": np.arange(1, m + 1), "pos": positions, "degree": degree})
plotting.save_data(FIG_DIR, "fig1_topology_edges",
                   {"i": np.nonzero(np.triu(adj))[0] + 1, "j": np.nonzero(np.triu(adj))[1] + 1})
plt.show()

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
ax.set_title(f"Fig. 2: Gilbert–Elliott channel, p = {p}, q = {q}")
ax.legend(loc="lower left")
plotting.save_figure(fig, FIG_DIR, "fig2_channel_state", data={"k": np.arange(N + 1), "delta": delta})
plt.show()

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
# `secest/filters.py` implements these steps twice. `secure_filter_step` is vectorised over
# nodes and Monte Carlo runs. `secure_filter_node_step` is a plain per-node reference that loops over
# the neighbours. Their agreement is claim C10. The vectorised step, with the equation numbers
# next to each line:

# %%
src = inspect.getsource(filters.secure_filter_step)
print(src[src.index("    if validate:"):])

# %% [markdown]
# ## Simulation driver
#
# The world ($x_0$, $\hat x_{i,0}$, $w$, $v$) is drawn once per run. Cases A and B, the filter
# without inspection and the constant-gain filter all reuse it (common random numbers).
# `simulate` runs the filter over all nodes and over a batch of runs at once.


# %%
def draw_world(rng: np.random.Generator, runs: int, steps: int) -> dict[str, np.ndarray]:
    """x_0, x_hat_0 ~ N(0, sigma0 I); trajectories x_k and clean measurements y_{i,k}."""
    s = np.sqrt(sigma0)
    x0 = s * rng.standard_normal((runs, n_x))
    xh0 = s * rng.standard_normal((runs, m, n_x))
    w = rng.standard_normal((runs, steps, n_x))
    v = rng.standard_normal((runs, steps + 1, m))
    x = np.empty((runs, steps + 1, n_x))
    x[:, 0] = x0
    for k in range(steps):
        x[:, k + 1] = x[:, k] @ A.T + w[:, k] @ B.T  # (1)
    y = np.einsum("in,rkn->rki", C_rows, x) + D[0, 0] * v  # (2)
    return {"x": x, "xh0": xh0, "y": y}


def simulate(xh0, y, delta_seq, *, inspect_=True, inspection_cov="Gamma", const_gain=None,
             keep_bounds=False, net=None):
    """Run the secure filter (or a constant-gain filter) over all steps.

    xh0 (R, m, n), y (R, N+1, m) measurements incl. attacks, delta_seq (N+1,).
    net = (adjacency, weights) of another topology (default: the stand-in of Fig. 1).
    Returns estimates (R, N+1, m, n), detector outcomes theta (R, N+1, m) (theta[:, 0] = 1:
    no update at k = 0) and, with keep_bounds, Pi, Gamma (R, N+1, m, n, n), gains and counters.
    """
    runs, steps = xh0.shape[0], y.shape[1] - 1
    adj_, H_ = (adj, H) if net is None else net
    x_post = xh0.copy()
    Pi = np.broadcast_to(pi0_scale * sigma0 * np.eye(n_x), (runs, m, n_x, n_x)).copy()
    Gam = Pi.copy()
    out = {"x": [x_post], "theta": [np.ones((runs, m))]}
    if keep_bounds:
        out.update(Pi=[Pi], Gamma=[Gam], K=[], q1_psd=[], min_branch=[], Gamma_eta=[], Pi_eta=[],
                   nis=[])
    for k in range(steps):
        if const_gain is not None:
            x_prior, d_r = filters.consensus_prediction(x_post, delta_seq[k], adj_, H_, A, kappa,
                                                         validate=(k == 0))
            if cmp_form == "predictor":  # x_{k+1} = A x_k + kappa A xi_k + K_i (y_k - C_i x_k)
                eta = y[:, k] - np.einsum("in,rin->ri", C_rows, x_post)
                x_post = x_prior + const_gain[None] * eta[..., None]
            else:  # corrector: x+ = x- + K_i (y_{k+1} - C_i x-)
                eta = y[:, k + 1] - np.einsum("in,rin->ri", C_rows, x_prior)
                x_post = x_prior + const_gain[None] * eta[..., None]
            theta = np.ones((runs, m))
        else:
            st = filters.secure_filter_step(
                x_post, Pi, Gam, delta_seq[k], y[:, k + 1, :, None], A=A, BBt=BBt, C=C, DDt=DDt,
                adj=adj_, weights=H_, kappa=kappa, threshold=threshold, inspect=inspect_,
                inspection_cov=inspection_cov, tol=tol, strict=strict, validate=(k == 0))
            d_r = st.delta_r
            x_post, Pi, Gam, theta = st.x_post, st.Pi_post, st.Gamma_post, st.theta
            if keep_bounds:
                for name, val in (("Pi", Pi), ("Gamma", Gam), ("K", st.gain[..., 0]),
                                  ("q1_psd", st.q1_psd), ("min_branch", st.min_branch),
                                  ("Gamma_eta", np.einsum("iyn,rinm,iym->ri", C, st.Gamma_prior, C)
                                   + DDt[0, 0]),
                                  ("Pi_eta", np.einsum("iyn,rinm,iym->ri", C, st.Pi_prior, C)
                                   + DDt[0, 0]), ("nis", st.nis)):
                    out[name].append(val)
        if not np.all(d_r == delta_seq[k]):  # literal (4) equals delta_k (P3)
            raise AssertionError(f"indicator (4) differs from delta_k at k = {k}")
        out["x"].append(x_post)
        out["theta"].append(theta)
    return {key: np.stack(val, axis=1) for key, val in out.items()}

# %% [markdown]
# ## The example (Section V): Cases A and B, no inspection, constant gains
#
# One run with the default seed. Case A has no attack. Case B adds $+15$ to $y_{4,k}$ for
# $k\in[90,95]$ and to $y_{12,k}$ for $k\in[50,55]$. The attacked data is not transmitted and
# touches no other sensor. "No inspection" is Case B with $\tilde\vartheta\equiv1$ in (34) and (35).

# %%
world = draw_world(rng_world, 1, N)
x_true, y_clean = world["x"], world["y"]
y_attacked = y_clean + attack
case_a = simulate(world["xh0"], y_clean, delta, keep_bounds=True)
case_b = simulate(world["xh0"], y_attacked, delta, keep_bounds=True)
no_insp = simulate(world["xh0"], y_attacked, delta, inspect_=False)
const_a = simulate(world["xh0"], y_clean, delta, const_gain=K_const)
const_b = simulate(world["xh0"], y_attacked, delta, const_gain=K_const)
k_all = np.arange(N + 1)


def pos_err(sim, x):
    """Position error x_hat_{i,k}(1) - x_{1,k}, shape (R, N+1, m)."""
    return sim["x"][..., 0] - x[:, :, None, 0]


def rmse(err, ks, i):
    """Position RMSE over steps ks at node index i, per run."""
    return np.sqrt(np.mean(err[:, ks, i] ** 2, axis=1))


err = {name: pos_err(sim, x_true) for name, sim in
       (("A", case_a), ("B", case_b), ("N", no_insp), ("cA", const_a), ("cB", const_b))}
rej_a = np.argwhere(case_a["theta"][0] == 0)
rej_b = np.argwhere(case_b["theta"][0] == 0)
print("Case A rejections (k, node):", [(int(k), int(i) + 1) for k, i in rej_a])
print("Case B rejections (k, node):", [(int(k), int(i) + 1) for k, i in rej_b])

# %% [markdown]
# ## Fig. 3 — measurements under attack
#
# Received $y_{4,k}$ and $y_{12,k}$. The normal measurement, without the injection, is dashed.
# The paper's note that normal curves are "attacked minus 15" confirms an additive constant.


# %%
def measurement_figure(nodes, name, title):
    fig, axes = plt.subplots(len(nodes), 1, figsize=(plotting.PAGE_WIDTH, 1.6 * len(nodes) + 0.4),
                             sharex=True)
    data = {"k": k_all[1:]}
    for ax, node in zip(np.atleast_1d(axes), nodes, strict=True):
        i = node - 1
        ax.plot(k_all[1:], y_attacked[0, 1:, i], color="tab:red", label=f"received $y_{{{node},k}}$")
        ax.plot(k_all[1:], y_clean[0, 1:, i], color="k", ls="--", lw=0.9, label="normal (no injection)")
        if node in windows:
            ax.axvspan(windows[node][0], windows[node][-1], color="tab:red", alpha=0.15,
                       label="attack window")
        ax.set_ylabel(f"$y_{{{node},k}}$ [sensor units]")
        ax.legend(loc="upper left", ncol=3)
        data[f"y{node}_received"] = y_attacked[0, 1:, i]
        data[f"y{node}_normal"] = y_clean[0, 1:, i]
    np.atleast_1d(axes)[-1].set_xlabel("time step k")
    np.atleast_1d(axes)[0].set_title(title)
    plotting.save_figure(fig, FIG_DIR, name, data=data)
    plt.show()


measurement_figure([4, 12], "fig3_measurements_attack", "Fig. 3: measurements subject to attacks")

# %% [markdown]
# ## Fig. 4 — position $x_{1,k}$ and its estimates at nodes 4, 12, 20
#
# (a) Case A. (b) Case B with the inspection (25). (c) Case B without the inspection.

# %%
node_colors = {4: "tab:orange", 12: "tab:green", 20: "tab:purple"}


def estimate_figure(sim, name, title, shade=True):
    fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 3.0))
    ax.plot(k_all, x_true[0, :, 0], color="k", lw=1.6, label=r"position $x_{1,k}$")
    data = {"k": k_all, "x1": x_true[0, :, 0]}
    for node in plot_nodes:
        ax.plot(k_all, sim["x"][0, :, node - 1, 0], color=node_colors.get(node), lw=1.0,
                label=f"estimate $\\hat x^+_{{{node},k}}(1)$, sensor {node}")
        data[f"xhat{node}"] = sim["x"][0, :, node - 1, 0]
    if shade:
        for ks in windows.values():
            ax.axvspan(ks[0], ks[-1], color="tab:red", alpha=0.12)
        ax.axvspan(0, 0, color="tab:red", alpha=0.12,
                   label=f"attack windows (sensors {', '.join(map(str, windows))})")
    ax.set_xlabel("time step k")
    ax.set_ylabel("position [length unit]")
    ax.set_xlim(0, N)
    ax.set_title(title)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=3)
    plotting.save_figure(fig, FIG_DIR, name, data=data)
    plt.show()


estimate_figure(case_a, "fig4a_estimates_case_a", "Fig. 4(a): Case A, no attack", shade=False)
estimate_figure(case_b, "fig4b_estimates_case_b", "Fig. 4(b): Case B, attacks, with inspection (25)")
estimate_figure(no_insp, "fig4c_estimates_no_inspection",
                "Fig. 4(c): Case B, attacks, inspection removed")

# %% [markdown]
# ## How far the attack leaks into unattacked nodes (claims C2a, C2b)
#
# Comparing Figs. 4(a) and 4(b), the paper finds "no obvious effect on the filtering performance with or
# without attacks". For the unattacked node 20 we read this as: its estimate is unaffected. The
# injected data never leaves the attacked sensor. It still reaches other nodes in two ways. The
# attacked node's estimate drifts during its six open-loop predictions, and the consensus term of
# (7) passes that drift to its neighbours. Its bound $\Pi^+$ also grows while updates are skipped. That
# bound enters the neighbours' $\tilde\Xi$ in (26), so their gains change. Each further hop
# attenuates the effect again (the coupling $\kappa$ is weak, but it acts at every step). How much node 20 moves therefore depends on how far it is from
# sensors 4 and 12 in Fig. 1, which we do not have.
#
# We measure the leak $\max_k\lVert\hat x^+_{i,k}(\text{B})-\hat x^+_{i,k}(\text{A})\rVert_\infty$ on ten
# stand-in topologies: the first ten seeds from the default, 2020–2029 (`leak_topology_seeds`). The list
# was fixed before the sweep ran; only seeds 2020 and 2021 had been looked at before (see the provenance
# table). The default topology is the first. Each topology gets one Case A and one Case B run on the default channel and world.
# We record node 20's leak with its hop distance to the nearest attacked sensor, and the leak of
# every unattacked node against its hop distance.

# %%
leak_rows = []  # (topology seed, node (1-based), hops to the nearest attacked sensor, leak)
for s_top in leak_topology_seeds:
    adj_s = graphs.check_connected(graphs.random_geometric_graph(m, radius, s_top))
    H_s = graphs.row_stochastic_weights(adj_s, self_weight=False)
    pair = simulate(np.concatenate([world["xh0"]] * 2), np.concatenate([y_clean, y_attacked]),
                    delta, net=(adj_s, H_s))
    leak_s = np.abs(pair["x"][1] - pair["x"][0]).max(axis=(0, 2))
    hops_s = dict(nx.all_pairs_shortest_path_length(nx.from_numpy_array(adj_s)))
    for i in range(m):
        h_i = min(hops_s[i][node - 1] for node in windows)
        if h_i > 0:
            leak_rows.append((s_top, i + 1, h_i, float(leak_s[i])))
leak_tab = np.array(leak_rows)
node20 = leak_tab[leak_tab[:, 1] == 20]
print("node 20 per topology seed (hops, leak):",
      ", ".join(f"{int(s_)}: ({int(h_)}, {v:.1e})" for s_, _, h_, v in node20))
leak_stats = {}
for h_ in np.unique(leak_tab[:, 2]).astype(int):
    v = leak_tab[leak_tab[:, 2] == h_, 3]
    leak_stats[str(h_)] = {"nodes": int(v.size), "min": float(v.min()), "median": float(np.median(v)),
                           "max": float(v.max()), "fraction_le_1e-3": float(np.mean(v <= 1e-3))}
    print(f"{h_} hop(s): {v.size:3d} node-topologies, leak min {v.min():.1e}, median {np.median(v):.1e}, "
          f"max {v.max():.1e}, fraction <= 1e-3: {np.mean(v <= 1e-3):.2f}")

# %%
fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 2.8))
jitter = (np.arange(len(leak_tab)) % 9 - 4) * 0.03
others = leak_tab[:, 1] != 20
ax.scatter(leak_tab[others, 2] + jitter[others], leak_tab[others, 3], s=10, color="0.55",
           label="other unattacked nodes (10 topologies)")
is20 = ~others
ax.scatter(leak_tab[is20, 2] + jitter[is20], leak_tab[is20, 3], s=30, color="tab:purple",
           edgecolors="k", lw=0.4, label="node 20 (10 topologies)")
dflt = is20 & (leak_tab[:, 0] == topology_seed)
ax.scatter(leak_tab[dflt, 2], leak_tab[dflt, 3], s=110, facecolors="none", edgecolors="tab:red",
           lw=1.4, label=f"node 20, default topology (seed {topology_seed})")
hop_axis = np.array([int(h_) for h_ in leak_stats])
ax.plot(hop_axis, [leak_stats[str(h_)]["median"] for h_ in hop_axis], color="k", marker="_",
        ms=14, lw=1.0, label="median over nodes and topologies")
ax.axhline(1e-3, color="tab:red", ls="--", lw=0.8, label="C2a limit $10^{-3}$")
ax.set_yscale("log")
ax.set_xticks(hop_axis)
ax.set_xlabel("hop distance to the nearest attacked sensor (4 or 12)")
ax.set_ylabel(r"leak $\max_k \|\hat x^+_B - \hat x^+_A\|_\infty$ [state units]")
ax.set_title("Extra: leak of the attack into unattacked nodes, Case B vs Case A")
ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
plotting.save_figure(fig, FIG_DIR, "extra_leak_by_hop",
                     data={"topology_seed": leak_tab[:, 0].astype(int), "node": leak_tab[:, 1].astype(int),
                           "hops": leak_tab[:, 2].astype(int), "leak": leak_tab[:, 3]},
                     tolerance={"leak": results.CANCELLATION})
plt.show()

# %% [markdown]
# **What holds and what does not.** The leak decays geometrically with the hop distance. Its
# median over nodes and topologies falls by more than a factor of ten per hop (printed above). Direct
# neighbours of an attacked sensor are clearly affected, by a few $10^{-3}$ up to about $0.2$
# in our runs, next to a position RMSE of about $0.3$–$0.5$ (P11). Two hops away the leak is around
# $10^{-3}$. From three hops on it is at most about $10^{-3}$, and mostly far below. Node 20 is unaffected
# in the paper's sense ($\le10^{-3}$) only in the topologies where it is at least two hops from
# sensors 4 and 12, and not in all of those. In our default topology it is a direct neighbour of
# sensor 12 (C2a does not hold). Its shift is still far too small to see at the scale of Fig. 4,
# which is all the paper's figure can show.

# %% [markdown]
# ## Figs. 5 and 6 — the constant-gain comparison filter
#
# The paper's comparison filter comes from LMIs of its refs. [9], [13] and is not specified
# beyond its gains. We use the same prediction (7), with the same $\kappa$, $\delta$ and $H$, and the
# update $\hat x^+=\hat x^-+K_i\eta$ with the printed constant gains and no detector. It is stable:
# the spectral radius of $(I-K_iC_i)A$ is printed below. The measurements
# are the same draws as in Fig. 3 (common random numbers), so Fig. 5 shows sensors 4, 12 and 20.

# %%
for label, kk, cc in (("nodes 1-7", K_const[0], C_rows[0]), ("nodes 8-20", K_const[-1], C_rows[-1])):
    rho = max(abs(np.linalg.eigvals((np.eye(3) - np.outer(kk, cc)) @ A)))
    print(f"{label}: C_i K_i = {cc @ kk:.4f}, spectral radius of (I - K_i C_i) A = {rho:.4f}")
measurement_figure([4, 12, 20], "fig5_measurements_comparison",
                   "Fig. 5: measurements of the comparison run (same draws as Fig. 3)")
estimate_figure(const_a, "fig6a_constant_gain_case_a", "Fig. 6(a): constant-gain filter, no attack",
                shade=False)
estimate_figure(const_b, "fig6b_constant_gain_case_b",
                "Fig. 6(b): constant-gain filter, attacks (no detector)")

# %% [markdown]
# ## What the bounds do in practice (P6, P8)
#
# Two counters show how the lower bound behaves. Whenever $\delta^r=1$ (after $k=0$),
# $\tilde Q_1$ is indefinite, so $\Gamma^-=BB^T$. $\Gamma^-$ and $\tilde S_1$ are never ordered, so
# $\Gamma^+=\lambda_{\min}I$ with $\lambda_{\min}\approx10^{-4}$. The test (25) therefore runs with
# an almost constant normaliser $\Gamma_\eta\approx C_iBB^TC_i^T+DD^T$. The table below lists these values.

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
for lo_, hi_, lab in ((0, 7, "nodes 1-7"), (7, m, "nodes 8-20")):
    cb = C_rows[lo_] @ BBt @ C_rows[lo_] + DDt[0, 0]
    print(f"{lab}: Gamma_eta median {np.median(g_eta[:, lo_:hi_]):.4f} "
          f"(C BB^T C^T + DD^T = {cb:.4f}); accepted |eta| < {np.sqrt(threshold * cb):.3f}")
print(f"for comparison, Pi_eta = C Pi^- C^T + DD^T of (32): median {np.median(case_a['Pi_eta'][0]):.3f}")

# %% [markdown]
# ## Exact covariance against the bounds (claim C5, extra figure)
#
# In Case A every update is accepted ($\tilde\vartheta\equiv1$). The conditioning on the test
# outcome behind Lemma 1 and Theorem 2 is then trivial (E12), and the gains $K_{i,k}$ depend only
# on $\delta$. So the exact stacked error covariance can be propagated. With
# $e_{i,k}=x_k-\hat x_{i,k}$ and $L=I-H$:
#
# $$e^-_{k+1}=\big(I\otimes A-\kappa\delta_k\,L\otimes A\big)e^+_k+(\mathbf 1\otimes B)w_k,\qquad
# e^+_{i,k+1}=(I-K_{i,k+1}C_i)e^-_{i,k+1}-K_{i,k+1}Dv_{i,k+1},$$
#
# with $\mathrm{cov}(e^+_0)=(\mathbf 1\mathbf 1^T+I)\otimes\sigma_0I$. We check
# $\lambda_{\min}(\Pi^+_{i,k}-P^+_{ii,k})\ge-10^{-9}\,\mathrm{tr}P^+_{ii,k}$ and the same for
# $P^+-\Gamma^+$. A Monte Carlo run of Case A cross-checks the propagation.


# %%
def exact_covariance(gains, delta_seq):
    """Stacked (3m x 3m) posterior error covariance for recorded gains (N, m, n)."""
    n3 = m * n_x
    P = np.kron(np.ones((m, m)) + np.eye(m), sigma0 * np.eye(n_x))
    L_mat = np.eye(m) - H
    bw = np.kron(np.ones((m, 1)), B)
    blocks = [np.stack([P[n_x * i:n_x * (i + 1), n_x * i:n_x * (i + 1)] for i in range(m)])]
    for k in range(gains.shape[0]):
        F = np.kron(np.eye(m), A) - kappa * delta_seq[k] * np.kron(L_mat, A)
        Pm = F @ P @ F.T + bw @ bw.T
        KC = np.zeros((n3, n3))
        KD = np.zeros((n3, m))
        for i in range(m):
            KC[n_x * i:n_x * (i + 1), n_x * i:n_x * (i + 1)] = np.outer(gains[k, i], C_rows[i])
            KD[n_x * i:n_x * (i + 1), i] = gains[k, i] * D[0, 0]
        G = np.eye(n3) - KC
        P = G @ Pm @ G.T + KD @ KD.T
        P = 0.5 * (P + P.T)
        blocks.append(np.stack([P[n_x * i:n_x * (i + 1), n_x * i:n_x * (i + 1)] for i in range(m)]))
    return np.stack(blocks)  # (N+1, m, n, n)


all_accepted_a = bool(np.all(case_a["theta"] == 1))
P_exact = exact_covariance(case_a["K"][0], delta)
tr_P = np.trace(P_exact, axis1=-2, axis2=-1)
Pi_a, Gam_a = case_a["Pi"][0], case_a["Gamma"][0]
gap_up = np.linalg.eigvalsh(Pi_a - P_exact)[..., 0] / tr_P
gap_low = np.linalg.eigvalsh(P_exact - Gam_a)[..., 0] / tr_P
ratio_tr = np.trace(Pi_a, axis1=-2, axis2=-1) / tr_P
print(f"Case A all accepted: {all_accepted_a}")
print(f"min_(i,k) lambda_min(Pi+ - P+)/tr P+ = {gap_up[1:].min():.3g}")
print(f"min_(i,k) lambda_min(P+ - Gamma+)/tr P+ = {gap_low[1:].min():.3g}")
print(f"median tr Pi+ / tr P+ = {np.median(ratio_tr[1:]):.3f}")

# %%
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(plotting.PAGE_WIDTH, 4.2), sharex=True,
                              height_ratios=[2, 1])
data = {"k": k_all}
for node in plot_nodes:
    i = node - 1
    c = node_colors.get(node)
    tr_pi_i = np.trace(Pi_a[:, i], axis1=-2, axis2=-1)
    tr_g_i = np.trace(Gam_a[:, i], axis1=-2, axis2=-1)
    ax.plot(k_all, tr_pi_i, color=c, label=f"sensor {node}: " + r"tr $\Pi^+$ (upper bound)")
    ax.plot(k_all, tr_P[:, i], color=c, ls="--", label=f"sensor {node}: " + r"tr $P^+$ (exact)")
    ax2.semilogy(k_all, tr_g_i, color=c, ls=":", label=f"sensor {node}: " + r"tr $\Gamma^+$ (lower bound)")
    data[f"trPi{node}"], data[f"trP{node}"], data[f"trGamma{node}"] = tr_pi_i, tr_P[:, i], tr_g_i
for a in (ax, ax2):
    for k in np.flatnonzero(delta == 0):
        a.axvspan(k, k + 1, color="0.8", lw=0)
ax.axvspan(0, 0, color="0.8", label=r"$\delta_k = 0$")
ax.set_yscale("log")
ax.set_ylim(2, 30)
ax.set_xlim(0, N)
ax.set_ylabel("trace [mixed units]")
ax.set_title(r"Extra: consistency of the bounds, Case A ($\Gamma^+ \preceq P^+ \preceq \Pi^+$)")
ax.legend(loc="upper center", ncol=3, fontsize=7)
ax2.set_ylim(1e-4, 1e2)
ax2.set_xlabel("time step k")
ax2.set_ylabel("trace [mixed units]")
ax2.legend(loc="upper right", ncol=3, fontsize=7)
plotting.save_figure(fig, FIG_DIR, "extra_bound_consistency", data=data)
plt.show()

# %% [markdown]
# The upper bound is conservative (median $\mathrm{tr}\,\Pi^+/\mathrm{tr}\,P^+$ printed above) but
# valid. It is tight along the measured direction, so $\lambda_{\min}(\Pi^+-P^+)$ sits at round-off
# level. One effect runs against intuition (P8): the crude consensus term
# $\tilde\Xi=2\sum\Pi$ inflates $\Pi^-$ by roughly $\kappa(1+\kappa)\,2(\lvert\mathcal N_i\rvert+1)$
# per step when $\delta=1$. So $\Pi^+$ *drops* when the channel fails, while the exact $P^+$ rises
# slightly because consensus is lost. The lower bound has collapsed to about $10^{-4}$ (P6).

# %% [markdown]
# ## Monte Carlo: detection, degradation and the χ² lockout
#
# We redraw $x_0$, $\hat x_{i,0}$, $w$ and $v$ in every run. The topology and the channel
# sequence $\delta$ of Fig. 2 stay fixed. All runs go through the vectorised step at once.
# The last case is an ablation of ours, not the paper's scheme: the test normalised by
# $\Pi_\eta$ instead of $\Gamma_\eta$.

# %%
mc_world = draw_world(rng_mc, R_MC, N)
mc_clean, mc_att = mc_world["y"], mc_world["y"] + attack
mc = {
    "A": simulate(mc_world["xh0"], mc_clean, delta, keep_bounds=False),
    "B": simulate(mc_world["xh0"], mc_att, delta),
    "N": simulate(mc_world["xh0"], mc_att, delta, inspect_=False),
    "B_Pi": simulate(mc_world["xh0"], mc_att, delta, inspection_cov="Pi"),
}
mc_err = {key: pos_err(sim, mc_world["x"]) for key, sim in mc.items()}
unattacked = np.setdiff1d(np.arange(m), [node - 1 for node in windows])
mc_stats = {}
for node, ks in windows.items():
    i = node - 1
    after = np.arange(ks[-1] + 1, N + 1)
    r_a, r_b, r_n = (rmse(mc_err[c], ks, i) for c in ("A", "B", "N"))
    th_b, th_pi = mc["B"]["theta"][:, :, i], mc["B_Pi"]["theta"][:, :, i]
    mc_stats[node] = {
        "reject_rate_window": float(1 - th_b[:, ks].mean()),
        "median_B_over_A": float(np.median(r_b / r_a)),
        "p05_noinsp_over_B": float(np.percentile(r_n / r_b, 5)),
        "median_noinsp_over_B": float(np.median(r_n / r_b)),
        "locked_at_end": float(np.mean(th_b[:, -1] == 0)),
        "any_reject_after": float(np.mean((th_b[:, after] == 0).any(axis=1))),
        "Pi_test_reject_rate_window": float(1 - th_pi[:, ks].mean()),
        "Pi_test_locked_at_end": float(np.mean(th_pi[:, -1] == 0)),
    }
false_alarms_a = int((mc["A"]["theta"] == 0).sum())
runs_with_alarm_a = float(np.mean((mc["A"]["theta"] == 0).any(axis=(1, 2))))
outside_b = int((mc["B"]["theta"][:, :, unattacked] == 0).sum())
print(f"{R_MC} runs. Case A: {false_alarms_a} rejections in total "
      f"({runs_with_alarm_a:.1%} of runs with one); Case B, unattacked nodes: {outside_b}")
for node, s in mc_stats.items():
    print(f"sensor {node}: " + ", ".join(f"{k} {v:.3f}" for k, v in s.items()))

# %%
fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 2.6))
data = {"k": k_all}
for node, ks in windows.items():
    i = node - 1
    c = node_colors.get(node)
    rate = 1 - mc["B"]["theta"][:, :, i].mean(axis=0)
    rate_pi = 1 - mc["B_Pi"]["theta"][:, :, i].mean(axis=0)
    ax.plot(k_all, rate, color=c, label=f"sensor {node}, test (25) with $\\Gamma_\\eta$ (paper)")
    ax.plot(k_all, rate_pi, color=c, ls=":",
            label=f"sensor {node}, test with $\\Pi_\\eta$ (ablation, ours)")
    ax.axvspan(ks[0], ks[-1], color="tab:red", alpha=0.12)
    data[f"reject_rate{node}"] = rate
    data[f"reject_rate_Pi{node}"] = rate_pi
ax.set_xlabel("time step k")
ax.set_ylabel(r"fraction of runs rejecting $y_{i,k}$")
ax.set_xlim(0, N)
ax.set_ylim(-0.02, 1.02)
ax.set_title(f"Extra: rejection rate over {R_MC} Monte Carlo runs, Case B (lockout after the windows)")
ax.legend(loc="center left", fontsize=7)
plotting.save_figure(fig, FIG_DIR, "extra_lockout_rate", data=data)
plt.show()

# %% [markdown]
# **The lockout mechanism (P5).** $\Gamma^+$ is a lower bound that holds whether or not the
# update happens, so it does not grow while updates are skipped. In practice it is pinned near
# $10^{-4}I$, and $\Gamma_\eta$ stays at its floor $C_iBB^TC_i^T+DD^T$. The prediction error,
# however, grows during the six skipped updates of an attack window. If the first clean innovation
# after the window exceeds $\sqrt{25\,\Gamma_\eta}\approx4.2$–$4.6$, it is rejected too. The next
# prediction is then worse again. The node never updates again and its error diverges: the
# estimate is open-loop for good. The paper's Fig. 4(b), like our default run, shows a run without a lockout.
# Over Monte Carlo runs the rate is far from zero (claim X1). A test normalised by $\Pi_\eta$,
# which grows while updates are skipped, does not lock out. But it lets part of the attack through
# (X2): it is not a fix within the paper's scheme.

# %% [markdown]
# ## Theorem 4 for the example
#
# $\xi_q=\zeta\bar\alpha^2\big(1-q+q(1+\kappa)(1+\kappa\bar N)\big)$ and
# $\xi_p=\zeta\bar\alpha^2\big(p+(1-p)(1+\kappa)(1+\kappa\bar N)\big)$ (42)–(43), with
# $\zeta=\big((1+\nu)\underline c^2+\bar c^2(1-\sigma)\big)/\underline c^2$. (41) holds if both are
# below 1. The proof's (45) carries $\tilde\kappa=2\kappa(1+\kappa)$, which gives
# $(1+\kappa)(1+2\kappa\bar N)$ instead (E9); we evaluate both forms.

# %%
alpha_bar = np.linalg.norm(A, 2)
c_norms = np.linalg.norm(C_rows, axis=1)
c_lo, c_hi = c_norms.min(), c_norms.max()
zeta = ((1 + nu) * c_lo**2 + c_hi**2 * (1 - sigma_fa)) / c_lo**2
thm4 = {}
for form, f in (("printed", 1.0), ("factor2", 2.0)):
    bracket = (1 + kappa) * (1 + f * kappa * N_bar)
    thm4[form] = {"xi_q": zeta * alpha_bar**2 * (1 - q + q * bracket),
                  "xi_p": zeta * alpha_bar**2 * (p + (1 - p) * bracket)}
print(f"alpha_bar^2 = {alpha_bar**2:.7f}, c_lo = {c_lo:.4f}, c_hi = {c_hi:.7f}, "
      f"zeta = {zeta:.6f}, zeta*alpha^2 = {zeta * alpha_bar**2:.5f}, N_bar = {N_bar}")
for form, v in thm4.items():
    print(f"{form:>8}: xi_q = {v['xi_q']:.4f}, xi_p = {v['xi_p']:.4f}")

# %% [markdown]
# **The condition fails, and it cannot hold for this plant.** The brackets are at least 1 for
# every $p,q\in[0,1]$ and $\kappa\ge0$. $\zeta\ge2-\sigma$ whatever $\nu\ge 0$, and $\bar\alpha^2=1.073$. So
# $\xi_q,\xi_p\ge\zeta\bar\alpha^2>2$. The condition would need $\lVert A\rVert^2<\approx0.5$, i.e. a
# strongly stable plant, and the paper's own target is marginally unstable. Theorem 4 therefore says nothing about the
# example. We show boundedness empirically instead (C8b): a long Case A run with its own channel chain.

# %%
delta_long = channels.gilbert_elliott(p, q, L_LONG + 1, rng_long, initial=delta0).astype(float)
world_long = draw_world(rng_long, 1, L_LONG)
long_run = simulate(world_long["xh0"], world_long["y"], delta_long, keep_bounds=True)
tr_pi_max = np.trace(long_run["Pi"][0], axis1=-2, axis2=-1).max(axis=1)
split = L_LONG // 2
early = float(tr_pi_max[100:split + 1].max())
late = float(tr_pi_max[split:].max())
long_rejections = int((long_run["theta"] == 0).sum())
print(f"{L_LONG} steps: max_i tr Pi+ in [100, {split}] = {early:.3f}, in [{split}, {L_LONG}] = "
      f"{late:.3f}, min over k >= 100 = {tr_pi_max[100:].min():.3f}; rejections: {long_rejections}")

fig, ax = plt.subplots(figsize=(plotting.PAGE_WIDTH, 2.2))
ax.plot(np.arange(L_LONG + 1), tr_pi_max, color="tab:blue", lw=0.7,
        label=r"$\max_i \mathrm{tr}\,\Pi^+_{i,k}$")
ax.axhline(1.5 * early, color="k", ls="--", lw=0.8, label="1.5 × max over the first half (C8b limit)")
ax.set_yscale("log")
ax.set_xlabel("time step k")
ax.set_ylabel(r"$\max_i \mathrm{tr}\,\Pi^+_{i,k}$ [mixed units]")
ax.set_xlim(0, L_LONG)
ax.set_title(f"Extra: the upper bound stays bounded over {L_LONG} steps (Case A) although (42)–(43) fail")
ax.set_ylim(0.5 * tr_pi_max.min(), 3 * early)
ax.legend(loc="lower right")
plotting.save_figure(fig, FIG_DIR, "extra_pi_long_run",
                     data={"k": np.arange(L_LONG + 1), "max_tr_Pi": tr_pi_max})
plt.show()

# %% [markdown]
# ## The channel statistics (C6)
#
# $\hat p=\#(1\to0)/\#1$ and $\hat q=\#(0\to1)/\#0$ over consecutive pairs, on a long chain and on
# the 151 samples of Fig. 2.


# %%
def rates(d):
    a, b = d[:-1], d[1:]
    return (float(np.sum((a == 1) & (b == 0)) / np.sum(a == 1)),
            float(np.sum((a == 0) & (b == 1)) / np.sum(a == 0)), float(d.mean()))


chain = channels.gilbert_elliott(p, q, chain_steps, rng_chain, initial=delta0)
p_hat, q_hat, frac1 = rates(chain)
p_fig2, q_fig2, _ = rates(delta)
stationary = channels.gilbert_elliott_stationary(p, q)
print(f"{chain_steps} steps: p_hat = {p_hat:.4f}, q_hat = {q_hat:.4f}, fraction of ones = "
      f"{frac1:.4f} (stationary {stationary:.5f}); Fig. 2: p_hat = {p_fig2:.3f}, q_hat = {q_fig2:.3f}")

# %% [markdown]
# ## Vectorised against per-node implementation (C10) and Remark 4 (C7)
#
# Twenty steps of Case B, once with `secure_filter_step` for all nodes and once with
# `secure_filter_node_step` node by node. The per-node step receives only the node's own data and its
# neighbours' packets.
#
# **Remark 4 (C7)** says that the cost per node, two inversions and $52+3\lvert\mathcal N_i\rvert$
# matrix products, does not depend on the network size. That is a timing claim. Timings are
# machine-dependent, so they belong to the benchmark suite, not to this notebook: `make bench` times
# `secure_filter_node_step` and `secure_filter_step` on graphs of growing size.

# %%
nbrs = graphs.neighbours(adj)
x_vec, Pi_vec = world["xh0"].copy(), np.broadcast_to(pi0_scale * sigma0 * np.eye(n_x),
                                                      (1, m, n_x, n_x)).copy()
G_vec = Pi_vec.copy()
x_loop, Pi_loop, G_loop = x_vec[0].copy(), Pi_vec[0].copy(), G_vec[0].copy()
steps_c10 = min(20, N)
for k in range(steps_c10):
    st = filters.secure_filter_step(x_vec, Pi_vec, G_vec, delta[k], y_attacked[:, k + 1, :, None],
                                    A=A, BBt=BBt, C=C, DDt=DDt, adj=adj, weights=H, kappa=kappa,
                                    threshold=threshold, tol=tol, strict=strict)
    x_vec, Pi_vec, G_vec = st.x_post, st.Pi_post, st.Gamma_post
    new = [filters.secure_filter_node_step(
        x_loop[i], Pi_loop[i], G_loop[i], x_loop[nbrs[i]], Pi_loop[nbrs[i]], H[i, nbrs[i]],
        int(delta[k]), y_attacked[0, k + 1, i:i + 1], A=A, BBt=BBt, C_i=C[i], DDt=DDt,
        kappa=kappa, threshold=threshold, tol=tol, strict=strict) for i in range(m)]
    x_loop = np.stack([r[0] for r in new])
    Pi_loop = np.stack([r[1] for r in new])
    G_loop = np.stack([r[2] for r in new])
c10_diff = float(max(np.abs(x_vec[0] - x_loop).max(),
                     np.abs(Pi_vec[0] - Pi_loop).max() / np.abs(Pi_loop).max(),
                     np.abs(G_vec[0] - G_loop).max() / np.abs(G_loop).max()))
print(f"max |vectorised - per-node| after {steps_c10} steps: x {np.abs(x_vec[0] - x_loop).max():.2g}, "
      f"Pi {np.abs(Pi_vec[0] - Pi_loop).max():.2g}, Gamma {np.abs(G_vec[0] - G_loop).max():.2g}")

# %% [markdown]
# ## Claims
#
# RMSE means position RMSE. A window is $k\in[90,95]$ for sensor 4 and $k\in[50,55]$ for sensor 12.
# The overall RMSE is over $k=1,\dots,150$. Thresholds are those of the reproduction brief.

# %%
w4, w12 = windows[4] if 4 in windows else None, windows[12] if 12 in windows else None
ks_all = np.arange(1, N + 1)
att_idx = {node: node - 1 for node in windows}
claims = {}

# C1: detection
rejected_b = {(int(k), int(i) + 1) for k, i in rej_b}
expected_b = {(int(k), node) for node, ks in windows.items() for k in ks}
c1_default = rejected_b == expected_b and rej_a.size == 0
c1_rates = {f"sensor{node}": mc_stats[node]["reject_rate_window"] for node in windows}
claims["C1"] = results.claim(
    paper="Fig. 4(b), Sec. V: the chi-square inspection (25) detects the injected data",
    check="default seed: exactly the attacked (k, sensor) pairs are rejected in Case B and none in "
    "Case A; Monte Carlo rejection rate inside the windows >= 0.99",
    measured={"default_rejected_in_windows": len(rejected_b & expected_b),
              "default_attacked_samples": len(expected_b),
              "default_rejections_elsewhere": len(rejected_b - expected_b) + int(rej_a.shape[0]),
              "mc_reject_rate_window": c1_rates, "mc_runs": R_MC},
    threshold={"mc_reject_rate_window": 0.99, "default_rejections_elsewhere": 0},
    holds=bool(c1_default and min(c1_rates.values()) >= 0.99),
)

# C2a: the paper's statement about node 20, over the ten stand-in topologies
diff20 = float(np.abs(case_b["x"][0, :, 19] - case_a["x"][0, :, 19]).max())
leak_by_hop_default = {}
for i in unattacked:
    h_min = min(hops[i][a] for a in att_idx.values())
    leak = float(np.abs(case_b["x"][0, :, i] - case_a["x"][0, :, i]).max())
    leak_by_hop_default[h_min] = max(leak_by_hop_default.get(h_min, 0.0), leak)
per_seed20 = {str(int(s_)): {"hops": int(h_), "leak": float(v)} for s_, _, h_, v in node20}
claims["C2a"] = results.claim(
    paper="Sec. V, Figs. 4(a)-(b): 'there is no obvious effect on the filtering performance with or "
    "without attacks'; for the unattacked node 20 (brief's reading): its estimate is unaffected "
    "by the attacks on sensors 4 and 12",
    check="leak = max_k ||x_hat_B - x_hat_A||_inf at sensor 20 <= 1e-3 in every one of the ten stand-in "
    f"topologies (seeds {leak_topology_seeds[0]}..{leak_topology_seeds[-1]}, fixed in advance; the "
    f"default topology is seed {topology_seed}); node 20's hop distance to the nearest attacked "
    "sensor is reported with each leak",
    measured={"default_topology_seed": topology_seed, "sensor20_default": diff20,
              "hops_sensor20_default": [hops[19][a] for a in att_idx.values()],
              "sensor20_by_topology": per_seed20,
              "topologies_sensor20_le_1e-3": int(sum(v["leak"] <= 1e-3 for v in per_seed20.values())),
              "topologies": len(per_seed20),
              "default_max_leak_by_hop": {str(h): v for h, v in sorted(leak_by_hop_default.items())}},
    threshold=1e-3,
    holds=bool(all(v["leak"] <= 1e-3 for v in per_seed20.values())),
    tolerance=results.CANCELLATION,
)

# C2b: how the leak decays with the hop distance (our criterion)
hop_keys = sorted(leak_stats, key=int)
med_ratio_hop = [leak_stats[a]["median"] / leak_stats[b]["median"]
                 for a, b in zip(hop_keys[:-1], hop_keys[1:], strict=True)]
claims["C2b"] = results.claim(
    paper="(ours, quantifying C2a; no paper statement) the attack reaches unattacked nodes only "
    "through the consensus term and the neighbours' bounds, so its effect decays with the hop "
    "distance from the attacked sensors",
    check="criterion (ours): over all unattacked nodes of the ten stand-in topologies, the median "
    "leak max_k ||x_hat_B - x_hat_A||_inf falls by at least a factor of 10 per hop; min, median, "
    "max and the fraction <= 1e-3 reported per hop distance",
    measured={"by_hops": leak_stats, "median_ratio_per_hop": med_ratio_hop},
    threshold={"median_ratio_per_hop": 10.0},
    holds=bool(len(med_ratio_hop) > 0 and min(med_ratio_hop) >= 10.0),
    tolerance=results.CANCELLATION,
)
print("leak by hop, median ratio per hop:", [f"{r:.1f}" for r in med_ratio_hop])

# C3: mild effect with detection
max_err_b = {f"sensor{node}": float(np.abs(err["B"][0, ks, node - 1]).max()) for node, ks in windows.items()}
med_ratio = {f"sensor{node}": mc_stats[node]["median_B_over_A"] for node in windows}
default_ratio = {f"sensor{node}": float(rmse(err["B"], ks, node - 1)[0] / rmse(err["A"], ks, node - 1)[0])
                 for node, ks in windows.items()}
claims["C3"] = results.claim(
    paper="Sec. V: with detection the attacked nodes are only mildly affected (Fig. 4(b) vs 4(a))",
    check="Monte Carlo median of RMSE_B(window)/RMSE_A(window) <= 3 at each attacked sensor; "
    "default seed: max |position error| in the window <= 2",
    measured={"mc_median_ratio": med_ratio, "default_max_abs_error": max_err_b,
              "default_ratio": default_ratio},
    threshold={"mc_median_ratio": 3.0, "default_max_abs_error": 2.0},
    holds=bool(max(med_ratio.values()) <= 3.0 and max(max_err_b.values()) <= 2.0),
)

# C4: degradation without inspection
ratio_na = {f"sensor{node}": float(rmse(err["N"], ks, node - 1)[0] / rmse(err["A"], ks, node - 1)[0])
            for node, ks in windows.items()}
p05 = {f"sensor{node}": mc_stats[node]["p05_noinsp_over_B"] for node in windows}
claims["C4"] = results.claim(
    paper="Sec. V, Fig. 4(c): without the inspection the filtering performance degrades at the "
    "attack instants",
    check="default seed: RMSE_noinsp(window)/RMSE_A(window) >= 5; Monte Carlo 5th percentile of "
    "RMSE_noinsp(window)/RMSE_B(window) >= 2.5",
    measured={"default_ratio_vs_A": ratio_na, "mc_p05_ratio_vs_B": p05,
              "mc_median_ratio_vs_B": {f"sensor{n}": mc_stats[n]["median_noinsp_over_B"]
                                       for n in windows}},
    threshold={"default_ratio_vs_A": 5.0, "mc_p05_ratio_vs_B": 2.5},
    holds=bool(min(ratio_na.values()) >= 5.0 and min(p05.values()) >= 2.5),
)

# C5: bounds against the exact covariance, with MC cross-check
# runs with a (rare) false alarm in Case A have other gains: the exact P applies to the others
clean_runs = np.all(mc["A"]["theta"] == 1, axis=(1, 2))
e_mc = (mc_world["x"][:, :, None, :] - mc["A"]["x"])[clean_runs]
emp_cov = np.einsum("rkia,rkib->kiab", e_mc, e_mc) / e_mc.shape[0]
frob = np.linalg.norm(emp_cov - P_exact, axis=(-2, -1)) / np.linalg.norm(P_exact, axis=(-2, -1))
mc_err_med = float(np.median(frob[1:]))
mc_thr = 0.12 * np.sqrt(300 / int(clean_runs.sum()))
claims["C5"] = results.claim(
    paper="(8)/Theorems 1-3: Gamma+ <= P+ <= Pi+ for every node and step",
    check="Case A (all updates accepted): min over (i, k >= 1) of lambda_min(Pi+ - P+)/tr P+ and "
    "lambda_min(P+ - Gamma+)/tr P+ >= -1e-9, P+ the exact stacked covariance; its Monte Carlo "
    "cross-check on the Monte Carlo runs without any rejection (median relative Frobenius "
    "error) <= 0.12*sqrt(300/runs)",
    measured={"case_a_all_accepted": all_accepted_a,
              "min_eig_Pi_minus_P_rel": float(gap_up[1:].min()),
              "min_eig_P_minus_Gamma_rel": float(gap_low[1:].min()),
              "median_trPi_over_trP": float(np.median(ratio_tr[1:])),
              "mc_median_rel_frobenius_error": mc_err_med,
              "mc_runs_all_accepted": int(clean_runs.sum()), "mc_runs": R_MC},
    threshold={"min_eig_rel": -1e-9, "mc_median_rel_frobenius_error": mc_thr},
    holds=bool(all_accepted_a and gap_up[1:].min() >= -1e-9 and gap_low[1:].min() >= -1e-9
               and mc_err_med <= mc_thr),
)

# C6: channel statistics
claims["C6"] = results.claim(
    paper="Sec. II: delta_k is a Gilbert-Elliott chain with failure rate p and recovery rate q",
    check=f"on {chain_steps} steps: |p_hat - p| <= 0.005, |q_hat - q| <= 0.015, |fraction of ones - "
    "q/(p+q)| <= 0.005; Fig. 2 sequence reported",
    measured={"p_hat": p_hat, "q_hat": q_hat, "fraction_ones": frac1,
              "fig2_p_hat": p_fig2, "fig2_q_hat": q_fig2, "fig2_ones": int(delta.sum()),
              "chain_steps": chain_steps},
    threshold={"p": p, "q": q, "stationary": stationary, "tol_p": 0.005, "tol_q": 0.015,
               "tol_stationary": 0.005},
    holds=bool(abs(p_hat - p) <= 0.005 and abs(q_hat - q) <= 0.015
               and abs(frac1 - stationary) <= 0.005),
)

# C8a: Theorem 4's sufficient condition for the example
thm4_holds = all(v["xi_q"] < 1 and v["xi_p"] < 1 for v in thm4.values())
claims["C8a"] = results.claim(
    paper="Theorem 4, (42)-(43): the mean upper bound sum_i ||E Pi+_{i,k}|| stays bounded if "
    "xi_q < 1 and xi_p < 1; Sec. V applies the scheme to the example",
    check="xi_q < 1 and xi_p < 1 for the example's values (p, q, kappa, A, C_i, threshold 25, "
    "nu = 0, N_bar = 1 + max degree), in the printed form of (42)-(43) and in the factor-2 form "
    "of the proof's (45)",
    measured={"xi": thm4, "N_bar": int(N_bar), "zeta_alpha2": float(zeta * alpha_bar**2)},
    threshold={"xi": 1.0},
    holds=bool(thm4_holds),
)

# C8b: Pi bounded over a long run (empirical)
claims["C8b"] = results.claim(
    paper="Theorem 4 / problem R2: Pi+_{i,k} stays bounded as k grows",
    check=f"empirical, one Case A run of {L_LONG} steps with its own channel chain: "
    f"max_i tr Pi+ over k in [{split}, {L_LONG}] <= 1.5 x its max over k in [100, {split}]",
    measured={"max_trPi_first_half": early, "max_trPi_second_half": late, "steps": L_LONG,
              "rejections": long_rejections},
    threshold={"growth_factor": 1.5},
    holds=bool(late <= 1.5 * early),
)

# C9: comparison with the constant-gain filter
ratio_const = {f"sensor{n}": float(rmse(err["cA"], ks_all, n - 1)[0] / rmse(err["A"], ks_all, n - 1)[0])
               for n in plot_nodes}
ratio_const_win = {f"sensor{n}": float(rmse(err["cB"], ks, n - 1)[0] / rmse(err["cA"], ks, n - 1)[0])
                   for n, ks in windows.items()}
claims["C9"] = results.claim(
    paper="Sec. V, Figs. 5-6: without attacks the LMI (constant-gain) filter performs similarly; "
    "under attack the proposed filter is more reliable",
    check="RMSE_const,A/RMSE_A over k = 1..150 in [0.8, 1.6] at sensors 4, 12, 20; "
    "RMSE_const,B(window)/RMSE_const,A(window) >= 5",
    measured={"overall_ratio_const_vs_proposed": ratio_const, "window_ratio_const_B_vs_A": ratio_const_win,
              "cmp_form": cmp_form},
    threshold={"overall_ratio": [0.8, 1.6], "window_ratio": 5.0},
    holds=bool(all(0.8 <= v <= 1.6 for v in ratio_const.values())
               and min(ratio_const_win.values()) >= 5.0),
)

# C10: vectorised against per-node
claims["C10"] = results.claim(
    paper="Remark 4: the filter is computed node by node from neighbour data only",
    check=f"after {steps_c10} steps of Case B: max of |x_vec - x_loop|, |Pi_vec - Pi_loop|/max|Pi| "
    "and |Gamma_vec - Gamma_loop|/max|Gamma| <= 1e-10",
    measured=c10_diff,
    threshold=1e-10,
    holds=c10_diff <= 1e-10,
    tolerance=results.ROUNDING_RESIDUAL,
)

# X1: lockout rate (ours, not a paper claim)
locked = {f"sensor{n}": mc_stats[n]["locked_at_end"] for n in windows}
claims["X1"] = results.claim(
    paper="(implied by Fig. 4(b)) after the attack window the attacked nodes resume normal filtering",
    check="fraction of Monte Carlo runs in which the attacked sensor still rejects at k = 150 "
    "(locked out); also the fraction with any rejection after its window, and Case A false alarms",
    measured={"locked_at_end": locked,
              "any_reject_after_window": {f"sensor{n}": mc_stats[n]["any_reject_after"]
                                          for n in windows},
              "case_a_runs_with_rejection": runs_with_alarm_a, "mc_runs": R_MC},
    threshold=0.0,
    holds=bool(max(locked.values()) == 0.0),
)

# X2: ablation with Pi_eta (ours)
x2_lock = max(mc_stats[n]["Pi_test_locked_at_end"] for n in windows)
x2_rate = min(mc_stats[n]["Pi_test_reject_rate_window"] for n in windows)
claims["X2"] = results.claim(
    paper="(ours, no paper statement) question: does normalising the test by Pi_eta instead of "
    "Gamma_eta fix the chi-square lockout (X1) without giving up detection?",
    check="criterion (ours): a fix needs, at both attacked sensors over the Monte Carlo runs, "
    "(i) lockout rate at k = 150 equal to 0 and (ii) rejection rate inside the windows >= 0.99, "
    "the detection level C1 requires of the paper's test; holds = (i) and (ii)",
    measured={**{f"sensor{n}": {"reject_rate_window": mc_stats[n]["Pi_test_reject_rate_window"],
                                "locked_at_end": mc_stats[n]["Pi_test_locked_at_end"]} for n in windows},
              "removes_lockout": bool(x2_lock == 0.0), "keeps_detection": bool(x2_rate >= 0.99),
              "mc_runs": R_MC},
    threshold={"locked_at_end": 0.0, "reject_rate_window": 0.99},
    holds=bool(x2_lock == 0.0 and x2_rate >= 0.99),
)

results.write_claims(results_path, claims)
for cid, c in claims.items():
    print(cid, "holds" if c["holds"] else "DOES NOT HOLD")

# %% [markdown]
# The claims table with what each one means for the paper:
#
# | id | paper | verdict |
# |---|---|---|
# | C1 | the detector catches the injections | holds: every attacked sample is rejected, and there are no false alarms in the default run |
# | C2a | the unattacked node 20 is unaffected ($\le10^{-3}$) | **does not hold** in general. Node 20's leak depends on its hop distance to sensors 4 and 12 in the unknown Fig. 1. Over the ten stand-in topologies it stays $\le10^{-3}$ only in some of those where it is at least two hops away. In the default topology it is a direct neighbour of sensor 12 and moves by about $10^{-2}$, which is invisible at the scale of Fig. 4 |
# | C2b | (ours) the leak decays with the hop distance | holds: the median leak falls by more than 10× per hop. Direct neighbours move by a few $10^{-3}$ up to about 0.2, nodes two hops away by about $10^{-3}$. The effect comes through the consensus term and through the attacked node's inflated $\Pi^+$, which enters their $\tilde\Xi$ and changes their gains |
# | C3 | mild effect with detection | holds (median ratio about 2: six open-loop predictions) |
# | C4 | degradation without inspection | holds, by an order of magnitude |
# | C5 | $\Gamma^+\preceq P^+\preceq\Pi^+$ | holds against the exact covariance (Case A) |
# | C6 | channel follows $(p,q)$ | holds |
# | C7 | Remark 4, cost per node independent of $m$ | timing: `make bench` |
# | C8a | Theorem 4's sufficient condition (42)–(43) for the example | **does not hold**: $\xi_q,\xi_p\approx2.46$ (2.56 with the proof's factor 2), and no $(p,q,\kappa)$ can satisfy it with this plant. Theorem 4 says nothing about the example |
# | C8b | $\Pi^+$ stays bounded (Theorem 4's conclusion) | holds empirically over 2000 steps (Case A), although the condition fails |
# | C9 | LMI filter similar without attack, worse with | holds with our stand-in structure of the comparison filter |
# | C10 | per-node computation | vectorised and per-node steps agree to round-off |
# | X1 | (ours) recovery after the attack | **does not hold**: χ² lockout in a sizeable fraction of runs |
# | X2 | (ours) does the Π-normalised test fix the lockout without giving up detection? | **no**, by our criterion (no lockout *and* ≥ 0.99 of attacked samples rejected): it removes the lockout but rejects only about 60 % of the attacked samples |

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
# | E8 | $\nu$ in Assumption 2 | bounds $\mathbb P\{\vartheta=0,\tilde\vartheta=1\}\equiv0$ | read as the extra rejection probability; $\nu=0$ | the printed event is empty |
# | E9 | (42)–(43) vs (45) | $(1+\kappa)(1+\kappa\bar N)$ vs $\tilde\kappa=2\kappa(1+\kappa)$ | both evaluated | neither changes the verdict |
# | E10 | noise index in (10), (16) | $v_{i,k}$ | $v_{i,k+1}$ | typo |
# | E11 | Remark 2 | $\sigma$ "detection probability" | false-alarm probability $5.73\cdot10^{-7}$ | threshold 25 is the $(1-\sigma)$-quantile |
# | E12 | Lemma 1 / Thm 2 conditioning | conditional on the test outcome | bounds checked on Case A only (all accepted) | conditioning on $\vartheta$ truncates $\eta$ |
# | — | Theorem 4 | claims boundedness under (42)–(43) | the condition fails for the example (C8a, recorded as not holding); boundedness is shown empirically (C8b) | $\zeta\bar\alpha^2>2$ |
# | — | node 20 unaffected (Fig. 4(b)) | unattacked node 20 unchanged | measured over ten stand-in topologies. It fails where node 20 is a direct neighbour of an attacked sensor, including the default topology (C2a). The leak decays by more than 10× per hop (C2b, our criterion) | Fig. 1 not available |
# | — | Π-normalised test (X2) | — | our ablation, judged by our own criterion: a fix must remove the lockout and keep ≥ 0.99 of attacked samples rejected | no paper statement |
# | — | Fig. 1 topology | a figure we do not have | random geometric graph, $r=0.35$, seed 2020 (the first candidate) | C2a depends on node 20's hop distance to the attacked nodes, so C2 is measured over ten stand-in topologies (seeds 2020–2029, fixed in advance). An earlier version switched to seed 2021 after seeing seed 2020's result; that was dropped |
# | — | comparison filter | LMI design of refs. [9], [13] | printed constant gains in structure (7) without detector | structure not given |
# | — | Fig. 5 | measurements of the comparison run | identical to Fig. 3 (common random numbers), sensors 4, 12, 20 | same draws, as the paper states |
# | — | initial values | "randomly produced" | $x_0$, $\hat x^+_{i,0}$ i.i.d. $\mathcal N(0, I_3)$, independent | zero mean keeps (9)–(10); non-zero estimates make (4) exact at $k=0$ (P3) |
# | — | $\Pi^+_0$, $\Gamma^+_0$ | not given | $2I_3$, the exact initial error covariance | both bounds hold at $k=0$ |
# | — | $\delta_0$ | not given | $\delta_0=1$ (`delta0`) | channel initially good |
# | — | first measurement update | not stated | at $k=1$ (no update at $k=0$; the first measurement used is $y_{i,1}$) | (7) updates at $k+1$ |
# | — | `tol`, `strict` | order relations of (17)–(19), (27) without a numerical tolerance | relative tolerance $10^{-10}$ for every $\succeq0$ / $\preceq$ test; non-strict reading of "$Y\prec X$" (`strict=False`) | round-off; the strict reading breaks (35) (E6) |
# | — | Monte Carlo sizes | one run per figure | 300 runs (fast mode 100) for C1, C3, C4, C5, X1, X2; one 2000-step run (fast mode 600) for C8b; a $10^5$-step chain for C6; one Case A/B pair on each of ten topologies for C2 | the paper reports single runs |
# | — | seeds and common random numbers | not given; the paper says the comparison uses the same parameters and channel | `SeedSequence(2020).spawn(5)` (channel, world, Monte Carlo, chain, long run). Cases A, B, no inspection and the comparison filter share $\delta$, $x_0$, $\hat x_0$, $w$, $v$; the Monte Carlo runs share the topology and $\delta$ of Fig. 2 and redraw $x_0$, $\hat x_0$, $w$, $v$ | comparable curves; common random numbers reduce the variance of the ratios |
# | — | delivery of $\Pi^+_{j,k}$ | not stated | sent in the same packet as $\hat x^+_{j,k}$, lost with it | (26) needs the neighbours' bounds only when $\delta^r=1$ |
# | — | Monte Carlo cross-check of C5 | — | uses the Case A runs without any rejection (a rare false alarm changes that run's gains) | the exact covariance is computed for the all-accepted gains |
# | — | Remark 4 timing (C7) | cost per node independent of $m$ | not measured here | timings belong to `make bench` |
# | — | χ² lockout | not shown | measured (X1), mechanism explained | the paper's scheme has it |

# %%
manifest_path = run.finish(extra={"mc_runs": R_MC, "long_steps": L_LONG})
print("run manifest:", manifest_path.relative_to(results.repo_root()))
