#!/usr/bin/env python3
"""A ROS 1 node (rospy) that drives mimics robots to their goals.

The same logic as mimics' built-in ``go_to_goal``: head for the goal, at full
speed when facing it, slower the more it is off. Run it beside
``mimics ros``, with the system's Python (where Debian puts rospy)::

    rosmaster --core &
    mimics ros line --robots 5 --lockstep &
    /usr/bin/python3 examples/ros/go_to_goal_node.py --robots 5

It reads each robot's latched goal first, then answers every
``/robot_i/pose`` (the positioning sensor's pose in ``map``, what the
built-in algorithms read; ``/robot_i/odom`` is the odometer, in the robot's
``odom`` frame) with one ``/robot_i/cmd``: ``[speed_ref, heading_ref,
stamp]``, the stamp being the pose's, so that in lockstep the bridge knows
which step the reference answers. Stop it with Ctrl-C.
"""

import argparse
import math
import time

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from std_msgs.msg import Float64MultiArray


class GoToGoal:
    """One robot: its goal, its command publisher and its pose callback."""

    def __init__(self, robot, max_speed):
        self.robot = robot
        self.max_speed = max_speed
        self.goal = None
        self.cmd = None
        self.goal_subscriber = rospy.Subscriber(f"/robot_{robot}/goal", PoseStamped,
                                                self.on_goal)

    def on_goal(self, message):
        self.goal = (message.pose.position.x, message.pose.position.y)

    def start(self):
        """Once the goal is known: publish commands, listen to the pose."""
        self.cmd = rospy.Publisher(f"/robot_{self.robot}/cmd", Float64MultiArray,
                                   queue_size=10, tcp_nodelay=True)
        rospy.Subscriber(f"/robot_{self.robot}/pose", Odometry, self.on_pose, tcp_nodelay=True)

    def on_pose(self, message):
        pose = message.pose.pose
        x, y = pose.position.x, pose.position.y
        q = pose.orientation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        gx, gy = self.goal
        heading = math.atan2(gy - y, gx - x)
        speed = self.max_speed * max(math.cos(heading - yaw), 0.0)
        stamp = message.header.stamp.to_sec()
        self.cmd.publish(Float64MultiArray(data=[speed, heading, stamp]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, required=True, help="robots 0 to N-1")
    parser.add_argument("--max-speed", type=float, default=1.0,
                        help="m/s (1.0: the Pioneer 3-AT of the line scenario)")
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node("go_to_goal")
    robots = [GoToGoal(i, args.max_speed) for i in range(args.robots)]
    while not rospy.is_shutdown() and any(r.goal is None for r in robots):
        # goals are latched: they come as soon as we subscribe. Wall time: with
        # /use_sim_time set, simulated time starts only once we subscribe to odom
        time.sleep(0.01)
    for robot in robots:
        robot.start()
    rospy.spin()


if __name__ == "__main__":
    main()
