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
# **Verdict: [Re, partial]**, by the project's one written rule (section "Verdict"), decided by
# the paper's main claims C2 (the probability guarantee, Theorem 3), C3 (the NN-based estimator
# beats the conventional one under the same falsified innovations) and C7 (the joint estimation of
# the attacks, contribution iv). At the paper's example (our default point, the geometric centre
# of the declared range of the missing Taylor scales) C2 holds as Theorem 3 states it, at every
# node and step: over 94 independent $\alpha_k$ realisations (a run count fixed by a power
# computation before the outcome was seen) every one of the 120 (node, step) pairs has its
# Bonferroni lower end above $p$; very conservatively, since the quadratic forms stay far below 1.
# Over the declared space, swept at 16 runs for cost, C2 cannot decide (its per-pair rule needs
# at least 50 runs to hold): not checked there, so the space gives no evidence for it either way.
# C3 does not hold at the example: over the same 94 realisations the NN estimator is worse than
# the conventional one at nodes 1 and 3 (ratios of the mean RMSEs 1.0016 and 1.0094). That
# failure says little about the falsified innovations: against an attack-free control the attack
# raises the conventional RMSE by 0.146 % at node 3 (the precondition, more than 0.1 % at some
# node, holds only narrowly: interval lower end 0.101 %), and without any attack the NN design is
# already 1.08 % worse there (ratio 1.0108). Over the space C3's counts are still those of its
# previous one-realisation rule (not re-swept). C7 does not hold: the NN's estimate of the attack
# is the zero estimate, by construction of OP1 (E4), so its failures over the space are one
# evaluation repeated, not independent evidence. **The NN
# compensator, the paper's main contribution, is never active**, at the example or anywhere in
# the declared space: with the paper's $Q_{ij,0}=20I$ and $e_1=3$ the tuning law's LMI (OP1) sets
# $\hat W=0$ from the first step on (E4), and the robust gain design switches the neighbours' innovations
# off (X3). Where C3 holds (only at the smallest Taylor scales, whose grid levels were placed
# knowing where it turns) it holds through the attack-aware gains, not through the network.
#
# The solvability of the recursive LMIs (C5) and Theorem 1's weight bound (C4) hold by
# construction here (C5: every LMI is feasible in exact arithmetic; C4: the bound is fixed by the
# data) and are shown, not counted as evidence. Our numerical limits (a solve our strict
# certificate rejects, and the stale gains of our fallback after it) are recorded as not checked,
# never as the paper's failures, and premises are evaluated on certified steps only. The counts
# over the declared space (7 Taylor scales × 2 realisations × 5 OCR readings = 70 points) are
# printed from the sweep in the sections "Claims" and "Verdict". Figures 1–8 are reproduced
# qualitatively only: $f$, $g_i$, $\bar\alpha$ and the initial values are reconstructions from a
# garbled OCR.

# %% tags=["parameters"]
mode = "paper"  # "paper": full runs; "fast": 8 steps and 3 Monte Carlo runs, for the tests (ours)
T = 40  # horizon [0, T] (RECONSTRUCTED from the 0..40 time axes)
seed = 0  # seed of the alpha_k realisation (MISSING)
alpha_bar = 0.67  # Prob{alpha_k is 1} (RECONSTRUCTED from the OCR "o: 067"; the brief reads 0.6)
p = 0.8  # probability level of (10)-(11) (PAPER)
e1 = 3.0  # bound on ||W_ij||_F, Assumption 2 (PAPER)
e3 = 3.0  # bound on ||delta_j||, Assumption 2 (PAPER)
# f and g_i as lists of terms [coef, fn, var, freq, shift] meaning coef * fn(freq * x^(var) + shift),
# fn in {"x", "sin", "cos"}; every coefficient, superscript and frequency is RECONSTRUCTED from the OCR
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
ocr_reading = "as read"  # one alternative reading of a garbled value, applied on top of the above (RECONSTRUCTED)
x0 = [2.0, 2.0]  # initial state; 1st entry PAPER, 2nd MISSING (chosen so that Assumption 3 holds)
xhat0 = [[1.5, 1.8], [1.7, 1.9], [1.8, 1.5]]  # initial estimates (nodes 2-3 RECONSTRUCTED)
P0 = [[0.6887, -0.0588], [-0.0588, 0.7390]]  # Assumption 3 (PAPER)
W0 = [[1.0, 0.0], [0.0, 1.0]]  # initial NN weights, every link (RECONSTRUCTED)
Q0 = [[20.0, 0.0], [0.0, 20.0]]  # Assumption 3 weight-error shape (PAPER)
L_scale = 0.198595065397  # L_i is L_scale times I in (12) (MISSING); the geometric centre of its range
aleph_scale = 0.198595065397  # aleph_i is aleph_scale times I in (13) (MISSING); tied to L_scale
varpi_form = "sum"  # varpi of (17): "sum" over j in N_i as reconstructed, or "per_link" (H_ij only)
shared_multipliers = False  # one Gamma_k for all nodes as printed (True) or one per node
shared_diag_steps = 2  # steps of the printed shared-multiplier LMI (22) run as a diagnostic (ours)
r_bound = "lumped"  # "lumped": r^T r below N^2 as printed; "per_link": one multiplier per link
lam2_max = 1000.0  # box on |lambda2| in OP1 (ours, numerical)
eps_lmi = 1e-6  # strictness margin: every LMI M is imposed as M + eps_lmi I negative semidefinite
cert_tol = 1e-8  # certificate: max eig of every solved LMI matrix at most -cert_tol (strict LMI)
solver = "CLARABEL"  # primary SDP solver
fallback_solver = "SCS"  # visible fallback
c3_margin = 0.001  # C3: NN counts as better at a node when its RMSE is below 1 - c3_margin times the other (ours)
attack_margin = 0.001  # C7: an attack estimate counts when its RMS error is below 1 - attack_margin of the attack RMS (ours)
settle_k = 10  # C1: errors measured from this step on (ours: after the transient)
track_tol = 0.2  # C1: |error| bound for "satisfactory precision" (ours: the paper states no number)
extras = True  # OP3 run, DPP re-solve check X5, certificate at the range's upper end (ours)
mc_runs = 94  # independent alpha_k realisations of C2 and C8b: the power rule of ma2021.toml; fast mode uses 3 (ours)
op3_scale = 2.0  # fixed ellipsoid B is op3_scale times I for the OP3 run (MISSING)
figures = True  # False: no figure or data file is made (robustness sweep points) (ours)
fig_dir = "figures/ma2021"
results_path = "figures/ma2021/claims.json"

# %%
import copy
import csv
import json
import re
import warnings

import cvxpy as cp
import matplotlib.pyplot as plt
import numpy as np
from IPython.display import Markdown, display
from scipy import stats

from secest.core import graphs, montecarlo
from secest.core.validation import ValidationError
from secest.methods import ma2021 as M
from secest.repro import plotting, results, spaces
from secest.repro.literate import show_source

print(results.environment_summary())
print("cvxpy:", cp.__version__, "solvers:", cp.installed_solvers())

run = results.Run("ma2021", globals())  # every value checked against notebooks/ma2021.toml
SPACE = spaces.load("ma2021")
T_run = int(T) if mode == "paper" else min(int(T), 8)
n_mc = int(mc_runs) if mode == "paper" else min(int(mc_runs), 3)
FIG_DIR = results.resolve(fig_dir)
ROBUSTNESS = "figures/ma2021/robustness.json"  # written by `make robustness NB=ma2021`
plotting.setup(enabled=figures)
warnings.filterwarnings("ignore", message="Solution may be inaccurate")  # status is checked


def check_terms(name: str, terms: list) -> None:
    """f_terms, g<i>_terms: two rows (n_x = n_y = 2) of terms [coef, fn, var, freq, shift]."""
    if len(terms) != 2 or not all(isinstance(row, list) and row for row in terms):
        raise ValidationError(f"{name} must hold 2 non-empty rows of terms, found {terms!r}")
    for term in (t for row in terms for t in row):
        numbers = [term[i] for i in (0, 3, 4)] if isinstance(term, list) and len(term) == 5 else []
        if not (numbers and term[1] in ("x", "sin", "cos") and term[2] in (1, 2)
                and all(isinstance(v, int | float) and not isinstance(v, bool) for v in numbers)):
            raise ValidationError(f"{name}: every term must be [coef, 'x' | 'sin' | 'cos', 1 | 2, "
                                  f"freq, shift], found {term!r}")


def check_matrix(name: str, value: list, shape: tuple, spd: bool = False) -> np.ndarray:
    """A nested-list parameter as an array of the given shape (symmetric positive definite)."""
    arr = np.array(value, dtype=object)
    if arr.shape != shape:
        raise ValidationError(f"{name} must have shape {shape}, found {value!r}")
    arr = arr.astype(float)
    if spd and not (np.allclose(arr, arr.T) and np.linalg.eigvalsh(arr).min() > 0):
        raise ValidationError(f"{name} must be symmetric positive definite, found {value!r}")
    return arr


for _name, _terms in (("f_terms", f_terms), ("g1_terms", g1_terms), ("g2_terms", g2_terms),
                      ("g3_terms", g3_terms)):
    check_terms(_name, _terms)
check_matrix("xhat0", xhat0, (3, 2))
check_matrix("P0", P0, (2, 2), spd=True)
check_matrix("W0", W0, (2, 2))
check_matrix("Q0", Q0, (2, 2), spd=True)

# %% [markdown]
# ## Parameter provenance
#
# The OCR of the paper interleaves its two PDF columns, so most of Section IV is garbled. Every
# parameter of the cell above is declared in `notebooks/ma2021.toml` with its admissible domain
# and its tag: **PAPER** (legible), **RECONSTRUCTED** (read from a damaged OCR fragment, which is
# quoted), **MISSING** (not in the paper; ours is a choice), **CORRECTED** (printed, but wrong) or
# **ours** (our own addition). Every value the paper does not pin down also has a **declared
# space**, chosen from the paper's text and assumptions before the sweep was run, with its reason;
# `make robustness NB=ma2021` runs the notebook at every point of its design and the claims'
# verdicts are taken over that space. The table is rendered from the TOML file.

# %%
display(Markdown(spaces.provenance_markdown("ma2021")))
print(f"design of the declared space: {len(spaces.design(SPACE))} points "
      f"(python -m secest.repro.sweep --list ma2021)")

# %% [markdown]
# The model constants that are not parameters:
#
# | quantity | value | tag | raw OCR fragment → reading / reason |
# |---|---|---|---|
# | $N$, graph | 3 nodes, $\Theta=[[0,1,0],[1,0,1],[0,1,0]]$ | PAPER | "01 0 / -1 0 1 / 01 0" (the "-1" is the bracket and a 1) |
# | $n_x,n_y,n_v,n_u,n_\phi$ | 2, 2, 1, 1, 2 | RECONSTRUCTED | from the shapes of $B_k$, $E_{i,k}$, $\phi$ |
# | $B_k$ | $[0.1+0.01\cos(k+1);\ 0.2+0.01\sin k]$ | PAPER | "0.1+ 0.01cos(k + 1) / By, = 0.2+ 0.01 sin(k)" |
# | $E_{1,k}$, $E_{3,k}$ | $[0.25;\ 0.2+a_1\cos(k+1)]$, $[0.25+a_3\sin k;\ 0.15]$ | RECONSTRUCTED | amplitudes $a_1$ = `E1_amp`, $a_3$ = `E3_amp` (table above) |
# | $E_{2,k}$ | $[0.2;\ 0.15+0.1\sin 2k]$ | PAPER | "0.2 / E26=1 0,15+ 0.1 sin(2k)" |
# | $v_k$, $\mu_k$ ($u_k$) | $0.3\cos 2k$, $0.4\sin k$ | PAPER | "We select v_k = 0.3cos(2k) and u(k) = 0.4sin(k)" |
# | $V_k$, $U_k$ | 1, 1 | PAPER | |
# | $\phi(z)$ | $[\tanh z^{(1)};\ \tanh z^{(2)}]$ | PAPER | |
# | $\chi(z)$ | $[0.15\sin z^{(1)};\ 0.30\cos z^{(2)}]$ | PAPER | "0.15sin(2}) / 0'30COS(Z£213)" |
# | $P_k$ in Lemma 4 | $P_k=(1-p)\mathfrak B_k$ | RECONSTRUCTED (E1, OCR) | "Define a matrix $P_k$ by … P& —%, / 1-p": the OCR lost the $-1$ superscripts of $P_k^{-1}=\mathfrak B_k^{-1}/(1-p)$, so the factor $\tfrac1{1-p}$ seems to multiply $P_k$; read with the inverses it is the only reading under which Lemma 3 (Markov's inequality) gives (11). An OCR reconstruction, not an erratum of the paper (an earlier version called it CORRECTED) |
# | OP3 (33) | min $\rho=1-p_{k+1}$ with $-\rho\mathfrak B$ in (30) | CORRECTED (E2) | printed "min $q_k=1/(1-p_k)$" is not convex and points the wrong way |
# | (24)–(28) | row blocks of $\Xi_k$, $\tilde\Xi_k$ re-derived from (15)–(16) | RECONSTRUCTED | the OCR is damaged; where it is legible (e.g. $(\Phi_k-G_k\Psi_k-H_k\dots)S_k$ in (27), $(G_k+H_k)E(I_N\otimes I)$ in (28)) it agrees with the re-derived blocks; checked to machine precision on the run (X1) |
# | conventional design | attack-unaware OP2 | MISSING | the paper only says "characterised by (3)"; we design (3) with the same LMI, without the attack terms, and run it on the falsified data. Other readings are plausible (e.g. an attack-aware OP2 without the NN terms; the NN design's own gains with $\hat W=0$ would coincide with the NN estimator, X3); none is swept, so C3's map is conditional on this one |
# | ideal weight $W_{ij}$ | $W^\star$, least-squares fit of $\chi$ | MISSING | needed only to evaluate C4 and X1 |
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
M_RHO = NY * NPHI  # length of rho(W) = vec of the rows of W
LINKS = [(i, j) for i in range(N) for j in range(N) if THETA[i, j] != 0]  # (receiver, sender)
NBRS = [[j for j in range(N) if THETA[i, j] != 0] for i in range(N)]


def read_example(name: str) -> dict:
    """The reading of the damaged example in use: the parameters cell with the single
    alternative `ocr_reading` applied (the TOML lists the alternatives and their OCR fragments)."""
    f_t, g1_t, e1_amp = copy.deepcopy(f_terms), copy.deepcopy(g1_terms), float(E1_amp)
    abar = 0.6 if name == "alpha_bar: 0.6" else float(alpha_bar)  # "o= 067" read as "0.6,"
    if name == "E1: +0.1cos(k+1)":  # "0.2401cos" read as 0.2 + 0.1cos(k+1)
        e1_amp = 0.1
    elif name in ("f: 0d5 as 0.05", "g1: sin(2x2)"):
        owner = "f_terms" if name.startswith("f") else "g1_terms"
        sin_terms = [t for t in (f_t if owner == "f_terms" else g1_t)[0] if t[1] == "sin"]
        if not sin_terms:
            raise ValidationError(f"ocr_reading {name!r} needs a sin term in row 1 of {owner}")
        if owner == "f_terms":
            sin_terms[0][0] = 0.05  # "0d5" read as 0.05 instead of 0.45
        else:
            sin_terms[0][3] = 2  # "sin(2z" read as sin(2 x^(2)) instead of sin x^(2)
    return {"f": f_t, "g": [g1_t, g2_terms, g3_terms], "E1_amp": e1_amp, "alpha_bar": abar}


READING = read_example(ocr_reading)
ALPHA_BAR = READING["alpha_bar"]  # Prob{alpha_k = 1} in use
print(f"OCR reading in use: {ocr_reading!r} (alpha_bar = {ALPHA_BAR:g}, E_1 amplitude "
      f"{READING['E1_amp']:g})")
_FN = {"x": (lambda u: u, lambda u: np.ones_like(u)), "sin": (np.sin, np.cos),
       "cos": (np.cos, lambda u: -np.sin(u))}


def _map(terms: list, x: np.ndarray) -> np.ndarray:
    """Sum of coef * fn(freq * x^(var) + shift) per row (the term lists of the parameters cell)."""
    return np.array([sum(c * _FN[fn][0](w * x[v - 1] + b) for c, fn, v, w, b in row)
                     for row in terms])


def _jac(terms: list, x: np.ndarray) -> np.ndarray:
    """Jacobian of `_map(terms, .)` at x."""
    J = np.zeros((len(terms), NX))
    for r, row in enumerate(terms):
        for c, fn, v, w, b in row:
            J[r, v - 1] += c * w * _FN[fn][1](w * x[v - 1] + b)
    return J


def f(x: np.ndarray) -> np.ndarray:
    """Plant map f of (1) (RECONSTRUCTED); terms `f_terms`."""
    return _map(READING["f"], x)


def jac_f(x: np.ndarray) -> np.ndarray:
    """Phi_{i,k} = df/dx at the estimate, (12)."""
    return _jac(READING["f"], x)


def g(i: int, x: np.ndarray) -> np.ndarray:
    """Sensor map g_i of (1), node i = 0, 1, 2 (RECONSTRUCTED); terms `g<i+1>_terms`."""
    return _map(READING["g"][i], x)


def jac_g(i: int, x: np.ndarray) -> np.ndarray:
    """Psi_{i,k} = dg_i/dx at the estimate, (13)."""
    return _jac(READING["g"][i], x)


# the Jacobians are checked against central differences
_xt = np.array([1.3, -0.7])
_fd = [np.column_stack([(fun(_xt + h) - fun(_xt - h)) / 2e-6 for h in 1e-6 * np.eye(NX)])
       for fun in [f] + [lambda x, i=i: g(i, x) for i in range(N)]]
assert np.allclose(_fd[0], jac_f(_xt), atol=1e-8)
assert all(np.allclose(_fd[i + 1], jac_g(i, _xt), atol=1e-8) for i in range(N))


def B_mat(k: int) -> np.ndarray:
    """Process-noise input B_k of (1) (PAPER)."""
    return np.array([[0.1 + 0.01 * np.cos(k + 1)], [0.2 + 0.01 * np.sin(k)]])


def E_mat(i: int, k: int) -> np.ndarray:
    """Measurement-noise input E_{i,k} of (1); E_1 and E_3 RECONSTRUCTED (amplitudes as parameters)."""
    if i == 0:
        return np.array([[0.25], [0.2 + READING["E1_amp"] * np.cos(k + 1)]])
    if i == 1:
        return np.array([[0.2], [0.15 + 0.1 * np.sin(2 * k)]])
    return np.array([[0.25 + E3_amp * np.sin(k)], [0.15]])


def v_noise(k: int) -> np.ndarray:
    """Process noise v_k (PAPER)."""
    return np.array([0.3 * np.cos(2 * k)])


def mu_noise(k: int) -> np.ndarray:
    """Measurement noise mu_k (u_k in Section IV), shared by all sensors (PAPER)."""
    return np.array([0.4 * np.sin(k)])


def phi(z: np.ndarray) -> np.ndarray:
    """Activation phi(z) = tanh, elementwise (PAPER)."""
    return np.tanh(z)


def chi(z: np.ndarray) -> np.ndarray:
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
#
# **Assumption 3** (initial conditions) is checked at this run's values:
# $(x_0-\hat x_{i,0})^\top P_0^{-1}(x_0-\hat x_{i,0})\le1$ at every node and
# $\mathrm{tr}[\tilde W_{ij,0}^\top Q_{ij,0}^{-1}\tilde W_{ij,0}]\le1$ with $W=W^\star$. It is part of
# the premise of Theorem 3 (C2). The second entry of $x_0$ is illegible; the values for which the
# first part holds at every node are printed, since they bound the plausible readings.

# %%
grid = np.linspace(-1.0, 1.0, 21)
Zg = np.array([[a, b] for a in grid for b in grid])
W_star = np.linalg.lstsq(phi(Zg), np.array([chi(z) for z in Zg]), rcond=None)[0].T
W_star[np.abs(W_star) < 1e-12] = 0.0
delta_grid = np.max(np.linalg.norm(np.array([chi(z) for z in Zg]) - phi(Zg) @ W_star.T, axis=1))
print("W* =", np.round(W_star, 4).tolist(), f"||W*||_F = {np.linalg.norm(W_star):.3f} <= e1 = {e1}")
print(f"max ||delta|| on the grid = {delta_grid:.3f} <= e3 = {e3}")


def assumption3_forms(x_init: list, xh_init: list) -> np.ndarray:
    """(x0 - xhat_i0)^T P0^-1 (x0 - xhat_i0) per node (Assumption 3, first part)."""
    e0 = np.asarray(x_init, float) - np.asarray(xh_init, float)
    return np.einsum("na,na->n", e0, np.linalg.solve(np.asarray(P0, float), e0.T).T)


A3_forms = assumption3_forms(x0, xhat0)
A3_weight = float(np.trace((W_star - np.asarray(W0)).T
                           @ np.linalg.solve(np.asarray(Q0), W_star - np.asarray(W0))))
A3_holds = bool(np.all(A3_forms <= 1.0) and A3_weight <= 1.0)
print(f"x0 = {x0}: Assumption 3 quadratic forms {np.round(A3_forms, 3).tolist()}, "
      f"weight part {A3_weight:.3f} -> Assumption 3 {'holds' if A3_holds else 'FAILS'}")
x2_grid = np.round(np.arange(0.0, 4.0001, 0.01), 2)
x2_ok = [x2 for x2 in x2_grid if np.all(assumption3_forms([x0[0], x2], xhat0) <= 1.0)]
print("2nd entries of x0 for which the first part holds at every node: "
      + (f"[{min(x2_ok):.2f}, {max(x2_ok):.2f}] (step 0.01)" if x2_ok else "none"))
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
show_source(M.estimator_update, after="    if W_hat is not None and phi_own is None:")
show_source(M.update_all, after="    th = np.asarray(theta, float)")


# %% [markdown]
# ## Taylor linearisation (12)–(13) and the error dynamics (15)–(16), (54)
#
# $f(x_k)=f(\hat x_{i,k})+\Phi_{i,k}\tilde x_{i,k}+L_i\Delta_{1i}\tilde x_{i,k}$ and
# $g_i(x_k)=g_i(\hat x_{i,k})+\Psi_{i,k}\tilde x_{i,k}+\aleph_i\Delta_{2i}\tilde x_{i,k}$ with
# $\|\Delta\|\le1$. The OCR letter in front of $\Delta_2$ is $\aleph$. The scales $L_i,\aleph_i$ are
# not given (MISSING): $L_i=\aleph_i=sI_2$ with $s$ in a declared range (section "The missing Taylor
# scales" below).
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
# **Lemma 4, reconstructed from the OCR (E1).** Markov's inequality (Lemma 3) needs
# $E\{\tilde x^\top\mathfrak B_k^{-1}\tilde x\}\le1-p$, so $P_k=(1-p)\mathfrak B_k$. The OCR's
# "P& —%, / 1-p" has lost the $-1$ superscripts of $P_k^{-1}=\mathfrak B_k^{-1}/(1-p)$: the
# "$1/(1-p)$" factor belongs to the inverses. This is a reading of a garbled line, not an erratum
# of the paper. Then $E\{\tilde x^\top P_k^{-1}\tilde x\}\le1$ gives
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
show_source(M.build_op2, after="    th = _theta(theta)")
show_source(M.set_op2_parameters, after="    p = sp.params")


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
show_source(M.build_op1, after='    check_real("e1", e1, lower=0.0)')
show_source(M.mbar, after='    Qm = as_matrix("Q", Q, square=True)')
show_source(M.set_op1_parameters, after="    ph = np.asarray(phi, float)")
show_source(M.varpi, after='    check_choice("form", form, VARPI_FORMS)')
show_source(M.weight_update, after="    return lam1")


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
# **Solves.** Every problem is solved by `secest.core.lmi.solve_certified`. CLARABEL runs first (with
# tolerances $10^{-7}$, and chordal decomposition off for the tiny, degenerate OP1). The status must
# be `optimal`, and every LMI matrix $M$ must have its largest numpy eigenvalue $\le-$`cert_tol`:
# the strict LMI $M<0$ holds beyond `cert_tol` (`certify="strict"`), even where the solver used up
# part of the margin `eps_lmi` it was given.
# Otherwise SCS is tried under a visible warning. If that fails too, an `InfeasibleLMIError` names
# the step and the problem. OP2/OP3 is one joint SDP over all nodes, coupled through
# $P_{k+1}$, so an infeasible solve cannot be blamed on one node ("joint SDP over nodes 1-3"); a
# failed certificate names the node whose LMI (30) violates it. The run then keeps the previous gains, doubles $P$ and counts the step
# (brief §7), and C5 reports the count.

#
# **An exact check of (29) (C8a).** $\alpha_k$ is the only random quantity (E8). Given everything
# up to step $k$, $\tilde x_{i,k+1}$ takes one of two values, for $\alpha_k=0$ and $\alpha_k=1$, so
# $E_{\alpha_k}\{\tilde x_{i,k+1}^\top P_{k+1}^{-1}\tilde x_{i,k+1}\mid\text{past}\}=(1-\bar\alpha)q_{i,0}+\bar\alpha q_{i,1}$
# is computed exactly at every step by running the update on both branches with the solved gains.
# By the Schur complement (55) and the S-procedure, (30) bounds it by 1 at every step where the
# realised $\zeta_k$ satisfies the constraints of (23): $\tilde x_{l,k}^\top P_k^{-1}\tilde x_{l,k}\le1$ at
# every node (the induction hypothesis), (12)–(13), $\|\delta\|\le e_3$ and Theorem 1's weight
# ellipsoid. This is a deterministic check of Theorem 2 along the run; the Monte Carlo check over
# independent realisations (C8b) is below, with C2's.

# %%
show_source(M.run_algorithm1, after="    th = _theta(theta)")
show_source(M._design_step, after="    n_nodes = th.shape[0]")
show_source(M._weight_step, after="    n_nodes = th.shape[0]")
show_source(M.solve, after="    from secest.core import lmi as slmi")

# %% [markdown]
# The example's model, as Algorithm 1 reads it, and the run: the plant (1) is simulated here, the
# sensors' measurements are handed to `run_algorithm1` with the attack (5) on the transmitted
# innovations, and the quantities the claims measure (below) are computed from what it returns.

# %%
MODEL = M.Model(f=f, jac_f=jac_f, g=g, jac_g=jac_g, B=B_mat, E=E_mat, phi=phi)
DIMS = M.Dims(NX, NY, NV, NU, NPHI)
PROBLEMS = {}  # cache of the per-step problems (M.step_problems), built once per configuration
FALLBACK = None if fallback_solver == "none" else fallback_solver


def sample_admissible(rng: np.random.Generator, n_samples: int, S: np.ndarray) -> np.ndarray:
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
             e3 * unit((n_samples, N, NY)), N * unit((n_samples, len(LINKS) * M_RHO))]
    return np.concatenate([q.reshape(n_samples, -1) for q in parts], axis=1)


def alpha_sequence(rng: np.random.Generator, n_steps: int, abar: float) -> np.ndarray:
    """One Bernoulli(abar) draw per step, shared by every link."""
    return (rng.random(n_steps) < abar).astype(float)


def plant_trajectory(x_init: list, n_steps: int) -> np.ndarray:
    """x_0..x_n of (1): x_{k+1} = f(x_k) + B_k v_k."""
    x = np.zeros((n_steps + 1, NX))
    x[0] = x_init
    for k in range(n_steps):
        x[k + 1] = f(x[k]) + B_mat(k) @ v_noise(k)
    return x


def measurements(x: np.ndarray) -> np.ndarray:
    """y_{i,k} = g_i(x_k) + E_{i,k} mu_k of (1), k = 0..n, every node."""
    return np.array([[g(i, x[k]) + E_mat(i, k) @ mu_noise(k) for i in range(N)]
                     for k in range(x.shape[0])])


def compensation(H: dict, What: dict, ph: np.ndarray, abar: float) -> float:
    """max_i ||abar sum_j theta_ij H_ij W^_ij phi(z_i)||: what the NN compensator subtracts in (8)."""
    return max(np.linalg.norm(sum(abar * THETA[i, j] * H[(i, j)] @ What[(i, j)] @ ph[i]
                                  for j in NBRS[i])) for i in range(N))


def conditional_expectation(F, G, H, xh_k, z, What, abar, compensate, x_next, P_next):
    """E_{alpha_k}{x~_(i,k+1)^T P_(k+1)^-1 x~_(i,k+1) | past} per node, exactly (C8a): the
    update on both branches alpha_k = 0 and 1, weighted 1 - abar and abar."""
    out = np.zeros(N)
    for a, weight in ((0.0, 1.0 - abar), (1.0, abar)):
        z_recv = np.array([z[j] + a * chi(z[j]) for j in range(N)])
        e = x_next - M.update_all(F, G, H, xh_k, z, z_recv, THETA,
                                  W_hat=What if compensate else None, phi_own=phi(z),
                                  alpha_bar=abar)
        out += weight * np.einsum("na,na->n", e, np.linalg.solve(P_next, e.T).T)
    return out


def remainders(x_k: np.ndarray, xh_k: np.ndarray) -> tuple:
    """x~_(i,k) and the Taylor remainders of (12) for f and (13) for g_i at every node."""
    xt = x_k - xh_k
    rem_f = [f(x_k) - f(xh_k[i]) - jac_f(xh_k[i]) @ xt[i] for i in range(N)]
    rem_g = [g(i, x_k) - g(i, xh_k[i]) - jac_g(i, xh_k[i]) @ xt[i] for i in range(N)]
    return xt, rem_f, rem_g


def dynamics_residual(rows: list, k: int, S: np.ndarray, xt, rem_f, rem_g, z, ph, What,
                      Mbar, Ls, As, alpha_k: float, abar: float, err_next) -> list:
    """X1: max |x~_(i,k+1) - (Xi_i + (alpha_k - abar) Xi~_i) zeta_k| per node, (54), with zeta_k
    built from the actual remainders, delta = chi - W* phi and r = Mbar^-1 rho(W* - W^)."""
    dl = [chi(z[j]) - W_star @ ph[j] for j in range(N)]
    zeta = np.concatenate(
        [[1.0]] + [np.linalg.solve(S, xt[i]) for i in range(N)]
        + [np.linalg.solve(Ls, rem_f[i]) for i in range(N)]
        + [np.linalg.solve(As, rem_g[i]) for i in range(N)]
        + [v_noise(k), mu_noise(k)] + dl
        + [np.linalg.solve(Mbar[lk], (W_star - What[lk]).flatten()) for lk in LINKS])
    res = []
    for i in range(N):
        Xi, Xit = rows[i]
        pred = (Xi + (alpha_k - abar) * Xit) @ zeta
        res.append(float(np.max(np.abs(pred - err_next[i]))))
    return res


def sampled_bound(rows: list, rng: np.random.Generator, S: np.ndarray, P_next: np.ndarray,
                  abar: float) -> list:
    """X4: max over 256 admissible zeta of zeta^T (Xi^T P^-1 Xi + sigma^2 Xi~^T P^-1 Xi~) zeta
    per node, the left side of (29) implied by (30)."""
    Z = sample_admissible(rng, 256, S)
    P_inv = np.linalg.inv(P_next)
    out = []
    for i in range(N):
        Y, Yt = Z @ rows[i][0].T, Z @ rows[i][1].T
        qv = (np.sum((Y @ P_inv) * Y, axis=1)
              + abar * (1.0 - abar) * np.sum((Yt @ P_inv) * Yt, axis=1))
        out.append(float(qv.max()))
    return out


def weight_stats(run_: M.Algorithm1Run) -> dict:
    """||W^_ij,k||_F, Theorem 1's tr[W~^T Q^-1 W~] with W = W* (C4) and tr Q_ij,k, per step and link."""
    W, Q = run_.W_hat, run_.Q
    return {"Wn": np.array([[np.linalg.norm(Wk[lk]) for lk in LINKS] for Wk in W]),
            "Wq": np.array([[np.trace((W_star - Wk[lk]).T @ np.linalg.solve(Qk[lk], W_star - Wk[lk]))
                             for lk in LINKS] for Wk, Qk in zip(W, Q, strict=True)]),
            "trQ": np.array([[np.trace(Qk[lk]) for lk in LINKS] for Qk in Q])}


def step_checks(run_: M.Algorithm1Run, x: np.ndarray, alpha: np.ndarray, nn: bool, abar: float,
                scale: tuple, check_dynamics: bool) -> dict:
    """What the claims measure at every step of a run: the largest gain and the compensation
    (X3), the remainder ratios (X2), the exact conditional expectation of (29) (C8a) and, with
    `check_dynamics`, the residual of (54) (X1), the sampled bound (X4) and ||delta|| (C2)."""
    n_steps = run_.z.shape[0]
    Ls, As = scale[0] * np.eye(NX), scale[1] * np.eye(NY, NX)
    out = {"Hn": np.zeros(n_steps), "comp": np.zeros(n_steps),
           "cond": np.full((n_steps, N), np.nan)}
    rec = {key: [] for key in ("dyn_res", "ratio_f", "ratio_g", "delta_n", "sampled_q")}
    sample_rng = montecarlo.spawn_rngs(seed, 64)[63]  # X4 only; independent of the alpha_k draws
    for k in range(n_steps):
        F, G, H, What = run_.F[k], run_.G[k], run_.H[k], run_.W_hat[k]
        z, ph, xh_k, P_next = run_.z[k], run_.phi[k], run_.xh[k], run_.P[k + 1]
        out["Hn"][k] = max(np.linalg.norm(H[lk], 2) for lk in LINKS)
        out["comp"][k] = compensation(H, What, ph, abar) if nn else 0.0
        xt, rem_f, rem_g = remainders(x[k], xh_k)
        for rem, key in ((rem_f, "ratio_f"), (rem_g, "ratio_g")):
            rec[key].extend(np.linalg.norm(rem[i]) / max(np.linalg.norm(xt[i]), 1e-300)
                            for i in range(N))
        if run_.solved[k]:
            out["cond"][k] = conditional_expectation(F, G, H, xh_k, z, What, abar, nn, x[k + 1],
                                                     P_next)
        if check_dynamics and nn:
            rec["delta_n"].extend(np.linalg.norm(chi(z[j]) - W_star @ ph[j]) for j in range(N))
            if run_.solved[k]:  # X1 and X4 on the gains actually used
                rec["dyn_res"].extend(dynamics_residual(
                    run_.rows[k], k, run_.S[k], xt, rem_f, rem_g, z, ph, What, run_.Mbar[k], Ls,
                    As, alpha[k], abar, x[k + 1] - run_.xh[k + 1]))
                rec["sampled_q"].extend(sampled_bound(run_.rows[k], sample_rng, run_.S[k],
                                                      P_next, abar))
    return out | {key: np.array(val) for key, val in rec.items()}


def simulate(*, alpha: np.ndarray, estimator: str, abar: float | None = None,
             scale: tuple | None = None, design: str = "op2", B_fixed: np.ndarray | None = None,
             check_dynamics: bool = False, shared: bool | None = None,
             fallback: str | None = None) -> dict:
    """Run one estimator (Algorithm 1) over the horizon under the falsified innovations (5).

    Parameters
    ----------
    alpha : the realisation alpha_0..alpha_(n-1) (one draw per step, shared by every link).
    estimator : "nn" for (8) with OP2/OP3 (30), OP1 (31) and the tuning law (17); "conv" for (3)
        with the attack-unaware design.
    abar, scale, shared : ALPHA_BAR, (L_scale, aleph_scale) and shared_multipliers by default.
    design : "op2" (32) or "op3" (33, corrected, with the fixed ellipsoid B_fixed).
    check_dynamics : evaluate X1 (54) and X4 along the run (NN design only).
    fallback : override the fallback solver ("none" disables it).

    Returns
    -------
    dict of trajectories (x, xh, err, P, Bell), the normalised errors qf = x~^T B^-1 x~ and
    qP = x~^T P^-1 x~, the per-step checks of `step_checks`, gains and weights (X3), the
    solver reports and failures (C5), and the record of `M.run_algorithm1` ("run").
    """
    abar = ALPHA_BAR if abar is None else abar
    scale = (L_scale, aleph_scale) if scale is None else scale
    nn = estimator == "nn"
    fb = FALLBACK if fallback is None else (None if fallback == "none" else fallback)
    x = plant_trajectory(x0, alpha.size)
    run_ = M.run_algorithm1(
        MODEL, measurements(x), lambda k, z: np.array([z[j] + alpha[k] * chi(z[j]) for j in range(N)]),
        theta=THETA, dims=DIMS, xhat0=xhat0, P0=P0, W0=W0, Q0=Q0, alpha_bar=abar, e1=e1, e3=e3,
        L=scale[0] * np.eye(NX), aleph=scale[1] * np.eye(NY, NX), V_inv=V_inv, U_inv=U_inv, nn=nn,
        p=p, design=design, B_fixed=B_fixed,
        shared=shared_multipliers if shared is None else shared, r_bound=r_bound,
        varpi_form=varpi_form, eps=eps_lmi, lam2_box=lam2_max, solver=solver, fallback=fb,
        tol=cert_tol, keep_rows=check_dynamics and nn, cache=PROBLEMS)
    for msg in run_.failures:
        print("NOT CERTIFIED:", msg.splitlines()[0])
    err = x[:, None, :] - run_.xh
    return {"x": x, "xh": run_.xh, "err": err, "P": run_.P, "Bell": run_.Bell, "rho": run_.rho,
            "lam": run_.lam, "reports": run_.reports, "failures": run_.failures,
            "failure_outcomes": run_.failure_outcomes, "run": run_,
            **weight_stats(run_), **step_checks(run_, x, alpha, nn, abar, scale, check_dynamics),
            "qf": montecarlo.nees(err, run_.Bell[:, None, :, :]),  # x~^T B_k^-1 x~ per (k, node)
            "qP": montecarlo.nees(err, run_.P[:, None, :, :])}  # x~^T P_k^-1 x~


def rmse(res: dict) -> np.ndarray:
    """Per-node RMSE of ||x~_{i,k}|| over k = 1..T."""
    return np.sqrt(np.mean(np.sum(res["err"][1:] ** 2, axis=2), axis=0))


# %% [markdown]
# ## The missing Taylor scales $L_i$, $\aleph_i$: a declared range
#
# The paper gives no values for $L_i$, $\aleph_i$ in (12)–(13), yet Theorems 2–3 rest on them: the
# remainders must satisfy $\|f(x)-f(\hat x_i)-\Phi_i\tilde x_i\|\le\|L_i\tilde x_i\|$, i.e.
# $\|\Delta_{1i}\|\le1$, and likewise for $g_i$ with $\aleph_i$. We take $L_i=\aleph_i=sI_2$ and
# declare a range for $s$ from the premise and the certificate, not from the comparison:
#
# * **Lower end: the premise's limit.** At $k=0$ the state and the estimates are given, so the
#   ratio $\|\text{remainder}\|/\|\tilde x_{i,0}\|$ does not depend on the design, and every $s$
#   below its maximum $r_0$ over the nodes and over $f$, $g_i$ voids the premise at the first step.
#   On the as-read example $r_0=0.1154$ (computed below), so the range starts at $0.116$.
# * **Upper end: the certificate.** A larger $s$ inflates the remainder terms of (30); the
#   ellipsoid then grows geometrically along the run and the solver stops certifying the steps. A
#   scan of the as-read example (seed 0, $\bar\alpha=0.67$, both designs, no SCS fallback)
#   certified every step at $s=0.30$, $0.32$ and $0.34$ ($\mathrm{tr}\,\mathfrak B_{40}\approx830$ at
#   $0.34$, against $\approx7$ at $0.15$) and failed at 11 + 10 steps at $0.36$, 22 + 19 at $0.40$
#   and 30 + 28 at $0.50$, the ceiling of the earlier rule. The range ends at $0.34$; in paper mode
#   the extras re-check $0.34$ and $0.36$ on the NN design. C5 records any point of the design
#   where a step is not certified. That scan used the earlier certificate, largest eigenvalue
#   $\le+10^{-8}$. The LMIs are now certified strict (largest eigenvalue $\le-10^{-8}$, see
#   "Solves"), and under it CLARABEL's solutions at $0.34$ use up the margin $10^{-6}$ to within
#   $10^{-8}$ at some step at every point: the sweep finds uncertified steps at all 10 points at
#   $0.34$ and at 3 of the 10 at $0.284$ (the sweep before issue #30's round 4); no solver
#   reports any of them infeasible, so C5 records them as not checked (our certificate's limit,
#   section "Claims"). The range was not changed after seeing this; on the as-read example the
#   last level certified at every step is now $0.284$.
# * **Levels.** The sweep steps the range geometrically ($s$ is a scale) in 7 levels, 0.116,
#   0.139, 0.166, 0.199, 0.238, 0.284 and 0.340: the fewest whose neighbouring levels bracket the
#   reversal of C3 between 0.14 and 0.15 reported in issue 15. The levels were thus placed knowing
#   where C3 turns (the ends were not: they come from the premise and the certificate), so the
#   number of points where C3 holds is set by this choice (5 of the 7 levels lie above the turn)
#   and is reported per level, not as a sampled fraction. With 2 seeds and 5 OCR readings
#   (one alternative at a time) that is 70 points. Each point is a papermill run of the two
#   designs plus the 15 further NN runs of the Monte Carlo of C2 (issue #30's round 4; the sweep
#   keeps 16 runs per point, `mc_runs = 16` in the TOML's `[sweep] base`, while paper mode runs
#   94, section "Monte Carlo"), about 1.5 min of CPU, so the sweep takes about 50 min on 2 idle
#   cores (28 min were measured on a quieter machine); denser designs cost in
#   proportion (13 levels × 4 seeds, or the 16 combinations of the readings, would take 3–4 times as long).
#   Sweep points run without the SCS fallback (`fallback_solver = "none"` in the TOML's `[sweep]
#   base`), a change made after the first sweep, for cost: there SCS was tried 68 times and
#   certified no step (it stops at its iteration cap short of the $10^{-8}$ certificate), while
#   its attempts took more CPU than the rest of the sweep. An uncertified step is counted the same
#   way with or without the attempt, so no claim changes.
# * **Default.** `L_scale` = `aleph_scale` = $\sqrt{0.116\cdot0.34}=0.198595$, the geometric
#   centre of the range (a scale multiplies, so its centre is geometric), which is the middle
#   level. Until issue #30's round 4 the default was the lower end, 0.116, "the least
#   conservative scale the premise admits"; that is also the scale most favourable to C3 (it holds
#   only at the two smallest levels), so a default there put the headline comparison's best case
#   in the paper's example. Neither end is a neutral choice: the upper end is the least certified.
#   The default is one point of the range; the claims' verdicts are taken over the declared space,
#   and the example's outcomes (which the rule also reads) are those at the centre.
#
# **How the scale was chosen before, and when.** The first version of this notebook (commit
# 6acd55d) used $s=0.1$, the brief's "usual size", under which the premise fails at $k=0$; it
# already reported that with $s=0.15$ the comparison C3 reverses at nodes 1 and 3, and the brief
# (§4.3) said the same ("0.15 covers it but changes the comparison"). About an hour later, commit
# 04bab43 introduced "the smallest multiple of 0.05 for which (12)–(13) hold along both runs",
# called it "a rule fixed in advance", and with it reported that C3 does not hold. The rule was
# written after the reversal at 0.15 was known, so it was not fixed in advance of the outcome, and
# its 0.05 grid decided the headline: C3 holds at every node for every scale from the premise's
# limit up to 0.14 on the as-read example with seed 0 (issue 15; with seed 1 it already fails at
# 0.139). The range above and its levels were committed in `notebooks/ma2021.toml` before the sweep
# was run (git history is the record) and have not been changed since, but they were not chosen
# blind: the brief and issue 15 had already reported the turn between 0.14 and 0.15, and the
# levels were placed to bracket it. C3's verdict is the map over them.


# %%
def remainder_ratios_k0(x_init: list, xh_init: list) -> tuple[float, float]:
    """max over nodes of ||remainder|| / ||x~|| at k = 0 for f (12) and for g_i (13); independent
    of the design because x_0 and the x^_(i,0) are given."""
    x_i, rf, rg = np.asarray(x_init, float), [], []
    for i, xh_i in enumerate(np.asarray(xh_init, float)):
        xt = x_i - xh_i
        rf.append(np.linalg.norm(f(x_i) - f(xh_i) - jac_f(xh_i) @ xt) / np.linalg.norm(xt))
        rg.append(np.linalg.norm(g(i, x_i) - g(i, xh_i) - jac_g(i, xh_i) @ xt) / np.linalg.norm(xt))
    return float(max(rf)), float(max(rg))


r0_f, r0_g = remainder_ratios_k0(x0, xhat0)
scale_axis = SPACE.parameters["L_scale"].space
print(f"premise's lower limit at this run's reading and x0: r0 = {max(r0_f, r0_g):.5f} "
      f"(f: {r0_f:.5f}, g: {r0_g:.5f})")
print(f"declared range of L_scale (aleph_scale tied): [{scale_axis.low:g}, {scale_axis.high:g}], "
      f"levels {[round(v, 4) for v in scale_axis.grid_values()]}")
premise_k0 = L_scale >= r0_f and aleph_scale >= r0_g
print(f"this run: L_i = {L_scale:g} I, aleph_i = {aleph_scale:g} I -> (12)-(13) at k = 0 "
      + ("hold" if premise_k0 else "FAIL (Theorems 2-3 do not apply: C2 fails its premise)"))

# %% [markdown]
# ## The example (Section IV): both estimators under the same falsified innovations
#
# One realisation of $\alpha_k$ (`seed`), shared by both estimators, as in the paper's Figs. 1–8.

# %%
alpha_main = alpha_sequence(montecarlo.spawn_rngs(seed, 1)[0], T_run, ALPHA_BAR)
print(f"alpha_k = 1 at {int(alpha_main.sum())} of {T_run} steps")
nn_run = simulate(alpha=alpha_main, estimator="nn", check_dynamics=True)
conv_run = simulate(alpha=alpha_main, estimator="conv")
# X5 (an extra: a software check, not a claim about the unknowns): the DPP problem re-solved
# with parameters equals a freshly built one at the last NN step
last_certified = not any(f"step {T_run - 1}," in msg for msg in nn_run["failures"])
dpp_gap = None
if extras and last_certified:
    cached, _ = M.step_problems(THETA, DIMS, nn=True, alpha_bar=ALPHA_BAR, e1=e1, e3=e3,
                                eps=eps_lmi, shared=shared_multipliers, r_bound=r_bound,
                                design="op2", lam2_box=lam2_max, cache=PROBLEMS)
    fresh = M.build_op2(THETA, DIMS, nn=True, alpha_bar=ALPHA_BAR, e3=e3, eps=eps_lmi,
                        shared=shared_multipliers, r_bound=r_bound)
    values = {q.name(): q.value for q in cached.problem.parameters()}
    for q in fresh.problem.parameters():
        q.value = values[q.name()]
    M.solve(fresh, T_run - 1, "fresh build (X5)", eps=eps_lmi, tol=cert_tol, solver=solver,
            fallback=FALLBACK)
    dpp_gap = float(np.max(np.abs(np.asarray(fresh.vars["P"].value)
                                  - np.asarray(cached.vars["P"].value))))
    print(f"X5: |P(re-solved DPP) - P(fresh build)| = {dpp_gap:.2e}")
k_axis = np.arange(T_run + 1)
for name, r in (("NN (8)", nn_run), ("conventional (3)", conv_run)):
    print(f"{name:>17}: RMSE per node = {np.round(rmse(r), 4).tolist()}, "
          f"max x~'B^-1 x~ = {r['qf'].max():.4f}, tr B_T = {np.trace(r['Bell'][-1]):.3f}, "
          f"max ||H|| = {r['Hn'].max():.2e}, median ||H|| = {np.median(r['Hn']):.3f}, "
          f"uncertified steps = {len(r['failures'])}")
print("RMSE ratio NN / conventional per node:", np.round(rmse(nn_run) / rmse(conv_run), 4).tolist())
print(f"X4: max sampled E_alpha x~'P^-1 x~ over admissible zeta = {nn_run['sampled_q'].max():.4f}")
print(f"C8a: max exact E_alpha(k) x~'P^-1 x~ = {np.nanmax(nn_run['cond']):.4f} (NN design), "
      f"{np.nanmax(conv_run['cond']):.4f} (conventional design, not a bound under attack)")

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
# the three estimates $\hat x^{(l)}_{i,k}$. In the error figures the axes follow the errors, as the
# paper's do (its axes run from −0.8 to 1); the shaded band is the projection of the required
# ellipsoid onto component $l$, $|\tilde x^{(l)}|\le\sqrt{[\mathfrak B_k]_{ll}}$, for that estimator's own
# design. It is drawn, not fitted: where it is wider than the errors it fills the axes, and its
# smallest half-width is given in the legend. For the conventional design this "region" comes
# from an attack-unaware LMI and guarantees nothing under attack.

# %%
MARKERS = {0: ("x", "--"), 1: ("o", "-."), 2: ("^", ":")}


def state_figure(res: dict, comp: int, est_name: str, stem: str) -> None:
    """Figs. 1-2, 5-6: x^(l)_k and the estimates x^^(l)_(i,k) of every node."""
    if not plotting.figures_enabled():  # sweep points: nothing is drawn
        return
    fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH, 3.0))
    ax.plot(k_axis, res["x"][:, comp], "k-", lw=1.6, label=f"$x^{{({comp + 1})}}_k$")
    for i in range(N):
        mk, ls = MARKERS[i]
        ax.plot(k_axis, res["xh"][:, i, comp], ls=ls, marker=mk, ms=3.5, mfc="none", lw=0.9,
                label=f"$\\hat x^{{({comp + 1})}}_{{{i + 1},k}}$ (node {i + 1})")
    ax.set_xlabel("time step $k$")
    ax.set_ylabel(f"state $x^{{({comp + 1})}}$ and estimates [–]")
    ax.set_title(f"{est_name}: $x^{{({comp + 1})}}_k$ and its estimates")
    ax.legend(fontsize=6.5, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.25), frameon=False)
    ax.set_xlim(0, T_run)
    fig.set_layout_engine("constrained")
    plotting.save_figure(fig, FIG_DIR, stem, data={
        "k": k_axis, "x": res["x"][:, comp],
        **{f"xhat_node{i + 1}": res["xh"][:, i, comp] for i in range(N)}},
        tolerance={"xhat_node*": results.LMI_ITERATES})


def data_limits(values: np.ndarray, pad: float = 0.08) -> tuple[float, float]:
    """Axis limits that follow the data, with a relative margin."""
    lo, hi = float(np.min(values)), float(np.max(values))
    span = max(hi - lo, 1e-3 * max(abs(lo), abs(hi), 1.0))
    return lo - pad * span, hi + pad * span


def error_figure(res: dict, comp: int, est_name: str, stem: str,
                 band_label: str = r"required region $|\tilde x^{(l)}|\leq\sqrt{[\mathfrak{B}_k]_{ll}}$"
                 ) -> None:
    """Figs. 3-4, 7-8: x~^(l)_(i,k) per node on the errors' own scale, the region shaded."""
    if not plotting.figures_enabled():
        return
    band = np.sqrt(res["Bell"][:, comp, comp])
    fig, ax = plt.subplots(figsize=(plotting.COLUMN_WIDTH, 3.0))
    lo, hi = data_limits(res["err"][:, :, comp])
    ax.fill_between(k_axis, -band, band, color="tab:green", alpha=0.12, lw=0,
                    label=f"{band_label}\n(half-width $\\geq${band.min():.2f}: fills the axes)"
                    if band.min() > max(abs(lo), abs(hi)) else band_label)
    for i in range(N):
        mk, ls = MARKERS[i]
        ax.plot(k_axis, res["err"][:, i, comp], ls=ls, marker=mk, ms=3.5, mfc="none", lw=0.9,
                label=f"node {i + 1}")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("time step $k$")
    ax.set_ylabel(f"estimation error $\\tilde x^{{({comp + 1})}}_{{i,k}}$ [–]")
    ax.set_title(f"{est_name}: error $\\tilde x^{{({comp + 1})}}_{{i,k}}$")
    ax.set_ylim(lo, hi)
    ax.set_xlim(0, T_run)
    ax.legend(fontsize=6, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.25), frameon=False)
    fig.set_layout_engine("constrained")
    plotting.save_figure(fig, FIG_DIR, stem, data={
        "k": k_axis, "band": band, **{f"err_node{i + 1}": res["err"][:, i, comp] for i in range(N)}},
        tolerance={"band": results.LMI_ITERATES, "err_node*": results.LMI_ITERATES})


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
# ### Extra — the comparison of Figs. 5–8 with Figs. 1–4, overlaid
#
# The paper's point is the difference between the two estimators under the same falsified
# innovations, which side-by-side figures hide. Each panel overlays the error of one component at
# one node for both estimators; the title gives the two per-node RMSEs of C3 (over $k=1..T$, the
# Euclidean norm of $\tilde x$). Steps with $\alpha_k=1$ (injection) are marked on the time axis.

# %%
def overlay_figure() -> None:
    """Errors of both estimators overlaid, per node (columns) and component (rows)."""
    fig, axs = plt.subplots(2, N, figsize=(plotting.PAGE_WIDTH, 4.4), sharex=True, sharey="row")
    e_nn_, e_conv_ = rmse(nn_run), rmse(conv_run)
    for comp in range(2):
        lo, hi = data_limits(np.concatenate([nn_run["err"][:, :, comp],
                                             conv_run["err"][:, :, comp]]))
        for i in range(N):
            ax = axs[comp, i]
            for n_att, k in enumerate(np.flatnonzero(alpha_main == 1)):  # update k -> k+1
                ax.axvspan(k, k + 1, color="0.9", lw=0, label=None if n_att else
                           r"$\alpha_k=1$: the update $k\to k+1$ uses falsified innovations")
            ax.plot(k_axis, nn_run["err"][:, i, comp], "-", color="tab:blue", lw=1.1,
                    label="NN-based (8)")
            ax.plot(k_axis, conv_run["err"][:, i, comp], "--", color="tab:red", lw=1.1,
                    label="conventional (3)")
            ax.axhline(0.0, color="k", lw=0.4)
            ax.set_ylim(lo, hi)
            ax.set_xlim(0, T_run)
            if comp == 0:
                ax.set_title(f"node {i + 1}: RMSE {e_nn_[i]:.4f} (NN), {e_conv_[i]:.4f} (conv.)",
                             fontsize=7)
            else:
                ax.set_xlabel("time step $k$")
        axs[comp, 0].set_ylabel(f"$\\tilde x^{{({comp + 1})}}_{{i,k}}$ [–]")
    handles, labels = axs[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize=7, frameon=False)
    fig.set_layout_engine("constrained")
    plotting.save_figure(fig, FIG_DIR, "extra_nn_vs_conventional", data={
        "k": k_axis, "alpha": np.append(alpha_main, np.nan),
        **{f"err_nn_node{i + 1}_c{c + 1}": nn_run["err"][:, i, c]
           for i in range(N) for c in range(2)},
        **{f"err_conv_node{i + 1}_c{c + 1}": conv_run["err"][:, i, c]
           for i in range(N) for c in range(2)}},
        tolerance={"err_*": results.LMI_ITERATES})


if plotting.figures_enabled():
    overlay_figure()

# %% [markdown]
# ## Extra — diagnostics: what the designs actually do
#
# Six panels, not in the paper. (a) The normalised errors
# $\tilde x^\top\mathfrak B_k^{-1}\tilde x$ against the threshold 1 of (11). (b)
# $\mathrm{tr}\,\mathfrak B_k$ of both designs. (c) The largest neighbour gain $\max_{ij}\|H_{ij,k}\|$.
# (d) The NN weights $\|\hat W_{ij,k}\|_F$. (e) The Theorem 1 quantity
# $\mathrm{tr}[\tilde W^\top Q^{-1}\tilde W]$ with $W=W^\star$. (f) The probability $p_k=1-\rho_k$
# guaranteed by the corrected OP3 (Corollary 3: $\mathfrak B_{k+1}$ given, $p_k$ maximised) for
# the ellipsoids $\mathfrak B_{k+1}$ that this run's OP2 designed, run on the same data (an extra;
# claim X10), and, as a record, for the constant $\mathfrak B=$ `op3_scale`$\cdot I$ used before
# (its stated reason, "close to the OP2 result", was wrong: OP2's $\mathrm{tr}\,\mathfrak B_k$ grows
# far beyond $\mathrm{tr}\,2I=4$, panel b). A step with $\rho_k\ge1$ guarantees nothing: it is
# marked "void" on the axis, not drawn as a negative probability.

# %%
op3_run = op3_fixed = None
if extras:
    # Corollary 3 / OP3 with B_(k+1) taken from this run's OP2 (the NN run at p): the probability
    # p_k = 1 - rho_k that OP3 then guarantees for the ellipsoid OP2 designed
    op3_run = simulate(alpha=alpha_main, estimator="nn", design="op3", B_fixed=nn_run["Bell"])
    p_op3 = 1.0 - op3_run["rho"]
    void = op3_run["rho"] >= 1.0
    inside_op3 = op3_run["qf"][1:] <= 1.0  # (k = 1..T, node), against B_k of OP2
    # the earlier default, a constant B = op3_scale I, kept as a record
    op3_fixed = simulate(alpha=alpha_main, estimator="nn", design="op3",
                         B_fixed=op3_scale * np.eye(NX))
    p_fixed = 1.0 - op3_fixed["rho"]
    void_fixed = op3_fixed["rho"] >= 1.0
    for name_, p_, v_, r_ in (("B_(k+1) of OP2", p_op3, void, op3_run),
                              (f"B = {op3_scale:g} I", p_fixed, void_fixed, op3_fixed)):
        print(f"OP3 ({name_}): p_k from {np.nanmax(p_):.3f} down to {np.nanmin(p_):.3f}; steps "
              f"with rho_k >= 1 (bound void): {int(v_[1:].sum())} of {T_run}; fraction of "
              f"(i, k >= 1) inside B_k: {np.mean(r_['qf'][1:] <= 1.0):.3f}; uncertified steps: "
              f"{len(r_['failures'])}")


def log_limits(values: np.ndarray, include: float | None = None) -> tuple[float, float]:
    """Log-axis limits that follow the positive data (and `include`), without empty decades."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v) & (v > 0)]
    if include is not None:
        v = np.append(v, include)
    return float(v.min()) / 1.6, float(v.max()) * 1.6


BELOW = {"loc": "upper center", "bbox_to_anchor": (0.5, -0.3), "fontsize": 6, "frameon": False}
LINK_STYLES = ["-", "--", "-.", ":"]


def panel_forms(ax) -> None:
    """(a) x~^T B_k^-1 x~ of both designs per node, against the threshold 1 of (11)."""
    for i in range(N):
        mk = MARKERS[i][0]
        ax.semilogy(k_axis, nn_run["qf"][:, i], "-", marker=mk, ms=2.5, mfc="none",
                    color="tab:blue", lw=0.8, label=f"node {i + 1}, NN design")
        ax.semilogy(k_axis, conv_run["qf"][:, i], ":", marker=mk, ms=2.5, mfc="none",
                    color="tab:red", lw=0.8, label=f"node {i + 1}, conventional")
    ax.axhline(1.0, color="k", lw=1.0, label="threshold 1 of (11)")
    ax.set_ylim(*log_limits(np.concatenate([nn_run["qf"], conv_run["qf"]]), include=1.0))
    ax.set_title(r"(a) $\tilde x^\top\mathfrak{B}_k^{-1}\tilde x$")
    ax.legend(ncol=2, **BELOW)


def panel_designs(ax_b, ax_c) -> None:
    """(b) tr B_k and (c) max ||H_ij,k|| of both designs."""
    ax_b.plot(k_axis, np.trace(nn_run["Bell"], axis1=1, axis2=2), color="tab:blue",
              label="NN design (30)")
    ax_b.plot(k_axis, np.trace(conv_run["Bell"], axis1=1, axis2=2), "--", color="tab:red",
              label="conventional design")
    ax_b.set_title(r"(b) $\mathrm{tr}\,\mathfrak{B}_k$")
    ax_b.legend(ncol=1, **BELOW)
    ax_c.semilogy(k_axis[:-1], nn_run["Hn"], color="tab:blue", label="NN design (30)")
    ax_c.semilogy(k_axis[:-1], conv_run["Hn"], "--", color="tab:red", label="conventional design")
    ax_c.set_ylim(*log_limits(np.concatenate([nn_run["Hn"], conv_run["Hn"]])))
    ax_c.set_title(r"(c) $\max_{ij}\|H_{ij,k}\|_2$")
    ax_c.legend(ncol=1, **BELOW)


def panel_weights(ax_d, ax_e) -> None:
    """(d) ||W^_ij,k||_F and (e) Theorem 1's tr[W~^T Q^-1 W~] per link, NN design."""
    W_floor = 1e-16
    for a, (i, j) in enumerate(LINKS):
        ax_d.semilogy(k_axis, np.maximum(nn_run["Wn"][:, a], W_floor), ls=LINK_STYLES[a % 4],
                      lw=0.9 + 0.3 * a, label=f"link {i + 1}←{j + 1}")
    ax_d.set_ylim(*log_limits(np.maximum(nn_run["Wn"], W_floor)))
    ax_d.set_title(r"(d) $\|\hat W_{ij,k}\|_F$ (floor $10^{-16}$)")
    ax_d.legend(ncol=2, **BELOW)
    for a, (i, j) in enumerate(LINKS):
        ax_e.semilogy(k_axis, nn_run["Wq"][:, a], ls=LINK_STYLES[a % 4], lw=0.9 + 0.3 * a,
                      label=f"link {i + 1}←{j + 1}")
    ax_e.axhline(1.0, color="k", lw=1.0, label="bound (19)")
    ax_e.set_ylim(*log_limits(nn_run["Wq"], include=1.0))
    ax_e.set_title(r"(e) $\mathrm{tr}[\tilde W^\top Q^{-1}\tilde W]$, $W=W^\star$")
    ax_e.legend(ncol=2, **BELOW)


def panel_op3(ax) -> None:
    """(f) the probability p_k = 1 - rho_k guaranteed by the corrected OP3 (Corollary 3), with
    B_(k+1) from this run's OP2 and with the earlier constant B; void steps marked."""
    if op3_run is not None:
        for p_, v_, style, colour, lab in (
                (p_op3, void, "o-", "tab:blue", r"OP3, $\mathfrak{B}_{k+1}$ of OP2"),
                (p_fixed, void_fixed, "s:", "tab:gray",
                 f"OP3, $\\mathfrak{{B}}={op3_scale:g}I$ (earlier default)")):
            ok = ~v_[1:]
            ax.plot(k_axis[1:][ok], p_[1:][ok], style, ms=2.5, color=colour, label=lab)
            if (~ok).any():
                ax.plot(k_axis[1:][~ok], np.zeros(int((~ok).sum())), "x", color=colour, ms=4,
                        label=r"void: $\rho_k\geq1$" + (" (earlier default)" if colour ==
                                                           "tab:gray" else ""))
        ax.axhline(p, color="k", ls="--", lw=0.8, label=f"p = {p} of OP2")
        ax.set_ylim(-0.04, 1.0)
        ax.legend(ncol=1, **BELOW)
    else:
        ax.text(0.5, 0.5, "OP3 not run (extras off)", ha="center", va="center",
                transform=ax.transAxes)
    ax.set_title(r"(f) OP3: guaranteed $p_k = 1-\rho_k$")


def diagnostics_data() -> dict:
    """The plotted series of the diagnostics figure."""
    return {
        "k": k_axis,
        **{f"qf_nn_node{i + 1}": nn_run["qf"][:, i] for i in range(N)},
        **{f"qf_conv_node{i + 1}": conv_run["qf"][:, i] for i in range(N)},
        "trB_nn": np.trace(nn_run["Bell"], axis1=1, axis2=2),
        "trB_conv": np.trace(conv_run["Bell"], axis1=1, axis2=2),
        "maxH_nn": np.append(nn_run["Hn"], np.nan), "maxH_conv": np.append(conv_run["Hn"], np.nan),
        **{f"What_F_link{i + 1}{j + 1}": nn_run["Wn"][:, a] for a, (i, j) in enumerate(LINKS)},
        **{f"thm1_link{i + 1}{j + 1}": nn_run["Wq"][:, a] for a, (i, j) in enumerate(LINKS)},
        "p_op3": p_op3 if op3_run is not None else np.full(T_run + 1, np.nan),
        "p_op3_fixed": p_fixed if op3_run is not None else np.full(T_run + 1, np.nan),
    }


DIAGNOSTICS_TOLERANCE = {
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
        reason="NN weights collapsed to rounding level after k = 0 (<= 3e-9): their values are "
        "noise, 38 % apart under other BLAS kernels"),
    **dict.fromkeys(["trB_*", "thm1_*", "p_op3", "p_op3_fixed"], results.LMI_ITERATES),
}


def diagnostics_figure() -> None:
    """Panels (a)-(f) of the diagnostics figure; blue: NN design (30), red: conventional design."""
    fig, axs = plt.subplots(2, 3, figsize=(plotting.PAGE_WIDTH, 6.0))
    panel_forms(axs[0, 0])
    panel_designs(axs[0, 1], axs[0, 2])
    panel_weights(axs[1, 0], axs[1, 1])
    panel_op3(axs[1, 2])
    for ax in axs.flat:
        ax.set_xlabel("time step $k$")
        ax.set_xlim(0, T_run)
    axs[0, 0].set_ylabel("value [–]")
    axs[1, 0].set_ylabel("value [–]")
    fig.set_layout_engine("constrained")
    plotting.save_figure(fig, FIG_DIR, "extra_diagnostics", data=diagnostics_data(),
                         tolerance=DIAGNOSTICS_TOLERANCE)


if plotting.figures_enabled():
    diagnostics_figure()

# %% [markdown]
# ## Extra — the certificate at the upper end of the declared scale range
#
# In paper mode, the NN design is run on this point's data at the range's upper end and 0.02
# above it, without the SCS fallback, and the steps the certificate rejects are counted (see "The
# missing Taylor scales"). This re-checks the reason for the upper end at the as-read point; the
# sweep records C5 at every point of the range.

# %%
if extras and mode == "paper":
    for s_chk in (scale_axis.high, round(scale_axis.high + 0.02, 6)):
        chk = simulate(alpha=alpha_main, estimator="nn", scale=(s_chk, s_chk), fallback="none")
        print(f"s = {s_chk:g}: {len(chk['failures'])} of {2 * T_run} NN solves not certified, "
              f"tr B_T = {np.trace(chk['Bell'][-1]):.3g}")

# %% [markdown]
# ## Monte Carlo over independent $\alpha_k$ realisations (C2, C8b)
#
# $\alpha_k$ is the only random quantity (E8), so the probability of Theorem 3 and the expectation
# of Theorem 2 are over its realisations. Within one run the (node, step) pairs are **not**
# independent samples (they share the realisation and the recursion); across runs each pair is
# one Bernoulli trial per run. The `mc_runs` runs (94 in paper mode; the first is the main run;
# each run has its own data-dependent $P_k$ and $\mathfrak B_k$) are therefore summarised **per
# pair**:
#
# * **C2 (Theorem 3, (11)).** Theorem 3 states $P\{\tilde x_{i,k}^\top\mathfrak B_k^{-1}
#   \tilde x_{i,k}\le1\}\ge p$ **at every node $i$ and step $k$**. At each pair $(i,k)$,
#   $k=1..T$, the fraction of runs inside $\mathfrak B_k$ gets a Wilson interval at the Bonferroni
#   level $1-0.05/m$ over the $m=NT$ pairs tested (the multiplicity correction: all $m$ intervals
#   hold together with probability $\ge0.95$). **C2 holds** if every pair's lower end is $\ge p$;
#   **fails** if some pair's upper end is $<p$; else it is **not checked** (too few runs to
#   decide). The rule is on intervals, so it means the same at any run count; what the run count
#   changes is only whether it can decide. A pair inside in every run reaches $p$ from 50 runs on
#   (lower end 0.8006; 16 of 16 give 0.5623), so the 16 runs of the sweep can only give "fails"
#   or "not checked", and the 3 runs of fast mode likewise. The paper-mode run count, 94, was fixed
#   in `notebooks/ma2021.toml` by a power computation written before any outcome at it was seen
#   (recomputed below). $k=0$ is left out and is no evidence: $\mathfrak B_0=P_0/(1-p)$, so
#   Assumption 3 (the premise) alone puts its forms below $1-p$.
# * The previous statistic, the average over the pairs of one run, $f_r$, with the Wilson score
#   interval of $E f_r$ over the runs, is weaker than (11) (an average can reach $p$ while some
#   pair stays below it); it is kept in C2's record (`average_record`) and decides nothing.
# * **C8b (Theorem 2, (29)).** Per pair, the Student-t interval of the mean of
#   $\tilde x^\top P_k^{-1}\tilde x$ over the runs at the Bonferroni level $1-0.05/m$: holds if every
#   upper end is $\le1$, fails if some lower end is $>1$, else not checked. Theorem 2 is stated
#   "under the condition of Theorem 1", so C8b carries C2's premise.
#
# **This Monte Carlo hardly exercises the probability** (issue #30, item 2). The NN design barely
# uses its neighbours (X3), and the neighbours' innovations are the only place where $\alpha_k$
# enters, so the realisations give almost the same errors and ellipsoids, and every quadratic
# form lies far below 1 (the spread over the runs and the largest form are printed below and
# recorded in C2's `measured`). C2 therefore tests whether a very conservative bound holds at
# every pair, not whether the probability $p$ is attained: a "holds" here says that the
# guarantee is met, with a large margin, not that it is tight. The runs are independent, so the
# intervals are valid; the runs barely differ because the design ignores $\alpha_k$.

# %%
def score_interval(mean: float, n: int, level: float) -> tuple[float, float]:
    """Wilson score interval of the mean of n independent statistics in [0, 1] (their variance is
    at most mean (1 - mean), the binomial variance the score interval assumes); the old average
    statistic of C2, kept as a record."""
    zq = stats.norm.ppf(0.5 + level / 2.0)
    centre = (mean + zq**2 / (2 * n)) / (1 + zq**2 / n)
    half = zq * np.sqrt(mean * (1 - mean) / n + zq**2 / (4 * n * n)) / (1 + zq**2 / n)
    return float(max(centre - half, 0.0)), float(min(centre + half, 1.0))


def pair_intervals(inside: np.ndarray, level: float) -> tuple[np.ndarray, np.ndarray]:
    """Per pair (k, node): Wilson interval of the fraction of runs inside, inside[run, k, node]."""
    n = inside.shape[0]
    iv = np.array([[montecarlo.wilson_interval(int(c), n, level=level) for c in row]
                   for row in inside.sum(axis=0)])
    return iv[..., 0], iv[..., 1]


def decisive_misses(n: int, level: float) -> int:
    """The most misses out of n runs at a pair that still give a Wilson lower end >= p (-1: none)."""
    j = -1
    while j + 1 <= n and montecarlo.wilson_interval(n - j - 1, n, level=level)[0] >= p:
        j += 1
    return j


def power_bound(n: int, m: int, rate: float, level: float) -> float:
    """Union bound on P{every one of m pairs reaches p} when each pair's true rate is `rate`."""
    j = decisive_misses(n, level)
    return 0.0 if j < 0 else max(0.0, 1.0 - m * float(stats.binom.sf(j, n, 1.0 - rate)))


n_pairs = T_run * N  # pairs (i, k), k = 1..T, tested per run
bonf_level = 1.0 - 0.05 / n_pairs
POWER_RATE, POWER_TARGET = 0.99, 0.8  # the power computation of ma2021.toml (ours)
n_power = next(n for n in range(2, 1000) if power_bound(n, n_pairs, POWER_RATE, bonf_level)
               >= POWER_TARGET)
print(f"power rule (ma2021.toml): m = {n_pairs} pairs, level {bonf_level:.6f}; fewest runs with "
      f"power >= {POWER_TARGET} at a true rate {POWER_RATE} per pair: {n_power} (misses allowed "
      f"{decisive_misses(n_power, bonf_level)}); this run: {n_mc} runs, power bound "
      f"{power_bound(n_mc, n_pairs, POWER_RATE, bonf_level):.3f}; a pair inside in every run "
      f"has lower end {montecarlo.wilson_interval(n_mc, n_mc, level=bonf_level)[0]:.4f}")

mc_alphas = [alpha_sequence(r, T_run, ALPHA_BAR) for r in montecarlo.spawn_rngs(seed, n_mc)]
mc_runs_list = [nn_run] + [simulate(alpha=a, estimator="nn") for a in mc_alphas[1:]]
assert np.array_equal(mc_alphas[0], alpha_main)  # the main run is run 0
qf_mc = np.stack([r["qf"][1:] for r in mc_runs_list])  # (runs, k = 1..T, node), C2
inside_mc = qf_mc <= 1.0
pair_lo, pair_hi = pair_intervals(inside_mc, bonf_level)  # (k, node), C2's rule
pair_rate = inside_mc.mean(axis=0)
f_runs = inside_mc.reshape(n_mc, -1).mean(axis=1)  # the old average statistic (record only)
c2_avg_lo, c2_avg_hi = score_interval(float(f_runs.mean()), n_mc, 0.95)
qP_mc = np.stack([r["qP"][1:] for r in mc_runs_list])  # (runs, k = 1..T, node), C8b
qP_iv = np.array([[montecarlo.mean_interval(qP_mc[:, k, i], level=bonf_level) for i in range(N)]
                  for k in range(T_run)])  # (k, node, 2)
qf_spread = float(np.max(qf_mc.max(axis=0) - qf_mc.min(axis=0)))
print(f"C2: {n_mc} runs; pairs with lower end >= p: {int((pair_lo >= p).sum())} of {n_pairs}, "
      f"with upper end < p: {int((pair_hi < p).sum())}; worst pair's rate {pair_rate.min():.4f}, "
      f"its interval [{pair_lo.min():.4f}, {pair_hi.min():.4f}]; largest form over k >= 1 "
      f"{qf_mc.max():.4f}, spread over the runs (max - min, worst pair) {qf_spread:.1e}")
print(f"C8b: largest mean of x~'P^-1 x~ {qP_mc.mean(axis=0).max():.4f}, largest Bonferroni upper "
      f"end {qP_iv[..., 1].max():.4f}; spread over the runs (max - min, worst pair) "
      f"{np.max(qP_mc.max(axis=0) - qP_mc.min(axis=0)):.1e}; uncertified solves over the runs: "
      f"{sum(len(r['failures']) for r in mc_runs_list)}")

# %% [markdown]
# ## C3 over the $\alpha_k$ realisations, with an attack-free control
#
# C3 compares the two designs "in the existence of falsified innovations". Two things are needed
# to read that comparison (a hostile re-read of the committed version, items 1 and 5):
#
# * **An attack-free control.** Both designs are also run with $\alpha_k\equiv0$ (no falsified
#   innovation reaches any node), on the same plant and measurements. C3's **precondition** (ours)
#   is that the attack raises the conventional design's RMSE by more than `c3_margin` at some
#   node: otherwise the falsified innovations do not make the conventional estimator worse, and
#   its comparison with the NN estimator says nothing about them (fails-premise). The margin is
#   C3's own (a change within solver noise is not an effect); no new level was introduced.
# * **Independent realisations.** One realisation of $\alpha_k$ can flip the comparison (in the
#   earlier sweep, at $s=0.139$, the worst node's ratio was 0.9839 on seed 0 and 1.0091 on seed 1).
#   C3 is therefore evaluated on the same `mc_runs` realisations as C2 (run 0 is the main run),
#   each with both designs, by a rule on intervals: per node, the Student-t interval (Bonferroni
#   level $1-0.05/N$ over the nodes) of the mean of $\mathrm{RMSE}_{NN}-(1-c)\,\mathrm{RMSE}_{conv}$
#   over the runs, $c$ = `c3_margin`; **holds** if every node's upper end is below 0, **fails** if
#   some node's lower end is above 0, else **not checked** (too few runs to decide). The
#   precondition is judged the same way on the relative rise
#   $\mathrm{RMSE}^{attack}_{conv}/\mathrm{RMSE}^{\alpha\equiv0}_{conv}-1$: it holds if some node's
#   lower end exceeds $c$, fails if every node's upper end is at most $c$, else C3 is not checked.
#   Intervals keep their meaning at any run count; the run count only changes whether they decide.

# %%
conv_mc = [conv_run] + [simulate(alpha=a, estimator="conv") for a in mc_alphas[1:]]
alpha_free = np.zeros(T_run)  # no falsified innovation at any step
nn_free = simulate(alpha=alpha_free, estimator="nn")
conv_free = simulate(alpha=alpha_free, estimator="conv")
rmse_nn_mc = np.stack([rmse(r) for r in mc_runs_list])  # (runs, node)
rmse_conv_mc = np.stack([rmse(r) for r in conv_mc])
c3_level = 1.0 - 0.05 / N  # Bonferroni over the nodes
c3_diff_iv = np.array([montecarlo.mean_interval(rmse_nn_mc[:, i] - (1.0 - c3_margin)
                                                * rmse_conv_mc[:, i], level=c3_level)
                       for i in range(N)])  # (node, 2); < 0: the NN is better by the margin
c3_rise_mc = rmse_conv_mc / rmse(conv_free) - 1.0  # the attack's effect on the conventional design
c3_rise_iv = np.array([montecarlo.mean_interval(c3_rise_mc[:, i], level=c3_level)
                       for i in range(N)])
ratio_mean_c3 = rmse_nn_mc.mean(axis=0) / rmse_conv_mc.mean(axis=0)
print(f"without attack: RMSE NN {np.round(rmse(nn_free), 5).tolist()}, conventional "
      f"{np.round(rmse(conv_free), 5).tolist()}, ratio "
      f"{np.round(rmse(nn_free) / rmse(conv_free), 5).tolist()}")
print(f"with attack, mean over {n_mc} runs: RMSE NN {np.round(rmse_nn_mc.mean(axis=0), 5).tolist()}, "
      f"conventional {np.round(rmse_conv_mc.mean(axis=0), 5).tolist()}, ratio of the means "
      f"{np.round(ratio_mean_c3, 5).tolist()}")
print("attack's relative rise of the conventional RMSE per node, interval at level "
      f"{c3_level:.4f}: {np.round(c3_rise_iv, 5).tolist()} (precondition: some lower end > "
      f"{c3_margin:g})")
print(f"RMSE_NN - (1 - c3_margin) RMSE_conv per node, interval: {np.round(c3_diff_iv, 5).tolist()}")

# %% [markdown]
# ## Claims
#
# | id | paper | what we measure, and the rule | decides |
# |---|---|---|---|
# | C1 | each node tracks both states "with a satisfactory precision" with the NN estimator (Figs. 1–4); the conventional one "with certain precision" (Figs. 5–8) | $\max|\tilde x^{(l)}_{i,k}|$ of (8) for $k\ge$ `settle_k` against `track_tol` = 0.2, **ours** (the paper states no number; 0.2 is the brief's reading of the tick residue of Fig. 4, data within about ±0.2); the conventional value is reported. **Premise**: the example's assumptions (below) on the NN run | no: its level is ours |
# | C2 | the errors stay in the required region with probability $\ge p$ **at every node and step** (Theorem 3, (11)) | per pair $(i,k)$, $k=1..T$: Wilson interval of the fraction of the `mc_runs` independent runs inside $\mathfrak B_k$ at the Bonferroni level $1-0.05/NT$; holds if every pair's lower end is $\ge p$, fails if some pair's upper end is $<p$, else not checked (section "Monte Carlo"); the former average over the pairs is recorded, not deciding. **Premise**: the example's assumptions and Theorem 1's (19) on every run | **yes** |
# | C3 | the conventional estimator "shows worse estimation performance in the existence of falsified innovations" than the NN-based one (Figs. 5–8 vs 1–4) | per-node RMSE of $\|\tilde x\|$ over $k=1..T$, both designs on each of C2's `mc_runs` realisations: per node the Student-t interval (Bonferroni over the nodes) of the mean of $\mathrm{RMSE}_{NN}-(1-$`c3_margin`$)\,\mathrm{RMSE}_{conv}$; holds if every node's upper end is $<0$, fails if some lower end is $>0$, else not checked (margin ours: a tie within solver noise is not "worse"); headline: the worst node's ratio of the mean RMSEs. **Precondition** (ours): against the attack-free control ($\alpha\equiv0$, both designs), the attack raises the conventional RMSE by more than `c3_margin` at some node (same interval rule), else fails-premise; and the example's assumptions on every run (section "C3 over the realisations") | **yes** |
# | C4 | $\mathrm{tr}[\tilde W^\top Q^{-1}\tilde W]\le1$ for all $k$ (Theorem 1) | max over links and steps, with $W=W^\star$. **By construction**: the maximum is at $k=0$, fixed by the data, and from $k=1$ on $Q=e_1^2I$ holds (19) for any $W$ that Assumption 2 allows | no: by construction |
# | C5 | the recursive LMIs are solvable at every step (Algorithm 1, Theorems 1–3) | every solve certified by our strict certificate. **By construction**: OP2/OP3 and OP1 are feasible in exact arithmetic ($\mathfrak B_{k+1}$, $Q_{ij,k+1}$ free), so only our certificate is measured; where it rejects a solve, **not checked** (a limit of ours) | no: by construction |
# | C7 | the attacks are estimated jointly with the states (abstract; Sec. I, contribution iv) | per link $i\leftarrow j$, $k=1..T-1$: RMS of $\chi(z_{j,k})-\hat W_{ij,k}\phi(z_{i,k})$ over the RMS of $\chi(z_{j,k})$ (the zero estimate's ratio is 1); holds if below $1-$`attack_margin` (ours: more than solver round-off) at every link where the premise's oracle fits. **Premise**: the NN class can fit the attack at all: an oracle of the same class, $W\phi(z_{i,k})$ with $W$ fitted by least squares to the true attack (two-fold cross-validated over **contiguous halves** of the steps, the out-of-sample split for a time series; the all-steps fit is recorded), beats the zero estimate by the same margin on at least one link — a level that admits an oracle removing only 0.1 % of the attack's RMS as "fits"; and the example's assumptions. **Fails by construction of OP1 (E4)** wherever the premise holds: one evaluation, not independent failures | **yes** (a failure that follows from the paper's own OP1) |
# | C8a | Theorem 2, (29), exactly along the run | $E_{\alpha_k}\{\tilde x_{i,k+1}^\top P_{k+1}^{-1}\tilde x_{i,k+1}\mid\text{past}\}\le1$ at every node and certified step (both branches of $\alpha_k$ computed). **Premise**: the constraints of (23) hold at every certified step | no: a step of Theorem 3, which C2 decides |
# | C8b | Theorem 2, (29), over realisations | per pair, Student-t interval of the mean of $\tilde x^\top P_k^{-1}\tilde x$ over the runs at the Bonferroni level: holds if every upper end $\le1$, fails if some lower end $>1$, else not checked. **Premise**: C2's (Theorem 2 holds "under the condition of Theorem 1") | no: as C8a |
# | X1 | (ours) the error dynamics (54) | $\max|\tilde x_{i,k+1}-(\Xi_i+\tilde\alpha_k\tilde\Xi_i)\zeta_k|$ at the actual $\zeta_k$, certified steps, $\le10^{-10}$ (round-off) | no: ours |
# | X2 | (ours) the premise (12)–(13) at this point's $L_i=\aleph_i$ | worst ratio $\|\text{remainder}\|/(s\|\tilde x\|)$ over the certified steps of both runs $\le1$ | no: ours |
# | X3 | (ours, E4–E5) the NN mechanism is not reproduced: OP1 collapses the weights, OP2 drops the neighbours | $\max_k|\lambda^{(2)}|\le10^{-6}$, $\max_{k\ge1}\|\hat W_{ij,k}\|_F\le10^{-6}$, $\max\|H_{ij}\|\le10^{-2}$ (levels ours: orders of magnitude above round-off, below any active compensation) | no: ours |
# | X4 | (ours) Theorem 2's Schur step: the solved (30) bounds the quadratic form by 1 for admissible $\zeta$ | 256 random admissible $\zeta$ per certified step (boundary of every constraint) | no: ours |
# | X5 | (ours) DPP re-solve equals a fresh build | $\max|P_{k+1}|$ difference at the last step $\le10^{-6}$ (premise: that step is certified) | no: ours |
# | X6a | (ours) our solvers certify the printed shared-multiplier LMI (22) at the first `shared_diag_steps` steps | holds if no shared solve is uncertified; an uncertified solve is a limit of ours (the LMI is feasible in exact arithmetic): **not checked**, never "fails" (a statement about our numerics, not the paper's) | no: ours |
# | X6b | (ours) the printed (22) is never less conservative than per-node multipliers | $\mathrm{tr}\,\mathfrak B_k$ shared $\ge$ per-node $-10^{-6}$ at $k=1..$`shared_diag_steps`; $k=1$ holds by construction (same data, a special case), $k\ge2$ is measured (the data differ); not checked unless every compared solve is certified | no: ours |
# | X10 | (ours) Corollary 3 / OP3 (33), corrected (E2): for given $\mathfrak B_{k+1}$ (here this run's OP2 ellipsoids) the error lies in $\mathcal X(0,\mathfrak B_{k+1})$ with probability $\ge p_k=1-\rho_k$ | on the main realisation: no step's guarantee void ($p_k>0$) and the fraction of (node, step) pairs inside $\mathfrak B_k$ $\ge$ the mean $p_k$; one realisation, so a record that the guarantee is non-void and not contradicted, not a test of the per-pair probability (C2 tests Theorem 3's); the earlier constant $\mathfrak B=2I$ is recorded (extra, paper mode, not swept) | no: ours |
# | X9 | (ours, brief E5) the attack-unaware conventional design uses its neighbours | median over $k$ of $\max_{ij}\|H_{ij,k}\|$ of the conventional design $\ge0.5$ (ours: a third of the 1.5 the brief reports, 500 times the NN design's $\sim10^{-3}$) | no: ours |
#
# C6 (the cost per step, Remark 7) is a timing and belongs to the benchmark suite (`make bench`).
#
# **The example's assumptions** (the premise of C1, C2, C3, C7 and C8b): Assumption 3 at $k=0$, and
# (12)–(13) with $L_i=\aleph_i=sI$ and $\|\delta_j\|\le e_3$ at every **certified** step of the
# runs the claim is measured on; C2 and C8b add Theorem 1's (19) on every run (Theorems 2–3 are
# stated under the condition of Theorem 1). Premises are evaluated on certified steps only: after the first
# solve that our certificate rejects, our fallback keeps the previous gains and doubles $P$ (brief
# §7), so the run is no longer Algorithm 1's, and what it does says nothing about the paper.
#
# **Our numerical limits are not the paper's failures.** OP2 is feasible in exact arithmetic
# ($\mathfrak B_{k+1}$ is a free variable, brief §7), and so is OP1 ($Q_{ij,k+1}$ free), so a
# rejected solve is ours, whatever the solver's status. A solve is *not certified* when no solver
# returns status "optimal" with every LMI's largest eigenvalue $\le-10^{-8}$; C5's
# `first_failure` records whether a solver called the first one "infeasible" or "numerical". C5 is
# then not checked; C1, C2, C3, C7 and C8a, measured on the trajectories, are **not checked**
# wherever our fallback drove a run they are measured on (after their premise, which decides
# first); X6b is not checked unless every compared solve is certified. X1 and X4 use certified
# steps only; X3 and X9 read the gains, which after a rejected step are copies of the last
# certified ones, and stand as measured.
#
# **Which claims decide** (`results.rescience_verdict`, the one rule for all five papers): the
# paper's main contributions, from its abstract, introduction and conclusion, each a measured
# statement that can fail: the probability guarantee (C2, Theorem 3), the NN-based mechanism that
# mitigates the falsified innovations, shown by the example's comparison (C3), and the joint
# estimation of the attacks (C7, contribution iv). The solvability of the recursive LMIs (C5) and
# Theorem 1's weight bound (C4) hold by construction here and cannot decide; C1's level is ours;
# C8a/C8b are Theorem 2's intermediate step towards Theorem 3, which C2 decides.
#
# Every claim is measured at this run's point; `make robustness` measures it at every point of the
# declared space, and the verdict written to `claims.json` is the one over that space, decided on
# the points where the claim is checked and its premise holds (X5 is an extra, not swept: its
# verdict is this point's). The counts over the space are printed below from
# `figures/ma2021/robustness.json`, and per Taylor-scale level in the section "Verdict".

# %%
SEC_EXAMPLE = "The example (Section IV): both estimators under the same falsified innovations"
SEC_MC = r"Monte Carlo over independent $\alpha_k$ realisations (C2, C8b)"
SEC_DIAG = "Extra — diagnostics: what the designs actually do"
SEC_C3 = r"C3 over the $\alpha_k$ realisations, with an attack-free control"
SEC_TAYLOR = r"The missing Taylor scales $L_i$, $\aleph_i$: a declared range"
TOL_LMI = results.LMI_ITERATES  # every value below driven by interior-point LMI solves


def first_failure(res: dict) -> str | None:
    """How the first uncertified solve of a run failed: None (every solve certified),
    "infeasible" (a solver reported the problem infeasible) or "numerical" (no solver reported
    infeasibility; each returned an inaccurate or uncertified solution, or a solver error)."""
    if not res["failures"]:
        return None
    return "infeasible" if "infeasible" in res["failure_outcomes"][0].values() else "numerical"


def failure_place(msg: str) -> str:
    """Step, problem and every solver's status of an uncertified solve, from its message."""
    return msg.splitlines()[0].split(" at ", 1)[-1]


def certified_steps(res: dict) -> int:
    """The leading steps k = 0, 1, ... before the first uncertified solve (OP2/OP3 or OP1): the
    steps that are Algorithm 1's (after it our fallback drives the run)."""
    steps = [re.search(r"step (\d+),", msg) for msg in res["failures"]]
    if not all(steps):
        raise ValidationError(f"an uncertified solve names no step: {res['failures']}")
    return min((int(m.group(1)) for m in steps), default=res["Hn"].size)


def fallback_note(*runs: tuple[str, dict]) -> str | None:
    """The not-checked reason of a claim measured on runs where our fallback fired, else None."""
    fired = [(name, r) for name, r in runs if r["failures"]]
    if not fired:
        return None
    first = ", ".join(f"{name} at {failure_place(r['failures'][0])}" for name, r in fired[:2])
    return (f"our fallback (previous gains kept, P doubled, brief §7) drove {len(fired)} of the "
            f"{len(runs)} run(s) measured after an uncertified solve ({first}"
            + (", ..." if len(fired) > 2 else "") + "): the trajectory is not Algorithm 1's")


def example_premise(runs: list, what: str) -> tuple[str, bool]:
    """The example's assumptions: Assumption 3 at k = 0; (12)-(13) and ||delta_j|| <= e3 on the
    certified steps of every run in `runs` (premise of C1, C2, C3, C7)."""
    wf = wg = wd = 0.0
    for res in runs:
        n_c = certified_steps(res)
        wf = max(wf, res["ratio_f"].reshape(-1, N)[:n_c].max(initial=0.0) / L_scale)
        wg = max(wg, res["ratio_g"].reshape(-1, N)[:n_c].max(initial=0.0) / aleph_scale)
        wd = max([wd] + [float(np.linalg.norm(chi(zj) - W_star @ phi(zj)))
                         for zk in res["run"].z[:n_c] for zj in zk])
    n_cert = sum(certified_steps(r) for r in runs)
    text = (f"Assumption 3 at k = 0 (quadratic forms {np.round(A3_forms, 3).tolist()} <= 1, weight "
            f"part {A3_weight:.3f} <= 1); on the certified steps of {what} ({n_cert} of "
            f"{sum(r['Hn'].size for r in runs)}): (12)-(13) with L_i = aleph_i = {L_scale:g} I (worst "
            f"||remainder|| / (s ||x~||): f {wf:.3f}, g {wg:.3f} <= 1) and ||delta_j|| <= e3 "
            f"(max {wd:.3f} <= {e3:g})")
    return text, bool(A3_holds and wf <= 1.0 and wg <= 1.0 and wd <= e3)


claims = {}
late = k_axis >= min(settle_k, T_run)
max_late = {name: float(np.max(np.abs(r["err"][late]))) for name, r in
            (("nn", nn_run), ("conv", conv_run))}
note_nn = fallback_note(("NN", nn_run))
claims["C1"] = results.claim(
    paper="Figs. 1-4: the NN-based estimator (8) estimates both state components at every node "
    "'with a satisfactory precision' (the conventional one, Figs. 5-8, is 'also capable of providing "
    "state estimation with certain precision')",
    check=f"max |x~^(l)_(i,k)| of (8) over nodes, components and k >= {min(settle_k, T_run)} "
    f"<= track_tol = {track_tol:g}. track_tol is ours: the paper states no number for 'satisfactory "
    "precision' and its OCR keeps no figure data; 0.2 is the brief's reading of the tick residue "
    "of Fig. 4 (data within about +-0.2), about a tenth of the state's level (1.2-2); settle_k "
    f"= {settle_k} is ours (after the transient). The conventional estimator's value is reported, "
    "not judged (the paper claims only 'certain precision' for it)",
    measured={**max_late, "nn_smaller_than_conv": max_late["nn"] < max_late["conv"]}, key="nn",
    threshold=track_tol, holds=None if note_nn else max_late["nn"] <= track_tol,
    not_checked=note_nn, premise=example_premise([nn_run], "the NN run"),
    source="Sec. IV, Figs. 1-4 (and Figs. 5-8)", section=SEC_EXAMPLE, tolerance=TOL_LMI,
)
note_mc = fallback_note(*((f"NN run {r_}", res) for r_, res in enumerate(mc_runs_list)))
text_mc, holds_mc = example_premise(mc_runs_list, f"the {n_mc} NN runs")
wq_mc = max(float(r["Wq"].max()) for r in mc_runs_list)  # Theorem 1's (19) on every run
premise_mc = (f"{text_mc}; Theorem 1's condition (19), tr[W~^T Q^-1 W~] <= 1 with W = W*, at "
              f"every link and step of every run (max {wq_mc:.3f})", holds_mc and wq_mc <= 1.0)
pairs_decide = int((pair_lo >= p).sum())
pairs_below = int((pair_hi < p).sum())
k_c2, i_c2 = np.unravel_index(int(np.argmin(pair_lo)), pair_lo.shape)  # the worst pair
if note_mc:
    c2_holds, c2_note = None, note_mc
elif pairs_below:
    c2_holds, c2_note = False, None
elif pairs_decide == n_pairs:
    c2_holds, c2_note = True, None
else:
    c2_holds, c2_note = None, (
        f"{n_mc} runs cannot decide: {n_pairs - pairs_decide} of the {n_pairs} pairs have a "
        f"Bonferroni interval containing p (worst pair [{pair_lo.min():.4f}, "
        f"{pair_hi[k_c2, i_c2]:.4f}]) and none lies below p; a pair inside in every run reaches p "
        "from 50 runs on")
claims["C2"] = results.claim(
    paper="Theorem 3, (10)-(11): P{x~_(i,k)^T B_k^-1 x~_(i,k) <= 1} >= p = 0.8 at every node i "
    "and step k ('both the estimation errors are confined within the required range')",
    check=f"per pair (node i, step k = 1..T; {n_pairs} pairs), over {n_mc} independent alpha_k "
    "realisations (NN design, each run with its own B_k): the Wilson interval of the pair's "
    f"fraction of runs inside B_k at the Bonferroni level 1 - 0.05/{n_pairs} (multiplicity "
    "correction over the pairs tested). Holds if every pair's lower end is >= p; fails if some "
    "pair's upper end is < p; else not checked (too few runs to decide; a pair inside in every "
    "run reaches p from 50 runs on). Headline: the worst pair's rate, with its interval. k = 0 is "
    "left out and is no evidence: B_0 = P_0 / (1 - p), so the premise (Assumption 3) alone puts "
    "its forms below 1 - p (max_quadratic_form_k0). The average over the pairs of one run with "
    "its Wilson score interval over the runs (the statistic used before issue #30, session 13) is "
    "weaker than (11) and is recorded in average_record, not deciding. The run count 94 (paper "
    "mode) is fixed by the power computation of notebooks/ma2021.toml",
    measured={"worst_pair_rate": float(pair_rate.min()), "runs": n_mc, "pairs": n_pairs,
              "bonferroni_level": bonf_level, "pairs_lower_at_least_p": pairs_decide,
              "pairs_upper_below_p": pairs_below, "min_pair_lower": float(pair_lo.min()),
              "min_pair_upper": float(pair_hi.min()),
              "worst_pair_step_node": [int(k_c2) + 1, int(i_c2) + 1],
              "max_quadratic_form": float(qf_mc.max()),
              "max_quadratic_form_k0": float(nn_run["qf"][0].max()),
              "max_spread_over_runs": qf_spread,
              "fraction_conventional_design": float(np.mean(conv_run["qf"][1:] <= 1.0)),
              "average_record": {"mean_fraction": float(f_runs.mean()),
                                 "min_run_fraction": float(f_runs.min()),
                                 "wilson95_over_runs": [c2_avg_lo, c2_avg_hi],
                                 "deciding": False}},
    key="worst_pair_rate",
    interval=results.interval(float(pair_lo[k_c2, i_c2]), float(pair_hi[k_c2, i_c2]),
                              level=bonf_level, method="wilson, the worst pair, Bonferroni"),
    threshold=p, holds=c2_holds, not_checked=c2_note, decides=True, runs=n_mc,
    premise=premise_mc,
    source="Theorem 3, (10)-(11); Sec. IV, Figs. 3-4", section=SEC_MC, tolerance=TOL_LMI,
)
e_nn, e_conv = rmse(nn_run), rmse(conv_run)
ratio_c3 = e_nn / e_conv  # run 0 (the main realisation): the quantity of the earlier sweep's map
nodes_better = [i + 1 for i in range(N) if c3_diff_iv[i, 1] < 0.0]
c3_pre_holds = bool((c3_rise_iv[:, 0] > c3_margin).any())  # the attack raises conv. RMSE somewhere
c3_pre_fails = bool((c3_rise_iv[:, 1] <= c3_margin).all())  # nowhere, with confidence
note_c3 = fallback_note(*((f"NN run {r_}", res) for r_, res in enumerate(mc_runs_list)),
                        *((f"conventional run {r_}", res) for r_, res in enumerate(conv_mc)),
                        ("NN without attack", nn_free), ("conventional without attack", conv_free))
if note_c3 is None and not (c3_pre_holds or c3_pre_fails):
    note_c3 = (f"{n_mc} runs cannot decide the precondition: no node's interval of the attack's "
               f"relative rise of the conventional RMSE lies above c3_margin = {c3_margin:g}, and "
               "some contains it")
elif note_c3 is None and not ((c3_diff_iv[:, 1] < 0.0).all() or (c3_diff_iv[:, 0] > 0.0).any()):
    note_c3 = (f"{n_mc} runs cannot decide: some node's interval of RMSE_NN - (1 - c3_margin) "
               "RMSE_conv contains 0 and none lies above it")
text_c3, prem_c3 = example_premise(mc_runs_list + conv_mc + [nn_free, conv_free],
                                   f"the {2 * n_mc + 2} runs (both designs, {n_mc} realisations and "
                                   "alpha = 0)")
claims["C3"] = results.claim(
    paper="Sec. IV: 'in comparison to our developed approach, the conventional algorithm shows "
    "worse estimation performance in the existence of falsified innovations' (Figs. 5-8 against "
    "Figs. 1-4)",
    check=f"per-node RMSE of ||x~_(i,k)|| over k = 1..T (the paper names no measure), both "
    f"estimators on each of the {n_mc} independent alpha_k realisations of C2 (run 0 is the main "
    "run). Per node, the Student-t interval at the Bonferroni level 1 - 0.05/N of the mean over the "
    "runs of RMSE_NN - (1 - c3_margin) RMSE_conv, c3_margin = "
    f"{c3_margin:g} (ours: a tie within solver noise is not 'worse'): holds if every node's upper "
    "end is < 0; fails if some node's lower end is > 0; else not checked (too few runs). "
    "Precondition (ours, issue #30 re-read item 1): the attack raises the conventional design's "
    "RMSE: per node, the same interval of RMSE_conv / RMSE_conv(alpha = 0) - 1, where alpha = 0 "
    "is the attack-free control (both designs run without any falsified innovation); it holds if "
    "some node's lower end is > c3_margin (fails-premise if every node's upper end is <= "
    "c3_margin; else not checked). Headline: the worst node's ratio of the mean RMSEs NN / "
    "conventional. The conventional design is MISSING in the paper (ours: the attack-unaware "
    "OP2). Before this rule C3 was judged on run 0 alone, without the control",
    measured={"worst_node_ratio": float(ratio_mean_c3.max()), "ratio_of_means": ratio_mean_c3,
              "runs": n_mc, "rmse_nn_mean": rmse_nn_mc.mean(axis=0),
              "rmse_conventional_mean": rmse_conv_mc.mean(axis=0),
              "diff_interval_low": c3_diff_iv[:, 0], "diff_interval_high": c3_diff_iv[:, 1],
              "bonferroni_level": c3_level, "nodes_nn_better": nodes_better,
              "attack_free": {"rmse_nn": rmse(nn_free), "rmse_conventional": rmse(conv_free),
                              "ratio": rmse(nn_free) / rmse(conv_free)},
              "attack_rise_conventional_mean": c3_rise_mc.mean(axis=0),
              "attack_rise_interval_low": c3_rise_iv[:, 0],
              "attack_rise_interval_high": c3_rise_iv[:, 1],
              "precondition_attack_raises_conventional": c3_pre_holds,
              "run0": {"ratio": ratio_c3, "rmse_nn": e_nn, "rmse_conventional": e_conv,
                       "worst_node_ratio": float(ratio_c3.max())},
              "mean_nn": float(rmse_nn_mc.mean()), "mean_conventional": float(rmse_conv_mc.mean()),
              "taylor_scale": float(L_scale)},
    key="worst_node_ratio", threshold=1.0 - c3_margin,
    holds=None if note_c3 else bool((c3_diff_iv[:, 1] < 0.0).all()), not_checked=note_c3,
    decides=True, runs=n_mc,
    premise=(f"the attack raises the conventional design's RMSE by more than c3_margin at some "
             f"node (relative rise, interval lower ends {np.round(c3_rise_iv[:, 0], 5).tolist()}); "
             "and " + text_c3, bool(prem_c3 and not c3_pre_fails)),
    source="Sec. IV, last paragraph; Figs. 1-8", section=SEC_C3, tolerance=TOL_LMI,
)
thm1_max = float(nn_run["Wq"].max())
claims["C4"] = results.claim(
    paper="Theorem 1, (19): tr[W~_(ij,k)^T Q_(ij,k)^-1 W~_(ij,k)] <= 1 for all k",
    check="max over links and k = 0..T with the ideal weight W = W* (least-squares fit of chi). "
    "Holds by construction: the max is at k = 0, fixed by the data (||I - W*||_F^2 / 20); from "
    "k = 1 on W_hat ~ 0 and Q = e1^2 I, so (19) holds for any W allowed by Assumption 2",
    measured=thm1_max, threshold=1.0, holds=thm1_max <= 1.0, basis="by-construction",
    premise=(f"Assumption 3, weight part: tr[W~_0^T Q_0^-1 W~_0] = {A3_weight:.3f} <= 1 with W = W*, "
             f"and ||W*||_F = {np.linalg.norm(W_star):.3f} <= e1 (Assumption 2)",
             bool(A3_weight <= 1.0 and np.linalg.norm(W_star) <= e1)),
    source="Theorem 1, (18)-(19)", section=SEC_EXAMPLE, tolerance=TOL_LMI,
)
all_reports = nn_run["reports"] + conv_run["reports"]
n_uncert = len(nn_run["failures"]) + len(conv_run["failures"])
worst = max((r.worst_eig for r in all_reports), default=None)
c5_first = {"NN": first_failure(nn_run), "conventional": first_failure(conv_run)}
c5_holds = n_uncert == 0 and worst is not None and worst <= -cert_tol
claims["C5"] = results.claim(
    paper="Algorithm 1 / Theorems 1-3 (conditional on the solvability of (18) and (30); the example "
    "implies it): the recursive LMIs are solvable at every step",
    check="By construction: OP2/OP3 (30) is feasible in exact arithmetic (B_(k+1) is free, brief "
    "§7) and so is OP1 (18) (Q_(ij,k+1) free), so solvability cannot fail; what is measured is our "
    "strict certificate: every solve of both designs (OP2, OP1) certified, largest eigenvalue of "
    f"every solved LMI matrix <= -{cert_tol:g}. Holds if every solve is certified; where one is not, "
    "a limit of our numerics: not checked (first_failure records whether a solver called the "
    "first rejected solve of each run infeasible or numerical)",
    measured={"uncertified_steps": n_uncert, "solves": len(all_reports) + n_uncert,
              "max_eigenvalue": worst, "fallbacks_to_scs": sum(r.fallback for r in all_reports),
              "statuses": sorted({r.status for r in all_reports}),
              "max_asymmetry": max((max(r.asymmetry.values()) for r in all_reports), default=0.0),
              "max_residual": max((max(r.residual.values()) for r in all_reports), default=0.0),
              "first_failure": {k_: v_ or "none" for k_, v_ in c5_first.items()}},
    key="uncertified_steps", threshold={"uncertified_steps": 0, "max_eigenvalue": -cert_tol},
    holds=True if c5_holds else None,
    not_checked=None if c5_holds else (
        "our strict certificate rejected a solve of a problem that is feasible in exact arithmetic "
        "(first uncertified solve: " + ", ".join(
            f"{k_} at {failure_place(r_['failures'][0])}" for k_, r_ in
            (("NN", nn_run), ("conventional", conv_run)) if r_["failures"]) + ")"),
    basis="by-construction",
    source="Algorithm 1 (step 3 'solve (30)'); Theorems 1-3", section=SEC_EXAMPLE,
    tolerance=results.Tolerance(
        rtol=0.25, atol=1e-6,
        reason="interior-point diagnostics at the solver's stopping point: residuals and eigenvalue "
        "margins (~1e-7) may differ by their own size between machines, and near the range's upper "
        "end the count of uncertified steps depends on the last digits of the data; the "
        "certification itself is compared exactly through holds"),
)


def rms_ratio(a: np.ndarray, est: np.ndarray) -> float:
    """RMS of the error of `est` over the RMS of `a` (the zero estimate's ratio is 1)."""
    return float(np.sqrt(np.sum((a - est) ** 2) / np.sum(a**2)))


def oracle_ratio(X: np.ndarray, a: np.ndarray, in_sample: bool = False) -> float:
    """rms_ratio of the least-squares fit a ~ W x (rows of X), two-fold cross-validated over
    contiguous halves of the steps (the first half's fit predicts the second half and back: the
    out-of-sample split for a time series; alternating steps would leave neighbouring, correlated
    steps on both sides), or fitted and scored on all steps (`in_sample`, recorded only)."""
    if in_sample:
        return rms_ratio(a, X @ np.linalg.lstsq(X, a, rcond=None)[0])
    first = np.arange(len(a)) < len(a) // 2
    pred = np.zeros_like(a)
    for test in (first, ~first):
        W = np.linalg.lstsq(X[~test], a[~test], rcond=None)[0]
        pred[test] = X[test] @ W
    return rms_ratio(a, pred)


def attack_estimates(res: dict) -> dict:
    """Per link i <- j over k = 1..T-1 (C7): the ratio of the NN's estimate W^_(ij,k) phi(z_(i,k))
    of the injected signal chi(z_(j,k)), and of the oracle fits with inputs phi(z_i) (8) and
    phi(z_j) (the model (6))."""
    run_, ks = res["run"], np.arange(1, res["run"].z.shape[0])
    out = {"nn": [], "oracle": [], "oracle_in_sample": [], "oracle_model6": []}
    for i, j in LINKS:
        a = np.array([chi(run_.z[k, j]) for k in ks])
        out["nn"].append(rms_ratio(a, np.array([run_.W_hat[k][(i, j)] @ run_.phi[k, i]
                                                for k in ks])))
        out["oracle"].append(oracle_ratio(run_.phi[ks, i], a))
        out["oracle_in_sample"].append(oracle_ratio(run_.phi[ks, i], a, in_sample=True))
        out["oracle_model6"].append(oracle_ratio(run_.phi[ks, j], a))
    return {key: np.array(val) for key, val in out.items()}


att = attack_estimates(nn_run) if T_run >= 5 else None  # the oracle needs >= 2 steps per fold
fit_links = [] if att is None else [a for a in range(len(LINKS))
                                    if att["oracle"][a] < 1.0 - attack_margin]
link_names = [f"{i + 1}<-{j + 1}" for i, j in LINKS]
prem_ex = example_premise([nn_run], "the NN run")
c7_note = note_nn or (None if att is not None else
                      f"T = {T_run}: too few steps for the two-fold oracle fit (needs >= 5)")
claims["C7"] = results.claim(
    paper="Abstract: 'to jointly estimate the system states as well as the unknown deception "
    "attacks'; Sec. I, contribution iv): 'a joint estimation algorithm is provided to "
    "simultaneously estimate the system state and falsified innovations' (the NN (6) approximates "
    "the injected signal chi; (8) subtracts its expectation)",
    check="the attack estimate on link i <- j is the NN output W^_(ij,k) phi(z_(i,k)) that (8) uses "
    "for the injected signal chi(z_(j,k)) (ours: the paper names no measure). Per link over "
    "k = 1..T-1 (W^_0 = I is Assumption 3's given initial guess, not an estimate): ratio = RMS of "
    "the error over RMS of chi(z_j), the zero estimate's ratio being 1. Holds if the ratio is "
    f"below 1 - attack_margin = {1 - attack_margin:g} (ours: beats the zero estimate by more than "
    "solver round-off) at every link where the premise's oracle fits. Premise: the NN class can "
    "fit the attack at all: an oracle of the same class, W phi(z_(i,k)), with W fitted by least "
    "squares to the true attack, two-fold cross-validated over contiguous halves of the steps "
    "(the first half's fit predicts the second and back: out of sample for a time series; before "
    "issue #30's re-read the folds alternated even and odd steps, which left correlated "
    "neighbouring steps on both sides and made the fit nearly in-sample), beats the zero "
    "estimate by the same margin on at least one link. What that level admits: an oracle that "
    "removes only 0.1 % of the attack's RMS counts as 'fits'. The all-steps (in-sample) fit and "
    "the oracle with the model (6)'s input phi(z_j) are reported. Headline: the worst NN ratio "
    "over the links where the oracle fits (over every link if none does). By construction of "
    "OP1 (E4): (18) is symmetric in lambda2, so OP1 returns lambda2 = 0 and (with Q_0 = 20 I, "
    "e1 = 3) lambda1 = 0 for any data, W^ = 0 from k = 1 on, and the ratio is 1 - O(1e-11) at "
    "every link; wherever the premise holds C7 fails for that one reason. It still decides (a "
    "failure that follows from the paper's own OP1 is a failure of the claim, not a limit of "
    "ours), but over the declared space it is one evaluation repeated, not independent failures",
    measured={} if att is None else {
        "worst_nn_ratio": float(max(att["nn"][fit_links] if fit_links else att["nn"])),
        "nn_ratio": att["nn"], "oracle_ratio": att["oracle"],
        "oracle_ratio_in_sample": att["oracle_in_sample"],
        "oracle_ratio_model6": att["oracle_model6"], "links": link_names,
        "links_oracle_fits": [link_names[a] for a in fit_links],
        "oracle_split": "contiguous halves",
        "fails_by_construction_of_OP1": bool(all(abs(v - 1.0) <= 1e-6 for v in att["nn"])),
        "nn_minus_one": att["nn"] - 1.0},
    key=None if att is None else "worst_nn_ratio", threshold=1.0 - attack_margin,
    holds=None if c7_note else bool(all(att["nn"][a] < 1.0 - attack_margin for a in fit_links)),
    not_checked=c7_note, decides=True,
    premise=(("the NN class fits the attack on at least one link (oracle, cross-validated over "
              f"contiguous halves, ratio < "
              f"{1 - attack_margin:g}): " + ("not evaluated (too few steps)" if att is None else
              ", ".join(f"{n_} {v_:.4f}" for n_, v_ in zip(link_names, att["oracle"], strict=True)))
              + "; and " + prem_ex[0]), bool(prem_ex[1] and (att is None or fit_links))),
    source="Abstract; Sec. I, contribution iv); (6), (8), (17)", section=SEC_EXAMPLE,
    tolerance=results.Tolerance(rtol=1e-3, atol=1e-6, reason="ratios of LMI-driven trajectories; "
                                "the NN part sits at solver round-off (~1e-11)"),
)
dyn = float(nn_run["dyn_res"].max()) if nn_run["dyn_res"].size else None
claims["X1"] = results.claim(
    paper="(ours) error dynamics (54) with the row blocks re-derived from (15)-(16)",
    check="max |x~_(i,k+1) - (Xi_i + (alpha_k - alpha_bar) Xi~_i) zeta_k| over nodes and certified "
    "steps (an uncertified step keeps the previous gains, so (54) with its solution does not apply), "
    "zeta_k built from the actual remainders, delta = chi - W* phi and r = Mbar^-1 rho(W* - W_hat); "
    "<= 1e-10 (ours: round-off)",
    measured=dyn, threshold=1e-10, holds=dyn is not None and dyn <= 1e-10,
    source="ours; (15)-(16), (24)-(28), (54)", section=SEC_EXAMPLE,
    tolerance=results.Tolerance(rtol=1.0, atol=1e-12, reason="a residual at round-off level"),
)
n_cert_nn, n_cert_conv = certified_steps(nn_run), certified_steps(conv_run)
rat_f = np.concatenate([nn_run["ratio_f"][: n_cert_nn * N], conv_run["ratio_f"][: n_cert_conv * N]])
rat_g = np.concatenate([nn_run["ratio_g"][: n_cert_nn * N], conv_run["ratio_g"][: n_cert_conv * N]])
x2_worst = float(max(rat_f.max(initial=0.0) / L_scale, rat_g.max(initial=0.0) / aleph_scale))
claims["X2"] = results.claim(
    paper="(ours) the premise of Theorems 2-3: Taylor remainders (12)-(13) with ||Delta|| <= 1, "
    "i.e. ||remainder|| <= s ||x~|| with L_i = L_scale I and aleph_i = aleph_scale I",
    check="worst ratio ||remainder|| / (s ||x~||) over the (node, step) pairs of the certified "
    "steps of the NN and the conventional run, for f with L_scale and g_i with aleph_scale, <= 1; "
    "the k = 0 ratios (the lower end of the declared range) and the coverage fractions are reported",
    measured={"worst_ratio_over_scale": x2_worst,
              "fraction_f": float(np.mean(rat_f <= L_scale)) if rat_f.size else 1.0,
              "fraction_g": float(np.mean(rat_g <= aleph_scale)) if rat_g.size else 1.0,
              "max_ratio_f": float(rat_f.max(initial=0.0)),
              "max_ratio_g": float(rat_g.max(initial=0.0)),
              "k0_ratio_f": r0_f, "k0_ratio_g": r0_g,
              "max_delta": float(nn_run["delta_n"].max())},
    key="worst_ratio_over_scale", threshold=1.0, holds=x2_worst <= 1.0,
    source="ours; the premise (12)-(13) of Theorems 2-3", section=SEC_TAYLOR, tolerance=TOL_LMI,
)
lam2 = float(np.abs(nn_run["lam"][..., 1]).max())
w_after = float(nn_run["Wn"][1:].max())
h_nn = float(nn_run["Hn"].max())
trQ_dev = float(np.max(np.abs(nn_run["trQ"][1:] - NY * e1**2)) / (NY * e1**2))
claims["X3"] = results.claim(
    paper="(ours, brief E4-E5) the NN mechanism is not reproduced: the feasible set of (18) is "
    "symmetric in lambda2, so OP1 returns lambda2 = 0 and (with Q_0 = 20 I > e1^2 I) lambda1 = 0, "
    "W_hat = 0 from k = 1 on; and the robust OP2 (30) drops the neighbour innovations",
    check="max_k |lambda2| <= 1e-6, max_(k>=1) ||W_hat_(ij,k)||_F <= 1e-6 and max_k ||H_ij,k|| of "
    "the NN design <= 1e-2 (levels ours: orders of magnitude above solver round-off, ~1e-11, and "
    "below any compensation that could act); reported: the compensation actually subtracted in "
    "(8), lambda1 at k = 0 and the deviation of tr Q_(ij,k), k >= 1, from n_y e1^2",
    measured={"max_What_after_k0": w_after, "max_abs_lambda2": lam2, "max_H_nn": h_nn,
              "lambda1_k0": nn_run["lam"][0, :, 0],
              "max_compensation": float(nn_run["comp"].max()),
              "max_compensation_after_k0": float(nn_run["comp"][1:].max(initial=0.0)),
              "trQ_relative_deviation_after_k0": trQ_dev},
    key="max_What_after_k0", threshold={"lambda2": 1e-6, "What": 1e-6, "H_nn": 1e-2},
    holds=lam2 <= 1e-6 and w_after <= 1e-6 and h_nn <= 1e-2,
    source="ours; brief E4-E5 on (17), (18), (31) and (30)", section=SEC_EXAMPLE,
    tolerance=results.Tolerance(rtol=1.0, atol=1e-8, reason="values at solver round-off (W_hat, "
                                "lambda2 ~ 1e-11) differ between machines; the thresholds are "
                                "orders of magnitude above"),
)
q_max = float(nn_run["sampled_q"].max()) if nn_run["sampled_q"].size else float("nan")
claims["X4"] = results.claim(
    paper="(ours) Theorem 2: LMI (30) implies E_alpha{x~_(i,k+1)^T P_(k+1)^-1 x~_(i,k+1)} <= 1 (29) "
    "for every zeta admissible under the S-procedure constraints of (23)",
    check="max over certified steps, nodes and 256 random zeta per step on the boundary of every "
    "constraint of zeta^T (Xi^T P^-1 Xi + sigma^2 Xi~^T P^-1 Xi~) zeta <= 1",
    measured=q_max if np.isfinite(q_max) else None, threshold=1.0,
    holds=bool(np.isfinite(q_max) and q_max <= 1.0),
    source="ours; Theorem 2, (29)-(30), (55)", section=SEC_EXAMPLE, tolerance=TOL_LMI,
)
if extras:
    claims["X5"] = results.claim(
        paper="(ours) DPP: the per-step problem built once with cp.Parameters and re-solved gives the "
        "same solution as a freshly built problem",
        check="max |P_(k+1) re-solved - P_(k+1) fresh| at the last step <= 1e-6 (ours: far above "
        "the solvers' 1e-7 tolerances' effect on P)",
        measured=dpp_gap, threshold=1e-6, holds=dpp_gap is not None and dpp_gap <= 1e-6,
        premise=("the last step of the NN run is certified (else there is no solution to compare)",
                 last_certified),
        source="ours", section=SEC_EXAMPLE,
        tolerance=results.Tolerance(rtol=1.0, atol=1e-6, reason="difference of two solver runs"),
    )
SEC_SHARED = "The printed shared multipliers (22), first steps"
claims["X6a"] = results.claim(
    paper="(ours) our solvers certify the printed LMI (22), with one multiplier set Gamma_k shared "
    "by all nodes, at the first shared_diag_steps steps (a statement about our numerics; OP2 with "
    "shared multipliers is feasible in exact arithmetic, B_(k+1) being free)",
    check=f"uncertified solves of the shared-multiplier design over k = 0..{n_sh - 1} == 0: holds "
    "if every solve is certified; where one is not, that is a limit of our solvers (the problem "
    "is feasible in exact arithmetic), so not checked, never fails (before issue #30's re-read "
    "an uncertified solve was recorded as 'fails')",
    measured={"uncertified_steps_shared": len(shared_run["failures"]), "steps": n_sh},
    key="uncertified_steps_shared", threshold=0,
    holds=True if not shared_run["failures"] else None,
    not_checked=None if not shared_run["failures"] else (
        f"our solvers did not certify {len(shared_run['failures'])} of the {n_sh} shared solves "
        f"(first at {failure_place(shared_run['failures'][0])}): a limit of ours"),
    source="ours; (22) as printed", section=SEC_SHARED, tolerance=TOL_LMI,
)
x6_uncert = [msg for msg in shared_run["failures"] + nn_run["failures"]
             if any(f"step {k_}," in msg for k_ in range(n_sh))]
x6_note = (f"not every compared solve is certified (at {failure_place(x6_uncert[0])}): no certified "
           "pair of solutions to compare (a limit of our solver, not a counter-example)"
           if x6_uncert else None)
excess = trB_shared - trB_node
claims["X6b"] = results.claim(
    paper="(ours) the printed LMI (22) with one multiplier set Gamma_k shared by all nodes is a "
    "special case of per-node multipliers, so it is never less conservative",
    check=f"tr B_k of the shared design >= that of the per-node design - 1e-6 at k = 1..{n_sh} on "
    "the same data; k = 1 holds by construction (both start from B_0, P_0 and x^_0, and the shared "
    "LMI is a special case), k >= 2 is measured (the two runs' data differ from k = 1 on). "
    "Headline: the smallest excess at k >= 2 (at k = 1 if only one step is run). Checked only where "
    "every compared solve is certified (else not checked)",
    measured={"min_excess_measured": float(np.min(excess[2:] if n_sh >= 2 else excess[1:])),
              "min_excess": float(np.min(excess)), "trB_shared": trB_shared,
              "trB_per_node": trB_node},
    key="min_excess_measured", threshold=-1e-6,
    holds=None if x6_note else bool(np.all(excess >= -1e-6)), not_checked=x6_note,
    source="ours; (22) as printed", section=SEC_SHARED, tolerance=TOL_LMI,
)
step_ok = ((nn_run["qP"][:-1] <= 1.0).all(axis=1)
           & (nn_run["ratio_f"].reshape(T_run, N) <= L_scale).all(axis=1)
           & (nn_run["ratio_g"].reshape(T_run, N) <= aleph_scale).all(axis=1)
           & (nn_run["delta_n"].reshape(T_run, N) <= e3).all(axis=1)
           & (nn_run["Wq"][:-1] <= 1.0).all(axis=1)
           & np.isfinite(nn_run["cond"]).all(axis=1))[:n_cert_nn]  # certified steps only
cond_ok = nn_run["cond"][:n_cert_nn][step_ok]
c8a = float(cond_ok.max()) if cond_ok.size else None
claims["C8a"] = results.claim(
    paper="Theorem 2, (29): E{x~_(i,k+1)^T P_(k+1)^-1 x~_(i,k+1)} <= 1; by its proof ((55)-(57)) "
    "for every zeta_k satisfying the constraints of (23), the expectation over alpha_k (E8)",
    check="max over nodes and certified steps of the exact conditional expectation given the past, "
    "(1 - alpha_bar) q_0 + alpha_bar q_1 (both branches of alpha_k computed), <= 1 (the paper's "
    "level). Premise: at every certified step the constraints of (23) hold: "
    "x~_(l,k)^T P_k^-1 x~_(l,k) <= 1 at every node, (12)-(13), ||delta|| <= e3, Theorem 1's "
    "ellipsoid. Not checked where our fallback drove the run",
    measured={"max_conditional_expectation": c8a, "steps_checked": int(step_ok.sum()),
              "certified_steps": n_cert_nn, "steps": T_run,
              "max_conventional_design": float(np.nanmax(conv_run["cond"]))
              if np.isfinite(conv_run["cond"]).any() else None},
    key="max_conditional_expectation", threshold=1.0,
    holds=None if note_nn else c8a is not None and c8a <= 1.0, not_checked=note_nn,
    premise=("the constraints of (23) hold at every certified step of the NN run "
             f"({int(step_ok.sum())} of {n_cert_nn} certified steps; {T_run} steps)",
             bool(step_ok.all())),
    source="Theorem 2, (29), proof (55)-(57); E8", section=SEC_EXAMPLE, tolerance=TOL_LMI,
)
k_w, i_w = np.unravel_index(int(np.argmax(qP_iv[..., 1])), qP_iv.shape[:2])
if note_mc:
    c8b_holds, c8b_note = None, note_mc
elif (qP_iv[..., 0] > 1.0).any():
    c8b_holds, c8b_note = False, None
elif (qP_iv[..., 1] <= 1.0).all():
    c8b_holds, c8b_note = True, None
else:
    c8b_holds, c8b_note = None, (f"{n_mc} runs cannot decide: some pair's Bonferroni interval "
                                 "contains 1 and none lies above it")
claims["C8b"] = results.claim(
    paper="Theorem 2, (29): E{x~_(i,k+1)^T P_(k+1)^-1 x~_(i,k+1)} <= 1, the expectation over the "
    "realisations of alpha",
    check=f"Monte Carlo over {n_mc} independent realisations (NN design, each with its own P_k): "
    "per pair (node, k = 1..T) the Student-t interval of the mean of x~^T P_k^-1 x~ over the runs at "
    f"the Bonferroni level 1 - 0.05/{n_pairs}; holds if every upper end is <= 1, fails if some "
    "lower end is > 1, else not checked. Premise: C2's (Theorem 2 is stated 'under the condition "
    "of Theorem 1'; the example's assumptions and (19) on every run). Nearly degenerate: the NN "
    "design ignores alpha (X3), so the runs barely differ",
    measured={"max_upper_bonferroni": float(qP_iv[..., 1].max()),
              "max_mean": float(qP_mc.mean(axis=0).max()),
              "worst_step_node": [int(k_w) + 1, int(i_w) + 1], "runs": n_mc,
              "max_spread_over_runs": float(np.max(qP_mc.max(axis=0) - qP_mc.min(axis=0))),
              "uncertified_steps": sum(len(r["failures"]) for r in mc_runs_list)},
    key="max_upper_bonferroni",
    interval=results.interval(*qP_iv[k_w, i_w], level=bonf_level, method="student-t"),
    threshold=1.0, holds=c8b_holds, not_checked=c8b_note, runs=n_mc, premise=premise_mc,
    source="Theorem 2, (29)", section=SEC_MC, tolerance=TOL_LMI,
)
h_conv_med = float(np.median(conv_run["Hn"]))
claims["X9"] = results.claim(
    paper="(ours, brief E5) the attack-unaware conventional design uses its neighbours' innovations "
    "(||H|| ~ 1.5-2 in the brief), which the attack then reaches",
    check="median over k of max_ij ||H_ij,k|| of the conventional design >= 0.5 (ours: a third of "
    "the 1.5 the brief reports for this design, 500 times the NN design's ~1e-3)",
    measured={"median_H_conventional": h_conv_med, "max_H_conventional": float(conv_run["Hn"].max()),
              "median_H_nn": float(np.median(nn_run["Hn"]))},
    key="median_H_conventional", threshold=0.5, holds=h_conv_med >= 0.5,
    source="ours; brief E5", section=SEC_EXAMPLE, tolerance=TOL_LMI,
)
def finite_or_none(values: np.ndarray, fn) -> float | None:
    """fn of the finite values, or None where no step was solved (X10)."""
    return float(fn(values)) if values.size else None


if op3_run is not None:  # an extra (paper mode and the tests' default point), not swept
    p_k = p_op3[1:][np.isfinite(p_op3[1:])]  # steps OP3 solved (rho is NaN where our fallback drove)
    p_kf = p_fixed[1:][np.isfinite(p_fixed[1:])]
    note_x10 = fallback_note(("OP3 run", op3_run))
    first_void_fixed = (int(np.argmax(void_fixed[1:])) + 1) if void_fixed[1:].any() else None
    claims["X10"] = results.claim(
        paper="(ours) Corollary 3 / OP3 (33), corrected as E2: for given ellipsoids B_(k+1) (here "
        "the ones this run's OP2 designed at p), the estimation error lies in X(0, B_(k+1)) with "
        "probability at least p_k = 1 - rho_k, the largest level the RLMI (30) certifies",
        check="OP3 run on the main realisation with B_(k+1) of the OP2 (NN) run; the guaranteed p_k, "
        "k = 1..T, against the empirical rate of this one realisation, the fraction of its (node, "
        "step) pairs inside B_k. Holds if no step's guarantee is void (p_k > 0 at every step) and "
        "the fraction inside is >= the mean guaranteed p_k (the expected fraction is at least that "
        "mean if Corollary 3 holds). One realisation: its pairs are not independent samples, so "
        "this is a record that the guarantee is non-void and not contradicted, not a test of the "
        "per-pair probability (C2 tests Theorem 3's). With B from OP2, p_k close to p is expected: "
        "OP2's own solution is feasible for OP3 at rho = 1 - p on the same data (exactly at k = 0; "
        "later the trajectories differ slightly), so the level is nearly fixed by construction and "
        "what is measured is that it stays non-void along OP3's own run. Not checked where our "
        "fallback drove the run. "
        f"Recorded: the same OP3 with the constant B = {op3_scale:g} I used before (its reason, "
        "'close to the OP2 result', was wrong)",
        measured={"min_guaranteed_p": finite_or_none(p_k, np.min),
                  "mean_guaranteed_p": finite_or_none(p_k, np.mean),
                  "max_guaranteed_p": finite_or_none(p_k, np.max), "void_steps": int(void[1:].sum()),
                  "steps": T_run, "fraction_inside": float(np.mean(inside_op3)),
                  "max_quadratic_form": float(op3_run["qf"][1:].max()),
                  "trB_op2_first_last": [float(np.trace(nn_run["Bell"][1])),
                                         float(np.trace(nn_run["Bell"][-1]))],
                  "constant_B_record": {
                      "scale": float(op3_scale), "void_steps": int(void_fixed[1:].sum()),
                      "first_void_step": first_void_fixed,
                      "min_guaranteed_p": finite_or_none(p_kf, np.min),
                      "guaranteed_p_last_step": finite_or_none(p_fixed[-1:][np.isfinite(p_fixed[-1:])],
                                                               np.min),
                      "uncertified_steps": len(op3_fixed["failures"])}},
        key="min_guaranteed_p", threshold=0.0,
        holds=None if note_x10 else bool(p_k.size and (p_k > 0.0).all()
                                         and np.mean(inside_op3) >= np.mean(p_k)),
        not_checked=note_x10,
        source="ours; Corollary 3, OP3 (33) (corrected, E2)", section=SEC_DIAG, tolerance=TOL_LMI,
    )
results.write_claims(results_path, claims, robustness=ROBUSTNESS)
written = json.loads(results.resolve(results_path).read_text())
for cid, c in written.items():
    extra_info = ""
    if "robustness" in c:
        rb = c["robustness"]
        extra_info = (f"; over the declared space: {c['verdict']} ({results.counts_text(rb['outcomes'])})"
                      + ("; counted under the previous rule, not re-swept"
                         if "rule_changed_after_sweep" in rb else ""))
    print(f"{cid}: at this point {results.point_verdict(c)}{extra_info}")

# %% [markdown]
# ## Verdict
#
# The deciding claims (section "Claims") are the paper's main contributions that numbers can
# check and that can fail: the probability guarantee (C2, Theorem 3), the NN-based mechanism's
# advantage shown by the example's comparison (C3), and the joint estimation of the attacks (C7,
# contribution iv). C4 and C5 hold by construction and do not decide; C1's level is ours; C8a/C8b
# are Theorem 2's step towards C2; the X claims are ours. The written rule
# (`results.rescience_verdict`) gives the line below, then the sweep's summary per claim (counts
# over the 70 points, in the form README and ERRATA quote) and, for the claims measured on the
# trajectories, the outcomes per level of the Taylor scale $s$ (holds / fails / fails-premise /
# not-checked, of 10 points per level).

# %%
verdict_now = results.rescience_verdict(json.loads(results.resolve(results_path).read_text()))
print(verdict_now["line"])
SUMMARY = (json.loads(results.resolve(ROBUSTNESS).read_text())
           if results.resolve(ROBUSTNESS).exists() else {})
for cid, s_ in SUMMARY.items():
    print(f"{cid} {results.counts_text(s_['outcomes'])} -> {s_['verdict']}"
          + (f"\n    NOTE: {s_['rule_changed_after_sweep']}" if "rule_changed_after_sweep" in s_ else ""))
if results.robustness_markdown("ma2021"):
    display(Markdown(results.robustness_markdown("ma2021")))


def level_table(rows: list[dict], ids: list[str]) -> str:
    """Outcomes per level of L_scale (holds / fails / fails-premise / not-checked) per claim."""
    levels = sorted({float(r["L_scale"]) for r in rows})
    head = "| claim | " + " | ".join(f"s = {v:.3f}" for v in levels) + " |\n"
    head += "|---|" + "---|" * len(levels) + "\n"
    body = ""
    for cid in ids:
        if f"{cid}.outcome" not in rows[0]:
            continue
        cells = []
        for v in levels:
            outs = [r[f"{cid}.outcome"] for r in rows if float(r["L_scale"]) == v]
            cells.append(" / ".join(str(outs.count(o)) for o in results.POINT_OUTCOMES))
        body += f"| {cid} | " + " | ".join(cells) + " |\n"
    return head + body


SWEEP_ROWS = []
if results.resolve("figures/ma2021/robustness.csv").exists():
    with results.resolve("figures/ma2021/robustness.csv").open(newline="") as fh:
        SWEEP_ROWS = [row for row in csv.DictReader(fh) if row["status"] == "ok"]
if SWEEP_ROWS:
    display(Markdown(level_table(SWEEP_ROWS, ["C1", "C2", "C3", "C5", "C7", "C8a", "C8b", "X2",
                                              "X6a", "X6b", "X9"])))

# %% [markdown]
# **What the verdict contains.** The rule counts claims, not mechanisms, so it is said here what
# the claims show.
#
# * **The NN compensator, the paper's main contribution, is never active**, at the example or at
#   any point of the declared space (X3 at every point; C7 measures its output as an estimate of
#   the attack). This is not a level of ours: with the paper's $Q_{ij,0}=20I$ and $e_1=3$, OP1's
#   optimum has $\lambda^{(2)}=0$ (the feasible set of (18) is symmetric in it, E4) and
#   $\lambda^{(1)}=0$ (the S-procedure radius $\lambda^{(1)}\sqrt{20}+(1-\lambda^{(1)})3$ is smallest
#   there), so $\hat W_{ij,k}=0$ from $k=1$ on, whatever the Taylor scale, the realisation or the
#   OCR reading; and the robust OP2 switches the neighbours off ($\|H_{ij}\|\sim10^{-3}$), so even a
#   non-zero $\hat W$ would be multiplied by almost nothing. We found no declared point where it
#   is active and did not search for one outside the declared space; the verdict follows the rule.
# * **C7 (joint estimation of the attacks)** can only be judged where the paper's NN class can fit
#   the attack at all. The attack's energy is almost all in $0.3\cos z^{(2)}\approx0.3$, an even,
#   nearly constant function that a bias-free $\tanh$ layer fits only through a non-zero mean of
#   the innovations (E6); the cross-validated oracle of the premise says where that is possible.
#   Where it is, the NN's estimate is the zero estimate (ratio $1-O(10^{-11})$) and C7 fails; where
#   no link can be fitted, C7 fails its premise. **C7 fails by construction of OP1 (E4)**: the
#   feasible set of (18) is symmetric in $\lambda^{(2)}$, so OP1 returns $\lambda^{(2)}=0$ for any
#   data and $\hat W=0$ from $k=1$ on; wherever its premise holds the outcome is fixed before any
#   data is seen. It still decides, because that is a failure of the paper's own method, not a
#   limit of ours; but the failures counted over the space are **one evaluation repeated**, not
#   independent evidence. The premise's oracle is cross-validated over contiguous halves of the
#   steps (at the example it fits all four links, ratios 0.9949, 0.9905, 0.9905, 0.8965; the
#   all-steps fit 0.9948, 0.9895, 0.9895, 0.7796). Before, the folds alternated even and odd
#   steps, nearly in-sample for a time series; the level $1-$`attack_margin` admits an oracle that
#   removes only 0.1 % of the attack's RMS as "fits". The space counts were made with the
#   alternating split (not re-swept).
# * **C3 (the comparison)** holds only at part of the declared space and says nothing about the
#   NN mechanism: where it holds it holds through the attack-aware gains (the robust design drops
#   the falsified neighbour innovations that the attack-unaware conventional design still uses,
#   X9), and the grid levels at which it holds were placed knowing where it turns (section "The
#   missing Taylor scales"). The default scale is the geometric centre of the declared range, not
#   its lower end, which is the scale most favourable to C3.
# * **C3 now has an attack-free control and is judged over the realisations** (the hostile
#   re-read, items 1 and 5). Without any attack (section "C3 over the realisations") the NN
#   design is already worse at node 3 (ratio 1.0108) and the attack moves the conventional RMSE
#   by under 0.15 % at every node: $-0.013$ %, $-0.028$ % and $+0.146$ % (means over the 94 runs).
#   The precondition (the attack raises the conventional RMSE by more than `c3_margin` = 0.1 % at
#   some node) holds only at node 3 and only narrowly: its interval is [0.101 %, 0.1915 %], so a
#   margin above 0.1011 % would have left C3 not checked, and one of 0.1915 % or more would have
#   made it fails-premise. The margin is C3's own, kept
#   rather than moved; it was chosen knowing the re-read's one-realisation numbers (node 3:
#   +0.10 %), so it was known to be close. So C3 "fails" at the example, but what it records is
#   mostly the robust design's conservatism, not an effect of the falsified innovations. The
#   committed sweep judged C3 on one realisation per point without the control (the counts in
#   the table above are that rule's); the current rule was not re-swept.
# * **C3's outcome rests on choices of ours** (issue #30, item 4). At the example it rests on
#   three missing inputs: the Taylor scales $L_i=\aleph_i$ (the default is the centre of a
#   declared range), the conventional design (ours: the attack-unaware OP2) and $x_0^{(2)}$ (2.0);
#   only the first is swept. Its every-node rule is ours and stronger than the paper's
#   figure-level statement ("the conventional algorithm shows worse estimation performance"). The
#   weaker node-averaged reading is recorded in C3's `measured` (`mean_nn` against
#   `mean_conventional`) and gives the same outcome at the example (the NN's mean RMSE is the
#   larger); over the space only the worst node's ratio is tabulated, so the counts are the
#   every-node rule's (previous, one-realisation form).
# * **C2 (the probability guarantee)** is tested as Theorem 3 states it, at every (node, step)
#   pair, with a per-pair interval and a Bonferroni correction (section "Monte Carlo"). At the
#   example, with 94 runs, it holds. Over the declared space the sweep ran 16 runs per point (the
#   run count of the committed sweep: at 94 runs the 70 points would take about 2 h of wall time
#   on this 2-core machine), at which a pair inside in every run has lower end 0.5623 < $p$: the
#   rule can only give "fails" (it does not, anywhere) or "not checked", and the sweep's C2 column
#   was re-derived from the committed rows by that rule (ERRATA, session 13). The space verdict
#   the tooling writes is "fails-premise" because the premise fails at 2 points and no point is
#   decided; it is not evidence against C2. C2 is very conservative where its premise holds (the
#   largest quadratic form and the spread over the runs are in its record).
# * **The intervals in `robustness.json`** (the table above, "95 % Wilson") are the tooling's one
#   format for all papers, labelled as if the decided points were a sample of the declared space.
#   For C3 they are not (issue #30, item 5): the Taylor-scale levels were placed knowing where C3
#   turns, so its interval is no estimate of anything; only the counts per level are quoted.

# %% [markdown]
# ## C3 over the declared space: the map
#
# **Under C3's previous rule, not re-swept.** The committed sweep (`robustness.csv`) measured C3
# on one $\alpha_k$ realisation per point (the point's seed), by the worst node's ratio of the two
# RMSEs, without the attack-free control. The current rule (both designs over the point's Monte
# Carlo realisations, intervals per node, the precondition that the attack raises the
# conventional RMSE; section "C3 over the realisations") was not run over the space: the sweep
# would need two more designs' runs per realisation at each of the 70 points, more than this
# session's budget. So the counts and the map below are the previous rule's (`robustness.json`
# says so in C3's entry, `rule_changed_after_sweep`); where the attack moves the conventional
# design by no more than `c3_margin` the current rule gives fails-premise instead (at the example
# the precondition holds only narrowly, section "Verdict"), and where one realisation's outcome
# differs from the mean over the realisations (as at $s=0.139$) the outcome can change.
#
# Over the 70 points of the declared space (7 Taylor scales × 2 realisations × 5 OCR readings) the
# outcomes of C3 per scale level are in the table of the section "Verdict"; they are counts on a
# fixed grid whose levels were placed knowing where C3 turns (section "The missing Taylor
# scales"), not a sampled fraction. The cell below prints, per OCR reading, the range of the worst
# node's RMSE ratio at the points where C3 is decided and where our fallback drove a run.
#
# The lower panels show what C3 needs, not what decides it: C3 can hold only where the
# attack-unaware conventional design leans on its neighbours (X9), so that the falsified
# innovations reach it; that is necessary, not sufficient. Where X9 fails (the conventional
# design's median neighbour gain is below 0.5; it is not zero there, reaching 0.38), C3 fails at
# every decided point: the worst node's ratio is above 1 by up to about 5 % (the cell below
# prints the ranges from `robustness.csv`; an earlier version called the two estimators "nearly
# coincident" there). So the direction of C3 is set by
# the missing scales $L_i$, $\aleph_i$, the missing conventional design and the realisation, not by
# the paper's method.
#
# The figure is drawn from `figures/ma2021/robustness.csv`, the table `make robustness` writes
# (one row per point of the design: each claim's outcome and headline value). Top: the worst
# node's RMSE ratio NN / conventional (C3's headline; C3 holds below the dashed line) against the
# Taylor scale, one panel per OCR reading; the line is the median over the $\alpha_k$ realisations
# (seeds) and the band their range. Bottom: what C3 needs, the conventional design's median
# neighbour gain (X9's headline). The star is this run's point. The per-node ratios of
# every point are in its claims (`build/sweeps/ma2021/<point>/claims.json` after a sweep; the
# committed `claims.json` for the default point).

# %%
def read_robustness(path: str) -> list[dict]:
    """The finished rows of the sweep table, or [] when it has not been made."""
    full = results.resolve(path)
    if not full.exists():
        return []
    with full.open(newline="") as fh:
        return [row for row in csv.DictReader(fh) if row["status"] == "ok"]


def map_series(rows: list[dict], reading: str, column: str) -> tuple:
    """Scales, median and range over the seeds of `column` at one OCR reading."""
    sel = [r for r in rows if r.get("ocr_reading", reading) == reading and r[column] != ""]
    scales = sorted({float(r["L_scale"]) for r in sel})
    vals = [[float(r[column]) for r in sel if float(r["L_scale"]) == s_] for s_ in scales]
    return (np.array(scales), np.array([np.median(v) for v in vals]),
            np.array([min(v) for v in vals]), np.array([max(v) for v in vals]))


def map_figure(rows: list[dict]) -> None:
    """C3's headline and X9's headline against the Taylor scale, one panel per OCR reading."""
    readings = list(dict.fromkeys(r.get("ocr_reading", ocr_reading) for r in rows))
    fig, axs = plt.subplots(2, len(readings), figsize=(plotting.PAGE_WIDTH, 4.4), sharex=True,
                            sharey="row", squeeze=False)
    data = {}
    for col, reading_ in enumerate(readings):
        for row, (column, colour) in enumerate((("C3.value", "tab:blue"), ("X9.value", "tab:red"))):
            s_, med, lo_, hi_ = map_series(rows, reading_, column)
            axs[row, col].fill_between(s_, lo_, hi_, color=colour, alpha=0.2, lw=0,
                                       label="range over the seeds")
            axs[row, col].plot(s_, med, "o-", color=colour, ms=2.5, lw=1.0,
                               label="median over the seeds")
            data[f"{column} | {reading_}"] = (s_, med, lo_, hi_)
        axs[0, col].axhline(1.0 - c3_margin, color="k", ls="--", lw=0.8,
                            label="C3 holds below: 1 - c3_margin")
        for row in range(2):
            axs[row, col].axvline(0.15, color="0.5", ls="-.", lw=0.8,
                                  label="0.15, the earlier 0.05-grid rule's scale")
        axs[1, col].axhline(0.5, color="k", ls=":", lw=0.8, label="X9 threshold 0.5")
        axs[0, col].set_title(reading_, fontsize=7.5)
        axs[1, col].set_xlabel("Taylor scale $s$ [–]")
        if reading_ == ocr_reading:
            axs[0, col].plot(L_scale, ratio_c3.max(), "*", color="k", ms=8, label="this run")
            axs[1, col].plot(L_scale, h_conv_med, "*", color="k", ms=8)
    axs[0, 0].set_ylabel("C3: worst node's RMSE\nratio NN / conv. [–]")
    axs[1, 0].set_ylabel("X9: conv. design's\nmedian $\\max\\|H_{ij,k}\\|$ [–]")
    handles, labels = axs[0, 0].get_legend_handles_labels()
    handles2, labels2 = axs[1, 0].get_legend_handles_labels()
    extra = [(h, lab) for h, lab in zip(handles2, labels2, strict=True) if lab.startswith("X9")]
    fig.legend(handles + [h for h, _ in extra], labels + [lab for _, lab in extra],
               loc="outside lower center", ncols=3, fontsize=6.5, frameon=False)
    fig.set_layout_engine("constrained")
    keys = sorted(data)
    plotting.save_figure(fig, FIG_DIR, "extra_c3_map", data={
        "series": np.array([k_ for k_ in keys for _ in data[k_][0]]),
        "scale": np.concatenate([data[k_][0] for k_ in keys]),
        "median": np.concatenate([data[k_][1] for k_ in keys]),
        "min": np.concatenate([data[k_][2] for k_ in keys]),
        "max": np.concatenate([data[k_][3] for k_ in keys])},
        tolerance=dict.fromkeys(["median", "min", "max"], results.LMI_ITERATES))


sweep_rows = read_robustness("figures/ma2021/robustness.csv")
if not sweep_rows:
    print("figures/ma2021/robustness.csv not found: run `make robustness NB=ma2021` for the map")
elif plotting.figures_enabled():
    map_figure(sweep_rows)
for reading_ in dict.fromkeys(r["ocr_reading"] for r in sweep_rows):
    sel = [r for r in sweep_rows if r["ocr_reading"] == reading_ and r["C3.value"] != ""]
    for label_, outs in (("decided", ("holds", "fails")), ("not checked", ("not-checked",))):
        vals = [float(r["C3.value"]) for r in sel if r["C3.outcome"] in outs]
        if vals:
            print(f"{reading_:>18}, C3 {label_}: {len(vals)} points, worst node's ratio "
                  f"{min(vals):.5f}-{max(vals):.5f}")
decided_c3 = [r for r in sweep_rows if r["C3.outcome"] in ("holds", "fails")]
for label_, sel in (("C3 holds", [r for r in decided_c3 if r["C3.outcome"] == "holds"]),
                    ("X9 holds", [r for r in decided_c3 if r["X9.outcome"] == "holds"]),
                    ("X9 fails", [r for r in decided_c3 if r["X9.outcome"] == "fails"])):
    if sel:  # C3 decided; the worst node's ratio and X9's headline, from robustness.csv
        c3v, x9v = ([float(r[c_]) for r in sel] for c_ in ("C3.value", "X9.value"))
        print(f"C3 decided and {label_}: {len(sel)} points, C3 holds at "
              f"{sum(r['C3.outcome'] == 'holds' for r in sel)}; worst node's ratio "
              f"{min(c3v):.4f}-{max(c3v):.4f}; X9's median max ||H|| {min(x9v):.3g}-{max(x9v):.3g}")

# %% [markdown]
# ## Discussion
#
# * **What C3 measures here.** Where C3 holds, it holds through the attack-aware gains, not
#   through learning. OP1 is a convex problem in which $\lambda^{(2)}=0$ is always at least as good
#   as any other value: (18) is invariant under $\lambda^{(2)}\to-\lambda^{(2)}$ (E4), and an
#   interior-point solver returns the symmetric point. With $Q_0=20I$ and $e_1=3$ the S-procedure
#   radius $\lambda^{(1)}\sqrt{20}+(1-\lambda^{(1)})\cdot3$ is smallest at $\lambda^{(1)}=0$. Hence
#   $\hat W_{ij,1}=0$, $Q_{ij,k}=e_1^2I$ from $k=1$ on, and the compensation
#   $\bar\alpha\hat W\phi(z_i)$ is zero from then on (X3, panel d; C7). The robust design (30)
#   pays a worst-case price $\approx\sqrt{\bar\alpha}e_3\|H\|$ for every neighbour innovation, so it
#   keeps $\|H_{ij}\|$ near $10^{-3}$ (panel c; X3's `max_H_nn`) and the network decouples. The
#   attack-unaware design uses its neighbours (X9) while the Taylor scale is small: their
#   innovations partly cancel the shared measurement noise $\mu_k$, and they carry the attack when
#   $\alpha_k=1$, since $0.3\cos z^{(2)}\approx0.3$ is almost a constant bias. A larger $s$ inflates
#   the remainder terms of the attack-unaware LMI as well, until it drops the neighbours too.
# * **The record.** The earlier verdict "C3 does not hold" rested on the scale 0.15 that a
#   0.05-grid rule picked after the reversal at 0.15 was known; the next default, 0.116, was the
#   lower end of the declared range, the scale most favourable to C3 (issue #30). The default is
#   now the range's geometric centre, 0.1986, the middle level (section "The missing Taylor
#   scales"). None of these is the paper's: it gives no $L_i$, $\aleph_i$; C3 is judged over the range.
# * **Premises.** C1, C2, C3, C7 and C8b carry the example's assumptions as their premise (Assumption
#   3, (12)–(13) and $\|\delta\|\le e_3$ on the certified steps of the runs measured; C2 and C8b
#   also Theorem 1's (19) on every run). Where the
#   premise fails they are "fails-premise", not "holds" or "fails" (the sweep's table gives
#   where: the $g_1$ reading $\sin 2x^{(2)}$ has a $k=0$ remainder ratio above the lowest scale,
#   X2). At $x_0=[2;1]$ (outside the declared space, run by the tests) Assumption 3 fails at
#   nodes 1–2 (quadratic forms 1.14 and 1.17). C2 is very conservative where its premise holds,
#   and part of that is fixed by the premise: at $k=0$, $\mathfrak B_0=P_0/(1-p)$, so Assumption 3
#   alone puts the forms below $1-p=0.2$ (0.089 here, independent of the design). C2 therefore
#   counts $k=1..T$ only, where Theorem 3 is what bounds them; the LMI budgets for $V_k=1$ while
#   $|v_k|\le0.3$ and for $e_3=3$ while $\|\delta\|\le0.3$. The LMI itself is tight: on sampled
#   $\zeta$ at the boundary of every S-procedure constraint the quadratic form of (55) comes
#   close to 1 (X4, printed above), while along the run the exact conditional expectation of
#   (29) stays far below (C8a).
# * **The upper end of the scale range: our certificate's limit.** Under the strict certificate
#   the solutions near the top scale use up the margin $10^{-6}$ the solver was given: CLARABEL
#   reports "optimal" and the largest eigenvalue of an LMI matrix lies between $-10^{-8}$ and 0 at
#   the first rejected step (C5's `first_failure` says whether any solver called it
#   infeasible). OP2 and OP1 are feasible in exact arithmetic, so these are limits of ours: C5 is
#   **not checked** there, and the claims measured on runs our fallback then drove (previous
#   gains, $P$ doubled) are not checked either, after their premises, which are evaluated on the
#   certified steps only. An earlier version recorded such points as C5 "fails" and C1 "fails"
#   from the stale gains: our limits, recorded as the paper's failures.
# * **Shared multipliers (X6a, X6b).** The printed (22) with one $\Gamma_k$ grows
#   $\mathrm{tr}\,\mathfrak B_k$ much faster than per-node multipliers over the steps run (printed
#   above). Whether our solvers certify the printed LMI (X6a, ours, a numerical statement) and
#   whether it is never less conservative (X6b) are two claims: X6b is not checked wherever a
#   compared solve is not certified (an earlier version counted those points as fails), and its
#   first step holds by construction. X6a is not checked where our solvers could not certify a
#   shared solve (a limit of ours: the LMI is feasible in exact arithmetic); before the hostile
#   re-read it recorded those 12 points of the sweep as "fails". Its sweep column was re-derived
#   from the committed rows (the uncertified count is the column's headline value), so its counts
#   are the current rule's. What happens later is not claimed.
# * **C1's bound is ours.** The paper says the NN estimator tracks "with a satisfactory precision"
#   and the conventional one "with certain precision", with no number; `track_tol` = 0.2 is our
#   reading of the tick residue of Fig. 4. The conventional estimator's value is reported, not
#   judged, since the paper claims only "certain precision" for it.
# * **C4 and C5 hold by construction.** C4's maximum is at $k=0$ and is fixed by the data,
#   $\|I-W^\star\|_F^2/20$; from $k=1$ on $\hat W\approx0$ and $Q=e_1^2I$, so (19) holds for any
#   $W$ that Assumption 2 allows. C5's LMIs are feasible in exact arithmetic. Both are recorded
#   with `basis="by-construction"` (shown, not counted as evidence, never deciding), and the
#   README does not count them as reproduced results.
# * **OP3 / Corollary 3 (extra, paper mode; X10).** Corollary 3 fixes $\mathfrak B_{k+1}$ and
#   maximises the guaranteed $p_k$. With the ellipsoids this run's OP2 designed
#   ($\mathrm{tr}\,\mathfrak B_k$ from 7.26 at $k=1$ to 14.30 at $k=40$) the corrected OP3
#   guarantees $p_k$ between 0.79996 and 0.800001 at every step, none void, and every (node,
#   step) pair of the run lies inside $\mathfrak B_k$: the guarantee is met and, as expected, sits
#   at $p$ (OP2's own solution is feasible for OP3 at $\rho=1-p$). The earlier default, the
#   constant $\mathfrak B=2I$ with the reason "close to the OP2 result", was not close
#   ($\mathrm{tr}\,2I=4$): with it the guarantee was void ($\rho_k\ge1$) at 37 of the 40 steps,
#   from $k=4$ on, reaching $p_{40}=-8.55$ (X10's `constant_B_record`, panel f), so Corollary 3
#   was not exercised.

# %% [markdown]
# ## Deviations from the paper
#
# | item (tag) | paper (as printed / OCR) | here | why |
# |---|---|---|---|
# | E1, Lemma 4 (RECONSTRUCTED, OCR) | \"P& —%, / 1-p\": the $-1$ superscripts are lost | $P_k^{-1}=\mathfrak B_k^{-1}/(1-p)$, i.e. $P_k=(1-p)\mathfrak B_k$ | the only reading under which Markov's inequality yields (11); an OCR reconstruction, not a paper erratum (an earlier version listed it as CORRECTED) |
# | E2, OP3 (33) (CORRECTED) | min $q_k=1/(1-p_k)$, "1 < q < +∞" | min $\rho=1-p_{k+1}$ with $-\rho\mathfrak B$ in (30) | as printed the problem is not convex and points the wrong way |
# | E3, multipliers (DEVIATION, design choice) | one $\Gamma_k$ shared by all $N$ inequalities (22) | one $\Gamma_{i,k}$ per node (`shared_multipliers=False`) | the printed form is not wrong, only more conservative; per-node multipliers are a valid relaxation (a separate S-procedure per inequality). The printed LMI is run for 2 steps (X6a: certified by our solvers?; X6b: never less conservative; the values are printed in its section) |
# | (24)–(28) (RECONSTRUCTED) | OCR damaged | row blocks re-derived from (15)–(16) (table above) | where legible the printed blocks agree; checked to machine precision on every certified step (X1) |
# | $\varrho$, $\bar M$ | $\varrho$ stacks rows; $Q_{ij}\otimes I$ | `A.flatten()`; $\bar M=\mathrm{chol}(Q)\otimes I_{n_\phi}$ | consistent with $\mathrm{tr}[W^\top Q^{-1}W]=\varrho^\top(Q^{-1}\otimes I)\varrho$ |
# | $r$-vector | all $N^2$ ordered pairs ($d=63$) | links only ($d=43$), bound $r^\top r\le N^2$ kept | the dropped columns are identically zero |
# | (18) strict, (22) non-strict | | every LMI imposed as $\le-10^{-6}I$ and certified strict with numpy (largest eigenvalue $\le-10^{-8}$) | the margin keeps the solver's iterate inside the strict LMIs |
# | OP1 (DEVIATION) | $\lambda^{(1)},\lambda^{(2)}$ "positive" | free, with $|\lambda^{(2)}|\le10^3$ | the box removes an unbounded optimal face when $\varpi\approx0$ and is never active; $\lambda^{(2)}=0$ is optimal anyway (E4); with $\lambda^{(2)}>0$ imposed the symmetric optimum $0$ would be cut off (also in ERRATA) |
# | OP1 (DEVIATION) | one problem per link | one separable problem (sum of traces over the links) | the links share no variable, so the minimisers are the same; one solve per step (also in ERRATA) |
# | conventional design (MISSING) | "characterised by (3)" | attack-unaware analogue of OP2 | MISSING in the paper; other designs are plausible (e.g. attack-aware OP2 without the NN terms) and are not swept; C3 needs this one to use its neighbours (X9), so C3's map is conditional on it |
# | $L_i$, $\aleph_i$ (MISSING) | not given | $sI_2$ with $s$ in a declared range [0.116, 0.34] (7 geometric levels), tied; default the geometric centre $\sqrt{0.116\cdot0.34}=0.1986$ (the middle level) | from the premise's $k=0$ limit to the last certified scale; claims are judged over the range. Earlier versions used 0.1 (premise fails at $k=0$), then 0.15, picked by a 0.05-grid rule written after the reversal of C3 at 0.15 was known, then 0.116, the lower end, the scale most favourable to C3 |
# | C7 criterion (ours) | "jointly estimate … the unknown deception attacks" | per-link RMS error of $\hat W_{ij,k}\phi(z_{i,k})$ against $\chi(z_{j,k})$ over the attack's RMS, below $1-$`attack_margin`, on the links where an oracle of the same class fits, cross-validated over contiguous halves (before: alternating steps, nearly in-sample) | the paper names no measure; the zero estimate's ratio 1 is the natural level, the margin keeps round-off from deciding (and admits a 0.1 % oracle improvement as "fits"); C7 fails by construction of OP1 (E4) wherever its premise holds |
# | C3 criterion (ours) | "worse estimation performance in the existence of falsified innovations" | per-node RMSE over $k=1..T$ on C2's `mc_runs` realisations, NN better at every node by more than `c3_margin` = 0.1 % (intervals per node); precondition: against the attack-free control the attack raises the conventional RMSE by more than `c3_margin` at some node | the paper names no measure; a tie within solver noise is not "worse"; without the control the comparison says nothing about the falsified innovations; one realisation can flip the comparison |
# | $x_0^{(2)}$ (MISSING) | illegible ("R [ O I") | 2.0 | Assumption 3 holds for a 2nd entry in [1.08, 2.31]; not swept (budget), although the brief (§6) reports node 2 turning in favour of the conventional design at $x_0=[2;1]$, so C3's map is conditional on it; the tests run [2, 1], where Assumption 3 fails |
# | $\bar\alpha$, $E_1$, "0d5", "sin(2z" (RECONSTRUCTED) | partly illegible | as read: 0.67, 0.01, 0.45, $\sin x^{(2)}$; each alternative (0.6, 0.1, 0.05, $\sin 2x^{(2)}$) is a level of `ocr_reading`, swept one at a time | OCR; combinations are not swept (budget) |
# | $\alpha_k$ realisation (MISSING) | one realisation shown, no seed | seeds 0 and 1 swept (the main run's); C2 and C8b run `mc_runs` independent realisations from each seed (94 in paper mode, by the power rule of `ma2021.toml`; 16 at the sweep's points, for cost, where C2's per-pair rule cannot decide \"holds\") | only 2 seeds (budget); C3 turned with the seed at $s=0.139$ in the committed sweep (worst node's ratio 0.9839 on seed 0, 1.0091 on seed 1), so C3 is now judged on C2's realisations (94 at the example); the sweep's C3 counts are still the one-realisation rule's (not re-swept) |
# | $\varpi$ in (17) (RECONSTRUCTED) | "a Z 9in5,;€‘1’2;€+12@1€+1 JEN;" | sum over $j\in\mathcal N_i$ (`varpi_form`) | immaterial: $\lambda^{(2)}=0$ at every point (E4, X3), so $\varpi$ drops out of (17) |
# | $W_{ij}$ | not given | $W^\star$, least-squares fit of $\chi$ | needed to evaluate C4 and X1 |
# | $\mathfrak B_{k+1}$ of OP3 (MISSING) | given, not printed for the example | this run's OP2 ellipsoids (X10, panel f); before: the constant `op3_scale`$\cdot I=2I$, "close to the OP2 result", which it is not (OP2's trace grows well beyond 4; with $2I$ most steps' guarantees are void, X10's record) | Corollary 3 is then exercised on the ellipsoids the paper's own design produces |
# | figures | curves of the paper | qualitative comparison only | the paper's figures survive only as tick residue; the reconstructed $f,g_i$ cannot be checked against them |
# | C6, cost per step | Remark 7 | not measured here | timings belong to the benchmark suite (`make bench`) |

# %%
manifest_path = run.finish(solver=f"{solver} (fallback {fallback_solver})",
                           extra={"T_run": T_run, "lmi_solves": len(all_reports)})
print("run manifest:", manifest_path.relative_to(results.repo_root()))
