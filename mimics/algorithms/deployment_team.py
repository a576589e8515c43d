"""``deployment`` for a whole team at once, vectorised with NumPy.

Same logic and same results as the per-robot ``deployment``: every robot
turns toward the sum of its range readings as vectors, and drives only when
facing it with the beams ahead reading more than a safety distance.
"""

import numpy as np

from mimics.algorithms.deployment import AHEAD, AHEAD_RANGE, MAX_TURN, REACH, SPEED, STOPPING


def team_step(team):
    """One row per robot: turn toward open space, drive when facing it with room ahead."""
    ranges, angles = team.scan.ranges, team.scan.angles  # (robots, beams)
    # NaN pads the rows of robots with fewer beams than others: they add nothing
    turn = np.arctan2(np.nansum(ranges * np.sin(angles), axis=1),
                      np.nansum(ranges * np.cos(angles), axis=1))
    length, cruise = _lengths(team), SPEED * team.max_speed
    ahead = np.minimum(np.maximum(AHEAD * length, STOPPING * cruise),
                       AHEAD_RANGE * team.scan.max_range)
    needed = REACH * length[:, None] + ahead[:, None] * np.maximum(np.cos(angles), 0.0)
    clear = np.all((ranges > needed) | np.isnan(angles), axis=1)
    speed = np.where((np.abs(turn) < MAX_TURN) & clear, cruise, 0.0)
    return speed, team.pose[:, 2] + turn


def _lengths(team):
    """Each robot's length ``(k,)``: ``team.length`` where the team view offers it."""
    if hasattr(type(team), "length"):
        return team.length
    return 2 * team._sim.types.half_length[team.ids]  # engines whose Team lacks .length
