"""The paper's experiments: one command runs the battery and writes the comparison."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from mimics.batteries.report import runs_table

ROOT = Path(__file__).resolve().parents[2]


def _load_paper():
    spec = importlib.util.spec_from_file_location("mimics_experiments_paper",
                                                  ROOT / "experiments" / "paper.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def test_figure2_quick_writes_the_figure_and_a_comparison_that_matches_the_runs(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    paper = _load_paper()
    out = tmp_path / "figure2"
    assert paper.main(["figure2", "--quick", "--out", str(out), "--workers", "2"]) == 0
    table = runs_table(out)
    assert sorted(table["robots"].unique()) == [1, 5, 10] and len(table) == 6
    assert (out / "plots" / "wall_time_vs_robots.png").stat().st_size > 10_000
    text = (out / "comparison.md").read_text()
    assert text in capsys.readouterr().out
    mean_wall = float(re.search(r"\| ([0-9.]+) ± ([0-9.]+) s,", text).group(1))
    assert mean_wall == pytest.approx(table["wall_time"].mean(), abs=0.006)
    paper_per_run = 28.92 * 3600 / 5400
    assert f"{paper_per_run / table['wall_time'].mean():,.0f}x" in text
    means = table.groupby("robots")["wall_time"].mean()
    slope = np.polyfit(means.index.to_numpy(float), means.to_numpy(float), 1)[0]
    assert f"{1000 * slope:.3g} ms per robot" in text
    assert "0 collisions" in text  # straight lines 1 m apart never meet
