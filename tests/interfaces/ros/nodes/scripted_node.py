"""A test controller with a script: known references, malformed messages, then silence.

Robot 0 (``cmd``): answers the odometry stamped at step ``k`` with
``[reference_speed(k), reference_heading(k), stamp]``, except at the steps of
``MALFORMED`` (numbers in ``scripted_plan.py``), where it sends a NaN or an array
of the wrong length.
Robot 1 (``cmd_vel``): a constant Twist (``TWIST_SPEED``, ``TWIST_RATE``).
Both stop answering from ``--stop-at`` seconds on (simulated time).
Run with the system's Python: ``/usr/bin/python3 scripted_node.py --stop-at 2``.
"""

import argparse
import math

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from scripted_plan import (
    DT,
    MALFORMED,
    TWIST_RATE,
    TWIST_SPEED,
    reference_heading,
    reference_speed,
)
from std_msgs.msg import Float64MultiArray


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--stop-at", type=float, default=math.inf)
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node("scripted")
    cmd = rospy.Publisher("/robot_0/cmd", Float64MultiArray, queue_size=10, tcp_nodelay=True)
    cmd_vel = rospy.Publisher("/robot_1/cmd_vel", Twist, queue_size=10, tcp_nodelay=True)

    def on_odom_0(message):
        stamp = message.header.stamp.to_sec()
        if stamp >= args.stop_at - 1e-9:
            return
        step = round(stamp / DT)
        fault = MALFORMED.get(step)
        if fault == "nan":
            data = [math.nan, reference_heading(step), stamp]
        elif fault == "length":
            data = [reference_speed(step), reference_heading(step), stamp, 1.0]
        else:
            data = [reference_speed(step), reference_heading(step), stamp]
        cmd.publish(Float64MultiArray(data=data))

    def on_odom_1(message):
        if message.header.stamp.to_sec() >= args.stop_at - 1e-9:
            return
        twist = Twist()
        twist.linear.x, twist.angular.z = TWIST_SPEED, TWIST_RATE
        cmd_vel.publish(twist)

    rospy.Subscriber("/robot_0/odom", Odometry, on_odom_0, tcp_nodelay=True)
    rospy.Subscriber("/robot_1/odom", Odometry, on_odom_1, tcp_nodelay=True)
    rospy.spin()


if __name__ == "__main__":
    main()
