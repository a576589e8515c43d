"""The subscriptions: each robot's ``cmd`` and ``cmd_vel`` (names from
:class:`~mimics.interfaces.ros.names.RosNames`; the ``stage`` names have
``cmd_vel`` only) feed the inbox.

``cmd`` is ``std_msgs/Float64MultiArray`` with ``data = [speed_ref,
heading_ref]`` or ``[speed_ref, heading_ref, stamp]`` (see
:func:`~mimics.interfaces.ros.conversion.command_from_array`); ``cmd_vel`` is
``geometry_msgs/Twist`` (``linear.x``, ``angular.z``). A message that cannot be
used is reported to the robot's log by the inbox and logged as a ROS
warning, at most once per robot per second (with the count of the messages
since), so a node that floods bad messages does not flood the terminal.
"""

from __future__ import annotations

import time
from typing import Any

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float64MultiArray

from mimics.interfaces.ros.conversion import (
    BadCommand,
    command_from_array,
    command_from_twist,
)
from mimics.interfaces.ros.inbox import Inbox
from mimics.interfaces.ros.names import RosNames

WARNING_INTERVAL = 1.0  # seconds of wall time between two warnings about one robot


class WarningThrottle:
    """At most one warning per robot per :data:`WARNING_INTERVAL`, counting the ones held back."""

    def __init__(self) -> None:
        self._warned: dict[int, tuple[float, int]] = {}  # robot: (when last warned, count since)

    def __call__(self, robot: int, problem: str, now: float) -> str | None:
        """The warning to log about a bad message at wall time ``now``, or None if too soon."""
        last, count = self._warned.get(robot, (float("-inf"), 0))
        count += 1
        if now - last < WARNING_INTERVAL:
            self._warned[robot] = (last, count)
            return None
        self._warned[robot] = (now, 0)
        if count == 1:
            return f"robot {robot}: {problem}"
        return (f"robot {robot}: {problem} ({count} bad messages for this robot in the "
                f"last {now - last:.1f} s)")


class CommandSubscriber:
    """Subscribes to both command topics of every robot."""

    def __init__(self, robots: int, inbox: Inbox, dt: float,
                 names: RosNames | None = None) -> None:
        names = names or RosNames(robots=robots)
        self.inbox = inbox
        self.dt = dt
        self.warnings = WarningThrottle()
        cmd_topics = [names.cmd(i) for i in range(robots)]
        self.cmd = [rospy.Subscriber(topic, Float64MultiArray, self._on_cmd, callback_args=i,
                                     tcp_nodelay=True) if topic is not None else None
                    for i, topic in enumerate(cmd_topics)]
        self.cmd_vel = [rospy.Subscriber(names.cmd_vel(i), Twist,
                                         self._on_twist, callback_args=i, tcp_nodelay=True)
                        for i in range(robots)]

    def _on_cmd(self, message: Float64MultiArray, robot: int) -> None:
        self._take(robot, command_from_array, message, self.dt)

    def _on_twist(self, message: Twist, robot: int) -> None:
        self._take(robot, command_from_twist, message)

    def _take(self, robot: int, convert: Any, *args: Any) -> None:
        try:
            command = convert(*args)
        except BadCommand as exc:
            warning = self.warnings(robot, str(exc), time.monotonic())
            if warning is not None:
                rospy.logwarn(warning)
            self.inbox.reject(robot, str(exc))
            return
        self.inbox.deliver(robot, command)

    def publishers_connected(self, robot: int) -> int:
        """How many publishers of the robot's two command topics have finished their handshake.

        rospy counts a subscriber's connection as soon as the master names a
        publisher, before the TCP handshake; a command the node publishes
        until the handshake ends is lost (its publisher adds the connection
        only after the handshake), and lockstep would wait for it in vain.
        """
        return sum(_handshaken(connection)
                   for subscriber in (self.cmd[robot], self.cmd_vel[robot])
                   if subscriber is not None
                   for connection in list(subscriber.impl.connections))

    def close(self) -> None:
        """Stop listening."""
        for subscriber in (*self.cmd, *self.cmd_vel):
            if subscriber is not None:
                subscriber.unregister()


def _handshaken(connection: Any) -> bool:
    """Whether a subscriber's TCPROS connection has read its publisher's header."""
    return getattr(connection, "header", None) is not None
