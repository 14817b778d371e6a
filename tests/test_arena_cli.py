"""The arena as a tool: the examples of docs/your-plant-your-method.md run as they are (from
Python and from the command line, in a temporary folder), the files they write, the command
line's argument checks, and the card schema of the documentation against the validator."""

from __future__ import annotations

import csv
import json
import runpy
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import repo_root

from secest.arena import cli, race, report, scenarios
from secest.arena.estimators import METHODS
from secest.core.validation import ValidationError

EXAMPLES = repo_root() / "docs" / "examples"
PAGE = repo_root() / "docs" / "your-plant-your-method.md"
FILES = ["heatmap.png", "matrix.csv", "matrix.json"]


@pytest.fixture
def examples(tmp_path: Path):
    """A copy of docs/examples; the method the examples register is unregistered afterwards."""
    folder = tmp_path / "examples"
    shutil.copytree(EXAMPLES, folder)
    before = list(METHODS)
    yield folder
    for name in [n for n in METHODS if n not in before]:
        METHODS.pop(name)
    sys.modules.pop("my_method", None)
    while str(folder) in sys.path:
        sys.path.remove(str(folder))


def _cells(folder: Path) -> dict[tuple[str, str], dict[str, str]]:
    with (folder / "matrix.csv").open() as fh:
        return {(r["scenario"], r["method"]): r for r in csv.DictReader(fh)}


def _check_folder(folder: Path, plants: list[str], scenarios_: list[str], methods: list[str]) -> dict:
    """The files a race writes, consistent with each other; returns the CSV cells."""
    written = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
    assert written == sorted(FILES + [f"tables/{p}.md" for p in plants])
    assert (folder / "heatmap.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    cells = _cells(folder)
    assert list(cells) == [(s, m) for s in scenarios_ for m in methods]
    record = json.loads((folder / "matrix.json").read_text())
    assert [s["name"] for s in record["scenarios"]] == scenarios_
    assert [m["name"] for m in record["methods"]] == methods
    for cell in record["cells"]:
        row = cells[(cell["scenario"], cell["method"])]
        assert cell["status"] == row["status"] == cell["text"]["status"].lower()
        assert (cell["steady"] is None) == (row["steady"] == "nan")
    plant_of = {s["name"]: s["plant"] for s in record["scenarios"]}
    for plant in plants:
        table = (folder / "tables" / f"{plant}.md").read_text()
        rows = [line for line in table.splitlines() if line.startswith("| `")]
        assert len(rows) == sum(plant_of[s] == plant for s, _ in cells)
    return cells


PLANT_SCENARIOS = ["oscillator6/none", "oscillator6/bias", "oscillator6/bias2"]
METHOD_SCENARIOS = ["oscillator6/none", "oscillator6/bias2", "target20/none", "target20/bias2"]
RACED = ["oracle", "fixed-gain-kf", "kf", "chi2-kf", "guo2023"]


def _check_plant_race(folder: Path, methods: list[str]) -> None:
    cells = _check_folder(folder, ["oscillator"], PLANT_SCENARIOS, methods)
    for sc in PLANT_SCENARIOS:  # what the page says of this plant
        assert float(cells[(sc, "oracle")]["steady"]) == pytest.approx(1.0, rel=1e-9)
        assert cells[(sc, "kf")]["status"] == cells[(sc, "chi2-kf")]["status"] == "ok"
        # outside its theory (different noise per node): scored all the same, and marked
        assert cells[(sc, "ding2020")]["outside"].startswith("every node has the same")
    for sc in PLANT_SCENARIOS[1:]:  # under a bias: li2025's and ma2021's theories do not cover it
        assert cells[(sc, "li2025")]["outside"] and cells[(sc, "ma2021")]["outside"]
    assert "Assumption 1: at most q = 1" in cells[("oscillator6/bias2", "lee2020")]["outside"]


def _check_method_race(folder: Path) -> None:
    cells = _check_folder(folder, ["oscillator", "target"], METHOD_SCENARIOS, RACED)
    assert all(cells[(sc, "fixed-gain-kf")]["status"] == "ok" for sc in METHOD_SCENARIOS)
    assert all(float(cells[(sc, "fixed-gain-kf")]["steady"]) >= 1.0 for sc in METHOD_SCENARIOS)


def test_the_examples_run_from_python(examples: Path) -> None:
    runpy.run_path(str(examples / "race_plant.py"), run_name="__main__")
    _check_plant_race(examples / "results-plant", list(METHODS))
    runpy.run_path(str(examples / "race_method.py"), run_name="__main__")
    _check_method_race(examples / "results-method")


def _commands(script: Path) -> list[list[str]]:
    """The commands of a shell script of the docs (comments dropped, continuations joined)."""
    text = script.read_text().replace("\\\n", " ")
    lines = [line.strip() for line in text.splitlines() if line.strip() and not line.startswith("#")]
    assert all(line.startswith("python -m secest.arena ") for line in lines)
    return [[sys.executable, *shlex.split(line)[1:]] for line in lines]


def test_the_examples_run_from_the_command_line(examples: Path) -> None:
    plant, method, listing = _commands(examples / "race.sh")
    procs = [subprocess.Popen(cmd, cwd=examples, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True) for cmd in (plant, method, listing)]  # side by side
    outs = [(p.communicate(timeout=120), p.returncode) for p in procs]
    assert [code for _, code in outs] == [0, 0, 0], [err[-2000:] for (_, err), _ in outs]
    stdout = [out for (out, _), _ in outs]
    _check_plant_race(examples / "results-plant", list(METHODS))
    _check_method_race(examples / "results-method")
    assert stdout[1].startswith("4 scenarios x 5 methods: 20 ok, 0 n/a, 0 diverged, 0 error")
    for name in ("oscillator6", "bias2", "oscillator", "fixed-gain-kf", "ding2020", "target20"):
        assert f"  {name} " in stdout[2]


@pytest.mark.parametrize("argv, words", [
    (["--runs", "1"], "argument --runs: expected an integer >= 2, found 1"),
    (["--horizon", "0"], "argument --horizon: expected an integer >= 1, found 0"),
    (["--seed", "x"], "argument --seed: expected an integer >= 0, found 'x'"),
    (["--methods", "kf,,li2025"], "argument --methods: expected a comma-separated list of names"),
    (["--frobnicate"], "unrecognized arguments: --frobnicate"),
    (["--out", "o", "--plants", "nope"], "plants: ['nope'] have no network card; known: ["),
    (["--out", "o", "--attacks", "bias,nope"], "attacks: ['nope'] have no attack card; known: ["),
    (["--out", "o", "--methods", "nope"], "methods ['nope'] are not registered; registered: ["),
    (["--cards", "missing.toml", "--list"], "--cards: no file 'missing.toml'"),
    (["--method", "foo", "--list"], "--method must be MOD:CLASS (a module or .py path, a class name)"),
    (["--method", "missing.py:X", "--list"], "--method missing.py:X: no file 'missing.py'"),
    (["--method", "no_such_mod:X", "--list"], "--method no_such_mod:X: cannot import module"),
    (["--method", "secest.arena.estimators:Score", "--list"],
     "'Score' is not a Method subclass of 'secest.arena.estimators'; Method subclasses there: ["),
    ([], "--out DIR is required to race (or --list to see the cards)"),
])
def test_a_bad_argument_is_one_line_and_exit_status_2(argv, words, tmp_path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    try:
        status = cli.main(argv)
    except SystemExit as exc:  # argparse's own checks
        status = exc.code
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1 and err.startswith("python -m secest.arena: error: ")
    assert words in err
    assert not (tmp_path / "o").exists()  # nothing written: refused before any work


def test_a_bad_cards_file_is_refused_by_key(tmp_path: Path, capsys) -> None:
    cards = tmp_path / "bad.toml"
    cards.write_text((EXAMPLES / "my_cards.toml").read_text().replace("magnitude = 30.0", "magnitud = 30.0"))
    assert cli.main(["--cards", str(cards), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"python -m secest.arena: error: --cards {cards}: ")
    assert err.endswith("attack bias2: unknown key 'magnitud' (did you mean 'magnitude'?); "
                        "valid: ['kind', 'magnitude', 'nodes', 'p', 'q', 'start', 'title', 'windows']")
    assert not (tmp_path / "o").exists()


def test_race_checks_its_arguments_before_running(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    for kw, words in [({"methods": "kf"}, "methods must be a non-empty list"),
                      ({"methods": [3]}, "methods: each entry must be a method name or a Method"),
                      ({"plants": "inertia5"}, "plants must be a non-empty list of card names"),
                      ({"attacks": []}, "attacks must be a non-empty list of card names"),
                      ({"out": tmp_path / "file"}, "out must be a folder path (not a file)")]:
        with pytest.raises(ValidationError, match=words.replace("(", r"\(").replace(")", r"\)")):
            race(**({"plants": ["inertia5"], "attacks": ["none"], "runs": 2, "horizon": 4,
                      "short": True} | kw))


def test_without_matplotlib_the_matrix_is_written_without_heatmap(tmp_path, monkeypatch) -> None:
    m = race(methods=["kf"], plants=["inertia5"], attacks=["none"], runs=2, horizon=4, short=True)
    report.write(m, tmp_path)
    assert (tmp_path / "heatmap.png").is_file()
    monkeypatch.setattr(report, "can_plot", lambda: False)
    written = report.write(m, tmp_path)
    assert not (tmp_path / "heatmap.png").exists()  # the stale one is gone too
    assert [p.name for p in written] == ["matrix.csv", "matrix.json", "three_inertia.md"]


# ---------------------------------------------------------------------------------- the schema


def _accepted_keys() -> dict[str, set[str]]:
    """Every key the card validator accepts, per kind, read from its own tables."""
    network = {"title", "plant", "N", "graph", "measures"}
    for required, optional in scenarios._NETWORK_KEYS.values():
        network |= required | optional
    attack = {"title", "kind"}
    for required, optional in scenarios._ATTACK_KEYS.values():
        attack |= required | optional
    # the scenario's keys are the schema itself (the validator reads them from it); the package's
    # [matrix] table uses every [matrix] key
    return {"plant": set(scenarios.CARD_KEYS["plant"]), "network": network, "attack": attack,
            "scenario": set(scenarios.CARD_KEYS["scenario"]), "matrix": set(scenarios._cards()["matrix"])}


def test_the_documented_card_keys_are_the_validated_ones() -> None:
    documented = {kind: set(keys) for kind, keys in scenarios.CARD_KEYS.items()}
    assert documented == _accepted_keys()  # the plant's are the schema itself, by construction
    text = report.card_schema()
    for kind, keys in scenarios.CARD_KEYS.items():
        heading = "[matrix]" if kind == "matrix" else f"[{kind}.<name>]"
        block = text.split(f"**`{heading}`**")[1].split("**`[")[0]
        rows = [line.split("`")[1] for line in block.splitlines() if line.startswith("| `")]
        assert rows == list(keys)
    assert "```{include} _generated/card_schema.md" in PAGE.read_text()


@pytest.mark.parametrize("key, low, below", [("horizon", 1, 0), ("runs", 2, 1), ("seed", 0, -1)])
def test_the_run_settings_are_checked_as_the_schema_says(key: str, low: int, below: int) -> None:
    """Each setting is a documented key of [scenario.<name>] and [matrix], with its lower bound."""
    assert key in scenarios.CARD_KEYS["scenario"] and key in scenarios.CARD_KEYS["matrix"]
    assert f">= {low}" in scenarios.CARD_KEYS["scenario"][key]
    assert f">= {low}" in scenarios.CARD_KEYS["matrix"][key]
    assert scenarios.SETTINGS[key](key, low) == low
    with pytest.raises(ValidationError, match=rf"^scenario s: {key} must be >= {low}, found {below}$"):
        scenarios.cards(extra={"scenario": {"s": {"network": "inertia5", "attack": "none", key: below}}})
    assert set(scenarios.SETTINGS) == set(scenarios.CARD_KEYS["scenario"]) - {"title", "network", "attack"}


def test_an_unknown_matrix_key_is_refused_with_the_nearest_one() -> None:
    table = {**scenarios._cards()["matrix"], "atacks": ["none"]}
    c = scenarios.cards()
    with pytest.raises(ValidationError, match=r"^cards \[matrix\]: unknown key 'atacks' \(did you mean "
                                              r"'attacks'\?\); valid: \[.*\]$"):
        scenarios._matrix_table(table, c["network"], c["attack"])


@pytest.mark.parametrize("kind, card", [
    ("plant", {"title": "t", "source": "s", "Ac": [[0.0]], "dt": 1.0, "q_std": 1.0,
               "outputs": [[1.0]], "r_std": [1.0], "x0_std": 1.0, "state_names": ["a"]}),
    ("network", {"title": "t", "plant": "target", "N": 4, "graph": "ring", "measures": [[0]] * 4}),
    ("attack", {"title": "t", "kind": "dos", "p": 0.1, "q": 0.9}),
])
def test_a_key_outside_the_schema_is_refused(kind: str, card: dict) -> None:
    scenarios.cards(extra={kind: {"mine": card}})  # valid as written
    with pytest.raises(ValidationError, match=rf"{kind} mine: unknown key 'colour'"):
        scenarios.cards(extra={kind: {"mine": {**card, "colour": "red"}}})


def test_the_package_docstring_names_every_subpackage_and_arena_module() -> None:
    import secest
    import secest.arena

    root = repo_root() / "secest"
    for pkg in sorted(p.parent.name for p in root.glob("*/__init__.py")):
        assert f":mod:`secest.{pkg}`" in secest.__doc__
    arena = sorted(p.stem for p in (root / "arena").glob("*.py") if not p.stem.startswith("_"))
    arena += sorted(p.parent.name for p in (root / "arena").glob("*/__init__.py"))
    assert {"scenarios", "estimators", "matrix", "report", "cli", "papers"} <= set(arena)
    for module in arena:
        assert f"``{module}``" in secest.__doc__ and f"``{module}``" in secest.arena.__doc__
