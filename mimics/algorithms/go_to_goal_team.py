"""``go_to_goal`` for a whole team at once, vectorised with NumPy.

Same logic, same results as the per-robot ``go_to_goal``; one call per step
instead of one per robot.
"""

import numpy as np


def team_step(team):
    """Head every robot for its goal; robots without a goal stop."""
    x, y, theta = team.pose[:, 0], team.pose[:, 1], team.pose[:, 2]
    gx, gy = team.goal[:, 0], team.goal[:, 1]
    has_goal = ~np.isnan(gx)
    heading = np.where(has_goal, np.arctan2(gy - y, gx - x), theta)
    alignment = np.maximum(np.cos(heading - theta), 0.0)
    speed = np.where(has_goal, team.max_speed * alignment, 0.0)
    return speed, heading
