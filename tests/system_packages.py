"""System (Debian) packages some tests need, installed before the suite when missing.

The README's test command runs on a fresh machine: a test that needs a browser,
ROS or a compiler must run there, not skip. ``tests/conftest.py`` calls
:func:`install_missing` once, in the main pytest process; it runs ``apt-get``
only when something is missing and the suite runs as root. Elsewhere a test
that needs a missing part calls :func:`require`, which skips with the reason
on a developer's machine and fails under CI.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest


def _has_command(name: str) -> Callable[[], bool]:
    return lambda: shutil.which(name) is not None


def _has_file(path: str) -> Callable[[], bool]:
    return lambda: Path(path).exists()


def _has_pkg_config(module: str) -> bool:
    done = subprocess.run(["pkg-config", "--exists", module], capture_output=True, check=False)
    return done.returncode == 0


# A part: how to tell it is there, and the Debian packages that provide it.
PARTS: dict[str, tuple[Callable[[], bool], list[str]]] = {
    "compiler": (_has_command("gcc"), ["gcc", "g++", "libc6-dev"]),
    # `ps`, for tests that look for processes left running (tests/processes.py)
    "ps": (_has_command("ps"), ["procps"]),
    "chromium": (_has_command("chromium"), ["chromium"]),
    # the batteries' optional OS sandbox (tests/batteries/test_sandbox.py)
    "bubblewrap": (_has_command("bwrap"), ["bubblewrap"]),
    "ros": (
        lambda: _has_command("rosmaster")() and _has_file("/usr/include/ros/ros.h")()
        and _has_file("/usr/lib/python3/dist-packages/tf2_ros")()
        and _has_file("/usr/lib/python3/dist-packages/std_srvs")()
        and _has_file("/usr/lib/python3/dist-packages/visualization_msgs")()
        and _has_file("/usr/lib/python3/dist-packages/roslaunch")()
        # the Stage node styles' tests: message_filters' time sync and teleop by rostopic
        and _has_file("/usr/lib/python3/dist-packages/message_filters")()
        and _has_command("rostopic")(),
        ["python3-rospy", "python3-rosmaster", "python3-tf2-ros", "python3-sensor-msgs",
         "python3-nav-msgs", "python3-geometry-msgs", "python3-tf2-msgs",
         "python3-std-msgs", "python3-rosgraph-msgs", "python3-std-srvs",
         "python3-visualization-msgs", "python3-roslaunch", "python3-message-filters",
         "python3-rostopic", "libroscpp-dev", "ros-core-dev", "g++", "pkg-config"],
    ),
    # roscpp nodes built by the tests: the headers and pkg-config files of their messages
    "roscpp": (
        lambda: _has_command("pkg-config")() and all(
            _has_pkg_config(module) for module in ("roscpp", "std_msgs", "nav_msgs",
                                                   "geometry_msgs")),
        ["libroscpp-dev", "libstd-msgs-dev", "libnav-msgs-dev", "libgeometry-msgs-dev",
         "pkg-config", "g++"],
    ),
    # ROS 1's own bag reader (Python), an independent check of `mimics export --bag`
    "rosbag": (_has_file("/usr/lib/python3/dist-packages/rosbag/__init__.py"),
               ["python3-rosbag", "python3-genpy"]),
    # RViz opened under a virtual X server and screenshotted (tests/interfaces/ros/
    # test_rviz_window.py): Xvfb, xauth for xvfb-run, ImageMagick's `import`
    "rviz": (lambda: all(_has_command(name)() for name in ("rviz", "Xvfb", "xauth", "import")),
             ["rviz", "xvfb", "xauth", "imagemagick"]),
    # the ROS 2 tests' independent peer (tests/interfaces/ros2/fastdds_peer.py): Fast DDS 2.9,
    # fastddsgen (its Debian dependencies bring Java and cpp) and a C++17 compiler
    "fastdds": (
        lambda: _has_command("fastddsgen")() and _has_command("java")()
        and _has_command("cpp")() and _has_command("g++")()
        and _has_file("/usr/include/fastdds/dds/domain/DomainParticipant.hpp")()
        and _has_file("/usr/include/fastcdr/Cdr.h")(),
        ["libfastrtps-dev", "libfastcdr-dev", "fastddsgen", "g++"],
    ),
}


def missing_parts() -> list[str]:
    """The names of the parts in :data:`PARTS` that are not on this machine."""
    return [name for name, (present, _) in PARTS.items() if not present()]


def install_missing() -> str | None:
    """``apt-get install`` the missing parts when root; a note of what happened, or None."""
    missing = missing_parts()
    if not missing:
        return None
    if os.name != "posix" or os.geteuid() != 0 or shutil.which("apt-get") is None:
        return f"not root or no apt-get: cannot install {', '.join(missing)}"
    packages = sorted({package for name in missing for package in PARTS[name][1]})
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    steps = (["apt-get", "update", "-q"],
             ["apt-get", "install", "-y", "-q", "--no-install-recommends", *packages])
    for command in steps:
        done = subprocess.run(command, env=env, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            return f"{' '.join(command[:2])} failed: {done.stderr.strip()[-500:]}"
    still = missing_parts()
    return f"installed {' '.join(packages)}" + (f"; still missing: {still}" if still else "")


def require(name: str) -> None:
    """Skip (or, under CI, fail) the calling test when part ``name`` is missing."""
    present, packages = PARTS[name]
    if present():
        return
    message = f"{name} is missing (Debian packages: {' '.join(packages)})"
    if os.environ.get("CI"):
        pytest.fail(message + "; the test set-up should have installed it")
    pytest.skip(message)
