"""Checks every notebook must pass: pairing, parameters, claims format, manifest."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import jupytext
import nbformat
import pytest

from secest.core.validation import ValidationError
from secest.repro.results import (
    REQUIRED_KEYS,
    VERDICTS,
    declared_parameters,
    repo_root,
    validate_parameters,
)
from secest.repro.run import execute_notebook

ROOT = repo_root()
KEYS = sorted(p.stem for p in (ROOT / "notebooks").glob("*.py"))
PAPERS = ("ding2020", "guo2023", "lee2020", "li2025", "ma2021")


def _code_and_markdown(nb: nbformat.NotebookNode) -> list[tuple[str, str]]:
    return [(c.cell_type, c.source.strip()) for c in nb.cells]


@pytest.mark.parametrize("key", KEYS)
def test_py_and_ipynb_carry_the_same_cells(key: str) -> None:
    """Timestamp-free pairing: the committed .ipynb was built from the current .py."""
    py = jupytext.read(ROOT / "notebooks" / f"{key}.py")
    ipynb = jupytext.read(ROOT / "notebooks" / f"{key}.ipynb")
    assert _code_and_markdown(py) == _code_and_markdown(ipynb)


@pytest.mark.parametrize("key", KEYS)
def test_committed_notebook_is_executed_and_clean(key: str) -> None:
    nb = nbformat.read(ROOT / "notebooks" / f"{key}.ipynb", as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(c.execution_count is not None for c in code), "notebook not executed"
    assert not any(o.get("output_type") == "error" for c in code for o in c.outputs)
    assert "papermill" not in nb.metadata
    assert all("execution" not in c.metadata and "id" not in c for c in nb.cells)


@pytest.mark.parametrize("key", KEYS)
def test_parameters_cell_has_the_required_names(key: str) -> None:
    declared = declared_parameters(key)
    assert {"mode", "fig_dir", "results_path"} <= set(declared)
    assert declared["mode"] == '"paper"'
    assert declared["fig_dir"] == f'"figures/{key}"'
    assert declared["results_path"] == f'"figures/{key}/claims.json"'


@pytest.mark.parametrize("key", KEYS)
def test_committed_claims_are_well_formed(key: str) -> None:
    claims = json.loads((ROOT / "figures" / key / "claims.json").read_text())
    assert claims, "no claims recorded"
    for cid, entry in claims.items():
        assert cid[0] in "CX" and cid[1:].replace("_", "").isalnum()
        assert set(REQUIRED_KEYS) <= set(entry)
        assert isinstance(entry["holds"], bool) or (entry["holds"] is None and entry["not_checked"])
        assert entry["verdict"] in VERDICTS


def _manifest_pngs(key: str) -> list[str]:
    manifest = tomllib.loads((ROOT / "figures" / "manifest.toml").read_text())
    return sorted(
        Path(name).stem
        for fig in manifest[key].get("figures", [])
        for name in fig["files"]
        if name.endswith(".png")
    )


@pytest.mark.parametrize("key", KEYS)
def test_every_saved_figure_is_shown_inline(key: str) -> None:
    """One image/png output per PNG the manifest lists, each tagged with its file stem."""
    nb = nbformat.read(ROOT / "notebooks" / f"{key}.ipynb", as_version=4)
    shown = sorted(
        out["metadata"]["secest"]["figure"]
        for cell in nb.cells
        if cell.cell_type == "code"
        for out in cell.outputs
        if "image/png" in out.get("data", {})
    )
    assert shown == _manifest_pngs(key)


def test_unknown_parameter_is_rejected(tmp_path: Path) -> None:
    with pytest.raises(ValidationError, match=r"parameters \['gama'\] are not declared"):
        validate_parameters("lee2020", {"gama": 2.0})
    with pytest.raises(ValidationError, match="not declared by notebook 'lee2020'"):
        execute_notebook("lee2020", {"mode": "fast", "gama": 2.0}, tmp_path / "out.ipynb")
    assert not (tmp_path / "out.ipynb").exists()


def test_unknown_notebook_is_rejected() -> None:
    with pytest.raises(ValidationError, match="key 'nope' names no notebook"):
        validate_parameters("nope", {})


def test_manifest_lists_every_notebook_and_existing_files() -> None:
    manifest = tomllib.loads((ROOT / "figures" / "manifest.toml").read_text())
    assert set(PAPERS) <= set(manifest)
    for key in KEYS:
        for fig in manifest[key].get("figures", []):
            assert fig["status"] in {"reproduced", "partial", "not reproduced", "ours"}
            for name in fig["files"]:
                assert (ROOT / name).exists(), name


def test_readme_lists_all_papers_and_errata_links_deviations() -> None:
    readme = (ROOT / "README.md").read_text()
    errata = (ROOT / "ERRATA.md").read_text()
    assert "make figures" in readme and "make test" in readme
    for key in PAPERS:
        assert f"notebooks/{key}" in readme
        assert f"## {key}" in errata


@pytest.mark.parametrize("key", KEYS)
def test_committed_notebook_has_no_checkout_path(key: str) -> None:
    """Outputs must not depend on where the repository is checked out (determinism)."""
    text = (ROOT / "notebooks" / f"{key}.ipynb").read_text()
    assert str(ROOT) not in text


def _perturbation_cases() -> list[tuple[str, int]]:
    from secest.repro import spaces

    cases = []
    for key in KEYS:
        space = spaces.load(key)
        if space.axes:
            cases += [(key, i) for i in range(len(spaces.perturbation_points(space)))]
    return cases


@pytest.mark.notebook
@pytest.mark.parametrize(("key", "index"), _perturbation_cases())
def test_notebook_runs_off_its_default_point(key: str, index: int, run_notebook) -> None:
    """Fast mode at a point of the declared space other than the default (edges included).

    The execution is shared with a module's fixture that asks for the same point."""
    from secest.repro import spaces

    point = spaces.perturbation_points(spaces.load(key))[index]
    claims = run_notebook(key, **point)  # read as strict JSON: no NaN, no Infinity
    fig_dir = Path(claims.pop("_fig_dir"))
    assert claims
    for cid, entry in claims.items():
        assert set(REQUIRED_KEYS) <= set(entry), cid
        assert entry["verdict"] in VERDICTS, cid
        assert isinstance(entry["holds"], bool) or (entry["holds"] is None and entry["not_checked"]), cid
    manifest = tomllib.loads((ROOT / "figures" / "manifest.toml").read_text())
    expected = {Path(n).name for fig in manifest[key].get("figures", []) for n in fig["files"]}
    made = {p.name for p in fig_dir.iterdir()} if fig_dir.exists() else set()
    assert expected <= made, f"not produced at {point}: {sorted(expected - made)}"
