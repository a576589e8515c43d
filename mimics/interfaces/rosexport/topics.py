"""The topics and frames of an exported run, named in one place.

========================== ============================= ==========================================
topic                      type                          what
========================== ============================= ==========================================
``/map``                   nav_msgs/OccupancyGrid        the walls rasterised, once, at time 0
``/tf_static``             tf2_msgs/TFMessage            ``robot_i/base_link -> robot_i/laser``
``/tf``                    tf2_msgs/TFMessage            ``map -> robot_i/base_link`` every step
``/robot_i/ground_truth``  nav_msgs/Odometry             true pose and velocity every step
``/robot_i/scan``          sensor_msgs/LaserScan         the recorded scan (with ``--record-scans``)
``/markers``               visualization_msgs/MarkerArray footprints and goals, at time 0 and
                                                         whenever a robot's status changes
========================== ============================= ==========================================

>>> base_link(3), truth_topic(3), scan_topic(3)
('robot_3/base_link', '/robot_3/ground_truth', '/robot_3/scan')
"""

from __future__ import annotations

MAP_FRAME = "map"
MAP_TOPIC = "/map"
TF_TOPIC = "/tf"
TF_STATIC_TOPIC = "/tf_static"
MARKERS_TOPIC = "/markers"

OCCUPANCY_GRID = "nav_msgs/msg/OccupancyGrid"
ODOMETRY = "nav_msgs/msg/Odometry"
LASER_SCAN = "sensor_msgs/msg/LaserScan"
MARKER_ARRAY = "visualization_msgs/msg/MarkerArray"
TF_MESSAGE = "tf2_msgs/msg/TFMessage"

#: topics whose last message stays valid (latched in ROS 1, transient local in ROS 2)
LATCHED = (MAP_TOPIC, TF_STATIC_TOPIC)


def robot_namespace(robot: int) -> str:
    """The name prefix of robot ``robot``'s frames and topics (0-based index)."""
    return f"robot_{robot}"


def base_link(robot: int) -> str:
    """Robot ``robot``'s body frame: x along its heading, z up, at its centre."""
    return f"{robot_namespace(robot)}/base_link"


def laser_frame(robot: int) -> str:
    """Robot ``robot``'s laser frame (at its centre, as the engine's ranger)."""
    return f"{robot_namespace(robot)}/laser"


def truth_topic(robot: int) -> str:
    """Robot ``robot``'s true pose topic: the live bridge's ``ground_truth`` (its ``odom``
    is the odometer, which a run folder does not record)."""
    return f"/{robot_namespace(robot)}/ground_truth"


def scan_topic(robot: int) -> str:
    """Robot ``robot``'s laser scan topic."""
    return f"/{robot_namespace(robot)}/scan"
