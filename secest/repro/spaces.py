"""Declared parameters and parameter spaces of the notebooks (``notebooks/<key>.toml``).

Every notebook declares its parameters in the cell tagged ``parameters`` of
``notebooks/<key>.py`` (literals with a comment each). Next to it,
``notebooks/<key>.toml`` says for every parameter

* its **domain**: type and admissible values, checked before a kernel starts
  (``python -m secest.repro.run``) and again when the notebook starts
  (:class:`secest.repro.results.Run`);
* its **provenance** ``tag``: ``PAPER`` (printed in the paper), ``MISSING`` (the paper
  withholds it; ours is a choice), ``RECONSTRUCTED`` (garbled in the paper, read by us),
  ``CORRECTED`` (printed wrongly, corrected by us) or ``ours`` (our own addition);
* for every value the paper does not pin down (MISSING and RECONSTRUCTED values,
  seeds, stand-in topologies, alternative readings of garbled text) its **declared
  space**: the plausible range or set, with the ``reason`` it was chosen from the
  paper's text and assumptions, never from the outcome. ``make robustness`` sweeps it.

The file's layout::

    [sweep]                       # how `make robustness` samples the declared space
    base = { mode = "paper" }     # parameters fixed at every point (figures are always off)
    design = "sobol"              # "sobol" or "lhs" for the ranges without `steps`
    n = 16                        # points of that design (a power of 2 for Sobol)
    seed = 1                      # seed of the design's scrambling

    [parameters.T]                # one table per parameter of the parameters cell
    type = "int"                  # int, float, bool, str, list, any
    min = 1                       # also max, exclusive_min, exclusive_max, choices,
    tag = "MISSING"               #  nullable, length, items ("int", "float", ...), unit
    reason = "the paper gives no horizon; its figures run to 100"
    space = { values = [30, 100, 300] }      # a set: every value is a grid level
    # space = { low = 0.1, high = 0.3, steps = 9 }  # a range on a grid (log = true: geometric)
    # space = { low = 0.1, high = 0.3 }             # a range sampled by the Sobol/LHS design
    # space = { same_as = "L_scale" }               # tied to another axis at every point
    # space = { low = 0, high = 1000000, integer = true, draw = true }  # a seed: its values are
    #                                               # draws, unordered (regions name draws)

A design is the full grid of the sets and stepped ranges times the Sobol / LHS
sample of the other ranges; the default point is always added.
"""

from __future__ import annotations

import ast
import io
import itertools
import json
import math
import tokenize
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from secest.core.validation import ValidationError

__all__ = [
    "TAGS",
    "TYPES",
    "Axis",
    "Parameter",
    "Space",
    "check_value",
    "design",
    "format_value",
    "load",
    "parameter_cell",
    "parse_value",
    "perturbation_points",
    "provenance_markdown",
    "validate",
]

TAGS = ("PAPER", "MISSING", "RECONSTRUCTED", "CORRECTED", "ours")
TYPES = ("int", "float", "bool", "str", "list", "any")
_SPEC_KEYS = {
    "type",
    "min",
    "max",
    "exclusive_min",
    "exclusive_max",
    "choices",
    "nullable",
    "length",
    "items",
    "tag",
    "reason",
    "space",
    "unit",
}
_SWEEP_KEYS = {"base", "design", "n", "seed", "perturb"}


def _root() -> Path:
    return Path(__file__).resolve().parents[2]


# ---------------------------------------------------------------------------- the parameters cell


@dataclass(frozen=True)
class CellEntry:
    """One assignment of a notebook's parameters cell: name, literal value and comment.

    Attributes
    ----------
    name : str
        The variable assigned.
    value : object
        The literal's value.
    source : str
        The literal's source text.
    comment : str
        The comments on the assignment's lines, joined (empty if none).
    """

    name: str
    value: Any
    source: str
    comment: str


def parameter_cell(key: str, root: Path | None = None) -> dict[str, CellEntry]:
    """Parse the cell tagged ``parameters`` of ``notebooks/<key>.py`` (literals only).

    Read with :mod:`ast` and :mod:`tokenize` from the jupytext source, so it is fast
    (no Jupyter import) and sees the comments that document each parameter.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.
    root : Path, optional
        Repository root holding ``notebooks/``; default: the one this package lives in.

    Returns
    -------
    dict of str to CellEntry
        Parameter name -> its entry (literal value, source text, comment), in the
        cell's order.

    Raises
    ------
    ValidationError
        If ``key`` names no notebook, the cell is missing, or holds anything but
        assignments of literals.
    """
    path = (root or _root()) / "notebooks" / f"{key}.py"
    if not path.exists():
        raise ValidationError(f"key {key!r} names no notebook: {path} does not exist")
    lines = path.read_text().splitlines(keepends=True)
    starts = [i for i, line in enumerate(lines) if line.startswith("# %%") and "parameters" in line]
    if len(starts) != 1:
        raise ValidationError(f"{path.name} must have exactly one cell tagged 'parameters'")
    body: list[str] = []
    for line in lines[starts[0] + 1 :]:
        if line.startswith("# %%"):
            break
        body.append(line)
    text = "".join(body)
    comments: dict[int, str] = {}
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type == tokenize.COMMENT:
            comments[tok.start[0]] = tok.string.lstrip("#").strip()
    entries: dict[str, CellEntry] = {}
    for node in ast.parse(text).body:
        if not isinstance(node, ast.Assign) or len(node.targets) != 1:
            raise ValidationError(f"the parameters cell of {path.name} must hold 'name = literal' lines")
        target = node.targets[0]
        if not isinstance(target, ast.Name):
            raise ValidationError(f"the parameters cell of {path.name} must assign plain names")
        try:
            value = ast.literal_eval(node.value)
        except ValueError as exc:
            raise ValidationError(f"parameter {target.id} of {path.name} is not a literal") from exc
        note = " ".join(comments[n] for n in range(node.lineno, node.end_lineno + 1) if n in comments)
        entries[target.id] = CellEntry(target.id, value, ast.get_source_segment(text, node.value), note)
    return entries


# ---------------------------------------------------------------------------- specifications


@dataclass(frozen=True)
class Axis:
    """The declared space of one parameter: a set, a (stepped) range, or a tie to another axis.

    Exactly one form is used (see :attr:`kind`): ``values`` (a set), ``low`` / ``high``
    with ``steps`` (a grid) or without (sampled by the Sobol / LHS design), or ``same_as``.

    Attributes
    ----------
    values : tuple, optional
        The levels of a set, in order.
    labels : tuple of str, optional
        One short printable name per entry of ``values`` (for long values, e.g. graphs).
    low, high : float, optional
        The bounds of a range, ``low < high`` (``low > 0`` if ``log``).
    steps : int, optional
        Number of grid levels of a stepped range (at least 2); None: a sampled range.
    log : bool
        Space the range geometrically rather than linearly. Default False.
    integer : bool
        Round the range's values to integers. Default False.
    same_as : str, optional
        Name of another swept parameter this one equals at every point (a tied axis).
    draw : bool
        The axis is a seed (``draw = true`` in its space): its values name random draws and
        carry no order, so a region over it names the draws where a claim fails (or holds),
        never a threshold (:func:`secest.repro.sweep.describe_region`). Default False.
    """

    values: tuple | None = None
    labels: tuple[str, ...] | None = None
    low: float | None = None
    high: float | None = None
    steps: int | None = None
    log: bool = False
    integer: bool = False
    same_as: str | None = None
    draw: bool = False

    @property
    def kind(self) -> str:
        """``set``, ``grid`` (stepped range), ``sample`` (range for the QMC design) or ``tied``."""
        if self.same_as is not None:
            return "tied"
        if self.values is not None:
            return "set"
        return "grid" if self.steps is not None else "sample"

    def grid_values(self) -> list[Any]:
        """The levels of a set or stepped range."""
        if self.values is not None:
            return list(self.values)
        assert self.low is not None and self.high is not None and self.steps is not None
        if self.log:
            vals = np.geomspace(self.low, self.high, self.steps)
        else:
            vals = np.linspace(self.low, self.high, self.steps)
        return [self._cast(v) for v in vals]

    def from_unit(self, u: float) -> Any:
        """Map ``u`` in [0, 1) to the range (geometrically if ``log``)."""
        assert self.low is not None and self.high is not None
        if self.log:
            v = math.exp(math.log(self.low) + u * (math.log(self.high) - math.log(self.low)))
        else:
            v = self.low + u * (self.high - self.low)
        return self._cast(v)

    def _cast(self, v: float) -> Any:
        return int(round(float(v))) if self.integer else float(np.float64(v).round(12))

    def contains(self, value: Any) -> bool:
        """Whether ``value`` is a point of this axis."""
        if self.values is not None:
            return any(_same(value, v) for v in self.values)
        if self.low is None or self.high is None or isinstance(value, bool):
            return False
        return isinstance(value, int | float) and self.low - 1e-12 <= value <= self.high + 1e-12

    def label(self, value: Any) -> str:
        """A short printable name of ``value`` (its label for sets of long values)."""
        if self.values is not None and self.labels is not None:
            for v, lab in zip(self.values, self.labels, strict=True):
                if _same(value, v):
                    return lab
        return format_value(value)


@dataclass(frozen=True)
class Parameter:
    """Domain, provenance and declared space of one notebook parameter.

    Built by :func:`load` from the ``parameters`` cell (name, default, comment) and the
    parameter's table in ``notebooks/<key>.toml`` (everything else).

    Attributes
    ----------
    name : str
        The variable name in the ``parameters`` cell.
    default : object
        Its literal value in the cell.
    comment : str
        The comment documenting it in the cell (empty if none).
    type : str
        One of :data:`TYPES`: ``"int"``, ``"float"``, ``"bool"``, ``"str"``, ``"list"``
        or ``"any"`` (default: inferred from ``default``).
    tag : str, optional
        Provenance tag, one of :data:`TAGS` (from the TOML or the comment).
    reason : str, optional
        Why the declared space is what it is (from the paper's text and assumptions).
    unit : str, optional
        Physical unit, shown in the provenance table.
    nullable : bool
        Whether None is admissible. Default False.
    min, max : float, optional
        Inclusive bounds of an ``int`` or ``float``.
    exclusive_min, exclusive_max : float, optional
        Exclusive bounds of an ``int`` or ``float``.
    choices : tuple, optional
        The only admissible values.
    length : int, optional
        Required length of a ``list``.
    items : str, optional
        Required type of a ``list``'s items: ``"int"``, ``"float"``, ``"str"``,
        ``"bool"`` or ``"list"``.
    space : Axis, optional
        The declared space swept by ``make robustness``; None: not swept.
    """

    name: str
    default: Any
    comment: str
    type: str = "any"
    tag: str | None = None
    reason: str | None = None
    unit: str | None = None
    nullable: bool = False
    min: float | None = None
    max: float | None = None
    exclusive_min: float | None = None
    exclusive_max: float | None = None
    choices: tuple | None = None
    length: int | None = None
    items: str | None = None
    space: Axis | None = None

    def domain_text(self) -> str:
        """What the domain admits, in words (used in error messages and ``--list``)."""
        if self.choices is not None:
            text = "one of " + ", ".join(repr(c) for c in self.choices)
        else:
            text = {
                "int": "an integer",
                "float": "a real number",
                "bool": "true or false",
                "str": "a string",
                "list": "a list",
                "any": "a literal",
            }[self.type]
            if self.type == "list" and self.items:
                text = f"a list of {self.items}"
            if self.length is not None:
                text += f" of length {self.length}"
            bounds = [
                f">= {format_value(self.min)}" if self.min is not None else "",
                f"> {format_value(self.exclusive_min)}" if self.exclusive_min is not None else "",
                f"<= {format_value(self.max)}" if self.max is not None else "",
                f"< {format_value(self.exclusive_max)}" if self.exclusive_max is not None else "",
            ]
            if any(bounds):
                text += " " + " and ".join(b for b in bounds if b)
        return text + (" or None" if self.nullable else "")

    def space_text(self) -> str:
        """The declared space in words, ``-`` when the parameter is not swept."""
        return "-" if self.space is None else _axis_text(self.space)


@dataclass(frozen=True)
class Space:
    """Every parameter of one notebook with its declared space and the sweep settings.

    Attributes
    ----------
    key : str
        Paper key of the notebook.
    parameters : dict of str to Parameter
        Every parameter of the ``parameters`` cell, in its order.
    base : dict
        Parameter values fixed at every point of the sweep (``[sweep] base``).
    design : str
        ``"sobol"`` or ``"lhs"``: how the sampled ranges are sampled. Default ``"sobol"``.
    n : int
        Number of points of that design. Default 8.
    seed : int
        Seed of the design's scrambling. Default 0.
    perturb : tuple of dict
        Explicit perturbation points (``[[sweep.perturb]]``), see
        :func:`perturbation_points`.
    """

    key: str
    parameters: dict[str, Parameter]
    base: dict[str, Any] = field(default_factory=dict)
    design: str = "sobol"
    n: int = 8
    seed: int = 0
    perturb: tuple[dict[str, Any], ...] = ()

    @property
    def axes(self) -> dict[str, Axis]:
        """The swept parameters and their axes, in the order of the parameters cell."""
        return {name: p.space for name, p in self.parameters.items() if p.space is not None}

    @property
    def defaults(self) -> dict[str, Any]:
        """Every parameter's default value."""
        return {name: p.default for name, p in self.parameters.items()}


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b
    if isinstance(a, int | float) and isinstance(b, int | float):
        return math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15)
    return json.dumps(a) == json.dumps(b)


def format_value(value: Any) -> str:
    """A short printable form of a parameter value (at most 40 characters).

    Parameters
    ----------
    value : object
        A parameter value: floats are written with 6 significant digits, strings as
        they are, anything else as JSON.

    Returns
    -------
    str
        The text, cut to 37 characters and ``...`` when longer than 40.
    """
    if isinstance(value, float):
        return format(value, ".6g")
    text = json.dumps(value) if not isinstance(value, str) else value
    return text if len(text) <= 40 else text[:37] + "..."


def _axis(name: str, spec: Mapping[str, Any]) -> Axis:
    known = {"values", "labels", "low", "high", "steps", "log", "integer", "same_as", "draw"}
    unknown = sorted(set(spec) - known)
    if unknown:
        raise ValidationError(f"space of {name} has unknown keys {unknown}; known: {sorted(known)}")
    draw = spec.get("draw", False)
    if not isinstance(draw, bool):
        raise ValidationError(f"space of {name}: draw must be true or false, found {draw!r}")
    if "same_as" in spec:
        if draw:
            raise ValidationError(f"space of {name}: a tied axis takes its kind from "
                                  f"{spec['same_as']!r}; declare draw there")
        return Axis(same_as=str(spec["same_as"]))
    if "values" in spec:
        values = tuple(spec["values"])
        labels = tuple(spec["labels"]) if "labels" in spec else None
        if not values or (labels is not None and len(labels) != len(values)):
            raise ValidationError(
                f"space of {name} needs a non-empty 'values' (and one label per value)"
            )
        return Axis(values=values, labels=labels, draw=draw)
    if "low" not in spec or "high" not in spec:
        raise ValidationError(f"space of {name} needs 'values', 'low' and 'high', or 'same_as'")
    low, high = float(spec["low"]), float(spec["high"])
    log = bool(spec.get("log", False))
    if not low < high or (log and low <= 0):
        raise ValidationError(
            f"space of {name} needs low < high (and low > 0 if log), found {low}, {high}"
        )
    steps = spec.get("steps")
    if steps is not None and (not isinstance(steps, int) or steps < 2):
        raise ValidationError(f"space of {name}: steps must be an integer >= 2, found {steps!r}")
    return Axis(low=low, high=high, steps=steps, log=log, integer=bool(spec.get("integer", False)),
                draw=draw)


def _parameter(name: str, entry: CellEntry, spec: Mapping[str, Any]) -> Parameter:
    unknown = sorted(set(spec) - _SPEC_KEYS)
    if unknown:
        raise ValidationError(
            f"parameter {name} has unknown keys {unknown}; known: {sorted(_SPEC_KEYS)}"
        )
    ptype = spec.get("type", _infer_type(entry.value))
    if ptype not in TYPES:
        raise ValidationError(f"parameter {name}: type must be one of {TYPES}, found {ptype!r}")
    tag = spec.get("tag", _tag_in(entry.comment))
    if tag is not None and tag not in TAGS:
        raise ValidationError(f"parameter {name}: tag must be one of {TAGS}, found {tag!r}")
    choices = spec.get("choices")
    return Parameter(
        name=name,
        default=entry.value,
        comment=entry.comment,
        type=ptype,
        tag=tag,
        reason=spec.get("reason"),
        unit=spec.get("unit"),
        nullable=bool(spec.get("nullable", False)),
        min=spec.get("min"),
        max=spec.get("max"),
        exclusive_min=spec.get("exclusive_min"),
        exclusive_max=spec.get("exclusive_max"),
        choices=tuple(choices) if choices is not None else None,
        length=spec.get("length"),
        items=spec.get("items"),
        space=_axis(name, spec["space"]) if "space" in spec else None,
    )


def _tag_in(comment: str) -> str | None:
    """The provenance tag written in a parameter's comment, e.g. ``(PAPER, Sec. V)``."""
    import re

    found = re.search(r"\((PAPER|MISSING|RECONSTRUCTED|CORRECTED|ours)\b", comment)
    return found.group(1) if found else None


def _infer_type(value: Any) -> str:
    if isinstance(value, bool):
        return "bool"
    for python, name in ((int, "int"), (float, "float"), (str, "str"), (list, "list")):
        if isinstance(value, python):
            return name
    return "any"


def load(key: str, root: Path | None = None) -> Space:
    """Read ``notebooks/<key>.toml`` against the parameters cell of ``notebooks/<key>.py``.

    A parameter without a table in the TOML file gets the type of its default and
    no range. Every declared space must lie in its parameter's domain and hold the
    default; tied axes must name a swept parameter.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``. A missing ``notebooks/<key>.toml`` is not an
        error (no domains, no declared spaces).
    root : Path, optional
        Repository root holding ``notebooks/``; default: the one this package lives in.

    Returns
    -------
    Space
        The notebook's parameters and sweep settings.

    Raises
    ------
    ValidationError
        If the file names a parameter the notebook does not declare, has unknown
        keys, or a default or space value lies outside the domain.
    """
    root = root or _root()
    cell = parameter_cell(key, root)
    path = root / "notebooks" / f"{key}.toml"
    data: dict[str, Any] = {}
    if path.exists():
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    specs = data.get("parameters", {})
    undeclared = sorted(set(specs) - set(cell))
    if undeclared:
        raise ValidationError(
            f"{path.name} describes parameters {undeclared} that {key}.py does not declare"
        )
    params = {name: _parameter(name, entry, specs.get(name, {})) for name, entry in cell.items()}
    sweep = data.get("sweep", {})
    unknown = sorted(set(sweep) - _SWEEP_KEYS)
    if unknown:
        raise ValidationError(
            f"[sweep] of {path.name} has unknown keys {unknown}; known: {sorted(_SWEEP_KEYS)}"
        )
    space = Space(
        key=key,
        parameters=params,
        base=dict(sweep.get("base", {})),
        design=sweep.get("design", "sobol"),
        n=int(sweep.get("n", 8)),
        seed=int(sweep.get("seed", 0)),
        perturb=tuple(dict(p) for p in sweep.get("perturb", [])),
    )
    _check_space(space)
    return space


def _check_space(space: Space) -> None:
    if space.design not in ("sobol", "lhs"):
        raise ValidationError(f"[sweep] design must be 'sobol' or 'lhs', found {space.design!r}")
    validate(space, space.base)
    for p in space.parameters.values():
        check_value(p, p.default)
        axis = p.space
        if axis is None:
            continue
        if axis.kind == "tied":
            target = space.parameters.get(axis.same_as)
            if target is None or target.space is None or target.space.kind == "tied":
                raise ValidationError(f"space of {p.name}: same_as must name a swept parameter")
            continue
        if axis.kind in ("set", "grid"):
            for v in axis.grid_values():
                check_value(p, v)
        else:
            check_value(p, axis.from_unit(0.0))
            check_value(p, axis.from_unit(1.0))
        if p.name not in space.base and not axis.contains(p.default):
            raise ValidationError(
                f"the default of {p.name} ({format_value(p.default)}) lies outside its declared space"
            )
    for point in space.perturb:
        validate(space, point)


# ---------------------------------------------------------------------------- checking values


def check_value(param: Parameter, value: Any) -> Any:
    """Check ``value`` against ``param``'s domain; return it (ints accepted for floats).

    Parameters
    ----------
    param : Parameter
        The parameter whose domain (type, bounds, choices, length, items,
        nullability) is checked.
    value : object
        The candidate value.

    Returns
    -------
    object
        ``value`` unchanged.

    Raises
    ------
    ValidationError
        One line naming the parameter, what it expects and what it got.
    """

    def fail() -> ValidationError:
        return ValidationError(f"parameter {param.name} must be {param.domain_text()}, found {value!r}")

    if value is None:
        if param.nullable or param.type == "any":
            return None
        raise fail()
    if param.choices is not None and not any(_same(value, c) for c in param.choices):
        raise fail()
    if param.type == "int" and (isinstance(value, bool) or not isinstance(value, int)):
        raise fail()
    if param.type == "float":
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise fail()
    if param.type == "bool" and not isinstance(value, bool):
        raise fail()
    if param.type == "str" and not isinstance(value, str):
        raise fail()
    if param.type == "list":
        if not isinstance(value, list) or (param.length is not None and len(value) != param.length):
            raise fail()
        if param.items is not None and not all(_item_ok(param.items, v) for v in value):
            raise fail()
    if param.type in ("int", "float") and not _in_bounds(param, value):
        raise fail()
    return value


def _item_ok(items: str, v: Any) -> bool:
    if items == "float":
        return not isinstance(v, bool) and isinstance(v, int | float) and math.isfinite(v)
    if items == "int":
        return not isinstance(v, bool) and isinstance(v, int)
    if items == "str":
        return isinstance(v, str)
    if items == "bool":
        return isinstance(v, bool)
    if items == "list":
        return isinstance(v, list)
    raise ValidationError(f"items must be int, float, str, bool or list, found {items!r}")


def _in_bounds(p: Parameter, v: float) -> bool:
    return not (
        (p.min is not None and v < p.min)
        or (p.max is not None and v > p.max)
        or (p.exclusive_min is not None and v <= p.exclusive_min)
        or (p.exclusive_max is not None and v >= p.exclusive_max)
    )


def parse_value(param: Parameter, text: str) -> Any:
    """Parse a command-line string as a value of ``param`` (then :func:`check_value` it).

    Booleans accept true/false, yes/no, on/off, 1/0 (any case); ``None``/``null``
    gives None; strings are taken as they are; everything else is a Python literal
    (``3``, ``0.5``, ``[1, 2]``).

    Parameters
    ----------
    param : Parameter
        The parameter the text is a value of (its type decides how it is parsed).
    text : str
        The value as typed on the command line.

    Returns
    -------
    object
        The parsed value, checked against ``param``'s domain.

    Raises
    ------
    ValidationError
        If the text is not a value of ``param``'s type or lies outside its domain.
        (A text that is not a Python literal is taken as a string when the type is ``any``.)
    """
    stripped = text.strip()
    if stripped.lower() in ("none", "null"):
        return check_value(param, None)
    if param.type == "bool":
        table = {
            "true": True,
            "yes": True,
            "on": True,
            "1": True,
            "false": False,
            "no": False,
            "off": False,
            "0": False,
        }
        if stripped.lower() not in table:
            raise ValidationError(f"parameter {param.name} must be true or false, found {text!r}")
        return table[stripped.lower()]
    if param.type == "str":
        return check_value(param, text)
    try:
        value = ast.literal_eval(stripped)
    except (ValueError, SyntaxError):
        if param.type == "any":
            return text
        raise ValidationError(
            f"parameter {param.name} must be {param.domain_text()}, found {text!r}"
        ) from None
    return check_value(param, value)


def validate(space: Space | str, values: Mapping[str, Any]) -> dict[str, Any]:
    """Check every entry of ``values`` against the domain of the notebook's parameters.

    Unknown names are an error (papermill itself only warns about them).

    Parameters
    ----------
    space : Space or str
        The notebook's declared parameters, or its paper key (then read with :func:`load`).
    values : mapping
        Parameter name -> value, a subset of the notebook's parameters.

    Returns
    -------
    dict
        The checked values, by name, in the order of ``values``.

    Raises
    ------
    ValidationError
        If a name is not declared by the notebook or a value lies outside its domain.
    """
    if isinstance(space, str):
        space = load(space)
    unknown = sorted(set(values) - set(space.parameters))
    if unknown:
        raise ValidationError(
            f"parameters {unknown} are not declared by notebook {space.key!r}; "
            f"declared: {sorted(space.parameters)}"
        )
    return {name: check_value(space.parameters[name], v) for name, v in values.items()}


# ---------------------------------------------------------------------------- designs


def design(space: Space) -> list[dict[str, Any]]:
    """The points of the declared space that ``make robustness`` runs, in a fixed order.

    Each point maps every swept parameter (and tied one) to its value; ``base``
    is not included. The full grid of sets and stepped ranges is crossed with a
    scrambled Sobol (or Latin hypercube) sample of ``n`` points over the other
    ranges; the default point comes first.

    Parameters
    ----------
    space : Space
        The notebook's declared space and sweep settings (``design``, ``n``, ``seed``).

    Returns
    -------
    list of dict
        The points, each mapping parameter name -> value; duplicates removed, the
        default point first. Deterministic for a given ``space``.
    """
    from scipy.stats import qmc

    axes = space.axes
    grid_names = [n for n, a in axes.items() if a.kind in ("set", "grid")]
    sample_names = [n for n, a in axes.items() if a.kind == "sample"]
    grid = list(itertools.product(*(axes[n].grid_values() for n in grid_names)))
    if sample_names:
        d = len(sample_names)
        if space.design == "sobol":
            unit = qmc.Sobol(d, scramble=True, seed=space.seed).random(space.n)
        else:
            unit = qmc.LatinHypercube(d, seed=space.seed).random(space.n)
        sample = [
            tuple(axes[n].from_unit(u) for n, u in zip(sample_names, row, strict=True)) for row in unit
        ]
    else:
        sample = [()]
    points = [_default_point(space)]
    for g in grid:
        for s in sample:
            point = dict(zip(grid_names, g, strict=True)) | dict(zip(sample_names, s, strict=True))
            _fill_ties(space, point)
            if not any(_same_point(point, q) for q in points):
                points.append(point)
    return points


def _default_point(space: Space) -> dict[str, Any]:
    return {name: space.parameters[name].default for name in space.axes}


def _fill_ties(space: Space, point: dict[str, Any]) -> None:
    for name, axis in space.axes.items():
        if axis.kind == "tied":
            point[name] = point[axis.same_as]


def _same_point(a: Mapping[str, Any], b: Mapping[str, Any]) -> bool:
    return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)


def perturbation_points(space: Space) -> list[dict[str, Any]]:
    """At least three points of the declared space other than the default, edges included.

    The ``[[sweep.perturb]]`` points of the TOML file if it gives three or more;
    otherwise every axis at its low edge, every axis at its high edge, and every
    axis at its middle level (sets: first, last, middle value).

    Parameters
    ----------
    space : Space
        The notebook's declared space.

    Returns
    -------
    list of dict
        The points, each mapping swept (and tied) parameter name -> value; in the
        second case the edge / middle points equal to the default point are left
        out and the (fewer than three) ``[[sweep.perturb]]`` points appended.

    Raises
    ------
    ValidationError
        If the notebook declares no space to perturb (and fewer than three
        ``[[sweep.perturb]]`` points).
    """
    if len(space.perturb) >= 3:
        return [dict(p) for p in space.perturb]
    axes = {n: a for n, a in space.axes.items() if a.kind != "tied"}
    if not axes:
        raise ValidationError(f"notebook {space.key!r} declares no space to perturb")
    points = []
    for pick in (_low, _high, _middle):
        point = {n: pick(a) for n, a in axes.items()}
        _fill_ties(space, point)
        points.append(point)
    default = _default_point(space)
    return [p for p in points if not _same_point(p, default)] + [dict(p) for p in space.perturb]


def _low(a: Axis) -> Any:
    return a.grid_values()[0] if a.kind in ("set", "grid") else a.from_unit(0.0)


def _high(a: Axis) -> Any:
    return a.grid_values()[-1] if a.kind in ("set", "grid") else a.from_unit(1.0)


def _middle(a: Axis) -> Any:
    if a.kind in ("set", "grid"):
        vals = a.grid_values()
        return vals[len(vals) // 2]
    return a.from_unit(0.5)


# ---------------------------------------------------------------------------- rendering


def provenance_markdown(key: str, *, only_tagged: bool = False) -> str:
    """A Markdown table of every parameter: value, tag, domain, declared space and reason.

    Notebooks display it in their provenance section, so the declared spaces the
    robustness sweep uses are visible where the reader checks the values.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.
    only_tagged : bool, optional
        List only the parameters with a provenance tag. Default False (all of them).

    Returns
    -------
    str
        The table, one row per parameter in the order of the ``parameters`` cell;
        the ``reason`` column falls back to the parameter's comment.

    Raises
    ------
    ValidationError
        As :func:`load`.
    """
    space = load(key)
    rows = [
        "| parameter | default | tag | admissible | declared space (swept) | reason |",
        "|---|---|---|---|---|---|",
    ]
    for p in space.parameters.values():
        if only_tagged and p.tag is None:
            continue
        axis = "–" if p.space is None else p.space_text().replace("|", "\\|")
        unit = f" [{p.unit}]" if p.unit else ""
        reason = (p.reason or p.comment or "").replace("|", "\\|")
        rows.append(
            f"| `{p.name}`{unit} | `{format_value(p.default)}` | {p.tag or '–'} | {p.domain_text()} "
            f"| {axis} | {reason} |"
        )
    return "\n".join(rows)


def _axis_text(a: Axis) -> str:
    if a.kind == "tied":
        return f"same as `{a.same_as}`"
    if a.kind == "set":
        return "{" + ", ".join(a.label(v) for v in a.grid_values()) + "}"
    scale = "geometric " if a.log else ""
    if a.kind == "grid":
        return f"[{format_value(a.low)}, {format_value(a.high)}], {a.steps} {scale}steps"
    text = f"[{format_value(a.low)}, {format_value(a.high)}] ({scale}sampled)"
    return text + (", draws of a seed (unordered)" if a.draw else "")
