"""Controller nodes as Stage labs write them, one ``--style`` each, all sending
``cmd_vel`` = (``--speed``, 0) to every robot (stage_ros names: ``robot_i/`` prefixes):

* ``odom``: publishes from its ``odom`` callback, and skips the step when no
  scan has come yet (a common guard);
* ``scan``: publishes from its ``base_scan`` callback;
* ``sync``: ``message_filters.TimeSynchronizer`` of ``odom`` and ``base_scan``;
* ``rate``: a ``rospy.Rate(10)`` loop (ROS time: with ``/use_sim_time`` set
  by a launch file it follows ``/clock``), started with ``/use_sim_time`` true;
* ``late-scan``: answers every ``odom`` at once (lockstep), and subscribes to
  ``base_scan`` ``--late`` seconds after ``odom``; logs the stamp of the first scan;
* ``skip``: answers the ``odom`` of even steps only (stamp / 0.1 s).

It drives ``--robots`` robots from ``--first``. Every command sent is counted;
at exit (SIGINT) one JSON line: ``{"commands": N, "first_scan_stamp": S or null}``.
Run with the system's Python.
"""

import argparse
import json
import threading
import time

import message_filters
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--style", required=True,
                        choices=["odom", "scan", "sync", "rate", "late-scan", "skip"])
    parser.add_argument("--robots", type=int, default=2)
    parser.add_argument("--first", type=int, default=0, help="the first robot driven")
    parser.add_argument("--speed", type=float, default=0.5)
    parser.add_argument("--late", type=float, default=0.5)
    args = parser.parse_args(rospy.myargv()[1:])
    if args.style == "rate":
        rospy.set_param("/use_sim_time", True)  # as a launch file's <param> does
    rospy.init_node(f"styles_{args.style.replace('-', '_')}")
    lock = threading.Lock()
    found = {"commands": 0, "first_scan_stamp": None}
    command = Twist()
    command.linear.x = args.speed
    prefixes = [f"robot_{args.first + i}/" for i in range(args.robots)]
    publishers = [rospy.Publisher(p + "cmd_vel", Twist, queue_size=10) for p in prefixes]
    have_scan = [False] * args.robots

    def send(robot):
        publishers[robot].publish(command)
        with lock:
            found["commands"] += 1

    def on_scan(message, robot):
        have_scan[robot] = True
        with lock:
            if found["first_scan_stamp"] is None:
                found["first_scan_stamp"] = message.header.stamp.to_sec()
        if args.style == "scan":
            send(robot)

    def on_odom(message, robot):
        even = round(message.header.stamp.to_sec() / 0.1) % 2 == 0
        if (args.style == "late-scan" or (args.style == "odom" and have_scan[robot])
                or (args.style == "skip" and even)):
            send(robot)

    def report():
        with lock:
            print(json.dumps(found), flush=True)

    rospy.on_shutdown(report)
    keep = []
    for i, prefix in enumerate(prefixes):
        if args.style == "sync":
            odom = message_filters.Subscriber(prefix + "odom", Odometry)
            scan = message_filters.Subscriber(prefix + "base_scan", LaserScan)
            sync = message_filters.TimeSynchronizer([odom, scan], 10)
            sync.registerCallback(lambda _o, s, robot=i: (on_scan(s, robot), send(robot)))
            keep.append(sync)
        elif args.style in ("odom", "scan", "late-scan", "skip"):
            rospy.Subscriber(prefix + "odom", Odometry, on_odom, callback_args=i)
            if args.style not in ("late-scan", "skip"):
                rospy.Subscriber(prefix + "base_scan", LaserScan, on_scan, callback_args=i)
    if args.style == "late-scan":
        time.sleep(args.late)
        for i, prefix in enumerate(prefixes):
            rospy.Subscriber(prefix + "base_scan", LaserScan, on_scan, callback_args=i)
    if args.style == "rate":
        rate = rospy.Rate(10)
        while not rospy.is_shutdown():
            for robot in range(args.robots):
                send(robot)
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
    rospy.spin()


if __name__ == "__main__":
    main()
