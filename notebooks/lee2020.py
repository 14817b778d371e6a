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
# **Verdict: [Re, partial]**, computed by the one written rule in the Verdict section (printed there
# and quoted in README and ERRATA) from the claims that decide it: C1, C3, C4, C8, C12, C13, C14,
# the contributions the abstract, the Introduction and the Conclusion name. C1, C3 and C8 hold;
# the plug-and-play claims C12 (re-initialisation) and C13 (leaving and rejoining) hold with Sec.
# III-C's plug-and-play method (11), whose Theorem 3 premise the example meets; C14 ("seamlessly")
# fails there; C4 (Theorem 2's "arbitrary precision") is not checked: the gains known to meet its
# premise cannot be integrated here. Checked against the text and the caption of Fig. 1 (the printed
# figure is not available: OCR text only). The outcomes at this run's parameters and the counts over
# the 72 points of the declared space are printed with the claims. (Until the session-13 review of
# issue #30 the verdict was [Re]: C4, C12 and C13 were decided at κ = 0.5 with (6) without Theorem
# 2's gain condition in their premises, "seamlessly" was quoted but not tested, and identification
# (C7b) decided next to C8 on the same runs. That review put Theorem 2's κ* into the premises, so
# C4, C12, C13, C14 failed their premise; the session-13 re-review moved C12–C14 to (11), whose
# premise holds, and made C4 not-checked, as the written verdict rule requires.)
#
# * **Theorem 1 (C1)** holds, one evaluation: the swept axes (observer poles × basis normalisation
#   × ring order × initial guess × scale of $P$) belong to Section IV's example and do not enter
#   Section II.
# * **Fig. 1 (C3)**: agent 1's own estimate is off by exactly $3a$ in the θ-sum ($\pi$ at the
#   paper's attack), while the resilient estimates keep an offset that does not grow with the attack
#   (the same at $a=\pi/3,\pi,10$ rad): "attack-resilient" read as an error bounded independently of
#   the attack. The offset is $O(1/\gamma)$ and not small at the paper's gains: 0.65 rad (θ-sum,
#   agent 1) at the default point, against the injected $\pi/3=1.05$ rad. The rule reads the θ-sum
#   only; the all-coordinate error (recorded) peaks at 1.2–1.3 rad after the attack and settles,
#   on a run of 60 s, at the same 0.217 rad at every attack size. (Over 35–40 s the largest attack's
#   was still a transient, 0.370 rad, which earlier versions read as growth with the attack.)
# * **Theorem 2 (C4) is not checked.** Theorem 2 promises $\limsup\|\hat x_i-x\|_\infty\le\eta$
#   only for $\kappa>\kappa^*$, $\gamma>\gamma^*$; the theorem only says $\kappa^*$ exists, and the one
#   value the paper gives (its proof's) is sufficient and at least $Nn\sqrt n\,\|\bar A\|\,V(0)\approx
#   1.8\cdot10^4$ at the default point (recorded at every point: C4's headline), against the example's
#   $\kappa=0.5$. So κ = 0.5 is not shown to meet the premise (C4a, recorded: fails-premise, not
#   deciding), and the gains that are shown to meet it cannot be integrated here (one sign step would
#   move $\hat x_i$ by about 15 rad in the ∞-norm at $dt=10^{-3}$): C4 decides as not-checked. What is measured at
#   $\kappa=0.5$ is ours (**X9**, not deciding): the error under attack falls like $1/\gamma$
#   (log–log slopes ≈ −1.0 between γ = 2, 5, 20, the rule ≤ −1/2), while the non-resilient
#   averaging baseline, which also decreases, flattens (slopes −0.19, −0.09). C5 (convergence
#   without attack) does not decide on the same ground.
# * **Theorem 3 (C8)**: the error of (11) stays below the bound (≈ 199 at γ = 2) at the example's
#   attack and at the large attacks of C7b (240–1922 rad), where a non-resilient estimator exceeds it.
#   The scale of $P$ in (11) is MISSING (any $cP$ will do) and swept: it changes (11)'s effective gain,
#   the bound, C7's premise and C7b's attack sizes.
# * **Attack identification (C7, C7b, C7c; none decides).** The paper says each agent finds, by
#   comparing $z_i$ with $\mathcal W_i\hat x_i$, whether it is corrupted "by the effective attack"
#   (Sec. III-C, for (11)). It gives no threshold and does not define "effective". With a threshold
#   we assemble from its bounds, $\theta=(Nn^2+\sqrt n)\sqrt N/(\gamma\lambda_2)\approx148$ at
#   $\gamma=2$, an attack is guaranteed to show only if its effect exceeds $2\theta$ (*our reading of
#   "effective"*). The example's $\pi/3$ has an effect of about 1.6: C7 fails its premise at every
#   point. At effective attacks (1.25, 2 and 10 times the smallest, ≈ 192 rad) no clean agent flags
#   itself (C7b, measured), while the averaging baseline put through the same rule flags clean
#   agents; agent 1's own flag is true by construction of the attack sizes (C7c). C7b does not
#   decide (session-13 review of issue #30): its measured part is C8's bound read in (11)'s
#   coordinates on the same runs, its other half is by construction, and our reading of "effective"
#   was adopted after outcomes were known; identification rests on C8's bound. Under the plain
#   reading (the Conclusion without "effective") no agent-local rule from the paper's bounds
#   identifies the example's attack (recorded in C7).
# * **Plug-and-play (C12, C13, C14), with (11), Sec. III-C's plug-and-play method.** Sec. III-C
#   says the plug-and-play operation "noted in the Introduction" becomes easy for Lyapunov-stable
#   plants with (11) (Theorem 3: any κ, γ > 0, any initial condition). The example's plant is
#   Lyapunov stable and $\bar P$ block-diagonal (C8's premise), so the events are run with (11) at
#   κ = 0.5, γ = 2 and decide (since the session-13 re-review). Eventual recovery holds: agents
#   1, 2, 4 re-initialised at 20 s with arbitrary states (C12), and agent 4 leaving for 5 s and
#   rejoining with an arbitrary state (C13), are back at the uninterrupted run's steady error within
#   our 45 s window (worst ratios 2.4e-4 and 3.8e-4 of the allowance; the window was set in round 3 of
#   issue #30 after a 15 s window had failed with (6)). Not "seamlessly" (C14, the Introduction's
#   word): with (11) the re-initialisation drives the untouched agents 3 and 5 to errors of about
#   25 rad in the next 5 s (0.02 and 0.18 uninterrupted) and agent 4's return drives the others to
#   5–11 rad (ratio up to about 1.2e3). C14's rule is ours, written in the session-13 review after that
#   review had seen the same disruption with (6); it is applied to (11) unchanged. The (6) runs are
#   kept as X10, X11, X12 (ours, not deciding: outside Theorem 2's premise; the same pattern). Sec.
#   III-C's own gains (γ from our declared $\bar N$ = 5 and $\bar s$ = 0.1 rad, γ ≈ 2.8e4, κ = 1/γ)
#   are recorded too: with κ ≈ 3.6e-5 nothing recovers within the window.
# * **Not deciding, and why**: C5 and C7 (premises: Theorem 2's gains, an effective attack), C7b
#   (rests on C8's bound, above), C6, C7c, C9, C10 and C11 (by construction; C11, footnote 3, fails
#   by construction of a step attack: the innovation of agent 1's observer jumps by $|a|$ at the
#   step and peaks at ≈ 3.2e3 at $t\approx12.9$ s; only the steady state is invisible), C2
#   (structural) and our own claims X1–X12. Read literally, C6 fails for (11) (X6, ours: agent 1's
#   θ-sum offset 0.744 → 0.689 rad for $\kappa$ = 0.5 → 2, and the same at a four times smaller step).
# * **What Fig. 1's details depend on:** the post-attack offsets scale with the basis normalisation
#   (0.65 rad with unit-norm $v_l$, 1.125 rad with the paper's unnormalised $[1,0,1,0,1,0]^\top$),
#   and the literal "near −1" poles leave the network unconverged until ≈ 22 s: X5 (ours) fails
#   exactly where the poles are "near" and the initial guess is off.

# %% tags=["parameters"]
mode = "paper"  # "paper": the full runs; "fast": shorter horizons for the tests (ours)
T = 20.0  # horizon of the Section II demo [s] (ours: Section II has no example)
dt = 1e-3  # explicit Euler step of the Section II solver [s] (ours)
gamma = 5.0  # coupling gain of (4) in the Section II demo (ours)
z = [0.8, 1.3, 0.9, 1.1, 1.6, 0.5, 6.0]  # measured values z_i; agent 7 is the outlier (ours)
s = [1, 1, 1, 1, 1, 0, 1]  # indicators s_i; agent 6 has no measurement (ours)
x0 = [-2.0, 3.0, 0.0, 1.0, -1.0, 4.0, 2.0]  # initial solver states x_i(0) (ours)
settle_fraction = 0.25  # "limsup": max distance over this last fraction of the horizon (ours)
sweep_gammas = [0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0]  # Theorem 1 sweep (ours)
sweep_T = 20.0  # horizon of the sweep [s] (ours)
sweep_z5 = [0.8, 1.3, 0.9, 1.1, 6.0]  # values of the ring-5 case, agent 5 the outlier (ours)
sweep_x05 = [-2.0, 3.0, 0.0, 1.0, -1.0]  # initial states of the ring-5 case (ours)
J_inertia = 0.01  # J1, J2, J3 [kg m^2] (PAPER, Section IV)
b_damping = 0.007  # b1, b2, b3 [N m s/rad] (PAPER)
k_spring = 1.37  # k1, k2 [N m/rad] (PAPER)
u_amplitude = 0.01  # u(t) is u_amplitude * sin(u_frequency t) [N m] (PAPER)
u_frequency = 0.5  # [rad/s] (PAPER)
kappa = 0.5  # gain of the sign correction in (6) (PAPER)
kappa_alt = 2.0  # second kappa of the kappa-independence check C6 (ours)
gamma_ex = 2.0  # coupling gain of (6) (PAPER)
q = 1  # number of corruptible banks (PAPER: "2-redundant observable")
ring_order = [1, 2, 3, 4, 5]  # agents around the ring (MISSING: "ring network")
basis_normalisation = "unit"  # scaling of the basis v_l of Assumption 4: "unit" or "integer" (MISSING)
observer_poles = "near"  # "near" (-1, -1.1, ...) or "shifted" (MISSING: "near -1")
P_scale = 1.0  # scale c of the P of (11), c times T^-T T^-1: any cP solves the Lyapunov inequality (MISSING)
attack_bank = 1  # attacked sensor bank, 1-based (PAPER)
attack_amplitude = 1.0471975511965976  # pi/3 rad (PAPER)
attack_start = 10.0  # [s] (PAPER)
x0_plant = [0.5, 0.0, 0.3, 0.0, 0.1, 0.0]  # plant state x(0) (MISSING)
z0_guess = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # z_i(0) is W_i z0_guess; or N rows, one per agent (MISSING)
xhat0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # x_hat_i(0) of every agent; or N rows, one per agent (MISSING)
T_ex = 40.0  # horizon of the example [s] (ours)
dt_ex = 1e-3  # exponential-Euler step of the example [s] (ours)
record_dt = 0.01  # recording grid [s] (ours)
final_window = 5.0  # steady-state values are averages over the last final_window seconds (ours)
offset_gammas = [2.0, 5.0, 20.0]  # gains of the offset-law check (ours)
amplitude_sweep = [3.141592653589793, 10.0]  # further attack sizes [rad] (ours)
amplitude_T = 60.0  # C3: horizon of the attack-size batch for the all-coordinate error [s] (ours, at least 50 s)
id_attack_factors = [1.25, 2.0, 10.0]  # C7b: attack sizes as multiples of the smallest effective one (ours)
pnp_time = 20.0  # C12, C13: time of the re-initialisation / of the agent's leaving [s] (ours)
pnp_agents = [1, 2, 4]  # C12: the re-initialised agents, 1-based (ours: the attacked one, a clean one observing v1, one not)
pnp_state = [2.0, -1.0, -2.0, 1.0, 3.0, -3.0]  # C12, C13: the arbitrary x_hat_i; z_i is W_i pnp_state (ours)
pnp_K_radius = 3.0  # C12, C13: half-width of the box K of Theorem 2 for the arbitrary states (ours)
pnp_recovery = 45.0  # C12, C13: recovery window, twice the known 22.5 s transient of (5) with "near" poles [s] (ours)
pnp_leave_agent = 4  # C13: the agent that leaves (links removed) and rejoins, 1-based (ours)
pnp_leave_duration = 5.0  # C13: how long it stays away [s] (ours)
pnp_s_bar = 0.1  # Sec. III-C's "prespecified goal of steady-state error" s_bar for its (11) gains [rad] (MISSING)
pnp_N_bar = 5  # Sec. III-C's "upper bound of the number of agents" N_bar for its (11) gains (MISSING)
accuracy_T = 20.0  # horizon of the integrator comparison [s] (ours)
accuracy_ref_dt = 1e-4  # step of the reference solution [s] (ours)
tanh_eps = [1e-3, 1e-2]  # widths of the smoothed sign for RK45 (ours)
stall_T = 0.002  # horizon of the exact-sign RK45 demonstration [s] (ours)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/lee2020"
results_path = "figures/lee2020/claims.json"

# %%
import json
from dataclasses import dataclass

import cvxpy as cp
import matplotlib.pyplot as plt
import matplotlib.ticker as mticker
import networkx as nx
import numpy as np
import scipy.linalg as sla
from IPython.display import Markdown, display
from scipy.integrate import solve_ivp

from secest.core import graphs, systems
from secest.core.validation import ValidationError
from secest.methods import lee2020 as M
from secest.repro import plotting, results, spaces
from secest.repro.literate import show_source

print(results.environment_summary())

run = results.Run("lee2020", globals())
accuracy_T = accuracy_T if mode == "paper" else min(accuracy_T, 4.0)
stall_T = stall_T if mode == "paper" else min(stall_T, 5e-4)
z_vals, s_vals, x_init = np.asarray(z, float), np.asarray(s, float), np.asarray(x0, float)
N = z_vals.size
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)


def require(ok: bool, name: str, message: str) -> None:
    """Raise a one-line ValidationError naming the parameter ``name`` unless ``ok``."""
    if not ok:
        raise ValidationError(f"parameter {name}: {message}")


require(N >= 3 and len(s) == N and len(x0) == N, "z",
        f"z, s and x0 need one entry per agent, at least 3; found {len(z)}, {len(s)}, {len(x0)}")
require(set(s) <= {0, 1} and 1 in s, "s", f"indicators must be 0 or 1 with at least one 1, found {s}")
require(len(sweep_z5) >= 3 and len(sweep_x05) == len(sweep_z5), "sweep_x05",
        f"needs one entry per value of sweep_z5 (at least 3), found {len(sweep_x05)} and {len(sweep_z5)}")
for _name, _vals in (("sweep_gammas", sweep_gammas), ("offset_gammas", offset_gammas),
                     ("tanh_eps", tanh_eps)):
    require(len(_vals) > 0 and min(_vals) > 0, _name, f"needs at least one value, all > 0, found {_vals}")
require(sorted(ring_order) == [1, 2, 3, 4, 5], "ring_order",
        f"must list the agents 1..5 once each, found {ring_order}")
record_every = int(round(record_dt / dt_ex))
require(record_every >= 1 and abs(record_every * dt_ex - record_dt) <= 1e-9 * record_dt, "record_dt",
        f"must be a multiple of dt_ex = {dt_ex:g} s, found {record_dt:g} s")
_ref_every = record_dt / accuracy_ref_dt
require(accuracy_ref_dt <= dt_ex / 2 and abs(_ref_every - round(_ref_every)) <= 1e-9 * _ref_every,
        "accuracy_ref_dt", f"must be <= dt_ex/2 and divide record_dt = {record_dt:g} s, "
        f"found {accuracy_ref_dt:g} s")
require(record_dt <= final_window < T_ex, "final_window",
        f"must lie in [record_dt, T_ex) = [{record_dt:g}, {T_ex:g}) s, found {final_window:g} s")
require(len(amplitude_sweep) > 0 and all(a != 0 and a != attack_amplitude for a in amplitude_sweep),
        "amplitude_sweep", f"needs at least one attack size, none 0 or attack_amplitude, found "
        f"{amplitude_sweep}")
AMPLITUDE_T_MIN = max(50.0, attack_start + 2 * final_window)  # the declared "at least 50 s" (toml)
require(amplitude_T >= AMPLITUDE_T_MIN, "amplitude_T",
        f"needs at least 50 s (the declared minimum: over T_ex = 40 s the error at a = 10 rad was still a "
        f"transient) and two windows of final_window after the attack: >= {AMPLITUDE_T_MIN:g} s, "
        f"found {amplitude_T:g} s")
require(len(id_attack_factors) > 0 and min(id_attack_factors) > 1.0, "id_attack_factors",
        f"needs at least one factor, all > 1 (an effective attack), found {id_attack_factors}")
require(attack_start < T_ex - final_window, "attack_start",
        f"the attack must start before the final window [{T_ex - final_window:g}, {T_ex:g}] s, "
        f"found {attack_start:g} s")

# %% [markdown]
# ## Parameter provenance
#
# Every parameter of the notebook, rendered from `notebooks/lee2020.toml`: its default, its tag
# (PAPER: printed in the paper; MISSING: the paper withholds it; ours: our addition), what it
# admits, the declared space that `make robustness` sweeps and why. The space was fixed from the
# paper's text before any sweep ran (the header of the TOML file states the rule): the two readings
# of "near −1", the two scalings of the basis, the three classes of ring orders that Section IV's
# final remark allows, and the observers' initial guess — $2\times2\times3\times2=24$ points.
# Section II has no numerical example in the paper, so its data are ours; so are the numerical
# settings (steps, horizons, windows) that approximate the paper's continuous-time,
# $t\to\infty$ statements: their adequacy is measured (X1, X3), not swept.
#
# *Cost of the sweep.* Each point is one papermill run with figures off, about 13 s of CPU
# including the kernel start: the 72 points take about 8 minutes on two idle cores (72 × 13 s
# over two). A denser
# design costs in proportion: all ten admissible rings instead of one per class, 240 points
# (≈ 26 minutes); a third initial guess, ×1.5; sampling `kappa` or `gamma_ex` around the paper's
# values would multiply it again (they are printed, so they are not swept).

# %%
display(Markdown(spaces.provenance_markdown("lee2020")))

# %% [markdown]
# Constants of the model that are not parameters:
#
# | item | value | tag | source / reason |
# |---|---|---|---|
# | $A,B,C$ | three-inertia system, $y=[\theta_1,\theta_2,\theta_3,\theta_1-\theta_2,\theta_2-\theta_3]$ | PAPER (IV) | built from `J_inertia`, `b_damping`, `k_spring` |
# | graphs (Section II) | ring and all-to-all, $N=7$; ring $N=5$ in the sweep | ours | Remark 2 discusses exactly these two families |
# | basis $\{v_l\}$ | grouped projected-orthonormal, then scaled by `basis_normalisation` | MISSING (derived) | Assumption 4 only asks for existence; built by `common_basis` below and verified against the $\mathcal U_i$ |
# | $P$ of (11) | $T^{-\top}T^{-1}$, $T$ real modal | MISSING (derived) | $PA+A^\top P\le0$ with $\bar P=V^\top PV$ block-diagonal over the indicator groups; Theorem 3's bound (C8) depends on it |
# | chattering tolerance | $10\,\kappa\,dt\,\|v_l\|$ (θ-sum: $|\mathbf 1_\theta^\top v_l|$; coordinates: $\kappa\,dt$) | ours (fixed before any run) | ten steps of the sign correction of (6); the Section II analogue is $10\,dt$ |
# | explicit-Euler demonstration step | $3\times$ the stability limit of $I+dt\,M$ | ours | the unstable run of X1: at this step the $(1,-2,1)$ mode grows as $e^{0.7t}$, visible within the horizon (at $2\times$ a switching transient masked it) |
#
# Fast mode (tests) shortens the integrator comparison to 4 s and the exact-sign demonstration to
# 0.5 ms, and integrates the figure-only runs with the recording step (up to 10× coarser);
# Section II and the example's claims always run in full.

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
show_source(M.median_set, after="    values = as_matrix")
median_set = M.median_set


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
# Euler, vectorised over agents (and over gains in the sweep). On a sliding surface the Euler
# iterate chatters: each step moves an agent by at most $dt$ through its sign term, so the
# chattering is $O(dt)$ (we allow $10\,dt$ where a value is compared with a limit, X3).


# %%
show_source(M.median_solver, after="    lap = graphs.laplacian")
euler_limit = M.euler_limit


def run_solver(adj: np.ndarray, gain: float) -> tuple[np.ndarray, np.ndarray]:
    """(4) on this notebook's data (z, s, x0, horizon T, step dt); ``dt`` checked by name first."""
    require(dt < euler_limit(adj, gain), "dt", f"{dt:g} s is above the Euler stability limit "
            f"2/(gamma lambda_max(L)) = {euler_limit(adj, gain):.3g} s")
    return M.median_solver(adj, z_vals, s_vals, x_init, gain, T, dt)


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
    t, xs = run_solver(adj, gamma)
    lam2 = graphs.algebraic_connectivity(adj)
    tail = t >= (1.0 - settle_fraction) * T
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
# The paper has no figure for Section II. Shaded: the median set; dashed: the median set widened
# by the Theorem 1 bound. The time axis shows the transient (up to 1.5 times the time after which
# every agent stays within 1 % of the initial spread of its final value); the rest of the horizon
# is flat. Dashed brown: the agent without a measurement ($s_i=0$); black: the outlier (the
# indicated value farthest from the median set, "attacked").


# %%
def settle_time(t: np.ndarray, xs: np.ndarray, frac: float = 0.01) -> float:
    """Last time any agent is farther than frac * (initial spread) from its final-window mean."""
    final = xs[t >= (1.0 - settle_fraction) * t[-1]].mean(axis=0)
    far = np.nonzero(np.abs(xs - final).max(axis=1) > frac * max(np.ptp(xs[0]), 1e-12))[0]
    return float(t[far.max()]) if far.size else 0.0


outlier_dist = np.where(s_vals == 1, distance_to_set(z_vals, lo, hi), -1.0)
outlier = int(np.argmax(outlier_dist)) if outlier_dist.max() > 0 else -1


def solver_style(i: int) -> dict:
    """Label and line style of agent i in Fig. S1 (unmeasured and outlier agents marked)."""
    if s_vals[i] == 0:
        return {"label": f"agent {i + 1} ($s_{{{i + 1}}}=0$: no measurement)", "color": "tab:brown",
                "ls": "--", "lw": 1.4}
    if i == outlier:
        return {"label": f"agent {i + 1} ($z_{{{i + 1}}}={z_vals[i]:g}$: outlier)", "color": "k",
                "lw": 1.6}
    return {"label": f"agent {i + 1}", "color": f"C{i % 10}", "lw": 1.0}


t_zoom = min(T, max(10 * dt, 1.5 * max(settle_time(r["t"], r["x"]) for r in runs.values())))
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 3.4), sharey=True, layout="constrained")
for ax, (name, r) in zip(axes, runs.items(), strict=True):
    view = r["t"] <= t_zoom
    ax.axhspan(lo, hi, color="0.8", label="median set $\\mathcal{M}$")
    ax.axhline(lo - r["bound"], color="0.3", ls="-.", lw=0.9,
               label="$\\mathcal{M}$ ± Theorem 1 bound")
    ax.axhline(hi + r["bound"], color="0.3", ls="-.", lw=0.9)
    for i in range(N):
        ax.plot(r["t"][view], r["x"][view, i], **solver_style(i))
    ax.set_xlim(0.0, t_zoom)
    ax.set_title(f"{name}, N = {N}, γ = {gamma:g}: bound {r['bound']:.3f}")
    ax.set_xlabel(f"time t [s] (first {t_zoom:.2g} s of {T:g} s)")
axes[0].set_ylabel("solver state $x_i(t)$ [–]")
fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=3, fontsize=7)
stride = max(1, int(round(0.01 / dt)))
_ = plotting.save_figure(  # the saved path; shown inline by save_figure
    fig, FIG_DIR, "extra_s1_median_solver",
    data={"t_s": runs["ring"]["t"][::stride],
          **{f"x_{g}": r["x"][::stride] for g, r in runs.items()}},
)

# %% [markdown]
# ## Section II-B — Theorem 1 across graphs and gains
#
# The bound $2\sqrt N/(\gamma\lambda_2)$ against the measured final distance for every gain of
# `sweep_gammas` on three graphs: ring $N=5$ with `sweep_z5`, all $s_i=1$ (the median set is a
# point), and ring and all-to-all $N=7$ with the data above. All gains of one graph run as
# columns of one explicit-Euler recursion ($dt$ below $2/(\gamma\lambda_{\max})$ for every
# $\gamma$, checked).
#
# **Where the agents end (ours).** The equilibria of (4) are the points where
# $0\in s_i\,\mathrm{Sgn}(z_i-x_i)-\gamma(\mathcal Lx)_i$ for every $i$: the optimality condition
# of the convex problem
#
# $$\min_x\ f_\gamma(x)=\sum_i s_i|z_i-x_i|+\tfrac{\gamma}{2}x^\top\mathcal Lx,$$
#
# and (4) is the subgradient flow $\dot x\in-\partial f_\gamma(x)$, which converges to a
# minimiser. The final distances are therefore not just below Theorem 1's bound: they are the
# distances of the minimiser the flow reaches. When $S$ is even $f_\gamma$ can have a segment of
# minimisers (the agents' mean can slide inside $\mathcal M$), and which point the flow reaches
# depends on where it starts; we therefore project the run's final-window mean $\bar x$ onto the
# set of minimisers (one CLARABEL solve of the proximal problem
# $\min_x f_\gamma(x)+\frac{\varepsilon}{2}\|x-\bar x\|^2$, $\varepsilon=10^{-3}$, whose solution tends
# to that projection as $\varepsilon\to0$; the bias is $O(\varepsilon\,\|\bar x-x^*\|/(\gamma\lambda_2))$,
# far below $dt$) and predict the final
# distance as that point's $\max_i\|x^*_i\|_{\mathcal M}$. Claim X3 compares them with the
# simulation within $10\,dt$ (the chattering of explicit Euler is $O(dt)$). At the default data
# the minimisers give closed forms: on ring-5 (one minimiser, $S$ odd) the distance is $0.4/\gamma$
# for $\gamma\ge1$; on the all-to-all graph $1.3/7$ and $0.3/7$ at $\gamma=0.5,1$ and zero from
# $\gamma=2$ on; on ring-7 the minimisers form a segment for $\gamma\ge5$ along which the
# distance grows with the agents' mean, and the flow, arriving from below (mean of $x(0)$ = 1),
# stops at its lower end: $0.6/7$ at $\gamma=5$ and $1/(7\gamma)$ for $\gamma\ge10$. The Euler
# iterate drifts $O(dt)$ into that segment, so at $\gamma=50$, where the value is only $2.9\,dt$,
# measured and projected distances differ by about $1.4\,dt$ — inside the stated bound.


# %%
def minimiser_projection(adj: np.ndarray, values: np.ndarray, indicators: np.ndarray):
    """DPP problem: the minimiser of f_gamma nearest to a point (a proximal step with a large step)."""
    x = cp.Variable(values.size)
    gain, target = cp.Parameter(nonneg=True), cp.Parameter(values.size)
    f = (cp.sum(cp.multiply(indicators, cp.abs(values - x)))
         + gain / 2 * cp.quad_form(x, cp.psd_wrap(graphs.laplacian(adj))))
    prox = cp.Problem(cp.Minimize(f + PROX_WEIGHT / 2 * cp.sum_squares(x - target)))

    def project(gain_value: float, point: np.ndarray) -> np.ndarray:
        """argmin_x f_gamma(x) + (eps/2)||x - point||^2: the projection of ``point`` onto argmin f."""
        gain.value, target.value = gain_value, point
        prox.solve(solver=cp.CLARABEL)
        if prox.status != cp.OPTIMAL:
            raise RuntimeError(f"minimiser of f_gamma: solver status {prox.status}")
        return np.asarray(x.value)

    return project


PROX_WEIGHT = 1e-3
sweep_cases = {
    "ring5": (graphs.ring_graph(len(sweep_z5)), np.array(sweep_z5, float), np.ones(len(sweep_z5)),
              np.array(sweep_x05, float)),
    "ring7": (graphs.ring_graph(N), z_vals, s_vals, x_init),
    "complete7": (graphs.complete_graph(N), z_vals, s_vals, x_init),
}
gam_sweep = np.asarray(sweep_gammas, dtype=float)
sweep = {}
for name, (adj, zc, sc, xc) in sweep_cases.items():
    require(dt < euler_limit(adj, gam_sweep), "dt",
            f"{dt:g} s is above the Euler stability limit of the sweep on {name}, "
            f"{euler_limit(adj, gam_sweep):.3g} s (largest gain {gam_sweep.max():g})")
    lo_c, hi_c = median_set(zc, sc)
    _, xs_all = M.median_solver(adj, zc, sc, xc, gam_sweep, sweep_T, dt)  # (K + 1, N, gains)
    tail = xs_all[int(round((1.0 - settle_fraction) * (xs_all.shape[0] - 1))):]
    dist = distance_to_set(tail, lo_c, hi_c).max(axis=(0, 1))
    x_bar = tail.sum(axis=0) / tail.shape[0]  # summed in time order, one state after another
    project = minimiser_projection(adj, zc, sc)
    x_star = np.column_stack([project(g, x_bar[:, j]) for j, g in enumerate(gam_sweep)])
    lam2 = graphs.algebraic_connectivity(adj)
    sweep[name] = {"distance": dist, "bound": 2 * np.sqrt(zc.size) / (gam_sweep * lam2),
                   "lambda2": lam2, "median": (lo_c, hi_c),
                   "predicted": distance_to_set(x_star, lo_c, hi_c).max(axis=0),
                   "to_minimiser": np.abs(x_bar - x_star).max(axis=0)}
    print(f"{name:>9}: lambda2 = {lam2:.6f}, median set = [{lo_c}, {hi_c}]")
    print("   distance: ", np.round(dist, 4))
    print("   minimiser:", np.round(sweep[name]["predicted"], 4))
    print("   bound:    ", np.round(sweep[name]["bound"], 4))

# %% [markdown]
# One panel per graph, each with its own bound (dashed). Filled circles: measured final distance
# (max over the last quarter of the horizon); open squares: the distance of the minimiser of
# $f_\gamma$ (X3). Distances that are exactly zero (the agents end inside $\mathcal M$) cannot be
# drawn on a log axis: they are marked ▼ (and □) on the lower edge, without connecting lines.

# %%
fig, axes = plt.subplots(1, 3, figsize=(plotting.PAGE_WIDTH, 3.1), sharey=True, layout="constrained")
positive = np.concatenate([np.ravel(r[k]) for r in sweep.values() for k in ("distance", "predicted",
                                                                             "bound")])
positive = positive[positive > 1e-9]
floor = 10.0 ** np.floor(np.log10(positive.min())) / 2
for ax, (name, r) in zip(axes, sweep.items(), strict=True):
    ax.loglog(gam_sweep, r["bound"], "k--", lw=1.0, label="Theorem 1 bound 2√N/(γλ₂)")
    nz = r["distance"] > 1e-9
    ax.loglog(gam_sweep[nz], r["distance"][nz], "o-", color="tab:blue", ms=4, label="measured")
    ax.loglog(gam_sweep[~nz], np.full((~nz).sum(), floor), "v", color="tab:blue", ms=6,
              clip_on=False, label="measured = 0 (inside $\\mathcal{M}$)")[0].set_in_layout(False)
    pz = r["predicted"] > 1e-9
    ax.loglog(gam_sweep[pz], r["predicted"][pz], "s", mfc="none", color="tab:orange", ms=7,
              label="minimiser of $f_\\gamma$ (X3)")
    ax.loglog(gam_sweep[~pz], np.full((~pz).sum(), floor), "s", mfc="none", color="tab:orange",
              ms=9, clip_on=False)[0].set_in_layout(False)
    ax.set_ylim(floor, positive.max() * 2)
    ax.set_title(f"{name}: λ₂ = {r['lambda2']:.3f}")
    ax.set_xlabel("coupling gain γ [–]")
axes[0].set_ylabel(r"final $\max_i\|x_i\|_{\mathcal{M}}$ [–]")
fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=2, fontsize=7)
_ = plotting.save_figure(  # the saved path; shown inline by save_figure
    fig, FIG_DIR, "extra_theorem1_gamma_sweep",
    data={"gamma": gam_sweep, **{f"distance_{g}": r["distance"] for g, r in sweep.items()},
          **{f"minimiser_{g}": r["predicted"] for g, r in sweep.items()},
          **{f"bound_{g}": r["bound"] for g, r in sweep.items()}},
)

# %% [markdown]
# The distance falls roughly as $1/\gamma$ and stays far below the bound (the bound adds a worst
# case for the disagreement and one for the average); on the all-to-all graph the agents end
# exactly inside $\mathcal M$ at intermediate gains (their mean slides inside the interval). Every
# measured distance is that of the minimiser of $f_\gamma$ to within the chattering of the Euler
# iterate. **Remark 2** — $\lambda_2=2(1-\cos(2\pi/N))$ on rings and $\lambda_2=N$ on all-to-all
# graphs — checked against networkx's `algebraic_connectivity` for $N=3,\dots,12$:

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
# computed by `secest.core.systems.unobservable_subspace` with an orthogonal staircase (Krylov
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


show_source(M.real_invariant_subspaces, after="    lam, vec = np.linalg.eig")
try:
    modes = M.real_invariant_subspaces(A)
except ValidationError as exc:
    raise ValidationError(f"parameters J_inertia, b_damping, k_spring: {exc}; our basis "
                          "construction needs distinct eigenvalues") from None
show_source(M.mode_pattern, after="    pattern = np.array(")
pattern = M.mode_pattern(modes, U_sub, banks)  # staircase, cross-checked with PBH
print("banks observing each real mode (rows: modes, columns: banks 1..5)")
for (mu, _), row in zip(modes, pattern, strict=True):
    print(f"  lambda = {mu.real:+.3f}{mu.imag:+.3f}j : {row}")

# %% [markdown]
# **Assumption 2 (2q-redundant observability)** by enumeration of all $\binom{N}{N-2q}$ subsets
# (`secest.core.systems.redundant_observability`). The paper states that $(C, A)$ is
# "2-redundant observable", i.e. $q=1$.

# %%
red = {qq: systems.redundant_observability(A, banks, q=qq) for qq in range(1, (N_banks - 1) // 2 + 1)}
q_max = max((qq for qq, r in red.items() if r.holds), default=0)
for qq, r in red.items():
    failing = [tuple(i + 1 for i in f) for f in r.failing]
    print(f"q = {qq}: {r.n_subsets} subsets of {N_banks - 2 * qq} banks, holds = {r.holds}, "
          f"failing (1-based) = {failing}")

# %% [markdown]
# For $q=2$ every single bank would have to observe the plant; banks 2, 4 and 5 do not: the
# example is $2q$-redundant observable for $q=1$ only (`q_max`), as the paper states.
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
# function refuses, and the brief's fallback (intersecting the $\mathcal U_i$ of bank subsets,
# `intersection_basis` in `secest.methods.lee2020`, which the arena uses) would be needed —
# Appendix B items 4 and 8 show that Assumption 4 can then genuinely fail.
# Any basis satisfying Assumption 4 is admissible, but the sign corrections of (6) move
# $\hat x_i$ along $\kappa v_l$, so the scaling of the $v_l$ changes speed and steady-state offsets.
# The paper does not fix it; Section IV writes the rigid-body span unnormalised,
# $\mathrm{span}\{[1,0,1,0,1,0]^\top,[0,1,0,1,0,1]^\top\}$. Parameter `basis_normalisation`:
# `"unit"` ($\|v_l\|=1$, default) or `"integer"` (every $v_l$ scaled so that its smallest
# nonzero entry is $1$: the paper's two vectors and the integer torsion shapes).


# %%
show_source(M.common_basis, after="    dim = modes[0][1].shape[0]")
show_source(M.check_assumption4, after="    n = V.shape[0]")
show_source(M.normalise_basis, after='    if how == "unit":')
normalise_basis = M.normalise_basis
V_unit, S_ind, T_modal = M.common_basis(modes, pattern)
# verification of Assumption 4 (membership does not depend on the scaling of the v_l)
a4_ok, a4_resid = M.check_assumption4(V_unit, S_ind, U_sub)
banks_per_coord = S_ind.sum(axis=0)
print("basis, 'unit' (columns v_l):")
print(np.round(V_unit, 6))
print("basis, 'integer':")
print(np.round(normalise_basis(V_unit, "integer"), 6))
print("indicators s_i^l (rows: banks, columns: l):")
print(S_ind)
print("Assumption 4 verified:", a4_ok, f"(max membership residual {a4_resid:.1e})")
print("banks per coordinate:", banks_per_coord, f">= 2q+1 = {2 * q + 1} (Lemma 1)")
A_bar_unit = V_unit.T @ A @ V_unit
print("A_bar = W A V ('unit' basis) =")
print(np.round(A_bar_unit, 6))

# %% [markdown]
# The unit basis is $v_1=[1,0,1,0,1,0]/\sqrt3$, $v_2=[0,1,0,1,0,1]/\sqrt3$ (rigid body,
# eigenvalues $0,-0.7$), $v_3,v_4$ the mode shape $(1,0,-1)/\sqrt2$ in angle and rate, and
# $v_5,v_6$ the shape $(1,-2,1)/\sqrt6$. It is orthonormal ($W=V^\top$), and
# $\bar A=WAV=\operatorname{blockdiag}\big(\begin{smallmatrix}0&1\\0&-0.7\end{smallmatrix},
# \begin{smallmatrix}0&1\\-137&-0.7\end{smallmatrix},\begin{smallmatrix}0&1\\-411&-0.7\end{smallmatrix}\big)$.
# The integer basis is the same up to the factors $\sqrt3,\sqrt3,\sqrt2,\sqrt2,\sqrt6,\sqrt6$; its
# $v_1,v_2$ are the paper's $[1,0,1,0,1,0]^\top,[0,1,0,1,0,1]^\top$, and $\bar A$ is the same
# ($\bar A\to D^{-1}\bar AD$ with equal factors inside each $2\times2$ block).
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
# are "near $-1$" (MISSING). `observer_poles="near"` (default): $-1,-1.1,\dots$ (first $o_i$;
# single-output placement needs distinct poles). `"shifted"`: keep the imaginary parts of
# $\operatorname{eig}(\mathcal W_iA\mathcal V_i)$ and move all real parts to $-1$ (real
# eigenvalues to $-1,-1.1$). Gains by pole placement with scipy (`scipy.signal.place_poles`, method YT, as python-control's `place` calls it, on the
# dual pair).
#
# Scaling the basis, $\mathcal V_i\to\mathcal V_iD_i$ with $D_i$ diagonal, maps the pair
# $(\mathcal W_iA\mathcal V_i, C_i\mathcal V_i)$ to a similar one, so the placed gain becomes
# $D_i^{-1}L_i$ and the partial estimates $\mathcal V_iz_i$ do not change: the normalisation acts
# on the median correction of (6) only (checked below). We build all four readings
# (normalisation × poles): the figures compare them, the claims use this run's.


# %%
show_source(M.observer_gains, after="    W = np.linalg.inv(V)")
masks = [S_ind[i] == 1 for i in range(N_banks)]
o_i = np.array([int(m.sum()) for m in masks])


@dataclass(frozen=True)
class Observers:
    """One reading of the design: basis V (columns v_l), W = V^-1, and per bank V_i, W_i, L_i, F_i."""

    V: np.ndarray
    W: np.ndarray
    V_i: list[np.ndarray]
    W_i: list[np.ndarray]
    L: list[np.ndarray]
    F: list[np.ndarray]


def make_observers(normalisation: str, poles: str) -> Observers:
    """Basis, partial-observer matrices and gains L_i of (5) by pole placement for one reading."""
    v_mat = normalise_basis(V_unit, normalisation)
    w_mat = np.linalg.inv(v_mat)  # rows w_l^T: [w_1 ... w_n]^T [v_1 ... v_n] = I
    v_i, w_i = [v_mat[:, m] for m in masks], [w_mat[m] for m in masks]
    gains, closed = M.observer_gains(A, v_mat, S_ind, banks, poles)
    return Observers(v_mat, w_mat, v_i, w_i, gains, closed)


def peak_gain(f: np.ndarray, horizon: float = 20.0, steps: int = 400) -> float:
    """max_t ||exp(F t)||_2 over t = 0, h, ..., horizon (transient peaking of the observer error).

    exp(F k h) = exp(F h)^k: one matrix exponential, then products (each expm of a stiff F
    costs many squarings)."""
    step, power, peak = sla.expm(f * (horizon / steps)), np.eye(f.shape[0]), 1.0
    for _ in range(steps):
        power = power @ step
        peak = max(peak, float(np.linalg.norm(power, 2)))
    return peak


READINGS = [(nrm, p) for p in ("near", "shifted") for nrm in ("unit", "integer")]
# reproduction tolerance (make verify) of figure data from the observers with "near" poles
NEAR_POLES = results.Tolerance(
    rtol=0.05, atol=0.05,
    reason="observers with near-pole gains (up to 1.5e3 at clustered poles: ill-conditioned) amplify "
    "the chattering differences of the sign-driven dynamics: under other BLAS kernels up to 0.017 "
    "late and 1.4 % of the value during the transient peak")
observers = {rd: make_observers(*rd) for rd in READINGS}
this_reading = (basis_normalisation, observer_poles)
obs = observers[this_reading]
V, W, V_i, W_i, L_gain, F_cl = obs.V, obs.W, obs.V_i, obs.W_i, obs.L, obs.F
decomp_resid = max(
    max(np.abs(W_i[i] @ A @ V[:, ~masks[i]]).max(initial=0.0),
        np.abs(banks[i] @ V[:, ~masks[i]]).max(initial=0.0))
    for i in range(N_banks)
)
print("o_i =", o_i, f"; max |W_i A V~_i|, |C_i V~_i| = {decomp_resid:.1e}")
for p in ("near", "shifted"):
    ob = observers[(basis_normalisation, p)]
    print(f"observer_poles = {p!r} (basis {basis_normalisation!r})")
    for i in range(N_banks):
        print(f"  bank {i + 1}: max|L_i| = {np.abs(ob.L[i]).max():9.3f}, "
              f"max Re eig(F_i) = {np.linalg.eigvals(ob.F[i]).real.max():+.3f}, "
              f"peak ||exp(F_i t)|| = {peak_gain(ob.F[i]):9.1f}")
# the partial estimates V_i z_i do not depend on the scaling: V_i L_i is the same for both
invariance = max(np.abs(observers[("unit", p)].V_i[i] @ observers[("unit", p)].L[i]
                        - observers[("integer", p)].V_i[i] @ observers[("integer", p)].L[i]).max()
                 / np.abs(observers[("unit", p)].V_i[i] @ observers[("unit", p)].L[i]).max()
                 for p in ("near", "shifted") for i in range(N_banks))
print(f"max relative |V_i L_i (unit) - V_i L_i (integer)| = {invariance:.1e}")

# %% [markdown]
# The literal "near $-1$" placement pulls the $11.7$ and $20.3$ rad/s modes down to $-1.2\dots-1.5$:
# gains up to $1.5\cdot10^3$ and a transient peak $\|e^{F_it}\|\approx5\cdot10^4$ for banks 1 and 3
# (unit basis; the numbers in $z$-coordinates change with the scaling, $\mathcal V_iz_i$ does not).
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
k_att = attack_bank - 1  # the attacked bank / agent, 0-based


def ring_adjacency(order: list[int]) -> np.ndarray:
    """Adjacency of the ring visiting the 1-based agents in ``order`` (and back)."""
    ring = nx.relabel_nodes(nx.cycle_graph(len(order)), {k: v - 1 for k, v in enumerate(order)})
    return graphs.adjacency(ring)


adj_ex = ring_adjacency(ring_order)
lap_ex = graphs.laplacian(graphs.check_connected(adj_ex))
lam2_ex = graphs.algebraic_connectivity(adj_ex)


show_source(M.network_system, after="    n = A.shape[0]")


def network_system(gains, gain_gamma, v_corr=None, w_corr=None, *, ob=None, gain_kappa=None,
                   lap=None):
    """Matrices M, E_w, E_s, R of the stacked system (1), (5), (6) [or (11) via v_corr, w_corr].

    ``ob`` is the reading (basis and partial observers; this run's by default), ``gains`` its L_i,
    ``gain_kappa`` the kappa of (6) (``kappa`` by default), ``lap`` the Laplacian (the ring's by
    default; C13 removes an agent's links for an interval); the example's A, B and banks.
    """
    ob = obs if ob is None else ob
    gain_kappa = kappa if gain_kappa is None else gain_kappa
    lap = lap_ex if lap is None else lap
    system = M.network_system(A, B, banks, ob.V, S_ind, gains, gain_kappa, gain_gamma, lap,
                              v_corr=v_corr, w_corr=w_corr)
    return system.M, system.E_w, system.E_s, system.R


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
    try:
        arr = np.asarray(value, dtype=float)
    except ValueError:
        arr = np.zeros(0)
    if arr.shape == (n,):
        arr = np.tile(arr, (N_banks, 1))
    require(arr.shape == (N_banks, n), name,
            f"needs {n} numbers or {N_banks} rows of {n}, found shape {arr.shape}")
    return arr


def initial_state(ob: Observers) -> np.ndarray:
    """X(0) = [x(0); z_1(0); ...; z_N(0); x_hat_1(0); ...; x_hat_N(0)] from the parameters.

    z_i(0) = W_i z0_guess[i] (the partial observer (5) started from a state guess) and
    x_hat_i(0) = xhat0[i]; a single length-n vector is used for every agent.
    """
    guesses = per_agent(z0_guess, "z0_guess")
    out = np.zeros(n_state)
    out[:n] = x0_plant
    for i in range(N_banks):
        out[z_start[i] : z_start[i + 1]] = ob.W_i[i] @ guesses[i]
    out[xh0:] = per_agent(xhat0, "xhat0").ravel()
    return out


X_init = initial_state(obs)  # validated once, before any run


show_source(M.sign_correction, after="    s_flat = np.asarray")
phi_sign = M.sign_correction(S_ind)  # s (.) sgn(r): the median correction of (6) / (11)


def phi_linear(r: np.ndarray) -> np.ndarray:
    """s (.) r: the non-resilient averaging baseline (ours)."""
    return s_flat[:, None] * r


def simulate(amplitudes, *, ob=None, gains=None, gain_gamma=None, gain_kappa=None, phi=phi_sign,
             v_corr=None, w_corr=None, step=None, horizon_s=None, method="expeuler", every=None):
    """Run (1), (5), (6) for a batch of attack amplitudes; returns t (K,), X (K, n_state, B).

    Defaults: this run's reading, its gains, gamma_ex, kappa, dt_ex, T_ex; states recorded every
    record_dt (``every`` steps overrides it).
    """
    ob = obs if ob is None else ob
    gains = ob.L if gains is None else gains
    gain_gamma = gamma_ex if gain_gamma is None else gain_gamma
    step = dt_ex if step is None else step
    horizon_s = T_ex if horizon_s is None else horizon_s
    m_mat, e_w, e_s, r_mat = network_system(gains, gain_gamma, v_corr, w_corr, ob=ob,
                                            gain_kappa=gain_kappa)
    amps = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    x_start = np.repeat(initial_state(ob)[:, None], amps.size, axis=1)
    n_steps = int(round(horizon_s / step))
    every = int(round(record_dt / step)) if every is None else every
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
# **Our integrator: exponential Euler** (`secest.core.systems.integrate_switched_linear`,
# `method="expeuler"`). Over each step the exogenous input $w$ is sampled at the midpoint and the
# switching term $\phi(RX_k)$ at the left end, both held, and the linear part is integrated
# exactly: $X_{k+1}=\Phi X_k+\Gamma_ww(t_k+dt/2)+\Gamma_s\phi(RX_k)$ with
# $\Phi=e^{M\,dt}$, $[\Gamma_w,\Gamma_s]=\int_0^{dt}e^{Ms}ds\,[E_w,E_s]$ from one matrix
# exponential (Van Loan). It costs what explicit Euler costs (one matrix–vector product per
# step, all agents and scenarios at once), has no stability limit from the plant, the observers or
# the coupling $\kappa\gamma$, and converges with order one in $dt$ to the Filippov solution.
#
# *Do not:* run explicit Euler above its stability limit (here $dt\approx1.7\cdot10^{-3}$ s); hand
# the exact $\mathrm{sgn}$ to an adaptive solver; or smooth $\mathrm{sgn}$ with an $\varepsilon$
# comparable to the offsets under study. Accuracy comparison below: every method against
# exponential Euler with `accuracy_ref_dt` $=10^{-4}$ s (reference) on the attacked example, at
# this run's reading; explicit Euler also at three times its stability limit (largest step with
# spectral radius of $I+dt\,M$ at most one, computed from $\operatorname{eig}(M)$). The speed side
# of the comparison (including explicit Euler at matched accuracy) is measured in the benchmark
# suite, not here (timings are machine-dependent). For it, the stacked matrices are written to
# `extra_integrator_system.csv` (columns `M[j]`, `E_w[j]`, `E_s[j]` with the indicators folded in,
# `R_T[j]`, `x0`): $\dot X=MX+E_ww(t)+E_s\,\mathrm{sgn}(RX)$ with
# $w=[u(t);\ a_1(t);\dots;a_N(t)]$, the attack on bank `attack_bank` from `attack_start` on.

# %%
acc_amp = [attack_amplitude]
t_acc, X_ref = simulate(acc_amp, step=accuracy_ref_dt, horizon_s=accuracy_T)
xh_ref = unpack(X_ref)["xh"][..., 0]


def deviation_from_ref(t_run: np.ndarray, X: np.ndarray) -> np.ndarray:
    """max_i ||x_hat_i - x_hat_i^ref||_inf on the reference's recording grid (linear interpolation)."""
    xh = unpack(X)["xh"][..., 0].reshape(t_run.size, -1)
    if t_run.size != t_acc.size or np.abs(t_run - t_acc).max() > 1e-9:
        xh = np.column_stack([np.interp(t_acc, t_run, col) for col in xh.T])
    return np.abs(xh.reshape(xh_ref.shape) - xh_ref).max(axis=(1, 2))


m_acc, ew_acc, es_acc, r_acc = network_system(L_gain, gamma_ex)
eig_m = np.linalg.eigvals(m_acc)
moving = np.abs(eig_m) > 1e-9 * np.abs(eig_m).max()
euler_dt_max = float(np.min(-2.0 * eig_m[moving].real / np.abs(eig_m[moving]) ** 2))
dt_unstable = 3.0 * euler_dt_max
label_ours = f"exponential Euler, dt = {dt_ex:g} (ours)"
label_half = f"exponential Euler, dt = {dt_ex / 2:g}"
label_euler = f"explicit Euler, dt = {dt_ex:g}"
label_unstable = f"explicit Euler, dt = {dt_unstable:.2g} (3 × limit: unstable)"
acc_runs = {}
for label, meth, step, every in [
    (label_ours, "expeuler", dt_ex, None),
    (label_half, "expeuler", dt_ex / 2, None),
    (label_euler, "euler", dt_ex, None),
    (label_unstable, "euler", dt_unstable, 1),
]:
    t_m, X_m = simulate(acc_amp, step=step, horizon_s=accuracy_T, method=meth, every=every)
    acc_runs[label] = deviation_from_ref(t_m, X_m)

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
    acc_runs[f"RK45, sgn = tanh(./{eps:g}), rtol = 1e-6"] = deviation_from_ref(
        sol.t, sol.y.T[:, :, None])


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
print(f"{'method':50s} {'RMS dev.':>10s} {'max dev.':>10s}")
for label, (rms, mx) in acc_table.items():
    print(f"{label:50s} {rms:10.2e} {mx:10.2e}")

# %%
rho_euler = {step: float(np.abs(np.linalg.eigvals(np.eye(n_state) + step * m_acc)).max())
             for step in (dt_ex, dt_unstable)}
print(f"explicit-Euler stability limit {euler_dt_max:.4g} s; spectral radius of I + dt M:",
      {f"{k:.3g}": round(v, 6) for k, v in rho_euler.items()})
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 3.6), sharey=True, layout="constrained")
acc_floor = 10.0 ** np.floor(np.log10(max(np.percentile(np.concatenate(
    [d[d > 0] for d in acc_runs.values()]), 1.0), 1e-12)))
acc_top = 10.0 ** np.ceil(np.log10(max(d.max() for d in acc_runs.values())))
for k, (label, d) in enumerate(acc_runs.items()):
    ax = axes[1] if label.startswith("RK45") else axes[0]
    color = "k" if label == label_ours else f"C{k}"
    ax.semilogy(t_acc, np.maximum(d, acc_floor), lw=0.9, color=color, label=label)
axes[1].semilogy(t_acc, np.maximum(acc_runs[label_ours], acc_floor), lw=0.9, color="k",
                 label=label_ours)
axes[0].set_title("fixed-step schemes")
axes[1].set_title("adaptive RK45 with a smoothed sign")
for ax in axes:
    if attack_start <= accuracy_T:
        ax.axvline(attack_start, color="k", lw=0.6, ls=":")
    ax.set_xlabel("time t [s]")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), fontsize=6.5)
axes[0].set_ylabel(r"$\max_i\|\hat x_i-\hat x_i^{\mathrm{ref}}\|_\infty$ [rad, rad/s]")
axes[0].set_ylim(acc_floor, acc_top)
_ = plotting.save_figure(  # the saved path; shown inline by save_figure
    fig, FIG_DIR, "extra_integrator_accuracy",
    data={"t_s": t_acc, **{f"dev[{lab}]": d for lab, d in acc_runs.items()}},
    tolerance={"dev*": results.Tolerance(
        rtol=0.1, atol=0.05,
        reason="deviation of one integration of the sign-driven system from another: a difference of "
        "two chattering trajectories (up to 0.013, or 0.0075 + 10 % of the value, under other BLAS "
        "kernels)")},
)

# %% [markdown]
# Exponential Euler at `dt_ex` tracks the reference about four times more closely than explicit
# Euler at the same step, and halving its step halves the deviation (order one: the deviation is
# chattering on the sliding surfaces). Explicit Euler at three times its stability limit (the
# limit is set by the $-0.35\pm20.27j$ plant mode, $0.7/411\approx1.7\cdot10^{-3}$ s) grows without
# bound: the torque $u$ excites the $(1,-2,1)$ mode, which the scheme amplifies at every step. The $\tanh$
# smoothing with $\varepsilon=10^{-2}$ shifts the sliding offsets.

# %% [markdown]
# ## Section IV — the example with the paper's values
#
# One batched run holds four attack amplitudes on bank `attack_bank` ($\pi/3$ of the paper, the
# sizes of `amplitude_sweep`, and 0) at this run's reading; further runs vary $\gamma$, $\kappa$,
# the reading, and the correction ((6), (11), baseline). The attack is $a(t)=$ amplitude for
# $t\ge$ `attack_start`. Steady-state values are means over the last `final_window` seconds.
#
# **Chattering tolerance (fixed before any run).** On a sliding surface the sign correction of (6)
# moves $\hat x_i$ by $\kappa v_l\,dt$ per step, so a finite-step steady state can differ from
# the Filippov one by a few such steps. Every comparison of a steady-state value with its exact
# prediction below allows ten steps: $10\kappa\,dt$ in the coordinates $w_l^\top(\cdot)$,
# $10\kappa\,dt\max_l|\mathbf 1_\theta^\top v_l|$ on the θ-sum ($\mathbf 1_\theta=[1,0,1,0,1,0]$)
# and $10\kappa\,dt\max_l\|v_l\|_\infty$ in the ∞-norm. The tolerance scales with $\kappa\,dt$ and
# the basis, not with $\gamma$.

# %%
CHATTER_STEPS = 10
theta_sel = np.array([1.0, 0, 1.0, 0, 1.0, 0])  # theta_1 + theta_2 + theta_3


def chatter_tol(v_corr: np.ndarray, gain_kappa: float) -> dict[str, float]:
    """Ten steps of the sign correction kappa v_l dt of (6) (columns v_l of ``v_corr``; V_bar for
    (11)): in the coordinates, on the theta-sum, in the inf-norm."""
    base = CHATTER_STEPS * gain_kappa * dt_ex
    return {"coord": base, "sum": base * float(np.abs(theta_sel @ v_corr).max()),
            "inf": base * float(np.abs(v_corr).max())}


tol = chatter_tol(V, kappa)
amp_batch = [attack_amplitude, *amplitude_sweep, 0.0]
t_ex, X_main = simulate(amp_batch)
sim = unpack(X_main)
last = t_ex >= T_ex - final_window - 1e-9
true_sum = sim["x"][:, :, 0] @ theta_sel
own_k = sim["z"][k_att][..., 0] @ V_i[k_att].T  # the attacked agent's own estimate V_k z_k
err = sim["xh"] - sim["x"][:, None]  # (K, N, n, B)
sum_err = np.einsum("kinb,n->kib", err, theta_sel)
max_err = np.abs(err).max(axis=(1, 2))  # (K, B)
print(f"final window: {t_ex[last][0]:g} ... {t_ex[-1]:g} s; chattering tolerances "
      + ", ".join(f"{k} {v:.2e}" for k, v in tol.items()))
for b, amp in enumerate(amp_batch):
    print(f"amplitude {amp:7.4f}: mean sum offsets {np.round(sum_err[last, :, b].mean(0), 4)}, "
          f"max_i ||x_hat_i - x||_inf = {max_err[last, b].max():.4f}")

# %% [markdown]
# ## Fig. 1 — $\theta_1+\theta_2+\theta_3$, agent 1's own estimate and the resilient estimates
#
# The caption: "the state trajectory $\theta_1+\theta_2+\theta_3$ (black), its estimate obtained by
# agent 1 (red), and its resilient estimate for all agents (blue)". The printed figure is not
# available (OCR text only), so this is checked against the caption and the text. The red curve is
# read as $\mathcal V_1z_1$, the estimate of agent 1's partial observer (5) from its own bank
# ($o_1=n$; our interpretation, Deviations table); the blue curves are the resilient $\hat x_i$ of
# (6). Agent 1 is the attacked agent of the paper (`attack_bank`; the figure follows it).
#
# What the figure's details depend on: the size of the post-attack offsets of the blue curves
# scales with the basis normalisation (θ-sum of $v_1$: $\sqrt3$ for unit norm, 3 for the paper's
# unnormalised span), and the transients before the attack depend on the observer poles. The grid
# shows all four readings; the one this run's claims use is marked.


# %%
def reading_title(rd: tuple[str, str]) -> str:
    """Panel title of one reading, marked when it is this run's."""
    mark = " (this run)" if rd == this_reading else ""
    return f'poles "{rd[1]}", basis "{rd[0]}"{mark}'


fig_every = next(m for m in range(min(record_every, 10), 0, -1) if record_every % m == 0)
fig_step = dt_ex if mode == "paper" else dt_ex * fig_every  # figure-only runs: coarser when fast
grid_runs = {this_reading: (t_ex, unpack(X_main[..., :1]))}
if figures:
    for rd in READINGS:
        if rd not in grid_runs:
            t_g, X_g = simulate([attack_amplitude], ob=observers[rd], step=fig_step)
            grid_runs[rd] = (t_g, unpack(X_g))
    fig, axes = plt.subplots(2, 2, figsize=(plotting.PAGE_WIDTH, 4.8), sharex=True, sharey=True,
                             layout="constrained")
    for ax, rd in zip(axes.ravel(), READINGS, strict=True):
        t_g, sim_g = grid_runs[rd]
        ob = observers[rd]
        ax.plot(t_g, sim_g["xh"][:, :, :, 0] @ theta_sel, color="tab:blue", lw=0.8)
        ax.plot(t_g, sim_g["z"][k_att][..., 0] @ ob.V_i[k_att].T @ theta_sel, color="tab:red",
                lw=1.1)
        ax.plot(t_g, sim_g["x"][:, :, 0] @ theta_sel, color="k", lw=1.0, ls="--")
        ax.axvline(attack_start, color="k", lw=0.6, ls=":")
        ax.set_title(reading_title(rd), fontsize=8, fontweight="bold" if rd == this_reading else None)
    for ax in axes[1]:
        ax.set_xlabel("time t [s]")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$\theta_1+\theta_2+\theta_3$ [rad]")
    handles = [plt.Line2D([], [], color="k", ls="--", label=r"$\theta_1+\theta_2+\theta_3$ (black)"),
               plt.Line2D([], [], color="tab:red",
                          label=f"estimate obtained by agent {attack_bank} (red)"),
               plt.Line2D([], [], color="tab:blue", label="resilient estimates, all agents (blue)")]
    fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=7.5)
    fig.suptitle(f"ring {'-'.join(map(str, ring_order))}, κ = {kappa:g}, γ = {gamma_ex:g}, "
                 f"a = {attack_amplitude:.3f} rad on bank {attack_bank} for t ≥ {attack_start:g} s",
                 fontsize=8.5)
    plotting.save_figure(
        fig, FIG_DIR, "fig1_theta_sum",
        data={"t_s": t_ex, "true_sum": true_sum,
              **{f"{key}[{rd[1]},{rd[0]}]": value for rd in READINGS for key, value in (
                  ("own_sum", grid_runs[rd][1]["z"][k_att][..., 0] @ observers[rd].V_i[k_att].T
                   @ theta_sel),
                  ("resilient_sum", grid_runs[rd][1]["xh"][:, :, :, 0] @ theta_sel))}},
        tolerance={"*near*": NEAR_POLES, "*_sum*": results.SIGN_DRIVEN},
    )


# %% [markdown]
# ## Why agent 1 alone is fooled (footnote 3)
#
# Let $v=[1,0,1,0,1,0]^\top$ (rigid rotation, the kernel of $A$; $=\sqrt3\,v_1$ in the unit
# basis). Then $Av=0$ and $C_1v=1$, so for $t\ge10$: $y_1+a_1=C_1\big(x+a\,v\big)$, and
# $x'=x+a\,v$ is itself a trajectory of the plant ($\dot x'=Ax'+Bu$). Agent 1's data after the
# step are those of an unattacked plant in another state: its partial observer (5) converges to
# $\mathcal W_1x'$ (indeed $-F_1^{-1}L_1a=a\,\mathcal W_1v$ exactly), its innovation returns to zero,
# and its own estimate $\mathcal V_1z_1$ is off by $a\,v$: θ-sum off by $3a=\pi$, every angle by
# $a=\pi/3$. Strictly, this is an output attack along a marginally stable eigenvector of $A$, not
# an invariant-zero ("zero-dynamics") attack. Banks 2 and 3 also observe $v_1$ and are clean, so
# the network out-votes bank 1.
#
# The code follows `attack_bank` $=k$: the argument needs $C_kv\ne0$ (bank $k$ sees the rigid-body
# rotation: banks 1–3, not the difference sensors 4, 5), and Fig. 1's reading of the red curve as a
# full-state estimate needs $o_k=n$ (banks 1 and 3). These are the premises of C3 and C11.

# %%
v_null = sla.null_space(A)[:, 0]
C_k_v = float((banks[k_att] @ v_null)[0])
sees_kernel = abs(C_k_v) > 1e-9 * np.abs(v_null).max()
v_rigid = v_null / C_k_v if sees_kernel else v_null / np.abs(v_null).max()  # C_k v = 1
A_v = float(np.abs(A @ v_rigid).max())
e_unit = -np.linalg.solve(F_cl[k_att], L_gain[k_att][:, 0])  # steady z_k error per unit attack
gain_identity = float(np.abs(e_unit - W_i[k_att] @ v_rigid).max())
z_shift = float(np.abs(sim["z"][k_att][last, :, 0]
                       - (sim["x"][last, :, 0] + attack_amplitude * v_rigid) @ W_i[k_att].T).max())
innov_k = (sim["x"][:, :, 0] @ banks[k_att][0] + np.where(t_ex >= attack_start, attack_amplitude, 0.0)
           - sim["z"][k_att][..., 0] @ (banks[k_att] @ V_i[k_att])[0])
own_pred = attack_amplitude * V_i[k_att] @ e_unit  # steady error of V_k z_k (full state if o_k = n)
own_sum_err = own_k[last] @ theta_sel - true_sum[last]
own_inf_err = np.abs(own_k[last] - sim["x"][last, :, 0]).max(axis=1)
print(f"v = {np.round(v_rigid, 6)}: ||A v|| = {A_v:.1e}, C_{attack_bank} v = "
      f"{float((banks[k_att] @ v_rigid)[0]):g}; |-F^-1 L - W_k v| = {gain_identity:.1e}")
print(f"last {final_window:g} s: |z_k - W_k(x + a v)| <= {z_shift:.1e}, "
      f"|innovation of agent {attack_bank}| <= {np.abs(innov_k[last]).max():.1e}")
print(f"agent {attack_bank}'s own estimate: theta-sum error {own_sum_err.mean():.5f} (predicted "
      f"{theta_sel @ own_pred:.5f}), inf-norm error {own_inf_err.mean():.5f} (predicted "
      f"{np.abs(own_pred).max():.5f})")

# %% [markdown]
# ## The steady-state offset law (ours)
#
# At the paper's gains the resilient estimates do not converge to $x$ after the attack: they keep
# constant offsets. Theorem 2 only promises $\limsup\|\hat x_i-x\|_\infty\le\eta$ for large enough
# $\kappa,\gamma$, so this is consistent with the paper, and the offsets can be predicted exactly.
# In the error coordinates $\bar x_i=W(\hat x_i-x)$ of (7), the partial observers settle at
# $p_i=W\mathcal V_iz_i-Wx$: zero for the clean banks and $p_k=-F_k^{-1}L_ka$ (scattered into bank
# $k$'s coordinates) for the attacked one. Suppose $p$ is nonzero only in coordinates $l$ whose
# column of $\bar A$ vanishes ("static" coordinates: here only $l=1$, since $Av_1=0$). Then
# constant offsets $c_i$ supported on those coordinates are an equilibrium of (7) iff, per
# coordinate,
#
# $$0\in s_i^l\,\mathrm{Sgn}(p_i^l-c_i^l)-\gamma(\mathcal Lc^l)_i\quad\forall i
# \iff c^l\in\arg\min_c\ \sum_i s_i^l|p_i^l-c_i|+\tfrac{\gamma}{2}c^\top\mathcal Lc,$$
#
# the optimality condition of a Laplacian-regularised median (the scalar solver (4) with values
# $p^l$, indicators $s^l$ and gain $\gamma$). **$\kappa$ drops out** — the paper's own remark after
# Theorem 3, "the steady-state error depends only on the parameter $\gamma$", read literally (X6; the
# paper means the bound, C6). On the ring
# 1–2–3–4–5–1 with $s^1=(1,1,1,0,0)$ and an attack on bank 1: agents 2 and 3 slide on $c=0$ with
# equivalent signs $-3/4$ and $-1/4$, agent 1 is saturated ($+1$), and the Laplacian rows give
#
# $$c^1=\frac1\gamma\big[\tfrac34,\,0,\,0,\,\tfrac14,\,\tfrac12\big]\quad(\text{valid while } p_1^1>\tfrac3{4\gamma}),$$
#
# independent of the attack size and of the basis scaling (in coordinates), with θ-sum offsets
# $(\mathbf 1_\theta^\top v_1)\,c^1$: $\sqrt3\,c^1$ for the unit basis, $3\,c^1$ for the paper's
# unnormalised $v_1$ (0.65 and 1.125 rad for agent 1 at $\gamma=2$). The identification residual of
# the attacked agent tends to $p_1^1-c_1^1=a\,w_1^\top v-\frac3{4\gamma}$ ($a\sqrt3-\frac3{4\gamma}$ in
# the unit basis). We compute the prediction for every reading with cvxpy (CLARABEL) and compare
# it with the hand formula and the simulation. The **averaging baseline** has the quadratic
# counterpart $(\gamma\mathcal L+D_s)c^l=D_sp^l$, $D_s=\operatorname{diag}(s^l)$: offsets
# proportional to $a$, tending to $p$ for every agent as $\gamma\to\infty$ — the attack is averaged
# in, not rejected. If $p$ reaches a coordinate with a nonzero column of $\bar A$ (an attack on a
# difference sensor, bank 4 or 5), this closed form does not apply: the premise of C4 and X7.

# %%
A_bar = W @ A @ V
static = np.abs(A_bar).max(axis=0) <= 1e-9 * np.abs(A_bar).max()  # columns of A_bar that vanish
_p_par, _s_par = cp.Parameter(N_banks), cp.Parameter(N_banks, nonneg=True)
_g_par = cp.Parameter(nonneg=True)
_c_var, _abs_var = cp.Variable(N_banks), cp.Variable(N_banks)  # c and |p - c|
_median_problem = cp.Problem(
    cp.Minimize(_s_par @ _abs_var + _g_par / 2 * cp.quad_form(_c_var, cp.psd_wrap(lap_ex))),
    [_abs_var >= _p_par - _c_var, _abs_var >= _c_var - _p_par],
)  # DPP: compiled once, re-solved for every p, s and gamma
if not _median_problem.is_dcp(dpp=True):
    raise RuntimeError("the median equilibrium problem is not DPP")


def attack_effect(ob: Observers, amp: float) -> np.ndarray:
    """p (N, n): steady-state w_l^T(V_i z_i - x) in the coordinates bank i observes, attack amp on k."""
    p = np.zeros((N_banks, n))
    p[k_att, masks[k_att]] = amp * -np.linalg.solve(ob.F[k_att], ob.L[k_att][:, 0])
    return p


def law_applies(ob: Observers, amp: float) -> bool:
    """Premise of the offset law: the attack's effect p lies in static coordinates only."""
    p = attack_effect(ob, amp)
    reached = np.abs(p).max(axis=0) > 1e-9 * max(np.abs(p).max(), 1e-300)
    return bool(np.all(static[reached]))


def median_equilibrium(p_col: np.ndarray, s_col: np.ndarray, gain_gamma: float) -> np.ndarray:
    """argmin_c sum_i s_i |p_i - c_i| + (gamma/2) c^T L c on the example ring (CLARABEL)."""
    _p_par.value, _s_par.value, _g_par.value = p_col, s_col, gain_gamma
    _median_problem.solve(solver=cp.CLARABEL)
    if _median_problem.status != cp.OPTIMAL:
        raise RuntimeError(f"median equilibrium: solver status {_median_problem.status}")
    return np.asarray(_c_var.value)


def offset_law(ob: Observers, amp: float, gain_gamma: float, *, baseline: bool = False) -> dict:
    """Predicted steady state under a constant attack amp: offsets c (N, n) in coordinates, and
    the theta-sum offsets, max_i ||x_hat_i - x||_inf and residuals ||z_i - W_i x_hat_i||_inf.

    Per static coordinate: the regularised median (6) or, with ``baseline``, the linear
    equilibrium (gamma L + D_s) c = D_s p of the averaging baseline. Zero elsewhere.
    """
    p = attack_effect(ob, amp)
    c = np.zeros((N_banks, n))
    for ll in np.nonzero(static & (np.abs(p).max(axis=0) > 0))[0]:
        s_col = S_ind[:, ll].astype(float)
        c[:, ll] = (np.linalg.solve(gain_gamma * lap_ex + np.diag(s_col), s_col * p[:, ll])
                    if baseline else median_equilibrium(p[:, ll], s_col, gain_gamma))
    resid = np.array([np.abs(p[i, masks[i]] - c[i, masks[i]]).max() for i in range(N_banks)])
    return {"c": c, "sum": c @ ob.V.T @ theta_sel, "inf": float(np.abs(c @ ob.V.T).max()),
            "resid": resid}


def steady_state(sim_r: dict, ob: Observers, b: int = 0) -> dict:
    """Measured last-window theta-sum offsets (mean), max ||x_hat_i - x||_inf (max), residuals (mean)."""
    e = sim_r["xh"][..., b] - sim_r["x"][:, None, :, b]
    resid = np.stack([np.abs(sim_r["z"][i][..., b] - sim_r["xh"][:, i, :, b] @ ob.W_i[i].T).max(1)
                      for i in range(N_banks)], axis=1)
    return {"sum": (e[last] @ theta_sel).mean(axis=0), "inf": float(np.abs(e[last]).max()),
            "resid": resid[last].mean(axis=0), "resid_t": resid}


law_premise = law_applies(obs, attack_amplitude)
gammas_law = sorted({*map(float, offset_gammas), float(gamma_ex)})
law_runs = {(basis_normalisation, float(gamma_ex), float(kappa)): steady_state(sim, obs)}
for g in gammas_law:
    if g != gamma_ex:
        law_runs[(basis_normalisation, g, float(kappa))] = steady_state(
            unpack(simulate([attack_amplitude], gain_gamma=g)[1]), obs)
law_pred = {g: offset_law(obs, attack_amplitude, g) for g in gammas_law}
law_dev = {g: float(np.abs(law_runs[(basis_normalisation, g, float(kappa))]["sum"]
                           - law_pred[g]["sum"]).max()) for g in gammas_law}
law_inf_dev = {g: abs(law_runs[(basis_normalisation, g, float(kappa))]["inf"] - law_pred[g]["inf"])
               for g in gammas_law}
print(f"offset law applies (p in static coordinates {np.nonzero(static)[0] + 1}): {law_premise}")
for g in gammas_law:
    meas = law_runs[(basis_normalisation, g, float(kappa))]
    print(f"gamma = {g:5g}: theta-sum offsets predicted {np.round(law_pred[g]['sum'], 4)}, "
          f"measured {np.round(meas['sum'], 4)}; max error predicted {law_pred[g]['inf']:.4f}, "
          f"measured {meas['inf']:.4f}")
if list(ring_order) == [1, 2, 3, 4, 5] and attack_bank == 1 and law_premise:
    hand = np.array([0.75, 0.0, 0.0, 0.25, 0.5]) / gamma_ex  # gamma * c for the natural ring
    print("cvxpy vs the hand formula c = [3/4, 0, 0, 1/4, 1/2]/gamma: "
          f"{np.abs(law_pred[gamma_ex]['c'][:, 0] - hand).max():.1e}")

base_t, X_base = simulate(amp_batch[:-1], phi=phi_linear)
base = unpack(X_base)
base_sum_err = np.einsum("kinb,n->kib", base["xh"] - base["x"][:, None], theta_sel)
amp_offsets = {amp: sum_err[last, :, b].mean(axis=0) for b, amp in enumerate(amp_batch[:-1])}
amp_pred = {amp: offset_law(obs, amp, gamma_ex)["sum"] for amp in amp_batch[:-1]}
base_offsets = {amp: base_sum_err[last, :, b].mean(axis=0) for b, amp in enumerate(amp_batch[:-1])}
base_pred = {amp: offset_law(obs, amp, gamma_ex, baseline=True)["sum"] for amp in amp_batch[:-1]}
amp_dev = max(float(np.abs(amp_offsets[a] - amp_pred[a]).max()) for a in amp_offsets)
for amp in amp_batch[:-1]:
    print(f"a = {amp:7.4f}: median offsets {np.round(amp_offsets[amp], 4)} (predicted "
          f"{np.round(amp_pred[amp], 4)}); baseline {np.round(base_offsets[amp], 4)} "
          f"(predicted {np.round(base_pred[amp], 4)})")
# %% [markdown]
# **The errors behind Fig. 1 (ours).** The θ-sum error $\mathbf 1_\theta^\top(\hat x_i-x)$ of every
# agent from two seconds before the attack on, for the median observer (6) and for the averaging
# baseline (sgn replaced by its argument), at this run's reading. Dotted: the offsets predicted by
# the offset law below. Colours are per agent (none is the blue or red of Fig. 1); markers tell
# apart agents whose curves coincide.

# %%
AGENT_COLORS = ["tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:olive"]
AGENT_MARKERS = ["o", "s", "^", "D", "v"]


def agent_style(i: int, n_points: int) -> dict:
    """Colour, marker and staggered marker positions of agent i (curves that coincide stay apart)."""
    spacing = max(1, n_points // 8)
    return {"color": AGENT_COLORS[i % 5], "marker": AGENT_MARKERS[i % 5], "ms": 4,
            "markevery": (i * spacing // N_banks, spacing)}




view = t_ex >= max(0.0, attack_start - 2.0)
fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 3.2), sharey=True, layout="constrained")
for ax, (title, errs, preds) in zip(axes, [
    ("median observer (6)", sum_err[view, :, 0], amp_pred[attack_amplitude]),
    ("averaging baseline (ours)", base_sum_err[view, :, 0], base_pred[attack_amplitude]),
], strict=True):
    for i in range(N_banks):
        ax.plot(t_ex[view], errs[:, i], lw=1.0, label=f"agent {i + 1}",
                **agent_style(i, int(view.sum())))
        ax.axhline(preds[i], color=AGENT_COLORS[i % 5], lw=0.8, ls=":")
    ax.axvline(attack_start, color="k", lw=0.6, ls=":")
    ax.set_title(f"{title}, γ = {gamma_ex:g}")
    ax.set_xlabel("time t [s]")
axes[0].set_ylabel("error of the θ-sum [rad]")
axes[1].plot([], [], color="0.3", lw=0.8, ls=":", label="offset law (predicted)")
fig.legend(*axes[1].get_legend_handles_labels(), loc="outside lower center", ncol=6, fontsize=7)
_ = plotting.save_figure(  # the saved path; shown inline by save_figure
    fig, FIG_DIR, "extra_fig1_errors",
    data={"t_s": t_ex[view], "median_sum_error": sum_err[view, :, 0],
          "baseline_sum_error": base_sum_err[view, :, 0]},
    tolerance={"*_sum_error*": NEAR_POLES if observer_poles == "near" else results.SIGN_DRIVEN},
)

# %% [markdown]
# ## Theorem 2 under attack: the error as γ grows
#
# Sec. III-B, the sentence before Theorem 2: "for sufficiently large κ and γ, the distributed
# algorithm (5) and (6) achieves a resilient estimation of $x$ with arbitrary precision"; Theorem 2:
# for every $\eta>0$ there are $\kappa^*,\gamma^*$ with $\limsup\|\hat x_i-x\|_\infty\le\eta$. The
# paper says neither how large nor at which rate, and its example runs one γ only. At finitely many
# gains (κ = `kappa`, every γ of `offset_gammas` and `gamma_ex`, the example's attack, the runs of
# the offset-law section) C4 measures the **rate**: the log–log slope of the last-window max error
# against γ between consecutive gains.
#
# **Why a rate, and the threshold (ours).** "Arbitrary precision" is an error that tends to 0 as γ
# grows. An error that merely decreases toward a nonzero limit has a log–log slope that tends to 0;
# one that tends to 0 like a power of γ keeps a slope bounded away from 0. A decrease alone does not
# separate the two: the non-resilient averaging baseline (sgn replaced by its argument) also
# decreases at every step, toward the nonzero limit of its offset law (the old rule of C4, "a
# decrease larger than the chattering at every step", was passed by it). We ask for a slope at most
# $-1/2$ at every step: half the rate $-1$ of the paper's own error bounds (Theorem 1,
# $2\sqrt N/(\gamma\lambda_2)$, and Theorem 3, both $\propto1/\gamma$), bounded away from 0 and
# from the bounds' rate alike. The threshold was set in the fourth re-read of issue #30, after a
# reviewer's simulation had given slopes of about −1 (median) and −0.13 (averaging); its value
# comes from the bounds' $1/\gamma$, not from those numbers. The averaging baseline is run at the
# same gains and put through the same rule (the negative control, recorded in C4). A measurement
# precondition: the slopes are taken over the gains whose error exceeds the chattering tolerance
# (below it the slope would measure the integrator); with fewer than two such gains the rule is not
# checked. (Until the session-13 review of issue #30 one gain below the floor made it not checked.)
#
# **Theorem 2's premise is not met at these gains (since the session-13 review of issue #30).**
# Theorem 2 promises $\limsup\|\hat x_i-x\|_\infty\le\eta$ only for $\kappa>\kappa^*$,
# $\gamma>\gamma^*$. The theorem only says that $\kappa^*$ exists; the one value the paper gives is
# its proof's, $\kappa^*=Nn\sqrt n\,\|\bar A\|\,\bar M\,e^{\|\bar A\|T}$ with $\bar M\ge V(0)=
# \|\bar x_{\rm avg}(0)\|$, so $\kappa^*\ge Nn\sqrt n\,\|\bar A\|\,V(0)$: with $\|\bar A\|\approx411$
# (the $(1,-2,1)$ torsion block) this is about $3.0\cdot10^4\,V(0)$, about $1.8\cdot10^4$ at the
# default point (printed below; C4's headline, recorded at every point of the sweep), against the
# paper's $\kappa=0.5$. That value is sufficient, not necessary, so κ = 0.5 is **not shown to meet**
# the premise (C4a, C4 evaluated here, is recorded as fails-premise and does not decide), and C4
# itself is **not checked** (deciding, since the session-13 re-review: the verdict rule's "a
# contribution that cannot be measured here"): the paper's "arbitrary precision" is a statement about
# gains far above the example's, and running
# (6) there is not numerically possible with our integrator (the sign correction would move
# $\hat x_i$ by $\kappa\|v_l\|dt\approx18$ rad per step at $dt=10^{-3}$; with $e^{\|\bar A\|T}$ the
# proof's constant is astronomically larger still). This is the same ground on which C5 does not
# decide. The slope measured at $\kappa=0.5$ is kept as **X9** (ours, not deciding): outside the
# theorem's premise the error under attack still falls like $1/\gamma$.

# %%
c4_gammas = sorted(g for (nrm, g, kap) in law_runs if nrm == basis_normalisation and kap == float(kappa)
                   and g in gammas_law)
c4_err = [law_runs[(basis_normalisation, g, float(kappa))]["inf"] for g in c4_gammas]
c4_steps = [c4_err[m] - c4_err[m + 1] for m in range(len(c4_err) - 1)]  # the old rule's decreases
C4_SLOPE = -0.5  # largest admissible log-log slope (ours: half the 1/gamma rate of the bounds)
# the slopes are taken over the gains whose error exceeds the chattering tolerance only (below it the
# slope would measure the integrator): session-13 review of issue #30; before, one such gain made the
# whole claim not-checked
c4_above = [m for m, e in enumerate(c4_err) if e > tol["inf"]]
c4_g_used = [c4_gammas[m] for m in c4_above]
c4_e_used = [c4_err[m] for m in c4_above]


def v_avg_norm(X_at: np.ndarray) -> float:
    """||x_bar_avg|| = ||mean_i W (x_hat_i - x)|| of one state (n_state,): V in Theorem 2's proof."""
    return float(np.linalg.norm(obs.W @ (X_at[xh0:].reshape(N_banks, n).mean(axis=0) - X_at[:n])))


# Theorem 2's gain premise: kappa > kappa*, which the theorem only says exists; the one value the paper
# gives is its proof's, kappa* = N n sqrt(n) ||A_bar|| M_bar exp(||A_bar|| T) with M_bar >= V(0), so
# kappa* >= N n sqrt(n) ||A_bar|| V(0) (exp >= 1): a lower bound computable from the run
A_bar_norm = float(np.linalg.norm(A_bar, 2))
kappa_star_factor = N_banks * n * np.sqrt(n) * A_bar_norm
kappa_star_lower = kappa_star_factor * v_avg_norm(X_init)
thm2_gains = bool(kappa > kappa_star_lower)
print(f"Theorem 2's kappa* (its proof) >= N n sqrt(n) ||A_bar|| V(0) = {N_banks} * {n} * {np.sqrt(n):.4f} * "
      f"{A_bar_norm:.2f} * {v_avg_norm(X_init):.4f} = {kappa_star_lower:.4g}; kappa = {kappa:g}: the premise "
      f"kappa > kappa* {'may hold' if thm2_gains else 'does not hold'}")


def loglog_slopes(gains: list[float], errors: list[float]) -> list[float]:
    """Slopes d log(error) / d log(gamma) between consecutive gains (nan where an error is <= 0)."""
    return [float(np.log(errors[m + 1] / errors[m]) / np.log(gains[m + 1] / gains[m]))
            if min(errors[m], errors[m + 1]) > 0 else float("nan") for m in range(len(gains) - 1)]


def loglog_fit(gains: list[float], errors: list[float]) -> float | None:
    """Least-squares slope of log(error) against log(gamma) (None with fewer than two gains)."""
    if len(gains) < 2 or min(errors) <= 0:
        return None
    return float(np.polyfit(np.log(gains), np.log(errors), 1)[0])


c4_slopes = loglog_slopes(c4_g_used, c4_e_used)
c4_base_err = [steady_state(unpack(simulate([attack_amplitude], gain_gamma=g, phi=phi_linear)[1]),
                            obs)["inf"] for g in c4_gammas]  # the averaging baseline: negative control
c4_base_slopes = loglog_slopes(c4_g_used, [c4_base_err[m] for m in c4_above])
c4_measurable = bool(len(c4_above) >= 2)
print("gamma:", c4_gammas, " last-window max error:", np.round(c4_err, 4), " gains above the floor "
      f"{tol['inf']:.2g}:", c4_g_used, " log-log slopes:", np.round(c4_slopes, 3), " fit:",
      loglog_fit(c4_g_used, c4_e_used))
print("averaging baseline, same gains: max error", np.round(c4_base_err, 4), " log-log slopes:",
      np.round(c4_base_slopes, 3), " fit:", loglog_fit(c4_g_used, [c4_base_err[m] for m in c4_above]))

# %% [markdown]
# ## Attack identification (Section III-C, Conclusion; Fig. S2, ours)
#
# After the transients each agent compares its partial estimate with its resilient one,
# $\|z_i-\mathcal W_i\hat x_i\|_\infty$. By the offset law it tends to $|p_i^l-c_i^l|$: for the
# attacked agent $a\,w_1^\top v-\frac3{4\gamma}$ ($a\sqrt3-3/(4\gamma)$ in the unit basis), for a
# clean agent its own offset $|c_i^1|$ (zero on the default ring) plus chattering.
#
# **Which rule.** Identification must be decided by each agent from its own residual: "each agent
# can, by comparing their partial estimates $z_i(t)$ with their resilient estimates
# $\mathcal W_i\hat x_i(t)$, find whether their measurement is corrupted by the effective attack or
# not" (Sec. III-C, last paragraph). Comparing residuals *across* agents (is agent 1's the
# largest?) is not a rule any agent can run; we keep that comparison as X7 (ours). The paper
# states its rule for the Lyapunov-stable variant (11) only and gives no threshold; we assemble one
# from the bounds of Theorem 3's proof. That rule, under our reading of the paper's qualifier
# "effective", is C7 (the example's attack: premise fails, does not decide) and C7b (effective
# attacks: measured, rests on C8's bound and does not decide; section after Theorem 3 below). For (6) at the paper's gains the
# paper gives no threshold either. One an agent can compute without knowing the attack is
# Theorem 1's bound applied to the coordinate-1 equilibrium (the scalar solver (4) with values
# $p^1$): $|c_i^1|\le\eta=2\sqrt N/(\gamma\lambda_2)$, so no clean residual exceeds $\eta$ at steady
# state (ours; agent $i$ flags its bank iff its residual exceeds $\eta$). We report what it gives at
# every $\gamma$ of `offset_gammas`. Drawn dashed; the predicted level of the attacked agent dotted.
# The figure shows both pole readings of this run's basis (the poles change the transient, not the
# level).

# %%
eta_id = 2 * np.sqrt(N_banks) / (gamma_ex * lam2_ex)
resid_meas = law_runs[(basis_normalisation, float(gamma_ex), float(kappa))]["resid"]
resid_pred = law_pred[gamma_ex]["resid"]
clean = np.arange(N_banks) != k_att
print("residual over the last window:", np.round(resid_meas, 5))
print("predicted by the offset law:  ", np.round(resid_pred, 5))
print(f"Theorem-1 threshold eta = 2 sqrt(N)/(gamma lambda_2) = {eta_id:.4f}: attacked agent "
      f"{'above' if resid_meas[k_att] > eta_id else 'below'} it")
# the agent-local rule of (6) (ours): agent i flags its bank iff its residual exceeds eta(gamma)
flagged_6 = {}
for g in gammas_law:
    eta_g = 2 * np.sqrt(N_banks) / (g * lam2_ex)
    res_g = law_runs[(basis_normalisation, g, float(kappa))]["resid"]
    flagged_6[f"{g:g}"] = [int(i) + 1 for i in np.nonzero(res_g > eta_g)[0]]
    print(f"gamma = {g:g}: eta = {eta_g:.4f}, residuals {np.round(res_g, 4)}, flagged (1-based) "
          f"{flagged_6[f'{g:g}']}")
gammas_identified = [g for g in gammas_law if flagged_6[f"{g:g}"] == [attack_bank]]
if figures:
    pole_pair = [(basis_normalisation, p) for p in ("near", "shifted")]
    fig, axes = plt.subplots(1, 2, figsize=(plotting.PAGE_WIDTH, 3.3), sharey=True,
                             layout="constrained")
    resid_curves = {}
    for ax, rd in zip(axes, pole_pair, strict=True):
        t_r, sim_r = grid_runs[rd]
        resid_curves[rd] = steady_state(sim_r, observers[rd])["resid_t"]
        for i in range(N_banks):
            ax.semilogy(t_r, resid_curves[rd][:, i], lw=0.9, label=f"agent {i + 1}",
                        **agent_style(i, t_r.size))
        ax.axhline(eta_id, color="k", ls="--", lw=0.9,
                   label=f"threshold η = 2√N/(γλ₂) = {eta_id:.3g} (ours)")
        ax.axhline(resid_pred[k_att], color="k", ls=":", lw=1.4,
                   label=f"predicted level of agent {attack_bank}: {resid_pred[k_att]:.3g}")
        ax.axvline(attack_start, color="k", lw=0.6, ls=":")
        ax.set_title(reading_title(rd), fontsize=8)
        ax.set_xlabel("time t [s]")
    all_res = np.concatenate([r.ravel() for r in resid_curves.values()])
    axes[0].set_ylim(max(all_res[all_res > 0].min(), 1e-8) / 2, all_res.max() * 2)
    axes[0].set_ylabel(r"$\|z_i-\mathcal{W}_i\hat x_i\|_\infty$ [–] (coordinates $w_l^\top\cdot$)")
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=4, fontsize=7)
    plotting.save_figure(fig, FIG_DIR, "extra_identification_residual",
                         data={"t_s": t_ex, **{f"resid_{rd[1]}": r for rd, r in resid_curves.items()}},
                         tolerance={"resid_near*": NEAR_POLES, "resid_shifted*": results.SIGN_DRIVEN})

# %% [markdown]
# ## No attack (Theorem 2 with $a\equiv0$)
#
# With $a\equiv0$ every $p_i\to0$ and the offset law predicts $c=0$: the estimates converge to
# $x$ up to the chattering tolerance.

# %%
err_free = max_err[:, -1]
above = np.nonzero(err_free >= 0.05)[0]
conv_time = (0.0 if not above.size else  # None: still above 0.05 at the end of the horizon
             float(t_ex[above.max() + 1]) if above.max() + 1 < t_ex.size else None)
final_noattack = float(err_free[last].max())
print(f"max_i ||x_hat_i - x||_inf < 0.05 from t = {conv_time} s; final {final_noattack:.1e} "
      f"(tolerance {tol['inf']:.1e})")

# %% [markdown]
# ## Plug-and-play: agents re-initialised with arbitrary states, an agent leaving and rejoining (Introduction, Conclusion)
#
# The Introduction names plug-and-play operation as a merit of the design: "it allows the
# plug-and-play (initialization-free) operation; that is, the observer can perform resilient state
# estimation seamlessly even when some sensor banks or local observers intermittently join or leave
# the network"; the Conclusion: "Since particular initialization is not needed for the algorithm (5)
# and (6) as seen in Theorem 2, the proposed scheme is suitable for the plug-and-play operation; …
# agents can freely join and leave the network during the operation". Theorem 2 is semi-global
# ("for each compact set $K$", with gains above thresholds that depend on $K$), and Sec. III-C's last
# paragraph, on the plug-and-play method for (11), repeats it: "if we additionally assume that the
# initial condition is in some compact set $K$ as in Theorem 2". C12 and C13 test eventual recovery
# (the final-window steady state equals the uninterrupted run's); **C14** tests the Introduction's
# "seamlessly" (since the session-13 review of issue #30; before, the word was quoted but not tested).
#
# **Theorem 2's premise.** The Conclusion rests the plug-and-play claim on Theorem 2 ("as seen in
# Theorem 2"): initialization-free because Theorem 2 holds for every initial condition in a compact
# set $K$, *with gains above thresholds that depend on $K$*. At the example's $\kappa=0.5$ that
# condition is not met (the one $\kappa^*$ the paper gives, its proof's, is at least
# $Nn\sqrt n\,\|\bar A\|\max V\approx10^5$ for a $K$ holding the arbitrary states; the Theorem 2
# section), so with (6) the plug-and-play claims fail their premise. These (6) runs are recorded
# in full as **X10, X11, X12** (ours, not deciding); since the session-13 re-review C12, C13 and
# C14 are decided with (11), Sec. III-C's plug-and-play method, whose Theorem 3 premise the example
# meets (section "Plug-and-play with (11)" below: the same events, states, windows and rules).
#
# **"Seamlessly" (C14).** The paper gives no measure. In its own usage the observer "can perform
# resilient state estimation seamlessly even when some sensor banks or local observers
# intermittently join or leave": the estimation goes on through the event. Our rule: for each event
# (C12's re-initialisation, C13's leaving, C13's rejoining), every agent that is not re-initialised
# and does not leave keeps, over the `final_window` seconds after the event (after the leaving:
# over min(`final_window`, `pnp_leave_duration`), while the agent is away — stated since the
# session-13 re-review; equal at the defaults; its own sample, shared with the uninterrupted run,
# excluded), a max error $\|\hat x_i-x\|_\infty$ within the
# uninterrupted run's over the same times plus twice the chattering tolerance (the allowance of C3,
# C12, C13). **This rule was written after the session-13 review had seen the disruption** (the
# untouched agents 3 and 5 at about 23 rad after C12's re-initialisation, against 0.41 and 0.14
# uninterrupted): it is not a rule declared before its outcome, and at the default point the outcome
# is far from its edge (ratios up to about $10^3$, printed below).
#
# **What we run here.** These checks use (6) at the example's gains ($\kappa=0.5$, $\gamma=2$) and attack,
# not the plug-and-play method of Sec. III-C, which is for (11) with gains chosen from $\bar N$ and
# $\bar s$ (Deviations). The arbitrary states come from Theorem 2's compact set, declared as the box
# $K=\{\|\hat x_i\|_\infty\le$ `pnp_K_radius`$\}$ with $z_i=\mathcal W_i\hat x_i$ (the rest of the
# state is the running system's at that time); the premise checks that `pnp_state` lies in it.
# $K$ is ours (the paper leaves it free): the smallest box that holds `pnp_state` and the plant's
# range. The recovery window `pnp_recovery` (45 s) is ours and was **not** declared before every
# run: it was set in round 3 of the review of issue #30, after C12 had failed with the 15 s window
# that the example's run left (the old reading, recorded), from the transient the notebook already
# knew: with the literal "near −1" poles the partial observers (5) need about 22.5 s to converge
# from the start (the no-attack section; ≈ 4 s with the shifted poles); twice that. Each check runs on its own for `pnp_recovery` + `final_window` after its event, and is
# compared with the uninterrupted run continued over the same times.
#
# * **C12, re-initialised with arbitrary states.** At $t=$ `pnp_time` (after the attack has
#   started) the agents of `pnp_agents` are re-initialised: $\hat x_i=$ `pnp_state`, partial
#   observers restarted at $z_i=\mathcal W_i\,$`pnp_state` (default: the attacked agent 1, agent 2
#   which observes $v_1$, agent 4 which does not). The network does not change.
# * **C13, leaving and rejoining.** At $t=$ `pnp_time` agent `pnp_leave_agent` leaves: its links are
#   removed (its row and column of the adjacency zeroed), for `pnp_leave_duration` s; then they are
#   restored and it returns with the arbitrary state ($\hat x_i=$ `pnp_state`,
#   $z_i=\mathcal W_i\,$`pnp_state`). Premise for the absence: the remaining agents are connected and
#   every coordinate keeps $2q+1$ observing banks among them (the assumptions the paper requires to
#   be maintained). The remaining agents' error during the absence is reported (without the
#   shared sample at `pnp_time`, which until the session-13 review made it equal to the
#   uninterrupted run's by construction).
#
# **Rule of C12 and C13 (ours), the same for both:** after the window, the last-window θ-sum offsets and max error
# equal the uninterrupted run's within twice the chattering tolerance (the tolerance of C3's
# comparison across attack sizes). Headline: the larger of the two ratios measured / allowed (≤ 1:
# holds). The time after which the run stays within 0.05 of the uninterrupted one is reported, and
# for C12 the same re-initialisation of $\hat x_i$ alone (partial observers kept running), which
# separates the transient of (5) from that of (6).

# %%
require(all(1 <= int(i) <= N_banks for i in pnp_agents) and len(set(pnp_agents)) == len(pnp_agents),
        "pnp_agents", f"needs distinct agents among 1..{N_banks}")
require(np.shape(pnp_state) == (n,), "pnp_state", f"needs {n} numbers")
require(1 <= int(pnp_leave_agent) <= N_banks, "pnp_leave_agent", f"needs an agent among 1..{N_banks}")
leave_steps = int(round(pnp_leave_duration / record_dt))
require(leave_steps >= 1 and abs(leave_steps * record_dt - pnp_leave_duration) <= 1e-9,
        "pnp_leave_duration", f"needs a positive multiple of record_dt = {record_dt:g} s")
pnp_xh = np.asarray(pnp_state, dtype=float)
pnp_idx = int(np.argmin(np.abs(t_ex - pnp_time)))
require(0 < pnp_idx and abs(t_ex[pnp_idx] - pnp_time) <= 1e-9 + record_dt / 2
        and t_ex[pnp_idx] > attack_start, "pnp_time",
        f"needs a recorded time in ({attack_start:g}, {T_ex:g}) s (after the attack has started)")
pnp_t0 = float(t_ex[pnp_idx])
pnp_in_K = bool(np.abs(pnp_xh).max() <= pnp_K_radius)


def restart(X_at: np.ndarray, agents) -> np.ndarray:
    """The state X_at with the agents' (0-based) x_hat_i = pnp_state and z_i = W_i pnp_state."""
    out = X_at.copy()
    for i in agents:
        out[z_start[i] : z_start[i + 1]] = obs.W_i[i] @ pnp_xh
        out[xh0 + i * n : xh0 + (i + 1) * n] = pnp_xh
    return out


def run_from(X_start: np.ndarray, t_start: float, horizon_s: float, lap=None, *, v_corr=None, w_corr=None,
             gain_kappa=None, gain_gamma=None):
    """(6) [(11) with v_corr, w_corr] at the example's attack from X_start (n_state, B) at t_start;
    gains: the example's (kappa, gamma_ex) unless given. Returns t (K,), X (K, n_state, B)."""
    m_r, e_w_r, e_s_r, r_r = network_system(obs.L, gamma_ex if gain_gamma is None else gain_gamma, v_corr,
                                            w_corr, gain_kappa=gain_kappa, lap=lap)
    w_r = exogenous([attack_amplitude] * X_start.shape[1])
    out = systems.integrate_switched_linear(
        m_r, e_w_r, lambda t: w_r(t + t_start), e_s_r, r_r, phi_sign, X_start, dt_ex,
        int(round(horizon_s / dt_ex)), record_every=record_every)
    return t_start + np.arange(out.shape[0]) * record_every * dt_ex, out


def final_compare(X_run: np.ndarray, X_ref: np.ndarray, t_run: np.ndarray, t_end: float, tl=None) -> dict:
    """Last-window theta-sum offsets and max error of X_run (K, n_state) against X_ref (chattering
    tolerance ``tl``: this estimator's, (6)'s ``tol`` by default)."""
    tl = tol if tl is None else tl
    win = (t_run >= t_end - final_window - 1e-9) & (t_run <= t_end + 1e-9)
    e_run = X_run[:, xh0:].reshape(-1, N_banks, n) - X_run[:, None, :n]
    e_ref = X_ref[:, xh0:].reshape(-1, N_banks, n) - X_ref[:, None, :n]
    sums, sums_ref = (e_run[win] @ theta_sel).mean(axis=0), (e_ref[win] @ theta_sel).mean(axis=0)
    inf, inf_ref = float(np.abs(e_run[win]).max()), float(np.abs(e_ref[win]).max())
    gap = np.abs(e_run - e_ref).max(axis=(1, 2))
    far_ = np.nonzero(gap > 0.05)[0]
    back = (float(t_run[0]) if not far_.size else
            float(t_run[far_.max() + 1]) if far_.max() + 1 < t_run.size else None)
    d_sum, d_inf = float(np.abs(sums - sums_ref).max()), abs(inf - inf_ref)
    return {"offset_difference": d_sum, "max_error_difference": d_inf,
            "worst_ratio": max(d_sum / (2 * tl["sum"]), d_inf / (2 * tl["inf"])),
            "offsets": sums, "offsets_uninterrupted": sums_ref, "max_error": inf,
            "max_error_uninterrupted": inf_ref, "back_within_0.05_at": back,
            "z_final_distance_from_uninterrupted": max(
                float(np.abs(X_run[win, z_start[i] : z_start[i + 1]]
                             - X_ref[win, z_start[i] : z_start[i + 1]]).max()) for i in range(N_banks))}


# the events' fixed data: who is re-initialised, who leaves, the windows
pnp_ids = [int(j) - 1 for j in pnp_agents]
untouched12 = [i for i in range(N_banks) if i not in pnp_ids]
t12_end = pnp_t0 + pnp_recovery + final_window
t13_ret = pnp_t0 + leave_steps * record_dt
t13_end = t13_ret + pnp_recovery + final_window
ret_idx = int(round((t13_ret - pnp_t0) / record_dt))
old_end = T_ex  # the old reading of C12 (until round 3 of issue #30): the window the example's run left
k_leave = int(pnp_leave_agent) - 1
adj_away = adj_ex.copy()
adj_away[k_leave, :] = 0
adj_away[:, k_leave] = 0
lap_away = graphs.laplacian(adj_away)
rest = [i for i in range(N_banks) if i != k_leave]
rest_connected = bool(nx.is_connected(nx.from_numpy_array(adj_away[np.ix_(rest, rest)])))
rest_banks = S_ind[rest].sum(axis=0)
away_ok = rest_connected and bool((rest_banks >= 2 * q + 1).all())
# C14's window after the leaving: final_window, cut at the return (the absence is pnp_leave_duration)
leave_window = min(float(final_window), leave_steps * record_dt)


def window_error(X_run: np.ndarray, t_run: np.ndarray, agents: list[int], lo: float, hi: float) -> np.ndarray:
    """Per agent (0-based ``agents``): max of ||x_hat_i - x||_inf over recorded t in (lo, hi]."""
    win = (t_run > lo + 1e-9) & (t_run <= hi + 1e-9)
    e = X_run[win][:, xh0:].reshape(-1, N_banks, n)[:, agents] - X_run[win][:, None, :n]
    return np.abs(e).max(axis=(0, 2))


def pnp_events(X_at0: np.ndarray, tl: dict, **est) -> dict:
    """C12's and C13's events from the uninterrupted state X_at0 at pnp_t0 for one estimator (``est``:
    run_from's v_corr, w_corr, gain_kappa, gain_gamma; (6) at the example's gains by default) with its
    chattering tolerance ``tl``: C12's, C13's final-window comparisons and C14's disruption."""
    X_c12 = restart(X_at0, pnp_ids)
    X_c12_xh = X_at0.copy()
    X_c12_xh[xh0:] = X_c12[xh0:]  # x_hat_i alone re-initialised, z_i kept
    t_b, X_b = run_from(np.stack([X_at0, X_c12, X_c12_xh], axis=1), pnp_t0, t13_end - pnp_t0, **est)
    in12, in_old = t_b <= t12_end + 1e-9, t_b <= old_end + 1e-9
    out = {"c12": final_compare(X_b[in12, :, 1], X_b[in12, :, 0], t_b[in12], t12_end, tl),
           "c12_xh": final_compare(X_b[in12, :, 2], X_b[in12, :, 0], t_b[in12], t12_end, tl),
           "c12_old": (final_compare(X_b[in_old, :, 1], X_b[in_old, :, 0], t_b[in_old], old_end, tl)
                       if old_end - final_window > pnp_t0 else None),
           "error_at_restart": float(np.abs(X_c12[xh0:].reshape(N_banks, n) - X_at0[:n]).max())}
    t_away, X_away = run_from(X_at0[:, None], pnp_t0, t13_ret - pnp_t0, lap=lap_away, **est)
    X_ret = restart(X_away[-1, :, 0], [k_leave])  # it returns with the arbitrary state
    t_back, X_back = run_from(X_ret[:, None], t13_ret, t13_end - t13_ret, **est)
    out["c13"] = final_compare(X_back[:, :, 0], X_b[ret_idx:, :, 0], t_back, t13_end, tl)
    # C14: the agents NOT re-initialised / not leaving after each event (its own sample, shared with
    # the uninterrupted run, excluded), against the uninterrupted run over the same times
    events = {"C12: re-initialisation": (untouched12, X_b[in12, :, 1], t_b[in12], X_b[in12, :, 0], t_b[in12],
                                         pnp_t0, pnp_t0 + final_window),
              "C13: leaving": (rest, X_away[:, :, 0], t_away, X_b[: ret_idx + 1, :, 0], t_b[: ret_idx + 1],
                               pnp_t0, pnp_t0 + leave_window),
              "C13: rejoining": (rest, X_back[:, :, 0], t_back, X_b[ret_idx:, :, 0], t_b[ret_idx:],
                                 t13_ret, t13_ret + final_window)}
    out["allow"] = 2 * tl["inf"]  # twice the chattering tolerance over the uninterrupted run's error
    out["seam"] = {}
    for ev, (ag, X_r, t_r, X_u, t_u, lo, hi) in events.items():
        dis, ref = window_error(X_r, t_r, ag, lo, hi), window_error(X_u, t_u, ag, lo, hi)
        out["seam"][ev] = {"agents": [i + 1 for i in ag], "max_error": dis, "max_error_uninterrupted": ref,
                           "ratio": float((dis / (ref + out["allow"])).max())}
    out["seam_worst"] = max(v["ratio"] for v in out["seam"].values())
    out["V_events"] = max(v_avg_norm(X_c12), v_avg_norm(X_ret))  # Theorem 2's V at the arbitrary states
    return out


def print_pnp(name: str, ev: dict, tl: dict) -> None:
    """C12's, C13's and C14's numbers of one estimator."""
    c12, c13 = ev["c12"], ev["c13"]
    print(f"{name} C12: agents {list(pnp_agents)} re-initialised at t = {pnp_t0:g} s (error "
          f"{ev['error_at_restart']:.2f} at the restart); final window ends at {t12_end:g} s: offsets "
          f"{np.round(c12['offsets'], 4)} vs uninterrupted {np.round(c12['offsets_uninterrupted'], 4)} "
          f"(difference {c12['offset_difference']:.2e}, allowed {2 * tl['sum']:.2e}); max error "
          f"{c12['max_error']:.4f} vs {c12['max_error_uninterrupted']:.4f} (difference "
          f"{c12['max_error_difference']:.2e}, allowed {2 * tl['inf']:.2e}); worst ratio {c12['worst_ratio']:.3g}; "
          f"back within 0.05 from t = {c12['back_within_0.05_at']} s")
    print(f"{name} C13: agent {pnp_leave_agent} away {pnp_t0:g}-{t13_ret:g} s, back with x_hat = pnp_state; "
          f"offset difference {c13['offset_difference']:.2e}, max-error difference "
          f"{c13['max_error_difference']:.2e}, worst ratio {c13['worst_ratio']:.3g}; back within 0.05 from "
          f"t = {c13['back_within_0.05_at']} s")
    for e_name, v in ev["seam"].items():
        print(f"{name} C14, {e_name}: agents {v['agents']}: max error {np.round(v['max_error'], 3)} vs "
              f"uninterrupted {np.round(v['max_error_uninterrupted'], 3)}; ratio to the allowance "
              f"(uninterrupted + {ev['allow']:.2g}) {v['ratio']:.3g}")


pnp6 = pnp_events(X_main[pnp_idx, :, 0], tol)
pnp_c12, pnp_c12_xh, pnp_c12_old, pnp_c13 = (pnp6[k] for k in ("c12", "c12_xh", "c12_old", "c13"))
pnp_initial_gap = pnp6["error_at_restart"]
seam, seam_worst, SEAM_ALLOW = pnp6["seam"], pnp6["seam_worst"], pnp6["allow"]
away_max_err = float(seam["C13: leaving"]["max_error"].max())
away_max_err_ref = float(seam["C13: leaving"]["max_error_uninterrupted"].max())
# Theorem 2's gain condition for a compact set K holding the run's initial state and the arbitrary ones
kappa_star_pnp = kappa_star_factor * max(v_avg_norm(X_init), pnp6["V_events"])
thm2_pnp = bool(kappa > kappa_star_pnp)
print_pnp("(6)", pnp6, tol)
print(f"  x_hat_i alone (z_i kept): worst ratio {pnp_c12_xh['worst_ratio']:.3g}"
      + (f"; old reading (window {old_end - final_window - pnp_t0:g} s, to T_ex): worst ratio "
         f"{pnp_c12_old['worst_ratio']:.3g}" if pnp_c12_old is not None else ""))
print(f"  remaining agents connected while agent {pnp_leave_agent} is away: {rest_connected}; banks per "
      f"coordinate among them {rest_banks.tolist()}, need {2 * q + 1}")
print(f"Theorem 2's kappa* for K (its proof) >= {kappa_star_pnp:.4g}; kappa = {kappa:g}")

# %% [markdown]
# ## Variant (11) and Theorem 3
#
# $A$ is Lyapunov stable with distinct eigenvalues; with $T$ the real modal matrix (columns
# $X_k$), $P=c\,T^{-\top}T^{-1}$ satisfies $PA+A^\top P\le0$ for every $c>0$, and
# $\bar P=V^\top PV=c\,(WT)^{-\top}(WT)^{-1}$ is block-diagonal over the indicator groups. **The
# scale $c$ (`P_scale`) is MISSING**: the paper asks only for some $P$, and any $cP$ is one. It is
# not harmless: $\bar V=V\bar P^{-1/2}$ scales by $c^{-1/2}$, so (11)'s correction acts like (6)'s
# with $\kappa/\sqrt c$, Theorem 3's bound scales by $c^{-1/2}$, and the residuals of the
# identification rule (in the coordinates $\sqrt{\bar P}\mathcal W$) by $c^{1/2}$ while its
# threshold $\theta$ does not, which moves C7's premise, C7b's effective size and C8's margin. The
# declared space is $c\in\{1/\lambda_{\max},1,1/\lambda_{\min}\}$ of our $T^{-\top}T^{-1}$: the two
# usual normalisations of a Lyapunov matrix (largest or smallest eigenvalue 1) and ours between them
# (printed below; `notebooks/lee2020.toml`). Theorem 3 bounds
# $\limsup\|\hat x_i-x\|\le(Nn^2+\sqrt n)\sqrt N\,\|V\bar P^{-1/2}\|/(\gamma\lambda_2)$. Scaling the
# basis by factors equal inside each group maps $\bar P\to D\bar PD$ and leaves
# $\bar V=V\bar P^{-1/2}$, the correction of (11) and the bound unchanged (checked).
#
# **What C8 can show here.** The bound is about 199 (at γ = 2) against errors of a few tenths of a
# radian. At the example's attack the non-resilient estimators we also run — the averaging baseline
# at every attack size and agent 1's own estimate $\mathcal V_1z_1$ — stay below it too (their
# largest error, $a\|v\|=10\sqrt3$ at $a=10$, is recorded in C8): there the bound cannot fail. A
# non-resilient error grows linearly with the attack and passes the bound above $a\approx115$ rad;
# C8 is therefore also evaluated at the large attacks of C7b (240–1922 rad at the defaults, next
# section), where the averaging baseline with (11)'s correction exceeds it (recorded). There the
# rule can fail, and C8 decides (until the round-2 review of issue #30 it was evaluated at the
# example's attack only and did not decide).


# %%
show_source(M.lyapunov_correction, after="    W = np.linalg.inv(V)")


def lyapunov_correction(ob: Observers) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """P_bar, P, V_bar, W_bar of (11) for one reading (its basis, the example's modal matrix), with
    P = P_scale T^-T T^-1: P_bar scales by c, V_bar = V P_bar^(-1/2) by c^(-1/2), W_bar by c^(1/2)."""
    p_bar, p_plant, v_bar, w_bar = M.lyapunov_correction(ob.V, T_modal)
    c = float(P_scale)
    return c * p_bar, c * p_plant, v_bar / np.sqrt(c), w_bar * np.sqrt(c)


P_bar, P_plant, V_bar, W_bar = lyapunov_correction(obs)
lyap_max = float(np.linalg.eigvalsh(P_plant @ A + A.T @ P_plant).max())
group_id = np.unique(S_ind.T, axis=0, return_inverse=True)[1].ravel()
offgroup = float(np.abs(P_bar[group_id[:, None] != group_id[None, :]]).max())
offgroup_rel = offgroup / float(np.abs(P_bar).max())  # invariant to P_scale
lyap_ok = lyap_max <= 1e-9 * float(np.abs(P_plant).max())  # PA + A'P <= 0, relative to the scale of P
eig_P1 = np.linalg.eigvalsh(P_plant / P_scale)  # our unscaled P = T^-T T^-1
print(f"P_scale = {P_scale:g}; eigenvalues of T^-T T^-1: {eig_P1.min():.4g} ... {eig_P1.max():.4g}, so "
      f"lambda_max(P) = 1 at P_scale = {1 / eig_P1.max():.4g} and lambda_min(P) = 1 at "
      f"{1 / eig_P1.min():.4g} (the declared space)")
vbar_invariance = max(float(np.abs(lyapunov_correction(observers[(nrm, observer_poles)])[2]
                                   - V_bar).max()) for nrm in ("unit", "integer"))
X_11 = simulate([attack_amplitude], v_corr=V_bar, w_corr=W_bar)[1]
sim_11 = unpack(X_11)
err_11 = sim_11["xh"][..., 0] - sim_11["x"][:, None, :, 0]
sums_11 = (err_11[last] @ theta_sel).mean(axis=0)
maxerr_11 = float(np.abs(err_11[last]).max())
maxerr2_11 = float(np.linalg.norm(err_11[last], axis=2).max())
thm3_bound = ((N_banks * n**2 + np.sqrt(n)) * np.sqrt(N_banks) / (gamma_ex * lam2_ex)
              * np.linalg.norm(V_bar, 2))
print(f"max eig(PA + A^T P) = {lyap_max:.1e}; largest off-group entry of P_bar = {offgroup:.1e}; "
      f"V_bar unit vs integer basis: {vbar_invariance:.1e}")
print(f"(11): theta-sum offsets {np.round(sums_11, 4)}, max ||.||_inf = {maxerr_11:.4f}, "
      f"max ||.||_2 = {maxerr2_11:.4f}, Theorem 3 bound = {thm3_bound:.1f}")

# %% [markdown]
# ## Plug-and-play with (11): Sec. III-C's method (C12, C13, C14)
#
# Sec. III-C: "by considering Lyapunov stable systems the method to allow plug-and-play operation
# noted in the Introduction … become[s] much easy": with (11), Theorem 3 holds "with any $\kappa>0$,
# $\gamma>0$" and any initial condition, "even when some sensor banks or local observers
# intermittently join or leave the network as long as the proposed assumptions are maintained". The
# example's plant is Lyapunov stable and $\bar P$ is block-diagonal over the indicator groups (C8's
# premise), so the Introduction's plug-and-play claims can be tested here **with their premise met**
# (since the session-13 re-review): C12's re-initialisation, C13's leaving and rejoining and C14's
# "seamlessly" are run again with (11) — the same events, agents, times, arbitrary states, windows
# and rules — at the example's gains $\kappa=0.5$, $\gamma=2$, which Theorem 3 allows, with (11)'s
# chattering tolerance (columns of $\bar V$). These runs decide C12, C13 and C14; the (6) runs above
# are kept, recorded and not deciding (X10, X11, X12, ours), because at $\kappa=0.5$ they lie outside
# Theorem 2's premise. Theorem 3 is global: it needs no compact set $K$ (the box `pnp_K_radius` is not
# part of these premises). C14's rule is the one written in the session-13 review after the (6)
# disruption had been seen; it is applied here unchanged.
#
# **Sec. III-C's own gains (recorded variant).** The paper's method takes
# $\gamma=\|\mathcal V\sqrt{\bar P^{-1}}\|\sqrt N(\bar Nn^2+\sqrt n)/(4\bar s/(\bar N^2-N))$ (as
# printed; it mixes $N$ and $\bar N$, read with $\bar N$ throughout — ERRATA — which is the same
# number at $\bar N=N$) and $\kappa=1/\gamma$, from an upper bound $\bar N$ on the number of agents and a goal $\bar s$ for
# the steady-state error. Both are MISSING: `pnp_N_bar` = 5 (the example's network never holds more
# than its five agents; leaving only lowers the count) and `pnp_s_bar` = 0.1 rad (a tenth of the
# example's attack π/3, so that meeting it means the attack is rejected); declared before these runs.
# With them κ is tiny and the sign correction of (11) moves $\hat x_i$ by about $\kappa\|\bar v_l\|$
# per second: its recovery takes far longer than `pnp_recovery`. Recorded, not deciding (in the
# measured dicts of C12–C14).

# %%
require(int(pnp_N_bar) >= N_banks, "pnp_N_bar", f"needs an upper bound on the number of agents (>= {N_banks})")
require(pnp_s_bar > 0, "pnp_s_bar", "needs a positive goal of steady-state error")
tol11 = chatter_tol(V_bar, kappa)
pnp11 = pnp_events(X_11[pnp_idx, :, 0], tol11, v_corr=V_bar, w_corr=W_bar)
print_pnp("(11)", pnp11, tol11)
# Sec. III-C's own gains, in the reading of ERRATA (the OCR mixes N and N_bar; they coincide at N_bar = N):
# gamma = ||V_bar|| sqrt(N_bar) (N_bar^2 - N_bar) (N_bar n^2 + sqrt(n)) / (4 s_bar), since lambda_2 >= 4/(N^2 - N)
gamma_sec3c = (float(np.linalg.norm(V_bar, 2)) * np.sqrt(pnp_N_bar) * (pnp_N_bar**2 - pnp_N_bar)
               * (pnp_N_bar * n**2 + np.sqrt(n)) / (4 * pnp_s_bar))
kappa_sec3c = 1.0 / gamma_sec3c
X_11c = simulate([attack_amplitude], v_corr=V_bar, w_corr=W_bar, gain_kappa=kappa_sec3c,
                 gain_gamma=gamma_sec3c)[1]
tol11c = chatter_tol(V_bar, kappa_sec3c)
pnp11c = pnp_events(X_11c[pnp_idx, :, 0], tol11c, v_corr=V_bar, w_corr=W_bar, gain_kappa=kappa_sec3c,
                    gain_gamma=gamma_sec3c)
print(f"Sec. III-C's gains (N_bar = {pnp_N_bar}, s_bar = {pnp_s_bar:g}): gamma = {gamma_sec3c:.4g}, "
      f"kappa = 1/gamma = {kappa_sec3c:.3g}")
print_pnp("(11), Sec. III-C's gains:", pnp11c, tol11c)


def pnp_variant(ev: dict, cid: str) -> dict:
    """The headline numbers of one recorded estimator for claim ``cid``."""
    return ({"worst_ratio": ev["seam_worst"], **{k: v["ratio"] for k, v in ev["seam"].items()}}
            if cid == "C14" else
            {k: ev["c12" if cid == "C12" else "c13"][k]
             for k in ("worst_ratio", "offset_difference", "max_error_difference", "back_within_0.05_at")})


# %% [markdown]
# ## Attack identification by the paper's own rule (Sec. III-C, last paragraph)
#
# **What the paper states, and under which condition.** For Lyapunov-stable plants, with (11) and
# the plug-and-play gains, each agent can compute a time $T'$ after which
# $V(t)\le Nn\sqrt n\big(\sqrt{Nn}/(\gamma\lambda_2)+2\epsilon\big)$; "from the time after $T'$,
# each agent can, by comparing their partial estimates $z_i(t)$ with their resilient estimates
# $\mathcal W_i\hat x_i(t)$, find whether their measurement is corrupted by **the effective
# attack** or not" (Sec. III-C, last paragraph; the Conclusion repeats it without the qualifier).
# The paper states no threshold for the comparison and does not define "effective". Which parts
# below are the paper's and which are ours:
#
# * **the paper's**: the bounds the comparison rests on — (13) for the disagreement,
#   $\|\tilde x\|\le\sqrt{Nn}/(\gamma\lambda_2)+\epsilon$, and the bound on $V$ after $T'$, which
#   give Theorem 3's bound in the coordinates $\bar x_i=\sqrt{\bar P}\mathcal W(\hat x_i-x)$ of (11);
#   and the condition that the attack be "effective";
# * **ours, the threshold**: assembled from those bounds with $\epsilon\to0$,
#   $\|\bar x_i\|\le\|\bar x_{\rm avg}\|+\|\tilde x\|\le(Nn^2+\sqrt n)\sqrt N/(\gamma\lambda_2)=:\theta$
#   (Theorem 3's bound without the factor $\|\mathcal V\bar P^{-1/2}\|$). A clean agent has
#   $p_i\to0$, so its residual $\max_{l:\,s_i^l=1}|\bar w_l^\top(\mathcal V_iz_i-\hat x_i)|=
#   \max_l|p_i^l-\bar x_i^l|$ (the argument of the sign in (11)) cannot exceed $\theta$: agent $i$ flags
#   its bank iff its residual exceeds $\theta$ — no false alarm, by Theorem 3;
# * **ours, the reading of "effective"**: the comparison can only reveal an attack whose steady
#   effect $p_k$ on the agent's partial estimate (in the same coordinates) stands out of what the
#   bounds allow: the attacked agent's residual is at least $\|p_k\|_\infty-\theta$, so the rule is
#   guaranteed to flag it iff $\|p_k\|_\infty>2\theta$. We call such an attack effective. It is the
#   reading under which the paper's sentence follows from its own bounds; an attack with a smaller
#   effect moves the estimates by no more than the error the paper already guarantees.
#
# **The example's attack is not effective.** At the paper's $\gamma=2$, $\theta\approx148$ (it does
# not depend on the ring order: every five-agent ring has the same $\lambda_2$), while the effect of
# $a_1=\pi/3$ is about 1.6 (printed): the premise of the paper's statement fails at the example,
# and C7 is `fails-premise` there whatever the rule flags (it flags nothing; recorded). It does
# not decide: it can neither hold nor fail anywhere in the space, and the paper claims no
# identification at its example (Sec. IV and Fig. 1 are about estimation). The
# previous reading of C7 (until the session-8 review of issue #30) took the example's attack as
# effective and recorded "fails"; its measurement is kept in C7's record. **C7b** tests the
# paper's statement where its premise holds (it decided until the session-13 review of issue #30;
# why it no longer does, below):
# attacks on bank `attack_bank` of `id_attack_factors` times the smallest effective size
# $a_{\rm eff}=2\theta/\|p_k^{(1)}\|_\infty$ ($p_k^{(1)}$ the effect per unit attack), at the paper's
# gains, with (11), all in one batch (default 1.25, 2, 10: just inside the edge of the premise, where
# the guaranteed margin is smallest — a residual of at least $1.5\theta$ — and well inside it; every
# point of the declared space runs all three). We also print the smallest $\gamma$ at which the paper's own
# $\pi/3$ would be effective ($\theta\propto1/\gamma$).
#
# **What is by construction and what is measured.** Agent 1's flag is true by construction: the
# sizes are $f\,a_{\rm eff}$, so its effect is $2f\theta$ and its residual $2f\theta-|\bar x_1|$
# (about $2\times1.25\,\theta$); it is recorded as **C7c**, by construction, not evidence, and does
# not decide. What is measured is that no *clean* agent is flagged, i.e. that the error of (11) in
# its coordinates stays below $\theta$ at these attack sizes: **C7b** (since the fourth re-read of
# issue #30; before, C7b's rule was "exactly the attacked bank flagged", which mixed the two). C7b
# rests on the same runs as C8's error at these sizes: with C8 it is one piece of evidence.
#
# **Why identification does not decide (session-13 review of issue #30).** Of the two halves of the
# paper's sentence, the attacked agent's flag (C7c) is by construction of the attack sizes, and the
# clean agents' silence (C7b) is C8's bound read in (11)'s coordinates, measured on the same runs;
# the reading of "effective" that makes the sentence testable at all is ours and was adopted after
# the outcomes were known (session 8). Letting C7b decide next to C8 would count one piece of
# evidence twice. The alternative, deciding identification as `not-checked` (a contribution that
# cannot be measured here), would misstate what is measured: its measurable content *is* measured,
# and it is C8's. So C7b is recorded, measured and shown, and does not decide; the identification
# statement rests on C8's bound, which decides. C7b's premise carries the block-diagonal $\bar P$
# condition, as C8's does, since it runs (11) too.
#
# To show that this part can fail, the averaging baseline with (11)'s correction ($\mathrm{sgn}$ replaced by its
# argument; non-resilient, ours) is put through the same rule at the same sizes (printed, recorded).
#
# **Which parts of the rule an agent could not run.** The paper compares $z_i$ with
# $\mathcal W_i\hat x_i$; the rule uses (11)'s coordinates $\sqrt{\bar P}\mathcal W$ (those of the
# sign argument, where the bound is stated); $\theta$ uses the true $N$ and $\lambda_2(\mathcal L)$,
# while an agent knows only $\bar N\ge N$ and $\lambda_2\ge4/(N^2-N)$ (0.2 against 1.382 here); and
# the residual is a mean over the final window, not every $t\ge T'$ (Deviations table). With the
# threshold an agent can compute ($\bar N=N$, $\lambda_2=4/(N^2-N)$: $\approx6.9\,\theta$) the flags
# are printed and recorded too (at the defaults only the ×10 attack is flagged).

# %%
theta_id = thm3_bound / float(np.linalg.norm(V_bar, 2))  # (N n^2 + sqrt n) sqrt N / (gamma lambda_2)


def residuals_11(sim_r: dict, b: int = 0) -> np.ndarray:
    """Mean over the last window of max_{l: s_i^l = 1} |w_bar_l'(V_i z_i - x_hat_i)|, per agent."""
    return np.stack([
        np.abs((sim_r["z"][i][..., b] @ V_i[i].T - sim_r["xh"][:, i, :, b]) @ W_bar.T)[:, masks[i]].max(1)
        for i in range(N_banks)], axis=1)[last].mean(axis=0)


resid_11 = residuals_11(sim_11)
flagged_11 = [int(i) + 1 for i in np.nonzero(resid_11 > theta_id)[0]]
# the attack's steady effect on z_k in the coordinates of (11), per unit attack: sqrt(P_bar) W V_k e
effect_unit_11 = float(np.abs((W_bar @ V_i[k_att] @ e_unit)[masks[k_att]]).max())
effect_example = abs(attack_amplitude) * effect_unit_11
example_effective = bool(effect_example > 2 * theta_id)
a_eff = 2 * theta_id / effect_unit_11 if effect_unit_11 > 0 else float("inf")
gamma_effective = gamma_ex * 2 * theta_id / effect_example if effect_example > 0 else float("inf")
print(f"(11): residuals at the example's attack {np.round(resid_11, 4)}; theta = {theta_id:.1f}; "
      f"flagged (1-based): {flagged_11}")
print(f"effect of the example's attack on z_{attack_bank} in (11)'s coordinates: {effect_example:.4f} "
      f"against 2 theta = {2 * theta_id:.1f}: effective = {example_effective}; smallest effective "
      f"attack a_eff = {a_eff:.1f} rad; the example's a = {attack_amplitude:.4f} rad would be "
      f"effective from gamma = {gamma_effective:.0f} on")
id_amps = [float(f) * a_eff for f in id_attack_factors] if np.isfinite(a_eff) else []
resid_id = np.zeros((0, N_banks))
if id_amps:  # one batch: every factor at once
    sim_id = unpack(simulate(id_amps, v_corr=V_bar, w_corr=W_bar)[1])
    resid_id = np.stack([residuals_11(sim_id, b) for b in range(len(id_amps))])
flagged_id = {f"{f:g}": [int(i) + 1 for i in np.nonzero(r > theta_id)[0]]
              for f, r in zip(id_attack_factors, resid_id, strict=False)}
for f, amp, r in zip(id_attack_factors, id_amps, resid_id, strict=False):
    print(f"a = {f:g} a_eff = {amp:8.1f} rad: residuals / theta {np.round(r / theta_id, 5)}, "
          f"flagged (1-based) {flagged_id[f'{f:g}']}")
# the same rule applied to a non-resilient estimator: the averaging baseline with (11)'s correction
# (sgn replaced by its argument), at the same attack sizes (it shows the rule's measured part can fail)
resid_id_base, err2_id, err2_id_base = np.zeros((0, N_banks)), 0.0, 0.0
if id_amps:
    sim_id_base = unpack(simulate(id_amps, v_corr=V_bar, w_corr=W_bar, phi=phi_linear)[1])
    resid_id_base = np.stack([residuals_11(sim_id_base, b) for b in range(len(id_amps))])
    err2_id = float(np.linalg.norm((sim_id["xh"] - sim_id["x"][:, None])[last], axis=2).max())
    err2_id_base = float(np.linalg.norm((sim_id_base["xh"] - sim_id_base["x"][:, None])[last],
                                        axis=2).max())
flagged_id_base = {f"{f:g}": [int(i) + 1 for i in np.nonzero(r > theta_id)[0]]
                   for f, r in zip(id_attack_factors, resid_id_base, strict=False)}
# the threshold an agent can compute: N_bar >= N (here N_bar = N) and lambda_2 >= 4 / (N_bar^2 - N_bar)
lam2_lower = 4 / (N_banks**2 - N_banks)
theta_agent = (N_banks * n**2 + np.sqrt(n)) * np.sqrt(N_banks) / (gamma_ex * lam2_lower)
flagged_id_agent = {f"{f:g}": [int(i) + 1 for i in np.nonzero(r > theta_agent)[0]]
                    for f, r in zip(id_attack_factors, resid_id, strict=False)}
print(f"averaging baseline through the same rule: flagged (1-based) {flagged_id_base}; "
      f"max ||x_hat_i - x||_2 over the batch: (11) {err2_id:.4g}, baseline {err2_id_base:.4g} "
      f"(Theorem 3 bound {thm3_bound:.1f})")
print(f"agent-computable threshold (lambda_2 >= 4/(N^2 - N) = {lam2_lower:.3g} instead of "
      f"{lam2_ex:.4g}): {theta_agent:.1f} = {theta_agent / theta_id:.2f} theta; flagged {flagged_id_agent}")

# %% [markdown]
# ## The steady-state error depends only on γ (Section III-C)
#
# After the proof of Theorem 3 the paper states: "Since the steady-state error depends only on
# the parameter γ, by increasing γ and decreasing κ, we can achieve arbitrary small steady-state
# error". **The paper's own usage of the term.** Remark 2 calls Theorem 1's *bound* "the
# steady-state error $2\sqrt N/(\gamma\lambda_2(\mathcal L))=2/(\gamma\sqrt N)$"; the plug-and-play
# paragraph that follows Theorem 3 meets "a prespecified goal of steady-state error $\bar s$" by
# choosing the gains so that the *bound* is $\le\bar s$. In the paper, "steady-state error" is the
# guaranteed bound on $\limsup\|\hat x_i-x\|$, and the sentence is about Theorem 3's bound, which
# contains $\gamma$ and not $\kappa$. **C6** records that reading: it holds, by inspection of the
# formula (by construction: not evidence, it does not decide); its measured content, that the
# error stays below the bound, is C8.
#
# **The literal reading (X6, ours).** Read as a statement about the steady state of the error
# itself, the sentence says more than the paper claims, and we test it as our own claim. The offset
# law says it holds for (6) whenever the law applies ($\kappa$ cancels in the equilibrium
# condition). For (11) it has no reason to: the correction $\kappa\bar V\,\mathrm{sgn}(\bar W\cdot)$ mixes the static coordinate
# $v_1$ with the rate coordinate $v_2$ (any admissible $\bar P$ couples them, since
# $\bar P\bar A+\bar A^\top\bar P\le0$ forbids a diagonal $\bar P$ on the rigid-body block), and
# $\bar A$ acts on $v_2$, so $\kappa$ stays in the equilibrium. We rerun the attacked example at
# `kappa_alt` for (6) and for (11) and compare the steady-state θ-sum offsets with those at
# `kappa`, within the chattering tolerance of the larger $\kappa$ (for (11) with the columns of
# $\bar V$). In paper mode the (11) pair is also rerun with a four times smaller step: a difference
# that is chattering shrinks with $dt$, a real dependence on $\kappa$ does not.

# %%
kappa_pair = float(kappa), float(kappa_alt)
tol_k = chatter_tol(V, max(kappa_pair))
tol_k11 = chatter_tol(V_bar, max(kappa_pair))
law_runs[(basis_normalisation, float(gamma_ex), float(kappa_alt))] = steady_state(
    unpack(simulate([attack_amplitude], gain_kappa=kappa_alt)[1]), obs)
sim_11_alt = unpack(simulate([attack_amplitude], v_corr=V_bar, w_corr=W_bar, gain_kappa=kappa_alt)[1])
sums_11_alt = ((sim_11_alt["xh"][..., 0] - sim_11_alt["x"][:, None, :, 0])[last] @ theta_sel).mean(0)
kappa_dev = {
    "(6)": float(np.abs(law_runs[(basis_normalisation, float(gamma_ex), kappa_pair[1])]["sum"]
                        - law_runs[(basis_normalisation, float(gamma_ex), kappa_pair[0])]["sum"]).max()),
    "(11)": float(np.abs(sums_11_alt - sums_11).max()),
}
print(f"kappa = {kappa:g} vs {kappa_alt:g}: max |theta-sum offset difference| (6) "
      f"{kappa_dev['(6)']:.2e} (tolerance {tol_k['sum']:.2e}), (11) {kappa_dev['(11)']:.2e} "
      f"(tolerance {tol_k11['sum']:.2e})")
print(f"(11): theta-sum offsets at kappa = {kappa:g}: {np.round(sums_11, 4)}; at {kappa_alt:g}: "
      f"{np.round(sums_11_alt, 4)}")
fine_dev_11 = None  # X6's second step: the (11) pair at dt_ex / 4 (paper mode, every sweep point)
if mode == "paper":
    fine = [unpack(simulate([attack_amplitude], v_corr=V_bar, w_corr=W_bar, gain_kappa=kap,
                            step=dt_ex / 4)[1]) for kap in kappa_pair]
    fine_sums = [((f["xh"][..., 0] - f["x"][:, None, :, 0])[last] @ theta_sel).mean(0) for f in fine]
    fine_dev_11 = float(np.abs(fine_sums[1] - fine_sums[0]).max())
    print(f"(11) at dt = {dt_ex / 4:g}: agent 1's theta-sum offset {fine_sums[0][0]:.4f} (kappa = "
          f"{kappa:g}) vs {fine_sums[1][0]:.4f} (kappa = {kappa_alt:g}); max difference "
          f"{fine_dev_11:.2e} (tolerance at that step {tol_k11['sum'] / 4:.2e})")

# %% [markdown]
# **The offsets as a map over γ, κ and the basis normalisation.** Lines: the offset law (one per
# agent with a nonzero offset; the same for every κ); filled marks: simulations at `kappa`, open
# marks at `kappa_alt`. Left and middle: the two normalisations (the θ-sum offsets scale with
# $\mathbf 1_\theta^\top v_1$: $\sqrt3$ against 3). Right: the attacked agent's offset against the
# attack size, median (6) against the averaging baseline.

# %%
if figures:
    for nrm in ("unit", "integer"):
        ob = observers[(nrm, observer_poles)]
        for g in gammas_law:
            for kap in kappa_pair:
                if (nrm, g, kap) not in law_runs:
                    law_runs[(nrm, g, kap)] = steady_state(unpack(simulate(
                        [attack_amplitude], ob=ob, gain_gamma=g, gain_kappa=kap, step=fig_step)[1]), ob)
    g_fine = np.geomspace(min(gammas_law) / 1.5, max(gammas_law) * 1.5, 25)
    fig, axes = plt.subplots(1, 3, figsize=(plotting.PAGE_WIDTH, 3.3), layout="constrained",
                             gridspec_kw={"width_ratios": [1, 1, 1.15]})
    axes[1].sharey(axes[0])
    map_data = {"gamma": np.asarray(gammas_law)}
    for ax, nrm in zip(axes[:2], ("unit", "integer"), strict=True):
        ob = observers[(nrm, observer_poles)]
        line = np.array([offset_law(ob, attack_amplitude, g)["sum"] for g in g_fine])
        for i in np.nonzero(np.abs(line).max(axis=0) > 1e-6)[0]:
            ax.loglog(g_fine, np.abs(line[:, i]), color=AGENT_COLORS[i % 5], lw=0.9)
            for kap, (fill, size) in zip(kappa_pair, (("full", 4), ("none", 9)), strict=True):
                meas = np.abs([law_runs[(nrm, g, kap)]["sum"][i] for g in gammas_law])
                map_data[f"offset_{nrm}_kappa{kap:g}[{i}]"] = meas
                ax.loglog(gammas_law, meas, AGENT_MARKERS[i % 5], color=AGENT_COLORS[i % 5],
                          ms=size, fillstyle=fill)
        ax.set_title(f'basis "{nrm}"' + (" (this run)" if nrm == basis_normalisation else ""),
                     fontsize=8)
        ax.set_xlabel("coupling gain γ [–]")
        ax.set_xticks(gammas_law, [f"{g:g}" for g in gammas_law])
        ax.xaxis.set_minor_formatter(mticker.NullFormatter())
    axes[1].tick_params(labelleft=False)
    axes[0].set_ylabel("|θ-sum offset| after the attack [rad]")
    handles = [plt.Line2D([], [], color=AGENT_COLORS[i % 5], marker=AGENT_MARKERS[i % 5],
                          label=f"agent {i + 1}") for i in range(N_banks)
               if np.abs(offset_law(obs, attack_amplitude, gamma_ex)["sum"][i]) > 1e-6]
    handles += [plt.Line2D([], [], color="0.3", label="offset law (any κ)"),
                plt.Line2D([], [], ls="", marker="o", color="0.3", ms=4,
                           label=f"simulated, κ = {kappa_pair[0]:g}"),
                plt.Line2D([], [], ls="", marker="o", color="0.3", ms=9, fillstyle="none",
                           label=f"simulated, κ = {kappa_pair[1]:g}")]
    fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=7)
    ax = axes[2]
    amps = np.array(amp_batch[:-1])
    amp_fine = np.linspace(min(0.0, amps.min()), max(0.0, amps.max()) * 1.05, 22)
    ax.plot(amps, [amp_offsets[a][k_att] for a in amps], "o", color="tab:blue",
            label=f"median (6), agent {attack_bank}")
    ax.plot(amps, [base_offsets[a][k_att] for a in amps], "s", color="tab:red",
            label=f"averaging baseline, agent {attack_bank}")
    ax.plot(amp_fine, [offset_law(obs, a, gamma_ex)["sum"][k_att] for a in amp_fine],
            color="tab:blue", lw=0.8)
    ax.plot(amp_fine, [offset_law(obs, a, gamma_ex, baseline=True)["sum"][k_att] for a in amp_fine],
            color="tab:red", lw=0.8)
    ax.set_xlabel("attack size a [rad]")
    ax.set_ylabel(f"θ-sum offset of agent {attack_bank} [rad]")
    ax.set_title(f"γ = {gamma_ex:g}: law (lines), runs (marks)", fontsize=8)
    ax.legend(fontsize=6.5, loc="upper left")
    plotting.save_figure(fig, FIG_DIR, "extra_offset_law", data=map_data,
                         tolerance={k: results.SIGN_DRIVEN for k in map_data if k.startswith("offset_")})

# %% [markdown]
# ## Final remark of Section IV — no local majority for agent 1
#
# Agent 1 and its ring neighbours observe the rigid-body coordinates $v_1,v_2$ only through the
# banks among 1, 2, 3 in that neighbourhood. On the natural ring (neighbours 2 and 5) these are
# banks 1 and 2: two, fewer than $2q+1=3$, so agent 1 cannot out-vote a corrupted bank from its
# neighbourhood alone. The declared ring orders are exactly those for which the paper's remark
# holds (a ring where agent 1 neighbours both 2 and 3 would give it three observing banks); this
# check confirms the construction.

# %%
nbhd_1 = [0, *np.nonzero(adj_ex[0])[0].tolist()]
local_voters = int(S_ind[nbhd_1, 0].sum())
print(f"agent 1's neighbourhood (1-based): {[i + 1 for i in nbhd_1]}; banks observing v1 in it: "
      f"{local_voters} < 2q+1 = {2 * q + 1}: {local_voters < 2 * q + 1}")

# %% [markdown]
# ## Claims
#
# | id | paper (source) | what we measure, and the rule |
# |---|---|---|
# | C1 | Theorem 1 (Sec. II): every agent ends within $2\sqrt N/(\gamma\lambda_2)$ of $\mathcal M$ | demo (ring, all-to-all) and the γ sweep on ring-5, ring-7, complete-7: max distance over the last quarter ≤ bound (the bound only; the trend in γ is X2, the exact value X3) |
# | C2 | Sec. IV: "$(C,A)$ is 2-redundant observable and satisfies Assumption 4"; Lemma 1 | enumeration for `q`; the constructed basis verified; banks per coordinate ≥ 2q+1 |
# | C3 | Sec. IV on Fig. 1: "It demonstrates the attack-resilient property of our estimation algorithm". Our reading: the own estimate (the caption's "estimate obtained by agent 1") is fooled, the resilient error is bounded independently of the attack (Assumption 1: unbounded $a_i$). Footnote 3 is C11 | premise: bank $k$ sees the full state and the kernel of $A$. Last-window own θ-sum and ∞-norm errors = the exact $\mathcal V_k(-F_k^{-1}L_k)a$ (±0.01 rad, ours), growing as $a$; the resilient θ-sum offsets the same at every attack size ($\pi/3$, `amplitude_sweep`) within twice the chattering tolerance (ours). The offsets themselves ($O(1/\gamma)$; 0.65 rad at the default point) and their ratio to the own error are reported, not a rule; so is the all-coordinate error $\max_i\|\hat x_i-x\|_\infty$ per attack size on a run of `amplitude_T` = 60 s (last window, previous window: settled?, peak after the attack, settling time), which the θ-sum rule does not see; over `T_ex` it is recorded too (at $a=10$ still a transient there) |
# | C4 | the same statement (Theorem 2's "arbitrary precision") | **not checked, decides** (since the session-13 re-review; the verdict rule: a contribution that cannot be measured here): κ\* is only said to exist, the proof's (sufficient) κ\* ≥ $Nn\sqrt n\|\bar A\|V(0)$ — recorded per point as the headline, ≈ 1.8e4 at the default point — so κ = 0.5 is not shown to meet the premise, and gains shown to meet it cannot be integrated at $dt=10^{-3}$ (one sign step ≈ 15 rad in the ∞-norm, `sign_step_at_kappa_star`). Its evaluation at κ = 0.5 is C4a |
# | C4a | Sec. III-B, before Theorem 2: (5), (6) achieve "a resilient estimation of $x$ with arbitrary precision" for large κ, γ; Theorem 2: $\limsup\|\hat x_i-x\|_\infty\le\eta$ for every η above some κ*, γ*. Our reading: the error tends to 0 as γ grows. **C4 evaluated at the example** (recorded, does not decide since the session-13 re-review) | premise: Assumptions 2 and 4, **and Theorem 2's κ > κ\*** (the proof's κ\* ≥ $Nn\sqrt n\|\bar A\|V(0)$ ≈ 1.8e4 at the default point, against κ = 0.5: **fails**, since the session-13 review of issue #30; running (6) above it is not numerically possible here). Measured all the same (the same measurement is X9, ours): last-window max error under the example's attack at every γ of `offset_gammas` and `gamma_ex`: log–log slope against γ ≤ −1/2 between every two consecutive gains whose error exceeds the chattering tolerance (ours: half the $1/\gamma$ rate of the paper's bounds). Negative control, recorded: the averaging baseline through the same rule (slopes −0.19, −0.09 at the default point: fails it). The comparison with our offset law is X8 |
# | C5 | our reading of Sec. IV / Fig. 1 before $t=10$ s and Theorem 2 with $a\equiv0$ (not the paper's words): without attack the estimates converge | final $\max_i\|\hat x_i-x\|_\infty$ ≤ the chattering tolerance (ours: the Filippov steady state has zero error, a finite step only chatters; Theorem 2 gives no η at these gains). **Does not decide** (fourth re-read of issue #30): a statement the paper does not make |
# | C6 | Sec. III-C: "the steady-state error depends only on the parameter γ", in the paper's usage (Remark 2): the *bound* | Theorem 3's bound contains γ and not κ: by inspection (**by construction**, not evidence); its measured content is C8 |
# | C7 | Sec. III-C (last paragraph), Conclusion: each agent, comparing $z_i$ with $\mathcal W_i\hat x_i$, finds whether it is corrupted "by the effective attack" — at the example's attack | premise: Lyapunov-stable plant, Assumptions 2, 4, **and the example's attack effective** (our reading of "effective": effect on $z_k$ in (11)'s coordinates $>2\theta$). Agent-local rule for (11), threshold $\theta=(Nn^2+\sqrt n)\sqrt N/(\gamma\lambda_2)$ (ours, assembled from the paper's bounds): exactly the attacked bank flagged. **Does not decide**: its premise fails at every point (the paper claims no identification at its example); C7b tests the statement at effective attacks (and rests on C8, which decides). Reported: the (6) rule with $\eta=2\sqrt N/(\gamma\lambda_2)$ (ours) at every γ of `offset_gammas`, and the plain reading (the Conclusion without "effective": the example's attack identified), under which neither agent-local threshold flags agent 1 at the paper's gains |
# | C7b | the same statement, at effective attacks: the clean agents find they are **not** corrupted | premise: as C7, and $\bar P$ block-diagonal over the indicator groups (as C8; since the session-13 review). (11) at the paper's gains, attacks of `id_attack_factors` × the smallest effective size: no clean agent flagged at any size (the error of (11) in its coordinates stays below θ). The averaging baseline through the same rule flags clean agents (recorded): it can fail. **Does not decide** (session-13 review): its measured part is C8's bound on the same runs, its other half (C7c) is by construction, and the reading of "effective" is ours, adopted after outcomes were known: identification rests on C8 |
# | C7c | the same statement, at effective attacks: the attacked agent finds it is corrupted | agent 1 flagged at every size: **by construction** (the sizes are $f\,a_{\rm eff}$, so its residual is $2f\theta-|\bar x_1|>\theta$ whenever C7b holds); not evidence, does not decide |
# | C8 | Theorem 3 for variant (11) | premise: $PA+A^\top P\le0$ for our $P$ (its scale `P_scale` MISSING, swept) and $\bar P$ block-diagonal over the indicator groups (the condition the paper does not state; in the premise since the fourth re-read of issue #30). Error ≤ bound at the example's attack and at the C7b attacks ($\bar P$ and $V$ recorded). At the example's attack the bound cannot fail (every estimator meets it); at the C7b sizes the non-resilient baseline exceeds it, so the rule can fail |
# | C9 | Remark 2: $\lambda_2$ of rings and all-to-all graphs | networkx against the closed forms, $N=3..12$ (**by construction**: an identity of linear algebra) |
# | C10 | Sec. IV final remark: no local majority for agent 1 | banks observing $v_1$ in agent 1's neighbourhood < 2q+1 (**by construction**: the declared rings are those the remark allows) |
# | C11 | footnote 3: the attacked agent cannot tell from its own data | premise: $C_kv\ne0$ and the identities $Av=0$, $-F_k^{-1}L_k=\mathcal W_kv$. Measured: $z_k\to\mathcal W_k(x+av)$ (last window, ≤ 0.01) and the innovation ≤ 1e-3 in **every** window of `final_window` s after the attack. **Fails by construction** of a step attack (the innovation jumps by $|a|\gg10^{-3}$ at the step, whatever the estimator): by construction, not evidence (marked so since the session-13 review) |
# | C12 | Introduction, Conclusion: plug-and-play, initialization-free operation; Sec. III-C: for Lyapunov-stable plants "the method to allow plug-and-play operation noted in the Introduction" is (11) (Theorem 3: any κ, γ > 0, any initial condition). "Seamlessly" is C14 | premise (Theorem 3's, since the session-13 re-review): Lyapunov-stable plant, Assumptions 2, 4, $\bar P$ block-diagonal (as C8); no compact set (Theorem 3 is global). **(11)** at the example's gains κ = 0.5, γ = 2 and attack; agents `pnp_agents` **re-initialised with arbitrary states** $\hat x_i$, $z_i$ (`pnp_state`) at `pnp_time`, in a run of their own: after `pnp_recovery` (45 s, ours, set in round 3 of issue #30 after the 15-s window had failed with (6)) the final-window offsets and max error equal the uninterrupted run's within twice (11)'s chattering tolerance (eventual recovery). Recorded: the disruption of the untouched agents (C14's measurement), Sec. III-C's own gains (γ from `pnp_N_bar`, `pnp_s_bar`, κ = 1/γ) and the (6) run (X10) |
# | C13 | Introduction: "intermittently join or leave the network"; Conclusion: "agents can freely join and leave the network"; Sec. III-C: (11), "as long as the proposed assumptions are maintained" | premise: as C12, and while the agent is away the remaining agents are connected with $2q+1$ banks per coordinate. (11); agent `pnp_leave_agent` leaves at `pnp_time` (links removed) for `pnp_leave_duration`, rejoins with the arbitrary state: the same rule as C12 (eventual recovery). Recorded: the disruption after the leaving and after the rejoining (C14's measurement), Sec. III-C's gains, the (6) run (X11) |
# | C14 | Introduction: "the observer can perform resilient state estimation **seamlessly** even when some sensor banks or local observers intermittently join or leave the network"; Sec. III-C: (11) | premise: as C13. C12's and C13's (11) runs: every agent not re-initialised / not leaving keeps, over the `final_window` s after each event (re-initialisation, rejoining; after the leaving over min(`final_window`, `pnp_leave_duration`), while the agent is away; the event's own sample excluded), a max error within the uninterrupted run's plus twice the chattering tolerance; headline the largest ratio measured / allowed. The rule is ours, **written after the session-13 review had seen the disruption** of the (6) runs (X12), and applied to (11) unchanged |
# | X1 | integrator (ours) | exponential Euler beats explicit Euler at `dt_ex`, converges with order one (halving dt divides the RMS deviation by 1.5–2.5); explicit Euler at three times its stability limit has spectral radius > 1 and its deviation grows |
# | X2 | (ours, not a statement of the paper) the final distance of (4) shrinks as γ grows | γ sweep: non-increasing in γ on every graph, up to $10\,dt$ |
# | X3 | (ours) the final state of (4) is a minimiser of $f_\gamma$ | distance of the final-window mean to the minimiser set and the distance to $\mathcal M$ against the minimiser's, both ≤ $10\,dt$ |
# | X4 | (ours) the median, not an average, rejects the attack | premise: the offset law applies. Baseline offsets = $(\gamma\mathcal L+D_s)^{-1}D_sp$ (1 % + tolerance), growing with $a$; median offsets = the law at every attack size |
# | X6 | (ours) the literal reading of C6: the steady state itself does not move with κ | θ-sum offsets at `kappa` and `kappa_alt` for (6) and (11) agree within the chattering tolerance of the larger κ (holds); fails only if (11)'s difference also exceeds the tolerance at $dt/4$ (paper mode, every point); not-checked otherwise |
# | X7 | (ours) the residuals of (6) follow the offset law; the attacked agent's is the largest | premise: the offset law applies. A comparison across agents, which no agent can make (not the paper's rule: C7) |
# | X8 | (ours) the steady state under attack is the offset law's (regularised median, ∝ 1/γ) | premise: the offset law applies. Last-window θ-sum offsets and max error = the law within the chattering tolerance at every γ of `offset_gammas` and `gamma_ex` (C4's rule until round 2 of issue #30) |
# | X9 | (ours) C4a's measurement at the paper's κ = 0.5, outside Theorem 2's premise: the error under attack falls like $1/\gamma$ | C4a's rule on C4a's runs (log–log slope ≤ −1/2 between consecutive gains above the chattering tolerance); not deciding |
# | X10 | (ours) C12 with (6) at κ = 0.5 (outside Theorem 2's premise; C12 until the session-13 re-review) | C12's events and rule with (6); premise with Theorem 2's κ > κ\* for the compact set $K$ (`pnp_K_radius`): fails; recorded, not deciding; the old 15-s window and the $\hat x_i$-only re-initialisation recorded here |
# | X11 | (ours) C13 with (6) (C13 until the session-13 re-review) | C13's events and rule with (6); fails its premise (as X10); recorded |
# | X12 | (ours) C14's rule on the (6) runs (C14 until the session-13 re-review) | fails its premise (as X10); recorded |
# | X5 | (ours) the attack at $t=10$ s lands on a converged network | every θ-sum error (own and resilient) < 0.05 rad in the 2 s before the attack (ours; split from C3 after the first sweep showed that this part alone varies over the declared space) |

# %%
claims = {}
tol_ii = CHATTER_STEPS * dt
SIGN_II = results.Tolerance(
    rtol=1e-6, atol=tol_ii, reason="explicit Euler of the sign-driven solver (4): which side of a "
    "sliding surface an iterate lands on depends on rounding; values can move by the chattering, O(dt)")
SIGN_IV = results.Tolerance(
    rtol=1e-6, atol=max(*tol_k.values(), *tol_k11.values()), reason="exponential Euler of the sign-driven observers (6), "
    "(11): chattering on the sliding surfaces, O(kappa ||v_l|| dt), depends on rounding near sign changes")
assumptions = bool(red[q].holds and a4_ok)
all_ratios = [r["final_distance"].max() / r["bound"] for r in runs.values()] + [
    float((r["distance"] / r["bound"]).max()) for r in sweep.values()]
claims["C1"] = results.claim(
    paper="Theorem 1: limsup_t ||x_i(t)||_M <= 2 sqrt(N) / (gamma lambda_2(L)) for every agent, "
    "every gamma > 0 and every initial condition",
    source="Sec. II, Theorem 1",
    check="demo per graph: each agent's max distance to the median set over the last "
    f"{settle_fraction:.0%} of the horizon <= the bound; sweep: max over agents for every graph "
    "and gamma <= the bound; headline: the largest ratio distance / bound (holds iff <= 1)",
    measured={**{g: r["final_distance"] for g, r in runs.items()},
              "sweep": {g: r["distance"] for g, r in sweep.items()},
              "worst_ratio": max(all_ratios)},
    threshold={**{g: r["bound"] for g, r in runs.items()},
               "sweep": {g: r["bound"] for g, r in sweep.items()}, "worst_ratio": 1.0},
    holds=max(all_ratios) <= 1.0,
    key="worst_ratio", tolerance=SIGN_II, decides=True, section="Theorem 1",
)
claims["C2"] = results.claim(
    paper=f"Section IV: (C, A) is 2q-redundant observable (q = {q}) and satisfies Assumption 4; "
    "Lemma 1: every coordinate is observed by >= 2q + 1 banks",
    source="Sec. IV; Assumptions 2 and 4; Lemma 1",
    check=f"enumeration of all subsets of N - 2q banks for q = {q} (and every q up to (N-1)/2: "
    "q_max is the largest that holds); the constructed basis verified against the unobservable "
    "subspaces; banks per coordinate >= 2q + 1",
    measured={"redundant": red[q].holds, "q_max": q_max,
              "failing": {str(qq): [[i + 1 for i in f] for f in r.failing] for qq, r in red.items()},
              "assumption4": bool(a4_ok), "banks_per_coordinate": banks_per_coord},
    threshold={"redundant": True, "assumption4": True, "min_banks_per_coordinate": 2 * q + 1},
    holds=assumptions and bool(banks_per_coord.min() >= 2 * q + 1),
    key="q_max", section="Assumption 4 — a common basis $\\{v_l\\}$",
)
pre = (t_ex >= attack_start - 2.0) & (t_ex < attack_start)
pre_sum_err = (float(max(np.abs(sum_err[pre, :, 0]).max(), np.abs(own_k[pre] @ theta_sel
                                                                    - true_sum[pre]).max()))
               if pre.any() else None)
res_sum_err = float(np.abs(sum_err[last, :, 0]).max())
own_sum_pred, own_inf_pred = float(theta_sel @ own_pred), float(np.abs(own_pred).max())
resilient_ratio = res_sum_err / max(abs(float(own_sum_err.mean())), 1e-300)
own_all = np.einsum("kob,no->kbn", sim["z"][k_att], V_i[k_att])  # V_k z_k for every attack size
own_sum_by_amp = [float((own_all[last, b] @ theta_sel - true_sum[last]).mean())
                  for b in range(len(amp_batch) - 1)]
resilient_spread = max(float(np.abs(amp_offsets[a] - amp_offsets[attack_amplitude]).max())
                       for a in amp_batch[:-1])
# the all-coordinate error (every agent, every coordinate, not the theta-sum only), per attack size,
# on a run of its own to amplitude_T (>= 50 s: over T_ex = 40 s the error at a = 10 rad was still a
# transient, the session-13 review of issue #30): its last-window max, the previous window's (settled
# iff the two agree within twice the chattering tolerance), its peak after the attack, and the time
# after the attack from which it stays within 0.05 of its last-window max (recorded, not a rule)
after = t_ex >= attack_start
t_amp, X_amp = simulate(amp_batch[:-1], horizon_s=amplitude_T)
max_err_amp = np.abs(X_amp[:, xh0:].reshape((t_amp.size, N_banks, n, -1))
                     - X_amp[:, None, :n]).max(axis=(1, 2))  # (K, B)
last_amp = t_amp >= amplitude_T - final_window - 1e-9
prev_amp = (t_amp >= amplitude_T - 2 * final_window - 1e-9) & ~last_amp
after_amp = t_amp >= attack_start
res_inf_by_amp = [float(max_err_amp[last_amp, b].max()) for b in range(len(amp_batch) - 1)]
res_inf_prev_by_amp = [float(max_err_amp[prev_amp, b].max()) for b in range(len(amp_batch) - 1)]
res_settled = bool(max(abs(a - b) for a, b in zip(res_inf_by_amp, res_inf_prev_by_amp, strict=True))
                   <= 2 * tol["inf"])
res_peak_by_amp = [float(max_err_amp[after_amp, b].max()) for b in range(len(amp_batch) - 1)]
res_inf_T_ex_by_amp = [float(max_err[last, b].max()) for b in range(len(amp_batch) - 1)]  # old record


def settle_time(series: np.ndarray, level: float) -> float | None:
    """Seconds after the attack from which ``series`` (on t_amp >= attack_start) stays <= level."""
    above = np.nonzero(series > level)[0]
    if above.size == 0:
        return 0.0
    return (None if above[-1] + 1 >= series.size
            else float(t_amp[after_amp][above[-1] + 1] - attack_start))


res_settle_by_amp = [settle_time(max_err_amp[after_amp, b], res_inf_by_amp[b] + 0.05)
                     for b in range(len(amp_batch) - 1)]
print(f"all-coordinate error per attack size {[round(a, 4) for a in amp_batch[:-1]]} over the last "
      f"{final_window:g} s of {amplitude_T:g} s: {np.round(res_inf_by_amp, 5)} (previous window "
      f"{np.round(res_inf_prev_by_amp, 5)}, settled: {res_settled}); over {T_ex - final_window:g}-{T_ex:g} s: "
      f"{np.round(res_inf_T_ex_by_amp, 5)}; peak after the attack {np.round(res_peak_by_amp, 3)}; "
      f"within 0.05 of the last-window value {res_settle_by_amp} s after the attack")
claims["C3"] = results.claim(
    paper="Sec. IV on Fig. 1: \"It demonstrates the attack-resilient property of our estimation "
    "algorithm\" (the caption: the state, \"its estimate obtained by agent 1\" and \"its resilient "
    "estimate for all agents\"). Our reading: after the attack agent 1's own estimate is wrong, "
    "while the error of the resilient estimates is bounded independently of the attack (Assumption "
    "1 lets a_i be unbounded). Footnote 3 (agent 1 alone cannot tell) is C11, not part of this claim "
    "(since the session-13 review of issue #30)",
    source="Sec. IV, Fig. 1",
    check=f"mean over the last {final_window:g} s of the attacked agent's own theta-sum and "
    "inf-norm errors = the exact V_k(-F_k^-1 L_k) a (within 0.01 rad, ours), an error growing as a; "
    "the resilient theta-sum offsets do not depend on the attack size: at a = "
    f"{', '.join(f'{a:.4g}' for a in amp_batch[:-1])} rad they differ by at most twice the "
    "chattering tolerance (ours: the attack is rejected up to an offset that does not grow with it; "
    "headline: the largest difference). Not a rule, reported: the resilient offsets themselves "
    "(O(1/gamma), nonzero at the paper's gains) and their ratio to the own error. Whether the "
    "network has converged before the attack is X5. The rule judges the theta-sum only, which is "
    "blind to the oscillatory modes; recorded next to it (not a rule): the all-coordinate error "
    "max_i ||x_hat_i - x||_inf per attack size over the last window of a run of its own to amplitude_T "
    f"= {amplitude_T:g} s (ours; since the session-13 review of issue #30: over T_ex the error at the "
    "largest attack was still a transient, recorded as 'resilient_inf_error_by_attack_T_ex'), the "
    "previous window's value ('settled' iff they agree within twice the chattering tolerance), its "
    "peak after the attack and the time from which it stays within 0.05 of its last-window value. "
    "'Attack-resilient' is read as bounded independently of the attack; the "
    "Introduction's goal, an estimate the attack cannot affect, is stronger and not what is tested",
    measured={"own_sum_error": float(own_sum_err.mean()), "own_inf_error": float(own_inf_err.mean()),
              "own_sum_error_by_attack": own_sum_by_amp, "attack_sizes": list(amp_batch[:-1]),
              "resilient_sum_error_max": res_sum_err, "resilient_to_own_ratio": resilient_ratio,
              "resilient_spread_over_attacks": resilient_spread,
              "resilient_inf_error_by_attack": res_inf_by_amp,
              "resilient_inf_error_previous_window_by_attack": res_inf_prev_by_amp,
              "resilient_inf_settled": res_settled, "resilient_inf_horizon_s": float(amplitude_T),
              "resilient_inf_error_by_attack_T_ex": res_inf_T_ex_by_amp,
              "resilient_inf_error_peak_after_attack": res_peak_by_amp,
              "resilient_inf_settle_s_by_attack": res_settle_by_amp},
    threshold={"own_sum_error": own_sum_pred, "own_inf_error": own_inf_pred,
               "resilient_spread_over_attacks": 2 * tol["sum"]},
    holds=abs(own_sum_err.mean() - own_sum_pred) <= 0.01
    and abs(own_inf_err.mean() - own_inf_pred) <= 0.01 and resilient_spread <= 2 * tol["sum"],
    premise=(f"bank {attack_bank} observes the full state (o_k = n) and the kernel of A "
             "(C_k v != 0): the setting of Fig. 1's red curve",
             bool(o_i[k_att] == n and sees_kernel)),
    key="resilient_spread_over_attacks", tolerance=SIGN_IV, decides=True,
    section="Fig. 1 — $\\theta_1+\\theta_2+\\theta_3$, agent 1's own estimate and the resilient estimates",
)
c4_worst = max(c4_slopes) if c4_slopes else None
c4_base_worst = max(c4_base_slopes) if c4_base_slopes else None
C4_PAPER = ("Sec. III-B, the sentence before Theorem 2: \"for sufficiently large kappa and gamma, the "
    "distributed algorithm (5) and (6) achieves a resilient estimation of x with arbitrary "
    "precision\"; Theorem 2: for every eta > 0 there are kappa*, gamma* such that for kappa > kappa*, "
    "gamma > gamma*, limsup ||x_hat_i - x||_inf <= eta under attack. Arbitrary precision read as: "
    "the error under attack tends to 0 as gamma grows (ours: the paper gives no rate; tested on the "
    "example of Sec. IV, which the paper runs at gamma = 2 only)")
kappa_star_step = kappa_star_lower * float(np.abs(V).max()) * dt_ex  # one sign step of (6) at kappa*
SLOPE_TOL = results.Tolerance(rtol=0.05, atol=0.05, reason="log-log slope of chattering-limited "
                              "errors: a chattering-size change of the smallest error moves it by a few "
                              "hundredths")
claims["C4"] = results.claim(
    paper=C4_PAPER,
    source="Sec. III-B, the sentence before Theorem 2, and Theorem 2, (6)",
    check="Theorem 2's 'arbitrary precision' holds for kappa > kappa*, gamma > gamma*; the theorem only "
    "says kappa* exists, and the one value the paper gives (its proof's, kappa* = N n sqrt(n) ||A_bar|| "
    "M_bar exp(||A_bar|| T), M_bar >= V(0)) is sufficient, not necessary: the example's kappa = 0.5 is "
    "not shown to meet the premise (it is not shown to fail it either), so the example cannot decide "
    "the claim (its evaluation there is C4a, recorded, not deciding). Gains known to meet the premise "
    "(kappa >= the proof's lower bound N n sqrt(n) ||A_bar|| V(0), recorded per point as the headline) "
    f"cannot be integrated here: one sign step kappa max ||v_l||_inf dt of (6) at kappa* is "
    f"{kappa_star_step:.3g} rad at dt = {dt_ex:g} s, against errors of a few tenths. Not checked: "
    "deciding, as ding2020's C8 and C12 (rescience_verdict: a contribution that cannot be measured "
    "here decides as not-checked). Since the session-13 re-review (before: decided as fails-premise "
    "at the example, which broke that rule)",
    measured={"kappa_star_lower_bound": kappa_star_lower, "kappa": float(kappa), "A_bar_norm": A_bar_norm,
              "V0": v_avg_norm(X_init), "sign_step_at_kappa_star": kappa_star_step, "dt": float(dt_ex)},
    threshold=None, holds=None,
    not_checked=f"Theorem 2's gains (kappa >= kappa* >= {kappa_star_lower:.2g}) cannot be integrated at "
    f"dt = {dt_ex:g} s here (one sign step moves x_hat_i by {kappa_star_step:.3g} rad), and the example's "
    "kappa = 0.5 is not shown to meet Theorem 2's premise (kappa* is only said to exist)",
    key="kappa_star_lower_bound", decides=True,
    section="Theorem 2 under attack: the error as γ grows",
)
claims["C4a"] = results.claim(
    paper=C4_PAPER + " — evaluated at the example's kappa = 0.5 (recorded, not deciding: C4)",
    source="Sec. III-B, the sentence before Theorem 2, and Theorem 2, (6); evaluated on Sec. IV's "
    "example (its attack and kappa)",
    check=f"the example's attack at kappa = {kappa:g} and every gamma of offset_gammas and gamma_ex "
    f"({', '.join(f'{g:g}' for g in c4_gammas)}): last-window max_i ||x_hat_i - x||_inf; holds iff the "
    f"log-log slope d log(error) / d log(gamma) between every two consecutive gains whose error exceeds "
    f"the chattering tolerance is <= {C4_SLOPE:g} (headline: the largest step slope; 'gammas_above_floor'"
    "; until the session-13 review one gain below the floor made the claim not checked). Fails its "
    "premise at the paper's kappa (Theorem 2's kappa*, premise; the proof's kappa* is sufficient, so "
    "strictly: not shown to meet it), so the rule's outcome there is recorded, not decided (C4 decides "
    "as not-checked since the session-13 re-review; until then this entry was C4 and decided): the "
    "same measurement is X9 (ours). Threshold (ours): an error tending to 0 keeps a slope "
    "bounded away from 0, one tending to a nonzero limit has a slope tending to 0; -1/2 is half the "
    "rate -1 of the paper's own bounds (Theorem 1, Theorem 3: prop. to 1/gamma); set in the fourth "
    "re-read of issue #30 after a reviewer's simulation (slopes about -1 median, -0.13 averaging), "
    "its value from the bounds, not from those numbers. Negative control, recorded: the averaging "
    "baseline (sgn replaced by its argument, non-resilient, ours) at the same gains through the same "
    "rule ('baseline_*'). Not checked if fewer than two gains have an error above the chattering "
    "tolerance (the slope would measure the integrator). Old rule (until the fourth re-read, recorded, not the "
    "rule): a decrease larger than the chattering tolerance at every step, which the averaging "
    "baseline passes too ('old_rule_*'). Until the round-2 review of issue #30 this claim compared "
    "the offsets with our closed-form offset law; that comparison is now X8 (ours)",
    measured={"gammas": c4_gammas, "max_error": c4_err, "gammas_above_floor": c4_g_used,
              "step_slopes": c4_slopes, "largest_step_slope": c4_worst,
              "fit_slope": loglog_fit(c4_g_used, c4_e_used),
              "kappa": float(kappa), "kappa_star_lower_bound": kappa_star_lower,
              "A_bar_norm": A_bar_norm, "V0": v_avg_norm(X_init),
              "baseline_max_error": c4_base_err, "baseline_step_slopes": c4_base_slopes,
              "baseline_largest_step_slope": c4_base_worst,
              "baseline_fit_slope": loglog_fit(c4_g_used, [c4_base_err[m] for m in c4_above]),
              "baseline_passes_rule": bool(c4_base_slopes) and c4_base_worst <= C4_SLOPE,
              "old_rule_smallest_decrease": float(min(c4_steps)) if c4_steps else None,
              "old_rule_holds": bool(c4_steps) and min(c4_steps) > tol["inf"],
              "old_rule_baseline_holds": bool(c4_base_err[:-1]) and min(
                  c4_base_err[m] - c4_base_err[m + 1] for m in range(len(c4_base_err) - 1)) > tol["inf"]},
    threshold={"largest_step_slope": C4_SLOPE, "max_error_floor": tol["inf"],
               "kappa_star_lower_bound": kappa_star_lower},
    holds=(c4_worst <= C4_SLOPE) if c4_measurable else None,
    not_checked=(None if c4_measurable else "fewer than two gains have an error above the chattering "
                 f"tolerance {tol['inf']:.2g}: a slope there would measure the integrator"),
    premise=("Assumptions 2 (q) and 4 hold (C2); at least two gains are run; and Theorem 2's gain "
             "condition kappa > kappa*: the theorem only says kappa* exists, the one value the paper "
             "gives is its proof's, kappa* = N n sqrt(n) ||A_bar|| M_bar exp(||A_bar|| T) with M_bar >= "
             f"V(0) = ||x_bar_avg(0)||, so kappa* >= N n sqrt(n) ||A_bar|| V(0) = {kappa_star_lower:.3g} "
             f"here, against kappa = {kappa:g} (since the session-13 review of issue #30; C5 was "
             "demoted on the same ground). Running (6) with kappa above it is not numerically possible "
             "here (one sign step kappa ||v_l|| dt would be about kappa* 1e-3, 18 rad with the unit basis at the default point, at dt = 1e-3). The slope at "
             "kappa = 0.5 is X9 (ours)",
             assumptions and len(c4_gammas) >= 2 and thm2_gains),
    key="largest_step_slope", decides=False,
    tolerance=SLOPE_TOL,
    section="Theorem 2 under attack: the error as γ grows",
)
claims["X9"] = results.claim(
    paper="(ours) at the example's kappa = 0.5, outside Theorem 2's premise (kappa* of its proof is "
    "orders of magnitude larger: C4), the error under the example's attack still falls like 1/gamma",
    source="ours (C4's measurement at the paper's kappa, since the session-13 review of issue #30)",
    check="C4's rule on C4's runs: last-window max_i ||x_hat_i - x||_inf at every gamma of offset_gammas "
    "and gamma_ex, log-log slope between every two consecutive gains whose error exceeds the chattering "
    f"tolerance <= {C4_SLOPE:g} (headline: the largest step slope); not checked with fewer than two "
    "such gains. The averaging baseline through the same rule is C4's negative control "
    "('baseline_*' there)",
    measured={"gammas_above_floor": c4_g_used, "max_error": c4_e_used, "step_slopes": c4_slopes,
              "largest_step_slope": c4_worst, "baseline_step_slopes": c4_base_slopes,
              "baseline_largest_step_slope": c4_base_worst},
    threshold={"largest_step_slope": C4_SLOPE, "max_error_floor": tol["inf"]},
    holds=(c4_worst <= C4_SLOPE) if c4_measurable else None,
    not_checked=(None if c4_measurable else "fewer than two gains have an error above the chattering "
                 f"tolerance {tol['inf']:.2g}"),
    premise=("Assumptions 2 (q) and 4 hold (C2); at least two gains are run",
             assumptions and len(c4_gammas) >= 2),
    key="largest_step_slope",
    tolerance=SLOPE_TOL,
    section="Theorem 2 under attack: the error as γ grows",
)
claims["X8"] = results.claim(
    paper="(ours) the steady state under attack is the offset law's: per static coordinate the "
    "regularised median argmin sum s|p - c| + gamma/2 c'Lc, prop. to 1/gamma",
    source="ours (offset law; the old reading of C4)",
    check="last-window theta-sum offsets and max_i ||x_hat_i - x||_inf against the offset law "
    "(equilibrium of (7)) at every gamma of offset_gammas and gamma_ex; "
    f"holds iff every deviation <= the chattering tolerance {CHATTER_STEPS} kappa dt ||v||",
    measured={"max_offset_deviation": max(law_dev.values()),
              "max_error_deviation": max(law_inf_dev.values()),
              "offsets": {f"{g:g}": law_runs[(basis_normalisation, g, float(kappa))]["sum"]
                          for g in gammas_law}},
    threshold={"max_offset_deviation": tol["sum"], "max_error_deviation": tol["inf"],
               "predicted_offsets": {f"{g:g}": law_pred[g]["sum"] for g in gammas_law},
               "predicted_max_error": {f"{g:g}": law_pred[g]["inf"] for g in gammas_law}},
    holds=max(law_dev.values()) <= tol["sum"] and max(law_inf_dev.values()) <= tol["inf"],
    premise=("Assumptions 2 (q) and 4 hold (C2), and the attack's steady effect p lies in static "
             "coordinates, where our closed form applies", assumptions and law_premise),
    key="max_offset_deviation", tolerance=SIGN_IV,
    section="The steady-state offset law (ours)",
)
claims["C5"] = results.claim(
    paper="Sec. IV, the example at the paper's gains (kappa = 0.5, gamma = 2), Fig. 1 before t = 10 s, "
    "and Theorem 2 with a = 0 — our reading, not the paper's words (Sec. IV does not state it): "
    "without attack the resilient estimates of all agents converge to the state",
    source="Sec. IV and Fig. 1 (the example); Sec. III-B, Theorem 2 (a = 0)",
    check=f"the attack-free run of the example: max_i ||x_hat_i - x||_inf over the last {final_window:g} s "
    f"<= the chattering tolerance {CHATTER_STEPS} kappa dt max ||v_l||_inf (ours: without attack the "
    "Filippov steady state has zero error (p = 0 gives c = 0), so a finite-step run can differ from "
    "it only by the chattering of the sign correction; Theorem 2 alone promises <= eta only for "
    "gains above kappa*, gamma*, which it does not give); the time after which it stays below 0.05 "
    "is reported. Does not decide (fourth re-read of issue #30): the rule decides on a statement the "
    "paper does not make (convergence at the paper's gains; Theorem 2 promises eta only above "
    "kappa*, gamma*); until then it decided",
    measured={"final_error": final_noattack, "time_below_0.05": conv_time},
    threshold={"final_error": tol["inf"]},
    holds=final_noattack <= tol["inf"],
    premise=("Assumptions 2 (q) and 4 hold (C2)", assumptions),
    key="final_error", tolerance=SIGN_IV,
    section="No attack (Theorem 2 with $a\\equiv0$)",
)
PNP_PAPER = ("Introduction: the observer \"allows the plug-and-play (initialization-free) operation; "
             "that is, the observer can perform resilient state estimation [...] even when some "
             "sensor banks or local observers intermittently join or leave the network\" (its word "
             "'seamlessly' is C14); Conclusion: "
             "\"particular initialization is not needed for the algorithm (5) and (6) as seen in Theorem "
             "2\" and \"agents can freely join and leave the network during the operation\"; Theorem 2 "
             "is semi-global (\"for each compact set K\"), and Sec. III-C's last paragraph: \"if we "
             "additionally assume that the initial condition is in some compact set K as in Theorem 2\"")
PNP_RULE = ("holds iff, after the window pnp_recovery = "
            f"{pnp_recovery:g} s (ours: twice the known 22.5 s transient of (5) with the literal 'near -1' "
            "poles, set in round 3 of the review of issue #30 after C12 had failed with the 15 s window; "
            "the paper gives no recovery time), the last-window "
            "theta-sum offsets and max_i ||x_hat_i - x||_inf equal those of the uninterrupted run over the "
            "same times within twice the chattering tolerance (as in C3; ours); headline 'worst_ratio': "
            "the larger of the two ratios difference / allowed (<= 1: holds). {RUN} Eventual recovery only: 'seamlessly' "
            "(Introduction) is C14; the disruption of the agents not re-initialised / not leaving in the "
            "final_window after each event is recorded here ('disruption') and judged there")
PNP_RUN6 = ("Run: (6) at the example's gains (kappa = 0.5, gamma = 2) and attack, not the plug-and-play "
            "method of Sec. III-C (which is for (11) with gains from N_bar and s_bar).")
PNP_RUN11 = ("Run: (11) (Sec. III-C's plug-and-play method for Lyapunov-stable plants) at the example's gains "
             "kappa = 0.5, gamma = 2, which Theorem 3 allows ('any kappa > 0, gamma > 0'), and attack; the "
             "chattering tolerance is (11)'s (columns of V_bar). Recorded too: the same events with Sec. "
             "III-C's own gains gamma = ||V_bar|| sqrt(N_bar) (N_bar^2 - N_bar) (N_bar n^2 + sqrt(n)) / (4 s_bar) "
             "(ERRATA's reading of the printed formula, the same at N_bar = N), "
             f"kappa = 1/gamma = {kappa_sec3c:.3g} (N_bar = {pnp_N_bar}, s_bar = {pnp_s_bar:g}, MISSING, "
             "declared; 'sec3c_gains'), and the (6) runs (X10, X11, X12: outside Theorem 2's premise).")
PNP_RULE6, PNP_RULE11 = PNP_RULE.replace("{RUN}", PNP_RUN6), PNP_RULE.replace("{RUN}", PNP_RUN11)
THM3_PNP = ("Theorem 3's premise (Sec. III-C), the assumptions the paper requires to be maintained: the "
            "plant is Lyapunov stable (our P = P_scale T^-T T^-1 satisfies PA + A'P <= 0), Assumptions 2 "
            "(q) and 4 hold (C2), and P_bar is block-diagonal over the indicator groups (as C8; the "
            "condition the paper does not state). Theorem 3 is global (any kappa > 0, gamma > 0 and any "
            "initial condition): no compact set K is needed")
PNP_THM2 = ("Theorem 2's gain condition, on which the Conclusion rests the plug-and-play claim (\"as seen "
            "in Theorem 2\"; Theorem 2 is semi-global, its gains depend on K): kappa > kappa* for a compact "
            "set K holding the run's initial state and the arbitrary states; the one kappa* the paper gives "
            f"(its proof's) is >= N n sqrt(n) ||A_bar|| max V = {kappa_star_pnp:.3g} here, against kappa = "
            f"{kappa:g} (as C4; in the premise since the session-13 review of issue #30)")
PNP_K = (f"the arbitrary states lie in Theorem 2's compact set, declared as the box ||x_hat_i||_inf <= "
         f"pnp_K_radius = {pnp_K_radius:g} with z_i = W_i x_hat_i (ours; the rest of the state is the "
         "running system's); K is ours, the paper leaves it free")
claims["X10"] = results.claim(
    paper="(ours: C12's events with (6), outside Theorem 2's premise; recorded, not deciding since the "
    "session-13 re-review, when C12 moved to (11)) " + PNP_PAPER + " — here: agents re-initialised with "
    "arbitrary states (the network unchanged)",
    source="ours (C12's events run with (6) at the example's gains; Theorem 2, Sec. III-B)",
    check=f"at t = {pnp_t0:g} s (under attack) agents {list(pnp_agents)} are re-initialised with "
    "x_hat_i = pnp_state and z_i = W_i pnp_state (ours, arbitrary), in a run of its own to "
    f"{t12_end:g} s; " + PNP_RULE6 + ". Reported: the time from which the run stays within 0.05 of "
    "the uninterrupted one (null: not within the run), the partial observers' final-window distance "
    "from the uninterrupted run's, and the same re-initialisation of x_hat_i alone with the partial "
    "observers kept running ('xhat_only_*'), which separates the transient of (5) from that of (6). "
    "Old reading (until round 3 of the review of issue #30, recorded, not the rule): the window "
    "T_ex - final_window - pnp_time (15 s at the defaults) that the example's run left, without a "
    "reason of its own and shorter than the known transient ('old_window_*'). Leaving and "
    "rejoining is C13",
    measured={**pnp_c12, "error_at_restart": pnp_initial_gap,
              "xhat_only_offset_difference": pnp_c12_xh["offset_difference"],
              "xhat_only_max_error_difference": pnp_c12_xh["max_error_difference"],
              "xhat_only_worst_ratio": pnp_c12_xh["worst_ratio"],
              "old_window_s": (old_end - final_window - pnp_t0) if pnp_c12_old else None,
              "old_window_worst_ratio": pnp_c12_old["worst_ratio"] if pnp_c12_old else None,
              "disruption": seam["C12: re-initialisation"], "kappa_star_lower_bound": kappa_star_pnp},
    threshold={"worst_ratio": 1.0, "offset_difference": 2 * tol["sum"],
               "max_error_difference": 2 * tol["inf"], "recovery_window_s": pnp_recovery,
               "K_radius": pnp_K_radius},
    holds=pnp_c12["worst_ratio"] <= 1.0,
    premise=("Assumptions 2 (q) and 4 hold (C2), the assumptions the paper requires to be maintained; "
             + PNP_K + "; " + PNP_THM2, assumptions and pnp_in_K and thm2_pnp),
    key="worst_ratio", tolerance=SIGN_IV, decides=False,
    section="Plug-and-play: agents re-initialised with arbitrary states, an agent leaving and "
    "rejoining (Introduction, Conclusion)",
)
claims["X11"] = results.claim(
    paper="(ours: C13's events with (6), outside Theorem 2's premise; recorded, not deciding since the "
    "session-13 re-review, when C13 moved to (11)) " + PNP_PAPER + " — here: an agent leaving the "
    "network and rejoining",
    source="ours (C13's events run with (6) at the example's gains; Theorem 2, Sec. III-B)",
    check=f"at t = {pnp_t0:g} s (under attack) agent {pnp_leave_agent} leaves: its links are removed "
    f"(row and column of the adjacency zeroed) for {leave_steps * record_dt:g} s (pnp_leave_duration, "
    f"ours), then restored, and it returns with x_hat_i = pnp_state, z_i = W_i pnp_state; run to "
    f"{t13_end:g} s; " + PNP_RULE6 + ". Reported: the remaining agents' max error while it is away "
    "(and the uninterrupted run's over the same times; the event's own sample at pnp_time, shared "
    "by both runs, excluded since the session-13 review of issue #30: before, both maxima were that "
    "sample), the disruption after the leaving and after the rejoining, the time from which the run "
    "stays within 0.05 of the uninterrupted one",
    measured={**pnp_c13, "away_max_error_remaining": away_max_err,
              "away_max_error_remaining_uninterrupted": away_max_err_ref,
              "banks_per_coordinate_while_away": rest_banks.tolist(),
              "disruption_leaving": seam["C13: leaving"], "disruption_rejoining": seam["C13: rejoining"],
              "kappa_star_lower_bound": kappa_star_pnp},
    threshold={"worst_ratio": 1.0, "offset_difference": 2 * tol["sum"],
               "max_error_difference": 2 * tol["inf"], "recovery_window_s": pnp_recovery,
               "K_radius": pnp_K_radius},
    holds=pnp_c13["worst_ratio"] <= 1.0,
    premise=("Assumptions 2 (q) and 4 hold (C2) for the whole network; while the agent is away the "
             "remaining agents are connected and every coordinate keeps 2q+1 observing banks among "
             "them (the assumptions maintained); " + PNP_K + "; " + PNP_THM2,
             assumptions and away_ok and pnp_in_K and thm2_pnp),
    key="worst_ratio", tolerance=SIGN_IV, decides=False,
    section="Plug-and-play: agents re-initialised with arbitrary states, an agent leaving and "
    "rejoining (Introduction, Conclusion)",
)
def seam_rule(allow: float) -> str:
    """C14's rule (as written in the session-13 review), with the estimator's allowance."""
    return ("for each event (C12's re-initialisation of pnp_agents at pnp_time; "
            "C13's agent leaving at pnp_time and rejoining pnp_leave_duration later), the max "
            f"||x_hat_i - x||_inf of every agent not re-initialised / not leaving over the {final_window:g} s "
            "(final_window) after the event (after the leaving: over min(final_window, pnp_leave_duration) = "
            f"{leave_window:g} s, while the agent is away; stated since the session-13 re-review), the event's "
            "own sample excluded, against the uninterrupted run's "
            "over the same times; holds iff for every such agent and event it is <= the uninterrupted run's "
            f"+ twice the chattering tolerance ({allow:.2g}; as C3, C12, C13); headline: the largest ratio "
            "measured / allowed. The rule is ours and was written in the session-13 review of issue #30, "
            "AFTER that review had seen the disruption of the (6) runs (X12: the untouched agents 3 and 5 at about 23 rad after "
            "C12's re-initialisation against 0.41 and 0.14 uninterrupted): not declared before the outcome. The window "
            "is the notebook's final_window, declared before; the tolerance is C3's. Until then 'seamlessly' "
            "was quoted in C12 and C13 but not tested")


claims["X12"] = results.claim(
    paper="(ours: C14's rule on the (6) runs, outside Theorem 2's premise; recorded, not deciding since "
    "the session-13 re-review, when C14 moved to (11)) Introduction: \"it allows the plug-and-play (initialization-free) operation; that is, the "
    "observer can perform resilient state estimation seamlessly even when some sensor banks or local "
    "observers intermittently join or leave the network as long as the proposed assumptions are "
    "maintained during the operation\". 'Seamlessly', in the paper's own usage: the estimation goes "
    "on through the event, i.e. the agents that are not re-initialised and do not leave keep "
    "estimating as they would have without the event",
    source="ours (C14's rule on the (6) runs at the example's gains; Theorem 2, Sec. III-B)",
    check="C12's and C13's (6) runs: " + seam_rule(SEAM_ALLOW),
    measured={"worst_ratio": seam_worst, **seam},
    threshold={"worst_ratio": 1.0, "allowance_over_uninterrupted": SEAM_ALLOW,
               "window_s": float(final_window), "leaving_window_s": leave_window},
    holds=seam_worst <= 1.0,
    premise=("Assumptions 2 (q) and 4 hold (C2), and while agent pnp_leave_agent is away the "
             "remaining agents are connected with 2q+1 banks per coordinate (the assumptions "
             "maintained); " + PNP_K + "; " + PNP_THM2,
             assumptions and away_ok and pnp_in_K and thm2_pnp),
    key="worst_ratio", tolerance=SIGN_IV, decides=False,
    section="Plug-and-play: agents re-initialised with arbitrary states, an agent leaving and "
    "rejoining (Introduction, Conclusion)",
)
thm3_pnp = bool(assumptions and lyap_ok and offgroup_rel <= 1e-9)  # Theorem 3's premise (as C8's)
PNP_SECTION11 = "Plug-and-play with (11): Sec. III-C's method (C12, C13, C14)"
PNP_SOURCE11 = ("Sec. I (Introduction), Sec. V (Conclusion); Sec. III-C (Theorem 3 and its plug-and-play "
                "paragraph: \"the method to allow plug-and-play operation noted in the Introduction\", (11)); "
                "the example of Sec. IV")
claims["C12"] = results.claim(
    paper=PNP_PAPER + "; Sec. III-C: \"by considering Lyapunov stable systems the method to allow "
    "plug-and-play operation noted in the Introduction [...] become[s] much easy\" ((11), Theorem 3: any "
    "kappa > 0, gamma > 0 and any initial condition) — here: agents re-initialised with arbitrary states "
    "(the network unchanged)",
    source=PNP_SOURCE11,
    check=f"(11) at t = {pnp_t0:g} s (under attack): agents {list(pnp_agents)} re-initialised with "
    "x_hat_i = pnp_state and z_i = W_i pnp_state (ours, arbitrary), in a run of its own to "
    f"{t12_end:g} s; " + PNP_RULE11 + " Since the session-13 re-review (before: the (6) runs, now X10)",
    measured={**pnp11["c12"], "error_at_restart": pnp11["error_at_restart"],
              "xhat_only_worst_ratio": pnp11["c12_xh"]["worst_ratio"],
              "disruption": pnp11["seam"]["C12: re-initialisation"],
              "sec3c_gains": {"gamma": gamma_sec3c, "kappa": kappa_sec3c, **pnp_variant(pnp11c, "C12")},
              "with_(6)": pnp_variant(pnp6, "C12")},
    threshold={"worst_ratio": 1.0, "offset_difference": 2 * tol11["sum"],
               "max_error_difference": 2 * tol11["inf"], "recovery_window_s": pnp_recovery},
    holds=pnp11["c12"]["worst_ratio"] <= 1.0,
    premise=(THM3_PNP, thm3_pnp),
    key="worst_ratio", tolerance=SIGN_IV, decides=True, section=PNP_SECTION11,
)
claims["C13"] = results.claim(
    paper=PNP_PAPER + "; Sec. III-C: (11), Theorem 3, \"even when some sensor banks or local observers "
    "intermittently join or leave the network as long as the proposed assumptions are maintained\" — "
    "here: an agent leaving the network and rejoining",
    source=PNP_SOURCE11,
    check=f"(11) at t = {pnp_t0:g} s (under attack): agent {pnp_leave_agent} leaves (links removed) for "
    f"{leave_steps * record_dt:g} s (pnp_leave_duration, ours), then rejoins with x_hat_i = pnp_state, "
    f"z_i = W_i pnp_state; run to {t13_end:g} s; " + PNP_RULE11 + " Since the session-13 re-review "
    "(before: the (6) runs, now X11)",
    measured={**pnp11["c13"], "banks_per_coordinate_while_away": rest_banks.tolist(),
              "away_max_error_remaining": float(pnp11["seam"]["C13: leaving"]["max_error"].max()),
              "disruption_leaving": pnp11["seam"]["C13: leaving"],
              "disruption_rejoining": pnp11["seam"]["C13: rejoining"],
              "sec3c_gains": {"gamma": gamma_sec3c, "kappa": kappa_sec3c, **pnp_variant(pnp11c, "C13")},
              "with_(6)": pnp_variant(pnp6, "C13")},
    threshold={"worst_ratio": 1.0, "offset_difference": 2 * tol11["sum"],
               "max_error_difference": 2 * tol11["inf"], "recovery_window_s": pnp_recovery},
    holds=pnp11["c13"]["worst_ratio"] <= 1.0,
    premise=(THM3_PNP + "; while the agent is away the remaining agents are connected and every "
             "coordinate keeps 2q+1 observing banks among them", thm3_pnp and away_ok),
    key="worst_ratio", tolerance=SIGN_IV, decides=True, section=PNP_SECTION11,
)
claims["C14"] = results.claim(
    paper="Introduction: \"it allows the plug-and-play (initialization-free) operation; that is, the "
    "observer can perform resilient state estimation seamlessly even when some sensor banks or local "
    "observers intermittently join or leave the network as long as the proposed assumptions are "
    "maintained during the operation\"; Sec. III-C: the plug-and-play method is (11) for Lyapunov-stable "
    "plants. 'Seamlessly', in the paper's own usage: the estimation goes on through the event, i.e. the "
    "agents that are not re-initialised and do not leave keep estimating as they would have without "
    "the event",
    source="Sec. I (Introduction); Sec. III-C ((11), Theorem 3); the example of Sec. IV",
    check="C12's and C13's (11) runs (since the session-13 re-review; before: the (6) runs, now X12), the "
    "rule unchanged: " + seam_rule(pnp11["allow"]) + ". Recorded: the same with Sec. III-C's own gains "
    "('sec3c_gains') and with (6) ('with_(6)')",
    measured={"worst_ratio": pnp11["seam_worst"], **pnp11["seam"],
              "sec3c_gains": {"gamma": gamma_sec3c, "kappa": kappa_sec3c, **pnp_variant(pnp11c, "C14")},
              "with_(6)": pnp_variant(pnp6, "C14")},
    threshold={"worst_ratio": 1.0, "allowance_over_uninterrupted": pnp11["allow"],
               "window_s": float(final_window), "leaving_window_s": leave_window},
    holds=pnp11["seam_worst"] <= 1.0,
    premise=(THM3_PNP + "; while agent pnp_leave_agent is away the remaining agents are connected with "
             "2q+1 banks per coordinate", thm3_pnp and away_ok),
    key="worst_ratio", tolerance=SIGN_IV, decides=True, section=PNP_SECTION11,
)
claims["C6"] = results.claim(
    paper="Section III-C (after the proof of Theorem 3): the steady-state error depends only on "
    "the parameter gamma — in the paper's usage, the steady-state error is the bound on "
    "limsup ||x_hat_i - x|| (Remark 2 calls Theorem 1's bound 2 sqrt(N)/(gamma lambda_2) \"the "
    "steady-state error\"; the plug-and-play paragraph meets a \"goal of steady-state error\" "
    "through the bound)",
    source="Sec. III-C, after Theorem 3; usage: Remark 2 and Sec. III-C (plug-and-play paragraph)",
    check="Theorem 3's bound (N n^2 + sqrt(n)) sqrt(N) ||V P_bar^(-1/2)|| / (gamma lambda_2) contains "
    "gamma and not kappa: true by inspection of the formula (by construction, not evidence); the "
    "bound evaluated at this run's gamma is recorded. Its measured content (the error stays below "
    "the bound) is C8; the literal reading (the steady state itself) is X6 (ours)",
    measured={"bound": float(thm3_bound), "kappa_enters_bound": False},
    threshold={"kappa_enters_bound": False},
    holds=True, basis="by-construction",
    key="bound", section="The steady-state error depends only on γ (Section III-C)",
)
x6_over = {"(6)": kappa_dev["(6)"] > tol_k["sum"], "(11)": kappa_dev["(11)"] > tol_k11["sum"]}
x6_confirmed = bool(x6_over["(11)"] and fine_dev_11 is not None and fine_dev_11 > tol_k11["sum"] / 4)
x6_holds = (True if not any(x6_over.values()) else False if x6_confirmed else None)
claims["X6"] = results.claim(
    paper="(ours: a literal reading of the sentence of Sec. III-C that the paper does not make) the "
    "steady state of the estimation error after the attack does not move with kappa, for (6) and "
    "for (11)",
    source="ours (a literal reading of Sec. III-C, after Theorem 3)",
    check=f"last-window theta-sum offsets after the attack at kappa = {kappa:g} and kappa_alt = "
    f"{kappa_alt:g} (gamma = {gamma_ex:g}), for (6) and (11): holds iff the max difference <= the "
    "chattering tolerance of the larger kappa (for (11) with the columns of V_bar); fails iff the "
    "(11) difference exceeds it AND, rerun at dt_ex / 4 (paper mode, every point), still exceeds the "
    "tolerance at that step (a chattering difference shrinks with dt; a dependence on kappa does "
    "not); not-checked otherwise. Until the round-2 review of issue #30 the rule was the first "
    "comparison alone (it 'failed' at margins down to 2 % over the tolerance). Headline: the larger "
    "ratio difference / tolerance at dt_ex",
    measured={"max_excess": max(kappa_dev["(6)"] / tol_k["sum"], kappa_dev["(11)"] / tol_k11["sum"]),
              **kappa_dev, "(11)_at_dt/4": fine_dev_11,
              "offsets_(6)": {f"{kap:g}": law_runs[(basis_normalisation, float(gamma_ex), kap)]["sum"]
                              for kap in kappa_pair},
              "offsets_(11)": {f"{kappa:g}": sums_11, f"{kappa_alt:g}": sums_11_alt}},
    threshold={"(6)": tol_k["sum"], "(11)": tol_k11["sum"], "(11)_at_dt/4": tol_k11["sum"] / 4,
               "max_excess": 1.0},
    holds=x6_holds,
    not_checked=(None if x6_holds is not None else
                 "the difference exceeds the chattering tolerance at dt_ex, but the dt_ex / 4 rerun "
                 + ("was not run (fast mode)" if fine_dev_11 is None else
                    "does not confirm it for (11)" if x6_over["(11)"] else
                    "covers (11) only and (6) exceeds it")),
    key="max_excess", tolerance=SIGN_IV,
    section="The steady-state error depends only on γ (Section III-C)",
)
clean_max = float(resid_meas[clean].max())
premise_id = ("the plant is Lyapunov stable (our P satisfies PA + A'P <= 0) and Assumptions 2 (q) and "
              "4 hold: the setting of the paper's rule")
claims["C7"] = results.claim(
    paper="Section III-C (last paragraph) and Conclusion: each agent, by comparing its partial "
    "estimate z_i with its resilient estimate W_i x_hat_i, finds whether its measurement is "
    "corrupted by the effective attack; the attack is identified. Here: the example's attack",
    source="Sec. III-C (last paragraph), Sec. V; Sec. IV (the example's attack)",
    check="premise (ours, the reading of 'effective'): the attack's steady effect on z_k in the "
    "coordinates of (11), max_l |(sqrt(P_bar) W V_k e_k)_l|, exceeds 2 theta, the smallest effect the "
    "comparison is guaranteed to reveal; theta = (N n^2 + sqrt(n)) sqrt(N) / (gamma lambda_2) is our "
    "assembly of the bounds the paper states ((13) and V after T', epsilon -> 0; the paper states no "
    "threshold). The rule, agent-local: agent i flags its bank iff the mean over the last "
    f"{final_window:g} s of max over its coordinates of |w_bar_l'(V_i z_i - x_hat_i)| exceeds theta; "
    "holds iff exactly the attacked bank is flagged. Until the session-8 review of issue #30 the "
    "example's attack was read as effective and C7 recorded 'fails' (holds is still measured and "
    "recorded). "
    "Headline: the attack's effect / (2 theta) (the premise holds iff > 1). Reported, not decided: "
    "the agent-local rule for (6) with eta = 2 sqrt(N)/(gamma lambda_2) (ours, from Theorem 1) at "
    "every gamma of offset_gammas, and the gammas at which it flags exactly the attacked bank. "
    "Does not decide (lead decision D1, round-2 review of issue #30): its premise fails at every "
    "point of the space (one evaluation), so it can neither hold nor fail, and the paper claims no "
    "identification at its example (Sec. IV and Fig. 1 are about estimation; footnote 3 only says "
    "agent 1 alone cannot tell). The paper's statement is tested by C7b, where its condition holds "
    "(measured; not deciding since the session-13 review of issue #30: it is C8's bound on the same "
    "runs, and C8 decides). "
    "The plain reading (the Conclusion's sentence without 'effective': the example's attack is "
    "identified) is recorded next to ours ('plain_reading'): under it no agent-local rule from the "
    "paper's bounds identifies the attack at the example's gains; the 'effective attack' reading is "
    "the paper's own usage in Sec. III-C (twice), and C7b rests on it",
    measured={"residual_11": resid_11, "flagged_11": flagged_11,
              "attacked_over_threshold": float(resid_11[k_att] / theta_id),
              "effect_11": effect_example, "effect_over_2theta": effect_example / (2 * theta_id),
              "smallest_effective_attack": a_eff, "gamma_at_which_effective": gamma_effective,
              "residual_6": resid_meas, "flagged_6": flagged_6,
              "gammas_identified_6": gammas_identified,
              "plain_reading": {
                  "statement": "Conclusion, without the qualifier: the attack is identified by "
                  "comparing z_i with W_i x_hat_i; at the example, its pi/3",
                  "flagged_11_theta": flagged_11,
                  "flagged_6_eta_at_gamma_ex": flagged_6.get(f"{gamma_ex:g}"),
                  "outcome": ("holds" if flagged_11 == [attack_bank]
                              or flagged_6.get(f"{gamma_ex:g}") == [attack_bank] else "fails"),
                  "note": "recorded, not the rule: at the example's gains neither agent-local "
                  "threshold from the paper's bounds (theta for (11), eta for (6)) flags the attacked "
                  "bank; the paper's own usage in Sec. III-C ('the effective attack', 'the method to "
                  "identify effective attacks') qualifies the statement, and C7b, C7c are tested under "
                  "it (neither decides: C7b is C8's bound on the same runs, C7c is by construction)"}},
    threshold={"theta_11": float(theta_id), "eta_6": float(eta_id), "effect_over_2theta": 1.0,
               "flagged": [attack_bank]},
    holds=flagged_11 == [attack_bank],
    premise=(premise_id + f"; and the example's attack (a = {attack_amplitude:.4g} rad on bank "
             f"{attack_bank}) is effective: its effect {effect_example:.3g} > 2 theta = "
             f"{2 * theta_id:.3g}", lyap_ok and assumptions and example_effective),
    key="effect_over_2theta", tolerance=SIGN_IV,
    section="Attack identification by the paper's own rule (Sec. III-C, last paragraph)",
)
id_margin = (float(min(r[k_att] for r in resid_id) / theta_id) if len(resid_id) else 0.0)
id_clean = (float(max(np.delete(r, k_att).max() for r in resid_id) / theta_id)
            if len(resid_id) else 0.0)
ID_PAPER = ("Section III-C (last paragraph) and Conclusion: each agent, by comparing its partial "
            "estimate z_i with its resilient estimate W_i x_hat_i, finds whether its measurement is "
            "corrupted by the effective attack or not (Sec. III-C also calls it \"the method to identify "
            "effective attacks\"). Here: effective attacks on the example")
ID_RUN = ("(11) at the paper's gains with a constant attack on bank attack_bank from attack_start of size "
          f"f a_eff for every f of id_attack_factors ({', '.join(f'{f:g}' for f in id_attack_factors)}; "
          "ours), a_eff = 2 theta / (effect per unit attack) the smallest effective attack (ours, as in "
          "C7); the agent-local rule of C7 with the same theta (ours, assembled from the paper's bounds)")
id_no_false = bool(id_amps) and all(set(f) <= {attack_bank} for f in flagged_id.values())
id_base_false = {k: [a for a in f if a != attack_bank] for k, f in flagged_id_base.items()}
claims["C7b"] = results.claim(
    paper=ID_PAPER + ": the clean agents find that they are not corrupted (the 'or not' of the "
    "statement; the attacked agent's flag is C7c, true by construction)",
    source="Sec. III-C (last paragraph), Sec. V",
    check=ID_RUN + ": holds iff at every size no clean agent is flagged, i.e. the error of (11) in "
    "its coordinates stays below theta at the clean agents (headline: the largest clean residual / "
    "theta, <= 1). The same runs give C8's error at the C7b sizes: C7b and C8 are one piece of "
    "evidence, not two (the bound of Theorem 3 read in (11)'s coordinates). It can fail: the "
    "averaging baseline with (11)'s correction (sgn replaced by its argument, non-resilient, ours) "
    "run through the same rule at the same sizes flags clean agents (recorded: "
    "'baseline_clean_flagged'). Also recorded: the flags with the threshold an agent can compute "
    "(lambda_2 >= 4/(N^2 - N) in place of the true lambda_2; 'flagged_agent_threshold'). Until the "
    "fourth re-read of issue #30 C7b's rule was 'exactly the attacked bank flagged', whose attacked "
    "part holds by construction (now C7c). Does not decide (since the session-13 review of issue "
    "#30): its measured part is C8's bound read in (11)'s coordinates on the same runs, the attacked "
    "half (C7c) is by construction, and the reading of 'effective' is ours and was adopted after "
    "outcomes were known; counting it next to C8 would count one piece of evidence twice. The "
    "identification statement is decided through C8's bound, on which it rests",
    measured={"attack_sizes": id_amps, "residuals_11": resid_id, "flagged": flagged_id,
              "clean_over_threshold_max": id_clean, "flagged_baseline": flagged_id_base,
              "baseline_clean_flagged": id_base_false, "residuals_baseline": resid_id_base,
              "theta_agent": float(theta_agent), "flagged_agent_threshold": flagged_id_agent},
    threshold={"theta_11": float(theta_id), "clean_over_threshold_max": 1.0},
    holds=id_no_false,
    premise=(premise_id + "; the tested attacks are effective (every factor > 1, checked) and bank "
             f"{attack_bank}'s effect per unit attack is nonzero; and P_bar = V'PV is block-diagonal over "
             "the indicator groups (largest off-group entry <= 1e-9 times the largest entry; CORRECTED: "
             "the condition the paper does not state; as in C8, since C7b also runs (11); in the premise "
             "since the session-13 review of issue #30)",
             lyap_ok and assumptions and bool(id_amps) and offgroup_rel <= 1e-9),
    key="clean_over_threshold_max", tolerance=SIGN_IV,
    section="Attack identification by the paper's own rule (Sec. III-C, last paragraph)",
)
claims["C7c"] = results.claim(
    paper=ID_PAPER + ": the attacked agent finds that it is corrupted",
    source="Sec. III-C (last paragraph), Sec. V",
    check=ID_RUN + ": the attacked agent is flagged at every size. True by construction, not "
    "evidence: the sizes are f a_eff with a_eff = 2 theta / (effect per unit attack), so the attacked "
    "agent's effect is 2 f theta and its residual 2 f theta - |x_bar_k| > theta whenever the error of "
    "(11) stays below theta, which is C7b's measured part (headline: the smallest attacked residual / "
    "theta, about 2 x 1.25)",
    measured={"attacked_over_threshold_min": id_margin,
              "attacked_flagged": {k: attack_bank in f for k, f in flagged_id.items()}},
    threshold={"attacked_over_threshold_min": 1.0},
    holds=bool(id_amps) and all(attack_bank in f for f in flagged_id.values()),
    basis="by-construction", key="attacked_over_threshold_min", tolerance=SIGN_IV,
    section="Attack identification by the paper's own rule (Sec. III-C, last paragraph)",
)
claims["X7"] = results.claim(
    paper="(ours) the identification residuals ||z_i - W_i x_hat_i||_inf of (6) are those the offset "
    "law predicts, and the attacked agent's is the largest (a comparison across agents, which no "
    "single agent can make: not the paper's rule, see C7)",
    source="ours (offset law; Sec. III-C's comparison)",
    check=f"mean over the last {final_window:g} s of ||z_i - W_i x_hat_i||_inf: the attacked agent's "
    "is the largest (headline: its margin over the largest clean one), and every agent's equals "
    "the offset law's prediction within the chattering tolerance kappa dt x10 (coordinates)",
    measured={"residual": resid_meas, "predicted": resid_pred,
              "max_deviation": float(np.abs(resid_meas - resid_pred).max()),
              "margin": float(resid_meas[k_att] - clean_max)},
    threshold={"max_deviation": tol["coord"], "margin": 0.0},
    holds=bool(int(np.argmax(resid_meas)) == k_att)
    and float(np.abs(resid_meas - resid_pred).max()) <= tol["coord"],
    premise=("the attack's steady effect p lies in static coordinates (the offset law applies)",
             law_premise),
    key="margin", tolerance=SIGN_IV,
    section="Attack identification (Section III-C, Conclusion; Fig. S2, ours)",
)
# C8 cannot fail at the example if even the non-resilient estimators meet its bound: the averaging
# baseline at every attack size and agent 1's own estimate V_k z_k (last window, 2-norm)
nonres_err2 = float(max(np.linalg.norm((base["xh"] - base["x"][:, None])[last], axis=2).max(),
                        np.linalg.norm(own_all[last] - sim["x"][last].transpose(0, 2, 1), axis=2).max()))
claims["C8"] = results.claim(
    paper="Theorem 3: for Lyapunov-stable plants, (5) + (11) gives limsup ||x_hat_i - x|| <= "
    "(N n^2 + sqrt(n)) sqrt(N) ||V P_bar^(-1/2)|| / (gamma lambda_2)",
    source="Sec. III-C, Theorem 3, (11)",
    check="last-window max ||x_hat_i - x||_2 <= the bound (the bound depends on our P of (11), whose "
    "scale P_scale is MISSING and swept: P_bar = V'PV and the basis V are recorded to recompute it), "
    "at the example's attack AND at the large attacks of C7b (f a_eff, f in "
    "id_attack_factors; headline: the larger of the two errors). At the example's attack the bound "
    "cannot fail: it exceeds the error of every estimator run there, the non-resilient ones "
    "included ('non_resilient_max_error_2norm', = a ||v||, linear in a). At the C7b sizes the "
    "non-resilient averaging baseline with (11)'s correction exceeds the bound "
    "('non_resilient_max_error_2norm_C7b'), so there the rule can fail: it decides (until the "
    "round-2 review of issue #30 it was evaluated at the example's attack only and did not decide). "
    "P_bar block-diagonal over the indicator groups (the condition under which (11) is the paper's "
    "algorithm; CORRECTED: unstated) is part of the premise (until the fourth re-read of issue #30 "
    "it sat in the holds rule)",
    measured={"max_error_2norm": max(maxerr2_11, err2_id), "max_error_2norm_example": maxerr2_11,
              "max_error_2norm_C7b": err2_id, "lyapunov_max_eig": lyap_max, "offgroup": offgroup,
              "offgroup_relative": offgroup_rel, "P_scale": float(P_scale),
              "non_resilient_max_error_2norm": nonres_err2,
              "non_resilient_max_error_2norm_C7b": err2_id_base,
              "theta_sum_offsets": sums_11, "P_bar": P_bar, "basis_V": V},
    threshold={"bound": float(thm3_bound), "offgroup_relative": 1e-9},
    holds=max(maxerr2_11, err2_id) <= thm3_bound,
    premise=("the plant is Lyapunov stable: our P = P_scale T^-T T^-1 satisfies PA + A'P <= 0 "
             "(max eigenvalue <= 1e-9 times the largest entry of P), and P_bar = V'PV is "
             "block-diagonal over the indicator groups (largest off-group entry <= 1e-9 times the "
             "largest entry; CORRECTED: the condition the paper does not state)", lyap_ok and offgroup_rel <= 1e-9),
    key="max_error_2norm", tolerance=SIGN_IV, decides=True, section="Variant (11) and Theorem 3",
)
lam2_formula = {"ring": 2 * (1 - np.cos(2 * np.pi / N)), "all-to-all": float(N)}
claims["C9"] = results.claim(
    paper="Remark 2: lambda_2 = 2(1 - cos(2 pi / N)) on a ring (decreasing in N), = N on the "
    "all-to-all graph",
    source="Sec. II, Remark 2",
    check="networkx algebraic_connectivity vs the closed forms for N = 3..12 (<= 1e-8); the "
    "demo graphs' eigenvalues (<= 1e-12). By construction: networkx's eigenvalue of a ring or "
    "complete graph against the closed form is an identity of linear algebra, not evidence",
    measured={"max_deviation": remark2_dev, **{g: r["lambda2"] for g, r in runs.items()}},
    threshold={"max_deviation": 1e-8, **lam2_formula},
    holds=remark2_dev <= 1e-8 and bool(np.all(np.diff(lam2_ring_seq) < 0))
    and all(abs(runs[g]["lambda2"] - v) <= 1e-12 for g, v in lam2_formula.items()),
    key="max_deviation", basis="by-construction",
    section="Section II-B — Theorem 1 across graphs and gains",
)
claims["C10"] = results.claim(
    paper="Section IV: on the ring agent 1 cannot obtain resilient estimates of span{v1, v2} "
    "from its neighbours' measurements alone",
    source="Sec. IV, final remark",
    check="number of banks observing v1 among agent 1 and its neighbours < 2q + 1. By construction: "
    "the declared ring orders are exactly those for which the remark holds (the space excludes the "
    "rings where agent 1 neighbours banks 2 and 3), so this checks our construction, not the paper",
    measured={"neighbourhood": [i + 1 for i in nbhd_1], "observing_banks": local_voters},
    threshold={"2q+1": 2 * q + 1},
    holds=local_voters < 2 * q + 1, basis="by-construction",
    key="observing_banks",
    section="Final remark of Section IV — no local majority for agent 1",
)
innov_max = float(np.abs(innov_k[last]).max())  # the last window (the rule until the fourth re-read)
# every window of final_window seconds from the attack's start to the end of the run
win_edges = np.arange(attack_start, T_ex - 1e-9, final_window)


def window_mask(lo: float) -> np.ndarray:
    """Recorded times in [lo, lo + final_window), the last window closed at T_ex."""
    hi = lo + final_window
    upper = t_ex <= T_ex + 1e-9 if hi >= T_ex - 1e-9 else t_ex < hi - 1e-9
    return (t_ex >= lo - 1e-9) & upper


innov_windows = [float(np.abs(innov_k[window_mask(lo)]).max()) for lo in win_edges]
innov_peak_t = float(t_ex[after][int(np.argmax(np.abs(innov_k[after])))])
claims["C11"] = results.claim(
    paper="Footnote 3: agent 1 \"could not identify whether it is compromised or not, by only "
    "observing its own measurement\"",
    source="Sec. IV, footnote 3",
    check="premise (identities, by construction, not part of the rule): ||Av|| <= 1e-9 for "
    "v = [1,0,1,0,1,0] scaled to C_k v = 1, and |-F_k^-1 L_k - W_k v| <= 1e-6. Measured: over the "
    f"last {final_window:g} s |z_k - W_k(x + a v)| <= 1e-2 (the tail of bank k's transient after "
    "the attack step), and in EVERY window of final_window seconds from the attack's start to the "
    "end of the run the innovation of (5) stays <= 1e-3 (headline: the largest window max). Until "
    "the fourth re-read of issue #30 only the last window was checked ('innovation_last_window'); "
    "the innovation jumps at the attack's step (its peak and time are recorded): the step itself is "
    "visible in agent 1's own data, only the steady state is not. Fails by construction of a step "
    "attack (since the session-13 review of issue #30 marked so): just after the step the partial "
    "observer has not moved, so the innovation jumps by |a| (here pi/3 >> 1e-3) in the first window "
    "whatever the estimator; the outcome is not evidence and does not decide",
    measured={"Av": A_v, "gain_identity": gain_identity, "z_shift": z_shift,
              "innovation": max(innov_windows), "innovation_by_window": innov_windows,
              "window_starts_s": [float(w) for w in win_edges], "innovation_last_window": innov_max,
              "innovation_peak_time_s": innov_peak_t},
    threshold={"Av": 1e-9, "gain_identity": 1e-6, "z_shift": 1e-2, "innovation": 1e-3},
    holds=z_shift <= 1e-2 and max(innov_windows) <= 1e-3,
    premise=(f"bank {attack_bank} observes the kernel of A (C_k v != 0), so a constant attack "
             "looks like a shift of the plant state; Av = 0 and -F_k^-1 L_k = W_k v (identities)",
             bool(sees_kernel) and A_v <= 1e-9 and gain_identity <= 1e-6),
    key="innovation", tolerance=SIGN_IV, basis="by-construction",
    section="Why agent 1 alone is fooled (footnote 3)",
)
acc_ours, acc_half = acc_table[label_ours][0], acc_table[label_half][0]
acc_eul = acc_table[label_euler][0]
dev_u = acc_runs[label_unstable]
quarter = accuracy_T / 4
euler_growth = float(dev_u[t_acc >= 3 * quarter].max() / dev_u[(t_acc >= quarter)
                                                              & (t_acc < 2 * quarter)].max())
claims["X1"] = results.claim(
    paper="(ours) integrator choice for the discontinuous right-hand side",
    source="ours",
    check="RMS deviation from the accuracy_ref_dt reference: exponential Euler (dt_ex) < explicit "
    "Euler (dt_ex); halving dt divides it by 1.5..2.5 (order one; headline: that ratio); explicit "
    "Euler at three times its stability limit: spectral radius of I + dt M > 1 and its deviation over the "
    "last quarter of the horizon exceeds that over the second quarter (it grows)",
    measured={"rms_deviation": {k: v[0] for k, v in acc_table.items()},
              "order_ratio": acc_ours / acc_half, "euler_stability_limit": euler_dt_max,
              "spectral_radius_euler": {f"{k:.3g}": v for k, v in rho_euler.items()},
              "euler_unstable_growth": euler_growth},
    threshold={"order_ratio": [1.5, 2.5], "spectral_radius": 1.0, "euler_unstable_growth": 1.0},
    holds=acc_ours < acc_eul and 1.5 <= acc_ours / acc_half <= 2.5
    and rho_euler[dt_unstable] > 1.0 and euler_growth > 1.0,
    key="order_ratio",
    tolerance=results.Tolerance(rtol=0.05, atol=tol["inf"], reason="RMS of sign-driven chattering "
                                "against a reference; rounding moves it at the chattering level"),
    section="Integrating the discontinuous dynamics",
)
claims["X2"] = results.claim(
    paper="(ours, not a statement of the paper) the final distance of (4) to the median set "
    "shrinks as gamma grows; Theorem 1 only bounds it by a quantity proportional to 1/gamma",
    source="ours",
    check="sweep: max over agents of the distance over the last "
    f"{settle_fraction:.0%} of the horizon non-increasing in gamma on every graph, up to "
    f"{CHATTER_STEPS} dt (chattering); headline: the largest increase",
    measured={**{g: r["distance"] for g, r in sweep.items()},
              "largest_increase": max(float(np.diff(r["distance"]).max(initial=0.0))
                                      for r in sweep.values())},
    threshold={"gammas": gam_sweep, "largest_increase": tol_ii},
    holds=all(bool(np.all(np.diff(r["distance"]) <= tol_ii)) for r in sweep.values()),
    key="largest_increase", tolerance=SIGN_II,
    section="Section II-B — Theorem 1 across graphs and gains",
)
x3_dev = max(float(np.abs(r["distance"] - r["predicted"]).max()) for r in sweep.values())
x3_to_min = max(float(r["to_minimiser"].max()) for r in sweep.values())
claims["X3"] = results.claim(
    paper="(ours) the final state of (4) is a minimiser of sum_i s_i |z_i - x_i| + gamma/2 x'Lx, so "
    "the final distances are those of that minimiser (closed forms at the default data: "
    "0.4/gamma on ring-5; on ring-7, the lower end of a segment of minimisers, 0.6/7 at "
    "gamma = 5 and 1/(7 gamma) for gamma >= 10)",
    source="ours (equilibria of (4))",
    check="for every graph and gamma of the sweep: the final-window mean within "
    f"{CHATTER_STEPS} dt of the minimiser set (sup norm), and the measured distance to M within "
    f"{CHATTER_STEPS} dt of the minimiser's (an O(dt) error bound for explicit Euler; headline)",
    measured={"max_deviation": x3_dev, "to_minimiser": x3_to_min,
              "predicted": {g: r["predicted"] for g, r in sweep.items()}},
    threshold={"max_deviation": tol_ii, "to_minimiser": tol_ii},
    holds=x3_dev <= tol_ii and x3_to_min <= tol_ii,
    key="max_deviation", tolerance=SIGN_II,
    section="Section II-B — Theorem 1 across graphs and gains",
)
amps_sorted = sorted(base_offsets)
base_dev = max(float(np.abs(base_offsets[a] - base_pred[a]).max()) for a in amps_sorted)
base_scale = max(float(np.abs(base_pred[a]).max()) for a in amps_sorted)
claims["X4"] = results.claim(
    paper="(ours) the median is what rejects the attack: an averaging correction (sgn(r) "
    "replaced by r) is corrupted in proportion to the attack",
    source="ours",
    check="baseline theta-sum offsets within 1 % (+ the chattering tolerance) of "
    "(gamma L + D_s)^-1 D_s p, which is linear in the attack size (headline: the largest "
    "deviation); median offsets equal the offset law at every attack size (tolerance)",
    measured={"attack_sizes": amps_sorted,
              "baseline_offset_attacked": [float(base_offsets[a][k_att]) for a in amps_sorted],
              "median_offset_attacked": [float(amp_offsets[a][k_att]) for a in amps_sorted],
              "baseline_max_deviation": base_dev, "median_max_deviation": amp_dev},
    threshold={"baseline_max_deviation": 0.01 * base_scale + tol["sum"],
               "median_max_deviation": tol["sum"]},
    holds=base_dev <= 0.01 * base_scale + tol["sum"] and amp_dev <= tol["sum"],
    premise=("the attack's steady effect p lies in static coordinates (the offset law applies)",
             law_premise),
    key="baseline_max_deviation", tolerance=SIGN_IV, section="The steady-state offset law (ours)",
)
claims["X5"] = results.claim(
    paper="(ours, the paper's Fig. 1 is not available) at the paper's attack time the network has "
    "converged: the attack lands on estimates that follow the true theta-sum",
    source="ours (Sec. IV: attack from t = 10 s)",
    check="max |theta-sum error| of the attacked agent's own estimate and of every resilient "
    "estimate over the 2 s before the attack (headline) < 0.05 rad (ours)",
    measured={"pre_attack_sum_error_max": pre_sum_err},
    threshold={"pre_attack_sum_error_max": 0.05},
    holds=pre_sum_err is not None and pre_sum_err < 0.05,
    premise=("the attack starts after t = 0 (there is a pre-attack window)", pre_sum_err is not None),
    key="pre_attack_sum_error_max", tolerance=SIGN_IV,
    section="Fig. 1 — $\\theta_1+\\theta_2+\\theta_3$, agent 1's own estimate and the resilient estimates",
)
results.write_claims(results_path, claims, robustness="figures/lee2020/robustness.json")
written = json.loads(results.resolve(results_path).read_text())
for cid in claims:
    c = written[cid]
    rob = c.get("robustness")
    over = ("not swept" if not rob else
            f"{rob['outcomes']['holds']}/{rob['points']} points, one evaluation (the swept axes do "
            "not enter it)" if rob.get("evaluations") == 1 else
            f"{rob['outcomes']['holds']}/{rob['points']} points, {rob.get('evaluations')} evaluations")
    mark = (" [by construction]" if c.get("basis") == "by-construction" else
            " [decides]" if c.get("decides") else "")
    print(f"{cid:>3}: {c['verdict']:<13} | at this run: {results.point_verdict(c):<13} | {over}{mark}")

# %% [markdown]
# **Verdicts over the declared space** (`make robustness`: 72 points, `figures/lee2020/robustness.csv`;
# the verdict printed above is the one over the space, "at this run" the outcome at these
# parameters, "evaluations" the number of distinct outcome-value pairs over the 72 points; 24 points
# until the fourth re-read of issue #30 added the scale of $P$, `P_scale`, as an axis).
#
# * **One evaluation.** C1, C2, C9, X2 and X3 take the same value at all 72 points: the swept axes
#   (observer poles, basis scaling, ring order, initial guess, scale of $P$) belong to Section IV's
#   example and do not enter Section II (C1, C9, X2, X3) or the structural check C2. For them
#   "holds" is one measurement, not a result over the space. C6 is one evaluation too, and by
#   construction.
# * **C4** is not checked (deciding): Theorem 2's $\kappa^*$ is only said to exist; its proof's,
#   sufficient, is at least $Nn\sqrt n\,\|\bar A\|V(0)$ — recorded at every point as C4's
#   headline (`C4.value` in `robustness.csv`; from 1.089e+04 to 4.429e+04 over the 72 points) — against κ = 0.5, and gains above it
#   cannot be integrated at $dt=10^{-3}$. **C4a** (C4 at the example, recorded, not deciding) fails
#   its premise at every point. Its measurement, the
#   log–log slope of the error against γ (≤ −1/2 between consecutive gains above the chattering
#   tolerance), is **X9** (ours): the slopes are about −1 wherever the offset law applies (its offsets
#   are $\propto1/\gamma$); the averaging baseline, run at the same gains, has slopes about −0.19 and
#   −0.09 at the default point and fails the rule (recorded in C4a, `baseline_*`). `P_scale` does not
#   enter (6).
# * **C7 fails its premise wherever the paper's gains are used** (it does not decide): the threshold
#   $\theta$ (about 148 at γ = 2) depends neither on the ring order (all five-agent rings share
#   $\lambda_2$) nor on the scale of $P$, and the effect of the example's attack in (11)'s coordinates
#   does not depend on the poles or on the basis scaling ($-F_k^{-1}L_k=\mathcal W_kv$ exactly;
#   $\bar V$ is invariant to the scaling) but grows as $\sqrt c$ with `P_scale`: about 0.08, 1.6 and
#   2.2 at $c$ = 0.002432, 1, 1.819, against $2\theta\approx295$. What the rule would give there is
#   still measured (it flags no agent), and so is the plain reading (no agent-local rule from the
#   paper's bounds flags agent 1 at the paper's gains). With our tighter rule for (6) agent 1 is
#   not flagged at γ = 2 either; at the default point it is flagged from γ = 5 on.
# * **C7b** (not deciding since the session-13 review: it rests on C8's bound) tests the same
#   statement at effective attacks (`id_attack_factors` × the smallest, ≈ 192 rad at $c=1$, ≈ 3.9e3
#   rad at $c$ = 0.002432, ≈ 142 rad at $c$ = 1.819) at every point: the clean agents' residuals stay
#   below $10^{-5}\theta$ (measured), while the averaging baseline through the same rule flags clean
#   agents at the ×2 and ×10 sizes (default point, recorded). Agent 1's flag is C7c, by construction.
# * **C8** is evaluated at the example's attack and at the C7b sizes, where the non-resilient
#   baseline's error (≈ 1.6e3 at the default point) exceeds the bound ≈ 199; the bound scales as
#   $c^{-1/2}$ (≈ 4.0e3 at $c$ = 0.002432), and so do the C7b sizes, so the baseline exceeds it at
#   every scale. Its premise includes the block-diagonal $\bar P$.
# * **C11** (footnote 3, by construction, does not decide) is checked in every window after the
#   attack: the innovation of agent 1's observer jumps by $|a|$ at the attack's step (and peaks at
#   ≈ 3.2e3 with the literal "near −1" poles), so the claim fails wherever there is a step; in the last
#   window it is below 1e-3 everywhere (recorded).
# * **C12, C13, C14** (plug-and-play, decided with (11) since the session-13 re-review; Theorem 3's
#   premise holds wherever C8's does): C12 holds at all 72 points (worst ratio 9.9e-05 to 0.005), C13 holds at all 72 points (0.00011 to 0.0036), C14 fails at all 72 points (worst ratio 40.03 to 3900). Their measurements per point are in
#   `robustness.csv` (`<id>.holds`, `<id>.value`): eventual recovery within the 45 s window (C12,
#   C13) and the disruption of the untouched agents after each event (C14's worst ratio). The same
#   events with (6) (**X10, X11, X12**, ours, not deciding) fail Theorem 2's premise at every point;
#   their rules measured: X10 fails its premise at all 72 points, X11 fails its premise at all 72 points, X12 fails its premise at all 72 points; their rules are met at 72, 72 and 0 of the 72 points (X12's worst ratio 284.2 to 2697; `X10.holds` etc. in `robustness.csv`).
# * **X6** (the literal reading of C6, ours) is decided "fails" only where the (11) difference also
#   exceeds the tolerance at a four times smaller step (run at every point in paper mode).
# * **C3**: the resilient θ-sum offset does not move with the attack size; it is not small (0.65
#   rad for agent 1 at the default point, 1.125 rad with the paper's unnormalised basis). "Resilient"
#   here means bounded independently of the attack, not unaffected by it.
# * **X5**: fails exactly where `observer_poles = "near"` and `z0_guess = "off"`: with the literal
#   poles and an initial guess off by 0.5–1, the θ-sum estimates are still off by more than 0.05 rad
#   in the 2 s before the attack. With the shifted poles, or observers started at zero, the network
#   has converged when the attack comes.

# %% [markdown]
# ## Verdict
#
# **Which claims decide, and why.** The abstract, the Introduction and the Conclusion present the
# contributions: the distributed median solver that approximately recovers the median (Theorem 1:
# C1); fully distributed resilient state estimation (Theorem 2: C4, "arbitrary precision"; and its
# global version Theorem 3 for Lyapunov-stable plants: C8), with the demonstration of Fig. 1 (C3);
# the plug-and-play, initialization-free operation (Introduction, Conclusion: C12, agents
# re-initialised with arbitrary states; C13, an agent leaving and rejoining; C14, the Introduction's
# "seamlessly"); and the identification of the compromised sensors "by comparing the partial
# estimate $z_i$ of the local observer and the resilient estimate $\mathcal W_i\hat x_i$", which
# rests on Theorem 3's bound (C8). These decide, each a measured statement of the paper that can
# fail: a resilient estimate that followed the attack (C3, C8 at the C7b sizes, where the
# non-resilient baseline exceeds Theorem 3's bound), an error that does not tend to 0 as γ grows
# (C4, not checked: its gains cannot be integrated here), estimates of (11) that do not recover after a
# re-initialisation (C12) or a return (C13) within our
# 45 s window, and an estimation that the events disrupt (C14).
#
# **What changed in the session-13 re-review.** The plug-and-play claims are decided with (11), the
# method Sec. III-C itself names for "plug-and-play operation noted in the Introduction" on
# Lyapunov-stable plants; Theorem 3's premise holds at the example, so C12, C13 and C14 are decided
# there (the same events, states, windows and rules; C14's rule unchanged). The (6) runs are X10,
# X11, X12 (ours, recorded). C4 decides as not-checked (the rule's "a contribution that cannot be
# measured here"): κ = 0.5 is not shown to meet Theorem 2's premise (κ\* is only said to exist; the
# proof's is sufficient), and gains shown to meet it cannot be integrated; its evaluation at the
# example is C4a (recorded, not deciding).
#
# **What changed in the session-13 review of issue #30.** C4, C12, C13 and C14 carry Theorem 2's
# gain condition κ > κ\* in their premises (the paper's example runs at κ = 0.5; the only κ\* the
# paper gives, its proof's, is at least $1.8\cdot10^4$ at the default point): they fail their premise, as C5's demotion in
# session 12 already implied. The slope that C4 measured is X9 (ours). C14 is new: the Introduction's
# "seamlessly", quoted in C12 and C13 but not tested before; its rule was written after the review
# had seen the disruption. C7b no longer decides: its measured part is C8's bound on the same runs,
# its other half (C7c) is by construction, and the reading of "effective" that makes it testable was
# adopted after outcomes were known; identification rests on C8, which decides (deciding it as
# `not-checked` instead would deny a measurement that exists). C11 is marked by construction (it
# fails by construction of a step attack). **Not deciding:** C5 (convergence without attack at the
# paper's gains: outside Theorem 2's premise, a statement the paper does not make), C7 (premise
# fails at every point: lead decision D1 of round 2), C7b (above), C4a (C4 at the example, outside
# Theorem 2's premise), the structural check C2, the
# claims true (or false) by construction (C6, C7c, C9, C10, C11) and our own claims (X).
# The verdict is computed by `secest.repro.results.rescience_verdict` from the claims just written:
# [Re] if every deciding claim holds at the paper's example and over the space, [¬Re] if none holds
# at the example, [Re, partial] otherwise.

# %%
print(results.rescience_verdict(json.loads(results.resolve(results_path).read_text()))["line"])

# %% [markdown]
# ## Deviations from the paper
#
# | item | paper | here | why |
# |---|---|---|---|
# | Section II example | none given | the values of the parameter table; γ sweep on three graphs (ours) | Theorem 1 holds for any data; these make the median set an interval ($S$ even) and include one outlier |
# | Section II integrator | continuous time, Filippov solutions | explicit Euler, $dt=10^{-3}$ s; error bound $10\,dt$ where a value is compared with an exact one (X3) | below the stability step; chattering on the sliding surface is $O(dt)$ |
# | limsup | $t\to\infty$ | max (Section II) or mean (Section IV) over a final window of a finite horizon | a finite run can only bound the limsup |
# | Assumption 2 wording (Section II) | "more than $2q+1$" nonzero $C_i$ | at least $2q+1$ (CORRECTED) | consistent with Lemma 1 |
# | basis of Assumption 4 | existence only; Sec. IV writes the rigid-body span unnormalised | grouped projected-orthonormal basis, scaled by `basis_normalisation` ("unit" default, "integer" = the paper's $[1,0,1,0,1,0]^\top$, $[0,1,0,1,0,1]^\top$ and integer torsion shapes) (MISSING, swept) | the post-attack offsets scale with $\mathbf 1_\theta^\top v_1$ ($\sqrt3$ vs 3: 0.65 vs 1.125 rad for agent 1 at γ = 2) |
# | observer poles | "near −1" | "near": $-1,-1.1,\dots$; "shifted": real parts to −1 (MISSING, swept) | the literal reading gives gains up to 1.5e3 and transient peaks of 5e4 (banks 1, 3): the estimates converge only after ≈ 22 s, after the attack at 10 s |
# | ring order | "ring network" | one ring per class the final remark allows: 1-2-3-4-5 (default), 1-2-4-3-5, 1-4-2-3-5 (MISSING, swept) | the final remark excludes rings where agent 1 neighbours banks 2 and 3 |
# | initial conditions, horizon | not given | `x0_plant`; observers' guess `z0_guess` = `xhat0` zero (default) or off by 0.5–1 (MISSING, swept); `T_ex` = 40 s (ours) | see the provenance table |
# | horizon of the attack-size batch (C3's record) | not given | `amplitude_T` = 60 s (ours, since the session-13 review of issue #30): the all-coordinate error per attack size is read over its last window, checked settled (the previous window agrees within twice the chattering tolerance) | over `T_ex` = 40 s the error at $a=10$ rad was still a transient (0.370 rad in 35–40 s; 0.217 rad in 50–55 s and 55–60 s, as at $a=\pi/3$), which an earlier version read as growth with the attack |
# | integrator (Section IV) | not given | exponential Euler, $dt=10^{-3}$ s (ours); chattering tolerance $10\kappa\,dt\|v_l\|$ | justified in the integrator section |
# | footnote 3 | "zero-dynamics attack" | an output attack along the marginally stable eigenvector $v$ ($Av=0$) (CORRECTED wording) | it is stealthy for bank 1 alone, not an invariant-zero attack |
# | variant (11) | any $P>0$ with $PA+A^\top P\le0$ | $P=c\,T^{-\top}T^{-1}$, its scale $c$ = `P_scale` MISSING and swept ($\{1/\lambda_{\max},1,1/\lambda_{\min}\}$); $\bar P$ block-diagonal over the indicator groups (CORRECTED: unstated condition; part of C8's premise) | otherwise $\bar P^{1/2}$ mixes unobservable coordinates into the sign arguments |
# | Theorem 3 proof / plug-and-play gain | $\bar x$ for the disagreement; "$\sqrt N/(4\bar s/(\bar N^2-N))$" | $\tilde x$; $\gamma=\|V\bar P^{-1/2}\|\sqrt{\bar N}(\bar N^2-\bar N)(\bar Nn^2+\sqrt n)/(4\bar s)$ (CORRECTED; used for the recorded Sec. III-C gains of C12–C14, the same number as printed at $\bar N=N$) | OCR drops tildes; $N$ and $\bar N$ mixed |
# | Theorem 2 at the paper's gains | "arbitrary precision" for κ > κ\*, γ > γ\* (κ\* only in the proof: $Nn\sqrt n\|\bar A\|\bar Me^{\|\bar A\|T}$) | κ = 0.5 is below the proof's κ\* (≥ $Nn\sqrt n\|\bar A\|V(0)\approx1.8\cdot10^4$ at the default point), which is sufficient only: κ = 0.5 is not shown to meet the premise, and gains shown to meet it cannot be integrated here, so C4 is not checked and decides so (since the session-13 re-review); its evaluation at κ = 0.5 is C4a (fails-premise, recorded; the session-13 review decided it; before, it was decided at κ = 0.5); its measurement, the log–log slope of the error under attack against γ ≤ −1/2 between consecutive gains above the chattering tolerance, is X9 (ours: half the $1/\gamma$ rate of the paper's bounds; the averaging baseline, which also decreases, fails it); offsets $O(1/\gamma)$ after the attack, independent of κ, predicted in closed form (X8, ours) | the theorem is semi-global and existential in the gains; (6) cannot be integrated at κ ≳ 10⁴ with $dt=10^{-3}$ (one sign step $\kappa\|v_l\|dt$ would be about 18 rad with the unit basis) |
# | remark after Theorem 3 | "the steady-state error depends only on the parameter γ" | in the paper's usage (the bound, Remark 2) it holds by inspection (C6, by construction); read literally it holds for (6) and fails for the steady state of (11) (X6, ours: 24 of 72 points, only at the smallest declared scale of P) | (11)'s correction mixes the static coordinate with the rate coordinate, on which $\bar A$ acts |
# | attack time | $t=10$ s; Fig. 1 not available | with the literal "near −1" poles and an off initial guess the network has not converged at 10 s (X5, ours: 54 of 72 points) | the observers' transient peaks (gains ≈ 1.5e3) and lasts ≈ 22 s |
# | attack identification | "by comparing $z_i$ with $\mathcal W_i\hat x_i$ … corrupted by the effective attack" (Sec. III-C, for (11); no threshold, "effective" undefined) | threshold $\theta$ assembled by us from the paper's bounds ($\varepsilon\to0$); "effective" read as an effect $>2\theta$ (ours), so the example's $\pi/3$ (effect ≈ 1.6, $2\theta\approx295$) is not effective: C7 fails its premise (recorded as "fails" before the review of issue #30, which read the example's attack as effective); at effective attacks the rule flags no clean agent (C7b, measured; C8's bound on the same runs, so it does not decide since the session-13 review) and agent 1 (C7c, by construction of the sizes); under the plain reading (no "effective") no agent-local rule from the bounds identifies the example's attack (recorded in C7); the (6) rule with $2\sqrt N/(\gamma\lambda_2)$ (ours) flags agent 1 from γ = 5, not at γ = 2; the cross-agent comparison (largest residual) is X7, ours | the paper states no explicit threshold and qualifies the attack as "effective" without defining it |
# | identification rule, what an agent can compute | compare $z_i$ with $\mathcal W_i\hat x_i$ for all $t\ge T'$; each agent knows $\bar N\ge N$ and $\lambda_2\ge4/(N^2-N)$ | residuals in (11)'s coordinates $\sqrt{\bar P}\mathcal W$ (the sign argument, where the bound holds), $\theta$ with the true $N$ and $\lambda_2(\mathcal L)$, mean over the final window (C7, C7b); the flags with the agent-computable threshold ($\lambda_2=4/(N^2-N)$: $\approx6.9\,\theta$) recorded in C7b | the tightest threshold the bounds give; with the agent-computable one the ×1.25 and ×2 attacks of C7b (residuals ≈ 369, 590 < 1020) are not flagged |
# | plug-and-play | "join or leave the network" at any time, no initialization, "seamlessly" (Introduction), "as seen in Theorem 2" (Conclusion); Sec. III-C's plug-and-play method is for (11): Lyapunov-stable plant, gains chosen from $\bar N$ and $\bar s$, $\kappa\gamma=1$ | **(11)** at the example's gains ($\kappa=0.5$, $\gamma=2$; Theorem 3 allows any κ, γ > 0) decides C12, C13, C14 (since the session-13 re-review; Theorem 3's premise holds at the example); Sec. III-C's own gains ($\bar N$ = `pnp_N_bar` = 5, $\bar s$ = `pnp_s_bar` = 0.1 rad, MISSING, declared: γ ≈ 2.8e4, κ = 1/γ) recorded; (6) at the example's gains recorded as X10–X12 (outside Theorem 2's gain condition). Events: agents re-initialised with arbitrary $\hat x_i$, $z_i$ once, at `pnp_time` (C12), and one agent leaving for `pnp_leave_duration` and rejoining with an arbitrary state (C13), eventual recovery within `pnp_recovery` = 45 s (ours: twice the known transient, set in round 3 of issue #30 after the 15 s window had failed); "seamlessly" (C14): the untouched agents' error over `final_window` after each event (after the leaving over min(`final_window`, `pnp_leave_duration`)) against the uninterrupted run's plus twice the chattering tolerance (ours, written after the session-13 review had seen the disruption with (6)) | the example is what the paper runs; with κ = 1/γ ≈ 3.6e-5 nothing recovers within any window we can run, so the example's gains decide; the window and the seamlessness rule are ours |
# | Appendix B item 7 | 4×4 real Jordan block missing its first row (OCR) | $[[\alpha,-\beta,1,0],[\beta,\alpha,0,1],[0,0,\alpha,-\beta],[0,0,\beta,\alpha]]$ (CORRECTED, not used numerically) | garbled |
# | basis construction | — | distinct eigenvalues only (our procedure refuses repeated ones) | the example has six distinct eigenvalues |
# | Fig. 1 | printed figure | our Fig. 1 for the four readings (printed figure not available in the OCR text) | checked against the caption and text only |
# | Fig. 1, red curve | "its estimate obtained by agent 1" | read as $\mathcal V_1z_1$, the θ-sum of agent 1's partial observer (5) ($o_1=n$, so it is a full-state estimate from bank 1 alone) (our interpretation) | the only estimate agent 1 forms without the network; footnote 3's argument is about it. Not $\hat x_1$, which is one of the blue resilient estimates |
# | extras (ours) | — | Theorem 1 sweep and the minimiser of $f_\gamma$ (X2, X3), integrator comparison (X1), offset law, averaging baseline (X4), identification residual (Fig. S2), κ map | acceptance of the reproduction issues |

# %%
manifest_path = run.finish(solver="exponential Euler (secest.core.systems.integrate_switched_linear); "
                           "CLARABEL for the offset law and the minimisers of f_gamma")
print("run manifest:", manifest_path.relative_to(results.repo_root()))
