"""Claims JSON, run manifests and papermill parameter validation.

Every notebook ends by writing its claims to ``results_path`` (default
``figures/<key>/claims.json``): one entry per claim id (``C<n>`` the paper's,
``X<n>`` ours) built by :func:`claim`, with the keys

``paper``
   what the paper states, in its words;
``source``
   where: section, figure, equation of the paper, or ``"ours"``;
``check``
   what we measure, against what, by which rule;
``measured``
   the measured value(s); ``key`` names the headline entry of a dict;
``interval``
   optional confidence interval of a Monte Carlo value (with its level and method);
``threshold``
   the value the measurement is compared with;
``holds``
   whether the statement holds at this run's parameters, or ``null`` when it was not
   checked here (``not_checked`` then says why: e.g. a numerical limit of ours);
``premise``
   optional: the theorem's own assumption, or a stated precondition of the measurement,
   and whether it holds here;
``basis``
   ``measured`` (evidence), or ``by-construction``: the claim holds because of how we
   built the check (an identity of our implementation, a quantity fixed by the premise);
   it is kept and shown, never counted as evidence;
``decides``
   optional, true for the claims that decide the paper's ReScience verdict
   (:func:`rescience_verdict`);
``runs``
   optional: the Monte Carlo run count the claim was measured with (its rule must not
   change meaning with it: a rule on an interval, never on a count);
``verdict``
   the outcome at this point, one of :data:`POINT_OUTCOMES`, or, once the declared space
   has been swept (``make robustness``), over that space (:data:`VERDICTS`):
   ``undetermined`` when it holds at part of the points where its premise holds, with
   ``robustness`` giving the fraction, its interval and the region;
``tolerance``
   how closely a re-run on another machine must reproduce ``measured``.

The outcome vocabulary, the same in every notebook:

``holds`` / ``fails``
   the measured statement holds / fails, its premise holding;
``fails-premise``
   the paper's premise (or a stated precondition of the measurement) fails: the claim
   says nothing here, whatever was measured;
``not-checked``
   we could not decide it here (a limit of our numerics or of our check): never a
   failure of the paper.

Every execution also writes a run manifest ``build/runs/<key>.json`` (not
committed) with package versions, solver, git commit, parameters and wall time.
"""

from __future__ import annotations

import json
import math
import platform
import re
import subprocess
import time
from collections.abc import Mapping, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from secest.core.tolerances import (  # noqa: F401  (claims and figure data declare these)
    CANCELLATION,
    DETERMINISTIC,
    LMI_ITERATES,
    ROUNDING_RESIDUAL,
    SIGN_DRIVEN,
    Tolerance,
)
from secest.core.validation import ValidationError

__all__ = [
    "CANCELLATION",
    "DETERMINISTIC",
    "LMI_ITERATES",
    "ROUNDING_RESIDUAL",
    "SIGN_DRIVEN",
    "BASES",
    "POINT_OUTCOMES",
    "VERDICTS",
    "Run",
    "Tolerance",
    "claim",
    "headline_value",
    "interval",
    "point_verdict",
    "rescience_verdict",
    "declared_parameters",
    "environment_summary",
    "notebook_path",
    "repo_root",
    "resolve",
    "robustness_markdown",
    "validate_parameters",
    "write_claims",
]

CLAIM_KEYS = ("paper", "source", "check", "measured", "threshold", "holds", "verdict", "tolerance")
POINT_OUTCOMES = ("holds", "fails", "fails-premise", "not-checked")
"""A claim's outcome at one point of its space (:func:`point_verdict`)."""
VERDICTS = ("holds", "fails", "undetermined", "fails-premise", "not-checked")
"""``undetermined`` only comes from a sweep of the declared space (``secest.repro.sweep``)."""
BASES = ("measured", "by-construction")
"""What a claim's outcome rests on: a measurement (evidence), or how the check is built."""
RESCIENCE = ("[Re]", "[Re, partial]", "[¬Re]")
"""The ReScience verdicts, decided by :func:`rescience_verdict`."""
_PACKAGES = ("numpy", "scipy", "networkx", "cvxpy", "clarabel", "scs", "control", "matplotlib")


def repo_root() -> Path:
    """The repository root (the folder holding ``secest/``); paths resolve from here."""
    return Path(__file__).resolve().parents[2]


def environment_summary() -> str:
    """Interpreter and secest location, repository paths shown as ``<repo>/...``.

    The first code cell of every notebook prints this, so a wrong interpreter is
    visible while the committed output does not depend on where the repository lives.
    """
    import sys

    import secest

    def show(path: str) -> str:
        p = Path(path)
        try:
            return "<repo>/" + p.relative_to(repo_root()).as_posix()
        except ValueError:
            return str(p)

    return f"python: {show(sys.executable)}\nsecest: {show(secest.__file__)}"


def resolve(path: str | Path) -> Path:
    """``path`` if absolute, else ``repo_root() / path``.

    Parameters
    ----------
    path : str or Path
        A path, absolute or relative to the repository root (not to the working
        directory), e.g. a notebook's ``fig_dir`` parameter.

    Returns
    -------
    Path
        The absolute path (not normalised; the file need not exist).
    """
    p = Path(path)
    return p if p.is_absolute() else repo_root() / p


def notebook_path(key: str, root: Path | None = None) -> Path:
    """``notebooks/<key>.ipynb`` under the repository root (must exist).

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.
    root : Path, optional
        Folder holding ``notebooks/``; default: this repository.

    Returns
    -------
    Path
        The notebook's absolute path.

    Raises
    ------
    ValidationError
        If the notebook does not exist.
    """
    path = (root or repo_root()) / "notebooks" / f"{key}.ipynb"
    if not path.exists():
        raise ValidationError(f"key {key!r} names no notebook: {path} does not exist")
    return path


def declared_parameters(key: str) -> dict[str, Any]:
    """Names and defaults of the ``parameters`` cell of ``notebooks/<key>.ipynb``.

    Read with papermill (what it will inject against) and cross-checked with the names
    the cell assigns, parsed with :mod:`ast`.

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.

    Returns
    -------
    dict
        Parameter name -> default, as papermill reports it (the default's source text).

    Raises
    ------
    ValidationError
        If the notebook does not exist, has no single cell tagged ``parameters``,
        that cell holds anything but assignments, or papermill parses other names
        than the cell assigns (e.g. because of an ``=`` inside a comment).
    """
    import papermill

    path = notebook_path(key)
    info = papermill.inspect_notebook(str(path))
    assigned = _parameter_cell_names(path)
    if set(info) != assigned:
        raise ValidationError(
            f"papermill parses parameters {sorted(info)} from notebook {key!r} but its "
            f"parameters cell assigns {sorted(assigned)}: papermill cannot parse a line "
            "(e.g. an '=' inside a comment); rewrite that line"
        )
    return {name: spec["default"] for name, spec in info.items()}


def _parameter_cell_names(path: Path) -> set[str]:
    """Names assigned at top level of the cell tagged ``parameters`` (parsed with ast)."""
    import ast

    import nbformat

    nb = nbformat.read(path, as_version=4)
    cells = [c for c in nb.cells if "parameters" in c.metadata.get("tags", [])]
    if len(cells) != 1:
        raise ValidationError(f"{path.name} must have exactly one cell tagged 'parameters'")
    names: set[str] = set()
    for node in ast.parse(cells[0].source).body:
        if not isinstance(node, ast.Assign | ast.AnnAssign):
            raise ValidationError(f"the parameters cell of {path.name} must hold literals only")
        targets = node.targets if isinstance(node, ast.Assign) else [node.target]
        names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def validate_parameters(key: str, parameters: Mapping[str, Any]) -> dict[str, Any]:
    """Check names and values of ``parameters`` against ``notebooks/<key>.toml``.

    Papermill only warns about unknown names; this rejects them, and values of the
    wrong type or outside their declared domain (see :mod:`secest.repro.spaces`).

    Parameters
    ----------
    key : str
        Paper key, e.g. ``"lee2020"``.
    parameters : mapping
        Parameter name -> value to inject (a subset of the notebook's parameters).

    Returns
    -------
    dict
        The checked values, by name (see :func:`secest.repro.spaces.validate`).

    Raises
    ------
    ValidationError
        Naming the first offending parameter and what it expects.
    """
    from secest.repro import spaces

    return spaces.validate(key, parameters)


def _plain(value: Any) -> Any:
    """Convert numpy scalars / arrays to JSON-ready Python values; reject NaN and infinity."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.bool_ | bool):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating | float):
        v = float(value)
        if not math.isfinite(v):
            raise ValidationError(
                f"claim values must be finite (JSON has no NaN or Infinity), found {v}; "
                "record a missing or unbounded value as None with the reason in 'check'"
            )
        return v
    return value


def interval(low: float, high: float, *, level: float = 0.95, method: str) -> dict[str, Any]:
    """A confidence interval entry for :func:`claim`.

    Parameters
    ----------
    low, high : float
        The interval's bounds; finite, with ``low <= high``.
    level : float, optional
        Confidence level, in (0, 1). Default 0.95.
    method : str
        How the interval was computed, e.g. ``"wilson"``, ``"t"`` (keyword-only, required).

    Returns
    -------
    dict
        ``{"low", "high", "level", "method"}``, bounds and level as Python floats.

    Raises
    ------
    ValidationError
        If a bound is not finite, ``low > high``, ``level`` lies outside (0, 1) or
        ``method`` is not a non-empty string.
    """
    lo, hi = float(low), float(high)
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
        raise ValidationError(f"interval must be finite with low <= high, found ({low}, {high})")
    if not 0.0 < float(level) < 1.0:
        raise ValidationError(f"level must lie in (0, 1), found {level!r}")
    if not isinstance(method, str) or not method.strip():
        raise ValidationError("method must be a non-empty string naming the interval's method")
    return {"low": lo, "high": hi, "level": float(level), "method": method}


def _check_text(name: str, text: Any) -> str:
    if not isinstance(text, str) or not text.strip():
        raise ValidationError(f"{name} must be a non-empty string, found {text!r}")
    return text


def claim(
    paper: str,
    check: str,
    measured: Any,
    threshold: Any,
    holds: bool | np.bool_ | None,
    *,
    source: str | None = None,
    interval: Mapping[str, Any] | None = None,
    premise: tuple[str, bool | np.bool_] | None = None,
    key: str | None = None,
    tolerance: Tolerance | None = None,
    section: str | None = None,
    not_checked: str | None = None,
    basis: str = "measured",
    decides: bool = False,
    runs: int | None = None,
) -> dict[str, Any]:
    """One claims-JSON entry (see the module docstring for the keys).

    Parameters
    ----------
    paper : str
        What the paper states, in its own words where possible.
    check : str
        What we measure, against what, and the decision rule (for Monte Carlo
        values: the rule on the confidence interval).
    measured : number, sequence or mapping
        The measured value(s); finite numbers only.
    threshold : number, sequence, mapping or None
        The value the measurement is compared with.
    holds : bool or None
        Whether the statement holds at this run's parameters; None when it could not be
        checked here (``not_checked`` says why; the outcome is ``not-checked``).
    source : str
        The paper's place (``"Sec. V, Fig. 4"``, ``"Theorem 2, (34)"``) or ``"ours"``.
    interval : mapping, optional
        Confidence interval of ``measured`` (or of its ``key`` entry) from :func:`interval`.
    premise : (str, bool), optional
        The theorem's own assumption and whether it holds at this run; when it
        does not, the verdict is ``fails-premise`` whatever ``holds`` says.
    key : str, optional
        The entry of a mapping ``measured`` that the robustness table records.
    tolerance : Tolerance, optional
        Reproduction tolerance of ``measured`` across machines (default :data:`DETERMINISTIC`).
    section : str, optional
        Heading of the notebook section that measures the claim (for links).
    not_checked : str, optional
        Why the claim could not be checked here; required exactly when ``holds`` is None.
    basis : {"measured", "by-construction"}
        ``by-construction`` marks a claim that holds because of how the check is built
        (kept and shown, not counted as evidence; :data:`BASES`).
    decides : bool
        True for the paper's main claims, which decide its ReScience verdict
        (:func:`rescience_verdict`).
    runs : int, optional
        The Monte Carlo run count behind ``measured`` (recorded; the rule must not depend on it).
    """
    if holds is not None and not isinstance(holds, bool | np.bool_):
        raise ValidationError(f"holds must be a bool or None, found {type(holds).__name__}")
    if (holds is None) != (not_checked is not None):
        raise ValidationError("not_checked: give the reason exactly when holds is None "
                              f"(holds={holds!r}, not_checked={not_checked!r})")
    if basis not in BASES:
        raise ValidationError(f"basis: expected one of {BASES}, found {basis!r}")
    if not isinstance(decides, bool):
        raise ValidationError(f"decides must be a bool, found {type(decides).__name__}")
    if decides and basis != "measured":
        raise ValidationError("decides: a claim that holds by construction is no evidence and "
                              "cannot decide the verdict (basis must be 'measured')")
    if decides and _ours(source):
        raise ValidationError(f"decides: a claim of ours cannot decide the paper's verdict "
                              f"(source {source!r})")
    if runs is not None and (isinstance(runs, bool) or not isinstance(runs, int) or runs < 1):
        raise ValidationError(f"runs: expected a run count >= 1, found {runs!r}")
    _check_text("paper", paper)
    _check_text("check", check)
    entry: dict[str, Any] = {
        "paper": paper,
        "check": check,
        "measured": _plain(measured),
        "threshold": _plain(threshold),
        "holds": None if holds is None else bool(holds),
        "basis": basis,
    }
    if not_checked is not None:
        entry["not_checked"] = _check_text("not_checked", not_checked)
    if decides:
        entry["decides"] = True
    if runs is not None:
        entry["runs"] = runs
    if source is not None:
        entry["source"] = _check_text("source", source)
    if interval is not None:
        if not isinstance(interval, Mapping) or not {"low", "high", "level", "method"} <= set(interval):
            raise ValidationError("interval must come from results.interval(low, high, level=, method=)")
        entry["interval"] = _plain(dict(interval))
    if key is not None:
        if not isinstance(entry["measured"], dict) or key not in entry["measured"]:
            raise ValidationError(f"key {key!r} must name an entry of the measured mapping")
        entry["key"] = key
    if premise is not None:
        if (
            not isinstance(premise, Sequence)
            or len(premise) != 2
            or not isinstance(premise[1], bool | np.bool_)
        ):
            raise ValidationError("premise must be a (statement, holds) pair with a bool")
        entry["premise"] = {"statement": _check_text("premise", premise[0]), "holds": bool(premise[1])}
    tol = DETERMINISTIC if tolerance is None else tolerance
    if not isinstance(tol, Tolerance):
        raise ValidationError(f"tolerance must be a results.Tolerance, found {type(tol).__name__}")
    entry["tolerance"] = tol.as_dict()
    if section is not None:
        entry["section"] = _check_text("section", section)
    entry["verdict"] = point_verdict(entry)
    return entry


def _ours(source: str | None) -> bool:
    """True when a claim's ``source`` says it is ours (``"ours"``, ``"ours (...)"``, ``"ours; ..."``)."""
    return source is not None and re.match(r"ours\b", source) is not None


def counts_text(outcomes: Mapping[str, int]) -> str:
    """The one written form of a claim's counts over the declared space.

    README and ERRATA quote counts only in this form, so that a test can compare every
    quoted count with ``figures/<key>/robustness.json`` (``tests/test_verdicts.py``).

    Parameters
    ----------
    outcomes : mapping
        Outcome -> number of design points (the ``outcomes`` of a robustness entry).

    Returns
    -------
    str
        ``"8 holds / 16 fails / 9 fails-premise / 0 not-checked"``: every outcome of
        :data:`POINT_OUTCOMES`, in that order, zeros included.
    """
    return " / ".join(f"{int(outcomes.get(o, 0))} {o}" for o in POINT_OUTCOMES)


COUNTS_PATTERN = re.compile(
    r"\b([CX]\w*)[:,]? (\d+) holds / (\d+) fails / (\d+) fails-premise / (\d+) not-checked")
"""Where README or ERRATA quote :func:`counts_text` after a claim id (``C2a 8 holds / ...``)."""


def point_verdict(entry: Mapping[str, Any]) -> str:
    """``fails-premise`` if the premise fails, else ``not-checked``, else ``holds`` or ``fails``.

    Parameters
    ----------
    entry : mapping
        A claims-JSON entry (from :func:`claim`): its ``holds`` and, if present,
        ``premise["holds"]`` are read.

    Returns
    -------
    str
        The outcome at this run's parameters, one of :data:`POINT_OUTCOMES`.
    """
    premise = entry.get("premise")
    if premise is not None and not premise["holds"]:
        return "fails-premise"  # whatever was (or could not be) measured
    if entry["holds"] is None:
        return "not-checked"
    return "holds" if entry["holds"] else "fails"


def rescience_verdict(claims: Mapping[str, Mapping[str, Any]]) -> dict[str, Any]:
    """The paper's ReScience verdict by one written rule, the same for all five papers.

    The deciding claims are the entries with ``decides`` true and ``basis`` ``measured``:
    the paper's main claims, chosen in the notebook (a claim true by construction never
    decides). With the outcome at the paper's example (:func:`point_verdict` of the
    entry: the notebooks' committed run is the paper's setting) and the verdict over the
    declared space (``verdict``):

    ``[Re]``
        every deciding claim holds at the paper's example and its verdict over the space
        is ``holds``;
    ``[¬Re]``
        no deciding claim holds at the paper's example;
    ``[Re, partial]``
        otherwise: some hold at the example, and some fail, fail their premise, are not
        checked, or hold only in part of the space.

    Which claims decide is the notebook's part, by one convention for all five papers:
    the paper's main contributions (its abstract, introduction and conclusion), each a
    measured statement of the paper that can fail. A general result that the paper's
    example cannot exercise (its premise cannot hold there, or it holds vacuously or by
    identities) is decided on a declared instance of ours that satisfies its premises; its
    evaluation at the example is shown (``fails-premise`` or by construction) and does not
    decide. A contribution that cannot be measured here decides as ``not-checked``.

    Parameters
    ----------
    claims : mapping
        Claim id -> entry, as in ``figures/<key>/claims.json``.

    Returns
    -------
    dict
        ``verdict`` (one of :data:`RESCIENCE`), ``deciding`` (id -> ``{"example": outcome at
        the paper's example, "space": verdict over the space}``) and ``line``: the verdict
        with the claims that decide it, e.g. ``"[Re, partial]: C1 holds; C3 undetermined"``.

    Raises
    ------
    ValidationError
        If no claim decides (a notebook must name its main claims).
    """
    deciding = {
        cid: {"example": point_verdict(e), "space": e["verdict"]}
        for cid, e in sorted(claims.items(), key=lambda item: _claim_order(item[0]))
        if e.get("decides") and e.get("basis", "measured") == "measured"
    }
    if not deciding:
        raise ValidationError("rescience_verdict: no claim has decides=True (and basis 'measured')")
    at_example = [d["example"] == "holds" for d in deciding.values()]
    if all(at_example) and all(d["space"] == "holds" for d in deciding.values()):
        verdict = "[Re]"
    elif not any(at_example):
        verdict = "[¬Re]"
    else:
        verdict = "[Re, partial]"

    def said(cid: str, d: Mapping[str, str]) -> str:
        if d["space"] == d["example"]:
            return f"{cid} {d['space']}"
        return f"{cid} {d['example']} at the example, {d['space']} over the space"

    line = f"{verdict}: " + "; ".join(said(cid, d) for cid, d in deciding.items())
    return {"verdict": verdict, "deciding": deciding, "line": line}


def _claim_order(cid: str) -> tuple:
    """C-claims before X-claims, numbers numerically (C2 < C2a < C10)."""
    import re

    parts = re.findall(r"\d+|\D+", cid)
    return (cid[0] != "C",) + tuple((0, int(p)) if p.isdigit() else (1, p) for p in parts)


def headline_value(entry: Mapping[str, Any]) -> float | None:
    """The number a robustness table records for a claim: ``measured`` or ``measured[key]``.

    Parameters
    ----------
    entry : mapping
        A claims-JSON entry (from :func:`claim`).

    Returns
    -------
    float or None
        ``measured`` when it is a number, ``measured[key]`` when ``measured`` is a
        mapping and the entry names its ``key`` and that value is a number; None
        otherwise (lists, booleans, a mapping without ``key``).
    """
    value = entry.get("measured")
    if isinstance(value, Mapping):
        value = value.get(entry["key"]) if "key" in entry else None
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


REQUIRED_KEYS = ("paper", "check", "measured", "threshold", "holds", "verdict", "tolerance")


def robustness_markdown(key: str) -> str | None:
    """The sweep's summary of notebook ``key`` as a Markdown table, or None before any sweep.

    One row per claim of ``figures/<key>/robustness.json`` (written by ``make robustness``):
    its verdict over the declared space, the points where it holds with the Wilson interval
    of that fraction, and the region in words.

    Parameters
    ----------
    key : str
        Notebook key, e.g. ``"guo2023"``.

    Returns
    -------
    str or None
        The table, or None when ``figures/<key>/robustness.json`` does not exist.
    """
    path = resolve(f"figures/{key}/robustness.json")
    if not path.exists():
        return None
    rows = [
        f"| {cid} | {s['verdict']} | {s['outcomes']['holds']} of {s['points']} points "
        f"(95 % Wilson {s['interval']['low']:.2f}-{s['interval']['high']:.2f}) | "
        + str(s["region"]).replace("|", "\\|")
        + " |\n"
        for cid, s in json.loads(path.read_text()).items()
    ]
    return "| claim | verdict over the space | holds at | region |\n|---|---|---|---|\n" + "".join(rows)


def write_claims(
    path: str | Path,
    claims: Mapping[str, Mapping[str, Any]],
    *,
    robustness: str | Path | None = None,
) -> Path:
    """Write ``claims`` (id -> :func:`claim` entry) as sorted, indented JSON.

    Numbers are written with the precision deterministic floating point carries: to a
    tenth of :data:`DETERMINISTIC` (:meth:`Tolerance.round`: 11 significant digits,
    multiples of 1e-13 near zero), whatever the claim's own tolerance, so that readers
    and recomputations keep every digit that can be reproduced and no rounding noise.
    A claim's ``tolerance`` says how much of that reproduces on another machine
    (``python -m secest.repro.verify``).

    Parameters
    ----------
    path : str or Path
        Output file, resolved from the repository root.
    claims : mapping
        Claim id -> :func:`claim` entry.
    robustness : str or Path, optional
        The sweep summary ``figures/<key>/robustness.json`` written by ``make
        robustness``. Where it covers a claim, the claim's ``verdict`` becomes the
        verdict over the declared space and ``robustness`` holds the fraction of
        the design where it holds, its interval and the region. A missing file
        leaves the point verdicts.

    Raises
    ------
    ValidationError
        If an id is not of the form ``C<number>`` or ``X<number>`` (ours), or an
        entry lacks one of the keys of :data:`REQUIRED_KEYS`.
    """
    for cid, entry in claims.items():
        if not (cid[:1] in "CX" and cid[1:].replace("_", "").isalnum() and len(cid) > 1):
            raise ValidationError(f"claim id {cid!r} must look like 'C1' (paper) or 'X1' (ours)")
        if cid.startswith("C") and _ours(entry.get("source")):
            raise ValidationError(f"claim {cid}: a claim of ours (source {entry.get('source')!r}) "
                                  "takes an X id; C ids are the paper's statements")
        missing = [k for k in REQUIRED_KEYS if k not in entry]
        if missing:
            raise ValidationError(f"claim {cid} lacks keys {missing}")
    merged = {cid: dict(entry) for cid, entry in claims.items()}
    summary_path = resolve(robustness) if robustness is not None else None
    if summary_path is not None and summary_path.exists():
        summary = json.loads(summary_path.read_text())
        for cid, entry in merged.items():
            if cid in summary:
                entry["verdict"] = summary[cid]["verdict"]
                entry["robustness"] = summary[cid]
    out = resolve(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    rounded = {cid: _rounded_claim(entry) for cid, entry in _plain(merged).items()}
    text = json.dumps(rounded, indent=2, sort_keys=True) + "\n"
    out.write_text(text)
    return out


def _rounded_claim(entry: Mapping[str, Any]) -> dict[str, Any]:
    """``entry`` with every number except its tolerance rounded with :data:`DETERMINISTIC`."""
    return {k: v if k == "tolerance" else _round_leaves(v, DETERMINISTIC) for k, v in entry.items()}


def _round_leaves(value: Any, tolerance: Tolerance) -> Any:
    """Round every float in a JSON-ready value (nested lists / dicts) with ``tolerance``."""
    if isinstance(value, dict):
        return {k: _round_leaves(v, tolerance) for k, v in value.items()}
    if isinstance(value, list):
        return [_round_leaves(v, tolerance) for v in value]
    if isinstance(value, float):
        return tolerance.round(value)
    return value


def _git_commit() -> str:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=repo_root(),
            capture_output=True,
            text=True,
            check=True,
        )
        dirty = subprocess.run(
            ["git", "status", "--porcelain"], cwd=repo_root(), capture_output=True, text=True
        ).stdout.strip()
        return out.stdout.strip() + ("-dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


class Run:
    """Run manifest of one notebook execution, written to ``build/runs/<key>.json``.

    Create it right after the parameters cell with the notebook's parameters: it
    checks every value against the notebook's declared domain (so a run through
    papermill directly is checked too); call :meth:`finish` at the end.
    Machine-dependent content (timings, versions) lives only here, never in
    committed outputs.

    Parameters
    ----------
    key : paper key, e.g. ``"lee2020"``.
    namespace : mapping holding the parameter values (pass ``globals()``).
    """

    def __init__(self, key: str, namespace: Mapping[str, Any]) -> None:
        from secest.repro import spaces

        space = spaces.load(key)
        self.key = key
        values = {name: namespace.get(name, p.default) for name, p in space.parameters.items()}
        spaces.validate(space, values)
        self.parameters = {name: _plain(v) for name, v in values.items()}
        self._start = time.perf_counter()

    def finish(self, *, solver: str | None = None, extra: Mapping[str, Any] | None = None) -> Path:
        """Write the manifest (versions, solver, git commit, parameters, wall time)."""
        versions = {"python": platform.python_version()}
        for pkg in _PACKAGES:
            try:
                versions[pkg] = metadata.version(pkg)
            except metadata.PackageNotFoundError:
                versions[pkg] = "not installed"
        manifest = {
            "key": self.key,
            "git_commit": _git_commit(),
            "machine": f"{platform.system()} {platform.machine()}",
            "versions": versions,
            "solver": solver,
            "parameters": self.parameters,
            "wall_time_s": round(time.perf_counter() - self._start, 3),
            "extra": _plain(dict(extra or {})),
        }
        path = repo_root() / "build" / "runs" / f"{self.key}.json"
        if self.parameters.get("mode") not in (None, "paper"):
            path = path.with_name(f"{self.key}.{self.parameters['mode']}.json")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n")
        return path
