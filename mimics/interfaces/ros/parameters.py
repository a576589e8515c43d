"""The run on the parameter server, for ROS tools and nodes that look there.

When the bridge starts, the run's ``/mimics`` tree is set; just before the
first ``/clock`` (once the controller nodes the run waits for have
connected), ``/use_sim_time`` is set to true: nodes and tools started from
then on (RViz, ``rosbag record``) follow ``/clock``, while the nodes already
running keep the time base they started with (ROS reads the parameter once,
at a node's start). Set earlier (in a launch file), a node that waits on ROS
time (``rospy.sleep``, ``ros::Rate``) before it subscribes would wait for a
clock that only starts once it has subscribed. The ``/mimics`` tree:

==================================== ========================================================
parameter                            value
==================================== ========================================================
``/mimics/robots``                   the robot count
``/mimics/scenario``                 the scenario's name
``/mimics/dt``                       seconds of simulated time per step
``/mimics/lockstep``                 true in lockstep, false in realtime
``/mimics/robot_i/type``             robot ``i``'s type name (``pioneer_3at``, ...)
``/mimics/robot_i/footprint``        ``[length, width]`` in metres (length along the heading)
``/mimics/robot_i/max_speed``        top speed, m/s (commands beyond it are clipped)
``/mimics/robot_i/max_turn_rate``    top turn rate, rad/s
``/mimics/robot_i/ranger/range``     the ranger's range in metres (absent: no ranger)
``/mimics/robot_i/ranger/fov``       its field of view in radians
``/mimics/robot_i/ranger/beams``     its number of beams
==================================== ========================================================

``robot_i`` is the robot's index from 0, as in its topics. When the run
ends, the ``/mimics`` tree is deleted and ``/use_sim_time`` put back as it
was: a node started for the next run on the same master (a battery's
``ros:`` runs share their worker's) starts as the first run's did.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import rospy

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation

ROOT = "/mimics"
SIM_TIME = "/use_sim_time"


def run_parameters(sim: Simulation, lockstep: bool) -> dict[str, Any]:
    """The ``/mimics`` tree of a run, as a dictionary (keys without the leading ``/mimics/``)."""
    scenario = sim.scenario
    tree: dict[str, Any] = {"robots": int(scenario.robot_count), "scenario": scenario.name,
                            "dt": float(scenario.settings.dt), "lockstep": bool(lockstep)}
    for robot in range(scenario.robot_count):
        kind = scenario.robot_type(robot)
        entry: dict[str, Any] = {"type": kind.name,
                                 "footprint": [float(kind.length), float(kind.width)],
                                 "max_speed": float(kind.kv), "max_turn_rate": float(kind.kw)}
        ranger = kind.ranger
        if ranger.beams > 0:
            entry["ranger"] = {"range": float(ranger.range), "fov": float(ranger.fov),
                               "beams": int(ranger.beams)}
        tree[f"robot_{robot}"] = entry  # the same keys whatever the run's name set
    return tree


_UNSET = object()  # /use_sim_time was not on the server


def use_sim_time() -> object:
    """Set ``/use_sim_time`` to true (before the first ``/clock``); returns what it was."""
    before = rospy.get_param(SIM_TIME, _UNSET)
    rospy.set_param(SIM_TIME, True)
    return before


def restore_sim_time(before: object) -> None:
    """Put ``/use_sim_time`` back as :func:`use_sim_time` found it; quiet when the master
    has gone."""
    try:
        if before is _UNSET:
            if rospy.has_param(SIM_TIME):
                rospy.delete_param(SIM_TIME)
        else:
            rospy.set_param(SIM_TIME, before)
    except Exception:  # the master stopped first: nothing left to restore
        return


def set_run_parameters(sim: Simulation, lockstep: bool) -> None:
    """Put the run's ``/mimics`` tree on the parameter server (replacing an earlier one)."""
    if rospy.has_param(ROOT):
        rospy.delete_param(ROOT)
    rospy.set_param(ROOT, run_parameters(sim, lockstep))


def clear_run_parameters() -> None:
    """Remove the ``/mimics`` tree (the run has ended); quiet when the master has gone."""
    try:
        if rospy.has_param(ROOT):
            rospy.delete_param(ROOT)
    except Exception:  # the master stopped first: nothing left to clean
        return
