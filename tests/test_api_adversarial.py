"""Adversarial sweep of the public API of the core numerical modules of secest.

For every public callable of :data:`MODULES` a valid call is declared in :data:`SPECS`;
each parameter gets a *kind* whose catalogue of invalid values (wrong type, None, strings,
NaN/inf, wrong shape, empty, out-of-range, non-symmetric / indefinite, absurd sizes, violated
standing assumptions ...) is substituted one at a time. Every such call must raise a
:class:`~secest.core.validation.ValidationError` whose message names the argument, within
:data:`TIME_LIMIT` seconds. Outcomes:

``clear``    ValidationError naming the argument
``unclear``  another exception, or a ValidationError that does not name the argument
``silent``   a result was returned (or the call ran past the time limit)

Run it as a script to print the counts and every call that is not ``clear``; with
``PYTHONPATH=<an older checkout>`` it measures an older secest (parameters and functions
that the older version lacks are skipped)::

    .venv/bin/python tests/test_api_adversarial.py [--verbose]
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import re
import signal
import sys
import time
import warnings
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

MODULES = {  # label in SPECS -> module
    **{m: f"secest.core.{m}" for m in ("validation", "graphs", "channels", "covariance", "detectors",
                                       "montecarlo", "systems", "estimation", "schedules", "lmi")},
    "ding2020": "secest.methods.ding2020",
}
TIME_LIMIT = 2.0
# Public names that are records or exception / warning classes, not computations.
NOT_CALLS = {
    "validation.ValidationError", "validation.SizeLimitError", "ding2020.FilterHealthWarning",
    "ding2020.SecureStep", "ding2020.SecureRun", "ding2020.Theorem4", "ding2020.Example", "systems.RedundancyResult", "estimation.FeedthroughSVD",
    "lmi.LMISolveReport", "lmi.LMISolveError", "lmi.InfeasibleLMIError", "lmi.UnboundedLMIError",
}

Variants = list[tuple[str, Any]]


# ----------------------------------------------------------------------------- catalogue
def _garbage(v: Any = None) -> Variants:
    return [("str", "a"), ("None", None), ("list of str", ["a", "b"]), ("object", object())]


def _real(*, low: float | None = None, low_open: bool = False, high: float | None = None,
          inf_ok: bool = False) -> Callable[[Any], Variants]:
    def kind(v: Any) -> Variants:
        out = _garbage() + [("nan", float("nan")), ("bool", True), ("array", np.array([1.0, 2.0]))]
        if not inf_ok:
            out.append(("inf", float("inf")))
        if low is not None:
            out.append(("below range", low - 1.0))
            if low_open:
                out.append(("at open bound", low))
        if high is not None:
            out.append(("above range", high + 0.5))
        return out
    return kind


def _int(minimum: int | None = None, *, huge: bool = False, none_ok: bool = False) -> Callable[[Any], Variants]:
    def kind(v: Any) -> Variants:
        out = [g for g in _garbage() if not (none_ok and g[0] == "None")]
        out += [("float", 2.5), ("bool", True), ("nan", float("nan"))]
        if minimum is not None:
            out.append(("below minimum", minimum - 1))
        if huge:
            out.append(("absurd size", 10**12))
        return out
    return kind


def _name(v: Any) -> Variants:
    return [("None", None), ("empty string", ""), ("list of str", ["a", "b"]), ("object", object())]


def _bool(v: Any) -> Variants:
    return [("str", "yes"), ("None", None), ("int", 2), ("float", 1.0)]


def _choice(v: Any) -> Variants:
    return [("unknown", "nonexistent"), ("None", None), ("int", 3), ("list", [v])]


def _callable(v: Any) -> Variants:
    return [("str", "a"), ("None", None), ("int", 3)]


def _seed(v: Any) -> Variants:
    return [("None", None), ("str", "a"), ("negative", -1), ("float", 1.5), ("bool", True)]


def _sym_part(a: np.ndarray) -> np.ndarray:
    return 0.5 * (a + np.swapaxes(a, -1, -2))


def _array(*, shape: bool = True, empty: bool = True, nan: bool = True, extra: Variants = ()) -> Callable:
    """Invalid arrays derived from the valid value ``v`` (a wrong shape appends to the last axis)."""
    def kind(v: Any) -> Variants:
        a = np.asarray(v, dtype=float)
        out = _garbage() + [("ragged", [[1.0, 2.0], [3.0]]), ("complex", a + 1j)]
        if nan:
            out.append(("nan", _put(a, np.nan)))
            out.append(("inf", _put(a, np.inf)))
        if shape:
            out.append(("wrong shape", np.concatenate([a, a[..., :1]], axis=-1) if a.ndim else a[None]))
        if empty:
            out.append(("empty", np.zeros((0,) * max(a.ndim, 1))))
        return out + list(extra)
    return kind


def _put(a: np.ndarray, value: float) -> np.ndarray:
    b = a.copy()
    b.reshape(-1)[0] = value
    return b


def _psd(*, strict: bool = False, shape: bool = True) -> Callable:
    def kind(v: Any) -> Variants:
        a = np.asarray(v, dtype=float)
        n = a.shape[-1]
        scale = float(np.abs(a).max()) or 1.0
        out = _array(shape=shape)(v)
        if n > 1:
            out.append(("non-symmetric", a + scale * np.triu(np.ones((n, n)), 1)))
        out.append(("indefinite", a - 3 * scale * np.eye(n) * (np.arange(n) == 0)))
        if strict:
            out.append(("singular", a * 0.0))
        return out
    return kind


def _sym(v: Any) -> Variants:
    a = np.asarray(v, dtype=float)
    n = a.shape[-1]
    return _array()(v) + [("non-symmetric", a + np.triu(np.ones((n, n)), 1))]


def _adj(*, connected: bool = False, extra: Variants = ()) -> Callable:
    def kind(v: Any) -> Variants:
        a = np.asarray(v, dtype=float)
        out = _array()(v) + [("not 0/1", 2 * a), ("self-loops", a + np.eye(a.shape[0]))]
        if connected:
            out.append(("disconnected", _TWO_RINGS))
        return out + list(extra)
    return kind


def _stochastic(v: Any) -> Variants:
    a = np.asarray(v, dtype=float)
    neg = a.copy()
    i, j = np.argwhere(a > 0)[0]
    neg[i, j] = -a[i, j]
    return _array()(v) + [("rows sum to 5", 5 * a), ("negative entry", neg)]


def _delta(v: Any) -> Variants:
    return _garbage() + [("0.5", 0.5), ("2", 2), ("nan", float("nan")), ("wrong shape", np.ones(7))]


def _sequence(element: Callable[[Any], Variants]) -> Callable:
    """Invalid sequences of arrays: garbage, empty, and every invalid first element."""
    def kind(v: Any) -> Variants:
        rest = list(v)[1:]
        out = [("str", "a"), ("None", None), ("empty list", []), ("object", object())]
        for label, bad in element(list(v)[0]):
            if label not in ("None", "str", "list of str", "object"):
                out.append((f"element {label}", [bad, *rest]))
        return out
    return kind


def _custom(*pairs: tuple[str, Any]) -> Callable:
    return lambda v: list(pairs)


def _join(*kinds: Callable) -> Callable:
    return lambda v: [x for k in kinds for x in k(v)]


# ----------------------------------------------------------------------------- fixtures
T = 0.05
A3 = np.array([[1, T, T**2 / 2], [0, 1, T], [0, 0, 1.0]])
P2 = np.array([[2.0, 0.5], [0.5, 1.0]])
RING6 = np.roll(np.eye(6), 1, axis=1) + np.roll(np.eye(6), -1, axis=1)
H6 = RING6 / 2
_TWO_RINGS = np.kron(np.eye(2), np.ones((3, 3)) - np.eye(3))
C6 = np.tile([[[4.0, -0.8, 1.0]]], (6, 1, 1))
P6 = np.broadcast_to(np.eye(3), (6, 3, 3)).copy()
BANKS = [np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]),
         np.array([[1.0, 1.0, 0.0]]), np.array([[0.0, 1.0, 1.0]])]
FORTY_BANKS = [np.eye(6)[[i % 6]] for i in range(40)]


def _lmi_fixture() -> tuple[Any, dict]:
    import cvxpy as cp

    from secest.core import lmi

    x = cp.Variable((2, 2), symmetric=True)
    m = lmi.block_symmetric([[-x], [np.eye(2), -np.eye(2)]])
    return cp.Problem(cp.Minimize(cp.trace(x)), [lmi.lmi(m, 1e-6)]), {"m": m}


def _expr() -> Any:
    import cvxpy as cp

    return cp.Variable((2, 2), symmetric=True)


@dataclass
class Spec:
    """A valid call (keyword arguments) and the kind of each parameter to attack."""

    valid: Callable[[], dict[str, Any]]
    kinds: dict[str, Callable[[Any], Variants]]
    mention: dict[str, str] = field(default_factory=dict)  # param -> name the message must contain
    none_ok: set[str] = field(default_factory=set)  # params for which None is a valid value


POS = _real(low=0.0, low_open=True)
NONNEG = _real(low=0.0)
PROB = _real(low=0.0, high=1.0)
PROB_OPEN = _join(_real(low=0.0, high=1.0), _custom(("0", 0.0), ("1", 1.0)))
RTOL = _join(_real(low=0.0, high=1.0), _custom(("0", 0.0), ("1", 1.0)))
ARRAY = _array()


def _ding_step() -> dict[str, Any]:
    return dict(x_post=np.ones((6, 3)), Pi_post=P6, Gamma_post=0.5 * P6, delta=1, y=np.zeros((6, 1)),
                A=A3, BBt=0.04 * np.eye(3), C=C6, DDt=np.array([[0.0025]]), adj=RING6, weights=H6,
                kappa=0.004, threshold=25.0, inspect=True, inspection_cov="Gamma", tol=1e-10,
                strict=False, joseph=False, rejections=np.zeros(6), lockout_steps=10, validate=True)


def _ding_node() -> dict[str, Any]:
    I3 = np.eye(3)
    return dict(x_self=np.ones(3), Pi_self=I3, Gamma_self=0.5 * I3, x_nbrs=np.ones((2, 3)),
                Pi_nbrs=np.stack([I3, I3]), h_nbrs=np.array([0.5, 0.5]), delta=1, y_i=np.zeros(1),
                A=A3, BBt=0.04 * I3, C_i=C6[0], DDt=np.array([[0.0025]]), kappa=0.004,
                threshold=25.0, inspect=True, inspection_cov="Gamma", tol=1e-10, strict=False,
                joseph=False, validate=True)


def _ding_run() -> dict[str, Any]:
    return dict(x0=np.ones((6, 3)), Pi0=P6, Gamma0=0.5 * P6, delta=np.ones(4), y=np.zeros((5, 6, 1)),
                A=A3, BBt=0.04 * np.eye(3), C=C6, DDt=np.array([[0.0025]]), adj=RING6, weights=H6,
                kappa=0.004, threshold=25.0, inspect=True, inspection_cov="Gamma", tol=1e-10,
                strict=False, joseph=False, received=None, keep=("Pi_post",), validate=True)


def _run_delta(v: Any) -> Variants:
    return _garbage() + [("0.5", np.full(4, 0.5)), ("2", np.full(4, 2.0)), ("nan", np.full(4, np.nan)),
                         ("too short", np.ones(2)), ("wrong batch", np.ones((3, 4)))]


FILTER_KINDS = dict(
    x_post=ARRAY, Pi_post=_psd(), Gamma_post=_join(_psd(), _custom(("above Pi", 2 * P6))),
    delta=_delta, y=ARRAY, A=ARRAY, BBt=_psd(), C=ARRAY, DDt=_psd(strict=True),
    adj=_adj(connected=True), weights=_stochastic, kappa=NONNEG, threshold=POS, inspect=_bool,
    inspection_cov=_choice, tol=NONNEG, strict=_bool, joseph=_bool,
    rejections=_join(_array(), _custom(("negative", -np.ones(6)), ("fraction", np.full(6, 0.5)))),
    lockout_steps=_int(1), validate=_bool,
)
RUN_KINDS = dict(
    x0=ARRAY, Pi0=_psd(), Gamma0=_join(_psd(), _custom(("above Pi", 2 * P6))), delta=_run_delta, y=ARRAY,
    A=ARRAY, BBt=_psd(), C=ARRAY, DDt=_psd(strict=True), adj=_adj(connected=True), weights=_stochastic,
    kappa=NONNEG, threshold=POS, inspect=_bool, inspection_cov=_choice, tol=NONNEG, strict=_bool,
    joseph=_bool, received=_callable,
    keep=_custom(("unknown", ("nonexistent",)), ("str", "Pi_post"), ("None", None), ("int", 3)),
    validate=_bool,
)
NODE_KINDS = dict(
    x_self=ARRAY, Pi_self=_psd(), Gamma_self=_join(_psd(), _custom(("above Pi", 2 * np.eye(3)))),
    x_nbrs=ARRAY, Pi_nbrs=_psd(), h_nbrs=_join(ARRAY, _custom(("negative", [-0.5, 1.5]), ("sum 2", [1.0, 1.0]))),
    delta=_join(_garbage, _custom(("0.5", 0.5), ("2", 2))), y_i=ARRAY, A=ARRAY, BBt=_psd(), C_i=ARRAY,
    DDt=_psd(strict=True), kappa=NONNEG, threshold=POS, inspect=_bool, inspection_cov=_choice,
    tol=NONNEG, strict=_bool, joseph=_bool, validate=_bool,
)


def _integrator() -> dict[str, Any]:
    return dict(M=-np.eye(2), E_w=np.eye(2), w=lambda t: np.zeros(2), E_s=np.eye(2), R=np.eye(2),
                phi=np.sign, x0=np.ones(2), dt=0.1, n_steps=5, record_every=1, method="expeuler")


SPECS: dict[str, Spec] = {
    # ------------------------------------------------------------------ validation helpers
    "validation.as_matrix": Spec(
        lambda: dict(name="R", value=P2, shape=(2, 2), square=True, finite=True, empty=False),
        dict(name=_name, value=ARRAY, shape=_custom(("str", "a"), ("negative", (-1, 2)), ("float", (2.5, 2))),
             square=_bool, finite=_bool, empty=_bool), mention={"value": "R"}),
    "validation.check_real": Spec(
        lambda: dict(name="x", value=0.5, lower=0.0, upper=1.0, lower_open=False, upper_open=False,
                     finite=True),
        dict(name=_name, value=PROB, lower=_custom(("str", "a"), ("nan", float("nan"))),
             upper=_custom(("str", "a"), ("nan", float("nan"))), lower_open=_bool, upper_open=_bool,
             finite=_bool), mention={"value": "x"}),
    "validation.check_int": Spec(
        lambda: dict(name="k", value=3, minimum=1, maximum=10),
        dict(name=_name, value=_join(_int(1), _custom(("above maximum", 11))),
             minimum=_custom(("str", "a"), ("float", 1.5)), maximum=_custom(("str", "a"), ("float", 1.5))),
        mention={"value": "k"}),
    "validation.check_positive_int": Spec(
        lambda: dict(name="k", value=3, minimum=1),
        dict(name=_name, value=_int(1), minimum=_custom(("str", "a"), ("float", 1.5), ("None", None))),
        mention={"value": "k"}),
    "validation.check_probability": Spec(
        lambda: dict(name="p", value=0.5, open_interval=False),
        dict(name=_name, value=PROB, open_interval=_bool), mention={"value": "p"}),
    "validation.check_bool": Spec(lambda: dict(name="flag", value=True), dict(name=_name, value=_bool),
                                  mention={"value": "flag"}),
    "validation.check_choice": Spec(
        lambda: dict(name="mode", value="a", choices=("a", "b")),
        dict(name=_name, value=_choice, choices=_custom(("str", "ab"), ("None", None), ("empty", ()))),
        mention={"value": "mode"}),
    "validation.check_callable": Spec(lambda: dict(name="f", value=len), dict(name=_name, value=_callable),
                                      mention={"value": "f"}),
    "validation.check_instance": Spec(
        lambda: dict(name="x", value=3, cls=int, made_by="int()"),
        dict(name=_name, value=_custom(("str", "a"), ("None", None)),
             cls=_custom(("not a class", 3), ("None", None)),
             made_by=_custom(("None", None), ("empty", ""), ("int", 3))),
        mention={"value": "x"}),
    "validation.as_rng": Spec(lambda: dict(name="rng", rng=0), dict(name=_name, rng=_seed)),
    "validation.check_size": Spec(
        lambda: dict(name="n", value=3, limit=10, what="entries"),
        dict(name=_name, value=_join(_int(), _custom(("above limit", 11))), limit=_int(),
             what=_custom(("None", None), ("int", 3))), mention={"value": "n"}),
    "validation.check_symmetric": Spec(
        lambda: dict(name="Q", P=P2, rtol=1e-10), dict(name=_name, P=_sym, rtol=NONNEG),
        mention={"P": "Q"}),
    "validation.check_psd": Spec(
        lambda: dict(name="Q", P=P2, strict=True, tol=1e-10),
        dict(name=_name, P=_psd(strict=True), strict=_bool, tol=NONNEG), mention={"P": "Q"}),
    "validation.check_loewner_order": Spec(
        lambda: dict(name_low="G", low=0.5 * P2, name_high="Pi", high=P2, tol=1e-10),
        dict(name_low=_name, low=_join(_array(), _custom(("above", 3 * P2))), name_high=_name,
             high=_array(), tol=NONNEG), mention={"low": "G", "high": "Pi"}),
    "validation.check_row_stochastic": Spec(
        lambda: dict(name="W", W=H6, tol=1e-10, diagonal=False),
        dict(name=_name, W=_join(_stochastic, _custom(("diagonal", 0.5 * H6 + 0.5 * np.eye(6)))),
             tol=NONNEG, diagonal=_bool), mention={"W": "W"}),
    # ------------------------------------------------------------------ graphs
    "graphs.adjacency": Spec(lambda: dict(graph=__import__("networkx").cycle_graph(4)),
                             dict(graph=_join(_garbage, lambda v: [
                                 ("empty graph", __import__("networkx").Graph()),
                                 ("too many nodes", __import__("networkx").empty_graph(10_000)),
                                 ("unsortable labels", __import__("networkx").Graph([(1, "a")]))]))),
    "graphs.ring_graph": Spec(lambda: dict(n=5), dict(n=_int(3, huge=True))),
    "graphs.complete_graph": Spec(lambda: dict(n=5), dict(n=_int(2, huge=True))),
    "graphs.random_geometric_graph": Spec(
        lambda: dict(n=10, radius=0.6, seed=1, max_tries=100, return_positions=False),
        dict(n=_int(2, huge=True), radius=POS, seed=_seed, max_tries=_int(1, huge=True),
             return_positions=_bool)),
    "graphs.edge_list": Spec(lambda: dict(adj=RING6), dict(adj=_adj())),
    "graphs.ring_edges": Spec(lambda: dict(n=6, degree=2), dict(
        n=_int(3, huge=True), degree=_join(_int(2, huge=True), _custom(("odd", 3), ("not below n", 6))))),
    "graphs.complete_edges": Spec(lambda: dict(n=5), dict(n=_int(2, huge=True))),
    "graphs.random_geometric_edges": Spec(
        lambda: dict(n=10, radius=0.6, seed=1, max_tries=100, return_positions=False),
        dict(n=_int(2, huge=True), radius=POS, seed=_seed, max_tries=_int(1, huge=True),
             return_positions=_bool)),
    "graphs.check_connected_edges": Spec(
        lambda: dict(edges=np.argwhere(RING6 > 0), n=6, strongly=True),
        dict(edges=_join(_garbage, _custom(
            ("wrong shape", np.ones((3, 3), int)), ("float", np.argwhere(RING6 > 0) + 0.5),
            ("out of range", np.array([[0, 7]])), ("self loop", np.array([[0, 0], [0, 1]])),
            ("unsorted", np.argwhere(RING6 > 0)[::-1]), ("disconnected", np.argwhere(_TWO_RINGS > 0)))),
             n=_int(1, huge=True), strongly=_bool)),
    "graphs.check_connected": Spec(lambda: dict(adj=RING6, strongly=True),
                                   dict(adj=_adj(connected=True), strongly=_bool)),
    "graphs.neighbours": Spec(lambda: dict(adj=RING6, include_self=False), dict(adj=_adj(), include_self=_bool)),
    "graphs.row_stochastic_weights": Spec(
        lambda: dict(adj=RING6, self_weight=False),
        dict(adj=_adj(extra=[("isolated node", np.zeros((3, 3)))]), self_weight=_bool)),
    "graphs.check_row_stochastic": Spec(lambda: dict(weights=H6, tol=1e-10),
                                        dict(weights=_stochastic, tol=NONNEG)),
    "graphs.laplacian": Spec(lambda: dict(adj=RING6), dict(adj=_adj())),
    "graphs.algebraic_connectivity": Spec(
        lambda: dict(adj=RING6),
        dict(adj=_adj(connected=True, extra=[("directed", np.triu(RING6)), ("one node", np.zeros((1, 1)))]))),
    # ------------------------------------------------------------------ channels
    "channels.gilbert_elliott_transition": Spec(lambda: dict(p=0.1, q=0.9), dict(p=PROB, q=PROB)),
    "channels.gilbert_elliott_stationary": Spec(
        lambda: dict(p=0.0, q=0.9), dict(p=PROB, q=_join(PROB, _custom(("p + q = 0", 0.0))))),
    "channels.gilbert_elliott": Spec(
        lambda: dict(p=0.1, q=0.9, steps=20, rng=np.random.default_rng(0), initial=1, size=2),
        dict(p=PROB, q=PROB, steps=_int(1, huge=True), rng=_seed,
             initial=_custom(("2", 2), ("str", "a"), ("None", None), ("bool", True)),
             size=_int(1, huge=True, none_ok=True))),
    "channels.bernoulli": Spec(
        lambda: dict(prob=0.3, shape=(4,), rng=np.random.default_rng(0)),
        dict(prob=PROB, shape=_custom(("negative", -1), ("str", "a"), ("None", None), ("float", 2.5),
                                      ("absurd", (10**6, 10**6))), rng=_seed)),
    # ------------------------------------------------------------------ covariance
    "covariance.symmetrize": Spec(lambda: dict(P=P2), dict(P=ARRAY)),
    "covariance.min_eig": Spec(lambda: dict(P=P2), dict(P=ARRAY)),
    "covariance.is_psd": Spec(lambda: dict(P=P2, tol=1e-10, strict=False),
                              dict(P=_array(nan=False, shape=False), tol=NONNEG, strict=_bool)),
    "covariance.check_psd": Spec(lambda: dict(name="Q", P=P2, strict=False, tol=1e-10),
                                 dict(name=_name, P=_psd(), strict=_bool, tol=NONNEG), mention={"P": "Q"}),
    "covariance.joseph_update": Spec(
        lambda: dict(P=P2, K=np.ones((2, 1)), H=np.ones((1, 2)), R=np.eye(1), symmetrize_result=True),
        dict(P=_psd(), K=ARRAY, H=ARRAY, R=_psd(), symmetrize_result=_bool)),
    "covariance.information_fusion": Spec(
        lambda: dict(estimates=[np.zeros(2), np.ones(2)], covariances=[P2, np.eye(2)], weights=[0.3, 0.7]),
        dict(estimates=_sequence(ARRAY), covariances=_sequence(_psd(strict=True)),
             weights=_join(_array(), _custom(("sum 0.8", [0.4, 0.4]), ("negative", [-0.5, 1.5])))),
        none_ok={"weights"}),
    "covariance.covariance_intersection": Spec(
        lambda: dict(estimates=[np.zeros(2), np.ones(2)], covariances=[P2, np.eye(2)]),
        dict(estimates=_sequence(ARRAY), covariances=_sequence(_psd(strict=True)))),
    # ------------------------------------------------------------------ detectors
    "detectors.chi2_threshold": Spec(lambda: dict(dof=2, alpha=0.05), dict(dof=_int(1), alpha=PROB_OPEN)),
    "detectors.chi2_false_alarm": Spec(lambda: dict(dof=2, threshold=5.0),
                                       dict(dof=_int(1), threshold=_real(low=0.0, inf_ok=True))),
    "detectors.nis": Spec(lambda: dict(innovation=np.ones(2), S=P2),
                          dict(innovation=ARRAY, S=_psd(strict=True))),
    "detectors.chi2_alarm": Spec(lambda: dict(innovation=np.ones(2), S=P2, threshold=5.0),
                                 dict(innovation=ARRAY, S=_psd(strict=True), threshold=POS)),
    "detectors.chi2_passes": Spec(lambda: dict(innovation=np.ones(2), S=P2, threshold=5.0),
                                  dict(innovation=ARRAY, S=_psd(strict=True), threshold=POS)),
    "detectors.chi2_test": Spec(lambda: dict(innovation=np.ones(2), S=P2, threshold=5.0),
                                dict(innovation=ARRAY, S=_psd(strict=True), threshold=POS)),
    # ------------------------------------------------------------------ montecarlo
    "montecarlo.spawn_rngs": Spec(lambda: dict(seed=1, n=3), dict(seed=_seed, n=_int(1, huge=True))),
    "montecarlo.nees": Spec(lambda: dict(errors=np.ones((5, 2)), P=P2),
                            dict(errors=ARRAY, P=_psd(strict=True))),
    "montecarlo.anees_bounds": Spec(lambda: dict(dim=2, runs=10, confidence=0.95),
                                    dict(dim=_int(1), runs=_int(1), confidence=PROB_OPEN)),
    "montecarlo.wilson_interval": Spec(
        lambda: dict(successes=3, n=10, level=0.95),
        dict(successes=_join(_int(0), _custom(("above n", 11))), n=_int(1), level=PROB_OPEN)),
    "montecarlo.mean_interval": Spec(
        lambda: dict(samples=np.arange(5.0), level=0.95),
        dict(samples=_join(_array(shape=False), _custom(("one value", [1.0]))), level=PROB_OPEN)),
    "montecarlo.bootstrap_interval": Spec(
        lambda: dict(samples=np.arange(6.0), statistic="mean", level=0.9, n_boot=200, seed=0),
        dict(samples=_join(_array(shape=False), _custom(("one run", [1.0]), ("three columns", np.ones((4, 3))))),
             statistic=_choice, level=PROB_OPEN, n_boot=_int(100, huge=True), seed=_seed)),
    # ------------------------------------------------------------------ systems
    "systems.observability_matrix": Spec(lambda: dict(A=A3, C=BANKS[0], steps=3),
                                         dict(A=ARRAY, C=ARRAY, steps=_int(1, huge=True, none_ok=True))),
    "systems.observable_subspace": Spec(lambda: dict(A=A3, C=BANKS[0], rtol=1e-9),
                                        dict(A=ARRAY, C=ARRAY, rtol=RTOL)),
    "systems.unobservable_subspace": Spec(lambda: dict(A=A3, C=BANKS[0], rtol=1e-9),
                                          dict(A=ARRAY, C=ARRAY, rtol=RTOL)),
    "systems.observability_rank": Spec(lambda: dict(A=A3, C=BANKS[0], rtol=1e-9),
                                       dict(A=ARRAY, C=ARRAY, rtol=RTOL)),
    "systems.is_observable": Spec(lambda: dict(A=A3, C=BANKS[0], rtol=1e-9),
                                  dict(A=ARRAY, C=ARRAY, rtol=RTOL)),
    "systems.stack_banks": Spec(lambda: dict(C_banks=BANKS, n=3),
                                dict(C_banks=_sequence(ARRAY), n=_int(1, none_ok=True))),
    "systems.redundant_observability": Spec(
        lambda: dict(A=A3, C_banks=BANKS, q=1, rtol=1e-9),
        dict(A=ARRAY, C_banks=_join(_sequence(ARRAY), _custom(("2-D array", np.eye(3)))),
             q=_join(_int(0), _custom(("too large", 3))), rtol=RTOL)),
    "systems.redundant_observability/sizes": Spec(
        lambda: dict(A=np.diag(np.arange(1.0, 7.0)), C_banks=FORTY_BANKS, q=1),
        dict(q=_custom(("1.4e11 subsets", 10)))),
    "systems.discretize_zoh": Spec(lambda: dict(M=-np.eye(2), E=np.ones((2, 1)), dt=0.1),
                                   dict(M=ARRAY, E=_join(_array(shape=False), _custom(("wrong rows", np.ones((3, 1))))),
                                        dt=POS)),
    "systems.integrate_switched_linear": Spec(
        _integrator,
        dict(M=ARRAY, E_w=ARRAY, E_s=ARRAY, R=ARRAY, x0=ARRAY, dt=POS,
             w=_join(_callable, _custom(("returns wrong shape", lambda t: np.zeros(3)),
                                        ("returns str", lambda t: "a"), ("returns nan", lambda t: np.full(2, np.nan)))),
             phi=_join(_callable, _custom(("returns wrong shape", lambda r: np.zeros(5)),
                                          ("returns nan", lambda r: r * np.nan))),
             n_steps=_int(0, huge=True), record_every=_int(1), method=_choice)),
    # ------------------------------------------------------------------ estimation
    "estimation.relative_rank": Spec(lambda: dict(M=np.ones((2, 3)), rtol=1e-10),
                                     dict(M=_array(shape=False, empty=False), rtol=RTOL)),
    "estimation.feedthrough_decomposition": Spec(
        lambda: dict(H=np.array([[1.0], [0.0]]), R=P2, rtol=1e-10),
        dict(H=_join(_array(shape=False), _custom(("wrong rows", np.ones((3, 1))))), R=_psd(strict=True),
             rtol=RTOL)),
    "estimation.constrained_gain": Spec(
        lambda: dict(S=np.ones((3, 2)), Theta=P2, U1=np.array([[1.0], [0.0]])),
        dict(S=ARRAY, Theta=_join(ARRAY, _custom(("singular", np.zeros((2, 2))))),
             U1=_array(empty=False))),
    "estimation.ltv_observability_matrix": Spec(
        lambda: dict(A_seq=[A3, A3], C_seq=[BANKS[0], BANKS[1], BANKS[2]]),
        dict(A_seq=_join(_sequence(ARRAY), _custom(("too short", [A3]))), C_seq=_sequence(ARRAY))),
    # ------------------------------------------------------------------ filters
    "ding2020.matrix_min": Spec(lambda: dict(X=P2, Y=np.eye(2), tol=1e-10, strict=False),
                               dict(X=_sym, Y=_sym, tol=NONNEG, strict=_bool)),
    "ding2020.matrix_max": Spec(lambda: dict(X=P2, Y=np.eye(2), tol=1e-10, strict=False),
                               dict(X=_sym, Y=_sym, tol=NONNEG, strict=_bool)),
    "ding2020.received_indicator": Spec(lambda: dict(x_post=np.ones((6, 3)), delta=1, adj=RING6),
                                       dict(x_post=_join(_array(shape=False), _custom(("wrong nodes", np.ones((7, 3))))),
                                            delta=_delta, adj=_adj())),
    "ding2020.consensus_prediction": Spec(
        lambda: dict(x_post=np.ones((6, 3)), delta=1, adj=RING6, weights=H6, A=A3, kappa=0.1, validate=True),
        dict(x_post=ARRAY, delta=_delta, adj=_adj(connected=True), weights=_stochastic, A=ARRAY,
             kappa=NONNEG, validate=_bool)),
    "ding2020.secure_filter_step": Spec(_ding_step, FILTER_KINDS),
    "ding2020.secure_filter_node_step": Spec(_ding_node, NODE_KINDS),
    "ding2020.secure_filter": Spec(_ding_run, RUN_KINDS),
    "ding2020.constant_gain_filter": Spec(
        lambda: dict(x0=np.ones((6, 3)), delta=np.ones(4), y=np.zeros((5, 6)), A=A3, C=C6[:, 0],
                     gains=np.full((6, 3), 0.1), adj=RING6, weights=H6, kappa=0.004, form="corrector",
                     validate=True),
        dict(x0=ARRAY, delta=_run_delta, y=ARRAY, A=ARRAY, C=ARRAY, gains=ARRAY, adj=_adj(connected=True),
             weights=_stochastic, kappa=NONNEG, form=_choice, validate=_bool)),
    "ding2020.theorem4_condition": Spec(
        lambda: dict(A=A3, C=C6[:, 0], p=0.1, q=0.92, kappa=0.004, n_bar=3, nu=0.0, sigma=1e-6, factor=1.0),
        dict(A=ARRAY, C=_join(ARRAY, _custom(("zero row", np.zeros((6, 3))))), p=PROB, q=PROB, kappa=NONNEG,
             n_bar=_int(1), nu=PROB, sigma=PROB, factor=NONNEG)),
    "ding2020.exact_error_covariance": Spec(
        lambda: dict(gains=np.zeros((4, 6, 3)), delta=np.ones(4), P0=np.eye(18), A=A3, B=0.2 * np.eye(3),
                     C=C6[:, 0], D=0.05, weights=H6, kappa=0.004),
        dict(gains=ARRAY, delta=_join(_array(shape=False), _custom(("0.5", np.full(4, 0.5)), ("too short", np.ones(2)))),
             P0=_psd(), A=ARRAY, B=_array(shape=False), C=ARRAY, D=_real(), weights=ARRAY, kappa=NONNEG)),
    "ding2020.example": Spec(
        lambda: dict(m=20, T=0.05, gains_low=[0.4177, 0.5799, 0.4029], gains_high=[0.2883, 0.6150, 0.4457]),
        dict(m=_int(1), T=POS, gains_low=ARRAY, gains_high=ARRAY)),
    # ------------------------------------------------------------------ schedules
    "schedules.rrl_map_period": Spec(lambda: dict(m=2, n_y=4),
                                     dict(m=_join(_int(1), _custom(("m > n_y", 5))), n_y=_int(1, huge=True))),
    "schedules.rrl_map_phase": Spec(lambda: dict(k=[1, 2, 3], m=2, n_y=4),
                                    dict(k=_custom(("zero", 0), ("float", 1.5), ("str", "a"), ("None", None),
                                                   ("ragged", [[1, 2], [3]]), ("overflow", 2**62)),
                                         m=_int(1), n_y=_int(1, huge=True))),
    "schedules.rrl_map_sets": Spec(lambda: dict(k=[1, 2, 3], m=2, n_y=4),
                                   dict(k=_custom(("zero", 0), ("float", 1.5), ("str", "a"), ("None", None),
                                                  ("overflow", 2**62)),
                                        m=_int(1), n_y=_int(1, huge=True))),
    "schedules.rrl_map_selector": Spec(lambda: dict(k=[1, 2], m=2, n_y=4),
                                       dict(k=_custom(("zero", 0), ("str", "a"), ("None", None)),
                                            m=_int(1), n_y=_int(1, huge=True))),
    "schedules.zero_input_update": Spec(
        lambda: dict(y=np.ones(4), k=1, m=2, n_y=4),
        dict(y=ARRAY, k=_custom(("zero", 0), ("array", [1, 2]), ("str", "a"), ("None", None)),
             m=_int(1), n_y=_int(1))),
    "schedules.rrl_map_window_counts": Spec(
        lambda: dict(sets=[[0, 1], [2, 3], [0, 1], [2, 3]], n_y=4, window=2, m=2),
        dict(sets=_custom(("str", "a"), ("None", None), ("floats", [[0.5, 1.0]]), ("out of range", [[0, 9]]),
                          ("repeated sensor", [[1, 1], [2, 3]]), ("ragged", [[0, 1], [2]])),
             n_y=_int(1, huge=True), window=_join(_int(1, none_ok=True), _custom(("too long", 9))),
             m=_int(1, none_ok=True))),
    # ------------------------------------------------------------------ lmi
    "lmi.symmetrize": Spec(lambda: dict(m=P2), dict(m=_array(shape=True, empty=True))),
    "lmi.block_diag": Spec(lambda: dict(blocks=[np.eye(1), P2]),
                           dict(blocks=_custom(("str", "a"), ("None", None), ("empty", []), ("None block", [None]),
                                               ("3-D block", [np.ones((2, 2, 2))]), ("str block", ["a"])))),
    "lmi.block_symmetric": Spec(
        lambda: dict(lower=[[P2], [np.ones((1, 2)), np.eye(1)]], sizes=None),
        dict(lower=_custom(("str", "a"), ("None", None), ("empty", []), ("non-square diagonal", [[np.ones((2, 3))]]),
                           ("mismatch", [[P2], [np.ones((1, 3)), np.eye(1)]]), ("row not a list", [P2])),
             sizes=_custom(("str", "a"), ("zero", [0, 1]), ("float", [2.5, 1]), ("wrong length", [2])))),
    "lmi.lmi": Spec(lambda: dict(m=_expr(), eps=1e-6),
                    dict(m=_custom(("numpy array", P2), ("str", "a"), ("None", None)), eps=NONNEG)),
    "lmi.max_eigenvalue": Spec(lambda: dict(m=P2), dict(m=ARRAY)),
    "lmi.solve_certified": Spec(
        lambda: dict(zip(("problem", "lmis"), _lmi_fixture(), strict=True), step=0, node=1,
                     solver="CLARABEL", fallback=None, tol=1e-8, eps=1e-6, certify="margin",
                     solver_opts=None, fallback_opts=None),
        dict(problem=_garbage, lmis=_custom(("empty", {}), ("None", None), ("str", "a"), ("value not expr", {"m": 1})),
             step=_custom(("str", "a"), ("float", 1.5)), node=_custom(("list", [1]), ("float", 1.5)),
             solver=_custom(("unknown", "NOPE"), ("None", None), ("int", 3)),
             fallback=_custom(("unknown", "NOPE"), ("int", 3)), tol=NONNEG, eps=NONNEG, certify=_choice,
             solver_opts=_custom(("str", "a"), ("list", [1])), fallback_opts=_custom(("str", "a"))))
}


# ----------------------------------------------------------------------------- the sweep
@dataclass
class Outcome:
    call: str
    param: str
    variant: str
    kind: str  # clear / unclear / silent
    detail: str


class _Timeout(BaseException):
    """Raised by the alarm; a BaseException so that library code cannot swallow it."""


def _alarm(signum: int, frame: Any) -> None:
    raise _Timeout


def _classify(func: Callable, kwargs: dict, mention: str) -> tuple[str, str]:
    from secest.core.validation import ValidationError

    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, TIME_LIMIT)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = func(**kwargs)
    except _Timeout:
        return "silent", f"still running after {TIME_LIMIT} s"
    except ValidationError as exc:
        named = re.search(rf"(?<![A-Za-z0-9_]){re.escape(mention)}(?![A-Za-z0-9_])", str(exc))
        return ("clear" if named else "unclear"), f"ValidationError: {exc}"
    except Exception as exc:  # noqa: BLE001 - any other exception is an unclear refusal
        return "unclear", f"{type(exc).__name__}: {str(exc)[:160]}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    return "silent", f"returned {type(result).__name__}"


def public_callables() -> dict[str, Callable]:
    """``"module.name" -> object`` for every public callable of :data:`MODULES`."""
    out = {}
    for mod_name, module in MODULES.items():
        mod = importlib.import_module(module)
        names = getattr(mod, "__all__", [n for n in vars(mod) if not n.startswith("_")])
        for name in names:
            obj = getattr(mod, name)
            if callable(obj):
                out[f"{mod_name}.{name}"] = obj
    return out


def cases() -> Iterator[tuple[str, str, str, Callable, dict, str]]:
    """Every adversarial call: (callable, parameter, variant, function, kwargs, name to mention)."""
    funcs = public_callables()
    for key, spec in SPECS.items():
        target = key.split("/")[0]
        if target not in funcs:
            continue
        func = funcs[target]
        params = inspect.signature(func).parameters
        for param, kind in spec.kinds.items():
            if param not in params:
                continue
            base = {k: v for k, v in spec.valid().items() if k in params}
            for variant, value in kind(base[param]):
                if value is None and (param in spec.none_ok or params[param].default is None):
                    continue
                kwargs = spec.valid()
                kwargs = {k: v for k, v in kwargs.items() if k in params}
                kwargs[param] = value
                yield target, param, variant, func, kwargs, spec.mention.get(param, param)


def sweep() -> list[Outcome]:
    """Run every adversarial call and classify its outcome."""
    return [Outcome(name, param, variant, *_classify(func, kwargs, mention))
            for name, param, variant, func, kwargs, mention in cases()]


def valid_calls_fail() -> dict[str, str]:
    """The declared valid calls that do not succeed (a broken spec), with the error."""
    funcs = public_callables()
    bad = {}
    for key, spec in SPECS.items():
        target = key.split("/")[0]
        if target not in funcs:
            continue
        params = inspect.signature(funcs[target]).parameters
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                funcs[target](**{k: v for k, v in spec.valid().items() if k in params})
        except Exception as exc:  # noqa: BLE001
            bad[key] = f"{type(exc).__name__}: {exc}"
    return bad


def counts(outcomes: list[Outcome]) -> dict[str, int]:
    c = Counter(o.kind for o in outcomes)
    return {"tried": len(outcomes), "clear": c["clear"], "unclear": c["unclear"], "silent": c["silent"]}


# ----------------------------------------------------------------------------- tests
def test_every_public_callable_is_swept() -> None:
    swept = {k.split("/")[0] for k in SPECS}
    missing = sorted(set(public_callables()) - swept - NOT_CALLS)
    assert not missing, f"add a Spec for: {missing}"


def test_declared_valid_calls_succeed() -> None:
    assert valid_calls_fail() == {}


def test_every_invalid_call_is_refused_clearly_and_quickly() -> None:
    t0 = time.perf_counter()
    outcomes = sweep()
    elapsed = time.perf_counter() - t0
    bad = [f"{o.call}({o.param}={o.variant}): {o.kind}: {o.detail}" for o in outcomes if o.kind != "clear"]
    print(f"\nadversarial sweep: {counts(outcomes)} in {elapsed:.1f} s")
    assert not bad, "\n".join(bad)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Adversarial sweep of the secest core API")
    parser.add_argument("--verbose", action="store_true", help="list every call that is not clear")
    parser.add_argument("--memory-gb", type=float, default=4.0, help="address-space limit of this process")
    parser.add_argument("--json", default=None, help="write every outcome to this JSON file")
    args = parser.parse_args(argv)
    import resource

    limit = int(args.memory_gb * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    import secest

    broken = valid_calls_fail()
    t0 = time.perf_counter()
    outcomes = [o for o in sweep() if o.call not in {k.split("/")[0] for k in broken}]
    print(f"secest at {secest.__file__}")
    print(f"callables swept: {len({o.call for o in outcomes})}, skipped (valid call fails): {sorted(broken)}")
    print(counts(outcomes), f"in {time.perf_counter() - t0:.1f} s")
    if args.json:
        import json

        with open(args.json, "w") as fh:
            json.dump([vars(o) for o in outcomes], fh, indent=0)
    if args.verbose:
        for o in outcomes:
            if o.kind != "clear":
                print(f"{o.kind:8s} {o.call}({o.param}={o.variant}): {o.detail}")


if __name__ == "__main__":
    sys.exit(main())
