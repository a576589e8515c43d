"""A test controller for the fail-safe paths; one ``--mode`` per test.

* ``die``: answers every robot's odometry with a constant Twist; on the first
  odometry stamped at ``--at`` seconds or later it prints ``died WALLTIME``
  (``time.time()``) and exits at once (``os._exit``: as a crash, no goodbye).
* ``late-scan``: robot 0 only. Subscribes to ``odom`` and, ``--at`` wall
  seconds after that subscription connects (mimics is up), to ``scan``;
  answers step k only once it has both step k's odometry and scan.
  Prints ``scan STAMP HITS`` for every scan received (HITS: finite ranges).
* ``huge``: robot 0 gets ``cmd_vel`` linear.x = 1e30, angular.z = -1e30;
  robot 1 gets ``cmd`` [1e300, 0.5, stamp].

Run with the system's Python: ``/usr/bin/python3 failsafe_node.py --mode die --robots 20``.
"""

import argparse
import os
import threading
import time

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float64MultiArray

SPEED, RATE = 0.3, 0.2


def twist(speed, rate):
    message = Twist()
    message.linear.x, message.angular.z = speed, rate
    return message


def die_mode(args):
    publishers = [rospy.Publisher(f"/robot_{i}/cmd_vel", Twist, queue_size=10,
                                  tcp_nodelay=True) for i in range(args.robots)]

    dying = threading.Lock()  # robots' callbacks run on their own threads: one dies

    def on_odom(message, robot):
        if message.header.stamp.to_sec() >= args.at - 1e-9:
            dying.acquire()  # the other threads wait here until the process is gone
            print(f"died {time.time()!r}", flush=True)
            os._exit(1)
        publishers[robot].publish(twist(SPEED, RATE))

    for i in range(args.robots):
        rospy.Subscriber(f"/robot_{i}/odom", Odometry, on_odom, callback_args=i,
                         tcp_nodelay=True)


def late_scan_mode(args):
    publisher = rospy.Publisher("/robot_0/cmd_vel", Twist, queue_size=10, tcp_nodelay=True)
    lock = threading.Lock()
    odometry, scans, answered = set(), set(), set()

    def answer():
        for stamp in sorted(odometry & scans - answered):
            answered.add(stamp)
            publisher.publish(twist(SPEED, RATE))

    def on_odom(message):
        with lock:
            odometry.add(message.header.stamp.to_nsec())
            answer()

    def on_scan(message):
        hits = sum(1 for value in message.ranges if value != float("inf"))
        print(f"scan {message.header.stamp.to_sec()!r} {hits}", flush=True)
        with lock:
            scans.add(message.header.stamp.to_nsec())
            answer()

    odom = rospy.Subscriber("/robot_0/odom", Odometry, on_odom, tcp_nodelay=True)
    while odom.get_num_connections() == 0:  # mimics publishes: the run is about to start
        time.sleep(0.01)
    time.sleep(args.at)
    rospy.Subscriber("/robot_0/scan", LaserScan, on_scan, tcp_nodelay=True)


def huge_mode(args):
    cmd_vel = rospy.Publisher("/robot_0/cmd_vel", Twist, queue_size=10, tcp_nodelay=True)
    cmd = rospy.Publisher("/robot_1/cmd", Float64MultiArray, queue_size=10, tcp_nodelay=True)
    rospy.Subscriber("/robot_0/odom", Odometry,
                     lambda message: cmd_vel.publish(twist(1e30, -1e30)), tcp_nodelay=True)
    rospy.Subscriber("/robot_1/odom", Odometry, lambda message: cmd.publish(
        Float64MultiArray(data=[1e300, 0.5, message.header.stamp.to_sec()])), tcp_nodelay=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--mode", choices=("die", "late-scan", "huge"), required=True)
    parser.add_argument("--robots", type=int, default=1)
    parser.add_argument("--at", type=float, default=1.0)
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node("failsafe")
    {"die": die_mode, "late-scan": late_scan_mode, "huge": huge_mode}[args.mode](args)
    rospy.spin()


if __name__ == "__main__":
    main()
