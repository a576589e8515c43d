"""The examples gallery: each example's run, and its figure made from a real run.

``python examples/gallery.py`` runs every example and redraws
``examples/<name>/figure.png`` with mimics' own plotting; ``python
examples/gallery.py NAME ...`` only those. The tests (``tests/examples/``)
run the same table with shorter times where they can.
"""

from __future__ import annotations

import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent


@dataclass(frozen=True)
class Example:
    """One example: its scenario (a built-in name or a file in its folder) and run settings."""

    scenario: str
    time: float
    params: dict[str, Any] = field(default_factory=dict)
    seed: int = 1

    def scenario_ref(self, name: str) -> str:
        local = HERE / name / self.scenario
        return str(local) if local.suffix in (".toml", ".py") else self.scenario


EXAMPLES: dict[str, Example] = {
    "go_to_goal": Example("line", 40.0, {"robots": 10}),
    "deployment": Example("scenario.toml", 90.0),
    "wall_following": Example("obstacle_room", 120.0, {"robots": 1}),
    "frontier_exploration": Example("../deployment/scenario.toml", 240.0, {"robots": 1}),
    "reciprocal_avoidance": Example("circle_swap", 120.0, {"robots": 12, "radius": 5.0}),
    "rendezvous": Example("scenario.toml", 90.0),
    "leader_follower": Example("scenario.toml", 120.0),
}


def algorithm_path(name: str) -> Path:
    """The example's algorithm file."""
    return HERE / name / "algorithm.py"


def simulate(name: str, out: str | Path | None = None, *, time: float | None = None,
             params: dict[str, Any] | None = None) -> Any:
    """Run example ``name`` (with ``out``, also write its run folder); the finished Simulation.

    ``time`` and ``params`` override the example's own.
    """
    from mimics.records.runner import prepare, run_to_folder

    example = EXAMPLES[name]
    sim = prepare(example.scenario_ref(name), str(algorithm_path(name)), seed=example.seed,
                  time=time or example.time, params={**example.params, **(params or {})})
    if out is None:
        sim.run()
    else:
        run_to_folder(sim, out, robot_logs="off")
    return sim


def make_figure(name: str) -> Path:
    """Run example ``name`` in full and draw its trajectories into its folder."""
    from mimics.interfaces.plots import plot_run

    with tempfile.TemporaryDirectory() as folder:
        simulate(name, folder)
        return plot_run(folder, HERE / name / "figure.png", width_px=800, height_px=600)


if __name__ == "__main__":
    for example_name in sys.argv[1:] or list(EXAMPLES):
        print(make_figure(example_name))
