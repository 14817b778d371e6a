"""ma2021 in the arena: probability-guaranteed distributed estimation under falsified innovations.

Ma, Wang, Chen, Yi (2021): node ``i`` runs the estimator (8)
``x_{i,k+1} = F_i x_i + G_i z_i + sum_j theta_ij H_ij (z~_j - alpha_bar W^_ij phi(z_i))`` on its own
innovation ``z_i`` and the innovations ``z~_j`` its neighbours send, which an adversary falsifies
with probability ``alpha_bar`` (5). The gains come from the recursive LMI (30) (OP2 (32), or OP3
(33) as corrected), the neural-network weights ``W^_ij`` from the tuning law (17) whose scalars
come from LMI (18) (OP1 (31)); by Markov's inequality (Lemma 4, corrected: ``P_k = (1 - p) B_k``)
the error stays in the ellipsoid ``B_k`` with probability at least ``p``.

**The paper's Algorithm 1** (its nonlinear example, the ma2021 notebook, which runs and shows
these functions): :func:`run_algorithm1` is the recursion over ``k`` on a :class:`Model`, built
from :func:`build_op2`, :func:`set_op2_parameters`, :func:`build_op1`, :func:`set_op1_parameters`,
:func:`mbar`, :func:`solve`, :func:`estimator_update` (:func:`update_all`), :func:`varpi` and
:func:`weight_update` (the re-derived row blocks of (24)-(28), per-node multipliers E3,
E1 an OCR reconstruction, E2 a correction), with the per-step problems built once per configuration
(:func:`step_problems`); it returns an :class:`Algorithm1Run`.

**The arena's reading** (:class:`Ma2021`; rules fixed before any arena run):

* *Linear plants.* ``f(x) = A x`` and ``g_i(x) = C_i x``: ``Phi = A``, ``Psi_i = C_i`` and the
  Taylor remainders of (12)-(13) vanish, so ``L_i = aleph_i = 0`` (the p-blocks of zeta drop).
* *Noise ellipsoids (Assumption 1)* from the clipping of the scenarios: process noise
  ``v = w`` (``B = I``) with ``V = n NOISE_CLIP^2 q_std^2 I`` and, for every node, its own
  measurement noise ``mu_i`` (``E_i = I``) with ``U_i = n_y NOISE_CLIP^2 R_i``: the smallest
  ellipsoids holding the clipping boxes, one S-procedure multiplier each. Ours: the paper has a
  single ``mu`` shared by all sensors, which for independent sensors would have to hold the box
  of all ``N n_y`` noises (sqrt(N n_y) times larger per sensor) and would couple them.
* *Prior.* ``x^_{i,0} = 0``; Assumption 3 in the expectation form the induction of Theorem 2
  uses, ``E[(x_0 - x^_{i,0})^T P_0^-1 (x_0 - x^_{i,0})] <= 1`` with equality:
  ``P_0 = n x0_std^2 I``; ``p = 0.8`` (the paper's example) for the reported ellipsoid
  ``B_k = P_k / (1 - p)``.
* *What the theory lets us compute once per scenario.* With the prior ``W^_{ij,0} = 0``,
  ``Q_{ij,0} = e_1^2 I`` (Assumption 2 alone, no knowledge of the injection) OP1 keeps
  ``W^ = 0``: LMI (18) is invariant under ``lambda2 -> -lambda2`` (congruence flipping the sign
  of the first block), so ``lambda2 = 0`` is optimal whatever the data, and with ``W^ = 0`` the
  optimum ``Q = e_1^2 I`` is reached by every ``lambda1`` in ``[0, 1]`` (``W^`` stays 0). Then the
  first column of Xi is ``(A - F_i) x^_i`` and that of Xi~ is zero: flipping the sign of the
  first block of (30) shows that a zero first column, ``F_i = A``, is optimal for every
  ``x^_i``. Finally (``L = aleph = 0``) every ``H_ij`` appears only in the
  columns of ``s_j``, ``mu_j``, ``delta_j``, ``r_ij`` and in the sigma-row, so the congruence
  flipping those blocks maps ``H_ij`` to ``-H_ij``: ``H_ij = 0`` is optimal (neighbour innovations
  carry only the neighbours' errors and noises, which the S-procedure bounds independently).
  OP2 is then ``min tr P_{k+1}`` subject to ``[[-Gamma_i, *], [Xi_i, -P_{k+1}]] < 0`` with
  ``Xi_i = [0, (A - G_i C_i) S_k, I, -G_i]`` on ``zeta_i = [1; s_i; v; mu_i]``: no data, no
  attack parameter (``alpha_bar``, ``e_1``, ``e_3`` and the activation drop out), one
  recursion per network, shared by every run and every attack card. Nodes with the same
  ``(C_i, R_i)`` give the same LMI: it is imposed once.
* *Messages.* Each node sends its innovation ``z_i`` (scale: the prior standard deviation of
  an innovation, ``max_i sqrt(max diag(x0_std^2 C_i C_i^T + R_i))``); the estimator (8) is run
  on what arrives (falsified under the message card; a lost message is not used: its link term
  is dropped). With ``H = 0`` neither changes the estimate, and neither does the arena's
  Bernoulli draw per link where the paper has one ``alpha_k`` per step for every link.
* *Time index.* (3)/(8) are one-step predictors: the estimate of ``x_k`` uses the data up to
  ``k - 1`` (reported as is).
* *Not applicable* on sensor attacks (bias, replacement): they break Assumption 1 at the attacked
  sensor. A step of the recursion that no solver certifies makes the method not applicable on
  the scenario, with the step named.
* *Numerics.* Each step is solved after the congruence ``diag(1, I, V^1/2, U_i^1/2, S_k^-1)``
  (every zeta block a unit ball, ``P~ = S_k^-1 P_{k+1} S_k^-T``), the same LMI in units in which
  the strictness margin ``eps = 1e-6`` means the same on every plant; CLARABEL (tolerances 1e-7),
  certified ``strict`` (``max eig <= -1e-8``), SCS fallback with a warning, as the notebook does.
* *Cost.* ``K`` SDPs per network (one LMI of size ``3n + n_y + 1`` per distinct node), cached
  in-process and shared by every attack card and run count: at ``K = 200`` about 1 s of CPU on
  ``target20``, 3.5 s on ``tank12`` and 8.5 s on ``inertia5``; the runs themselves are
  vectorised (well under 1 s per scenario). The paper's per-run, per-step design would cost one
  SDP per run and step.
* *Non-unique minimisers.* OP2 minimises a trace: ``P_{k+1}`` and the gains (those of a node
  whose LMI is not active, in particular) need not be unique, and the recursion carries the
  solver's choice forward (deterministic for a given solver, version and options; CLARABEL with
  chordal decomposition off changes ``tr P_40`` on ``inertia5`` by 0.2 %).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import sparse

from secest.core import covariance
from secest.core.validation import (
    ValidationError,
    as_matrix,
    check_callable,
    check_choice,
    check_positive_int,
    check_probability,
    check_real,
)

__all__ = [
    "CERT_TOL",
    "CLARABEL_OPTS",
    "DESIGNS",
    "EPS_LMI",
    "P_LEVEL",
    "R_BOUNDS",
    "SCS_OPTS",
    "VARPI_FORMS",
    "Algorithm1Run",
    "Dims",
    "LinearDesign",
    "Model",
    "StepProblem",
    "build_op1",
    "build_op2",
    "estimator_update",
    "linear_design",
    "links",
    "mbar",
    "run_algorithm1",
    "set_op1_parameters",
    "set_op2_parameters",
    "solve",
    "step_problems",
    "update_all",
    "varpi",
    "weight_update",
]

Array = NDArray[np.float64]

P_LEVEL = 0.8
"""Probability level ``p`` of (10)-(11) (the paper's example)."""
EPS_LMI = 1e-6
"""Strictness margin: every LMI ``M < 0`` is imposed as ``M + EPS_LMI I <= 0`` (the notebook's)."""
CERT_TOL = 1e-8
"""Certificate: the largest eigenvalue of every solved LMI matrix is at most ``-CERT_TOL``."""
CLARABEL_OPTS = {"tol_feas": 1e-7, "tol_gap_abs": 1e-7, "tol_gap_rel": 1e-7}
"""CLARABEL tolerances of the notebook."""
SCS_OPTS = {"max_iters": 20000}
"""SCS options of the visible fallback (bounds its cost)."""
R_BOUNDS = ("lumped", "per_link")
"""Bound on the weight-error vector r of (23): ``r^T r <= N^2`` as printed, or one per link."""
DESIGNS = ("op2", "op3")
"""OP2 (32), min tr B_{k+1}; OP3 (33) as corrected (E2), min rho = 1 - p_{k+1} for a fixed B."""
VARPI_FORMS = ("sum", "per_link")
"""varpi of (17): summed over the in-neighbours (reconstructed reading) or the link's H only."""


# ------------------------------------------------------------------ the paper's Algorithm 1


@dataclass(frozen=True)
class Dims:
    """Dimensions of the paper's model (1), (6).

    Attributes
    ----------
    nx, ny, nv, nu, nphi : int
        State, output, process noise, measurement noise and activation dimensions.
    """

    nx: int
    ny: int
    nv: int
    nu: int
    nphi: int

    def __post_init__(self) -> None:
        for name in ("nx", "ny", "nv", "nu", "nphi"):
            check_positive_int(name, getattr(self, name))

    @property
    def m(self) -> int:
        """Length ``n_y n_phi`` of ``rho(W)``, the rows of a weight matrix stacked."""
        return self.ny * self.nphi


@dataclass
class StepProblem:
    """A per-step SDP built once with ``cvxpy.Parameter`` s (DPP) and re-solved each step.

    Attributes
    ----------
    problem : cvxpy.Problem
        The problem.
    params : dict
        Its parameters by name (lists per node, dicts per link).
    vars : dict
        Its decision variables by name.
    lmis : dict
        Name -> LMI matrix expression, certified by :func:`solve`.
    rows : dict
        OP2 only: node -> (row block ``R_i Xi_k``, row block ``R_i Xi~_k`` or None).
    """

    problem: Any
    params: dict
    vars: dict
    lmis: dict = field(default_factory=dict)
    rows: dict = field(default_factory=dict)


def _theta(theta: ArrayLike) -> Array:
    t = as_matrix("theta", theta, square=True)
    if np.any(t < 0) or np.any(np.diag(t) != 0):
        raise ValidationError("theta must be nonnegative with a zero diagonal (no self-loops)")
    return t


def links(theta: ArrayLike) -> list[tuple[int, int]]:
    """The links ``(i, j)`` with ``theta_ij > 0`` (node ``j`` sends to node ``i``), row by row.

    Parameters
    ----------
    theta : (N, N) array_like
        Weighted adjacency of the graph, nonnegative, zero diagonal.

    Returns
    -------
    list of (receiver, sender) pairs
    """
    t = _theta(theta)
    return [(i, j) for i in range(t.shape[0]) for j in range(t.shape[0]) if t[i, j] != 0]


def build_op2(
    theta: ArrayLike,
    dims: Dims,
    *,
    nn: bool,
    alpha_bar: float,
    e3: float,
    eps: float = EPS_LMI,
    shared: bool = False,
    r_bound: str = "lumped",
    design: str = "op2",
) -> StepProblem:
    """OP2 (32) or the corrected OP3 (33) subject to LMI (30) for every node, built once (DPP).

    Node ``i``'s error is ``x~_{i,k+1} = (Xi_i + alpha~_k Xi~_i) zeta_k`` (54) with
    ``zeta = [1; s; p1; p2; v; mu; delta; r]`` and the row blocks re-derived from (15)-(16)
    (the notebook's table; the OCR of (24)-(28) is damaged). With the S-procedure multipliers
    of (23) in ``Gamma_i`` (one set per node, E3; ``shared=True`` keeps the printed single
    ``Gamma_k``), (30) is ``[[-Gamma_i, *, *], [Xi_i, -P, *], [sigma Xi~_i, 0, -P]] < 0``,
    ``sigma^2 = alpha_bar (1 - alpha_bar)`` (21), imposed as ``<= -eps I``; ``nn=False`` gives the
    attack-unaware conventional design (``zeta = [1; s; p1; p2; v; mu]``, no sigma-row).

    Parameters
    ----------
    theta : (N, N) array_like
        Graph weights ``theta_ij`` (node ``j`` sends to ``i``), zero diagonal.
    dims : Dims
        Model dimensions.
    nn : bool
        Design of the NN-based estimator (8) (True) or of the conventional (3) (False).
    alpha_bar : float
        ``Prob{alpha_k = 1}`` of (5), in ``[0, 1]``.
    e3 : float
        Bound on ``||delta_j||`` of Assumption 2.
    eps : float, default EPS_LMI
        Strictness margin.
    shared : bool, default False
        One multiplier set for all nodes (the printed (22)) instead of one per node.
    r_bound : {"lumped", "per_link"}
        ``r^T r <= N^2`` as printed (23), or ``r_ij^T r_ij <= 1`` with one multiplier per link.
    design : {"op2", "op3"}
        ``"op2"``: minimise ``tr P_{k+1}`` (``P = (1 - p) B``, E1, read from the OCR);
        ``"op3"``: ``P = rho B`` with ``B`` a parameter, minimise ``rho = 1 - p_{k+1}`` (E2).

    Returns
    -------
    StepProblem
        Parameters (per node ``i``): ``fhat`` ``f(x^_i)``, ``xhat``, ``PhiS`` ``Phi_i S_k``,
        ``PsiS`` ``Psi_i S_k``, ``E`` ``E_{i,k}``, ``L``, ``aleph``; shared: ``StS``
        ``S_k^T S_k``, ``B``, ``Vinv``, ``Uinv`` (and ``Bell`` for OP3); per link when ``nn``:
        ``c1`` ``W^(phi(z_j) - phi(z_i))``, ``c2`` ``W^ phi(z_j)``, ``Cr``
        ``(I (x) phi(z_j)^T) Mbar_ij``. Variables ``F``, ``G`` (lists), ``H`` (dict by link),
        ``P`` (and ``rho``).
    """
    import cvxpy as cp

    from secest.core import lmi as slmi

    th = _theta(theta)
    check_probability("alpha_bar", alpha_bar)
    check_real("e3", e3, lower=0.0)
    check_choice("r_bound", r_bound, R_BOUNDS)
    check_choice("design", design, DESIGNS)
    n, lk_all = th.shape[0], links(th)
    nbrs = [[j for j in range(n) if th[i, j] != 0] for i in range(n)]
    NX, NY, NV, NU, M = dims.nx, dims.ny, dims.nv, dims.nu, dims.m
    sigma = np.sqrt(alpha_bar * (1.0 - alpha_bar))  # (21)
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
        par["c1"] = {lk: cp.Parameter(NY, name=f"c1_{lk}") for lk in lk_all}
        par["c2"] = {lk: cp.Parameter(NY, name=f"c2_{lk}") for lk in lk_all}
        par["Cr"] = {lk: cp.Parameter((NY, M), name=f"Cr_{lk}") for lk in lk_all}
    F = [cp.Variable((NX, NX), name=f"F{i}") for i in range(n)]
    G = [cp.Variable((NX, NY), name=f"G{i}") for i in range(n)]
    H = {lk: cp.Variable((NX, NY), name=f"H{lk}") for lk in lk_all}
    if design == "op2":
        P = cp.Variable((NX, NX), symmetric=True, name="P")  # P_{k+1} = (1 - p) B_{k+1}
        objective = cp.trace(P)
    else:
        par["Bell"] = cp.Parameter((NX, NX), symmetric=True, name="Bell")
        rho = cp.Variable(nonneg=True, name="rho")  # rho = 1 - p_{k+1}
        P = rho * par["Bell"]
        objective = rho
    nm = 1 if shared else n
    b1, b5, b6, b7 = (cp.Variable((nm, n), nonneg=True, name=nme) for nme in ("b1", "b5", "b6", "b7"))
    b2, b3 = cp.Variable(nm, nonneg=True, name="b2"), cp.Variable(nm, nonneg=True, name="b3")
    b4 = cp.Variable((nm, len(lk_all) if r_bound == "per_link" else 1), nonneg=True, name="b4")
    Ix = np.eye(NX)
    cons, lmis, rows = [], {}, {}
    for i in range(n):
        q = 0 if shared else i
        # Gamma_{i,k} of (23)
        gam = 1 - cp.sum(b1[q]) - b2[q] - b3[q]
        diag = [b1[q, ell] * Ix - (b5[q, ell] + b6[q, ell]) * par["StS"] for ell in range(n)]
        diag += [b5[q, ell] * Ix for ell in range(n)] + [b6[q, ell] * Ix for ell in range(n)]
        diag += [b2[q] * par["Vinv"], b3[q] * par["Uinv"]]
        if nn:
            gam = gam - e3**2 * cp.sum(b7[q])
            diag += [b7[q, ell] * np.eye(NY) for ell in range(n)]
            if r_bound == "per_link":
                gam = gam - cp.sum(b4[q])
                diag += [b4[q, a] * np.eye(M) for a in range(len(lk_all))]
            else:
                gam = gam - n**2 * b4[q, 0]
                diag += [b4[q, 0] * np.eye(len(lk_all) * M)]
        Gam = slmi.block_diag([cp.reshape(gam, (1, 1), order="F"), *diag])
        # row block i of Xi_k (24)-(28) and of Xi~_k (26)
        xi1 = par["fhat"][i] - F[i] @ par["xhat"][i]
        xit1 = np.zeros(NX)
        if nn:
            for j in nbrs[i]:
                xi1 = xi1 - alpha_bar * th[i, j] * (H[(i, j)] @ par["c1"][(i, j)])
                xit1 = xit1 - th[i, j] * (H[(i, j)] @ par["c2"][(i, j)])
        row = [cp.reshape(xi1, (NX, 1), order="F")]
        for ell in range(n):  # s_l
            blk = np.zeros((NX, NX))
            if ell == i:
                blk = blk + par["PhiS"][i] - G[i] @ par["PsiS"][i]
            if th[i, ell] != 0:
                blk = blk - th[i, ell] * (H[(i, ell)] @ par["PsiS"][ell])
            row.append(blk)
        row += [par["L"][i] if ell == i else np.zeros((NX, NX)) for ell in range(n)]  # p1_l
        for ell in range(n):  # p2_l
            blk = np.zeros((NX, NX))
            if ell == i:
                blk = blk - G[i] @ par["aleph"][i]
            if th[i, ell] != 0:
                blk = blk - th[i, ell] * (H[(i, ell)] @ par["aleph"][ell])
            row.append(blk)
        row.append(par["B"])  # v
        mu = -G[i] @ par["E"][i]
        for j in nbrs[i]:
            mu = mu - th[i, j] * (H[(i, j)] @ par["E"][j])
        row.append(mu)  # mu
        Xit = None
        if nn:
            rowt = [cp.reshape(xit1, (NX, 1), order="F"), np.zeros((NX, 3 * n * NX + NV + NU))]
            for ell in range(n):  # delta_l
                if th[i, ell] != 0:
                    row.append(-alpha_bar * th[i, ell] * H[(i, ell)])
                    rowt.append(-th[i, ell] * H[(i, ell)])
                else:
                    row.append(np.zeros((NX, NY)))
                    rowt.append(np.zeros((NX, NY)))
            for a, b in lk_all:  # r_ab
                if a == i:
                    row.append(-alpha_bar * th[a, b] * (H[(a, b)] @ par["Cr"][(a, b)]))
                    rowt.append(-th[a, b] * (H[(a, b)] @ par["Cr"][(a, b)]))
                else:
                    row.append(np.zeros((NX, M)))
                    rowt.append(np.zeros((NX, M)))
            Xit = cp.hstack(rowt)
        Xi = cp.hstack(row)
        if nn:
            Mi = slmi.block_symmetric([[-Gam], [Xi, -P], [sigma * Xit, None, -P]])  # (30)
        else:
            Mi = slmi.block_symmetric([[-Gam], [Xi, -P]])
        lmis[f"node {i + 1}"] = Mi
        rows[i] = (Xi, Xit)
        cons.append(slmi.lmi(Mi, eps))
    prob = cp.Problem(cp.Minimize(objective), cons)
    if not prob.is_dpp():  # pragma: no cover - a construction error
        raise RuntimeError("OP2/OP3 problem is not DPP")
    var = {"F": F, "G": G, "H": H, "P": P}
    if design == "op3":
        var["rho"] = rho
    return StepProblem(prob, par, var, lmis, rows)


def mbar(Q: ArrayLike, nphi: int) -> Array:
    """``Mbar = chol(Q) (x) I_{n_phi}``, so that ``Mbar Mbar^T = Q (x) I`` (proof of Theorem 1).

    Parameters
    ----------
    Q : (n_y, n_y) array_like
        Weight-error shape ``Q_{ij,k}`` of (19), positive definite (symmetrised first).
    nphi : int
        Activation dimension.

    Returns
    -------
    (n_y n_phi, n_y n_phi) ndarray
    """
    Qm = as_matrix("Q", Q, square=True)
    return np.kron(np.linalg.cholesky(covariance.symmetrize(Qm)), np.eye(nphi))


def set_op2_parameters(
    sp: StepProblem,
    *,
    S: ArrayLike,
    xhat: ArrayLike,
    fhat: ArrayLike,
    Phi: ArrayLike,
    Psi: ArrayLike,
    E: ArrayLike,
    B: ArrayLike,
    W_hat: Mapping[tuple[int, int], ArrayLike] | None = None,
    phi: ArrayLike | None = None,
    Mbar: Mapping[tuple[int, int], ArrayLike] | None = None,
) -> None:
    """Set the step-``k`` data of an OP2/OP3 problem (Algorithm 1, step 2).

    ``L``, ``aleph``, ``Vinv``, ``Uinv`` (and ``Bell``) are constant: set them once on
    ``sp.params`` directly.

    Parameters
    ----------
    sp : StepProblem
        From :func:`build_op2`.
    S : (n_x, n_x) array_like
        ``S_k``, ``P_k = S_k S_k^T``.
    xhat, fhat : (N, n_x) array_like
        ``x^_{i,k}`` and ``f(x^_{i,k})``.
    Phi : (N, n_x, n_x) array_like
        ``Phi_{i,k} = df/dx`` at ``x^_{i,k}`` (12).
    Psi : (N, n_y, n_x) array_like
        ``Psi_{i,k} = dg_i/dx`` at ``x^_{i,k}`` (13).
    E : (N, n_y, n_u) array_like
        ``E_{i,k}``.
    B : (n_x, n_v) array_like
        ``B_k``.
    W_hat, Mbar : mapping link -> array, optional
        ``W^_{ij,k}`` and ``Mbar_{ij,k}`` (required when the problem was built with ``nn``).
    phi : (N, n_phi) array_like, optional
        ``phi(z_{i,k})`` (required with ``nn``).
    """
    p = sp.params
    N = len(p["fhat"])
    (nx, nv), (ny, nu) = p["B"].shape, p["E"][0].shape
    S = _shaped("S", S, (nx, nx))
    xhat, fhat = _shaped("xhat", xhat, (N, nx)), _shaped("fhat", fhat, (N, nx))
    Phi, Psi = _shaped("Phi", Phi, (N, nx, nx)), _shaped("Psi", Psi, (N, ny, nx))
    E = _shaped("E", E, (N, ny, nu))
    p["StS"].value = S.T @ S
    p["B"].value = _shaped("B", B, (nx, nv))
    for i in range(N):
        p["fhat"][i].value = fhat[i]
        p["xhat"][i].value = xhat[i]
        p["PhiS"][i].value = Phi[i] @ S
        p["PsiS"][i].value = Psi[i] @ S
        p["E"][i].value = E[i]
    if "c1" not in p:
        return
    if W_hat is None or phi is None or Mbar is None:
        raise ValidationError("W_hat, phi and Mbar are required by a problem built with nn=True")
    ph = np.asarray(phi, float)
    for i, j in p["c1"]:
        p["c1"][(i, j)].value = W_hat[(i, j)] @ (ph[j] - ph[i])
        p["c2"][(i, j)].value = W_hat[(i, j)] @ ph[j]
        p["Cr"][(i, j)].value = np.kron(np.eye(ny), ph[j][None, :]) @ Mbar[(i, j)]


def _shaped(name: str, value: ArrayLike, shape: tuple[int, ...]) -> Array:
    a = np.array(value, dtype=float)
    if a.shape != shape:
        raise ValidationError(f"Incompatible dimensions of {name}: expected {shape}, found {a.shape}")
    return a


def build_op1(theta: ArrayLike, dims: Dims, *, e1: float, eps: float = EPS_LMI,
              lam2_box: float = 1e3) -> StepProblem:
    """OP1 (31) subject to LMI (18) for every link, as one separable DPP problem.

    ``rho(W~_{ij,k+1}) = Upsilon pi`` with ``pi = [1; r_ij; rho(W_ij)]`` and
    ``Upsilon = [-lambda2 (varpi (x) phi(z_i)), lambda1 Mbar, (1 - lambda1) I]``; the S-procedure
    with ``r^T r <= 1`` and ``||rho(W)||^2 <= e1^2`` gives (18),
    ``[[Omega, Upsilon^T], [Upsilon, -Q_{k+1} (x) I]] < 0``,
    ``Omega = diag(-1 + s1 + e1^2 s2, -s1 I, -s2 I)``; the objective is the sum over links of
    ``tr Q_{ij,k+1}`` (the link problems are independent). ``lambda2`` is sign-free and boxed.

    Parameters
    ----------
    theta : (N, N) array_like
        Graph weights (the links are its nonzero entries).
    dims : Dims
        Model dimensions.
    e1 : float
        Bound on ``||W_ij||_F`` of Assumption 2.
    eps : float, default EPS_LMI
        Strictness margin.
    lam2_box : float, default 1e3
        ``|lambda2| <= lam2_box`` (numerical: OP1 has an unbounded optimal face when varpi = 0).

    Returns
    -------
    StepProblem
        Parameters ``a`` (``varpi (x) phi(z_i)``) and ``Mbar`` per link; variables per link
        ``{"l1", "l2", "Q"}``.
    """
    import cvxpy as cp

    from secest.core import lmi as slmi

    check_real("e1", e1, lower=0.0)
    M, NY = dims.m, dims.ny
    lk_all = links(theta)
    par = {"a": {lk: cp.Parameter(M, name=f"a_{lk}") for lk in lk_all},
           "Mbar": {lk: cp.Parameter((M, M), name=f"Mbar_{lk}") for lk in lk_all}}
    var, cons, lmis, obj = {}, [], {}, 0
    for lk in lk_all:
        s1 = cp.Variable(nonneg=True, name=f"s1_{lk}")
        s2 = cp.Variable(nonneg=True, name=f"s2_{lk}")
        l1, l2 = cp.Variable(name=f"l1_{lk}"), cp.Variable(name=f"l2_{lk}")
        Q = cp.Variable((NY, NY), symmetric=True, name=f"Q_{lk}")
        Om = slmi.block_diag([cp.reshape(-1 + s1 + e1**2 * s2, (1, 1), order="F"),
                              -s1 * np.eye(M), -s2 * np.eye(M)])
        Ups = cp.hstack([cp.reshape(-l2 * par["a"][lk], (M, 1), order="F"),
                         l1 * par["Mbar"][lk], (1 - l1) * np.eye(M)])
        Ml = slmi.block_symmetric([[Om], [Ups, -cp.kron(Q, np.eye(dims.nphi))]])  # (18)
        lmis[f"link {lk[0] + 1}<-{lk[1] + 1}"] = Ml
        cons += [slmi.lmi(Ml, eps), cp.abs(l2) <= lam2_box]
        obj = obj + cp.trace(Q)
        var[lk] = {"l1": l1, "l2": l2, "Q": Q}
    return StepProblem(cp.Problem(cp.Minimize(obj), cons), par, var, lmis)


def set_op1_parameters(
    op1: StepProblem,
    varpi_: Mapping[tuple[int, int], ArrayLike],
    phi: ArrayLike,
    Mbar: Mapping[tuple[int, int], ArrayLike],
) -> None:
    """Set the data of OP1 (Algorithm 1, step 6): ``a_ij = varpi_ij (x) phi(z_{i,k})``, ``Mbar_ij``.

    Parameters
    ----------
    op1 : StepProblem
        From :func:`build_op1`.
    varpi_ : mapping link -> (n_y,) array
        ``varpi`` of (17) per link (:func:`varpi`).
    phi : (N, n_phi) array_like
        ``phi(z_{i,k})`` of every node (the receiver's own innovation, Remark 2).
    Mbar : mapping link -> array
        ``Mbar_{ij,k}`` (:func:`mbar`).
    """
    ph = np.asarray(phi, float)
    for lk in op1.params["a"]:
        op1.params["a"][lk].value = np.kron(varpi_[lk], ph[lk[0]])
        op1.params["Mbar"][lk].value = Mbar[lk]


def solve(
    sp: StepProblem,
    step: int,
    label: str,
    *,
    chordal: bool = True,
    eps: float = EPS_LMI,
    tol: float = CERT_TOL,
    solver: str = "CLARABEL",
    fallback: str | None = "SCS",
) -> Any:
    """Solve and certify a step problem: ``solver``, then ``fallback`` visibly (:mod:`secest.core.lmi`).

    The solution is accepted if the status is ``optimal`` and every LMI of ``sp.lmis`` has its
    largest eigenvalue at most ``-tol`` (``certify="strict"``), as in the notebook.

    Parameters
    ----------
    sp : StepProblem
        A problem with every parameter set.
    step : int
        Time step (named in the report and in an error).
    label : str
        Which problem (named in the report and in an error).
    chordal : bool, default True
        CLARABEL's chordal decomposition (the notebook turns it off for the tiny OP1).
    eps : float, default EPS_LMI
        The margin the LMIs were built with (reported).
    tol : float, default CERT_TOL
        Certification tolerance.
    solver, fallback : str
        cvxpy solver names; ``CLARABEL_OPTS`` go to CLARABEL, ``SCS_OPTS`` to SCS.

    Returns
    -------
    secest.core.lmi.LMISolveReport

    Raises
    ------
    secest.core.lmi.InfeasibleLMIError
        No solver returned an optimal solution certified ``strict`` at ``CERT_TOL``.
    """
    from secest.core import lmi as slmi

    def options(name: str | None) -> dict[str, Any]:
        if name == "CLARABEL":
            return {**CLARABEL_OPTS, **({} if chordal else {"chordal_decomposition_enable": False})}
        return dict(SCS_OPTS) if name == "SCS" else {}

    return slmi.solve_certified(sp.problem, sp.lmis, step=step, node=label, solver=solver,
                                fallback=fallback, tol=tol, eps=eps, certify="strict",
                                solver_opts=options(solver), fallback_opts=options(fallback))


def estimator_update(
    F: ArrayLike,
    G: ArrayLike,
    H: ArrayLike,
    xhat: ArrayLike,
    z: ArrayLike,
    z_recv: ArrayLike,
    theta: ArrayLike,
    *,
    W_hat: ArrayLike | None = None,
    phi_own: ArrayLike | None = None,
    alpha_bar: float = 0.0,
    edges: ArrayLike | None = None,
) -> Array:
    """One step of (8) (with ``W_hat``) or of the conventional (3) (without), every node.

    .. math:: \\hat x_{i,k+1} = F_i \\hat x_{i,k} + G_i z_{i,k}
              + \\sum_j \\theta_{ij} H_{ij} (\\tilde z_{ij,k} - \\bar\\alpha \\hat W_{ij} \\phi(z_{i,k}))

    Batched over any leading axes (Monte Carlo runs).

    Parameters
    ----------
    F : (N, n, n) array_like
        ``F_{i,k}``.
    G : (N, n, n_y) array_like
        ``G_{i,k}``.
    H : (N, N, n, n_y) array_like
        ``H_{ij,k}`` (any value where ``theta_ij = 0``).
    xhat : (..., N, n) array_like
        ``x^_{i,k}``.
    z : (..., N, n_y) array_like
        Own innovations ``z_{i,k} = y_{i,k} - g_i(x^_{i,k})``.
    z_recv : (..., N, N, n_y) array_like
        ``z_recv[..., i, j]``: the innovation node ``i`` received from ``j`` (5).
    theta : (..., N, N) array_like
        Graph weights; leading axes allow a per-run graph (a lost message: ``theta_ij = 0``).
    W_hat : (N, N, n_y, n_phi) array_like, optional
        ``W^_{ij,k}`` of (8); None gives (3).
    phi_own : (..., N, n_phi) array_like, optional
        ``phi(z_{i,k})``, the network input of node ``i`` (Remark 2); required with ``W_hat``.
    alpha_bar : float, default 0
        ``Prob{alpha_k = 1}``.
    edges : (E, 2) int array_like, optional
        The links as ``(receiver i, sender j)`` pairs. Given, every per-link argument is per
        edge instead of ``(N, N)``: ``H`` (E, n, n_y), ``z_recv`` (..., E, n_y), ``theta``
        (..., E), ``W_hat`` (E, n_y, n_phi), and a step costs ``O(E)`` instead of ``O(N^2)``.

    Returns
    -------
    (..., N, n) ndarray
        ``x^_{i,k+1}``.
    """
    if edges is not None:
        return _update_per_edge(F, G, H, xhat, z, z_recv, theta, np.asarray(edges),
                                W_hat, phi_own, alpha_bar)
    if W_hat is not None and phi_own is None:
        raise ValidationError("phi_own is required with W_hat (the compensation of (8))")
    F, G, H, theta = (np.asarray(a, float) for a in (F, G, H, theta))
    z_recv = np.asarray(z_recv, float)
    upd = _matvec(F, xhat) + _matvec(G, z)
    for j in range(H.shape[1]):  # neighbours in increasing order, as the notebook's sum
        inc = z_recv[..., j, :]
        if W_hat is not None:
            inc = inc - _matvec(alpha_bar * np.asarray(W_hat, float)[:, j], phi_own)
        upd = upd + _matvec(theta[..., j, None, None] * H[:, j], inc)
    return upd


def _update_per_edge(F: ArrayLike, G: ArrayLike, H: ArrayLike, xhat: ArrayLike, z: ArrayLike,
                     z_recv: ArrayLike, theta: ArrayLike, edges: NDArray[np.intp],
                     W_hat: ArrayLike | None, phi_own: ArrayLike | None, alpha_bar: float) -> Array:
    """:func:`estimator_update` with one ``H``, ``z_recv``, ``theta`` (and ``W_hat``) per edge."""
    if W_hat is not None and phi_own is None:
        raise ValidationError("phi_own is required with W_hat (the compensation of (8))")
    F, G, H, theta = (np.asarray(a, float) for a in (F, G, H, theta))
    N, E = F.shape[0], H.shape[0]
    if edges.shape != (E, 2) or theta.shape[-1] != E or np.shape(z_recv)[-2] != E:
        raise ValidationError(f"edges: expected ({E}, 2) (receiver, sender) pairs matching H, theta "
                              f"and z_recv per edge, found edges {edges.shape}, theta {theta.shape}, "
                              f"z_recv {np.shape(z_recv)}")
    inc = np.asarray(z_recv, float)
    if W_hat is not None:
        own = np.asarray(phi_own)[..., edges[:, 0], :]  # phi(z_i) of every edge's receiver
        inc = inc - _matvec(alpha_bar * np.asarray(W_hat, float), own)
    terms = _matvec(theta[..., None, None] * H, inc)  # (..., E, n)
    per_node = sparse.csr_array((np.ones(E), (edges[:, 0], np.arange(E))), shape=(N, E))
    summed = per_node @ np.moveaxis(terms, -2, 0).reshape(E, -1)  # sum over each node's in-edges
    neighbours = np.moveaxis(summed.reshape(N, *terms.shape[:-2], -1), 0, -2)
    return _matvec(F, xhat) + _matvec(G, z) + neighbours


def _matvec(M: Array, v: ArrayLike) -> Array:
    """``M[..., i] @ v[..., i]`` for every node ``i`` (broadcast over leading axes).

    Contiguous operands, so that numpy takes the same BLAS kernel as the notebook's ``M @ v``
    (a strided view takes a loop that rounds differently, which the recursive LMIs amplify).
    """
    return np.matmul(np.ascontiguousarray(M), np.ascontiguousarray(v, dtype=float)[..., None])[..., 0]


def varpi(
    H: Mapping[tuple[int, int], ArrayLike],
    Psi_next: ArrayLike,
    z_next: ArrayLike,
    theta: ArrayLike,
    alpha_bar: float,
    form: str = "sum",
) -> dict[tuple[int, int], Array]:
    """``varpi`` of the tuning law (17), per link (reconstructed from the OCR).

    ``"sum"``: ``varpi_i = alpha_bar sum_{j in N_i} theta_ij H_ij^T Psi_{i,k+1}^T z_{i,k+1}`` (every
    link of node ``i`` gets it); ``"per_link"``: only the term of the link's own ``H_ij``.

    Parameters
    ----------
    H : mapping link -> (n, n_y) array
        ``H_{ij,k}``.
    Psi_next : (N, n_y, n) array_like
        ``Psi_{i,k+1}``, the Jacobian of ``g_i`` at ``x^_{i,k+1}``.
    z_next : (N, n_y) array_like
        ``z_{i,k+1}``.
    theta : (N, N) array_like
        Graph weights.
    alpha_bar : float
        ``Prob{alpha_k = 1}``.
    form : {"sum", "per_link"}
        Reading of (17).

    Returns
    -------
    dict link -> (n_y,) ndarray
    """
    check_choice("form", form, VARPI_FORMS)
    th = _theta(theta)
    out = {}
    for i, j in links(th):
        Psi1 = np.asarray(Psi_next[i], float)
        terms = [jj for jj in range(th.shape[0]) if th[i, jj] != 0] if form == "sum" else [j]
        out[(i, j)] = alpha_bar * sum(th[i, jj] * np.asarray(H[(i, jj)]).T @ Psi1.T @ z_next[i]
                                      for jj in terms)
    return out


def weight_update(W_hat: ArrayLike, lam1: float, lam2: float, varpi_ij: ArrayLike,
                  phi_own: ArrayLike) -> Array:
    """Tuning law (17): ``W^_{ij,k+1} = lambda1 W^_{ij,k} + lambda2 varpi_ij phi(z_{i,k})^T``.

    Parameters
    ----------
    W_hat : (n_y, n_phi) array_like
        ``W^_{ij,k}``.
    lam1, lam2 : float
        The scalars of OP1 (31).
    varpi_ij : (n_y,) array_like
        ``varpi`` of the link (:func:`varpi`).
    phi_own : (n_phi,) array_like
        ``phi(z_{i,k})`` of the receiver.

    Returns
    -------
    (n_y, n_phi) ndarray
    """
    return lam1 * np.asarray(W_hat, float) + lam2 * np.outer(varpi_ij, phi_own)


# ------------------------------------------------------------------ Algorithm 1, the recursion


@dataclass(frozen=True)
class Model:
    """The plant and sensors of (1) and the activation of (6), as Algorithm 1 uses them.

    Attributes
    ----------
    f : callable ``x -> f(x)``
        Plant map of (1).
    jac_f : callable ``x -> Phi``
        ``Phi = df/dx`` at ``x`` (12).
    g : callable ``(i, x) -> g_i(x)``
        Sensor map of node ``i`` (1).
    jac_g : callable ``(i, x) -> Psi_i``
        ``Psi_i = dg_i/dx`` at ``x`` (13).
    B : callable ``k -> B_k``
        Process-noise input of (1).
    E : callable ``(i, k) -> E_{i,k}``
        Measurement-noise input of node ``i`` (1).
    phi : callable ``z -> phi(z)``, default tanh
        Activation of the network (6).
    """

    f: Callable[[Array], Array]
    jac_f: Callable[[Array], Array]
    g: Callable[[int, Array], Array]
    jac_g: Callable[[int, Array], Array]
    B: Callable[[int], Array]
    E: Callable[[int, int], Array]
    phi: Callable[[Array], Array] = np.tanh


@dataclass
class Algorithm1Run:
    """What Algorithm 1 computed, step by step (``n`` steps, ``k = 0..n-1``).

    Attributes
    ----------
    links : list of (receiver, sender)
        The links of the graph (:func:`links`), the keys of ``H``, ``W_hat``, ``Q``, ``Mbar``.
    xh : (n + 1, N, n_x) ndarray
        Estimates ``x^_{i,k}`` (8) (or (3) for the conventional design).
    P : (n + 1, n_x, n_x) ndarray
        ``P_k = (1 - p) B_k`` of OP2 (``rho_k B`` of OP3); at a step not certified ``2 P_k``.
    Bell : (n + 1, n_x, n_x) ndarray
        The ellipsoid ``B_k`` of (11): ``P_k / (1 - p)`` (OP2) or the fixed ``B`` (OP3);
        ``B_0 = P_0 / (1 - p)`` (Lemma 4, E1: P_k^-1 = B_k^-1 / (1 - p), read from the OCR).
    rho : (n + 1,) ndarray
        OP3's ``rho_k = 1 - p_k`` (NaN for OP2 and at ``k = 0``).
    S : (n, n_x, n_x) ndarray
        ``S_k = chol(P_k)``.
    z, z_recv : (n, N, n_y) ndarray
        Own innovations ``z_{i,k}`` and what the neighbours of node ``j`` receive from it.
    phi : (n, N, n_phi) ndarray
        ``phi(z_{i,k})``.
    F, G : list of n lists of N arrays
        The gains used at step ``k`` (a step not certified keeps the previous ones).
    H : list of n dicts link -> array
        The neighbour gains used at step ``k``.
    W_hat, Q : list of n + 1 dicts link -> array
        NN weights ``W^_{ij,k}`` and their error shapes ``Q_{ij,k}`` (19).
    Mbar : list of n dicts link -> array
        ``Mbar_{ij,k}`` (:func:`mbar`).
    lam : (n, n_links, 2) ndarray
        ``(lambda1, lambda2)`` of OP1 per step and link (0 for the conventional design).
    solved : (n,) ndarray of bool
        Whether OP2/OP3 was certified at step ``k``.
    rows : list of n (list of N (Xi_i, Xi~_i) pairs) or None
        The solved row blocks of (54) per node, evaluated (``keep_rows=True``, certified steps).
    reports : list
        The :class:`secest.core.lmi.LMISolveReport` of every certified solve.
    failures : list of str
        The message of every solve no solver certified (OP2/OP3 and OP1).
    failure_outcomes : list of dict
        Per entry of ``failures``, solver name -> outcome of its attempt (``"infeasible"``,
        ``"inaccurate"``, ``"not certified"``, ``"solver error"``;
        :class:`secest.core.lmi.LMISolveError`).
    """

    links: list[tuple[int, int]]
    xh: Array
    P: Array
    Bell: Array
    rho: Array
    S: Array
    z: Array
    z_recv: Array
    phi: Array
    F: list = field(default_factory=list)
    G: list = field(default_factory=list)
    H: list = field(default_factory=list)
    W_hat: list = field(default_factory=list)
    Q: list = field(default_factory=list)
    Mbar: list = field(default_factory=list)
    lam: Array | None = None
    solved: Array | None = None
    rows: list = field(default_factory=list)
    reports: list = field(default_factory=list)
    failures: list = field(default_factory=list)
    failure_outcomes: list = field(default_factory=list)


def step_problems(
    theta: ArrayLike,
    dims: Dims,
    *,
    nn: bool,
    alpha_bar: float,
    e1: float,
    e3: float,
    eps: float = EPS_LMI,
    shared: bool = False,
    r_bound: str = "lumped",
    design: str = "op2",
    lam2_box: float = 1e3,
    cache: dict | None = None,
) -> tuple[StepProblem, StepProblem]:
    """OP2/OP3 (:func:`build_op2`) and OP1 (:func:`build_op1`), built once per configuration.

    With a ``cache`` the same problem objects are returned for the same configuration, so that
    every run re-solves them with new parameter values (DPP). A re-solved problem and a freshly
    built one agree to the solver's tolerance only (~1e-7): which of the two a run uses decides
    its last digits.

    Parameters
    ----------
    theta, dims, nn, alpha_bar, e3, eps, shared, r_bound, design
        As in :func:`build_op2`.
    e1, lam2_box
        As in :func:`build_op1`.
    cache : dict, optional
        Problems built so far, by configuration (filled here); None builds fresh ones.

    Returns
    -------
    (StepProblem, StepProblem)
        OP2/OP3 and OP1.
    """
    th = _theta(theta)
    key2 = ("nn" if nn else "conv", th.tobytes(), dims, alpha_bar, e3, eps, shared, r_bound,
            design)
    key1 = ("op1", th.tobytes(), dims, e1, eps, lam2_box)
    cache = {} if cache is None else cache
    if key2 not in cache:
        cache[key2] = build_op2(th, dims, nn=nn, alpha_bar=alpha_bar, e3=e3, eps=eps,
                                shared=shared, r_bound=r_bound, design=design)
    if key1 not in cache:
        cache[key1] = build_op1(th, dims, e1=e1, eps=eps, lam2_box=lam2_box)
    return cache[key2], cache[key1]


def run_algorithm1(
    model: Model,
    y: ArrayLike,
    received: Callable[[int, Array], Array],
    *,
    theta: ArrayLike,
    dims: Dims,
    xhat0: ArrayLike,
    P0: ArrayLike,
    W0: ArrayLike,
    Q0: ArrayLike,
    alpha_bar: float,
    e1: float,
    e3: float,
    L: ArrayLike,
    aleph: ArrayLike,
    V_inv: ArrayLike,
    U_inv: ArrayLike,
    nn: bool = True,
    p: float = P_LEVEL,
    design: str = "op2",
    B_fixed: ArrayLike | None = None,
    shared: bool = False,
    r_bound: str = "lumped",
    varpi_form: str = "sum",
    eps: float = EPS_LMI,
    lam2_box: float = 1e3,
    solver: str = "CLARABEL",
    fallback: str | None = "SCS",
    tol: float = CERT_TOL,
    keep_rows: bool = False,
    cache: dict | None = None,
) -> Algorithm1Run:
    """Algorithm 1: the NN-based estimator (8) with OP2 (32) / OP3 (33), OP1 (31) and (17).

    For ``k = 0..n-1``: (1) every node forms ``z_{i,k} = y_{i,k} - g_i(x^_{i,k})`` and receives
    ``received(k, z)``; (2) ``Phi_{i,k}``, ``Psi_{i,k}``, ``phi(z_{i,k})`` and ``Mbar_{ij,k}``
    are formed; (3) OP2 (or OP3) is solved for ``F, G, H`` and ``P_{k+1} = (1 - p) B_{k+1}``
    (:func:`solve`); (4) the estimates follow from (8) (``nn``) or (3); (5)-(6) ``varpi`` of (17)
    from ``z_{i,k+1}``, ``Psi_{i,k+1}`` and OP1 gives ``lambda1, lambda2, Q_{ij,k+1}``; (7)
    ``W^_{ij,k+1}`` from (17). A step no solver certifies keeps the previous gains and doubles
    ``P`` (OP2/OP3), or keeps ``W^`` and ``Q`` (OP1), and is named in ``failures``.

    Parameters
    ----------
    model : Model
        ``f``, ``g_i``, their Jacobians, ``B_k``, ``E_{i,k}`` and ``phi``.
    y : (n + 1, N, n_y) array_like
        Measurements ``y_{i,k}``, ``k = 0..n`` (``y_{i,n}`` is read by OP1 at the last step).
    received : callable ``(k, z) -> z_recv``
        The innovations as they arrive, ``(N, n_y)`` from ``(N, n_y)`` (the attack (5)).
    theta : (N, N) array_like
        Graph weights.
    dims : Dims
        Model dimensions.
    xhat0 : (N, n_x) array_like
        Initial estimates.
    P0 : (n_x, n_x) array_like
        ``P_0`` of Assumption 3 (``B_0 = P_0 / (1 - p)``).
    W0 : (n_y, n_phi) array_like
        Initial weights of every link.
    Q0 : (n_y, n_y) array_like
        Initial weight-error shape of every link, positive definite.
    alpha_bar, e1, e3 : float
        ``Prob{alpha_k = 1}`` and the bounds of Assumption 2.
    L, aleph : (n_x, n_x), (n_y, n_x) array_like
        Taylor scales ``L_i``, ``aleph_i`` of (12)-(13), the same for every node.
    V_inv, U_inv : array_like
        ``V_k^-1`` and ``U_k^-1`` of Assumption 1.
    nn : bool, default True
        NN-based design (8) or the attack-unaware conventional design (3) (no OP1).
    p : float, default P_LEVEL
        Probability level of (10)-(11).
    design : {"op2", "op3"}
        OP2 (32), or the corrected OP3 (33) with the fixed ellipsoid ``B_fixed``.
    B_fixed : (n_x, n_x) or (n + 1, n_x, n_x) array_like, optional
        The ellipsoid of OP3 (required with ``design="op3"``): one matrix for every step, or
        the sequence B_0..B_n, of which step k uses B_(k+1) (Corollary 3 fixes B_(k+1)).
    shared, r_bound, eps
        As in :func:`build_op2`.
    varpi_form : {"sum", "per_link"}
        Reading of ``varpi`` in (17) (:func:`varpi`).
    lam2_box : float
        As in :func:`build_op1`.
    solver, fallback, tol
        As in :func:`solve` (``fallback=None``: none).
    keep_rows : bool, default False
        Keep the solved row blocks ``Xi_i``, ``Xi~_i`` of (54) of every certified step.
    cache : dict, optional
        Problems shared between runs (:func:`step_problems`).

    Returns
    -------
    Algorithm1Run

    Raises
    ------
    ValidationError
        An argument of the wrong shape or value (named).
    """
    from secest.core import lmi as slmi

    if not isinstance(model, Model):
        raise ValidationError(f"model must be a Model, found {type(model).__name__}")
    th = _theta(theta)
    n_nodes, nx, ny = th.shape[0], dims.nx, dims.ny
    Y = np.asarray(y, float)
    if Y.ndim != 3 or Y.shape[0] < 2 or Y.shape[1:] != (n_nodes, ny):
        raise ValidationError(f"Incompatible dimensions of y: expected (n + 1, {n_nodes}, {ny}) "
                              f"with n >= 1, found {Y.shape}")
    check_callable("received", received)
    check_probability("p", p, open_interval=True)
    check_choice("varpi_form", varpi_form, VARPI_FORMS)
    check_choice("design", design, DESIGNS)
    if design == "op3" and B_fixed is None:
        raise ValidationError("B_fixed is required with design='op3'")
    n = Y.shape[0] - 1
    sp, op1 = step_problems(th, dims, nn=nn, alpha_bar=alpha_bar, e1=e1, e3=e3, eps=eps,
                            shared=shared, r_bound=r_bound, design=design, lam2_box=lam2_box,
                            cache=cache)
    Ls, As = as_matrix("L", L, (nx, nx)), as_matrix("aleph", aleph, (ny, nx))
    for i in range(n_nodes):
        sp.params["L"][i].value, sp.params["aleph"][i].value = Ls, As
    sp.params["Vinv"].value = as_matrix("V_inv", V_inv, (dims.nv, dims.nv))
    sp.params["Uinv"].value = as_matrix("U_inv", U_inv, (dims.nu, dims.nu))
    B_seq = None
    if design == "op3":
        B_arr = np.asarray(B_fixed, float)
        if B_arr.ndim == 3:
            B_seq = _shaped("B_fixed", B_arr, (n + 1, nx, nx))
            for b_k in B_seq:
                as_matrix("B_fixed", 0.5 * (b_k + b_k.T), (nx, nx))
            B_seq = 0.5 * (B_seq + B_seq.transpose(0, 2, 1))
        else:
            sp.params["Bell"].value = as_matrix("B_fixed", B_fixed, (nx, nx))
    lk_all = links(th)
    run = Algorithm1Run(
        lk_all, np.zeros((n + 1, n_nodes, nx)), np.zeros((n + 1, nx, nx)), np.zeros(0),
        np.full(n + 1, np.nan), np.zeros((n, nx, nx)), np.zeros((n, n_nodes, ny)),
        np.zeros((n, n_nodes, ny)), np.zeros((n, n_nodes, dims.nphi)),
        lam=np.zeros((n, len(lk_all), 2)), solved=np.zeros(n, dtype=bool))
    run.xh[0] = _shaped("xhat0", xhat0, (n_nodes, nx))
    run.P[0] = as_matrix("P0", P0, (nx, nx))
    run.W_hat.append({lk: as_matrix("W0", W0, (ny, dims.nphi)).copy() for lk in lk_all})
    run.Q.append({lk: as_matrix("Q0", Q0, (ny, ny)).copy() for lk in lk_all})
    gains = ([np.zeros((nx, nx)) for _ in range(n_nodes)], [np.zeros((nx, ny)) for _ in range(n_nodes)],
             {lk: np.zeros((nx, ny)) for lk in lk_all})
    label = f"joint SDP over nodes 1-{n_nodes} ({design.upper()}, {'nn' if nn else 'conv'})"
    for k in range(n):
        if B_seq is not None:
            sp.params["Bell"].value = B_seq[k + 1]  # OP3 at step k fixes B_(k+1)
        gains = _design_step(run, k, model, Y, received, sp, gains, th, dims, nn, alpha_bar,
                             label, solver, fallback, tol, eps, keep_rows, slmi)
        if nn:
            _weight_step(run, k, model, Y, op1, th, dims, alpha_bar, varpi_form, solver,
                         fallback, tol, eps, slmi)
        else:
            run.W_hat.append(run.W_hat[-1])
            run.Q.append(run.Q[-1])
    run.Bell = (run.P / (1.0 - p) if design == "op2" else B_seq.copy() if B_seq is not None
                else np.broadcast_to(np.asarray(B_fixed, float), run.P.shape).copy())
    run.Bell[0] = run.P[0] / (1.0 - p)  # B_0 = P_0 / (1 - p) (Lemma 4, corrected)
    return run


def _design_step(run: Algorithm1Run, k: int, model: Model, Y: Array, received: Callable,
                 sp: StepProblem, gains: tuple, th: Array, dims: Dims, nn: bool, alpha_bar: float,
                 label: str, solver: str, fallback: str | None, tol: float, eps: float,
                 keep_rows: bool, slmi: Any) -> tuple:
    """Steps 1-4 of Algorithm 1 at step ``k``: innovations, OP2/OP3 (30), the update (8)/(3)."""
    n_nodes = th.shape[0]
    xh_k, P = run.xh[k], run.P[k]
    W_hat, Q = run.W_hat[k], run.Q[k]
    S = np.linalg.cholesky(covariance.symmetrize(P))  # P_k = S_k S_k^T
    z = np.array([Y[k, i] - model.g(i, xh_k[i]) for i in range(n_nodes)])  # z_{i,k}
    z_recv = np.asarray(received(k, z), float)  # (5)
    ph = model.phi(z)
    Mbar = {lk: mbar(Q[lk], dims.nphi) for lk in run.links}
    set_op2_parameters(sp, S=S, xhat=xh_k, fhat=[model.f(xh_k[i]) for i in range(n_nodes)],
                       Phi=[model.jac_f(xh_k[i]) for i in range(n_nodes)],
                       Psi=[model.jac_g(i, xh_k[i]) for i in range(n_nodes)],
                       E=[model.E(i, k) for i in range(n_nodes)], B=model.B(k),
                       W_hat=W_hat if nn else None, phi=ph if nn else None,
                       Mbar=Mbar if nn else None)
    try:  # one SDP over all nodes, coupled through P_{k+1}: a failure names no single node
        run.reports.append(solve(sp, k, label, eps=eps, tol=tol, solver=solver, fallback=fallback))
        gains = ([v.value.copy() for v in sp.vars["F"]], [v.value.copy() for v in sp.vars["G"]],
                 {lk: sp.vars["H"][lk].value.copy() for lk in run.links})
        P_next = covariance.symmetrize(np.asarray(sp.vars["P"].value))
        if "rho" in sp.vars:
            run.rho[k + 1] = float(sp.vars["rho"].value)
        run.solved[k] = True
        if keep_rows:
            run.rows.append([(Xi.value, None if Xit is None else Xit.value)
                             for Xi, Xit in (sp.rows[i] for i in range(n_nodes))])
    except slmi.InfeasibleLMIError as err:  # keep the previous gains, double P (brief §7)
        run.failures.append(str(err))
        run.failure_outcomes.append(dict(err.outcomes))
        P_next = 2.0 * P
        if keep_rows:
            run.rows.append(None)
    F, G, H = gains
    run.xh[k + 1] = update_all(F, G, H, xh_k, z, z_recv, th, W_hat=W_hat if nn else None,
                               phi_own=ph, alpha_bar=alpha_bar)  # (8) / (3)
    run.P[k + 1] = P_next
    run.S[k], run.z[k], run.z_recv[k], run.phi[k] = S, z, z_recv, ph
    run.F.append(F)
    run.G.append(G)
    run.H.append(H)
    run.Mbar.append(Mbar)
    return gains


def _weight_step(run: Algorithm1Run, k: int, model: Model, Y: Array, op1: StepProblem,
                 th: Array, dims: Dims, alpha_bar: float, varpi_form: str, solver: str,
                 fallback: str | None, tol: float, eps: float, slmi: Any) -> None:
    """Steps 5-7 of Algorithm 1 at step ``k``: varpi of (17), OP1 (31), the tuning law (17)."""
    n_nodes = th.shape[0]
    xh1 = run.xh[k + 1]
    z1 = np.array([Y[k + 1, i] - model.g(i, xh1[i]) for i in range(n_nodes)])  # z_{i,k+1}
    vp = varpi(run.H[k], [model.jac_g(i, xh1[i]) for i in range(n_nodes)], z1, th, alpha_bar,
               varpi_form)
    set_op1_parameters(op1, vp, run.phi[k], run.Mbar[k])
    W_hat, Q = run.W_hat[k], run.Q[k]
    try:
        run.reports.append(solve(op1, k, "all links (OP1)", chordal=False, eps=eps, tol=tol,
                                 solver=solver, fallback=fallback))
        W_new, Q_new = {}, {}
        for a, lk in enumerate(run.links):
            l1, l2 = float(op1.vars[lk]["l1"].value), float(op1.vars[lk]["l2"].value)
            W_new[lk] = weight_update(W_hat[lk], l1, l2, vp[lk], run.phi[k][lk[0]])  # (17)
            Q_new[lk] = covariance.symmetrize(op1.vars[lk]["Q"].value)
            run.lam[k, a] = (l1, l2)
        W_hat, Q = W_new, Q_new
    except slmi.InfeasibleLMIError as err:  # keep W^ and Q
        run.failures.append(str(err))
        run.failure_outcomes.append(dict(err.outcomes))
    run.W_hat.append(W_hat)
    run.Q.append(Q)


def update_all(F: list, G: list, H: Mapping[tuple[int, int], ArrayLike], xhat: ArrayLike,
               z: ArrayLike, z_recv: ArrayLike, theta: ArrayLike, *,
               W_hat: Mapping[tuple[int, int], ArrayLike] | None = None,
               phi_own: ArrayLike | None = None, alpha_bar: float = 0.0) -> Array:
    """(8) or (3) for every node from per-node gains and per-link dicts (:func:`estimator_update`).

    Parameters
    ----------
    F, G : sequences of N arrays
        ``F_{i,k}``, ``G_{i,k}``.
    H : mapping link -> (n, n_y) array
        ``H_{ij,k}``.
    xhat : (N, n) array_like
        ``x^_{i,k}``.
    z : (N, n_y) array_like
        Own innovations.
    z_recv : (N, n_y) array_like
        The innovation every node ``j`` sent, as it arrives (the same at every receiver).
    theta : (N, N) array_like
        Graph weights.
    W_hat : mapping link -> (n_y, n_phi) array, optional
        ``W^_{ij,k}`` of (8); None gives (3).
    phi_own : (N, n_phi) array_like, optional
        ``phi(z_{i,k})``.
    alpha_bar : float, default 0
        ``Prob{alpha_k = 1}``.

    Returns
    -------
    (N, n) ndarray
    """
    th = np.asarray(theta, float)
    N = th.shape[0]
    F_a, G_a = np.stack(F), np.stack(G)
    n, ny = G_a.shape[1:]
    H_a = np.zeros((N, N, n, ny))
    for lk, Hij in H.items():
        H_a[lk] = Hij
    W_a = None
    if W_hat is not None:
        W_a = np.zeros((N, N, *np.shape(next(iter(W_hat.values())))))
        for lk, Wij in W_hat.items():
            W_a[lk] = Wij
    recv = np.broadcast_to(np.asarray(z_recv, float)[None], (N, N, ny))
    return estimator_update(F_a, G_a, H_a, xhat, z, recv, th, W_hat=W_a, phi_own=phi_own,
                            alpha_bar=alpha_bar)


# ------------------------------------------------------------------ the linear reading (arena)


@dataclass
class LinearDesign:
    """The recursion of OP2 on a linear plant with ``F_i = A``, ``H = 0``, ``W^ = 0``.

    Attributes
    ----------
    G : (K, N, n, n_y) ndarray
        ``G_{i,k}`` of every node and step (NaN from a failed step on).
    P : (K + 1, n, n) ndarray
        ``P_k`` (``P_0`` given; NaN from a failed step on); ``B_k = P_k / (1 - p)``.
    types : list of int
        One node per distinct ``(C_i, R_i)``: the LMIs imposed.
    failure : str or None
        The message of the first step no solver certified.
    worst_eig : float
        Largest eigenvalue over every certified LMI matrix (in the normalised units).
    fallbacks : int
        Steps solved by the fallback solver.
    held_from : int or None
        First step whose gains are held from the settled recursion (``hold_rtol``), else None.
    """

    G: Array
    P: Array
    types: list[int]
    failure: str | None = None
    worst_eig: float = float("-inf")
    fallbacks: int = 0
    held_from: int | None = None


HOLD_STEPS = 10
"""Consecutive settled steps after which :func:`linear_design` holds its gains (``hold_rtol``)."""


def _node_types(C: Array, U_half: Array) -> tuple[list[int], Array]:
    """First node of every distinct ``(C_i, U_i)`` and the type index of every node."""
    first: dict[bytes, int] = {}
    kind = np.empty(C.shape[0], dtype=np.intp)
    for i in range(C.shape[0]):
        key = C[i].tobytes() + U_half[i].tobytes()
        kind[i] = first.setdefault(key, len(first))
    types = [int(np.flatnonzero(kind == t)[0]) for t in range(len(first))]
    return types, kind


def _linear_op2(A: Array, C: Array, U_half: Array, types: list[int]) -> StepProblem:
    """OP2 with ``F = A``, ``H = 0``, ``L = aleph = 0``, ``W^ = 0``, normalised by ``S_k``.

    Node ``i`` (one per type): ``zeta_i = [1; s_i; v'; mu_i']`` with unit-ball blocks,
    ``Gamma_i = diag(gamma_i, b1 I, b2 I, b3 I)``, ``gamma_i = 1 - b1 - b2 - b3`` and
    ``Xi_i = [0, S^-1 A S - G~_i C_i S, S^-1 V^1/2, -G~_i U_i^1/2]``, ``G~_i = S^-1 G_i``; the LMI
    ``[[-Gamma_i, *], [Xi_i, -P~]] <= -eps I``; objective
    ``tr(S^T S P~) / tr P_k = tr P_{k+1} / tr P_k``.
    """
    import cvxpy as cp

    from secest.core import lmi as slmi

    n, ny = A.shape[0], C.shape[1]
    par = {"SAS": cp.Parameter((n, n), name="SAS"), "SV": cp.Parameter((n, n), name="SV"),
           "W": cp.Parameter((n, n), PSD=True, name="W"),
           "CS": {i: cp.Parameter((ny, n), name=f"CS{i}") for i in types}}
    Pt = cp.Variable((n, n), symmetric=True, name="Ptilde")
    G = {i: cp.Variable((n, ny), name=f"Gtilde{i}") for i in types}
    cons, lmis = [], {}
    for i in types:
        b = cp.Variable(3, nonneg=True, name=f"b{i}")
        Gam = slmi.block_diag([cp.reshape(1 - cp.sum(b), (1, 1), order="F"), b[0] * np.eye(n),
                               b[1] * np.eye(n), b[2] * np.eye(ny)])
        Xi = cp.hstack([np.zeros((n, 1)), par["SAS"] - G[i] @ par["CS"][i], par["SV"],
                        -G[i] @ U_half[i]])
        Mi = slmi.block_symmetric([[-Gam], [Xi, -Pt]])  # (30)
        lmis[f"node {i + 1}"] = Mi
        cons.append(slmi.lmi(Mi, EPS_LMI))
    prob = cp.Problem(cp.Minimize(cp.trace(par["W"] @ Pt)), cons)
    return StepProblem(prob, par, {"P": Pt, "G": G}, lmis)


def linear_design(A: ArrayLike, C: ArrayLike, V_half: ArrayLike, U_half: ArrayLike, P0: ArrayLike,
                  steps: int, *, hold_rtol: float | None = None) -> LinearDesign:
    """OP2 (32) on a linear plant, ``F_i = A``, ``H = 0``, ``W^ = 0``: the gains ``G_{i,k}``, ``P_k``.

    Each step solves ``min tr P_{k+1}`` subject to LMI (30) of every distinct node (see
    :func:`_linear_op2` for the normalisation), then ``G_i = S_k G~_i``,
    ``P_{k+1} = S_k P~ S_k^T`` (symmetrised). The recursion stops at the first step no solver
    certifies (:attr:`LinearDesign.failure`). With ``hold_rtol`` (ours, for long horizons) it
    also stops once the recursion is at its steady state, ``||P_{k+1} - P_k||_F <= hold_rtol
    ||P_k||_F`` on :data:`HOLD_STEPS` consecutive steps, and holds the last gains and ``P``
    for the remaining steps.

    Parameters
    ----------
    A : (n, n) array_like
        Sampled dynamics.
    C : (N, n_y, n) array_like
        Measurement matrices.
    V_half : (n, n) array_like
        ``B V^1/2`` of the process noise (``B = I`` on the arena).
    U_half : (N, n_y, n_y) array_like
        ``E_i U_i^1/2`` of node ``i``'s measurement noise.
    P0 : (n, n) array_like
        ``P_0``, positive definite (Assumption 3).
    steps : int
        Number of steps ``K``.
    hold_rtol : float, optional
        Relative change of ``P_k`` below which the recursion counts as settled (None: solve
        every step).

    Returns
    -------
    LinearDesign
    """
    from secest.core import lmi as slmi

    A = as_matrix("A", A, square=True)
    n = A.shape[0]
    C = np.asarray(C, float)
    if C.ndim != 3 or C.shape[2] != n:
        raise ValidationError(f"Incompatible dimensions of C: expected (N, ny, {n}), found {C.shape}")
    U_half = np.asarray(U_half, float)
    if U_half.shape != (C.shape[0], C.shape[1], C.shape[1]):
        raise ValidationError(f"Incompatible dimensions of U_half: expected "
                              f"{(C.shape[0], C.shape[1], C.shape[1])}, found {U_half.shape}")
    V_half = as_matrix("V_half", V_half, (n, None))
    steps = check_positive_int("steps", steps)
    P = np.full((steps + 1, n, n), np.nan)
    P[0] = covariance.symmetrize(as_matrix("P0", P0, (n, n)))
    types, kind = _node_types(C, U_half)
    sp = _linear_op2(A, C, U_half, types)
    out = LinearDesign(np.full((steps, C.shape[0], n, C.shape[1]), np.nan), P, types)
    settled = 0
    for k in range(steps):
        S = np.linalg.cholesky(P[k])
        Si = np.linalg.inv(S)
        sp.params["SAS"].value = Si @ A @ S
        sp.params["SV"].value = Si @ V_half
        sp.params["W"].value = covariance.symmetrize(S.T @ S) / np.trace(P[k])
        for i in types:
            sp.params["CS"][i].value = C[i] @ S
        try:
            rep = solve(sp, k, f"nodes {[i + 1 for i in types]}")
        except slmi.LMISolveError as err:
            out.failure = str(err)
            break
        out.worst_eig = max(out.worst_eig, rep.worst_eig)
        out.fallbacks += int(rep.fallback)
        P[k + 1] = covariance.symmetrize(S @ sp.vars["P"].value @ S.T)
        gains = np.stack([S @ sp.vars["G"][i].value for i in types])
        out.G[k] = gains[kind]
        settled = settled + 1 if hold_rtol is not None and (
            np.linalg.norm(P[k + 1] - P[k]) <= hold_rtol * np.linalg.norm(P[k])) else 0
        if settled >= HOLD_STEPS:
            out.G[k + 1:], P[k + 2:] = out.G[k], P[k + 1]
            out.held_from = k + 1
            break
    return out
