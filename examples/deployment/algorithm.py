"""Deployment: spread out into the free space using only the laser.

Sensors: the laser. The paper's deployment controller took 54 lines of MATLAB
and 133 of C++ for Stage; this is the same behaviour in a few lines.

Each reading, as a vector along its beam, pulls toward open space: their sum
points where there is most room. Drive that way while nothing is close ahead.
"""

import numpy as np


def step(robot):
    """Head for the most open space; stop and turn when something is close ahead."""
    ranges, angles = robot.scan.ranges, robot.scan.angles
    open_x, open_y = np.sum(ranges * np.cos(angles)), np.sum(ranges * np.sin(angles))
    turn = np.arctan2(open_y, open_x)  # direction of open space, relative to the heading
    ahead = ranges[np.abs(angles) < np.pi / 4].min()  # nearest thing in a 90° cone ahead
    room = 2.5 * robot.type.length  # keep this much free space in front
    cruise = 0.6 * robot.type.max_speed
    speed = cruise if ahead > room and abs(turn) < 0.6 else 0.0
    return speed, robot.heading + turn
