"""``ros2:`` algorithms: a ROS 2 controller node, started by mimics, drives a run.

An algorithm written ``ros2:PROGRAM [ARGS...]`` (``mimics run``, a battery
file's ``algorithms``, the Python API) is a ROS 2 controller node: a ``.py``
file (run with this Python, where the ``cyclonedds`` binding is) or an
executable (an ``rclcpp`` node, a ``ros2 run`` wrapper script, any DDS
program). For each run, mimics

1. reserves a DDS domain nobody else on this machine uses
   (:mod:`~mimics.interfaces.ros2.private_domain`), the ROS 2 counterpart
   of ROS 1's private master;
2. publishes the run's topics there (the bridge of ``mimics ros2``), starts
   the node with ``ROS_DOMAIN_ID`` set to that domain, ``MIMICS_ROBOTS`` and
   ``MIMICS_SEED`` to the run's robot count and seed (``{robots}``, ``{seed}``
   and ``{domain}`` in ARGS replaced by them) and ``CYCLONEDDS_URI`` as this
   process has it, and waits until it subscribes to each robot's topics and
   its ``cmd_vel`` writers match;
3. runs in lockstep (each step waits for every active robot's command), so
   the run is as deterministic as the node, and a battery of such runs gives
   the same results on any number of workers;
4. stops the node when the run ends (SIGINT, then SIGKILL), leaves the domain
   and frees it. The kernel kills the node if this process dies first.

``ros2:--names=stage PROGRAM [ARGS...]`` publishes ``stage_ros``' names, as
``ros:`` does. The command, the node's process and the scheme are shared
with ``ros:`` (:mod:`~mimics.interfaces.ros.node_process`); the entry point
``ros2`` of ``mimics.algorithm_schemes`` (``pyproject.toml``) is :data:`SCHEME`.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

import numpy as np

from mimics.interfaces.ros import node_process
from mimics.interfaces.ros.node_process import (
    DEFAULTS,
    NodeController,
    NodeKind,
    NodeRun,
    NodeScheme,
    close_current,
)

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.engine.user_code import UserFailure

ROS2 = NodeKind("ros2", "a .py file or an executable ROS 2 node", lambda: sys.executable)


class Ros2NodeCommand(node_process.NodeCommand):
    """A ROS 2 controller node's command (``ros2:[--names=SET] PROGRAM [ARGS...]``)."""

    kind = ROS2


class Ros2NodeController(NodeController):
    """The engine's controller of a ``ros2:`` algorithm: references from a node it starts
    on a DDS domain of the run's own."""

    def reset(self, sim: Simulation) -> list[UserFailure]:
        from mimics.interfaces.ros2 import require_cyclonedds

        require_cyclonedds()
        from mimics.interfaces.ros.bridge_core import BridgeOptions
        from mimics.interfaces.ros.inbox import Inbox
        from mimics.interfaces.ros.references import RosReferences
        from mimics.interfaces.ros2.bridge import Ros2Bridge
        from mimics.interfaces.ros2.private_domain import reserve_domain
        from mimics.interfaces.ros2.transport import DOMAIN_VARIABLE, DdsGraph

        # lockstep: a run as deterministic as the node
        options = BridgeOptions(timeout=DEFAULTS.timeout, timeout_option=DEFAULTS.timeout_option,
                                names=self.command.names or DEFAULTS.names)
        close_current()  # a run that ended without on_end (it raised) leaves its node
        state = sim.state
        domain = reserve_domain()
        graph: DdsGraph | None = None
        try:
            graph = DdsGraph(domain.domain)
            inbox = Inbox(state.n, lockstep=True, timeout=options.timeout)
            bridge = Ros2Bridge(sim, inbox, options, graph)
        except BaseException:
            if graph is not None:
                graph.close()
            domain.release()
            raise
        references = RosReferences(inbox, sim.scenario.stages[:, 2], options.timeout,
                                   options.timeout_option)
        references.publishers, references.names = bridge.commands_connected, bridge.names
        self._references = references.controller()
        argv = self.command.argv(robots=state.n, seed=sim.seed, domain=domain.domain)
        run = NodeRun(bridge, argv, {DOMAIN_VARIABLE: str(domain.domain),
                                     "MIMICS_ROBOTS": str(state.n),
                                     "MIMICS_SEED": str(sim.seed)}, released=domain.release)
        self._waited(run, bridge, np.flatnonzero(state.active))
        sim.observers.append(run)
        return self._references.reset(sim)


SCHEME = NodeScheme(Ros2NodeCommand, Ros2NodeController)
