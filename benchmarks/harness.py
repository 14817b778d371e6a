"""Timing harness of the benchmark suite: ratios in one process, alternating repeats.

Every comparison times two callables computing the same thing ("ours" and an
"alternative"): one call of each first (warm-up, excluded from the timings, whose
results are handed to ``agree``), then ``repeats`` calls of each, alternating, so
that drifts of the machine load hit both sides alike. It reports the median of
each side and the ratio alternative / ours (a speed-up of ours when > 1). A
disagreement is an error (``agree`` raises), not a row. Plain ``time.perf_counter``
is enough here and keeps the suite free of a benchmark framework.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

__all__ = [
    "MIN_REPEATS",
    "Row",
    "compare",
    "format_table",
    "measure",
    "not_measured",
]

MIN_REPEATS = 5


@dataclass
class Row:
    """One line of the benchmark table (times in seconds, per ``unit``)."""

    what: str
    ours: str
    alternative: str
    ours_s: float | None
    alternative_s: float | None
    ratio: float | None
    agreement: str
    target: str
    met: bool | None
    unit: str = "call"
    repeats: int = 0

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


def _check_repeats(repeats: int) -> None:
    if isinstance(repeats, bool) or not isinstance(repeats, int) or repeats < MIN_REPEATS:
        raise ValueError(f"repeats must be an integer >= {MIN_REPEATS}, found {repeats!r}")


def compare(
    what: str,
    ours: tuple[str, Callable[[], Any]],
    alternative: tuple[str, Callable[[], Any]],
    agree: Callable[[Any, Any], str],
    *,
    repeats: int = MIN_REPEATS,
    target: tuple[str, Callable[[float], bool]] | None = None,
    per: float = 1.0,
    unit: str = "call",
) -> Row:
    """Time ``ours`` against ``alternative`` with alternating repeats (median of each).

    Parameters
    ----------
    what : description of the comparison.
    ours, alternative : (label, zero-argument callable) pairs.
    agree : called once with the two warm-up results; returns a short description
        of the agreement (e.g. ``"max |diff| 3e-15 <= 1e-10"``) or raises
        AssertionError. It is called before any timing.
    repeats : timed calls of each side (after the warm-up), at least 5.
    target : (description, predicate on the ratio) of the goal, if any. A missed
        target is reported (``met=False``), never raised.
    per : both medians are divided by ``per`` (e.g. the number of node-steps one
        call performs); the ratio is unaffected.
    unit : what one timed unit is (shown in the table).
    """
    _check_repeats(repeats)
    a_label, a_fn = ours
    b_label, b_fn = alternative
    agreement = agree(a_fn(), b_fn())  # also the warm-up
    t_a, t_b = [], []
    for _ in range(repeats):
        for fn, store in ((a_fn, t_a), (b_fn, t_b)):
            t0 = time.perf_counter()
            fn()
            store.append(time.perf_counter() - t0)
    med_a, med_b = float(np.median(t_a)) / per, float(np.median(t_b)) / per
    ratio = med_b / med_a
    return Row(
        what=what,
        ours=a_label,
        alternative=b_label,
        ours_s=med_a,
        alternative_s=med_b,
        ratio=ratio,
        agreement=agreement,
        target=target[0] if target else "",
        met=bool(target[1](ratio)) if target else None,
        unit=unit,
        repeats=repeats,
    )


def measure(
    what: str,
    ours: tuple[str, Callable[[], Any]],
    check: Callable[[Any], str],
    *,
    repeats: int = MIN_REPEATS,
    per: float = 1.0,
    unit: str = "call",
) -> Row:
    """Median time of one callable (no alternative), after a warm-up checked by ``check``."""
    _check_repeats(repeats)
    label, fn = ours
    agreement = check(fn())
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return Row(what, label, "-", float(np.median(times)) / per, None, None, agreement, "", None,
               unit, repeats)


def not_measured(what: str, reason: str) -> Row:
    """A row for a comparison that could not be run, with the reason."""
    return Row(what, "not measured", "-", None, None, None, reason, "", None)


def _fmt_time(t: float | None) -> str:
    if t is None:
        return "-"
    for scale, suffix in ((1.0, "s"), (1e-3, "ms"), (1e-6, "us")):
        if t >= scale:
            return f"{t / scale:.3g} {suffix}"
    return f"{t * 1e9:.3g} ns"


def format_table(rows: list[Row]) -> str:
    """Plain-text (Markdown) table of the rows."""
    head = ["what", "ours", "alternative", "ours time", "alt. time", "ratio alt/ours",
            "agreement check", "target", "met"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        unit = f" /{r.unit}" if r.ours_s is not None and r.unit != "call" else ""
        met = {None: "-", True: "yes", False: "NO"}[r.met]
        ratio = "-" if r.ratio is None else f"{r.ratio:.3g}"
        cells = [r.what, r.ours, r.alternative, _fmt_time(r.ours_s) + unit,
                 _fmt_time(r.alternative_s) + (unit if r.alternative_s is not None else ""),
                 ratio, r.agreement, r.target or "-", met]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines)
