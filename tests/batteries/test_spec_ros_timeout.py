"""A battery file's ``ros_timeout``: validated naming the field, stored with the spec."""

from __future__ import annotations

import pytest

from mimics.batteries.spec import BatterySpec, spec_from_dict
from mimics.world.errors import MimicsError

SCENARIOS = [{"name": "line", "robots": 2}]


def ros_battery(tmp_path, **battery):
    node = tmp_path / "node.py"
    node.write_text("# a rospy node\n")
    table = {"algorithms": [f"ros:{node} --robots {{robots}}"], **battery}
    return spec_from_dict({"battery": table, "scenarios": SCENARIOS}, base=tmp_path,
                          source=str(tmp_path / "battery.toml"))


def test_ros_timeout_is_kept_and_survives_the_database(tmp_path):
    spec = ros_battery(tmp_path, ros_timeout=2.5)
    assert spec.ros_timeout == 2.5
    assert BatterySpec.from_json(spec.to_json()).ros_timeout == 2.5
    assert ros_battery(tmp_path).ros_timeout is None


@pytest.mark.parametrize("value", [0, -1, "5", True, float("inf"), float("nan")])
def test_a_bad_ros_timeout_is_named(tmp_path, value):
    with pytest.raises(MimicsError, match=r"battery\.toml.*\[battery\] ros_timeout: expected a "
                                          r"positive number of wall-clock seconds "
                                          r"\(at most 4e\+06\)"):
        ros_battery(tmp_path, ros_timeout=value)


def test_ros_timeout_without_a_ros_algorithm_is_refused(tmp_path):
    with pytest.raises(MimicsError,
                       match=r"\[battery\] ros_timeout: only for ros: and ros2: algorithms"):
        spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "ros_timeout": 3},
                        "scenarios": SCENARIOS})
