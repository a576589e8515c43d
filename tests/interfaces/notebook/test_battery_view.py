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

import mimics
from mimics.batteries.report import aggregate, runs_table
from mimics.interfaces.notebook.html import png_bytes
from mimics.interfaces.plots import battery_plots
from mimics.world.errors import MimicsError

SPEC = {"battery": {"algorithms": ["go_to_goal"], "seeds": 3, "time": 1.0},
        "scenarios": [{"name": "line", "robots": 2}]}


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
    summary = battery.summary()
    expected = aggregate(runs_table(battery.folder))
    assert len(summary) == 1 and summary.iloc[0]["runs"] == 3
    assert summary.equals(expected)
    tables = battery.report_tables()
    assert set(tables) == {"runs", "failures", "aggregate", "intervals", "comparison"}
    assert tables["failures"].empty
    # one algorithm: nothing to compare; the intervals rest on the 3 done runs
    assert battery.compare().empty and battery.intervals()["done"].tolist() == [3]


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
    with pytest.raises(MimicsError, match="expected one of"):
        battery.plot("pie")


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
