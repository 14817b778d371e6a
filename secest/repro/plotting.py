"""One house style for every figure, and deterministic saving of figure + data.

Every figure is written as ``<fig_dir>/<name>.png`` next to ``<name>.csv``
holding the plotted numbers, so readers and tests compare numbers, not pixels.
PNGs carry no software/version metadata and are byte-identical across runs.

Inside a notebook the saved PNG is also displayed inline, right under the code
that made it (the rendered notebooks and the site show exactly the committed file).

Each CSV column has a reproduction tolerance (a :class:`secest.repro.results.Tolerance`,
default :data:`~secest.repro.results.DETERMINISTIC`) declared where the data is saved.
Its numbers are written to a tenth of that tolerance (:meth:`Tolerance.round`), and
the tolerances of every CSV in a folder are recorded in ``<fig_dir>/tolerances.json``,
which ``python -m secest.repro.verify`` reads::

    {"<csv stem>": [{"columns": ["t", "x[0]"], "rtol": 1e-09, "atol": 1e-12, "reason": "..."}, ...]}

one group per distinct tolerance, in column order. Entries whose CSV no longer exists
are dropped whenever the file is written, so a stale entry cannot outlive its data.

:func:`setup` turns all of this off for robustness sweeps (``figures = False``):
a sweep point measures claims only, so it neither renders nor writes figures.
"""

from __future__ import annotations

import csv
import json
from collections.abc import Mapping
from fnmatch import fnmatchcase
from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from secest.core.validation import ValidationError
from secest.repro.results import DETERMINISTIC, Tolerance

__all__ = [
    "COLUMN_WIDTH",
    "PAGE_WIDTH",
    "TOLERANCES_FILE",
    "figures_enabled",
    "save_data",
    "save_figure",
    "setup",
    "use_style",
]

COLUMN_WIDTH = 3.5
"""Width of one IEEE column in inches."""
PAGE_WIDTH = 7.16
"""Width of a two-column IEEE figure in inches."""
TOLERANCES_FILE = "tolerances.json"
"""Sidecar in each figure folder: the reproduction tolerance of every CSV column."""

ColumnTolerance = Tolerance | Mapping[str, Tolerance] | None
"""One tolerance for every column, or column name / data key / glob -> tolerance."""

_STYLE = {
    "figure.figsize": (COLUMN_WIDTH * 1.6, COLUMN_WIDTH),
    "figure.dpi": 110,
    "savefig.dpi": 200,
    "savefig.bbox": "tight",
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 8,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "lines.linewidth": 1.2,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "legend.framealpha": 0.85,
    "svg.hashsalt": "secest",
    "image.cmap": "viridis",
}


_STATE = {"enabled": True}


def use_style() -> None:
    """Apply the house style (font sizes readable at IEEE column width, grid, fixed dpi)."""
    mpl.rcParams.update(_STYLE)


def setup(*, enabled: bool = True) -> None:
    """Apply the house style and switch figure making on or off.

    Parameters
    ----------
    enabled : bool, default True
        ``False`` (a robustness sweep point) makes :func:`save_figure` and
        :func:`save_data` close the figure and write nothing.
    """
    if not isinstance(enabled, bool):
        raise ValidationError(f"enabled must be a bool, found {enabled!r}")
    use_style()
    _STATE["enabled"] = enabled


def figures_enabled() -> bool:
    """Whether figures and their data are being written (see :func:`setup`)."""
    return _STATE["enabled"]


def _columns(data: Mapping[str, ArrayLike]) -> tuple[list[str], list[str], list[np.ndarray]]:
    """Column names, the data key of each column and the columns (2-D arrays split)."""
    names: list[str] = []
    keys: list[str] = []
    cols: list[np.ndarray] = []
    length = None
    for key, value in data.items():
        arr = np.asarray(value)
        if arr.ndim == 0 or arr.ndim > 2:
            raise ValidationError(
                f"data[{key!r}] must be 1-D or 2-D (rows = samples), found shape {arr.shape}"
            )
        if length is None:
            length = arr.shape[0]
        if arr.shape[0] != length:
            raise ValidationError(
                f"data[{key!r}] has {arr.shape[0]} rows, expected {length} like the first column; "
                "save tables of other lengths with save_data under another name"
            )
        if arr.ndim == 1:
            names.append(key)
            cols.append(arr)
        else:
            names.extend(f"{key}[{j}]" for j in range(arr.shape[1]))
            cols.extend(arr.T)
        keys.extend([key] * (1 if arr.ndim == 1 else arr.shape[1]))
    return names, keys, cols


def _column_tolerances(names: list[str], keys: list[str], tolerance: ColumnTolerance) -> list[Tolerance]:
    """The tolerance of each column (see :func:`save_data`).

    An exact column name or data key first, else the first matching glob in the mapping's
    order, else :data:`~secest.repro.results.DETERMINISTIC`.
    """
    if tolerance is None or isinstance(tolerance, Tolerance):
        return [tolerance or DETERMINISTIC] * len(names)
    if not isinstance(tolerance, Mapping):
        raise ValidationError(
            f"tolerance must be a results.Tolerance or a mapping of column -> Tolerance, "
            f"found {type(tolerance).__name__}"
        )
    for pattern, tol in tolerance.items():
        if not isinstance(tol, Tolerance):
            raise ValidationError(f"tolerance[{pattern!r}] must be a results.Tolerance, found {tol!r}")
    chosen, used = [], set()
    for name, key in zip(names, keys, strict=True):
        exact = [p for p in (name, key) if p in tolerance]
        globs = [p for p in tolerance if fnmatchcase(name, p) or fnmatchcase(key, p)]
        pattern = (exact or globs or [None])[0]
        used.add(pattern)
        chosen.append(DETERMINISTIC if pattern is None else tolerance[pattern])
    unused = [p for p in tolerance if p not in used]
    if unused:
        raise ValidationError(f"tolerance patterns {unused} match no column; columns: {names}")
    return chosen


def _fmt(value: object, tolerance: Tolerance) -> str:
    """A CSV cell: floats rounded with ``tolerance`` in their shortest form (``1`` not ``1.0``)."""
    if isinstance(value, float | np.floating):
        text = repr(tolerance.round(float(value)))
        return text[:-2] if text.endswith(".0") else text
    return str(value)


def _record_tolerances(folder: Path, name: str, names: list[str], tols: list[Tolerance]) -> None:
    """Set the entry of ``name`` in the folder's :data:`TOLERANCES_FILE`, dropping stale entries."""
    groups: list[dict] = []
    for column, tol in zip(names, tols, strict=True):
        group = next((g for g in groups if g["tolerance"] == tol), None)
        if group is None:
            groups.append({"tolerance": tol, "columns": [column]})
        else:
            group["columns"].append(column)
    path = folder / TOLERANCES_FILE
    try:
        table = json.loads(path.read_text()) if path.exists() else {}
    except json.JSONDecodeError:  # a damaged generated file: rebuilt from the CSVs written from now on
        table = {}
    table = {stem: entry for stem, entry in table.items() if (folder / f"{stem}.csv").exists()}
    table[name] = [{"columns": g["columns"], **g["tolerance"].as_dict()} for g in groups]
    path.write_text(json.dumps(table, indent=1, sort_keys=True) + "\n")


def save_data(
    fig_dir: str | Path,
    name: str,
    data: Mapping[str, ArrayLike],
    *,
    tolerance: ColumnTolerance = None,
) -> Path | None:
    """Write equal-length columns to ``<fig_dir>/<name>.csv`` (2-D arrays become ``key[j]``).

    Parameters
    ----------
    fig_dir : path
        Output folder.
    name : str
        File stem.
    data : mapping of str to array
        The columns; a 2-D array ``key`` gives the columns ``key[0]``, ``key[1]``, ...
    tolerance : Tolerance or mapping, optional
        How closely a re-run on another machine must reproduce the columns: one
        :class:`~secest.repro.results.Tolerance` for all, or a mapping from a column name
        (``"x[1]"``), a data key (``"x"``: all its columns) or a glob (``"err_*"``) to
        a tolerance; other columns get :data:`~secest.repro.results.DETERMINISTIC`. Every
        pattern must match a column. Recorded in ``<fig_dir>/tolerances.json``.

    Returns
    -------
    Path of the CSV, or ``None`` (nothing written) when figures are switched off by
    :func:`setup`.

    Notes
    -----
    Floats are written to a tenth of their column's tolerance (:meth:`Tolerance.round`,
    11 significant digits under the default), so the files are deterministic and a
    re-run on another machine changes only digits that approach the tolerance.
    """
    if not data:
        raise ValidationError("data must hold at least one column")
    names, keys, cols = _columns(data)
    tols = _column_tolerances(names, keys, tolerance)
    if not _STATE["enabled"]:
        return None
    path = Path(fig_dir) / f"{name}.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(names)
        for row in zip(*cols, strict=True):
            writer.writerow([_fmt(v, tol) for v, tol in zip(row, tols, strict=True)])
    _record_tolerances(path.parent, name, names, tols)
    return path


def save_figure(
    fig: Figure,
    fig_dir: str | Path,
    name: str,
    data: Mapping[str, ArrayLike] | None = None,
    *,
    tolerance: ColumnTolerance = None,
) -> Path | None:
    """Save ``fig`` as a deterministic PNG ``<fig_dir>/<name>.png`` (+ ``<name>.csv`` of ``data``).

    In a notebook the PNG is then displayed inline (at half its pixel size, i.e.
    100 dpi on screen, sharp on high-density displays) with output metadata
    ``{"secest": {"figure": name}}``, and the figure is closed so that no backend
    shows it a second time.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    fig_dir : path
        Output folder, e.g. ``figures/<key>`` resolved from the repository root.
    name : str
        File stem following ``fig<N>[<panel>]_<slug>`` or ``extra_<slug>``.
    data : mapping of str to array, optional
        The plotted numbers, written by :func:`save_data`.
    tolerance : Tolerance or mapping, optional
        Reproduction tolerance of the data's columns (see :func:`save_data`).

    Returns
    -------
    Path of the PNG, or ``None`` when figures are switched off by :func:`setup`.
    """
    import matplotlib.pyplot as plt

    if not name or "/" in name or name.endswith(".png"):
        raise ValidationError(f"name must be a bare file stem like 'fig1_states', found {name!r}")
    if data is not None:
        names, keys, _ = _columns(data)  # validate before anything is written
        _column_tolerances(names, keys, tolerance)
    elif tolerance is not None:
        raise ValidationError(f"tolerance given for figure {name!r} without data to apply it to")
    if not _STATE["enabled"]:
        plt.close(fig)
        return None
    path = Path(fig_dir) / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Software": None})
    if data is not None:
        save_data(fig_dir, name, data, tolerance=tolerance)
    plt.close(fig)
    _display_inline(path, name)
    return path


def _display_inline(path: Path, name: str) -> None:
    """Show the saved PNG in the running notebook kernel (no-op outside IPython kernels)."""
    try:
        from IPython import get_ipython
        from IPython.display import Image, display
    except ImportError:  # core install without IPython: nothing to display into
        return
    shell = get_ipython()
    if shell is None or not hasattr(shell, "kernel"):
        return
    display(Image(filename=str(path), retina=True), metadata={"secest": {"figure": name}})
