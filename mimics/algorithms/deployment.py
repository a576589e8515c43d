"""Deployment: spread out to fill the free space, steering by the laser (Stage's "expand").

The paper's benchmark behaviour for the Cave and the Hospital. Each robot adds
up its range readings as vectors (each reading times the unit vector of its
beam), so that open directions, which read the most, weigh the most: the sum
points to the most open space. The robot turns toward it, and drives forward
at a constant speed only while it faces that way and the beams ahead read
more than a safety distance, which shrinks toward the sides; otherwise it
stops and turns on the spot. No goals are used.

The constants are in robot lengths, fractions of the robot's top speed and
of its laser's range, so the same code drives a Pioneer2DX (8 m laser) and a
0.1 m swarm robot (2 m laser). ``deployment_team`` is the same logic for the
whole team at once.
"""

import numpy as np

SPEED = 2 / 3  # cruising speed, as a fraction of the robot's top speed
MAX_TURN = 0.5  # rad: drive only when the open space is at most this far off the heading
REACH = 1.0  # robot lengths of free space needed on every side (room to turn on the spot)
AHEAD = 2.0  # extra room to stop straight ahead: this many robot lengths, or...
STOPPING = 3.0  # ...the distance covered in this many seconds at cruising speed if longer
# (the speed loop takes about that long to bring a robot to rest)...
AHEAD_RANGE = 0.25  # ...but at most this fraction of the laser's range


def step(robot):
    """Turn toward the most open space; drive when facing it with room ahead."""
    ranges = robot.scan.ranges
    sin_cos, needed, cruise = _constants(robot)
    # the readings as vectors in the robot's frame: their sum points to open space
    # both sums in one call; array methods: the same sums as np.sum, less overhead
    y, x = (ranges * sin_cos).sum(axis=1)
    turn = np.arctan2(y, x)
    speed = cruise if abs(turn) < MAX_TURN and (ranges > needed).all() else 0.0
    return speed, robot.heading + turn


def _constants(robot):
    """Sine and cosine of the beam angles (one row each), the free space needed along
    each beam, and the cruising speed.

    None of them changes during a run, so they are worked out once and kept in
    the robot's memory: the trigonometry is most of the cost of a step otherwise.
    """
    kept = robot.memory.get("deployment.constants")
    if kept is None:
        angles = robot.scan.angles
        cos = np.cos(angles)
        # free space needed along each beam: REACH all round, more and more toward the front
        length, cruise = robot.type.length, SPEED * robot.type.max_speed
        ahead = min(max(AHEAD * length, STOPPING * cruise), AHEAD_RANGE * robot.scan.max_range)
        needed = REACH * length + ahead * np.maximum(cos, 0.0)
        kept = robot.memory["deployment.constants"] = (np.stack([np.sin(angles), cos]), needed,
                                                       cruise)
    return kept
