"""``mimics ros-files --out DIR``: a roslaunch package that brings up mimics with RViz.

Writes ``DIR/mimics_launch/`` (a ROS package, so put ``DIR`` on
``ROS_PACKAGE_PATH``)::

    package.xml            the package's manifest
    launch/mimics.launch   master (roslaunch's), ``mimics ros SCENARIO ARGS`` and RViz
                           (SCENARIO, ARGS: what it was written for, or roslaunch's
                           ``scenario:=``, ``args:=``)
    rviz/mimics.rviz       RViz: /map, each robot's /robot_i/scan, tf, /mimics/markers, in
                           a window with the 3D view (RViz's default dock layout)
    scripts/mimics_ros     the executable roslaunch runs: ``mimics ros`` of this install

The files are package data of mimics (``mimics/interfaces/ros/files``); the
RViz config gets one scan display per robot (``robots``). Nothing here needs
ROS: the files are written on any machine.

>>> import tempfile
>>> written = write_ros_files(Path(tempfile.mkdtemp()) / "ros", robots=2)
>>> [path.relative_to(written[0].parent).as_posix() for path in written]
['package.xml', 'launch/mimics.launch', 'rviz/mimics.rviz', 'scripts/mimics_ros']
"""

from __future__ import annotations

import copy
import shlex
import sys
from importlib import resources
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape as xml_escape

import yaml

from mimics.interfaces.ros.names import RosNames, check_name_set
from mimics.world.errors import MimicsError

PACKAGE = "mimics_launch"
SCAN_DISPLAY = "Scan robot_0"  # the RViz display repeated for every robot
_QUOTES = {'"': "&quot;"}  # the values go into XML attributes


def _template(name: str) -> str:
    return resources.files("mimics.interfaces.ros").joinpath("files", name).read_text()


def rviz_config(robots: int, names: str = "mimics") -> str:
    """The RViz config with one laser scan display per robot, named as the run's
    ``names`` set has it (``/robot_i/scan``; stage: ``/robot_i/base_scan``)."""
    config: dict[str, Any] = yaml.safe_load(_template("mimics.rviz"))
    displays = config["Visualization Manager"]["Displays"]
    template = next(d for d in displays if d["Name"] == SCAN_DISPLAY)
    at = displays.index(template)
    scans = []
    topics = RosNames(check_name_set(names, "--names"), robots)
    for robot in range(robots):
        display = copy.deepcopy(template)
        display["Name"] = f"Scan robot_{robot}"
        display["Topic"] = topics.scan(robot)
        scans.append(display)
    displays[at:at + 1] = scans
    header = "".join(line + "\n" for line in _template("mimics.rviz").splitlines()
                     if line.startswith("#"))
    return header + yaml.safe_dump(config, sort_keys=False)


def launch_file(robots: int, names: str = "mimics", scenario: str = "line") -> str:
    """The launch file, its ``scenario`` and ``args`` defaulting to what it was written for
    (``--robots N --names SET``); the node is ``/stageros`` under the stage names, as
    stage_ros' launch files have it. Under the stage names the package also asks for
    ``--publish-map-odom``: its RViz shows the robots in ``map``, and with no localiser
    running nothing else links ``map`` to their ``odom`` frames (a lab that runs amcl
    drops it from ``args:=``)."""
    stage = check_name_set(names, "--names") == "stage"
    node = "stageros" if stage else "mimics"
    arguments = f"--robots {robots} --names {names}" + (" --publish-map-odom" if stage else "")
    return (_template("mimics.launch").replace("@SCENARIO@", xml_escape(scenario, _QUOTES))
            .replace("@ARGS@", xml_escape(arguments, _QUOTES)).replace("@NODE@", node))


def ros_files(robots: int, names: str = "mimics", scenario: str = "line") -> dict[str, str]:
    """The package's files by path within it."""
    wrapper = _template("mimics_ros.sh").replace("@PYTHON@", shlex.quote(sys.executable))
    return {"package.xml": _template("package.xml"),
            "launch/mimics.launch": launch_file(robots, names, scenario),
            "rviz/mimics.rviz": rviz_config(robots, names),
            "scripts/mimics_ros": wrapper}


def write_ros_files(out: Path, robots: int = 4, names: str = "mimics",
                    scenario: str = "line") -> list[Path]:
    """Write the package into ``out/mimics_launch``; returns the files written.

    The launch file runs ``scenario`` with ``--robots robots --names names``
    unless roslaunch is given ``scenario:=`` or ``args:=``.

    ``out`` is created if need be, but not its parent folder; no file is replaced.

    Raises:
        MimicsError: in one line: ``robots`` below 1, ``out``'s parent folder
            missing, ``out`` not a folder, a file of the package already there, or
            an unknown name set.
    """
    if not isinstance(robots, int) or robots < 1:
        raise MimicsError(f"--robots: expected a whole number >= 1, got {robots!r}")
    out = Path(out)
    if not out.parent.is_dir():
        raise MimicsError(f"{out}: the folder {str(out.parent)!r} does not exist (create it "
                          "first)")
    if out.exists() and not out.is_dir():
        raise MimicsError(f"{out}: is not a folder")
    if not isinstance(scenario, str) or not scenario.strip():
        raise MimicsError(f"--scenario: expected a scenario name or file, got {scenario!r}")
    files = ros_files(robots, names, scenario)
    targets = {out / PACKAGE / name: text for name, text in files.items()}
    for target in targets:
        if target.exists():
            raise MimicsError(f"{target}: already exists (mimics ros-files replaces no file; "
                              "remove it or choose another --out)")
    try:
        for target, text in targets.items():
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(text)
        (out / PACKAGE / "scripts" / "mimics_ros").chmod(0o755)
    except OSError as exc:
        raise MimicsError(f"{out}: cannot write here ({exc.strerror or exc})") from None
    return list(targets)
