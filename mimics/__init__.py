"""mimics: a fast multi-robot simulator for teaching, prototyping and Monte Carlo batteries.

>>> import mimics
>>> run = mimics.simulate("line", "go_to_goal", robots=2, seed=1,
...                       params={"random_yaw": False})  # both facing their goals
>>> run.reached_goal
2
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

# Public names, imported on first use so that `import mimics` stays fast.
_EXPORTS = {
    "simulate": "mimics.interfaces.api",
    "Simulation": "mimics.engine.simulation",
    "RunResult": "mimics.engine.outcome",
    "Scenario": "mimics.world.scenario",
    "Settings": "mimics.world.scenario",
    "Map": "mimics.world.maps",
    "RobotType": "mimics.world.robot_types",
    "RangerSpec": "mimics.world.robot_types",
    "PidGains": "mimics.world.robot_types",
    "MimicsError": "mimics.world.errors",
    "UserCodeError": "mimics.interfaces.user_errors",
    "load_scenario": "mimics.catalog",
    "find_algorithm": "mimics.catalog",
    "list_algorithms": "mimics.catalog",
    "list_scenarios": "mimics.catalog",
    "load_run": "mimics.interfaces.api",
    "run_battery": "mimics.interfaces.api",
    "load_battery": "mimics.interfaces.api",
    "show": "mimics.interfaces.api",
    "RunView": "mimics.interfaces.notebook.run",
    "BatteryView": "mimics.interfaces.notebook.battery",
}

__all__ = [*_EXPORTS, "__version__"]


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    if name == "env":  # learning environments; PettingZoo/Gymnasium load on first use
        return importlib.import_module("mimics.env")
    raise AttributeError(f"module 'mimics' has no attribute {name!r}")
