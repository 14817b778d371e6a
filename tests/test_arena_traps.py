"""The silent traps of issue #29, one test each: every one now fails with a one-line error that
names the card key or argument and what was expected (the message is matched whole).

The traps listed in the issue come first, then those found while checking them (cards that ran
another graph, or truncated or ignored a value, without a word).
"""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

from secest.arena import estimators, matrix, scenarios
from secest.arena.estimators import METHODS, Estimate, Method, register
from secest.core.validation import SizeLimitError, ValidationError

BIAS = {"title": "a bias", "kind": "bias", "nodes": [0], "start": 0.3, "magnitude": 40.0}
RING = {"title": "t", "plant": "target", "N": 5, "graph": "ring", "measures": [[0]] * 5}
PLANT = {"title": "t", "source": "s", "Ac": [[0.0, 1.0], [0.0, 0.0]], "dt": 0.1, "q_std": 0.1,
         "outputs": [[1.0, 0.0]], "r_std": [0.1], "x0_std": 1.0, "state_names": ["p", "v"]}


def _refused(call, pattern: str, error: type[Exception] = ValidationError) -> str:
    """Run ``call``; it must raise ``error`` with a one-line message matching ``pattern`` whole."""
    with pytest.raises(error) as info:
        call()
    text = str(info.value)
    assert "\n" not in text
    assert re.fullmatch(pattern, text), text
    return text


def _card(kind: str, card: dict, drop: tuple[str, ...] = ()) -> dict:
    return {kind: {"mine": {k: v for k, v in card.items() if k not in drop}}}


@pytest.fixture(scope="module")
def small() -> tuple[scenarios.Scenario, scenarios.Trial, Estimate]:
    sc = scenarios.scenario("inertia5", "none", runs=3, horizon=10)
    trial = scenarios.simulate(sc)
    return sc, trial, METHODS["oracle"].run(trial)


# ------------------------------------------------------------------------- the traps


def test_the_five_methods_are_registered_without_importing_secest_methods() -> None:
    code = ("from secest.arena import matrix; from secest.arena.estimators import METHODS; "
            "print(','.join(METHODS))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    names = out.stdout.strip().split(",")
    assert {"ding2020", "guo2023", "lee2020", "li2025", "ma2021"} <= set(names)
    assert names[:3] == ["oracle", "kf", "chi2-kf"]
    assert {"local-kf", "consensus-kf-1", "consensus-kf", "diffusion-kf", "kcf", "wmsr-kf"} <= set(names)


def test_a_method_named_oracle_is_refused() -> None:
    class Impostor(Method):
        name = "oracle"

    _refused(lambda: register(Impostor, replace=True),
             r"method name 'oracle' is reserved \(the reference of every score\)")
    assert type(METHODS["oracle"]).__name__ == "Oracle"


def test_a_taken_name_is_refused_unless_replace() -> None:
    class Twin(Method):
        name = "kf"

    _refused(lambda: register(Twin), r"method name 'kf' is already registered \(UndefendedKF\); "
             r"pass replace=True to replace it")
    assert type(METHODS["kf"]).__name__ == "UndefendedKF"


def test_a_misspelt_magnitude_is_refused_with_the_nearest_key() -> None:
    extra = _card("attack", {**BIAS, "magnitud": 40.0}, drop=("magnitude",))
    _refused(lambda: scenarios.cards(extra=extra), r"attack mine: unknown key 'magnitud' "
             r"\(did you mean 'magnitude'\?\); valid: \[.*'magnitude'.*\]")


def test_a_bias_without_nodes_is_refused() -> None:
    _refused(lambda: scenarios.cards(extra=_card("attack", BIAS, drop=("nodes",))),
             r"attack mine: missing key\(s\) \['nodes'\]")


def test_a_start_outside_the_horizon_is_refused() -> None:
    _refused(lambda: scenarios.cards(extra=_card("attack", {**BIAS, "start": 1.5})),
             r"attack mine: start must lie in \[0, 1\), found 1\.5")


def test_a_negative_node_index_is_refused() -> None:
    _refused(lambda: scenarios.cards(extra=_card("attack", {**BIAS, "nodes": [-1]})),
             r"attack mine: nodes must be a non-empty list of node indices >= 0, found \[-1\]")


def test_a_node_index_beyond_the_network_is_refused() -> None:
    extra = _card("attack", {**BIAS, "nodes": [7]})
    _refused(lambda: scenarios.scenario("inertia5", "mine", extra=extra),
             r"attack mine: nodes \(7,\) do not all exist in inertia5")


def test_an_estimate_for_fewer_nodes_is_refused(small) -> None:
    _, trial, oracle = small
    _refused(lambda: estimators.score(trial, Estimate(oracle.xhat[:, :, :-1]), oracle),
             r"Incompatible dimensions of estimate\.xhat: expected \(3, 11, 5, 6\) "
             r"\(runs, K \+ 1, nodes, states\), found \(3, 11, 4, 6\)")


def test_an_estimate_of_fewer_state_components_is_refused(small) -> None:
    _, trial, oracle = small
    _refused(lambda: estimators.score(trial, Estimate(oracle.xhat[..., :1]), oracle),
             r"Incompatible dimensions of estimate\.xhat: expected \(3, 11, 5, 6\) "
             r"\(runs, K \+ 1, nodes, states\), found \(3, 11, 5, 1\)")


def test_a_trial_of_another_scenario_is_refused(small) -> None:
    sc, _, _ = small
    other = scenarios.simulate(scenarios.scenario("inertia5", "bias", runs=3, horizon=10))
    _refused(lambda: estimators.evaluate(sc, ["oracle"], trial=other),
             r"trial: drawn for scenario 'inertia5/bias', not for 'inertia5/none'")


def test_a_horizon_without_a_steady_window_is_refused(small) -> None:
    sc, trial, oracle = small
    expected = (r"horizon of inertia5/none: 10 steps give no steady window; at least 20 tau = 2857 "
                r"steps \(tau = 143 steps; horizon = \"auto\" gives 2860\)")
    _refused(lambda: estimators.score(trial, oracle, oracle), expected)
    _refused(lambda: matrix.run_matrix([sc], ["oracle"]), expected)


def test_run_sweep_with_zero_workers_is_refused() -> None:
    from secest.repro import sweep

    _refused(lambda: sweep.run_sweep(["guo2023"], workers=0, progress=False),
             r"workers must be >= 1, found 0")


def test_a_huge_network_is_refused_before_allocation() -> None:
    """Networks are edge lists: 10^5 nodes on a ring are fine, 10^10 edges or 10^9 nodes are not."""
    extra = _card("network", {**RING, "N": 10**5, "graph": "complete", "measures": [[0]]})
    _refused(lambda: scenarios.cards(extra=extra),
             r"network mine: N \(N - 1\) asks for 1e\+10 edges of a complete network, more than the "
             r"limit .*", SizeLimitError)
    extra = _card("network", {**RING, "N": 10**9, "measures": [[0]]})
    _refused(lambda: scenarios.cards(extra=extra),
             r"network mine: N asks for 1e\+09 nodes of a network, more than the limit .*", SizeLimitError)


def test_a_huge_horizon_is_refused_before_allocation() -> None:
    _refused(lambda: scenarios.scenario("inertia5", "none", horizon=10**9),
             r"horizon asks for 1e\+09 steps, more than the limit .*", SizeLimitError)


# ------------------------------------------------------------------ found while checking them


@pytest.mark.parametrize("degree", [3, 6])
def test_a_ring_degree_that_is_odd_or_not_below_n_is_refused(degree: int) -> None:
    """Degree 3 ran a ring of degree 2, degree 6 on 5 nodes the complete graph, silently."""
    _refused(lambda: scenarios.cards(extra=_card("network", {**RING, "degree": degree})),
             rf"network mine: degree must be even and below N = 5, found {degree}")


def test_fractional_measured_rows_are_refused() -> None:
    """measures = [[0.7], ...] was truncated to row 0."""
    _refused(lambda: scenarios.cards(extra=_card("network", {**RING, "measures": [[0.7]] * 5})),
             r"network mine: measures must be a list \(one per node\) of lists of output indices "
             r"\(integers\), found .*")


def test_a_fractional_rgg_seed_is_refused() -> None:
    """seed = 1.5 was truncated to 1."""
    card = {**RING, "graph": "rgg", "radius": 0.9, "seed": 1.5}
    _refused(lambda: scenarios.cards(extra=_card("network", card)),
             r"network mine: seed must be an integer, found 1\.5")


def test_state_names_of_the_wrong_length_are_refused() -> None:
    _refused(lambda: scenarios.cards(extra=_card("plant", {**PLANT, "state_names": ["p"]})),
             r"plant mine: state_names must list 2 names \(one per state component\), found \['p'\]")


@pytest.mark.parametrize("dt, found", [("0.1", "must be a real number, found '0.1'"),
                                       (float("inf"), "must be a finite real number, found inf")])
def test_a_sampling_period_that_is_no_finite_number_is_refused(dt: object, found: str) -> None:
    _refused(lambda: scenarios.cards(extra=_card("plant", {**PLANT, "dt": dt})),
             rf"plant mine: dt {found}")


def test_a_misspelt_matrix_key_of_an_extra_file_is_refused() -> None:
    """[matrix] network = [...] in an extra file was ignored: the cross ran without it."""
    _refused(lambda: scenarios.cards(extra={"matrix": {"network": ["inertia5"]}}),
             r"extra cards: \[matrix\]: unknown key 'network' \(did you mean 'networks'\?\); "
             r"valid: \['attacks', 'networks'\]")


def test_a_horizon_in_an_extra_matrix_is_refused() -> None:
    """[matrix] horizon = 5 in an extra file was ignored: the package's horizon ran."""
    _refused(lambda: scenarios.cards(extra={"matrix": {"horizon": 5}}),
             r"extra cards: \[matrix\] horizon is not read from an extra file; pass horizon= to "
             r"matrix\(\) or scenario\(\) \(--horizon on the command line\)")



# ------------------------------------------------------------- found by the API sweep (issue #29)


@pytest.mark.parametrize("change, pattern", [
    ({"start": 1.0}, r"attack mine: start must lie in \[0, 1\), found 1\.0"),
    ({"nodes": [0, 0]}, r"attack mine: nodes must be distinct, found \[0, 0\]"),
    ({"title": 5}, r"attack mine: title must be a non-empty string, found 5"),
    ({"kin": "bias", "kind": None}, r"attack mine: unknown key 'kin' \(did you mean 'kind'\?\); "
                                    r"valid: \[.*'kind'.*\]"),
])
def test_a_bias_card_that_ran_silently_is_refused(change: dict, pattern: str) -> None:
    """start = 1 attacked the last step only; duplicate nodes, a number as title passed unseen; a
    misspelt kind was reported as a missing kind."""
    card = {k: v for k, v in {**BIAS, **change}.items() if v is not None}
    _refused(lambda: scenarios.cards(extra=_card("attack", card)), pattern)


@pytest.mark.parametrize("card, pattern", [
    ({"title": "r", "kind": "replacement", "nodes": [0], "prob": 0.0, "magnitude": 4.0},
     r"attack mine: prob must lie in \(0, 1\], found 0\.0"),
    ({"title": "d", "kind": "dos", "p": 0.0, "q": 0.5}, r"attack mine: p must lie in \(0, 1\], found 0\.0"),
])
def test_an_attack_that_never_acts_is_refused(card: dict, pattern: str) -> None:
    _refused(lambda: scenarios.cards(extra=_card("attack", card)), pattern)


def test_a_misspelt_graph_is_named_not_an_optional_key() -> None:
    """``grap = "ring"`` was reported as an unknown ``degree``."""
    card = {("grap" if k == "graph" else k): v for k, v in {**RING, "degree": 2}.items()}
    _refused(lambda: scenarios.cards(extra=_card("network", card)),
             r"network mine: unknown key 'grap' \(did you mean 'graph'\?\); valid: \[.*\]")


@pytest.mark.parametrize("key, value, pattern", [
    ("runs", 1, r"scenario s: runs must be >= 2, found 1"),
    ("horizon", "Auto", r"scenario s: horizon must be an integer >= 1 or \"auto\", found 'Auto'"),
    ("seed", -1, r"scenario s: seed must be >= 0, found -1"),
])
def test_a_named_scenario_card_checks_its_settings(key: str, value: object, pattern: str) -> None:
    """cards() returned a named scenario with runs = 1 or seed = -1 as checked."""
    card = {"network": "inertia5", "attack": "none", key: value}
    _refused(lambda: scenarios.cards(extra={"scenario": {"s": card}}), pattern)


def test_an_extra_matrix_naming_no_card_is_refused() -> None:
    _refused(lambda: scenarios.cards(extra={"matrix": {"networks": ["nosuch"]}}),
             r"\[matrix\] networks: \['nosuch'\] have no card; known: \[.*\]")


def test_a_cards_file_that_is_no_toml_is_refused(tmp_path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[plant.x\n")
    _refused(lambda: scenarios.cards(extra=bad), rf"extra: '{re.escape(str(bad))}' is not a TOML file \(.*\)")


@pytest.mark.parametrize("kwargs, pattern", [
    ({"seed": -1}, r"seed must be >= 0, found -1"),
    ({"name": ""}, r"name must be a non-empty string, found ''"),
])
def test_scenario_arguments_are_checked(kwargs: dict, pattern: str) -> None:
    _refused(lambda: scenarios.scenario("inertia5", "none", runs=2, horizon=10, **kwargs), pattern)


def test_a_misspelt_matrix_override_is_refused() -> None:
    _refused(lambda: scenarios.matrix(runs=2, horizn=10),
             r"matrix\(\) arguments: unknown key 'horizn' \(did you mean 'horizon'\?\); "
             r"valid: \['horizon', 'runs', 'seed'\]")


def test_evaluate_with_no_names_is_refused(small) -> None:
    """names=[] scored every registered method."""
    sc, trial, _ = small
    _refused(lambda: estimators.evaluate(sc, [], trial=trial, short=True),
             r"names must be a non-empty list of registered method names, found \[\]")


def test_run_matrix_of_no_scenario_is_refused() -> None:
    _refused(lambda: matrix.run_matrix([], ["kf"]),
             r"scenarios must be a non-empty list of Scenario, found list")


def test_an_oracle_of_another_trial_is_refused(small) -> None:
    _, trial, oracle = small
    other = scenarios.simulate(scenarios.scenario("inertia5", "none", runs=3, horizon=10, seed=7))
    _refused(lambda: estimators.score(other, oracle, oracle, short=True),
             r"oracle: not the oracle's estimate on this trial of 'inertia5/none' "
             r"\(computed on another trial\?\)")


def test_a_paper_method_constant_out_of_range_is_refused() -> None:
    from secest.arena.papers.ding2020 import Ding2020

    _refused(lambda: Ding2020(kappa=-1.0), r"kappa must lie in \(0, 1\), found -1\.0")


def test_a_network_of_another_plant_is_refused() -> None:
    c = scenarios.cards()
    _refused(lambda: scenarios.steady_state(c["plant"]["target"], c["network"]["inertia5"]),
             r"network inertia5 observes plant 'three_inertia', not plant 'target'")
