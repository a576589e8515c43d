"""Random placement of robots in free space: apart from each other and clear of walls.

Used by the TOML ``random`` generator (:mod:`mimics.world.scenario_files`), the
built-in scenarios that place robots at random and the workbench's scenario page.
"""

from __future__ import annotations

import math

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType
from mimics.world.start_state import Bodies, touching_walls


def random_placement(count: int, robot_type: RobotType, map: Map, rng: np.random.Generator,
                     region: tuple[float, float, float, float] | None = None,
                     min_spacing: float | None = None, clearance: float | None = None,
                     yaw: float | None = None, others: np.ndarray | None = None,
                     max_tries: int = 2000) -> np.ndarray:
    """``count`` random poses ``(count, 3)`` in free space, apart from each other and ``others``.

    Args:
        count: robots to place.
        robot_type: their type (its size decides what touches).
        map: the walls to keep clear of.
        rng: the seeded generator to draw from.
        region: ``(xmin, ymin, xmax, ymax)`` to draw centres in (default the map
            bounds, less the robot's reach).
        min_spacing: least centre-to-centre distance (default 1.5 robot diagonals).
        clearance: least gap between a robot and a wall (default half the robot's width).
        yaw: everyone's heading, or None for random headings.
        others: ``(k, 2)`` centres already taken (kept ``min_spacing`` away).
        max_tries: draws per robot before giving up.

    Raises:
        ScenarioError: a robot could not be placed.
    """
    half = np.array([robot_type.length / 2]), np.array([robot_type.width / 2])
    diagonal = 2 * math.hypot(robot_type.length / 2, robot_type.width / 2)
    spacing = 1.5 * diagonal if min_spacing is None else min_spacing
    gap = robot_type.width / 2 if clearance is None else clearance
    if region is None:  # keep the whole robot inside the bounds
        inset = diagonal / 2 + gap
        xmin, ymin, xmax, ymax = map.bounds
        region = (xmin + inset, ymin + inset, xmax - inset, ymax - inset)
    x0, y0, x1, y1 = region
    taken = np.zeros((0, 2)) if others is None else np.asarray(others, dtype=float).reshape(-1, 2)
    poses = np.zeros((count, 3))
    batch = 64
    for k in range(count):
        for _ in range(0, max_tries, batch):
            xy = rng.uniform((x0, y0), (x1, y1), size=(batch, 2))
            headings = (np.full(batch, float(yaw)) if yaw is not None
                        else rng.uniform(-np.pi, np.pi, batch))
            ok = np.ones(batch, dtype=bool)
            if len(taken):
                dist = np.hypot(*(xy[:, None, :] - taken[None, :, :]).transpose(2, 0, 1))
                ok &= (dist >= spacing).all(axis=1)
            bodies = Bodies(xy, headings, np.repeat(half[0], batch), np.repeat(half[1], batch))
            touching, _ = touching_walls(bodies, map.segments, grow=gap)
            ok[touching] = False
            if ok.any():
                pick = int(np.flatnonzero(ok)[0])
                poses[k] = (*xy[pick], headings[pick])
                taken = np.vstack([taken, xy[pick]])
                break
        else:
            raise ScenarioError(f"cannot place robot {k + 1} of {count} ({robot_type.name}) after "
                                f"{max_tries} tries in region ({x0:g}, {y0:g}, {x1:g}, {y1:g}) "
                                f"with min_spacing {spacing:g} m and clearance {gap:g} m "
                                "(expected fewer robots, a larger region or smaller spacings)")
    return poses
