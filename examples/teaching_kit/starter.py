"""Starter for the assignment "Crossing without collisions" (see ASSIGNMENT.md).

As handed out, this drives straight to the goal and ignores everyone else:
on the crossroads all four robots meet in the middle. Make them pass.
"""

import numpy as np


def step(robot):
    """Return (speed reference in m/s, absolute heading reference in rad)."""
    if robot.goal is None:
        return 0.0, robot.heading
    x, y, theta = robot.pose
    gx, gy = robot.goal
    heading = np.arctan2(gy - y, gx - x)
    speed = min(robot.type.max_speed, np.hypot(gx - x, gy - y)) * max(np.cos(heading - theta), 0)

    # Your avoidance goes here. At hand, each in one line:
    #   robot.scan.ranges, robot.scan.angles   the laser (robots show up in it)
    #   robot.comms                            rows [id, x, y, theta, v, w] of every robot
    #                                          in range, this one's own row included
    #   robot.memory                           a dict kept between your steps
    return speed, heading
