"""Dispersion: move away from whatever the short range beams see; stop when nothing is near.

Each beam that reads less than the sensor's range pushes the robot away
along it, the harder the nearer the obstacle (``SEEN * range - reading``). The
robot heads along the sum of the pushes, driving at full speed times how well
it faces that way; with nothing in sight it stops where it is. A packed swarm
spreads out until every robot is out of its neighbours' sensor range.
"""

import numpy as np

# a beam reading beyond this share of its range sees nothing: the sensor noise
# (e-puck: 3 mm of 0.1 m) must not set a lone robot creeping
SEEN = 0.85


def step(robot):
    """Head away from what is near; stop when nothing is."""
    ranges = robot.scan.ranges
    angles = robot.scan.angles
    push = SEEN * robot.scan.max_range - ranges
    push = np.where(push > 0.0, push, 0.0)
    px = -np.sum(push * np.cos(angles))
    py = -np.sum(push * np.sin(angles))
    if not (px != 0.0 or py != 0.0):
        return 0.0, robot.heading
    turn = np.arctan2(py, px)
    return robot.type.max_speed * max(np.cos(turn), 0.0), robot.heading + turn
