"""Reproduced or drifted? Compare a run's numbers with the committed ones, within declared tolerances.

Command line::

    python -m secest.repro.verify [KEY ...]                            # what `make verify` runs
    python -m secest.repro.verify --against DIR [--reference DIR] [KEY ...]

The first form executes each notebook in paper mode into ``build/verify/<key>/``
(never over the committed files) and compares it with the committed
``figures/<key>/``. The second compares two result folders laid out like
``figures/`` (two machines, two package versions), e.g. a colleague's run with
yours; without ``KEY`` it compares every notebook folder of ``DIR``.

What is compared, number by number:

* ``claims.json``: every number of each claim's ``measured`` (through nested lists
  and mappings) and of its ``interval`` with the claim's ``tolerance``; ``holds`` and
  ``verdict`` exactly; non-numeric leaves exactly.
* every CSV column with the tolerance recorded in ``tolerances.json`` (written by
  :func:`secest.repro.plotting.save_data`); non-numeric cells exactly.
* the sweep's outputs (``robustness.csv``, ``robustness_<id>.png``) only when both
  sides hold them: a paper-mode run does not write them (``make robustness`` does).
* PNGs are never compared byte-wise: their data is in the CSVs. Their RMS pixel
  difference (:func:`matplotlib.testing.compare.calculate_rms`) is reported for
  information only.

A number ``b`` reproduces ``a`` when ``|b - a| <= atol + rtol*|a| + r``, with ``r``
the larger of the decimal steps the two were written with
(:meth:`secest.repro.results.Tolerance.resolution`: a tenth of the column's tolerance in
CSVs, of :data:`~secest.repro.results.DETERMINISTIC` in claims): differences below the
written precision cannot be seen. Where the two folders
declare different tolerances, the reference's is used and the change is noted.

The report (numbers compared, largest relative difference and where, each
tolerance and the quantities it covers, everything beyond tolerance by name) is
printed per notebook and written to ``build/verify.json``. Exit status: 0 when
everything is reproduced, 1 when a number leaves its tolerance, a claim's
``holds`` or ``verdict`` changes or a file is missing on one side, 2 on bad input.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import re
import shutil
import sys
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from secest.core.validation import ValidationError
from secest.repro.results import DETERMINISTIC, Tolerance, notebook_path, repo_root

__all__ = [
    "NotebookReport",
    "Quantity",
    "compare_folders",
    "main",
    "run_paper_mode",
    "verify",
]

CLAIMS_FILE = "claims.json"
TOLERANCES_FILE = "tolerances.json"  # = plotting.TOLERANCES_FILE (no matplotlib import here)


@dataclass
class Quantity:
    """The comparison of one quantity: a claim's measured values or one CSV column.

    Attributes
    ----------
    name : str
        ``"C3.measured"``, ``"C3.interval"`` or ``"<csv stem>.csv:<column>"``.
    tolerance : Tolerance
        The tolerance it was compared with.
    written : Tolerance
        The tolerance its numbers were rounded with when written (claims:
        :data:`~secest.repro.results.DETERMINISTIC`; CSV columns: their own).
    compared, beyond : int
        Numbers (and non-numeric cells) compared, and how many left the tolerance.
    max_rel, max_rel_at : float, str
        Largest relative difference ``|b - a| / max(|a|, |b|)`` and where (``""``: none).
    share, worst_at, worst : float, str, tuple of str
        Largest ``|b - a| / allowed`` (above 1: beyond tolerance), where, and the two values there.
    """

    name: str
    tolerance: Tolerance
    written: Tolerance
    compared: int = 0
    beyond: int = 0
    max_rel: float = 0.0
    max_rel_at: str = ""
    share: float = 0.0
    worst_at: str = ""
    worst: tuple[str, str] = ("", "")

    def update(self, ref: Sequence[Any], cand: Sequence[Any], where: Callable[[int], str]) -> None:
        """Compare ``ref[i]`` with ``cand[i]`` (numbers or text); ``where(i)`` names the place."""
        a, a_num = _as_numbers(ref)
        b, b_num = _as_numbers(cand)
        numeric = a_num & b_num
        rel, share = _differences(a, b, self.tolerance, self.written)
        text_equal = np.array([str(x) == str(y) for x, y in zip(ref, cand, strict=True)], dtype=bool)
        share = np.where(numeric, share, np.where(text_equal, 0.0, np.inf))
        rel = np.where(numeric, rel, np.where(text_equal, 0.0, np.inf))
        self.compared += len(ref)
        self.beyond += int(np.sum(share > 1.0))
        i, j = (int(np.argmax(rel)), int(np.argmax(share))) if len(ref) else (0, 0)
        if len(ref) and rel[i] > self.max_rel:
            self.max_rel, self.max_rel_at = float(rel[i]), where(i)
        if len(ref) and share[j] > self.share:
            self.share, self.worst_at = float(share[j]), where(j)
            self.worst = (str(ref[j]), str(cand[j]))

    def as_dict(self) -> dict[str, Any]:
        """JSON form for ``build/verify.json``."""
        return {
            "name": self.name,
            "tolerance": self.tolerance.as_dict(),
            "compared": self.compared,
            "beyond": self.beyond,
            "largest_relative_difference": {"value": _finite(self.max_rel), "at": self.max_rel_at},
            "closest_to_tolerance": {
                "share": _finite(self.share),
                "at": self.worst_at,
                "reference": self.worst[0],
                "candidate": self.worst[1],
            },
        }


@dataclass
class NotebookReport:
    """Everything compared for one notebook, and what did not reproduce.

    Attributes
    ----------
    key : str
        Notebook (paper) key.
    reference, candidate : Path
        The two result folders compared (laid out like ``figures/<key>/``).
    quantities : list of Quantity
        One comparison per claim value and CSV column.
    problems : list of str
        Structural changes: a file or claim present on one side only, different
        columns or rows, a claim's ``holds`` or ``verdict`` changed, a failed
        paper-mode execution. Any problem means not reproduced.
    notes : list of str
        Informative remarks, e.g. a tolerance declared differently on the two sides.
    images : dict of str to float or str
        PNG stem -> RMS pixel difference, or why it could not be computed (sizes
        differ); information only.
    seconds : float or None
        Wall time of the paper-mode run; None when the folders were compared only.
    """

    key: str
    reference: Path
    candidate: Path
    quantities: list[Quantity] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    images: dict[str, float | str] = field(default_factory=dict)
    seconds: float | None = None

    @property
    def compared(self) -> int:
        """Numbers compared in total."""
        return sum(q.compared for q in self.quantities)

    @property
    def beyond(self) -> list[Quantity]:
        """Quantities with at least one number beyond tolerance."""
        return [q for q in self.quantities if q.beyond]

    @property
    def passed(self) -> bool:
        """Reproduced: nothing beyond tolerance and no structural change."""
        return not self.problems and not self.beyond

    def as_dict(self) -> dict[str, Any]:
        """JSON form for ``build/verify.json``."""
        widest = max(self.quantities, key=lambda q: q.max_rel, default=None)
        closest = max(self.quantities, key=lambda q: q.share, default=None)
        widest_dict = widest.as_dict()["largest_relative_difference"] if widest else None
        return {
            "passed": self.passed,
            "reference": str(self.reference),
            "candidate": str(self.candidate),
            "seconds": self.seconds,
            "compared": self.compared,
            "beyond_tolerance": [q.name for q in self.beyond],
            "problems": self.problems,
            "notes": self.notes,
            "largest_relative_difference": widest_dict,
            "closest_to_tolerance": closest.as_dict()["closest_to_tolerance"] if closest else None,
            "quantities": [q.as_dict() for q in self.quantities],
            "images_rms": self.images,
        }


# ------------------------------------------------------------------ numbers


def _finite(value: float) -> float | str:
    """JSON has no infinity: write it as the string ``"inf"``."""
    return value if math.isfinite(value) else "inf"


def _as_numbers(values: Sequence[Any]) -> tuple[np.ndarray, np.ndarray]:
    """Floats of ``values`` (NaN where not a number) and the mask of those that are numbers."""
    out = np.full(len(values), np.nan)
    numeric = np.zeros(len(values), dtype=bool)
    for i, v in enumerate(values):
        if isinstance(v, bool) or v is None:
            continue
        try:
            out[i] = float(v)
        except (TypeError, ValueError):
            continue
        numeric[i] = True
    return out, numeric


def _resolution(values: np.ndarray, tol: Tolerance) -> np.ndarray:
    """Vectorised :meth:`Tolerance.resolution` (the decimal step values are written with)."""
    width = tol.atol + tol.rtol * np.abs(np.nan_to_num(values, nan=0.0, posinf=0.0, neginf=0.0))
    with np.errstate(divide="ignore"):
        step = 10.0 ** (np.floor(np.log10(width)) - 1.0)
    return np.where(width > 0.0, step, 0.0)


def _differences(
    a: np.ndarray, b: np.ndarray, tol: Tolerance, written: Tolerance
) -> tuple[np.ndarray, np.ndarray]:
    """Relative difference of ``b`` from ``a`` and its share of the allowed difference.

    NaN equals NaN and infinity itself; NaN against a number is infinitely far. The relative
    difference of values within ``atol`` of zero is set to 0: there it means nothing
    (``1e-17`` vs ``3e-17``), and the share of the allowed difference covers them.
    """
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    with np.errstate(invalid="ignore"):
        diff = np.where(same, 0.0, np.abs(b - a))
    diff = np.where(np.isnan(diff), np.inf, diff)
    resolution = np.maximum(_resolution(a, written), _resolution(b, written))
    allowed = tol.atol + tol.rtol * np.abs(a) + resolution
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.maximum(np.abs(a), np.abs(b))
        rel = np.where((diff == 0.0) | (scale <= tol.atol), 0.0, diff / scale)
        share = np.where(diff == 0.0, 0.0, diff / allowed)
    return np.where(np.isnan(rel), np.inf, rel), np.where(np.isnan(share), np.inf, share)


# ------------------------------------------------------------------ claims


def _read_json(path: Path, what: str) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise ValidationError(f"{what} {path} is not valid JSON: {exc}") from exc
    if not isinstance(data, dict) or not all(isinstance(v, dict) for v in data.values()):
        raise ValidationError(f"{what} {path} must map names to JSON objects")
    return data


def _claim_tolerance(
    cid: str, ref: Mapping[str, Any], cand: Mapping[str, Any], notes: list[str]
) -> Tolerance:
    """The reference claim's tolerance (else the candidate's, else DETERMINISTIC)."""
    declared = [e["tolerance"] for e in (ref, cand) if isinstance(e.get("tolerance"), dict)]
    if not declared:
        notes.append(f"{cid}: no tolerance recorded; DETERMINISTIC used")
        return DETERMINISTIC
    if len(declared) == 2 and declared[0] != declared[1]:
        notes.append(f"{cid}: tolerance changed from {declared[0]} to {declared[1]}; "
                     "the reference's used")
    try:
        return Tolerance(**declared[0])
    except TypeError as exc:
        raise ValidationError(f"claim {cid}: malformed tolerance {declared[0]!r}") from exc


def _leaves(value: Any, path: str) -> Iterator[tuple[str, Any]]:
    """``(path, leaf)`` of every leaf of nested lists / mappings."""
    if isinstance(value, Mapping):
        for k in sorted(value):
            yield from _leaves(value[k], f"{path}.{k}")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _leaves(v, f"{path}[{i}]")
    else:
        yield path, value


def _compare_values(name: str, tol: Tolerance, ref: Any, cand: Any, report: NotebookReport) -> None:
    """Compare the leaves of ``ref`` and ``cand`` as one quantity ``name``."""
    ref_leaves, cand_leaves = dict(_leaves(ref, name)), dict(_leaves(cand, name))
    if ref_leaves.keys() != cand_leaves.keys():
        only = sorted(ref_leaves.keys() ^ cand_leaves.keys())
        report.problems.append(f"{name}: structure differs (entries on one side only: {only})")
        return
    quantity = Quantity(name, tol, written=DETERMINISTIC)  # claims are written at this precision
    where = list(ref_leaves)
    quantity.update([ref_leaves[w] for w in where], [cand_leaves[w] for w in where], where.__getitem__)
    report.quantities.append(quantity)


def _compare_claims(ref_path: Path, cand_path: Path, report: NotebookReport) -> None:
    """Claims present on both sides: measured and interval numbers, holds and verdict exactly."""
    missing = [str(p) for p in (ref_path, cand_path) if not p.exists()]
    if missing:
        report.problems.append(f"{CLAIMS_FILE} missing: {', '.join(missing)}")
        return
    ref, cand = _read_json(ref_path, "claims file"), _read_json(cand_path, "claims file")
    for cid in sorted(ref.keys() ^ cand.keys()):
        side = "reference" if cid in ref else "candidate"
        report.problems.append(f"claim {cid} only in the {side}")
    for cid in sorted(ref.keys() & cand.keys(), key=_natural):
        r, c = ref[cid], cand[cid]
        for key in ("holds", "verdict"):
            if r.get(key) != c.get(key):
                report.problems.append(f"{cid}: {key} changed from {r.get(key)!r} to {c.get(key)!r}")
        tol = _claim_tolerance(cid, r, c, report.notes)
        _compare_values(f"{cid}.measured", tol, r.get("measured"), c.get("measured"), report)
        if "interval" in r or "interval" in c:
            bounds = [{k: e.get("interval", {}).get(k) for k in ("low", "high")} for e in (r, c)]
            _compare_values(f"{cid}.interval", tol, *bounds, report)


def _natural(cid: str) -> tuple[str, int, str]:
    """Sort C2 before C10."""
    digits = "".join(ch for ch in cid[1:] if ch.isdigit())
    return cid[0], int(digits or 0), cid


# ------------------------------------------------------------------ figure data


def _read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows:
        raise ValidationError(f"figure data {path} is empty (no header row)")
    return rows[0], rows[1:]


def _read_tolerances(folder: Path) -> dict[str, dict[str, Tolerance]]:
    """``tolerances.json`` of a figure folder as csv stem -> column -> Tolerance ({} if absent)."""
    path = folder / TOLERANCES_FILE
    if not path.exists():
        return {}
    try:
        table = json.loads(path.read_text())
        return {
            stem: {c: Tolerance(g["rtol"], g["atol"], g["reason"]) for g in groups for c in g["columns"]}
            for stem, groups in table.items()
        }
    except (json.JSONDecodeError, AttributeError, KeyError, TypeError) as exc:
        raise ValidationError(f"tolerances file {path} is malformed: {exc!r}") from exc


def _column_tolerance(
    stem: str, column: str, sides: Sequence[Mapping[str, Any]], notes: list[str]
) -> Tolerance:
    """The reference's recorded tolerance of a column (else the candidate's, else DETERMINISTIC)."""
    declared = [t[stem][column] for t in sides if column in t.get(stem, {})]
    if not declared:
        if any(stem in t for t in sides):
            notes.append(f"{stem}.csv:{column}: no tolerance recorded; DETERMINISTIC used")
        return DETERMINISTIC
    if len(declared) == 2 and declared[0] != declared[1]:
        notes.append(f"{stem}.csv:{column}: tolerance changed from {declared[0]} to {declared[1]}; "
                     "the reference's used")
    return declared[0]


def _compare_table(stem: str, report: NotebookReport, tolerances: Sequence[Mapping[str, Any]]) -> None:
    """Compare the columns of ``<stem>.csv`` present in both folders."""
    ref_head, ref_rows = _read_csv(report.reference / f"{stem}.csv")
    cand_head, cand_rows = _read_csv(report.candidate / f"{stem}.csv")
    if ref_head != cand_head:
        report.problems.append(
            f"{stem}.csv: columns differ (only in reference: {sorted(set(ref_head) - set(cand_head))}, "
            f"only in candidate: {sorted(set(cand_head) - set(ref_head))}, or in another order)"
        )
    if len(ref_rows) != len(cand_rows):
        report.problems.append(
            f"{stem}.csv: {len(ref_rows)} rows in reference, {len(cand_rows)} in candidate"
        )
        return
    if not any(stem in t for t in tolerances):
        report.notes.append(f"{stem}.csv: no tolerances recorded; DETERMINISTIC used")
    for j, column in enumerate(ref_head):
        if column not in cand_head:
            continue
        k = cand_head.index(column)
        tol = _column_tolerance(stem, column, tolerances, report.notes)
        quantity = Quantity(f"{stem}.csv:{column}", tol, written=tol)

        def where(i: int, name: str = quantity.name, j: int = j) -> str:
            first = "" if j == 0 else f" ({ref_head[0]} = {ref_rows[i][0]})"
            return f"{name} row {i}{first}"

        quantity.update([row[j] for row in ref_rows], [row[k] for row in cand_rows], where)
        report.quantities.append(quantity)


def _image_rms(ref: Path, cand: Path) -> float | str:
    """RMS pixel difference of two PNGs (matplotlib's image-comparison measure), or why not."""
    from matplotlib.testing.compare import calculate_rms
    from PIL import Image

    a = np.asarray(Image.open(ref).convert("RGB")).astype(np.int16)
    b = np.asarray(Image.open(cand).convert("RGB")).astype(np.int16)
    if a.shape != b.shape:
        return f"size differs: {a.shape[1]}x{a.shape[0]} vs {b.shape[1]}x{b.shape[0]}"
    return round(float(calculate_rms(a, b)), 4)


SWEEP_PREFIX = "robustness"
"""Stem prefix of the sweep's outputs (``robustness.csv``, ``robustness_<id>.png``): a
paper-mode run does not write them, so a side without them is noted, not a failure."""


def compare_folders(key: str, reference: Path, candidate: Path) -> NotebookReport:
    """Compare the result folder ``candidate`` with ``reference`` (both like ``figures/<key>/``).

    Parameters
    ----------
    key : str
        Notebook key, for the report.
    reference, candidate : Path
        Folders holding ``claims.json``, ``*.csv``, ``*.png`` and ``tolerances.json``.

    Returns
    -------
    NotebookReport
    """
    for name, folder in (("reference", reference), ("candidate", candidate)):
        if not folder.is_dir():
            raise ValidationError(f"{name} folder {folder} of notebook {key!r} does not exist")
    report = NotebookReport(key, reference, candidate)
    _compare_claims(reference / CLAIMS_FILE, candidate / CLAIMS_FILE, report)
    tolerances = [_read_tolerances(reference), _read_tolerances(candidate)]
    for suffix in (".csv", ".png"):
        ref_stems = {p.stem for p in reference.glob(f"*{suffix}")}
        cand_stems = {p.stem for p in candidate.glob(f"*{suffix}")}
        for stem in sorted(ref_stems ^ cand_stems):
            side = "reference" if stem in ref_stems else "candidate"
            if stem.startswith(SWEEP_PREFIX):
                report.notes.append(f"{stem}{suffix} only in the {side}: written by `make robustness`, "
                                    "not by a paper-mode run; not compared")
            else:
                report.problems.append(f"{stem}{suffix} only in the {side}")
        for stem in sorted(ref_stems & cand_stems):
            if suffix == ".csv":
                _compare_table(stem, report, tolerances)
            else:
                report.images[stem] = _image_rms(reference / f"{stem}.png", candidate / f"{stem}.png")
    return report


# ------------------------------------------------------------------ running and reporting


def run_paper_mode(key: str, out_root: Path) -> tuple[Path, float]:
    """Execute ``notebooks/<key>.ipynb`` in paper mode into a fresh ``out_root/<key>/``.

    The folder is emptied first; the executed notebook, its figures and its claims
    are written there (``fig_dir`` and ``results_path`` point into it), never over
    the committed files.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"guo2023"``.
    out_root : Path
        Parent folder of the run (``build/verify`` for ``make verify``).

    Returns
    -------
    folder : Path
        The result folder ``out_root/<key>``.
    seconds : float
        Wall time of the execution.

    Raises
    ------
    ValidationError
        If ``key`` names no notebook (checked before anything is deleted).
    papermill.PapermillExecutionError
        If a cell of the notebook raises.
    """
    from secest.repro.run import execute_notebook

    notebook_path(key)  # unknown key -> ValidationError before anything is deleted
    folder = out_root / key
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    params = {"mode": "paper", "fig_dir": str(folder), "results_path": str(folder / CLAIMS_FILE)}
    start = time.perf_counter()
    execute_notebook(key, params, folder / f"{key}.ipynb")
    return folder, time.perf_counter() - start


def _tolerance_lines(report: NotebookReport) -> list[str]:
    """Two lines per distinct tolerance: its values and reason, then every quantity it covers."""
    groups: dict[Tolerance, list[str]] = {}
    for q in report.quantities:
        groups.setdefault(q.tolerance, []).append(q.name)
    columns_per_file: dict[str, int] = {}
    for q in report.quantities:
        if ":" in q.name:
            stem = q.name.split(":", 1)[0]
            columns_per_file[stem] = columns_per_file.get(stem, 0) + 1
    lines = []
    for tol, names in groups.items():
        lines.append(f"    rtol {tol.rtol:g}, atol {tol.atol:g} ({tol.reason}):")
        lines.append(f"      {_compact(names, columns_per_file)}")
    return lines


def _compact(names: list[str], columns_per_file: Mapping[str, int]) -> str:
    """``claims C1, C2.interval; fig1.csv (all 4 columns); fig2.csv: t, x[0]``."""
    claims = [n.removesuffix(".measured") for n in names if ":" not in n]
    files: dict[str, list[str]] = {}
    for n in names:
        if ":" in n:
            stem, column = n.split(":", 1)
            files.setdefault(stem, []).append(column)
    parts = [f"claims {', '.join(claims)}"] if claims else []
    for stem, cols in files.items():
        whole = len(cols) == columns_per_file[stem]
        parts.append(f"{stem} (all {len(cols)} columns)" if whole else f"{stem}: {_ranges(cols)}")
    return "; ".join(parts)


def _ranges(columns: list[str]) -> str:
    """``x[0], x[1], x[2], t`` as ``x[0..2], t`` (runs of a 2-D key's columns)."""
    runs: list[tuple[str, int, int] | str] = []
    for column in columns:
        match = re.fullmatch(r"(.*)\[(\d+)\]", column)
        last = runs[-1] if runs else None
        if match and isinstance(last, tuple) and last[0] == match[1] and last[2] + 1 == int(match[2]):
            runs[-1] = (last[0], last[1], last[2] + 1)
        elif match:
            runs.append((match[1], int(match[2]), int(match[2])))
        else:
            runs.append(column)
    texts = [r if isinstance(r, str) else f"{r[0]}[{r[1]}" + (f"..{r[2]}]" if r[2] > r[1] else "]")
             for r in runs]
    return ", ".join(texts)


def format_report(report: NotebookReport) -> str:
    """The printed report of one notebook."""
    status = "REPRODUCED" if report.passed else "NOT REPRODUCED"
    timing = f", paper mode in {report.seconds:.1f} s" if report.seconds is not None else ""
    n_claims = sum(q.compared for q in report.quantities if ":" not in q.name)
    lines = [
        f"== {report.key}: {status}{timing}",
        f"  {report.compared} values compared ({n_claims} in claims, {report.compared - n_claims} in "
        f"figure data), {sum(q.beyond for q in report.quantities)} beyond tolerance",
    ]
    widest = max(report.quantities, key=lambda q: q.max_rel, default=None)
    closest = max(report.quantities, key=lambda q: q.share, default=None)
    if widest is None or widest.max_rel == 0.0:
        lines.append("  every value identical")
    else:
        lines.append(f"  largest relative difference {widest.max_rel:.2g} at {widest.max_rel_at}")
        lines.append(f"  closest to its tolerance: {100 * closest.share:.3g} % of it at "
                     f"{closest.worst_at} ({closest.worst[0]} vs {closest.worst[1]})")
    numeric = [v for v in report.images.values() if isinstance(v, float)]
    if report.images:
        lines.append(f"  {len(report.images)} PNGs, largest RMS pixel difference "
                     f"{max(numeric, default=0.0):.3g} (information only: their data is compared)")
    lines.append("  tolerances:")
    lines += _tolerance_lines(report)
    for q in report.beyond:
        tol = q.tolerance
        lines.append(f"  BEYOND TOLERANCE {q.name}: {q.beyond} of {q.compared} values; worst "
                     f"{q.worst_at}: {q.worst[0]} vs {q.worst[1]}, {q.share:.3g} x the allowed "
                     f"difference (rtol {tol.rtol:g}, atol {tol.atol:g}: {tol.reason})")
    lines += [f"  CHANGED {p}" for p in report.problems]
    lines += [f"  note: {n}" for n in report.notes]
    return "\n".join(lines)


def write_report(reports: Sequence[NotebookReport], path: Path) -> Path:
    """Write ``reports`` as JSON (``build/verify.json``)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    doc = {"passed": all(r.passed for r in reports), "notebooks": {r.key: r.as_dict() for r in reports}}
    path.write_text(json.dumps(doc, indent=2, sort_keys=True) + "\n")
    return path


def _result_keys(folder: Path) -> list[str]:
    """Subfolders of ``folder`` holding a claims file or figure data."""
    return sorted(
        p.name for p in folder.iterdir()
        if p.is_dir() and ((p / CLAIMS_FILE).exists() or any(p.glob("*.csv")))
    )


def verify(
    keys: Sequence[str],
    *,
    against: Path | None = None,
    reference: Path | None = None,
    out_root: Path | None = None,
) -> list[NotebookReport]:
    """Run (or take from ``against``) each notebook's results and compare them with ``reference``.

    Parameters
    ----------
    keys : sequence of str
        Notebook keys; empty means every notebook (or every result folder of ``against``).
    against : Path, optional
        A folder laid out like ``figures/`` to compare instead of executing notebooks.
    reference : Path, optional
        The folder compared with (default: the committed ``figures/``).
    out_root : Path, optional
        Where fresh runs go (default ``build/verify``).
    """
    reference = reference or repo_root() / "figures"
    if not reference.is_dir():
        raise ValidationError(f"reference folder {reference} does not exist")
    if against is not None and not against.is_dir():
        raise ValidationError(f"against folder {against} does not exist")
    if against is not None:
        keys = list(keys) or _result_keys(against)
        if not keys:
            raise ValidationError(f"against folder {against} holds no result folders <key>/claims.json")
        return [compare_folders(k, reference / k, against / k) for k in keys]
    from papermill.exceptions import PapermillExecutionError

    keys = list(keys) or sorted(p.stem for p in (repo_root() / "notebooks").glob("*.py"))
    for k in keys:
        notebook_path(k)
    out_root = out_root or repo_root() / "build" / "verify"
    reports = []
    for k in keys:
        try:
            folder, seconds = run_paper_mode(k, out_root)
        except PapermillExecutionError as exc:
            report = NotebookReport(k, reference / k, out_root / k)
            report.problems.append(f"paper-mode execution failed: {exc.ename}: {exc.evalue}")
        else:
            report = compare_folders(k, reference / k, folder)
            report.seconds = seconds
        reports.append(report)
        print(format_report(report), flush=True)
    return reports


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point (see the module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name: ``[KEY ...] [--against DIR]
        [--reference DIR] [--report PATH]``. Default: ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 when every notebook reproduced within tolerance, 1 when one
        did not, 2 on bad input (a key naming no notebook, a missing folder).
        argparse exits with status 2 on malformed arguments.
    """
    parser = argparse.ArgumentParser(prog="python -m secest.repro.verify",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("keys", nargs="*", metavar="KEY", help="notebook keys (default: all)")
    parser.add_argument("--against", type=Path, help="compare this result folder instead of running")
    parser.add_argument("--reference", type=Path, help="folder compared with (default: figures/)")
    parser.add_argument("--report", type=Path, help="JSON report (default: build/verify.json)")
    args = parser.parse_args(argv)
    try:
        reports = verify(args.keys, against=args.against, reference=args.reference)
    except ValidationError as exc:
        print(f"secest.repro.verify: {exc}", file=sys.stderr)
        return 2
    if args.against is not None:
        for report in reports:
            print(format_report(report))
    path = write_report(reports, args.report or repo_root() / "build" / "verify.json")
    failed = [r.key for r in reports if not r.passed]
    print(f"{len(reports) - len(failed)} of {len(reports)} reproduced within tolerance"
          + (f"; not reproduced: {', '.join(failed)}" if failed else "") + f" (report: {path})")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
