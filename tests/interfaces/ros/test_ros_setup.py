"""How the bridge finds ROS, and its one-line errors before any ROS node starts."""

from __future__ import annotations

import subprocess
import sys

from mimics.interfaces.cli.program import main
from mimics.interfaces.ros import system_ros
from tests.system_packages import require

PROBE = """
import sys
from mimics.interfaces.ros.system_ros import SYSTEM_DIST_PACKAGES, add_system_packages
assert str(SYSTEM_DIST_PACKAGES) not in sys.path
assert add_system_packages()
import rospy, yaml
print(sys.path.index(str(SYSTEM_DIST_PACKAGES)) == len(sys.path) - 1)
print(rospy.__file__.startswith(str(SYSTEM_DIST_PACKAGES)))
print(yaml.__file__.startswith(sys.prefix))
"""


def test_system_packages_are_appended_after_the_venvs_own():
    require("ros")
    done = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                          check=False)
    assert done.returncode == 0, done.stderr
    # last on sys.path; rospy from the system; PyYAML (in both) still the venv's
    assert done.stdout.split() == ["True", "True", "True"]


def test_missing_ros_is_one_line_naming_the_debian_packages(monkeypatch, capsys):
    monkeypatch.setattr(system_ros, "_MODULES", ("rospy_not_installed_here",))
    assert main(["ros", "line", "--robots", "1"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("mimics: error: ROS 1 is not installed (rospy_not_installed_here "
                               "cannot be imported")
    assert "apt-get install python3-rospy python3-rosmaster" in lines[0]


def test_bad_options_are_one_line_errors(capsys):
    assert main(["ros", "line", "--timeout", "0"]) == 2
    error = capsys.readouterr().err.strip()  # the range check every command's --timeout gets
    assert error.startswith("mimics: error: ") and "\n" not in error
    assert "--timeout" in error and "above 0" in error
    assert main(["ros", "line", "--map-resolution", "-1"]) == 2
    assert "--map-resolution: expected a positive number" in capsys.readouterr().err
