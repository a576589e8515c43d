"""The paper's scalability line: N Pioneer3AT on the y-axis 1 m apart, goals 20 m ahead.

Paper section 4 (Figure 2): each robot drives straight to a goal 20 m ahead on
x; 21.8 simulated seconds are enough for all to arrive. The map has no walls.
"""

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_3AT
from mimics.world.scenario import Scenario, Settings


def scenario(robots: int = 60, spacing: float = 1.0, distance: float = 20.0,
             x_offset: float = 0.0, random_yaw: bool = False, seed: int = 5) -> Scenario:
    """``robots`` Pioneer3AT at ``(x_offset, spacing*i)``, goals ``distance`` m ahead.

    With ``random_yaw`` each starts with a random heading (as the paper's
    Listing 1, seeded by ``seed``), otherwise facing its goal.
    """
    if robots < 1:
        raise ScenarioError(f"line: robots must be at least 1, got {robots}")
    rng = np.random.default_rng(seed)
    i = np.arange(1, robots + 1, dtype=np.float64)
    yaw = rng.uniform(-np.pi, np.pi, robots) if random_yaw else np.zeros(robots)
    rows = np.column_stack([np.full(robots, x_offset), spacing * i, yaw, np.zeros(robots),
                            np.full(robots, x_offset + distance), spacing * i])
    margin = 5.0
    bounds = (x_offset - margin, -margin, x_offset + distance + margin,
              spacing * robots + margin)
    return Scenario.from_matrix(rows, Map.empty(bounds, name="open field"), PIONEER_3AT,
                                settings=Settings(time_limit=21.8), name="line")
