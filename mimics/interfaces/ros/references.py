"""The algorithm of a ROS-driven run: each robot's references are the ones ROS sent.

It follows the ordinary algorithm contract (``step(robot)`` per robot, see
``mimics.engine.controllers``), so the engine times each call, contains its
failures and records everything as for any algorithm. A lockstep time-out
is raised as :class:`~mimics.interfaces.ros.inbox.LockstepTimeout`; under
the default ``abort`` policy it ends the run with status ``error`` and the
message in the summary.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mimics.engine.controllers import PerRobotController
from mimics.interfaces.ros.conversion import twist_to_references
from mimics.interfaces.ros.inbox import HOLD, Command, Inbox, LockstepTimeout

ALGORITHM_NAME = "ros"


class RosReferences:
    """Per robot, the last reference received (held until a new one comes).

    Args:
        inbox: where the subscriptions put the commands.
        initial_headings: each robot's heading at time zero; a robot holds
            ``(0 m/s, that heading)`` until its first command.
        timeout: lockstep: seconds to wait for a robot's command.
    """

    def __init__(self, inbox: Inbox, initial_headings: np.ndarray, timeout: float) -> None:
        self.inbox = inbox
        self.timeout = timeout
        self.held = [(0.0, float(heading)) for heading in initial_headings]

    def step(self, robot: Any) -> tuple[float, float]:
        """The reference for ``robot`` at this step (waits for it in lockstep)."""
        step = round(robot.time / robot.dt)
        try:
            command, notes = self.inbox.take(robot.id, step, self.timeout)
        except LockstepTimeout:
            raise LockstepTimeout(
                f"no command on /robot_{robot.id}/cmd or /robot_{robot.id}/cmd_vel for "
                f"t={robot.time:g} s within {self.timeout:g} s (--lockstep): has the "
                "controller node stopped?") from None
        for note in notes:
            robot.log(note)
        if command is not None and command is not HOLD:
            self.held[robot.id] = self._references(command, robot)
        return self.held[robot.id]

    @staticmethod
    def _references(command: Command, robot: Any) -> tuple[float, float]:
        if command.kind == "reference":
            return command.first, command.second
        kind = robot.type
        return twist_to_references(command.first, command.second, float(robot.heading),
                                   kind.kw, kind.heading_pid.kp, kind.heading_pid.kd)

    def controller(self) -> PerRobotController:
        """The engine's controller calling :meth:`step` for each active robot."""
        return PerRobotController(ALGORITHM_NAME, step=self.step)
