"""The QoS of each topic, as ROS 2 nodes publish and subscribe them.

* commands, odometry, ground truth, scans, ``/tf`` and markers: reliable,
  volatile, keep-last 10 (rclcpp's default, what ``stage_ros2`` publishes
  its ``base_scan`` with: a best-effort reader, ``SensorDataQoS``, matches
  a reliable writer too);
* ``/clock``: reliable, keep-last 1 (rclcpp's clock subscription is best
  effort, which a reliable writer serves);
* ``/tf_static``: reliable, transient local, keep-last 100 (tf2_ros' static
  broadcaster); ``/map`` and the goals: reliable, transient local,
  keep-last 1, so a node that starts later still gets them;
* services' requests and replies: reliable, volatile, keep-last 10
  (``rmw_qos_profile_services_default``).

Every writer announces XCDR1 only (plain CDR, what ROS 2's middlewares
send); readers accept XCDR1 and XCDR2.
"""

from __future__ import annotations

from cyclonedds.qos import Policy, Qos

_BLOCKING = 100_000_000  # ns a reliable write may wait for room in the history
_XCDR1 = Policy.DataRepresentation(use_cdrv0_representation=True)
_ANY = Policy.DataRepresentation(use_cdrv0_representation=True,
                                 use_xcdrv2_representation=True)


def _qos(depth: int, latched: bool, representation: Policy.DataRepresentation) -> Qos:
    durability = Policy.Durability.TransientLocal if latched else Policy.Durability.Volatile
    return Qos(Policy.Reliability.Reliable(max_blocking_time=_BLOCKING), durability,
               Policy.History.KeepLast(depth), representation)


STREAM = _qos(10, False, _XCDR1)  # odometry, scans, /tf, markers
CLOCK = _qos(1, False, _XCDR1)
LATCHED = _qos(1, True, _XCDR1)  # /map, goals
TF_STATIC = _qos(100, True, _XCDR1)
COMMANDS = _qos(10, False, _ANY)  # the cmd_vel readers
SERVICES = _qos(10, False, _XCDR1)  # the replies
SERVICE_REQUESTS = _qos(10, False, _ANY)
