"""li2025 in the arena: secure recursive estimation under Bernoulli replacement attacks.

Li, Wei, Liu, Xie, Tian (2025): each subsystem's estimator predicts with its upstream
neighbours' estimates (7), corrects with the scheduled, possibly replaced, measurement
entries (8), and chooses the gain (28) that minimises the trace of an upper bound of its
error covariance, propagated by (17)-(18). The functions below are the li2025 notebook's
equations, with its corrections (ERRATA.md): the bound coefficients re-derived from
the paper's own proof (``variant="corrected"``; ``"paper"`` keeps Theorem 2's printed ones),
the ``|K_i|`` factor of the coupling term of (17), and (28) solved on the scheduled rows.

Reading on a shared scenario (:class:`Li2025`, rules fixed before any arena run):

* **Structure**: one plant, so there is no sequential coupling: every node runs the paper's
  estimator of a subsystem without upstream neighbours (``K_i`` empty, no estimate is
  exchanged). A regular plant is an SPDSS with no fast part (``n_f = 0``, ``H_eps = I``).
* **Packets**: node ``i``'s sensors are its own and its neighbours' (closed neighbourhood),
  whose raw measurements reach it over the links: the paper's sensor-to-estimator packets.
  The arena has no bandwidth limit, so RRL-MAP is read with ``m = n_y`` (every packet every
  step); a lost packet (link down) is not used, as the zero-input rule (3) treats an
  unscheduled one.
* **Attack model** (6): packets of the sensors the replacement card attacks are replaced
  with probability ``1 - psi_check``; the paper takes ``psi_check`` and ``xi*`` as known,
  so they are read from the card (``psi_check = 1 - prob``, ``xi* = sum over rows of
  (magnitude r_std)^2``, the largest energy of the uniform replacement); every other packet
  has ``psi_check = 1``. The paper's ``psi`` is one Bernoulli variable per packet, so each
  attacked sensor is its own packet; node ``i`` processes its clean packets first (one update,
  equal to sequential ones since ``psi_check = 1`` is the Kalman update), then each attacked
  packet, each step an instance of the paper's update (8), (18), (28).
* **Design parameters**: ``(lambda, alpha_1..alpha_4) = (1e-3, 1, 1e-2, 0.1, 0.1)``, the
  Remark-4 grid optimum of the li2025 notebook for the paper's target 1, whose attack
  probability 0.3 is the replacement card's; corrected coefficients; ``E{x_hat x_hat^T}``
  replaced by the run's own ``x_hat x_hat^T`` (the notebook's default); ``x_hat(0|0) = 0``,
  ``S(0|0)`` the prior covariance, first update at ``k = 1`` (Algorithm 1).

A sensor bias and falsified messages are not replacements of a bounded value (the replaced
value would have to follow the state): the method answers "not applicable" there.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from secest.core.validation import ValidationError, check_int

__all__ = [
    "COEFFICIENTS",
    "EXAMPLE_B",
    "EXAMPLE_C",
    "EXAMPLE_PARENTS",
    "EXAMPLE_X0",
    "THEOREM3_CONSTANTS",
    "UPDATES",
    "VARIANTS",
    "bound_coefficients",
    "bound_for_gain",
    "correct",
    "estimate",
    "exact_design_moments",
    "gain_and_bound",
    "predict",
    "predicted_bound",
    "turn_model",
    "sym",
    "theorem2_check",
    "theorem3_c_floor",
    "theorem3_candidates",
    "theorem3_proof_envelope",
    "theorem3_eta",
]

Array = NDArray[np.float64]
Coefficients = tuple[Any, Any, Any, Any]

VARIANTS = ("corrected", "paper")
"""Bound coefficients of the replacement attack (6): re-derived from the paper's proof, or as
printed in Theorem 2 (the arena's choices)."""
COEFFICIENTS = (*VARIANTS, "additive")
"""Every reading of :func:`bound_coefficients`: also ``"additive"``, re-derived for the additive
reading of (6) (the notebook's sensitivity row of C7)."""
UPDATES = ("zero", "zoh", "debiased", "open_loop")
"""Measurement updates of :func:`estimate` (the last two are the notebook's, not the paper's; the
notebook runs them in its exact-moment recursion only, ``exact_moments``)."""


# ------------------------------------------------------------------ the example of Section IV
EXAMPLE_PARENTS = {0: (), 1: (0,), 2: (0, 1)}
"""``K_i`` of Section IV, 0-based: target 2 is driven by 1, target 3 by 1 and 2."""
EXAMPLE_C = np.array([[1, 0, 0, 0], [0, 0, 1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], float)
"""``C_i`` of Section IV (the same for every target): sensors of X^p, Y^p, X^v, Y^v."""
EXAMPLE_B = {(1, 0): np.diag([0, 0.05, 0, 0.02]), (2, 0): np.diag([0, 0.06, 0, 0.07]),
             (2, 1): np.diag([0, 0.05, 0, 0.09])}
"""``B_{i,j}`` of Section IV, keyed by 0-based ``(i, j)``, ``j in K_i``."""
EXAMPLE_X0 = np.array([[0, 1, 0, 1], [2, 1, 2, 1], [2, 2, 2, 2]], float)
"""Offsets of the initial states of Section IV (a uniform [0, 1) draw is added per component)."""


def turn_model(horizon: int) -> tuple[Array, Array]:
    """``A_i(k)`` and ``E_i(k)``, ``k = 0..horizon``, of Section IV's turning targets.

    ``T_k = 0.8 tanh k`` and ``r_k = 0.1 + 0.3 tanh k``; the same for every target.

    Parameters
    ----------
    horizon : int
        Last step ``T`` (>= 0).

    Returns
    -------
    A : (horizon + 1, 4, 4) array
    E : (horizon + 1, 4) array
    """
    k = np.arange(check_int("horizon", horizon, minimum=0) + 1)
    tk, rk = 0.8 * np.tanh(k), 0.1 + 0.3 * np.tanh(k)
    s, c = np.sin(rk * tk), np.cos(rk * tk)
    a = np.zeros((k.size, 4, 4))
    a[:, 0, 0] = a[:, 2, 2] = 1.0
    a[:, 0, 1] = a[:, 2, 3] = s / rk
    a[:, 0, 3] = -(1 - c) / rk
    a[:, 2, 1] = (1 - c) / rk
    a[:, 1, 1] = a[:, 3, 3] = c
    a[:, 1, 3] = -s
    a[:, 3, 1] = s
    return a, np.stack([tk**2 / 2, tk, tk**2 / 2, tk], axis=1)


def _t(M: Array) -> Array:
    """Transpose of the last two axes."""
    return np.swapaxes(M, -1, -2)


def sym(a: Array) -> Array:
    """Symmetric part over the last two axes.

    Parameters
    ----------
    a : (..., n, n) array
        A stack of square matrices.

    Returns
    -------
    (..., n, n) array
        ``(a + a^T) / 2``.
    """
    return 0.5 * (a + _t(a))


def bound_coefficients(
    psi_bar: ArrayLike, a2: ArrayLike, a3: ArrayLike, a4: ArrayLike, variant: str = "corrected"
) -> Coefficients:
    """``(c0, kappa_x, kappa_xi, kappa_v)`` of the bound (18) and the gain (28).

    ``c0`` multiplies ``M S(k|k-1) M^T`` and ``Psi``, ``kappa_x`` the state terms, ``kappa_xi``
    the attack-energy term ``xi* L Phi Phi^T L^T`` and ``kappa_v`` the noise term
    ``L Phi V Phi^T L^T``.

    Parameters
    ----------
    psi_bar : float or array
        ``psi_check``, the probability that a packet is **not** replaced (6).
    a2, a3, a4 : float or array
        Lemma 1 weights of the ``e/xi`` (25), ``e/x`` (26) and ``x/xi`` (27) cross terms.
    variant : {"corrected", "paper", "additive"}
        ``"corrected"`` (re-derived from (12) with Lemma 1; the li2025 notebook):
        ``c0 = 1 + (a2 + a3)(1 - psi)``, ``kappa_x = (1 - psi)(1 + 1/a3 + a4)``;
        ``"paper"`` (Theorem 2 as printed): ``c0 = 1 - (a3 - a2)(1 - psi)``,
        ``kappa_x = psi + 1/a3 + a4 - 1``. Both: ``kappa_xi = (1 - psi)(1 + 1/a2 + 1/a4)``,
        ``kappa_v = psi``. ``"additive"`` (re-derived for ``y = y_bar + (1 - psi) Phi xi``, not
        the paper's reading): ``c0 = 1 + a2 (1 - psi)``, ``kappa_x = 0``,
        ``kappa_xi = (1 - psi)(1 + 1/a2)``, ``kappa_v = 1``.

    Returns
    -------
    c0, kappa_x, kappa_xi, kappa_v
        Floats or arrays, broadcast from the arguments.

    Raises
    ------
    ValidationError
        Unknown ``variant``.
    """
    p = 1 - psi_bar
    if variant == "corrected":
        return 1 + (a2 + a3) * p, p * (1 + 1 / a3 + a4), p * (1 + 1 / a2 + 1 / a4), psi_bar  # (18)
    if variant == "paper":
        return 1 - (a3 - a2) * p, psi_bar + 1 / a3 + a4 - 1, p * (1 + 1 / a2 + 1 / a4), psi_bar  # Thm 2
    if variant == "additive":
        return 1 + a2 * p, 0 * p, p * (1 + 1 / a2), 1 + 0 * p
    raise ValidationError(f"variant must be one of {COEFFICIENTS}, found {variant!r}")


def predicted_bound(
    S_own: Array,
    S_parents: Sequence[Array],
    ah: Array,
    bh_list: Sequence[Array],
    lam: ArrayLike,
    ewe: Array,
    k_factor: bool = True,
) -> Array:
    """Predicted bound (17), corrected: ``S(k|k-1)``, batched over the leading axes.

    .. math::  \\mathfrak S_i(k|k-1) = (1+\\lambda) A H \\mathfrak S_i A^T H^T
               + (1+\\lambda^{-1}) |K_i| \\sum_{j\\in K_i} B_{i,j} H \\mathfrak S_j H^T B_{i,j}^T
               + E W E^T

    Parameters
    ----------
    S_own : (..., n, n) array
        ``S_i(k-1|k-1)``.
    S_parents : sequence of (..., n, n) arrays
        ``S_j(k-1|k-1)`` of the upstream subsystems ``j in K_i``, paired with ``bh_list``.
    ah : (n, n) array
        ``A_i(k-1) H_eps``.
    bh_list : sequence of (n, n) arrays
        ``B_{i,j}(k-1) H_eps``.
    lam : float or array
        Lemma 1 weight ``lambda`` of the cross terms with the upstream errors (unused, and may be
        0, without upstream subsystems).
    ewe : (n, n) array
        ``E_i(k-1) W_i E_i^T(k-1)``.
    k_factor : bool, default True
        Multiply the coupling term by ``|K_i|`` (needed for a bound when ``|K_i| >= 2``; the
        printed (17) has no factor and an undefined product).

    Returns
    -------
    (..., n, n) array
        ``S_i(k|k-1)``, symmetrised.

    Raises
    ------
    ValidationError
        ``S_parents`` and ``bh_list`` of different lengths.
    """
    if len(S_parents) != len(bh_list):
        raise ValidationError(
            f"S_parents and bh_list must pair up: found {len(S_parents)} and {len(bh_list)} entries")
    s = (1 + lam) * (ah @ S_own @ ah.T) + ewe  # (17): own term and noise
    factor = len(bh_list) if k_factor else 1
    for bh, S_j in zip(bh_list, S_parents, strict=True):
        s = s + (1 + 1 / lam) * factor * (bh @ S_j @ bh.T)  # (17): coupling, times |K_i|
    return sym(s)


def gain_and_bound(
    S_pred: Array,
    X_hat: Array,
    G: Array,
    coefs: Coefficients,
    a1: ArrayLike,
    xi_star: ArrayLike,
    V: ArrayLike,
) -> tuple[Array, Array, Array]:
    """Gain (28) on the received rows and the updated bound (18).

    ``Pi`` of (28) has the rank of ``Phi`` (every term is sandwiched by it), so the gain is
    solved on the received rows ``G = (C H_eps)_{eps(k)}``:
    ``L = c0 S(k|k-1) G^T Pi^-1``, ``Pi = c0 G S G^T + R`` with

    .. math::  R = \\kappa_x(1+\\alpha_1) G S G^T + \\kappa_x(1+\\alpha_1^{-1}) G \\hat X G^T
               + (\\kappa_\\xi \\xi^* + \\kappa_v \\mathcal V) I,

    and ``S(k|k) = c0 M S(k|k-1) M^T + L R L^T``, ``M = I - L G`` (valid for any ``L``). A batch
    member whose ``Pi`` is not finite or exceeds 1e14 (an exploding bound, e.g. a grid
    candidate) gets a NaN gain instead of an error.

    Parameters
    ----------
    S_pred, X_hat : (..., n, n) arrays
        ``S(k|k-1)`` and the surrogate of ``E{x_hat(k|k-1) x_hat^T(k|k-1)}``.
    G : (..., rows, n) array
        Received rows of ``C H_eps``.
    coefs : (c0, kappa_x, kappa_xi, kappa_v)
        :func:`bound_coefficients`: floats or arrays broadcasting as (..., 1, 1).
    a1 : float or array
        Lemma 1 weight of (24).
    xi_star : float or array
        Energy bound of the attack signal, ``||xi||^2 <= xi*``.
    V : float or (..., rows, rows) diagonal array
        Measurement-noise variance (the paper's scalar ``V_i``, or one per row as a diagonal
        matrix: the expression ``(kxi xi* + kv V) * I`` keeps its diagonal).

    Returns
    -------
    L : (..., n, rows)
    S_new : (..., n, n)
        Symmetrised.
    R : (..., rows, rows)

    Raises
    ------
    ValidationError
        ``G`` whose columns do not match ``S_pred``, or ``coefs`` not a 4-tuple.
    """
    _check_bound_inputs(S_pred, G, coefs)
    c0, kx, kxi, kv = coefs
    rows, n = G.shape[-2], G.shape[-1]
    gsg = G @ S_pred @ _t(G)
    eye = np.eye(rows)
    R = (kx * (1 + a1) * gsg + kx * (1 + 1 / a1) * (G @ X_hat @ _t(G))
         + (kxi * xi_star + kv * V) * eye)  # R of (18), (24) and (23) applied
    Pi = sym(c0 * gsg + R)  # Pi of (28)
    bad = ~np.all(np.isfinite(Pi), axis=(-1, -2)) | ~(np.max(np.abs(Pi), axis=(-1, -2)) < 1e14)
    Pi = np.where(bad[..., None, None], eye, Pi)
    L = _t(np.linalg.solve(Pi, c0 * (G @ S_pred)))  # (28): L = Psi Pi^-1, Psi = c0 S G^T
    L[bad] = np.nan
    Mm = np.eye(n) - L @ G
    S_new = c0 * (Mm @ S_pred @ _t(Mm)) + L @ R @ _t(L)  # (18)
    return L, sym(S_new), R


def _check_bound_inputs(S_pred: Array, G: Array, coefs: Coefficients) -> None:
    """Refuse ``G`` whose columns do not match ``S_pred`` and ``coefs`` that are not 4 scalars."""
    if np.shape(G)[-1] != np.shape(S_pred)[-1]:
        raise ValidationError(
            f"G must have one column per state of S_pred: found {np.shape(G)} and {np.shape(S_pred)}")
    if len(coefs) != 4:
        raise ValidationError(
            f"coefs must be (c0, kappa_x, kappa_xi, kappa_v), found {len(coefs)} values")


def bound_for_gain(
    S_pred: Array,
    X_hat: Array,
    G: Array,
    L: Array,
    coefs: Coefficients,
    a1: ArrayLike,
    xi_star: ArrayLike,
    V: ArrayLike,
) -> Array:
    """The bound (18) for an arbitrary gain ``L``, term by term as printed.

    .. math::  \\mathfrak S(k|k) = c_0 M \\mathfrak S(k|k-1) M^T
               + (1+\\alpha_1)\\kappa_x L G \\mathfrak S(k|k-1) G^T L^T
               + (1+\\alpha_1^{-1})\\kappa_x L G \\hat X G^T L^T
               + \\kappa_\\xi L (\\xi^* I) L^T + \\kappa_v L \\mathcal V L^T,
               \\qquad M = I - L G,

    with ``G = (C H_eps)_{eps(k)}`` the received rows (``Phi_o(k)`` applied). Theorem 2 states
    that the gain (28) (:func:`gain_and_bound`) minimises its trace; this function evaluates the
    trace at any other gain, which is how that statement is checked (li2025 notebook, C8).

    Parameters
    ----------
    S_pred, X_hat : (..., n, n) arrays
        ``S(k|k-1)`` and ``E{x_hat(k|k-1) x_hat^T(k|k-1)}`` (or its surrogate).
    G : (..., rows, n) array
        Received rows of ``C H_eps``.
    L : (..., n, rows) array
        The gain at which (18) is evaluated.
    coefs : (c0, kappa_x, kappa_xi, kappa_v)
        :func:`bound_coefficients` (or any other reading of (18)'s scalars).
    a1 : float or array
        Lemma 1 weight of (24).
    xi_star : float or array
        Energy bound of the attack signal.
    V : float or (..., rows, rows) diagonal array
        Measurement-noise variance, as in :func:`gain_and_bound`.

    Returns
    -------
    (..., n, n) array
        ``S(k|k)`` of (18) at ``L``, symmetrised.

    Raises
    ------
    ValidationError
        Shapes of ``G`` and ``L`` that do not match ``S_pred``, or ``coefs`` not a 4-tuple.
    """
    rows_n = np.shape(G)[-1:] + np.shape(G)[-2:-1]  # (n, rows): the shape L must end with
    if np.shape(G)[-1] == np.shape(S_pred)[-1] and np.shape(L)[-2:] != rows_n:
        raise ValidationError(
            f"G (rows, n) and L (n, rows) must match S_pred (n, n): found {np.shape(G)}, "
            f"{np.shape(L)} and {np.shape(S_pred)}")
    _check_bound_inputs(S_pred, G, coefs)
    c0, kx, kxi, kv = coefs
    rows, n = G.shape[-2], G.shape[-1]
    Mm = np.eye(n) - L @ G
    LG = L @ G
    s = c0 * (Mm @ S_pred @ _t(Mm))  # (18): first term
    s = s + (1 + a1) * kx * (LG @ S_pred @ _t(LG))  # (18): (1 + a1) kappa_x L G S G^T L^T
    s = s + (1 + 1 / a1) * kx * (LG @ X_hat @ _t(LG))  # (18): (1 + 1/a1) kappa_x L G Xhat G^T L^T
    s = s + L @ ((kxi * xi_star + kv * V) * np.eye(rows)) @ _t(L)  # (18): attack energy and noise
    return sym(s)


# ------------------------------------------------------------------ Theorem 3, as printed
THEOREM3_CONSTANTS = ("a_lo2", "a_hi2", "h_lo", "h_hi", "c_lo2", "c_hi2", "e_lo2", "e_hi2",
                      "b_lo2", "b_hi2", "q_lo", "q_hi", "r_lo", "r_hi", "wp", "x2", "xi_star")
"""Keys of the ``const`` mapping of :func:`theorem3_eta`: Assumption 1's bounds (squares where
the paper squares them: ``a_lo2`` is ``a_*^2``), ``wp`` the ``\\wp_i`` of Theorem 3, ``x2``
``(X^*)^2`` and ``xi_star`` the attack-energy bound ``xi_i^*``."""


def theorem3_eta(
    phi_lo: ArrayLike,
    phi_hi: ArrayLike,
    psi_bar: float,
    weights: Sequence[ArrayLike],
    const: Mapping[str, float],
    variant: str = "paper",
) -> dict[str, Array]:
    """``eta_*``, ``eta^*`` of Theorem 3 and the constants they are built from, as printed.

    With ``c0``, ``kappa_x`` of :func:`bound_coefficients` (the printed ones for
    ``variant="paper"``: Theorem 3 writes ``1 - (a3 - a2)(1 - psi)`` and ``psi + 1/a3 + a4 - 1``)
    and ``tail = (1 + 1/a2 + 1/a4)(1 - psi)``:

    .. math::
       \\varpi_* &= (1+\\lambda)(h_*a_*)^2\\phi_* + (1+\\lambda^{-1})(h_*b_*)^2\\phi_* + e_*^2q_*,\\quad
       \\varpi^* \\text{ alike with upper constants},\\\\
       \\pi_* &= (c_0+(1+\\alpha_1)\\kappa_x)c_*^2\\varpi_* + \\mathrm{tail}\\,\\xi^*
               + \\check\\psi r_*,\\\\
       \\pi^* &= (c_0+(1+\\alpha_1)\\kappa_x+\\kappa_x(1+\\alpha_1^{-1})^2)(c^*)^2\\varpi^*
               + \\kappa_x(1+\\alpha_1^{-1})(1+\\alpha_1)(X^*)^2(c^*)^2
               + \\mathrm{tail}\\,\\xi^* + \\check\\psi r^*,\\\\
       \\Gamma_* &= c_0\\varpi_*\\wp_i/\\pi^*,\\quad \\Gamma^* = c_0\\varpi^*(h^*c^*)^2/\\pi_*,\\\\
       \\eta_* &= c_0\\varpi_*(1-\\Gamma^*)^2 + (1+\\alpha_1)\\kappa_x\\varpi_*\\Gamma_*^2
               + (\\mathrm{tail}+\\check\\psi r_*)\\Gamma_*^2,\\\\
       \\eta^* &= c_0\\varpi^*(1-\\Gamma^*)^2 + (1+\\alpha_1)\\kappa_x\\varpi^*(\\Gamma^*)^2
               + (1+\\alpha_1^{-1})\\kappa_x((1+\\alpha_1)(X^*)^2
               +(1+\\alpha_1^{-1})\\varpi^*)(\\Gamma^*)^2
               + (\\mathrm{tail}+\\check\\psi r^*)(\\Gamma^*)^2

    ("tr" in the printed ``Gamma^*`` is read as the scalar itself). Theorem 3's conditions are
    (a) ``1 + a5 + a6 <= c0`` for some positive ``a5, a6`` (``c0 > 1``), (b) ``eta_* >= phi_*``,
    (c) ``eta^* <= phi^*``; the proof inverts (35), ``pi_* I <= Pi <= pi^* I``, which needs
    ``pi_* > 0``.

    Parameters
    ----------
    phi_lo, phi_hi : float or array
        ``phi_*`` and ``phi^*`` (broadcast with each other and with the weights).
    psi_bar : float
        ``psi_check_i``, the probability of no attack.
    weights : sequence of 5 floats or arrays
        ``(lambda, alpha_1, alpha_2, alpha_3, alpha_4)``, positive.
    const : mapping
        The constants named in :data:`THEOREM3_CONSTANTS`.
    variant : {"paper", "corrected"}
        Coefficients substituted for ``c0`` and ``kappa_x``.

    Returns
    -------
    dict
        ``c0``, ``kappa_x``, ``varpi_lo``, ``varpi_hi``, ``pi_lo``, ``pi_hi``, ``gamma_lo``,
        ``gamma_hi``, ``eta_lo``, ``eta_hi`` (arrays, broadcast).

    Raises
    ------
    ValidationError
        Missing constants, or not five positive weights.
    """
    missing = [name for name in THEOREM3_CONSTANTS if name not in const]
    if missing:
        raise ValidationError(f"const: missing Theorem 3 constants {missing}")
    if len(weights) != 5 or not all(np.all(np.asarray(w) > 0) for w in weights):
        raise ValidationError("weights must be 5 positive (lambda, alpha1..alpha4) values or arrays")
    lam, a1, a2, a3, a4 = (np.asarray(w, float) for w in weights)
    k = {name: float(const[name]) for name in THEOREM3_CONSTANTS}
    c0, kx, *_ = bound_coefficients(psi_bar, a2, a3, a4, variant)
    tail = (1 + 1 / a2 + 1 / a4) * (1 - psi_bar)  # printed factor of xi^* and of Gamma^2
    varpi_lo = ((1 + lam) * k["h_lo"] ** 2 * k["a_lo2"]
                + (1 + 1 / lam) * k["h_lo"] ** 2 * k["b_lo2"]) * phi_lo + k["e_lo2"] * k["q_lo"]
    varpi_hi = ((1 + lam) * k["h_hi"] ** 2 * k["a_hi2"]
                + (1 + 1 / lam) * k["h_hi"] ** 2 * k["b_hi2"]) * phi_hi + k["e_hi2"] * k["q_hi"]
    pi_lo = ((c0 + (1 + a1) * kx) * k["c_lo2"] * varpi_lo + tail * k["xi_star"]
             + psi_bar * k["r_lo"])  # (35), lower
    pi_hi = ((c0 + (1 + a1) * kx + kx * (1 + 1 / a1) ** 2) * k["c_hi2"] * varpi_hi
             + kx * (1 + 1 / a1) * (1 + a1) * k["x2"] * k["c_hi2"] + tail * k["xi_star"]
             + psi_bar * k["r_hi"])  # (35), upper
    with np.errstate(divide="ignore", invalid="ignore"):
        gamma_lo = c0 * varpi_lo * k["wp"] / pi_hi  # (36), Gamma_*
        gamma_hi = c0 * varpi_hi * k["h_hi"] ** 2 * k["c_hi2"] / pi_lo  # (36), Gamma^*
    eta_lo = (c0 * varpi_lo * (1 - gamma_hi) ** 2 + (1 + a1) * kx * varpi_lo * gamma_lo ** 2
              + (tail + psi_bar * k["r_lo"]) * gamma_lo ** 2)
    eta_hi = (c0 * varpi_hi * (1 - gamma_hi) ** 2 + (1 + a1) * kx * varpi_hi * gamma_hi ** 2
              + (1 + 1 / a1) * kx * ((1 + a1) * k["x2"] + (1 + 1 / a1) * varpi_hi) * gamma_hi ** 2
              + (tail + psi_bar * k["r_hi"]) * gamma_hi ** 2)
    return {"c0": c0, "kappa_x": kx, "varpi_lo": varpi_lo, "varpi_hi": varpi_hi, "pi_lo": pi_lo,
            "pi_hi": pi_hi, "gamma_lo": gamma_lo, "gamma_hi": gamma_hi, "eta_lo": eta_lo,
            "eta_hi": eta_hi}


def theorem3_c_floor(const: Mapping[str, float]) -> float:
    """A weight-free lower bound of ``eta^* / phi^*`` (ours): ``(1 - 1/(4(1 - rho))) (h^* a^*)^2``.

    Valid for every ``lambda > 0`` and ``alpha_1..alpha_4 > 0`` with ``kappa_x >= 0`` and
    ``c0 >= 1`` (condition (a) needs ``c0 > 1``) and every ``phi_* <= phi^*``, when
    ``e_* = 0``, ``c_* = c^* = h^* = 1``, ``r_* = r^*`` and ``xi^* <= 1`` (the example's
    constants). Proof: with ``A = c0 varpi^*`` and
    ``Q = (1+alpha_1) kappa_x varpi^* + tail + psi r``, every dropped term of
    :func:`theorem3_eta` is >= 0, ``varpi_* <= rho varpi^*`` with ``rho = (h_*/h^*)^2``, so
    ``pi_* <= rho A + Q`` and ``Gamma^* = A / pi_* >= G_0 = A / (rho A + Q)``;
    ``eta^* >= A (1 - G)^2 + Q G^2`` at ``G = Gamma^*``, a convex function of ``G`` whose
    minimiser ``A / (A + Q)`` lies below ``G_0``, so ``eta^* >= A f(u)`` with
    ``u = rho + Q/A`` and ``f(u) = 1 - 1/u + (1 - rho)/u^2 >= 1 - 1/(4(1 - rho))``
    (minimum at ``u = 2(1 - rho)``). Finally ``A >= c0 (1 + lambda)(h^* a^*)^2 phi^*`` and
    ``c0 (1 + lambda) > 1``. If the floor is >= 1, conditions (a) and (c) never hold together
    for such weights.

    Parameters
    ----------
    const : mapping
        The constants of :data:`THEOREM3_CONSTANTS`.

    Returns
    -------
    float
        The floor.

    Raises
    ------
    ValidationError
        If the constants are not of the kind the bound needs (``e_* > 0``, ``c_* != c^*``,
        ``c^* != 1``, ``h^* != 1``, ``r_* != r^*``, ``xi^* > 1``, or ``h_* >= h^*``).
    """
    missing = [name for name in THEOREM3_CONSTANTS if name not in const]
    if missing:
        raise ValidationError(f"const: missing Theorem 3 constants {missing}")
    if not (const["e_lo2"] == 0 and const["c_lo2"] == const["c_hi2"] == 1 and const["h_hi"] == 1
            and const["r_lo"] == const["r_hi"] and const["xi_star"] <= 1
            and 0 < const["h_lo"] < const["h_hi"]):
        raise ValidationError("const: the floor needs e_* = 0, c_* = c^* = h^* = 1, r_* = r^*, "
                              f"xi^* <= 1 and 0 < h_* < 1, found {dict(const)}")
    rho = (const["h_lo"] / const["h_hi"]) ** 2
    return float((1 - 1 / (4 * (1 - rho))) * const["h_hi"] ** 2 * const["a_hi2"])


def predict(xh_own: Array, xh_parents: Sequence[Array], ah: Array, bh_list: Sequence[Array]) -> Array:
    """Prediction (7): ``x_hat_i(k|k-1)``, batched over the leading axes.

    Parameters
    ----------
    xh_own : (..., n) array
        ``x_hat_i(k-1|k-1)``.
    xh_parents : sequence of (..., n) arrays
        ``x_hat_j(k-1|k-1)`` of the upstream subsystems ``j in K_i``, paired with ``bh_list``.
    ah, bh_list : (n, n) arrays
        ``A_i(k-1) H_eps`` and the ``B_{i,j}(k-1) H_eps``.

    Returns
    -------
    (..., n) array

    Raises
    ------
    ValidationError
        ``xh_parents`` and ``bh_list`` of different lengths.
    """
    if len(xh_parents) != len(bh_list):
        raise ValidationError(
            f"xh_parents and bh_list must pair up: found {len(xh_parents)} and {len(bh_list)} entries")
    xp = xh_own @ ah.T  # (7): own term
    for bh, xh_j in zip(bh_list, xh_parents, strict=True):
        xp = xp + xh_j @ bh.T  # (7): upstream estimates
    return xp


def correct(xp: Array, y: Array, G: Array, L: Array, c: ArrayLike = 1.0) -> Array:
    """Update (8): ``x_hat(k|k) = x_hat(k|k-1) + L (y - c G x_hat(k|k-1))``, batched over runs.

    Parameters
    ----------
    xp : (runs, n) array
        ``x_hat_i(k|k-1)``.
    y : (runs, rows) array
        The received rows (``y_{i, eps(k)}(k)``, or the ZOH buffer).
    G : (rows, n) array
        The rows of ``C H_eps`` that ``y`` measures.
    L : (runs, n, rows) array
        The gain.
    c : float, default 1.0
        Weight of the predicted measurement: 1 in (8), ``psi_check`` in the notebook's debiased
        innovation (X1).

    Returns
    -------
    (runs, n) array
    """
    return xp + np.einsum("frc,fc->fr", L, y - c * (xp @ G.T))  # (8)


def _per_target(name: str, value: ArrayLike, N: int) -> Array:
    arr = np.broadcast_to(np.asarray(value, float), (N,))
    if not np.all(np.isfinite(arr)):
        raise ValidationError(f"{name} must be finite")
    return arr


def _per_step(name: str, M: ArrayLike, shape: tuple[int, ...]) -> Array:
    """``M`` common to the subsystems (one axis fewer than ``shape``) or one per subsystem."""
    M = np.asarray(M, float)
    if M.ndim == len(shape) - 1:
        M = np.expand_dims(M, axis=len(shape) - 3)
    try:
        return np.broadcast_to(M, shape)
    except ValueError as exc:
        msg = f"Incompatible dimensions of {name}: expected {shape}, found {M.shape}"
        raise ValidationError(msg) from exc


def estimate(
    y: Array,
    sched: Array,
    AH: Array,
    EWE: Array,
    CH: Array,
    x0: Array,
    S0: Array,
    weights: Sequence[Sequence[float]],
    psi_bar: ArrayLike,
    xi_star: ArrayLike,
    V: ArrayLike,
    *,
    parents: Mapping[int, Sequence[int]] | None = None,
    BH: Mapping[tuple[int, int], Array] | None = None,
    variant: str = "corrected",
    moment: str = "run",
    update: str = "zero",
    k_factor: bool = True,
    gains: ArrayLike | None = None,
) -> dict[str, Array]:
    """Algorithm 1 for every subsystem, vectorised over runs, in the DAG order of ``parents``.

    Parameters
    ----------
    y : (runs, T, N, m) array
        Received scheduled entries ``y_{i, eps(k)}(k)`` for ``k = 1..T`` (row ``k - 1``), after
        the attack (6).
    sched : (T, m) int array
        ``eps(k)`` (0-based sensor indices) for ``k = 1..T``.
    AH : (T, n, n) or (T, N, n, n) array
        ``A_i(k-1) H_eps`` for ``k = 1..T``.
    EWE : (T, n, n) or (T, N, n, n) array
        ``E_i(k-1) W_i E_i^T(k-1)``.
    CH : (n_y, n) or (N, n_y, n) array
        ``C_i H_eps``.
    x0 : (runs, N, n) array
        ``x_hat_i(0|0)``.
    S0 : (n, n) or (N, n, n) array
        ``S_i(0|0)``.
    weights : N sequences ``(lambda, alpha_1, alpha_2, alpha_3, alpha_4)``
    psi_bar, xi_star, V : float or (N,) arrays
        ``psi_check_i``, ``xi*_i`` and the scalar noise variance ``V_i`` of each subsystem.
    parents : mapping ``i -> K_i`` (0-based, upstream only), optional
        Default: no coupling.
    BH : mapping ``(i, j) -> B_{i,j} H_eps``, optional
        Required for every coupled pair.
    variant : {"corrected", "paper", "additive"}
        :func:`bound_coefficients`.
    moment : {"run", "ensemble"}
        Surrogate of ``E{x_hat x_hat^T}``: the run's own ``x_hat(k|k-1) x_hat^T(k|k-1)``, or
        its mean over the runs.
    update : {"zero", "zoh", "debiased", "open_loop"}
        ``"zero"``: the paper's zero-input update (8). ``"zoh"``: the ZOH variant of Fig. 6 (a
        buffer holds the last received value of each sensor, initialised with
        ``C H x_hat(0|0)``, used as a full measurement, gain and bound with ``Phi = I``).
        ``"debiased"`` (the notebook's X1, not the paper's): innovation
        ``y - psi_check Phi C H x_hat(k|k-1)``, gain (28) of the zero-input design.
        ``"open_loop"`` (reference): no correction (``L = 0``); ``S`` is still the bound of the
        zero-input gain. The notebook runs these two only in its exact-moment recursion
        (``exact_moments(debias=True)``, ``exact_moments(gain="zero")``: the exact
        ``E{x_hat x_hat^T}``, and no bound for the open loop); here they run on sampled data
        with the ``moment`` surrogate, like the notebook's ``simulate`` for the other two.
    k_factor : bool, default True
        :func:`predicted_bound`.
    gains : (T + 1, N, n, n_y) array, optional
        Fixed gains ``L_i(k)`` (row ``k``; the columns of the sensors used at ``k``) instead of
        (28): the estimator (7)-(8) with data-independent gains (the notebook's check of its
        exact-moment recursion, X3). The bound is then not computed: ``S`` is NaN from ``k = 1``
        on (and ``S_pred`` from ``k = 2`` on).

    Returns
    -------
    dict
        ``xhat`` (runs, T + 1, N, n), ``S``, ``S_pred`` (runs, T + 1, N, n, n) and ``L``
        (runs, T + 1, N, n, n_y) (zero columns off the schedule).

    Raises
    ------
    ValidationError
        Unknown option, or arrays of incompatible shapes.
    """
    for name, val, allowed in (("variant", variant, COEFFICIENTS),
                               ("moment", moment, ("run", "ensemble")), ("update", update, UPDATES)):
        if val not in allowed:
            raise ValidationError(f"{name} must be one of {allowed}, found {val!r}")
    y = np.asarray(y, float)
    if y.ndim != 4:
        raise ValidationError(f"Incompatible dimensions of y: expected (runs, T, N, m), found {y.shape}")
    runs, T, N, m = y.shape
    n = np.shape(x0)[-1]
    if np.shape(x0) != (runs, N, n) or np.shape(sched) != (T, m) or len(weights) != N:
        raise ValidationError(
            f"x0, sched and weights must match y: expected x0 {(runs, N, n)}, sched {(T, m)}, "
            f"{N} weight sets; found {np.shape(x0)}, {np.shape(sched)}, {len(weights)}"
        )
    AH, EWE = (_per_step(nm, M, (T, N, n, n)) for nm, M in (("AH", AH), ("EWE", EWE)))
    CH = _per_step("CH", CH, (N, np.shape(CH)[-2], n))
    psi, xis, Vs = (_per_target(nm, v, N) for nm, v in (("psi_bar", psi_bar), ("xi_star", xi_star),
                                                         ("V", V)))
    parents = parents or {}
    n_y = CH.shape[1]
    if gains is not None:
        gains = np.asarray(gains, float)
        if gains.shape != (T + 1, N, n, n_y):
            raise ValidationError(
                f"Incompatible dimensions of gains: expected {(T + 1, N, n, n_y)}, found {gains.shape}")
    xh = np.zeros((runs, T + 1, N, n))
    S = np.zeros((runs, T + 1, N, n, n))
    S_pred = np.zeros_like(S)
    L_all = np.zeros((runs, T + 1, N, n, n_y))
    xh[:, 0] = x0
    S[:, 0] = np.broadcast_to(S0, (N, n, n))
    z = np.einsum("fin,iyn->fiy", xh[:, 0], CH)  # ZOH buffer z_i(0) = C H x_hat(0|0)
    for k in range(1, T + 1):
        sel = np.asarray(sched[k - 1])
        for i in range(N):
            lam, a1, a2, a3, a4 = weights[i]
            coefs = bound_coefficients(psi[i], a2, a3, a4, variant)
            up = tuple(parents.get(i, ()))
            ah = AH[k - 1, i]
            xp = predict(xh[:, k - 1, i], [xh[:, k - 1, j] for j in up], ah,
                         [BH[(i, j)] for j in up])  # (7)
            Sp = predicted_bound(S[:, k - 1, i], [S[:, k - 1, j] for j in up], ah,
                                 [BH[(i, j)] for j in up], lam, EWE[k - 1, i], k_factor)  # (17)
            S_pred[:, k, i] = Sp
            X_hat = xp[:, :, None] * xp[:, None, :]
            if moment == "ensemble":
                X_hat = np.broadcast_to(X_hat.mean(axis=0), X_hat.shape)
            if update == "zoh":
                z[:, i, sel] = y[:, k - 1, i]
                G, y_use, cols = CH[i], z[:, i], np.arange(n_y)
            else:
                G, y_use, cols = CH[i, sel], y[:, k - 1, i], sel
            if gains is None:
                L, S_new, _ = gain_and_bound(Sp, X_hat, G, coefs, a1, xis[i], Vs[i])  # (28), (18)
            else:  # fixed gains: the bound is not computed
                L, S_new = np.broadcast_to(gains[k, i][:, cols], (runs, n, len(cols))), np.nan
            L_use = np.zeros_like(L) if update == "open_loop" else L
            xh[:, k, i] = correct(xp, y_use, G, L_use, psi[i] if update == "debiased" else 1.0)  # (8)
            S[:, k, i] = S_new
            L_all[:, k, i][..., cols] = L_use
    return {"xhat": xh, "S": S, "S_pred": S_pred, "L": L_all}


# ------------------------------------------------------------------ Theorem 2, checked
def theorem2_check(
    S_pred: Array,
    X_hat: Array,
    G_steps: Sequence[Array],
    psi_bar: ArrayLike,
    weights: Sequence[Sequence[float]],
    xi_star: float,
    V: float,
    variant: str = "paper",
    *,
    literal: bool = False,
    seed: int = 20250,
    n_random: int = 32,
    steps: Sequence[float] = (1e-3, 1e-1, 1.0),
) -> dict[str, Any] | None:
    """Does the gain (28) minimise the trace of the bound (18)? Perturbations along a trajectory.

    Theorem 2 states that for given positive ``epsilon, alpha_1..alpha_4, lambda`` the bound
    ``S_i(k|k)`` of (18) "can be minimized" by the gain (28), from
    ``d tr S_i(k|k) / d L_i(k) = 0`` (29). At every step ``k = 1..T`` and subsystem ``i``, with
    that step's ``S_i(k|k-1)`` and ``E{x_hat x_hat^T}``, the gain ``L*`` of (28)
    (:func:`gain_and_bound`) is perturbed, ``L = L* +- s delta``, and the trace of (18) is
    evaluated at ``L`` term by term (:func:`bound_for_gain`). Directions ``delta`` (unit Frobenius
    norm): ``n_random`` Gaussian ones, the structured ``e_r v_j^T`` (``v_j`` the eigenvectors of
    ``Pi`` of (28)) and ``L*/||L*||``; step sizes ``s = t max(||L*||_F, 1)`` for ``t`` in ``steps``.
    (18) is quadratic in ``L``: the symmetric difference is the first-order term (zero at a
    stationary point) and the second-order term is ``s^2 tr(delta Pi delta^T)``, non-negative in
    every direction iff ``Pi >= 0``.

    Parameters
    ----------
    S_pred, X_hat : (T+1, N, n, n) arrays
        ``S_i(k|k-1)`` and ``E{x_hat_i(k|k-1) x_hat_i^T(k|k-1)}`` along the trajectory (row 0
        unused).
    G_steps : sequence of T (rows, n) arrays
        ``(C H_eps)_{eps(k)}``, the received rows at ``k = 1..T``.
    psi_bar : (N,) array
        ``psi_check_i``.
    weights : N sequences of 5 floats
        ``(lambda, alpha_1..alpha_4)`` per subsystem (``lambda`` does not enter (18) or (28): it
        acts through ``S_pred``).
    xi_star, V : float
        Attack-energy bound and measurement-noise variance.
    variant : str, default "paper"
        Coefficients of :func:`bound_coefficients`.
    literal : bool, default False
        Also evaluate (18) with its first factor read literally, ``(1 - (a3 - a2))(1 - psi)``:
        the relative excess of tr (18) at (28) over its minimum, and the steps without one.
    seed, n_random, steps
        Random directions and step sizes (ours).

    Returns
    -------
    dict or None
        None if the gain (28) is not finite at some step; else ``min_relative_change`` (the
        smallest relative change of tr S(k|k), negative: a decrease), ``worst_k_target_step``,
        ``max_relative_first_order``, ``min_eig_pi``, ``min_eig_pi_relative`` (min over steps of
        ``lambda_min(Pi) / max |lambda(Pi)|``), ``steps_with_pi_indefinite``, ``steps``,
        ``min_eig_S_at_indefinite_pi`` (smallest lambda_min of S(k|k) at (28) over the steps with
        Pi indefinite; None if there are none), ``indefinite_pi_steps_with_S_pd``,
        ``c0_per_target``, ``kappa_x_per_target`` and, for ``literal``, ``literal_18_excess`` and
        ``literal_18_steps_without_minimum``.

    Raises
    ------
    ValidationError
        ``S_pred`` / ``X_hat`` / ``G_steps`` / ``weights`` of inconsistent sizes.
    """
    S_pred, X_hat = np.asarray(S_pred, float), np.asarray(X_hat, float)
    if S_pred.shape != X_hat.shape or S_pred.ndim != 4 or S_pred.shape[0] != len(G_steps) + 1:
        raise ValidationError(
            f"S_pred and X_hat must be (T+1, N, n, n) with T = len(G_steps) = {len(G_steps)}: "
            f"found {S_pred.shape} and {X_hat.shape}")
    T, N, n = len(G_steps), S_pred.shape[1], S_pred.shape[2]
    psi = _per_target("psi_bar", psi_bar, N)
    if len(weights) != N or any(len(w) != 5 for w in weights):
        raise ValidationError(f"weights must hold {N} tuples (lambda, alpha1..alpha4)")
    rng = np.random.default_rng(seed)
    worst, where, first, pi_rel, pi_min = np.inf, None, 0.0, np.inf, np.inf
    excess, no_min, negative_pi, s_pd, s_min = 0.0, 0, 0, 0, np.inf
    c0_kx = [bound_coefficients(psi[i], *weights[i][2:], variant)[:2] for i in range(N)]
    for k in range(1, T + 1):
        G = np.asarray(G_steps[k - 1], float)
        rows = G.shape[0]
        for i in range(N):
            _, a1, a2, a3, a4 = weights[i]
            coefs = bound_coefficients(psi[i], a2, a3, a4, variant)
            Sp, Xh = S_pred[k, i], X_hat[k, i]
            L, S_new, R = gain_and_bound(Sp[None], Xh[None], G, coefs, a1, xi_star, V)  # (28), (18)
            L, R = L[0], R[0]
            if not np.all(np.isfinite(L)):
                return None
            Pi = sym(coefs[0] * (G @ Sp @ G.T) + R)  # Pi of (28)
            ev, vec = np.linalg.eigh(Pi)
            pi_min = min(pi_min, float(ev[0]))
            pi_rel = min(pi_rel, float(ev[0] / np.abs(ev).max()))
            if ev[0] < 0:  # (28) is a saddle of tr (18): is S(k|k) at (28) still positive definite?
                negative_pi += 1
                s_eig = float(np.linalg.eigvalsh(S_new[0])[0])
                s_min, s_pd = min(s_min, s_eig), s_pd + int(s_eig > 0)
            structured = [np.outer(np.eye(n)[r], vec[:, j]) for r in range(n) for j in range(rows)]
            scale_dir = [L / np.linalg.norm(L)] if np.linalg.norm(L) > 0 else []
            dirs = np.concatenate([rng.standard_normal((n_random, n, rows)),
                                   np.array(structured + scale_dir)])
            dirs /= np.linalg.norm(dirs, axis=(1, 2), keepdims=True)
            f0 = np.trace(bound_for_gain(Sp, Xh, G, L, coefs, a1, xi_star, V))  # tr (18) at (28)
            base = max(float(np.linalg.norm(L)), 1.0)
            for t in steps:
                s_ = t * base
                fp = np.trace(bound_for_gain(Sp, Xh, G, L + s_ * dirs, coefs, a1, xi_star, V),
                              axis1=-2, axis2=-1)
                fm = np.trace(bound_for_gain(Sp, Xh, G, L - s_ * dirs, coefs, a1, xi_star, V),
                              axis1=-2, axis2=-1)
                rel = np.minimum(fp - f0, fm - f0) / abs(f0)
                if rel.min() < worst:
                    worst, where = float(rel.min()), (k, i + 1, t)
                if t == steps[0]:
                    first = max(first, float(np.abs(fp - fm).max() / (2 * abs(f0))))
            if literal:
                lit = ((1 - (a3 - a2)) * (1 - psi[i]),) + tuple(coefs[1:])  # (18)'s factor, literal
                f_lit = np.trace(bound_for_gain(Sp, Xh, G, L, lit, a1, xi_star, V))
                Pi_l = sym(lit[0] * (G @ Sp @ G.T) + R)
                if np.linalg.eigvalsh(Pi_l)[0] <= 0:
                    no_min += 1  # tr (18) unbounded below in L, or flat: no minimiser
                else:
                    L_l = np.linalg.solve(Pi_l, lit[0] * (G @ Sp)).T
                    f_min = np.trace(bound_for_gain(Sp, Xh, G, L_l, lit, a1, xi_star, V))
                    excess = max(excess, float((f_lit - f_min) / abs(f_lit)))
    return {"min_relative_change": worst, "worst_k_target_step": where,
            "max_relative_first_order": first, "min_eig_pi": pi_min,
            "min_eig_pi_relative": pi_rel, "steps_with_pi_indefinite": negative_pi,
            "steps": T * N,
            "min_eig_S_at_indefinite_pi": float(s_min) if negative_pi else None,
            "indefinite_pi_steps_with_S_pd": s_pd,
            "c0_per_target": [float(c) for c, _ in c0_kx],
            "kappa_x_per_target": [float(x) for _, x in c0_kx],
            "literal_18_excess": excess if literal else None,
            "literal_18_steps_without_minimum": no_min if literal else None}


# ------------------------------------------------------------------ Theorem 3 on an instance
def exact_design_moments(
    AH: Array,
    BH: Mapping[tuple[int, int], Array],
    parents: Mapping[int, Sequence[int]],
    EWE: Array,
    CH: Array,
    sched: Array,
    psi_bar: ArrayLike,
    xi: Array,
    xi_star: float,
    V: float,
    weights: Sequence[Sequence[float]],
    mean0: Array,
    cov0: Array,
    S0: Array,
    variant: str = "paper",
    zero_gain: bool = False,
) -> dict[str, Array]:
    """Algorithm 1 with the exact ``E{x_hat x_hat^T}`` on a time-invariant SPDSS, exact moments.

    With the theorem's own expectation in (18) and (28) the gains are deterministic, and the
    joint vector ``z = col(x_1..x_N, x_hat_1..x_hat_N)`` has an exactly propagated mean and
    second moment: prediction (1), (7) ``z^- = A_z z + noise``; update (8) of subsystem ``i`` with
    the replacement attack (6), averaged over ``psi_i(k) in {1, 0}`` (independent of ``z^-`` and
    of ``v``). ``S_i(k|k-1)`` is (17) (:func:`predicted_bound`, factor ``|K_i|``), the gain
    (28) and ``S_i(k|k)`` (18) are :func:`gain_and_bound` with ``variant`` coefficients.

    Parameters
    ----------
    AH : (n, n) array
        ``A H_eps`` (the same for every subsystem).
    BH : mapping (i, j) -> (n, n) array
        ``B_{i,j} H_eps`` for ``j in K_i`` (0-based).
    parents : mapping i -> sequence of int
        ``K_i``, upstream subsystems first (a sequential order).
    EWE : (n, n) array
        ``E W E^T``.
    CH : (n_y, n) array
        ``C H_eps``.
    sched : (T, m) int array
        ``eps(k)`` (0-based rows of ``CH``) for ``k = 1..T``.
    psi_bar : (N,) array
        ``psi_check_i``, probability of no attack.
    xi : (T+1, n_y) array
        Attack signal ``xi(k)`` (the same for every subsystem).
    xi_star, V : float
        Energy bound of ``xi`` and measurement-noise variance (``V I``).
    weights : N sequences of 5 floats
        ``(lambda, alpha_1..alpha_4)`` per subsystem.
    mean0, cov0 : (N n,) and (N n, N n) arrays
        Mean and covariance of ``x(0)``; ``x_hat(0|0) = mean0``.
    S0 : (n, n) array
        ``S_i(0|0)`` (every subsystem).
    variant : str, default "paper"
        Coefficients of :func:`bound_coefficients`.
    zero_gain : bool, default False
        Update (8) with ``L = 0`` instead of (28): the open-loop prediction on the same
        system, noise and attacks (the baseline a gain must beat to be informative). ``S``
        and ``Sp`` are still (17), (18) at the gain (28); ``L`` records (28).

    Returns
    -------
    dict
        ``P`` (T+1, N, n, n) = E{e e^T}, ``S`` = S(k|k), ``Sp`` = S(k|k-1), ``Xh`` =
        E{x_hat(k|k-1) x_hat^T(k|k-1)}, ``Exx`` = E{x x^T} and ``L`` (T+1, N, n, m).

    Raises
    ------
    ValidationError
        Incompatible dimensions.
    """
    N, n = len(parents), AH.shape[0]
    T, m = np.shape(sched)
    psi = _per_target("psi_bar", psi_bar, N)
    if np.shape(cov0) != (N * n, N * n) or np.shape(mean0) != (N * n,) or np.shape(xi)[0] != T + 1:
        raise ValidationError(f"Incompatible dimensions of mean0 / cov0 / xi: expected ({N * n},), "
                              f"({N * n}, {N * n}), ({T + 1}, n_y); found {np.shape(mean0)}, "
                              f"{np.shape(cov0)}, {np.shape(xi)}")
    nz = 2 * N * n
    xs = [slice(i * n, (i + 1) * n) for i in range(N)]
    hs = [slice((N + i) * n, (N + i + 1) * n) for i in range(N)]
    Az, Qw = np.zeros((nz, nz)), np.zeros((nz, nz))
    for i in range(N):
        Qw[xs[i], xs[i]] = EWE
        for rows in (xs, hs):
            Az[rows[i], rows[i]] = AH  # (1), (7): own term
            for j in parents[i]:
                Az[rows[i], rows[j]] = BH[(i, j)]  # (1), (7): upstream term
    mu = np.concatenate([mean0, mean0])
    Q = np.zeros((nz, nz))
    Q[:N * n, :N * n] = cov0
    Q = Q + np.outer(mu, mu)
    S = np.broadcast_to(S0, (N, n, n)).copy()
    rec = {name: np.zeros((T + 1, N, n, n)) for name in ("P", "S", "Sp", "Xh", "Exx")}
    rec["L"] = np.zeros((T + 1, N, n, m))
    for k in range(T + 1):
        if k > 0:
            mu, Q = Az @ mu, Az @ Q @ Az.T + Qw  # prediction (1), (7)
            G, xi_s = CH[sched[k - 1]], xi[k, sched[k - 1]]
            S_new = S.copy()
            for i in range(N):
                lam, a1, a2, a3, a4 = weights[i]
                Sp = predicted_bound(S[i], [S[j] for j in parents[i]], AH,
                                     [BH[(i, j)] for j in parents[i]], lam, EWE)  # (17)
                L, S_i, _ = gain_and_bound(Sp[None], Q[hs[i], hs[i]][None], G,
                                           bound_coefficients(psi[i], a2, a3, a4, variant),
                                           a1, xi_star, V)  # (28), (18)
                S_new[i], rec["Sp"][k, i], rec["Xh"][k, i], rec["L"][k, i] = S_i[0], Sp, \
                    Q[hs[i], hs[i]], L[0]
            for i in range(N):  # update (8) with (6), averaged over psi_i(k)
                L = 0.0 * rec["L"][k, i] if zero_gain else rec["L"][k, i]
                mu_n, Q_n = np.zeros_like(mu), np.zeros_like(Q)
                for b, p in ((1.0, psi[i]), (0.0, 1.0 - psi[i])):
                    J = np.eye(nz)
                    J[hs[i], xs[i]] += b * (L @ G)
                    J[hs[i], hs[i]] -= L @ G
                    u = np.zeros(nz)
                    u[hs[i]] = (1 - b) * (L @ xi_s)
                    Jm = J @ mu
                    mu_n += p * (Jm + u)
                    Q_n += p * (J @ Q @ J.T + np.outer(Jm, u) + np.outer(u, Jm) + np.outer(u, u))
                    Q_n[hs[i], hs[i]] += p * b * V * (L @ L.T)
                mu, Q = mu_n, sym(Q_n)
            S = S_new
        for i in range(N):
            qxx, qxh, qhh = Q[xs[i], xs[i]], Q[xs[i], hs[i]], Q[hs[i], hs[i]]
            rec["P"][k, i], rec["Exx"][k, i] = sym(qxx - qxh - qxh.T + qhh), qxx
        rec["S"][k] = S
    return rec


def theorem3_candidates(points: int, log10_box: ArrayLike, seed: int = 0) -> Array:
    """The declared weight search of Theorem 3: scrambled Sobol points, log-uniform in a box.

    The one generator of the candidate weight sets ``(lambda, alpha_1..alpha_4)``, used both
    on the paper's example (X7) and on our instance (C3), so that both search the same sets.

    Parameters
    ----------
    points : int
        Number of candidates, a power of 2 (``random_base2``).
    log10_box : (5, 2) array
        ``[low, high]`` of ``log10`` of ``lambda, alpha_1..alpha_4``.
    seed : int, default 0
        Seed of the scrambling.

    Returns
    -------
    (points, 5) array
        The candidate weight sets.

    Raises
    ------
    ValidationError
        ``points`` not a power of 2, or a box not of shape (5, 2) with low < high.
    """
    from scipy import stats

    box = np.asarray(log10_box, dtype=float)
    if box.shape != (5, 2) or not np.all(box[:, 0] < box[:, 1]):
        raise ValidationError(f"log10_box must be (5, 2) with low < high, found {box.tolist()}")
    if isinstance(points, bool) or not isinstance(points, int | np.integer) or points < 1 \
            or points & (points - 1):
        raise ValidationError(f"points must be a power of 2, found {points!r}")
    unit = stats.qmc.Sobol(5, scramble=True, seed=seed).random_base2(int(points).bit_length() - 1)
    return 10 ** (box[:, 0] + unit * np.diff(box, axis=1)[:, 0])


def theorem3_proof_envelope(
    phi_lo: float,
    phi_hi: float,
    psi_bar: float,
    weights: Sequence[float],
    const: Mapping[str, float],
    e0: float,
    horizon: int,
    n_x: int,
    n_y: int,
    variant: str = "paper",
) -> dict[str, Any]:
    """The envelope of Theorem 3's proof, (46)-(56), with its own constants; Lemma 3 consistent.

    From the proof, as printed: ``chi_1 = (1+1/lambda) h_*^2 b_*^2 phi_* + e_*^2 q_*`` (44),
    ``rho = 1 - (1 + lambda + chi_1/((h^* a^*)^2 phi^*))^{-1}`` (55),
    ``mu_1 = ((h^* b^*)^2 phi^* + (e^*)^2 q^*) / (c0 ((1+lambda)(h^* a^*)^2 phi^* + chi_1))``
    (49), ``Lambda`` of (53) and ``mu_2 = Lambda t_bar / phi_*`` (51). (50) is corrected (it
    prints ``(psi-1)(h^*c^*)^2 (X^*)^2 + (1-psi) xi^*``, negative when ``(X^*)^2 > xi^*``, and
    omits the noise): ``E{t^T t} <= t_bar = psi n_y r^* + (1-psi)(sqrt(xi^*) + h^* c^*
    sqrt(n_x) X^*)^2`` (Minkowski; ``E||x||^2 <= n_x (X^*)^2``). ``alpha_5..alpha_7`` are the
    free weights of (42) under condition (a), ``alpha_5 + alpha_6 <= c0 - 1``; the ones that
    minimise ``mu`` of (55), ``alpha_7 = sqrt(mu_2/mu_1)`` and ``alpha_5 : alpha_6 = sqrt(mu_1) :
    sqrt(mu_2)`` with ``alpha_5 + alpha_6 = c0 - 1``, give ``mu = (sqrt(mu_1) + sqrt(mu_2))^2
    (1 + 1/(c0 - 1))`` (the tightest envelope the theorem offers). Lemma 3 with its roles
    consistent (the printed (32), (56) swap the rate and the constant and start the sum at 1):

    .. math::  UB(k) = \\frac{\\phi^*}{\\phi_*}\\mathbb E\\|e(0|0)\\|^2(1-\\rho)^k
               + \\mu\\phi^*\\sum_{l=0}^{k-1}(1-\\rho)^l.

    Parameters
    ----------
    phi_lo, phi_hi : float
        ``phi_*`` and ``phi^*`` of Theorem 3.
    psi_bar : float
        ``psi_check_i``.
    weights : 5 floats
        ``(lambda, alpha_1..alpha_4)``.
    const : mapping
        The constants of :data:`THEOREM3_CONSTANTS`.
    e0 : float
        ``E||e_i(0|0)||^2``.
    horizon : int
        Last step ``T`` of the envelope.
    n_x, n_y : int
        State and output dimensions.
    variant : str, default "paper"
        Coefficients ``c0, kappa_x`` (Theorem 3 prints Theorem 2's).

    Returns
    -------
    dict
        ``rho``, ``chi1``, ``mu1``, ``mu2``, ``Lambda``, ``t_bar``, ``t_bar_printed``, ``mu``,
        ``UB`` ((horizon+1,) array, NaN when condition (a) fails: ``c0 <= 1``) and
        ``UB_literal`` ((56) as printed, with ``rho`` and ``mu`` in the printed places).

    Raises
    ------
    ValidationError
        Missing constants, or ``phi_*`` not in (0, phi^*].
    """
    missing = [name for name in THEOREM3_CONSTANTS if name not in const]
    if missing:
        raise ValidationError(f"const: missing Theorem 3 constants {missing}")
    if not 0 < phi_lo <= phi_hi:
        raise ValidationError(
            f"phi_lo, phi_hi must satisfy 0 < phi_lo <= phi_hi, found {phi_lo}, {phi_hi}")
    lam, a1, a2, a3, a4 = (float(w) for w in weights)
    k = {name: float(const[name]) for name in THEOREM3_CONSTANTS}
    c0, kx, *_ = bound_coefficients(psi_bar, a2, a3, a4, variant)
    ha2, hc2 = k["h_hi"] ** 2 * k["a_hi2"], k["h_hi"] ** 2 * k["c_hi2"]
    chi1 = (1 + 1 / lam) * k["h_lo"] ** 2 * k["b_lo2"] * phi_lo + k["e_lo2"] * k["q_lo"]  # (44)
    rho = 1 - 1 / (1 + lam + chi1 / (ha2 * phi_hi))  # (55)
    mu1 = ((k["h_hi"] ** 2 * k["b_hi2"] * phi_hi + k["e_hi2"] * k["q_hi"])
           / (c0 * ((1 + lam) * ha2 * phi_hi + chi1)))  # (49)
    varpi_hi = ((1 + lam) * ha2 + (1 + 1 / lam) * k["h_hi"] ** 2 * k["b_hi2"]) * phi_hi \
        + k["e_hi2"] * k["q_hi"]  # (33), upper
    tail = (1 + 1 / a2 + 1 / a4) * (1 - psi_bar)
    denom = (c0 * varpi_hi * hc2 + (1 + a1) * kx * varpi_hi * hc2
             + (1 + 1 / a1) * kx * hc2 * ((1 + a1) * k["x2"] + (1 + 1 / a1) * phi_hi)
             + tail * k["xi_star"] + psi_bar * k["r_hi"])
    lam_L = c0 ** 2 * varpi_hi ** 2 * hc2 / denom ** 2  # (53)
    t_bar = psi_bar * n_y * k["r_hi"] + (1 - psi_bar) * (
        np.sqrt(k["xi_star"]) + np.sqrt(hc2 * n_x * k["x2"])) ** 2  # (50), corrected
    t_printed = (psi_bar - 1) * hc2 * k["x2"] + (1 - psi_bar) * k["xi_star"]  # (50) as printed
    mu2 = lam_L * t_bar / phi_lo  # (51)
    steps = np.arange(horizon + 1)
    if c0 > 1:
        mu = (np.sqrt(mu1) + np.sqrt(mu2)) ** 2 * (1 + 1 / (c0 - 1))  # (55), best alpha_5..7
        geo = np.concatenate([[0.0], np.cumsum((1 - rho) ** np.arange(horizon))])
        ub = phi_hi / phi_lo * e0 * (1 - rho) ** steps + mu * phi_hi * geo  # Lemma 3, consistent
        with np.errstate(all="ignore"):  # |1 - mu| > 1 is possible in the printed form
            geo1 = np.concatenate([[0.0, 0.0], np.cumsum((1 - mu) ** np.arange(1, horizon))])
            ub_lit = phi_hi / phi_lo * e0 * (1 - mu) ** steps + rho * phi_hi * geo1  # (56)
    else:
        mu, ub, ub_lit = np.nan, np.full(horizon + 1, np.nan), np.full(horizon + 1, np.nan)
    return {"rho": float(rho), "chi1": float(chi1), "mu1": float(mu1), "mu2": float(mu2),
            "Lambda": float(lam_L), "t_bar": float(t_bar), "t_bar_printed": float(t_printed),
            "mu": float(mu), "UB": ub, "UB_literal": ub_lit}
