"""A test node for what ROS tools look for: parameters, markers and the run's services.

Every robot's odometry is answered with a constant Twist (``SPEED``, ``RATE``),
so a lockstep run is the same whatever the timing. One ``--mode`` per test:

* ``observe``: on the first ``/clock`` it reads ``/use_sim_time``, the
  ``/mimics`` tree and the topics published; it keeps every
  ``/mimics/markers`` message. At exit (SIGINT) it prints one JSON line:
  ``{"sim_time_at_first_clock", "params", "topics",
  "markers": [[stamp_ns, [[ns, id, frame, x, y, type, text], ...]], ...]}``.
* ``control``: once ``/clock`` reaches ``--at`` it calls ``/mimics/pause``,
  waits ``--quiet`` wall seconds, keeps the clocks that came during a second
  ``--quiet`` (none expected), calls ``/mimics/step`` and keeps the clocks of
  the next ``--quiet`` seconds, calls ``/mimics/resume``, waits for the clock
  to pass ``--reset-at`` and calls ``/mimics/reset``, then waits for the
  clock to jump back. Prints one JSON line: each service's ``[success,
  message]`` and the clocks seen (the first five after the jump back).
* ``sleepy``: sleeps 0.05 s of ROS time before it subscribes (as many nodes
  wait for something at their start), then answers as the others.

Run with the system's Python: ``/usr/bin/python3 control_node.py --mode observe --robots 2``.
"""

import argparse
import json
import threading
import time

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

SPEED, RATE = 0.3, 0.2


def answer_every_robot(robots):
    publishers = [rospy.Publisher(f"/robot_{i}/cmd_vel", Twist, queue_size=10,
                                  tcp_nodelay=True) for i in range(robots)]
    command = Twist()
    command.linear.x, command.angular.z = SPEED, RATE

    def on_odom(_message, robot):
        publishers[robot].publish(command)

    for i in range(robots):
        rospy.Subscriber(f"/robot_{i}/odom", Odometry, on_odom, callback_args=i,
                         tcp_nodelay=True)


def observe(args):
    found = {"sim_time_at_first_clock": None, "params": None, "topics": [], "markers": []}
    lock = threading.Lock()

    def on_clock(_message):
        with lock:
            if found["params"] is None:
                found["sim_time_at_first_clock"] = rospy.get_param("/use_sim_time", None)
                found["params"] = rospy.get_param("/mimics", None)
                found["topics"] = sorted(name for name, _ in rospy.get_published_topics())

    def on_markers(message):
        rows = [[m.ns, m.id, m.header.frame_id, m.pose.position.x, m.pose.position.y,
                 m.type, m.text] for m in message.markers]
        stamp = message.markers[0].header.stamp.to_nsec() if message.markers else -1
        with lock:
            found["markers"].append([stamp, rows])

    def report():
        with lock:
            print(json.dumps(found), flush=True)

    rospy.Subscriber("/clock", Clock, on_clock)
    rospy.Subscriber("/mimics/markers", MarkerArray, on_markers, queue_size=100)
    rospy.on_shutdown(report)
    answer_every_robot(args.robots)
    rospy.spin()


def control(args):
    clocks = []
    lock = threading.Lock()

    def on_clock(message):
        with lock:
            clocks.append(message.clock.to_nsec())

    def since(start):
        with lock:
            return clocks[start:]

    def wait_clock(predicate):
        while not rospy.is_shutdown():
            with lock:
                if clocks and predicate(clocks[-1]):
                    return len(clocks)
            time.sleep(0.01)
        raise SystemExit(1)

    rospy.Subscriber("/clock", Clock, on_clock, tcp_nodelay=True)
    services = {}
    for name in ("pause", "resume", "step", "reset"):
        rospy.wait_for_service(f"/mimics/{name}", timeout=60)
        services[name] = rospy.ServiceProxy(f"/mimics/{name}", Trigger)
    answer_every_robot(args.robots)  # only now: the run cannot start without our answers
    report = {"refused_step": list(_call(services["step"]))}
    at = round(args.at * 1e9)
    wait_clock(lambda ns: ns >= at)
    report["pause"] = _call(services["pause"])
    time.sleep(args.quiet)
    start = len(clocks)
    report["last_clock_paused"] = clocks[-1]
    time.sleep(args.quiet)
    report["clocks_while_paused"] = since(start)
    start = len(clocks)
    report["step"] = _call(services["step"])
    time.sleep(args.quiet)
    report["clocks_after_step"] = since(start)
    report["resume"] = _call(services["resume"])
    reset_at = round(args.reset_at * 1e9)
    start = wait_clock(lambda ns: ns >= reset_at)
    report["reset"] = _call(services["reset"])
    before = since(start - 1)[0]
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and not any(ns < before for ns in since(start)):
        time.sleep(0.01)  # until the clock has jumped back (or 10 s)
    report["clock_before_reset"] = before
    report["clocks_after_reset"] = [ns for ns in since(start) if ns < before][:5]
    print(json.dumps(report), flush=True)
    rospy.spin()


def sleepy(args):
    rospy.sleep(0.05)  # ROS time: waits for a /clock when the node started with use_sim_time
    answer_every_robot(args.robots)
    rospy.spin()


def _call(proxy):
    response = proxy()
    return [response.success, response.message]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--mode", choices=["observe", "control", "sleepy"], required=True)
    parser.add_argument("--robots", type=int, default=2)
    parser.add_argument("--at", type=float, default=0.5)
    parser.add_argument("--reset-at", type=float, default=1.0)
    parser.add_argument("--quiet", type=float, default=0.5)
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node("control_test")
    {"observe": observe, "control": control, "sleepy": sleepy}[args.mode](args)


if __name__ == "__main__":
    main()
