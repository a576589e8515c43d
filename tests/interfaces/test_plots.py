"""Run and battery plots: files of the expected size, and one-line errors on bad input."""

import json
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import pytest
import typer
from typer.testing import CliRunner

from mimics.interfaces.cli.view import battery_plot_command, plot_command
from mimics.interfaces.plots import battery_plots, battery_table, plot_run
from mimics.records.runner import prepare, run_to_folder
from mimics.world.errors import MimicsError


def cli() -> typer.Typer:
    app = typer.Typer()
    app.command("plot")(plot_command)
    app.command("battery-plot")(battery_plot_command)
    return app


def write_battery(root: Path, with_line: bool = True) -> Path:
    """A battery folder of run summaries only (as a finished battery leaves them)."""
    k = 0
    combos = [("cave", "deployment"), ("cave", "wall_aware")]
    if with_line:
        combos += [("line", "go_to_goal"), ("line", "go_to_goal_team")]
    for scenario, algorithm in combos:
        for robots in (1, 10, 30) if scenario == "line" else (100,):
            for seed in range(3):
                reached = robots - (seed % 2)
                summary = {
                    "status": "error" if (algorithm, seed) == ("wall_aware", 2) else "completed",
                    "scenario": scenario, "algorithm": algorithm, "seed": seed,
                    "parameters": {"robots": robots}, "robots": robots,
                    "sim_time": 21.8, "wall_time": 0.01 * robots + 0.001 * seed,
                    "reached_goal": reached, "collisions": robots - reached, "escaped": 0,
                    "deadlocks": 0, "livelocks": 0, "exceptions": 0, "active_at_end": 0,
                    "time_to_goal": {"mean": 20.0 + seed, "min": 19.0, "max": 22.0}}
                folder = root / f"run-{k:04d}"
                folder.mkdir(parents=True)
                (folder / "summary.json").write_text(json.dumps(summary))
                k += 1
    return root


@pytest.fixture(scope="module")
def recorded_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A short Cave deployment run when the Stage data is here, else the line scenario."""
    folder = tmp_path_factory.mktemp("plots") / "run"
    try:
        sim = prepare("cave", "deployment", time=2.0, seed=1)
    except MimicsError:  # no Stage data on this machine
        sim = prepare("line", "go_to_goal", robots=5, time=21.8, seed=1)
    run_to_folder(sim, folder, robot_logs="off")
    return folder


def test_plot_command_writes_a_png_of_the_requested_size(recorded_run: Path,
                                                         tmp_path: Path) -> None:
    out = tmp_path / "run.png"
    result = CliRunner().invoke(cli(), ["plot", str(recorded_run), "--out", str(out),
                                        "--width", "900", "--height", "700"])
    assert result.exit_code == 0, result.output
    assert iio.imread(out).shape[:2] == (700, 900)
    plot_run(recorded_run, tmp_path / "default.png")
    assert iio.imread(tmp_path / "default.png").shape[:2] == (800, 1000)


def test_battery_plots_include_the_papers_figure_2(tmp_path: Path) -> None:
    root = write_battery(tmp_path / "battery")
    table = battery_table(root)
    assert len(table) == 2 * 3 + 2 * 9
    written, skipped = battery_plots(root)
    assert [p.name for p in written] == ["outcomes.png", "time_to_goal.png",
                                         "wall_time_vs_robots.png"]
    assert skipped == []
    assert all(p.parent == root / "plots" for p in written)
    assert iio.imread(written[0]).shape[:2] == (600, 1200)
    assert iio.imread(written[2]).shape[:2] == (600, 900)


def test_battery_without_line_runs_skips_figure_2(tmp_path: Path) -> None:
    root = write_battery(tmp_path / "battery", with_line=False)
    written, skipped = battery_plots(root, tmp_path / "figs")
    assert len(written) == 2 and len(skipped) == 1 and "line" in skipped[0]


def test_bad_folders_are_one_line_errors(tmp_path: Path) -> None:
    with pytest.raises(MimicsError, match="no run summaries"):
        battery_table(tmp_path)
    result = CliRunner().invoke(cli(), ["battery-plot", str(tmp_path / "missing")])
    assert result.exit_code == 2
    assert result.stderr.strip().startswith("mimics: error: ")
    assert len(result.stderr.strip().splitlines()) == 1
    result = CliRunner().invoke(cli(), ["plot", str(tmp_path / "missing")])
    assert result.exit_code == 2
    assert "not a run folder" in result.stderr


def test_battery_plot_command_names_what_it_wrote(tmp_path: Path) -> None:
    root = write_battery(tmp_path / "battery")
    result = CliRunner().invoke(cli(), ["battery-plot", str(root), "--out",
                                        str(tmp_path / "out")])
    assert result.exit_code == 0, result.output
    assert result.stdout.count("wrote ") == 3
    assert (tmp_path / "out" / "wall_time_vs_robots.png").is_file()


def test_runs_without_a_summary_come_from_the_battery_database(tmp_path: Path,
                                                               monkeypatch) -> None:
    import pandas as pd

    from mimics.batteries import report

    root = write_battery(tmp_path / "battery", with_line=False)
    (root / "battery.db").write_bytes(b"")  # the report below stands in for the database
    done = sorted(p.parent for p in root.rglob("summary.json"))
    rows = [{"folder": str(f), "state": "done", "algorithm": "deployment", "scenario": "cave",
             "seed": k, "params": "{}"} for k, f in enumerate(done[:3])]
    rows.append({"folder": str(root / "runs" / "never-written"), "state": "crashed",
                 "algorithm": "deployment", "scenario": "cave", "seed": 9, "params": "{}"})
    monkeypatch.setattr(report, "runs_table", lambda folder: pd.DataFrame(rows))
    table = battery_table(root)
    assert table["status"].tolist() == ["completed"] * 3 + ["crashed"]
    written, _ = battery_plots(root)
    assert len(written) == 2


def boxes(artists: list[Any], renderer: Any) -> list[Any]:
    return [a.get_window_extent(renderer) for a in artists if a.get_visible()]


@pytest.mark.parametrize("algorithms", [1, 2])
def test_the_outcome_legends_cover_no_bar_and_no_label(tmp_path: Path, algorithms: int) -> None:
    from mimics.interfaces.plots import plot_outcomes

    root = write_battery(tmp_path / "battery", with_line=False)
    if algorithms == 1:  # one tall bar per axes: no room left inside them for a legend
        for summary in root.rglob("summary.json"):
            if json.loads(summary.read_text())["algorithm"] == "wall_aware":
                summary.unlink()
    fig = plot_outcomes(battery_table(root), None)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    for ax in fig.axes:
        legend = ax.get_legend().get_window_extent(renderer)
        bars = boxes([p for p in ax.patches if p.get_height() > 0], renderer)
        assert bars
        labels = boxes([*ax.get_xticklabels(), *ax.texts, ax.title], renderer)
        assert not [b for b in [*bars, *labels] if legend.overlaps(b)]
        assert fig.bbox.contains(legend.x0, legend.y0) and fig.bbox.contains(legend.x1,
                                                                             legend.y1)


def test_a_metric_without_data_says_so_instead_of_an_empty_axis(tmp_path: Path) -> None:
    from mimics.interfaces.plots import plot_time_to_goal

    root = write_battery(tmp_path / "battery", with_line=False)
    for summary in root.rglob("summary.json"):  # nobody reached a goal
        data = json.loads(summary.read_text())
        data.update(reached_goal=0, collisions=data["robots"], time_to_goal={})
        summary.write_text(json.dumps(data))
    fig = plot_time_to_goal(battery_table(root), None)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any("No robot reached its goal" in t for t in texts), texts
    assert all(not ax.axison for ax in fig.axes)  # no empty axis drawn
    out = plot_time_to_goal(battery_table(root), tmp_path / "ttg.png")
    assert iio.imread(out).shape[:2] == (600, 1000)


def test_a_cell_without_data_is_marked_in_the_time_to_goal_plot(tmp_path: Path) -> None:
    from mimics.interfaces.plots import plot_time_to_goal

    root = write_battery(tmp_path / "battery", with_line=False)
    for summary in root.rglob("summary.json"):
        data = json.loads(summary.read_text())
        if data["algorithm"] == "wall_aware":
            data.update(reached_goal=0, collisions=data["robots"], time_to_goal={})
            summary.write_text(json.dumps(data))
    fig = plot_time_to_goal(battery_table(root), None)
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert "no data" in texts and "n=3" in texts
