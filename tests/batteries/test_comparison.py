"""Paired comparisons, per-cell intervals and identical-seed warnings on per-run tables of
known content (synthetic tables and a real battery), checked against hand computations."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats as scipy_stats
from typer.testing import CliRunner

from mimics.batteries import run_battery, runs_table
from mimics.batteries.comparison import (
    cell_intervals,
    identical_seed_warnings,
    paired_comparison,
    seed_ranges,
)
from mimics.batteries.metrics import row_value, run_digest, summary_metrics
from mimics.world.errors import MimicsError
from tests.batteries.helpers import fault, write_battery


def synthetic(rows: list[tuple[str, int, float, float]], scenario: str = "line",
              label: str = "robots=2") -> pd.DataFrame:
    """A per-run table: (algorithm, seed, time_to_goal, success) per run, all done."""
    return pd.DataFrame([{"algorithm": a, "scenario": scenario, "parameters": label,
                          "seed": s, "state": "done", "time_to_goal": t, "success": ok,
                          "collisions": 0.0, "digest": f"o:{a}{s}"} for a, s, t, ok in rows])


def test_paired_comparison_against_a_hand_computation() -> None:
    base = [3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    other = [3.5, 4.1, 5.9, 6.2, 7.8, 8.3, 10.0]  # differences 0.5 0.1 0.9 0.2 0.8 0.3 1.0
    table = synthetic([("a", s, t, 1.0) for s, t in enumerate(base, 1)]
                      + [("b", s, t, 1.0) for s, t in enumerate(other, 1)]
                      + [("b", 99, 1.0, 1.0)])  # a seed the baseline did not run: no pair
    found = paired_comparison(table, "a", ["time_to_goal", "success"]).set_index("metric")
    row = found.loc["time_to_goal"]
    differences = [0.5, 0.1, 0.9, 0.2, 0.8, 0.3, 1.0]
    mean = sum(differences) / 7  # 3.8 / 7
    s = math.sqrt(sum((d - mean) ** 2 for d in differences) / 6)
    half = 2.4469118511449692 * s / math.sqrt(7)  # t(0.975, 6), from tables
    assert (row["algorithm"], row["baseline"], row["pairs"]) == ("b", "a", 7)
    assert row["mean_difference"] == pytest.approx(3.8 / 7, rel=1e-12)
    assert (row["ci95_low"], row["ci95_high"]) == pytest.approx((mean - half, mean + half),
                                                                rel=1e-9)
    # all seven differences positive: the exact two-sided p-value is 2 / 2^7
    assert row["p_value"] == pytest.approx(2 / 128, rel=1e-12)
    assert row["p_value"] == pytest.approx(scipy_stats.wilcoxon(differences).pvalue)
    same = found.loc["success"]  # seven pairs (1, 1): Newcombe's interval, no McNemar test
    assert same["mean_difference"] == 0.0 and math.isnan(same["p_value"])
    assert same["ci95_low"] < 0.0 < same["ci95_high"]
    assert same["note"] == "no discordant pairs among 7: nothing for McNemar's test to weigh"


def test_pairs_are_within_one_scenario_and_parameter_point() -> None:
    table = pd.concat([synthetic([("a", 1, 1.0, 1.0), ("b", 1, 2.0, 1.0)], label="robots=2"),
                       synthetic([("a", 1, 5.0, 1.0), ("b", 1, 9.0, 1.0)], label="robots=4")])
    found = paired_comparison(table, metrics=["time_to_goal"]).set_index("parameters")
    assert found.loc["robots=2", "mean_difference"] == 1.0
    assert found.loc["robots=4", "mean_difference"] == 4.0
    assert set(found["baseline"]) == {"a"}  # the first algorithm by default
    with pytest.raises(MimicsError, match="--baseline 'c': not an algorithm"):
        paired_comparison(table, "c")
    with pytest.raises(MimicsError, match="--metric 'speed': unknown metric"):
        paired_comparison(table, "a", ["speed"])


def test_cell_intervals_are_t_for_means_and_wilson_for_proportions() -> None:
    table = synthetic([("a", s, t, ok) for s, t, ok in
                       [(1, 2.0, 1.0), (2, 4.0, 1.0), (3, 9.0, 0.0), (4, math.nan, 0.0)]])
    row = cell_intervals(table, ["time_to_goal", "success"]).iloc[0]
    # Hall's skewness-corrected t (stats.skew_corrected_interval), by hand: deviations
    # -3, -1, 4; m2 = 26/3, m3 = 12; G1 = m3 / m2^1.5 * sqrt(3 * 2) / 1; s = sqrt(13)
    q = 0.95 / math.sqrt(2 * 0.975 * 0.025)  # Student's t(2) quantile in closed form
    skew = 12.0 / (26.0 / 3.0) ** 1.5 * math.sqrt(6.0)
    a, b = skew / (3 * math.sqrt(3.0)), skew / (6 * math.sqrt(3.0))
    upper_t = (math.cbrt(1 + 3 * a * (-q - b)) - 1) / a  # T with g(T) = -q
    assert row["time_to_goal"] == 5.0 and row["time_to_goal_n"] == 3  # NaN left out
    assert row["time_to_goal_high"] == pytest.approx(
        5.0 - upper_t * math.sqrt(13.0) / math.sqrt(3.0), rel=1e-9)
    z = 1.959963984540054  # Wilson, 2 of 4
    centre = (0.5 + z * z / 8) / (1 + z * z / 4)
    width = z / (1 + z * z / 4) * math.sqrt(0.25 / 4 + z * z / 64)
    assert row["success"] == 0.5
    assert (row["success_low"], row["success_high"]) == pytest.approx(
        (centre - width, centre + width), rel=1e-12)


def test_identical_seeds_are_named_with_their_cell() -> None:
    table = synthetic([("go_to_goal", s, 4.4, 1.0) for s in range(0, 30)]
                      + [("wall_aware", s, 4.0 + s, 1.0) for s in range(1, 6)],
                      label="robots=5")
    table.loc[table["algorithm"] == "go_to_goal", "digest"] = "t:same"
    table.loc[(table["algorithm"] == "wall_aware") & (table["seed"].isin([2, 3])),
              "digest"] = "t:twice"
    lines = identical_seed_warnings(table, {"line": "randomize start poses (random_yaw)"})
    assert lines == [
        "seeds 0-29 of go_to_goal x line (robots=5) gave identical runs: the seed changes "
        "nothing here; randomize start poses (random_yaw)",
        "seeds 2-3 of wall_aware x line (robots=5) gave identical runs: 2 of 5 seeds are "
        "copies of one run; randomize start poses (random_yaw)"]
    table["digest"] = [f"o:{k}" for k in range(len(table))]
    assert identical_seed_warnings(table) == []
    assert seed_ranges([7, 1, 2, 3, 9, 10]) == "1-3, 7, 9-10"


def summary(**extra: object) -> dict[str, object]:
    return {"status": "completed", "steps": 44, "sim_time": 4.4, "robots": 2,
            "reached_goal": 2, "collisions": 0, "time_to_goal": {"mean": 4.4, "min": 4.4,
                                                                 "max": 4.4},
            "path_length": {"mean": 3.0}, "path_efficiency": {"mean": None}, **extra}


def test_the_digest_reads_the_trajectory_digest_when_the_summary_has_one() -> None:
    plain = run_digest(summary())
    assert plain.startswith("o:") and plain == run_digest(summary())
    with_trajectory = run_digest(summary(trajectory_digest="ab12"))
    assert with_trajectory.startswith("t:")
    assert with_trajectory != run_digest(summary(trajectory_digest="ab13"))  # poses differ
    assert run_digest(summary(sim_time=4.5)) != plain  # outcomes differ
    assert run_digest(summary(wall_time=9.0)) == plain  # wall time is not an outcome
    assert summary_metrics(summary()) == {"time_to_goal": None, "time_to_goal_arrived": 4.4,
                                          "path_length": 3.0, "path_efficiency": None,
                                          "user_time": None}  # no arrivals: an older summary
    arrivals = {"goal_robots": 2, "arrived": 1, "horizon": 10.0, "times": [4.4],
                "restricted_mean": 7.2}
    found = summary_metrics(summary(arrivals=arrivals))
    assert (found["time_to_goal"], found["goal_robots"], found["horizon"],
            found["arrival_times"]) == (7.2, 2, 10.0, [4.4])


def test_row_values() -> None:
    row = {"state": "done", "robots": 3, "reached_goal": 2, "collisions": 1,
           "metrics": '{"time_to_goal": 8.5, "time_to_goal_arrived": 7.5, "path_length": null,'
                      ' "goal_robots": 3}'}
    assert row_value(row, "success") == 0.0 and row_value(row, "collisions") == 1.0
    assert row_value(row, "time_to_goal") == 8.5 and math.isnan(row_value(row, "path_length"))
    assert row_value(row, "time_to_goal_arrived") == 7.5
    failed = {**row, "state": "timeout"}  # brought no robot home; no finished-run metrics
    assert row_value(failed, "success") == 0.0 and row_value(failed, "reached_goal") == 0.0
    assert math.isnan(row_value(failed, "collisions"))
    assert math.isnan(row_value(failed, "time_to_goal"))
    assert math.isnan(row_value(failed, "success", count_failed=False))
    no_goal = {**row, "metrics": '{"goal_robots": 0}'}  # success does not apply: n/a
    assert math.isnan(row_value(no_goal, "success"))
    older = {**row, "metrics": '{"time_to_goal": 7.5}'}  # the mean over arrivals, then
    assert row_value(older, "time_to_goal_arrived") == 7.5
    assert math.isnan(row_value(older, "time_to_goal"))


def test_a_real_battery_compares_and_warns(tmp_path: Path) -> None:
    # over 4 s, a robot driving at a random speed covers 1 to 4 m; one standing still none
    path = write_battery(tmp_path / "b.toml", [fault("stand_still"), fault("random_speed")],
                         seeds=6, time=4.0, timeout=30.0,
                         scenarios=[{"name": "line", "robots": 1, "random_yaw": False}])
    run_battery(path, tmp_path / "out", workers=2, progress=False)
    table = runs_table(tmp_path / "out")
    assert table["path_length"].notna().all() and (table["success"] == 0.0).all()
    found = paired_comparison(table, "stand_still", ["path_length"]).iloc[0]
    mine = table.set_index(["algorithm", "seed"])["path_length"]
    differences = np.array([mine["random_speed", s] - mine["stand_still", s]
                            for s in range(1, 7)])
    assert (differences > 0.5).all() and len(set(differences)) == 6
    assert found["pairs"] == 6
    assert found["mean_difference"] == pytest.approx(differences.mean())
    assert found["p_value"] == pytest.approx(scipy_stats.wilcoxon(differences).pvalue)
    lines = identical_seed_warnings(table)
    # standing still from fixed start poses, the seed changes nothing; random_speed draws
    # its speed from it
    assert len(lines) == 1 and lines[0].startswith("seeds 1-6 of stand_still x line")

    from mimics.interfaces.cli.battery import app

    out = tmp_path / "cmp.csv"
    result = CliRunner().invoke(app, ["compare", str(tmp_path / "out"), "--metric",
                                      "path_length", "--csv", str(out)])
    assert result.exit_code == 0, result.output
    assert "Wilcoxon" in result.output and "Wilson" in result.output
    assert "gave identical" in result.stderr
    written = pd.read_csv(out)
    assert written.loc[0, "mean_difference"] == pytest.approx(differences.mean())
    bad = CliRunner().invoke(app, ["compare", str(tmp_path / "out"), "--metric", "speed"])
    assert bad.exit_code == 2 and "--metric 'speed'" in bad.stderr


def test_copies_of_one_pair_give_no_p_value() -> None:
    table = synthetic([("a", s, 3.0, 1.0) for s in range(1, 11)]
                      + [("b", s, 5.0, 1.0) for s in range(1, 11)])
    table.loc[table["algorithm"] == "a", "digest"] = "t:a"
    table.loc[table["algorithm"] == "b", "digest"] = "t:b"
    row = paired_comparison(table, "a", ["time_to_goal"]).iloc[0]
    # ten identical differences of 2.0 would give p = 2 / 2^10, but they are one observation
    assert row["mean_difference"] == 2.0 and (row["ci95_low"], row["ci95_high"]) == (2.0, 2.0)
    assert math.isnan(row["p_value"]) and "copies of one pair" in row["note"]
    table.loc[(table["algorithm"] == "b") & (table["seed"] > 5), "digest"] = "t:b2"
    table.loc[(table["algorithm"] == "b") & (table["seed"] > 5), "time_to_goal"] = 6.0
    row = paired_comparison(table, "a", ["time_to_goal"]).iloc[0]
    assert row["p_value"] == pytest.approx(2 / 1024)  # all ten differences positive
    assert "only 2 distinct pairs of runs among 10" in row["note"]
