"""Topic and frame names of a run's robots, for each name set the bridge speaks.

Every publisher, subscriber and frame of the bridge takes its names from a
:class:`RosNames`, so no module spells a topic itself. Two name sets:

``mimics`` (the default): every robot under ``robot_i/``, whatever the
robot count::

    /robot_i/odom          nav_msgs/Odometry  odometer, frame robot_i/odom, child robot_i/base_link
    /robot_i/pose          nav_msgs/Odometry  positioning sensor, frame map
    /robot_i/ground_truth  nav_msgs/Odometry  true pose and velocity, frame map
    /robot_i/scan          sensor_msgs/LaserScan, frame robot_i/laser
    /robot_i/goal          geometry_msgs/PoseStamped (latched), frame map
    /robot_i/cmd, /robot_i/cmd_vel (subscribed)
    tf: map -> robot_i/odom -> robot_i/base_link -> robot_i/laser

``stage`` (what ``stage_ros``' ``stageros`` node publishes): under
``robot_i/`` only when the run has more than one robot, no prefix at all
for a single robot (``stageros``' ``mapName``)::

    odom                    nav_msgs/Odometry  odometer, frame odom, child base_footprint
    base_pose_ground_truth  nav_msgs/Odometry  true pose and velocity, frame map
    base_scan               sensor_msgs/LaserScan (base_scan_0, base_scan_1... with several
                            rangers), frame base_laser_link (base_laser_link_0...)
    goal                    geometry_msgs/PoseStamped (latched; stage_ros has none)
    is_crashed              std_msgs/Int8: 1 once stalled (collided), else 0, as the
                            stage_ros forks that publish Stage's stall flag name it
    cmd_vel (subscribed)
    tf: [map ->] odom -> base_footprint -> base_link -> base_laser_link

Frame ids carry no leading slash (``robot_0/odom``, where ``stageros``
writes ``/robot_0/odom``): tf2 refuses frame ids that start with one.

>>> names = RosNames("stage", robots=1)
>>> names.odom(0), names.scan(0), names.odom_frame(0), names.laser_frame(0)
('/odom', '/base_scan', 'odom', 'base_laser_link')
>>> names = RosNames("stage", robots=3)
>>> names.odom(2), names.scan(2, ranger=1, rangers=2), names.footprint_frame(2)
('/robot_2/odom', '/robot_2/base_scan_1', 'robot_2/base_footprint')
>>> RosNames("mimics", robots=1).ground_truth(0)
'/robot_0/ground_truth'
"""

from __future__ import annotations

from dataclasses import dataclass

from mimics.world.errors import MimicsError

NAME_SETS = ("mimics", "stage")
MAP_FRAME = "map"


def check_name_set(name_set: str, where: str = "names") -> str:
    """``name_set`` if it is one of :data:`NAME_SETS`.

    Raises:
        MimicsError: naming ``where`` and the sets known.
    """
    if name_set not in NAME_SETS:
        raise MimicsError(f"{where}: expected one of {', '.join(NAME_SETS)}, got {name_set!r}")
    return name_set


@dataclass(frozen=True)
class RosNames:
    """The names of every topic and frame of a run's ``robots`` robots under ``name_set``."""

    name_set: str = "mimics"
    robots: int = 1

    def __post_init__(self) -> None:
        check_name_set(self.name_set)

    @property
    def stage(self) -> bool:
        """Whether these are ``stage_ros``' names."""
        return self.name_set == "stage"

    def prefix(self, robot: int) -> str:
        """The namespace of a robot's topics and frames: ``robot_3/``, or ``""``.

        ``stage``: empty when the run has one robot, as ``stageros`` does.
        """
        if self.stage and self.robots == 1:
            return ""
        return f"robot_{robot}/"

    def _topic(self, robot: int, name: str) -> str:
        return f"/{self.prefix(robot)}{name}"

    def _frame(self, robot: int, name: str) -> str:
        return f"{self.prefix(robot)}{name}"

    # -- topics ----------------------------------------------------------------

    def odom(self, robot: int) -> str:
        """The odometer's topic (``nav_msgs/Odometry`` in :meth:`odom_frame`)."""
        return self._topic(robot, "odom")

    def pose(self, robot: int) -> str | None:
        """The positioning sensor's topic (pose in ``map``); None under ``stage``."""
        return None if self.stage else self._topic(robot, "pose")

    def ground_truth(self, robot: int) -> str:
        """The true pose's topic (``nav_msgs/Odometry`` in ``map``)."""
        return self._topic(robot, "base_pose_ground_truth" if self.stage else "ground_truth")

    def scan(self, robot: int, ranger: int = 0, rangers: int = 1) -> str:
        """Ranger ``ranger`` of ``rangers``'s topic: ``base_scan`` (``base_scan_1`` of several)."""
        if not self.stage:
            return self._topic(robot, "scan" if rangers == 1 else f"scan_{ranger}")
        return self._topic(robot, "base_scan" if rangers == 1 else f"base_scan_{ranger}")

    def goal(self, robot: int) -> str:
        """The latched goal's topic."""
        return self._topic(robot, "goal")

    def stall(self, robot: int) -> str | None:
        """The stall flag's topic (``std_msgs/Int8``): ``is_crashed`` under ``stage``,
        the name stage_ros forks give Stage's ``Stalled()``; None under ``mimics``."""
        return self._topic(robot, "is_crashed") if self.stage else None

    def cmd(self, robot: int) -> str | None:
        """The reference command's topic (``[speed_ref, heading_ref]``); None under ``stage``."""
        return None if self.stage else self._topic(robot, "cmd")

    def cmd_vel(self, robot: int) -> str:
        """The velocity command's topic (``geometry_msgs/Twist``)."""
        return self._topic(robot, "cmd_vel")

    def command_topics(self, robot: int) -> tuple[str, ...]:
        """Every topic the robot listens to for commands."""
        cmd = self.cmd(robot)
        return (cmd, self.cmd_vel(robot)) if cmd is not None else (self.cmd_vel(robot),)

    def commands_text(self, robot: int | None = None) -> str:
        """The command topics in a message: ``/robot_3/cmd or cmd_vel``; robot None:
        ``/robot_i/cmd or /robot_i/cmd_vel`` (every robot)."""
        if robot is None:
            topics = [topic.replace("robot_0/", "robot_i/") for topic in self.command_topics(0)]
            return " or ".join(topics)
        first, *others = self.command_topics(robot)
        return " or ".join([first, *(topic.rsplit("/", 1)[1] for topic in others)])

    # -- frames ----------------------------------------------------------------

    def odom_frame(self, robot: int) -> str:
        """The frame the odometer's pose lives in: the robot's start pose in ``map``."""
        return self._frame(robot, "odom")

    def footprint_frame(self, robot: int) -> str | None:
        """``base_footprint`` (under ``stage``), the odometer's child frame; else None."""
        return self._frame(robot, "base_footprint") if self.stage else None

    def base_frame(self, robot: int) -> str:
        """The robot's body frame: its centre, x forward."""
        return self._frame(robot, "base_link")

    def body_frame(self, robot: int) -> str:
        """The odometry's child frame: ``base_footprint`` under ``stage``, else ``base_link``."""
        return self.footprint_frame(robot) or self.base_frame(robot)

    def laser_frame(self, robot: int, ranger: int = 0, rangers: int = 1) -> str:
        """Ranger ``ranger`` of ``rangers``'s frame."""
        name = "base_laser_link" if self.stage else "laser"
        return self._frame(robot, name if rangers == 1 else f"{name}_{ranger}")
