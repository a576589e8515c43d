"""``deployment`` for a whole team at once, vectorised with NumPy.

Same logic and same results as the per-robot ``deployment``: every robot
turns toward the sum of its range readings as vectors, and drives only when
facing it with the beams ahead reading more than a safety distance.
"""

import numpy as np

from mimics.algorithms.deployment import AHEAD, AHEAD_RANGE, MAX_TURN, REACH, SPEED, STOPPING


def team_step(team):
    """One row per robot: turn toward open space, drive when facing it with room ahead."""
    ranges = team.scan.ranges  # (robots, beams)
    sin, cos, needed, unused, cruise = _team_constants(team)
    turn = np.arctan2(_row_sums(ranges * sin), _row_sums(ranges * cos))
    room = ranges > needed
    if unused is not None:
        room |= unused  # NaN pads of robots with fewer beams than others never block
    clear = np.logical_and.reduce(room, axis=1)  # np.all without its Python wrapper
    speed = np.where((np.abs(turn) < MAX_TURN) & clear, cruise, 0.0)
    return speed, team.pose[:, 2] + turn


def _row_sums(values):
    """Sum of each row, NaN (the pads of robots with fewer beams) counting as nothing."""
    sums = np.add.reduce(values, axis=1)  # np.sum without its Python wrapper (same numbers)
    # a NaN sum means a NaN in the row: only then pay for nansum (same numbers otherwise)
    return np.nansum(values, axis=1) if np.isnan(sums).any() else sums


def _team_constants(team):
    """What depends only on which robots are in the team, not on what they sense.

    Sine and cosine of the beam angles, the free space needed along each beam,
    the NaN pads (None if none) and each robot's cruising speed. They change
    only when the team does (a robot is deactivated), so they are kept in the
    team's memory: working them out is most of the cost of a step otherwise.
    """
    key = team.ids.tobytes()
    kept = team.memory.get("deployment_team.constants")
    if kept is None or kept[0] != key:
        angles = team.scan.angles
        unused = np.isnan(angles)
        cos = np.cos(angles)
        # free space needed along each beam: REACH all round, more and more toward the front
        length, cruise = team.length, SPEED * team.max_speed
        ahead = np.minimum(np.maximum(AHEAD * length, STOPPING * cruise),
                           AHEAD_RANGE * team.scan.max_range)
        needed = REACH * length[:, None] + ahead[:, None] * np.maximum(cos, 0.0)
        kept = (key, np.sin(angles), cos, needed, unused if unused.any() else None, cruise)
        team.memory["deployment_team.constants"] = kept
    return kept[1:]
