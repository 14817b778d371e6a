"""The arena's pre-registered protocol (``protocol.toml``): seeds, search sets, tuning and scores.

The file was committed before any result on its test seeds existed; :func:`load` reads it and
checks its structure, so a redesign of the arena implements exactly what was registered.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from typing import Any

from secest.core.validation import ValidationError

__all__ = ["SECTIONS", "load"]

SECTIONS = ("seeds", "score", "divergence", "detection", "tuning", "search")
"""The tables of ``protocol.toml``."""


def _seed_list(name: str, value: Any) -> list[int]:
    if (not isinstance(value, list) or not value
            or not all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in value)):
        raise ValidationError(f"seeds.{name}: expected a non-empty list of integers >= 0, "
                              f"found {value!r}")
    if len(set(value)) != len(value):
        raise ValidationError(f"seeds.{name}: a seed is listed twice in {value!r}")
    return value


def load(text: str | None = None) -> dict[str, Any]:
    """The protocol, checked.

    Parameters
    ----------
    text : str, optional
        TOML text laid out like ``secest/arena/protocol.toml``; default: that file.

    Returns
    -------
    dict
        Its tables (:data:`SECTIONS`); ``search`` maps a method name to its search set, each
        constant a non-empty list whose first entry is the printed value.

    Raises
    ------
    ValidationError
        If a table is missing or unknown, the validation and test seeds are not two disjoint
        lists of integers, either meets the retired test seeds (``retired_test``, optional),
        or a search set holds a constant that is not a non-empty list.
    """
    if text is None:
        text = resources.files("secest.arena").joinpath("protocol.toml").read_text()
    data = tomllib.loads(text)
    if set(data) != set(SECTIONS):
        raise ValidationError(f"protocol: expected the tables {sorted(SECTIONS)}, found {sorted(data)}")
    seeds = data["seeds"]
    validation = set(_seed_list("validation", seeds.get("validation")))
    test = set(_seed_list("test", seeds.get("test")))
    shared = validation & test
    if shared:
        raise ValidationError(f"seeds: validation and test seeds must be disjoint, "
                              f"both hold {sorted(shared)}")
    retired = (set(_seed_list("retired_test", seeds["retired_test"])) if "retired_test" in seeds
               else set())
    reused = (validation | test) & retired
    if reused:
        raise ValidationError(f"seeds: the retired test seeds {sorted(reused)} may not be "
                              "validation or test seeds again")
    for method, constants in data["search"].items():
        for name, values in constants.items():
            if not isinstance(values, list) or not values:
                raise ValidationError(f"search.{method}.{name}: expected a non-empty list, "
                                      f"found {values!r}")
    return data
