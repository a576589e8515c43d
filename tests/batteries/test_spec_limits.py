"""Battery files with finite but enormous numbers or wrong types: one line naming the file,
the key and what was expected (never a run that fails later, blaming the algorithm)."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.batteries.spec import load_battery
from mimics.interfaces.cli import main
from mimics.world.errors import MimicsError
from mimics.world.limits import MAX_STEPS, MAX_TIME, MAX_WALL_SECONDS

HEAD = '[battery]\nalgorithms = ["go_to_goal"]\n'
LINE = '\n[[scenarios]]\nname = "line"\nrobots = 2\n'


@pytest.mark.parametrize(("line", "key"), [
    ("time = 1e300", "time"), ("time = 1e308", "time"), ("time = 1e12", "time"),
    ("time = true", "time"), ('time = "60"', "time"), ("time = [60.0]", "time"),
    ("timeout = 1e300", "timeout"), ("timeout = false", "timeout"),
    ("timeout = {a = 1}", "timeout"), ("record_every = 100000000000000000", "record_every"),
    ("record_every = true", "record_every"), ('seeds = "1,2"', "seeds"),
    ("seeds = [1, true]", "seeds"), ("seeds = [[]]", "seeds"), ("seeds = []", "seeds"),
    ('policy = ["abort"]', "policy"), ('robot_logs = {on = 1}', "robot_logs"),
    ("name = [1]", "name"), ("record_scans = 1", "record_scans"),
])
def test_battery_keys_refuse_enormous_numbers_and_wrong_types(tmp_path: Path, line: str,
                                                              key: str) -> None:
    path = tmp_path / "b.toml"
    path.write_text(f"{HEAD}{line}{LINE}")
    with pytest.raises(MimicsError) as error:
        load_battery(path)
    message = str(error.value)
    assert message.startswith(f"{path}: [battery] {key}: expected"), message
    assert "\n" not in message


@pytest.mark.parametrize(("line", "key"), [
    ("robots = 0", "robots"), ("robots = 100000000000000000000", "robots"),
    ("robots = true", "robots"), ('robots = "2"', "robots"), ("seed = -1", "seed"),
])
def test_scenario_counts_are_checked_in_the_file_not_in_each_run(tmp_path: Path, line: str,
                                                                 key: str) -> None:
    path = tmp_path / "b.toml"
    path.write_text(f'{HEAD}seeds = 1\n[[scenarios]]\nname = "line"\n{line}\n')
    with pytest.raises(MimicsError, match=rf"\[\[scenarios\]\] #1 \(line\): {key}"):
        load_battery(path)


@settings(max_examples=25, deadline=None, derandomize=True)
@given(time=st.floats(min_value=MAX_TIME * 1.0001, max_value=1.7e308),
       timeout=st.floats(min_value=MAX_WALL_SECONDS * 1.0001, max_value=1.7e308))
def test_every_time_past_the_limits_is_refused(time: float, timeout: float) -> None:
    from mimics.batteries.spec import spec_from_dict

    for key, value in (("time", time), ("timeout", timeout)):
        with pytest.raises(MimicsError, match=rf"\[battery\] {key}: expected a positive"):
            spec_from_dict({"battery": {"algorithms": ["go_to_goal"], key: value},
                            "scenarios": [{"name": "line"}]})


def test_the_limits_are_what_the_step_counter_holds() -> None:
    from mimics.world.limits import check_steps

    assert pytest.approx(MAX_STEPS * 0.1) == MAX_TIME
    assert check_steps(MAX_TIME, 0.1) == MAX_STEPS  # the longest run at the default dt fits


@pytest.mark.parametrize("seeds", ["1,,5", "1,", ",1", "1, ,2", "²"])
def test_battery_new_refuses_seed_lists_with_empty_items(
        seeds: str, tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))
    out = tmp_path / "b.toml"
    assert main(["battery", "new", "-a", "go_to_goal", "-s", "line", "--seeds", seeds,
                 "--no-input", "-o", str(out)]) == 2
    assert "--seeds" in capsys.readouterr().err
    assert not out.exists()


def test_battery_new_refuses_an_enormous_time(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))
    out = tmp_path / "b.toml"
    assert main(["battery", "new", "-a", "go_to_goal", "-s", "line", "--time", "1e12",
                 "--no-input", "-o", str(out)]) == 2
    assert "--time" in capsys.readouterr().err
    assert not out.exists()
