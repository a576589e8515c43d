"""``ros:`` algorithms: a ROS controller node, started by mimics, drives a run.

An algorithm written ``ros:PROGRAM [ARGS...]`` (``mimics run``, a battery
file's ``algorithms``, the Python API) is a ROS 1 controller node: a rospy
``.py`` file (run with the system's Python, where Debian puts rospy) or an
executable (a roscpp node, say). For each run, mimics

1. starts this process's private master if it has none yet
   (:mod:`~mimics.interfaces.ros.private_master`) and joins it as the node
   ``/mimics`` (once per process, as rospy allows);
2. publishes the run's topics (the bridge of ``mimics ros``), starts the
   node with ``{robots}`` and ``{seed}`` in ARGS replaced by the run's robot
   count and seed (also given as ``MIMICS_ROBOTS`` and ``MIMICS_SEED``) and
   waits until it listens to each robot's topics and publishes commands;
3. runs in lockstep (each step waits for every active robot's command), so
   the run is as deterministic as the node, and a battery of such runs gives
   the same results on any number of workers;
4. stops the node when the run ends (SIGINT, then SIGKILL) and withdraws
   the run's topics. The kernel kills the node and the master if the process
   dies first (a battery worker past its time limit, say).

Options of the bridge may come before PROGRAM: ``ros:--names=stage
PROGRAM [ARGS...]`` publishes ``stage_ros``' names
(:mod:`~mimics.interfaces.ros.names`), for a node written for Stage; in a
battery file that is the way to choose them (``mimics run`` also has
``--ros-names``, which the algorithm's own option overrides).

The entry point ``ros`` of the group ``mimics.algorithm_schemes``
(``pyproject.toml``) is :data:`SCHEME`: the catalog finds it there, so that
the layers below the interfaces never import ROS. What ``ros2:`` algorithms
share with these (the command, the node's process, the scheme) is in
:mod:`~mimics.interfaces.ros.node_process`.
"""

from __future__ import annotations

import shutil
import sys
from typing import TYPE_CHECKING

import numpy as np

from mimics.interfaces.ros import node_process
from mimics.interfaces.ros.node_process import (
    DEFAULTS,
    NodeController,
    NodeDefaults,
    NodeKind,
    NodeRun,
    NodeScheme,
    close_current,
)

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.engine.user_code import UserFailure

__all__ = ["DEFAULTS", "SCHEME", "NodeCommand", "NodeDefaults", "RosNodeCommand",
           "RosNodeController", "system_python"]


def system_python() -> str:
    """The Python that runs rospy nodes: the system's (Debian's rospy lives there)."""
    return shutil.which("python3", path="/usr/bin") or sys.executable


ROS1 = NodeKind("ros", "a rospy .py file or an executable ROS node", system_python)


class RosNodeCommand(node_process.NodeCommand):
    """A ROS 1 controller node's command (``ros:[--names=SET] PROGRAM [ARGS...]``)."""

    kind = ROS1


NodeCommand = RosNodeCommand  # the name it had before ros2: shared it


class RosNodeController(NodeController):
    """The engine's controller of a ``ros:`` algorithm: references from a node it starts."""

    def reset(self, sim: Simulation) -> list[UserFailure]:
        from mimics.interfaces.ros.bridge import BridgeOptions, RosBridge, join_ros
        from mimics.interfaces.ros.private_master import private_master

        # lockstep: a run as deterministic as the node
        options = BridgeOptions(timeout=DEFAULTS.timeout, timeout_option=DEFAULTS.timeout_option,
                                names=self.command.names or DEFAULTS.names)
        close_current()  # a run that ended without on_end (it raised) leaves its node
        private_master()
        join_ros()  # rospy importable from here on
        from mimics.interfaces.ros.inbox import Inbox
        from mimics.interfaces.ros.references import RosReferences

        state = sim.state
        inbox = Inbox(state.n, lockstep=True, timeout=options.timeout)
        references = RosReferences(inbox, sim.scenario.stages[:, 2], options.timeout,
                                   options.timeout_option)
        self._references = references.controller()
        bridge = RosBridge(sim, inbox, options)
        references.publishers = bridge.commands.publishers_connected
        references.names = bridge.names
        run = NodeRun(bridge, self.command.argv(robots=state.n, seed=sim.seed),
                      {"MIMICS_ROBOTS": str(state.n), "MIMICS_SEED": str(sim.seed)})
        self._waited(run, bridge, np.flatnonzero(state.active))
        sim.observers.append(run)
        return self._references.reset(sim)


SCHEME = NodeScheme(RosNodeCommand, RosNodeController)
