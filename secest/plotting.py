"""One house style for every figure, and deterministic saving of figure + data.

Every figure is written as ``<fig_dir>/<name>.png`` next to ``<name>.csv``
holding the plotted numbers, so readers and tests compare numbers, not pixels.
PNGs carry no software/version metadata and are byte-identical across runs.
Inside a notebook the saved PNG is also displayed inline, right under the code
that made it (the rendered notebooks and the site show exactly the committed file).

:func:`setup` turns all of this off for robustness sweeps (``figures = False``):
a sweep point measures claims only, so it neither renders nor writes figures.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping
from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike

from secest.validation import ValidationError

__all__ = [
    "COLUMN_WIDTH",
    "PAGE_WIDTH",
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


def _columns(data: Mapping[str, ArrayLike]) -> tuple[list[str], list[np.ndarray]]:
    names: list[str] = []
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
    return names, cols


def _fmt(value: object) -> str:
    if isinstance(value, float | np.floating):
        return format(float(value), ".10g")
    return str(value)


def save_data(fig_dir: str | Path, name: str, data: Mapping[str, ArrayLike]) -> Path | None:
    """Write equal-length columns to ``<fig_dir>/<name>.csv`` (2-D arrays become ``key[j]``).

    Floats are written with 10 significant digits, so files are deterministic.
    Returns ``None`` (and writes nothing) when figures are switched off by :func:`setup`.
    """
    if not data:
        raise ValidationError("data must hold at least one column")
    names, cols = _columns(data)
    if not _STATE["enabled"]:
        return None
    path = Path(fig_dir) / f"{name}.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh, lineterminator="\n")
        writer.writerow(names)
        for row in zip(*cols, strict=True):
            writer.writerow([_fmt(v) for v in row])
    return path


def save_figure(
    fig: Figure,
    fig_dir: str | Path,
    name: str,
    data: Mapping[str, ArrayLike] | None = None,
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

    Returns
    -------
    Path of the PNG, or ``None`` when figures are switched off by :func:`setup`.
    """
    import matplotlib.pyplot as plt

    if not name or "/" in name or name.endswith(".png"):
        raise ValidationError(f"name must be a bare file stem like 'fig1_states', found {name!r}")
    if data is not None:
        _columns(data)  # validate before anything is written
    if not _STATE["enabled"]:
        plt.close(fig)
        return None
    path = Path(fig_dir) / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Software": None})
    if data is not None:
        save_data(fig_dir, name, data)
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
