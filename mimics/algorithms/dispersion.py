"""Dispersion: move away from whatever the short range beams see; stop when nothing is near.

Each beam that reads less than the sensor's range pushes the robot away
along it, the harder the nearer the obstacle (``SEEN * range - reading``). The
robot heads along the sum of the pushes, driving at full speed times how well
it faces that way when its front beams (within ``FRONT``) see nothing, else
turning on the spot; with nothing in sight it stops where it is. A packed
swarm spreads out until no beam sees a neighbour (eight beams leave gaps, and
robots can still bump: the beams behind do not stop the one behind them).
"""

import numpy as np

# a beam reading beyond this share of its range sees nothing: the sensor noise
# (e-puck: 3 mm of 0.1 m) must not set a lone robot creeping
SEEN = 0.85
# drive only when the beams this close to the heading see nothing (else turn on the spot)
FRONT = np.pi / 3


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
    clear = bool(np.all((push <= 0.0) | (np.abs(angles) >= FRONT)))
    speed = robot.type.max_speed * max(np.cos(turn), 0.0) if clear else 0.0
    return speed, robot.heading + turn
