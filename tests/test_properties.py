"""Property-based tests (Hypothesis) of the public API of the secest core.

Random valid inputs must give finite, well-shaped results with the documented invariants
(symmetry, PSD, row sums, monotone bounds); random invalid inputs must give a
``ValidationError`` -- never another exception, never a silent result. The profile is
derandomized (same examples on every run) and small enough for ``make test``.
"""

from __future__ import annotations

import warnings
from math import lcm

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from secest.core import (
    channels,
    covariance,
    detectors,
    graphs,
    montecarlo,
    schedules,
    systems,
)
from secest.core.validation import ValidationError, check_psd, check_real
from secest.methods import ding2020, guo2023

settings.register_profile(
    "secest-ci",
    derandomize=True,
    max_examples=100,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
CI = settings.get_profile("secest-ci")

FLOATS = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
SCALES = st.sampled_from([1e-12, 1e-6, 1.0, 1e6, 1e12])


@st.composite
def spd(draw, n: int | None = None, *, psd_only: bool = False) -> np.ndarray:
    """A symmetric PSD (PD unless ``psd_only``) matrix of any scale and rotation."""
    n = draw(st.integers(1, 5)) if n is None else n
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    lam = rng.uniform(0.1, 10.0, n)
    if psd_only and n > 1:
        lam[0] = 0.0
    P = draw(SCALES) * (Q * lam) @ Q.T
    return 0.5 * (P + P.T)


@st.composite
def connected_graph(draw) -> np.ndarray:
    n = draw(st.integers(2, 9))
    seed = draw(st.integers(0, 2**32 - 1))
    return graphs.random_geometric_graph(n, 0.8, seed)


# ---------------------------------------------------------------- covariance
@CI
@given(spd(psd_only=True))
def test_psd_matrices_of_any_scale_pass_the_relative_check(P) -> None:
    check_psd("P", P)
    assert covariance.is_psd(P)


@CI
@given(spd(), st.floats(1e-3, 1.0))
def test_shifting_below_zero_is_refused(P, frac) -> None:
    rho = float(np.abs(np.linalg.eigvalsh(P)).max())
    with pytest.raises(ValidationError, match="P must be positive semidefinite"):
        check_psd("P", P - (np.linalg.eigvalsh(P)[0] + frac * rho) * np.eye(P.shape[0]))


@CI
@given(st.integers(1, 4).flatmap(
    lambda n: hnp.arrays(np.float64, st.tuples(st.integers(1, 3), st.just(n), st.just(n)), elements=FLOATS)))
def test_symmetrize_is_a_symmetric_projection(M) -> None:
    S = covariance.symmetrize(M)
    assert np.array_equal(S, np.swapaxes(S, -1, -2))
    assert np.allclose(covariance.symmetrize(S), S)
    lam = covariance.min_eig(M)
    assert np.all(lam <= np.diagonal(S, axis1=-2, axis2=-1).min(axis=-1) + 1e-9)


@CI
@given(spd(3), spd(2), hnp.arrays(np.float64, (3, 2), elements=FLOATS), hnp.arrays(np.float64, (2, 3), elements=FLOATS))
def test_joseph_update_is_psd_for_any_gain(P, R, K, H) -> None:
    out = covariance.joseph_update(P, K, H, R)
    assert out.shape == (3, 3) and np.array_equal(out, out.T)
    rho = max(np.abs(np.linalg.eigvalsh(out)).max(), 1e-300)
    assert np.linalg.eigvalsh(out)[0] >= -1e-10 * rho


@CI
@given(st.lists(spd(2), min_size=1, max_size=4), st.data())
def test_information_fusion_is_a_consistent_pd_bound(covs, data) -> None:
    w = np.asarray(data.draw(st.lists(st.floats(0.01, 1.0), min_size=len(covs), max_size=len(covs))))
    w = w / w.sum()
    xs = [np.arange(2.0) * i for i in range(len(covs))]
    x, P = covariance.information_fusion(xs, covs, w)
    assert x.shape == (2,) and np.all(np.isfinite(x))
    check_psd("P", P, strict=True)
    # guo2023's fusion (19)-(20), the one library implementation, gives the same bound
    P2, W, x2 = guo2023.fuse(np.stack(covs), w[None], np.stack(xs)[None])  # one node fusing all
    np.testing.assert_allclose(P, P2[0], rtol=1e-9)
    np.testing.assert_allclose(W[0].sum(axis=0), np.eye(2), atol=1e-8)
    np.testing.assert_allclose(x2[0], x, rtol=1e-8, atol=1e-8)


# ---------------------------------------------------------------- graphs and channels
@CI
@given(connected_graph(), st.booleans())
def test_weights_are_row_stochastic_on_the_edges(adj, self_weight) -> None:
    H = graphs.row_stochastic_weights(adj, self_weight=self_weight)
    graphs.check_row_stochastic(H)
    off = ~np.eye(adj.shape[0], dtype=bool)
    assert np.array_equal(H[off] > 0, adj[off] > 0)
    assert np.all(np.diag(H) > 0) == self_weight
    graphs.check_connected(adj)
    assert graphs.algebraic_connectivity(adj) > 0
    np.testing.assert_allclose(graphs.laplacian(adj).sum(axis=1), 0.0)


@CI
@given(st.floats(0, 1), st.floats(0, 1), st.integers(1, 50), st.integers(0, 2**32 - 1), st.sampled_from([0, 1]))
def test_gilbert_elliott_paths(p, q, steps, seed, initial) -> None:
    d = channels.gilbert_elliott(p, q, steps, seed, initial=initial)
    assert d.shape == (steps,) and set(np.unique(d)) <= {0, 1} and d[0] == initial
    P = channels.gilbert_elliott_transition(p, q)
    np.testing.assert_allclose(P.sum(axis=1), 1.0)
    if p + q > 0:
        pi = channels.gilbert_elliott_stationary(p, q)
        np.testing.assert_allclose(np.array([1 - pi, pi]) @ P, [1 - pi, pi], atol=1e-12)


# ---------------------------------------------------------------- detectors and Monte Carlo
@CI
@given(st.integers(1, 20), st.floats(1e-6, 0.5))
def test_threshold_and_false_alarm_are_inverse(dof, alpha) -> None:
    tau = detectors.chi2_threshold(dof, alpha)
    assert detectors.chi2_false_alarm(dof, tau) == pytest.approx(alpha, rel=1e-6)


@CI
@given(spd(3), hnp.arrays(np.float64, (4, 3), elements=FLOATS), st.floats(0.1, 50))
def test_alarm_is_the_negation_of_passing(S, r, tau) -> None:
    g = detectors.nis(r, S)
    assert g.shape == (4,) and np.all(g >= 0)
    assert np.array_equal(detectors.chi2_alarm(r, S, tau), ~detectors.chi2_passes(r, S, tau))


@CI
@given(st.integers(1, 200), st.data(), st.floats(0.5, 0.999))
def test_wilson_interval_brackets_the_fraction(n, data, level) -> None:
    k = data.draw(st.integers(0, n))
    lo, hi = montecarlo.wilson_interval(k, n, level)
    assert 0.0 <= lo <= k / n <= hi <= 1.0


# ---------------------------------------------------------------- schedules and systems
@CI
@given(st.integers(1, 12), st.data())
def test_rrl_map_is_fair(n_y, data) -> None:
    m = data.draw(st.integers(1, n_y))
    U = schedules.rrl_map_period(m, n_y)
    sets = schedules.rrl_map_sets(np.arange(1, 3 * U + 1), m, n_y)
    counts = schedules.rrl_map_window_counts(sets, n_y)
    assert np.all(counts == lcm(m, n_y) // n_y)


@CI
@given(st.integers(1, 5), st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_observable_subspace_is_orthonormal_and_complementary(n, p, seed) -> None:
    rng = np.random.default_rng(seed)
    A, C = rng.standard_normal((n, n)), rng.standard_normal((p, n))
    Q = systems.observable_subspace(A, C)
    U = systems.unobservable_subspace(A, C)
    assert Q.shape[1] + U.shape[1] == n
    np.testing.assert_allclose(np.hstack([Q, U]).T @ np.hstack([Q, U]), np.eye(n), atol=1e-9)
    np.testing.assert_allclose(C @ U, 0.0, atol=1e-8 * max(1.0, np.abs(C).max()))


# ---------------------------------------------------------------- the secure filter
@st.composite
def filter_inputs(draw):
    adj = draw(connected_graph())
    m, n = adj.shape[0], 3
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    Pi = np.stack([draw(spd(n)) for _ in range(m)])
    frac = draw(st.floats(0.0, 1.0))
    return dict(
        x_post=rng.standard_normal((m, n)), Pi_post=Pi, Gamma_post=frac * Pi,
        delta=draw(st.sampled_from([0, 1])), y=rng.standard_normal((m, 1)),
        A=np.eye(n) + 0.1 * rng.standard_normal((n, n)), BBt=draw(spd(n, psd_only=True)),
        C=rng.standard_normal((m, 1, n)), DDt=np.array([[draw(st.floats(1e-3, 10.0))]]), adj=adj,
        weights=graphs.row_stochastic_weights(adj), kappa=draw(st.floats(0.0, 0.5)),
        threshold=draw(st.floats(0.5, 50.0)),
    )


@settings(parent=CI, max_examples=40)
@given(filter_inputs())
def test_secure_filter_step_invariants(kw) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ding2020.FilterHealthWarning)  # flags are checked below
        st_ = ding2020.secure_filter_step(**kw)
        jo = ding2020.secure_filter_step(**kw, joseph=True)
    m, n = kw["x_post"].shape
    for M in (st_.Pi_post, st_.Gamma_post, st_.Pi_prior, st_.Gamma_prior):
        assert M.shape == (m, n, n) and np.all(np.isfinite(M))
        assert np.array_equal(M, np.swapaxes(M, -1, -2))
    assert st_.x_post.shape == (m, n) and np.all(np.isfinite(st_.x_post))
    scale = np.abs(np.linalg.eigvalsh(st_.Pi_prior)).max(axis=-1)
    # (35) never increases the bound; Gamma^+ = min{...} <= Gamma^-; an accepted node updates
    assert np.all(np.linalg.eigvalsh(st_.Pi_prior - st_.Pi_post)[..., 0] >= -1e-9 * scale)
    g_scale = np.abs(np.linalg.eigvalsh(st_.Gamma_prior)).max(axis=-1)
    assert np.all(np.linalg.eigvalsh(st_.Gamma_prior - st_.Gamma_post)[..., 0] >= -1e-9 * g_scale)
    assert np.all(np.isin(st_.theta, (0.0, 1.0))) and np.array_equal(st_.rejections, (st_.theta == 0) * 1)
    np.testing.assert_allclose(jo.Pi_post, st_.Pi_post, rtol=1e-6, atol=1e-9 * scale.max())
    assert jo.joseph and np.all(jo.Pi_psd)


@CI
@given(spd(3), spd(3))
def test_matrix_min_and_max_bound_both_arguments(X, Y) -> None:
    lo, _ = ding2020.matrix_min(X, Y)
    hi, _ = ding2020.matrix_max(X, Y)
    scale = max(np.abs(np.linalg.eigvalsh(X)).max(), np.abs(np.linalg.eigvalsh(Y)).max())
    for Z in (X, Y):
        assert np.linalg.eigvalsh(Z - lo)[0] >= -1e-9 * scale
        assert np.linalg.eigvalsh(hi - Z)[0] >= -1e-9 * scale


# ---------------------------------------------------------------- random invalid inputs
ANYTHING = st.one_of(
    st.none(), st.booleans(), st.text(max_size=5), st.integers(-10**15, 10**15),
    st.floats(allow_nan=True, allow_infinity=True), st.lists(st.floats(), max_size=3),
    st.lists(st.text(max_size=2), max_size=3), st.complex_numbers(),
)


def _refused_or_valid(call, value, valid) -> None:
    """``call(value)`` succeeds if ``valid(value)``, else raises ValidationError -- nothing else."""
    try:
        call(value)
    except ValidationError:
        assert not valid(value), f"valid value {value!r} refused"
        return
    assert valid(value), f"invalid value {value!r} accepted"


def _is_real(v) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and np.isfinite(v)


@CI
@given(ANYTHING)
def test_random_kappa(value) -> None:
    adj = graphs.ring_graph(4)
    _refused_or_valid(
        lambda k: ding2020.consensus_prediction(np.ones((4, 2)), 1, adj, graphs.row_stochastic_weights(adj),
                                               np.eye(2), k),
        value, lambda v: _is_real(v) and v >= 0)


@CI
@given(ANYTHING)
def test_random_probability(value) -> None:
    _refused_or_valid(lambda p: channels.gilbert_elliott_transition(p, 0.5), value,
                      lambda v: _is_real(v) and 0 <= v <= 1)


@CI
@given(ANYTHING)
def test_random_seed(value) -> None:
    _refused_or_valid(lambda s: montecarlo.spawn_rngs(s, 2), value,
                      lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 0)


@CI
@given(ANYTHING)
def test_random_size(value) -> None:
    _refused_or_valid(graphs.complete_graph, value,
                      lambda v: isinstance(v, int) and not isinstance(v, bool) and 2 <= v <= 5000)


@CI
@given(hnp.arrays(np.float64, st.tuples(st.integers(1, 4), st.integers(1, 4)),
                  elements=st.floats(allow_nan=True, allow_infinity=True, width=64)))
def test_random_matrices_into_check_psd(M) -> None:
    def valid(v: np.ndarray) -> bool:
        if v.shape[0] != v.shape[1] or not np.all(np.isfinite(v)):
            return False
        u = v / (np.abs(v).max() or 1.0)  # the rule is scale-invariant; avoid overflow
        if np.abs(u - u.T).max() > 1e-10:
            return False
        lam = np.linalg.eigvalsh(0.5 * (u + u.T))
        return bool(lam[0] >= -1e-10 * np.abs(lam).max())

    _refused_or_valid(lambda v: check_psd("M", v), M, valid)


@CI
@given(ANYTHING)
def test_random_real(value) -> None:
    _refused_or_valid(lambda v: check_real("x", v, lower=0.0), value, lambda v: _is_real(v) and v >= 0)
