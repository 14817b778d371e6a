"""secest.repro.verify: reproduced or drifted, within declared tolerances (no notebook is executed here)."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest

from secest.core.validation import ValidationError
from secest.repro import plotting, results, verify
from secest.repro.results import DETERMINISTIC, Tolerance

ROOT = results.repo_root()
KEY = "guo2023"  # the smallest committed result folder
LOOSE = Tolerance(rtol=1e-3, atol=1e-2, reason="test: sign-driven chattering")


@pytest.fixture
def folders(tmp_path: Path) -> tuple[Path, Path]:
    """Two copies of the committed ``figures/<KEY>/``: reference and candidate roots."""
    for side in ("ref", "cand"):
        shutil.copytree(ROOT / "figures" / KEY, tmp_path / side / KEY)
    return tmp_path / "ref", tmp_path / "cand"


def _run(folders: tuple[Path, Path], tmp_path: Path, *keys: str) -> tuple[int, dict[str, Any]]:
    ref, cand = folders
    report = tmp_path / "verify.json"
    code = verify.main(["--against", str(cand), "--reference", str(ref), "--report", str(report), *keys])
    return code, json.loads(report.read_text())


def _numeric_leaf(claims: dict[str, Any]) -> tuple[str, list[str | int], float]:
    """The first claim with a numeric leaf in ``measured``: its id, the path to it and its value."""
    def walk(value: Any, path: list[str | int]) -> tuple[list[str | int], float] | None:
        if isinstance(value, dict):
            items = sorted(value.items())
        elif isinstance(value, list):
            items = list(enumerate(value))
        else:
            ok = isinstance(value, int | float) and not isinstance(value, bool) and value != 0
            return (path, float(value)) if ok else None
        for k, v in items:
            found = walk(v, [*path, k])
            if found:
                return found
        return None

    for cid in sorted(claims):
        found = walk(claims[cid]["measured"], [])
        if found:
            return cid, *found
    raise AssertionError("no claim with a numeric measured value")


def _set_leaf(claims: dict[str, Any], cid: str, path: list[str | int], value: float) -> None:
    if not path:
        claims[cid]["measured"] = value
        return
    target = claims[cid]["measured"]
    for step in path[:-1]:
        target = target[step]
    target[path[-1]] = value


def _perturb_claim(folder: Path, factor: float) -> tuple[str, str]:
    """Move one measured value by ``factor`` times its allowed difference; return claim id and its name."""
    path = folder / KEY / "claims.json"
    claims = json.loads(path.read_text())
    cid, leaf, value = _numeric_leaf(claims)
    tol = Tolerance(**claims[cid]["tolerance"])
    _set_leaf(claims, cid, leaf, value + factor * tol.allowed(value))
    path.write_text(json.dumps(claims))
    name = f"{cid}.measured" + "".join(f"[{s}]" if isinstance(s, int) else f".{s}" for s in leaf)
    return cid, name


def _edit_csv(folder: Path, edit) -> tuple[str, str]:
    """Apply ``edit(rows)`` to the first CSV of the folder; return its stem and its second column."""
    path = sorted((folder / KEY).glob("*.csv"))[0]
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    edit(rows)
    with path.open("w", newline="") as fh:
        csv.writer(fh, lineterminator="\n").writerows(rows)
    return path.stem, rows[0][1]


# ------------------------------------------------------------------ --against


def test_identical_folders_reproduce(folders, tmp_path, capsys) -> None:
    code, report = _run(folders, tmp_path)
    out = capsys.readouterr().out
    assert code == 0 and report["passed"]
    nb = report["notebooks"][KEY]
    assert nb["compared"] > 1000 and nb["beyond_tolerance"] == [] and nb["problems"] == []
    assert f"== {KEY}: REPRODUCED" in out and "every value identical" in out
    assert "tolerances:" in out and "rtol 1e-09, atol 1e-12" in out  # every tolerance is named


def test_measured_value_beyond_tolerance_is_named(folders, tmp_path, capsys) -> None:
    cid, name = _perturb_claim(folders[1], factor=100.0)
    code, report = _run(folders, tmp_path, KEY)
    out = capsys.readouterr().out
    assert code == 1 and not report["passed"]
    assert report["notebooks"][KEY]["beyond_tolerance"] == [f"{cid}.measured"]
    assert f"BEYOND TOLERANCE {cid}.measured" in out and name in out and "NOT REPRODUCED" in out


def test_measured_value_within_tolerance_passes(folders, tmp_path) -> None:
    _perturb_claim(folders[1], factor=0.5)
    code, report = _run(folders, tmp_path, KEY)
    assert code == 0, report["notebooks"][KEY]["beyond_tolerance"]
    assert report["notebooks"][KEY]["closest_to_tolerance"]["share"] > 0.1


def test_flipped_holds_is_caught(folders, tmp_path, capsys) -> None:
    path = folders[1] / KEY / "claims.json"
    claims = json.loads(path.read_text())
    cid = sorted(claims)[0]
    claims[cid]["holds"] = not claims[cid]["holds"]
    path.write_text(json.dumps(claims))
    code, report = _run(folders, tmp_path, KEY)
    assert code == 1
    assert any(p.startswith(f"{cid}: holds changed") for p in report["notebooks"][KEY]["problems"])
    assert f"CHANGED {cid}: holds changed" in capsys.readouterr().out


def test_changed_verdict_and_missing_claim_are_caught(folders, tmp_path) -> None:
    path = folders[1] / KEY / "claims.json"
    claims = json.loads(path.read_text())
    first, last = sorted(claims)[0], sorted(claims)[-1]
    claims[first]["verdict"] = "undetermined"
    del claims[last]
    path.write_text(json.dumps(claims))
    code, report = _run(folders, tmp_path, KEY)
    problems = report["notebooks"][KEY]["problems"]
    assert code == 1
    assert any(p.startswith(f"{first}: verdict changed") for p in problems)
    assert f"claim {last} only in the reference" in problems


def test_csv_column_beyond_tolerance_is_named(folders, tmp_path, capsys) -> None:
    def bump(rows: list[list[str]]) -> None:
        rows[5][1] = repr(float(rows[5][1]) * 1.01 + 1.0)

    stem, column = _edit_csv(folders[1], bump)
    code, report = _run(folders, tmp_path, KEY)
    assert code == 1
    assert report["notebooks"][KEY]["beyond_tolerance"] == [f"{stem}.csv:{column}"]
    assert f"BEYOND TOLERANCE {stem}.csv:{column}: 1 of" in capsys.readouterr().out


def test_non_numeric_cell_and_row_count_are_compared(folders, tmp_path) -> None:
    stem, column = _edit_csv(folders[1], lambda rows: rows[3].__setitem__(1, "n/a"))
    code, report = _run(folders, tmp_path, KEY)
    assert code == 1 and report["notebooks"][KEY]["beyond_tolerance"] == [f"{stem}.csv:{column}"]
    _edit_csv(folders[1], lambda rows: rows.pop())
    code, report = _run(folders, tmp_path, KEY)
    assert code == 1 and any("rows in reference" in p for p in report["notebooks"][KEY]["problems"])


def test_missing_figure_is_a_problem_but_pixels_are_only_reported(folders, tmp_path) -> None:
    pngs = sorted((folders[1] / KEY).glob("*.png"))
    pngs[0].unlink()
    code, report = _run(folders, tmp_path, KEY)
    assert code == 1 and f"{pngs[0].name} only in the reference" in report["notebooks"][KEY]["problems"]
    shutil.copy(pngs[1], pngs[0])  # a different picture under the same name: reported, not failed
    code, report = _run(folders, tmp_path, KEY)
    rms = report["notebooks"][KEY]["images_rms"][pngs[0].stem]
    assert code == 0 and (isinstance(rms, str) or rms > 0)


def test_declared_column_tolerance_is_used(tmp_path, capsys) -> None:
    for side, value in (("ref", 1.0), ("cand", 1.005)):
        plotting.save_data(tmp_path / side / "demo", "extra_demo",
                           {"t": [0.0, 1.0], "x": [[0.5] * 3, [value] * 3]}, tolerance={"x": LOOSE})
    code = verify.main(["--against", str(tmp_path / "cand"), "--reference", str(tmp_path / "ref"),
                        "--report", str(tmp_path / "v.json")])
    out = capsys.readouterr().out
    assert code == 1  # no claims.json on either side
    assert "BEYOND" not in out and "claims.json missing" in out
    assert "rtol 0.001, atol 0.01 (test: sign-driven chattering)" in out and "extra_demo.csv: x[0..2]" in out


# ------------------------------------------------------------------ bad input and the run mode


def test_bad_input(folders, tmp_path, capsys) -> None:
    ref, cand = folders
    assert verify.main(["--against", str(tmp_path / "nowhere"), "--reference", str(ref)]) == 2
    assert "against folder" in capsys.readouterr().err
    assert verify.main(["--against", str(cand), "--reference", str(tmp_path / "nowhere")]) == 2
    assert "reference folder" in capsys.readouterr().err
    with pytest.raises(ValidationError, match="folder .* of notebook 'nokey' does not exist"):
        verify.verify(["nokey"], against=cand, reference=ref)
    with pytest.raises(ValidationError, match="key 'nokey' names no notebook"):
        verify.verify(["nokey"], reference=ref)
    (cand / KEY / "claims.json").write_text("{not json")
    with pytest.raises(ValidationError, match="claims file .*claims.json is not valid JSON"):
        verify.verify([KEY], against=cand, reference=ref)
    (cand / KEY / "claims.json").unlink()
    (cand / KEY / "tolerances.json").write_text('{"x": 1}')
    with pytest.raises(ValidationError, match="tolerances file .* is malformed"):
        verify.verify([KEY], against=cand, reference=ref)
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValidationError, match="holds no result folders"):
        verify.verify([], against=empty, reference=ref)


def test_run_mode_compares_the_fresh_folder(monkeypatch, tmp_path, capsys) -> None:
    def fake_run(key: str, out_root: Path) -> tuple[Path, float]:  # stands in for papermill
        shutil.copytree(ROOT / "figures" / key, out_root / key)
        return out_root / key, 1.5

    monkeypatch.setattr(verify, "run_paper_mode", fake_run)
    reports = verify.verify([KEY], out_root=tmp_path / "build")
    assert reports[0].passed and reports[0].seconds == 1.5
    assert "paper mode in 1.5 s" in capsys.readouterr().out


# ------------------------------------------------------------------ writers: precision and sidecar


def test_tolerance_rounding() -> None:
    assert DETERMINISTIC.round(0.9450393948859259) == DETERMINISTIC.round(0.9450393948859268) == 0.94503939489
    assert DETERMINISTIC.round(1e-17) == 0.0 and str(DETERMINISTIC.round(-1e-17)) == "0.0"
    assert LOOSE.resolution(1.0) == 0.001 and LOOSE.round(0.123456) == 0.123
    exact = Tolerance(rtol=0.0, atol=0.0, reason="exact")
    assert exact.round(0.1 + 0.2) == 0.1 + 0.2 and exact.resolution(3.0) == 0.0
    assert DETERMINISTIC.round(float("nan")) != DETERMINISTIC.round(float("nan"))


def test_write_claims_rounds_to_deterministic_precision(tmp_path) -> None:
    c = results.claim("p", "c", {"a": 0.12345678901234, "b": [1.0e-17, 2]}, 0.1 + 0.2, True,
                      tolerance=LOOSE, interval=results.interval(0.1234567, 0.2345678, method="t"))
    path = results.write_claims(tmp_path / "claims.json", {"C1": c})
    entry = json.loads(path.read_text())["C1"]
    assert entry["measured"] == {"a": 0.12345678901, "b": [0.0, 2]}  # not to LOOSE's 3 digits
    assert entry["interval"]["low"] == 0.1234567 and entry["threshold"] == 0.3
    assert entry["tolerance"] == LOOSE.as_dict()


def test_save_data_records_tolerances_and_drops_stale_entries(tmp_path) -> None:
    data = {"t": [0.0, 0.5], "x": [[1.0, 2.0], [3.0, 4.0]], "err_a": [1e-3, 2e-3], "err_b": [0.0, 1.0]}
    tol = {"x[1]": LOOSE, "err_*": LOOSE}
    plotting.save_data(tmp_path, "fig1_demo", data, tolerance=tol)
    plotting.save_data(tmp_path, "fig2_demo", {"k": [1, 2]})
    sidecar = tmp_path / plotting.TOLERANCES_FILE
    first = sidecar.read_bytes()
    table = json.loads(first)
    assert table["fig1_demo"] == [
        {"columns": ["t", "x[0]"], **DETERMINISTIC.as_dict()},
        {"columns": ["x[1]", "err_a", "err_b"], **LOOSE.as_dict()},
    ]
    assert table["fig2_demo"] == [{"columns": ["k"], **DETERMINISTIC.as_dict()}]
    plotting.save_data(tmp_path, "fig1_demo", data, tolerance=tol)
    assert sidecar.read_bytes() == first  # deterministic
    (tmp_path / "fig2_demo.csv").unlink()  # what `secest.repro.build prepare` does before a run
    plotting.save_data(tmp_path, "fig1_demo", data, tolerance={"x": LOOSE})
    table = json.loads(sidecar.read_text())
    assert set(table) == {"fig1_demo"} and table["fig1_demo"][1]["columns"] == ["x[0]", "x[1]"]


def test_save_data_tolerance_bad_input(tmp_path) -> None:
    with pytest.raises(ValidationError, match=r"tolerance patterns \['y\*'\] match no column"):
        plotting.save_data(tmp_path, "d", {"x": [1.0]}, tolerance={"y*": LOOSE})
    with pytest.raises(ValidationError, match=r"tolerance\['x'\] must be a results.Tolerance"):
        plotting.save_data(tmp_path, "d", {"x": [1.0]}, tolerance={"x": 1e-3})
    with pytest.raises(ValidationError, match="tolerance must be a results.Tolerance or a mapping"):
        plotting.save_data(tmp_path, "d", {"x": [1.0]}, tolerance=1e-3)
    fig, _ = plt.subplots()
    with pytest.raises(ValidationError, match="without data"):
        plotting.save_figure(fig, tmp_path, "fig1_demo", tolerance=LOOSE)
    plt.close(fig)
    assert not any(tmp_path.iterdir())


def test_save_figure_passes_the_tolerance_and_writes_rounded_data(tmp_path) -> None:
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0.123456, -1e-9])
    plotting.save_figure(fig, tmp_path, "fig1_demo", data={"t": [0, 1], "y": [0.123456, -1e-9]},
                         tolerance={"y": LOOSE})
    assert (tmp_path / "fig1_demo.csv").read_text().splitlines() == ["t,y", "0,0.123", "1,0"]
    assert json.loads((tmp_path / "tolerances.json").read_text())["fig1_demo"][1]["columns"] == ["y"]


def test_nan_and_infinity_compare_as_values(tmp_path) -> None:
    columns = {"ref": [float("nan"), float("inf"), 1.0], "cand": [float("nan"), float("inf"), float("nan")]}
    for side, values in columns.items():
        plotting.save_data(tmp_path / side / "demo", "extra_demo", {"x": values})
    report = verify.compare_folders("demo", tmp_path / "ref" / "demo", tmp_path / "cand" / "demo")
    (x,) = report.quantities
    assert x.compared == 3 and x.beyond == 1 and x.worst_at == "extra_demo.csv:x row 2"


def test_sweep_outputs_missing_from_a_paper_mode_run_are_noted_not_failed(folders, tmp_path) -> None:
    for path in (folders[1] / KEY).glob("robustness*"):
        path.unlink()  # a paper-mode run writes no sweep outputs
    code, report = _run(folders, tmp_path, KEY)
    notes = report["notebooks"][KEY]["notes"]
    assert code == 0 and any(n.startswith("robustness.csv only in the reference") for n in notes)
