"""nav_msgs/Odometry: each robot's true pose and velocity at every recorded step.

One message per row of trajectory.parquet on ``/robot_i/ground_truth``: frame ``map``,
child frame ``robot_i/base_link``; the pose is the true ``x, y, theta`` (the
heading as a rotation about z) and the twist the true speed ``v`` along the
body's x axis and turn rate ``w`` about z, in the child frame as ROS expects.
"""

from __future__ import annotations

from collections.abc import Iterator

from mimics.interfaces.rosexport.conversion import Messages, Stamped
from mimics.interfaces.rosexport.source import Trajectory
from mimics.interfaces.rosexport.topics import MAP_FRAME, ODOMETRY, base_link, truth_topic


def odometry_messages(messages: Messages, trajectory: Trajectory) -> Iterator[Stamped]:
    """One Odometry per trajectory row, in (step, robot) order."""
    for k in range(trajectory.rows):
        robot = int(trajectory.robot[k])
        stamp = int(trajectory.stamp[k])
        linear = messages.make("geometry_msgs/msg/Vector3", x=float(trajectory.v[k]))
        angular = messages.make("geometry_msgs/msg/Vector3", z=float(trajectory.w[k]))
        message = messages.make(
            ODOMETRY, header=messages.header(stamp, MAP_FRAME), child_frame_id=base_link(robot),
            pose=messages.make("geometry_msgs/msg/PoseWithCovariance",
                               pose=messages.pose(trajectory.x[k], trajectory.y[k],
                                                  trajectory.theta[k])),
            twist=messages.make("geometry_msgs/msg/TwistWithCovariance",
                                twist=messages.make("geometry_msgs/msg/Twist", linear=linear,
                                                    angular=angular)))
        yield Stamped(stamp, truth_topic(robot), message)
