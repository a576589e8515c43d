"""Start-pose jitter drawn from the run's seed: what varies between repetitions of a layout.

Robot ``i``'s offsets (x, y, heading) are keyed draws of ``(seed, purpose, i)``
(:func:`mimics.world.streams.keyed_uniform`): adding robots leaves the
others' offsets as they were. A jittered robot that would start touching a
wall or another robot, or outside the bounds, keeps its nominal pose instead (and so does the other
robot of a touching pair), so jitter never makes a valid layout invalid.

>>> from mimics.world.maps import Map
>>> from mimics.world.robot_types import PIONEER_2DX
>>> s = Scenario.from_matrix([[0.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 0.0]],
...                          Map.empty((-5, -5, 5, 5)), PIONEER_2DX)
>>> moved = jitter_start(s, 3, "example", position=0.1, heading=0.2)
>>> bool(abs(moved.stages[:, :2] - s.stages[:, :2]).max() <= 0.1)
True
>>> bool((jitter_start(s, 3, "example", 0.1, 0.2).stages == moved.stages).all())
True
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mimics.world.scenario import Scenario
from mimics.world.start_state import Bodies, overlapping_robots, touching_walls
from mimics.world.streams import keyed_uniform

MAX_PASSES = 8  # reverting robots to their nominal poses settles in one or two passes


def jitter_start(scenario: Scenario, seed: int, purpose: str, position: float = 0.0,
                 heading: float = 0.0) -> Scenario:
    """``scenario`` with each start moved by up to ``position`` m along x and y and turned by
    up to ``heading`` rad (uniform draws keyed ``(seed, purpose, robot)``); goals stay."""
    n = scenario.robot_count
    if position <= 0 and heading <= 0:
        return scenario
    nominal = scenario.stages
    stages = nominal.copy()
    stages[:, 0] += keyed_uniform(seed, f"{purpose}.x", n, -position, position)
    stages[:, 1] += keyed_uniform(seed, f"{purpose}.y", n, -position, position)
    stages[:, 2] += keyed_uniform(seed, f"{purpose}.heading", n, -heading, heading)
    kept = np.zeros(n, dtype=bool)
    for _ in range(MAX_PASSES):
        candidate = replace(scenario, stages=stages)
        bodies = Bodies.of(candidate)
        robots, _ = touching_walls(bodies, scenario.map.segments)
        first, second = overlapping_robots(bodies)
        xmin, ymin, xmax, ymax = scenario.map.bounds
        x, y = stages[:, 0], stages[:, 1]
        # the robots to revert, in order (a mask: np.unique would import numpy.ma, 5 ms)
        flagged = (x < xmin) | (x > xmax) | (y < ymin) | (y > ymax)
        flagged[np.concatenate([robots, first, second])] = True
        bad = np.flatnonzero(flagged & ~kept)
        if bad.size == 0:
            return candidate
        stages[bad] = nominal[bad]
        kept[bad] = True
    return replace(scenario, stages=stages)
