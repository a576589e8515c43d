"""Rendezvous by consensus: robots agree on a meeting point by messages, then meet there.

Sensors: the communication system (the comms matrix for neighbours' positions,
messages for their estimates), the laser (to stop short of others), the pose.

Every robot keeps an estimate of the meeting point, starting at its own
position. Each step it broadcasts its estimate and moves it toward the average
of the estimates it received (linear consensus: all estimates converge to the
average of the starting positions when everyone hears everyone, and to a
common point whenever the comms graph stays connected). It drives toward its
estimate and stops when it is near the meeting point or something is close
ahead, so the robots gather in a cluster without touching.
"""

import numpy as np

RATE = 0.3  # consensus step: the fraction of the disagreement removed each step
GATHERED = 1.0  # m from the meeting point counts as arrived
CLEARANCE = 0.6  # m kept free ahead


def step(robot):
    """Update the estimate from the neighbours' messages, then drive toward it."""
    x, y, theta = robot.pose
    estimate = robot.memory.setdefault("estimate", np.array([x, y]))
    received = [np.asarray(message) for _, message in robot.inbox]
    if received:
        estimate += RATE * (np.mean(received, axis=0) - estimate)
    robot.send(estimate.copy())  # to every robot in range, delivered next step

    dx, dy = estimate - (x, y)
    distance = np.hypot(dx, dy)
    heading = np.arctan2(dy, dx)
    ahead = robot.scan.ranges[np.abs(robot.scan.angles) < np.pi / 6].min()
    if distance < GATHERED or ahead < CLEARANCE + robot.type.length / 2:
        return 0.0, heading
    speed = min(0.5 * robot.type.max_speed, distance) * max(np.cos(heading - theta), 0.0)
    return speed, heading
