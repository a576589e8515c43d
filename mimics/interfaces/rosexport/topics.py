"""The topics and frames of an exported run: the live bridge's, under either name set.

Robot topics and frames come from the bridge's own
:class:`~mimics.interfaces.ros.names.RosNames` (``mimics`` or ``stage``), so
an export carries the names ``mimics ros --names ...`` publishes; with the
``mimics`` names and robot ``i``:

========================= ============================== =====================================
topic                     type                           what
========================= ============================== =====================================
``/map``                  nav_msgs/OccupancyGrid         the walls rasterised, once, at time 0
``/tf_static``            tf2_msgs/TFMessage             ``robot_i/base_link -> robot_i/laser``
``/tf``                   tf2_msgs/TFMessage             ``map -> robot_i/odom ->
                                                         robot_i/base_link`` every step
``/robot_i/odom``         nav_msgs/Odometry              the odometer in ``robot_i/odom``
``/robot_i/pose``         nav_msgs/Odometry              the positioning sensor's pose
``/robot_i/ground_truth`` nav_msgs/Odometry              true pose and velocity
``/robot_i/scan``         sensor_msgs/LaserScan          the recorded scan (``--record-scans``)
``/markers``              visualization_msgs/MarkerArray footprints and goals, at time 0 and
                                                         whenever a robot's status changes
========================= ============================== =====================================

With the ``stage`` names: ``odom``, ``base_pose_ground_truth``, ``base_scan``
(no ``pose``), frames ``odom -> base_footprint -> base_link ->
base_laser_link``, under ``robot_i/`` only when the run has several robots.
"""

from __future__ import annotations

# re-exported: the bridge's modules import it from here too
from mimics.interfaces.ros.names import MAP_FRAME as MAP_FRAME

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
