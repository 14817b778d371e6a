"""Adversarial sweep of the arena's public API: invalid calls, and what each one does.

Every public function and class of :mod:`secest.arena` (cards and their keys, scenarios, trials,
registration, scoring, the matrix, the report, the tuning engine and both command lines) is called
with invalid values of one argument or card key at a time: wrong type, NaN or infinity, negative,
zero, too large, wrong shape, unknown names, typos of card keys, nodes out of range, a trial of
another scenario, an estimate of the wrong shape, bad Dask arguments, huge sizes. Each outcome is
classified:

``clear``
    a :class:`~secest.core.validation.ValidationError` of one line that names the argument or key;
``unclear``
    any other exception, a message of several lines, one that does not name the argument, or no
    answer within :data:`TIMEOUT_S` seconds;
``silent``
    no error at all.

Usage: ``python benchmarks/api_sweep.py [--show silent,unclear] [--json FILE]``. The address space
is capped (:data:`MEMORY_CAP`) so that a call that would allocate without a size check fails
quickly (as ``unclear``) instead of exhausting the machine. Nothing here is timed.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import resource
import signal
import sys
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

TIMEOUT_S = 120
"""A call without an answer after this long is ``unclear`` (a hang)."""
MEMORY_CAP = 12 * 2**30
"""Address-space limit of the sweep's process (bytes)."""
NAN, INF = float("nan"), float("inf")


@dataclass
class Case:
    """One invalid call: where it goes, the words a clear message names, the call itself."""

    target: str
    words: tuple[str, ...]
    call: Callable[[], Any]


class _Hang(BaseException):
    """No answer within :data:`TIMEOUT_S`."""


def _alarm(signum: int, frame: object) -> None:
    raise _Hang


def classify(case: Case) -> tuple[str, str]:
    """Run ``case``; return (outcome, what it said)."""
    from secest.core.validation import ValidationError

    err = io.StringIO()
    signal.alarm(TIMEOUT_S)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            status = case.call()
    except _Hang:
        return "unclear", f"no answer within {TIMEOUT_S} s"
    except ValidationError as exc:
        return _judge(str(exc), case.words, "")
    except SystemExit as exc:  # a command line's exit
        return _cli(exc.code, err.getvalue(), case.words)
    except Exception as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
        return "unclear", f"{type(exc).__name__}: {first}"[:200]
    finally:
        signal.alarm(0)
    if case.target.startswith(("cli.main", "tuning.main")):
        return _cli(status, err.getvalue(), case.words)
    return "silent", f"returned {type(status).__name__}"


def _judge(text: str, words: tuple[str, ...], prefix: str) -> tuple[str, str]:
    one_line = "\n" not in text.strip()
    named = any(w in text for w in words)
    outcome = "clear" if one_line and named else "unclear"
    return outcome, prefix + text.strip().replace("\n", " | ")[:200]


def _cli(code: object, stderr: str, words: tuple[str, ...]) -> tuple[str, str]:
    if code in (0, None):
        return "silent", "exit status 0"
    return _judge(stderr, words, f"exit {code}: ")


# ---------------------------------------------------------------------------------- fixtures


PLANT = {
    "title": "t",
    "source": "s",
    "Ac": [[0.0, 1.0], [0.0, 0.0]],
    "dt": 0.1,
    "q_std": 0.1,
    "outputs": [[1.0, 0.0]],
    "r_std": [0.1],
    "x0_std": 1.0,
    "state_names": ["p", "v"],
}
RING = {"title": "t", "plant": "target", "N": 5, "graph": "ring", "degree": 2, "measures": [[0]] * 5}
RGG = {
    "title": "t",
    "plant": "target",
    "N": 6,
    "graph": "rgg",
    "radius": 0.9,
    "seed": 3,
    "measures": [[0]] * 6,
}
COMPLETE = {"title": "t", "plant": "target", "N": 4, "graph": "complete", "measures": [[1]] * 4}
ATTACKS = {
    "none": {"title": "t", "kind": "none"},
    "bias": {"title": "t", "kind": "bias", "nodes": [0], "start": 0.3, "magnitude": 40.0},
    "replacement": {"title": "t", "kind": "replacement", "nodes": [0], "prob": 0.3, "magnitude": 40.0},
    "message": {"title": "t", "kind": "message", "prob": 0.3, "magnitude": 20.0},
    "dos": {"title": "t", "kind": "dos", "p": 0.1, "q": 0.9},
}
NAMED = {"title": "t", "network": "inertia5", "attack": "bias", "horizon": 10, "runs": 2, "seed": 1}

BAD_REAL = ["x", True, NAN, INF, -1.0, 0.0, [1.0]]
BAD_PROB = ["x", True, NAN, -0.1, 1.5]
BAD_COUNT = ["x", True, 2.5, NAN, -1, 0]
BAD_TEXT = [5, True, [], ""]


def _typo(key: str) -> str:
    return key[:-1] if len(key) > 2 else key + key[-1]


OPTIONAL = {"degree", "title@scenario", "horizon@scenario", "runs@scenario", "seed@scenario"}
"""Card keys that may be left out (``key`` or ``key@kind``): no "missing" case for them."""


def _card_cases(
    kind: str, label: str, card: dict[str, Any], bad: dict[str, list], check: Callable[[dict], Any]
) -> Iterator[Case]:
    """A card with one key misspelt, one required key missing, or one key of each bad value."""
    for key in card:
        typo = _typo(key)
        changed = {k if k != key else typo: v for k, v in card.items()}
        yield Case(
            f"{kind} card {label}: key {key} misspelt {typo}", (repr(typo),), lambda c=changed: check(c)
        )
        if key not in OPTIONAL and f"{key}@{kind}" not in OPTIONAL:
            dropped = {k: v for k, v in card.items() if k != key}
            yield Case(f"{kind} card {label}: key {key} missing", (key,), lambda c=dropped: check(c))
    for key, values in bad.items():
        for value in values:
            yield Case(
                f"{kind} card {label}: {key} = {value!r}"[:120],
                (key,),
                lambda c={**card, key: value}: check(c),
            )


def _cards(kind: str) -> Callable[[dict], Any]:
    from secest.arena import scenarios

    return lambda card: scenarios.cards(extra={kind: {"mine": card}})


def _attack_in(network: str) -> Callable[[dict], Any]:
    """An attack card checked on a network: the cards, then a scenario of the two."""
    from secest.arena import scenarios

    def check(card: dict) -> Any:
        return scenarios.scenario(network, "mine", runs=2, horizon=10, extra={"attack": {"mine": card}})

    return check


def card_cases() -> Iterator[Case]:
    """Every card kind and key."""
    yield from _card_cases(
        "plant",
        "2-state",
        PLANT,
        {
            "title": BAD_TEXT,
            "source": BAD_TEXT,
            "Ac": ["x", [[1.0, 2.0]], [[NAN, 0.0], [0.0, 0.0]], [[INF, 0.0], [0.0, 0.0]], [], [[[1.0]]]],
            "dt": BAD_REAL,
            "q_std": BAD_REAL,
            "x0_std": BAD_REAL,
            "outputs": ["x", [[1.0]], [[NAN, 0.0]], [], [[1.0, 0.0, 0.0]]],
            "r_std": ["x", [0.1, 0.1], [0.0], [-0.1], [NAN], [INF], 0.1],
            "state_names": [["p"], [1, 2], "pv", ["p", "p", "a"]],
        },
        _cards("plant"),
    )
    net_bad = {
        "title": BAD_TEXT,
        "plant": ["nosuch", 3, "targt"],
        "N": [*BAD_COUNT, 1, 10**9],
        "graph": ["star", 3, "Ring"],
        "measures": [
            "x",
            [[0]] * 4,
            [[5]] * 5,
            [[-1]] * 5,
            [[0.5]] * 5,
            [[0], [0, 1], [0], [0], [0]],
            [],
            [[]] * 5,
            [[True]] * 5,
        ],
    }
    yield from _card_cases(
        "network", "ring", RING, {**net_bad, "degree": [3, 0, -2, 6, 2.0, "2", True]}, _cards("network")
    )
    yield from _card_cases(
        "network",
        "rgg",
        RGG,
        {"radius": [*BAD_REAL, 1e-4], "seed": ["x", -1, 1.5, True], "N": [1, 10**9]},
        _cards("network"),
    )
    yield from _card_cases("network", "complete", COMPLETE, {"N": [1, 0, 10**5]}, _cards("network"))
    yield Case(
        "network card ring: key radius of an rgg",
        ("'radius'",),
        lambda: _cards("network")({**RING, "radius": 0.5}),
    )
    node_bad = [[-1], [], [0.5], "0", [True], [99], [0, 0], 0]
    check = _attack_in("inertia5")
    yield from _card_cases(
        "attack",
        "bias",
        ATTACKS["bias"],
        {
            "kind": ["biass", 3, "Bias"],
            "nodes": node_bad,
            "start": [*BAD_PROB, 1.0],
            "magnitude": BAD_REAL,
            "title": BAD_TEXT,
        },
        check,
    )
    yield from _card_cases(
        "attack",
        "replacement",
        ATTACKS["replacement"],
        {"nodes": node_bad, "prob": [*BAD_PROB, 0.0], "magnitude": BAD_REAL},
        check,
    )
    yield from _card_cases(
        "attack", "message", ATTACKS["message"], {"prob": [*BAD_PROB, 0.0], "magnitude": BAD_REAL}, check
    )
    yield from _card_cases(
        "attack", "dos", ATTACKS["dos"], {"p": [*BAD_PROB, 0.0], "q": BAD_PROB}, check
    )
    yield from _card_cases("attack", "none", ATTACKS["none"], {}, check)
    for kind, extra_key in (
        ("none", "magnitude"),
        ("dos", "nodes"),
        ("message", "nodes"),
        ("bias", "prob"),
    ):
        yield Case(
            f"attack card {kind}: key {extra_key} of another kind",
            (repr(extra_key),),
            lambda k=kind, e=extra_key: check({**ATTACKS[k], e: [0] if e == "nodes" else 0.5}),
        )
    yield from _card_cases(
        "scenario",
        "named",
        NAMED,
        {
            "title": BAD_TEXT,
            "network": ["nosuch", 3],
            "attack": ["nosuch", 3],
            "horizon": ["x", True, 2.5, NAN, -1, 0, 10**12, "Auto"],
            "runs": ["x", True, 2.5, -1, 0, 1, 10**12],
            "seed": ["x", True, 1.5, -1, NAN],
        },
        _cards("scenario"),
    )
    yield from _matrix_cases()
    yield from _file_cases()


def _matrix_cases() -> Iterator[Case]:
    from secest.arena import scenarios

    def check(table: dict) -> Any:
        return scenarios.cards(extra={"matrix": table})

    for key in ("networks", "attacks"):
        for value in ("inertia5" if key == "networks" else "none", [3], ["nosuch"], [], [[]]):
            yield Case(f"extra [matrix] {key} = {value!r}", (key,), lambda v=value, k=key: check({k: v}))
        yield Case(
            f"extra [matrix] key {key} misspelt",
            (repr(_typo(key)),),
            lambda k=key: check({_typo(k): ["inertia5"]}),
        )
    for key in ("horizon", "runs", "seed", "colour"):
        yield Case(f"extra [matrix] {key}", (key,), lambda k=key: check({k: 5}))


def _file_cases() -> Iterator[Case]:
    from secest.arena import scenarios

    tmp = Path(tempfile.mkdtemp(prefix="api-sweep-"))
    broken = tmp / "broken.toml"
    broken.write_text("[plant.x\ntitle = 'a'\n")
    for label, extra in (
        ("a number", 3),
        ("a missing file", str(tmp / "nofile.toml")),
        ("a folder", str(tmp)),
        ("a TOML syntax error", str(broken)),
        ("an unknown table", {"plnt": {}}),
        ("a kind table not a table", {"plant": 3}),
        ("a card not a table", {"plant": {"p": 3}}),
        ("a name of the package", {"network": {"inertia5": RING}}),
        ("a list", [1, 2]),
    ):
        yield Case(f"cards(extra = {label})", ("extra", "cards"), lambda e=extra: scenarios.cards(e))


# ---------------------------------------------------------------------------------- functions


def _small() -> tuple[Any, Any, Any]:
    from secest.arena import scenarios
    from secest.arena.estimators import METHODS

    sc = scenarios.scenario("inertia5", "bias", runs=3, horizon=10)
    trial = scenarios.simulate(sc)
    return sc, trial, METHODS["oracle"].run(trial)


def scenario_cases() -> Iterator[Case]:
    """scenarios.scenario, matrix, simulate, steady_state, auto_horizon, horizon_of, received."""
    from secest.arena import scenarios

    base = {"runs": 2, "horizon": 10}

    def sc(**kw: Any) -> Any:
        args = {"network": "inertia5", "attack": "none", **base, **kw}
        return scenarios.scenario(args.pop("network"), args.pop("attack"), **args)

    for key, values in {
        "network": [3, "nosuch", "inertia", None],
        "attack": [3, "nosuch", "bais", None],
        "horizon": ["x", True, 2.5, NAN, -1, 0, 10**9, "Auto", [10]],
        "runs": ["x", True, 2.5, NAN, -1, 0, 1, 10**9],
        "seed": ["x", True, 1.5, NAN, -1],
        "name": [3, "", []],
        "extra": [3, "nofile.toml", [1]],
    }.items():
        for v in values:
            yield Case(f"scenario({key}={v!r})", (key,), lambda k=key, v=v: sc(**{k: v}))
    yield Case(
        "scenario(network=a 400-node ring card, runs=40, horizon=10^6)",
        ("runs", "horizon", "nodes"),
        lambda: scenarios.scenario(
            "big",
            "none",
            runs=40,
            horizon=10**6,
            extra={"network": {"big": {**RING, "N": 400, "measures": [[0]] * 400}}},
        ),
    )
    for key, values in {
        "networks": ["inertia5", [], [3], ["nosuch"]],
        "attacks": ["none", [], [3], ["nosuch"]],
    }.items():
        for v in values:
            yield Case(
                f"matrix({key}={v!r})",
                (key,),
                lambda k=key, v=v: scenarios.matrix(**{k: v}, runs=2, horizon=10),
            )
    yield Case("matrix(horizn=10)", ("horizn",), lambda: scenarios.matrix(runs=2, horizn=10))
    yield Case("matrix(runs=1)", ("runs",), lambda: scenarios.matrix(runs=1, horizon=10))
    yield Case("matrix(extra=3)", ("extra",), lambda: scenarios.matrix(extra=3))
    for v in (3, None, "inertia5/none"):
        yield Case(f"simulate(sc={v!r})", ("sc", "scenario"), lambda v=v: scenarios.simulate(v))
    plant = scenarios.cards()["plant"]["target"]
    net = scenarios.cards()["network"]["target20"]
    other = scenarios.cards()["network"]["inertia5"]
    for label, p, n in (
        ("plant=3", 3, net),
        ("network=3", plant, 3),
        ("a network of another plant", plant, other),
    ):
        yield Case(
            f"steady_state({label})", ("plant", "network"), lambda p=p, n=n: scenarios.steady_state(p, n)
        )
        yield Case(
            f"auto_horizon({label})", ("plant", "network"), lambda p=p, n=n: scenarios.auto_horizon(p, n)
        )
    for v in ("x", NAN, INF, -1.0, 0.0):
        yield Case(f"horizon_of(tau={v!r})", ("tau",), lambda v=v: scenarios.horizon_of(v))
    yield from _received_cases()


def _received_cases() -> Iterator[Case]:
    from secest.arena import scenarios

    sc = scenarios.scenario("inertia5", "message", runs=2, horizon=10)
    trial = scenarios.simulate(sc)
    m = np.zeros((2, 5, 6))
    for label, k, msgs in (
        ("k=-1", -1, m),
        ("k=99", 99, m),
        ("k=2.5", 2.5, m),
        ("k='x'", "x", m),
        ("messages of 4 nodes", 0, m[:, :4]),
        ("messages of 3 runs", 0, np.zeros((3, 5, 6))),
        ("messages 2-D", 0, m[0]),
    ):  # non-finite messages are valid: a diverging method's, passed on (its cell: diverged)
        word = "k" if label.startswith("k") else "messages"
        yield Case(f"Trial.received({label})", (word,), lambda k=k, msgs=msgs: trial.received(k, msgs))
    yield Case("Trial.received(encode=3)", ("encode",), lambda: trial.received(0, m, 3))


def estimator_cases() -> Iterator[Case]:
    """register, evaluate, score, rate, rate_of_counts, growth, normalised_errors, settle_steps."""
    from secest.arena import estimators
    from secest.arena.estimators import Estimate, Method

    class Nameless(Method):
        pass

    class NumberName(Method):
        name = 3

    class Oracle2(Method):
        name = "oracle"

    for label, m, kw in (
        ("3", 3, {}),
        ("None", None, {}),
        ("a class not a Method", int, {}),
        ("a nameless Method", Nameless, {}),
        ("a Method named 3", NumberName, {}),
        ("a Method named oracle", Oracle2, {}),
        ("a Method named oracle, replace=True", Oracle2, {"replace": True}),
        ("a taken name", type("K", (Method,), {"name": "kf"}), {}),
        ("replace='yes'", type("Z", (Method,), {"name": "zz-sweep"}), {"replace": "yes"}),
    ):
        word = ("replace",) if "replace=" in label and "oracle" not in label else ("method", "name")
        yield Case(f"register({label})", word, lambda m=m, kw=kw: _register_once(m, **kw))
    sc, trial, oracle = _small()
    other = _other_trial()

    def ev(**kw: Any) -> Any:
        args = {"sc": sc, "names": ["kf"], "trial": trial, "short": True, **kw}
        return estimators.evaluate(args.pop("sc"), args.pop("names"), **args)

    for key, values in {
        "sc": [3, None],
        "names": ["kf", [], [3], ["nosuch"], ["kf", "kf"]],
        "runner": [3],
        "observe": [3],
        "trial": [3, other],
        "short": ["yes", 1],
    }.items():
        for v in values:
            yield Case(f"evaluate({key}={v!r})"[:100], (key,), lambda k=key, v=v: ev(**{k: v}))
    yield from _score_cases(trial, oracle, other)
    yield from _rate_cases()
    for v in (3, None):
        yield Case(f"settle_steps(sc={v!r})", ("sc",), lambda v=v: estimators.settle_steps(v))
    yield Case("settle_steps(short='yes')", ("short",), lambda: estimators.settle_steps(sc, short="yes"))
    yield Case(
        "Estimate(xhat=3) scored",
        ("estimate",),
        lambda: estimators.score(trial, Estimate(3), oracle, short=True),
    )


def _register_once(method: Any, **kw: Any) -> Any:
    """Register, then undo whatever the call added (the sweep must not change the registry)."""
    from secest.arena.estimators import METHODS, register

    before = dict(METHODS)
    try:
        return register(method, **kw)
    finally:
        METHODS.clear()
        METHODS.update(before)


def _other_trial() -> Any:
    from secest.arena import scenarios

    return scenarios.simulate(scenarios.scenario("inertia5", "bias", runs=3, horizon=10, seed=7))


def _score_cases(trial: Any, oracle: Any, other: Any) -> Iterator[Case]:
    from secest.arena import estimators
    from secest.arena.estimators import Estimate

    xhat = oracle.xhat
    alarms = np.zeros(xhat.shape[:3], bool)
    for label, est, word in (
        ("estimate of 4 of 5 nodes", Estimate(xhat[:, :, :4]), "estimate"),
        ("estimate of 1 of 6 components", Estimate(xhat[..., :1]), "estimate"),
        ("estimate of 2 of 3 runs", Estimate(xhat[:2]), "estimate"),
        ("estimate of 5 of 11 steps", Estimate(xhat[:, :5]), "estimate"),
        ("estimate as a list", Estimate(xhat.tolist()), "estimate"),
        ("estimate of strings", Estimate(xhat.astype(str)), "estimate"),
        ("alarms of 4 nodes", Estimate(xhat, alarms=alarms[:, :, :4]), "alarms"),
        ("alarms of floats 0.5", Estimate(xhat, alarms=alarms + 0.5), "alarms"),
        ("bound of the wrong shape", Estimate(xhat, bound=np.zeros(3)), "bound"),
        ("an estimate that is no Estimate", xhat, "estimate"),
    ):
        yield Case(
            f"score({label})", (word,), lambda e=est: estimators.score(trial, e, oracle, short=True)
        )
    yield Case(
        "score(oracle of the wrong shape)",
        ("oracle",),
        lambda: estimators.score(trial, oracle, Estimate(xhat[:, :, :, :2]), short=True),
    )
    yield Case("score(trial=3)", ("trial",), lambda: estimators.score(3, oracle, oracle, short=True))
    yield Case(
        "score(trial of another scenario, same shapes)",
        ("trial", "oracle"),
        lambda: estimators.score(other, oracle, oracle, short=True),
    )
    yield Case(
        "score(short='yes')", ("short",), lambda: estimators.score(trial, oracle, oracle, short="yes")
    )


def _rate_cases() -> Iterator[Case]:
    from secest.arena import estimators

    a = np.zeros((3, 4, 2), bool)
    for label, args, word in (
        ("alarms of another shape", (a[:, :2], a), "alarms"),
        ("alarms of floats", (a + 0.5, a), "alarms"),
        ("where selecting nothing", (a, a), "where"),
        ("alarms=3", (3, a), "alarms"),
    ):
        yield Case(f"rate({label})", (word,), lambda args=args: estimators.rate(*args))
    for label, args in (
        ("negative hits", ([-1, 0], [2, 2])),
        ("hits > total", ([5, 0], [2, 2])),
        ("fractional counts", ([0.5, 0], [2, 2])),
        ("NaN counts", ([NAN, 0], [2, 2])),
        ("shapes differ", ([0], [2, 2])),
    ):
        yield Case(
            f"rate_of_counts({label})",
            ("hits", "total"),
            lambda args=args: estimators.rate_of_counts(np.asarray(args[0]), np.asarray(args[1])),
        )
    for label, q in (
        ("q 2-D", np.ones((3, 4))),
        ("q empty", np.ones((3, 0, 2))),
        ("q=3", 3),
        ("q negative", -np.ones((3, 4, 2))),
        ("q NaN", np.full((3, 4, 2), NAN)),
    ):
        yield Case(f"growth({label})", ("q",), lambda q=q: estimators.growth(q))
    x = np.zeros((3, 4, 2))
    for label, args, word in (
        ("xhat 3-D", (x, x, x), "xhat"),
        ("x of 3 components", (x[:, :, None], np.zeros((3, 4, 3)), x), "x"),
        ("oracle of 2 steps", (x[:, :, None], x, x[:, :2]), "oracle"),
    ):
        yield Case(
            f"normalised_errors({label})", (word,), lambda args=args: estimators.normalised_errors(*args)
        )


def method_cases() -> Iterator[Case]:
    """The constructors of the baselines and the five papers' methods."""
    from secest.arena import baselines, estimators
    from secest.arena.papers import ding2020, guo2023, lee2020, li2025, ma2021

    table: list[tuple[type, str, list]] = [
        (estimators.Chi2KF, "false_alarm", [*BAD_PROB, 0.0, 1.0]),
        (baselines.ConsensusInformationKF, "rounds", [*BAD_COUNT, 10**9]),
        (baselines.ConsensusKF, "rounds", [*BAD_COUNT, 10**9]),
        (baselines.DiffusionKF, "combination", ["x", 3]),
        (baselines.KalmanConsensusFilter, "epsilon", ["x", True, NAN, INF, -1.0]),
        (baselines.WmsrKF, "trimmed", ["x", True, 2.5, -1]),
        (ding2020.Ding2020, "kappa", BAD_REAL),
        (ding2020.Ding2020, "threshold", BAD_REAL),
        (guo2023.Guo2023, "threat", ["x", 3]),
        (guo2023.Guo2023, "rtol", BAD_REAL),
        (guo2023.Guo2023, "false_alarm", [*BAD_PROB, 0.0]),
        (lee2020.Lee2020, "kappa", BAD_REAL),
        (lee2020.Lee2020, "gamma", BAD_REAL),
        (lee2020.Lee2020, "q", BAD_COUNT),
        (lee2020.Lee2020, "poles", ["x", 3]),
        (lee2020.Lee2020, "chatter", BAD_REAL),
        (
            li2025.Li2025,
            "weights",
            [(1.0,) * 4, (1.0, 1.0, 1.0, 1.0, -1.0), (NAN,) * 5, "abcde", 3, ("a",) * 5, (INF,) * 5],
        ),
        (li2025.Li2025, "variant", ["x", 3]),
        (ma2021.Ma2021, "p", [*BAD_PROB, 0.0, 1.0]),
    ]
    for cls, key, values in table:
        for v in values:
            yield Case(f"{cls.__name__}({key}={v!r})", (key,), lambda c=cls, k=key, v=v: c(**{k: v}))


def matrix_cases() -> Iterator[Case]:
    """run_matrix, scaled, error_curve, attack_activity, cell_text, table_rows, fmt_interval, cell."""
    from secest.arena import matrix, scenarios
    from secest.arena.estimators import Score

    sc = scenarios.scenario("inertia5", "none", runs=2, horizon=10)
    twin = scenarios.scenario("inertia5", "bias", runs=2, horizon=10, name="inertia5/none")

    def rm(**kw: Any) -> Any:
        args = {"scenarios": [sc], "methods": ["kf"], "short": True, **kw}
        return matrix.run_matrix(args.pop("scenarios"), args.pop("methods"), **args)

    for key, values in {
        "scenarios": [3, [], [3], sc, [sc, twin]],
        "methods": ["kf", [], [3], ["nosuch"], ["kf", "kf"]],
        "curves": ["yes"],
        "short": ["yes"],
        "workers": [0, -1, 2.5, True, "2", 10**6],
        "scheduler": ["localhost", 3, ""],
    }.items():
        for v in values:
            yield Case(f"run_matrix({key}={v!r})"[:100], (key,), lambda k=key, v=v: rm(**{k: v}))
    yield Case(
        "run_matrix(scheduler and workers)",
        ("scheduler", "workers"),
        lambda: rm(scheduler="tcp://127.0.0.1:1", workers=2),
    )
    for v in (0, -1.0, NAN, INF, True, "2"):
        yield Case(f"scaled(factor={v!r})", ("factor",), lambda v=v: matrix.scaled(sc, v))
    yield Case("scaled(sc=3)", ("sc",), lambda: matrix.scaled(3, 2.0))
    x = np.zeros((2, 11, 6))
    for label, args in (("xhat 3-D", (x, x)), ("x of 5 components", (x[:, :, None], x[..., :5]))):
        yield Case(f"error_curve({label})", ("xhat", "x"), lambda args=args: matrix.error_curve(*args))
    yield Case("attack_activity(trial=3)", ("trial",), lambda: matrix.attack_activity(3))
    for label, s in (
        ("s=3", 3),
        ("status 'good'", Score("good")),
        ("n/a without reason", Score("n/a")),
        ("ok without scores", Score("ok")),
    ):
        yield Case(
            f"cell_text({label})", ("s", "status", "reason", "score"), lambda s=s: matrix.cell_text(s)
        )
    yield Case("table_rows(m=3)", ("m",), lambda: matrix.table_rows(3))
    for v in (3, (1.0, 2.0), ("a", "b", "c")):
        yield Case(f"fmt_interval(value={v!r})", ("value",), lambda v=v: matrix.fmt_interval(v))
    m = matrix.Matrix([sc], ["kf"], {})
    yield Case("Matrix.cell(unknown)", ("cell", "nosuch"), lambda: m.cell("nosuch", "kf"))
    for key, v in (("scheduler", 3), ("workers", 0)):
        yield Case(
            f"check_dask_arguments({key}={v!r})",
            (key,),
            lambda k=key, v=v: matrix.check_dask_arguments(**{"scheduler": None, "workers": None, k: v}),
        )


def report_cases() -> Iterator[Case]:
    """race, columns, method_order, heatmap, plant_tables, write."""
    from secest.arena import matrix, report, scenarios

    tmp = Path(tempfile.mkdtemp(prefix="api-sweep-"))
    afile = tmp / "file.txt"
    afile.write_text("x")

    def race(**kw: Any) -> Any:
        args = {
            "cards": None,
            "methods": ["kf"],
            "plants": ["inertia5"],
            "attacks": ["none"],
            "runs": 2,
            "horizon": 10,
            "short": True,
            **kw,
        }
        return report.race(args.pop("cards"), args.pop("methods"), **args)

    for key, values in {
        "cards": [3, "nofile.toml", [1]],
        "methods": ["kf", [], [3], ["nosuch"], ["kf", "kf"]],
        "plants": ["inertia5", [], [3], ["nosuch"], ["inertia5", "inertia5"]],
        "attacks": ["none", [], [3], ["nosuch"]],
        "runs": ["x", True, 2.5, -1, 0, 1, 10**9],
        "horizon": ["x", 2.5, -1, 0, "Auto"],
        "seed": ["x", 1.5, -1, True],
        "out": [3, str(afile)],
        "short": ["yes"],
        "workers": [0, "2"],
        "scheduler": ["localhost"],
    }.items():
        for v in values:
            yield Case(f"race({key}={v!r})"[:100], (key,), lambda k=key, v=v: race(**{k: v}))
    sc = scenarios.scenario("inertia5", "none", runs=2, horizon=10)
    m = matrix.run_matrix([sc], ["kf"], short=True)
    yield Case("columns(m=3)", ("m",), lambda: report.columns(3))
    yield Case(
        "method_order(names=['nosuch'])", ("names", "nosuch"), lambda: report.method_order(["nosuch"])
    )
    yield Case("method_order(names='kf')", ("names",), lambda: report.method_order("kf"))
    yield Case("heatmap(m=3)", ("m",), lambda: report.heatmap(3, title="t"))
    yield Case("heatmap(title=3)", ("title",), lambda: report.heatmap(m, title=3))
    for v in (-1.0, 0.0, NAN, "x"):
        yield Case(
            f"heatmap(width={v!r})", ("width",), lambda v=v: report.heatmap(m, title="t", width=v)
        )
    yield Case("plant_tables(m=3)", ("m",), lambda: report.plant_tables(3))
    yield Case("write(m=3)", ("m",), lambda: report.write(3, tmp / "out"))
    yield Case("write(out=a file)", ("out",), lambda: report.write(m, afile))
    yield Case("write(out=3)", ("out",), lambda: report.write(m, 3))


def tuning_cases() -> Iterator[Case]:
    """grid, validate, choose, tune, refuse_test_seeds, point_task."""
    from secest.arena import scenarios, tuning
    from secest.arena.estimators import METHODS

    for key, v in (
        ("method_name", "nosuch"),
        ("method_name", 3),
        ("method_name", "oracle"),
        ("plant_ny", 0),
        ("plant_ny", -1),
        ("plant_ny", 2.5),
        ("plant_ny", "x"),
    ):
        args = {"method_name": "kf", "plant_ny": 1, key: v}
        yield Case(f"grid({key}={v!r})", (key, "method"), lambda a=args: tuning.grid(**a))
    small = {"seeds": [101], "runs": 2, "horizon": 10, "short": True, "points": [0]}

    def val(**kw: Any) -> Any:
        args = {"method_name": "kf", "plant": "inertia5", **small, **kw}
        return tuning.validate(args.pop("method_name"), args.pop("plant"), **args)

    for key, values in {
        "method_name": ["nosuch", 3],
        "plant": ["nosuch", 3, "three_inertia"],
        "seeds": [[201], [], [1.5], [101, 101], "101", [7]],
        "runs": ["x", 1, 0, -1],
        "horizon": [0, -1, "x"],
        "short": ["yes"],
        "workers": [0, -1],
        "scheduler": ["x"],
        "points": [[99], [-1], [], "0", [0.5]],
    }.items():
        for v in values:
            yield Case(
                f"validate({key}={v!r})",
                (key, "method" if key == "method_name" else key),
                lambda k=key, v=v: val(**{k: v}),
            )
    record = {
        "point": 0,
        "printed": True,
        "status": "ok",
        "score": 1.0,
        "false_alarm": None,
        "constants": {},
        "arguments": {},
    }
    for label, records, cap in (
        ("records=3", 3, None),
        ("records=[]", [], None),
        ("no printed point", [{**record, "printed": False}], None),
        ("two printed points", [record, {**record, "point": 1}], None),
        ("score 'x'", [{**record, "score": "x"}], None),
        ("score NaN", [{**record, "score": NAN}], None),
        ("duplicate points", [record, {**record, "printed": False}], None),
        ("cap=-1", [record], -1.0),
        ("cap=NaN", [record], NAN),
        ("cap='x'", [record], "x"),
        ("cap=2", [record], 2.0),
    ):
        word = ("cap",) if label.startswith("cap") else ("records", "score", "point")
        yield Case(f"choose({label})", word, lambda r=records, c=cap: tuning.choose(r, cap=c))

    def tune(**kw: Any) -> Any:
        args = {
            "methods": ["kf"],
            "plants": ["inertia5"],
            **{k: v for k, v in small.items() if k != "points"},
            **kw,
        }
        return tuning.tune(args.pop("methods"), args.pop("plants"), **args)

    for key, values in {
        "methods": ["kf", [], ["nosuch"], ["kf", "kf"]],
        "plants": ["inertia5", [], ["nosuch"]],
        "seeds": [[201]],
        "runs": [1],
    }.items():
        for v in values:
            yield Case(
                f"tune({key}={v!r})",
                (key, "method" if key == "methods" else key),
                lambda k=key, v=v: tune(**{k: v}),
            )
    for label, seeds, test in (
        ("seeds=3", 3, None),
        ("seeds='x'", "x", None),
        ("test=3", [101], 3),
        ("seeds=[201]", [201], None),
    ):
        word = ("test",) if label.startswith("test") else ("seeds",)
        yield Case(
            f"refuse_test_seeds({label})", word, lambda s=seeds, t=test: tuning.refuse_test_seeds(s, t)
        )
    sc = scenarios.scenario("inertia5", "none", runs=2, horizon=10)
    yield Case("point_task(sc=3)", ("sc",), lambda: tuning.point_task(3, METHODS["kf"], True))
    yield Case("point_task(method=3)", ("method",), lambda: tuning.point_task(sc, 3, True))
    yield Case(
        "point_task(short='yes')", ("short",), lambda: tuning.point_task(sc, METHODS["kf"], "yes")
    )


def cli_cases() -> Iterator[Case]:
    """Both command lines, load_method and list_text."""
    from secest.arena import cli, tuning

    tmp = Path(tempfile.mkdtemp(prefix="api-sweep-"))
    afile = tmp / "file.txt"
    afile.write_text("x")
    out = str(tmp / "out")
    base = [
        "--plants",
        "inertia5",
        "--attacks",
        "none",
        "--methods",
        "kf",
        "--runs",
        "2",
        "--horizon",
        "10",
        "--short",
        "--out",
        out,
    ]

    def run(*args: str) -> Any:
        return cli.main([*base, *args])

    for option, value in (
        ("--runs", "1"),
        ("--runs", "x"),
        ("--runs", "-3"),
        ("--horizon", "0"),
        ("--horizon", "2.5"),
        ("--seed", "-1"),
        ("--seed", "x"),
        ("--workers", "0"),
        ("--workers", "x"),
        ("--scheduler", "localhost"),
        ("--methods", "nosuch"),
        ("--methods", ","),
        ("--plants", "nosuch"),
        ("--plants", ""),
        ("--attacks", "nosuch"),
        ("--cards", str(tmp / "nofile.toml")),
        ("--cards", str(afile)),
        ("--method", "x"),
        ("--method", "nosuch.py:X"),
        ("--method", "os:path"),
        ("--method", "secest.arena.estimators:Score"),
        ("--out", str(afile)),
        ("--runs", "1000000000"),
    ):
        yield Case(
            f"cli.main({option} {value!r})",
            (option, option.lstrip("-")),
            lambda o=option, v=value: run(o, v),
        )
    yield Case("cli.main(--bogus)", ("--bogus",), lambda: run("--bogus"))
    yield Case(
        "cli.main(--scheduler with --workers)",
        ("--scheduler", "--workers", "scheduler"),
        lambda: run("--scheduler", "tcp://127.0.0.1:1", "--workers", "2"),
    )
    yield Case("cli.main(no --out)", ("--out",), lambda: cli.main(base[:-2]))
    for v in (3, "x", "a:b:c", ":X", "os:"):
        yield Case(f"load_method(spec={v!r})", ("spec", "--method"), lambda v=v: cli.load_method(v))
    yield Case("list_text(cards=3)", ("cards", "extra"), lambda: cli.list_text(3))
    tbase = [
        "--methods",
        "kf",
        "--plants",
        "inertia5",
        "--seeds",
        "101",
        "--runs",
        "2",
        "--horizon",
        "10",
        "--short",
        "--out",
        str(tmp / "t.json"),
    ]
    for option, value in (
        ("--methods", "nosuch"),
        ("--plants", "nosuch"),
        ("--seeds", "201"),
        ("--seeds", "x"),
        ("--runs", "1"),
        ("--runs", "x"),
        ("--horizon", "0"),
        ("--workers", "0"),
        ("--scheduler", "x"),
        ("--out", str(tmp)),
    ):
        args = [*tbase]
        i = args.index(option) if option in args else None
        if i is None:
            args += [option, value]
        else:
            args[i + 1] = value
        yield Case(
            f"tuning.main({option} {value!r})",
            (option, option.lstrip("-")),
            lambda a=args: tuning.main(a),
        )


GROUPS: dict[str, Callable[[], Iterator[Case]]] = {
    "cards": card_cases,
    "scenarios": scenario_cases,
    "estimators": estimator_cases,
    "methods": method_cases,
    "matrix": matrix_cases,
    "report": report_cases,
    "tuning": tuning_cases,
    "cli": cli_cases,
}


def sweep(groups: list[str], show: Callable[[dict], None] | None = None) -> list[dict[str, str]]:
    """Every case of ``groups``, classified: one record (group, target, outcome, said) per call.

    Parameters
    ----------
    groups : list of str
        Keys of :data:`GROUPS`.
    show : callable, optional
        Called with each record as soon as it is classified.
    """
    previous = signal.signal(signal.SIGALRM, _alarm)
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    cap = MEMORY_CAP if hard == resource.RLIM_INFINITY else min(MEMORY_CAP, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))  # the soft limit only: restored below
    results = []
    try:
        for group in groups:
            for case in GROUPS[group]():
                outcome, said = classify(case)
                results.append({"group": group, "target": case.target, "outcome": outcome, "said": said})
                if show is not None:
                    show(results[-1])
    finally:
        signal.signal(signal.SIGALRM, previous)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
    return results


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--only", default=",".join(GROUPS), help="comma-separated groups")
    p.add_argument("--show", default="silent,unclear", help="outcomes to list one per line")
    p.add_argument("--json", help="write every case and its outcome here")
    args = p.parse_args(argv)
    import secest.arena  # registers every method

    print(f"secest from {Path(secest.arena.__file__).parent.parent}")
    shown = set(args.show.split(","))

    def show(r: dict) -> None:
        if r["outcome"] in shown:
            print(f"{r['outcome']:8} {r['target']}: {r['said']}", flush=True)

    results = sweep(args.only.split(","), show)
    counts = {o: sum(r["outcome"] == o for r in results) for o in ("clear", "unclear", "silent")}
    print(f"\n{len(results)} invalid calls: " + ", ".join(f"{n} {o}" for o, n in counts.items()))
    for group in GROUPS:
        mine = [r for r in results if r["group"] == group]
        if mine:
            print(
                f"  {group:10} {len(mine):4} calls: "
                + ", ".join(f"{sum(r['outcome'] == o for r in mine)} {o}" for o in counts)
            )
    if args.json:
        Path(args.json).write_text(json.dumps({"counts": counts, "cases": results}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
