"""A controller node written as a stage_ros user writes one (no mimics names in it but the
``--names mimics`` table below, written from the docs).

Per robot it subscribes to ``odom``, ``base_pose_ground_truth`` and
``base_scan`` (``robot_i/...`` with several robots, no prefix with one, as
``stageros`` names them) and publishes ``cmd_vel``. It answers step k once
it has step k's three messages (so a run is deterministic), with:

* ``--goals "x,y;x,y;..."`` (in ``map``): head for the goal using the ground
  truth, turning at 2 rad/s per radian of error, slower when the scan sees
  something within 0.8 m ahead;
* ``--twist v,w``: a constant command.

Every message received is logged to ``--log`` as a JSON line (frames,
pose, twist, covariance); a thread logs the ``map -> LASER_FRAME`` transform
tf2 finds (a ``tf`` line) once the run is past ``--tf-after`` seconds.
Run with the system's Python: ``/usr/bin/python3 stage_user_node.py --robots 3 ...``.
"""

import argparse
import json
import math
import threading
import time

import rospy
import tf2_ros
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

NAMES = {  # the topic of each role, per name set (robot_i/ or no prefix is added)
    "stage": {"odom": "odom", "truth": "base_pose_ground_truth", "scan": "base_scan",
              "laser": "base_laser_link"},
    "mimics": {"odom": "odom", "truth": "ground_truth", "scan": "scan", "pose": "pose",
               "laser": "laser"},
}


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def planar(pose):
    return [pose.position.x, pose.position.y, yaw_of(pose.orientation)]


class Robot:
    def __init__(self, node, index, prefix):
        self.node, self.index = node, index
        self.received = {}  # stamp (ns): {role: message}
        self.answered = set()
        self.cmd_vel = rospy.Publisher(prefix + "cmd_vel", Twist, queue_size=10,
                                       tcp_nodelay=True)
        for role, topic in NAMES[node.args.names].items():
            if role == "laser":
                continue
            kind = LaserScan if role == "scan" else Odometry
            rospy.Subscriber(prefix + topic, kind, self.on_message, callback_args=role,
                             tcp_nodelay=True)

    def on_message(self, message, role):
        stamp = message.header.stamp.to_nsec()
        entry = {"kind": role, "robot": self.index, "stamp": stamp,
                 "frame": message.header.frame_id}
        if role == "scan":
            entry["ranges"] = len(message.ranges)
        else:
            entry.update(child=message.child_frame_id, pose=planar(message.pose.pose),
                         twist=[message.twist.twist.linear.x, message.twist.twist.angular.z],
                         covariance=list(message.pose.covariance))
        self.node.log(entry)
        with self.node.lock:
            self.received.setdefault(stamp, {})[role] = message
            ready = [s for s, got in self.received.items()
                     if len(got) == self.node.roles and s not in self.answered]
            for s in sorted(ready):
                self.answered.add(s)
                self.cmd_vel.publish(self.command(self.received.pop(s)))

    def command(self, got):
        twist = Twist()
        if self.node.twist is not None:
            twist.linear.x, twist.angular.z = self.node.twist
            return twist
        x, y, yaw = planar(got["truth"].pose.pose)
        gx, gy = self.node.goals[self.index]
        error = math.atan2(gy - y, gx - x) - yaw
        error = math.atan2(math.sin(error), math.cos(error))
        scan = got["scan"]
        ahead = [r for k, r in enumerate(scan.ranges)
                 if abs(scan.angle_min + k * scan.angle_increment) < math.radians(30)]
        slow = 0.3 if ahead and min(ahead) < 0.8 else 1.0
        twist.linear.x = 0.8 * max(math.cos(error), 0.0) * slow
        twist.angular.z = max(-1.0, min(1.0, 2.0 * error))
        return twist


class Node:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.out = open(args.log, "w")  # noqa: SIM115 (open while the node lives)
        self.roles = len([role for role in NAMES[args.names] if role != "laser"])
        self.twist = [float(v) for v in args.twist.split(",")] if args.twist else None
        self.goals = ([[float(v) for v in goal.split(",")] for goal in args.goals.split(";")]
                      if args.goals else None)

    def log(self, entry):
        with self.lock:
            self.out.write(json.dumps(entry) + "\n")
            self.out.flush()


def prefix_of(args, robot):
    if args.names == "stage" and args.robots == 1:
        return ""  # stageros: no namespace for a single robot
    return f"robot_{robot}/"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--robots", type=int, required=True)
    parser.add_argument("--names", default="stage", choices=sorted(NAMES))
    parser.add_argument("--goals", default="")
    parser.add_argument("--twist", default="")
    parser.add_argument("--log", required=True)
    parser.add_argument("--tf-after", type=float, default=1.0)
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node("stage_user")
    node = Node(args)
    buffer = tf2_ros.Buffer()
    tf2_ros.TransformListener(buffer)
    [Robot(node, i, prefix_of(args, i)) for i in range(args.robots)]
    laser = prefix_of(args, 0) + NAMES[args.names]["laser"]
    while not rospy.is_shutdown():  # wall-clock polling: never blocks the answers
        try:
            found = buffer.lookup_transform("map", laser, rospy.Time(0))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException):
            found = None
        if found is not None and found.header.stamp.to_sec() >= args.tf_after:
            t, q = found.transform.translation, found.transform.rotation
            node.log({"kind": "tf", "frame": laser, "stamp": found.header.stamp.to_nsec(),
                      "pose": [t.x, t.y, yaw_of(q)]})
            break
        time.sleep(0.01)
    rospy.spin()


if __name__ == "__main__":
    main()
