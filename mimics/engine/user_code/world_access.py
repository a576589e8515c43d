"""What the user-code machinery reads of a simulation, as a protocol.

The controllers, the views and their hub take a :class:`SimulationParts` rather than
``mimics.engine.simulation.Simulation``, which calls them: the simulation is one such
thing (a structural match, checked by the type checker), and the user-code folder
needs nothing above it, so no import leads back from here to the step.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np

from mimics.engine.messages import MessageBus
from mimics.engine.state import TypeArrays, WorldState
from mimics.world.maps import Map
from mimics.world.scenario import Scenario


class SimulationParts(Protocol):
    """The parts of a running simulation that user code's machinery reads."""

    scenario: Scenario
    types: TypeArrays
    state: WorldState
    messages: MessageBus
    team_memory: dict[str, Any]
    world_map: Map  # the walls with the run's edits so far

    def user_rng(self, robot: int | None = None) -> np.random.Generator:
        """The algorithm's random stream of ``robot`` (None: the team's)."""
        ...

    def comms_table(self) -> np.ndarray:
        """Every robot's row of the communication table this step."""
        ...
