"""The arena's pre-registered protocol: readable, and its seeds disjoint from every seed used before."""

from __future__ import annotations

import tomllib

import pytest
from conftest import repo_root

from secest.arena import protocol
from secest.core.validation import ValidationError

FIRST_DESIGN_SEEDS = {2026, 1, 2, 3}
"""The seed axis notebooks/arena.toml declared (and its perturbation points used) until the test
stage replaced it (issue #28; the file's History says so)."""


def _seeds_used_before() -> set[int]:
    """Trial seeds the repository ran: the matrix's (cards.toml) and the arena's first design's."""
    cards = tomllib.loads((repo_root() / "secest" / "arena" / "cards.toml").read_text())
    return {cards["matrix"]["seed"]} | FIRST_DESIGN_SEEDS


def test_the_protocol_loads_and_its_seeds_are_new() -> None:
    p = protocol.load()
    val, test = set(p["seeds"]["validation"]), set(p["seeds"]["test"])
    assert val and test and not val & test
    used = _seeds_used_before()
    assert used == {1, 2, 3, 2026}
    retired = set(p["seeds"]["retired_test"])  # Amendment 4: seen under three versions of the rules
    assert retired == set(range(201, 209))
    assert not (val | test) & (used | retired)
    for method, constants in p["search"].items():
        assert all(isinstance(v, list) and v for v in constants.values()), method


@pytest.mark.parametrize("text, match", [
    ("[seeds]\nvalidation = [1]\ntest = [1]\n[score]\n[divergence]\n[detection]\n[tuning]\n[search]\n",
     "disjoint"),
    ("[seeds]\nvalidation = []\ntest = [2]\n[score]\n[divergence]\n[detection]\n[tuning]\n[search]\n",
     "seeds.validation"),
    ("[seeds]\nvalidation = [1]\ntest = [2]\nretired_test = [2]\n[score]\n[divergence]\n[detection]\n"
     "[tuning]\n[search]\n", "retired test seeds"),
    ("[seeds]\nvalidation = [1]\ntest = [2]\n[score]\n[divergence]\n[detection]\n[tuning]\n[search.x]\nk = 3\n",
     "search.x.k"),
    ("[seeds]\nvalidation = [1]\ntest = [2]\n", "expected the tables"),
])
def test_a_malformed_protocol_is_refused(text: str, match: str) -> None:
    with pytest.raises(ValidationError, match=match):
        protocol.load(text)
