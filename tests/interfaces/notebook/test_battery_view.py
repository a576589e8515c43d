"""BatteryView: mimics.run_battery / load_battery over the battery driver and report.

The truth: the battery's own report functions and the run folders' summaries
(each run's reached_goal), and the figures of ``mimics battery plot``.
"""

from __future__ import annotations

import io
import json

import imageio.v3 as imageio
import numpy as np
import pytest
from matplotlib.figure import Figure
from scipy import stats

import mimics
from mimics.batteries.report import aggregate, runs_table
from mimics.interfaces.notebook.html import png_bytes
from mimics.interfaces.plots import battery_plots
from mimics.world.errors import MimicsError

# goals 1 m away and 4 s: some robots arrive, some never do (the arrival curves' censoring)
SPEC = {"battery": {"algorithms": ["go_to_goal"], "seeds": 3, "time": 4.0},
        "scenarios": [{"name": "line", "robots": 2, "distance": 1.0}]}


@pytest.fixture(scope="module")
def battery(tmp_path_factory):
    return mimics.run_battery(SPEC, tmp_path_factory.mktemp("b") / "night", workers=1,
                              progress=False)


def test_table_has_one_row_per_run_with_each_runs_outcome(battery):
    table = battery.table
    assert len(table) == 3 and set(table["state"]) == {"done"}
    assert sorted(table["seed"]) == [1, 2, 3]
    for row in table.itertuples():
        summary = json.loads((battery.folder / "runs").glob(f"{row.id:05d}-*").__next__()
                             .joinpath("summary.json").read_text())
        assert row.reached_goal == summary["reached_goal"]
    assert battery.counts == {"done": 3}


def test_summary_is_the_reports_aggregate(battery):
    summary = battery.summary(columns="all")
    expected = aggregate(runs_table(battery.folder))
    assert len(summary) == 1 and summary.iloc[0]["runs"] == 3
    assert summary.equals(expected)
    tables = battery.report_tables()
    assert set(tables) == {"runs", "failures", "aggregate", "intervals", "comparison", "costs"}
    assert tables["failures"].empty
    # one algorithm: nothing to compare; the intervals rest on the 3 done runs
    assert battery.compare().empty and battery.intervals(columns="all")["done"].tolist() == [3]


def test_compare_pairs_runs_by_seed_against_the_baseline(tmp_path):
    spec = {"battery": {"algorithms": ["go_to_goal", "wall_aware"], "seeds": 3, "time": 2.0},
            "scenarios": [{"name": "line", "robots": 2}]}
    two = mimics.run_battery(spec, tmp_path / "two", workers=1, progress=False)
    runs = two.table
    # the truth: per seed, wall_aware's path length minus go_to_goal's, from the run table
    by_seed = runs.pivot(index="seed", columns="algorithm", values="path_length")
    differences = (by_seed["wall_aware"] - by_seed["go_to_goal"]).to_numpy()
    row = two.compare(metrics=["path_length"]).iloc[0]
    assert (row["algorithm"], row["baseline"], row["pairs"]) == ("wall_aware", "go_to_goal", 3)
    assert row["mean_difference"] == pytest.approx(differences.mean())
    assert row["ci95_low"] <= row["mean_difference"] <= row["ci95_high"]
    assert "Paired by seed" in two._repr_html_()
    with pytest.raises(MimicsError, match="not an algorithm of this battery"):
        two.compare(baseline="nobody")


def test_plot_is_the_figure_of_mimics_battery_plot(battery, tmp_path):
    figure = battery.plot("outcomes")
    assert isinstance(figure, Figure)
    written, _ = battery_plots(battery.folder, tmp_path)
    from_cli = imageio.imread(written[0])
    assert np.array_equal(imageio.imread(io.BytesIO(png_bytes(figure))), from_cli)
    assert isinstance(battery.plot("time_to_goal"), Figure)
    assert [p.name for p in written][:3] == ["outcomes.png", "time_to_goal.png", "arrivals.png"]
    arrivals = battery.plot("arrivals")
    assert np.array_equal(imageio.imread(io.BytesIO(png_bytes(arrivals))),
                          imageio.imread(written[2]))
    with pytest.raises(MimicsError, match="expected one of"):
        battery.plot("pie")


def test_arrivals_are_the_kaplan_meier_curve_of_the_runs(battery):
    curves = battery.arrivals()
    assert list(curves.columns) == ["algorithm", "scenario", "parameters", "time", "fraction",
                                    "low", "high", "runs", "robots", "arrived", "horizon"]
    # the truth, from the run folders: every goal robot, each non-arrival censored at 4 s
    summaries = [json.loads(p.read_text()) for p in battery.folder.glob("runs/*/summary.json")]
    arrived = [t for s in summaries for t in s["arrivals"]["times"]]
    censored = [s["arrivals"]["horizon"] for s in summaries
                for _ in range(s["arrivals"]["goal_robots"] - s["arrivals"]["arrived"])]
    assert arrived and censored  # both kinds of robot, as SPEC intends
    truth = stats.ecdf(stats.CensoredData(uncensored=arrived, right=censored)).cdf
    assert curves["time"].tolist() == truth.quantiles.tolist()
    assert curves["fraction"].to_numpy() == pytest.approx(truth.probabilities, abs=1e-12)
    assert set(curves["runs"]) == {3} and set(curves["robots"]) == {6}
    assert set(curves["arrived"]) == {len(arrived)} and set(curves["horizon"]) == {4.0}
    assert set(curves["parameters"]) == {"robots=2, distance=1.0"}


def test_load_battery_and_one_run_of_it(battery):
    again = mimics.load_battery(battery.folder)
    assert again.table["id"].tolist() == battery.table["id"].tolist()
    run = again.run(2)
    assert run.summary["seed"] == 2 and len(run.trajectory) > 0
    assert "<table" in again._repr_html_() and "data:image/png" in again._repr_html_()
    with pytest.raises(MimicsError, match="no run #9"):
        again.run(9)


def test_not_a_battery_is_refused_in_one_line(tmp_path):
    with pytest.raises(MimicsError):
        mimics.load_battery(tmp_path)
    with pytest.raises(MimicsError, match="expected a battery file"):
        mimics.run_battery(42, tmp_path / "x")
