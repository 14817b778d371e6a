"""lee2020: papermill fast-mode execution, claims asserted against the paper."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.xdist_group("lee2020")


@pytest.fixture(scope="module")
def claims(run_notebook):
    return run_notebook("lee2020")


def test_theorem1_every_agent_within_bound(claims) -> None:
    c1 = claims["C1"]
    assert set(c1["measured"]) == {"ring", "all-to-all"}
    for graph, distances in c1["measured"].items():
        assert len(distances) == 7
        assert max(distances) <= c1["threshold"][graph]
    assert c1["holds"] is True


def test_theorem1_bound_values(claims) -> None:
    n, gamma = 7, 5.0
    lam2_ring = 2 * (1 - np.cos(2 * np.pi / n))
    assert claims["C1"]["threshold"]["ring"] == pytest.approx(2 * np.sqrt(n) / (gamma * lam2_ring))
    assert claims["C1"]["threshold"]["all-to-all"] == pytest.approx(2 / (gamma * np.sqrt(n)))


def test_remark2_lambda2(claims) -> None:
    assert claims["C2"]["holds"] is True
    assert claims["C2"]["measured"]["ring"] == pytest.approx(0.753020, abs=1e-6)


def test_figure_and_data_written(claims) -> None:
    fig_dir = Path(claims["_fig_dir"])
    assert (fig_dir / "extra_s1_median_solver.png").stat().st_size > 10_000
    header = (fig_dir / "extra_s1_median_solver.csv").read_text().splitlines()[0]
    assert header.startswith("t_s,x_ring[0]")
