"""README, ERRATA and the claims say the same verdict, by the one written rule (issue #30).

For each paper the verdict is computed from ``figures/<key>/claims.json`` by
:func:`secest.repro.results.rescience_verdict`; README's row of the paper must carry that verdict
and name exactly the deciding claims ("decided by C1, C3, ..."), and the paper's ERRATA section
must give the same verdict first and name every deciding claim.
"""

from __future__ import annotations

import json
import re

import pytest

from secest.repro.results import (
    COUNTS_PATTERN,
    POINT_OUTCOMES,
    counts_text,
    repo_root,
    rescience_verdict,
)
from secest.repro.site import paper_keys

ROOT = repo_root()
VERDICT = re.compile(r"\[(?:Re|Re, partial|¬Re)\]")


def _claims(key: str) -> dict:
    return json.loads((ROOT / "figures" / key / "claims.json").read_text())


def _readme_row(key: str) -> str:
    rows = [line for line in (ROOT / "README.md").read_text().splitlines()
            if line.startswith(f"| `{key}` |")]
    assert len(rows) == 1, f"README has {len(rows)} rows for {key}"
    return rows[0]


def _errata_section(key: str) -> str:
    text = (ROOT / "ERRATA.md").read_text()
    match = re.search(rf"^## {key}\n(.*?)(?=^## |\Z)", text, flags=re.S | re.M)
    assert match, f"ERRATA has no section ## {key}"
    return match.group(1)


@pytest.mark.parametrize("key", paper_keys())
def test_readme_names_the_computed_verdict_and_its_deciding_claims(key: str) -> None:
    verdict = rescience_verdict(_claims(key))
    row = _readme_row(key)
    assert VERDICT.findall(row) == [verdict["verdict"]], row
    named = re.search(r"decided by ((?:[CX]\w+(?:, )?)+)", row)
    assert named, f"README's {key} row does not say which claims decide its verdict"
    assert named.group(1).split(", ") == list(verdict["deciding"]), row


@pytest.mark.parametrize("key", paper_keys())
def test_errata_gives_the_same_verdict_and_names_the_deciding_claims(key: str) -> None:
    verdict = rescience_verdict(_claims(key))
    section = _errata_section(key)
    found = VERDICT.findall(section)
    assert found and found[0] == verdict["verdict"], (key, found[:1], verdict["verdict"])
    for cid in verdict["deciding"]:
        assert re.search(rf"\b{cid}\b", section), f"ERRATA's {key} section does not name {cid}"


@pytest.mark.parametrize("key", paper_keys())
def test_the_deciding_claims_are_measured_claims_of_the_paper(key: str) -> None:
    claims = _claims(key)
    deciding = rescience_verdict(claims)["deciding"]
    for cid in deciding:
        entry = claims[cid]
        assert cid.startswith("C") and entry["basis"] == "measured", cid
        assert entry.get("source") != "ours", cid


def _robustness(key: str) -> dict:
    path = ROOT / "figures" / key / "robustness.json"
    return json.loads(path.read_text()) if path.exists() else {}


def _quoted_counts(text: str) -> list[tuple[str, dict[str, int]]]:
    return [(m.group(1), dict(zip(POINT_OUTCOMES, map(int, m.groups()[1:]), strict=True)))
            for m in COUNTS_PATTERN.finditer(text)]


@pytest.mark.parametrize("key", paper_keys())
def test_every_count_quoted_in_readme_and_errata_is_the_sweeps(key: str) -> None:
    summary = _robustness(key)
    texts = {"README": _readme_row(key), "ERRATA": _errata_section(key)}
    for where, text in texts.items():
        for cid, counts in _quoted_counts(text):
            assert cid in summary, f"{where} quotes counts for {key} {cid}, which the sweep has not"
            assert counts == summary[cid]["outcomes"], (where, key, cid, counts,
                                                        summary[cid]["outcomes"])


@pytest.mark.parametrize("key", paper_keys())
def test_errata_quotes_the_counts_of_every_deciding_claim(key: str) -> None:
    summary = _robustness(key)
    section = _errata_section(key)
    quoted = {cid for cid, _ in _quoted_counts(section)}
    for cid in rescience_verdict(_claims(key))["deciding"]:
        if cid in summary:
            expected = f"{cid} {counts_text(summary[cid]['outcomes'])}"
            assert cid in quoted, f"ERRATA's {key} section lacks '{expected}'"


def test_counts_text_is_the_form_the_pattern_reads() -> None:
    outcomes = {"holds": 8, "fails": 16, "fails-premise": 9, "not-checked": 0}
    text = f"C2a {counts_text(outcomes)}"
    assert text == "C2a 8 holds / 16 fails / 9 fails-premise / 0 not-checked"
    assert _quoted_counts(f"so {text}.") == [("C2a", outcomes)]


# ------------------------------------------------------------------------------------------
# the arena: README, ERRATA and the site say what its claims.json and registry say
# ------------------------------------------------------------------------------------------

_NUMBERS = {w: i for i, w in enumerate("zero one two three four five six seven eight nine ten eleven "
                                        "twelve".split())}


def test_arena_texts_count_the_registered_baselines() -> None:
    import secest.methods  # noqa: F401  (registers the papers' methods)
    from secest.arena.estimators import METHODS

    n = sum(m.kind == "baseline" for m in METHODS.values())
    for path in ("README.md", "docs/index.md", "docs/your-plant-your-method.md"):
        said = re.findall(r"\b(\w+) baselines\b", (ROOT / path).read_text())
        counts = [_NUMBERS[w] for w in said if w in _NUMBERS]
        assert counts and set(counts) == {n}, (path, said, n)


def test_errata_arena_applicability_is_claims_x5() -> None:
    x5 = json.loads((ROOT / "figures" / "arena" / "claims.json").read_text())["X5"]["measured"]
    errata = (ROOT / "ERRATA.md").read_text()
    section = errata[errata.index("## arena"):]
    line = next(t for t in section.splitlines() if t.startswith("- APPLICABILITY (X5)"))
    said = dict(re.findall(r"(\w+\d{4}) (\d+)", line[line.index("counts in X5"):]))
    assert {k: int(v) for k, v in said.items()} == x5["outside_theory"], (said, x5["outside_theory"])
    assert ("no paper method is N/A" in line) == (x5["n_na"] == 0), line
    assert f"of {x5['cells']})" in line, line


def test_readme_arena_numbers_are_claims_x2_at_their_printed_precision() -> None:
    """README's no-attack numbers (target / three-inertia / tank) are X2's upper bounds, rounded as
    printed; `diverged` where X2 did not score the cell; `(home)` where the plant is the paper's."""
    per_plant = json.loads((ROOT / "figures" / "arena" / "claims.json").read_text())["X2"]["measured"]
    readme = " ".join((ROOT / "README.md").read_text().split())
    plants = ("target20", "inertia5", "tank12")
    checked = 0
    for key in paper_keys(ROOT):
        number = r"(?:[\d.]+(?:e\d+)?‡?|diverged)(?: \(home\))?"
        m = re.search(rf"\b{key} ({number}(?: / {number}){{2}})", readme)
        assert m, key
        for plant, said in zip(plants, m.group(1).split(" / "), strict=True):
            row = per_plant["per_plant"][plant]
            name = f"{key} (home)" if "(home)" in said else key
            value = said.replace(" (home)", "")
            # ‡ exactly where X2 says the runs do not resolve the row's growth (Amendment 4)
            assert ("‡" in value) == (f"{key} on {plant}" in per_plant["undecided"]), (key, plant, said)
            value = value.replace("‡", "")
            if value == "diverged":
                assert name not in row and f"{key} on {plant}" in per_plant["not_scored"], (key, plant)
                continue
            assert name in row, (key, plant, said)
            digits = len(value.split("e")[0].replace(".", "").lstrip("0"))
            assert float(f"{row[name]:.{digits}g}") == float(value), (key, plant, row[name], value)
            checked += 1
    assert checked >= 12
