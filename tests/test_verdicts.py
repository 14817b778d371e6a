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
