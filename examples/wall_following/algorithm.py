"""Wall following: keep a wall on the right at a set distance, turn left at corners.

Sensors: the laser (beams to the right, front-right and ahead).

A proportional rule on the distance to the wall: too close turns left, too far
turns right; a wall ahead makes the robot stop and turn left on the spot; a
lost wall (an open corner) makes it curve right to find it again.
"""

import numpy as np

DISTANCE = 0.6  # m kept between the robot's centre and the wall on its right
GAIN = 1.2  # rad of heading change per metre of distance error
CRUISE = 0.3  # m/s


def _nearest(ranges, angles, centre, half_width):
    """The shortest reading among the beams within ``half_width`` of ``centre`` (rad)."""
    window = np.abs(angles - centre) <= half_width
    return ranges[window].min()


def step(robot):
    """Follow the wall on the right."""
    ranges, angles = robot.scan.ranges, robot.scan.angles
    ahead = _nearest(ranges, angles, 0.0, np.pi / 10)
    right = _nearest(ranges, angles, -np.pi / 2, np.pi / 12)
    front_right = _nearest(ranges, angles, -np.pi / 4, np.pi / 12) * np.cos(np.pi / 4)
    wall = min(right, front_right)  # distance to the wall on the right, corners included
    if ahead < DISTANCE + robot.type.length / 2:  # wall ahead: turn left on the spot
        robot.log("corner: turning left")
        return 0.0, robot.heading + np.pi / 3
    if wall > 2.5 * DISTANCE:  # no wall on the right: curve right to find one
        return CRUISE, robot.heading - 0.5
    turn = np.clip(GAIN * (DISTANCE - wall), -0.6, 0.6)
    return CRUISE * np.cos(turn), robot.heading + turn
