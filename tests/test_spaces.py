"""Declared parameter spaces: parsing, domains, designs, the runner's checks."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

from secest.core.validation import ValidationError
from secest.repro import spaces
from secest.repro.results import repo_root
from secest.repro.run import safe_outputs

ROOT = repo_root()
KEYS = sorted(p.stem for p in (ROOT / "notebooks").glob("*.py"))


def test_parameter_cell_reads_values_and_comments(toy: Path) -> None:
    cell = spaces.parameter_cell("toy", toy)
    assert list(cell)[:3] == ["mode", "T", "scale"]
    assert cell["T"].value == 40 and cell["T"].comment == "horizon (MISSING)"
    assert cell["gains"].value == [0.4, 0.5]


def test_load_infers_types_and_tags(toy: Path) -> None:
    space = spaces.load("toy", toy)
    assert space.parameters["flag"].type == "bool"  # inferred from the default
    assert space.parameters["alpha"].tag == "RECONSTRUCTED"  # read from the comment
    assert space.parameters["fig_dir"].type == "str"
    assert set(space.axes) == {"scale", "twin", "alpha", "seed"}
    assert space.base == {"mode": "fast"}


def test_design_is_grid_times_sobol_with_the_default_first(toy: Path) -> None:
    space = spaces.load("toy", toy)
    points = spaces.design(space)
    assert points[0] == {"scale": 0.15, "twin": 0.15, "alpha": 0.67, "seed": 0}
    assert len(points) == 1 + 2 * 2 * 4  # default + alpha x seed x 4 Sobol points
    assert all(p["twin"] == p["scale"] for p in points)  # tied axis
    assert all(0.1 <= p["scale"] <= 0.3 for p in points)
    assert points == spaces.design(space)  # deterministic
    assert len({round(p["scale"], 12) for p in points[1:]}) == 4


def test_perturbation_points_hit_the_edges(toy: Path) -> None:
    space = spaces.load("toy", toy)
    low, high, middle = spaces.perturbation_points(space)
    assert low == {"scale": 0.1, "twin": 0.1, "alpha": 0.6, "seed": 0}
    assert high == {"scale": 0.3, "twin": 0.3, "alpha": 0.67, "seed": 1}
    assert middle["scale"] == pytest.approx(0.2) and middle["alpha"] == 0.67


def test_check_and_parse_values(toy: Path) -> None:
    p = spaces.load("toy", toy).parameters
    assert spaces.parse_value(p["flag"], "false") is False
    assert spaces.parse_value(p["flag"], "YES") is True
    assert spaces.parse_value(p["T"], "12") == 12
    assert spaces.parse_value(p["scale"], "2") == 2  # an int is a real number
    assert spaces.parse_value(p["gains"], "[1, 2.5]") == [1, 2.5]
    assert spaces.parse_value(p["mode"], "fast") == "fast"
    cases = [
        ("T", "-5", "parameter T must be an integer >= 1, found -5"),
        ("T", "5.5", "parameter T must be an integer >= 1, found 5.5"),
        ("scale", "abc", "parameter scale must be a real number > 0, found 'abc'"),
        ("scale", "nan", "parameter scale must be a real number > 0, found 'nan'"),
        ("alpha", "1.5", "parameter alpha must be a real number >= 0 and <= 1, found 1.5"),
        ("mode", "slow", "parameter mode must be one of 'paper', 'fast', found 'slow'"),
        ("flag", "maybe", "parameter flag must be true or false, found 'maybe'"),
        ("gains", "[1]", "parameter gains must be a list of float of length 2, found [1]"),
        ("gains", "['a', 1]", "parameter gains must be a list of float of length 2"),
        ("T", "None", "parameter T must be an integer >= 1, found None"),
    ]
    for name, text, message in cases:
        with pytest.raises(ValidationError, match=message.replace("[", r"\[").replace("]", r"\]")):
            spaces.parse_value(p[name], text)


def test_bad_space_files_are_refused(toy: Path) -> None:
    path = toy / "notebooks" / "toy.toml"
    good = path.read_text()
    path.write_text(good + "\n[parameters.nope]\ntype = 'int'\n")
    with pytest.raises(
        ValidationError, match=r"describes parameters \['nope'\] that toy.py does not declare"
    ):
        spaces.load("toy", toy)
    path.write_text(good.replace("low = 0.1, high = 0.3", "low = 0.2, high = 0.3"))
    with pytest.raises(
        ValidationError, match="the default of scale .0.15. lies outside its declared space"
    ):
        spaces.load("toy", toy)
    path.write_text(good.replace("values = [0, 1]", "values = [0, -1]"))
    with pytest.raises(ValidationError, match="parameter seed must be an integer >= 0, found -1"):
        spaces.load("toy", toy)
    path.write_text(good.replace('same_as = "scale"', 'same_as = "T"'))
    with pytest.raises(ValidationError, match="same_as must name a swept parameter"):
        spaces.load("toy", toy)
    path.write_text(good.replace("n = 4", "n = 4\nwhat = 1"))
    with pytest.raises(ValidationError, match=r"\[sweep\] of toy.toml has unknown keys \['what'\]"):
        spaces.load("toy", toy)


def test_provenance_markdown_lists_every_parameter(toy: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(spaces, "_root", lambda: toy)
    table = spaces.provenance_markdown("toy")
    assert table.count("\n") == 2 + len(spaces.parameter_cell("toy", toy)) - 1
    assert (
        "| `scale` | `0.15` | MISSING | a real number > 0 | [0.1, 0.3] (sampled) | premise (12)" in table
    )
    assert "{brief, OCR}" in table and "same as `scale`" in table


@pytest.mark.parametrize("key", KEYS)
def test_every_notebook_space_loads(key: str) -> None:
    """The declared space of every notebook is consistent with its parameters cell."""
    space = spaces.load(key)
    assert set(space.parameters) == set(spaces.parameter_cell(key))
    assert space.parameters["mode"].choices == ("paper", "fast")
    points = spaces.design(space)
    assert points[0] == {name: space.parameters[name].default for name in space.axes}


# ---------------------------------------------------------------------------- the runner


def _run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "secest.repro.run", *args], capture_output=True, text=True, cwd=ROOT, timeout=60
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ("ding2020", "-p", "kappa", "abc"),
            "error: parameter kappa must be a real number >= 0, found 'abc'",
        ),
        (("li2025", "-p", "T", "-5"), "error: parameter T must be an integer >= 1, found -5"),
        (
            ("lee2020", "-p", "mode", "slow"),
            "error: parameter mode must be one of 'paper', 'fast', found 'slow'",
        ),
        (("ding2020", "-p", "strict", "perhaps"), "error: parameter strict must be true or false"),
        (
            ("lee2020", "-p", "gama", "2"),
            "error: parameter 'gama' is not declared by notebook 'lee2020'",
        ),
    ],
)
def test_runner_refuses_bad_values_in_one_line_before_any_kernel(args: tuple, message: str) -> None:
    start = time.perf_counter()
    proc = _run(*args)
    elapsed = time.perf_counter() - start
    assert proc.returncode == 2
    assert proc.stderr.startswith(message) and proc.stderr.count("\n") == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    assert elapsed < 3.0  # well under a second on an idle machine; a kernel start takes longer


def test_runner_lists_parameters() -> None:
    proc = _run("ding2020", "--list")
    assert proc.returncode == 0
    lines = proc.stdout.splitlines()
    assert lines[0].split()[:5] == ["name", "default", "admissible", "tag", "declared"]
    assert len(lines) == 1 + len(spaces.parameter_cell("ding2020"))
    assert any(line.startswith("kappa ") and "PAPER" in line for line in lines)


def test_runner_writes_under_build_unless_told_otherwise() -> None:
    out, params = safe_outputs("lee2020", {"gamma_ex": 3.0}, None)
    assert out == ROOT / "build" / "run" / "lee2020" / "lee2020.ipynb"
    assert params["fig_dir"] == str(ROOT / "build" / "run" / "lee2020" / "figures")
    assert params["results_path"] == str(ROOT / "build" / "run" / "lee2020" / "claims.json")
    out, params = safe_outputs("lee2020", {"fig_dir": "/tmp/f"}, "/tmp/x/out.ipynb")
    assert params["fig_dir"] == "/tmp/f" and params["results_path"] == "/tmp/x/claims.json"


def test_runner_booleans_are_parsed() -> None:
    space = spaces.load("ding2020")
    assert spaces.parse_value(space.parameters["strict"], "false") is False
