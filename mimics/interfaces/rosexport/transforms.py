"""tf2_msgs/TFMessage: where each robot is, for RViz's and Foxglove's 3D views.

``/tf`` gets one message per recorded step holding ``map -> robot_i/base_link``
(the true pose) for every robot with a row at that step; ``/tf_static`` one
message at time 0 holding ``robot_i/base_link -> robot_i/laser`` (identity: the
engine's ranger sits at the robot's centre, looking along its heading).
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from mimics.interfaces.rosexport.conversion import Messages, Stamped, nanoseconds
from mimics.interfaces.rosexport.source import Trajectory
from mimics.interfaces.rosexport.topics import (
    MAP_FRAME,
    TF_MESSAGE,
    TF_STATIC_TOPIC,
    TF_TOPIC,
    base_link,
    laser_frame,
)


def tf_messages(messages: Messages, trajectory: Trajectory) -> Iterator[Stamped]:
    """One TFMessage per recorded step, in step order."""
    starts = np.flatnonzero(np.diff(trajectory.step, prepend=-1) != 0)
    ends = np.append(starts[1:], trajectory.rows)
    for start, end in zip(starts, ends, strict=True):
        stamp = int(trajectory.stamp[start])
        transforms = [messages.transform(stamp, MAP_FRAME, base_link(int(trajectory.robot[k])),
                                         trajectory.x[k], trajectory.y[k], trajectory.theta[k])
                      for k in range(start, end)]
        yield Stamped(stamp, TF_TOPIC, messages.make(TF_MESSAGE, transforms=transforms))


def tf_static_messages(messages: Messages, robots: int) -> Iterator[Stamped]:
    """The one static TFMessage: every robot's laser frame on its body."""
    start = nanoseconds(0.0)
    transforms = [messages.transform(start, base_link(i), laser_frame(i), 0.0, 0.0, 0.0)
                  for i in range(robots)]
    yield Stamped(start, TF_STATIC_TOPIC, messages.make(TF_MESSAGE, transforms=transforms))
