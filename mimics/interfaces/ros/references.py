"""The algorithm of a ROS-driven run: each robot's references are the ones ROS sent.

It follows the ordinary algorithm contract (``step(robot)`` per robot, see
``mimics.engine.user_code.controllers``), so the engine times each call, contains its
failures and records everything as for any algorithm. A lockstep time-out
is raised as :class:`~mimics.interfaces.ros.inbox.LockstepTimeout`; under
the default ``abort`` policy it ends the run with status ``error`` and the
message in the summary.

Fail-safe rules applied here, each written to the robot's log (the run's
``user_message`` events):

* a command beyond the robot's limits (speed beyond its top speed ``kv``, a
  turn rate beyond ``kw``) is clipped to them; the log says what was asked
  and what was applied (at most once per simulated second, with a count);
* realtime: a robot whose last command is older than the watchdog
  (``watchdog`` seconds of simulated time, as stage_ros' ``base_watchdog_timeout``)
  is stopped (speed 0, heading held) until commands come again; when nothing
  publishes its commands any more the log says its node has gone.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from mimics.engine.user_code import PerRobotController
from mimics.interfaces.ros.inbox import HOLD, Command, Inbox, LockstepTimeout
from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.ros.planar import twist_to_references

ALGORITHM_NAME = "ros"


class RosReferences:
    """Per robot, the last reference received (held until a new one comes).

    Args:
        inbox: where the subscriptions put the commands.
        initial_headings: each robot's heading at time zero; a robot holds
            ``(0 m/s, that heading)`` until its first command.
        timeout: lockstep: seconds each step waits for all its commands.
        timeout_option: the option that sets ``timeout`` in the command that
            is running (``--timeout``), cited by the time-out's message; None
            when there is none.
        watchdog: realtime: seconds without a command after which a robot is
            stopped (None: never).
        publishers: how many command publishers robot ``i`` has (to tell a
            node that has gone from one that is only late).
        names: the run's topic names (cited by messages).
    """

    def __init__(self, inbox: Inbox, initial_headings: np.ndarray, timeout: float,
                 timeout_option: str | None = "--timeout", watchdog: float | None = None,
                 publishers: Callable[[int], int] | None = None,
                 names: RosNames | None = None) -> None:
        self.inbox = inbox
        self.names = names or RosNames(robots=len(initial_headings))
        self.timeout = timeout
        self.timeout_option = timeout_option
        self.watchdog = watchdog
        self.publishers = publishers
        self.held = [(0.0, float(heading)) for heading in initial_headings]
        self._stopped = [False] * len(self.held)  # realtime: the watchdog holds the robot
        self._gone = [False] * len(self.held)  # realtime: its node's going has been noted
        self._clipped: dict[int, tuple[float, int]] = {}  # robot: (time of last note, count)

    def step(self, robot: Any) -> tuple[float, float]:
        """The reference for ``robot`` at this step (waits for it in lockstep)."""
        step = round(robot.time / robot.dt)
        try:
            command, notes = self.inbox.take(robot.id, step)
        except LockstepTimeout as exc:
            raise LockstepTimeout(self._timeout_message(exc.robots, robot.time),
                                  exc.robots) from None
        for note in notes:
            robot.log(note)
        if self.watchdog is not None and not self.inbox.lockstep and self._silent(robot):
            return self.held[robot.id]  # the stale command is not used again
        if command is not None and command is not HOLD:
            self.held[robot.id] = self._references(command, robot)
        return self.held[robot.id]

    def _timeout_message(self, waiting: tuple[int, ...], seconds: float) -> str:
        option = f" ({self.timeout_option})" if self.timeout_option else ""
        plural = "s" if len(waiting) > 1 else ""
        return (f"no command for t={seconds:g} s within {self.timeout:g} s{option} from "
                f"{len(waiting)} robot{plural}: {robot_ranges(waiting)} (on "
                f"{self.names.commands_text()}): has the controller node stopped, or does "
                "it answer only on a timer or after a message that has not come (a "
                "rate loop on ROS time, rospy.Rate or an rclpy timer, waits for /clock, "
                "which waits for it; teleop sends at its own pace)? Lockstep wants one "
                "command per robot and step; such nodes run in --realtime")

    def _silent(self, robot: Any) -> bool:
        """Realtime: whether the robot's commands have ceased; it is then stopped (once)."""
        i = robot.id
        silence = self.inbox.sim_silence(i, float(robot.time))
        if silence <= self.watchdog + 1e-9 or math.isinf(silence):  # inf: no command yet, standing
            if self._stopped[i]:
                self._stopped[i] = self._gone[i] = False
                robot.log("commands again: the watchdog releases the robot")
            return False
        gone = self.publishers is not None and self.publishers(i) == 0
        gone_note = (f"its node has gone (nothing publishes "
                     f"{self.names.commands_text(i)})")
        if not self._stopped[i]:
            self._stopped[i] = True
            self._gone[i] = gone
            cause = gone_note if gone else f"no command for {silence:.2f} s"
            robot.log(f"watchdog: {cause}; stopping the robot (watchdog {self.watchdog:g} s)")
            self.held[i] = (0.0, float(robot.heading))
        elif gone and not self._gone[i]:  # its publisher's connection closed since
            self._gone[i] = True
            robot.log(f"watchdog: {gone_note}")
        return True

    def _references(self, command: Command, robot: Any) -> tuple[float, float]:
        kind = robot.type
        top_speed, top_rate = float(kind.kv), float(kind.kw)
        speed = _clip(command.first, top_speed)
        if command.kind == "reference":
            if speed != command.first:
                self._note_clip(robot, f"cmd asked speed_ref={command.first:g} m/s; applied "
                                       f"{speed:g} m/s (top speed {top_speed:g} m/s)")
            return speed, command.second
        rate = _clip(command.second, top_rate)
        if (speed, rate) != (command.first, command.second):
            self._note_clip(robot, f"cmd_vel asked linear.x={command.first:g} m/s, "
                                   f"angular.z={command.second:g} rad/s; applied {speed:g} "
                                   f"m/s, {rate:g} rad/s (the robot's limits)")
        return twist_to_references(speed, rate, float(robot.heading), kind.kw,
                                   kind.heading_pid.kp, kind.heading_pid.kd)

    def _note_clip(self, robot: Any, text: str) -> None:
        """Log a clipped command, at most once per simulated second (with the count since)."""
        last, count = self._clipped.get(robot.id, (-math.inf, 0))
        count += 1
        if robot.time - last >= 1.0 - 1e-9:
            suffix = f" ({count} clipped commands since the last note)" if count > 1 else ""
            robot.log(text + suffix)
            last, count = robot.time, 0
        self._clipped[robot.id] = (last, count)

    def controller(self, name: str = ALGORITHM_NAME) -> PerRobotController:
        """The engine's controller calling :meth:`step` for each active robot; ``name`` is
        the run's algorithm (``ros``, ``ros2``)."""
        return PerRobotController(name, step=self.step)


def _clip(value: float, limit: float) -> float:
    """``value`` within ``[-limit, limit]``."""
    return max(-limit, min(limit, value))


def robot_ranges(robots: tuple[int, ...]) -> str:
    """Robot ids, runs of three or more as ranges: ``(0, 1, 2, 5, 6)`` gives ``"0-2, 5, 6"``."""
    parts: list[str] = []
    start = previous = robots[0]
    for robot in (*robots[1:], None):
        if robot is not None and robot == previous + 1:
            previous = robot
            continue
        if previous - start >= 2:
            parts.append(f"{start}-{previous}")
        else:
            parts.extend(str(i) for i in range(start, previous + 1))
        if robot is not None:
            start = previous = robot
    return ", ".join(parts)
