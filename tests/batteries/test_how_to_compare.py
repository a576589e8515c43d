"""The how-to 'Compare algorithms with statistics': its code blocks are snippet files, and
they run as a reader would run them (in a temporary folder, through the CLI)."""

from __future__ import annotations

import runpy
import shlex
from pathlib import Path

import pandas as pd
import pytest

from mimics.batteries import runs_table
from mimics.batteries.stats import t_interval
from mimics.interfaces.cli import main
from tests.docs.test_snippets import SNIPPETS, included

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "how-to" / "compare-algorithms.md"


def run_shell(snippet: str) -> None:
    for line in (SNIPPETS / snippet).read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            words = shlex.split(line)
            assert words[0] == "mimics" and main(words[1:]) == 0, line


def test_the_how_to_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                         capsys: pytest.CaptureFixture[str]) -> None:
    snippets = included(PAGE)  # fails on a code block that is not a snippet file
    assert snippets == ["compare_algorithms/compare.toml", "compare_algorithms/run.sh",
                        "compare_algorithms/compare.sh", "compare_algorithms/compare.py"]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "compare.toml").write_text((SNIPPETS / snippets[0]).read_text())
    run_shell(snippets[1])
    run_shell(snippets[2])
    runpy.run_path(str(SNIPPETS / snippets[3]), run_name="__main__")
    printed = capsys.readouterr().out
    assert "Wilcoxon signed-rank" in printed and "95% Wilson interval" in printed
    table = runs_table(tmp_path / "compare")
    for _, cell in table.groupby("algorithm"):  # each cell met the rule or used every seed
        values = cell["path_length"].to_numpy(dtype=float)
        assert len(values) >= 5
        assert t_interval(values).half_width <= 0.2 or len(values) == 200
    written = pd.read_csv(tmp_path / "compare.csv").set_index("metric")
    lengths = table.set_index(["algorithm", "seed"])["path_length"]
    seeds = sorted(set(table[table["algorithm"] == "go_to_goal"]["seed"])
                   & set(table[table["algorithm"] == "wall_aware"]["seed"]))
    differences = [lengths["go_to_goal", s] - lengths["wall_aware", s] for s in seeds]
    assert written.loc["path_length", "pairs"] == len(seeds)
    assert written.loc["path_length", "mean_difference"] == pytest.approx(
        sum(differences) / len(differences))
