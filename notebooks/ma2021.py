# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3 (secest)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # ma2021 — Probability-guaranteed distributed secure estimation with a neural network against falsified innovations
#
# L. Ma, Z. Wang, Y. Chen and X. Yi, "Probability-guaranteed distributed secure estimation for
# nonlinear systems over sensor networks under deception attacks on innovations", *IEEE
# Transactions on Signal and Information Processing over Networks*, vol. 7, pp. 465–, 2021.
#
# **Summary.** A nonlinear plant with unknown-but-bounded (ellipsoidal) noises is observed by
# $N$ sensors over a finite horizon. Every node runs an estimator that adds the innovations of its
# neighbours to its own. An adversary intercepts each transmitted innovation and, when a
# Bernoulli variable $\alpha_k$ fires, adds an unknown nonlinear function $\chi(\cdot)$ of it. The
# receiving node models $\chi$ as a one-layer neural network $W\phi(\cdot)$ plus a bounded residual
# and subtracts the expected injection $\bar\alpha\hat W_{ij}\phi(z_i)$. The weights are tuned by a
# two-scalar law (17) whose scalars come from an LMI (Theorem 1, OP1). The gains come from a
# recursive LMI (Theorems 2–3, OP2). It treats Taylor remainders, noises, the NN residual and the
# weight error with the S-procedure, and through Markov's inequality it guarantees
# $P\{\tilde x_{i,k}\in\mathcal X(0,\mathfrak B_k)\}\ge p$.
#
# **Verdict: [Re, partial].** The machinery reproduces: the recursive LMIs are feasible and
# certified at every step (C5), the NN-based estimator tracks the state (C1), the probabilistic
# ellipsoid holds at every node and step (C2, very conservatively), the Theorem 1 weight bound
# holds, by construction on this example (C4), and the re-derived error dynamics hold to machine
# precision (X1). These guarantees rest on the paper's premise (12)–(13) for the missing Taylor
# scales $L_i$, $\aleph_i$. We fix them by a rule chosen in advance, the smallest multiple of 0.05
# for which the premise holds along the runs: $0.15I$ (X2 holds; the earlier default $0.1I$
# violates it at $k=0$). **The headline comparison C3 does not hold at that scale.** The RMSE of
# the NN-based estimator is [0.107, 0.057, 0.104] against [0.099, 0.057, 0.100] for the
# conventional one; NN is better only at node 2, by 0.4 %, and worse on the network average
# (0.089 against 0.085). On three further $\alpha_k$ realisations the conventional estimator is
# better at every node, and in C1 its largest late error is the smaller one (0.105 against 0.115).
# C3 held at $0.1I$, where the premise fails, and it holds at every node under two alternative
# OCR readings ($E_1$ amplitude 0.1; $\sin 2x^{(2)}$ in $g_1$), so the comparison hinges on missing
# and illegible values. Either way the mechanism is **not** learning: OP1 sends the NN weights to
# zero at the first step (E4), and the robust OP2 design switches the neighbour innovations off
# ($\|H_{ij}\|\approx4\cdot10^{-4}$, E5), so the "NN estimator" is $N$ decoupled local estimators,
# identical to (3) with the attack-aware gains and no compensation. Figures 1–8 are reproduced
# qualitatively only: $f$, $g_i$, $\bar\alpha$ and the initial values are reconstructions from a
# garbled OCR, and $L_i$, $\aleph_i$ and the conventional design are missing.

# %% tags=["parameters"]
mode = "paper"  # "paper": full runs; "fast": short horizon and fewer extras for the tests
T = 40  # horizon [0, T] (RECONSTRUCTED from the 0..40 time axes)
seed = 0  # seed of the alpha_k realisation (MISSING)
extra_seeds = 3  # further alpha_k realisations for C2 and the sensitivity table (ours)
alpha_bar = 0.67  # Prob{alpha_k is 1} (RECONSTRUCTED from the OCR "o: 067")
p = 0.8  # probability level of (10)-(11) (PAPER)
e1 = 3.0  # bound on ||W_ij||_F, Assumption 2 (PAPER)
e3 = 3.0  # bound on ||delta_j||, Assumption 2 (PAPER)
# f and g_i as lists of terms [coef, fn, var, freq, shift] = coef * fn(freq * x^(var) + shift), fn in
# {"x", "sin", "cos"}; every coefficient, superscript and frequency is RECONSTRUCTED from the OCR
f_terms = [[[0.5, "x", 1, 1, 0], [0.45, "sin", 2, 1, 0], [0.25, "x", 2, 1, 0]],
           [[0.4, "cos", 1, 1, 0], [0.3, "x", 1, 1, 0], [0.6, "x", 2, 1, 0]]]  # "0d5" read 0.45
g1_terms = [[[0.15, "x", 1, 1, 0], [0.35, "sin", 2, 1, 0], [0.2, "x", 2, 1, 0]],
            [[0.5, "sin", 1, 1, 0], [0.15, "x", 1, 1, 0], [0.35, "x", 2, 1, 0]]]  # "sin(2z" read sin x
g2_terms = [[[0.3, "cos", 1, 1, 0], [0.3, "sin", 2, 1, 1], [0.4, "x", 1, 1, 0]],
            [[0.45, "cos", 2, 1, 0], [0.25, "x", 1, 1, 0], [0.5, "x", 2, 1, 0]]]
g3_terms = [[[0.5, "sin", 1, 1, 0], [0.4, "x", 1, 1, 0], [0.2, "x", 2, 1, 0]],
            [[0.4, "sin", 2, 1, 0], [0.1, "x", 2, 1, 0], [0.3, "x", 1, 1, 0]]]
E1_amp = 0.01  # amplitude of cos(k+1) in E_1k (RECONSTRUCTED from "0.2401cos"; 0.1 also possible)
E3_amp = 0.05  # amplitude of sin(k) in E_3k (RECONSTRUCTED)
x0 = [2.0, 2.0]  # initial state; 1st entry PAPER, 2nd MISSING (chosen so that Assumption 3 holds)
xhat0 = [[1.5, 1.8], [1.7, 1.9], [1.8, 1.5]]  # initial estimates (nodes 2-3 RECONSTRUCTED)
P0 = [[0.6887, -0.0588], [-0.0588, 0.7390]]  # Assumption 3 (PAPER)
W0 = [[1.0, 0.0], [0.0, 1.0]]  # initial NN weights, every link (RECONSTRUCTED)
Q0 = [[20.0, 0.0], [0.0, 20.0]]  # Assumption 3 weight-error shape (PAPER)
L_scale = None  # scale of L_i in (12) (MISSING); None: the rule below, a number overrides it
aleph_scale = None  # scale of aleph_i in (13) (MISSING); None: the rule below
taylor_grid = 0.05  # rule: smallest multiple of this for which (12)-(13) hold along both runs
taylor_max = 0.5  # the rule gives up above this scale (ours)
varpi_form = "sum"  # varpi of (17): "sum" over j in N_i as reconstructed, or "per_link" (H_ij only)
shared_multipliers = False  # one Gamma_k for all nodes as printed (True) or one per node
shared_diag_steps = 2  # steps of the printed shared-multiplier LMI (22) run as a diagnostic
r_bound = "lumped"  # "lumped": r^T r below N^2 as printed; "per_link": one multiplier per link
lam2_max = 1000.0  # box on |lambda2| in OP1 (ours, numerical)
eps_lmi = 1e-6  # strictness margin: every LMI M is imposed as M + eps_lmi I negative semidefinite
cert_tol = 1e-8  # certificate: max eig of every solved LMI matrix at most cert_tol
solver = "CLARABEL"  # primary SDP solver
fallback_solver = "SCS"  # visible fallback
op3_scale = 2.0  # fixed ellipsoid B is op3_scale times I for the OP3 run (MISSING)
settle_k = 10  # C1: errors measured from this step on
track_tol = 0.2  # C1: |error| bound read from the Fig. 3-4 data range
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/ma2021"
results_path = "figures/ma2021/claims.json"

# %%
import copy
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field

import cvxpy as cp
import matplotlib.pyplot as plt
import numpy as np

from secest import covariance, graphs, montecarlo, plotting, results
from secest import lmi as slmi

print(results.environment_summary())
print("cvxpy:", cp.__version__, "solvers:", cp.installed_solvers())

run = results.Run("ma2021", globals())
if mode not in ("paper", "fast"):
    raise ValueError(f"mode must be 'paper' or 'fast', found {mode!r}")
if r_bound not in ("lumped", "per_link"):
    raise ValueError(f"r_bound must be 'lumped' or 'per_link', found {r_bound!r}")
if varpi_form not in ("sum", "per_link"):
    raise ValueError(f"varpi_form must be 'sum' or 'per_link', found {varpi_form!r}")
for _name, _val in (("L_scale", L_scale), ("aleph_scale", aleph_scale)):
    if _val is not None and not float(_val) > 0:
        raise ValueError(f"{_name} must be None (rule) or positive, found {_val!r}")
T_run = int(T) if mode == "paper" else min(int(T), 8)
n_extra = int(extra_seeds) if mode == "paper" else 1
FIG_DIR = results.resolve(fig_dir)
plotting.setup(enabled=figures)
CLARABEL_OPTS = {"tol_feas": 1e-7, "tol_gap_abs": 1e-7, "tol_gap_rel": 1e-7}
SCS_OPTS = {"max_iters": 20000}  # bounds the cost of a fallback (a few seconds)
warnings.filterwarnings("ignore", message="Solution may be inaccurate")  # status is checked

# %% [markdown]
# ## Parameter provenance
#
# The OCR of the paper interleaves its two PDF columns, so most of Section IV is garbled. The
# tags are: **PAPER** (legible), **RECONSTRUCTED** (read from a damaged OCR fragment; the fragment
# is quoted), **MISSING** (not in the paper; our default) and **CORRECTED** (printed, but wrong).
#
# | quantity | value | tag | raw OCR fragment → reading / reason |
# |---|---|---|---|
# | $N$, graph | 3 nodes, $\Theta=[[0,1,0],[1,0,1],[0,1,0]]$ | PAPER | "01 0 / -1 0 1 / 01 0" (the "-1" is the bracket and a 1) |
# | $n_x,n_y,n_v,n_u,n_\phi$ | 2, 2, 1, 1, 2 | RECONSTRUCTED | from the shapes of $B_k$, $E_{i,k}$, $\phi$ |
# | $B_k$ | $[0.1+0.01\cos(k+1);\ 0.2+0.01\sin k]$ | PAPER | "0.1+ 0.01cos(k + 1) / By, = 0.2+ 0.01 sin(k)" |
# | $E_{1,k}$ (`E1_amp`) | $[0.25;\ 0.2+0.01\cos(k+1)]$ | RECONSTRUCTED | "[ 0.25 / LR 0.2401cos(k+1)": "+0.01" read as "401". Alternative: "+0.1cos" (`E1_amp` = 0.1), the simpler reading if "4" is a "+" and "01" is "0.1"; it is a row of the sensitivity table |
# | $E_{2,k}$ | $[0.2;\ 0.15+0.1\sin 2k]$ | PAPER | "0.2 / E26=1 0,15+ 0.1 sin(2k)" |
# | $E_{3,k}$ (`E3_amp`) | $[0.25+0.05\sin k;\ 0.15]$ | RECONSTRUCTED | "[ 0.25 4 0.05sin(k / B3 = 015 ()}": "4" is "+" |
# | $f$ (`f_terms`) | $[0.5x^{(1)}+0.45\sin x^{(2)}+0.25x^{(2)};\ 0.4\cos x^{(1)}+0.3x^{(1)}+0.6x^{(2)}]$ | RECONSTRUCTED | "057 +0d5sin(@y)) +0.250 1 / 0.4cos(z; ) + 0.3z, + 0.6z,": superscripts lost (the variable of every term is a parameter; the brief found 31 of 32 assignments bounded, so the data cannot tell them apart). "0d5" read 0.45; alternative 0.05 (the brief's other reading), a row of the sensitivity table |
# | $g_1$ (`g1_terms`) | $[0.15x^{(1)}+0.35\sin x^{(2)}+0.2x^{(2)};\ 0.5\sin x^{(1)}+0.15x^{(1)}+0.35x^{(2)}]$ | RECONSTRUCTED | "0.1521" + 0.35 sin(2z(") + 0.2z / 0.5 Sln(%(f)) + 0-1551(3) + 0-3551(:)": the "2" after "sin(" read as the superscript of $x^{(2)}$; alternative $\sin(2x^{(2)})$ (frequency 2 in the term list), a row of the sensitivity table |
# | $g_2$ (`g2_terms`) | $[0.3\cos x^{(1)}+0.3\sin(x^{(2)}+1)+0.4x^{(1)};\ 0.45\cos x^{(2)}+0.25x^{(1)}+0.5x^{(2)}]$ | RECONSTRUCTED | "0.3:05C ) 403 sm(argC ) + 1)+ 0.417,(C ) / 0.45 Cos(x(2)) +0.252% £ 0520" |
# | $g_3$ (`g3_terms`) | $[0.5\sin x^{(1)}+0.4x^{(1)}+0.2x^{(2)};\ 0.4\sin x^{(2)}+0.1x^{(2)}+0.3x^{(1)}]$ | RECONSTRUCTED | "0.5 sin(az:,(C )) + O.4:c§C )+ 0-2$§c) / 0.4 sin(x,(f)) +0.1x§f) +0.3x§€1)" |
# | $v_k$, $\mu_k$ ($u_k$) | $0.3\cos 2k$, $0.4\sin k$ | PAPER | "We select v_k = 0.3cos(2k) and u(k) = 0.4sin(k)" |
# | $V_k$, $U_k$ | 1, 1 | PAPER | |
# | $e_{1ij}=e_2=e_{3j}$ | 3 | PAPER | "Set e1i = e2 = e3 = 3" (`e1`, `e3`; $e_2$ is never used) |
# | $\phi(z)$ | $[\tanh z^{(1)};\ \tanh z^{(2)}]$ | PAPER | |
# | $\chi(z)$ | $[0.15\sin z^{(1)};\ 0.30\cos z^{(2)}]$ | PAPER | "0.15sin(2}) / 0'30COS(Z£213)" |
# | `p` | 0.8 | PAPER | "Set p = 0.8" |
# | `alpha_bar` | 0.67 | RECONSTRUCTED | "o= 067". We read "0.67" with the decimal point lost, as in "015" → 0.15 for $E_3$. The brief reads "0.6," (comma misread as 7); 0.6 is a row of the sensitivity table |
# | `x0` | $[2.0;\ 2.0]$ | PAPER (1st entry), MISSING (2nd entry) | "B0 = 2.0 } … / R [ O I": the 2nd entry has no support in the OCR. It is **chosen** so that Assumption 3 holds at every node (initial quadratic forms 0.44, 0.15, 0.42): 1.0 gives 1.14, 1.17, 0.38 and 0.1 gives 4.1, 4.4, 2.7, both violating it. "x0 = [2, 1]" is a row of the sensitivity table |
# | `xhat0` | $[1.5;1.8]$, $[1.7;1.9]$, $[1.8;1.5]$ | PAPER (node 1), RECONSTRUCTED (nodes 2–3) | "[ 1.7 1.8 / … 19 } … [ 1.5 ]": two-column layout |
# | `P0` | $[[0.6887,-0.0588],[-0.0588,0.7390]]$ | PAPER | |
# | `W0` | $I_2$ on every link | RECONSTRUCTED | "10 } / 101 ’" |
# | `Q0` | $\mathrm{diag}(20,20)$ | PAPER | |
# | `T` | 40 | RECONSTRUCTED | every time axis runs 0–40 |
# | `L_scale`, `aleph_scale` | $L_i=\aleph_i=sI_2$, $s$ by the rule (`None`) | MISSING | the paper gives no Taylor-remainder scales. Rule fixed in advance (`taylor_grid` = 0.05, `taylor_max` = 0.5): the smallest multiple of 0.05 for which the premise (12)–(13), $\|\Delta\|\le1$, holds along both runs (X2). The previous default 0.1 (the brief's "usual size") violates it at $k=0$ (ratios 0.103 for $f$, 0.115 for $g$) and is a row of the sensitivity table, as are 0.05 and 0.2 |
# | conventional design | attack-unaware OP2 | MISSING | the paper only says "characterised by (3)"; we design (3) with the same LMI, without the attack terms, and run it on the falsified data |
# | `seed` | 0 | MISSING | $\alpha_k$ is the only randomness; one Bernoulli draw per step, shared by all links |
# | `shared_multipliers` | False | DEVIATION (design choice) | the printed (22) shares one $\Gamma_k$ among the $N$ inequalities; that is not wrong, only more conservative. One $\Gamma_{i,k}$ per node is a valid relaxation (a separate S-procedure per inequality). The printed form is run for `shared_diag_steps` = 2 steps as a diagnostic (X6) |
# | `r_bound` | lumped, $r^\top r\le N^2$ | PAPER | (23) as printed |
# | $\varpi_{i,k}$ of (17) (`varpi_form`) | $\bar\alpha\sum_{j\in\mathcal N_i}\theta_{ij}H_{ij,k}^\top\Psi_{i,k+1}^\top z_{i,k+1}$ ("sum") | RECONSTRUCTED | "a Z 9in5,;€‘1’2;€+12@1€+1 JEN;": $\bar\alpha$, a sum over $j\in\mathcal N_i$, $\theta_{ij}$, $H^\top$, $\Psi^\top_{k+1}$, $z_{k+1}$. Alternative "per_link": only $H_{ij}$ of the link. Immaterial on this example: OP1 returns $\lambda^{(2)}=0$ (E4) |
# | $P_k$ in Lemma 4 | $P_k=(1-p)\mathfrak B_k$ | CORRECTED (E1) | printed with a factor $\tfrac1{1-p}$ that belongs to the inverses; only this reading gives (11) by Markov's inequality |
# | OP3 (33) | min $\rho=1-p_{k+1}$ with $-\rho\mathfrak B$ in (30) | CORRECTED (E2) | printed "min $q_k=1/(1-p_k)$" is not convex and points the wrong way |
# | `taylor_grid`, `taylor_max` | 0.05, 0.5 | MISSING | grid and ceiling of the Taylor-scale rule |
# | `shared_diag_steps` | 2 | MISSING | length of the shared-multiplier diagnostic (X6); from $k=2$ on the solvers no longer certify that LMI |
# | `eps_lmi` | $10^{-6}$ | MISSING | (18) is strict; the margin must exceed the solver tolerance ($10^{-7}$) for the numpy certificate at `cert_tol` = $10^{-8}$ |
# | `lam2_max` | $10^3$ | MISSING | box on $\lambda^{(2)}$; without it OP1 has an unbounded optimal face when $\varpi\approx0$ (never active) |
# | `op3_scale` | $\mathfrak B=2I$ | MISSING | fixed ellipsoid for OP3 |
# | `settle_k`, `track_tol` | 10, 0.2 | MISSING | C1: errors within the ±0.2 band of the Fig. 3–4 data after the transient |

# %% [markdown]
# ## Setup: network, plant, noises (1)–(2), attack (4)–(5), neural network (6)–(7)
#
# The graph $\mathcal G=(\mathcal V,\mathcal E,\Theta)$ has $\theta_{ij}>0$ when node $j$ sends to
# node $i$. $\mathcal N_i=\{j:\theta_{ij}>0\}$, and there are no self-loops. The plant on $[0,T]$ is (1):
#
# $$x_{k+1}=f(x_k)+B_kv_k,\qquad y_{i,k}=g_i(x_k)+E_{i,k}\mu_k,$$
#
# with one measurement-noise signal $\mu_k$ shared by all sensors (the paper's (16) carries it as
# $\mathcal E_k(1_N\otimes I_{n_u})\mu_k$). Assumption 1, (2): $v_k^\top V_k^{-1}v_k\le1$ and
# $\mu_k^\top U_k^{-1}\mu_k\le1$.
#
# Node $j$'s innovation is $z_{j,k}=y_{j,k}-g_j(\hat x_{j,k})$. The adversary adds $\chi(z_{j,k})$
# when $\alpha_k=1$ (4)–(5):
# $\tilde z_{j,k}=z_{j,k}+\alpha_k\chi(z_{j,k})$, with $\mathrm{Prob}\{\alpha_k=1\}=\bar\alpha$. There is
# one $\alpha_k$ per step, shared by all links (the paper gives it no link index), and
# $\tilde\alpha_k=\alpha_k-\bar\alpha$ has $E\tilde\alpha_k^2=\bar\alpha(1-\bar\alpha)=\sigma^2$ (21).
# The network model (6) is $\chi(z_{j,k})=W_{ij}\phi(z_{j,k})+\delta_{j,k}$, with
# $\|W_{ij}\|_F\le e_{1ij}$ and $\|\delta_{j,k}\|\le e_{3j}$ (7).

# %%
THETA = graphs.check_connected(np.array([[0, 1, 0], [1, 0, 1], [0, 1, 0]], dtype=float))
N = THETA.shape[0]
NX, NY, NV, NU, NPHI = 2, 2, 1, 1, 2
M = NY * NPHI  # length of rho(W) = vec of the rows of W
LINKS = [(i, j) for i in range(N) for j in range(N) if THETA[i, j] != 0]  # (receiver, sender)
NBRS = [[j for j in range(N) if THETA[i, j] != 0] for i in range(N)]


# the reading of the damaged example in use; `reading(...)` swaps it for the sensitivity rows
READING = {"f": f_terms, "g": [g1_terms, g2_terms, g3_terms], "E1_amp": E1_amp}
_FN = {"x": (lambda u: u, lambda u: np.ones_like(u)), "sin": (np.sin, np.cos),
       "cos": (np.cos, lambda u: -np.sin(u))}


def _map(terms, x):
    """sum of coef * fn(freq * x^(var) + shift) per row (the term lists of the parameters cell)."""
    return np.array([sum(c * _FN[fn][0](w * x[v - 1] + b) for c, fn, v, w, b in row)
                     for row in terms])


def _jac(terms, x):
    J = np.zeros((len(terms), NX))
    for r, row in enumerate(terms):
        for c, fn, v, w, b in row:
            J[r, v - 1] += c * w * _FN[fn][1](w * x[v - 1] + b)
    return J


def f(x):
    """Plant map f of (1) (RECONSTRUCTED); terms `f_terms`."""
    return _map(READING["f"], x)


def jac_f(x):
    """Phi_{i,k} = df/dx at the estimate, (12)."""
    return _jac(READING["f"], x)


def g(i, x):
    """Sensor map g_i of (1), node i = 0, 1, 2 (RECONSTRUCTED); terms `g<i+1>_terms`."""
    return _map(READING["g"][i], x)


def jac_g(i, x):
    """Psi_{i,k} = dg_i/dx at the estimate, (13)."""
    return _jac(READING["g"][i], x)


@contextmanager
def reading(**changes):
    """Temporarily replace entries of READING (alternative OCR readings, sensitivity table)."""
    old = {key: READING[key] for key in changes}
    READING.update(changes)
    try:
        yield
    finally:
        READING.update(old)


# the Jacobians are checked against central differences
_xt = np.array([1.3, -0.7])
_fd = [np.column_stack([(fun(_xt + h) - fun(_xt - h)) / 2e-6 for h in 1e-6 * np.eye(NX)])
       for fun in [f] + [lambda x, i=i: g(i, x) for i in range(N)]]
assert np.allclose(_fd[0], jac_f(_xt), atol=1e-8)
assert all(np.allclose(_fd[i + 1], jac_g(i, _xt), atol=1e-8) for i in range(N))


def B_mat(k):
    return np.array([[0.1 + 0.01 * np.cos(k + 1)], [0.2 + 0.01 * np.sin(k)]])


def E_mat(i, k):
    if i == 0:
        return np.array([[0.25], [0.2 + READING["E1_amp"] * np.cos(k + 1)]])
    if i == 1:
        return np.array([[0.2], [0.15 + 0.1 * np.sin(2 * k)]])
    return np.array([[0.25 + E3_amp * np.sin(k)], [0.15]])


def v_noise(k):
    return np.array([0.3 * np.cos(2 * k)])


def mu_noise(k):
    return np.array([0.4 * np.sin(k)])


def phi(z):
    """Activation phi(z) = tanh, elementwise (PAPER)."""
    return np.tanh(z)


def chi(z):
    """Injected function chi(z) of (4) (PAPER); unknown to the estimators."""
    return np.array([0.15 * np.sin(z[0]), 0.30 * np.cos(z[1])])


V_inv, U_inv = np.eye(NV), np.eye(NU)
# Assumption 1 holds: |v_k| <= 0.3 and |mu_k| <= 0.4 against V = U = 1
assert max(abs(v_noise(k)[0]) for k in range(T + 1)) <= 1.0

# %% [markdown]
# **The ideal weight.** $W_{ij}$ is not given. Theorem 1 (C4) can only be checked against some
# ideal weight, so we take the least-squares fit $W^\star$ of $\chi(z)\approx W\phi(z)$ on a
# $21\times21$ grid of $[-1,1]^2$, which covers every innovation of the run. $\tanh$ is odd and
# $0.3\cos z^{(2)}$ is even, so the second row of $\chi$ cannot be fitted and the residual
# $\delta\approx0.3$ is carried by $e_3$.

# %%
grid = np.linspace(-1.0, 1.0, 21)
Zg = np.array([[a, b] for a in grid for b in grid])
W_star = np.linalg.lstsq(phi(Zg), np.array([chi(z) for z in Zg]), rcond=None)[0].T
W_star[np.abs(W_star) < 1e-12] = 0.0
delta_grid = np.max(np.linalg.norm(np.array([chi(z) for z in Zg]) - phi(Zg) @ W_star.T, axis=1))
print("W* =", np.round(W_star, 4).tolist(), f"||W*||_F = {np.linalg.norm(W_star):.3f} <= e1 = {e1}")
print(f"max ||delta|| on the grid = {delta_grid:.3f} <= e3 = {e3}")


# Assumption 3 at k = 0 for the chosen (MISSING) 2nd entry of x0 and two alternatives
for x2 in (x0[1], 1.0, 0.1):
    e0 = np.array([x0[0], x2]) - np.asarray(xhat0, float)
    q0 = np.einsum("na,ab,nb->n", e0, np.linalg.inv(P0), e0)
    print(f"x0 = [{x0[0]}, {x2}]: (x0 - xhat_i0)^T P0^-1 (x0 - xhat_i0) = {np.round(q0, 2).tolist()}"
          f" -> Assumption 3 {'holds' if np.all(q0 <= 1) else 'FAILS'}")

# %% [markdown]
# ## The two estimators, (3) and (8)
#
# Conventional (3), run on the received (falsified) innovations:
# $\hat x_{i,k+1}=F_{i,k}\hat x_{i,k}+G_{i,k}z_{i,k}+\sum_{j\in\mathcal N_i}\theta_{ij}H_{ij,k}\tilde z_{j,k}$.
#
# NN-based (8): $\hat x_{i,k+1}=F_{i,k}\hat x_{i,k}+G_{i,k}z_{i,k}+\sum_{j\in\mathcal N_i}\theta_{ij}H_{ij,k}
# \big(\tilde z_{j,k}-\bar\alpha\hat W_{ij,k}\phi(z_{i,k})\big)$. By Remark 2 the network input is the
# node's **own** innovation $z_{i,k}$, because the true $z_{j,k}$ is not available at node $i$.

# %%
def estimator_update(F, G, H, xh_k, z, z_recv, What, alpha_bar_, compensate):
    """One step of (8) (compensate=True) or (3) (compensate=False) for every node."""
    new = np.empty_like(xh_k)
    for i in range(N):
        upd = F[i] @ xh_k[i] + G[i] @ z[i]
        for j in NBRS[i]:
            inc = z_recv[j] - (alpha_bar_ * What[(i, j)] @ phi(z[i]) if compensate else 0.0)
            upd = upd + THETA[i, j] * H[(i, j)] @ inc
        new[i] = upd
    return new


# %% [markdown]
# ## Taylor linearisation (12)–(13) and the error dynamics (15)–(16), (54)
#
# $f(x_k)=f(\hat x_{i,k})+\Phi_{i,k}\tilde x_{i,k}+L_i\Delta_{1i}\tilde x_{i,k}$ and
# $g_i(x_k)=g_i(\hat x_{i,k})+\Psi_{i,k}\tilde x_{i,k}+\aleph_i\Delta_{2i}\tilde x_{i,k}$ with
# $\|\Delta\|\le1$. The OCR letter in front of $\Delta_2$ is $\aleph$. The scales $L_i,\aleph_i$ are
# not given (MISSING); they are fixed by the rule of the section "The missing Taylor scales" below.
#
# **Induction variables (proof of Theorem 2).** $P_k=S_kS_k^\top$ is shared by all nodes, and
# $\tilde x_{i,k}=S_ks_{i,k}$ with $E\{s_{i,k}^\top s_{i,k}\}\le1$. Further
# $p_{1i}=\Delta_{1i}S_ks_i$, $p_{2i}=\Delta_{2i}S_ks_i$ (so $\|p_{\cdot i}\|\le\|S_ks_i\|$),
# $\varrho(\tilde W_{ij,k})=\bar M_{ij,k}r_{ij,k}$ with $r^\top r\le1$, and
# $\bar M\bar M^\top=Q_{ij,k}\otimes I_{n_\phi}$. Here $\varrho(A)$ stacks the rows of $A$ (numpy
# `A.flatten()`), so $\tilde W\phi=(I_{n_y}\otimes\phi^\top)\varrho(\tilde W)$. With
#
# $$\zeta_k=[\,1;\ s_k;\ p_{1,k};\ p_{2,k};\ v_k;\ \mu_k;\ \delta_k;\ r_k\,]$$
#
# (block sizes $1, Nn_x, Nn_x, Nn_x, n_v, n_u, Nn_y$, and $n_yn_\phi$ per link, so $d=43$), the
# error of node $i$ under (8) is exactly (54): $\tilde x_{i,k+1}=(\Xi_{i,k}+\tilde\alpha_k\tilde\Xi_{i,k})\zeta_k$.
# Its row blocks, re-derived from (15)–(16) because the OCR of (24)–(28) is damaged, are:
#
# | column | $\Xi_{i,k}$ | $\tilde\Xi_{i,k}$ |
# |---|---|---|
# | 1 | $f(\hat x_i)-F_i\hat x_i-\bar\alpha\sum_{j\in\mathcal N_i}\theta_{ij}H_{ij}\hat W_{ij}(\phi(z_j)-\phi(z_i))$ (25) | $-\sum_j\theta_{ij}H_{ij}\hat W_{ij}\phi(z_j)$ (26) |
# | $s_l$ | $\delta_{il}(\Phi_i-G_i\Psi_i)S_k-\theta_{il}H_{il}\Psi_lS_k$ (27) | 0 |
# | $p_{1l}$ | $\delta_{il}L_i$ | 0 |
# | $p_{2l}$ | $-\delta_{il}G_i\aleph_i-\theta_{il}H_{il}\aleph_l$ | 0 |
# | $v$ | $B_k$ | 0 |
# | $\mu$ | $-G_iE_i-\sum_j\theta_{ij}H_{ij}E_j$ (28) | 0 |
# | $\delta_l$ | $-\bar\alpha\theta_{il}H_{il}$ | $-\theta_{il}H_{il}$ |
# | $r_{ib}$ | $-\bar\alpha\theta_{ib}H_{ib}(I_{n_y}\otimes\phi(z_b)^\top)\bar M_{ib}$ | $-\theta_{ib}H_{ib}(I\otimes\phi(z_b)^\top)\bar M_{ib}$ |
#
# Both $\Xi$ and $\tilde\Xi$ need $\phi(z_{j,k})$ of the **true** neighbour innovations. The design
# LMI is therefore a centralised computation, even though each update (8) is local. The derivation
# is checked numerically at every step of the run (X1, below): the true error equals
# $(\Xi+\tilde\alpha\tilde\Xi)\zeta$ evaluated at the actual remainders, residual and weight error.

# %% [markdown]
# ## Theorems 2–3: the recursive LMI (22)/(30) and OP2 (32), OP3 (33)
#
# **Lemma 4, corrected (E1).** Markov's inequality (Lemma 3) needs
# $E\{\tilde x^\top\mathfrak B_k^{-1}\tilde x\}\le1-p$, so $P_k=(1-p)\mathfrak B_k$. The OCR's
# "$1/(1-p)$" factor belongs to the inverses. Then $E\{\tilde x^\top P_k^{-1}\tilde x\}\le1$ gives
# $P\{\tilde x^\top\mathfrak B_k^{-1}\tilde x\le1\}\ge p$. At $k=0$, $\mathfrak B_0=P_0/(1-p)$.
#
# **S-procedure multipliers** (23), (57), all $\ge0$: $\beta^{(1)}_l$ for $E s_l^\top s_l\le1$,
# $\beta^{(2)},\beta^{(3)}$ for $v,\mu$, $\beta^{(4)}$ for $r^\top r\le N^2$, $\beta^{(5)}_l,\beta^{(6)}_l$ for
# $\|p_{1l}\|^2,\|p_{2l}\|^2\le\|S_ks_l\|^2$, and $\beta^{(7)}_l$ for $\|\delta_l\|^2\le e_3^2$:
#
# $$\Gamma_{i,k}=\mathrm{diag}\Big\{\gamma_{i},\ \mathrm{diag}_l\big(\beta^{(1)}_lI-(\beta^{(5)}_l+\beta^{(6)}_l)S_k^\top S_k\big),
# \ \mathrm{diag}_l\beta^{(5)}_lI,\ \mathrm{diag}_l\beta^{(6)}_lI,\ \beta^{(2)}V_k^{-1},\ \beta^{(3)}U_k^{-1},
# \ \mathrm{diag}_l\beta^{(7)}_lI,\ \beta^{(4)}I\Big\},$$
# $$\gamma_i=1-\textstyle\sum_l\beta^{(1)}_l-\beta^{(2)}-\beta^{(3)}-N^2\beta^{(4)}-\sum_le_{3}^2\beta^{(7)}_l .$$
#
# **LMI (30)**, one for each node $i$ ($R_i=R_{n_x,i}$ selects the row block of node $i$), of size
# $d+2n_x=47$:
#
# $$\begin{bmatrix}-\Gamma_{i,k} & * & *\\ R_i\Xi_k & -(1-p)\mathfrak B_{k+1} & *\\
# \sigma R_i\tilde\Xi_k & 0 & -(1-p)\mathfrak B_{k+1}\end{bmatrix}\le-\epsilon I .$$
#
# By the Schur complement (55), $\Xi_i^\top P^{-1}\Xi_i+\sigma^2\tilde\Xi_i^\top P^{-1}\tilde\Xi_i\le\Gamma_i$.
# Since $\tilde\alpha_k$ has zero mean and is independent of $\zeta_k$, this gives
# $E\{\tilde x_{i,k+1}^\top P_{k+1}^{-1}\tilde x_{i,k+1}\}\le1$ (29). **Per-node multipliers (E3):**
# each inequality has its own S-procedure, so $\Gamma_{i,k}$ may differ per node. The printed shared
# $\Gamma_k$ is a special case, available as `shared_multipliers=True`. All step-dependent data
# ($\hat x$, $\Phi S$, $\Psi S$, $S^\top S$, $\hat W$, $\bar M$, $\phi(z)$, $B_k$, $E_{i,k}$) are
# `cp.Parameter`s, and every block is affine in the decision variables $(F,G,H,\beta,\mathfrak B)$.
# DPP forbids parameter × parameter, so products such as $\Psi_{i}S$,
# $\hat W_{ij}(\phi(z_j)-\phi(z_i))$ and $(I\otimes\phi(z_j)^\top)\bar M_{ij}$ are passed as single
# parameters. The sparsity $H_k\in\mathcal T$ is structural: a variable $H_{ij}$ exists only for
# the links.
#
# * **OP2 (32):** $\min\ \mathrm{tr}\,\mathfrak B_{k+1}$ subject to (30) for all $i$ (we minimise
#   $\mathrm{tr}\,P_{k+1}$, which is the same up to the factor $1-p$).
# * **OP3 (33), corrected (E2):** with $\mathfrak B$ fixed, minimise $\rho=1-p_{k+1}$ with $-\rho\mathfrak B$
#   in both $P$-blocks, and report $p_{k+1}=1-\rho$. As printed, "min $q_k=1/(1-p_k)$" is not
#   convex and points the wrong way, since a smaller $q$ means a smaller probability.
# * **Conventional design (MISSING):** the attack-unaware analogue. $\zeta^c=[1;s;p_1;p_2;v;\mu]$
#   ($d=21$), the same first six column blocks with $\xi^c_i=f(\hat x_i)-F_i\hat x_i$, no $\sigma$-row,
#   and $\gamma_i=1-\sum\beta^{(1)}-\beta^{(2)}-\beta^{(3)}$.

# %%
@dataclass
class StepProblem:
    """A per-step SDP built once (DPP) and re-solved with new parameter values."""

    problem: cp.Problem
    params: dict
    vars: dict
    lmis: dict = field(default_factory=dict)
    rows: dict = field(default_factory=dict)


def build_op2_problem(*, nn, alpha_bar_, e3_, eps, theta=THETA, links=LINKS,
                      shared=False, r_bound_="lumped", design="op2"):
    """Per-step problem OP2 (32) [design="op2"] or corrected OP3 (33) [design="op3"]
    subject to LMI (30) for every node; nn=False gives the attack-unaware conventional design.

    Built once with cp.Parameters (DPP); the caller sets the parameters and re-solves.
    """
    n = theta.shape[0]
    nl = len(links)
    sigma = np.sqrt(alpha_bar_ * (1.0 - alpha_bar_))  # (21)
    par = {
        "fhat": [cp.Parameter(NX, name=f"fhat{i}") for i in range(n)],
        "xhat": [cp.Parameter(NX, name=f"xhat{i}") for i in range(n)],
        "PhiS": [cp.Parameter((NX, NX), name=f"PhiS{i}") for i in range(n)],
        "PsiS": [cp.Parameter((NY, NX), name=f"PsiS{i}") for i in range(n)],
        "E": [cp.Parameter((NY, NU), name=f"E{i}") for i in range(n)],
        "L": [cp.Parameter((NX, NX), name=f"L{i}") for i in range(n)],
        "aleph": [cp.Parameter((NY, NX), name=f"aleph{i}") for i in range(n)],
        "StS": cp.Parameter((NX, NX), symmetric=True, name="StS"),
        "B": cp.Parameter((NX, NV), name="B"),
        "Vinv": cp.Parameter((NV, NV), symmetric=True, name="Vinv"),
        "Uinv": cp.Parameter((NU, NU), symmetric=True, name="Uinv"),
    }
    if nn:
        par["c1"] = {lk: cp.Parameter(NY, name=f"c1_{lk}") for lk in links}  # W(phi_j - phi_i)
        par["c2"] = {lk: cp.Parameter(NY, name=f"c2_{lk}") for lk in links}  # W phi_j
        par["Cr"] = {lk: cp.Parameter((NY, M), name=f"Cr_{lk}") for lk in links}  # (I x phi_j^T)M
    F = [cp.Variable((NX, NX), name=f"F{i}") for i in range(n)]
    G = [cp.Variable((NX, NY), name=f"G{i}") for i in range(n)]
    H = {lk: cp.Variable((NX, NY), name=f"H{lk}") for lk in links}
    if design == "op2":
        P = cp.Variable((NX, NX), symmetric=True, name="P")  # P_{k+1} = (1 - p) B_{k+1}
        objective = cp.trace(P)
    elif design == "op3":
        par["Bell"] = cp.Parameter((NX, NX), symmetric=True, name="Bell")
        rho = cp.Variable(nonneg=True, name="rho")  # rho = 1 - p_{k+1}
        P = rho * par["Bell"]
        objective = rho
    else:
        raise ValueError(f"design must be 'op2' or 'op3', found {design!r}")
    nm = 1 if shared else n
    b1, b5, b6, b7 = (cp.Variable((nm, n), nonneg=True, name=nme) for nme in ("b1", "b5", "b6", "b7"))
    b2, b3 = cp.Variable(nm, nonneg=True, name="b2"), cp.Variable(nm, nonneg=True, name="b3")
    b4 = cp.Variable((nm, nl if r_bound_ == "per_link" else 1), nonneg=True, name="b4")
    Ix = np.eye(NX)
    cons, lmis, rows = [], {}, {}
    for i in range(n):
        q = 0 if shared else i
        # ---- Gamma_{i,k}, (23)
        gam = 1 - cp.sum(b1[q]) - b2[q] - b3[q]
        diag = [b1[q, ell] * Ix - (b5[q, ell] + b6[q, ell]) * par["StS"] for ell in range(n)]
        diag += [b5[q, ell] * Ix for ell in range(n)] + [b6[q, ell] * Ix for ell in range(n)]
        diag += [b2[q] * par["Vinv"], b3[q] * par["Uinv"]]
        if nn:
            gam = gam - e3_**2 * cp.sum(b7[q])
            diag += [b7[q, ell] * np.eye(NY) for ell in range(n)]
            if r_bound_ == "per_link":
                gam = gam - cp.sum(b4[q])
                diag += [b4[q, a] * np.eye(M) for a in range(nl)]
            else:
                gam = gam - n**2 * b4[q, 0]
                diag += [b4[q, 0] * np.eye(nl * M)]
        Gam = slmi.block_diag([cp.reshape(gam, (1, 1), order="F"), *diag])
        # ---- row block i of Xi_k (24)-(28) and of Xi~_k (26): see the table above
        xi1 = par["fhat"][i] - F[i] @ par["xhat"][i]
        xit1 = np.zeros(NX)
        if nn:
            for j in NBRS[i]:
                xi1 = xi1 - alpha_bar_ * theta[i, j] * (H[(i, j)] @ par["c1"][(i, j)])
                xit1 = xit1 - theta[i, j] * (H[(i, j)] @ par["c2"][(i, j)])
        row = [cp.reshape(xi1, (NX, 1), order="F")]
        for ell in range(n):  # s_l
            blk = np.zeros((NX, NX))
            if ell == i:
                blk = blk + par["PhiS"][i] - G[i] @ par["PsiS"][i]
            if theta[i, ell] != 0:
                blk = blk - theta[i, ell] * (H[(i, ell)] @ par["PsiS"][ell])
            row.append(blk)
        row += [par["L"][i] if ell == i else np.zeros((NX, NX)) for ell in range(n)]  # p1_l
        for ell in range(n):  # p2_l
            blk = np.zeros((NX, NX))
            if ell == i:
                blk = blk - G[i] @ par["aleph"][i]
            if theta[i, ell] != 0:
                blk = blk - theta[i, ell] * (H[(i, ell)] @ par["aleph"][ell])
            row.append(blk)
        row.append(par["B"])  # v
        mu = -G[i] @ par["E"][i]
        for j in NBRS[i]:
            mu = mu - theta[i, j] * (H[(i, j)] @ par["E"][j])
        row.append(mu)  # mu
        if nn:
            rowt = [cp.reshape(xit1, (NX, 1), order="F"),
                    np.zeros((NX, 3 * n * NX + NV + NU))]  # s, p1, p2, v, mu: zero in Xi~
            for ell in range(n):  # delta_l
                if theta[i, ell] != 0:
                    row.append(-alpha_bar_ * theta[i, ell] * H[(i, ell)])
                    rowt.append(-theta[i, ell] * H[(i, ell)])
                else:
                    row.append(np.zeros((NX, NY)))
                    rowt.append(np.zeros((NX, NY)))
            for a, b in links:  # r_ab
                if a == i:
                    row.append(-alpha_bar_ * theta[a, b] * (H[(a, b)] @ par["Cr"][(a, b)]))
                    rowt.append(-theta[a, b] * (H[(a, b)] @ par["Cr"][(a, b)]))
                else:
                    row.append(np.zeros((NX, M)))
                    rowt.append(np.zeros((NX, M)))
        Xi = cp.hstack(row)
        if nn:
            Xit = cp.hstack(rowt)
            Mi = slmi.block_symmetric([[-Gam], [Xi, -P], [sigma * Xit, None, -P]])  # (30)
        else:
            Xit = None
            Mi = slmi.block_symmetric([[-Gam], [Xi, -P]])  # conventional, no sigma-row
        lmis[f"node {i + 1}"] = Mi
        rows[i] = (Xi, Xit)
        cons.append(slmi.lmi(Mi, eps))
    prob = cp.Problem(cp.Minimize(objective), cons)
    if not prob.is_dpp():
        raise RuntimeError("OP2/OP3 problem is not DPP")
    var = {"F": F, "G": G, "H": H, "P": P}
    if design == "op3":
        var["rho"] = rho
    return StepProblem(prob, par, var, lmis, rows)


# %% [markdown]
# ## Weight tuning law (17), Theorem 1 / LMI (18) and OP1 (31)
#
# (17): $\hat W_{ij,k+1}=\lambda^{(1)}_{ij,k}\hat W_{ij,k}+\lambda^{(2)}_{ij,k}\varpi_{i,k}\phi^\top(z_{i,k})$ with
# $\varpi_{i,k}=\bar\alpha\sum_{j\in\mathcal N_i}\theta_{ij}H_{ij,k}^\top\Psi_{i,k+1}^\top z_{i,k+1}$ (RECONSTRUCTED
# from "a Z 9in5,;€‘1’2;€+12@1€+1 JEN;"). Proof of Theorem 1:
# $\varrho(\tilde W_{ij,k+1})=\Upsilon_{ij,k}\pi_{ij,k}$ with $\pi=[1;r_{ij};\varrho(W_{ij})]$ and
# $\Upsilon=[-\lambda^{(2)}(\varpi\otimes\phi(z_i)),\ \lambda^{(1)}\bar M_{ij,k},\ (1-\lambda^{(1)})I_m]$. The S-procedure
# with $r^\top r\le1$ ($\varsigma^{(1)}$) and $\|\varrho(W)\|^2\le e_1^2$ ($\varsigma^{(2)}$) gives (18), of size
# $(1+2m)+m=13$:
#
# $$\begin{bmatrix}\Omega_{ij,k} & \Upsilon_{ij,k}^\top\\ \Upsilon_{ij,k} & -Q_{ij,k+1}\otimes I_{n_\phi}\end{bmatrix}<0,\qquad
# \Omega=\mathrm{diag}\{-1+\varsigma^{(1)}+e_1^2\varsigma^{(2)},\ -\varsigma^{(1)}I_m,\ -\varsigma^{(2)}I_m\}.$$
#
# It yields (19): $\mathrm{tr}[\tilde W_{ij,k+1}^\top Q_{ij,k+1}^{-1}\tilde W_{ij,k+1}]\le1$. **OP1 (31):**
# $\min\mathrm{tr}\,Q_{ij,k+1}$ over $(\varsigma,\lambda,Q)$. The four link problems are independent. We
# solve them as one separable SDP (sum of the traces), which has the same minimisers. $\lambda^{(2)}$ is
# left sign-free (descent needs $\lambda^{(2)}<0$, while the paper calls both scalars "positive") and
# boxed by `lam2_max`.

# %%
def build_op1_problem(*, e1_, eps, links=LINKS, lam2_box=1e3):
    """OP1 (31) subject to LMI (18) for every link, as one separable DPP problem."""
    par = {"a": {lk: cp.Parameter(M, name=f"a_{lk}") for lk in links},  # varpi (x) phi(z_i)
           "Mbar": {lk: cp.Parameter((M, M), name=f"Mbar_{lk}") for lk in links}}
    var, cons, lmis, obj = {}, [], {}, 0
    for lk in links:
        s1 = cp.Variable(nonneg=True, name=f"s1_{lk}")
        s2 = cp.Variable(nonneg=True, name=f"s2_{lk}")
        l1, l2 = cp.Variable(name=f"l1_{lk}"), cp.Variable(name=f"l2_{lk}")
        Q = cp.Variable((NY, NY), symmetric=True, name=f"Q_{lk}")
        Om = slmi.block_diag([cp.reshape(-1 + s1 + e1_**2 * s2, (1, 1), order="F"),
                              -s1 * np.eye(M), -s2 * np.eye(M)])
        Ups = cp.hstack([cp.reshape(-l2 * par["a"][lk], (M, 1), order="F"),
                         l1 * par["Mbar"][lk], (1 - l1) * np.eye(M)])
        Ml = slmi.block_symmetric([[Om], [Ups, -cp.kron(Q, np.eye(NPHI))]])  # (18)
        lmis[f"link {lk[0] + 1}<-{lk[1] + 1}"] = Ml
        cons += [slmi.lmi(Ml, eps), cp.abs(l2) <= lam2_box]
        obj = obj + cp.trace(Q)
        var[lk] = {"l1": l1, "l2": l2, "Q": Q}
    prob = cp.Problem(cp.Minimize(obj), cons)
    if not prob.is_dpp():
        raise RuntimeError("OP1 problem is not DPP")
    return StepProblem(prob, par, var, lmis)


# %% [markdown]
# ## Algorithm 1 in computation order
#
# For $k=0,\dots,T-1$: (1) every node forms $z_{i,k}$ and the links deliver $\tilde z_{j,k}$; (2)
# $\Phi_{i,k},\Psi_{i,k}$, $\phi(z_{j,k})$ and $\bar M_{ij,k}$ are computed; (3) OP2 is solved for
# $F,G,H$ and $\mathfrak B_{k+1}$, so $P_{k+1}=(1-p)\mathfrak B_{k+1}$; (4) the estimates are updated
# by (8), or by (3) for the conventional design; (5) the plant steps and $z_{i,k+1}$, $\Psi_{i,k+1}$
# and $\varpi$ are formed; (6) OP1 gives $\lambda^{(1)},\lambda^{(2)},Q_{ij,k+1}$; (7) $\hat W_{ij,k+1}$
# follows from (17), and $S_{k+1}=\mathrm{chol}(P_{k+1})$ after symmetrisation.
#
# **Solves.** Every problem is solved by `secest.lmi.solve_certified`. CLARABEL runs first (with
# tolerances $10^{-7}$, and chordal decomposition off for the tiny, degenerate OP1). The status must
# be `optimal`, and every LMI matrix must have its largest numpy eigenvalue $\le$ `cert_tol`.
# Otherwise SCS is tried under a visible warning. If that fails too, an `InfeasibleLMIError` names
# the step and the problem. OP2/OP3 is one joint SDP over all nodes, coupled through
# $P_{k+1}$, so an infeasible solve cannot be blamed on one node ("joint SDP over nodes 1-3"); a
# failed certificate names the node whose LMI (30) violates it. The run then keeps the previous gains, doubles $P$ and counts the step
# (brief §7), and C5 reports the count.

# %%
PROBLEMS = {}  # cache: (kind, constants) -> StepProblem, built once per configuration


def get_problem(kind, **const):
    key = (kind, *sorted(const.items()))
    if key not in PROBLEMS:
        if kind == "op1":
            PROBLEMS[key] = build_op1_problem(**const)
        else:
            PROBLEMS[key] = build_op2_problem(nn=(kind == "nn"), **const)
    return PROBLEMS[key]


def solve(sp, k, label, opts):
    return slmi.solve_certified(sp.problem, sp.lmis, step=k, node=label, solver=solver,
                                fallback=fallback_solver, tol=cert_tol, eps=eps_lmi,
                                certify="strict", solver_opts=opts, fallback_opts=SCS_OPTS)


def sample_admissible(rng, n_samples, S):
    """Random zeta on the boundary of every S-procedure constraint of (23) (X4).

    ||s_l|| = 1, ||p_1l|| = ||p_2l|| = ||S s_l||, |v| = |mu| = 1 (V = U = 1),
    ||delta_l|| = e3, ||r|| = N (lumped bound). A quadratic form convex in each block attains
    its maximum over these balls on their boundaries.
    """
    def unit(shape):
        u = rng.standard_normal(shape)
        return u / np.linalg.norm(u, axis=-1, keepdims=True)

    s = unit((n_samples, N, NX))
    rad = np.linalg.norm(np.einsum("ab,knb->kna", S, s), axis=-1, keepdims=True)
    parts = [np.ones((n_samples, 1)), s, unit((n_samples, N, NX)) * rad,
             unit((n_samples, N, NX)) * rad, unit((n_samples, NV)), unit((n_samples, NU)),
             e3 * unit((n_samples, N, NY)), N * unit((n_samples, len(LINKS) * M))]
    return np.concatenate([q.reshape(n_samples, -1) for q in parts], axis=1)


def alpha_sequence(rng, n_steps, abar):
    """One Bernoulli(abar) draw per step, shared by every link."""
    return (rng.random(n_steps) < abar).astype(float)


def simulate(*, alpha, estimator, abar=alpha_bar, L_s=L_scale, A_s=aleph_scale, x_init=x0,
             xh_init=xhat0, design="op2", B_fixed=None, check_dynamics=False,
             shared=shared_multipliers):
    """Run one estimator over the horizon under the falsified innovations alpha_k chi(z).

    estimator: "nn" (8) with OP2/OP3 + OP1 + (17); "conv" (3) with the attack-unaware design;
    "aware0" (3) with the attack-aware gains of (30) but no compensation (W_hat = 0, Q = e1^2 I).
    L_s, A_s = None (the default parameters) use the scale chosen by the rule (`taylor_scale`).
    The remainder ratios of (12)-(13) along the run are always recorded (X2 and the rule).
    """
    n_steps = alpha.size
    L_s = taylor_scale if L_s is None else L_s
    A_s = taylor_scale if A_s is None else A_s
    nn_design = estimator in ("nn", "aware0")
    sp = get_problem("conv" if estimator == "conv" else "nn", alpha_bar_=abar, e3_=e3,
                     eps=eps_lmi, shared=shared, r_bound_=r_bound, design=design)
    op1 = get_problem("op1", e1_=e1, eps=eps_lmi, lam2_box=lam2_max)
    Ls, As = L_s * np.eye(NX), A_s * np.eye(NY, NX)
    x = np.zeros((n_steps + 1, NX))
    x[0] = x_init
    for k in range(n_steps):
        x[k + 1] = f(x[k]) + B_mat(k) @ v_noise(k)  # (1)
    xh = np.zeros((n_steps + 1, N, NX))
    xh[0] = np.asarray(xh_init, float)
    P = np.asarray(P0, float)
    Ps = np.zeros((n_steps + 1, NX, NX))
    Ps[0] = P
    if estimator == "aware0":
        What = {lk: np.zeros((NY, NPHI)) for lk in LINKS}
        Q = {lk: e1**2 * np.eye(NY) for lk in LINKS}
    else:
        What = {lk: np.asarray(W0, float).copy() for lk in LINKS}
        Q = {lk: np.asarray(Q0, float).copy() for lk in LINKS}
    rec = {k2: [] for k2 in ("reports", "failures")}
    Wn = np.zeros((n_steps + 1, len(LINKS)))
    Wq = np.zeros((n_steps + 1, len(LINKS)))  # tr[W~^T Q^-1 W~] with W = W*
    lam = np.zeros((n_steps, len(LINKS), 2))
    Hn = np.zeros(n_steps)
    rho = np.full(n_steps + 1, np.nan)
    dyn_res, ratio_f, ratio_g, delta_n, sampled_q = [], [], [], [], []
    sample_rng = montecarlo.spawn_rngs(seed, 64)[63]  # X4 only; independent of the alpha_k draws

    def weight_stats(k):
        Wn[k] = [np.linalg.norm(What[lk]) for lk in LINKS]
        Wq[k] = [np.trace((W_star - What[lk]).T @ np.linalg.solve(Q[lk], W_star - What[lk]))
                 for lk in LINKS]

    weight_stats(0)
    for i in range(N):
        sp.params["L"][i].value, sp.params["aleph"][i].value = Ls, As
    sp.params["Vinv"].value, sp.params["Uinv"].value = V_inv, U_inv
    if design == "op3":
        sp.params["Bell"].value = np.asarray(B_fixed, float)
    F = [np.zeros((NX, NX)) for _ in range(N)]
    G = [np.zeros((NX, NY)) for _ in range(N)]
    H = {lk: np.zeros((NX, NY)) for lk in LINKS}
    for k in range(n_steps):
        S = np.linalg.cholesky(covariance.symmetrize(P))  # P_k = S_k S_k^T
        z = np.array([g(i, x[k]) + E_mat(i, k) @ mu_noise(k) - g(i, xh[k, i]) for i in range(N)])
        z_recv = np.array([z[j] + alpha[k] * chi(z[j]) for j in range(N)])  # (5)
        ph = phi(z)
        sp.params["StS"].value = S.T @ S
        sp.params["B"].value = B_mat(k)
        for i in range(N):
            sp.params["fhat"][i].value = f(xh[k, i])
            sp.params["xhat"][i].value = xh[k, i]
            sp.params["PhiS"][i].value = jac_f(xh[k, i]) @ S
            sp.params["PsiS"][i].value = jac_g(i, xh[k, i]) @ S
            sp.params["E"][i].value = E_mat(i, k)
        Mbar = {lk: np.kron(np.linalg.cholesky(covariance.symmetrize(Q[lk])), np.eye(NPHI))
                for lk in LINKS}
        if nn_design:
            for (i, j) in LINKS:
                sp.params["c1"][(i, j)].value = What[(i, j)] @ (ph[j] - ph[i])
                sp.params["c2"][(i, j)].value = What[(i, j)] @ ph[j]
                sp.params["Cr"][(i, j)].value = np.kron(np.eye(NY), ph[j][None, :]) @ Mbar[(i, j)]
        # OP2/OP3 is one SDP over all nodes, coupled through P_{k+1} (and the multipliers when
        # shared): a failed solve cannot be blamed on one node. A failed certificate names the node.
        label = f"joint SDP over nodes 1-{N} ({design.upper()}, {estimator})"
        try:
            rep = solve(sp, k, label, CLARABEL_OPTS)
            rec["reports"].append(rep)
            solved = True
            F = [v.value.copy() for v in sp.vars["F"]]
            G = [v.value.copy() for v in sp.vars["G"]]
            H = {lk: sp.vars["H"][lk].value.copy() for lk in LINKS}
            P_next = covariance.symmetrize(np.asarray(sp.vars["P"].value))
            if design == "op3":
                rho[k + 1] = float(sp.vars["rho"].value)
        except slmi.InfeasibleLMIError as err:  # keep the previous gains, double P (brief §7)
            rec["failures"].append(str(err))
            print("INFEASIBLE:", err)
            P_next = 2.0 * P
            solved = False
        Hn[k] = max(np.linalg.norm(H[lk], 2) for lk in LINKS)
        xh[k + 1] = estimator_update(F, G, H, xh[k], z, z_recv, What, abar,
                                     compensate=(estimator == "nn"))
        xt = x[k] - xh[k]  # (12)-(13): remainders of the linearisation at x^_(i,k)
        rem_f = [f(x[k]) - f(xh[k, i]) - jac_f(xh[k, i]) @ xt[i] for i in range(N)]
        rem_g = [g(i, x[k]) - g(i, xh[k, i]) - jac_g(i, xh[k, i]) @ xt[i] for i in range(N)]
        ratio_f.extend(np.linalg.norm(rem_f[i]) / np.linalg.norm(xt[i]) for i in range(N))
        ratio_g.extend(np.linalg.norm(rem_g[i]) / np.linalg.norm(xt[i]) for i in range(N))
        if check_dynamics and estimator == "nn":  # X1: (54) with the actual zeta
            dl = [chi(z[j]) - W_star @ ph[j] for j in range(N)]
            delta_n.extend(np.linalg.norm(d) for d in dl)
            zeta = np.concatenate(
                [[1.0]] + [np.linalg.solve(S, xt[i]) for i in range(N)]
                + [np.linalg.solve(Ls, rem_f[i]) for i in range(N)]
                + [np.linalg.solve(As, rem_g[i]) for i in range(N)]
                + [v_noise(k), mu_noise(k)] + dl
                + [np.linalg.solve(Mbar[lk], (W_star - What[lk]).flatten()) for lk in LINKS])
            x_err_next = x[k + 1] - xh[k + 1]
            for i in range(N):
                Xi, Xit = sp.rows[i]
                pred = (Xi.value + (alpha[k] - abar) * Xit.value) @ zeta
                dyn_res.append(float(np.max(np.abs(pred - x_err_next[i]))))
            if solved:  # X4: (30) => (29) on sampled admissible zeta
                Z = sample_admissible(sample_rng, 256, S)
                P_inv = np.linalg.inv(P_next)
                sig2 = abar * (1.0 - abar)
                for i in range(N):
                    Y, Yt = Z @ sp.rows[i][0].value.T, Z @ sp.rows[i][1].value.T
                    qv = np.sum((Y @ P_inv) * Y, axis=1) + sig2 * np.sum((Yt @ P_inv) * Yt, axis=1)
                    sampled_q.append(float(qv.max()))
        P = P_next
        Ps[k + 1] = P
        if estimator == "nn":  # steps 5-7: varpi, OP1 (31), tuning law (17)
            z1 = np.array([g(i, x[k + 1]) + E_mat(i, k + 1) @ mu_noise(k + 1) - g(i, xh[k + 1, i])
                           for i in range(N)])
            varpi = {}
            for (i, j) in LINKS:
                Psi1 = jac_g(i, xh[k + 1, i])
                terms = NBRS[i] if varpi_form == "sum" else [j]  # (17), RECONSTRUCTED
                varpi[(i, j)] = abar * sum(THETA[i, jj] * H[(i, jj)].T @ Psi1.T @ z1[i]
                                           for jj in terms)
                op1.params["a"][(i, j)].value = np.kron(varpi[(i, j)], ph[i])
                op1.params["Mbar"][(i, j)].value = Mbar[(i, j)]
            try:
                rep1 = solve(op1, k, "all links (OP1)", {**CLARABEL_OPTS,
                                                          "chordal_decomposition_enable": False})
                rec["reports"].append(rep1)
                for a, lk in enumerate(LINKS):
                    l1, l2 = float(op1.vars[lk]["l1"].value), float(op1.vars[lk]["l2"].value)
                    What[lk] = l1 * What[lk] + l2 * np.outer(varpi[lk], ph[lk[0]])  # (17)
                    Q[lk] = covariance.symmetrize(op1.vars[lk]["Q"].value)
                    lam[k, a] = (l1, l2)
            except slmi.InfeasibleLMIError as err:
                rec["failures"].append(str(err))
                print("INFEASIBLE:", err)
        weight_stats(k + 1)
    err = x[:, None, :] - xh
    Bell = Ps / (1.0 - p) if design == "op2" else np.broadcast_to(np.asarray(B_fixed), Ps.shape)
    Bell = np.array(Bell)
    Bell[0] = np.asarray(P0) / (1.0 - p)
    qf = montecarlo.nees(err, Bell[:, None, :, :])  # x~^T B_k^-1 x~ per (k, node)
    return {"x": x, "xh": xh, "err": err, "P": Ps, "Bell": Bell, "qf": qf, "Hn": Hn, "Wn": Wn,
            "Wq": Wq, "lam": lam, "rho": rho, "reports": rec["reports"],
            "failures": rec["failures"], "dyn_res": np.array(dyn_res),
            "ratio_f": np.array(ratio_f), "ratio_g": np.array(ratio_g),
            "delta_n": np.array(delta_n), "sampled_q": np.array(sampled_q)}


def rmse(res):
    """Per-node RMSE of ||x~_{i,k}|| over k = 1..T."""
    return np.sqrt(np.mean(np.sum(res["err"][1:] ** 2, axis=2), axis=0))


# %% [markdown]
# ## The missing Taylor scales $L_i$, $\aleph_i$: a rule fixed in advance
#
# The paper gives no values for $L_i$, $\aleph_i$ in (12)–(13), but Theorems 2–3 rest on them: the
# remainders must satisfy $\|f(x)-f(\hat x_i)-\Phi_i\tilde x_i\|\le\|L_i\tilde x_i\|$, i.e.
# $\|\Delta_{1i}\|\le1$, and likewise for $g_i$ with $\aleph_i$. A scale under which this premise
# fails voids the guarantee, so we do not pick one by taste. **Rule** (fixed before looking at the
# comparison): $L_i=\aleph_i=sI_2$ with $s$ the smallest multiple of `taylor_grid` $=0.05$ such that
# $\|\text{remainder}\|\le s\|\tilde x_{i,k}\|$ for $f$ and every $g_i$, at every node and step of
# **both** runs (the NN design (30) and the conventional design, which uses the same
# linearisation). The trajectory depends on $s$, so each candidate is run; candidates below the
# ratios at $k=0$ are rejected without a run, because $\hat x_{i,0}$ is given and the $k=0$ ratio
# does not depend on $s$. The earlier default $s=0.1$ (the brief's "usual size") violates the premise
# at $k=0$ and is kept as a sensitivity row.


# %%
def remainder_ratios_k0(x_init, xh_init):
    """||remainder|| / ||x~|| of (12) for f and (13) for g_i at k = 0 (independent of the design)."""
    x_i, out = np.asarray(x_init, float), []
    for i, xh_i in enumerate(np.asarray(xh_init, float)):
        xt = x_i - xh_i
        out.append(np.linalg.norm(f(x_i) - f(xh_i) - jac_f(xh_i) @ xt) / np.linalg.norm(xt))
        out.append(np.linalg.norm(g(i, x_i) - g(i, xh_i) - jac_g(i, xh_i) @ xt) / np.linalg.norm(xt))
    return max(out)


def select_taylor_scale(alpha, check_dynamics=False, **kw):
    """The rule above: smallest s on the grid taylor_grid * {1, 2, ...} for which (12)-(13) hold
    with L_i = aleph_i = s I along the NN run and the conventional run. Returns the scale, both runs
    and the candidates tried as (s, worst ratio)."""
    r0 = remainder_ratios_k0(kw.get("x_init", x0), kw.get("xh_init", xhat0))
    m, history = max(1, int(np.ceil(r0 / taylor_grid - 1e-9))), []
    while True:
        s = round(m * taylor_grid, 10)
        if s > taylor_max:
            raise RuntimeError(f"no Taylor scale up to taylor_max = {taylor_max} satisfies (12)-(13): "
                               f"{history}")
        r_nn = simulate(alpha=alpha, estimator="nn", L_s=s, A_s=s, check_dynamics=check_dynamics,
                        **kw)
        r_cv = simulate(alpha=alpha, estimator="conv", L_s=s, A_s=s, **kw)
        worst = float(max(r[key].max() for r in (r_nn, r_cv) for key in ("ratio_f", "ratio_g")))
        history.append((s, worst))
        if worst <= s:
            return s, r_nn, r_cv, history
        m += 1


alpha_rule = alpha_sequence(montecarlo.spawn_rngs(seed, 1)[0], T_run, alpha_bar)  # = alphas[0]
taylor_scale = None
if L_scale is None and aleph_scale is None:
    taylor_scale, rule_nn, rule_conv, rule_history = select_taylor_scale(alpha_rule,
                                                                         check_dynamics=True)
elif L_scale is not None and aleph_scale is not None:  # explicit override, no rule
    rule_history = []
    rule_nn = simulate(alpha=alpha_rule, estimator="nn", check_dynamics=True)
    rule_conv = simulate(alpha=alpha_rule, estimator="conv")
else:
    raise ValueError("L_scale and aleph_scale must both be None (rule) or both be numbers")
L_used = taylor_scale if L_scale is None else float(L_scale)
aleph_used = taylor_scale if aleph_scale is None else float(aleph_scale)
print(f"k = 0 remainder ratio (design-independent): {remainder_ratios_k0(x0, xhat0):.4f}")
print("candidates (s, worst ratio along both runs):",
      [(c, round(w, 4)) for c, w in rule_history])
print(f"L_i = {L_used:g} I, aleph_i = {aleph_used:g} I"
      + (" (rule)" if taylor_scale is not None else " (override, no rule)"))

# %% [markdown]
# ## The example (Section IV): both estimators under the same falsified innovations
#
# The two runs at the chosen scale are the ones the rule accepted.

# %%
rngs = montecarlo.spawn_rngs(seed, 1 + n_extra)
alphas = [alpha_sequence(r, T_run, alpha_bar) for r in rngs]
alpha_main = alphas[0]
assert np.array_equal(alpha_main, alpha_rule)
print(f"alpha_k = 1 at {int(alpha_main.sum())} of {T_run} steps")
nn_run, conv_run = rule_nn, rule_conv  # the NN run is the last OP2 solved: X5 reads its last step
# X5: the DPP problem re-solved with parameters equals a freshly built one (last step)
cached = get_problem("nn", alpha_bar_=alpha_bar, e3_=e3, eps=eps_lmi, shared=shared_multipliers,
                     r_bound_=r_bound, design="op2")
fresh = build_op2_problem(nn=True, alpha_bar_=alpha_bar, e3_=e3, eps=eps_lmi,
                          shared=shared_multipliers, r_bound_=r_bound)
values = {q.name(): q.value for q in cached.problem.parameters()}
for q in fresh.problem.parameters():
    q.value = values[q.name()]
P_cached = np.asarray(cached.vars["P"].value)
solve(fresh, T_run - 1, "fresh build (X5)", CLARABEL_OPTS)
dpp_gap = float(np.max(np.abs(np.asarray(fresh.vars["P"].value) - P_cached)))
print(f"X5: |P(re-solved DPP) - P(fresh build)| = {dpp_gap:.2e}")
print(f"X4: max sampled E_alpha x~'P^-1 x~ over admissible zeta = {nn_run['sampled_q'].max():.4f}")
k_axis = np.arange(T_run + 1)
for name, r in (("NN (8)", nn_run), ("conventional (3)", conv_run)):
    print(f"{name:>17}: RMSE per node = {np.round(rmse(r), 4).tolist()}, "
          f"max x~'B^-1 x~ = {r['qf'].max():.4f}, tr B_T = {np.trace(r['Bell'][-1]):.3f}, "
          f"max ||H|| = {r['Hn'].max():.2e}, infeasible steps = {len(r['failures'])}")

# %% [markdown]
# ### The printed shared multipliers (22), first steps
#
# As printed, one $\Gamma_k$ serves all $N$ inequalities. That is a valid but more conservative
# S-procedure than one $\Gamma_{i,k}$ per node, which we use by default (a design choice, not a
# correction). The printed LMI is run here for `shared_diag_steps` steps on the same data and
# compared with the default. We do not run it further: in a one-off longer run the solvers stopped
# certifying it from $k=2$ on (CLARABEL "optimal_inaccurate", SCS not converged), so what happens
# later is not reproducible from committed output and is not claimed.

# %%
n_sh = min(int(shared_diag_steps), T_run)
shared_run = simulate(alpha=alpha_main[:n_sh], estimator="nn", shared=True)
trB_shared = np.trace(shared_run["Bell"], axis1=1, axis2=2)
trB_node = np.trace(nn_run["Bell"][: n_sh + 1], axis1=1, axis2=2)
print("k                      :", list(range(n_sh + 1)))
print("tr B_k, shared Gamma_k :", np.round(trB_shared, 3).tolist())
print("tr B_k, per-node Gamma :", np.round(trB_node, 3).tolist())
print(f"uncertified steps of the shared run: {len(shared_run['failures'])}")
_ = plotting.save_data(FIG_DIR, "extra_shared_multipliers", {
    "k": np.arange(n_sh + 1), "trB_shared": trB_shared, "trB_per_node": trB_node},
    tolerance={"trB_*": results.LMI_ITERATES})

# %% [markdown]
# ### Figures 1–8
#
# One marker style per node, as in the paper. The state figures show the true state $x^{(l)}_k$ and
# the three estimates $\hat x^{(l)}_{i,k}$. In the error figures the shaded band is the projection of
# the required ellipsoid onto component $l$, $|\tilde x^{(l)}|\le\sqrt{[\mathfrak B_k]_{ll}}$, for that
# estimator's own design. For the conventional design this "region" comes from an attack-unaware
# LMI and guarantees nothing under attack.

# %%
MARKERS = {0: ("x", "--"), 1: ("o", "-."), 2: ("^", ":")}


def state_figure(res, comp, est_name, stem):
    fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH, 2.5))
    ax.plot(k_axis, res["x"][:, comp], "k-", lw=1.6, label=f"$x^{{({comp + 1})}}_k$")
    for i in range(N):
        mk, ls = MARKERS[i]
        ax.plot(k_axis, res["xh"][:, i, comp], ls=ls, marker=mk, ms=3.5, mfc="none", lw=0.9,
                label=f"$\\hat x^{{({comp + 1})}}_{{{i + 1},k}}$ (node {i + 1})")
    ax.set_xlabel("time step $k$")
    ax.set_ylabel(f"state $x^{{({comp + 1})}}$ and estimates [–]")
    ax.set_title(f"{est_name}: $x^{{({comp + 1})}}_k$ and its estimates")
    ax.legend(fontsize=7, ncol=2, loc="upper right")
    ax.set_xlim(0, T_run)
    plotting.save_figure(fig, FIG_DIR, stem, data={
        "k": k_axis, "x": res["x"][:, comp],
        **{f"xhat_node{i + 1}": res["xh"][:, i, comp] for i in range(N)}},
        tolerance={"xhat_node*": results.LMI_ITERATES})
    plt.show()


def error_figure(res, comp, est_name, stem,
                 band_label=r"required region $\pm\sqrt{[\mathfrak{B}_k]_{ll}}$"):
    band = np.sqrt(res["Bell"][:, comp, comp])
    fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH, 2.5))
    ax.fill_between(k_axis, -band, band, color="tab:green", alpha=0.15, label=band_label)
    for i in range(N):
        mk, ls = MARKERS[i]
        ax.plot(k_axis, res["err"][:, i, comp], ls=ls, marker=mk, ms=3.5, mfc="none", lw=0.9,
                label=f"Node {i + 1}")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("time step $k$")
    ax.set_ylabel(f"estimation error $\\tilde x^{{({comp + 1})}}_{{i,k}}$ [–]")
    ax.set_title(f"{est_name}: error $\\tilde x^{{({comp + 1})}}_{{i,k}}$")
    ax.plot(k_axis, band, color="tab:green", lw=0.8, ls="--")
    ax.plot(k_axis, -band, color="tab:green", lw=0.8, ls="--")
    lim = 1.15 * float(band.max())
    ax.set_ylim(-lim, lim)
    ax.set_xlim(0, T_run)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    plotting.save_figure(fig, FIG_DIR, stem, data={
        "k": k_axis, "band": band, **{f"err_node{i + 1}": res["err"][:, i, comp] for i in range(N)}},
        tolerance={"band": results.LMI_ITERATES, "err_node*": results.LMI_ITERATES})
    plt.show()


# %% [markdown]
# ### Fig. 1 — $x^{(1)}_k$ and its estimates (estimator with NN)

# %%
state_figure(nn_run, 0, "NN-based estimator (8)", "fig1_nn_state1")

# %% [markdown]
# ### Fig. 2 — $x^{(2)}_k$ and its estimates (estimator with NN)

# %%
state_figure(nn_run, 1, "NN-based estimator (8)", "fig2_nn_state2")

# %% [markdown]
# ### Fig. 3 — estimation error $\tilde x^{(1)}_{i,k}$ (estimator with NN)

# %%
error_figure(nn_run, 0, "NN-based (8)", "fig3_nn_error1")

# %% [markdown]
# ### Fig. 4 — estimation error $\tilde x^{(2)}_{i,k}$ (estimator with NN)

# %%
error_figure(nn_run, 1, "NN-based (8)", "fig4_nn_error2")

# %% [markdown]
# ### Fig. 5 — $x^{(1)}_k$ and its estimates (conventional estimator (3))

# %%
state_figure(conv_run, 0, "conventional estimator (3)", "fig5_conv_state1")

# %% [markdown]
# ### Fig. 6 — $x^{(2)}_k$ and its estimates (conventional estimator (3))

# %%
state_figure(conv_run, 1, "conventional estimator (3)", "fig6_conv_state2")

# %% [markdown]
# ### Fig. 7 — estimation error $\tilde x^{(1)}_{i,k}$ (conventional estimator (3))

# %%
error_figure(conv_run, 0, "conventional (3)", "fig7_conv_error1",
             band_label="own region (attack-unaware)")

# %% [markdown]
# ### Fig. 8 — estimation error $\tilde x^{(2)}_{i,k}$ (conventional estimator (3))

# %%
error_figure(conv_run, 1, "conventional (3)", "fig8_conv_error2",
             band_label="own region (attack-unaware)")

# %% [markdown]
# ## Extra — diagnostics: what the designs actually do
#
# Six panels, not in the paper. (a) The normalised errors
# $\tilde x^\top\mathfrak B_k^{-1}\tilde x$ against the threshold 1 of (11). (b)
# $\mathrm{tr}\,\mathfrak B_k$ of both designs. (c) The largest neighbour gain $\max_{ij}\|H_{ij,k}\|$.
# (d) The NN weights $\|\hat W_{ij,k}\|_F$. (e) The Theorem 1 quantity
# $\mathrm{tr}[\tilde W^\top Q^{-1}\tilde W]$ with $W=W^\star$. (f) The probability $p_k=1-\rho_k$
# guaranteed by the corrected OP3 for the fixed ellipsoid $\mathfrak B=$ `op3_scale`$\cdot I$, run
# on the same data; $p_k\le0$ means $\rho_k\ge1$, a void bound at that step (reported, not clipped).

# %%
op3_run = simulate(alpha=alpha_main, estimator="nn", design="op3", B_fixed=op3_scale * np.eye(NX))
p_op3 = 1.0 - op3_run["rho"]
frac_op3 = float(np.mean(op3_run["qf"][1:] <= 1.0))
print(f"OP3: steps with rho_k >= 1 (bound void): {int(np.sum(op3_run['rho'][1:] >= 1.0))}")
print(f"OP3 (B = {op3_scale} I): p_k from {np.nanmax(p_op3):.3f} down to {np.nanmin(p_op3):.3f}; "
      f"fraction of (i, k >= 1) inside: {frac_op3:.3f}; infeasible steps: "
      f"{len(op3_run['failures'])}")

fig, axs = plt.subplots(2, 3, figsize=(plotting.PAGE_WIDTH, 4.6))
ax = axs[0, 0]
for i in range(N):
    ax.semilogy(k_axis, nn_run["qf"][:, i], "-", color=f"C{i}", lw=0.8, label=f"node {i + 1}")
    ax.semilogy(k_axis, conv_run["qf"][:, i], ":", color=f"C{i}", lw=0.8)
ax.plot([], [], "k-", lw=0.8, label="NN design")
ax.plot([], [], "k:", lw=0.8, label="conventional")
ax.axhline(1.0, color="r", lw=1.0, label="threshold 1 of (11)")
ax.set_ylim(1e-7, 1e7)
ax.set_title(r"(a) $\tilde x^\top\mathfrak{B}_k^{-1}\tilde x$")
ax.legend(fontsize=5.5, ncol=2, loc="upper center")
ax = axs[0, 1]
ax.plot(k_axis, np.trace(nn_run["Bell"], axis1=1, axis2=2), label="NN design (30)")
ax.plot(k_axis, np.trace(conv_run["Bell"], axis1=1, axis2=2), "--", label="conventional design")
ax.set_title(r"(b) $\mathrm{tr}\,\mathfrak{B}_k$")
ax.legend(fontsize=7)
ax = axs[0, 2]
ax.semilogy(k_axis[:-1], nn_run["Hn"], label="NN design (30)")
ax.semilogy(k_axis[:-1], conv_run["Hn"], "--", label="conventional design")
ax.set_title(r"(c) $\max_{ij}\|H_{ij,k}\|_2$")
ax.legend(fontsize=7)
ax = axs[1, 0]
for a, (i, j) in enumerate(LINKS):
    ax.semilogy(k_axis, np.maximum(nn_run["Wn"][:, a], 1e-16), lw=0.9, label=f"link {i + 1}←{j + 1}")
ax.set_title(r"(d) $\|\hat W_{ij,k}\|_F$ (floored at $10^{-16}$)")
ax.legend(fontsize=7)
ax = axs[1, 1]
for a, (i, j) in enumerate(LINKS):
    ax.semilogy(k_axis, nn_run["Wq"][:, a], lw=0.9, label=f"link {i + 1}←{j + 1}")
ax.axhline(1.0, color="r", lw=1.0, label="bound (19)")
ax.set_title(r"(e) $\mathrm{tr}[\tilde W^\top Q^{-1}\tilde W]$, $W=W^\star$")
ax.set_ylim(1e-3, 10)
ax.legend(fontsize=7)
ax = axs[1, 2]
ax.plot(k_axis[1:], p_op3[1:], "o-", ms=2.5, label=f"OP3, $\\mathfrak{{B}}={op3_scale:g}I$")
ax.axhline(p, color="k", ls="--", lw=0.8, label=f"p = {p} (OP2)")
ax.axhline(0.0, color="r", lw=0.8, ls=":", label=r"$\rho_k\geq1$: void")
ax.set_title(r"(f) guaranteed $p_k = 1-\rho_k$ (corrected OP3)")
ax.set_ylim(min(0.0, float(np.nanmin(p_op3))) - 0.1, 1)
ax.legend(fontsize=6.5, loc="upper right", bbox_to_anchor=(1.0, 0.76))
for ax in axs.flat:
    ax.set_xlabel("time step $k$")
axs[0, 0].set_ylabel("value [–]")
axs[1, 0].set_ylabel("value [–]")
fig.tight_layout()
plotting.save_figure(fig, FIG_DIR, "extra_diagnostics", data={
    "k": k_axis,
    **{f"qf_nn_node{i + 1}": nn_run["qf"][:, i] for i in range(N)},
    **{f"qf_conv_node{i + 1}": conv_run["qf"][:, i] for i in range(N)},
    "trB_nn": np.trace(nn_run["Bell"], axis1=1, axis2=2),
    "trB_conv": np.trace(conv_run["Bell"], axis1=1, axis2=2),
    "maxH_nn": np.append(nn_run["Hn"], np.nan), "maxH_conv": np.append(conv_run["Hn"], np.nan),
    **{f"What_F_link{i + 1}{j + 1}": nn_run["Wn"][:, a] for a, (i, j) in enumerate(LINKS)},
    **{f"thm1_link{i + 1}{j + 1}": nn_run["Wq"][:, a] for a, (i, j) in enumerate(LINKS)},
    "p_op3": p_op3,
}, tolerance={
    "qf_*": results.Tolerance(
        rtol=0.05, atol=1e-9,
        reason="quadratic forms on a log axis, set by interior-point iterates of B_k: up to 0.6 % "
        "apart under other BLAS kernels"),
    "maxH_*": results.Tolerance(
        rtol=0.2, atol=1e-9,
        reason="largest coupling gain ||H_ij|| (NN design ~1e-4, log axis): a flat LMI direction, "
        "its interior-point iterate 4 % apart under other BLAS kernels"),
    "What_F_*": results.Tolerance(
        rtol=0.0, atol=1e-8,
        reason="NN weights collapsed to rounding level after k = 0 (<= 3e-9): their values are noise, "
        "38 % apart under other BLAS kernels"),
    "*": results.LMI_ITERATES,
})
plt.show()

# %% [markdown]
# ## Extra — sensitivity of the headline comparison to the missing values
#
# Each row changes one missing value or one alternative OCR reading and reruns both estimators.
# Rows marked "rule" re-apply the Taylor-scale rule to their own runs (the premise of (12)–(13)
# depends on $f$, $g_i$ and the trajectory); rows marked "fixed" impose a scale, and the column
# "(12)-(13)" says whether the premise then holds along both runs. The columns are the per-node
# RMSE of the NN-based estimator (8) and of the comparison design, their network averages and the
# nodes at which NN is better. The comparison design is the attack-unaware conventional design
# except in the row "attack-aware (3)". That row runs (3) with the gains of LMI (30) and no
# compensation ($\hat W\equiv0$, $Q=e_1^2I$, no OP1), which isolates what the NN compensator adds.
# The last columns are the fraction of (node, step) pairs inside the NN design's ellipsoid,
# $\mathrm{tr}\,\mathfrak B_T$ of the NN design and the number of infeasible steps.

# %%
f_0d5 = copy.deepcopy(f_terms)
f_0d5[0][1][0] = 0.05  # "0d5" read as 0.05 instead of 0.45
g1_sin2 = copy.deepcopy(g1_terms)
g1_sin2[0][1][3] = 2  # "sin(2z" read as sin(2 x^(2)) instead of sin x^(2)
# (label, simulate keywords, reading changes, comparison, scale: "rule" or a number)
sens_rows = [("default", {}, {}, "conv", "rule")]
if mode == "paper":
    sens_rows += [
        ("L_i = aleph_i = 0.05 I", {}, {}, "conv", 0.05),
        ("L_i = aleph_i = 0.1 I (previous default)", {}, {}, "conv", 0.1),
        ("L_i = aleph_i = 0.2 I", {}, {}, "conv", 0.2),
        ("alpha_bar = 0.6", {"abar": 0.6}, {}, "conv", "rule"),
        ("x0 = [2, 1]", {"x_init": [2.0, 1.0]}, {}, "conv", "rule"),
        ("E_1 amplitude 0.1 ('+0.1cos')", {}, {"E1_amp": 0.1}, "conv", "rule"),
        ("f: '0d5' read 0.05", {}, {"f": f_0d5}, "conv", "rule"),
        ("g_1: sin(2 x^(2))", {}, {"g": [g1_sin2, g2_terms, g3_terms]}, "conv", "rule"),
        ("attack-aware (3), W_hat = 0", {}, {}, "aware0", "rule"),
    ]
else:
    sens_rows += [("L_i = aleph_i = 0.1 I (previous default)", {}, {}, "conv", 0.1)]
sens_rows += [(f"alpha realisation {s_ + 1}", {"alpha_idx": s_ + 1}, {}, "conv", "rule")
              for s_ in range(n_extra)]

table = []
for label, kw, changes, comp, scale in sens_rows:
    kw = dict(kw)
    idx = kw.pop("alpha_idx", 0)
    abar_row = kw.get("abar", alpha_bar)
    a_seq = alphas[idx] if abar_row == alpha_bar else alpha_sequence(
        montecarlo.spawn_rngs(seed, 1)[0], T_run, abar_row)
    with reading(**changes):
        if label == "default":
            s_row, r_nn, r_cmp = taylor_scale, nn_run, conv_run
        elif scale == "rule":
            s_row, r_nn, r_cmp, _ = select_taylor_scale(a_seq, **kw)
            if comp != "conv":
                r_cmp = simulate(alpha=a_seq, estimator=comp, L_s=s_row, A_s=s_row, **kw)
        else:
            s_row = scale
            r_nn = simulate(alpha=a_seq, estimator="nn", L_s=s_row, A_s=s_row, **kw)
            r_cmp = simulate(alpha=a_seq, estimator=comp, L_s=s_row, A_s=s_row, **kw)
    worst = float(max(r[key].max() for r in (r_nn, r_cmp) for key in ("ratio_f", "ratio_g")))
    e_nn, e_cmp = rmse(r_nn), rmse(r_cmp)
    table.append({
        "label": label, "comparison": comp, "scale": s_row,
        "scale_from": "rule" if scale == "rule" else "fixed", "premise": worst <= s_row,
        "nn": e_nn, "cmp": e_cmp,
        "nn_better": [int(i + 1) for i in range(N) if e_nn[i] < e_cmp[i]],
        "frac_inside": float(np.mean(r_nn["qf"] <= 1.0)),
        "trB_T": float(np.trace(r_nn["Bell"][-1])),
        "infeasible": len(r_nn["failures"]) + len(r_cmp["failures"]),
    })
print("| row | L_i = aleph_i | (12)-(13) | NN RMSE (nodes 1-3) | comparison RMSE | mean NN / cmp "
      "| NN better at | inside | tr B_T (NN) | infeasible |")
print("|---|---|---|---|---|---|---|---|---|---|")
for row in table:
    print(f"| {row['label']} ({row['comparison']}) | {row['scale']:g} ({row['scale_from']}) | "
          f"{'holds' if row['premise'] else 'FAILS'} | {np.round(row['nn'], 4).tolist()} | "
          f"{np.round(row['cmp'], 4).tolist()} | {row['nn'].mean():.4f} / {row['cmp'].mean():.4f} | "
          f"{row['nn_better']} | {row['frac_inside']:.3f} | {row['trB_T']:.2f} | "
          f"{row['infeasible']} |")
_ = plotting.save_data(FIG_DIR, "extra_sensitivity", {
    "row": np.array([r["label"] for r in table]),
    "comparison": np.array([r["comparison"] for r in table]),
    "taylor_scale": np.array([r["scale"] for r in table]),
    "scale_from": np.array([r["scale_from"] for r in table]),
    "premise_holds": np.array([int(r["premise"]) for r in table]),
    "rmse_nn": np.array([r["nn"] for r in table]),
    "rmse_comparison": np.array([r["cmp"] for r in table]),
    "n_nodes_nn_better": np.array([len(r["nn_better"]) for r in table]),
    "frac_inside": np.array([r["frac_inside"] for r in table]),
    "trB_T_nn": np.array([r["trB_T"] for r in table]),
    "infeasible_steps": np.array([r["infeasible"] for r in table]),
}, tolerance=dict.fromkeys(["rmse_*", "frac_inside", "trB_T_nn"], results.LMI_ITERATES))

# %% [markdown]
# ## Claims
#
# | id | paper | what we measure |
# |---|---|---|
# | C1 | each node tracks both states with the NN estimator (Figs. 1–4); the conventional one "with certain precision" (Figs. 5–8) | $\max|\tilde x^{(l)}_{i,k}|$ of (8) for $k\ge$ `settle_k` against `track_tol`; the conventional value and which of the two is smaller are reported |
# | C2 | the errors stay in the required region with probability $\ge p$ (Theorem 3, (11)) | fraction of (node, step) pairs with $\tilde x^\top\mathfrak B_k^{-1}\tilde x\le1$, NN design, against $p$ (plus the extra $\alpha$ realisations) |
# | C3 | the NN estimator beats the conventional one under the same falsified innovations (Figs. 5–8 vs 1–4) | per-node RMSE over $k=1..T$ (the brief's check): holds if (8) has the lower RMSE at **every** node; the network average is reported as extra information |
# | C4 | $\mathrm{tr}[\tilde W^\top Q^{-1}\tilde W]\le1$ for all $k$ (Theorem 1) | max over links and steps, with $W=W^\star$. Holds **by construction** here: the maximum is at $k=0$, fixed by the data ($\|I-W^\star\|_F^2/20$), and from $k=1$ on $\hat W\approx0$, $Q=e_1^2I$, so (19) holds for any $W$ allowed by Assumption 2 |
# | C5 | the RLMIs are solvable at every step (Algorithm 1) | infeasible steps (both designs and OP1) and the certificate: largest eigenvalue of every solved LMI matrix $\le10^{-8}$ |
# | X1 | (ours) the error dynamics (54) | $\max|\tilde x_{i,k+1}-(\Xi_i+\tilde\alpha_k\tilde\Xi_i)\zeta_k|$ at the actual $\zeta_k$ |
# | X2 | (ours) the premise (12)–(13) of Theorems 2–3 with the chosen $L_i=\aleph_i$ | fraction of (node, step) of both runs with $\|\text{remainder}\|\le$ scale $\cdot\|\tilde x\|$ (the rule makes it 1 unless the scales are overridden) |
# | X3 | (ours) the mechanism: OP1 collapses the weights (E4), OP2 drops the neighbours (E5) | $\max_{k\ge1}\|\hat W_{ij,k}\|_F$ and $\max\|H_{ij}\|$ of both designs |
# | X4 | (ours) Theorem 2: the solved (30) bounds $E_\alpha\{\tilde x^\top P^{-1}\tilde x\}$ by 1 (29) | the quadratic form on 256 random admissible $\zeta$ per step (boundary of every constraint) |
# | X5 | (ours) DPP re-solve equals a fresh build | $\max|P_{k+1}|$ difference at the last step |
# | X6 | (ours) the printed shared multipliers (22) against per-node multipliers | $\mathrm{tr}\,\mathfrak B_k$ of both over the first `shared_diag_steps` steps, every solve certified |
#
# C6 (the cost per step, Remark 7) is a timing and belongs to the benchmark suite (`make bench`).

# %%
claims = {}
late = k_axis >= min(settle_k, T_run)
max_late = {name: float(np.max(np.abs(r["err"][late]))) for name, r in
            (("nn", nn_run), ("conv", conv_run))}
claims["C1"] = results.claim(
    paper="Figs. 1-4: the NN-based estimator (8) estimates both state components at every node "
    "with satisfactory precision (the conventional one, Figs. 5-8, 'with certain precision')",
    check=f"max |x~^(l)_(i,k)| of (8) over nodes, components and k >= {min(settle_k, T_run)} "
    f"<= {track_tol} (the Fig. 3-4 data range); the conventional estimator's value is reported",
    measured={**max_late, "nn_smaller_than_conv": max_late["nn"] < max_late["conv"]},
    threshold=track_tol, holds=max_late["nn"] <= track_tol,
    tolerance=results.LMI_ITERATES,
)
frac = float(np.mean(nn_run["qf"] <= 1.0))
frac_seeds = [float(np.mean(row["frac_inside"])) for row in table if "realisation" in row["label"]]
claims["C2"] = results.claim(
    paper="Theorem 3: P{x~_(i,k)^T B_k^-1 x~_(i,k) <= 1} >= p = 0.8 at every node and step",
    check="fraction of (node, step) pairs, k = 0..T, inside the OP2 ellipsoid B_k of the NN "
    "design >= p (also on the extra alpha_k realisations); max of the quadratic form reported. "
    f"Valid only where the premise (12)-(13) holds (X2, L_i = aleph_i = {L_used:g} I)",
    measured={"fraction": frac, "max_quadratic_form": float(nn_run["qf"].max()),
              "fraction_extra_realisations": frac_seeds,
              "fraction_conventional_design": float(np.mean(conv_run["qf"] <= 1.0))},
    threshold=p,
    holds=frac >= p and all(fs >= p for fs in frac_seeds),
    tolerance=results.LMI_ITERATES,
)
e_nn, e_conv = rmse(nn_run), rmse(conv_run)
nodes_better = [i + 1 for i in range(N) if e_nn[i] < e_conv[i]]
claims["C3"] = results.claim(
    paper="Section IV: under identical falsified innovations the conventional estimator (3) "
    "shows worse estimation performance than the NN-based estimator (8)",
    check="per-node RMSE (k = 1..T) of (8) < that of (3) at every node (the brief's per-node "
    "check); the network averages are reported as extra information, not used for holds",
    measured={"rmse_nn": e_nn, "rmse_conventional": e_conv, "nodes_nn_better": nodes_better,
              "mean_nn": float(e_nn.mean()), "mean_conventional": float(e_conv.mean()),
              "mean_nn_better": bool(e_nn.mean() < e_conv.mean()),
              "relative_difference": (e_nn - e_conv) / e_conv,
              "taylor_scale": L_used},
    threshold="rmse_nn < rmse_conventional at every node",
    holds=len(nodes_better) == N,
    tolerance=results.LMI_ITERATES,
)
thm1_max = float(nn_run["Wq"].max())
claims["C4"] = results.claim(
    paper="Theorem 1, (19): tr[W~_(ij,k)^T Q_(ij,k)^-1 W~_(ij,k)] <= 1 for all k",
    check="max over links and k = 0..T with the ideal weight W = W* (least-squares fit of chi). "
    "Holds by construction: the max is at k = 0, fixed by the data (||I - W*||_F^2 / 20); from "
    "k = 1 on W_hat ~ 0 and Q = e1^2 I, so (19) holds for any W allowed by Assumption 2",
    measured=thm1_max, threshold=1.0, holds=thm1_max <= 1.0,
    tolerance=results.LMI_ITERATES,
)
all_reports = nn_run["reports"] + conv_run["reports"]
worst = max(r.worst_eig for r in all_reports)
n_infeasible = len(nn_run["failures"]) + len(conv_run["failures"])
claims["C5"] = results.claim(
    paper="Algorithm 1 / Theorems 1-3: the recursive LMIs (18) and (30) are solvable at every "
    "step",
    check="number of steps without a certified solution (OP2 of both designs, OP1) == 0, and the "
    f"largest eigenvalue of every solved LMI matrix <= {cert_tol:g}",
    measured={"infeasible_steps": n_infeasible, "solves": len(all_reports),
              "max_eigenvalue": worst, "fallbacks_to_scs": sum(r.fallback for r in all_reports),
              "statuses": sorted({r.status for r in all_reports}),
              "max_asymmetry": max(max(r.asymmetry.values()) for r in all_reports),
              "max_residual": max(max(r.residual.values()) for r in all_reports),
              "max_iterations": max(r.iterations or 0 for r in all_reports)},
    threshold={"infeasible_steps": 0, "max_eigenvalue": cert_tol},
    holds=n_infeasible == 0 and worst <= cert_tol,
    tolerance=results.Tolerance(
        rtol=0.25, atol=1e-6,
        reason="interior-point diagnostics at the solver's stopping point: iteration counts may differ "
        "by a few and residuals / eigenvalue margins (~1e-7) by their own size between machines; "
        "the certification itself is compared exactly through holds"),
)
claims["X1"] = results.claim(
    paper="(ours) error dynamics (54) with the row blocks re-derived from (15)-(16)",
    check="max |x~_(i,k+1) - (Xi_i + (alpha_k - alpha_bar) Xi~_i) zeta_k| over nodes and steps, "
    "zeta_k built from the actual remainders, delta = chi - W* phi and r = Mbar^-1 rho(W* - W_hat)",
    measured=float(nn_run["dyn_res"].max()), threshold=1e-10,
    holds=float(nn_run["dyn_res"].max()) <= 1e-10,
)
rat_f = np.concatenate([nn_run["ratio_f"], conv_run["ratio_f"]])
rat_g = np.concatenate([nn_run["ratio_g"], conv_run["ratio_g"]])
cover_f, cover_g = float(np.mean(rat_f <= L_used)), float(np.mean(rat_g <= aleph_used))
claims["X2"] = results.claim(
    paper="(ours) the premise of Theorems 2-3: Taylor remainders (12)-(13) with ||Delta|| <= 1, "
    "i.e. ||remainder|| <= ||L_i|| ||x~|| with the chosen L_i = aleph_i",
    check="fraction of (node, step) pairs of the NN and the conventional run where the f- and "
    "g-remainders are within the scale == 1; the scale comes from the rule (smallest multiple of "
    f"{taylor_grid:g} satisfying it) unless overridden; max ratios and max ||delta_j|| <= e3 "
    "reported",
    measured={"fraction_f": cover_f, "fraction_g": cover_g,
              "max_ratio_f": float(rat_f.max()), "max_ratio_g": float(rat_g.max()),
              "max_ratio_f_nn": float(nn_run["ratio_f"].max()),
              "max_ratio_g_nn": float(nn_run["ratio_g"].max()),
              "k0_ratio": float(remainder_ratios_k0(x0, xhat0)),
              "candidates": [[c, w] for c, w in rule_history],
              "max_delta": float(nn_run["delta_n"].max())},
    threshold={"L_scale": L_used, "aleph_scale": aleph_used, "grid": taylor_grid, "e3": e3,
               "from_rule": taylor_scale is not None},
    holds=cover_f == 1.0 and cover_g == 1.0,
    tolerance=results.LMI_ITERATES,
)
w_after = float(nn_run["Wn"][1:].max())
claims["X3"] = results.claim(
    paper="(ours, brief E4-E5) the NN compensation is inactive: OP1 sets W_hat to ~0 at k = 1 "
    "and the robust design (30) drops the neighbour innovations",
    check="max_(k>=1) ||W_hat_(ij,k)||_F <= 1e-6 and max ||H_ij|| of (30) below 1e-2 while the "
    "conventional design's is above 0.5",
    measured={"max_What_after_k0": w_after, "max_H_nn": float(nn_run["Hn"].max()),
              "max_H_conventional": float(conv_run["Hn"].max()),
              "lambda1_k0": nn_run["lam"][0, :, 0], "lambda2_k0": nn_run["lam"][0, :, 1]},
    threshold={"What": 1e-6, "H_nn": 1e-2, "H_conventional": 0.5},
    holds=w_after <= 1e-6 and nn_run["Hn"].max() < 1e-2 and conv_run["Hn"].max() > 0.5,
    tolerance=results.LMI_ITERATES,
)
q_max = float(nn_run["sampled_q"].max())
claims["X4"] = results.claim(
    paper="(ours) Theorem 2: LMI (30) implies E_alpha{x~_(i,k+1)^T P_(k+1)^-1 x~_(i,k+1)} <= 1 (29) "
    "for every zeta admissible under the S-procedure constraints of (23)",
    check="max over steps, nodes and 256 random zeta per step on the boundary of every "
    "constraint of zeta^T (Xi^T P^-1 Xi + sigma^2 Xi~^T P^-1 Xi~) zeta <= 1",
    measured=q_max, threshold=1.0, holds=q_max <= 1.0,
    tolerance=results.LMI_ITERATES,
)
claims["X5"] = results.claim(
    paper="(ours) DPP: the per-step problem built once with cp.Parameters and re-solved gives the "
    "same solution as a freshly built problem",
    check="max |P_(k+1) re-solved - P_(k+1) fresh| at the last step <= 1e-6",
    measured=dpp_gap, threshold=1e-6, holds=dpp_gap <= 1e-6,
    tolerance=results.LMI_ITERATES,
)
claims["X6"] = results.claim(
    paper="(ours) the printed LMI (22) with one multiplier set Gamma_k shared by all nodes is a "
    "special case of per-node multipliers, so it is never less conservative",
    check=f"tr B_k of the shared and the per-node design over k = 0..{n_sh} on the same data "
    "(shared >= per-node at every step), every shared solve certified",
    measured={"trB_shared": trB_shared, "trB_per_node": trB_node,
              "uncertified_steps_shared": len(shared_run["failures"])},
    threshold="trB_shared >= trB_per_node - 1e-6",
    holds=bool(np.all(trB_shared >= trB_node - 1e-6)) and not shared_run["failures"],
    tolerance=results.LMI_ITERATES,
)
results.write_claims(results_path, claims)
for cid, c in claims.items():
    print(cid, "holds" if c["holds"] else "DOES NOT HOLD")

# %% [markdown]
# ## Discussion
#
# * **The Taylor scales decide the headline.** The premise (12)–(13) of Theorems 2–3 needs
#   $\|\text{remainder}\|\le s\|\tilde x\|$. At $k=0$ the estimates are given, and the ratios are
#   0.103 ($f$) and 0.115 ($g$) whatever the design, so every $s<0.115$ voids the guarantee at the
#   first step. The rule picks $s=0.15$, and the premise then holds at every node and step of both
#   runs (X2). At this scale the conventional design also becomes cautious ($\|H\|\approx1.6$
#   instead of 1.9) and its RMSE drops to the level of the NN design. C3 fails per node (NN better
#   only at node 2, by 0.4 %) and on the network average (0.089 against 0.085), and the three
#   further $\alpha_k$ realisations favour the conventional estimator at every node. At $s=0.2$
#   the two are equal to within 1 %.
# * **Where C3 held, it held through robustness, not learning.** OP1 is a convex problem in which
#   $\lambda^{(2)}=0$ is always at least as good as any other value: (18) is invariant under
#   $\lambda^{(2)}\to-\lambda^{(2)}$ (E4). With $Q_0=20I$ and $e_1=3$ the S-procedure radius
#   $\lambda^{(1)}\sqrt{20}+(1-\lambda^{(1)})\cdot3$ is smallest at $\lambda^{(1)}=0$. Hence
#   $\hat W_{ij,1}=0$, $Q_{ij,k}\to9I$, and the compensation $\bar\alpha\hat W\phi(z_i)$ is zero from
#   $k=1$ on (X3, panel d). The robust design (30) pays a worst-case price
#   $\approx\sqrt{\bar\alpha}e_3\|H\|$ for every neighbour innovation, so it sets
#   $\|H_{ij}\|\approx4\cdot10^{-4}$ (panel c) and the network decouples. The attack-unaware design
#   uses $\|H\|\approx1.6$–$1.9$: neighbour innovations help it because they partly cancel the shared
#   measurement noise $\mu_k$, and they hurt it when $\alpha_k=1$, since $0.3\cos z^{(2)}\approx0.3$
#   is almost a constant bias. The row "attack-aware (3), W_hat = 0" gives the same RMSE as the NN
#   estimator to four digits: everything the comparison shows is due to the attack-aware gains.
# * **Alternative OCR readings.** With $E_1$'s amplitude read as 0.1 or the $g_1$ term read as
#   $\sin 2x^{(2)}$, NN is better at all three nodes (by 1–6 %); with "0d5" read as 0.05 only at
#   node 1. With $x_0=[2;1]$ (Assumption 3 fails at nodes 1–2) the rule gives $s=0.2$ and the
#   conventional estimator is better at every node. $\bar\alpha=0.6$ does not change the NN design,
#   whose gains switch the attacked channels off.
# * **C2 is very conservative.** The largest normalised error is about 0.09 against the threshold
#   1, and it occurs at $k=0$, where $\mathfrak B_0=P_0/(1-p)$ is fixed by Assumption 3. The LMI
#   budgets for the worst case $V_k=1$, while $|v_k|\le0.3$, and for $e_3=3$, while
#   $\|\delta\|\le0.3$. The LMI itself is tight: on sampled $\zeta$ at the boundary of every
#   S-procedure constraint, the quadratic form of (55) reaches 0.9996 (X4). The slack comes from
#   the admissible set (the bounds $V$, $U$, $e_3$, $N^2$), not from the S-procedure.
# * **C4 holds by construction.** Its maximum is at $k=0$ and is fixed by the data,
#   $\|I-W^\star\|_F^2/20$. From $k=1$ on $\hat W\approx0$ and $Q=e_1^2I$, so (19) holds for any
#   $W$ that Assumption 2 allows: the check cannot fail on this example.
# * **OP3.** With the fixed ellipsoid $\mathfrak B=2I$ the guaranteed probability starts at 0.57
#   and falls below 0 ($\rho_k\ge1$) from $k=7$ on (34 of 40 steps): $2I$ is smaller than what the
#   premise-respecting design needs ($\mathrm{tr}\,\mathfrak B_k\approx7$), so the bound is void
#   there (panel f). With the earlier scale $0.1I$ it stayed near 0.4.
# * **Shared multipliers (X6).** The printed (22) with one $\Gamma_k$ roughly doubles
#   $\mathrm{tr}\,\mathfrak B_k$ per step over the two steps run (7.1, 16.1, 32.0), while per-node
#   multipliers keep it near 7. We do not claim what happens later: from $k=2$ on the solvers no
#   longer certify the shared LMI.

# %% [markdown]
# ## Deviations from the paper
#
# | item (tag) | paper (as printed / OCR) | here | why |
# |---|---|---|---|
# | E1, Lemma 4 (CORRECTED) | $P_k$ defined with a factor $\tfrac1{1-p}$ | $P_k=(1-p)\mathfrak B_k$ | the only reading under which Markov's inequality yields (11) |
# | E2, OP3 (33) (CORRECTED) | min $q_k=1/(1-p_k)$, \"1 < q < +∞\" | min $\rho=1-p_{k+1}$ with $-\rho\mathfrak B$ in (30) | as printed the problem is not convex and points the wrong way |
# | E3, multipliers (DEVIATION, design choice) | one $\Gamma_k$ shared by all $N$ inequalities (22) | one $\Gamma_{i,k}$ per node (`shared_multipliers=False`) | the printed form is not wrong, only more conservative; per-node multipliers are a valid relaxation (a separate S-procedure per inequality). The printed LMI is run for 2 steps (X6): $\mathrm{tr}\,\mathfrak B$ 7.1 → 16.1 → 32.0 against 7.1 → 6.6 → 6.9. Later steps are not claimed: the solvers stop certifying the shared LMI from $k=2$ on |
# | (24)–(28) | OCR damaged | row blocks re-derived from (15)–(16) (table above) | checked to machine precision on the actual run (X1) |
# | $\varrho$, $\bar M$ | $\varrho$ stacks rows; $Q_{ij}\otimes I$ | `A.flatten()`; $\bar M=\mathrm{chol}(Q)\otimes I_{n_\phi}$ | consistent with $\mathrm{tr}[W^\top Q^{-1}W]=\varrho^\top(Q^{-1}\otimes I)\varrho$ |
# | $r$-vector | all $N^2$ ordered pairs ($d=63$) | links only ($d=43$), bound $r^\top r\le N^2$ kept | the dropped columns are identically zero |
# | (18) strict, (22) non-strict | | every LMI imposed as $\le-10^{-6}I$ and certified with numpy at $10^{-8}$ | margin above the solver tolerance |
# | OP1 | $\lambda^{(1)},\lambda^{(2)}$ "positive" | free, with $|\lambda^{(2)}|\le10^3$ | the box removes an unbounded optimal face when $\varpi\approx0$ and is never active; $\lambda^{(2)}=0$ is optimal anyway (E4) |
# | OP1 | one problem per link | one separable problem (sum of traces) | same minimisers, one solve per step |
# | conventional design (MISSING) | "characterised by (3)" | attack-unaware analogue of OP2 | MISSING in the paper |
# | $L_i$, $\aleph_i$ (MISSING) | not given | $sI_2$, $s$ = smallest multiple of 0.05 for which (12)–(13) hold along both runs: 0.15 | a value under which the paper's own premise fails would void Theorems 2–3; the previous default 0.1 (premise fails at $k=0$) is a sensitivity row |
# | C3 criterion | "worse estimation performance" | per node, as in the brief's check; network average reported | an earlier version of this notebook judged C3 on the network average, a change of criterion that was not named; we follow the brief again |
# | $x_0^{(2)}$ (MISSING) | illegible ("R [ O I") | 2.0 | chosen so that Assumption 3 holds; 1.0 and 0.1 violate it |
# | $\varpi$ in (17) (RECONSTRUCTED) | "a Z 9in5,;€‘1’2;€+12@1€+1 JEN;" | sum over $j\in\mathcal N_i$ (`varpi_form`) | immaterial here ($\lambda^{(2)}=0$, E4) |
# | example values (RECONSTRUCTED / MISSING) | partly illegible | see the provenance table; the alternative readings of $E_1$, \"0d5\" and \"sin(2z\" are sensitivity rows | OCR |
# | $\bar\alpha$ (RECONSTRUCTED) | \"o= 067\" | 0.67 (brief: 0.6) | we read the digits literally, with the decimal point lost; 0.6 is in the sensitivity table |
# | $W_{ij}$ | not given | $W^\star$, least-squares fit of $\chi$ | needed to evaluate C4 and X1 |
# | figures | curves of the paper | qualitative comparison only | the paper's figures survive only as tick residue; the reconstructed $f,g_i$ cannot be checked against them |
# | C6, cost per step | Remark 7 | not measured here | timings belong to the benchmark suite (`make bench`) |

# %%
manifest_path = run.finish(solver=f"{solver} (fallback {fallback_solver})",
                           extra={"T_run": T_run, "lmi_solves": len(all_reports)})
print("run manifest:", manifest_path.relative_to(results.repo_root()))
