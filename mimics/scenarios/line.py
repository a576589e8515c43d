"""The paper's scalability line: N Pioneer3AT on the y-axis 1 m apart, goals 20 m ahead.

Paper section 4 (Figure 2): each robot drives straight to a goal 20 m ahead on
x; 21.8 simulated seconds is the paper's run length. The map has no walls.

Each robot's start heading is drawn at random from the run's seed, as in the
paper's Listing 1 (robots not facing their goal first turn, so with random
headings some arrive after 21.8 s); ``random_yaw = false`` (or ``fixed =
true``) starts every robot facing its goal.
"""

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_3AT
from mimics.world.scenario import Scenario, Settings
from mimics.world.streams import keyed_uniform

SEED_CHANGES = "each robot's start heading (unless random_yaw = false or fixed = true)"


def scenario(robots: int = 60, spacing: float = 1.0, distance: float = 20.0,
             x_offset: float = 0.0, random_yaw: bool = True, seed: int = 0,
             fixed: bool = False) -> Scenario:
    """``robots`` Pioneer3AT at ``(x_offset, spacing*i)``, goals ``distance`` m ahead.

    With ``random_yaw`` each starts with a random heading in [-pi, pi) (as the
    paper's Listing 1), robot i's drawn from ``(seed, i)`` alone (a run passes
    its own seed); otherwise, or when ``fixed``, facing its goal.
    """
    if robots < 1:
        raise ScenarioError(f"line: robots must be at least 1, got {robots}")
    i = np.arange(1, robots + 1, dtype=np.float64)
    yaw = (keyed_uniform(seed, "line.start_yaw", robots, -np.pi, np.pi)
           if random_yaw and not fixed else np.zeros(robots))
    rows = np.column_stack([np.full(robots, x_offset), spacing * i, yaw, np.zeros(robots),
                            np.full(robots, x_offset + distance), spacing * i])
    margin = 5.0
    bounds = (x_offset - margin, -margin, x_offset + distance + margin,
              spacing * robots + margin)
    return Scenario.from_matrix(rows, Map.empty(bounds, name="open field"), PIONEER_3AT,
                                settings=Settings(time_limit=21.8), name="line")
