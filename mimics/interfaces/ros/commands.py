"""The subscriptions: ``/robot_i/cmd`` and ``/robot_i/cmd_vel`` feed the inbox.

``cmd`` is ``std_msgs/Float64MultiArray`` with ``data = [speed_ref,
heading_ref]`` or ``[speed_ref, heading_ref, stamp]`` (see
:func:`~mimics.interfaces.ros.conversion.command_from_array`); ``cmd_vel`` is
``geometry_msgs/Twist`` (``linear.x``, ``angular.z``). A message that cannot be
used is logged as a warning and reported to the robot's log by the inbox.
"""

from __future__ import annotations

from typing import Any

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Float64MultiArray

from mimics.interfaces.ros.conversion import (
    BadCommand,
    command_from_array,
    command_from_twist,
    robot_namespace,
)
from mimics.interfaces.ros.inbox import Inbox


class CommandSubscriber:
    """Subscribes to both command topics of every robot."""

    def __init__(self, robots: int, inbox: Inbox, dt: float) -> None:
        self.inbox = inbox
        self.dt = dt
        self.cmd = [rospy.Subscriber(f"/{robot_namespace(i)}/cmd", Float64MultiArray,
                                     self._on_cmd, callback_args=i, tcp_nodelay=True)
                    for i in range(robots)]
        self.cmd_vel = [rospy.Subscriber(f"/{robot_namespace(i)}/cmd_vel", Twist,
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
            rospy.logwarn("robot %d: %s", robot, exc)
            self.inbox.reject(robot, str(exc))
            return
        self.inbox.deliver(robot, command)

    def publishers_connected(self, robot: int) -> int:
        """How many publishers are connected to the robot's two command topics."""
        return self.cmd[robot].get_num_connections() + self.cmd_vel[robot].get_num_connections()

    def close(self) -> None:
        """Stop listening."""
        for subscriber in (*self.cmd, *self.cmd_vel):
            subscriber.unregister()
