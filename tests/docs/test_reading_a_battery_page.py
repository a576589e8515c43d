"""The explanation 'Reading a battery': its code blocks are snippet files, its battery runs
as a reader would run it, and the numbers its tables quote are the ones mimics prints."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from mimics.batteries.evidence import battery_evidence
from mimics.batteries.report import runs_table
from tests.docs.test_snippets import SNIPPETS, included, run_shell

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "explanation" / "reading-a-battery.md"


def quoted(label: str, last: bool = False) -> list[str]:
    """The cells of the page's first (or last) table row that starts with ``label``."""
    rows = [line for line in PAGE.read_text().splitlines() if line.startswith(f"| {label} |")]
    return [cell.strip() for cell in rows[-1 if last else 0].strip("|").split("|")[1:]]


def text(estimate: float, low: float, high: float) -> str:
    return f"{estimate:.2f} [{low:.2f}, {high:.2f}]"


def test_the_worked_example_prints_what_the_page_quotes(tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    assert included(PAGE) == ["reading_a_battery/line.toml", "reading_a_battery/run.sh"]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "line.toml").write_text((SNIPPETS / "reading_a_battery/line.toml").read_text())
    run_shell("reading_a_battery/run.sh")
    assert (tmp_path / "line" / "plots" / "arrivals.png").stat().st_size > 10_000
    metrics = ["success", "time_to_goal", "time_to_goal_arrived"]
    evidence = battery_evidence(tmp_path / "line", metrics=metrics)
    cells = evidence.intervals.set_index("algorithm")
    for metric, label in (("success", "success"),
                          ("time_to_goal_arrived", "time_to_goal_arrived (conditional)"),
                          ("time_to_goal", "time_to_goal (restricted, 120 s horizon)")):
        shown = [text(cells.loc[a, metric], cells.loc[a, f"{metric}_low"],
                      cells.loc[a, f"{metric}_high"]) for a in ("wall_aware", "go_to_goal")]
        assert [re.sub(r" s$", "", q).replace(" s [", " [").replace("] s", "]")
                for q in quoted(label)] == shown
    table = runs_table(tmp_path / "line")
    arrived = [f"{int(table[table['algorithm'] == a]['reached_goal'].sum())} of 200"
               for a in ("wall_aware", "go_to_goal")]
    assert quoted("robots arrived") == arrived
    pairs = evidence.comparison.set_index("metric")
    for metric in metrics:
        row = pairs.loc[metric]
        cells_ = quoted(metric, last=True)
        assert cells_[0] == text(row["mean_difference"], row["ci95_low"], row["ci95_high"])
        p = row["p_value"]
        assert cells_[1] == ("<1e-4" if p < 1e-4 else f"{p:.2g}")
    assert evidence.tests == 3
