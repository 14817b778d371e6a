"""The arena as a tool: race methods on cards, and write the matrix as files and text.

:func:`race` is the whole arena in one call (the command line ``python -m secest.arena`` is a
thin layer over it, :mod:`secest.arena.cli`): cards (the package's and a file of one's own),
methods (registered names or :class:`~secest.arena.estimators.Method` subclasses), the scenarios
of the cross, :func:`secest.arena.matrix.run_matrix`, and, given ``out``, the files:

``matrix.csv``, ``matrix.json``
   one row per (scenario, method) cell: :func:`columns` (every number with its interval, NaN /
   ``null`` where there is none) and the words of :func:`secest.arena.matrix.table_rows`
``heatmap.png``
   :func:`heatmap`, the steady-window score of every cell
``tables/<plant>.md``
   :func:`plant_tables`, one markdown table per plant

:func:`card_schema` renders :data:`secest.arena.scenarios.CARD_KEYS`, the schema the card
validator uses, as the markdown tables of the documentation.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from secest.arena import estimators, matrix, scenarios
from secest.arena.estimators import METHODS, Method, register
from secest.core.validation import ValidationError, check_bool, check_real

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "COLUMNS",
    "GROUPS",
    "can_plot",
    "card_schema",
    "columns",
    "heatmap",
    "method_order",
    "plant_tables",
    "race",
    "write",
]

COLUMNS = ("scenario", "method", "status", "steady", "steady_low", "steady_high", "worst", "worst_low",
           "worst_high", "transient", "transient_low", "transient_high", "growth", "detection",
           "detection_low", "detection_high", "false_alarm", "false_alarm_low", "false_alarm_high",
           "reason", "outside")
"""The columns of :func:`columns` (and of ``matrix.csv``), in order."""
GROUPS = (("baseline", "baselines"), ("paper", "papers' methods"), (None, "other methods"))
"""Column groups of the heatmap: :attr:`Method.kind` (None: any other kind) and its label."""
VMAX = 1e3
"""Colours of :func:`heatmap` saturate above this score (the number in the cell is exact)."""


def _triple(value: tuple[float, float, float] | None) -> tuple[float, float, float]:
    return (np.nan, np.nan, np.nan) if value is None else tuple(float(v) for v in value)


def columns(m: matrix.Matrix) -> dict[str, list]:
    """One row per cell of ``m`` (scenario, then method order): every number of its tables.

    Parameters
    ----------
    m : Matrix
        The scored matrix (:func:`secest.arena.matrix.run_matrix`).

    Returns
    -------
    dict
        :data:`COLUMNS` -> list: the status, the unit-free steady-window network and worst-node
        scores, the transient score, the growth factor, the detection and false-alarm rates
        with their 95 % intervals (``<name>_low``, ``<name>_high``; NaN where the cell has no
        such number), the reason of a cell that is not scored, and the conditions of the
        method's theory that fail there (``outside``, ``"; "``-joined).
    """
    data: dict[str, list] = {k: [] for k in COLUMNS}
    for sc in matrix.check_matrix("m", m).scenarios:
        for name in m.methods:
            c = m.cell(sc.name, name)
            data["scenario"].append(sc.name)
            data["method"].append(name)
            data["status"].append(c.status)
            for key, value in (("steady", c.steady), ("worst", c.steady_worst),
                               ("transient", c.transient), ("detection", c.detection),
                               ("false_alarm", c.false_alarm)):
                v, lo, hi = _triple(value)
                data[key].append(v)
                data[f"{key}_low"].append(lo)
                data[f"{key}_high"].append(hi)
            data["growth"].append(np.nan if c.growth is None else float(c.growth))
            data["reason"].append(c.reason)
            data["outside"].append("; ".join(c.outside))
    return data


def method_order(names: Sequence[str]) -> list[str]:
    """``names`` grouped as the heatmap's columns (:data:`GROUPS`), registration order within.

    Parameters
    ----------
    names : sequence of str
        Registered method names.
    """
    names = estimators.check_names("names", names)
    return [n for kind, _ in GROUPS for n in names if _group(n) == kind]


def _group(name: str) -> str | None:
    """The heatmap group of method ``name``: its kind if :data:`GROUPS` names it, else None."""
    kind = METHODS[name].kind
    return kind if kind in {k for k, _ in GROUPS if k is not None} else None


def heatmap(m: matrix.Matrix, *, title: str, width: float = 7.16) -> Figure:
    """Every cell's steady-window score on a logarithmic colour scale, the number printed in it.

    Rows are the scenarios, grouped by plant (a line between plants, the plant's name on the
    right); columns the methods in :func:`method_order`, a line between groups. Hatched grey
    cells are N/A, hatched black ones diverged or raised (``div.``, ``err.``); a dot in the
    corner marks a cell outside the method's theory (scored all the same). Colours run from
    ``min(1, smallest score)`` to ``min(VMAX, max(10, largest score))``.

    Parameters
    ----------
    m : Matrix
        The scored matrix; at least one cell must be scored.
    title : str
        Title of the axes (what was run: runs, steps, seed...).
    width : float
        Figure width in inches (the height grows with the number of scenarios).

    Returns
    -------
    matplotlib.figure.Figure
        Not attached to pyplot; save it with ``fig.savefig``. Font sizes are set here (those of
        :mod:`secest.repro.plotting`'s house style), so the figure reads the same without it.
    """
    matrix.check_matrix("m", m)
    if not isinstance(title, str):
        raise ValidationError(f"title must be a string, found {type(title).__name__}")
    width = check_real("width", width, lower=0.0, lower_open=True)
    import matplotlib as mpl
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Rectangle

    order = method_order(m.methods)
    rows = m.scenarios
    values = np.full((len(rows), len(order)), np.nan)
    for i, sc in enumerate(rows):
        for j, name in enumerate(order):
            c = m.cell(sc.name, name)
            if c.status == "ok":
                values[i, j] = c.steady[0]
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        raise ValidationError("m: the heatmap needs at least one scored cell, found none")
    norm = LogNorm(vmin=min(1.0, float(finite.min())), vmax=min(VMAX, max(10.0, float(finite.max()))))
    cmap = mpl.colormaps["YlOrRd"]
    height = 1.2 + 0.27 * len(rows)  # inches
    fig = Figure(figsize=(width, height))
    ax = fig.subplots()
    image = ax.imshow(np.ma.masked_invalid(values), cmap=cmap, norm=norm, aspect="auto")
    for i, sc in enumerate(rows):
        for j, name in enumerate(order):
            c = m.cell(sc.name, name)
            if c.status == "ok":
                r, g, b, _ = cmap(norm(values[i, j]))
                ink = "black" if 0.299 * r + 0.587 * g + 0.114 * b > 0.55 else "white"
                ax.text(j, i, matrix._sig(values[i, j]), ha="center", va="center", fontsize=6.5,
                        color=ink)
                if c.outside:
                    ax.plot(j + 0.36, i - 0.3, marker="o", ms=2.2, color=ink, lw=0)
            else:
                colour = "0.85" if c.status == "n/a" else "black"
                ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, facecolor=colour, hatch="////",
                                       edgecolor="0.55", lw=0))
                label = {"n/a": "N/A", "diverged": "div.", "error": "err."}[c.status]
                ax.text(j, i, label, ha="center", va="center",
                        fontsize=6.5, color="black" if c.status == "n/a" else "white")
    starts = [i for i, sc in enumerate(rows) if i == 0 or sc.plant.name != rows[i - 1].plant.name]
    for i in starts[1:]:
        ax.axhline(i - 0.5, color="black", lw=1.2)
    for i, end in zip(starts, [*starts[1:], len(rows)], strict=True):  # the plant of each group
        ax.text(len(order) - 0.4, (i + end - 1) / 2, rows[i].plant.name.replace("_", " "),
                rotation=270, ha="left", va="center", fontsize=7.5, clip_on=False)
    groups = [(label, sum(_group(n) == kind for n in order)) for kind, label in GROUPS]
    groups = [(label, size) for label, size in groups if size]
    for edge in np.cumsum([size for _, size in groups])[:-1]:
        ax.axvline(edge - 0.5, color="black", lw=1.2)
    ax.set_xticks(range(len(order)), order, rotation=30, ha="right")
    ax.set_yticks(range(len(rows)), [sc.name.replace("/", " / ") for sc in rows])
    ax.tick_params(length=0, labelsize=8)
    ax.grid(False)
    ax.set_xlabel(" | ".join(label for label, _ in groups), fontsize=9)
    bar = fig.colorbar(image, ax=ax, fraction=0.04, pad=0.05,
                       extend="max" if finite.max() > norm.vmax else "neither")
    bar.set_label("steady-window score, oracle = 1 (log scale)", fontsize=9)
    bar.ax.tick_params(labelsize=8)
    ax.legend(handles=[Patch(facecolor="0.85", hatch="////", edgecolor="0.55",
                             label="no score: n/a (cannot run), div. (diverged: growth, escape "
                                   "or not finite) or err. (raised)"),
                       Line2D([], [], marker="o", ms=2.2, color="black", lw=0,
                              label="outside the method's theory (scored)")],
              ncols=2,
              loc="upper left", frameon=False, fontsize=7,
              # as far below the axes at any number of rows as at 15 (the arena's, -0.16 of its axes)
              bbox_to_anchor=(0.0, -0.16 * (1.2 + 0.27 * 15) / height))
    ax.set_title(title, fontsize=9)
    return fig


def _md(text: object) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def plant_tables(m: matrix.Matrix) -> dict[str, str]:
    """One markdown table per plant of ``m``: every (scenario, method) cell in words.

    Parameters
    ----------
    m : Matrix
        The scored matrix.

    Returns
    -------
    dict
        Plant name -> markdown: a bold heading with the plant's title, then one row per cell
        (:func:`secest.arena.matrix.table_rows`): the steady-window network and worst-node
        scores, the transient score, the detection and false-alarm rates with their 95 %
        intervals, and the failed conditions of the method's theory; or the cell's status in bold.
    """
    plant_of = {sc.name: sc.plant for sc in matrix.check_matrix("m", m).scenarios}
    out: dict[str, list[str]] = {}
    for row in matrix.table_rows(m):
        plant = plant_of[row["scenario"]]
        lines = out.setdefault(plant.name, [
            f"**Plant `{plant.name}`** — {_md(plant.title)}", "",
            "| scenario | method | steady score [95 % CI] | worst node | transient | "
            "detection | false alarm | outside its theory |", "|---|---|---|---|---|---|---|---|"])
        if row["status"] == "ok":
            cells = [row["steady"], row["worst"], row["transient"], row["detection"],
                     row["false_alarm"], _md(row["outside"])]
        else:
            cells = [f"**{_md(row['steady'])}**", "", "", "", "", _md(row["outside"])]
        lines.append(f"| `{row['scenario']}` | `{row['method']}` | " + " | ".join(cells) + " |")
    return {plant: "\n".join(lines) for plant, lines in out.items()}


def card_schema() -> str:
    """:data:`secest.arena.scenarios.CARD_KEYS` as markdown: one table of keys per card kind.

    Returns
    -------
    str
        For each kind a heading (``[<kind>.<name>]`` for the named cards, ``[matrix]``) and a
        table ``| key | meaning |`` in the schema's order.
    """
    parts = []
    for kind, keys in scenarios.CARD_KEYS.items():
        heading = "[matrix]" if kind == "matrix" else f"[{kind}.<name>]"
        parts += [f"**`{heading}`**", "", "| key | meaning |", "|---|---|"]
        parts += [f"| `{key}` | {_md(text)} |" for key, text in keys.items()]
        parts.append("")
    return "\n".join(parts)


# ---------------------------------------------------------------------------------- the race


def _names(label: str, value: Sequence[str] | None) -> list[str] | None:
    if value is None:
        return None
    if isinstance(value, str) or not isinstance(value, Sequence) or not value or not all(
            isinstance(v, str) and v for v in value):
        raise ValidationError(f"{label} must be a non-empty list of card names, found {value!r}")
    if len(set(value)) != len(value):
        raise ValidationError(f"{label}: a card is listed twice in {list(value)}")
    return list(value)


def _method_names(methods: Sequence[str | Method | type[Method]] | None) -> list[str] | None:
    """Names of ``methods``; a Method (class or instance) not yet registered is registered."""
    if methods is None:
        return None
    if isinstance(methods, str | Method | type) or not isinstance(methods, Sequence) or not methods:
        raise ValidationError("methods must be a non-empty list of registered names or Method "
                              f"subclasses, found {methods!r}")
    names = []
    for m in methods:
        if isinstance(m, type) and issubclass(m, Method) or isinstance(m, Method):
            cls = m if isinstance(m, type) else type(m)
            if type(METHODS.get(cls.name)) is not cls:
                register(m)
            names.append(cls.name)
        elif isinstance(m, str):
            names.append(m)
        else:
            raise ValidationError(f"methods: each entry must be a method name or a Method subclass, "
                                  f"found {m!r}")
    return estimators.check_names("methods", names)


def race(
    cards: scenarios.Extra = None,
    methods: Sequence[str | Method | type[Method]] | None = None,
    *,
    plants: Sequence[str] | None = None,
    attacks: Sequence[str] | None = None,
    runs: int | None = None,
    horizon: int | str | None = None,
    seed: int | None = None,
    out: str | Path | None = None,
    short: bool = False,
    scheduler: str | None = None,
    workers: int | None = None,
) -> matrix.Matrix:
    """Race ``methods`` on the scenarios of ``cards``; with ``out``, write the matrix there.

    Parameters
    ----------
    cards : path or mapping, optional
        More cards laid out like ``secest/arena/cards.toml`` (``extra=`` of
        :func:`secest.arena.scenarios.matrix`); their ``[matrix]`` lists extend the cross.
    methods : list, optional
        Registered method names, or :class:`~secest.arena.estimators.Method` subclasses (or
        instances), registered here if they are not yet; default every registered method.
        The oracle is always scored (the reference of every ratio).
    plants : list of str, optional
        The network cards (each with its plant) to cross; default the ``[matrix]`` networks.
    attacks : list of str, optional
        The attack cards to cross; default the ``[matrix]`` attacks.
    runs, horizon, seed : int, optional
        Monte Carlo runs (>= 2), steps (>= 1, or ``"auto"``: 20 time constants of each plant)
        and root seed of every scenario; default the ``[matrix]`` values (40, "auto", 2026 in
        the package's cards).
    out : path, optional
        Folder to write ``matrix.csv``, ``matrix.json``, ``heatmap.png`` and
        ``tables/<plant>.md`` into (created if missing): :func:`write`.
    short : bool
        Allow horizons shorter than 20 time constants (a smoke test: the windows are then
        halves of the horizon and say nothing of a steady state); otherwise such a horizon is
        refused (:func:`secest.arena.estimators.settle_steps`).
    scheduler, workers : optional
        Run the scenarios on Dask: an existing cluster's address, or the size of a
        ``LocalCluster`` (:func:`secest.arena.matrix.run_matrix`).

    Returns
    -------
    Matrix
        The scored matrix (:func:`secest.arena.matrix.run_matrix`).
    """
    if cards is not None and not isinstance(cards, str | Path | Mapping):
        raise ValidationError(f"cards must be a TOML file's path or a mapping of card tables, found "
                              f"{type(cards).__name__}")
    names = _method_names(methods)
    short = check_bool("short", short)
    matrix.check_dask_arguments(scheduler, workers)
    plants, attacks = _names("plants", plants), _names("attacks", attacks)
    if out is not None and (not isinstance(out, str | Path) or Path(out).is_file()):
        raise ValidationError(f"out must be a folder path (not a file), found {out!r}")
    known = scenarios.cards(cards)
    for label, kind, chosen in (("plants", "network", plants), ("attacks", "attack", attacks)):
        unknown = [n for n in chosen or [] if n not in known[kind]]
        if unknown:
            raise ValidationError(f"{label}: {unknown} have no {kind} card; known: "
                                  f"{sorted(known[kind])}")
    grid = scenarios.matrix(networks=plants, attacks=attacks, extra=cards, runs=runs,
                            horizon=horizon, seed=seed)
    m = matrix.run_matrix(grid, names, short=short, scheduler=scheduler, workers=workers)
    if out is not None:
        write(m, out)
    return m


def can_plot() -> bool:
    """Whether matplotlib is installed (the ``notebooks`` extra): :func:`write` draws the heatmap."""
    return importlib.util.find_spec("matplotlib") is not None


def _json_number(value: Any) -> Any:
    return None if isinstance(value, float) and not math.isfinite(value) else value


def write(m: matrix.Matrix, out: str | Path) -> list[Path]:
    """Write ``m`` into the folder ``out``: the matrix (CSV, JSON), the heatmap, the tables.

    Parameters
    ----------
    m : Matrix
        The scored matrix.
    out : path
        The folder (created if missing); files of the same names are replaced.

    Returns
    -------
    list of Path
        The files written: ``matrix.csv`` (:func:`columns`), ``matrix.json`` (the scenarios,
        the methods and one record per cell: :func:`columns` with NaN as ``null``, and the
        words of :func:`secest.arena.matrix.table_rows` under ``"text"``), ``heatmap.png``
        (:func:`heatmap`; only where matplotlib is installed, :func:`can_plot`, and some cell
        is scored) and ``tables/<plant>.md`` (:func:`plant_tables`).
    """
    matrix.check_matrix("m", m)
    if not isinstance(out, str | Path):
        raise ValidationError(f"out must be a folder path, found {type(out).__name__}")
    folder = Path(out)
    if folder.is_file():
        raise ValidationError(f"out must be a folder path (not a file), found {str(out)!r}")
    (folder / "tables").mkdir(parents=True, exist_ok=True)
    data = columns(m)
    cells = [dict(zip(COLUMNS, row, strict=True)) for row in zip(*data.values(), strict=True)]
    with (folder / "matrix.csv").open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(COLUMNS)
        writer.writerows([cell[k] for k in COLUMNS] for cell in cells)
    record = {
        **{key: sorted({getattr(sc, key) for sc in m.scenarios}) for key in ("runs", "horizon", "seed")},
        "scenarios": [{"name": sc.name, "plant": sc.plant.name, "network": sc.network.name,
                       "attack": sc.attack.name, "horizon": sc.horizon, "runs": sc.runs,
                       "seed": sc.seed} for sc in m.scenarios],
        "methods": [{"name": n, "kind": METHODS[n].kind, "title": METHODS[n].title}
                    for n in m.methods],
        "cells": [{k: _json_number(v) for k, v in cell.items()} | {"text": text}
                  for cell, text in zip(cells, matrix.table_rows(m), strict=True)],
    }
    (folder / "matrix.json").write_text(json.dumps(record, indent=1, allow_nan=False) + "\n")
    written = [folder / "matrix.csv", folder / "matrix.json"]
    png = folder / "heatmap.png"
    png.unlink(missing_ok=True)  # never a stale heatmap next to a new matrix
    if can_plot() and any(c.status == "ok" for c in m.cells.values()):
        fig = heatmap(m, title=f"Arena: steady-window score, oracle = 1 "
                               f"({', '.join(map(str, record['runs']))} runs, "
                               f"{', '.join(map(str, record['horizon']))} steps, seed "
                               f"{', '.join(map(str, record['seed']))})")
        fig.savefig(png, dpi=200, bbox_inches="tight", metadata={"Software": None})
        written.append(png)
    for plant, text in plant_tables(m).items():
        (folder / "tables" / f"{plant}.md").write_text(text + "\n")
        written.append(folder / "tables" / f"{plant}.md")
    return written
