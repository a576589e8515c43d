"""Run and battery plots: files of the expected size, and one-line errors on bad input."""

import json
from pathlib import Path
from typing import Any

import imageio.v3 as iio
import numpy as np
import pytest
import typer
from matplotlib.collections import PathCollection
from scipy import stats
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


def arrivals(robots: int, reached: int, seed: int, horizon: float = 21.8) -> dict[str, Any]:
    """A summary's arrival record: ``reached`` of ``robots`` goal robots arrived."""
    times = sorted(12.0 + seed + 0.05 * k for k in range(reached))
    restricted = (sum(times) + horizon * (robots - reached)) / robots if robots else None
    return {"goal_robots": robots, "arrived": reached, "horizon": horizon, "times": times,
            "restricted_mean": restricted}


def write_battery(root: Path, with_line: bool = True, recorded: bool = True) -> Path:
    """A battery folder of run summaries only (as a finished battery leaves them); without
    ``recorded``, summaries as mimics wrote them before it kept arrival times."""
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
                if recorded:
                    summary["arrivals"] = arrivals(robots, reached, seed)
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
    assert [p.name for p in written] == ["outcomes.png", "time_to_goal.png", "arrivals.png",
                                         "wall_time_vs_robots.png"]
    assert skipped == []
    assert all(p.parent == root / "plots" for p in written)
    assert iio.imread(written[0]).shape[:2] == (600, 1200)
    assert iio.imread(written[3]).shape[:2] == (600, 900)
    # four panels (cave, and the line's three points) on two rows: the default height
    assert iio.imread(written[1]).shape[:2] == iio.imread(written[2]).shape[:2] == (600, 1000)


def test_battery_without_line_runs_skips_figure_2(tmp_path: Path) -> None:
    root = write_battery(tmp_path / "battery", with_line=False)
    written, skipped = battery_plots(root, tmp_path / "figs")
    assert len(written) == 3 and len(skipped) == 1 and "line" in skipped[0]


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
    assert result.stdout.count("wrote ") == 4
    assert f"wrote {tmp_path / 'out' / 'arrivals.png'}" in result.stdout
    help_text = CliRunner().invoke(cli(), ["battery-plot", "--help"]).stdout
    assert "arrivals.png" in help_text and "one point per run" in help_text
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
    assert table["state"].tolist() == ["done"] * 3 + ["crashed"]
    written, _ = battery_plots(root)
    assert len(written) == 3


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


# -- time to goal per run, arrival curves ---------------------------------------------

HORIZON = 21.8


def title(fig: Any) -> str:
    """The figure's title on one line (it is wrapped to the figure's width)."""
    return " ".join(fig._suptitle.get_text().split())


def panels(fig: Any) -> dict[str, Any]:
    """The figure's panels by title (hidden grid cells left out)."""
    return {ax.get_title(): ax for ax in fig.axes if ax.axison}


def points(ax: Any) -> tuple[np.ndarray, int]:
    """The y of every point drawn in a panel, and how many are hollow."""
    scatters = [c for c in ax.collections if isinstance(c, PathCollection)]
    ys = np.concatenate([c.get_offsets()[:, 1] for c in scatters]) if scatters else np.zeros(0)
    hollow = sum(len(c.get_offsets()) for c in scatters if len(c.get_facecolors()) == 0)
    return np.sort(np.asarray(ys, dtype=float)), hollow


def by_hand(robots: int, seeds: list[int]) -> list[float]:
    """Restricted means of write_battery's runs, from their arrival times written out."""
    means = []
    for seed in seeds:
        reached = robots - (seed % 2)
        times = [12.0 + seed + 0.05 * k for k in range(reached)]
        means.append((sum(times) + HORIZON * (robots - reached)) / robots)
    return sorted(means)


def rewrite(root: Path, algorithm: str, **changes: Any) -> None:
    for path in root.rglob("summary.json"):
        data = json.loads(path.read_text())
        if data["algorithm"] == algorithm:
            data.update(changes)
            path.write_text(json.dumps(data))


def test_time_to_goal_is_one_point_per_run_in_a_panel_per_parameter_point(
        tmp_path: Path) -> None:
    from mimics.interfaces.plots import plot_time_to_goal

    fig = plot_time_to_goal(battery_table(write_battery(tmp_path / "battery")), None)
    shown = panels(fig)
    assert list(shown) == ["cave", "line: robots=1", "line: robots=10", "line: robots=30"]
    # cave: 3 + 2 done runs of 100 robots each, 5 points (not 500 robots); seed 1 lost one
    ys, hollow = points(shown["cave"])
    assert ys == pytest.approx(sorted(by_hand(100, [0, 1, 2]) + by_hand(100, [0, 1])))
    assert hollow == 2
    ys, hollow = points(shown["line: robots=10"])
    assert ys == pytest.approx(sorted(by_hand(10, [0, 1, 2]) * 2)) and hollow == 2
    assert points(shown["line: robots=1"])[0].max() == pytest.approx(HORIZON)  # never arrived
    for ax in shown.values():
        assert any(list(line.get_ydata()) == [HORIZON, HORIZON] and line.get_linestyle() == "--"
                   for line in ax.lines)
    ticks = [t.get_text() for t in shown["cave"].get_xticklabels()]
    assert ticks == ["deployment\nn = 3 runs", "wall_aware\nn = 2 runs\n1 failed"]
    assert "21.8 s horizon" in shown["cave"].get_ylabel()
    assert "one point per run" in title(fig)


def test_robots_that_never_arrive_count_at_the_horizon_and_keep_the_curve_low(
        tmp_path: Path) -> None:
    """The reviewer's case: an algorithm whose robots never arrive has no mean over arrivals,
    but its runs score the horizon and its arrival curve stays at 0."""
    from mimics.interfaces.plots import plot_arrivals, plot_time_to_goal

    root = write_battery(tmp_path / "battery")
    for robots in (1, 10, 30):
        for path in root.rglob("summary.json"):
            data = json.loads(path.read_text())
            if data["algorithm"] == "go_to_goal_team" and data["robots"] == robots:
                data.update(reached_goal=0, time_to_goal={"mean": None},
                            arrivals=arrivals(robots, 0, data["seed"]))
                path.write_text(json.dumps(data))
    table = battery_table(root)
    team = table[table["algorithm"] == "go_to_goal_team"]
    assert team["time_to_goal_arrived"].isna().all()
    assert team["time_to_goal"].tolist() == pytest.approx([HORIZON] * 9)
    shown = panels(plot_time_to_goal(table, None))
    ys, hollow = points(shown["line: robots=10"])
    assert ys[-3:] == pytest.approx([HORIZON] * 3) and hollow == 1 + 3
    curve = next(line for line in panels(plot_arrivals(table, None))["line: robots=10"].lines
                 if line.get_label().startswith("go_to_goal_team"))
    assert set(curve.get_ydata()) == {0.0}
    assert curve.get_label() == "go_to_goal_team: 0/30 arrived, n = 3 runs"


def test_arrival_curves_are_scipys_kaplan_meier_per_cell(tmp_path: Path) -> None:
    from mimics.interfaces.plots import plot_arrivals

    root = write_battery(tmp_path / "battery")
    fig = plot_arrivals(battery_table(root), None)
    shown = panels(fig)
    assert list(shown) == ["cave", "line: robots=1", "line: robots=10", "line: robots=30"]
    # the truth: wall_aware's two done cave runs, each non-arrival censored at 21.8 s
    summaries = [json.loads(p.read_text()) for p in root.rglob("summary.json")]
    mine = [s for s in summaries if s["algorithm"] == "wall_aware" and s["status"] != "error"]
    truth = stats.ecdf(stats.CensoredData(
        uncensored=[t for s in mine for t in s["arrivals"]["times"]],
        right=[HORIZON] * sum(s["robots"] - s["reached_goal"] for s in mine))).cdf
    line = next(ln for ln in shown["cave"].lines if ln.get_label().startswith("wall_aware"))
    assert line.get_ydata() == pytest.approx(truth.evaluate(line.get_xdata()), abs=1e-12)
    assert line.get_xdata()[-1] == HORIZON
    assert line.get_label() == "wall_aware: 199/200 arrived, n = 2 runs, 1 failed (left out)"
    ax = shown["cave"]
    assert any(list(ln.get_xdata()) == [HORIZON, HORIZON] for ln in ax.lines)  # the horizon
    assert "21.8 s horizon" in ax.get_xlabel()
    assert "Kaplan-Meier" in title(fig)


def test_older_batteries_fall_back_and_say_so(tmp_path: Path) -> None:
    from mimics.interfaces.plots import plot_arrivals, plot_time_to_goal

    table = battery_table(write_battery(tmp_path / "battery", recorded=False))
    assert table["arrival_times"].isna().all() and table["time_to_goal"].isna().all()
    fig = plot_time_to_goal(table, None)
    assert "conditional on arriving" in title(fig)
    assert points(panels(fig)["cave"])[0] == pytest.approx([20, 20, 21, 21, 22])
    fig = plot_arrivals(table, None)
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert any("recorded before" in t for t in texts), texts
    assert all(not ax.axison for ax in fig.axes)
    written, _ = battery_plots(tmp_path / "battery")
    assert [p.name for p in written][:3] == ["outcomes.png", "time_to_goal.png", "arrivals.png"]


def test_no_goal_robots_say_so_instead_of_an_empty_axis(tmp_path: Path) -> None:
    from mimics.interfaces.plots import plot_arrivals, plot_time_to_goal

    root = write_battery(tmp_path / "battery", with_line=False)
    for path in root.rglob("summary.json"):  # deployment: nobody has a goal
        data = json.loads(path.read_text())
        data.update(reached_goal=0, time_to_goal={}, arrivals=arrivals(0, 0, 0))
        path.write_text(json.dumps(data))
    for plot in (plot_time_to_goal, plot_arrivals):
        fig = plot(battery_table(root), None)
        texts = [t.get_text() for ax in fig.axes for t in ax.texts]
        assert any("No robot in these runs has a goal" in t for t in texts), texts
        assert all(not ax.axison for ax in fig.axes)
        assert iio.imread(plot(battery_table(root), tmp_path / "f.png")).shape[:2] == (600, 1000)


def test_the_database_gives_the_points_and_arrivals(tmp_path: Path, monkeypatch) -> None:
    """A battery's runs table (the contract's columns) names the parameter points and
    carries the arrivals even where a run's summary has none."""
    import pandas as pd

    from mimics.batteries import report
    from mimics.interfaces.plots import plot_time_to_goal

    root = write_battery(tmp_path / "battery", with_line=False, recorded=False)
    (root / "battery.db").write_bytes(b"")
    rows = []
    for path in sorted(root.rglob("summary.json")):
        data = json.loads(path.read_text())
        record = arrivals(100, data["reached_goal"], data["seed"])
        rows.append({"folder": str(path.parent), "state": "done", "params": "{}",
                     "algorithm": data["algorithm"], "scenario": "cave", "seed": data["seed"],
                     "parameters": "robots=100", "arrival_times": record["times"],
                     "goal_robots": 100, "horizon": HORIZON,
                     "time_to_goal": record["restricted_mean"], "time_to_goal_arrived": 1.0})
    monkeypatch.setattr(report, "runs_table", lambda folder: pd.DataFrame(rows))
    table = battery_table(root)
    assert set(table["point"]) == {"robots=100"} and set(table["state"]) == {"done"}
    assert table["arrived"].tolist() == [100, 99, 100] * 2
    fig = plot_time_to_goal(table, None)
    assert list(panels(fig)) == ["robots=100"]
    expected = sorted(by_hand(100, [0, 1, 2]) * 2)
    assert points(panels(fig)["robots=100"])[0] == pytest.approx(expected)


def test_outcome_bars_partition_the_robots_when_collisions_stall(tmp_path: Path) -> None:
    # under on_collision = "stall" a robot that collided drives on (collisions 2, both
    # active at the end): the outcome bars stack final states, which add up to the robots
    import math

    from mimics.world.maps import Map
    from mimics.world.robot_types import RobotType
    from mimics.world.scenario import Scenario, Settings

    body = RobotType("blind", width=0.5, length=0.7, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2)
    world = Map(np.zeros((0, 4)), (-10, -10, 10, 10))
    for rule in ("stall", "deactivate"):
        scene = Scenario.from_matrix([[-1.0, 0.0, 0.0, 0.0], [1.0, 0.0, math.pi, 0.0]], world,
                                     body, settings=Settings(noise="off", on_collision=rule))
        sim = prepare(scene, lambda robot: (0.6, 0.0 if robot.id == 0 else math.pi), time=4.0,
                      seed=3)
        run_to_folder(sim, tmp_path / rule / "run-0001", robot_logs="off")
    table = battery_table(tmp_path)
    by_rule = {Path(folder).parent.name: row for folder, row in
               zip(table["folder"], table.to_dict("records"), strict=True)}
    stalled, deactivated = by_rule["stall"], by_rule["deactivate"]
    assert (stalled["collisions"], stalled["collided_at_end"],
            stalled["active_at_end"]) == (2, 0, 2)
    assert (deactivated["collisions"], deactivated["collided_at_end"]) == (2, 2)
    for row in (stalled, deactivated):
        bars = (row["reached_goal"] + row["collided_at_end"] + row["escaped"]
                + row["stopped_other"] + row["active_at_end"])
        assert bars == row["robots"] == 2
