"""Notebook build steps used by the Makefile.

``python -m secest.repro.build ipynb KEY``
   build ``notebooks/KEY.ipynb`` from ``KEY.py`` (one way)
``python -m secest.repro.build prepare KEY``
   delete KEY's old PNG/CSV figures before a run
``python -m secest.repro.build strip KEY``
   strip timing metadata and cell ids after a run
``python -m secest.repro.build manifest KEY..``
   check that every figure listed in ``figures/manifest.toml`` exists

The ``.ipynb`` is always rebuilt from the ``.py`` (never synced the other way:
``jupytext --sync`` trusts timestamps, which git scrambles). Cell ids are
removed (nbformat 4.4) and papermill / nbclient timing metadata is stripped so
that executing twice leaves ``git status`` clean.
"""

from __future__ import annotations

import sys
import tomllib
from pathlib import Path

import jupytext
import nbformat

from secest.core.validation import ValidationError
from secest.repro.results import repo_root

__all__ = [
    "build_ipynb",
    "check_manifest",
    "notebook_from_source",
    "prepare_figures",
    "strip_notebook",
]

_CELL_KEYS_DROPPED = ("papermill", "execution", "ExecuteTime", "collapsed", "scrolled")
_NB_KEYS_DROPPED = ("papermill", "widgets")


def _paths(key: str, root: Path | None = None) -> tuple[Path, Path]:
    root = (root or repo_root()) / "notebooks"
    src = root / f"{key}.py"
    if not src.exists():
        raise ValidationError(f"key {key!r} names no notebook source: {src} does not exist")
    return src, root / f"{key}.ipynb"


def _without_ids(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    nb.nbformat, nb.nbformat_minor = 4, 4
    for cell in nb.cells:
        cell.pop("id", None)
    return nb


def notebook_from_source(key: str, dst: Path, root: Path | None = None) -> Path:
    """Write the notebook of ``notebooks/<key>.py`` (outputs empty, no cell ids) to ``dst``.

    The jupytext header is dropped and the notebook written as nbformat 4.4, so the
    file does not depend on the jupytext version or on cell ids.

    Parameters
    ----------
    key : str
        Paper key naming the source ``notebooks/<key>.py``, e.g. ``"lee2020"``.
    dst : Path
        Where to write the ``.ipynb`` (overwritten if it exists; its folder must exist).
    root : Path, optional
        Folder holding ``notebooks/``; default: this repository.

    Returns
    -------
    Path
        ``dst``.

    Raises
    ------
    ValidationError
        If ``notebooks/<key>.py`` does not exist.
    """
    src, _ = _paths(key, root)
    nb = jupytext.read(src)
    nb.metadata.pop("jupytext", None)
    jupytext.write(_without_ids(nb), dst, fmt="ipynb")
    return dst


def build_ipynb(key: str) -> Path:
    """Write ``notebooks/<key>.ipynb`` from ``notebooks/<key>.py`` (outputs empty).

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.

    Returns
    -------
    Path
        The notebook written, ``notebooks/<key>.ipynb`` (see :func:`notebook_from_source`).

    Raises
    ------
    ValidationError
        If ``notebooks/<key>.py`` does not exist.
    """
    return notebook_from_source(key, _paths(key)[1])


def strip_notebook(key: str) -> Path:
    """Remove timing metadata and cell ids from the executed ``notebooks/<key>.ipynb``.

    Drops the notebook-level ``papermill`` / ``widgets`` metadata, the per-cell
    ``papermill``, ``execution``, ``ExecuteTime``, ``collapsed`` and ``scrolled``
    metadata and every cell id, and merges consecutive stream outputs of the same
    name (their split depends on flush timing), so that executing twice leaves
    ``git status`` clean. The notebook is rewritten in place.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.

    Returns
    -------
    Path
        The rewritten notebook, ``notebooks/<key>.ipynb``.

    Raises
    ------
    ValidationError
        If ``notebooks/<key>.py`` does not exist.
    FileNotFoundError
        If ``notebooks/<key>.ipynb`` has not been built.
    """
    _, path = _paths(key)
    nb = nbformat.read(path, as_version=4)
    for k in _NB_KEYS_DROPPED:
        nb.metadata.pop(k, None)
    for cell in nb.cells:
        for k in _CELL_KEYS_DROPPED:
            cell.metadata.pop(k, None)
        if cell.cell_type == "code":
            cell.outputs = _coalesce_streams(cell.outputs)
    nbformat.write(_without_ids(nb), path)
    return path


def _coalesce_streams(outputs: list) -> list:
    """Merge consecutive stream outputs of the same name (their split depends on flush timing)."""
    merged: list = []
    for out in outputs:
        prev = merged[-1] if merged else None
        if (
            out.get("output_type") == "stream"
            and prev is not None
            and prev.get("output_type") == "stream"
            and prev.get("name") == out.get("name")
        ):
            prev["text"] = prev["text"] + out["text"]
        else:
            merged.append(out)
    return merged


def _manifest() -> dict:
    path = repo_root() / "figures" / "manifest.toml"
    with path.open("rb") as fh:
        return tomllib.load(fh)


def prepare_figures(key: str) -> list[Path]:
    """Delete the PNG and CSV files in ``figures/<key>/`` so stale figures cannot survive a run.

    The outputs of ``make robustness`` (``robustness*``) are kept: the notebook reads them.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``. A missing ``figures/<key>/`` is not an error.

    Returns
    -------
    list of Path
        The files deleted, sorted (empty when there was nothing to delete).
    """
    folder = repo_root() / "figures" / key
    found = [*folder.glob("*.png"), *folder.glob("*.csv")] if folder.exists() else []
    removed = sorted(p for p in found if not p.name.startswith("robustness"))
    for path in removed:
        path.unlink()
    return removed


def check_manifest(keys: list[str]) -> list[str]:
    """Return the files listed for ``keys`` in ``figures/manifest.toml`` that are missing.

    Parameters
    ----------
    keys : list of str
        Paper keys; each must have a ``[<key>]`` table in the manifest.

    Returns
    -------
    list of str
        The missing files, as listed (paths relative to the repository root), in the
        order of ``keys`` and of the manifest; empty when every listed file exists.

    Raises
    ------
    ValidationError
        If ``figures/manifest.toml`` has no table for one of ``keys``.
    """
    manifest = _manifest()
    missing = []
    for key in keys:
        if key not in manifest:
            raise ValidationError(f"figures/manifest.toml has no [{key}] table")
        for fig in manifest[key].get("figures", []):
            for name in fig["files"]:
                if not (repo_root() / name).exists():
                    missing.append(name)
    return missing


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point (see the module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name: a command (``ipynb``, ``prepare``,
        ``strip`` or ``manifest``) followed by one or more paper keys. Default:
        ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 on success, 1 when ``manifest`` finds a listed figure missing
        (each printed to stderr), 2 on a usage error (the module docstring is printed).
    """
    args = sys.argv[1:] if argv is None else argv
    if len(args) < 2 or args[0] not in {"ipynb", "prepare", "strip", "manifest"}:
        print(__doc__, file=sys.stderr)
        return 2
    command, keys = args[0], args[1:]
    if command == "manifest":
        missing = check_manifest(keys)
        for name in missing:
            print(f"missing figure listed in figures/manifest.toml: {name}", file=sys.stderr)
        return 1 if missing else 0
    action = {"ipynb": build_ipynb, "prepare": prepare_figures, "strip": strip_notebook}[command]
    for key in keys:
        action(key)
    return 0


if __name__ == "__main__":
    sys.exit(main())
