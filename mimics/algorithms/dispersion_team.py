"""``dispersion`` for a whole team at once, vectorised with NumPy.

Same logic and same results as the per-robot ``dispersion``: every robot
heads away from what its beams see (each beam pushing by ``SEEN * range - reading``)
and stops when nothing is in range.
"""

import numpy as np

from mimics.algorithms.dispersion import FRONT, SEEN


def team_step(team):
    """One row per robot: head away from what is near, stop when nothing is."""
    ranges = team.scan.ranges  # (robots, beams); NaN pads for robots with fewer beams
    angles = team.scan.angles
    push = SEEN * team.scan.max_range[:, None] - ranges
    push = np.where(push > 0.0, push, 0.0)  # NaN compares false: pads push nothing
    px = -np.sum(push * np.cos(np.where(np.isnan(angles), 0.0, angles)), axis=1)
    py = -np.sum(push * np.sin(np.where(np.isnan(angles), 0.0, angles)), axis=1)
    seen = (px != 0.0) | (py != 0.0)
    turn = np.arctan2(py, px)
    theta = team.pose[:, 2]
    clear = np.all((push <= 0.0) | ~(np.abs(angles) < FRONT), axis=1)  # NaN pads: clear
    speed = np.where(seen & clear, team.max_speed * np.maximum(np.cos(turn), 0.0), 0.0)
    return speed, np.where(seen, theta + turn, theta)
