"""Answers that hold up (issue 48): time to goal as time to an event, failed runs counted,
intervals no narrower than the data allow, many tests adjusted; checked against hand
computations, SciPy, and real batteries."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from rich.console import Console
from scipy import stats as scipy_stats

from mimics.algorithms import go_to_goal
from mimics.batteries import run_battery, runs_table
from mimics.batteries.comparison import cell_intervals, failed_runs_lines, paired_comparison
from mimics.batteries.evidence import battery_evidence
from mimics.batteries.printing import print_report
from mimics.engine.outcome import RunResult
from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.scenarios.line import scenario as line
from tests.batteries.helpers import fault, write_battery


def result(statuses: list[Status], goal_times: list[float], has_goal: list[bool],
           time_limit: float) -> RunResult:
    n = len(statuses)
    return RunResult("completed", "s", "a", 1, n, time_limit, 1.0, 10,
                     np.array(statuses), np.full(n, -2), np.array(goal_times), np.ones(n),
                     np.ones(n), np.zeros(n, bool), np.zeros(n, bool),
                     has_goal=np.array(has_goal), time_limit=time_limit)


def test_the_restricted_mean_counts_each_non_arrival_at_the_horizon() -> None:
    found = result([Status.REACHED_GOAL, Status.COLLIDED, Status.REACHED_GOAL, Status.ACTIVE,
                    Status.REMOVED, Status.ACTIVE],
                   [2.0, math.nan, 5.0, math.nan, math.nan, math.nan],
                   [True, True, True, True, True, False], 10.0).arrivals()
    # robots 0-3 have goals (4 is removed by an edit, 5 has none): (2 + 10 + 5 + 10) / 4
    assert found == {"goal_robots": 4, "arrived": 2, "horizon": 10.0, "times": [2.0, 5.0],
                     "restricted_mean": pytest.approx(27.0 / 4, rel=1e-15)}
    nobody = result([Status.ACTIVE], [math.nan], [False], 10.0).arrivals()
    assert nobody["goal_robots"] == 0 and nobody["restricted_mean"] is None


def test_a_real_run_reports_its_arrivals_and_horizon() -> None:
    done = Simulation(line(robots=2, distance=3.0, random_yaw=False), go_to_goal, seed=1,
                      time_limit=30.0).run()
    arrivals = done.summary()["arrivals"]
    times = sorted(done.goal_time.tolist())
    assert arrivals["arrived"] == 2 and arrivals["times"] == times
    assert arrivals["restricted_mean"] == pytest.approx(np.mean(times), rel=1e-12)
    short = Simulation(line(robots=2, distance=3.0, random_yaw=False), go_to_goal, seed=1,
                       time_limit=1.0).run().summary()["arrivals"]
    assert (short["arrived"], short["horizon"], short["restricted_mean"]) == (0, 1.0, 1.0)
    assert short["times"] == []


def runs(algorithm: str, arrivals: list[list[float]], horizon: float, robots: int
         ) -> list[dict[str, object]]:
    """Per-run rows from the arrival times of each run's robots (the rest never arrived)."""
    rows = []
    for seed, times in enumerate(arrivals, 1):
        restricted = (sum(times) + horizon * (robots - len(times))) / robots
        rows.append({"algorithm": algorithm, "scenario": "s", "parameters": "", "seed": seed,
                     "state": "done", "time_to_goal": restricted,
                     "time_to_goal_arrived": np.mean(times) if times else math.nan,
                     "success": float(len(times) == robots), "goal_robots": robots,
                     "digest": f"t:{algorithm}{seed}"})
    return rows


def test_conditional_times_reverse_the_sign_the_restricted_mean_keeps() -> None:
    # the careful algorithm brings its 2 robots home at 30 s and 32 s in every run; the
    # hasty one is home at 20 s when it arrives at all, and deadlocks on 7 seeds of 10
    careful = [[30.0 + 0.1 * k, 32.0] for k in range(10)]
    hasty = [[20.0 + 0.1 * k, 21.0] if k < 3 else [20.0 + 0.1 * k] for k in range(10)]
    table = pd.DataFrame(runs("careful", careful, 100.0, 2) + runs("hasty", hasty, 100.0, 2))
    found = paired_comparison(table, "careful", ["time_to_goal", "time_to_goal_arrived"]
                              ).set_index("metric")
    conditional = found.loc["time_to_goal_arrived"]
    assert conditional["mean_difference"] < -10.0  # "faster", on the survivors
    assert conditional["note"].startswith("conditional: only the 10 of 10 pairs")
    # by hand: hasty's restricted means minus careful's, pair by pair
    differences = [(sum(h) + 100.0 * (2 - len(h))) / 2 - sum(c) / 2
                   for h, c in zip(hasty, careful, strict=True)]
    restricted = found.loc["time_to_goal"]
    assert restricted["mean_difference"] == pytest.approx(np.mean(differences), rel=1e-12)
    assert restricted["mean_difference"] > 0 and restricted["ci95_low"] > 0  # slower
    assert restricted["p_value"] == pytest.approx(scipy_stats.wilcoxon(differences).pvalue)


def test_a_success_difference_is_never_zero_width_and_uses_mcnemar() -> None:
    table = pd.DataFrame(runs("a", [[1.0]] * 20, 9.0, 1) + runs("b", [[]] * 20, 9.0, 1))
    row = paired_comparison(table, "b", ["success"]).iloc[0]
    assert row["mean_difference"] == 1.0 and row["ci95_high"] == 1.0
    assert row["ci95_low"] < 0.85  # the cells' own Wilson intervals are [0.84, 1] and [0, 0.16]
    assert row["p_value"] == pytest.approx(scipy_stats.binomtest(20, 20, 0.5).pvalue)
    assert row["test"] == "McNemar exact"


def test_holm_adjusts_the_p_values_shown() -> None:
    rng = np.random.default_rng(3)
    rows = []
    for cell in range(4):
        a = runs("a", [[float(t)] for t in rng.uniform(5, 9, 12)], 60.0, 1)
        b = runs("b", [[float(t) + cell * 0.3] for t in rng.uniform(5, 9, 12)], 60.0, 1)
        for row in a + b:
            row["parameters"] = f"k={cell}"
        rows += a + b
    found = paired_comparison(pd.DataFrame(rows), "a", ["time_to_goal"])
    raw = found["p_value"].to_numpy()
    order = np.argsort(raw)
    m = len(raw)
    holm = np.minimum(1.0, np.maximum.accumulate((m - np.arange(m)) * raw[order]))
    expected = np.empty(m)
    expected[order] = holm
    assert found["p_adjusted"].to_numpy() == pytest.approx(expected, rel=1e-12)
    none = paired_comparison(pd.DataFrame(rows), "a", ["time_to_goal"], adjust="none")
    assert (none["p_adjusted"] == none["p_value"]).all()


def test_failed_runs_count_and_are_named(tmp_path: Path) -> None:
    path = write_battery(tmp_path / "b.toml", ["go_to_goal", fault("fail_some_seeds")],
                         seeds=12, time=12.0, timeout=60.0,
                         scenarios=[{"name": "line", "robots": 2, "distance": 3.0,
                                     "random_yaw": False}])
    run_battery(path, tmp_path / "out", workers=2, progress=False)
    table = runs_table(tmp_path / "out")
    flaky = table[table["algorithm"] == "fail_some_seeds"]
    failed = flaky[flaky["state"] == "error"]
    done = flaky[flaky["state"] == "done"]
    assert 0 < len(failed) < 12 and len(failed) + len(done) == 12
    assert (done["success"] == 1.0).all()  # every run that finished brought its robots home
    cell = cell_intervals(table, ["success", "time_to_goal"]).set_index("algorithm").loc[
        "fail_some_seeds"]
    assert (cell["runs"], cell["done"], cell["failed"]) == (12, len(done), len(failed))
    assert cell["success"] == pytest.approx(len(done) / 12)  # failures count as 0
    assert cell["success_n"] == 12 and cell["time_to_goal_n"] == len(done)
    old = cell_intervals(table, ["success"], exclude_failed=True).set_index("algorithm")
    assert old.loc["fail_some_seeds", "success"] == 1.0  # the old answer, on purpose only
    row = paired_comparison(table, "go_to_goal", ["success"]).iloc[0]
    assert row["pairs"] == 12 and row["mean_difference"] == pytest.approx(-len(failed) / 12)
    assert row["p_value"] == pytest.approx(scipy_stats.binomtest(0, len(failed)).pvalue)
    seeds = sorted(int(s) for s in failed["seed"])
    (line_,) = failed_runs_lines(table)
    assert line_.startswith(f"fail_some_seeds x line (robots=2, distance=3.0, random_yaw=False):"
                            f" {len(failed)} of 12 runs failed (error {len(failed)}), seeds")
    assert str(seeds[0]) in line_
    evidence = battery_evidence(tmp_path / "out")
    assert evidence.primary == "success" and evidence.metrics[0] == "success"
    assert evidence.failed == [line_]
    assert "wall_time" not in set(evidence.comparison["metric"])  # a cost, not an outcome
    assert list(evidence.costs["algorithm"]) == ["go_to_goal", "fail_some_seeds"]
    printed = io.StringIO()
    print_report(evidence, Console(file=printed, width=300), runs=False)
    text = printed.getvalue()
    assert text.index("failed: fail_some_seeds") < text.index("Per cell")  # named first
    arrivals = next(line for line in text.splitlines()
                    if "go_to_goal" in line and "/ 24" in line)  # 12 runs x 2 robots
    # the goals are 3 m away at about 1 m/s: every robot is home by half the 12 s horizon
    assert "24 / 24" in arrivals and "1.00 (6 s)" in arrivals


def test_success_does_not_apply_where_no_robot_has_a_goal(tmp_path: Path) -> None:
    path = write_battery(tmp_path / "b.toml", ["dispersion", "go_to_goal"], seeds=3, time=1.0,
                         scenarios=[{"name": "swarm", "robots": 4}])
    run_battery(path, tmp_path / "out", workers=2, progress=False)
    evidence = battery_evidence(tmp_path / "out")
    assert evidence.primary == ""
    cells = evidence.intervals
    assert cells["success"].isna().all() and cells["time_to_goal"].isna().all()
    assert (cells["collisions_n"] == 3).all()
