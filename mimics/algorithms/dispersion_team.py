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
    cos, sin, seen_within, aside, max_speed = _team_constants(team)
    push = np.fmax(seen_within - ranges, 0.0)  # fmax, unlike maximum, makes a NaN pad 0
    # np.add.reduce and np.logical_and.reduce: np.sum and np.all without their Python
    # wrappers (the same numbers; a few microseconds a call, a tenth of a small team's step)
    px = -np.add.reduce(push * cos, axis=1)
    py = -np.add.reduce(push * sin, axis=1)
    seen = (px != 0.0) | (py != 0.0)
    turn = np.arctan2(py, px)
    theta = team.pose[:, 2]
    clear = np.logical_and.reduce((push <= 0.0) | aside, axis=1)
    speed = np.where(seen & clear, max_speed * np.maximum(np.cos(turn), 0.0), 0.0)
    return speed, np.where(seen, theta + turn, theta)


def _team_constants(team):
    """What depends only on which robots are in the team: the beams' cosines and sines
    (0 for the NaN pads), the reading below which a beam sees something, which beams
    lie outside the front (the pads too) and the top speeds. Kept in the team's memory
    until the team changes: at a hundred robots, working them out was a third of a call."""
    key = team.ids.tobytes()
    kept = team.memory.get("dispersion_team.constants")
    if kept is None or kept[0] != key:
        angles = team.scan.angles
        # robots whose beams all point alike (one robot type): worked out for one row
        # and broadcast (100,000 robots: 2 ms rather than 50)
        rows = angles[:1] if np.array_equal(angles, np.broadcast_to(angles[:1], angles.shape),
                                             equal_nan=True) else angles
        unpadded = np.where(np.isnan(rows), 0.0, rows)
        aside = ~(np.abs(rows) < FRONT)  # NaN compares false: pads are aside
        cos, sin = np.cos(unpadded), np.sin(unpadded)
        kept = (key, *(np.broadcast_to(values, angles.shape) for values in (cos, sin)),
                SEEN * team.scan.max_range[:, None], np.broadcast_to(aside, angles.shape),
                team.max_speed)
        team.memory["dispersion_team.constants"] = kept
    return kept[1:]
