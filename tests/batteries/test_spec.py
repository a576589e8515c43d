"""Battery files: expansion into runs, and one-line errors naming the file and the key."""

from __future__ import annotations

from pathlib import Path

import pytest

from mimics.batteries.spec import BatterySpec, battery_toml, load_battery, spec_from_dict
from mimics.world.errors import MimicsError
from tests.batteries.helpers import fault, write_battery
from tests.file_errors import file_error


def test_runs_are_every_combination_in_file_order() -> None:
    spec = spec_from_dict({
        "battery": {"algorithms": ["go_to_goal", "wall_aware"], "seeds": [3, 1]},
        "scenarios": [{"name": "line", "robots": [1, 10], "spacing": 2.0},
                      {"name": "line", "distance": 5.0}]})
    runs = spec.runs()
    assert len(runs) == 2 * (2 + 1) * 2
    first = runs[0]
    assert (first.algorithm, first.scenario, first.params, first.seed) == (
        "go_to_goal", "line", {"robots": 1, "spacing": 2.0}, 3)
    assert first.label == "robots=1, spacing=2.0"
    assert [r.seed for r in runs[:4]] == [3, 1, 3, 1]
    assert runs[6].algorithm == "wall_aware"
    assert first.folder_name(7) == "00007-go_to_goal-line-robots=1-spacing=2.0-s3"
    assert len({(r.algorithm, r.label, r.seed) for r in runs}) == len(runs)


def test_a_seed_count_means_seeds_one_to_n_and_defaults_apply() -> None:
    spec = spec_from_dict({"battery": {"algorithms": "go_to_goal", "seeds": 30},
                           "scenarios": [{"name": "line"}]})
    assert spec.seeds == tuple(range(1, 31))
    assert (spec.time, spec.timeout, spec.policy, spec.robot_logs) == (None, 300.0, "abort",
                                                                       "off")
    assert BatterySpec.from_json(spec.to_json()) == spec


def test_paths_are_relative_to_the_battery_file(tmp_path: Path) -> None:
    algos = tmp_path / "my_algos"
    algos.mkdir()
    (algos / "avoid.py").write_text((Path(fault("nan"))).read_text())
    path = tmp_path / "b.toml"
    path.write_text('[battery]\nalgorithms = ["go_to_goal", "my_algos/avoid.py"]\n'
                    '[[scenarios]]\nname = "line"\nrobots = 1\n')
    spec = load_battery(path)
    assert spec.algorithms[1] == str((algos / "avoid.py").resolve())
    assert [r.algorithm for r in spec.runs()] == ["go_to_goal", "avoid"]


@pytest.mark.parametrize(("text", "expected"), [
    ("[battery\nalgorithms = 1", "not valid TOML"),
    ('[battery]\nalgorithms = ["go_to_goal"]\nseed = 3\n[[scenarios]]\nname = "line"',
     "[battery]: unknown key 'seed'"),
    ('[battery]\nalgorithms = ["go_to_goal"]\n[[scenarios]]\nname = "line"\n[extra]\na = 1',
     "the top level: unknown key 'extra'"),
    ('[battery]\nalgorithms = ["no_such_algo"]\n[[scenarios]]\nname = "line"',
     "unknown algorithm 'no_such_algo'"),
    ('[battery]\nalgorithms = ["missing.py"]\n[[scenarios]]\nname = "line"', "does not exist"),
    ('[battery]\nalgorithms = ["go_to_goal"]\n[[scenarios]]\nname = "nowhere"',
     "unknown scenario 'nowhere'"),
    ('[battery]\nalgorithms = ["go_to_goal"]\n[[scenarios]]\nname = "line"\nrobot = [1, 2]',
     "has no parameter 'robot'"),
    ('[battery]\nalgorithms = ["go_to_goal"]\n[[scenarios]]\nname = "line"\nrobots = "ten"',
     "robots: expected a value like the default 60"),
    ('[battery]\nalgorithms = ["go_to_goal"]\n[[scenarios]]\nname = "line"\nrobots = []',
     "robots: an empty list sweeps nothing"),
    ('[battery]\nalgorithms = ["go_to_goal"]\nseeds = [1, 1]\n[[scenarios]]\nname = "line"',
     "seeds: a seed is listed twice"),
    ('[battery]\nalgorithms = ["go_to_goal"]\nseeds = 0\n[[scenarios]]\nname = "line"',
     "seeds: expected a count"),
    ('[battery]\nalgorithms = ["go_to_goal"]\npolicy = "ignore"\n[[scenarios]]\nname = "line"',
     "policy: expected"),
    ('[battery]\nalgorithms = ["go_to_goal"]\ntimeout = -1\n[[scenarios]]\nname = "line"',
     "timeout: expected a positive number"),
    ('[battery]\nalgorithms = ["go_to_goal"]\ntime = "long"\n[[scenarios]]\nname = "line"',
     "time: expected a positive number"),
    ('[battery]\nalgorithms = ["go_to_goal"]', "missing [[scenarios]]"),
    ('[[scenarios]]\nname = "line"', "missing [battery]"),
    ('[battery]\nalgorithms = ["go_to_goal", "go_to_goal"]\n[[scenarios]]\nname = "line"',
     "listed twice"),
])
def test_bad_battery_files_are_one_line_naming_file_and_key(tmp_path: Path, text: str,
                                                             expected: str) -> None:
    assert expected in file_error(load_battery, tmp_path / "bad.toml", text)


def test_toml_scenarios_are_checked_by_building_each_point(tmp_path: Path) -> None:
    scenario = tmp_path / "s.toml"
    scenario.write_text(
        'map = { segments = [[0.0, 0.0, 10.0, 0.0]], bounds = [-1.0, -1.0, 11.0, 5.0] }\n'
        'robots = [{ generator = "line", type = "Pioneer2DX", count = 3, start = [1.0, 1.0],'
        ' step = [0.0, 1.0], goal_offset = [8.0, 0.0] }]\n')
    good = write_battery(tmp_path / "good.toml", ["go_to_goal"],
                         scenarios=[{"name": "s.toml", "robots": [1, 2]}])
    assert len(load_battery(good).runs()) == 2
    bad = write_battery(tmp_path / "bad.toml", ["go_to_goal"],
                        scenarios=[{"name": "s.toml", "colour": "red"}])
    with pytest.raises(MimicsError, match="colour"):
        load_battery(bad)


def test_battery_toml_round_trips(tmp_path: Path) -> None:
    text = battery_toml(["go_to_goal"], [{"name": "line", "robots": [1, 2]}], seeds=[4, 5],
                        time=3.0, timeout=20.0, policy="deactivate")
    path = tmp_path / "b.toml"
    path.write_text(text)
    spec = load_battery(path)
    assert (spec.seeds, spec.time, spec.timeout, spec.policy) == ((4, 5), 3.0, 20.0,
                                                                  "deactivate")
    assert len(spec.runs()) == 4


@pytest.mark.parametrize(("scenarios", "expected"), [
    ('[[scenarios]]\nname = "line"\nrobots = [1, 10]\n[[scenarios]]\nname = "line"\n'
     'robots = 10\n',
     "[[scenarios]] #2: robots = 10 repeats runs of [[scenarios]] #1 (robots = [1, 10]): "
     "robots = 10; give each point once"),
    ('[[scenarios]]\nname = "line"\nrobots = 4\nspacing = [1.0, 2.0]\n[[scenarios]]\n'
     'name = "line"\nrobots = [4, 8]\nspacing = 2.0\n',
     "repeats runs of [[scenarios]] #1 (robots = 4, spacing = [1.0, 2.0]): robots = 4, "
     "spacing = 2.0"),
])
def test_a_point_given_fixed_and_in_a_sweep_is_refused_naming_both_tables(
        tmp_path: Path, scenarios: str, expected: str) -> None:
    path = tmp_path / "twice.toml"
    path.write_text(f'[battery]\nalgorithms = ["go_to_goal"]\n{scenarios}')
    with pytest.raises(MimicsError) as error:
        load_battery(path)
    assert expected in str(error.value) and "\n" not in str(error.value)


def test_the_same_scenario_with_other_points_is_accepted(tmp_path: Path) -> None:
    path = tmp_path / "two.toml"
    path.write_text('[battery]\nalgorithms = ["go_to_goal"]\n[[scenarios]]\nname = "line"\n'
                    'robots = [1, 10]\n[[scenarios]]\nname = "line"\nrobots = [2, 20]\n')
    assert [r.params["robots"] for r in load_battery(path).runs()] == [1, 10, 2, 20]


def test_battery_time_and_a_scenario_time_limit_are_refused_naming_both(
        tmp_path: Path) -> None:
    path = tmp_path / "time.toml"
    path.write_text('[battery]\nalgorithms = ["go_to_goal"]\ntime = 10\n[[scenarios]]\n'
                    'name = "obstacle_room"\ntime_limit = [5.0, 20.0]\n')
    with pytest.raises(MimicsError, match=r"\[battery\] time = 10 and \[\[scenarios\]\] #1 "
                                          r"\(obstacle_room\) time_limit = \[5.0, 20.0\]"):
        load_battery(path)
