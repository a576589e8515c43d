"""The notebook API as a Python user expects it (issue 51): errors raise, run.scenario is a
Scenario, batteries take notebook functions and a second call, tables fit a cell."""

from __future__ import annotations

import math
import traceback
from pathlib import Path

import distributed
import numpy as np
import pytest

import mimics
from mimics.batteries.metrics import run_digest
from mimics.interfaces.notebook.pickled import algorithm_ref, without_pickles
from mimics.world.errors import MimicsError

BAD_FILE = """\
import math

def step(robot):
    x, y, theta = robot.pose
    return math.sqrt(-1.0), theta
"""


def test_a_failing_file_algorithm_raises_with_its_file_and_line(tmp_path: Path) -> None:
    algo = tmp_path / "bad_algo.py"
    algo.write_text(BAD_FILE)
    with pytest.raises(mimics.UserCodeError) as caught:
        mimics.simulate("line", str(algo), robots=2, time=1.0, seed=1)
    error = caught.value
    assert "ValueError in robot 0 at t=0 s" in str(error) and "bad_algo.py:5" in str(error)
    # the cause is the algorithm's own exception, its traceback the user's frames only
    cause = error.__cause__
    assert isinstance(cause, ValueError)
    frames = traceback.extract_tb(cause.__traceback__)
    assert [(Path(f.filename).name, f.lineno) for f in frames] == [("bad_algo.py", 5)]
    # the run is attached, recorded up to the failure
    assert error.run.status == "error" and error.run.error == error.run.summary["error"]
    assert error.run.trajectory.step.max() == error.run.summary["steps"] == 1


def test_on_error_record_returns_the_run_and_its_repr_shows_the_error_first_in_red() -> None:
    def step(robot):
        return robot.no_such_sensor, 0.0

    run = mimics.simulate("line", step, robots=2, time=1.0, seed=1, on_error="record")
    assert run.status == "error" and "AttributeError" in run.error
    page = run._repr_html_()
    error_at = page.index('class="mimics-error"')
    assert error_at < page.index("<table")  # before the summary table
    assert "color:#c00" in page[error_at:page.index(">", error_at)]
    assert "no_such_sensor" in page[error_at:page.index("<table")]
    with pytest.raises(MimicsError, match="on_error: expected 'raise' or 'record'"):
        mimics.simulate("line", step, robots=2, time=1.0, on_error="ignore")


def test_deactivate_policy_and_working_code_raise_nothing() -> None:
    def step(robot):
        if robot.id == 1:
            raise RuntimeError("robot 1 only")
        return 0.5, 0.0

    run = mimics.simulate("line", step, robots=3, time=0.5, seed=1, policy="deactivate")
    assert run.status == "time_limit" and run.summary["exceptions"] == 1


def test_run_scenario_is_the_scenario_after_simulate_as_after_load_run(tmp_path: Path) -> None:
    run = mimics.simulate("circle_swap", "go_to_goal", time=2.0, seed=3)
    loaded = mimics.load_run(run.save(tmp_path / "run"))
    for view in (run, loaded):
        assert isinstance(view.scenario, mimics.Scenario) and view.scenario.name == "circle_swap"
    # the first analysis: each robot's distance to its goal, at the start and at the end
    trajectory = run.trajectory
    first = trajectory[trajectory.step == 0].sort_values("robot")
    goals = run.scenario.goals
    start = np.hypot(first.x.to_numpy() - goals[:, 0], first.y.to_numpy() - goals[:, 1])
    np.testing.assert_allclose(start, run.result.start_goal_distance)
    np.testing.assert_array_equal(loaded.scenario.goals, goals)


@pytest.mark.parametrize("name", ["circle_swap", "corridor"])
def test_headings_are_in_minus_pi_to_pi_from_step_0(name: str) -> None:
    # both jitter headings near +-pi: some fell outside before the wrap
    starts = [mimics.load_scenario(name, seed=seed).stages[:, 2] for seed in range(20)]
    yaw = np.concatenate(starts)
    assert yaw.min() >= -math.pi and yaw.max() <= math.pi
    run = mimics.simulate(name, "go_to_goal", time=0.2, seed=7)
    theta = run.trajectory[run.trajectory.step == 0].theta
    assert theta.min() >= -math.pi and theta.max() <= math.pi


def test_a_wrapped_heading_is_the_same_direction_and_one_in_range_is_untouched() -> None:
    base = mimics.load_scenario("line", robots=3, seed=1)
    given = np.array([3.5, -3.5, math.pi])
    stages = base.stages.copy()
    stages[:, 2] = given
    from dataclasses import replace

    wrapped = replace(base, stages=stages).stages[:, 2]
    np.testing.assert_allclose(np.cos(wrapped), np.cos(given), atol=1e-12)
    np.testing.assert_allclose(np.sin(wrapped), np.sin(given), atol=1e-12)
    assert wrapped[2] == given[2]  # in range (pi itself too): bit for bit
    assert abs(wrapped[0]) <= math.pi and abs(wrapped[1]) <= math.pi


def _toward_goal(robot):
    x, y, _ = robot.pose
    gx, gy = robot.goal
    return 0.6, math.atan2(gy - y, gx - x)


def test_run_battery_takes_notebook_functions_and_a_second_call_continues(
        tmp_path: Path) -> None:
    def step(robot):  # local: pickled by value, as a notebook cell's function
        return _toward_goal(robot)

    class Cautious:
        def step(self, robot):
            speed, heading = _toward_goal(robot)
            return speed / 2, heading

    spec = {"battery": {"algorithms": [step, Cautious], "seeds": 2, "time": 1.0},
            "scenarios": [{"name": "line", "robots": 2}]}
    first = mimics.run_battery(spec, tmp_path / "b", workers=2, progress=False)
    assert first.counts == {"done": 4}
    table = first.table.sort_values(["algorithm", "seed"])
    assert sorted(set(table.algorithm)) == ["Cautious", "step"]
    # the workers ran the same code: the same digests as here
    for row in table.itertuples():
        algorithm = step if row.algorithm == "step" else Cautious
        here = mimics.simulate("line", algorithm, robots=2, time=1.0, seed=row.seed)
        assert row.digest == run_digest(here.summary())
    again = mimics.run_battery(spec, tmp_path / "b", workers=2, progress=False)
    assert again.result.finished == 0 and again.counts == {"done": 4}
    changed = {**spec, "battery": {**spec["battery"], "seeds": 3}}
    with pytest.raises(MimicsError, match=r"holds another battery \(different seeds\)") as err:
        mimics.run_battery(changed, tmp_path / "b", workers=2, progress=False)
    assert "--out" not in str(err.value) and "out=" in str(err.value)


def test_a_battery_interrupted_is_continued_by_the_same_call(tmp_path: Path) -> None:
    from mimics.batteries.store import BatteryStore

    spec = {"battery": {"algorithms": ["go_to_goal"], "seeds": 2, "time": 0.5},
            "scenarios": [{"name": "line", "robots": 2}]}
    mimics.run_battery(spec, tmp_path / "b", workers=1, progress=False)
    store = BatteryStore.open(tmp_path / "b")  # as if killed before the second run ended
    with store.db:
        store.db.execute("UPDATE runs SET state = 'pending' WHERE id = 2")
    store.close()
    again = mimics.run_battery(spec, tmp_path / "b", workers=1, progress=False)
    assert again.result.finished == 1 and again.counts == {"done": 2}


def test_a_changed_notebook_function_is_another_battery() -> None:
    def step(robot):
        return 0.5, 0.0

    same = algorithm_ref(step)

    def step(robot):  # defined again, changed, as a cell run again
        return 0.6, 0.0

    assert without_pickles(same) != without_pickles(algorithm_ref(step))
    assert without_pickles(same).startswith("pickle:step:")


def test_a_folder_of_other_files_is_refused_in_python_words(tmp_path: Path) -> None:
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "notes.txt").write_text("mine")
    spec = {"battery": {"algorithms": ["go_to_goal"], "seeds": 1, "time": 0.5},
            "scenarios": [{"name": "line", "robots": 1}]}
    with pytest.raises(MimicsError, match="holds other files") as err:
        mimics.run_battery(spec, tmp_path / "b", workers=1, progress=False)
    assert "--out" not in str(err.value)


def test_dask_workers_run_notebook_functions(tmp_path: Path) -> None:
    def step(robot):
        return _toward_goal(robot)

    spec = {"battery": {"algorithms": [step], "seeds": [4], "time": 1.0},
            "scenarios": [{"name": "line", "robots": 2}]}
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        battery = mimics.run_battery(spec, tmp_path / "b", dask=cluster.scheduler_address,
                                     progress=False)
    row = battery.table.iloc[0]
    assert battery.counts == {"done": 1} and row.worker.startswith("tcp://127.0.0.1:")
    here = mimics.simulate("line", step, robots=2, time=1.0, seed=4)
    assert row.digest == run_digest(here.summary())


def test_tables_show_a_default_set_of_columns_and_all_on_request(tmp_path: Path) -> None:
    spec = {"battery": {"algorithms": ["go_to_goal", "wall_aware"], "seeds": 2, "time": 1.0},
            "scenarios": [{"name": "line", "robots": 2}]}
    battery = mimics.run_battery(spec, tmp_path / "b", workers=2, progress=False)
    summary, everything = battery.summary(), battery.summary(columns="all")
    assert len(summary.columns) <= 10 < len(everything.columns)
    assert summary.equals(everything[list(summary.columns)])
    intervals = battery.intervals()
    assert list(intervals.columns[-6:]) == ["success", "success_low", "success_high",
                                            "time_to_goal", "time_to_goal_low",
                                            "time_to_goal_high"]
    assert len(battery.intervals(columns="all").columns) > len(intervals.columns)
    picked = battery.intervals(["collisions"], columns=["algorithm", "collisions_n"])
    assert list(picked.columns) == ["algorithm", "collisions_n"]
    compared = battery.compare()
    assert "wall_time" not in set(compared.metric) and len(compared.columns) <= 10
    with pytest.raises(MimicsError, match="summary: columns: no column 'nope'"):
        battery.summary(columns=["nope"])
    with pytest.raises(MimicsError, match="compare: columns: expected None, 'all'"):
        battery.compare(columns="some")
