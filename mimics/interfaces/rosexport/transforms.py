"""tf2_msgs/TFMessage: the live bridge's frame tree (REP 105), for RViz's and Foxglove's 3D views.

``/tf`` gets one message per recorded step holding, for every robot with a
row at that step, ``map -> odom`` (the correction ``T(measured) *
T(odometer)^-1`` that puts the body at the positioning sensor's pose, as a
localiser would publish it) and ``odom -> body`` (the rebuilt odometer,
:mod:`~.odometer`), exactly what ``mimics ros`` publishes. When the odometer
cannot be rebuilt, ``map -> body`` at the measured pose instead (no ``odom``
frame). ``/tf_static`` gets one message at time 0 holding ``base_footprint ->
base_link`` (``stage`` names) and ``base_link -> laser`` (robots with a
ranger), both the identity: the engine's ranger sits at the robot's centre,
looking along its heading. Frame names from
:class:`~mimics.interfaces.ros.names.RosNames`; the correction and the fixed
frames are computed by the live bridge's own pure functions
(:mod:`mimics.interfaces.ros.planar`, :mod:`mimics.interfaces.ros.readings`).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np

from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.planar import odom_correction
from mimics.interfaces.ros.readings import fixed_frames
from mimics.interfaces.rosexport.conversion import Messages, Stamped, nanoseconds
from mimics.interfaces.rosexport.odometer import OdometerTrack, step_bounds
from mimics.interfaces.rosexport.source import Trajectory
from mimics.interfaces.rosexport.topics import TF_MESSAGE, TF_STATIC_TOPIC, TF_TOPIC


def tf_messages(messages: Messages, trajectory: Trajectory, names: RosNames,
                odometer: OdometerTrack | None) -> Iterator[Stamped]:
    """One TFMessage per recorded step, in step order."""
    measured = np.column_stack((trajectory.x_meas, trajectory.y_meas, trajectory.theta_meas))
    for _, start, end in step_bounds(trajectory):
        stamp = int(trajectory.stamp[start])
        transforms: list[Any] = []
        for k in range(start, end):
            robot = int(trajectory.robot[k])
            body = names.body_frame(robot)
            if odometer is None:
                transforms.append(messages.transform(stamp, MAP_FRAME, body, *measured[k]))
                continue
            odom = names.odom_frame(robot)
            transforms.append(messages.transform(stamp, MAP_FRAME, odom,
                                                 *odom_correction(measured[k], odometer.pose[k])))
            transforms.append(messages.transform(stamp, odom, body, *odometer.pose[k]))
        yield Stamped(stamp, TF_TOPIC, messages.make(TF_MESSAGE, transforms=transforms))


def tf_static_messages(messages: Messages, names: RosNames,
                       beam_count: np.ndarray) -> Iterator[Stamped]:
    """The one static TFMessage: the live bridge's identity frames (each robot's body on
    its footprint, its laser on its body)."""
    start = nanoseconds(0.0)
    transforms = [messages.transform(start, parent, child, 0.0, 0.0, 0.0)
                  for parent, child in fixed_frames(beam_count, names)]
    yield Stamped(start, TF_STATIC_TOPIC, messages.make(TF_MESSAGE, transforms=transforms))
