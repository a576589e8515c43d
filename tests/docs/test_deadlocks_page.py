"""The how-to "Deadlocks and livelocks": its command runs as written (issue 54: the page's
``--param deadlock_window=20`` on a built-in scenario was refused), and the stall settings it
lists are parameters of every built-in scenario."""

from __future__ import annotations

import re
import shlex
import tomllib
from pathlib import Path

import pytest

from mimics.catalog import STALL_SETTINGS, load_scenario, scenario_parameters
from mimics.interfaces.cli import main
from mimics.scenarios import __path__ as scenario_folders
from mimics.world.errors import ScenarioError
from mimics.world.scenario import Settings

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "how-to" / "deadlocks.md"
BUILT_IN = sorted(p.stem for p in Path(scenario_folders[0]).glob("*.py")
                  if not p.stem.startswith("_"))


def page_command() -> list[str]:
    (block,) = re.findall(r"^```\n(mimics run .*?)\n```", PAGE.read_text(), re.M)
    return shlex.split(block)


def test_the_pages_command_runs_with_the_settings_it_gives(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    words = page_command()
    monkeypatch.chdir(tmp_path)
    assert main([*words[1:], "--time", "0.5", "--robot-logs", "off", "--out", "run"]) == 0
    ran = tomllib.loads((tmp_path / "run" / "scenario.toml").read_text())
    given = dict(word.split("=") for word in words[words.index("--param") + 1::2])
    for key, value in given.items():
        assert ran["settings"][key] == float(value), key


def test_the_page_lists_exactly_the_stall_settings_every_scenario_takes() -> None:
    table = set(re.findall(r"^\| `(\w+)` \|", PAGE.read_text(), re.M))
    assert table == set(STALL_SETTINGS)


@pytest.mark.parametrize("name", BUILT_IN)
def test_every_built_in_scenario_takes_the_stall_settings(name: str) -> None:
    defaults = scenario_parameters(name)
    for key in STALL_SETTINGS:
        assert defaults[key] == getattr(Settings(), key), (name, key)


def test_a_stall_setting_given_as_a_parameter_reaches_the_settings() -> None:
    built = load_scenario("line", robots=2, deadlock_window=20, livelock_window=60.0,
                          deactivate_on_deadlock=False)
    assert built.settings.deadlock_window == 20
    assert built.settings.livelock_window == 60.0
    assert built.settings.deactivate_on_deadlock is False
    assert built.parameters["deadlock_window"] == 20  # recorded with the run's parameters
    assert load_scenario("line", robots=2).settings.deadlock_window == 10.0


def test_a_bad_stall_setting_is_one_error_naming_it() -> None:
    with pytest.raises(ScenarioError, match="deadlock_window: expected a positive number"):
        load_scenario("line", robots=2, deadlock_window=-1.0)
    with pytest.raises(ScenarioError, match="has no parameter 'deadlock_windw'"):
        load_scenario("line", robots=2, deadlock_windw=20.0)


def test_a_battery_file_sets_the_deadlock_rule_on_a_built_in_scenario() -> None:
    from mimics.batteries.spec import spec_from_dict

    spec = spec_from_dict({"battery": {"name": "b", "algorithms": ["go_to_goal"], "seeds": 1},
                           "scenarios": [{"name": "corridor", "deadlock_window": [10.0, 20.0]}]})
    (entry,) = spec.scenarios
    windows = sorted(point["deadlock_window"] for point in entry.points())
    assert windows == [10.0, 20.0]
    built = load_scenario("corridor", robots=2, **{"deadlock_window": windows[1]})
    assert built.settings.deadlock_window == 20.0
