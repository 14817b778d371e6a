# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (secest)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # lee2020 — Fully distributed resilient state estimation based on a distributed median solver
#
# J. G. Lee, J. Kim and H. Shim, "Fully distributed resilient state estimation based on
# distributed median solver", *IEEE Transactions on Automatic Control*, 2020,
# doi:10.1109/TAC.2020.2989275.
#
# **Summary.** A median is what a resilient estimator needs: with at most $q$ of $2q+1$
# redundant measurements corrupted, the median of the measurements stays among the honest
# ones. The paper computes a median *without any agent seeing all measurements*: each agent
# follows the sign of its own residual and is coupled diffusively to its neighbours (the
# distributed median solver (4)); Theorem 1 bounds the final distance to the median set by
# $2\sqrt N/(\gamma\lambda_2(\mathcal L))$. For a linear plant measured by $N$ sensor banks, none
# of which needs to observe the whole state, a basis shared by all banks' unobservable subspaces
# (Assumption 4) turns state estimation into one median per coordinate: every agent runs a
# partial Luenberger observer (5) for the coordinates its bank sees, and a copy of the plant
# corrected by coordinate-wise sign terms and consensus with its neighbours (6). Coordinates an
# agent cannot see are supplied by its neighbours; a corrupted minority of banks is out-voted by
# the distributed median (Theorem 2, semi-global; Theorem 3 and variant (11), global for
# Lyapunov-stable plants). The example: a three-inertia system with five single-sensor banks on a
# ring, and an attack on sensor 1 that agent 1 alone cannot detect.
#
# **Verdict: [Re].** Every claim that numbers can check holds: Theorem 1 on every graph and
# gain tested; 2q-redundant observability ($q=1$) and Assumption 4 with a constructed basis;
# Fig. 1 — agent 1's own estimate is off by exactly $\pi$ after the attack while the network's
# estimates are not. The printed Fig. 1 is not available (OCR text only), and the observer poles,
# basis, initial conditions and horizon are ours. At the paper's gains the resilient estimates
# keep offsets of $O(1/\gamma)$ (0.65 rad on agent 1's θ-sum at $\gamma=2$), consistent with the
# semi-global Theorem 2 and predicted here in closed form.

# %% tags=["parameters"]
mode = "paper"  # "paper": the full runs; "fast": shorter horizons for the tests
T = 20.0  # horizon of the Section II demo [s] (MISSING; brief Fig. S1)
dt = 1e-3  # explicit Euler step of the Section II solver [s] (MISSING)
gamma = 5.0  # coupling gain of (4) in the Section II demo (MISSING; brief Fig. S1)
z = [0.8, 1.3, 0.9, 1.1, 1.6, 0.5, 6.0]  # measured values z_i; agent 7 attacked (MISSING)
s = [1, 1, 1, 1, 1, 0, 1]  # indicators s_i; agent 6 has no measurement (MISSING)
x0 = [-2.0, 3.0, 0.0, 1.0, -1.0, 4.0, 2.0]  # initial solver states x_i(0) (MISSING)
settle_fraction = 0.25  # "limsup": max distance over this last fraction of the horizon
sweep_gammas = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0]  # Theorem 1 sweep (ours)
sweep_T = 20.0  # horizon of the sweep [s] (ours)
sweep_z5 = [0.8, 1.3, 0.9, 1.1, 6.0]  # values of the ring-5 case, agent 5 attacked (ours)
sweep_x05 = [-2.0, 3.0, 0.0, 1.0, -1.0]  # initial states of the ring-5 case (ours)
J_inertia = 0.01  # J1, J2, J3 [kg m^2] (PAPER, Section IV)
b_damping = 0.007  # b1, b2, b3 [N m s/rad] (PAPER)
k_spring = 1.37  # k1, k2 [N m/rad] (PAPER)
u_amplitude = 0.01  # u(t) is u_amplitude * sin(u_frequency t) [N m] (PAPER)
u_frequency = 0.5  # [rad/s] (PAPER)
kappa = 0.5  # gain of the sign correction in (6) (PAPER)
gamma_ex = 2.0  # coupling gain of (6) (PAPER)
q = 1  # number of corruptible banks (PAPER: "2-redundant observable")
ring_order = [1, 2, 3, 4, 5]  # agents around the ring (MISSING: "ring network")
attack_bank = 1  # attacked sensor bank, 1-based (PAPER)
attack_amplitude = 1.0471975511965976  # pi/3 rad (PAPER)
attack_start = 10.0  # [s] (PAPER)
x0_plant = [0.5, 0.0, 0.3, 0.0, 0.1, 0.0]  # plant state x(0) (MISSING)
z0_guess = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # z_i(0) is W_i z0_guess; N rows: one per agent (MISSING)
xhat0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # x_hat_i(0) of every agent; N rows: one per agent (MISSING)
T_ex = 40.0  # horizon of the example [s] (MISSING)
dt_ex = 1e-3  # exponential-Euler step of the example [s] (MISSING)
record_dt = 0.01  # recording grid [s]
final_window = 5.0  # steady-state values are averages over the last final_window seconds
observer_poles = "near"  # "near" (-1, -1.1, ...) or "shifted" (MISSING: "near -1")
offset_gammas = [2.0, 5.0, 20.0]  # gains of the offset-law check (ours)
amplitude_sweep = [3.141592653589793, 10.0]  # further attack sizes [rad] (ours)
accuracy_T = 20.0  # horizon of the integrator comparison [s] (ours)
accuracy_ref_dt = 1e-4  # step of the reference solution [s] (ours)
tanh_eps = [1e-3, 1e-2]  # widths of the smoothed sign for RK45 (ours)
stall_T = 0.002  # horizon of the exact-sign RK45 demonstration [s] (ours)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/lee2020"
results_path = "figures/lee2020/claims.json"

# %%
import control
import cvxpy as cp
import matplotlib.pyplot as plt
import matplotlib.ticker as mticker
import networkx as nx
import numpy as np
import scipy.linalg as sla
from scipy.integrate import solve_ivp

from secest import graphs, plotting, results, systems

print(results.environment_summary())

run = results.Run("lee2020", globals())
if mode not in ("paper", "fast"):
    raise ValueError(f"mode must be 'paper' or 'fast', found {mode!r}")
horizon = T if mode == "paper" else min(T, 10.0)
sweep_horizon = sweep_T if mode == "paper" else min(sweep_T, 10.0)
accuracy_T = accuracy_T if mode == "paper" else min(accuracy_T, 8.0)
stall_T = stall_T if mode == "paper" else min(stall_T, 5e-4)
z_vals, s_vals, x_init = np.asarray(z, float), np.asarray(s, float), np.asarray(x0, float)
N = z_vals.size
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)

# %% [markdown]
# ## Parameter provenance
#
# Section II of the paper has no numerical example; every Section II value is ours. Section IV
# gives the plant, the gains $\kappa,\gamma$, the network type and the attack.
#
# | name | value | tag | source / reason |
# |---|---|---|---|
# | graphs (Section II) | ring and all-to-all, $N=7$; ring $N=5$ in the sweep | PAPER | Remark 2 discusses exactly these two families |
# | `z` | 0.8, 1.3, 0.9, 1.1, 1.6, 0.5, 6.0 | MISSING | clean values near 1, agent 7 attacked (6.0) |
# | `s` | 1, 1, 1, 1, 1, 0, 1 | MISSING | agent 6 has no measurement, so $S=6$ is even and the median set is an interval |
# | `x0` | −2, 3, 0, 1, −1, 4, 2 | MISSING | spread initial states, so convergence is visible |
# | `gamma` | 5 | MISSING | a moderate gain for the demo |
# | `T`, `dt` | 20 s, 1e-3 s | MISSING | explicit Euler; $dt < 2/(\gamma\lambda_{\max}(\mathcal L))$ = 0.1 (ring) and 0.057 (all-to-all) |
# | `settle_fraction` | 0.25 | MISSING | "limsup" measured as the max over the last quarter of the horizon |
# | `sweep_gammas`, `sweep_T`, `sweep_z5`, `sweep_x05` | 0.5 … 50; 20 s; ring-5 data | MISSING | Theorem 1 across graphs and gains (ours) |
# | `J_inertia`, `b_damping`, `k_spring` | 0.01, 0.007, 1.37 | PAPER (IV) | three-inertia system |
# | `u_amplitude`, `u_frequency` | 0.01, 0.5 rad/s | PAPER (IV) | $u=0.01\sin(0.5t)$ |
# | `kappa`, `gamma_ex` | 0.5, 2 | PAPER (IV) | gains of (6) |
# | `q` | 1 | PAPER (IV) | "2-redundant observable" |
# | `attack_bank`, `attack_amplitude`, `attack_start` | 1, $\pi/3$, 10 s | PAPER (IV) | $a_1(t)=\pi/3$ for $t\ge10$ |
# | `ring_order` | 1–2–3–4–5–1 | MISSING | "ring network"; the natural order, for which the final remark of Section IV holds |
# | basis $\{v_l\}$ | grouped projected-orthonormal, unit norm | MISSING (ours; derived, not a parameter) | Assumption 4 only asks for existence. Built by `common_basis` (Section "Assumption 4" below): real invariant subspaces of $A$ grouped by their observation pattern, in each group Gram–Schmidt on the projections of $e_1,e_2,\dots$; verified against the $\mathcal U_i$. Speed and offsets depend on the scaling |
# | `observer_poles` | "near": $-1,-1.1,\dots$ (first $o_i$) | MISSING | "eigenvalues … near −1"; distinct poles for single-output placement; "shifted" is the alternative |
# | `x0_plant` | [0.5, 0, 0.3, 0, 0.1, 0] | MISSING | plant state $x(0)$; a visible transient |
# | `z0_guess` | zeros (length $n$; or $N$ rows, one per agent) | MISSING | $z_i(0)=\mathcal W_i\,$`z0_guess` (any $z_i(0)\in\mathbb R^{o_i}$ is reachable, $\mathcal W_i$ has full row rank); default: partial observers (5) not initialised (Theorems 2, 3 allow any) |
# | `xhat0` | zeros (length $n$; or $N$ rows, one per agent) | MISSING | $\hat x_i(0)$ of (6) / (11); default: uninitialised, the same for every agent |
# | `T_ex`, `final_window` | 40 s, last 5 s | MISSING | banks 1 and 3 peak until ≈ 20 s with "near" poles, and the attack restarts bank 1's transient |
# | `dt_ex`, `record_dt` | 1e-3 s, 0.01 s | MISSING | exponential Euler (integrator section) |
# | $P$ of (11) | $T^{-\top}T^{-1}$, $T$ real modal | MISSING (ours; derived, not a parameter) | built in the Theorem 3 section from the real modal matrix $T$ of $A$ (columns: the real invariant subspaces above); gives $PA+A^\top P\le0$ with $\bar P=V^\top PV$ block-diagonal over the indicator groups. Theorem 3's bound (C8) scales with $\|V\bar P^{-1/2}\|$, so its value depends on this choice |
# | `offset_gammas`, `amplitude_sweep` | 2, 5, 20; $\pi$, 10 | ours | offset law and baseline |
# | `accuracy_T`, `accuracy_ref_dt`, `tanh_eps`, `stall_T` | 20 s, 1e-4 s, 1e-3 and 1e-2, 2 ms | ours | integrator comparison |
#
# Fast mode (tests) shortens the Section II horizons to 10 s, the integrator comparison to 8 s and
# the exact-sign demonstration to 0.5 ms; the example itself always runs the full `T_ex`.

# %% [markdown]
# ## Section II — the median set
#
# For values $z_i$ with indicators $s_i\in\{0,1\}$, let $S=|\{i: s_i=1\}|$ and
# $z^s_1\le\dots\le z^s_S$ the indicated values sorted. The median set is
#
# $$\mathcal M^{\mathcal S}_{\mathcal Z}=\begin{cases}\{z^s_{(S+1)/2}\}, & S\text{ odd},\\
# [z^s_{S/2},\,z^s_{S/2+1}], & S\text{ even},\end{cases}$$
#
# the minimiser set of $\sum_i s_i|z_i-x|$. With 0-based indices the interval is
# $[z^s_{\lfloor (S-1)/2\rfloor}, z^s_{\lfloor S/2\rfloor}]$, which covers both cases.


# %%
def median_set(values: np.ndarray, indicators: np.ndarray) -> tuple[float, float]:
    """Median set [lo, hi] of the indicated values (a single point when S is odd)."""
    zs = np.sort(values[indicators == 1])
    if zs.size == 0:
        raise ValueError("indicators must mark at least one value (s_i = 1)")
    return float(zs[(zs.size - 1) // 2]), float(zs[zs.size // 2])


def distance_to_set(x: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Distance ||x||_M of each entry of x to the interval [lo, hi]."""
    return np.maximum(lo - x, 0.0) + np.maximum(x - hi, 0.0)


lo, hi = median_set(z_vals, s_vals)
print(f"S = {int(s_vals.sum())}, median set = [{lo}, {hi}]")

# %% [markdown]
# ## The distributed median solver (4)
#
# The centralised gradient flow (3), $\dot{\hat x}=\sum_i s_i\,\mathrm{sgn}(z_i-\hat x)$, needs all
# $z_i$. The distributed solver (4) gives agent $i$ only its own sign term and couples it to its
# neighbours:
#
# $$\dot x_i = s_i\,\mathrm{sgn}(z_i-x_i) + \gamma\sum_{j\in\mathcal N_i}(x_j-x_i),\qquad
# \text{i.e.}\quad \dot x = s\odot\mathrm{sgn}(z-x) - \gamma\mathcal L x,$$
#
# with $\mathrm{sgn}(0)=0$ and solutions in the Filippov sense. We integrate it with explicit
# Euler, vectorised over agents. On a sliding surface the Euler iterate chatters within
# $dt$ of it, which is far below the distances measured here.


# %%
def median_solver(
    adj: np.ndarray, values: np.ndarray, indicators: np.ndarray, x_start: np.ndarray,
    gain: float, horizon_s: float, step: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Explicit-Euler solution of (4); returns times (K,) and states (K, N)."""
    lap = graphs.laplacian(graphs.check_connected(adj))
    if step >= 2.0 / (gain * np.linalg.eigvalsh(lap)[-1]):
        raise ValueError(f"dt={step} is above the Euler stability limit 2/(gamma*lambda_max(L))")
    steps = int(round(horizon_s / step))
    xs = np.empty((steps + 1, values.size))
    xs[0] = x_start
    for k in range(steps):
        xs[k + 1] = xs[k] + step * (indicators * np.sign(values - xs[k]) - gain * lap @ xs[k])
    return step * np.arange(steps + 1), xs


# %% [markdown]
# ## Theorem 1
#
# Under Assumption 3 (undirected, connected graph), for every $\gamma>0$ and every initial
# condition, $\limsup_{t\to\infty}\|x_i(t)\|_{\mathcal M}\le 2\sqrt N/(\gamma\lambda_2(\mathcal L))$.
# Remark 2: $\lambda_2 = 2(1-\cos(2\pi/N))$ on a ring and $\lambda_2=N$ on the all-to-all graph,
# where the bound becomes $2/(\gamma\sqrt N)$. We run the same data on both graphs.

# %%
graph_set = {"ring": graphs.ring_graph(N), "all-to-all": graphs.complete_graph(N)}
runs = {}
for name, adj in graph_set.items():
    t, xs = median_solver(adj, z_vals, s_vals, x_init, gamma, horizon, dt)
    lam2 = graphs.algebraic_connectivity(adj)
    tail = t >= (1.0 - settle_fraction) * horizon
    runs[name] = {
        "t": t,
        "x": xs,
        "lambda2": lam2,
        "bound": 2.0 * np.sqrt(N) / (gamma * lam2),
        "final_distance": distance_to_set(xs[tail], lo, hi).max(axis=0),
    }
    print(f"{name:>10}: lambda2 = {lam2:.6f}, bound = {runs[name]['bound']:.4f}, "
          f"max final distance = {runs[name]['final_distance'].max():.4f}")

# %% [markdown]
# ## Fig. S1 (ours) — agents of (4) against the median set and the Theorem 1 band
#
# The paper has no figure for Section II. Shaded: the median set $[1.1, 1.3]$; dashed: the
# median set widened by the Theorem 1 bound.

# %%
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 2.8), sharey=True)
for ax, (name, r) in zip(axes, runs.items(), strict=True):
    ax.axhspan(lo, hi, color="tab:green", alpha=0.25, label="median set $\\mathcal{M}$")
    ax.axhline(lo - r["bound"], color="k", ls="--", lw=0.8, label="$\\mathcal{M}$ ± Theorem 1 bound")
    ax.axhline(hi + r["bound"], color="k", ls="--", lw=0.8)
    ax.plot(r["t"], r["x"], lw=1.0, label=[f"agent {i + 1}" for i in range(N)])
    ax.set_title(f"{name}, N = {N}, γ = {gamma:g}, bound = {r['bound']:.3f}")
    ax.set_xlabel("time t [s]")
axes[0].set_ylabel("solver state $x_i(t)$ [–]")
axes[0].legend(loc="upper right", ncol=2, fontsize=7)
axes[0].set_ylim(-2.5, 4.5)
stride = max(1, int(round(0.01 / dt)))
plotting.save_figure(
    fig, FIG_DIR, "extra_s1_median_solver",
    data={"t_s": runs["ring"]["t"][::stride],
          **{f"x_{g}": r["x"][::stride] for g, r in runs.items()}},
)
plt.show()

# %% [markdown]
# ## Section II-B — Theorem 1 across graphs and gains
#
# The bound $2\sqrt N/(\gamma\lambda_2)$ against the measured final distance for
# $\gamma\in\{0.5,\dots,50\}$ on three graphs: ring $N=5$ with $z=[0.8,1.3,0.9,1.1,6.0]$, all
# $s_i=1$ (median $\{1.1\}$), and ring and all-to-all $N=7$ with the data above (median set
# $[1.1,1.3]$). All $\gamma$ of one graph run as columns of one explicit-Euler recursion
# ($dt$ below $2/(\gamma\lambda_{\max})$ for every $\gamma$, checked).

# %%
sweep_cases = {
    "ring5": (graphs.ring_graph(5), np.array(sweep_z5, float), np.ones(5), np.array(sweep_x05, float)),
    "ring7": (graphs.ring_graph(N), z_vals, s_vals, x_init),
    "complete7": (graphs.complete_graph(N), z_vals, s_vals, x_init),
}
gam_sweep = np.asarray(sweep_gammas, dtype=float)
sweep = {}
for name, (adj, zc, sc, xc) in sweep_cases.items():
    lap = graphs.laplacian(graphs.check_connected(adj))
    if dt >= 2.0 / (gam_sweep.max() * np.linalg.eigvalsh(lap)[-1]):
        raise ValueError("dt above the Euler stability limit of the sweep")
    lo_c, hi_c = median_set(zc, sc)
    xs = np.repeat(xc[:, None], gam_sweep.size, axis=1)
    steps = int(round(sweep_horizon / dt))
    tail_from = int(round((1.0 - settle_fraction) * steps))
    dist = np.zeros(gam_sweep.size)
    for k in range(steps):
        xs = xs + dt * (sc[:, None] * np.sign(zc[:, None] - xs) - gam_sweep[None, :] * (lap @ xs))
        if k + 1 >= tail_from:
            dist = np.maximum(dist, distance_to_set(xs, lo_c, hi_c).max(axis=0))
    lam2 = graphs.algebraic_connectivity(adj)
    sweep[name] = {"distance": dist, "bound": 2 * np.sqrt(zc.size) / (gam_sweep * lam2),
                   "lambda2": lam2, "median": (lo_c, hi_c)}
    print(f"{name:>9}: lambda2 = {lam2:.6f}, median set = [{lo_c}, {hi_c}]")
    print("   distance:", np.round(dist, 4))
    print("   bound:   ", np.round(sweep[name]["bound"], 4))

# %%
fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH * 1.6, 3.0))
for k, (name, r) in enumerate(sweep.items()):
    ax.loglog(gam_sweep, np.maximum(r["distance"], 1e-4), "o-", color=f"C{k}", ms=4,
              label=f"{name}: measured")
    ax.loglog(gam_sweep, r["bound"], "--", color=f"C{k}", lw=1.0, label=f"{name}: 2√N/(γλ₂)")
ax.set_xlabel("coupling gain γ [–]")
ax.set_ylabel(r"final $\max_i\|x_i\|_{\mathcal{M}}$ [–] (0 drawn at 1e-4)")
ax.set_title("Theorem 1: distance to the median set against the bound")
ax.legend(fontsize=6.5, ncol=2)
plotting.save_figure(
    fig, FIG_DIR, "extra_theorem1_gamma_sweep",
    data={"gamma": gam_sweep, **{f"distance_{g}": r["distance"] for g, r in sweep.items()},
          **{f"bound_{g}": r["bound"] for g, r in sweep.items()}},
)
plt.show()

# %% [markdown]
# The distance falls roughly as $1/\gamma$ and stays 7 to 50 times below the bound (the bound adds
# a worst case for the disagreement and one for the average); on the all-to-all graph the agents reach the median set exactly from $\gamma=2$ on (they slide inside
# it). **Remark 2** — $\lambda_2=2(1-\cos(2\pi/N))$ on rings and $\lambda_2=N$ on all-to-all graphs —
# checked against networkx's `algebraic_connectivity` for $N=3,\dots,12$:

# %%
remark2_n = np.arange(3, 13)
remark2_dev = 0.0
for nn in remark2_n:
    ring_nx = nx.algebraic_connectivity(
        nx.cycle_graph(int(nn)), tol=1e-12, method="tracemin_lu", seed=0)
    comp_nx = nx.algebraic_connectivity(
        nx.complete_graph(int(nn)), tol=1e-12, method="tracemin_lu", seed=0)
    remark2_dev = max(remark2_dev, abs(ring_nx - 2 * (1 - np.cos(2 * np.pi / nn))),
                      abs(comp_nx - nn))
lam2_ring_seq = 2 * (1 - np.cos(2 * np.pi / remark2_n))
print(f"max |networkx - closed form| over N = 3..12: {remark2_dev:.1e}; ring lambda2 decreasing: "
      f"{bool(np.all(np.diff(lam2_ring_seq) < 0))}")

# %% [markdown]
# ## Section III-A — the example plant and its unobservable subspaces
#
# Section IV's three-inertia system (three disks $J_1=J_2=J_3$ on two torsion springs $k_1=k_2$,
# viscous damping $b$), state $x=[\theta_1,\dot\theta_1,\theta_2,\dot\theta_2,\theta_3,\dot\theta_3]$,
# torque $u = 0.01\sin(0.5t)$ on disk 1 and five single-sensor banks
# $y=[\theta_1,\theta_2,\theta_3,\theta_1-\theta_2,\theta_2-\theta_3]$ (1).


# %%
def three_inertia(J: float, b: float, k: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Matrices A, B, C of the Section IV example (J1=J2=J3=J, b1=b2=b3=b, k1=k2=k)."""
    a = np.array([
        [0, 1, 0, 0, 0, 0],
        [-k / J, -b / J, k / J, 0, 0, 0],
        [0, 0, 0, 1, 0, 0],
        [k / J, 0, -2 * k / J, -b / J, k / J, 0],
        [0, 0, 0, 0, 0, 1],
        [0, 0, k / J, 0, -k / J, -b / J],
    ])
    b_in = np.array([0.0, 1.0 / J, 0.0, 0.0, 0.0, 0.0])
    c = np.array([
        [1, 0, 0, 0, 0, 0],
        [0, 0, 1, 0, 0, 0],
        [0, 0, 0, 0, 1, 0],
        [1, 0, -1, 0, 0, 0],
        [0, 0, 1, 0, -1, 0],
    ], dtype=float)
    return a, b_in, c


A, B, C = three_inertia(J_inertia, b_damping, k_spring)
n, N_banks = A.shape[0], C.shape[0]
banks = [C[i : i + 1] for i in range(N_banks)]  # C_i, one row per bank
eig_A = np.linalg.eigvals(A)
print("eig(A) =", np.round(np.sort_complex(eig_A), 4))

# %% [markdown]
# $A$ has six distinct eigenvalues: $0$ and $-b/J=-0.7$ (rigid-body rotation and its rate) and
# two lightly damped torsion modes $-0.35\pm 11.70j$ (shape $(1,0,-1)$) and $-0.35\pm20.27j$
# (shape $(1,-2,1)$). It is Lyapunov stable but not asymptotically stable.
#
# **Unobservable subspaces.** $\mathcal U_i=\ker\operatorname{col}(C_i, C_iA,\dots,C_iA^{n-1})$,
# computed by `secest.systems.unobservable_subspace` with an orthogonal staircase (Krylov
# iteration on $A/\|A\|$ with re-orthonormalisation and a relative rank tolerance): the raw
# observability matrix of bank 1 has singular values from $1.3\cdot10^5$ down to $0.58$, so a
# rank decision on it is fragile. Cross-check: the PBH test on each real invariant subspace
# $X_k$ of $A$ (mode $k$ is unobservable from bank $i$ iff $C_iX_k=0$).

# %%
U_sub = [systems.unobservable_subspace(A, Ci) for Ci in banks]
obs_rank = [n - U.shape[1] for U in U_sub]
print("observable dimension o_i per bank:", obs_rank)
sv = np.linalg.svd(systems.observability_matrix(A, banks[0]), compute_uv=False)
print(f"singular values of the observability matrix of bank 1: {sv.max():.3g} ... {sv.min():.3g}")


def real_invariant_subspaces(a: np.ndarray) -> list[tuple[complex, np.ndarray]]:
    """Real invariant subspaces of a matrix with distinct eigenvalues.

    One column (unit real eigenvector) per real eigenvalue, two columns [Re v, Im v] per
    conjugate pair, with v rotated so that Re v is orthogonal to Im v and scaled so that
    ||Re v|| = 1. Then a X_k = X_k Lambda_k with Lambda_k = [[alpha, beta], [-beta, alpha]].
    """
    lam, vec = np.linalg.eig(a)
    if np.min(np.abs(lam[:, None] - lam[None, :]) + np.eye(lam.size) * 1e9) < 1e-9 * max(
        1.0, np.abs(lam).max()
    ):
        raise ValueError("repeated eigenvalues: use the Jordan-chain fallback of the brief")
    out = []
    for idx in np.argsort(-lam.real + 1e-9 * np.abs(lam.imag)):
        mu = lam[idx]
        if abs(mu.imag) <= 1e-12 * max(1.0, abs(mu)):
            v = vec[:, idx].real
            out.append((complex(mu.real), (v / np.linalg.norm(v))[:, None]))
        elif mu.imag > 0:
            v = vec[:, idx]
            th = 0.5 * np.arctan2(2 * v.real @ v.imag, v.real @ v.real - v.imag @ v.imag)
            v = v * np.exp(-1j * th)
            v = v / np.linalg.norm(v.real)
            out.append((complex(mu), np.column_stack([v.real, v.imag])))
    return out


def in_span(vec: np.ndarray, basis: np.ndarray, tol: float = 1e-7) -> bool:
    """True iff vec lies in range(basis) (orthonormal columns), relative residual <= tol."""
    resid = vec - basis @ (basis.T @ vec) if basis.shape[1] else vec
    return bool(np.linalg.norm(resid) <= tol * np.linalg.norm(vec))


modes = real_invariant_subspaces(A)
pattern = np.array(
    [[0 if all(in_span(X[:, c], U) for c in range(X.shape[1])) else 1 for U in U_sub]
     for _, X in modes]
)
pbh = np.array(
    [[int(np.linalg.norm(Ci @ X) > 1e-9 * np.linalg.norm(Ci) * np.linalg.norm(X)) for Ci in banks]
     for _, X in modes]
)
assert np.array_equal(pattern, pbh), "staircase and PBH disagree"
print("banks observing each real mode (rows: modes, columns: banks 1..5)")
for (mu, _), row in zip(modes, pattern, strict=True):
    print(f"  lambda = {mu.real:+.3f}{mu.imag:+.3f}j : {row}")

# %% [markdown]
# **Assumption 2 (2q-redundant observability)** by enumeration of all $\binom{N}{N-2q}$ subsets
# (`secest.systems.redundant_observability`). The paper states that $(C, A)$ is
# "2-redundant observable", i.e. $q=1$.

# %%
red = {qq: systems.redundant_observability(A, banks, q=qq) for qq in (1, 2)}
for qq, r in red.items():
    failing = [tuple(i + 1 for i in f) for f in r.failing]
    print(f"q = {qq}: {r.n_subsets} subsets of {N_banks - 2 * qq} banks, holds = {r.holds}, "
          f"failing (1-based) = {failing}")

# %% [markdown]
# For $q=2$ every single bank would have to observe the plant; banks 2, 4 and 5 do not.
#
# ## Assumption 4 — a common basis $\{v_l\}$
#
# The paper requires a basis in which every $\mathcal U_i$ is a coordinate subspace but does not
# say how to build one (nor which one it used; MISSING). Appendix B shows that one exists when
# $A$ is non-derogatory; here all eigenvalues are distinct, and every $\mathcal U_i$ is a sum of
# real invariant subspaces $X_k$ (the $\mathcal U_i$ are $A$-invariant). Our procedure:
#
# 1. real invariant subspaces $X_k$ of $A$ (above) and their observation pattern
#    $(s_1,\dots,s_N)$ (PBH, cross-checked against the staircase);
# 2. group the $X_k$ with equal patterns; in each group an orthonormal basis by Gram–Schmidt on
#    the orthogonal projections of $e_1,e_2,\dots$ onto the group's span (deterministic; dependent
#    projections with norm $<10^{-6}$ skipped);
# 3. order the groups by the number of observing banks;
# 4. verify: for every $i,l$: $v_l\in\mathcal U_i \Leftrightarrow s_i^l=0$ (projection residual
#    $<10^{-7}$), and $\#\{l: s_i^l=0\}=\dim\mathcal U_i$.
#
# The procedure covers matrices with distinct eigenvalues (as here); for repeated eigenvalues the
# function refuses, and the brief's fallback (intersecting the $\mathcal U_i$ of bank subsets) would
# be needed — Appendix B items 4 and 8 show that Assumption 4 can then genuinely fail.
# Any basis satisfying Assumption 4 is admissible, but the sign corrections move $\hat x_i$ by
# $\kappa\|v_l\|$ per coordinate, so scaling and rotation inside a group change speed and
# steady-state offsets (our unit-norm choice is recorded in the provenance table).


# %%
def common_basis(
    modes: list[tuple[complex, np.ndarray]], pattern: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Grouped projected-orthonormal basis V (n x n), indicators S (N x n), modal matrix T."""
    dim = modes[0][1].shape[0]
    groups: dict[tuple[int, ...], list[int]] = {}
    for kk, row in enumerate(pattern):
        groups.setdefault(tuple(int(v) for v in row), []).append(kk)
    cols, ind, modal = [], [], []
    for pat, ks in sorted(groups.items(), key=lambda g: (sum(g[0]), min(g[1]))):
        span = np.hstack([modes[kk][1] for kk in ks])
        q_span = sla.orth(span)
        proj = q_span @ q_span.T
        basis: list[np.ndarray] = []
        for e in np.eye(dim):
            v = proj @ e
            for bv in basis:
                v = v - (bv @ v) * bv
            if np.linalg.norm(v) > 1e-6:
                basis.append(v / np.linalg.norm(v))
            if len(basis) == q_span.shape[1]:
                break
        cols += basis
        ind += [pat] * len(basis)
        modal += list(span.T)
    return np.column_stack(cols), np.array(ind).T, np.column_stack(modal)


V, S_ind, T_modal = common_basis(modes, pattern)
W = np.linalg.inv(V)  # rows w_l^T: [w_1 ... w_n]^T [v_1 ... v_n] = I
# verification of Assumption 4
a4_resid = 0.0
a4_ok = True
for i, U in enumerate(U_sub):
    a4_ok &= int((S_ind[i] == 0).sum()) == U.shape[1]
    for ll in range(n):
        member = in_span(V[:, ll], U)
        a4_ok &= member == (S_ind[i, ll] == 0)
        if member and U.shape[1]:
            a4_resid = max(a4_resid, float(np.linalg.norm(V[:, ll] - U @ (U.T @ V[:, ll]))))
banks_per_coord = S_ind.sum(axis=0)
print("sqrt(3, 3, 2, 2, 6, 6) * V =")
print(np.round(V * np.sqrt([3, 3, 2, 2, 6, 6]), 6))
print("indicators s_i^l (rows: banks, columns: l):")
print(S_ind)
print("Assumption 4 verified:", a4_ok, f"(max membership residual {a4_resid:.1e})")
print("banks per coordinate:", banks_per_coord, f">= 2q+1 = {2 * q + 1} (Lemma 1)")
A_bar = W @ A @ V
print("A_bar = W A V =")
print(np.round(A_bar, 6))

# %% [markdown]
# The basis is $v_1=[1,0,1,0,1,0]/\sqrt3$, $v_2=[0,1,0,1,0,1]/\sqrt3$ (rigid body,
# eigenvalues $0,-0.7$), $v_3,v_4$ the mode shape $(1,0,-1)/\sqrt2$ in angle and rate, and
# $v_5,v_6$ the shape $(1,-2,1)/\sqrt6$. It is orthonormal ($W=V^\top$), and
# $\bar A=WAV=\operatorname{blockdiag}\big(\begin{smallmatrix}0&1\\0&-0.7\end{smallmatrix},
# \begin{smallmatrix}0&1\\-137&-0.7\end{smallmatrix},\begin{smallmatrix}0&1\\-411&-0.7\end{smallmatrix}\big)$.
# The indicator table: banks 1 and 3 see everything, bank 2 ($\theta_2$) misses the
# $(1,0,-1)$ mode, banks 4 and 5 (angle differences) miss the rigid-body motion; each coordinate
# is observed by $[3,3,4,4,5,5]\ge 2q+1=3$ banks, as Lemma 1 requires.
#
# ## Section III-B — partial observers (5)
#
# $\mathcal V_i$ = the columns $v_l$ with $s_i^l=1$, $\mathcal W_i$ = the matching rows
# $w_l^\top$ (same order, so $\mathcal W_i\mathcal V_i=I_{o_i}$). With $\tilde{\mathcal V}_i$,
# $\tilde{\mathcal W}_i$ the rest, $\mathcal W_iA\tilde{\mathcal V}_i=0$ and
# $C_i\tilde{\mathcal V}_i=0$ (Kalman observability decomposition). The gain $L_i$ makes
# $F_i=\mathcal W_iA\mathcal V_i-L_iC_i\mathcal V_i$ Hurwitz; the paper only says its eigenvalues
# are "near $-1$" (MISSING). Default `observer_poles="near"`: $-1,-1.1,\dots$ (first $o_i$;
# single-output placement needs distinct poles). Alternative `"shifted"`: keep the imaginary
# parts of $\operatorname{eig}(\mathcal W_iA\mathcal V_i)$ and move all real parts to $-1$
# (real eigenvalues to $-1,-1.1$). Gains by pole placement with python-control
# (`control.place`, on the dual pair).

# %%
masks = [S_ind[i] == 1 for i in range(N_banks)]
V_i = [V[:, m] for m in masks]
W_i = [W[m] for m in masks]
o_i = np.array([int(m.sum()) for m in masks])
decomp_resid = max(
    max(np.abs(W_i[i] @ A @ V[:, ~masks[i]]).max(initial=0.0),
        np.abs(banks[i] @ V[:, ~masks[i]]).max(initial=0.0))
    for i in range(N_banks)
)
print("o_i =", o_i, f"; max |W_i A V~_i|, |C_i V~_i| = {decomp_resid:.1e}")


def observer_gains(which: str) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Gains L_i of (5) by pole placement; returns (L_i, F_i = W_i A V_i - L_i C_i V_i)."""
    gains, closed = [], []
    for i in range(N_banks):
        f_i, h_i = W_i[i] @ A @ V_i[i], banks[i] @ V_i[i]
        if which == "near":
            poles = -1.0 - 0.1 * np.arange(o_i[i])
        elif which == "shifted":
            ev = np.linalg.eigvals(f_i)
            real = ev[np.abs(ev.imag) < 1e-9]
            cplx = ev[np.abs(ev.imag) >= 1e-9]
            poles = np.concatenate([-1.0 - 0.1 * np.arange(real.size), -1.0 + 1j * cplx.imag])
        else:
            raise ValueError(f"observer_poles must be 'near' or 'shifted', found {which!r}")
        gain = control.place(f_i.T, h_i.T, poles).T
        gains.append(gain)
        closed.append(f_i - gain @ h_i)
    return gains, closed


def peak_gain(f: np.ndarray) -> float:
    """max_t ||exp(F t)||_2 over a grid of [0, 20] s (transient peaking of the observer error)."""
    return max(np.linalg.norm(sla.expm(f * tk), 2) for tk in np.linspace(0.0, 20.0, 401))


gain_sets = {p: observer_gains(p) for p in ("near", "shifted")}
for p, (gains, closed) in gain_sets.items():
    print(f"observer_poles = {p!r}")
    for i in range(N_banks):
        print(f"  bank {i + 1}: max|L_i| = {np.abs(gains[i]).max():9.3f}, "
              f"max Re eig(F_i) = {np.linalg.eigvals(closed[i]).real.max():+.3f}, "
              f"peak ||exp(F_i t)|| = {peak_gain(closed[i]):9.1f}")
L_gain, F_cl = gain_sets[observer_poles]

# %% [markdown]
# The literal "near $-1$" placement pulls the $11.7$ and $20.3$ rad/s modes down to $-1.2\dots-1.5$:
# gains up to $1.5\cdot10^3$ and a transient peak $\|e^{F_it}\|\approx5\cdot10^4$ for banks 1 and 3.
# Their partial estimates of the torsion modes are wrong for about 20 s; the θ-sum of Fig. 1 is
# unaffected (both torsion shapes have zero angle sum). The "shifted" placement has gains
# $\le 11$ and a peak of $\approx17$.
#
# **Partial observer (5):** $\dot z_i=\mathcal W_i(A\mathcal V_iz_i+Bu)+L_i(y_i-C_i\mathcal V_iz_i)$.
# With $y_i=C_ix+a_i$ its error $e_i=z_i-\mathcal W_ix$ obeys $\dot e_i=F_ie_i+L_ia_i$, so a
# clean bank converges to $\mathcal W_ix$ and a constant attack leaves $e_i\to-F_i^{-1}L_ia_i$.
#
# ## The median-embedded observer (6) and the Lyapunov variant (11)
#
# $$\dot{\hat x}_i=A\hat x_i+Bu+\kappa\sum_{l=1}^n s_i^l\,\mathrm{sgn}\big(w_l^\top\mathcal V_iz_i-w_l^\top\hat x_i\big)v_l
# +\kappa\gamma\sum_{j\in\mathcal N_i}(\hat x_j-\hat x_i).\qquad(6)$$
#
# Per agent: $r_i=W(\mathcal V_iz_i-\hat x_i)\in\mathbb R^n$ (note $W\mathcal V_iz_i$ is $z_i$
# scattered into the positions $s_i^l=1$), correction $\kappa V(s_i\odot\mathrm{sgn}(r_i))$.
# Variant (11) replaces $V,W$ in the correction by $\bar V=V\bar P^{-1/2}$, $\bar W=\bar P^{1/2}W$
# with $\bar P=V^\top PV$, $PA+A^\top P\le0$; this identity is exact when $\bar P$ is
# block-diagonal over the groups of coordinates with equal indicators (otherwise
# $\bar P^{1/2}$ mixes coordinates a bank cannot see into the arguments of those it can — a
# condition the paper does not state). The non-resilient **baseline** (ours) replaces
# $\mathrm{sgn}(r)$ by $r$: a Laplacian-coupled average instead of a median.
#
# **Stacked system.** $X=[x;z_1;\dots;z_N;\hat x_1;\dots;\hat x_N]\in\mathbb R^{60}$ obeys
#
# $$\dot X = MX + E_w\,w(t) + E_s\,\phi(RX),\qquad w=[u;a_1;\dots;a_N],\quad
# \phi(r)=s\odot\mathrm{sgn}(r)\ (\text{or } s\odot r),$$
#
# with $M$ holding $A$, the $F_i$ with the coupling $L_iC_ix$, and $I_N\otimes A-\kappa\gamma\,\mathcal L\otimes I_n$;
# $E_w$ holding $B$, $\mathcal W_iB$, $L_i$ (on $a_i$); $RX$ stacking the $r_i$ and
# $E_s=\kappa(I_N\otimes V)$ on the $\hat x$ rows. All agents are updated at once by these
# matrix products (no loop over agents). The initial state $X(0)$ comes from the parameters
# `x0_plant` ($x(0)$), `z0_guess` ($z_i(0)=\mathcal W_i\,$`z0_guess`, i.e. each partial observer
# started from a guess of the state) and `xhat0` ($\hat x_i(0)$); both default to zero.


# %%
z_start = n + np.r_[0, np.cumsum(o_i)]  # z_i occupies rows z_start[i]:z_start[i+1]
xh0 = n + int(o_i.sum())  # first row of x_hat_1
n_state = xh0 + N_banks * n
s_flat = S_ind.reshape(-1).astype(float)


def ring_adjacency(order: list[int]) -> np.ndarray:
    """Adjacency of the ring visiting the 1-based agents in ``order`` (and back)."""
    ring = nx.relabel_nodes(nx.cycle_graph(len(order)), {k: v - 1 for k, v in enumerate(order)})
    return graphs.adjacency(ring)


adj_ex = ring_adjacency(ring_order)
lap_ex = graphs.laplacian(graphs.check_connected(adj_ex))
lam2_ex = graphs.algebraic_connectivity(adj_ex)


def network_system(gains, gain_gamma, v_corr=None, w_corr=None):
    """Matrices M, E_w, E_s, R of the stacked system (1), (5), (6) [or (11) via v_corr, w_corr]."""
    v_corr = V if v_corr is None else v_corr
    w_corr = W if w_corr is None else w_corr
    m_mat = np.zeros((n_state, n_state))
    e_w = np.zeros((n_state, 1 + N_banks))
    r_mat = np.zeros((N_banks * n, n_state))
    m_mat[:n, :n], e_w[:n, 0] = A, B
    for i in range(N_banks):
        zi = slice(z_start[i], z_start[i + 1])
        m_mat[zi, zi] = W_i[i] @ A @ V_i[i] - gains[i] @ banks[i] @ V_i[i]
        m_mat[zi, :n] = gains[i] @ banks[i]
        e_w[zi, 0], e_w[zi, 1 + i] = W_i[i] @ B, gains[i][:, 0]
        rows = slice(i * n, (i + 1) * n)
        r_mat[rows, zi] = w_corr @ V_i[i]
        r_mat[rows, xh0 + i * n : xh0 + (i + 1) * n] = -w_corr
    m_mat[xh0:, xh0:] = np.kron(np.eye(N_banks), A) - kappa * gain_gamma * np.kron(lap_ex, np.eye(n))
    e_w[xh0:, 0] = np.tile(B, N_banks)
    e_s = np.zeros((n_state, N_banks * n))
    e_s[xh0:] = kappa * np.kron(np.eye(N_banks), v_corr)
    return m_mat, e_w, e_s, r_mat


def exogenous(amplitudes):
    """w(t) = [u; a_1..a_N] for a batch of attack amplitudes on bank `attack_bank` (columns)."""
    amps = np.atleast_1d(np.asarray(amplitudes, dtype=float))

    def w(t: float) -> np.ndarray:
        out = np.zeros((1 + N_banks, amps.size))
        out[0] = u_amplitude * np.sin(u_frequency * t)
        if t >= attack_start:
            out[attack_bank] = amps
        return out

    return w


def per_agent(value, name: str) -> np.ndarray:
    """One length-n vector per agent, (N, n): shape (n,) is shared by all agents, (N, n) is per agent."""
    arr = np.asarray(value, dtype=float)
    if arr.shape == (n,):
        arr = np.tile(arr, (N_banks, 1))
    if arr.shape != (N_banks, n):
        raise ValueError(f"{name} must have shape ({n},) or ({N_banks}, {n}), found {arr.shape}")
    return arr


def initial_state() -> np.ndarray:
    """X(0) = [x(0); z_1(0); ...; z_N(0); x_hat_1(0); ...; x_hat_N(0)] from the parameters.

    z_i(0) = W_i z0_guess[i] (the partial observer (5) started from a state guess) and
    x_hat_i(0) = xhat0[i]; a single length-n vector is used for every agent.
    """
    x_plant = np.asarray(x0_plant, dtype=float)
    if x_plant.shape != (n,):
        raise ValueError(f"x0_plant must have shape ({n},), found {x_plant.shape}")
    guesses = per_agent(z0_guess, "z0_guess")
    out = np.zeros(n_state)
    out[:n] = x_plant
    for i in range(N_banks):
        out[z_start[i] : z_start[i + 1]] = W_i[i] @ guesses[i]
    out[xh0:] = per_agent(xhat0, "xhat0").ravel()
    return out


X_init = initial_state()  # validated once, before any run


def phi_sign(r: np.ndarray) -> np.ndarray:
    """s (.) sgn(r): the median correction of (6) / (11) (sgn(0) = 0)."""
    return s_flat[:, None] * np.sign(r)


def phi_linear(r: np.ndarray) -> np.ndarray:
    """s (.) r: the non-resilient averaging baseline (ours)."""
    return s_flat[:, None] * r


def simulate(amplitudes, *, gains=None, gain_gamma=None, phi=phi_sign, v_corr=None, w_corr=None,
             step=None, horizon_s=None, method="expeuler"):
    """Run (1), (5), (6) for a batch of attack amplitudes; returns t (K,), X (K, n_state, B)."""
    gains = L_gain if gains is None else gains
    gain_gamma = gamma_ex if gain_gamma is None else gain_gamma
    step = dt_ex if step is None else step
    horizon_s = T_ex if horizon_s is None else horizon_s
    m_mat, e_w, e_s, r_mat = network_system(gains, gain_gamma, v_corr, w_corr)
    amps = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    x_start = np.repeat(X_init[:, None], amps.size, axis=1)
    n_steps = int(round(horizon_s / step))
    every = int(round(record_dt / step))
    out = systems.integrate_switched_linear(
        m_mat, e_w, exogenous(amps), e_s, r_mat, phi, x_start, step, n_steps,
        record_every=every, method=method,
    )
    return np.arange(out.shape[0]) * every * step, out


def unpack(X: np.ndarray) -> dict[str, np.ndarray]:
    """Split recorded states (K, n_state[, B]) into x (K, n), z_i, x_hat (K, N, n)."""
    return {
        "x": X[:, :n],
        "z": [X[:, z_start[i] : z_start[i + 1]] for i in range(N_banks)],
        "xh": X[:, xh0:].reshape((X.shape[0], N_banks, n) + X.shape[2:]),
    }

# %% [markdown]
# ## Integrating the discontinuous dynamics
#
# The sign terms make the right-hand side discontinuous; the paper takes Filippov solutions,
# in which $\hat x_i$ *slides* along surfaces $w_l^\top(\mathcal V_iz_i-\hat x_i)=0$ with an
# equivalent sign value in $[-1,1]$. Any consistent fixed-step scheme approximates a sliding
# motion by chattering of amplitude $O(\kappa\|v_l\|\,dt)$ around it. Three facts fix our choice:
#
# * the linear part is stiff and lightly damped: plant modes $-0.35\pm20.27j$, observer gains
#   up to $1.5\cdot10^3$; explicit Euler is unstable for $dt>0.7/411\approx1.7\cdot10^{-3}$ s
#   ($|1+dt\lambda|>1$) and under-damps the torsion modes below that;
# * error-controlled adaptive solvers (RK45) with an exact $\mathrm{sgn}$ collapse their step on
#   every switching surface (measured below);
# * replacing $\mathrm{sgn}$ by $\tanh(\cdot/\varepsilon)$ lets RK45 run, but it changes the
#   model: the sliding equilibria move by $O(\varepsilon)$.
#
# **Our integrator: exponential Euler** (`secest.systems.integrate_switched_linear`,
# `method="expeuler"`). Over each step the exogenous input $w$ is sampled at the midpoint and the
# switching term $\phi(RX_k)$ at the left end, both held, and the linear part is integrated
# exactly: $X_{k+1}=\Phi X_k+\Gamma_ww(t_k+dt/2)+\Gamma_s\phi(RX_k)$ with
# $\Phi=e^{M\,dt}$, $[\Gamma_w,\Gamma_s]=\int_0^{dt}e^{Ms}ds\,[E_w,E_s]$ from one matrix
# exponential (Van Loan). It costs what explicit Euler costs (one matrix–vector product per
# step, all agents and scenarios at once), has no stability limit from the plant, the observers or
# the coupling $\kappa\gamma$, and converges with order one in $dt$ to the Filippov solution.
#
# *Do not:* run explicit Euler above $dt\approx1.7\cdot10^{-3}$ s here; hand the exact $\mathrm{sgn}$
# to an adaptive solver; or smooth $\mathrm{sgn}$ with an $\varepsilon$ comparable to the
# offsets under study. Accuracy comparison below: every method against exponential Euler with
# $dt=10^{-4}$ s (reference) on the attacked example; the speed side of the comparison is
# measured in the benchmark suite, not here (timings are machine-dependent). For it, the stacked
# matrices are written to `extra_integrator_system.csv` (columns `M[j]`, `E_w[j]`, `E_s[j]` with the
# indicators folded in, `R_T[j]`, `x0`): $\dot X=MX+E_ww(t)+E_s\,\mathrm{sgn}(RX)$ with
# $w=[0.01\sin0.5t;\ a_1(t);0;0;0;0]$, $a_1=\pi/3$ for $t\ge10$ s.

# %%
acc_amp = [attack_amplitude]
t_acc, X_ref = simulate(acc_amp, step=accuracy_ref_dt, horizon_s=accuracy_T)
xh_ref = unpack(X_ref)["xh"][..., 0]


def deviation_from_ref(X: np.ndarray) -> np.ndarray:
    """max_i ||x_hat_i - x_hat_i^ref||_inf on the common 0.01 s grid."""
    return np.abs(unpack(X)["xh"][..., 0] - xh_ref).max(axis=(1, 2))


acc_runs = {}
for label, meth, step in [
    ("exponential Euler, dt = 1e-3 (ours)", "expeuler", 1e-3),
    ("exponential Euler, dt = 5e-4", "expeuler", 5e-4),
    ("explicit Euler, dt = 1e-3", "euler", 1e-3),
    ("explicit Euler, dt = 1e-4", "euler", 1e-4),
    ("explicit Euler, dt = 2.5e-3 (unstable)", "euler", 2.5e-3),
]:
    _, X_m = simulate(acc_amp, step=step, horizon_s=accuracy_T, method=meth)
    acc_runs[label] = deviation_from_ref(X_m)

m_acc, ew_acc, es_acc, r_acc = network_system(L_gain, gamma_ex)
w_acc = exogenous(acc_amp)
x_start_acc = X_init.copy()


# the example as plain matrices, for the benchmark suite: X' = M X + E_w w(t) + E_s sgn(R X) with
# w(t) = [u(t); a_1(t); ...; a_N(t)] and the indicators folded into E_s (10 significant digits)
plotting.save_data(FIG_DIR, "extra_integrator_system", {
    "M": m_acc, "E_w": ew_acc, "E_s": es_acc * s_flat[None, :], "R_T": r_acc.T, "x0": x_start_acc,
}, tolerance=dict.fromkeys(["M", "E_w"], results.Tolerance(
    rtol=1e-3, atol=1e-9,
    reason="observer gains placed at the clustered poles -1, -1.1, ... (ill-conditioned): up to "
    "3.8e-5 (large gains) and 1.7e-4 (small entries) relative between BLAS kernels; near-zero "
    "entries are rounding residuals (~1e-13)")))


def rhs_smooth(t: float, X: np.ndarray, eps: float) -> np.ndarray:
    """Right-hand side with sgn replaced by tanh(./eps) (for solve_ivp)."""
    return m_acc @ X + ew_acc @ w_acc(t)[:, 0] + es_acc @ (s_flat * np.tanh(r_acc @ X / eps))


for eps in tanh_eps:
    sol = solve_ivp(rhs_smooth, (0.0, accuracy_T), x_start_acc, args=(eps,), t_eval=t_acc,
                    rtol=1e-6, atol=1e-9, max_step=0.01)
    acc_runs[f"RK45, sgn = tanh(./{eps:g}), rtol = 1e-6"] = deviation_from_ref(sol.y.T[:, :, None])


def rhs_exact(t: float, X: np.ndarray) -> np.ndarray:
    """Exact-sgn right-hand side (for the adaptive-solver stall demonstration)."""
    return m_acc @ X + ew_acc @ w_acc(t)[:, 0] + es_acc @ (s_flat * np.sign(r_acc @ X))


stall = solve_ivp(rhs_exact, (0.0, stall_T), x_start_acc, rtol=1e-6, atol=1e-9)
nfev_per_s = stall.nfev / stall_T
print(f"RK45 with the exact sgn (rtol 1e-6): {stall.nfev} RHS evaluations for the first "
      f"{stall_T * 1e3:g} ms, i.e. about {nfev_per_s:.0e} per simulated second")
acc_table = {
    label: (float(np.sqrt(np.mean(d**2))), float(d.max())) for label, d in acc_runs.items()
}
print(f"{'method':45s} {'RMS dev.':>10s} {'max dev.':>10s}")
for label, (rms, mx) in acc_table.items():
    print(f"{label:45s} {rms:10.2e} {mx:10.2e}")

# %%
rho_euler = {step: float(np.abs(np.linalg.eigvals(np.eye(n_state) + step * m_acc)).max())
             for step in (1e-3, 2.5e-3)}
print("spectral radius of I + dt M:", {k: round(v, 6) for k, v in rho_euler.items()})
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 2.9), sharey=True)
for k, (label, d) in enumerate(acc_runs.items()):
    ax = axes[1] if label.startswith("RK45") else axes[0]
    color = "k" if "(ours)" in label else f"C{k}"
    ax.semilogy(t_acc, np.maximum(d, 1e-6), lw=0.9, color=color, label=label)
axes[1].semilogy(t_acc, np.maximum(acc_runs["exponential Euler, dt = 1e-3 (ours)"], 1e-6), lw=0.9,
                 color="k", label="exponential Euler, dt = 1e-3 (ours)")
axes[0].set_title("fixed-step schemes")
axes[1].set_title("adaptive RK45 with a smoothed sign")
for ax in axes:
    ax.axvline(attack_start, color="k", lw=0.6, ls=":")
    ax.set_xlabel("time t [s]")
    ax.legend(loc="upper right", fontsize=6.5)
axes[0].set_ylabel(r"$\max_i\|\hat x_i-\hat x_i^{\mathrm{ref}}\|_\infty$ [rad, rad/s]")
axes[0].set_ylim(1e-5, 1e3)
plotting.save_figure(
    fig, FIG_DIR, "extra_integrator_accuracy",
    data={"t_s": t_acc, **{f"dev[{lab}]": d for lab, d in acc_runs.items()}},
    tolerance={"dev*": results.Tolerance(
        rtol=0.1, atol=0.05,
        reason="deviation of one integration of the sign-driven system from another: a difference of "
        "two chattering trajectories (up to 0.013, or 0.0075 + 10 % of the value, under other BLAS "
        "kernels)")},
)
plt.show()

# %% [markdown]
# Exponential Euler at $dt=10^{-3}$ s tracks the reference about four times more closely than
# explicit Euler at the same step, and halving its step halves the deviation (order one: the
# deviation is chattering on the sliding surfaces). Explicit Euler at $dt=2.5\cdot10^{-3}$ s is unstable (spectral radius of
# $I+dt\,M$ above one, from the $20.3$ rad/s plant mode); that mode is barely excited in this run
# (the initial angles have no $(1,-2,1)$ component), so its deviation grows only slowly here (×2.1
# over 20 s, X1), but it grows. The $\tanh$ smoothing with $\varepsilon=10^{-2}$ shifts the sliding offsets.
#
# ## Section IV — the example with the paper's values
#
# One batched run holds four attack amplitudes on bank 1 ($\pi/3$ of the paper, $\pi$, 10 and 0)
# with the default ("near $-1$") gains; further runs vary $\gamma$, the poles, the correction
# ((6), (11), baseline). Attack $a_1(t)=$ amplitude for $t\ge10$ s.

# %%
amp_batch = [attack_amplitude, *amplitude_sweep, 0.0]
t_ex, X_main = simulate(amp_batch)
sim = unpack(X_main)
last = t_ex >= T_ex - final_window - 1e-9
theta_sel = np.array([1.0, 0, 1.0, 0, 1.0, 0])  # theta_1 + theta_2 + theta_3
true_sum = sim["x"][:, :, 0] @ theta_sel
own_1 = sim["z"][0][..., 0] @ V_i[0].T  # agent 1's own estimate V_1 z_1 (o_1 = n)
err = sim["xh"] - sim["x"][:, None]  # (K, N, n, B)
sum_err = np.einsum("kinb,n->kib", err, theta_sel)
max_err = np.abs(err).max(axis=(1, 2))  # (K, B)
print("final window:", t_ex[last][0], "...", t_ex[-1], "s")
for b, amp in enumerate(amp_batch):
    print(f"amplitude {amp:7.4f}: mean sum offsets {np.round(sum_err[last, :, b].mean(0), 4)}, "
          f"max_i ||x_hat_i - x||_inf = {max_err[last, b].max():.4f}")

# %% [markdown]
# ## Fig. 1 — $\theta_1+\theta_2+\theta_3$, agent 1's own estimate and the resilient estimates
#
# The caption's "estimate obtained by agent 1" (red) is read here as $\mathcal V_1z_1$, the
# estimate of agent 1's partial observer (5) from its own bank ($o_1=n$); this is our
# interpretation (Deviations table). The blue curves are the resilient $\hat x_i$ of (6).

# %%
base_t, X_base = simulate(amp_batch[:-1], phi=phi_linear)
base = unpack(X_base)
base_sum_err = np.einsum("kinb,n->kib", base["xh"] - base["x"][:, None], theta_sel)

fig, axes = plt.subplots(2, 1, figsize=(plotting.COLUMN_WIDTH * 1.6, 5.0), sharex=True,
                         gridspec_kw={"height_ratios": [3, 2]})
ax = axes[0]
ax.plot(t_ex, own_1 @ theta_sel, color="tab:red", lw=1.2, label="estimate obtained by agent 1")
ax.plot(t_ex, sim["xh"][:, :, :, 0] @ theta_sel, color="tab:blue", lw=0.9)
ax.plot([], [], color="tab:blue", label="resilient estimates (all agents)")
ax.plot(t_ex, true_sum, color="k", lw=1.0, ls="--", label=r"$\theta_1+\theta_2+\theta_3$")
ax.axvline(attack_start, color="k", lw=0.6, ls=":")
ax.set_ylim(-4, 12)
ax.set_ylabel(r"$\theta_1+\theta_2+\theta_3$ [rad]")
ax.legend(loc="upper left", fontsize=7)
ax.set_title(f"ring of {N_banks} agents, κ = {kappa:g}, γ = {gamma_ex:g}, "
             f"a₁ = {attack_amplitude:.3f} rad for t ≥ {attack_start:g} s")
ax = axes[1]
for i in range(N_banks):
    ax.plot(t_ex, sum_err[:, i, 0], lw=1.0, color=f"C{i}", label=f"agent {i + 1}, (6)")
    ax.plot(base_t, base_sum_err[:, i, 0], lw=0.8, ls="--", color=f"C{i}")
ax.plot([], [], color="gray", ls="--", label="averaging baseline (ours)")
ax.axvline(attack_start, color="k", lw=0.6, ls=":")
ax.set_ylim(-1.0, 2.6)
ax.set_xlabel("time t [s]")
ax.set_ylabel("error of the θ-sum [rad]")
ax.legend(loc="upper left", fontsize=6.5, ncol=3)
plotting.save_figure(
    fig, FIG_DIR, "fig1_theta_sum",
    data={"t_s": t_ex, "true_sum": true_sum, "agent1_own_sum": own_1 @ theta_sel,
          "resilient_sum": sim["xh"][:, :, :, 0] @ theta_sel,
          "baseline_sum_error": base_sum_err[:, :, 0]},
    tolerance=dict.fromkeys(["agent1_own_sum", "resilient_sum", "baseline_sum_error"], results.SIGN_DRIVEN),
)
plt.show()

# %% [markdown]
# ## Why agent 1 alone is fooled (footnote 3)
#
# Let $v=[1,0,1,0,1,0]^\top$ (rigid rotation, $=\sqrt3\,v_1$). Then $Av=0$ and $C_1v=1$, so for
# $t\ge10$: $y_1+a_1=C_1\big(x+a\,v\big)$, and $x'=x+a\,v$ is itself a trajectory of the plant
# ($\dot x'=Ax'+Bu$). Agent 1's data after the step are those of an unattacked plant in another
# state: its partial observer (5) converges to $\mathcal W_1x'$ (indeed
# $-F_1^{-1}L_1a=a\,\mathcal W_1v$ exactly), its innovation returns to zero, and its θ-sum is
# off by $3a=\pi$ with every angle off by $a=\pi/3$. Strictly, this is an output attack along a
# marginally stable eigenvector of $A$, not an invariant-zero ("zero-dynamics") attack. Banks 2 and
# 3 also observe $v_1$ and are clean, so the network out-votes bank 1.

# %%
v_rigid = np.array([1.0, 0, 1.0, 0, 1.0, 0])
A_v, C1_v = float(np.abs(A @ v_rigid).max()), float((banks[0] @ v_rigid)[0])
p1_pred = -np.linalg.solve(F_cl[0], L_gain[0][:, 0])  # steady-state z_1 error per unit attack
p1_identity = float(np.abs(p1_pred - W_i[0] @ v_rigid).max())
z1_shift = np.abs(sim["z"][0][last, :, 0]
                  - (sim["x"][last, :, 0] + attack_amplitude * v_rigid) @ W_i[0].T).max()
innov_1 = (sim["x"][:, :, 0] @ banks[0][0] + np.where(t_ex >= attack_start, attack_amplitude, 0.0)
           - sim["z"][0][..., 0] @ (banks[0] @ V_i[0])[0])
own_sum_err = own_1[last] @ theta_sel - true_sum[last]
own_inf_err = np.abs(own_1[last] - sim["x"][last, :, 0]).max(axis=1)
print(f"||A v|| = {A_v:.1e}, C_1 v = {C1_v:g}; |-F_1^-1 L_1 - W_1 v| = {p1_identity:.1e}")
print(f"last {final_window:g} s: |z_1 - W_1(x + a v)| <= {z1_shift:.1e}, "
      f"|innovation of agent 1| <= {np.abs(innov_1[last]).max():.1e}")
print(f"agent 1's own estimate: theta-sum error {own_sum_err.mean():.5f} (pi = {np.pi:.5f}), "
      f"inf-norm error {own_inf_err.mean():.5f} (pi/3 = {np.pi / 3:.5f})")

# %% [markdown]
# ## The steady-state offset law (ours)
#
# With $\gamma=2$ the resilient estimates do not converge to $x$ after the attack: they keep
# constant offsets. Theorem 2 only promises $\limsup\|\hat x_i-x\|_\infty\le\eta$ for large enough
# $\kappa,\gamma$, so this is consistent with the paper, and the offsets can be predicted exactly.
# In the error coordinates $\bar x_i=W(\hat x_i-x)$ (7), only coordinate 1 ($v_1$) is pushed:
# $p_1=\mathcal WV_1z_1-\mathcal Wx\to a\sqrt3\,e_1$, the other agents' $p_i\to0$. Column 1 of $\bar A$
# is zero ($Av_1=0$), so constant offsets $c_i$ in coordinate 1 are an equilibrium of (7) iff
#
# $$0\in s_i^1\,\mathrm{Sgn}(p_i^1-c_i)-\gamma(\mathcal Lc)_i\quad\forall i
# \iff c\in\arg\min_c\ \sum_i s_i^1|p_i^1-c_i|+\tfrac{\gamma}{2}c^\top\mathcal Lc,$$
#
# the optimality condition of a Laplacian-regularised median (the same holds for the scalar
# solver (4): its equilibria minimise $\sum_is_i|z_i-x_i|+\frac\gamma2x^\top\mathcal Lx$). $\kappa$
# drops out. On the ring 1–2–3–4–5–1 with $s^1=(1,1,1,0,0)$: agents 2 and 3 slide on $c=0$ with
# equivalent signs $-3/4$ and $-1/4$, agent 1 is saturated ($+1$), and the Laplacian rows give
#
# $$c=\frac1\gamma\big[\tfrac34,\,0,\,0,\,\tfrac14,\,\tfrac12\big]\quad(\text{valid while } a\sqrt3>\tfrac3{4\gamma}),$$
#
# θ-sum offsets $\sqrt3\,c$ (independent of the attack size $a$), $\max_i\|\hat x_i-x\|_\infty=\sqrt3/(4\gamma)$,
# and identification residual $\|z_1-\mathcal W_1\hat x_1\|_\infty\to a\sqrt3-\frac3{4\gamma}$. We compute
# the prediction generally with cvxpy (CLARABEL) and compare it with the hand formula and the
# simulation. The **averaging baseline** has the quadratic counterpart
# $(\gamma\mathcal L+D_s)c=D_sp$, $D_s=\operatorname{diag}(s^1)$: offsets proportional to $a$,
# tending to $a\sqrt3$ for every agent as $\gamma\to\infty$ — the attack is averaged in, not rejected.


# %%
s_v1 = S_ind[:, 0].astype(float)  # banks observing coordinate 1
_p_par = cp.Parameter(N_banks)
_g_par = cp.Parameter(nonneg=True)
_c_var = cp.Variable(N_banks)
_median_problem = cp.Problem(cp.Minimize(
    cp.sum(cp.multiply(s_v1, cp.abs(_p_par - _c_var)))
    + _g_par / 2 * cp.quad_form(_c_var, cp.psd_wrap(lap_ex))
))  # DPP: compiled once, re-solved for every p and gamma
assert _median_problem.is_dcp(dpp=True)


def median_equilibrium(p: np.ndarray, gain_gamma: float) -> np.ndarray:
    """argmin_c sum_i s_i^1 |p_i - c_i| + (gamma/2) c^T L c on the example ring (CLARABEL)."""
    _p_par.value, _g_par.value = p, gain_gamma
    _median_problem.solve(solver=cp.CLARABEL)
    if _median_problem.status != cp.OPTIMAL:
        raise RuntimeError(f"median equilibrium: solver status {_median_problem.status}")
    return np.asarray(_c_var.value)


def baseline_equilibrium(p: np.ndarray, gain_gamma: float) -> np.ndarray:
    """Equilibrium of the averaging baseline: (gamma L + D_s) c = D_s p."""
    return np.linalg.solve(gain_gamma * lap_ex + np.diag(s_v1), s_v1 * p)


sum_v1 = float(theta_sel @ V[:, 0])  # theta-sum of v_1 (= sqrt(3))


def p_attack(amp: float) -> np.ndarray:
    """Steady-state coordinate-1 error p_i^1 of the partial observers for attack size amp."""
    p = np.zeros(N_banks)
    p[attack_bank - 1] = amp * (W[0] @ v_rigid)
    return p


hand = np.array([0.75, 0.0, 0.0, 0.25, 0.5])  # gamma * c for the natural ring order
offsets_pred = {}
offsets_meas = {}
for g in offset_gammas:
    offsets_pred[g] = sum_v1 * median_equilibrium(p_attack(attack_amplitude), g)
    if g == gamma_ex:
        offsets_meas[g] = sum_err[last, :, 0].mean(axis=0)
        maxerr_g = max_err[last, 0].max()
    else:
        _, X_g = simulate([attack_amplitude], gain_gamma=g)
        sim_g = unpack(X_g)
        err_g = sim_g["xh"][..., 0] - sim_g["x"][:, None, :, 0]
        offsets_meas[g] = (err_g[last] @ theta_sel).mean(axis=0)
        maxerr_g = np.abs(err_g[last]).max()
    print(f"gamma = {g:5g}: predicted {np.round(offsets_pred[g], 4)}, measured "
          f"{np.round(offsets_meas[g], 4)}, max err {maxerr_g:.4f} "
          f"(sqrt3/(4 gamma) = {np.sqrt(3) / (4 * g):.4f})")
    offsets_meas[g] = (offsets_meas[g], maxerr_g)
hand_dev = (float(np.abs(offsets_pred[gamma_ex] - sum_v1 * hand / gamma_ex).max())
            if list(ring_order) == [1, 2, 3, 4, 5] else float("nan"))
print(f"cvxpy prediction vs hand formula (natural ring): {hand_dev:.1e}")

amp_offsets = {amp: sum_err[last, :, b].mean(axis=0) for b, amp in enumerate(amp_batch[:-1])}
base_offsets = {amp: base_sum_err[last, :, b].mean(axis=0) for b, amp in enumerate(amp_batch[:-1])}
base_pred = {amp: sum_v1 * baseline_equilibrium(p_attack(amp), gamma_ex)
             for amp in amp_batch[:-1]}
for amp in amp_batch[:-1]:
    print(f"a = {amp:7.4f}: median offsets {np.round(amp_offsets[amp], 4)}; baseline "
          f"{np.round(base_offsets[amp], 4)} (predicted {np.round(base_pred[amp], 4)})")

# %%
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 2.8))
ax = axes[0]
g_fine = np.geomspace(min(offset_gammas) / 1.5, max(offset_gammas) * 1.5, 25)
pred_line = np.array([sum_v1 * median_equilibrium(p_attack(attack_amplitude), g)
                      for g in g_fine])
for i in range(N_banks):
    if np.abs(pred_line[:, i]).max() > 1e-6:
        ax.loglog(g_fine, pred_line[:, i], color=f"C{i}", lw=0.8)
        ax.loglog(offset_gammas, [offsets_meas[g][0][i] for g in offset_gammas], "o",
                  color=f"C{i}", ms=4, label=f"agent {i + 1}")
ax.plot([], [], color="gray", lw=0.8, label="prediction (argmin)")
ax.set_xticks(offset_gammas, [f"{g:g}" for g in offset_gammas])
ax.xaxis.set_minor_formatter(mticker.NullFormatter())
ax.set_xlabel("coupling gain γ [–]")
ax.set_ylabel("θ-sum offset after the attack [rad]")
ax.set_title("median observer (6): offsets ∝ 1/γ")
ax.legend(fontsize=7)
ax = axes[1]
amps = np.array(amp_batch[:-1])
amp_fine = np.linspace(0.0, amps.max() * 1.05, 22)
ax.plot(amps, [amp_offsets[a][0] for a in amps], "o", color="tab:blue", label="median (6), agent 1")
ax.plot(amps, [base_offsets[a][0] for a in amps], "s", color="tab:red",
        label="averaging baseline, agent 1")
ax.plot(amp_fine, [sum_v1 * median_equilibrium(p_attack(a), gamma_ex)[0] for a in amp_fine],
        color="tab:blue", lw=0.8)
ax.plot(amp_fine, [sum_v1 * baseline_equilibrium(p_attack(a), gamma_ex)[0]
                   for a in amp_fine], color="tab:red", lw=0.8)
ax.set_xlabel("attack size a [rad]")
ax.set_ylabel("θ-sum offset of agent 1 [rad]")
ax.set_title(f"γ = {gamma_ex:g}: lines = predictions, marks = simulation")
ax.legend(fontsize=7)
plotting.save_figure(
    fig, FIG_DIR, "extra_offset_law",
    data={"amplitude": amps, "median_offset_agent1": [amp_offsets[a][0] for a in amps],
          "baseline_offset_agent1": [base_offsets[a][0] for a in amps],
          "median_pred_agent1": [sum_v1 * median_equilibrium(p_attack(a), gamma_ex)[0]
                                 for a in amps],
          "baseline_pred_agent1": [base_pred[a][0] for a in amps]},
    tolerance=dict.fromkeys(["median_offset_agent1", "baseline_offset_agent1"], results.SIGN_DRIVEN),
)
plt.show()

# %% [markdown]
# ## Attack identification (Conclusion; Fig. S2, ours)
#
# After the transients each agent compares its partial estimate with its resilient one,
# $\|z_i-\mathcal W_i\hat x_i\|_\infty$: for agent 1 it tends to $a\sqrt3-3/(4\gamma)$, for the
# clean agents to the chattering level.

# %%
_, X_sh = simulate([attack_amplitude, 0.0], gains=gain_sets["shifted"][0])
sim_sh = unpack(X_sh)
resid = {}
for label, sim_r in (("near", sim), ("shifted", sim_sh)):
    resid[label] = np.stack([np.abs(sim_r["z"][i][..., 0] - sim_r["xh"][:, i, :, 0] @ W_i[i].T).max(1)
                             for i in range(N_banks)], axis=1)
resid_final = resid[observer_poles][last].mean(axis=0)
resid_pred = attack_amplitude * np.sqrt(3) - 3 / (4 * gamma_ex)
print("residual over the last window:", np.round(resid_final, 5),
      f"(agent 1 predicted {resid_pred:.4f})")
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 2.8), sharey=True)
for ax, (label, r) in zip(axes, resid.items(), strict=True):
    for i in range(N_banks):
        ax.semilogy(t_ex, np.maximum(r[:, i], 1e-6), lw=0.9, label=f"agent {i + 1}")
    ax.axvline(attack_start, color="k", lw=0.6, ls=":")
    ax.set_title(f'observer poles "{label}"')
    ax.set_xlabel("time t [s]")
axes[0].set_ylabel(r"$\|z_i-\mathcal{W}_i\hat x_i\|_\infty$ [rad, rad/s]")
axes[0].set_ylim(1e-5, 1e4)
axes[0].legend(fontsize=7, ncol=2)
plotting.save_figure(fig, FIG_DIR, "extra_identification_residual",
                     data={"t_s": t_ex, "resid_near": resid["near"], "resid_shifted": resid["shifted"]},
                     tolerance={
                         "resid_near": results.Tolerance(
                             rtol=0.05, atol=0.05,
                             reason="residual of observers with near-pole gains (up to 1.5e3, placed at "
                             "clustered poles: ill-conditioned), which amplify the agents' chattering "
                             "differences: under other BLAS kernels up to 0.017 late, 1.4 % of the value "
                             "during the transient"),
                         "resid_shifted": results.Tolerance(
                             rtol=1e-6, atol=1e-9,
                             reason="residual of observers with well-conditioned (shifted) gains: no sgn "
                             "flipped under other BLAS kernels, last bits grown to <= 6e-10 relative "
                             "over 40 s")})
plt.show()

# %% [markdown]
# ## No attack (Theorem 2 with $a\equiv0$)

# %%
conv_time = {}
final_noattack = {}
for label, me in (("near", max_err[:, -1]),
                  ("shifted", np.abs(sim_sh["xh"][..., 1] - sim_sh["x"][:, None, :, 1]).max(axis=(1, 2)))):
    above = np.nonzero(me >= 0.05)[0]
    conv_time[label] = float(t_ex[above.max() + 1]) if above.size else 0.0
    final_noattack[label] = float(me[last].max())
    print(f'poles "{label}": max_i ||x_hat_i - x||_inf < 0.05 from t = {conv_time[label]:.2f} s, '
          f"final {final_noattack[label]:.1e}")

# %% [markdown]
# ## Variant (11) and Theorem 3
#
# $A$ is Lyapunov stable with distinct eigenvalues; with $T$ the real modal matrix (columns
# $X_k$), $P=T^{-\top}T^{-1}$ satisfies $PA+A^\top P\le0$, and $\bar P=V^\top PV=(WT)^{-\top}(WT)^{-1}$ is
# block-diagonal over the indicator groups. Theorem 3 bounds
# $\limsup\|\hat x_i-x\|\le(Nn^2+\sqrt n)\sqrt N\,\|V\bar P^{-1/2}\|/(\gamma\lambda_2)$.

# %%
WT_inv = np.linalg.inv(W @ T_modal)
P_bar = WT_inv.T @ WT_inv  # (WT)^-T (WT)^-1
P_bar = 0.5 * (P_bar + P_bar.T)
P_plant = W.T @ P_bar @ W
lyap_max = float(np.linalg.eigvalsh(P_plant @ A + A.T @ P_plant).max())
group_id = np.unique(S_ind.T, axis=0, return_inverse=True)[1].ravel()
offgroup = float(np.abs(P_bar[group_id[:, None] != group_id[None, :]]).max())
P_half = np.real(sla.sqrtm(P_bar))
V_bar, W_bar = np.linalg.solve(P_half.T, V.T).T, P_half @ W
_, X_11 = simulate([attack_amplitude], v_corr=V_bar, w_corr=W_bar)
sim_11 = unpack(X_11)
err_11 = sim_11["xh"][..., 0] - sim_11["x"][:, None, :, 0]
sums_11 = (err_11[last] @ theta_sel).mean(axis=0)
maxerr_11 = float(np.abs(err_11[last]).max())
maxerr2_11 = float(np.linalg.norm(err_11[last], axis=2).max())
thm3_bound = ((N_banks * n**2 + np.sqrt(n)) * np.sqrt(N_banks) / (gamma_ex * lam2_ex)
              * np.linalg.norm(V_bar, 2))
print(f"max eig(PA + A^T P) = {lyap_max:.1e}; largest off-group entry of P_bar = {offgroup:.1e}")
print(f"(11): theta-sum offsets {np.round(sums_11, 4)}, max ||.||_inf = {maxerr_11:.4f}, "
      f"max ||.||_2 = {maxerr2_11:.4f}, Theorem 3 bound = {thm3_bound:.1f}")

# %% [markdown]
# ## Final remark of Section IV — no local majority for agent 1
#
# Agent 1 and its ring neighbours 2 and 5 observe the rigid-body coordinates $v_1,v_2$ only
# through banks 1 and 2: two banks, fewer than $2q+1=3$, so agent 1 cannot out-vote a corrupted
# bank from its neighbourhood alone. This depends on the ring order: with neighbours 2 and 3 it
# would see three observing banks.

# %%
nbhd_1 = [0, *np.nonzero(adj_ex[0])[0].tolist()]
local_voters = int(S_ind[nbhd_1, 0].sum())
print(f"agent 1's neighbourhood (1-based): {[i + 1 for i in nbhd_1]}; banks observing v1 in it: "
      f"{local_voters} < 2q+1 = {2 * q + 1}: {local_voters < 2 * q + 1}")

# %% [markdown]
# ## Claims
#
# | id | paper | what we measure |
# |---|---|---|
# | C1 | Theorem 1: every agent ends within $2\sqrt N/(\gamma\lambda_2)$ of $\mathcal M$ | demo (ring, all-to-all) and the γ sweep on ring-5, ring-7, complete-7: max distance over the last quarter ≤ bound (judged on the bound only) |
# | C2 | Assumptions 2 and 4, Lemma 1 for the example | enumeration for $q=1$ (holds) and $q=2$ (fails); the constructed basis verified; banks per coordinate ≥ 2q+1 |
# | C3 | Fig. 1 / footnote 3: agent 1 alone is fooled, the network is not | last-window mean error of agent 1's θ-sum ≈ π and ∞-norm ≈ π/3 (±0.01); resilient θ-sum errors < 1 rad |
# | C4 | Theorem 2: resilient estimation (for large enough κ, γ) | offsets vs the closed-form prediction (±0.01), ∝ 1/γ, independent of the attack size; max error ≤ 0.25 at γ = 2 and ≤ 0.03 at γ = 20 |
# | C5 | Theorem 2 without attack | final max error ≤ 0.01 for both pole sets |
# | C6 | median, not average (ours: the averaging baseline) | baseline offsets grow linearly with the attack size and match $(\gamma\mathcal L+D_s)c=D_sp$ (1 %); median offsets do not grow |
# | C7 | Conclusion: $\|z_i-\mathcal W_i\hat x_i\|$ identifies the attacked bank | agent 1's residual ≈ $a\sqrt3-3/(4\gamma)$ (±0.01), the others < 0.01, ratio > 100 |
# | C8 | Theorem 3 for variant (11) | $P$ valid, $\bar P$ block-diagonal, error ≤ bound (vacuous: consistency only; the bound depends on our $P$, whose $\bar P$ and basis $V$ are recorded so the bound can be recomputed) |
# | C9 | Remark 2: $\lambda_2$ of rings and all-to-all graphs | networkx against the closed forms, $N=3..12$ |
# | C10 | Section IV final remark: no local majority for agent 1 | banks observing $v_1$ in agent 1's neighbourhood < 2q+1 |
# | C11 | footnote 3: agent 1's own data cannot reveal the attack | $Av=0$, $C_1v=1$, $-F_1^{-1}L_1=\mathcal W_1v$; $z_1\to\mathcal W_1(x+av)$ and the innovation → 0 |
# | X1 | integrator (ours) | exponential Euler beats explicit Euler at equal $dt$, converges with order one; explicit Euler at 2.5e-3 s is unstable (spectral radius of $I+dt\,M$ 1.0004 > 1; its deviation grows ×2.1 over 20 s, reported, not tested) |
# | X2 | (ours, not a statement of the paper) the final distance of (4) shrinks as γ grows | γ sweep: max distance non-increasing in γ on every graph (tolerance 1e-3 for chattering) |

# %%
claims = {}
sweep_ok = all(bool(np.all(r["distance"] <= r["bound"])) for r in sweep.values())
sweep_mono = all(bool(np.all(np.diff(r["distance"]) <= 1e-3)) for r in sweep.values())
claims["C1"] = results.claim(
    paper="Theorem 1: limsup_t dist(x_i(t), M) <= 2 sqrt(N) / (gamma lambda_2(L)) for every agent",
    check="demo per graph: each agent's max distance to the median set over the last "
    f"{settle_fraction:.0%} of the horizon <= the bound; sweep: max over agents for every graph "
    "and gamma <= the bound (the bound only; the trend in gamma is X2, ours)",
    measured={**{g: r["final_distance"] for g, r in runs.items()},
              "sweep": {g: r["distance"] for g, r in sweep.items()}},
    threshold={**{g: r["bound"] for g, r in runs.items()},
               "sweep": {g: r["bound"] for g, r in sweep.items()}},
    holds=all(bool(np.all(r["final_distance"] <= r["bound"])) for r in runs.values())
    and sweep_ok,
)
claims["C2"] = results.claim(
    paper="Section IV: (C, A) is 2-redundant observable (q = 1) and satisfies Assumption 4; "
    "Lemma 1: every coordinate is observed by >= 2q + 1 banks",
    check="enumeration of all subsets of N - 2q banks for q = 1 and q = 2; the constructed "
    "basis verified against the unobservable subspaces; banks per coordinate",
    measured={"redundant_q1": red[1].holds, "redundant_q2": red[2].holds,
              "failing_q2": [[i + 1 for i in f] for f in red[2].failing],
              "assumption4": bool(a4_ok), "banks_per_coordinate": banks_per_coord},
    threshold={"redundant_q1": True, "redundant_q2": False, "assumption4": True,
               "min_banks_per_coordinate": 2 * q + 1},
    holds=red[1].holds and not red[2].holds and bool(a4_ok)
    and bool(banks_per_coord.min() >= 2 * q + 1),
)
res_sum_err = float(np.abs(sum_err[last, :, 0]).max())
pre_attack = (t_ex >= attack_start - 2.0) & (t_ex < attack_start)
pre_sum_err = float(max(np.abs(sum_err[pre_attack, :, 0]).max(),
                        np.abs(own_1[pre_attack] @ theta_sel - true_sum[pre_attack]).max()))
claims["C3"] = results.claim(
    paper="Fig. 1 and footnote 3: after the attack agent 1's own estimate is wrong while the "
    "resilient estimates of all agents follow the true theta-sum",
    check=f"mean over the last {final_window:g} s of agent 1's own theta-sum error (vs pi) and "
    "infinity-norm error (vs pi/3), tolerance 0.01; max |resilient theta-sum error| < 1 rad; "
    "all theta-sum errors (own and resilient) < 0.05 in the 2 s before the attack",
    measured={"own_sum_error": float(own_sum_err.mean()), "own_inf_error": float(own_inf_err.mean()),
              "resilient_sum_error_max": res_sum_err, "pre_attack_sum_error_max": pre_sum_err},
    threshold={"own_sum_error": 3 * attack_amplitude, "own_inf_error": attack_amplitude,
               "resilient_sum_error_max": 1.0, "pre_attack_sum_error_max": 0.05},
    holds=abs(own_sum_err.mean() - 3 * attack_amplitude) <= 0.01
    and abs(own_inf_err.mean() - attack_amplitude) <= 0.01 and res_sum_err < 1.0
    and pre_sum_err < 0.05,
    tolerance=results.SIGN_DRIVEN,
)
off_dev = max(float(np.abs(offsets_meas[g][0] - offsets_pred[g]).max()) for g in offset_gammas)
gamma_scaled = [offsets_meas[g][0][0] * g for g in offset_gammas]
amp_dev = max(float(np.abs(amp_offsets[a] - amp_offsets[attack_amplitude]).max())
              for a in amp_offsets)
maxerr_by_gamma = {g: float(offsets_meas[g][1]) for g in offset_gammas}
claims["C4"] = results.claim(
    paper="Theorem 2: for large enough kappa, gamma, limsup ||x_hat_i - x||_inf <= eta under attack",
    check="last-window theta-sum offsets vs the closed-form equilibrium (argmin of "
    "sum s|p - c| + gamma/2 c'Lc), tolerance 0.01, for every gamma; agent 1's offset * gamma "
    "constant (spread <= 0.02); offsets independent of the attack size (<= 0.01); "
    "max error <= 0.25 at gamma = 2 and <= 0.03 at gamma = 20",
    measured={"max_offset_deviation": off_dev, "agent1_offset_times_gamma": gamma_scaled,
              "amplitude_dependence": amp_dev, "max_error": maxerr_by_gamma,
              "offsets": {str(g): offsets_meas[g][0] for g in offset_gammas}},
    threshold={"max_offset_deviation": 0.01, "predicted_offsets":
               {str(g): offsets_pred[g] for g in offset_gammas},
               "amplitude_dependence": 0.01, "max_error": {"2.0": 0.25, "20.0": 0.03}},
    holds=off_dev <= 0.01 and np.ptp(gamma_scaled) <= 0.02 and amp_dev <= 0.01
    and maxerr_by_gamma.get(2.0, 0.0) <= 0.25 and maxerr_by_gamma.get(20.0, 0.0) <= 0.03,
    tolerance=results.SIGN_DRIVEN,
)
claims["C5"] = results.claim(
    paper="Theorem 2 without attack: every x_hat_i converges to x (up to eta)",
    check=f"max_i ||x_hat_i - x||_inf over the last {final_window:g} s <= 0.01 for both pole sets; "
    "time after which it stays below 0.05",
    measured={"final_error": final_noattack, "time_below_0.05": conv_time},
    threshold={"final_error": 0.01},
    holds=all(v <= 0.01 for v in final_noattack.values()),
    tolerance=results.SIGN_DRIVEN,
)
amps_sorted = sorted(base_offsets)
base_growth = [float(base_offsets[a][0]) for a in amps_sorted]
base_rel = max(float(np.abs(base_offsets[a] - base_pred[a]).max() / np.abs(base_pred[a]).max())
               for a in amps_sorted)
claims["C6"] = results.claim(
    paper="(ours) the median is what rejects the attack: an averaging correction (sgn(r) "
    "replaced by r) is corrupted in proportion to the attack",
    check="agent 1's baseline theta-sum offset strictly increasing with the attack size and "
    "within 1 % of (gamma L + D_s) c = D_s p; median offsets unchanged (<= 0.01)",
    measured={"attack_sizes": amps_sorted, "baseline_agent1_offset": base_growth,
              "baseline_relative_deviation": base_rel,
              "median_agent1_offset": [float(amp_offsets[a][0]) for a in amps_sorted]},
    threshold={"baseline_relative_deviation": 0.01, "median_amplitude_dependence": 0.01},
    holds=bool(np.all(np.diff(base_growth) > 0)) and base_rel <= 0.01 and amp_dev <= 0.01,
    tolerance=results.SIGN_DRIVEN,
)
clean_max = float(np.delete(resid_final, attack_bank - 1).max())
claims["C7"] = results.claim(
    paper="Conclusion: comparing z_i with W_i x_hat_i identifies the attacked bank",
    check=f"mean over the last {final_window:g} s of ||z_i - W_i x_hat_i||_inf: agent 1 vs "
    "a sqrt(3) - 3/(4 gamma) (tolerance 0.01), the other agents < 0.01, ratio > 100",
    measured={"residual": resid_final, "ratio": float(resid_final[attack_bank - 1] / clean_max)},
    threshold={"agent1_predicted": resid_pred, "clean_max": 0.01, "ratio": 100.0},
    holds=abs(resid_final[attack_bank - 1] - resid_pred) <= 0.01 and clean_max < 0.01
    and resid_final[attack_bank - 1] / clean_max > 100,
    tolerance=results.Tolerance(
        rtol=0.3, atol=5e-3,
        reason="the clean agents' residuals (~4e-4) are chattering-level (kappa*dt = 5e-4) and differ "
        "by up to 16 % under other BLAS kernels; the ratio of agent 1's residual to them inherits it"),
)
claims["C8"] = results.claim(
    paper="Theorem 3: for Lyapunov-stable plants, (5) + (11) gives limsup ||x_hat_i - x|| <= "
    "(N n^2 + sqrt(n)) sqrt(N) ||V P_bar^(-1/2)|| / (gamma lambda_2)",
    check="max eig(PA + A'P) <= 1e-9, P_bar block-diagonal over indicator groups (<= 1e-9), "
    "last-window max ||x_hat_i - x||_2 <= the bound (vacuous here: a consistency check; the bound "
    "depends on our P of (11): P_bar = V'PV and the basis V are recorded to recompute it)",
    measured={"lyapunov_max_eig": lyap_max, "offgroup": offgroup, "max_error_2norm": maxerr2_11,
              "theta_sum_offsets": sums_11, "P_bar": P_bar, "basis_V": V},
    threshold={"bound": float(thm3_bound)},
    holds=lyap_max <= 1e-9 and offgroup <= 1e-9 and maxerr2_11 <= thm3_bound,
    tolerance=results.SIGN_DRIVEN,
)
lam2_formula = {"ring": 2 * (1 - np.cos(2 * np.pi / N)), "all-to-all": float(N)}
claims["C9"] = results.claim(
    paper="Remark 2: lambda_2 = 2(1 - cos(2 pi / N)) on a ring (decreasing in N), = N on the "
    "all-to-all graph",
    check="networkx algebraic_connectivity vs the closed forms for N = 3..12 (<= 1e-8); the "
    "demo graphs' eigenvalues (<= 1e-12)",
    measured={"max_deviation": remark2_dev, **{g: r["lambda2"] for g, r in runs.items()}},
    threshold={"max_deviation": 1e-8, **lam2_formula},
    holds=remark2_dev <= 1e-8 and bool(np.all(np.diff(lam2_ring_seq) < 0))
    and all(abs(runs[g]["lambda2"] - v) <= 1e-12 for g, v in lam2_formula.items()),
)
claims["C10"] = results.claim(
    paper="Section IV: on the ring agent 1 cannot obtain resilient estimates of span{v1, v2} "
    "from its neighbours' measurements alone",
    check="number of banks observing v1 among agent 1 and its neighbours < 2q + 1",
    measured={"neighbourhood": [i + 1 for i in nbhd_1], "observing_banks": local_voters},
    threshold={"2q+1": 2 * q + 1},
    holds=local_voters < 2 * q + 1,
)
innov_max = float(np.abs(innov_1[last]).max())
claims["C11"] = results.claim(
    paper="Footnote 3: agent 1 cannot tell from its own measurement that it is attacked",
    check="||Av|| <= 1e-9 and C_1 v = 1 for v = [1,0,1,0,1,0]; |-F_1^-1 L_1 - W_1 v| <= 1e-6; "
    f"over the last {final_window:g} s |z_1 - W_1(x + a v)| <= 1e-2 (the tail of bank 1's "
    "transient after the attack step) and |innovation of (5)| <= 1e-3",
    measured={"Av": A_v, "C1v": C1_v, "gain_identity": p1_identity, "z1_shift": float(z1_shift),
              "innovation": innov_max},
    threshold={"identities": 1e-6, "z1_shift": 1e-2, "innovation": 1e-3},
    holds=A_v <= 1e-9 and abs(C1_v - 1) <= 1e-12 and p1_identity <= 1e-6 and z1_shift <= 1e-2
    and innov_max <= 1e-3,
    tolerance=results.Tolerance(
        rtol=1e-3, atol=1e-5,
        reason="z_1's tail and the innovation follow agent 1's chattering observer (<= 7e-7 measured "
        "under other BLAS kernels); the gain identity is a rounding residual of gains ~1.5e3 placed "
        "at clustered poles (1.4e-9 or 0)"),
)
acc_exp, acc_exp2 = acc_table["exponential Euler, dt = 1e-3 (ours)"][0], acc_table[
    "exponential Euler, dt = 5e-4"][0]
acc_eul = acc_table["explicit Euler, dt = 1e-3"][0]
eul_unstable = acc_runs["explicit Euler, dt = 2.5e-3 (unstable)"]
eul_growth = float(eul_unstable[t_acc >= accuracy_T - 1.0].max() / eul_unstable[t_acc <= 2.0].max())
claims["X1"] = results.claim(
    paper="(ours) integrator choice for the discontinuous right-hand side",
    check="RMS deviation from the dt = 1e-4 reference: exponential Euler (1e-3) < explicit Euler "
    "(1e-3); halving dt divides it by 1.5..2.5 (order one); explicit Euler at dt = 2.5e-3: "
    "spectral radius of I + dt M > 1 (its deviation growth is reported, not tested: the "
    "unstable (1,-2,1) mode is barely excited here)",
    measured={"rms_deviation": {k: v[0] for k, v in acc_table.items()},
              "spectral_radius_euler": {str(k): v for k, v in rho_euler.items()},
              "euler_unstable_growth": eul_growth},
    threshold={"order_ratio": [1.5, 2.5], "spectral_radius": 1.0},
    holds=acc_exp < acc_eul and 1.5 <= acc_exp / acc_exp2 <= 2.5 and rho_euler[2.5e-3] > 1.0
    and rho_euler[1e-3] <= 1.0 + 1e-12,
    tolerance=results.Tolerance(
        rtol=0.1, atol=5e-3,
        reason="RMS deviations between chattering integrations (<= 2e-4 apart under other BLAS "
        "kernels); the unstable-Euler growth is a ratio of two chattering-dominated maxima (2.12 "
        "vs 2.16)"),
)
claims["X2"] = results.claim(
    paper="(ours, not a statement of the paper) the final distance of (4) to the median set "
    "shrinks as gamma grows; Theorem 1 only bounds it by a quantity proportional to 1/gamma",
    check="sweep: max over agents of the distance over the last "
    f"{settle_fraction:.0%} of the horizon non-increasing in gamma on every graph "
    "(tolerance 1e-3 for chattering)",
    measured={g: r["distance"] for g, r in sweep.items()},
    threshold={"gammas": gam_sweep, "tolerance": 1e-3},
    holds=sweep_mono,
)
results.write_claims(results_path, claims)
for cid, c in claims.items():
    print(cid, "holds" if c["holds"] else "DOES NOT HOLD")

# %% [markdown]
# ## Deviations from the paper
#
# | item | paper | here | why |
# |---|---|---|---|
# | Section II example | none given | the values of the parameter table; γ sweep on three graphs | Theorem 1 holds for any data; these make the median set an interval ($S$ even) and include one outlier |
# | Section II integrator | continuous time, Filippov solutions | explicit Euler, $dt=10^{-3}$ s | below the stability step; chattering on the sliding surface is $O(dt)$ |
# | limsup | $t\to\infty$ | max (Section II) or mean (Section IV) over a final window of a finite horizon | a finite run can only bound the limsup |
# | Assumption 2 wording (Section II) | "more than $2q+1$" nonzero $C_i$ | at least $2q+1$ (CORRECTED) | consistent with Lemma 1 |
# | basis of Assumption 4 | existence only | grouped projected-orthonormal basis, unit norm (MISSING) | the numbers (speed, offsets) depend on the basis scaling |
# | observer poles | "near −1" | $-1,-1.1,\dots$ (MISSING); "shifted" alternative | the literal reading gives gains up to 1.5e3 and transient peaks of 5e4 (banks 1, 3) |
# | initial conditions, horizon, ring order | not given | parameters `x0_plant`, `z0_guess`, `xhat0` (observers start at zero), `T_ex`, `ring_order` (MISSING) | see the provenance table |
# | integrator (Section IV) | not given | exponential Euler, $dt=10^{-3}$ s (MISSING) | justified in the integrator section |
# | footnote 3 | "zero-dynamics attack" | an output attack along the marginally stable eigenvector $v$ ($Av=0$) (CORRECTED wording) | it is stealthy for bank 1 alone, not an invariant-zero attack |
# | variant (11) | any $P>0$ with $PA+A^\top P\le0$ | $\bar P$ block-diagonal over the indicator groups (CORRECTED: unstated condition) | otherwise $\bar P^{1/2}$ mixes unobservable coordinates into the sign arguments |
# | Theorem 3 proof / plug-and-play gain | $\bar x$ for the disagreement; "$\sqrt N/(4\bar s/(\bar N^2-N))$" | $\tilde x$; $\gamma=\|V\bar P^{-1/2}\|\sqrt{\bar N}(\bar N^2-\bar N)(\bar Nn^2+\sqrt n)/(4\bar s)$ (CORRECTED, not used numerically) | OCR drops tildes; $N$ and $\bar N$ mixed |
# | Theorem 2 at the paper's gains | "arbitrary precision" for large κ, γ | offsets $O(1/\gamma)$ after the attack (0.65 rad θ-sum for agent 1 at γ = 2), predicted in closed form | the theorem is semi-global and asymptotic in the gains; not a contradiction |
# | Appendix B item 7 | 4×4 real Jordan block missing its first row (OCR) | $[[\alpha,-\beta,1,0],[\beta,\alpha,0,1],[0,0,\alpha,-\beta],[0,0,\beta,\alpha]]$ (CORRECTED, not used numerically) | garbled |
# | basis construction | — | distinct eigenvalues only (our procedure refuses repeated ones) | the example has six distinct eigenvalues |
# | Fig. 1 | printed figure | our Fig. 1 (printed figure not available in the OCR text) | compared with the caption and text only |
# | Fig. 1, red curve | "its estimate obtained by agent 1" | read as $\mathcal V_1z_1$, the θ-sum of agent 1's partial observer (5) ($o_1=n$, so it is a full-state estimate from bank 1 alone) (our interpretation) | the only estimate agent 1 forms without the network; footnote 3's argument (agent 1 cannot detect the attack from its own measurement) is about it. Not $\hat x_1$, which is one of the blue resilient estimates |
# | extras (ours) | — | Theorem 1 sweep, integrator comparison, offset law, averaging baseline, identification residual (Fig. S2), no-attack and (11) runs | acceptance of the reproduction issue |

# %%
manifest_path = run.finish(solver="exponential Euler (secest.systems.integrate_switched_linear); "
                           "CLARABEL for the offset prediction")
print("run manifest:", manifest_path.relative_to(results.repo_root()))
